/* mesh_subdivide.h - midpoint subdivision of a triangle mesh, for the hull tests
 * (tests/model_hull_tests.c) and bench_hull. Static inline, no test framework, so bench/ can take
 * it too (bench_qlearn takes tests/test_rng.h the same way). */
#ifndef COMLEARN_TESTS_MESH_SUBDIVIDE_H
#define COMLEARN_TESTS_MESH_SUBDIVIDE_H

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "comlearn/model.h"

/* Every triangle of `in` into four through its edge midpoints; each edge's midpoint is one vertex
 * shared by the edge's triangles, so a closed mesh stays closed and keeps its orientation. The
 * input vertices come first, in order. A midpoint (a + b) / 2 of doubles with a few significant
 * bits, like float coordinates from a file, is exact: the subdivided mesh is then the same
 * surface, and its hull the same solid. round_f32: round the midpoints to float, as an STL file
 * stores them (within 4e-9 m of the surface for a 5 cm object). out must not own arrays; returns
 * 0, or -1 when out of memory (out zeroed). */
static inline int mesh_subdivide(const model_mesh_t *in, model_mesh_t *out, int round_f32) {
  const size_t nv = in->vertex_count, nt = in->triangle_count;
  size_t cap = 64;
  while (cap < 4 * nt) cap *= 2; /* room for 3 nt edges at load <= 3/4 */
  uint64_t *key = malloc(cap * sizeof *key);
  uint32_t *mid = malloc(cap * sizeof *mid);
  memset(out, 0, sizeof *out);
  out->vertices_m = malloc((nv + 3 * nt) * sizeof *out->vertices_m);
  out->triangles = malloc(4 * nt * sizeof *out->triangles);
  if (key == NULL || mid == NULL || out->vertices_m == NULL || out->triangles == NULL) {
    free(key);
    free(mid);
    model_mesh_free(out);
    return -1;
  }
  memset(key, 0xff, cap * sizeof *key); /* UINT64_MAX: empty slot */
  memcpy(out->vertices_m, in->vertices_m, nv * sizeof *in->vertices_m);
  size_t n = nv;
  for (size_t t = 0; t < nt; ++t) {
    uint32_t m[3];
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = in->triangles[t][k], b = in->triangles[t][(k + 1) % 3];
      const uint64_t e = a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a;
      size_t h = (size_t)((e * 0x9e3779b97f4a7c15u) >> 20) & (cap - 1);
      while (key[h] != UINT64_MAX && key[h] != e) h = (h + 1) & (cap - 1);
      if (key[h] == UINT64_MAX) {
        key[h] = e;
        mid[h] = (uint32_t)n;
        for (int j = 0; j < 3; ++j) {
          const double v = 0.5 * (in->vertices_m[a][j] + in->vertices_m[b][j]);
          out->vertices_m[n][j] = round_f32 ? (double)(float)v : v;
        }
        ++n;
      }
      m[k] = mid[h];
    }
    const uint32_t *v = in->triangles[t];
    const uint32_t tri[4][3] = {
        {v[0], m[0], m[2]}, {m[0], v[1], m[1]}, {m[2], m[1], v[2]}, {m[0], m[1], m[2]}};
    memcpy(out->triangles[4 * t], tri, sizeof tri);
  }
  out->vertex_count = n;
  out->triangle_count = 4 * nt;
  free(key);
  free(mid);
  return 0;
}

#endif
