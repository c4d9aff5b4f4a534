/* stable.c - stable poses confirmed in simulation: candidates from lib/model's hull faces
 * (model_faces_find) with a CoM guess, each confirmed by a trial in the middle of B. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "balance_internal.h"
#include "comlearn/balance_poses.h"
#include "comlearn/math3d.h"

/* ---- confirmation in simulation ----------------------------------------------------------- */

static balance_status_t stable_config_resolve(const model_stable_config_t *cfg,
                                              model_stable_config_t *out) {
  model_stable_config_default(out);
  if (cfg == NULL) return BALANCE_OK;
  if (!isfinite(cfg->max_rotation_rad) || !isfinite(cfg->max_displacement_m) ||
      !isfinite(cfg->touch_depth_m))
    return BALANCE_E_NONFINITE;
  if (!(cfg->max_rotation_rad > 0.0) || !(cfg->max_displacement_m > 0.0) ||
      !(cfg->touch_depth_m >= 0.0) || cfg->touch_depth_m > 1e-3)
    return BALANCE_E_ARG;
  *out = *cfg;
  return BALANCE_OK;
}

balance_status_t balance_stable_confirm(balance_world_t *world, balance_object_t *obj,
                                        const double orientation_wxyz[4],
                                        const double center_link_m[3],
                                        const model_stable_config_t *cfg,
                                        balance_trial_result_t *trial, int *confirmed) {
  if (world == NULL || obj == NULL || confirmed == NULL || center_link_m == NULL)
    return BALANCE_E_ARG;
  *confirmed = 0;
  if (obj->world != world) return BALANCE_E_ARG;
  const model_mesh_t *mesh_link = &obj->mesh_link;
  model_stable_config_t sc;
  balance_status_t st = stable_config_resolve(cfg, &sc);
  if (st != BALANCE_OK) return st;
  for (int k = 0; k < 3; ++k) {
    if (!isfinite(center_link_m[k])) return BALANCE_E_NONFINITE;
  }
  model_pose_t pose;
  st = balance_status_from_model(model_quat_unit(orientation_wxyz, pose.orientation_wxyz));
  if (st != BALANCE_OK) return st;
  double zmin = HUGE_VAL, cw[3];
  for (size_t v = 0; v < mesh_link->vertex_count; ++v) {
    double w[3];
    cl_quat_rotate(pose.orientation_wxyz, mesh_link->vertices_m[v], w);
    if (w[2] < zmin) zmin = w[2];
  }
  cl_quat_rotate(pose.orientation_wxyz, center_link_m, cw);
  pose.position_m[0] = -cw[0];
  pose.position_m[1] = -cw[1];
  pose.position_m[2] = -zmin - sc.touch_depth_m;
  balance_trial_result_t r;
  st = balance_trial_run(world, obj, &pose, NULL, &r);
  if (st != BALANCE_OK) return st;
  *confirmed = r.outcome == BALANCE_STAYS && r.rotation_rad <= sc.max_rotation_rad &&
               r.displacement_m <= sc.max_displacement_m;
  if (trial != NULL) *trial = r;
  return BALANCE_OK;
}

balance_status_t balance_stable_find(balance_world_t *world, balance_object_t *obj,
                                     const double com_guess_link_m[3],
                                     const model_regime_config_t *regime_cfg,
                                     const model_stable_config_t *stable_cfg,
                                     balance_stable_pose_t *poses, size_t capacity, size_t *count,
                                     size_t *trials_run) {
  if (world == NULL || obj == NULL || count == NULL || (poses == NULL && capacity > 0) ||
      obj->world != world)
    return BALANCE_E_ARG;
  const model_mesh_t *mesh_link = &obj->mesh_link;
  *count = 0;
  if (trials_run != NULL) *trials_run = 0;
  size_t nf = 0;
  /* the object's hull, built once at balance_object_create */
  balance_status_t st = balance_status_from_model(model_faces_find_hull(
      mesh_link, &obj->hull_link, com_guess_link_m, regime_cfg, NULL, 0, &nf));
  if (st != BALANCE_OK) return st;
  model_face_t *faces = malloc((nf > 0 ? nf : 1) * sizeof *faces);
  if (faces == NULL) return BALANCE_E_NOMEM;
  st = balance_status_from_model(model_faces_find_hull(mesh_link, &obj->hull_link, com_guess_link_m,
                                                       regime_cfg, faces, nf, &nf));
  size_t confirmed_count = 0;
  for (size_t i = 0; st == BALANCE_OK && i < nf; ++i) {
    if (!faces[i].candidate) continue;
    balance_trial_result_t r;
    int ok = 0;
    st = balance_stable_confirm(world, obj, faces[i].orientation_wxyz, com_guess_link_m, stable_cfg,
                                &r, &ok);
    if (st != BALANCE_OK) break;
    if (trials_run != NULL) ++*trials_run;
    if (!ok) continue;
    if (confirmed_count < capacity) {
      poses[confirmed_count].face = faces[i];
      poses[confirmed_count].trial = r;
    }
    ++confirmed_count;
  }
  if (st == BALANCE_OK) *count = confirmed_count;
  free(faces);
  return st;
}
