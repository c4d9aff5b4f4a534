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

model_status_t rockgen_patches_find(const model_mesh_t *mesh, double min_area_m2,
                                    rockgen_patch_t *patches, size_t capacity, size_t *count) {
  if (mesh == NULL || count == NULL || (patches == NULL && capacity > 0)) return MODEL_E_ARG;
  *count = 0;
  const size_t nt = mesh->triangle_count, nv = mesh->vertex_count;
  if (nt == 0 || nv == 0) return MODEL_E_DEGENERATE;
  double(*tn)[3] = malloc(nt * sizeof *tn);
  double *ta = malloc(nt * sizeof *ta);
  size_t *start = calloc(nv + 1, sizeof *start);
  size_t *adj = malloc(3 * nt * sizeof *adj);
  size_t *queue = malloc(nt * sizeof *queue);
  unsigned char *seen = calloc(nt, 1);
  unsigned char *in_patch = calloc(nv, 1);
  double(*pts)[2] = malloc(nv * sizeof *pts);
  double(*hull)[2] = malloc((nv + 1) * sizeof *hull);
  model_status_t st = MODEL_OK;
  if (!tn || !ta || !start || !adj || !queue || !seen || !in_patch || !pts || !hull) {
    st = MODEL_E_NOMEM;
    goto done;
  }
  for (size_t t = 0; t < nt; ++t) {
    const uint32_t *tri = mesh->triangles[t];
    double e1[3], e2[3];
    for (int k = 0; k < 3; ++k) {
      if (tri[k] >= nv) {
        st = MODEL_E_ARG;
        goto done;
      }
    }
    for (int k = 0; k < 3; ++k) {
      e1[k] = mesh->vertices_m[tri[1]][k] - mesh->vertices_m[tri[0]][k];
      e2[k] = mesh->vertices_m[tri[2]][k] - mesh->vertices_m[tri[0]][k];
    }
    cl_vec3_cross(e1, e2, tn[t]);
    const double len = sqrt(cl_vec3_dot(tn[t], tn[t]));
    if (!(len > 0.0)) {
      st = MODEL_E_DEGENERATE;
      goto done;
    }
    ta[t] = 0.5 * len;
    for (int k = 0; k < 3; ++k) tn[t][k] /= len;
    for (int k = 0; k < 3; ++k) ++start[tri[k] + 1];
  }
  /* Triangles around each vertex (compressed rows). */
  for (size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  {
    size_t *fill = malloc(nv * sizeof *fill);
    if (fill == NULL) {
      st = MODEL_E_NOMEM;
      goto done;
    }
    memcpy(fill, start, nv * sizeof *fill);
    for (size_t t = 0; t < nt; ++t) {
      for (int k = 0; k < 3; ++k) adj[fill[mesh->triangles[t][k]]++] = t;
    }
    free(fill);
  }

  size_t found = 0;
  for (size_t seed = 0; seed < nt; ++seed) {
    if (seen[seed]) continue;
    /* Grow from the seed through triangles that share a vertex and lie in the seed's plane. */
    const double *n0 = tn[seed];
    const double h0 = cl_vec3_dot(n0, mesh->vertices_m[mesh->triangles[seed][0]]);
    size_t head = 0, tail = 0;
    queue[tail++] = seed;
    seen[seed] = 1;
    while (head < tail) {
      const size_t t = queue[head++];
      for (int k = 0; k < 3; ++k) {
        const uint32_t v = mesh->triangles[t][k];
        for (size_t a = start[v]; a < start[v + 1]; ++a) {
          const size_t u = adj[a];
          if (seen[u] || cl_vec3_dot(tn[u], n0) < ROCKGEN_PLANE_COS) continue;
          int flat = 1;
          for (int j = 0; j < 3; ++j) {
            if (fabs(cl_vec3_dot(n0, mesh->vertices_m[mesh->triangles[u][j]]) - h0) >
                ROCKGEN_PLANE_TOL_M)
              flat = 0;
          }
          if (!flat) continue;
          seen[u] = 1;
          queue[tail++] = u;
        }
      }
    }
    double area = 0.0, nsum[3] = {0, 0, 0};
    for (size_t i = 0; i < tail; ++i) {
      area += ta[queue[i]];
      for (int k = 0; k < 3; ++k) nsum[k] += ta[queue[i]] * tn[queue[i]][k];
    }
    if (area < min_area_m2) continue;
    ++found;
    if (found > capacity) continue;
    rockgen_patch_t *p = &patches[found - 1];
    memset(p, 0, sizeof *p);
    const double nl = sqrt(cl_vec3_dot(nsum, nsum));
    for (int k = 0; k < 3; ++k) p->normal[k] = nsum[k] / nl;
    p->area_m2 = area;
    p->triangle_count = tail;
    model_plane_basis(p->normal, p->basis[0], p->basis[1]);
    /* The patch's own vertices: plane offset, width, diameter. */
    size_t np = 0;
    double hsum = 0.0;
    for (size_t i = 0; i < tail; ++i) {
      for (int k = 0; k < 3; ++k) {
        const uint32_t v = mesh->triangles[queue[i]][k];
        if (in_patch[v]) continue;
        in_patch[v] = 1;
        const double *x = mesh->vertices_m[v];
        hsum += cl_vec3_dot(p->normal, x);
        pts[np][0] = cl_vec3_dot(p->basis[0], x);
        pts[np][1] = cl_vec3_dot(p->basis[1], x);
        ++np;
      }
    }
    for (size_t i = 0; i < tail; ++i) {
      for (int k = 0; k < 3; ++k) in_patch[mesh->triangles[queue[i]][k]] = 0;
    }
    p->offset_m = hsum / (double)np;
    const size_t nh = model_polygon_hull(pts, np, hull);
    p->width_m = model_polygon_width((const double(*)[2])hull, nh);
    p->diameter_m = polygon_diameter((const double(*)[2])hull, nh);
    /* Support: does the plane bound the body, and where does the body touch it? */
    double excess = -HUGE_VAL;
    size_t ns = 0;
    for (size_t v = 0; v < nv; ++v) {
      const double s = cl_vec3_dot(p->normal, mesh->vertices_m[v]) - p->offset_m;
      if (s > excess) excess = s;
      if (s >= -ROCKGEN_PLANE_TOL_M) {
        pts[ns][0] = cl_vec3_dot(p->basis[0], mesh->vertices_m[v]);
        pts[ns][1] = cl_vec3_dot(p->basis[1], mesh->vertices_m[v]);
        ++ns;
      }
    }
    p->support_excess_m = excess;
    const size_t nsh = model_polygon_hull(pts, ns, hull);
    if (nsh > ROCKGEN_MAX_SUPPORT) {
      st = MODEL_E_UNSUPPORTED;
      goto done;
    }
    p->support_count = nsh;
    memcpy(p->support_uv, hull, nsh * sizeof *hull);
  }
  const size_t stored = found < capacity ? found : capacity;
  if (stored > 1) qsort(patches, stored, sizeof *patches, cmp_patch);
  *count = found;

done:
  free(tn);
  free(ta);
  free(start);
  free(adj);
  free(queue);
  free(seen);
  free(in_patch);
  free(pts);
  free(hull);
  return st;
}

double rockgen_patch_margin(const rockgen_patch_t *patch, const double com_m[3]) {
  if (patch == NULL || com_m == NULL) return -HUGE_VAL;
  const double p[2] = {cl_vec3_dot(patch->basis[0], com_m), cl_vec3_dot(patch->basis[1], com_m)};
  return model_polygon_margin((const double(*)[2])patch->support_uv, patch->support_count, p);
}
