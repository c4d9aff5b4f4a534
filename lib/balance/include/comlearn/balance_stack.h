/*
 * comlearn/balance_stack.h - stacks: several objects set down at given poses (the first on B,
 * the others on top), simulated for a while, and whether they stand.
 *
 * Frames, units, memory and threads as in comlearn/balance.h. The objects carry the simulator's
 * mass properties (the truth); the poses come from the caller (e.g. `comlearn stack` aligning the
 * learned CoMs), and balance_stack_pose_above computes them from geometry only.
 */
#ifndef COMLEARN_BALANCE_STACK_H
#define COMLEARN_BALANCE_STACK_H

#include <stddef.h>
#include <stdint.h>

#include "comlearn/balance.h"
#include "comlearn/model.h"

#ifdef __cplusplus
extern "C" {
#endif

/* When a stack stands. balance_stack_config_default(). */
typedef struct {
  double duration_s; /* how long it must stand: 5.0 */
  /* An object has moved (the stack fell) when its link origin is more than max_displacement_m
   * from where it was released, or its orientation more than max_rotation_rad from it.
   * Defaults 0.005 m, 0.05 rad. */
  double max_displacement_m;
  double max_rotation_rad;
  int run_to_end; /* 0 (default): stop at the first object that moved */
} balance_stack_config_t;

void balance_stack_config_default(balance_stack_config_t *cfg);

/* One object of a stack after the run. */
typedef struct {
  model_pose_t final_pose; /* world, when the run ended */
  double displacement_m;   /* largest |link origin - released| seen during the run */
  double rotation_rad;     /* largest angle from the released orientation seen */
  double moved_at_s;       /* first time it passed a threshold; -1 if it never did */
  /* How far it went in the last BALANCE_STACK_REST_WINDOW_S of the run (the whole run when it was
   * shorter): a stack at rest does not move there, one that creeps does. */
  double late_displacement_m;
  double late_rotation_rad;
} balance_stack_object_t;

/* The window at the end of a run over which balance_stack_object_t's late motion is measured. */
#define BALANCE_STACK_REST_WINDOW_S 1.0

typedef struct {
  int stands;              /* no object moved during duration_s */
  double seconds_standing; /* time until the first object moved, or duration_s */
  double sim_time_s;       /* simulated time of the run */
  uint32_t steps;
} balance_stack_result_t;

/* Simulate objects[0..count) released at poses[i] (world; touching, as balance_pose_over_edge or
 * balance_stack_pose_above give them; none deeper than 0.1 mm inside B). Every object of the world
 * not in the list is taken out of the simulation; the listed ones are removed again afterwards.
 * per_object (count entries) may be NULL. cfg may be NULL (defaults). The world time is reset.
 * Errors: BALANCE_E_ARG (NULL, count 0, an object listed twice or from another world, bad cfg),
 * BALANCE_E_NONFINITE, BALANCE_E_POSE (a pose not finite / not unit / deep inside B),
 * BALANCE_E_DIVERGED, BALANCE_E_NOMEM. Deterministic. Allocates two small arrays, and what
 * stepping does. */
balance_status_t balance_stack_run(balance_world_t *world, balance_object_t *const *objects,
                                   const model_pose_t *poses, size_t count,
                                   const balance_stack_config_t *cfg,
                                   balance_stack_result_t *result,
                                   balance_stack_object_t *per_object);

/* The pose that sets the object mesh_link (link frame) in orientation_wxyz straight down onto the
 * object below (below_link at below_pose, world) with its link-frame point point_link_m at world
 * x, y = at_xy_m, touching it (pre-penetrated by touch_depth_m, use 1e-6): the largest height at
 * which the two meshes touch, found exactly (vertex over triangle both ways and edge over edge,
 * in vertical projection). BALANCE_E_POSE when the two do not overlap seen from above. Pure
 * geometry, O(V T + E E) (~0.1 s for two 2000-triangle rocks). Errors: BALANCE_E_ARG,
 * BALANCE_E_NONFINITE, BALANCE_E_MESH, BALANCE_E_POSE, BALANCE_E_NOMEM. Allocates temporary
 * memory (both meshes in world coordinates). */
balance_status_t balance_stack_pose_above(const model_mesh_t *below_link,
                                          const model_pose_t *below_pose,
                                          const model_mesh_t *mesh_link,
                                          const double orientation_wxyz[4],
                                          const double point_link_m[3], const double at_xy_m[2],
                                          double touch_depth_m, model_pose_t *out);

#ifdef __cplusplus
}
#endif

#endif /* COMLEARN_BALANCE_STACK_H */
