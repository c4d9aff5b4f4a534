/*
 * comlearn/qlearn_mlp.h - a small fixed-size neural network Q(s, .) for the paper's policy.
 *
 * Network: 1 input (the state s, dimensionless: the caller scales it) -> QLEARN_MLP_HIDDEN tanh
 * units -> QLEARN_MLP_OUT linear outputs (one Q value per action). Trained by full-batch Adam on
 * the mean squared error over every (s, Q) instance stored so far.
 *
 * Memory: no heap, no I/O, no globals. Everything (parameters, Adam moments, the random
 * generator, the instance buffer) lives in qlearn_mlp_t, which the caller owns; it holds no
 * pointers and may be copied with memcpy. Parameters are one contiguous array (kann style):
 *   p[0 .. H-1]            W1 (input -> hidden weights)
 *   p[H .. 2H-1]           b1 (hidden biases)
 *   p[2H .. 2H + O*H - 1]  W2, row-major [output][hidden]
 *   p[2H + O*H .. end]     b2 (output biases)
 * The pure functions (qlearn_mlp_forward, qlearn_mlp_grad_add, qlearn_mlp_adam_step) work on
 * caller arrays of QLEARN_MLP_NPARAM doubles. Thread safety: functions touch only their
 * arguments. Every loop is bounded by the compile-time sizes, the instance count and epochs.
 */
#ifndef COMLEARN_QLEARN_MLP_H
#define COMLEARN_QLEARN_MLP_H

#include <stddef.h>
#include <stdint.h>

#include "comlearn/qlearn_types.h"

#ifdef __cplusplus
extern "C" {
#endif

#define QLEARN_MLP_HIDDEN 16
#define QLEARN_MLP_OUT 2
#define QLEARN_MLP_NPARAM \
  (2 * QLEARN_MLP_HIDDEN + QLEARN_MLP_OUT * QLEARN_MLP_HIDDEN + QLEARN_MLP_OUT)
/* Instance buffer capacity: one instance per trial. */
#define QLEARN_MLP_MAX_INSTANCES QLEARN_MAX_TRIALS
/* Hard cap on epochs of one qlearn_mlp_fit call. */
#define QLEARN_MLP_MAX_EPOCHS 100000u

/* Adam settings (Kingma & Ba 2015). */
typedef struct {
  double lr;    /* step size, > 0 */
  double beta1; /* in [0, 1) */
  double beta2; /* in [0, 1) */
  double eps;   /* > 0 */
} qlearn_mlp_adam_t;

/* lr 0.01, beta1 0.9, beta2 0.999, eps 1e-8. */
#define QLEARN_MLP_ADAM_DEFAULT \
  { 0.01, 0.9, 0.999, 1e-8 }

typedef struct {
  double p[QLEARN_MLP_NPARAM]; /* parameters, layout above */
  double m[QLEARN_MLP_NPARAM]; /* Adam first moment */
  double v[QLEARN_MLP_NPARAM]; /* Adam second moment */
  double beta1_pow;            /* beta1^t and beta2^t for Adam's bias correction */
  double beta2_pow;
  uint64_t rng;                       /* splitmix64 state, for the initial weights */
  uint32_t steps;                     /* Adam steps taken so far */
  uint32_t n;                         /* instances stored */
  double s[QLEARN_MLP_MAX_INSTANCES]; /* instance inputs */
  double q[QLEARN_MLP_MAX_INSTANCES][QLEARN_MLP_OUT]; /* instance targets */
} qlearn_mlp_t;

/* Reset the network: Adam moments and instances cleared, weights drawn from the seed (W1 and b1
 * uniform in [-1, 1], W2 uniform in [-1/sqrt(H), 1/sqrt(H)], b2 = 0). The same seed gives
 * bit-identical weights. QLEARN_E_ARG for NULL. */
qlearn_status_t qlearn_mlp_init(qlearn_mlp_t *mlp, uint64_t seed);

/* Q(s, .) into q[QLEARN_MLP_OUT] from parameters p[QLEARN_MLP_NPARAM]. Pure. h, if not NULL,
 * receives the hidden activations (QLEARN_MLP_HIDDEN doubles). */
void qlearn_mlp_forward(const double *p, double s, double *q, double *h);

/* Add the gradient of 0.5 * scale * |Q(s, .) - target|^2 with respect to p into g
 * (QLEARN_MLP_NPARAM doubles). Pure. */
void qlearn_mlp_grad_add(const double *p, double s, const double *target, double scale, double *g);

/* One Adam step over n parameters: p -= lr * mhat / (sqrt(vhat) + eps), with m, v updated from
 * g and the bias corrections 1 - beta1_pow, 1 - beta2_pow (beta^t including this step). Pure. */
void qlearn_mlp_adam_step(double *p, const double *g, double *m, double *v, size_t n,
                          const qlearn_mlp_adam_t *adam, double beta1_pow, double beta2_pow);

/* Append one instance (s, q[QLEARN_MLP_OUT]). QLEARN_E_NONFINITE for a non-finite value,
 * QLEARN_E_CAPACITY when QLEARN_MLP_MAX_INSTANCES are stored; on error mlp is unchanged. */
qlearn_status_t qlearn_mlp_add(qlearn_mlp_t *mlp, double s, const double *q);

/* Refit on all stored instances: `epochs` full-batch Adam steps on the mean squared error,
 * continuing from the current weights and moments (warm start). QLEARN_E_ARG for NULL, epochs 0
 * or above QLEARN_MLP_MAX_EPOCHS, or bad Adam settings; QLEARN_E_RANGE with no instance;
 * QLEARN_E_NOCONVERGE if a weight became non-finite. On error mlp is unchanged. No allocation;
 * uses about 2.5 KiB of stack. */
qlearn_status_t qlearn_mlp_fit(qlearn_mlp_t *mlp, uint32_t epochs, const qlearn_mlp_adam_t *adam);

/* Mean squared error 0.5 * mean |Q - target|^2 over the stored instances (0 with none). */
double qlearn_mlp_loss(const qlearn_mlp_t *mlp);

#ifdef __cplusplus
}
#endif

#endif /* COMLEARN_QLEARN_MLP_H */
