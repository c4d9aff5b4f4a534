/*
 * estimate.c - the estimator side of `comlearn estimate` (see estimate.h and docs/estimate.md).
 * Geometry only: this file must never include comlearn/model_inertial.h.
 */
#include "estimate.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "comlearn/balance_poses.h"
#include "comlearn/qlearn_solve.h"

#define PI 3.14159265358979323846
enum { FACE_CAP = 256, YAW_STEPS = 90, ESTIMATE_RETRIES = 3 }; /* 2-degree yaw sweep over [0, pi) */

/* Bound on the threshold bias of one flat-patch edge test in lib/balance (docs/physics.md: <= 2.4 um
 * measured down to a 0.97 mm chord margin, <= 5 um asserted by the accuracy tests). */
#define ESTIMATE_PHYSICS_BIAS_M 5e-6
/* How far from the estimate (along the test direction) a planned edge line is checked. */
#define ESTIMATE_PLAN_OFFSET_M 3e-3

const char *estimate_policy_name(qlearn_policy_kind_t k) {
  switch (k) {
    case QLEARN_POLICY_BISECT: return "bisect";
    case QLEARN_POLICY_PBA: return "pba";
    case QLEARN_POLICY_PAPER_QTABLE: return "paper-qtable";
    case QLEARN_POLICY_PAPER_MLP: return "paper-mlp";
  }
  return "?";
}

int estimate_policy_parse(const char *s, qlearn_policy_kind_t *k) {
  static const qlearn_policy_kind_t all[] = {QLEARN_POLICY_BISECT, QLEARN_POLICY_PBA,
                                             QLEARN_POLICY_PAPER_QTABLE, QLEARN_POLICY_PAPER_MLP};
  for (size_t i = 0; s && i < sizeof all / sizeof all[0]; ++i)
    if (strcmp(s, estimate_policy_name(all[i])) == 0) {
      *k = all[i];
      return 0;
    }
  return -1;
}

const char *estimate_status_str(estimate_status_t s) {
  switch (s) {
    case ESTIMATE_OK: return "ok";
    case ESTIMATE_E_ARG: return "bad argument";
    case ESTIMATE_E_GEOMETRY: return "no usable flat face in the geometry";
    case ESTIMATE_E_BACKEND: return "trial backend failed";
    case ESTIMATE_E_NOPOSE: return "no resting face confirmed stable";
    case ESTIMATE_E_CAPACITY: return "too many trials";
    case ESTIMATE_E_LEARNER: return "learner error";
    case ESTIMATE_E_NOMEM: return "out of memory";
  }
  return "unknown status";
}

void estimate_config_default(estimate_config_t *cfg) {
  memset(cfg, 0, sizeof *cfg);
  cfg->policy = QLEARN_POLICY_BISECT;
  cfg->resolution_m = 1e-4;
  cfg->max_halfwidth_m = 1e-3;
  cfg->z = 1.96;
  cfg->seed = 1;
  cfg->min_chord_margin_m = 0.003;
  cfg->min_dir_angle_rad = PI / 3.0;
  cfg->min_face_angle_rad = PI / 6.0;
  cfg->noise_max_trials = 48;
  cfg->verify_margin_m = 0.001;
  cfg->max_retests = 3;
}

typedef struct {
  int face;
  double yaw[2];
  double margin[2];
  double score;
} face_plan_t;

/* Everything one run needs; heap-allocated (the face list and the result are large). */
typedef struct {
  const model_mesh_t *mesh;
  const estimate_backend_t *backend;
  const estimate_config_t *cfg;
  estimate_result_t *out;
  balance_world_t *plan_world;  /* geometry only: B's size and the object's shape for planning */
  balance_object_t *plan_obj;   /* carries uniform-density mass properties, never the truth */
  double guess_m[3];            /* current CoM estimate, link frame (planning) */
  double start_m[3];            /* where the next search starts: cfg->start, moved alike */
  double halfwidth_m[3];        /* its half widths (INFINITY until a solve finds the component) */
  int noisy;                    /* cfg->noise_sigma_m > 0 */
  char face2_note[ESTIMATE_NOTE_SIZE]; /* why the second face gave no search ("" if it did) */
  int face_src[ESTIMATE_MAX_FACES];    /* out->face[i] is faces[face_src[i]] */
  balance_face_t faces[FACE_CAP];
  size_t nfaces;
  face_plan_t plans[FACE_CAP];  /* scratch of face_one / face_two */
  balance_regime_t regime;      /* scratch (~4 KiB) */
  qlearn_policy_t policy;       /* the current search (~12 KiB for PBA) */
  qlearn_policy_t handover;     /* PBA after a noisy walk */
  qlearn_solve_t solve;
  qlearn_solve_result_t last;   /* the latest solve (update_guess), for planning */
  int have_solve;
} run_t;

static double dot3(const double a[3], const double b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Link-frame direction of world +x (the +X edge's normal) for orientation q: R^T e_x. */
static void dir_of(const double q[4], double dir[3]) {
  double r[3][3];
  model_quat_to_rot(q, r);
  for (int k = 0; k < 3; ++k) dir[k] = r[0][k];
}

/* The threshold plane of a trial released at `pose` over the +X edge: n_obj . c = d. */
static void trial_plane(const run_t *run, const balance_pose_t *pose, double n_obj[3],
                        double *d_m) {
  double n[3], d_edge, r[3][3];
  balance_edge_line(run->backend->base_size_m, BALANCE_EDGE_PX, n, &d_edge);
  model_quat_to_rot(pose->orientation_wxyz, r);
  for (int k = 0; k < 3; ++k) n_obj[k] = r[0][k] * n[0] + r[1][k] * n[1] + r[2][k] * n[2];
  *d_m = d_edge - dot3(n, pose->position_m);
}

static double quat_angle(const double a[4], const double b[4]) {
  double c = fabs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]);
  return 2.0 * acos(c > 1.0 ? 1.0 : c);
}

static estimate_status_t fail(run_t *run, estimate_status_t s, const char *what) {
  snprintf(run->out->msg, sizeof run->out->msg, "%s", what);
  return s;
}

/* The request fields every trial carries for records: the running estimate before it. */
static void request_common(const run_t *run, estimate_trial_request_t *req) {
  memcpy(req->com_before_m, run->guess_m, sizeof req->com_before_m);
  memcpy(req->halfwidth_before_m, run->halfwidth_m, sizeof req->halfwidth_before_m);
}

/* Run one trial through the backend and log it. */
static estimate_status_t do_trial(run_t *run, const estimate_trial_request_t *req, int face,
                                  int search, double x_m, estimate_trial_t **logged) {
  estimate_result_t *out = run->out;
  if (out->trial_count >= ESTIMATE_MAX_TRIALS)
    return fail(run, ESTIMATE_E_CAPACITY, "trial log full");
  estimate_trial_reply_t reply;
  memset(&reply, 0, sizeof reply);
  char err[256] = "";
  if (run->backend->run(run->backend->ctx, req, &reply, err, sizeof err) != 0) {
    snprintf(out->msg, sizeof out->msg, "%s backend: %s", run->backend->name,
             err[0] ? err : "trial failed");
    return ESTIMATE_E_BACKEND;
  }
  estimate_trial_t *t = &out->trial[out->trial_count++];
  memset(t, 0, sizeof *t);
  t->kind = req->kind;
  memcpy(t->target_link_m, req->target_link_m, sizeof t->target_link_m);
  t->face = face;
  t->search = search;
  t->x_m = x_m;
  t->outcome = reply.outcome;
  t->regime = -1;
  t->chord_margin_m = NAN;
  t->released = reply.released;
  t->settled = reply.settled;
  if (req->kind == ESTIMATE_TRIAL_STABLE) {
    ++out->stable_trials;
  } else {
    /* Classify what was actually released, with the current estimate: only flat-patch trials
     * measure the CoM (docs/physics.md, "Where an edge test measures the CoM exactly"). */
    balance_regime_t *reg = &run->regime;
    balance_status_t bs = balance_regime_classify(run->mesh, &reply.released,
                                                  run->backend->base_size_m, req->edge,
                                                  run->guess_m, NULL, reg);
    if (bs == BALANCE_OK) {
      t->regime = (int)reg->kind;
      t->chord_margin_m = reg->chord_margin_m;
    }
    t->flagged = bs != BALANCE_OK || !reg->flat_patch_regime ||
                 (reply.outcome != BALANCE_STAYS && reply.outcome != BALANCE_TIPS);
    if (t->flagged) ++out->flagged_trials;
  }
  if (run->cfg->progress) {
    char what[160];
    if (req->kind == ESTIMATE_TRIAL_STABLE)
      snprintf(what, sizeof what, "stable check, face %d: %s", face,
               reply.outcome == BALANCE_STAYS ? "stays" : "does not stay");
    else
      snprintf(what, sizeof what, "search %d, x = %+.4f mm: %s%s", search, 1e3 * x_m,
               reply.outcome == BALANCE_STAYS ? "stays" : "tips", t->flagged ? " (flagged)" : "");
    run->cfg->progress(run->cfg->progress_ctx, out->trial_count, what);
  }
  *logged = t;
  return ESTIMATE_OK;
}

/* Set the object down in `face`'s resting orientation with the current estimate over B's middle;
 * it rests stably when it stays, barely moved. */
static estimate_status_t stable_check(run_t *run, int face_index, int log_face, int *confirmed) {
  const balance_face_t *f = &run->faces[face_index];
  estimate_trial_request_t req;
  memset(&req, 0, sizeof req);
  req.kind = ESTIMATE_TRIAL_STABLE;
  req.edge = BALANCE_EDGE_PX;
  req.search = -1;
  req.component = -1;
  req.direction = 0;
  memcpy(req.target_link_m, run->guess_m, sizeof req.target_link_m);
  request_common(run, &req);
  double r[3][3];
  memcpy(req.release.orientation_wxyz, f->orientation_wxyz, sizeof f->orientation_wxyz);
  model_quat_to_rot(f->orientation_wxyz, r);
  double bottom = balance_object_bottom_z(run->plan_obj, f->orientation_wxyz);
  if (!isfinite(bottom)) return fail(run, ESTIMATE_E_GEOMETRY, "resting orientation not usable");
  for (int i = 0; i < 2; ++i)
    req.release.position_m[i] = -(r[i][0] * run->guess_m[0] + r[i][1] * run->guess_m[1] +
                                  r[i][2] * run->guess_m[2]);
  req.release.position_m[2] = -bottom - 1e-6; /* touching: 1 um pre-penetrated, never dropped */
  estimate_trial_t *t;
  estimate_status_t s = do_trial(run, &req, log_face, -1, 0.0, &t);
  if (s != ESTIMATE_OK) return s;
  balance_stable_config_t sc;
  balance_stable_config_default(&sc);
  double dx = t->settled.position_m[0] - t->released.position_m[0];
  double dy = t->settled.position_m[1] - t->released.position_m[1];
  double dz = t->settled.position_m[2] - t->released.position_m[2];
  *confirmed = t->outcome == BALANCE_STAYS &&
               quat_angle(t->settled.orientation_wxyz, t->released.orientation_wxyz) <=
                   sc.max_rotation_rad &&
               sqrt(dx * dx + dy * dy + dz * dz) <= sc.max_displacement_m;
  return ESTIMATE_OK;
}

/* The range of a search along u: the object's extent along u, 1 mm inside at each end (a CoM
 * cannot lie on the hull surface, and a point at the very extreme over the edge leaves nothing
 * of the object over B to set it down on). */
static void search_range(const run_t *run, const double u[3], double *lo, double *hi) {
  *lo = HUGE_VAL;
  *hi = -HUGE_VAL;
  for (size_t i = 0; i < run->mesh->vertex_count; ++i) {
    const double p = dot3(run->mesh->vertices_m[i], u);
    if (p < *lo) *lo = p;
    if (p > *hi) *hi = p;
  }
  *lo += 1e-3;
  *hi -= 1e-3;
}

/* What one search needs while its trials run. */
typedef struct {
  int si;           /* its index in out->search */
  int log_face;     /* its face in out->face */
  int comp;         /* the link axis it determines most */
  double q[4];      /* the resting orientation, yawed */
  double u[3];      /* the test direction, link frame */
  double lo, hi;    /* its range */
} search_ctx_t;

/* Plan the placement of link point g + (x - u.g) u over the +X edge and run it; *t is the logged
 * trial with t->x_m the x actually achieved. */
static estimate_status_t edge_trial(run_t *run, const search_ctx_t *sc, double xa,
                                    estimate_trial_t **t) {
  estimate_result_t *out = run->out;
  double p_link[3];
  const double gx = dot3(run->guess_m, sc->u);
  for (int k = 0; k < 3; ++k) p_link[k] = run->guess_m[k] + (xa - gx) * sc->u[k];
  estimate_trial_request_t req;
  memset(&req, 0, sizeof req);
  req.kind = ESTIMATE_TRIAL_EDGE;
  req.edge = BALANCE_EDGE_PX;
  balance_status_t bs = balance_pose_over_edge(run->plan_world, run->plan_obj, sc->q,
                                               BALANCE_EDGE_PX, p_link, 0.0, 1e-6, &req.release);
  if (bs != BALANCE_OK) {
    snprintf(out->msg, sizeof out->msg, "planning a placement at x = %.6f m: %s", xa,
             balance_status_str(bs));
    return ESTIMATE_E_GEOMETRY;
  }
  req.search = sc->si;
  req.component = sc->comp;
  req.direction = sc->u[sc->comp] >= 0.0 ? 1 : -1;
  memcpy(req.target_link_m, p_link, sizeof p_link);
  request_common(run, &req);
  /* the planned pose's regime, as do_trial classifies the released one */
  req.flat_patch = 0;
  req.sideways_margin_m = -HUGE_VAL;
  if (balance_regime_classify(run->mesh, &req.release, run->backend->base_size_m, req.edge,
                              run->guess_m, NULL, &run->regime) == BALANCE_OK) {
    req.flat_patch = run->regime.flat_patch_regime != 0;
    req.sideways_margin_m = run->regime.chord_margin_m;
  }
  estimate_status_t s = do_trial(run, &req, sc->log_face, sc->si, xa, t);
  if (s != ESTIMATE_OK) return s;
  ++out->search[sc->si].trials;
  /* The placement actually achieved: its plane's offset along u (equal to xa when exact). */
  double n_obj[3], d;
  trial_plane(run, &(*t)->released, n_obj, &d);
  double x_got = dot3(n_obj, sc->u) > 0.99 ? d / dot3(n_obj, sc->u) : xa;
  if (!(x_got >= sc->lo && x_got <= sc->hi)) x_got = xa;
  (*t)->x_m = x_got;
  return ESTIMATE_OK;
}

static int clear_outcome(const estimate_trial_t *t) {
  return t->outcome == BALANCE_STAYS || t->outcome == BALANCE_TIPS;
}

/* Record a clear trial's outcome in a policy. */
static qlearn_status_t observe_trial(qlearn_policy_t *pol, const estimate_trial_t *t) {
  return qlearn_policy_observe(pol, t->x_m, t->outcome == BALANCE_STAYS ? QLEARN_STAYS : QLEARN_TIPS);
}

/* Does trial i (of search sr, clear) set the threshold? Noiseless: it is one of the two
 * bracketing trials; with a noise model: it lies within c +- (h + 3 sigma). */
static int deciding_trial(const run_t *run, const estimate_search_t *sr, size_t i) {
  if (!run->noisy) return (int)i == sr->lo_trial || (int)i == sr->hi_trial;
  return fabs(run->out->trial[i].x_m - sr->c_m) <= sr->halfwidth_m + 3.0 * run->cfg->noise_sigma_m;
}

/* The probit noise model of cfg->noise_sigma_m in a PBA config; its searches stop at
 * max(resolution, sigma), at most the range. */
static void probit_config(const run_t *run, qlearn_policy_config_t *pc) {
  pc->noise = QLEARN_NOISE_PROBIT;
  pc->sigma_m = run->cfg->noise_sigma_m;
  pc->resolution_m = fmax(run->cfg->resolution_m, run->cfg->noise_sigma_m);
  if (pc->resolution_m > pc->range_hi_m - pc->range_lo_m)
    pc->resolution_m = pc->range_hi_m - pc->range_lo_m;
}

/* Run the trials `pol` asks for until it is done. An unclear outcome (INVALID: still moving at
 * the horizon, or SLIDES) says nothing about the CoM: it is logged, flagged and not observed; the
 * placement is retried a quarter of the resolution further on (at most ESTIMATE_RETRIES times; the
 * simulation is deterministic, so the same pose would give the same answer). *stopped gets a
 * reason when the walk ended early: no clear outcome, or outcomes that contradict a noiseless
 * bracket (only bisect refuses those). */
static estimate_status_t search_walk(run_t *run, const search_ctx_t *sc, qlearn_policy_t *pol,
                                     uint32_t *ran, char *stopped, size_t stopped_size) {
  estimate_result_t *out = run->out;
  stopped[0] = '\0';
  for (uint32_t n = 0; n < QLEARN_MAX_TRIALS && !qlearn_policy_done(pol); ++n) {
    double x;
    qlearn_status_t qs = qlearn_policy_next(pol, &x);
    if (qs == QLEARN_E_DONE) break;
    if (qs != QLEARN_OK) {
      snprintf(out->msg, sizeof out->msg, "policy next: %s", qlearn_status_str(qs));
      return ESTIMATE_E_LEARNER;
    }
    estimate_trial_t *t = NULL;
    for (int attempt = 0; attempt <= ESTIMATE_RETRIES; ++attempt) {
      double xa = x + 0.25 * run->cfg->resolution_m * attempt * (attempt % 2 ? 1.0 : -1.0);
      if (xa < sc->lo) xa = sc->lo;
      if (xa > sc->hi) xa = sc->hi;
      estimate_status_t s = edge_trial(run, sc, xa, &t);
      if (s != ESTIMATE_OK) return s;
      if (ran) ++*ran;
      if (clear_outcome(t)) break;
      t = NULL;
    }
    if (!t) {
      snprintf(stopped, stopped_size, "no clear outcome near x = %.3f mm", 1e3 * x);
      return ESTIMATE_OK;
    }
    qs = observe_trial(pol, t);
    if (qs == QLEARN_E_RANGE) {
      snprintf(stopped, stopped_size,
               "outcome at x = %.3f mm contradicts the earlier ones (noise, or physics the "
               "noiseless model does not cover)", 1e3 * t->x_m);
      return ESTIMATE_OK;
    }
    if (qs != QLEARN_OK) {
      snprintf(out->msg, sizeof out->msg, "search %d: outcome refused by the policy: %s", sc->si,
               qlearn_status_str(qs));
      return ESTIMATE_E_LEARNER;
    }
  }
  return ESTIMATE_OK;
}

/* Noisy walk: hand over to PBA with the probit noise model, starting from the posterior of every
 * clear trial the walk made, and run it until its interval is narrow enough. */
static estimate_status_t search_handover(run_t *run, const search_ctx_t *sc,
                                         const qlearn_policy_config_t *walk) {
  estimate_result_t *out = run->out;
  estimate_search_t *sr = &out->search[sc->si];
  qlearn_policy_config_t pc;
  qlearn_policy_config_default(QLEARN_POLICY_PBA, &pc);
  pc.range_lo_m = walk->range_lo_m;
  pc.range_hi_m = walk->range_hi_m;
  pc.prior_m = walk->prior_m;
  probit_config(run, &pc);
  pc.max_trials = QLEARN_MAX_TRIALS;
  qlearn_policy_t *pba = &run->handover;
  qlearn_status_t qs = qlearn_policy_init(pba, &pc);
  uint32_t seen = 0;
  for (size_t i = 0; qs == QLEARN_OK && i < out->trial_count; ++i) {
    const estimate_trial_t *t = &out->trial[i];
    if (t->search != sc->si || !clear_outcome(t)) continue;
    qs = observe_trial(pba, t);
    ++seen;
  }
  if (qs == QLEARN_E_DONE) qs = QLEARN_OK; /* already narrow enough */
  if (qs != QLEARN_OK) {
    snprintf(out->msg, sizeof out->msg, "search %d: handover: %s", sc->si, qlearn_status_str(qs));
    return ESTIMATE_E_LEARNER;
  }
  pba->cfg.max_trials = seen + run->cfg->noise_max_trials; /* cap the extra trials */
  if (pba->cfg.max_trials > QLEARN_MAX_TRIALS) pba->cfg.max_trials = QLEARN_MAX_TRIALS;
  char stopped[ESTIMATE_NOTE_SIZE];
  estimate_status_t s = search_walk(run, sc, pba, &sr->handover_trials, stopped, sizeof stopped);
  if (s == ESTIMATE_OK && stopped[0]) snprintf(sr->note, sizeof sr->note, "%s", stopped);
  return s;
}

/* The threshold plane of a search, from its bracketing trials (noiseless) or the trials nearest
 * to its estimate (noisy), moved to the estimate c. It is used only when the trials that set it
 * were in the flat-patch regime; with a noise model every trial within c +- (h + 3 sigma) must
 * be. Otherwise the search gets a note and is not fed. */
static void search_plane(run_t *run, const search_ctx_t *sc) {
  estimate_result_t *out = run->out;
  estimate_search_t *sr = &out->search[sc->si];
  const double c = sr->c_m;
  const int ends[2] = {sr->lo_trial, sr->hi_trial};
  double n_obj[3] = {0, 0, 0}, d = 0.0;
  int nb = 0;
  for (int e = 0; e < 2; ++e) {
    if (ends[e] < 0) continue;
    const estimate_trial_t *t = &out->trial[ends[e]];
    double ne[3], de;
    trial_plane(run, &t->released, ne, &de);
    de += (c - t->x_m) * dot3(ne, sc->u); /* move it to the estimate c */
    for (int k = 0; k < 3; ++k) n_obj[k] += ne[k];
    d += de;
    ++nb;
  }
  if (nb < 2 && !run->noisy) {
    snprintf(sr->note, sizeof sr->note, "the threshold was not bracketed (all trials %s)",
             sr->lo_trial < 0 ? "stayed" : "tipped");
    return;
  }
  if (nb == 0) {
    snprintf(sr->note, sizeof sr->note, "no clear trial");
    return;
  }
  for (size_t i = 0; i < out->trial_count; ++i) {
    const estimate_trial_t *t = &out->trial[i];
    if (t->search != sc->si || !clear_outcome(t)) continue;
    if (deciding_trial(run, sr, i) && t->flagged) {
      sr->flat_failed = 1;
      snprintf(sr->note, sizeof sr->note,
               "a trial that sets the threshold (x = %.3f mm) is not in the flat-patch regime "
               "(%s, chord margin %.2f mm)", 1e3 * t->x_m,
               t->regime == BALANCE_REGIME_EDGE_ROLL ? "edge roll" :
               t->regime == BALANCE_REGIME_POINT_SUPPORT ? "point support" : "unclassified",
               1e3 * t->chord_margin_m);
      return;
    }
  }
  const double len = sqrt(dot3(n_obj, n_obj));
  for (int k = 0; k < 3; ++k) sr->plane_n_obj[k] = n_obj[k] / len;
  sr->plane_d_m = d / len;
  sr->bias_m = ESTIMATE_PHYSICS_BIAS_M;
  sr->fed = 1;
}

/* The estimate of a search: noiseless, the bracket of its clear trials (the largest x that
 * tipped, the smallest that stayed), whatever the policy; with a noise model, the policy's
 * posterior (PBA). */
static void search_estimate(run_t *run, const search_ctx_t *sc, const qlearn_policy_t *pol) {
  estimate_result_t *out = run->out;
  estimate_search_t *sr = &out->search[sc->si];
  sr->lo_trial = sr->hi_trial = -1;
  for (size_t i = 0; i < out->trial_count; ++i) {
    const estimate_trial_t *t = &out->trial[i];
    if (t->search != sc->si || !clear_outcome(t)) continue;
    if (t->outcome == BALANCE_TIPS && (sr->lo_trial < 0 || t->x_m >= out->trial[sr->lo_trial].x_m))
      sr->lo_trial = (int)i;
    if (t->outcome == BALANCE_STAYS && (sr->hi_trial < 0 || t->x_m <= out->trial[sr->hi_trial].x_m))
      sr->hi_trial = (int)i;
  }
  const double lo = sr->lo_trial >= 0 ? out->trial[sr->lo_trial].x_m : sc->lo;
  const double hi = sr->hi_trial >= 0 ? out->trial[sr->hi_trial].x_m : sc->hi;
  if (run->noisy) {
    double c, hw;
    if (qlearn_policy_estimate(pol, &c, &hw) != QLEARN_OK) {
      snprintf(sr->note, sizeof sr->note, "the posterior gives no estimate");
      return;
    }
    sr->c_m = c;
    sr->halfwidth_m = hw;
  } else if (hi >= lo) {
    sr->c_m = 0.5 * (lo + hi);
    sr->halfwidth_m = 0.5 * (hi - lo);
  } else {
    /* A trial tipped above one that stayed: the noiseless model does not hold here. */
    sr->c_m = 0.5 * (lo + hi);
    sr->halfwidth_m = 0.5 * (lo - hi);
    snprintf(sr->note, sizeof sr->note, "trials contradict each other: tipped at %.3f mm, stayed "
             "at %.3f mm (noise, or physics the noiseless model does not cover)", 1e3 * lo, 1e3 * hi);
  }
}

/* One 1-D search along the test direction of face_index at yaw_rad. */
static estimate_status_t search_run(run_t *run, int face_index, int log_face, double yaw_rad,
                                    double margin_m, int retest_of) {
  estimate_result_t *out = run->out;
  if (out->search_count >= ESTIMATE_MAX_SEARCHES)
    return fail(run, ESTIMATE_E_CAPACITY, "too many searches");
  search_ctx_t sc;
  sc.si = (int)out->search_count++;
  sc.log_face = log_face;
  estimate_search_t *sr = &out->search[sc.si];
  memset(sr, 0, sizeof *sr);
  sr->face = log_face;
  sr->yaw_rad = yaw_rad;
  sr->chord_margin_m = margin_m;
  sr->verified_margin_m = NAN;
  sr->lo_trial = sr->hi_trial = -1;
  sr->retest_of = retest_of;
  balance_orientation_yawed(run->faces[face_index].orientation_wxyz, yaw_rad, sc.q);
  dir_of(sc.q, sc.u);
  memcpy(sr->dir_link, sc.u, sizeof sc.u);
  sc.comp = 0;
  for (int k = 1; k < 3; ++k)
    if (fabs(sc.u[k]) > fabs(sc.u[sc.comp])) sc.comp = k;
  search_range(run, sc.u, &sc.lo, &sc.hi);
  double prior = dot3(run->start_m, sc.u);
  if (prior < sc.lo) prior = sc.lo;
  if (prior > sc.hi) prior = sc.hi;
  sr->prior_m = prior;
  sr->range_lo_m = sc.lo;
  sr->range_hi_m = sc.hi;

  qlearn_policy_config_t pc;
  qlearn_policy_config_default(run->cfg->policy, &pc);
  pc.range_lo_m = sc.lo;
  pc.range_hi_m = sc.hi;
  pc.prior_m = prior;
  pc.resolution_m = run->cfg->resolution_m;
  pc.seed = run->cfg->seed;
  if (run->cfg->policy == QLEARN_POLICY_PBA && run->noisy) probit_config(run, &pc);
  qlearn_policy_t *pol = &run->policy;
  qlearn_status_t qs = qlearn_policy_init(pol, &pc);
  if (qs != QLEARN_OK) {
    snprintf(out->msg, sizeof out->msg, "policy init: %s", qlearn_status_str(qs));
    return ESTIMATE_E_LEARNER;
  }
  char stopped[ESTIMATE_NOTE_SIZE];
  estimate_status_t s = search_walk(run, &sc, pol, NULL, stopped, sizeof stopped);
  if (s != ESTIMATE_OK) return s;
  const qlearn_policy_t *final = pol;
  if (run->noisy && run->cfg->policy != QLEARN_POLICY_PBA) {
    s = search_handover(run, &sc, &pc);
    if (s != ESTIMATE_OK) return s;
    final = &run->handover;
  } else if (stopped[0]) {
    snprintf(sr->note, sizeof sr->note, "%s", stopped);
    return ESTIMATE_OK;
  }
  search_estimate(run, &sc, final);
  if (!sr->note[0]) search_plane(run, &sc);
  return ESTIMATE_OK;
}

/* A fed plane's sigma in the solve: the bracket's uniform spread h / sqrt 3 (noiseless) or the
 * 95 % interval's h / 1.96 (noise model); at least 1 nm (a collapsed, knife-edge bracket). */
static double plane_sigma(const run_t *run, const estimate_search_t *sr) {
  const double sigma = run->noisy ? sr->halfwidth_m / 1.96 : sr->halfwidth_m / sqrt(3.0);
  return sigma > 1e-9 ? sigma : 1e-9;
}

/* The 3-D solve over the fed planes. Each plane's sigma: the bracket's uniform spread h / sqrt 3
 * (noiseless) or the 95 % interval's h / 1.96 (noise model). Every component the planes
 * determine is reported (found[] here means determined; the caller applies the width limit). */
static estimate_status_t solve_all(run_t *run, qlearn_solve_result_t *res) {
  qlearn_solve_t *solve = &run->solve;
  qlearn_solve_init(solve);
  for (size_t i = 0; i < run->out->search_count; ++i) {
    const estimate_search_t *sr = &run->out->search[i];
    if (!sr->fed) continue;
    qlearn_status_t qs =
        qlearn_solve_add_plane(solve, sr->plane_n_obj, sr->plane_d_m, plane_sigma(run, sr));
    if (qs != QLEARN_OK) {
      snprintf(run->out->msg, sizeof run->out->msg, "solve: %s", qlearn_status_str(qs));
      return ESTIMATE_E_LEARNER;
    }
  }
  memset(res, 0, sizeof *res);
  if (solve->count == 0) {
    for (int k = 0; k < 3; ++k) res->halfwidth_m[k] = INFINITY;
    return ESTIMATE_OK;
  }
  qlearn_status_t qs = qlearn_solve_compute(solve, run->cfg->z, 1e9, res);
  if (qs != QLEARN_OK && qs != QLEARN_E_SINGULAR) {
    snprintf(run->out->msg, sizeof run->out->msg, "solve: %s", qlearn_status_str(qs));
    return ESTIMATE_E_LEARNER;
  }
  return ESTIMATE_OK;
}

/* Is direction a determined by the fed planes (orthogonal to the solve's null space)? */
static int dir_determined(const qlearn_solve_result_t *res, const double a[3]) {
  if (res->rank == 0) return 0;
  double leak = 0.0;
  for (int e = 0; e < 3 - res->rank; ++e) {
    const double p = dot3(res->eigenvector[e], a);
    leak += p * p;
  }
  return leak <= QLEARN_SOLVE_NULL_LEAK;
}

/* The coefficient of fed plane sr in the solve's estimate of a . c: p = w a . (A^+ n),
 * w = 1 / sigma^2 (dimensionless: a . c = sum over planes of p d). */
static double plane_coef(const run_t *run, const qlearn_solve_result_t *res, const double a[3],
                         const estimate_search_t *sr) {
  double p = 0.0;
  for (int e = 3 - res->rank; e < 3; ++e)
    p += dot3(res->eigenvector[e], a) * dot3(res->eigenvector[e], sr->plane_n_obj) /
         res->eigenvalue[e];
  const double sigma = plane_sigma(run, sr);
  return p / (sigma * sigma);
}

/* The half width of a . c (a unit, link frame) that holds, INFINITY when the planes do not
 * determine it. The solve's estimate is linear in the planes' offsets, a . c = sum_j p_j d_j with
 * p_j = w_j a . (A^+ n_j) (A^+ the pseudo-inverse of the normal matrix over its non-null
 * eigenvectors, exact for a orthogonal to the null space). Noiseless, each offset is known within
 * its bracket h_j plus its regime's bias b_j, so |error| <= sum_j |p_j| (h_j + b_j): a bound, also
 * when the planes are oblique or fewer than three. With a noise model: the solve's z sigma (95 %)
 * plus the bias budget sum_j |p_j| b_j. */
static double dir_halfwidth(const run_t *run, const qlearn_solve_result_t *res, const double a[3]) {
  if (!dir_determined(res, a)) return INFINITY;
  const int first = 3 - res->rank; /* eigenvalues ascend: the null ones come first */
  double bound = 0.0, bias = 0.0, var = 0.0;
  for (int e = first; e < 3; ++e) {
    const double p = dot3(res->eigenvector[e], a);
    var += p * p / res->eigenvalue[e];
  }
  for (size_t i = 0; i < run->out->search_count; ++i) {
    const estimate_search_t *sr = &run->out->search[i];
    if (!sr->fed) continue;
    const double p = plane_coef(run, res, a, sr);
    bound += fabs(p) * (sr->halfwidth_m + sr->bias_m);
    bias += fabs(p) * sr->bias_m;
  }
  return run->noisy ? run->cfg->z * sqrt(var) + bias : bound;
}

/* The first fed search that a . c depends on (a coefficient above rounding) but that is not
 * verified, or -1. */
static int dir_unverified(const run_t *run, const qlearn_solve_result_t *res, const double a[3]) {
  for (size_t i = 0; i < run->out->search_count; ++i) {
    const estimate_search_t *sr = &run->out->search[i];
    if (sr->fed && !sr->verified && fabs(plane_coef(run, res, a, sr)) > 1e-9) return (int)i;
  }
  return -1;
}

/* Solve and move the estimate: the guess (and the start point) take the solution's components in
 * the determined subspace, keep theirs in the null space; run->halfwidth_m per link axis. */
static estimate_status_t update_guess(run_t *run, qlearn_solve_result_t *res) {
  estimate_status_t s = solve_all(run, res);
  if (s != ESTIMATE_OK) return s;
  run->last = *res;
  run->have_solve = 1;
  for (int k = 0; k < 3; ++k) { /* INFINITY while a component is not found */
    const double e[3] = {k == 0, k == 1, k == 2};
    const double hw = dir_halfwidth(run, res, e);
    run->halfwidth_m[k] = hw <= run->cfg->max_halfwidth_m ? hw : INFINITY;
  }
  if (res->rank == 0) return ESTIMATE_OK;
  double *pts[2] = {run->guess_m, run->start_m};
  for (int i = 0; i < 2; ++i) {
    double delta[3], corr[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k) delta[k] = res->com_m[k] - pts[i][k];
    for (int j = 3 - res->rank; j < 3; ++j) {
      const double p = dot3(res->eigenvector[j], delta);
      for (int k = 0; k < 3; ++k) corr[k] += p * res->eigenvector[j][k];
    }
    for (int k = 0; k < 3; ++k) pts[i][k] += corr[k];
  }
  return ESTIMATE_OK;
}


/* Chord margins of face f at yaws k * pi / YAW_STEPS (pure geometry), robust to where the edge
 * line will be: the threshold line passes through the true CoM, which may lie +-e along the test
 * direction u from the estimate (e: the estimate's half width along u, at most
 * ESTIMATE_PLAN_OFFSET_M), so each margin is the smallest over lines at -e, 0 and +e. On a convex
 * patch that changes little; where the contact has gaps (two feet) a line that just crosses both
 * at the estimate but misses one a few mm away is not chosen. */
static estimate_status_t yaw_margins(run_t *run, const balance_face_t *f, double m[YAW_STEPS]) {
  enum { N = 3 * YAW_STEPS };
  double yaw[N], com[N][3], mj[N];
  for (int k = 0; k < YAW_STEPS; ++k) {
    double q[4], u[3];
    balance_orientation_yawed(f->orientation_wxyz, k * PI / YAW_STEPS, q);
    dir_of(q, u);
    const double e = run->have_solve ? fmin(dir_halfwidth(run, &run->last, u), ESTIMATE_PLAN_OFFSET_M)
                                     : ESTIMATE_PLAN_OFFSET_M;
    for (int j = 0; j < 3; ++j) {
      yaw[3 * k + j] = k * PI / YAW_STEPS;
      for (int i = 0; i < 3; ++i) com[3 * k + j][i] = run->guess_m[i] + (j - 1) * e * u[i];
    }
  }
  balance_status_t bs = balance_yaw_margins(run->mesh, f->orientation_wxyz, BALANCE_EDGE_PX, NULL,
                                            N, yaw, (const double(*)[3])com, mj);
  if (bs != BALANCE_OK) return fail(run, ESTIMATE_E_GEOMETRY, balance_status_str(bs));
  for (int k = 0; k < YAW_STEPS; ++k) m[k] = fmin(mj[3 * k], fmin(mj[3 * k + 1], mj[3 * k + 2]));
  return ESTIMATE_OK;
}

/* Face 1: two test directions at least min_dir_angle apart, both with a good chord margin. */
static estimate_status_t plan_first(run_t *run, int fi, face_plan_t *p) {
  double m[YAW_STEPS];
  estimate_status_t s = yaw_margins(run, &run->faces[fi], m);
  if (s != ESTIMATE_OK) return s;
  p->face = fi;
  p->score = -HUGE_VAL;
  int min_sep = (int)ceil(run->cfg->min_dir_angle_rad / (PI / YAW_STEPS) - 1e-9);
  for (int i = 0; i < YAW_STEPS; ++i) {
    for (int j = i + min_sep; j <= i + YAW_STEPS - min_sep; ++j) {
      int jj = j % YAW_STEPS;
      double sc = fmin(m[i], m[jj]);
      /* prefer perpendicular directions among near-equal margins */
      double sep = fabs(sin((j - i) * PI / YAW_STEPS));
      sc += 1e-4 * sep;
      if (sc > p->score) {
        p->score = sc;
        p->yaw[0] = i * PI / YAW_STEPS;
        p->yaw[1] = jj * PI / YAW_STEPS;
        p->margin[0] = m[i];
        p->margin[1] = m[jj];
      }
    }
  }
  return ESTIMATE_OK;
}

/* Face 1's second direction, planned after the first search moved the estimate: among yaws at
 * least min_dir_angle from yaw0 with a chord margin of twice the minimum (or the minimum when
 * none has that), the most perpendicular one, so that its sideways coordinate (along the edge) is
 * the one the first search measured. Keeps *yaw1 / *margin1 when no yaw qualifies. */
static estimate_status_t plan_partner(run_t *run, int fi, double yaw0, double *yaw1,
                                      double *margin1) {
  double m[YAW_STEPS];
  estimate_status_t s = yaw_margins(run, &run->faces[fi], m);
  if (s != ESTIMATE_OK) return s;
  for (int pass = 0; pass < 2; ++pass) {
    const double need = run->cfg->min_chord_margin_m * (pass == 0 ? 2.0 : 1.0);
    double best = -1.0;
    for (int k = 0; k < YAW_STEPS; ++k) {
      const double sep = fabs(sin(k * PI / YAW_STEPS - yaw0));
      if (!(m[k] >= need) || sep < sin(run->cfg->min_dir_angle_rad) - 1e-9) continue;
      const double sc = sep + 1e-6 * m[k]; /* ties: the larger margin */
      if (sc > best) {
        best = sc;
        *yaw1 = k * PI / YAW_STEPS;
        *margin1 = m[k];
      }
    }
    if (best >= 0.0) break;
  }
  return ESTIMATE_OK;
}

/* Face 2: one direction with the largest component along the first face's normal, among yaws
 * with a chord margin of twice the minimum (or the minimum when none has that). */
static estimate_status_t plan_second(run_t *run, int fi, const double n1[3], face_plan_t *p) {
  double m[YAW_STEPS];
  estimate_status_t s = yaw_margins(run, &run->faces[fi], m);
  if (s != ESTIMATE_OK) return s;
  p->face = fi;
  p->score = -HUGE_VAL;
  for (int pass = 0; pass < 2 && p->score == -HUGE_VAL; ++pass) {
    double need = run->cfg->min_chord_margin_m * (pass == 0 ? 2.0 : 1.0);
    for (int k = 0; k < YAW_STEPS; ++k) {
      if (!(m[k] >= need)) continue;
      double q[4], u[3];
      balance_orientation_yawed(run->faces[fi].orientation_wxyz, k * PI / YAW_STEPS, q);
      dir_of(q, u);
      double sc = fabs(dot3(u, n1));
      if (sc > p->score) {
        p->score = sc;
        p->yaw[0] = k * PI / YAW_STEPS;
        p->margin[0] = m[k];
      }
    }
  }
  return ESTIMATE_OK;
}

static int plan_cmp(const void *a, const void *b) {
  double sa = ((const face_plan_t *)a)->score, sb = ((const face_plan_t *)b)->score;
  return sa < sb ? 1 : sa > sb ? -1 : 0;
}

static int record_face(run_t *run, int fi) {
  estimate_result_t *out = run->out;
  if (out->face_count >= ESTIMATE_MAX_FACES) return -1;
  estimate_face_t *f = &out->face[out->face_count];
  memcpy(f->normal_link, run->faces[fi].normal_link, sizeof f->normal_link);
  f->area_m2 = run->faces[fi].area_m2;
  f->contact_area_m2 = run->faces[fi].patch_area_m2;
  f->regions = run->faces[fi].region_count;
  f->com_margin_m = run->faces[fi].com_margin_m;
  f->confirmed = 0;
  run->face_src[out->face_count] = fi;
  return (int)out->face_count++;
}

/* Check plans in order with a stable-pose trial; the first confirmed one's log index (or -1)
 * and its plan. */
static estimate_status_t confirm_first(run_t *run, const face_plan_t *plans, size_t np, int *rec_out,
                                       face_plan_t *chosen) {
  *rec_out = -1;
  for (size_t i = 0; i < np && *rec_out < 0; ++i) {
    int conf = 0, rec = record_face(run, plans[i].face);
    if (rec < 0) break;
    estimate_status_t s = stable_check(run, plans[i].face, rec, &conf);
    if (s != ESTIMATE_OK) return s;
    run->out->face[rec].confirmed = conf;
    if (conf) {
      *rec_out = rec;
      *chosen = plans[i];
    }
  }
  return ESTIMATE_OK;
}

/* Face 1: the flat, stable-candidate face with the best pair of chord margins, two searches. */
static estimate_status_t face_one(run_t *run, face_plan_t *plans, int *face_out) {
  size_t np = 0;
  for (size_t i = 0; i < run->nfaces; ++i) {
    if (!run->faces[i].flat || !run->faces[i].candidate) continue;
    estimate_status_t s = plan_first(run, (int)i, &plans[np]);
    if (s != ESTIMATE_OK) return s;
    if (plans[np].score >= run->cfg->min_chord_margin_m) ++np;
  }
  if (np == 0) return fail(run, ESTIMATE_E_GEOMETRY, "no flat face with two usable edge directions");
  qsort(plans, np, sizeof plans[0], plan_cmp);
  int first = -1;
  face_plan_t p1 = plans[0];
  estimate_status_t s = confirm_first(run, plans, np, &first, &p1);
  if (s != ESTIMATE_OK) return s;
  if (first < 0) return fail(run, ESTIMATE_E_NOPOSE, "no flat resting face was confirmed stable");
  qlearn_solve_result_t res;
  s = search_run(run, p1.face, first, p1.yaw[0], p1.margin[0], -1);
  if (s == ESTIMATE_OK) s = update_guess(run, &res);
  if (s == ESTIMATE_OK) s = plan_partner(run, p1.face, p1.yaw[0], &p1.yaw[1], &p1.margin[1]);
  if (s == ESTIMATE_OK) s = search_run(run, p1.face, first, p1.yaw[1], p1.margin[1], -1);
  if (s != ESTIMATE_OK) return s;
  *face_out = p1.face;
  return update_guess(run, &res);
}

/* Face 2: a flat stable face whose normal is not (anti)parallel to face 1's, one search. */
static estimate_status_t face_two(run_t *run, face_plan_t *plans, int face1) {
  const double *n1 = run->faces[face1].normal_link;
  const double cos_max = cos(run->cfg->min_face_angle_rad);
  size_t np = 0;
  for (size_t i = 0; i < run->nfaces; ++i) {
    const balance_face_t *f = &run->faces[i];
    if (!f->flat || !f->candidate || (int)i == face1) continue;
    if (fabs(dot3(f->normal_link, n1)) > cos_max) continue;
    estimate_status_t s = plan_second(run, (int)i, n1, &plans[np]);
    if (s != ESTIMATE_OK) return s;
    if (plans[np].score > 0.0) ++np;
  }
  if (np == 0) {
    snprintf(run->face2_note, sizeof run->face2_note,
             "no second flat resting face at >= %.0f deg to the first",
             run->cfg->min_face_angle_rad * 180.0 / PI);
    return ESTIMATE_OK;
  }
  qsort(plans, np, sizeof plans[0], plan_cmp);
  int second = -1;
  face_plan_t p2 = plans[0];
  estimate_status_t s = confirm_first(run, plans, np, &second, &p2);
  if (s != ESTIMATE_OK) return s;
  if (second < 0) {
    snprintf(run->face2_note, sizeof run->face2_note,
             "no second flat face was confirmed stable");
    return ESTIMATE_OK;
  }
  return search_run(run, p2.face, second, p2.yaw[0], p2.margin[0], -1);
}

/* How far the CoM can be from the current estimate along a (unit, link frame) at most: to the
 * farthest vertex, as it lies inside the object. */
static double hull_extent(const run_t *run, const double a[3]) {
  double ext = 0.0;
  const double g = dot3(run->guess_m, a);
  for (size_t i = 0; i < run->mesh->vertex_count; ++i)
    ext = fmax(ext, fabs(dot3(run->mesh->vertices_m[i], a) - g));
  return ext;
}

/* The deciding trials of search si (its bracket; with a noise model every clear trial within
 * c +- (h + 3 sigma)), checked at the current estimate: the smallest chord margin, less the
 * estimate's half width along the edge line (and 3 sigma of sideways placement noise). */
static double search_verified_margin(run_t *run, int si, const qlearn_solve_result_t *res,
                                     int *bounded) {
  const estimate_result_t *out = run->out;
  const estimate_search_t *sr = &out->search[si];
  const double sigma = run->cfg->noise_sigma_m;
  double worst = HUGE_VAL;
  *bounded = 1;
  for (size_t i = 0; i < out->trial_count; ++i) {
    const estimate_trial_t *t = &out->trial[i];
    if (t->search != si || !clear_outcome(t) || !deciding_trial(run, sr, i)) continue;
    if (balance_regime_classify(run->mesh, &t->released, run->backend->base_size_m,
                                BALANCE_EDGE_PX, run->guess_m, NULL, &run->regime) != BALANCE_OK ||
        !run->regime.patch.flat)
      return -HUGE_VAL;
    double r[3][3], along[3];
    model_quat_to_rot(t->released.orientation_wxyz, r);
    for (int k = 0; k < 3; ++k) along[k] = r[1][k]; /* world +y, the +X edge line, in the link */
    double ext = dir_halfwidth(run, res, along);
    if (!isfinite(ext)) {
      ext = hull_extent(run, along); /* the CoM is inside the object */
      *bounded = 0;
    }
    const double m = run->regime.chord_margin_m - ext - 3.0 * sigma;
    if (m < worst) worst = m;
  }
  return worst;
}

/* Search again on the face of search si, with the yaw of largest chord margin at the current
 * estimate among directions that keep the solve's shape: at least min_dir_angle from every
 * other search fed on that face (or, when no yaw qualifies, half that: an oblique pair still
 * determines the face's plane, and the bound widens with it), or (none fed there) within 30
 * degrees of the old direction; and at least 20 degrees from every direction that failed there. */
static int retest_yaw(run_t *run, const estimate_search_t *old, int fi, const double m[YAW_STEPS],
                      double min_angle) {
  const estimate_result_t *out = run->out;
  int siblings = 0;
  for (size_t j = 0; j < out->search_count; ++j)
    siblings += out->search[j].fed && out->search[j].face == old->face;
  int best = -1;
  for (int k = 0; k < 2 * YAW_STEPS; ++k) { /* yaw and yaw + pi share a chord */
    double q[4], u[3];
    balance_orientation_yawed(run->faces[fi].orientation_wxyz, k * PI / YAW_STEPS, q);
    dir_of(q, u);
    int ok = m[k % YAW_STEPS] >= run->cfg->min_chord_margin_m &&
             (siblings > 0 || dot3(u, old->dir_link) >= cos(PI / 6.0));
    for (size_t j = 0; ok && j < out->search_count; ++j) {
      const estimate_search_t *o = &out->search[j];
      if (o->face != old->face) continue;
      const double c = fabs(dot3(u, o->dir_link));
      if (o->fed && c > cos(min_angle) + 1e-9) ok = 0;
      if (!o->fed && c > cos(PI / 9.0)) ok = 0;
    }
    if (ok && (best < 0 || m[k % YAW_STEPS] > m[best % YAW_STEPS])) best = k;
  }
  return best;
}

static estimate_status_t search_retest(run_t *run, int si) {
  estimate_result_t *out = run->out;
  if (out->search_count >= ESTIMATE_MAX_SEARCHES) return ESTIMATE_OK;
  const estimate_search_t old = out->search[si];
  const int fi = run->face_src[old.face];
  double m[YAW_STEPS];
  estimate_status_t s = yaw_margins(run, &run->faces[fi], m);
  if (s != ESTIMATE_OK) return s;
  int best = retest_yaw(run, &old, fi, m, run->cfg->min_dir_angle_rad);
  if (best < 0) best = retest_yaw(run, &old, fi, m, 0.5 * run->cfg->min_dir_angle_rad);
  estimate_search_t *sr = &out->search[si];
  if (best < 0) {
    const size_t len = strlen(sr->note);
    snprintf(sr->note + len, sizeof sr->note - len, "; no other yaw spans the estimate");
    return ESTIMATE_OK;
  }
  sr->retested = 1;
  return search_run(run, fi, old.face, best * PI / YAW_STEPS, m[best % YAW_STEPS], si);
}

/* The next search to do again: one whose own trials left the flat-patch regime (its plane was
 * never used) and that was not done again yet; else the fed search whose check at the estimate
 * fails worst. Only checks the other planes can bound count: a search whose edge direction the
 * others leave undetermined stays fed but unverified (sr->verified 0), and the components that
 * depend on it are not claimed. -1: nothing to do. *unverified: the search returned failed its
 * check (and is to be unfed). */
static int worst_search(run_t *run, const qlearn_solve_result_t *res, int *unverified) {
  estimate_result_t *out = run->out;
  *unverified = 0;
  int worst = -1;
  for (size_t i = 0; i < out->search_count; ++i) {
    estimate_search_t *sr = &out->search[i];
    if (!sr->fed) continue;
    int bounded = 0;
    sr->verified_margin_m = search_verified_margin(run, (int)i, res, &bounded);
    sr->verified = bounded && sr->verified_margin_m >= run->cfg->verify_margin_m;
    if (!bounded || sr->verified) continue;
    if (worst < 0 || sr->verified_margin_m < out->search[worst].verified_margin_m) worst = (int)i;
  }
  for (size_t i = 0; i < out->search_count; ++i)
    if (!out->search[i].fed && out->search[i].flat_failed && !out->search[i].retested)
      return (int)i;
  *unverified = worst >= 0;
  return worst;
}

/* Solve, check every fed search's physics at the estimate, and drop the one that fails worst
 * (one bad plane moves the estimate, so the others are judged again without it); search again in
 * its place, or where a search's own trials left the flat-patch regime, while the retest budget
 * lasts. Bounded: every pass stops, unfeeds a search or spends a retest. */
static estimate_status_t verify_and_solve(run_t *run, qlearn_solve_result_t *res) {
  estimate_result_t *out = run->out;
  uint32_t retests = 0;
  for (int pass = 0; pass <= 3 * ESTIMATE_MAX_SEARCHES; ++pass) {
    estimate_status_t s = update_guess(run, res);
    if (s != ESTIMATE_OK) return s;
    int unverified = 0;
    const int w = worst_search(run, res, &unverified);
    if (w < 0) return ESTIMATE_OK;
    estimate_search_t *sw = &out->search[w];
    if (unverified) {
      sw->fed = 0;
      snprintf(sw->note, sizeof sw->note,
               "at the estimate its chord spans the interval along the edge by %.2f mm, under the "
               "%.2f mm needed", 1e3 * sw->verified_margin_m, 1e3 * run->cfg->verify_margin_m);
    }
    if (sw->retested || retests >= run->cfg->max_retests) {
      sw->retested = 1; /* no (more) retests: only unfeeding continues */
      if (!unverified) return ESTIMATE_OK;
      continue;
    }
    ++retests;
    s = search_retest(run, w);
    if (s != ESTIMATE_OK) return s;
    sw->retested = 1;
  }
  return update_guess(run, res);
}

/* Why component k is not found (or "" when it is). */
static void component_reason(run_t *run, int k, int determined, int unverified, double hw) {
  estimate_result_t *out = run->out;
  char r[sizeof out->reason[k]];
  if (out->found[k]) {
    r[0] = '\0';
  } else if (determined && unverified >= 0) {
    snprintf(r, sizeof r, "depends on search %d, whose chord cannot be checked: the estimate "
             "along its edge is not determined", unverified);
  } else if (determined) {
    snprintf(r, sizeof r, "its interval +-%.3f mm is wider than the %.3f mm limit", 1e3 * hw,
             1e3 * run->cfg->max_halfwidth_m);
  } else if (run->face2_note[0] && out->rank == 2) {
    snprintf(r, sizeof r, "not determined: %s", run->face2_note);
  } else {
    int last = -1; /* the last search that is not fed says most */
    for (size_t i = 0; i < out->search_count; ++i)
      if (!out->search[i].fed && out->search[i].note[0]) last = (int)i;
    if (last >= 0)
      snprintf(r, sizeof r, "not determined: search %d not used: %s", last,
               out->search[last].note);
    else
      snprintf(r, sizeof r, "not determined by the %d independent directions measured", out->rank);
  }
  memcpy(out->reason[k], r, sizeof r);
}

static estimate_status_t estimate_finish(run_t *run) {
  estimate_result_t *out = run->out;
  qlearn_solve_result_t res;
  estimate_status_t s = verify_and_solve(run, &res);
  if (s != ESTIMATE_OK) return s;
  out->rank = res.rank;
  out->chi2 = res.chi2;
  int missing = 0;
  for (int k = 0; k < 3; ++k) {
    const double e[3] = {k == 0, k == 1, k == 2};
    const int determined = dir_determined(&res, e);
    const double hw = dir_halfwidth(run, &res, e);
    const int unverified = determined ? dir_unverified(run, &res, e) : -1;
    out->found[k] = determined && unverified < 0 && hw <= run->cfg->max_halfwidth_m;
    out->halfwidth_m[k] = out->found[k] ? hw : INFINITY;
    /* not found: report the best guess (prior moved by what was measured), flagged as such */
    out->com_m[k] = out->found[k] ? res.com_m[k] : run->guess_m[k];
    component_reason(run, k, determined, unverified, hw);
    if (!out->found[k] && !missing++)
      snprintf(out->msg, sizeof out->msg, "%c not found: %s", "xyz"[k], out->reason[k]);
  }
  return ESTIMATE_OK;
}

static estimate_status_t estimate_body(run_t *run) {
  estimate_result_t *out = run->out;
  model_mass_t uni;
  if (model_mesh_mass(run->mesh, 1000.0, &uni) != MODEL_OK)
    return fail(run, ESTIMATE_E_GEOMETRY, "mass properties of the mesh");
  memcpy(out->uniform_com_m, uni.com_m, sizeof uni.com_m);
  memcpy(run->guess_m, uni.com_m, sizeof uni.com_m);
  memcpy(run->start_m, uni.com_m, sizeof uni.com_m);
  if (run->cfg->start == ESTIMATE_START_BBOX) {
    model_aabb_t box;
    if (model_mesh_aabb(run->mesh, &box) != MODEL_OK)
      return fail(run, ESTIMATE_E_GEOMETRY, "bounding box of the mesh");
    model_aabb_center(&box, run->start_m);
  }
  memcpy(out->start_m, run->start_m, sizeof out->start_m);
  for (int k = 0; k < 3; ++k) run->halfwidth_m[k] = INFINITY;

  balance_config_t bc;
  balance_config_default(&bc);
  memcpy(bc.base_size_m, run->backend->base_size_m, sizeof bc.base_size_m);
  balance_status_t bs = balance_world_create(&bc, &run->plan_world);
  if (bs == BALANCE_OK) bs = balance_object_create(run->plan_world, run->mesh, &uni, &run->plan_obj);
  if (bs != BALANCE_OK) {
    snprintf(out->msg, sizeof out->msg, "planning world: %s", balance_status_str(bs));
    return bs == BALANCE_E_NOMEM ? ESTIMATE_E_NOMEM : ESTIMATE_E_GEOMETRY;
  }
  bs = balance_faces_find(run->mesh, run->guess_m, NULL, run->faces, FACE_CAP, &run->nfaces);
  if (bs != BALANCE_OK) {
    snprintf(out->msg, sizeof out->msg, "faces: %s", balance_status_str(bs));
    return ESTIMATE_E_GEOMETRY;
  }
  if (run->nfaces > FACE_CAP) run->nfaces = FACE_CAP;
  int face1 = -1;
  estimate_status_t s = face_one(run, run->plans, &face1);
  if (s == ESTIMATE_OK) s = face_two(run, run->plans, face1);
  if (s == ESTIMATE_OK) s = estimate_finish(run);
  return s;
}

estimate_status_t estimate_run(const model_mesh_t *mesh_link, const estimate_backend_t *backend,
                               const estimate_config_t *cfg, estimate_result_t *out) {
  if (!mesh_link || !backend || !backend->run || !cfg || !out) return ESTIMATE_E_ARG;
  memset(out, 0, sizeof *out);
  for (int k = 0; k < 3; ++k) out->halfwidth_m[k] = INFINITY;
  if (!(cfg->resolution_m >= 1e-6 && cfg->resolution_m <= 1e-2) ||
      !(cfg->max_halfwidth_m > 0 && isfinite(cfg->max_halfwidth_m)) ||
      !(cfg->z > 0 && isfinite(cfg->z)) || !(cfg->min_chord_margin_m > 0) ||
      !isfinite(cfg->min_chord_margin_m) || !(cfg->min_dir_angle_rad > 0) ||
      !(cfg->min_dir_angle_rad <= PI / 2) || !(cfg->min_face_angle_rad > 0) ||
      !(cfg->min_face_angle_rad <= PI / 2) ||
      !(cfg->noise_sigma_m >= 0.0 && cfg->noise_sigma_m <= 0.1) ||
      !(cfg->noise_max_trials >= 1 && cfg->noise_max_trials <= 200) ||
      !(cfg->verify_margin_m >= 0.0 && cfg->verify_margin_m <= 0.02) || cfg->max_retests > 6 ||
      (cfg->start != ESTIMATE_START_UNIFORM && cfg->start != ESTIMATE_START_BBOX)) {
    snprintf(out->msg, sizeof out->msg, "bad estimator setting");
    return ESTIMATE_E_ARG;
  }
  for (int k = 0; k < 3; ++k)
    if (!(backend->base_size_m[k] > 0) || !isfinite(backend->base_size_m[k])) {
      snprintf(out->msg, sizeof out->msg, "backend reports a bad size of B");
      return ESTIMATE_E_ARG;
    }
  run_t *run = calloc(1, sizeof *run);
  if (!run) return ESTIMATE_E_NOMEM;
  run->mesh = mesh_link;
  run->backend = backend;
  run->cfg = cfg;
  run->out = out;
  run->noisy = cfg->noise_sigma_m > 0.0;
  out->noisy = run->noisy;
  estimate_status_t s = estimate_body(run);
  balance_world_destroy(run->plan_world);
  free(run);
  return s;
}
