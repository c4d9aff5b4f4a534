/* Rotations shared by every library above lib/model (comlearn/model.h). */
#include <math.h>

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
