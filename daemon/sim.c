/* sim.c - comlearn-sim's kinematic YuMi, held object and physics (see sim.h, docs/sim.md). */
#define _XOPEN_SOURCE 700 /* realpath */
#include "sim.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "comlearn/math3d.h"
#include "comlearn/model_inertial.h"

#define ERR(name) COMLEARN_YUMI_STATUS_T_##name
#define SC(name) COMLEARN_OBJECT_STATE_T_##name

static void set_error(sim_t *s, int32_t code, const char *fmt, ...) {
  s->error_code = code;
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(s->error_text, sizeof s->error_text, fmt, ap);
  va_end(ap);
}

static void clear_error(sim_t *s) {
  s->error_code = ERR(ERR_NONE);
  s->error_text[0] = '\0';
}

/* ---- small pose helpers ------------------------------------------------------------------ */

/* model_pose_t has cl_pose_t's layout but is its own type (lib/model does not use
 * comlearn/math3d.h): the quaternion comes from lib/placement's converter, through a cl_pose_t.
 * The way back stays unchecked (cl_quat_to_rot of the quaternion as it is):
 * placement_pose_from_cl_pose would normalise it again, changing the last bits of poses that
 * lib/balance already normalised. */
static void pose_to_balance(const placement_pose_t *p, model_pose_t *b) {
  cl_pose_t c;
  placement_pose_to_cl_pose(p, &c);
  memcpy(b->position_m, c.position_m, sizeof b->position_m);
  memcpy(b->orientation_wxyz, c.orientation_wxyz, sizeof b->orientation_wxyz);
}

static void pose_from_balance(const model_pose_t *b, placement_pose_t *p) {
  cl_quat_to_rot(b->orientation_wxyz, p->rot);
  memcpy(p->pos_m, b->position_m, sizeof p->pos_m);
}

/* Rotation vector of rb * ra^T (world axes): the rotation that takes a to b. */
static void rot_delta(const placement_pose_t *pa, const placement_pose_t *pb, double w[3]) {
  const double(*ra)[3] = pa->rot, (*rb)[3] = pb->rot;
  double d[3][3];
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      d[i][j] = 0.0;
      for (int k = 0; k < 3; k++) d[i][j] += rb[i][k] * ra[j][k];
    }
  const double c = fmax(-1.0, fmin(1.0, 0.5 * (d[0][0] + d[1][1] + d[2][2] - 1.0)));
  const double ang = acos(c);
  double ax[3] = {d[2][1] - d[1][2], d[0][2] - d[2][0], d[1][0] - d[0][1]};
  const double sn = sqrt(ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]);
  for (int i = 0; i < 3; i++) w[i] = sn > 1e-15 ? ax[i] / sn * ang : 0.5 * ax[i];
}

/* ---- set-up -------------------------------------------------------------------------------- */

int sim_init(sim_t *s, const sim_config_t *cfg, char *err, size_t err_len) {
  memset(s, 0, sizeof *s);
  s->cfg = *cfg;
  if (cfg->object_dir_count > SIM_OBJECT_DIRS_MAX) {
    snprintf(err, err_len, "more than %d object folders", SIM_OBJECT_DIRS_MAX);
    return -1;
  }
  for (size_t i = 0; i < cfg->object_dir_count; ++i) {
    struct stat st;
    if (realpath(cfg->object_dirs[i], s->object_dir[i]) == NULL ||
        stat(s->object_dir[i], &st) != 0 || !S_ISDIR(st.st_mode)) {
      snprintf(err, err_len, "object folder %s: %s", cfg->object_dirs[i],
               errno ? strerror(errno) : "not a folder");
      return -1;
    }
    s->cfg.object_dirs[i] = s->object_dir[i];
  }
  for (int a = 0; a < 2; a++) {
    placement_error_t pe = {{0}};
    placement_status_t ps = placement_arm_load_yumi(
        &s->arm[a], cfg->yumi_urdf, a == 0 ? PLACEMENT_ARM_LEFT : PLACEMENT_ARM_RIGHT, &pe);
    if (ps != PLACEMENT_OK) {
      snprintf(err, err_len, "cannot load the YuMi model %s: %s (%s)", cfg->yumi_urdf,
               placement_status_str(ps), pe.msg);
      return -1;
    }
    placement_yumi_nominal(a == 0 ? PLACEMENT_ARM_LEFT : PLACEMENT_ARM_RIGHT, s->q[a]);
    memcpy(s->q_target[a], s->q[a], sizeof s->q[a]);
  }
  placement_plan_config_default(&s->plan);
  placement_pose_inverse(&s->plan.block_in_base, &s->base_in_block);
  s->state = ERR(STATE_HOLD);
  s->in_position = 1;
  s->last_seq = -1;
  s->last_seq_utime = -1;
  s->active_expire_utime = INT64_MAX;
  s->motion_us = -1;
  s->sc_seq_processed = -1;
  s->sc_ack_seq = -1;
  s->sc_ack_result = SC(SIM_CONTROL_APPLIED);
  s->held_arm = 0;
  return 0;
}

static void object_unload(sim_t *s) {
  balance_world_destroy(s->world);
  s->world = NULL;
  s->obj = NULL;
  model_object_free(&s->model);
  s->loaded = 0;
  s->phase = SIM_OBJ_NONE;
  s->object_id[0] = '\0';
}

void sim_fini(sim_t *s) { object_unload(s); }

int sim_busy(const sim_t *s) {
  return s->motion_us >= 0 || (s->phase == SIM_OBJ_TRIAL && s->utime < s->trial_t1);
}

/* ---- object pose -------------------------------------------------------------------------- */

static void tool_pose(const sim_t *s, int arm, placement_pose_t *tcp_in_base) {
  if (placement_fk(&s->arm[arm], s->q[arm], tcp_in_base) != PLACEMENT_OK)
    placement_pose_identity(tcp_in_base); /* unreachable: q is always finite */
}

/* The object's link frame in the world (yumi_body) now; 0 when not tracked. */
static int object_pose(sim_t *s, placement_pose_t *out, int *moving) {
  *moving = 0;
  switch (s->phase) {
    case SIM_OBJ_NONE: return 0;
    case SIM_OBJ_HELD:
    case SIM_OBJ_REFUSED: {
      if (s->phase == SIM_OBJ_REFUSED) {
        *out = s->rel_world;
        return 1;
      }
      placement_pose_t tcp;
      tool_pose(s, s->held_arm, &tcp);
      placement_pose_mul(&tcp, &s->link_in_tool, out);
      return 1;
    }
    case SIM_OBJ_TRIAL: {
      if (s->utime >= s->trial_t1) {
        *out = s->set_world;
        return 1;
      }
      /* Played back on the sim clock: lib/balance decided the whole trial at release (its result
       * is the authority, bit-identical to `comlearn estimate --direct`); in between, the pose is
       * interpolated from the released to the final one. */
      const double t = (double)(s->utime - s->trial_t0) / (double)(s->trial_t1 - s->trial_t0);
      model_pose_t a, b;
      pose_to_balance(&s->rel_world, &a);
      pose_to_balance(&s->set_world, &b);
      model_pose_t m;
      for (int i = 0; i < 3; i++)
        m.position_m[i] = a.position_m[i] + t * (b.position_m[i] - a.position_m[i]);
      cl_quat_slerp(a.orientation_wxyz, b.orientation_wxyz, t, m.orientation_wxyz);
      pose_from_balance(&m, out);
      *moving = 1;
      return 1;
    }
  }
  return 0;
}

/* Release the held object into lib/balance exactly where it is. */
static void object_release(sim_t *s) {
  placement_pose_t world_pose, block_pose;
  int moving;
  object_pose(s, &world_pose, &moving);
  s->rel_world = world_pose;
  placement_pose_mul(&s->base_in_block, &world_pose, &block_pose);
  double z0 = 0.0;
  placement_status_t ps =
      placement_plan_touch_z(&s->model.mesh, &block_pose, s->plan.block_size_m, 0.0, &z0);
  if (ps != PLACEMENT_OK) {
    s->phase = SIM_OBJ_REFUSED;
    set_error(s, ERR(ERR_FAULT),
              "release refused: object %s is not over block B (%s); not simulated", s->object_id,
              placement_status_str(ps));
    return;
  }
  const double gap = block_pose.pos_m[2] - z0;
  if (gap > SIM_RELEASE_MAX_GAP_M || gap < -SIM_RELEASE_MAX_GAP_M) {
    s->phase = SIM_OBJ_REFUSED;
    set_error(s, ERR(ERR_FAULT),
              "release refused: object %s %.4f mm %s B's top (limit %.3f mm); not simulated",
              s->object_id, fabs(gap) * 1e3, gap > 0 ? "above" : "inside",
              SIM_RELEASE_MAX_GAP_M * 1e3);
    return;
  }
  model_pose_t rel;
  pose_to_balance(&block_pose, &rel);
  balance_noise_t noise = {.seed = balance_noise_seed(s->cfg.seed, s->trial_count + 1),
                           .placement_noise_m = s->cfg.placement_noise_m,
                           .pose_noise_m = s->cfg.pose_noise_m};
  s->trial_count++;
  balance_status_t bs = balance_trial_run(s->world, s->obj, &rel, &noise, &s->trial);
  if (bs != BALANCE_OK) {
    s->phase = SIM_OBJ_REFUSED;
    set_error(s, ERR(ERR_FAULT), "release refused by the physics: %s", balance_status_str(bs));
    return;
  }
  pose_from_balance(&s->trial.released, &block_pose);
  placement_pose_mul(&s->plan.block_in_base, &block_pose, &s->rel_world);
  pose_from_balance(&s->trial.settled, &block_pose);
  placement_pose_mul(&s->plan.block_in_base, &block_pose, &s->set_world);
  s->trial_t0 = s->utime;
  s->trial_t1 = s->utime + (int64_t)s->trial.steps *
                               (int64_t)llround(balance_world_config(s->world)->dt_s * 1e6);
  if (s->trial_t1 <= s->trial_t0) s->trial_t1 = s->trial_t0 + 1;
  s->phase = SIM_OBJ_TRIAL;
}

/* ---- stepping ------------------------------------------------------------------------------ */

static void hold_here(sim_t *s) {
  for (int a = 0; a < 2; a++) {
    memcpy(s->q_target[a], s->q[a], sizeof s->q[a]);
    memset(s->qdot[a], 0, sizeof s->qdot[a]);
    s->width_target[a] = s->width[a];
  }
  s->motion_us = -1;
  s->in_position = 1;
}

int sim_step(sim_t *s) {
  const int playing = s->phase == SIM_OBJ_TRIAL && s->utime < s->trial_t1;
  s->utime += SIM_DT_US;
  int event = playing && s->utime >= s->trial_t1 ? SIM_EVENT_OBJECT : 0; /* it ends now */
  /* Expiry of the executing command: stop and hold (docs/messages.md). */
  if (s->state == ERR(STATE_POSITION) && s->utime >= s->active_expire_utime) {
    event |= SIM_EVENT_ARM;
    hold_here(s);
    s->state = ERR(STATE_HOLD);
    s->active_expire_utime = INT64_MAX;
    set_error(s, ERR(ERR_EXPIRED), "command seq %lld expired at utime %lld; holding",
              (long long)s->last_seq, (long long)s->utime);
  }
  if (s->motion_us >= 0) {
    const int64_t el = s->utime - s->motion_t0;
    const int done = el >= s->motion_us;
    const double f = done ? 1.0 : (double)el / (double)s->motion_us;
    const double tsec = (double)s->motion_us * 1e-6;
    for (int a = 0; a < 2; a++) {
      for (int k = 0; k < PLACEMENT_JOINTS; k++) {
        const double d = s->q_target[a][k] - s->q_start[a][k];
        s->q[a][k] = done ? s->q_target[a][k] : s->q_start[a][k] + f * d;
        s->qdot[a][k] = done || tsec <= 0.0 ? 0.0 : d / tsec;
      }
      s->width[a] = done ? s->width_target[a]
                         : s->width_start[a] + f * (s->width_target[a] - s->width_start[a]);
    }
    if (done) {
      s->motion_us = -1;
      s->in_position = 1;
      event |= SIM_EVENT_ARM;
    }
  }
  /* Gripper opened past the held width: the fingers let go. */
  if (s->phase == SIM_OBJ_HELD && s->width[s->held_arm] > s->held_width) object_release(s);

  /* Velocities and the rest window of the object, by differences over one tick. */
  placement_pose_t p;
  int moving;
  if (object_pose(s, &p, &moving)) {
    if (s->have_prev) {
      for (int i = 0; i < 3; i++)
        s->vel[i] = (p.pos_m[i] - s->pose_prev.pos_m[i]) / (SIM_DT_US * 1e-6);
      double w[3];
      rot_delta(&s->pose_prev, &p, w);
      for (int i = 0; i < 3; i++) s->omega[i] = w[i] / (SIM_DT_US * 1e-6);
    }
    const double vn = sqrt(s->vel[0] * s->vel[0] + s->vel[1] * s->vel[1] + s->vel[2] * s->vel[2]);
    const double wn =
        sqrt(s->omega[0] * s->omega[0] + s->omega[1] * s->omega[1] + s->omega[2] * s->omega[2]);
    s->quiet_ticks = (vn < 1e-3 && wn < 1e-2) ? s->quiet_ticks + 1 : 0;
    s->pose_prev = p;
    s->have_prev = 1;
  } else {
    s->have_prev = 0;
  }
  return event;
}

/* ---- commands ------------------------------------------------------------------------------ */

static const char *mode_str(int8_t m) {
  switch (m) {
    case COMLEARN_YUMI_COMMAND_T_MODE_HOLD: return "HOLD";
    case COMLEARN_YUMI_COMMAND_T_MODE_POSITION: return "POSITION";
    case COMLEARN_YUMI_COMMAND_T_MODE_STOP: return "STOP";
    default: return "?";
  }
}

static int32_t refuse(sim_t *s, int32_t code, const char *fmt, const char *detail) {
  s->n_rejected++;
  if (code >= 0 && code < (int32_t)(sizeof s->n_refused_by / sizeof s->n_refused_by[0]))
    s->n_refused_by[code]++;
  set_error(s, code, fmt, detail);
  return code;
}

/* The checks of a command before it is accepted, in order: sequence, expiry, mode, joint limits
 * and gripper widths, velocity scale, the stop latch. Returns 0, or the refusal's code (counted
 * and explained by refuse()). */
/* The time a POSITION command's straight line takes: its slowest axis at its limit x
 * velocity_scale (every axis arrives together). */
static double motion_time_s(const sim_t *s, const comlearn_yumi_command_t *c) {
  double t = 0.0;
  for (int a = 0; a < 2; a++) {
    for (int k = 0; k < PLACEMENT_JOINTS; k++)
      t = fmax(t, fabs(c->q_commanded_rad[a][k] - s->q[a][k]) /
                      (s->arm[a].velocity_rad_s[k] * c->velocity_scale));
    t = fmax(t, fabs(c->gripper_width_commanded_m[a] - s->width[a]) /
                    (SIM_GRIPPER_SPEED_M_S * c->velocity_scale));
  }
  return t;
}

/* Is the tool point of arm a at q inside the workspace box (B's frame)? *p_block: where it is. */
static int in_workspace(const sim_t *s, int a, const double q[PLACEMENT_JOINTS],
                        double p_block[3]) {
  placement_pose_t tip;
  if (placement_fk(&s->arm[a], q, &tip) != PLACEMENT_OK) return 0;
  const placement_pose_t *b = &s->base_in_block;
  for (int i = 0; i < 3; i++)
    p_block[i] = b->rot[i][0] * tip.pos_m[0] + b->rot[i][1] * tip.pos_m[1] +
                 b->rot[i][2] * tip.pos_m[2] + b->pos_m[i];
  const double m = s->cfg.workspace_margin_m, *sz = s->plan.block_size_m;
  return fabs(p_block[0]) <= 0.5 * sz[0] + m && fabs(p_block[1]) <= 0.5 * sz[1] + m &&
         p_block[2] >= -sz[2] - SIM_WORKSPACE_BELOW_M && p_block[2] <= SIM_WORKSPACE_ABOVE_M;
}

/* The first arm whose tool point leaves the workspace along a POSITION command's straight joint
 * line (SIM_WORKSPACE_SAMPLES points, the target last), or -1; p_block: where. */
static int workspace_leaving_arm(const sim_t *s, const comlearn_yumi_command_t *c,
                                 double p_block[3]) {
  for (int a = 0; a < 2; a++) {
    const int start_in = in_workspace(s, a, s->q[a], p_block);
    for (int k = start_in ? 1 : SIM_WORKSPACE_SAMPLES; k <= SIM_WORKSPACE_SAMPLES; k++) {
      const double f = (double)k / SIM_WORKSPACE_SAMPLES;
      double q[PLACEMENT_JOINTS];
      for (int j = 0; j < PLACEMENT_JOINTS; j++)
        q[j] = s->q[a][j] + f * (c->q_commanded_rad[a][j] - s->q[a][j]);
      if (!in_workspace(s, a, q, p_block)) return a;
    }
  }
  return -1;
}

static int32_t command_check(sim_t *s, const comlearn_yumi_command_t *c) {
  char d[SIM_TEXT_MAX];
  if (c->seq <= s->last_seq) {
    snprintf(d, sizeof d, "seq %lld <= last accepted %lld", (long long)c->seq,
             (long long)s->last_seq);
    return refuse(s, ERR(ERR_SEQ), "command refused: %s", d);
  }
  if (c->seq > s->last_seq + SIM_SEQ_MAX_JUMP) { /* last_seq grows by <= the jump: no overflow */
    snprintf(d, sizeof d, "seq %lld jumps more than %lld past the last accepted %lld",
             (long long)c->seq, (long long)SIM_SEQ_MAX_JUMP, (long long)s->last_seq);
    return refuse(s, ERR(ERR_SEQ), "command refused: %s", d);
  }
  if (s->utime >= c->expire_utime) {
    snprintf(d, sizeof d, "seq %lld stale: expire_utime %lld <= controller utime %lld",
             (long long)c->seq, (long long)c->expire_utime, (long long)s->utime);
    return refuse(s, ERR(ERR_STALE), "command refused: %s", d);
  }
  if (c->expire_utime > s->utime + SIM_EXPIRE_MAX_US) { /* the sim clock is small: no overflow */
    snprintf(d, sizeof d,
             "seq %lld: expire_utime %lld is more than %.0f s past controller utime %lld",
             (long long)c->seq, (long long)c->expire_utime, 1e-6 * (double)SIM_EXPIRE_MAX_US,
             (long long)s->utime);
    return refuse(s, ERR(ERR_INVALID), "command refused: %s", d);
  }
  if (c->mode != COMLEARN_YUMI_COMMAND_T_MODE_HOLD &&
      c->mode != COMLEARN_YUMI_COMMAND_T_MODE_POSITION &&
      c->mode != COMLEARN_YUMI_COMMAND_T_MODE_STOP) {
    snprintf(d, sizeof d, "seq %lld: unknown mode %d", (long long)c->seq, (int)c->mode);
    return refuse(s, ERR(ERR_INVALID), "command refused: %s", d);
  }
  for (int a = 0; a < 2; a++) {
    for (int k = 0; k < PLACEMENT_JOINTS; k++) {
      const double v = c->q_commanded_rad[a][k];
      if (!isfinite(v) || v < s->arm[a].lower_rad[k] || v > s->arm[a].upper_rad[k]) {
        snprintf(d, sizeof d, "seq %lld: q_commanded_rad[%d][%d] = %g %s [%g, %g]",
                 (long long)c->seq, a, k, v, isfinite(v) ? "outside" : "not finite, limits",
                 s->arm[a].lower_rad[k], s->arm[a].upper_rad[k]);
        return refuse(s, ERR(ERR_INVALID), "command refused: %s", d);
      }
    }
    const double w = c->gripper_width_commanded_m[a];
    if (!isfinite(w) || w < 0.0 || w > SIM_GRIPPER_MAX_M) {
      snprintf(d, sizeof d, "seq %lld: gripper_width_commanded_m[%d] = %g outside [0, %g]",
               (long long)c->seq, a, w, SIM_GRIPPER_MAX_M);
      return refuse(s, ERR(ERR_INVALID), "command refused: %s", d);
    }
  }
  if (c->mode == COMLEARN_YUMI_COMMAND_T_MODE_POSITION &&
      (!isfinite(c->velocity_scale) || c->velocity_scale < SIM_VELOCITY_SCALE_MIN ||
       c->velocity_scale > 1.0)) {
    snprintf(d, sizeof d, "seq %lld: velocity_scale %g outside [%g, 1]", (long long)c->seq,
             c->velocity_scale, SIM_VELOCITY_SCALE_MIN);
    return refuse(s, ERR(ERR_INVALID), "command refused: %s", d);
  }
  const double motion_s =
      c->mode == COMLEARN_YUMI_COMMAND_T_MODE_POSITION ? motion_time_s(s, c) : 0.0;
  if (!(motion_s <= SIM_MOTION_MAX_S)) {
    snprintf(d, sizeof d, "seq %lld: the motion would take %g s, over %g s", (long long)c->seq,
             motion_s, SIM_MOTION_MAX_S);
    return refuse(s, ERR(ERR_INVALID), "command refused: %s", d);
  }
  double p[3];
  const int leaving =
      c->mode == COMLEARN_YUMI_COMMAND_T_MODE_POSITION ? workspace_leaving_arm(s, c, p) : -1;
  if (leaving >= 0) {
    snprintf(d, sizeof d,
             "seq %lld: arm %d's tool would leave the workspace box around B, at (%.3f, %.3f, "
             "%.3f) m in B's frame (--workspace-margin-mm)",
             (long long)c->seq, leaving, p[0], p[1], p[2]);
    return refuse(s, ERR(ERR_INVALID), "command refused: %s", d);
  }
  if (c->mode == COMLEARN_YUMI_COMMAND_T_MODE_POSITION && s->stop_latched) {
    snprintf(d, sizeof d, "seq %lld: POSITION while stopped (send HOLD to clear)",
             (long long)c->seq);
    return refuse(s, ERR(ERR_STOPPED), "command refused: %s", d);
  }
  return 0;
}

/* HOLD or STOP (accepted): hold the current pose; STOP latches until a HOLD. */
static void command_hold(sim_t *s, const comlearn_yumi_command_t *c) {
  hold_here(s);
  s->active_expire_utime = INT64_MAX;
  if (c->mode == COMLEARN_YUMI_COMMAND_T_MODE_STOP) {
    s->stop_latched = 1;
    s->state = ERR(STATE_STOPPED);
  } else {
    s->stop_latched = 0;
    s->state = ERR(STATE_HOLD);
  }
}

/* POSITION (accepted): one straight line in joint and gripper space, timed by the slowest axis at
 * its limit x velocity_scale: every axis arrives together (the plan's linear joint
 * interpolation). A zero-length motion is in position at once. */
static void command_motion_start(sim_t *s, const comlearn_yumi_command_t *c) {
  s->state = ERR(STATE_POSITION);
  s->active_expire_utime = c->expire_utime;
  const double t = motion_time_s(s, c); /* <= SIM_MOTION_MAX_S (command_check) */
  for (int a = 0; a < 2; a++) {
    for (int k = 0; k < PLACEMENT_JOINTS; k++) {
      s->q_start[a][k] = s->q[a][k];
      s->q_target[a][k] = c->q_commanded_rad[a][k];
    }
    s->width_start[a] = s->width[a];
    s->width_target[a] = c->gripper_width_commanded_m[a];
  }
  s->motion_t0 = s->utime;
  s->motion_us = (int64_t)ceil(t * 1e6);
  s->in_position = 0;
  if (s->motion_us == 0) {
    for (int a = 0; a < 2; a++) {
      memcpy(s->q[a], s->q_target[a], sizeof s->q[a]);
      memset(s->qdot[a], 0, sizeof s->qdot[a]);
      s->width[a] = s->width_target[a];
    }
    s->motion_us = -1;
    s->in_position = 1;
  }
}

int32_t sim_command(sim_t *s, const comlearn_yumi_command_t *c) {
  const int32_t refused = command_check(s, c);
  if (refused != 0) return refused;
  /* Accepted: it replaces whatever was executing (latest command only). */
  s->last_seq = c->seq;
  s->last_seq_utime = c->utime;
  clear_error(s);
  (void)mode_str;
  if (c->mode != COMLEARN_YUMI_COMMAND_T_MODE_POSITION)
    command_hold(s, c);
  else
    command_motion_start(s, c);
  return 0;
}

/* ---- simulation control -------------------------------------------------------------------- */

static int32_t sc_done(sim_t *s, const comlearn_sim_control_t *c, int32_t result) {
  s->sc_seq_processed = c->seq;
  s->sc_ack_seq = c->seq;
  s->sc_ack_result = result;
  if (result != SC(SIM_CONTROL_APPLIED)) {
    s->n_rejected++;
    if (result > 0 && result < (int32_t)(sizeof s->n_sc_refused_by / sizeof s->n_sc_refused_by[0]))
      s->n_sc_refused_by[result]++;
  }
  return result;
}

void sim_refusals_str(const sim_t *s, char *buf, size_t size) {
  snprintf(buf, size,
           "commands refused: %lld seq, %lld stale, %lld invalid, %lld stopped; SIM_CONTROL not "
           "applied: %lld seq, %lld invalid, %lld load, %lld unknown id",
           (long long)s->n_refused_by[ERR(ERR_SEQ)], (long long)s->n_refused_by[ERR(ERR_STALE)],
           (long long)s->n_refused_by[ERR(ERR_INVALID)],
           (long long)s->n_refused_by[ERR(ERR_STOPPED)],
           (long long)s->n_sc_refused_by[SC(SIM_CONTROL_ERR_SEQ)],
           (long long)s->n_sc_refused_by[SC(SIM_CONTROL_ERR_INVALID)],
           (long long)s->n_sc_refused_by[SC(SIM_CONTROL_ERR_LOAD)],
           (long long)s->n_sc_refused_by[SC(SIM_CONTROL_ERR_UNKNOWN_ID)]);
}

/* A LOAD that lib/model refused: SIM_CONTROL_ERR_LOAD, and the reason in the status' error_text
 * (ERR_INVALID: the urdf_path field names no object the simulator can have). The loaded object,
 * if any, stays. */
static int32_t sc_load_refused(sim_t *s, const comlearn_sim_control_t *c, model_status_t ms,
                               const char *why) {
  set_error(s, ERR(ERR_INVALID), "SIM_CONTROL load of '%s' refused: %s (%s)", c->object_id,
            why[0] ? why : c->urdf_path, model_status_str(ms));
  return sc_done(s, c, SC(SIM_CONTROL_ERR_LOAD));
}

/* The URDF of a LOAD, canonical, inside the allowed folders (--object-dir); 0 refused, with a
 * reason in why. */
static int load_path_allowed(const sim_t *s, const char *urdf, char *canon, size_t canon_size,
                             char *why, size_t why_size) {
  char buf[PATH_MAX];
  if (realpath(urdf, buf) == NULL) {
    snprintf(why, why_size, "cannot open URDF %.300s: %s", urdf, strerror(errno));
    return 0;
  }
  if (!model_path_within(buf, s->cfg.object_dirs, s->cfg.object_dir_count)) {
    snprintf(why, why_size,
             "URDF %.300s is outside the folders this simulator may read (--object-dir)", buf);
    return 0;
  }
  snprintf(canon, canon_size, "%s", buf);
  return 1;
}

static void put_in_gripper(sim_t *s, const comlearn_sim_control_t *c) {
  s->held_arm = c->arm;
  s->held_width = c->gripper_width_m;
  placement_pose_from_wxyz(c->link_in_tool_position_m, c->link_in_tool_wxyz, &s->link_in_tool);
  /* The hand-over sets the fingers; a motion in progress keeps going for everything else. */
  s->width[c->arm] = s->width_target[c->arm] = s->width_start[c->arm] = c->gripper_width_m;
  s->phase = SIM_OBJ_HELD;
  s->have_prev = 0;
  s->quiet_ticks = 0;
  memset(s->vel, 0, sizeof s->vel);
  memset(s->omega, 0, sizeof s->omega);
}

int32_t sim_control(sim_t *s, const comlearn_sim_control_t *c) {
  if (c->seq <= s->sc_seq_processed || c->seq > s->sc_seq_processed + SIM_SEQ_MAX_JUMP) {
    /* Ignored: the acknowledgement keeps naming the last processed seq (so a restarted sender
     * resumes from it + 1), with ERR_SEQ as the result; so is a seq too far ahead (it would block
     * every later message). */
    s->sc_ack_result = SC(SIM_CONTROL_ERR_SEQ);
    s->n_rejected++;
    s->n_sc_refused_by[SC(SIM_CONTROL_ERR_SEQ)]++;
    return SC(SIM_CONTROL_ERR_SEQ);
  }
  const int act = c->action;
  if (act != COMLEARN_SIM_CONTROL_T_ACTION_LOAD && act != COMLEARN_SIM_CONTROL_T_ACTION_RESET &&
      act != COMLEARN_SIM_CONTROL_T_ACTION_REMOVE)
    return sc_done(s, c, SC(SIM_CONTROL_ERR_INVALID));
  const size_t idlen = strlen(c->object_id);
  if (idlen == 0 || idlen >= SIM_ID_MAX) return sc_done(s, c, SC(SIM_CONTROL_ERR_INVALID));
  if (act != COMLEARN_SIM_CONTROL_T_ACTION_REMOVE) {
    if (c->arm != 0 && c->arm != 1) return sc_done(s, c, SC(SIM_CONTROL_ERR_INVALID));
    if (!isfinite(c->gripper_width_m) || c->gripper_width_m < 0.0 ||
        c->gripper_width_m > SIM_GRIPPER_MAX_M)
      return sc_done(s, c, SC(SIM_CONTROL_ERR_INVALID));
    for (int i = 0; i < 3; i++)
      if (!isfinite(c->link_in_tool_position_m[i]) || fabs(c->link_in_tool_position_m[i]) > 1.0)
        return sc_done(s, c, SC(SIM_CONTROL_ERR_INVALID));
    placement_pose_t g;
    if (placement_pose_from_wxyz(c->link_in_tool_position_m, c->link_in_tool_wxyz, &g) !=
        PLACEMENT_OK)
      return sc_done(s, c, SC(SIM_CONTROL_ERR_INVALID));
  }
  if (act == COMLEARN_SIM_CONTROL_T_ACTION_LOAD) {
    if (c->urdf_path[0] == '\0') return sc_done(s, c, SC(SIM_CONTROL_ERR_INVALID));
    model_object_t mo;
    model_mass_t mass;
    model_error_t me = {{0}};
    char urdf[PATH_MAX];
    if (!load_path_allowed(s, c->urdf_path, urdf, sizeof urdf, me.msg, sizeof me.msg))
      return sc_load_refused(s, c, MODEL_E_NOFILE, me.msg);
    /* every mesh it names is checked against the folders before it is opened */
    model_status_t ms =
        model_object_load_within(urdf, NULL, s->cfg.object_dirs, s->cfg.object_dir_count, &mo, &me);
    if (ms != MODEL_OK) return sc_load_refused(s, c, ms, me.msg);
    ms = model_inertial_load(urdf, NULL, &mass, &me);
    if (ms == MODEL_OK && (ms = model_mass_plausible(&mass, &mo.mesh, &me)) != MODEL_OK) {
      char why[sizeof me.msg];
      memcpy(why, me.msg, sizeof why);
      /* the reason first: error_text holds SIM_TEXT_MAX bytes */
      snprintf(me.msg, sizeof me.msg, "%.300s (URDF %.180s <inertial>)", why, c->urdf_path);
    }
    if (ms != MODEL_OK) {
      model_object_free(&mo);
      return sc_load_refused(s, c, ms, me.msg);
    }
    balance_config_t bc;
    balance_config_default(&bc);
    memcpy(bc.base_size_m, s->plan.block_size_m, sizeof bc.base_size_m);
    balance_world_t *w = NULL;
    balance_object_t *o = NULL;
    balance_status_t bs = balance_world_create(&bc, &w);
    if (bs == BALANCE_OK) bs = balance_object_create(w, &mo.mesh, &mass, &o);
    if (bs != BALANCE_OK) {
      balance_world_destroy(w);
      model_object_free(&mo);
      set_error(s, ERR(ERR_INVALID), "SIM_CONTROL load of '%s' refused by the physics: %s",
                c->object_id, balance_status_str(bs));
      return sc_done(s, c, SC(SIM_CONTROL_ERR_LOAD));
    }
    object_unload(s);
    s->model = mo;
    s->mass = mass;
    s->world = w;
    s->obj = o;
    s->loaded = 1;
    memcpy(s->object_id, c->object_id, idlen + 1);
    put_in_gripper(s, c);
    return sc_done(s, c, SC(SIM_CONTROL_APPLIED));
  }
  if (!s->loaded || strcmp(c->object_id, s->object_id) != 0)
    return sc_done(s, c, SC(SIM_CONTROL_ERR_UNKNOWN_ID));
  if (act == COMLEARN_SIM_CONTROL_T_ACTION_RESET)
    put_in_gripper(s, c);
  else
    object_unload(s);
  return sc_done(s, c, SC(SIM_CONTROL_APPLIED));
}

void sim_undecodable(sim_t *s, const char *channel, const char *reason) {
  s->n_undecodable++;
  set_error(s, ERR(ERR_DECODE), "undecodable buffer on %s: %s", channel, reason);
}

void sim_received(sim_t *s) { s->n_received++; }

/* ---- outputs ------------------------------------------------------------------------------- */

void sim_status_fill(sim_t *s, comlearn_yumi_status_t *st) {
  memset(st, 0, sizeof *st);
  st->utime = s->utime;
  st->state = s->state;
  st->in_position = s->in_position && s->motion_us < 0;
  st->last_accepted_seq = s->last_seq;
  st->last_accepted_utime = s->last_seq_utime;
  memcpy(st->q_measured_rad, s->q, sizeof s->q);
  memcpy(st->qdot_estimated_rad_s, s->qdot, sizeof s->qdot);
  memcpy(st->q_commanded_rad, s->q_target, sizeof s->q_target);
  memcpy(st->gripper_width_measured_m, s->width, sizeof s->width);
  memcpy(st->gripper_width_commanded_m, s->width_target, sizeof s->width_target);
  st->error_code = s->error_code;
  st->error_text = s->error_text;
  st->messages_received = s->n_received;
  st->messages_rejected = s->n_rejected;
  st->messages_undecodable = s->n_undecodable;
}

void sim_object_fill(sim_t *s, comlearn_object_state_t *os) {
  memset(os, 0, sizeof *os);
  os->utime = s->utime;
  os->object_id = s->object_id;
  os->sim_control_seq = s->sc_ack_seq;
  os->sim_control_result = s->sc_ack_result;
  os->orientation_measured_wxyz[0] = 1.0;
  placement_pose_t p;
  int moving;
  if (!s->loaded || !object_pose(s, &p, &moving)) return;
  os->tracked = 1;
  model_pose_t b;
  pose_to_balance(&p, &b);
  memcpy(os->position_measured_m, b.position_m, sizeof b.position_m);
  memcpy(os->orientation_measured_wxyz, b.orientation_wxyz, sizeof b.orientation_wxyz);
  memcpy(os->velocity_estimated_m_s, s->vel, sizeof s->vel);
  memcpy(os->omega_estimated_rad_s, s->omega, sizeof s->omega);
  switch (s->phase) {
    case SIM_OBJ_HELD:
      os->at_rest = s->quiet_ticks >= SIM_REST_TICKS;
      os->on_base = 0;
      break;
    case SIM_OBJ_REFUSED:
      os->at_rest = 0;
      os->on_base = 0;
      break;
    case SIM_OBJ_TRIAL:
      if (s->utime < s->trial_t1) {
        os->at_rest = 0;
        os->on_base = 1;
      } else {
        /* After the trial: STAYS rests on B; TIPS has gone over the edge (B's world has no floor,
         * so it is reported off B and not at rest); SLIDES / INVALID: on B while the CoM is over
         * B's top. */
        placement_pose_t blk;
        pose_from_balance(&s->trial.settled, &blk);
        double com[3];
        for (int i = 0; i < 3; i++) {
          com[i] = blk.pos_m[i];
          for (int j = 0; j < 3; j++) com[i] += blk.rot[i][j] * s->mass.com_m[j];
        }
        const int over = fabs(com[0]) <= 0.5 * s->plan.block_size_m[0] &&
                         fabs(com[1]) <= 0.5 * s->plan.block_size_m[1];
        const balance_outcome_t o = s->trial.outcome;
        os->at_rest = o == BALANCE_STAYS;
        os->on_base = o == BALANCE_STAYS || (o != BALANCE_TIPS && over);
        if (o == BALANCE_STAYS) {
          memset(os->velocity_estimated_m_s, 0, sizeof os->velocity_estimated_m_s);
          memset(os->omega_estimated_rad_s, 0, sizeof os->omega_estimated_rad_s);
        }
      }
      break;
    case SIM_OBJ_NONE: break;
  }
}
