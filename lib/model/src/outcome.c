/* outcome.c - the geometric outcome model (comlearn/model_outcome.h): the support polygon of an
 * object released on B and the CoM test against it. Pure geometry, no allocation (except
 * model_outcome_predict without a work area). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "comlearn/model_outcome.h"
#include "model_internal.h"

/* Points gathered before the hull is taken of them (the hull then replaces them). Twice the
 * largest polygon, so every compression frees at least half of the buffer. */
enum { CHUNK = 2 * MODEL_OUTCOME_MAX_VERTICES };

/* Points where the hull turns by less than 1e-12 rad are dropped (the crossings of one edge line,
 * a rotated row of vertices: collinear but for rounding); each lies within 1e-12 x the side's
 * length of it. */
#define HULL_SIN_TOL 1e-12

struct model_outcome_work {
  size_t vertex_count, triangle_count;
  double (*w)[3];      /* vertices in the world */
  unsigned char *code; /* out-codes against B's four edge planes (bit k: beyond plane k) */
  uint32_t *cross;     /* triangles whose corners' out-codes differ */
  size_t ncross;
  double (*pts)[2];                 /* support points gathered, CHUNK + 1 */
  double (*hull)[2];                /* hull scratch, CHUNK + 1 */
  double (*p0)[2];                  /* the band's hull, MODEL_OUTCOME_MAX_VERTICES */
  size_t npts;                      /* in pts now */
  size_t total;                     /* gathered in all */
  model_outcome_support_t *support; /* model_outcome_predict's */
};

static size_t align8(size_t n) { return (n + 7u) & ~(size_t)7u; }

void model_outcome_config_default(model_outcome_config_t *cfg) {
  if (cfg == NULL) return;
  const model_outcome_config_t d = MODEL_OUTCOME_CONFIG_DEFAULT;
  *cfg = d;
}

model_status_t model_outcome_config_check(const model_outcome_config_t *cfg) {
  if (cfg == NULL) return MODEL_E_ARG;
  if (!isfinite(cfg->tol_m) || !isfinite(cfg->tilt_rad) || !isfinite(cfg->min_width_m))
    return MODEL_E_NONFINITE;
  if (cfg->tol_m < 0.0 || cfg->tol_m > MODEL_OUTCOME_MAX_TOL_M || cfg->tilt_rad < 0.0 ||
      cfg->tilt_rad > MODEL_OUTCOME_MAX_TILT_RAD || cfg->min_width_m < 0.0)
    return MODEL_E_ARG;
  return MODEL_OK;
}

size_t model_outcome_work_size(const model_mesh_t *mesh) {
  if (mesh == NULL || mesh->vertex_count == 0 || mesh->triangle_count == 0) return 0;
  const size_t nv = mesh->vertex_count;
  return align8(sizeof(model_outcome_work_t)) + align8(nv * sizeof(double[3])) + align8(nv) +
         align8(mesh->triangle_count * sizeof(uint32_t)) +
         2 * align8((CHUNK + 1) * sizeof(double[2])) +
         align8(MODEL_OUTCOME_MAX_VERTICES * sizeof(double[2])) +
         align8(sizeof(model_outcome_support_t));
}

model_outcome_work_t *model_outcome_work_init(void *mem, size_t size, const model_mesh_t *mesh) {
  const size_t need = model_outcome_work_size(mesh);
  if (mem == NULL || need == 0 || size < need || ((uintptr_t)mem & 7u) != 0) return NULL;
  const size_t nv = mesh->vertex_count;
  unsigned char *p = mem;
  model_outcome_work_t *w = (model_outcome_work_t *)(void *)p;
  memset(w, 0, sizeof *w);
  p += align8(sizeof *w);
  w->vertex_count = nv;
  w->triangle_count = mesh->triangle_count;
  w->w = (double(*)[3])(void *)p;
  p += align8(nv * sizeof(double[3]));
  w->code = p;
  p += align8(nv);
  w->cross = (uint32_t *)(void *)p;
  p += align8(mesh->triangle_count * sizeof(uint32_t));
  w->pts = (double(*)[2])(void *)p;
  p += align8((CHUNK + 1) * sizeof(double[2]));
  w->hull = (double(*)[2])(void *)p;
  p += align8((CHUNK + 1) * sizeof(double[2]));
  w->p0 = (double(*)[2])(void *)p;
  p += align8(MODEL_OUTCOME_MAX_VERTICES * sizeof(double[2]));
  w->support = (model_outcome_support_t *)(void *)p;
  return w;
}

/* Add a support point; when the buffer is full, replace its points by their hull (the hull of
 * the union is the hull of (hull of the first part) and the rest). */
static model_status_t point_add(model_outcome_work_t *w, double x, double y) {
  if (w->npts == CHUNK) {
    const size_t k = model_polygon_hull_tol(w->pts, w->npts, w->hull, HULL_SIN_TOL);
    if (k > MODEL_OUTCOME_MAX_VERTICES) return MODEL_E_CAPACITY;
    memcpy(w->pts, w->hull, k * sizeof *w->hull);
    w->npts = k;
  }
  w->pts[w->npts][0] = x;
  w->pts[w->npts][1] = y;
  ++w->npts;
  ++w->total;
  return MODEL_OK;
}

/* ---- the support set ---------------------------------------------------------------------- */

static model_status_t pose_check(const model_pose_t *pose, double r[3][3]) {
  for (int k = 0; k < 3; ++k)
    if (!isfinite(pose->position_m[k])) return MODEL_E_NONFINITE;
  for (int k = 0; k < 3; ++k)
    if (fabs(pose->position_m[k]) > MODEL_MAX_POSITION_M) return MODEL_E_POSE;
  double q[4];
  const model_status_t st = model_quat_unit(pose->orientation_wxyz, q);
  if (st != MODEL_OK) return st;
  model_quat_to_rot(q, r);
  return MODEL_OK;
}

static model_status_t inputs_check(const model_mesh_t *m, const model_pose_t *pose,
                                   const double base[3], const model_outcome_work_t *w) {
  if (m == NULL || pose == NULL || base == NULL || w == NULL || m->vertices_m == NULL ||
      m->triangles == NULL || m->vertex_count == 0 || m->triangle_count == 0)
    return MODEL_E_ARG;
  if (w->vertex_count != m->vertex_count || w->triangle_count != m->triangle_count)
    return MODEL_E_ARG;
  for (int k = 0; k < 3; ++k) {
    if (!isfinite(base[k])) return MODEL_E_NONFINITE;
    if (!(base[k] > 0.0)) return MODEL_E_ARG;
  }
  return MODEL_OK;
}

/* Vertices into the world with their out-codes; checks finiteness. *zmin: the lowest vertex
 * over the rectangle (HUGE_VAL when none). */
static model_status_t vertices_place(const model_mesh_t *m, const double r[3][3], const double p[3],
                                     double hx, double hy, model_outcome_work_t *w, double *zmin) {
  *zmin = HUGE_VAL;
  for (size_t i = 0; i < m->vertex_count; ++i) {
    const double *v = m->vertices_m[i];
    if (!isfinite(v[0]) || !isfinite(v[1]) || !isfinite(v[2])) return MODEL_E_NONFINITE;
    double *x = w->w[i];
    for (int k = 0; k < 3; ++k) x[k] = r[k][0] * v[0] + r[k][1] * v[1] + r[k][2] * v[2] + p[k];
    const unsigned char c =
        (unsigned char)((x[0] > hx) | (x[0] < -hx) << 1 | (x[1] > hy) << 2 | (x[1] < -hy) << 3);
    w->code[i] = c;
    if (c == 0 && x[2] < *zmin) *zmin = x[2];
  }
  return MODEL_OK;
}

/* Where segment a -> b crosses edge plane k (0: x = +hx, 1: x = -hx, 2: y = +hy, 3: y = -hy)
 * within the edge's length, as lib/balance's generator computes it. Only called when the ends'
 * out-codes differ in bit k. Returns 1 with the point in x. */
static int plane_cross(const double a[3], const double b[3], int k, double hx, double hy,
                       double x[3]) {
  const int axis = k < 2 ? 0 : 1;
  const double h = axis == 0 ? hx : hy, other = axis == 0 ? hy : hx;
  const double plane = (k % 2 == 0) ? h : -h;
  const double da = a[axis] - plane, db = b[axis] - plane;
  const double t = da / (da - db);
  for (int c = 0; c < 3; ++c) x[c] = a[c] + t * (b[c] - a[c]);
  return fabs(x[1 - axis]) <= other;
}

/* Which support candidates are taken: z <= zband (the band), or, with tilt > 0, z <= zband +
 * tilt x (horizontal distance to the band's hull p0): the object reaches such a point by turning
 * at most `tilt` about its band support. zmax bounds both (a cheap first test). */
typedef struct {
  double zband, zmax, tilt;
  const double (*p0)[2];
  size_t n0;
} gate_t;

/* Distance from (x, y) to the convex polygon p0 (n0 vertices, counter-clockwise; 1: a point,
 * 2: a segment); 0 inside. */
static double poly_dist(const double (*p0)[2], size_t n0, double x, double y) {
  int inside = n0 >= 3;
  double best = HUGE_VAL;
  for (size_t i = 0; i < n0; ++i) {
    const double *a = p0[i], *b = p0[(i + 1) % n0];
    const double ex = b[0] - a[0], ey = b[1] - a[1], px = x - a[0], py = y - a[1];
    if (ex * py - ey * px < 0.0) inside = 0;
    const double ll = ex * ex + ey * ey;
    double t = ll > 0.0 ? (px * ex + py * ey) / ll : 0.0;
    t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
    const double dx = px - t * ex, dy = py - t * ey, d = sqrt(dx * dx + dy * dy);
    if (d < best) best = d;
    if (n0 == 2) break; /* a segment: one side */
  }
  return inside ? 0.0 : best;
}

static int gate_pass(const gate_t *g, double x, double y, double z) {
  if (z > g->zmax) return 0;
  if (g->tilt <= 0.0) return z <= g->zband;
  /* the band's points are the vertices of p0 already */
  return z > g->zband && z <= g->zband + g->tilt * poly_dist(g->p0, g->n0, x, y);
}

/* The crossings of triangle t's sides with the edge planes, within the edges' lengths: the
 * lowest into *zmin (g NULL), or those g passes into the point buffer. Every side is visited, so
 * a closed mesh's edges twice: duplicates do not change a hull. */
static model_status_t tri_crossings(const model_mesh_t *m, size_t t, double hx, double hy,
                                    const gate_t *g, model_outcome_work_t *w, double *zmin) {
  const double zcut = g ? g->zmax : HUGE_VAL;
  const uint32_t *tri = m->triangles[t];
  for (int s = 0; s < 3; ++s) {
    const uint32_t ia = tri[s], ib = tri[(s + 1) % 3];
    const unsigned diff = (unsigned)(w->code[ia] ^ w->code[ib]);
    const double *a = w->w[ia], *b = w->w[ib];
    if (diff == 0 || (a[2] > zcut && b[2] > zcut)) continue;
    for (int k = 0; k < 4; ++k) {
      double x[3];
      if (!(diff & (1u << k)) || !plane_cross(a, b, k, hx, hy, x)) continue;
      if (g == NULL) {
        if (x[2] < *zmin) *zmin = x[2];
      } else if (gate_pass(g, x[0], x[1], x[2])) {
        const model_status_t st = point_add(w, x[0], x[1]);
        if (st != MODEL_OK) return st;
      }
    }
  }
  return MODEL_OK;
}

/* First pass over the triangles: checks the indices, lists the triangles whose corners' out-codes
 * differ (only they cross an edge plane) and lowers *zmin to their lowest crossing. */
static model_status_t tris_scan(const model_mesh_t *m, double hx, double hy,
                                model_outcome_work_t *w, double *zmin) {
  w->ncross = 0;
  for (size_t t = 0; t < m->triangle_count; ++t) {
    const uint32_t *tri = m->triangles[t];
    if (tri[0] >= m->vertex_count || tri[1] >= m->vertex_count || tri[2] >= m->vertex_count)
      return MODEL_E_DEGENERATE;
    const unsigned char c0 = w->code[tri[0]];
    if (c0 == w->code[tri[1]] && c0 == w->code[tri[2]]) continue;
    w->cross[w->ncross++] = (uint32_t)t;
    tri_crossings(m, t, hx, hy, NULL, w, zmin);
  }
  return MODEL_OK;
}

/* Every vertex over the rectangle and every listed crossing that g passes into the point
 * buffer (after what it holds). */
static model_status_t support_gather(const model_mesh_t *m, double hx, double hy, const gate_t *g,
                                     model_outcome_work_t *w) {
  model_status_t st = MODEL_OK;
  for (size_t i = 0; i < m->vertex_count && st == MODEL_OK; ++i) {
    const double *x = w->w[i];
    if (w->code[i] == 0 && gate_pass(g, x[0], x[1], x[2])) st = point_add(w, x[0], x[1]);
  }
  for (size_t j = 0; j < w->ncross && st == MODEL_OK; ++j)
    st = tri_crossings(m, w->cross[j], hx, hy, g, w, NULL);
  return st;
}

/* The hull of the point buffer into w->hull; *nh its vertex count. */
static model_status_t buffer_hull(model_outcome_work_t *w, size_t *nh) {
  const size_t k = model_polygon_hull_tol(w->pts, w->npts, w->hull, HULL_SIN_TOL);
  if (k > MODEL_OUTCOME_MAX_VERTICES) return MODEL_E_CAPACITY;
  *nh = k;
  return MODEL_OK;
}

/* The band's hull (w->hull, *nh), then, with tilt > 0, the hull of it and the points reached by
 * turning at most tilt about it. */
static model_status_t support_sets(const model_mesh_t *m, const double base[3], double zref,
                                   double tol_m, double tilt_rad, model_outcome_work_t *w,
                                   size_t *nh) {
  const double hx = 0.5 * base[0], hy = 0.5 * base[1];
  gate_t g = {.zband = zref + tol_m, .zmax = zref + tol_m, .tilt = 0.0};
  w->npts = 0;
  w->total = 0;
  model_status_t st = support_gather(m, hx, hy, &g, w);
  if (st == MODEL_OK) st = buffer_hull(w, nh);
  if (st != MODEL_OK || !(tilt_rad > 0.0)) return st;
  memcpy(w->p0, w->hull, *nh * sizeof *w->hull);
  g.p0 = (const double(*)[2])w->p0;
  g.n0 = *nh;
  g.tilt = tilt_rad;
  g.zmax = g.zband + tilt_rad * hypot(base[0], base[1]); /* every point over B is that near */
  w->npts = 0;
  for (size_t i = 0; i < g.n0 && st == MODEL_OK; ++i) st = point_add(w, w->p0[i][0], w->p0[i][1]);
  w->total -= g.n0; /* counted in the band already */
  if (st == MODEL_OK) st = support_gather(m, hx, hy, &g, w);
  if (st == MODEL_OK) st = buffer_hull(w, nh);
  return st;
}

/* The support hull into w->hull[0 .. *nh), with the plane, the point count and the rotation. */
static model_status_t support_hull(const model_mesh_t *m, const model_pose_t *pose,
                                   const double base[3], double tol_m, double tilt_rad,
                                   model_outcome_work_t *w, double r[3][3], double *zref,
                                   size_t *npoints, size_t *nh) {
  *nh = 0;
  *npoints = 0;
  *zref = HUGE_VAL;
  model_status_t st = inputs_check(m, pose, base, w);
  if (st != MODEL_OK) return st;
  if (!isfinite(tol_m)) return MODEL_E_NONFINITE;
  if (tol_m < 0.0 || tol_m > MODEL_OUTCOME_MAX_TOL_M) return MODEL_E_ARG;
  if ((st = pose_check(pose, r)) != MODEL_OK) return st;
  const double hx = 0.5 * base[0], hy = 0.5 * base[1];
  st = vertices_place(m, (const double(*)[3])r, pose->position_m, hx, hy, w, zref);
  if (st == MODEL_OK) st = tris_scan(m, hx, hy, w, zref);
  if (st != MODEL_OK || !(*zref < HUGE_VAL)) return st; /* nothing over B */
  if ((st = support_sets(m, base, *zref, tol_m, tilt_rad, w, nh)) != MODEL_OK) {
    *nh = 0;
    return st;
  }
  *npoints = w->total;
  return MODEL_OK;
}

model_status_t model_support_polygon(const model_mesh_t *mesh_link, const model_pose_t *pose,
                                     const double base_size_m[3], double tol_m,
                                     model_outcome_work_t *work, double (*polygon_xy_m)[2],
                                     size_t capacity, size_t *n) {
  if (n == NULL || (polygon_xy_m == NULL && capacity > 0)) return MODEL_E_ARG;
  *n = 0;
  double r[3][3], zref;
  size_t npoints, nh;
  const model_status_t st =
      support_hull(mesh_link, pose, base_size_m, tol_m, 0.0, work, r, &zref, &npoints, &nh);
  if (st != MODEL_OK) return st;
  *n = nh;
  if (nh > capacity) return MODEL_E_CAPACITY;
  if (nh > 0) memcpy(polygon_xy_m, work->hull, nh * sizeof *work->hull);
  return MODEL_OK;
}

/* ---- the outcome -------------------------------------------------------------------------- */

static void support_sides(model_outcome_support_t *s) {
  const size_t n = s->vertex_count;
  for (size_t i = 0; i < n && n >= 3; ++i) {
    const double *a = s->polygon_xy_m[i], *b = s->polygon_xy_m[(i + 1) % n];
    const double ex = b[0] - a[0], ey = b[1] - a[1], len = sqrt(ex * ex + ey * ey);
    /* counter-clockwise: the interior is to the left, inward normal (-ey, ex) / len */
    s->side_m[i][0] = -ey / len;
    s->side_m[i][1] = ex / len;
    s->side_m[i][2] = s->side_m[i][0] * a[0] + s->side_m[i][1] * a[1];
  }
}

model_status_t model_outcome_support_build(const model_mesh_t *mesh_link, const model_pose_t *pose,
                                           const double base_size_m[3],
                                           const model_outcome_config_t *cfg,
                                           model_outcome_work_t *work,
                                           model_outcome_support_t *out) {
  if (out == NULL) return MODEL_E_ARG;
  memset(out, 0, offsetof(model_outcome_support_t, polygon_xy_m));
  model_outcome_config_t c = MODEL_OUTCOME_CONFIG_DEFAULT;
  if (cfg != NULL) {
    const model_status_t cs = model_outcome_config_check(cfg);
    if (cs != MODEL_OK) return cs;
    c = *cfg;
  }
  double zref;
  size_t npoints, nh;
  const model_status_t st = support_hull(mesh_link, pose, base_size_m, c.tol_m, c.tilt_rad, work,
                                         out->rot, &zref, &npoints, &nh);
  if (st != MODEL_OK) {
    memset(out->rot, 0, sizeof out->rot);
    return st;
  }
  memcpy(out->position_m, pose->position_m, sizeof out->position_m);
  out->support_z_m = zref;
  out->point_count = npoints;
  out->vertex_count = nh;
  memcpy(out->polygon_xy_m, work->hull, nh * sizeof *work->hull);
  out->width_m = model_polygon_width((const double(*)[2])out->polygon_xy_m, nh);
  out->valid = nh >= 3 && out->width_m >= c.min_width_m && out->width_m > 0.0;
  out->area_m2 = out->valid ? model_polygon_area((const double(*)[2])out->polygon_xy_m, nh) : 0.0;
  if (out->valid) support_sides(out);
  return MODEL_OK;
}

/* Distance from p to segment a-b (a == b: to the point). */
static double segment_dist(const double a[2], const double b[2], const double p[2]) {
  const double ex = b[0] - a[0], ey = b[1] - a[1], ll = ex * ex + ey * ey;
  double s = ll > 0.0 ? ((p[0] - a[0]) * ex + (p[1] - a[1]) * ey) / ll : 0.0;
  s = s < 0.0 ? 0.0 : (s > 1.0 ? 1.0 : s);
  const double dx = p[0] - (a[0] + s * ex), dy = p[1] - (a[1] + s * ey);
  return sqrt(dx * dx + dy * dy);
}

/* Distance from p to the closed polygon boundary-or-inside: 0 inside, else to the nearest side. */
static double outside_dist(const model_outcome_support_t *s, const double p[2]) {
  const size_t n = s->vertex_count;
  if (n == 1) return segment_dist(s->polygon_xy_m[0], s->polygon_xy_m[0], p);
  double best = HUGE_VAL;
  for (size_t i = 0; i < n; ++i) {
    const double d = segment_dist(s->polygon_xy_m[i], s->polygon_xy_m[(i + 1) % n], p);
    if (d < best) best = d;
  }
  return best;
}

model_status_t model_outcome_support_test(const model_outcome_support_t *s,
                                          const double com_link_m[3], int *in_place,
                                          double *margin_m) {
  if (s == NULL || com_link_m == NULL || in_place == NULL || margin_m == NULL) return MODEL_E_ARG;
  *in_place = 0;
  *margin_m = -HUGE_VAL;
  if (!isfinite(com_link_m[0]) || !isfinite(com_link_m[1]) || !isfinite(com_link_m[2]))
    return MODEL_E_NONFINITE;
  if (s->vertex_count == 0 || s->vertex_count > MODEL_OUTCOME_MAX_VERTICES) return MODEL_OK;
  double p[2];
  for (int k = 0; k < 2; ++k)
    p[k] = s->rot[k][0] * com_link_m[0] + s->rot[k][1] * com_link_m[1] +
           s->rot[k][2] * com_link_m[2] + s->position_m[k];
  if (!s->valid) {
    /* a point, a segment or a sliver: no rest; how far the CoM is from it */
    double d = outside_dist(s, p);
    if (s->vertex_count >= 3 && model_polygon_margin(s->polygon_xy_m, s->vertex_count, p) >= 0.0)
      d = 0.0;
    *margin_m = -d;
    return MODEL_OK;
  }
  /* Inside: the distance to the nearest side line. Outside a convex polygon the nearest point lies
   * on a side the CoM is beyond, so only those sides' segments are measured. */
  const size_t n = s->vertex_count;
  double inside = HUGE_VAL, outside = HUGE_VAL;
  for (size_t i = 0; i < n; ++i) {
    const double d = s->side_m[i][0] * p[0] + s->side_m[i][1] * p[1] - s->side_m[i][2];
    if (d < inside) inside = d;
    if (d < 0.0) {
      const double e = segment_dist(s->polygon_xy_m[i], s->polygon_xy_m[(i + 1) % n], p);
      if (e < outside) outside = e;
    }
  }
  *margin_m = inside >= 0.0 ? inside : -outside;
  *in_place = *margin_m > 0.0;
  return MODEL_OK;
}

model_status_t model_outcome_predict(const model_mesh_t *mesh_link, const model_pose_t *pose,
                                     const double base_size_m[3], const double com_link_m[3],
                                     const model_outcome_config_t *cfg, model_outcome_work_t *work,
                                     int *in_place, double *margin_m) {
  if (in_place == NULL || margin_m == NULL || com_link_m == NULL) return MODEL_E_ARG;
  *in_place = 0;
  *margin_m = -HUGE_VAL;
  void *mem = NULL;
  if (work == NULL) {
    const size_t size = model_outcome_work_size(mesh_link);
    if (size == 0) return MODEL_E_ARG;
    mem = malloc(size);
    if (mem == NULL) return MODEL_E_NOMEM;
    work = model_outcome_work_init(mem, size, mesh_link);
  }
  model_status_t st =
      model_outcome_support_build(mesh_link, pose, base_size_m, cfg, work, work->support);
  if (st == MODEL_OK)
    st = model_outcome_support_test(work->support, com_link_m, in_place, margin_m);
  free(mem);
  return st;
}
