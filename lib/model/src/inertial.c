/* inertial.c - the inertial truth of a URDF link, and physical checks of mass properties.
 * Part of comlearn_model_sim only. */
#include <math.h>
#include <string.h>

#include "comlearn/math3d.h"
#include "comlearn/model_inertial.h"
#include "model_internal.h"

enum { JACOBI_MAX_SWEEPS = 64 };

static const double SYMMETRY_TOL = 1e-9;
static const double TRIANGLE_TOL = 1e-9;

/* Rotates the (p, q) pair of a to zero: a <- J^T a J and v <- v J, with J the Jacobi rotation
 * in the (p, q) plane. */
static void jacobi_rotate(double a[3][3], double v[3][3], int p, int q) {
  double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
  double t = (theta >= 0.0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
  double c = 1.0 / sqrt(t * t + 1.0);
  double s = t * c;
  for (int k = 0; k < 3; ++k) {
    double akp = a[k][p], akq = a[k][q];
    a[k][p] = c * akp - s * akq;
    a[k][q] = s * akp + c * akq;
  }
  for (int k = 0; k < 3; ++k) {
    double apk = a[p][k], aqk = a[q][k];
    a[p][k] = c * apk - s * aqk;
    a[q][k] = s * apk + c * aqk;
  }
  for (int k = 0; k < 3; ++k) {
    double vkp = v[k][p], vkq = v[k][q];
    v[k][p] = c * vkp - s * vkq;
    v[k][q] = s * vkp + c * vkq;
  }
}

/* Cyclic Jacobi: rotate each off-diagonal pair to zero; converges quadratically. `scale` is
 * the squared Frobenius norm of a. Returns 1 when converged within JACOBI_MAX_SWEEPS. */
static int jacobi_diagonalize(double a[3][3], double v[3][3], double scale) {
  for (int sweep = 0; sweep < JACOBI_MAX_SWEEPS; ++sweep) {
    double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    if (off <= 1e-32 * scale) {
      return 1;
    }
    for (int p = 0; p < 2; ++p) {
      for (int q = p + 1; q < 3; ++q) {
        if (a[p][q] == 0.0) {
          continue;
        }
        jacobi_rotate(a, v, p, q);
      }
    }
  }
  return 0;
}

/* Sort ascending (columns move with their moments), then make the frame right-handed. */
static void principal_sort(const double a[3][3], const double v[3][3], double moments[3],
                           double axes[3][3]) {
  int order[3] = {0, 1, 2};
  for (int i = 0; i < 3; ++i) {
    for (int j = i + 1; j < 3; ++j) {
      if (a[order[j]][order[j]] < a[order[i]][order[i]]) {
        int t = order[i];
        order[i] = order[j];
        order[j] = t;
      }
    }
  }
  for (int i = 0; i < 3; ++i) {
    moments[i] = a[order[i]][order[i]];
    for (int k = 0; k < 3; ++k) {
      axes[k][i] = v[k][order[i]];
    }
  }
  double det = axes[0][0] * (axes[1][1] * axes[2][2] - axes[1][2] * axes[2][1]) -
               axes[0][1] * (axes[1][0] * axes[2][2] - axes[1][2] * axes[2][0]) +
               axes[0][2] * (axes[1][0] * axes[2][1] - axes[1][1] * axes[2][0]);
  if (det < 0.0) {
    for (int k = 0; k < 3; ++k) {
      axes[k][2] = -axes[k][2];
    }
  }
}

model_status_t model_inertia_principal(const double inertia_kg_m2[3][3], double moments[3],
                                       double axes[3][3]) {
  if (inertia_kg_m2 == NULL || moments == NULL || axes == NULL) {
    return MODEL_E_ARG;
  }
  double a[3][3], v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  double scale = 0.0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (!isfinite(inertia_kg_m2[i][j])) {
        return MODEL_E_INERTIAL;
      }
      /* Symmetrise: only the symmetric part has real eigenvalues and orthogonal axes. */
      a[i][j] = 0.5 * (inertia_kg_m2[i][j] + inertia_kg_m2[j][i]);
      scale += a[i][j] * a[i][j];
    }
  }
  if (!jacobi_diagonalize(a, v, scale)) {
    return MODEL_E_INERTIAL;
  }
  principal_sort((const double(*)[3])a, (const double(*)[3])v, moments, axes);
  return MODEL_OK;
}

model_status_t model_mass_check(const model_mass_t *mass, model_error_t *err) {
  if (mass == NULL) {
    return model_fail(err, MODEL_E_ARG, "mass properties are NULL");
  }
  const double(*I)[3] = mass->inertia_kg_m2;
  int finite = isfinite(mass->mass_kg);
  for (int i = 0; i < 3; ++i) {
    finite = finite && isfinite(mass->com_m[i]);
    for (int j = 0; j < 3; ++j) {
      finite = finite && isfinite(I[i][j]);
    }
  }
  if (!finite) {
    return model_fail(err, MODEL_E_INERTIAL, "mass, center of mass or inertia is not finite");
  }
  if (!(mass->mass_kg > 0.0)) {
    return model_fail(err, MODEL_E_INERTIAL, "mass %g kg is not positive", mass->mass_kg);
  }
  double scale = 0.0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      scale = fmax(scale, fabs(I[i][j]));
    }
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = i + 1; j < 3; ++j) {
      if (fabs(I[i][j] - I[j][i]) > SYMMETRY_TOL * scale) {
        return model_fail(err, MODEL_E_INERTIAL,
                          "inertia is not symmetric: I[%d][%d] = %g, "
                          "I[%d][%d] = %g",
                          i, j, I[i][j], j, i, I[j][i]);
      }
    }
  }
  double m[3], axes[3][3];
  if (model_inertia_principal(I, m, axes) != MODEL_OK) {
    return model_fail(err, MODEL_E_INERTIAL, "principal moments of inertia did not converge");
  }
  if (!(m[0] > 0.0)) {
    return model_fail(err, MODEL_E_INERTIAL,
                      "inertia is not positive definite: principal moments %g, %g, %g kg m^2", m[0],
                      m[1], m[2]);
  }
  /* Ascending order: only the largest can exceed the sum of the other two. */
  if (m[2] > (m[0] + m[1]) * (1.0 + TRIANGLE_TOL)) {
    return model_fail(err, MODEL_E_INERTIA_TRIANGLE,
                      "principal moments %g, %g, %g kg m^2 violate the triangle inequality "
                      "(%g > %g + %g)",
                      m[0], m[1], m[2], m[2], m[0], m[1]);
  }
  return MODEL_OK;
}

/* ---- plausibility against the mesh ------------------------------------------------------- */

static const double PLAUSIBLE_REL_TOL = 1e-9;

static model_status_t plausible_density(double mass_kg, double volume_m3, model_error_t *err) {
  const double density = mass_kg / volume_m3;
  if (density < MODEL_DENSITY_MIN_KG_M3 || density > MODEL_DENSITY_MAX_KG_M3) {
    return model_fail(err, MODEL_E_IMPLAUSIBLE,
                      "mean density %g kg/m^3 (mass %g kg / mesh "
                      "volume %g m^3) is outside the range of solids [%g, %g] kg/m^3",
                      density, mass_kg, volume_m3, MODEL_DENSITY_MIN_KG_M3,
                      MODEL_DENSITY_MAX_KG_M3);
  }
  return MODEL_OK;
}

static model_status_t plausible_com(const double com_m[3], const model_aabb_t *box,
                                    model_error_t *err) {
  double d2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double e = box->max_m[k] - box->min_m[k];
    d2 += e * e;
  }
  const double slack = PLAUSIBLE_REL_TOL * sqrt(d2);
  for (int k = 0; k < 3; ++k) {
    if (com_m[k] < box->min_m[k] - slack || com_m[k] > box->max_m[k] + slack) {
      return model_fail(err, MODEL_E_IMPLAUSIBLE,
                        "center of mass (%g, %g, %g) m is outside the "
                        "mesh's bounding box: %c = %g m not in [%g, %g] m",
                        com_m[0], com_m[1], com_m[2], "xyz"[k], com_m[k], box -> min_m[k],
                        box -> max_m[k]);
    }
  }
  return MODEL_OK;
}

/* Principal moments against the two rigorous bounds in model_inertial.h. */
static model_status_t plausible_moments(const model_mass_t *mass, const model_mesh_t *mesh,
                                        model_error_t *err) {
  double r2 = 0.0;
  for (size_t v = 0; v < mesh->vertex_count; ++v) {
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double d = mesh->vertices_m[v][k] - mass->com_m[k];
      d2 += d * d;
    }
    r2 = fmax(r2, d2);
  }
  double m[3], axes[3][3];
  if (model_inertia_principal(mass->inertia_kg_m2, m, axes) != MODEL_OK) {
    return model_fail(err, MODEL_E_INERTIAL, "principal moments of inertia did not converge");
  }
  const double upper = mass->mass_kg * r2;
  if (m[2] > upper * (1.0 + PLAUSIBLE_REL_TOL)) {
    return model_fail(err, MODEL_E_IMPLAUSIBLE,
                      "principal moment %g kg m^2 exceeds mass x "
                      "(farthest mesh vertex from the CoM)^2 = %g kg x (%g m)^2 = %g kg m^2",
                      m[2], mass->mass_kg, sqrt(r2), upper);
  }
  /* Least sum of moments: the mass packed into a ball at the densest material's density. */
  const double ball_r = cbrt(3.0 * mass->mass_kg / (4.0 * CL_PI * MODEL_DENSITY_MAX_KG_M3));
  const double lower = 1.2 * mass->mass_kg * ball_r * ball_r;
  const double sum = m[0] + m[1] + m[2];
  if (sum < lower * (1.0 - PLAUSIBLE_REL_TOL)) {
    return model_fail(err, MODEL_E_IMPLAUSIBLE,
                      "principal moments sum to %g kg m^2, below "
                      "%g kg m^2, the least for %g kg (a ball of radius %g m at %g kg/m^3)",
                      sum, lower, mass->mass_kg, ball_r, MODEL_DENSITY_MAX_KG_M3);
  }
  return MODEL_OK;
}

model_status_t model_mass_plausible(const model_mass_t *mass, const model_mesh_t *mesh,
                                    model_error_t *err) {
  model_status_t st = model_mass_check(mass, err);
  if (st != MODEL_OK) {
    return st;
  }
  if (mass->mass_kg < MODEL_MASS_MIN_KG || mass->mass_kg > MODEL_MASS_MAX_KG) {
    return model_fail(err, MODEL_E_IMPLAUSIBLE,
                      "mass %g kg is outside the plausible range "
                      "[%g, %g] kg",
                      mass->mass_kg, MODEL_MASS_MIN_KG, MODEL_MASS_MAX_KG);
  }
  if (mesh == NULL) {
    return model_fail(err, MODEL_E_ARG, "mesh is NULL");
  }
  model_mass_t unit;
  st = model_mesh_mass(mesh, 1.0, &unit);
  if (st != MODEL_OK) {
    return model_fail(err, st, "the mesh has no usable volume (%s)", model_status_str(st));
  }
  model_aabb_t box;
  st = model_mesh_aabb(mesh, &box);
  if (st != MODEL_OK) {
    return model_fail(err, st, "the mesh has no bounding box (%s)", model_status_str(st));
  }
  st = plausible_density(mass->mass_kg, unit.mass_kg, err);
  if (st == MODEL_OK) st = plausible_com(mass->com_m, &box, err);
  if (st == MODEL_OK) st = plausible_moments(mass, mesh, err);
  return st;
}

model_status_t model_inertial_load(const char *urdf_path, const char *link_name, model_mass_t *out,
                                   model_error_t *err) {
  if (out == NULL) {
    return model_fail(err, MODEL_E_ARG, "model_inertial_load: NULL output");
  }
  memset(out, 0, sizeof *out);
  model_urdf_inertial_t in;
  model_status_t st = model_urdf_inertial_read(urdf_path, link_name, &in, err);
  if (st != MODEL_OK) {
    return st;
  }
  model_mass_t m;
  memset(&m, 0, sizeof m);
  m.mass_kg = in.mass_kg;
  memcpy(m.com_m, in.com_m, sizeof m.com_m);
  /* Inertia in link axes: R I R^T, R = link <- inertial frame. */
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      double s = 0.0;
      for (int k = 0; k < 3; ++k) {
        for (int l = 0; l < 3; ++l) {
          s += in.rot[i][k] * in.inertia_kg_m2[k][l] * in.rot[j][l];
        }
      }
      m.inertia_kg_m2[i][j] = s;
    }
  }
  /* Rounding in R I R^T leaves an asymmetry of a few ulps; make it exact. */
  for (int i = 0; i < 3; ++i) {
    for (int j = i + 1; j < 3; ++j) {
      double s = 0.5 * (m.inertia_kg_m2[i][j] + m.inertia_kg_m2[j][i]);
      m.inertia_kg_m2[i][j] = m.inertia_kg_m2[j][i] = s;
    }
  }
  st = model_mass_check(&m, err);
  if (st != MODEL_OK) {
    model_error_prefix(err, "URDF %s: link '%s': <inertial>: ", urdf_path, in.link_name);
    return st;
  }
  *out = m;
  return MODEL_OK;
}
