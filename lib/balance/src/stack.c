/* stack.c - stacks of objects: the pose that sets one object onto another, and a run that
 * reports whether the stack stands. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "balance_internal.h"
#include "comlearn/balance_stack.h"
#include "comlearn/math3d.h"
#include "comlearn/model_support.h"

void balance_stack_config_default(balance_stack_config_t *cfg) {
  if (cfg == NULL) return;
  cfg->duration_s = 5.0;
  cfg->max_displacement_m = 0.005;
  cfg->max_rotation_rad = 0.05;
  cfg->run_to_end = 0;
}

static balance_status_t stack_config_resolve(const balance_stack_config_t *cfg,
                                             balance_stack_config_t *out) {
  balance_stack_config_default(out);
  if (cfg == NULL) return BALANCE_OK;
  if (!isfinite(cfg->duration_s) || !isfinite(cfg->max_displacement_m) ||
      !isfinite(cfg->max_rotation_rad))
    return BALANCE_E_NONFINITE;
  /* An hour of simulated time at 1 ms is 3.6e6 steps: the loop stays bounded. */
  if (!(cfg->duration_s > 0.0) || cfg->duration_s > 3600.0 || !(cfg->max_displacement_m > 0.0) ||
      !(cfg->max_rotation_rad > 0.0))
    return BALANCE_E_ARG;
  *out = *cfg;
  return BALANCE_OK;
}

/* Every object non-NULL, in this world, listed once; every pose usable. */
static balance_status_t stack_inputs_check(const balance_world_t *world,
                                           balance_object_t *const *objects,
                                           const model_pose_t *poses, size_t count) {
  for (size_t i = 0; i < count; ++i) {
    if (objects[i] == NULL || objects[i]->world != world) return BALANCE_E_ARG;
    for (size_t j = 0; j < i; ++j) {
      if (objects[j] == objects[i]) return BALANCE_E_ARG;
    }
    model_pose_t checked;
    const balance_status_t st = balance_pose_check(&poses[i], &checked);
    if (st != BALANCE_OK) return st;
  }
  return BALANCE_OK;
}

/* Per object: the pose at release and the largest displacement and rotation from it so far, and
 * when it first moved beyond the thresholds (-1 if not yet); the pose at the start of the rest
 * window (late), taken at step late_step. */
typedef struct {
  model_pose_t *released, *late;
  double *disp, *rot, *moved;
  double first_moved;
  uint32_t late_step;
} stack_track_t;

static void stack_poses_get(balance_object_t *const *objects, size_t count, model_pose_t *out) {
  for (size_t i = 0; i < count; ++i) balance_object_pose_get(objects[i], &out[i]);
}

/* How far pose p lies from pose q: the distance of the link origins and the rotation angle. */
static void pose_apart(const model_pose_t *p, const model_pose_t *q, double *d_m, double *a_rad) {
  double d[3];
  cl_vec3_sub(p->position_m, q->position_m, d);
  *d_m = sqrt(cl_vec3_dot(d, d));
  *a_rad = cl_quat_angle(p->orientation_wxyz, q->orientation_wxyz);
}

static void stack_track_update(balance_object_t *const *objects, size_t count,
                               const balance_stack_config_t *sc, double t, stack_track_t *tr) {
  for (size_t i = 0; i < count; ++i) {
    model_pose_t p;
    double d, a;
    balance_object_pose_get(objects[i], &p);
    pose_apart(&p, &tr->released[i], &d, &a);
    if (d > tr->disp[i]) tr->disp[i] = d;
    if (a > tr->rot[i]) tr->rot[i] = a;
    if (tr->moved[i] < 0.0 && (d > sc->max_displacement_m || a > sc->max_rotation_rad)) {
      tr->moved[i] = t;
      if (tr->first_moved < 0.0) tr->first_moved = t;
    }
  }
}

/* Steps the world for sc->duration_s (or until the first object moves, unless run_to_end);
 * *steps_done is the number of steps taken when the stepping did not fail. */
static balance_status_t stack_simulate(balance_world_t *world, balance_object_t *const *objects,
                                       size_t count, const balance_stack_config_t *sc,
                                       stack_track_t *tr, uint32_t *steps_done) {
  balance_status_t st = BALANCE_OK;
  const double dt = balance_world_config(world)->dt_s;
  const uint32_t steps = (uint32_t)ceil(sc->duration_s / dt - 1e-9);
  const uint32_t window = (uint32_t)ceil(BALANCE_STACK_REST_WINDOW_S / dt - 1e-9);
  tr->late_step = steps > window ? steps - window : 0;
  uint32_t s = 0;
  for (; s < steps; ++s) {
    if (s == tr->late_step) stack_poses_get(objects, count, tr->late);
    st = balance_world_step(world);
    if (st != BALANCE_OK) break;
    stack_track_update(objects, count, sc, balance_world_time(world), tr);
    if (tr->first_moved >= 0.0 && !sc->run_to_end) {
      ++s;
      break;
    }
  }
  *steps_done = s;
  return st;
}

static void stack_result_fill(balance_world_t *world, balance_object_t *const *objects,
                              size_t count, const balance_stack_config_t *sc,
                              const stack_track_t *tr, uint32_t steps,
                              balance_stack_result_t *result, balance_stack_object_t *per_object) {
  result->stands = tr->first_moved < 0.0;
  result->seconds_standing = tr->first_moved < 0.0 ? sc->duration_s : tr->first_moved;
  result->sim_time_s = balance_world_time(world);
  result->steps = steps;
  /* A run stopped before its rest window began (an object moved) measures from the release. */
  const model_pose_t *from = steps > tr->late_step ? tr->late : tr->released;
  for (size_t i = 0; per_object != NULL && i < count; ++i) {
    balance_object_pose_get(objects[i], &per_object[i].final_pose);
    per_object[i].displacement_m = tr->disp[i];
    per_object[i].rotation_rad = tr->rot[i];
    per_object[i].moved_at_s = tr->moved[i];
    pose_apart(&per_object[i].final_pose, &from[i], &per_object[i].late_displacement_m,
               &per_object[i].late_rotation_rad);
  }
}

balance_status_t balance_stack_run(balance_world_t *world, balance_object_t *const *objects,
                                   const model_pose_t *poses, size_t count,
                                   const balance_stack_config_t *cfg,
                                   balance_stack_result_t *result,
                                   balance_stack_object_t *per_object) {
  if (world == NULL || objects == NULL || poses == NULL || result == NULL || count == 0)
    return BALANCE_E_ARG;
  balance_stack_config_t sc;
  balance_status_t st = stack_config_resolve(cfg, &sc);
  if (st != BALANCE_OK) return st;
  st = stack_inputs_check(world, objects, poses, count);
  if (st != BALANCE_OK) return st;
  memset(result, 0, sizeof *result);
  balance_world_reset(world);
  for (size_t i = 0; i < count && st == BALANCE_OK; ++i)
    st = balance_object_place(objects[i], &poses[i]);
  if (st != BALANCE_OK) {
    balance_world_reset(world);
    return st;
  }
  model_pose_t *released = malloc(2 * count * sizeof *released);
  double *track = malloc(3 * count * sizeof *track);
  if (released == NULL || track == NULL) {
    free(released);
    free(track);
    balance_world_reset(world);
    return BALANCE_E_NOMEM;
  }
  stack_track_t tr = {.released = released,
                      .late = released + count,
                      .disp = track,
                      .rot = track + count,
                      .moved = track + 2 * count,
                      .first_moved = -1.0};
  for (size_t i = 0; i < count; ++i) {
    balance_object_pose_get(objects[i], &released[i]);
    tr.disp[i] = 0.0;
    tr.rot[i] = 0.0;
    tr.moved[i] = -1.0;
  }
  uint32_t steps = 0;
  st = stack_simulate(world, objects, count, &sc, &tr, &steps);
  if (st == BALANCE_OK)
    stack_result_fill(world, objects, count, &sc, &tr, steps, result, per_object);
  for (size_t i = 0; i < count; ++i) balance_object_remove(objects[i]);
  free(released);
  free(track);
  return st;
}

/* ---- setting one object onto another ------------------------------------------------------ */

typedef struct {
  double (*w)[3];   /* world vertices */
  uint32_t (*e)[2]; /* unique edges */
  size_t ne;
  const model_mesh_t *m;
} placed_t;

static balance_status_t placed_build(const model_mesh_t *m, const double q[4], const double p[3],
                                     placed_t *out) {
  out->m = m;
  out->ne = 0;
  out->w = malloc(m->vertex_count * sizeof *out->w);
  out->e = malloc(3 * m->triangle_count * sizeof *out->e);
  if (out->w == NULL || out->e == NULL) return BALANCE_E_NOMEM;
  for (size_t v = 0; v < m->vertex_count; ++v) {
    cl_quat_rotate(q, m->vertices_m[v], out->w[v]);
    for (int k = 0; k < 3; ++k) out->w[v][k] += p[k];
  }
  /* A closed mesh has every edge once in each direction: keep the increasing one. Open or
   * non-manifold input only repeats work. */
  for (size_t t = 0; t < m->triangle_count; ++t) {
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = m->triangles[t][k], b = m->triangles[t][(k + 1) % 3];
      if (a < b) {
        out->e[out->ne][0] = a;
        out->e[out->ne][1] = b;
        ++out->ne;
      }
    }
  }
  return BALANCE_OK;
}

static void placed_free(placed_t *p) {
  free(p->w);
  free(p->e);
}

/* z of triangle abc (world) above x, y when the point is inside its vertical projection. */
static int tri_z_at(const double a[3], const double b[3], const double c[3], const double x,
                    const double y, double *z) {
  const double d = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
  if (fabs(d) < 1e-18) return 0; /* vertical: its edges cover it */
  const double u = ((x - a[0]) * (c[1] - a[1]) - (y - a[1]) * (c[0] - a[0])) / d;
  const double v = ((b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0])) / d;
  if (u < 0.0 || v < 0.0 || u + v > 1.0) return 0;
  *z = a[2] + u * (b[2] - a[2]) + v * (c[2] - a[2]);
  return 1;
}

/* Largest (lower z - upper z) over points of `lo` and `up` on one vertical line, with `up` at
 * its current height: how far `up` must rise to sit on `lo`. -HUGE_VAL if nothing overlaps. */
static double rise_needed(const placed_t *lo, const placed_t *up) {
  double need = -HUGE_VAL, z;
  /* Vertices of one over / under triangles of the other. */
  for (int pass = 0; pass < 2; ++pass) {
    const placed_t *pv = pass == 0 ? up : lo, *pt = pass == 0 ? lo : up;
    for (size_t t = 0; t < pt->m->triangle_count; ++t) {
      const double *a = pt->w[pt->m->triangles[t][0]], *b = pt->w[pt->m->triangles[t][1]],
                   *c = pt->w[pt->m->triangles[t][2]];
      const double x0 = fmin(a[0], fmin(b[0], c[0])), x1 = fmax(a[0], fmax(b[0], c[0]));
      const double y0 = fmin(a[1], fmin(b[1], c[1])), y1 = fmax(a[1], fmax(b[1], c[1]));
      for (size_t v = 0; v < pv->m->vertex_count; ++v) {
        const double *p = pv->w[v];
        if (p[0] < x0 || p[0] > x1 || p[1] < y0 || p[1] > y1) continue;
        if (!tri_z_at(a, b, c, p[0], p[1], &z)) continue;
        const double r = pass == 0 ? z - p[2] : p[2] - z;
        if (r > need) need = r;
      }
    }
  }
  /* Edges crossing in projection. */
  for (size_t i = 0; i < up->ne; ++i) {
    const double *a = up->w[up->e[i][0]], *b = up->w[up->e[i][1]];
    const double ax0 = fmin(a[0], b[0]), ax1 = fmax(a[0], b[0]);
    const double ay0 = fmin(a[1], b[1]), ay1 = fmax(a[1], b[1]);
    for (size_t j = 0; j < lo->ne; ++j) {
      const double *c = lo->w[lo->e[j][0]], *d = lo->w[lo->e[j][1]];
      if (fmax(c[0], d[0]) < ax0 || fmin(c[0], d[0]) > ax1 || fmax(c[1], d[1]) < ay0 ||
          fmin(c[1], d[1]) > ay1)
        continue;
      const double r0 = b[0] - a[0], r1 = b[1] - a[1], s0 = d[0] - c[0], s1 = d[1] - c[1];
      const double den = r0 * s1 - r1 * s0;
      if (fabs(den) < 1e-18) continue;
      const double t = ((c[0] - a[0]) * s1 - (c[1] - a[1]) * s0) / den;
      const double u = ((c[0] - a[0]) * r1 - (c[1] - a[1]) * r0) / den;
      if (t < 0.0 || t > 1.0 || u < 0.0 || u > 1.0) continue;
      const double zu = a[2] + t * (b[2] - a[2]), zl = c[2] + u * (d[2] - c[2]);
      if (zl - zu > need) need = zl - zu;
    }
  }
  return need;
}

balance_status_t balance_stack_pose_above(const model_mesh_t *below_link,
                                          const model_pose_t *below_pose,
                                          const model_mesh_t *mesh_link,
                                          const double orientation_wxyz[4],
                                          const double point_link_m[3], const double at_xy_m[2],
                                          double touch_depth_m, model_pose_t *out) {
  if (below_pose == NULL || orientation_wxyz == NULL || point_link_m == NULL || at_xy_m == NULL ||
      out == NULL)
    return BALANCE_E_ARG;
  balance_status_t st = balance_status_from_model(model_mesh_usable(below_link));
  if (st == BALANCE_OK) st = balance_status_from_model(model_mesh_usable(mesh_link));
  if (st != BALANCE_OK) return st;
  if (!isfinite(touch_depth_m) || !isfinite(at_xy_m[0]) || !isfinite(at_xy_m[1]))
    return BALANCE_E_NONFINITE;
  for (int k = 0; k < 3; ++k) {
    if (!isfinite(point_link_m[k]) || !isfinite(below_pose->position_m[k]))
      return BALANCE_E_NONFINITE;
  }
  if (touch_depth_m < 0.0 || touch_depth_m > 1e-3) return BALANCE_E_ARG;
  double qb[4], qu[4];
  st = balance_status_from_model(model_quat_unit(below_pose->orientation_wxyz, qb));
  if (st == BALANCE_OK) st = balance_status_from_model(model_quat_unit(orientation_wxyz, qu));
  if (st != BALANCE_OK) return st;
  double pw[3];
  cl_quat_rotate(qu, point_link_m, pw);
  const double pos[3] = {at_xy_m[0] - pw[0], at_xy_m[1] - pw[1], 0.0};
  placed_t lo = {0}, up = {0};
  st = placed_build(below_link, qb, below_pose->position_m, &lo);
  if (st == BALANCE_OK) st = placed_build(mesh_link, qu, pos, &up);
  if (st == BALANCE_OK) {
    const double rise = rise_needed(&lo, &up);
    if (rise == -HUGE_VAL) {
      st = BALANCE_E_POSE;
    } else {
      memcpy(out->orientation_wxyz, qu, sizeof qu);
      out->position_m[0] = pos[0];
      out->position_m[1] = pos[1];
      out->position_m[2] = rise - touch_depth_m;
    }
  }
  placed_free(&lo);
  placed_free(&up);
  return st;
}
