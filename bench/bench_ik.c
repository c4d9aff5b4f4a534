/* bench_ik: accuracy and cost of lib/placement's YuMi FK and IK.
 *
 * For each arm: N random postures uniform within the joint limits, T = FK(q), then IK(T) from the
 * nominal seed with the default options (PLACEMENT_IK_CONFIG_INIT), and again without the
 * redundancy phase (nullspace_gain 0). Prints the success rate, the verified FK(IK(T)) error,
 * iterations (median / max), seeds, microseconds per solve, and microseconds per FK call.
 *
 * Usage: bench_ik [--poses N] [--seed S] [--urdf PATH] [--json] [--help] */
#define _POSIX_C_SOURCE 200809L

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "comlearn/cli_args.h"
#include "comlearn/cli_log.h"
#include "comlearn/cli_time.h"
#include "comlearn/math3d.h"
#include "comlearn/placement.h"

static double now_us(void) { return 1e6 * cli_time_now_s(); }

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

static double median(double *v, size_t n) {
  qsort(v, n, sizeof *v, cmp_double);
  return n == 0 ? 0.0 : (n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]));
}

typedef struct {
  size_t ok;
  double worst_pos_m, worst_rot_rad;
  double it_median, it_max, seeds_max, us_median, us_mean, us_max;
} run_stats_t;

static void run(const placement_arm_t *arm, const placement_pose_t *targets, size_t n,
                const placement_ik_config_t *cfg, double *it_buf, double *us_buf, run_stats_t *st) {
  memset(st, 0, sizeof *st);
  double us_sum = 0.0;
  for (size_t i = 0; i < n; ++i) {
    placement_ik_result_t res;
    double t0 = now_us();
    placement_status_t s = placement_ik(arm, &targets[i], NULL, cfg, &res);
    double dt = now_us() - t0;
    us_buf[i] = dt;
    us_sum += dt;
    st->us_max = fmax(st->us_max, dt);
    it_buf[i] = res.iterations;
    st->it_max = fmax(st->it_max, res.iterations);
    st->seeds_max = fmax(st->seeds_max, res.seeds);
    if (s == PLACEMENT_OK) {
      placement_pose_t got;
      double dp, dr;
      placement_fk(arm, res.q_rad, &got);
      placement_pose_distance(&got, &targets[i], &dp, &dr);
      st->worst_pos_m = fmax(st->worst_pos_m, dp);
      st->worst_rot_rad = fmax(st->worst_rot_rad, dr);
      ++st->ok;
    }
  }
  st->it_median = median(it_buf, n);
  st->us_median = median(us_buf, n);
  st->us_mean = us_sum / (double)n;
}

static void usage(FILE *f) {
  fprintf(f,
          "usage: bench_ik [options]\n"
          "  --poses N    random reachable poses per arm (default 10000)\n"
          "  --seed S     random seed (default 1)\n"
          "  --urdf PATH  YuMi URDF (default %s/yumi/yumi.urdf)\n"
          "  --json       print JSON instead of text\n"
          "  -h, --help   this text\n"
          "  -V, --version  print the version\n",
          COMLEARN_ASSETS_DIR);
}

/* targets[0 .. n): FK of postures uniform within the arm's joint limits, drawn from rng. */
static void targets_draw(const placement_arm_t *arm, uint64_t rng, placement_pose_t *targets,
                         size_t n) {
  for (size_t i = 0; i < n; ++i) {
    double q[PLACEMENT_JOINTS];
    for (int k = 0; k < PLACEMENT_JOINTS; ++k) {
      double u = cl_rng_uniform(&rng);
      q[k] = arm->lower_rad[k] + (arm->upper_rad[k] - arm->lower_rad[k]) * u;
    }
    placement_fk(arm, q, &targets[i]);
  }
}

/* One arm's line (JSON: its object) for the two IK modes. */
static void arm_print(int json, int side, double fk_us, size_t n, const run_stats_t *const rs[2]) {
  const char *name = side == 0 ? "left" : "right";
  const char *mode[2] = {"default", "no_redundancy"};
  if (json) {
    printf("%s{\"arm\": \"%s\", \"fk_us\": %.3f, \"runs\": [", side ? ", " : "", name, fk_us);
    for (int r = 0; r < 2; ++r) {
      printf(
          "%s{\"mode\": \"%s\", \"success\": %.6f, \"worst_pos_m\": %.3g, "
          "\"worst_rot_rad\": %.3g, \"iterations_median\": %.1f, \"iterations_max\": %.0f, "
          "\"seeds_max\": %.0f, \"us_median\": %.2f, \"us_mean\": %.2f, \"us_max\": %.1f}",
          r ? ", " : "", mode[r], (double)rs[r]->ok / (double)n, rs[r]->worst_pos_m,
          rs[r]->worst_rot_rad, rs[r]->it_median, rs[r]->it_max, rs[r]->seeds_max, rs[r]->us_median,
          rs[r]->us_mean, rs[r]->us_max);
    }
    printf("]}");
  } else {
    printf("%s arm: FK %.3f us/call, %zu random reachable poses\n", name, fk_us, n);
    for (int r = 0; r < 2; ++r) {
      printf(
          "  IK %-13s success %zu/%zu (%.4f %%), worst FK(IK(T)) error %.2g m %.2g rad, "
          "iterations median %.0f max %.0f, seeds max %.0f, us/solve median %.1f mean %.1f "
          "max %.0f\n",
          mode[r], rs[r]->ok, n, 100.0 * (double)rs[r]->ok / (double)n, rs[r]->worst_pos_m,
          rs[r]->worst_rot_rad, rs[r]->it_median, rs[r]->it_max, rs[r]->seeds_max, rs[r]->us_median,
          rs[r]->us_mean, rs[r]->us_max);
    }
  }
}

/* One arm: targets, the FK cost, IK with and without the redundancy phase. Returns 0 or 1. */
static int arm_bench(const char *urdf, int side, uint64_t seed, size_t n, int json,
                     placement_pose_t *targets, double *it_buf, double *us_buf) {
  placement_arm_t arm;
  placement_error_t err;
  if (placement_arm_load_yumi(&arm, urdf, (placement_side_t)side, &err) != PLACEMENT_OK) {
    LOG_E("%s", err.msg);
    return 1;
  }
  targets_draw(&arm, seed + (uint64_t)side, targets, n);
  /* FK cost: the same postures again, ten times over, with the poses regenerated. */
  const double t0 = now_us();
  for (int rep = 0; rep < 10; ++rep) targets_draw(&arm, seed + (uint64_t)side, targets, n);
  double fk_us = (now_us() - t0) / (10.0 * (double)n); /* includes drawing q */
  placement_ik_config_t cfg = PLACEMENT_IK_CONFIG_INIT;
  run_stats_t full, plain;
  run(&arm, targets, n, &cfg, it_buf, us_buf, &full);
  cfg.nullspace_gain = 0.0;
  run(&arm, targets, n, &cfg, it_buf, us_buf, &plain);
  const run_stats_t *const rs[2] = {&full, &plain};
  arm_print(json, side, fk_us, n, rs);
  return 0;
}

int main(int argc, char **argv) {
  cli_log_init("bench_ik");
  long poses = 10000;
  uint64_t seed = 1;
  const char *urdf = COMLEARN_ASSETS_DIR "/yumi/yumi.urdf";
  int json = 0;
  static const struct option opts[] = {{"poses", required_argument, NULL, 'n'},
                                       {"seed", required_argument, NULL, 's'},
                                       {"urdf", required_argument, NULL, 'u'},
                                       {"json", no_argument, NULL, 'j'},
                                       {"help", no_argument, NULL, 'h'},
                                       {"version", no_argument, NULL, 'V'},
                                       {NULL, 0, NULL, 0}};
  int c;
  opterr = 0;
  while ((c = getopt_long(argc, argv, "hV", opts, NULL)) != -1) {
    switch (c) {
      case 'n': poses = strtol(optarg, NULL, 10); break;
      case 's': seed = (uint64_t)strtoull(optarg, NULL, 10); break;
      case 'u': urdf = optarg; break;
      case 'j': json = 1; break;
      case 'h': usage(stdout); return 0;
      case 'V': cli_version_print(stdout, "bench_ik"); return 0;
      default: cli_getopt_complain("bench_ik", "hV", opts, argv); return 2;
    }
  }
  if (poses < 1 || poses > 10000000 || optind != argc) {
    usage(stderr);
    return 2;
  }
  size_t n = (size_t)poses;
  placement_pose_t *targets = malloc(n * sizeof *targets);
  double *it_buf = malloc(n * sizeof *it_buf), *us_buf = malloc(n * sizeof *us_buf);
  if (targets == NULL || it_buf == NULL || us_buf == NULL) {
    LOG_E("out of memory");
    return 1;
  }
  if (json) {
    printf("{\"poses\": %zu, \"arms\": [", n);
  }
  for (int side = 0; side < 2; ++side)
    if (arm_bench(urdf, side, seed, n, json, targets, it_buf, us_buf) != 0) return 1;
  if (json) {
    printf("]}\n");
  }
  free(targets);
  free(it_buf);
  free(us_buf);
  return 0;
}
