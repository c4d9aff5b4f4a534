/* check_shapegen: the adversarial test objects (tools/shapegen.h, `comlearn-shapegen`).
 *
 * Requirements (docs/assets.md, "Adversarial shapes"): for every family and several seeds the
 * acceptance rule holds (closed, nothing repaired, hull, plausible mass properties, a resting face
 * with >= 1 mm margin for both materials, the dense region moves the CoM 2-6 mm); a seed names one
 * mesh bit for bit; volume and CoM equal closed forms computed here from the spec's parameters
 * (boxes, slabs with square feet or facets, solids of revolution; bounds for round feet, the mug's
 * handle, the torus against the ideal one and the scanned box against its noise); each family's
 * defining feature holds (feet: separate coplanar contact groups; ring: no flat triangle at the
 * bottom; rim: annuli; mug: genus 1, open; pebble: no flat face; scanned: faces no longer planar;
 * plate: thin or many-sided; tilted: facets at 0.1-1 degree); the written files load back with the
 * generator's mass properties; the command line answers --help, --version and refuses bad
 * arguments. */
#define _POSIX_C_SOURCE 200809L
#include <check.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "comlearn/math3d.h"
#include "comlearn/model.h"
#include "comlearn/model_inertial.h"
#include "file_test_util.h"
#include "model_test_util.h"
#include "shapegen.h"

enum { SEEDS = 5 };
static const double MM = 1e-3;

static void gen(int family, uint64_t seed, shapegen_object_t *o) {
  const model_status_t st = shapegen_generate((shapegen_family_t)family, seed, o);
  ck_assert_msg(st == MODEL_OK, "%s seed %llu: %s", shapegen_family_name((shapegen_family_t)family),
                (unsigned long long)seed, model_status_str(st));
}

/* float32 through a volatile (GCC may drop a plain (double)(float) round trip, tools/rockgen.c) */
static double to_f32(double x) {
  volatile float f = (float)x;
  return (double)f;
}

static void bbox(const model_mesh_t *m, double lo[3], double hi[3]) {
  for (int k = 0; k < 3; ++k) lo[k] = HUGE_VAL, hi[k] = -HUGE_VAL;
  for (size_t v = 0; v < m->vertex_count; ++v) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = fmin(lo[k], m->vertices_m[v][k]);
      hi[k] = fmax(hi[k], m->vertices_m[v][k]);
    }
  }
}

static double tri_area(const model_mesh_t *m, size_t t, double n[3]) {
  const double *a = m->vertices_m[m->triangles[t][0]], *b = m->vertices_m[m->triangles[t][1]],
               *c = m->vertices_m[m->triangles[t][2]];
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  double x[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
  const double len = sqrt(cl_vec3_dot(x, x));
  if (n != NULL) {
    for (int k = 0; k < 3; ++k) n[k] = x[k] / len;
  }
  return 0.5 * len;
}

/* Euler characteristic of a closed triangle mesh: V - E + F with E = 3F/2. */
static long euler(const model_mesh_t *m) {
  return (long)m->vertex_count - (long)m->triangle_count / 2;
}

/* ---- edge-connected groups of selected triangles ------------------------------------------- */

static size_t uf_find(size_t *p, size_t i) {
  while (p[i] != i) i = p[i] = p[p[i]];
  return i;
}

typedef struct {
  unsigned long long key;
  size_t tri;
} edge_t;

static int cmp_edge(const void *a, const void *b) {
  const edge_t *x = a, *y = b;
  return x->key < y->key ? -1 : x->key > y->key;
}

/* Group the triangles with sel[t] != 0 by shared edges: group id per triangle into grp (or
 * SIZE_MAX), number of groups returned. */
static size_t groups_find(const model_mesh_t *m, const unsigned char *sel, size_t *grp) {
  const size_t nt = m->triangle_count;
  size_t *parent = malloc(nt * sizeof *parent);
  edge_t *e = malloc(3 * nt * sizeof *e);
  ck_assert(parent != NULL && e != NULL);
  size_t ne = 0;
  for (size_t t = 0; t < nt; ++t) {
    parent[t] = t;
    if (!sel[t]) continue;
    for (int k = 0; k < 3; ++k) {
      unsigned long long a = m->triangles[t][k], b = m->triangles[t][(k + 1) % 3];
      if (a > b) {
        const unsigned long long s = a;
        a = b;
        b = s;
      }
      e[ne].key = (a << 32) | b;
      e[ne++].tri = t;
    }
  }
  qsort(e, ne, sizeof *e, cmp_edge);
  for (size_t i = 0; i + 1 < ne; ++i) {
    if (e[i].key == e[i + 1].key) parent[uf_find(parent, e[i].tri)] = uf_find(parent, e[i + 1].tri);
  }
  size_t count = 0;
  for (size_t t = 0; t < nt; ++t) grp[t] = SIZE_MAX;
  for (size_t t = 0; t < nt; ++t) {
    if (!sel[t] || uf_find(parent, t) != t) continue;
    grp[t] = count++;
  }
  for (size_t t = 0; t < nt; ++t) {
    if (sel[t]) grp[t] = grp[uf_find(parent, t)];
  }
  free(parent);
  free(e);
  return count;
}

/* Triangles whose three vertices have z == z exactly (a plane of the link frame). */
static unsigned char *select_plane(const model_mesh_t *m, double z, size_t *count) {
  unsigned char *sel = calloc(m->triangle_count, 1);
  ck_assert_ptr_nonnull(sel);
  *count = 0;
  for (size_t t = 0; t < m->triangle_count; ++t) {
    int in = 1;
    for (int k = 0; k < 3; ++k) in = in && m->vertices_m[m->triangles[t][k]][2] == z;
    sel[t] = (unsigned char)in;
    *count += (size_t)in;
  }
  return sel;
}

typedef struct {
  size_t count;              /* groups */
  double area[8];            /* real area per group (the first 8) */
  double hull_area[8];       /* area of the convex hull of each group's vertices */
  double area_all, hull_all; /* all groups together */
  double gap_m;              /* smallest distance between vertices of different groups */
} plane_groups_t;

static void plane_groups(const model_mesh_t *m, double z, plane_groups_t *out) {
  memset(out, 0, sizeof *out);
  size_t nsel = 0;
  unsigned char *sel = select_plane(m, z, &nsel);
  size_t *grp = malloc(m->triangle_count * sizeof *grp);
  ck_assert_ptr_nonnull(grp);
  out->count = groups_find(m, sel, grp);
  double(*pts)[2] = malloc((3 * nsel + 1) * sizeof *pts);
  double(*h)[2] = malloc((3 * nsel + 2) * sizeof *h);
  size_t *owner = malloc((3 * nsel + 1) * sizeof *owner);
  ck_assert(pts != NULL && h != NULL && owner != NULL);
  for (size_t g = 0; g <= out->count && g <= 8; ++g) {
    size_t np = 0;
    double area = 0.0;
    for (size_t t = 0; t < m->triangle_count; ++t) {
      if (!sel[t] || (g < out->count && grp[t] != g)) continue;
      area += tri_area(m, t, NULL);
      for (int k = 0; k < 3; ++k) {
        pts[np][0] = m->vertices_m[m->triangles[t][k]][0];
        pts[np][1] = m->vertices_m[m->triangles[t][k]][1];
        owner[np++] = grp[t];
      }
    }
    if (g == out->count) {
      out->area_all = area;
      out->gap_m = HUGE_VAL;
      for (size_t i = 0; i < np; ++i) {
        for (size_t j = i + 1; j < np; ++j) {
          if (owner[i] == owner[j]) continue;
          out->gap_m = fmin(out->gap_m, hypot(pts[i][0] - pts[j][0], pts[i][1] - pts[j][1]));
        }
      }
    }
    const size_t nh = model_polygon_hull(pts, np, h);
    const double ha = model_polygon_area((const double(*)[2])h, nh);
    if (g == out->count) {
      out->hull_all = ha;
    } else if (g < 8) {
      out->area[g] = area;
      out->hull_area[g] = ha;
    }
  }
  free(pts);
  free(h);
  free(owner);
  free(grp);
  free(sel);
}

/* ---- hull planes --------------------------------------------------------------------------- */

enum { PLANES_MAX = 4096 };
typedef struct {
  size_t count;
  double n[PLANES_MAX][3];
  double area[PLANES_MAX];
} planes_t;

static void hull_planes(const model_mesh_t *m, planes_t *p) {
  model_mesh_t hull;
  ck_assert_int_eq(model_mesh_hull(m, &hull, NULL), MODEL_OK);
  p->count = 0;
  for (size_t t = 0; t < hull.triangle_count; ++t) {
    double n[3];
    const double a = tri_area(&hull, t, n);
    const double h = cl_vec3_dot(n, hull.vertices_m[hull.triangles[t][0]]);
    size_t i = 0;
    for (; i < p->count; ++i) {
      const double hi = cl_vec3_dot(p->n[i], hull.vertices_m[hull.triangles[t][0]]);
      if (cl_vec3_dot(n, p->n[i]) > 1.0 - 1e-12 && fabs(hi - h) < 1e-7) break;
    }
    if (i == p->count) {
      ck_assert_uint_lt(p->count, PLANES_MAX);
      memcpy(p->n[p->count], n, sizeof n);
      p->area[p->count++] = 0.0;
    }
    p->area[i] += a;
  }
  model_mesh_free(&hull);
}

/* ---- the rule ------------------------------------------------------------------------------ */

START_TEST(trig_exact_and_accurate) {
  static const long ns[] = {3, 7, 12, 64, 96, 100, 127, 128, 1000};
  for (size_t i = 0; i < sizeof ns / sizeof ns[0]; ++i) {
    const long n = ns[i];
    for (long j = -n; j <= 2 * n; ++j) {
      double c, s;
      shapegen_cos_sin_turn(j, n, &c, &s);
      const double a = 2.0 * CL_PI * (double)j / (double)n;
      const double tol = 2.5e-16 * (1.0 + fabs(a)); /* a itself is rounded */
      ck_assert_msg(fabs(c - cos(a)) <= tol && fabs(s - sin(a)) <= tol, "j %ld n %ld", j, n);
    }
  }
  double c, s;
  shapegen_cos_sin_turn(0, 96, &c, &s);
  ck_assert(c == 1.0 && s == 0.0 && !signbit(s));
  shapegen_cos_sin_turn(24, 96, &c, &s);
  ck_assert(c == 0.0 && s == 1.0 && !signbit(c));
  shapegen_cos_sin_turn(-48, 96, &c, &s);
  ck_assert(c == -1.0 && s == 0.0);
  /* the polygon is symmetric: j and n - j are mirror images */
  for (long j = 0; j < 128; ++j) {
    double c2, s2;
    shapegen_cos_sin_turn(j, 128, &c, &s);
    shapegen_cos_sin_turn(128 - j, 128, &c2, &s2);
    ck_assert(c == c2 && s == -s2);
  }
}
END_TEST

START_TEST(names_and_bad_arguments) {
  for (unsigned f = 0; f < SHAPEGEN_FAMILY_COUNT; ++f) {
    shapegen_family_t back;
    const char *name = shapegen_family_name((shapegen_family_t)f);
    ck_assert_ptr_nonnull(name);
    ck_assert_int_eq(shapegen_family_parse(name, &back), 0);
    ck_assert_int_eq(back, f);
  }
  shapegen_family_t f;
  ck_assert_ptr_null(shapegen_family_name(SHAPEGEN_FAMILY_COUNT));
  ck_assert_int_eq(shapegen_family_parse("all", &f), -1);
  ck_assert_int_eq(shapegen_family_parse(NULL, &f), -1);
  shapegen_object_t o;
  shapegen_spec_t s;
  ck_assert_int_eq(shapegen_generate(SHAPEGEN_FAMILY_COUNT, 1, &o), MODEL_E_ARG);
  ck_assert_int_eq(shapegen_generate(SHAPEGEN_BOX, 1, NULL), MODEL_E_ARG);
  ck_assert_int_eq(shapegen_spec_draw(SHAPEGEN_BOX, 1, 0, NULL), MODEL_E_ARG);
  ck_assert_int_eq(shapegen_spec_draw((shapegen_family_t)-1, 1, 0, &s), MODEL_E_ARG);
  int ok = 1;
  ck_assert_int_eq(shapegen_accept(NULL, &ok, &o), MODEL_E_ARG);
  /* an invalid spec is "not accepted", not an error */
  ck_assert_int_eq(shapegen_spec_draw(SHAPEGEN_FEET2, 1, 0, &s), MODEL_OK);
  s.slab.top0_m = -1.0;
  ck_assert_int_eq(shapegen_accept(&s, &ok, &o), MODEL_OK);
  ck_assert_int_eq(ok, 0);
  ck_assert_ptr_null(o.mesh.vertices_m);
  model_mesh_t m;
  ck_assert_int_eq(shapegen_shape_build(&s, &m), MODEL_E_ARG);
}
END_TEST

/* The rule, checked again from outside for every family (_i) and seed. */
START_TEST(every_family_accepted) {
  for (uint64_t seed = 1; seed <= SEEDS; ++seed) {
    shapegen_object_t o;
    gen(_i, seed, &o);
    const char *name = o.spec.name;
    char want[64];
    snprintf(want, sizeof want, "%s_s%llu", shapegen_family_name((shapegen_family_t)_i),
             (unsigned long long)seed);
    ck_assert_str_eq(name, want);
    ck_assert_int_eq(o.spec.family, _i);
    ck_assert_uint_lt(o.spec.attempt, SHAPEGEN_MAX_ATTEMPTS);
    /* closed, outward, nothing to repair */
    model_mesh_t copy;
    model_mesh_report_t rep;
    model_error_t err = {{0}};
    ck_assert_int_eq(model_mesh_copy(&o.mesh, &copy), MODEL_OK);
    ck_assert_msg(model_mesh_check(&copy, &rep, &err) == MODEL_OK, "%s: %s", name, err.msg);
    ck_assert_uint_eq(rep.merged_vertices + rep.removed_degenerate + rep.removed_unreferenced, 0);
    ck_assert_int_eq(rep.flipped, 0);
    ck_assert_uint_eq(copy.vertex_count, o.mesh.vertex_count);
    model_mesh_free(&copy);
    /* size, frame, materials */
    double lo[3], hi[3], ext = 0.0;
    bbox(&o.mesh, lo, hi);
    for (int k = 0; k < 3; ++k) {
      ext = fmax(ext, hi[k] - lo[k]);
      ck_assert_msg(fabs(hi[k] + lo[k]) <= 1e-8, "%s: bbox center %d %.3g", name, k, hi[k] + lo[k]);
    }
    ck_assert_msg(ext >= 0.020 && ext <= 0.120, "%s: extent %.4f m", name, ext);
    ck_assert(o.spec.density_kg_m3 >= 700.0 && o.spec.density_kg_m3 <= 2700.0);
    ck_assert(o.spec.region_ratio >= 1.5 && o.spec.region_ratio <= 3.0);
    /* masses: even is the mesh at the density; uneven is the documented half-space */
    model_mass_t e, u;
    ck_assert_int_eq(model_mesh_mass(&o.mesh, o.spec.density_kg_m3, &e), MODEL_OK);
    ck_assert_double_eq_tol(e.mass_kg, o.even.mass_kg, 1e-12 * e.mass_kg);
    ck_assert_double_eq_tol(cl_vec3_dot(o.region.normal, o.region.normal), 1.0, 1e-12);
    ck_assert_int_eq(model_mesh_mass_halfspace(&o.mesh, o.spec.density_kg_m3, &o.region,
                                               o.spec.density_kg_m3 * o.spec.region_ratio, &u),
                     MODEL_OK);
    ck_assert_double_eq_tol(u.mass_kg, o.uneven.mass_kg, 1e-12 * u.mass_kg);
    const double shift = cl_vec3_dist(u.com_m, e.com_m);
    ck_assert_msg(shift >= SHAPEGEN_SHIFT_MIN_M - 1e-9 && shift <= SHAPEGEN_SHIFT_MAX_M + 1e-9,
                  "%s: shift %.4g m", name, shift);
    const double d[3] = {u.com_m[0] - e.com_m[0], u.com_m[1] - e.com_m[1], u.com_m[2] - e.com_m[2]};
    ck_assert(cl_vec3_dot(d, o.region.normal) > 0.0); /* towards the dense side */
    ck_assert(u.mass_kg > e.mass_kg && e.mass_kg >= MODEL_MASS_MIN_KG);
    ck_assert_int_eq(model_mass_plausible(&e, &o.mesh, NULL), MODEL_OK);
    ck_assert_int_eq(model_mass_plausible(&u, &o.mesh, NULL), MODEL_OK);
    /* it can rest somewhere, for either material */
    model_mesh_t hull;
    ck_assert_int_eq(model_mesh_hull(&o.mesh, &hull, NULL), MODEL_OK);
    double me = 0.0, mu = 0.0, n[3];
    ck_assert_int_eq(shapegen_rest_margin(&o.mesh, &hull, e.com_m, &me, n), MODEL_OK);
    ck_assert_int_eq(shapegen_rest_margin(&o.mesh, &hull, u.com_m, &mu, NULL), MODEL_OK);
    ck_assert_msg(me >= SHAPEGEN_MIN_MARGIN_M && mu >= SHAPEGEN_MIN_MARGIN_M,
                  "%s: margins %.4g %.4g m", name, me, mu);
    ck_assert_double_eq(me, o.margin_even_m);
    model_mesh_free(&hull);
    shapegen_object_free(&o);
  }
}
END_TEST

/* Same seed, same mesh bit for bit; another seed, another mesh; the documented redraw rule. */
START_TEST(deterministic_and_rule) {
  shapegen_object_t a, b;
  gen(_i, 7, &a);
  gen(_i, 7, &b);
  ck_assert_uint_eq(a.mesh.vertex_count, b.mesh.vertex_count);
  ck_assert_uint_eq(a.mesh.triangle_count, b.mesh.triangle_count);
  ck_assert_int_eq(
      memcmp(a.mesh.vertices_m, b.mesh.vertices_m, a.mesh.vertex_count * sizeof *a.mesh.vertices_m),
      0);
  ck_assert_int_eq(
      memcmp(a.mesh.triangles, b.mesh.triangles, a.mesh.triangle_count * sizeof *a.mesh.triangles),
      0);
  ck_assert_int_eq(memcmp(&a.spec, &b.spec, sizeof a.spec), 0);
  ck_assert_int_eq(memcmp(&a.uneven, &b.uneven, sizeof a.uneven), 0);
  shapegen_object_free(&b);
  gen(_i, 8, &b);
  ck_assert(a.mesh.vertex_count != b.mesh.vertex_count ||
            memcmp(a.mesh.vertices_m, b.mesh.vertices_m,
                   a.mesh.vertex_count * sizeof *a.mesh.vertices_m) != 0);
  shapegen_object_free(&b);
  /* shapegen_generate is the first accepted attempt */
  unsigned k = 0;
  int ok = 0;
  shapegen_spec_t *s = malloc(sizeof *s);
  ck_assert_ptr_nonnull(s);
  for (; k < SHAPEGEN_MAX_ATTEMPTS && !ok; ++k) {
    const model_status_t st = shapegen_spec_draw((shapegen_family_t)_i, 7, k, s);
    if (st == MODEL_E_DEGENERATE) continue;
    ck_assert_int_eq(st, MODEL_OK);
    ck_assert_int_eq(shapegen_accept(s, &ok, &b), MODEL_OK);
  }
  ck_assert(ok);
  ck_assert_uint_eq(k - 1, a.spec.attempt);
  ck_assert_int_eq(
      memcmp(b.mesh.vertices_m, a.mesh.vertices_m, a.mesh.vertex_count * sizeof *a.mesh.vertices_m),
      0);
  free(s);
  shapegen_object_free(&b);
  shapegen_object_free(&a);
}
END_TEST

/* ---- closed forms -------------------------------------------------------------------------- */

/* Integrals of a piecewise-linear function (values f at lines x) over [x_0, x_n]. */
static double pl_i0(const double *x, const double *f, size_t n) {
  double s = 0.0;
  for (size_t i = 0; i + 1 < n; ++i) s += 0.5 * (x[i + 1] - x[i]) * (f[i] + f[i + 1]);
  return s;
}

static double pl_i1(const double *x, const double *f, size_t n) { /* integral of x f */
  double s = 0.0;
  for (size_t i = 0; i + 1 < n; ++i) {
    s +=
        (x[i + 1] - x[i]) / 6.0 * (x[i] * (2 * f[i] + f[i + 1]) + x[i + 1] * (f[i] + 2 * f[i + 1]));
  }
  return s;
}

static double pl_i2(const double *x, const double *f, size_t n) { /* integral of f^2 */
  double s = 0.0;
  for (size_t i = 0; i + 1 < n; ++i) {
    s += (x[i + 1] - x[i]) / 3.0 * (f[i] * f[i] + f[i] * f[i + 1] + f[i + 1] * f[i + 1]);
  }
  return s;
}

/* Moments of F = a0 + p(x) + q(y) over the footprint: [0] integral of F, [1] of x F, [2] of y F,
 * [3] of F^2 / 2. */
static void separable_moments(const shapegen_slab_t *s, double a0, const double *p, const double *q,
                              double out[4]) {
  const double *x = s->lines_m[0], *y = s->lines_m[1];
  const size_t nx = s->line_count[0], ny = s->line_count[1];
  const double lx = 2.0 * s->half_m[0], ly = 2.0 * s->half_m[1];
  const double ip = pl_i0(x, p, nx), iq = pl_i0(y, q, ny);
  out[0] = a0 * lx * ly + ly * ip + lx * iq;
  out[1] = ly * pl_i1(x, p, nx); /* the integrals of a0 x and q(y) x vanish (x symmetric) */
  out[2] = lx * pl_i1(y, q, ny);
  out[3] = 0.5 * (a0 * a0 * lx * ly + ly * pl_i2(x, p, nx) + lx * pl_i2(y, q, ny) +
                  2.0 * a0 * (ly * ip + lx * iq) + 2.0 * ip * iq);
}

/* Volume and CoM (link frame) of a slab whose feet are square (or absent), exactly. */
static void slab_closed_form(const shapegen_slab_t *s, double *volume, double com[3]) {
  double t[4], b[4];
  separable_moments(s, s->top0_m, s->top_m[0], s->top_m[1], t);
  separable_moments(s, 0.0, s->bottom_m[0], s->bottom_m[1], b);
  if (s->foot_count > 0) { /* b = c min(1, d / slope): the plateau minus each foot's deficit */
    const double c = s->clearance_m, sl = s->slope_m, area = 4.0 * s->half_m[0] * s->half_m[1];
    b[0] += c * area;
    b[3] += 0.5 * c * c * area;
    for (size_t f = 0; f < s->foot_count; ++f) {
      const double hx = s->feet[f].half_m[0], hy = s->feet[f].half_m[1];
      const double d0 = c * (4 * hx * hy + 2 * sl * (hx + hy) + 4 * sl * sl / 3);
      const double d2 = c * c * (4 * hx * hy + 8 * sl * (hx + hy) / 3 + 2 * sl * sl);
      b[0] -= d0;
      b[1] -= s->feet[f].center_m[0] * d0;
      b[2] -= s->feet[f].center_m[1] * d0;
      b[3] -= 0.5 * d2;
    }
  }
  *volume = t[0] - b[0];
  double zmax = s->top0_m, zmin = 0.0;
  for (int a = 0; a < 2; ++a) {
    double tmax = -HUGE_VAL, bmin = HUGE_VAL;
    for (size_t i = 0; i < s->line_count[a]; ++i) {
      tmax = fmax(tmax, s->top_m[a][i]);
      bmin = fmin(bmin, s->bottom_m[a][i]);
    }
    zmax += tmax;
    zmin += bmin;
  }
  com[0] = (t[1] - b[1]) / *volume;
  com[1] = (t[2] - b[2]) / *volume;
  com[2] = (t[3] - b[3]) / *volume - 0.5 * (zmin + zmax);
}

/* Profile integrals of r and r z (Green's theorem on the polygon). */
static void profile_moments(const shapegen_revolve_t *rev, double *ir, double *irz) {
  *ir = *irz = 0.0;
  const size_t p = rev->point_count;
  for (size_t i = 0; i < p; ++i) {
    const double x0 = rev->rz_m[i][0], y0 = rev->rz_m[i][1];
    const double x1 = rev->rz_m[(i + 1) % p][0], y1 = rev->rz_m[(i + 1) % p][1];
    const double cr = x0 * y1 - x1 * y0;
    *ir += cr * (x0 + x1) / 6.0;
    *irz += cr * (x0 * y1 + 2 * x0 * y0 + 2 * x1 * y1 + x1 * y0) / 24.0;
  }
}

/* The revolved solid without handle: volume, CoM in the link frame. */
static void revolve_closed_form(const shapegen_spec_t *s, double *volume, double com[3]) {
  const shapegen_revolve_t *rev = &s->rev;
  const unsigned n = rev->segments;
  double ir, irz, rmax = 0.0, zlo = HUGE_VAL, zhi = -HUGE_VAL;
  profile_moments(rev, &ir, &irz);
  *volume = n * sin(2 * CL_PI / n) * ir;
  for (size_t i = 0; i < rev->point_count; ++i) {
    rmax = fmax(rmax, rev->rz_m[i][0]);
    zlo = fmin(zlo, rev->rz_m[i][1]);
    zhi = fmax(zhi, rev->rz_m[i][1]);
  }
  double xlo = HUGE_VAL, xhi = -HUGE_VAL, ylo = HUGE_VAL, yhi = -HUGE_VAL;
  for (unsigned j = 0; j < n; ++j) {
    xlo = fmin(xlo, rmax * cos(2 * CL_PI * j / n));
    xhi = fmax(xhi, rmax * cos(2 * CL_PI * j / n));
    ylo = fmin(ylo, rmax * sin(2 * CL_PI * j / n));
    yhi = fmax(yhi, rmax * sin(2 * CL_PI * j / n));
  }
  const double c_gen[3] = {0.5 * (xlo + xhi), 0.5 * (ylo + yhi), 0.5 * (zlo + zhi)};
  const double com_gen[3] = {0.0, 0.0, irz / ir};
  for (int k = 0; k < 3; ++k) com[k] = com_gen[k] - c_gen[k];
  if (s->lay_on_side) { /* (x, y, z) -> (z, y, -x) */
    const double x = com[0];
    com[0] = com[2];
    com[2] = -x;
  }
}

static void assert_com(const char *name, const double got[3], const double want[3], double tol) {
  for (int k = 0; k < 3; ++k) {
    ck_assert_msg(fabs(got[k] - want[k]) <= tol, "%s: com[%d] %.9g, closed form %.9g", name, k,
                  got[k], want[k]);
  }
}

/* An unscanned box: volume, CoM at the origin and the diagonal inertia, exactly. */
static void closed_form_box(const shapegen_spec_t *s, const model_mass_t *m) {
  const double com[3] = {0, 0, 0};
  double dim[3];
  for (int k = 0; k < 3; ++k) dim[k] = 2.0 * to_f32(0.5 * s->box.size_m[k]);
  const double v = dim[0] * dim[1] * dim[2];
  ck_assert_double_eq_tol(m->mass_kg, v, 1e-12 * v);
  assert_com(s->name, m->com_m, com, 1e-15);
  for (int k = 0; k < 3; ++k) {
    const double want =
        v / 12.0 * (dim[(k + 1) % 3] * dim[(k + 1) % 3] + dim[(k + 2) % 3] * dim[(k + 2) % 3]);
    ck_assert_double_eq_tol(m->inertia_kg_m2[k][k], want, 1e-12 * want);
    ck_assert_double_eq_tol(m->inertia_kg_m2[k][(k + 1) % 3], 0.0, 1e-12 * want);
  }
}

/* A scanned box: volume and CoM within its noise. */
static void closed_form_scanned_box(const shapegen_spec_t *s, const model_mass_t *m) {
  const double com[3] = {0, 0, 0};
  double surf = 0.0, dim[3];
  for (int k = 0; k < 3; ++k) dim[k] = s->box.size_m[k];
  const double v = dim[0] * dim[1] * dim[2];
  for (int k = 0; k < 3; ++k) surf += 2.0 * dim[(k + 1) % 3] * dim[(k + 2) % 3];
  ck_assert_msg(fabs(m->mass_kg - v) <= 2.0 * s->noise_m * surf, "%s: volume %.9g vs %.9g", s->name,
                m->mass_kg, v);
  assert_com(s->name, m->com_m, com, 2.0 * s->noise_m);
}

/* A slab: square feet against the closed form; round feet between disks of radius
 * r - 1.5 mm and r + slope + 1.5 mm. */
static void closed_form_slab(const shapegen_spec_t *s, const model_mass_t *m) {
  int round = 0;
  for (size_t f = 0; f < s->slab.foot_count; ++f) round |= s->slab.feet[f].round;
  if (!round) {
    double v = 0.0, com[3] = {0, 0, 0};
    slab_closed_form(&s->slab, &v, com);
    ck_assert_msg(fabs(m->mass_kg - v) <= 2e-6 * v, "%s: volume %.9g, closed form %.9g", s->name,
                  m->mass_kg, v);
    assert_com(s->name, m->com_m, com, 1e-7);
    return;
  }
  shapegen_slab_t bare = s->slab;
  bare.foot_count = 0;
  double v0, c0[3];
  slab_closed_form(&bare, &v0, c0);
  v0 -= s->slab.clearance_m * 4.0 * s->slab.half_m[0] * s->slab.half_m[1];
  double lo = v0, hi = v0;
  for (size_t f = 0; f < s->slab.foot_count; ++f) {
    const double r = s->slab.feet[f].half_m[0];
    lo += s->slab.clearance_m * CL_PI * (r - 1.5 * MM) * (r - 1.5 * MM);
    hi += s->slab.clearance_m * CL_PI * (r + s->slab.slope_m + 1.5 * MM) *
          (r + s->slab.slope_m + 1.5 * MM);
  }
  ck_assert_msg(m->mass_kg > lo && m->mass_kg < hi, "%s: volume %.9g not in [%.9g, %.9g]", s->name,
                m->mass_kg, lo, hi);
}

/* A solid of revolution without a handle: the closed form; a ring also against the ideal
 * elliptic torus. */
static void closed_form_revolve(const shapegen_spec_t *s, const model_mass_t *m) {
  double v = 0.0, com[3] = {0, 0, 0};
  revolve_closed_form(s, &v, com);
  ck_assert_msg(fabs(m->mass_kg - v) <= 2e-6 * v, "%s: volume %.9g, closed form %.9g", s->name,
                m->mass_kg, v);
  assert_com(s->name, m->com_m, com, 1e-7);
  if (s->family != SHAPEGEN_RING) return;
  const size_t pm = s->rev.point_count;
  const double big = s->rev.rz_m[0][0], az = -s->rev.rz_m[0][1];
  const double ar = s->rev.rz_m[pm / 4][0] - big;
  const double ideal = 2.0 * CL_PI * CL_PI * big * ar * az;
  const double n2 = (double)s->rev.segments * s->rev.segments;
  const double bound = 2.0 * CL_PI * CL_PI / 3.0 * (1.0 / n2 + 1.0 / ((double)pm * (double)pm));
  ck_assert_msg(m->mass_kg <= ideal && m->mass_kg >= ideal * (1.0 - bound),
                "%s: volume %.9g, ideal torus %.9g, bound %.3g", s->name, m->mass_kg, ideal, bound);
}

/* The mug: cup + a tube along the handle. */
static void closed_form_mug(const shapegen_object_t *o, const model_mass_t *m) {
  const shapegen_spec_t *s = &o->spec;
  double v = 0.0, com[3] = {0, 0, 0};
  revolve_closed_form(s, &v, com);
  const shapegen_handle_t *h = &s->handle;
  const unsigned n = s->rev.segments;
  const double a = h->radius_m * sin(2 * CL_PI * h->columns / n);
  const double bh = 0.5 * (s->rev.rz_m[h->upper_row + h->rows][1] - s->rev.rz_m[h->upper_row][1]);
  double len = 0.0;
  for (int k = 0; k < 1000; ++k) {
    const double p0 = CL_PI / 2 - CL_PI * k / 1000, p1 = CL_PI / 2 - CL_PI * (k + 1) / 1000;
    len += hypot(h->reach_m * (cos(p1) - cos(p0)), h->half_height_m * (sin(p1) - sin(p0)));
  }
  const double lo = v + 0.5 * CL_PI * a * bh * len, hi = v + 1.1 * 4.0 * a * bh * len;
  ck_assert_msg(m->mass_kg > lo && m->mass_kg < hi, "%s: volume %.9g not in [%.9g, %.9g]", s->name,
                m->mass_kg, lo, hi);
  /* the handle pulls the CoM off the cup's axis towards +x (the axis: min x + radius) */
  double blo[3], bhi[3];
  bbox(&o->mesh, blo, bhi);
  ck_assert_msg(m->com_m[0] - (blo[0] + h->radius_m) > 0.5 * MM, "%s: CoM x %.4g, axis %.4g",
                s->name, m->com_m[0], blo[0] + h->radius_m);
  ck_assert_double_eq_tol(m->com_m[1], 0.0, 1e-9);
}

START_TEST(closed_forms) {
  for (uint64_t seed = 1; seed <= SEEDS; ++seed) {
    shapegen_object_t o;
    gen(_i, seed, &o);
    const shapegen_spec_t *s = &o.spec;
    model_mass_t m;
    ck_assert_int_eq(model_mesh_mass(&o.mesh, 1.0, &m), MODEL_OK);
    if (s->shape == SHAPEGEN_SHAPE_BOX && s->noise_m == 0.0) {
      closed_form_box(s, &m);
    } else if (s->shape == SHAPEGEN_SHAPE_BOX) {
      closed_form_scanned_box(s, &m);
    } else if (s->shape == SHAPEGEN_SHAPE_SLAB) {
      closed_form_slab(s, &m);
    } else if (s->shape == SHAPEGEN_SHAPE_REVOLVE && !s->handle.present) {
      closed_form_revolve(s, &m);
    } else if (s->shape == SHAPEGEN_SHAPE_REVOLVE) {
      closed_form_mug(&o, &m);
    }
    shapegen_object_free(&o);
  }
}
END_TEST

/* ---- the defining features ---------------------------------------------------------------- */

static void feature_feet(const shapegen_object_t *o) {
  const char *name = o->spec.name;
  double lo[3], hi[3];
  bbox(&o->mesh, lo, hi);
  plane_groups_t g;
  plane_groups(&o->mesh, lo[2], &g);
  ck_assert_msg(g.count == o->spec.slab.foot_count, "%s: %zu contact groups, %zu feet", name,
                g.count, o->spec.slab.foot_count);
  ck_assert_msg(g.gap_m >= 10 * MM, "%s: feet %.2f mm apart", name, g.gap_m / MM);
  /* the hull face under it spans all feet; the real contact is a fraction of it */
  ck_assert_msg(g.hull_all >= 1.4 * g.area_all, "%s: hull %.1f mm^2, contact %.1f mm^2", name,
                g.hull_all / (MM * MM), g.area_all / (MM * MM));
  /* each foot is flat and compact: its own hull is nearly its area (round: pixelated) */
  for (size_t i = 0; i < g.count && i < 8; ++i) {
    ck_assert_msg(g.area[i] >= 0.8 * g.hull_area[i] && g.area[i] >= 10 * MM * MM,
                  "%s: foot %zu area %.2f mm^2, hull %.2f", name, i, g.area[i] / (MM * MM),
                  g.hull_area[i] / (MM * MM));
  }
}

static void feature_ring(const shapegen_object_t *o) {
  const char *name = o->spec.name;
  double lo[3], hi[3];
  bbox(&o->mesh, lo, hi);
  size_t n = 0;
  free(select_plane(&o->mesh, lo[2], &n));
  ck_assert_msg(n == 0, "%s: %zu triangles in the resting plane", name, n);
  size_t ring = 0;
  for (size_t v = 0; v < o->mesh.vertex_count; ++v) ring += o->mesh.vertices_m[v][2] == lo[2];
  ck_assert_uint_eq(ring, o->spec.rev.segments); /* a ring of vertices, nothing else */
  ck_assert_int_eq(euler(&o->mesh), 0);          /* genus 1 */
  /* it rests on that ring: the CoM is inside the hull of the bottom vertices */
  double(*p)[2] = malloc((ring + 1) * sizeof *p), (*h)[2] = malloc((ring + 2) * sizeof *h);
  size_t np = 0;
  for (size_t v = 0; v < o->mesh.vertex_count; ++v) {
    if (o->mesh.vertices_m[v][2] != lo[2]) continue;
    p[np][0] = o->mesh.vertices_m[v][0];
    p[np++][1] = o->mesh.vertices_m[v][1];
  }
  const size_t nh = model_polygon_hull(p, np, h);
  ck_assert(model_polygon_margin((const double(*)[2])h, nh, o->even.com_m) >= 5 * MM);
  free(p);
  free(h);
}

static void feature_rim(const shapegen_object_t *o) {
  const char *name = o->spec.name;
  double lo[3], hi[3];
  bbox(&o->mesh, lo, hi);
  plane_groups_t g;
  plane_groups(&o->mesh, lo[2], &g);
  ck_assert_uint_eq(g.count, 1);
  ck_assert_msg(g.hull_area[0] >= 2.5 * g.area[0], "%s: foot ring area %.1f, hull %.1f mm^2", name,
                g.area[0] / (MM * MM), g.hull_area[0] / (MM * MM));
  plane_groups(&o->mesh, hi[2], &g);
  ck_assert_uint_eq(g.count, 1);
  ck_assert_msg(g.hull_area[0] >= 2.0 * g.area[0], "%s: top rim area %.1f, hull %.1f mm^2", name,
                g.area[0] / (MM * MM), g.hull_area[0] / (MM * MM));
  ck_assert_int_eq(euler(&o->mesh), 2);
}

static void feature_mug(const shapegen_object_t *o) {
  const char *name = o->spec.name;
  const model_mesh_t *m = &o->mesh;
  ck_assert_int_eq(euler(m), 0); /* the handle is part of the one surface: genus 1 */
  unsigned char *all = malloc(m->triangle_count);
  size_t *grp = malloc(m->triangle_count * sizeof *grp);
  memset(all, 1, m->triangle_count);
  ck_assert_uint_eq(groups_find(m, all, grp), 1); /* one shell */
  free(all);
  free(grp);
  double lo[3], hi[3];
  bbox(m, lo, hi);
  /* open: upward flat triangles at the rim and at an inner floor far below it */
  int rim = 0, floor_found = 0;
  for (size_t t = 0; t < m->triangle_count; ++t) {
    double n[3];
    tri_area(m, t, n);
    const double z = m->vertices_m[m->triangles[t][0]][2];
    if (n[2] < 1.0 - 1e-9 || m->vertices_m[m->triangles[t][1]][2] != z ||
        m->vertices_m[m->triangles[t][2]][2] != z)
      continue;
    rim |= z == hi[2];
    floor_found |= z > lo[2] + 3 * MM && z < hi[2] - 30 * MM;
  }
  ck_assert_msg(rim && floor_found, "%s: rim %d floor %d", name, rim, floor_found);
  plane_groups_t g;
  plane_groups(m, lo[2], &g);
  ck_assert_uint_eq(g.count, 1);
  if (strstr(o->spec.variant, "foot ring") != NULL) {
    ck_assert_msg(g.hull_area[0] >= 1.8 * g.area[0], "%s: foot ring %.1f, hull %.1f", name,
                  g.area[0] / (MM * MM), g.hull_area[0] / (MM * MM));
  } else {
    ck_assert_msg(g.hull_area[0] <= 1.001 * g.area[0], "%s: bottom disk %.1f, hull %.1f", name,
                  g.area[0] / (MM * MM), g.hull_area[0] / (MM * MM));
  }
  ck_assert(hi[0] - lo[0] >= 2.0 * o->spec.handle.radius_m + 10 * MM); /* the handle sticks out */
}

/* All planar patches of a mesh (rockgen_patches_find, 1 um / 1.4e-4 rad), any size. */
static rockgen_patch_t *all_patches(const model_mesh_t *m, size_t *count) {
  rockgen_patch_t *p = malloc(m->triangle_count * sizeof *p);
  ck_assert_ptr_nonnull(p);
  ck_assert_int_eq(rockgen_patches_find(m, 0.0, p, m->triangle_count, count), MODEL_OK);
  ck_assert_uint_le(*count, m->triangle_count);
  return p;
}

static void feature_pebble(const shapegen_object_t *o) {
  size_t count = 0, pairs = 0;
  rockgen_patch_t *p = all_patches(&o->mesh, &count);
  for (size_t i = 0; i < count; ++i) {
    ck_assert_msg(p[i].triangle_count <= 2, "%s: a flat face of %zu triangles", o->spec.name,
                  p[i].triangle_count);
    pairs += p[i].triangle_count == 2;
  }
  ck_assert_msg(pairs * 50 <= o->mesh.triangle_count, "%s: %zu coplanar pairs", o->spec.name,
                pairs);
  free(p);
}

static void feature_lumpy(const shapegen_object_t *o) {
  const rockgen_spec_t *r = &o->spec.rock;
  size_t count = 0, faces = 0;
  rockgen_patch_t *p = all_patches(&o->mesh, &count);
  for (size_t i = 0; i < count; ++i) {
    if (p[i].triangle_count < 3) continue;
    ++faces;
    ck_assert_msg(p[i].width_m <= 25 * MM, "%s: a face %.1f mm wide", o->spec.name,
                  p[i].width_m / MM);
    int fracture = 0; /* every flat face is one of the fracture planes */
    for (size_t f = 0; f < r->fracture_count; ++f) {
      const double *n = r->fractures[f].normal;
      fracture |= cl_vec3_dot(n, p[i].normal) / sqrt(cl_vec3_dot(n, n)) > 1.0 - 1e-6;
    }
    ck_assert_msg(fracture, "%s: a flat face off every fracture plane", o->spec.name);
  }
  ck_assert_msg(faces >= 1 && faces <= 2 * r->fracture_count, "%s: %zu faces, %zu fractures",
                o->spec.name, faces, r->fracture_count);
  free(p);
}

static void feature_scanned(const shapegen_object_t *o) {
  const char *name = o->spec.name;
  shapegen_spec_t clean = o->spec;
  clean.noise_m = 0.0;
  model_mesh_t ideal;
  ck_assert_int_eq(shapegen_shape_build(&clean, &ideal), MODEL_OK);
  ck_assert_uint_eq(ideal.vertex_count, o->mesh.vertex_count);
  /* the noise is in its band: vertex by vertex, up to the re-centering */
  const double a = o->spec.noise_m;
  double worst = 0.0;
  for (size_t v = 0; v < ideal.vertex_count; ++v) {
    for (int k = 0; k < 3; ++k) {
      const double d = fabs(o->mesh.vertices_m[v][k] - ideal.vertices_m[v][k]);
      ck_assert_msg(d <= 2.0 * a + 1e-8, "%s: vertex %zu moved %.3g m", name, v, d);
      worst = fmax(worst, d);
    }
  }
  ck_assert_msg(worst >= 0.5 * a, "%s: noise %.3g m, largest move %.3g m", name, a, worst);
  /* no face survives: the largest planar patch is a small fraction of the ideal's */
  size_t ni = 0, nn = 0;
  rockgen_patch_t *pi = all_patches(&ideal, &ni), *pn = all_patches(&o->mesh, &nn);
  double big_i = 0.0, big_n = 0.0;
  for (size_t i = 0; i < ni; ++i) big_i = fmax(big_i, pi[i].area_m2);
  for (size_t i = 0; i < nn; ++i) big_n = fmax(big_n, pn[i].area_m2);
  ck_assert_msg(big_n <= 0.25 * big_i, "%s: largest flat patch %.1f mm^2, without noise %.1f", name,
                big_n / (MM * MM), big_i / (MM * MM));
  if (o->spec.shape == SHAPEGEN_SHAPE_BOX) {
    ck_assert_uint_eq(ni, 6);
    ck_assert_uint_ge(o->mesh.triangle_count, 6 * 2 * 4); /* finely tessellated */
  }
  free(pi);
  free(pn);
  model_mesh_free(&ideal);
}

static void feature_plate(const shapegen_object_t *o) {
  const char *name = o->spec.name, *var = o->spec.variant;
  double lo[3], hi[3], e[3];
  bbox(&o->mesh, lo, hi);
  for (int k = 0; k < 3; ++k) e[k] = hi[k] - lo[k];
  const double emin = fmin(e[0], fmin(e[1], e[2])), emax = fmax(e[0], fmax(e[1], e[2]));
  if (strstr(var, "thin") != NULL) {
    ck_assert_msg(emin >= 2 * MM - 1e-9 && emin <= 4 * MM + 1e-9, "%s: %.2f mm thick", name,
                  emin / MM);
    ck_assert(emax >= 20 * MM);
  } else if (strstr(var, "bar") != NULL) {
    ck_assert(emax >= 60 * MM && e[1] <= 10 * MM + 1e-9 && e[2] <= 10 * MM + 1e-9);
  }
  if (o->spec.shape == SHAPEGEN_SHAPE_REVOLVE) { /* N side facets at 360/N degrees + 2 caps */
    const unsigned n = o->spec.rev.segments;
    ck_assert(n >= 64 && n <= 128);
    planes_t *p = malloc(sizeof *p);
    hull_planes(&o->mesh, p);
    ck_assert_msg(p->count == n + 2, "%s: %zu hull planes, %u sides", name, p->count, n);
    free(p);
  } else {
    ck_assert_uint_eq(o->mesh.triangle_count, 12);
  }
}

/* Number of linear pieces of a piecewise-linear function sampled at lines. */
static size_t pl_pieces(const double *x, const double *f, size_t n) {
  size_t pieces = 1;
  for (size_t i = 1; i + 1 < n; ++i) {
    const double s0 = (f[i] - f[i - 1]) / (x[i] - x[i - 1]),
                 s1 = (f[i + 1] - f[i]) / (x[i + 1] - x[i]);
    pieces += fabs(s1 - s0) > 1e-6;
  }
  return pieces;
}

static void feature_tilted(const shapegen_object_t *o) {
  const char *name = o->spec.name;
  const shapegen_slab_t *s = &o->spec.slab;
  const size_t bottom = pl_pieces(s->lines_m[0], s->bottom_m[0], s->line_count[0]) *
                        pl_pieces(s->lines_m[1], s->bottom_m[1], s->line_count[1]);
  const size_t top = pl_pieces(s->lines_m[0], s->top_m[0], s->line_count[0]) *
                     pl_pieces(s->lines_m[1], s->top_m[1], s->line_count[1]);
  ck_assert(bottom >= 4 && top >= 4);
  planes_t *p = malloc(sizeof *p);
  hull_planes(&o->mesh, p);
  const double c2 = cos(2.0 * CL_PI / 180.0), area = 4.0 * s->half_m[0] * s->half_m[1];
  size_t nb = 0, ntop = 0, idx[16];
  for (size_t i = 0; i < p->count; ++i) {
    if (p->n[i][2] < -c2) {
      ck_assert_uint_lt(nb, 16);
      idx[nb++] = i;
      ck_assert_msg(p->area[i] <= 0.6 * area, "%s: a bottom facet of %.0f %% of the footprint",
                    name, 100.0 * p->area[i] / area);
    }
    ntop += p->n[i][2] > c2;
  }
  ck_assert_msg(nb == bottom && ntop == top, "%s: hull facets %zu / %zu, drawn %zu / %zu", name, nb,
                ntop, bottom, top);
  /* facets at small angles to each other: 0.1 degree at least, 3 degrees at most */
  for (size_t i = 0; i < nb; ++i) {
    for (size_t j = i + 1; j < nb; ++j) {
      const double ang = acos(fmin(1.0, cl_vec3_dot(p->n[idx[i]], p->n[idx[j]]))) * 180.0 / CL_PI;
      ck_assert_msg(ang >= 0.09 && ang <= 3.0, "%s: facets %.3f degrees apart", name, ang);
    }
  }
  free(p);
}

START_TEST(family_features) {
  for (uint64_t seed = 1; seed <= SEEDS; ++seed) {
    shapegen_object_t o;
    gen(_i, seed, &o);
    switch ((shapegen_family_t)_i) {
      case SHAPEGEN_BOX:
        ck_assert_uint_eq(o.mesh.triangle_count, 12);
        ck_assert_uint_eq(o.mesh.vertex_count, 8);
        break;
      case SHAPEGEN_DOMINO: {
        size_t count = 0, wide = 0;
        rockgen_patch_t *p = all_patches(&o.mesh, &count);
        ck_assert_uint_eq(count, 6);
        for (size_t i = 0; i < count; ++i) wide += p[i].width_m >= 10 * MM;
        ck_assert_uint_eq(wide, 2);
        free(p);
        const double *d = o.spec.box.size_m;
        ck_assert(fabs(d[0] / (48 * MM) - 1) <= 0.15 && fabs(d[1] / (24 * MM) - 1) <= 0.15 &&
                  fabs(d[2] / (7.5 * MM) - 1) <= 0.15);
        break;
      }
      case SHAPEGEN_FEET2:
      case SHAPEGEN_FEET3:
      case SHAPEGEN_FEET4:
        ck_assert_uint_eq(o.spec.slab.foot_count, (size_t)(_i - SHAPEGEN_FEET2 + 2));
        feature_feet(&o);
        break;
      case SHAPEGEN_RING: feature_ring(&o); break;
      case SHAPEGEN_RIM: feature_rim(&o); break;
      case SHAPEGEN_MUG: feature_mug(&o); break;
      case SHAPEGEN_PEBBLE: feature_pebble(&o); break;
      case SHAPEGEN_LUMPY: feature_lumpy(&o); break;
      case SHAPEGEN_SCANNED: feature_scanned(&o); break;
      case SHAPEGEN_PLATE: feature_plate(&o); break;
      case SHAPEGEN_TILTED: feature_tilted(&o); break;
      default: ck_abort();
    }
    shapegen_object_free(&o);
  }
}
END_TEST

/* A box's best resting margin is half its middle dimension (on its largest face). */
START_TEST(rest_margin_of_a_box) {
  const double lo[3] = {-0.03, -0.01, -0.02}, hi[3] = {0.03, 0.01, 0.02};
  model_mesh_t box, hull;
  ck_assert_int_eq(model_mesh_box(lo, hi, &box), MODEL_OK);
  ck_assert_int_eq(model_mesh_hull(&box, &hull, NULL), MODEL_OK);
  double m = 0.0, n[3];
  const double c0[3] = {0, 0, 0}, c1[3] = {0.005, 0, 0.004}, out[3] = {0.05, 0.02, 0.03};
  ck_assert_int_eq(shapegen_rest_margin(&box, &hull, c0, &m, n), MODEL_OK);
  ck_assert_double_eq_tol(m, 0.02, 1e-12);
  ck_assert_double_eq_tol(fabs(n[1]), 1.0, 1e-12);
  ck_assert_int_eq(shapegen_rest_margin(&box, &hull, c1, &m, NULL), MODEL_OK);
  ck_assert_double_eq_tol(m, 0.016, 1e-12);
  ck_assert_int_eq(shapegen_rest_margin(&box, &hull, out, &m, NULL), MODEL_OK);
  ck_assert(m < 0.0);
  ck_assert_int_eq(shapegen_rest_margin(NULL, &hull, c0, &m, NULL), MODEL_E_ARG);
  model_mesh_free(&hull);
  model_mesh_free(&box);
}
END_TEST

/* ---- the command line and the files -------------------------------------------------------- */

/* Run comlearn-shapegen with argv (NULL-terminated), stdout to out_path (or /dev/null), stderr
 * discarded; its exit status or -1. */
static int run_shapegen(char *const argv[], const char *out_path) {
  fflush(stdout);
  fflush(stderr);
  const pid_t pid = fork();
  ck_assert_int_ge(pid, 0);
  if (pid == 0) {
    const int null = open("/dev/null", O_WRONLY);
    const int out = out_path != NULL ? open(out_path, O_WRONLY | O_CREAT | O_TRUNC, 0644) : null;
    if (null >= 0) dup2(null, 2);
    if (out >= 0) dup2(out, 1);
    execv(COMLEARN_SHAPEGEN, argv);
    _exit(127);
  }
  int ws = 0;
  ck_assert_int_eq(waitpid(pid, &ws, 0), pid);
  return WIFEXITED(ws) ? WEXITSTATUS(ws) : -1;
}

static double max_abs(const double m[3][3]) {
  double r = 0.0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) r = fmax(r, fabs(m[i][j]));
  }
  return r;
}

static void assert_mass_eq(const char *what, const model_mass_t *got, const model_mass_t *want) {
  ck_assert_msg(fabs(got->mass_kg - want->mass_kg) <= 1e-9 * want->mass_kg, "%s: mass", what);
  for (int k = 0; k < 3; ++k) {
    ck_assert_msg(fabs(got->com_m[k] - want->com_m[k]) <= 1e-9 * 0.12, "%s: com %d", what, k);
  }
  const double scale = max_abs(want->inertia_kg_m2);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      ck_assert_msg(fabs(got->inertia_kg_m2[i][j] - want->inertia_kg_m2[i][j]) <= 1e-9 * scale,
                    "%s: I[%d][%d]", what, i, j);
    }
  }
}

enum { BATCH = SHAPEGEN_FAMILY_COUNT, FIRST = 100 };

/* The batch's list file: one line per object, in order, each family once. Removes it. */
static void round_trip_check_list(const char *list) {
  size_t size = 0;
  char *text = test_slurp(list, &size);
  char *line = text;
  for (int i = 0; i < BATCH; ++i) {
    const char *fam = shapegen_family_name((shapegen_family_t)i);
    char head[96];
    snprintf(head, sizeof head, "%s %s_s%d (", fam, fam, FIRST + i);
    ck_assert_msg(strncmp(line, head, strlen(head)) == 0, "line %d: %.60s", i, line);
    ck_assert_ptr_nonnull(strstr(line, " triangles, "));
    ck_assert_ptr_nonnull(strstr(line, " mm from uniform"));
    line = strchr(line, '\n');
    ck_assert_ptr_nonnull(line);
    ++line;
  }
  ck_assert_int_eq(*line, '\0');
  free(text);
  remove(list);
}

/* One URDF of o (k: 0 even, 1 uneven), the same in both runs, loads back to o's mesh and mass. */
static void round_trip_check_urdf(const shapegen_object_t *o, const mt_tmpdir_t *a,
                                  const mt_tmpdir_t *b, int k) {
  static const char *const kinds[2] = {"even", "uneven"};
  char pa[512], pb[512], rel[128];
  snprintf(rel, sizeof rel, "%s_%s.urdf", o->spec.name, kinds[k]);
  ck_assert_msg(test_same_file(mt_join(a, rel, pa, sizeof pa), mt_join(b, rel, pb, sizeof pb)),
                "%s differs between two runs", rel);
  model_object_t obj;
  model_mass_t mass;
  model_error_t err = {{0}};
  ck_assert_msg(model_object_load(pa, NULL, &obj, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_msg(model_inertial_load(pa, NULL, &mass, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_str_eq(obj.link_name, o->spec.name);
  ck_assert_uint_eq(obj.mesh.triangle_count, o->mesh.triangle_count);
  ck_assert_msg(mt_same_vertices(&obj.mesh, &o->mesh, 0.0), "%s: vertices differ", rel);
  assert_mass_eq(rel, &mass, k ? &o->uneven : &o->even);
  model_mass_t again;
  ck_assert_int_eq(model_mesh_mass(&obj.mesh, o->spec.density_kg_m3, &again), MODEL_OK);
  assert_mass_eq(rel, &again, &o->even);
  if (k) { /* the URDF comment documents the region */
    size_t n = 0;
    char *u = test_slurp(pa, &n), want[128];
    snprintf(want, sizeof want, "n = (%.17g, ", o->region.normal[0]);
    ck_assert_ptr_nonnull(strstr(u, want));
    free(u);
  }
  model_object_free(&obj);
}

/* Every object of the batch: its mesh and both URDFs the same in runs a and b, and loadable. */
static void round_trip_check_objects(const mt_tmpdir_t *a, const mt_tmpdir_t *b) {
  char pa[512], pb[512], rel[128];
  for (int i = 0; i < BATCH; ++i) {
    shapegen_object_t o;
    gen(i, (uint64_t)(FIRST + i), &o);
    snprintf(rel, sizeof rel, "meshes/%s.stl", o.spec.name);
    ck_assert_msg(test_same_file(mt_join(a, rel, pa, sizeof pa), mt_join(b, rel, pb, sizeof pb)),
                  "%s differs between two runs", rel);
    for (int k = 0; k < 2; ++k) round_trip_check_urdf(&o, a, b, k);
    shapegen_object_free(&o);
  }
}

/* Remove the batch's files from a and b, the single mug's from c, and the folders. */
static void round_trip_remove(mt_tmpdir_t *a, mt_tmpdir_t *b, mt_tmpdir_t *c) {
  const char *names[3 * BATCH + 1];
  char store[3 * BATCH][64];
  for (int i = 0; i < BATCH; ++i) {
    const char *fam = shapegen_family_name((shapegen_family_t)i);
    snprintf(store[3 * i], 64, "meshes/%s_s%d.stl", fam, FIRST + i);
    snprintf(store[3 * i + 1], 64, "%s_s%d_even.urdf", fam, FIRST + i);
    snprintf(store[3 * i + 2], 64, "%s_s%d_uneven.urdf", fam, FIRST + i);
  }
  for (int i = 0; i < 3 * BATCH; ++i) names[i] = store[i];
  names[3 * BATCH] = "meshes";
  mt_tmpdir_remove(a, names, 3 * BATCH + 1);
  mt_tmpdir_remove(b, names, 3 * BATCH + 1);
  const char *one[] = {"meshes/mug_s107.stl", "mug_s107_even.urdf", "mug_s107_uneven.urdf",
                       "meshes"};
  mt_tmpdir_remove(c, one, 4);
}

START_TEST(files_round_trip) {
  mt_tmpdir_t a, b, c;
  mt_tmpdir_make(&a);
  mt_tmpdir_make(&b);
  mt_tmpdir_make(&c);
  char first[32], count[32], pa[512], pb[512], list[512];
  snprintf(first, sizeof first, "%d", FIRST);
  snprintf(count, sizeof count, "%d", BATCH);
  snprintf(list, sizeof list, "%s.txt", a.path);
  char *const run_a[] = {"g",       "--family", "all",       "--seed", first,
                         "--count", count,      "--out-dir", a.path,   NULL};
  char *const run_b[] = {"g",       "--family", "all",       "--seed", first,
                         "--count", count,      "--out-dir", b.path,   NULL};
  ck_assert_int_eq(run_shapegen(run_a, list), 0);
  ck_assert_int_eq(run_shapegen(run_b, NULL), 0);
  round_trip_check_list(list);
  /* a seed written alone equals the same object in the batch */
  char *const run_c[] = {"g", "--family", "mug", "--seed", "107", "--out-dir", c.path, NULL};
  ck_assert_int_eq(run_shapegen(run_c, NULL), 0);
  ck_assert(test_same_file(mt_join(&a, "mug_s107_uneven.urdf", pa, sizeof pa),
                           mt_join(&c, "mug_s107_uneven.urdf", pb, sizeof pb)));
  ck_assert(test_same_file(mt_join(&a, "meshes/mug_s107.stl", pa, sizeof pa),
                           mt_join(&c, "meshes/mug_s107.stl", pb, sizeof pb)));
  round_trip_check_objects(&a, &b);
  round_trip_remove(&a, &b, &c);
}
END_TEST

START_TEST(cli_usage) {
  mt_tmpdir_t d;
  mt_tmpdir_make(&d);
  char out[512], sub[512];
  mt_join(&d, "out.txt", out, sizeof out);
  mt_join(&d, "sub", sub, sizeof sub);
  /* --help lists every option and family with its default, writes nothing */
  char *const help[] = {"g", "--help", NULL};
  ck_assert_int_eq(run_shapegen(help, out), 0);
  size_t n = 0;
  char *text = test_slurp(out, &n);
  static const char *const opts[] = {"--family", "--seed",    "--count",      "--out-dir",
                                     "--help",   "--version", "(default: 1)", "Exit status"};
  for (size_t i = 0; i < sizeof opts / sizeof opts[0]; ++i)
    ck_assert_ptr_nonnull(strstr(text, opts[i]));
  for (unsigned f = 0; f < SHAPEGEN_FAMILY_COUNT; ++f) {
    ck_assert_ptr_nonnull(strstr(text, shapegen_family_name((shapegen_family_t)f)));
  }
  free(text);
  char *const version[] = {"g", "--version", NULL};
  ck_assert_int_eq(run_shapegen(version, out), 0);
  text = test_slurp(out, &n);
  ck_assert_int_eq(strncmp(text, "comlearn-shapegen ", 18), 0);
  ck_assert_uint_gt(n, 19);
  free(text);
  char *const cases[][10] = {
      {"g", "--family", "cube", "--seed", "1", "--out-dir", sub, NULL},
      {"g", "--family", "box", "--out-dir", sub, NULL},
      {"g", "--seed", "1", "--out-dir", sub, NULL},
      {"g", "--family", "box", "--seed", "1", NULL},
      {"g", "--family", "box", "--seed", "-1", "--out-dir", sub, NULL},
      {"g", "--family", "box", "--seed", "1x", "--out-dir", sub, NULL},
      {"g", "--family", "box", "--seed", "18446744073709551616", "--out-dir", sub, NULL},
      {"g", "--family", "box", "--seed", "18446744073709551615", "--count", "2", "--out-dir", sub,
       NULL},
      {"g", "--family", "box", "--seed", "1", "--count", "0", "--out-dir", sub, NULL},
      {"g", "--family", "box", "--seed", "1", "--count", "100001", "--out-dir", sub, NULL},
      {"g", "--family", "box", "--seed", "1", "--out-dir", sub, "extra", NULL},
      {"g", "--family", "box", "--seed", "1", "--bogus", "--out-dir", sub, NULL},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
    ck_assert_msg(run_shapegen(cases[i], NULL) == 2, "case %zu", i);
  }
  struct stat st;
  ck_assert_int_ne(stat(sub, &st), 0); /* nothing was written */
  char *const unwritable[] = {"g",         "--family",         "box", "--seed", "1",
                              "--out-dir", "/proc/comlearn/x", NULL};
  ck_assert_int_eq(run_shapegen(unwritable, NULL), 1);
  const char *names[] = {"out.txt"};
  mt_tmpdir_remove(&d, names, 1);
}
END_TEST

static Suite *shapegen_suite(void) {
  Suite *s = suite_create("shapegen");
  TCase *rule = tcase_create("rule");
  tcase_set_timeout(rule, 240);
  tcase_add_test(rule, trig_exact_and_accurate);
  tcase_add_test(rule, names_and_bad_arguments);
  tcase_add_test(rule, rest_margin_of_a_box);
  tcase_add_loop_test(rule, every_family_accepted, 0, SHAPEGEN_FAMILY_COUNT);
  tcase_add_loop_test(rule, deterministic_and_rule, 0, SHAPEGEN_FAMILY_COUNT);
  suite_add_tcase(s, rule);
  TCase *shape = tcase_create("shapes");
  tcase_set_timeout(shape, 240);
  tcase_add_loop_test(shape, closed_forms, 0, SHAPEGEN_FAMILY_COUNT);
  tcase_add_loop_test(shape, family_features, 0, SHAPEGEN_FAMILY_COUNT);
  suite_add_tcase(s, shape);
  TCase *files = tcase_create("files");
  tcase_set_timeout(files, 240);
  tcase_add_test(files, files_round_trip);
  tcase_add_test(files, cli_usage);
  suite_add_tcase(s, files);
  return s;
}

int main(void) {
  SRunner *runner = srunner_create(shapegen_suite());
  srunner_run_all(runner, CK_NORMAL);
  const int failed = srunner_ntests_failed(runner);
  srunner_free(runner);
  return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
