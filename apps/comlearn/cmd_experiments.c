/*
 * cmd_experiments.c - `comlearn experiments OBJECT.urdf...`: the paper's Table I and Fig. 2 for
 * every rock and policy, noiseless and with placement / pose noise (docs/experiments.md).
 *
 * Each run is one `comlearn estimate`: geometry in, trials through a backend (noiseless: --direct
 * or LCM to a running comlearn-sim; noisy: always the direct backend with comlearn-sim's noise
 * and seeding), estimate out. A small decorator backend records the running estimate the
 * estimator reports before every trial (estimate_trial_request_t.com_before_m) for Fig. 2. The
 * URDF <inertial> is read only after a rock's runs, for the report (as `estimate --truth`).
 */
#define _GNU_SOURCE
#include "cmd_experiments.h"

#include <errno.h>
#include <getopt.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include "comlearn/cli_args.h"
#include "comlearn/cli_json.h"
#include "comlearn/cli_log.h"
#include "comlearn/cli_paths.h"
#include "comlearn/cli_time.h"
#include "comlearn/model.h"
#include "comlearn/model_inertial.h"
#include "estimate_backend.h"
#include "estimate_direct.h"
#include "estimate_lcm.h"
#include "experiments_svg.h"

enum { EXIT_USAGE = 2, MAX_POLICIES = 4, MAX_SEEDS = 1000, MAX_SIMS = 16 };

/* The paper's result as docs/design.md states it in "What is being reproduced" (McGovern, Mao &
 * Xiao, IROS 2019, Table I: three even rocks, Gazebo + ODE + YuMi). Only the summary is given
 * there: no per-cell numbers. */
#define PAPER_ROCKS 3
#define PAPER_COMPONENTS 9
#define PAPER_NA 2
#define PAPER_ERR_MIN_MM 0.1
#define PAPER_ERR_MAX_MM 4.4
#define PAPER_ERR_MEAN_MM 1.5

static const qlearn_policy_kind_t all_policies[MAX_POLICIES] = {
    QLEARN_POLICY_PAPER_QTABLE, QLEARN_POLICY_PAPER_MLP, QLEARN_POLICY_BISECT, QLEARN_POLICY_PBA};

/* One trial as the estimator asked for it: the running estimate before it, and what came of it. */
typedef struct {
  int kind;      /* estimate_trial_kind_t */
  int component; /* -1 for a stable check */
  int outcome;   /* balance_outcome_t; -1 when the backend failed */
  double com_before_m[3];
  double halfwidth_before_m[3];
  /* the link point set over the edge (stable checks: over B's centre). For every policy this is
   * its current estimate along the search direction, so Fig. 2 draws it: the paper's walk. */
  double target_link_m[3];
} exp_step_t;

/* The decorator backend: records each request, forwards it to the inner backend. */
typedef struct {
  const estimate_backend_t *inner;
  exp_step_t step[ESTIMATE_MAX_TRIALS];
  size_t n;
} recorder_t;

static int recorder_run(void *ctx, const estimate_trial_request_t *req,
                        estimate_trial_reply_t *reply, char *err, size_t err_size) {
  recorder_t *r = ctx;
  exp_step_t *s = r->n < ESTIMATE_MAX_TRIALS ? &r->step[r->n++] : NULL;
  int rc = r->inner->run(r->inner->ctx, req, reply, err, err_size);
  if (s) {
    s->kind = (int)req->kind;
    s->component = req->component;
    s->outcome = rc == 0 ? (int)reply->outcome : -1;
    memcpy(s->com_before_m, req->com_before_m, sizeof s->com_before_m);
    memcpy(s->halfwidth_before_m, req->halfwidth_before_m, sizeof s->halfwidth_before_m);
    memcpy(s->target_link_m, req->target_link_m, sizeof s->target_link_m);
  }
  return rc;
}

/* The three kinds of run per object and policy: Table I (noiseless, started where the paper
 * starts: the bounding-box centre, state 0), the same with the mesh prior (started at the mesh's
 * uniform-density CoM: information the paper does not use, a labelled row of its own), and noisy
 * (started at the bounding-box centre, every policy told the noise model). */
typedef enum { RUN_TABLE = 0, RUN_PRIOR = 1, RUN_NOISY = 2 } run_kind_t;

typedef struct {
  size_t rock;
  qlearn_policy_kind_t policy;
  run_kind_t kind;
  int noisy;            /* kind == RUN_NOISY */
  uint64_t seed;        /* noisy runs: the noise seed (and the MLP's) */
  const char *backend;  /* "direct" / "lcm" */
  double resolution_m;  /* what the estimator ran with */
  double noise_sigma_m; /* estimate_config_t.noise_sigma_m */
  estimate_status_t status;
  char note[512];
  size_t trials, stable_trials, flagged_trials;
  size_t nsearch;
  uint32_t search_trials[ESTIMATE_MAX_SEARCHES]; /* edge trials of each search */
  double com_m[3], halfwidth_m[3];
  int found[3];
  double error_m[3]; /* com - truth; NAN when not found or no truth */
  double wall_s;
  exp_step_t *steps; /* nsteps, heap */
  size_t nsteps;
} exp_run_t;

typedef struct {
  const char *path;
  char stem[128];
  double bbox_center_m[3];
  double uniform_com_m[3];
  int have_truth;
  double truth_m[3];
  int uniform_density; /* truth within 1 um of the uniform-density CoM (like the paper's) */
} exp_rock_t;

typedef struct {
  const char *policies_arg;
  qlearn_policy_kind_t policy[MAX_POLICIES];
  int npolicies;
  int seeds;
  double placement_noise_m, pose_noise_m, resolution_m;
  const char *lcm_url, *out_dir;
  int json, quiet;
  int sims;                   /* --sims: worker processes, each with a comlearn-sim; 0: none */
  int direct;                 /* --direct given (the default; refused with --lcm-url, --sims) */
  const char *channel_prefix; /* a worker's robot (R<w>_); NULL: none */
} exp_opts_t;

static void usage(FILE *out) {
  fprintf(
      out,
      "usage: comlearn experiments OBJECT.urdf... [options]\n"
      "\n"
      "Reproduces the paper's Table I and Fig. 2: estimates every object's CoM with every\n"
      "policy, noiseless and with placement / pose noise, and compares with the URDF\n"
      "<inertial> (read after each estimate, for the report only). docs/experiments.md.\n"
      "\n"
      "options:\n"
      "  --policies LIST          comma list of paper-qtable, paper-mlp, bisect, pba\n"
      "                           (default: paper-qtable,paper-mlp,bisect,pba)\n"
      "  --seeds N                noisy runs per object and policy, seeds 1..N, 0..%d;\n"
      "                           0: noiseless only (default: 5)\n"
      "  --placement-noise-mm S   std. dev. of the horizontal release offset of noisy runs,\n"
      "                           0..100 (default: 0.5)\n"
      "  --pose-noise-mm S        std. dev. of the perceived settled position of noisy runs,\n"
      "                           0..100 (default: 0.2)\n"
      "  --resolution-mm R        search resolution in mm, 0.001..10 (default: 0.1); noisy\n"
      "                           runs take every component to a 0.5 mm 95 %% half width\n"
      "                           (estimate --noise-target-mm)\n"
      "  --lcm-url URL            run the noiseless estimates over LCM with YuMi placement\n"
      "                           against a comlearn-sim already running there (default:\n"
      "                           in-process, as `estimate --direct`); noisy runs are\n"
      "                           always in-process\n"
      "  --direct                 every run in-process, on lib/balance (the default; as\n"
      "                           `estimate --direct`)\n"
      "  --sims N                 start N comlearn-sims (channel prefixes R0_ .. R<N-1>_) on\n"
      "                           --lcm-url, or on udpm://239.255.76.67:<7700 + pid %% 1000>\n"
      "                           ?ttl=0, and spread the objects over N worker processes, one\n"
      "                           per sim: the noiseless runs over LCM, the noisy ones\n"
      "                           in-process; the same results as one sim, 1..16 (default:\n"
      "                           none: --lcm-url's running sim, or in-process)\n"
      "  --out DIR                write DIR/table.md, DIR/experiments.json,\n"
      "                           DIR/fig2_<object>.svg and, with --seeds > 0, DIR/noisy.svg\n"
      "                           (default: no files)\n"
      "  --json                   print the JSON on stdout instead of the table (default: off)\n"
      "  -v, --verbose            log debug messages on stderr (default: info)\n"
      "  -q, --quiet              log errors only; no progress (default: one line per run\n"
      "                           with its count and the time left, when stderr is a\n"
      "                           terminal or with -v)\n"
      "  -h, --help               show this help\n"
      "  -V, --version            print the version\n"
      "\n"
      "exit status: 0 success, 1 runtime failure, 2 usage or bad input\n",
      MAX_SEEDS);
}

/* A number in [lo, hi] or -1 with a message naming the option. */
static int parse_mm(const char *opt, const char *arg, double lo, double hi, double *out_mm) {
  char *end;
  errno = 0;
  double v = strtod(arg, &end);
  if (end == arg || *end != '\0' || errno != 0 || !isfinite(v) || v < lo || v > hi) {
    LOG_E("%s: '%s' is not a number in [%g, %g]", opt, arg, lo, hi);
    return -1;
  }
  *out_mm = v;
  return 0;
}

static int parse_policies(const char *arg, exp_opts_t *o) {
  char buf[256];
  if (strlen(arg) >= sizeof buf) {
    LOG_E("--policies: list too long");
    return -1;
  }
  snprintf(buf, sizeof buf, "%s", arg);
  o->npolicies = 0;
  char *save = NULL;
  for (char *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
    int hit = -1;
    for (int i = 0; i < MAX_POLICIES; ++i)
      if (strcmp(tok, estimate_policy_name(all_policies[i])) == 0) hit = i;
    if (hit < 0) {
      LOG_E("--policies: '%s' is not one of paper-qtable, paper-mlp, bisect, pba", tok);
      return -1;
    }
    for (int i = 0; i < o->npolicies; ++i)
      if (o->policy[i] == all_policies[hit]) {
        LOG_E("--policies: '%s' is listed twice", tok);
        return -1;
      }
    o->policy[o->npolicies++] = all_policies[hit];
  }
  if (o->npolicies == 0) {
    LOG_E("--policies: empty list");
    return -1;
  }
  return 0;
}

static void lcm_log(void *ctx, const char *msg) {
  (void)ctx;
  LOG_D("lcm: %s", msg);
}

static void stem_of(const char *path, char *out, size_t size) {
  const char *b = strrchr(path, '/');
  b = b ? b + 1 : path;
  size_t n = strlen(b);
  if (n > 5 && strcmp(b + n - 5, ".urdf") == 0) n -= 5;
  if (n >= size) n = size - 1;
  memcpy(out, b, n);
  out[n] = '\0';
  for (char *p = out; *p; ++p) /* safe in a file name */
    if (!((*p >= 'a' && *p <= 'z') || (*p >= 'A' && *p <= 'Z') || (*p >= '0' && *p <= '9') ||
          *p == '_' || *p == '-' || *p == '.'))
      *p = '_';
}

/* ---- one run -------------------------------------------------------------------------------- */

/* The estimator's configuration of one run; records what it runs with in run. */
static void run_config(const exp_opts_t *o, exp_run_t *run, estimate_config_t *cfg) {
  estimate_config_default(cfg);
  cfg->policy = run->policy;
  cfg->resolution_m = o->resolution_m;
  cfg->start = run->kind == RUN_PRIOR ? ESTIMATE_START_UNIFORM : ESTIMATE_START_BBOX;
  if (run->noisy) {
    cfg->seed = run->seed;
    /* outcomes are probit in the placement error along the edge normal (docs/estimate.md): every
     * policy gets the noise model, so every interval is a 95 % interval */
    cfg->noise_sigma_m = o->placement_noise_m;
  }
  /* noisy: where a search first stops (estimate.h, noise_stop_width_m) */
  run->resolution_m = run->noisy ? fmax(fmax(cfg->resolution_m, cfg->noise_sigma_m),
                                        2.0 * cfg->noise_target_halfwidth_m)
                                 : cfg->resolution_m;
  run->noise_sigma_m = cfg->noise_sigma_m;
}

/* The backend of one run: LCM to a running comlearn-sim (noiseless, with --lcm-url), else
 * in-process with the run's noise. *sim or *lcmb is the one opened. Returns 0, or (logged, both
 * closed) 1 when it could not open, 2 bad input. */
static int run_backend_open(const exp_opts_t *o, const exp_rock_t *rock, const model_object_t *obj,
                            const exp_run_t *run, estimate_direct_t **sim, estimate_lcm_t **lcmb,
                            estimate_backend_t *inner) {
  char err[512] = "";
  int rc;
  if (!run->noisy && o->lcm_url) {
    estimate_lcm_config_t lc;
    estimate_lcm_config_default(&lc);
    lc.lcm_url = o->lcm_url;
    lc.channel_prefix = o->channel_prefix;
    lc.urdf_path = rock->path;
    lc.mesh_link = &obj->mesh;
    lc.yumi_urdf = cli_paths_yumi_urdf();
    lc.policy = estimate_policy_name(run->policy);
    lc.log = lcm_log;
    rc = estimate_lcm_open(&lc, lcmb, inner, err, sizeof err);
  } else {
    rc = estimate_direct_open(rock->path, NULL, NULL, sim, inner, err, sizeof err);
    if (rc == 0 && run->noisy &&
        estimate_direct_set_noise(*sim, run->seed, o->placement_noise_m, o->pose_noise_m) != 0) {
      snprintf(err, sizeof err, "noise out of range");
      rc = 2;
    }
  }
  if (rc != 0) {
    LOG_E("%s: %s", rock->path, err);
    estimate_direct_close(*sim);
    estimate_lcm_close(*lcmb);
    *sim = NULL;
    *lcmb = NULL;
  }
  return rc;
}

/* The estimator's result and the recorded trials into run. Returns 0, or 1 out of memory. */
static int run_record(const estimate_result_t *res, const recorder_t *rec, exp_run_t *run) {
  snprintf(run->note, sizeof run->note, "%s", res->msg);
  run->trials = res->trial_count;
  run->stable_trials = res->stable_trials;
  run->flagged_trials = res->flagged_trials;
  run->nsearch = res->search_count;
  for (size_t i = 0; i < res->search_count; ++i) run->search_trials[i] = res->search[i].trials;
  for (int k = 0; k < 3; ++k) {
    run->found[k] = run->status == ESTIMATE_OK && res->found[k];
    run->com_m[k] = res->com_m[k];
    run->halfwidth_m[k] = run->found[k] ? res->halfwidth_m[k] : INFINITY;
    run->error_m[k] = NAN;
  }
  run->nsteps = rec->n;
  run->steps = malloc((rec->n ? rec->n : 1) * sizeof *run->steps);
  if (!run->steps) {
    LOG_E("out of memory");
    return 1;
  }
  memcpy(run->steps, rec->step, rec->n * sizeof *run->steps);
  return 0;
}

/* Run one estimate. Returns 0 (the run is recorded, even when the estimator gave up: status),
 * 1 runtime failure of the machinery (backend could not open, out of memory), 2 bad input. */
static int run_one(const exp_opts_t *o, const exp_rock_t *rock, const model_object_t *obj,
                   recorder_t *rec, estimate_result_t *res, exp_run_t *run) {
  estimate_config_t cfg;
  run_config(o, run, &cfg);
  estimate_direct_t *sim = NULL;
  estimate_lcm_t *lcmb = NULL;
  estimate_backend_t inner;
  const int rc = run_backend_open(o, rock, obj, run, &sim, &lcmb, &inner);
  if (rc != 0) return rc;
  run->backend = inner.name;
  rec->inner = &inner;
  rec->n = 0;
  estimate_backend_t deco = inner;
  deco.ctx = rec;
  deco.run = recorder_run;

  double t0 = cli_time_now_s();
  run->status = estimate_run(&obj->mesh, &deco, &cfg, res);
  run->wall_s = cli_time_now_s() - t0;
  if (lcmb && run->status == ESTIMATE_OK &&
      estimate_lcm_publish_estimate(lcmb, res, cfg.resolution_m, 1) != 0)
    LOG_W("publishing COM_ESTIMATE failed");
  estimate_direct_close(sim);
  estimate_lcm_close(lcmb);

  if (run_record(res, rec, run) != 0) return 1;
  if (run->status == ESTIMATE_E_BACKEND || run->status == ESTIMATE_E_NOMEM) {
    LOG_E("%s: %s: %s", rock->path, estimate_status_str(run->status), res->msg);
    return 1;
  }
  return 0;
}

/* ---- statistics ----------------------------------------------------------------------------- */

typedef struct {
  size_t runs, failed;
  size_t comps, found, errs; /* components asked, found, found with a truth to compare */
  double err_sum, err_sq, err_max;
  double *err;    /* |error| of each found component (for the 95th percentile) */
  size_t covered; /* found components whose |error| <= reported half width */
  double hw_sum;
  double trials_sum, trials_sq;
  double wall_sum;
} exp_stats_t;

static int dbl_cmp(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return x < y ? -1 : x > y ? 1 : 0;
}

/* Stats of the runs of one policy and kind; only_uniform:
 * only rocks with uniform density. err must hold 3 * nruns values. */
static void stats_of(const exp_run_t *runs, size_t nruns, const exp_rock_t *rocks,
                     qlearn_policy_kind_t policy, run_kind_t kind, int only_uniform, double *err,
                     exp_stats_t *st) {
  memset(st, 0, sizeof *st);
  st->err = err;
  for (size_t i = 0; i < nruns; ++i) {
    const exp_run_t *r = &runs[i];
    if (r->policy != policy || r->kind != kind) continue;
    if (only_uniform && !rocks[r->rock].uniform_density) continue;
    ++st->runs;
    if (r->status != ESTIMATE_OK) ++st->failed;
    st->trials_sum += (double)r->trials;
    st->trials_sq += (double)r->trials * (double)r->trials;
    st->wall_sum += r->wall_s;
    for (int k = 0; k < 3; ++k) {
      ++st->comps;
      if (!r->found[k]) continue;
      ++st->found;
      if (!isfinite(r->error_m[k])) continue;
      double e = fabs(r->error_m[k]);
      st->err[st->errs++] = e;
      st->err_sum += e;
      st->err_sq += e * e;
      if (e > st->err_max) st->err_max = e;
      st->hw_sum += r->halfwidth_m[k];
      if (e <= r->halfwidth_m[k]) ++st->covered;
    }
  }
  qsort(st->err, st->errs, sizeof *st->err, dbl_cmp);
}

static double mean_of(double sum, size_t n) { return n ? sum / (double)n : NAN; }
static double sd_of(double sum, double sq, size_t n) {
  if (n < 2) return n ? 0.0 : NAN;
  double m = sum / (double)n, v = (sq - (double)n * m * m) / (double)(n - 1);
  return v > 0.0 ? sqrt(v) : 0.0;
}
/* Nearest-rank percentile of sorted values. */
static double pct_of(const double *v, size_t n, double p) {
  if (!n) return NAN;
  size_t r = (size_t)ceil(p * (double)n);
  if (r < 1) r = 1;
  if (r > n) r = n;
  return v[r - 1];
}

/* ---- the table (markdown) -------------------------------------------------------------------- */

static void md_mm(FILE *f, double v_m, int digits) {
  if (isfinite(v_m))
    fprintf(f, " %.*f |", digits, 1e3 * v_m);
  else
    fprintf(f, " N/A |");
}

/* The Table I run of object ri with policy, or NULL. */
static const exp_run_t *table_run_of(const exp_run_t *runs, size_t nruns, size_t ri,
                                     qlearn_policy_kind_t policy) {
  for (size_t i = 0; i < nruns; ++i)
    if (runs[i].rock == ri && runs[i].policy == policy && runs[i].kind == RUN_TABLE)
      return &runs[i];
  return NULL;
}

/* One cell pair of Table I: row k of a run (k < 3: CoM component and |error|; 3: trials). */
static void table_cell(FILE *f, const exp_rock_t *rk, const exp_run_t *r, int k) {
  if (!r) {
    fprintf(f, " | |");
  } else if (k == 3) {
    fprintf(f, " %zu (", r->trials);
    for (size_t i = 0; i < r->nsearch; ++i) fprintf(f, "%s%u", i ? "+" : "", r->search_trials[i]);
    fprintf(f, " + %zu) | %s |", r->stable_trials,
            r->status == ESTIMATE_OK ? "" : estimate_status_str(r->status));
  } else {
    md_mm(f, r->found[k] ? r->com_m[k] - rk->bbox_center_m[k] : NAN, 2);
    md_mm(f, r->found[k] ? fabs(r->error_m[k]) : NAN, 3);
  }
}

/* Table I: per object the true CoM and, per policy, the learned one, its |error| and trials. */
static void table_noiseless(FILE *f, const exp_opts_t *o, const exp_rock_t *rocks, size_t nrocks,
                            const exp_run_t *runs, size_t nruns) {
  const char *backend = o->lcm_url ? "LCM (YuMi placement, comlearn-sim)" : "direct (in-process)";
  fprintf(f, "## Table I: noiseless, %s\n\n", backend);
  fprintf(f,
          "Every policy starts where the paper starts: at the bounding-box center (state 0). "
          "CoM in mm relative to the bounding-box center (the paper's reference); learned value, "
          "|error| against the URDF <inertial>. N/A: the component was not found. `trials`: "
          "every placement of the run (edge trials of each search + stable-pose checks); the "
          "searches run along oblique directions of the object, so a component's trials are "
          "not separable.\n\n");
  fprintf(f, "| object | axis | true |");
  for (int p = 0; p < o->npolicies; ++p)
    fprintf(f, " %s | \\|err\\| |", estimate_policy_name(o->policy[p]));
  fprintf(f, "\n|---|---|---:|");
  for (int p = 0; p < o->npolicies; ++p) fprintf(f, "---:|---:|");
  fprintf(f, "\n");
  for (size_t ri = 0; ri < nrocks; ++ri) {
    const exp_rock_t *rk = &rocks[ri];
    for (int k = 0; k <= 3; ++k) {
      if (k < 3) {
        fprintf(f, "| %s | %c |", rk->stem, "xyz"[k]);
        md_mm(f, rk->have_truth ? rk->truth_m[k] - rk->bbox_center_m[k] : NAN, 2);
      } else {
        fprintf(f, "| %s | trials | |", rk->stem);
      }
      for (int p = 0; p < o->npolicies; ++p)
        table_cell(f, rk, table_run_of(runs, nruns, ri, o->policy[p]), k);
      fprintf(f, "\n");
    }
  }
}

/* The noiseless summary: per start, density class and policy; the paper's row last. */
static void table_summary(FILE *f, const exp_opts_t *o, const exp_rock_t *rocks,
                          const exp_run_t *runs, size_t nruns, double *scratch) {
  fprintf(f, "\n### Summary, noiseless\n\n");
  fprintf(f,
          "| policy | start | objects | mean \\|err\\| (mm) | max \\|err\\| (mm) | found | "
          "coverage | trials per object (mean) | wall per object (s) |\n"
          "|---|---|---|---:|---:|---:|---:|---:|---:|\n");
  for (int kind = RUN_TABLE; kind <= RUN_PRIOR; ++kind) {
    for (int pass = 0; pass < 2; ++pass) {
      for (int p = 0; p < o->npolicies; ++p) {
        exp_stats_t st;
        stats_of(runs, nruns, rocks, o->policy[p], (run_kind_t)kind, pass, scratch, &st);
        if (!st.runs) continue;
        fprintf(f, "| %s | %s | %s%zu | %.3f | %.3f | %zu of %zu | %zu of %zu | %.1f | %.3f |\n",
                estimate_policy_name(o->policy[p]),
                kind == RUN_TABLE ? "bounding-box center (paper)" : "mesh prior (uniform CoM)",
                pass ? "uniform-density: " : "all: ", st.runs, 1e3 * mean_of(st.err_sum, st.errs),
                1e3 * st.err_max, st.found, st.comps, st.covered, st.errs,
                mean_of(st.trials_sum, st.runs), mean_of(st.wall_sum, st.runs));
      }
    }
  }
  fprintf(f,
          "| paper (McGovern et al., Table I; Gazebo + ODE + YuMi) | bounding-box center | "
          "even: %d | %.1f | %.1f (min %.1f) | %d of %d (%d N/A) | no intervals | not given | "
          "not given |\n",
          PAPER_ROCKS, PAPER_ERR_MEAN_MM, PAPER_ERR_MAX_MM, PAPER_ERR_MIN_MM,
          PAPER_COMPONENTS - PAPER_NA, PAPER_COMPONENTS, PAPER_NA);
  fprintf(f,
          "\nThe paper's numbers are its summary as docs/design.md states it (\"What is being "
          "reproduced\"; per-cell values are not given there). `uniform-density`: objects whose "
          "true CoM is within 1 um of the "
          "mesh's uniform-density CoM, like the paper's even rocks. `mesh prior`: the same "
          "runs started at the mesh's uniform-density CoM, which is the truth for an even "
          "object (so a walk from there needs few trials): information the paper does not "
          "use. Coverage: found components whose |error| is within the reported bound.\n");
}

/* The noisy runs (o->seeds > 0): per policy over objects x seeds, and the targets. */
static void table_noisy(FILE *f, const exp_opts_t *o, const exp_rock_t *rocks,
                        const exp_run_t *runs, size_t nruns, double *scratch) {
  fprintf(
      f,
      "\n## With noise: placement %.3g mm, pose %.3g mm (std. dev.), seeds 1..%d, in-process\n\n",
      1e3 * o->placement_noise_m, 1e3 * o->pose_noise_m, o->seeds);
  fprintf(f,
          "Over objects x seeds per policy. |err| statistics over the found components; "
          "coverage: fraction of found components whose |error| is within the reported half "
          "width. Every policy is told the noise model (probit outcomes, sigma = the placement "
          "noise) and reports 95 %% intervals: bisect and the paper walks hand over to PBA "
          "after their walk; searches first stop at a 95 %% interval max(R, sigma, 2 T) wide, "
          "then the one that widens a component most goes on until every component's half "
          "width is at most T (the target). Started at the bounding-box center.\n\n");
  fprintf(f,
          "| policy | runs | target T (mm) | mean \\|err\\| +- sd (mm) | p95 \\|err\\| (mm) | "
          "worst (mm) | found | mean half width (mm) | coverage | trials per object | "
          "failed runs |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (int p = 0; p < o->npolicies; ++p) {
    exp_stats_t st;
    stats_of(runs, nruns, rocks, o->policy[p], RUN_NOISY, 0, scratch, &st);
    if (!st.runs) continue;
    estimate_config_t dc;
    estimate_config_default(&dc);
    const double res = dc.noise_target_halfwidth_m;
    fprintf(
        f,
        "| %s | %zu | %.3g | %.3f +- %.3f | %.3f | %.3f | %.0f %% (%zu of %zu) | %.3f | "
        "%.0f %% (%zu of %zu) | %.1f +- %.1f | %zu |\n",
        estimate_policy_name(o->policy[p]), st.runs, 1e3 * res, 1e3 * mean_of(st.err_sum, st.errs),
        1e3 * sd_of(st.err_sum, st.err_sq, st.errs), 1e3 * pct_of(st.err, st.errs, 0.95),
        1e3 * st.err_max, st.comps ? 100.0 * (double)st.found / (double)st.comps : 0.0, st.found,
        st.comps, 1e3 * mean_of(st.hw_sum, st.errs),
        st.errs ? 100.0 * (double)st.covered / (double)st.errs : 0.0, st.covered, st.errs,
        mean_of(st.trials_sum, st.runs), sd_of(st.trials_sum, st.trials_sq, st.runs), st.failed);
  }
  fprintf(f,
          "\nTargets (docs/design.md, \"Targets and where they stand\"): 95 %% of errors "
          "<= 1 mm; the reported 95 %% intervals contain the truth >= 90 %% of the time "
          "(second wave: >= 95 %%).\n");
}

static void write_table(FILE *f, const exp_opts_t *o, const exp_rock_t *rocks, size_t nrocks,
                        const exp_run_t *runs, size_t nruns, double *scratch, double wall_s) {
  fprintf(f, "# comlearn experiments\n\n");
  fprintf(f, "%zu objects, policies:", nrocks);
  for (int p = 0; p < o->npolicies; ++p)
    fprintf(f, "%s %s", p ? "," : "", estimate_policy_name(o->policy[p]));
  fprintf(f, "; resolution %.3g mm; %.1f s wall.\n\n", 1e3 * o->resolution_m, wall_s);
  table_noiseless(f, o, rocks, nrocks, runs, nruns);
  table_summary(f, o, rocks, runs, nruns, scratch);
  if (o->seeds > 0) table_noisy(f, o, rocks, runs, nruns, scratch);
}

/* ---- JSON ------------------------------------------------------------------------------------ */

static void js_vec(FILE *f, const char *key, const double v[3]) {
  fprintf(f, "\"%s\": ", key);
  cli_json_array(f, v, 3);
}

static void js_stats(FILE *f, const exp_stats_t *st) {
  fprintf(f,
          "{\"runs\": %zu, \"failed_runs\": %zu, \"components\": %zu, \"found\": %zu, "
          "\"mean_abs_error_m\": ",
          st->runs, st->failed, st->comps, st->found);
  cli_json_number(f, mean_of(st->err_sum, st->errs));
  fputs(", \"sd_abs_error_m\": ", f);
  cli_json_number(f, sd_of(st->err_sum, st->err_sq, st->errs));
  fputs(", \"p95_abs_error_m\": ", f);
  cli_json_number(f, pct_of(st->err, st->errs, 0.95));
  fputs(", \"max_abs_error_m\": ", f);
  cli_json_number(f, st->errs ? st->err_max : NAN);
  fputs(", \"mean_halfwidth_m\": ", f);
  cli_json_number(f, mean_of(st->hw_sum, st->errs));
  fputs(", \"coverage\": ", f);
  cli_json_number(f, st->errs ? (double)st->covered / (double)st->errs : NAN);
  fputs(", \"mean_trials\": ", f);
  cli_json_number(f, mean_of(st->trials_sum, st->runs));
  fputs(", \"sd_trials\": ", f);
  cli_json_number(f, sd_of(st->trials_sum, st->trials_sq, st->runs));
  fputs(", \"mean_wall_s\": ", f);
  cli_json_number(f, mean_of(st->wall_sum, st->runs));
  fputc('}', f);
}

/* "settings", "wall_s" and "paper", from the opening brace. */
static void json_head(FILE *f, const exp_opts_t *o, double wall_s) {
  fprintf(f, "{\"settings\": {\"policies\": [");
  for (int p = 0; p < o->npolicies; ++p) {
    if (p) fputs(", ", f);
    cli_json_string(f, estimate_policy_name(o->policy[p]), 0);
  }
  fprintf(f, "], \"seeds\": %d, \"placement_noise_m\": ", o->seeds);
  cli_json_number(f, o->placement_noise_m);
  fputs(", \"pose_noise_m\": ", f);
  cli_json_number(f, o->pose_noise_m);
  fputs(", \"resolution_m\": ", f);
  cli_json_number(f, o->resolution_m);
  fputs(", \"noiseless_backend\": ", f);
  cli_json_string(f, o->lcm_url ? "lcm" : "direct", 0);
  fputs(", \"lcm_url\": ", f);
  if (o->lcm_url)
    cli_json_string(f, o->lcm_url, 0);
  else
    fputs("null", f);
  fprintf(f,
          "}, \"wall_s\": %.3f, \"paper\": {\"rocks\": %d, \"components\": %d, \"not_found\": %d, "
          "\"min_abs_error_m\": %.4g, \"max_abs_error_m\": %.4g, \"mean_abs_error_m\": %.4g, "
          "\"source\": \"McGovern, Mao & Xiao, IROS 2019, Table I (summary in docs/design.md, "
          "What is being reproduced)\"}",
          wall_s, PAPER_ROCKS, PAPER_COMPONENTS, PAPER_NA, 1e-3 * PAPER_ERR_MIN_MM,
          1e-3 * PAPER_ERR_MAX_MM, 1e-3 * PAPER_ERR_MEAN_MM);
}

/* ", \"objects\": [...]". */
static void json_objects(FILE *f, const exp_rock_t *rocks, size_t nrocks) {
  fputs(", \"objects\": [", f);
  for (size_t i = 0; i < nrocks; ++i) {
    const exp_rock_t *r = &rocks[i];
    fprintf(f, "%s{\"name\": ", i ? ", " : "");
    cli_json_string(f, r->stem, 0);
    fputs(", \"urdf\": ", f);
    cli_json_string(f, r->path, 0);
    fputs(", ", f);
    js_vec(f, "bbox_center_m", r->bbox_center_m);
    fputs(", ", f);
    js_vec(f, "uniform_com_m", r->uniform_com_m);
    fputs(", ", f);
    const double none[3] = {NAN, NAN, NAN};
    js_vec(f, "truth_m", r->have_truth ? r->truth_m : none);
    fprintf(f, ", \"uniform_density\": %s}", r->uniform_density ? "true" : "false");
  }
  fputc(']', f);
}

/* ", \"summary\": [...]": the stats of every kind and policy that ran. */
static void json_summary(FILE *f, const exp_opts_t *o, const exp_rock_t *rocks,
                         const exp_run_t *runs, size_t nruns, double *scratch) {
  fputs(", \"summary\": [", f);
  int first = 1;
  for (int kind = RUN_TABLE; kind <= RUN_NOISY; ++kind)
    for (int p = 0; p < o->npolicies; ++p) {
      exp_stats_t st;
      stats_of(runs, nruns, rocks, o->policy[p], (run_kind_t)kind, 0, scratch, &st);
      if (!st.runs) continue;
      fprintf(f, "%s{\"policy\": \"%s\", \"noisy\": %s, \"start\": \"%s\", \"stats\": ",
              first ? "" : ", ", estimate_policy_name(o->policy[p]),
              kind == RUN_NOISY ? "true" : "false", kind == RUN_PRIOR ? "uniform" : "bbox");
      js_stats(f, &st);
      fputc('}', f);
      first = 0;
    }
  fputc(']', f);
}

static const char *outcome_name(int oc) {
  return oc == BALANCE_STAYS     ? "stays"
         : oc == BALANCE_TIPS    ? "tips"
         : oc == BALANCE_SLIDES  ? "slides"
         : oc == BALANCE_INVALID ? "invalid"
                                 : "failed";
}

/* The run's "trace" object: one entry per recorded trial in each array. */
static void json_trace(FILE *f, const exp_run_t *r) {
  fputs("{\"kind\": [", f);
  for (size_t t = 0; t < r->nsteps; ++t)
    fprintf(f, "%s%s", t ? ", " : "",
            r->steps[t].kind == ESTIMATE_TRIAL_STABLE ? "\"stable\"" : "\"edge\"");
  fputs("], \"component\": [", f);
  for (size_t t = 0; t < r->nsteps; ++t) fprintf(f, "%s%d", t ? ", " : "", r->steps[t].component);
  fputs("], \"outcome\": [", f);
  for (size_t t = 0; t < r->nsteps; ++t)
    fprintf(f, "%s\"%s\"", t ? ", " : "", outcome_name(r->steps[t].outcome));
  fputs("], \"com_before_m\": [", f);
  for (size_t t = 0; t < r->nsteps; ++t) {
    if (t) fputs(", ", f);
    cli_json_array(f, r->steps[t].com_before_m, 3);
  }
  fputs("], \"target_link_m\": [", f);
  for (size_t t = 0; t < r->nsteps; ++t) {
    if (t) fputs(", ", f);
    cli_json_array(f, r->steps[t].target_link_m, 3);
  }
  fputs("], \"halfwidth_before_m\": [", f);
  for (size_t t = 0; t < r->nsteps; ++t) {
    if (t) fputs(", ", f);
    cli_json_array(f, r->steps[t].halfwidth_before_m, 3);
  }
  fputs("]}", f);
}

/* One run's object, its trace included. */
static void json_run(FILE *f, const exp_opts_t *o, const exp_rock_t *rocks, const exp_run_t *r) {
  fputs("{\"object\": ", f);
  cli_json_string(f, rocks[r->rock].stem, 0);
  fprintf(f, ", \"policy\": \"%s\", \"noisy\": %s, \"start\": \"%s\", \"seed\": ",
          estimate_policy_name(r->policy), r->noisy ? "true" : "false",
          r->kind == RUN_PRIOR ? "uniform" : "bbox");
  if (r->noisy)
    fprintf(f, "%llu", (unsigned long long)r->seed);
  else
    fputs("null", f);
  fputs(", \"placement_noise_m\": ", f);
  cli_json_number(f, r->noisy ? o->placement_noise_m : 0.0);
  fputs(", \"pose_noise_m\": ", f);
  cli_json_number(f, r->noisy ? o->pose_noise_m : 0.0);
  fputs(", \"backend\": ", f);
  cli_json_string(f, r->backend, 0);
  fputs(", \"resolution_m\": ", f);
  cli_json_number(f, r->resolution_m);
  fputs(", \"noise_sigma_m\": ", f);
  cli_json_number(f, r->noise_sigma_m);
  fputs(", \"status\": ", f);
  cli_json_string(f, estimate_status_str(r->status), 0);
  fputs(", \"note\": ", f);
  cli_json_string(f, r->note, 0);
  fprintf(f,
          ", \"trials\": %zu, \"stable_trials\": %zu, \"flagged_trials\": %zu, "
          "\"search_trials\": [",
          r->trials, r->stable_trials, r->flagged_trials);
  for (size_t t = 0; t < r->nsearch; ++t) fprintf(f, "%s%u", t ? ", " : "", r->search_trials[t]);
  fputs("], ", f);
  js_vec(f, "com_m", r->com_m);
  fputs(", ", f);
  js_vec(f, "halfwidth_m", r->halfwidth_m);
  fprintf(f, ", \"found\": [%s, %s, %s], ", r->found[0] ? "true" : "false",
          r->found[1] ? "true" : "false", r->found[2] ? "true" : "false");
  const double none[3] = {NAN, NAN, NAN};
  js_vec(f, "truth_m", rocks[r->rock].have_truth ? rocks[r->rock].truth_m : none);
  fputs(", ", f);
  js_vec(f, "error_m", r->error_m);
  fprintf(f, ", \"wall_s\": %.6f, \"trace\": ", r->wall_s);
  json_trace(f, r);
  fputc('}', f);
}

static void write_json(FILE *f, const exp_opts_t *o, const exp_rock_t *rocks, size_t nrocks,
                       const exp_run_t *runs, size_t nruns, double *scratch, double wall_s) {
  json_head(f, o, wall_s);
  json_objects(f, rocks, nrocks);
  json_summary(f, o, rocks, runs, nruns, scratch);
  fputs(", \"runs\": [", f);
  for (size_t i = 0; i < nruns; ++i) {
    fputs(i ? ",\n" : "\n", f);
    json_run(f, o, rocks, &runs[i]);
  }
  fputs("\n]}\n", f);
}

/* ---- Fig. 2 ---------------------------------------------------------------------------------- */

static int write_fig2(const char *path, const exp_opts_t *o, const exp_rock_t *rock, size_t ri,
                      const exp_run_t *runs, size_t nruns) {
  experiments_svg_series_t ser[MAX_POLICIES];
  double *vals[MAX_POLICIES][3] = {{NULL}};
  char labels[MAX_POLICIES][96];
  size_t ns = 0;
  int rc = 0;
  for (int p = 0; p < o->npolicies && rc == 0; ++p) {
    const exp_run_t *r = table_run_of(runs, nruns, ri, o->policy[p]);
    if (!r) continue;
    size_t n = r->nsteps + 1;
    for (int k = 0; k < 3; ++k) {
      vals[ns][k] = malloc(n * sizeof(double));
      if (!vals[ns][k]) rc = -1;
    }
    if (rc) {
      ++ns;
      break;
    }
    for (int k = 0; k < 3; ++k) {
      for (size_t t = 0; t < r->nsteps; ++t) {
        const exp_step_t *st = &r->steps[t];
        const double *v = st->kind == ESTIMATE_TRIAL_EDGE ? st->target_link_m : st->com_before_m;
        vals[ns][k][t] = 1e3 * (v[k] - rock->bbox_center_m[k]);
      }
      /* the final estimate; a component not found is drawn as what the estimator reports */
      vals[ns][k][r->nsteps] =
          r->status == ESTIMATE_OK ? 1e3 * (r->com_m[k] - rock->bbox_center_m[k]) : NAN;
      ser[ns].value_mm[k] = vals[ns][k];
    }
    snprintf(labels[ns], sizeof labels[ns], "%s (%zu trials)", estimate_policy_name(r->policy),
             r->trials);
    ser[ns].label = labels[ns];
    ser[ns].name = estimate_policy_name(r->policy);
    ser[ns].n = n;
    ++ns;
  }
  if (rc == 0) {
    double truth_mm[3];
    for (int k = 0; k < 3; ++k)
      truth_mm[k] = rock->have_truth ? 1e3 * (rock->truth_m[k] - rock->bbox_center_m[k]) : NAN;
    char title[256];
    snprintf(title, sizeof title,
             "%s: CoM estimate per trial (point placed over the edge; mm from the bbox center), "
             "noiseless",
             rock->stem);
    FILE *f = fopen(path, "w");
    if (!f) {
      LOG_E("%s: %s", path, strerror(errno));
      rc = -1;
    } else {
      rc = experiments_svg_fig2(f, title, truth_mm, ns, ser);
      if (fclose(f) != 0) rc = -1;
      if (rc) LOG_E("%s: write failed", path);
    }
  } else {
    LOG_E("out of memory");
  }
  for (size_t s = 0; s < ns; ++s)
    for (int k = 0; k < 3; ++k) free(vals[s][k]);
  return rc;
}

/* ---- the noisy runs as a plot ---------------------------------------------------------------- */

/* DIR/noisy.svg: every noisy run's error and 95 % half width per component, in the order of the
 * JSON's runs (object, policy, seed). Returns 0, or -1 (logged). */
static int write_noisy(const char *path, const exp_opts_t *o, const exp_rock_t *rocks,
                       const exp_run_t *runs, size_t nruns) {
  experiments_svg_interval_t *rows = malloc((nruns ? nruns : 1) * sizeof *rows);
  if (!rows) {
    LOG_E("out of memory");
    return -1;
  }
  const char *names[MAX_POLICIES];
  for (int p = 0; p < o->npolicies; ++p) names[p] = estimate_policy_name(o->policy[p]);
  size_t n = 0;
  for (size_t i = 0; i < nruns; ++i) {
    const exp_run_t *r = &runs[i];
    if (r->kind != RUN_NOISY) continue;
    experiments_svg_interval_t *w = &rows[n++];
    w->group = rocks[r->rock].stem;
    w->series = 0;
    for (int p = 0; p < o->npolicies; ++p)
      if (o->policy[p] == r->policy) w->series = (size_t)p;
    for (int k = 0; k < 3; ++k) {
      w->found[k] = r->found[k];
      w->error_mm[k] = 1e3 * r->error_m[k];
      w->halfwidth_mm[k] = 1e3 * r->halfwidth_m[k];
    }
  }
  char title[256];
  snprintf(title, sizeof title,
           "Noisy runs (placement %.3g mm, pose %.3g mm, seeds 1..%d): error and 95 %% interval "
           "per component, one row per run",
           1e3 * o->placement_noise_m, 1e3 * o->pose_noise_m, o->seeds);
  int rc = -1;
  FILE *f = fopen(path, "w");
  if (f) {
    rc = experiments_svg_intervals(f, title, names, (size_t)o->npolicies, rows, n);
    if (fclose(f) != 0) rc = -1;
  }
  if (rc) LOG_E("%s: %s", path, f ? "write failed" : strerror(errno));
  free(rows);
  return rc;
}

/* ---- the command ----------------------------------------------------------------------------- */

static int write_file(const char *dir, const char *name, int json, const exp_opts_t *o,
                      const exp_rock_t *rocks, size_t nrocks, const exp_run_t *runs, size_t nruns,
                      double *scratch, double wall_s) {
  char path[4096];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  FILE *f = fopen(path, "w");
  if (!f) {
    LOG_E("%s: %s", path, strerror(errno));
    return -1;
  }
  if (json)
    write_json(f, o, rocks, nrocks, runs, nruns, scratch, wall_s);
  else
    write_table(f, o, rocks, nrocks, runs, nruns, scratch, wall_s);
  int bad = ferror(f);
  if (fclose(f) != 0 || bad) {
    LOG_E("%s: write failed", path);
    return -1;
  }
  return 0;
}

/* --seeds: an integer in [0, MAX_SEEDS], or -1 with a message. */
static int parse_seeds(const char *arg, int *out) {
  char *end;
  errno = 0;
  long v = strtol(arg, &end, 10);
  if (end == arg || *end != '\0' || errno != 0 || v < 0 || v > MAX_SEEDS) {
    LOG_E("--seeds: '%s' is not an integer in [0, %d]", arg, MAX_SEEDS);
    return -1;
  }
  *out = (int)v;
  return 0;
}

/* Options into o (defaults as usage() says). Returns -1 to go on, else the exit status (0 after
 * --help, EXIT_USAGE). */
static int parse_args(int argc, char **argv, exp_opts_t *o) {
  static const struct option opts[] = {{"policies", required_argument, NULL, 'P'},
                                       {"seeds", required_argument, NULL, 'S'},
                                       {"placement-noise-mm", required_argument, NULL, 'n'},
                                       {"pose-noise-mm", required_argument, NULL, 'N'},
                                       {"resolution-mm", required_argument, NULL, 'r'},
                                       {"lcm-url", required_argument, NULL, 'u'},
                                       {"sims", required_argument, NULL, 's'},
                                       {"direct", no_argument, NULL, 'd'},
                                       {"out", required_argument, NULL, 'o'},
                                       {"json", no_argument, NULL, 'j'},
                                       {"verbose", no_argument, NULL, 'v'},
                                       {"quiet", no_argument, NULL, 'q'},
                                       {"help", no_argument, NULL, 'h'},
                                       {"version", no_argument, NULL, 'V'},
                                       {NULL, 0, NULL, 0}};
  memset(o, 0, sizeof *o);
  o->npolicies = MAX_POLICIES;
  memcpy(o->policy, all_policies, sizeof all_policies);
  o->seeds = 5;
  o->placement_noise_m = 0.5e-3;
  o->pose_noise_m = 0.2e-3;
  o->resolution_m = 1e-4;
  int c;
  double mm;
  optind = 1;
  opterr = 0;
  while ((c = getopt_long(argc, argv, "vqhV", opts, NULL)) != -1) {
    switch (c) {
      case 'P':
        if (parse_policies(optarg, o) != 0) return EXIT_USAGE;
        break;
      case 'S':
        if (parse_seeds(optarg, &o->seeds) != 0) return EXIT_USAGE;
        break;
      case 'n':
        if (parse_mm("--placement-noise-mm", optarg, 0.0, 100.0, &mm) != 0) return EXIT_USAGE;
        o->placement_noise_m = 1e-3 * mm;
        break;
      case 'N':
        if (parse_mm("--pose-noise-mm", optarg, 0.0, 100.0, &mm) != 0) return EXIT_USAGE;
        o->pose_noise_m = 1e-3 * mm;
        break;
      case 'r':
        if (parse_mm("--resolution-mm", optarg, 0.001, 10.0, &mm) != 0) return EXIT_USAGE;
        o->resolution_m = 1e-3 * mm;
        break;
      case 'u':
        if (!optarg[0]) {
          LOG_E("--lcm-url: empty URL");
          return EXIT_USAGE;
        }
        o->lcm_url = optarg;
        break;
      case 's': {
        char *end = NULL;
        const long n = strtol(optarg, &end, 10);
        if (end == optarg || *end != '\0' || n < 1 || n > MAX_SIMS) {
          LOG_E("--sims: '%s' is not an integer in [1, %d]", optarg, MAX_SIMS);
          return EXIT_USAGE;
        }
        o->sims = (int)n;
        break;
      }
      case 'o':
        if (!optarg[0]) {
          LOG_E("--out: empty directory name");
          return EXIT_USAGE;
        }
        o->out_dir = optarg;
        break;
      case 'j': o->json = 1; break;
      case 'd': o->direct = 1; break;
      case 'v': cli_log_set_level(CLI_LOG_DEBUG); break;
      case 'q':
        o->quiet = 1;
        cli_log_set_level(CLI_LOG_ERROR);
        break;
      case 'h': usage(stdout); return EXIT_SUCCESS;
      case 'V': cli_version_print(stdout, "comlearn"); return EXIT_SUCCESS;
      default: cli_getopt_complain("comlearn experiments", "vqhV", opts, argv); return EXIT_USAGE;
    }
  }
  if (o->direct && (o->lcm_url || o->sims)) {
    LOG_E("--direct and %s exclude each other (in-process, or over LCM)",
          o->lcm_url ? "--lcm-url" : "--sims");
    return EXIT_USAGE;
  }
  return -1;
}

/* Every file first, geometry only: a typo fails at once, not after minutes of runs. Then the
 * --out directory. Returns an exit status. */
static int inputs_check(char *const *paths, size_t n, const char *out_dir) {
  for (size_t i = 0; i < n; ++i) {
    model_error_t merr = {{0}};
    model_object_t obj = {0};
    model_status_t ms = model_object_load(paths[i], NULL, &obj, &merr);
    model_object_free(&obj);
    if (ms != MODEL_OK) {
      LOG_E("%s (%s)", merr.msg[0] ? merr.msg : paths[i], model_status_str(ms));
      return ms == MODEL_E_NOMEM ? EXIT_FAILURE : EXIT_USAGE;
    }
  }
  if (out_dir && mkdir(out_dir, 0777) != 0 && errno != EEXIST) {
    LOG_E("--out: cannot create '%s': %s", out_dir, strerror(errno));
    return EXIT_FAILURE;
  }
  return EXIT_SUCCESS;
}

/* This process's runs (all of them, or a --sims worker's share), for the progress lines. */
static cli_progress_t progress;

/* Progress lines go to stderr when it is a terminal or with --verbose, never with --quiet. */
static int progress_shown(const exp_opts_t *o) {
  return !o->quiet && (isatty(STDERR_FILENO) || cli_log_enabled(CLI_LOG_DEBUG));
}

/* The progress line of one run on stderr: the worker's robot with --sims, the run's count and the
 * time left. s: -1 mesh prior, 0 noiseless, else the noise seed. */
static void progress_line(const exp_opts_t *o, const exp_rock_t *rk, const exp_run_t *run, int s) {
  char what[32], count[64];
  cli_progress_step(&progress, count, sizeof count);
  if (!progress_shown(o)) return;
  if (run->noisy)
    snprintf(what, sizeof what, "seed %d", s);
  else
    snprintf(what, sizeof what, s < 0 ? "mesh prior" : "noiseless");
  int all = run->found[0] && run->found[1] && run->found[2];
  fprintf(stderr, "comlearn experiments: %s%-16s %-12s %-9s %3zu trials  %.3f s  %s%s  [%s]\n",
          o->channel_prefix ? o->channel_prefix : "", rk->stem, estimate_policy_name(run->policy),
          what, run->trials, run->wall_s, estimate_status_str(run->status),
          all ? "" : " (not all found)", count);
}

/* The truth, read after this object's estimates are final, for the report only: the errors of
 * runs[0..nruns). No truth is a warning, not a failure. */
static void truth_compare(exp_rock_t *rk, exp_run_t *runs, size_t nruns) {
  model_error_t merr = {{0}};
  model_mass_t tm;
  model_status_t ms = model_inertial_load(rk->path, NULL, &tm, &merr);
  if (ms != MODEL_OK) {
    LOG_W("%s: no truth to compare with: %s (%s)", rk->path, merr.msg, model_status_str(ms));
    return;
  }
  rk->have_truth = 1;
  memcpy(rk->truth_m, tm.com_m, sizeof rk->truth_m);
  double d = 0.0;
  for (int k = 0; k < 3; ++k) d = fmax(d, fabs(tm.com_m[k] - rk->uniform_com_m[k]));
  rk->uniform_density = d <= 1e-6;
  for (size_t i = 0; i < nruns; ++i)
    for (int k = 0; k < 3; ++k)
      runs[i].error_m[k] = runs[i].found[k] ? runs[i].com_m[k] - tm.com_m[k] : NAN;
}

/* The runs rock_runs makes of one object: per policy the mesh prior, Table I and the seeds. */
static size_t runs_per_object(const exp_opts_t *o) {
  return (size_t)o->npolicies * (2 + (size_t)o->seeds);
}

/* Every run of one object: per policy the mesh prior (s = -1), Table I (s = 0) and the noisy
 * seeds, appended at runs[*nruns]. Returns an exit status. */
static int rock_runs(const exp_opts_t *o, exp_rock_t *rk, size_t ri, recorder_t *rec,
                     estimate_result_t *res, exp_run_t *runs, size_t *nruns) {
  stem_of(rk->path, rk->stem, sizeof rk->stem);
  model_error_t merr = {{0}};
  model_object_t obj = {0};
  model_status_t ms = model_object_load(rk->path, NULL, &obj, &merr);
  if (ms != MODEL_OK) {
    LOG_E("%s (%s)", merr.msg[0] ? merr.msg : rk->path, model_status_str(ms));
    return ms == MODEL_E_NOMEM ? EXIT_FAILURE : EXIT_USAGE;
  }
  model_aabb_center(&obj.aabb, rk->bbox_center_m);
  const size_t first_run = *nruns;
  int rc = EXIT_SUCCESS;
  for (int p = 0; p < o->npolicies && rc == EXIT_SUCCESS; ++p) {
    for (int s = -1; s <= o->seeds && rc == EXIT_SUCCESS; ++s) {
      exp_run_t *run = &runs[(*nruns)++];
      run->rock = ri;
      run->policy = o->policy[p];
      run->kind = s < 0 ? RUN_PRIOR : s == 0 ? RUN_TABLE : RUN_NOISY;
      run->noisy = s > 0;
      run->seed = (uint64_t)(s > 0 ? s : 0);
      rc = run_one(o, rk, &obj, rec, res, run);
      if (rc != 0) break;
      if (s == 0) memcpy(rk->uniform_com_m, res->uniform_com_m, sizeof rk->uniform_com_m);
      progress_line(o, rk, run, s);
    }
  }
  model_object_free(&obj);
  truth_compare(rk, runs + first_run, *nruns - first_run);
  return rc;
}

/* The report on stdout, then with --out the table, the JSON, one Fig. 2 per object and the noisy
 * plot there.
 * Returns an exit status. */
static int report_write(const exp_opts_t *o, const exp_rock_t *rocks, size_t nrocks,
                        const exp_run_t *runs, size_t nruns, double *scratch, double wall) {
  if (o->json)
    write_json(stdout, o, rocks, nrocks, runs, nruns, scratch, wall);
  else
    write_table(stdout, o, rocks, nrocks, runs, nruns, scratch, wall);
  fflush(stdout);
  if (!o->out_dir) return EXIT_SUCCESS;
  int rc = EXIT_SUCCESS;
  if (write_file(o->out_dir, "table.md", 0, o, rocks, nrocks, runs, nruns, scratch, wall) ||
      write_file(o->out_dir, "experiments.json", 1, o, rocks, nrocks, runs, nruns, scratch, wall))
    rc = EXIT_FAILURE;
  for (size_t ri = 0; ri < nrocks && rc == EXIT_SUCCESS; ++ri) {
    char path[4096];
    snprintf(path, sizeof path, "%s/fig2_%s.svg", o->out_dir, rocks[ri].stem);
    if (write_fig2(path, o, &rocks[ri], ri, runs, nruns) != 0) rc = EXIT_FAILURE;
  }
  char path[4096];
  snprintf(path, sizeof path, "%s/noisy.svg", o->out_dir);
  if (rc == EXIT_SUCCESS && o->seeds > 0 && write_noisy(path, o, rocks, runs, nruns) != 0)
    rc = EXIT_FAILURE;
  return rc;
}

/* ---- --sims: worker processes, one comlearn-sim each ------------------------------------------
 */

/* What a worker sends back for one object, in its scratch file: the index, the object's record,
 * the number of runs, then each run followed by its steps. The pointers inside (the URDF path,
 * the backend name) point into argv and the program's constants, the same in parent and child. */
static int record_write(FILE *f, size_t ri, const exp_rock_t *rk, const exp_run_t *runs, size_t n) {
  int ok = fwrite(&ri, sizeof ri, 1, f) == 1 && fwrite(rk, sizeof *rk, 1, f) == 1 &&
           fwrite(&n, sizeof n, 1, f) == 1;
  for (size_t i = 0; i < n && ok; ++i)
    ok = fwrite(&runs[i], sizeof runs[i], 1, f) == 1 &&
         fwrite(runs[i].steps, sizeof *runs[i].steps, runs[i].nsteps, f) == runs[i].nsteps;
  return ok ? 0 : -1;
}

/* One object's record into rocks[ri] and by_rock[ri] (n_rock[ri] runs, steps on the heap).
 * Returns 1 read, 0 at the end of the file, -1 on a short or impossible record. */
static int record_read(FILE *f, size_t nrocks, exp_rock_t *rocks, exp_run_t **by_rock,
                       size_t *n_rock, size_t max_runs) {
  size_t ri = 0, n = 0;
  if (fread(&ri, sizeof ri, 1, f) != 1) return 0;
  exp_rock_t rk;
  if (ri >= nrocks || by_rock[ri] || fread(&rk, sizeof rk, 1, f) != 1 ||
      fread(&n, sizeof n, 1, f) != 1 || n > max_runs)
    return -1;
  exp_run_t *runs = calloc(n ? n : 1, sizeof *runs);
  if (!runs) return -1;
  by_rock[ri] = runs;
  for (size_t i = 0; i < n; ++i) {
    if (fread(&runs[i], sizeof runs[i], 1, f) != 1 || runs[i].nsteps > ESTIMATE_MAX_TRIALS) {
      runs[i].steps = NULL;
      n_rock[ri] = i;
      return -1;
    }
    runs[i].steps = malloc((runs[i].nsteps ? runs[i].nsteps : 1) * sizeof *runs[i].steps);
    if (!runs[i].steps ||
        fread(runs[i].steps, sizeof *runs[i].steps, runs[i].nsteps, f) != runs[i].nsteps) {
      n_rock[ri] = i + 1;
      return -1;
    }
  }
  n_rock[ri] = n;
  rk.path = rocks[ri].path;
  rocks[ri] = rk;
  return 1;
}

/* The folders a worker's sim may read: each object's folder and the bundled assets (as
 * `estimate --spawn-sim`). dirs gets at most cap - 1 of them and a NULL. Returns 0, or -1 when
 * an object cannot be resolved or there are too many folders. */
static int worker_dirs(char *const *paths, size_t nrocks, int w, int nw, char (*store)[4096],
                       const char **dirs, size_t cap) {
  size_t n = 0;
  for (size_t ri = (size_t)w; ri < nrocks; ri += (size_t)nw) {
    char dir[4096];
    if (realpath(paths[ri], dir) == NULL) return -1;
    *strrchr(dir, '/') = '\0';
    if (!dir[0]) snprintf(dir, sizeof dir, "/");
    int seen = 0;
    for (size_t k = 0; k < n && !seen; ++k) seen = strcmp(store[k], dir) == 0;
    if (seen) continue;
    if (n + 2 >= cap) return -1;
    snprintf(store[n], sizeof store[n], "%s", dir);
    dirs[n] = store[n];
    ++n;
  }
  dirs[n++] = cli_paths_assets_dir();
  dirs[n] = NULL;
  return 0;
}

/* Worker w of nw (a forked child): a comlearn-sim with prefix R<w>_ on url, then every object
 * ri with ri % nw == w as the serial loop runs it, each record into out. Exits with the status
 * the serial loop would have returned. */
static void sims_worker(int w, int nw, exp_opts_t o, char *const *paths, size_t nrocks,
                        const char *url, FILE *out) {
  char prefix[16], err[512] = "";
  snprintf(prefix, sizeof prefix, "R%d_", w);
  enum { DIRS_CAP = 16 };
  static char store[DIRS_CAP][4096];
  const char *dirs[DIRS_CAP];
  if (worker_dirs(paths, nrocks, w, nw, store, dirs, DIRS_CAP) != 0) {
    LOG_E("--sims: the objects of worker %d lie in more than %d folders", w, DIRS_CAP - 2);
    _exit(EXIT_USAGE);
  }
  const char *exe = getenv("COMLEARN_SIM");
  if (!exe || !exe[0]) exe = cli_paths_sim_exe();
  const pid_t sim = estimate_lcm_sim_spawn(exe, url, prefix, dirs, err, sizeof err);
  if (sim < 0) {
    LOG_E("--sims: %s", err);
    _exit(EXIT_FAILURE);
  }
  o.lcm_url = url;
  o.channel_prefix = prefix;
  const size_t per_rock = runs_per_object(&o);
  exp_run_t *runs = calloc(per_rock, sizeof *runs);
  recorder_t *rec = malloc(sizeof *rec);
  estimate_result_t *res = malloc(sizeof *res);
  int rc = runs && rec && res ? EXIT_SUCCESS : EXIT_FAILURE;
  const size_t mine = (size_t)w < nrocks ? (nrocks - (size_t)w + (size_t)nw - 1) / (size_t)nw : 0;
  cli_progress_start(&progress, per_rock * mine); /* objects w, w + nw, ... */
  for (size_t ri = (size_t)w; ri < nrocks && rc == EXIT_SUCCESS; ri += (size_t)nw) {
    exp_rock_t rk = {.path = paths[ri]};
    size_t n = 0;
    rc = rock_runs(&o, &rk, ri, rec, res, runs, &n);
    if (rc == EXIT_SUCCESS && record_write(out, ri, &rk, runs, n) != 0) rc = EXIT_FAILURE;
    for (size_t i = 0; i < n; ++i) free(runs[i].steps);
  }
  if (fflush(out) != 0) rc = EXIT_FAILURE;
  estimate_lcm_sim_stop(sim, 2.0);
  free(runs);
  free(rec);
  free(res);
  _exit(rc);
}

/* --sims: fork the workers on url, wait for them, and gather their objects and runs into rocks and
 * runs in the serial order (object by object). Returns an exit status (the first worker's that
 * failed). */
static int sims_run(const exp_opts_t *o, const char *url, char *const *paths, size_t nrocks,
                    exp_rock_t *rocks, exp_run_t *runs, size_t *nruns) {
  const int nw = o->sims < (int)nrocks ? o->sims : (int)nrocks;
  LOG_I("%d comlearn-sims on %s (channel prefixes R0_ ..), one worker each", nw, url);
  FILE *out[MAX_SIMS] = {NULL};
  pid_t pid[MAX_SIMS];
  int rc = EXIT_SUCCESS;
  fflush(stdout);
  fflush(stderr);
  for (int w = 0; w < nw && rc == EXIT_SUCCESS; ++w) {
    out[w] = tmpfile();
    pid[w] = out[w] ? fork() : -1;
    if (pid[w] == 0) sims_worker(w, nw, *o, paths, nrocks, url, out[w]);
    if (pid[w] < 0) {
      LOG_E("--sims: %s", strerror(errno));
      rc = EXIT_FAILURE;
    }
  }
  for (int w = 0; w < nw; ++w) {
    int ws = 0;
    if (out[w] && pid[w] > 0 && waitpid(pid[w], &ws, 0) == pid[w]) {
      const int st = WIFEXITED(ws) ? WEXITSTATUS(ws) : EXIT_FAILURE;
      if (rc == EXIT_SUCCESS) rc = st;
    }
  }
  exp_run_t **by_rock = calloc(nrocks, sizeof *by_rock);
  size_t *n_rock = calloc(nrocks, sizeof *n_rock);
  if (!by_rock || !n_rock) rc = EXIT_FAILURE;
  const size_t per_rock = runs_per_object(o);
  for (int w = 0; w < nw; ++w) {
    if (!out[w]) continue;
    rewind(out[w]);
    int r;
    while (rc == EXIT_SUCCESS &&
           (r = record_read(out[w], nrocks, rocks, by_rock, n_rock, per_rock)) != 0)
      if (r < 0) {
        LOG_E("--sims: worker %d's results are unreadable", w);
        rc = EXIT_FAILURE;
      }
    fclose(out[w]);
  }
  for (size_t ri = 0; ri < nrocks && by_rock && n_rock; ++ri) {
    if (rc == EXIT_SUCCESS && !by_rock[ri]) {
      LOG_E("--sims: no results for %s", paths[ri]);
      rc = EXIT_FAILURE;
    }
    for (size_t i = 0; i < n_rock[ri]; ++i) {
      if (rc == EXIT_SUCCESS)
        runs[(*nruns)++] = by_rock[ri][i];
      else
        free(by_rock[ri][i].steps);
    }
    free(by_rock[ri]);
  }
  free(by_rock);
  free(n_rock);
  return rc;
}

int cmd_experiments(int argc, char **argv) {
  exp_opts_t o;
  const int prc = parse_args(argc, argv, &o);
  if (prc >= 0) return prc;
  if (optind >= argc) {
    LOG_E("experiments needs at least one OBJECT.urdf");
    usage(stderr);
    return EXIT_USAGE;
  }
  const size_t nrocks = (size_t)(argc - optind);
  char *const *paths = argv + optind;
  int rc = inputs_check(paths, nrocks, o.out_dir);
  if (rc != EXIT_SUCCESS) return rc;

  const size_t cap = nrocks * runs_per_object(&o);
  exp_rock_t *rocks = calloc(nrocks, sizeof *rocks);
  exp_run_t *runs = calloc(cap, sizeof *runs);
  double *scratch = malloc(3 * cap * sizeof *scratch);
  recorder_t *rec = malloc(sizeof *rec);
  estimate_result_t *res = malloc(sizeof *res);
  size_t nruns = 0;
  const double t_all = cli_time_now_s();
  if (!rocks || !runs || !scratch || !rec || !res) {
    LOG_E("out of memory");
    rc = EXIT_FAILURE;
  }
  for (size_t ri = 0; ri < nrocks; ++ri) rocks[ri].path = paths[ri];
  char sims_url[128]; /* --sims without --lcm-url: a port of this process's own */
  if (o.sims > 0 && !o.lcm_url) {
    snprintf(sims_url, sizeof sims_url, "udpm://239.255.76.67:%u?ttl=0",
             7700u + (unsigned)getpid() % 1000u);
    o.lcm_url = sims_url; /* the noiseless runs go over LCM, and the report says where */
  }
  if (rc == EXIT_SUCCESS && o.sims > 0)
    rc = sims_run(&o, o.lcm_url, paths, nrocks, rocks, runs, &nruns);
  if (o.sims == 0) cli_progress_start(&progress, runs_per_object(&o) * nrocks);
  for (size_t ri = 0; ri < nrocks && rc == EXIT_SUCCESS && o.sims == 0; ++ri)
    rc = rock_runs(&o, &rocks[ri], ri, rec, res, runs, &nruns);
  const double wall = cli_time_now_s() - t_all;
  if (rc == EXIT_SUCCESS) {
    rc = report_write(&o, rocks, nrocks, runs, nruns, scratch, wall);
    LOG_I("%zu runs in %.1f s", nruns, wall);
  }
  if (runs)
    for (size_t i = 0; i < nruns; ++i) free(runs[i].steps);
  free(runs);
  free(rocks);
  free(scratch);
  free(rec);
  free(res);
  return rc;
}
