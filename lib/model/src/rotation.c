/* Rotations shared by every library above lib/model (comlearn/model.h). */
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
