/* model_massprop_tests.c - model_mesh_mass() and model_mesh_mass_halfspace() against closed forms:
 * boxes, a tetrahedron (Tonon 2004), an icosphere (symmetry, inscribed-sphere bounds and the
 * exact polyhedron volume), two-material boxes cut by axis-aligned and oblique planes, rigid
 * motions, and bad input; model_mass_plausible() at each of its limits, just inside and just
 * outside, and on the bundled rocks. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "comlearn/math3d.h"
#include "comlearn/model.h"
#include "comlearn/model_inertial.h"
#include "model_suites.h"

/* ---- small helpers ---------------------------------------------------------------------- */

static double max_abs3x3(const double m[3][3]) {
  double r = 0.0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (fabs(m[i][j]) > r) r = fabs(m[i][j]);
    }
  }
  return r;
}

/* Every field of got within rel_tol of want: mass relative, CoM relative to `size_m`, inertia
 * relative to the largest entry of want. */
static void assert_mass_near(const model_mass_t *got, const model_mass_t *want, double size_m,
                             double rel_tol) {
  ck_assert_msg(fabs(got->mass_kg - want->mass_kg) <= rel_tol * fabs(want->mass_kg),
                "mass %.17g want %.17g", got->mass_kg, want->mass_kg);
  for (int i = 0; i < 3; ++i) {
    ck_assert_msg(fabs(got->com_m[i] - want->com_m[i]) <= rel_tol * size_m,
                  "com[%d] %.17g want %.17g", i, got->com_m[i], want->com_m[i]);
  }
  const double scale = max_abs3x3(want->inertia_kg_m2);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      ck_assert_msg(fabs(got->inertia_kg_m2[i][j] - want->inertia_kg_m2[i][j]) <= rel_tol * scale,
                    "I[%d][%d] %.17g want %.17g", i, j, got->inertia_kg_m2[i][j],
                    want->inertia_kg_m2[i][j]);
    }
  }
}

static void mesh_alloc(model_mesh_t *m, size_t nv, size_t nt) {
  m->vertices_m = calloc(nv, sizeof *m->vertices_m);
  m->triangles = calloc(nt, sizeof *m->triangles);
  ck_assert_ptr_nonnull(m->vertices_m);
  ck_assert_ptr_nonnull(m->triangles);
  m->vertex_count = nv;
  m->triangle_count = nt;
}

/* Closed box [lo, hi], outward counter-clockwise triangles. */
static void make_box(model_mesh_t *m, const double lo[3], const double hi[3]) {
  static const uint32_t tris[12][3] = {
      {0, 2, 1}, {0, 3, 2}, /* z = lo */ {4, 5, 6}, {4, 6, 7}, /* z = hi */
      {0, 1, 5}, {0, 5, 4}, /* y = lo */ {2, 3, 7}, {2, 7, 6}, /* y = hi */
      {1, 2, 6}, {1, 6, 5}, /* x = hi */ {0, 4, 7}, {0, 7, 3}, /* x = lo */
  };
  mesh_alloc(m, 8, 12);
  for (uint32_t v = 0; v < 8; ++v) {
    const int bx = ((v & 1u) != 0) != ((v & 2u) != 0); /* 0,1,1,0 around the bottom */
    const int by = (v & 2u) != 0;
    const int bz = (v & 4u) != 0;
    m->vertices_m[v][0] = bx ? hi[0] : lo[0];
    m->vertices_m[v][1] = by ? hi[1] : lo[1];
    m->vertices_m[v][2] = bz ? hi[2] : lo[2];
  }
  memcpy(m->triangles, tris, sizeof tris);
}

/* Tetrahedron p0..p3 with positive orientation (det(p1-p0, p2-p0, p3-p0) > 0). */
static void make_tetra(model_mesh_t *m, const double p[4][3]) {
  static const uint32_t tris[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  mesh_alloc(m, 4, 4);
  memcpy(m->vertices_m, p, 4 * sizeof *m->vertices_m);
  memcpy(m->triangles, tris, sizeof tris);
}

static void normalize(double v[3], double radius) {
  const double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  for (int k = 0; k < 3; ++k) v[k] *= radius / n;
}

/* Icosphere of `radius` around `center`: an icosahedron whose triangles are split `levels` times
 * at their edge midpoints pushed onto the sphere; a triangle soup (three vertices per triangle),
 * which mass properties do not mind. Centrally and icosahedrally symmetric up to rounding. */
static void make_icosphere(model_mesh_t *m, int levels, double radius, const double center[3]) {
  const double g = (1.0 + sqrt(5.0)) / 2.0;
  const double ico_v[12][3] = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0},
                               {0, -1, g}, {0, 1, g}, {0, -1, -g}, {0, 1, -g},
                               {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  static const uint32_t ico_t[20][3] = {
      {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  size_t nt = 20;
  for (int l = 0; l < levels; ++l) nt *= 4;
  double(*tri)[3][3] = calloc(nt, sizeof *tri);
  double(*next)[3][3] = calloc(nt, sizeof *next);
  ck_assert_ptr_nonnull(tri);
  ck_assert_ptr_nonnull(next);
  for (int t = 0; t < 20; ++t) {
    for (int i = 0; i < 3; ++i) {
      memcpy(tri[t][i], ico_v[ico_t[t][i]], sizeof tri[t][i]);
      normalize(tri[t][i], 1.0);
    }
  }
  size_t count = 20;
  for (int l = 0; l < levels; ++l) {
    for (size_t t = 0; t < count; ++t) {
      double mid[3][3];
      for (int e = 0; e < 3; ++e) {
        for (int k = 0; k < 3; ++k) mid[e][k] = tri[t][e][k] + tri[t][(e + 1) % 3][k];
        normalize(mid[e], 1.0);
      }
      const double *corner[4][3] = {{tri[t][0], mid[0], mid[2]},
                                    {tri[t][1], mid[1], mid[0]},
                                    {tri[t][2], mid[2], mid[1]},
                                    {mid[0], mid[1], mid[2]}};
      for (int c = 0; c < 4; ++c) {
        for (int i = 0; i < 3; ++i)
          memcpy(next[4 * t + (size_t)c][i], corner[c][i], 3 * sizeof(double));
      }
    }
    count *= 4;
    double(*swap)[3][3] = tri;
    tri = next;
    next = swap;
  }
  mesh_alloc(m, 3 * nt, nt);
  for (size_t t = 0; t < nt; ++t) {
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < 3; ++k)
        m->vertices_m[3 * t + (size_t)i][k] = radius * tri[t][i][k] + center[k];
      m->triangles[t][i] = (uint32_t)(3 * t + (size_t)i);
    }
  }
  free(tri);
  free(next);
}

/* Mass properties of a solid box [lo, hi] in closed form. */
static model_mass_t box_closed_form(const double lo[3], const double hi[3], double rho) {
  model_mass_t r;
  memset(&r, 0, sizeof r);
  const double a = hi[0] - lo[0], b = hi[1] - lo[1], c = hi[2] - lo[2];
  r.mass_kg = rho * a * b * c;
  for (int k = 0; k < 3; ++k) r.com_m[k] = 0.5 * (lo[k] + hi[k]);
  r.inertia_kg_m2[0][0] = r.mass_kg / 12.0 * (b * b + c * c);
  r.inertia_kg_m2[1][1] = r.mass_kg / 12.0 * (a * a + c * c);
  r.inertia_kg_m2[2][2] = r.mass_kg / 12.0 * (a * a + b * b);
  return r;
}

/* Tonon (2004), "Explicit exact formulas for the 3-D tetrahedron inertia tensor in terms of its
 * vertex coordinates": with coordinates relative to the centroid and |J| = 6 V,
 *   a  = rho |J| / 60 * sum_{i<=j} (y_i y_j + z_i z_j)        (Ixx; b, c alike)
 *   a' = rho |J| / 120 * sum_{i,j} (1 + [i==j]) y_i z_j       (-Iyz; b' = -Ixz, c' = -Ixy). */
static model_mass_t tetra_tonon(const double p[4][3], double rho) {
  model_mass_t r;
  memset(&r, 0, sizeof r);
  double e[3][3];
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) e[i][k] = p[i + 1][k] - p[0][k];
  }
  const double det = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                     e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                     e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
  const double absj = fabs(det);
  r.mass_kg = rho * absj / 6.0;
  for (int k = 0; k < 3; ++k) r.com_m[k] = (p[0][k] + p[1][k] + p[2][k] + p[3][k]) / 4.0;
  double q[4][3];
  for (int i = 0; i < 4; ++i) {
    for (int k = 0; k < 3; ++k) q[i][k] = p[i][k] - r.com_m[k];
  }
  double sq[3] = {0, 0, 0}; /* sum_{i<=j} u_i u_j for u = x, y, z */
  double pr[3][3] = {{0}};  /* sum_{i,j} (1 + [i==j]) u_i v_j */
  for (int k = 0; k < 3; ++k) {
    for (int i = 0; i < 4; ++i) {
      for (int j = i; j < 4; ++j) sq[k] += q[i][k] * q[j][k];
    }
  }
  for (int k = 0; k < 3; ++k) {
    for (int l = 0; l < 3; ++l) {
      for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 4; ++j) pr[k][l] += (i == j ? 2.0 : 1.0) * q[i][k] * q[j][l];
      }
    }
  }
  r.inertia_kg_m2[0][0] = rho * absj / 60.0 * (sq[1] + sq[2]);
  r.inertia_kg_m2[1][1] = rho * absj / 60.0 * (sq[0] + sq[2]);
  r.inertia_kg_m2[2][2] = rho * absj / 60.0 * (sq[0] + sq[1]);
  for (int k = 0; k < 3; ++k) {
    for (int l = 0; l < 3; ++l) {
      if (k != l) r.inertia_kg_m2[k][l] = -rho * absj / 120.0 * pr[k][l];
    }
  }
  return r;
}

/* Right prism over the triangle t[3] (x, y) from z0 to z1, in closed form: the triangle's area
 * moments (covariance A/12 * sum of vertex outer products about the centroid) times the height,
 * and the height's A * h^3 / 12. */
static model_mass_t prism_closed_form(const double t[3][2], double z0, double z1, double rho) {
  model_mass_t r;
  memset(&r, 0, sizeof r);
  const double area = 0.5 * fabs((t[1][0] - t[0][0]) * (t[2][1] - t[0][1]) -
                                 (t[2][0] - t[0][0]) * (t[1][1] - t[0][1]));
  const double h = z1 - z0;
  r.mass_kg = rho * area * h;
  const double cx = (t[0][0] + t[1][0] + t[2][0]) / 3.0, cy = (t[0][1] + t[1][1] + t[2][1]) / 3.0;
  r.com_m[0] = cx;
  r.com_m[1] = cy;
  r.com_m[2] = 0.5 * (z0 + z1);
  double cxx = 0, cyy = 0, cxy = 0;
  for (int i = 0; i < 3; ++i) {
    cxx += (t[i][0] - cx) * (t[i][0] - cx);
    cyy += (t[i][1] - cy) * (t[i][1] - cy);
    cxy += (t[i][0] - cx) * (t[i][1] - cy);
  }
  cxx *= rho * h * area / 12.0;
  cyy *= rho * h * area / 12.0;
  cxy *= rho * h * area / 12.0;
  const double czz = r.mass_kg * h * h / 12.0;
  r.inertia_kg_m2[0][0] = cyy + czz;
  r.inertia_kg_m2[1][1] = cxx + czz;
  r.inertia_kg_m2[2][2] = cxx + cyy;
  r.inertia_kg_m2[0][1] = r.inertia_kg_m2[1][0] = -cxy;
  return r;
}

/* a + w * b as one body (w may be negative: b removed and re-added at another density), by the
 * parallel-axis theorem. */
static model_mass_t compose(const model_mass_t *a, const model_mass_t *b, double w) {
  model_mass_t r;
  memset(&r, 0, sizeof r);
  const double mb = w * b->mass_kg;
  r.mass_kg = a->mass_kg + mb;
  for (int k = 0; k < 3; ++k)
    r.com_m[k] = (a->mass_kg * a->com_m[k] + mb * b->com_m[k]) / r.mass_kg;
  const model_mass_t *part[2] = {a, b};
  const double mass[2] = {a->mass_kg, mb};
  const double scale[2] = {1.0, w};
  for (int p = 0; p < 2; ++p) {
    double d[3];
    for (int k = 0; k < 3; ++k) d[k] = part[p]->com_m[k] - r.com_m[k];
    const double dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        r.inertia_kg_m2[i][j] +=
            scale[p] * part[p]->inertia_kg_m2[i][j] + mass[p] * ((i == j ? dd : 0.0) - d[i] * d[j]);
      }
    }
  }
  return r;
}

/* ---- single material ---------------------------------------------------------------------- */

START_TEST(unit_cube) {
  const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
  model_mesh_t m;
  memset(&m, 0, sizeof m);
  make_box(&m, lo, hi);
  model_mass_t got;
  ck_assert_int_eq(model_mesh_mass(&m, 1.0, &got), MODEL_OK);
  const model_mass_t want = box_closed_form(lo, hi, 1.0);
  ck_assert_double_eq_tol(want.inertia_kg_m2[0][0], 1.0 / 6.0, 1e-15);
  assert_mass_near(&got, &want, 1.0, 1e-9);
  model_mesh_free(&m);
}
END_TEST

START_TEST(offset_box) {
  const double lo[3] = {-3.25, 1.5, 0.75}, hi[3] = {-3.05, 1.83, 0.8};
  model_mesh_t m;
  memset(&m, 0, sizeof m);
  make_box(&m, lo, hi);
  model_mass_t got;
  ck_assert_int_eq(model_mesh_mass(&m, 2650.0, &got), MODEL_OK);
  const model_mass_t want = box_closed_form(lo, hi, 2650.0);
  assert_mass_near(&got, &want, 0.33, 1e-9);
  model_mesh_free(&m);
}
END_TEST

START_TEST(box_far_from_origin) {
  /* Far from the origin the reference point near the mesh keeps the digits. */
  const double lo[3] = {1000.0, -2000.0, 500.0}, hi[3] = {1000.1, -1999.95, 500.03};
  model_mesh_t m;
  memset(&m, 0, sizeof m);
  make_box(&m, lo, hi);
  model_mass_t got;
  ck_assert_int_eq(model_mesh_mass(&m, 7800.0, &got), MODEL_OK);
  const model_mass_t want = box_closed_form(lo, hi, 7800.0);
  assert_mass_near(&got, &want, 0.1, 1e-9);
  model_mesh_free(&m);
}
END_TEST

START_TEST(tetrahedron_tonon) {
  /* Tonon's own example: vertices (8.33220, -11.86875, 0.93355), (0.75523, 5.00000, 16.37072),
   * (52.61236, 5.00000, -5.38580), (2.00000, 5.00000, 3.00000); his published result. */
  const double p[4][3] = {{8.33220, -11.86875, 0.93355},
                          {0.75523, 5.00000, 16.37072},
                          {52.61236, 5.00000, -5.38580},
                          {2.00000, 5.00000, 3.00000}};
  model_mesh_t m;
  memset(&m, 0, sizeof m);
  make_tetra(&m, p);
  model_mass_t got;
  ck_assert_int_eq(model_mesh_mass(&m, 1.0, &got), MODEL_OK);
  const model_mass_t want = tetra_tonon(p, 1.0);
  assert_mass_near(&got, &want, 50.0, 1e-9);
  /* Tonon's printed values, which carry 10 significant digits computed from inputs rounded to 5
   * decimals: agreement to 1e-7 relative. His centroid x (15.92492) is a misprint: the mean of the
   * four x coordinates is 15.9249475. */
  ck_assert_double_eq_tol(got.com_m[0], 15.9249475, 1e-9);
  ck_assert_double_eq_tol(got.com_m[1], 0.78281, 1e-5);
  ck_assert_double_eq_tol(got.com_m[2], 3.72962, 1e-5);
  const double paper[6] = {43520.33257, 194711.28938, 191168.76173, /* a, b, c */
                           4417.66150,  -46343.16662, 11996.20119}; /* a', b', c' */
  const double ours[6] = {got.inertia_kg_m2[0][0],  got.inertia_kg_m2[1][1],
                          got.inertia_kg_m2[2][2],  -got.inertia_kg_m2[1][2],
                          -got.inertia_kg_m2[0][2], -got.inertia_kg_m2[0][1]};
  for (int i = 0; i < 6; ++i) ck_assert_double_eq_tol(ours[i] / paper[i], 1.0, 1e-7);
  model_mesh_free(&m);
}
END_TEST

START_TEST(icosphere_offset) {
  /* 1280 triangles, vertices on the sphere of radius R. Checks:
   * - CoM at the offset to 1e-12 m: the polyhedron is centrally symmetric about it.
   * - inertia isotropic (icosahedral symmetry) to 1e-12 relative.
   * - volume equals the exact polyhedron's, sum of face area * plane distance / 3, to 1e-12:
   *   a second formula for the same solid.
   * - volume and moment between those of the inscribed ball (radius r_in = smallest distance from
   *   the center to a face plane, measured on the mesh) and of the circumscribed ball (R): the
   *   polyhedron contains the first and lies in the second, and both integrands are positive. This
   *   is the tolerance the discretisation allows (about 1 % here), derived, not guessed. */
  const double c[3] = {1.5, -2.0, 0.7};
  const double radius = 1.0, rho = 3.0;
  model_mesh_t m;
  memset(&m, 0, sizeof m);
  make_icosphere(&m, 3, radius, c);
  ck_assert_uint_eq(m.triangle_count, 1280);
  model_mass_t got;
  ck_assert_int_eq(model_mesh_mass(&m, rho, &got), MODEL_OK);
  for (int k = 0; k < 3; ++k) ck_assert_double_eq_tol(got.com_m[k], c[k], 1e-12);
  const double iso = got.inertia_kg_m2[0][0];
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const double want = i == j ? iso : 0.0;
      ck_assert_double_eq_tol(got.inertia_kg_m2[i][j], want, 1e-12 * iso);
    }
  }
  double vol_exact = 0.0, r_in = radius;
  for (size_t t = 0; t < m.triangle_count; ++t) {
    const double *a = m.vertices_m[m.triangles[t][0]], *b = m.vertices_m[m.triangles[t][1]],
                 *d = m.vertices_m[m.triangles[t][2]];
    double e1[3], e2[3], n[3];
    for (int k = 0; k < 3; ++k) {
      e1[k] = b[k] - a[k];
      e2[k] = d[k] - a[k];
    }
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    const double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    const double dist = (n[0] * (a[0] - c[0]) + n[1] * (a[1] - c[1]) + n[2] * (a[2] - c[2])) / nn;
    vol_exact += 0.5 * nn * dist / 3.0;
    if (dist < r_in) r_in = dist;
  }
  ck_assert_double_eq_tol(got.mass_kg / rho, vol_exact, 1e-12 * vol_exact);
  const double pi = CL_PI;
  const double v_in = 4.0 / 3.0 * pi * pow(r_in, 3), v_out = 4.0 / 3.0 * pi * pow(radius, 3);
  const double i_in = 8.0 / 15.0 * pi * rho * pow(r_in, 5),
               i_out = 8.0 / 15.0 * pi * rho * pow(radius, 5);
  ck_assert(r_in > 0.98 * radius);
  ck_assert(got.mass_kg / rho > v_in && got.mass_kg / rho < v_out);
  ck_assert(iso > i_in && iso < i_out);
  model_mesh_free(&m);
}
END_TEST

/* An irregular closed mesh for the rigid-motion tests: an icosphere with a smooth radial bump. */
static void make_lumpy(model_mesh_t *m) {
  const double zero[3] = {0, 0, 0};
  make_icosphere(m, 2, 1.0, zero);
  for (size_t v = 0; v < m->vertex_count; ++v) {
    double *p = m->vertices_m[v];
    const double r = 1.0 + 0.3 * p[0] * p[0] - 0.2 * p[1] * p[2] + 0.15 * p[0] + 0.1 * p[2];
    for (int k = 0; k < 3; ++k) p[k] = 0.04 * r * p[k] + (k == 0 ? 0.01 : 0.0);
  }
}

/* Rotation about unit axis u by angle t (Rodrigues). */
static void rotation(const double u_in[3], double t, double r[3][3]) {
  double u[3] = {u_in[0], u_in[1], u_in[2]};
  normalize(u, 1.0);
  const double c = cos(t), s = sin(t);
  const double k[3][3] = {{0, -u[2], u[1]}, {u[2], 0, -u[0]}, {-u[1], u[0], 0}};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) r[i][j] = (i == j ? c : 0.0) + s * k[i][j] + (1 - c) * u[i] * u[j];
  }
}

static model_mass_t transform_mass(const model_mass_t *a, double r[3][3], const double t[3]) {
  model_mass_t b;
  memset(&b, 0, sizeof b);
  b.mass_kg = a->mass_kg;
  for (int i = 0; i < 3; ++i) {
    b.com_m[i] = t[i];
    for (int k = 0; k < 3; ++k) b.com_m[i] += r[i][k] * a->com_m[k];
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      for (int k = 0; k < 3; ++k) {
        for (int l = 0; l < 3; ++l)
          b.inertia_kg_m2[i][j] += r[i][k] * a->inertia_kg_m2[k][l] * r[j][l];
      }
    }
  }
  return b;
}

static void transform_mesh(model_mesh_t *m, double r[3][3], const double t[3]) {
  for (size_t v = 0; v < m->vertex_count; ++v) {
    double p[3];
    for (int i = 0; i < 3; ++i) {
      p[i] = t[i];
      for (int k = 0; k < 3; ++k) p[i] += r[i][k] * m->vertices_m[v][k];
    }
    memcpy(m->vertices_m[v], p, sizeof p);
  }
}

START_TEST(rigid_motion_invariance) {
  model_mesh_t m;
  memset(&m, 0, sizeof m);
  make_lumpy(&m);
  const model_halfspace_t region = {{0.3, -0.5, 0.8}, 0.004};
  model_mass_t a, ah;
  ck_assert_int_eq(model_mesh_mass(&m, 2650.0, &a), MODEL_OK);
  ck_assert_int_eq(model_mesh_mass_halfspace(&m, 2650.0, &region, 5000.0, &ah), MODEL_OK);
  const double axis[3] = {0.2, -0.7, 0.4}, t[3] = {0.75, -1.25, 3.5};
  double r[3][3];
  rotation(axis, 1.1, r);
  transform_mesh(&m, r, t);
  model_halfspace_t region_b;
  region_b.offset_m = region.offset_m;
  for (int i = 0; i < 3; ++i) {
    region_b.normal[i] = 0.0;
    for (int k = 0; k < 3; ++k) region_b.normal[i] += r[i][k] * region.normal[k];
    region_b.offset_m += region_b.normal[i] * t[i];
  }
  model_mass_t b, bh;
  ck_assert_int_eq(model_mesh_mass(&m, 2650.0, &b), MODEL_OK);
  ck_assert_int_eq(model_mesh_mass_halfspace(&m, 2650.0, &region_b, 5000.0, &bh), MODEL_OK);
  const model_mass_t want = transform_mass(&a, r, t), want_h = transform_mass(&ah, r, t);
  assert_mass_near(&b, &want, 0.1, 1e-11);
  assert_mass_near(&bh, &want_h, 0.1, 1e-11);
  /* The dense region really moved the CoM, so the second comparison means something. */
  double shift = 0.0;
  for (int k = 0; k < 3; ++k) shift += (ah.com_m[k] - a.com_m[k]) * (ah.com_m[k] - a.com_m[k]);
  ck_assert(sqrt(shift) > 1e-3);
  model_mesh_free(&m);
}
END_TEST

/* ---- two materials -------------------------------------------------------------------------- */

START_TEST(halfspace_axis_aligned) {
  const double lo[3] = {0.2, -0.1, 0.05}, hi[3] = {0.5, 0.15, 0.2}, cut = 0.37;
  const double rho1 = 2650.0, rho2 = 5200.0;
  model_mesh_t m;
  memset(&m, 0, sizeof m);
  make_box(&m, lo, hi);
  const model_halfspace_t region = {{2.0, 0.0, 0.0}, 2.0 * cut}; /* x >= cut, normal not unit */
  model_mass_t got;
  ck_assert_int_eq(model_mesh_mass_halfspace(&m, rho1, &region, rho2, &got), MODEL_OK);
  const double mid_lo[3] = {cut, lo[1], lo[2]}, mid_hi[3] = {cut, hi[1], hi[2]};
  const model_mass_t light = box_closed_form(lo, mid_hi, rho1);
  const model_mass_t heavy = box_closed_form(mid_lo, hi, rho2);
  const model_mass_t want = compose(&light, &heavy, 1.0);
  assert_mass_near(&got, &want, 0.3, 1e-9);
  /* Lighter region too (rho2 < rho1), and the region's complement. */
  ck_assert_int_eq(model_mesh_mass_halfspace(&m, rho2, &region, rho1, &got), MODEL_OK);
  const model_mass_t light2 = box_closed_form(mid_lo, hi, rho1);
  const model_mass_t heavy2 = box_closed_form(lo, mid_hi, rho2);
  const model_mass_t want2 = compose(&heavy2, &light2, 1.0);
  assert_mass_near(&got, &want2, 0.3, 1e-9);
  model_mesh_free(&m);
}
END_TEST

START_TEST(halfspace_oblique_corner) {
  /* Region = the corner tetrahedron cut off by the plane through three points on the edges
   * from the corner lo: composite = box at rho1 + tetrahedron at (rho2 - rho1) (Tonon). */
  const double lo[3] = {0.3, -0.1, 0.2}, hi[3] = {0.7, 0.15, 0.35};
  const double f[3] = {0.6, 0.8, 0.45}; /* fraction of each edge inside the region */
  const double rho1 = 2650.0, rho2 = 5200.0;
  model_mesh_t m;
  memset(&m, 0, sizeof m);
  make_box(&m, lo, hi);
  double len[3];
  for (int k = 0; k < 3; ++k) len[k] = f[k] * (hi[k] - lo[k]);
  /* (x - lo) . (1/len) <= 1  <=>  -(1/len) . x >= -1 - (1/len) . lo */
  model_halfspace_t region = {{-1.0 / len[0], -1.0 / len[1], -1.0 / len[2]}, -1.0};
  for (int k = 0; k < 3; ++k) region.offset_m += region.normal[k] * lo[k];
  const double tet[4][3] = {{lo[0], lo[1], lo[2]},
                            {lo[0] + len[0], lo[1], lo[2]},
                            {lo[0], lo[1] + len[1], lo[2]},
                            {lo[0], lo[1], lo[2] + len[2]}};
  model_mass_t got;
  ck_assert_int_eq(model_mesh_mass_halfspace(&m, rho1, &region, rho2, &got), MODEL_OK);
  const model_mass_t box = box_closed_form(lo, hi, rho1);
  const model_mass_t corner = tetra_tonon(tet, 1.0);
  const model_mass_t want = compose(&box, &corner, rho2 - rho1);
  assert_mass_near(&got, &want, 0.4, 1e-9);
  model_mesh_free(&m);
}
END_TEST

START_TEST(halfspace_oblique_prism) {
  /* The plane through two opposite vertical edges' neighbours: x/a + y/b >= 1 relative to the
   * corner cuts the box into two triangular prisms. */
  const double lo[3] = {-0.2, 0.1, -0.05}, hi[3] = {0.1, 0.3, 0.07};
  const double rho1 = 2400.0, rho2 = 2900.0;
  const double a = hi[0] - lo[0], b = hi[1] - lo[1];
  model_mesh_t m;
  memset(&m, 0, sizeof m);
  make_box(&m, lo, hi);
  model_halfspace_t region = {{1.0 / a, 1.0 / b, 0.0}, 1.0 + lo[0] / a + lo[1] / b};
  model_mass_t got;
  ck_assert_int_eq(model_mesh_mass_halfspace(&m, rho1, &region, rho2, &got), MODEL_OK);
  const double t_in[3][2] = {{hi[0], lo[1]}, {hi[0], hi[1]}, {lo[0], hi[1]}};
  const double t_out[3][2] = {{lo[0], lo[1]}, {hi[0], lo[1]}, {lo[0], hi[1]}};
  const model_mass_t p_in = prism_closed_form(t_in, lo[2], hi[2], rho2);
  const model_mass_t p_out = prism_closed_form(t_out, lo[2], hi[2], rho1);
  const model_mass_t want = compose(&p_out, &p_in, 1.0);
  assert_mass_near(&got, &want, 0.3, 1e-9);
  /* The box's closed form confirms the prism formula: both at one density give the box. */
  const model_mass_t p_in1 = prism_closed_form(t_in, lo[2], hi[2], rho1);
  const model_mass_t whole = compose(&p_out, &p_in1, 1.0);
  const model_mass_t box = box_closed_form(lo, hi, rho1);
  assert_mass_near(&whole, &box, 0.3, 1e-12);
  model_mesh_free(&m);
}
END_TEST

START_TEST(halfspace_all_or_nothing) {
  /* Region missing the body: rho1 everywhere; containing it: rho2 everywhere; region plane
   * through a face (vertices exactly on the plane count as inside). */
  const double lo[3] = {0, 0, 0}, hi[3] = {0.1, 0.2, 0.3};
  model_mesh_t m;
  memset(&m, 0, sizeof m);
  make_box(&m, lo, hi);
  const model_halfspace_t miss = {{0, 0, 1}, 0.5}, all = {{0, 0, 1}, 0.0},
                          all_far = {{0, 0, 1}, -7.0};
  model_mass_t got;
  const model_mass_t want1 = box_closed_form(lo, hi, 1000.0),
                     want2 = box_closed_form(lo, hi, 3000.0);
  ck_assert_int_eq(model_mesh_mass_halfspace(&m, 1000.0, &miss, 3000.0, &got), MODEL_OK);
  assert_mass_near(&got, &want1, 0.3, 1e-12);
  ck_assert_int_eq(model_mesh_mass_halfspace(&m, 1000.0, &all, 3000.0, &got), MODEL_OK);
  assert_mass_near(&got, &want2, 0.3, 1e-12);
  ck_assert_int_eq(model_mesh_mass_halfspace(&m, 1000.0, &all_far, 3000.0, &got), MODEL_OK);
  assert_mass_near(&got, &want2, 0.3, 1e-12);
  /* Equal densities: the same as model_mesh_mass. */
  const model_halfspace_t cut = {{0.3, 0.4, -0.2}, 0.01};
  model_mass_t plain;
  ck_assert_int_eq(model_mesh_mass(&m, 1000.0, &plain), MODEL_OK);
  ck_assert_int_eq(model_mesh_mass_halfspace(&m, 1000.0, &cut, 1000.0, &got), MODEL_OK);
  assert_mass_near(&got, &plain, 0.3, 1e-12);
  model_mesh_free(&m);
}
END_TEST

/* ---- bad input ------------------------------------------------------------------------------ */

static int is_zero_mass(const model_mass_t *m) {
  const model_mass_t zero = {0};
  return memcmp(m, &zero, sizeof zero) == 0;
}

START_TEST(bad_input) {
  const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
  model_mesh_t m;
  memset(&m, 0, sizeof m);
  make_box(&m, lo, hi);
  const model_halfspace_t region = {{1, 0, 0}, 0.5};
  model_mass_t out;
  const double bad_rho[4] = {0.0, -1.0, NAN, INFINITY};
  for (int i = 0; i < 4; ++i) {
    memset(&out, 0xab, sizeof out);
    ck_assert_int_eq(model_mesh_mass(&m, bad_rho[i], &out), MODEL_E_ARG);
    ck_assert(is_zero_mass(&out));
    ck_assert_int_eq(model_mesh_mass_halfspace(&m, bad_rho[i], &region, 1.0, &out), MODEL_E_ARG);
    ck_assert_int_eq(model_mesh_mass_halfspace(&m, 1.0, &region, bad_rho[i], &out), MODEL_E_ARG);
  }
  ck_assert_int_eq(model_mesh_mass(NULL, 1.0, &out), MODEL_E_ARG);
  ck_assert_int_eq(model_mesh_mass(&m, 1.0, NULL), MODEL_E_ARG);
  ck_assert_int_eq(model_mesh_mass_halfspace(&m, 1.0, NULL, 1.0, &out), MODEL_E_ARG);

  /* Regions: zero normal, non-finite normal or offset. */
  const model_halfspace_t zero_n = {{0, 0, 0}, 0.5}, nan_n = {{NAN, 0, 1}, 0.5},
                          inf_o = {{0, 0, 1}, INFINITY};
  ck_assert_int_eq(model_mesh_mass_halfspace(&m, 1.0, &zero_n, 2.0, &out), MODEL_E_REGION);
  ck_assert(is_zero_mass(&out));
  ck_assert_int_eq(model_mesh_mass_halfspace(&m, 1.0, &nan_n, 2.0, &out), MODEL_E_REGION);
  ck_assert_int_eq(model_mesh_mass_halfspace(&m, 1.0, &inf_o, 2.0, &out), MODEL_E_REGION);

  /* A NaN vertex; an index out of range. */
  m.vertices_m[3][1] = NAN;
  ck_assert_int_eq(model_mesh_mass(&m, 1.0, &out), MODEL_E_NONFINITE);
  ck_assert_int_eq(model_mesh_mass_halfspace(&m, 1.0, &region, 2.0, &out), MODEL_E_NONFINITE);
  m.vertices_m[3][1] = 1.0;
  m.triangles[5][2] = 8;
  ck_assert_int_eq(model_mesh_mass(&m, 1.0, &out), MODEL_E_ARG);
  m.triangles[5][2] = 4;

  /* Inside-out: negative volume. Flat: zero volume. */
  for (size_t t = 0; t < m.triangle_count; ++t) {
    const uint32_t s = m.triangles[t][1];
    m.triangles[t][1] = m.triangles[t][2];
    m.triangles[t][2] = s;
  }
  ck_assert_int_eq(model_mesh_mass(&m, 1.0, &out), MODEL_E_DEGENERATE);
  ck_assert_int_eq(model_mesh_mass_halfspace(&m, 1.0, &region, 2.0, &out), MODEL_E_DEGENERATE);
  model_mesh_free(&m);
  const double flat_hi[3] = {1, 1, 0};
  make_box(&m, lo, flat_hi);
  ck_assert_int_eq(model_mesh_mass(&m, 1.0, &out), MODEL_E_DEGENERATE);
  model_mesh_free(&m);

  /* Empty meshes. */
  model_mesh_t empty;
  memset(&empty, 0, sizeof empty);
  ck_assert_int_eq(model_mesh_mass(&empty, 1.0, &out), MODEL_E_DEGENERATE);
  ck_assert_int_eq(model_mesh_mass_halfspace(&empty, 1.0, &region, 2.0, &out), MODEL_E_DEGENERATE);
}
END_TEST

/* ---- plausibility against the mesh (model_mass_plausible) ------------------------------- */

/* A box [lo, hi] with the exact uniform mass properties of total mass mass_kg. */
static void plausible_box(model_mesh_t *m, const double lo[3], const double hi[3], double mass_kg,
                          model_mass_t *out) {
  memset(m, 0, sizeof *m);
  make_box(m, lo, hi);
  model_mass_t unit;
  ck_assert_int_eq(model_mesh_mass(m, 1.0, &unit), MODEL_OK);
  *out = unit;
  out->mass_kg = mass_kg;
  const double scale = mass_kg / unit.mass_kg;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) out->inertia_kg_m2[i][j] = unit.inertia_kg_m2[i][j] * scale;
  }
}

static void set_isotropic(model_mass_t *mp, double moment_kg_m2) {
  memset(mp->inertia_kg_m2, 0, sizeof mp->inertia_kg_m2);
  for (int i = 0; i < 3; ++i) mp->inertia_kg_m2[i][i] = moment_kg_m2;
}

/* st must be MODEL_E_IMPLAUSIBLE with every one of the `n` words in the message. */
static void expect_implausible(const model_mass_t *mp, const model_mesh_t *m, const char *what,
                               const char *const *words, size_t n) {
  model_error_t err = {{0}};
  const model_status_t st = model_mass_plausible(mp, m, &err);
  ck_assert_msg(st == MODEL_E_IMPLAUSIBLE, "%s: status %d (%s)", what, (int)st, err.msg);
  for (size_t i = 0; i < n; ++i) {
    ck_assert_msg(strstr(err.msg, words[i]) != NULL, "%s: '%s' not in: %s", what, words[i],
                  err.msg);
  }
}

static void expect_plausible(const model_mass_t *mp, const model_mesh_t *m, const char *what) {
  model_error_t err = {{0}};
  const model_status_t st = model_mass_plausible(mp, m, &err);
  ck_assert_msg(st == MODEL_OK, "%s: status %d: %s", what, (int)st, err.msg);
}

START_TEST(plausible_box_passes) {
  /* 40 x 60 x 20 mm of granite, off the origin, with its exact inertia; and a two-material box
   * (CoM off centre, exact inertia) */
  const double lo[3] = {-0.01, -0.05, 0.005}, hi[3] = {0.03, 0.01, 0.025};
  model_mesh_t m;
  memset(&m, 0, sizeof m);
  make_box(&m, lo, hi);
  model_mass_t mp;
  ck_assert_int_eq(model_mesh_mass(&m, 2650.0, &mp), MODEL_OK);
  expect_plausible(&mp, &m, "granite box");
  const model_mass_t cf = box_closed_form(lo, hi, 2650.0);
  expect_plausible(&cf, &m, "granite box, closed form");
  const model_halfspace_t region = {{1.0, 0.3, -0.2}, 0.012};
  ck_assert_int_eq(model_mesh_mass_halfspace(&m, 1000.0, &region, 8000.0, &mp), MODEL_OK);
  expect_plausible(&mp, &m, "two-material box");
  /* what this function adds to model_mass_check: 1e-300 kg passes that, not this */
  model_mesh_free(&m);
  plausible_box(&m, lo, hi, 1e-300, &mp);
  ck_assert_int_eq(model_mass_check(&mp, NULL), MODEL_OK);
  const char *words[] = {"mass 1e-300 kg", "[0.001, 10] kg"};
  expect_implausible(&mp, &m, "1e-300 kg", words, 2);
  model_mesh_free(&m);
}
END_TEST

START_TEST(plausible_mass_limits) {
  /* 1 cm^3 at the lower limit (density 1000), a 10 cm cube at the upper one (density 10000) */
  const double lo[3] = {0, 0, 0}, small[3] = {0.01, 0.01, 0.01}, big[3] = {0.1, 0.1, 0.1};
  model_mesh_t m;
  model_mass_t mp;
  plausible_box(&m, lo, small, MODEL_MASS_MIN_KG, &mp);
  expect_plausible(&mp, &m, "1 g");
  model_mesh_free(&m);
  plausible_box(&m, lo, small, MODEL_MASS_MIN_KG * (1.0 - 1e-9), &mp);
  const char *low[] = {"mass 0.001 kg", "[0.001, 10] kg"};
  expect_implausible(&mp, &m, "just under 1 g", low, 2);
  model_mesh_free(&m);
  plausible_box(&m, lo, big, MODEL_MASS_MAX_KG, &mp);
  expect_plausible(&mp, &m, "10 kg");
  model_mesh_free(&m);
  plausible_box(&m, lo, big, MODEL_MASS_MAX_KG * (1.0 + 1e-9), &mp);
  const char *high[] = {"mass 10 kg", "[0.001, 10] kg"};
  expect_implausible(&mp, &m, "just over 10 kg", high, 2);
  model_mesh_free(&m);
}
END_TEST

START_TEST(plausible_density_limits) {
  /* a 10 cm cube: 1e-3 m^3; at 10 kg/m^3 it weighs 10 g, at 25 000 kg/m^3 25 kg: use 0.1 m x
   * 0.1 m x 0.02 m (2e-4 m^3, 5 kg) for the upper limit */
  const double lo[3] = {0, 0, 0}, cube[3] = {0.1, 0.1, 0.1}, slab[3] = {0.1, 0.1, 0.02};
  const double volume_cube = 1e-3, volume_slab = 2e-4;
  model_mesh_t m;
  model_mass_t mp;
  plausible_box(&m, lo, cube, MODEL_DENSITY_MIN_KG_M3 * volume_cube * (1.0 + 1e-6), &mp);
  expect_plausible(&mp, &m, "just over 10 kg/m^3");
  model_mesh_free(&m);
  plausible_box(&m, lo, cube, MODEL_DENSITY_MIN_KG_M3 * volume_cube * (1.0 - 1e-6), &mp);
  const char *low[] = {"mean density 9.99999 kg/m^3", "[10, 25000] kg/m^3"};
  expect_implausible(&mp, &m, "just under 10 kg/m^3", low, 2);
  model_mesh_free(&m);
  plausible_box(&m, lo, slab, MODEL_DENSITY_MAX_KG_M3 * volume_slab * (1.0 - 1e-6), &mp);
  expect_plausible(&mp, &m, "just under 25000 kg/m^3");
  model_mesh_free(&m);
  plausible_box(&m, lo, slab, MODEL_DENSITY_MAX_KG_M3 * volume_slab * (1.0 + 1e-6), &mp);
  const char *high[] = {"mean density 25000", "[10, 25000] kg/m^3"};
  expect_implausible(&mp, &m, "just over 25000 kg/m^3", high, 2);
  model_mesh_free(&m);
  /* a mesh in millimetres read as metres: 1e9 x the volume */
  const double mm[3] = {40, 60, 20};
  plausible_box(&m, lo, mm, 0.2, &mp);
  const char *units[] = {"mean density 4.16667e-06 kg/m^3"};
  expect_implausible(&mp, &m, "mesh in mm", units, 1);
  model_mesh_free(&m);
}
END_TEST

START_TEST(plausible_com_in_bbox) {
  const double lo[3] = {-0.02, -0.03, 0.0}, hi[3] = {0.02, 0.03, 0.02};
  model_mesh_t m;
  model_mass_t mp;
  plausible_box(&m, lo, hi, 0.2, &mp);
  for (int k = 0; k < 3; ++k) {
    for (int side = 0; side < 2; ++side) {
      model_mass_t t = mp;
      const double edge = side ? hi[k] : lo[k], out = side ? 1e-6 : -1e-6;
      t.com_m[k] = edge; /* on the box's face: inside */
      expect_plausible(&t, &m, "CoM on a face of the bounding box");
      t.com_m[k] = edge + out; /* 1 um beyond it */
      char axis[8];
      snprintf(axis, sizeof axis, "%c = ", "xyz"[k]);
      const char *words[] = {"center of mass", "outside the mesh's bounding box", axis};
      expect_implausible(&t, &m, "CoM 1 um outside the bounding box", words, 3);
    }
  }
  model_mesh_free(&m);
}
END_TEST

START_TEST(plausible_moment_upper_bound) {
  /* CoM at the centre: the farthest vertex is a corner, r^2 = 0.02^2 + 0.03^2 + 0.01^2 */
  const double lo[3] = {-0.02, -0.03, -0.01}, hi[3] = {0.02, 0.03, 0.01};
  const double r2 = 0.02 * 0.02 + 0.03 * 0.03 + 0.01 * 0.01, mass = 0.2;
  model_mesh_t m;
  model_mass_t mp;
  plausible_box(&m, lo, hi, mass, &mp);
  set_isotropic(&mp, mass * r2 * (1.0 - 1e-7));
  expect_plausible(&mp, &m, "moments just under m r^2");
  set_isotropic(&mp, mass * r2 * (1.0 + 1e-7));
  char bound[64];
  snprintf(bound, sizeof bound, "= %g kg m^2", mass * r2);
  const char *words[] = {"exceeds mass x (farthest mesh vertex from the CoM)^2", bound};
  expect_implausible(&mp, &m, "moments just over m r^2", words, 2);
  /* one moment too large on a rotated tensor (the triangle inequality still holds) */
  const double a = 0.6, c = 0.8; /* rotation about z */
  const double d[3] = {mass * r2 * 0.6, mass * r2 * 0.55, mass * r2 * 1.01};
  memset(mp.inertia_kg_m2, 0, sizeof mp.inertia_kg_m2);
  mp.inertia_kg_m2[0][0] = c * c * d[0] + a * a * d[1];
  mp.inertia_kg_m2[1][1] = a * a * d[0] + c * c * d[1];
  mp.inertia_kg_m2[0][1] = mp.inertia_kg_m2[1][0] = c * a * (d[0] - d[1]);
  mp.inertia_kg_m2[2][2] = d[2];
  expect_implausible(&mp, &m, "one moment over m r^2", words, 1);
  model_mesh_free(&m);
}
END_TEST

START_TEST(plausible_moment_lower_bound) {
  const double lo[3] = {-0.02, -0.03, -0.01}, hi[3] = {0.02, 0.03, 0.01}, mass = 0.2;
  model_mesh_t m;
  model_mass_t mp;
  plausible_box(&m, lo, hi, mass, &mp);
  /* the least sum of moments: a ball of 0.2 kg at 25 000 kg/m^3, (6/5) m R^2 */
  const double pi = CL_PI;
  const double ball_r = cbrt(3.0 * mass / (4.0 * pi * MODEL_DENSITY_MAX_KG_M3));
  const double least = 1.2 * mass * ball_r * ball_r;
  set_isotropic(&mp, least / 3.0 * (1.0 + 1e-7));
  expect_plausible(&mp, &m, "sum just over (6/5) m R^2");
  set_isotropic(&mp, least / 3.0 * (1.0 - 1e-7));
  char bound[64];
  snprintf(bound, sizeof bound, "below %g kg m^2", least);
  const char *words[] = {"principal moments sum to", bound, "25000 kg/m^3"};
  expect_implausible(&mp, &m, "sum just under (6/5) m R^2", words, 3);
  set_isotropic(&mp, 1e-300);
  expect_implausible(&mp, &m, "inertia 1e-300", words, 1);
  /* positive: zero and negative moments stay model_mass_check's MODEL_E_INERTIAL */
  set_isotropic(&mp, 0.0);
  ck_assert_int_eq(model_mass_plausible(&mp, &m, NULL), MODEL_E_INERTIAL);
  set_isotropic(&mp, 1e-5);
  mp.inertia_kg_m2[2][2] = -1e-5;
  ck_assert_int_eq(model_mass_plausible(&mp, &m, NULL), MODEL_E_INERTIAL);
  /* the triangle inequality too */
  set_isotropic(&mp, 1e-5);
  mp.inertia_kg_m2[2][2] = 2.1e-5;
  ck_assert_int_eq(model_mass_plausible(&mp, &m, NULL), MODEL_E_INERTIA_TRIANGLE);
  model_mesh_free(&m);
}
END_TEST

START_TEST(plausible_nonfinite_and_null) {
  const double lo[3] = {-0.02, -0.03, -0.01}, hi[3] = {0.02, 0.03, 0.01};
  model_mesh_t m;
  model_mass_t mp;
  plausible_box(&m, lo, hi, 0.2, &mp);
  expect_plausible(&mp, &m, "reference box");
  const double bad[3] = {NAN, INFINITY, -INFINITY};
  for (int b = 0; b < 3; ++b) {
    model_mass_t t = mp;
    t.mass_kg = bad[b];
    ck_assert_int_eq(model_mass_plausible(&t, &m, NULL), MODEL_E_INERTIAL);
    t = mp;
    t.com_m[1] = bad[b];
    ck_assert_int_eq(model_mass_plausible(&t, &m, NULL), MODEL_E_INERTIAL);
    t = mp;
    t.inertia_kg_m2[0][2] = t.inertia_kg_m2[2][0] = bad[b];
    ck_assert_int_eq(model_mass_plausible(&t, &m, NULL), MODEL_E_INERTIAL);
  }
  model_error_t err = {{0}};
  ck_assert_int_eq(model_mass_plausible(NULL, &m, &err), MODEL_E_ARG);
  ck_assert_int_eq(model_mass_plausible(&mp, NULL, &err), MODEL_E_ARG);
  ck_assert_ptr_nonnull(strstr(err.msg, "mesh"));
  m.vertices_m[5][2] = NAN;
  ck_assert_int_eq(model_mass_plausible(&mp, &m, &err), MODEL_E_NONFINITE);
  ck_assert_ptr_nonnull(strstr(err.msg, "mesh"));
  model_mesh_free(&m);
  model_mesh_t empty;
  memset(&empty, 0, sizeof empty);
  ck_assert_int_eq(model_mass_plausible(&mp, &empty, &err), MODEL_E_DEGENERATE);
}
END_TEST

static const char *const kRocks[] = {"rock_1_even",   "rock_1_uneven", "rock_2_even",
                                     "rock_2_uneven", "rock_3_even",   "rock_3_uneven"};

START_TEST(plausible_bundled_rocks) {
  char path[1024];
  snprintf(path, sizeof path, "%s/rocks/%s.urdf", COMLEARN_ASSETS_DIR, kRocks[_i]);
  model_object_t obj;
  model_mass_t mp;
  model_error_t err = {{0}};
  ck_assert_msg(model_object_load(path, NULL, &obj, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_msg(model_inertial_load(path, NULL, &mp, &err) == MODEL_OK, "%s", err.msg);
  expect_plausible(&mp, &obj.mesh, kRocks[_i]);
  /* and not with a mesh 10 x too large (a scale slip): 1/1000 of the density */
  for (size_t v = 0; v < obj.mesh.vertex_count; ++v) {
    for (int k = 0; k < 3; ++k) obj.mesh.vertices_m[v][k] *= 10.0;
  }
  const char *words[] = {"mean density", "[10, 25000] kg/m^3"};
  expect_implausible(&mp, &obj.mesh, kRocks[_i], words, 2);
  model_object_free(&obj);
}
END_TEST

Suite *model_massprop_suite(void) {
  Suite *s = suite_create("model_massprop");
  TCase *one = tcase_create("one_material");
  tcase_add_test(one, unit_cube);
  tcase_add_test(one, offset_box);
  tcase_add_test(one, box_far_from_origin);
  tcase_add_test(one, tetrahedron_tonon);
  tcase_add_test(one, icosphere_offset);
  tcase_add_test(one, rigid_motion_invariance);
  suite_add_tcase(s, one);
  TCase *two = tcase_create("two_materials");
  tcase_add_test(two, halfspace_axis_aligned);
  tcase_add_test(two, halfspace_oblique_corner);
  tcase_add_test(two, halfspace_oblique_prism);
  tcase_add_test(two, halfspace_all_or_nothing);
  suite_add_tcase(s, two);
  TCase *bad = tcase_create("bad_input");
  tcase_add_test(bad, bad_input);
  suite_add_tcase(s, bad);
  TCase *plaus = tcase_create("plausible");
  tcase_add_test(plaus, plausible_box_passes);
  tcase_add_test(plaus, plausible_mass_limits);
  tcase_add_test(plaus, plausible_density_limits);
  tcase_add_test(plaus, plausible_com_in_bbox);
  tcase_add_test(plaus, plausible_moment_upper_bound);
  tcase_add_test(plaus, plausible_moment_lower_bound);
  tcase_add_test(plaus, plausible_nonfinite_and_null);
  tcase_add_loop_test(plaus, plausible_bundled_rocks, 0, (int)(sizeof kRocks / sizeof kRocks[0]));
  suite_add_tcase(s, plaus);
  return s;
}
