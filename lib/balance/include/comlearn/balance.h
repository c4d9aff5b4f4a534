/*
 * comlearn/balance.h - the physics that stands in for the real world: base block B and objects in
 * an ODE world, and the one experiment the paper repeats: an object set down with a chosen point
 * over a chosen edge of B, then watched until it clearly stays or clearly tips off.
 *
 * World frame: z up, gravity -z. B is fixed: its top face is the rectangle |x| <= sx/2, |y| <= sy/2
 * at z = 0 (it fills z in [-sz, 0]); its four top edges are straight lines along world X and Y.
 * An edge is named by its outward normal (BALANCE_EDGE_*).
 *
 * Object frame: the URDF link frame of lib/model (mesh and inertial both in it). A pose is the
 * link frame's pose in the world. Internally the ODE body origin sits at the CoM and the geometry
 * is offset (ODE's debug checks abort on a mass whose CoM is not at the body origin).
 *
 * Every input is validated before it reaches ODE (whose checks call abort()): non-finite or
 * absurd numbers give a status, never an abort. Results are deterministic: the same inputs give
 * bit-identical results.
 *
 * Memory: balance_world_create / balance_object_create allocate; nothing allocates inside a trial
 * beyond what ODE does per step (and, on the stock contact path only, a collision scratch buffer
 * that doubles the first time OPCODE returns more contacts than it holds). Thread safety: ODE must
 * be initialised once per process (balance_world_create does it, guarded); a world and its objects
 * belong to one thread at a time. Nothing here prints.
 */
#ifndef COMLEARN_BALANCE_H
#define COMLEARN_BALANCE_H

#include <stddef.h>
#include <stdint.h>

#include "comlearn/model_support.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One status enum for the module: 0 is success, negative values are errors. */
typedef enum {
  BALANCE_OK = 0,
  BALANCE_E_ARG = -1,       /* NULL pointer, zero count, bad option value */
  BALANCE_E_NONFINITE = -2, /* a NaN or infinity in a pose, mesh, mass or option */
  BALANCE_E_MASS = -3,      /* mass <= 0, inertia not positive definite / triangle inequality */
  BALANCE_E_MESH = -4,      /* mesh empty, degenerate, or not usable for contacts */
  BALANCE_E_POSE = -5,      /* pose absurd: far from B, deep inside B, not a unit quaternion */
  BALANCE_E_NOMEM = -6,     /* allocation failed */
  BALANCE_E_DIVERGED = -7,  /* the simulation produced a non-finite state (reported, not aborted) */
  BALANCE_E_CAPACITY = -8   /* more objects than the world holds, output array too small */
} balance_status_t;

/* A static English description of a status; never NULL. */
const char *balance_status_str(balance_status_t status);

/* How contacts between an object and B are generated. */
typedef enum {
  BALANCE_CONTACT_FAST = 0, /* comlearn's mesh-on-block generator (default) */
  BALANCE_CONTACT_STOCK = 1 /* ODE's own trimesh-box collider (OPCODE), for comparison */
} balance_contact_t;

/* World and trial settings. Fill with balance_config_default() and change what you need.
 * docs/physics.md explains every default and what moving it does to the threshold bias. */
typedef struct {
  double base_size_m[3]; /* B: x, y, z extent; default 0.30, 0.30, 0.10; each in [1 mm, 100 m] */
  double gravity_m_s2;   /* default 9.81 */
  double dt_s;           /* step; default 1e-3, in [1e-6, 0.1] */
  double friction;       /* Coulomb mu (ODE friction pyramid, dContactApprox1), object-B and
                          * object-object; default 0.8. Has no effect on the threshold. */
  double soft_erp;       /* default 0.2 */
  double soft_cfm;       /* default 1e-7 */
  balance_contact_t contact; /* default BALANCE_CONTACT_FAST */
  int max_contacts;          /* contacts kept per object-B and object-object pair after reduction,
                              * in [4, 64]; default 8 (3 never comes to rest) */
  /* Rest test: STAYS once t >= rest_min_time_s and, for rest_steps consecutive steps,
   * |v| < rest_lin_m_s, |w| < rest_ang_rad_s and |w| did not grow from the step before.
   * Defaults 0.03 s, 1e-3 m/s, 1e-2 rad/s, 10. The "did not grow" part is what makes short
   * trials exact: a body that stays only loses the contact transient (|w| decays geometrically),
   * a body tipping ever so slowly over the edge gains speed every step. */
  double rest_min_time_s;
  double rest_lin_m_s;
  double rest_ang_rad_s;
  int rest_steps;
  /* Clearly tipping early: the CoM is beyond B's top (outside its footprint) and |w| grew for
   * tip_grow_steps consecutive steps. Default 20. */
  int tip_grow_steps;
  /* Time cap of one trial; default 0.75 s. Reached: STAYS when the body never rotated more than
   * 1e-3 rad from release nor moved its CoM more than 10 um, its CoM over B (held still in a
   * contact limit cycle on a rough face, docs/physics.md); else INVALID. */
  double horizon_s;
  /* Clearly tipped: rotated more than tip_angle_rad from release, the CoM below the top of B, or
   * the CoM beyond B's footprint by more than the object's radius. Default 0.35 rad. */
  double tip_angle_rad;
  /* Clearly slid: the CoM moved more than slide_m horizontally while the object rotated less than
   * tip_angle_rad / 4. Default 0.005 m. */
  double slide_m;
} balance_config_t;

/* Fill cfg with the defaults documented above. */
void balance_config_default(balance_config_t *cfg);

/* Check every field of cfg (finite, in range); BALANCE_E_ARG / BALANCE_E_NONFINITE otherwise. */
balance_status_t balance_config_check(const balance_config_t *cfg);

typedef struct balance_world balance_world_t;   /* opaque: ODE world, space, B */
typedef struct balance_object balance_object_t; /* opaque: one object's body, geometry, mass */

/* Create a world with B per cfg (copied). The first call in the process initialises ODE
 * (dInitODE2, guarded by pthread_once) and installs a silent ODE message handler (ODE's warnings
 * would print); every call allocates ODE's per-thread collision data for the calling thread.
 * Allocates. Returns BALANCE_E_ARG / BALANCE_E_NONFINITE (cfg, see balance_config_check),
 * BALANCE_E_NOMEM. *out is NULL on error. */
balance_status_t balance_world_create(const balance_config_t *cfg, balance_world_t **out);

/* Destroy a world and every object in it. NULL is fine. */
void balance_world_destroy(balance_world_t *world);

/* The world's configuration (read-only, owned by the world); NULL for NULL. */
const balance_config_t *balance_world_config(const balance_world_t *world);

/* Add an object: its closed mesh and its mass properties, both in the link frame (lib/model).
 * Both are copied; the caller keeps ownership of its arguments; the world owns the object (freed
 * by balance_world_destroy). The object starts outside the simulation until a trial or a stack
 * places it. Allocates (mesh copies, edge list, convex hull, ODE body and trimesh).
 * Checked before anything reaches ODE:
 *   BALANCE_E_ARG        NULL world / mesh / mass / out, NULL mesh arrays
 *   BALANCE_E_NONFINITE  a non-finite vertex, mass, CoM or inertia entry
 *   BALANCE_E_MESH       < 4 vertices or triangles, an index out of range, a triangle with a
 *                        repeated index or (near) zero area (|cross| <= 1e-12 extent^2), largest
 *                        extent outside [0.1 mm, 10 m], or no convex hull
 *   BALANCE_E_MASS       mass <= 0 or > 1e6 kg, inertia not symmetric, not positive definite or
 *                        violating the triangle inequality, CoM outside the mesh's bounding box
 *   BALANCE_E_NOMEM      allocation failed
 * *out is NULL on error. */
balance_status_t balance_object_create(balance_world_t *world, const model_mesh_t *mesh_link,
                                       const model_mass_t *mass, balance_object_t **out);

/* Lowest z of the object's mesh in orientation `orientation_wxyz` with its link origin at z = 0:
 * minus the height to add so that the object just touches a plane. Pure geometry. NAN for NULL,
 * a non-finite quaternion or one whose norm is off 1 by more than 1e-6. */
double balance_object_bottom_z(const balance_object_t *obj, const double orientation_wxyz[4]);

/* The pose that sets the object in `orientation_wxyz` down on B with the link-frame point
 * point_link_m exactly over `edge` (normal . p = d in the world), at `along_m` along the edge
 * (the point's world y for the X edges, its world x for the Y edges; 0 is the edge's middle),
 * lowered vertically until it first touches B as a solid box, then touch_depth_m further (trials
 * use 1e-6: pre-penetrated by 1 um, never dropped). The height:
 *   - when some of the mesh's lowest vertices (within 1 um of the lowest) lie over B's top
 *     footprint: the lowest vertex touch_depth_m below the top (as a table would be touched);
 *   - otherwise the lowest point of the mesh over B: a vertex over the footprint, or where the
 *     mesh crosses the vertical plane through one of B's four top edges within that edge's length
 *     (the object resting on the edge line, e.g. a rounded underside whose support point lies
 *     beyond the edge), that point touch_depth_m below the top.
 * The quaternion is normalised (its norm must be 1 within 1e-6). Pure geometry, no allocation.
 * Returns BALANCE_E_ARG (NULL, bad edge, touch_depth_m outside [0, 1e-4]), BALANCE_E_NONFINITE,
 * BALANCE_E_POSE (quaternion norm, |along_m| beyond the edge's half length, a coordinate of
 * point_link_m beyond 100 m, or no part of the mesh over B's top or its edges: it would not rest
 * on B). */
balance_status_t balance_pose_over_edge(const balance_world_t *world, const balance_object_t *obj,
                                        const double orientation_wxyz[4], model_edge_t edge,
                                        const double point_link_m[3], double along_m,
                                        double touch_depth_m, model_pose_t *out);

/* Outcome of a trial; the values equal comlearn_com_trial_t's OUTCOME_* constants. */
typedef enum {
  BALANCE_INVALID = 0, /* no usable outcome (time cap with the object still moving) */
  BALANCE_STAYS = 1,   /* came to rest on B */
  BALANCE_TIPS = 2,    /* rotated over the edge: clearly tipping off */
  BALANCE_SLIDES = 3   /* translated along/off B without tipping: friction decided, not the CoM */
} balance_outcome_t;

/* Seeded perturbations, for reliability work. Zero noise = exact pose (the result is then
 * bit-identical to a run with noise NULL). The stream is splitmix64 + Box-Muller from seed. */
typedef struct {
  uint64_t seed;
  double placement_noise_m; /* std. dev. of a horizontal (x and y) offset of the release
                             * position; [0, 0.1]. An offset that would push the object into B
                             * (a part below B's top beyond the edge, into B's side) stops where
                             * the object meets B, as a hand would be stopped. */
  double pose_noise_m;      /* std. dev. of the perceived settled position (x, y, z; added to
                             * result.settled only); [0, 0.1] */
} balance_noise_t;

/* The seed of trial n (1-based) of a noisy run seeded run_seed: one splitmix64 step of
 * run_seed ^ (0x9E3779B97F4A7C15 * n). The step spreads the trials' streams over the whole
 * period; without it, run seed 1 or 2 made trial n draw what trial n + 2 (or n + 1) drew again
 * (the Weyl step is the multiplier), so the noise of nearby trials was not independent.
 * comlearn-sim and the direct backend seed trials alike with it. */
uint64_t balance_noise_seed(uint64_t run_seed, uint64_t n);

typedef struct {
  balance_outcome_t outcome;
  model_pose_t released; /* the pose actually released (after placement noise), world */
  model_pose_t settled;  /* the pose when the trial ended (perceived: pose noise added) */
  double displacement_m; /* |settled - released| of the link origin */
  double rotation_rad;   /* angle between released and settled orientations, [0, pi] */
  double sim_time_s;     /* steps * dt_s */
  uint32_t steps;
} balance_trial_result_t;

/* Run one trial: release obj at `release` (link frame in the world; touching B, see
 * balance_pose_over_edge) at rest, step until it is clearly at rest (STAYS), clearly tipping or
 * tipped (TIPS), slid (SLIDES), or the horizon passes (INVALID, or STAYS when held still); see
 * balance_config_t for each test. Other objects of the world are taken out of the simulation first.
 * noise may be NULL. Deterministic: the same world configuration, object and inputs give a
 * bit-identical result, whatever ran before. Allocates nothing itself (ODE allocates its step
 * memory). Returns BALANCE_E_ARG (NULL, obj of another world, noise out of range),
 * BALANCE_E_NONFINITE (pose or noise), BALANCE_E_POSE (see balance_pose_over_edge; or the mesh
 * starting more than 0.1 mm inside B), BALANCE_E_DIVERGED (non-finite state: reported, not
 * aborted), BALANCE_E_NOMEM. *out is filled only on BALANCE_OK (zeroed otherwise). */
balance_status_t balance_trial_run(balance_world_t *world, balance_object_t *obj,
                                   const model_pose_t *release, const balance_noise_t *noise,
                                   balance_trial_result_t *out);

/* The slide rule (balance_config_t's "clearly slid"): 1 when a point of the object moved from
 * from_m to to_m (world) by more than cfg->slide_m horizontally (hypot of the x and y change)
 * while the object turned by rotation_rad < 0.25 * cfg->tip_angle_rad (the angle between the two
 * orientations, e.g. the accurate 2 atan2 of comlearn/math3d.h's cl_quat_angle); 0 otherwise,
 * for NULL, and for a NaN anywhere (every comparison is false). balance_trial_run applies it to
 * the CoM every step (SLIDES); a caller that only sees the object (no CoM: comlearn's LCM
 * backend) applies it to the link origin to tell SLIDES from TIPS for an object that left B.
 * Pure, thread-safe, no allocation; cfg is read only (not checked beyond NULL). */
int balance_trial_slid(const balance_config_t *cfg, const double from_m[3], const double to_m[3],
                       double rotation_rad);

/* The slide rule's rotation limit: 0.25 * cfg->tip_angle_rad (an object that turned less than
 * this and moved more than slide_m slid). For clients that apply the rule themselves (comlearn
 * plan's JSON). Pure; cfg must not be NULL. */
double balance_slide_max_rotation_rad(const balance_config_t *cfg);

#ifdef __cplusplus
}
#endif

#endif /* COMLEARN_BALANCE_H */
