/* balance_phys_util.h - fixtures of the trial and accuracy suites (tests/balance_trial_tests.c,
 * tests/balance_accuracy_tests.c): meshes built in memory, rocks from the bundled assets, and the
 * tipping threshold found by bisection. Everything is static inline. */
#ifndef COMLEARN_TESTS_BALANCE_PHYS_UTIL_H
#define COMLEARN_TESTS_BALANCE_PHYS_UTIL_H

#include <check.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "comlearn/balance.h"
#include "comlearn/math3d.h"
#include "comlearn/model.h"
#include "comlearn/model_inertial.h"

/* A box [lo, hi], 8 vertices, 12 outward triangles (model_mesh_free releases). */
static inline void bp_box(model_mesh_t *m, const double lo[3], const double hi[3]) {
  memset(m, 0, sizeof *m);
  ck_assert_int_eq(model_mesh_box(lo, hi, m), MODEL_OK);
}

/* An L-shaped prism (two boxes joined): the polygon (0,0) (60,0) (60,20) (20,20) (20,50) (0,50)
 * mm in the x-z plane, extruded over y in [-20, 20] mm. Analytic CoM: x = (1200*30 + 600*10) /
 * 1800 mm, y = 0, z = (1200*10 + 600*35) / 1800 mm. */
static inline void bp_ell(model_mesh_t *m, double com_m[3]) {
  static const double px[6] = {0, 60, 60, 20, 20, 0}, pz[6] = {0, 0, 20, 20, 50, 50};
  m->vertex_count = 12;
  m->triangle_count = 20;
  m->vertices_m = malloc(12 * sizeof *m->vertices_m);
  m->triangles = malloc(20 * sizeof *m->triangles);
  ck_assert_ptr_nonnull(m->vertices_m);
  ck_assert_ptr_nonnull(m->triangles);
  for (uint32_t i = 0; i < 6; i++) {
    m->vertices_m[i][0] = m->vertices_m[i + 6][0] = px[i] * 1e-3;
    m->vertices_m[i][1] = -0.02;
    m->vertices_m[i + 6][1] = 0.02;
    m->vertices_m[i][2] = m->vertices_m[i + 6][2] = pz[i] * 1e-3;
  }
  size_t t = 0;
  for (uint32_t i = 1; i + 1 < 6; i++) { /* caps: a fan from vertex 0 sees the whole L */
    uint32_t *a = m->triangles[t++], *b = m->triangles[t++];
    a[0] = 0, a[1] = i, a[2] = i + 1;         /* y = -20 mm, normal -y */
    b[0] = 6, b[1] = 6 + i + 1, b[2] = 6 + i; /* y = +20 mm, normal +y */
  }
  for (uint32_t i = 0; i < 6; i++) {
    const uint32_t j = (i + 1) % 6;
    uint32_t *a = m->triangles[t++], *b = m->triangles[t++];
    a[0] = i, a[1] = 6 + i, a[2] = 6 + j;
    b[0] = i, b[1] = 6 + j, b[2] = j;
  }
  com_m[0] = (1200.0 * 30.0 + 600.0 * 10.0) / 1800.0 * 1e-3;
  com_m[1] = 0.0;
  com_m[2] = (1200.0 * 10.0 + 600.0 * 35.0) / 1800.0 * 1e-3;
}

/* Load a bundled rock: mesh (estimator view) and inertial truth. */
static inline void bp_rock(const char *name, model_object_t *obj, model_mass_t *mass) {
  char path[1024];
  snprintf(path, sizeof path, "%s/rocks/%s.urdf", COMLEARN_ASSETS_DIR, name);
  model_error_t err;
  ck_assert_msg(model_object_load(path, NULL, obj, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_msg(model_inertial_load(path, NULL, mass, &err) == MODEL_OK, "%s", err.msg);
}

/* Edge normal n expressed in the link frame for orientation q: u = R(q)^T n. */
static inline void bp_edge_dir_link(const double q[4], const double n[3], double u[3]) {
  double r[3][3];
  cl_quat_to_rot(q, r);
  for (int i = 0; i < 3; i++) u[i] = r[0][i] * n[0] + r[1][i] * n[1] + r[2][i] * n[2];
}

/* Outcome with the link point p0 + s u put over `edge` (u = the edge normal in the link frame).
 * The CoM is inside B by s - u.(com - p0). */
static inline balance_outcome_t bp_trial_at(balance_world_t *w, balance_object_t *o,
                                            const double q[4], model_edge_t edge,
                                            const double p0[3], const double u[3], double s) {
  double p[3];
  for (int i = 0; i < 3; i++) p[i] = p0[i] + s * u[i];
  model_pose_t pose;
  balance_status_t st = balance_pose_over_edge(w, o, q, edge, p, 0.0, 1e-6, &pose);
  ck_assert_msg(st == BALANCE_OK, "pose_over_edge: %s", balance_status_str(st));
  balance_trial_result_t res;
  st = balance_trial_run(w, o, &pose, NULL, &res);
  ck_assert_msg(st == BALANCE_OK, "trial: %s", balance_status_str(st));
  ck_assert_msg(res.outcome == BALANCE_STAYS || res.outcome == BALANCE_TIPS,
                "outcome %d at s = %.9g m", (int)res.outcome, s);
  return res.outcome;
}

/* Tipping threshold in s (see bp_trial_at), bisected in [lo, hi] for `iters` halvings; the
 * outcome must be TIPS at lo and STAYS at hi. */
static inline double bp_threshold(balance_world_t *w, balance_object_t *o, const double q[4],
                                  model_edge_t edge, const double p0[3], const double u[3],
                                  double lo, double hi, int iters) {
  ck_assert_int_eq(bp_trial_at(w, o, q, edge, p0, u, lo), BALANCE_TIPS);
  ck_assert_int_eq(bp_trial_at(w, o, q, edge, p0, u, hi), BALANCE_STAYS);
  for (int i = 0; i < iters; i++) {
    const double mid = 0.5 * (lo + hi);
    if (bp_trial_at(w, o, q, edge, p0, u, mid) == BALANCE_STAYS)
      hi = mid;
    else
      lo = mid;
  }
  return 0.5 * (lo + hi);
}

#endif /* COMLEARN_TESTS_BALANCE_PHYS_UTIL_H */
