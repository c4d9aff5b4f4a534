/* mesh.c - mesh ownership, validation and repair, bounding boxes. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "comlearn/math3d.h"
#include "model_internal.h"

void model_mesh_free(model_mesh_t *mesh) {
  if (mesh == NULL) {
    return;
  }
  free(mesh->vertices_m);
  free(mesh->triangles);
  memset(mesh, 0, sizeof *mesh);
}

model_status_t model_mesh_alloc(model_mesh_t *out, size_t vertex_count, size_t triangle_count) {
  memset(out, 0, sizeof *out);
  if (vertex_count > SIZE_MAX / sizeof *out->vertices_m ||
      triangle_count > SIZE_MAX / sizeof *out->triangles) {
    return MODEL_E_NOMEM;
  }
  out->vertices_m = malloc((vertex_count > 0 ? vertex_count : 1) * sizeof *out->vertices_m);
  out->triangles = malloc((triangle_count > 0 ? triangle_count : 1) * sizeof *out->triangles);
  if (out->vertices_m == NULL || out->triangles == NULL) {
    model_mesh_free(out);
    return MODEL_E_NOMEM;
  }
  out->vertex_count = vertex_count;
  out->triangle_count = triangle_count;
  return MODEL_OK;
}

model_status_t model_mesh_copy(const model_mesh_t *src, model_mesh_t *dst) {
  if (src == NULL || dst == NULL || (src->vertex_count > 0 && src->vertices_m == NULL) ||
      (src->triangle_count > 0 && src->triangles == NULL)) {
    return MODEL_E_ARG;
  }
  model_status_t st = model_mesh_alloc(dst, src->vertex_count, src->triangle_count);
  if (st != MODEL_OK) {
    return st;
  }
  if (src->vertex_count > 0) {
    memcpy(dst->vertices_m, src->vertices_m, src->vertex_count * sizeof *src->vertices_m);
  }
  if (src->triangle_count > 0) {
    memcpy(dst->triangles, src->triangles, src->triangle_count * sizeof *src->triangles);
  }
  return MODEL_OK;
}

/* ---- model_mesh_check ------------------------------------------------------------------------ */

typedef struct {
  double p[3];
  uint32_t index;
} vertex_key_t;

static int vertex_key_cmp(const void *pa, const void *pb) {
  const vertex_key_t *a = pa;
  const vertex_key_t *b = pb;
  for (int k = 0; k < 3; ++k) {
    if (a->p[k] < b->p[k]) {
      return -1;
    }
    if (a->p[k] > b->p[k]) {
      return 1;
    }
  }
  return (a->index > b->index) - (a->index < b->index);
}

typedef struct {
  uint32_t lo;
  uint32_t hi;
  uint32_t triangle;
  uint32_t forward; /* 1 when the triangle runs lo -> hi */
} edge_key_t;

static int edge_key_cmp(const void *pa, const void *pb) {
  const edge_key_t *a = pa;
  const edge_key_t *b = pb;
  if (a->lo != b->lo) {
    return a->lo < b->lo ? -1 : 1;
  }
  if (a->hi != b->hi) {
    return a->hi < b->hi ? -1 : 1;
  }
  return (a->triangle > b->triangle) - (a->triangle < b->triangle);
}

/* Edge sort and scan; reports the first defect found in `err`. */
static model_status_t check_edges(uint32_t (*tris)[3], size_t tri_count, double (*verts)[3],
                                  size_t removed_degenerate, model_error_t *err) {
  edge_key_t *edges = malloc(3 * tri_count * sizeof *edges);
  if (edges == NULL) {
    return MODEL_E_NOMEM;
  }
  for (size_t t = 0; t < tri_count; ++t) {
    for (int k = 0; k < 3; ++k) {
      uint32_t a = tris[t][k];
      uint32_t b = tris[t][(k + 1) % 3];
      edge_key_t *e = &edges[3 * t + (size_t)k];
      e->lo = a < b ? a : b;
      e->hi = a < b ? b : a;
      e->triangle = (uint32_t)t;
      e->forward = a < b;
    }
  }
  qsort(edges, 3 * tri_count, sizeof *edges, edge_key_cmp);

  size_t boundary = 0, nonmanifold = 0, misoriented = 0;
  const edge_key_t *first_open = NULL, *first_orient = NULL;
  size_t first_open_uses = 0;
  for (size_t i = 0; i < 3 * tri_count;) {
    size_t j = i + 1;
    while (j < 3 * tri_count && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi) {
      ++j;
    }
    size_t uses = j - i;
    if (uses != 2) {
      if (uses == 1) {
        ++boundary;
      } else {
        ++nonmanifold;
      }
      if (first_open == NULL) {
        first_open = &edges[i];
        first_open_uses = uses;
      }
    } else if (edges[i].forward == edges[i + 1].forward) {
      ++misoriented;
      if (first_orient == NULL) {
        first_orient = &edges[i];
      }
    }
    i = j;
  }

  model_status_t st = MODEL_OK;
  char note[96] = "";
  if (removed_degenerate > 0) {
    (void)snprintf(note, sizeof note, " (after dropping %zu degenerate triangles)",
                   removed_degenerate);
  }
  if (first_open != NULL) {
    const double *a = verts[first_open->lo];
    const double *b = verts[first_open->hi];
    st = model_fail(err, MODEL_E_OPEN,
                    "mesh is not closed%s: %zu boundary and %zu non-manifold edges; e.g. the edge "
                    "(%.9g, %.9g, %.9g)-(%.9g, %.9g, %.9g) is used by %zu triangle(s), not 2",
                    note, boundary, nonmanifold, a[0], a[1], a[2], b[0], b[1], b[2],
                    first_open_uses);
  } else if (first_orient != NULL) {
    const double *a = verts[first_orient->lo];
    const double *b = verts[first_orient->hi];
    st = model_fail(err, MODEL_E_ORIENT,
                    "mesh triangles are not consistently oriented: %zu edges are traversed twice "
                    "in the same direction; e.g. the edge (%.9g, %.9g, %.9g)-(%.9g, %.9g, %.9g) "
                    "by triangles %u and %u",
                    misoriented, a[0], a[1], a[2], b[0], b[1], b[2], first_orient[0].triangle,
                    first_orient[1].triangle);
  }
  free(edges);
  return st;
}

/* The input checks of model_mesh_check, in their order: counts, arrays, size, finite vertices,
 * indices in range. */
static model_status_t mesh_check_input(const model_mesh_t *mesh, model_error_t *err) {
  const size_t nv = mesh->vertex_count;
  const size_t nt = mesh->triangle_count;
  if (nv == 0 || nt == 0) {
    return model_fail(err, MODEL_E_DEGENERATE, "empty mesh (%zu vertices, %zu triangles)", nv, nt);
  }
  if (mesh->vertices_m == NULL || mesh->triangles == NULL) {
    return model_fail(err, MODEL_E_ARG, "mesh arrays are NULL");
  }
  if (nv > UINT32_MAX || nt > UINT32_MAX / 3) {
    return model_fail(err, MODEL_E_ARG, "mesh too large (%zu vertices, %zu triangles)", nv, nt);
  }
  for (size_t i = 0; i < nv; ++i) {
    const double *p = mesh->vertices_m[i];
    if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2])) {
      return model_fail(err, MODEL_E_NONFINITE, "vertex %zu is not finite (%g, %g, %g)", i, p[0],
                        p[1], p[2]);
    }
  }
  for (size_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k) {
      if (mesh->triangles[t][k] >= nv) {
        return model_fail(err, MODEL_E_ARG, "triangle %zu uses vertex %u but the mesh has %zu", t,
                          mesh->triangles[t][k], nv);
      }
    }
  }
  return MODEL_OK;
}

/* Joins bit-identical vertices: sort, and map every member of a run to its lowest index.
 * Returns the number of distinct vertices. */
static size_t mesh_join_vertices(const model_mesh_t *mesh, vertex_key_t *keys, uint32_t *map) {
  const size_t nv = mesh->vertex_count;
  for (size_t i = 0; i < nv; ++i) {
    memcpy(keys[i].p, mesh->vertices_m[i], sizeof keys[i].p);
    keys[i].index = (uint32_t)i;
  }
  qsort(keys, nv, sizeof *keys, vertex_key_cmp);
  size_t distinct = 0;
  for (size_t i = 0; i < nv;) {
    size_t j = i + 1;
    while (j < nv && keys[j].p[0] == keys[i].p[0] && keys[j].p[1] == keys[i].p[1] &&
           keys[j].p[2] == keys[i].p[2]) {
      ++j;
    }
    for (size_t k = i; k < j; ++k) {
      map[keys[k].index] = keys[i].index; /* runs are sorted by index: keys[i] is the lowest */
    }
    ++distinct;
    i = j;
  }
  return distinct;
}

/* Drops degenerate triangles (a repeated corner after the join, or a zero normal) and writes
 * the others, through map[], to tris. Returns how many are kept. */
static size_t mesh_drop_degenerate(const model_mesh_t *mesh, const uint32_t *map,
                                   uint32_t (*tris)[3], size_t *removed_degenerate) {
  size_t kept = 0;
  for (size_t t = 0; t < mesh->triangle_count; ++t) {
    uint32_t a = map[mesh->triangles[t][0]];
    uint32_t b = map[mesh->triangles[t][1]];
    uint32_t c = map[mesh->triangles[t][2]];
    if (a == b || b == c || a == c) {
      ++*removed_degenerate;
      continue;
    }
    double ab[3], ac[3], n[3];
    cl_vec3_sub(mesh->vertices_m[b], mesh->vertices_m[a], ab);
    cl_vec3_sub(mesh->vertices_m[c], mesh->vertices_m[a], ac);
    cl_vec3_cross(ab, ac, n);
    if (n[0] == 0.0 && n[1] == 0.0 && n[2] == 0.0) {
      ++*removed_degenerate;
      continue;
    }
    tris[kept][0] = a;
    tris[kept][1] = b;
    tris[kept][2] = c;
    ++kept;
  }
  return kept;
}

/* Numbers the vertices the kept triangles use in their original order: newindex[old] = new, or
 * UINT32_MAX when unused. Returns how many are used. */
static size_t mesh_number_used(uint32_t *newindex, size_t nv, uint32_t (*tris)[3], size_t kept) {
  for (size_t i = 0; i < nv; ++i) {
    newindex[i] = UINT32_MAX;
  }
  for (size_t t = 0; t < kept; ++t) {
    for (int k = 0; k < 3; ++k) {
      newindex[tris[t][k]] = 0;
    }
  }
  size_t used = 0;
  for (size_t i = 0; i < nv; ++i) {
    if (newindex[i] == 0) {
      newindex[i] = (uint32_t)used++;
    }
  }
  return used;
}

/* Copies the used vertices to verts and renumbers tris, both through newindex[]. */
static void mesh_compact(const model_mesh_t *mesh, const uint32_t *newindex, double (*verts)[3],
                         uint32_t (*tris)[3], size_t kept) {
  for (size_t i = 0; i < mesh->vertex_count; ++i) {
    if (newindex[i] != UINT32_MAX) {
      memcpy(verts[newindex[i]], mesh->vertices_m[i], sizeof verts[0]);
    }
  }
  for (size_t t = 0; t < kept; ++t) {
    for (int k = 0; k < 3; ++k) {
      tris[t][k] = newindex[tris[t][k]];
    }
  }
}

/* Signed volume about the bbox center (smaller rounding than about the origin); the largest
 * bbox extent goes to *extent. */
static double mesh_signed_volume(double (*verts)[3], size_t used, uint32_t (*tris)[3], size_t kept,
                                 double *extent) {
  double lo[3], hi[3];
  memcpy(lo, verts[0], sizeof lo);
  memcpy(hi, verts[0], sizeof hi);
  for (size_t i = 1; i < used; ++i) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = fmin(lo[k], verts[i][k]);
      hi[k] = fmax(hi[k], verts[i][k]);
    }
  }
  double ref[3] = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
  *extent = fmax(hi[0] - lo[0], fmax(hi[1] - lo[1], hi[2] - lo[2]));
  double volume6 = 0.0;
  for (size_t t = 0; t < kept; ++t) {
    double a[3], b[3], c[3], bc[3];
    cl_vec3_sub(verts[tris[t][0]], ref, a);
    cl_vec3_sub(verts[tris[t][1]], ref, b);
    cl_vec3_sub(verts[tris[t][2]], ref, c);
    cl_vec3_cross(b, c, bc);
    volume6 += a[0] * bc[0] + a[1] * bc[1] + a[2] * bc[2];
  }
  return volume6 / 6.0;
}

/* Fails on a mesh that encloses no volume; turns an inward mesh outward (*flipped = 1). */
static model_status_t mesh_orient(double (*verts)[3], size_t used, uint32_t (*tris)[3], size_t kept,
                                  int *flipped, model_error_t *err) {
  double extent;
  double volume = mesh_signed_volume(verts, used, tris, kept, &extent);
  if (!(fabs(volume) > 1e-12 * extent * extent * extent)) {
    return model_fail(err, MODEL_E_DEGENERATE,
                      "closed mesh encloses no volume (%g m^3 for a size of %g m)", volume, extent);
  }
  if (volume < 0.0) {
    for (size_t t = 0; t < kept; ++t) {
      uint32_t tmp = tris[t][1];
      tris[t][1] = tris[t][2];
      tris[t][2] = tmp;
    }
    *flipped = 1;
  }
  return MODEL_OK;
}

/* Hands the repaired arrays to the mesh, freeing its old ones. */
static void mesh_commit(model_mesh_t *mesh, double (*verts)[3], size_t used, uint32_t (*tris)[3],
                        size_t kept) {
  free(mesh->vertices_m);
  free(mesh->triangles);
  mesh->vertices_m = verts;
  mesh->vertex_count = used;
  uint32_t(*shrunk)[3] = realloc(tris, kept * sizeof *tris);
  mesh->triangles = shrunk != NULL ? shrunk : tris;
  mesh->triangle_count = kept;
}

model_status_t model_mesh_check(model_mesh_t *mesh, model_mesh_report_t *report,
                                model_error_t *err) {
  model_mesh_report_t rep;
  memset(&rep, 0, sizeof rep);
  if (report != NULL) {
    *report = rep;
  }
  if (mesh == NULL) {
    return model_fail(err, MODEL_E_ARG, "mesh is NULL");
  }
  model_status_t st = mesh_check_input(mesh, err);
  if (st != MODEL_OK) {
    return st;
  }
  const size_t nv = mesh->vertex_count;
  const size_t nt = mesh->triangle_count;
  vertex_key_t *keys = malloc(nv * sizeof *keys);
  uint32_t *map = malloc(nv * sizeof *map);
  uint32_t(*tris)[3] = malloc(nt * sizeof *tris);
  double(*verts)[3] = NULL;
  if (keys == NULL || map == NULL || tris == NULL) {
    st = MODEL_E_NOMEM;
    goto done;
  }

  const size_t distinct = mesh_join_vertices(mesh, keys, map);
  rep.merged_vertices = nv - distinct;
  const size_t kept = mesh_drop_degenerate(mesh, map, tris, &rep.removed_degenerate);
  /* map[] is reused as old -> new. */
  uint32_t *newindex = map;
  const size_t used = mesh_number_used(newindex, nv, tris, kept);
  rep.removed_unreferenced = distinct - used;
  if (report != NULL) {
    *report = rep;
  }
  if (kept < 4) {
    st = model_fail(err, MODEL_E_DEGENERATE,
                    "mesh has %zu non-degenerate triangles (of %zu); a closed surface needs >= 4",
                    kept, nt);
    goto done;
  }
  verts = malloc(used * sizeof *verts);
  if (verts == NULL) {
    st = MODEL_E_NOMEM;
    goto done;
  }
  mesh_compact(mesh, newindex, verts, tris, kept);

  st = check_edges(tris, kept, verts, rep.removed_degenerate, err);
  if (st != MODEL_OK) {
    goto done;
  }

  st = mesh_orient(verts, used, tris, kept, &rep.flipped, err);
  if (st != MODEL_OK) {
    goto done;
  }

  mesh_commit(mesh, verts, used, tris, kept);
  verts = NULL;
  tris = NULL;
  if (report != NULL) {
    *report = rep;
  }

done:
  free(keys);
  free(map);
  free(tris);
  free(verts);
  if (st == MODEL_E_NOMEM) {
    (void)model_fail(err, st, "out of memory checking a mesh of %zu triangles", nt);
  }
  return st;
}

/* ---- bounding box ---------------------------------------------------------------------------- */

model_status_t model_mesh_aabb(const model_mesh_t *mesh, model_aabb_t *out) {
  if (mesh == NULL || out == NULL || (mesh->vertex_count > 0 && mesh->vertices_m == NULL)) {
    return MODEL_E_ARG;
  }
  memset(out, 0, sizeof *out);
  if (mesh->vertex_count == 0) {
    return MODEL_E_DEGENERATE;
  }
  model_aabb_t box;
  memcpy(box.min_m, mesh->vertices_m[0], sizeof box.min_m);
  memcpy(box.max_m, mesh->vertices_m[0], sizeof box.max_m);
  for (size_t i = 0; i < mesh->vertex_count; ++i) {
    for (int k = 0; k < 3; ++k) {
      double v = mesh->vertices_m[i][k];
      if (!isfinite(v)) {
        return MODEL_E_NONFINITE;
      }
      box.min_m[k] = v < box.min_m[k] ? v : box.min_m[k];
      box.max_m[k] = v > box.max_m[k] ? v : box.max_m[k];
    }
  }
  *out = box;
  return MODEL_OK;
}

void model_aabb_center(const model_aabb_t *box, double center_m[3]) {
  for (int k = 0; k < 3; ++k) {
    center_m[k] = 0.5 * (box->min_m[k] + box->max_m[k]);
  }
}
