/* check_math: comlearn/math3d.h against analytic values and against the streams of the PRNG
 * copies it replaces (their first outputs, computed with those copies and pinned here). */
#include <check.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "comlearn/math3d.h"

static const double kId[4] = {1.0, 0.0, 0.0, 0.0};
static const double kEx[3] = {1, 0, 0}, kEy[3] = {0, 1, 0}, kEz[3] = {0, 0, 1};

static void assert_vec3(const double got[3], double x, double y, double z, double tol) {
  const double want[3] = {x, y, z};
  for (int k = 0; k < 3; ++k)
    ck_assert_msg(fabs(got[k] - want[k]) <= tol, "component %d: %.17g, want %.17g (tol %g)", k,
                  got[k], want[k], tol);
}

static void quat_about(const double axis[3], double angle_rad, double q[4]) {
  double u[3];
  (void)cl_vec3_normalize(axis, u);
  cl_quat_from_axis_angle(u, angle_rad, q);
}

/* ---- vec3 --------------------------------------------------------------------------------- */

START_TEST(test_vec3_known) {
  const double a[3] = {3, 4, 12}, b[3] = {1, -2, 0.5};
  ck_assert_double_eq(cl_vec3_dot(a, b), 3 - 8 + 6);
  ck_assert_double_eq(cl_vec3_norm(a), 13.0);
  ck_assert_double_eq(cl_vec3_dist(a, (const double[3]){0, 0, 0}), 13.0);
  ck_assert_double_eq(cl_vec3_dist(a, a), 0.0);
  double c[3];
  cl_vec3_cross(kEx, kEy, c);
  assert_vec3(c, 0, 0, 1, 0.0);
  cl_vec3_cross(kEy, kEx, c);
  assert_vec3(c, 0, 0, -1, 0.0);
  cl_vec3_cross(a, b, c); /* perpendicular to both */
  ck_assert_double_eq_tol(cl_vec3_dot(c, a), 0.0, 1e-12);
  ck_assert_double_eq_tol(cl_vec3_dot(c, b), 0.0, 1e-12);
  double d[3] = {1, 2, 3};
  cl_vec3_cross(d, kEz, d); /* aliasing the output with an input */
  assert_vec3(d, 2, -1, 0, 0.0);
  cl_vec3_add(a, b, c);
  assert_vec3(c, 4, 2, 12.5, 0.0);
  cl_vec3_sub(a, b, c);
  assert_vec3(c, 2, 6, 11.5, 0.0);
  cl_vec3_scale(a, -0.5, c);
  assert_vec3(c, -1.5, -2, -6, 0.0);
  ck_assert_double_eq(cl_vec3_normalize(a, c), 13.0);
  assert_vec3(c, 3.0 / 13.0, 4.0 / 13.0, 12.0 / 13.0, 0.0);
}
END_TEST

/* cl_tri_normal: a right triangle in the x-y plane points +z (ccw) or -z (cw), returns twice its
 * area; a tilted one gives the known unit normal; a degenerate one gives 0 and a zero normal. */
START_TEST(test_tri_normal) {
  const double a[3] = {1.0, 1.0, 0.5}, b[3] = {4.0, 1.0, 0.5}, c[3] = {1.0, 3.0, 0.5};
  double n[3];
  ck_assert_double_eq_tol(cl_tri_normal(a, b, c, n), 6.0, 1e-15); /* legs 3 and 2 */
  ck_assert_double_eq_tol(n[2], 1.0, 1e-15);
  ck_assert_double_eq_tol(fabs(n[0]) + fabs(n[1]), 0.0, 1e-15);
  ck_assert_double_eq_tol(cl_tri_normal(a, c, b, n), 6.0, 1e-15);
  ck_assert_double_eq_tol(n[2], -1.0, 1e-15);
  const double p[3] = {1.0, 0.0, 0.0}, q[3] = {0.0, 1.0, 0.0}, r[3] = {0.0, 0.0, 1.0};
  ck_assert_double_eq_tol(cl_tri_normal(p, q, r, n), sqrt(3.0), 1e-15);
  for (int k = 0; k < 3; ++k) ck_assert_double_eq_tol(n[k], 1.0 / sqrt(3.0), 1e-15);
  const double m[3] = {2.5, 1.0, 0.5}; /* on a-b */
  ck_assert_double_eq(cl_tri_normal(a, b, m, n), 0.0);
  for (int k = 0; k < 3; ++k) ck_assert_double_eq(n[k], 0.0);
}
END_TEST

START_TEST(test_pi) {
  ck_assert_double_eq(CL_PI, acos(-1.0));
  ck_assert_double_eq(2.0 * CL_PI, 6.283185307179586);
  ck_assert_double_eq(CL_PI / 180.0, 0.017453292519943295769);
}
END_TEST

/* ---- quaternions -------------------------------------------------------------------------- */

START_TEST(test_quat_rotate_known) {
  double qz[4], qx[4], q[4], v[3];
  cl_quat_from_axis_angle(kEz, 0.5 * CL_PI, qz);
  cl_quat_rotate(qz, kEx, v); /* 90 deg about z: x -> y, y -> -x */
  assert_vec3(v, 0, 1, 0, 1e-15);
  cl_quat_rotate(qz, kEy, v);
  assert_vec3(v, -1, 0, 0, 1e-15);
  cl_quat_rotate(qz, kEz, v);
  assert_vec3(v, 0, 0, 1, 1e-15);
  /* 120 deg about (1, 1, 1): x -> y -> z -> x */
  quat_about((const double[3]){1, 1, 1}, 2.0 * CL_PI / 3.0, q);
  cl_quat_rotate(q, kEx, v);
  assert_vec3(v, 0, 1, 0, 1e-15);
  cl_quat_rotate(q, kEz, v);
  assert_vec3(v, 1, 0, 0, 1e-15);
  /* Order: mul(qz, qx) applies qx first. e_y -x90-> e_z -z90-> e_z; mul(qx, qz): e_y -z90-> -e_x
   * -x90-> -e_x. */
  cl_quat_from_axis_angle(kEx, 0.5 * CL_PI, qx);
  cl_quat_mul(qz, qx, q);
  cl_quat_rotate(q, kEy, v);
  assert_vec3(v, 0, 0, 1, 1e-15);
  cl_quat_mul(qx, qz, q);
  cl_quat_rotate(q, kEy, v);
  assert_vec3(v, -1, 0, 0, 1e-15);
  /* the conjugate undoes the rotation; the matrix agrees with the rotation */
  const double p[3] = {0.3, -1.2, 2.5};
  double c[4], r[3][3], w[3];
  quat_about((const double[3]){0.2, -0.7, 0.4}, 2.1, q);
  cl_quat_rotate(q, p, v);
  cl_quat_conj(q, c);
  cl_quat_rotate(c, v, w);
  assert_vec3(w, p[0], p[1], p[2], 1e-15);
  cl_quat_to_rot(q, r);
  for (int i = 0; i < 3; ++i)
    ck_assert_double_eq_tol(r[i][0] * p[0] + r[i][1] * p[1] + r[i][2] * p[2], v[i], 1e-15);
  cl_quat_rotate(q, v, v); /* aliasing: a second turn */
  cl_quat_mul(q, q, c);
  cl_quat_rotate(c, p, w);
  assert_vec3(v, w[0], w[1], w[2], 1e-14);
}
END_TEST

START_TEST(test_quat_rot_round_trip) {
  /* identity, half turns (trace -1: every Shepperd branch) and a generic rotation */
  const double qs[6][4] = {{1, 0, 0, 0}, {0, 1, 0, 0},     {0, 0, 1, 0},
                           {0, 0, 0, 1}, {0, 0.6, 0.8, 0}, {0.5, -0.5, 0.5, 0.5}};
  for (int i = 0; i < 6; ++i) {
    double r[3][3], q[4];
    cl_quat_to_rot(qs[i], r);
    cl_quat_from_rot((const double(*)[3])r, q);
    ck_assert(q[0] >= 0.0);
    const double s = qs[i][0] < 0.0 ? -1.0 : 1.0;
    for (int k = 0; k < 4; ++k) ck_assert_double_eq_tol(q[k], s * qs[i][k], 1e-15);
  }
  double q[4], n;
  n = cl_quat_normalize((const double[4]){2, 0, 0, -2}, q);
  ck_assert_double_eq_tol(n, sqrt(8.0), 1e-15);
  ck_assert_double_eq_tol(q[0], sqrt(0.5), 3e-16);
  ck_assert_double_eq_tol(q[3], -sqrt(0.5), 3e-16);
}
END_TEST

START_TEST(test_quat_angle_known) {
  double q[4], a[4], b[4], d[4];
  cl_quat_from_axis_angle(kEx, 0.5 * CL_PI, q);
  ck_assert_double_eq_tol(cl_quat_angle(kId, q), 0.5 * CL_PI, 1e-15);
  ck_assert_double_eq_tol(cl_quat_angle(q, kId), 0.5 * CL_PI, 1e-15);
  const double nq[4] = {-q[0], -q[1], -q[2], -q[3]}; /* same rotation */
  ck_assert_double_eq_tol(cl_quat_angle(kId, nq), 0.5 * CL_PI, 1e-15);
  ck_assert_double_eq_tol(cl_quat_angle(q, nq), 0.0, 1e-15);
  cl_quat_from_axis_angle(kEy, CL_PI, q);
  ck_assert_double_eq_tol(cl_quat_angle(kId, q), CL_PI, 1e-15);
  cl_quat_from_axis_angle(kEz, 1.5 * CL_PI, q); /* 270 deg is 90 deg the other way */
  ck_assert_double_eq_tol(cl_quat_angle(kId, q), 0.5 * CL_PI, 1e-15);
  ck_assert_double_eq(cl_quat_angle(kId, kId), 0.0);
  /* relative rotation between two general orientations: b = a * d, d by 0.7 rad */
  quat_about((const double[3]){0.3, 1.0, -0.2}, 2.4, a);
  quat_about((const double[3]){-0.8, 0.1, 0.5}, 0.7, d);
  cl_quat_mul(a, d, b);
  ck_assert_double_eq_tol(cl_quat_angle(a, b), 0.7, 1e-15);
  ck_assert_double_eq_tol(cl_quat_angle(b, a), 0.7, 1e-15);
  /* a single rotation's angle: bit for bit 2 atan2(|v|, |w|) (cmd_watch's formula) */
  const double v = sqrt(b[1] * b[1] + b[2] * b[2] + b[3] * b[3]);
  ck_assert_double_eq(cl_quat_angle(kId, b), 2.0 * atan2(v, fabs(b[0])));
}
END_TEST

/* The accurate formula where 2 acos(|a . b|) fails: 1e-9 rad. cos(5e-10) rounds to 1.0, so the
 * acos formula returns 0 (and only ~1e-8 resolution above that); atan2 keeps full precision. */
START_TEST(test_quat_angle_tiny) {
  const double tiny = 1e-9;
  double q[4], a[4], b[4], d[4];
  cl_quat_from_axis_angle(kEz, tiny, q);
  const double dot = fabs(q[0]);
  const double acos_formula = 2.0 * acos(dot > 1.0 ? 1.0 : dot);
  ck_assert_double_eq(acos_formula, 0.0);
  ck_assert_double_eq_tol(cl_quat_angle(kId, q), tiny, 1e-24);
  for (int e = 3; e <= 12; ++e) { /* 1e-3 .. 1e-12 rad, relative error ~1 ulp */
    const double t = pow(10.0, -e);
    cl_quat_from_axis_angle(kEx, t, q);
    ck_assert_double_le(fabs(cl_quat_angle(kId, q) - t), 1e-15 * t);
  }
  /* between two general orientations the products round at ~1e-16 absolute: still 1e-9 to
   * 1e-7 relative, where acos gives 0 or garbage */
  quat_about((const double[3]){0.3, 1.0, -0.2}, 2.4, a);
  quat_about((const double[3]){-0.8, 0.1, 0.5}, tiny, d);
  cl_quat_mul(a, d, b);
  ck_assert_double_eq_tol(cl_quat_angle(a, b), tiny, 1e-15);
}
END_TEST

START_TEST(test_quat_slerp) {
  double qz[4], h[4], out[4];
  cl_quat_from_axis_angle(kEz, 0.5 * CL_PI, qz);
  cl_quat_from_axis_angle(kEz, 0.25 * CL_PI, h);
  cl_quat_slerp(kId, qz, 0.5, out);
  for (int k = 0; k < 4; ++k) ck_assert_double_eq_tol(out[k], h[k], 1e-15);
  cl_quat_slerp(kId, qz, 0.0, out);
  for (int k = 0; k < 4; ++k) ck_assert_double_eq_tol(out[k], kId[k], 1e-15);
  const double nqz[4] = {-qz[0], -qz[1], -qz[2], -qz[3]}; /* the shorter arc: same halfway */
  cl_quat_slerp(kId, nqz, 0.5, out);
  for (int k = 0; k < 4; ++k) ck_assert_double_eq_tol(out[k], h[k], 1e-15);
  cl_quat_slerp(kId, qz, 1.0, out);
  ck_assert_double_eq_tol(cl_quat_angle(out, qz), 0.0, 1e-15);
}
END_TEST

/* ---- poses -------------------------------------------------------------------------------- */

START_TEST(test_pose) {
  cl_pose_t a, b, ab, inv, id;
  cl_pose_identity(&id);
  ck_assert_double_eq(id.orientation_wxyz[0], 1.0);
  a.position_m[0] = 1.0;
  a.position_m[1] = 2.0;
  a.position_m[2] = 3.0;
  cl_quat_from_axis_angle(kEz, 0.5 * CL_PI, a.orientation_wxyz);
  double p[3];
  cl_pose_apply(&a, kEx, p); /* (1, 0, 0) -> rotated to (0, 1, 0), then + (1, 2, 3) */
  assert_vec3(p, 1, 3, 3, 1e-15);
  b.position_m[0] = 0.0;
  b.position_m[1] = 0.0;
  b.position_m[2] = 0.5;
  cl_quat_from_axis_angle(kEx, 0.5 * CL_PI, b.orientation_wxyz);
  cl_pose_mul(&a, &b, &ab); /* frame 2 in frame 0 */
  double p1[3], p0[3];
  cl_pose_apply(&b, kEy, p1);
  cl_pose_apply(&a, p1, p0);
  cl_pose_apply(&ab, kEy, p);
  assert_vec3(p, p0[0], p0[1], p0[2], 1e-15);
  assert_vec3(p, 1, 2, 4.5, 1e-15); /* e_y -x90-> e_z (+0.5 z) -z90-> (0, 0, 1.5) + (1, 2, 3) */
  cl_pose_inverse(&ab, &inv);
  cl_pose_mul(&inv, &ab, &id);
  assert_vec3(id.position_m, 0, 0, 0, 1e-15);
  ck_assert_double_eq_tol(cl_quat_angle(kId, id.orientation_wxyz), 0.0, 1e-15);
  cl_pose_apply(&inv, p, p);
  assert_vec3(p, 0, 1, 0, 1e-15);
  cl_pose_mul(&a, &b, &a); /* aliasing */
  assert_vec3(a.position_m, ab.position_m[0], ab.position_m[1], ab.position_m[2], 0.0);
}
END_TEST

/* ---- PRNG --------------------------------------------------------------------------------- */

/* splitmix64's published reference output for seed 0, and the copies' (lib/qlearn mlp.c,
 * lib/placement ik.c / plan.c, lib/balance trial.c, daemon/main.c, tools rockgen*.c /
 * shapegen_mesh.c, bench_ik, tests/test_rng.h: all the same mixer) for seed 1234567. */
START_TEST(test_rng_first_outputs) {
  uint64_t s = 0;
  ck_assert_uint_eq(cl_rng_next(&s), UINT64_C(0xe220a8397b1dcdaf));
  ck_assert_uint_eq(cl_rng_next(&s), UINT64_C(0x6e789e6aa1b965f4));
  ck_assert_uint_eq(cl_rng_next(&s), UINT64_C(0x06c45d188009454f));
  ck_assert_uint_eq(s, 3 * UINT64_C(0x9E3779B97F4A7C15));
  s = 1234567;
  ck_assert_uint_eq(cl_rng_next(&s), UINT64_C(0x599ed017fb08fc85));
  ck_assert_uint_eq(cl_rng_next(&s), UINT64_C(0x2c73f08458540fa5));
  /* uniforms: [0, 1) as rockgen / shapegen / placement / qlearn, (0, 1) as balance's noise */
  s = 42;
  ck_assert_double_eq(cl_rng_uniform(&s), 0x1.7bae644c5fd6dp-1);
  s = 42;
  ck_assert_double_eq(cl_rng_uniform_open(&s), 0x1.7bae644c5fd6ep-1);
  s = 42;
  ck_assert_double_eq(cl_rng_range(&s, -2.0, 2.0), -2.0 + 4.0 * 0x1.7bae644c5fd6dp-1);
  s = 0;
  ck_assert_uint_eq(cl_rng_below(&s, 1000), (unsigned)(UINT64_C(0xe220a8397b1dcdaf) % 1000));
  ck_assert_uint_eq(cl_rng_below(&s, 0), 0);
  ck_assert_uint_eq(s, UINT64_C(0x9E3779B97F4A7C15)); /* n == 0 draws nothing */
}
END_TEST

/* The Box-Muller pair of lib/balance's trial noise (trial.c gauss2), bit for bit: seed 42, and
 * the seed comlearn-sim / estimate_direct give trial 1 of a run seeded 7. */
START_TEST(test_rng_normal_stream) {
  uint64_t s = 42;
  double g[2];
  cl_rng_normal2(&s, g);
  ck_assert_double_eq(g[0], 0x1.a8ac4b546f505p-2);
  ck_assert_double_eq(g[1], 0x1.4e2c3bafb6393p-1);
  ck_assert_uint_eq(s, 42 + 2 * UINT64_C(0x9E3779B97F4A7C15));
  s = 7 ^ (UINT64_C(0x9E3779B97F4A7C15) * 1);
  cl_rng_normal2(&s, g);
  ck_assert_double_eq(g[0], 0x1.97d0f764687eap-2);
  ck_assert_double_eq(g[1], -0x1.7006426833c5cp-7);
}
END_TEST

START_TEST(test_rng_normal_moments) {
  enum { N = 200000 };
  uint64_t s = 99;
  double m = 0.0, m2 = 0.0, m4 = 0.0, c01 = 0.0;
  for (int i = 0; i < N / 2; ++i) {
    double g[2];
    cl_rng_normal2(&s, g);
    ck_assert(isfinite(g[0]) && isfinite(g[1]));
    m += g[0] + g[1];
    m2 += g[0] * g[0] + g[1] * g[1];
    m4 += g[0] * g[0] * g[0] * g[0] + g[1] * g[1] * g[1] * g[1];
    c01 += g[0] * g[1];
  }
  m /= N;
  const double var = m2 / N - m * m;
  /* standard errors: mean 0.0022, variance 0.0032, kurtosis ~0.02, pair covariance 0.0032 */
  ck_assert_double_le(fabs(m), 0.01);
  ck_assert_double_le(fabs(var - 1.0), 0.015);
  ck_assert_double_le(fabs(m4 / N - 3.0), 0.1);
  ck_assert_double_le(fabs(c01 / (N / 2)), 0.015);
}
END_TEST

START_TEST(test_rng_uniform_and_direction) {
  uint64_t s = 5;
  double sum = 0.0, lo = 1.0, hi = 0.0;
  for (int i = 0; i < 100000; ++i) {
    const double u = cl_rng_uniform(&s), o = cl_rng_uniform_open(&s);
    ck_assert(u >= 0.0 && u < 1.0 && o > 0.0 && o < 1.0);
    sum += u;
    lo = fmin(lo, u);
    hi = fmax(hi, u);
  }
  ck_assert_double_le(fabs(sum / 100000 - 0.5), 0.005);
  ck_assert(lo < 1e-4 && hi > 1.0 - 1e-4);
  double mean3[3] = {0, 0, 0};
  for (int i = 0; i < 20000; ++i) {
    double u[3];
    cl_rng_direction(&s, 3, u);
    ck_assert_double_eq_tol(cl_vec3_norm(u), 1.0, 1e-15);
    cl_vec3_add(mean3, u, mean3);
    cl_rng_direction(&s, 2, u);
    ck_assert_double_eq(u[2], 0.0);
    ck_assert_double_eq_tol(cl_vec3_norm(u), 1.0, 1e-15);
  }
  for (int k = 0; k < 3; ++k) ck_assert_double_le(fabs(mean3[k] / 20000), 0.015);
}
END_TEST

static Suite *math_suite(void) {
  Suite *s = suite_create("math3d");
  TCase *v = tcase_create("vec3");
  tcase_add_test(v, test_vec3_known);
  tcase_add_test(v, test_pi);
  tcase_add_test(v, test_tri_normal);
  suite_add_tcase(s, v);
  TCase *q = tcase_create("quat");
  tcase_add_test(q, test_quat_rotate_known);
  tcase_add_test(q, test_quat_rot_round_trip);
  tcase_add_test(q, test_quat_angle_known);
  tcase_add_test(q, test_quat_angle_tiny);
  tcase_add_test(q, test_quat_slerp);
  tcase_add_test(q, test_pose);
  suite_add_tcase(s, q);
  TCase *r = tcase_create("rng");
  tcase_add_test(r, test_rng_first_outputs);
  tcase_add_test(r, test_rng_normal_stream);
  tcase_add_test(r, test_rng_normal_moments);
  tcase_add_test(r, test_rng_uniform_and_direction);
  suite_add_tcase(s, r);
  return s;
}

int main(void) {
  SRunner *runner = srunner_create(math_suite());
  srunner_run_all(runner, CK_NORMAL);
  const int failed = srunner_ntests_failed(runner);
  srunner_free(runner);
  return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
