/*
 * estimate_lcm.c - the LCM trial backend (see estimate_lcm.h and docs/estimate.md).
 */
#define _GNU_SOURCE
#include "estimate_lcm.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <sys/prctl.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#include "comlearn/balance.h" /* its trial settings: the outcome horizon and the slide rule */

#include <lcm/lcm.h>

#include "comlearn/cli_net.h"
#include "comlearn/comlearn_com_estimate_t.h"
#include "comlearn/comlearn_com_trial_t.h"
#include "comlearn/comlearn_object_state_t.h"
#include "comlearn/comlearn_sim_control_t.h"
#include "comlearn/comlearn_yumi_command_t.h"
#include "comlearn/comlearn_yumi_status_t.h"
#include "comlearn/math3d.h"
#include "comlearn/msg.h"
#include "comlearn/placement.h"
#include "comlearn/placement_plan.h"

#define ST(name) COMLEARN_YUMI_STATUS_T_##name
#define CMD(name) COMLEARN_YUMI_COMMAND_T_##name
#define OS(name) COMLEARN_OBJECT_STATE_T_##name
#define SC(name) COMLEARN_SIM_CONTROL_T_##name

enum { ID_MAX = 128, PATH_MAX_LEN = 4096 };

/* Expiry margin on the controller's clock beyond the expected motion time. */
#define EXPIRE_MARGIN_US 5000000

struct estimate_lcm {
  estimate_lcm_config_t cfg;
  char url[512];
  comlearn_msg_channels_t ch; /* the robot's channels, with its prefix (comlearn/msg.h) */
  char urdf[PATH_MAX_LEN];
  char object_id[ID_MAX];
  char policy[32];
  lcm_t *lcm;
  comlearn_msg_subscription_t *sub_st, *sub_os;
  comlearn_msg_stats_t stats;
  placement_arm_t arm[2];
  placement_plan_config_t plan_cfg;
  double bib_wxyz[4]; /* block_in_base orientation as a quaternion */
  /* latest messages */
  comlearn_yumi_status_t st;
  char st_text[512]; /* its error_text, truncated (the simulator's reason for a refusal) */
  uint64_t n_st;
  comlearn_object_state_t os;
  char os_id[ID_MAX];
  uint64_t n_os;
  /* senders */
  int64_t seq, sc_seq;
  int opened; /* estimate_lcm_open took the cell's seqs: from now on they are ours */
  int loaded;
  /* The last trial's retreat, sent and not yet seen in position: the estimator chooses and plans
   * the next trial while the arm moves away (docs/estimate.md, "Pipelining"). */
  int retreating;
  int retreat_arm;
  int64_t retreat_seq;
  placement_waypoint_t retreat_wp;
  int64_t run_id;
  uint64_t rcvbuf_errors_open; /* cli_udp_rcvbuf_errors at the open */
  int rcvbuf_known;
  estimate_lcm_stats_t counters;
};

/* ---- small helpers ------------------------------------------------------------------------- */

static double now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int64_t wall_us(void) {
  struct timespec ts;
  clock_gettime(CLOCK_REALTIME, &ts);
  return (int64_t)ts.tv_sec * 1000000 + (int64_t)ts.tv_nsec / 1000;
}

static void logf_(estimate_lcm_t *l, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void logf_(estimate_lcm_t *l, const char *fmt, ...) {
  if (!l->cfg.log) return;
  char buf[512];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  l->cfg.log(l->cfg.log_ctx, buf);
}

static int rot_is_identity(const double r[3][3]) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (r[i][j] != (i == j ? 1.0 : 0.0)) return 0;
  return 1;
}

/* World (yumi_body) pose from OBJECT_STATE -> B's frame. With B unrotated (the default) only the
 * position moves, so the quaternion passes through bit for bit. */
static void world_to_block(const estimate_lcm_t *l, const double p_w[3], const double q_w[4],
                           model_pose_t *out) {
  const placement_pose_t *b = &l->plan_cfg.block_in_base;
  double d[3];
  for (int i = 0; i < 3; ++i) d[i] = p_w[i] - b->pos_m[i];
  for (int i = 0; i < 3; ++i)
    out->position_m[i] = b->rot[0][i] * d[0] + b->rot[1][i] * d[1] + b->rot[2][i] * d[2];
  if (rot_is_identity(b->rot)) {
    memcpy(out->orientation_wxyz, q_w, 4 * sizeof(double));
  } else {
    double c[4];
    cl_quat_conj(l->bib_wxyz, c);
    cl_quat_mul(c, q_w, out->orientation_wxyz);
  }
}

static void block_to_world(const estimate_lcm_t *l, const model_pose_t *in, double p_w[3],
                           double q_w[4]) {
  const placement_pose_t *b = &l->plan_cfg.block_in_base;
  for (int i = 0; i < 3; ++i)
    p_w[i] = b->pos_m[i] + b->rot[i][0] * in->position_m[0] + b->rot[i][1] * in->position_m[1] +
             b->rot[i][2] * in->position_m[2];
  if (rot_is_identity(b->rot))
    memcpy(q_w, in->orientation_wxyz, 4 * sizeof(double));
  else
    cl_quat_mul(l->bib_wxyz, in->orientation_wxyz, q_w);
}

/* ---- LCM handlers and waits ---------------------------------------------------------------- */

/* The seq of the next message, after `ours` (the last sent) and `theirs` (the last the controller
 * accepted): one past the larger. When ours lies far ahead of theirs (adopted at open from a
 * status nobody else could check, and the controller refuses jumps of more than 2^20,
 * docs/messages.md), start again from theirs. */
static int64_t next_seq(int64_t ours, int64_t theirs) {
  if (ours > theirs + ((int64_t)1 << 19)) ours = theirs;
  return (theirs > ours ? theirs : ours) + 1;
}

/* A clock or counter value the arithmetic here can take: adding a timeout or 1 cannot overflow. */
static int sane_count(int64_t v) { return v >= -1 && v <= ((int64_t)1 << 62); }

static int all_finite(const double *v, size_t n) {
  for (size_t i = 0; i < n; ++i)
    if (!isfinite(v[i])) return 0;
  return 1;
}

static void on_status(const lcm_recv_buf_t *rb, const char *ch, const void *msg, void *user) {
  (void)rb;
  (void)ch;
  estimate_lcm_t *l = user;
  const comlearn_yumi_status_t *m = msg;
  if (!sane_count(m->utime) || !sane_count(m->last_accepted_seq) ||
      !sane_count(m->last_accepted_utime) || !all_finite(&m->q_measured_rad[0][0], 14) ||
      (l->opened && m->last_accepted_seq > l->seq)) { /* a seq we never sent: not our cell's */
    l->counters.refused++;
    return;
  }
  l->st = *m;
  /* the string is valid only during the call: keep a copy */
  snprintf(l->st_text, sizeof l->st_text, "%s", l->st.error_text ? l->st.error_text : "");
  l->st.error_text = NULL;
  l->n_st++;
}

static void on_object(const lcm_recv_buf_t *rb, const char *ch, const void *msg, void *user) {
  (void)rb;
  (void)ch;
  estimate_lcm_t *l = user;
  const comlearn_object_state_t *o = msg;
  if (!sane_count(o->utime) || !sane_count(o->sim_control_seq) ||
      !all_finite(o->position_measured_m, 3) || !all_finite(o->orientation_measured_wxyz, 4) ||
      (l->opened && o->sim_control_seq > l->sc_seq) || /* a SIM_CONTROL we never sent */
      (l->loaded && o->tracked && strcmp(o->object_id, l->object_id) != 0)) { /* another object */
    l->counters.refused++;
    return;
  }
  l->os = *o;
  snprintf(l->os_id, sizeof l->os_id, "%s", o->object_id);
  l->os.object_id = l->os_id;
  l->n_os++;
}

typedef int (*pred_t)(const estimate_lcm_t *l, const void *arg);

/* Handle LCM until pred holds or timeout_s of wall time passed; 1 when it held, 0 on timeout,
 * -1 when LCM fails. */
static int wait_for(estimate_lcm_t *l, pred_t pred, const void *arg, double timeout_s) {
  const double end = now_s() + timeout_s;
  for (;;) {
    if (pred(l, arg)) return 1;
    const double left = end - now_s();
    if (left <= 0) return 0;
    int ms = (int)ceil(left * 1e3);
    if (ms > 50) ms = 50;
    if (lcm_handle_timeout(l->lcm, ms) < 0) return -1;
  }
}

static int have_both(const estimate_lcm_t *l, const void *arg) {
  (void)arg;
  return l->n_st > 0 && l->n_os > 0;
}

static int sc_acked(const estimate_lcm_t *l, const void *arg) {
  return l->n_os > 0 && l->os.sim_control_seq == *(const int64_t *)arg;
}

static int seq_accepted(const estimate_lcm_t *l, const void *arg) {
  return l->n_st > 0 && l->st.last_accepted_seq >= *(const int64_t *)arg;
}

/* In position on seq *arg, or the command lost: the accepted seq went back below it (a restarted
 * controller starts again at -1), so waiting for the motion timeout would be in vain. */
static int seq_in_position(const estimate_lcm_t *l, const void *arg) {
  const int64_t seq = *(const int64_t *)arg;
  return l->n_st > 0 &&
         ((l->st.last_accepted_seq == seq && l->st.in_position) || l->st.last_accepted_seq < seq);
}

/* An object state of utime *arg or later: the one published with the status of that utime. */
static int os_since(const estimate_lcm_t *l, const void *arg) {
  return l->n_os > 0 && l->os.utime >= *(const int64_t *)arg;
}

typedef struct {
  int64_t t_release_us, horizon_us;
} outcome_arg_t;

static int outcome_ready(const estimate_lcm_t *l, const void *arg) {
  const outcome_arg_t *a = arg;
  if (l->n_os == 0 || l->os.utime <= a->t_release_us) return 0;
  if (!l->os.tracked) return 1; /* the object is gone (the simulator restarted): the caller */
  if (l->os.at_rest && l->os.on_base) return 1;
  if (!l->os.on_base) return 1;
  return l->os.utime > a->t_release_us + a->horizon_us;
}

/* ---- messages ------------------------------------------------------------------------------ */

/* SIM_CONTROL with resends; returns the simulator's result, or -1 on a timeout (err filled). */
static int sim_control(estimate_lcm_t *l, int8_t action, int arm, const double g_pos[3],
                       const double g_wxyz[4], double width, char *err, size_t err_size) {
  comlearn_sim_control_t sc;
  memset(&sc, 0, sizeof sc);
  sc.action = action;
  sc.object_id = l->object_id;
  sc.urdf_path = action == SC(ACTION_LOAD) ? l->urdf : (char *)"";
  sc.arm = (int8_t)arm;
  memcpy(sc.link_in_tool_position_m, g_pos, sizeof sc.link_in_tool_position_m);
  memcpy(sc.link_in_tool_wxyz, g_wxyz, sizeof sc.link_in_tool_wxyz);
  sc.gripper_width_m = width;
  for (int k = 0; k <= l->cfg.max_resends; ++k) {
    /* continue after whatever the simulator processed last (it may have restarted) */
    l->sc_seq = next_seq(l->sc_seq, l->n_os > 0 ? l->os.sim_control_seq : l->sc_seq);
    sc.seq = l->sc_seq;
    sc.utime = wall_us();
    if (comlearn_sim_control_t_publish(l->lcm, l->ch.sim_control, &sc) != 0) {
      snprintf(err, err_size, "publish %s failed", l->ch.sim_control);
      return -1;
    }
    l->counters.controls_sent++;
    const int w = wait_for(l, sc_acked, &sc.seq, l->cfg.ack_timeout_s);
    if (w < 0) {
      snprintf(err, err_size, "lcm_handle_timeout failed");
      return -1;
    }
    if (w == 1) return l->os.sim_control_result;
    logf_(l, "SIM_CONTROL seq %lld not acknowledged within %.2f s; resending", (long long)sc.seq,
          l->cfg.ack_timeout_s);
  }
  snprintf(err, err_size,
           "SIM_CONTROL not acknowledged on %s after %d sends (is comlearn-sim "
           "running on %s?)",
           l->ch.object_state, l->cfg.max_resends + 1, l->url);
  return -1;
}

/* Publish one waypoint (arm `arm` to q / width, the other arm held where it is, from the latest
 * status) with a new seq, into *seq. 0 ok, -1 (err). */
static int publish_waypoint(estimate_lcm_t *l, int arm, const placement_waypoint_t *wp,
                            int64_t *seq, char *err, size_t err_size) {
  const double scale = l->plan_cfg.velocity_fraction;
  comlearn_yumi_command_t c;
  memset(&c, 0, sizeof c);
  memcpy(c.q_commanded_rad, l->st.q_measured_rad, sizeof c.q_commanded_rad);
  memcpy(c.gripper_width_commanded_m, l->st.gripper_width_measured_m,
         sizeof c.gripper_width_commanded_m);
  memcpy(c.q_commanded_rad[arm], wp->q_rad, sizeof wp->q_rad);
  c.gripper_width_commanded_m[arm] = wp->gripper_width_m;
  l->seq = next_seq(l->seq, l->st.last_accepted_seq);
  c.seq = l->seq;
  c.utime = wall_us();
  /* The sim times joints at scale x their limits and the gripper at scale x 25 mm/s: the
   * planned duration / scale bounds the motion on the controller's clock. */
  c.expire_utime = l->st.utime + (int64_t)llround(wp->duration_s / scale * 1e6) + EXPIRE_MARGIN_US;
  c.mode = CMD(MODE_POSITION);
  c.velocity_scale = scale;
  if (comlearn_yumi_command_t_publish(l->lcm, l->ch.yumi_command, &c) != 0) {
    snprintf(err, err_size, "publish %s failed", l->ch.yumi_command);
    return -1;
  }
  l->counters.commands_sent++;
  *seq = c.seq;
  return 0;
}

/* Wait until waypoint seq is accepted and reached, the motion waited for at most motion_s of wall
 * time. 1 reached; 0 not (not accepted, something newer accepted, not in position in time, or
 * lost by a restarted controller: the caller sends it again), logged; -1 when LCM fails (err). */
static int await_waypoint(estimate_lcm_t *l, const placement_waypoint_t *wp, int64_t seq,
                          double motion_s, char *err, size_t err_size) {
  int w = wait_for(l, seq_accepted, &seq, l->cfg.ack_timeout_s);
  if (w == 1 && l->st.last_accepted_seq == seq) {
    w = wait_for(l, seq_in_position, &seq, motion_s);
    if (w == 1 && l->st.last_accepted_seq < seq) {
      logf_(l, "%s waypoint seq %lld: the controller lost it (accepted seq now %lld: restarted?)",
            placement_waypoint_kind_str(wp->kind), (long long)seq,
            (long long)l->st.last_accepted_seq);
      return 0; /* resend at once */
    }
  } else if (w == 1)
    w = 0; /* something newer was accepted: not ours; resend */
  if (w < 0) {
    snprintf(err, err_size, "lcm_handle_timeout failed");
    return -1;
  }
  if (w == 0)
    logf_(l, "%s waypoint seq %lld: no %s within the timeout (status seq %lld, error %d)",
          placement_waypoint_kind_str(wp->kind), (long long)seq,
          l->st.last_accepted_seq >= seq ? "in_position" : "acceptance",
          (long long)l->st.last_accepted_seq, (int)l->st.error_code);
  return w;
}

/* Send one waypoint and wait until it is accepted and reached; resend with a new seq on a
 * timeout or a refusal. 0 ok, -1 (err). */
static int send_waypoint(estimate_lcm_t *l, int arm, const placement_waypoint_t *wp, char *err,
                         size_t err_size) {
  for (int k = 0; k <= l->cfg.max_resends; ++k) {
    int64_t seq;
    if (publish_waypoint(l, arm, wp, &seq, err, err_size) != 0) return -1;
    if (k > 0) l->counters.commands_resent++;
    const int w = await_waypoint(l, wp, seq, l->cfg.motion_timeout_s, err, err_size);
    if (w < 0) return -1;
    if (w == 1) return 0;
  }
  snprintf(err, err_size, "%s waypoint: not accepted / reached after %d sends (status error %d)",
           placement_waypoint_kind_str(wp->kind), l->cfg.max_resends + 1, (int)l->st.error_code);
  return -1;
}

/* The pipelined retreat of the last trial, seen through: in position, or sent again until it is.
 * 0 ok (or none pending), -1 (err). */
static int retreat_finish(estimate_lcm_t *l, char *err, size_t err_size) {
  if (!l->retreating) return 0;
  l->retreating = 0;
  const int w =
      await_waypoint(l, &l->retreat_wp, l->retreat_seq, l->cfg.motion_timeout_s, err, err_size);
  if (w < 0) return -1;
  return w == 1 ? 0 : send_waypoint(l, l->retreat_arm, &l->retreat_wp, err, err_size);
}

/* ---- one trial ----------------------------------------------------------------------------- */

/* The grasp (lib/placement's top-down grasp, docs/estimate.md) for the release pose and a plan
 * from the measured joints (a pipelined retreat's arm from the retreat's target): right arm,
 * finger yaws 0, 90, -90, 180 degrees, then the left arm. The planned arm's start into start.
 * 0 ok, -1 (err). */
static int plan_trial(estimate_lcm_t *l, const model_pose_t *rel, placement_grasp_t *g,
                      double start[PLACEMENT_JOINTS], char *err, size_t err_size) {
  placement_grasp_request_t req;
  memset(&req, 0, sizeof req);
  req.mesh_link = l->cfg.mesh_link;
  req.object_in_block = *rel;
  memcpy(req.q_start_rad, l->st.q_measured_rad, sizeof req.q_start_rad);
  if (l->retreating) /* the arm is on its way there */
    memcpy(req.q_start_rad[l->retreat_arm], l->retreat_wp.q_rad, sizeof l->retreat_wp.q_rad);
  const placement_grasp_config_t gcfg = PLACEMENT_GRASP_CONFIG_INIT;
  placement_error_t pe = {{0}};
  const placement_status_t ps = placement_grasp_plan(l->arm, &l->plan_cfg, &gcfg, &req, g, &pe);
  if (ps == PLACEMENT_OK) {
    memcpy(start, req.q_start_rad[g->side], sizeof req.q_start_rad[g->side]);
    return 0;
  }
  snprintf(err, err_size, "no placement plan for the release pose (%.4f, %.4f, %.4f): %s %s",
           rel->position_m[0], rel->position_m[1], rel->position_m[2], placement_status_str(ps),
           pe.msg);
  return -1;
}

static int8_t outcome_to_msg(estimate_outcome_t o) {
  switch (o) {
    case ESTIMATE_STAYS: return COMLEARN_COM_TRIAL_T_OUTCOME_STAYS;
    case ESTIMATE_TIPS: return COMLEARN_COM_TRIAL_T_OUTCOME_TIPS;
    case ESTIMATE_SLIDES: return COMLEARN_COM_TRIAL_T_OUTCOME_SLIDES;
    case ESTIMATE_INVALID: return COMLEARN_COM_TRIAL_T_OUTCOME_INVALID;
  }
  return COMLEARN_COM_TRIAL_T_OUTCOME_INVALID;
}

static void publish_trial(estimate_lcm_t *l, const estimate_trial_request_t *req,
                          const estimate_trial_reply_t *rep) {
  comlearn_com_trial_t t;
  memset(&t, 0, sizeof t);
  t.utime = wall_us();
  t.run_id = l->run_id;
  t.object_id = l->object_id;
  t.policy = l->policy;
  t.trial_index = (int32_t)l->counters.trials;
  t.kind = req->kind == ESTIMATE_TRIAL_EDGE ? COMLEARN_COM_TRIAL_T_KIND_EDGE
                                            : COMLEARN_COM_TRIAL_T_KIND_REST;
  t.base_top_z_m = l->plan_cfg.block_in_base.pos_m[2];
  if (req->kind == ESTIMATE_TRIAL_EDGE) {
    double n[3], d;
    model_edge_line(l->plan_cfg.block_size_m, req->edge, n, &d);
    const placement_pose_t *b = &l->plan_cfg.block_in_base;
    for (int i = 0; i < 3; ++i)
      t.edge_normal_world[i] = b->rot[i][0] * n[0] + b->rot[i][1] * n[1] + b->rot[i][2] * n[2];
    t.edge_offset_m = d + t.edge_normal_world[0] * b->pos_m[0] +
                      t.edge_normal_world[1] * b->pos_m[1] + t.edge_normal_world[2] * b->pos_m[2];
  }
  block_to_world(l, &rep->released, t.released_position_m, t.released_orientation_wxyz);
  block_to_world(l, &rep->settled, t.settled_position_m, t.settled_orientation_wxyz);
  t.outcome = outcome_to_msg(rep->outcome);
  double dd = 0;
  for (int i = 0; i < 3; ++i) {
    const double e = rep->settled.position_m[i] - rep->released.position_m[i];
    dd += e * e;
  }
  t.displacement_m = sqrt(dd);
  t.rotation_rad = cl_quat_angle(rep->released.orientation_wxyz, rep->settled.orientation_wxyz);
  /* Estimator-side fields, from the request (estimate.h): component (-1 for a rest check),
   * direction, target point, the planned pose's regime, the running estimate before the trial. */
  t.component = (int8_t)req->component;
  t.direction = (int8_t)req->direction;
  memcpy(t.target_point_link_m, req->target_link_m, sizeof t.target_point_link_m);
  t.flat_patch = req->kind == ESTIMATE_TRIAL_EDGE && req->flat_patch;
  t.sideways_margin_m = req->sideways_margin_m;
  memcpy(t.com_estimated_m, req->com_before_m, sizeof t.com_estimated_m);
  memcpy(t.halfwidth_m, req->halfwidth_before_m, sizeof t.halfwidth_m);
  if (req->kind == ESTIMATE_TRIAL_EDGE) {
    /* the target point at release, beyond the edge line (B's frame: the same distance) */
    double n[3], d, r[3][3], p = 0.0;
    model_edge_line(l->plan_cfg.block_size_m, req->edge, n, &d);
    model_quat_to_rot(rep->released.orientation_wxyz, r);
    for (int i = 0; i < 3; ++i)
      p += n[i] * (rep->released.position_m[i] + r[i][0] * req->target_link_m[0] +
                   r[i][1] * req->target_link_m[1] + r[i][2] * req->target_link_m[2]);
    t.target_offset_m = p - d;
  }
  if (comlearn_com_trial_t_publish(l->lcm, l->ch.com_trial, &t) != 0)
    logf_(l, "publish %s failed", l->ch.com_trial);
}

/* Step 1 of a trial: the object into the gripper (SIM_CONTROL LOAD, or RESET once loaded; a
 * simulator that forgot the object loads it again). 0 ok, 1 retryable, -1 fatal (err filled). */
static int trial_load(estimate_lcm_t *l, const placement_grasp_t *tp, char *err, size_t err_size) {
  int r = sim_control(l, l->loaded ? SC(ACTION_RESET) : SC(ACTION_LOAD), (int)tp->side,
                      tp->object_in_tcp.position_m, tp->object_in_tcp.orientation_wxyz,
                      tp->grip_width_m, err, err_size);
  if (r == OS(SIM_CONTROL_ERR_UNKNOWN_ID)) { /* the simulator restarted: load again */
    logf_(l, "the simulator does not know %s (restarted?); loading it again", l->object_id);
    l->loaded = 0;
    r = sim_control(l, SC(ACTION_LOAD), (int)tp->side, tp->object_in_tcp.position_m,
                    tp->object_in_tcp.orientation_wxyz, tp->grip_width_m, err, err_size);
  }
  if (r < 0) return 1;
  if (r != OS(SIM_CONTROL_APPLIED)) {
    /* comlearn-sim publishes the status, with its reason for a refused LOAD, before the
     * acknowledgement; any other error text is not about this message */
    const int why = strncmp(l->st_text, "SIM_CONTROL", 11) == 0;
    snprintf(err, err_size, "SIM_CONTROL %s of %s refused: result %d%s%s",
             l->loaded ? "reset" : "load", l->urdf, r, why ? ": " : "", why ? l->st_text : "");
    return -1;
  }
  l->loaded = 1;
  return 0;
}

/* Steps 2-3: pre-place, place, release; reply->released is the held object as perceived at
 * PLACE, before the fingers open. 0 ok, 1 retryable, -1 fatal. */
static int trial_place(estimate_lcm_t *l, const placement_grasp_t *tp,
                       estimate_trial_reply_t *reply, char *err, size_t err_size) {
  /* A fresh status after the reset, for the plan's start. The plan was made from the status
   * before; the arm did not move in between (a reset does not move it). */
  for (int k = 0; k <= PLACEMENT_WAYPOINT_RELEASE; ++k) {
    if (send_waypoint(l, (int)tp->side, &tp->plan.waypoints[k], err, err_size) != 0) return 1;
    if (k == PLACEMENT_WAYPOINT_PLACE) {
      /* the object as the status that said "in position" saw it: comlearn-sim publishes both
       * on that tick; waiting for a newer one cost up to a status period of an idle sim */
      const int64_t t = l->st.utime;
      if (wait_for(l, os_since, &t, l->cfg.ack_timeout_s) != 1) {
        snprintf(err, err_size, "no OBJECT_STATE at the place pose");
        return 1;
      }
      if (!l->os.tracked || strcmp(l->os.object_id, l->object_id) != 0) {
        snprintf(err, err_size, "OBJECT_STATE does not track %s at the place pose", l->object_id);
        return 1;
      }
      world_to_block(l, l->os.position_measured_m, l->os.orientation_measured_wxyz,
                     &reply->released);
    }
  }
  if (l->st.error_code == ST(ERR_FAULT)) {
    snprintf(err, err_size, "the controller refused the release (ERR_FAULT at utime %lld)",
             (long long)l->st.utime);
    return -1;
  }
  return 0;
}

/* Step 4: the outcome, on the controller's clock: reply->settled and reply->outcome. 0 ok, 1
 * retryable. */
static int trial_outcome(estimate_lcm_t *l, estimate_trial_reply_t *reply, char *err,
                         size_t err_size) {
  balance_config_t bc;
  balance_config_default(&bc);
  outcome_arg_t oa = {
      .t_release_us =
          l->st.utime -
          (int64_t)llround(l->plan_cfg.release_opening_m /
                           (l->plan_cfg.gripper_speed_m_s * l->plan_cfg.velocity_fraction) * 1e6),
      .horizon_us = (int64_t)llround(bc.horizon_s * 1e6) + 200000};
  /* release happened when the opening started; the status at in_position is later. The object
   * state of that status's tick is enough (comlearn-sim publishes both on it): waiting for a
   * newer one cost a status period of an idle sim, 4 ms a trial when the release's motion and
   * the trial end on the same tick */
  const int64_t t_now = l->st.utime;
  if (wait_for(l, os_since, &t_now, l->cfg.ack_timeout_s) != 1 ||
      wait_for(l, outcome_ready, &oa, l->cfg.outcome_timeout_s) != 1) {
    snprintf(err, err_size, "no trial outcome on %s within %.1f s", l->ch.object_state,
             l->cfg.outcome_timeout_s);
    return 1;
  }
  if (!l->os.tracked || strcmp(l->os.object_id, l->object_id) != 0) {
    snprintf(err, err_size, "%s no longer tracked after the release (the simulator restarted?)",
             l->object_id);
    return 1;
  }
  world_to_block(l, l->os.position_measured_m, l->os.orientation_measured_wxyz, &reply->settled);
  if (l->os.at_rest && l->os.on_base)
    reply->outcome = ESTIMATE_STAYS;
  else if (!l->os.on_base) {
    /* off B: tipped, unless it clearly slid (lib/balance's slide rule, on the link origin
     * since the CoM is unknown). A tip is often called early, after little motion. */
    const double rot =
        cl_quat_angle(reply->released.orientation_wxyz, reply->settled.orientation_wxyz);
    reply->outcome =
        balance_trial_slid(&bc, reply->released.position_m, reply->settled.position_m, rot)
            ? ESTIMATE_SLIDES
            : ESTIMATE_TIPS;
  } else
    reply->outcome = ESTIMATE_INVALID;
  return 0;
}

/* The plan's start is where the arm is: after a pipelined retreat it was planned from the
 * retreat's target, which the arm reaches unless the controller lost the command (restarted). */
static int plan_start_holds(const estimate_lcm_t *l, const placement_grasp_t *tp,
                            const double q_start[PLACEMENT_JOINTS]) {
  for (int k = 0; k < PLACEMENT_JOINTS; ++k)
    if (fabs(l->st.q_measured_rad[tp->side][k] - q_start[k]) > 1e-9) return 0;
  return 1;
}

/* One attempt of a trial. 0 ok (reply filled), 1 retryable failure, -1 fatal (err filled). */
static int trial_attempt(estimate_lcm_t *l, const estimate_trial_request_t *req,
                         estimate_trial_reply_t *reply, char *err, size_t err_size) {
  placement_grasp_t tp;
  double q_start[PLACEMENT_JOINTS];
  if (plan_trial(l, &req->release, &tp, q_start, err, err_size) != 0) return -1;
  /* the plan was made while the last retreat moved; now see the arm there */
  if (retreat_finish(l, err, err_size) != 0) return 1;
  if (!plan_start_holds(l, &tp, q_start) &&
      plan_trial(l, &req->release, &tp, q_start, err, err_size) != 0)
    return -1;
  const int side = (int)tp.side;
  int r = trial_load(l, &tp, err, err_size);
  if (r == 0) r = trial_place(l, &tp, reply, err, err_size);
  if (r == 0) r = trial_outcome(l, reply, err, err_size);
  if (r != 0) return r;
  /* 5. retreat (the object is no longer held): sent now, seen through before the next trial's
   * first message (or at the close), so that the estimator's choice and the next plan overlap
   * the motion */
  l->retreat_arm = side;
  l->retreat_wp = tp.plan.waypoints[PLACEMENT_WAYPOINT_RETREAT];
  if (publish_waypoint(l, side, &l->retreat_wp, &l->retreat_seq, err, err_size) != 0) return 1;
  l->retreating = 1;
  return 0;
}

static int lcm_run(void *ctx, const estimate_trial_request_t *req, estimate_trial_reply_t *reply,
                   char *err, size_t err_size) {
  estimate_lcm_t *l = ctx;
  memset(reply, 0, sizeof *reply);
  for (int a = 0; a < l->cfg.max_trial_attempts; ++a) {
    if (a > 0) {
      l->counters.trial_restarts++;
      logf_(l, "trial %llu: %s; running it again (attempt %d of %d)",
            (unsigned long long)l->counters.trials, err, a + 1, l->cfg.max_trial_attempts);
      l->loaded = 0; /* whatever happened, start from a fresh load */
    }
    if (wait_for(l, have_both, NULL, l->cfg.ack_timeout_s) != 1) {
      snprintf(err, err_size, "no YUMI_STATUS / OBJECT_STATE on %s", l->url);
      continue;
    }
    const int r = trial_attempt(l, req, reply, err, err_size);
    if (r == 0) {
      if (l->cfg.publish_records) publish_trial(l, req, reply);
      l->counters.trials++;
      return 0;
    }
    if (r < 0) return -1;
  }
  return -1;
}

/* ---- open / close ---------------------------------------------------------------------------- */

void estimate_lcm_config_default(estimate_lcm_config_t *cfg) {
  memset(cfg, 0, sizeof *cfg);
  cfg->ack_timeout_s = 0.5;
  cfg->motion_timeout_s = 10.0;
  cfg->outcome_timeout_s = 10.0;
  cfg->startup_timeout_s = 3.0;
  cfg->max_resends = 10;
  cfg->max_trial_attempts = 3;
  cfg->publish_records = 1;
}

void estimate_lcm_plan_config(placement_plan_config_t *cfg) {
  placement_plan_config_default(cfg);
  /* the estimator's trials are 1 um pre-penetrated; plan the same touching depth */
  cfg->touch_depth_m = 1e-6;
}

/* The backend's names: its copy of the settings, the LCM URL, the URDF's absolute path, the
 * object id (the option, or the URDF's file name without .urdf), the policy label, the run id,
 * and the placement plan settings. */
static void lcm_identity(estimate_lcm_t *l, const estimate_lcm_config_t *cfg) {
  l->cfg = *cfg;
  (void)comlearn_msg_channels(cfg->channel_prefix, &l->ch); /* checked in estimate_lcm_open */
  /* with comlearn's receive buffer (cli_net.h); a URL too long for it is kept as it is */
  const char *url = cfg->lcm_url ? cfg->lcm_url : COMLEARN_MSG_LCM_URL_DEFAULT;
  if (cli_lcm_url_buffered(url, l->url, sizeof l->url) != 0)
    snprintf(l->url, sizeof l->url, "%s", url);
  char *abs = realpath(cfg->urdf_path, NULL);
  snprintf(l->urdf, sizeof l->urdf, "%s", abs ? abs : cfg->urdf_path);
  free(abs);
  if (cfg->object_id && cfg->object_id[0]) {
    snprintf(l->object_id, sizeof l->object_id, "%s", cfg->object_id);
  } else {
    const char *b = strrchr(cfg->urdf_path, '/');
    snprintf(l->object_id, sizeof l->object_id, "%s", b ? b + 1 : cfg->urdf_path);
    char *dot = strstr(l->object_id, ".urdf");
    if (dot) *dot = '\0';
    if (!l->object_id[0]) snprintf(l->object_id, sizeof l->object_id, "object");
  }
  snprintf(l->policy, sizeof l->policy, "%s", cfg->policy ? cfg->policy : "");
  l->seq = 0;
  l->sc_seq = 0;
  l->run_id = wall_us();
  estimate_lcm_plan_config(&l->plan_cfg);
  model_rot_to_quat((const double(*)[3])l->plan_cfg.block_in_base.rot, l->bib_wxyz);
}

/* LCM up, both status channels subscribed and heard from within the startup timeout. 0 ok; -1
 * with err filled and l freed. */
static int lcm_connect(estimate_lcm_t *l, char *err, size_t err_size) {
  l->lcm = lcm_create(l->url);
  if (!l->lcm) {
    snprintf(err, err_size,
             "lcm_create(%s) failed (udpm needs a multicast route: "
             "`ip route add 224.0.0.0/4 dev lo` as root, see scripts/setup.sh)",
             l->url);
    free(l);
    return -1;
  }
  comlearn_msg_sub_config_t c1 = {.type = comlearn_yumi_status_t_get_type_info(),
                                  .on_message = on_status,
                                  .user = l,
                                  .stats = &l->stats};
  comlearn_msg_sub_config_t c2 = {.type = comlearn_object_state_t_get_type_info(),
                                  .on_message = on_object,
                                  .user = l,
                                  .stats = &l->stats};
  cli_socket_set_t before;
  cli_socket_set_now(&before);
  if (comlearn_msg_subscribe(l->lcm, l->ch.yumi_status, &c1, &l->sub_st) != COMLEARN_MSG_OK ||
      comlearn_msg_subscribe(l->lcm, l->ch.object_state, &c2, &l->sub_os) != COMLEARN_MSG_OK) {
    snprintf(err, err_size, "subscribing on %s failed", l->url);
    estimate_lcm_close(l);
    return -1;
  }
  /* LCM opens its receive socket on the first subscription: check its buffer, and let the
   * kernel drop what this estimator does not read (cli_net.h) */
  const char *heard[] = {l->ch.yumi_status, l->ch.object_state};
  l->counters.kernel_filter = cli_lcm_receive_setup(l->url, &before, heard, 2) > 0;
  l->rcvbuf_known = cli_udp_rcvbuf_errors(&l->rcvbuf_errors_open) == 0;
  if (wait_for(l, have_both, NULL, l->cfg.startup_timeout_s) != 1) {
    snprintf(err, err_size,
             "no YUMI_STATUS / OBJECT_STATE on %s within %.1f s: is comlearn-sim "
             "(or a YuMi driver) running there? (--spawn-sim starts one)",
             l->url, l->cfg.startup_timeout_s);
    estimate_lcm_close(l);
    return -1;
  }
  return 0;
}

int estimate_lcm_open(const estimate_lcm_config_t *cfg, estimate_lcm_t **out,
                      estimate_backend_t *backend, char *err, size_t err_size) {
  if (out) *out = NULL;
  if (!cfg || !out || !backend || !cfg->urdf_path || !cfg->mesh_link || !cfg->yumi_urdf ||
      cfg->mesh_link->vertex_count == 0 || !(cfg->ack_timeout_s > 0) ||
      !(cfg->motion_timeout_s > 0) || !(cfg->outcome_timeout_s > 0) ||
      !(cfg->startup_timeout_s > 0) || cfg->max_resends < 0 || cfg->max_trial_attempts < 1 ||
      !comlearn_msg_channel_prefix_ok(cfg->channel_prefix)) {
    snprintf(err, err_size, "estimate_lcm_open: bad argument");
    return 2;
  }
  memset(backend, 0, sizeof *backend);
  estimate_lcm_t *l = calloc(1, sizeof *l);
  if (!l) {
    snprintf(err, err_size, "out of memory");
    return 1;
  }
  lcm_identity(l, cfg);
  placement_error_t pe = {{0}};
  placement_status_t ps =
      placement_arm_load_yumi(&l->arm[0], cfg->yumi_urdf, PLACEMENT_ARM_LEFT, &pe);
  if (ps == PLACEMENT_OK)
    ps = placement_arm_load_yumi(&l->arm[1], cfg->yumi_urdf, PLACEMENT_ARM_RIGHT, &pe);
  if (ps != PLACEMENT_OK) {
    snprintf(err, err_size, "%s: %s %s", cfg->yumi_urdf, placement_status_str(ps), pe.msg);
    free(l);
    return 1;
  }
  if (lcm_connect(l, err, err_size) != 0) return 1; /* l freed */
  l->seq = l->st.last_accepted_seq > 0 ? l->st.last_accepted_seq : 0;
  l->sc_seq = l->os.sim_control_seq > 0 ? l->os.sim_control_seq : 0;
  l->opened = 1;
  backend->ctx = l;
  backend->name = "lcm";
  balance_config_t bc;
  balance_config_default(&bc);
  memcpy(backend->base_size_m, bc.base_size_m, sizeof bc.base_size_m);
  backend->run = lcm_run;
  *out = l;
  return 0;
}

int estimate_lcm_publish_estimate(estimate_lcm_t *l, const estimate_result_t *r,
                                  double resolution_m, int done) {
  if (!l || !r) return -1;
  comlearn_com_estimate_t e;
  memset(&e, 0, sizeof e);
  e.utime = wall_us();
  e.run_id = l->run_id;
  e.object_id = l->object_id;
  e.policy = l->policy;
  e.resolution_m = resolution_m;
  for (int k = 0; k < 3; ++k) {
    e.com_estimated_m[k] = r->com_m[k];
    e.halfwidth_m[k] = r->halfwidth_m[k];
    e.found[k] = (int8_t)(r->found[k] != 0);
  }
  e.trials = r->trial_count > INT32_MAX ? INT32_MAX : (int32_t)r->trial_count;
  e.done = (int8_t)(done != 0);
  return comlearn_com_estimate_t_publish(l->lcm, l->ch.com_estimate, &e) == 0 ? 0 : -1;
}

void estimate_lcm_stats(const estimate_lcm_t *l, estimate_lcm_stats_t *out) {
  *out = l->counters;
  uint64_t now = 0;
  out->rcvbuf_overflows = l->rcvbuf_known && cli_udp_rcvbuf_errors(&now) == 0
                              ? (int64_t)(now - l->rcvbuf_errors_open)
                              : -1;
  out->statuses = l->n_st;
  out->object_states = l->n_os;
  out->undecodable = comlearn_msg_stats_rejected(&l->stats);
}

void estimate_lcm_close(estimate_lcm_t *l) {
  if (!l) return;
  if (l->lcm && l->retreating) {
    /* leave the arm at rest where the last trial sent it; a controller that went away costs at
     * most the acknowledgement timeout and the motion's own time */
    char err[256];
    l->retreating = 0;
    (void)await_waypoint(
        l, &l->retreat_wp, l->retreat_seq,
        l->retreat_wp.duration_s / l->plan_cfg.velocity_fraction + l->cfg.ack_timeout_s, err,
        sizeof err);
  }
  if (l->lcm) {
    comlearn_msg_unsubscribe(l->lcm, l->sub_st);
    comlearn_msg_unsubscribe(l->lcm, l->sub_os);
    lcm_destroy(l->lcm);
  }
  free(l);
}

/* ---- --spawn-sim ----------------------------------------------------------------------------- */

pid_t estimate_lcm_sim_spawn(const char *exe, const char *url, const char *channel_prefix,
                             const char *const *object_dirs, char *err, size_t err_size) {
  if (!exe || !url || !comlearn_msg_channel_prefix_ok(channel_prefix)) {
    snprintf(err, err_size, "spawn: bad argument");
    return -1;
  }
  enum { DIRS_MAX = 16 };
  const char *argv[7 + 2 * DIRS_MAX] = {exe, "--lcm-url", url, "-q"};
  int argc = 4;
  if (channel_prefix && channel_prefix[0]) {
    argv[argc++] = "--channel-prefix";
    argv[argc++] = channel_prefix;
  }
  for (int i = 0; object_dirs && object_dirs[i]; ++i) {
    if (i >= DIRS_MAX) {
      snprintf(err, err_size, "spawn: more than %d object folders", DIRS_MAX);
      return -1;
    }
    argv[argc++] = "--object-dir";
    argv[argc++] = object_dirs[i];
  }
  argv[argc] = NULL;
  if (access(exe, X_OK) != 0) {
    snprintf(err, err_size, "spawn: %s: %s", exe, strerror(errno));
    return -1;
  }
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) {
    snprintf(err, err_size, "fork: %s", strerror(errno));
    return -1;
  }
  if (pid == 0) {
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(127);
    execv(exe, (char *const *)argv);
    _exit(127);
  }
  return pid;
}

int estimate_lcm_sim_stop(pid_t pid, double timeout_s) {
  if (pid <= 0) return -1;
  kill(pid, SIGTERM);
  const double end = now_s() + timeout_s;
  int ws;
  for (;;) {
    const pid_t r = waitpid(pid, &ws, WNOHANG);
    if (r == pid) return ws;
    if (r < 0) return -1;
    if (now_s() >= end) break;
    struct timespec ts = {0, 5000000};
    nanosleep(&ts, NULL);
  }
  kill(pid, SIGKILL);
  return waitpid(pid, &ws, 0) == pid ? ws : -1;
}
