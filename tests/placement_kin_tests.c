/* placement_kin_tests.c - URDF kinematic chains (lib/model), YuMi FK against RobotStudio, IK. */
#define _POSIX_C_SOURCE 200809L

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <unistd.h>

#include "comlearn/math3d.h"
#include "comlearn/model_chain.h"
#include "comlearn/placement.h"
#include "placement_suites.h"

#define YUMI_URDF COMLEARN_ASSETS_DIR "/yumi/yumi.urdf"
#define DEG (CL_PI / 180.0)

/* Random poses for the IK round trip, per arm. The sanitizer build runs the same count. */
#ifndef PLACEMENT_TEST_IK_POSES
#define PLACEMENT_TEST_IK_POSES 2000
#endif

static void load_arm(placement_arm_t *arm, const char *tip) {
  placement_error_t err = {{0}};
  ck_assert_msg(
      placement_arm_load(arm, YUMI_URDF, PLACEMENT_YUMI_BASE_LINK, tip, &err) == PLACEMENT_OK, "%s",
      err.msg);
}

static void load_yumi(placement_arm_t *arm, placement_side_t side) {
  placement_error_t err = {{0}};
  ck_assert_msg(placement_arm_load_yumi(arm, YUMI_URDF, side, &err) == PLACEMENT_OK, "%s", err.msg);
}

static void random_q(const placement_arm_t *arm, uint64_t *s, double q[PLACEMENT_JOINTS]) {
  for (int k = 0; k < PLACEMENT_JOINTS; ++k) {
    q[k] = cl_rng_range(s, arm->lower_rad[k], arm->upper_rad[k]);
  }
}

/* ---- lib/model: URDF chains --------------------------------------------------------------- */

START_TEST(test_chain_yumi) {
  static const char *const sides[2] = {"r", "l"};
  for (int s = 0; s < 2; ++s) {
    char tip[64], name[64];
    snprintf(tip, sizeof tip, "yumi_tcp_%s", sides[s]);
    model_chain_t c;
    model_error_t err = {{0}};
    ck_assert_msg(model_chain_load(YUMI_URDF, "yumi_body", tip, &c, &err) == MODEL_OK, "%s",
                  err.msg);
    ck_assert_str_eq(c.base_link, "yumi_body");
    ck_assert_str_eq(c.tip_link, tip);
    ck_assert_uint_eq(c.joint_count, 9);
    ck_assert_uint_eq(c.moving_count, 7);
    /* ABB's physical order 1, 2, 7, 3, 4, 5, 6, then tool0 and the TCP (fixed). */
    static const char abb[7] = {'1', '2', '7', '3', '4', '5', '6'};
    for (int k = 0; k < 7; ++k) {
      snprintf(name, sizeof name, "yumi_joint_%c_%s", abb[k], sides[s]);
      ck_assert_str_eq(c.joints[k].name, name);
      ck_assert_int_eq(c.joints[k].type, MODEL_JOINT_REVOLUTE);
      ck_assert_int_eq(c.joints[k].has_limits, 1);
      ck_assert_double_eq_tol(c.joints[k].axis[2], 1.0, 1e-15);
      ck_assert_str_eq(c.joints[k].parent_link, k == 0 ? "yumi_body" : c.joints[k - 1].child_link);
    }
    ck_assert_int_eq(c.joints[7].type, MODEL_JOINT_FIXED);
    ck_assert_int_eq(c.joints[8].type, MODEL_JOINT_FIXED);
    ck_assert_double_eq_tol(c.joints[8].origin_xyz_m[2], 0.1142, 1e-15);
    ck_assert_double_eq_tol(c.joints[7].origin_xyz_m[2], 0.007, 1e-15);
    ck_assert_double_eq_tol(c.joints[7].origin_rpy_rad[2], CL_PI, 1e-12);
    /* The ABB corrections: elbow offset 40.5 mm, upper arm 0.17277 + 0.07873 = 0.2515 m. */
    ck_assert_double_eq_tol(c.joints[3].origin_xyz_m[0], -0.0405, 1e-15);
    ck_assert_double_eq_tol(c.joints[2].origin_xyz_m[1] + c.joints[3].origin_xyz_m[2], 0.2515,
                            1e-15);
    /* Limits (deg) and speeds (deg/s) of the ABB product specification. */
    static const double lo[7] = {-168.5, -143.5, -168.5, -123.5, -290, -88, -229};
    static const double hi[7] = {168.5, 43.5, 168.5, 80, 290, 138, 229};
    static const double vel[7] = {180, 180, 180, 180, 400, 400, 400};
    for (int k = 0; k < 7; ++k) {
      ck_assert_double_eq_tol(c.joints[k].lower, lo[k] * DEG, 1e-12);
      ck_assert_double_eq_tol(c.joints[k].upper, hi[k] * DEG, 1e-12);
      ck_assert_double_eq_tol(c.joints[k].velocity, vel[k] * DEG, 1e-12);
    }
    /* The matrix and the rpy describe the same rotation (R = Rz Ry Rx). */
    double r[3][3];
    placement_rot_from_rpy(c.joints[0].origin_rpy_rad[0], c.joints[0].origin_rpy_rad[1],
                           c.joints[0].origin_rpy_rad[2], r);
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        ck_assert_double_eq_tol(r[i][j], c.joints[0].origin_rot[i][j], 1e-12);
      }
    }
  }
  /* The gripper fingers are prismatic; a chain may end at one. */
  model_chain_t c;
  model_error_t err = {{0}};
  ck_assert_msg(
      model_chain_load(YUMI_URDF, "yumi_tool0_l", "yumi_finger_a_l", &c, &err) == MODEL_OK, "%s",
      err.msg);
  ck_assert_uint_eq(c.joint_count, 1);
  ck_assert_int_eq(c.joints[0].type, MODEL_JOINT_PRISMATIC);
  ck_assert_double_eq_tol(c.joints[0].axis[0], -1.0, 1e-15);
  ck_assert_double_eq_tol(c.joints[0].upper, 0.0125, 1e-15);
  /* base == tip: an empty chain. */
  ck_assert_int_eq(model_chain_load(YUMI_URDF, "yumi_link_3_r", "yumi_link_3_r", &c, &err),
                   MODEL_OK);
  ck_assert_uint_eq(c.joint_count, 0);
}
END_TEST

static char tmpdir[256];

static void tmp_setup(void) {
  const char *t = getenv("TMPDIR");
  snprintf(tmpdir, sizeof tmpdir, "%s/placement_kin_XXXXXX", t != NULL && t[0] ? t : "/tmp");
  ck_assert_ptr_nonnull(mkdtemp(tmpdir));
}

/* Write a three-link URDF whose second joint ("j2") has the given attributes, return its path. */
static const char *write_chain_urdf(const char *name, const char *j2_type, const char *j2_origin,
                                    const char *j2_axis, const char *j2_limit) {
  static char path[512];
  snprintf(path, sizeof path, "%s/%s.urdf", tmpdir, name);
  FILE *f = fopen(path, "w");
  ck_assert_ptr_nonnull(f);
  fprintf(
      f,
      "<?xml version=\"1.0\"?>\n<robot name=\"t\">\n"
      "  <link name=\"a\"/><link name=\"b\"/><link name=\"c\"/><link name=\"lonely\"/>\n"
      "  <link name=\"d\"/>\n"
      "  <joint name=\"j1\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/>\n"
      "    <origin xyz=\"0 0 1\" rpy=\"0 0 0\"/><axis xyz=\"0 0 1\"/>\n"
      "    <limit lower=\"-1\" upper=\"1\" velocity=\"2\" effort=\"1\"/></joint>\n"
      "  <joint name=\"j2\" type=\"%s\"><parent link=\"b\"/><child link=\"c\"/>\n"
      "    %s %s %s</joint>\n"
      "  <joint name=\"j3\" type=\"fixed\"><parent link=\"a\"/><child link=\"lonely\"/></joint>\n"
      "  <joint name=\"j4\" type=\"fixed\"><parent link=\"a\"/><child link=\"d\"/></joint>\n"
      "</robot>\n",
      j2_type, j2_origin, j2_axis, j2_limit);
  ck_assert_int_eq(fclose(f), 0);
  return path;
}

#define LIMIT_OK "<limit lower=\"-1\" upper=\"1\" velocity=\"2\" effort=\"1\"/>"
#define ORIGIN_OK "<origin xyz=\"0.5 0 0\" rpy=\"0 1.5707963267948966 0\"/>"
#define AXIS_OK "<axis xyz=\"0 2 0\"/>"

/* Expect status st and a message that contains `needle`. */
static void expect_chain_error(const char *path, const char *base, const char *tip,
                               model_status_t st, const char *needle) {
  model_chain_t c;
  model_error_t err = {{0}};
  model_status_t got = model_chain_load(path, base, tip, &c, &err);
  ck_assert_msg(got == st, "expected %s, got %s: %s", model_status_str(st), model_status_str(got),
                err.msg);
  ck_assert_msg(strstr(err.msg, needle) != NULL, "'%s' not in '%s'", needle, err.msg);
  ck_assert_uint_eq(c.joint_count, 0);
}

START_TEST(test_chain_errors) {
  tmp_setup();
  char good[512];
  snprintf(good, sizeof good, "%s",
           write_chain_urdf("good", "revolute", ORIGIN_OK, AXIS_OK, LIMIT_OK));
  model_chain_t c;
  model_error_t err = {{0}};
  ck_assert_msg(model_chain_load(good, "a", "c", &c, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_uint_eq(c.joint_count, 2);
  ck_assert_double_eq_tol(c.joints[1].axis[1], 1.0, 1e-15); /* normalised */
  ck_assert_double_eq_tol(c.joints[1].origin_rot[0][2], 1.0, 1e-15);
  ck_assert_double_eq(c.joints[1].velocity, 2.0);
  expect_chain_error(good, "a", "nowhere", MODEL_E_NOLINK, "nowhere");
  expect_chain_error(good, "nowhere", "c", MODEL_E_NOLINK, "nowhere");
  expect_chain_error(good, "b", "lonely", MODEL_E_CHAIN, "does not descend");
  expect_chain_error(good, "c", "a", MODEL_E_CHAIN, "does not descend");
  expect_chain_error(good, "d", "c", MODEL_E_CHAIN, "'d'");
  expect_chain_error(COMLEARN_ASSETS_DIR "/yumi/none.urdf", "a", "c", MODEL_E_NOFILE, "none.urdf");
  expect_chain_error(good, "", "c", MODEL_E_ARG, "empty");
  const char *p;
  p = write_chain_urdf("zero_axis", "revolute", ORIGIN_OK, "<axis xyz=\"0 0 0\"/>", LIMIT_OK);
  expect_chain_error(p, "a", "c", MODEL_E_CHAIN, "'j2'");
  p = write_chain_urdf("swapped", "revolute", ORIGIN_OK, AXIS_OK,
                       "<limit lower=\"1\" upper=\"-1\" velocity=\"2\" effort=\"1\"/>");
  expect_chain_error(p, "a", "c", MODEL_E_CHAIN, "'j2': lower limit");
  p = write_chain_urdf("negvel", "revolute", ORIGIN_OK, AXIS_OK,
                       "<limit lower=\"-1\" upper=\"1\" velocity=\"-2\" effort=\"1\"/>");
  expect_chain_error(p, "a", "c", MODEL_E_CHAIN, "'j2': velocity");
  p = write_chain_urdf("floating", "floating", ORIGIN_OK, "", "");
  expect_chain_error(p, "a", "c", MODEL_E_CHAIN, "'j2' is floating");
  /* Bad numbers: urdfdom rejects them while parsing (its message names the joint). */
  p = write_chain_urdf("nan_origin", "revolute", "<origin xyz=\"0 nan 0\"/>", AXIS_OK, LIMIT_OK);
  expect_chain_error(p, "a", "c", MODEL_E_PARSE, "j2");
  p = write_chain_urdf("word_limit", "revolute", ORIGIN_OK, AXIS_OK,
                       "<limit lower=\"-one\" upper=\"1\" velocity=\"2\" effort=\"1\"/>");
  expect_chain_error(p, "a", "c", MODEL_E_PARSE, "j2");
  p = write_chain_urdf("no_limit", "revolute", ORIGIN_OK, AXIS_OK, "");
  expect_chain_error(p, "a", "c", MODEL_E_PARSE, "j2");
  /* The arm loader wants exactly 7 revolute joints. */
  placement_arm_t arm;
  placement_error_t perr = {{0}};
  ck_assert_int_eq(placement_arm_load(&arm, good, "a", "c", &perr), PLACEMENT_E_MODEL);
  ck_assert_ptr_nonnull(strstr(perr.msg, "2 moving joints"));
  ck_assert_int_eq(placement_arm_load(&arm, YUMI_URDF, "yumi_body", "yumi_link_5_r", &perr),
                   PLACEMENT_E_MODEL);
  ck_assert_int_eq(placement_arm_load(&arm, YUMI_URDF, "yumi_body", "nope", &perr),
                   PLACEMENT_E_MODEL);
  ck_assert_ptr_nonnull(strstr(perr.msg, "nope"));
  ck_assert_int_eq(placement_arm_load(&arm, YUMI_URDF, "yumi_link_1_r", "yumi_tcp_r", &perr),
                   PLACEMENT_E_MODEL); /* 6 joints */
  ck_assert_int_eq(placement_arm_load(NULL, YUMI_URDF, "a", "b", &perr), PLACEMENT_E_ARG);
}
END_TEST

/* ---- FK -------------------------------------------------------------------------------------- */

/* RobotStudio tool0 poses in one arm's base frame B (rpiRobotics/yumi-ik
 * unit_tests/compare_to_robotstudio.m, via the kinematics reference section 5.1). q in chain order
 * (deg), p (mm), R = Rz(Y) Ry(P) Rx(R) with (R, P, Y) in deg. */
static const struct {
  double q[7], p[3], rpy[3];
} robotstudio[10] = {
    {{0, 0, 0, 0, 0, 0, 0}, {341.5, 0, 598}, {0, 90, 0}},
    {{20, 20, 20, 20, 20, 20, 20}, {292.46, 234.73, 348.75}, {148.67, 16.13, 175.45}},
    {{30, 30, 30, 30, 30, 30, 30}, {165.49, 290.86, 255.37}, {157.34, -19.80, -175.99}},
    {{-40, -40, -40, -40, -40, -40, -40}, {-219.17, 12.62, 796.12}, {13.67, -3.39, -152.29}},
    {{-80, -80, -80, -80, -80, -80, -80}, {-126.60, 499.23, 441.88}, {5.30, 17.08, 34.27}},
    {{104, -31, 1, -18, -55, 117, 69}, {32.02, 91.43, 763.94}, {157.59, 43.43, 170.70}},
    {{162, 1, -23, -88, 241, 98, -44}, {45.84, 32.22, 846.74}, {-98.58, 43.30, -76.21}},
    {{-20, -139, -144, 77, -263, 128, -104}, {-47.12, -136.89, 270.77}, {-106.88, -60.36, 122.56}},
    {{67, -142, 121, 78, -38, 113, -194}, {-100.23, 3.25, 338.01}, {43.05, -59.81, 44.29}},
    {{-58, -138, -35, 70, -283, 133, 207}, {-123.66, 141.01, 425.04}, {-118.25, -37.89, -10.09}},
};

START_TEST(test_fk_robotstudio) {
  const placement_side_t side = (placement_side_t)_i;
  placement_arm_t arm;
  load_arm(&arm,
           side == PLACEMENT_ARM_LEFT ? PLACEMENT_YUMI_TOOL0_LEFT : PLACEMENT_YUMI_TOOL0_RIGHT);
  /* B = joint 1's frame at q1 = 0, turned by pi about z and moved 0.206 m down its axis. */
  placement_pose_t b = arm.origin[0], shift, b_inv;
  placement_pose_identity(&shift);
  shift.rot[0][0] = shift.rot[1][1] = -1.0;
  shift.pos_m[2] = -0.206;
  placement_pose_mul(&b, &shift, &b);
  placement_pose_inverse(&b, &b_inv);
  double worst_mm = 0.0, worst_deg = 0.0;
  for (int c = 0; c < 10; ++c) {
    double q[7];
    for (int k = 0; k < 7; ++k) {
      q[k] = robotstudio[c].q[k] * DEG;
    }
    placement_pose_t tool0, in_b, ref;
    ck_assert_int_eq(placement_fk(&arm, q, &tool0), PLACEMENT_OK);
    placement_pose_mul(&b_inv, &tool0, &in_b);
    placement_rot_from_rpy(robotstudio[c].rpy[0] * DEG, robotstudio[c].rpy[1] * DEG,
                           robotstudio[c].rpy[2] * DEG, ref.rot);
    for (int i = 0; i < 3; ++i) {
      ref.pos_m[i] = robotstudio[c].p[i] * 1e-3;
    }
    double dp, dr;
    placement_pose_distance(&in_b, &ref, &dp, &dr);
    worst_mm = fmax(worst_mm, dp * 1e3);
    worst_deg = fmax(worst_deg, dr / DEG);
    ck_assert_msg(dp <= 0.01e-3 && dr <= 0.01 * DEG, "case %d: %.4f mm %.4f deg", c + 1, dp * 1e3,
                  dr / DEG);
  }
  fprintf(stderr, "FK vs RobotStudio (%s arm): max %.4f mm, %.4f deg\n",
          side == PLACEMENT_ARM_LEFT ? "left" : "right", worst_mm, worst_deg);
}
END_TEST

/* Body-frame tool0 positions of the ABB-corrected chain (kinematics reference section 7), q in
 * ABB axis order (deg), p (m) given to 1e-6 m. */
START_TEST(test_fk_body_vectors) {
  static const struct {
    placement_side_t side;
    double q_abb[7], p[3];
  } v[6] = {
      {PLACEMENT_ARM_LEFT, {0, 0, 0, 0, 0, 0, 0}, {0.567761, -0.004137, 0.414338}},
      {PLACEMENT_ARM_RIGHT, {0, 0, 0, 0, 0, 0, 0}, {0.567626, 0.005034, 0.415334}},
      {PLACEMENT_ARM_LEFT, {0, -130, 30, 0, 40, 0, 135}, {-0.010103, 0.182953, 0.198857}},
      {PLACEMENT_ARM_RIGHT, {0, -130, 30, 0, 40, 0, -135}, {-0.009599, -0.182350, 0.198403}},
      {PLACEMENT_ARM_LEFT, {20, -30, 40, -50, 60, -70, 80}, {0.219797, 0.371742, 0.359227}},
      {PLACEMENT_ARM_RIGHT, {20, -30, 40, -50, 60, -70, 80}, {0.162919, 0.007846, 0.734089}},
  };
  placement_arm_t tool0[2], tcp[2];
  load_arm(&tool0[0], PLACEMENT_YUMI_TOOL0_LEFT);
  load_arm(&tool0[1], PLACEMENT_YUMI_TOOL0_RIGHT);
  load_yumi(&tcp[0], PLACEMENT_ARM_LEFT);
  load_yumi(&tcp[1], PLACEMENT_ARM_RIGHT);
  for (int c = 0; c < 6; ++c) {
    double q_abb[7], q[7];
    for (int k = 0; k < 7; ++k) {
      q_abb[k] = v[c].q_abb[k] * DEG;
    }
    placement_chain_from_abb(q_abb, q);
    double back[7];
    placement_abb_from_chain(q, back);
    ck_assert_mem_eq(back, q_abb, sizeof back);
    placement_pose_t t0, tc;
    ck_assert_int_eq(placement_fk(&tool0[v[c].side], q, &t0), PLACEMENT_OK);
    ck_assert_int_eq(placement_fk(&tcp[v[c].side], q, &tc), PLACEMENT_OK);
    for (int i = 0; i < 3; ++i) {
      ck_assert_msg(fabs(t0.pos_m[i] - v[c].p[i]) <= 1e-6, "case %d axis %d: %.7f vs %.6f", c, i,
                    t0.pos_m[i], v[c].p[i]);
      /* TCP = tool0 + 0.1142 m along tool0 z, same orientation. */
      ck_assert_double_eq_tol(tc.pos_m[i], t0.pos_m[i] + 0.1142 * t0.rot[i][2], 1e-15);
      for (int j = 0; j < 3; ++j) {
        ck_assert_double_eq_tol(tc.rot[i][j], t0.rot[i][j], 1e-15);
      }
    }
  }
  /* The sync pose of the left arm is the right one's mirror image (ABB axes 1, 4, 7 negated) to
   * within the URDF's 4-decimal base rotations (reference: 1-2 mm). */
  double qr[7], ql[7];
  placement_yumi_nominal(PLACEMENT_ARM_RIGHT, qr);
  placement_yumi_nominal(PLACEMENT_ARM_LEFT, ql);
  ck_assert_double_eq_tol(qr[2], -135.0 * DEG, 1e-12);
  ck_assert_double_eq_tol(ql[2], 135.0 * DEG, 1e-12);
  placement_pose_t pr, pl;
  placement_fk(&tcp[1], qr, &pr);
  placement_fk(&tcp[0], ql, &pl);
  ck_assert_double_eq_tol(pr.pos_m[0], pl.pos_m[0], 3e-3);
  ck_assert_double_eq_tol(pr.pos_m[1], -pl.pos_m[1], 3e-3);
  ck_assert_double_eq_tol(pr.pos_m[2], pl.pos_m[2], 3e-3);
}
END_TEST

START_TEST(test_fk_jacobian_and_inputs) {
  placement_arm_t arm;
  load_yumi(&arm, PLACEMENT_ARM_RIGHT);
  uint64_t rng = 7;
  for (int n = 0; n < 50; ++n) {
    double q[7], jac[6][7];
    random_q(&arm, &rng, q);
    ck_assert_int_eq(placement_arm_check(&arm, q), PLACEMENT_OK);
    ck_assert_int_eq(placement_jacobian(&arm, q, jac), PLACEMENT_OK);
    placement_pose_t t0;
    placement_fk(&arm, q, &t0);
    for (int k = 0; k < 7; ++k) {
      const double h = 1e-6;
      double qp[7], qm[7];
      memcpy(qp, q, sizeof qp);
      memcpy(qm, q, sizeof qm);
      qp[k] += h;
      qm[k] -= h;
      placement_pose_t tp, tm;
      placement_fk(&arm, qp, &tp);
      placement_fk(&arm, qm, &tm);
      for (int i = 0; i < 3; ++i) {
        ck_assert_double_eq_tol(jac[i][k], (tp.pos_m[i] - tm.pos_m[i]) / (2 * h), 1e-8);
      }
      /* angular velocity: (dR/dq) R^T is skew with vector jac[3..5][k] */
      double w[3][3];
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
          w[i][j] = 0.0;
          for (int m = 0; m < 3; ++m) {
            w[i][j] += (tp.rot[i][m] - tm.rot[i][m]) / (2 * h) * t0.rot[j][m];
          }
        }
      }
      ck_assert_double_eq_tol(jac[3][k], w[2][1], 1e-8);
      ck_assert_double_eq_tol(jac[4][k], w[0][2], 1e-8);
      ck_assert_double_eq_tol(jac[5][k], w[1][0], 1e-8);
    }
  }
  double q[7] = {0, -1, 0, 0, 0, 0, 0};
  placement_pose_t t;
  ck_assert_int_eq(placement_fk(NULL, q, &t), PLACEMENT_E_ARG);
  ck_assert_int_eq(placement_fk(&arm, NULL, &t), PLACEMENT_E_ARG);
  ck_assert_int_eq(placement_fk(&arm, q, NULL), PLACEMENT_E_ARG);
  q[3] = NAN;
  ck_assert_int_eq(placement_fk(&arm, q, &t), PLACEMENT_E_NONFINITE);
  ck_assert_int_eq(placement_arm_check(&arm, q), PLACEMENT_E_NONFINITE);
  q[3] = INFINITY;
  ck_assert_int_eq(placement_fk(&arm, q, &t), PLACEMENT_E_NONFINITE);
  q[3] = 0.0;
  q[1] = 1.0; /* above +43.5 deg */
  ck_assert_int_eq(placement_arm_check(&arm, q), PLACEMENT_E_LIMITS);
  ck_assert_str_ne(placement_status_str(PLACEMENT_E_NO_SOLUTION), "");
  ck_assert_str_eq(placement_status_str((placement_status_t)42), "unknown placement status");
}
END_TEST

/* ---- IK -------------------------------------------------------------------------------------- */

/* FK(IK(FK(q))) over random q within the limits, from the nominal seed. */
START_TEST(test_ik_round_trip) {
  const placement_side_t side = (placement_side_t)_i;
  placement_arm_t arm;
  load_yumi(&arm, side);
  uint64_t rng = 1234u + (uint64_t)side;
  const placement_ik_config_t cfg = PLACEMENT_IK_CONFIG_INIT;
  unsigned failures = 0, seeds_max = 0;
  double worst_p = 0.0, worst_r = 0.0;
  unsigned long iterations = 0;
  for (int n = 0; n < PLACEMENT_TEST_IK_POSES; ++n) {
    double q[7];
    random_q(&arm, &rng, q);
    placement_pose_t target, got;
    placement_fk(&arm, q, &target);
    placement_ik_result_t res;
    placement_status_t st = placement_ik(&arm, &target, NULL, &cfg, &res);
    iterations += res.iterations;
    if (st != PLACEMENT_OK) {
      ++failures;
      ck_assert_int_eq(st, PLACEMENT_E_NO_SOLUTION);
      continue;
    }
    seeds_max = res.seeds > seeds_max ? res.seeds : seeds_max;
    ck_assert_int_eq(placement_arm_check(&arm, res.q_rad), PLACEMENT_OK);
    ck_assert_int_eq(placement_fk(&arm, res.q_rad, &got), PLACEMENT_OK);
    double dp, dr;
    placement_pose_distance(&got, &target, &dp, &dr);
    worst_p = fmax(worst_p, dp);
    worst_r = fmax(worst_r, dr);
    ck_assert_msg(dp <= 1e-6 && dr <= 1e-6, "pose %d: %g m %g rad", n, dp, dr);
    ck_assert(dp <= res.pos_err_m + 1e-15 && dr <= res.rot_err_rad + 1e-15);
  }
  fprintf(stderr,
          "IK round trip (%s arm): %d poses, %u failures, worst %.2g m %.2g rad, "
          "%.1f iterations/pose, max seeds %u\n",
          side == PLACEMENT_ARM_LEFT ? "left" : "right", PLACEMENT_TEST_IK_POSES, failures, worst_p,
          worst_r, (double)iterations / PLACEMENT_TEST_IK_POSES, seeds_max);
  ck_assert_uint_eq(failures, 0);
}
END_TEST

/* Determinant of a 6x6 matrix (Gaussian elimination with partial pivoting). */
static double det6(double m[6][6]) {
  double det = 1.0;
  for (int c = 0; c < 6; ++c) {
    int p = c;
    for (int r = c + 1; r < 6; ++r) {
      p = fabs(m[r][c]) > fabs(m[p][c]) ? r : p;
    }
    if (m[p][c] == 0.0) {
      return 0.0;
    }
    if (p != c) {
      for (int k = 0; k < 6; ++k) {
        double t = m[c][k];
        m[c][k] = m[p][k];
        m[p][k] = t;
      }
      det = -det;
    }
    det *= m[c][c];
    for (int r = c + 1; r < 6; ++r) {
      double f = m[r][c] / m[c][c];
      for (int k = c; k < 6; ++k) {
        m[r][k] -= f * m[c][k];
      }
    }
  }
  return det;
}

/* Unit vector spanning the Jacobian's nullspace: the signed 6x6 minors (generalised cross
 * product of the six rows). */
static void nullspace_dir(const placement_arm_t *arm, const double q[7], double dir[7]) {
  double jac[6][7], n2 = 0.0;
  ck_assert_int_eq(placement_jacobian(arm, q, jac), PLACEMENT_OK);
  for (int k = 0; k < 7; ++k) {
    double m[6][6];
    for (int i = 0; i < 6; ++i) {
      for (int j = 0, c = 0; j < 7; ++j) {
        if (j != k) {
          m[i][c++] = jac[i][j];
        }
      }
    }
    dir[k] = (k % 2 ? -1.0 : 1.0) * det6(m);
    n2 += dir[k] * dir[k];
  }
  ck_assert_double_gt(n2, 0.0);
  for (int k = 0; k < 7; ++k) {
    dir[k] /= sqrt(n2);
  }
}

START_TEST(test_ik_redundancy_and_limits) {
  placement_arm_t arm;
  load_yumi(&arm, PLACEMENT_ARM_RIGHT);
  placement_ik_result_t res;
  placement_pose_t target;
  /* The nominal posture's own pose comes back as the nominal posture. */
  placement_fk(&arm, arm.nominal_rad, &target);
  ck_assert_int_eq(placement_ik(&arm, &target, NULL, NULL, &res), PLACEMENT_OK);
  for (int k = 0; k < 7; ++k) {
    ck_assert_double_eq_tol(res.q_rad[k], arm.nominal_rad[k], 1e-6);
  }
  ck_assert_uint_eq(res.seeds, 1);
  /* Redundancy: another posture on the same pose's self-motion manifold (reached without the
   * nullspace phase by nudging ABB axis 7 = q[2] and projecting back) is pulled to nominal. */
  placement_ik_config_t cfg = PLACEMENT_IK_CONFIG_INIT;
  cfg.nullspace_gain = 0.0;
  double seed[7], other[7];
  memcpy(other, arm.nominal_rad, sizeof other);
  double prev_dir[7] = {0};
  for (int n = 0; n < 20; ++n) { /* walk 0.03 rad along the nullspace, project back */
    double dir[7];
    nullspace_dir(&arm, other, dir);
    double dot = 0.0;
    for (int k = 0; k < 7; ++k) {
      dot += dir[k] * prev_dir[k];
    }
    for (int k = 0; k < 7; ++k) {
      dir[k] = dot < 0.0 ? -dir[k] : dir[k];
      seed[k] = other[k] + 0.03 * dir[k];
    }
    memcpy(prev_dir, dir, sizeof dir);
    ck_assert_int_eq(placement_ik(&arm, &target, seed, &cfg, &res), PLACEMENT_OK);
    memcpy(other, res.q_rad, sizeof other);
  }
  double away = 0.0;
  for (int k = 0; k < 7; ++k) {
    away += (other[k] - arm.nominal_rad[k]) * (other[k] - arm.nominal_rad[k]);
  }
  ck_assert_double_gt(sqrt(away), 0.3);
  ck_assert_int_eq(placement_ik(&arm, &target, other, NULL, &res), PLACEMENT_OK);
  for (int k = 0; k < 7; ++k) {
    ck_assert_double_eq_tol(res.q_rad[k], arm.nominal_rad[k], 1e-3);
  }
  /* Without the pull, a seed that already solves the pose is returned as it is. */
  ck_assert_int_eq(placement_ik(&arm, &target, other, &cfg, &res), PLACEMENT_OK);
  ck_assert_mem_eq(res.q_rad, other, sizeof other);
  double q[7];
  /* Narrowed limits are respected: forbid the solution's q[0] region. */
  uint64_t rng = 99;
  for (int n = 0; n < 200; ++n) {
    random_q(&arm, &rng, q);
    placement_fk(&arm, q, &target);
    placement_arm_t narrow = arm;
    narrow.lower_rad[0] = q[0] - 0.2;
    narrow.upper_rad[0] = q[0] + 0.2;
    narrow.lower_rad[4] = q[4] - 0.5;
    narrow.upper_rad[4] = q[4] + 0.5;
    placement_status_t st = placement_ik(&narrow, &target, NULL, NULL, &res);
    ck_assert(st == PLACEMENT_OK || st == PLACEMENT_E_NO_SOLUTION);
    if (st == PLACEMENT_OK) {
      ck_assert_int_eq(placement_arm_check(&narrow, res.q_rad), PLACEMENT_OK);
    }
  }
}
END_TEST

/* Distance of the TCP from joint 1's origin. */
static double tcp_radius(const placement_arm_t *arm, const double q[7]) {
  placement_pose_t t;
  placement_fk(arm, q, &t);
  double d[3] = {t.pos_m[0] - arm->origin[0].pos_m[0], t.pos_m[1] - arm->origin[0].pos_m[1],
                 t.pos_m[2] - arm->origin[0].pos_m[2]};
  return sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

START_TEST(test_ik_unreachable) {
  placement_arm_t arm;
  load_yumi(&arm, PLACEMENT_ARM_LEFT);
  ck_assert_double_gt(arm.reach_m, 0.6);
  ck_assert_double_lt(arm.reach_m, 0.9);
  placement_ik_result_t res;
  placement_pose_t target;
  placement_fk(&arm, arm.nominal_rad, &target);
  /* Far away in front. */
  placement_pose_t far = target;
  far.pos_m[0] = 2.0;
  ck_assert_int_eq(placement_ik(&arm, &far, NULL, NULL, &res), PLACEMENT_E_OUT_OF_REACH);
  /* Behind the robot, at the floor. */
  placement_pose_t behind = target;
  behind.pos_m[0] = -0.6;
  behind.pos_m[1] = 0.0;
  behind.pos_m[2] = -0.2;
  placement_status_t st = placement_ik(&arm, &behind, NULL, NULL, &res);
  ck_assert_msg(st == PLACEMENT_E_OUT_OF_REACH || st == PLACEMENT_E_NO_SOLUTION, "%s",
                placement_status_str(st));
  /* Within the distance bound but beyond the real workspace: the solver has to say so. The
   * largest sampled distance of the TCP from joint 1 (random postures, then a local ascent) stays
   * clear of the bound; targets between the two are unreachable but not provably so. */
  uint64_t rng = 5;
  double best_q[7], max_r = 0.0;
  for (int n = 0; n < 20000; ++n) {
    double q[7];
    random_q(&arm, &rng, q);
    double r = tcp_radius(&arm, q);
    if (r > max_r) {
      max_r = r;
      memcpy(best_q, q, sizeof best_q);
    }
  }
  for (double h = 0.1; h > 1e-4; h *= 0.5) { /* coordinate ascent */
    for (int pass = 0, moved = 1; moved && pass < 100; ++pass) {
      moved = 0;
      for (int k = 0; k < 7; ++k) {
        for (int sgn = -1; sgn <= 1; sgn += 2) {
          double q[7];
          memcpy(q, best_q, sizeof q);
          q[k] += sgn * h;
          if (placement_arm_check(&arm, q) == PLACEMENT_OK && tcp_radius(&arm, q) > max_r) {
            max_r = tcp_radius(&arm, q);
            memcpy(best_q, q, sizeof best_q);
            moved = 1;
          }
        }
      }
    }
  }
  fprintf(stderr, "left TCP reach from joint 1: sampled max %.4f m, bound %.4f m\n", max_r,
          arm.reach_m);
  const double radius = arm.reach_m - 0.002;
  ck_assert_double_lt(max_r + 0.005, radius);
  placement_ik_config_t cfg = PLACEMENT_IK_CONFIG_INIT;
  cfg.max_seeds = 8;
  for (int n = 0; n < 5; ++n) {
    placement_pose_t t = target;
    double dir[3] = {cl_rng_range(&rng, -1, 1), cl_rng_range(&rng, -1, 1),
                     cl_rng_range(&rng, -1, 1)};
    double len = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
    for (int i = 0; i < 3; ++i) {
      t.pos_m[i] = arm.origin[0].pos_m[i] + radius * dir[i] / len;
    }
    st = placement_ik(&arm, &t, NULL, &cfg, &res);
    ck_assert_int_eq(st, PLACEMENT_E_NO_SOLUTION);
    ck_assert_double_gt(res.pos_err_m, 1e-3);
    ck_assert_uint_eq(res.seeds, 8);
  }
}
END_TEST

START_TEST(test_ik_bad_input) {
  placement_arm_t arm;
  load_yumi(&arm, PLACEMENT_ARM_RIGHT);
  placement_ik_result_t res;
  placement_pose_t target;
  placement_fk(&arm, arm.nominal_rad, &target);
  placement_pose_t bad = target;
  bad.pos_m[1] = NAN;
  ck_assert_int_eq(placement_ik(&arm, &bad, NULL, NULL, &res), PLACEMENT_E_NONFINITE);
  bad = target;
  bad.rot[2][2] = INFINITY;
  ck_assert_int_eq(placement_ik(&arm, &bad, NULL, NULL, &res), PLACEMENT_E_NONFINITE);
  double seed[7];
  memcpy(seed, arm.nominal_rad, sizeof seed);
  seed[6] = NAN;
  ck_assert_int_eq(placement_ik(&arm, &target, seed, NULL, &res), PLACEMENT_E_NONFINITE);
  bad = target;
  bad.rot[0][0] *= 1.01;
  ck_assert_int_eq(placement_ik(&arm, &bad, NULL, NULL, &res), PLACEMENT_E_ROTATION);
  bad = target;
  for (int j = 0; j < 3; ++j) {
    bad.rot[0][j] = -bad.rot[0][j]; /* a reflection */
  }
  ck_assert_int_eq(placement_ik(&arm, &bad, NULL, NULL, &res), PLACEMENT_E_ROTATION);
  ck_assert_int_eq(placement_ik(NULL, &target, NULL, NULL, &res), PLACEMENT_E_ARG);
  ck_assert_int_eq(placement_ik(&arm, NULL, NULL, NULL, &res), PLACEMENT_E_ARG);
  ck_assert_int_eq(placement_ik(&arm, &target, NULL, NULL, NULL), PLACEMENT_E_ARG);
  placement_ik_config_t cfg = PLACEMENT_IK_CONFIG_INIT;
  cfg.tol_pos_m = 0.0;
  ck_assert_int_eq(placement_ik(&arm, &target, NULL, &cfg, &res), PLACEMENT_E_ARG);
  cfg = (placement_ik_config_t)PLACEMENT_IK_CONFIG_INIT;
  cfg.max_seeds = 0;
  ck_assert_int_eq(placement_ik(&arm, &target, NULL, &cfg, &res), PLACEMENT_E_ARG);
  cfg = (placement_ik_config_t)PLACEMENT_IK_CONFIG_INIT;
  cfg.nullspace_gain = NAN;
  ck_assert_int_eq(placement_ik(&arm, &target, NULL, &cfg, &res), PLACEMENT_E_ARG);
  /* A seed outside the limits is clamped, not an error. */
  seed[6] = 100.0;
  ck_assert_int_eq(placement_ik(&arm, &target, seed, NULL, &res), PLACEMENT_OK);
}
END_TEST

START_TEST(test_pose_helpers) {
  uint64_t rng = 3;
  for (int n = 0; n < 200; ++n) {
    double rpy[3] = {cl_rng_range(&rng, -3, 3), cl_rng_range(&rng, -1.5, 1.5),
                     cl_rng_range(&rng, -3, 3)};
    placement_pose_t a, inv, id;
    placement_rot_from_rpy(rpy[0], rpy[1], rpy[2], a.rot);
    double back[3];
    placement_pose_rpy(&a, back);
    for (int i = 0; i < 3; ++i) {
      ck_assert_double_eq_tol(back[i], rpy[i], 1e-9);
      a.pos_m[i] = cl_rng_range(&rng, -1, 1);
    }
    placement_pose_inverse(&a, &inv);
    placement_pose_mul(&a, &inv, &id);
    double dp, dr;
    placement_pose_t ident;
    placement_pose_identity(&ident);
    placement_pose_distance(&id, &ident, &dp, &dr);
    ck_assert_double_lt(dp, 1e-14);
    ck_assert_double_lt(dr, 1e-14);
    /* the distance angle is accurate near 0 and near pi */
    double axis[3] = {0.6, 0.0, 0.8};
    placement_pose_t r = ident;
    placement_rot_from_axis_angle(axis, 1e-10, r.rot);
    placement_pose_distance(&r, &ident, NULL, &dr);
    ck_assert_double_eq_tol(dr, 1e-10, 1e-20);
    placement_rot_from_axis_angle(axis, CL_PI - 1e-7, r.rot);
    placement_pose_distance(&r, &ident, NULL, &dr);
    ck_assert_double_eq_tol(dr, CL_PI - 1e-7, 1e-12);
  }
}
END_TEST

Suite *placement_kin_suite(void) {
  Suite *s = suite_create("placement_kin");
  TCase *chain = tcase_create("chain");
  tcase_add_test(chain, test_chain_yumi);
  tcase_add_test(chain, test_chain_errors);
  suite_add_tcase(s, chain);
  TCase *fk = tcase_create("fk");
  tcase_add_loop_test(fk, test_fk_robotstudio, 0, 2);
  tcase_add_test(fk, test_fk_body_vectors);
  tcase_add_test(fk, test_fk_jacobian_and_inputs);
  tcase_add_test(fk, test_pose_helpers);
  suite_add_tcase(s, fk);
  TCase *ik = tcase_create("ik");
  tcase_set_timeout(ik, 240);
  tcase_add_loop_test(ik, test_ik_round_trip, 0, 2);
  tcase_add_test(ik, test_ik_redundancy_and_limits);
  tcase_add_test(ik, test_ik_unreachable);
  tcase_add_test(ik, test_ik_bad_input);
  suite_add_tcase(s, ik);
  return s;
}
