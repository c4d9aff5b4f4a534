/*
 * daemon/sim.h - comlearn-sim's controller and world, without LCM: a kinematic YuMi that tracks
 * the latest accepted command, an object held in a gripper, and lib/balance for the physics after
 * release. main.c turns LCM messages into these calls; docs/sim.md describes the behaviour.
 *
 * Clock: sim->utime [us], advanced only by sim_step() (SIM_DT_US per call). It is the clock of
 * yumi_status_t.utime and of yumi_command_t.expire_utime.
 * Frames: "world" of the messages = yumi_body (the YuMi URDF has no world link); B stands at
 * placement_plan_config_default()'s block_in_base; lib/balance works in B's frame ("block").
 * Memory: sim_create allocates (arm models, balance world); a load allocates (mesh, world). Not
 * thread safe: one thread owns a sim_t. Nothing prints; failures are written to err buffers.
 */
#ifndef COMLEARN_DAEMON_SIM_H
#define COMLEARN_DAEMON_SIM_H

#include <stddef.h>
#include <stdint.h>

#include "comlearn/balance.h"
#include "comlearn/comlearn_object_state_t.h"
#include "comlearn/comlearn_sim_control_t.h"
#include "comlearn/comlearn_yumi_command_t.h"
#include "comlearn/comlearn_yumi_status_t.h"
#include "comlearn/model.h"
#include "comlearn/placement.h"
#include "comlearn/placement_plan.h"

enum {
  SIM_DT_US = 1000,            /* controller tick [us] */
  SIM_STATUS_PERIOD_US = 4000, /* YUMI_STATUS / OBJECT_STATE every 4 ms of the sim clock (250 Hz) */
  SIM_FAST_BATCH = 32,         /* as fast as possible: ticks between two reads of LCM */
  SIM_REST_TICKS = 20,         /* at_rest of a held object: quiet for this many ticks */
  SIM_TEXT_MAX = 512,
  SIM_ID_MAX = 128
};

/* Largest gap between the released object's lowest point over B and B's top, either way
 * (above: it would drop; below: it starts inside B). Equal to lib/balance's start-depth limit. */
#define SIM_RELEASE_MAX_GAP_M 1e-4
/* Gripper opening speed limit [m/s] (ABB SmartGripper MAX_SPEED, as placement plans assume). */
#define SIM_GRIPPER_SPEED_M_S 0.025
#define SIM_GRIPPER_MAX_M 0.05
/* Joint positions within this of the target count as reached. */
#define SIM_POS_TOL_RAD 1e-12
/* The safety envelope of a command (docs/sim.md, docs/security.md): its seq at most
 * SIM_SEQ_MAX_JUMP past the last accepted (a sender resumes from YUMI_STATUS.last_accepted_seq;
 * one message with seq INT64_MAX would otherwise block every later command), its expiry at most
 * SIM_EXPIRE_MAX_US ahead of the controller clock (no command that never expires), its
 * velocity_scale at least SIM_VELOCITY_SCALE_MIN and its motion at most SIM_MOTION_MAX_S long.
 * SIM_CONTROL's seq has the same jump bound. */
#define SIM_SEQ_MAX_JUMP ((int64_t)1 << 20)
#define SIM_EXPIRE_MAX_US ((int64_t)60000000)
#define SIM_VELOCITY_SCALE_MIN 1e-3
#define SIM_MOTION_MAX_S 120.0
/* The workspace of POSITION commands: the box over B's footprint grown by
 * sim_config_t.workspace_margin_m on every side, from SIM_WORKSPACE_BELOW_M under B's bottom to
 * SIM_WORKSPACE_ABOVE_M over its top (B's frame: top at z = 0). The tool point (each arm's FK tip)
 * must stay inside along the whole straight joint line of a command, checked at
 * SIM_WORKSPACE_SAMPLES points; from a start outside the box only the target must be inside. */
#define SIM_WORKSPACE_BELOW_M 0.05
#define SIM_WORKSPACE_ABOVE_M 0.60
#define SIM_WORKSPACE_MARGIN_DEFAULT_M 0.35
enum { SIM_WORKSPACE_SAMPLES = 16 };

enum { SIM_OBJECT_DIRS_MAX = 16 };

typedef struct {
  const char *yumi_urdf;    /* assets/yumi/yumi.urdf */
  uint64_t seed;            /* placement / pose noise stream */
  double placement_noise_m; /* [0, 0.1] */
  double pose_noise_m;      /* [0, 0.1] */
  /* The folders a SIM_CONTROL LOAD may read a URDF from (and its meshes: the first one is
   * checked), each with everything below it; existing folders, resolved at sim_init. None: any
   * file (the library's default; comlearn-sim passes --object-dir or its defaults). */
  const char *object_dirs[SIM_OBJECT_DIRS_MAX];
  size_t object_dir_count;
  double workspace_margin_m; /* the workspace box around B (SIM_WORKSPACE_*); [0, 10] */
} sim_config_t;

typedef enum { SIM_OBJ_NONE = 0, SIM_OBJ_HELD, SIM_OBJ_TRIAL, SIM_OBJ_REFUSED } sim_obj_phase_t;

typedef struct {
  sim_config_t cfg;
  char object_dir[SIM_OBJECT_DIRS_MAX][4096]; /* cfg.object_dirs, canonical (realpath) */
  placement_arm_t arm[2];
  placement_plan_config_t plan; /* block_in_base, block size */
  placement_pose_t base_in_block;

  int64_t utime;
  /* controller */
  int8_t state;
  int stop_latched;
  int in_position;
  int64_t last_seq, last_seq_utime;
  int64_t active_expire_utime; /* INT64_MAX when nothing can expire */
  double q[2][PLACEMENT_JOINTS], qdot[2][PLACEMENT_JOINTS], q_target[2][PLACEMENT_JOINTS];
  double width[2], width_target[2];
  /* current motion: straight line in (q, width) from start to target over motion_us */
  double q_start[2][PLACEMENT_JOINTS], width_start[2];
  int64_t motion_t0, motion_us; /* motion_us < 0: no motion */
  int32_t error_code;
  char error_text[SIM_TEXT_MAX];
  int64_t n_received, n_rejected, n_undecodable;
  int64_t n_refused_by[8];    /* refused commands by their ERR_* code (n_rejected counts all) */
  int64_t n_sc_refused_by[5]; /* SIM_CONTROL messages not applied, by SIM_CONTROL_ERR_* result */

  /* object */
  int loaded;
  char object_id[SIM_ID_MAX];
  model_object_t model;
  model_mass_t mass; /* the truth: the simulator alone reads it */
  balance_world_t *world;
  balance_object_t *obj;
  sim_obj_phase_t phase;
  int held_arm;
  double held_width;
  placement_pose_t link_in_tool;
  placement_pose_t pose_prev; /* world (yumi_body), last tick: for velocities */
  int have_prev;
  double vel[3], omega[3];
  int quiet_ticks;
  /* trial: released / settled poses in world, playback on the sim clock */
  balance_trial_result_t trial;
  placement_pose_t rel_world, set_world;
  int64_t trial_t0, trial_t1;
  uint64_t trial_count;
  int64_t sc_seq_processed;
  int64_t sc_ack_seq;
  int32_t sc_ack_result;
} sim_t;

/* Load both arms, set the start posture (YuMi nominal, grippers closed), HOLD, clock 0.
 * 0 on success; -1 with err filled. */
int sim_init(sim_t *sim, const sim_config_t *cfg, char *err, size_t err_len);
void sim_fini(sim_t *sim);

/* The refusals by reason, one line for the log: "commands refused: N seq, N stale, N invalid,
 * N stopped; SIM_CONTROL not applied: N seq, N invalid, N load, N unknown id". */
void sim_refusals_str(const sim_t *sim, char *buf, size_t size);

/* 1 while something moves on the sim clock (arm or gripper motion, a trial playing out). */
int sim_busy(const sim_t *sim);

/* What a step changed that a client waits for (sim_step's result, a mask): the daemon publishes
 * at once what it names. */
enum {
  SIM_EVENT_ARM = 1,   /* the arms came into position or a command expired: YUMI_STATUS, and
                        * OBJECT_STATE (where the motion left the object) */
  SIM_EVENT_OBJECT = 2 /* a trial's outcome became final: OBJECT_STATE */
};

/* Advance the clock by SIM_DT_US: track, expire, release, play out a trial. Returns the events
 * of the step (SIM_EVENT_*), 0 when none. */
int sim_step(sim_t *sim);

/* Apply the acceptance rules of docs/messages.md to a decoded command. 0 accepted, else the
 * ERR_* code it was refused with (also in the status). */
int32_t sim_command(sim_t *sim, const comlearn_yumi_command_t *cmd);

/* Process a SIM_CONTROL message; returns its SIM_CONTROL_* result (also in OBJECT_STATE). */
int32_t sim_control(sim_t *sim, const comlearn_sim_control_t *sc);

/* Count an undecodable buffer on `channel` (reason: comlearn_msg_status_str text). */
void sim_undecodable(sim_t *sim, const char *channel, const char *reason);
/* Count a decoded message. */
void sim_received(sim_t *sim);

/* Fill the outgoing messages. The strings point into sim (valid until the next call). */
void sim_status_fill(sim_t *sim, comlearn_yumi_status_t *st);
void sim_object_fill(sim_t *sim, comlearn_object_state_t *os);

#endif /* COMLEARN_DAEMON_SIM_H */
