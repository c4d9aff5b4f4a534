/* bisect and PBA through the one policy interface (qlearn_policy_*), against synthetic oracles:
 * a noiseless threshold, a fixed flip probability and a probit (placement noise) oracle. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "comlearn/qlearn.h"
#include "qlearn_suites.h"

#include "test_rng.h"

typedef enum { ORACLE_EXACT, ORACLE_FLIP, ORACLE_PROBIT } oracle_kind_t;

/* STAYS when c < x (ties: STAYS); FLIP inverts with probability p; PROBIT compares c with the
 * placement actually achieved, x + N(0, sigma), i.e. P(TIPS) = Phi((c - x) / sigma). */
static qlearn_outcome_t oracle(oracle_kind_t kind, double c, double x, double p_or_sigma,
                               rng_t *r) {
  if (kind == ORACLE_PROBIT) x += p_or_sigma * rng_normal(r);
  qlearn_outcome_t o = c > x ? QLEARN_TIPS : QLEARN_STAYS;
  if (kind == ORACLE_FLIP && rng_uniform(r) < p_or_sigma) {
    o = o == QLEARN_TIPS ? QLEARN_STAYS : QLEARN_TIPS;
  }
  return o;
}

/* Run one search to the end; returns the trials used, -1 on an unexpected status. */
static int run_search(qlearn_policy_t *pol, oracle_kind_t kind, double c, double noise, rng_t *r) {
  for (int i = 0; i < QLEARN_MAX_TRIALS + 1; ++i) {
    double x = 0.0;
    qlearn_status_t st = qlearn_policy_next(pol, &x);
    if (st == QLEARN_E_DONE) return (int)pol->trials;
    if (st != QLEARN_OK) return -1;
    st = qlearn_policy_observe(pol, x, oracle(kind, c, x, noise, r));
    if (st != QLEARN_OK) return -1;
  }
  return -1;
}

/* The gallop's first step as docs/learner.md defines it: s0 = resolution * 2^k, the largest with
 * s0 <= range / 64, at least the resolution. */
static double bisect_s0(double range, double res) {
  double k = floor(log2(range / (64.0 * res)));
  return res * pow(2.0, fmax(0.0, k));
}

/* The bound of docs/learner.md: the prior, at most M = floor(log2(range / s0 + 1)) gallop steps
 * (an offset (2^M - 1) s0 beyond the range cannot be placed), then halving a bracket narrower than
 * the range. */
static int bisect_bound(double range, double res) {
  double s0 = bisect_s0(range, res);
  return 1 + (int)floor(log2(range / s0 + 1.0)) + (int)ceil(log2(range / res));
}

START_TEST(test_bisect_bound_and_accuracy) {
  /* Bound: 1 + floor(log2(100 / 0.8 + 1)) + ceil(log2(1000)) = 1 + 6 + 10 = 17 for the defaults
   * (s0 = 0.8 mm). */
  qlearn_policy_config_t cfg;
  qlearn_policy_config_default(QLEARN_POLICY_BISECT, &cfg);
  const double range = cfg.range_hi_m - cfg.range_lo_m;
  ck_assert_double_eq_tol(bisect_s0(range, cfg.resolution_m), 8e-4, 1e-12);
  const int bound = bisect_bound(range, cfg.resolution_m);
  ck_assert_int_eq(bound, 17);
  rng_t r = {42};
  int worst = 0;
  for (int run = 0; run < 4000; ++run) {
    double c = cfg.range_lo_m + range * rng_uniform(&r);
    if (run == 0) c = cfg.range_lo_m;
    if (run == 1) c = cfg.range_hi_m;
    qlearn_policy_config_t k = cfg;
    /* priors: the box center, a random point, a bound, close to c (a good mesh CoM) */
    switch (run % 4) {
      case 0: k.prior_m = 0.0; break;
      case 1: k.prior_m = cfg.range_lo_m + range * rng_uniform(&r); break;
      case 2: k.prior_m = (run / 4) % 2 ? cfg.range_lo_m : cfg.range_hi_m; break;
      default: k.prior_m = fmin(cfg.range_hi_m, fmax(cfg.range_lo_m, c + 0.002 * rng_normal(&r)));
    }
    qlearn_policy_t pol;
    ck_assert_int_eq(qlearn_policy_init(&pol, &k), QLEARN_OK);
    int n = run_search(&pol, ORACLE_EXACT, c, 0.0, &r);
    ck_assert_int_ge(n, 1);
    ck_assert_int_le(n, bound);
    if (n > worst) worst = n;
    double est = 0.0;
    double hw = 0.0;
    ck_assert_int_eq(qlearn_policy_estimate(&pol, &est, &hw), QLEARN_OK);
    ck_assert(2.0 * hw <= k.resolution_m * (1.0 + 1e-9));
    ck_assert(fabs(c - est) <= hw + 1e-15);
  }
  ck_assert_int_le(worst, bound);
}
END_TEST

START_TEST(test_bisect_close_prior_is_cheap) {
  /* c at distance d from the prior, (2^(m-1) - 1) s0 < d <= (2^m - 1) s0: the prior, m gallop
   * steps, then halving a bracket 2^(m-1) s0 wide, 2m + log2(s0 / resolution) trials in all:
   * 5 within s0 = 0.8 mm, 7 within 2.4 mm, 9 within 5.6 mm, 11 within 12 mm (the old single
   * probe of 3.2 mm: 7 within 3.2 mm, up to 12 beyond). */
  qlearn_policy_config_t cfg;
  qlearn_policy_config_default(QLEARN_POLICY_BISECT, &cfg);
  const double s0 = 8e-4;
  rng_t r = {7};
  int at_most[4] = {0, 0, 0, 0};
  for (int run = 0; run < 2000; ++run) {
    int m = 1 + run % 4;
    double d_hi = (pow(2.0, m) - 1.0) * s0;
    double d_lo = (pow(2.0, m - 1) - 1.0) * s0;
    double d = d_lo + (d_hi - d_lo) * rng_uniform(&r);
    double c = 0.02 + (run % 8 < 4 ? d : -d);
    cfg.prior_m = 0.02;
    qlearn_policy_t pol;
    ck_assert_int_eq(qlearn_policy_init(&pol, &cfg), QLEARN_OK);
    int n = run_search(&pol, ORACLE_EXACT, c, 0.0, &r);
    ck_assert_int_le(n, 2 * m + 3);
    if (n > at_most[m - 1]) at_most[m - 1] = n;
    double est = 0.0;
    double hw = 0.0;
    ck_assert_int_eq(qlearn_policy_estimate(&pol, &est, &hw), QLEARN_OK);
    ck_assert(fabs(c - est) <= hw + 1e-15 && 2.0 * hw <= cfg.resolution_m * (1.0 + 1e-9));
  }
  /* the count is reached, not just bounded: each band's slowest run needs all of it */
  for (int m = 1; m <= 4; ++m) ck_assert_int_eq(at_most[m - 1], 2 * m + 3);
}
END_TEST

START_TEST(test_bisect_other_resolutions) {
  /* The bound for other ranges and resolutions, thresholds anywhere in the range. */
  const double res[] = {1e-5, 3e-5, 1e-4, 7e-4, 1e-3, 0.05};
  rng_t r = {99};
  for (size_t i = 0; i < sizeof res / sizeof res[0]; ++i) {
    qlearn_policy_config_t cfg;
    qlearn_policy_config_default(QLEARN_POLICY_BISECT, &cfg);
    cfg.range_lo_m = -0.03;
    cfg.range_hi_m = 0.07;
    cfg.resolution_m = res[i];
    int bound = bisect_bound(0.1, res[i]);
    for (int run = 0; run < 500; ++run) {
      double c = -0.03 + 0.1 * rng_uniform(&r);
      cfg.prior_m = -0.03 + 0.1 * rng_uniform(&r);
      qlearn_policy_t pol;
      ck_assert_int_eq(qlearn_policy_init(&pol, &cfg), QLEARN_OK);
      int n = run_search(&pol, ORACLE_EXACT, c, 0.0, &r);
      ck_assert_int_ge(n, 1);
      ck_assert_int_le(n, bound);
      double est = 0.0;
      double hw = 0.0;
      ck_assert_int_eq(qlearn_policy_estimate(&pol, &est, &hw), QLEARN_OK);
      ck_assert(fabs(c - est) <= hw + 1e-15 && 2.0 * hw <= res[i] * (1.0 + 1e-9));
    }
  }
}
END_TEST

/* Coverage of PBA's credible interval over 1000 seeded runs; returns the runs covered. */
static int pba_coverage(qlearn_policy_config_t cfg, oracle_kind_t kind, double noise,
                        double *mean_trials) {
  rng_t r = {2024};
  int covered = 0;
  long trials = 0;
  for (int run = 0; run < 1000; ++run) {
    double c = -0.049 + 0.098 * rng_uniform(&r);
    qlearn_policy_t pol;
    ck_assert_int_eq(qlearn_policy_init(&pol, &cfg), QLEARN_OK);
    int n = run_search(&pol, kind, c, noise, &r);
    ck_assert_int_ge(n, 1);
    trials += n;
    double est = 0.0;
    double hw = 0.0;
    ck_assert_int_eq(qlearn_policy_estimate(&pol, &est, &hw), QLEARN_OK);
    if (fabs(c - est) <= hw) covered++;
  }
  *mean_trials = (double)trials / 1000.0;
  return covered;
}

START_TEST(test_pba_flip_coverage) {
  qlearn_policy_config_t cfg;
  qlearn_policy_config_default(QLEARN_POLICY_PBA, &cfg);
  cfg.noise = QLEARN_NOISE_FLIP;
  cfg.flip_prob = 0.1;
  cfg.resolution_m = 2e-4;
  double mean = 0.0;
  int covered = pba_coverage(cfg, ORACLE_FLIP, 0.1, &mean);
  fprintf(stderr, "pba flip 0.1: 95 %% interval covers the truth in %d / 1000, %.1f trials\n",
          covered, mean);
  ck_assert_int_ge(covered, 900);
}
END_TEST

START_TEST(test_pba_probit_coverage) {
  qlearn_policy_config_t cfg;
  qlearn_policy_config_default(QLEARN_POLICY_PBA, &cfg);
  cfg.noise = QLEARN_NOISE_PROBIT;
  cfg.sigma_m = 5e-4;
  cfg.resolution_m = 1e-3;
  double mean = 0.0;
  int covered = pba_coverage(cfg, ORACLE_PROBIT, 5e-4, &mean);
  fprintf(stderr, "pba probit 0.5 mm: 95 %% interval covers the truth in %d / 1000, %.1f trials\n",
          covered, mean);
  ck_assert_int_ge(covered, 900);
}
END_TEST

START_TEST(test_pba_noiseless_resolution) {
  /* sigma 0: the step likelihood; the interval reaches 0.1 mm (about two bins). */
  qlearn_policy_config_t cfg;
  qlearn_policy_config_default(QLEARN_POLICY_PBA, &cfg);
  cfg.sigma_m = 0.0;
  rng_t r = {5};
  for (int run = 0; run < 200; ++run) {
    double c = -0.05 + 0.1 * rng_uniform(&r);
    qlearn_policy_t pol;
    ck_assert_int_eq(qlearn_policy_init(&pol, &cfg), QLEARN_OK);
    int n = run_search(&pol, ORACLE_EXACT, c, 0.0, &r);
    ck_assert_int_ge(n, 1);
    ck_assert_int_le(n, 16);
    double est = 0.0;
    double hw = 0.0;
    ck_assert_int_eq(qlearn_policy_estimate(&pol, &est, &hw), QLEARN_OK);
    ck_assert(hw <= cfg.resolution_m);
    ck_assert(fabs(c - est) <= hw);
  }
}
END_TEST

START_TEST(test_pba_wide_range_zooms) {
  /* The default probit model (sigma = resolution = 0.1 mm, as the estimator's noiseless PBA runs)
   * on a 14 cm range: its bins are 68 um, more than half the resolution, and on the range's own
   * grid the 95 % interval stalls near 0.12 mm and the search runs to max_trials. The zoom
   * regrids onto the mass and the interval reaches the resolution. */
  qlearn_policy_config_t cfg;
  qlearn_policy_config_default(QLEARN_POLICY_PBA, &cfg);
  cfg.range_lo_m = -0.07;
  cfg.range_hi_m = 0.07;
  cfg.prior_m = 0.0;
  const double w = (cfg.range_hi_m - cfg.range_lo_m) / (double)QLEARN_PBA_BINS;
  rng_t r = {17};
  int most = 0, covered = 0;
  for (int run = 0; run < 300; ++run) {
    /* the first 100 truths on a bin boundary of the range's grid (the centre first) */
    double c = run < 100 ? w * (double)(run % 2 == 0 ? run / 2 : -(run + 1) / 2 * 7)
                         : -0.069 + 0.138 * rng_uniform(&r);
    qlearn_policy_t pol;
    ck_assert_int_eq(qlearn_policy_init(&pol, &cfg), QLEARN_OK);
    int n = run_search(&pol, ORACLE_EXACT, c, 0.0, &r);
    ck_assert_int_ge(n, 1);
    if (n > most) most = n;
    double est = 0.0;
    double hw = 0.0;
    ck_assert_int_eq(qlearn_policy_estimate(&pol, &est, &hw), QLEARN_OK);
    ck_assert_msg(hw <= cfg.resolution_m, "truth %.9f: half width %.9f after %d trials", c, hw, n);
    if (fabs(c - est) <= hw) covered++;
  }
  fprintf(stderr, "pba 14 cm range: at most %d trials, interval covers the truth in %d / 300\n",
          most, covered);
  ck_assert_int_le(most, 64);
  ck_assert_int_eq(covered, 300);
}
END_TEST

START_TEST(test_pba_stops_at_max_trials) {
  qlearn_policy_config_t cfg;
  qlearn_policy_config_default(QLEARN_POLICY_PBA, &cfg);
  cfg.sigma_m = 5e-3; /* too noisy for 0.1 mm in 20 trials */
  cfg.max_trials = 20;
  qlearn_policy_t pol;
  ck_assert_int_eq(qlearn_policy_init(&pol, &cfg), QLEARN_OK);
  rng_t r = {11};
  ck_assert_int_eq(run_search(&pol, ORACLE_PROBIT, 0.01, 5e-3, &r), 20);
  ck_assert(qlearn_policy_done(&pol));
  double x = 0.0;
  ck_assert_int_eq(qlearn_policy_next(&pol, &x), QLEARN_E_DONE);
}
END_TEST

/* Bad input through the interface: an error and the bytes of the state unchanged. */
static void check_bad_input(qlearn_policy_kind_t kind) {
  qlearn_policy_config_t cfg;
  qlearn_policy_config_default(kind, &cfg);
  qlearn_policy_t pol;
  memset(&pol, 0xA5, sizeof pol);
  qlearn_policy_t copy;
  memcpy(&copy, &pol, sizeof pol);
  const double bad_res[] = {0.0, -1e-4, 0.2, NAN, INFINITY};
  for (size_t i = 0; i < sizeof bad_res / sizeof bad_res[0]; ++i) {
    qlearn_policy_config_t k = cfg;
    k.resolution_m = bad_res[i];
    qlearn_status_t st = qlearn_policy_init(&pol, &k);
    ck_assert_int_eq(st, isfinite(bad_res[i]) ? QLEARN_E_RANGE : QLEARN_E_NONFINITE);
    ck_assert(memcmp(&pol, &copy, sizeof pol) == 0);
  }
  qlearn_policy_config_t k = cfg;
  k.prior_m = 0.06;
  ck_assert_int_eq(qlearn_policy_init(&pol, &k), QLEARN_E_RANGE);
  k = cfg;
  k.max_trials = QLEARN_MAX_TRIALS + 1;
  ck_assert_int_eq(qlearn_policy_init(&pol, &k), QLEARN_E_RANGE);
  ck_assert(memcmp(&pol, &copy, sizeof pol) == 0);
  /* The policy functions check their own arguments when called directly. */
  k = cfg;
  k.resolution_m = 0.0;
  if (kind == QLEARN_POLICY_BISECT) {
    ck_assert_int_eq(qlearn_bisect_init(&pol.u.bisect, &k), QLEARN_E_RANGE);
  } else {
    ck_assert_int_eq(qlearn_pba_init(&pol.u.pba, &k), QLEARN_E_RANGE);
  }
  ck_assert(memcmp(&pol, &copy, sizeof pol) == 0);

  cfg.max_trials = 3;
  ck_assert_int_eq(qlearn_policy_init(&pol, &cfg), QLEARN_OK);
  double x = 0.0;
  ck_assert_int_eq(qlearn_policy_next(&pol, &x), QLEARN_OK);
  ck_assert_int_eq(qlearn_policy_observe(&pol, x, QLEARN_TIPS), QLEARN_OK);
  memcpy(&copy, &pol, sizeof pol);
  const double bad_x[] = {NAN, INFINITY, -INFINITY};
  for (size_t i = 0; i < 3; ++i) {
    ck_assert_int_eq(qlearn_policy_observe(&pol, bad_x[i], QLEARN_STAYS), QLEARN_E_NONFINITE);
    ck_assert(memcmp(&pol, &copy, sizeof pol) == 0);
  }
  ck_assert_int_eq(qlearn_policy_observe(&pol, 0.051, QLEARN_STAYS), QLEARN_E_RANGE);
  ck_assert_int_eq(qlearn_policy_observe(&pol, 0.01, (qlearn_outcome_t)0), QLEARN_E_ARG);
  ck_assert_int_eq(qlearn_policy_observe(NULL, 0.01, QLEARN_STAYS), QLEARN_E_ARG);
  ck_assert_int_eq(qlearn_policy_next(&pol, NULL), QLEARN_E_ARG);
  ck_assert(memcmp(&pol, &copy, sizeof pol) == 0);
  if (kind == QLEARN_POLICY_BISECT) {
    /* TIPS at the prior 0 said c >= 0: STAYS at -0.01 contradicts it (noisy data). */
    ck_assert_int_eq(qlearn_policy_observe(&pol, -0.01, QLEARN_STAYS), QLEARN_E_RANGE);
    ck_assert(memcmp(&pol, &copy, sizeof pol) == 0);
  }
  /* Capacity: max_trials 3 reached before the search is done. */
  ck_assert_int_eq(qlearn_policy_next(&pol, &x), QLEARN_OK);
  ck_assert_int_eq(qlearn_policy_observe(&pol, x, QLEARN_STAYS), QLEARN_OK);
  ck_assert_int_eq(qlearn_policy_next(&pol, &x), QLEARN_OK);
  ck_assert_int_eq(qlearn_policy_observe(&pol, x, QLEARN_STAYS), QLEARN_OK);
  memcpy(&copy, &pol, sizeof pol);
  qlearn_status_t st = qlearn_policy_observe(&pol, 0.0, QLEARN_STAYS);
  /* bisect: capacity; PBA counts max_trials as done (its documented stop rule) */
  ck_assert_int_eq(st, kind == QLEARN_POLICY_BISECT ? QLEARN_E_CAPACITY : QLEARN_E_DONE);
  ck_assert(memcmp(&pol, &copy, sizeof pol) == 0);
}

START_TEST(test_bad_input_bisect) { check_bad_input(QLEARN_POLICY_BISECT); }
END_TEST

START_TEST(test_bad_input_pba) { check_bad_input(QLEARN_POLICY_PBA); }
END_TEST

START_TEST(test_next_after_done) {
  const qlearn_policy_kind_t kinds[] = {QLEARN_POLICY_BISECT, QLEARN_POLICY_PBA};
  for (size_t i = 0; i < 2; ++i) {
    qlearn_policy_config_t cfg;
    qlearn_policy_config_default(kinds[i], &cfg);
    cfg.sigma_m = 0.0;
    qlearn_policy_t pol;
    ck_assert_int_eq(qlearn_policy_init(&pol, &cfg), QLEARN_OK);
    rng_t r = {3};
    ck_assert_int_ge(run_search(&pol, ORACLE_EXACT, 0.0123, 0.0, &r), 1);
    ck_assert(qlearn_policy_done(&pol));
    qlearn_policy_t copy = pol;
    double x = 0.0;
    ck_assert_int_eq(qlearn_policy_next(&pol, &x), QLEARN_E_DONE);
    ck_assert_int_eq(qlearn_policy_observe(&pol, 0.0123, QLEARN_TIPS), QLEARN_E_DONE);
    ck_assert(memcmp(&pol, &copy, sizeof pol) == 0);
  }
}
END_TEST

START_TEST(test_state_sizes) {
  fprintf(stderr, "sizeof: qlearn_bisect_t %zu, qlearn_pba_t %zu, qlearn_policy_t %zu\n",
          sizeof(qlearn_bisect_t), sizeof(qlearn_pba_t), sizeof(qlearn_policy_t));
  ck_assert_uint_le(sizeof(qlearn_pba_t), 12u * 1024u);
}
END_TEST

Suite *qlearn_search_suite(void) {
  Suite *s = suite_create("qlearn_search");
  TCase *tc = tcase_create("bisect_pba");
  tcase_set_timeout(tc, 120);
  tcase_add_test(tc, test_bisect_bound_and_accuracy);
  tcase_add_test(tc, test_bisect_close_prior_is_cheap);
  tcase_add_test(tc, test_bisect_other_resolutions);
  tcase_add_test(tc, test_pba_flip_coverage);
  tcase_add_test(tc, test_pba_probit_coverage);
  tcase_add_test(tc, test_pba_noiseless_resolution);
  tcase_add_test(tc, test_pba_wide_range_zooms);
  tcase_add_test(tc, test_pba_stops_at_max_trials);
  tcase_add_test(tc, test_bad_input_bisect);
  tcase_add_test(tc, test_bad_input_pba);
  tcase_add_test(tc, test_next_after_done);
  tcase_add_test(tc, test_state_sizes);
  suite_add_tcase(s, tc);
  return s;
}
