/*
 * comlearn/placement_plan.h - placement plans: the object pose the learner wants on block B,
 * turned into the joint targets one YuMi arm executes (pre-place, place, open, retreat).
 *
 * Frames (metres, radians, seconds; poses are "child in parent", x_parent = rot * x_child + pos):
 *   base   yumi_body (ABB world / wobj0): x forward, y to the robot's left, z up.
 *   block  B's frame = the balance world of lib/balance (docs/physics.md): origin at the centre of
 *          B's top face, top at z = 0, B filling |x| <= sx/2, |y| <= sy/2, z in [-sz, 0], its
 *          four top edges along the block's x and y axes. cfg.block_in_base places it in front of
 *          the robot (placement_plan_config_default: docs/placement.md says where and why).
 *   tcp    the arm's tool point (placement.h: yumi_tcp_{l,r} = ABB tool0 + 0.1142 m along z,
 *          ABB's SmartGripper finger TCP). The fingers close along the tcp's x axis.
 *   link   the object's URDF link frame (lib/model: its mesh is in this frame).
 *
 * A plan is four waypoints, each one arm's 7 joint targets (chain order, placement.h), the
 * gripper opening and the time to reach it from the previous waypoint (from q_start for the
 * first):
 *   PREPLACE  the object preplace_height_m above the place pose (block z), still held
 *   PLACE     the object touching B's top: the link point and orientation the learner asked for,
 *             the height computed exactly from the mesh (placement_plan_touch_z)
 *   RELEASE   same joints, the gripper opened by release_opening_m
 *   RETREAT   the tcp retreat_height_m straight up (block z) from where it let go
 * The controller moves in joint space between waypoints (linear joint interpolation over
 * duration_s); PREPLACE and RETREAT are followed from PLACE along the vertical line in small IK
 * steps, so consecutive targets stay on one IK branch.
 *
 * Memory: nothing here allocates; every struct is caller-owned with no pointers inside except the
 * borrowed mesh of a request. Thread safety: functions touch only their arguments. Nothing prints.
 */
#ifndef COMLEARN_PLACEMENT_PLAN_H
#define COMLEARN_PLACEMENT_PLAN_H

#include <stddef.h>

#include "comlearn/model.h"
#include "comlearn/model_support.h"
#include "comlearn/placement.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The gripper as boxes in the tcp frame, for the check against B (ABB SmartGripper, servo
 * module; numbers from the kinematics reference, see docs/placement.md):
 *   finger: the finger on the +x side spans x in [w/2, w/2 + finger_thickness_m] at opening w;
 *           the other mirrors it (x -> -x). Both span y in [-finger_half_depth_m, +...] and
 *           z in [finger_z_lo_m, finger_z_hi_m]. Defaults: 0.01089, 0.011, -0.0305, +0.0217
 *           (the finger mesh of [O]; tips 21.7 mm beyond the tcp).
 *   housing: the box [housing_lo_m, housing_hi_m]. Default x +-0.0635, y -0.025..+0.040,
 *           z -0.1142..-0.0305 (tool0 to the finger base; x, y an assumed envelope: the vacuum
 *           tool frames sit at x +-63.5 mm, the camera at y +28.3 mm; no ABB drawing was found). */
typedef struct {
  double finger_thickness_m;
  double finger_half_depth_m;
  double finger_z_lo_m;
  double finger_z_hi_m;
  double housing_lo_m[3];
  double housing_hi_m[3];
} placement_gripper_t;

/* Plan settings: fill with placement_plan_config_default() and change what you need. */
typedef struct {
  placement_pose_t block_in_base; /* B's frame in yumi_body; default rot identity, pos
                                     (0.40, 0, 0): B standing on YuMi's table, docs/placement.md */
  double block_size_m[3];         /* B's extent x, y, z; default 0.30, 0.30, 0.10 (lib/balance) */
  double preplace_height_m;       /* PREPLACE above PLACE along block z; default 0.05, [0, 0.5] */
  double retreat_height_m;        /* RETREAT above RELEASE along block z; default 0.05, [0, 0.5] */
  double touch_depth_m;           /* the lowest point over B this far below the top; default 0
                                     (exactly touching), [0, 1e-4] (lib/balance trials use 1e-6) */
  double velocity_fraction;       /* joints move at most this fraction of their URDF velocity
                                     limit; default 0.25, (0, 1] */
  double min_duration_s;          /* no segment shorter; default 0.1, [0, 60] */
  double gripper_speed_m_s;       /* opening speed (ABB's MAX_SPEED 25 mm/s); default 0.025, > 0 */
  double release_opening_m;       /* RELEASE width = grip width + this; default 0.01, [0, 0.05] */
  double gripper_max_width_m;     /* largest opening; default 0.05, comlearn-sim's limit (the
                                     URDF's fingers travel 0.0125 m each, 0.025 m in all, ABB's
                                     software cap: see docs/placement.md) */
  double clearance_m;             /* the gripper boxes must stay this far from B (B's box grown by
                                     it on every side); default 0.002, [0, 0.1] */
  unsigned approach_steps;        /* PREPLACE and RETREAT are solved along the straight tcp line
                                     up from PLACE in this many steps, each IK seeded from the
                                     step before; default 5 (1 cm), [1, 100] */
  unsigned branch_attempts;       /* PLACE solves (start postures) tried until both lines can be
                                     followed; default 8, [1, 64] */
  double max_joint_step_rad;      /* every such step must stay within this of the one before on
                                     every joint (else IK changed branch); default 0.5, > 0 */
  placement_gripper_t gripper;
  placement_ik_config_t ik; /* default PLACEMENT_IK_CONFIG_INIT */
} placement_plan_config_t;

/* Fill cfg with the defaults documented above. */
void placement_plan_config_default(placement_plan_config_t *cfg);

/* Check every field: PLACEMENT_E_ARG (NULL, out of range), PLACEMENT_E_NONFINITE,
 * PLACEMENT_E_ROTATION (block_in_base.rot not a rotation within 1e-6). */
placement_status_t placement_plan_config_check(const placement_plan_config_t *cfg);

/* What the learner asks for. */
typedef struct {
  const model_mesh_t *mesh_link;    /* the object's mesh, link frame (borrowed, read only) */
  placement_pose_t object_in_tcp;   /* the grasp: object link frame in the tcp frame */
  placement_pose_t object_in_block; /* the wanted pose on B (e.g. balance_pose_over_edge's,
                                        converted with placement_pose_from_wxyz). Its x, y and
                                        rot are kept; its z is replaced by the exact touching
                                        height (placement_plan_touch_z) */
  double grip_width_m;              /* gripper opening while holding, [0, gripper_max_width_m] */
  double q_start_rad[PLACEMENT_JOINTS]; /* the arm's joints now: first IK seed and the start of
                                           the first segment; within the arm's limits */
} placement_plan_request_t;

typedef enum {
  PLACEMENT_WAYPOINT_PREPLACE = 0,
  PLACEMENT_WAYPOINT_PLACE = 1,
  PLACEMENT_WAYPOINT_RELEASE = 2,
  PLACEMENT_WAYPOINT_RETREAT = 3
} placement_waypoint_kind_t;

enum { PLACEMENT_PLAN_WAYPOINTS = 4 };

typedef struct {
  placement_waypoint_kind_t kind;
  double q_rad[PLACEMENT_JOINTS]; /* joint targets, chain order */
  double gripper_width_m;         /* finger opening at this waypoint */
  double duration_s;              /* time to reach it from the previous waypoint (q_start, grip
                                     width): max(min_duration_s, max_k |dq_k| / (velocity_fraction
                                     * velocity_rad_s[k]), |d width| / gripper_speed_m_s) */
  placement_pose_t tcp_in_base;   /* the tcp pose IK solved for (FK(q) within cfg.ik's tolerance) */
} placement_waypoint_t;

typedef struct {
  placement_waypoint_t waypoints[PLACEMENT_PLAN_WAYPOINTS]; /* in execution order (kind = index) */
  placement_pose_t object_in_block; /* the place pose planned: the request's x, y, rot and the
                                       touching z */
  double total_duration_s;          /* sum of the waypoints' durations */
  unsigned ik_iterations;           /* summed over the three IK solves (diagnostics) */
} placement_plan_t;

/* Convert a position and a quaternion (w, x, y, z), e.g. a model_pose_t's fields, to a pose.
 * The quaternion is normalised; PLACEMENT_E_ROTATION when its norm is off 1 by more than 1e-6,
 * PLACEMENT_E_NONFINITE, PLACEMENT_E_ARG (NULL). *out is unchanged on error. */
placement_status_t placement_pose_from_wxyz(const double position_m[3],
                                            const double orientation_wxyz[4],
                                            placement_pose_t *out);

/* The block-frame z of the link origin that sets the mesh down on B's top in the orientation
 * object_in_block->rot (link in block) with its link origin at block x, y =
 * object_in_block->pos_m[0], [1] (pos_m[2] is ignored), so that its lowest point over B's top face
 * is touch_depth_m below z = 0. "Over B's top": the mesh surface above the rectangle
 * |x| <= sx/2, |y| <= sy/2, i.e. B lowered onto as a solid box, as balance_pose_over_edge does.
 * Exact (no iteration, no tolerance): vertices over the top, mesh edges crossing the four edge
 * planes within the top, and the top's corners under a triangle are all visited. O(triangles).
 * PLACEMENT_E_ARG (NULL, empty mesh, an index out of range, block size or touch depth out of
 * range), PLACEMENT_E_NONFINITE, PLACEMENT_E_GEOMETRY (no part of the mesh over B's top: it would
 * not rest on B). *z_m is unchanged on error. */
placement_status_t placement_plan_touch_z(const model_mesh_t *mesh_link,
                                          const placement_pose_t *object_in_block,
                                          const double block_size_m[3], double touch_depth_m,
                                          double *z_m);

/* 1 when the gripper at opening width_m with its tcp at tcp_in_block stays clearance_m clear of
 * B (exact box-box separating-axis test against B grown by clearance_m), 0 when it does not or
 * for NULL. */
int placement_plan_gripper_clear(const placement_plan_config_t *cfg,
                                 const placement_pose_t *tcp_in_block, double width_m);

/* Plan one placement with `arm` (placement_arm_load_yumi for the arm holding the object).
 * Checks, in this order, before any IK (no command comes out of a bad request):
 *   PLACEMENT_E_ARG        NULL arm / cfg / req / out / mesh, bad cfg, an empty mesh or an index
 *                          out of range, grip width outside [0, gripper_max_width_m - opening]
 *   PLACEMENT_E_NONFINITE  a non-finite pose, joint, width or vertex
 *   PLACEMENT_E_ROTATION   a pose whose rot is not a rotation within 1e-6
 *   PLACEMENT_E_LIMITS     q_start outside the arm's limits
 *   PLACEMENT_E_GEOMETRY   no part of the object over B's top
 *   PLACEMENT_E_COLLISION  the gripper (placement_plan_gripper_clear) would reach into B at any
 *                          waypoint (the held object itself touches by design)
 * then IK (placement.h's placement_ik): PLACE from q_start (the full solver, random restarts
 * allowed), then PREPLACE and RETREAT along the straight vertical tcp line up from PLACE in
 * approach_steps steps, each seeded from the step before. When a line cannot be followed on
 * PLACE's branch, PLACE is solved again from another start posture (random within the limits,
 * from cfg.ik.rng_seed: deterministic), at most branch_attempts times in all:
 *   PLACEMENT_E_OUT_OF_REACH, PLACEMENT_E_NO_SOLUTION  PLACE unreachable (from placement_ik), or
 *                          PLACEMENT_E_NO_SOLUTION when no attempt gave a followable line (a
 *                          step failed or moved a joint by more than max_joint_step_rad).
 * The gripper is checked at the four waypoints only: on the vertical lines between them its
 * footprint over B does not change, so the lowest end decides (the controller interpolates in
 * joint space, which stays within a few mm of the line for 1 cm steps, not checked here).
 * *out is written only on PLACEMENT_OK (untouched otherwise); err (may be NULL) names the failing
 * waypoint. No allocation; 1 + 2 x approach_steps IK solves per attempt (11 by default). */
placement_status_t placement_plan_build(const placement_arm_t *arm,
                                        const placement_plan_config_t *cfg,
                                        const placement_plan_request_t *req, placement_plan_t *out,
                                        placement_error_t *err);

/* ---- top-down grasps: which arm, which finger yaw, and the plan (placement_grasp_plan) ---- */

/* How placement_grasp_plan holds the object. Fill with placement_grasp_config_default() or
 * PLACEMENT_GRASP_CONFIG_INIT and change what you need. */
typedef struct {
  double depth_m;      /* the tcp this far below the top of the object's box (block z);
                            default 0.010, [0, 0.5] */
  double tip_length_m; /* the finger tips this far beyond the tcp along tcp z; default 0.0217
                            (the figure comlearn's LCM backend always used; cfg.gripper's
                            finger_z_hi_m is 0.02168) [0, 0.5] */
  double tip_clear_m;  /* the tips at least this far above B's top: the tcp never lower than
                            tip_length_m + tip_clear_m (block z); default 0.004, [0, 0.5] */
  double min_width_m;  /* narrowest opening while holding; default 0.005, [0, 0.2] */
} placement_grasp_config_t;

#define PLACEMENT_GRASP_CONFIG_INIT \
  { .depth_m = 0.010, .tip_length_m = 0.0217, .tip_clear_m = 0.004, .min_width_m = 0.005 }

/* Fill cfg with PLACEMENT_GRASP_CONFIG_INIT. */
void placement_grasp_config_default(placement_grasp_config_t *cfg);

/* What to place, and the arms' joints now. */
typedef struct {
  const model_mesh_t *mesh_link;           /* the object's mesh, link frame (borrowed) */
  model_pose_t object_in_block;            /* the release pose: the link frame in B's frame
                                               (position, unit quaternion w, x, y, z), touching
                                               B as lib/model's model_pose_over_edge makes it */
  double q_start_rad[2][PLACEMENT_JOINTS]; /* each arm's joints now, indexed by
                                               placement_side_t (LEFT 0, RIGHT 1) */
} placement_grasp_request_t;

/* A grasp and the plan that places with it. */
typedef struct {
  placement_side_t side;                  /* the arm that holds the object */
  double yaw_rad;                         /* finger yaw about block z: the fingers close along
                                      (cos yaw, sin yaw, 0) of B's frame */
  double grip_width_m;                    /* opening while holding */
  placement_pose_t tcp_in_block;          /* the nominal tcp pose at the release pose: straight down
                                      (tcp z = -block z), tcp x along the closing direction */
  placement_pose_t object_in_tcp_nominal; /* the grasp planned with: tcp_in_block^-1 * release */
  cl_pose_t object_in_tcp;                /* the grasp to hand the gripper (or a simulator):
                                      G = FK(q_place)^-1 * block_in_base * release, which differs
                                      from the nominal grasp by the IK error only (< 1e-8) and
                                      makes FK(q_place) * G equal the release pose (in yumi_body)
                                      to rounding (~1e-16 m) instead of IK's 1e-9 m; w >= 0 */
  placement_plan_t plan;                  /* placement_plan_build's plan for side with this grasp */
  unsigned attempts;                      /* (arm, yaw) pairs tried, 1..8 */
} placement_grasp_t;

/* Choose a top-down grasp for the release pose req->object_in_block and plan the placement with
 * it. The tcp points straight down (block -z) over the centre of the object's footprint (the
 * block-frame axis-aligned box of the mesh at the release pose), gcfg->depth_m below the box's
 * top but never lower than gcfg->tip_length_m + gcfg->tip_clear_m above B's top. The fingers
 * close along the yawed block x; the opening is the box's extent along that direction,
 * clamped to [min_width_m, gripper_max_width_m - release_opening_m]. Tried in this order until
 * placement_plan_build succeeds: the right arm with finger yaws 0, 90, -90, 180 degrees, then the
 * left arm with the same yaws. arms[side] is the arm of that side (placement_arm_load_yumi),
 * started from req->q_start_rad[side].
 * Returns PLACEMENT_OK with *out filled, or:
 *   PLACEMENT_E_ARG        NULL arms / cfg / gcfg / req / out / mesh, an empty mesh, gcfg out of
 *                          range, bad cfg (placement_plan_config_check)
 *   PLACEMENT_E_NONFINITE, PLACEMENT_E_ROTATION  the release pose or a vertex (as
 *                          placement_pose_from_wxyz)
 *   any status of placement_plan_build  no (arm, yaw) planned: the last attempt's status (err
 *                          holds the last message placement_plan_build wrote), e.g.
 *                          PLACEMENT_E_OUT_OF_REACH when the pose is beyond both arms
 * *out is written only on PLACEMENT_OK. err may be NULL. No allocation; up to 8
 * placement_plan_build calls. Thread safety: touches only its arguments. */
placement_status_t placement_grasp_plan(const placement_arm_t arms[2],
                                        const placement_plan_config_t *cfg,
                                        const placement_grasp_config_t *gcfg,
                                        const placement_grasp_request_t *req,
                                        placement_grasp_t *out, placement_error_t *err);

/* A static English name of a waypoint kind ("preplace", "place", "release", "retreat"). */
const char *placement_waypoint_kind_str(placement_waypoint_kind_t kind);

#ifdef __cplusplus
}
#endif

#endif /* COMLEARN_PLACEMENT_PLAN_H */
