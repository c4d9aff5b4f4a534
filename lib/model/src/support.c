/* regime.c - the geometry of a placement over an edge: the resting patch, its chord on the edge
 * line, the regime verdict, yaws that make the chord span the CoM; and the private geometry
 * helpers of support_geom.h. Pure geometry: no ODE. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "comlearn/math3d.h"
#include "comlearn/model_support.h"
#include "support_geom.h"

/* ---- private helpers (support_geom.h) ------------------------------------------------------- */

model_status_t model_mesh_usable(const model_mesh_t *mesh) {
  if (mesh == NULL || mesh->vertices_m == NULL || mesh->triangles == NULL ||
      mesh->vertex_count == 0 || mesh->triangle_count == 0)
    return MODEL_E_ARG;
  for (size_t v = 0; v < mesh->vertex_count; ++v) {
    for (int k = 0; k < 3; ++k) {
      if (!isfinite(mesh->vertices_m[v][k])) return MODEL_E_NONFINITE;
    }
  }
  for (size_t t = 0; t < mesh->triangle_count; ++t) {
    for (int k = 0; k < 3; ++k) {
      if (mesh->triangles[t][k] >= mesh->vertex_count) return MODEL_E_DEGENERATE;
    }
  }
  return MODEL_OK;
}

static uint32_t region_root(uint32_t *parent, uint32_t v) {
  while (parent[v] != v) {
    parent[v] = parent[parent[v]]; /* path halving */
    v = parent[v];
  }
  return v;
}

/* model_support_contact in the scratch buffers of a work area: parent[nv], area[nv] (zeroed
 * here), pts[nv + 1], hull[nv + 1]. */
static void contact_compute(const model_mesh_t *mesh, const double (*xy)[2],
                            const unsigned char *on, double (*tri_xy)[3][2],
                            model_support_contact_t *out, uint32_t *parent, double *area,
                            double (*pts)[2], double (*hull)[2]) {
  const size_t nv = mesh->vertex_count, nt = mesh->triangle_count;
  memset(out, 0, sizeof *out);
  memset(area, 0, nv * sizeof *area);
  for (size_t v = 0; v < nv; ++v) parent[v] = (uint32_t)v;
  /* Group the in-plane triangles by shared vertices (union-find), summing real areas. */
  for (size_t t = 0; t < nt; ++t) {
    const uint32_t *tri = mesh->triangles[t];
    if (!on[tri[0]] || !on[tri[1]] || !on[tri[2]]) continue;
    const double *a = xy[tri[0]], *b = xy[tri[1]], *c = xy[tri[2]];
    if (tri_xy != NULL) {
      for (int k = 0; k < 3; ++k) memcpy(tri_xy[out->triangle_count][k], xy[tri[k]], sizeof *xy);
    }
    ++out->triangle_count;
    const double ta = 0.5 * fabs((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
    out->area_m2 += ta;
    uint32_t r0 = region_root(parent, tri[0]);
    for (int k = 1; k < 3; ++k) {
      const uint32_t rk = region_root(parent, tri[k]);
      if (rk == r0) continue;
      parent[rk] = r0;
      area[r0] += area[rk];
      area[rk] = 0.0;
    }
    area[r0] += ta;
  }
  if (out->triangle_count == 0) return;
  /* Regions: roots of vertices that belong to an in-plane triangle; the largest by real area
   * (ties to the lowest vertex index, so the choice does not depend on rounding). */
  uint32_t best = UINT32_MAX;
  for (size_t t = 0; t < nt; ++t) {
    const uint32_t *tri = mesh->triangles[t];
    if (!on[tri[0]] || !on[tri[1]] || !on[tri[2]]) continue;
    const uint32_t r = region_root(parent, tri[0]);
    if (area[r] < 0.0) continue; /* counted already (marked by the sign) */
    ++out->region_count;
    if (best == UINT32_MAX || area[r] > out->region_area_m2 ||
        (area[r] == out->region_area_m2 && r < best)) {
      best = r;
      out->region_area_m2 = area[r];
    }
    area[r] = -area[r] - 1.0; /* mark, recoverable: -(a + 1) */
  }
  size_t np = 0;
  for (size_t v = 0; v < nv; ++v) {
    if (on[v] && region_root(parent, (uint32_t)v) == best) {
      pts[np][0] = xy[v][0];
      pts[np][1] = xy[v][1];
      ++np;
    }
  }
  const size_t nh = model_polygon_hull(pts, np, hull);
  out->region_width_m = model_polygon_width((const double(*)[2])hull, nh);
}

model_status_t model_support_contact(const model_mesh_t *mesh, const double (*xy)[2],
                                     const unsigned char *on, double (*tri_xy)[3][2],
                                     model_support_contact_t *out) {
  const size_t nv = mesh->vertex_count;
  memset(out, 0, sizeof *out);
  uint32_t *parent = malloc(nv * sizeof *parent);
  double *area = calloc(nv, sizeof *area);
  double(*pts)[2] = malloc((nv + 1) * sizeof *pts);
  double(*hull)[2] = malloc((nv + 1) * sizeof *hull);
  model_status_t st = MODEL_OK;
  if (parent == NULL || area == NULL || pts == NULL || hull == NULL) {
    st = MODEL_E_NOMEM;
    goto done;
  }
  contact_compute(mesh, xy, on, tri_xy, out, parent, area, pts, hull);
done:
  free(parent);
  free(area);
  free(pts);
  free(hull);
  return st;
}

/* The line p + s d (d unit) and the edge from a point at signed distance ha and position sa along
 * it to one at hb, sb, into [*lo, *hi]: the first point itself when it lies on the line, the
 * crossing when the two lie on either side (the second is counted as the next edge's first). */
static void chord_step(double ha, double sa, double hb, double sb, double *lo, double *hi) {
  if (ha == 0.0) {
    if (sa < *lo) *lo = sa;
    if (sa > *hi) *hi = sa;
  }
  if ((ha < 0.0 && hb > 0.0) || (ha > 0.0 && hb < 0.0)) {
    const double x = sa + (sb - sa) * (ha / (ha - hb));
    if (x < *lo) *lo = x;
    if (x > *hi) *hi = x;
  }
}

/* Signed distance from the line p + s d and position along it of point q. */
static void chord_coords(const double q[2], const double p[2], const double d[2], double *h,
                         double *sp) {
  const double rx = q[0] - p[0], ry = q[1] - p[1];
  *h = d[0] * ry - d[1] * rx;
  *sp = d[0] * rx + d[1] * ry;
}

/* A chord of positive length [lo, hi] into [*s0, *s1]: 1, else 0. */
static int chord_result(double lo, double hi, double *s0, double *s1) {
  if (!(hi > lo)) return 0;
  *s0 = lo;
  *s1 = hi;
  return 1;
}

double model_support_spread(const model_mesh_t *mesh, const double (*p)[3], const double n[3],
                            double top, const unsigned char *on) {
  double spread = 0.0;
  for (size_t t = 0; t < mesh->triangle_count; ++t) {
    const uint32_t *tri = mesh->triangles[t];
    if (!on[tri[0]] || !on[tri[1]] || !on[tri[2]]) continue;
    for (int k = 0; k < 3; ++k) spread = fmax(spread, top - cl_vec3_dot(n, p[tri[k]]));
  }
  return spread;
}

int model_support_flat(const model_support_contact_t *ct, double spread_m,
                       const model_regime_config_t *cfg) {
  return ct->region_area_m2 >= cfg->min_patch_area_m2 &&
         ct->region_width_m >= cfg->min_patch_width_m && spread_m <= cfg->flat_spread_m;
}

int model_support_closed(const model_support_contact_t *ct, double hull_area_m2) {
  return ct->region_count == 1 && ct->region_area_m2 > 0.0 &&
         hull_area_m2 <= ct->region_area_m2 * (1.0 + 1e-6);
}

/* Index of point q among the n hull points (exact coordinates), or -1. */
static long hull_index(const double (*hull)[2], size_t n, const double q[2]) {
  for (size_t i = 0; i < n; ++i) {
    if (hull[i][0] == q[0] && hull[i][1] == q[1]) return (long)i;
  }
  return -1;
}

int model_support_edges_close(const model_mesh_t *mesh, const double (*xy)[2],
                              const unsigned char *on, const double (*hull)[2], size_t nh) {
  enum { MAX_SIDES = 512 };
  if (nh < 3 || nh > MAX_SIDES) return 0;
  unsigned char side[MAX_SIDES] = {0}; /* side i joins hull[i] and hull[i + 1] */
  size_t covered = 0;
  for (size_t t = 0; t < mesh->triangle_count; ++t) {
    const uint32_t *tri = mesh->triangles[t];
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = tri[k], b = tri[(k + 1) % 3];
      if (!on[a] || !on[b]) continue;
      const long ia = hull_index(hull, nh, xy[a]), ib = hull_index(hull, nh, xy[b]);
      if (ia < 0 || ib < 0) continue;
      long i = -1;
      if ((size_t)ib == ((size_t)ia + 1) % nh) i = ia;
      if ((size_t)ia == ((size_t)ib + 1) % nh) i = ib;
      if (i >= 0 && !side[i]) {
        side[i] = 1;
        ++covered;
      }
    }
  }
  return covered == nh;
}

int model_polygon_chord(const double (*poly)[2], size_t n, const double p[2], const double d[2],
                        double *s0, double *s1) {
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  if (n == 0) return 0;
  double h0, sp0, ha, sa;
  chord_coords(poly[0], p, d, &h0, &sp0);
  ha = h0;
  sa = sp0;
  for (size_t k = 0; k < n; ++k) {
    double hb = h0, sb = sp0; /* the last edge closes the polygon */
    if (k + 1 < n) chord_coords(poly[k + 1], p, d, &hb, &sb);
    chord_step(ha, sa, hb, sb, &lo, &hi);
    ha = hb;
    sa = sb;
  }
  return chord_result(lo, hi, s0, s1);
}

int model_support_tris_chord(const double (*tri_xy)[3][2], size_t n, const double p[2],
                             const double d[2], double *s0, double *s1) {
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (size_t t = 0; t < n; ++t) {
    double h[3], sp[3];
    for (int k = 0; k < 3; ++k) chord_coords(tri_xy[t][k], p, d, &h[k], &sp[k]);
    for (int k = 0; k < 3; ++k) chord_step(h[k], sp[k], h[(k + 1) % 3], sp[(k + 1) % 3], &lo, &hi);
  }
  return chord_result(lo, hi, s0, s1);
}

/* ---- configuration ------------------------------------------------------------------------ */

void model_regime_config_default(model_regime_config_t *cfg) {
  if (cfg == NULL) return;
  cfg->plane_tol_m = 1e-6;
  cfg->min_patch_area_m2 = 1e-4;
  cfg->min_patch_width_m = 0.010;
  cfg->min_chord_margin_m = 0.003;
  cfg->min_com_margin_m = 0.002;
  cfg->min_face_area_m2 = 1e-5;
  cfg->flat_spread_m = 1e-7;
}

model_status_t model_regime_config_check(const model_regime_config_t *cfg) {
  if (cfg == NULL) return MODEL_E_ARG;
  const double all[7] = {cfg->plane_tol_m,        cfg->min_patch_area_m2, cfg->min_patch_width_m,
                         cfg->min_chord_margin_m, cfg->min_com_margin_m,  cfg->min_face_area_m2,
                         cfg->flat_spread_m};
  for (int k = 0; k < 7; ++k) {
    if (!isfinite(all[k])) return MODEL_E_NONFINITE;
  }
  if (!(cfg->plane_tol_m > 0.0) || !(cfg->min_patch_area_m2 > 0.0) ||
      !(cfg->min_patch_width_m > 0.0) || !(cfg->min_face_area_m2 > 0.0) ||
      !(cfg->flat_spread_m > 0.0))
    return MODEL_E_ARG;
  return MODEL_OK;
}

static model_status_t config_resolve(const model_regime_config_t *cfg, model_regime_config_t *out) {
  if (cfg == NULL) {
    model_regime_config_default(out);
    return MODEL_OK;
  }
  const model_status_t st = model_regime_config_check(cfg);
  if (st == MODEL_OK) *out = *cfg;
  return st;
}

/* ---- orientations ------------------------------------------------------------------------- */

void model_orientation_yawed(const double orientation_wxyz[4], double yaw_rad, double out[4]) {
  const double rz[4] = {cos(0.5 * yaw_rad), 0.0, 0.0, sin(0.5 * yaw_rad)};
  double r[4];
  cl_quat_mul(rz, orientation_wxyz, r);
  const double n = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + r[3] * r[3]);
  for (int k = 0; k < 4; ++k) out[k] = r[k] / n;
}

model_status_t model_orientation_resting(const double normal_link[3], double out[4]) {
  if (normal_link == NULL || out == NULL) return MODEL_E_ARG;
  for (int k = 0; k < 3; ++k) {
    if (!isfinite(normal_link[k])) return MODEL_E_NONFINITE;
  }
  const double len = sqrt(normal_link[0] * normal_link[0] + normal_link[1] * normal_link[1] +
                          normal_link[2] * normal_link[2]);
  if (!(len > 0.0) || !isfinite(len)) return MODEL_E_ARG;
  const double n[3] = {normal_link[0] / len, normal_link[1] / len, normal_link[2] / len};
  /* Shortest rotation n -> m = (0, 0, -1): q ~ (1 + n.m, n x m). */
  const double c = -n[2];
  if (c < -1.0 + 1e-12) {
    out[0] = 0.0; /* n = +z: pi about x */
    out[1] = 1.0;
    out[2] = 0.0;
    out[3] = 0.0;
    return MODEL_OK;
  }
  double q[4] = {1.0 + c, -n[1], n[0], 0.0}; /* n x (0,0,-1) = (-n_y, n_x, 0) */
  const double qn = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
  for (int k = 0; k < 4; ++k) out[k] = q[k] / qn;
  return MODEL_OK;
}

/* ---- resting patch ------------------------------------------------------------------------ */

/* ---- scratch memory ----------------------------------------------------------------------- */

/* A resting patch with its in-plane triangles (world x, y), for chords. */
typedef struct {
  model_patch_t patch;
  double (*tris)[3][2]; /* patch.face_count triangles (in the work area) */
} contact_t;

struct model_support_work {
  size_t vertex_count, triangle_count;
  double (*w)[3];               /* vertices in the world */
  double (*xy)[2];              /* their x, y */
  unsigned char *touch;         /* on the support plane */
  double (*pts)[2], (*hull)[2]; /* the outline's points and hull (nv + 1) */
  double (*tri_xy)[3][2];       /* the in-plane triangles */
  uint32_t *parent;             /* the contact's regions (contact_compute) */
  double *area;
  double (*cpts)[2], (*chull)[2];
  contact_t ct;
  /* The convex hull kept for model_support_work_hull: of hull_of (NULL: none yet); its arrays
   * here with room for every vertex and 2 per vertex triangles (a hull of V vertices has 2V - 4).
   */
  const model_mesh_t *hull_of;
  model_mesh_t kept_hull;
};

static size_t align8(size_t n) { return (n + 7u) & ~(size_t)7u; }

size_t model_support_work_size(const model_mesh_t *mesh) {
  if (mesh == NULL || mesh->vertex_count == 0 || mesh->triangle_count == 0) return 0;
  const size_t nv = mesh->vertex_count, nt = mesh->triangle_count;
  return align8(sizeof(model_support_work_t)) + align8(nv * sizeof(double[3])) +
         align8(nv * sizeof(double[2])) + align8(nv) + 4 * align8((nv + 1) * sizeof(double[2])) +
         align8(nt * sizeof(double[3][2])) + align8(nv * sizeof(uint32_t)) +
         align8(nv * sizeof(double)) + align8(nv * sizeof(double[3])) +
         align8(2 * nv * sizeof(uint32_t[3]));
}

model_support_work_t *model_support_work_init(void *mem, size_t size, const model_mesh_t *mesh) {
  const size_t need = model_support_work_size(mesh);
  if (mem == NULL || need == 0 || size < need || ((uintptr_t)mem & 7u) != 0) return NULL;
  const size_t nv = mesh->vertex_count, nt = mesh->triangle_count;
  unsigned char *p = mem;
  model_support_work_t *w = (model_support_work_t *)(void *)p;
  memset(w, 0, sizeof *w);
  p += align8(sizeof *w);
  w->vertex_count = nv;
  w->triangle_count = nt;
  w->w = (double(*)[3])(void *)p;
  p += align8(nv * sizeof(double[3]));
  w->xy = (double(*)[2])(void *)p;
  p += align8(nv * sizeof(double[2]));
  w->touch = p;
  p += align8(nv);
  double(**pairs[4])[2] = {&w->pts, &w->hull, &w->cpts, &w->chull};
  for (int k = 0; k < 4; ++k) {
    *pairs[k] = (double(*)[2])(void *)p;
    p += align8((nv + 1) * sizeof(double[2]));
  }
  w->tri_xy = (double(*)[3][2])(void *)p;
  p += align8(nt * sizeof(double[3][2]));
  w->parent = (uint32_t *)(void *)p;
  p += align8(nv * sizeof(uint32_t));
  w->area = (double *)(void *)p;
  p += align8(nv * sizeof(double));
  w->kept_hull.vertices_m = (double(*)[3])(void *)p;
  p += align8(nv * sizeof(double[3]));
  w->kept_hull.triangles = (uint32_t(*)[3])(void *)p;
  return w;
}

model_status_t model_support_work_hull(model_support_work_t *work, const model_mesh_t *mesh_link,
                                       const model_mesh_t **hull) {
  if (hull != NULL) *hull = NULL;
  if (work == NULL || mesh_link == NULL || hull == NULL ||
      mesh_link->vertex_count != work->vertex_count ||
      mesh_link->triangle_count != work->triangle_count)
    return MODEL_E_ARG;
  if (work->hull_of != mesh_link) {
    model_mesh_t h;
    const model_status_t st = model_mesh_hull(mesh_link, &h, NULL);
    if (st != MODEL_OK) return st;
    /* a hull's vertices are input vertices: at most vertex_count, and 2V - 4 triangles */
    memcpy(work->kept_hull.vertices_m, h.vertices_m, h.vertex_count * sizeof h.vertices_m[0]);
    memcpy(work->kept_hull.triangles, h.triangles, h.triangle_count * sizeof h.triangles[0]);
    work->kept_hull.vertex_count = h.vertex_count;
    work->kept_hull.triangle_count = h.triangle_count;
    work->hull_of = mesh_link;
    model_mesh_free(&h);
  }
  *hull = &work->kept_hull;
  return MODEL_OK;
}

/* A work area of its own for mesh (malloc'd: free() it), or NULL (out of memory). */
static model_support_work_t *work_new(const model_mesh_t *mesh) {
  const size_t n = model_support_work_size(mesh);
  void *mem = n > 0 ? malloc(n) : NULL;
  model_support_work_t *w = mem != NULL ? model_support_work_init(mem, n, mesh) : NULL;
  if (w == NULL) free(mem);
  return w;
}

/* ---- resting patch ------------------------------------------------------------------------ */

/* The patch of the mesh in orientation q (unit) with the link origin at pos, in the work area.
 * When tri_xy is not NULL it receives the in-plane triangles in world x, y (out->face_count of
 * them). */
/* A patch's outline: the convex polygon hull[0, nh) into out, with at most
 * MODEL_PATCH_MAX_VERTICES vertices. A longer one (a finely tessellated round foot or ring) is
 * reduced by dropping, one at a time, the vertex whose triangle with its neighbours is smallest:
 * what is left is convex and inside the hull, so every margin measured on it is at most the true
 * one. The area and width are the reduced polygon's. hull is overwritten. */
static void patch_outline(model_patch_t *out, double (*hull)[2], size_t nh) {
  while (nh > MODEL_PATCH_MAX_VERTICES) {
    size_t drop = 0;
    double least = HUGE_VAL;
    for (size_t i = 0; i < nh; ++i) {
      const double *a = hull[(i + nh - 1) % nh], *b = hull[i], *c = hull[(i + 1) % nh];
      const double area = fabs((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
      if (area < least) {
        least = area;
        drop = i;
      }
    }
    --nh;
    if (drop < nh) memmove(hull + drop, hull + drop + 1, (nh - drop) * sizeof *hull);
  }
  out->vertex_count = nh;
  memcpy(out->polygon_xy_m, hull, nh * sizeof *hull);
  out->area_m2 = model_polygon_area((const double(*)[2])hull, nh);
  out->width_m = model_polygon_width((const double(*)[2])hull, nh);
}

static model_status_t patch_compute(const model_mesh_t *mesh, const double q[4],
                                    const double pos[3], const model_regime_config_t *cfg,
                                    model_patch_t *out, double (*tri_xy)[3][2],
                                    model_support_work_t *work) {
  const size_t nv = mesh->vertex_count, nt = mesh->triangle_count;
  double(*w)[3] = work->w;
  double(*xy)[2] = work->xy;
  unsigned char *touch = work->touch;
  double(*pts)[2] = work->pts;
  double(*hull)[2] = work->hull;
  memset(touch, 0, nv);
  model_status_t st = MODEL_OK;
  memset(out, 0, sizeof *out);
  double zmin = HUGE_VAL;
  for (size_t v = 0; v < nv; ++v) {
    cl_quat_rotate(q, mesh->vertices_m[v], w[v]);
    for (int k = 0; k < 3; ++k) w[v][k] += pos[k];
    xy[v][0] = w[v][0];
    xy[v][1] = w[v][1];
    if (w[v][2] < zmin) zmin = w[v][2];
  }
  out->support_z_m = zmin;
  for (size_t v = 0; v < nv; ++v) {
    if (w[v][2] - zmin <= cfg->plane_tol_m) {
      touch[v] = 1;
      ++out->touch_count;
    }
  }
  model_support_contact_t ct;
  contact_compute(mesh, (const double(*)[2])xy, touch, tri_xy, &ct, work->parent, work->area,
                  work->cpts, work->chull);
  if (ct.region_count <= 1) {
    /* closed: the hull of every touching vertex (isolated ones too) is the region's real area,
     * or with no in-plane triangle, the in-plane edges are the hull's sides (a torus' ring) */
    size_t np = 0;
    for (size_t v = 0; v < nv; ++v) {
      if (touch[v]) memcpy(pts[np++], xy[v], sizeof *pts);
    }
    const size_t nh = model_polygon_hull(pts, np, hull);
    out->closed = ct.region_count == 1
                      ? model_support_closed(&ct, model_polygon_area((const double(*)[2])hull, nh))
                      : model_support_edges_close(mesh, (const double(*)[2])xy, touch,
                                                  (const double(*)[2])hull, nh);
    if (out->closed && ct.region_count == 0) patch_outline(out, hull, nh); /* the ring */
  }
  out->face_count = ct.triangle_count;
  out->faces_area_m2 = ct.area_m2;
  out->region_count = ct.region_count;
  out->region_area_m2 = ct.region_area_m2;
  out->region_width_m = ct.region_width_m;
  if (out->face_count > 0) {
    /* The hull of every vertex of an in-plane triangle: an outline, which may span gaps between
     * regions (two feet); chords use the triangles themselves. */
    size_t np = 0;
    for (size_t t = 0; t < nt; ++t) {
      const uint32_t *tri = mesh->triangles[t];
      if (!touch[tri[0]] || !touch[tri[1]] || !touch[tri[2]]) continue;
      for (int k = 0; k < 3; ++k) {
        if (touch[tri[k]] == 2) continue;
        touch[tri[k]] = 2;
        memcpy(pts[np++], xy[tri[k]], sizeof *pts);
      }
    }
    patch_outline(out, hull, model_polygon_hull(pts, np, hull));
  }
  static const double down[3] = {0.0, 0.0, -1.0};
  out->spread_m = model_support_spread(mesh, (const double(*)[3])w, down, -zmin, touch);
  out->flat = model_support_flat(&ct, out->spread_m, cfg);
  return st;
}

static model_status_t pose_check(const model_pose_t *pose, double q[4]) {
  if (pose == NULL) return MODEL_E_ARG;
  for (int k = 0; k < 3; ++k) {
    if (!isfinite(pose->position_m[k])) return MODEL_E_NONFINITE;
  }
  return model_quat_unit(pose->orientation_wxyz, q);
}

static model_status_t vec_check(const double v[3]) {
  if (v == NULL) return MODEL_E_ARG;
  for (int k = 0; k < 3; ++k) {
    if (!isfinite(v[k])) return MODEL_E_NONFINITE;
  }
  return MODEL_OK;
}

/* The checks every patch function makes: config (resolved into *c), mesh, pose (q: unit). */
static model_status_t patch_args(const model_mesh_t *mesh_link, const model_pose_t *pose,
                                 const model_regime_config_t *cfg, model_regime_config_t *c,
                                 double q[4]) {
  model_status_t st = config_resolve(cfg, c);
  if (st == MODEL_OK) st = model_mesh_usable(mesh_link);
  if (st == MODEL_OK) st = pose_check(pose, q);
  return st;
}

model_status_t model_patch_resting(const model_mesh_t *mesh_link, const model_pose_t *pose,
                                   const model_regime_config_t *cfg, model_patch_t *out) {
  if (out == NULL) return MODEL_E_ARG;
  model_regime_config_t c;
  double q[4];
  model_status_t st = patch_args(mesh_link, pose, cfg, &c, q);
  if (st != MODEL_OK) return st;
  model_support_work_t *work = work_new(mesh_link);
  if (work == NULL) return MODEL_E_NOMEM;
  st = patch_compute(mesh_link, q, pose->position_m, &c, out, NULL, work);
  free(work);
  return st;
}

/* ---- chords and regimes ------------------------------------------------------------------- */

/* Outward normal (x, y) of an edge and the unit direction of the "along" coordinate. */
static int edge_axes(model_edge_t edge, double normal[2], double along[2]) {
  switch (edge) {
    case MODEL_EDGE_PX:
      normal[0] = 1.0;
      normal[1] = 0.0;
      break;
    case MODEL_EDGE_NX:
      normal[0] = -1.0;
      normal[1] = 0.0;
      break;
    case MODEL_EDGE_PY:
      normal[0] = 0.0;
      normal[1] = 1.0;
      break;
    case MODEL_EDGE_NY:
      normal[0] = 0.0;
      normal[1] = -1.0;
      break;
    default: return 0;
  }
  along[0] = normal[0] != 0.0 ? 0.0 : 1.0;
  along[1] = normal[0] != 0.0 ? 1.0 : 0.0;
  return 1;
}

/* The patch of mesh_link resting in `pose` with its triangles, in `work` (one of mesh_link's),
 * or when work is NULL in one allocated here (*own: free() it, also on error); *out NULL on
 * error. */
static model_status_t contact_build(const model_mesh_t *mesh_link, const model_pose_t *pose,
                                    const model_regime_config_t *cfg, model_support_work_t *work,
                                    model_support_work_t **own, contact_t **out) {
  *out = NULL;
  *own = NULL;
  model_regime_config_t c;
  double q[4];
  model_status_t st = patch_args(mesh_link, pose, cfg, &c, q);
  if (st != MODEL_OK) return st;
  if (work == NULL) {
    work = *own = work_new(mesh_link);
    if (work == NULL) return MODEL_E_NOMEM;
  } else if (work->vertex_count != mesh_link->vertex_count ||
             work->triangle_count != mesh_link->triangle_count) {
    return MODEL_E_ARG;
  }
  contact_t *ct = &work->ct;
  ct->tris = work->tri_xy;
  st = patch_compute(mesh_link, q, pose->position_m, &c, &ct->patch, ct->tris, work);
  if (st != MODEL_OK) return st;
  *out = ct;
  return MODEL_OK;
}

/* Chord margin of the line through p along `dir` (unit) across the real contact of a flat patch:
 * the extent of the in-plane triangles on that line, so two feet or a ring give the interval
 * between their outermost crossings, and a line that crosses one foot only gives that foot's. */
static double chord_margin(const contact_t *ct, const double p[2], const double dir[2], double *s0,
                           double *s1) {
  double lo = 0.0, hi = 0.0;
  if (!ct->patch.flat || !model_support_tris_chord((const double(*)[3][2])ct->tris,
                                                   ct->patch.face_count, p, dir, &lo, &hi))
    return -HUGE_VAL;
  if (s0 != NULL) *s0 = lo;
  if (s1 != NULL) *s1 = hi;
  return fmin(-lo, hi);
}

model_status_t model_regime_classify(const model_mesh_t *mesh_link, const model_pose_t *pose,
                                     const double base_size_m[3], model_edge_t edge,
                                     const double com_estimate_link_m[3],
                                     const model_regime_config_t *cfg, model_regime_t *out) {
  return model_regime_classify_in(mesh_link, pose, base_size_m, edge, com_estimate_link_m, cfg,
                                  NULL, out);
}

model_status_t model_regime_classify_in(const model_mesh_t *mesh_link, const model_pose_t *pose,
                                        const double base_size_m[3], model_edge_t edge,
                                        const double com_estimate_link_m[3],
                                        const model_regime_config_t *cfg,
                                        model_support_work_t *work, model_regime_t *out) {
  if (out == NULL || base_size_m == NULL) return MODEL_E_ARG;
  model_status_t st = vec_check(com_estimate_link_m);
  if (st == MODEL_OK) st = vec_check(base_size_m);
  if (st != MODEL_OK) return st;
  double normal[2], along[2];
  if (!edge_axes(edge, normal, along)) return MODEL_E_ARG;
  for (int k = 0; k < 3; ++k) {
    if (!(base_size_m[k] > 0.0)) return MODEL_E_ARG;
  }
  memset(out, 0, sizeof *out);
  contact_t *ct = NULL;
  model_support_work_t *own = NULL;
  st = contact_build(mesh_link, pose, cfg, work, &own, &ct);
  if (st != MODEL_OK) {
    free(own);
    return st;
  }
  out->patch = ct->patch;
  model_regime_config_t c;
  model_regime_config_default(&c);
  if (cfg != NULL) c = *cfg; /* checked by contact_build */
  double q[4], cw[3];
  model_quat_unit(pose->orientation_wxyz, q);
  cl_quat_rotate(q, com_estimate_link_m, cw);
  const double p[2] = {cw[0] + pose->position_m[0], cw[1] + pose->position_m[1]};
  const double half = 0.5 * (normal[0] != 0.0 ? base_size_m[0] : base_size_m[1]);
  out->com_along_m = p[0] * along[0] + p[1] * along[1];
  out->com_beyond_m = p[0] * normal[0] + p[1] * normal[1] - half;
  /* The edge line itself: the CoM estimate moved onto it along the normal. */
  const double on[2] = {p[0] - out->com_beyond_m * normal[0], p[1] - out->com_beyond_m * normal[1]};
  double s0 = 0.0, s1 = 0.0;
  out->chord_margin_m = -HUGE_VAL;
  const int ring = ct->patch.closed && ct->patch.face_count == 0; /* chord across the outline */
  if (ring ? model_polygon_chord((const double(*)[2])ct->patch.polygon_xy_m, ct->patch.vertex_count,
                                 on, along, &s0, &s1)
           : model_support_tris_chord((const double(*)[3][2])ct->tris, ct->patch.face_count, on,
                                      along, &s0, &s1)) {
    out->chord_valid = 1;
    out->chord_m[0] = out->com_along_m + s0;
    out->chord_m[1] = out->com_along_m + s1;
    out->chord_margin_m = fmin(-s0, s1);
  }
  free(own);
  if (!out->patch.flat && out->patch.closed && out->chord_valid) {
    out->kind = MODEL_REGIME_CLOSED_PATCH;
  } else if (!out->patch.flat || !out->chord_valid) {
    /* No flat patch on the edge line. A patch that exists but is too small still meets the edge
     * along a short segment: that rolls, it does not drop. */
    out->kind = out->chord_valid ? MODEL_REGIME_EDGE_ROLL : MODEL_REGIME_POINT_SUPPORT;
  } else if (out->chord_margin_m >= c.min_chord_margin_m) {
    out->kind = MODEL_REGIME_FLAT_PATCH;
  } else {
    out->kind = MODEL_REGIME_EDGE_ROLL;
  }
  out->flat_patch_regime =
      out->kind == MODEL_REGIME_FLAT_PATCH || out->kind == MODEL_REGIME_CLOSED_PATCH;
  return MODEL_OK;
}

/* ---- yaws --------------------------------------------------------------------------------- */

/* Margin at yaw psi: rotating the object by Rz(psi) is rotating the edge direction by -psi in
 * the frame of the unrotated patch. */
static double yaw_margin(const contact_t *ct, const double p[2], const double along[2],
                         double psi) {
  const double c = cos(psi), s = sin(psi);
  const double d[2] = {c * along[0] + s * along[1], -s * along[0] + c * along[1]};
  return chord_margin(ct, p, d, NULL, NULL);
}

static model_status_t yaw_setup(const model_mesh_t *mesh_link, const double orientation_wxyz[4],
                                const double com_estimate_link_m[3], model_edge_t edge,
                                const double *out1, const double *out2,
                                const model_regime_config_t *cfg, model_support_work_t *work,
                                model_support_work_t **own, contact_t **ct, double p[2],
                                double along[2]) {
  *ct = NULL;
  *own = NULL;
  if (out1 == NULL || out2 == NULL || orientation_wxyz == NULL) return MODEL_E_ARG;
  double normal[2];
  if (!edge_axes(edge, normal, along)) return MODEL_E_ARG;
  model_status_t st = vec_check(com_estimate_link_m);
  if (st != MODEL_OK) return st;
  model_pose_t pose = {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0, 0.0}};
  memcpy(pose.orientation_wxyz, orientation_wxyz, sizeof pose.orientation_wxyz);
  st = contact_build(mesh_link, &pose, cfg, work, own, ct);
  if (st != MODEL_OK) return st;
  double q[4], cw[3];
  model_quat_unit(orientation_wxyz, q);
  cl_quat_rotate(q, com_estimate_link_m, cw);
  p[0] = cw[0];
  p[1] = cw[1];
  return MODEL_OK;
}

model_status_t model_yaw_margins(const model_mesh_t *mesh_link, const double orientation_wxyz[4],
                                 model_edge_t edge, const model_regime_config_t *cfg, size_t n,
                                 const double *yaw_rad, const double (*com_estimate_link_m)[3],
                                 double *margin_m) {
  return model_yaw_margins_in(mesh_link, orientation_wxyz, edge, cfg, n, yaw_rad,
                              com_estimate_link_m, NULL, margin_m);
}

model_status_t model_yaw_margins_in(const model_mesh_t *mesh_link, const double orientation_wxyz[4],
                                    model_edge_t edge, const model_regime_config_t *cfg, size_t n,
                                    const double *yaw_rad, const double (*com_estimate_link_m)[3],
                                    model_support_work_t *work, double *margin_m) {
  if (n == 0) return MODEL_OK;
  if (yaw_rad == NULL || com_estimate_link_m == NULL) return MODEL_E_ARG;
  for (size_t i = 0; i < n; ++i) {
    if (!isfinite(yaw_rad[i])) return MODEL_E_NONFINITE;
    const model_status_t st = vec_check(com_estimate_link_m[i]);
    if (st != MODEL_OK) return st;
  }
  contact_t *ct = NULL;
  model_support_work_t *own = NULL;
  double p[2], along[2];
  const double dummy = 0.0;
  /* the contact depends on the orientation only: built once for every (yaw, point) */
  model_status_t st = yaw_setup(mesh_link, orientation_wxyz, com_estimate_link_m[0], edge, margin_m,
                                &dummy, cfg, work, &own, &ct, p, along);
  if (st == MODEL_OK) {
    double q[4];
    model_quat_unit(orientation_wxyz, q);
    for (size_t i = 0; i < n; ++i) {
      double cw[3];
      cl_quat_rotate(q, com_estimate_link_m[i], cw);
      const double pi[2] = {cw[0], cw[1]};
      margin_m[i] = yaw_margin(ct, pi, along, yaw_rad[i]);
    }
  }
  free(own);
  return st;
}

model_status_t model_yaw_margin(const model_mesh_t *mesh_link, const double orientation_wxyz[4],
                                const double com_estimate_link_m[3], model_edge_t edge,
                                double yaw_rad, const model_regime_config_t *cfg,
                                double *margin_m) {
  if (com_estimate_link_m == NULL) return MODEL_E_ARG;
  return model_yaw_margins(mesh_link, orientation_wxyz, edge, cfg, 1, &yaw_rad,
                           (const double(*)[3])com_estimate_link_m, margin_m);
}

model_status_t model_yaw_best(const model_mesh_t *mesh_link, const double orientation_wxyz[4],
                              const double com_estimate_link_m[3], model_edge_t edge,
                              const model_regime_config_t *cfg, double *yaw_rad, double *margin_m) {
  contact_t *ct = NULL;
  model_support_work_t *own = NULL;
  double p[2], along[2];
  model_status_t st = yaw_setup(mesh_link, orientation_wxyz, com_estimate_link_m, edge, yaw_rad,
                                margin_m, cfg, NULL, &own, &ct, p, along);
  if (st != MODEL_OK) {
    free(own);
    return st;
  }
  enum { STEPS = 360, GOLDEN_ITERS = 40 };
  const double pi = CL_PI, step = pi / STEPS;
  int best = -1;
  double best_m = -HUGE_VAL;
  for (int i = 0; i < STEPS; ++i) {
    const double m = yaw_margin(ct, p, along, step * i);
    if (m > best_m) {
      best_m = m;
      best = i;
    }
  }
  double best_psi = 0.0;
  if (best >= 0) {
    /* The margin is the minimum of two smooth ray lengths: unimodal near its maximum. */
    const double g = 0.5 * (sqrt(5.0) - 1.0);
    double a = step * (best - 1), b = step * (best + 1);
    double x1 = b - g * (b - a), x2 = a + g * (b - a);
    double f1 = yaw_margin(ct, p, along, x1), f2 = yaw_margin(ct, p, along, x2);
    for (int it = 0; it < GOLDEN_ITERS; ++it) {
      if (f1 < f2) {
        a = x1;
        x1 = x2;
        f1 = f2;
        x2 = a + g * (b - a);
        f2 = yaw_margin(ct, p, along, x2);
      } else {
        b = x2;
        x2 = x1;
        f2 = f1;
        x1 = b - g * (b - a);
        f1 = yaw_margin(ct, p, along, x1);
      }
    }
    best_psi = step * best;
    if (f1 > best_m) {
      best_m = f1;
      best_psi = x1;
    }
    best_psi = fmod(best_psi + pi, pi);
  }
  *yaw_rad = best_psi;
  *margin_m = best_m;
  free(own);
  return MODEL_OK;
}
