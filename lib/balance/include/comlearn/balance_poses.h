/*
 * comlearn/balance_poses.h - the geometry of a placement (pure geometry, no ODE) and the stable
 * poses of an object (candidates from geometry, confirmed in simulation).
 *
 * Why the geometry: an edge test measures the CoM exactly only where a flat patch of the object
 * crosses the edge along a chord that spans the CoM sideways (docs/physics.md, "Regimes"). On a
 * rounded underside resting on isolated points the object drops onto the edge line when a support
 * passes over it and rolls sideways off that single point (bench_regimes: up to 12 mm, median
 * 1.3 mm inside the truth on the bundled rocks). The functions here tell which regime a planned
 * trial is in, list the flat faces an object can rest on, and choose yaws whose chord spans the
 * CoM estimate.
 *
 * Who passes what (estimator / simulator boundary):
 *   - Every geometric function takes the object's mesh in its link frame (what perception gives)
 *     and a CoM *estimate or guess* in the link frame: the estimator passes its current estimate
 *     or the mesh's uniform-density CoM (model_mesh_mass), never the truth.
 *   - balance_stable_confirm / balance_stable_find run trials in a world whose object carries the
 *     simulator's mass properties (balance_object_create's `mass`, the URDF truth). They take no
 *     CoM for the physics: the truth stays inside the simulated object. Their com_guess only
 *     selects the candidates and where the object is set down.
 *
 * Frames and units: SI. Link frame as in comlearn/balance.h. World: z up, B's top at z = 0.
 * An "orientation" is a unit quaternion (w, x, y, z) of the link frame in the world; |q| must be
 * within 1e-6 of 1 (BALANCE_E_POSE otherwise) and is normalised before use. A yaw is a rotation
 * about world +z applied after the orientation: q' = Rz(yaw) q.
 *
 * Memory: functions that say so allocate temporary memory and free it before returning; every
 * output is caller-owned. Nothing prints. Thread safety: the geometric functions touch only their
 * arguments; the simulation functions follow comlearn/balance.h (one thread per world).
 */
#ifndef COMLEARN_BALANCE_POSES_H
#define COMLEARN_BALANCE_POSES_H

#include <stddef.h>

#include "comlearn/balance.h"
#include "comlearn/model.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Most vertices of one patch or support polygon (convex hull, collinear points dropped). */
enum { BALANCE_PATCH_MAX_VERTICES = 256 };

/* Thresholds of the regime geometry and the stable-pose search. Fill with
 * balance_regime_config_default(); every function accepts cfg == NULL for the defaults. */
typedef struct {
  /* A vertex touches the support plane when it is within plane_tol_m of the lowest vertex (1e-6:
   * covers float32 vertex rounding, ~4e-9 m at 5 cm, and stays far below how much a curved 3 mm
   * triangle bends, ~1e-4 m). A mesh triangle lies in the plane when all three vertices do. */
  double plane_tol_m;
  /* A flat patch needs at least this area and smallest width (its convex hull): defaults
   * 1e-4 m^2 (1 cm^2) and 0.010 m. */
  double min_patch_area_m2;
  double min_patch_width_m;
  /* Flat-patch regime: the chord on the edge line spans the CoM estimate's projection with at
   * least this margin on both sides. Default 0.003 m (docs/physics.md: measured bias against
   * margin; it also absorbs a few mm of sideways error of the estimate). */
  double min_chord_margin_m;
  /* Stable-pose candidate: the CoM guess projects inside the support polygon by at least this.
   * Default 0.002 m. */
  double min_com_margin_m;
  /* Hull faces (merged coplanar hull facets) smaller than this are not listed. Default 1e-5 m^2. */
  double min_face_area_m2;
} balance_regime_config_t;

/* Fill cfg with the defaults documented above. */
void balance_regime_config_default(balance_regime_config_t *cfg);

/* Check every field of cfg: finite and > 0 (min_com_margin_m and min_chord_margin_m may be any
 * finite value). BALANCE_E_ARG / BALANCE_E_NONFINITE otherwise. */
balance_status_t balance_regime_config_check(const balance_regime_config_t *cfg);

/* The patch an object rests on in a pose: the mesh triangles lying in its support plane (the
 * horizontal plane through its lowest vertex): the real contact. They may form several regions
 * (two feet, the pads of a tripod) or one that is not convex (a ring); chords on an edge line are
 * computed on the triangles themselves, never on a hull that would bridge the gaps. */
typedef struct {
  double support_z_m;     /* world z of the lowest vertex */
  size_t touch_count;     /* mesh vertices within plane_tol_m of the support plane */
  size_t face_count;      /* mesh triangles with all three vertices within plane_tol_m */
  double faces_area_m2;   /* sum of those triangles' areas: the real contact area */
  size_t region_count;    /* groups of those triangles that touch (share a vertex) */
  double region_area_m2;  /* real area of the largest group */
  double region_width_m;  /* smallest width of that group's convex hull */
  int flat;               /* one region is a flat patch: region_area_m2 >= min_patch_area_m2 and
                             region_width_m >= min_patch_width_m */
  double area_m2;         /* area of the convex hull of all their vertices (an outline that spans
                             gaps between regions); 0 when face_count == 0 */
  double width_m;         /* smallest width of that hull (0 when face_count == 0) */
  size_t vertex_count;    /* the hull, counter-clockwise seen from above, world x, y */
  double polygon_xy_m[BALANCE_PATCH_MAX_VERTICES][2];
} balance_patch_t;

/* The resting patch of mesh_link (link frame) in `pose` (world). The support plane is found (the
 * lowest vertex), not assumed at z = 0. Pure geometry, O(V + T).
 * BALANCE_E_ARG (NULL, empty mesh), BALANCE_E_MESH (triangle index out of range),
 * BALANCE_E_NONFINITE (vertex or pose), BALANCE_E_POSE (quaternion not unit),
 * BALANCE_E_CAPACITY (hull above BALANCE_PATCH_MAX_VERTICES). Allocates temporary memory. */
balance_status_t balance_patch_resting(const model_mesh_t *mesh_link, const balance_pose_t *pose,
                                       const balance_regime_config_t *cfg, balance_patch_t *out);

/* Which physics a planned edge trial is in. */
typedef enum {
  /* A flat patch crosses the edge along a chord that spans the CoM estimate sideways by at least
   * min_chord_margin_m: the object pivots on the edge line; the threshold is the CoM (um). */
  BALANCE_REGIME_FLAT_PATCH = 0,
  /* The edge meets the underside along a short chord or one point (narrow patch, chord not
   * spanning the CoM, or the margin too small): the object rolls sideways over the edge; biased
   * by a fraction of a millimetre to millimetres. */
  BALANCE_REGIME_EDGE_ROLL = 1,
  /* No flat patch crosses the edge line (rounded underside resting on isolated points): the
   * object drops onto the edge when its support passes over it and tips by overshoot (mm). */
  BALANCE_REGIME_POINT_SUPPORT = 2
} balance_regime_kind_t;

/* A planned trial, analysed. "Along" coordinates are world coordinates along the edge line
 * (world y for BALANCE_EDGE_PX / NX, world x for PY / NY). */
typedef struct {
  balance_patch_t patch;
  int chord_valid;          /* the edge line meets the real contact (the in-plane triangles)
                               along a positive length */
  double chord_m[2];        /* the chord, along the edge: chord_m[0] < chord_m[1], the outermost
                               points where the edge line meets the real contact. Between them
                               the edge line bounds the support polygon (the convex hull of the
                               contact on B's side) whatever gaps the contact has there; a line
                               that crosses one of two feet gets that foot's chord only. */
  double com_along_m;       /* the CoM estimate's projection, along the edge */
  double com_beyond_m;      /* its signed distance beyond the edge line (outward normal); ~0 for
                               a pose from balance_pose_over_edge with that point */
  double chord_margin_m;    /* min(com_along - chord_m[0], chord_m[1] - com_along): positive
                               when the chord spans it; -HUGE_VAL without a chord */
  int flat_patch_regime;    /* kind == BALANCE_REGIME_FLAT_PATCH */
  balance_regime_kind_t kind;
} balance_regime_t;

/* Analyse a planned trial: the object (mesh_link) released at `pose` (as balance_pose_over_edge
 * gives it) over `edge` of a block of size base_size_m, with the CoM estimate
 * com_estimate_link_m (link frame). Pure geometry. Errors as balance_patch_resting, and
 * BALANCE_E_ARG for a bad edge or base size. */
balance_status_t balance_regime_classify(const model_mesh_t *mesh_link, const balance_pose_t *pose,
                                         const double base_size_m[3], balance_edge_t edge,
                                         const double com_estimate_link_m[3],
                                         const balance_regime_config_t *cfg,
                                         balance_regime_t *out);

/* The chord margin (as in balance_regime_t) that a trial would have with the object in
 * orientation Rz(yaw_rad) q, the CoM estimate over `edge`: pure geometry, independent of the
 * position along the edge and of B's size. -HUGE_VAL when the edge line misses the patch or there
 * is no flat patch. Errors as balance_patch_resting. */
balance_status_t balance_yaw_margin(const model_mesh_t *mesh_link, const double orientation_wxyz[4],
                                    const double com_estimate_link_m[3], balance_edge_t edge,
                                    double yaw_rad, const balance_regime_config_t *cfg,
                                    double *margin_m);

/* balance_yaw_margin for n (yaw, CoM estimate) pairs of one orientation at once: margin_m[i] for
 * yaw_rad[i] and com_estimate_link_m[i]. The resting contact is built once (it depends on the
 * orientation only), so a sweep costs one patch plus n chords. n == 0 does nothing. Errors as
 * balance_yaw_margin (any yaw non-finite: BALANCE_E_NONFINITE). */
balance_status_t balance_yaw_margins(const model_mesh_t *mesh_link,
                                     const double orientation_wxyz[4], balance_edge_t edge,
                                     const balance_regime_config_t *cfg, size_t n,
                                     const double *yaw_rad, const double (*com_estimate_link_m)[3],
                                     double *margin_m);

/* The yaw in [0, pi) that maximises that chord margin (yaw + pi gives the same chord with the
 * object on the other side of the edge). Sweeps 0.5-degree steps, then refines by golden section
 * (40 iterations) around the best step: deterministic. *margin_m is -HUGE_VAL (and *yaw_rad 0)
 * when the orientation rests on no flat patch. Errors as balance_patch_resting. */
balance_status_t balance_yaw_best(const model_mesh_t *mesh_link, const double orientation_wxyz[4],
                                  const double com_estimate_link_m[3], balance_edge_t edge,
                                  const balance_regime_config_t *cfg, double *yaw_rad,
                                  double *margin_m);

/* Rz(yaw_rad) q, normalised. */
void balance_orientation_yawed(const double orientation_wxyz[4], double yaw_rad, double out[4]);

/* The orientation that turns the link-frame direction normal_link (need not be unit; finite,
 * non-zero) to world -z: the shortest rotation, or pi about x for normal_link along +z.
 * BALANCE_E_ARG / BALANCE_E_NONFINITE. */
balance_status_t balance_orientation_resting(const double normal_link[3], double out[4]);

/* A face of the object's convex hull (coplanar hull facets merged): a plane it can rest on. */
typedef struct {
  double normal_link[3];        /* outward unit normal, link frame */
  double offset_m;              /* plane normal . x = offset_m, link frame */
  double orientation_wxyz[4];   /* balance_orientation_resting(normal_link): rests on it, yaw 0 */
  double area_m2;               /* support polygon: convex hull of every mesh vertex on the plane */
  double width_m;               /* its smallest width */
  size_t face_count;            /* mesh triangles lying in the plane (the real contact) */
  size_t region_count;          /* groups of them that touch (share a vertex) */
  double patch_area_m2;         /* real area of the largest group (0 if none) */
  double patch_width_m;         /* smallest width of that group's convex hull */
  int flat;                     /* that group is a flat patch (min_patch_area_m2,
                                   min_patch_width_m) */
  double com_margin_m;          /* CoM guess projected along the normal: signed distance to the
                                   support polygon's boundary, positive inside */
  int candidate;                /* com_margin_m >= min_com_margin_m: a stable-pose candidate */
} balance_face_t;

/* The faces of mesh_link's convex hull with area >= min_face_area_m2, largest first (ties by
 * normal), each analysed for the CoM guess com_guess_link_m (link frame; the estimator's guess,
 * see the top of this file). A hull facet joins a face when its normal is within 1e-3 rad of the
 * face's first (largest) facet and its three vertices are within plane_tol_m of that plane.
 * Writes up to `capacity` faces and the number found (may exceed capacity) to *count.
 * Flat patches of the object: the faces with flat != 0. Stable-pose candidates: candidate != 0.
 * Errors as balance_patch_resting, plus BALANCE_E_MESH when the hull fails (flat or degenerate
 * mesh) and BALANCE_E_NOMEM. Allocates temporary memory (the hull); ~20 ms for a 1000-vertex rock. */
balance_status_t balance_faces_find(const model_mesh_t *mesh_link, const double com_guess_link_m[3],
                                    const balance_regime_config_t *cfg, balance_face_t *faces,
                                    size_t capacity, size_t *count);

/* ---- stable poses, confirmed in simulation ------------------------------------------------ */

/* When a confirmation trial counts as resting stably. balance_stable_config_default(). */
typedef struct {
  double max_rotation_rad;     /* settled within this angle of the release orientation: 0.02 */
  double max_displacement_m;   /* link origin moved at most this: 0.002 */
  double touch_depth_m;        /* release pre-penetration, as balance_pose_over_edge: 1e-6 */
} balance_stable_config_t;

void balance_stable_config_default(balance_stable_config_t *cfg);

/* Release obj (of `world`; it carries the simulator's mass properties) in `orientation_wxyz`
 * with the link-frame point center_link_m above the middle of B's top, touching it (lowest vertex
 * touch_depth_m below z = 0), and run one trial (balance_trial_run, no noise). *confirmed = 1
 * when the outcome is BALANCE_STAYS within max_rotation_rad and max_displacement_m. trial may be
 * NULL. cfg may be NULL (defaults). Errors: those of balance_trial_run, BALANCE_E_ARG,
 * BALANCE_E_NONFINITE, BALANCE_E_POSE. Allocates only what a trial does. */
balance_status_t balance_stable_confirm(balance_world_t *world, balance_object_t *obj,
                                        const double orientation_wxyz[4],
                                        const double center_link_m[3],
                                        const balance_stable_config_t *cfg,
                                        balance_trial_result_t *trial, int *confirmed);

/* One stable pose: a hull face, the trial that confirmed it, the settled pose in trial.settled. */
typedef struct {
  balance_face_t face;
  balance_trial_result_t trial;
} balance_stable_pose_t;

/* The stable poses of obj: balance_faces_find(obj's mesh, com_guess_link_m) for the candidates,
 * each confirmed with balance_stable_confirm (with com_guess_link_m over B's middle). Writes the
 * confirmed ones, largest face first, up to `capacity`, and their number (may exceed capacity)
 * to *count; *trials_run (may be NULL) gets the number of trials run. Allocates temporary
 * memory. Errors of balance_faces_find and balance_stable_confirm. */
balance_status_t balance_stable_find(balance_world_t *world, balance_object_t *obj,
                                     const double com_guess_link_m[3],
                                     const balance_regime_config_t *regime_cfg,
                                     const balance_stable_config_t *stable_cfg,
                                     balance_stable_pose_t *poses, size_t capacity, size_t *count,
                                     size_t *trials_run);

#ifdef __cplusplus
}
#endif

#endif /* COMLEARN_BALANCE_POSES_H */
