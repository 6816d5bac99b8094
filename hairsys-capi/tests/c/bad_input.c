/* Every function of hairsys.h given bad input: NULL pointers, misaligned pointers, wrong
 * lengths, NaN, out-of-range values, files that are not there. Each call must return the
 * status the header documents and leave a message naming the argument; nothing may crash.
 *
 *   bad_input DIR   (a writable directory for the caches it records)
 *
 * Prints "N passed, M failed" and exits non-zero when any check failed. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hairsys.h"

static int passed = 0, failed = 0;

/* `call` returns `code`, and the thread's last error agrees (a message that mentions `word`
 * unless the call succeeded). */
#define EXPECT(call, code, word) expect((call), (code), (word), #call, __LINE__)

static void expect(HairsysStatus got, HairsysStatus want, const char *word, const char *what,
                   int line) {
  const char *message = hairsys_last_error_message();
  int ok = got == want && hairsys_last_error_code() == got && message != NULL;
  if (ok && want != HAIRSYS_STATUS_OK) ok = strstr(message, word) != NULL;
  if (ok && want == HAIRSYS_STATUS_OK) ok = message[0] == '\0';
  if (ok) {
    passed++;
  } else {
    failed++;
    fprintf(stderr, "line %d: %s returned %d (wanted %d): \"%s\" (wanted a mention of \"%s\")\n",
            line, what, (int)got, (int)want, message ? message : "(null)", word);
  }
}

/* A 3x3-vertex grid scalp at z = 0 (0.1 m square) with two 4-point curves. */
static float vertices[9 * 3];
static uint32_t triangles[8 * 3];
static float points[8 * 3];
static uint32_t counts[2] = {4, 4};

static void make_groom(void) {
  for (int j = 0; j < 3; j++)
    for (int i = 0; i < 3; i++) {
      float *v = &vertices[3 * (3 * j + i)];
      v[0] = 0.05f * (float)i;
      v[1] = 0.05f * (float)j;
      v[2] = 0.0f;
    }
  int t = 0;
  for (int j = 0; j < 2; j++)
    for (int i = 0; i < 2; i++) {
      uint32_t a = (uint32_t)(3 * j + i), b = a + 1, c = a + 3, d = a + 4;
      uint32_t tri[6] = {a, b, d, a, d, c};
      memcpy(&triangles[3 * t], tri, sizeof tri);
      t += 2;
    }
  for (int c = 0; c < 2; c++)
    for (int k = 0; k < 4; k++) {
      float *p = &points[3 * (4 * c + k)];
      p[0] = 0.03f + 0.04f * (float)c;
      p[1] = 0.05f;
      p[2] = 0.02f * (float)k;
    }
}

static HairsysGroomArrays groom_arrays(void) {
  HairsysGroomArrays a;
  memset(&a, 0, sizeof a);
  a.scalp_vertices = vertices;
  a.scalp_vertex_count = 9;
  a.scalp_triangles = triangles;
  a.scalp_triangle_count = 8;
  a.curve_points = points;
  a.curve_point_count = 8;
  a.curve_counts = counts;
  a.curve_count = 2;
  return a;
}

int main(int argc, char **argv) {
  if (argc != 2) {
    fprintf(stderr, "usage: bad_input DIR\n");
    return 2;
  }
  make_groom();
  const HairsysStatus OK = HAIRSYS_STATUS_OK, NUL = HAIRSYS_STATUS_NULL_POINTER,
                      MIS = HAIRSYS_STATUS_MISALIGNED, LEN = HAIRSYS_STATUS_BAD_LENGTH,
                      NAN_ = HAIRSYS_STATUS_NOT_FINITE, ARG = HAIRSYS_STATUS_BAD_ARGUMENT;
  const HairsysTransform id = {{0, 0, 0}, {0, 0, 0, 1}};
  const HairsysTransform nan_t = {{0, NAN, 0}, {0, 0, 0, 1}};
  const HairsysTransform long_q = {{0, 0, 0}, {0, 0, 0, 2}};
  /* A buffer whose second byte is a misaligned pointer to floats. */
  static float spare[64];
  const float *mis_f = (const float *)((const char *)spare + 1);

  /* Options and creation. */
  HairsysGroomOptions o;
  EXPECT(hairsys_groom_options_default(NULL), NUL, "out");
  EXPECT(hairsys_groom_options_default((HairsysGroomOptions *)((char *)&o + 1)), MIS, "out");
  EXPECT(hairsys_groom_options_default(&o), OK, "");
  HairsysGroomArrays a = groom_arrays();
  HairsysSession *s = NULL;
  EXPECT(hairsys_session_from_groom(NULL, &o, &s), NUL, "arrays");
  EXPECT(hairsys_session_from_groom(&a, NULL, &s), NUL, "options");
  EXPECT(hairsys_session_from_groom(&a, &o, NULL), NUL, "out");
  a.scalp_vertices = NULL;
  EXPECT(hairsys_session_from_groom(&a, &o, &s), NUL, "scalp_vertices");
  a = groom_arrays();
  a.curve_points = mis_f;
  EXPECT(hairsys_session_from_groom(&a, &o, &s), MIS, "curve_points");
  a = groom_arrays();
  a.scalp_vertex_count = (size_t)1 << 62;
  EXPECT(hairsys_session_from_groom(&a, &o, &s), LEN, "scalp_vertices");
  a = groom_arrays();
  const float kept = points[5];
  points[5] = NAN;
  EXPECT(hairsys_session_from_groom(&a, &o, &s), NAN_, "curve_points");
  points[5] = kept;
  a.curve_count = 1;
  EXPECT(hairsys_session_from_groom(&a, &o, &s), ARG, "curve_counts");
  a = groom_arrays();
  float weights[8] = {0, 0, 0, 0, 0, 0, 0, INFINITY};
  a.goal_weights = weights;
  EXPECT(hairsys_session_from_groom(&a, &o, &s), NAN_, "goal_weights");
  a = groom_arrays();
  uint8_t pins[8] = {1, 0, 0, 2, 1, 0, 0, 0};
  a.pinned = pins;
  EXPECT(hairsys_session_from_groom(&a, &o, &s), ARG, "pinned");
  a = groom_arrays();
  HairsysStrandScales scales[2] = {{1, 1, 1, 1, 1}, {1, NAN, 1, 1, 1}};
  a.strand_scales = scales;
  EXPECT(hairsys_session_from_groom(&a, &o, &s), NAN_, "strand_scales");
  a = groom_arrays();
  o.fps = NAN;
  EXPECT(hairsys_session_from_groom(&a, &o, &s), NAN_, "fps");
  hairsys_groom_options_default(&o);
  o.sag_free = 5;
  EXPECT(hairsys_session_from_groom(&a, &o, &s), ARG, "sag_free");
  hairsys_groom_options_default(&o);
  o.integrator = "leapfrog";
  EXPECT(hairsys_session_from_groom(&a, &o, &s), ARG, "integrator");
  hairsys_groom_options_default(&o);
  o.integrator = "\xff\xfe";
  EXPECT(hairsys_session_from_groom(&a, &o, &s), ARG, "UTF-8");
  hairsys_groom_options_default(&o);
  HairsysCollider col;
  memset(&col, 0, sizeof col);
  col.shape = 9;
  col.radius = 0.02f;
  col.pose = id;
  o.colliders = &col;
  o.collider_count = 1;
  EXPECT(hairsys_session_from_groom(&a, &o, &s), ARG, "colliders[0].shape");
  col.shape = HAIRSYS_SHAPE_SPHERE;
  col.pose = long_q;
  EXPECT(hairsys_session_from_groom(&a, &o, &s), ARG, "unit quaternion");
  col.pose = id;
  col.pose.translation[2] = 1.0f;
  o.collider_count = 0;
  o.colliders = NULL;
  o.collider_count = 1;
  EXPECT(hairsys_session_from_groom(&a, &o, &s), NUL, "colliders");
  o.colliders = &col;
  o.goal_tip = 3.0f;
  EXPECT(hairsys_session_from_groom(&a, &o, &s), ARG, "goal_tip");
  o.goal_tip = 0.0f;
  o.sim_hairs = 4000000000u;
  EXPECT(hairsys_session_from_groom(&a, &o, &s), ARG, "sim_hairs");
  o.sim_hairs = 0;
  if (s != NULL) {
    fprintf(stderr, "a refused create wrote its out-parameter\n");
    failed++;
  }
  o.collider_speed = 0.5;
  EXPECT(hairsys_session_from_groom(&a, &o, &s), OK, "");
  if (s == NULL) {
    fprintf(stderr, "no session: cannot go on\n");
    return 1;
  }

  HairsysSession *scene = NULL;
  EXPECT(hairsys_session_from_scene("/nonexistent/scene.toml", 0, &scene), HAIRSYS_STATUS_SCENE,
         "scene.toml");
  EXPECT(hairsys_session_from_scene("\xff.toml", 0, &scene), ARG, "UTF-8");
  EXPECT(hairsys_session_from_scene(NULL, 0, NULL), NUL, "out");
  EXPECT(hairsys_session_from_scene(NULL, HAIRSYS_MAX_THREADS + 1, &scene), ARG, "threads");
  o.threads = 5000;
  EXPECT(hairsys_session_from_groom(&a, &o, &scene), ARG, "HAIRSYS_MAX_THREADS");
  o.threads = 0;

  /* Per-frame setters. */
  HairsysSessionInfo info;
  EXPECT(hairsys_session_info(NULL, &info), NUL, "session");
  EXPECT(hairsys_session_info(s, NULL), NUL, "out");
  EXPECT(hairsys_session_info((const HairsysSession *)((const char *)s + 1), &info), MIS,
         "session");
  EXPECT(hairsys_session_info(s, &info), OK, "");
  EXPECT(hairsys_session_set_scalp_transform(NULL, &id), NUL, "session");
  EXPECT(hairsys_session_set_scalp_transform(s, NULL), NUL, "transform");
  EXPECT(hairsys_session_set_scalp_transform(s, &nan_t), NAN_, "transform");
  EXPECT(hairsys_session_set_scalp_transform(s, &long_q), ARG, "unit quaternion");
  EXPECT(hairsys_session_set_scalp_vertices(s, NULL, 9, NULL), NUL, "vertices");
  EXPECT(hairsys_session_set_scalp_vertices(s, NULL, 0, NULL), NUL, "vertices");
  EXPECT(hairsys_session_set_scalp_vertices(s, vertices, 8, NULL), LEN, "9 vertices");
  EXPECT(hairsys_session_set_scalp_vertices(s, mis_f, 9, NULL), MIS, "vertices");
  float moved[27];
  memcpy(moved, vertices, sizeof moved);
  moved[13] = NAN;
  EXPECT(hairsys_session_set_scalp_vertices(s, moved, 9, NULL), NAN_, "float 13");
  moved[13] = 0.0f;
  EXPECT(hairsys_session_set_scalp_vertices(s, moved, 9, &long_q), ARG, "body");
  EXPECT(hairsys_session_set_collider_pose(s, 5, &id), ARG, "collider 5");
  EXPECT(hairsys_session_set_collider_pose(s, 0, NULL), NUL, "pose");
  EXPECT(hairsys_session_set_collider_pose(s, 0, &nan_t), NAN_, "pose");
  EXPECT(hairsys_session_set_collider_vertices(s, 0, vertices, 9), ARG, "collider 0");
  EXPECT(hairsys_session_set_collider_vertices(s, 0, NULL, 3), NUL, "vertices");
  moved[4] = NAN;
  EXPECT(hairsys_session_set_collider_vertices(s, 0, moved, 9), NAN_, "vertices");
  /* A mesh collider: its vertices are checked against its own count. */
  {
    HairsysGroomOptions mo;
    hairsys_groom_options_default(&mo);
    HairsysCollider mesh;
    memset(&mesh, 0, sizeof mesh);
    mesh.shape = HAIRSYS_SHAPE_MESH;
    mesh.vertices = vertices;
    mesh.vertex_count = 9;
    mesh.triangles = triangles;
    mesh.triangle_count = 8;
    mesh.pose = id;
    mesh.pose.translation[2] = 0.5f;
    mo.colliders = &mesh;
    mo.collider_count = 1;
    mo.collider_speed = 0.0;
    HairsysSession *m = NULL;
    mesh.triangles = NULL;
    EXPECT(hairsys_session_from_groom(&a, &mo, &m), NUL, "colliders[].triangles");
    mesh.triangles = (const uint32_t *)((const char *)triangles + 2);
    EXPECT(hairsys_session_from_groom(&a, &mo, &m), MIS, "colliders[].triangles");
    mesh.triangles = triangles;
    EXPECT(hairsys_session_from_groom(&a, &mo, &m), OK, "");
    float lifted[27];
    memcpy(lifted, vertices, sizeof lifted);
    lifted[2] = 0.01f;
    EXPECT(hairsys_session_set_collider_vertices(m, 0, lifted, 8), LEN, "9 vertices");
    EXPECT(hairsys_session_set_collider_vertices(m, 0, lifted, 9), OK, "");
    EXPECT(hairsys_session_step(m, NULL), OK, "");
    hairsys_session_destroy(m);
  }

  HairsysParams params;
  EXPECT(hairsys_session_params(s, NULL), NUL, "out");
  EXPECT(hairsys_session_params(s, &params), OK, "");
  HairsysParams bad = params;
  bad.air_drag = NAN;
  EXPECT(hairsys_session_set_params(s, &bad), NAN_, "params");
  EXPECT(hairsys_session_set_params(s, NULL), NUL, "params");
  EXPECT(hairsys_session_set_params(s, &params), OK, "");

  /* Stepping and views. */
  HairsysFrameReport report;
  EXPECT(hairsys_session_step(NULL, &report), NUL, "session");
  EXPECT(hairsys_session_step(s, (HairsysFrameReport *)((char *)&report + 2)), MIS, "report");
  EXPECT(hairsys_session_step(s, &report), OK, "");
  HairsysPointsView view;
  HairsysIndexView offsets;
  EXPECT(hairsys_session_positions(s, NULL), NUL, "out");
  EXPECT(hairsys_session_velocities(NULL, &view), NUL, "session");
  EXPECT(hairsys_session_strand_offsets(s, NULL), NUL, "out");
  EXPECT(hairsys_session_strand_offsets(s, &offsets), OK, "");

  /* Snapshots. */
  HairsysSnapshot *snap = NULL;
  uint32_t frame = 0;
  EXPECT(hairsys_session_snapshot(s, NULL), NUL, "out");
  EXPECT(hairsys_session_snapshot(s, &snap), OK, "");
  EXPECT(hairsys_session_restore(s, NULL), NUL, "snapshot");
  EXPECT(hairsys_snapshot_frame(NULL, &frame), NUL, "snapshot");
  EXPECT(hairsys_snapshot_frame(snap, NULL), NUL, "out");
  EXPECT(hairsys_snapshot_frame(snap, &frame), OK, "");

  /* Recording and reading caches. */
  char cache_path[4096], usd_path[4096], bad_path[4096];
  snprintf(cache_path, sizeof cache_path, "%s/bad_input.mcap", argv[1]);
  snprintf(usd_path, sizeof usd_path, "%s/bad_input.usda", argv[1]);
  snprintf(bad_path, sizeof bad_path, "%s/no/such/dir/x.mcap", argv[1]);
  EXPECT(hairsys_session_finish_recording(s, NULL), ARG, "not recording");
  EXPECT(hairsys_session_record(s, NULL, 0, 0), NUL, "path");
  EXPECT(hairsys_session_record(s, cache_path, 7, 0), ARG, "compression");
  EXPECT(hairsys_session_record(s, cache_path, 0, 3), ARG, "quantize");
  EXPECT(hairsys_session_record(s, bad_path, 0, 0), HAIRSYS_STATUS_CACHE, "");
  EXPECT(hairsys_session_record(s, cache_path, HAIRSYS_COMPRESSION_ZSTD, 0), OK, "");
  EXPECT(hairsys_session_restore(s, snap), ARG, "recording");
  EXPECT(hairsys_session_step(s, NULL), OK, "");
  HairsysCacheSummary summary;
  EXPECT(hairsys_session_finish_recording(s, &summary), OK, "");
  if (summary.frames != 2) {
    fprintf(stderr, "the cache holds %zu frames, wanted 2\n", summary.frames);
    failed++;
  }
  EXPECT(hairsys_session_restore(s, snap), OK, "");

  HairsysCache *cache = NULL;
  EXPECT(hairsys_cache_open(NULL, &cache), NUL, "path");
  EXPECT(hairsys_cache_open(cache_path, NULL), NUL, "out");
  EXPECT(hairsys_cache_open(bad_path, &cache), HAIRSYS_STATUS_CACHE, "");
  EXPECT(hairsys_cache_open(cache_path, &cache), OK, "");
  HairsysCacheInfo ci;
  EXPECT(hairsys_cache_info(cache, NULL), NUL, "out");
  EXPECT(hairsys_cache_info(NULL, &ci), NUL, "cache");
  EXPECT(hairsys_cache_info(cache, &ci), OK, "");
  EXPECT(hairsys_cache_strand_offsets(cache, NULL), NUL, "out");
  float frame_xyz[8 * 3], frame_vel[8 * 3];
  EXPECT(hairsys_cache_read_frame(cache, ci.first_frame, frame_xyz, NULL, 7), LEN, "8 points");
  EXPECT(hairsys_cache_read_frame(cache, ci.first_frame, NULL, NULL, 8), NUL, "positions");
  EXPECT(hairsys_cache_read_frame(cache, ci.first_frame, (float *)mis_f, NULL, 8), MIS,
         "positions");
  EXPECT(hairsys_cache_read_frame(cache, 999, frame_xyz, NULL, 8), HAIRSYS_STATUS_CACHE, "999");
  EXPECT(hairsys_cache_read_frame(cache, ci.last_frame, frame_xyz, frame_vel, 8), OK, "");
  EXPECT(hairsys_export_usd(NULL, usd_path), NUL, "cache_path");
  EXPECT(hairsys_export_usd(cache_path, NULL), NUL, "usd_path");
  EXPECT(hairsys_export_usd(cache_path, cache_path), HAIRSYS_STATUS_OUTPUT, "extension");
  EXPECT(hairsys_export_usd(bad_path, usd_path), HAIRSYS_STATUS_OUTPUT, "");
  EXPECT(hairsys_export_usd(cache_path, usd_path), OK, "");

  /* Children. */
  HairsysChildSettings cs;
  HairsysChildren *kids = NULL;
  HairsysChildrenView kv;
  EXPECT(hairsys_child_settings_default(NULL), NUL, "out");
  EXPECT(hairsys_child_settings_default(&cs), OK, "");
  EXPECT(hairsys_session_children(s, NULL, &kids), NUL, "settings");
  EXPECT(hairsys_session_children(s, &cs, NULL), NUL, "out");
  cs.total = 1000000000000ull;
  EXPECT(hairsys_session_children(s, &cs, &kids), ARG, "GiB");
  cs.total = 0;
  cs.interpolated = 4;
  EXPECT(hairsys_session_children(s, &cs, &kids), ARG, "interpolated");
  cs.interpolated = 0;
  cs.spread = NAN;
  EXPECT(hairsys_session_children(s, &cs, &kids), NAN_, "settings");
  hairsys_child_settings_default(&cs);
  EXPECT(hairsys_session_children(s, &cs, &kids), OK, "");
  EXPECT(hairsys_children_view(kids, NULL), NUL, "out");
  EXPECT(hairsys_children_view(NULL, &kv), NUL, "children");
  EXPECT(hairsys_children_view(kids, &kv), OK, "");
  if (kv.curve_count != 2 * cs.per_parent) {
    fprintf(stderr, "%zu children, wanted %u\n", kv.curve_count, 2 * cs.per_parent);
    failed++;
  }

  /* Destroying NULL does nothing. */
  hairsys_session_destroy(NULL);
  hairsys_snapshot_destroy(NULL);
  hairsys_children_destroy(NULL);
  hairsys_cache_destroy(NULL);
  hairsys_children_destroy(kids);
  hairsys_cache_destroy(cache);
  hairsys_snapshot_destroy(snap);
  hairsys_session_destroy(s);
  printf("%d passed, %d failed\n", passed, failed);
  return failed != 0;
}
