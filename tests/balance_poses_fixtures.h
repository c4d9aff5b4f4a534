/* balance_poses_fixtures.h - meshes and mass properties shared by the regime, stable-pose and
 * stack suites: boxes, a leaning box (parallelepiped), an ellipsoid, the bundled rocks. Static
 * inline so each suite takes only what it uses. */
#ifndef COMLEARN_TESTS_BALANCE_POSES_FIXTURES_H
#define COMLEARN_TESTS_BALANCE_POSES_FIXTURES_H

#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "comlearn/balance.h"
#include "comlearn/math3d.h"
#include "comlearn/model.h"
#include "comlearn/model_inertial.h"

/* A hexahedron from 8 corners in the order of a box [lo, hi]: bottom face 0..3 counter-clockwise
 * from (lo, lo), top face 4..7 above them. 12 outward triangles; allocated. */
static inline void bp_hexahedron(model_mesh_t *m, const double corners[8][3]) {
  static const uint32_t tris[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7},
                                       {0, 1, 5}, {0, 5, 4}, {1, 2, 6}, {1, 6, 5},
                                       {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  m->vertex_count = 8;
  m->triangle_count = 12;
  m->vertices_m = malloc(8 * sizeof *m->vertices_m);
  m->triangles = malloc(sizeof tris);
  ck_assert_ptr_nonnull(m->vertices_m);
  ck_assert_ptr_nonnull(m->triangles);
  memcpy(m->vertices_m, corners, 8 * sizeof *m->vertices_m);
  memcpy(m->triangles, tris, sizeof tris);
}

/* Box of half extents h centered at the origin; the top face shifted by lean_x along x (a leaning
 * parallelepiped when lean_x != 0). */
static inline void bp_box(model_mesh_t *m, const double h[3], double lean_x) {
  double c[8][3];
  for (int i = 0; i < 8; ++i) {
    c[i][0] = ((i % 4 == 1 || i % 4 == 2) ? h[0] : -h[0]) + (i >= 4 ? lean_x : 0.0);
    c[i][1] = (i % 4 >= 2) ? h[1] : -h[1];
    c[i][2] = i >= 4 ? h[2] : -h[2];
  }
  bp_hexahedron(m, (const double(*)[3])c);
}

/* Two boxes of half extents h side by side along x, centred at x = -gap/2 - h[0] and
 * gap/2 + h[0], bottoms coplanar: an object on two separate feet (two shells; 16 vertices). */
static inline void bp_two_feet(model_mesh_t *m, const double h[3], double gap) {
  model_mesh_t a = {0}, b = {0};
  bp_box(&a, h, 0.0);
  bp_box(&b, h, 0.0);
  m->vertex_count = 16;
  m->triangle_count = 24;
  m->vertices_m = malloc(16 * sizeof *m->vertices_m);
  m->triangles = malloc(24 * sizeof *m->triangles);
  ck_assert_ptr_nonnull(m->vertices_m);
  ck_assert_ptr_nonnull(m->triangles);
  for (int v = 0; v < 8; ++v) {
    memcpy(m->vertices_m[v], a.vertices_m[v], sizeof *m->vertices_m);
    memcpy(m->vertices_m[v + 8], b.vertices_m[v], sizeof *m->vertices_m);
    m->vertices_m[v][0] -= 0.5 * gap + h[0];
    m->vertices_m[v + 8][0] += 0.5 * gap + h[0];
  }
  for (int t = 0; t < 12; ++t) {
    for (int k = 0; k < 3; ++k) {
      m->triangles[t][k] = a.triangles[t][k];
      m->triangles[t + 12][k] = b.triangles[t][k] + 8u;
    }
  }
  model_mesh_free(&a);
  model_mesh_free(&b);
}

/* A washer: the annulus r_in..r_out (n segments, vertices on the circles) extruded over z in
 * [-h, h], centred at the origin. Its bottom is one flat region that is not convex. Allocated. */
static inline void bp_washer(model_mesh_t *m, double r_in, double r_out, double h, unsigned n) {
  m->vertex_count = 4 * (size_t)n;
  m->triangle_count = 8 * (size_t)n;
  m->vertices_m = malloc(m->vertex_count * sizeof *m->vertices_m);
  m->triangles = malloc(m->triangle_count * sizeof *m->triangles);
  ck_assert_ptr_nonnull(m->vertices_m);
  ck_assert_ptr_nonnull(m->triangles);
  /* vertex 4i + j: j = 0 outer bottom, 1 outer top, 2 inner bottom, 3 inner top */
  for (unsigned i = 0; i < n; ++i) {
    const double a = 2.0 * CL_PI * i / n, c = cos(a), s = sin(a);
    const double r[4] = {r_out, r_out, r_in, r_in}, z[4] = {-h, h, -h, h};
    for (unsigned j = 0; j < 4; ++j) {
      m->vertices_m[4 * i + j][0] = r[j] * c;
      m->vertices_m[4 * i + j][1] = r[j] * s;
      m->vertices_m[4 * i + j][2] = z[j];
    }
  }
  size_t t = 0;
  for (unsigned i = 0; i < n; ++i) {
    const uint32_t a = 4 * i, b = 4 * ((i + 1) % n);
    const uint32_t quads[4][4] = {{a + 0, b + 0, b + 1, a + 1},  /* outer wall, facing out */
                                  {a + 3, b + 3, b + 2, a + 2},  /* inner wall, facing in */
                                  {a + 1, b + 1, b + 3, a + 3},  /* top */
                                  {a + 2, b + 2, b + 0, a + 0}}; /* bottom */
    for (int q = 0; q < 4; ++q) {
      const uint32_t tri[2][3] = {{quads[q][0], quads[q][1], quads[q][2]},
                                  {quads[q][0], quads[q][2], quads[q][3]}};
      memcpy(m->triangles[t++], tri[0], sizeof tri[0]);
      memcpy(m->triangles[t++], tri[1], sizeof tri[1]);
    }
  }
}

/* Mass properties of a box of half extents h and mass kg with its CoM moved to com (the inertia
 * stays the box's own about its center: a valid, positive-definite tensor). */
static inline void bp_box_mass(const double h[3], double kg, const double com[3],
                               model_mass_t *out) {
  memset(out, 0, sizeof *out);
  out->mass_kg = kg;
  memcpy(out->com_m, com, sizeof out->com_m);
  out->inertia_kg_m2[0][0] = kg / 3.0 * (h[1] * h[1] + h[2] * h[2]);
  out->inertia_kg_m2[1][1] = kg / 3.0 * (h[0] * h[0] + h[2] * h[2]);
  out->inertia_kg_m2[2][2] = kg / 3.0 * (h[0] * h[0] + h[1] * h[1]);
}

/* UV ellipsoid with semi-axes a (rings x segs, poles on z): a rounded underside. Allocated. */
static inline void bp_ellipsoid(model_mesh_t *m, const double a[3], unsigned rings, unsigned segs) {
  m->vertex_count = 2 + (size_t)(rings - 1) * segs;
  m->triangle_count = 2 * (size_t)segs * (rings - 1);
  m->vertices_m = malloc(m->vertex_count * sizeof *m->vertices_m);
  m->triangles = malloc(m->triangle_count * sizeof *m->triangles);
  ck_assert_ptr_nonnull(m->vertices_m);
  ck_assert_ptr_nonnull(m->triangles);
  const double top[3] = {0.0, 0.0, a[2]}, bottom[3] = {0.0, 0.0, -a[2]};
  memcpy(m->vertices_m[0], top, sizeof top);
  memcpy(m->vertices_m[1], bottom, sizeof bottom);
  for (unsigned i = 1; i < rings; ++i) {
    const double th = CL_PI * i / rings;
    for (unsigned j = 0; j < segs; ++j) {
      const double ph = 2.0 * CL_PI * j / segs;
      double *v = m->vertices_m[2 + (i - 1) * segs + j];
      v[0] = a[0] * sin(th) * cos(ph);
      v[1] = a[1] * sin(th) * sin(ph);
      v[2] = a[2] * cos(th);
    }
  }
  size_t t = 0;
#define BP_RING(i, j) ((uint32_t)(2 + ((i)-1) * segs + ((j) % segs)))
  for (unsigned j = 0; j < segs; ++j) {
    uint32_t *p = m->triangles[t++];
    p[0] = 0, p[1] = BP_RING(1, j), p[2] = BP_RING(1, j + 1);
    uint32_t *q = m->triangles[t++];
    q[0] = 1, q[1] = BP_RING(rings - 1, j + 1), q[2] = BP_RING(rings - 1, j);
  }
  for (unsigned i = 1; i + 1 < rings; ++i) {
    for (unsigned j = 0; j < segs; ++j) {
      uint32_t *p = m->triangles[t++];
      p[0] = BP_RING(i, j), p[1] = BP_RING(i + 1, j), p[2] = BP_RING(i + 1, j + 1);
      uint32_t *q = m->triangles[t++];
      q[0] = BP_RING(i, j), q[1] = BP_RING(i + 1, j + 1), q[2] = BP_RING(i, j + 1);
    }
  }
#undef BP_RING
}

/* A bundled rock: its mesh (link frame), the uniform-density CoM (the estimator's prior) and the
 * URDF inertial (the simulator's truth). which: 1..3, uneven 0/1. */
typedef struct {
  model_object_t obj;
  model_mass_t uniform;
  model_mass_t truth;
} bp_rock_t;

static inline void bp_rock_load(bp_rock_t *r, int which, int uneven) {
  char path[1024];
  snprintf(path, sizeof path, "%s/rocks/rock_%d_%s.urdf", COMLEARN_ASSETS_DIR, which,
           uneven ? "uneven" : "even");
  model_error_t err;
  memset(r, 0, sizeof *r);
  ck_assert_msg(model_object_load(path, NULL, &r->obj, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_msg(model_inertial_load(path, NULL, &r->truth, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_int_eq(model_mesh_mass(&r->obj.mesh, 2650.0, &r->uniform), MODEL_OK);
}

static inline void bp_rock_free(bp_rock_t *r) { model_object_free(&r->obj); }

#endif
