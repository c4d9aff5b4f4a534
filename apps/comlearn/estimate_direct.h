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
 * Memory: estimate_direct_open allocates the world (ODE) and the object; estimate_direct_close
 * frees them. One thread at a time per backend.
 */
#ifndef COMLEARN_APP_ESTIMATE_DIRECT_H
#define COMLEARN_APP_ESTIMATE_DIRECT_H

#include <stddef.h>

#include "comlearn/balance.h"
#include "estimate.h"

typedef struct estimate_direct estimate_direct_t;

/* Load urdf_path (link NULL = root) with its inertial and build the world per cfg (NULL: the
 * balance defaults). Fills *backend (its ctx is the returned handle). Returns 0 on success,
 * 2 for bad input (missing or unreadable file, no/invalid inertial, unusable mesh) and 1 for a
 * runtime failure (out of memory), matching the program's exit codes; err gets a message. */
int estimate_direct_open(const char *urdf_path, const char *link_name, const balance_config_t *cfg,
                         estimate_direct_t **out, estimate_backend_t *backend, char *err,
                         size_t err_size);

/* Free the world and the object. NULL is fine. */
void estimate_direct_close(estimate_direct_t *direct);

#endif
