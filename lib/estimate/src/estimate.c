/*
 * estimate.c - the estimator side of `comlearn estimate` (see estimate.h and docs/estimate.md).
 * Geometry only: this file must never include comlearn/model_inertial.h.
 */
#include "comlearn/estimate.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "comlearn/math3d.h"
#include "comlearn/model_outcome.h"
#include "comlearn/model_support.h"
#include "comlearn/qlearn_solve.h"
#include "pivot.h"

enum { FACE_CAP = 256, YAW_STEPS = 90, ESTIMATE_RETRIES = 3 }; /* 2-degree yaw sweep over [0, pi) */

/* A closed patch (a small convex facet of a rounded underside) is confirmed only when the object
 * stayed on it within this angle: off it, the object rolls onto a neighbouring facet, a few
 * degrees away on the meshes measured (docs/estimate.md, "Closed patches"). */
#define ESTIMATE_CLOSED_ROTATION_RAD 1e-3
/* An INVALID trial (the horizon came first) counts as at rest on a rough face when the object
 * turned by at most this much and moved by at most ESTIMATE_CREEP_M. A CoM beyond its support by
 * delta turns the object by alpha T^2 / 2 in the horizon T, alpha = g delta / k^2 with k <= R
 * (the farthest vertex): so delta <= 2 theta R^2 / (g T^2), which stays_bound adds (lib/balance's
 * and comlearn-sim's horizon T = 0.75 s; 7.7 um for a 0.12 m box turned by 5e-3 rad).
 * docs/estimate.md, "Rough faces". */
#define ESTIMATE_CREEP_ROTATION_RAD 5e-3
#define ESTIMATE_CREEP_M 2e-4
#define ESTIMATE_CREEP_HORIZON_S 0.75
/* What a STAYS bound allows for the simulation: at the threshold a trial can come to rest with
 * the CoM up to 0.5 um beyond B's edge in its settled pose (PBA bisecting a pebble's rough face
 * to 1e-7 m, shapegen pebble seed 23 uneven: soft contact and the rest test's residual motion). */
#define ESTIMATE_STAYS_SLACK_M 2e-6
/* With pose noise, the probability that a rough pair's side misses the CoM (pose_allowance): a
 * 95 % interval for the pair's plane, split over its two sides. */
#define ESTIMATE_POSE_MISS 0.025
/* With a noise model a closed patch needs only this much at the estimate (noiseless: the 1 mm of
 * verify_margin_m): the tens of um of bias nearer a side (58 um at 0.58 mm, a lumpy rock) are a
 * small part of a 95 % interval (0.27 mm mean half width at 0.5 mm noise), and 1 mm cost 490 of
 * 3324 noisy components over bench_coverage --seeds 6 (before rough faces with noise) for 0.2
 * points of coverage (97.9 -> 98.1 %). */
#define ESTIMATE_CLOSED_NOISY_MARGIN_M 2.5e-4
/* fall_steer: how far beyond its contact a fallen check puts the CoM, and how far the estimate
 * must have moved for fall_relist to list the phase's faces again. */
#define ESTIMATE_FALL_MARGIN_M 5e-4
#define ESTIMATE_RELIST_M 1e-4
enum {
  ESTIMATE_SETTLED_MAX = 8, /* faces taken from settled poses, per estimate */
  ESTIMATE_FALLS_MAX = 32,  /* stable checks' falls that steer the estimate (fall_steer) */
  ESTIMATE_FACE_REDO = 3    /* a face replaced by another closed patch, per estimate */
};

/* Bound on the threshold bias of one flat-patch edge test in lib/balance (docs/physics.md: <= 2.4
 * um measured down to a 0.97 mm chord margin, <= 5 um asserted by the accuracy tests). */
#define ESTIMATE_PHYSICS_BIAS_M 5e-6
/* ... except where a vertex of the face lies at B's edge line at the threshold: there the contact
 * at the corner moved it (docs/physics.md, "bias at a corner"; the cause was lib/balance's
 * contact reduction keeping a speculative point as a support's extreme, fixed 2026-12-04: such
 * planes of a 1792-object survey now <= 3.6 um; the budget is kept as measured before): 9.3 um with
 * a vertex 10.1 um beyond the line on rock_1's face F2, 5.4 um at 9.05 um, 7.4 um at 3.5-3.9 um on
 * a mug's side strip, mug 6008 uneven under PBA; 23.5 um on lumpy rock 3066 even under PBA, its
 * chord end 11 um inside the line and an inner vertex 4.7 um beyond). A plane whose threshold
 * interval has a vertex of its face within ESTIMATE_CORNER_NEAR_M of the edge line gets
 * ESTIMATE_CORNER_BIAS_M (noiseless: with a noise model the 95 % interval is hundreds of um
 * wide). */
#define ESTIMATE_CORNER_NEAR_M 2.5e-5
#define ESTIMATE_CORNER_BIAS_M 3e-5
/* The bias budget of a plane measured on a ring of edges (a torus lying flat): lib/balance's
 * thresholds on such rings lay up to 35.1 um inside the static one (bench/placements_dump, 16
 * lines of an even torus: 0, 10.2 or 35.1 um; docs/physics.md, "Cross-check with MuJoCo"), where
 * the ring's edges, not a face, meet the edge line; <= 4.3 um since the contact reduction keeps
 * touching points first (kept as measured before). */
#define ESTIMATE_RING_BIAS_M 5e-5
/* How far from the estimate (along the test direction) a planned edge line is checked. */
#define ESTIMATE_PLAN_OFFSET_M 3e-3
/* Two lengths that differ by no more than this are equal where a choice is made by them (the worst
 * check, a pivot's score): the backends agree to rounding only (an LCM release is FK(q) * grasp,
 * 1e-16 m off the one asked for), and a tie must break alike on every backend. */
#define ESTIMATE_TIE_M 1e-12

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
    case ESTIMATE_E_GEOMETRY: return "no usable resting face in the geometry";
    case ESTIMATE_E_BACKEND: return "trial backend failed";
    case ESTIMATE_E_NOPOSE: return "no resting face confirmed stable";
    case ESTIMATE_E_CAPACITY: return "too many trials";
    case ESTIMATE_E_LEARNER: return "learner error";
    case ESTIMATE_E_NOMEM: return "out of memory";
    case ESTIMATE_E_STATE: return "no trial is pending";
    case ESTIMATE_DONE: return "done";
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
  cfg->min_dir_angle_rad = CL_PI / 3.0;
  cfg->min_face_angle_rad = CL_PI / 6.0;
  cfg->noise_max_trials = 48;
  cfg->verify_margin_m = 0.001;
  cfg->max_retests = 3;
  cfg->closed_patches = 1;
  cfg->rough_faces = 1;
  cfg->noise_target_halfwidth_m = 5e-4;
  cfg->max_added_dirs = 3;
  cfg->fall_steering = 1;
  cfg->max_pivots = 4;
}

typedef struct {
  int face;
  double yaw[2];
  double margin[2];
  double score;
} face_plan_t;

/* What one search needs while its trials run. */
typedef struct {
  int si;        /* its index in out->search */
  int log_face;  /* its face in out->face */
  int comp;      /* the link axis it determines most */
  double q[4];   /* the resting orientation, yawed */
  double u[3];   /* the test direction, link frame */
  double lo, hi; /* its range */
  int pivot;     /* a pivot search: its edge is est->pivot[si] */
} search_ctx_t;

typedef enum {
  PHASE_START = 0,     /* nothing planned yet: the first estimate_next plans face 1 */
  PHASE_FACE1,         /* stable checks of face 1's candidates, in plan order */
  PHASE_FACE1_SEARCH0, /* face 1's first search */
  PHASE_FACE1_SEARCH1, /* face 1's second search */
  PHASE_FACE2,         /* stable checks of face 2's candidates */
  PHASE_FACE2_SEARCH,  /* face 2's search */
  PHASE_RETEST,        /* a search again, from the check at the estimate */
  PHASE_REFINE,        /* a noisy search resumed: a component is wider than the target */
  PHASE_MORE,          /* a direction more on a face already searched (yaw_more) */
  PHASE_PIVOT,         /* a pivot search (pivot_more) */
  PHASE_DONE,
  PHASE_FAILED
} phase_t;

/* The search whose trials are running: its context and where its walk stands. */
typedef struct {
  search_ctx_t sc;
  qlearn_policy_t *pol;             /* the walking policy: &est->policy, then &est->handover */
  qlearn_policy_config_t pc;        /* the walk's config (the handover starts from its range) */
  int in_handover;                  /* the PBA handover after a noisy walk is running */
  uint32_t n;                       /* trials the current walk observed */
  double x;                         /* the policy's proposed x for the trial in flight */
  int attempt;                      /* retries of that x after unclear outcomes */
  uint32_t *ran;                    /* counts the handover's trials (NULL during the walk) */
  char stopped[ESTIMATE_NOTE_SIZE]; /* why the walk ended early ("" when it did not) */
} walk_t;

/* Everything one estimate needs, in the block of estimate_create / estimate_init, followed there
 * by lib/model's work area (work): no trial allocates. */
struct estimate {
  const model_mesh_t *mesh; /* the caller's, link frame; must outlive the estimate */
  double base_size_m[3];    /* B */
  estimate_config_t cfg;    /* the caller's, copied */
  estimate_result_t result; /* what estimate_result shows */
  phase_t phase;
  estimate_status_t status; /* of the failure, once phase is PHASE_FAILED */
  /* The trial asked for and not yet observed, with what its log entry needs. */
  int pending;
  int refused; /* the last reply was refused (its message is in out->msg) */
  estimate_trial_request_t req;
  int req_face;   /* its face in out->face */
  double req_x_m; /* edge trial: the x planned */
  /* Face choice: the candidate plans being confirmed, in order. */
  size_t np, ci;      /* plans and the one being checked */
  face_plan_t chosen; /* the confirmed plan of face 1 / face 2 */
  int chosen_log;     /* its index in out->face */
  int face1;          /* face 1's index in faces[] */
  walk_t walk;
  uint32_t retests; /* verify_loop: retests spent, the pass, the search redone */
  int pass;
  int retest_of;
  double guess_m[3];     /* current CoM estimate, link frame (planning) */
  double start_m[3];     /* where the next search starts: cfg->start, moved alike */
  double halfwidth_m[3]; /* its half widths (INFINITY until a solve finds the component) */
  int noisy;             /* cfg->noise_sigma_m > 0 */
  char face2_note[ESTIMATE_NOTE_SIZE]; /* why the second face gave no search ("" if it did) */
  int face_src[ESTIMATE_MAX_FACES];    /* out->face[i] is faces[face_src[i]] */
  model_face_t faces[FACE_CAP];
  size_t nfaces;
  size_t nflat_list;    /* faces[0, nflat_list) are model_faces_find's flat candidates; the
                           rest closed patches (model_faces_stable's, settled poses') */
  int closed1, closed2; /* face 1's / face 2's closed patches were listed */
  int rough1, rough2;   /* face 1's / face 2's rough faces were listed */
  int line2;            /* face 2's faces along face 1's normal were listed (line_once) */
  int line_late;        /* ... only after the checks, for a component too wide (wide_more) */
  uint32_t more;        /* directions yaw_more added */
  uint32_t pivots;      /* pivot searches started (pivot_more) */
  estimate_pivot_t pivot[ESTIMATE_MAX_SEARCHES]; /* the edge of each pivot search */
  int more_si; /* the search of the last, and the widest component not found before */
  double more_before_m;
  unsigned char rough[FACE_CAP]; /* faces[i] is searched as a rough face: by its stays bounds */
  int mirror_next;               /* the search about to start mirrors this one (-1: none) */
  unsigned char search_rough[ESTIMATE_MAX_SEARCHES]; /* bounded by its STAYS trials (a rough
                                                        face's, or one made so, rough_retest) */
  double target_scale; /* of cfg->noise_target_halfwidth_m: 1, ESTIMATE_CLOSED_TARGET_SCALE */
  /* The first closed patch of this phase whose stable check came to rest but rolled off it (not
   * confirmed as a patch): searched as a rough face when nothing else is left (spare_rough). */
  face_plan_t spare;
  int spare_log;
  int spare_phase;        /* the phase it belongs to, -1: none */
  uint32_t face_redos;    /* faces chosen again after their closed patch failed (face_redo) */
  int face1_redone;       /* face 1 was replaced: its new searches go straight to the check */
  int redo_of;            /* the search that face_redo replaces, or -1 */
  int redo_face;          /* the face (out->face) that face_redo replaces as face 1, or -1 */
  size_t closed_from;     /* the closed patches planned in this phase: faces[closed_from, ...) */
  uint32_t found_settled; /* faces added from settled poses (at most ESTIMATE_SETTLED_MAX) */
  /* Falls of stable checks on closed patches and rough faces: the CoM lies beyond the face's
   * contact in the direction the object fell, fall_a[i] . c >= fall_b[i] (fall_steer). */
  double fall_a[ESTIMATE_FALLS_MAX][3];
  double fall_b[ESTIMATE_FALLS_MAX];
  uint32_t falls;
  int steered; /* guess_m was steered in this face phase; unsteered_m is the one before */
  double unsteered_m[3];
  int list_rough;        /* the phase's pending plans are its closed patches (0) or rough faces
                            (1) listed under listed_at_m; -1: another list, not listed again */
  double listed_at_m[3]; /* the estimate that list was made under */
  face_plan_t plans[FACE_CAP];           /* the candidates of face 1, then of face 2 */
  model_regime_t regime;                 /* scratch (~4 KiB) */
  double bounds[2][ESTIMATE_MAX_TRIALS]; /* scratch: a rough pair's STAYS bounds (rough_plane) */
  model_support_work_t *work;            /* the geometry's scratch memory, after this struct */
  qlearn_policy_t policy;                /* the current search (~12 KiB for PBA) */
  qlearn_policy_t handover;              /* PBA after a noisy walk */
  qlearn_solve_t solve;
  qlearn_solve_result_t res; /* the latest solve (update_guess) */
  int have_solve;
};
typedef struct estimate est_t;

/* Link-frame direction of world +x (the +X edge's normal) for orientation q: R^T e_x. */
static void dir_of(const double q[4], double dir[3]) {
  double r[3][3];
  model_quat_to_rot(q, r);
  for (int k = 0; k < 3; ++k) dir[k] = r[0][k];
}

/* The threshold plane of a trial released at `pose` over the +X edge: n_obj . c = d. */
static void trial_plane(const est_t *est, const model_pose_t *pose, double n_obj[3], double *d_m) {
  double n[3], d_edge, r[3][3];
  model_edge_line(est->base_size_m, MODEL_EDGE_PX, n, &d_edge);
  model_quat_to_rot(pose->orientation_wxyz, r);
  for (int k = 0; k < 3; ++k) n_obj[k] = r[0][k] * n[0] + r[1][k] * n[1] + r[2][k] * n[2];
  *d_m = d_edge - cl_vec3_dot(n, pose->position_m);
}

static estimate_status_t fail(est_t *est, estimate_status_t s, const char *what) {
  snprintf(est->result.msg, sizeof est->result.msg, "%s", what);
  return s;
}

/* The request fields every trial carries for records: the running estimate before it. */
static void request_common(const est_t *est, estimate_trial_request_t *req) {
  memcpy(req->com_before_m, est->guess_m, sizeof req->com_before_m);
  memcpy(req->halfwidth_before_m, est->halfwidth_m, sizeof req->halfwidth_before_m);
}

/* Ask for a trial: it is pending until estimate_observe brings its reply. */
static estimate_status_t request(est_t *est, const estimate_trial_request_t *req, int face,
                                 double x_m) {
  if (est->result.trial_count >= ESTIMATE_MAX_TRIALS)
    return fail(est, ESTIMATE_E_CAPACITY, "trial log full");
  est->req = *req;
  est->req_face = face;
  est->req_x_m = x_m;
  est->pending = 1;
  return ESTIMATE_OK;
}

static estimate_outcome_t seen_outcome(const est_t *est, const estimate_trial_t *t);

/* Search si is a pivot search (pivot_more). */
static int search_pivot(const est_t *est, int si) {
  return si >= 0 && (size_t)si < est->result.search_count && est->result.search[si].pivot;
}

/* Log the pending trial with its reply. */
static estimate_trial_t *log_trial(est_t *est, const estimate_trial_reply_t *reply) {
  estimate_result_t *out = &est->result;
  const estimate_trial_request_t *req = &est->req;
  estimate_trial_t *t = &out->trial[out->trial_count++];
  memset(t, 0, sizeof *t);
  t->kind = req->kind;
  memcpy(t->target_link_m, req->target_link_m, sizeof t->target_link_m);
  t->face = est->req_face;
  t->search = req->search;
  t->x_m = est->req_x_m;
  t->outcome = reply->outcome;
  t->regime = -1;
  t->chord_margin_m = NAN;
  t->released = reply->released;
  t->settled = reply->settled;
  if (req->kind == ESTIMATE_TRIAL_STABLE) {
    ++out->stable_trials;
  } else if (search_pivot(est, req->search)) {
    /* what it says depends only on which way it turned (estimate_pivot_outcome) */
    t->chord_margin_m = estimate_pivot_side_margin(&est->pivot[req->search], est->guess_m);
    t->flagged = estimate_pivot_outcome(reply->outcome, &reply->released, &reply->settled) ==
                 ESTIMATE_INVALID;
    if (t->flagged) ++out->flagged_trials;
  } else {
    /* Classify what was actually released, with the current estimate: only flat-patch trials
     * measure the CoM (docs/physics.md, "Where an edge test measures the CoM exactly"). */
    model_regime_t *reg = &est->regime;
    model_status_t ms = model_regime_classify_in(est->mesh, &reply->released, est->base_size_m,
                                                 req->edge, est->guess_m, NULL, est->work, reg);
    if (ms == MODEL_OK) {
      t->regime = (int)reg->kind;
      t->chord_margin_m = reg->chord_margin_m;
    }
    t->flagged = ms != MODEL_OK || !reg->flat_patch_regime ||
                 (reply->outcome != ESTIMATE_STAYS && reply->outcome != ESTIMATE_TIPS);
    if (t->flagged) ++out->flagged_trials;
  }
  est->pending = 0;
  t->counted = req->kind == ESTIMATE_TRIAL_STABLE ? t->outcome : seen_outcome(est, t);
  return t;
}

/* faces[fi] is a closed patch (from model_faces_stable or a settled pose), not a flat face. */
static int face_is_closed(const est_t *est, int fi) {
  return fi >= 0 && !est->rough[fi] && est->faces[fi].closed && !est->faces[fi].flat;
}

/* Search si is bounded by its STAYS trials, from both sides (a rough face's, or rough_retest). */
static int search_rough(const est_t *est, int si) {
  return si >= 0 && (size_t)si < est->result.search_count && est->search_rough[si];
}

/* How far trial t's object turned and moved from its release to where it settled. */
static double trial_turned_rad(const estimate_trial_t *t) {
  return cl_quat_angle(t->settled.orientation_wxyz, t->released.orientation_wxyz);
}

static double trial_moved_m(const estimate_trial_t *t) {
  double d[3];
  cl_vec3_sub(t->settled.position_m, t->released.position_m, d);
  return sqrt(cl_vec3_dot(d, d));
}

/* Came to rest: STAYS, or on a rough face the horizon came while the object barely crept
 * (ESTIMATE_CREEP_*: what lib/balance reports on faces of many noise peaks, docs/physics.md). */
static int at_rest(const estimate_trial_t *t, int rough) {
  if (t->outcome == ESTIMATE_STAYS) return 1;
  return rough && t->outcome == ESTIMATE_INVALID &&
         trial_turned_rad(t) <= ESTIMATE_CREEP_ROTATION_RAD && trial_moved_m(t) <= ESTIMATE_CREEP_M;
}

/* The outcome an edge trial counts as: in a rough search a barely creeping INVALID is a STAYS
 * (at_rest). (Counting every INVALID of a rough search as "did not tip" was tried: 2 fewer
 * components found over bench_coverage's 224 objects.) */
static estimate_outcome_t seen_outcome(const est_t *est, const estimate_trial_t *t) {
  if (search_pivot(est, t->search))
    return estimate_pivot_outcome(t->outcome, &t->released, &t->settled);
  return at_rest(t, search_rough(est, t->search)) ? ESTIMATE_STAYS : t->outcome;
}

/* The same face: unit normals within 1e-3 rad (model_faces_find's merge angle). */
static int same_normal(const double a[3], const double b[3]) {
  return cl_vec3_dot(a, b) > cos(1e-3);
}

/* Set the object down in `face`'s resting orientation with the current estimate over B's middle;
 * it rests stably when it stays, barely moved (stable_confirmed). */
static estimate_status_t stable_request(est_t *est, int face_index, int log_face) {
  const model_face_t *f = &est->faces[face_index];
  estimate_trial_request_t req;
  memset(&req, 0, sizeof req);
  req.kind = ESTIMATE_TRIAL_STABLE;
  req.edge = MODEL_EDGE_PX;
  req.search = -1;
  req.component = -1;
  req.direction = 0;
  memcpy(req.target_link_m, est->guess_m, sizeof req.target_link_m);
  request_common(est, &req);
  double r[3][3];
  memcpy(req.release.orientation_wxyz, f->orientation_wxyz, sizeof f->orientation_wxyz);
  model_quat_to_rot(f->orientation_wxyz, r);
  double bottom = model_mesh_bottom_z(est->mesh, f->orientation_wxyz);
  if (!isfinite(bottom)) return fail(est, ESTIMATE_E_GEOMETRY, "resting orientation not usable");
  for (int i = 0; i < 2; ++i)
    req.release.position_m[i] =
        -(r[i][0] * est->guess_m[0] + r[i][1] * est->guess_m[1] + r[i][2] * est->guess_m[2]);
  req.release.position_m[2] = -bottom - 1e-6; /* touching: 1 um pre-penetrated, never dropped */
  return request(est, &req, log_face, 0.0);
}

/* Did the stable check t confirm its face? On a closed patch it must barely have turned; a rough
 * face may also have crept at the horizon (at_rest). */
static int stable_confirmed(const estimate_trial_t *t, int closed, int rough) {
  model_stable_config_t sc;
  model_stable_config_default(&sc);
  if (closed) sc.max_rotation_rad = ESTIMATE_CLOSED_ROTATION_RAD;
  return at_rest(t, rough) && trial_turned_rad(t) <= sc.max_rotation_rad &&
         trial_moved_m(t) <= sc.max_displacement_m;
}

/* The range of a search along u: the object's extent along u, min(1 mm, a quarter of it) inside
 * at each end (a CoM cannot lie on the hull surface, and a point at the very extreme over the
 * edge leaves nothing of the object over B to set it down on). */
static void search_range(const est_t *est, const double u[3], double *lo, double *hi) {
  *lo = HUGE_VAL;
  *hi = -HUGE_VAL;
  for (size_t i = 0; i < est->mesh->vertex_count; ++i) {
    const double p = cl_vec3_dot(est->mesh->vertices_m[i], u);
    if (p < *lo) *lo = p;
    if (p > *hi) *hi = p;
  }
  /* a 2.1 mm plate's thickness: 0.05 mm would be left of it with the full 1 mm */
  const double trim = fmin(1e-3, 0.25 * (*hi - *lo));
  *lo += trim;
  *hi -= trim;
}

/* v lies in face f's plane (within tol). */
static int on_plane(const model_face_t *f, const double v[3], double tol) {
  return f->offset_m - cl_vec3_dot(f->normal_link, v) <= tol;
}

/* The extent along u of face f's vertices in its plane: [*a, *b] (HUGE_VAL, -HUGE_VAL when none
 * lies there). */
static void face_extent(const est_t *est, const model_face_t *f, const double u[3], double *a,
                        double *b) {
  model_regime_config_t rc;
  model_regime_config_default(&rc);
  *a = HUGE_VAL;
  *b = -HUGE_VAL;
  for (size_t i = 0; i < est->mesh->vertex_count; ++i) {
    const double *v = est->mesh->vertices_m[i];
    if (!on_plane(f, v, rc.plane_tol_m)) continue;
    *a = fmin(*a, cl_vec3_dot(v, u));
    *b = fmax(*b, cl_vec3_dot(v, u));
  }
}

/* On a closed patch the confirmed face holds the CoM's projection: the range is the patch's
 * extent along u (face_extent), inside the object's. */
static void search_range_closed(const est_t *est, const model_face_t *f, const double u[3],
                                double *lo, double *hi) {
  double a, b;
  face_extent(est, f, u, &a, &b);
  if (a > *lo) *lo = a;
  if (b < *hi) *hi = b;
}

/* Vertex vi lies on the boundary of the real contact on face f's plane: the angles of the
 * in-plane triangles around it add up to less than a full turn. O(triangles). */
static int contact_boundary(const model_mesh_t *m, const model_face_t *f, uint32_t vi, double tol) {
  double turn = 0.0;
  for (size_t t = 0; t < m->triangle_count; ++t) {
    const uint32_t *tri = m->triangles[t];
    int k = 0;
    while (k < 3 && tri[k] != vi) ++k;
    if (k == 3 || !on_plane(f, m->vertices_m[tri[(k + 1) % 3]], tol) ||
        !on_plane(f, m->vertices_m[tri[(k + 2) % 3]], tol))
      continue;
    double a[3], b[3];
    cl_vec3_sub(m->vertices_m[tri[(k + 1) % 3]], m->vertices_m[vi], a);
    cl_vec3_sub(m->vertices_m[tri[(k + 2) % 3]], m->vertices_m[vi], b);
    double ab[3];
    cl_vec3_cross(a, b, ab);
    turn += atan2(cl_vec3_norm(ab), cl_vec3_dot(a, b));
  }
  return turn < 2.0 * CL_PI - 1e-6;
}

/* A vertex on the boundary of face f's real contact within ESTIMATE_CORNER_NEAR_M of B's edge
 * line for some release in search sr's threshold interval: placed at x, a link point v lies
 * u . v - x beyond the line (u the test direction, world +x). Inner vertices of a flat patch
 * do not count (a vertex 6.45 um beyond the line that was not a chord end moved nothing). */
static int corner_at_edge(const est_t *est, const estimate_search_t *sr, const model_face_t *f) {
  model_regime_config_t rc;
  model_regime_config_default(&rc);
  const double reach = ESTIMATE_CORNER_NEAR_M + sr->halfwidth_m;
  for (size_t i = 0; i < est->mesh->vertex_count; ++i) {
    const double *v = est->mesh->vertices_m[i];
    if (on_plane(f, v, rc.plane_tol_m) && fabs(cl_vec3_dot(sr->dir_link, v) - sr->c_m) <= reach &&
        contact_boundary(est->mesh, f, (uint32_t)i, rc.plane_tol_m))
      return 1;
  }
  return 0;
}

/* Plan the placement of link point g + (x - u.g) u over the +X edge and ask for it. */
static estimate_status_t edge_request(est_t *est, const search_ctx_t *sc, double xa) {
  estimate_result_t *out = &est->result;
  double p_link[3];
  const double gx = cl_vec3_dot(est->guess_m, sc->u);
  for (int k = 0; k < 3; ++k) p_link[k] = est->guess_m[k] + (xa - gx) * sc->u[k];
  estimate_trial_request_t req;
  memset(&req, 0, sizeof req);
  req.kind = ESTIMATE_TRIAL_EDGE;
  req.edge = MODEL_EDGE_PX;
  model_status_t ms = model_pose_over_edge(est->mesh, est->base_size_m, sc->q, MODEL_EDGE_PX,
                                           p_link, 0.0, 1e-6, &req.release);
  if (ms != MODEL_OK) {
    snprintf(out->msg, sizeof out->msg, "planning a placement at x = %.6f m: %s", xa,
             model_status_str(ms));
    return ESTIMATE_E_GEOMETRY;
  }
  req.search = sc->si;
  req.component = sc->comp;
  req.direction = sc->u[sc->comp] >= 0.0 ? 1 : -1;
  memcpy(req.target_link_m, p_link, sizeof p_link);
  request_common(est, &req);
  /* the planned pose's regime, as log_trial classifies the released one */
  req.flat_patch = 0;
  req.sideways_margin_m = -HUGE_VAL;
  if (model_regime_classify_in(est->mesh, &req.release, est->base_size_m, req.edge, est->guess_m,
                               NULL, est->work, &est->regime) == MODEL_OK) {
    req.flat_patch = est->regime.flat_patch_regime != 0;
    req.sideways_margin_m = est->regime.chord_margin_m;
  }
  return request(est, &req, sc->log_face, xa);
}

/* Plan pivot search sc's trial at x (the object tilted about its edge, the edge on B's +X edge
 * line, touching: 1 um pre-penetrated) and ask for it: 0. 1 (nothing asked, *why says it) when
 * the pose does not rest on the edge's two ends. */
static int pivot_request(est_t *est, const search_ctx_t *sc, double xa, estimate_status_t *s,
                         char *why, size_t why_size) {
  const estimate_pivot_t *pv = &est->pivot[sc->si];
  estimate_trial_request_t req;
  memset(&req, 0, sizeof req);
  req.kind = ESTIMATE_TRIAL_EDGE;
  req.edge = MODEL_EDGE_PX;
  if (!estimate_pivot_pose(pv, est->mesh, est->base_size_m, xa, 1e-6, &req.release)) {
    snprintf(why, why_size, "at x = %.3f mm the object does not rest on its edge's ends", 1e3 * xa);
    return 1;
  }
  req.search = sc->si;
  req.component = sc->comp;
  req.direction = sc->u[sc->comp] >= 0.0 ? 1 : -1;
  memcpy(req.target_link_m, pv->mid_m, sizeof req.target_link_m);
  request_common(est, &req);
  req.flat_patch = 0;
  req.sideways_margin_m = estimate_pivot_side_margin(pv, est->guess_m);
  *s = request(est, &req, -1, xa);
  return 0;
}

/* Log an edge trial's reply; t->x_m becomes the x actually achieved. */
static estimate_trial_t *edge_logged(est_t *est, const search_ctx_t *sc,
                                     const estimate_trial_reply_t *reply) {
  const double xa = est->req_x_m;
  estimate_trial_t *t = log_trial(est, reply);
  ++est->result.search[sc->si].trials;
  /* The placement actually achieved: its plane's offset along u (equal to xa when exact). */
  double n_obj[3], d, x_got;
  trial_plane(est, &t->released, n_obj, &d);
  if (sc->pivot) /* its tilt about the edge */
    x_got = estimate_pivot_x(&est->pivot[sc->si], t->released.orientation_wxyz);
  else
    x_got = cl_vec3_dot(n_obj, sc->u) > 0.99 ? d / cl_vec3_dot(n_obj, sc->u) : xa;
  /* achieved to rounding (an LCM release is FK(q) * grasp: 1e-16 m off): the one asked for, so
   * that ties later break alike on every backend */
  if (!(x_got >= sc->lo && x_got <= sc->hi) || fabs(x_got - xa) <= 1e-12) x_got = xa;
  t->x_m = x_got;
  return t;
}

static int clear_outcome(const est_t *est, const estimate_trial_t *t) {
  const estimate_outcome_t o = seen_outcome(est, t);
  return o == ESTIMATE_STAYS || o == ESTIMATE_TIPS;
}

/* Record a clear trial's outcome in a policy. */
static qlearn_status_t observe_trial(const est_t *est, qlearn_policy_t *pol,
                                     const estimate_trial_t *t) {
  return qlearn_policy_observe(pol, t->x_m,
                               seen_outcome(est, t) == ESTIMATE_STAYS ? QLEARN_STAYS : QLEARN_TIPS);
}

/* Does trial i (of search sr, clear) set the threshold? Noiseless: it is one of the two
 * bracketing trials; with a noise model: it lies within c +- (h + 3 sigma). */
static int deciding_trial(const est_t *est, const estimate_search_t *sr, size_t i) {
  if (!est->noisy) return (int)i == sr->lo_trial || (int)i == sr->hi_trial;
  return fabs(est->result.trial[i].x_m - sr->c_m) <= sr->halfwidth_m + 3.0 * est->cfg.noise_sigma_m;
}

/* The probit noise model of cfg->noise_sigma_m in a PBA config. Its search stops at width_m
 * when > 0 (a resumed search, refine_next), else at cfg->noise_stop_width_m when set, else at
 * max(resolution, sigma, twice the target half width); at most the range. */
static void probit_config(const est_t *est, qlearn_policy_config_t *pc, double width_m) {
  const estimate_config_t *cfg = &est->cfg;
  pc->noise = QLEARN_NOISE_PROBIT;
  pc->sigma_m = cfg->noise_sigma_m;
  pc->resolution_m =
      width_m > 0.0 ? width_m
      : cfg->noise_stop_width_m > 0.0
          ? cfg->noise_stop_width_m
          : fmax(fmax(cfg->resolution_m, cfg->noise_sigma_m), 2.0 * cfg->noise_target_halfwidth_m);
  if (pc->resolution_m > pc->range_hi_m - pc->range_lo_m)
    pc->resolution_m = pc->range_hi_m - pc->range_lo_m;
}

static estimate_status_t search_done(est_t *est);
static estimate_status_t walk_end(est_t *est);
static estimate_status_t search_start(est_t *est, int face_index, int log_face, double yaw_rad,
                                      double margin_m, int retest_of);
static void search_plane(est_t *est, const search_ctx_t *sc);
static void pivot_plane(est_t *est, const search_ctx_t *sc);
static void search_estimate(est_t *est, const search_ctx_t *sc, const qlearn_policy_t *pol);

/* Ask for the walk's trial at its x, moved by a quarter of the resolution per retry. */
static estimate_status_t walk_request(est_t *est) {
  walk_t *w = &est->walk;
  const int attempt = w->attempt;
  double xa = w->x + 0.25 * est->cfg.resolution_m * attempt * (attempt % 2 ? 1.0 : -1.0);
  if (xa < w->sc.lo) xa = w->sc.lo;
  if (xa > w->sc.hi) xa = w->sc.hi;
  if (!w->sc.pivot) return edge_request(est, &w->sc, xa);
  estimate_status_t s = ESTIMATE_OK;
  return pivot_request(est, &w->sc, xa, &s, w->stopped, sizeof w->stopped) ? walk_end(est) : s;
}

/* The next trial the walking policy asks for, or the walk's end. */
static estimate_status_t walk_next(est_t *est) {
  walk_t *w = &est->walk;
  if (!(w->n < QLEARN_MAX_TRIALS && !qlearn_policy_done(w->pol))) return walk_end(est);
  const double last_x = w->x;
  const int last_retried = w->n > 0 && w->attempt > 0;
  qlearn_status_t qs = qlearn_policy_next(w->pol, &w->x);
  if (qs == QLEARN_E_DONE) return walk_end(est);
  if (qs != QLEARN_OK) {
    snprintf(est->result.msg, sizeof est->result.msg, "policy next: %s", qlearn_status_str(qs));
    return ESTIMATE_E_LEARNER;
  }
  /* The last x needed retries, and the clear outcome they found told the policy nothing new: it
   * asks for the same x again, and would forever. */
  if (last_retried && w->x == last_x) {
    snprintf(w->stopped, sizeof w->stopped, "no clear outcome near x = %.3f mm", 1e3 * w->x);
    return walk_end(est);
  }
  w->attempt = 0;
  return walk_request(est);
}

/* An edge trial's reply. An unclear outcome (INVALID: still moving at the horizon, or SLIDES) says
 * nothing about the CoM: it is logged, flagged and not observed; the placement is retried a
 * quarter of the resolution further on (at most ESTIMATE_RETRIES times; the simulation is
 * deterministic, so the same pose would give the same answer). The walk stops early, with a reason
 * in w->stopped, when no retry gives a clear outcome or the outcomes contradict a noiseless
 * bracket (only bisect refuses those). */
static estimate_status_t walk_reply(est_t *est, const estimate_trial_reply_t *reply) {
  walk_t *w = &est->walk;
  const estimate_trial_t *t = edge_logged(est, &w->sc, reply);
  if (w->ran) ++*w->ran;
  if (!clear_outcome(est, t)) {
    if (++w->attempt <= ESTIMATE_RETRIES) return walk_request(est);
    snprintf(w->stopped, sizeof w->stopped, "no clear outcome near x = %.3f mm", 1e3 * w->x);
    return walk_end(est);
  }
  qlearn_status_t qs = observe_trial(est, w->pol, t);
  if (qs == QLEARN_E_RANGE) {
    snprintf(w->stopped, sizeof w->stopped,
             "outcome at x = %.3f mm contradicts the earlier ones (noise, or physics the "
             "noiseless model does not cover)",
             1e3 * t->x_m);
    return walk_end(est);
  }
  if (qs != QLEARN_OK) {
    snprintf(est->result.msg, sizeof est->result.msg,
             "search %d: outcome refused by the policy: %s", w->sc.si, qlearn_status_str(qs));
    return ESTIMATE_E_LEARNER;
  }
  ++w->n;
  return walk_next(est);
}

/* Noisy walk: hand over to PBA with the probit noise model, starting from the posterior of every
 * clear trial the walk made, and run it until its interval is narrow enough (width_m, 0: the
 * configured stop; probit_config). A search resumed by refine_next comes here too: its trials
 * after the walk stay within cfg->noise_max_trials in all. */
static estimate_status_t handover_start(est_t *est, double width_m) {
  estimate_result_t *out = &est->result;
  walk_t *w = &est->walk;
  const search_ctx_t *sc = &w->sc;
  estimate_search_t *sr = &out->search[sc->si];
  qlearn_policy_config_t pc;
  qlearn_policy_config_default(QLEARN_POLICY_PBA, &pc);
  pc.range_lo_m = w->pc.range_lo_m;
  pc.range_hi_m = w->pc.range_hi_m;
  pc.prior_m = w->pc.prior_m;
  probit_config(est, &pc, width_m);
  pc.max_trials = QLEARN_MAX_TRIALS;
  qlearn_policy_t *pba = &est->handover;
  qlearn_status_t qs = qlearn_policy_init(pba, &pc);
  uint32_t seen = 0;
  for (size_t i = 0; qs == QLEARN_OK && i < out->trial_count; ++i) {
    const estimate_trial_t *t = &out->trial[i];
    if (t->search != sc->si || !clear_outcome(est, t)) continue;
    qs = observe_trial(est, pba, t);
    ++seen;
  }
  if (qs == QLEARN_E_DONE) qs = QLEARN_OK; /* already narrow enough */
  if (qs != QLEARN_OK) {
    snprintf(out->msg, sizeof out->msg, "search %d: handover: %s", sc->si, qlearn_status_str(qs));
    return ESTIMATE_E_LEARNER;
  }
  pba->cfg.max_trials = seen + est->cfg.noise_max_trials - sr->handover_trials; /* the cap */
  if (pba->cfg.max_trials > QLEARN_MAX_TRIALS) pba->cfg.max_trials = QLEARN_MAX_TRIALS;
  w->in_handover = 1;
  w->pol = pba;
  w->ran = &sr->handover_trials;
  w->n = 0;
  w->stopped[0] = '\0';
  return walk_next(est);
}

/* The bound a STAYS trial t of a rough-face search sets along u (unit, link frame). At rest, the
 * CoM lies over the support polygon, and every contact is on B's top or its edge line, so in the
 * settled pose n_s . c <= d_s (trial_plane) exactly, whatever the support looks like. Along u,
 * with g the estimate and r2 the squared distance from g to the farthest vertex (the CoM is inside
 * the object): u . c <= d_s + (u - n_s) . g + |u - n_s| r. */
static double stays_bound(const est_t *est, const estimate_trial_t *t, const double u[3],
                          double r2) {
  double n_s[3], d_s, du[3];
  trial_plane(est, &t->settled, n_s, &d_s);
  for (int k = 0; k < 3; ++k) du[k] = u[k] - n_s[k];
  double creep = 0.0; /* a creeping INVALID: how far beyond its support the CoM can be */
  if (t->outcome != ESTIMATE_STAYS)
    creep = 2.0 * trial_turned_rad(t) * r2 /
            (9.81 * ESTIMATE_CREEP_HORIZON_S * ESTIMATE_CREEP_HORIZON_S);
  return d_s + cl_vec3_dot(du, est->guess_m) + sqrt(cl_vec3_dot(du, du) * r2) + creep +
         ESTIMATE_STAYS_SLACK_M;
}

/* What the tightest of one side's STAYS bounds b[0..n) (b[0] the tightest) allows for pose noise
 * sigma. Each bound is off by the perceived position's error e_i ~ N(0, sigma^2) along the edge
 * normal, independently; the side misses the CoM only if some bound i, slack s_i = b_i - b_0
 * above the tightest, erred by more than k sigma + s_i. So k is the smallest with
 * sum_i Phi(-k - s_i / sigma) <= ESTIMATE_POSE_MISS (bisection; 1.96 for one tight bound, 2.24
 * for two, 2.8 for ten; the union bound makes it conservative). Returns k sigma. */
static double pose_allowance(const double *b, size_t n, double sigma) {
  if (n == 0 || !(sigma > 0.0)) return 0.0;
  double lo = 0.0, hi = 8.0;
  for (int it = 0; it < 40; ++it) {
    const double k = 0.5 * (lo + hi);
    double miss = 0.0;
    for (size_t i = 0; i < n; ++i) miss += 0.5 * erfc((k + (b[i] - b[0]) / sigma) / sqrt(2.0));
    if (miss > ESTIMATE_POSE_MISS)
      lo = k;
    else
      hi = k;
  }
  return hi * sigma;
}

/* The plane of a rough face's pair of searches: search a along u and its mirror b along -u (yaw
 * + pi). Their tightest STAYS bounds enclose the CoM from both sides: -B_b <= u . c <= B_a, a
 * bound without a physics budget. Only a is fed; b says where its trials went. */
static void rough_plane(est_t *est, int a, int b) {
  estimate_result_t *out = &est->result;
  estimate_search_t *sa = &out->search[a], *sb = &out->search[b];
  double r2 = 0.0;
  for (size_t i = 0; i < est->mesh->vertex_count; ++i) { /* the farthest vertex from the estimate */
    double v[3];
    cl_vec3_sub(est->mesh->vertices_m[i], est->guess_m, v);
    r2 = fmax(r2, cl_vec3_dot(v, v));
  }
  /* Each side's bounds, the tightest first: u . c <= bound_a, -u . c <= bound_b. */
  double *side[2] = {est->bounds[0], est->bounds[1]};
  size_t n[2] = {0, 0};
  for (size_t i = 0; i < out->trial_count; ++i) {
    const estimate_trial_t *t = &out->trial[i];
    if ((t->search != a && t->search != b) || seen_outcome(est, t) != ESTIMATE_STAYS) continue;
    const int k = t->search == b;
    double *v = side[k];
    const double x = stays_bound(est, t, out->search[t->search].dir_link, r2);
    v[n[k]++] = x;
    if (x < v[0]) { /* keep the tightest first */
      v[n[k] - 1] = v[0];
      v[0] = x;
    }
  }
  const double sigma = est->cfg.pose_noise_sigma_m;
  const double hi = n[0] ? side[0][0] + pose_allowance(side[0], n[0], sigma) : HUGE_VAL;
  const double lo = n[1] ? -(side[1][0] + pose_allowance(side[1], n[1], sigma)) : -HUGE_VAL;
  snprintf(sb->note, sizeof sb->note, "mirrors search %d: its STAYS bound is in that plane", a);
  if (!isfinite(hi) || !isfinite(lo)) {
    snprintf(sa->note, sizeof sa->note, "no placement stayed on %s",
             isfinite(hi) ? "the mirror's side" : "its side");
    return;
  }
  if (lo > hi) {
    snprintf(sa->note, sizeof sa->note,
             "the STAYS bounds of both sides contradict each other (%.3f mm > %.3f mm)", 1e3 * lo,
             1e3 * hi);
    return;
  }
  sa->c_m = 0.5 * (lo + hi);
  sa->halfwidth_m = 0.5 * (hi - lo);
  sa->note[0] = '\0'; /* a search made rough (rough_retest) drops why it failed its check */
  memcpy(sa->plane_n_obj, sa->dir_link, sizeof sa->plane_n_obj);
  sa->plane_d_m = sa->c_m;
  sa->bias_m = 0.0;
  sa->fed = 1;
}

/* A rough face's search ended: the first of a pair starts its mirror at yaw + pi (the edge on the
 * other side of the CoM); the mirror's end sets the pair's plane (rough_plane). A walk that
 * stopped early or contradicted itself still leaves valid STAYS bounds: its note is dropped. */
static estimate_status_t rough_end(est_t *est) {
  estimate_result_t *out = &est->result;
  walk_t *w = &est->walk;
  const int si = w->sc.si;
  estimate_search_t *sr = &out->search[si];
  search_estimate(est, &w->sc, w->pol);
  sr->note[0] = '\0';
  if (sr->mirror_of >= 0) {
    rough_plane(est, sr->mirror_of, si);
    return search_done(est);
  }
  if (out->search_count >= ESTIMATE_MAX_SEARCHES) {
    snprintf(sr->note, sizeof sr->note, "no room left for its mirror search");
    return search_done(est);
  }
  est->mirror_next = si;
  return search_start(est, est->face_src[sr->face], sr->face, sr->yaw_rad + CL_PI,
                      sr->chord_margin_m, -1);
}

/* The walk ended: hand over (noisy, not PBA), or take the search's estimate and plane. */
static estimate_status_t walk_end(est_t *est) {
  walk_t *w = &est->walk;
  estimate_search_t *sr = &est->result.search[w->sc.si];
  if (search_rough(est, w->sc.si)) return rough_end(est);
  if (!w->in_handover) {
    if (est->noisy && est->cfg.policy != QLEARN_POLICY_PBA) return handover_start(est, 0.0);
    if (w->stopped[0]) {
      snprintf(sr->note, sizeof sr->note, "%s", w->stopped);
      return search_done(est);
    }
  } else if (w->stopped[0]) {
    snprintf(sr->note, sizeof sr->note, "%s", w->stopped);
  }
  search_estimate(est, &w->sc, w->pol);
  if (!sr->note[0]) {
    if (w->sc.pivot)
      pivot_plane(est, &w->sc);
    else
      search_plane(est, &w->sc);
  }
  return search_done(est);
}

/* The threshold plane of a search, from its bracketing trials (noiseless) or the trials nearest
 * to its estimate (noisy), moved to the estimate c. It is used only when the trials that set it
 * were in the flat-patch regime; with a noise model every trial within c +- (h + 3 sigma) must
 * be. Otherwise the search gets a note and is not fed. */
static void search_plane(est_t *est, const search_ctx_t *sc) {
  estimate_result_t *out = &est->result;
  estimate_search_t *sr = &out->search[sc->si];
  const double c = sr->c_m;
  const int ends[2] = {sr->lo_trial, sr->hi_trial};
  double n_obj[3] = {0, 0, 0}, d = 0.0;
  int nb = 0;
  for (int e = 0; e < 2; ++e) {
    if (ends[e] < 0) continue;
    const estimate_trial_t *t = &out->trial[ends[e]];
    double ne[3], de;
    trial_plane(est, &t->released, ne, &de);
    de += (c - t->x_m) * cl_vec3_dot(ne, sc->u); /* move it to the estimate c */
    for (int k = 0; k < 3; ++k) n_obj[k] += ne[k];
    d += de;
    ++nb;
  }
  if (nb < 2 && !est->noisy) {
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
    if (t->search != sc->si || !clear_outcome(est, t)) continue;
    if (deciding_trial(est, sr, i) && t->flagged) {
      sr->flat_failed = 1;
      snprintf(sr->note, sizeof sr->note,
               "a trial that sets the threshold (x = %.3f mm) is not in the flat-patch regime "
               "(%s, chord margin %.2f mm)",
               1e3 * t->x_m,
               t->regime == MODEL_REGIME_EDGE_ROLL       ? "edge roll"
               : t->regime == MODEL_REGIME_POINT_SUPPORT ? "point support"
                                                         : "unclassified",
               1e3 * t->chord_margin_m);
      return;
    }
  }
  const double len = sqrt(cl_vec3_dot(n_obj, n_obj));
  for (int k = 0; k < 3; ++k) sr->plane_n_obj[k] = n_obj[k] / len;
  sr->plane_d_m = d / len;
  const model_face_t *f = &est->faces[est->face_src[sr->face]];
  sr->bias_m = f->closed && f->face_count == 0             ? ESTIMATE_RING_BIAS_M
               : !est->noisy && corner_at_edge(est, sr, f) ? ESTIMATE_CORNER_BIAS_M
                                                           : ESTIMATE_PHYSICS_BIAS_M;
  sr->fed = 1;
}

/* The plane of pivot search sc: its bracketing trials' planes both pass through the edge, the CoM
 * between them (beyond the one that tipped, short of the one that turned back); their bisector,
 * with the half width that holds for every point of the hull between them (the farthest vertex
 * from the edge line, reach r: r sin(angle / 2)). */
static void pivot_plane(est_t *est, const search_ctx_t *sc) {
  estimate_result_t *out = &est->result;
  estimate_search_t *sr = &out->search[sc->si];
  const estimate_pivot_t *pv = &est->pivot[sc->si];
  if (sr->lo_trial < 0 || sr->hi_trial < 0) {
    snprintf(sr->note, sizeof sr->note, "the threshold was not bracketed (all trials %s)",
             sr->lo_trial < 0 ? "turned back" : "tipped");
    return;
  }
  double a[3], b[3], n[3], d[3];
  estimate_pivot_normal(out->trial[sr->lo_trial].released.orientation_wxyz, a);
  estimate_pivot_normal(out->trial[sr->hi_trial].released.orientation_wxyz, b);
  cl_vec3_add(a, b, n);
  cl_vec3_sub(a, b, d);
  const double half = atan2(cl_vec3_norm(d), cl_vec3_norm(n)); /* half the angle between them */
  cl_vec3_normalize(n, n);
  memcpy(sr->plane_n_obj, n, sizeof n);
  memcpy(sr->dir_link, n, sizeof n);
  sr->plane_d_m = sr->c_m = cl_vec3_dot(n, pv->mid_m);
  sr->halfwidth_m = pv->reach_m * sin(half);
  sr->bias_m = ESTIMATE_PIVOT_BIAS_M;
  sr->fed = 1;
}

/* The estimate of a search: noiseless, the bracket of its clear trials (the largest x that
 * tipped, the smallest that stayed), whatever the policy; with a noise model, the policy's
 * posterior (PBA). */
static void search_estimate(est_t *est, const search_ctx_t *sc, const qlearn_policy_t *pol) {
  estimate_result_t *out = &est->result;
  estimate_search_t *sr = &out->search[sc->si];
  sr->lo_trial = sr->hi_trial = -1;
  for (size_t i = 0; i < out->trial_count; ++i) {
    const estimate_trial_t *t = &out->trial[i];
    if (t->search != sc->si || !clear_outcome(est, t)) continue;
    const estimate_outcome_t o = seen_outcome(est, t);
    if (o == ESTIMATE_TIPS && (sr->lo_trial < 0 || t->x_m >= out->trial[sr->lo_trial].x_m))
      sr->lo_trial = (int)i;
    if (o == ESTIMATE_STAYS && (sr->hi_trial < 0 || t->x_m <= out->trial[sr->hi_trial].x_m))
      sr->hi_trial = (int)i;
  }
  const double lo = sr->lo_trial >= 0 ? out->trial[sr->lo_trial].x_m : sc->lo;
  const double hi = sr->hi_trial >= 0 ? out->trial[sr->hi_trial].x_m : sc->hi;
  if (est->noisy) {
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
    snprintf(sr->note, sizeof sr->note,
             "trials contradict each other: tipped at %.3f mm, stayed "
             "at %.3f mm (noise, or physics the noiseless model does not cover)",
             1e3 * lo, 1e3 * hi);
  }
}

/* A search's resting orientation on face_index at yaw_rad, its test direction and the link axis
 * that direction determines most. */
static void ctx_orient(const est_t *est, int face_index, double yaw_rad, search_ctx_t *sc) {
  model_orientation_yawed(est->faces[face_index].orientation_wxyz, yaw_rad, sc->q);
  dir_of(sc->q, sc->u);
  sc->comp = 0;
  for (int k = 1; k < 3; ++k)
    if (fabs(sc->u[k]) > fabs(sc->u[sc->comp])) sc->comp = k;
}

/* A new search in out->search and the walk that runs it, with nothing planned yet: NULL when the
 * result has no room left. */
static estimate_search_t *search_new(est_t *est, int log_face, double yaw_rad, double margin_m,
                                     int retest_of) {
  estimate_result_t *out = &est->result;
  if (out->search_count >= ESTIMATE_MAX_SEARCHES) return NULL;
  walk_t *w = &est->walk;
  memset(w, 0, sizeof *w);
  search_ctx_t *sc = &w->sc;
  sc->si = (int)out->search_count++;
  sc->log_face = log_face;
  estimate_search_t *sr = &out->search[sc->si];
  memset(sr, 0, sizeof *sr);
  sr->face = log_face;
  sr->yaw_rad = yaw_rad;
  sr->chord_margin_m = margin_m;
  sr->verified_margin_m = NAN;
  sr->lo_trial = sr->hi_trial = -1;
  sr->retest_of = retest_of;
  sr->mirror_of = est->mirror_next;
  sr->added = est->phase == PHASE_MORE;
  est->mirror_next = -1;
  return sr;
}

/* The walk over [sc->lo, sc->hi] (its range set) from `prior` to `resolution_m`: the policy's
 * first trial. */
static estimate_status_t walk_begin(est_t *est, double prior, double resolution_m) {
  walk_t *w = &est->walk;
  const search_ctx_t *sc = &w->sc;
  qlearn_policy_config_t *pc = &w->pc;
  qlearn_policy_config_default(est->cfg.policy, pc);
  pc->range_lo_m = sc->lo;
  pc->range_hi_m = sc->hi;
  pc->prior_m = prior;
  pc->resolution_m = resolution_m;
  pc->seed = est->cfg.seed;
  if (est->cfg.policy == QLEARN_POLICY_PBA) {
    if (est->noisy)
      probit_config(est, pc, 0.0);
    else
      pc->sigma_m = 0.0;
  }
  w->pol = &est->policy;
  qlearn_status_t qs = qlearn_policy_init(w->pol, pc);
  if (qs != QLEARN_OK) {
    snprintf(est->result.msg, sizeof est->result.msg, "policy init: %s", qlearn_status_str(qs));
    return ESTIMATE_E_LEARNER;
  }
  return walk_next(est);
}

/* Start a 1-D search along the test direction of face_index at yaw_rad; search_done follows
 * when its trials are over. */
static estimate_status_t search_start(est_t *est, int face_index, int log_face, double yaw_rad,
                                      double margin_m, int retest_of) {
  estimate_result_t *out = &est->result;
  estimate_search_t *sr = search_new(est, log_face, yaw_rad, margin_m, retest_of);
  if (!sr) return fail(est, ESTIMATE_E_CAPACITY, "too many searches");
  search_ctx_t *sc = &est->walk.sc;
  est->search_rough[sc->si] = (unsigned char)(est->rough[face_index] || sr->mirror_of >= 0);
  ctx_orient(est, face_index, yaw_rad, sc);
  memcpy(sr->dir_link, sc->u, sizeof sc->u);
  search_range(est, sc->u, &sc->lo, &sc->hi);
  if (face_is_closed(est, face_index) && sr->mirror_of < 0) /* a mirror: the CoM may be off it */
    search_range_closed(est, &est->faces[face_index], sc->u, &sc->lo, &sc->hi);
  double prior = cl_vec3_dot(est->start_m, sc->u);
  if (prior < sc->lo) prior = sc->lo;
  if (prior > sc->hi) prior = sc->hi;
  sr->prior_m = prior;
  sr->range_lo_m = sc->lo;
  sr->range_hi_m = sc->hi;
  if (!(sc->hi - sc->lo >= est->cfg.resolution_m)) { /* a thin plate's side, a narrow patch */
    snprintf(sr->note, sizeof sr->note, "its range, %.3f mm, is under the resolution",
             1e3 * fmax(sc->hi - sc->lo, 0.0));
    if (sr->mirror_of >= 0)
      snprintf(out->search[sr->mirror_of].note, sizeof out->search[sr->mirror_of].note,
               "its mirror search %d had no range", sc->si);
    return search_done(est);
  }
  return walk_begin(est, prior, est->cfg.resolution_m);
}

/* A fed plane's sigma in the solve: the bracket's uniform spread h / sqrt 3 (noiseless) or the
 * 95 % interval's h / 1.96 (noise model); at least 1 nm (a collapsed, knife-edge bracket). */
static double plane_sigma(const est_t *est, const estimate_search_t *sr) {
  const double sigma = est->noisy ? sr->halfwidth_m / 1.96 : sr->halfwidth_m / sqrt(3.0);
  return sigma > 1e-9 ? sigma : 1e-9;
}

/* The 3-D solve over the fed planes. Each plane's sigma: the bracket's uniform spread h / sqrt 3
 * (noiseless) or the 95 % interval's h / 1.96 (noise model). Every component the planes
 * determine is reported (found[] here means determined; the caller applies the width limit). */
static estimate_status_t solve_all(est_t *est, qlearn_solve_result_t *res) {
  qlearn_solve_t *solve = &est->solve;
  qlearn_solve_init(solve);
  for (size_t i = 0; i < est->result.search_count; ++i) {
    const estimate_search_t *sr = &est->result.search[i];
    if (!sr->fed) continue;
    qlearn_status_t qs =
        qlearn_solve_add_plane(solve, sr->plane_n_obj, sr->plane_d_m, plane_sigma(est, sr));
    if (qs != QLEARN_OK) {
      snprintf(est->result.msg, sizeof est->result.msg, "solve: %s", qlearn_status_str(qs));
      return ESTIMATE_E_LEARNER;
    }
  }
  memset(res, 0, sizeof *res);
  if (solve->count == 0) {
    for (int k = 0; k < 3; ++k) res->halfwidth_m[k] = INFINITY;
    return ESTIMATE_OK;
  }
  qlearn_status_t qs = qlearn_solve_compute(solve, est->cfg.z, 1e9, res);
  if (qs != QLEARN_OK && qs != QLEARN_E_SINGULAR) {
    snprintf(est->result.msg, sizeof est->result.msg, "solve: %s", qlearn_status_str(qs));
    return ESTIMATE_E_LEARNER;
  }
  return ESTIMATE_OK;
}

/* Is direction a determined by the fed planes (orthogonal to the solve's null space)? */
static int dir_determined(const qlearn_solve_result_t *res, const double a[3]) {
  if (res->rank == 0) return 0;
  double leak = 0.0;
  for (int e = 0; e < 3 - res->rank; ++e) {
    const double p = cl_vec3_dot(res->eigenvector[e], a);
    leak += p * p;
  }
  return leak <= QLEARN_SOLVE_NULL_LEAK;
}

/* The coefficient of fed plane sr in the solve's estimate of a . c: p = w a . (A^+ n),
 * w = 1 / sigma^2 (dimensionless: a . c = sum over planes of p d). */
static double plane_coef(const est_t *est, const qlearn_solve_result_t *res, const double a[3],
                         const estimate_search_t *sr) {
  double p = 0.0;
  for (int e = 3 - res->rank; e < 3; ++e)
    p += cl_vec3_dot(res->eigenvector[e], a) * cl_vec3_dot(res->eigenvector[e], sr->plane_n_obj) /
         res->eigenvalue[e];
  const double sigma = plane_sigma(est, sr);
  return p / (sigma * sigma);
}

/* The half width of a . c (a unit, link frame) that holds, INFINITY when the planes do not
 * determine it. The solve's estimate is linear in the planes' offsets, a . c = sum_j p_j d_j with
 * p_j = w_j a . (A^+ n_j) (A^+ the pseudo-inverse of the normal matrix over its non-null
 * eigenvectors, exact for a orthogonal to the null space). Noiseless, each offset is known within
 * its bracket h_j plus its regime's bias b_j, so |error| <= sum_j |p_j| (h_j + b_j): a bound, also
 * when the planes are oblique or fewer than three. With a noise model: the solve's z sigma (95 %)
 * plus the bias budget sum_j |p_j| b_j. */
static double dir_halfwidth(const est_t *est, const qlearn_solve_result_t *res, const double a[3]) {
  if (!dir_determined(res, a)) return INFINITY;
  const int first = 3 - res->rank; /* eigenvalues ascend: the null ones come first */
  double bound = 0.0, bias = 0.0, var = 0.0;
  for (int e = first; e < 3; ++e) {
    const double p = cl_vec3_dot(res->eigenvector[e], a);
    var += p * p / res->eigenvalue[e];
  }
  for (size_t i = 0; i < est->result.search_count; ++i) {
    const estimate_search_t *sr = &est->result.search[i];
    if (!sr->fed) continue;
    const double p = plane_coef(est, res, a, sr);
    bound += fabs(p) * (sr->halfwidth_m + sr->bias_m);
    bias += fabs(p) * sr->bias_m;
  }
  return est->noisy ? est->cfg.z * sqrt(var) + bias : bound;
}

/* The first fed search that a . c depends on (a coefficient above rounding) but that is not
 * verified, or -1. */
static int dir_unverified(const est_t *est, const qlearn_solve_result_t *res, const double a[3]) {
  for (size_t i = 0; i < est->result.search_count; ++i) {
    const estimate_search_t *sr = &est->result.search[i];
    if (sr->fed && !sr->verified && fabs(plane_coef(est, res, a, sr)) > 1e-9) return (int)i;
  }
  return -1;
}

/* Solve and move the estimate: the guess (and the start point) take the solution's components in
 * the determined subspace, keep theirs in the null space; est->halfwidth_m per link axis. */
static estimate_status_t update_guess(est_t *est) {
  qlearn_solve_result_t *res = &est->res;
  estimate_status_t s = solve_all(est, res);
  if (s != ESTIMATE_OK) return s;
  est->have_solve = 1;
  for (int k = 0; k < 3; ++k) { /* INFINITY while a component is not found */
    const double e[3] = {k == 0, k == 1, k == 2};
    const double hw = dir_halfwidth(est, res, e);
    est->halfwidth_m[k] = hw <= est->cfg.max_halfwidth_m ? hw : INFINITY;
  }
  if (res->rank == 0) return ESTIMATE_OK;
  double *pts[2] = {est->guess_m, est->start_m};
  for (int i = 0; i < 2; ++i) {
    double delta[3], corr[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k) delta[k] = res->com_m[k] - pts[i][k];
    for (int j = 3 - res->rank; j < 3; ++j) {
      const double p = cl_vec3_dot(res->eigenvector[j], delta);
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
static estimate_status_t yaw_margins(est_t *est, const model_face_t *f, double m[YAW_STEPS]) {
  enum { N = 3 * YAW_STEPS };
  double yaw[N], com[N][3], mj[N];
  for (int k = 0; k < YAW_STEPS; ++k) {
    double q[4], u[3];
    model_orientation_yawed(f->orientation_wxyz, k * CL_PI / YAW_STEPS, q);
    dir_of(q, u);
    const double e = est->have_solve
                         ? fmin(dir_halfwidth(est, &est->res, u), ESTIMATE_PLAN_OFFSET_M)
                         : ESTIMATE_PLAN_OFFSET_M;
    for (int j = 0; j < 3; ++j) {
      yaw[3 * k + j] = k * CL_PI / YAW_STEPS;
      for (int i = 0; i < 3; ++i) com[3 * k + j][i] = est->guess_m[i] + (j - 1) * e * u[i];
    }
  }
  model_status_t ms = model_yaw_margins_in(est->mesh, f->orientation_wxyz, MODEL_EDGE_PX, NULL, N,
                                           yaw, (const double(*)[3])com, est->work, mj);
  if (ms != MODEL_OK) return fail(est, ESTIMATE_E_GEOMETRY, model_status_str(ms));
  for (int k = 0; k < YAW_STEPS; ++k) m[k] = fmin(mj[3 * k], fmin(mj[3 * k + 1], mj[3 * k + 2]));
  return ESTIMATE_OK;
}

/* Face 1: two test directions at least min_dir_angle apart, both with a good chord margin. */
static estimate_status_t plan_first(est_t *est, int fi, face_plan_t *p) {
  double m[YAW_STEPS];
  estimate_status_t s = yaw_margins(est, &est->faces[fi], m);
  if (s != ESTIMATE_OK) return s;
  p->face = fi;
  p->score = -HUGE_VAL;
  int min_sep = (int)ceil(est->cfg.min_dir_angle_rad / (CL_PI / YAW_STEPS) - 1e-9);
  for (int i = 0; i < YAW_STEPS; ++i) {
    for (int j = i + min_sep; j <= i + YAW_STEPS - min_sep; ++j) {
      int jj = j % YAW_STEPS;
      double sc = fmin(m[i], m[jj]);
      /* prefer perpendicular directions among near-equal margins */
      double sep = fabs(sin((j - i) * CL_PI / YAW_STEPS));
      sc += 1e-4 * sep;
      if (sc > p->score) {
        p->score = sc;
        p->yaw[0] = i * CL_PI / YAW_STEPS;
        p->yaw[1] = jj * CL_PI / YAW_STEPS;
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
static estimate_status_t plan_partner(est_t *est, int fi, double yaw0, double *yaw1,
                                      double *margin1) {
  double m[YAW_STEPS];
  estimate_status_t s = yaw_margins(est, &est->faces[fi], m);
  if (s != ESTIMATE_OK) return s;
  for (int pass = 0; pass < 2; ++pass) {
    const double need = est->cfg.min_chord_margin_m * (pass == 0 ? 2.0 : 1.0);
    double best = -1.0;
    for (int k = 0; k < YAW_STEPS; ++k) {
      const double sep = fabs(sin(k * CL_PI / YAW_STEPS - yaw0));
      if (!(m[k] >= need) || sep < sin(est->cfg.min_dir_angle_rad) - 1e-9) continue;
      const double sc = sep + 1e-6 * m[k]; /* ties: the larger margin */
      if (sc > best) {
        best = sc;
        *yaw1 = k * CL_PI / YAW_STEPS;
        *margin1 = m[k];
      }
    }
    if (best >= 0.0) break;
  }
  return ESTIMATE_OK;
}

/* Face 2: one direction with the largest component along the first face's normal, among yaws
 * with a chord margin of twice the minimum (or the minimum when none has that). */
static estimate_status_t plan_second(est_t *est, int fi, const double n1[3], face_plan_t *p) {
  double m[YAW_STEPS];
  estimate_status_t s = yaw_margins(est, &est->faces[fi], m);
  if (s != ESTIMATE_OK) return s;
  p->face = fi;
  p->score = -HUGE_VAL;
  for (int pass = 0; pass < 2 && p->score == -HUGE_VAL; ++pass) {
    double need = est->cfg.min_chord_margin_m * (pass == 0 ? 2.0 : 1.0);
    for (int k = 0; k < YAW_STEPS; ++k) {
      if (!(m[k] >= need)) continue;
      double q[4], u[3];
      model_orientation_yawed(est->faces[fi].orientation_wxyz, k * CL_PI / YAW_STEPS, q);
      dir_of(q, u);
      double sc = fabs(cl_vec3_dot(u, n1));
      if (sc > p->score) {
        p->score = sc;
        p->yaw[0] = k * CL_PI / YAW_STEPS;
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

static int record_face(est_t *est, int fi) {
  estimate_result_t *out = &est->result;
  if (out->face_count >= ESTIMATE_MAX_FACES) return -1;
  estimate_face_t *f = &out->face[out->face_count];
  memcpy(f->normal_link, est->faces[fi].normal_link, sizeof f->normal_link);
  f->area_m2 = est->faces[fi].area_m2;
  f->contact_area_m2 = est->faces[fi].patch_area_m2;
  f->regions = est->faces[fi].region_count;
  f->com_margin_m = est->faces[fi].com_margin_m;
  f->confirmed = 0;
  f->rough = est->rough[fi];
  est->face_src[out->face_count] = fi;
  return (int)out->face_count++;
}

static estimate_status_t confirm_none(est_t *est);
static estimate_status_t confirmed(est_t *est);

/* Check the plans in order with a stable-pose trial, from est->ci on; the first confirmed one
 * becomes est->chosen (confirmed), none: confirm_none. */
static estimate_status_t confirm_next(est_t *est) {
  if (est->ci >= est->np) return confirm_none(est);
  const int rec = record_face(est, est->plans[est->ci].face);
  if (rec < 0) return confirm_none(est);
  est->chosen_log = rec;
  return stable_request(est, est->plans[est->ci].face, rec);
}

/* Confirm plans[0, np) in order (confirm_next from the first). */
static estimate_status_t confirm_plans(est_t *est, size_t np) {
  est->np = np;
  est->ci = 0;
  return confirm_next(est);
}

static estimate_status_t plan_closed(est_t *est, int fi, face_plan_t *p);

/* Was a face with this normal checked already (in out->face)? */
static int face_recorded(const est_t *est, const double normal[3]) {
  for (size_t i = 0; i < est->result.face_count; ++i) {
    if (same_normal(est->result.face[i].normal_link, normal)) return 1;
  }
  return 0;
}

/* May face f be tried in the current phase? Face 2 needs a normal at least min_face_angle from
 * face 1's (not parallel, not antiparallel); a face 1 that replaces another (face_redo), from
 * every face whose search is kept. */
static int face_allowed(const est_t *est, const model_face_t *f) {
  const double cos_max = cos(est->cfg.min_face_angle_rad);
  if (est->phase == PHASE_FACE2)
    return fabs(cl_vec3_dot(f->normal_link, est->faces[est->face1].normal_link)) <= cos_max;
  /* a new face 1 (face_redo): at an angle to every face whose search is kept */
  for (size_t j = 0; est->redo_face >= 0 && j < est->result.search_count; ++j) {
    const estimate_search_t *o = &est->result.search[j];
    if (!o->fed || o->face < 0 || o->face == est->redo_face) continue;
    if (fabs(cl_vec3_dot(f->normal_link, est->faces[est->face_src[o->face]].normal_link)) > cos_max)
      return 0;
  }
  return 1;
}

/* Rough faces and searches made rough may be used: on, and with a noise model only when told the
 * pose noise (a STAYS bound takes the settled pose as observed; pose noise moves it). */
static int rough_usable(const est_t *est) {
  return est->cfg.rough_faces && (!est->noisy || est->cfg.pose_noise_sigma_m > 0.0);
}

/* A stable check that did not confirm its face but came to rest on B: the object rolled onto the
 * face it really rests on. That face (under the settled pose's down direction) holds the CoM's
 * projection: when it is a closed patch not planned yet, it is checked next; when it is neither
 * flat nor closed (a pebble's point support) and rough faces are usable, it is checked as a rough
 * face after the patches still planned (a patch's plane is exact, a rough one a bound). */
static estimate_status_t settled_face(est_t *est, const estimate_trial_t *t) {
  if (!est->cfg.closed_patches || t->outcome != ESTIMATE_STAYS ||
      est->found_settled >= ESTIMATE_SETTLED_MAX || est->nfaces >= FACE_CAP || est->np >= FACE_CAP)
    return ESTIMATE_OK;
  double r[3][3], down[3];
  model_quat_to_rot(t->settled.orientation_wxyz, r);
  for (int k = 0; k < 3; ++k) down[k] = -r[2][k]; /* world -z in the link frame */
  model_face_t f;
  model_status_t ms = model_face_at(est->mesh, down, est->guess_m, NULL, &f);
  if (ms != MODEL_OK) return ESTIMATE_OK; /* nothing usable under that pose */
  if (f.flat || (!f.closed && !rough_usable(est)) || !face_allowed(est, &f)) return ESTIMATE_OK;
  const int rough = !f.closed;
  for (size_t i = est->ci + 1; i < est->np; ++i) {
    if (same_normal(est->faces[est->plans[i].face].normal_link, f.normal_link))
      return ESTIMATE_OK; /* planned already */
  }
  if (face_recorded(est, f.normal_link)) return ESTIMATE_OK; /* checked already */
  const int fi = (int)est->nfaces++;
  est->faces[fi] = f;
  est->rough[fi] = (unsigned char)rough;
  ++est->found_settled;
  face_plan_t p;
  estimate_status_t s = plan_closed(est, fi, &p);
  if (s != ESTIMATE_OK) return s;
  if (rough) {
    est->plans[est->np++] = p;
    return ESTIMATE_OK;
  }
  memmove(&est->plans[est->ci + 2], &est->plans[est->ci + 1],
          (est->np - est->ci - 1) * sizeof est->plans[0]);
  est->plans[est->ci + 1] = p;
  ++est->np;
  return ESTIMATE_OK;
}

/* Steer the estimate by a stable check that fell (t, on faces[fi], a closed patch or a rough
 * face): the object turned about an edge of its contact, away from B's middle, toward f (world,
 * horizontal: the top's motion, axis x z for the turn's axis), so the CoM lies beyond the contact
 * along f: f . c >= max over the contact's vertices of f . v, in the link frame at release. That
 * is recorded (capped at the object's extent along f, less search_range's trim) with
 * ESTIMATE_FALL_MARGIN_M more, and the estimate is moved the least to satisfy every fall so far
 * (cyclic projections, only along the directions the solve has not determined), so the faces
 * listed next are those the CoM more likely rests on. A heuristic for planning only: a fall is
 * never fed to the solve. On an uneven lumpy rock every patch under the mesh's uniform CoM (3 mm
 * off) fell and the face log filled (docs/estimate.md, "Steered by falls"). */
static void fall_steer(est_t *est, const estimate_trial_t *t, int fi) {
  const model_face_t *f = &est->faces[fi];
  if (!est->cfg.fall_steering || f->flat || t->outcome != ESTIMATE_TIPS ||
      est->falls >= ESTIMATE_FALLS_MAX)
    return;
  double qc[4], qr[4];
  cl_quat_conj(t->released.orientation_wxyz, qc);
  cl_quat_mul(t->settled.orientation_wxyz, qc, qr); /* the turn, world frame */
  const double sgn = qr[0] < 0.0 ? -1.0 : 1.0;
  double fw[3] = {sgn * qr[2], -sgn * qr[1], 0.0}; /* axis x z */
  const double h = hypot(fw[0], fw[1]);
  if (!(h > 1e-9)) return; /* turned about the vertical only */
  double r[3][3], a[3];
  model_quat_to_rot(t->released.orientation_wxyz, r);
  for (int k = 0; k < 3; ++k) a[k] = (r[0][k] * fw[0] + r[1][k] * fw[1]) / h;
  double b0, b;
  face_extent(est, f, a, &b0, &b);
  if (!isfinite(b)) return;
  double lo = 0.0, hi = 0.0;
  search_range(est, a, &lo, &hi);
  b = fmin(b + ESTIMATE_FALL_MARGIN_M, hi);
  memcpy(est->fall_a[est->falls], a, sizeof a);
  est->fall_b[est->falls++] = b;
  if (!est->steered) memcpy(est->unsteered_m, est->guess_m, sizeof est->unsteered_m);
  est->steered = 1;
  /* the directions free to move in: those the solve has not determined */
  double fr[3][3];
  int nfree = 3;
  for (int j = 0; j < 3; ++j)
    for (int k = 0; k < 3; ++k) fr[j][k] = j == k;
  if (est->have_solve) {
    nfree = 3 - est->res.rank;
    for (int j = 0; j < nfree; ++j) memcpy(fr[j], est->res.eigenvector[j], sizeof fr[j]);
  }
  for (int pass = 0; pass < 32; ++pass) {
    for (uint32_t i = 0; i < est->falls; ++i) {
      const double need = est->fall_b[i] - cl_vec3_dot(est->fall_a[i], est->guess_m);
      if (need <= 0.0) continue;
      double ap[3] = {0, 0, 0}; /* fall_a[i] in the free directions */
      for (int j = 0; j < nfree; ++j) {
        const double c = cl_vec3_dot(fr[j], est->fall_a[i]);
        for (int k = 0; k < 3; ++k) ap[k] += c * fr[j][k];
      }
      const double den = cl_vec3_dot(ap, est->fall_a[i]);
      if (den < 0.05) continue; /* nearly along a determined direction */
      for (int k = 0; k < 3; ++k) est->guess_m[k] += need / den * ap[k];
    }
  }
}

static estimate_status_t faces_append(est_t *est, int rough);
static estimate_status_t closed_plans(est_t *est, size_t *np);

/* After fall_steer: when the estimate moved by ESTIMATE_RELIST_M or more since the phase's closed
 * patches (or rough faces) were listed, they are listed again under it and checked first, best
 * first; the plans still pending follow (those listed again are not repeated). */
static estimate_status_t fall_relist(est_t *est) {
  double d[3];
  cl_vec3_sub(est->guess_m, est->listed_at_m, d);
  if (est->list_rough < 0 || !(cl_vec3_norm(d) >= ESTIMATE_RELIST_M) || est->nfaces >= FACE_CAP)
    return ESTIMATE_OK;
  const size_t first = est->ci + 1, pend = est->np - first;
  face_plan_t old[FACE_CAP];
  memcpy(old, est->plans + first, pend * sizeof old[0]);
  estimate_status_t s = faces_append(est, est->list_rough);
  size_t np = first;
  if (s == ESTIMATE_OK) s = closed_plans(est, &np);
  if (s != ESTIMATE_OK) return s;
  for (size_t i = 0; i < pend && np < FACE_CAP; ++i) {
    size_t j = first;
    while (j < np && !same_normal(est->faces[est->plans[j].face].normal_link,
                                  est->faces[old[i].face].normal_link))
      ++j;
    if (j == np) est->plans[np++] = old[i];
  }
  est->np = np;
  return ESTIMATE_OK;
}

static estimate_status_t confirm_reply(est_t *est, const estimate_trial_reply_t *reply) {
  const estimate_trial_t *t = log_trial(est, reply);
  const int fi = est->plans[est->ci].face;
  const int closed = face_is_closed(est, fi);
  const int conf = stable_confirmed(t, closed, est->rough[fi]);
  est->result.face[est->chosen_log].confirmed = conf;
  if (conf) {
    est->chosen = est->plans[est->ci];
    return confirmed(est);
  }
  if (closed && !est->rough[fi] && est->spare_phase != (int)est->phase &&
      stable_confirmed(t, 0, 1)) { /* at rest, within a stable pose's tolerance: a rough face */
    est->spare = est->plans[est->ci];
    est->spare_log = est->chosen_log;
    est->spare_phase = (int)est->phase;
  }
  estimate_status_t s = settled_face(est, t);
  if (s != ESTIMATE_OK) return s;
  fall_steer(est, t, fi);
  if ((s = fall_relist(est)) != ESTIMATE_OK) return s;
  ++est->ci;
  return confirm_next(est);
}

/* A closed patch's plan (any chord holds on a closed patch, so no yaw is refused): face 1 at
 * yaws 0 and 90 degrees, face 2 at the yaw whose test direction is most along face 1's normal;
 * scored by how far inside the patch the estimate projects (model_faces_stable's order). */
static estimate_status_t plan_closed(est_t *est, int fi, face_plan_t *p) {
  p->face = fi;
  p->score = est->faces[fi].com_margin_m;
  p->yaw[0] = 0.0;
  if (est->phase == PHASE_FACE2) { /* the test direction most along face 1's normal */
    const double *n1 = est->faces[est->face1].normal_link;
    double best = -1.0;
    for (int k = 0; k < YAW_STEPS; ++k) {
      double q[4], u[3];
      model_orientation_yawed(est->faces[fi].orientation_wxyz, k * CL_PI / YAW_STEPS, q);
      dir_of(q, u);
      if (fabs(cl_vec3_dot(u, n1)) > best) {
        best = fabs(cl_vec3_dot(u, n1));
        p->yaw[0] = k * CL_PI / YAW_STEPS;
      }
    }
  }
  p->yaw[1] = p->yaw[0] + 0.5 * CL_PI;
  p->margin[0] = p->margin[1] = -HUGE_VAL; /* no chord margin is needed */
  return ESTIMATE_OK;
}

/* Closed patches after the flat faces' plans (from plans[np] on), in model_faces_stable's order:
 * for face 2 only those at least min_face_angle from face 1. */
static estimate_status_t closed_plans(est_t *est, size_t *np) {
  for (size_t i = est->closed_from; i < est->nfaces && *np < FACE_CAP; ++i) {
    if ((int)i == est->face1 || !face_allowed(est, &est->faces[i]) ||
        face_recorded(est, est->faces[i].normal_link))
      continue;
    estimate_status_t s = plan_closed(est, (int)i, &est->plans[*np]);
    if (s != ESTIMATE_OK) return s;
    ++*np;
  }
  return ESTIMATE_OK;
}

static estimate_status_t face_one_closed(est_t *est);
static estimate_status_t closed_append(est_t *est);

/* The closed patches of the current phase under the estimate, listed and planned once (*listed
 * marks it): *np plans, 0 when listed before or closed patches are off. */
static estimate_status_t closed_once(est_t *est, int *listed, size_t *np) {
  *np = 0;
  if (!est->cfg.closed_patches || *listed) return ESTIMATE_OK;
  *listed = 1;
  estimate_status_t s = closed_append(est);
  return s == ESTIMATE_OK ? closed_plans(est, np) : s;
}

/* The rough faces of the current phase under the estimate, once the flat faces and closed
 * patches are used up: every hull face that holds the estimate and was not checked yet, listed
 * and planned once (*listed marks it). */
static estimate_status_t rough_once(est_t *est, int *listed, size_t *np) {
  *np = 0;
  if (!rough_usable(est) || *listed) return ESTIMATE_OK;
  *listed = 1;
  estimate_status_t s = faces_append(est, 1);
  return s == ESTIMATE_OK ? closed_plans(est, np) : s;
}

/* When no flat face of the phase is (left): its closed patches, else its rough faces, each listed
 * once (*closed, *rough mark it); *np plans. */
static estimate_status_t fallback_once(est_t *est, int *closed, int *rough, size_t *np) {
  estimate_status_t s = closed_once(est, closed, np);
  if (s == ESTIMATE_OK && *np == 0) s = rough_once(est, rough, np);
  return s;
}

/* Face 2's last list, when nothing under the estimate was confirmed: face 1's searches bound the
 * CoM across face 1's normal n1, but along n1 the estimate is still the prior's, which on an
 * uneven object can be millimetres off, so the faces the object really rests on may not hold the
 * estimate's projection. The faces that hold the projection of some of LINE_SAMPLES points of
 * the line g + t n1 across the object and were not checked are listed, most weight first (each
 * point weighs exp(-t^2 / (2 s^2)), s = LINE_SPREAD of the extent: the prior is likelier near
 * than far off), at most LINE_FACES: closed patches as such, the others as rough faces when those
 * are usable. Once (est->line2); *np plans. */
static estimate_status_t line_once(est_t *est, size_t *np) {
  enum { LINE_SAMPLES = 33, LINE_FACES = 2 };
  static const double LINE_SPREAD = 0.25; /* of the extent: how far the prior may be off */
  *np = 0;
  if (est->phase != PHASE_FACE2 || est->line2 || !est->cfg.closed_patches) return ESTIMATE_OK;
  est->line2 = 1;
  est->list_rough = 0; /* a fall among them lists the closed patches under the new estimate */
  memcpy(est->listed_at_m, est->guess_m, sizeof est->listed_at_m);
  const double *n1 = est->faces[est->face1].normal_link;
  double lo = 0.0, hi = 0.0;
  search_range(est, n1, &lo, &hi);
  const double g = cl_vec3_dot(est->guess_m, n1), sd = LINE_SPREAD * (hi - lo);
  est->closed_from = est->nfaces;
  double held[FACE_CAP] = {0}; /* held[j]: weight of the samples faces[closed_from + j] holds at */
  size_t u = 0;                /* faces[closed_from, closed_from + u): the distinct ones so far */
  for (int k = 0; k < LINE_SAMPLES; ++k) {
    const size_t room = FACE_CAP - est->closed_from - u;
    const double t = lo + (hi - lo) * k / (LINE_SAMPLES - 1) - g; /* from the estimate */
    const double w = exp(-0.5 * t * t / (sd * sd));
    double point[3];
    for (int c = 0; c < 3; ++c) point[c] = est->guess_m[c] + t * n1[c];
    model_face_t *listed = est->faces + est->closed_from + u;
    size_t n = 0;
    const model_status_t ms =
        room == 0 ? MODEL_OK
                  : model_faces_stable_in(est->mesh, point, NULL, est->work, listed, room, &n);
    if (ms != MODEL_OK) {
      snprintf(est->result.msg, sizeof est->result.msg, "stable faces: %s", model_status_str(ms));
      return ms == MODEL_E_NOMEM ? ESTIMATE_E_NOMEM : ESTIMATE_E_GEOMETRY;
    }
    if (n > room) n = room;
    for (size_t i = 0; i < n; ++i) {
      const model_face_t f = listed[i];
      if (face_recorded(est, f.normal_link) || !face_allowed(est, &f) ||
          (!f.closed && !rough_usable(est)))
        continue;
      size_t j = 0;
      while (j < u && !same_normal(est->faces[est->closed_from + j].normal_link, f.normal_link))
        ++j;
      if (j == u) est->faces[est->closed_from + u++] = f; /* listed[i] or before: no overlap */
      held[j] += w;
    }
  }
  for (size_t a = 1; a < u; ++a) { /* insertion sort, most held first, stable */
    const model_face_t f = est->faces[est->closed_from + a];
    const double h = held[a];
    size_t b = a;
    for (; b > 0 && held[b - 1] < h; --b) {
      est->faces[est->closed_from + b] = est->faces[est->closed_from + b - 1];
      held[b] = held[b - 1];
    }
    est->faces[est->closed_from + b] = f;
    held[b] = h;
  }
  if (u > LINE_FACES) u = LINE_FACES;
  for (size_t j = 0; j < u; ++j)
    est->rough[est->closed_from + j] = !est->faces[est->closed_from + j].closed;
  est->nfaces = est->closed_from + u;
  return closed_plans(est, np);
}

/* What the face choice tried, for its messages. */
static const char *faces_tried(const est_t *est) {
  return est->rough1 || est->rough2 ? "flat face, closed patch or rough face"
         : est->cfg.closed_patches  ? "flat face or closed patch"
                                    : "flat face";
}

/* Face 1: the flat, stable-candidate faces with the best pairs of chord margins, to confirm in
 * that order, then (none confirmed) the closed patches; two searches on the first confirmed. */
static estimate_status_t face_one(est_t *est) {
  size_t np = 0;
  for (size_t i = 0; i < est->nflat_list; ++i) {
    if (!est->faces[i].flat || !est->faces[i].candidate) continue;
    estimate_status_t s = plan_first(est, (int)i, &est->plans[np]);
    if (s != ESTIMATE_OK) return s;
    if (est->plans[np].score >= est->cfg.min_chord_margin_m) ++np;
  }
  qsort(est->plans, np, sizeof est->plans[0], plan_cmp);
  est->phase = PHASE_FACE1;
  est->list_rough = -1;
  if (np == 0) return face_one_closed(est);
  return confirm_plans(est, np);
}

/* Nothing is left to check in this phase: the spare (a closed patch that came to rest off
 * itself) is searched as a rough face, whose STAYS bounds need no patch; its stable check
 * already stayed. *used = 0 when there is none (or rough faces are not usable). */
static estimate_status_t spare_rough(est_t *est, int *used) {
  *used = est->spare_phase == (int)est->phase && rough_usable(est);
  if (!*used) return ESTIMATE_OK;
  est->spare_phase = -1;
  est->rough[est->spare.face] = 1;
  estimate_face_t *lf = &est->result.face[est->spare_log];
  lf->rough = 1;
  lf->confirmed = 1;
  est->chosen = est->spare;
  est->chosen_log = est->spare_log;
  return confirmed(est);
}

/* Face 1 on a closed patch, when no flat face 1 is (left): the patches under the prior (listed
 * only then: a flat object never needs them), else its rough faces, else the spare. */
static estimate_status_t face_one_closed(est_t *est) {
  size_t np = 0;
  estimate_status_t s = fallback_once(est, &est->closed1, &est->rough1, &np);
  if (s != ESTIMATE_OK) return s;
  int used = 0;
  if (np == 0 && ((s = spare_rough(est, &used)) != ESTIMATE_OK || used)) return s;
  if (np == 0) {
    if (!est->closed1 && !est->rough1 && est->result.face_count == 0)
      return fail(est, ESTIMATE_E_GEOMETRY, "no flat face with two usable edge directions");
    char m[ESTIMATE_NOTE_SIZE];
    snprintf(m, sizeof m, "no resting %s was confirmed stable", faces_tried(est));
    return fail(est, ESTIMATE_E_NOPOSE, m);
  }
  return confirm_plans(est, np);
}

static estimate_status_t verify_begin(est_t *est);
static estimate_status_t face_two_closed(est_t *est);

/* Face 2: the flat stable faces whose normals are not (anti)parallel to face 1's, to confirm;
 * one search on the first confirmed. */
static estimate_status_t face_two(est_t *est) {
  const double *n1 = est->faces[est->face1].normal_link;
  const double cos_max = cos(est->cfg.min_face_angle_rad);
  size_t np = 0;
  for (size_t i = 0; i < est->nflat_list; ++i) {
    const model_face_t *f = &est->faces[i];
    if (!f->flat || !f->candidate || (int)i == est->face1) continue;
    if (fabs(cl_vec3_dot(f->normal_link, n1)) > cos_max) continue;
    estimate_status_t s = plan_second(est, (int)i, n1, &est->plans[np]);
    if (s != ESTIMATE_OK) return s;
    if (est->plans[np].score > 0.0) ++np;
  }
  qsort(est->plans, np, sizeof est->plans[0], plan_cmp);
  est->phase = PHASE_FACE2; /* face_allowed: at an angle to face 1 */
  est->list_rough = -1;
  if (np == 0) return face_two_closed(est);
  return confirm_plans(est, np);
}

/* Face 2 on a closed patch, when no flat face 2 is left: the patches under the estimate after
 * face 1's searches (computed only then: a flat object never needs them). */
static estimate_status_t face_two_closed(est_t *est) {
  size_t np = 0;
  estimate_status_t s = fallback_once(est, &est->closed2, &est->rough2, &np);
  if (s == ESTIMATE_OK && np == 0) s = line_once(est, &np);
  if (s != ESTIMATE_OK) return s;
  int used = 0;
  if (np == 0 && ((s = spare_rough(est, &used)) != ESTIMATE_OK || used)) return s;
  if (np == 0) {
    if (!est->line_late) /* a face 2 was searched before */
      snprintf(est->face2_note, sizeof est->face2_note,
               "no second resting %s at >= %.0f deg to the first was confirmed stable",
               faces_tried(est), est->cfg.min_face_angle_rad * 180.0 / CL_PI);
    return verify_begin(est);
  }
  return confirm_plans(est, np);
}

/* No candidate of the current face was confirmed stable. */
static estimate_status_t confirm_none(est_t *est) {
  return est->phase == PHASE_FACE1 ? face_one_closed(est) : face_two_closed(est);
}

/* est->chosen was confirmed stable: search on it. */
static estimate_status_t confirmed(est_t *est) {
  const face_plan_t *p = &est->chosen;
  if (est->steered) /* the steered estimate chose the face; the searches plan from the prior's */
    memcpy(est->guess_m, est->unsteered_m, sizeof est->guess_m);
  est->steered = 0;
  if (est->phase == PHASE_FACE1) {
    est->phase = PHASE_FACE1_SEARCH0;
    return search_start(est, p->face, est->chosen_log, p->yaw[0], p->margin[0], est->redo_of);
  }
  est->phase = PHASE_FACE2_SEARCH;
  return search_start(est, p->face, est->chosen_log, p->yaw[0], p->margin[0], est->redo_of);
}

/* How far the CoM can be from the current estimate along a (unit, link frame) at most: to the
 * farthest vertex, as it lies inside the object. */
static double hull_extent(const est_t *est, const double a[3]) {
  double ext = 0.0;
  const double g = cl_vec3_dot(est->guess_m, a);
  for (size_t i = 0; i < est->mesh->vertex_count; ++i)
    ext = fmax(ext, fabs(cl_vec3_dot(est->mesh->vertices_m[i], a) - g));
  return ext;
}

/* The deciding trials of search si (its bracket; with a noise model every clear trial within
 * c +- (h + 3 sigma)), checked at the current estimate: the smallest chord margin, less the
 * estimate's half width along the edge line (and 3 sigma of sideways placement noise). */
/* Closed-patch trial t (est->regime classified at its released pose): how far inside the patch
 * the estimate projects, less the interval box's extent in the patch plane (world x and y). */
static double closed_margin(est_t *est, const estimate_trial_t *t, const qlearn_solve_result_t *res,
                            int *bounded) {
  double r[3][3], cw[3], ext2 = 0.0;
  model_quat_to_rot(t->released.orientation_wxyz, r);
  for (int i = 0; i < 2; ++i) {
    cw[i] = t->released.position_m[i] + cl_vec3_dot(r[i], est->guess_m);
    double ext = dir_halfwidth(est, res, r[i]); /* world x / y in the link frame: rows of R */
    if (!isfinite(ext)) {
      ext = hull_extent(est, r[i]);
      *bounded = 0;
    }
    ext2 += ext * ext;
  }
  const model_patch_t *pa = &est->regime.patch;
  return model_polygon_margin((const double(*)[2])pa->polygon_xy_m, pa->vertex_count, cw) -
         sqrt(ext2);
}

static double search_verified_margin(est_t *est, int si, const qlearn_solve_result_t *res,
                                     int *bounded) {
  const estimate_result_t *out = &est->result;
  const estimate_search_t *sr = &out->search[si];
  const double sigma = est->cfg.noise_sigma_m;
  double worst = HUGE_VAL;
  *bounded = 1;
  if (search_rough(est, si)) return worst; /* its STAYS bounds need no regime */
  if (sr->pivot) { /* the CoM between the edge's ends, the interval box included */
    const estimate_pivot_t *pv = &est->pivot[si];
    double ext = dir_halfwidth(est, res, pv->e);
    if (!isfinite(ext)) {
      ext = hull_extent(est, pv->e);
      *bounded = 0;
    }
    return estimate_pivot_side_margin(pv, est->guess_m) - ext;
  }
  for (size_t i = 0; i < out->trial_count; ++i) {
    const estimate_trial_t *t = &out->trial[i];
    if (t->search != si || !clear_outcome(est, t) || !deciding_trial(est, sr, i)) continue;
    if (model_regime_classify_in(est->mesh, &t->released, est->base_size_m, MODEL_EDGE_PX,
                                 est->guess_m, NULL, est->work, &est->regime) != MODEL_OK)
      return -HUGE_VAL;
    /* A closed patch's chord spans every CoM over the patch: what counts is how far inside. */
    if (est->regime.kind == MODEL_REGIME_CLOSED_PATCH) {
      worst = fmin(worst, closed_margin(est, t, res, bounded)); /* noise moves the object, not
                                                                   its CoM over the patch */
      continue;
    }
    if (!est->regime.patch.flat) return -HUGE_VAL;
    double r[3][3], along[3];
    model_quat_to_rot(t->released.orientation_wxyz, r);
    for (int k = 0; k < 3; ++k) along[k] = r[1][k]; /* world +y, the +X edge line, in the link */
    double ext = dir_halfwidth(est, res, along);
    if (!isfinite(ext)) {
      ext = hull_extent(est, along); /* the CoM is inside the object */
      *bounded = 0;
    }
    const double m = est->regime.chord_margin_m - ext - 3.0 * sigma;
    if (m < worst) worst = m;
  }
  return worst;
}

/* Search again on the face of search si, with the yaw of largest chord margin at the current
 * estimate among directions that keep the solve's shape: at least min_dir_angle from every
 * other search fed on that face (or, when no yaw qualifies, half that: an oblique pair still
 * determines the face's plane, and the bound widens with it), or (none fed there) within 30
 * degrees of the old direction; and at least 20 degrees from every direction that failed there. */
static int retest_yaw(est_t *est, const estimate_search_t *old, int fi, const double m[YAW_STEPS],
                      double min_angle) {
  const estimate_result_t *out = &est->result;
  int siblings = 0;
  for (size_t j = 0; j < out->search_count; ++j)
    siblings += out->search[j].fed && out->search[j].face == old->face;
  int best = -1;
  for (int k = 0; k < 2 * YAW_STEPS; ++k) { /* yaw and yaw + pi share a chord */
    double q[4], u[3];
    model_orientation_yawed(est->faces[fi].orientation_wxyz, k * CL_PI / YAW_STEPS, q);
    dir_of(q, u);
    int ok = m[k % YAW_STEPS] >= est->cfg.min_chord_margin_m &&
             (siblings > 0 || cl_vec3_dot(u, old->dir_link) >= cos(CL_PI / 6.0));
    for (size_t j = 0; ok && j < out->search_count; ++j) {
      const estimate_search_t *o = &out->search[j];
      if (o->face != old->face) continue;
      const double c = fabs(cl_vec3_dot(u, o->dir_link));
      if (o->fed && c > cos(min_angle) + 1e-9) ok = 0;
      if (!o->fed && c > cos(CL_PI / 9.0)) ok = 0;
    }
    if (ok && (best < 0 || m[k % YAW_STEPS] > m[best % YAW_STEPS])) best = k;
  }
  return best;
}

/* A search on closed patch si failed its check at the estimate (the estimate projects too near
 * the patch's side): instead of another yaw on it, another closed patch for its face, listed
 * under the current estimate (at most ESTIMATE_FACE_REDO times per estimate). Face 1: its two
 * searches are dropped and done again on the new patch (they share the patch); face 2: at an
 * angle to face 1. *started = 1 when a stable check was asked for; the searches then go through
 * the phases of that face. */
static estimate_status_t face_redo(est_t *est, int si, int *started) {
  estimate_result_t *out = &est->result;
  const int face = out->search[si].face, one = est->face_src[face] == est->face1;
  if (!est->cfg.closed_patches || est->face_redos >= ESTIMATE_FACE_REDO ||
      out->search_count + (one ? 2u : 1u) > ESTIMATE_MAX_SEARCHES)
    return ESTIMATE_OK;
  ++est->face_redos;
  est->phase = one ? PHASE_FACE1 : PHASE_FACE2;
  est->redo_face = one ? face : -1; /* face_allowed: the new face 1 at an angle to face 2 */
  size_t np = 0;
  estimate_status_t s = closed_append(est);
  if (s == ESTIMATE_OK) s = closed_plans(est, &np);
  if (s != ESTIMATE_OK || np == 0) return s;
  for (size_t j = 0; one && j < out->search_count; ++j) {
    estimate_search_t *o = &out->search[j];
    if (o->face != face || (int)j == si || !o->fed) continue;
    o->fed = 0;
    o->retested = 1;
    snprintf(o->note, sizeof o->note, "its face was replaced: search %d failed the patch check",
             si);
  }
  est->face1_redone |= one;
  if (one) est->closed2 = 0; /* face 2's patches are listed again under the new estimate */
  out->search[si].retested = 1;
  est->redo_of = si;
  *started = 1;
  return confirm_plans(est, np);
}

/* Search si failed its check at the estimate (on a closed patch, or with no other yaw left): its
 * STAYS trials still bound the CoM exactly (rough faces), so its mirror at yaw + pi is searched
 * and the pair gives a plane as on a rough face (when rough_usable). The check then no longer
 * matters. */
static estimate_status_t rough_retest(est_t *est, int si, int *started) {
  estimate_result_t *out = &est->result;
  if (!rough_usable(est) || out->search_count >= ESTIMATE_MAX_SEARCHES) return ESTIMATE_OK;
  estimate_search_t *sr = &out->search[si];
  est->search_rough[si] = 1;
  sr->retested = 1;
  *started = 1;
  est->phase = PHASE_RETEST;
  est->retest_of = si;
  est->mirror_next = si;
  return search_start(est, est->face_src[sr->face], sr->face, sr->yaw_rad + CL_PI,
                      sr->chord_margin_m, si);
}

/* Search again in place of search si (retest_yaw); *started = 0 when no search could be started
 * (no room, or no yaw qualifies: a note on si says so). */
static estimate_status_t retest_start(est_t *est, int si, int *started) {
  estimate_result_t *out = &est->result;
  *started = 0;
  if (out->search_count >= ESTIMATE_MAX_SEARCHES) return ESTIMATE_OK;
  const estimate_search_t old = out->search[si];
  const int fi = est->face_src[old.face];
  if (face_is_closed(est, fi)) {
    estimate_status_t s = rough_retest(est, si, started);
    if (s != ESTIMATE_OK || *started) return s;
    s = face_redo(est, si, started);
    if (s != ESTIMATE_OK || *started) return s;
  }
  double m[YAW_STEPS];
  estimate_status_t s = yaw_margins(est, &est->faces[fi], m);
  if (s != ESTIMATE_OK) return s;
  int best = retest_yaw(est, &old, fi, m, est->cfg.min_dir_angle_rad);
  if (best < 0) best = retest_yaw(est, &old, fi, m, 0.5 * est->cfg.min_dir_angle_rad);
  estimate_search_t *sr = &out->search[si];
  if (best < 0) {
    const size_t len = strlen(sr->note);
    snprintf(sr->note + len, sizeof sr->note - len, "; no other yaw spans the estimate");
    return rough_retest(est, si, started);
  }
  sr->retested = 1;
  *started = 1;
  est->phase = PHASE_RETEST;
  est->retest_of = si;
  return search_start(est, fi, old.face, best * CL_PI / YAW_STEPS, m[best % YAW_STEPS], si);
}

/* The next search to do again: one whose own trials left the flat-patch regime (its plane was
 * never used) and that was not done again yet; else the fed search whose check at the estimate
 * fails worst. Only checks the other planes can bound count: a search whose edge direction the
 * others leave undetermined stays fed but unverified (sr->verified 0), and the components that
 * depend on it are not claimed. -1: nothing to do. *unverified: the search returned failed its
 * check (and is to be unfed). */
static int worst_search(est_t *est, const qlearn_solve_result_t *res, int *unverified) {
  estimate_result_t *out = &est->result;
  *unverified = 0;
  int worst = -1;
  for (size_t i = 0; i < out->search_count; ++i) {
    estimate_search_t *sr = &out->search[i];
    if (!sr->fed) continue;
    int bounded = 0;
    sr->verified_margin_m = search_verified_margin(est, (int)i, res, &bounded);
    sr->verify_need_m = search_rough(est, (int)i) ? 0.0
                        : sr->pivot               ? ESTIMATE_PIVOT_SIDE_M
                        : est->noisy && face_is_closed(est, est->face_src[sr->face])
                            ? ESTIMATE_CLOSED_NOISY_MARGIN_M
                            : est->cfg.verify_margin_m;
    const double slack = sr->verified_margin_m - sr->verify_need_m;
    sr->verified = bounded && slack >= 0.0;
    if (!bounded || sr->verified) continue;
    if (worst < 0 || slack < out->search[worst].verified_margin_m -
                                 out->search[worst].verify_need_m - ESTIMATE_TIE_M)
      worst = (int)i;
  }
  for (size_t i = 0; i < out->search_count; ++i)
    if (!out->search[i].fed && out->search[i].flat_failed && !out->search[i].retested)
      return (int)i;
  *unverified = worst >= 0;
  return worst;
}

static estimate_status_t finish(est_t *est);

enum { ESTIMATE_REFINES = 3 }; /* times one search can be resumed */
/* With a noise model, a closed patch that does not hold the interval box is given one more chance
 * before it is searched again or made rough, when the narrower box would make up what it lacks:
 * the target half width drops to this fraction, and the check runs again on the narrower box (a
 * 0.8 mm patch margin fails a 0.5 mm box by 0.16 mm and holds a 0.27 mm one; a mug,
 * bench_coverage). The box's extent in the patch plane, about sqrt 2 half widths, then shrinks
 * by (1 - this) sqrt 2 target. */
#define ESTIMATE_CLOSED_TARGET_SCALE 0.5

/* Resume noisy search si (PBA from all its clear trials) until its 95 % interval is width_m
 * wide; search_done goes back to the check. Its plane is not used until it is set again. */
static estimate_status_t refine_start(est_t *est, int si, double width_m) {
  estimate_search_t *sr = &est->result.search[si];
  walk_t *w = &est->walk;
  memset(w, 0, sizeof *w);
  search_ctx_t *sc = &w->sc;
  sc->si = si;
  sc->log_face = sr->face;
  ctx_orient(est, est->face_src[sr->face], sr->yaw_rad, sc);
  sc->lo = w->pc.range_lo_m = sr->range_lo_m;
  sc->hi = w->pc.range_hi_m = sr->range_hi_m;
  w->pc.prior_m = sr->prior_m;
  ++sr->refines;
  sr->fed = 0;
  sr->note[0] = '\0';
  est->phase = PHASE_REFINE;
  return handover_start(est, width_m);
}

/* With a noise model, the components are only as narrow as their searches: when a determined
 * component's 95 % half width h is over cfg->noise_target_halfwidth_m T, resume the fed search
 * that contributes most to its variance. The component's variance is sum_j p_j^2 sigma_j^2
 * (plane_coef; with three planes p_j does not depend on the weights), so search j alone meets the
 * target at sigma_j'^2 = ((T - bias) / z)^2 - the others' share) / p_j^2; it is asked for a
 * sigma between a half and 0.9 of its own (the rest, if any, on a later pass). Searches that can
 * still run trials only: not rough (their bounds are not posteriors), within the budget of
 * cfg->noise_max_trials after the walk and ESTIMATE_REFINES resumptions; a component whose
 * other planes alone leave it wide is left as it is. *started = 1 when one was resumed. */
static estimate_status_t refine_next(est_t *est, int *started) {
  const estimate_result_t *out = &est->result;
  const qlearn_solve_result_t *res = &est->res;
  const double target = est->cfg.noise_target_halfwidth_m * est->target_scale, z = est->cfg.z;
  *started = 0;
  if (!est->noisy || !(target > 0.0)) return ESTIMATE_OK;
  double worst_ratio = 1.0;
  int best = -1;
  double best_sigma = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double e[3] = {k == 0, k == 1, k == 2};
    const double hw = dir_halfwidth(est, res, e);
    if (!isfinite(hw) || hw <= worst_ratio * target) continue;
    double var = 0.0, bias = 0.0, top = 0.0, fixed = 0.0; /* fixed: what no search can narrow */
    double p_top = 0.0, sigma_top = 0.0;
    int j_top = -1;
    for (size_t j = 0; j < out->search_count; ++j) {
      const estimate_search_t *sr = &out->search[j];
      if (!sr->fed) continue;
      const double p = plane_coef(est, res, e, sr), sigma = plane_sigma(est, sr);
      const double part = p * p * sigma * sigma;
      var += part;
      bias += fabs(p) * sr->bias_m;
      if (search_rough(est, (int)j) || sr->refines >= ESTIMATE_REFINES ||
          sr->handover_trials >= est->cfg.noise_max_trials) {
        fixed += part;
        continue;
      }
      if (!(part > top)) continue;
      top = part;
      p_top = p;
      sigma_top = sigma;
      j_top = (int)j;
    }
    const double allowed = (target - bias) / z;
    /* Out of reach: the planes no search can narrow (a rough pair's bound) leave the others
     * under half the variance allowed. */
    if (j_top < 0 || !(allowed > 0.0) || fixed >= 0.5 * allowed * allowed) continue;
    const double want2 = allowed * allowed - (var - top);
    double s_new = want2 > 0.0 ? sqrt(want2) / fabs(p_top) : 0.0;
    s_new = fmin(fmax(s_new, 0.5 * sigma_top), 0.9 * sigma_top);
    worst_ratio = hw / target;
    best = j_top;
    best_sigma = s_new;
  }
  if (best < 0) return ESTIMATE_OK;
  *started = 1;
  /* PBA stops on the width of its interval; the half width it reports is the longer side about
   * the median plus half a bin (qlearn_pba_estimate): ask for 0.9 of the width that gives, so
   * one resumption reaches it. */
  const estimate_search_t *sr = &out->search[best];
  const double half_bin = 0.5 * (sr->range_hi_m - sr->range_lo_m) / QLEARN_PBA_BINS;
  return refine_start(est, best, fmax(1.8 * (z * best_sigma - half_bin), 4.0 * half_bin));
}

/* Every check passed, but a component is still not found (too wide: a rough face 2 whose two
 * sides' tip-over distances lie far apart, or not determined): the faces along face 1's normal
 * (line_once) that were not listed yet are tried as face 2 candidates once, and a face confirmed
 * among them adds its searches to the solve. *started = 1 when that began. */
static estimate_status_t wide_more(est_t *est, int *started) {
  *started = 0;
  int wide = 0;
  for (int k = 0; k < 3; ++k) wide |= !(est->halfwidth_m[k] <= est->cfg.max_halfwidth_m);
  if (!wide || est->line2 || est->face1 < 0) return ESTIMATE_OK;
  est->phase = PHASE_FACE2;
  size_t np = 0;
  estimate_status_t s = line_once(est, &np);
  if (s != ESTIMATE_OK || np == 0) return s;
  *started = 1;
  est->line_late = 1;
  return confirm_plans(est, np);
}

/* yaw_more adds a direction only when it would narrow the widest component not found to this
 * fraction of its width (or under the claim limit). */
#define ESTIMATE_MORE_GAIN 0.8

/* A component the planes do not determine counts this wide in a sum of half widths (wide_with):
 * more than any determined one, so that a plane that determines one more is progress. */
#define ESTIMATE_UNDETERMINED_M 1e3

/* How wide the components wider than wide_m are (est->halfwidth_m: INFINITY when not found; with
 * wide_m the claim limit, the components not found): the widest of them, or with sum 1 the sum
 * of their half widths (ESTIMATE_UNDETERMINED_M for one not determined), from the fed planes and,
 * when u is not NULL, one more plane along u of half width h through the estimate: what a search
 * along u would give if it reached h. 0 when no component is that wide. */
static double wide_with(est_t *est, const double *u, double h, double wide_m, int sum) {
  estimate_result_t *out = &est->result;
  if (u) { /* a hypothetical fed search after the real ones, removed below */
    estimate_search_t *sr = &out->search[out->search_count++];
    memset(sr, 0, sizeof *sr);
    memcpy(sr->plane_n_obj, u, sizeof sr->plane_n_obj);
    sr->plane_d_m = cl_vec3_dot(u, est->guess_m);
    sr->halfwidth_m = h;
    sr->fed = 1;
  }
  qlearn_solve_result_t res;
  double widest = 0.0;
  if (solve_all(est, &res) == ESTIMATE_OK)
    for (int k = 0; k < 3; ++k) {
      if (est->halfwidth_m[k] <= wide_m) continue;
      const double e[3] = {k == 0, k == 1, k == 2};
      const double w = dir_halfwidth(est, &res, e);
      widest = sum ? widest + fmin(w, ESTIMATE_UNDETERMINED_M) : fmax(widest, w);
    }
  else
    widest = HUGE_VAL;
  if (u) --out->search_count;
  return widest;
}

/* The widest of the components not found (wide_with). */
static double widest_with(est_t *est, const double *u, double h) {
  return wide_with(est, u, h, est->cfg.max_halfwidth_m, 0);
}

/* Every check passed and no face is left to list, but a component is still too wide or not
 * determined (a pebble whose face 1 tipped when a support point left B, x and y +-1.9 mm, while
 * faces 2 and 3 each gave one plane within 0.2 mm): one more direction on a face that already
 * gave a plane, the yaw that narrows the widest such component most, counting on the half width
 * the face's fed searches reached (a rough face: a pair). The candidates: every face with a fed
 * search, yaws on the 2-degree sweep at least 20 deg from that face's searches, with a chord
 * margin on flat faces. Only when the widest drops to ESTIMATE_MORE_GAIN of what it is or under
 * the claim limit, at most max_added_dirs times. *started = 1 when a search began. */
static estimate_status_t yaw_more(est_t *est, int *started) {
  estimate_result_t *out = &est->result;
  *started = 0;
  if (est->more >= est->cfg.max_added_dirs || out->search_count + 2 > ESTIMATE_MAX_SEARCHES)
    return ESTIMATE_OK;
  const double now = widest_with(est, NULL, 0.0);
  if (!(now > 0.0)) return ESTIMATE_OK;
  /* worth a search: a fifth narrower, or under the limit (+-1.07 mm to under +-1 mm) */
  double best = fmax(ESTIMATE_MORE_GAIN * now, fmin(now, est->cfg.max_halfwidth_m));
  double best_yaw = 0.0, best_margin = 0.0;
  int best_face = -1;
  for (size_t lf = 0; lf < out->face_count; ++lf) {
    double h = 0.0;
    int fed = 0;
    for (size_t j = 0; j < out->search_count; ++j)
      if (out->search[j].fed && out->search[j].face == (int)lf) {
        h += out->search[j].halfwidth_m + out->search[j].bias_m;
        ++fed;
      }
    if (fed == 0) continue;
    h /= fed;
    const int fi = est->face_src[lf];
    const int any_chord = est->rough[fi] || face_is_closed(est, fi);
    double m[YAW_STEPS];
    if (!any_chord) {
      estimate_status_t s = yaw_margins(est, &est->faces[fi], m);
      if (s != ESTIMATE_OK) return s;
    }
    for (int k = 0; k < YAW_STEPS; ++k) {
      if (!any_chord && !(m[k] >= est->cfg.min_chord_margin_m)) continue;
      double q[4], u[3];
      model_orientation_yawed(est->faces[fi].orientation_wxyz, k * CL_PI / YAW_STEPS, q);
      dir_of(q, u);
      int near = 0;
      for (size_t j = 0; j < out->search_count && !near; ++j)
        near = out->search[j].face == (int)lf &&
               fabs(cl_vec3_dot(u, out->search[j].dir_link)) > cos(CL_PI / 9.0);
      if (near) continue;
      const double w = widest_with(est, u, h);
      if (w < best) {
        best = w;
        best_face = (int)lf;
        best_yaw = k * CL_PI / YAW_STEPS;
        best_margin = any_chord ? -HUGE_VAL : m[k];
      }
    }
  }
  if (best_face < 0) return ESTIMATE_OK;
  ++est->more;
  *started = 1;
  est->phase = PHASE_MORE;
  est->more_si = (int)out->search_count;
  est->more_before_m = now;
  return search_start(est, est->face_src[best_face], best_face, best_yaw, best_margin, -1);
}

/* An added search (yaw_more's, pivot_more's: est->more_si) is over: its plane is kept only when
 * it narrowed the components wider than wide_m (est->more_before_m: the widest of them, or with
 * sum 1 the sum of their half widths, as wide_with measures them) and widened no other over
 * wide_m, nor a found one over the claim limit (noiseless, a wide plane can widen the bound of
 * the others: a pebble whose other directions also tipped when a support point left B).
 * *dropped = 1 when it was fed and is not kept (a note says why). */
static estimate_status_t added_check(est_t *est, double wide_m, int sum, int *dropped) {
  estimate_search_t *sr = &est->result.search[est->more_si];
  const double limit = est->cfg.max_halfwidth_m;
  *dropped = 0;
  if (!sr->fed) return ESTIMATE_OK;
  qlearn_solve_result_t res;
  estimate_status_t s = solve_all(est, &res);
  if (s != ESTIMATE_OK) return s;
  int lost = 0;
  double after = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double e[3] = {k == 0, k == 1, k == 2};
    const double w = dir_halfwidth(est, &res, e), was = est->halfwidth_m[k];
    if (was <= wide_m)
      lost |= !(w <= wide_m);
    else if (was <= limit)
      lost |= !(w <= limit);
    if (was > wide_m) after = sum ? after + fmin(w, ESTIMATE_UNDETERMINED_M) : fmax(after, w);
  }
  if (!lost && after < est->more_before_m) return ESTIMATE_OK;
  sr->fed = 0;
  *dropped = 1;
  char what[48];
  if (wide_m >= limit)
    snprintf(what, sizeof what, "not found");
  else
    snprintf(what, sizeof what, "wider than +-%.3f mm", 1e3 * wide_m);
  if (lost)
    snprintf(sr->note, sizeof sr->note, "added for a component %s, it widened %s", what,
             wide_m >= limit ? "a found one" : "another");
  else
    snprintf(sr->note, sizeof sr->note,
             "added for a component %s, it did not narrow it (+-%.3f mm, +-%.3f mm before%s)", what,
             1e3 * after, 1e3 * est->more_before_m, sum ? ", summed" : "");
  return ESTIMATE_OK;
}

/* yaw_more's search is over (added_check); one that is dropped ends yaw_more: the half width it
 * was chosen by was not reached. */
static estimate_status_t more_done(est_t *est) {
  int dropped = 0;
  const estimate_status_t s = added_check(est, est->cfg.max_halfwidth_m, 0, &dropped);
  if (dropped) est->more = UINT32_MAX;
  return s;
}

/* ---- pivots (docs/estimate.md, "Pivots") --------------------------------------------------- */

/* Pivots narrow the components wider than this: twice the resolution (noiseless, a face search's
 * bracket is one resolution wide; a rough pair's bounds can be far wider), at most the claim
 * limit. */
static double pivot_wide(const est_t *est) {
  return fmin(2.0 * est->cfg.resolution_m, est->cfg.max_halfwidth_m);
}

/* How far the CoM can lie from the estimate along a (unit, link frame), for planning: a's part in
 * the subspace the fed planes determine by the solve's bound, its part along each undetermined
 * direction v by how far the mesh's bounding box reaches from the estimate (far[k] along link
 * axis k, so sum_k |v_k| far[k] along v). */
static double plan_extent(const est_t *est, const double far[3], const double a[3]) {
  const qlearn_solve_result_t *res = &est->res;
  const int rank = est->have_solve ? res->rank : 0;
  double det[3] = {a[0], a[1], a[2]}, ext = 0.0;
  for (int j = 0; j < 3 - rank; ++j) { /* the null eigenvectors come first */
    const double *v = rank > 0 ? res->eigenvector[j] : (const double[3]){j == 0, j == 1, j == 2};
    const double p = cl_vec3_dot(a, v);
    for (int k = 0; k < 3; ++k) det[k] -= p * v[k];
    ext += fabs(p) * (fabs(v[0]) * far[0] + fabs(v[1]) * far[1] + fabs(v[2]) * far[2]);
  }
  const double len = cl_vec3_norm(det);
  if (rank > 0 && len > 1e-12) {
    for (int k = 0; k < 3; ++k) det[k] /= len;
    const double hw = dir_halfwidth(est, res, det);
    ext +=
        len *
        (isfinite(hw) ? hw : fabs(det[0]) * far[0] + fabs(det[1]) * far[1] + fabs(det[2]) * far[2]);
  }
  return ext;
}

/* Was hull edge he the edge of a pivot search already? */
static int pivot_tried(const est_t *est, const model_hull_edge_t *he) {
  for (size_t j = 0; j < est->result.search_count; ++j) {
    const estimate_pivot_t *pv = &est->pivot[j];
    if (est->result.search[j].pivot && pv->v[0] + pv->v[1] == he->v[0] + he->v[1] &&
        (pv->v[0] == he->v[0] || pv->v[0] == he->v[1]))
      return 1;
  }
  return 0;
}

/* The pivot that would narrow the widest component not found most: over every hull edge not tried
 * yet, both ways along B's edge line, whose tilt range holds the estimate balanced and whose ends
 * hold the estimate with its box (ESTIMATE_PIVOT_SIDE_M), the one whose plane through the
 * estimate, as wide as a search reaches, leaves the widest component narrowest; edges whose tilts
 * cover where the CoM can lie along the test direction first; *gets: that widest. *found = 0
 * when none qualifies. Allocates the hull edges' array for the call. */
static estimate_status_t pivot_choose(est_t *est, estimate_pivot_t *best, double *gets,
                                      int *found) {
  *found = 0;
  const model_mesh_t *hull = NULL;
  if (model_support_work_hull(est->work, est->mesh, &hull) != MODEL_OK)
    return fail(est, ESTIMATE_E_GEOMETRY, "pivots: the convex hull of the mesh");
  model_aabb_t box;
  if (model_mesh_aabb(est->mesh, &box) != MODEL_OK)
    return fail(est, ESTIMATE_E_GEOMETRY, "pivots: the bounding box of the mesh");
  double far[3];
  for (int k = 0; k < 3; ++k)
    far[k] = fmax(est->guess_m[k] - box.min_m[k], box.max_m[k] - est->guess_m[k]);
  const size_t cap = 3 * hull->triangle_count;
  model_hull_edge_t *edges = malloc(cap * sizeof *edges);
  if (!edges) return fail(est, ESTIMATE_E_NOMEM, "pivots: the hull's edges");
  size_t n = 0;
  if (model_hull_edges(hull, cos(1e-3), edges, cap, &n) != MODEL_OK) n = 0;
  const double h_exp = 0.5 * est->cfg.resolution_m + ESTIMATE_PIVOT_BIAS_M;
  double best_score = HUGE_VAL, best_side = 0.0;
  int best_covers = 0;
  for (size_t i = 0; i < n; ++i) {
    if (pivot_tried(est, &edges[i])) continue;
    for (int flip = 0; flip < 2; ++flip) {
      estimate_pivot_t pv;
      if (!estimate_pivot_plan(hull, &edges[i], flip, est->guess_m, ESTIMATE_PIVOT_WEDGE_RAD,
                               ESTIMATE_PIVOT_HEIGHT_M, &pv))
        continue;
      const double side =
          estimate_pivot_side_margin(&pv, est->guess_m) - plan_extent(est, far, pv.e);
      if (!(side >= ESTIMATE_PIVOT_SIDE_M)) continue;
      const double ext = plan_extent(est, far, pv.u) / pv.h_m; /* tan of the tilt to reach it */
      const int covers = ext <= tan(-pv.beta_lo_rad) && ext <= tan(pv.beta_hi_rad);
      const double score = wide_with(est, pv.u, h_exp, pivot_wide(est), 1);
      /* Better by more than rounding (a mirror image scores the same but for the last bits, which
       * differ between backends that agree to 1e-16 m): else the first in edge order stays. */
      const int better =
          covers > best_covers ||
          (covers == best_covers &&
           (score < best_score - ESTIMATE_TIE_M ||
            (fabs(score - best_score) <= ESTIMATE_TIE_M && side > best_side + ESTIMATE_TIE_M)));
      if (!better) continue;
      *best = pv;
      best_score = score;
      best_side = side;
      best_covers = covers;
      *found = 1;
    }
  }
  free(edges);
  if (*found) estimate_pivot_reach(hull, best);
  *gets = best_score;
  return ESTIMATE_OK;
}

/* Start a pivot search on pv: its tilt range as x, from the estimate balanced (x = u . g), to a
 * resolution that makes its plane's half width (reach x tilt / 2) half cfg->resolution_m. */
static estimate_status_t pivot_start(est_t *est, const estimate_pivot_t *pv) {
  estimate_search_t *sr =
      search_new(est, -1, 0.0, estimate_pivot_side_margin(pv, est->guess_m), -1);
  if (!sr) return fail(est, ESTIMATE_E_CAPACITY, "too many searches");
  search_ctx_t *sc = &est->walk.sc;
  sc->pivot = 1;
  est->pivot[sc->si] = *pv;
  est->search_rough[sc->si] = 0;
  sr->pivot = 1;
  sr->retested = 1; /* no yaw to search again with: a failed check only unfeeds it */
  memcpy(sr->pivot_link_m[0], pv->p1_m, sizeof pv->p1_m);
  memcpy(sr->pivot_link_m[1], pv->p2_m, sizeof pv->p2_m);
  memcpy(sc->u, pv->u, sizeof sc->u);
  memcpy(sr->dir_link, pv->u, sizeof sc->u);
  sc->comp = 0;
  for (int k = 1; k < 3; ++k)
    if (fabs(sc->u[k]) > fabs(sc->u[sc->comp])) sc->comp = k;
  sc->lo = sr->range_lo_m = pv->gx_m - pv->h_m * tan(pv->beta_hi_rad);
  sc->hi = sr->range_hi_m = pv->gx_m - pv->h_m * tan(pv->beta_lo_rad);
  sr->prior_m = pv->gx_m;
  const double res = est->cfg.resolution_m * fmin(1.0, pv->h_m / pv->reach_m);
  return walk_begin(est, pv->gx_m, res);
}

/* Every check passed and nothing else is left, but a component is still not found: a pivot
 * search (noiseless, at most cfg->max_pivots, pivot_choose). *started = 1 when one began. */
static estimate_status_t pivot_more(est_t *est, int *started) {
  estimate_result_t *out = &est->result;
  *started = 0;
  if (est->noisy || est->pivots >= est->cfg.max_pivots ||
      out->search_count + 1 > ESTIMATE_MAX_SEARCHES)
    return ESTIMATE_OK;
  const double now = wide_with(est, NULL, 0.0, pivot_wide(est), 1);
  if (!(now > 0.0)) return ESTIMATE_OK;
  estimate_pivot_t pv;
  int found = 0;
  double gets = 0.0;
  estimate_status_t s = pivot_choose(est, &pv, &gets, &found);
  if (s != ESTIMATE_OK) return s;
  /* worth a search as a direction more is: the wide components' half widths a fifth narrower in
   * sum (one more determined counts as more) */
  if (!found || !(gets < ESTIMATE_MORE_GAIN * now)) {
    est->pivots = est->cfg.max_pivots; /* none qualifies now: none will */
    return ESTIMATE_OK;
  }
  ++est->pivots;
  *started = 1;
  est->phase = PHASE_PIVOT;
  est->more_si = (int)out->search_count;
  est->more_before_m = now;
  return pivot_start(est, &pv);
}

/* Solve; with a noise model, first resume a search while a component is wider than the target
 * (refine_next: the checks below use the interval box). Then check every fed search's physics at
 * the estimate, and drop the one that fails worst (one bad plane moves the estimate, so the
 * others are judged again without it); search again in its place, or where a search's own trials
 * left the flat-patch regime, while the retest budget lasts. Bounded: every pass stops, resumes a
 * search within its budget, unfeeds a search or spends a retest. Resumed (from est->pass) when a
 * retest's or a refinement's search is over. */
static estimate_status_t verify_loop(est_t *est) {
  estimate_result_t *out = &est->result;
  qlearn_solve_result_t *res = &est->res;
  for (; est->pass <= 3 * ESTIMATE_MAX_SEARCHES; ++est->pass) {
    estimate_status_t s = update_guess(est);
    if (s != ESTIMATE_OK) return s;
    int started = 0; /* narrow the components first: the checks use the interval box */
    s = refine_next(est, &started);
    if (s != ESTIMATE_OK || started) return s;
    int unverified = 0;
    const int w = worst_search(est, res, &unverified);
    if (w < 0) {
      s = wide_more(est, &started);
      if (s == ESTIMATE_OK && !started) s = yaw_more(est, &started);
      if (s == ESTIMATE_OK && !started) s = pivot_more(est, &started);
      return s != ESTIMATE_OK || started ? s : finish(est);
    }
    estimate_search_t *sw = &out->search[w];
    const double closed_gain = (1.0 - ESTIMATE_CLOSED_TARGET_SCALE) * sqrt(2.0) *
                               est->cfg.noise_target_halfwidth_m; /* what the narrower box adds */
    if (est->noisy && est->target_scale == 1.0 && closed_gain > 0.0 && !sw->pivot &&
        face_is_closed(est, est->face_src[sw->face]) && !search_rough(est, w) &&
        sw->verify_need_m - sw->verified_margin_m <= closed_gain) {
      est->target_scale = ESTIMATE_CLOSED_TARGET_SCALE; /* narrow the box, then check again */
      continue;
    }
    if (unverified) {
      sw->fed = 0;
      snprintf(sw->note, sizeof sw->note,
               "at the estimate its %s by %.2f mm, under the %.2f mm needed",
               sw->pivot ? "edge's ends hold the interval box"
               : face_is_closed(est, est->face_src[sw->face])
                   ? "patch holds the interval box"
                   : "chord spans the interval along the edge",
               1e3 * sw->verified_margin_m, 1e3 * sw->verify_need_m);
    }
    if (sw->retested || est->retests >= est->cfg.max_retests) {
      sw->retested = 1; /* no (more) retests: only unfeeding continues */
      if (!unverified) return finish(est);
      continue;
    }
    ++est->retests;
    s = retest_start(est, w, &started);
    if (s != ESTIMATE_OK || started) return s; /* search_done resumes the loop */
    sw->retested = 1;
  }
  estimate_status_t s = update_guess(est);
  return s == ESTIMATE_OK ? finish(est) : s;
}

static estimate_status_t verify_begin(est_t *est) {
  est->retests = 0;
  est->pass = 0;
  return verify_loop(est);
}

/* Is a search on another face than face 1 fed (a face 2 kept when face 1 was replaced)? */
static int face_two_fed(const est_t *est) {
  for (size_t j = 0; j < est->result.search_count; ++j) {
    const estimate_search_t *o = &est->result.search[j];
    if (o->fed && o->face >= 0 && est->face_src[o->face] != est->face1) return 1;
  }
  return 0;
}

/* A search is over: what comes next depends on the phase. */
static estimate_status_t search_done(est_t *est) {
  estimate_status_t s;
  const face_plan_t *p = &est->chosen;
  switch (est->phase) {
    case PHASE_FACE1_SEARCH0: {
      face_plan_t *c = &est->chosen;
      s = update_guess(est);
      if (s == ESTIMATE_OK && !face_is_closed(est, c->face) && !est->rough[c->face])
        /* closed and rough: any yaw, kept at 90 deg */
        s = plan_partner(est, c->face, c->yaw[0], &c->yaw[1], &c->margin[1]);
      if (s != ESTIMATE_OK) return s;
      est->phase = PHASE_FACE1_SEARCH1;
      return search_start(est, c->face, est->chosen_log, c->yaw[1], c->margin[1], -1);
    }
    case PHASE_FACE1_SEARCH1:
      est->face1 = p->face;
      s = update_guess(est);
      if (s != ESTIMATE_OK) return s;
      return est->face1_redone && face_two_fed(est) ? verify_begin(est) : face_two(est);
    case PHASE_FACE2_SEARCH: return verify_begin(est);
    case PHASE_RETEST:
      est->result.search[est->retest_of].retested = 1;
      ++est->pass;
      return verify_loop(est);
    case PHASE_MORE:
      s = more_done(est);
      if (s != ESTIMATE_OK) return s;
      ++est->pass;
      return verify_loop(est);
    case PHASE_PIVOT: {
      int dropped = 0;
      s = added_check(est, pivot_wide(est), 1, &dropped);
      if (s != ESTIMATE_OK) return s;
      ++est->pass;
      return verify_loop(est);
    }
    case PHASE_REFINE: ++est->pass; return verify_loop(est);
    default: return fail(est, ESTIMATE_E_ARG, "internal: a search ended in no search phase");
  }
}

/* The fed search whose plane widens a . c most (the largest term |p_j| (h_j + b_j) of
 * dir_halfwidth), or -1. */
static int widest_plane(const est_t *est, const qlearn_solve_result_t *res, const double a[3]) {
  int widest = -1;
  double most = 0.0;
  for (size_t i = 0; i < est->result.search_count; ++i) {
    const estimate_search_t *sr = &est->result.search[i];
    if (!sr->fed) continue;
    const double w = fabs(plane_coef(est, res, a, sr)) * (sr->halfwidth_m + sr->bias_m);
    if (w > most) {
      most = w;
      widest = (int)i;
    }
  }
  return widest;
}

/* By the outcome model, how far outside its support polygon the estimate lay at the placement of
 * search si that tipped next to its STAYS (the largest x that tipped below the smallest that
 * stayed, or the largest that tipped when none stayed; docs/physics.md, "The outcome model,
 * validated"). Where the CoM sets the threshold that is about the bracket; millimetres mean a
 * support point left B first and the object tipped wherever its CoM was. HUGE_VAL when nothing
 * tipped there or the model cannot say. */
static double tip_margin(const est_t *est, int si, model_outcome_work_t *work,
                         model_outcome_support_t *sup) {
  const estimate_result_t *out = &est->result;
  double stays = HUGE_VAL;
  for (size_t i = 0; i < out->trial_count; ++i)
    if (out->trial[i].search == si && seen_outcome(est, &out->trial[i]) == ESTIMATE_STAYS)
      stays = fmin(stays, out->trial[i].x_m);
  int tip = -1;
  for (size_t i = 0; i < out->trial_count; ++i) {
    const estimate_trial_t *t = &out->trial[i];
    if (t->search == si && seen_outcome(est, t) == ESTIMATE_TIPS && t->x_m < stays &&
        (tip < 0 || t->x_m > out->trial[tip].x_m))
      tip = (int)i;
  }
  int in;
  double margin;
  if (tip < 0 ||
      model_outcome_support_build(est->mesh, &out->trial[tip].released, est->base_size_m, NULL,
                                  work, sup) != MODEL_OK ||
      model_outcome_support_test(sup, est->guess_m, &in, &margin) != MODEL_OK)
    return HUGE_VAL;
  return margin;
}

/* Why a component is not found, when rough search j (its widest plane, or the search that was not
 * used) and its mirror tipped because a support point left B, not because the CoM crossed the
 * edge (the estimate more than the limit outside the support at the tip: a bowl on its side, on a
 * few points of its foot ring and rim): appended to r as "; ..." (nothing otherwise). Allocates
 * the outcome model's work area for the call. */
static void contact_limited_note(const est_t *est, int j, char *r, size_t size) {
  const estimate_result_t *out = &est->result;
  if (j < 0 || !search_rough(est, j)) return;
  if (out->search[j].mirror_of >= 0) j = out->search[j].mirror_of;
  const size_t wsize = model_outcome_work_size(est->mesh);
  void *mem = malloc(wsize);
  model_outcome_support_t *sup = malloc(sizeof *sup);
  model_outcome_work_t *work = mem ? model_outcome_work_init(mem, wsize, est->mesh) : NULL;
  double worst = HUGE_VAL;
  int at = -1;
  for (size_t i = 0; work && sup && i < out->search_count; ++i) {
    if ((int)i != j && out->search[i].mirror_of != j) continue;
    const double m = tip_margin(est, (int)i, work, sup);
    if (m < worst) {
      worst = m;
      at = (int)i;
    }
  }
  free(mem);
  free(sup);
  if (at < 0 || !(worst < -est->cfg.max_halfwidth_m)) return;
  const size_t len = strlen(r);
  snprintf(r + len, size - len,
           "; on face %d (search %d) it tipped when a support point left B, not when the CoM "
           "crossed the edge (the estimate %.1f mm outside the support left)",
           out->search[at].face, at, -1e3 * worst);
}

/* Why component k is not found (or "" when it is). */
static void component_reason(est_t *est, int k, int determined, int unverified, double hw) {
  estimate_result_t *out = &est->result;
  char r[sizeof out->reason[k]];
  if (out->found[k]) {
    r[0] = '\0';
  } else if (determined && unverified >= 0) {
    snprintf(r, sizeof r,
             "depends on search %d, whose chord cannot be checked: the estimate "
             "along its edge is not determined",
             unverified);
  } else if (determined) {
    snprintf(r, sizeof r, "its interval +-%.3f mm is wider than the %.3f mm limit", 1e3 * hw,
             1e3 * est->cfg.max_halfwidth_m);
    const double e[3] = {k == 0, k == 1, k == 2};
    contact_limited_note(est, widest_plane(est, &est->res, e), r, sizeof r);
  } else if (est->face2_note[0] && out->rank == 2) {
    snprintf(r, sizeof r, "not determined: %s", est->face2_note);
  } else {
    int last = -1; /* the last search that is not fed says most */
    for (size_t i = 0; i < out->search_count; ++i)
      if (!out->search[i].fed && out->search[i].note[0] && out->search[i].mirror_of < 0)
        last = (int)i;
    if (last >= 0) {
      snprintf(r, sizeof r, "not determined: search %d not used: %s", last, out->search[last].note);
      contact_limited_note(est, last, r, sizeof r);
    } else
      snprintf(r, sizeof r, "not determined by the %d independent directions measured", out->rank);
  }
  memcpy(out->reason[k], r, sizeof r);
}

/* The verified solve: every component with its interval, or the reason it is not found. */
static estimate_status_t finish(est_t *est) {
  estimate_result_t *out = &est->result;
  const qlearn_solve_result_t res = est->res;
  out->rank = res.rank;
  out->chi2 = res.chi2;
  int missing = 0;
  for (int k = 0; k < 3; ++k) {
    const double e[3] = {k == 0, k == 1, k == 2};
    const int determined = dir_determined(&res, e);
    const double hw = dir_halfwidth(est, &res, e);
    const int unverified = determined ? dir_unverified(est, &res, e) : -1;
    out->found[k] = determined && unverified < 0 && hw <= est->cfg.max_halfwidth_m;
    out->halfwidth_m[k] = out->found[k] ? hw : INFINITY;
    /* not found: report the best guess (prior moved by what was measured), flagged as such */
    out->com_m[k] = out->found[k] ? res.com_m[k] : est->guess_m[k];
    component_reason(est, k, determined, unverified, hw);
    if (!out->found[k] && !missing++)
      snprintf(out->msg, sizeof out->msg, "%c not found: %s", "xyz"[k], out -> reason[k]);
  }
  est->phase = PHASE_DONE;
  return ESTIMATE_OK;
}

/* The closed patches the current estimate can rest on (model_faces_stable), appended to faces[]
 * from est->closed_from on: at the start under the prior, for face 2 again under the estimate
 * after face 1's searches (its in-plane components are known then). */
static estimate_status_t closed_append(est_t *est) { return faces_append(est, 0); }

/* The faces model_faces_stable lists under the estimate, appended to faces[] from
 * est->closed_from on: the closed patches (rough 0), or every face not checked yet, marked rough
 * (rough 1). */
static estimate_status_t faces_append(est_t *est, int rough) {
  est->closed_from = est->nfaces;
  size_t n = 0;
  const model_status_t ms =
      model_faces_stable_in(est->mesh, est->guess_m, NULL, est->work, est->faces + est->nfaces,
                            FACE_CAP - est->nfaces, &n);
  if (ms != MODEL_OK) {
    snprintf(est->result.msg, sizeof est->result.msg, "stable faces: %s", model_status_str(ms));
    return ms == MODEL_E_NOMEM ? ESTIMATE_E_NOMEM : ESTIMATE_E_GEOMETRY;
  }
  if (n > FACE_CAP - est->nfaces) n = FACE_CAP - est->nfaces;
  size_t kept = est->nfaces;
  for (size_t i = est->nfaces; i < est->nfaces + n; ++i) {
    const model_face_t *f = &est->faces[i];
    if (rough ? face_recorded(est, f->normal_link) : !f->closed || f->flat) continue;
    est->rough[kept] = (unsigned char)rough;
    est->faces[kept++] = *f;
  }
  est->nfaces = kept;
  est->list_rough = rough;
  memcpy(est->listed_at_m, est->guess_m, sizeof est->listed_at_m);
  return ESTIMATE_OK;
}

/* Before the first trial: the prior, the hull faces, and face 1's plans. */
static estimate_status_t strategy_start(est_t *est) {
  estimate_result_t *out = &est->result;
  model_mass_t uni;
  if (model_mesh_mass(est->mesh, 1000.0, &uni) != MODEL_OK)
    return fail(est, ESTIMATE_E_GEOMETRY, "mass properties of the mesh");
  memcpy(out->uniform_com_m, uni.com_m, sizeof uni.com_m);
  memcpy(est->guess_m, uni.com_m, sizeof uni.com_m);
  memcpy(est->start_m, uni.com_m, sizeof uni.com_m);
  if (est->cfg.start == ESTIMATE_START_BBOX) {
    model_aabb_t box;
    if (model_mesh_aabb(est->mesh, &box) != MODEL_OK)
      return fail(est, ESTIMATE_E_GEOMETRY, "bounding box of the mesh");
    model_aabb_center(&box, est->start_m);
  }
  memcpy(out->start_m, est->start_m, sizeof out->start_m);
  for (int k = 0; k < 3; ++k) est->halfwidth_m[k] = INFINITY;
  est->face1 = -1;
  est->redo_of = -1;
  est->target_scale = 1.0;
  est->spare_phase = -1;
  est->redo_face = -1;
  est->mirror_next = -1;
  est->list_rough = -1;
  /* the hull stays in est->work: model_support_work_hull(est->work, est->mesh, ...) reuses it */
  const model_status_t ms = model_faces_find_in(est->mesh, est->guess_m, NULL, est->work,
                                                est->faces, FACE_CAP, &est->nfaces);
  if (ms != MODEL_OK) {
    snprintf(out->msg, sizeof out->msg, "faces: %s", model_status_str(ms));
    return ms == MODEL_E_NOMEM ? ESTIMATE_E_NOMEM : ESTIMATE_E_GEOMETRY;
  }
  if (est->nfaces > FACE_CAP) est->nfaces = FACE_CAP;
  size_t nflat = 0; /* only the flat faces are planned on: room for the closed patches */
  for (size_t i = 0; i < est->nfaces; ++i) {
    if (est->faces[i].flat) est->faces[nflat++] = est->faces[i];
  }
  est->nfaces = est->nflat_list = nflat;
  est->closed_from = est->nfaces;
  return face_one(est);
}

static int config_ok(const estimate_config_t *cfg) {
  return cfg->resolution_m >= 1e-6 && cfg->resolution_m <= 1e-2 && cfg->max_halfwidth_m > 0 &&
         isfinite(cfg->max_halfwidth_m) && cfg->z > 0 && isfinite(cfg->z) &&
         cfg->min_chord_margin_m > 0 && isfinite(cfg->min_chord_margin_m) &&
         cfg->min_dir_angle_rad > 0 && cfg->min_dir_angle_rad <= CL_PI / 2 &&
         cfg->min_face_angle_rad > 0 && cfg->min_face_angle_rad <= CL_PI / 2 &&
         cfg->noise_sigma_m >= 0.0 && cfg->noise_sigma_m <= 0.1 && cfg->noise_max_trials >= 1 &&
         cfg->noise_max_trials <= 200 && cfg->verify_margin_m >= 0.0 &&
         cfg->verify_margin_m <= 0.02 && cfg->max_retests <= 6 &&
         (cfg->closed_patches == 0 || cfg->closed_patches == 1) &&
         (cfg->rough_faces == 0 || cfg->rough_faces == 1) &&
         (cfg->fall_steering == 0 || cfg->fall_steering == 1) && cfg->pose_noise_sigma_m >= 0.0 &&
         cfg->pose_noise_sigma_m <= 0.1 && cfg->noise_stop_width_m >= 0.0 &&
         cfg->noise_stop_width_m <= 0.01 && cfg->noise_target_halfwidth_m >= 0.0 &&
         cfg->noise_target_halfwidth_m <= 0.01 && cfg->max_added_dirs <= 6 &&
         cfg->max_pivots <= 8 &&
         (cfg->start == ESTIMATE_START_UNIFORM || cfg->start == ESTIMATE_START_BBOX) &&
         (cfg->policy == QLEARN_POLICY_BISECT || cfg->policy == QLEARN_POLICY_PBA ||
          cfg->policy == QLEARN_POLICY_PAPER_QTABLE || cfg->policy == QLEARN_POLICY_PAPER_MLP);
}

/* est_t, then the geometry's work area, 8-byte aligned. */
static size_t est_head(void) { return (sizeof(est_t) + 7u) & ~(size_t)7u; }

size_t estimate_size(const model_mesh_t *mesh_link) {
  const size_t w = model_support_work_size(mesh_link);
  return w > 0 ? est_head() + w : 0;
}

estimate_status_t estimate_init(void *mem, size_t size, const model_mesh_t *mesh_link,
                                const double base_size_m[3], const estimate_config_t *cfg,
                                estimate_t **out) {
  if (out) *out = NULL;
  const size_t need = estimate_size(mesh_link);
  if (!mem || need == 0 || size < need || ((uintptr_t)mem & 7u) != 0 || !mesh_link->vertices_m ||
      !mesh_link->triangles || !base_size_m || !cfg || !out)
    return ESTIMATE_E_ARG;
  if (!config_ok(cfg)) return ESTIMATE_E_ARG;
  for (int k = 0; k < 3; ++k)
    if (!(base_size_m[k] > 0) || !isfinite(base_size_m[k])) return ESTIMATE_E_ARG;
  est_t *est = mem;
  memset(est, 0, sizeof *est);
  est->work =
      model_support_work_init((unsigned char *)mem + est_head(), size - est_head(), mesh_link);
  if (!est->work) return ESTIMATE_E_ARG;
  est->mesh = mesh_link;
  memcpy(est->base_size_m, base_size_m, sizeof est->base_size_m);
  est->cfg = *cfg;
  for (int k = 0; k < 3; ++k) est->result.halfwidth_m[k] = INFINITY;
  est->noisy = cfg->noise_sigma_m > 0.0;
  est->result.noisy = est->noisy;
  est->phase = PHASE_START;
  *out = est;
  return ESTIMATE_OK;
}

estimate_status_t estimate_create(const model_mesh_t *mesh_link, const double base_size_m[3],
                                  const estimate_config_t *cfg, estimate_t **out) {
  if (out) *out = NULL;
  const size_t size = estimate_size(mesh_link);
  if (size == 0) return ESTIMATE_E_ARG;
  void *mem = malloc(size);
  if (!mem) return ESTIMATE_E_NOMEM;
  const estimate_status_t s = estimate_init(mem, size, mesh_link, base_size_m, cfg, out);
  if (s != ESTIMATE_OK) free(mem);
  return s;
}

void estimate_destroy(estimate_t *est) { free(est); }

/* A step of the strategy ended with s: keep a failure. */
static estimate_status_t settle(est_t *est, estimate_status_t s) {
  if (s != ESTIMATE_OK) {
    est->phase = PHASE_FAILED;
    est->status = s;
    est->pending = 0;
  }
  return s;
}

estimate_status_t estimate_next(estimate_t *est, estimate_trial_request_t *req) {
  if (!est || !req) return ESTIMATE_E_ARG;
  if (est->phase == PHASE_START && settle(est, strategy_start(est)) != ESTIMATE_OK)
    return est->status;
  if (est->phase == PHASE_FAILED) return est->status;
  if (est->phase == PHASE_DONE) return ESTIMATE_DONE;
  if (!est->pending) /* every step ends with a request, the end, or a failure */
    return settle(est, fail(est, ESTIMATE_E_STATE, "internal: no trial planned and not done"));
  *req = est->req;
  return ESTIMATE_OK;
}

static int pose_ok(const model_pose_t *p) {
  double n = 0.0;
  for (int k = 0; k < 3; ++k)
    if (!isfinite(p->position_m[k])) return 0;
  for (int k = 0; k < 4; ++k) {
    if (!isfinite(p->orientation_wxyz[k])) return 0;
    n += p->orientation_wxyz[k] * p->orientation_wxyz[k];
  }
  return fabs(sqrt(n) - 1.0) <= MODEL_QUAT_UNIT_TOL;
}

estimate_status_t estimate_observe(estimate_t *est, const estimate_trial_reply_t *reply) {
  if (!est || !reply) return ESTIMATE_E_ARG;
  if (est->phase == PHASE_FAILED) return est->status;
  if (!est->pending) return ESTIMATE_E_STATE;
  if (reply->outcome < ESTIMATE_INVALID || reply->outcome > ESTIMATE_SLIDES ||
      !pose_ok(&reply->released) || !pose_ok(&reply->settled)) {
    snprintf(est->result.msg, sizeof est->result.msg,
             "reply refused: outcome %d, or a released / settled pose not finite or not unit",
             (int)reply->outcome);
    est->refused = 1;
    return ESTIMATE_E_ARG; /* nothing changed: the trial is still pending */
  }
  if (est->refused) est->result.msg[0] = '\0';
  est->refused = 0;
  estimate_status_t s;
  if (est->req.kind == ESTIMATE_TRIAL_STABLE)
    s = confirm_reply(est, reply);
  else
    s = walk_reply(est, reply);
  return settle(est, s);
}

const estimate_result_t *estimate_result(const estimate_t *est) {
  return est ? &est->result : NULL;
}

estimate_status_t estimate_status(const estimate_t *est) {
  if (!est) return ESTIMATE_E_ARG;
  if (est->phase == PHASE_FAILED) return est->status;
  return est->phase == PHASE_DONE ? ESTIMATE_DONE : ESTIMATE_OK;
}
