/* McGovern, Mao & Xiao (IROS 2019), Algorithm 1 (comlearn/qlearn_paper.h, docs/learner.md). */
#include <math.h>
#include <string.h>

#include "comlearn/qlearn_paper.h"

/* Step of each level in grid units (resolution): 1 cm, 1 mm, 0.1 mm for the paper's 0.1 mm. */
static const int64_t level_step[QLEARN_PAPER_LEVELS] = {100, 10, 1};

_Static_assert(QLEARN_PAPER_LEVELS == 3, "the paper steps 1 cm, 1 mm, 0.1 mm");
_Static_assert(QLEARN_QTABLE_MAX_STATES >= QLEARN_MAX_TRIALS, "a state per trial");
_Static_assert(QLEARN_MLP_MAX_INSTANCES >= QLEARN_MAX_TRIALS, "an instance per trial");
_Static_assert(QLEARN_MLP_OUT == 2 && QLEARN_QTABLE_ACTIONS == 2, "two actions");

static int is_paper(const qlearn_policy_config_t *cfg) {
  return cfg->kind == QLEARN_POLICY_PAPER_QTABLE || cfg->kind == QLEARN_POLICY_PAPER_MLP;
}

/* State limits: the grid points inside [range_lo, range_hi] plus, when a bound is off the grid
 * (a prior off the bounds' grid), one state beyond the last grid point that grid_x clamps to the
 * bound itself. Without it, a c between the last grid point and the bound (inside the range)
 * could never be bracketed and would be reported as outside. A little slack for rounding. */
static int64_t grid_lo(const qlearn_policy_config_t *cfg) {
  return (int64_t)floor((cfg->range_lo_m - cfg->prior_m) / cfg->resolution_m + 1e-9);
}
static int64_t grid_hi(const qlearn_policy_config_t *cfg) {
  return (int64_t)ceil((cfg->range_hi_m - cfg->prior_m) / cfg->resolution_m - 1e-9);
}

static double grid_x(const qlearn_policy_config_t *cfg, int64_t k) {
  const double x = cfg->prior_m + (double)k * cfg->resolution_m;
  return fmin(fmax(x, cfg->range_lo_m), cfg->range_hi_m);
}

/* The state nearest x_m (x_m inside the range): the grid point, or a bound's state, whose
 * grid_x is closest. A placement at a bound maps to that bound's state even when the bound is
 * less than half a step past the last grid point. */
static int64_t grid_k(const qlearn_policy_config_t *cfg, double x_m) {
  const int64_t klo = grid_lo(cfg), khi = grid_hi(cfg);
  int64_t k = (int64_t)llround((x_m - cfg->prior_m) / cfg->resolution_m);
  if (k < klo) k = klo;
  if (k > khi) k = khi;
  if (k < khi && fabs(grid_x(cfg, k + 1) - x_m) < fabs(grid_x(cfg, k) - x_m)) k++;
  if (k > klo && fabs(grid_x(cfg, k - 1) - x_m) < fabs(grid_x(cfg, k) - x_m)) k--;
  return k;
}

/* The MLP's input: the state in units of the coarsest step. */
static double mlp_input(int64_t k) { return (double)k / (double)level_step[0]; }

static void learner_q(const qlearn_paper_t *paper, const qlearn_policy_config_t *cfg, int64_t k,
                      double *q) {
  if (cfg->kind == QLEARN_POLICY_PAPER_MLP) {
    qlearn_mlp_forward(paper->learner.mlp.p, mlp_input(k), q, NULL);
  } else {
    (void)qlearn_qtable_get(&paper->learner.table, k, q);
  }
}

qlearn_status_t qlearn_paper_init(qlearn_paper_t *paper, const qlearn_policy_config_t *cfg) {
  if (paper == NULL || cfg == NULL || !is_paper(cfg)) return QLEARN_E_ARG;
  if (!isfinite(cfg->range_lo_m) || !isfinite(cfg->range_hi_m) || !isfinite(cfg->prior_m) ||
      !isfinite(cfg->resolution_m)) {
    return QLEARN_E_NONFINITE;
  }
  if (!(cfg->resolution_m > 0.0) || !(cfg->range_lo_m < cfg->range_hi_m) ||
      cfg->prior_m < cfg->range_lo_m || cfg->prior_m > cfg->range_hi_m ||
      (cfg->range_hi_m - cfg->range_lo_m) / cfg->resolution_m > 4503599627370496.0) {
    return QLEARN_E_RANGE;
  }
  memset(paper, 0, sizeof *paper);
  if (cfg->kind == QLEARN_POLICY_PAPER_MLP) {
    (void)qlearn_mlp_init(&paper->learner.mlp, cfg->seed);
  } else {
    (void)qlearn_qtable_init(&paper->learner.table);
  }
  paper->k_next = 0; /* the prior itself */
  paper->lo_m = cfg->range_lo_m;
  paper->hi_m = cfg->range_hi_m;
  return QLEARN_OK;
}

qlearn_status_t qlearn_paper_next(const qlearn_paper_t *paper, const qlearn_policy_config_t *cfg,
                                  double *x_m) {
  if (paper == NULL || cfg == NULL || x_m == NULL || !is_paper(cfg)) return QLEARN_E_ARG;
  if (paper->done) return QLEARN_E_DONE;
  *x_m = grid_x(cfg, paper->k_next);
  return QLEARN_OK;
}

qlearn_status_t qlearn_paper_observe(qlearn_paper_t *paper, const qlearn_policy_config_t *cfg,
                                     double x_m, qlearn_outcome_t outcome) {
  if (paper == NULL || cfg == NULL || !is_paper(cfg)) return QLEARN_E_ARG;
  if (outcome != QLEARN_STAYS && outcome != QLEARN_TIPS) return QLEARN_E_ARG;
  if (!isfinite(x_m)) return QLEARN_E_NONFINITE;
  if (x_m < cfg->range_lo_m || x_m > cfg->range_hi_m) return QLEARN_E_RANGE;
  if (paper->done) return QLEARN_E_DONE;
  if (paper->trials >= cfg->max_trials || paper->trials >= QLEARN_MAX_TRIALS) {
    return QLEARN_E_CAPACITY;
  }
  const int64_t k_obs = grid_k(cfg, x_m);

  /* Reward: STAYS (c < x) -> OUT (x decreases), TIPS (c > x) -> IN. */
  double q[2];
  const int rewarded = (outcome == QLEARN_STAYS) ? QLEARN_PAPER_OUT : QLEARN_PAPER_IN;
  q[rewarded] = QLEARN_PAPER_R;
  q[1 - rewarded] = 1.0 - QLEARN_PAPER_R;

  /* Learner update; on failure nothing has changed (the MLP's add is undone). */
  qlearn_status_t st;
  if (cfg->kind == QLEARN_POLICY_PAPER_MLP) {
    qlearn_mlp_t *mlp = &paper->learner.mlp;
    st = qlearn_mlp_add(mlp, mlp_input(k_obs), q);
    if (st != QLEARN_OK) return st;
    const qlearn_mlp_adam_t adam = QLEARN_PAPER_MLP_ADAM;
    st = qlearn_mlp_fit(mlp, QLEARN_PAPER_MLP_EPOCHS, &adam);
    if (st != QLEARN_OK) {
      mlp->n--;
      return st;
    }
  } else {
    st = qlearn_qtable_set(&paper->learner.table, k_obs, q);
    if (st != QLEARN_OK) return st;
  }
  paper->trials++;

  int64_t k_from; /* the state the next action is taken from */
  const int flip = paper->prev_outcome != 0 && (int)outcome != (int)paper->prev_outcome;
  if (flip) {
    paper->lo_m = fmin(paper->x_prev_m, x_m);
    paper->hi_m = fmax(paper->x_prev_m, x_m);
    if (paper->level + 1 >= QLEARN_PAPER_LEVELS) {
      paper->done = 1; /* the finest step brackets the flip */
      return QLEARN_OK;
    }
    /* Step back to the last state before the flip (its outcome is known: no placement there),
     * and go on from it with the next finer step. prev stays that state, for the next flip. */
    paper->level++;
    k_from = paper->k_prev;
  } else {
    if (outcome == QLEARN_TIPS) {
      paper->lo_m = fmax(paper->lo_m, x_m);
    } else {
      paper->hi_m = fmin(paper->hi_m, x_m);
    }
    paper->k_prev = k_obs;
    paper->x_prev_m = x_m;
    paper->prev_outcome = (uint8_t)outcome;
    k_from = k_obs;
  }

  /* argmax Q at that state; a tie (never for a visited state) goes OUT. */
  double qa[2];
  learner_q(paper, cfg, k_from, qa);
  const int64_t step = level_step[paper->level];
  int64_t k_new = (qa[QLEARN_PAPER_IN] > qa[QLEARN_PAPER_OUT]) ? k_from + step : k_from - step;
  const int64_t klo = grid_lo(cfg), khi = grid_hi(cfg);
  if (k_new < klo) k_new = klo;
  if (k_new > khi) k_new = khi;
  if (k_new == k_from) {
    /* The walk would leave the range: c lies outside it. */
    paper->done = 1;
    paper->outside = 1;
  }
  paper->k_next = k_new;
  return QLEARN_OK;
}

int qlearn_paper_done(const qlearn_paper_t *paper, const qlearn_policy_config_t *cfg) {
  if (paper == NULL || cfg == NULL) return 0;
  return paper->done ? 1 : 0;
}

qlearn_status_t qlearn_paper_estimate(const qlearn_paper_t *paper,
                                      const qlearn_policy_config_t *cfg, double *c_m,
                                      double *halfwidth_m) {
  if (paper == NULL || cfg == NULL || c_m == NULL || halfwidth_m == NULL || !is_paper(cfg)) {
    return QLEARN_E_ARG;
  }
  if (paper->outside) return QLEARN_E_RANGE;
  const double lo = fmin(paper->lo_m, paper->hi_m), hi = fmax(paper->lo_m, paper->hi_m);
  *c_m = 0.5 * (lo + hi);
  *halfwidth_m = 0.5 * (hi - lo);
  return QLEARN_OK;
}

qlearn_status_t qlearn_paper_q(const qlearn_paper_t *paper, const qlearn_policy_config_t *cfg,
                               double x_m, double *q) {
  if (paper == NULL || cfg == NULL || q == NULL || !is_paper(cfg)) return QLEARN_E_ARG;
  if (!isfinite(x_m)) return QLEARN_E_NONFINITE;
  const double kd = (x_m - cfg->prior_m) / cfg->resolution_m;
  if (!(fabs(kd) < 4503599627370496.0)) return QLEARN_E_RANGE;
  const int inside = x_m >= cfg->range_lo_m && x_m <= cfg->range_hi_m;
  learner_q(paper, cfg, inside ? grid_k(cfg, x_m) : (int64_t)llround(kd), q);
  return QLEARN_OK;
}
