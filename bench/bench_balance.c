/* bench_balance - speed and bias of one balance trial (lib/balance), one core.
 *
 * For each case: the tipping threshold is bisected over the +X edge of B (placement offset of the
 * point put over the edge, along the edge normal, 2 cm bracket around the truth, down to 1 nm),
 * bias = threshold - true CoM coordinate. Then "trials near the threshold" are timed: trials
 * with the true CoM at +-1, +-3, +-10 and +-30 um from the edge, round robin, until --trials are
 * done. trials/s and microseconds per step (wall time / steps) count those trials only.
 * The stock path runs trials / 8 near-threshold trials (it is ~20x slower). "wrong" counts
 * near-threshold trials whose outcome contradicts the truth. BENCH_ONLY=substring selects cases.
 * Usage: bench_balance [--trials N] [--json] [--verbose] [--rock URDF] */
#define _POSIX_C_SOURCE 200809L
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "comlearn/balance.h"
#include "comlearn/cli_args.h"
#include "comlearn/cli_log.h"
#include "comlearn/cli_time.h"
#include "comlearn/model.h"
#include "comlearn/model_inertial.h"

typedef struct {
  const char *name;
  balance_contact_t path;
  model_mesh_t mesh;
  model_mass_t mass;
} bench_case_t;

typedef struct {
  double bias_m;
  int bisect_trials;
  int trials;
  double trials_per_s;
  double us_per_step;
  double steps_per_trial;
  int wrong; /* near-threshold trials whose outcome contradicts the truth */
} bench_result_t;

/* One trial with the CoM at `offset_m` inside the +X edge (negative: beyond it). */
static int trial_at(balance_world_t *w, balance_object_t *o, const model_mass_t *ms, double s,
                    balance_trial_result_t *res) {
  const double q[4] = {1, 0, 0, 0};
  const double p[3] = {ms->com_m[0] + s, ms->com_m[1], ms->com_m[2]};
  model_pose_t pose;
  balance_status_t st = balance_pose_over_edge(w, o, q, MODEL_EDGE_PX, p, 0.0, 1e-6, &pose);
  if (st != BALANCE_OK) return (int)st;
  return (int)balance_trial_run(w, o, &pose, NULL, res);
}

static int run_case(bench_case_t *c, int ntrials, int verbose, bench_result_t *r) {
  balance_config_t cfg;
  balance_config_default(&cfg);
  cfg.contact = c->path;
  balance_world_t *w = NULL;
  balance_object_t *o = NULL;
  if (balance_world_create(&cfg, &w) != BALANCE_OK) return -1;
  balance_status_t st = balance_object_create(w, &c->mesh, &c->mass, &o);
  if (st != BALANCE_OK) {
    LOG_E("%s: %s", c->name, balance_status_str(st));
    balance_world_destroy(w);
    return -1;
  }
  memset(r, 0, sizeof *r);
  /* s: how far the point over the edge lies beyond the CoM along +x; the CoM is inside by s. */
  double lo = -0.01, hi = 0.01;
  while (hi - lo > 1e-9) {
    const double mid = 0.5 * (lo + hi);
    balance_trial_result_t res;
    if (trial_at(w, o, &c->mass, mid, &res) != 0) return -1;
    r->bisect_trials++;
    if (verbose)
      fprintf(stderr, "  %s s=%+.4f um outcome %d steps %u rot %.3g\n", c->name, mid * 1e6,
              (int)res.outcome, res.steps, res.rotation_rad);
    if (res.outcome == BALANCE_STAYS)
      hi = mid;
    else
      lo = mid;
  }
  /* Threshold in s; the truth is s = 0. */
  r->bias_m = 0.5 * (lo + hi);
  static const double offs[8] = {1e-6, -1e-6, 3e-6, -3e-6, 1e-5, -1e-5, 3e-5, -3e-5};
  unsigned long steps = 0;
  const double t0 = cli_time_now_s();
  for (int i = 0; i < ntrials; i++) {
    balance_trial_result_t res;
    const double s = offs[i % 8];
    if (trial_at(w, o, &c->mass, s, &res) != 0) return -1;
    steps += res.steps;
    const balance_outcome_t want = s > 0 ? BALANCE_STAYS : BALANCE_TIPS;
    if (res.outcome != want) r->wrong++;
  }
  const double dt = cli_time_now_s() - t0;
  r->trials = ntrials;
  r->trials_per_s = ntrials / dt;
  r->us_per_step = 1e6 * dt / (double)steps;
  r->steps_per_trial = (double)steps / ntrials;
  balance_world_destroy(w);
  return 0;
}

/* The cases: a box on the fast path, the rock on the stock and the fast path. obj holds the rock
 * (freed by the caller). Returns 0, or 1 (logged when the rock cannot be read). */
static int cases_load(const char *rock, bench_case_t cases[3], model_object_t *obj) {
  memset(cases, 0, 3 * sizeof *cases);
  const double lo[3] = {-0.02, -0.03, -0.025}, hi[3] = {0.02, 0.03, 0.025};
  if (model_mesh_box(lo, hi, &cases[0].mesh) != MODEL_OK) return 1;
  if (model_mesh_mass(&cases[0].mesh, 2650.0, &cases[0].mass) != MODEL_OK) return 1;
  cases[0].name = "box 40x60x50 mm";
  cases[0].path = BALANCE_CONTACT_FAST;
  model_error_t err;
  if (model_object_load(rock, NULL, obj, &err) != MODEL_OK) {
    LOG_E("%s", err.msg);
    return 1;
  }
  model_mass_t rm;
  if (model_inertial_load(rock, NULL, &rm, &err) != MODEL_OK) {
    LOG_E("%s", err.msg);
    return 1;
  }
  for (int k = 1; k < 3; k++) {
    if (model_mesh_copy(&obj->mesh, &cases[k].mesh) != MODEL_OK) return 1;
    cases[k].mass = rm;
  }
  static char rock_name[128];
  const char *base = strrchr(rock, '/');
  snprintf(rock_name, sizeof rock_name, "%s", base ? base + 1 : rock);
  char *dot = strstr(rock_name, ".urdf");
  if (dot) *dot = '\0';
  cases[1].name = rock_name;
  cases[1].path = BALANCE_CONTACT_STOCK;
  cases[2].name = rock_name;
  cases[2].path = BALANCE_CONTACT_FAST;
  return 0;
}

/* One case's table row, or its JSON object (first: no comma before it). */
static void case_print(int json, int first, const bench_case_t *c, const bench_result_t *r) {
  const char *path = c->path == BALANCE_CONTACT_FAST ? "fast" : "stock";
  if (json)
    printf(
        "%s{\"case\":\"%s\",\"path\":\"%s\",\"triangles\":%zu,\"trials\":%d,\"trials_per_s\":%.1f,"
        "\"us_per_step\":%.2f,\"steps_per_trial\":%.1f,\"wrong\":%d,\"bias_um\":%.3f}",
        first ? "" : ",", c->name, path, c->mesh.triangle_count, r->trials, r->trials_per_s,
        r->us_per_step, r->steps_per_trial, r->wrong, r->bias_m * 1e6);
  else
    printf("| %s | %s | %zu | %d | %.0f | %.2f | %.0f | %d | %+.3f |\n", c->name, path,
           c->mesh.triangle_count, r->trials, r->trials_per_s, r->us_per_step, r->steps_per_trial,
           r->wrong, r->bias_m * 1e6);
}

int main(int argc, char **argv) {
  cli_log_init("bench_balance");
  int ntrials = 400, json = 0, verbose = 0;
  const char *rock = COMLEARN_ASSETS_DIR "/rocks/rock_1_even.urdf";
  static const struct option opts[] = {{"trials", required_argument, NULL, 'n'},
                                       {"json", no_argument, NULL, 'j'},
                                       {"verbose", no_argument, NULL, 'v'},
                                       {"rock", required_argument, NULL, 'r'},
                                       {"help", no_argument, NULL, 'h'},
                                       {"version", no_argument, NULL, 'V'},
                                       {NULL, 0, NULL, 0}};
  int c;
  opterr = 0;
  while ((c = getopt_long(argc, argv, "hV", opts, NULL)) != -1) {
    switch (c) {
      case 'n': ntrials = atoi(optarg); break;
      case 'j': json = 1; break;
      case 'v': verbose = 1; break;
      case 'r': rock = optarg; break;
      case 'h':
        printf(
            "usage: bench_balance [--trials N (400)] [--json] [--verbose] [--rock URDF (%s)]\n"
            "                     [-h | --help] [-V | --version]\n",
            rock);
        return 0;
      case 'V': cli_version_print(stdout, "bench_balance"); return 0;
      default: cli_getopt_complain("bench_balance", "hV", opts, argv); return 2;
    }
  }
  if (cli_args_none_left("bench_balance", argc, argv)) return 2;
  if (ntrials < 8) ntrials = 8;
  bench_case_t cases[3];
  model_object_t obj;
  if (cases_load(rock, cases, &obj) != 0) return 1;
  const char *only = getenv("BENCH_ONLY");
  if (json)
    printf("[");
  else
    printf(
        "| case | contact path | triangles | trials | trials/s | us/step | steps/trial | wrong | "
        "bias um |\n|---|---|---|---|---|---|---|---|---|\n");
  int first = 1;
  for (int k = 0; k < 3; k++) {
    if (only && !strstr(cases[k].name, only) &&
        !strstr(cases[k].path == BALANCE_CONTACT_FAST ? "fast" : "stock", only))
      continue;
    bench_result_t r;
    const int nt =
        cases[k].path == BALANCE_CONTACT_STOCK ? (ntrials / 8 > 8 ? ntrials / 8 : 8) : ntrials;
    if (run_case(&cases[k], nt, verbose, &r) != 0) return 1;
    case_print(json, first, &cases[k], &r);
    fflush(stdout);
    first = 0;
  }
  if (json) printf("]\n");
  for (int k = 0; k < 3; k++) model_mesh_free(&cases[k].mesh);
  model_object_free(&obj);
  return 0;
}
