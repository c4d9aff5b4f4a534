#define _POSIX_C_SOURCE 200809L
/* check_experiments: the noisy direct backend (comlearn-sim's seeding, the held pose reported as
 * released, zero noise = the old backend), PBA's noise model in the estimator, and
 * `comlearn experiments` as a user runs it: JSON, table, SVG and exit codes. */
#include <check.h>
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli_test_util.h"
#include "comlearn/balance.h"
#include "comlearn/model.h"
#include "comlearn/model_inertial.h"
#include "estimate_backend.h"
#include "estimate_direct.h"
#include "experiments_svg.h"
#include "file_test_util.h"

static char tmpdir[256];

static void setup(void) {
  snprintf(tmpdir, sizeof tmpdir, "/tmp/check_experiments.XXXXXX");
  ck_assert_ptr_nonnull(mkdtemp(tmpdir));
}

static void teardown(void) {
  char cmd[512];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
  ck_assert_int_eq(system(cmd), 0);
}

static void rock_path(const char *name, char *out, size_t size) {
  snprintf(out, size, "%s/rocks/%s.urdf", COMLEARN_ASSETS_DIR, name);
}

/* ---- a recording backend: every request and reply of a run ---- */

typedef struct {
  estimate_backend_t inner;
  size_t n;
  estimate_trial_request_t req[ESTIMATE_MAX_TRIALS];
  estimate_trial_reply_t rep[ESTIMATE_MAX_TRIALS];
} tape_t;

static int tape_run(void *ctx, const estimate_trial_request_t *req, estimate_trial_reply_t *reply,
                    char *err, size_t err_size) {
  tape_t *t = ctx;
  int rc = t->inner.run(t->inner.ctx, req, reply, err, err_size);
  if (rc == 0 && t->n < ESTIMATE_MAX_TRIALS) {
    t->req[t->n] = *req;
    t->rep[t->n] = *reply;
    ++t->n;
  }
  return rc;
}

/* Estimate urdf on a direct backend (noise set when placement or pose > 0, or force_set), every
 * trial taped. */
static void run_direct(const char *urdf, qlearn_policy_kind_t policy, double res_m, double sigma_m,
                       int force_set, uint64_t seed, double placement_m, double pose_m,
                       tape_t *tape, estimate_result_t *res) {
  model_object_t obj = {0};
  model_error_t err = {{0}};
  ck_assert_msg(model_object_load(urdf, NULL, &obj, &err) == MODEL_OK, "%s", err.msg);
  estimate_direct_t *sim = NULL;
  char msg[512] = "";
  ck_assert_msg(estimate_direct_open(urdf, NULL, NULL, &sim, &tape->inner, msg, sizeof msg) == 0,
                "%s", msg);
  if (force_set || placement_m > 0 || pose_m > 0)
    ck_assert_int_eq(estimate_direct_set_noise(sim, seed, placement_m, pose_m), 0);
  tape->n = 0;
  estimate_backend_t b = tape->inner;
  b.ctx = tape;
  b.run = tape_run;
  estimate_config_t cfg;
  estimate_config_default(&cfg);
  cfg.policy = policy;
  cfg.resolution_m = res_m;
  cfg.noise_sigma_m = sigma_m;
  estimate_status_t s = estimate_run(&obj.mesh, &b, &cfg, res);
  ck_assert_msg(s == ESTIMATE_OK, "%s: %s: %s", urdf, estimate_status_str(s), res->msg);
  ck_assert_uint_eq(tape->n, res->trial_count);
  ck_assert_uint_eq(estimate_direct_trial_count(sim), res->trial_count);
  estimate_direct_close(sim);
  model_object_free(&obj);
}

static int pose_eq(const model_pose_t *a, const model_pose_t *b) {
  return memcmp(a, b, sizeof *a) == 0;
}

/* Same seed, same requests: the same replies, bit for bit; the released pose is the requested
 * (held) one; outcome and settled pose are lib/balance's with comlearn-sim's per-trial seed. */
START_TEST(noise_seeding_and_held_pose) {
  char urdf[512];
  rock_path("rock_1_uneven", urdf, sizeof urdf);
  tape_t *a = malloc(sizeof *a), *b = malloc(sizeof *b);
  estimate_result_t *ra = malloc(sizeof *ra), *rb = malloc(sizeof *rb);
  ck_assert(a && b && ra && rb);
  const uint64_t seed = 7;
  const double pn = 0.5e-3, qn = 0.2e-3;
  run_direct(urdf, QLEARN_POLICY_BISECT, 1e-4, 0.0, 0, seed, pn, qn, a, ra);
  run_direct(urdf, QLEARN_POLICY_BISECT, 1e-4, 0.0, 0, seed, pn, qn, b, rb);
  ck_assert_uint_eq(a->n, b->n);
  for (size_t i = 0; i < a->n; ++i) {
    ck_assert(pose_eq(&a->req[i].release, &b->req[i].release));
    ck_assert_int_eq(a->rep[i].outcome, b->rep[i].outcome);
    ck_assert(pose_eq(&a->rep[i].settled, &b->rep[i].settled));
    /* held: the reported release is exactly the request */
    ck_assert(pose_eq(&a->rep[i].released, &a->req[i].release));
  }

  /* Replay the taped requests on lib/balance with seed ^ (K * (i + 1)) (daemon/sim.c). */
  model_object_t obj = {0};
  model_mass_t truth;
  ck_assert_int_eq(model_object_load(urdf, NULL, &obj, NULL), MODEL_OK);
  ck_assert_int_eq(model_inertial_load(urdf, NULL, &truth, NULL), MODEL_OK);
  balance_config_t bc;
  balance_config_default(&bc);
  balance_world_t *w = NULL;
  balance_object_t *o = NULL;
  ck_assert_int_eq(balance_world_create(&bc, &w), BALANCE_OK);
  ck_assert_int_eq(balance_object_create(w, &obj.mesh, &truth, &o), BALANCE_OK);
  size_t offset_seen = 0;
  for (size_t i = 0; i < a->n; ++i) {
    balance_noise_t nz = {balance_noise_seed(seed, (uint64_t)i + 1), pn, qn};
    balance_trial_result_t r;
    ck_assert_int_eq(balance_trial_run(w, o, &a->req[i].release, &nz, &r), BALANCE_OK);
    ck_assert_msg((int)r.outcome == (int)a->rep[i].outcome, "trial %zu: outcome %d vs %d", i,
                  (int)r.outcome, (int)a->rep[i].outcome);
    ck_assert(pose_eq(&r.settled, &a->rep[i].settled));
    /* the offset the backend hides: horizontal, of the order of the placement noise */
    double dx = r.released.position_m[0] - a->req[i].release.position_m[0];
    double dy = r.released.position_m[1] - a->req[i].release.position_m[1];
    ck_assert_double_eq(r.released.position_m[2], a->req[i].release.position_m[2]);
    ck_assert(hypot(dx, dy) < 8.0 * pn);
    if (hypot(dx, dy) > 1e-6) ++offset_seen;
  }
  ck_assert_uint_ge(offset_seen, a->n - 1);
  balance_world_destroy(w);
  model_object_free(&obj);

  /* another seed: other draws, so somewhere another settled pose */
  run_direct(urdf, QLEARN_POLICY_BISECT, 1e-4, 0.0, 0, seed + 1, pn, qn, b, rb);
  int differ = b->n != a->n;
  for (size_t i = 0; i < a->n && i < b->n && !differ; ++i)
    differ = !pose_eq(&a->rep[i].settled, &b->rep[i].settled);
  ck_assert(differ);
  free(a);
  free(b);
  free(ra);
  free(rb);
}
END_TEST

/* Zero noise set explicitly is the old noiseless backend, trial by trial. */
START_TEST(zero_noise_is_noiseless) {
  char urdf[512];
  rock_path("rock_2_even", urdf, sizeof urdf);
  tape_t *a = malloc(sizeof *a), *b = malloc(sizeof *b);
  estimate_result_t *ra = malloc(sizeof *ra), *rb = malloc(sizeof *rb);
  ck_assert(a && b && ra && rb);
  run_direct(urdf, QLEARN_POLICY_BISECT, 1e-4, 0.0, 0, 0, 0.0, 0.0, a, ra);
  run_direct(urdf, QLEARN_POLICY_BISECT, 1e-4, 0.0, 1, 12345, 0.0, 0.0, b, rb);
  ck_assert_uint_eq(a->n, b->n);
  for (size_t i = 0; i < a->n; ++i) {
    ck_assert(pose_eq(&a->req[i].release, &b->req[i].release));
    ck_assert_int_eq(a->rep[i].outcome, b->rep[i].outcome);
    ck_assert(pose_eq(&a->rep[i].released, &b->rep[i].released));
    ck_assert(pose_eq(&a->rep[i].settled, &b->rep[i].settled));
  }
  ck_assert(memcmp(ra->com_m, rb->com_m, sizeof ra->com_m) == 0);
  free(a);
  free(b);
  free(ra);
  free(rb);
}
END_TEST

START_TEST(noise_arguments_checked) {
  char urdf[512];
  rock_path("rock_1_even", urdf, sizeof urdf);
  estimate_direct_t *sim = NULL;
  estimate_backend_t be;
  char msg[256];
  ck_assert_int_eq(estimate_direct_open(urdf, NULL, NULL, &sim, &be, msg, sizeof msg), 0);
  ck_assert_int_eq(estimate_direct_set_noise(NULL, 1, 0.0, 0.0), -1);
  ck_assert_int_eq(estimate_direct_set_noise(sim, 1, NAN, 0.0), -1);
  ck_assert_int_eq(estimate_direct_set_noise(sim, 1, 0.0, INFINITY), -1);
  ck_assert_int_eq(estimate_direct_set_noise(sim, 1, -1e-4, 0.0), -1);
  ck_assert_int_eq(estimate_direct_set_noise(sim, 1, 0.0, 0.2), -1);
  ck_assert_int_eq(estimate_direct_set_noise(sim, 1, 0.1, 0.1), 0);
  estimate_direct_close(sim);

  /* the estimator refuses a bad noise sigma before any trial */
  model_object_t obj = {0};
  ck_assert_int_eq(model_object_load(urdf, NULL, &obj, NULL), MODEL_OK);
  ck_assert_int_eq(estimate_direct_open(urdf, NULL, NULL, &sim, &be, msg, sizeof msg), 0);
  estimate_result_t *r = malloc(sizeof *r);
  ck_assert_ptr_nonnull(r);
  estimate_config_t cfg;
  estimate_config_default(&cfg);
  ck_assert_double_eq(cfg.noise_sigma_m, 0.0);
  const double bad[] = {-1e-4, NAN, 0.2};
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
    cfg.noise_sigma_m = bad[i];
    ck_assert_int_eq(estimate_run(&obj.mesh, &be, &cfg, r), ESTIMATE_E_ARG);
    ck_assert_uint_eq(r->trial_count, 0);
  }
  free(r);
  estimate_direct_close(sim);
  model_object_free(&obj);
}
END_TEST

/* PBA told the noise (probit, sigma = placement noise) at resolution = sigma: every component
 * found, within 1 mm, and the reported half widths are honest (the truth inside). */
START_TEST(pba_under_noise) {
  char urdf[512];
  rock_path("rock_1_uneven", urdf, sizeof urdf);
  tape_t *a = malloc(sizeof *a);
  estimate_result_t *r = malloc(sizeof *r);
  ck_assert(a && r);
  run_direct(urdf, QLEARN_POLICY_PBA, 0.5e-3, 0.5e-3, 0, 3, 0.5e-3, 0.2e-3, a, r);
  model_mass_t truth;
  ck_assert_int_eq(model_inertial_load(urdf, NULL, &truth, NULL), MODEL_OK);
  for (int k = 0; k < 3; ++k) {
    ck_assert_msg(r->found[k], "component %d not found (%s)", k, r->msg);
    double e = fabs(r->com_m[k] - truth.com_m[k]);
    ck_assert_msg(e <= 1e-3, "component %d: %.3f mm off", k, 1e3 * e);
    ck_assert_msg(e <= r->halfwidth_m[k], "component %d: %.3f mm off, +-%.3f mm reported", k,
                  1e3 * e, 1e3 * r->halfwidth_m[k]);
  }
  /* the running estimate before each trial is recorded in the request */
  ck_assert(isinf(a->req[0].halfwidth_before_m[0]));
  ck_assert_double_eq(a->req[0].com_before_m[0], r->uniform_com_m[0]);
  ck_assert_uint_lt(r->trial_count, 3 * 256);
  free(a);
  free(r);
}
END_TEST

/* ---- a minimal JSON syntax check (the tests must not trust a hand-written writer) ---- */

static const char *js_ws(const char *p) {
  while (*p == ' ' || *p == '\n' || *p == '\t' || *p == '\r') ++p;
  return p;
}

static const char *js_value(const char *p, int depth);

static const char *js_string(const char *p) {
  if (*p != '"') return NULL;
  for (++p; *p && *p != '"'; ++p) {
    if ((unsigned char)*p < 0x20) return NULL;
    if (*p == '\\') {
      ++p;
      if (*p == 'u') {
        for (int i = 1; i <= 4; ++i)
          if (!isxdigit((unsigned char)p[i])) return NULL;
        p += 4;
      } else if (!strchr("\"\\/bfnrt", *p) || !*p) {
        return NULL;
      }
    }
  }
  return *p == '"' ? p + 1 : NULL;
}

static const char *js_value(const char *p, int depth) {
  if (depth > 64) return NULL;
  p = js_ws(p);
  if (*p == '{' || *p == '[') {
    char close = *p == '{' ? '}' : ']';
    int obj = *p == '{';
    p = js_ws(p + 1);
    if (*p == close) return p + 1;
    for (;;) {
      if (obj) {
        p = js_string(js_ws(p));
        if (!p) return NULL;
        p = js_ws(p);
        if (*p++ != ':') return NULL;
      }
      p = js_value(p, depth + 1);
      if (!p) return NULL;
      p = js_ws(p);
      if (*p == ',') {
        ++p;
        continue;
      }
      return *p == close ? p + 1 : NULL;
    }
  }
  if (*p == '"') return js_string(p);
  if (strncmp(p, "true", 4) == 0) return p + 4;
  if (strncmp(p, "false", 5) == 0) return p + 5;
  if (strncmp(p, "null", 4) == 0) return p + 4;
  char *end;
  strtod(p, &end);
  return end == p ? NULL : end;
}

static size_t count_of(const char *hay, const char *needle) {
  size_t n = 0;
  for (const char *p = strstr(hay, needle); p; p = strstr(p + 1, needle)) ++n;
  return n;
}

/* Two rocks, bisect and paper-qtable; per rock and policy Table I (bbox start), the mesh-prior
 * row and one noisy seed: 2 x 2 x 3 runs. */
START_TEST(cli_experiments_outputs) {
  static char out[1 << 16];
  char cmd[2048], dir[512], r1[512], r2[512];
  snprintf(dir, sizeof dir, "%s/out", tmpdir);
  rock_path("rock_1_uneven", r1, sizeof r1);
  rock_path("rock_3_even", r2, sizeof r2);
  snprintf(cmd, sizeof cmd,
           "'%s' experiments '%s' '%s' --seeds 1 --policies bisect,paper-qtable --out '%s' -q",
           COMLEARN_BIN, r1, r2, dir);
  ck_assert_int_eq(run(cmd, out, sizeof out), 0);
  /* stdout: the table with the paper's row */
  ck_assert_ptr_nonnull(strstr(out, "## Table I: noiseless"));
  ck_assert_ptr_nonnull(strstr(out, "| paper (McGovern et al., Table I"));
  ck_assert_ptr_nonnull(strstr(out, "| 1.5 | 4.4 (min 0.1) | 7 of 9 (2 N/A) |"));
  ck_assert_ptr_nonnull(strstr(out, "## With noise: placement 0.5 mm, pose 0.2 mm"));
  ck_assert_ptr_nonnull(strstr(out, "| rock_1_uneven | x |"));

  char path[1024];
  snprintf(path, sizeof path, "%s/table.md", dir);
  char *table = test_slurp(path, NULL);
  ck_assert_ptr_nonnull(strstr(table, "| paper (McGovern et al., Table I"));
  free(table);

  snprintf(path, sizeof path, "%s/experiments.json", dir);
  char *js = test_slurp(path, NULL);
  const char *end = js_value(js, 0);
  ck_assert_msg(end != NULL, "experiments.json does not parse");
  ck_assert_msg(*js_ws(end) == '\0', "trailing bytes after the JSON");
  ck_assert_uint_eq(count_of(js, "{\"object\": "), 12);
  ck_assert_uint_eq(count_of(js, "\"noisy\": false, \"start\": \"bbox\", \"seed\": null"), 4);
  ck_assert_uint_eq(count_of(js, "\"noisy\": false, \"start\": \"uniform\", \"seed\": null"), 4);
  ck_assert_uint_eq(count_of(js, "\"noisy\": true, \"start\": \"bbox\", \"seed\": 1"), 4);
  ck_assert_uint_eq(count_of(js, "\"com_before_m\": [["), 12);
  /* noisy runs are told the noise model: every policy's noise_sigma_m is the placement noise */
  ck_assert_uint_eq(count_of(js, "\"noise_sigma_m\": 0.0005,"), 4);
  /* bisect, noiseless: <= 0.2 mm against the URDF truth, which the JSON reports correctly */
  const char *const names[2] = {"rock_1_uneven", "rock_3_even"};
  const char *const paths[2] = {r1, r2};
  for (int i = 0; i < 2; ++i) {
    char pat[256];
    snprintf(pat, sizeof pat,
             "{\"object\": \"%s\", \"policy\": \"bisect\", \"noisy\": false, \"start\": \"bbox\"",
             names[i]);
    const char *p = strstr(js, pat);
    ck_assert_msg(p != NULL, "no noiseless bisect run of %s", names[i]);
    double truth[3], err[3], com[3];
    json_vec(p, "truth_m", truth);
    json_vec(p, "error_m", err);
    json_vec(p, "com_m", com);
    model_mass_t t;
    ck_assert_int_eq(model_inertial_load(paths[i], NULL, &t, NULL), MODEL_OK);
    for (int k = 0; k < 3; ++k) {
      ck_assert_double_eq_tol(truth[k], t.com_m[k], 1e-9);
      ck_assert_double_eq_tol(err[k], com[k] - t.com_m[k], 1e-9);
      ck_assert_msg(fabs(err[k]) <= 2e-4, "%s %c: %.4f mm", names[i], "xyz"[k], 1e3 * err[k]);
    }
    ck_assert_ptr_nonnull(strstr(p, "\"found\": [true, true, true]"));
    ck_assert_ptr_nonnull(strstr(p, "\"backend\": \"direct\""));
  }
  free(js);

  for (int i = 0; i < 2; ++i) {
    size_t n = 0;
    snprintf(path, sizeof path, "%s/fig2_%s.svg", dir, names[i]);
    char *svg = test_slurp(path, &n);
    ck_assert_uint_lt(n, 100 * 1024);
    ck_assert_ptr_nonnull(strstr(svg, "<svg xmlns=\"http://www.w3.org/2000/svg\""));
    ck_assert_ptr_nonnull(strstr(svg, "</svg>"));
    /* a line per policy per panel, and the dashed truth in each panel */
    ck_assert_uint_eq(count_of(svg, "<polyline"), 2 * 3);
    ck_assert_uint_eq(count_of(svg, "stroke-dasharray=\"6 4\"/>\n"), 3);
    ck_assert_ptr_nonnull(strstr(svg, "bisect ("));
    ck_assert_ptr_nonnull(strstr(svg, "paper-qtable ("));
    free(svg);
  }
}
END_TEST

/* ---- reading the figures back: the SVG's own axis mapping, the JSON's numbers ---- */

/* The number in attribute name="..." of the element text at p (up to its '>'). */
static double svg_attr(const char *p, const char *name) {
  char pat[64];
  snprintf(pat, sizeof pat, " %s=\"", name);
  const char *end = strchr(p, '>');
  const char *a = strstr(p, pat);
  ck_assert_msg(a != NULL && (!end || a < end), "no %s in %.80s", name, p);
  return strtod(a + strlen(pat), NULL);
}

/* A JSON number or null (NAN) at p; *next after it. */
static double js_num_or_null(const char *p, const char **next) {
  p = js_ws(p);
  if (strncmp(p, "null", 4) == 0) {
    *next = p + 4;
    return NAN;
  }
  char *end;
  const double v = strtod(p, &end);
  ck_assert_msg(end != p, "not a number: %.40s", p);
  *next = end;
  return v;
}

/* The three numbers (or nulls) of "key": [a, b, c] after p. */
static void js_vec3(const char *p, const char *key, double v[3]) {
  char pat[64];
  snprintf(pat, sizeof pat, "\"%s\": [", key);
  const char *q = strstr(p, pat);
  ck_assert_msg(q != NULL, "no %s", key);
  q += strlen(pat);
  for (int k = 0; k < 3; ++k) {
    v[k] = js_num_or_null(q, &q);
    q = js_ws(q);
    if (*q == ',') ++q;
  }
}

/* "key": [[a, b, c], ...] after p into out (at most cap); returns the count. */
static size_t js_triples(const char *p, const char *key, double (*out)[3], size_t cap) {
  char pat[64];
  snprintf(pat, sizeof pat, "\"%s\": [", key);
  const char *q = strstr(p, pat);
  ck_assert_msg(q != NULL, "no %s", key);
  q = js_ws(q + strlen(pat));
  size_t n = 0;
  while (*q == '[') {
    ck_assert_uint_lt(n, cap);
    ++q;
    for (int k = 0; k < 3; ++k) {
      out[n][k] = js_num_or_null(q, &q);
      q = js_ws(q);
      if (*q == ',') ++q;
    }
    ck_assert_int_eq(*q, ']');
    ++n;
    q = js_ws(q + 1);
    if (*q == ',') q = js_ws(q + 1);
  }
  return n;
}

/* The JSON run of object, policy, noiseless Table I (seed 0) or noisy seed s. */
static const char *js_run(const char *js, const char *object, const char *policy, int seed) {
  char pat[256];
  if (seed == 0)
    snprintf(pat, sizeof pat,
             "{\"object\": \"%s\", \"policy\": \"%s\", \"noisy\": false, \"start\": \"bbox\"",
             object, policy);
  else
    snprintf(pat, sizeof pat,
             "{\"object\": \"%s\", \"policy\": \"%s\", \"noisy\": true, \"start\": \"bbox\", "
             "\"seed\": %d,",
             object, policy, seed);
  const char *p = strstr(js, pat);
  ck_assert_msg(p != NULL, "no run %s", pat);
  return p;
}

/* The k-th <g class="panel" of an SVG (k from 0). */
static const char *svg_panel(const char *svg, int k) {
  const char *p = svg;
  for (int i = 0; i <= k; ++i) {
    p = strstr(i ? p + 1 : p, "<g class=\"panel\"");
    ck_assert_ptr_nonnull(p);
  }
  return p;
}

enum { FIG_POLICIES = 4 };
static const char *const fig_policy[FIG_POLICIES] = {"paper-qtable", "paper-mlp", "bisect", "pba"};

/* The trial axis's end as experiments_svg.h states the rule, from the series' point counts:
 * the longest, unless it is more than 1.5 x the second longest + 5; then 1.25 x the second
 * longest, up to a multiple of 5. *cut: the index of the run cut there, else -1. */
static size_t axis_end(size_t nseries, const size_t *points, int *cut) {
  size_t l1 = 0, l2 = 0;
  int longest = -1;
  for (size_t p = 0; p < nseries; ++p) {
    if (points[p] > l1) {
      l2 = l1;
      l1 = points[p];
      longest = (int)p;
    } else if (points[p] > l2) {
      l2 = points[p];
    }
  }
  *cut = -1;
  if (nseries < 2 || 2.0 * (double)l1 <= 1.5 * 2.0 * (double)l2 + 10.0) return l1;
  *cut = longest;
  return (size_t)(5.0 * ceil(1.25 * (double)l2 / 5.0));
}

/* Fig. 2 of rock_1_uneven read back: per panel and policy a polyline with its own colour and dash
 * pattern whose step points are the JSON trace (edge trials: the point set over the edge; stable
 * checks: the running estimate; last: the final estimate; mm from the bbox center), the trial
 * axis ending as axis_end says (a cut run's note saying where it goes on). */
static void check_fig2(const char *svg, const char *js, const char *object) {
  const char *obj = strstr(js, "\"objects\": [");
  ck_assert_ptr_nonnull(obj);
  char pat[128];
  snprintf(pat, sizeof pat, "{\"name\": \"%s\"", object);
  obj = strstr(obj, pat);
  ck_assert_ptr_nonnull(obj);
  double bbox[3];
  js_vec3(obj, "bbox_center_m", bbox);
  static double target[ESTIMATE_MAX_TRIALS][3], before[ESTIMATE_MAX_TRIALS][3];
  size_t trials[FIG_POLICIES], points[FIG_POLICIES];
  for (int p = 0; p < FIG_POLICIES; ++p) {
    trials[p] = (size_t)json_num(js_run(js, object, fig_policy[p], 0), "trials");
    points[p] = trials[p] + 1;
  }
  int cut = -1;
  const size_t end = axis_end(FIG_POLICIES, points, &cut);
  /* Noiseless, no run here is long enough to be cut (PBA's 114 trials were, until noiseless PBA
   * ran on the step likelihood): svg_trial_axis_cut checks the cut */
  ck_assert_int_eq(cut, -1);
  double xtick_max = 0.0;
  for (const char *t = strstr(svg, "class=\"xtick\""); t; t = strstr(t + 1, "class=\"xtick\""))
    xtick_max = fmax(xtick_max, strtod(strchr(t, '>') + 1, NULL));
  ck_assert_double_le(xtick_max, (double)end);
  ck_assert_uint_eq(count_of(svg, "continues to"), 0);
  ck_assert_ptr_nonnull(strstr(svg, "paper-mlp (43 trials) = paper-qtable (same walk)"));
  char styles[FIG_POLICIES][96];
  for (int k = 0; k < 3; ++k) {
    const char *g = svg_panel(svg, k);
    const double x0 = svg_attr(g, "data-x0"), y0 = svg_attr(g, "data-y0");
    const double w = svg_attr(g, "data-w"), h = svg_attr(g, "data-h");
    const double tmax = svg_attr(g, "data-tmax"), vlo = svg_attr(g, "data-vlo");
    const double vhi = svg_attr(g, "data-vhi");
    ck_assert_double_eq(tmax, (double)end);
    const double tol_mm = 0.006 * (vhi - vlo) / h + 1e-6, tol_t = 0.06 * tmax / w;
    for (int p = 0; p < FIG_POLICIES; ++p) {
      const char *run = js_run(js, object, fig_policy[p], 0);
      const char *kinds = strstr(run, "\"kind\": [");
      const size_t n = js_triples(run, "target_link_m", target, ESTIMATE_MAX_TRIALS);
      ck_assert_uint_eq(js_triples(run, "com_before_m", before, ESTIMATE_MAX_TRIALS), n);
      ck_assert_uint_eq(n, trials[p]);
      double com[3];
      js_vec3(run, "com_m", com);
      snprintf(pat, sizeof pat, "<polyline class=\"series\" data-series=\"%d\"", p);
      const char *pl = strstr(g, pat);
      ck_assert_msg(pl != NULL, "panel %d: no line of %s", k, fig_policy[p]);
      const char *st = strstr(pl, "stroke=\""), *da = strstr(pl, "stroke-dasharray=\"");
      char style[96];
      snprintf(style, sizeof style, "%.8s|%.12s", st + 8, da + 18);
      if (k == 0) {
        memcpy(styles[p], style, sizeof style);
        for (int e = 0; e < p; ++e)
          ck_assert_msg(strcmp(styles[e], style) != 0, "%s styled as %s", fig_policy[p],
                        fig_policy[e]);
      }
      const char *q = strstr(pl, "points=\"") + 8;
      size_t i = 0;
      for (; (double)(i + 1) <= tmax + 1e-9 && i <= n; ++i) {
        double want;
        if (i == n) {
          want = 1e3 * (com[k] - bbox[k]);
        } else {
          /* the i-th entry of "kind" */
          const char *kk = kinds + 9;
          for (size_t j = 0; j < i; ++j) kk = strchr(kk, ',') + 1;
          const int is_edge = strncmp(js_ws(kk), "\"edge\"", 6) == 0;
          want = 1e3 * ((is_edge ? target[i][k] : before[i][k]) - bbox[k]);
        }
        char *e;
        const double xa = strtod(q, &e), ya = strtod(e + 1, &e);
        const double xb = strtod(e + 1, &e), yb = strtod(e + 1, &e);
        q = e;
        const double t = (xa - x0) * tmax / w, v = vlo + (1.0 - (ya - y0) / h) * (vhi - vlo);
        ck_assert_msg(fabs(t - (double)(i + 1)) <= tol_t, "%s %c point %zu at trial %g",
                      fig_policy[p], "xyz"[k], i, t);
        ck_assert_msg(fabs(v - want) <= tol_mm, "%s %c point %zu: %.4f mm drawn, %.4f in the JSON",
                      fig_policy[p], "xyz"[k], i, v, want);
        ck_assert_double_eq(ya, yb); /* a step: level until the next trial */
        ck_assert_double_ge(xb, xa);
      }
      ck_assert_int_eq(*q, '"'); /* nothing past the axis end */
      ck_assert_uint_eq(i, n + 1 < end ? n + 1 : end);
    }
  }
}

/* The noisy plot read back: one row per noisy run in the JSON's order, each found component's bar
 * spanning error -+ half width and its point at the error (mm, through the panel's mapping), the
 * count of intervals that hold the truth as the JSON's numbers give it. */
static void check_noisy(const char *svg, const char *js, const char *object, int seeds) {
  for (int k = 0; k < 3; ++k) {
    const char *g = svg_panel(svg, k);
    const double x0 = svg_attr(g, "data-x0"), w = svg_attr(g, "data-w");
    const double vlo = svg_attr(g, "data-vlo"), vhi = svg_attr(g, "data-vhi");
    const double tol_mm = 0.006 * (vhi - vlo) / w + 1e-6;
    size_t row = 0, found = 0, hold = 0;
    for (int p = 0; p < FIG_POLICIES; ++p)
      for (int s = 1; s <= seeds; ++s, ++row) {
        const char *run = js_run(js, object, fig_policy[p], s);
        double err[3], hw[3];
        js_vec3(run, "error_m", err);
        js_vec3(run, "halfwidth_m", hw);
        char pat[64];
        snprintf(pat, sizeof pat, "<line class=\"bar\" data-row=\"%zu\"", row);
        const char *bar = strstr(g, pat);
        const char *next = strstr(g + 1, "<g class=\"panel\"");
        if (next && bar > next) bar = NULL;
        if (!isfinite(err[k]) || !isfinite(hw[k])) {
          ck_assert_msg(bar == NULL, "row %zu %c: a bar for a component not found", row, "xyz"[k]);
          continue;
        }
        ck_assert_msg(bar != NULL, "row %zu %c: no bar", row, "xyz"[k]);
        ++found;
        hold += fabs(err[k]) <= hw[k];
        const double lo = vlo + (svg_attr(bar, "x1") - x0) / w * (vhi - vlo);
        const double hi = vlo + (svg_attr(bar, "x2") - x0) / w * (vhi - vlo);
        ck_assert_msg(fabs(lo - 1e3 * (err[k] - hw[k])) <= tol_mm && lo < 1e3 * err[k],
                      "row %zu %c: bar from %.4f, JSON %.4f", row, "xyz"[k], lo,
                      1e3 * (err[k] - hw[k]));
        ck_assert_msg(fabs(hi - 1e3 * (err[k] + hw[k])) <= tol_mm && hi > 1e3 * err[k],
                      "row %zu %c: bar to %.4f, JSON %.4f", row, "xyz"[k], hi,
                      1e3 * (err[k] + hw[k]));
        snprintf(pat, sizeof pat, "<circle class=\"pt\" data-row=\"%zu\"", row);
        const char *pt = strstr(bar, pat);
        ck_assert_ptr_nonnull(pt);
        const double e = vlo + (svg_attr(pt, "cx") - x0) / w * (vhi - vlo);
        ck_assert_double_eq_tol(e, 1e3 * err[k], tol_mm);
      }
    ck_assert_uint_gt(found, 0);
    ck_assert_double_eq(svg_attr(g, "data-found"), (double)found);
    ck_assert_double_eq(svg_attr(g, "data-hold"), (double)hold);
    char head[96];
    snprintf(head, sizeof head, "%c: %zu of %zu intervals hold the truth", "xyz"[k], hold, found);
    ck_assert_msg(strstr(svg, head) != NULL, "no '%s'", head);
  }
  ck_assert_ptr_nonnull(strstr(svg, "seeds 1..2"));
}

/* The trial axis with one long run, on synthetic series: cut at 1.25 x the second longest (55
 * here), the long run's line drawn to the edge with a note in each panel, and without the long
 * run the axis ends at the longest. */
START_TEST(svg_trial_axis_cut) {
  enum { NS = 4, LONG = 115 };
  static double v[NS][LONG];
  const size_t n[NS] = {44, 44, 35, LONG};
  const char *names[NS] = {"paper-qtable", "paper-mlp", "bisect", "pba"};
  experiments_svg_series_t series[NS];
  for (int s = 0; s < NS; ++s) {
    for (size_t i = 0; i < n[s]; ++i) v[s][i] = 0.01 * (double)s + 1.0 / (double)(i + 1);
    series[s] = (experiments_svg_series_t){names[s], names[s], n[s], {v[s], v[s], v[s]}};
  }
  int cut = -1;
  ck_assert_uint_eq(axis_end(NS, n, &cut), 55);
  ck_assert_int_eq(cut, 3);
  ck_assert_uint_eq(experiments_svg_trial_limit(NS, series), 55);
  ck_assert_uint_eq(experiments_svg_trial_limit(NS - 1, series), 44);
  const size_t short_n[NS] = {44, 44, 35, 32};
  ck_assert_uint_eq(axis_end(NS, short_n, &cut), 44);
  ck_assert_int_eq(cut, -1);
  char path[512];
  snprintf(path, sizeof path, "%s/fig2_synthetic.svg", tmpdir);
  FILE *f = fopen(path, "w");
  ck_assert_ptr_nonnull(f);
  const double truth[3] = {0.0, 0.0, 0.0};
  ck_assert_int_eq(experiments_svg_fig2(f, "synthetic", truth, NS, series), 0);
  ck_assert_int_eq(fclose(f), 0);
  char *svg = test_slurp(path, NULL);
  ck_assert_uint_eq(count_of(svg, "pba continues to 114 trials"), 3);
  ck_assert_uint_eq(count_of(svg, "data-tmax=\"55\""), 3);
  /* the long run's line stops at the axis end: 55 points, not 115 */
  const char *pat = "<polyline class=\"series\" data-series=\"3\"";
  size_t lines = 0;
  for (const char *pl = strstr(svg, pat); pl; pl = strstr(pl + 1, pat), ++lines) {
    const char *q = strstr(pl, "points=\"") + 8, *e = strchr(q, '"');
    size_t vertices = 0;
    for (const char *c = q; c < e; ++c) vertices += *c == ',';
    ck_assert_uint_eq(vertices, 2 * 55); /* a step: two vertices per trial */
  }
  ck_assert_uint_eq(lines, 3);
  free(svg);
}
END_TEST

/* One rock, every policy, two seeds: Fig. 2 and the noisy plot checked against the JSON. */
START_TEST(cli_experiments_figures) {
  static char out[1 << 16];
  char cmd[2048], dir[512], r1[512], path[1024];
  snprintf(dir, sizeof dir, "%s/out", tmpdir);
  rock_path("rock_1_uneven", r1, sizeof r1);
  snprintf(cmd, sizeof cmd, "'%s' experiments '%s' --seeds 2 --out '%s' -q", COMLEARN_BIN, r1, dir);
  ck_assert_int_eq(run(cmd, out, sizeof out), 0);
  snprintf(path, sizeof path, "%s/experiments.json", dir);
  char *js = test_slurp(path, NULL);
  snprintf(path, sizeof path, "%s/fig2_rock_1_uneven.svg", dir);
  char *svg = test_slurp(path, NULL);
  check_fig2(svg, js, "rock_1_uneven");
  free(svg);
  snprintf(path, sizeof path, "%s/noisy.svg", dir);
  svg = test_slurp(path, NULL);
  ck_assert_uint_eq(count_of(svg, "<g class=\"panel\""), 3);
  check_noisy(svg, js, "rock_1_uneven", 2);
  free(svg);
  free(js);
  /* --seeds 0: no noisy runs, no noisy plot */
  snprintf(dir, sizeof dir, "%s/out0", tmpdir);
  snprintf(cmd, sizeof cmd, "'%s' experiments '%s' --seeds 0 --policies bisect --out '%s' -q",
           COMLEARN_BIN, r1, dir);
  ck_assert_int_eq(run(cmd, out, sizeof out), 0);
  snprintf(path, sizeof path, "%s/noisy.svg", dir);
  ck_assert_int_ne(access(path, F_OK), 0);
}
END_TEST

/* --sims 2: two comlearn-sims (channel prefixes R0_, R1_) on one URL, one worker process each,
 * the objects spread over them. Every noiseless run goes over LCM and gives what the serial
 * in-process run gives: the same trials, components found, and CoM (to the 9 printed digits,
 * within 2e-12 m: the LCM path rounds the release pose at ~1e-18 m), in the serial order. */
START_TEST(cli_experiments_sims) {
  static char out_s[1 << 18], out_d[1 << 18];
  char cmd[2048], r1[512], r2[512], r3[512];
  rock_path("rock_1_uneven", r1, sizeof r1);
  rock_path("rock_2_even", r2, sizeof r2);
  rock_path("rock_3_uneven", r3, sizeof r3);
  snprintf(cmd, sizeof cmd,
           "'%s' experiments '%s' '%s' '%s' --seeds 0 --policies bisect --sims 2 --json -q",
           COMLEARN_BIN, r1, r2, r3);
  ck_assert_int_eq(run(cmd, out_s, sizeof out_s), 0);
  snprintf(cmd, sizeof cmd, "'%s' experiments '%s' '%s' '%s' --seeds 0 --policies bisect --json -q",
           COMLEARN_BIN, r1, r2, r3);
  ck_assert_int_eq(run(cmd, out_d, sizeof out_d), 0);
  ck_assert_uint_eq(count_of(out_s, "{\"object\": "), 6);
  ck_assert_uint_eq(count_of(out_s, "\"backend\": \"lcm\""), 6);
  ck_assert_uint_eq(count_of(out_d, "\"backend\": \"direct\""), 6);
  const char *names[3] = {"rock_1_uneven", "rock_2_even", "rock_3_uneven"};
  const char *starts[2] = {"uniform", "bbox"};
  const char *prev_s = out_s;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 2; ++k) {
      char pat[256];
      snprintf(pat, sizeof pat,
               "{\"object\": \"%s\", \"policy\": \"bisect\", \"noisy\": false, \"start\": "
               "\"%s\"",
               names[i], starts[k]);
      const char *ps = strstr(out_s, pat), *pd = strstr(out_d, pat);
      ck_assert_msg(ps && pd, "no run %s %s", names[i], starts[k]);
      ck_assert_msg(ps >= prev_s, "%s %s out of the serial order", names[i], starts[k]);
      prev_s = ps;
      double cs[3], cd[3];
      json_vec(ps, "com_m", cs);
      json_vec(pd, "com_m", cd);
      for (int c = 0; c < 3; ++c)
        ck_assert_msg(fabs(cs[c] - cd[c]) <= 2e-12, "%s %s %c: %.12g vs %.12g", names[i], starts[k],
                      "xyz"[c], cs[c], cd[c]);
      ck_assert_double_eq(json_num(ps, "trials"), json_num(pd, "trials"));
      ck_assert_ptr_nonnull(strstr(ps, "\"found\": [true, true, true]"));
      ck_assert_ptr_nonnull(strstr(pd, "\"found\": [true, true, true]"));
    }
}
END_TEST

/* Progress: one line per run with its count and the time left, on a terminal or with -v; none
 * when stderr is not a terminal (a log, a pipe). Here stderr is a pipe: nothing without -v; with
 * -v, runs 1/4 .. 4/4 of one rock, bisect and PBA, noiseless (mesh prior and Table I), the last
 * without an ETA. */
START_TEST(cli_experiments_progress) {
  static char out[1 << 16];
  char cmd[2048], r1[512];
  rock_path("rock_1_even", r1, sizeof r1);
  snprintf(cmd, sizeof cmd, "'%s' experiments '%s' --seeds 0 --policies bisect,pba 2>&1 >/dev/null",
           COMLEARN_BIN, r1);
  ck_assert_int_eq(run(cmd, out, sizeof out), 0);
  ck_assert_msg(strstr(out, "[1/4") == NULL, "progress in a pipe: %s", out);
  snprintf(cmd, sizeof cmd,
           "'%s' experiments '%s' --seeds 0 --policies bisect,pba -v 2>&1 >/dev/null", COMLEARN_BIN,
           r1);
  ck_assert_int_eq(run(cmd, out, sizeof out), 0);
  const char *want[4] = {"[1/4, ETA ", "[2/4, ETA ", "[3/4, ETA ", "[4/4]"};
  const char *at = out;
  for (int i = 0; i < 4; ++i) {
    const char *p = strstr(at, want[i]);
    ck_assert_msg(p != NULL, "no '%s' (in order) in: %s", want[i], out);
    at = p;
  }
  ck_assert_ptr_null(strstr(out, "[5/"));
}
END_TEST

START_TEST(cli_bad_input) {
  char cmd[2048], out[8192], urdf[512];
  rock_path("rock_1_even", urdf, sizeof urdf);
  const struct {
    const char *args, *expect;
  } cases[] = {
      {"--policies bisect,foo", "--policies: 'foo' is not one of"},
      {"--policies bisect,bisect", "'bisect' is listed twice"},
      {"--seeds -1", "--seeds: '-1' is not an integer"},
      {"--seeds 2x", "--seeds: '2x'"},
      {"--placement-noise-mm nan", "--placement-noise-mm: 'nan' is not a number"},
      {"--pose-noise-mm inf", "--pose-noise-mm: 'inf' is not a number"},
      {"--placement-noise-mm -0.5", "--placement-noise-mm: '-0.5'"},
      {"--resolution-mm 0", "--resolution-mm: '0'"},
      {"--sims 0", "--sims: '0' is not an integer in [1, 16]"},
      {"--sims 17", "--sims: '17'"},
      {"--bogus", "comlearn experiments: error: unknown option '--bogus'"},
      {"--seeds", "comlearn experiments: error: --seeds needs a value"},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
    snprintf(cmd, sizeof cmd, "'%s' experiments '%s' %s 2>&1", COMLEARN_BIN, urdf, cases[i].args);
    ck_assert_msg(run(cmd, out, sizeof out) == 2, "%s: not exit 2", cases[i].args);
    ck_assert_msg(strstr(out, cases[i].expect) != NULL, "%s: message '%s' missing in: %s",
                  cases[i].args, cases[i].expect, out);
  }
  snprintf(cmd, sizeof cmd, "'%s' experiments '%s/missing.urdf' 2>&1", COMLEARN_BIN, tmpdir);
  ck_assert_int_eq(run(cmd, out, sizeof out), 2);
  ck_assert_ptr_nonnull(strstr(out, "missing.urdf"));
  snprintf(cmd, sizeof cmd, "'%s' experiments 2>&1", COMLEARN_BIN);
  ck_assert_int_eq(run(cmd, out, sizeof out), 2);
  ck_assert_ptr_nonnull(strstr(out, "at least one OBJECT.urdf"));
  snprintf(cmd, sizeof cmd, "'%s' experiments --help", COMLEARN_BIN);
  ck_assert_int_eq(run(cmd, out, sizeof out), 0);
  ck_assert_ptr_nonnull(strstr(out, "--placement-noise-mm S"));
  ck_assert_ptr_nonnull(strstr(out, "(default: 5)"));
}
END_TEST

static Suite *suite(void) {
  Suite *s = suite_create("experiments");
  TCase *tc = tcase_create("direct_noise");
  tcase_set_timeout(tc, 300);
  tcase_add_test(tc, noise_seeding_and_held_pose);
  tcase_add_test(tc, zero_noise_is_noiseless);
  tcase_add_test(tc, noise_arguments_checked);
  tcase_add_test(tc, pba_under_noise);
  suite_add_tcase(s, tc);
  tc = tcase_create("cli");
  tcase_add_checked_fixture(tc, setup, teardown);
  tcase_set_timeout(tc, 300);
  tcase_add_test(tc, cli_experiments_outputs);
  tcase_add_test(tc, svg_trial_axis_cut);
  tcase_add_test(tc, cli_experiments_figures);
  tcase_add_test(tc, cli_experiments_sims);
  tcase_add_test(tc, cli_experiments_progress);
  tcase_add_test(tc, cli_bad_input);
  suite_add_tcase(s, tc);
  return s;
}

int main(void) {
  SRunner *sr = srunner_create(suite());
  srunner_run_all(sr, CK_NORMAL);
  int failed = srunner_ntests_failed(sr);
  srunner_free(sr);
  return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
