/*
 * estimate_direct.h - the in-process trial backend of `comlearn estimate --direct`: the
 * "simulator side" of the estimator / simulator boundary (estimate.h).
 *
 * This is the only code of the comlearn program that reads the URDF <inertial> for physics: it
 * loads the object's geometry and its inertial truth, builds a lib/balance world with base block
 * B and the object carrying the true mass properties, and runs each requested placement with
 * balance_trial_run. The truth never leaves this file: the estimator gets outcomes and poses only,
 * exactly what comlearn-sim would send over LCM.
 *
 * Noise (estimate_direct_set_noise): off by default. When set, each trial is perturbed exactly as
 * comlearn-sim perturbs it (daemon/sim.c, docs/sim.md): balance_trial_run with a balance_noise_t
 * seeded balance_noise_seed(seed, n + 1), n the number of trials this backend ran since the
 * noise was set. As in comlearn-sim, the pose reported as released is the requested one (while an
 * object is held its reported pose is exact: the placement offset is not observable), and the
 * settled pose carries the pose noise. So a noisy direct run makes the same draws as a freshly
 * started `comlearn-sim --seed S --placement-noise-mm P --pose-noise-mm Q` given the same requests.
 *
 * Memory: estimate_direct_open allocates the world (ODE) and the object; estimate_direct_close
 * frees them. One thread at a time per backend.
 */
#ifndef COMLEARN_APP_ESTIMATE_DIRECT_H
#define COMLEARN_APP_ESTIMATE_DIRECT_H

#include <stddef.h>
#include <stdint.h>

#include "comlearn/balance.h"
#include "estimate_backend.h"

typedef struct estimate_direct estimate_direct_t;

/* Load urdf_path (link NULL = root) with its inertial and build the world per cfg (NULL: the
 * balance defaults). Fills *backend (its ctx is the returned handle). Returns 0 on success,
 * 2 for bad input (missing or unreadable file, no/invalid inertial, one that fails
 * model_mass_plausible against the mesh, unusable mesh) and 1 for a runtime failure (out of
 * memory), matching the program's exit codes; err gets a message naming the URDF. */
int estimate_direct_open(const char *urdf_path, const char *link_name, const balance_config_t *cfg,
                         estimate_direct_t **out, estimate_backend_t *backend, char *err,
                         size_t err_size);

/* Perturb the following trials: placement_noise_m is the std. dev. of a horizontal (world x, y)
 * offset of each release, pose_noise_m that of the perceived settled position (x, y, z); both
 * finite and in [0, 0.1] m. Both zero turns the noise off (trials then run exactly as without
 * this call: balance_trial_run with noise NULL, released pose as lib/balance reports it). Resets
 * the trial count that seeds the draws to 0. Returns 0, or -1 (d NULL, a value non-finite or out
 * of range; nothing changed). Does not allocate. */
int estimate_direct_set_noise(estimate_direct_t *d, uint64_t seed, double placement_noise_m,
                              double pose_noise_m);

/* Trials run by this backend since it was opened or the noise was last set. */
uint64_t estimate_direct_trial_count(const estimate_direct_t *d);

/* Free the world and the object. NULL is fine. */
void estimate_direct_close(estimate_direct_t *direct);

#endif
