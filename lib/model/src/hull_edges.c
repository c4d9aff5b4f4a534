/* hull_edges.c - the edges of a convex hull where two facets meet at an angle: the lines an object
 * can be balanced on, as on a knife edge (lib/estimate's pivot searches). Pure geometry. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "comlearn/math3d.h"
#include "comlearn/model_support.h"

/* By (v[0], v[1]), then by the triangle's third vertex: a total order, so the result does not
 * depend on qsort. */
static int cmp_half(const void *pa, const void *pb) {
  const model_hull_edge_t *a = pa, *b = pb;
  for (int k = 0; k < 2; ++k)
    if (a->v[k] != b->v[k]) return a->v[k] < b->v[k] ? -1 : 1;
  return a->opposite[0] < b->opposite[0] ? -1 : (a->opposite[0] > b->opposite[0]);
}

/* The cosine of the angle between the outward normals of an edge's two triangles, (v0, v1, o0)
 * and (v1, v0, o1): 1 where they are coplanar. */
static double facet_cos(const model_mesh_t *hull, const model_hull_edge_t *e) {
  const double(*v)[3] = (const double(*)[3])hull->vertices_m;
  double n0[3], n1[3];
  cl_tri_normal(v[e->v[0]], v[e->v[1]], v[e->opposite[0]], n0);
  cl_tri_normal(v[e->v[1]], v[e->v[0]], v[e->opposite[1]], n1);
  return cl_vec3_dot(n0, n1);
}

model_status_t model_hull_edges(const model_mesh_t *hull, double merge_cos,
                                model_hull_edge_t *edges, size_t capacity, size_t *count) {
  if (count) *count = 0;
  if (!hull || !edges || !count || !hull->vertices_m || !hull->triangles ||
      hull->triangle_count == 0 || capacity < 3 * hull->triangle_count || !isfinite(merge_cos))
    return MODEL_E_ARG;
  const size_t nt = hull->triangle_count, nh = 3 * nt;
  /* every half-edge, its ends in ascending order, with its triangle's third vertex */
  for (size_t t = 0; t < nt; ++t) {
    const uint32_t *tri = hull->triangles[t];
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = tri[k], b = tri[(k + 1) % 3], c = tri[(k + 2) % 3];
      if (a >= hull->vertex_count || b >= hull->vertex_count || c >= hull->vertex_count || a == b)
        return MODEL_E_DEGENERATE;
      model_hull_edge_t *h = &edges[3 * t + (size_t)k];
      /* the first triangle of an edge is the one that runs it from v[0] to v[1] */
      h->v[0] = a < b ? a : b;
      h->v[1] = a < b ? b : a;
      h->opposite[0] = c;
      h->opposite[1] = a < b ? 0u : 1u; /* scratch: which way this triangle runs it */
    }
  }
  qsort(edges, nh, sizeof *edges, cmp_half);
  size_t n = 0;
  for (size_t i = 0; i < nh; i += 2) {
    /* a closed hull has each edge in exactly two triangles, running it both ways */
    if (i + 1 >= nh || edges[i].v[0] != edges[i + 1].v[0] || edges[i].v[1] != edges[i + 1].v[1] ||
        (i + 2 < nh && edges[i + 2].v[0] == edges[i].v[0] && edges[i + 2].v[1] == edges[i].v[1]) ||
        edges[i].opposite[1] == edges[i + 1].opposite[1])
      return MODEL_E_OPEN;
    const int first = edges[i].opposite[1] == 0u ? 0 : 1; /* runs v[0] -> v[1] */
    model_hull_edge_t e = {.v = {edges[i].v[0], edges[i].v[1]},
                           .opposite = {edges[i + (size_t)first].opposite[0],
                                        edges[i + 1 - (size_t)first].opposite[0]}};
    if (facet_cos(hull, &e) >= merge_cos) continue; /* inside a face */
    edges[n++] = e;
  }
  *count = n;
  return MODEL_OK;
}
