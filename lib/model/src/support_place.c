/* support_place.c - where an object touches B: its lowest point in an orientation, the edge lines
 * of B's top, and the pose that sets a link point over an edge, touching and never dropped.
 * Pure geometry. */
#include <math.h>

#include "comlearn/model_support.h"

static void link_vertex_world(double r[3][3], const double p[3], const double v[3],
                              double out[3]) {
  for (int i = 0; i < 3; i++) out[i] = r[i][0] * v[0] + r[i][1] * v[1] + r[i][2] * v[2] + p[i];
}

void model_edge_line(const double base_size_m[3], model_edge_t edge, double normal[3],
                       double *offset_m) {
  normal[0] = normal[1] = normal[2] = 0.0;
  switch (edge) {
    case MODEL_EDGE_PX: normal[0] = 1.0; *offset_m = 0.5 * base_size_m[0]; break;
    case MODEL_EDGE_NX: normal[0] = -1.0; *offset_m = 0.5 * base_size_m[0]; break;
    case MODEL_EDGE_PY: normal[1] = 1.0; *offset_m = 0.5 * base_size_m[1]; break;
    case MODEL_EDGE_NY: normal[1] = -1.0; *offset_m = 0.5 * base_size_m[1]; break;
    default: *offset_m = 0.0; break;
  }
}

static int quat_ok(const double q[4]) {
  if (!q) return 0;
  double n = 0.0;
  for (int i = 0; i < 4; i++) {
    if (!isfinite(q[i])) return 0;
    n += q[i] * q[i];
  }
  return fabs(sqrt(n) - 1.0) <= MODEL_QUAT_UNIT_TOL;
}

double model_mesh_bottom_z(const model_mesh_t *m, const double q_in[4]) {
  if (!m || !m->vertices_m || m->vertex_count == 0 || !quat_ok(q_in)) return NAN;
  double q[4], n = sqrt(q_in[0] * q_in[0] + q_in[1] * q_in[1] + q_in[2] * q_in[2] +
                        q_in[3] * q_in[3]);
  for (int i = 0; i < 4; i++) q[i] = q_in[i] / n;
  double r[3][3];
  model_quat_to_rot(q, r);
  double lo = INFINITY;
  for (size_t i = 0; i < m->vertex_count; i++) {
    const double *v = m->vertices_m[i];
    lo = fmin(lo, r[2][0] * v[0] + r[2][1] * v[1] + r[2][2] * v[2]);
  }
  return lo;
}

/* Lowest z of the segment (s0, z0)-(s1, z1) of a vertical plane within |s| <= half (z is linear
 * along it: the lowest point is an end of the clipped segment); INFINITY if it misses. */
static double clipped_low_z(double s0, double z0, double s1, double z1, double half) {
  if (s1 < s0) {
    double t = s0;
    s0 = s1, s1 = t, t = z0, z0 = z1, z1 = t;
  }
  if (s1 < -half || s0 > half) return INFINITY;
  if (!(s1 > s0)) return fmin(z0, z1);
  const double a = fmax(s0, -half), b = fmin(s1, half);
  return fmin(z0 + (a - s0) / (s1 - s0) * (z1 - z0), z0 + (b - s0) / (s1 - s0) * (z1 - z0));
}

/* Lowest world z, with the link origin at pos (z as given), of the part of the mesh that lies
 * over B as a solid box: vertices over the footprint |x| <= hx, |y| <= hy, and every triangle's
 * cut by the vertical planes x = +-hx, y = +-hy within the footprint's side there (B's top edge
 * lines, their ends the corners). INFINITY when no part of the mesh is over B. */
static double solid_touch_z(const model_mesh_t *m, double r[3][3], const double pos[3],
                            double hx, double hy) {
  double lo = INFINITY;
  for (size_t i = 0; i < m->vertex_count; i++) {
    double v[3];
    link_vertex_world(r, pos, m->vertices_m[i], v);
    if (fabs(v[0]) <= hx && fabs(v[1]) <= hy) lo = fmin(lo, v[2]);
  }
  for (size_t t = 0; t < m->triangle_count; t++) {
    double x[3][3];
    for (int k = 0; k < 3; k++) link_vertex_world(r, pos, m->vertices_m[m->triangles[t][k]], x[k]);
    for (int pl = 0; pl < 4; pl++) {
      const int axis = pl < 2 ? 0 : 1, along = 1 - axis;
      const double plane = (pl % 2 == 0 ? 1.0 : -1.0) * (axis == 0 ? hx : hy);
      const double half = axis == 0 ? hy : hx;
      double d[3];
      for (int k = 0; k < 3; k++) d[k] = x[k][axis] - plane;
      if ((d[0] > 0.0 && d[1] > 0.0 && d[2] > 0.0) || (d[0] < 0.0 && d[1] < 0.0 && d[2] < 0.0))
        continue;
      if (d[0] == 0.0 && d[1] == 0.0 && d[2] == 0.0) { /* the triangle lies in the plane */
        for (int k = 0; k < 3; k++) {
          const int j = (k + 1) % 3;
          lo = fmin(lo, clipped_low_z(x[k][along], x[k][2], x[j][along], x[j][2], half));
        }
        continue;
      }
      /* Otherwise the triangle meets the plane in a segment (or a point): at most two points,
       * its vertices on the plane and its edges' crossings. */
      double s[2] = {0.0, 0.0}, z[2] = {0.0, 0.0};
      int n = 0;
      for (int k = 0; k < 3 && n < 2; k++) {
        const int j = (k + 1) % 3;
        if (d[k] == 0.0) {
          s[n] = x[k][along];
          z[n++] = x[k][2];
        } else if (d[k] * d[j] < 0.0) {
          const double u = d[k] / (d[k] - d[j]);
          s[n] = x[k][along] + u * (x[j][along] - x[k][along]);
          z[n++] = x[k][2] + u * (x[j][2] - x[k][2]);
        }
      }
      if (n == 1) s[1] = s[0], z[1] = z[0];
      if (n > 0) lo = fmin(lo, clipped_low_z(s[0], z[0], s[1], z[1], half));
    }
  }
  return lo;
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
  if (!quat_ok(q_in)) return MODEL_E_POSE;
  if (touch_depth_m < 0.0 || touch_depth_m > MODEL_MAX_TOUCH_DEPTH_M) return MODEL_E_ARG;
  for (int i = 0; i < 3; i++)
    if (fabs(point_link_m[i]) > MODEL_MAX_POSITION_M) return MODEL_E_POSE;
  const int axis = (edge == MODEL_EDGE_PX || edge == MODEL_EDGE_NX) ? 0 : 1;
  if (fabs(along_m) > 0.5 * base_size_m[1 - axis]) return MODEL_E_POSE;
  double n[3], d;
  model_edge_line(base_size_m, edge, n, &d);
  model_pose_t p;
  const double qn = sqrt(q_in[0] * q_in[0] + q_in[1] * q_in[1] + q_in[2] * q_in[2] +
                         q_in[3] * q_in[3]);
  for (int i = 0; i < 4; i++) p.orientation_wxyz[i] = q_in[i] / qn;
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
    p.position_m[2] = 0.0;
    const double zlow = solid_touch_z(m, r, p.position_m, hx, hy);
    if (!isfinite(zlow)) return MODEL_E_POSE;
    p.position_m[2] = -zlow - touch_depth_m;
  }
  *out = p;
  return MODEL_OK;
}
