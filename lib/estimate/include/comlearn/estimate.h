/*
 * comlearn/estimate.h - the CoM estimator as a library: geometry in, placements out, outcomes in,
 * the CoM (with half widths, found flags and reasons) back. The caller owns the loop, as with
 * lib/qlearn's policies:
 *
 *   estimate_t *est;
 *   estimate_create(&mesh_link, base_size_m, &cfg, &est);
 *   estimate_trial_request_t req;
 *   while (estimate_next(est, &req) == ESTIMATE_OK) {
 *     estimate_trial_reply_t reply = run_the_trial(&req);  // a robot, comlearn-sim, lib/balance
 *     estimate_observe(est, &reply);
 *   }
 *   const estimate_result_t *r = estimate_result(est);      // estimate_next said ESTIMATE_DONE
 *   estimate_destroy(est);
 *
 * What the estimator sees is only what perception gives: the object's mesh in its URDF link frame
 * (comlearn/model.h) and, per trial, the outcome and the released and settled poses. It never
 * reads the URDF <inertial>: this library links lib/model's geometry (comlearn_model) and
 * lib/qlearn only; no physics engine (tests/estimate.cmake checks the archive's symbols).
 *
 * Frames and units: SI. World as in comlearn/model_support.h (z up, B's top at z = 0, its edges
 * along X and Y). Object: the URDF link frame. A pose is the link frame's pose in the world.
 *
 * Memory: estimate_create makes one allocation of estimate_size(mesh) bytes (or estimate_init uses
 * the caller's); nothing is allocated per trial after that (the planning geometry runs in a work
 * area inside that memory). The first estimate_next finds the mesh's hull faces, which allocates
 * temporary memory once and frees it; the hull itself stays in the work area. Objects without
 * flat faces allocate temporary memory too (docs/estimate.md): listing closed patches and rough
 * faces, a face from a settled pose, planning a pivot search (the hull's edges), and at the end a
 * reason that names a support point leaving B (the outcome model's work area, per such
 * component). The mesh is the
 * caller's and must outlive the estimate. Nothing here prints or does I/O. One thread per estimate;
 * separate estimates are independent.
 */
#ifndef COMLEARN_ESTIMATE_H
#define COMLEARN_ESTIMATE_H

#include <stddef.h>
#include <stdint.h>

#include "comlearn/model.h"
#include "comlearn/model_support.h"
#include "comlearn/qlearn.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One status enum: 0 success, negative errors; ESTIMATE_DONE (positive) from estimate_next when
 * the estimate is complete. */
typedef enum {
  ESTIMATE_DONE = 1, /* no more trials: estimate_result holds the estimate */
  ESTIMATE_OK = 0,
  ESTIMATE_E_ARG = -1,      /* NULL, bad option value, non-finite number */
  ESTIMATE_E_GEOMETRY = -2, /* the mesh gives no flat face to rest on, or no usable yaw */
  ESTIMATE_E_BACKEND = -3, /* for drivers: the trial runner failed (not returned by this library) */
  ESTIMATE_E_NOPOSE = -4,  /* no candidate resting face was confirmed stable */
  ESTIMATE_E_CAPACITY = -5, /* more trials or searches than the result holds */
  ESTIMATE_E_LEARNER = -6,  /* lib/qlearn refused (status in the message) */
  ESTIMATE_E_NOMEM = -7,
  ESTIMATE_E_STATE = -8 /* estimate_observe with no trial pending (call estimate_next) */
} estimate_status_t;

const char *estimate_status_str(estimate_status_t s);

/* The command-line names of the policies: "bisect", "pba", "paper-qtable", "paper-mlp" ("?" for
 * anything else), and back (0, or -1 for an unknown name). */
const char *estimate_policy_name(qlearn_policy_kind_t k);
int estimate_policy_parse(const char *s, qlearn_policy_kind_t *k);

/* ---- one trial ------------------------------------------------------------------------------ */

/* Outcome of a trial; the values equal comlearn/balance.h's balance_outcome_t and the COM_TRIAL
 * message's OUTCOME_* constants. */
typedef enum {
  ESTIMATE_INVALID = 0, /* no usable outcome (e.g. still moving when the observation ended) */
  ESTIMATE_STAYS = 1,   /* came to rest on B */
  ESTIMATE_TIPS = 2,    /* rotated over the edge: tipped off */
  ESTIMATE_SLIDES = 3   /* translated along / off B without tipping: says nothing of the CoM */
} estimate_outcome_t;

typedef enum {
  ESTIMATE_TRIAL_STABLE = 0, /* a resting-pose check: the object set down in the middle of B */
  ESTIMATE_TRIAL_EDGE = 1    /* an edge test: a link point set over an edge of B */
} estimate_trial_kind_t;

/* What the estimator asks for: the pose to release the object in (world; touching B, never
 * dropped), and for edge tests the edge. A real robot achieves the pose only approximately; the
 * caller reports the pose it actually released. */
typedef struct {
  estimate_trial_kind_t kind;
  model_edge_t edge;    /* ESTIMATE_TRIAL_EDGE only */
  model_pose_t release; /* requested release pose, world */
  /* What the estimator knows of the trial, for records (e.g. comlearn's COM_TRIAL messages); a
   * caller that only runs trials ignores it. */
  int search;               /* search index (estimate_result_t.search), -1 for a stable check */
  int component;            /* link axis (0 x, 1 y, 2 z) the search's direction (dir_link)
                                determines most: its largest |component|; -1 for a stable check */
  int direction;            /* sign of dir_link[component] (+1: that link axis points along the
                                edge's outward normal), 0 for a stable check */
  double target_link_m[3];  /* link point placed over the edge (stable check: over B's centre) */
  int flat_patch;           /* the requested pose is in the flat-patch regime (model_regime_
                                classify with the running estimate, default thresholds); 0 for a
                                stable check */
  double sideways_margin_m; /* its chord margin [m] (-HUGE_VAL without a chord); 0 for a stable
                                check */
  double com_before_m[3];   /* the running CoM estimate before this trial, link frame */
  double halfwidth_before_m[3]; /* its half widths before this trial (INFINITY: not found yet) */
} estimate_trial_request_t;

typedef struct {
  estimate_outcome_t outcome;
  model_pose_t released; /* pose actually released (measured), world */
  model_pose_t settled;  /* pose after the trial (perceived), world */
} estimate_trial_reply_t;

/* ---- settings and results ----------------------------------------------------------------- */

/* Where the searches start (qlearn's prior, "state 0"): the mesh's uniform-density CoM (default:
 * the truth for an object of one material), or the bounding-box centre (the paper's reference
 * point, McGovern et al. 2019: what a fair comparison with its walks uses). Planning (faces,
 * yaws, chord margins) always uses the uniform-density CoM, moved by what was measured. */
typedef enum { ESTIMATE_START_UNIFORM = 0, ESTIMATE_START_BBOX = 1 } estimate_start_t;

typedef struct {
  qlearn_policy_kind_t policy; /* default QLEARN_POLICY_BISECT */
  estimate_start_t start;      /* default ESTIMATE_START_UNIFORM */
  double resolution_m;         /* search resolution, default 1e-4; in [1e-6, 1e-2] */
  double max_halfwidth_m;      /* widest half width still called found; default 1e-3 */
  double z;                    /* half width = z * sigma; default 1.96 */
  uint64_t seed;               /* for the MLP policy; default 1 */
  /* Chord margin wanted for edge tests (flat-patch regime, see comlearn/model_support.h); the
   * regime classification itself uses model_regime_config_default's 3 mm. Default 0.003 m. */
  double min_chord_margin_m;
  /* Smallest angle between a second test direction and the first on one face; default 60 deg. */
  double min_dir_angle_rad;
  /* Faces whose normals are within this angle of the first face's do not count as "a second
   * face"; default 30 deg. */
  double min_face_angle_rad;
  /* The noise model: the std. dev. [m] of the placement error along the edge normal (the
   * robot's release offset, comlearn-sim --placement-noise-mm), in [0, 0.1]. 0 (default): the
   * outcomes are noiseless and every reported interval is a worst-case bound (the bracket plus
   * the regime's bias budget); PBA then places on the step likelihood (sigma 0). > 0: every search
   * ends with the posterior of its threshold under the probit model P(TIPS | c) = Phi((c - x) /
   * sigma) from all its clear trials, and reports that posterior's 95 % credible interval; bisect
   * and the paper walks run as published and then hand over to probabilistic bisection (PBA) until
   * that interval is narrow enough (noise_stop_width_m, noise_target_halfwidth_m) or
   * noise_max_trials more trials were run. PBA itself uses the probit model with this sigma from
   * its first trial. An interval can shrink only as fast as the outcomes inform it, about
   * 2 x 1.96 sigma / sqrt(0.64 n) after n trials near the threshold. */
  double noise_sigma_m;
  uint32_t
      noise_max_trials; /* PBA trials after a noisy walk, per search; default 48, in [1, 200] */
  /* With a noise model, a search first stops when its 95 % interval is at most this wide [m], in
   * [0, 0.01]. 0 (default): max(resolution_m, noise_sigma_m, 2 * noise_target_halfwidth_m).
   * Wider stops cost fewer trials and give wider intervals (docs/results.md, "With noise"). */
  double noise_stop_width_m;
  /* An interval is only as good as the physics of the trials that set it: an edge test measures
   * the CoM where the real contact on the edge line spans the CoM sideways. After the solve, the
   * deciding trials of every search are checked against the final estimate: their chord must
   * span the estimate's interval box, seen along the edge, with this margin to spare (default
   * 1 mm: the measured flat-patch bias does not grow down to a 1 mm margin, docs/physics.md; in
   * [0, 0.02]). On a closed patch, where any chord spans the CoM, the estimate must project
   * this far inside the patch, its box included (a CoM 0.58 mm inside a lumpy rock's facet tipped
   * 58 um early; docs/estimate.md, "Closed patches"). The search that fails worst is dropped and
   * searched again with a yaw chosen at the estimate, or made rough (its STAYS bound it), until
   * all hold (at most max_retests new searches; default 3, in [0, 6]). */
  double verify_margin_m;
  uint32_t max_retests;
  /* Rest on closed patches too (default 1): small convex facets (one triangle of a rounded
   * underside, a narrow side strip) that hold the CoM's projection, found under the estimate or
   * under the pose a stable check settled in; any chord of one spans the CoM, so no chord margin
   * is needed (docs/estimate.md, "Closed patches"). 0: flat faces only, as before. */
  int closed_patches;
  /* Rough faces too (default 1): when no flat face or closed patch is left, any
   * hull face that holds the estimate (a noisy scanned face, the facets of a pebble) is searched
   * from both sides, yaw and yaw + pi, and only its STAYS trials set the plane: at rest, the CoM
   * lies over B's top in the settled pose, exactly, whatever the support looks like
   * (docs/estimate.md, "Rough faces"). 0: not used. With a noise model they are used only when
   * pose_noise_sigma_m says how well the settled pose is perceived. */
  int rough_faces;
  /* Std. dev. of the perceived settled position (each axis) [m], in [0, 0.1]; default 0: not
   * told. With a noise model (noise_sigma_m > 0) and this > 0, rough faces are used too: each
   * rough pair's side then allows k of it, k for a 2.5 % miss over its bounds (estimate.c,
   * pose_allowance; the release's own noise does not enter: the
   * bound is taken in the settled pose). */
  double pose_noise_sigma_m;
  /* With a noise model, the 95 % half width [m] every determined component is taken to, in
   * [0, 0.01]; default 5e-4 (a 1 mm wide interval). Searches first stop at twice it (unless
   * noise_stop_width_m is set); then, while a component is wider, the search that contributes
   * most to its variance is resumed with a narrower stop, within noise_max_trials after its walk
   * and three resumptions (docs/estimate.md, "With noise"). 0: no resumption, and the first stop
   * is max(resolution_m, noise_sigma_m). */
  double noise_target_halfwidth_m;
  /* When every check passed and no face is left to try but a component is still too wide, up
   * to this many more directions on faces already searched (default 3, in [0, 6]; 0: none): each
   * the yaw that would narrow the widest such component most, tried only when it would narrow it
   * to 0.8 of its width or under max_halfwidth_m, and kept only when it narrowed it (docs/
   * estimate.md, "A direction more"). */
  uint32_t max_added_dirs;
  /* Steer by falls (default 1): a stable check on a closed patch or rough face that tipped tells
   * on which side of that face's contact the CoM lies (the direction it fell); the estimate that
   * picks the next candidates is moved the least to lie beyond every such contact, and the
   * phase's candidates are listed again under it (docs/estimate.md, "Steered by falls"). Only
   * planning: a fall is never fed to the solve. 0: candidates under the mesh prior only. */
  int fall_steering;
  /* Pivots (default 4, in [0, 8]; 0: none): when every check passed and nothing else is left but
   * a component is still not found, up to this many pivot searches, noiseless only. The object is
   * set down balanced on B's edge line along an edge of its convex hull, tilted about it, and
   * turns back onto B or falls off as its CoM lies on B's side of the vertical plane through that
   * edge or beyond it; a search over the tilt finds the plane through the edge that holds the CoM
   * (a knife-edge balance, exact to a micron in lib/balance wherever the CoM projects between the
   * edge's ends). The edge is the one whose plane would narrow the widest such component most; a
   * search is kept only when it narrowed it (docs/estimate.md, "Pivots"). */
  uint32_t max_pivots;
} estimate_config_t;

void estimate_config_default(estimate_config_t *cfg);

enum {
  ESTIMATE_MAX_TRIALS = 512,
  ESTIMATE_MAX_SEARCHES = 16,
  ESTIMATE_MAX_FACES = 32,
  ESTIMATE_NOTE_SIZE = 160,
  ESTIMATE_REASON_SIZE = 224
};

/* One placement, as logged. */
typedef struct {
  estimate_trial_kind_t kind;
  int face;                /* index into the face list of estimate_result_t */
  int search;              /* search index for edge tests, -1 for stable checks */
  double x_m;              /* edge tests: the 1-D coordinate placed over the edge */
  double target_link_m[3]; /* the link point the request placed over the edge (stable checks:
                               over B's centre); = the request's target_link_m */
  estimate_outcome_t outcome;
  estimate_outcome_t counted; /* what the search took it for: the outcome, except that on a
                                  rough face a barely creeping INVALID counts as STAYS, and that
                                  a pivot trial counts as TIPS when it fell off, STAYS when it
                                  turned back onto B, INVALID when neither is clear */
  int regime;                 /* model_regime_kind_t of the released pose (edge tests), -1 */
  double chord_margin_m;      /* of the released pose (edge tests) */
  int flagged;                /* edge test outside the flat-patch regime, or an unclear outcome
                                    (INVALID / SLIDES: not observed, retried): not fed to the solve */
  model_pose_t released;
  model_pose_t settled;
} estimate_trial_t;

/* One 1-D search along a horizontal direction of a resting face. */
typedef struct {
  int face;
  double yaw_rad;
  double dir_link[3]; /* the test direction (edge normal) in the link frame */
  double prior_m, range_lo_m, range_hi_m;
  double c_m, halfwidth_m;  /* the threshold along dir_link and its half width: noiseless, the
                               bracket of its trials (TIPS below, STAYS above); with a noise
                               model, the 95 % credible interval of the posterior */
  uint32_t trials;          /* edge tests of this search */
  uint32_t handover_trials; /* of which run by PBA after a noisy walk */
  uint32_t refines;         /* times resumed to narrow a component (noise_target_halfwidth_m) */
  int fed;                  /* its threshold plane went into the final 3-D solve */
  double plane_n_obj[3];    /* the plane: n_obj . c = plane_d_m (unit n_obj) */
  double plane_d_m;
  double bias_m;            /* physics bias budget of its regime, added to the bound */
  double chord_margin_m;    /* planned margin at the chosen yaw */
  double verified_margin_m; /* smallest chord margin of its deciding trials at the final
                               estimate, less the interval box's extent along the edge (NaN:
                               not checked); fed only when >= verify_need_m. On a closed patch:
                               how far inside the patch the estimate projects, less the box's
                               extent in the patch plane */
  double verify_need_m;     /* what that check needs: verify_margin_m (flat faces and closed
                               patches), 0 for a search bounded by its STAYS (rough) */
  int lo_trial, hi_trial;   /* indices into trial[] of the bracketing TIPS / STAYS (-1: none) */
  int retest_of;            /* the search this one repeats with a new yaw, or -1 */
  int mirror_of;            /* rough face: the search this one mirrors (yaw + pi), whose plane
                               both set; -1 */
  int retested;             /* a later search repeats this one (or none could) */
  int added;                /* a direction more on a face already searched, for a component
                               still not found after every check (kept only if it narrowed it) */
  int flat_failed;          /* a trial that sets its threshold left the flat-patch regime */
  int verified;             /* fed and its check at the final estimate passed; a fed search
                               that the other planes cannot check stays fed for the solve but
                               the components it influences are not claimed */
  /* A pivot search (estimate_config_t.max_pivots): face is -1, yaw_rad 0; the object balanced on
   * the hull edge from pivot_link_m[0] to pivot_link_m[1] (link frame), which lay along B's edge
   * line. Its trials' x_m, prior_m and range are the offset along the planned direction at which
   * a CoM at the estimate's height over the edge would balance (the tilt, as a length); c_m,
   * halfwidth_m and dir_link are its plane's (the bisector of its bracketing trials' planes, both
   * through the edge; the half width covers every point of the hull between them).
   * verified_margin_m: how far inside the edge's ends the estimate projects, less the interval
   * box's extent along the edge. */
  int pivot;
  double pivot_link_m[2][3];
  char note[ESTIMATE_NOTE_SIZE]; /* why it is not fed ("" when fed) */
} estimate_search_t;

typedef struct {
  double normal_link[3];
  double area_m2;         /* support polygon (hull of the mesh vertices on the plane) */
  double contact_area_m2; /* real area of its largest region of in-plane triangles */
  size_t regions;         /* regions of in-plane triangles (two feet: 2) */
  double com_margin_m;
  int confirmed; /* stable check stayed */
  int rough;     /* checked and searched as a rough face (estimate_config_t.rough_faces) */
} estimate_face_t;

typedef struct {
  double uniform_com_m[3]; /* the prior: the mesh's uniform-density CoM, link frame */
  double start_m[3];       /* where the searches started (estimate_config_t.start) */
  double com_m[3];         /* estimate, link frame */
  double halfwidth_m[3];   /* INFINITY when not found. Noiseless (noise_sigma_m 0): a bound,
                               sum_j |P_kj| (h_j + bias_j) over the fed planes j with P the
                               solve's (pseudo-)inverse: the truth lies inside unless the physics
                               left the modelled regimes. With a noise model: the 95 % interval
                               1.96 sigma_k of the solve plus the same bias budget. */
  int found[3];            /* determined by the fed planes with halfwidth_m <= max_halfwidth_m */
  int noisy;               /* 1: 95 % intervals under the noise model; 0: bounds */
  char reason[3][ESTIMATE_REASON_SIZE]; /* why a component is not found ("" when found) */
  int rank;
  double chi2;
  size_t trial_count; /* all placements, stable checks included */
  size_t stable_trials;
  size_t flagged_trials;
  estimate_trial_t trial[ESTIMATE_MAX_TRIALS];
  size_t search_count;
  estimate_search_t search[ESTIMATE_MAX_SEARCHES];
  size_t face_count; /* faces that were checked */
  estimate_face_t face[ESTIMATE_MAX_FACES];
  char msg[512]; /* detail of a failure, or a note (e.g. why a component is missing) */
} estimate_result_t;

/* ---- the loop ------------------------------------------------------------------------------- */

typedef struct estimate estimate_t; /* opaque */

/* Bytes an estimate of mesh_link needs (for estimate_init): the estimator's state (171 824 on
 * x86-64) and lib/model's scratch memory for this mesh, the mesh's convex hull included (265 728
 * for rock_1: 437 552 in all); 0 for NULL or an empty mesh. */
size_t estimate_size(const model_mesh_t *mesh_link);

/* Start an estimate of the object whose link-frame geometry is mesh_link (kept by pointer: it must
 * outlive the estimate) on a block B of size base_size_m (world x, y, z). cfg is copied.
 * estimate_create allocates estimate_size(mesh_link) bytes; estimate_init uses the caller's `size`
 * bytes at mem (8-byte aligned, at least estimate_size(mesh_link)). ESTIMATE_E_ARG for NULL, an
 * empty mesh, a base size that is not finite and positive or a setting out of its documented range
 * (*out NULL); ESTIMATE_E_NOMEM. */
estimate_status_t estimate_create(const model_mesh_t *mesh_link, const double base_size_m[3],
                                  const estimate_config_t *cfg, estimate_t **out);
estimate_status_t estimate_init(void *mem, size_t size, const model_mesh_t *mesh_link,
                                const double base_size_m[3], const estimate_config_t *cfg,
                                estimate_t **out);

/* Free an estimate of estimate_create (not one of estimate_init). NULL is fine. */
void estimate_destroy(estimate_t *est);

/* The placement to try next, in *req: ESTIMATE_OK. ESTIMATE_DONE when the estimate is complete
 * (estimate_result). An error when the estimate failed (the same error from then on; the result
 * holds what was learned so far and a message): ESTIMATE_E_GEOMETRY (no usable resting face or
 * yaw), ESTIMATE_E_NOPOSE (no face confirmed stable), ESTIMATE_E_CAPACITY, ESTIMATE_E_LEARNER,
 * ESTIMATE_E_NOMEM. The first call plans (the hull faces, ~20 ms for a 1000-vertex rock). Calling
 * it again before estimate_observe returns the same request. */
estimate_status_t estimate_next(estimate_t *est, estimate_trial_request_t *req);

/* What happened to the pending trial: plans the next one. A reply with an outcome out of range or
 * a pose that is not finite or not a unit quaternion is refused with ESTIMATE_E_ARG and changes
 * nothing (the trial stays pending: run it again or give up); ESTIMATE_E_STATE when no trial is
 * pending. Otherwise ESTIMATE_OK, or the failure that ended the estimate (as estimate_next). */
estimate_status_t estimate_observe(estimate_t *est, const estimate_trial_reply_t *reply);

/* The estimate so far (complete once estimate_next returned ESTIMATE_DONE): owned by est, valid
 * until estimate_destroy. ESTIMATE_OK (found[] may hold 0s, each with its reason[]: a component
 * that the trials cannot determine honestly is reported missing, never invented). */
const estimate_result_t *estimate_result(const estimate_t *est);

/* ESTIMATE_OK while trials remain, ESTIMATE_DONE, or the error that ended the estimate. */
estimate_status_t estimate_status(const estimate_t *est);

#ifdef __cplusplus
}
#endif

#endif
