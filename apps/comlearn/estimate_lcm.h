/*
 * estimate_lcm.h - the LCM trial backend of `comlearn estimate` (without --direct): each trial
 * is a YuMi placement driven over LCM, against comlearn-sim or a real cell (docs/estimate.md,
 * "The LCM backend"; the channels in docs/messages.md).
 *
 * Per trial request (release pose in B's frame, estimate.h):
 *   1. SIM_CONTROL: ACTION_LOAD (first trial, or after the simulator lost the object) or
 *      ACTION_RESET puts the object into the chosen arm's gripper with a top-down grasp computed
 *      for this trial (tcp z down, over the centre of the object's footprint, see the docs);
 *      acknowledged on OBJECT_STATE (sim_control_seq), resent with a new seq on a timeout.
 *   2. placement_plan_build from the measured joints of YUMI_STATUS.
 *   3. YUMI_COMMAND per waypoint (pre-place, place, release), seq increasing, expire_utime from
 *      the latest status utime (the controller's clock), each resent with a new seq until the
 *      status shows it accepted and in_position.
 *   4. After the release: OBJECT_STATE until at rest on B (STAYS), off B (TIPS; SLIDES when it
 *      left B nearly unrotated) or, on the controller's clock, past the physics horizon while
 *      still on B (INVALID); then the retreat waypoint.
 *   5. A trial that times out as a whole (no acknowledgement after all resends, no outcome) is
 *      run again from step 1, a bounded number of times; then the backend fails.
 * Every wait is lcm_handle_timeout with a bounded wall-clock budget: nothing blocks forever.
 *
 * Frames: requests and replies in B's frame (lib/balance); messages in the world of the YuMi
 * URDF (yumi_body), B at placement_plan_config_default()'s block_in_base.
 *
 * Memory: estimate_lcm_open allocates the handle (lcm_t, subscriptions, arm models, a copy of
 * the mesh pointer - the mesh itself is borrowed and must outlive the handle); estimate_lcm_close
 * frees everything. One thread per handle (LCM's rule). Nothing prints except through the
 * optional log callback.
 */
#ifndef COMLEARN_APP_ESTIMATE_LCM_H
#define COMLEARN_APP_ESTIMATE_LCM_H

#include <stddef.h>
#include <stdint.h>
#include <sys/types.h>

#include "comlearn/model.h"
#include "comlearn/placement_plan.h"
#include "estimate_backend.h"

typedef struct estimate_lcm estimate_lcm_t;

typedef struct {
  const char *lcm_url;           /* NULL: COMLEARN_MSG_LCM_URL_DEFAULT */
  const char *channel_prefix;    /* the robot's channels, e.g. "R2_" (comlearn/msg.h); NULL: none */
  const char *urdf_path;         /* sent in ACTION_LOAD (made absolute when it exists here) */
  const char *object_id;         /* NULL: the URDF file name without ".urdf" */
  const model_mesh_t *mesh_link; /* the object's geometry, link frame (borrowed), for planning */
  const char *yumi_urdf;         /* the arm model for planning (required) */
  const char *policy;            /* for COM_TRIAL / COM_ESTIMATE ("bisect", ...); NULL: "" */
  double ack_timeout_s;          /* wall time to wait for an acknowledgement; default 0.5 */
  double motion_timeout_s;       /* wall time for a waypoint to be reached; default 10 */
  double outcome_timeout_s;      /* wall time for the trial outcome; default 10 */
  double startup_timeout_s;      /* wall time for the first YUMI_STATUS / OBJECT_STATE; default 3 */
  int max_resends;               /* resends of one message (new seq each); default 10 */
  int max_trial_attempts;        /* whole-trial attempts; default 3 */
  int publish_records;           /* publish COM_TRIAL per trial; default 1 */
  void (*log)(void *ctx, const char *msg); /* optional diagnostics (retries, ...) */
  void *log_ctx;
} estimate_lcm_config_t;

void estimate_lcm_config_default(estimate_lcm_config_t *cfg);

/* The placement settings this backend plans every trial with: placement_plan_config_default(),
 * touching B 1 um deep as the estimator's release poses are (`comlearn plan` plans with them). */
void estimate_lcm_plan_config(placement_plan_config_t *cfg);

/* Connect to LCM, subscribe to YUMI_STATUS and OBJECT_STATE, load both YuMi arms and wait
 * (cfg->startup_timeout_s) for the controller's first status. Fills *backend (ctx = handle,
 * name "lcm", B's size from the plan defaults). Returns 0, or 1 (runtime failure: LCM not usable,
 * no controller answering, arm model not loadable) / 2 (bad argument) with err filled. */
int estimate_lcm_open(const estimate_lcm_config_t *cfg, estimate_lcm_t **out,
                      estimate_backend_t *backend, char *err, size_t err_size);

/* Publish COM_ESTIMATE for r (done: the final one). 0 on success, -1 on a publish failure. */
int estimate_lcm_publish_estimate(estimate_lcm_t *l, const estimate_result_t *r,
                                  double resolution_m, int done);

/* Counters of the run (for reports and tests). */
typedef struct {
  uint64_t trials;        /* trial requests answered */
  uint64_t commands_sent; /* YUMI_COMMAND messages, resends included */
  uint64_t commands_resent;
  uint64_t controls_sent;   /* SIM_CONTROL messages, resends included */
  uint64_t trial_restarts;  /* whole trials run again */
  uint64_t statuses;        /* YUMI_STATUS received */
  uint64_t object_states;   /* OBJECT_STATE received */
  uint64_t undecodable;     /* buffers on the subscribed channels that did not decode */
  uint64_t refused;         /* decoded but refused (docs/security.md): a utime or seq outside
                               [-1, 2^62] or a non-finite pose, which would otherwise overflow the
                               expiry and seq arithmetic or poison the trial; a seq this estimator
                               never sent; the state of another object than the one it loaded */
  int kernel_filter;        /* 1: the kernel drops, on LCM's receive socket, every channel but
                               the two it reads (cli_net.h); 0: it could not be attached */
  int64_t rcvbuf_overflows; /* datagrams lost to a full receive buffer on this host since the
                               open (cli_udp_rcvbuf_errors: any socket); -1 when unknown */
} estimate_lcm_stats_t;

void estimate_lcm_stats(const estimate_lcm_t *l, estimate_lcm_stats_t *out);

/* Unsubscribe, destroy the lcm_t, free. NULL is fine. */
void estimate_lcm_close(estimate_lcm_t *l);

/* --spawn-sim: start exe (comlearn-sim) as a child on url with -q, --channel-prefix
 * channel_prefix unless it is NULL or "", and --object-dir for each of object_dirs
 * (NULL-terminated, at most 16; NULL: the simulator's defaults, the bundled assets and its current
 * folder); the child gets SIGKILL if this process dies (PR_SET_PDEATHSIG). Returns the pid, or -1
 * with err filled (also for a channel prefix that is not valid, comlearn/msg.h). */
pid_t estimate_lcm_sim_spawn(const char *exe, const char *url, const char *channel_prefix,
                             const char *const *object_dirs, char *err, size_t err_size);

/* SIGTERM the child and wait for it (SIGKILL after timeout_s). Returns its wait status, or -1. */
int estimate_lcm_sim_stop(pid_t pid, double timeout_s);

#endif
