/*
 * plan_geom.h - internal geometry of the placement plans (no I/O, no heap): rigid transforms,
 * and an exact box-box overlap test.
 * Not installed; lib/placement/src and the tests include it.
 */
#ifndef COMLEARN_PLACEMENT_PLAN_GEOM_H
#define COMLEARN_PLACEMENT_PLAN_GEOM_H

#include <stddef.h>

#include "comlearn/model.h"

/* 1 when the box (center, axes as the columns of rot, half extents half_b) overlaps the
 * axis-aligned box (center_a, half_a), 0 when they are separated; touching counts as separated
 * (a gap of exactly 0). Exact separating-axis test (15 axes; the 9 edge-edge axes are skipped when
 * an edge pair is parallel within 1e-12, where a face axis already decides). */
int plan_box_overlap(const double center_a[3], const double half_a[3], const double center_b[3],
                     const double rot_b[3][3], const double half_b[3]);

#endif /* COMLEARN_PLACEMENT_PLAN_GEOM_H */
