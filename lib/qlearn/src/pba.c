/* PBA: probabilistic bisection over a binned posterior (comlearn/qlearn_search.h). */
#include <math.h>
#include <stddef.h>

#include "comlearn/qlearn_search.h"

/* Beyond |u| > this many sigma, Phi is 0 or 1 to double precision for our purposes; skipping erfc
 * there keeps an update at a few hundred bins' worth of libm calls. */
#define PBA_TAIL_U 10.0

static qlearn_status_t cfg_check(const qlearn_policy_config_t *c) {
  if (!isfinite(c->range_lo_m) || !isfinite(c->range_hi_m) || !isfinite(c->prior_m) ||
      !isfinite(c->resolution_m) || !isfinite(c->flip_prob) || !isfinite(c->sigma_m) ||
      !isfinite(c->credible)) {
    return QLEARN_E_NONFINITE;
  }
  if (c->noise != QLEARN_NOISE_FLIP && c->noise != QLEARN_NOISE_PROBIT) return QLEARN_E_ARG;
  if (!(c->range_lo_m < c->range_hi_m) || !(c->resolution_m > 0.0) ||
      c->resolution_m > c->range_hi_m - c->range_lo_m || c->max_trials == 0 ||
      c->max_trials > QLEARN_MAX_TRIALS || c->flip_prob < 0.0 || c->flip_prob >= 0.5 ||
      c->sigma_m < 0.0 || !(c->credible > 0.0) || !(c->credible < 1.0)) {
    return QLEARN_E_RANGE;
  }
  return QLEARN_OK;
}

/* Antiderivative of Phi: G(u) = u Phi(u) + phi(u). */
static double phi_integral(double u) {
  if (u > PBA_TAIL_U) return u;
  if (u < -PBA_TAIL_U) return 0.0;
  const double inv_sqrt2 = 0.70710678118654752440;
  const double inv_sqrt2pi = 0.39894228040143267794;
  return u * 0.5 * erfc(-u * inv_sqrt2) + inv_sqrt2pi * exp(-0.5 * u * u);
}

static double std_cdf(double u) { return 0.5 * erfc(-u * 0.70710678118654752440); }

/* Mean over the bin [a, b] of P(outcome | c), for c uniform in the bin. */
static double bin_likelihood(const qlearn_policy_config_t *cfg, double a, double b, double x,
                             qlearn_outcome_t outcome) {
  double l;
  if (cfg->noise == QLEARN_NOISE_PROBIT && cfg->sigma_m > 0.0) {
    /* P(TIPS | c) = Phi((c - x) / s), P(STAYS | c) = Phi((x - c) / s): in both, Phi(u) over
     * u in [ua, ub]; mean = (G(ub) - G(ua)) / (ub - ua). */
    double s = cfg->sigma_m;
    double ua = outcome == QLEARN_TIPS ? (a - x) / s : (x - b) / s;
    double ub = outcome == QLEARN_TIPS ? (b - x) / s : (x - a) / s;
    if (ub - ua < 1e-3 || (ua > PBA_TAIL_U) || (ub < -PBA_TAIL_U)) {
      l = ua > PBA_TAIL_U ? 1.0 : ub < -PBA_TAIL_U ? 0.0 : std_cdf(0.5 * (ua + ub));
    } else {
      l = (phi_integral(ub) - phi_integral(ua)) / (ub - ua);
    }
  } else {
    double p = cfg->noise == QLEARN_NOISE_FLIP ? cfg->flip_prob : 0.0;
    double right = (b - x) / (b - a); /* the part of the bin with c > x */
    if (right < 0.0) right = 0.0;
    if (right > 1.0) right = 1.0;
    double tips = p + (1.0 - 2.0 * p) * right;
    l = outcome == QLEARN_TIPS ? tips : 1.0 - tips;
  }
  return l < QLEARN_PBA_LIK_FLOOR ? QLEARN_PBA_LIK_FLOOR : l;
}

/* Median and equal-tailed interval, interpolating linearly inside a bin. */
static void summarize(qlearn_pba_t *p, const qlearn_policy_config_t *cfg) {
  double lo = cfg->range_lo_m;
  double w = (cfg->range_hi_m - cfg->range_lo_m) / (double)QLEARN_PBA_BINS;
  double total = 0.0;
  for (int i = 0; i < QLEARN_PBA_BINS; ++i) total += (double)p->mass[i];
  double tail = 0.5 * (1.0 - cfg->credible);
  double q[3] = {tail * total, 0.5 * total, (1.0 - tail) * total};
  double out[3] = {cfg->range_hi_m, cfg->range_hi_m, cfg->range_hi_m};
  int k = 0;
  double cum = 0.0;
  for (int i = 0; i < QLEARN_PBA_BINS && k < 3; ++i) {
    double m = (double)p->mass[i];
    while (k < 3 && m > 0.0 && cum + m >= q[k]) {
      double f = (q[k] - cum) / m;
      out[k] = lo + w * ((double)i + (f < 0.0 ? 0.0 : f > 1.0 ? 1.0 : f));
      ++k;
    }
    cum += m;
  }
  p->ci_lo_m = out[0];
  p->median_m = out[1];
  p->ci_hi_m = out[2];
}

qlearn_status_t qlearn_pba_init(qlearn_pba_t *pba, const qlearn_policy_config_t *cfg) {
  if (pba == NULL || cfg == NULL) return QLEARN_E_ARG;
  qlearn_status_t st = cfg_check(cfg);
  if (st != QLEARN_OK) return st;
  const float uniform = 1.0f / (float)QLEARN_PBA_BINS;
  for (int i = 0; i < QLEARN_PBA_BINS; ++i) pba->mass[i] = uniform;
  pba->trials = 0;
  summarize(pba, cfg);
  return QLEARN_OK;
}

int qlearn_pba_done(const qlearn_pba_t *pba, const qlearn_policy_config_t *cfg) {
  if (pba == NULL || cfg == NULL) return 0;
  return pba->ci_hi_m - pba->ci_lo_m <= cfg->resolution_m || pba->trials >= cfg->max_trials;
}

qlearn_status_t qlearn_pba_next(const qlearn_pba_t *pba, const qlearn_policy_config_t *cfg,
                                double *x_m) {
  if (pba == NULL || cfg == NULL || x_m == NULL) return QLEARN_E_ARG;
  if (qlearn_pba_done(pba, cfg)) return QLEARN_E_DONE;
  *x_m = pba->median_m;
  return QLEARN_OK;
}

qlearn_status_t qlearn_pba_observe(qlearn_pba_t *pba, const qlearn_policy_config_t *cfg, double x_m,
                                   qlearn_outcome_t outcome) {
  if (pba == NULL || cfg == NULL) return QLEARN_E_ARG;
  if (outcome != QLEARN_STAYS && outcome != QLEARN_TIPS) return QLEARN_E_ARG;
  if (!isfinite(x_m)) return QLEARN_E_NONFINITE;
  if (x_m < cfg->range_lo_m || x_m > cfg->range_hi_m) return QLEARN_E_RANGE;
  if (qlearn_pba_done(pba, cfg)) return QLEARN_E_DONE;
  if (pba->trials >= cfg->max_trials) return QLEARN_E_CAPACITY;
  /* No error past this point: the update may work in place. */
  double lo = cfg->range_lo_m;
  double w = (cfg->range_hi_m - cfg->range_lo_m) / (double)QLEARN_PBA_BINS;
  double total = 0.0;
  for (int i = 0; i < QLEARN_PBA_BINS; ++i) {
    double a = lo + w * (double)i;
    double m = (double)pba->mass[i] * bin_likelihood(cfg, a, a + w, x_m, outcome);
    pba->mass[i] = (float)m;
    total += m;
  }
  /* total >= QLEARN_PBA_LIK_FLOOR * (previous total, 1): never zero. */
  double scale = 1.0 / total;
  for (int i = 0; i < QLEARN_PBA_BINS; ++i) {
    pba->mass[i] = (float)((double)pba->mass[i] * scale);
  }
  pba->trials++;
  summarize(pba, cfg);
  return QLEARN_OK;
}

qlearn_status_t qlearn_pba_estimate(const qlearn_pba_t *pba, const qlearn_policy_config_t *cfg,
                                    double *c_m, double *halfwidth_m) {
  if (pba == NULL || cfg == NULL || c_m == NULL || halfwidth_m == NULL) return QLEARN_E_ARG;
  double below = pba->median_m - pba->ci_lo_m;
  double above = pba->ci_hi_m - pba->median_m;
  /* Half a bin more: inside a bin the density is taken as uniform, so a quantile may sit up to
   * about half a bin from where the exact (unbinned) posterior would put it. */
  double half_bin = 0.5 * (cfg->range_hi_m - cfg->range_lo_m) / (double)QLEARN_PBA_BINS;
  *c_m = pba->median_m;
  *halfwidth_m = (below > above ? below : above) + half_bin;
  return QLEARN_OK;
}
