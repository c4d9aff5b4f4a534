/* bisect: the prior, a gallop away from it, then plain bisection (comlearn/qlearn_search.h). */
#include <math.h>
#include <stddef.h>

#include "comlearn/qlearn_search.h"

/* The checks of the settings this policy reads (policy.c checks all of them first; this covers
 * direct calls). */
static qlearn_status_t cfg_check(const qlearn_policy_config_t *c) {
  if (!isfinite(c->range_lo_m) || !isfinite(c->range_hi_m) || !isfinite(c->prior_m) ||
      !isfinite(c->resolution_m)) {
    return QLEARN_E_NONFINITE;
  }
  if (!(c->range_lo_m < c->range_hi_m) || !(c->resolution_m > 0.0) ||
      c->resolution_m > c->range_hi_m - c->range_lo_m || c->prior_m < c->range_lo_m ||
      c->prior_m > c->range_hi_m || c->max_trials == 0 || c->max_trials > QLEARN_MAX_TRIALS) {
    return QLEARN_E_RANGE;
  }
  return QLEARN_OK;
}

/* The trial after an outcome: while galloping, the prior +- (2 last_off + s0) toward c (offsets
 * s0, 3 s0, 7 s0, ...: each bracket a gallop leaves is s0 times a power of two), or the midpoint
 * once that leaves the bracket (or lands on its end) and for every trial after the gallop. */
static void plan_next(qlearn_bisect_t *b, double prior_m, qlearn_outcome_t last,
                      double last_off_m) {
  if (b->phase == QLEARN_BISECT_PROBE) {
    double off = 2.0 * last_off_m + b->probe_m;
    double probe = last == QLEARN_TIPS ? prior_m + off : prior_m - off;
    if (probe > b->lo_m && probe < b->hi_m) {
      b->next_m = probe;
      return;
    }
    b->phase = QLEARN_BISECT_HALVE;
  }
  b->next_m = 0.5 * (b->lo_m + b->hi_m);
}

qlearn_status_t qlearn_bisect_init(qlearn_bisect_t *bisect, const qlearn_policy_config_t *cfg) {
  if (bisect == NULL || cfg == NULL) return QLEARN_E_ARG;
  qlearn_status_t st = cfg_check(cfg);
  if (st != QLEARN_OK) return st;
  qlearn_bisect_t b;
  b.lo_m = cfg->range_lo_m;
  b.hi_m = cfg->range_hi_m;
  b.trials = 0;
  /* s0 = resolution * 2^k, the largest with s0 <= range / 64 (k < 64: a bounded loop). */
  double ratio = (cfg->range_hi_m - cfg->range_lo_m) / (64.0 * cfg->resolution_m);
  double step = cfg->resolution_m;
  for (int k = 0; k < 64 && 2.0 * step <= ratio * cfg->resolution_m; ++k) step *= 2.0;
  b.probe_m = step;
  if (cfg->prior_m > b.lo_m && cfg->prior_m < b.hi_m) {
    b.phase = QLEARN_BISECT_PRIOR;
    b.next_m = cfg->prior_m;
  } else { /* a prior on a bound tells nothing: probe inward from it */
    b.phase = QLEARN_BISECT_PROBE;
    plan_next(&b, cfg->prior_m, cfg->prior_m <= b.lo_m ? QLEARN_TIPS : QLEARN_STAYS, 0.0);
  }
  *bisect = b;
  return QLEARN_OK;
}

int qlearn_bisect_done(const qlearn_bisect_t *bisect, const qlearn_policy_config_t *cfg) {
  if (bisect == NULL || cfg == NULL) return 0;
  /* The relative slack absorbs rounding of the bracket ends (p + s0 - p != s0 exactly). */
  return bisect->hi_m - bisect->lo_m <= cfg->resolution_m * (1.0 + 1e-9);
}

qlearn_status_t qlearn_bisect_next(const qlearn_bisect_t *bisect, const qlearn_policy_config_t *cfg,
                                   double *x_m) {
  if (bisect == NULL || cfg == NULL || x_m == NULL) return QLEARN_E_ARG;
  if (qlearn_bisect_done(bisect, cfg)) return QLEARN_E_DONE;
  *x_m = bisect->next_m;
  return QLEARN_OK;
}

qlearn_status_t qlearn_bisect_observe(qlearn_bisect_t *bisect, const qlearn_policy_config_t *cfg,
                                      double x_m, qlearn_outcome_t outcome) {
  if (bisect == NULL || cfg == NULL) return QLEARN_E_ARG;
  if (outcome != QLEARN_STAYS && outcome != QLEARN_TIPS) return QLEARN_E_ARG;
  if (!isfinite(x_m)) return QLEARN_E_NONFINITE;
  if (x_m < cfg->range_lo_m || x_m > cfg->range_hi_m) return QLEARN_E_RANGE;
  if (qlearn_bisect_done(bisect, cfg)) return QLEARN_E_DONE;
  if (bisect->trials >= cfg->max_trials) return QLEARN_E_CAPACITY;
  /* STAYS: c <= x; TIPS: c >= x (x == c may give either). */
  if ((outcome == QLEARN_STAYS && x_m < bisect->lo_m) ||
      (outcome == QLEARN_TIPS && x_m > bisect->hi_m)) {
    return QLEARN_E_RANGE; /* contradicts earlier outcomes: noisy data (use PBA) */
  }
  qlearn_bisect_t b = *bisect;
  if (outcome == QLEARN_STAYS) {
    if (x_m < b.hi_m) b.hi_m = x_m;
  } else if (x_m > b.lo_m) {
    b.lo_m = x_m;
  }
  b.trials++;
  if (b.phase == QLEARN_BISECT_PRIOR) {
    b.phase = QLEARN_BISECT_PROBE;
    plan_next(&b, cfg->prior_m, outcome, 0.0);
  } else if (b.phase == QLEARN_BISECT_PROBE &&
             (outcome == QLEARN_TIPS ? x_m > cfg->prior_m : x_m < cfg->prior_m)) {
    plan_next(&b, cfg->prior_m, outcome, fabs(x_m - cfg->prior_m)); /* c lies farther out */
  } else {
    b.phase = QLEARN_BISECT_HALVE;
    plan_next(&b, cfg->prior_m, outcome, 0.0);
  }
  *bisect = b;
  return QLEARN_OK;
}

qlearn_status_t qlearn_bisect_estimate(const qlearn_bisect_t *bisect,
                                       const qlearn_policy_config_t *cfg, double *c_m,
                                       double *halfwidth_m) {
  if (bisect == NULL || cfg == NULL || c_m == NULL || halfwidth_m == NULL) return QLEARN_E_ARG;
  *c_m = 0.5 * (bisect->lo_m + bisect->hi_m);
  *halfwidth_m = 0.5 * (bisect->hi_m - bisect->lo_m);
  return QLEARN_OK;
}
