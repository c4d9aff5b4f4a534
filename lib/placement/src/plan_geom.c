/* Geometry of the placement plans: transforms, resting height on B's top, box-box overlap. */
#include "plan_geom.h"

#include <math.h>

static void keep_min(double z, int *found, double *best) {
  if (!*found || z < *best) {
    *best = z;
    *found = 1;
  }
}

/* Where the segment p -> q crosses the line coordinate[axis] = c, with the other coordinate
 * within +-half_other: the z there. */
static void edge_crossing(const double p[3], const double q[3], int axis, double c,
                          double half_other, int *found, double *best) {
  const double dp = p[axis] - c, dq = q[axis] - c;
  if ((dp > 0.0 && dq > 0.0) || (dp < 0.0 && dq < 0.0) || dp == dq) return;
  const double t = dp / (dp - dq);
  const int other = 1 - axis;
  const double u = p[other] + t * (q[other] - p[other]);
  if (fabs(u) > half_other) return;
  keep_min(p[2] + t * (q[2] - p[2]), found, best);
}

int plan_mesh_lowest_over_rect(const model_mesh_t *mesh, const double (*r)[3], double ox,
                               double oy, double half_x, double half_y, double *z_m) {
  int found = 0;
  double best = 0.0;
  for (size_t i = 0; i < mesh->vertex_count; ++i) {
    const double *v = mesh->vertices_m[i];
    const double x = r[0][0] * v[0] + r[0][1] * v[1] + r[0][2] * v[2] + ox;
    const double y = r[1][0] * v[0] + r[1][1] * v[1] + r[1][2] * v[2] + oy;
    if (fabs(x) <= half_x && fabs(y) <= half_y) {
      keep_min(r[2][0] * v[0] + r[2][1] * v[1] + r[2][2] * v[2], &found, &best);
    }
  }
  const double corners[4][2] = {{-half_x, -half_y}, {half_x, -half_y}, {half_x, half_y},
                                {-half_x, half_y}};
  for (size_t t = 0; t < mesh->triangle_count; ++t) {
    double w[3][3];
    for (int k = 0; k < 3; ++k) {
      const double *v = mesh->vertices_m[mesh->triangles[t][k]];
      for (int a = 0; a < 3; ++a) w[k][a] = r[a][0] * v[0] + r[a][1] * v[1] + r[a][2] * v[2];
      w[k][0] += ox;
      w[k][1] += oy;
    }
    for (int k = 0; k < 3; ++k) {
      const double *p = w[k], *q = w[(k + 1) % 3];
      edge_crossing(p, q, 0, -half_x, half_y, &found, &best);
      edge_crossing(p, q, 0, half_x, half_y, &found, &best);
      edge_crossing(p, q, 1, -half_y, half_x, &found, &best);
      edge_crossing(p, q, 1, half_y, half_x, &found, &best);
    }
    /* Rectangle corners inside the projected triangle: barycentric z. */
    const double e1x = w[1][0] - w[0][0], e1y = w[1][1] - w[0][1];
    const double e2x = w[2][0] - w[0][0], e2y = w[2][1] - w[0][1];
    const double det = e1x * e2y - e2x * e1y;
    if (fabs(det) <= 1e-300) continue; /* vertical triangle: its edges were visited */
    for (int c = 0; c < 4; ++c) {
      const double dx = corners[c][0] - w[0][0], dy = corners[c][1] - w[0][1];
      const double b1 = (dx * e2y - e2x * dy) / det;
      const double b2 = (e1x * dy - dx * e1y) / det;
      if (b1 < 0.0 || b2 < 0.0 || b1 + b2 > 1.0) continue;
      keep_min(w[0][2] + b1 * (w[1][2] - w[0][2]) + b2 * (w[2][2] - w[0][2]), &found, &best);
    }
  }
  if (found) *z_m = best;
  return found;
}

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
