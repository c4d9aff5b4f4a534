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

/* The real contact of a mesh on a plane: the mesh triangles whose three vertices lie on it. */
typedef struct {
  size_t triangle_count;  /* triangles in the plane */
  double area_m2;         /* the sum of their areas (the real contact area) */
  size_t region_count;    /* groups of them that touch (share a vertex), transitively */
  double region_area_m2;  /* the largest group's real area */
  double region_width_m;  /* the smallest width of that group's convex hull */
} balance_geom_contact_t;

/* Analyse the real contact: on[v] != 0 marks the vertices on the plane, xy[v] their 2-D
 * coordinates in it (every vertex has an entry; only those marked are read). When tri_xy is not
 * NULL it receives the in-plane triangles' corners (room for mesh->triangle_count). Allocates
 * temporary memory: BALANCE_E_NOMEM, else BALANCE_OK. */
balance_status_t balance_geom_contact(const model_mesh_t *mesh, const double (*xy)[2],
                                      const unsigned char *on, double (*tri_xy)[3][2],
                                      balance_geom_contact_t *out);

/* Extent of the real contact along the line p + s d (d unit): the smallest and the largest s at
 * which the line meets one of the n triangles (corners in tri_xy). Returns 1 with [*s0, *s1] when
 * that extent has a positive length, 0 otherwise (no triangle met, or only at one point). The
 * extent may bridge gaps between separate regions: over a line, the convex hull of the contact is
 * the interval between its outermost points, whatever lies between. */
int balance_geom_tris_chord(const double (*tri_xy)[3][2], size_t n, const double p[2],
                            const double d[2], double *s0, double *s1);

#endif
