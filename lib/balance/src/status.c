/* status.c - status strings (and lib/model's mapped to ours) and the default configuration. */
#include <math.h>

#include "balance_internal.h"

const char *balance_status_str(balance_status_t status) {
  switch (status) {
    case BALANCE_OK: return "ok";
    case BALANCE_E_ARG: return "invalid argument";
    case BALANCE_E_NONFINITE: return "non-finite number in the input";
    case BALANCE_E_MASS: return "invalid mass properties";
    case BALANCE_E_MESH: return "mesh not usable for contacts";
    case BALANCE_E_POSE:
      return "absurd pose (far away, deep inside the base block, or not a unit quaternion)";
    case BALANCE_E_NOMEM: return "out of memory";
    case BALANCE_E_DIVERGED: return "the simulation diverged (non-finite state)";
    case BALANCE_E_CAPACITY: return "capacity exceeded";
  }
  return "unknown status";
}

balance_status_t balance_status_from_model(model_status_t status) {
  switch (status) {
    case MODEL_OK: return BALANCE_OK;
    case MODEL_E_ARG: return BALANCE_E_ARG;
    case MODEL_E_NONFINITE: return BALANCE_E_NONFINITE;
    case MODEL_E_POSE: return BALANCE_E_POSE;
    case MODEL_E_NOMEM: return BALANCE_E_NOMEM;
    case MODEL_E_CAPACITY: return BALANCE_E_CAPACITY;
    default: return BALANCE_E_MESH; /* the mesh does not give the geometry asked for */
  }
}

void balance_config_default(balance_config_t *cfg) {
  if (!cfg) return;
  cfg->base_size_m[0] = 0.30;
  cfg->base_size_m[1] = 0.30;
  cfg->base_size_m[2] = 0.10;
  cfg->gravity_m_s2 = 9.81;
  cfg->dt_s = 1e-3;
  cfg->friction = 0.8;
  cfg->soft_erp = 0.2;
  cfg->soft_cfm = 1e-7;
  cfg->contact = BALANCE_CONTACT_FAST;
  cfg->max_contacts = 8;
  cfg->rest_min_time_s = 0.03;
  cfg->rest_lin_m_s = 1e-3;
  cfg->rest_ang_rad_s = 1e-2;
  cfg->rest_steps = 10;
  cfg->tip_grow_steps = 20;
  cfg->horizon_s = 0.75;
  cfg->tip_angle_rad = 0.35;
  cfg->slide_m = 0.005;
}

static int finite_in(double v, double lo, double hi) { return isfinite(v) && v >= lo && v <= hi; }

balance_status_t balance_config_check(const balance_config_t *cfg) {
  if (!cfg) return BALANCE_E_ARG;
  const double d[] = {cfg->base_size_m[0], cfg->base_size_m[1], cfg->base_size_m[2],
                      cfg->gravity_m_s2,   cfg->dt_s,           cfg->friction,
                      cfg->soft_erp,       cfg->soft_cfm,       cfg->rest_min_time_s,
                      cfg->rest_lin_m_s,   cfg->rest_ang_rad_s, cfg->horizon_s,
                      cfg->tip_angle_rad,  cfg->slide_m};
  for (size_t i = 0; i < sizeof d / sizeof d[0]; i++)
    if (!isfinite(d[i])) return BALANCE_E_NONFINITE;
  for (int i = 0; i < 3; i++)
    if (!finite_in(cfg->base_size_m[i], 1e-3, 100.0)) return BALANCE_E_ARG;
  if (!finite_in(cfg->gravity_m_s2, 0.0, 1e3)) return BALANCE_E_ARG;
  if (!finite_in(cfg->dt_s, 1e-6, 0.1)) return BALANCE_E_ARG;
  if (!finite_in(cfg->friction, 0.0, 1e3)) return BALANCE_E_ARG;
  if (!finite_in(cfg->soft_erp, 0.0, 1.0)) return BALANCE_E_ARG;
  if (!finite_in(cfg->soft_cfm, 0.0, 1.0)) return BALANCE_E_ARG;
  if (cfg->contact != BALANCE_CONTACT_FAST && cfg->contact != BALANCE_CONTACT_STOCK)
    return BALANCE_E_ARG;
  if (cfg->max_contacts < 4 || cfg->max_contacts > 64) return BALANCE_E_ARG;
  if (!finite_in(cfg->rest_min_time_s, 0.0, 1e3)) return BALANCE_E_ARG;
  if (!finite_in(cfg->rest_lin_m_s, 0.0, 1e3) || cfg->rest_lin_m_s <= 0.0) return BALANCE_E_ARG;
  if (!finite_in(cfg->rest_ang_rad_s, 0.0, 1e3) || cfg->rest_ang_rad_s <= 0.0) return BALANCE_E_ARG;
  if (cfg->rest_steps < 1 || cfg->rest_steps > 1000000) return BALANCE_E_ARG;
  if (cfg->tip_grow_steps < 1 || cfg->tip_grow_steps > 1000000) return BALANCE_E_ARG;
  if (!finite_in(cfg->horizon_s, cfg->dt_s, 1e4)) return BALANCE_E_ARG;
  if (!finite_in(cfg->tip_angle_rad, 1e-6, CL_PI)) return BALANCE_E_ARG;
  if (!finite_in(cfg->slide_m, 1e-9, 100.0)) return BALANCE_E_ARG;
  if (cfg->horizon_s / cfg->dt_s > 1e8) return BALANCE_E_ARG;
  return BALANCE_OK;
}
