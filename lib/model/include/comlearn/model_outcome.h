/*
 * comlearn/model_outcome.h - a geometric model of a placement's outcome on block B: from the mesh,
 * the release pose and a hypothesised CoM, does the object stay in place? Pure geometry (no
 * physics engine, no I/O), for an estimator that weighs thousands of CoM hypotheses per placement.
 *
 * The rule (docs/physics.md, "The outcome model, validated"): an object released at rest, touching
 * B, stays in place iff the vertical line through its CoM passes strictly inside its support
 * polygon, the convex hull (world x, y) of the support set:
 *   - the mesh vertices over B's top rectangle within tol_m of the support plane, and
 *   - the points where mesh edges cross the vertical planes through B's four top edges (within
 *     the edge's length) within tol_m of the support plane: where the object rests on or rolls
 *     over an edge line. An edge with both ends in the band crosses in the band, so a flat face
 *     straddling the edge is clipped exactly along the edge line.
 * The support plane is the lowest point of the mesh over B's top (a vertex over the rectangle or
 * such an edge crossing): found, not assumed at z = 0, so the pose need not touch exactly. The
 * candidates are those of lib/balance's contact generator (lib/balance/src/contact_fast.c:
 * vertices inside the footprint, edge-plane crossings within the edges' lengths); B's corners
 * lying under a mesh triangle are not support points (lib/balance has no such contact either).
 * The band: lib/balance loads every candidate below +2 um, i.e. within 3 um of a pose released
 * 1 um deep by model_pose_over_edge, but those above B's top are speculative contacts that carry
 * no load until the object turns onto them; what holds the object at release is what is pressed
 * into B, the points within the 1 um release depth. Measured (docs/physics.md, bench_outcome): a
 * 1 um band agrees with lib/balance's in-place verdict on 99.1-100 % of the placements of every
 * object class but scanned ones (93 %), a 3 um band on 93 % for objects on three small feet and
 * 83 % for scanned ones (the object turns onto the band's outer points, by 1e-3 rad or more: not
 * in place).
 * The hull is exact: separate feet are not bridged before clipping (an edge line through one of two
 * feet keeps that foot's clipped part and the whole other foot, not the clipped hull of both).
 *
 * What "stays in place" means and where the rule is wrong: docs/physics.md (measured against
 * lib/balance on thousands of placements per object class).
 *
 * Frames and units: SI. World as comlearn/model_support.h: z up, B's top face is the rectangle
 * |x| <= sx/2, |y| <= sy/2 at z = 0 (base_size_m = sx, sy, sz). A pose is the link frame's pose
 * in the world; its quaternion must be within MODEL_QUAT_UNIT_TOL of unit (normalised before use)
 * and its position within MODEL_MAX_POSITION_M. Meshes and CoMs are in the link frame.
 *
 * Memory: nothing here allocates, except model_outcome_predict with work == NULL. A work area
 * (model_outcome_work_size / _init) holds the per-vertex scratch of one mesh; the caller owns it
 * and every output. Nothing prints.
 * Thread safety: each call touches only its arguments. A work area serves one call at a time; a
 * model_outcome_support_t, once built, may be tested from any number of threads at once.
 */
#ifndef COMLEARN_MODEL_OUTCOME_H
#define COMLEARN_MODEL_OUTCOME_H

#include <stddef.h>

#include "comlearn/model.h"
#include "comlearn/model_support.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Most vertices of a support polygon (collinear points dropped); more: MODEL_E_CAPACITY. */
enum { MODEL_OUTCOME_MAX_VERTICES = 512 };

/* Largest support band accepted (1 mm): beyond it the "support set" is not a contact. */
#define MODEL_OUTCOME_MAX_TOL_M 1e-3
/* Largest tilt accepted (10 mrad). */
#define MODEL_OUTCOME_MAX_TILT_RAD 1e-2

/* Settings. Fill with model_outcome_config_default() or MODEL_OUTCOME_CONFIG_DEFAULT; every
 * function accepts cfg == NULL for the defaults. */
typedef struct {
  /* The support band above the support plane: 1e-6 m, the release depth of the trials
   * (model_pose_over_edge with 1e-6: the points pressed into B; see the top of this file for why
   * not lib/balance's 3 um contact band). Use the release depth of your trials.
   * In [0, MODEL_OUTCOME_MAX_TOL_M]. */
  double tol_m;
  /* Optionally the support also takes the candidates the object reaches by turning at most
   * tilt_rad about its band support: a candidate h above the band at horizontal distance L from
   * the band's hull joins when h <= tilt_rad x L. 2e-4 rad is the rotation bound of "stays in
   * place" (docs/physics.md): an object that settles by less onto such a point has not visibly
   * moved. Default 0 (the band only, the set of model_support_polygon): measured, 2e-4 decides
   * placements whose third support lies just beyond the edge (the object settles onto the edge
   * line by ~1e-4 rad); with a 0.1 um band it gains 0.1-0.35 % on rims, pebbles and rocks but
   * loses 7 % on faces with micrometre noise (scanned), where it takes noise peaks.
   * In [0, MODEL_OUTCOME_MAX_TILT_RAD]. */
  double tilt_rad;
  /* A support polygon narrower than this (its smallest width) counts as a line or a point: the
   * object has no static rest on it. 1e-7 m (float32 vertex rounding is ~4e-9 m at 5 cm). >= 0. */
  double min_width_m;
} model_outcome_config_t;

#define MODEL_OUTCOME_CONFIG_DEFAULT \
  { .tol_m = 1e-6, .tilt_rad = 0.0, .min_width_m = 1e-7 }

/* Fill cfg with the defaults above. */
void model_outcome_config_default(model_outcome_config_t *cfg);

/* Check every field: MODEL_E_ARG (NULL, out of range), MODEL_E_NONFINITE. */
model_status_t model_outcome_config_check(const model_outcome_config_t *cfg);

/* Scratch memory for one mesh: its vertices in the world and a bounded point buffer (the support
 * hull is built in chunks of 2 x MODEL_OUTCOME_MAX_VERTICES points, so the buffer does not grow
 * with the support set): 25 B per vertex, 4 B per triangle and ~62 KiB; 94 768 B for a bundled
 * rock). model_outcome_work_size: the bytes for mesh (0 for NULL or an empty mesh).
 * model_outcome_work_init lays a work area out in the caller's `size` bytes at mem (8-byte
 * aligned); NULL when mem is NULL, misaligned or too small. It serves any mesh with the same vertex
 * and triangle counts (others: MODEL_E_ARG), one call at a time. */
typedef struct model_outcome_work model_outcome_work_t;
size_t model_outcome_work_size(const model_mesh_t *mesh);
model_outcome_work_t *model_outcome_work_init(void *mem, size_t size, const model_mesh_t *mesh);

/* The support polygon of mesh_link (link frame) at `pose` (world) on a block of size base_size_m,
 * band tol_m (see the top of this file; 1e-6 is the default): its vertices, world (x, y),
 * counter-clockwise seen from above, starting at the lowest x (then lowest y), points collinear
 * within 1e-12 rad dropped, into polygon_xy_m (room for `capacity`), their number into *n. *n is 1
 * or 2 when the support set is one point or collinear, 0 when no part of the mesh is over B's top
 * (nothing supports it). O(V + T), no allocation. Returns MODEL_OK; MODEL_E_ARG (NULL, empty mesh,
 * work of another size, a base size <= 0, tol_m outside [0, MODEL_OUTCOME_MAX_TOL_M]),
 * MODEL_E_DEGENERATE (a triangle index out of range), MODEL_E_NONFINITE (vertex, pose, base size or
 * tol_m), MODEL_E_POSE (quaternion not unit, position beyond MODEL_MAX_POSITION_M),
 * MODEL_E_CAPACITY (more than `capacity` or MODEL_OUTCOME_MAX_VERTICES vertices; *n is then the
 * number needed, or 0 when above the maximum). polygon_xy_m may be NULL when capacity is 0. */
model_status_t model_support_polygon(const model_mesh_t *mesh_link, const model_pose_t *pose,
                                     const double base_size_m[3], double tol_m,
                                     model_outcome_work_t *work, double (*polygon_xy_m)[2],
                                     size_t capacity, size_t *n);

/* The support of one placement, built once per pose, then tested against any number of CoM
 * hypotheses (model_outcome_support_test: tens of nanoseconds). Caller-allocated (~20 KiB). */
typedef struct {
  double rot[3][3];     /* the pose: link to world rotation */
  double position_m[3]; /* and link origin in the world */
  double support_z_m;   /* world z of the support plane (the lowest point over B); HUGE_VAL
                           when no part of the mesh is over B */
  size_t point_count;   /* support points found (before the hull) */
  int valid;            /* >= 3 vertices and width >= min_width_m: a polygon to rest on */
  double area_m2;       /* of the polygon (0 unless valid) */
  double width_m;       /* its smallest width (0 for fewer than 3 vertices) */
  size_t vertex_count;  /* the polygon, as model_support_polygon gives it */
  double polygon_xy_m[MODEL_OUTCOME_MAX_VERTICES][2];
  double side_m[MODEL_OUTCOME_MAX_VERTICES][3]; /* derived, for the test: side i (vertex i to
                                                   i + 1) as unit inward normal (a, b) and offset c,
                                                   distance inside = a x + b y - c */
} model_outcome_support_t;

/* Build the support of mesh_link at `pose` on a block of size base_size_m (cfg NULL: defaults).
 * O(V + T) with the work area (required), no allocation. Errors as model_support_polygon (cfg:
 * model_outcome_config_check); on error *out is zeroed (valid 0, vertex_count 0). */
model_status_t model_outcome_support_build(const model_mesh_t *mesh_link, const model_pose_t *pose,
                                           const double base_size_m[3],
                                           const model_outcome_config_t *cfg,
                                           model_outcome_work_t *work,
                                           model_outcome_support_t *out);

/* The verdict for the CoM hypothesis com_link_m (link frame) on a built support: *in_place = 1
 * iff the CoM's vertical line is strictly inside the polygon (support->valid and margin > 0);
 * *margin_m = the signed distance of the CoM's (x, y) to the polygon's boundary, positive inside
 * (the distance to the nearest side), negative outside (minus the distance to the polygon).
 * When the support is not valid (a point, a line or a sliver narrower than min_width_m) the margin
 * is minus the distance to that point, segment or sliver (<= 0: on it is 0) and *in_place is 0;
 * with no support point at all it is -HUGE_VAL. O(vertices), no allocation, thread-safe on a
 * shared support. Returns MODEL_OK, MODEL_E_ARG (NULL), MODEL_E_NONFINITE (the CoM). */
model_status_t model_outcome_support_test(const model_outcome_support_t *support,
                                          const double com_link_m[3], int *in_place,
                                          double *margin_m);

/* One placement, one hypothesis: model_outcome_support_build then model_outcome_support_test.
 * work may be NULL: a work area is then allocated for the call and freed (MODEL_E_NOMEM);
 * otherwise nothing allocates. For many hypotheses at one pose build the support once instead.
 * Errors as those two functions. */
model_status_t model_outcome_predict(const model_mesh_t *mesh_link, const model_pose_t *pose,
                                     const double base_size_m[3], const double com_link_m[3],
                                     const model_outcome_config_t *cfg, model_outcome_work_t *work,
                                     int *in_place, double *margin_m);

#ifdef __cplusplus
}
#endif

#endif /* COMLEARN_MODEL_OUTCOME_H */
