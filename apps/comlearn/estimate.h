/*
 * estimate.h - the CoM estimator of `comlearn estimate`: geometry in, trials out through a
 * backend, CoM (with half widths and found flags) back.
 *
 * The estimator side (estimate.c) sees only what perception gives: the object's mesh in its URDF
 * link frame (comlearn/model.h) and, per trial, the released and settled poses the backend
 * reports. It never reads the URDF <inertial>: estimate.c does not include
 * comlearn/model_inertial.h and its library target does not link comlearn_model_sim.
 *
 * The simulator side is a backend (estimate_backend_t): it places the object as asked and reports
 * what happened. estimate_direct.c runs the trials in-process on lib/balance with the URDF truth;
 * a later LCM backend sends YuMi commands to comlearn-sim and waits for its status and object
 * state, without any change here.
 *
 * Frames and units: SI. World as in comlearn/balance.h (z up, B's top at z = 0, its edges along
 * X and Y). Object: the URDF link frame. A pose is the link frame's pose in the world.
 *
 * Memory: estimate_run allocates (the planning world, the hull in balance_faces_find) and frees
 * everything before returning; the result is caller-owned and fixed size. Nothing here prints;
 * progress goes through the caller's callback. Not thread-safe per backend.
 */
#ifndef COMLEARN_APP_ESTIMATE_H
#define COMLEARN_APP_ESTIMATE_H

#include <stddef.h>
#include <stdint.h>

#include "comlearn/balance.h"
#include "comlearn/model.h"
#include "comlearn/qlearn.h"

/* One status enum: 0 success, negative errors. */
typedef enum {
  ESTIMATE_OK = 0,
  ESTIMATE_E_ARG = -1,      /* NULL, bad option value, non-finite number */
  ESTIMATE_E_GEOMETRY = -2, /* the mesh gives no flat face to rest on, or no usable yaw */
  ESTIMATE_E_BACKEND = -3,  /* the backend failed (its own message in estimate_result_t) */
  ESTIMATE_E_NOPOSE = -4,   /* no candidate resting face was confirmed stable */
  ESTIMATE_E_CAPACITY = -5, /* more trials or searches than the result holds */
  ESTIMATE_E_LEARNER = -6,  /* lib/qlearn refused (status in the message) */
  ESTIMATE_E_NOMEM = -7
} estimate_status_t;

const char *estimate_status_str(estimate_status_t s);

/* The command-line names of the policies: "bisect", "pba", "paper-qtable", "paper-mlp" ("?" for
 * anything else), and back (0, or -1 for an unknown name). */
const char *estimate_policy_name(qlearn_policy_kind_t k);
int estimate_policy_parse(const char *s, qlearn_policy_kind_t *k);

/* ---- the trial backend -------------------------------------------------------------------- */

typedef enum {
  ESTIMATE_TRIAL_STABLE = 0, /* a resting-pose check: the object set down in the middle of B */
  ESTIMATE_TRIAL_EDGE = 1    /* an edge test: a link point set over an edge of B */
} estimate_trial_kind_t;

/* What the estimator asks for: the pose to release the object in (world; touching B, never
 * dropped), and for edge tests the edge. A real robot achieves the pose only approximately; the
 * backend reports the pose it actually released. */
typedef struct {
  estimate_trial_kind_t kind;
  balance_edge_t edge;       /* ESTIMATE_TRIAL_EDGE only */
  balance_pose_t release;    /* requested release pose, world */
  /* What the estimator knows of the trial, for records (the LCM backend's COM_TRIAL); a backend
   * that only runs trials (estimate_direct.c) ignores it. */
  int search;                /* search index (estimate_result_t.search), -1 for a stable check */
  int component;             /* link axis (0 x, 1 y, 2 z) the search's direction (dir_link)
                                determines most: its largest |component|; -1 for a stable check */
  int direction;             /* sign of dir_link[component] (+1: that link axis points along the
                                edge's outward normal), 0 for a stable check */
  double target_link_m[3];   /* link point placed over the edge (stable check: over B's centre) */
  int flat_patch;            /* the requested pose is in the flat-patch regime (balance_regime_
                                classify with the running estimate, default thresholds); 0 for a
                                stable check */
  double sideways_margin_m;  /* its chord margin [m] (-HUGE_VAL without a chord); 0 for a stable
                                check */
  double com_before_m[3];    /* the running CoM estimate before this trial, link frame */
  double halfwidth_before_m[3]; /* its half widths before this trial (INFINITY: not found yet) */
} estimate_trial_request_t;

typedef struct {
  balance_outcome_t outcome; /* STAYS / TIPS / SLIDES / INVALID (comlearn/balance.h) */
  balance_pose_t released;   /* pose actually released (measured), world */
  balance_pose_t settled;    /* pose after the trial (perceived), world */
} estimate_trial_reply_t;

/* A place to run trials. `run` places the object per req and fills *reply; it returns 0 on
 * success and a negative value on failure, with a message in err (err_size bytes, NUL-terminated).
 * base_size_m is the size of B (world x, y, z), needed for planning. ctx belongs to the backend.
 * The backend owns the simulated truth; the estimator never asks it for anything else. */
typedef struct {
  void *ctx;
  const char *name; /* "direct", "lcm", ... */
  double base_size_m[3];
  int (*run)(void *ctx, const estimate_trial_request_t *req, estimate_trial_reply_t *reply,
             char *err, size_t err_size);
} estimate_backend_t;

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
  /* Chord margin wanted for edge tests (flat-patch regime, see balance_poses.h); the regime
   * classification itself uses balance_regime_config_default's 3 mm. Default 0.003 m. */
  double min_chord_margin_m;
  /* Smallest angle between a second test direction and the first on one face; default 60 deg. */
  double min_dir_angle_rad;
  /* Faces whose normals are within this angle of the first face's do not count as "a second
   * face"; default 30 deg. */
  double min_face_angle_rad;
  /* The noise model: the std. dev. [m] of the placement error along the edge normal (the
   * robot's release offset, comlearn-sim --placement-noise-mm), in [0, 0.1]. 0 (default): the
   * outcomes are noiseless and every reported interval is a worst-case bound (the bracket plus
   * the regime's bias budget). > 0: every search ends with the posterior of its threshold under
   * the probit model P(TIPS | c) = Phi((c - x) / sigma) from all its clear trials, and reports
   * that posterior's 95 % credible interval; bisect and the paper walks run as published and
   * then hand over to probabilistic bisection (PBA) until that interval is at most
   * max(resolution_m, noise_sigma_m) wide or noise_max_trials more trials were run. PBA itself
   * uses the probit model with this sigma from its first trial. An interval can shrink only as
   * fast as the outcomes inform it, about 2 * 1.96 * sigma / sqrt(0.64 n) after n trials near the
   * threshold. */
  double noise_sigma_m;
  uint32_t noise_max_trials;   /* PBA trials after a noisy walk; default 48, in [1, 200] */
  /* An interval is only as good as the physics of the trials that set it: an edge test measures
   * the CoM where the real contact on the edge line spans the CoM sideways. After the solve, the
   * deciding trials of every search are checked against the final estimate: their chord must
   * span the estimate's interval box, seen along the edge, with this margin to spare (default
   * 1 mm: the measured flat-patch bias does not grow down to a 1 mm margin, docs/physics.md; in
   * [0, 0.02]). The search that fails worst is dropped and searched again with a yaw chosen at
   * the estimate, until all hold (at most max_retests new searches; default 3, in [0, 6]). */
  double verify_margin_m;
  uint32_t max_retests;
  /* Called after every trial (may be NULL). */
  void (*progress)(void *ctx, size_t trial_index, const char *what);
  void *progress_ctx;
} estimate_config_t;

void estimate_config_default(estimate_config_t *cfg);

enum {
  ESTIMATE_MAX_TRIALS = 512,
  ESTIMATE_MAX_SEARCHES = 12,
  ESTIMATE_MAX_FACES = 16,
  ESTIMATE_NOTE_SIZE = 160,
  ESTIMATE_REASON_SIZE = 224
};

/* One placement, as logged. */
typedef struct {
  estimate_trial_kind_t kind;
  int face;                 /* index into the face list of estimate_result_t */
  int search;               /* search index for edge tests, -1 for stable checks */
  double x_m;               /* edge tests: the 1-D coordinate placed over the edge */
  double target_link_m[3];  /* the link point the request placed over the edge (stable checks:
                               over B's centre); = the request's target_link_m */
  balance_outcome_t outcome;
  int regime;               /* balance_regime_kind_t of the released pose (edge tests), -1 */
  double chord_margin_m;    /* of the released pose (edge tests) */
  int flagged;              /* edge test outside the flat-patch regime, or an unclear outcome
                               (INVALID / SLIDES: not observed, retried): not fed to the solve */
  balance_pose_t released;
  balance_pose_t settled;
} estimate_trial_t;

/* One 1-D search along a horizontal direction of a resting face. */
typedef struct {
  int face;
  double yaw_rad;
  double dir_link[3];       /* the test direction (edge normal) in the link frame */
  double prior_m, range_lo_m, range_hi_m;
  double c_m, halfwidth_m;  /* the threshold along dir_link and its half width: noiseless, the
                               bracket of its trials (TIPS below, STAYS above); with a noise
                               model, the 95 % credible interval of the posterior */
  uint32_t trials;          /* edge tests of this search */
  uint32_t handover_trials; /* of which run by PBA after a noisy walk */
  int fed;                  /* its threshold plane went into the final 3-D solve */
  double plane_n_obj[3];    /* the plane: n_obj . c = plane_d_m (unit n_obj) */
  double plane_d_m;
  double bias_m;            /* physics bias budget of its regime, added to the bound */
  double chord_margin_m;    /* planned margin at the chosen yaw */
  double verified_margin_m; /* smallest chord margin of its deciding trials at the final
                               estimate, less the interval box's extent along the edge (NaN:
                               not checked); fed only when >= verify_margin_m */
  int lo_trial, hi_trial;   /* indices into trial[] of the bracketing TIPS / STAYS (-1: none) */
  int retest_of;            /* the search this one repeats with a new yaw, or -1 */
  int retested;             /* a later search repeats this one (or none could) */
  int flat_failed;          /* a trial that sets its threshold left the flat-patch regime */
  int verified;             /* fed and its check at the final estimate passed; a fed search
                               that the other planes cannot check stays fed for the solve but
                               the components it influences are not claimed */
  char note[ESTIMATE_NOTE_SIZE]; /* why it is not fed ("" when fed) */
} estimate_search_t;

typedef struct {
  double normal_link[3];
  double area_m2;           /* support polygon (hull of the mesh vertices on the plane) */
  double contact_area_m2;   /* real area of its largest region of in-plane triangles */
  size_t regions;           /* regions of in-plane triangles (two feet: 2) */
  double com_margin_m;
  int confirmed;            /* stable check stayed */
} estimate_face_t;

typedef struct {
  double uniform_com_m[3];  /* the prior: the mesh's uniform-density CoM, link frame */
  double start_m[3];        /* where the searches started (estimate_config_t.start) */
  double com_m[3];          /* estimate, link frame */
  double halfwidth_m[3];    /* INFINITY when not found. Noiseless (noise_sigma_m 0): a bound,
                               sum_j |P_kj| (h_j + bias_j) over the fed planes j with P the
                               solve's (pseudo-)inverse: the truth lies inside unless the physics
                               left the modelled regimes. With a noise model: the 95 % interval
                               1.96 sigma_k of the solve plus the same bias budget. */
  int found[3];             /* determined by the fed planes with halfwidth_m <= max_halfwidth_m */
  int noisy;                /* 1: 95 % intervals under the noise model; 0: bounds */
  char reason[3][ESTIMATE_REASON_SIZE]; /* why a component is not found ("" when found) */
  int rank;
  double chi2;
  size_t trial_count;       /* all placements, stable checks included */
  size_t stable_trials;
  size_t flagged_trials;
  estimate_trial_t trial[ESTIMATE_MAX_TRIALS];
  size_t search_count;
  estimate_search_t search[ESTIMATE_MAX_SEARCHES];
  size_t face_count;        /* faces that were checked */
  estimate_face_t face[ESTIMATE_MAX_FACES];
  char msg[512];            /* detail of a failure, or a note (e.g. why a component is missing) */
} estimate_result_t;

/* Estimate the CoM of the object whose link-frame geometry is mesh_link, running every trial
 * through backend. Fills *out (also on error, as far as it got). Returns ESTIMATE_OK when the
 * estimate ran (found[] may still hold 0s, each with its reason[]: a component that the trials
 * cannot determine honestly is reported missing, never invented), or an error. */
estimate_status_t estimate_run(const model_mesh_t *mesh_link, const estimate_backend_t *backend,
                               const estimate_config_t *cfg, estimate_result_t *out);

#endif
