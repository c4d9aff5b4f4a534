/* object.c - an object's body and geometry: validation, placement, pose queries. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "balance_internal.h"

static int cmp_edge(const void *a, const void *b) {
  const uint32_t *x = a, *y = b;
  if (x[0] != y[0]) return x[0] < y[0] ? -1 : 1;
  if (x[1] != y[1]) return x[1] < y[1] ? -1 : 1;
  return 0;
}

/* Mesh usable for contacts: finite, indices in range, no degenerate triangle, sane size. */
static balance_status_t mesh_validate(const model_mesh_t *m) {
  if (!m || !m->vertices_m || !m->triangles) return BALANCE_E_ARG;
  if (m->vertex_count < 4 || m->triangle_count < 4) return BALANCE_E_MESH;
  if (m->vertex_count >= UINT32_MAX || m->triangle_count >= UINT32_MAX / 3) return BALANCE_E_MESH;
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (size_t i = 0; i < m->vertex_count; i++)
    for (int k = 0; k < 3; k++) {
      const double v = m->vertices_m[i][k];
      if (!isfinite(v)) return BALANCE_E_NONFINITE;
      if (v < lo[k]) lo[k] = v;
      if (v > hi[k]) hi[k] = v;
    }
  double ext = 0.0;
  for (int k = 0; k < 3; k++) ext = fmax(ext, hi[k] - lo[k]);
  if (!(ext >= 1e-4 && ext <= 10.0)) return BALANCE_E_MESH;
  for (size_t t = 0; t < m->triangle_count; t++) {
    const uint32_t *tri = m->triangles[t];
    if (tri[0] >= m->vertex_count || tri[1] >= m->vertex_count || tri[2] >= m->vertex_count)
      return BALANCE_E_MESH;
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) return BALANCE_E_MESH;
    const double *a = m->vertices_m[tri[0]], *b = m->vertices_m[tri[1]], *c = m->vertices_m[tri[2]];
    double u[3], v[3];
    for (int k = 0; k < 3; k++) {
      u[k] = b[k] - a[k];
      v[k] = c[k] - a[k];
    }
    const double cx = u[1] * v[2] - u[2] * v[1], cy = u[2] * v[0] - u[0] * v[2],
                 cz = u[0] * v[1] - u[1] * v[0];
    /* A zero-area triangle has no normal: colliders would produce zero or NaN normals. */
    if (!(sqrt(cx * cx + cy * cy + cz * cz) > 1e-12 * ext * ext)) return BALANCE_E_MESH;
  }
  return BALANCE_OK;
}

/* Mass properties ODE accepts without aborting: mass > 0, inertia symmetric and positive definite,
 * principal moments obeying the triangle inequality (J = tr(I)/2 - I, the second moment, positive
 * semi-definite), CoM inside the mesh's bounding box. */
static balance_status_t mass_validate(const model_mass_t *ms, const model_mesh_t *m) {
  if (!ms) return BALANCE_E_ARG;
  if (!isfinite(ms->mass_kg)) return BALANCE_E_NONFINITE;
  for (int i = 0; i < 3; i++) {
    if (!isfinite(ms->com_m[i])) return BALANCE_E_NONFINITE;
    for (int j = 0; j < 3; j++)
      if (!isfinite(ms->inertia_kg_m2[i][j])) return BALANCE_E_NONFINITE;
  }
  if (!(ms->mass_kg > 0.0) || ms->mass_kg > 1e6) return BALANCE_E_MASS;
  const double(*I)[3] = ms->inertia_kg_m2;
  double s = 0.0;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) s = fmax(s, fabs(I[i][j]));
  if (!(s > 0.0)) return BALANCE_E_MASS;
  for (int i = 0; i < 3; i++)
    for (int j = i + 1; j < 3; j++)
      if (fabs(I[i][j] - I[j][i]) > 1e-9 * s) return BALANCE_E_MASS;
  /* Positive definite by leading minors, with a margin so that ODE's Cholesky agrees. */
  const double m1 = I[0][0], m2 = I[0][0] * I[1][1] - I[0][1] * I[1][0];
  const double m3 = I[0][0] * (I[1][1] * I[2][2] - I[1][2] * I[2][1]) -
                    I[0][1] * (I[1][0] * I[2][2] - I[1][2] * I[2][0]) +
                    I[0][2] * (I[1][0] * I[2][1] - I[1][1] * I[2][0]);
  if (!(m1 > 1e-12 * s && m2 > 1e-12 * s * s && m3 > 1e-12 * s * s * s)) return BALANCE_E_MASS;
  const double half_tr = 0.5 * (I[0][0] + I[1][1] + I[2][2]);
  double J[3][3];
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) J[i][j] = (i == j ? half_tr : 0.0) - I[i][j];
  const double tol = 1e-9 * s;
  for (int i = 0; i < 3; i++)
    if (J[i][i] < -tol) return BALANCE_E_MASS;
  for (int i = 0; i < 3; i++)
    for (int j = i + 1; j < 3; j++)
      if (J[i][i] * J[j][j] - J[i][j] * J[j][i] < -tol * s) return BALANCE_E_MASS;
  const double dj = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
                    J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
                    J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
  if (dj < -tol * s * s) return BALANCE_E_MASS;
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (size_t i = 0; i < m->vertex_count; i++)
    for (int k = 0; k < 3; k++) {
      lo[k] = fmin(lo[k], m->vertices_m[i][k]);
      hi[k] = fmax(hi[k], m->vertices_m[i][k]);
    }
  for (int k = 0; k < 3; k++) {
    const double slack = 1e-9 * (hi[k] - lo[k]);
    if (ms->com_m[k] < lo[k] - slack || ms->com_m[k] > hi[k] + slack) return BALANCE_E_MASS;
  }
  return BALANCE_OK;
}

void balance_object_destroy_internal(balance_object_t *o) {
  if (!o) return;
  if (o->geom) dGeomDestroy(o->geom);
  if (o->tm_data) dGeomTriMeshDataDestroy(o->tm_data);
  if (o->body) dBodyDestroy(o->body);
  free(o->tm_vertices);
  free(o->tm_indices);
  free(o->verts_body_m);
  free(o->hull_planes);
  free(o->sep_cache);
  free(o->vert_normals);
  free(o->edges);
  free(o->fast.verts);
  free(o->fast.verts_w);
  free(o->fast.edges);
  free(o->fast.edge_ids);
  free(o->fast.code);
  free(o->fast.local);
  model_mesh_free(&o->mesh_link);
  model_mesh_free(&o->hull_link);
  free(o);
}

/* The per-vertex and per-triangle buffers; *all (every triangle edge, later the unique edges) is
 * the caller's on success and freed here on failure. */
static balance_status_t object_buffers_alloc(balance_object_t *o, size_t nv, size_t nt,
                                             uint32_t (**all)[2]) {
  o->verts_body_m = malloc(nv * sizeof *o->verts_body_m);
  o->tm_vertices = malloc(3 * nv * sizeof *o->tm_vertices);
  o->tm_indices = malloc(3 * nt * sizeof *o->tm_indices);
  *all = malloc(3 * nt * sizeof **all);
  o->fast.verts = malloc(nv * sizeof *o->fast.verts);
  o->fast.verts_w = malloc(nv * sizeof *o->fast.verts_w);
  o->fast.local = malloc(nv * sizeof *o->fast.local);
  o->sep_cache = calloc(nv * BALANCE_SEP_SLOTS, sizeof *o->sep_cache);
  if (!o->verts_body_m || !o->tm_vertices || !o->tm_indices || !*all || !o->fast.verts ||
      !o->fast.verts_w || !o->fast.local || !o->sep_cache) {
    free(*all);
    *all = NULL;
    return BALANCE_E_NOMEM;
  }
  return BALANCE_OK;
}

/* Vertices in the body frame (CoM at the origin) and the radius about the CoM. */
static void object_vertices_fill(balance_object_t *o, const model_mesh_t *mesh,
                                 const double com_m[3]) {
  for (size_t i = 0; i < mesh->vertex_count; i++) {
    double r2 = 0.0;
    for (int k = 0; k < 3; k++) {
      const double v = mesh->vertices_m[i][k] - com_m[k];
      o->verts_body_m[i][k] = v;
      o->tm_vertices[3 * i + (size_t)k] = v;
      r2 += v * v;
    }
    o->radius_m = fmax(o->radius_m, sqrt(r2));
    o->fast.local[i] = UINT32_MAX;
  }
}

/* ODE's triangle indices and the sorted unique edges (taking over `all`), then the edge-sized
 * buffers of the fast contact path. */
static balance_status_t object_edges_build(balance_object_t *o, const model_mesh_t *mesh,
                                           uint32_t (*all)[2]) {
  const size_t nv = mesh->vertex_count, nt = mesh->triangle_count;
  for (size_t t = 0; t < nt; t++)
    for (int k = 0; k < 3; k++) {
      o->tm_indices[3 * t + (size_t)k] = (dTriIndex)mesh->triangles[t][k];
      uint32_t a = mesh->triangles[t][k], b = mesh->triangles[t][(k + 1) % 3];
      all[3 * t + (size_t)k][0] = a < b ? a : b;
      all[3 * t + (size_t)k][1] = a < b ? b : a;
    }
  qsort(all, 3 * nt, sizeof *all, cmp_edge);
  size_t ne = 0;
  for (size_t i = 0; i < 3 * nt; i++)
    if (ne == 0 || cmp_edge(all[i], all[ne - 1]) != 0) {
      all[ne][0] = all[i][0];
      all[ne][1] = all[i][1];
      ne++;
    }
  /* Shrink to the unique edges; on failure keep the larger block (still valid). */
  uint32_t(*shrunk)[2] = realloc(all, ne * sizeof *all);
  o->edges = shrunk ? shrunk : all;
  o->edge_count = ne;
  o->fast.edges = malloc(ne * sizeof *o->fast.edges);
  o->fast.edge_ids = malloc(ne * sizeof *o->fast.edge_ids);
  o->fast.code = malloc(nv * sizeof *o->fast.code);
  if (!o->fast.edges || !o->fast.edge_ids || !o->fast.code) return BALANCE_E_NOMEM;
  return BALANCE_OK;
}

/* Unit vertex normals: the sum of the adjacent triangles' area-weighted normals, normalised. */
static balance_status_t object_vertex_normals(balance_object_t *o, const model_mesh_t *mesh) {
  const size_t nv = mesh->vertex_count, nt = mesh->triangle_count;
  o->vert_normals = calloc(nv, sizeof *o->vert_normals);
  if (!o->vert_normals) return BALANCE_E_NOMEM;
  for (size_t t = 0; t < nt; t++) {
    const uint32_t *tri = mesh->triangles[t];
    const double *a = mesh->vertices_m[tri[0]], *b = mesh->vertices_m[tri[1]],
                 *c = mesh->vertices_m[tri[2]];
    double u[3], v[3];
    for (int k = 0; k < 3; k++) {
      u[k] = b[k] - a[k];
      v[k] = c[k] - a[k];
    }
    const double cr[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                          u[0] * v[1] - u[1] * v[0]};
    for (int j = 0; j < 3; j++)
      for (int k = 0; k < 3; k++) o->vert_normals[tri[j]][k] += cr[k];
  }
  for (size_t i = 0; i < nv; i++) {
    double *vn = o->vert_normals[i];
    const double len = sqrt(vn[0] * vn[0] + vn[1] * vn[1] + vn[2] * vn[2]);
    for (int k = 0; k < 3; k++) vn[k] = len > 0.0 ? vn[k] / len : 0.0;
  }
  return BALANCE_OK;
}

/* The kept hull planes bucketed by floor(n_x / 2e-12): a plane within 1e-12 of a kept one in
 * every number (the duplicate test) finds it in its own bucket or a neighbouring one, so the test
 * looks at those three buckets instead of every kept plane (faces x planes for a fine hull). */
typedef struct {
  int64_t *key;   /* per slot; with head[slot] == PLANE_NONE the slot is free */
  uint32_t *head; /* first kept plane of the bucket */
  uint32_t *next; /* per kept plane, the next of its bucket */
  size_t mask;
} plane_buckets_t;

enum { PLANE_NONE = UINT32_MAX };

static size_t plane_slot(const plane_buckets_t *b, int64_t key) {
  size_t h = (size_t)(((uint64_t)key * 0x9e3779b97f4a7c15u) >> 17) & b->mask;
  while (b->head[h] != PLANE_NONE && b->key[h] != key) h = (h + 1) & b->mask;
  return h;
}

static int plane_dup(const plane_buckets_t *b, const double (*planes)[4], const double pl[4],
                     int64_t key) {
  for (int64_t k = key - 1; k <= key + 1; k++) {
    for (uint32_t q = b->head[plane_slot(b, k)]; q != PLANE_NONE; q = b->next[q]) {
      const double *r2 = planes[q];
      if (fabs(r2[0] - pl[0]) < 1e-12 && fabs(r2[1] - pl[1]) < 1e-12 &&
          fabs(r2[2] - pl[2]) < 1e-12 && fabs(r2[3] - pl[3]) < 1e-12)
        return 1;
    }
  }
  return 0;
}

/* The hull's planes in the body frame, one per set of coplanar facets (they come out
 * triangulated), in facet order. */
static balance_status_t hull_planes_fill(balance_object_t *o, const double com_m[3]) {
  const model_mesh_t *hull = &o->hull_link;
  const size_t nt = hull->triangle_count;
  plane_buckets_t b = {NULL, NULL, NULL, 0};
  size_t cap = 16;
  while (cap < 2 * nt) cap *= 2;
  b.mask = cap - 1;
  b.key = malloc(cap * sizeof *b.key);
  b.head = malloc(cap * sizeof *b.head);
  b.next = malloc((nt > 0 ? nt : 1) * sizeof *b.next);
  o->hull_planes = malloc((nt > 0 ? nt : 1) * sizeof *o->hull_planes);
  balance_status_t st = BALANCE_OK;
  if (!b.key || !b.head || !b.next || !o->hull_planes || nt >= PLANE_NONE) {
    st = BALANCE_E_NOMEM;
    goto done;
  }
  for (size_t i = 0; i < cap; i++) b.head[i] = PLANE_NONE;
  for (size_t t = 0; t < nt; t++) {
    const double *a = hull->vertices_m[hull->triangles[t][0]];
    const double *p1 = hull->vertices_m[hull->triangles[t][1]];
    const double *c = hull->vertices_m[hull->triangles[t][2]];
    double *pl = o->hull_planes[o->hull_plane_count];
    if (!(cl_tri_normal(a, p1, c, pl) > 0.0)) continue;
    pl[3] = pl[0] * (a[0] - com_m[0]) + pl[1] * (a[1] - com_m[1]) + pl[2] * (a[2] - com_m[2]);
    const int64_t key = (int64_t)floor(pl[0] / 2e-12); /* |n_x| <= 1: within int64 */
    if (plane_dup(&b, (const double(*)[4])o->hull_planes, pl, key)) continue;
    const size_t slot = plane_slot(&b, key);
    if (b.head[slot] == PLANE_NONE) b.key[slot] = key;
    b.next[o->hull_plane_count] = b.head[slot];
    b.head[slot] = (uint32_t)o->hull_plane_count++;
  }
done:
  free(b.key);
  free(b.head);
  free(b.next);
  return st;
}

/* The convex hull (kept in o->hull_link for balance_stable_find) and its planes for object-object
 * contacts, in the body frame: BALANCE_E_MESH when the hull fails, BALANCE_E_NOMEM when its
 * planes cannot be stored. */
static balance_status_t object_hull_planes(balance_object_t *o, const model_mesh_t *mesh,
                                           const double com_m[3]) {
  const model_status_t hs = model_mesh_hull(mesh, &o->hull_link, NULL);
  if (hs != MODEL_OK) return hs == MODEL_E_NOMEM ? BALANCE_E_NOMEM : BALANCE_E_MESH;
  return hull_planes_fill(o, com_m);
}

/* The ODE trimesh, geom and disabled body with the object's mass properties. */
static void object_ode_build(balance_object_t *o, balance_world_t *w, const model_mass_t *mass,
                             size_t nv, size_t nt) {
  o->tm_data = dGeomTriMeshDataCreate();
  dGeomTriMeshDataBuildDouble(o->tm_data, o->tm_vertices, 3 * (int)sizeof(double), (int)nv,
                              o->tm_indices, 3 * (int)nt, 3 * (int)sizeof(dTriIndex));
  o->geom = dCreateTriMesh(0, o->tm_data, 0, 0, 0);
  /* Temporal coherence caches make a collision depend on the previous ones: off, for
   * bit-identical repeats. */
  dGeomTriMeshEnableTC(o->geom, dSphereClass, 0);
  dGeomTriMeshEnableTC(o->geom, dBoxClass, 0);
  dGeomTriMeshEnableTC(o->geom, dCapsuleClass, 0);
  o->body = dBodyCreate(w->ode);
  dBodySetAutoDisableFlag(o->body, 0);
  dMass dm;
  dMassSetZero(&dm);
  const double(*I)[3] = mass->inertia_kg_m2;
  /* CoM at the body origin (ODE aborts otherwise); the geometry is already shifted by -com. */
  dMassSetParameters(&dm, mass->mass_kg, 0.0, 0.0, 0.0, I[0][0], I[1][1], I[2][2],
                     0.5 * (I[0][1] + I[1][0]), 0.5 * (I[0][2] + I[2][0]),
                     0.5 * (I[1][2] + I[2][1]));
  dBodySetMass(o->body, &dm);
  dGeomSetBody(o->geom, o->body);
  dBodyDisable(o->body);
}

/* Everything after validation; o is left for the caller to destroy on failure. */
static balance_status_t object_build(balance_object_t *o, balance_world_t *w,
                                     const model_mesh_t *mesh, const model_mass_t *mass) {
  const size_t nv = mesh->vertex_count, nt = mesh->triangle_count;
  if (model_mesh_copy(mesh, &o->mesh_link) != MODEL_OK) return BALANCE_E_NOMEM;
  uint32_t(*all)[2] = NULL;
  balance_status_t st = object_buffers_alloc(o, nv, nt, &all);
  if (st != BALANCE_OK) return st;
  object_vertices_fill(o, mesh, mass->com_m);
  st = object_edges_build(o, mesh, all);
  if (st != BALANCE_OK) return st;
  st = object_vertex_normals(o, mesh);
  if (st != BALANCE_OK) return st;
  st = object_hull_planes(o, mesh, mass->com_m);
  if (st != BALANCE_OK) return st;
  object_ode_build(o, w, mass, nv, nt);
  return balance_world_add_object_internal(w, o, balance_fast_capacity(o) + 2 * nv);
}

balance_status_t balance_object_create(balance_world_t *w, const model_mesh_t *mesh,
                                       const model_mass_t *mass, balance_object_t **out) {
  if (!out) return BALANCE_E_ARG;
  *out = NULL;
  if (!w || !mesh || !mass) return BALANCE_E_ARG;
  balance_status_t st = mesh_validate(mesh);
  if (st != BALANCE_OK) return st;
  st = mass_validate(mass, mesh);
  if (st != BALANCE_OK) return st;

  balance_object_t *o = calloc(1, sizeof *o);
  if (!o) return BALANCE_E_NOMEM;
  o->world = w;
  o->mass = *mass;
  st = object_build(o, w, mesh, mass);
  if (st != BALANCE_OK) {
    balance_object_destroy_internal(o);
    return st;
  }
  *out = o;
  return BALANCE_OK;
}

static void link_vertex_world(double r[3][3], const double p[3], const double v[3], double out[3]) {
  for (int i = 0; i < 3; i++) out[i] = r[i][0] * v[0] + r[i][1] * v[1] + r[i][2] * v[2] + p[i];
}

double balance_object_penetration_m(const balance_object_t *o, const model_pose_t *pose) {
  const balance_config_t *cfg = &o->world->cfg;
  const double hx = 0.5 * cfg->base_size_m[0], hy = 0.5 * cfg->base_size_m[1];
  const double sz = cfg->base_size_m[2];
  double r[3][3];
  model_quat_to_rot(pose->orientation_wxyz, r);
  double depth = 0.0;
  const model_mesh_t *m = &o->mesh_link;
  for (size_t i = 0; i < m->vertex_count; i++) {
    double w[3];
    link_vertex_world(r, pose->position_m, m->vertices_m[i], w);
    if (fabs(w[0]) < hx && fabs(w[1]) < hy && w[2] < 0.0 && w[2] > -sz) {
      double d = fmin(fmin(-w[2], w[2] + sz), fmin(hx - fabs(w[0]), hy - fabs(w[1])));
      depth = fmax(depth, d);
    }
  }
  for (size_t e = 0; e < o->edge_count; e++) {
    /* Only an edge with an end below the top can cross a plane below it: test z first. */
    const double *va = m->vertices_m[o->edges[e][0]], *vb = m->vertices_m[o->edges[e][1]];
    if (r[2][0] * va[0] + r[2][1] * va[1] + r[2][2] * va[2] + pose->position_m[2] >= 0.0 &&
        r[2][0] * vb[0] + r[2][1] * vb[1] + r[2][2] * vb[2] + pose->position_m[2] >= 0.0)
      continue;
    double a[3], b[3];
    link_vertex_world(r, pose->position_m, m->vertices_m[o->edges[e][0]], a);
    link_vertex_world(r, pose->position_m, m->vertices_m[o->edges[e][1]], b);
    for (int axis = 0; axis < 2; axis++) {
      const double h = axis == 0 ? hx : hy, ho = axis == 0 ? hy : hx;
      for (int sgn = -1; sgn <= 1; sgn += 2) {
        const double plane = sgn * h;
        const double da = a[axis] - plane, db = b[axis] - plane;
        if (!(da * db < 0.0)) continue;
        const double t = da / (da - db);
        const double z = a[2] + t * (b[2] - a[2]);
        const double o2 = a[1 - axis] + t * (b[1 - axis] - a[1 - axis]);
        if (fabs(o2) <= ho && z < 0.0 && z > -sz) depth = fmax(depth, fmin(-z, z + sz));
      }
    }
  }
  return depth;
}

balance_status_t balance_object_place(balance_object_t *o, const model_pose_t *pose_link) {
  if (!o || !pose_link) return BALANCE_E_ARG;
  model_pose_t p;
  balance_status_t st = balance_pose_check(pose_link, &p);
  if (st != BALANCE_OK) return st;
  if (balance_object_penetration_m(o, &p) > BALANCE_MAX_START_DEPTH_M) return BALANCE_E_POSE;
  double r[3][3], c[3];
  model_quat_to_rot(p.orientation_wxyz, r);
  link_vertex_world(r, p.position_m, o->mass.com_m, c);
  dBodySetPosition(o->body, c[0], c[1], c[2]);
  dQuaternion q = {p.orientation_wxyz[0], p.orientation_wxyz[1], p.orientation_wxyz[2],
                   p.orientation_wxyz[3]};
  dBodySetQuaternion(o->body, q);
  dBodySetLinearVel(o->body, 0.0, 0.0, 0.0);
  dBodySetAngularVel(o->body, 0.0, 0.0, 0.0);
  dBodySetForce(o->body, 0.0, 0.0, 0.0);
  dBodySetTorque(o->body, 0.0, 0.0, 0.0);
  dBodyEnable(o->body);
  o->placed = 1;
  o->world->pair_prev_count = 0;
  o->fast.valid = 0;
  o->fast.sel_valid = 0;
  return BALANCE_OK;
}

void balance_object_remove(balance_object_t *o) {
  if (!o) return;
  dBodyDisable(o->body);
  o->placed = 0;
  o->world->pair_prev_count = 0;
  o->fast.valid = 0;
  o->fast.sel_valid = 0;
}

int balance_object_is_placed(const balance_object_t *o) { return o ? o->placed : 0; }

void balance_object_pose_get(const balance_object_t *o, model_pose_t *out) {
  const dReal *q = dBodyGetQuaternion(o->body), *c = dBodyGetPosition(o->body);
  double qq[4] = {q[0], q[1], q[2], q[3]}, r[3][3];
  model_quat_to_rot(qq, r);
  for (int i = 0; i < 4; i++) out->orientation_wxyz[i] = qq[i];
  for (int i = 0; i < 3; i++)
    out->position_m[i] = c[i] - (r[i][0] * o->mass.com_m[0] + r[i][1] * o->mass.com_m[1] +
                                 r[i][2] * o->mass.com_m[2]);
}

void balance_object_com_get(const balance_object_t *o, double com_world_m[3]) {
  const dReal *c = dBodyGetPosition(o->body);
  for (int i = 0; i < 3; i++) com_world_m[i] = c[i];
}

void balance_object_velocity_get(const balance_object_t *o, double lin[3], double ang[3]) {
  const dReal *v = dBodyGetLinearVel(o->body), *a = dBodyGetAngularVel(o->body);
  for (int i = 0; i < 3; i++) {
    if (lin) lin[i] = v[i];
    if (ang) ang[i] = a[i];
  }
}

double balance_object_bottom_z(const balance_object_t *o, const double q_in[4]) {
  return o ? model_mesh_bottom_z(&o->mesh_link, q_in) : NAN;
}

balance_status_t balance_pose_over_edge(const balance_world_t *w, const balance_object_t *o,
                                        const double q_in[4], model_edge_t edge,
                                        const double point_link_m[3], double along_m,
                                        double touch_depth_m, model_pose_t *out) {
  if (!w || !o) return BALANCE_E_ARG;
  return balance_status_from_model(model_pose_over_edge(
      &o->mesh_link, w->cfg.base_size_m, q_in, edge, point_link_m, along_m, touch_depth_m, out));
}
