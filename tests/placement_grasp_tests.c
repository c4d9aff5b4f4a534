/* Top-down grasps (lib/placement/src/grasp.c, placement_grasp_plan): the grasp sent makes FK of
 * the PLACE joints land on the release pose, the nominal grasp is the documented one (tcp
 * straight down over the footprint's centre, fingers along the yaw, opening = the extent), the
 * (arm, yaw) order is the documented one, and what cannot be planned is refused with a status. */
#include <check.h>
#include <math.h>
#include <string.h>

#include "comlearn/math3d.h"
#include "comlearn/model.h"
#include "comlearn/placement.h"
#include "comlearn/placement_plan.h"
#include "placement_suites.h"

#define YUMI_URDF COMLEARN_ASSETS_DIR "/yumi/yumi.urdf"

static void load_arms(placement_arm_t arms[2]) {
  placement_error_t err = {{0}};
  ck_assert_msg(
      placement_arm_load_yumi(&arms[0], YUMI_URDF, PLACEMENT_ARM_LEFT, &err) == PLACEMENT_OK,
      "left: %s", err.msg);
  ck_assert_msg(
      placement_arm_load_yumi(&arms[1], YUMI_URDF, PLACEMENT_ARM_RIGHT, &err) == PLACEMENT_OK,
      "right: %s", err.msg);
}

static model_mesh_t box_mesh(double hx, double hy, double hz) {
  model_mesh_t m;
  const double lo[3] = {-hx, -hy, -hz}, hi[3] = {hx, hy, hz};
  ck_assert_int_eq(model_mesh_box(lo, hi, &m), MODEL_OK);
  return m;
}

/* The LCM backend's plan settings: defaults, 1 um pre-penetration. */
static void lcm_plan_config(placement_plan_config_t *cfg) {
  placement_plan_config_default(cfg);
  cfg->touch_depth_m = 1e-6;
}

/* A release pose: the box yawed by yaw_rad about block z, link origin at (x, y), touching B
 * (touch_depth_m into it, as the estimator's poses are). */
static model_pose_t release_at(const model_mesh_t *m, const placement_plan_config_t *cfg, double x,
                               double y, double yaw_rad) {
  placement_pose_t p;
  const double z_axis[3] = {0.0, 0.0, 1.0};
  placement_pose_identity(&p);
  placement_rot_from_axis_angle(z_axis, yaw_rad, p.rot);
  p.pos_m[0] = x;
  p.pos_m[1] = y;
  double z = 0.0;
  ck_assert_int_eq(placement_plan_touch_z(m, &p, cfg->block_size_m, cfg->touch_depth_m, &z),
                   PLACEMENT_OK);
  p.pos_m[2] = z;
  cl_pose_t c;
  placement_pose_to_cl_pose(&p, &c);
  model_pose_t r;
  memcpy(r.position_m, c.position_m, sizeof r.position_m);
  memcpy(r.orientation_wxyz, c.orientation_wxyz, sizeof r.orientation_wxyz);
  return r;
}

static void request_nominal(placement_grasp_request_t *req, const model_mesh_t *m,
                            const placement_arm_t arms[2], const model_pose_t *rel) {
  memset(req, 0, sizeof *req);
  req->mesh_link = m;
  req->object_in_block = *rel;
  for (int s = 0; s < 2; ++s)
    memcpy(req->q_start_rad[s], arms[s].nominal_rad, sizeof req->q_start_rad[s]);
}

/* FK(q_place) * G against block_in_base * release (yumi_body): 1e-6 m / rad as the brief asks;
 * the correction makes it rounding-exact, so 1e-12 m is asserted too. */
static void assert_reaches(const placement_arm_t arms[2], const placement_plan_config_t *cfg,
                           const model_pose_t *rel, const placement_grasp_t *g) {
  placement_pose_t tcp, grasp, got, want_b, want;
  ck_assert_int_eq(
      placement_fk(&arms[g->side], g->plan.waypoints[PLACEMENT_WAYPOINT_PLACE].q_rad, &tcp),
      PLACEMENT_OK);
  ck_assert_int_eq(placement_pose_from_cl_pose(&g->object_in_tcp, &grasp), PLACEMENT_OK);
  placement_pose_mul(&tcp, &grasp, &got);
  ck_assert_int_eq(placement_pose_from_wxyz(rel->position_m, rel->orientation_wxyz, &want_b),
                   PLACEMENT_OK);
  placement_pose_mul(&cfg->block_in_base, &want_b, &want);
  double dp, dr;
  placement_pose_distance(&got, &want, &dp, &dr);
  ck_assert_msg(dp <= 1e-6 && dr <= 1e-6, "FK * G off the release pose by %g m, %g rad", dp, dr);
  ck_assert_msg(dp <= 1e-12 && dr <= 1e-9, "FK * G not rounding-exact: %g m, %g rad", dp, dr);
  /* G differs from the nominal grasp by the IK error only */
  placement_pose_distance(&grasp, &g->object_in_tcp_nominal, &dp, &dr);
  ck_assert_msg(dp <= 1e-8 && dr <= 1e-8, "G off the nominal grasp by %g m, %g rad", dp, dr);
  ck_assert(g->object_in_tcp.orientation_wxyz[0] >= 0.0);
  for (int w = 0; w < PLACEMENT_PLAN_WAYPOINTS; ++w)
    ck_assert_int_eq(placement_arm_check(&arms[g->side], g->plan.waypoints[w].q_rad), PLACEMENT_OK);
}

/* The nominal grasp, rebuilt here from the documented rule: tcp = Rz(yaw) Rx(pi) at (centre of
 * the box footprint, top - depth); object_in_tcp = tcp^-1 * release. */
static void assert_nominal(const placement_grasp_t *g, const model_pose_t *rel,
                           const double centre[2], double top_z, double depth_m) {
  const double x_axis[3] = {1, 0, 0}, z_axis[3] = {0, 0, 1};
  double rz[3][3], rx[3][3];
  placement_rot_from_axis_angle(z_axis, g->yaw_rad, rz);
  placement_rot_from_axis_angle(x_axis, CL_PI, rx);
  placement_pose_t a, b, tcp, inv, obj, want;
  placement_pose_identity(&a);
  placement_pose_identity(&b);
  memcpy(a.rot, rz, sizeof rz);
  memcpy(b.rot, rx, sizeof rx);
  placement_pose_mul(&a, &b, &tcp);
  tcp.pos_m[0] = centre[0];
  tcp.pos_m[1] = centre[1];
  tcp.pos_m[2] = top_z - depth_m;
  double dp, dr;
  placement_pose_distance(&g->tcp_in_block, &tcp, &dp, &dr);
  ck_assert_msg(dp <= 1e-12 && dr <= 1e-12, "tcp off the rule by %g m, %g rad", dp, dr);
  /* straight down, fingers closing along (cos yaw, sin yaw, 0) */
  ck_assert_double_eq_tol(g->tcp_in_block.rot[2][2], -1.0, 1e-12);
  ck_assert_double_eq_tol(g->tcp_in_block.rot[0][0], cos(g->yaw_rad), 1e-12);
  ck_assert_double_eq_tol(g->tcp_in_block.rot[1][0], sin(g->yaw_rad), 1e-12);
  placement_pose_inverse(&tcp, &inv);
  ck_assert_int_eq(placement_pose_from_wxyz(rel->position_m, rel->orientation_wxyz, &obj),
                   PLACEMENT_OK);
  placement_pose_mul(&inv, &obj, &want);
  placement_pose_distance(&g->object_in_tcp_nominal, &want, &dp, &dr);
  ck_assert_msg(dp <= 1e-12 && dr <= 1e-12, "nominal grasp off by %g m, %g rad", dp, dr);
}

/* A 30 x 20 x 50 mm box at the -y edge (the robot's right), in the middle of B and at the +x
 * edge, unrotated and yawed 30 deg: the right arm, yaw 0 (first in the order), opening 30 mm
 * (20 mm at yaw 90), and FK * G = the release pose. */
START_TEST(grasp_reaches_release_pose) {
  placement_arm_t arms[2];
  load_arms(arms);
  placement_plan_config_t cfg;
  lcm_plan_config(&cfg);
  placement_grasp_config_t gcfg;
  placement_grasp_config_default(&gcfg);
  ck_assert_double_eq(gcfg.depth_m, 0.010);
  model_mesh_t m = box_mesh(0.015, 0.010, 0.025);
  const double poses[][3] = {
      {0.0, -0.15, 0.0}, {0.0, 0.0, 0.0}, {0.15, -0.05, 0.0}, {0.0, -0.15, CL_PI / 6.0}};
  for (size_t k = 0; k < sizeof poses / sizeof poses[0]; ++k) {
    const model_pose_t rel = release_at(&m, &cfg, poses[k][0], poses[k][1], poses[k][2]);
    ck_assert_double_eq_tol(rel.position_m[2], 0.025 - 1e-6, 1e-15);
    placement_grasp_request_t req;
    request_nominal(&req, &m, arms, &rel);
    placement_grasp_t g;
    placement_error_t err = {{0}};
    const placement_status_t st = placement_grasp_plan(arms, &cfg, &gcfg, &req, &g, &err);
    ck_assert_msg(st == PLACEMENT_OK, "pose %zu: %s (%s)", k, placement_status_str(st), err.msg);
    ck_assert_int_eq(g.side, PLACEMENT_ARM_RIGHT);
    ck_assert_uint_eq(g.attempts, 1);
    ck_assert_double_eq(g.yaw_rad, 0.0);
    /* the block-frame box of a yawed box: extent 30 cos + 20 sin along x */
    const double c = cos(poses[k][2]), s = sin(poses[k][2]);
    ck_assert_double_eq_tol(g.grip_width_m, 0.030 * c + 0.020 * s, 1e-15);
    const double centre[2] = {poses[k][0], poses[k][1]};
    assert_nominal(&g, &rel, centre, rel.position_m[2] + 0.025, gcfg.depth_m);
    assert_reaches(arms, &cfg, &rel, &g);
    /* the plan is placement_plan_build's for this grasp: PLACE puts the object at the request */
    ck_assert_double_eq_tol(g.plan.object_in_block.pos_m[2], rel.position_m[2], 1e-12);
    ck_assert_double_eq(g.plan.waypoints[PLACEMENT_WAYPOINT_PLACE].gripper_width_m, g.grip_width_m);
  }
  model_mesh_free(&m);
}
END_TEST

/* The order: the right arm cannot start (joints outside its limits), so the left arm plans, with
 * yaw 0, on the 5th attempt (after the right arm's four yaws); both arms out of their limits:
 * the last attempt's status. */
START_TEST(grasp_falls_back_to_the_left_arm) {
  placement_arm_t arms[2];
  load_arms(arms);
  placement_plan_config_t cfg;
  lcm_plan_config(&cfg);
  const placement_grasp_config_t gcfg = PLACEMENT_GRASP_CONFIG_INIT;
  model_mesh_t m = box_mesh(0.015, 0.010, 0.025);
  const model_pose_t rel = release_at(&m, &cfg, 0.0, 0.10, 0.0);
  placement_grasp_request_t req;
  request_nominal(&req, &m, arms, &rel);
  req.q_start_rad[PLACEMENT_ARM_RIGHT][0] = arms[PLACEMENT_ARM_RIGHT].upper_rad[0] + 0.1;
  placement_grasp_t g;
  placement_error_t err = {{0}};
  const placement_status_t st = placement_grasp_plan(arms, &cfg, &gcfg, &req, &g, &err);
  ck_assert_msg(st == PLACEMENT_OK, "%s (%s)", placement_status_str(st), err.msg);
  ck_assert_int_eq(g.side, PLACEMENT_ARM_LEFT);
  ck_assert_uint_eq(g.attempts, 5);
  ck_assert_double_eq(g.yaw_rad, 0.0);
  assert_reaches(arms, &cfg, &rel, &g);
  req.q_start_rad[PLACEMENT_ARM_LEFT][0] = arms[PLACEMENT_ARM_LEFT].lower_rad[0] - 0.1;
  ck_assert_int_eq(placement_grasp_plan(arms, &cfg, &gcfg, &req, &g, &err), PLACEMENT_E_LIMITS);
  model_mesh_free(&m);
}
END_TEST

/* A flat plate (10 mm): the tcp would be at 0 mm; it stays tip_length + tip_clear (25.7 mm)
 * above B, so the finger tips keep 4 mm. A 100 mm wide box: the opening is capped at
 * gripper_max_width - release_opening (40 mm); a 2 mm stick: at least min_width (5 mm). */
START_TEST(grasp_height_and_width_limits) {
  placement_arm_t arms[2];
  load_arms(arms);
  placement_plan_config_t cfg;
  lcm_plan_config(&cfg);
  const placement_grasp_config_t gcfg = PLACEMENT_GRASP_CONFIG_INIT;
  const double dims[3][3] = {{0.015, 0.015, 0.005}, {0.050, 0.010, 0.025}, {0.001, 0.010, 0.025}};
  const double width_want[3] = {0.030, 0.040, 0.005};
  for (int k = 0; k < 3; ++k) {
    model_mesh_t m = box_mesh(dims[k][0], dims[k][1], dims[k][2]);
    const model_pose_t rel = release_at(&m, &cfg, 0.0, -0.10, 0.0);
    placement_grasp_request_t req;
    request_nominal(&req, &m, arms, &rel);
    placement_grasp_t g;
    placement_error_t err = {{0}};
    const placement_status_t st = placement_grasp_plan(arms, &cfg, &gcfg, &req, &g, &err);
    ck_assert_msg(st == PLACEMENT_OK, "box %d: %s (%s)", k, placement_status_str(st), err.msg);
    ck_assert_double_eq(g.yaw_rad, 0.0);
    ck_assert_double_eq_tol(g.grip_width_m, width_want[k], 1e-15);
    const double top = rel.position_m[2] + dims[k][2];
    const double z_want = k == 0 ? gcfg.tip_length_m + gcfg.tip_clear_m : top - gcfg.depth_m;
    ck_assert_double_eq_tol(g.tcp_in_block.pos_m[2], z_want, 1e-15);
    assert_reaches(arms, &cfg, &rel, &g);
    model_mesh_free(&m);
  }
}
END_TEST

/* Refusals: B 1.5 m away (no yaw of either arm reaches: PLACEMENT_E_OUT_OF_REACH after all 8),
 * a release quaternion of norm 1.1, a NaN, bad settings, NULLs, an empty mesh: a status and *out
 * untouched. */
START_TEST(grasp_refusals) {
  placement_arm_t arms[2];
  load_arms(arms);
  placement_plan_config_t cfg;
  lcm_plan_config(&cfg);
  const placement_grasp_config_t gcfg = PLACEMENT_GRASP_CONFIG_INIT;
  model_mesh_t m = box_mesh(0.015, 0.010, 0.025);
  const model_pose_t rel = release_at(&m, &cfg, 0.0, 0.0, 0.0);
  placement_grasp_request_t req;
  request_nominal(&req, &m, arms, &rel);
  placement_grasp_t g, sentinel;
  memset(&sentinel, 0xA5, sizeof sentinel);
  placement_error_t err = {{0}};
#define REFUSED(call, status)                  \
  do {                                         \
    g = sentinel;                              \
    ck_assert_int_eq((call), (status));        \
    ck_assert_mem_eq(&g, &sentinel, sizeof g); \
  } while (0)
  placement_plan_config_t far = cfg;
  far.block_in_base.pos_m[0] = 1.5;
  err.msg[0] = '\0';
  REFUSED(placement_grasp_plan(arms, &far, &gcfg, &req, &g, &err), PLACEMENT_E_OUT_OF_REACH);
  ck_assert(err.msg[0] != '\0');
  placement_grasp_request_t bad = req;
  for (int i = 0; i < 4; ++i) bad.object_in_block.orientation_wxyz[i] *= 1.1;
  REFUSED(placement_grasp_plan(arms, &cfg, &gcfg, &bad, &g, &err), PLACEMENT_E_ROTATION);
  bad = req;
  bad.object_in_block.position_m[1] = NAN;
  REFUSED(placement_grasp_plan(arms, &cfg, &gcfg, &bad, &g, &err), PLACEMENT_E_NONFINITE);
  bad = req;
  bad.q_start_rad[PLACEMENT_ARM_RIGHT][3] = NAN;
  bad.q_start_rad[PLACEMENT_ARM_LEFT][3] = NAN;
  REFUSED(placement_grasp_plan(arms, &cfg, &gcfg, &bad, &g, &err), PLACEMENT_E_NONFINITE);
  placement_grasp_config_t gbad = gcfg;
  gbad.depth_m = -0.001;
  REFUSED(placement_grasp_plan(arms, &cfg, &gbad, &req, &g, &err), PLACEMENT_E_ARG);
  gbad = gcfg;
  gbad.min_width_m = INFINITY;
  REFUSED(placement_grasp_plan(arms, &cfg, &gbad, &req, &g, &err), PLACEMENT_E_NONFINITE);
  placement_plan_config_t cbad = cfg;
  cbad.velocity_fraction = 0.0;
  REFUSED(placement_grasp_plan(arms, &cbad, &gcfg, &req, &g, &err), PLACEMENT_E_ARG);
  REFUSED(placement_grasp_plan(NULL, &cfg, &gcfg, &req, &g, &err), PLACEMENT_E_ARG);
  REFUSED(placement_grasp_plan(arms, NULL, &gcfg, &req, &g, &err), PLACEMENT_E_ARG);
  REFUSED(placement_grasp_plan(arms, &cfg, NULL, &req, &g, &err), PLACEMENT_E_ARG);
  REFUSED(placement_grasp_plan(arms, &cfg, &gcfg, NULL, &g, &err), PLACEMENT_E_ARG);
  ck_assert_int_eq(placement_grasp_plan(arms, &cfg, &gcfg, &req, NULL, NULL), PLACEMENT_E_ARG);
  model_mesh_t empty = m;
  empty.vertex_count = 0;
  bad = req;
  bad.mesh_link = &empty;
  REFUSED(placement_grasp_plan(arms, &cfg, &gcfg, &bad, &g, NULL), PLACEMENT_E_ARG);
#undef REFUSED
  model_mesh_free(&m);
}
END_TEST

Suite *placement_grasp_suite(void) {
  Suite *s = suite_create("placement_grasp");
  TCase *tc = tcase_create("grasp");
  tcase_set_timeout(tc, 120);
  tcase_add_test(tc, grasp_reaches_release_pose);
  tcase_add_test(tc, grasp_falls_back_to_the_left_arm);
  tcase_add_test(tc, grasp_height_and_width_limits);
  tcase_add_test(tc, grasp_refusals);
  suite_add_tcase(s, tc);
  return s;
}
