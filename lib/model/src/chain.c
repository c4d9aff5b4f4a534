/* chain.c - a URDF kinematic chain (comlearn/model_chain.h): urdf.cpp reads the joints, this file
 * checks the numbers, so a chain that loads is one FK can use as it is. */
#include <math.h>
#include <string.h>

#include "model_internal.h"

const char *model_joint_type_str(model_joint_type_t type) {
  switch (type) {
    case MODEL_JOINT_REVOLUTE: return "revolute";
    case MODEL_JOINT_CONTINUOUS: return "continuous";
    case MODEL_JOINT_PRISMATIC: return "prismatic";
    case MODEL_JOINT_FIXED: return "fixed";
  }
  return "unknown";
}

static int all_finite(const double *v, size_t n) {
  for (size_t i = 0; i < n; ++i) {
    if (!isfinite(v[i])) {
      return 0;
    }
  }
  return 1;
}

static model_status_t check_joint(const char *path, model_joint_t *j, model_error_t *err) {
  if (!all_finite(j->origin_xyz_m, 3) || !all_finite(j->origin_rpy_rad, 3) ||
      !all_finite(&j->origin_rot[0][0], 9)) {
    return model_fail(err, MODEL_E_NONFINITE, "URDF %s: joint '%s': origin is not finite", path,
                      j->name);
  }
  if (j->type == MODEL_JOINT_FIXED) {
    /* urdfdom leaves a fixed joint's axis at (1, 0, 0) or as written; it is never used. */
    j->axis[0] = 1.0;
    j->axis[1] = j->axis[2] = 0.0;
    return MODEL_OK;
  }
  if (!all_finite(j->axis, 3)) {
    return model_fail(err, MODEL_E_NONFINITE, "URDF %s: joint '%s': axis is not finite", path,
                      j->name);
  }
  double n = sqrt(j->axis[0] * j->axis[0] + j->axis[1] * j->axis[1] + j->axis[2] * j->axis[2]);
  if (!(n > 1e-12)) {
    return model_fail(err, MODEL_E_CHAIN, "URDF %s: joint '%s': axis (%g %g %g) is zero", path,
                      j->name, j->axis[0], j->axis[1], j->axis[2]);
  }
  for (int k = 0; k < 3; ++k) {
    j->axis[k] /= n;
  }
  if (isnan(j->velocity) || isinf(j->velocity)) {
    return model_fail(err, MODEL_E_NONFINITE, "URDF %s: joint '%s': velocity limit is not finite",
                      path, j->name);
  }
  if (j->velocity < 0.0) {
    return model_fail(err, MODEL_E_CHAIN, "URDF %s: joint '%s': velocity limit %g is negative",
                      path, j->name, j->velocity);
  }
  if (j->has_limits) {
    if (!isfinite(j->lower) || !isfinite(j->upper)) {
      return model_fail(err, MODEL_E_NONFINITE, "URDF %s: joint '%s': limits are not finite", path,
                        j->name);
    }
    if (j->lower > j->upper) {
      return model_fail(err, MODEL_E_CHAIN, "URDF %s: joint '%s': lower limit %g > upper %g", path,
                        j->name, j->lower, j->upper);
    }
  }
  return MODEL_OK;
}

model_status_t model_chain_load(const char *urdf_path, const char *base_link, const char *tip_link,
                                model_chain_t *out, model_error_t *err) {
  if (out == NULL) {
    return model_fail(err, MODEL_E_ARG, "model_chain_load: NULL output");
  }
  memset(out, 0, sizeof *out);
  if (urdf_path == NULL || base_link == NULL || tip_link == NULL || base_link[0] == '\0' ||
      tip_link[0] == '\0') {
    return model_fail(err, MODEL_E_ARG, "model_chain_load: NULL or empty argument");
  }
  model_status_t st = model_urdf_chain_read(urdf_path, base_link, tip_link, out, err);
  for (size_t i = 0; st == MODEL_OK && i < out->joint_count; ++i) {
    st = check_joint(urdf_path, &out->joints[i], err);
    if (out->joints[i].type != MODEL_JOINT_FIXED) {
      out->moving_count++;
    }
  }
  if (st != MODEL_OK) {
    memset(out, 0, sizeof *out);
  }
  return st;
}
