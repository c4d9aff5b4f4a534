/* hull.c - 3-D convex hull by quickhull with conflict lists.
 *
 * Points are centred on their bounding box and scaled by a power of two into [-1, 1]. Which side
 * of a face a point lies on is decided exactly (model_orient3d, orient.h), so the faces visible
 * from the eye are exactly those whose plane it is strictly above: for a convex polytope that set
 * is a topological disk (the beneath-beyond theorem), found whole by a depth-first walk from any
 * of its faces, and its boundary, the horizon, is one loop. The cone over the horizon keeps the
 * surface the exact boundary of the convex hull of the points added so far. A point joins a
 * conflict list only when it is more than tol = 1e-10 * (bbox diagonal) above the face (and
 * exactly above it), so coplanar, duplicate and interior points are discarded instead of making
 * slivers; a discarded point is within about tol of the hull, which only grows. A point outside a
 * deleted face is either outside one of the new cone faces or inside the new hull (the points of
 * the cone above a visible face all lie between the eye and the old surface), so conflicts are
 * only redistributed to new faces. Each iteration turns one point into a hull vertex, so n
 * iterations bound the loop. The horizon is checked to be one loop and the result to hold every
 * input point below every face; a failure (possible only through a bug) is MODEL_E_HULL. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "comlearn/math3d.h"
#include "model_internal.h"
#include "orient.h"

#define NONE UINT32_MAX

typedef struct {
  uint32_t v[3];     /* counter-clockwise seen from outside */
  uint32_t nb[3];    /* face across the edge v[i] -> v[i+1] */
  double n[3];       /* unit outward normal */
  double d;          /* plane: n . x = d */
  uint32_t conflict; /* head of this face's outside-point list */
  uint8_t alive;
  uint8_t visible;
} face_t;

typedef struct {
  const double (*p)[3]; /* centred points */
  size_t n;
  double tol;
  face_t *faces;
  size_t face_count, face_cap;
  uint32_t *next;  /* conflict list links, per point */
  uint32_t *stack; /* faces that may have conflicts */
  size_t stack_count, stack_cap;
} hull_t;

static int grow(void **arr, size_t *cap, size_t need, size_t elem) {
  if (need <= *cap) {
    return 1;
  }
  size_t cap2 = *cap > 0 ? *cap : 64;
  while (cap2 < need) {
    cap2 *= 2;
  }
  void *p = realloc(*arr, cap2 * elem);
  if (p == NULL) {
    return 0;
  }
  *arr = p;
  *cap = cap2;
  return 1;
}

static double face_dist(const hull_t *h, const face_t *f, uint32_t i) {
  const double *q = h->p[i];
  return f->n[0] * q[0] + f->n[1] * q[1] + f->n[2] * q[2] - f->d;
}

/* (pb - pa) x (pc - pa) into n; returns its length. A sliver (the sine of its angle at pa below
 * 1e-6) loses the direction to cancellation in the double cross product: it takes the exact one,
 * rounded. */
static double tri_cross(const double *pa, const double *pb, const double *pc, double n[3]) {
  const double u[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
  const double w[3] = {pc[0] - pa[0], pc[1] - pa[1], pc[2] - pa[2]};
  n[0] = u[1] * w[2] - u[2] * w[1];
  n[1] = u[2] * w[0] - u[0] * w[2];
  n[2] = u[0] * w[1] - u[1] * w[0];
  const double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (len > 1e-6 * sqrt((u[0] * u[0] + u[1] * u[1] + u[2] * u[2]) *
                        (w[0] * w[0] + w[1] * w[1] + w[2] * w[2])))
    return len;
  model_tri_cross(pa, pb, pc, n);
  return sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

/* New face a, b, c; plane through its centroid. Returns its index or NONE (no memory). */
static uint32_t face_new(hull_t *h, uint32_t a, uint32_t b, uint32_t c) {
  if (h->face_count >= UINT32_MAX - 1 ||
      !grow((void **)&h->faces, &h->face_cap, h->face_count + 1, sizeof *h->faces)) {
    return NONE;
  }
  face_t *f = &h->faces[h->face_count];
  memset(f, 0, sizeof *f);
  f->v[0] = a;
  f->v[1] = b;
  f->v[2] = c;
  f->nb[0] = f->nb[1] = f->nb[2] = NONE;
  f->conflict = NONE;
  f->alive = 1;
  const double *pa = h->p[a], *pb = h->p[b], *pc = h->p[c];
  double n[3];
  const double len = tri_cross(pa, pb, pc, n);
  if (len > 0.0) {
    for (int k = 0; k < 3; ++k) {
      f->n[k] = n[k] / len;
    }
  }
  f->d = (f->n[0] * (pa[0] + pb[0] + pc[0]) + f->n[1] * (pa[1] + pb[1] + pc[1]) +
          f->n[2] * (pa[2] + pb[2] + pc[2])) /
         3.0;
  return (uint32_t)h->face_count++;
}

/* Whether point i lies strictly above face f's plane, decided exactly. */
static int point_above(const hull_t *h, const face_t *f, uint32_t i) {
  return model_orient3d(h->p[f->v[0]], h->p[f->v[1]], h->p[f->v[2]], h->p[i]) > 0;
}

static int push_face(hull_t *h, uint32_t f) {
  if (!grow((void **)&h->stack, &h->stack_cap, h->stack_count + 1, sizeof *h->stack)) {
    return 0;
  }
  h->stack[h->stack_count++] = f;
  return 1;
}

/* Give point i to the first face in faces[] it is outside of; 0 when it is inside all. */
static int assign_point(hull_t *h, uint32_t i, const uint32_t *faces, size_t count) {
  for (size_t k = 0; k < count; ++k) {
    face_t *f = &h->faces[faces[k]];
    if (face_dist(h, f, i) > h->tol && point_above(h, f, i)) {
      h->next[i] = f->conflict;
      f->conflict = i;
      return 1;
    }
  }
  return 0;
}

/* Index of the edge of face g that runs b -> a (the twin of a -> b), or -1. */
static int twin_edge(const face_t *g, uint32_t a, uint32_t b) {
  for (int k = 0; k < 3; ++k) {
    if (g->v[k] == b && g->v[(k + 1) % 3] == a) {
      return k;
    }
  }
  return -1;
}

static model_status_t initial_simplex(hull_t *h, model_error_t *err, uint32_t tet[4]) {
  /* Two points farthest apart along an axis. */
  uint32_t lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  for (uint32_t i = 0; i < h->n; ++i) {
    for (int k = 0; k < 3; ++k) {
      if (h->p[i][k] < h->p[lo[k]][k]) {
        lo[k] = i;
      }
      if (h->p[i][k] > h->p[hi[k]][k]) {
        hi[k] = i;
      }
    }
  }
  int axis = 0;
  for (int k = 1; k < 3; ++k) {
    if (h->p[hi[k]][k] - h->p[lo[k]][k] > h->p[hi[axis]][axis] - h->p[lo[axis]][axis]) {
      axis = k;
    }
  }
  uint32_t a = lo[axis], b = hi[axis];
  if (!(h->p[b][axis] - h->p[a][axis] > h->tol)) {
    return model_fail(err, MODEL_E_HULL, "convex hull: all %zu points coincide", h->n);
  }
  /* Farthest from the line a-b. */
  const double *pa = h->p[a], *pb = h->p[b];
  double dir[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
  double dlen = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
  uint32_t c = NONE;
  double best = 0.0;
  for (uint32_t i = 0; i < h->n; ++i) {
    const double *q = h->p[i];
    double r[3] = {q[0] - pa[0], q[1] - pa[1], q[2] - pa[2]};
    double x[3] = {r[1] * dir[2] - r[2] * dir[1], r[2] * dir[0] - r[0] * dir[2],
                   r[0] * dir[1] - r[1] * dir[0]};
    double dist = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]) / dlen;
    if (dist > best) {
      best = dist;
      c = i;
    }
  }
  if (c == NONE || !(best > h->tol)) {
    return model_fail(err, MODEL_E_HULL, "convex hull: all %zu points are collinear", h->n);
  }
  /* Farthest from the plane a-b-c. */
  const double *pc = h->p[c];
  double n[3];
  const double nlen = tri_cross(pa, pb, pc, n);
  uint32_t d = NONE;
  best = 0.0;
  for (uint32_t i = 0; i < h->n; ++i) {
    const double *q = h->p[i];
    double s = (n[0] * (q[0] - pa[0]) + n[1] * (q[1] - pa[1]) + n[2] * (q[2] - pa[2])) / nlen;
    if (fabs(s) > best) {
      best = fabs(s);
      d = i;
    }
  }
  const int side = d == NONE ? 0 : model_orient3d(pa, pb, pc, h->p[d]);
  if (d == NONE || !(best > h->tol) || side == 0) {
    return model_fail(err, MODEL_E_HULL, "convex hull: all %zu points are coplanar", h->n);
  }
  /* Orient a-b-c away from d (exactly: the walk relies on it). */
  if (side > 0) {
    uint32_t t = b;
    b = c;
    c = t;
  }
  tet[0] = a;
  tet[1] = b;
  tet[2] = c;
  tet[3] = d;
  return MODEL_OK;
}

/* a-b-c (tet[0..2]) faces away from d (tet[3]); the other three faces wind to match. Links the
 * four faces, gives them the other points and stacks those with conflicts. */
static model_status_t simplex_start(hull_t *h, const uint32_t tet[4]) {
  const uint32_t a = tet[0], b = tet[1], c = tet[2], d = tet[3];
  uint32_t f0 = face_new(h, a, b, c);
  uint32_t f1 = face_new(h, a, d, b);
  uint32_t f2 = face_new(h, b, d, c);
  uint32_t f3 = face_new(h, c, d, a);
  if (f0 == NONE || f1 == NONE || f2 == NONE || f3 == NONE) {
    return MODEL_E_NOMEM;
  }
  uint32_t first[4] = {f0, f1, f2, f3};
  for (int i = 0; i < 4; ++i) {
    face_t *f = &h->faces[first[i]];
    for (int k = 0; k < 3; ++k) {
      for (int j = 0; j < 4; ++j) {
        if (j != i && twin_edge(&h->faces[first[j]], f->v[k], f->v[(k + 1) % 3]) >= 0) {
          f->nb[k] = first[j];
        }
      }
    }
  }
  for (uint32_t i = 0; i < h->n; ++i) {
    if (i != a && i != b && i != c && i != d) {
      (void)assign_point(h, i, first, 4);
    }
  }
  for (int i = 0; i < 4; ++i) {
    if (h->faces[first[i]].conflict != NONE && !push_face(h, first[i])) {
      return MODEL_E_NOMEM;
    }
  }
  return MODEL_OK;
}

/* One face of the depth-first walk: its edges first, first + 1, ... (count of them), i done. */
typedef struct {
  uint32_t face;
  uint8_t first, count, i;
} frame_t;

/* Work arrays of one iteration, reused by every iteration (counts reset per iteration). */
typedef struct {
  frame_t *frames;
  size_t frame_count, frame_cap;
  uint32_t *visible; /* faces visible from the eye */
  size_t visible_count, visible_cap;
  uint32_t *horizon_face; /* horizon edge k is edge horizon_edge[k] of horizon_face[k] */
  uint8_t *horizon_edge;
  size_t horizon_count, horizon_cap, horizon_edge_cap;
  uint32_t *new_faces; /* the cone, new_faces[k] on horizon edge k */
  size_t new_cap;
} work_t;

static void work_free(work_t *w) {
  free(w->frames);
  free(w->visible);
  free(w->horizon_face);
  free(w->horizon_edge);
  free(w->new_faces);
}

/* The eye: the farthest outside point of face fi. */
static uint32_t eye_find(const hull_t *h, uint32_t fi) {
  uint32_t eye = NONE;
  double far = -1.0;
  for (uint32_t q = h->faces[fi].conflict; q != NONE; q = h->next[q]) {
    double dist = face_dist(h, &h->faces[fi], q);
    if (dist > far) {
      far = dist;
      eye = q;
    }
  }
  return eye;
}

/* Depth-first over the faces visible from the eye, starting at fi; edges to invisible faces form
 * the horizon, in loop order. */
static model_status_t visible_walk(hull_t *h, work_t *w, uint32_t fi, uint32_t eye,
                                   model_error_t *err) {
  w->visible_count = w->horizon_count = w->frame_count = 0;
  if (!grow((void **)&w->frames, &w->frame_cap, 1, sizeof *w->frames) ||
      !grow((void **)&w->visible, &w->visible_cap, 1, sizeof *w->visible)) {
    return MODEL_E_NOMEM;
  }
  h->faces[fi].visible = 1;
  w->visible[w->visible_count++] = fi;
  w->frames[w->frame_count++] = (frame_t){fi, 0, 3, 0};
  while (w->frame_count > 0) {
    frame_t *fr = &w->frames[w->frame_count - 1];
    if (fr->i == fr->count) {
      --w->frame_count;
      continue;
    }
    int e = (fr->first + fr->i) % 3;
    fr->i++;
    const face_t *f = &h->faces[fr->face];
    uint32_t g = f->nb[e];
    if (g == NONE) {
      return model_fail(err, MODEL_E_HULL, "convex hull: broken face adjacency");
    }
    if (h->faces[g].visible) {
      continue;
    }
    if (point_above(h, &h->faces[g], eye)) {
      int j = twin_edge(&h->faces[g], f->v[e], f->v[(e + 1) % 3]);
      if (j < 0) {
        return model_fail(err, MODEL_E_HULL, "convex hull: broken face adjacency");
      }
      if (!grow((void **)&w->frames, &w->frame_cap, w->frame_count + 1, sizeof *w->frames) ||
          !grow((void **)&w->visible, &w->visible_cap, w->visible_count + 1, sizeof *w->visible)) {
        return MODEL_E_NOMEM;
      }
      h->faces[g].visible = 1;
      w->visible[w->visible_count++] = g;
      w->frames[w->frame_count++] = (frame_t){g, (uint8_t)((j + 1) % 3), 2, 0};
    } else {
      if (!grow((void **)&w->horizon_face, &w->horizon_cap, w->horizon_count + 1,
                sizeof *w->horizon_face) ||
          !grow((void **)&w->horizon_edge, &w->horizon_edge_cap, w->horizon_count + 1,
                sizeof *w->horizon_edge)) {
        return MODEL_E_NOMEM;
      }
      w->horizon_face[w->horizon_count] = fr->face;
      w->horizon_edge[w->horizon_count] = (uint8_t)e;
      ++w->horizon_count;
    }
  }
  return MODEL_OK;
}

/* The horizon must be one closed loop. */
static model_status_t horizon_check(const hull_t *h, const work_t *w, model_error_t *err) {
  const size_t nhor = w->horizon_count;
  int loop_ok = nhor >= 3;
  for (size_t k = 0; k < nhor && loop_ok; ++k) {
    const face_t *f = &h->faces[w->horizon_face[k]];
    const face_t *g = &h->faces[w->horizon_face[(k + 1) % nhor]];
    loop_ok = f->v[(w->horizon_edge[k] + 1) % 3] == g->v[w->horizon_edge[(k + 1) % nhor]];
  }
  if (!loop_ok) {
    return model_fail(err, MODEL_E_HULL,
                      "convex hull: numerical failure (horizon of %zu edges is not one loop)",
                      nhor);
  }
  return MODEL_OK;
}

/* The cone of new faces from the horizon to the eye, linked to the faces beyond the horizon and
 * to each other. */
static model_status_t cone_build(hull_t *h, work_t *w, uint32_t eye, model_error_t *err) {
  const size_t nhor = w->horizon_count;
  if (!grow((void **)&w->new_faces, &w->new_cap, nhor, sizeof *w->new_faces)) {
    return MODEL_E_NOMEM;
  }
  for (size_t k = 0; k < nhor; ++k) {
    const face_t *f = &h->faces[w->horizon_face[k]];
    int e = w->horizon_edge[k];
    uint32_t va = f->v[e], vb = f->v[(e + 1) % 3], outer = f->nb[e];
    uint32_t nf = face_new(h, va, vb, eye); /* may move h->faces */
    if (nf == NONE) {
      return MODEL_E_NOMEM;
    }
    w->new_faces[k] = nf;
    h->faces[nf].nb[0] = outer;
    int j = twin_edge(&h->faces[outer], va, vb);
    if (j < 0) {
      return model_fail(err, MODEL_E_HULL, "convex hull: broken face adjacency");
    }
    h->faces[outer].nb[j] = nf;
  }
  for (size_t k = 0; k < nhor; ++k) {
    h->faces[w->new_faces[k]].nb[1] = w->new_faces[(k + 1) % nhor];
    h->faces[w->new_faces[k]].nb[2] = w->new_faces[(k + nhor - 1) % nhor];
  }
  return MODEL_OK;
}

/* Retire the visible faces; their points go to the new faces or are inside. New faces with
 * conflicts are stacked. */
static model_status_t visible_retire(hull_t *h, const work_t *w, uint32_t eye) {
  const size_t nhor = w->horizon_count;
  for (size_t k = 0; k < w->visible_count; ++k) {
    face_t *f = &h->faces[w->visible[k]];
    f->alive = 0;
    uint32_t q = f->conflict;
    f->conflict = NONE;
    while (q != NONE) {
      uint32_t nq = h->next[q];
      if (q != eye) {
        (void)assign_point(h, q, w->new_faces, nhor);
      }
      q = nq;
    }
  }
  for (size_t k = 0; k < nhor; ++k) {
    if (h->faces[w->new_faces[k]].conflict != NONE && !push_face(h, w->new_faces[k])) {
      return MODEL_E_NOMEM;
    }
  }
  return MODEL_OK;
}

/* One quickhull iteration: the farthest outside point of face fi becomes a hull vertex. */
static model_status_t point_add(hull_t *h, work_t *w, uint32_t fi, model_error_t *err) {
  const uint32_t eye = eye_find(h, fi);
  model_status_t st = visible_walk(h, w, fi, eye, err);
  if (st == MODEL_OK) {
    st = horizon_check(h, w, err);
  }
  if (st == MODEL_OK) {
    st = cone_build(h, w, eye, err);
  }
  if (st == MODEL_OK) {
    st = visible_retire(h, w, eye);
  }
  return st;
}

static model_status_t build(hull_t *h, model_error_t *err) {
  uint32_t tet[4] = {0, 0, 0, 0};
  model_status_t st = initial_simplex(h, err, tet);
  if (st == MODEL_OK) {
    st = simplex_start(h, tet);
  }
  if (st != MODEL_OK) {
    return st;
  }
  work_t w;
  memset(&w, 0, sizeof w);
  size_t iterations = 0;
  while (h->stack_count > 0 && st == MODEL_OK) {
    uint32_t fi = h->stack[--h->stack_count];
    if (!h->faces[fi].alive || h->faces[fi].conflict == NONE) {
      continue;
    }
    if (++iterations > h->n) {
      st = model_fail(err, MODEL_E_HULL, "convex hull: iteration cap (%zu) reached", h->n);
    } else {
      st = point_add(h, &w, fi, err);
    }
  }
  work_free(&w);
  return st;
}

/* Bounding-box center of the n >= 1 vertices and its squared diagonal; MODEL_E_NONFINITE at the
 * first vertex that is not finite. */
static model_status_t points_bounds(const model_mesh_t *mesh, size_t n, double center[3],
                                    double *diag2, model_error_t *err) {
  double lo[3], hi[3];
  memcpy(lo, mesh->vertices_m[0], sizeof lo);
  memcpy(hi, mesh->vertices_m[0], sizeof hi);
  for (size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) {
      double v = mesh->vertices_m[i][k];
      if (!isfinite(v)) {
        return model_fail(err, MODEL_E_NONFINITE, "convex hull: vertex %zu is not finite", i);
      }
      lo[k] = fmin(lo[k], v);
      hi[k] = fmax(hi[k], v);
    }
  }
  *diag2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    center[k] = 0.5 * (lo[k] + hi[k]);
    *diag2 += (hi[k] - lo[k]) * (hi[k] - lo[k]);
  }
  return MODEL_OK;
}

/* The working points p: the vertices centred on center, times the power of two that brings them
 * into [-1, 1] (exact, so every decision is the one the centred points would give), with
 * coordinates below 2^-250 flushed to zero (so model_orient3d's products cannot underflow).
 * Returns the tolerance, 1e-10 x the bounding box diagonal, in those units. */
static double points_place(const model_mesh_t *mesh, const double center[3], double diag2,
                           double (*p)[3]) {
  const size_t n = mesh->vertex_count;
  double big = 0.0;
  for (size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) {
      p[i][k] = mesh->vertices_m[i][k] - center[k];
      big = fmax(big, fabs(p[i][k]));
    }
  }
  int e = 0;
  (void)frexp(big, &e); /* big = f 2^e, f in [0.5, 1) */
  const double scale = ldexp(1.0, -e);
  for (size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) {
      const double v = p[i][k] * scale;
      p[i][k] = fabs(v) < 0x1p-250 ? 0.0 : v;
    }
  }
  return fmax(1e-10 * sqrt(diag2) * scale, 8.0 * DBL_MIN);
}

/* The live faces as a mesh of the input's (uncentred) vertices they use, numbered in input order.
 * newindex: h->n entries, all NONE on entry. */
static model_status_t hull_mesh_write(const hull_t *h, const model_mesh_t *mesh, uint32_t *newindex,
                                      model_mesh_t *hull) {
  size_t nf = 0, nv = 0;
  for (size_t f = 0; f < h->face_count; ++f) {
    if (h->faces[f].alive) {
      ++nf;
      for (int k = 0; k < 3; ++k) {
        if (newindex[h->faces[f].v[k]] == NONE) {
          newindex[h->faces[f].v[k]] = 0; /* mark; numbered below in input order */
        }
      }
    }
  }
  for (size_t i = 0; i < h->n; ++i) {
    if (newindex[i] == 0) {
      newindex[i] = (uint32_t)nv++;
    }
  }
  model_status_t st = model_mesh_alloc(hull, nv, nf);
  if (st != MODEL_OK) {
    return st;
  }
  for (size_t i = 0; i < h->n; ++i) {
    if (newindex[i] != NONE) {
      memcpy(hull->vertices_m[newindex[i]], mesh->vertices_m[i], sizeof hull->vertices_m[0]);
    }
  }
  size_t t = 0;
  for (size_t f = 0; f < h->face_count; ++f) {
    if (h->faces[f].alive) {
      for (int k = 0; k < 3; ++k) {
        hull->triangles[t][k] = newindex[h->faces[f].v[k]];
      }
      ++t;
    }
  }
  return MODEL_OK;
}

/* ---- the final check's search structure -------------------------------------------------- */

enum { TREE_LEAF = 16 };

typedef struct {
  double lo[3], hi[3];
} box_t;

/* The points in Morton order, cut into leaves of TREE_LEAF points; a complete binary tree over
 * the leaves (node k has the children 2k and 2k + 1, leaf j is node first_leaf + j, nodes past
 * the last leaf have empty boxes) with each node's bounding box. */
typedef struct {
  uint32_t *order; /* the tree's points, in Morton order */
  box_t *box;
  size_t count, leaves, first_leaf;
} ptree_t;

typedef struct {
  uint64_t key;
  uint32_t index;
} morton_t;

static int cmp_morton(const void *pa, const void *pb) {
  const morton_t *a = pa, *b = pb;
  if (a->key != b->key) {
    return a->key < b->key ? -1 : 1;
  }
  return a->index < b->index ? -1 : (a->index > b->index);
}

/* The low 21 bits of v, two zero bits after each. */
static uint64_t spread3(uint64_t v) {
  uint64_t x = v & 0x1fffffu;
  x = (x | x << 32) & 0x1f00000000ffffu;
  x = (x | x << 16) & 0x1f0000ff0000ffu;
  x = (x | x << 8) & 0x100f00f00f00f00fu;
  x = (x | x << 4) & 0x10c30c30c30c30c3u;
  x = (x | x << 2) & 0x1249249249249249u;
  return x;
}

/* Sort the points idx[0 .. count) (in [-1, 1]) along a Morton curve, in place: neighbours in
 * order are near in space. */
static model_status_t ptree_order(const hull_t *h, uint32_t *idx, size_t count) {
  morton_t *m = malloc((count > 0 ? count : 1) * sizeof *m);
  if (m == NULL) {
    return MODEL_E_NOMEM;
  }
  for (size_t i = 0; i < count; ++i) {
    uint64_t key = 0;
    for (int k = 0; k < 3; ++k) {
      const double q = fmin(fmax((h->p[idx[i]][k] + 1.0) * 1048575.5, 0.0), 2097151.0);
      key |= spread3((uint64_t)q) << k;
    }
    m[i] = (morton_t){key, idx[i]};
  }
  qsort(m, count, sizeof *m, cmp_morton);
  for (size_t i = 0; i < count; ++i) {
    idx[i] = m[i].index;
  }
  free(m);
  return MODEL_OK;
}

/* The tree over the points idx[0 .. count), which it takes (and ptree_free frees). */
static model_status_t ptree_build(const hull_t *h, uint32_t *idx, size_t count, ptree_t *t) {
  memset(t, 0, sizeof *t);
  t->order = idx;
  t->count = count;
  t->leaves = (count + TREE_LEAF - 1) / TREE_LEAF;
  t->first_leaf = 1;
  while (t->first_leaf < t->leaves) {
    t->first_leaf *= 2;
  }
  t->box = malloc(2 * t->first_leaf * sizeof *t->box);
  if (t->box == NULL || ptree_order(h, idx, count) != MODEL_OK) {
    return MODEL_E_NOMEM;
  }
  for (size_t k = 0; k < 2 * t->first_leaf; ++k) {
    for (int c = 0; c < 3; ++c) {
      t->box[k].lo[c] = HUGE_VAL;
      t->box[k].hi[c] = -HUGE_VAL;
    }
  }
  for (size_t i = 0; i < count; ++i) {
    box_t *b = &t->box[t->first_leaf + i / TREE_LEAF];
    for (int c = 0; c < 3; ++c) {
      b->lo[c] = fmin(b->lo[c], h->p[t->order[i]][c]);
      b->hi[c] = fmax(b->hi[c], h->p[t->order[i]][c]);
    }
  }
  for (size_t k = t->first_leaf - 1; k >= 1; --k) {
    for (int c = 0; c < 3; ++c) {
      t->box[k].lo[c] = fmin(t->box[2 * k].lo[c], t->box[2 * k + 1].lo[c]);
      t->box[k].hi[c] = fmax(t->box[2 * k].hi[c], t->box[2 * k + 1].hi[c]);
    }
  }
  return MODEL_OK;
}

static void ptree_free(ptree_t *t) {
  free(t->order);
  free(t->box);
}

/* Whether some point of the tree lies more than slack above face f: what testing each of them
 * finds. A box is skipped when its highest corner is at most slack / 2 above the plane; the
 * rounding of that bound and of a point's distance (~1e-15 for points in [-1, 1]) is far below
 * slack / 2. */
static int ptree_above(const hull_t *h, const ptree_t *t, const face_t *f, double slack) {
  size_t stack[64]; /* depth-first: at most one pending sibling per level, < 40 levels */
  size_t top = 0;
  stack[top++] = 1;
  while (top > 0) {
    const size_t k = stack[--top];
    const box_t *b = &t->box[k];
    double m = -f->d;
    for (int c = 0; c < 3; ++c) {
      m += f->n[c] > 0.0 ? f->n[c] * b->hi[c] : f->n[c] < 0.0 ? f->n[c] * b->lo[c] : 0.0;
    }
    if (!(m > 0.5 * slack)) {
      continue; /* also an empty box: -inf */
    }
    if (k < t->first_leaf) {
      stack[top++] = 2 * k;
      stack[top++] = 2 * k + 1;
      continue;
    }
    const size_t lo = (k - t->first_leaf) * TREE_LEAF;
    const size_t hi = lo + TREE_LEAF < t->count ? lo + TREE_LEAF : t->count;
    for (size_t i = lo; i < hi; ++i) {
      if (face_dist(h, f, t->order[i]) > slack) {
        return 1;
      }
    }
  }
  return 0;
}

/* Whether an input point that is not a hull vertex (newindex NONE) lies above a live face by
 * more than slack. */
static model_status_t points_outside(const hull_t *h, const uint32_t *newindex, double slack,
                                     int *outside) {
  *outside = 0;
  uint32_t *idx = malloc(h->n * sizeof *idx);
  if (idx == NULL) {
    return MODEL_E_NOMEM;
  }
  size_t count = 0;
  for (uint32_t i = 0; i < h->n; ++i) {
    if (newindex[i] == NONE) {
      idx[count++] = i;
    }
  }
  if (count == 0) {
    free(idx);
    return MODEL_OK;
  }
  ptree_t t;
  model_status_t st = ptree_build(h, idx, count, &t);
  for (size_t f = 0; st == MODEL_OK && f < h->face_count && !*outside; ++f) {
    if (h->faces[f].alive) {
      *outside = ptree_above(h, &t, &h->faces[f], slack);
    }
  }
  ptree_free(&t);
  return st;
}

/* Whether the live faces, every edge twinned, fail to bound a convex polytope: an edge whose far
 * face's third vertex lies more than slack above the near face (reflex), a surface that is not one
 * sphere (connected, V - E + F = 2), or a vertex whose faces do not go once around it (seen from
 * the vertices' mean, which lies below every face of a convex surface, each face must face away
 * from it and their corners' angles must sum to one turn: a star that wraps twice sums to two). A
 * closed, connected surface, convex at every edge and vertex, bounds a convex body, so its own
 * vertices need no test against the other faces. newindex numbers the hull vertices 0 .. nv - 1
 * (NONE for the other points). */
static model_status_t surface_not_convex(const hull_t *h, const uint32_t *newindex, size_t nv,
                                         double slack, const char **why) {
  size_t live = 0;
  for (size_t f = 0; f < h->face_count; ++f) {
    live += h->faces[f].alive;
  }
  if (2 * nv != live + 4) {
    *why = "the faces do not form one sphere";
    return MODEL_OK;
  }
  double *turn = calloc(nv, sizeof *turn);
  uint32_t *queue = malloc(live * sizeof *queue);
  uint8_t *seen = calloc(h->face_count, 1);
  if (turn == NULL || queue == NULL || seen == NULL) {
    free(turn), free(queue), free(seen);
    return MODEL_E_NOMEM;
  }
  double center[3] = {0.0, 0.0, 0.0}; /* the vertices' mean: inside, below every face */
  for (uint32_t i = 0; i < h->n; ++i) {
    for (int c = 0; c < 3 && newindex[i] != NONE; ++c) {
      center[c] += h->p[i][c] / (double)nv;
    }
  }
  size_t first = 0;
  while (!h->faces[first].alive) {
    ++first;
  }
  size_t head = 0, tail = 0;
  queue[tail++] = (uint32_t)first;
  seen[first] = 1;
  while (head < tail && *why == NULL) {
    const face_t *f = &h->faces[queue[head++]];
    for (int k = 0; k < 3 && *why == NULL; ++k) {
      const face_t *g = &h->faces[f->nb[k]];
      const int j = twin_edge(g, f->v[k], f->v[(k + 1) % 3]);
      if (face_dist(h, f, g->v[(j + 2) % 3]) > slack) {
        *why = "a reflex edge";
      } else if (!seen[f->nb[k]]) {
        seen[f->nb[k]] = 1;
        queue[tail++] = f->nb[k];
      }
    }
  }
  if (*why == NULL && tail != live) {
    *why = "the faces do not form one sphere";
  }
  for (size_t f = 0; f < h->face_count && *why == NULL; ++f) {
    const face_t *fa = &h->faces[f];
    for (int k = 0; k < 3 && fa->alive && *why == NULL; ++k) {
      const uint32_t v = fa->v[k];
      const double *o = h->p[v], *pb = h->p[fa->v[(k + 1) % 3]], *pc = h->p[fa->v[(k + 2) % 3]];
      const double e1[3] = {pb[0] - o[0], pb[1] - o[1], pb[2] - o[2]};
      const double e2[3] = {pc[0] - o[0], pc[1] - o[1], pc[2] - o[2]};
      const double m[3] = {o[0] - center[0], o[1] - center[1], o[2] - center[2]};
      const double x[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                           e1[0] * e2[1] - e1[1] * e2[0]};
      const double mm = m[0] * m[0] + m[1] * m[1] + m[2] * m[2];
      const double d1 = e1[0] * m[0] + e1[1] * m[1] + e1[2] * m[2];
      const double d2 = e2[0] * m[0] + e2[1] * m[1] + e2[2] * m[2];
      if (!(fa->n[0] * m[0] + fa->n[1] * m[1] + fa->n[2] * m[2] > 0.0)) {
        *why = "a vertex whose faces do not go once around it";
      }
      /* the corner's angle seen along m: sine and cosine, both times |m|^2 |e1| |e2|-ish */
      turn[newindex[v]] += atan2(sqrt(mm) * (x[0] * m[0] + x[1] * m[1] + x[2] * m[2]),
                                 mm * (e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2]) - d1 * d2);
    }
  }
  for (size_t v = 0; v < nv && *why == NULL; ++v) {
    if (!(fabs(turn[v] - 2.0 * CL_PI) < 1.0)) {
      *why = "a vertex whose faces do not go once around it";
    }
  }
  free(turn), free(queue), free(seen);
  return MODEL_OK;
}

/* The construction is closed, outward and convex by design; verify it rather than trust it:
 * every edge has a live twin that points back, the volume is positive, the surface is one convex
 * sphere (surface_not_convex), and no other input point lies above a face by more than 1000 tol.
 * The last two are what catch the inexact walk of old, which left a sheet of two opposite faces
 * through the middle of a generated rock with every edge twinned and the volume right, or a dent
 * (docs/model.md). The hull's own vertices, which on a finely tessellated smooth object are
 * nearly all its points, are covered by the convexity of the surface; the others are tested over
 * a tree of point boxes, O(faces x log points) in practice instead of O(faces x points). */
static model_status_t hull_verify(const hull_t *h, const uint32_t *newindex, size_t nv,
                                  model_error_t *err) {
  double volume6 = 0.0;
  const char *why = NULL;
  for (size_t f = 0; f < h->face_count && why == NULL; ++f) {
    const face_t *fa = &h->faces[f];
    if (!fa->alive) {
      continue;
    }
    for (int k = 0; k < 3 && why == NULL; ++k) {
      uint32_t g = fa->nb[k];
      int j = g == NONE ? -1 : twin_edge(&h->faces[g], fa->v[k], fa->v[(k + 1) % 3]);
      if (j < 0 || !h->faces[g].alive || h->faces[g].nb[j] != f) {
        why = "broken face adjacency";
      }
    }
    const double *a = h->p[fa->v[0]], *b = h->p[fa->v[1]], *c = h->p[fa->v[2]];
    volume6 += a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) +
               a[2] * (b[0] * c[1] - b[1] * c[0]);
  }
  if (why == NULL && !(volume6 > 0.0)) {
    why = "non-positive volume";
  }
  const double slack = 1e3 * h->tol;
  model_status_t st = MODEL_OK;
  if (why == NULL) {
    st = surface_not_convex(h, newindex, nv, slack, &why);
  }
  int outside = 0;
  if (st == MODEL_OK && why == NULL) {
    st = points_outside(h, newindex, slack, &outside);
    why = outside ? "a point above a hull face" : NULL;
  }
  if (st != MODEL_OK) {
    return st;
  }
  if (why != NULL) {
    return model_fail(err, MODEL_E_HULL, "convex hull: numerical failure (%s)", why);
  }
  return MODEL_OK;
}

model_status_t model_hull_verify_faces(const model_mesh_t *points, const uint32_t (*tris)[3],
                                       size_t nt, model_error_t *err) {
  const size_t n = points->vertex_count;
  double center[3], diag2 = 0.0;
  model_status_t st = points_bounds(points, n, center, &diag2, err);
  if (st != MODEL_OK) {
    return st;
  }
  hull_t h;
  memset(&h, 0, sizeof h);
  double(*p)[3] = malloc(n * sizeof *p);
  uint32_t *newindex = malloc(n * sizeof *newindex);
  st = p == NULL || newindex == NULL ? MODEL_E_NOMEM : MODEL_OK;
  if (st == MODEL_OK) {
    h.tol = points_place(points, center, diag2, p);
    h.p = (const double(*)[3])p;
    h.n = n;
  }
  for (size_t t = 0; st == MODEL_OK && t < nt; ++t) {
    st = face_new(&h, tris[t][0], tris[t][1], tris[t][2]) == NONE ? MODEL_E_NOMEM : MODEL_OK;
  }
  for (size_t f = 0; st == MODEL_OK && f < nt; ++f) { /* O(nt^2): for small test surfaces */
    for (size_t g = 0; g < nt; ++g) {
      for (int k = 0; k < 3; ++k) {
        if (twin_edge(&h.faces[g], h.faces[f].v[k], h.faces[f].v[(k + 1) % 3]) >= 0) {
          h.faces[f].nb[k] = (uint32_t)g;
        }
      }
    }
  }
  size_t nv = 0;
  for (size_t i = 0; st == MODEL_OK && i < n; ++i) {
    newindex[i] = NONE;
    for (size_t t = 0; t < nt && newindex[i] == NONE; ++t) {
      if (tris[t][0] == i || tris[t][1] == i || tris[t][2] == i) {
        newindex[i] = (uint32_t)nv++;
      }
    }
  }
  if (st == MODEL_OK) {
    st = hull_verify(&h, newindex, nv, err);
  }
  free(p);
  free(newindex);
  free(h.faces);
  return st;
}

model_status_t model_mesh_hull(const model_mesh_t *mesh, model_mesh_t *hull, model_error_t *err) {
  if (hull == NULL) {
    return model_fail(err, MODEL_E_ARG, "hull output is NULL");
  }
  memset(hull, 0, sizeof *hull);
  if (mesh == NULL || (mesh->vertex_count > 0 && mesh->vertices_m == NULL)) {
    return model_fail(err, MODEL_E_ARG, "hull input mesh is NULL");
  }
  const size_t n = mesh->vertex_count;
  if (n < 4) {
    return model_fail(err, MODEL_E_HULL, "convex hull needs >= 4 points, got %zu", n);
  }
  if (n >= UINT32_MAX) {
    return model_fail(err, MODEL_E_ARG, "convex hull: too many points (%zu)", n);
  }
  double center[3], diag2 = 0.0;
  model_status_t st = points_bounds(mesh, n, center, &diag2, err);
  if (st != MODEL_OK) {
    return st;
  }

  hull_t h;
  memset(&h, 0, sizeof h);
  double(*p)[3] = malloc(n * sizeof *p);
  h.next = malloc(n * sizeof *h.next);
  uint32_t *newindex = malloc(n * sizeof *newindex);
  if (p == NULL || h.next == NULL || newindex == NULL) {
    st = MODEL_E_NOMEM;
    goto done;
  }
  h.tol = points_place(mesh, center, diag2, p);
  for (size_t i = 0; i < n; ++i) {
    h.next[i] = NONE;
    newindex[i] = NONE;
  }
  h.p = (const double(*)[3])p;
  h.n = n;
  st = build(&h, err);
  if (st == MODEL_OK) {
    st = hull_mesh_write(&h, mesh, newindex, hull);
  }
  if (st == MODEL_OK) {
    st = hull_verify(&h, newindex, hull->vertex_count, err);
    if (st != MODEL_OK) {
      model_mesh_free(hull);
    }
  }

done:
  if (st == MODEL_E_NOMEM) {
    (void)model_fail(err, st, "convex hull: out of memory for %zu points", n);
  }
  free(p);
  free(h.next);
  free(h.faces);
  free(h.stack);
  free(newindex);
  return st;
}
