/* The scenario the C and C++ drivers and the Rust test share: a groom, and per frame the
 * scalp (rigid or deformed) and a sphere collider's pose. Written by tests/c_programs.rs as
 * little-endian binary:
 *
 *   u32 V, f32 scalp_vertices[3V], u32 T, u32 scalp_triangles[3T],
 *   u32 C, u32 curve_counts[C], u32 P, f32 curve_points[3P],
 *   f32 collider_radius, f32 collider_pose[7] (tx ty tz qx qy qz qw),
 *   u32 F, then F frames: u32 kind (0 rigid, 1 deformed), f32 scalp[7], f32 collider[7],
 *   and for kind 1: f32 vertices[3V] (body space)
 */
#ifndef SCENARIO_H
#define SCENARIO_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "hairsys.h"

typedef struct Frame {
  uint32_t kind;
  HairsysTransform scalp;
  HairsysTransform collider;
  float *vertices;
} Frame;

typedef struct Scenario {
  uint32_t vertex_count, triangle_count, curve_count, point_count, frame_count;
  float *vertices;
  uint32_t *triangles;
  uint32_t *counts;
  float *points;
  float collider_radius;
  HairsysTransform collider_pose;
  Frame *frames;
} Scenario;

static void *read_array(FILE *f, size_t count, size_t size) {
  void *p = malloc(count * size + 1);
  if (!p || fread(p, size, count, f) != count) {
    fprintf(stderr, "scenario: truncated file\n");
    exit(2);
  }
  return p;
}

static uint32_t read_u32(FILE *f) {
  uint32_t v;
  if (fread(&v, 4, 1, f) != 1) {
    fprintf(stderr, "scenario: truncated file\n");
    exit(2);
  }
  return v;
}

static HairsysTransform read_transform(FILE *f) {
  float t[7];
  if (fread(t, 4, 7, f) != 7) {
    fprintf(stderr, "scenario: truncated file\n");
    exit(2);
  }
  HairsysTransform x = {{t[0], t[1], t[2]}, {t[3], t[4], t[5], t[6]}};
  return x;
}

static Scenario read_scenario(const char *path) {
  Scenario s;
  FILE *f = fopen(path, "rb");
  if (!f) {
    fprintf(stderr, "scenario: cannot open %s\n", path);
    exit(2);
  }
  s.vertex_count = read_u32(f);
  s.vertices = (float *)read_array(f, 3 * (size_t)s.vertex_count, 4);
  s.triangle_count = read_u32(f);
  s.triangles = (uint32_t *)read_array(f, 3 * (size_t)s.triangle_count, 4);
  s.curve_count = read_u32(f);
  s.counts = (uint32_t *)read_array(f, s.curve_count, 4);
  s.point_count = read_u32(f);
  s.points = (float *)read_array(f, 3 * (size_t)s.point_count, 4);
  if (fread(&s.collider_radius, 4, 1, f) != 1) exit(2);
  s.collider_pose = read_transform(f);
  s.frame_count = read_u32(f);
  s.frames = (Frame *)calloc(s.frame_count, sizeof(Frame));
  for (uint32_t i = 0; i < s.frame_count; i++) {
    Frame *fr = &s.frames[i];
    fr->kind = read_u32(f);
    fr->scalp = read_transform(f);
    fr->collider = read_transform(f);
    fr->vertices = fr->kind == 1 ? (float *)read_array(f, 3 * (size_t)s.vertex_count, 4) : NULL;
  }
  fclose(f);
  return s;
}

static void free_scenario(Scenario *s) {
  for (uint32_t i = 0; i < s->frame_count; i++) free(s->frames[i].vertices);
  free(s->frames);
  free(s->vertices);
  free(s->triangles);
  free(s->counts);
  free(s->points);
}

#endif
