/* The learners of lib/qlearn: the Q-table and the MLP (comlearn/qlearn_qtable.h, qlearn_mlp.h). */
#include <check.h>
#include <math.h>
#include <string.h>

#include "comlearn/qlearn_mlp.h"
#include "comlearn/qlearn_qtable.h"
#include "qlearn_suites.h"

/* ---- Q-table ---- */

START_TEST(qtable_set_get_overwrite) {
  qlearn_qtable_t t;
  ck_assert_int_eq(qlearn_qtable_init(&t), QLEARN_OK);
  double q[2] = {-1.0, -1.0};
  ck_assert_int_eq(qlearn_qtable_get(&t, 42, q), 0);
  ck_assert(q[0] == QLEARN_QTABLE_Q_UNSEEN && q[1] == QLEARN_QTABLE_Q_UNSEEN);
  const double a[2] = {0.9, 0.1}, b[2] = {0.1, 0.9};
  ck_assert_int_eq(qlearn_qtable_set(&t, 42, a), QLEARN_OK);
  ck_assert_int_eq(qlearn_qtable_set(&t, -7, b), QLEARN_OK);
  ck_assert_int_eq(qlearn_qtable_get(&t, 42, q), 1);
  ck_assert(q[0] == 0.9 && q[1] == 0.1);
  ck_assert_int_eq(qlearn_qtable_get(&t, -7, q), 1);
  ck_assert(q[0] == 0.1 && q[1] == 0.9);
  /* Overwriting a state keeps one row. */
  ck_assert_int_eq(qlearn_qtable_set(&t, 42, b), QLEARN_OK);
  ck_assert_uint_eq(t.n, 2);
  ck_assert_int_eq(qlearn_qtable_get(&t, 42, q), 1);
  ck_assert(q[0] == 0.1 && q[1] == 0.9);
  ck_assert_int_eq(qlearn_qtable_get(&t, 43, q), 0);
  ck_assert_int_eq(qlearn_qtable_get(NULL, 43, q), -1);
  ck_assert_int_eq(qlearn_qtable_init(NULL), QLEARN_E_ARG);
}
END_TEST

START_TEST(qtable_capacity_and_bad_input_leave_state_unchanged) {
  static qlearn_qtable_t t, before;
  ck_assert_int_eq(qlearn_qtable_init(&t), QLEARN_OK);
  const double a[2] = {0.9, 0.1};
  for (int64_t s = 0; s < QLEARN_QTABLE_MAX_STATES; s++) {
    ck_assert_int_eq(qlearn_qtable_set(&t, s * 3, a), QLEARN_OK);
  }
  ck_assert_uint_eq(t.n, QLEARN_QTABLE_MAX_STATES);
  memcpy(&before, &t, sizeof t);
  ck_assert_int_eq(qlearn_qtable_set(&t, -1, a), QLEARN_E_CAPACITY);
  ck_assert_int_eq(memcmp(&before, &t, sizeof t), 0);
  const double bad[2] = {NAN, 0.1}, inf[2] = {0.9, INFINITY};
  ck_assert_int_eq(qlearn_qtable_set(&t, 3, bad), QLEARN_E_NONFINITE);
  ck_assert_int_eq(qlearn_qtable_set(&t, 3, inf), QLEARN_E_NONFINITE);
  ck_assert_int_eq(qlearn_qtable_set(&t, 3, NULL), QLEARN_E_ARG);
  ck_assert_int_eq(memcmp(&before, &t, sizeof t), 0);
  /* A full table still accepts updates of a stored state. */
  const double b[2] = {0.1, 0.9};
  ck_assert_int_eq(qlearn_qtable_set(&t, 3 * (QLEARN_QTABLE_MAX_STATES - 1), b), QLEARN_OK);
  double q[2];
  ck_assert_int_eq(qlearn_qtable_get(&t, 3 * (QLEARN_QTABLE_MAX_STATES - 1), q), 1);
  ck_assert(q[1] == 0.9);
}
END_TEST

/* ---- MLP ---- */

START_TEST(mlp_forward_by_hand) {
  double p[QLEARN_MLP_NPARAM];
  memset(p, 0, sizeof p);
  const int H = QLEARN_MLP_HIDDEN;
  p[0] = 2.0;                  /* W1[0] */
  p[H + 0] = -0.5;             /* b1[0] */
  p[2 * H + 0] = 1.5;          /* W2[0][0] */
  p[2 * H + H] = -3.0;         /* W2[1][0] */
  p[2 * H + 2 * H] = 0.25;     /* b2[0] */
  p[2 * H + 2 * H + 1] = -1.0; /* b2[1] */
  double q[2], h[QLEARN_MLP_HIDDEN];
  qlearn_mlp_forward(p, 0.75, q, h);
  const double h0 = tanh(2.0 * 0.75 - 0.5); /* tanh(1) = 0.761594... */
  ck_assert_double_eq_tol(h[0], 0.7615941559557649, 1e-15);
  ck_assert(h[1] == 0.0);
  ck_assert_double_eq_tol(q[0], 0.25 + 1.5 * h0, 1e-15);
  ck_assert_double_eq_tol(q[1], -1.0 - 3.0 * h0, 1e-15);
}
END_TEST

START_TEST(mlp_gradient_matches_finite_differences) {
  qlearn_mlp_t mlp;
  ck_assert_int_eq(qlearn_mlp_init(&mlp, 7), QLEARN_OK);
  const double s = 0.37, t[2] = {0.9, 0.1};
  double g[QLEARN_MLP_NPARAM];
  memset(g, 0, sizeof g);
  qlearn_mlp_grad_add(mlp.p, s, t, 1.0, g);
  for (int i = 0; i < QLEARN_MLP_NPARAM; i++) {
    double p[QLEARN_MLP_NPARAM], q[2];
    memcpy(p, mlp.p, sizeof p);
    const double eps = 1e-6;
    p[i] += eps;
    qlearn_mlp_forward(p, s, q, NULL);
    const double lp = 0.5 * ((q[0] - t[0]) * (q[0] - t[0]) + (q[1] - t[1]) * (q[1] - t[1]));
    p[i] -= 2.0 * eps;
    qlearn_mlp_forward(p, s, q, NULL);
    const double lm = 0.5 * ((q[0] - t[0]) * (q[0] - t[0]) + (q[1] - t[1]) * (q[1] - t[1]));
    ck_assert_double_eq_tol(g[i], (lp - lm) / (2.0 * eps), 1e-7);
  }
}
END_TEST

START_TEST(mlp_adam_first_step_is_lr_times_sign) {
  /* With bias correction, Adam's first step is lr * g / (|g| + eps) per parameter. */
  double p[3] = {1.0, 1.0, 1.0}, g[3] = {0.5, -2.0, 0.0}, m[3] = {0}, v[3] = {0};
  const qlearn_mlp_adam_t adam = QLEARN_MLP_ADAM_DEFAULT;
  qlearn_mlp_adam_step(p, g, m, v, 3, &adam, adam.beta1, adam.beta2);
  ck_assert_double_eq_tol(p[0], 1.0 - 0.01, 1e-9);
  ck_assert_double_eq_tol(p[1], 1.0 + 0.01, 1e-9);
  ck_assert(p[2] == 1.0);
}
END_TEST

/* Targets of a smooth two-output function on [-1, 1]. */
static void target(double s, double *q) {
  q[0] = 0.5 + 0.4 * sin(2.0 * s);
  q[1] = 0.2 + 0.3 * s * s;
}

START_TEST(mlp_fits_a_smooth_target) {
  static qlearn_mlp_t mlp;
  ck_assert_int_eq(qlearn_mlp_init(&mlp, 1), QLEARN_OK);
  for (int i = 0; i <= 20; i++) {
    double q[2];
    const double s = -1.0 + 0.1 * i;
    target(s, q);
    ck_assert_int_eq(qlearn_mlp_add(&mlp, s, q), QLEARN_OK);
  }
  const double loss0 = qlearn_mlp_loss(&mlp);
  const qlearn_mlp_adam_t adam = QLEARN_MLP_ADAM_DEFAULT;
  ck_assert_int_eq(qlearn_mlp_fit(&mlp, 5000, &adam), QLEARN_OK);
  ck_assert_uint_eq(mlp.steps, 5000);
  const double loss = qlearn_mlp_loss(&mlp);
  ck_assert(loss0 > 1e-2);
  ck_assert_msg(loss < 5e-5, "loss %g", loss);
  /* Between the training points too: every output within 0.01. */
  for (int i = 0; i < 40; i++) {
    const double s = -0.975 + 0.05 * i;
    double q[2], t[2];
    qlearn_mlp_forward(mlp.p, s, q, NULL);
    target(s, t);
    ck_assert_double_eq_tol(q[0], t[0], 0.01);
    ck_assert_double_eq_tol(q[1], t[1], 0.01);
  }
}
END_TEST

START_TEST(mlp_seed_gives_bit_identical_weights) {
  static qlearn_mlp_t a, b, c;
  ck_assert_int_eq(qlearn_mlp_init(&a, 12345), QLEARN_OK);
  ck_assert_int_eq(qlearn_mlp_init(&b, 12345), QLEARN_OK);
  ck_assert_int_eq(qlearn_mlp_init(&c, 12346), QLEARN_OK);
  ck_assert_int_eq(memcmp(a.p, b.p, sizeof a.p), 0);
  ck_assert_int_ne(memcmp(a.p, c.p, sizeof a.p), 0);
  int differ = 0;
  for (int i = 0; i < 2 * QLEARN_MLP_HIDDEN; i++) differ += a.p[i] != c.p[i];
  ck_assert_int_eq(differ, 2 * QLEARN_MLP_HIDDEN); /* every W1 and b1 weight differs */
  /* Weights drawn in the documented ranges. */
  for (int i = 0; i < 2 * QLEARN_MLP_HIDDEN; i++) ck_assert(fabs(a.p[i]) <= 1.0);
  const qlearn_mlp_adam_t adam = QLEARN_MLP_ADAM_DEFAULT;
  const double s[3] = {-0.5, 0.0, 0.8}, q[3][2] = {{0.1, 0.9}, {0.1, 0.9}, {0.9, 0.1}};
  for (int i = 0; i < 3; i++) {
    ck_assert_int_eq(qlearn_mlp_add(&a, s[i], q[i]), QLEARN_OK);
    ck_assert_int_eq(qlearn_mlp_add(&b, s[i], q[i]), QLEARN_OK);
    ck_assert_int_eq(qlearn_mlp_add(&c, s[i], q[i]), QLEARN_OK);
  }
  ck_assert_int_eq(qlearn_mlp_fit(&a, 500, &adam), QLEARN_OK);
  ck_assert_int_eq(qlearn_mlp_fit(&b, 500, &adam), QLEARN_OK);
  ck_assert_int_eq(qlearn_mlp_fit(&c, 500, &adam), QLEARN_OK);
  ck_assert_int_eq(memcmp(&a, &b, sizeof a), 0);
  ck_assert_int_ne(memcmp(a.p, c.p, sizeof a.p), 0);
  /* Both seeds learn the three labels (argmax). */
  for (int i = 0; i < 3; i++) {
    double qa[2], qc[2];
    qlearn_mlp_forward(a.p, s[i], qa, NULL);
    qlearn_mlp_forward(c.p, s[i], qc, NULL);
    ck_assert_int_eq(qa[1] > qa[0], q[i][1] > q[i][0]);
    ck_assert_int_eq(qc[1] > qc[0], q[i][1] > q[i][0]);
  }
}
END_TEST

START_TEST(mlp_bad_input_and_capacity_leave_state_unchanged) {
  static qlearn_mlp_t mlp, before;
  ck_assert_int_eq(qlearn_mlp_init(&mlp, 3), QLEARN_OK);
  const qlearn_mlp_adam_t adam = QLEARN_MLP_ADAM_DEFAULT;
  memcpy(&before, &mlp, sizeof mlp);
  ck_assert_int_eq(qlearn_mlp_fit(&mlp, 10, &adam), QLEARN_E_RANGE); /* no instance */
  const double q[2] = {0.9, 0.1}, nanq[2] = {0.9, NAN};
  ck_assert_int_eq(qlearn_mlp_add(&mlp, NAN, q), QLEARN_E_NONFINITE);
  ck_assert_int_eq(qlearn_mlp_add(&mlp, INFINITY, q), QLEARN_E_NONFINITE);
  ck_assert_int_eq(qlearn_mlp_add(&mlp, 0.5, nanq), QLEARN_E_NONFINITE);
  ck_assert_int_eq(memcmp(&before, &mlp, sizeof mlp), 0);
  for (int i = 0; i < QLEARN_MLP_MAX_INSTANCES; i++) {
    ck_assert_int_eq(qlearn_mlp_add(&mlp, 0.01 * i, q), QLEARN_OK);
  }
  memcpy(&before, &mlp, sizeof mlp);
  ck_assert_int_eq(qlearn_mlp_add(&mlp, 0.0, q), QLEARN_E_CAPACITY);
  ck_assert_int_eq(qlearn_mlp_fit(&mlp, 0, &adam), QLEARN_E_ARG);
  ck_assert_int_eq(qlearn_mlp_fit(&mlp, QLEARN_MLP_MAX_EPOCHS + 1, &adam), QLEARN_E_ARG);
  qlearn_mlp_adam_t bad = adam;
  bad.lr = -1.0;
  ck_assert_int_eq(qlearn_mlp_fit(&mlp, 1, &bad), QLEARN_E_ARG);
  bad = adam;
  bad.beta2 = 1.0;
  ck_assert_int_eq(qlearn_mlp_fit(&mlp, 1, &bad), QLEARN_E_ARG);
  /* A step size that overflows the weights: the fit reports it and keeps the old weights. */
  bad = adam;
  bad.lr = 1e300;
  ck_assert_int_eq(qlearn_mlp_fit(&mlp, 20, &bad), QLEARN_E_NOCONVERGE);
  ck_assert_int_eq(memcmp(&before, &mlp, sizeof mlp), 0);
}
END_TEST

Suite *qlearn_learner_suite(void) {
  Suite *s = suite_create("qlearn_learner");
  TCase *tc = tcase_create("qtable");
  tcase_add_test(tc, qtable_set_get_overwrite);
  tcase_add_test(tc, qtable_capacity_and_bad_input_leave_state_unchanged);
  suite_add_tcase(s, tc);
  tc = tcase_create("mlp");
  tcase_set_timeout(tc, 60);
  tcase_add_test(tc, mlp_forward_by_hand);
  tcase_add_test(tc, mlp_gradient_matches_finite_differences);
  tcase_add_test(tc, mlp_adam_first_step_is_lr_times_sign);
  tcase_add_test(tc, mlp_fits_a_smooth_target);
  tcase_add_test(tc, mlp_seed_gives_bit_identical_weights);
  tcase_add_test(tc, mlp_bad_input_and_capacity_leave_state_unchanged);
  suite_add_tcase(s, tc);
  return s;
}
