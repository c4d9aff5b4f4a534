/*
 * comlearn/qlearn_search.h - the two search policies that need few placements: bisect
 * (noiseless outcomes) and PBA (probabilistic bisection, noisy outcomes).
 *
 * Callers normally use them through qlearn_policy_* (comlearn/qlearn.h), which checks the
 * settings and the common arguments first; the functions here check their own arguments too, so
 * they may be called directly. Conventions (1-D coordinate x, STAYS means c < x, TIPS means
 * c > x) are those of comlearn/qlearn.h. Every function touches only its arguments: no heap, no
 * I/O, no globals; every loop is bounded by a compile-time constant. On error the state is
 * unchanged. The cfg passed to every call must be the one passed to _init.
 */
#ifndef COMLEARN_QLEARN_SEARCH_H
#define COMLEARN_QLEARN_SEARCH_H

#include <stdint.h>

#include "comlearn/qlearn_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- bisect ----------------------------------------------------------------------------------
 * Trial 1 at the prior p (skipped when p lies on a range bound); then a gallop toward the CoM:
 * p + s0, p + 3 s0, p + 7 s0, ... after TIPS (p - s0, ... after STAYS), (2^m - 1) s0 away at step
 * m, for as long as the outcome repeats and the step stays inside the bracket; then plain bisection
 * of the bracket [lo, hi] that the outcomes leave, until hi - lo <= resolution (with a relative
 * slack of 1e-9 for rounding of the bracket ends).
 * s0 = resolution * 2^floor(log2(range / (64 resolution))) (at least the resolution). A CoM d from
 * the prior, (2^(m-1) - 1) s0 < d <= (2^m - 1) s0, costs 2m + log2(s0 / resolution) trials: a good
 * prior is cheap (5 within 0.8 mm at 0.1 mm over 10 cm), a poor one costs about two trials per
 * doubling of d.
 * Bound (proved in docs/learner.md, checked by tests/qlearn_search_tests.c): with the prior in the
 * range and noiseless outcomes, at most 1 + floor(log2(range / s0 + 1)) + ceil(log2(range /
 * resolution)) trials (17 for 10 cm at 0.1 mm, at most 8 over the information limit), since a
 * gallop step beyond the range is not taken and the bracket it leaves is narrower than the range.
 * The final bracket contains c (noiseless).
 * An outcome that contradicts the bracket (STAYS at x < lo, TIPS at x > hi: noisy data) is
 * rejected with QLEARN_E_RANGE; outcomes exactly at a bracket end collapse it (knife edge). */
typedef enum {
  QLEARN_BISECT_PRIOR = 0, /* next trial: the prior */
  QLEARN_BISECT_PROBE = 1, /* next trial: the prior +- a gallop step */
  QLEARN_BISECT_HALVE = 2  /* next trial: the bracket's midpoint */
} qlearn_bisect_phase_t;

typedef struct {
  double lo_m; /* c is known to lie in [lo_m, hi_m] */
  double hi_m;
  double probe_m; /* the gallop's first step s0 (> 0) */
  double next_m;  /* the next trial (valid while not done) */
  qlearn_bisect_phase_t phase;
  uint32_t trials; /* outcomes accepted */
} qlearn_bisect_t;

/* Start: bracket = the range. QLEARN_E_ARG for NULL, QLEARN_E_NONFINITE / QLEARN_E_RANGE for a
 * bad cfg (range, resolution, prior outside the range). */
qlearn_status_t qlearn_bisect_init(qlearn_bisect_t *bisect, const qlearn_policy_config_t *cfg);
/* Next coordinate x (metres). QLEARN_E_DONE when hi - lo <= resolution; state never changes. */
qlearn_status_t qlearn_bisect_next(const qlearn_bisect_t *bisect, const qlearn_policy_config_t *cfg,
                                   double *x_m);
/* Outcome at x. QLEARN_E_NONFINITE / QLEARN_E_RANGE (x outside the range, or contradicting the
 * bracket), QLEARN_E_ARG (bad outcome), QLEARN_E_DONE, QLEARN_E_CAPACITY (max_trials reached). */
qlearn_status_t qlearn_bisect_observe(qlearn_bisect_t *bisect, const qlearn_policy_config_t *cfg,
                                      double x_m, qlearn_outcome_t outcome);
/* 1 when the bracket is at most the resolution wide, else 0 (also 0 for NULL). */
int qlearn_bisect_done(const qlearn_bisect_t *bisect, const qlearn_policy_config_t *cfg);
/* Midpoint of the bracket and half its width: c lies in [*c_m - *hw, *c_m + *hw] (noiseless). */
qlearn_status_t qlearn_bisect_estimate(const qlearn_bisect_t *bisect,
                                       const qlearn_policy_config_t *cfg, double *c_m,
                                       double *halfwidth_m);

/* ---- PBA: probabilistic bisection --------------------------------------------------------------
 * Horstein's scheme as analysed by Waeber, Frazier & Henderson (2013): the posterior density of c
 * over the range is kept on QLEARN_PBA_BINS equal bins (piecewise constant, float masses: fixed
 * memory); the next trial is the posterior median; each outcome multiplies every bin by the
 * likelihood of that outcome averaged over the bin (exact for a piecewise-constant density):
 *   QLEARN_NOISE_FLIP    P(correct outcome) = 1 - flip_prob; the bin holding x is split at x
 *   QLEARN_NOISE_PROBIT  P(TIPS | c) = Phi((c - x) / sigma_m), averaged over the bin in closed form
 *                        (sigma_m == 0 is the noiseless step)
 * Likelihoods are floored at QLEARN_PBA_LIK_FLOOR (a tiny lapse rate) so a contradictory outcome
 * cannot zero the posterior. Done when the equal-tailed credible interval of mass cfg->credible is
 * at most the resolution wide, or after max_trials outcomes. Estimate: the posterior median, and
 * the half width max(median - q_lo, q_hi - median) + w / 2, which covers the (possibly
 * asymmetric) equal-tailed interval [q_lo, q_hi] plus half a bin w. Quantiles interpolate
 * linearly inside a bin.
 * Discretisation: the grid starts as the range cut in QLEARN_PBA_BINS bins of width w (48.8 um
 * for a 10 cm range). Inside a bin the density is uniform, so the mass a trial at x leaves on one
 * side of x is spread over the whole bin and quantiles can be off by up to a bin (hence the w / 2
 * added to the half width); the interval cannot shrink much below two bins. So while w is more
 * than half the resolution, once all but QLEARN_PBA_ZOOM_TAIL of the mass lies within a quarter
 * of the window QLEARN_PBA_BINS x resolution / 4, the posterior is laid again on that window
 * (centred on the mass, shifted to stay inside the grid): each new bin takes the old density's
 * exact mass over it, and the mass outside (at most twice the tail) is dropped. A search over a
 * range wider than QLEARN_PBA_BINS x resolution / 2 (10.24 cm at 0.1 mm) then ends as one over a
 * narrow range would, instead of running to max_trials with the mass split over two bins. */
#define QLEARN_PBA_BINS 2048
#define QLEARN_PBA_LIK_FLOOR 1e-6
#define QLEARN_PBA_ZOOM_TAIL 1e-9

typedef struct {
  float mass[QLEARN_PBA_BINS]; /* posterior mass per bin, sums to 1 */
  double median_m;             /* cached after every update: the median, */
  double ci_lo_m;              /*   and the equal-tailed credible interval */
  double ci_hi_m;
  double lo_m;     /* the grid: [lo_m, hi_m] in QLEARN_PBA_BINS bins, */
  double hi_m;     /*   the range until the zoom narrows it */
  uint32_t trials; /* outcomes accepted */
} qlearn_pba_t;

/* Start with the uniform posterior over the range. Errors as qlearn_bisect_init, plus
 * QLEARN_E_ARG / QLEARN_E_RANGE for a bad noise model or credible mass. */
qlearn_status_t qlearn_pba_init(qlearn_pba_t *pba, const qlearn_policy_config_t *cfg);
/* The posterior median. QLEARN_E_DONE when done. */
qlearn_status_t qlearn_pba_next(const qlearn_pba_t *pba, const qlearn_policy_config_t *cfg,
                                double *x_m);
/* Bayes update with the outcome at x. Errors as qlearn_bisect_observe (no contradiction error). */
qlearn_status_t qlearn_pba_observe(qlearn_pba_t *pba, const qlearn_policy_config_t *cfg, double x_m,
                                   qlearn_outcome_t outcome);
/* 1 when the credible interval is at most the resolution wide or max_trials were observed. */
int qlearn_pba_done(const qlearn_pba_t *pba, const qlearn_policy_config_t *cfg);
/* Posterior median and the half width that covers the credible interval. */
qlearn_status_t qlearn_pba_estimate(const qlearn_pba_t *pba, const qlearn_policy_config_t *cfg,
                                    double *c_m, double *halfwidth_m);

_Static_assert(QLEARN_PBA_BINS >= 16 && QLEARN_PBA_BINS <= 4096, "PBA bin count out of range");
_Static_assert(sizeof(qlearn_pba_t) <= 12 * 1024, "PBA state must leave room in 16 KiB");

#ifdef __cplusplus
}
#endif

#endif /* COMLEARN_QLEARN_SEARCH_H */
