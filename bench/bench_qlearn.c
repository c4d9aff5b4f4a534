/* bench_qlearn: trials per CoM component for each policy over 1000 random thresholds, noiseless
 * and with probit placement noise (0.1, 0.5, 1 mm), against the information limit
 * log2(range / resolution); plus the final error. Prints a markdown table. Not a test.
 * Usage: bench_qlearn [runs]   (default 1000) */
#include <getopt.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "comlearn/cli_args.h"
#include "comlearn/qlearn.h"

#include "test_rng.h"

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a;
  double y = *(const double *)b;
  return (x > y) - (x < y);
}
static double pct(double *v, int n, double p) {
  qsort(v, (size_t)n, sizeof *v, cmp_double);
  int i = (int)ceil(p * n) - 1;
  return v[i < 0 ? 0 : i];
}

int main(int argc, char **argv) {
  static const struct option opts[] = {
      {"help", no_argument, NULL, 'h'}, {"version", no_argument, NULL, 'V'}, {NULL, 0, NULL, 0}};
  int opt;
  opterr = 0;
  while ((opt = getopt_long(argc, argv, "hV", opts, NULL)) != -1) {
    switch (opt) {
      case 'h':
        printf("usage: bench_qlearn [RUNS (1..100000, default 1000)] [-h] [-V]\n");
        return 0;
      case 'V': cli_version_print(stdout, "bench_qlearn"); return 0;
      default: cli_getopt_complain("bench_qlearn", "hV", opts, argv); return 2;
    }
  }
  int runs = optind < argc ? atoi(argv[optind]) : 1000;
  if (runs < 1 || runs > 100000 || argc - optind > 1) {
    fprintf(stderr, "usage: bench_qlearn [RUNS (1..100000, default 1000)] [-h] [-V]\n");
    return 2;
  }
  const qlearn_policy_kind_t kinds[] = {QLEARN_POLICY_BISECT, QLEARN_POLICY_PBA,
                                        QLEARN_POLICY_PAPER_QTABLE, QLEARN_POLICY_PAPER_MLP};
  const char *names[] = {"bisect", "pba", "paper-qtable", "paper-mlp"};
  const double sigmas[] = {0.0, 1e-4, 5e-4, 1e-3};
  const char *priors[] = {"box center (prior 0)", "mesh CoM (prior = c + N(0, 2 mm))"};
  double *tr = malloc(sizeof(double) * (size_t)runs);
  double *err = malloc(sizeof(double) * (size_t)runs);
  if (tr == NULL || err == NULL) return 1;
  qlearn_policy_config_t base;
  qlearn_policy_config_default(QLEARN_POLICY_BISECT, &base);
  double limit = log2((base.range_hi_m - base.range_lo_m) / base.resolution_m);
  printf(
      "sizeof(qlearn_policy_t) = %zu bytes; range %.0f mm, resolution %.2f mm, "
      "information limit log2(range / resolution) = %.2f trials; %d thresholds c ~ U(-5, 5) cm "
      "per row\n\n",
      sizeof(qlearn_policy_t), 1e3 * (base.range_hi_m - base.range_lo_m), 1e3 * base.resolution_m,
      limit, runs);
  printf(
      "| policy | prior | noise sigma | trials median | trials p95 | trials max | "
      "|error| median (mm) | |error| p95 (mm) | in reported interval |\n");
  printf("|---|---|---|---|---|---|---|---|---|\n");
  for (int pr = 0; pr < 2; ++pr) {
    for (int k = 0; k < 4; ++k) {
      for (int si = 0; si < 4; ++si) {
        rng_t r = {1000u + (uint64_t)si};
        int inside = 0;
        int failed = 0;
        for (int run = 0; run < runs; ++run) {
          double c = -0.05 + 0.1 * rng_uniform(&r);
          qlearn_policy_config_t cfg;
          qlearn_policy_config_default(kinds[k], &cfg);
          cfg.noise = QLEARN_NOISE_PROBIT;
          cfg.sigma_m = sigmas[si];
          cfg.seed = (uint64_t)run + 1u;
          if (pr == 1) cfg.prior_m = fmin(0.05, fmax(-0.05, c + 0.002 * rng_normal(&r)));
          qlearn_policy_t pol;
          if (qlearn_policy_init(&pol, &cfg) != QLEARN_OK) return 1;
          for (int i = 0; i <= QLEARN_MAX_TRIALS; ++i) {
            double x = 0.0;
            if (qlearn_policy_next(&pol, &x) != QLEARN_OK) break;
            double achieved = x + sigmas[si] * rng_normal(&r);
            qlearn_outcome_t o = c > achieved ? QLEARN_TIPS : QLEARN_STAYS;
            qlearn_status_t st = qlearn_policy_observe(&pol, x, o);
            if (st != QLEARN_OK) { /* bisect rejects contradicting (noisy) outcomes: stop */
              failed++;
              break;
            }
          }
          double est = 0.0;
          double hw = 0.0;
          qlearn_policy_estimate(&pol, &est, &hw);
          tr[run] = (double)pol.trials;
          err[run] = fabs(est - c);
          if (err[run] <= hw) inside++;
        }
        double med = pct(tr, runs, 0.5);
        double p95 = pct(tr, runs, 0.95);
        double mx = pct(tr, runs, 1.0);
        double emed = pct(err, runs, 0.5);
        double ep95 = pct(err, runs, 0.95);
        printf("| %s | %s | %.1f mm | %.0f | %.0f | %.0f | %.3f | %.3f | %.1f %%%s |\n", names[k],
               priors[pr], 1e3 * sigmas[si], med, p95, mx, 1e3 * emed, 1e3 * ep95,
               100.0 * inside / runs, failed ? " (stopped early: contradiction)" : "");
        fflush(stdout);
      }
    }
  }
  free(tr);
  free(err);
  return 0;
}
