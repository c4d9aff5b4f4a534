/* Geometry of the placement plans: box-box overlap (the resting height on B's top is lib/model's
 * model_mesh_lowest_over_rect). */
#include "plan_geom.h"

#include <math.h>

int plan_box_overlap(const double ca[3], const double a[3], const double cb[3],
                     const double r[3][3], const double b[3]) {
  const double t[3] = {cb[0] - ca[0], cb[1] - ca[1], cb[2] - ca[2]};
  double ar[3][3];
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) ar[i][j] = fabs(r[i][j]);
  }
  for (int i = 0; i < 3; ++i) { /* A's axes */
    const double rb = b[0] * ar[i][0] + b[1] * ar[i][1] + b[2] * ar[i][2];
    if (fabs(t[i]) >= a[i] + rb) return 0;
  }
  for (int j = 0; j < 3; ++j) { /* B's axes */
    const double ra = a[0] * ar[0][j] + a[1] * ar[1][j] + a[2] * ar[2][j];
    const double d = t[0] * r[0][j] + t[1] * r[1][j] + t[2] * r[2][j];
    if (fabs(d) >= ra + b[j]) return 0;
  }
  for (int i = 0; i < 3; ++i) { /* A_i x B_j, unnormalised (both sides scale alike) */
    const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
    for (int j = 0; j < 3; ++j) {
      if (1.0 - r[i][j] * r[i][j] < 1e-12) continue; /* parallel: a face axis decides */
      const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      const double ra = a[i1] * ar[i2][j] + a[i2] * ar[i1][j];
      const double rb = b[j1] * ar[i][j2] + b[j2] * ar[i][j1];
      const double d = t[i2] * r[i1][j] - t[i1] * r[i2][j];
      if (fabs(d) >= ra + rb) return 0;
    }
  }
  return 1;
}
