/* support_place.c - where an object touches B: its lowest point in an orientation, the edge lines
 * of B's top, and the pose that sets a link point over an edge, touching and never dropped.
 * Pure geometry. */
#include <math.h>

#include "comlearn/model_support.h"

static void link_vertex_world(double r[3][3], const double p[3], const double v[3], double out[3]) {
  for (int i = 0; i < 3; i++) out[i] = r[i][0] * v[0] + r[i][1] * v[1] + r[i][2] * v[2] + p[i];
}

void model_edge_line(const double base_size_m[3], model_edge_t edge, double normal[3],
                     double *offset_m) {
  normal[0] = normal[1] = normal[2] = 0.0;
  switch (edge) {
    case MODEL_EDGE_PX:
      normal[0] = 1.0;
      *offset_m = 0.5 * base_size_m[0];
      break;
    case MODEL_EDGE_NX:
      normal[0] = -1.0;
      *offset_m = 0.5 * base_size_m[0];
      break;
    case MODEL_EDGE_PY:
      normal[1] = 1.0;
      *offset_m = 0.5 * base_size_m[1];
      break;
    case MODEL_EDGE_NY:
      normal[1] = -1.0;
      *offset_m = 0.5 * base_size_m[1];
      break;
    default: *offset_m = 0.0; break;
  }
}

double model_mesh_bottom_z(const model_mesh_t *m, const double q_in[4]) {
  double q[4];
  if (!m || !m->vertices_m || m->vertex_count == 0 || model_quat_unit(q_in, q) != MODEL_OK)
    return NAN;
  double r[3][3];
  model_quat_to_rot(q, r);
  double lo = INFINITY;
  for (size_t i = 0; i < m->vertex_count; i++) {
    const double *v = m->vertices_m[i];
    lo = fmin(lo, r[2][0] * v[0] + r[2][1] * v[1] + r[2][2] * v[2]);
  }
  return lo;
}

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

int model_mesh_lowest_over_rect(const model_mesh_t *mesh, const double (*r)[3], double ox,
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
  const double corners[4][2] = {
      {-half_x, -half_y}, {half_x, -half_y}, {half_x, half_y}, {-half_x, half_y}};
  for (size_t t = 0; t < mesh->triangle_count; ++t) {
    double w[3][3];
    for (int k = 0; k < 3; ++k) {
      const double *v = mesh->vertices_m[mesh->triangles[t][k]];
      for (int a = 0; a < 3; ++a) w[k][a] = r[a][0] * v[0] + r[a][1] * v[1] + r[a][2] * v[2];
      w[k][0] += ox;
      w[k][1] += oy;
    }
    /* Inside the rectangle, a triangle's lowest point is a vertex (seen above); wholly beyond
     * one side of it, the triangle does not count. Only the others can cross its boundary or
     * hold a corner. */
    int inside = 0, beyond[4] = {0, 0, 0, 0};
    for (int k = 0; k < 3; ++k) {
      inside += fabs(w[k][0]) <= half_x && fabs(w[k][1]) <= half_y;
      beyond[0] += w[k][0] < -half_x;
      beyond[1] += w[k][0] > half_x;
      beyond[2] += w[k][1] < -half_y;
      beyond[3] += w[k][1] > half_y;
    }
    if (inside == 3 || beyond[0] == 3 || beyond[1] == 3 || beyond[2] == 3 || beyond[3] == 3)
      continue;
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

model_status_t model_pose_over_edge(const model_mesh_t *m, const double base_size_m[3],
                                    const double q_in[4], model_edge_t edge,
                                    const double point_link_m[3], double along_m,
                                    double touch_depth_m, model_pose_t *out) {
  if (!m || !m->vertices_m || !m->triangles || m->vertex_count == 0 || !base_size_m || !q_in ||
      !point_link_m || !out)
    return MODEL_E_ARG;
  for (int i = 0; i < 3; i++)
    if (!(base_size_m[i] > 0.0) || !isfinite(base_size_m[i])) return MODEL_E_ARG;
  if (edge != MODEL_EDGE_PX && edge != MODEL_EDGE_NX && edge != MODEL_EDGE_PY &&
      edge != MODEL_EDGE_NY)
    return MODEL_E_ARG;
  for (int i = 0; i < 4; i++)
    if (!isfinite(q_in[i])) return MODEL_E_NONFINITE;
  for (int i = 0; i < 3; i++)
    if (!isfinite(point_link_m[i])) return MODEL_E_NONFINITE;
  if (!isfinite(along_m) || !isfinite(touch_depth_m)) return MODEL_E_NONFINITE;
  model_pose_t p;
  if (model_quat_unit(q_in, p.orientation_wxyz) != MODEL_OK) return MODEL_E_POSE;
  if (touch_depth_m < 0.0 || touch_depth_m > MODEL_MAX_TOUCH_DEPTH_M) return MODEL_E_ARG;
  for (int i = 0; i < 3; i++)
    if (fabs(point_link_m[i]) > MODEL_MAX_POSITION_M) return MODEL_E_POSE;
  const int axis = (edge == MODEL_EDGE_PX || edge == MODEL_EDGE_NX) ? 0 : 1;
  if (fabs(along_m) > 0.5 * base_size_m[1 - axis]) return MODEL_E_POSE;
  double n[3], d;
  model_edge_line(base_size_m, edge, n, &d);
  double r[3][3], rp[3];
  model_quat_to_rot(p.orientation_wxyz, r);
  for (int i = 0; i < 3; i++)
    rp[i] = r[i][0] * point_link_m[0] + r[i][1] * point_link_m[1] + r[i][2] * point_link_m[2];
  /* The point lies on the edge line: its coordinate along the normal axis is n[axis] * d. */
  p.position_m[axis] = n[axis] * d - rp[axis];
  p.position_m[1 - axis] = along_m - rp[1 - axis];
  p.position_m[2] = -model_mesh_bottom_z(m, p.orientation_wxyz) - touch_depth_m;
  /* It must rest on B's top: some of its lowest points inside the footprint. */
  const double hx = 0.5 * base_size_m[0], hy = 0.5 * base_size_m[1];
  int on_top = 0;
  for (size_t i = 0; i < m->vertex_count && !on_top; i++) {
    double v[3];
    link_vertex_world(r, p.position_m, m->vertices_m[i], v);
    if (v[2] <= -touch_depth_m + 1e-6 && fabs(v[0]) <= hx && fabs(v[1]) <= hy) on_top = 1;
  }
  if (!on_top) {
    /* The lowest vertices are off B: lowered vertically, the mesh first touches B's top face
     * (a vertex over the footprint) or a top edge line (a triangle crossing the edge's vertical
     * plane within the edge's length; B's corners are the ends of those segments). */
    double zlow = 0.0;
    if (!model_mesh_lowest_over_rect(m, (const double(*)[3])r, p.position_m[0], p.position_m[1], hx,
                                     hy, &zlow))
      return MODEL_E_POSE;
    p.position_m[2] = -zlow - touch_depth_m;
  }
  *out = p;
  return MODEL_OK;
}
