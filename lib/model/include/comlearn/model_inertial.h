/*
 * comlearn/model_inertial.h - the inertial truth of an object: for the simulator and the asset
 * tools only. Lives in the library comlearn_model_sim; the estimator must never link it (a test
 * checks that comlearn_model itself holds no code that reads <inertial>).
 *
 * Units SI; frames as in comlearn/model.h (the URDF link frame).
 */
#ifndef COMLEARN_MODEL_INERTIAL_H
#define COMLEARN_MODEL_INERTIAL_H

#include "comlearn/model.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Read a link's <inertial> from a URDF: mass, the CoM (the inertial origin's xyz) and the
 * inertia tensor about the CoM expressed in link-frame axes (the inertial origin's rotation
 * applied). link_name NULL means the root link. The result is checked with model_mass_check(). */
model_status_t model_inertial_load(const char *urdf_path, const char *link_name,
                                   model_mass_t *out, model_error_t *err);

/* Physical validity of mass properties: every number finite; mass > 0; inertia symmetric
 * (relative 1e-9) and positive definite; principal moments satisfy the triangle inequality
 * (each <= the sum of the other two, relative tolerance 1e-9). MODEL_E_INERTIAL or
 * MODEL_E_INERTIA_TRIANGLE otherwise. */
model_status_t model_mass_check(const model_mass_t *mass, model_error_t *err);

/* A half-space region { x : normal . x >= offset_m } in the mesh frame. normal need not be unit
 * length but must be finite and non-zero. */
typedef struct {
  double normal[3];
  double offset_m;
} model_halfspace_t;

/* Exact mass properties of a body of two materials: the mesh at density_kg_m3, except its part
 * inside `region` at region_density_kg_m3. Computed by clipping every triangle against the plane
 * and integrating signed tetrahedra from a point on the plane, so the cut face contributes zero and
 * needs no capping: exact up to rounding. Both densities finite and > 0. */
model_status_t model_mesh_mass_halfspace(const model_mesh_t *mesh, double density_kg_m3,
                                         const model_halfspace_t *region,
                                         double region_density_kg_m3, model_mass_t *out);

/* Principal moments (ascending) and axes (columns of axes[3][3], right-handed) of a symmetric
 * inertia tensor, by cyclic Jacobi with an iteration cap; MODEL_E_INERTIAL if it does not
 * converge or the input is not finite. */
model_status_t model_inertia_principal(const double inertia_kg_m2[3][3], double moments[3],
                                       double axes[3][3]);

#ifdef __cplusplus
}
#endif

#endif /* COMLEARN_MODEL_INERTIAL_H */
