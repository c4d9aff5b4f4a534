/*
 * estimate_backend.h - the comlearn program's trial runners ("backends") and the loop that drives
 * lib/estimate (comlearn/estimate.h) through one of them.
 *
 * A backend places the object as asked and reports what happened: estimate_direct.c runs the
 * trials in-process on lib/balance with the URDF truth; estimate_lcm.c sends YuMi commands to
 * comlearn-sim (or a real cell) and waits for its status and object state. The backend owns the
 * simulated truth; the estimator never asks it for anything else.
 */
#ifndef COMLEARN_APP_ESTIMATE_BACKEND_H
#define COMLEARN_APP_ESTIMATE_BACKEND_H

#include <stddef.h>

#include "comlearn/estimate.h"

/* A place to run trials. `run` places the object per req and fills *reply; it returns 0 on
 * success and a negative value on failure, with a message in err (err_size bytes, NUL-terminated).
 * base_size_m is the size of B (world x, y, z), needed for planning. ctx belongs to the backend.
 * progress (may be NULL) is called after every trial with the trial's index (1-based) and a line
 * saying what it was. */
typedef struct {
  void *ctx;
  const char *name; /* "direct", "lcm", ... */
  double base_size_m[3];
  int (*run)(void *ctx, const estimate_trial_request_t *req, estimate_trial_reply_t *reply,
             char *err, size_t err_size);
  void (*progress)(void *ctx, size_t trial_index, const char *what);
  void *progress_ctx;
} estimate_backend_t;

/* Estimate the CoM of the object whose link-frame geometry is mesh_link, running every trial
 * through backend: estimate_create, then estimate_next / backend->run / estimate_observe until
 * done. Fills *out (also on error, as far as it got). Returns ESTIMATE_OK when the estimate ran
 * (found[] may still hold 0s, each with its reason[]), ESTIMATE_E_BACKEND when a trial failed
 * (the backend's message in out->msg), or the estimator's error. */
estimate_status_t estimate_run(const model_mesh_t *mesh_link, const estimate_backend_t *backend,
                               const estimate_config_t *cfg, estimate_result_t *out);

/* "stays", "tips", "slides", "invalid" (the JSON's and the pictures' words), "?" otherwise. */
const char *trial_outcome_name(estimate_outcome_t o);

#endif
