/* Placement plans: learner's object pose on B -> one arm's waypoints (see placement_plan.h). */
#include "comlearn/placement_plan.h"

#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "comlearn/model_support.h"
#include "plan_geom.h"

static void set_err(placement_error_t *err, const char *fmt, ...) {
  if (!err) return;
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(err->msg, sizeof err->msg, fmt, ap);
  va_end(ap);
}

static int finite_n(const double *v, size_t n) {
  for (size_t i = 0; i < n; ++i) {
    if (!isfinite(v[i])) return 0;
  }
  return 1;
}

/* Row by row, not finite_n(&r[0][0], 9): GCC 12 at -O3 reuses that &r[0][0] (a double[3]) as the
 * argument of a later rot_valid(r) and warns -Wstringop-overflow (72 bytes read from 24). */
static int rot_finite(const double r[3][3]) {
  return finite_n(r[0], 3) && finite_n(r[1], 3) && finite_n(r[2], 3);
}

static int pose_finite(const placement_pose_t *p) {
  return rot_finite(p->rot) && finite_n(p->pos_m, 3);
}

/* Orthonormal with det +1, within 1e-6 per entry of R^T R - I and of det - 1. */
static int rot_valid(const double r[3][3]) {
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const double d = r[0][i] * r[0][j] + r[1][i] * r[1][j] + r[2][i] * r[2][j];
      if (fabs(d - (i == j ? 1.0 : 0.0)) > 1e-6) return 0;
    }
  }
  const double det = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1]) -
                     r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0]) +
                     r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
  return fabs(det - 1.0) <= 1e-6;
}

static int in_range(double v, double lo, double hi) { return v >= lo && v <= hi; }

void placement_plan_config_default(placement_plan_config_t *cfg) {
  const placement_ik_config_t ik = PLACEMENT_IK_CONFIG_INIT;
  memset(cfg, 0, sizeof *cfg);
  placement_pose_identity(&cfg->block_in_base);
  cfg->block_in_base.pos_m[0] = 0.40;
  cfg->block_in_base.pos_m[1] = 0.0;
  cfg->block_in_base.pos_m[2] = 0.0;
  cfg->block_size_m[0] = 0.30;
  cfg->block_size_m[1] = 0.30;
  cfg->block_size_m[2] = 0.10;
  cfg->preplace_height_m = 0.05;
  cfg->retreat_height_m = 0.05;
  cfg->touch_depth_m = 0.0;
  cfg->velocity_fraction = 0.25;
  cfg->min_duration_s = 0.1;
  cfg->gripper_speed_m_s = 0.025;
  cfg->release_opening_m = 0.01;
  cfg->gripper_max_width_m = 0.05;
  cfg->clearance_m = 0.002;
  cfg->max_joint_step_rad = 0.5;
  cfg->approach_steps = 5;
  cfg->branch_attempts = 8;
  cfg->gripper.finger_thickness_m = 0.01089;
  cfg->gripper.finger_half_depth_m = 0.011;
  cfg->gripper.finger_z_lo_m = 0.0837 - 0.1142;
  cfg->gripper.finger_z_hi_m = 0.0837 + 0.05218 - 0.1142;
  cfg->gripper.housing_lo_m[0] = -0.0635;
  cfg->gripper.housing_lo_m[1] = -0.025;
  cfg->gripper.housing_lo_m[2] = -0.1142;
  cfg->gripper.housing_hi_m[0] = 0.0635;
  cfg->gripper.housing_hi_m[1] = 0.040;
  cfg->gripper.housing_hi_m[2] = 0.0837 - 0.1142;
  cfg->ik = ik;
}

placement_status_t placement_plan_config_check(const placement_plan_config_t *cfg) {
  if (!cfg) return PLACEMENT_E_ARG;
  const placement_gripper_t *g = &cfg->gripper;
  const double scalars[] = {
      cfg->preplace_height_m,  cfg->retreat_height_m,    cfg->touch_depth_m,
      cfg->velocity_fraction,  cfg->min_duration_s,      cfg->gripper_speed_m_s,
      cfg->release_opening_m,  cfg->gripper_max_width_m, cfg->clearance_m,
      cfg->max_joint_step_rad, g->finger_thickness_m,    g->finger_half_depth_m,
      g->finger_z_lo_m,        g->finger_z_hi_m,         cfg->ik.tol_pos_m,
      cfg->ik.tol_rot_rad,     cfg->ik.nullspace_gain};
  if (!pose_finite(&cfg->block_in_base) || !finite_n(cfg->block_size_m, 3) ||
      !finite_n(scalars, sizeof scalars / sizeof scalars[0]) || !finite_n(g->housing_lo_m, 3) ||
      !finite_n(g->housing_hi_m, 3)) {
    return PLACEMENT_E_NONFINITE;
  }
  for (int i = 0; i < 3; ++i) {
    if (!in_range(cfg->block_size_m[i], 1e-3, 100.0)) return PLACEMENT_E_ARG;
    if (!(g->housing_lo_m[i] < g->housing_hi_m[i])) return PLACEMENT_E_ARG;
  }
  if (!in_range(cfg->preplace_height_m, 0.0, 0.5) || !in_range(cfg->retreat_height_m, 0.0, 0.5) ||
      !in_range(cfg->touch_depth_m, 0.0, 1e-4) || !(cfg->velocity_fraction > 0.0) ||
      cfg->velocity_fraction > 1.0 || !in_range(cfg->min_duration_s, 0.0, 60.0) ||
      !(cfg->gripper_speed_m_s > 0.0) || !in_range(cfg->release_opening_m, 0.0, 0.05) ||
      !in_range(cfg->gripper_max_width_m, 0.0, 0.2) || !in_range(cfg->clearance_m, 0.0, 0.1) ||
      !(cfg->max_joint_step_rad > 0.0) || !(g->finger_thickness_m > 0.0) ||
      !(g->finger_half_depth_m > 0.0) || !(g->finger_z_lo_m < g->finger_z_hi_m) ||
      !(cfg->ik.tol_pos_m > 0.0) || !(cfg->ik.tol_rot_rad > 0.0) ||
      !in_range(cfg->ik.nullspace_gain, 0.0, 1.0) || cfg->ik.max_iterations == 0 ||
      cfg->ik.max_seeds == 0 || cfg->approach_steps == 0 || cfg->approach_steps > 100 ||
      cfg->branch_attempts == 0 || cfg->branch_attempts > 64) {
    return PLACEMENT_E_ARG;
  }
  if (!rot_valid(cfg->block_in_base.rot)) return PLACEMENT_E_ROTATION;
  return PLACEMENT_OK;
}

placement_status_t placement_pose_from_wxyz(const double position_m[3],
                                            const double orientation_wxyz[4],
                                            placement_pose_t *out) {
  if (!position_m || !orientation_wxyz || !out) return PLACEMENT_E_ARG;
  if (!finite_n(position_m, 3) || !finite_n(orientation_wxyz, 4)) return PLACEMENT_E_NONFINITE;
  double q[4];
  const double n = cl_quat_normalize(orientation_wxyz, q);
  if (fabs(n - 1.0) > 1e-6) return PLACEMENT_E_ROTATION;
  cl_quat_to_rot(q, out->rot);
  memcpy(out->pos_m, position_m, sizeof out->pos_m);
  return PLACEMENT_OK;
}

void placement_pose_to_cl_pose(const placement_pose_t *in, cl_pose_t *out) {
  memcpy(out->position_m, in->pos_m, sizeof out->position_m);
  cl_quat_from_rot((const double(*)[3])in->rot, out->orientation_wxyz);
}

placement_status_t placement_pose_from_cl_pose(const cl_pose_t *in, placement_pose_t *out) {
  if (!in) return PLACEMENT_E_ARG;
  return placement_pose_from_wxyz(in->position_m, in->orientation_wxyz, out);
}

/* Mesh usable: non-empty, indices in range, finite vertices. */
static placement_status_t mesh_check(const model_mesh_t *m) {
  if (!m || !m->vertices_m || !m->triangles || m->vertex_count == 0 || m->triangle_count == 0) {
    return PLACEMENT_E_ARG;
  }
  for (size_t t = 0; t < m->triangle_count; ++t) {
    for (int k = 0; k < 3; ++k) {
      if (m->triangles[t][k] >= m->vertex_count) return PLACEMENT_E_ARG;
    }
  }
  for (size_t i = 0; i < m->vertex_count; ++i) {
    if (!finite_n(m->vertices_m[i], 3)) return PLACEMENT_E_NONFINITE;
  }
  return PLACEMENT_OK;
}

placement_status_t placement_plan_touch_z(const model_mesh_t *mesh_link,
                                          const placement_pose_t *object_in_block,
                                          const double block_size_m[3], double touch_depth_m,
                                          double *z_m) {
  if (!object_in_block || !block_size_m || !z_m) return PLACEMENT_E_ARG;
  placement_status_t st = mesh_check(mesh_link);
  if (st != PLACEMENT_OK) return st;
  const double x_m = object_in_block->pos_m[0], y_m = object_in_block->pos_m[1];
  if (!rot_finite(object_in_block->rot) || !isfinite(x_m) || !isfinite(y_m) ||
      !finite_n(block_size_m, 3) || !isfinite(touch_depth_m)) {
    return PLACEMENT_E_NONFINITE;
  }
  for (int i = 0; i < 3; ++i) {
    if (!in_range(block_size_m[i], 1e-3, 100.0)) return PLACEMENT_E_ARG;
  }
  if (!in_range(touch_depth_m, 0.0, 1e-4)) return PLACEMENT_E_ARG;
  double lowest = 0.0;
  if (!model_mesh_lowest_over_rect(mesh_link, object_in_block->rot, x_m, y_m, 0.5 * block_size_m[0],
                                   0.5 * block_size_m[1], &lowest)) {
    return PLACEMENT_E_GEOMETRY;
  }
  *z_m = -lowest - touch_depth_m;
  return PLACEMENT_OK;
}

int placement_plan_gripper_clear(const placement_plan_config_t *cfg,
                                 const placement_pose_t *tcp_in_block, double width_m) {
  if (!cfg || !tcp_in_block) return 0;
  const placement_gripper_t *g = &cfg->gripper;
  const double c = cfg->clearance_m;
  const double block_c[3] = {0.0, 0.0, -0.5 * cfg->block_size_m[2]};
  const double block_h[3] = {0.5 * cfg->block_size_m[0] + c, 0.5 * cfg->block_size_m[1] + c,
                             0.5 * cfg->block_size_m[2] + c};
  /* Three boxes in the tcp frame: two fingers and the housing (centre, half extents). */
  double lo[3][3], hi[3][3];
  lo[0][0] = 0.5 * width_m;
  hi[0][0] = 0.5 * width_m + g->finger_thickness_m;
  lo[1][0] = -hi[0][0];
  hi[1][0] = -lo[0][0];
  for (int f = 0; f < 2; ++f) {
    lo[f][1] = -g->finger_half_depth_m;
    hi[f][1] = g->finger_half_depth_m;
    lo[f][2] = g->finger_z_lo_m;
    hi[f][2] = g->finger_z_hi_m;
  }
  memcpy(lo[2], g->housing_lo_m, sizeof lo[2]);
  memcpy(hi[2], g->housing_hi_m, sizeof hi[2]);
  for (int b = 0; b < 3; ++b) {
    double local_c[3], half[3], center[3];
    for (int i = 0; i < 3; ++i) {
      local_c[i] = 0.5 * (lo[b][i] + hi[b][i]);
      half[i] = 0.5 * (hi[b][i] - lo[b][i]);
    }
    for (int i = 0; i < 3; ++i) {
      center[i] = tcp_in_block->rot[i][0] * local_c[0] + tcp_in_block->rot[i][1] * local_c[1] +
                  tcp_in_block->rot[i][2] * local_c[2] + tcp_in_block->pos_m[i];
    }
    if (plan_box_overlap(block_c, block_h, center, tcp_in_block->rot, half)) return 0;
  }
  return 1;
}

const char *placement_waypoint_kind_str(placement_waypoint_kind_t kind) {
  switch (kind) {
    case PLACEMENT_WAYPOINT_PREPLACE: return "preplace";
    case PLACEMENT_WAYPOINT_PLACE: return "place";
    case PLACEMENT_WAYPOINT_RELEASE: return "release";
    case PLACEMENT_WAYPOINT_RETREAT: return "retreat";
  }
  return "unknown";
}

static double segment_duration(const placement_arm_t *arm, const placement_plan_config_t *cfg,
                               const double q0[PLACEMENT_JOINTS], const double q1[PLACEMENT_JOINTS],
                               double w0, double w1) {
  double t = cfg->min_duration_s;
  for (int k = 0; k < PLACEMENT_JOINTS; ++k) {
    const double tk = fabs(q1[k] - q0[k]) / (cfg->velocity_fraction * arm->velocity_rad_s[k]);
    if (tk > t) t = tk;
  }
  const double tw = fabs(w1 - w0) / cfg->gripper_speed_m_s;
  return tw > t ? tw : t;
}

static double max_step(const double a[PLACEMENT_JOINTS], const double b[PLACEMENT_JOINTS]) {
  double m = 0.0;
  for (int k = 0; k < PLACEMENT_JOINTS; ++k) {
    if (fabs(a[k] - b[k]) > m) m = fabs(a[k] - b[k]);
  }
  return m;
}

/* IK from a seed anywhere (PLACE from q_start): the full solver, random restarts allowed. */
static placement_status_t solve_free(const placement_arm_t *arm, const placement_plan_config_t *cfg,
                                     const placement_pose_t *target,
                                     const double seed[PLACEMENT_JOINTS],
                                     double q[PLACEMENT_JOINTS], unsigned *iterations) {
  placement_ik_result_t ik;
  memset(&ik, 0, sizeof ik);
  const placement_status_t st = placement_ik(arm, target, seed, &cfg->ik, &ik);
  *iterations += ik.iterations;
  if (st == PLACEMENT_OK) memcpy(q, ik.q_rad, sizeof ik.q_rad);
  return st;
}

/* IK along the straight tcp line from `from` to `to` (same rotation: up from PLACE to PREPLACE
 * and RETREAT) in cfg->approach_steps steps, each seeded from the step before. A step is solved
 * first without the pull toward the nominal posture and without random restarts, so that it stays
 * on the seed's branch (with both on, single 5 cm moves changed joints by 2.3-2.9 rad; one 5 cm
 * jump from a seed clamped at a joint limit did not converge where five 1 cm steps do); then with
 * the full solver. Every step must stay within max_joint_step_rad of the one before:
 * PLACEMENT_E_NO_SOLUTION otherwise (the line is not followable on one branch). */
static placement_status_t solve_straight(const placement_arm_t *arm,
                                         const placement_plan_config_t *cfg,
                                         const placement_pose_t *from, const placement_pose_t *to,
                                         const double seed[PLACEMENT_JOINTS],
                                         double q[PLACEMENT_JOINTS], unsigned *iterations) {
  double cur[PLACEMENT_JOINTS];
  memcpy(cur, seed, sizeof cur);
  placement_ik_config_t near = cfg->ik;
  near.nullspace_gain = 0.0;
  near.max_seeds = 1;
  for (unsigned k = 1; k <= cfg->approach_steps; ++k) {
    const double u = (double)k / (double)cfg->approach_steps;
    placement_pose_t target = *to;
    for (int i = 0; i < 3; ++i) {
      target.pos_m[i] = k == cfg->approach_steps
                            ? to->pos_m[i]
                            : from->pos_m[i] + u * (to->pos_m[i] - from->pos_m[i]);
    }
    placement_ik_result_t ik;
    memset(&ik, 0, sizeof ik);
    placement_status_t st = placement_ik(arm, &target, cur, &near, &ik);
    *iterations += ik.iterations;
    if (st != PLACEMENT_OK) {
      st = placement_ik(arm, &target, cur, &cfg->ik, &ik);
      *iterations += ik.iterations;
      if (st != PLACEMENT_OK) return st;
    }
    if (max_step(cur, ik.q_rad) > cfg->max_joint_step_rad) return PLACEMENT_E_NO_SOLUTION;
    memcpy(cur, ik.q_rad, sizeof cur);
  }
  memcpy(q, cur, sizeof cur);
  return PLACEMENT_OK;
}

/* Arguments, config, arm limits, mesh, finiteness, grip width, rotations and start joints, in
 * that order; err says which failed. */
static placement_status_t plan_request_check(const placement_arm_t *arm,
                                             const placement_plan_config_t *cfg,
                                             const placement_plan_request_t *req,
                                             placement_error_t *err) {
  placement_status_t st = placement_plan_config_check(cfg);
  if (st != PLACEMENT_OK) {
    set_err(err, "placement_plan_build: bad config (%s)", placement_status_str(st));
    return st;
  }
  for (int k = 0; k < PLACEMENT_JOINTS; ++k) {
    if (!(arm->velocity_rad_s[k] > 0.0) || !isfinite(arm->velocity_rad_s[k])) {
      set_err(err, "placement_plan_build: arm joint %d has no velocity limit", k);
      return PLACEMENT_E_ARG;
    }
  }
  st = mesh_check(req->mesh_link);
  if (st != PLACEMENT_OK) {
    set_err(err, "placement_plan_build: object mesh unusable (%s)", placement_status_str(st));
    return st;
  }
  if (!pose_finite(&req->object_in_tcp) || !pose_finite(&req->object_in_block) ||
      !isfinite(req->grip_width_m) || !finite_n(req->q_start_rad, PLACEMENT_JOINTS)) {
    set_err(err, "placement_plan_build: non-finite grasp, target, width or start joints");
    return PLACEMENT_E_NONFINITE;
  }
  if (!in_range(req->grip_width_m, 0.0, cfg->gripper_max_width_m - cfg->release_opening_m)) {
    set_err(err, "placement_plan_build: grip width %g m outside [0, %g]", req->grip_width_m,
            cfg->gripper_max_width_m - cfg->release_opening_m);
    return PLACEMENT_E_ARG;
  }
  if (!rot_valid(req->object_in_tcp.rot) || !rot_valid(req->object_in_block.rot)) {
    set_err(err, "placement_plan_build: grasp or target rotation not orthonormal");
    return PLACEMENT_E_ROTATION;
  }
  st = placement_arm_check(arm, req->q_start_rad);
  if (st != PLACEMENT_OK) {
    set_err(err, "placement_plan_build: start joints: %s", placement_status_str(st));
    return st;
  }
  return PLACEMENT_OK;
}

/* The object lowered to touch B, the tcp in block at every waypoint (PLACE, then PREPLACE /
 * RETREAT raised along block z) and the gripper width at each, with the gripper clear of B. */
static placement_status_t plan_tcp_in_block(const placement_plan_config_t *cfg,
                                            const placement_plan_request_t *req,
                                            placement_plan_t *plan,
                                            placement_pose_t tcp_in_block[PLACEMENT_PLAN_WAYPOINTS],
                                            double widths[PLACEMENT_PLAN_WAYPOINTS],
                                            placement_error_t *err) {
  plan->object_in_block = req->object_in_block;
  const placement_status_t st =
      placement_plan_touch_z(req->mesh_link, &req->object_in_block, cfg->block_size_m,
                             cfg->touch_depth_m, &plan->object_in_block.pos_m[2]);
  if (st != PLACEMENT_OK) {
    set_err(err, "placement_plan_build: no part of the object over B's top");
    return st;
  }
  placement_pose_t tcp_in_obj;
  placement_pose_inverse(&req->object_in_tcp, &tcp_in_obj);
  placement_pose_mul(&plan->object_in_block, &tcp_in_obj, &tcp_in_block[1]);
  tcp_in_block[0] = tcp_in_block[1];
  tcp_in_block[0].pos_m[2] += cfg->preplace_height_m;
  tcp_in_block[2] = tcp_in_block[1];
  tcp_in_block[3] = tcp_in_block[1];
  tcp_in_block[3].pos_m[2] += cfg->retreat_height_m;
  const double release_w = req->grip_width_m + cfg->release_opening_m;
  widths[0] = req->grip_width_m;
  widths[1] = req->grip_width_m;
  widths[2] = release_w;
  widths[3] = release_w;
  for (int w = 0; w < PLACEMENT_PLAN_WAYPOINTS; ++w) {
    if (!placement_plan_gripper_clear(cfg, &tcp_in_block[w], widths[w])) {
      set_err(err, "placement_plan_build: the gripper would reach into B at %s",
              placement_waypoint_kind_str((placement_waypoint_kind_t)w));
      return PLACEMENT_E_COLLISION;
    }
  }
  return PLACEMENT_OK;
}

/* PLACE first (it is what the learner asked for), then the lines up to PREPLACE and RETREAT
 * from it. When a line cannot be followed on PLACE's branch, PLACE is solved again from another
 * start posture (deterministic, from cfg->ik.rng_seed). */
static placement_status_t plan_solve_joints(
    const placement_arm_t *arm, const placement_plan_config_t *cfg,
    const placement_plan_request_t *req,
    const placement_pose_t tcp_in_base[PLACEMENT_PLAN_WAYPOINTS], double q_place[PLACEMENT_JOINTS],
    double q_pre[PLACEMENT_JOINTS], double q_ret[PLACEMENT_JOINTS], unsigned *iterations,
    placement_error_t *err) {
  uint64_t rng = cfg->ik.rng_seed ^ 0x9e3779b97f4a7c15ull;
  for (unsigned attempt = 0;; ++attempt) {
    double start[PLACEMENT_JOINTS];
    if (attempt == 0) {
      memcpy(start, req->q_start_rad, sizeof start);
    } else {
      for (int k = 0; k < PLACEMENT_JOINTS; ++k) {
        const double u = cl_rng_uniform(&rng);
        start[k] = arm->lower_rad[k] + u * (arm->upper_rad[k] - arm->lower_rad[k]);
      }
    }
    placement_status_t st = solve_free(arm, cfg, &tcp_in_base[1], start, q_place, iterations);
    if (st != PLACEMENT_OK) {
      set_err(err, "placement_plan_build: place unreachable (%s)", placement_status_str(st));
      return st;
    }
    st = solve_straight(arm, cfg, &tcp_in_base[1], &tcp_in_base[0], q_place, q_pre, iterations);
    if (st == PLACEMENT_OK) {
      st = solve_straight(arm, cfg, &tcp_in_base[2], &tcp_in_base[3], q_place, q_ret, iterations);
    }
    if (st == PLACEMENT_OK) return PLACEMENT_OK;
    if (attempt + 1 >= cfg->branch_attempts) {
      set_err(err,
              "placement_plan_build: no IK branch follows the vertical line through place "
              "(%u attempts): %s",
              cfg->branch_attempts, placement_status_str(st));
      return st;
    }
  }
}

placement_status_t placement_plan_build(const placement_arm_t *arm,
                                        const placement_plan_config_t *cfg,
                                        const placement_plan_request_t *req, placement_plan_t *out,
                                        placement_error_t *err) {
  if (!arm || !cfg || !req || !out) {
    set_err(err, "placement_plan_build: NULL argument");
    return PLACEMENT_E_ARG;
  }
  placement_status_t st = plan_request_check(arm, cfg, req, err);
  if (st != PLACEMENT_OK) return st;

  placement_plan_t plan;
  memset(&plan, 0, sizeof plan);
  placement_pose_t tcp_in_block[PLACEMENT_PLAN_WAYPOINTS];
  double widths[PLACEMENT_PLAN_WAYPOINTS];
  st = plan_tcp_in_block(cfg, req, &plan, tcp_in_block, widths, err);
  if (st != PLACEMENT_OK) return st;

  placement_pose_t tcp_in_base[PLACEMENT_PLAN_WAYPOINTS];
  for (int w = 0; w < PLACEMENT_PLAN_WAYPOINTS; ++w) {
    placement_pose_mul(&cfg->block_in_base, &tcp_in_block[w], &tcp_in_base[w]);
  }
  double q_place[PLACEMENT_JOINTS], q_pre[PLACEMENT_JOINTS], q_ret[PLACEMENT_JOINTS];
  st = plan_solve_joints(arm, cfg, req, tcp_in_base, q_place, q_pre, q_ret, &plan.ik_iterations,
                         err);
  if (st != PLACEMENT_OK) return st;

  const double *const qs[PLACEMENT_PLAN_WAYPOINTS] = {q_pre, q_place, q_place, q_ret};
  const double *prev = req->q_start_rad;
  double prev_w = req->grip_width_m;
  for (int w = 0; w < PLACEMENT_PLAN_WAYPOINTS; ++w) {
    placement_waypoint_t *wp = &plan.waypoints[w];
    wp->kind = (placement_waypoint_kind_t)w;
    wp->gripper_width_m = widths[w];
    wp->tcp_in_base = tcp_in_base[w];
    memcpy(wp->q_rad, qs[w], sizeof wp->q_rad);
    wp->duration_s = segment_duration(arm, cfg, prev, wp->q_rad, prev_w, wp->gripper_width_m);
    plan.total_duration_s += wp->duration_s;
    prev = wp->q_rad;
    prev_w = wp->gripper_width_m;
  }
  *out = plan;
  return PLACEMENT_OK;
}
