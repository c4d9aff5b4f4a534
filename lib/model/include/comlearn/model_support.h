/*
 * comlearn/model_support.h - the geometry of an object resting on base block B and of a
 * placement over one of B's edges: what an estimator plans with and a simulator checks against.
 * Pure geometry: no physics engine, no I/O. lib/balance (the physics) calls the same functions.
 *
 * Why it matters: an edge test measures the CoM exactly only where a flat patch of the object
 * crosses the edge along a chord that spans the CoM sideways (docs/physics.md, "Regimes"). On a
 * rounded underside resting on isolated points the object drops onto the edge line when a support
 * passes over it and rolls sideways off that single point. The functions here tell which regime a
 * planned trial is in, list the faces an object can rest on, choose yaws whose chord spans the CoM
 * estimate, and give the pose that sets the object down touching B (never dropped).
 *
 * Every function takes the object's mesh in its link frame (what perception gives) and, where it
 * needs one, a CoM *estimate or guess* in the link frame: an estimator passes its current estimate
 * or the mesh's uniform-density CoM (model_mesh_mass), never the truth.
 *
 * Frames and units: SI. World: z up, B's top face is the rectangle |x| <= sx/2, |y| <= sy/2 at
 * z = 0; its four top edges are named by their outward normals. A pose is the link frame's pose
 * in the world. An "orientation" is a unit quaternion (w, x, y, z) of the link frame in the world;
 * |q| must be within MODEL_QUAT_UNIT_TOL of 1 (MODEL_E_POSE otherwise) and is normalised before
 * use. A yaw is a rotation about world +z applied after the orientation: q' = Rz(yaw) q.
 *
 * Memory: functions that say so allocate temporary memory and free it before returning; every
 * output is caller-owned. Nothing prints. Thread safety: each call touches only its arguments.
 */
#ifndef COMLEARN_MODEL_SUPPORT_H
#define COMLEARN_MODEL_SUPPORT_H

#include <stddef.h>

#include "comlearn/math3d.h"
#include "comlearn/model.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A pose of an object's link frame in the world: position and unit quaternion (w, x, y, z); the
 * project's one pose type (comlearn/math3d.h). */
typedef cl_pose_t model_pose_t;

/* The four top edges of B, by outward normal (world frame). */
typedef enum {
  MODEL_EDGE_PX = 0, /* x = +sx/2, normal (+1, 0, 0) */
  MODEL_EDGE_NX = 1, /* x = -sx/2, normal (-1, 0, 0) */
  MODEL_EDGE_PY = 2, /* y = +sy/2, normal (0, +1, 0) */
  MODEL_EDGE_NY = 3  /* y = -sy/2, normal (0, -1, 0) */
} model_edge_t;

/* Outward unit normal of an edge and its offset d: points p of the edge line satisfy
 * normal . p = d, p.z = 0. */
void model_edge_line(const double base_size_m[3], model_edge_t edge, double normal[3],
                     double *offset_m);

/* A mesh usable for this geometry: non-NULL arrays, counts > 0, indices in range, finite vertices.
 * MODEL_E_ARG (NULL or empty), MODEL_E_DEGENERATE (an index out of range), MODEL_E_NONFINITE. */
model_status_t model_mesh_usable(const model_mesh_t *mesh);

/* Lowest z of mesh_link in orientation `orientation_wxyz` with its link origin at z = 0: minus
 * the height to add so that the object just touches a plane. NAN for NULL, an empty mesh, a
 * non-finite quaternion or one whose norm is off 1 by more than MODEL_QUAT_UNIT_TOL. */
double model_mesh_bottom_z(const model_mesh_t *mesh_link, const double orientation_wxyz[4]);

/* The lowest z of the mesh surface over the rectangle |x| <= half_x, |y| <= half_y (B's top
 * face) with the mesh's link frame rotated by rot and its origin at (ox, oy, 0). Exact: the
 * minimum of z over each triangle's part above the rectangle is attained at a vertex of that part
 * (a triangle vertex inside the rectangle, a triangle edge crossing a side of the rectangle, or a
 * rectangle corner inside the triangle's projection), and all three kinds are visited. Returns 1
 * and *z_m when some of the mesh is over the rectangle, 0 when none is. O(triangles). The one
 * resting height of the project: model_pose_over_edge and lib/placement's plans use it. */
int model_mesh_lowest_over_rect(const model_mesh_t *mesh, const double (*rot)[3], double ox,
                                double oy, double half_x, double half_y, double *z_m);

/* The pose that sets the object (mesh_link) in `orientation_wxyz` down on a block B of size
 * base_size_m with the link-frame point point_link_m exactly over `edge` (normal . p = d in the
 * world), at `along_m` along the edge (the point's world y for the X edges, its world x for the Y
 * edges; 0 is the edge's middle), lowered vertically until it first touches B as a solid box,
 * then touch_depth_m further (trials use 1e-6: pre-penetrated by 1 um, never dropped). The height:
 *   - when some of the mesh's lowest vertices (within 1 um of the lowest) lie over B's top
 *     footprint: the lowest vertex touch_depth_m below the top (as a table would be touched);
 *   - otherwise the lowest point of the mesh over B: a vertex over the footprint, or where the
 *     mesh crosses the vertical plane through one of B's four top edges within that edge's length
 *     (the object resting on the edge line, e.g. a rounded underside whose support point lies
 *     beyond the edge), that point touch_depth_m below the top.
 * The quaternion is normalised. Pure geometry, no allocation. Returns MODEL_E_ARG (NULL, empty
 * mesh, bad edge, touch_depth_m outside [0, MODEL_MAX_TOUCH_DEPTH_M], a base size not finite and
 * positive), MODEL_E_NONFINITE, MODEL_E_POSE (quaternion norm, |along_m| beyond the edge's half
 * length, a coordinate of point_link_m beyond MODEL_MAX_POSITION_M, or no part of the mesh over
 * B's top or its edges: it would not rest on B). */
#define MODEL_MAX_TOUCH_DEPTH_M 1e-4
#define MODEL_MAX_POSITION_M 100.0
model_status_t model_pose_over_edge(const model_mesh_t *mesh_link, const double base_size_m[3],
                                    const double orientation_wxyz[4], model_edge_t edge,
                                    const double point_link_m[3], double along_m,
                                    double touch_depth_m, model_pose_t *out);

/* Most vertices of one patch or support polygon (convex hull, collinear points dropped). */
enum { MODEL_PATCH_MAX_VERTICES = 256 };

/* Thresholds of the regime geometry and the stable-pose search. Fill with
 * model_regime_config_default(); every function accepts cfg == NULL for the defaults. */
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
  /* A flat patch is flat: the vertices of its in-plane triangles lie within this of the plane.
   * Default 1e-7 m: an exactly flat face's vertices scatter by their float32 rounding (~4e-9 m
   * at 5 cm); a scanned face's noise (1 um and more) fills the plane_tol_m band, its contact is a
   * few noise peaks, and an edge test on it tips early by tens of um (docs/physics.md, "Scanned
   * faces"): not a flat-patch test. Finite, > 0. */
  double flat_spread_m;
} model_regime_config_t;

/* Fill cfg with the defaults documented above. */
void model_regime_config_default(model_regime_config_t *cfg);

/* Check every field of cfg: finite and > 0 (min_com_margin_m and min_chord_margin_m may be any
 * finite value). MODEL_E_ARG / MODEL_E_NONFINITE otherwise. */
model_status_t model_regime_config_check(const model_regime_config_t *cfg);

/* The patch an object rests on in a pose: the mesh triangles lying in its support plane (the
 * horizontal plane through its lowest vertex): the real contact. They may form several regions
 * (two feet, the pads of a tripod) or one that is not convex (a ring); chords on an edge line are
 * computed on the triangles themselves, never on a hull that would bridge the gaps. */
typedef struct {
  double support_z_m;    /* world z of the lowest vertex */
  size_t touch_count;    /* mesh vertices within plane_tol_m of the support plane */
  size_t face_count;     /* mesh triangles with all three vertices within plane_tol_m */
  double faces_area_m2;  /* sum of those triangles' areas: the real contact area */
  size_t region_count;   /* groups of those triangles that touch (share a vertex) */
  double region_area_m2; /* real area of the largest group */
  double region_width_m; /* smallest width of that group's convex hull */
  double spread_m;       /* how far above the support plane the vertices of the in-plane
                             triangles lie, at most (0 when face_count == 0) */
  int flat;              /* one region is a flat patch: region_area_m2 >= min_patch_area_m2,
                             region_width_m >= min_patch_width_m and spread_m <= flat_spread_m */
  int closed;            /* the real contact is one convex region: one region of in-plane
                             triangles whose real area is the area of the convex hull of every
                             touching vertex (to 1e-6), as a single triangle or a convex fracture
                             face. Then whatever line crosses it, the hull of the contact on one
                             side is the hull clipped by that line (no gap to bridge) */
  double area_m2;        /* area of the convex hull of all their vertices (an outline that spans
                             gaps between regions); 0 when face_count == 0 */
  double width_m;        /* smallest width of that hull (0 when face_count == 0) */
  size_t vertex_count;   /* the hull, counter-clockwise seen from above, world x, y; one of
                            more than MODEL_PATCH_MAX_VERTICES vertices is reduced to a convex
                            polygon inside it (the smallest corners dropped first) */
  double polygon_xy_m[MODEL_PATCH_MAX_VERTICES][2];
} model_patch_t;

/* The resting patch of mesh_link (link frame) in `pose` (world). The support plane is found (the
 * lowest vertex), not assumed at z = 0. Pure geometry, O(V + T).
 * MODEL_E_ARG (NULL, empty mesh), MODEL_E_DEGENERATE (triangle index out of range),
 * MODEL_E_NONFINITE (vertex or pose), MODEL_E_POSE (quaternion not unit). Allocates temporary
 * memory. */
model_status_t model_patch_resting(const model_mesh_t *mesh_link, const model_pose_t *pose,
                                   const model_regime_config_t *cfg, model_patch_t *out);

/* Which physics a planned edge trial is in. */
typedef enum {
  /* A flat patch crosses the edge along a chord that spans the CoM estimate sideways by at least
   * min_chord_margin_m: the object pivots on the edge line; the threshold is the CoM (um). */
  MODEL_REGIME_FLAT_PATCH = 0,
  /* The edge meets the underside along a short chord or one point (narrow patch, chord not
   * spanning the CoM, or the margin too small): the object rolls sideways over the edge; biased
   * by a fraction of a millimetre to millimetres. */
  MODEL_REGIME_EDGE_ROLL = 1,
  /* No flat patch crosses the edge line (rounded underside resting on isolated points): the
   * object drops onto the edge when its support passes over it and tips by overshoot (mm). */
  MODEL_REGIME_POINT_SUPPORT = 2,
  /* A closed contact smaller than a flat patch (one triangle of a rounded underside, a small convex
   * facet) crosses the edge: the support polygon is that contact clipped by the edge line, so an
   * object confirmed resting on it (its CoM over the contact) pivots on the edge line exactly
   * where its CoM crosses it, whatever the chord margin (docs/physics.md, "Closed patches"). */
  MODEL_REGIME_CLOSED_PATCH = 3
} model_regime_kind_t;

/* A planned trial, analysed. "Along" coordinates are world coordinates along the edge line
 * (world y for MODEL_EDGE_PX / NX, world x for PY / NY). */
typedef struct {
  model_patch_t patch;
  int chord_valid;       /* the edge line meets the real contact (the in-plane triangles)
                               along a positive length */
  double chord_m[2];     /* the chord, along the edge: chord_m[0] < chord_m[1], the outermost
                               points where the edge line meets the real contact. Between them
                               the edge line bounds the support polygon (the convex hull of the
                               contact on B's side) whatever gaps the contact has there; a line
                               that crosses one of two feet gets that foot's chord only. */
  double com_along_m;    /* the CoM estimate's projection, along the edge */
  double com_beyond_m;   /* its signed distance beyond the edge line (outward normal); ~0 for
                               a pose from model_pose_over_edge with that point */
  double chord_margin_m; /* min(com_along - chord_m[0], chord_m[1] - com_along): positive
                               when the chord spans it; -HUGE_VAL without a chord */
  int flat_patch_regime; /* the threshold is the CoM: kind == MODEL_REGIME_FLAT_PATCH or
                             MODEL_REGIME_CLOSED_PATCH */
  model_regime_kind_t kind;
} model_regime_t;

/* Scratch memory for the patch, regime and yaw functions of one mesh: with it (the *_in variants)
 * they allocate nothing. model_support_work_size: the bytes for mesh (0 for NULL or an empty
 * mesh; 265 728 for rock_1, 1 002 vertices and 2 000 triangles, of which 48 096 hold the kept
 * convex hull). model_support_work_init lays a work area out in the caller's `size` bytes at mem
 * (8-byte aligned); NULL when mem is NULL, misaligned or too small.
 * A work area serves any mesh with the same vertex and triangle counts (others: MODEL_E_ARG),
 * one call at a time. The functions without _in allocate one per call. */
typedef struct model_support_work model_support_work_t;
size_t model_support_work_size(const model_mesh_t *mesh);
model_support_work_t *model_support_work_init(void *mem, size_t size, const model_mesh_t *mesh);

/* The convex hull of mesh_link kept in a work area, so that it is built once: the first call for
 * mesh_link (the same pointer, its vertices unchanged) after model_support_work_init builds it
 * with model_mesh_hull, which allocates temporary memory; later calls return it at once and
 * allocate nothing. A call with another mesh builds that mesh's hull in its place. *hull points
 * into the work area: valid while the work area is and until a call with another mesh; never
 * model_mesh_free it. MODEL_E_ARG (NULL, or counts other than the work area's), else the errors
 * of model_mesh_hull (*hull NULL, nothing kept). */
model_status_t model_support_work_hull(model_support_work_t *work, const model_mesh_t *mesh_link,
                                       const model_mesh_t **hull);

/* Analyse a planned trial: the object (mesh_link) released at `pose` (as model_pose_over_edge
 * gives it) over `edge` of a block of size base_size_m, with the CoM estimate
 * com_estimate_link_m (link frame). Pure geometry. Errors as model_patch_resting, and
 * MODEL_E_ARG for a bad edge or base size. */
model_status_t model_regime_classify(const model_mesh_t *mesh_link, const model_pose_t *pose,
                                     const double base_size_m[3], model_edge_t edge,
                                     const double com_estimate_link_m[3],
                                     const model_regime_config_t *cfg, model_regime_t *out);
model_status_t model_regime_classify_in(const model_mesh_t *mesh_link, const model_pose_t *pose,
                                        const double base_size_m[3], model_edge_t edge,
                                        const double com_estimate_link_m[3],
                                        const model_regime_config_t *cfg,
                                        model_support_work_t *work, model_regime_t *out);

/* The chord margin (as in model_regime_t) that a trial would have with the object in
 * orientation Rz(yaw_rad) q, the CoM estimate over `edge`: pure geometry, independent of the
 * position along the edge and of B's size. -HUGE_VAL when the edge line misses the patch or there
 * is no flat patch. Errors as model_patch_resting. */
model_status_t model_yaw_margin(const model_mesh_t *mesh_link, const double orientation_wxyz[4],
                                const double com_estimate_link_m[3], model_edge_t edge,
                                double yaw_rad, const model_regime_config_t *cfg, double *margin_m);

/* model_yaw_margin for n (yaw, CoM estimate) pairs of one orientation at once: margin_m[i] for
 * yaw_rad[i] and com_estimate_link_m[i]. The resting contact is built once (it depends on the
 * orientation only), so a sweep costs one patch plus n chords. n == 0 does nothing. Errors as
 * model_yaw_margin (any yaw non-finite: MODEL_E_NONFINITE). */
model_status_t model_yaw_margins(const model_mesh_t *mesh_link, const double orientation_wxyz[4],
                                 model_edge_t edge, const model_regime_config_t *cfg, size_t n,
                                 const double *yaw_rad, const double (*com_estimate_link_m)[3],
                                 double *margin_m);
model_status_t model_yaw_margins_in(const model_mesh_t *mesh_link, const double orientation_wxyz[4],
                                    model_edge_t edge, const model_regime_config_t *cfg, size_t n,
                                    const double *yaw_rad, const double (*com_estimate_link_m)[3],
                                    model_support_work_t *work, double *margin_m);

/* The yaw in [0, pi) that maximises that chord margin (yaw + pi gives the same chord with the
 * object on the other side of the edge). Sweeps 0.5-degree steps, then refines by golden section
 * (40 iterations) around the best step: deterministic. *margin_m is -HUGE_VAL (and *yaw_rad 0)
 * when the orientation rests on no flat patch. Errors as model_patch_resting. */
model_status_t model_yaw_best(const model_mesh_t *mesh_link, const double orientation_wxyz[4],
                              const double com_estimate_link_m[3], model_edge_t edge,
                              const model_regime_config_t *cfg, double *yaw_rad, double *margin_m);

/* Rz(yaw_rad) q, normalised. */
void model_orientation_yawed(const double orientation_wxyz[4], double yaw_rad, double out[4]);

/* The orientation that turns the link-frame direction normal_link (need not be unit; finite,
 * non-zero) to world -z: the shortest rotation, or pi about x for normal_link along +z.
 * MODEL_E_ARG / MODEL_E_NONFINITE. */
model_status_t model_orientation_resting(const double normal_link[3], double out[4]);

/* A face of the object's convex hull (coplanar hull facets merged): a plane it can rest on. */
typedef struct {
  double normal_link[3];      /* outward unit normal, link frame */
  double offset_m;            /* plane normal . x = offset_m, link frame */
  double orientation_wxyz[4]; /* model_orientation_resting(normal_link): rests on it, yaw 0 */
  double area_m2;             /* support polygon: convex hull of every mesh vertex on the plane */
  double width_m;             /* its smallest width */
  size_t face_count;          /* mesh triangles lying in the plane (the real contact) */
  size_t region_count;        /* groups of them that touch (share a vertex) */
  double patch_area_m2;       /* real area of the largest group (0 if none) */
  double patch_width_m;       /* smallest width of that group's convex hull */
  double patch_spread_m;      /* how far inside the plane the vertices of the in-plane triangles
                                   lie, at most */
  int flat;                   /* that group is a flat patch (min_patch_area_m2,
                                   min_patch_width_m, flat_spread_m) */
  int closed;                 /* the real contact is one convex region (model_patch_t.closed):
                                   its real area is the support polygon's, to 1e-6 */
  double com_margin_m;        /* CoM guess projected along the normal: signed distance to the
                                   support polygon's boundary, positive inside */
  int candidate;              /* com_margin_m >= min_com_margin_m: a stable-pose candidate */
} model_face_t;

/* A face of a convex hull: its coplanar facets merged. */
typedef struct {
  double normal[3]; /* area-weighted mean of its facets' outward unit normals */
  double area_m2;   /* the sum of its facets' areas */
  size_t seed;      /* the hull triangle it grew from (its largest) */
} model_hull_face_t;

/* Merge the facets of `hull` (a convex hull, model_mesh_hull) into faces. Seeds are taken largest
 * facet first (ties by normal, then index); a facet joins the seed's face when its normal's dot
 * product with the seed's is at least merge_cos and its three vertices lie within plane_tol_m of
 * the seed's plane. Facets of zero area seed nothing. Writes the faces in seed order to faces
 * (room for hull->triangle_count), each facet's face (or -1) to facet_face (room for
 * hull->triangle_count), their number to *count. MODEL_E_ARG, MODEL_E_NOMEM (allocates temporary
 * memory). The one merge of the project: model_faces_find (1e-3 rad) and lib/stack's planner
 * (2e-4 rad) use it. */
model_status_t model_hull_faces(const model_mesh_t *hull, double merge_cos, double plane_tol_m,
                                model_hull_face_t *faces, int *facet_face, size_t *count);

/* An edge of a convex hull where its two facets meet at an angle: a line the object can be
 * balanced on, as on a knife edge. Seen along v[0] -> v[1], triangle (v[0], v[1], opposite[0])
 * lies on one side and (v[1], v[0], opposite[1]) on the other; the whole hull lies in the wedge
 * between their planes. */
typedef struct {
  uint32_t v[2];        /* its two hull vertices, v[0] < v[1] */
  uint32_t opposite[2]; /* the third vertex of each of its two hull triangles */
} model_hull_edge_t;

/* The edges of `hull` (a closed convex hull, model_mesh_hull) whose two triangles' outward unit
 * normals have a dot product under merge_cos (the others lie inside a face), ordered by their
 * vertices. `edges` must hold 3 * hull->triangle_count entries: it is the sorting scratch too;
 * the first *count are the result. No allocation, O(T log T). MODEL_E_ARG (NULL, empty, capacity
 * short, merge_cos not finite), MODEL_E_DEGENERATE (an index out of range, a repeated vertex),
 * MODEL_E_OPEN (an edge not in exactly two triangles running it both ways). */
model_status_t model_hull_edges(const model_mesh_t *hull, double merge_cos,
                                model_hull_edge_t *edges, size_t capacity, size_t *count);

/* The faces of mesh_link's convex hull with area >= min_face_area_m2, largest first (ties by
 * normal), each analysed for the CoM guess com_guess_link_m (link frame; the estimator's guess,
 * see the top of this file). A hull facet joins a face when its normal is within 1e-3 rad of the
 * face's first (largest) facet and its three vertices are within plane_tol_m of that plane.
 * Writes up to `capacity` faces and the number found (may exceed capacity) to *count.
 * Flat patches of the object: the faces with flat != 0. Stable-pose candidates: candidate != 0.
 * Errors as model_patch_resting, plus MODEL_E_HULL when the hull fails (flat or degenerate
 * mesh) and MODEL_E_NOMEM. Allocates temporary memory (the hull and the faces' scratch); ~3 ms
 * for a 1000-vertex rock, of which the hull is 1 ms. */
model_status_t model_faces_find(const model_mesh_t *mesh_link, const double com_guess_link_m[3],
                                const model_regime_config_t *cfg, model_face_t *faces,
                                size_t capacity, size_t *count);

/* The hull faces the CoM guess can rest on, whatever their size: every face (area > 0) whose
 * support polygon holds the guess's projection (com_margin_m >= 0), largest margin first. On a
 * convex polyhedron these are the stable resting faces for that CoM; on a rounded mesh they are
 * small facets. Errors and memory as model_faces_find. */
model_status_t model_faces_stable(const model_mesh_t *mesh_link, const double com_guess_link_m[3],
                                  const model_regime_config_t *cfg, model_face_t *faces,
                                  size_t capacity, size_t *count);

/* model_faces_stable with the hull kept in a work area of mesh_link (as model_faces_find_in). */
model_status_t model_faces_stable_in(const model_mesh_t *mesh_link,
                                     const double com_guess_link_m[3],
                                     const model_regime_config_t *cfg, model_support_work_t *work,
                                     model_face_t *faces, size_t capacity, size_t *count);

/* The face of mesh_link's hull with outward normal ~normal_link (unit, link frame): the support
 * plane with that normal (through the farthest vertex), analysed as model_faces_find does for the
 * CoM guess; when the plane holds in-plane triangles its normal is refined to their area-weighted
 * normal, so a normal read from a settled pose (off by micro-radians) gives the exact face.
 * MODEL_E_ARG / MODEL_E_NONFINITE, MODEL_E_NOMEM (allocates temporary memory). */
model_status_t model_face_at(const model_mesh_t *mesh_link, const double normal_link[3],
                             const double com_guess_link_m[3], const model_regime_config_t *cfg,
                             model_face_t *out);

/* model_faces_find on a hull the caller built: hull must be model_mesh_hull(mesh_link) (it is
 * taken as it is, and only checked like a mesh, model_mesh_usable). The same faces, bit for bit;
 * builds no hull. Allocates temporary memory (the faces' scratch). */
model_status_t model_faces_find_hull(const model_mesh_t *mesh_link, const model_mesh_t *hull,
                                     const double com_guess_link_m[3],
                                     const model_regime_config_t *cfg, model_face_t *faces,
                                     size_t capacity, size_t *count);

/* model_faces_find with the hull kept in a work area of mesh_link (model_support_work_hull): the
 * first call builds it, later calls and every other user of the work area reuse it. The same
 * faces, bit for bit; MODEL_E_ARG also for a NULL work area or one of other counts. Allocates
 * temporary memory (the first call's hull, and the faces' scratch). */
model_status_t model_faces_find_in(const model_mesh_t *mesh_link, const double com_guess_link_m[3],
                                   const model_regime_config_t *cfg, model_support_work_t *work,
                                   model_face_t *faces, size_t capacity, size_t *count);

/* When a confirmation trial counts as resting stably. model_stable_config_default(). */
typedef struct {
  double max_rotation_rad;   /* settled within this angle of the release orientation: 0.02 */
  double max_displacement_m; /* link origin moved at most this: 0.002 */
  double touch_depth_m;      /* release pre-penetration, as model_pose_over_edge: 1e-6 */
} model_stable_config_t;

void model_stable_config_default(model_stable_config_t *cfg);

#ifdef __cplusplus
}
#endif

#endif /* COMLEARN_MODEL_SUPPORT_H */
