/* bench_estimate: wall time of a whole `comlearn estimate` per bundled rock, with the direct
 * backend (lib/balance in-process) and with the LCM backend against a spawned comlearn-sim
 * (YuMi placements planned with lib/placement, commands and states over a udpm URL of its own),
 * and the LCM messages per trial (YUMI_COMMAND and SIM_CONTROL sent, YUMI_STATUS and
 * OBJECT_STATE received; estimate_lcm_stats).
 *
 * Per rock and repetition: the direct estimate (open + run), then comlearn-sim spawned, the LCM
 * backend opened (waits for the first status), the estimate run, the daemon stopped. "lcm s" is
 * estimate_run alone; "open s" is spawn + estimate_lcm_open (the daemon's start and the first
 * status). Medians over the repetitions. Both estimates must agree on every component (else the
 * row is marked and the exit status is 1). Prints a markdown table (docs/estimate.md).
 *
 * Target (docs/design.md): a full 3-component estimate over LCM with YuMi placement <= 1 s wall.
 *
 * Usage: bench_estimate [--reps N] [--rock NAME] [--help]
 * Needs a multicast route for udpm (`ip route add 224.0.0.0/4 dev lo`, scripts/setup.sh). */
#define _GNU_SOURCE

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "comlearn/model.h"
#include "estimate_backend.h"
#include "estimate_direct.h"
#include "estimate_lcm.h"

static const char *const all_rocks[] = {"rock_1_even", "rock_1_uneven", "rock_2_even",
                                        "rock_2_uneven", "rock_3_even", "rock_3_uneven"};
#define N_ROCKS (sizeof all_rocks / sizeof all_rocks[0])
#define MAX_REPS 100

static double now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

static double median(double *v, size_t n) {
  qsort(v, n, sizeof *v, cmp_double);
  return n == 0 ? 0.0 : (n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]));
}

static unsigned url_counter;

static void unique_url(char *url, size_t n) {
  const unsigned port = 8700u + ((unsigned)getpid() * 7u + url_counter++) % 1000u;
  snprintf(url, n, "udpm://239.255.76.67:%u?ttl=0", port);
}

/* One direct estimate; returns the wall time of open + run, or -1. */
static double run_direct(const char *urdf, const model_mesh_t *mesh, estimate_result_t *r) {
  char msg[512] = "";
  estimate_direct_t *d = NULL;
  estimate_backend_t b;
  const double t0 = now_s();
  if (estimate_direct_open(urdf, NULL, NULL, &d, &b, msg, sizeof msg) != 0) {
    fprintf(stderr, "bench_estimate: direct %s: %s\n", urdf, msg);
    return -1.0;
  }
  estimate_config_t cfg;
  estimate_config_default(&cfg);
  const estimate_status_t s = estimate_run(mesh, &b, &cfg, r);
  const double dt = now_s() - t0;
  estimate_direct_close(d);
  if (s != ESTIMATE_OK) {
    fprintf(stderr, "bench_estimate: direct %s: %s: %s\n", urdf, estimate_status_str(s), r->msg);
    return -1.0;
  }
  return dt;
}

/* One LCM estimate against a fresh comlearn-sim; fills *open_s and *st; returns the wall time
 * of estimate_run, or -1. */
static double run_lcm(const char *urdf, const model_mesh_t *mesh, estimate_result_t *r,
                      double *open_s, estimate_lcm_stats_t *st) {
  char url[128], msg[512] = "";
  unique_url(url, sizeof url);
  const double t0 = now_s();
  const pid_t pid = estimate_lcm_sim_spawn(COMLEARN_SIM_EXE, url, msg, sizeof msg);
  if (pid <= 0) {
    fprintf(stderr, "bench_estimate: %s\n", msg);
    return -1.0;
  }
  estimate_lcm_config_t lc;
  estimate_lcm_config_default(&lc);
  lc.lcm_url = url;
  lc.urdf_path = urdf;
  lc.mesh_link = mesh;
  lc.yumi_urdf = COMLEARN_ASSETS_DIR "/yumi/yumi.urdf";
  lc.policy = "bisect";
  estimate_lcm_t *l = NULL;
  estimate_backend_t b;
  if (estimate_lcm_open(&lc, &l, &b, msg, sizeof msg) != 0) {
    fprintf(stderr, "bench_estimate: %s (udpm needs a multicast route, scripts/setup.sh)\n", msg);
    estimate_lcm_sim_stop(pid, 2.0);
    return -1.0;
  }
  const double t1 = now_s();
  *open_s = t1 - t0;
  estimate_config_t cfg;
  estimate_config_default(&cfg);
  const estimate_status_t s = estimate_run(mesh, &b, &cfg, r);
  const double dt = now_s() - t1;
  estimate_lcm_stats(l, st);
  estimate_lcm_close(l);
  const int ws = estimate_lcm_sim_stop(pid, 2.0);
  if (s != ESTIMATE_OK) {
    fprintf(stderr, "bench_estimate: lcm %s: %s: %s\n", urdf, estimate_status_str(s), r->msg);
    return -1.0;
  }
  if (ws == -1 || !WIFEXITED(ws) || WEXITSTATUS(ws) != 0)
    fprintf(stderr, "bench_estimate: comlearn-sim exit status %d\n", ws);
  return dt;
}

static void usage(FILE *f) {
  fprintf(f, "usage: bench_estimate [--reps N (1-%d, default 3)] [--rock NAME] [--help]\n",
          MAX_REPS);
}

int main(int argc, char **argv) {
  int reps = 3;
  const char *only = NULL;
  static const struct option opts[] = {{"reps", required_argument, NULL, 'r'},
                                       {"rock", required_argument, NULL, 'k'},
                                       {"help", no_argument, NULL, 'h'},
                                       {NULL, 0, NULL, 0}};
  int c;
  while ((c = getopt_long(argc, argv, "h", opts, NULL)) != -1) {
    switch (c) {
    case 'r':
      reps = atoi(optarg);
      if (reps < 1 || reps > MAX_REPS) {
        usage(stderr);
        return 2;
      }
      break;
    case 'k': only = optarg; break;
    case 'h': usage(stdout); return 0;
    default: usage(stderr); return 2;
    }
  }
  if (optind != argc) {
    usage(stderr);
    return 2;
  }

  estimate_result_t *rd = malloc(sizeof *rd), *rl = malloc(sizeof *rl);
  if (!rd || !rl) {
    fprintf(stderr, "bench_estimate: out of memory\n");
    return 1;
  }
  printf("Full estimate (bisect, 0.1 mm, noiseless), median of %d; LCM against a spawned "
         "comlearn-sim.\n\n",
         reps);
  printf("| rock | trials | direct s | lcm s | lcm open s | commands / trial | SIM_CONTROL / "
         "trial | statuses / trial | object states / trial | lcm <= 1 s | agree |\n");
  printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
  int failed = 0, rows = 0, met = 0;
  double worst = 0.0;
  for (size_t i = 0; i < N_ROCKS; ++i) {
    if (only && strcmp(only, all_rocks[i]) != 0) continue;
    char urdf[512];
    snprintf(urdf, sizeof urdf, "%s/rocks/%s.urdf", COMLEARN_ASSETS_DIR, all_rocks[i]);
    model_object_t obj = {0};
    model_error_t err = {{0}};
    if (model_object_load(urdf, NULL, &obj, &err) != MODEL_OK) {
      fprintf(stderr, "bench_estimate: %s: %s\n", urdf, err.msg);
      failed = 1;
      continue;
    }
    double td[MAX_REPS], tl[MAX_REPS], to[MAX_REPS];
    double cmd = 0, ctl = 0, sta = 0, obs = 0;
    int agree = 1, ok = 1;
    size_t trials = 0;
    for (int k = 0; k < reps && ok; ++k) {
      estimate_lcm_stats_t st;
      td[k] = run_direct(urdf, &obj.mesh, rd);
      tl[k] = td[k] < 0 ? -1.0 : run_lcm(urdf, &obj.mesh, rl, &to[k], &st);
      if (td[k] < 0 || tl[k] < 0) {
        ok = 0;
        break;
      }
      trials = rl->trial_count;
      const double n = st.trials ? (double)st.trials : 1.0;
      cmd += (double)st.commands_sent / n;
      ctl += (double)st.controls_sent / n;
      sta += (double)st.statuses / n;
      obs += (double)st.object_states / n;
      if (rl->trial_count != rd->trial_count) agree = 0;
      for (int j = 0; j < 3; ++j)
        if (rl->found[j] != rd->found[j] || !rl->found[j] ||
            fabs(rl->com_m[j] - rd->com_m[j]) > 1e-12)
          agree = 0;
    }
    model_object_free(&obj);
    if (!ok) {
      printf("| %s | failed | | | | | | | | | |\n", all_rocks[i]);
      failed = 1;
      continue;
    }
    const double mtl = median(tl, (size_t)reps);
    ++rows;
    met += mtl <= 1.0;
    if (mtl > worst) worst = mtl;
    printf("| %s | %zu | %.3f | %.3f | %.3f | %.2f | %.2f | %.1f | %.1f | %s | %s |\n",
           all_rocks[i], trials, median(td, (size_t)reps), mtl, median(to, (size_t)reps),
           cmd / reps, ctl / reps, sta / reps, obs / reps, mtl <= 1.0 ? "yes" : "no",
           agree ? "yes" : "NO");
    fflush(stdout);
    if (!agree) failed = 1;
  }
  printf("\nTarget (docs/design.md): full 3-component estimate over LCM with YuMi placement <= 1 s wall: "
         "%d of %d rocks (worst %.3f s).\n",
         met, rows, worst);
  free(rd);
  free(rl);
  return failed ? 1 : 0;
}
