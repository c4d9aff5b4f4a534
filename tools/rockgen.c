/* rockgen.c - the rock shapes: geodesic sphere, random smooth radius, fracture planes. */
#include "rockgen.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "comlearn/math3d.h"

/* ---- the radius function -------------------------------------------------------------------- */

enum { MAX_LOBES = 64 };

typedef struct {
  double dir[MAX_LOBES][3];
  double amp[MAX_LOBES];
  double cosr[MAX_LOBES];
  unsigned count;
} lobes_t;

static void lobes_draw(uint64_t *state, unsigned count, double amplitude, double cos_radius,
                       lobes_t *lobes) {
  for (unsigned i = 0; i < count && lobes->count < MAX_LOBES; ++i) {
    const unsigned k = lobes->count++;
    cl_rng_direction(state, 3, lobes->dir[k]);
    const double sign = cl_rng_uniform(state) < 0.5 ? -1.0 : 1.0;
    lobes->amp[k] = sign * amplitude * (0.5 + 0.5 * cl_rng_uniform(state));
    lobes->cosr[k] = cos_radius;
  }
}

/* Radius in unit direction d: ellipsoid times (1 + sum of lobes); a lobe is s^3 with
 * s = (d.u - cos r) / (1 - cos r) inside its cap, 0 outside: twice differentiable, no libm. */
static double radius_at(const rockgen_spec_t *spec, const lobes_t *lobes, const double d[3]) {
  double q = 0.0;
  for (int k = 0; k < 3; ++k) q += d[k] * d[k] / (spec->semi_axes_m[k] * spec->semi_axes_m[k]);
  double f = 1.0;
  for (unsigned i = 0; i < lobes->count; ++i) {
    const double c = cl_vec3_dot(d, lobes->dir[i]);
    if (c > lobes->cosr[i]) {
      const double s = (c - lobes->cosr[i]) / (1.0 - lobes->cosr[i]);
      f += lobes->amp[i] * s * s * s;
    }
  }
  return f / sqrt(q);
}

/* ---- geodesic sphere ------------------------------------------------------------------------- */

static const double kGolden = 1.6180339887498948482;

static const uint32_t kIcoFaces[20][3] = {
    {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
    {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
    {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};

static void ico_vertex(uint32_t i, double v[3]) {
  const double g = kGolden;
  const double table[12][3] = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0},
                               {0, -1, g}, {0, 1, g}, {0, -1, -g}, {0, 1, -g},
                               {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  for (int k = 0; k < 3; ++k) v[k] = table[i][k];
  (void)cl_vec3_normalize(v, v);
}

/* Unit directions and triangles of a class-I geodesic sphere of frequency f: every icosahedron
 * face split into f^2 triangles at its barycentric grid, grid points pushed onto the sphere.
 * Shared edge and corner points are joined (within 1e-12 of each other, while distinct grid
 * points are > 0.01 apart). */
static model_status_t geodesic_build(unsigned f, double (**dirs)[3], size_t *dir_count,
                                     uint32_t (**tris)[3], size_t *tri_count) {
  const size_t per_face = (size_t)(f + 1) * (f + 2) / 2;
  const size_t raw = 20 * per_face;
  const size_t nt = 20 * (size_t)f * f;
  double(*d)[3] = malloc(raw * sizeof *d);
  uint32_t *local = malloc(raw * sizeof *local);
  uint32_t(*t)[3] = malloc(nt * sizeof *t);
  if (d == NULL || local == NULL || t == NULL) {
    free(d);
    free(local);
    free(t);
    return MODEL_E_NOMEM;
  }
  size_t nd = 0, it = 0;
  for (size_t face = 0; face < 20; ++face) {
    double a[3], b[3], c[3];
    ico_vertex(kIcoFaces[face][0], a);
    ico_vertex(kIcoFaces[face][1], b);
    ico_vertex(kIcoFaces[face][2], c);
    uint32_t *grid = local + face * per_face; /* grid[(i, j)] at i * (2f + 3 - i) / 2 + j */
    for (unsigned i = 0; i <= f; ++i) {
      for (unsigned j = 0; j + i <= f; ++j) {
        const double wa = (double)(f - i - j), wb = (double)i, wc = (double)j;
        double p[3];
        for (int k = 0; k < 3; ++k) p[k] = wa * a[k] + wb * b[k] + wc * c[k];
        (void)cl_vec3_normalize(p, p);
        size_t found = nd;
        for (size_t q = 0; q < nd; ++q) {
          const double dx = d[q][0] - p[0], dy = d[q][1] - p[1], dz = d[q][2] - p[2];
          if (dx * dx + dy * dy + dz * dz < 1e-24) {
            found = q;
            break;
          }
        }
        if (found == nd) {
          memcpy(d[nd], p, sizeof p);
          ++nd;
        }
        grid[i * (2 * f + 3 - i) / 2 + j] = (uint32_t)found;
      }
    }
    for (unsigned i = 0; i < f; ++i) {
      for (unsigned j = 0; j + i < f; ++j) {
        const uint32_t p00 = grid[i * (2 * f + 3 - i) / 2 + j];
        const uint32_t p10 = grid[(i + 1) * (2 * f + 3 - (i + 1)) / 2 + j];
        const uint32_t p01 = grid[i * (2 * f + 3 - i) / 2 + j + 1];
        t[it][0] = p00;
        t[it][1] = p10;
        t[it][2] = p01;
        ++it;
        if (j + i + 1 < f) {
          const uint32_t p11 = grid[(i + 1) * (2 * f + 3 - (i + 1)) / 2 + j + 1];
          t[it][0] = p10;
          t[it][1] = p11;
          t[it][2] = p01;
          ++it;
        }
      }
    }
  }
  free(local);
  /* Orient every triangle counter-clockwise seen from outside: det(a, b, c) > 0. */
  for (size_t i = 0; i < it; ++i) {
    const double *a = d[t[i][0]], *b = d[t[i][1]], *c = d[t[i][2]];
    const double det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                       a[2] * (b[0] * c[1] - b[1] * c[0]);
    if (det < 0.0) {
      const uint32_t s = t[i][1];
      t[i][1] = t[i][2];
      t[i][2] = s;
    }
  }
  *dirs = d;
  *dir_count = nd;
  *tris = t;
  *tri_count = it;
  return MODEL_OK;
}

/* x rounded to the nearest float32. Through a volatile: GCC 12.2 at -O2 vectorised the plain
 * (double)(float) round trip in the loop below into a subtraction without the rounding (seen in
 * the disassembly), which would make the -O0 and -O2 builds write different assets. */
static double to_float32(double x) {
  volatile float f = (float)x;
  return (double)f;
}

static model_status_t mesh_alloc(model_mesh_t *m, size_t nv, size_t nt) {
  m->vertices_m = malloc(nv * sizeof *m->vertices_m);
  m->triangles = malloc(nt * sizeof *m->triangles);
  if (m->vertices_m == NULL || m->triangles == NULL) {
    free(m->vertices_m);
    free(m->triangles);
    memset(m, 0, sizeof *m);
    return MODEL_E_NOMEM;
  }
  m->vertex_count = nv;
  m->triangle_count = nt;
  return MODEL_OK;
}

/* ---- the fractured surface: min of the smooth radius and each plane's ----------------------- */

typedef struct {
  const rockgen_spec_t *spec;
  const lobes_t *lobes;
  const double (*n)[3]; /* unit plane normals */
  const double *h;      /* plane offsets */
  size_t planes;
} surface_t;

/* Radius of candidate `label` in direction d: -1 the smooth surface, i >= 0 plane i (infinite
 * where the plane does not face d). */
static double surface_candidate(const surface_t *s, int label, const double d[3]) {
  if (label < 0) return radius_at(s->spec, s->lobes, d);
  const double c = cl_vec3_dot(d, s->n[label]);
  return c > 0.0 ? s->h[label] / c : HUGE_VAL;
}

/* The fractured surface's radius in direction d and which candidate gives it (ties go to the
 * plane, so that a vertex on a rim is put exactly on the plane). */
static double surface_eval(const surface_t *s, const double d[3], int *label) {
  double r = radius_at(s->spec, s->lobes, d);
  *label = -1;
  for (size_t i = 0; i < s->planes; ++i) {
    const double ri = surface_candidate(s, (int)i, d);
    if (ri <= r) {
      r = ri;
      *label = (int)i;
    }
  }
  return r;
}

static double det3(const double a[3], const double b[3], const double c[3]) {
  return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
         a[2] * (b[0] * c[1] - b[1] * c[0]);
}

/* Cosine of the smallest angle of triangle (a, b, c). */
static double min_angle_cos(const double a[3], const double b[3], const double c[3]) {
  const double *p[3] = {a, b, c};
  double worst = -1.0;
  for (int i = 0; i < 3; ++i) {
    double u[3], v[3];
    for (int k = 0; k < 3; ++k) {
      u[k] = p[(i + 1) % 3][k] - p[i][k];
      v[k] = p[(i + 2) % 3][k] - p[i][k];
    }
    const double c_i = cl_vec3_dot(u, v) / sqrt(cl_vec3_dot(u, u) * cl_vec3_dot(v, v));
    if (c_i > worst) worst = c_i;
  }
  return worst;
}

/* Snapping keeps every triangle's angles above 20 degrees (cos 20 deg). */
static const double kMaxAngleCos = 0.93969262078590838;

/* Without this step the edge of a fracture face follows the mesh edges in a staircase. For each
 * mesh edge whose endpoints take their radius from different candidates (a rim: plane/smooth or
 * plane/plane), find where the two candidates are equal (bisection on the arc) and move the
 * nearer endpoint there, unless it moved already or the move would fold a triangle (every
 * triangle must keep a positive solid angle from the origin, which keeps the surface closed and
 * free of self-intersection). The rims then pass through vertices. */
static model_status_t snap_to_rims(const surface_t *s, double (*d)[3], size_t nv, uint32_t (*t)[3],
                                   size_t nt) {
  unsigned char *moved = calloc(nv, 1);
  int *label = malloc(nv * sizeof *label);
  if (moved == NULL || label == NULL) {
    free(moved);
    free(label);
    return MODEL_E_NOMEM;
  }
  for (size_t v = 0; v < nv; ++v) (void)surface_eval(s, d[v], &label[v]);
  for (size_t i = 0; i < nt; ++i) {
    for (int e = 0; e < 3; ++e) {
      const uint32_t a = t[i][e], b = t[i][(e + 1) % 3];
      if (label[a] == label[b] || moved[a] || moved[b]) continue;
      /* g(x) = R_a - R_b along the arc: <= 0 at a, >= 0 at b. */
      double lo = 0.0, hi = 1.0, p[3];
      for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (lo + hi);
        for (int k = 0; k < 3; ++k) p[k] = (1.0 - mid) * d[a][k] + mid * d[b][k];
        (void)cl_vec3_normalize(p, p);
        if (surface_candidate(s, label[a], p) - surface_candidate(s, label[b], p) <= 0.0) {
          lo = mid;
        } else {
          hi = mid;
        }
      }
      const double x = 0.5 * (lo + hi);
      for (int k = 0; k < 3; ++k) p[k] = (1.0 - x) * d[a][k] + x * d[b][k];
      (void)cl_vec3_normalize(p, p);
      const uint32_t w = x < 0.5 ? a : b;
      double old[3];
      memcpy(old, d[w], sizeof old);
      memcpy(d[w], p, sizeof p);
      int bad = 0;
      for (size_t j = 0; j < nt && !bad; ++j) {
        if (t[j][0] == w || t[j][1] == w || t[j][2] == w) {
          bad = det3(d[t[j][0]], d[t[j][1]], d[t[j][2]]) <= 0.0 ||
                min_angle_cos(d[t[j][0]], d[t[j][1]], d[t[j][2]]) > kMaxAngleCos;
        }
      }
      if (bad) {
        memcpy(d[w], old, sizeof old);
        continue;
      }
      moved[w] = 1;
      (void)surface_eval(s, d[w], &label[w]);
    }
  }
  free(moved);
  free(label);
  return MODEL_OK;
}

/* ---- the rock -------------------------------------------------------------------------------- */

static int spec_valid(const rockgen_spec_t *spec) {
  if (spec == NULL || spec->frequency == 0 || spec->frequency > 64) return 0;
  if (spec->fracture_count > ROCKGEN_MAX_FRACTURES) return 0;
  if (spec->lobe_count + spec->bump_count > MAX_LOBES) return 0;
  for (int k = 0; k < 3; ++k) {
    if (!(spec->semi_axes_m[k] > 0.0) || !isfinite(spec->semi_axes_m[k])) return 0;
  }
  if (!(spec->lobe_cos < 1.0) || !(spec->bump_cos < 1.0)) return 0;
  for (size_t i = 0; i < spec->fracture_count; ++i) {
    const rockgen_fracture_t *fr = &spec->fractures[i];
    if (!(cl_vec3_dot(fr->normal, fr->normal) > 0.0) || !(fr->depth_m >= 0.0)) return 0;
  }
  return 1;
}

/* Fracture plane i (unit normal n[i], offset h[i]) placed depth_m inside the unfractured surface
 * of radii r[] in directions d[]. MODEL_E_ARG when a plane would pass behind the center. */
static model_status_t fractures_place(const rockgen_spec_t *spec, const double (*d)[3],
                                      const double *r, size_t nv,
                                      double n[ROCKGEN_MAX_FRACTURES][3],
                                      double h[ROCKGEN_MAX_FRACTURES]) {
  model_status_t st = MODEL_OK;
  for (size_t i = 0; i < spec->fracture_count; ++i) {
    for (int k = 0; k < 3; ++k) n[i][k] = spec->fractures[i].normal[k];
    (void)cl_vec3_normalize(n[i], n[i]);
    double extreme = 0.0;
    for (size_t v = 0; v < nv; ++v) {
      const double s = r[v] * cl_vec3_dot(d[v], n[i]);
      if (s > extreme) extreme = s;
    }
    h[i] = extreme - spec->fractures[i].depth_m;
    if (!(h[i] > 0.0)) st = MODEL_E_ARG;
  }
  return st;
}

/* out's vertices at radius r[v] in direction d[v] (a vertex labelled with a plane put onto it),
 * then moved to the bounding-box center and rounded to float32. */
static void vertices_write(model_mesh_t *out, const surface_t *s, const double (*d)[3],
                           const double *r, const int *plane_of) {
  const size_t nv = out->vertex_count;
  double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (size_t v = 0; v < nv; ++v) {
    double p[3];
    for (int k = 0; k < 3; ++k) p[k] = r[v] * d[v][k];
    if (plane_of[v] >= 0) { /* onto its plane to the last bit the arithmetic allows */
      const double *pn = s->n[plane_of[v]];
      const double e = cl_vec3_dot(p, pn) - s->h[plane_of[v]];
      for (int k = 0; k < 3; ++k) p[k] -= e * pn[k];
    }
    for (int k = 0; k < 3; ++k) {
      out->vertices_m[v][k] = p[k];
      if (p[k] < lo[k]) lo[k] = p[k];
      if (p[k] > hi[k]) hi[k] = p[k];
    }
  }
  /* Link frame: origin at the bounding-box center; then float32, as the STL file stores. */
  double center[3];
  for (int k = 0; k < 3; ++k) center[k] = 0.5 * (lo[k] + hi[k]);
  for (size_t v = 0; v < nv; ++v) {
    for (int k = 0; k < 3; ++k) {
      out->vertices_m[v][k] = to_float32(out->vertices_m[v][k] - center[k]);
    }
  }
}

model_status_t rockgen_shape_build(const rockgen_spec_t *spec, model_mesh_t *out) {
  if (out == NULL) return MODEL_E_ARG;
  memset(out, 0, sizeof *out);
  if (!spec_valid(spec)) return MODEL_E_ARG;

  lobes_t lobes;
  memset(&lobes, 0, sizeof lobes);
  uint64_t state = spec->seed;
  lobes_draw(&state, spec->lobe_count, spec->lobe_amplitude, spec->lobe_cos, &lobes);
  lobes_draw(&state, spec->bump_count, spec->bump_amplitude, spec->bump_cos, &lobes);

  double(*d)[3] = NULL;
  uint32_t(*t)[3] = NULL;
  size_t nv = 0, nt = 0;
  model_status_t st = geodesic_build(spec->frequency, &d, &nv, &t, &nt);
  if (st != MODEL_OK) return st;

  double *r = malloc(nv * sizeof *r);
  int *plane_of = malloc(nv * sizeof *plane_of);
  if (r == NULL || plane_of == NULL) {
    free(d);
    free(t);
    free(r);
    free(plane_of);
    return MODEL_E_NOMEM;
  }
  for (size_t v = 0; v < nv; ++v) {
    r[v] = radius_at(spec, &lobes, d[v]);
    plane_of[v] = -1;
    if (!(r[v] > 0.0)) st = MODEL_E_ARG; /* lobes too strong for this shape */
  }

  /* Fracture planes, each placed against the unfractured surface. */
  double n[ROCKGEN_MAX_FRACTURES][3], h[ROCKGEN_MAX_FRACTURES];
  if (fractures_place(spec, (const double(*)[3])d, r, nv, n, h) != MODEL_OK) st = MODEL_E_ARG;
  const surface_t surf = {spec, &lobes, (const double(*)[3])n, h, spec->fracture_count};
  if (st == MODEL_OK) st = snap_to_rims(&surf, d, nv, t, nt);
  for (size_t v = 0; v < nv; ++v) r[v] = surface_eval(&surf, d[v], &plane_of[v]);

  if (st == MODEL_OK) st = mesh_alloc(out, nv, nt);
  if (st == MODEL_OK) {
    vertices_write(out, &surf, (const double(*)[3])d, r, plane_of);
    memcpy(out->triangles, t, nt * sizeof *t);
  }
  free(d);
  free(t);
  free(r);
  free(plane_of);
  if (st != MODEL_OK) model_mesh_free(out);
  return st;
}

model_status_t rockgen_mass(const rockgen_spec_t *spec, const model_mesh_t *mesh,
                            model_mass_t *even, model_mass_t *uneven, model_halfspace_t *region) {
  if (spec == NULL || mesh == NULL) return MODEL_E_ARG;
  model_mass_t e, u;
  model_halfspace_t reg;
  model_status_t st = model_mesh_mass(mesh, spec->density_kg_m3, &e);
  if (st != MODEL_OK) return st;
  for (int k = 0; k < 3; ++k) reg.normal[k] = spec->region_normal[k];
  if (!(cl_vec3_dot(reg.normal, reg.normal) > 0.0)) return MODEL_E_REGION;
  (void)cl_vec3_normalize(reg.normal, reg.normal);
  reg.offset_m = cl_vec3_dot(reg.normal, e.com_m) + spec->region_offset_m;
  st = model_mesh_mass_halfspace(mesh, spec->density_kg_m3, &reg, spec->region_density_kg_m3, &u);
  if (st != MODEL_OK) return st;
  if (even != NULL) *even = e;
  if (uneven != NULL) *uneven = u;
  if (region != NULL) *region = reg;
  return MODEL_OK;
}
