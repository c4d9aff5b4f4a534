/*
 * comlearn/qlearn_paper.h - McGovern, Mao & Xiao (IROS 2019), Algorithm 1, in the 1-D terms of
 * comlearn/qlearn.h (policies QLEARN_POLICY_PAPER_QTABLE and QLEARN_POLICY_PAPER_MLP).
 *
 * State: the CoM estimate x relative to the reference point (cfg->prior_m, 0 = the bounding-box
 * center in the paper), on the grid x = prior + k * resolution (k an integer), limited to
 * [range_lo, range_hi]; a range bound off that grid (a prior off the bounds' grid) is one more
 * state, next to the last grid point, so every c inside the range can be bracketed. Each trial
 * places the object with x over the edge. Actions (the paper's +1 / -1):
 *   QLEARN_PAPER_OUT  paper's +1: the object moves out over the edge, away from B's center;
 *                     the point over the edge moves to smaller x (x -= step). Rewarded on STAYS
 *                     (STAYS means c < x: x must decrease to reach c).
 *   QLEARN_PAPER_IN   paper's -1: the object moves back toward B's center (x += step).
 *                     Rewarded on TIPS (c > x).
 * Reward: the rewarded action's Q at the placed state is set to QLEARN_PAPER_R (0.9), the other
 * action's to 1 - R. The learner (Q-table, or the MLP refit on every instance after every trial)
 * then gives the next action as argmax Q. Step 100, 10, then 1 times cfg->resolution_m (1 cm,
 * 1 mm, 0.1 mm for the paper's 1e-4 m): when the outcome flips, the walk steps back to the last
 * state before the flip (a move of the estimate, not a new placement: its outcome is known) and
 * continues from there, by argmax Q at that state, with the next finer step. Done when the finest
 * step brackets the flip (a bracket ending at an off-grid bound is narrower than the resolution);
 * the estimate is the middle of that bracket. docs/learner.md lists every
 * choice made where the paper's text is ambiguous, with hand-traced examples.
 *
 * Assumes noiseless outcomes. Memory: no heap, no I/O, no globals; qlearn_paper_t is
 * caller-owned and may be copied with memcpy. Thread safety: functions touch only their
 * arguments. On any error the state is unchanged.
 */
#ifndef COMLEARN_QLEARN_PAPER_H
#define COMLEARN_QLEARN_PAPER_H

#include <stdint.h>

#include "comlearn/qlearn_mlp.h"
#include "comlearn/qlearn_qtable.h"
#include "comlearn/qlearn_types.h"

#ifdef __cplusplus
extern "C" {
#endif

enum { QLEARN_PAPER_OUT = 0, QLEARN_PAPER_IN = 1 }; /* action index = Q column */

#define QLEARN_PAPER_R 0.9
#define QLEARN_PAPER_LEVELS 3 /* step sizes: 100, 10, 1 x resolution */
/* The MLP's input is the state in units of the coarsest step: s = (x - prior) / (100 res). */
#define QLEARN_PAPER_MLP_EPOCHS 100u /* Adam epochs of each refit (warm start) */
#define QLEARN_PAPER_MLP_ADAM \
  { 0.01, 0.9, 0.999, 1e-8 }

typedef struct {
  union {
    qlearn_qtable_t table; /* QLEARN_POLICY_PAPER_QTABLE */
    qlearn_mlp_t mlp;      /* QLEARN_POLICY_PAPER_MLP */
  } learner;
  int64_t k_next;       /* grid index of the next placement */
  int64_t k_prev;       /* grid index of the last placement (flip detection, step back) */
  double x_prev_m;      /* that placement as observed */
  double lo_m, hi_m;    /* the bracket: last flip pair, or what the outcomes so far exclude */
  uint32_t trials;      /* placements observed */
  uint8_t level;        /* 0, 1, 2: step 100, 10, 1 x resolution */
  uint8_t prev_outcome; /* 0 before the first trial, else a qlearn_outcome_t */
  uint8_t done;         /* the finest step bracketed the flip, or the walk left the range */
  uint8_t outside;      /* the walk had to leave [range_lo, range_hi]: c is outside the range */
} qlearn_paper_t;

/* Start: the first placement is at prior_m. cfg->kind must be QLEARN_POLICY_PAPER_QTABLE or
 * QLEARN_POLICY_PAPER_MLP (QLEARN_E_ARG otherwise); the MLP is seeded from cfg->seed.
 * QLEARN_E_RANGE if the range holds more than 2^52 grid points. */
qlearn_status_t qlearn_paper_init(qlearn_paper_t *paper, const qlearn_policy_config_t *cfg);

/* x of the next placement (a grid point inside the range, or a range bound). QLEARN_E_DONE when
 * finished. */
qlearn_status_t qlearn_paper_next(const qlearn_paper_t *paper, const qlearn_policy_config_t *cfg,
                                  double *x_m);

/* Record a placement at x_m (normally what _next gave; an achieved placement off the grid is
 * mapped to the nearest state, grid point or bound, while the bracket keeps x_m itself), reward,
 * refit, and choose the next placement. QLEARN_E_NONFINITE / _RANGE for a bad x_m, QLEARN_E_ARG
 * for a bad outcome, QLEARN_E_DONE after the end, QLEARN_E_CAPACITY at cfg->max_trials (or a
 * learner buffer full), QLEARN_E_NOCONVERGE if the MLP refit diverged. On error, unchanged. */
qlearn_status_t qlearn_paper_observe(qlearn_paper_t *paper, const qlearn_policy_config_t *cfg,
                                     double x_m, qlearn_outcome_t outcome);

/* 1 when finished, else 0 (also 0 for NULL). */
int qlearn_paper_done(const qlearn_paper_t *paper, const qlearn_policy_config_t *cfg);

/* The middle of the bracket and its half width: the final flip pair when done, else the last flip
 * pair, else the interval the outcomes so far leave (within the range). QLEARN_E_RANGE when the
 * walk had to leave the range (c outside it). */
qlearn_status_t qlearn_paper_estimate(const qlearn_paper_t *paper,
                                      const qlearn_policy_config_t *cfg, double *c_m,
                                      double *halfwidth_m);

/* Q(x, .) of the current learner at the state nearest x_m (for tests and diagnostics):
 * q[QLEARN_PAPER_OUT], q[QLEARN_PAPER_IN]. */
qlearn_status_t qlearn_paper_q(const qlearn_paper_t *paper, const qlearn_policy_config_t *cfg,
                               double x_m, double *q);

#ifdef __cplusplus
}
#endif

#endif /* COMLEARN_QLEARN_PAPER_H */
