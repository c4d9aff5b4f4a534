/* The one policy interface: argument checks common to every policy, then dispatch by kind.
 * Each policy implements <name>_init / _next / _observe / _done / _estimate over its own state
 * and the search settings (comlearn/qlearn_search.h, comlearn/qlearn_paper.h). */
#include <math.h>
#include <string.h>

#include "comlearn/qlearn.h"

const char *qlearn_status_str(qlearn_status_t status) {
  switch (status) {
    case QLEARN_OK: return "ok";
    case QLEARN_E_ARG: return "invalid argument";
    case QLEARN_E_NONFINITE: return "non-finite number";
    case QLEARN_E_RANGE: return "value out of range";
    case QLEARN_E_CAPACITY: return "capacity exhausted";
    case QLEARN_E_DONE: return "search already finished";
    case QLEARN_E_NOCONVERGE: return "iteration cap reached without convergence";
    case QLEARN_E_SINGULAR: return "underdetermined: not enough independent constraints";
  }
  return "unknown status";
}

void qlearn_policy_config_default(qlearn_policy_kind_t kind, qlearn_policy_config_t *cfg) {
  if (cfg == NULL) return;
  memset(cfg, 0, sizeof *cfg);
  cfg->kind = kind;
  cfg->range_lo_m = -0.05;
  cfg->range_hi_m = 0.05;
  cfg->prior_m = 0.0;
  cfg->resolution_m = 1e-4;
  cfg->noise = QLEARN_NOISE_PROBIT;
  cfg->flip_prob = 0.0;
  cfg->sigma_m = 1e-4;
  cfg->credible = 0.95;
  cfg->max_trials = QLEARN_MAX_TRIALS;
  cfg->seed = 1;
}

static qlearn_status_t config_check(const qlearn_policy_config_t *c) {
  if (c->kind != QLEARN_POLICY_BISECT && c->kind != QLEARN_POLICY_PBA &&
      c->kind != QLEARN_POLICY_PAPER_QTABLE && c->kind != QLEARN_POLICY_PAPER_MLP) {
    return QLEARN_E_ARG;
  }
  if (!isfinite(c->range_lo_m) || !isfinite(c->range_hi_m) || !isfinite(c->prior_m) ||
      !isfinite(c->resolution_m) || !isfinite(c->flip_prob) || !isfinite(c->sigma_m) ||
      !isfinite(c->credible)) {
    return QLEARN_E_NONFINITE;
  }
  if (!(c->range_lo_m < c->range_hi_m) || !(c->resolution_m > 0.0) ||
      c->resolution_m > c->range_hi_m - c->range_lo_m || c->prior_m < c->range_lo_m ||
      c->prior_m > c->range_hi_m) {
    return QLEARN_E_RANGE;
  }
  if (c->max_trials == 0 || c->max_trials > QLEARN_MAX_TRIALS) return QLEARN_E_RANGE;
  if (c->noise != QLEARN_NOISE_FLIP && c->noise != QLEARN_NOISE_PROBIT) return QLEARN_E_ARG;
  if (c->flip_prob < 0.0 || c->flip_prob >= 0.5 || c->sigma_m < 0.0 || !(c->credible > 0.0) ||
      !(c->credible < 1.0)) {
    return QLEARN_E_RANGE;
  }
  return QLEARN_OK;
}

qlearn_status_t qlearn_policy_init(qlearn_policy_t *policy, const qlearn_policy_config_t *cfg) {
  if (policy == NULL || cfg == NULL) return QLEARN_E_ARG;
  qlearn_status_t st = config_check(cfg);
  if (st != QLEARN_OK) return st;
  qlearn_policy_t fresh;
  memset(&fresh, 0, sizeof fresh);
  fresh.cfg = *cfg;
  switch (cfg->kind) {
    case QLEARN_POLICY_BISECT: st = qlearn_bisect_init(&fresh.u.bisect, &fresh.cfg); break;
    case QLEARN_POLICY_PBA: st = qlearn_pba_init(&fresh.u.pba, &fresh.cfg); break;
    default: st = qlearn_paper_init(&fresh.u.paper, &fresh.cfg); break;
  }
  if (st == QLEARN_OK) *policy = fresh; /* the state changes only on success */
  return st;
}

qlearn_status_t qlearn_policy_next(const qlearn_policy_t *policy, double *x_m) {
  if (policy == NULL || x_m == NULL) return QLEARN_E_ARG;
  if (qlearn_policy_done(policy)) return QLEARN_E_DONE;
  switch (policy->cfg.kind) {
    case QLEARN_POLICY_BISECT: return qlearn_bisect_next(&policy->u.bisect, &policy->cfg, x_m);
    case QLEARN_POLICY_PBA: return qlearn_pba_next(&policy->u.pba, &policy->cfg, x_m);
    default: return qlearn_paper_next(&policy->u.paper, &policy->cfg, x_m);
  }
}

qlearn_status_t qlearn_policy_observe(qlearn_policy_t *policy, double x_m,
                                      qlearn_outcome_t outcome) {
  if (policy == NULL) return QLEARN_E_ARG;
  if (outcome != QLEARN_STAYS && outcome != QLEARN_TIPS) return QLEARN_E_ARG;
  if (!isfinite(x_m)) return QLEARN_E_NONFINITE;
  if (x_m < policy->cfg.range_lo_m || x_m > policy->cfg.range_hi_m) return QLEARN_E_RANGE;
  if (qlearn_policy_done(policy)) return QLEARN_E_DONE;
  if (policy->trials >= policy->cfg.max_trials) return QLEARN_E_CAPACITY;
  qlearn_status_t st;
  switch (policy->cfg.kind) {
    case QLEARN_POLICY_BISECT:
      st = qlearn_bisect_observe(&policy->u.bisect, &policy->cfg, x_m, outcome);
      break;
    case QLEARN_POLICY_PBA:
      st = qlearn_pba_observe(&policy->u.pba, &policy->cfg, x_m, outcome);
      break;
    default: st = qlearn_paper_observe(&policy->u.paper, &policy->cfg, x_m, outcome); break;
  }
  if (st == QLEARN_OK) policy->trials++;
  return st;
}

int qlearn_policy_done(const qlearn_policy_t *policy) {
  if (policy == NULL) return 0;
  switch (policy->cfg.kind) {
    case QLEARN_POLICY_BISECT: return qlearn_bisect_done(&policy->u.bisect, &policy->cfg);
    case QLEARN_POLICY_PBA: return qlearn_pba_done(&policy->u.pba, &policy->cfg);
    default: return qlearn_paper_done(&policy->u.paper, &policy->cfg);
  }
}

qlearn_status_t qlearn_policy_estimate(const qlearn_policy_t *policy, double *c_m,
                                       double *halfwidth_m) {
  if (policy == NULL || c_m == NULL || halfwidth_m == NULL) return QLEARN_E_ARG;
  switch (policy->cfg.kind) {
    case QLEARN_POLICY_BISECT:
      return qlearn_bisect_estimate(&policy->u.bisect, &policy->cfg, c_m, halfwidth_m);
    case QLEARN_POLICY_PBA:
      return qlearn_pba_estimate(&policy->u.pba, &policy->cfg, c_m, halfwidth_m);
    default: return qlearn_paper_estimate(&policy->u.paper, &policy->cfg, c_m, halfwidth_m);
  }
}
