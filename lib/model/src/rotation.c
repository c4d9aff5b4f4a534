/* Rotations of lib/model's API (comlearn/model.h): comlearn/math3d.h's arithmetic, and the check
 * of a unit quaternion. */
#include <math.h>
#include <string.h>

#include "comlearn/math3d.h"
#include "comlearn/model.h"

void model_quat_to_rot(const double q_wxyz[4], double rot[3][3]) { cl_quat_to_rot(q_wxyz, rot); }

void model_rot_to_quat(const double rot[3][3], double q_wxyz[4]) { cl_quat_from_rot(rot, q_wxyz); }

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
