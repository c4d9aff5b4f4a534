/* massprop.c - exact mass properties of a closed polyhedron by signed tetrahedra. */
#include <math.h>
#include <string.h>

#include "comlearn/model.h"
#include "massprop_accum.h"

void model_massprop_acc_init(model_massprop_acc_t *acc, const double ref_m[3]) {
  memset(acc, 0, sizeof *acc);
  for (int i = 0; i < 3; ++i) acc->ref_m[i] = ref_m[i];
}

/* Tetrahedron (0, a, b, c) with det = a . (b x c) = 6 V:
 *   integral of x       = V (a + b + c) / 4
 *   integral of x x^T   = V / 20 (a a^T + b b^T + c c^T + s s^T),  s = a + b + c
 * (the second moment of a simplex is V/20 times the sum of its vertices' outer products plus the
 * outer product of their sum; the vertex at the origin adds nothing). */
void model_massprop_acc_add_triangle(model_massprop_acc_t *acc, const double a_abs[3],
                                     const double b_abs[3], const double c_abs[3]) {
  double a[3], b[3], c[3], s[3];
  for (int i = 0; i < 3; ++i) {
    a[i] = a_abs[i] - acc->ref_m[i];
    b[i] = b_abs[i] - acc->ref_m[i];
    c[i] = c_abs[i] - acc->ref_m[i];
    s[i] = a[i] + b[i] + c[i];
  }
  const double det = a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) +
                     a[2] * (b[0] * c[1] - b[1] * c[0]);
  const double vol = det / 6.0;
  acc->vol += vol;
  for (int i = 0; i < 3; ++i) acc->first[i] += vol * s[i] / 4.0;
  const double w = vol / 20.0;
  for (int i = 0; i < 3; ++i) {
    for (int j = i; j < 3; ++j) {
      acc->second[i][j] += w * (a[i] * a[j] + b[i] * b[j] + c[i] * c[j] + s[i] * s[j]);
    }
  }
}

/* Moments about r re-expressed about r' = r - d (d = r - r'):
 *   first'  = first + vol d
 *   second' = second + first d^T + d first^T + vol d d^T */
void model_massprop_acc_add_scaled(model_massprop_acc_t *dst, const model_massprop_acc_t *src,
                                   double weight) {
  double d[3];
  for (int i = 0; i < 3; ++i) d[i] = src->ref_m[i] - dst->ref_m[i];
  dst->vol += weight * src->vol;
  for (int i = 0; i < 3; ++i) dst->first[i] += weight * (src->first[i] + src->vol * d[i]);
  for (int i = 0; i < 3; ++i) {
    for (int j = i; j < 3; ++j) {
      dst->second[i][j] += weight * (src->second[i][j] + src->first[i] * d[j] +
                                     d[i] * src->first[j] + src->vol * d[i] * d[j]);
    }
  }
}

model_status_t model_massprop_acc_finish(const model_massprop_acc_t *acc, double density_kg_m3,
                                         double min_mass, model_mass_t *out) {
  memset(out, 0, sizeof *out);
  const double mass = density_kg_m3 * acc->vol;
  if (!isfinite(mass)) return MODEL_E_NONFINITE;
  if (!(mass > 0.0) || mass < min_mass) return MODEL_E_DEGENERATE;
  double c[3];
  for (int i = 0; i < 3; ++i) c[i] = acc->first[i] / acc->vol;
  /* Second moment about the CoM (per unit density), upper triangle. */
  double cov[3][3];
  for (int i = 0; i < 3; ++i) {
    for (int j = i; j < 3; ++j) cov[i][j] = acc->second[i][j] - acc->vol * c[i] * c[j];
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < i; ++j) cov[i][j] = cov[j][i];
  }
  const double trace = cov[0][0] + cov[1][1] + cov[2][2];
  out->mass_kg = mass;
  for (int i = 0; i < 3; ++i) {
    out->com_m[i] = acc->ref_m[i] + c[i];
    for (int j = 0; j < 3; ++j) {
      out->inertia_kg_m2[i][j] = density_kg_m3 * ((i == j ? trace : 0.0) - cov[i][j]);
    }
  }
  for (int i = 0; i < 3; ++i) {
    if (!isfinite(out->com_m[i])) {
      memset(out, 0, sizeof *out);
      return MODEL_E_NONFINITE;
    }
    for (int j = 0; j < 3; ++j) {
      if (!isfinite(out->inertia_kg_m2[i][j])) {
        memset(out, 0, sizeof *out);
        return MODEL_E_NONFINITE;
      }
    }
  }
  return MODEL_OK;
}

model_status_t model_massprop_mesh_validate(const model_mesh_t *mesh, double center_m[3],
                                            double *extent_m) {
  if (mesh == NULL) return MODEL_E_ARG;
  if (mesh->triangle_count == 0 || mesh->vertex_count == 0) return MODEL_E_DEGENERATE;
  if (mesh->vertices_m == NULL || mesh->triangles == NULL) return MODEL_E_ARG;
  if (mesh->triangle_count < 4) return MODEL_E_DEGENERATE;
  double lo[3], hi[3];
  for (int k = 0; k < 3; ++k) lo[k] = hi[k] = mesh->vertices_m[0][k];
  for (size_t v = 0; v < mesh->vertex_count; ++v) {
    for (int k = 0; k < 3; ++k) {
      const double x = mesh->vertices_m[v][k];
      if (!isfinite(x)) return MODEL_E_NONFINITE;
      if (x < lo[k]) lo[k] = x;
      if (x > hi[k]) hi[k] = x;
    }
  }
  for (size_t t = 0; t < mesh->triangle_count; ++t) {
    for (int k = 0; k < 3; ++k) {
      if (mesh->triangles[t][k] >= mesh->vertex_count) return MODEL_E_ARG;
    }
  }
  double extent = 0.0;
  for (int k = 0; k < 3; ++k) {
    center_m[k] = 0.5 * (lo[k] + hi[k]);
    if (hi[k] - lo[k] > extent) extent = hi[k] - lo[k];
  }
  *extent_m = extent;
  return MODEL_OK;
}

double model_massprop_min_volume(double extent_m) {
  /* Far below any real solid of that size (a 1e-6 x 1 x 1 slab relative to its extent), far
   * above the rounding noise of a closed surface's signed volume (~1e-16 extent^3). */
  return 1e-12 * extent_m * extent_m * extent_m;
}

model_status_t model_mesh_mass(const model_mesh_t *mesh, double density_kg_m3, model_mass_t *out) {
  if (out == NULL) return MODEL_E_ARG;
  memset(out, 0, sizeof *out);
  if (!isfinite(density_kg_m3) || !(density_kg_m3 > 0.0)) return MODEL_E_ARG;
  double ref[3], extent;
  model_status_t st = model_massprop_mesh_validate(mesh, ref, &extent);
  if (st != MODEL_OK) return st;
  model_massprop_acc_t acc;
  model_massprop_acc_init(&acc, ref);
  for (size_t t = 0; t < mesh->triangle_count; ++t) {
    const uint32_t *tri = mesh->triangles[t];
    model_massprop_acc_add_triangle(&acc, mesh->vertices_m[tri[0]], mesh->vertices_m[tri[1]],
                                    mesh->vertices_m[tri[2]]);
  }
  return model_massprop_acc_finish(&acc, density_kg_m3,
                                   density_kg_m3 * model_massprop_min_volume(extent), out);
}
