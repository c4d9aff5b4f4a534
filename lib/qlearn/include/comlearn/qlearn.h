/*
 * comlearn/qlearn.h - the learner: where the object goes next, and what is known of its CoM.
 *
 * Embedded-style C11: no heap, no I/O, no globals, no ODE, no LCM. All state, random generators
 * included, lives in structs the caller owns; every loop is bounded; capacities are compile-time
 * constants checked with _Static_assert. Thread safety: functions touch only their arguments.
 *
 * One CoM component at a time (a "search"): the caller picks an axis of the object and a
 * direction, and works in a 1-D coordinate x along it, relative to a reference point (the
 * bounding-box center in the paper). A trial places the object with the point at coordinate x
 * exactly over the edge, the object's +x side overhanging. The outcome tells on which side of x
 * the CoM coordinate c lies:
 *   QLEARN_STAYS   c < x (the CoM is over B)          QLEARN_TIPS   c > x (it overhangs)
 * (c == x is the knife edge; either outcome may come.) Every policy below works in these terms;
 * the caller maps an axis and edge direction onto them (negate x for the -x side).
 *
 * Policies (behind one interface, qlearn_policy_*):
 *   QLEARN_POLICY_PAPER_QTABLE, QLEARN_POLICY_PAPER_MLP  McGovern, Mao & Xiao (IROS 2019),
 *       Algorithm 1 (docs/learner.md says where its text is ambiguous and what we chose)
 *   QLEARN_POLICY_BISECT  bracket the flip from a prior, then bisect to the resolution
 *   QLEARN_POLICY_PBA     probabilistic bisection over a discretized posterior, noisy outcomes
 *
 * The 3-D solve (comlearn/qlearn_solve.h) combines thresholds from several directions and poses.
 */
#ifndef COMLEARN_QLEARN_H
#define COMLEARN_QLEARN_H

#include <stddef.h>
#include <stdint.h>

#include "comlearn/qlearn_types.h"
/* The per-policy state structs. */
#include "comlearn/qlearn_paper.h"
#include "comlearn/qlearn_search.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The state of one search: caller-owned, fixed size, no pointers to outside memory (it may be
 * copied with memcpy). sizeof(qlearn_policy_t) is reported by the tests and benchmarks. */
typedef struct {
  qlearn_policy_config_t cfg;
  uint32_t trials; /* trials observed so far */
  union {
    qlearn_bisect_t bisect;
    qlearn_pba_t pba;
    qlearn_paper_t paper; /* paper-qtable and paper-mlp */
  } u;
} qlearn_policy_t;

/* Start a search. Checks cfg (QLEARN_E_ARG / _NONFINITE / _RANGE). */
qlearn_status_t qlearn_policy_init(qlearn_policy_t *policy, const qlearn_policy_config_t *cfg);

/* The coordinate x of the next trial. QLEARN_E_DONE when the search is finished. Does not change
 * the state (it may be called again). */
qlearn_status_t qlearn_policy_next(const qlearn_policy_t *policy, double *x_m);

/* Record the outcome of a trial at x (normally the x that qlearn_policy_next gave; the placement
 * actually achieved may be passed instead). QLEARN_E_DONE after the end, QLEARN_E_CAPACITY at
 * max_trials, QLEARN_E_NONFINITE / _RANGE for a bad x, QLEARN_E_ARG for a bad outcome. */
qlearn_status_t qlearn_policy_observe(qlearn_policy_t *policy, double x_m,
                                      qlearn_outcome_t outcome);

/* 1 when the search is finished (bracketed to the resolution, credible interval narrow enough, or
 * the paper's 0.1 mm step bracketed the flip), else 0. */
int qlearn_policy_done(const qlearn_policy_t *policy);

/* The current estimate of c and the half width of its interval: for bisect and the paper policies
 * the bracket known to contain c (noiseless); for PBA the credible interval of mass cfg.credible
 * (centered estimate: the posterior median). */
qlearn_status_t qlearn_policy_estimate(const qlearn_policy_t *policy, double *c_m,
                                       double *halfwidth_m);

#ifdef __cplusplus
}
#endif

#endif /* COMLEARN_QLEARN_H */
