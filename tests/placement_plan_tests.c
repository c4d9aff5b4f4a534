/* Placement plans (lib/placement/src/plan.c): waypoints against FK, exact touching height,
 * durations from the velocity limits, and bad input that must leave the output untouched. */
#include <check.h>
#include <math.h>
#include <string.h>

#include "comlearn/math3d.h"
#include "comlearn/model.h"
#include "comlearn/placement.h"
#include "comlearn/placement_plan.h"

Suite *placement_plan_suite(void);

#define YUMI_URDF COMLEARN_ASSETS_DIR "/yumi/yumi.urdf"

/* The test object: a 40 x 60 x 50 mm box, link origin at its centre. */
static const double BOX_HALF[3] = {0.020, 0.030, 0.025};

static model_mesh_t box_mesh(const double half[3]) {
  model_mesh_t m;
  const double lo[3] = {-half[0], -half[1], -half[2]};
  ck_assert_int_eq(model_mesh_box(lo, half, &m), MODEL_OK);
  return m;
}

static void load_arm(placement_side_t side, placement_arm_t *arm) {
  placement_error_t err = {{0}};
  const placement_status_t st = placement_arm_load_yumi(arm, YUMI_URDF, side, &err);
  ck_assert_msg(st == PLACEMENT_OK, "arm load: %s", err.msg);
}

static void rot_z(double yaw, double r[3][3]) {
  const double axis[3] = {0.0, 0.0, 1.0};
  placement_rot_from_axis_angle(axis, yaw, r);
}

/* Top-down grasp: tcp z along the object's -z, fingers closing along the object's x (40 mm);
 * the tcp 15 mm below the object's top face (object centre 10 mm further along tcp z). */
static void grasp_top(placement_pose_t *object_in_tcp, double depth_below_top_m) {
  placement_pose_identity(object_in_tcp);
  object_in_tcp->rot[1][1] = -1.0;
  object_in_tcp->rot[2][2] = -1.0;
  object_in_tcp->pos_m[2] = BOX_HALF[2] - depth_below_top_m;
}

/* The object point (link origin) over `edge` (0 +x, 1 -x, 2 +y, 3 -y) at `along`, box yawed by
 * yaw about the block z. */
static void target_over_edge(const placement_plan_config_t *cfg, int edge, double along, double yaw,
                             placement_pose_t *obj) {
  placement_pose_identity(obj);
  rot_z(yaw, obj->rot);
  const double hx = 0.5 * cfg->block_size_m[0], hy = 0.5 * cfg->block_size_m[1];
  switch (edge) {
    case 0:
      obj->pos_m[0] = hx;
      obj->pos_m[1] = along;
      break;
    case 1:
      obj->pos_m[0] = -hx;
      obj->pos_m[1] = along;
      break;
    case 2:
      obj->pos_m[0] = along;
      obj->pos_m[1] = hy;
      break;
    default:
      obj->pos_m[0] = along;
      obj->pos_m[1] = -hy;
      break;
  }
  obj->pos_m[2] = 0.123; /* replaced by the plan */
}

static void request_for(placement_plan_request_t *req, const model_mesh_t *mesh,
                        const placement_arm_t *arm) {
  memset(req, 0, sizeof *req);
  req->mesh_link = mesh;
  grasp_top(&req->object_in_tcp, 0.015);
  req->grip_width_m = 0.040;
  memcpy(req->q_start_rad, arm->nominal_rad, sizeof req->q_start_rad);
}

/* Object link frame in the block at joint values q: block^-1 * FK(q) * object_in_tcp. */
static void object_in_block_at(const placement_arm_t *arm, const placement_plan_config_t *cfg,
                               const placement_plan_request_t *req, const double q[7],
                               placement_pose_t *obj) {
  placement_pose_t tcp, base_in_block, tcp_in_block;
  ck_assert_int_eq(placement_fk(arm, q, &tcp), PLACEMENT_OK);
  placement_pose_inverse(&cfg->block_in_base, &base_in_block);
  placement_pose_mul(&base_in_block, &tcp, &tcp_in_block);
  placement_pose_mul(&tcp_in_block, &req->object_in_tcp, obj);
}

static double lowest_vertex_z(const model_mesh_t *m, const placement_pose_t *p) {
  double lo = HUGE_VAL;
  for (size_t i = 0; i < m->vertex_count; ++i) {
    const double *v = m->vertices_m[i];
    const double z = p->rot[2][0] * v[0] + p->rot[2][1] * v[1] + p->rot[2][2] * v[2] + p->pos_m[2];
    if (z < lo) lo = z;
  }
  return lo;
}

static double expected_duration(const placement_arm_t *arm, const placement_plan_config_t *cfg,
                                const double *q0, const double *q1, double w0, double w1) {
  double t = cfg->min_duration_s;
  for (int k = 0; k < 7; ++k) {
    t = fmax(t, fabs(q1[k] - q0[k]) / (cfg->velocity_fraction * arm->velocity_rad_s[k]));
  }
  return fmax(t, fabs(w1 - w0) / cfg->gripper_speed_m_s);
}

/* Plan the box over every edge with the arm on that side (the far +x edge and the near -x edge
 * with both arms) at two yaws and three positions; FK of the plan's joints must put the object
 * exactly where asked. */
START_TEST(plan_each_edge_fk_exact) {
  placement_arm_t arms[2];
  load_arm(PLACEMENT_ARM_LEFT, &arms[0]);
  load_arm(PLACEMENT_ARM_RIGHT, &arms[1]);
  model_mesh_t mesh = box_mesh(BOX_HALF);
  placement_plan_config_t cfg;
  placement_plan_config_default(&cfg);
  const double hx = 0.5 * cfg.block_size_m[0], hy = 0.5 * cfg.block_size_m[1];
  /* edge -> arms: +x, -x both; +y (left side of the robot) left; -y right */
  const int edge_arm_mask[4] = {3, 3, 1, 2};
  const double yaws[2] = {0.0, 0.5 * CL_PI};
  const double alongs[3] = {-0.05, 0.0, 0.05};
  int plans = 0;
  for (int edge = 0; edge < 4; ++edge) {
    for (int a = 0; a < 2; ++a) {
      if (!(edge_arm_mask[edge] & (1 << a))) continue;
      const placement_arm_t *arm = &arms[a];
      for (int iy = 0; iy < 2; ++iy) {
        for (int ia = 0; ia < 3; ++ia) {
          placement_plan_request_t req;
          request_for(&req, &mesh, arm);
          target_over_edge(&cfg, edge, alongs[ia], yaws[iy], &req.object_in_block);
          placement_plan_t plan;
          placement_error_t err = {{0}};
          const placement_status_t st = placement_plan_build(arm, &cfg, &req, &plan, &err);
          ck_assert_msg(st == PLACEMENT_OK, "edge %d arm %d yaw %d along %g: %s (%s)", edge, a, iy,
                        alongs[ia], placement_status_str(st), err.msg);
          ++plans;
          /* The planned pose: x, y, rot as asked, z touching (the box's half height). */
          ck_assert_double_eq_tol(plan.object_in_block.pos_m[2], BOX_HALF[2], 1e-12);
          placement_pose_t obj;
          object_in_block_at(arm, &cfg, &req, plan.waypoints[PLACEMENT_WAYPOINT_PLACE].q_rad, &obj);
          const double over[4] = {obj.pos_m[0] - hx, -obj.pos_m[0] - hx, obj.pos_m[1] - hy,
                                  -obj.pos_m[1] - hy};
          const double along_got = edge < 2 ? obj.pos_m[1] : obj.pos_m[0];
          ck_assert_msg(fabs(over[edge]) <= 1e-6, "point off the edge line by %g m", over[edge]);
          ck_assert_double_eq_tol(along_got, alongs[ia], 1e-6);
          const double low = lowest_vertex_z(&mesh, &obj);
          ck_assert_msg(fabs(low) <= 1e-6, "lowest vertex %g m from B's top", low);
          double dp, dr;
          placement_pose_distance(&obj, &req.object_in_block, &dp, &dr);
          ck_assert_msg(dr <= 1e-6, "orientation off by %g rad", dr);
          /* PREPLACE and RETREAT: the tcp straight above by the configured heights. */
          placement_pose_t pre, place, ret;
          object_in_block_at(arm, &cfg, &req, plan.waypoints[0].q_rad, &pre);
          object_in_block_at(arm, &cfg, &req, plan.waypoints[1].q_rad, &place);
          object_in_block_at(arm, &cfg, &req, plan.waypoints[3].q_rad, &ret);
          ck_assert_double_eq_tol(pre.pos_m[2] - place.pos_m[2], cfg.preplace_height_m, 2e-6);
          ck_assert_double_eq_tol(pre.pos_m[0], place.pos_m[0], 2e-6);
          ck_assert_double_eq_tol(pre.pos_m[1], place.pos_m[1], 2e-6);
          ck_assert_double_eq_tol(ret.pos_m[2] - place.pos_m[2], cfg.retreat_height_m, 2e-6);
          ck_assert_double_eq_tol(ret.pos_m[0], place.pos_m[0], 2e-6);
          placement_pose_distance(&pre, &place, &dp, &dr);
          ck_assert_msg(dr <= 2e-6, "preplace turned by %g rad", dr);
          /* RELEASE: same joints, wider. */
          ck_assert_mem_eq(plan.waypoints[2].q_rad, plan.waypoints[1].q_rad, sizeof(double) * 7);
          ck_assert_double_eq(plan.waypoints[0].gripper_width_m, req.grip_width_m);
          ck_assert_double_eq(plan.waypoints[1].gripper_width_m, req.grip_width_m);
          ck_assert_double_eq_tol(plan.waypoints[2].gripper_width_m,
                                  req.grip_width_m + cfg.release_opening_m, 1e-15);
          ck_assert_double_eq(plan.waypoints[3].gripper_width_m, plan.waypoints[2].gripper_width_m);
          for (int w = 0; w < 4; ++w) {
            ck_assert_int_eq(plan.waypoints[w].kind, w);
            ck_assert_int_eq(placement_arm_check(arm, plan.waypoints[w].q_rad), PLACEMENT_OK);
          }
        }
      }
    }
  }
  ck_assert_int_eq(plans, 36);
  model_mesh_free(&mesh);
}
END_TEST

/* A rock (non-convex mesh, float vertices), tilted, its bounding-box centre over the -y edge with
 * the right arm: FK puts that point on the edge line and the rock touches B's top exactly (the
 * lowest point over B at z = 0, nothing of it below). */
START_TEST(plan_rock_touches) {
  placement_arm_t arm;
  load_arm(PLACEMENT_ARM_RIGHT, &arm);
  model_object_t rock;
  model_error_t merr;
  ck_assert_msg(model_object_load(COMLEARN_ASSETS_DIR "/rocks/rock_1_even.urdf", NULL, &rock,
                                  &merr) == MODEL_OK,
                "%s", merr.msg);
  placement_plan_config_t cfg;
  placement_plan_config_default(&cfg);
  const double hx = 0.5 * cfg.block_size_m[0], hy = 0.5 * cfg.block_size_m[1];
  /* orientation: 0.25 rad about x, then 0.6 rad about z */
  placement_pose_t obj;
  placement_rot_from_rpy(0.25, 0.0, 0.6, obj.rot);
  double pl[3];
  model_aabb_center(&rock.aabb, pl);
  const double along = 0.03;
  double rp[3];
  for (int i = 0; i < 3; ++i)
    rp[i] = obj.rot[i][0] * pl[0] + obj.rot[i][1] * pl[1] + obj.rot[i][2] * pl[2];
  obj.pos_m[0] = along - rp[0];
  obj.pos_m[1] = -hy - rp[1];
  obj.pos_m[2] = 0.2;
  /* grasp: tcp straight down, 15 mm below the rock's highest point, above the box centre */
  double top = -HUGE_VAL;
  for (size_t i = 0; i < rock.mesh.vertex_count; ++i) {
    const double *v = rock.mesh.vertices_m[i];
    top = fmax(top, obj.rot[2][0] * v[0] + obj.rot[2][1] * v[1] + obj.rot[2][2] * v[2]);
  }
  placement_pose_t tcp, block_in_tcp;
  placement_pose_identity(&tcp);
  tcp.rot[1][1] = -1.0;
  tcp.rot[2][2] = -1.0;
  tcp.pos_m[0] = along;
  tcp.pos_m[1] = -hy;
  tcp.pos_m[2] = obj.pos_m[2] + top - 0.015;
  placement_plan_request_t req;
  request_for(&req, &rock.mesh, &arm);
  placement_pose_inverse(&tcp, &block_in_tcp);
  placement_pose_mul(&block_in_tcp, &obj, &req.object_in_tcp);
  req.object_in_block = obj;
  placement_plan_t plan;
  placement_error_t err = {{0}};
  ck_assert_msg(placement_plan_build(&arm, &cfg, &req, &plan, &err) == PLACEMENT_OK, "%s", err.msg);
  placement_pose_t got;
  object_in_block_at(&arm, &cfg, &req, plan.waypoints[PLACEMENT_WAYPOINT_PLACE].q_rad, &got);
  double p[3];
  for (int i = 0; i < 3; ++i) {
    p[i] = got.rot[i][0] * pl[0] + got.rot[i][1] * pl[1] + got.rot[i][2] * pl[2] + got.pos_m[i];
  }
  ck_assert_msg(fabs(p[1] + hy) <= 1e-6, "point %g m off the -y edge line", p[1] + hy);
  ck_assert_double_eq_tol(p[0], along, 1e-6);
  /* Touching, checked independently: no vertex over B's top below it, and the lowest point over
   * B (a vertex over the top, or a mesh edge crossing the -y edge plane) at z = 0. */
  double low = HUGE_VAL;
  double w[3][3];
  for (size_t t = 0; t < rock.mesh.triangle_count; ++t) {
    for (int k = 0; k < 3; ++k) {
      const double *v = rock.mesh.vertices_m[rock.mesh.triangles[t][k]];
      for (int i = 0; i < 3; ++i) {
        w[k][i] = got.rot[i][0] * v[0] + got.rot[i][1] * v[1] + got.rot[i][2] * v[2] + got.pos_m[i];
      }
    }
    for (int k = 0; k < 3; ++k) {
      const double *a = w[k], *b = w[(k + 1) % 3];
      if (fabs(a[0]) <= hx && fabs(a[1]) <= hy) low = fmin(low, a[2]);
      if ((a[1] + hy) * (b[1] + hy) < 0.0) {
        const double u = (-hy - a[1]) / (b[1] - a[1]);
        low = fmin(low, a[2] + u * (b[2] - a[2]));
      }
    }
  }
  ck_assert_msg(fabs(low) <= 1e-6, "lowest point over B %g m from the top", low);
  ck_assert_double_eq_tol(got.pos_m[2], plan.object_in_block.pos_m[2], 1e-6);
  model_object_free(&rock);
}
END_TEST

START_TEST(plan_durations_formula) {
  placement_arm_t arm;
  load_arm(PLACEMENT_ARM_RIGHT, &arm);
  model_mesh_t mesh = box_mesh(BOX_HALF);
  placement_plan_config_t cfg;
  placement_plan_config_default(&cfg);
  cfg.velocity_fraction = 0.3;
  placement_plan_request_t req;
  request_for(&req, &mesh, &arm);
  target_over_edge(&cfg, 3, 0.02, 0.3, &req.object_in_block);
  placement_plan_t plan;
  ck_assert_int_eq(placement_plan_build(&arm, &cfg, &req, &plan, NULL), PLACEMENT_OK);
  const double *prev = req.q_start_rad;
  double prev_w = req.grip_width_m, total = 0.0;
  for (int w = 0; w < 4; ++w) {
    const placement_waypoint_t *wp = &plan.waypoints[w];
    const double t = expected_duration(&arm, &cfg, prev, wp->q_rad, prev_w, wp->gripper_width_m);
    ck_assert_double_eq_tol(wp->duration_s, t, 1e-12);
    total += t;
    prev = wp->q_rad;
    prev_w = wp->gripper_width_m;
  }
  ck_assert_double_eq_tol(plan.total_duration_s, total, 1e-12);
  /* Opening 10 mm at 25 mm/s with the joints still: 0.4 s. */
  ck_assert_double_eq_tol(plan.waypoints[2].duration_s, 0.4, 1e-12);
  /* The nominal posture is far from the target: the first segment is set by a joint limit. */
  ck_assert(plan.waypoints[0].duration_s > cfg.min_duration_s);
  /* Halving the fraction doubles every joint-limited segment. */
  placement_plan_t slow;
  cfg.velocity_fraction = 0.15;
  ck_assert_int_eq(placement_plan_build(&arm, &cfg, &req, &slow, NULL), PLACEMENT_OK);
  ck_assert_double_eq_tol(slow.waypoints[0].duration_s, 2.0 * plan.waypoints[0].duration_s, 1e-9);
  model_mesh_free(&mesh);
}
END_TEST

/* Exact touching height against analytic values. */
START_TEST(touch_z_analytic) {
  const double size[3] = {0.30, 0.30, 0.10};
  const double half[3] = {0.020, 0.030, 0.025};
  model_mesh_t mesh = box_mesh(half);
  const double th = 0.4;
  const double axis_y[3] = {0.0, 1.0, 0.0};
  double z = -1.0;
  placement_pose_t pose;
  placement_pose_identity(&pose);
  /* Tilted about y in the middle of B: the lowest corner, -(a sin + c cos). */
  placement_rot_from_axis_angle(axis_y, th, pose.rot);
  ck_assert_int_eq(placement_plan_touch_z(&mesh, &pose, size, 0.0, &z), PLACEMENT_OK);
  ck_assert_double_eq_tol(z, half[0] * sin(th) + half[2] * cos(th), 1e-15);
  ck_assert_int_eq(placement_plan_touch_z(&mesh, &pose, size, 1e-6, &z), PLACEMENT_OK);
  ck_assert_double_eq_tol(z, half[0] * sin(th) + half[2] * cos(th) - 1e-6, 1e-15);
  /* Over the +x edge with the lowest corner beyond it: the bottom face crossing x = 0.15. */
  const double x0 = 0.15 - 0.005;
  const double xl = (0.15 - x0 + half[2] * sin(th)) / cos(th);
  ck_assert(xl < half[0]); /* the crossing lies on the bottom face */
  ck_assert(x0 + half[0] * cos(th) - half[2] * sin(th) > 0.15); /* lowest corner beyond */
  pose.pos_m[0] = x0;
  ck_assert_int_eq(placement_plan_touch_z(&mesh, &pose, size, 0.0, &z), PLACEMENT_OK);
  ck_assert_double_eq_tol(z, xl * sin(th) + half[2] * cos(th), 1e-15);
  /* A plate larger than B, tilted: no vertex over B, the lowest point is B's corner under it. */
  const double plate[3] = {0.30, 0.30, 0.01};
  model_mesh_t big = box_mesh(plate);
  pose.pos_m[0] = 0.0;
  ck_assert_int_eq(placement_plan_touch_z(&big, &pose, size, 0.0, &z), PLACEMENT_OK);
  ck_assert_double_eq_tol(z, (0.15 + plate[2] * sin(th)) * tan(th) + plate[2] * cos(th), 1e-15);
  /* Entirely beside B: nothing over the top. */
  z = 7.0;
  pose.pos_m[0] = 0.5;
  ck_assert_int_eq(placement_plan_touch_z(&mesh, &pose, size, 0.0, &z), PLACEMENT_E_GEOMETRY);
  ck_assert_double_eq(z, 7.0);
  model_mesh_free(&big);
  model_mesh_free(&mesh);
}
END_TEST

/* The fingertips 21.7 mm beyond the tcp, pointing down over B: clear exactly above the
 * clearance. */
START_TEST(gripper_clear_boundary) {
  placement_plan_config_t cfg;
  placement_plan_config_default(&cfg);
  placement_pose_t tcp;
  placement_pose_identity(&tcp);
  tcp.rot[1][1] = -1.0;
  tcp.rot[2][2] = -1.0;
  const double tip = cfg.gripper.finger_z_hi_m + cfg.clearance_m;
  tcp.pos_m[2] = tip + 1e-9;
  ck_assert_int_eq(placement_plan_gripper_clear(&cfg, &tcp, 0.02), 1);
  tcp.pos_m[2] = tip - 1e-9;
  ck_assert_int_eq(placement_plan_gripper_clear(&cfg, &tcp, 0.02), 0);
  /* Tilted 30 degrees about the finger axis x: a corner of a finger tip leads. */
  const double ax[3] = {1.0, 0.0, 0.0};
  double r30[3][3], down[3][3];
  placement_rot_from_axis_angle(ax, CL_PI + CL_PI / 6.0, r30);
  memcpy(down, r30, sizeof down);
  memcpy(tcp.rot, down, sizeof down);
  const double corner = cfg.gripper.finger_z_hi_m * cos(CL_PI / 6.0) +
                        cfg.gripper.finger_half_depth_m * sin(CL_PI / 6.0) + cfg.clearance_m;
  tcp.pos_m[2] = corner + 1e-9;
  ck_assert_int_eq(placement_plan_gripper_clear(&cfg, &tcp, 0.02), 1);
  tcp.pos_m[2] = corner - 1e-9;
  ck_assert_int_eq(placement_plan_gripper_clear(&cfg, &tcp, 0.02), 0);
  /* Beside B, below its top: the +x finger's outer face against B's -x... far off: clear. */
  placement_pose_identity(&tcp);
  tcp.pos_m[0] = 0.15 + cfg.clearance_m + 0.0635 + 1e-9;
  tcp.pos_m[2] = -0.05;
  ck_assert_int_eq(placement_plan_gripper_clear(&cfg, &tcp, 0.02), 1);
  tcp.pos_m[0] -= 2e-9;
  ck_assert_int_eq(placement_plan_gripper_clear(&cfg, &tcp, 0.02), 0);
}
END_TEST

/* Bad input: a status, a message and the output untouched. */
static void expect_rejected(const placement_arm_t *arm, const placement_plan_config_t *cfg,
                            const placement_plan_request_t *req, placement_status_t want,
                            const char *what) {
  placement_plan_t out, before;
  memset(&out, 0xA5, sizeof out);
  memcpy(&before, &out, sizeof out);
  placement_error_t err = {{0}};
  const placement_status_t st = placement_plan_build(arm, cfg, req, &out, &err);
  ck_assert_msg(st == want, "%s: got %s, want %s (%s)", what, placement_status_str(st),
                placement_status_str(want), err.msg);
  ck_assert_msg(memcmp(&out, &before, sizeof out) == 0, "%s: output written", what);
  ck_assert_msg(err.msg[0] != '\0', "%s: no message", what);
}

START_TEST(plan_bad_input) {
  placement_arm_t arm;
  load_arm(PLACEMENT_ARM_LEFT, &arm);
  model_mesh_t mesh = box_mesh(BOX_HALF);
  placement_plan_config_t cfg;
  placement_plan_config_default(&cfg);
  placement_plan_request_t good, req;
  request_for(&good, &mesh, &arm);
  target_over_edge(&cfg, 0, 0.0, 0.0, &good.object_in_block);
  placement_plan_t ok;
  ck_assert_int_eq(placement_plan_build(&arm, &cfg, &good, &ok, NULL), PLACEMENT_OK);

  /* Unreachable: B 1.5 m in front of the robot. */
  placement_plan_config_t far = cfg;
  far.block_in_base.pos_m[0] = 1.5;
  expect_rejected(&arm, &far, &good, PLACEMENT_E_OUT_OF_REACH, "B out of reach");
  /* Within the reach bound (arm.reach_m, a triangle-inequality bound) but beyond the real reach:
   * the tcp 0.70 m in front of the left shoulder at its height. IK tries and fails. */
  far.block_in_base.pos_m[0] = 0.60;
  far.block_in_base.pos_m[2] = 0.39;
  expect_rejected(&arm, &far, &good, PLACEMENT_E_NO_SOLUTION, "B beyond the real reach");
  /* Into B: the tcp 35 mm below the top, the fingertips 6.7 mm below the object's bottom. */
  req = good;
  grasp_top(&req.object_in_tcp, 0.035);
  expect_rejected(&arm, &cfg, &req, PLACEMENT_E_COLLISION, "fingers below the object");
  /* Into B by the clearance only: fingertips 1 mm above B's top (clearance 2 mm). */
  req = good;
  grasp_top(&req.object_in_tcp, 0.05 - 0.001 - cfg.gripper.finger_z_hi_m);
  expect_rejected(&arm, &cfg, &req, PLACEMENT_E_COLLISION, "fingers within the clearance");
  cfg.clearance_m = 0.0005;
  placement_plan_t plan;
  ck_assert_int_eq(placement_plan_build(&arm, &cfg, &req, &plan, NULL), PLACEMENT_OK);
  cfg.clearance_m = 0.002;

  /* Non-finite. */
  req = good;
  req.object_in_block.pos_m[0] = NAN;
  expect_rejected(&arm, &cfg, &req, PLACEMENT_E_NONFINITE, "NaN target");
  req = good;
  req.object_in_tcp.rot[0][1] = INFINITY;
  expect_rejected(&arm, &cfg, &req, PLACEMENT_E_NONFINITE, "inf grasp");
  req = good;
  req.q_start_rad[3] = NAN;
  expect_rejected(&arm, &cfg, &req, PLACEMENT_E_NONFINITE, "NaN start joint");
  req = good;
  req.grip_width_m = NAN;
  expect_rejected(&arm, &cfg, &req, PLACEMENT_E_NONFINITE, "NaN width");
  model_mesh_t bad_mesh = box_mesh(BOX_HALF);
  bad_mesh.vertices_m[5][2] = NAN;
  req = good;
  req.mesh_link = &bad_mesh;
  expect_rejected(&arm, &cfg, &req, PLACEMENT_E_NONFINITE, "NaN vertex");
  placement_plan_config_t nan_cfg = cfg;
  nan_cfg.block_in_base.pos_m[2] = NAN;
  expect_rejected(&arm, &nan_cfg, &good, PLACEMENT_E_NONFINITE, "NaN block pose");

  /* Other bad input. */
  req = good;
  req.object_in_block.rot[0][0] = 1.1;
  expect_rejected(&arm, &cfg, &req, PLACEMENT_E_ROTATION, "not a rotation");
  req = good;
  req.object_in_block.pos_m[0] = 0.5; /* 0.35 m beyond the +x edge */
  expect_rejected(&arm, &cfg, &req, PLACEMENT_E_GEOMETRY, "object beside B");
  req = good;
  req.grip_width_m = cfg.gripper_max_width_m;
  expect_rejected(&arm, &cfg, &req, PLACEMENT_E_ARG, "grip width leaves no room to open");
  req = good;
  req.q_start_rad[1] = arm.upper_rad[1] + 0.1;
  expect_rejected(&arm, &cfg, &req, PLACEMENT_E_LIMITS, "start outside the limits");
  req = good;
  req.mesh_link = NULL;
  expect_rejected(&arm, &cfg, &req, PLACEMENT_E_ARG, "no mesh");
  placement_plan_config_t bad_cfg = cfg;
  bad_cfg.velocity_fraction = 0.0;
  expect_rejected(&arm, &bad_cfg, &good, PLACEMENT_E_ARG, "zero velocity fraction");
  ck_assert_int_eq(placement_plan_build(NULL, &cfg, &good, &plan, NULL), PLACEMENT_E_ARG);
  model_mesh_free(&bad_mesh);
  model_mesh_free(&mesh);
}
END_TEST

START_TEST(pose_from_wxyz) {
  const double p[3] = {0.1, -0.2, 0.3};
  const double h = sqrt(0.5);
  const double q[4] = {h, 0.0, 0.0, h}; /* 90 degrees about z */
  placement_pose_t out;
  ck_assert_int_eq(placement_pose_from_wxyz(p, q, &out), PLACEMENT_OK);
  ck_assert_double_eq_tol(out.rot[0][1], -1.0, 1e-15);
  ck_assert_double_eq_tol(out.rot[1][0], 1.0, 1e-15);
  ck_assert_double_eq_tol(out.rot[2][2], 1.0, 1e-15);
  ck_assert_double_eq(out.pos_m[1], -0.2);
  placement_pose_t before = out;
  const double q_bad[4] = {1.0, 0.01, 0.0, 0.0};
  ck_assert_int_eq(placement_pose_from_wxyz(p, q_bad, &out), PLACEMENT_E_ROTATION);
  const double q_nan[4] = {NAN, 0.0, 0.0, 0.0};
  ck_assert_int_eq(placement_pose_from_wxyz(p, q_nan, &out), PLACEMENT_E_NONFINITE);
  ck_assert_mem_eq(&out, &before, sizeof out);
}
END_TEST

/* placement_pose_t <-> cl_pose_t: a known rotation, the round trip, and the checks. */
START_TEST(pose_cl_pose_round_trip) {
  placement_pose_t a;
  const double axis[3] = {0.6, 0.0, -0.8};
  placement_rot_from_axis_angle(axis, 2.5, a.rot);
  a.pos_m[0] = 0.4;
  a.pos_m[1] = -0.1;
  a.pos_m[2] = 0.25;
  cl_pose_t c;
  placement_pose_to_cl_pose(&a, &c);
  ck_assert_double_eq_tol(c.orientation_wxyz[0], cos(1.25), 1e-15);
  ck_assert_double_eq_tol(c.orientation_wxyz[1], 0.6 * sin(1.25), 1e-15);
  ck_assert_double_eq_tol(c.orientation_wxyz[2], 0.0, 1e-15);
  ck_assert_double_eq_tol(c.orientation_wxyz[3], -0.8 * sin(1.25), 1e-15);
  ck_assert_mem_eq(c.position_m, a.pos_m, sizeof c.position_m);
  placement_pose_t b;
  ck_assert_int_eq(placement_pose_from_cl_pose(&c, &b), PLACEMENT_OK);
  double dp, dr;
  placement_pose_distance(&a, &b, &dp, &dr);
  ck_assert_double_eq(dp, 0.0);
  ck_assert_double_le(dr, 1e-15);
  /* a point maps the same through either type */
  const double x[3] = {0.01, 0.02, -0.03};
  double via_cl[3];
  cl_pose_apply(&c, x, via_cl);
  for (int i = 0; i < 3; ++i)
    ck_assert_double_eq_tol(
        via_cl[i], a.rot[i][0] * x[0] + a.rot[i][1] * x[1] + a.rot[i][2] * x[2] + a.pos_m[i],
        1e-16);
  c.orientation_wxyz[0] *= 1.1;
  ck_assert_int_eq(placement_pose_from_cl_pose(&c, &b), PLACEMENT_E_ROTATION);
  ck_assert_int_eq(placement_pose_from_cl_pose(NULL, &b), PLACEMENT_E_ARG);
}
END_TEST

Suite *placement_plan_suite(void) {
  Suite *s = suite_create("placement_plan");
  TCase *tc = tcase_create("plan");
  tcase_set_timeout(tc, 120);
  tcase_add_test(tc, plan_each_edge_fk_exact);
  tcase_add_test(tc, plan_rock_touches);
  tcase_add_test(tc, plan_durations_formula);
  tcase_add_test(tc, touch_z_analytic);
  tcase_add_test(tc, gripper_clear_boundary);
  tcase_add_test(tc, plan_bad_input);
  tcase_add_test(tc, pose_from_wxyz);
  tcase_add_test(tc, pose_cl_pose_round_trip);
  suite_add_tcase(s, tc);
  return s;
}
