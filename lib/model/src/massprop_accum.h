/*
 * massprop_accum.h - private to lib/model: the one signed-tetrahedron accumulator behind
 * model_mesh_mass() (massprop.c) and model_mesh_mass_halfspace() (massprop_halfspace.c).
 *
 * A closed, outward surface bounds a solid whose volume integrals are the sums over its triangles
 * (a, b, c) of the integrals over the signed tetrahedra (ref, a, b, c), for any reference point
 * ref (divergence theorem). The accumulator keeps the raw moments about ref:
 *   vol          = integral of 1
 *   first[i]     = integral of (x - ref)_i
 *   second[i][j] = integral of (x - ref)_i (x - ref)_j
 * Keeping ref near the body keeps the coordinates small, so that the final shift to the CoM
 * (second - vol * c c^T) does not cancel digits away.
 *
 * No allocation, no I/O. The functions are defined in massprop.c.
 */
#ifndef COMLEARN_MODEL_MASSPROP_ACCUM_H
#define COMLEARN_MODEL_MASSPROP_ACCUM_H

#include "comlearn/model.h"

typedef struct {
  double ref_m[3];
  double vol;
  double first[3];
  double second[3][3];
} model_massprop_acc_t;

/* Zero moments about ref_m. */
void model_massprop_acc_init(model_massprop_acc_t *acc, const double ref_m[3]);

/* Add the signed tetrahedron (ref, a, b, c); a, b, c in absolute coordinates, counter-clockwise
 * seen from outside the solid. */
void model_massprop_acc_add_triangle(model_massprop_acc_t *acc, const double a[3],
                                     const double b[3], const double c[3]);

/* dst += weight * src, with src's moments first re-expressed about dst's reference point. */
void model_massprop_acc_add_scaled(model_massprop_acc_t *dst, const model_massprop_acc_t *src,
                                   double weight);

/* Mass properties of the accumulated solid at density_kg_m3 (moments already weighted by
 * densities are finished with density 1). MODEL_E_DEGENERATE when the mass is not positive or
 * below min_mass; MODEL_E_NONFINITE on overflow; out is zeroed on error. */
model_status_t model_massprop_acc_finish(const model_massprop_acc_t *acc, double density_kg_m3,
                                         double min_mass, model_mass_t *out);

/* Shared argument checks: mesh non-NULL and non-empty (else MODEL_E_ARG / MODEL_E_DEGENERATE),
 * indices in range (MODEL_E_ARG), every vertex finite (MODEL_E_NONFINITE). On success writes the
 * bounding-box center (the reference point) and the largest box extent. */
model_status_t model_massprop_mesh_validate(const model_mesh_t *mesh, double center_m[3],
                                            double *extent_m);

/* Smallest meaningful volume for a mesh of this extent: volumes below it are rounding noise. */
double model_massprop_min_volume(double extent_m);

#endif /* COMLEARN_MODEL_MASSPROP_ACCUM_H */
