/* estimate_backend.c - the loop of estimate_backend.h. */
#include "estimate_backend.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* What the last trial was, for progress lines. */
static void trial_line(const estimate_trial_t *t, char *what, size_t size) {
  if (t->kind == ESTIMATE_TRIAL_STABLE)
    snprintf(what, size, "stable check, face %d: %s", t->face,
             t->outcome == ESTIMATE_STAYS ? "stays" : "does not stay");
  else
    snprintf(what, size, "search %d, x = %+.4f mm: %s%s", t->search, 1e3 * t->x_m,
             t->outcome == ESTIMATE_STAYS ? "stays" : "tips", t->flagged ? " (flagged)" : "");
}

estimate_status_t estimate_run(const model_mesh_t *mesh_link, const estimate_backend_t *backend,
                               const estimate_config_t *cfg, estimate_result_t *out) {
  if (!mesh_link || !backend || !backend->run || !cfg || !out) return ESTIMATE_E_ARG;
  memset(out, 0, sizeof *out);
  for (int k = 0; k < 3; ++k) out->halfwidth_m[k] = INFINITY;
  estimate_t *est = NULL;
  estimate_status_t s = estimate_create(mesh_link, backend->base_size_m, cfg, &est);
  if (s != ESTIMATE_OK) {
    snprintf(out->msg, sizeof out->msg, "%s",
             s == ESTIMATE_E_ARG ? "bad estimator setting, or the backend reports a bad size of B"
                                 : estimate_status_str(s));
    return s;
  }
  estimate_trial_request_t req;
  char err[256] = "";
  while ((s = estimate_next(est, &req)) == ESTIMATE_OK) {
    estimate_trial_reply_t reply;
    memset(&reply, 0, sizeof reply);
    if (backend->run(backend->ctx, &req, &reply, err, sizeof err) != 0) {
      s = ESTIMATE_E_BACKEND;
      break;
    }
    s = estimate_observe(est, &reply);
    const estimate_result_t *r = estimate_result(est);
    if (backend->progress && r->trial_count > 0) {
      char what[160];
      trial_line(&r->trial[r->trial_count - 1], what, sizeof what);
      backend->progress(backend->progress_ctx, r->trial_count, what);
    }
    if (s != ESTIMATE_OK) break;
  }
  memcpy(out, estimate_result(est), sizeof *out);
  estimate_destroy(est);
  if (s == ESTIMATE_E_BACKEND)
    snprintf(out->msg, sizeof out->msg, "%s backend: %s", backend->name,
             err[0] ? err : "trial failed");
  return s == ESTIMATE_DONE ? ESTIMATE_OK : s;
}

const char *trial_outcome_name(estimate_outcome_t o) {
  switch (o) {
    case ESTIMATE_STAYS: return "stays";
    case ESTIMATE_TIPS: return "tips";
    case ESTIMATE_SLIDES: return "slides";
    case ESTIMATE_INVALID: return "invalid";
  }
  return "?";
}
