/* balance_stable_tests.c - stable poses (comlearn/balance_poses.h): hull-face candidates for a CoM
 * guess, confirmed by a trial in the middle of B with the simulator's mass properties. */
#include <check.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "balance_poses_fixtures.h"
#include "balance_suites.h"
#include "comlearn/balance_poses.h"

static balance_world_t *world_new(void) {
  balance_config_t cfg;
  balance_config_default(&cfg);
  balance_world_t *w = NULL;
  ck_assert_int_eq(balance_world_create(&cfg, &w), BALANCE_OK);
  return w;
}

static const double kBoxH[3] = {0.03, 0.02, 0.01};

/* Which axis a face normal runs along (+-1 on it), -1 if none. */
static int normal_axis(const double n[3]) {
  for (int k = 0; k < 3; ++k) {
    if (fabs(fabs(n[k]) - 1.0) < 1e-12) return k;
  }
  return -1;
}

START_TEST(box_rests_on_all_six_faces) {
  const double com[3] = {0, 0, 0};
  model_mesh_t m = {0};
  bp_box(&m, kBoxH, 0.0);
  model_mass_t mass;
  bp_box_mass(kBoxH, 0.2, com, &mass);
  balance_world_t *w = world_new();
  balance_object_t *obj = NULL;
  ck_assert_int_eq(balance_object_create(w, &m, &mass, &obj), BALANCE_OK);
  balance_stable_pose_t poses[8];
  size_t n = 0, trials = 0;
  ck_assert_int_eq(balance_stable_find(w, obj, com, NULL, NULL, poses, 8, &n, &trials), BALANCE_OK);
  ck_assert_uint_eq(n, 6);
  ck_assert_uint_eq(trials, 6);
  for (size_t i = 0; i < n; ++i) {
    const int axis = normal_axis(poses[i].face.normal_link);
    ck_assert_int_ge(axis, 0);
    ck_assert_int_eq(poses[i].trial.outcome, BALANCE_STAYS);
    ck_assert(poses[i].trial.rotation_rad < 1e-3);
    /* Settled with the link origin (the box center) half the box's height above B, over the
     * middle of B. */
    ck_assert_double_eq_tol(poses[i].trial.settled.position_m[2], kBoxH[axis], 2e-5);
    ck_assert_double_eq_tol(poses[i].trial.settled.position_m[0], 0.0, 1e-4);
    ck_assert_double_eq_tol(poses[i].trial.settled.position_m[1], 0.0, 1e-4);
  }
  balance_world_destroy(w);
  model_mesh_free(&m);
}
END_TEST

START_TEST(box_with_offset_com) {
  /* CoM 25 mm along +x in a 60 x 40 x 20 mm box: 10 mm inside the +-x faces, 5 mm inside the
   * four others (analytic). All six rest; with a 6 mm margin required only the x faces are
   * candidates, and only they are tried. */
  const double com[3] = {0.025, 0.0, 0.0};
  model_mesh_t m = {0};
  bp_box(&m, kBoxH, 0.0);
  model_mass_t mass;
  bp_box_mass(kBoxH, 0.2, com, &mass);
  balance_world_t *w = world_new();
  balance_object_t *obj = NULL;
  ck_assert_int_eq(balance_object_create(w, &m, &mass, &obj), BALANCE_OK);
  balance_stable_pose_t poses[8];
  size_t n = 0, trials = 0;
  ck_assert_int_eq(balance_stable_find(w, obj, com, NULL, NULL, poses, 8, &n, &trials), BALANCE_OK);
  ck_assert_uint_eq(n, 6);
  model_regime_config_t rc;
  model_regime_config_default(&rc);
  rc.min_com_margin_m = 0.006;
  ck_assert_int_eq(balance_stable_find(w, obj, com, &rc, NULL, poses, 8, &n, &trials), BALANCE_OK);
  ck_assert_uint_eq(n, 2);
  ck_assert_uint_eq(trials, 2);
  for (size_t i = 0; i < n; ++i) {
    ck_assert_int_eq(normal_axis(poses[i].face.normal_link), 0);
    ck_assert_double_eq_tol(poses[i].face.com_margin_m, 0.010, 1e-12);
  }
  balance_world_destroy(w);
  model_mesh_free(&m);
}
END_TEST

START_TEST(com_outside_support_is_not_confirmed) {
  /* A leaning parallelepiped: bottom 20 x 20 mm, top shifted 30 mm in x, 60 mm tall. Its true
   * (uniform) CoM is 5 mm beyond the bottom face. A guess at the bottom face's middle makes the
   * bottom face a candidate; the simulation (truth) tips it over. */
  const double h[3] = {0.01, 0.01, 0.03};
  model_mesh_t m = {0};
  bp_box(&m, h, 0.03);
  model_mass_t truth;
  ck_assert_int_eq(model_mesh_mass(&m, 1000.0, &truth), MODEL_OK);
  balance_world_t *w = world_new();
  balance_object_t *obj = NULL;
  ck_assert_int_eq(balance_object_create(w, &m, &truth, &obj), BALANCE_OK);
  const double guess[3] = {0.0, 0.0, -0.03};
  const double up[4] = {1, 0, 0, 0};
  balance_trial_result_t tr;
  int ok = 1;
  ck_assert_int_eq(balance_stable_confirm(w, obj, up, guess, NULL, &tr, &ok), BALANCE_OK);
  ck_assert_int_eq(ok, 0);
  ck_assert_int_ne(tr.outcome, BALANCE_STAYS);
  ck_assert(tr.rotation_rad > 0.1);
  balance_stable_pose_t poses[8];
  size_t n = 0, trials = 0;
  ck_assert_int_eq(balance_stable_find(w, obj, guess, NULL, NULL, poses, 8, &n, &trials),
                   BALANCE_OK);
  ck_assert(trials > n); /* the bottom face was tried and rejected */
  for (size_t i = 0; i < n; ++i) ck_assert(fabs(poses[i].face.normal_link[2]) < 0.99);
  /* With the true CoM as the guess the bottom face is not even tried. */
  model_face_t f[8];
  size_t nf = 0;
  ck_assert_int_eq(model_faces_find(&m, truth.com_m, NULL, f, 8, &nf), MODEL_OK);
  for (size_t i = 0; i < nf; ++i) {
    if (f[i].normal_link[2] < -0.99) ck_assert(!f[i].candidate);
  }
  balance_world_destroy(w);
  model_mesh_free(&m);
}
END_TEST

START_TEST(rocks_rest_on_their_flat_faces) {
  const int which = _i / 2 + 1, uneven = _i % 2;
  bp_rock_t r;
  bp_rock_load(&r, which, uneven);
  balance_world_t *w = world_new();
  balance_object_t *obj = NULL;
  ck_assert_int_eq(balance_object_create(w, &r.obj.mesh, &r.truth, &obj), BALANCE_OK);
  /* The estimator's side: candidates from the uniform-density CoM. The truth is in obj only. */
  balance_stable_pose_t poses[16];
  size_t n = 0, trials = 0;
  ck_assert_int_eq(balance_stable_find(w, obj, r.uniform.com_m, NULL, NULL, poses, 16, &n, &trials),
                   BALANCE_OK);
  ck_assert_msg(n >= 2, "rock %d %s: %zu stable poses of %zu tried", which,
                uneven ? "uneven" : "even", n, trials);
  int bottom = 0;
  for (size_t i = 0; i < n && i < 16; ++i) {
    ck_assert_int_eq(poses[i].trial.outcome, BALANCE_STAYS);
    ck_assert(poses[i].trial.rotation_rad <= 0.02);
    if (poses[i].face.normal_link[2] == -1.0) {
      bottom = 1;
      ck_assert(poses[i].face.flat);
    }
  }
  ck_assert(bottom);
  balance_world_destroy(w);
  bp_rock_free(&r);
}
END_TEST

START_TEST(bad_input_gives_status) {
  const double com[3] = {0, 0, 0}, up[4] = {1, 0, 0, 0};
  model_mesh_t m = {0};
  bp_box(&m, kBoxH, 0.0);
  model_mass_t mass;
  bp_box_mass(kBoxH, 0.2, com, &mass);
  balance_world_t *w = world_new(), *w2 = world_new();
  balance_object_t *obj = NULL;
  ck_assert_int_eq(balance_object_create(w, &m, &mass, &obj), BALANCE_OK);
  int ok = 7;
  ck_assert_int_eq(balance_stable_confirm(NULL, obj, up, com, NULL, NULL, &ok), BALANCE_E_ARG);
  ck_assert_int_eq(balance_stable_confirm(w, NULL, up, com, NULL, NULL, &ok), BALANCE_E_ARG);
  ck_assert_int_eq(balance_stable_confirm(w2, obj, up, com, NULL, NULL, &ok), BALANCE_E_ARG);
  ck_assert_int_eq(balance_stable_confirm(w, obj, up, com, NULL, NULL, NULL), BALANCE_E_ARG);
  const double q_bad[4] = {0.9, 0, 0, 0}, q_nan[4] = {NAN, 0, 0, 0}, c_nan[3] = {0, INFINITY, 0};
  ck_assert_int_eq(balance_stable_confirm(w, obj, q_bad, com, NULL, NULL, &ok), BALANCE_E_POSE);
  ck_assert_int_eq(ok, 0);
  ck_assert_int_eq(balance_stable_confirm(w, obj, q_nan, com, NULL, NULL, &ok),
                   BALANCE_E_NONFINITE);
  ck_assert_int_eq(balance_stable_confirm(w, obj, up, c_nan, NULL, NULL, &ok), BALANCE_E_NONFINITE);
  model_stable_config_t sc;
  model_stable_config_default(&sc);
  sc.max_rotation_rad = -1.0;
  ck_assert_int_eq(balance_stable_confirm(w, obj, up, com, &sc, NULL, &ok), BALANCE_E_ARG);
  sc.max_rotation_rad = NAN;
  ck_assert_int_eq(balance_stable_confirm(w, obj, up, com, &sc, NULL, &ok), BALANCE_E_NONFINITE);
  size_t n = 5;
  balance_stable_pose_t poses[2];
  ck_assert_int_eq(balance_stable_find(w, obj, c_nan, NULL, NULL, poses, 2, &n, NULL),
                   BALANCE_E_NONFINITE);
  ck_assert_uint_eq(n, 0);
  ck_assert_int_eq(balance_stable_find(w, obj, com, NULL, NULL, NULL, 2, &n, NULL), BALANCE_E_ARG);
  /* A short array still reports the count. */
  ck_assert_int_eq(balance_stable_find(w, obj, com, NULL, NULL, poses, 2, &n, NULL), BALANCE_OK);
  ck_assert_uint_eq(n, 6);
  balance_world_destroy(w);
  balance_world_destroy(w2);
  model_mesh_free(&m);
}
END_TEST

Suite *balance_stable_suite(void) {
  Suite *s = suite_create("balance_stable");
  TCase *tc = tcase_create("stable");
  tcase_set_timeout(tc, 300);
  tcase_add_test(tc, box_rests_on_all_six_faces);
  tcase_add_test(tc, box_with_offset_com);
  tcase_add_test(tc, com_outside_support_is_not_confirmed);
  tcase_add_loop_test(tc, rocks_rest_on_their_flat_faces, 0, 6);
  tcase_add_test(tc, bad_input_gives_status);
  suite_add_tcase(s, tc);
  return s;
}
