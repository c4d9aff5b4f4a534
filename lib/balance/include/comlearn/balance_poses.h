/*
 * comlearn/balance_poses.h - the geometry of a placement (pure geometry, no ODE) and the stable
 * poses of an object (candidates from geometry, confirmed in simulation).
 *
 * Why the geometry: an edge test measures the CoM exactly only where a flat patch of the object
 * crosses the edge along a chord that spans the CoM sideways (docs/physics.md, "Regimes"). On a
 * rounded underside resting on isolated points the object drops onto the edge line when a support
 * passes over it and rolls sideways off that single point (bench_regimes: up to 12 mm, median
 * 1.3 mm inside the truth on the bundled rocks). The functions here tell which regime a planned
 * trial is in, list the flat faces an object can rest on, and choose yaws whose chord spans the
 * CoM estimate.
 *
 * Who passes what (estimator / simulator boundary):
 *   - Every geometric function takes the object's mesh in its link frame (what perception gives)
 *     and a CoM *estimate or guess* in the link frame: the estimator passes its current estimate
 *     or the mesh's uniform-density CoM (model_mesh_mass), never the truth.
 *   - balance_stable_confirm / balance_stable_find run trials in a world whose object carries the
 *     simulator's mass properties (balance_object_create's `mass`, the URDF truth). They take no
 *     CoM for the physics: the truth stays inside the simulated object. Their com_guess only
 *     selects the candidates and where the object is set down.
 *
 * Frames and units: SI. Link frame as in comlearn/balance.h. World: z up, B's top at z = 0.
 * An "orientation" is a unit quaternion (w, x, y, z) of the link frame in the world; |q| must be
 * within 1e-6 of 1 (BALANCE_E_POSE otherwise) and is normalised before use. A yaw is a rotation
 * about world +z applied after the orientation: q' = Rz(yaw) q.
 *
 * Memory: functions that say so allocate temporary memory and free it before returning; every
 * output is caller-owned. Nothing prints. Thread safety: the geometric functions touch only their
 * arguments; the simulation functions follow comlearn/balance.h (one thread per world).
 */
#ifndef COMLEARN_BALANCE_POSES_H
#define COMLEARN_BALANCE_POSES_H

#include <stddef.h>

#include "comlearn/balance.h"
#include "comlearn/model_support.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- stable poses, confirmed in simulation ------------------------------------------------ */

/* Release obj (of `world`; it carries the simulator's mass properties) in `orientation_wxyz`
 * with the link-frame point center_link_m above the middle of B's top, touching it (lowest vertex
 * touch_depth_m below z = 0), and run one trial (balance_trial_run, no noise). *confirmed = 1
 * when the outcome is BALANCE_STAYS within max_rotation_rad and max_displacement_m. trial may be
 * NULL. cfg may be NULL (defaults). Errors: those of balance_trial_run, BALANCE_E_ARG,
 * BALANCE_E_NONFINITE, BALANCE_E_POSE. Allocates only what a trial does. */
balance_status_t balance_stable_confirm(balance_world_t *world, balance_object_t *obj,
                                        const double orientation_wxyz[4],
                                        const double center_link_m[3],
                                        const model_stable_config_t *cfg,
                                        balance_trial_result_t *trial, int *confirmed);

/* One stable pose: a hull face, the trial that confirmed it, the settled pose in trial.settled. */
typedef struct {
  model_face_t face;
  balance_trial_result_t trial;
} balance_stable_pose_t;

/* The stable poses of obj: model_faces_find(obj's mesh, com_guess_link_m) for the candidates
 * (on the hull balance_object_create built: model_faces_find_hull), each confirmed with
 * balance_stable_confirm (with com_guess_link_m over B's middle). Writes the confirmed ones,
 * largest face first, up to `capacity`, and their number (may exceed capacity) to *count;
 * *trials_run (may be NULL) gets the number of trials run. Allocates temporary memory. Errors of
 * model_faces_find and balance_stable_confirm. */
balance_status_t balance_stable_find(balance_world_t *world, balance_object_t *obj,
                                     const double com_guess_link_m[3],
                                     const model_regime_config_t *regime_cfg,
                                     const model_stable_config_t *stable_cfg,
                                     balance_stable_pose_t *poses, size_t capacity, size_t *count,
                                     size_t *trials_run);

#ifdef __cplusplus
}
#endif

#endif /* COMLEARN_BALANCE_POSES_H */
