/* arm.c - a 7R arm from a URDF chain (lib/model), YuMi names and joint orders. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "comlearn/model_chain.h"
#include "placement_internal.h"

placement_status_t placement_arm_load(placement_arm_t *arm, const char *urdf_path,
                                      const char *base_link, const char *tip_link,
                                      placement_error_t *err) {
  if (arm == NULL) {
    return placement_fail(err, PLACEMENT_E_ARG, "placement_arm_load: NULL arm");
  }
  memset(arm, 0, sizeof *arm);
  if (urdf_path == NULL || base_link == NULL || tip_link == NULL) {
    return placement_fail(err, PLACEMENT_E_ARG, "placement_arm_load: NULL argument");
  }
  model_chain_t chain; /* ~20 kB on the stack, released on return */
  model_error_t merr;
  model_status_t mst = model_chain_load(urdf_path, base_link, tip_link, &chain, &merr);
  if (mst != MODEL_OK) {
    return placement_fail(err, PLACEMENT_E_MODEL, "%s (%s)", merr.msg, model_status_str(mst));
  }
  if (chain.moving_count != PLACEMENT_JOINTS) {
    return placement_fail(err, PLACEMENT_E_MODEL,
                          "URDF %s: chain '%s' -> '%s' has %zu moving joints, a 7R arm needs %d",
                          urdf_path, base_link, tip_link, chain.moving_count,
                          (int)PLACEMENT_JOINTS);
  }
  snprintf(arm->base_link, sizeof arm->base_link, "%s", chain.base_link);
  snprintf(arm->tip_link, sizeof arm->tip_link, "%s", chain.tip_link);
  /* Fold fixed joints into the next moving joint's origin (or into the tip). */
  placement_pose_t acc;
  placement_pose_identity(&acc);
  int k = 0;
  for (size_t i = 0; i < chain.joint_count; ++i) {
    const model_joint_t *j = &chain.joints[i];
    placement_pose_t o;
    memcpy(o.rot, j->origin_rot, sizeof o.rot);
    memcpy(o.pos_m, j->origin_xyz_m, sizeof o.pos_m);
    placement_pose_mul(&acc, &o, &acc);
    if (j->type == MODEL_JOINT_FIXED) {
      continue;
    }
    if (j->type != MODEL_JOINT_REVOLUTE) {
      memset(arm, 0, sizeof *arm);
      return placement_fail(err, PLACEMENT_E_MODEL,
                            "URDF %s: joint '%s' is %s; the arm needs revolute joints with limits",
                            urdf_path, j->name, model_joint_type_str(j->type));
    }
    if (!(j->velocity > 0.0)) {
      memset(arm, 0, sizeof *arm);
      return placement_fail(err, PLACEMENT_E_MODEL, "URDF %s: joint '%s' has no velocity limit",
                            urdf_path, j->name);
    }
    arm->origin[k] = acc;
    memcpy(arm->axis[k], j->axis, sizeof arm->axis[k]);
    arm->lower_rad[k] = j->lower;
    arm->upper_rad[k] = j->upper;
    arm->velocity_rad_s[k] = j->velocity;
    arm->nominal_rad[k] = 0.5 * (j->lower + j->upper);
    snprintf(arm->joint_names[k], sizeof arm->joint_names[k], "%s", j->name);
    placement_pose_identity(&acc);
    ++k;
  }
  arm->tip = acc;
  /* Joint 0 turns about its own origin, so every later origin and the tip keep their distance
   * from the previous frame's origin: the sum bounds the tip's distance from joint 0. */
  double reach = cl_vec3_norm(arm->tip.pos_m);
  for (int i = 1; i < PLACEMENT_JOINTS; ++i) {
    reach += cl_vec3_norm(arm->origin[i].pos_m);
  }
  arm->reach_m = reach;
  return PLACEMENT_OK;
}

void placement_yumi_nominal(placement_side_t side, double q_rad[PLACEMENT_JOINTS]) {
  /* Chain order (ABB axes 1, 2, 7, 3, 4, 5, 6), degrees: ABB's synchronisation pose
   * (axes 1..7 = 0, -130, 30, 0, 40, 0, -+135), mirrored for the left arm (axes 1, 4, 7). */
  const double deg = CL_PI / 180.0;
  const double right[PLACEMENT_JOINTS] = {0.0, -130.0, -135.0, 30.0, 0.0, 40.0, 0.0};
  for (int k = 0; k < PLACEMENT_JOINTS; ++k) {
    q_rad[k] = right[k] * deg;
  }
  if (side == PLACEMENT_ARM_LEFT) {
    q_rad[0] = -q_rad[0];
    q_rad[2] = -q_rad[2];
    q_rad[4] = -q_rad[4];
  }
}

placement_status_t placement_arm_load_yumi(placement_arm_t *arm, const char *urdf_path,
                                           placement_side_t side, placement_error_t *err) {
  if (side != PLACEMENT_ARM_LEFT && side != PLACEMENT_ARM_RIGHT) {
    if (arm != NULL) {
      memset(arm, 0, sizeof *arm);
    }
    return placement_fail(err, PLACEMENT_E_ARG, "placement_arm_load_yumi: bad side %d", (int)side);
  }
  placement_status_t st = placement_arm_load(
      arm, urdf_path, PLACEMENT_YUMI_BASE_LINK,
      side == PLACEMENT_ARM_LEFT ? PLACEMENT_YUMI_TCP_LEFT : PLACEMENT_YUMI_TCP_RIGHT, err);
  if (st == PLACEMENT_OK) {
    placement_yumi_nominal(side, arm->nominal_rad);
  }
  return st;
}

/* chain index k holds ABB axis CHAIN_TO_ABB[k] (1-based). */
static const int CHAIN_TO_ABB[PLACEMENT_JOINTS] = {1, 2, 7, 3, 4, 5, 6};

void placement_abb_from_chain(const double chain[PLACEMENT_JOINTS], double abb[PLACEMENT_JOINTS]) {
  double t[PLACEMENT_JOINTS];
  for (int k = 0; k < PLACEMENT_JOINTS; ++k) {
    t[CHAIN_TO_ABB[k] - 1] = chain[k];
  }
  memcpy(abb, t, sizeof t);
}

void placement_chain_from_abb(const double abb[PLACEMENT_JOINTS], double chain[PLACEMENT_JOINTS]) {
  double t[PLACEMENT_JOINTS];
  for (int k = 0; k < PLACEMENT_JOINTS; ++k) {
    t[k] = abb[CHAIN_TO_ABB[k] - 1];
  }
  memcpy(chain, t, sizeof t);
}

placement_status_t placement_arm_check(const placement_arm_t *arm,
                                       const double q_rad[PLACEMENT_JOINTS]) {
  if (arm == NULL || q_rad == NULL) {
    return PLACEMENT_E_ARG;
  }
  if (!placement_finite(q_rad, PLACEMENT_JOINTS)) {
    return PLACEMENT_E_NONFINITE;
  }
  for (int k = 0; k < PLACEMENT_JOINTS; ++k) {
    if (q_rad[k] < arm->lower_rad[k] || q_rad[k] > arm->upper_rad[k]) {
      return PLACEMENT_E_LIMITS;
    }
  }
  return PLACEMENT_OK;
}
