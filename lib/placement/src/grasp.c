/* grasp.c - a top-down grasp for a release pose and the plan that places with it (see
 * placement_plan.h). The arithmetic is the LCM backend's, moved here unchanged: its estimates
 * agree with the in-process backend's at 1e-12 (check_estimate_lcm). */
#include <math.h>
#include <string.h>

#include "comlearn/math3d.h"
#include "comlearn/placement_plan.h"
#include "placement_internal.h"

void placement_grasp_config_default(placement_grasp_config_t *cfg) {
  const placement_grasp_config_t d = PLACEMENT_GRASP_CONFIG_INIT;
  *cfg = d;
}

static int in_range(double v, double lo, double hi) { return v >= lo && v <= hi; }

static placement_status_t grasp_config_check(const placement_grasp_config_t *g) {
  if (!placement_finite(&g->depth_m, 1) || !placement_finite(&g->tip_length_m, 1) ||
      !placement_finite(&g->tip_clear_m, 1) || !placement_finite(&g->min_width_m, 1))
    return PLACEMENT_E_NONFINITE;
  if (!in_range(g->depth_m, 0.0, 0.5) || !in_range(g->tip_length_m, 0.0, 0.5) ||
      !in_range(g->tip_clear_m, 0.0, 0.5) || !in_range(g->min_width_m, 0.0, 0.2))
    return PLACEMENT_E_ARG;
  return PLACEMENT_OK;
}

/* The block-frame axis-aligned box of the mesh at obj (link in block). */
static placement_status_t mesh_box(const model_mesh_t *m, const placement_pose_t *obj, double lo[3],
                                   double hi[3]) {
  for (int i = 0; i < 3; ++i) {
    lo[i] = INFINITY;
    hi[i] = -INFINITY;
  }
  for (size_t v = 0; v < m->vertex_count; ++v) {
    const double *p = m->vertices_m[v];
    if (!placement_finite(p, 3)) return PLACEMENT_E_NONFINITE;
    for (int i = 0; i < 3; ++i) {
      const double x =
          obj->rot[i][0] * p[0] + obj->rot[i][1] * p[1] + obj->rot[i][2] * p[2] + obj->pos_m[i];
      if (x < lo[i]) lo[i] = x;
      if (x > hi[i]) hi[i] = x;
    }
  }
  return PLACEMENT_OK;
}

/* The nominal grasp at finger yaw yaw_deg: the tcp at tcp_p, Rz(yaw) Rx(pi) in the block (tcp z
 * down, fingers closing along (cos yaw, sin yaw, 0)); the link frame in the tcp frame; the
 * opening. 0 when a pose does not convert (not expected). */
static int grasp_at_yaw(const placement_plan_config_t *cfg, const placement_grasp_config_t *gcfg,
                        const placement_pose_t *obj, const double q_obj[4], const double tcp_p[3],
                        const double lo[3], const double hi[3], double yaw_deg,
                        placement_grasp_t *g) {
  const double h = 0.5 * yaw_deg * CL_PI / 180.0;
  const double qz[4] = {cos(h), 0, 0, sin(h)}, qx[4] = {0, 1, 0, 0};
  double q_tcp[4], q_tcp_c[4], q_g[4];
  cl_quat_mul(qz, qx, q_tcp);
  cl_quat_conj(q_tcp, q_tcp_c);
  cl_quat_mul(q_tcp_c, q_obj, q_g);
  (void)cl_quat_normalize(q_g, q_g);
  if (placement_pose_from_wxyz(tcp_p, q_tcp, &g->tcp_in_block) != PLACEMENT_OK) return 0;
  /* link origin in the tcp frame: R_tcp^T (p_obj - p_tcp) */
  double d[3], g_pos[3];
  for (int i = 0; i < 3; ++i) d[i] = obj->pos_m[i] - tcp_p[i];
  for (int i = 0; i < 3; ++i)
    g_pos[i] = g->tcp_in_block.rot[0][i] * d[0] + g->tcp_in_block.rot[1][i] * d[1] +
               g->tcp_in_block.rot[2][i] * d[2];
  /* finger opening: the object's extent along the closing axis, within the gripper */
  const double cy = cos(2 * h), sy = sin(2 * h);
  double width = fabs(cy) * (hi[0] - lo[0]) + fabs(sy) * (hi[1] - lo[1]);
  const double wmax = cfg->gripper_max_width_m - cfg->release_opening_m;
  if (width > wmax) width = wmax;
  if (width < gcfg->min_width_m) width = gcfg->min_width_m;
  g->yaw_rad = 2.0 * h;
  g->grip_width_m = width;
  return placement_pose_from_wxyz(g_pos, q_g, &g->object_in_tcp_nominal) == PLACEMENT_OK;
}

/* G = FK(q_place)^-1 * block_in_base * obj: the grasp that makes the PLACE joints put the link
 * frame exactly on the release pose. IK meets a pose within 1e-9 m / rad only; with G the
 * controller's FK(q_place) * G lands on it to rounding, so a robot (or simulator) releases where
 * the estimator asked, as the in-process backend does (a 1e-10 m miss can flip a policy's
 * stopping test). */
static placement_status_t grasp_correct(const placement_arm_t *arm,
                                        const placement_plan_config_t *cfg,
                                        const placement_pose_t *obj, placement_grasp_t *g) {
  placement_pose_t tcp_place, want_w, tcp_inv, corr;
  const placement_status_t st =
      placement_fk(arm, g->plan.waypoints[PLACEMENT_WAYPOINT_PLACE].q_rad, &tcp_place);
  if (st != PLACEMENT_OK) return st;
  placement_pose_mul(&cfg->block_in_base, obj, &want_w);
  placement_pose_inverse(&tcp_place, &tcp_inv);
  placement_pose_mul(&tcp_inv, &want_w, &corr);
  cl_quat_from_rot((const double(*)[3])corr.rot, g->object_in_tcp.orientation_wxyz);
  (void)cl_quat_normalize(g->object_in_tcp.orientation_wxyz, g->object_in_tcp.orientation_wxyz);
  memcpy(g->object_in_tcp.position_m, corr.pos_m, sizeof corr.pos_m);
  return PLACEMENT_OK;
}

placement_status_t placement_grasp_plan(const placement_arm_t arms[2],
                                        const placement_plan_config_t *cfg,
                                        const placement_grasp_config_t *gcfg,
                                        const placement_grasp_request_t *req,
                                        placement_grasp_t *out, placement_error_t *err) {
  if (!arms || !cfg || !gcfg || !req || !out || !req->mesh_link || !req->mesh_link->vertices_m ||
      req->mesh_link->vertex_count == 0)
    return placement_fail(err, PLACEMENT_E_ARG, "grasp: NULL argument or empty mesh");
  placement_status_t st = grasp_config_check(gcfg);
  if (st != PLACEMENT_OK) return placement_fail(err, st, "grasp: bad grasp config");
  st = placement_plan_config_check(cfg);
  if (st != PLACEMENT_OK) return placement_fail(err, PLACEMENT_E_ARG, "grasp: bad plan config");
  placement_pose_t obj;
  st = placement_pose_from_wxyz(req->object_in_block.position_m,
                                req->object_in_block.orientation_wxyz, &obj);
  if (st != PLACEMENT_OK)
    return placement_fail(err, st, "release pose: %s", placement_status_str(st));
  double lo[3], hi[3];
  st = mesh_box(req->mesh_link, &obj, lo, hi);
  if (st != PLACEMENT_OK) return placement_fail(err, st, "grasp: a non-finite vertex");
  double tcp_p[3] = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), hi[2] - gcfg->depth_m};
  if (tcp_p[2] < gcfg->tip_length_m + gcfg->tip_clear_m)
    tcp_p[2] = gcfg->tip_length_m + gcfg->tip_clear_m;
  static const double yaws_deg[] = {0.0, 90.0, -90.0, 180.0};
  static const placement_side_t sides[] = {PLACEMENT_ARM_RIGHT, PLACEMENT_ARM_LEFT};
  placement_status_t last = PLACEMENT_E_NO_SOLUTION;
  placement_grasp_t g;
  memset(&g, 0, sizeof g);
  for (size_t a = 0; a < 2; ++a) {
    for (size_t y = 0; y < sizeof yaws_deg / sizeof yaws_deg[0]; ++y) {
      g.attempts++;
      if (!grasp_at_yaw(cfg, gcfg, &obj, req->object_in_block.orientation_wxyz, tcp_p, lo, hi,
                        yaws_deg[y], &g))
        continue;
      placement_plan_request_t pr;
      memset(&pr, 0, sizeof pr);
      pr.mesh_link = req->mesh_link;
      pr.object_in_tcp = g.object_in_tcp_nominal;
      pr.object_in_block = obj;
      pr.grip_width_m = g.grip_width_m;
      memcpy(pr.q_start_rad, req->q_start_rad[sides[a]], sizeof pr.q_start_rad);
      last = placement_plan_build(&arms[sides[a]], cfg, &pr, &g.plan, err);
      if (last != PLACEMENT_OK) continue;
      g.side = sides[a];
      st = grasp_correct(&arms[sides[a]], cfg, &obj, &g);
      if (st != PLACEMENT_OK) return placement_fail(err, st, "FK of the place joints failed");
      *out = g;
      return PLACEMENT_OK;
    }
  }
  return last;
}
