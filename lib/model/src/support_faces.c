/* support_faces.c - the faces of an object's convex hull: the planes it can rest on, each
 * analysed for a CoM guess (stable-pose candidates). Pure geometry. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "comlearn/math3d.h"
#include "comlearn/model_support.h"
#include "support_geom.h"

typedef struct {
  double n[3];
  double area;
  size_t index;
} facet_t;

/* Largest first; ties by normal, then by index: a total order, so the faces do not depend on
 * qsort. */
static int cmp_facet(const void *pa, const void *pb) {
  const facet_t *a = pa, *b = pb;
  if (a->area != b->area) return a->area > b->area ? -1 : 1;
  for (int k = 0; k < 3; ++k)
    if (a->n[k] != b->n[k]) return a->n[k] < b->n[k] ? -1 : 1;
  return a->index < b->index ? -1 : (a->index > b->index);
}

/* ---- which facets can join a seed: a grid over their normals --------------------------------- */

/* A facet's cell: floor(n / side) per component. Two normals whose dot product reaches merge_cos
 * are at most side apart (see faces_grid), so in the same or adjacent cells. */
typedef struct {
  int64_t cell[3];
  size_t pos; /* in the sorted facets */
} cell_t;

static int cmp_cell(const void *pa, const void *pb) {
  const cell_t *a = pa, *b = pb;
  for (int k = 0; k < 3; ++k)
    if (a->cell[k] != b->cell[k]) return a->cell[k] < b->cell[k] ? -1 : 1;
  return a->pos < b->pos ? -1 : (a->pos > b->pos);
}

static int cmp_size(const void *pa, const void *pb) {
  const size_t a = *(const size_t *)pa, b = *(const size_t *)pb;
  return a < b ? -1 : (a > b);
}

typedef struct {
  cell_t *cells; /* every facet, by cell then position; NULL: no grid, every facet is a candidate */
  size_t *cand;
  double side;
} grid_t;

/* The grid for normals within acos(merge_cos) of each other: |n - m|^2 = 2 - 2 n.m for unit
 * vectors, plus a margin for their rounding. No grid when a normal is not finite. */
static model_status_t faces_grid(const facet_t *fac, size_t nf, double merge_cos, grid_t *g) {
  g->side = 1.001 * sqrt(fmax(0.0, 2.0 - 2.0 * merge_cos) + 1e-12);
  g->cand = malloc((nf > 0 ? nf : 1) * sizeof *g->cand);
  g->cells = malloc((nf > 0 ? nf : 1) * sizeof *g->cells);
  if (g->cand == NULL || g->cells == NULL) return MODEL_E_NOMEM;
  for (size_t t = 0; t < nf; ++t) {
    for (int k = 0; k < 3; ++k) {
      if (!(fabs(fac[t].n[k]) <= 2.0)) {
        free(g->cells);
        g->cells = NULL;
        return MODEL_OK;
      }
      g->cells[t].cell[k] = (int64_t)floor(fac[t].n[k] / g->side);
    }
    g->cells[t].pos = t;
  }
  qsort(g->cells, nf, sizeof *g->cells, cmp_cell);
  return MODEL_OK;
}

/* The positions >= s of the facets that may join seed s, ascending, into g->cand: the scan over
 * every later facet, minus those whose normal cannot reach merge_cos. */
static size_t faces_candidates(const grid_t *g, const facet_t *fac, size_t nf, size_t s) {
  size_t n = 0;
  if (g->cells == NULL) {
    for (size_t t = s; t < nf; ++t) g->cand[n++] = t;
    return n;
  }
  cell_t key;
  for (int k = 0; k < 3; ++k) key.cell[k] = (int64_t)floor(fac[s].n[k] / g->side);
  for (int d = 0; d < 27; ++d) {
    cell_t q = {{key.cell[0] + d % 3 - 1, key.cell[1] + d / 3 % 3 - 1, key.cell[2] + d / 9 - 1}, s};
    size_t lo = 0, hi = nf; /* the first entry >= q */
    while (lo < hi) {
      const size_t mid = lo + (hi - lo) / 2;
      if (cmp_cell(&g->cells[mid], &q) < 0)
        lo = mid + 1;
      else
        hi = mid;
    }
    for (size_t i = lo; i < nf && memcmp(g->cells[i].cell, q.cell, sizeof q.cell) == 0; ++i)
      g->cand[n++] = g->cells[i].pos;
  }
  qsort(g->cand, n, sizeof *g->cand, cmp_size);
  return n;
}

model_status_t model_hull_faces(const model_mesh_t *hull, double merge_cos, double plane_tol_m,
                                model_hull_face_t *faces, int *facet_face, size_t *count) {
  if (hull == NULL || faces == NULL || facet_face == NULL || count == NULL ||
      hull->vertices_m == NULL || hull->triangles == NULL || !isfinite(merge_cos) ||
      !(plane_tol_m >= 0.0) || !isfinite(plane_tol_m))
    return MODEL_E_ARG;
  *count = 0;
  const size_t nf = hull->triangle_count;
  facet_t *fac = malloc((nf > 0 ? nf : 1) * sizeof *fac);
  if (fac == NULL) return MODEL_E_NOMEM;
  for (size_t t = 0; t < nf; ++t) {
    const double *a = hull->vertices_m[hull->triangles[t][0]];
    const double *b = hull->vertices_m[hull->triangles[t][1]];
    const double *d = hull->vertices_m[hull->triangles[t][2]];
    fac[t].area = 0.5 * cl_tri_normal(a, b, d, fac[t].n);
    fac[t].index = t;
    facet_face[t] = -1;
  }
  qsort(fac, nf, sizeof *fac, cmp_facet);
  grid_t g = {NULL, NULL, 0.0};
  const model_status_t st = faces_grid(fac, nf, merge_cos, &g);
  size_t found = 0;
  for (size_t s = 0; s < nf && st == MODEL_OK; ++s) {
    if (facet_face[fac[s].index] >= 0 || !(fac[s].area > 0.0)) continue;
    /* Merge every facet coplanar with the seed (on a convex hull they are one convex face), in
     * the sorted order: the sums come out the same whatever the grid leaves out. */
    const double *n0 = fac[s].n;
    const double h0 = cl_vec3_dot(n0, hull->vertices_m[hull->triangles[fac[s].index][0]]);
    double nsum[3] = {0.0, 0.0, 0.0}, area = 0.0;
    const size_t nc = faces_candidates(&g, fac, nf, s);
    for (size_t c = 0; c < nc; ++c) {
      const size_t t = g.cand[c];
      if (facet_face[fac[t].index] >= 0 || cl_vec3_dot(fac[t].n, n0) < merge_cos) continue;
      int in = 1;
      for (int k = 0; k < 3; ++k) {
        if (fabs(cl_vec3_dot(n0, hull->vertices_m[hull->triangles[fac[t].index][k]]) - h0) >
            plane_tol_m)
          in = 0;
      }
      if (!in) continue;
      facet_face[fac[t].index] = (int)found;
      area += fac[t].area;
      for (int k = 0; k < 3; ++k) nsum[k] += fac[t].area * fac[t].n[k];
    }
    const double nl = sqrt(cl_vec3_dot(nsum, nsum));
    model_hull_face_t *f = &faces[found++];
    for (int k = 0; k < 3; ++k) f->normal[k] = nsum[k] / nl;
    f->area_m2 = area;
    f->seed = fac[s].index;
  }
  free(g.cells);
  free(g.cand);
  free(fac);
  *count = found;
  return st;
}

static int cmp_face(const void *pa, const void *pb) {
  const model_face_t *a = pa, *b = pb;
  if (a->area_m2 != b->area_m2) return a->area_m2 > b->area_m2 ? -1 : 1;
  for (int k = 0; k < 3; ++k) {
    if (a->normal_link[k] != b->normal_link[k])
      return a->normal_link[k] < b->normal_link[k] ? -1 : 1;
  }
  return 0;
}

/* Analyse the plane with outward unit normal n that supports the mesh. xy: scratch for nv plane
 * coordinates; pts / hull: scratch for nv + 1 points; on: nv bytes, zero on entry and exit. */
static model_status_t face_analyse(const model_mesh_t *mesh, const double n[3], const double com[3],
                                   const model_regime_config_t *cfg, double (*xy)[2],
                                   double (*pts)[2], double (*hull)[2], unsigned char *on,
                                   model_face_t *f) {
  const size_t nv = mesh->vertex_count;
  memset(f, 0, sizeof *f);
  memcpy(f->normal_link, n, sizeof f->normal_link);
  double h = -HUGE_VAL;
  for (size_t v = 0; v < nv; ++v) {
    const double s = cl_vec3_dot(n, mesh->vertices_m[v]);
    if (s > h) h = s;
  }
  f->offset_m = h;
  double u[3], w[3];
  model_plane_basis(n, u, w);
  size_t np = 0;
  for (size_t v = 0; v < nv; ++v) {
    if (h - cl_vec3_dot(n, mesh->vertices_m[v]) > cfg->plane_tol_m) continue;
    on[v] = 1;
    xy[v][0] = pts[np][0] = cl_vec3_dot(u, mesh->vertices_m[v]);
    xy[v][1] = pts[np][1] = cl_vec3_dot(w, mesh->vertices_m[v]);
    ++np;
  }
  size_t nh = model_polygon_hull(pts, np, hull);
  f->area_m2 = model_polygon_area((const double(*)[2])hull, nh);
  f->width_m = model_polygon_width((const double(*)[2])hull, nh);
  const double c2[2] = {cl_vec3_dot(u, com), cl_vec3_dot(w, com)};
  f->com_margin_m = model_polygon_margin((const double(*)[2])hull, nh, c2);
  f->candidate = f->com_margin_m >= cfg->min_com_margin_m;
  /* The real contact: mesh triangles in the plane, grouped into regions. */
  model_support_contact_t ct;
  const model_status_t st = model_support_contact(mesh, (const double(*)[2])xy, on, NULL, &ct);
  const int ring =
      st == MODEL_OK && ct.region_count == 0 &&
      model_support_edges_close(mesh, (const double(*)[2])xy, on, (const double(*)[2])hull, nh);
  f->patch_spread_m = model_support_spread(mesh, (const double(*)[3])mesh->vertices_m, n, h, on);
  for (size_t v = 0; v < nv; ++v) on[v] = 0;
  if (st != MODEL_OK) return st;
  f->face_count = ct.triangle_count;
  f->region_count = ct.region_count;
  f->patch_area_m2 = ct.region_area_m2;
  f->patch_width_m = ct.region_width_m;
  f->flat = model_support_flat(&ct, f->patch_spread_m, cfg);
  f->closed = ct.region_count == 1 ? model_support_closed(&ct, f->area_m2) : ring;
  return model_orientation_resting(n, f->orientation_wxyz);
}

/* Margin first (largest), then as cmp_face. */
static int cmp_face_margin(const void *pa, const void *pb) {
  const model_face_t *a = pa, *b = pb;
  if (a->com_margin_m != b->com_margin_m) return a->com_margin_m > b->com_margin_m ? -1 : 1;
  return cmp_face(pa, pb);
}

/* The arguments model_faces_find and its variants check, in its order, and the configuration. */
static model_status_t faces_args(const model_mesh_t *mesh_link, const double com_guess_link_m[3],
                                 const model_regime_config_t *cfg, const model_face_t *faces,
                                 size_t capacity, size_t *count, model_regime_config_t *c) {
  if (count == NULL || com_guess_link_m == NULL || (faces == NULL && capacity > 0))
    return MODEL_E_ARG;
  *count = 0;
  if (cfg == NULL) {
    model_regime_config_default(c);
  } else {
    const model_status_t cs = model_regime_config_check(cfg);
    if (cs != MODEL_OK) return cs;
    *c = *cfg;
  }
  const model_status_t st = model_mesh_usable(mesh_link);
  if (st != MODEL_OK) return st;
  for (int k = 0; k < 3; ++k) {
    if (!isfinite(com_guess_link_m[k])) return MODEL_E_NONFINITE;
  }
  return MODEL_OK;
}

/* The faces of the hull of mesh_link (arguments checked): stable_only 0, model_faces_find's (at
 * least min_face_area_m2, largest first); 1, model_faces_stable's (any area, holding the guess,
 * largest margin first). */
/* holds[f] = 1 for the merged faces f (of hf) one of whose facets holds g's projection along the
 * face's normal, with a 0.1 mm slack: the only ones that can hold it (face_analyse then decides
 * exactly). A cheap pass, O(facets), so that model_faces_stable analyses only those. */
static void faces_holding(const model_mesh_t *hull, const model_hull_face_t *hf,
                          const int *facet_face, const double g[3], unsigned char *holds) {
  const double slack = 1e-4;
  for (size_t t = 0; t < hull->triangle_count; ++t) {
    const int f = facet_face[t];
    if (f < 0 || holds[f]) continue;
    double u[3], w[3], p[3][2];
    model_plane_basis(hf[f].normal, u, w);
    for (int k = 0; k < 3; ++k) {
      const double *v = hull->vertices_m[hull->triangles[t][k]];
      p[k][0] = cl_vec3_dot(u, v) - cl_vec3_dot(u, g);
      p[k][1] = cl_vec3_dot(w, v) - cl_vec3_dot(w, g);
    }
    const double area2 =
        (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
    int inside = area2 != 0.0;
    for (int k = 0; k < 3 && inside; ++k) { /* g (the origin) on the inner side of edge k */
      const double *a = p[k], *b = p[(k + 1) % 3];
      const double len = hypot(b[0] - a[0], b[1] - a[1]);
      const double side = (a[0] * b[1] - a[1] * b[0]) * (area2 > 0.0 ? 1.0 : -1.0);
      inside = len == 0.0 || side >= -slack * len;
    }
    holds[f] = (unsigned char)inside;
  }
}

static model_status_t faces_of_hull(const model_mesh_t *mesh_link, const model_mesh_t *hull,
                                    const double com_guess_link_m[3],
                                    const model_regime_config_t *c, int stable_only,
                                    model_face_t *faces, size_t capacity, size_t *count) {
  const size_t nf = hull->triangle_count, nv = mesh_link->vertex_count;
  const double min_area = stable_only ? 0.0 : c->min_face_area_m2;
  model_hull_face_t *hf = malloc((nf > 0 ? nf : 1) * sizeof *hf);
  int *facet_face = malloc((nf > 0 ? nf : 1) * sizeof *facet_face);
  unsigned char *used = calloc(nv, 1);
  double(*xy)[2] = malloc(nv * sizeof *xy);
  double(*pts)[2] = malloc((nv + 1) * sizeof *pts);
  double(*poly)[2] = malloc((nv + 1) * sizeof *poly);
  model_face_t *tmp = malloc((nf > 0 ? nf : 1) * sizeof *tmp);
  unsigned char *holds = stable_only ? calloc(nf > 0 ? nf : 1, 1) : NULL;
  size_t nhf = 0, found = 0;
  model_status_t st = MODEL_OK;
  if (hf == NULL || facet_face == NULL || used == NULL || xy == NULL || pts == NULL ||
      poly == NULL || tmp == NULL || (stable_only && holds == NULL)) {
    st = MODEL_E_NOMEM;
    goto done;
  }
  st = model_hull_faces(hull, cos(1e-3), c->plane_tol_m, hf, facet_face, &nhf);
  if (st == MODEL_OK && stable_only) faces_holding(hull, hf, facet_face, com_guess_link_m, holds);
  for (size_t i = 0; st == MODEL_OK && i < nhf; ++i) {
    if (hf[i].area_m2 < min_area || !(hf[i].area_m2 > 0.0) || (stable_only && !holds[i])) continue;
    st = face_analyse(mesh_link, hf[i].normal, com_guess_link_m, c, xy, pts, poly, used,
                      &tmp[found]);
    if (st == MODEL_OK && tmp[found].area_m2 >= min_area &&
        (!stable_only || tmp[found].com_margin_m >= 0.0))
      ++found;
  }
  if (st != MODEL_OK) goto done;
  qsort(tmp, found, sizeof *tmp, stable_only ? cmp_face_margin : cmp_face);
  if (capacity > 0 && found > 0)
    memcpy(faces, tmp, (found < capacity ? found : capacity) * sizeof *tmp);
  *count = found;
done:
  free(holds);
  free(hf);
  free(facet_face);
  free(used);
  free(xy);
  free(pts);
  free(poly);
  free(tmp);
  return st;
}

/* A hull that failed: out of memory, or MODEL_E_HULL whatever model_mesh_hull said. */
static model_status_t hull_failed(model_status_t st) {
  return st == MODEL_E_NOMEM ? MODEL_E_NOMEM : MODEL_E_HULL;
}

/* The faces (model_faces_find's, stable_only 0, or model_faces_stable's, 1) on a hull of its own
 * (work NULL) or on the one kept in work. */
static model_status_t faces_list(const model_mesh_t *mesh_link, const double com_guess_link_m[3],
                                 const model_regime_config_t *cfg, model_support_work_t *work,
                                 int own_hull, int stable_only, model_face_t *faces,
                                 size_t capacity, size_t *count) {
  model_regime_config_t c;
  model_status_t st = faces_args(mesh_link, com_guess_link_m, cfg, faces, capacity, count, &c);
  if (st != MODEL_OK) return st;
  if (!own_hull) {
    const model_mesh_t *hull = NULL;
    st = model_support_work_hull(work, mesh_link, &hull);
    if (st == MODEL_E_ARG) return st;
    if (st != MODEL_OK) return hull_failed(st);
    return faces_of_hull(mesh_link, hull, com_guess_link_m, &c, stable_only, faces, capacity,
                         count);
  }
  model_mesh_t hull = {0};
  st = model_mesh_hull(mesh_link, &hull, NULL);
  if (st != MODEL_OK) return hull_failed(st);
  st = faces_of_hull(mesh_link, &hull, com_guess_link_m, &c, stable_only, faces, capacity, count);
  model_mesh_free(&hull);
  return st;
}

model_status_t model_faces_find(const model_mesh_t *mesh_link, const double com_guess_link_m[3],
                                const model_regime_config_t *cfg, model_face_t *faces,
                                size_t capacity, size_t *count) {
  return faces_list(mesh_link, com_guess_link_m, cfg, NULL, 1, 0, faces, capacity, count);
}

model_status_t model_faces_find_hull(const model_mesh_t *mesh_link, const model_mesh_t *hull,
                                     const double com_guess_link_m[3],
                                     const model_regime_config_t *cfg, model_face_t *faces,
                                     size_t capacity, size_t *count) {
  model_regime_config_t c;
  model_status_t st = faces_args(mesh_link, com_guess_link_m, cfg, faces, capacity, count, &c);
  if (st != MODEL_OK) return st;
  st = model_mesh_usable(hull);
  if (st != MODEL_OK) return st;
  return faces_of_hull(mesh_link, hull, com_guess_link_m, &c, 0, faces, capacity, count);
}

model_status_t model_faces_find_in(const model_mesh_t *mesh_link, const double com_guess_link_m[3],
                                   const model_regime_config_t *cfg, model_support_work_t *work,
                                   model_face_t *faces, size_t capacity, size_t *count) {
  return faces_list(mesh_link, com_guess_link_m, cfg, work, 0, 0, faces, capacity, count);
}

model_status_t model_faces_stable(const model_mesh_t *mesh_link, const double com_guess_link_m[3],
                                  const model_regime_config_t *cfg, model_face_t *faces,
                                  size_t capacity, size_t *count) {
  return faces_list(mesh_link, com_guess_link_m, cfg, NULL, 1, 1, faces, capacity, count);
}

model_status_t model_faces_stable_in(const model_mesh_t *mesh_link,
                                     const double com_guess_link_m[3],
                                     const model_regime_config_t *cfg, model_support_work_t *work,
                                     model_face_t *faces, size_t capacity, size_t *count) {
  return faces_list(mesh_link, com_guess_link_m, cfg, work, 0, 1, faces, capacity, count);
}

/* The area-weighted normal of the mesh triangles within tol of the support plane n . x = h
 * (outward: the mesh is closed and outward, so an in-plane triangle's normal points along n);
 * n itself when there are none. */
static void plane_normal_refine(const model_mesh_t *mesh, const double n[3], double h, double tol,
                                double out[3]) {
  double acc[3] = {0.0, 0.0, 0.0};
  for (size_t t = 0; t < mesh->triangle_count; ++t) {
    const uint32_t *tri = mesh->triangles[t];
    int in = 1;
    for (int k = 0; k < 3 && in; ++k) in = h - cl_vec3_dot(n, mesh->vertices_m[tri[k]]) <= tol;
    if (!in) continue;
    double nt[3];
    const double a2 = cl_tri_normal(mesh->vertices_m[tri[0]], mesh->vertices_m[tri[1]],
                                    mesh->vertices_m[tri[2]], nt);
    if (cl_vec3_dot(nt, n) > 0.0) {
      for (int k = 0; k < 3; ++k) acc[k] += a2 * nt[k];
    }
  }
  const double len = cl_vec3_norm(acc);
  for (int k = 0; k < 3; ++k) out[k] = len > 0.0 ? acc[k] / len : n[k];
}

model_status_t model_face_at(const model_mesh_t *mesh_link, const double normal_link[3],
                             const double com_guess_link_m[3], const model_regime_config_t *cfg,
                             model_face_t *out) {
  if (out == NULL || normal_link == NULL) return MODEL_E_ARG;
  model_regime_config_t c;
  size_t unused = 0;
  model_status_t st = faces_args(mesh_link, com_guess_link_m, cfg, NULL, 0, &unused, &c);
  if (st != MODEL_OK) return st;
  double n[3];
  const double len = cl_vec3_norm(normal_link);
  if (!isfinite(len)) return MODEL_E_NONFINITE;
  if (!(len > 0.0)) return MODEL_E_ARG;
  for (int k = 0; k < 3; ++k) n[k] = normal_link[k] / len;
  const size_t nv = mesh_link->vertex_count;
  double h = -HUGE_VAL;
  for (size_t v = 0; v < nv; ++v) h = fmax(h, cl_vec3_dot(n, mesh_link->vertices_m[v]));
  plane_normal_refine(mesh_link, n, h, c.plane_tol_m, n);
  unsigned char *used = calloc(nv, 1);
  double(*xy)[2] = malloc(nv * sizeof *xy);
  double(*pts)[2] = malloc((nv + 1) * sizeof *pts);
  double(*poly)[2] = malloc((nv + 1) * sizeof *poly);
  st = used && xy && pts && poly
           ? face_analyse(mesh_link, n, com_guess_link_m, &c, xy, pts, poly, used, out)
           : MODEL_E_NOMEM;
  free(used);
  free(xy);
  free(pts);
  free(poly);
  return st;
}

void model_stable_config_default(model_stable_config_t *cfg) {
  if (cfg == NULL) return;
  cfg->max_rotation_rad = 0.02;
  cfg->max_displacement_m = 0.002;
  cfg->touch_depth_m = 1e-6;
}
