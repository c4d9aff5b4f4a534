/*
 * comlearn/model_chain.h - a kinematic chain of a URDF: the joints from a base link to a tip link.
 *
 * Geometry only: joint types, origins, axes and limits. No <inertial> is read (this lives in
 * comlearn_model, the estimator's library).
 *
 * Units SI (metres, radians, m/s or rad/s). Each joint's origin places the joint frame in its
 * parent link's frame: x_parent = origin_rot * x_joint + origin_xyz_m, origin_rot = Rz(yaw)
 * Ry(pitch) Rx(roll) of origin_rpy_rad (URDF's convention). The axis is a unit vector in the joint
 * frame.
 *
 * Memory: model_chain_t has a compile-time capacity (MODEL_CHAIN_MAX_JOINTS) and no pointers;
 * model_chain_load() allocates only temporarily (inside urdfdom). Thread safety as model.h.
 */
#ifndef COMLEARN_MODEL_CHAIN_H
#define COMLEARN_MODEL_CHAIN_H

#include <stddef.h>

#include "comlearn/model.h"

#ifdef __cplusplus
extern "C" {
#endif

enum { MODEL_CHAIN_MAX_JOINTS = 32, MODEL_CHAIN_NAME_MAX = 128 };

typedef enum {
  MODEL_JOINT_REVOLUTE = 0,   /* rotation about axis, limited */
  MODEL_JOINT_CONTINUOUS = 1, /* rotation about axis, no position limits */
  MODEL_JOINT_PRISMATIC = 2,  /* translation along axis, limited */
  MODEL_JOINT_FIXED = 3       /* rigid */
} model_joint_type_t;

typedef struct {
  char name[MODEL_CHAIN_NAME_MAX];
  char parent_link[MODEL_CHAIN_NAME_MAX];
  char child_link[MODEL_CHAIN_NAME_MAX];
  model_joint_type_t type;
  double origin_xyz_m[3];
  double origin_rpy_rad[3]; /* as urdfdom reports it (roll, pitch, yaw) */
  double origin_rot[3][3];  /* the same rotation as a matrix (parent <- joint) */
  double axis[3];           /* unit; (1, 0, 0) for fixed joints */
  int has_limits;           /* 1 for revolute and prismatic (URDF requires <limit>) */
  double lower;             /* rad or m; -HUGE_VAL for continuous and fixed joints */
  double upper;             /* rad or m; +HUGE_VAL for continuous and fixed joints */
  double velocity;          /* rad/s or m/s; 0 when the URDF gives none (fixed joints) */
} model_joint_t;

typedef struct {
  char robot_name[MODEL_CHAIN_NAME_MAX];
  char base_link[MODEL_CHAIN_NAME_MAX];
  char tip_link[MODEL_CHAIN_NAME_MAX];
  size_t joint_count;                           /* joints from base to tip, fixed ones included */
  size_t moving_count;                          /* joints that are not fixed */
  model_joint_t joints[MODEL_CHAIN_MAX_JOINTS]; /* joints[0]'s parent is base_link, the last
                                                    joint's child is tip_link */
} model_chain_t;

/* Read the chain base_link -> tip_link from a URDF. base == tip gives an empty chain.
 * Checks (each error message names the URDF and the joint or link):
 *   MODEL_E_ARG      NULL argument or empty link name
 *   MODEL_E_NOFILE   the URDF cannot be read
 *   MODEL_E_PARSE    not a URDF (urdfdom's text: bad numbers such as "nan" in an origin, a
 *                    revolute joint without <limit>, ...)
 *   MODEL_E_NOLINK   base_link or tip_link not in the URDF (lists the links)
 *   MODEL_E_CHAIN    tip_link does not descend from base_link; more than MODEL_CHAIN_MAX_JOINTS
 *                    joints; a joint type not listed above (floating, planar); a zero axis;
 *                    lower > upper; a negative velocity limit; a name longer than 127 bytes
 *   MODEL_E_NONFINITE an origin, axis or limit that is NaN or infinite
 * On error *out is zeroed. Allocates temporarily. */
model_status_t model_chain_load(const char *urdf_path, const char *base_link, const char *tip_link,
                                model_chain_t *out, model_error_t *err);

/* A static name of a joint type ("revolute", ...); never NULL. */
const char *model_joint_type_str(model_joint_type_t type);

#ifdef __cplusplus
}
#endif

#endif /* COMLEARN_MODEL_CHAIN_H */
