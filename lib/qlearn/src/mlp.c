/* A 1 -> H -> O tanh network trained by full-batch Adam (comlearn/qlearn_mlp.h). */
#include <math.h>
#include <string.h>

#include "comlearn/math3d.h"
#include "comlearn/qlearn_mlp.h"

#define H QLEARN_MLP_HIDDEN
#define O QLEARN_MLP_OUT
#define OFF_W1 0
#define OFF_B1 (H)
#define OFF_W2 (2 * H)
#define OFF_B2 (2 * H + O * H)

_Static_assert(QLEARN_MLP_NPARAM == OFF_B2 + O, "parameter layout");
_Static_assert(QLEARN_MLP_MAX_INSTANCES >= QLEARN_MAX_TRIALS, "one instance per trial");
_Static_assert(QLEARN_MLP_MAX_INSTANCES <= 65536, "instance count fits the loops' bounds");

/* Uniform in [-a, a] from the top 53 bits of splitmix64 (comlearn/math3d.h). */
static double uniform_sym(uint64_t *state, double a) {
  return a * (2.0 * cl_rng_uniform(state) - 1.0);
}

qlearn_status_t qlearn_mlp_init(qlearn_mlp_t *mlp, uint64_t seed) {
  if (mlp == NULL) return QLEARN_E_ARG;
  memset(mlp, 0, sizeof *mlp);
  mlp->rng = seed;
  const double a2 = 1.0 / sqrt((double)H);
  for (int j = 0; j < H; j++) mlp->p[OFF_W1 + j] = uniform_sym(&mlp->rng, 1.0);
  for (int j = 0; j < H; j++) mlp->p[OFF_B1 + j] = uniform_sym(&mlp->rng, 1.0);
  for (int k = 0; k < O * H; k++) mlp->p[OFF_W2 + k] = uniform_sym(&mlp->rng, a2);
  for (int k = 0; k < O; k++) mlp->p[OFF_B2 + k] = 0.0;
  mlp->beta1_pow = 1.0;
  mlp->beta2_pow = 1.0;
  return QLEARN_OK;
}

void qlearn_mlp_forward(const double *p, double s, double *q, double *h) {
  double hid[H];
  for (int j = 0; j < H; j++) hid[j] = tanh(p[OFF_W1 + j] * s + p[OFF_B1 + j]);
  for (int k = 0; k < O; k++) {
    double acc = p[OFF_B2 + k];
    for (int j = 0; j < H; j++) acc += p[OFF_W2 + k * H + j] * hid[j];
    q[k] = acc;
  }
  if (h != NULL) memcpy(h, hid, sizeof hid);
}

void qlearn_mlp_grad_add(const double *p, double s, const double *target, double scale, double *g) {
  double hid[H], q[O], dq[O];
  qlearn_mlp_forward(p, s, q, hid);
  for (int k = 0; k < O; k++) {
    dq[k] = scale * (q[k] - target[k]);
    g[OFF_B2 + k] += dq[k];
    for (int j = 0; j < H; j++) g[OFF_W2 + k * H + j] += dq[k] * hid[j];
  }
  for (int j = 0; j < H; j++) {
    double dh = 0.0;
    for (int k = 0; k < O; k++) dh += dq[k] * p[OFF_W2 + k * H + j];
    const double dz = dh * (1.0 - hid[j] * hid[j]);
    g[OFF_W1 + j] += dz * s;
    g[OFF_B1 + j] += dz;
  }
}

void qlearn_mlp_adam_step(double *p, const double *g, double *m, double *v, size_t n,
                          const qlearn_mlp_adam_t *adam, double beta1_pow, double beta2_pow) {
  const double c1 = 1.0 - beta1_pow, c2 = 1.0 - beta2_pow;
  for (size_t i = 0; i < n; i++) {
    m[i] = adam->beta1 * m[i] + (1.0 - adam->beta1) * g[i];
    v[i] = adam->beta2 * v[i] + (1.0 - adam->beta2) * g[i] * g[i];
    p[i] -= adam->lr * (m[i] / c1) / (sqrt(v[i] / c2) + adam->eps);
  }
}

qlearn_status_t qlearn_mlp_add(qlearn_mlp_t *mlp, double s, const double *q) {
  if (mlp == NULL || q == NULL) return QLEARN_E_ARG;
  for (int k = 0; k < O; k++) {
    if (!isfinite(q[k])) return QLEARN_E_NONFINITE;
  }
  if (!isfinite(s)) return QLEARN_E_NONFINITE;
  if (mlp->n >= QLEARN_MLP_MAX_INSTANCES) return QLEARN_E_CAPACITY;
  mlp->s[mlp->n] = s;
  for (int k = 0; k < O; k++) mlp->q[mlp->n][k] = q[k];
  mlp->n++;
  return QLEARN_OK;
}

static int adam_ok(const qlearn_mlp_adam_t *a) {
  return isfinite(a->lr) && a->lr > 0.0 && a->beta1 >= 0.0 && a->beta1 < 1.0 && a->beta2 >= 0.0 &&
         a->beta2 < 1.0 && isfinite(a->eps) && a->eps > 0.0;
}

qlearn_status_t qlearn_mlp_fit(qlearn_mlp_t *mlp, uint32_t epochs, const qlearn_mlp_adam_t *adam) {
  if (mlp == NULL || adam == NULL || epochs == 0 || epochs > QLEARN_MLP_MAX_EPOCHS ||
      !adam_ok(adam)) {
    return QLEARN_E_ARG;
  }
  if (mlp->n == 0) return QLEARN_E_RANGE;
  /* Work on copies so that a diverged fit leaves mlp unchanged. */
  double p[QLEARN_MLP_NPARAM], m[QLEARN_MLP_NPARAM], v[QLEARN_MLP_NPARAM], g[QLEARN_MLP_NPARAM];
  memcpy(p, mlp->p, sizeof p);
  memcpy(m, mlp->m, sizeof m);
  memcpy(v, mlp->v, sizeof v);
  double b1p = mlp->beta1_pow, b2p = mlp->beta2_pow;
  const double scale = 1.0 / (double)mlp->n;
  for (uint32_t e = 0; e < epochs; e++) {
    memset(g, 0, sizeof g);
    for (uint32_t i = 0; i < mlp->n; i++) qlearn_mlp_grad_add(p, mlp->s[i], mlp->q[i], scale, g);
    b1p *= adam->beta1;
    b2p *= adam->beta2;
    qlearn_mlp_adam_step(p, g, m, v, QLEARN_MLP_NPARAM, adam, b1p, b2p);
  }
  for (int i = 0; i < QLEARN_MLP_NPARAM; i++) {
    if (!isfinite(p[i]) || !isfinite(m[i]) || !isfinite(v[i])) return QLEARN_E_NOCONVERGE;
  }
  memcpy(mlp->p, p, sizeof p);
  memcpy(mlp->m, m, sizeof m);
  memcpy(mlp->v, v, sizeof v);
  mlp->beta1_pow = b1p;
  mlp->beta2_pow = b2p;
  mlp->steps = (mlp->steps > UINT32_MAX - epochs) ? UINT32_MAX : mlp->steps + epochs;
  return QLEARN_OK;
}

double qlearn_mlp_loss(const qlearn_mlp_t *mlp) {
  if (mlp == NULL || mlp->n == 0) return 0.0;
  double sum = 0.0, q[O];
  for (uint32_t i = 0; i < mlp->n; i++) {
    qlearn_mlp_forward(mlp->p, mlp->s[i], q, NULL);
    for (int k = 0; k < O; k++) sum += 0.5 * (q[k] - mlp->q[i][k]) * (q[k] - mlp->q[i][k]);
  }
  return sum / (double)mlp->n;
}
