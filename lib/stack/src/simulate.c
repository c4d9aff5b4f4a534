/*
 * simulate.c - the simulator side of lib/stack (library comlearn_stack_sim): the planned
 * stack released on lib/balance with each object's URDF truth. The only code of the stack path
 * that reads the <inertial>.
 */
#include <stdio.h>
#include <string.h>

#include "comlearn/balance_stack.h"
#include "comlearn/model_inertial.h"
#include "comlearn/stack.h"

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
  model_object_t obj[STACK_MAX_OBJECTS];
  model_mass_t truth[STACK_MAX_OBJECTS];
  const model_mesh_t *meshes[STACK_MAX_OBJECTS];
  memset(obj, 0, sizeof obj);
  stack_status_t st = STACK_OK;
  for (size_t i = 0; i < count && st == STACK_OK; ++i) {
    if (urdf_paths[i] == NULL) {
      snprintf(out->msg, sizeof out->msg, "object %zu: no URDF path", i);
      st = STACK_E_ARG;
      break;
    }
    model_error_t merr = {{0}};
    model_status_t ms = model_object_load(urdf_paths[i], NULL, &obj[i], &merr);
    if (ms == MODEL_OK) ms = model_inertial_load(urdf_paths[i], NULL, &truth[i], &merr);
    if (ms == MODEL_OK && (ms = model_mass_plausible(&truth[i], &obj[i].mesh, &merr)) != MODEL_OK) {
      char why[sizeof merr.msg];
      memcpy(why, merr.msg, sizeof why);
      snprintf(merr.msg, sizeof merr.msg, "URDF %.180s: link '%.60s': <inertial>: %.230s",
               urdf_paths[i], obj[i].link_name, why);
    }
    if (ms != MODEL_OK) {
      snprintf(out->msg, sizeof out->msg, "%.200s (%s)", merr.msg[0] ? merr.msg : urdf_paths[i],
               model_status_str(ms));
      st = ms == MODEL_E_NOMEM ? STACK_E_NOMEM : STACK_E_ARG;
    }
    meshes[i] = &obj[i].mesh;
  }
  if (st == STACK_OK) st = stack_run_bodies(meshes, truth, count, plan, cfg, scfg, out);
  for (size_t i = 0; i < count; ++i) model_object_free(&obj[i]);
  return st;
}
