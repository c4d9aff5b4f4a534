/*
 * stack_sim.c - the simulator side of `comlearn stack` (library comlearn_stack_sim): the planned
 * stack released on lib/balance with each object's URDF truth. The only code of the stack path
 * that reads the <inertial>.
 */
#include <stdio.h>
#include <string.h>

#include "comlearn/balance_stack.h"
#include "comlearn/model_inertial.h"
#include "stack.h"

stack_status_t stack_simulate(const char *const *urdf_paths, size_t count, const stack_plan_t *plan,
                              const balance_config_t *cfg, const balance_stack_config_t *scfg,
                              stack_sim_result_t *out) {
  if (out == NULL) return STACK_E_ARG;
  memset(out, 0, sizeof *out);
  if (urdf_paths == NULL || plan == NULL || count < 1 || count > STACK_MAX_OBJECTS ||
      plan->count != count) {
    snprintf(out->msg, sizeof out->msg, "need 1..%d objects matching the plan", STACK_MAX_OBJECTS);
    return STACK_E_ARG;
  }
  balance_config_t bc;
  if (cfg) bc = *cfg;
  else balance_config_default(&bc);
  balance_world_t *world = NULL;
  balance_status_t bs = balance_world_create(&bc, &world);
  if (bs != BALANCE_OK) {
    snprintf(out->msg, sizeof out->msg, "world: %s", balance_status_str(bs));
    return bs == BALANCE_E_NOMEM ? STACK_E_NOMEM : STACK_E_ARG;
  }
  balance_object_t *objs[STACK_MAX_OBJECTS] = {NULL};
  stack_status_t st = STACK_OK;
  for (size_t i = 0; i < count && st == STACK_OK; ++i) {
    if (urdf_paths[i] == NULL) {
      snprintf(out->msg, sizeof out->msg, "object %zu: no URDF path", i);
      st = STACK_E_ARG;
      break;
    }
    model_error_t merr = {{0}};
    model_object_t obj = {0};
    model_mass_t truth;
    model_status_t ms = model_object_load(urdf_paths[i], NULL, &obj, &merr);
    if (ms == MODEL_OK) ms = model_inertial_load(urdf_paths[i], NULL, &truth, &merr);
    if (ms != MODEL_OK) {
      snprintf(out->msg, sizeof out->msg, "%.200s (%s)", merr.msg[0] ? merr.msg : urdf_paths[i],
               model_status_str(ms));
      model_object_free(&obj);
      st = ms == MODEL_E_NOMEM ? STACK_E_NOMEM : STACK_E_ARG;
      break;
    }
    bs = balance_object_create(world, &obj.mesh, &truth, &objs[i]);
    model_object_free(&obj);
    if (bs != BALANCE_OK) {
      snprintf(out->msg, sizeof out->msg, "%s: simulated object: %s", urdf_paths[i],
               balance_status_str(bs));
      st = bs == BALANCE_E_NOMEM ? STACK_E_NOMEM : STACK_E_SIM;
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
