/*
 * comlearn/placement.h - YuMi (ABB IRB 14000) arm model, forward and inverse kinematics.
 *
 * An arm is the serial chain of one URDF from a base link to a tip link (for YuMi:
 * PLACEMENT_YUMI_BASE_LINK to PLACEMENT_YUMI_TCP_LEFT / _RIGHT of assets/yumi/yumi.urdf), loaded
 * through lib/model (comlearn/model_chain.h); nothing of the geometry is hard-coded here. The chain
 * must hold exactly PLACEMENT_JOINTS revolute joints; fixed joints are folded into the transforms.
 *
 * Units and frames: metres, radians, seconds. Poses are "child in parent":
 * x_parent = rot * x_child + pos_m. FK and IK poses are the tip link (the TCP) in the base link
 * (yumi_body = ABB world / wobj0; x forward, y to the robot's left, z up).
 *
 * Joint order: q_rad[k], k = 0..6, is the chain order from the body outwards. For YuMi this is
 * ABB axes 1, 2, 7, 3, 4, 5, 6 (URDF joints yumi_joint_{1,2,7,3,4,5,6}_{l,r}); q_rad[2] is ABB
 * axis 7, the upper-arm roll that carries the redundancy. placement_abb_from_chain() and
 * placement_chain_from_abb() convert.
 *
 * Memory: no function here allocates, except placement_arm_load() (temporarily, inside urdfdom).
 * placement_arm_t is a plain caller-owned struct with no pointers: copy it freely.
 * Thread safety: every function touches only its arguments; a loaded arm may be shared read-only
 * between threads. Nothing prints.
 */
#ifndef COMLEARN_PLACEMENT_H
#define COMLEARN_PLACEMENT_H

#include <stddef.h>
#include <stdint.h>

#include "comlearn/math3d.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One status enum for the module (kinematics and plans): 0 is success, negative values errors. */
typedef enum {
  PLACEMENT_OK = 0,
  PLACEMENT_E_ARG = -1,          /* NULL pointer, bad option (tolerance <= 0, zero caps, ...) */
  PLACEMENT_E_NONFINITE = -2,    /* a NaN or infinite number in the input */
  PLACEMENT_E_MODEL = -3,        /* the URDF chain could not be loaded or is not a 7R arm */
  PLACEMENT_E_LIMITS = -4,       /* joint values outside the joint limits */
  PLACEMENT_E_OUT_OF_REACH = -5, /* IK: the target position is provably beyond the arm's reach */
  PLACEMENT_E_NO_SOLUTION = -6,  /* IK: no seed converged within limits and iteration caps (the
                                    pose is unreachable, or too close to the workspace boundary) */
  PLACEMENT_E_ROTATION = -7,     /* a rotation matrix that is not orthonormal with det +1 */
  PLACEMENT_E_COLLISION = -8,    /* plans: the gripper or object would penetrate the block B */
  PLACEMENT_E_GEOMETRY = -9      /* plans: object / block geometry unusable */
} placement_status_t;

/* A static English description of a status; never NULL. */
const char *placement_status_str(placement_status_t status);

/* Caller-owned buffer for a readable error detail (names the file, link or joint). Functions
 * taking `placement_error_t *err` accept NULL and write a message on failure only. */
typedef struct {
  char msg[512];
} placement_error_t;

/* Rigid transform, child frame in parent frame: x_parent = rot * x_child + pos_m. */
typedef struct {
  double rot[3][3];
  double pos_m[3];
} placement_pose_t;

enum { PLACEMENT_JOINTS = 7, PLACEMENT_NAME_MAX = 128 };

typedef enum { PLACEMENT_ARM_LEFT = 0, PLACEMENT_ARM_RIGHT = 1 } placement_side_t;

#define PLACEMENT_YUMI_BASE_LINK "yumi_body"
#define PLACEMENT_YUMI_TCP_LEFT "yumi_tcp_l"
#define PLACEMENT_YUMI_TCP_RIGHT "yumi_tcp_r"
#define PLACEMENT_YUMI_TOOL0_LEFT "yumi_tool0_l" /* ABB tool0 (flange); TCP = tool0 + 0.1142 z */
#define PLACEMENT_YUMI_TOOL0_RIGHT "yumi_tool0_r"

/* A 7R arm, read from a URDF chain. All fields are filled by placement_arm_load(); callers may
 * change nominal_rad (the preferred posture for IK) and narrow lower_rad / upper_rad. */
typedef struct {
  char base_link[PLACEMENT_NAME_MAX];
  char tip_link[PLACEMENT_NAME_MAX];
  char joint_names[PLACEMENT_JOINTS][PLACEMENT_NAME_MAX];
  /* joint k's frame at q = 0 in joint k-1's moving frame (k = 0: in the base link); fixed joints
   * between them are folded in */
  placement_pose_t origin[PLACEMENT_JOINTS];
  double axis[PLACEMENT_JOINTS][3];   /* unit rotation axis in joint k's frame */
  placement_pose_t tip;               /* the tip link in joint 6's moving frame */
  double lower_rad[PLACEMENT_JOINTS]; /* URDF position limits */
  double upper_rad[PLACEMENT_JOINTS];
  double velocity_rad_s[PLACEMENT_JOINTS]; /* URDF velocity limits (> 0) */
  double nominal_rad[PLACEMENT_JOINTS];    /* preferred posture (IK nullspace target, first seed) */
  double reach_m; /* upper bound of |tip - joint 0 origin| over all q (triangle inequality) */
} placement_arm_t;

/* Load the chain base_link -> tip_link of a URDF as a 7R arm. nominal_rad is set to the middle of
 * each joint's range. Errors: PLACEMENT_E_ARG (NULL), PLACEMENT_E_MODEL (file, link, chain or
 * joint problem, or not exactly 7 revolute joints; err carries lib/model's message, which names
 * the file, link or joint). On error *arm is zeroed. Allocates temporarily (urdfdom) and uses
 * about 20 kB of stack (a model_chain_t). */
placement_status_t placement_arm_load(placement_arm_t *arm, const char *urdf_path,
                                      const char *base_link, const char *tip_link,
                                      placement_error_t *err);

/* Load one YuMi arm, yumi_body -> yumi_tcp_{l,r}, and set nominal_rad to the YuMi preferred
 * posture (placement_yumi_nominal). Same errors as placement_arm_load(). */
placement_status_t placement_arm_load_yumi(placement_arm_t *arm, const char *urdf_path,
                                           placement_side_t side, placement_error_t *err);

/* The YuMi preferred posture (IK nullspace target and first seed), chain order, rad: ABB's
 * synchronisation pose, ABB axes 1..7 = (0, -130, 30, 0, 40, 0, -135) deg for the right arm, i.e.
 * chain (0, -130, -135, 30, 0, 40, 0) deg; the left arm is its mirror image (ABB axes 1, 4, 7
 * negated: ABB axis 7 = +135 deg). */
void placement_yumi_nominal(placement_side_t side, double q_rad[PLACEMENT_JOINTS]);

/* Joint order conversions for YuMi: chain order (ABB axes 1,2,7,3,4,5,6) <-> ABB order 1..7. */
void placement_abb_from_chain(const double chain[PLACEMENT_JOINTS], double abb[PLACEMENT_JOINTS]);
void placement_chain_from_abb(const double abb[PLACEMENT_JOINTS], double chain[PLACEMENT_JOINTS]);

/* PLACEMENT_OK when every q_rad[k] is finite and within [lower_rad[k], upper_rad[k]];
 * PLACEMENT_E_NONFINITE, PLACEMENT_E_LIMITS otherwise, PLACEMENT_E_ARG for NULL. */
placement_status_t placement_arm_check(const placement_arm_t *arm,
                                       const double q_rad[PLACEMENT_JOINTS]);

/* Forward kinematics: the tip link in the base link at q_rad. Limits are not checked (use
 * placement_arm_check). PLACEMENT_E_ARG (NULL), PLACEMENT_E_NONFINITE (a non-finite q; *tip is
 * left unchanged). About 0.5 us. */
placement_status_t placement_fk(const placement_arm_t *arm, const double q_rad[PLACEMENT_JOINTS],
                                placement_pose_t *tip);

/* FK of every joint frame as well: frames[k] is joint k's moving frame in the base link (k =
 * 0..6), then the tip is written to *tip. Either output may be NULL. Same statuses as
 * placement_fk. */
placement_status_t placement_fk_frames(const placement_arm_t *arm,
                                       const double q_rad[PLACEMENT_JOINTS],
                                       placement_pose_t frames[PLACEMENT_JOINTS],
                                       placement_pose_t *tip);

/* Geometric Jacobian of the tip in the base frame, jac[row][k]: rows 0..2 the linear velocity of
 * the tip origin (m/rad), rows 3..5 the angular velocity (rad/rad). Statuses as placement_fk. */
placement_status_t placement_jacobian(const placement_arm_t *arm,
                                      const double q_rad[PLACEMENT_JOINTS],
                                      double jac[6][PLACEMENT_JOINTS]);

/* IK options: a caller-owned struct; start from PLACEMENT_IK_CONFIG_INIT. */
typedef struct {
  double tol_pos_m;        /* success: |p_fk - p_target| <= tol_pos_m (> 0) */
  double tol_rot_rad;      /* success: angle(R_target^T R_fk) <= tol_rot_rad (> 0) */
  unsigned max_iterations; /* Levenberg-Marquardt iterations per seed (>= 1) */
  unsigned max_seeds;      /* seeds tried: the caller's seed (or nominal), nominal, random (>= 1) */
  double nullspace_gain;   /* 0..1: size of the first redundancy step, as a fraction of
                               (nominal - q) projected on the nullspace; 0 turns the redundancy
                               phase off (the solution is then the one nearest the seed) */
  uint64_t rng_seed;       /* random seeds come from this (deterministic, no global state) */
  unsigned redundancy_iterations; /* cap of nullspace steps after convergence */
} placement_ik_config_t;

/* Tolerances 1e-9 m / 1e-9 rad, 50 iterations x 64 seeds, gain 0.5, 20 redundancy steps. */
#define PLACEMENT_IK_CONFIG_INIT \
  { 1e-9, 1e-9, 50u, 64u, 0.5, 0x5eedu, 20u }

/* What an IK call did. */
typedef struct {
  double q_rad[PLACEMENT_JOINTS]; /* the solution (PLACEMENT_OK), or the best attempt
                                     (PLACEMENT_E_NO_SOLUTION); zero for other statuses */
  double pos_err_m;               /* FK error of q_rad, verified after solving */
  double rot_err_rad;
  unsigned iterations; /* total over all seeds and the redundancy phase */
  unsigned seeds;      /* seeds tried (1 = converged from the first) */
} placement_ik_result_t;

/* Inverse kinematics of the tip to `target` (tip in base).
 *  1. Levenberg-Marquardt (damped least squares, damping x0.2 on success, x8 on failure) on the
 *     6-D error (position; rotation vector of R_target R^T, both in the base frame). After each
 *     step the joints go back into their limits (a joint past a limit first tries the same angle
 *     one turn back: axes 4 and 6 span more than a turn; else it is clamped), and joints resting
 *     on a limit the step would push further are taken out of that step. Steps are capped at
 *     1 rad per joint.
 *  2. Seeds: q_seed_rad (NULL: arm->nominal_rad), then arm->nominal_rad (if a seed was given),
 *     then random postures uniform within the limits (from cfg->rng_seed), at most
 *     cfg->max_seeds, each with at most cfg->max_iterations iterations.
 *  3. Redundancy, once converged: steps along the Jacobian's nullspace toward arm->nominal_rad
 *     (the projected gradient of |q - nominal|^2), each pulled back onto the pose by at most 4 LM
 *     iterations and kept only if the pose still meets the tolerances and the posture is nearer
 *     nominal (at most cfg->redundancy_iterations steps). ABB axis 7 (q[2], the arm-angle joint)
 *     is thereby drawn toward its nominal value together with the others.
 * PLACEMENT_OK is returned only after an independent FK of the returned q_rad meets both
 * tolerances and q_rad is within the limits: never a wrong answer.
 * Statuses: PLACEMENT_E_ARG (NULL arm/target/out, a cfg field out of range),
 * PLACEMENT_E_NONFINITE (target or seed not finite), PLACEMENT_E_ROTATION (target rot not
 * orthonormal within 1e-9 or a reflection), PLACEMENT_E_OUT_OF_REACH (target farther than
 * arm->reach_m from joint 0's origin: proven unreachable, no seed tried), PLACEMENT_E_NO_SOLUTION
 * (every seed failed: unreachable, or so near the workspace boundary that no seed converged;
 * out->q_rad is the best attempt and the errors say how far it is). cfg NULL means
 * PLACEMENT_IK_CONFIG_INIT. A seed outside the limits is moved into them. No allocation; cost in
 * docs/placement.md (median about 25 us without and 130-160 us with the redundancy phase; an
 * unreachable pose costs all seeds, about 7 ms). */
placement_status_t placement_ik(const placement_arm_t *arm, const placement_pose_t *target,
                                const double q_seed_rad[PLACEMENT_JOINTS],
                                const placement_ik_config_t *cfg, placement_ik_result_t *out);

/* ---- pose helpers (pure, no checks beyond what they say) ----------------------------------- */

/* Identity. */
void placement_pose_identity(placement_pose_t *out);
/* out = a * b (b's child in a's parent). out may alias a or b. */
void placement_pose_mul(const placement_pose_t *a, const placement_pose_t *b,
                        placement_pose_t *out);
/* out = a^-1. out may alias a. */
void placement_pose_inverse(const placement_pose_t *a, placement_pose_t *out);
/* Rotation from URDF / ABB roll-pitch-yaw: R = Rz(yaw) Ry(pitch) Rx(roll). */
void placement_rot_from_rpy(double roll_rad, double pitch_rad, double yaw_rad, double rot[3][3]);
/* Roll, pitch, yaw of a pose's rotation (inverse of placement_rot_from_rpy), pitch in
 * [-pi/2, pi/2]; at pitch +-pi/2 the roll is 0. (Takes the pose, not the bare matrix: a
 * `const double[3][3]` parameter would not accept a non-const matrix in ISO C11.) */
void placement_pose_rpy(const placement_pose_t *pose, double rpy_rad[3]);
/* Rotation by angle_rad about a unit axis. */
void placement_rot_from_axis_angle(const double axis[3], double angle_rad, double rot[3][3]);
/* Position distance and rotation angle (rad, in [0, pi]) between two poses. */
void placement_pose_distance(const placement_pose_t *a, const placement_pose_t *b, double *pos_m,
                             double *rot_rad);

/* ---- the quaternion pose of the rest of comlearn (comlearn/math3d.h's cl_pose_t, laid out as
 * model_pose_t) -------------------------------------------------------------------------------- */

/* The same transform as a position and a unit quaternion (w, x, y, z), w >= 0 (cl_quat_from_rot:
 * Shepperd, normalised). No checks: a non-rotation gives a meaningless quaternion. */
void placement_pose_to_cl_pose(const placement_pose_t *in, cl_pose_t *out);
/* The checked inverse: placement_pose_from_wxyz(in->position_m, in->orientation_wxyz, out)
 * (comlearn/placement_plan.h): the quaternion is normalised; PLACEMENT_E_ROTATION when its norm is
 * off 1 by more than 1e-6, PLACEMENT_E_NONFINITE, PLACEMENT_E_ARG (NULL); *out unchanged on
 * error. */
placement_status_t placement_pose_from_cl_pose(const cl_pose_t *in, placement_pose_t *out);

#ifdef __cplusplus
}
#endif

#endif /* COMLEARN_PLACEMENT_H */
