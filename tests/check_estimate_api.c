/* check_estimate_api: lib/estimate's caller-driven loop (comlearn/estimate.h) on its own, with
 * lib/balance as the caller's trial function: the loop agrees with estimate_run trial for trial,
 * bad replies are refused without losing anything, calls out of order give ESTIMATE_E_STATE, and
 * an estimate lives in the caller's memory. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "comlearn/estimate.h"
#include "comlearn/model.h"
#include "estimate_backend.h"
#include "estimate_direct.h"

static const double kBase[3] = {0.30, 0.30, 0.10};

typedef struct {
  model_object_t obj;
  estimate_direct_t *d;
  estimate_backend_t be;
} rock_t;

static void rock_open(rock_t *r, const char *name) {
  char urdf[512];
  snprintf(urdf, sizeof urdf, "%s/rocks/%s.urdf", COMLEARN_ASSETS_DIR, name);
  memset(r, 0, sizeof *r);
  model_error_t merr = {{0}};
  ck_assert_int_eq(model_object_load(urdf, NULL, &r->obj, &merr), MODEL_OK);
  char err[256];
  ck_assert_msg(estimate_direct_open(urdf, NULL, NULL, &r->d, &r->be, err, sizeof err) == 0, "%s",
                err);
}

static void rock_close(rock_t *r) {
  estimate_direct_close(r->d);
  model_object_free(&r->obj);
}

/* One trial through the direct backend. */
static void run_trial(rock_t *r, const estimate_trial_request_t *req, estimate_trial_reply_t *rep) {
  char err[256];
  memset(rep, 0, sizeof *rep);
  ck_assert_msg(r->be.run(r->be.ctx, req, rep, err, sizeof err) == 0, "%s", err);
}

static void results_equal(const estimate_result_t *a, const estimate_result_t *b) {
  ck_assert_uint_eq(a->trial_count, b->trial_count);
  ck_assert_uint_eq(a->search_count, b->search_count);
  for (size_t i = 0; i < a->trial_count; ++i) {
    ck_assert_int_eq(a->trial[i].outcome, b->trial[i].outcome);
    ck_assert(a->trial[i].x_m == b->trial[i].x_m);
  }
  for (int k = 0; k < 3; ++k) {
    ck_assert_int_eq(a->found[k], b->found[k]);
    ck_assert(a->com_m[k] == b->com_m[k]);
    ck_assert(a->halfwidth_m[k] == b->halfwidth_m[k]);
  }
}

/* The caller's loop, with every request run once and a refused reply slipped in before every
 * fifth trial: the same estimate, bit for bit, as estimate_run's loop. */
START_TEST(caller_loop_matches_run) {
  rock_t r;
  rock_open(&r, "rock_2_uneven");
  estimate_config_t cfg;
  estimate_config_default(&cfg);
  estimate_result_t *want = calloc(1, sizeof *want);
  ck_assert_ptr_nonnull(want);
  ck_assert_int_eq(estimate_run(&r.obj.mesh, &r.be, &cfg, want), ESTIMATE_OK);
  ck_assert_int_eq(want->found[0] + want->found[1] + want->found[2], 3);
  rock_close(&r);

  rock_open(&r, "rock_2_uneven");
  estimate_t *est = NULL;
  ck_assert_int_eq(estimate_create(&r.obj.mesh, kBase, &cfg, &est), ESTIMATE_OK);
  ck_assert_int_eq(estimate_status(est), ESTIMATE_OK);
  estimate_trial_request_t req, again;
  size_t n = 0;
  estimate_status_t s;
  while ((s = estimate_next(est, &req)) == ESTIMATE_OK) {
    /* asking again without an answer gives the same request */
    ck_assert_int_eq(estimate_next(est, &again), ESTIMATE_OK);
    ck_assert_mem_eq(&again, &req, sizeof req);
    estimate_trial_reply_t rep;
    run_trial(&r, &req, &rep);
    if (n % 5 == 0) {
      estimate_trial_reply_t bad = rep;
      bad.settled.position_m[1] = NAN;
      ck_assert_int_eq(estimate_observe(est, &bad), ESTIMATE_E_ARG);
      bad = rep;
      bad.outcome = (estimate_outcome_t)7;
      ck_assert_int_eq(estimate_observe(est, &bad), ESTIMATE_E_ARG);
      bad = rep;
      bad.released.orientation_wxyz[0] *= 1.01; /* not a unit quaternion */
      ck_assert_int_eq(estimate_observe(est, &bad), ESTIMATE_E_ARG);
      ck_assert_uint_eq(estimate_result(est)->trial_count, n); /* nothing logged */
      ck_assert_int_eq(estimate_next(est, &again), ESTIMATE_OK);
      ck_assert_mem_eq(&again, &req, sizeof req);
    }
    ck_assert_int_eq(estimate_observe(est, &rep), ESTIMATE_OK);
    ++n;
    ck_assert_uint_eq(estimate_result(est)->trial_count, n);
  }
  ck_assert_int_eq(s, ESTIMATE_DONE);
  ck_assert_int_eq(estimate_status(est), ESTIMATE_DONE);
  ck_assert_int_eq(estimate_next(est, &req), ESTIMATE_DONE);
  const estimate_trial_reply_t none = {0};
  ck_assert_int_eq(estimate_observe(est, &none), ESTIMATE_E_STATE);
  const estimate_result_t *got = estimate_result(est);
  results_equal(got, want);
  ck_assert_str_eq(got->msg, want->msg);
  estimate_destroy(est);
  rock_close(&r);
  free(want);
}
END_TEST

/* Out of order and bad arguments: refused with a status, nothing crashes. */
START_TEST(bad_calls_refused) {
  rock_t r;
  rock_open(&r, "rock_1_even");
  estimate_config_t cfg;
  estimate_config_default(&cfg);
  estimate_t *est = (estimate_t *)&cfg; /* any non-NULL: must be set to NULL on failure */
  const double no_base[3] = {0.3, 0.0, 0.1};
  ck_assert_int_eq(estimate_create(&r.obj.mesh, no_base, &cfg, &est), ESTIMATE_E_ARG);
  ck_assert_ptr_null(est);
  const double nan_base[3] = {0.3, NAN, 0.1};
  ck_assert_int_eq(estimate_create(&r.obj.mesh, nan_base, &cfg, &est), ESTIMATE_E_ARG);
  ck_assert_int_eq(estimate_create(NULL, kBase, &cfg, &est), ESTIMATE_E_ARG);
  estimate_config_t bad = cfg;
  bad.resolution_m = 0.5;
  ck_assert_int_eq(estimate_create(&r.obj.mesh, kBase, &bad, &est), ESTIMATE_E_ARG);
  bad = cfg;
  bad.policy = (qlearn_policy_kind_t)99;
  ck_assert_int_eq(estimate_create(&r.obj.mesh, kBase, &bad, &est), ESTIMATE_E_ARG);
  bad = cfg;
  bad.max_added_dirs = 7;
  ck_assert_int_eq(estimate_create(&r.obj.mesh, kBase, &bad, &est), ESTIMATE_E_ARG);
  bad = cfg;
  bad.fall_steering = 2;
  ck_assert_int_eq(estimate_create(&r.obj.mesh, kBase, &bad, &est), ESTIMATE_E_ARG);
  ck_assert_int_eq(estimate_create(&r.obj.mesh, kBase, &cfg, &est), ESTIMATE_OK);
  estimate_trial_request_t req;
  const estimate_trial_reply_t zero = {0};
  ck_assert_int_eq(estimate_observe(est, &zero), ESTIMATE_E_STATE); /* nothing asked yet */
  ck_assert_int_eq(estimate_next(NULL, &req), ESTIMATE_E_ARG);
  ck_assert_int_eq(estimate_next(est, NULL), ESTIMATE_E_ARG);
  ck_assert_int_eq(estimate_observe(est, NULL), ESTIMATE_E_ARG);
  ck_assert_int_eq(estimate_next(est, &req), ESTIMATE_OK);
  ck_assert_int_eq(req.kind, ESTIMATE_TRIAL_STABLE); /* a face is confirmed first */
  ck_assert_ptr_null(estimate_result(NULL));
  ck_assert_int_eq(estimate_status(NULL), ESTIMATE_E_ARG);
  estimate_destroy(est);
  estimate_destroy(NULL);
  rock_close(&r);
}
END_TEST

/* An estimate in the caller's memory (estimate_init): too little is refused, enough works, and
 * the estimate equals one of estimate_create. */
START_TEST(caller_memory) {
  rock_t r;
  rock_open(&r, "rock_3_even");
  estimate_config_t cfg;
  estimate_config_default(&cfg);
  const size_t size = estimate_size(&r.obj.mesh);
  ck_assert_uint_gt(size, sizeof(estimate_result_t));
  ck_assert_uint_eq(estimate_size(NULL), 0);
  double *mem = malloc(size);
  ck_assert_ptr_nonnull(mem);
  estimate_t *est = NULL;
  ck_assert_int_eq(estimate_init(mem, size - 1, &r.obj.mesh, kBase, &cfg, &est), ESTIMATE_E_ARG);
  ck_assert_ptr_null(est);
  ck_assert_int_eq(estimate_init(mem, size, &r.obj.mesh, kBase, &cfg, &est), ESTIMATE_OK);
  ck_assert_ptr_eq((void *)est, (void *)mem);
  estimate_trial_request_t req;
  while (estimate_next(est, &req) == ESTIMATE_OK) {
    estimate_trial_reply_t rep;
    run_trial(&r, &req, &rep);
    ck_assert_int_eq(estimate_observe(est, &rep), ESTIMATE_OK);
  }
  ck_assert_int_eq(estimate_status(est), ESTIMATE_DONE);
  rock_close(&r);
  rock_open(&r, "rock_3_even");
  estimate_result_t *want = calloc(1, sizeof *want);
  ck_assert_ptr_nonnull(want);
  ck_assert_int_eq(estimate_run(&r.obj.mesh, &r.be, &cfg, want), ESTIMATE_OK);
  results_equal(estimate_result(est), want);
  free(want);
  free(mem); /* estimate_init's memory is the caller's: no estimate_destroy */
  rock_close(&r);
}
END_TEST

/* A failure ends the estimate for good: every later call gives the same error. */
START_TEST(failure_is_final) {
  model_mesh_t flat = {0};
  const double lo[3] = {-0.002, -0.002, -0.002}, hi[3] = {0.002, 0.002, 0.002}; /* faces < 1 cm^2 */
  ck_assert_int_eq(model_mesh_box(lo, hi, &flat), MODEL_OK);
  estimate_config_t cfg;
  estimate_config_default(&cfg);
  cfg.closed_patches = 0; /* flat faces only: none is usable (with closed patches it is) */
  cfg.rough_faces = 0;
  estimate_t *est = NULL;
  ck_assert_int_eq(estimate_create(&flat, kBase, &cfg, &est), ESTIMATE_OK);
  estimate_trial_request_t req;
  const estimate_status_t s = estimate_next(est, &req);
  ck_assert_int_eq(s, ESTIMATE_E_GEOMETRY);
  ck_assert_int_eq(estimate_next(est, &req), s);
  ck_assert_int_eq(estimate_status(est), s);
  const estimate_trial_reply_t zero = {0};
  ck_assert_int_eq(estimate_observe(est, &zero), s);
  ck_assert_str_ne(estimate_result(est)->msg, "");
  estimate_destroy(est);
  model_mesh_free(&flat);
}
END_TEST

int main(void) {
  Suite *s = suite_create("estimate_api");
  TCase *tc = tcase_create("loop");
  tcase_set_timeout(tc, 300);
  tcase_add_test(tc, caller_loop_matches_run);
  tcase_add_test(tc, bad_calls_refused);
  tcase_add_test(tc, caller_memory);
  tcase_add_test(tc, failure_is_final);
  suite_add_tcase(s, tc);
  SRunner *sr = srunner_create(s);
  srunner_run_all(sr, CK_NORMAL);
  const int failed = srunner_ntests_failed(sr);
  srunner_free(sr);
  return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
