/* Drives a hairsys session from C and writes what it computed, for tests/c_programs.rs to
 * compare with the Rust Session bit for bit.
 *
 *   session groom SCENARIO OUTPUT THREADS   the scenario's groom through every frame; checks
 *                                           that a restored snapshot steps to the same bits
 *   session scene FRAMES OUTPUT             the built-in default scene, FRAMES steps
 *
 * OUTPUT holds every frame's positions, then the last frame's velocities (float32). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hairsys.h"
#include "scenario.h"

#define CHECK(call)                                                                   \
  do {                                                                                \
    HairsysStatus status_ = (call);                                                   \
    if (status_ != HAIRSYS_STATUS_OK) {                                               \
      fprintf(stderr, "%s:%d: %s -> %d: %s\n", __FILE__, __LINE__, #call, (int)status_, \
              hairsys_last_error_message());                                          \
      exit(1);                                                                        \
    }                                                                                 \
  } while (0)

static void drive_frame(HairsysSession *s, const Frame *f, uint32_t vertex_count) {
  if (f->kind == 0) {
    CHECK(hairsys_session_set_scalp_transform(s, &f->scalp));
  } else {
    CHECK(hairsys_session_set_scalp_vertices(s, f->vertices, vertex_count, &f->scalp));
  }
  CHECK(hairsys_session_set_collider_pose(s, 0, &f->collider));
  HairsysFrameReport report;
  CHECK(hairsys_session_step(s, &report));
}

static int groom(const char *input, const char *output, uint32_t threads) {
  Scenario sc = read_scenario(input);
  HairsysGroomArrays arrays;
  memset(&arrays, 0, sizeof arrays);
  arrays.scalp_vertices = sc.vertices;
  arrays.scalp_vertex_count = sc.vertex_count;
  arrays.scalp_triangles = sc.triangles;
  arrays.scalp_triangle_count = sc.triangle_count;
  arrays.curve_points = sc.points;
  arrays.curve_point_count = sc.point_count;
  arrays.curve_counts = sc.counts;
  arrays.curve_count = sc.curve_count;

  HairsysCollider sphere;
  memset(&sphere, 0, sizeof sphere);
  sphere.shape = HAIRSYS_SHAPE_SPHERE;
  sphere.radius = sc.collider_radius;
  sphere.pose = sc.collider_pose;

  HairsysGroomOptions options;
  CHECK(hairsys_groom_options_default(&options));
  options.colliders = &sphere;
  options.collider_count = 1;
  options.collider_speed = 1.0;
  options.threads = threads;

  HairsysSession *s = NULL;
  CHECK(hairsys_session_from_groom(&arrays, &options, &s));
  HairsysSessionInfo info;
  CHECK(hairsys_session_info(s, &info));
  size_t floats = 3 * info.point_count;
  float *all = (float *)malloc(sc.frame_count * floats * sizeof(float) + 1);
  uint32_t half = sc.frame_count / 2;
  HairsysSnapshot *snap = NULL;
  for (uint32_t i = 0; i < sc.frame_count; i++) {
    drive_frame(s, &sc.frames[i], sc.vertex_count);
    HairsysPointsView p;
    CHECK(hairsys_session_positions(s, &p));
    if (p.count != info.point_count) return 1;
    memcpy(all + i * floats, p.xyz, floats * sizeof(float));
    if (i + 1 == half) CHECK(hairsys_session_snapshot(s, &snap));
  }
  HairsysPointsView v;
  CHECK(hairsys_session_velocities(s, &v));
  FILE *out = fopen(output, "wb");
  if (!out) return 2;
  fwrite(all, sizeof(float), sc.frame_count * floats, out);
  fwrite(v.xyz, sizeof(float), floats, out);
  fclose(out);

  /* Scrubbing back: the frames after the snapshot again, to the same bits. */
  CHECK(hairsys_session_restore(s, snap));
  for (uint32_t i = half; i < sc.frame_count; i++) {
    drive_frame(s, &sc.frames[i], sc.vertex_count);
    HairsysPointsView p;
    CHECK(hairsys_session_positions(s, &p));
    if (memcmp(p.xyz, all + i * floats, floats * sizeof(float)) != 0) {
      fprintf(stderr, "frame %u after restore differs from the first pass\n", i);
      return 1;
    }
  }
  hairsys_snapshot_destroy(snap);
  hairsys_session_destroy(s);
  free(all);
  free_scenario(&sc);
  return 0;
}

static int scene(uint32_t frames, const char *output) {
  HairsysSession *s = NULL;
  CHECK(hairsys_session_from_scene(NULL, 0, &s));
  FILE *out = fopen(output, "wb");
  if (!out) return 2;
  HairsysPointsView p;
  for (uint32_t i = 0; i < frames; i++) {
    CHECK(hairsys_session_step(s, NULL));
    CHECK(hairsys_session_positions(s, &p));
    fwrite(p.xyz, sizeof(float), 3 * p.count, out);
  }
  CHECK(hairsys_session_velocities(s, &p));
  fwrite(p.xyz, sizeof(float), 3 * p.count, out);
  fclose(out);
  hairsys_session_destroy(s);
  return 0;
}

int main(int argc, char **argv) {
  uint32_t v = hairsys_abi_version();
  if ((v >> 16) != HAIRSYS_ABI_VERSION_MAJOR ||
      (int64_t)(v & 0xffffu) < (int64_t)HAIRSYS_ABI_VERSION_MINOR) {
    fprintf(stderr, "library ABI %u.%u, header %u.%u\n", v >> 16, v & 0xffffu,
            HAIRSYS_ABI_VERSION_MAJOR, HAIRSYS_ABI_VERSION_MINOR);
    return 3;
  }
  if (argc == 5 && strcmp(argv[1], "groom") == 0) {
    return groom(argv[2], argv[3], (uint32_t)atoi(argv[4]));
  }
  if (argc == 4 && strcmp(argv[1], "scene") == 0) {
    return scene((uint32_t)atoi(argv[2]), argv[3]);
  }
  fprintf(stderr, "usage: session groom SCENARIO OUTPUT THREADS | session scene FRAMES OUTPUT\n");
  return 2;
}
