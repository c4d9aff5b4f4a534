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
 * inertia tensor about the CoM expressed in link-frame axes: I_link = R I R^T with R the inertial
 * origin's rotation (rpy, R = Rz(yaw) Ry(pitch) Rx(roll)); the result is made exactly symmetric.
 * link_name NULL means the root link. The result is checked with model_mass_check().
 * Errors (messages name the URDF and the link): MODEL_E_ARG, MODEL_E_NOFILE, MODEL_E_PARSE (as in
 * model_object_load, including an <inertial> urdfdom could not parse, e.g. mass "nan"),
 * MODEL_E_NOLINK, MODEL_E_INERTIAL (no <inertial>, or invalid values),
 * MODEL_E_INERTIA_TRIANGLE. On error *out is zeroed. Allocates temporarily (urdfdom). */
model_status_t model_inertial_load(const char *urdf_path, const char *link_name,
                                   model_mass_t *out, model_error_t *err);

/* Physical validity of mass properties: every number finite (mass, com, inertia); mass > 0;
 * inertia symmetric (|I_ij - I_ji| <= 1e-9 max |I|) and positive definite (smallest principal
 * moment > 0); principal moments satisfy the triangle inequality (the largest <= (sum of the other
 * two) (1 + 1e-9); equality, a flat plate, passes). MODEL_E_ARG for NULL, MODEL_E_INERTIAL or
 * MODEL_E_INERTIA_TRIANGLE otherwise, with the offending numbers in err. Does not allocate. */
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

/* Principal moments (ascending) and axes (columns of axes[3][3], unit, right-handed: I axes[:,i] =
 * moments[i] axes[:,i]) of a symmetric inertia tensor, by cyclic Jacobi (at most 64 sweeps; a
 * few suffice). Only the symmetric part (I + I^T) / 2 is used. MODEL_E_ARG for NULL,
 * MODEL_E_INERTIAL if it does not converge or the input is not finite. Does not allocate.
 * In C before C23, pass a non-const double[3][3] as (const double(*)[3])I. */
model_status_t model_inertia_principal(const double inertia_kg_m2[3][3], double moments[3],
                                       double axes[3][3]);

#ifdef __cplusplus
}
#endif

#endif /* COMLEARN_MODEL_INERTIAL_H */
