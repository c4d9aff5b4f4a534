/* trial.c - one placement trial: release touching B, step, decide stays / tips / slides. */
#include <math.h>
#include <string.h>

#include "balance_internal.h"
#include "comlearn/math3d.h"

double balance_slide_max_rotation_rad(const balance_config_t *cfg) {
  return 0.25 * cfg->tip_angle_rad;
}

int balance_trial_slid(const balance_config_t *cfg, const double from_m[3], const double to_m[3],
                       double rotation_rad) {
  if (!cfg || !from_m || !to_m) return 0;
  return hypot(to_m[0] - from_m[0], to_m[1] - from_m[1]) > cfg->slide_m &&
         rotation_rad < balance_slide_max_rotation_rad(cfg);
}

/* Noise check and the placement perturbation of the release; the RNG and the pose noise for the
 * settled pose come back through rng and pose_noise. */
static balance_status_t trial_noise_apply(const balance_noise_t *noise, model_pose_t *rel,
                                          uint64_t *rng, double *pose_noise) {
  if (!isfinite(noise->placement_noise_m) || !isfinite(noise->pose_noise_m))
    return BALANCE_E_NONFINITE;
  if (noise->placement_noise_m < 0.0 || noise->placement_noise_m > 0.1 ||
      noise->pose_noise_m < 0.0 || noise->pose_noise_m > 0.1)
    return BALANCE_E_ARG;
  *rng = noise->seed;
  double g[2];
  cl_rng_normal2(rng, g);
  rel->position_m[0] += noise->placement_noise_m * g[0];
  rel->position_m[1] += noise->placement_noise_m * g[1];
  *pose_noise = noise->pose_noise_m;
  return BALANCE_OK;
}

/* What the trial watches from step to step. */
typedef struct {
  const balance_config_t *cfg;
  const model_pose_t *rel;
  double com0[3];
  double hx, hy;
  uint32_t min_rest_steps;
  uint32_t quiet, grow;
  double om_prev;
  double rot_max, move_max; /* over the trial: rotation from release, the CoM's displacement */
  int beyond;               /* the CoM beyond B's footprint at the last step */
} trial_watch_t;

/* A body that has not moved by the horizon: rotated at most STILL_ROT_RAD from release and its
 * CoM within STILL_M of where it started, at every step, its CoM over B. On a rough face (a
 * scanned mesh's 2 um bumps) the fast contact path can hold a body in a limit cycle: it rocks
 * between contact sets at a few 1e-2 rad/s with a period of a few steps and an amplitude of
 * 5e-5 rad, so the velocity test never sees rest, while the pose stays put. Such a body stays.
 * A body tipping over the edge too slowly for the trend test turns more than 1e-3 rad within
 * the 0.75 s horizon unless its CoM is within a micron of the edge (docs/physics.md). */
#define STILL_ROT_RAD 1e-3
#define STILL_M 1e-5

/* One step's verdict after `steps` steps: BALANCE_INVALID while undecided. */
static balance_outcome_t trial_watch_step(trial_watch_t *tw, const balance_object_t *obj,
                                          uint32_t steps) {
  const balance_config_t *cfg = tw->cfg;
  const double hx = tw->hx, hy = tw->hy;
  model_pose_t now;
  balance_object_pose_get(obj, &now);
  double com[3], v[3], om[3];
  balance_object_com_get(obj, com);
  balance_object_velocity_get(obj, v, om);
  const double rot = cl_quat_angle(tw->rel->orientation_wxyz, now.orientation_wxyz);
  const double wn = cl_vec3_norm(om), vn = cl_vec3_norm(v);
  const int beyond = fabs(com[0]) > hx || fabs(com[1]) > hy;
  const double move[3] = {com[0] - tw->com0[0], com[1] - tw->com0[1], com[2] - tw->com0[2]};
  tw->rot_max = fmax(tw->rot_max, rot);
  tw->move_max = fmax(tw->move_max, cl_vec3_norm(move));
  tw->beyond = beyond;
  /* Clearly tipped: turned far, fallen below the top, or gone beyond the edge. */
  if (rot > cfg->tip_angle_rad || com[2] < 0.0 || fabs(com[0]) > hx + obj->radius_m ||
      fabs(com[1]) > hy + obj->radius_m)
    return BALANCE_TIPS;
  if (balance_trial_slid(cfg, tw->com0, com, rot)) return BALANCE_SLIDES;
  /* Released at rest, a body that stays only loses the contact transient: its angular speed
   * decays geometrically (by the ERP fraction per step) down to rounding noise. A body with its
   * CoM beyond the edge pivots on it like an inverted pendulum: its angular speed grows every
   * step, from the first milliseconds and however close to the edge the CoM is. Telling the two
   * apart by the trend, not by a speed threshold, is what makes short trials exact: a speed
   * threshold calls a slowly tipping body "at rest" (an outward bias of microns). */
  const int growing = wn > tw->om_prev && wn > 1e-11;
  tw->grow = growing ? tw->grow + 1 : 0;
  if (beyond && tw->grow >= (uint32_t)cfg->tip_grow_steps) return BALANCE_TIPS;
  if (vn < cfg->rest_lin_m_s && wn < cfg->rest_ang_rad_s && !growing)
    tw->quiet++;
  else
    tw->quiet = 0;
  tw->om_prev = wn;
  if (steps >= tw->min_rest_steps && tw->quiet >= (uint32_t)cfg->rest_steps) return BALANCE_STAYS;
  return BALANCE_INVALID;
}

/* The result fields after the run: settled pose (with pose noise), displacement, rotation, time. */
static void trial_result_fill(const balance_config_t *cfg, const balance_object_t *obj,
                              const model_pose_t *rel, uint64_t *rng, double pose_noise,
                              balance_outcome_t outcome, uint32_t steps,
                              balance_trial_result_t *out) {
  out->outcome = outcome;
  out->released = *rel;
  balance_object_pose_get(obj, &out->settled);
  if (pose_noise > 0.0) {
    double g[2];
    cl_rng_normal2(rng, g);
    out->settled.position_m[0] += pose_noise * g[0];
    out->settled.position_m[1] += pose_noise * g[1];
    cl_rng_normal2(rng, g);
    out->settled.position_m[2] += pose_noise * g[0];
  }
  double d[3];
  for (int i = 0; i < 3; i++) d[i] = out->settled.position_m[i] - rel->position_m[i];
  out->displacement_m = cl_vec3_norm(d);
  out->rotation_rad = cl_quat_angle(rel->orientation_wxyz, out->settled.orientation_wxyz);
  out->sim_time_s = (double)steps * cfg->dt_s;
  out->steps = steps;
}

/* The placement offset moved the release from `asked` into B (a part of the object hanging below
 * B's top beyond the edge, pushed into B's side): the hand is stopped where the object meets B.
 * *rel is moved back along the offset to the farthest point (bisection, to 1e-6 of the offset)
 * that is not deeper in B than balance_object_place allows. Unchanged when the offset release
 * places, or when the asked one does not either (its own error is reported then). */
static void trial_offset_stopped(const balance_object_t *obj, const model_pose_t *asked,
                                 model_pose_t *rel) {
  if (balance_object_penetration_m(obj, rel) <= BALANCE_MAX_START_DEPTH_M ||
      balance_object_penetration_m(obj, asked) > BALANCE_MAX_START_DEPTH_M)
    return;
  double off[2] = {rel->position_m[0] - asked->position_m[0],
                   rel->position_m[1] - asked->position_m[1]};
  double lo = 0.0, hi = 1.0;
  model_pose_t p = *asked;
  for (int i = 0; i < 20; ++i) {
    const double t = 0.5 * (lo + hi);
    for (int k = 0; k < 2; ++k) p.position_m[k] = asked->position_m[k] + t * off[k];
    if (balance_object_penetration_m(obj, &p) <= BALANCE_MAX_START_DEPTH_M)
      lo = t;
    else
      hi = t;
  }
  for (int k = 0; k < 2; ++k) rel->position_m[k] = asked->position_m[k] + lo * off[k];
}

uint64_t balance_noise_seed(uint64_t run_seed, uint64_t n) {
  uint64_t state = run_seed ^ (0x9E3779B97F4A7C15ull * n);
  return cl_rng_next(&state);
}

balance_status_t balance_trial_run(balance_world_t *w, balance_object_t *obj,
                                   const model_pose_t *release, const balance_noise_t *noise,
                                   balance_trial_result_t *out) {
  if (!w || !obj || !release || !out || obj->world != w) return BALANCE_E_ARG;
  memset(out, 0, sizeof *out);
  model_pose_t rel;
  balance_status_t st = balance_pose_check(release, &rel);
  if (st != BALANCE_OK) return st;
  uint64_t rng = 0;
  double pose_noise = 0.0;
  if (noise) {
    const model_pose_t asked = rel;
    st = trial_noise_apply(noise, &rel, &rng, &pose_noise);
    if (st != BALANCE_OK) return st;
    trial_offset_stopped(obj, &asked, &rel);
  }
  balance_world_reset(w);
  st = balance_object_place(obj, &rel);
  if (st != BALANCE_OK) return st;

  const balance_config_t *cfg = &w->cfg;
  trial_watch_t tw = {.cfg = cfg,
                      .rel = &rel,
                      .hx = 0.5 * cfg->base_size_m[0],
                      .hy = 0.5 * cfg->base_size_m[1],
                      .om_prev = INFINITY};
  balance_object_com_get(obj, tw.com0);
  const uint32_t max_steps = (uint32_t)ceil(cfg->horizon_s / cfg->dt_s - 1e-9);
  tw.min_rest_steps = (uint32_t)ceil(cfg->rest_min_time_s / cfg->dt_s - 1e-9);
  uint32_t steps = 0;
  balance_outcome_t outcome = BALANCE_INVALID;
  while (steps < max_steps) {
    st = balance_world_step(w);
    steps++;
    if (st != BALANCE_OK) {
      balance_object_remove(obj);
      return st;
    }
    outcome = trial_watch_step(&tw, obj, steps);
    if (outcome != BALANCE_INVALID) break;
  }
  if (outcome == BALANCE_INVALID && steps == max_steps && !tw.beyond &&
      tw.rot_max <= STILL_ROT_RAD && tw.move_max <= STILL_M)
    outcome = BALANCE_STAYS; /* held still in a contact limit cycle (above) */
  trial_result_fill(cfg, obj, &rel, &rng, pose_noise, outcome, steps, out);
  balance_object_remove(obj);
  return BALANCE_OK;
}
