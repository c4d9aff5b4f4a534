/*
 * plan_geom.h - internal geometry of the placement plans (no I/O, no heap): rigid transforms,
 * the exact resting height of a mesh on B's top face, and an exact box-box overlap test.
 * Not installed; lib/placement/src and the tests include it.
 */
#ifndef COMLEARN_PLACEMENT_PLAN_GEOM_H
#define COMLEARN_PLACEMENT_PLAN_GEOM_H

#include <stddef.h>

#include "comlearn/model.h"

/* The lowest z of the mesh surface over the rectangle |x| <= half_x, |y| <= half_y (B's top
 * face) with the mesh's link frame rotated by rot and its origin at (ox, oy, 0). Exact: the
 * minimum of z over each triangle's part above the rectangle is attained at a vertex of that part
 * (a triangle vertex inside the rectangle, a triangle edge crossing a side of the rectangle, or a
 * rectangle corner inside the triangle's projection), and all three kinds are visited. Returns 1
 * and *z_m when some of the mesh is over the rectangle, 0 when none is. O(triangles). */
int plan_mesh_lowest_over_rect(const model_mesh_t *mesh, const double (*rot)[3], double ox,
                               double oy, double half_x, double half_y, double *z_m);

/* 1 when the box (center, axes as the columns of rot, half extents half_b) overlaps the
 * axis-aligned box (center_a, half_a), 0 when they are separated; touching counts as separated
 * (a gap of exactly 0). Exact separating-axis test (15 axes; the 9 edge-edge axes are skipped when
 * an edge pair is parallel within 1e-12, where a face axis already decides). */
int plan_box_overlap(const double center_a[3], const double half_a[3], const double center_b[3],
                     const double rot_b[3][3], const double half_b[3]);

#endif /* COMLEARN_PLACEMENT_PLAN_GEOM_H */
