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

/* The posterior's quantiles q[0] < q[1] < ... (fractions of the mass, n of them) into out[],
 * interpolating linearly inside a bin; a quantile past the last bin with mass is the grid's top. */
static void quantiles(const qlearn_pba_t *p, const double *q, int n, double *out) {
  const double w = (p->hi_m - p->lo_m) / (double)QLEARN_PBA_BINS;
  double total = 0.0;
  for (int i = 0; i < QLEARN_PBA_BINS; ++i) total += (double)p->mass[i];
  for (int k = 0; k < n; ++k) out[k] = p->hi_m;
  int k = 0;
  double cum = 0.0;
  for (int i = 0; i < QLEARN_PBA_BINS && k < n; ++i) {
    double m = (double)p->mass[i];
    while (k < n && m > 0.0 && cum + m >= q[k] * total) {
      double f = (q[k] * total - cum) / m;
      out[k] = p->lo_m + w * ((double)i + (f < 0.0 ? 0.0 : f > 1.0 ? 1.0 : f));
      ++k;
    }
    cum += m;
  }
}

/* Median and equal-tailed interval. */
static void summarize(qlearn_pba_t *p, const qlearn_policy_config_t *cfg) {
  const double tail = 0.5 * (1.0 - cfg->credible);
  const double q[3] = {tail, 0.5, 1.0 - tail};
  double out[3];
  quantiles(p, q, 3, out);
  p->ci_lo_m = out[0];
  p->median_m = out[1];
  p->ci_hi_m = out[2];
}

/* New bin j's mass on the zoomed grid: the old piecewise-constant density over [a_j, a_j + r)
 * (in old bins from the grid's bottom), reading old bins i_lo .. i_hi only. */
static double zoomed_bin(const qlearn_pba_t *p, double a0, double r, int j, int i_lo, int i_hi) {
  const double a = a0 + r * (double)j, b = a + r;
  double m = 0.0;
  for (int i = (int)floor(a); i <= i_hi && (double)i < b; ++i) {
    if (i < i_lo) continue;
    const double from = a > (double)i ? a : (double)i;
    const double to = b < (double)(i + 1) ? b : (double)(i + 1);
    if (to > from) m += (double)p->mass[i] * (to - from);
  }
  return m;
}

/* The zoom (qlearn_search.h, "Discretisation"): while the bins are wider than half the
 * resolution, once all but QLEARN_PBA_ZOOM_TAIL of the mass lies in a quarter of the window
 * QLEARN_PBA_BINS x resolution / 4 wide, the posterior is laid again on that window (inside the
 * grid), each new bin taking the old density's mass over it; the mass outside, at most twice the
 * tail, is dropped. Returns 1 when it zoomed.
 * In place, with no scratch copy (an 8 KiB stack array would not suit a microcontroller): new
 * bin j covers old bins from a_j = a_0 + r j on, r = new / old width < 1/2. Below the first j
 * with floor(a_j) < j, a new bin reads only old bins at or above its own index and below that
 * j; from that j on, only old bins at or below its own index and not below that j - 1. So the
 * upper part is written first, downwards, then the lower part, upwards: no bin is read after it
 * was written. */
static int zoom(qlearn_pba_t *p, const qlearn_policy_config_t *cfg) {
  const double span = p->hi_m - p->lo_m;
  const double w = span / (double)QLEARN_PBA_BINS;
  if (!(w > 0.5 * cfg->resolution_m)) return 0;
  const double window = 0.25 * cfg->resolution_m * (double)QLEARN_PBA_BINS; /* < span / 2 */
  const double q[2] = {QLEARN_PBA_ZOOM_TAIL, 1.0 - QLEARN_PBA_ZOOM_TAIL};
  double ab[2];
  quantiles(p, q, 2, ab);
  if (!(ab[1] - ab[0] <= 0.25 * window)) return 0;
  double lo = 0.5 * (ab[0] + ab[1]) - 0.5 * window;
  if (lo < p->lo_m) lo = p->lo_m;
  if (lo + window > p->hi_m) lo = p->hi_m - window;
  const double a0 = (lo - p->lo_m) / w, r = window / span;
  int split = 0;
  while (split < QLEARN_PBA_BINS && floor(a0 + r * (double)split) >= (double)split) ++split;
  const int last = QLEARN_PBA_BINS - 1;
  double total = 0.0;
  for (int j = last; j >= split; --j) {
    const double m = zoomed_bin(p, a0, r, j, split - 1 < 0 ? 0 : split - 1, j);
    p->mass[j] = (float)m;
    total += m;
  }
  for (int j = 0; j < split; ++j) {
    const double m = zoomed_bin(p, a0, r, j, j, split - 1);
    p->mass[j] = (float)m;
    total += m;
  }
  /* total > 0: the window holds all but 2 x QLEARN_PBA_ZOOM_TAIL of a mass that sums to 1 */
  for (int j = 0; j < QLEARN_PBA_BINS; ++j) p->mass[j] = (float)((double)p->mass[j] / total);
  p->lo_m = lo;
  p->hi_m = lo + window;
  return 1;
}

qlearn_status_t qlearn_pba_init(qlearn_pba_t *pba, const qlearn_policy_config_t *cfg) {
  if (pba == NULL || cfg == NULL) return QLEARN_E_ARG;
  qlearn_status_t st = cfg_check(cfg);
  if (st != QLEARN_OK) return st;
  const float uniform = 1.0f / (float)QLEARN_PBA_BINS;
  for (int i = 0; i < QLEARN_PBA_BINS; ++i) pba->mass[i] = uniform;
  pba->trials = 0;
  pba->lo_m = cfg->range_lo_m;
  pba->hi_m = cfg->range_hi_m;
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
  const double lo = pba->lo_m;
  const double w = (pba->hi_m - pba->lo_m) / (double)QLEARN_PBA_BINS;
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
  if (zoom(pba, cfg)) summarize(pba, cfg);
  return QLEARN_OK;
}

qlearn_status_t qlearn_pba_estimate(const qlearn_pba_t *pba, const qlearn_policy_config_t *cfg,
                                    double *c_m, double *halfwidth_m) {
  if (pba == NULL || cfg == NULL || c_m == NULL || halfwidth_m == NULL) return QLEARN_E_ARG;
  double below = pba->median_m - pba->ci_lo_m;
  double above = pba->ci_hi_m - pba->median_m;
  /* Half a bin more: inside a bin the density is taken as uniform, so a quantile may sit up to
   * about half a bin from where the exact (unbinned) posterior would put it. */
  double half_bin = 0.5 * (pba->hi_m - pba->lo_m) / (double)QLEARN_PBA_BINS;
  *c_m = pba->median_m;
  *halfwidth_m = (below > above ? below : above) + half_bin;
  return QLEARN_OK;
}
