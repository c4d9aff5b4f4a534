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
}

/* Everything one run needs; heap-allocated (the face list and the result are large). */
typedef struct {
  const model_mesh_t *mesh;
  const estimate_backend_t *backend;
  const estimate_config_t *cfg;
  estimate_result_t *out;
  balance_world_t *plan_world;  /* geometry only: B's size and the object's shape for planning */
  balance_object_t *plan_obj;   /* carries uniform-density mass properties, never the truth */
  double guess_m[3];            /* current CoM estimate, link frame */
  double halfwidth_m[3];        /* its half widths (INFINITY until a solve finds the component) */
  balance_face_t faces[FACE_CAP];
  size_t nfaces;
  balance_regime_t regime;      /* scratch (~4 KiB) */
  qlearn_policy_t policy;       /* the current search (~12 KiB for PBA) */
  qlearn_solve_t solve;
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

/* Chord margins of face f at yaws k * pi / YAW_STEPS (pure geometry). */
static estimate_status_t yaw_margins(run_t *run, const balance_face_t *f, double m[YAW_STEPS]) {
  for (int k = 0; k < YAW_STEPS; ++k) {
    balance_status_t bs = balance_yaw_margin(run->mesh, f->orientation_wxyz, run->guess_m,
                                             BALANCE_EDGE_PX, k * PI / YAW_STEPS, NULL, &m[k]);
    if (bs != BALANCE_OK) return fail(run, ESTIMATE_E_GEOMETRY, balance_status_str(bs));
  }
  return ESTIMATE_OK;
}

/* One 1-D search along the test direction of face_index at yaw_rad, fed to the plane list. */
static estimate_status_t search_run(run_t *run, int face_index, int log_face, double yaw_rad,
                                    double margin_m) {
  estimate_result_t *out = run->out;
  if (out->search_count >= ESTIMATE_MAX_SEARCHES)
    return fail(run, ESTIMATE_E_CAPACITY, "too many searches");
  int si = (int)out->search_count++;
  estimate_search_t *sr = &out->search[si];
  memset(sr, 0, sizeof *sr);
  sr->face = log_face;
  sr->yaw_rad = yaw_rad;
  sr->chord_margin_m = margin_m;

  double q[4], u[3];
  balance_orientation_yawed(run->faces[face_index].orientation_wxyz, yaw_rad, q);
  dir_of(q, u);
  memcpy(sr->dir_link, u, sizeof u);
  int comp = 0; /* the link axis this search determines most */
  for (int k = 1; k < 3; ++k)
    if (fabs(u[k]) > fabs(u[comp])) comp = k;
  /* Range: the object's extent along u (its bounding box in that direction), 1 mm inside at
   * each end: a CoM cannot lie on the hull surface, and a point at the very extreme over the edge
   * leaves nothing of the object over B to set it down on. */
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (size_t i = 0; i < run->mesh->vertex_count; ++i) {
    double p = dot3(run->mesh->vertices_m[i], u);
    if (p < lo) lo = p;
    if (p > hi) hi = p;
  }
  lo += 1e-3;
  hi -= 1e-3;
  double prior = dot3(run->guess_m, u);
  if (prior < lo) prior = lo;
  if (prior > hi) prior = hi;
  sr->prior_m = prior;
  sr->range_lo_m = lo;
  sr->range_hi_m = hi;

  qlearn_policy_config_t pc;
  qlearn_policy_config_default(run->cfg->policy, &pc);
  pc.range_lo_m = lo;
  pc.range_hi_m = hi;
  pc.prior_m = prior;
  pc.resolution_m = run->cfg->resolution_m;
  pc.seed = run->cfg->seed;
  if (run->cfg->policy == QLEARN_POLICY_PBA && run->cfg->noise_sigma_m > 0.0) {
    pc.noise = QLEARN_NOISE_PROBIT;
    pc.sigma_m = run->cfg->noise_sigma_m;
  }
  qlearn_policy_t *pol = &run->policy;
  qlearn_status_t qs = qlearn_policy_init(pol, &pc);
  if (qs != QLEARN_OK) {
    snprintf(out->msg, sizeof out->msg, "policy init: %s", qlearn_status_str(qs));
    return ESTIMATE_E_LEARNER;
  }
  const estimate_trial_t *lo_trial = NULL, *hi_trial = NULL; /* TIPS at the largest x, STAYS at
                                                                the smallest x */
  for (uint32_t n = 0; n < QLEARN_MAX_TRIALS && !qlearn_policy_done(pol); ++n) {
    double x;
    qs = qlearn_policy_next(pol, &x);
    if (qs == QLEARN_E_DONE) break;
    if (qs != QLEARN_OK) {
      snprintf(out->msg, sizeof out->msg, "policy next: %s", qlearn_status_str(qs));
      return ESTIMATE_E_LEARNER;
    }
    /* An unclear outcome (INVALID: still moving at the horizon, or SLIDES) says nothing about
     * the CoM: it is logged, flagged and not observed; the placement is retried a quarter of the
     * resolution further on (at most ESTIMATE_RETRIES times; the simulation is deterministic, so
     * the same pose would give the same answer). */
    estimate_trial_t *t = NULL;
    for (int attempt = 0; attempt <= ESTIMATE_RETRIES; ++attempt) {
      double xa = x + 0.25 * run->cfg->resolution_m * attempt * (attempt % 2 ? 1.0 : -1.0);
      if (xa < lo) xa = lo;
      if (xa > hi) xa = hi;
      double p_link[3];
      double gx = dot3(run->guess_m, u);
      for (int k = 0; k < 3; ++k) p_link[k] = run->guess_m[k] + (xa - gx) * u[k];
      estimate_trial_request_t req;
      memset(&req, 0, sizeof req);
      req.kind = ESTIMATE_TRIAL_EDGE;
      req.edge = BALANCE_EDGE_PX;
      balance_status_t bs = balance_pose_over_edge(run->plan_world, run->plan_obj, q,
                                                   BALANCE_EDGE_PX, p_link, 0.0, 1e-6,
                                                   &req.release);
      if (bs != BALANCE_OK) {
        snprintf(out->msg, sizeof out->msg, "planning a placement at x = %.6f m: %s", xa,
                 balance_status_str(bs));
        return ESTIMATE_E_GEOMETRY;
      }
      req.search = si;
      req.component = comp;
      req.direction = u[comp] >= 0.0 ? 1 : -1;
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
      estimate_status_t s = do_trial(run, &req, log_face, si, xa, &t);
      if (s != ESTIMATE_OK) return s;
      ++sr->trials;
      /* The placement actually achieved: its plane's offset along u (equal to xa when exact). */
      double n_obj[3], d;
      trial_plane(run, &t->released, n_obj, &d);
      double x_got = dot3(n_obj, u) > 0.99 ? d / dot3(n_obj, u) : xa;
      if (!(x_got >= lo && x_got <= hi)) x_got = xa;
      t->x_m = x_got;
      if (t->outcome == BALANCE_STAYS || t->outcome == BALANCE_TIPS) break;
      t = NULL;
    }
    if (!t) {
      snprintf(out->msg, sizeof out->msg, "search %d: no clear outcome near x = %.6f m", si, x);
      return ESTIMATE_OK; /* this search is not fed */
    }
    qlearn_outcome_t oc = t->outcome == BALANCE_STAYS ? QLEARN_STAYS : QLEARN_TIPS;
    qs = qlearn_policy_observe(pol, t->x_m, oc);
    if (qs != QLEARN_OK) {
      snprintf(out->msg, sizeof out->msg, "search %d: outcome refused by the policy: %s", si,
               qlearn_status_str(qs));
      return ESTIMATE_E_LEARNER;
    }
    if (oc == QLEARN_STAYS && (!hi_trial || t->x_m <= hi_trial->x_m)) hi_trial = t;
    if (oc == QLEARN_TIPS && (!lo_trial || t->x_m >= lo_trial->x_m)) lo_trial = t;
  }
  double c, hw;
  qs = qlearn_policy_estimate(pol, &c, &hw);
  if (qs != QLEARN_OK) {
    snprintf(out->msg, sizeof out->msg, "search %d: %s (the CoM is outside the range?)", si,
             qlearn_status_str(qs));
    return ESTIMATE_OK; /* this search is simply not fed */
  }
  sr->c_m = c;
  sr->halfwidth_m = hw;
  /* The threshold plane: between the two bracketing trials (their released poses), or from the one
   * trial and a range bound. Fed only when every trial that sets it is a flat-patch trial. */
  double n_obj[3] = {0, 0, 0}, d = 0.0;
  int nb = 0, ok = 1;
  const estimate_trial_t *ends[2] = {lo_trial, hi_trial};
  for (int e = 0; e < 2; ++e) {
    if (!ends[e]) continue;
    double ne[3], de;
    trial_plane(run, &ends[e]->released, ne, &de);
    de += (c - ends[e]->x_m) * dot3(ne, u); /* move it to the estimate c */
    for (int k = 0; k < 3; ++k) n_obj[k] += ne[k];
    d += de;
    ++nb;
    if (ends[e]->flagged) ok = 0;
  }
  if (nb == 0 || !ok) return ESTIMATE_OK;
  for (int k = 0; k < 3; ++k) sr->plane_n_obj[k] = n_obj[k] / nb;
  sr->plane_d_m = d / nb;
  sr->fed = 1;
  return ESTIMATE_OK;
}

/* The 3-D solve over the fed planes. */
static estimate_status_t solve_all(run_t *run, qlearn_solve_result_t *res) {
  qlearn_solve_t *solve = &run->solve;
  qlearn_solve_init(solve);
  for (size_t i = 0; i < run->out->search_count; ++i) {
    const estimate_search_t *sr = &run->out->search[i];
    if (!sr->fed) continue;
    /* bisect / paper: c uniform in the bracket (sigma = h / sqrt 3); PBA: a 95 % interval. */
    double sigma = run->cfg->policy == QLEARN_POLICY_PBA ? sr->halfwidth_m / 1.96
                                                         : sr->halfwidth_m / sqrt(3.0);
    if (!(sigma > 1e-9)) sigma = 1e-9; /* a collapsed (knife-edge) bracket */
    qlearn_status_t qs = qlearn_solve_add_plane(solve, sr->plane_n_obj, sr->plane_d_m, sigma);
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
  qlearn_status_t qs = qlearn_solve_compute(solve, run->cfg->z, run->cfg->max_halfwidth_m, res);
  if (qs != QLEARN_OK && qs != QLEARN_E_SINGULAR) {
    snprintf(run->out->msg, sizeof run->out->msg, "solve: %s", qlearn_status_str(qs));
    return ESTIMATE_E_LEARNER;
  }
  return ESTIMATE_OK;
}

/* Bound on the threshold bias of one flat-patch edge test in lib/balance (docs/physics.md: <= 2.4 um
 * measured, <= 5 um asserted by the accuracy tests). */
#define ESTIMATE_PHYSICS_BIAS_M 5e-6

/* A noiseless bracket (bisect, paper policies) holds each plane's threshold within its half width,
 * so the error of the least-squares solution is bounded by sum_j |P_kj| (h_j + bias), with P the
 * solve's weighted pseudo-inverse. A statistical z-sigma can be smaller than that bound when the
 * planes are oblique (an error in one plane spreads into several components); report the larger,
 * so the interval is a guarantee. Only when the planes determine all three components (rank 3). */
static void bound_halfwidths(const run_t *run, qlearn_solve_result_t *res) {
  if (run->cfg->policy == QLEARN_POLICY_PBA || res->rank != 3) return;
  double m[3][3] = {{0}};
  for (size_t i = 0; i < run->out->search_count; ++i) {
    const estimate_search_t *sr = &run->out->search[i];
    if (!sr->fed) continue;
    const double h = sr->halfwidth_m > 1e-9 ? sr->halfwidth_m : 1e-9, w = 3.0 / (h * h);
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) m[a][b] += w * sr->plane_n_obj[a] * sr->plane_n_obj[b];
  }
  /* inverse of the symmetric 3 x 3 normal matrix by cofactors */
  double inv[3][3];
  inv[0][0] = m[1][1] * m[2][2] - m[1][2] * m[2][1];
  inv[0][1] = m[0][2] * m[2][1] - m[0][1] * m[2][2];
  inv[0][2] = m[0][1] * m[1][2] - m[0][2] * m[1][1];
  inv[1][0] = m[1][2] * m[2][0] - m[1][0] * m[2][2];
  inv[1][1] = m[0][0] * m[2][2] - m[0][2] * m[2][0];
  inv[1][2] = m[0][2] * m[1][0] - m[0][0] * m[1][2];
  inv[2][0] = m[1][0] * m[2][1] - m[1][1] * m[2][0];
  inv[2][1] = m[0][1] * m[2][0] - m[0][0] * m[2][1];
  inv[2][2] = m[0][0] * m[1][1] - m[0][1] * m[1][0];
  const double det = m[0][0] * inv[0][0] + m[0][1] * inv[1][0] + m[0][2] * inv[2][0];
  if (!(fabs(det) > 0.0) || !isfinite(det)) return;
  double bound[3] = {0, 0, 0};
  for (size_t i = 0; i < run->out->search_count; ++i) {
    const estimate_search_t *sr = &run->out->search[i];
    if (!sr->fed) continue;
    const double h = sr->halfwidth_m > 1e-9 ? sr->halfwidth_m : 1e-9, w = 3.0 / (h * h);
    for (int k = 0; k < 3; ++k) {
      double p = 0.0; /* P_kj = w_j (M^-1 n_j)_k */
      for (int a = 0; a < 3; ++a) p += inv[k][a] / det * sr->plane_n_obj[a];
      bound[k] += fabs(w * p) * (sr->halfwidth_m + ESTIMATE_PHYSICS_BIAS_M);
    }
  }
  for (int k = 0; k < 3; ++k)
    if (res->found[k] && bound[k] > res->halfwidth_m[k]) res->halfwidth_m[k] = bound[k];
}

/* Move the guess so that it agrees with the fed searches (within their span): the components
 * found replace the prior's, the rest stays at the prior. */
static void update_guess(run_t *run) {
  qlearn_solve_result_t res;
  if (solve_all(run, &res) != ESTIMATE_OK || res.rank == 0) return;
  bound_halfwidths(run, &res);
  for (int k = 0; k < 3; ++k) run->halfwidth_m[k] = res.found[k] ? res.halfwidth_m[k] : INFINITY;
  /* Project: guess += V_r V_r^T (com - guess) over the non-null eigenvectors. */
  double delta[3];
  for (int k = 0; k < 3; ++k) delta[k] = res.com_m[k] - run->guess_m[k];
  double corr[3] = {0, 0, 0};
  for (int j = 3 - res.rank; j < 3; ++j) {
    double p = dot3(res.eigenvector[j], delta);
    for (int k = 0; k < 3; ++k) corr[k] += p * res.eigenvector[j][k];
  }
  for (int k = 0; k < 3; ++k) run->guess_m[k] += corr[k];
}

typedef struct {
  int face;
  double yaw[2];
  double margin[2];
  double score;
} face_plan_t;

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
  f->com_margin_m = run->faces[fi].com_margin_m;
  f->confirmed = 0;
  return (int)out->face_count++;
}

static estimate_status_t estimate_body(run_t *run) {
  estimate_result_t *out = run->out;
  const estimate_config_t *cfg = run->cfg;
  model_mass_t uni;
  if (model_mesh_mass(run->mesh, 1000.0, &uni) != MODEL_OK)
    return fail(run, ESTIMATE_E_GEOMETRY, "mass properties of the mesh");
  memcpy(out->uniform_com_m, uni.com_m, sizeof uni.com_m);
  memcpy(run->guess_m, uni.com_m, sizeof uni.com_m);
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

  /* ---- face 1: the flat, stable-candidate face with the best pair of chord margins ---- */
  face_plan_t plans[FACE_CAP];
  size_t np = 0;
  for (size_t i = 0; i < run->nfaces; ++i) {
    if (!run->faces[i].flat || !run->faces[i].candidate) continue;
    estimate_status_t s = plan_first(run, (int)i, &plans[np]);
    if (s != ESTIMATE_OK) return s;
    if (plans[np].score >= cfg->min_chord_margin_m) ++np;
  }
  if (np == 0) return fail(run, ESTIMATE_E_GEOMETRY, "no flat face with two usable edge directions");
  qsort(plans, np, sizeof plans[0], plan_cmp);
  int first = -1;
  face_plan_t p1 = plans[0];
  for (size_t i = 0; i < np && first < 0; ++i) {
    int conf = 0, rec = record_face(run, plans[i].face);
    if (rec < 0) break;
    estimate_status_t s = stable_check(run, plans[i].face, rec, &conf);
    if (s != ESTIMATE_OK) return s;
    out->face[rec].confirmed = conf;
    if (conf) {
      first = rec;
      p1 = plans[i];
    }
  }
  if (first < 0) return fail(run, ESTIMATE_E_NOPOSE, "no flat resting face was confirmed stable");
  for (int k = 0; k < 2; ++k) {
    estimate_status_t s = search_run(run, p1.face, first, p1.yaw[k], p1.margin[k]);
    if (s != ESTIMATE_OK) return s;
  }
  update_guess(run);

  /* ---- face 2: a flat stable face whose normal is not (anti)parallel to face 1's ---- */
  const double *n1 = run->faces[p1.face].normal_link;
  double cos_max = cos(cfg->min_face_angle_rad);
  np = 0;
  for (size_t i = 0; i < run->nfaces; ++i) {
    const balance_face_t *f = &run->faces[i];
    if (!f->flat || !f->candidate || (int)i == p1.face) continue;
    if (fabs(dot3(f->normal_link, n1)) > cos_max) continue;
    estimate_status_t s = plan_second(run, (int)i, n1, &plans[np]);
    if (s != ESTIMATE_OK) return s;
    if (plans[np].score > 0.0) ++np;
  }
  if (np == 0) {
    snprintf(out->msg, sizeof out->msg,
             "no second flat resting face at >= %.0f deg to the first: the component along its "
             "normal is not found",
             cfg->min_face_angle_rad * 180.0 / PI);
  }
  qsort(plans, np, sizeof plans[0], plan_cmp);
  int second = -1;
  for (size_t i = 0; i < np && second < 0; ++i) {
    int conf = 0, rec = record_face(run, plans[i].face);
    if (rec < 0) break;
    estimate_status_t s = stable_check(run, plans[i].face, rec, &conf);
    if (s != ESTIMATE_OK) return s;
    out->face[rec].confirmed = conf;
    if (conf) {
      second = rec;
      s = search_run(run, plans[i].face, rec, plans[i].yaw[0], plans[i].margin[0]);
      if (s != ESTIMATE_OK) return s;
    }
  }
  if (np > 0 && second < 0)
    snprintf(out->msg, sizeof out->msg,
             "no second flat face was confirmed stable: the component along the first face's "
             "normal is not found");

  /* ---- the 3-D solve; components not determined keep found = 0 ---- */
  qlearn_solve_result_t res;
  estimate_status_t s = solve_all(run, &res);
  if (s != ESTIMATE_OK) return s;
  bound_halfwidths(run, &res);
  out->rank = res.rank;
  out->chi2 = res.chi2;
  for (int k = 0; k < 3; ++k) {
    out->found[k] = res.found[k];
    out->halfwidth_m[k] = res.found[k] ? res.halfwidth_m[k] : INFINITY;
    /* not found: report the best guess (prior moved by what was measured), flagged as such */
    out->com_m[k] = res.found[k] ? res.com_m[k] : run->guess_m[k];
  }
  return ESTIMATE_OK;
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
      !(cfg->noise_sigma_m >= 0.0 && cfg->noise_sigma_m <= 0.1)) {
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
  estimate_status_t s = estimate_body(run);
  balance_world_destroy(run->plan_world);
  free(run);
  return s;
}
