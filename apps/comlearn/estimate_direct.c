/*
 * estimate_direct.c - the in-process trial backend (simulator side; see estimate_direct.h).
 */
#include "estimate_direct.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "comlearn/model.h"
#include "comlearn/model_inertial.h"

struct estimate_direct {
  balance_world_t *world;
  balance_object_t *obj;
  int noisy;             /* estimate_direct_set_noise with a non-zero value */
  balance_noise_t noise; /* its seed and std. devs. */
  uint64_t trial_count;  /* trials since open / set_noise: seeds the per-trial draws */
};

/* lib/balance's outcome as the estimator's (the same four values). */
static estimate_outcome_t outcome_of(balance_outcome_t o) {
  switch (o) {
    case BALANCE_STAYS: return ESTIMATE_STAYS;
    case BALANCE_TIPS: return ESTIMATE_TIPS;
    case BALANCE_SLIDES: return ESTIMATE_SLIDES;
    case BALANCE_INVALID: break;
  }
  return ESTIMATE_INVALID;
}

static int direct_run(void *ctx, const estimate_trial_request_t *req, estimate_trial_reply_t *reply,
                      char *err, size_t err_size) {
  estimate_direct_t *d = ctx;
  balance_trial_result_t r;
  balance_noise_t noise = d->noise;
  noise.seed = balance_noise_seed(d->noise.seed, d->trial_count + 1); /* as comlearn-sim */
  ++d->trial_count;
  balance_status_t s =
      balance_trial_run(d->world, d->obj, &req->release, d->noisy ? &noise : NULL, &r);
  if (s != BALANCE_OK) {
    snprintf(err, err_size, "balance_trial_run: %s", balance_status_str(s));
    return -1;
  }
  reply->outcome = outcome_of(r.outcome);
  /* Held, the object's pose is known exactly; where the fingers actually let go (r.released,
   * with the placement offset) is not observable, as in comlearn-sim. */
  reply->released = d->noisy ? req->release : r.released;
  reply->settled = r.settled;
  return 0;
}

int estimate_direct_open(const char *urdf_path, const char *link_name, const balance_config_t *cfg,
                         estimate_direct_t **out, estimate_backend_t *backend, char *err,
                         size_t err_size) {
  *out = NULL;
  memset(backend, 0, sizeof *backend);
  balance_config_t bc;
  if (cfg)
    bc = *cfg;
  else
    balance_config_default(&bc);
  model_error_t merr = {{0}};
  model_object_t obj = {0};
  model_mass_t truth;
  model_status_t ms = model_object_load(urdf_path, link_name, &obj, &merr);
  if (ms == MODEL_OK) ms = model_inertial_load(urdf_path, link_name, &truth, &merr);
  if (ms == MODEL_OK && (ms = model_mass_plausible(&truth, &obj.mesh, &merr)) != MODEL_OK) {
    /* bad input like any other: a truth no real object of this shape can have */
    char why[sizeof merr.msg];
    memcpy(why, merr.msg, sizeof why);
    snprintf(merr.msg, sizeof merr.msg, "URDF %.180s: link '%.60s': <inertial>: %.230s", urdf_path,
             obj.link_name, why);
  }
  if (ms != MODEL_OK) {
    snprintf(err, err_size, "%s (%s)", merr.msg[0] ? merr.msg : urdf_path, model_status_str(ms));
    model_object_free(&obj);
    return ms == MODEL_E_NOMEM ? 1 : 2;
  }
  estimate_direct_t *d = calloc(1, sizeof *d);
  if (!d) {
    model_object_free(&obj);
    snprintf(err, err_size, "out of memory");
    return 1;
  }
  balance_status_t bs = balance_world_create(&bc, &d->world);
  if (bs == BALANCE_OK) bs = balance_object_create(d->world, &obj.mesh, &truth, &d->obj);
  model_object_free(&obj);
  if (bs != BALANCE_OK) {
    snprintf(err, err_size, "%s: simulated object: %s", urdf_path, balance_status_str(bs));
    estimate_direct_close(d);
    return bs == BALANCE_E_NOMEM ? 1 : 2;
  }
  backend->ctx = d;
  backend->name = "direct";
  memcpy(backend->base_size_m, bc.base_size_m, sizeof bc.base_size_m);
  backend->run = direct_run;
  *out = d;
  return 0;
}

int estimate_direct_set_noise(estimate_direct_t *d, uint64_t seed, double placement_noise_m,
                              double pose_noise_m) {
  if (!d || !isfinite(placement_noise_m) || !isfinite(pose_noise_m) ||
      !(placement_noise_m >= 0.0 && placement_noise_m <= 0.1) ||
      !(pose_noise_m >= 0.0 && pose_noise_m <= 0.1))
    return -1;
  d->noise.seed = seed;
  d->noise.placement_noise_m = placement_noise_m;
  d->noise.pose_noise_m = pose_noise_m;
  d->noisy = placement_noise_m > 0.0 || pose_noise_m > 0.0;
  d->trial_count = 0;
  return 0;
}

uint64_t estimate_direct_trial_count(const estimate_direct_t *d) { return d ? d->trial_count : 0; }

void estimate_direct_close(estimate_direct_t *direct) {
  if (!direct) return;
  balance_world_destroy(direct->world);
  free(direct);
}
