/*
 * balance_internal.h - the world and object structs of lib/balance and the internal calls the
 * trial, stable-pose and stack code share. Not installed; only lib/balance/src includes it.
 *
 * Frames: "link" is the object's URDF link frame (mesh and inertial). The ODE body origin sits at
 * the CoM with the link frame's axes ("body" frame = link frame translated by -com), so the
 * trimesh is stored in the body frame and no geom offset is needed. World: z up, B's top at z = 0.
 *
 * Signatures here are stable: stack.c and stable.c build on them.
 */
#ifndef COMLEARN_BALANCE_INTERNAL_H
#define COMLEARN_BALANCE_INTERNAL_H

#include <stddef.h>
#include <stdint.h>

#include <ode/ode.h>

#include "comlearn/balance.h"
#include "comlearn/math3d.h"

/* lib/model's status as ours: the geometry it computes for lib/balance. */
balance_status_t balance_status_from_model(model_status_t status);

/* Largest penetration into B that a release pose may start with (deeper: BALANCE_E_POSE), and
 * position components beyond which a pose is absurd: lib/model's, which plans the poses. */
#define BALANCE_MAX_START_DEPTH_M MODEL_MAX_TOUCH_DEPTH_M
#define BALANCE_MAX_POSITION_M MODEL_MAX_POSITION_M
/* A quaternion whose norm differs from 1 by more than this is rejected (BALANCE_E_POSE). */
#define BALANCE_QUAT_NORM_TOL MODEL_QUAT_UNIT_TOL
/* Points within this gap above a surface become contacts with a negative depth (speculative
 * contacts, ODE's dContactMotionN: ODE clamps a negative depth to zero otherwise). */
#define BALANCE_CONTACT_BAND_M 2e-6
/* Points deeper than this below B's top are not contacts of the top (they are beside B). */
#define BALANCE_CONTACT_MAX_DEPTH_M 2e-3
/* Object-object contacts: hull faces a vertex lies this close to being behind count as candidates
 * for its normal. */
#define BALANCE_PAIR_TIE_M 1e-5
/* Reductions treat projections / depths this close as equal (then the deeper point, then the
 * lowest id wins). */
#define BALANCE_REDUCE_TIE_M 1e-6
/* Within a tie of an extreme key, a point this much deeper than the other wins: two points where
 * mesh edges cross an edge line microns apart can be one on the face (touching) and one on a
 * steep side edge microns above the top; taking the latter by id left that end of the chord
 * without support (a box tipped with its CoM 0.15 mm inside, bench_coverage). Depths of a flat
 * face's points differ by nanometres, so they still tie and go to the lowest id. */
#define BALANCE_REDUCE_DEPTH_TIE_M 1e-7
/* The fast path reselects its reduced contacts after this much motion of any point (m). */
#define BALANCE_FAST_RESELECT_M 1e-6
/* Fast contact candidates are rebuilt after this much motion since the last rebuild. */
#define BALANCE_FAST_REBUILD_M 5e-4
#define BALANCE_FAST_REBUILD_RAD 0.02

/* One contact point before it becomes an ODE contact joint. */
typedef struct {
  double pos_m[3];  /* world */
  double normal[3]; /* unit, world, pointing into the first body (pushes it out) */
  double depth_m;   /* > 0 penetration, < 0 gap (within BALANCE_CONTACT_BAND_M) */
  int edge_plane;   /* -1, or which vertical plane through a top edge of B (model_edge_t) */
  uint32_t id;      /* stable identity (vertex / edge of the mesh): breaks ties in reductions */
} balance_point_t;

/* Candidate set of the fast mesh-on-block generator (contact_fast.c). */
typedef struct {
  int valid;            /* 0: rebuild at the next call */
  double pos_m[3];      /* body position at the last rebuild */
  double quat_wxyz[4];  /* body orientation at the last rebuild */
  uint32_t *verts;      /* candidate vertex indices (into balance_object.verts_body_m) */
  double (*verts_w)[3]; /* their world positions this step */
  uint32_t vert_count;
  uint8_t *code;        /* per candidate vertex: out-code against B's four edge planes */
  uint32_t (*edges)[2]; /* candidate edges as indices into verts[] */
  uint32_t *edge_ids;   /* their indices in balance_object.edges */
  uint32_t edge_count;
  uint32_t *local; /* vertex -> index in verts[], UINT32_MAX if not a candidate */
  /* The reduced contact set of the last full generation, reused (positions and depths recomputed
   * from the mesh) while the body moves less than BALANCE_FAST_RESELECT_M. */
  int sel_valid;
  double sel_pos_m[3];
  double sel_quat_wxyz[4];
  uint32_t sel_id[64];
  int sel_plane[64];
  size_t sel_count;
} balance_fast_cache_t;

enum { BALANCE_SEP_SLOTS = 4 };

/* The normal force an object-object contact carried in the last step (world.c): the friction bound
 * of the same contact in the next step. */
typedef struct {
  const struct balance_object *a, *b; /* the pair, in contact-joint order */
  double pos_m[3];                    /* the contact point, world */
  double normal[3];                   /* the contact normal (into a) */
  double force_n;                     /* normal force on a [N], after the step */
} balance_pair_force_t;

struct balance_object {
  balance_world_t *world;
  size_t index;              /* position in world->objects */
  model_mesh_t mesh_link;    /* copy of the mesh, link frame */
  model_mesh_t hull_link;    /* its convex hull (model_mesh_hull), link frame: built once */
  model_mass_t mass;         /* copy of the mass properties, link frame */
  double (*verts_body_m)[3]; /* mesh vertices - com (body frame) */
  uint32_t (*edges)[2];      /* unique undirected mesh edges */
  size_t edge_count;
  double radius_m;           /* largest |vertex - com| */
  double (*vert_normals)[3]; /* unit outward vertex normals (area-weighted), body frame */
  double (*hull_planes)[4];  /* convex hull faces in the body frame: n . x <= d, (nx, ny, nz, d) */
  size_t hull_plane_count;
  /* vertex_count x BALANCE_SEP_SLOTS: per vertex, the hull plane of another object (slot: that
   * object's index % BALANCE_SEP_SLOTS) that last had the vertex outside. A hint only, tried
   * first: contact_pair.c decides exactly as without it, only sooner (bodies at rest barely move,
   * so the same plane keeps separating). */
  uint32_t *sep_cache;
  dBodyID body; /* disabled while the object is not placed */
  dGeomID geom; /* trimesh in the body frame (stock path) */
  dTriMeshDataID tm_data;
  double *tm_vertices; /* ODE's trimesh references these arrays: owned here */
  dTriIndex *tm_indices;
  int placed; /* 1 while it takes part in balance_world_step */
  balance_fast_cache_t fast;
};

struct balance_world {
  balance_config_t cfg;
  dWorldID ode;
  dJointGroupID contact_group;
  dGeomID base_geom; /* static dBox for the stock path, top face at z = 0 */
  balance_object_t **objects;
  size_t object_count;
  size_t object_capacity;
  dContactGeom *raw; /* collision scratch (stock paths) */
  size_t raw_capacity;
  balance_point_t *points; /* contact scratch before reduction */
  size_t point_capacity;
  double time_s; /* simulated time since the last balance_world_time_reset */
  /* Object-object friction history (world.c): the contacts of the last step with their normal
   * forces (prev), the ones being built (now, with ODE feedback slots). Cleared whenever an
   * object is placed or removed. */
  balance_pair_force_t *pair_prev, *pair_now;
  dJointFeedback *pair_feedback;
  size_t pair_prev_count, pair_now_count, pair_capacity;
};

/* ---- geometry helpers (world.c); pure ---- */

/* Validate a pose: finite (BALANCE_E_NONFINITE), |position| components <= BALANCE_MAX_POSITION_M
 * and |quaternion| within BALANCE_QUAT_NORM_TOL of 1 (BALANCE_E_POSE). *out gets the pose with the
 * quaternion normalised (may alias in). */
balance_status_t balance_pose_check(const model_pose_t *in, model_pose_t *out);

/* ---- objects (object.c) ---- */

/* Place obj at pose_link (link frame in the world), at rest (zero velocities), and make it take
 * part in balance_world_step. The pose is checked (balance_pose_check) and must not start deeper
 * than BALANCE_MAX_START_DEPTH_M inside B (BALANCE_E_POSE). Resets the fast contact cache. */
balance_status_t balance_object_place(balance_object_t *obj, const model_pose_t *pose_link);

/* Take obj out of the simulation (its body is disabled, no contacts). Idempotent. */
void balance_object_remove(balance_object_t *obj);

/* 1 while obj is placed. */
int balance_object_is_placed(const balance_object_t *obj);

/* Current pose of obj's link frame in the world (last placed / stepped state). */
void balance_object_pose_get(const balance_object_t *obj, model_pose_t *out);

/* Current CoM in the world, and its linear (m/s) and angular (rad/s, world axes) velocity.
 * Either output may be NULL. */
void balance_object_com_get(const balance_object_t *obj, double com_world_m[3]);
void balance_object_velocity_get(const balance_object_t *obj, double lin_m_s[3],
                                 double ang_rad_s[3]);

/* Deepest penetration into B (m, > 0 inside) of obj's mesh at pose_link: vertices inside B's box
 * and mesh edges crossing B's vertical top-edge planes below z = 0. 0 when not inside. Pure. */
double balance_object_penetration_m(const balance_object_t *obj, const model_pose_t *pose_link);

/* ---- world (world.c) ---- */

/* Between world.c and object.c only: register a new object (the world then owns it and sizes its
 * contact scratch to points_needed), and free one object's memory and ODE objects. */
balance_status_t balance_world_add_object_internal(balance_world_t *world, balance_object_t *obj,
                                                   size_t points_needed);
void balance_object_destroy_internal(balance_object_t *obj);

/* Number of objects and the i-th (creation order); NULL if out of range. */
size_t balance_world_object_count(const balance_world_t *world);
balance_object_t *balance_world_object(balance_world_t *world, size_t i);

/* Take every object out of the simulation and set the world time to 0. */
void balance_world_reset(balance_world_t *world);

/* One step of cfg.dt_s for every placed object: object-B contacts (cfg.contact: the fast generator
 * or ODE's trimesh-box with all contacts collected), object-object contacts (contact_pair.c:
 * vertices inside the other's convex hull; ODE's trimesh-trimesh is unusable for flat faces),
 * each pair reduced to at most cfg.max_contacts support-preserving contacts (object-object ones
 * also merged within 10 um), then dWorldStep. BALANCE_E_DIVERGED if a placed body's state became
 * non-finite (it is removed), BALANCE_E_NOMEM if ODE or a scratch buffer could not allocate. */
balance_status_t balance_world_step(balance_world_t *world);

/* Simulated time since the last balance_world_reset (s). */
double balance_world_time(const balance_world_t *world);

/* ---- contacts (contact_fast.c) ---- */

/* The fast mesh-on-block generator for obj's body in its current state: vertices below the top
 * (within the band) inside the footprint, plus points where candidate mesh edges cross the
 * vertical planes through B's top edges. Writes at most cap points; returns the count (all of
 * them: the caller sizes out by balance_fast_capacity). */
size_t balance_fast_contacts(const balance_world_t *world, balance_object_t *obj,
                             balance_point_t *out, size_t cap);
/* balance_fast_contacts followed by balance_points_reduce(k), with the reduced set reused while
 * the body has moved less than BALANCE_FAST_RESELECT_M since it was chosen (the chosen points'
 * positions and depths are recomputed every call). Returns the count (<= k). */
size_t balance_fast_contacts_reduced(const balance_world_t *world, balance_object_t *obj,
                                     balance_point_t *out, size_t cap, size_t k);
/* Points balance_fast_contacts can produce at most for obj. */
size_t balance_fast_capacity(const balance_object_t *obj);

/* Object-object contacts (contact_pair.c): the vertices of each object inside, or within
 * BALANCE_CONTACT_BAND_M of, the other's convex hull, normal = the nearest hull face's normal,
 * oriented into `a` (the first body of the contact joints). At most cap points (size cap by
 * balance_pair_capacity). */
size_t balance_pair_contacts(const balance_object_t *a, const balance_object_t *b,
                             balance_point_t *out, size_t cap);

/* Copy n ODE contacts to points (at most cap), dropping those with a non-finite number or a normal
 * that is not unit length (libccd and OPCODE can return a zero normal at exact touch, which turns
 * the body into NaN). id = index in raw. Returns the count kept. */
size_t balance_points_from_ode(const dContactGeom *raw, size_t n, balance_point_t *pts, size_t cap);

/* Reduce n points in place to at most k (k >= 4) that keep the support: the two extreme points
 * along each top-edge line (edge_plane >= 0), the deepest point, then the extremes along eight
 * directions in the plane perpendicular to the mean normal. Near-ties (within
 * BALANCE_REDUCE_TIE_M) go to the point deeper by more than BALANCE_REDUCE_DEPTH_TIE_M, else to
 * the lowest id, so that a flat face whose points are all equally deep keeps the same contacts
 * from step to step. Returns the new count. */
size_t balance_points_reduce(balance_point_t *pts, size_t n, size_t k);

#endif /* COMLEARN_BALANCE_INTERNAL_H */
