/*
 * rehearse.c - a plan tried out in simulation on the planner's own beliefs before the real
 * stack is built (library comlearn_stack: geometry and beliefs only, never the URDF inertial).
 *
 * The planner's margins are statics. What statics does not see - a contact tilted enough that the
 * load creeps, a twist about a contact normal - the simulation does, so `comlearn stack` rehearses
 * each plan on a model made of what it believes: the mesh, the believed CoM, the mass guess, and
 * the inertia of the mesh at uniform density carried over to the believed CoM (parallel axes).
 * A plan that falls in rehearsal is replaced by one on flatter contacts. With a learned CoM the
 * rehearsal is as good as the estimate; with a bounding-box center it is as wrong as the box.
 */
#include <stdio.h>
#include <string.h>

#include "comlearn/stack.h"

/* The believed mass properties of one object: mass guess, believed CoM, and the uniform-density
 * inertia of its mesh moved from the mesh's own CoM to the believed one. */
static int belief_mass(const stack_object_t *o, model_mass_t *out) {
  model_mass_t uni;
  if (model_mesh_mass(o->mesh_link, 1.0, &uni) != MODEL_OK || !(uni.mass_kg > 0.0)) return -1;
  const double m = o->mass_kg, scale = m / uni.mass_kg;
  double d[3], d2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    d[k] = o->com_m[k] - uni.com_m[k];
    d2 += d[k] * d[k];
  }
  out->mass_kg = m;
  memcpy(out->com_m, o->com_m, sizeof out->com_m);
  /* I about the believed CoM of a body whose inertia about its own CoM is I_u, as if the
   * distribution were the uniform one shifted: I_u + m (|d|^2 E - d d^T). */
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      out->inertia_kg_m2[r][c] =
          scale * uni.inertia_kg_m2[r][c] + m * ((r == c ? d2 : 0.0) - d[r] * d[c]);
  return 0;
}

stack_status_t stack_run_bodies(const model_mesh_t *const *meshes_link, const model_mass_t *masses,
                                size_t count, const stack_plan_t *plan, const balance_config_t *cfg,
                                const balance_stack_config_t *scfg, stack_sim_result_t *out) {
  if (out == NULL) return STACK_E_ARG;
  memset(out, 0, sizeof *out);
  if (meshes_link == NULL || masses == NULL || plan == NULL || count < 1 ||
      count > STACK_MAX_OBJECTS || plan->count != count) {
    snprintf(out->msg, sizeof out->msg, "need 1..%d objects matching the plan", STACK_MAX_OBJECTS);
    return STACK_E_ARG;
  }
  balance_config_t bc;
  if (cfg)
    bc = *cfg;
  else
    balance_config_default(&bc);
  balance_world_t *world = NULL;
  balance_status_t bs = balance_world_create(&bc, &world);
  if (bs != BALANCE_OK) {
    snprintf(out->msg, sizeof out->msg, "world: %s", balance_status_str(bs));
    return bs == BALANCE_E_NOMEM ? STACK_E_NOMEM : STACK_E_ARG;
  }
  balance_object_t *objs[STACK_MAX_OBJECTS] = {NULL};
  stack_status_t st = STACK_OK;
  for (size_t i = 0; i < count && st == STACK_OK; ++i) {
    bs = meshes_link[i] ? balance_object_create(world, meshes_link[i], &masses[i], &objs[i])
                        : BALANCE_E_ARG;
    if (bs != BALANCE_OK) {
      snprintf(out->msg, sizeof out->msg, "object %zu: simulated body: %s", i,
               balance_status_str(bs));
      st = bs == BALANCE_E_NOMEM ? STACK_E_NOMEM : bs == BALANCE_E_ARG ? STACK_E_ARG : STACK_E_SIM;
    }
  }
  if (st == STACK_OK) {
    bs = balance_stack_run(world, objs, plan->pose, count, scfg, &out->run, out->object);
    if (bs != BALANCE_OK) {
      snprintf(out->msg, sizeof out->msg, "balance_stack_run: %s", balance_status_str(bs));
      st = bs == BALANCE_E_NOMEM ? STACK_E_NOMEM : STACK_E_SIM;
    }
  }
  balance_world_destroy(world);
  return st;
}

stack_status_t stack_rehearse(const stack_object_t *objects, size_t count, const stack_plan_t *plan,
                              const balance_config_t *cfg, const balance_stack_config_t *scfg,
                              stack_sim_result_t *out) {
  if (out == NULL) return STACK_E_ARG;
  memset(out, 0, sizeof *out);
  if (objects == NULL || count < 1 || count > STACK_MAX_OBJECTS) {
    snprintf(out->msg, sizeof out->msg, "need 1..%d objects", STACK_MAX_OBJECTS);
    return STACK_E_ARG;
  }
  const model_mesh_t *meshes[STACK_MAX_OBJECTS];
  model_mass_t masses[STACK_MAX_OBJECTS];
  for (size_t i = 0; i < count; ++i) {
    meshes[i] = objects[i].mesh_link;
    if (meshes[i] == NULL || belief_mass(&objects[i], &masses[i]) != 0) {
      snprintf(out->msg, sizeof out->msg, "object %zu: no usable mesh or mass guess", i);
      return STACK_E_ARG;
    }
  }
  return stack_run_bodies(meshes, masses, count, plan, cfg, scfg, out);
}
