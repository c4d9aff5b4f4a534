/* Rotations shared by every library above lib/model (comlearn/model.h). */
#include <math.h>
#include <string.h>

#include "comlearn/model.h"

void model_quat_to_rot(const double q_wxyz[4], double rot[3][3]) {
  const double w = q_wxyz[0], x = q_wxyz[1], y = q_wxyz[2], z = q_wxyz[3];
  rot[0][0] = 1.0 - 2.0 * (y * y + z * z);
  rot[0][1] = 2.0 * (x * y - w * z);
  rot[0][2] = 2.0 * (x * z + w * y);
  rot[1][0] = 2.0 * (x * y + w * z);
  rot[1][1] = 1.0 - 2.0 * (x * x + z * z);
  rot[1][2] = 2.0 * (y * z - w * x);
  rot[2][0] = 2.0 * (x * z - w * y);
  rot[2][1] = 2.0 * (y * z + w * x);
  rot[2][2] = 1.0 - 2.0 * (x * x + y * y);
}

void model_rot_to_quat(const double rot[3][3], double q_wxyz[4]) {
  const double(*r)[3] = rot;
  double *q = q_wxyz;
  /* Shepperd: divide by the largest of the four 4 q_i^2 terms. */
  const double tr = r[0][0] + r[1][1] + r[2][2];
  if (tr > 0.0) {
    const double s = sqrt(tr + 1.0) * 2.0;
    q[0] = 0.25 * s;
    q[1] = (r[2][1] - r[1][2]) / s;
    q[2] = (r[0][2] - r[2][0]) / s;
    q[3] = (r[1][0] - r[0][1]) / s;
  } else if (r[0][0] > r[1][1] && r[0][0] > r[2][2]) {
    const double s = sqrt(1.0 + r[0][0] - r[1][1] - r[2][2]) * 2.0;
    q[0] = (r[2][1] - r[1][2]) / s;
    q[1] = 0.25 * s;
    q[2] = (r[0][1] + r[1][0]) / s;
    q[3] = (r[0][2] + r[2][0]) / s;
  } else if (r[1][1] > r[2][2]) {
    const double s = sqrt(1.0 + r[1][1] - r[0][0] - r[2][2]) * 2.0;
    q[0] = (r[0][2] - r[2][0]) / s;
    q[1] = (r[0][1] + r[1][0]) / s;
    q[2] = 0.25 * s;
    q[3] = (r[1][2] + r[2][1]) / s;
  } else {
    const double s = sqrt(1.0 + r[2][2] - r[0][0] - r[1][1]) * 2.0;
    q[0] = (r[1][0] - r[0][1]) / s;
    q[1] = (r[0][2] + r[2][0]) / s;
    q[2] = (r[1][2] + r[2][1]) / s;
    q[3] = 0.25 * s;
  }
  const double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  for (int i = 0; i < 4; i++) q[i] /= n;
  if (q[0] < 0.0)
    for (int i = 0; i < 4; i++) q[i] = -q[i];
}

model_status_t model_quat_unit(const double q[4], double unit[4]) {
  if (q == NULL) return MODEL_E_ARG;
  double n2 = 0.0;
  for (int k = 0; k < 4; ++k) {
    if (!isfinite(q[k])) return MODEL_E_NONFINITE;
    n2 += q[k] * q[k];
  }
  const double n = sqrt(n2);
  if (!(fabs(n - 1.0) <= MODEL_QUAT_UNIT_TOL)) return MODEL_E_POSE;
  for (int k = 0; k < 4; ++k) unit[k] = q[k] / n;
  return MODEL_OK;
}

void model_quat_rotate(const double q[4], const double v[3], double out[3]) {
  /* v' = v + 2 w (u x v) + 2 u x (u x v), u = (x, y, z). */
  const double w = q[0], u[3] = {q[1], q[2], q[3]};
  const double t[3] = {2.0 * (u[1] * v[2] - u[2] * v[1]), 2.0 * (u[2] * v[0] - u[0] * v[2]),
                       2.0 * (u[0] * v[1] - u[1] * v[0])};
  const double r[3] = {v[0] + w * t[0] + (u[1] * t[2] - u[2] * t[1]),
                       v[1] + w * t[1] + (u[2] * t[0] - u[0] * t[2]),
                       v[2] + w * t[2] + (u[0] * t[1] - u[1] * t[0])};
  out[0] = r[0];
  out[1] = r[1];
  out[2] = r[2];
}

void model_quat_mul(const double a[4], const double b[4], double out[4]) {
  const double r[4] = {a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
                       a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
                       a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
                       a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]};
  memcpy(out, r, sizeof r);
}

double model_quat_angle(const double a[4], const double b[4]) {
  double d = 0.0;
  for (int k = 0; k < 4; ++k) d += a[k] * b[k];
  d = fabs(d);
  if (d > 1.0) d = 1.0;
  return 2.0 * acos(d);
}
