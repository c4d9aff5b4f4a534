/* poses_geom.h - private geometry shared by regime.c, stable.c and stack.c: quaternions, mesh
 * validation, convex polygons in a plane. Defined in regime.c. (tools/rockgen_patch.c has its own
 * copy of the 2-D hull and width; it could call these once tools link lib/balance.) */
#ifndef COMLEARN_BALANCE_POSES_GEOM_H
#define COMLEARN_BALANCE_POSES_GEOM_H

#include <stddef.h>

#include "comlearn/balance.h"
#include "comlearn/balance_poses.h"

/* |q| within this of 1 is accepted as a unit quaternion (then normalised). */
#define BALANCE_GEOM_QUAT_TOL 1e-6

/* Validate q (finite, unit within BALANCE_GEOM_QUAT_TOL) and write it normalised. */
balance_status_t balance_geom_quat_check(const double q[4], double unit[4]);

/* v' = R(q) v for a unit quaternion (w, x, y, z). */
void balance_geom_quat_rotate(const double q[4], const double v[3], double out[3]);

/* a * b (apply b, then a). */
void balance_geom_quat_mul(const double a[4], const double b[4], double out[4]);

/* Angle between two unit quaternions' rotations, [0, pi]. */
double balance_geom_quat_angle(const double a[4], const double b[4]);

/* Mesh usable for geometry: non-NULL arrays, counts > 0, indices in range, finite vertices. */
balance_status_t balance_geom_mesh_check(const model_mesh_t *mesh);

/* Planar hull, area, width and margin: model_polygon_*() in comlearn/model.h. */

/* The chord of the line p + s d (d unit) through a convex counter-clockwise polygon: returns 1 and
 * [s0, s1] when the line crosses its interior (s1 - s0 > 0), 0 otherwise. */
int balance_geom_poly_chord(const double (*poly)[2], size_t n, const double p[2], const double d[2],
                            double *s0, double *s1);

#endif
