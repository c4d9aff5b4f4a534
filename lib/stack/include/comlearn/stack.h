/*
 * comlearn/stack.h - lib/stack: plan a vertical stack of objects from geometry and believed CoMs,
 * rehearse it on the beliefs, and simulate it with the truth (the library behind `comlearn stack`).
 *
 * Two sides, as for the estimator (estimate.h), in two targets:
 * - The planner (src/plan.c and src/rehearse.c, library comlearn_stack) sees only geometry
 *   (link-frame meshes) and what the caller believes of each object: its CoM (learned,
 *   bounding-box center or truth, the planner cannot tell), the CoM's uncertainty and a mass
 *   guess. It never reads the URDF <inertial>; its archive is checked with nm like
 *   comlearn_estimate's (tests/stack.cmake).
 * - The simulator side (src/simulate.c, library comlearn_stack_sim, links comlearn_model_sim)
 *   loads each object's truth and runs the planned stack on lib/balance (balance_stack_run).
 *
 * No I/O and no logging: every function returns a stack_status_t and explains a failure in the
 * result's msg. The side-view picture of a stack is the program's (apps/comlearn/stack_svg.h):
 * it writes a file, and the libraries under lib/ do no I/O.
 *
 * Thread-safety: no globals; calls on distinct output structs may run concurrently. Memory: the
 * planner and the rehearsal allocate their working sets on the heap and free them before
 * returning (STACK_E_NOMEM when that fails); inputs are borrowed, never kept.
 *
 * Frames and units: SI. World as in comlearn/balance.h: z up, B's top at z = 0 centered at the
 * origin; the stack stands on B. Object: the URDF link frame. A pose is the link frame's pose in
 * the world.
 */
#ifndef COMLEARN_STACK_H
#define COMLEARN_STACK_H

#include <stddef.h>

#include "comlearn/balance.h"
#include "comlearn/balance_stack.h"
#include "comlearn/model.h"

typedef enum {
  STACK_OK = 0,
  STACK_E_ARG = -1,      /* NULL, count out of range, non-finite CoM / mass / uncertainty */
  STACK_E_GEOMETRY = -2, /* a mesh the planner cannot use (no resting face, bad mesh) */
  STACK_E_NOPLAN = -3,   /* no order / pose found whose planned margins are all positive */
  STACK_E_SIM = -4,      /* the simulation failed (lib/balance error; message in msg) */
  STACK_E_NOMEM = -5
} stack_status_t;

const char *stack_status_str(stack_status_t s);

enum { STACK_MAX_OBJECTS = 8 };

/* Where the believed CoMs come from: for reports and JSON ("learned", "bbox", "true"). */
typedef enum { STACK_COM_LEARNED = 0, STACK_COM_BBOX = 1, STACK_COM_TRUE = 2 } stack_com_source_t;
const char *stack_com_source_str(stack_com_source_t s);

/* What the planner knows of one object. */
typedef struct {
  const model_mesh_t *mesh_link; /* geometry, link frame (borrowed) */
  double com_m[3];               /* believed CoM, link frame */
  double com_halfwidth_m[3];     /* its uncertainty per link axis (0: taken as exact) */
  double mass_kg;                /* believed mass (e.g. volume x a nominal density) */
  double mass_rel_uncertainty;   /* plans hold for every mass in mass_kg * [1/(1+u), 1+u] */
} stack_object_t;

typedef struct {
  double max_tilt_rad;         /* steepest contact plane used; default 15 deg (docs/stack.md) */
  double mass_rel_uncertainty; /* default for objects that give 0: 0.3 */
  unsigned yaw_steps;          /* yaws tried per contact; default 24 */
} stack_plan_config_t;

void stack_plan_config_default(stack_plan_config_t *cfg);

/* A plan: the order (bottom first) and the pose of every object. */
typedef struct {
  size_t count;
  size_t order[STACK_MAX_OBJECTS];      /* order[0] rests on B; indices into the input */
  model_pose_t pose[STACK_MAX_OBJECTS]; /* per INPUT index: release pose, world, touching */
  /* Per level (bottom first): the planned worst-case distance, in the contact plane, from the
   * gravity line through the believed CoM of everything above that contact to the edge of the
   * contact's support polygon (level 0: the support on B). Positive inside. */
  double margin_m[STACK_MAX_OBJECTS];
  double tilt_rad[STACK_MAX_OBJECTS]; /* slope of each level's contact plane */
  char msg[256];                      /* why, when no plan */
} stack_plan_t;

/* Plan a stack of objects[0..count), 2 <= count <= STACK_MAX_OBJECTS. Geometry only.
 * cfg NULL: defaults. Deterministic. */
stack_status_t stack_plan(const stack_object_t *objects, size_t count,
                          const stack_plan_config_t *cfg, stack_plan_t *out);

/* ---- simulator side (comlearn_stack_sim) ----------------------------------------------------- */

typedef struct {
  balance_stack_result_t run;                       /* stands, seconds_standing, ... */
  balance_stack_object_t object[STACK_MAX_OBJECTS]; /* per INPUT index */
  char msg[256];
} stack_sim_result_t;

/* Load each URDF's geometry and <inertial> truth (link: root; a truth that fails
 * model_mass_plausible against its mesh is STACK_E_ARG, msg naming the URDF and the limit), build
 * a lib/balance world (cfg NULL: balance defaults), release the objects at plan->pose and run for
 * scfg->duration_s (NULL: balance_stack_config_default, 5 s). urdf_paths[i] matches the planner's
 * objects[i]. */
stack_status_t stack_simulate(const char *const *urdf_paths, size_t count, const stack_plan_t *plan,
                              const balance_config_t *cfg, const balance_stack_config_t *scfg,
                              stack_sim_result_t *out);

/* Release count objects (meshes_link[i] with mass properties masses[i], link frame) at
 * plan->pose on lib/balance and run them (cfg / scfg NULL: defaults). What stack_rehearse and
 * stack_simulate share; the caller decides where the masses come from. */
stack_status_t stack_run_bodies(const model_mesh_t *const *meshes_link, const model_mass_t *masses,
                                size_t count, const stack_plan_t *plan, const balance_config_t *cfg,
                                const balance_stack_config_t *scfg, stack_sim_result_t *out);

/* `comlearn stack` keeps a plan only when its rehearsal stands and comes to rest: no object moves
 * more than these in the run's last BALANCE_STACK_REST_WINDOW_S (1 s). A stack that creeps on a
 * steep contact can stay inside the 5 mm / 0.05 rad thresholds for 5 s on the beliefs and cross
 * them for real (the bundled uneven stack's top rock on its 16-degree contact: 0.2-0.6 mm and
 * 2-4 mrad in the last second of rehearsal; a stack at rest: under 1 um). */
#define STACK_REST_DISPLACEMENT_M 2e-5
#define STACK_REST_ROTATION_RAD 5e-4

/* Rehearse a plan in simulation on the planner's beliefs (src/rehearse.c; no URDF inertial):
 * every object with its mass guess, its believed CoM and its mesh's uniform-density inertia moved
 * to that CoM, released at plan->pose and run like stack_simulate. A plan that falls here falls
 * in the believed world; `comlearn stack` then plans again on flatter contacts. cfg / scfg NULL:
 * defaults. */
stack_status_t stack_rehearse(const stack_object_t *objects, size_t count, const stack_plan_t *plan,
                              const balance_config_t *cfg, const balance_stack_config_t *scfg,
                              stack_sim_result_t *out);

#endif
