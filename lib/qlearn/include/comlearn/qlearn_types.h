/*
 * comlearn/qlearn_types.h - what every part of lib/qlearn shares: the status enum, outcomes,
 * policy kinds and the settings of one search. See comlearn/qlearn.h for the conventions.
 */
#ifndef COMLEARN_QLEARN_TYPES_H
#define COMLEARN_QLEARN_TYPES_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* One status enum for the module: 0 is success, negative values are errors. On error, the state
 * passed in is unchanged. */
typedef enum {
  QLEARN_OK = 0,
  QLEARN_E_ARG = -1,        /* NULL pointer, unknown kind, bad option */
  QLEARN_E_NONFINITE = -2,  /* a NaN or infinity in the input */
  QLEARN_E_RANGE = -3,      /* resolution <= 0 or larger than the range; x outside the range */
  QLEARN_E_CAPACITY = -4,   /* a fixed-capacity buffer is full */
  QLEARN_E_DONE = -5,       /* the search is finished: no next trial */
  QLEARN_E_NOCONVERGE = -6, /* an iterative routine hit its iteration cap */
  QLEARN_E_SINGULAR = -7    /* the 3-D solve cannot determine what was asked */
} qlearn_status_t;

/* A static English description of a status; never NULL. */
const char *qlearn_status_str(qlearn_status_t status);

/* Outcome of one trial (values equal comlearn_com_trial_t's OUTCOME_STAYS / OUTCOME_TIPS). */
typedef enum { QLEARN_STAYS = 1, QLEARN_TIPS = 2 } qlearn_outcome_t;

typedef enum {
  QLEARN_POLICY_BISECT = 0,
  QLEARN_POLICY_PBA = 1,
  QLEARN_POLICY_PAPER_QTABLE = 2,
  QLEARN_POLICY_PAPER_MLP = 3
} qlearn_policy_kind_t;

/* Noise model of the outcomes, for PBA (the others assume noiseless outcomes). */
typedef enum {
  QLEARN_NOISE_FLIP = 0,  /* each outcome is wrong with probability flip_prob, independently */
  QLEARN_NOISE_PROBIT = 1 /* P(TIPS | x) = Phi((c - x) / sigma_m): placement / pose noise */
} qlearn_noise_kind_t;

/* Settings of one search. All lengths in metres, in the 1-D coordinate described above. */
typedef struct {
  qlearn_policy_kind_t kind;
  double range_lo_m;   /* the CoM coordinate is known to lie in [range_lo_m, range_hi_m] */
  double range_hi_m;   /*   (e.g. the bounding box along the axis) */
  double prior_m;      /* where to start: the mesh's uniform-density CoM, or 0 (box center) */
  double resolution_m; /* stop when the CoM is bracketed to this width (paper: 1e-4) */
  qlearn_noise_kind_t noise;
  double flip_prob;    /* QLEARN_NOISE_FLIP, in [0, 0.5) */
  double sigma_m;      /* QLEARN_NOISE_PROBIT, > 0 */
  double credible;     /* PBA: mass of the reported interval, e.g. 0.95 */
  uint32_t max_trials; /* hard cap on trials of this search (<= QLEARN_MAX_TRIALS) */
  uint64_t seed;       /* for the MLP's initial weights */
} qlearn_policy_config_t;

/* Defaults for a kind: range +-0.05 m, prior 0, resolution 1e-4 m, probit noise sigma 1e-4 m,
 * credible 0.95, max_trials QLEARN_MAX_TRIALS, seed 1. */
void qlearn_policy_config_default(qlearn_policy_kind_t kind, qlearn_policy_config_t *cfg);

/* Hard cap of trials in one search, for every policy. */
#define QLEARN_MAX_TRIALS 256

#ifdef __cplusplus
}
#endif

#endif /* COMLEARN_QLEARN_TYPES_H */
