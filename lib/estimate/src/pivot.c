/* pivot.c - the geometry of pivot trials (pivot.h). */
#include "pivot.h"

#include <math.h>
#include <string.h>

#include "comlearn/math3d.h"

/* Tilts beyond this are not planned: tan grows without bound toward pi / 2. */
#define PIVOT_MAX_TILT_RAD 1.2
/* How far a tilt keeps from laying all of the object beyond the edge's vertical plane, or all of
 * it on B's side (estimate_pivot_plan). */
#define PIVOT_STRADDLE_RAD 0.01
/* The edge's ends must be the lowest of the object over B's top to this (estimate_pivot_pose). */
#define PIVOT_TOUCH_TOL_M 1e-8
/* A pivot trial that ended within this angle of its release, or turned about the edge line by
 * less, has not shown a direction (lib/balance calls a CoM beyond the edge within ~20 ms, turned
 * by 1e-7 to 1e-2 rad; one that turns back ends turned by 0.05-0.35 rad). */
#define PIVOT_TURN_RAD 1e-2

/* The angle of w (perpendicular to e) about e, from up (0) toward -u (positive: B's side at tilt
 * 0) or u (negative), in (-pi, pi]. */
static double wedge_angle(const estimate_pivot_t *pv, const double w[3]) {
  return atan2(-cl_vec3_dot(w, pv->u), cl_vec3_dot(w, pv->up));
}

int estimate_pivot_plan(const model_mesh_t *hull, const model_hull_edge_t *he, int flip,
                        const double g[3], double wedge_margin_rad, double min_height_m,
                        estimate_pivot_t *out) {
  const double(*v)[3] = (const double(*)[3])hull->vertices_m;
  estimate_pivot_t *pv = out;
  memset(pv, 0, sizeof *pv);
  pv->v[0] = he->v[flip ? 1 : 0];
  pv->v[1] = he->v[flip ? 0 : 1];
  memcpy(pv->p1_m, v[pv->v[0]], sizeof pv->p1_m);
  memcpy(pv->p2_m, v[pv->v[1]], sizeof pv->p2_m);
  double d[3], w[3];
  cl_vec3_sub(pv->p2_m, pv->p1_m, d);
  pv->len_m = cl_vec3_normalize(d, pv->e);
  for (int k = 0; k < 3; ++k) pv->mid_m[k] = 0.5 * (pv->p1_m[k] + pv->p2_m[k]);
  if (!(pv->len_m > 0.0)) return 0;
  cl_vec3_sub(g, pv->p1_m, d);
  const double t = cl_vec3_dot(d, pv->e);
  for (int k = 0; k < 3; ++k) w[k] = d[k] - t * pv->e[k];
  pv->h_m = cl_vec3_normalize(w, pv->up);
  if (!(pv->h_m >= min_height_m)) return 0;
  cl_vec3_cross(pv->e, pv->up, pv->u);
  pv->gx_m = cl_vec3_dot(pv->u, g);
  /* The hull lies in the wedge between its two triangles at the edge; g (angle 0) inside it. */
  double a[2];
  for (int i = 0; i < 2; ++i) {
    cl_vec3_sub(v[he->opposite[i]], pv->p1_m, d);
    const double s = cl_vec3_dot(d, pv->e);
    for (int k = 0; k < 3; ++k) w[k] = d[k] - s * pv->e[k];
    a[i] = wedge_angle(pv, w);
  }
  const double lo = fmin(a[0], a[1]), hi = fmax(a[0], a[1]);
  if (!(lo <= 0.0 && hi >= 0.0 && hi - lo < CL_PI)) return 0; /* g is not inside the hull */
  /* Tilted by beta, a direction at wedge angle a points at world angle pi/2 + a - beta (from +x
   * toward +z); B fills the angles (pi, 3 pi / 2). The wedge [lo, hi] clears B for
   * hi - pi/2 <= beta <= pi + lo, and it reaches over B's top as well as beyond the edge for
   * lo < beta < hi (at beta = a a CoM at wedge angle a balances: every CoM inside the hull has
   * its threshold there). Where all of the object lay on one side of the edge's vertical plane,
   * only the edge would touch it, and whether the edge counts as over B's top would be a
   * matter of rounding (model_mesh_lowest_over_rect). */
  pv->beta_lo_rad =
      fmax(fmax(hi - 0.5 * CL_PI + wedge_margin_rad, lo + PIVOT_STRADDLE_RAD), -PIVOT_MAX_TILT_RAD);
  pv->beta_hi_rad =
      fmin(fmin(CL_PI + lo - wedge_margin_rad, hi - PIVOT_STRADDLE_RAD), PIVOT_MAX_TILT_RAD);
  if (!(pv->beta_lo_rad < 0.0 && pv->beta_hi_rad > 0.0)) return 0;
  return 1;
}

void estimate_pivot_reach(const model_mesh_t *hull, estimate_pivot_t *pv) {
  pv->reach_m = 0.0;
  for (size_t i = 0; i < hull->vertex_count; ++i) {
    double d[3], w[3];
    cl_vec3_sub(hull->vertices_m[i], pv->p1_m, d);
    const double s = cl_vec3_dot(d, pv->e);
    for (int k = 0; k < 3; ++k) w[k] = d[k] - s * pv->e[k];
    pv->reach_m = fmax(pv->reach_m, cl_vec3_norm(w));
  }
}

double estimate_pivot_side_margin(const estimate_pivot_t *pv, const double c[3]) {
  double d[3];
  cl_vec3_sub(c, pv->p1_m, d);
  const double t = cl_vec3_dot(d, pv->e);
  return fmin(t, pv->len_m - t);
}

void estimate_pivot_orientation(const estimate_pivot_t *pv, double x, double q_wxyz[4]) {
  const double beta = atan((pv->gx_m - x) / pv->h_m);
  const double c = cos(beta), s = sin(beta);
  double r[3][3];
  for (int k = 0; k < 3; ++k) {
    r[0][k] = c * pv->u[k] + s * pv->up[k]; /* world +x, in the link frame */
    r[1][k] = pv->e[k];
    r[2][k] = c * pv->up[k] - s * pv->u[k];
  }
  cl_quat_from_rot((const double(*)[3])r, q_wxyz);
}

int estimate_pivot_pose(const estimate_pivot_t *pv, const model_mesh_t *mesh,
                        const double base_size_m[3], double x, double touch_m, model_pose_t *out) {
  estimate_pivot_orientation(pv, x, out->orientation_wxyz);
  double r[3][3], m[3];
  cl_quat_to_rot(out->orientation_wxyz, r);
  for (int i = 0; i < 3; ++i) m[i] = cl_vec3_dot(r[i], pv->mid_m);
  out->position_m[0] = 0.5 * base_size_m[0] - m[0];
  out->position_m[1] = -m[1];
  /* lowered as every placement planner lowers (lib/placement's touch height): until the lowest
   * point of the mesh over B's top touches, touch_m deep */
  double low = 0.0;
  if (!model_mesh_lowest_over_rect(mesh, (const double(*)[3])r, out->position_m[0],
                                   out->position_m[1], 0.5 * base_size_m[0], 0.5 * base_size_m[1],
                                   &low))
    return 0;
  out->position_m[2] = -touch_m - low;
  for (int i = 0; i < 2; ++i) { /* that point is the edge: both its ends touch */
    double p[3];
    cl_pose_apply(out, i ? pv->p2_m : pv->p1_m, p);
    if (!(fabs(p[2] + touch_m) <= PIVOT_TOUCH_TOL_M)) return 0;
  }
  return 1;
}

void estimate_pivot_normal(const double q_wxyz[4], double n[3]) {
  double r[3][3];
  cl_quat_to_rot(q_wxyz, r);
  for (int k = 0; k < 3; ++k) n[k] = r[0][k];
}

double estimate_pivot_x(const estimate_pivot_t *pv, const double q_wxyz[4]) {
  double n[3];
  estimate_pivot_normal(q_wxyz, n);
  const double beta = atan2(cl_vec3_dot(n, pv->up), cl_vec3_dot(n, pv->u));
  return pv->gx_m - pv->h_m * tan(beta);
}

estimate_outcome_t estimate_pivot_outcome(estimate_outcome_t outcome, const model_pose_t *released,
                                          const model_pose_t *settled) {
  /* the turn from release to the end, in the world: angle rot about a unit axis */
  double qc[4], dq[4];
  cl_quat_conj(released->orientation_wxyz, qc);
  cl_quat_mul(settled->orientation_wxyz, qc, dq);
  const double vn = sqrt(dq[1] * dq[1] + dq[2] * dq[2] + dq[3] * dq[3]);
  const double rot = 2.0 * atan2(vn, fabs(dq[0]));
  /* about the edge line (world +y), positive outward (the top toward +x) */
  const double turn = vn > 0.0 ? rot * dq[2] / vn * (dq[0] < 0.0 ? -1.0 : 1.0) : 0.0;
  /* A clear turn about the edge line says the side, whatever the trial was called: turning about
   * an edge far below the CoM moves it fast for the angle, and lib/balance's slide rule (5 mm
   * before 0.09 rad) can call it SLIDES (over LCM, on B: INVALID). */
  if ((outcome == ESTIMATE_TIPS && rot <= PIVOT_TURN_RAD) ||
      (rot > PIVOT_TURN_RAD && turn >= 0.5 * rot))
    return ESTIMATE_TIPS;
  if (turn <= -PIVOT_TURN_RAD && turn <= -0.5 * rot) return ESTIMATE_STAYS;
  return ESTIMATE_INVALID;
}
