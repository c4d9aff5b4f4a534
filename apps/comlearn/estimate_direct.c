/*
 * estimate_direct.c - the in-process trial backend (simulator side; see estimate_direct.h).
 */
#include "estimate_direct.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "comlearn/model.h"
#include "comlearn/model_inertial.h"

struct estimate_direct {
  balance_world_t *world;
  balance_object_t *obj;
};

static int direct_run(void *ctx, const estimate_trial_request_t *req, estimate_trial_reply_t *reply,
                      char *err, size_t err_size) {
  estimate_direct_t *d = ctx;
  balance_trial_result_t r;
  balance_status_t s = balance_trial_run(d->world, d->obj, &req->release, NULL, &r);
  if (s != BALANCE_OK) {
    snprintf(err, err_size, "balance_trial_run: %s", balance_status_str(s));
    return -1;
  }
  reply->outcome = r.outcome;
  reply->released = r.released;
  reply->settled = r.settled;
  return 0;
}

int estimate_direct_open(const char *urdf_path, const char *link_name, const balance_config_t *cfg,
                         estimate_direct_t **out, estimate_backend_t *backend, char *err,
                         size_t err_size) {
  *out = NULL;
  memset(backend, 0, sizeof *backend);
  balance_config_t bc;
  if (cfg) bc = *cfg;
  else balance_config_default(&bc);
  model_error_t merr = {{0}};
  model_object_t obj = {0};
  model_mass_t truth;
  model_status_t ms = model_object_load(urdf_path, link_name, &obj, &merr);
  if (ms == MODEL_OK) ms = model_inertial_load(urdf_path, link_name, &truth, &merr);
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

void estimate_direct_close(estimate_direct_t *direct) {
  if (!direct) return;
  balance_world_destroy(direct->world);
  free(direct);
}
