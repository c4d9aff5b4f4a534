/* check_estimate_noalloc: after its first estimate_next (which finds the hull faces), lib/estimate
 * allocates nothing, whatever the trials: every malloc / calloc / realloc that the estimator and
 * lib/model's geometry make is counted (this executable links with --wrap for them, which reaches
 * every reference in the project's static archives) while estimate_next and estimate_observe run.
 * The trials themselves (lib/balance, ODE) are not counted: they are the caller's. */
#include <check.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "comlearn/estimate.h"
#include "estimate_backend.h"
#include "estimate_direct.h"

#include "alloc_count.h"

static void run_rock(const char *name, double noise_m) {
  char urdf[512];
  snprintf(urdf, sizeof urdf, "%s/rocks/%s.urdf", COMLEARN_ASSETS_DIR, name);
  model_object_t obj = {0};
  model_error_t merr = {{0}};
  ck_assert_int_eq(model_object_load(urdf, NULL, &obj, &merr), MODEL_OK);
  estimate_direct_t *d = NULL;
  estimate_backend_t be;
  char err[256];
  ck_assert_int_eq(estimate_direct_open(urdf, NULL, NULL, &d, &be, err, sizeof err), 0);
  estimate_config_t cfg;
  estimate_config_default(&cfg);
  if (noise_m > 0.0) {
    ck_assert_int_eq(estimate_direct_set_noise(d, 3, noise_m, noise_m), 0);
    cfg.noise_sigma_m = noise_m;
    cfg.policy = QLEARN_POLICY_PAPER_QTABLE; /* a walk, then the PBA handover */
  }
  estimate_t *est = NULL;
  ck_assert_int_eq(estimate_create(&obj.mesh, be.base_size_m, &cfg, &est), ESTIMATE_OK);
  estimate_trial_request_t req;
  ck_assert_int_eq(estimate_next(est, &req), ESTIMATE_OK); /* plans: allocates (the hull) */
  size_t trials = 0;
  estimate_status_t s = ESTIMATE_OK;
  allocations = 0;
  while (s == ESTIMATE_OK) {
    estimate_trial_reply_t rep;
    ck_assert_int_eq(be.run(be.ctx, &req, &rep, err, sizeof err), 0);
    counting = 1;
    const estimate_status_t so = estimate_observe(est, &rep);
    s = so == ESTIMATE_OK ? estimate_next(est, &req) : so;
    counting = 0;
    ++trials;
  }
  ck_assert_int_eq(s, ESTIMATE_DONE);
  ck_assert_uint_gt(trials, 10);
  ck_assert_msg(allocations == 0, "%s: %zu allocations in %zu trials", name, allocations, trials);
  estimate_destroy(est);
  estimate_direct_close(d);
  model_object_free(&obj);
}

/* The wrap works: an allocation made while counting is counted (else the test above proves
 * nothing). */
START_TEST(wrap_counts) {
  allocations = 0;
  counting = 1;
  void *volatile p = malloc(16); /* volatile: the compiler may not drop the pair */
  counting = 0;
  ck_assert_uint_eq(allocations, 1);
  free(p);
}
END_TEST

START_TEST(no_allocation_per_trial) {
  run_rock("rock_1_uneven", 0.0);
  run_rock("rock_3_even", 0.0);
  run_rock("rock_2_uneven", 1e-3);
}
END_TEST

int main(void) {
  Suite *s = suite_create("estimate_noalloc");
  TCase *tc = tcase_create("trials");
  tcase_set_timeout(tc, 300);
  tcase_add_test(tc, wrap_counts);
  tcase_add_test(tc, no_allocation_per_trial);
  suite_add_tcase(s, tc);
  SRunner *sr = srunner_create(s);
  srunner_run_all(sr, CK_NORMAL);
  const int failed = srunner_ntests_failed(sr);
  srunner_free(sr);
  return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
