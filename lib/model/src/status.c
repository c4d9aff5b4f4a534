/* status.c - status strings and the error-message helpers of lib/model. */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "model_internal.h"

const char *model_status_str(model_status_t status) {
  switch (status) {
    case MODEL_OK: return "ok";
    case MODEL_E_ARG: return "invalid argument";
    case MODEL_E_NOFILE: return "file does not exist or cannot be read or written";
    case MODEL_E_PARSE: return "file is corrupt or not understood";
    case MODEL_E_NOLINK: return "no link of that name in the URDF";
    case MODEL_E_NOGEOM: return "link has no usable collision or visual geometry";
    case MODEL_E_OPEN: return "mesh is not closed (boundary or non-manifold edge)";
    case MODEL_E_ORIENT: return "mesh triangles are not consistently oriented";
    case MODEL_E_DEGENERATE: return "mesh is degenerate (empty, too few triangles or zero volume)";
    case MODEL_E_NONFINITE: return "a number is NaN or infinite";
    case MODEL_E_INERTIAL: return "missing or physically invalid mass or inertia";
    case MODEL_E_INERTIA_TRIANGLE:
      return "principal moments of inertia violate the triangle inequality";
    case MODEL_E_NOMEM: return "out of memory";
    case MODEL_E_UNSUPPORTED: return "unsupported format or geometry";
    case MODEL_E_REGION: return "invalid density region";
    case MODEL_E_HULL: return "convex hull failed";
    case MODEL_E_CHAIN: return "no usable kinematic chain between the links";
    case MODEL_E_IMPLAUSIBLE: return "mass properties implausible for a real object of that shape";
    case MODEL_E_POSE:
      return "absurd pose (not a unit quaternion, or nothing of the object over B)";
    case MODEL_E_CAPACITY: return "capacity exceeded";
  }
  return "unknown model status";
}

model_status_t model_fail(model_error_t *err, model_status_t status, const char *fmt, ...) {
  if (err != NULL) {
    va_list ap;
    va_start(ap, fmt);
    (void)vsnprintf(err->msg, sizeof err->msg, fmt, ap);
    va_end(ap);
  }
  return status;
}

void model_error_prefix(model_error_t *err, const char *fmt, ...) {
  if (err == NULL) {
    return;
  }
  char old[sizeof err->msg];
  memcpy(old, err->msg, sizeof old);
  old[sizeof old - 1] = '\0';
  va_list ap;
  va_start(ap, fmt);
  int n = vsnprintf(err->msg, sizeof err->msg, fmt, ap);
  va_end(ap);
  if (n >= 0 && (size_t)n < sizeof err->msg) {
    (void)snprintf(err->msg + n, sizeof err->msg - (size_t)n, "%s", old);
  }
}
