/* fk.c - forward kinematics and the geometric Jacobian of a placement_arm_t. */
#include <math.h>
#include <string.h>

#include "placement_internal.h"

/* frames[k] = joint k's moving frame in the base; returns the tip in *tip. No checks. */
static void fk_all(const placement_arm_t *arm, const double q[PLACEMENT_JOINTS],
                   placement_pose_t frames[PLACEMENT_JOINTS], placement_pose_t *tip) {
  placement_pose_t t;
  placement_pose_identity(&t);
  for (int k = 0; k < PLACEMENT_JOINTS; ++k) {
    placement_pose_mul(&t, &arm->origin[k], &t);
    const double *a = arm->axis[k];
    if (a[0] == 0.0 && a[1] == 0.0 && a[2] == 1.0) {
      /* URDF arms mostly turn about z: rotate the first two columns (half the work). */
      double c = cos(q[k]), s = sin(q[k]);
      for (int i = 0; i < 3; ++i) {
        double x = t.rot[i][0], y = t.rot[i][1];
        t.rot[i][0] = c * x + s * y;
        t.rot[i][1] = c * y - s * x;
      }
    } else {
      placement_pose_t j;
      placement_rot_from_axis_angle(a, q[k], j.rot);
      j.pos_m[0] = j.pos_m[1] = j.pos_m[2] = 0.0;
      placement_pose_mul(&t, &j, &t);
    }
    if (frames != NULL) {
      frames[k] = t;
    }
  }
  placement_pose_mul(&t, &arm->tip, tip);
}

placement_status_t placement_fk_frames(const placement_arm_t *arm,
                                       const double q_rad[PLACEMENT_JOINTS],
                                       placement_pose_t frames[PLACEMENT_JOINTS],
                                       placement_pose_t *tip) {
  if (arm == NULL || q_rad == NULL) {
    return PLACEMENT_E_ARG;
  }
  if (!placement_finite(q_rad, PLACEMENT_JOINTS)) {
    return PLACEMENT_E_NONFINITE;
  }
  placement_pose_t t;
  fk_all(arm, q_rad, frames, &t);
  if (tip != NULL) {
    *tip = t;
  }
  return PLACEMENT_OK;
}

placement_status_t placement_fk(const placement_arm_t *arm, const double q_rad[PLACEMENT_JOINTS],
                                placement_pose_t *tip) {
  if (tip == NULL) {
    return PLACEMENT_E_ARG;
  }
  return placement_fk_frames(arm, q_rad, NULL, tip);
}

/* Jacobian from frames already computed (used by the IK loop). */
void placement_jacobian_from_frames(const placement_arm_t *arm,
                                    const placement_pose_t frames[PLACEMENT_JOINTS],
                                    const placement_pose_t *tip, double jac[6][PLACEMENT_JOINTS]) {
  for (int k = 0; k < PLACEMENT_JOINTS; ++k) {
    const placement_pose_t *f = &frames[k];
    double w[3];
    for (int i = 0; i < 3; ++i) {
      w[i] = f->rot[i][0] * arm->axis[k][0] + f->rot[i][1] * arm->axis[k][1] +
             f->rot[i][2] * arm->axis[k][2];
    }
    double d[3] = {tip->pos_m[0] - f->pos_m[0], tip->pos_m[1] - f->pos_m[1],
                   tip->pos_m[2] - f->pos_m[2]};
    jac[0][k] = w[1] * d[2] - w[2] * d[1];
    jac[1][k] = w[2] * d[0] - w[0] * d[2];
    jac[2][k] = w[0] * d[1] - w[1] * d[0];
    jac[3][k] = w[0];
    jac[4][k] = w[1];
    jac[5][k] = w[2];
  }
}

placement_status_t placement_jacobian(const placement_arm_t *arm,
                                      const double q_rad[PLACEMENT_JOINTS],
                                      double jac[6][PLACEMENT_JOINTS]) {
  if (jac == NULL) {
    return PLACEMENT_E_ARG;
  }
  placement_pose_t frames[PLACEMENT_JOINTS], tip;
  placement_status_t st = placement_fk_frames(arm, q_rad, frames, &tip);
  if (st == PLACEMENT_OK) {
    placement_jacobian_from_frames(arm, frames, &tip, jac);
  }
  return st;
}
