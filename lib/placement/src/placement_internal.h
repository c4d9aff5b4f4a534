/* placement_internal.h - private to lib/placement: small 3-vector / 3x3 helpers shared by the
 * kinematics sources. */
#ifndef COMLEARN_PLACEMENT_INTERNAL_H
#define COMLEARN_PLACEMENT_INTERNAL_H

#include "comlearn/placement.h"

#if defined(__GNUC__)
#define PLACEMENT_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define PLACEMENT_PRINTF(a, b)
#endif

/* Write a message into err (NULL is fine); returns status. */
placement_status_t placement_fail(placement_error_t *err, placement_status_t status,
                                  const char *fmt, ...) PLACEMENT_PRINTF(3, 4);

/* Rotation vector (axis * angle, angle in [0, pi]) of a rotation matrix; robust near 0 and pi. */
void placement_rot_log(const double rot[3][3], double w[3]);

/* Angle of a rotation matrix in [0, pi], accurate near 0 (atan2 of the antisymmetric part). */
double placement_rot_angle(const double rot[3][3]);

/* 1 when every one of n values is finite. */
int placement_finite(const double *v, size_t n);

/* Geometric Jacobian (as placement_jacobian) from frames and tip computed by FK. */
void placement_jacobian_from_frames(const placement_arm_t *arm,
                                    const placement_pose_t frames[PLACEMENT_JOINTS],
                                    const placement_pose_t *tip, double jac[6][PLACEMENT_JOINTS]);

#endif /* COMLEARN_PLACEMENT_INTERNAL_H */
