/* The paper's Algorithm 1 (comlearn/qlearn_paper.h) against a noiseless threshold oracle:
 * outcome = STAYS iff c < x. Hand-traced sequences follow docs/learner.md. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "comlearn/math3d.h"
#include "comlearn/qlearn.h"
#include "comlearn/qlearn_paper.h"
#include "qlearn_suites.h"

static qlearn_outcome_t oracle(double c, double x) { return c < x ? QLEARN_STAYS : QLEARN_TIPS; }

static qlearn_policy_config_t paper_cfg(qlearn_policy_kind_t kind) {
  qlearn_policy_config_t cfg;
  qlearn_policy_config_default(kind, &cfg); /* +-5 cm, prior 0, resolution 0.1 mm, seed 1 */
  return cfg;
}

/* Run a whole search on qlearn_paper_*; the placements into xs (up to cap); the trial count. */
static int walk(qlearn_paper_t *p, const qlearn_policy_config_t *cfg, double c, double *xs,
                int cap) {
  ck_assert_int_eq(qlearn_paper_init(p, cfg), QLEARN_OK);
  int n = 0;
  while (!qlearn_paper_done(p, cfg) && n < QLEARN_MAX_TRIALS) {
    double x;
    ck_assert_int_eq(qlearn_paper_next(p, cfg, &x), QLEARN_OK);
    ck_assert(x >= cfg->range_lo_m && x <= cfg->range_hi_m);
    if (n < cap) xs[n] = x;
    ck_assert_int_eq(qlearn_paper_observe(p, cfg, x, oracle(c, x)), QLEARN_OK);
    n++;
  }
  return n;
}

static void expect_sequence(qlearn_policy_kind_t kind, double c, const double *want_mm, int nwant,
                            double est_mm) {
  static qlearn_paper_t p;
  const qlearn_policy_config_t cfg = paper_cfg(kind);
  double xs[64];
  const int n = walk(&p, &cfg, c, xs, 64);
  ck_assert_int_eq(n, nwant);
  for (int i = 0; i < n; i++) {
    ck_assert_msg(fabs(xs[i] * 1e3 - want_mm[i]) < 1e-9,
                  "kind %d c %g trial %d: x %.6f mm, want %.6f", (int)kind, c, i, xs[i] * 1e3,
                  want_mm[i]);
  }
  double e, h, xn;
  ck_assert_int_eq(qlearn_paper_estimate(&p, &cfg, &e, &h), QLEARN_OK);
  ck_assert_double_eq_tol(e * 1e3, est_mm, 1e-9);
  ck_assert_double_eq_tol(h * 1e3, 0.05, 1e-9);
  ck_assert_int_eq(qlearn_paper_next(&p, &cfg, &xn), QLEARN_E_DONE);
}

/* c = 23.47 mm: 1 cm steps 0 T, 10 T, 20 T, 30 S (flip) -> back to 20; 1 mm steps 21 T, 22 T,
 * 23 T, 24 S (flip) -> back to 23; 0.1 mm steps 23.1 .. 23.4 T, 23.5 S: the 0.1 mm step brackets
 * the flip; estimate 23.45 +- 0.05 mm; 13 trials. */
static const double seq_pos_mm[] = {0, 10, 20, 30, 21, 22, 23, 24, 23.1, 23.2, 23.3, 23.4, 23.5};
/* c = -7.03 mm: 0 S, -10 T (flip) -> back to 0; -1 .. -7 S, -8 T (flip) -> back to -7; -7.1 T
 * (flip at 0.1 mm): estimate -7.05 +- 0.05 mm; 11 trials. */
static const double seq_neg_mm[] = {0, -10, -1, -2, -3, -4, -5, -6, -7, -8, -7.1};
/* c = 0.04 mm, next to the prior: 0 T, 10 S (flip) -> back to 0; 1 S (flip) -> back to 0;
 * 0.1 S (flip): estimate 0.05 +- 0.05 mm; 4 trials (the fewest possible). */
static const double seq_zero_mm[] = {0, 10, 1, 0.1};
/* c = 49.93 mm, the far end: 0 .. 40 T, 50 S; 41 .. 49 T, 50 S; 49.1 .. 49.9 T, 50 S
 * (placed again: the walk does not skip known states); 26 trials (the most possible). */
static const double seq_far_mm[] = {0,    10,   20,   30,   40,   50,   41,   42,   43,
                                    44,   45,   46,   47,   48,   49,   50,   49.1, 49.2,
                                    49.3, 49.4, 49.5, 49.6, 49.7, 49.8, 49.9, 50};

START_TEST(qtable_matches_hand_traced_sequences) {
  expect_sequence(QLEARN_POLICY_PAPER_QTABLE, 23.47e-3, seq_pos_mm, 13, 23.45);
  expect_sequence(QLEARN_POLICY_PAPER_QTABLE, -7.03e-3, seq_neg_mm, 11, -7.05);
  expect_sequence(QLEARN_POLICY_PAPER_QTABLE, 0.04e-3, seq_zero_mm, 4, 0.05);
  expect_sequence(QLEARN_POLICY_PAPER_QTABLE, 49.93e-3, seq_far_mm, 26, 49.95);
}
END_TEST

START_TEST(mlp_matches_hand_traced_sequences) {
  /* With seed 1 the refit network's argmax reproduces the rewarded action at every state the
   * walk asks about, so it walks exactly as the table does. */
  expect_sequence(QLEARN_POLICY_PAPER_MLP, 23.47e-3, seq_pos_mm, 13, 23.45);
  expect_sequence(QLEARN_POLICY_PAPER_MLP, -7.03e-3, seq_neg_mm, 11, -7.05);
  expect_sequence(QLEARN_POLICY_PAPER_MLP, 0.04e-3, seq_zero_mm, 4, 0.05);
  expect_sequence(QLEARN_POLICY_PAPER_MLP, 49.93e-3, seq_far_mm, 26, 49.95);
}
END_TEST

/* Trial count of the table walk from prior 0 (docs/learner.md): with d = |c| / resolution,
 * ceil(d/100) + 1 placements at 1 cm, ceil(d/10) - 10 floor(d/100) at 1 mm, ceil(d) -
 * 10 floor(d/10) at 0.1 mm. */
static int expected_trials(double c, double res) {
  const double d = fabs(c) / res;
  return (int)(ceil(d / 100.0) + 1.0 + ceil(d / 10.0) - 10.0 * floor(d / 100.0) + ceil(d) -
               10.0 * floor(d / 10.0));
}

static void many_thresholds(qlearn_policy_kind_t kind, int count) {
  static qlearn_paper_t p;
  const qlearn_policy_config_t cfg = paper_cfg(kind);
  uint64_t s = 2019;
  int same_as_table = 0;
  for (int i = 0; i < count; i++) {
    const double c = -0.05 + 0.1 * cl_rng_uniform(&s);
    const int n = walk(&p, &cfg, c, NULL, 0);
    ck_assert(qlearn_paper_done(&p, &cfg));
    double e, h;
    ck_assert_int_eq(qlearn_paper_estimate(&p, &cfg, &e, &h), QLEARN_OK);
    ck_assert_msg(e - h <= c && c <= e + h, "c %.6f mm not in [%.6f, %.6f]", c * 1e3, (e - h) * 1e3,
                  (e + h) * 1e3);
    ck_assert_double_le_tol(2.0 * h, cfg.resolution_m, 1e-12);
    ck_assert_double_ge(2.0 * h, cfg.resolution_m - 1e-12); /* adjacent 0.1 mm placements */
    if (kind == QLEARN_POLICY_PAPER_QTABLE) {
      ck_assert_int_eq(n, expected_trials(c, cfg.resolution_m));
    } else {
      ck_assert_int_le(n, 60);
      same_as_table += n == expected_trials(c, cfg.resolution_m);
    }
  }
  /* With too few epochs the MLP's argmax can send the walk a step the wrong way (it comes back,
   * a trial or two later); with 100 epochs and seed 1 it follows the table on every threshold. */
  if (kind == QLEARN_POLICY_PAPER_MLP) ck_assert_int_eq(same_as_table, count);
}

START_TEST(qtable_finds_200_thresholds) { many_thresholds(QLEARN_POLICY_PAPER_QTABLE, 200); }
END_TEST

START_TEST(mlp_finds_200_thresholds) { many_thresholds(QLEARN_POLICY_PAPER_MLP, 200); }
END_TEST

START_TEST(offset_prior_clamps_to_the_range) {
  /* Prior 3 mm: the 1 cm walk toward c = 49.01 mm would go to 53 mm; it is clamped to 50 mm. */
  static qlearn_paper_t p;
  qlearn_policy_config_t cfg = paper_cfg(QLEARN_POLICY_PAPER_QTABLE);
  cfg.prior_m = 3e-3;
  double xs[64];
  const int n = walk(&p, &cfg, 49.01e-3, xs, 64);
  const double want_mm[] = {3, 13, 23, 33, 43, 50, 44, 45, 46, 47, 48, 49, 50, 49.1};
  ck_assert_int_eq(n, 14);
  for (int i = 0; i < n; i++) ck_assert_double_eq_tol(xs[i] * 1e3, want_mm[i], 1e-9);
  double e, h;
  ck_assert_int_eq(qlearn_paper_estimate(&p, &cfg, &e, &h), QLEARN_OK);
  ck_assert_double_eq_tol(e * 1e3, 49.05, 1e-9);
}
END_TEST

/* A prior off the grid of the range bounds (e.g. a mesh CoM): the grid x = prior + k res then
 * stops short of range_lo / range_hi by up to a resolution. A c in that strip, inside the range,
 * must still be bracketed (bench_qlearn, mesh-CoM rows: 2 of 1000 runs came back QLEARN_E_RANGE).
 */
static void check_bracket(qlearn_policy_kind_t kind, const qlearn_policy_config_t *cfg, double c) {
  static qlearn_paper_t p;
  const int n = walk(&p, cfg, c, NULL, 0);
  ck_assert_msg(qlearn_paper_done(&p, cfg), "kind %d c %.17g prior %.17g: not done after %d",
                (int)kind, c, cfg->prior_m, n);
  double e, h;
  const qlearn_status_t st = qlearn_paper_estimate(&p, cfg, &e, &h);
  ck_assert_msg(st == QLEARN_OK, "kind %d c %.17g prior %.17g: status %d (c is in the range)",
                (int)kind, c, cfg->prior_m, (int)st);
  ck_assert_msg(fabs(e - c) <= h, "kind %d c %.17g prior %.17g: not in [%.17g, %.17g]", (int)kind,
                c, cfg->prior_m, e - h, e + h);
  ck_assert_msg(2.0 * h <= cfg->resolution_m * (1.0 + 1e-9),
                "kind %d c %.17g prior %.17g: "
                "width %.17g",
                (int)kind, c, cfg->prior_m, 2.0 * h);
  ck_assert_int_le(n, 3 * 11); /* at most 11 placements per level */
}

static double unit(uint64_t *s) { return cl_rng_uniform(s); }

static void off_grid_priors(qlearn_policy_kind_t kind, int count) {
  /* The two bench_qlearn cases, exactly. */
  qlearn_policy_config_t cfg = paper_cfg(kind);
  cfg.prior_m = 0.046841811541620662;
  check_bracket(kind, &cfg, 0.049992193484443628);
  cfg.prior_m = -0.049212188688643847;
  check_bracket(kind, &cfg, -0.049951391291328223);
  /* Seeded (c, prior) pairs on three ranges / resolutions; c uniform over the range, or in the
   * last resolution before a bound; prior = c + U(-4, 4) mm (clamped), or uniform. */
  const double ranges[3][3] = {{-0.05, 0.05, 1e-4}, {-0.037, 0.061, 3e-4}, {-0.02, 0.013, 7e-5}};
  uint64_t s = 20190;
  for (int r = 0; r < 3; r++) {
    cfg = paper_cfg(kind);
    cfg.range_lo_m = ranges[r][0];
    cfg.range_hi_m = ranges[r][1];
    cfg.resolution_m = ranges[r][2];
    const double span = cfg.range_hi_m - cfg.range_lo_m;
    for (int i = 0; i < count; i++) {
      double c;
      switch (i % 3) {
        case 0: c = cfg.range_lo_m + span * unit(&s); break;
        case 1: c = cfg.range_hi_m - cfg.resolution_m * unit(&s); break;
        default: c = cfg.range_lo_m + cfg.resolution_m * unit(&s); break;
      }
      if (!(c > cfg.range_lo_m && c < cfg.range_hi_m)) continue;
      const double prior =
          (i % 2) ? c + 0.008 * (unit(&s) - 0.5) : cfg.range_lo_m + span * unit(&s);
      cfg.prior_m = fmin(cfg.range_hi_m, fmax(cfg.range_lo_m, prior));
      check_bracket(kind, &cfg, c);
    }
  }
}

START_TEST(qtable_brackets_c_from_off_grid_priors) {
  off_grid_priors(QLEARN_POLICY_PAPER_QTABLE, 1500);
}
END_TEST

START_TEST(mlp_brackets_c_from_off_grid_priors) { off_grid_priors(QLEARN_POLICY_PAPER_MLP, 100); }
END_TEST

START_TEST(threshold_outside_the_range_is_reported) {
  static qlearn_paper_t p;
  const qlearn_policy_config_t cfg = paper_cfg(QLEARN_POLICY_PAPER_QTABLE);
  double xs[64];
  const int n = walk(&p, &cfg, 0.07, xs, 64); /* TIPS everywhere: 0, 10, .., 50, then stuck */
  ck_assert_int_eq(n, 6);
  ck_assert(qlearn_paper_done(&p, &cfg));
  double e, h;
  ck_assert_int_eq(qlearn_paper_estimate(&p, &cfg, &e, &h), QLEARN_E_RANGE);
}
END_TEST

START_TEST(estimate_before_the_end_is_what_outcomes_leave) {
  static qlearn_paper_t p;
  const qlearn_policy_config_t cfg = paper_cfg(QLEARN_POLICY_PAPER_QTABLE);
  ck_assert_int_eq(qlearn_paper_init(&p, &cfg), QLEARN_OK);
  double e, h;
  ck_assert_int_eq(qlearn_paper_estimate(&p, &cfg, &e, &h), QLEARN_OK);
  ck_assert_double_eq_tol(e, 0.0, 1e-15);
  ck_assert_double_eq_tol(h, 0.05, 1e-15);
  ck_assert_int_eq(qlearn_paper_observe(&p, &cfg, 0.0, QLEARN_TIPS), QLEARN_OK);
  ck_assert_int_eq(qlearn_paper_estimate(&p, &cfg, &e, &h), QLEARN_OK);
  ck_assert_double_eq_tol(e, 0.025, 1e-15); /* [0, 5 cm] */
  double q[2];
  ck_assert_int_eq(qlearn_paper_q(&p, &cfg, 0.0, q), QLEARN_OK);
  ck_assert(q[QLEARN_PAPER_IN] == QLEARN_PAPER_R && q[QLEARN_PAPER_OUT] == 1.0 - QLEARN_PAPER_R);
  ck_assert_int_eq(qlearn_paper_observe(&p, &cfg, 0.01, QLEARN_STAYS), QLEARN_OK); /* flip */
  ck_assert_int_eq(qlearn_paper_estimate(&p, &cfg, &e, &h), QLEARN_OK);
  ck_assert_double_eq_tol(e, 0.005, 1e-15);
  ck_assert_double_eq_tol(h, 0.005, 1e-15);
  ck_assert_int_eq(qlearn_paper_q(&p, &cfg, 0.01, q), QLEARN_OK);
  ck_assert(q[QLEARN_PAPER_OUT] == QLEARN_PAPER_R);
  double x;
  ck_assert_int_eq(qlearn_paper_next(&p, &cfg, &x), QLEARN_OK);
  ck_assert_double_eq_tol(x, 0.001, 1e-15); /* stepped back to 0, then +1 mm */
}
END_TEST

START_TEST(bad_input_leaves_state_unchanged) {
  static qlearn_paper_t p, before;
  for (int kind = QLEARN_POLICY_PAPER_QTABLE; kind <= QLEARN_POLICY_PAPER_MLP; kind++) {
    qlearn_policy_config_t cfg = paper_cfg((qlearn_policy_kind_t)kind);
    cfg.max_trials = 5;
    ck_assert_int_eq(qlearn_paper_init(&p, &cfg), QLEARN_OK);
    ck_assert_int_eq(qlearn_paper_observe(&p, &cfg, 0.0, QLEARN_TIPS), QLEARN_OK);
    memcpy(&before, &p, sizeof p);
    ck_assert_int_eq(qlearn_paper_observe(&p, &cfg, NAN, QLEARN_TIPS), QLEARN_E_NONFINITE);
    ck_assert_int_eq(qlearn_paper_observe(&p, &cfg, INFINITY, QLEARN_TIPS), QLEARN_E_NONFINITE);
    ck_assert_int_eq(qlearn_paper_observe(&p, &cfg, 0.06, QLEARN_TIPS), QLEARN_E_RANGE);
    ck_assert_int_eq(qlearn_paper_observe(&p, &cfg, 0.01, (qlearn_outcome_t)0), QLEARN_E_ARG);
    ck_assert_int_eq(qlearn_paper_observe(NULL, &cfg, 0.01, QLEARN_TIPS), QLEARN_E_ARG);
    ck_assert_int_eq(memcmp(&before, &p, sizeof p), 0);
    /* Capacity: max_trials = 5 while c = 23.47 mm needs 13. */
    for (int i = 1; i < 5; i++) {
      double x;
      ck_assert_int_eq(qlearn_paper_next(&p, &cfg, &x), QLEARN_OK);
      ck_assert_int_eq(qlearn_paper_observe(&p, &cfg, x, oracle(23.47e-3, x)), QLEARN_OK);
    }
    memcpy(&before, &p, sizeof p);
    double x;
    ck_assert_int_eq(qlearn_paper_next(&p, &cfg, &x), QLEARN_OK);
    ck_assert_int_eq(qlearn_paper_observe(&p, &cfg, x, oracle(23.47e-3, x)), QLEARN_E_CAPACITY);
    ck_assert_int_eq(memcmp(&before, &p, sizeof p), 0);
    /* A wrong kind or config. */
    qlearn_policy_config_t bad = cfg;
    bad.kind = QLEARN_POLICY_BISECT;
    ck_assert_int_eq(qlearn_paper_init(&p, &bad), QLEARN_E_ARG);
    bad = cfg;
    bad.resolution_m = 0.0;
    ck_assert_int_eq(qlearn_paper_init(&p, &bad), QLEARN_E_RANGE);
    bad = cfg;
    bad.prior_m = NAN;
    ck_assert_int_eq(qlearn_paper_init(&p, &bad), QLEARN_E_NONFINITE);
    ck_assert_int_eq(memcmp(&before, &p, sizeof p), 0);
  }
  /* After the end: QLEARN_E_DONE, unchanged. */
  const qlearn_policy_config_t cfg = paper_cfg(QLEARN_POLICY_PAPER_QTABLE);
  (void)walk(&p, &cfg, 0.04e-3, NULL, 0);
  memcpy(&before, &p, sizeof p);
  ck_assert_int_eq(qlearn_paper_observe(&p, &cfg, 0.0, QLEARN_TIPS), QLEARN_E_DONE);
  ck_assert_int_eq(memcmp(&before, &p, sizeof p), 0);
}
END_TEST

START_TEST(through_the_policy_interface) {
  static qlearn_policy_t pol;
  for (int kind = QLEARN_POLICY_PAPER_QTABLE; kind <= QLEARN_POLICY_PAPER_MLP; kind++) {
    const qlearn_policy_config_t cfg = paper_cfg((qlearn_policy_kind_t)kind);
    ck_assert_int_eq(qlearn_policy_init(&pol, &cfg), QLEARN_OK);
    int n = 0;
    while (!qlearn_policy_done(&pol) && n < 64) {
      double x;
      ck_assert_int_eq(qlearn_policy_next(&pol, &x), QLEARN_OK);
      ck_assert_double_eq_tol(x * 1e3, seq_neg_mm[n], 1e-9);
      ck_assert_int_eq(qlearn_policy_observe(&pol, x, oracle(-7.03e-3, x)), QLEARN_OK);
      n++;
    }
    ck_assert_int_eq(n, 11);
    ck_assert_uint_eq(pol.trials, 11);
    double e, h;
    ck_assert_int_eq(qlearn_policy_estimate(&pol, &e, &h), QLEARN_OK);
    ck_assert_double_eq_tol(e * 1e3, -7.05, 1e-9);
  }
}
END_TEST

START_TEST(state_sizes) {
  /* The whole estimator state stays within 16 KiB (issue 4). */
  ck_assert_uint_le(sizeof(qlearn_paper_t), 8192);
  ck_assert_uint_le(sizeof(qlearn_policy_t), 16384);
  fprintf(stderr,
          "sizeof: qlearn_qtable_t %zu, qlearn_mlp_t %zu, qlearn_paper_t %zu, "
          "qlearn_policy_t %zu\n",
          sizeof(qlearn_qtable_t), sizeof(qlearn_mlp_t), sizeof(qlearn_paper_t),
          sizeof(qlearn_policy_t));
}
END_TEST

Suite *qlearn_paper_suite(void) {
  Suite *s = suite_create("qlearn_paper");
  TCase *tc = tcase_create("walk");
  tcase_set_timeout(tc, 120);
  tcase_add_test(tc, qtable_matches_hand_traced_sequences);
  tcase_add_test(tc, mlp_matches_hand_traced_sequences);
  tcase_add_test(tc, qtable_finds_200_thresholds);
  tcase_add_test(tc, mlp_finds_200_thresholds);
  tcase_add_test(tc, offset_prior_clamps_to_the_range);
  tcase_add_test(tc, threshold_outside_the_range_is_reported);
  tcase_add_test(tc, qtable_brackets_c_from_off_grid_priors);
  tcase_add_test(tc, mlp_brackets_c_from_off_grid_priors);
  tcase_add_test(tc, estimate_before_the_end_is_what_outcomes_leave);
  suite_add_tcase(s, tc);
  tc = tcase_create("contract");
  tcase_add_test(tc, bad_input_leaves_state_unchanged);
  tcase_add_test(tc, through_the_policy_interface);
  tcase_add_test(tc, state_sizes);
  suite_add_tcase(s, tc);
  return s;
}
