/* pose.c - rigid transforms, rotations, statuses of lib/placement. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "comlearn/math3d.h"
#include "placement_internal.h"

const char *placement_status_str(placement_status_t status) {
  switch (status) {
    case PLACEMENT_OK: return "ok";
    case PLACEMENT_E_ARG: return "invalid argument";
    case PLACEMENT_E_NONFINITE: return "a number is NaN or infinite";
    case PLACEMENT_E_MODEL: return "the robot model could not be loaded or is not a 7R arm";
    case PLACEMENT_E_LIMITS: return "joint values outside the joint limits";
    case PLACEMENT_E_OUT_OF_REACH: return "target beyond the arm's reach";
    case PLACEMENT_E_NO_SOLUTION: return "no inverse kinematics solution within the joint limits";
    case PLACEMENT_E_ROTATION: return "not a rotation matrix";
    case PLACEMENT_E_COLLISION: return "the gripper or object would penetrate the block";
    case PLACEMENT_E_GEOMETRY: return "object or block geometry unusable";
  }
  return "unknown placement status";
}

placement_status_t placement_fail(placement_error_t *err, placement_status_t status,
                                  const char *fmt, ...) {
  if (err != NULL) {
    va_list ap;
    va_start(ap, fmt);
    (void)vsnprintf(err->msg, sizeof err->msg, fmt, ap);
    va_end(ap);
  }
  return status;
}

int placement_finite(const double *v, size_t n) {
  for (size_t i = 0; i < n; ++i) {
    if (!isfinite(v[i])) {
      return 0;
    }
  }
  return 1;
}

void placement_pose_identity(placement_pose_t *out) {
  memset(out, 0, sizeof *out);
  out->rot[0][0] = out->rot[1][1] = out->rot[2][2] = 1.0;
}

void placement_pose_mul(const placement_pose_t *a, const placement_pose_t *b,
                        placement_pose_t *out) {
  placement_pose_t r;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      r.rot[i][j] =
          a->rot[i][0] * b->rot[0][j] + a->rot[i][1] * b->rot[1][j] + a->rot[i][2] * b->rot[2][j];
    }
    r.pos_m[i] = a->rot[i][0] * b->pos_m[0] + a->rot[i][1] * b->pos_m[1] +
                 a->rot[i][2] * b->pos_m[2] + a->pos_m[i];
  }
  *out = r;
}

void placement_pose_inverse(const placement_pose_t *a, placement_pose_t *out) {
  placement_pose_t r;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      r.rot[i][j] = a->rot[j][i];
    }
  }
  for (int i = 0; i < 3; ++i) {
    r.pos_m[i] =
        -(r.rot[i][0] * a->pos_m[0] + r.rot[i][1] * a->pos_m[1] + r.rot[i][2] * a->pos_m[2]);
  }
  *out = r;
}

void placement_rot_from_rpy(double roll_rad, double pitch_rad, double yaw_rad, double rot[3][3]) {
  double cr = cos(roll_rad), sr = sin(roll_rad);
  double cp = cos(pitch_rad), sp = sin(pitch_rad);
  double cy = cos(yaw_rad), sy = sin(yaw_rad);
  rot[0][0] = cy * cp;
  rot[0][1] = cy * sp * sr - sy * cr;
  rot[0][2] = cy * sp * cr + sy * sr;
  rot[1][0] = sy * cp;
  rot[1][1] = sy * sp * sr + cy * cr;
  rot[1][2] = sy * sp * cr - cy * sr;
  rot[2][0] = -sp;
  rot[2][1] = cp * sr;
  rot[2][2] = cp * cr;
}

void placement_pose_rpy(const placement_pose_t *pose, double rpy_rad[3]) {
  const double(*rot)[3] = pose->rot;
  rpy_rad[1] = atan2(-rot[2][0], sqrt(rot[0][0] * rot[0][0] + rot[1][0] * rot[1][0]));
  if (fabs(rot[2][0]) < 1.0 - 1e-12) {
    rpy_rad[0] = atan2(rot[2][1], rot[2][2]);
    rpy_rad[2] = atan2(rot[1][0], rot[0][0]);
  } else { /* gimbal lock: put everything into yaw */
    rpy_rad[0] = 0.0;
    rpy_rad[2] = atan2(-rot[0][1], rot[1][1]);
  }
}

void placement_rot_from_axis_angle(const double axis[3], double angle_rad, double rot[3][3]) {
  cl_rot_from_axis_angle(axis, angle_rad, rot);
}

double placement_rot_angle(const double rot[3][3]) {
  double vx = rot[2][1] - rot[1][2], vy = rot[0][2] - rot[2][0], vz = rot[1][0] - rot[0][1];
  double s = 0.5 * sqrt(vx * vx + vy * vy + vz * vz);
  double c = 0.5 * (rot[0][0] + rot[1][1] + rot[2][2] - 1.0);
  return atan2(s, c);
}

void placement_rot_log(const double rot[3][3], double w[3]) {
  double v[3] = {rot[2][1] - rot[1][2], rot[0][2] - rot[2][0], rot[1][0] - rot[0][1]};
  double s = 0.5 * sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  double c = 0.5 * (rot[0][0] + rot[1][1] + rot[2][2] - 1.0);
  double angle = atan2(s, c);
  if (angle < 1e-6) { /* theta / sin(theta) = 1 + theta^2 / 6 */
    double f = 0.5 * (1.0 + angle * angle / 6.0);
    for (int i = 0; i < 3; ++i) {
      w[i] = f * v[i];
    }
    return;
  }
  if (angle < CL_PI - 1e-4) {
    double f = angle / (2.0 * s);
    for (int i = 0; i < 3; ++i) {
      w[i] = f * v[i];
    }
    return;
  }
  /* Near pi the antisymmetric part vanishes. The symmetric part is c I + (1 - c) a a^T, so its
   * column k minus c e_k is (1 - c) a_k a: take the column of the largest diagonal entry (best
   * conditioned) and the sign from the (small) antisymmetric part v = 2 sin(angle) a. */
  int k = 0;
  for (int i = 1; i < 3; ++i) {
    if (rot[i][i] > rot[k][k]) {
      k = i;
    }
  }
  double a[3];
  for (int i = 0; i < 3; ++i) {
    a[i] = 0.5 * (rot[i][k] + rot[k][i]) - (i == k ? c : 0.0);
  }
  double n = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  double sign = a[0] * v[0] + a[1] * v[1] + a[2] * v[2] < 0.0 ? -1.0 : 1.0;
  for (int i = 0; i < 3; ++i) {
    w[i] = sign * angle * a[i] / n;
  }
}

void placement_pose_distance(const placement_pose_t *a, const placement_pose_t *b, double *pos_m,
                             double *rot_rad) {
  if (pos_m != NULL) {
    *pos_m = cl_vec3_dist(a->pos_m, b->pos_m);
  }
  if (rot_rad != NULL) {
    double r[3][3]; /* a^T b */
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        r[i][j] =
            a->rot[0][i] * b->rot[0][j] + a->rot[1][i] * b->rot[1][j] + a->rot[2][i] * b->rot[2][j];
      }
    }
    *rot_rad = placement_rot_angle((const double(*)[3])r);
  }
}
