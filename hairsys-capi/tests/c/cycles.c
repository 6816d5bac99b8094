/* Create, step, record, read back and destroy sessions over and over, with failures in
 * between, for valgrind: every handle and buffer the library hands out is released by its
 * _destroy, and nothing reads or writes out of bounds.
 *
 *   cycles DIR   (a writable directory for the caches) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hairsys.h"

#define CHECK(call)                                                                    \
  do {                                                                                 \
    HairsysStatus status_ = (call);                                                    \
    if (status_ != HAIRSYS_STATUS_OK) {                                                \
      fprintf(stderr, "%s:%d: %s -> %d: %s\n", __FILE__, __LINE__, #call, (int)status_, \
              hairsys_last_error_message());                                           \
      return 1;                                                                        \
    }                                                                                  \
  } while (0)

int main(int argc, char **argv) {
  if (argc != 2) return 2;
  float vertices[4 * 3] = {0, 0, 0, 0.1f, 0, 0, 0.1f, 0.1f, 0, 0, 0.1f, 0};
  uint32_t triangles[2 * 3] = {0, 1, 2, 0, 2, 3};
  uint32_t counts[3] = {5, 5, 5};
  float points[15 * 3];
  for (int c = 0; c < 3; c++)
    for (int k = 0; k < 5; k++) {
      float *p = &points[3 * (5 * c + k)];
      p[0] = 0.02f + 0.03f * (float)c;
      p[1] = 0.05f;
      p[2] = 0.0005f + 0.01f * (float)k;
    }
  HairsysGroomArrays a;
  memset(&a, 0, sizeof a);
  a.scalp_vertices = vertices;
  a.scalp_vertex_count = 4;
  a.scalp_triangles = triangles;
  a.scalp_triangle_count = 2;
  a.curve_points = points;
  a.curve_point_count = 15;
  a.curve_counts = counts;
  a.curve_count = 3;
  char cache_path[4096];
  snprintf(cache_path, sizeof cache_path, "%s/cycles.mcap", argv[1]);

  for (int cycle = 0; cycle < 3; cycle++) {
    HairsysGroomOptions o;
    CHECK(hairsys_groom_options_default(&o));
    o.threads = (uint32_t)(cycle % 2 + 1);
    HairsysSession *s = NULL;
    CHECK(hairsys_session_from_groom(&a, &o, &s));
    CHECK(hairsys_session_record(s, cache_path, HAIRSYS_COMPRESSION_LZ4, 0));
    HairsysSnapshot *snap = NULL;
    for (int f = 0; f < 4; f++) {
      float moved[12];
      memcpy(moved, vertices, sizeof moved);
      for (int v = 0; v < 4; v++) moved[3 * v + 2] = 0.002f * (float)(f * v);
      CHECK(hairsys_session_set_scalp_vertices(s, moved, 4, NULL));
      CHECK(hairsys_session_step(s, NULL));
      if (f == 1) CHECK(hairsys_session_snapshot(s, &snap));
    }
    /* Failures leave messages behind; they must not leak either. */
    if (hairsys_session_set_scalp_vertices(s, vertices, 3, NULL) != HAIRSYS_STATUS_BAD_LENGTH)
      return 1;
    if (hairsys_session_restore(s, snap) != HAIRSYS_STATUS_BAD_ARGUMENT) return 1;
    CHECK(hairsys_session_finish_recording(s, NULL));
    CHECK(hairsys_session_restore(s, snap));
    HairsysChildSettings cs;
    CHECK(hairsys_child_settings_default(&cs));
    HairsysChildren *kids = NULL;
    CHECK(hairsys_session_children(s, &cs, &kids));
    HairsysChildrenView kv;
    CHECK(hairsys_children_view(kids, &kv));
    double sum = 0;
    for (size_t i = 0; i < 3 * kv.point_count; i++) sum += kv.points[i];
    if (!isfinite(sum)) return 1;
    HairsysCache *cache = NULL;
    CHECK(hairsys_cache_open(cache_path, &cache));
    HairsysCacheInfo ci;
    CHECK(hairsys_cache_info(cache, &ci));
    float *xyz = (float *)malloc(3 * ci.point_count * sizeof(float));
    CHECK(hairsys_cache_read_frame(cache, ci.last_frame, xyz, NULL, ci.point_count));
    free(xyz);
    hairsys_cache_destroy(cache);
    hairsys_children_destroy(kids);
    hairsys_snapshot_destroy(snap);
    hairsys_session_destroy(s);
  }
  printf("3 cycles\n");
  return 0;
}
