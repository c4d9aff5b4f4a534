/*
 * plan.c - the stack planner (lib/stack, library comlearn_stack): geometry and believed
 * CoMs in, an order and poses out. Never reads the URDF <inertial> (nm-checked).
 *
 * Contacts (docs/stack.md): every object rests with a face of its convex hull (coplanar hull
 * facets merged) on the hull face of the object below whose plane is exactly antiparallel, or on
 * B. Both hulls lie on their side of the common plane, so the two touch only there; the support
 * polygon is the convex hull of the lower's mesh vertices on that plane inside the upper's face
 * and the upper's inside the lower's face (what lib/balance's pair contacts generate). The
 * margin of a contact is the signed distance from where the vertical line through the CoM of
 * everything above meets the plane to the support's boundary, worst case over the CoM boxes and
 * the mass-ratio range.
 *
 * Search: a beam over (object, resting face, facet below, yaw) bottom-up, scored by a cheap bound;
 * the survivors get their in-plane translations top-down (each CoM over its facet's deepest
 * point), refined jointly by a compass search on the sorted margins.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "comlearn/math3d.h"
#include "comlearn/stack.h"

enum {
  BEAM_WIDTH = 48,
  FULL_EVAL = 16,
  MAX_PER_SIGNATURE = 3,
  MAX_UPPER_FACES = 8,
  MAX_LOWER_FACETS = 12
};

static const double kMergeCos = 0.99999998; /* 2e-4 rad between merged hull facets */
static const double kPlaneTol = 1e-6;       /* a vertex on a face: within 1 um of its plane */
static const double kMinInradius = 1e-3;    /* faces narrower than 2 mm are not used */
static const double kInsideTol = 2e-6;      /* lib/balance's pair contact band */
static const double kClearance = 5e-4;      /* non-adjacent objects and B stay this far apart */

const char *stack_status_str(stack_status_t s) {
  switch (s) {
    case STACK_OK: return "ok";
    case STACK_E_ARG: return "bad argument";
    case STACK_E_GEOMETRY: return "unusable geometry";
    case STACK_E_NOPLAN: return "no stable stack found";
    case STACK_E_SIM: return "simulation failed";
    case STACK_E_NOMEM: return "out of memory";
  }
  return "unknown status";
}

const char *stack_com_source_str(stack_com_source_t s) {
  switch (s) {
    case STACK_COM_LEARNED: return "learned";
    case STACK_COM_BBOX: return "bbox";
    case STACK_COM_TRUE: return "true";
  }
  return "?";
}

void stack_plan_config_default(stack_plan_config_t *cfg) {
  if (cfg == NULL) return;
  cfg->max_tilt_rad = 15.0 * CL_PI / 180.0;
  cfg->mass_rel_uncertainty = 0.3;
  cfg->yaw_steps = 24;
}

/* ---- small vector helpers ------------------------------------------------------------------ */

static void mat_vec(const double r[3][3], const double v[3], double out[3]) {
  for (int i = 0; i < 3; ++i) out[i] = r[i][0] * v[0] + r[i][1] * v[1] + r[i][2] * v[2];
}

static void mat_t_vec(const double r[3][3], const double v[3], double out[3]) {
  for (int i = 0; i < 3; ++i) out[i] = r[0][i] * v[0] + r[1][i] * v[1] + r[2][i] * v[2];
}

static void mat_mul(const double a[3][3], const double b[3][3], double out[3][3]) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      out[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
}

/* The shortest rotation taking unit a to unit b. */
static void rot_a_to_b(const double a[3], const double b[3], double r[3][3]) {
  const double c = cl_vec3_dot(a, b);
  double ax[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  double s = sqrt(cl_vec3_dot(ax, ax));
  if (s < 1e-12) {
    if (c > 0.0) {
      cl_rot_from_axis_angle((const double[3]){0, 0, 1}, 0.0, r);
      return;
    }
    /* half turn about any axis perpendicular to a */
    double u[3], v[3];
    model_plane_basis(a, u, v);
    cl_rot_from_axis_angle(u, CL_PI, r);
    return;
  }
  for (int k = 0; k < 3; ++k) ax[k] /= s;
  cl_rot_from_axis_angle(ax, atan2(s, c), r);
}

/* ---- polygons ------------------------------------------------------------------------------ */

/* min over edges of (b - a.p) for a CCW polygon: the signed distance inside, a lower bound of
 * minus the distance outside (enough to tell inside from outside and to maximise). */
static double poly_depth(const double (*poly)[2], size_t n, const double p[2]) {
  if (n < 3) return -HUGE_VAL;
  double best = HUGE_VAL;
  for (size_t i = 0; i < n; ++i) {
    const double *a = poly[i], *b = poly[(i + 1) % n];
    const double dx = b[0] - a[0], dy = b[1] - a[1], len = sqrt(dx * dx + dy * dy);
    if (len <= 0.0) continue;
    const double d = ((p[1] - a[1]) * dx - (p[0] - a[0]) * dy) / len;
    if (d < best) best = d;
  }
  return best;
}

/* p within tol of a CCW polygon (early exit on the first edge it is outside of). */
static int poly_inside(const double (*poly)[2], size_t n, const double p[2], double tol) {
  if (n < 3) return 0;
  for (size_t i = 0; i < n; ++i) {
    const double *a = poly[i], *b = poly[(i + 1) % n];
    const double dx = b[0] - a[0], dy = b[1] - a[1];
    const double cr = (p[1] - a[1]) * dx - (p[0] - a[0]) * dy;
    if (cr < 0.0 && cr * cr > tol * tol * (dx * dx + dy * dy)) return 0;
  }
  return 1;
}

/* The deepest point of a convex polygon (Chebyshev center) and its depth, by nested golden-section
 * search on the concave depth function min_i (b_i - a_i . p) over the edges' unit outward
 * normals a_i (bounded: 36 x 36 evaluations; 0.618^36 ~ 3e-8 of the polygon's extent). */
static double hp_depth(const double (*hp)[3], size_t n, double x, double y) {
  double best = HUGE_VAL;
  for (size_t i = 0; i < n; ++i) {
    const double d = hp[i][2] - hp[i][0] * x - hp[i][1] * y;
    if (d < best) best = d;
  }
  return best;
}

static double hp_inner_y(const double (*hp)[3], size_t n, double x, double y0, double y1,
                         double *ybest) {
  const double g = 0.5 * (sqrt(5.0) - 1.0);
  double a = y0, b = y1;
  double c = b - g * (b - a), d = a + g * (b - a);
  double fc = hp_depth(hp, n, x, c), fd = hp_depth(hp, n, x, d);
  for (int it = 0; it < 36; ++it) {
    if (fc > fd) {
      b = d;
      d = c;
      fd = fc;
      c = b - g * (b - a);
      fc = hp_depth(hp, n, x, c);
    } else {
      a = c;
      c = d;
      fc = fd;
      d = a + g * (b - a);
      fd = hp_depth(hp, n, x, d);
    }
  }
  *ybest = 0.5 * (a + b);
  return hp_depth(hp, n, x, *ybest);
}

static double poly_center(const double (*poly)[2], size_t n, double center[2]) {
  center[0] = center[1] = 0.0;
  if (n < 3) return -HUGE_VAL;
  double(*hp)[3] = malloc(n * sizeof *hp);
  if (!hp) return -HUGE_VAL;
  size_t m = 0;
  double lo[2] = {poly[0][0], poly[0][1]}, hi[2] = {poly[0][0], poly[0][1]};
  for (size_t i = 0; i < n; ++i) {
    const double *a = poly[i], *b = poly[(i + 1) % n];
    const double dx = b[0] - a[0], dy = b[1] - a[1], len = sqrt(dx * dx + dy * dy);
    for (int k = 0; k < 2; ++k) {
      if (a[k] < lo[k]) lo[k] = a[k];
      if (a[k] > hi[k]) hi[k] = a[k];
    }
    if (len <= 0.0) continue;
    hp[m][0] = dy / len;
    hp[m][1] = -dx / len;
    hp[m][2] = hp[m][0] * a[0] + hp[m][1] * a[1];
    ++m;
  }
  const double(*h)[3] = (const double(*)[3])hp;
  const double g = 0.5 * (sqrt(5.0) - 1.0);
  double a = lo[0], b = hi[0], yc, yd;
  double c = b - g * (b - a), d = a + g * (b - a);
  double fc = hp_inner_y(h, m, c, lo[1], hi[1], &yc);
  double fd = hp_inner_y(h, m, d, lo[1], hi[1], &yd);
  for (int it = 0; it < 36; ++it) {
    if (fc > fd) {
      b = d;
      d = c;
      fd = fc;
      yd = yc;
      c = b - g * (b - a);
      fc = hp_inner_y(h, m, c, lo[1], hi[1], &yc);
    } else {
      a = c;
      c = d;
      fc = fd;
      yc = yd;
      d = a + g * (b - a);
      fd = hp_inner_y(h, m, d, lo[1], hi[1], &yd);
    }
  }
  center[0] = 0.5 * (a + b);
  const double r = hp_inner_y(h, m, center[0], lo[1], hi[1], &center[1]);
  free(hp);
  return r;
}

/* ---- per-object faces ---------------------------------------------------------------------- */

typedef struct {
  double n[3], d;    /* outward unit normal and offset, link frame: n.x = d */
  double u[3], v[3]; /* in-plane basis, u x v = n */
  size_t npts;       /* mesh vertices on the plane */
  double (*pts3)[3]; /* link frame */
  double (*pts2)[2]; /* (u.x, v.x) */
  size_t npoly;      /* their convex hull, CCW seen from outside */
  double (*poly)[2];
  double area_m2, inradius_m, center[2];
} face_t;

typedef struct {
  const stack_object_t *in;
  double mass_lo, mass_hi;
  face_t *face; /* usable faces, deepest (largest inradius) first */
  size_t nface;
  double (*hull_planes)[4]; /* every hull facet plane (n, d), for clearance checks */
  size_t nplanes;
  const model_mesh_t *mesh;
} obj_t;

static void faces_free(obj_t *o) {
  for (size_t i = 0; i < o->nface; ++i) {
    free(o->face[i].pts3);
    free(o->face[i].pts2);
    free(o->face[i].poly);
  }
  free(o->face);
  free(o->hull_planes);
  o->face = NULL;
  o->hull_planes = NULL;
  o->nface = o->nplanes = 0;
}

static int face_cmp(const void *a, const void *b) {
  const face_t *fa = a, *fb = b;
  if (fa->inradius_m != fb->inradius_m) return fa->inradius_m > fb->inradius_m ? -1 : 1;
  for (int k = 0; k < 3; ++k)
    if (fa->n[k] != fb->n[k]) return fa->n[k] < fb->n[k] ? -1 : 1;
  return 0;
}

/* Face f of the hull, from lib/model's merge (model_hull_faces): its plane's offset at the
 * outermost vertex of its facets and the in-plane basis. */
static void face_of(const model_mesh_t *hull, const model_hull_face_t *hf, const int *facet_face,
                    int index, face_t *f) {
  memset(f, 0, sizeof *f);
  memcpy(f->n, hf->normal, sizeof f->n);
  f->d = -HUGE_VAL;
  for (size_t s = 0; s < hull->triangle_count; ++s)
    if (facet_face[s] == index)
      for (int k = 0; k < 3; ++k) {
        const double dd = cl_vec3_dot(f->n, hull->vertices_m[hull->triangles[s][k]]);
        if (dd > f->d) f->d = dd;
      }
  model_plane_basis(f->n, f->u, f->v);
}

/* Every hull facet's plane (n, d), for the clearance checks. */
static void hull_planes(const model_mesh_t *hull, double (*planes)[4]) {
  for (size_t t = 0; t < hull->triangle_count; ++t) {
    const double *a = hull->vertices_m[hull->triangles[t][0]];
    const double *b = hull->vertices_m[hull->triangles[t][1]];
    const double *c = hull->vertices_m[hull->triangles[t][2]];
    double n[3];
    cl_tri_normal(a, b, c, n);
    for (int k = 0; k < 3; ++k) planes[t][k] = n[k];
    planes[t][3] = cl_vec3_dot(n, a);
  }
}

/* The mesh vertices within 1 um of f's plane: link frame into pts3, (u.x, v.x) into pts2.
 * Returns their count. */
static size_t face_points(const model_mesh_t *mesh, const face_t *f, double (*pts3)[3],
                          double (*pts2)[2]) {
  size_t np = 0;
  for (size_t i = 0; i < mesh->vertex_count; ++i) {
    if (fabs(cl_vec3_dot(f->n, mesh->vertices_m[i]) - f->d) > kPlaneTol) continue;
    memcpy(pts3[np], mesh->vertices_m[i], sizeof pts3[np]);
    pts2[np][0] = cl_vec3_dot(f->u, mesh->vertices_m[i]);
    pts2[np][1] = cl_vec3_dot(f->v, mesh->vertices_m[i]);
    ++np;
  }
  return np;
}

/* f's outline from its np >= 3 points: convex hull, area, inradius and center; a face at least
 * 2 mm wide keeps copies of the points. Returns 1 (kept: f owns poly, pts3, pts2), 0 (too
 * narrow, nothing kept) or -1 (out of memory, nothing kept). */
static int face_outline(face_t *f, size_t np, const double (*pts3)[3], const double (*pts2)[2]) {
  double(*sorted)[2] = malloc(np * sizeof *sorted);
  double(*poly)[2] = malloc((np + 1) * sizeof *poly);
  if (!sorted || !poly) {
    free(sorted);
    free(poly);
    return -1;
  }
  memcpy(sorted, pts2, np * sizeof *sorted);
  f->npoly = model_polygon_hull(sorted, np, poly);
  free(sorted);
  f->area_m2 = model_polygon_area((const double(*)[2])poly, f->npoly);
  /* inradius <= 2 area / perimeter: most hull facets are too small to need the search */
  double perim = 0.0;
  for (size_t i = 0; i < f->npoly; ++i) {
    const double *next = poly[(i + 1) % f->npoly];
    perim += hypot(next[0] - poly[i][0], next[1] - poly[i][1]);
  }
  f->inradius_m = f->npoly >= 3 && 2.0 * f->area_m2 >= kMinInradius * perim
                      ? poly_center((const double(*)[2])poly, f->npoly, f->center)
                      : 0.0;
  if (f->npoly < 3 || !(f->inradius_m >= kMinInradius)) {
    free(poly);
    return 0;
  }
  f->poly = poly;
  f->npts = np;
  f->pts3 = malloc(np * sizeof *f->pts3);
  f->pts2 = malloc(np * sizeof *f->pts2);
  if (!f->pts3 || !f->pts2) {
    free(f->pts3);
    free(f->pts2);
    free(poly);
    return -1;
  }
  memcpy(f->pts3, pts3, np * sizeof *f->pts3);
  memcpy(f->pts2, pts2, np * sizeof *f->pts2);
  return 1;
}

/* The hull faces of one object: hull facets merged when their normals are within 2e-4 rad and
 * their vertices within 1 um of the plane; each face gets every mesh vertex within 1 um. */
static stack_status_t faces_build(obj_t *o, char *msg, size_t msg_size, size_t index) {
  const model_mesh_t *mesh = o->mesh;
  model_mesh_t hull = {0};
  model_error_t merr = {{0}};
  if (model_mesh_hull(mesh, &hull, &merr) != MODEL_OK) {
    snprintf(msg, msg_size, "object %zu: convex hull failed: %.160s", index, merr.msg);
    return STACK_E_GEOMETRY;
  }
  const size_t nt = hull.triangle_count;
  model_hull_face_t *hf = malloc(nt * sizeof *hf);
  int *facet_face = malloc(nt * sizeof *facet_face);
  o->hull_planes = malloc(nt * sizeof *o->hull_planes);
  o->face = calloc(nt, sizeof *o->face);
  double(*buf3)[3] = malloc(mesh->vertex_count * sizeof *buf3);
  double(*buf2)[2] = malloc((mesh->vertex_count + 1) * sizeof *buf2);
  stack_status_t st = STACK_OK;
  size_t nhf = 0;
  if (!hf || !facet_face || !o->hull_planes || !o->face || !buf3 || !buf2) {
    st = STACK_E_NOMEM;
    goto done;
  }
  hull_planes(&hull, o->hull_planes);
  o->nplanes = nt;
  if (model_hull_faces(&hull, kMergeCos, kPlaneTol, hf, facet_face, &nhf) != MODEL_OK) {
    st = STACK_E_NOMEM;
    goto done;
  }
  size_t nface = 0;
  for (size_t i = 0; i < nhf && st == STACK_OK; ++i) {
    face_t f;
    face_of(&hull, &hf[i], facet_face, (int)i, &f);
    const size_t np = face_points(mesh, &f, buf3, buf2);
    if (np < 3) continue;
    const int kept = face_outline(&f, np, (const double(*)[3])buf3, (const double(*)[2])buf2);
    if (kept < 0)
      st = STACK_E_NOMEM;
    else if (kept)
      o->face[nface++] = f;
  }
  o->nface = nface; /* also on failure: faces_free releases what was kept */
  if (st != STACK_OK) goto done;
  qsort(o->face, nface, sizeof *o->face, face_cmp);
  if (nface == 0) {
    snprintf(msg, msg_size, "object %zu: no hull face at least %.0f mm wide to rest on", index,
             2e3 * kMinInradius);
    st = STACK_E_GEOMETRY;
  }
done:
  free(hf);
  free(facet_face);
  free(buf3);
  free(buf2);
  model_mesh_free(&hull);
  return st;
}

/* ---- candidate stacks ---------------------------------------------------------------------- */

typedef struct {
  size_t count;                        /* levels filled */
  size_t obj[STACK_MAX_OBJECTS];       /* object per level */
  size_t face[STACK_MAX_OBJECTS];      /* its resting face (F) */
  size_t facet[STACK_MAX_OBJECTS];     /* level k >= 1: the face of level k-1 it rests on */
  double rot[STACK_MAX_OBJECTS][3][3]; /* link -> world */
  unsigned used;
  double score; /* screening bound: min over levels */
} cand_t;

typedef struct {
  obj_t obj[STACK_MAX_OBJECTS];
  size_t count;
  double cos_tilt;
  unsigned yaw_steps;
  size_t max_pts;
  /* scratch for the evaluation */
  double (*up0)[2]; /* upper face points at t = 0, per level */
  double (*buf)[2];
  double (*hull)[2];
  double (*uph)[2];
} ctx_t;

/* Margin of object o's own CoM, projected vertically (world) onto its resting face f, for the
 * link->world rotation r: the screening bound of one level. */
static double own_margin(const obj_t *o, const face_t *f, const double r[3][3]) {
  double w[3];
  mat_t_vec(r, (const double[3]){0, 0, 1}, w);
  const double *c = o->in->com_m;
  const double nw = cl_vec3_dot(f->n, w);
  if (fabs(nw) < 1e-9) return -HUGE_VAL;
  const double s = (f->d - cl_vec3_dot(f->n, c)) / nw;
  const double p3[3] = {c[0] + s * w[0], c[1] + s * w[1], c[2] + s * w[2]};
  const double p[2] = {cl_vec3_dot(f->u, p3), cl_vec3_dot(f->v, p3)};
  return poly_depth((const double(*)[2])f->poly, f->npoly, p);
}

/* Same objects, faces and facets at every level: candidates that differ only in yaws. */
static int same_signature(const cand_t *a, const cand_t *b) {
  if (a->count != b->count) return 0;
  for (size_t k = 0; k < a->count; ++k)
    if (a->obj[k] != b->obj[k] || a->face[k] != b->face[k] || (k > 0 && a->facet[k] != b->facet[k]))
      return 0;
  return 1;
}

/* Keep the BEAM_WIDTH best, at most MAX_PER_SIGNATURE of one signature (yaw variants of one
 * arrangement would otherwise crowd out every other order when their bounds tie). */
static void beam_insert(cand_t *beam, size_t *n, const cand_t *c) {
  size_t same = 0, worst_same = SIZE_MAX;
  for (size_t i = 0; i < *n; ++i)
    if (same_signature(&beam[i], c)) {
      ++same;
      if (worst_same == SIZE_MAX || beam[i].score < beam[worst_same].score) worst_same = i;
    }
  if (same >= MAX_PER_SIGNATURE) {
    if (c->score > beam[worst_same].score) beam[worst_same] = *c;
    return;
  }
  if (*n < BEAM_WIDTH) {
    beam[(*n)++] = *c;
    return;
  }
  size_t worst = 0;
  for (size_t i = 1; i < *n; ++i)
    if (beam[i].score < beam[worst].score) worst = i;
  if (c->score > beam[worst].score) beam[worst] = *c;
}

static int cand_cmp(const void *a, const void *b) {
  const cand_t *ca = a, *cb = b;
  if (ca->score != cb->score) return ca->score > cb->score ? -1 : 1;
  return memcmp(ca->obj, cb->obj, sizeof ca->obj);
}

/* ---- evaluation of a complete candidate with translations ------------------------------------ */

typedef struct {
  double pos[STACK_MAX_OBJECTS][3];
  double margin[STACK_MAX_OBJECTS];
  double tilt[STACK_MAX_OBJECTS];
  /* contact planes: origin, normal, basis (world) */
  double O[STACK_MAX_OBJECTS][3], m[STACK_MAX_OBJECTS][3], u[STACK_MAX_OBJECTS][3],
      v[STACK_MAX_OBJECTS][3];
} layout_t;

static void layout_positions(const ctx_t *x, const cand_t *c, const double (*t)[2], layout_t *L) {
  const face_t *f0 = &x->obj[c->obj[0]].face[c->face[0]];
  L->pos[0][0] = 0.0;
  L->pos[0][1] = 0.0;
  L->pos[0][2] = f0->d; /* R n = -z: the face's plane at z = 0 */
  memset(L->O[0], 0, sizeof L->O[0]);
  L->m[0][0] = 0;
  L->m[0][1] = 0;
  L->m[0][2] = 1;
  L->u[0][0] = 1;
  L->u[0][1] = 0;
  L->u[0][2] = 0;
  L->v[0][0] = 0;
  L->v[0][1] = 1;
  L->v[0][2] = 0;
  L->tilt[0] = 0.0;
  for (size_t k = 1; k < c->count; ++k) {
    const face_t *f = &x->obj[c->obj[k - 1]].face[c->facet[k]];
    const face_t *F = &x->obj[c->obj[k]].face[c->face[k]];
    double dn[3] = {f->d * f->n[0], f->d * f->n[1], f->d * f->n[2]}, w[3];
    mat_vec(c->rot[k - 1], dn, w);
    for (int i = 0; i < 3; ++i) L->O[k][i] = L->pos[k - 1][i] + w[i];
    mat_vec(c->rot[k - 1], f->n, L->m[k]);
    mat_vec(c->rot[k - 1], f->u, L->u[k]);
    mat_vec(c->rot[k - 1], f->v, L->v[k]);
    L->tilt[k] = acos(fmin(1.0, fmax(-1.0, L->m[k][2])));
    for (int i = 0; i < 3; ++i)
      L->pos[k][i] = L->O[k][i] + F->d * L->m[k][i] + t[k][0] * L->u[k][i] + t[k][1] * L->v[k][i];
  }
}

/* Worst-case signed margin of the polygon (plane k's uv coordinates) for the CoM of levels
 * k..count-1: over each object's CoM box and the mass range. */
static double worst_margin(const ctx_t *x, const cand_t *c, const layout_t *L, size_t k,
                           const double (*poly)[2], size_t n) {
  if (n < 3) return -HUGE_VAL;
  const size_t na = c->count - k;
  double cw[STACK_MAX_OBJECTS][3];
  for (size_t j = 0; j < na; ++j) {
    const size_t lv = k + j;
    mat_vec(c->rot[lv], x->obj[c->obj[lv]].in->com_m, cw[j]);
    for (int i = 0; i < 3; ++i) cw[j][i] += L->pos[lv][i] - L->O[k][i];
  }
  const double *m = L->m[k];
  double best = HUGE_VAL;
  for (size_t e = 0; e < n; ++e) {
    const double *a = poly[e], *b = poly[(e + 1) % n];
    const double dx = b[0] - a[0], dy = b[1] - a[1], len = hypot(dx, dy);
    if (len <= 0.0) continue;
    const double au = dy / len, av = -dx / len; /* outward normal in uv */
    const double off = au * a[0] + av * a[1];
    double G[3], A[3];
    for (int i = 0; i < 3; ++i) G[i] = au * L->u[k][i] + av * L->v[k][i];
    for (int i = 0; i < 3; ++i) A[i] = G[i] - (G[2] / m[2]) * m[i];
    /* per object: the largest a.uv its CoM box reaches */
    double s[STACK_MAX_OBJECTS];
    for (size_t j = 0; j < na; ++j) {
      const obj_t *o = &x->obj[c->obj[k + j]];
      double al[3];
      mat_t_vec(c->rot[k + j], A, al);
      s[j] = cl_vec3_dot(A, cw[j]);
      for (int i = 0; i < 3; ++i) s[j] += o->in->com_halfwidth_m[i] * fabs(al[i]);
    }
    /* the largest mass-weighted mean of s: heavy (hi) for the top-p values, light for the rest */
    size_t idx[STACK_MAX_OBJECTS];
    for (size_t j = 0; j < na; ++j) idx[j] = j;
    for (size_t i = 1; i < na; ++i)
      for (size_t j = i; j > 0 && s[idx[j]] > s[idx[j - 1]]; --j) {
        const size_t tmp = idx[j];
        idx[j] = idx[j - 1];
        idx[j - 1] = tmp;
      }
    double worst = -HUGE_VAL;
    for (size_t p = 0; p <= na; ++p) {
      double num = 0.0, den = 0.0;
      for (size_t j = 0; j < na; ++j) {
        const obj_t *o = &x->obj[c->obj[k + idx[j]]];
        const double w = j < p ? o->mass_hi : o->mass_lo;
        num += w * s[idx[j]];
        den += w;
      }
      if (num / den > worst) worst = num / den;
    }
    const double d = off - worst;
    if (d < best) best = d;
  }
  return best;
}

/* The support polygon of contact k (k >= 1) in plane k's uv: the lower's face points inside the
 * upper's face and the upper's inside the lower's. Returns its vertex count (into x->hull). */
static size_t support_polygon(ctx_t *x, const cand_t *c, const double (*t)[2], size_t k,
                              const double (*up0)[2], size_t nup, const double (*uph)[2],
                              size_t nuph) {
  const face_t *f = &x->obj[c->obj[k - 1]].face[c->facet[k]];
  size_t n = 0;
  for (size_t i = 0; i < f->npts; ++i) {
    const double p[2] = {f->pts2[i][0] - t[k][0], f->pts2[i][1] - t[k][1]};
    if (poly_inside(uph, nuph, p, kInsideTol)) {
      x->buf[n][0] = f->pts2[i][0];
      x->buf[n][1] = f->pts2[i][1];
      ++n;
    }
  }
  for (size_t i = 0; i < nup; ++i) {
    const double p[2] = {up0[i][0] + t[k][0], up0[i][1] + t[k][1]};
    if (poly_inside((const double(*)[2])f->poly, f->npoly, p, kInsideTol)) {
      x->buf[n][0] = p[0];
      x->buf[n][1] = p[1];
      ++n;
    }
  }
  if (n < 3) return 0;
  return model_polygon_hull(x->buf, n, x->hull);
}

/* Upper face points of level k in plane k's uv at t = 0 (into dst) and their hull (into hull). */
static void upper_points(const ctx_t *x, const cand_t *c, const layout_t *L, size_t k,
                         double (*dst)[2], size_t *n, double (*hull)[2], size_t *nh,
                         double (*scratch)[2]) {
  const face_t *F = &x->obj[c->obj[k]].face[c->face[k]];
  double ru[3], rv[3];
  mat_t_vec(c->rot[k], L->u[k], ru);
  mat_t_vec(c->rot[k], L->v[k], rv);
  for (size_t i = 0; i < F->npts; ++i) {
    dst[i][0] = cl_vec3_dot(ru, F->pts3[i]);
    dst[i][1] = cl_vec3_dot(rv, F->pts3[i]);
  }
  *n = F->npts;
  memcpy(scratch, dst, F->npts * sizeof *scratch);
  *nh = model_polygon_hull(scratch, F->npts, hull);
}

/* Margins of all levels for translations t (levels 1..count-1); fills L. */
static void evaluate(ctx_t *x, const cand_t *c, const double (*t)[2], layout_t *L,
                     const size_t *nup, const size_t *nuph) {
  layout_positions(x, c, t, L);
  /* level 0: the bottom face on B, in world x, y */
  {
    const face_t *f0 = &x->obj[c->obj[0]].face[c->face[0]];
    for (size_t i = 0; i < f0->npts; ++i) {
      double w[3];
      mat_vec(c->rot[0], f0->pts3[i], w);
      x->buf[i][0] = w[0] + L->pos[0][0];
      x->buf[i][1] = w[1] + L->pos[0][1];
    }
    const size_t nh = model_polygon_hull(x->buf, f0->npts, x->hull);
    L->margin[0] = worst_margin(x, c, L, 0, (const double(*)[2])x->hull, nh);
  }
  for (size_t k = 1; k < c->count; ++k) {
    const double(*up0)[2] = (const double(*)[2])(x->up0 + k * x->max_pts);
    const double(*uph)[2] = (const double(*)[2])(x->uph + k * (x->max_pts + 1));
    const size_t nh = support_polygon(x, c, t, k, up0, nup[k], uph, nuph[k]);
    L->margin[k] = nh >= 3 ? worst_margin(x, c, L, k, (const double(*)[2])x->hull, nh) : -HUGE_VAL;
  }
}

/* a better than b: sorted margins compared lexicographically (smallest first). */
static int margins_better(const double *a, const double *b, size_t n) {
  double sa[STACK_MAX_OBJECTS], sb[STACK_MAX_OBJECTS];
  memcpy(sa, a, n * sizeof *a);
  memcpy(sb, b, n * sizeof *b);
  for (size_t i = 1; i < n; ++i)
    for (size_t j = i; j > 0 && sa[j] < sa[j - 1]; --j) {
      double tmp = sa[j];
      sa[j] = sa[j - 1];
      sa[j - 1] = tmp;
    }
  for (size_t i = 1; i < n; ++i)
    for (size_t j = i; j > 0 && sb[j] < sb[j - 1]; --j) {
      double tmp = sb[j];
      sb[j] = sb[j - 1];
      sb[j - 1] = tmp;
    }
  for (size_t i = 0; i < n; ++i) {
    if (sa[i] > sb[i] + 1e-10) return 1;
    if (sa[i] < sb[i] - 1e-10) return 0;
  }
  return 0;
}

/* Translations for a complete candidate: top-down, each level's CoM (of all above) over the
 * deepest point of the facet below; then a compass search on all of them. Fills t and L. */
static void place(ctx_t *x, const cand_t *c, double (*t)[2], layout_t *L) {
  size_t nup[STACK_MAX_OBJECTS] = {0}, nuph[STACK_MAX_OBJECTS] = {0};
  memset(t, 0, STACK_MAX_OBJECTS * sizeof *t);
  layout_positions(x, c, (const double(*)[2])t, L);
  for (size_t k = 1; k < c->count; ++k)
    upper_points(x, c, L, k, x->up0 + k * x->max_pts, &nup[k], x->uph + k * (x->max_pts + 1),
                 &nuph[k], x->buf);
  for (size_t k = c->count; k-- > 1;) {
    layout_positions(x, c, (const double(*)[2])t, L);
    /* the CoM of levels k.. and where its vertical meets plane k */
    double cm[3] = {0, 0, 0}, mt = 0.0;
    for (size_t j = k; j < c->count; ++j) {
      const obj_t *o = &x->obj[c->obj[j]];
      double w[3];
      mat_vec(c->rot[j], o->in->com_m, w);
      for (int i = 0; i < 3; ++i) cm[i] += o->in->mass_kg * (w[i] + L->pos[j][i]);
      mt += o->in->mass_kg;
    }
    for (int i = 0; i < 3; ++i) cm[i] /= mt;
    const double *m = L->m[k];
    double rel[3] = {L->O[k][0] - cm[0], L->O[k][1] - cm[1], L->O[k][2] - cm[2]};
    const double s = cl_vec3_dot(m, rel) / m[2];
    const double X[3] = {cm[0] - L->O[k][0], cm[1] - L->O[k][1], cm[2] + s - L->O[k][2]};
    const face_t *f = &x->obj[c->obj[k - 1]].face[c->facet[k]];
    t[k][0] += f->center[0] - cl_vec3_dot(L->u[k], X);
    t[k][1] += f->center[1] - cl_vec3_dot(L->v[k], X);
  }
  evaluate(x, c, (const double(*)[2])t, L, nup, nuph);
  const size_t nvar = 2 * (c->count - 1);
  double step = 2e-3;
  for (int it = 0; it < 400 && step >= 4e-5; ++it) {
    int improved = 0;
    for (size_t vi = 0; vi < nvar && !improved; ++vi) {
      for (int sgn = -1; sgn <= 1 && !improved; sgn += 2) {
        double tt[STACK_MAX_OBJECTS][2];
        memcpy(tt, t, sizeof tt);
        tt[1 + vi / 2][vi % 2] += sgn * step;
        layout_t L2;
        evaluate(x, c, (const double(*)[2])tt, &L2, nup, nuph);
        if (margins_better(L2.margin, L->margin, c->count)) {
          memcpy(t, tt, sizeof tt);
          *L = L2;
          improved = 1;
        }
      }
    }
    if (!improved) step *= 0.5;
  }
}

/* ---- clearance checks of a placed stack ---------------------------------------------------- */

/* Does object a (rot ra, pos pa) come within kClearance of the hull of object b? */
static int too_close(const obj_t *a, const double ra[3][3], const double pa[3], const obj_t *b,
                     const double rb[3][3], const double pb[3]) {
  for (size_t i = 0; i < a->mesh->vertex_count; ++i) {
    double w[3], rel[3], lb[3];
    mat_vec(ra, a->mesh->vertices_m[i], w);
    for (int k = 0; k < 3; ++k) rel[k] = w[k] + pa[k] - pb[k];
    mat_t_vec(rb, rel, lb);
    double worst = -HUGE_VAL;
    for (size_t p = 0; p < b->nplanes && worst < kClearance; ++p) {
      const double s = cl_vec3_dot(b->hull_planes[p], lb) - b->hull_planes[p][3];
      if (s > worst) worst = s;
    }
    if (worst < kClearance) return 1;
  }
  return 0;
}

static int stack_clear(const ctx_t *x, const cand_t *c, const layout_t *L) {
  for (size_t k = 1; k < c->count; ++k) {
    const obj_t *o = &x->obj[c->obj[k]];
    for (size_t i = 0; i < o->mesh->vertex_count; ++i) {
      double w[3];
      mat_vec(c->rot[k], o->mesh->vertices_m[i], w);
      if (w[2] + L->pos[k][2] < kClearance) return 0; /* reaches down to B */
    }
    for (size_t j = 0; j + 1 < k; ++j) {
      const obj_t *b = &x->obj[c->obj[j]];
      if (too_close(o, c->rot[k], L->pos[k], b, c->rot[j], L->pos[j]) ||
          too_close(b, c->rot[j], L->pos[j], o, c->rot[k], L->pos[k]))
        return 0;
    }
  }
  return 1;
}

/* ---- the planner --------------------------------------------------------------------------- */

static stack_status_t check_input(const stack_object_t *objects, size_t count,
                                  const stack_plan_config_t *cfg, char *msg, size_t msg_size) {
  if (!(isfinite(cfg->max_tilt_rad) && cfg->max_tilt_rad > 0.0 && cfg->max_tilt_rad <= 1.0) ||
      !(isfinite(cfg->mass_rel_uncertainty) && cfg->mass_rel_uncertainty >= 0.0 &&
        cfg->mass_rel_uncertainty <= 10.0) ||
      cfg->yaw_steps < 1 || cfg->yaw_steps > 360) {
    snprintf(msg, msg_size,
             "bad configuration (max_tilt in (0, 1] rad, mass uncertainty in "
             "[0, 10], yaw_steps in [1, 360])");
    return STACK_E_ARG;
  }
  for (size_t i = 0; i < count; ++i) {
    const stack_object_t *o = &objects[i];
    int ok = o->mesh_link != NULL && o->mesh_link->vertices_m != NULL &&
             o->mesh_link->triangles != NULL && o->mesh_link->vertex_count >= 4 &&
             isfinite(o->mass_kg) && o->mass_kg > 0.0 && isfinite(o->mass_rel_uncertainty) &&
             o->mass_rel_uncertainty >= 0.0 && o->mass_rel_uncertainty <= 10.0;
    for (int k = 0; k < 3 && ok; ++k)
      ok = isfinite(o->com_m[k]) && isfinite(o->com_halfwidth_m[k]) &&
           o->com_halfwidth_m[k] >= 0.0 && fabs(o->com_m[k]) < 100.0 && o->com_halfwidth_m[k] < 1.0;
    if (!ok) {
      snprintf(msg, msg_size,
               "object %zu: no mesh, or a CoM, half width or mass that is not "
               "finite and in range",
               i);
      return STACK_E_ARG;
    }
  }
  return STACK_OK;
}

/* The objects' faces and mass ranges into x, then the scratch buffers sized by the largest face.
 * Returns STACK_OK, STACK_E_GEOMETRY (msg says which object) or STACK_E_NOMEM. */
static stack_status_t ctx_init(ctx_t *x, const stack_object_t *objects, size_t count,
                               const stack_plan_config_t *cfg, char *msg, size_t msg_size) {
  x->count = count;
  x->cos_tilt = cos(cfg->max_tilt_rad);
  x->yaw_steps = cfg->yaw_steps;
  stack_status_t st = STACK_OK;
  for (size_t i = 0; i < count && st == STACK_OK; ++i) {
    obj_t *o = &x->obj[i];
    o->in = &objects[i];
    o->mesh = objects[i].mesh_link;
    const double u = objects[i].mass_rel_uncertainty > 0.0 ? objects[i].mass_rel_uncertainty
                                                           : cfg->mass_rel_uncertainty;
    o->mass_lo = objects[i].mass_kg / (1.0 + u);
    o->mass_hi = objects[i].mass_kg * (1.0 + u);
    st = faces_build(o, msg, msg_size, i);
    for (size_t f = 0; f < o->nface; ++f)
      if (o->face[f].npts > x->max_pts) x->max_pts = o->face[f].npts;
  }
  if (st != STACK_OK) return st;
  const size_t mp = x->max_pts + 1;
  x->up0 = malloc(STACK_MAX_OBJECTS * mp * sizeof *x->up0);
  x->uph = malloc(STACK_MAX_OBJECTS * (mp + 1) * sizeof *x->uph);
  x->buf = malloc(4 * mp * sizeof *x->buf);
  x->hull = malloc((4 * mp + 1) * sizeof *x->hull);
  return x->up0 && x->uph && x->buf && x->hull ? STACK_OK : STACK_E_NOMEM;
}

static void ctx_free(ctx_t *x) {
  for (size_t i = 0; i < x->count; ++i) faces_free(&x->obj[i]);
  free(x->up0);
  free(x->uph);
  free(x->buf);
  free(x->hull);
  free(x);
}

/* Level 0 of the beam: every object on every one of its first faces, on B. */
static void beam_level0(const ctx_t *x, cand_t *beam, size_t *nbeam) {
  for (size_t i = 0; i < x->count; ++i) {
    const obj_t *o = &x->obj[i];
    for (size_t f = 0; f < o->nface && f < MAX_UPPER_FACES; ++f) {
      cand_t c;
      memset(&c, 0, sizeof c);
      c.count = 1;
      c.obj[0] = i;
      c.face[0] = f;
      c.used = 1u << i;
      rot_a_to_b(o->face[f].n, (const double[3]){0, 0, -1}, c.rot[0]);
      c.score =
          fmin(o->face[f].inradius_m, own_margin(o, &o->face[f], (const double(*)[3])c.rot[0]));
      if (c.score > 0.0) beam_insert(beam, nbeam, &c);
    }
  }
}

/* Candidate c of lv levels with object j on its face F on facet f of the top object (world
 * normal m), at every yaw about m, into next. */
static void beam_put_on(const ctx_t *x, const cand_t *c, size_t lv, size_t f, const double m[3],
                        size_t j, size_t F, cand_t *next, size_t *nnext) {
  const obj_t *lo = &x->obj[c->obj[lv - 1]];
  const obj_t *up = &x->obj[j];
  double base[3][3], yawr[3][3];
  const double negm[3] = {-m[0], -m[1], -m[2]};
  rot_a_to_b(up->face[F].n, negm, base);
  for (unsigned y = 0; y < x->yaw_steps; ++y) {
    cand_t nc = *c;
    cl_rot_from_axis_angle(m, 2.0 * CL_PI * y / x->yaw_steps, yawr);
    mat_mul((const double(*)[3])yawr, (const double(*)[3])base, nc.rot[lv]);
    nc.count = lv + 1;
    nc.obj[lv] = j;
    nc.face[lv] = F;
    nc.facet[lv] = f;
    nc.used |= 1u << j;
    double s = fmin(lo->face[f].inradius_m, up->face[F].inradius_m);
    s = fmin(s, own_margin(up, &up->face[F], (const double(*)[3])nc.rot[lv]));
    nc.score = fmin(c->score, s);
    if (nc.score > 0.0) beam_insert(next, nnext, &nc);
  }
}

/* Level lv of the beam: every unused object on every face, on every facet of the top object
 * within the tilt limit, from beam[0..nbeam) into next. */
static void beam_level(const ctx_t *x, size_t lv, const cand_t *beam, size_t nbeam, cand_t *next,
                       size_t *nnext) {
  for (size_t b = 0; b < nbeam; ++b) {
    const cand_t *c = &beam[b];
    const obj_t *lo = &x->obj[c->obj[lv - 1]];
    size_t nf = 0;
    for (size_t f = 0; f < lo->nface && nf < MAX_LOWER_FACETS; ++f) {
      if (f == c->face[lv - 1]) continue;
      double m[3];
      mat_vec(c->rot[lv - 1], lo->face[f].n, m);
      if (m[2] < x->cos_tilt) continue;
      ++nf;
      for (size_t j = 0; j < x->count; ++j) {
        if (c->used & (1u << j)) continue;
        for (size_t F = 0; F < x->obj[j].nface && F < MAX_UPPER_FACES; ++F)
          beam_put_on(x, c, lv, f, m, j, F, next, nnext);
      }
    }
  }
}

/* The beam search bottom-up: the surviving full stacks in *beam (the buffers swap), their count
 * returned. */
static size_t beam_search(const ctx_t *x, cand_t **beam, cand_t **next) {
  size_t nbeam = 0;
  beam_level0(x, *beam, &nbeam);
  for (size_t lv = 1; lv < x->count && nbeam > 0; ++lv) {
    size_t nnext = 0;
    beam_level(x, lv, *beam, nbeam, *next, &nnext);
    cand_t *tmp = *beam;
    *beam = *next;
    *next = tmp;
    nbeam = nnext;
  }
  return nbeam;
}

/* Lay out the best FULL_EVAL candidates (translations, margins) and choose the one with the best
 * sorted margins, all positive, that touches nothing it should not. *chosen: its index into
 * beam, *L its layout. Returns STACK_OK, STACK_E_NOPLAN (msg says why) or STACK_E_NOMEM. */
static stack_status_t layout_choose(ctx_t *x, const cand_t *beam, size_t nbeam, size_t *chosen,
                                    layout_t *L, char *msg, size_t msg_size) {
  const size_t count = x->count;
  const size_t neval = nbeam < FULL_EVAL ? nbeam : FULL_EVAL;
  layout_t *lay = malloc(neval * sizeof *lay);
  double(*tt)[STACK_MAX_OBJECTS][2] = malloc(neval * sizeof *tt);
  size_t *rank = malloc(neval * sizeof *rank);
  stack_status_t st = STACK_OK;
  if (!lay || !tt || !rank) {
    st = STACK_E_NOMEM;
    goto done;
  }
  for (size_t i = 0; i < neval; ++i) {
    place(x, &beam[i], tt[i], &lay[i]);
    rank[i] = i;
  }
  for (size_t i = 1; i < neval; ++i)
    for (size_t j = i; j > 0 && margins_better(lay[rank[j]].margin, lay[rank[j - 1]].margin, count);
         --j) {
      const size_t tmp = rank[j];
      rank[j] = rank[j - 1];
      rank[j - 1] = tmp;
    }
  *chosen = SIZE_MAX;
  double best_min = -HUGE_VAL;
  for (size_t r = 0; r < neval && *chosen == SIZE_MAX; ++r) {
    const size_t i = rank[r];
    double mn = HUGE_VAL;
    for (size_t k = 0; k < count; ++k) mn = fmin(mn, lay[i].margin[k]);
    if (r == 0) best_min = mn;
    if (!(mn > 0.0)) break;
    if (stack_clear(x, &beam[i], &lay[i])) *chosen = i;
  }
  if (*chosen == SIZE_MAX) {
    snprintf(msg, msg_size,
             "no stack with all margins > 0 (best smallest margin %.2f mm, or the objects "
             "would touch B or each other)",
             1e3 * best_min);
    st = STACK_E_NOPLAN;
  } else {
    *L = lay[*chosen];
  }
done:
  free(lay);
  free(tt);
  free(rank);
  return st;
}

/* The chosen candidate c with layout L as the plan: order, margins, tilts and poses, the whole
 * stack's believed CoM centred over B's middle. */
static void plan_fill(const ctx_t *x, const cand_t *c, const layout_t *L, stack_plan_t *out) {
  const size_t count = x->count;
  double cm[3] = {0, 0, 0}, mt = 0.0;
  for (size_t k = 0; k < count; ++k) {
    const obj_t *o = &x->obj[c->obj[k]];
    double w[3];
    mat_vec(c->rot[k], o->in->com_m, w);
    for (int i = 0; i < 3; ++i) cm[i] += o->in->mass_kg * (w[i] + L->pos[k][i]);
    mt += o->in->mass_kg;
  }
  out->count = count;
  for (size_t k = 0; k < count; ++k) {
    const size_t i = c->obj[k];
    out->order[k] = i;
    out->margin_m[k] = L->margin[k];
    out->tilt_rad[k] = L->tilt[k];
    model_pose_t *p = &out->pose[i];
    model_rot_to_quat(c->rot[k], p->orientation_wxyz);
    p->position_m[0] = L->pos[k][0] - cm[0] / mt;
    p->position_m[1] = L->pos[k][1] - cm[1] / mt;
    p->position_m[2] = L->pos[k][2];
  }
}

/* Exact touching poses, 1 um pre-penetrated, from the real meshes: each object set onto the one
 * below (balance_stack_pose_above) must land within 20 um of the planned contact. Returns
 * STACK_OK or STACK_E_GEOMETRY (msg says where). */
static stack_status_t poses_settle(const stack_object_t *objects, const cand_t *c, size_t count,
                                   stack_plan_t *out) {
  out->pose[c->obj[0]].position_m[2] -= 1e-6;
  for (size_t k = 1; k < count; ++k) {
    const size_t lo = c->obj[k - 1], i = c->obj[k];
    model_pose_t *p = &out->pose[i];
    const double planned_z = p->position_m[2] - 1e-6 * (double)(k + 1);
    const double origin[3] = {0, 0, 0}, at[2] = {p->position_m[0], p->position_m[1]};
    model_pose_t exact;
    balance_status_t bs =
        balance_stack_pose_above(objects[lo].mesh_link, &out->pose[lo], objects[i].mesh_link,
                                 p->orientation_wxyz, origin, at, 1e-6, &exact);
    if (bs != BALANCE_OK) {
      snprintf(out->msg, sizeof out->msg, "level %zu: setting object %zu onto %zu: %s", k, i, lo,
               balance_status_str(bs));
      return STACK_E_GEOMETRY;
    }
    if (fabs(exact.position_m[2] - planned_z) > 2e-5) {
      snprintf(out->msg, sizeof out->msg,
               "level %zu: object %zu touches %zu %.3f mm from the planned contact", k, i, lo,
               1e3 * (exact.position_m[2] - planned_z));
      return STACK_E_GEOMETRY;
    }
    *p = exact;
  }
  return STACK_OK;
}

stack_status_t stack_plan(const stack_object_t *objects, size_t count,
                          const stack_plan_config_t *cfg_in, stack_plan_t *out) {
  if (out == NULL) return STACK_E_ARG;
  memset(out, 0, sizeof *out);
  if (objects == NULL || count < 2 || count > STACK_MAX_OBJECTS) {
    snprintf(out->msg, sizeof out->msg, "need 2..%d objects", STACK_MAX_OBJECTS);
    return STACK_E_ARG;
  }
  stack_plan_config_t cfg;
  if (cfg_in)
    cfg = *cfg_in;
  else
    stack_plan_config_default(&cfg);
  stack_status_t st = check_input(objects, count, &cfg, out->msg, sizeof out->msg);
  if (st != STACK_OK) return st;

  ctx_t *x = calloc(1, sizeof *x);
  cand_t *beam = malloc(BEAM_WIDTH * sizeof *beam), *next = malloc(BEAM_WIDTH * sizeof *next);
  if (!x || !beam || !next) {
    free(x);
    free(beam);
    free(next);
    return STACK_E_NOMEM;
  }
  st = ctx_init(x, objects, count, &cfg, out->msg, sizeof out->msg);
  const size_t nbeam = st == STACK_OK ? beam_search(x, &beam, &next) : 0;
  if (st == STACK_OK && nbeam == 0) {
    snprintf(out->msg, sizeof out->msg,
             "no order of the objects gives each one a face over a facet of the one below within "
             "%.1f deg of level with its CoM inside",
             cfg.max_tilt_rad * 180.0 / CL_PI);
    st = STACK_E_NOPLAN;
  }
  size_t chosen = SIZE_MAX;
  layout_t L;
  if (st == STACK_OK) {
    qsort(beam, nbeam, sizeof *beam, cand_cmp);
    st = layout_choose(x, beam, nbeam, &chosen, &L, out->msg, sizeof out->msg);
  }
  if (st == STACK_OK) {
    plan_fill(x, &beam[chosen], &L, out);
    st = poses_settle(objects, &beam[chosen], count, out);
  }
  ctx_free(x);
  free(beam);
  free(next);
  if (st != STACK_OK) out->count = 0;
  return st;
}
