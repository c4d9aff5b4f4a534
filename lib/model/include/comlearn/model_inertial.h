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
model_status_t model_inertial_load(const char *urdf_path, const char *link_name, model_mass_t *out,
                                   model_error_t *err);

/* Physical validity of mass properties: every number finite (mass, com, inertia); mass > 0;
 * inertia symmetric (|I_ij - I_ji| <= 1e-9 max |I|) and positive definite (smallest principal
 * moment > 0); principal moments satisfy the triangle inequality (the largest <= (sum of the other
 * two) (1 + 1e-9); equality, a flat plate, passes). MODEL_E_ARG for NULL, MODEL_E_INERTIAL or
 * MODEL_E_INERTIA_TRIANGLE otherwise, with the offending numbers in err. Does not allocate. */
model_status_t model_mass_check(const model_mass_t *mass, model_error_t *err);

/* Limits of model_mass_plausible() (docs/model.md says why these numbers). */
#define MODEL_MASS_MIN_KG 1e-3          /* 1 g: a paper clip; lighter is no object to place */
#define MODEL_MASS_MAX_KG 10.0          /* 10 kg: 20 x the YuMi's payload per arm */
#define MODEL_DENSITY_MIN_KG_M3 10.0    /* mean density: expanded polystyrene, sealed shells */
#define MODEL_DENSITY_MAX_KG_M3 25000.0 /* above osmium (22 590), the densest element */

/* Whether mass properties are those of a real object whose surface is `mesh` (closed and outward,
 * as model_object_load() gives it; the same frame as mass, the URDF link frame). Every simulator
 * loader runs it on the truth before physics sees it. In this order, each failure naming the
 * number and the limit in err:
 *   model_mass_check(mass) first (its statuses: MODEL_E_INERTIAL, MODEL_E_INERTIA_TRIANGLE);
 *   MODEL_E_IMPLAUSIBLE  mass outside [MODEL_MASS_MIN_KG, MODEL_MASS_MAX_KG];
 *   the mesh, as model_mesh_mass() judges it: MODEL_E_ARG (NULL, an index out of range),
 *             MODEL_E_NONFINITE (a vertex), MODEL_E_DEGENERATE (empty, under 4 triangles, or
 *             a volume not clearly > 0);
 *   MODEL_E_IMPLAUSIBLE  mean density mass / mesh volume outside
 *                        [MODEL_DENSITY_MIN_KG_M3, MODEL_DENSITY_MAX_KG_M3];
 *   MODEL_E_IMPLAUSIBLE  the CoM outside the mesh's bounding box (slack 1e-9 x its diagonal): a
 *                        CoM is an average of points of the body;
 *   MODEL_E_IMPLAUSIBLE  a principal moment above mass x r^2 (1 + 1e-9), r the largest distance
 *                        from the CoM to a mesh vertex: no mass element is farther than r from any
 *                        axis through the CoM (the body lies in the vertices' convex hull);
 *   MODEL_E_IMPLAUSIBLE  the sum of the principal moments below (6/5) mass R^2 (1 - 1e-9), R the
 *                        radius of a ball of mass `mass` at MODEL_DENSITY_MAX_KG_M3: the sum is
 *                        2 x the integral of rho |x - com|^2, least when the mass is packed as
 *                        densely as any material allows into a ball around the CoM.
 * MODEL_OK when all hold. Does not allocate. */
model_status_t model_mass_plausible(const model_mass_t *mass, const model_mesh_t *mesh,
                                    model_error_t *err);

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
