/* rockgen_patch.c - planar patches of a closed mesh and the polygons a body rests on. */
#include "rockgen.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "comlearn/math3d.h"

/* Largest distance between two vertices of a polygon (a few dozen points: brute force). */
static double polygon_diameter(const double (*h)[2], size_t n) {
  double dia = 0.0;
  for (size_t i = 0; i < n; ++i) {
    for (size_t j = i + 1; j < n; ++j) {
      const double dd = hypot(h[j][0] - h[i][0], h[j][1] - h[i][1]);
      if (dd > dia) dia = dd;
    }
  }
  return dia;
}

static int cmp_patch(const void *pa, const void *pb) {
  const rockgen_patch_t *a = pa, *b = pb;
  if (a->area_m2 != b->area_m2) return a->area_m2 > b->area_m2 ? -1 : 1;
  for (int k = 0; k < 3; ++k) {
    if (a->normal[k] != b->normal[k]) return a->normal[k] < b->normal[k] ? -1 : 1;
  }
  return 0;
}

/* Scratch arrays of rockgen_patches_find. */
typedef struct {
  double (*tn)[3];         /* unit normal of each triangle */
  double *ta;              /* area of each triangle */
  size_t *start;           /* nv + 1 row starts of adj */
  size_t *adj;             /* triangles around each vertex (compressed rows) */
  size_t *queue;           /* the triangles of the patch being grown */
  unsigned char *seen;     /* triangle already in a patch */
  unsigned char *in_patch; /* vertex already counted for the current patch */
  double (*pts)[2];
  double (*hull)[2];
} patch_work_t;

/* Allocates every array of w; returns 0 when one is missing (patch_work_free frees the others). */
static int patch_work_alloc(patch_work_t *w, size_t nt, size_t nv) {
  w->tn = malloc(nt * sizeof *w->tn);
  w->ta = malloc(nt * sizeof *w->ta);
  w->start = calloc(nv + 1, sizeof *w->start);
  w->adj = malloc(3 * nt * sizeof *w->adj);
  w->queue = malloc(nt * sizeof *w->queue);
  w->seen = calloc(nt, 1);
  w->in_patch = calloc(nv, 1);
  w->pts = malloc(nv * sizeof *w->pts);
  w->hull = malloc((nv + 1) * sizeof *w->hull);
  return w->tn && w->ta && w->start && w->adj && w->queue && w->seen && w->in_patch && w->pts &&
         w->hull;
}

static void patch_work_free(patch_work_t *w) {
  free(w->tn);
  free(w->ta);
  free(w->start);
  free(w->adj);
  free(w->queue);
  free(w->seen);
  free(w->in_patch);
  free(w->pts);
  free(w->hull);
}

/* Unit normal and area of every triangle; counts the triangles of each vertex into start[v + 1]. */
static model_status_t patch_triangle_normals(const model_mesh_t *mesh, patch_work_t *w) {
  const size_t nt = mesh->triangle_count, nv = mesh->vertex_count;
  for (size_t t = 0; t < nt; ++t) {
    const uint32_t *tri = mesh->triangles[t];
    double e1[3], e2[3];
    for (int k = 0; k < 3; ++k) {
      if (tri[k] >= nv) return MODEL_E_ARG;
    }
    for (int k = 0; k < 3; ++k) {
      e1[k] = mesh->vertices_m[tri[1]][k] - mesh->vertices_m[tri[0]][k];
      e2[k] = mesh->vertices_m[tri[2]][k] - mesh->vertices_m[tri[0]][k];
    }
    cl_vec3_cross(e1, e2, w->tn[t]);
    const double len = sqrt(cl_vec3_dot(w->tn[t], w->tn[t]));
    if (!(len > 0.0)) return MODEL_E_DEGENERATE;
    w->ta[t] = 0.5 * len;
    for (int k = 0; k < 3; ++k) w->tn[t][k] /= len;
    for (int k = 0; k < 3; ++k) ++w->start[tri[k] + 1];
  }
  return MODEL_OK;
}

/* Triangles around each vertex (compressed rows), from the counts in start[]. */
static model_status_t patch_vertex_triangles(const model_mesh_t *mesh, patch_work_t *w) {
  const size_t nt = mesh->triangle_count, nv = mesh->vertex_count;
  for (size_t v = 0; v < nv; ++v) w->start[v + 1] += w->start[v];
  size_t *fill = malloc(nv * sizeof *fill);
  if (fill == NULL) return MODEL_E_NOMEM;
  memcpy(fill, w->start, nv * sizeof *fill);
  for (size_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k) w->adj[fill[mesh->triangles[t][k]]++] = t;
  }
  free(fill);
  return MODEL_OK;
}

/* Grow from the seed through triangles that share a vertex and lie in the seed's plane. The
 * patch is queue[0 .. return value). */
static size_t patch_grow(const model_mesh_t *mesh, patch_work_t *w, size_t seed) {
  const double *n0 = w->tn[seed];
  const double h0 = cl_vec3_dot(n0, mesh->vertices_m[mesh->triangles[seed][0]]);
  size_t head = 0, tail = 0;
  w->queue[tail++] = seed;
  w->seen[seed] = 1;
  while (head < tail) {
    const size_t t = w->queue[head++];
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = mesh->triangles[t][k];
      for (size_t a = w->start[v]; a < w->start[v + 1]; ++a) {
        const size_t u = w->adj[a];
        if (w->seen[u] || cl_vec3_dot(w->tn[u], n0) < ROCKGEN_PLANE_COS) continue;
        int flat = 1;
        for (int j = 0; j < 3; ++j) {
          if (fabs(cl_vec3_dot(n0, mesh->vertices_m[mesh->triangles[u][j]]) - h0) >
              ROCKGEN_PLANE_TOL_M)
            flat = 0;
        }
        if (!flat) continue;
        w->seen[u] = 1;
        w->queue[tail++] = u;
      }
    }
  }
  return tail;
}

/* Area of the patch queue[0 .. tail); its area-weighted normal sum goes to nsum. */
static double patch_area(const patch_work_t *w, size_t tail, double nsum[3]) {
  double area = 0.0;
  for (size_t i = 0; i < tail; ++i) {
    area += w->ta[w->queue[i]];
    for (int k = 0; k < 3; ++k) nsum[k] += w->ta[w->queue[i]] * w->tn[w->queue[i]][k];
  }
  return area;
}

/* Fills p's plane: normal, area, basis, and from the patch's own vertices its offset, width and
 * diameter. */
static void patch_plane(const model_mesh_t *mesh, patch_work_t *w, size_t tail, double area,
                        const double nsum[3], rockgen_patch_t *p) {
  memset(p, 0, sizeof *p);
  const double nl = sqrt(cl_vec3_dot(nsum, nsum));
  for (int k = 0; k < 3; ++k) p->normal[k] = nsum[k] / nl;
  p->area_m2 = area;
  p->triangle_count = tail;
  model_plane_basis(p->normal, p->basis[0], p->basis[1]);
  size_t np = 0;
  double hsum = 0.0;
  for (size_t i = 0; i < tail; ++i) {
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = mesh->triangles[w->queue[i]][k];
      if (w->in_patch[v]) continue;
      w->in_patch[v] = 1;
      const double *x = mesh->vertices_m[v];
      hsum += cl_vec3_dot(p->normal, x);
      w->pts[np][0] = cl_vec3_dot(p->basis[0], x);
      w->pts[np][1] = cl_vec3_dot(p->basis[1], x);
      ++np;
    }
  }
  for (size_t i = 0; i < tail; ++i) {
    for (int k = 0; k < 3; ++k) w->in_patch[mesh->triangles[w->queue[i]][k]] = 0;
  }
  p->offset_m = hsum / (double)np;
  const size_t nh = model_polygon_hull(w->pts, np, w->hull);
  p->width_m = model_polygon_width((const double(*)[2])w->hull, nh);
  p->diameter_m = polygon_diameter((const double(*)[2])w->hull, nh);
}

/* Support: does the plane bound the body, and where does the body touch it? */
static model_status_t patch_support(const model_mesh_t *mesh, patch_work_t *w, rockgen_patch_t *p) {
  double excess = -HUGE_VAL;
  size_t ns = 0;
  for (size_t v = 0; v < mesh->vertex_count; ++v) {
    const double s = cl_vec3_dot(p->normal, mesh->vertices_m[v]) - p->offset_m;
    if (s > excess) excess = s;
    if (s >= -ROCKGEN_PLANE_TOL_M) {
      w->pts[ns][0] = cl_vec3_dot(p->basis[0], mesh->vertices_m[v]);
      w->pts[ns][1] = cl_vec3_dot(p->basis[1], mesh->vertices_m[v]);
      ++ns;
    }
  }
  p->support_excess_m = excess;
  const size_t nsh = model_polygon_hull(w->pts, ns, w->hull);
  if (nsh > ROCKGEN_MAX_SUPPORT) return MODEL_E_UNSUPPORTED;
  p->support_count = nsh;
  memcpy(p->support_uv, w->hull, nsh * sizeof *w->hull);
  return MODEL_OK;
}

model_status_t rockgen_patches_find(const model_mesh_t *mesh, double min_area_m2,
                                    rockgen_patch_t *patches, size_t capacity, size_t *count) {
  if (mesh == NULL || count == NULL || (patches == NULL && capacity > 0)) return MODEL_E_ARG;
  *count = 0;
  const size_t nt = mesh->triangle_count, nv = mesh->vertex_count;
  if (nt == 0 || nv == 0) return MODEL_E_DEGENERATE;
  patch_work_t w;
  model_status_t st = MODEL_OK;
  if (!patch_work_alloc(&w, nt, nv)) {
    st = MODEL_E_NOMEM;
    goto done;
  }
  st = patch_triangle_normals(mesh, &w);
  if (st == MODEL_OK) st = patch_vertex_triangles(mesh, &w);
  if (st != MODEL_OK) goto done;

  size_t found = 0;
  for (size_t seed = 0; seed < nt; ++seed) {
    if (w.seen[seed]) continue;
    const size_t tail = patch_grow(mesh, &w, seed);
    double nsum[3] = {0, 0, 0};
    const double area = patch_area(&w, tail, nsum);
    if (area < min_area_m2) continue;
    ++found;
    if (found > capacity) continue;
    rockgen_patch_t *p = &patches[found - 1];
    patch_plane(mesh, &w, tail, area, nsum, p);
    st = patch_support(mesh, &w, p);
    if (st != MODEL_OK) goto done;
  }
  const size_t stored = found < capacity ? found : capacity;
  if (stored > 1) qsort(patches, stored, sizeof *patches, cmp_patch);
  *count = found;

done:
  patch_work_free(&w);
  return st;
}

double rockgen_patch_margin(const rockgen_patch_t *patch, const double com_m[3]) {
  if (patch == NULL || com_m == NULL) return -HUGE_VAL;
  const double p[2] = {cl_vec3_dot(patch->basis[0], com_m), cl_vec3_dot(patch->basis[1], com_m)};
  return model_polygon_margin((const double(*)[2])patch->support_uv, patch->support_count, p);
}
