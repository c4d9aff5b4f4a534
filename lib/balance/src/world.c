/* world.c - the ODE world with base block B, one step of it, and pose helpers. */
#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "balance_internal.h"

/* ODE prints "ODE Message" warnings (e.g. LCP internal errors) to stderr; a library stays quiet.
 * Errors and debug checks still abort inside ODE: inputs are validated before they get there. */
static void ode_message_silent(int num, const char *msg, va_list ap) {
  (void)num;
  (void)msg;
  (void)ap;
}

static pthread_once_t ode_once = PTHREAD_ONCE_INIT;
static int ode_init_ok;

static void ode_init_once(void) {
  ode_init_ok = dInitODE2(0) != 0;
  dSetMessageHandler(ode_message_silent);
}

balance_status_t balance_pose_check(const model_pose_t *in, model_pose_t *out) {
  if (!in || !out) return BALANCE_E_ARG;
  for (int i = 0; i < 3; i++)
    if (!isfinite(in->position_m[i])) return BALANCE_E_NONFINITE;
  for (int i = 0; i < 4; i++)
    if (!isfinite(in->orientation_wxyz[i])) return BALANCE_E_NONFINITE;
  for (int i = 0; i < 3; i++)
    if (fabs(in->position_m[i]) > BALANCE_MAX_POSITION_M) return BALANCE_E_POSE;
  const double *q = in->orientation_wxyz;
  const double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (!(fabs(n - 1.0) <= BALANCE_QUAT_NORM_TOL)) return BALANCE_E_POSE;
  model_pose_t p = *in;
  for (int i = 0; i < 4; i++) p.orientation_wxyz[i] = q[i] / n;
  *out = p;
  return BALANCE_OK;
}

balance_status_t balance_world_create(const balance_config_t *cfg, balance_world_t **out) {
  if (!out) return BALANCE_E_ARG;
  *out = NULL;
  balance_status_t st = balance_config_check(cfg);
  if (st != BALANCE_OK) return st;
  pthread_once(&ode_once, ode_init_once);
  if (!ode_init_ok) return BALANCE_E_NOMEM;
  /* Trimesh colliders keep per-thread data: allocate it for the calling thread (idempotent). */
  if (!dAllocateODEDataForThread(~0u)) return BALANCE_E_NOMEM;

  balance_world_t *w = calloc(1, sizeof *w);
  if (!w) return BALANCE_E_NOMEM;
  w->cfg = *cfg;
  w->ode = dWorldCreate();
  w->contact_group = dJointGroupCreate(0);
  /* Auto-disable must be off before any body exists: ODE puts a body balanced near the edge to
   * sleep before it tips, and per-body settings do not reset the first countdown. */
  dWorldSetAutoDisableFlag(w->ode, 0);
  dWorldSetGravity(w->ode, 0.0, 0.0, -cfg->gravity_m_s2);
  dWorldSetERP(w->ode, cfg->soft_erp);
  dWorldSetCFM(w->ode, cfg->soft_cfm);
  dWorldSetContactSurfaceLayer(w->ode, 0.0);
  w->base_geom = dCreateBox(0, cfg->base_size_m[0], cfg->base_size_m[1], cfg->base_size_m[2]);
  dGeomSetPosition(w->base_geom, 0.0, 0.0, -0.5 * cfg->base_size_m[2]);
  w->raw_capacity = 1024;
  w->raw = malloc(w->raw_capacity * sizeof *w->raw);
  if (!w->raw) {
    balance_world_destroy(w);
    return BALANCE_E_NOMEM;
  }
  *out = w;
  return BALANCE_OK;
}

static void object_free(balance_object_t *obj);

void balance_world_destroy(balance_world_t *w) {
  if (!w) return;
  for (size_t i = 0; i < w->object_count; i++) object_free(w->objects[i]);
  free(w->objects);
  free(w->raw);
  free(w->points);
  free(w->pair_prev);
  free(w->pair_now);
  free(w->pair_feedback);
  if (w->base_geom) dGeomDestroy(w->base_geom);
  if (w->contact_group) dJointGroupDestroy(w->contact_group);
  if (w->ode) dWorldDestroy(w->ode);
  free(w);
}

const balance_config_t *balance_world_config(const balance_world_t *w) {
  return w ? &w->cfg : NULL;
}

size_t balance_world_object_count(const balance_world_t *w) { return w ? w->object_count : 0; }

balance_object_t *balance_world_object(balance_world_t *w, size_t i) {
  return (w && i < w->object_count) ? w->objects[i] : NULL;
}

void balance_world_reset(balance_world_t *w) {
  if (!w) return;
  for (size_t i = 0; i < w->object_count; i++) balance_object_remove(w->objects[i]);
  dJointGroupEmpty(w->contact_group);
  w->time_s = 0.0;
}

double balance_world_time(const balance_world_t *w) { return w ? w->time_s : 0.0; }

static int points_reserve(balance_world_t *w, size_t n) {
  if (n <= w->point_capacity) return 1;
  balance_point_t *p = realloc(w->points, n * sizeof *p);
  if (!p) return 0;
  w->points = p;
  w->point_capacity = n;
  return 1;
}

static void object_free(balance_object_t *obj) { balance_object_destroy_internal(obj); }

balance_status_t balance_world_add_object_internal(balance_world_t *w, balance_object_t *obj,
                                                   size_t points_needed) {
  if (w->object_count == w->object_capacity) {
    size_t cap = w->object_capacity ? 2 * w->object_capacity : 4;
    balance_object_t **o = realloc(w->objects, cap * sizeof *o);
    if (!o) return BALANCE_E_NOMEM;
    w->objects = o;
    w->object_capacity = cap;
  }
  if (!points_reserve(w, points_needed)) return BALANCE_E_NOMEM;
  obj->index = w->object_count;
  w->objects[w->object_count++] = obj;
  return BALANCE_OK;
}

/* All contacts of one ODE collision between two geoms: the scratch grows (and the call is
 * repeated) when full, so the set is never truncated (OPCODE returns contacts in tree order: a
 * truncated set is lopsided). Returns the count or -1 on allocation failure. */
static long collide_all(balance_world_t *w, dGeomID a, dGeomID b) {
  for (int attempt = 0; attempt < 8; attempt++) {
    int cap = w->raw_capacity > 0xffff ? 0xffff : (int)w->raw_capacity;
    int n = dCollide(a, b, cap, w->raw, (int)sizeof(dContactGeom));
    if (n < cap || cap == 0xffff) return n;
    size_t ncap = 2 * w->raw_capacity;
    dContactGeom *r = realloc(w->raw, ncap * sizeof *r);
    if (!r) return -1;
    w->raw = r;
    w->raw_capacity = ncap;
  }
  return -1;
}

/* Copy usable ODE contacts to points: drop non-finite ones and zero normals (libccd and OPCODE
 * can return a zero normal at exact touch, which turns the body into NaN). */
size_t balance_points_from_ode(const dContactGeom *raw, size_t n, balance_point_t *pts,
                               size_t cap) {
  size_t m = 0;
  for (size_t i = 0; i < n && m < cap; i++) {
    const dContactGeom *c = &raw[i];
    int ok = isfinite(c->depth);
    double nn = 0.0;
    for (int k = 0; k < 3; k++) {
      ok = ok && isfinite(c->pos[k]) && isfinite(c->normal[k]);
      nn += c->normal[k] * c->normal[k];
    }
    if (!ok || !(fabs(nn - 1.0) < 1e-3)) continue;
    balance_point_t *p = &pts[m++];
    for (int k = 0; k < 3; k++) {
      p->pos_m[k] = c->pos[k];
      p->normal[k] = c->normal[k] / sqrt(nn);
    }
    p->depth_m = c->depth;
    p->edge_plane = -1;
    p->id = (uint32_t)i;
  }
  return m;
}

/* OPCODE clips the mesh against B's box: points on the vertical planes through B's top edges are
 * where the object rolls over an edge. Tag them, so the reduction keeps the ends of that chord
 * (without them the support line at the edge shrinks to a point and the body tips early). */
static void tag_edge_points(const balance_world_t *w, balance_point_t *pts, size_t n) {
  const double hx = 0.5 * w->cfg.base_size_m[0], hy = 0.5 * w->cfg.base_size_m[1];
  const double tol = 1e-7;
  for (size_t i = 0; i < n; i++) {
    const double *p = pts[i].pos_m;
    if (fabs(p[0] - hx) < tol)
      pts[i].edge_plane = MODEL_EDGE_PX;
    else if (fabs(p[0] + hx) < tol)
      pts[i].edge_plane = MODEL_EDGE_NX;
    else if (fabs(p[1] - hy) < tol)
      pts[i].edge_plane = MODEL_EDGE_PY;
    else if (fabs(p[1] + hy) < tol)
      pts[i].edge_plane = MODEL_EDGE_NY;
  }
}

/* Drop points within 10 um of an earlier one: two objects' coincident corners both report a
 * contact, and perfectly redundant contact rows make ODE's LCP fail (it then returns forces that
 * throw the bodies). n is small (after reduction). */
static size_t dedupe(balance_point_t *p, size_t n) {
  size_t m = 0;
  for (size_t i = 0; i < n; i++) {
    int dup = 0;
    for (size_t j = 0; j < m && !dup; j++) {
      const double dx = p[i].pos_m[0] - p[j].pos_m[0], dy = p[i].pos_m[1] - p[j].pos_m[1],
                   dz = p[i].pos_m[2] - p[j].pos_m[2];
      dup = dx * dx + dy * dy + dz * dz < 1e-10;
    }
    if (!dup) p[m++] = p[i];
  }
  return m;
}

/* One contact joint. mu_abs < 0: ODE's friction pyramid with mu = cfg.friction (the bound
 * follows the contact's normal force inside the LCP); else a fixed friction bound of mu_abs N. */
static dJointID add_joint(balance_world_t *w, dBodyID b1, dBodyID b2, const balance_point_t *pt,
                          double mu_abs) {
  dContact c;
  memset(&c, 0, sizeof c);
  c.surface.mode = dContactSoftERP | dContactSoftCFM;
  if (mu_abs < 0.0) {
    c.surface.mode |= dContactApprox1;
    c.surface.mu = w->cfg.friction;
  } else {
    c.surface.mu = mu_abs;
  }
  c.surface.soft_erp = w->cfg.soft_erp;
  c.surface.soft_cfm = w->cfg.soft_cfm;
  if (pt->depth_m < 0.0) {
    /* Speculative contact: ODE clamps a negative depth to zero, which would hold the point at
     * its gap. Allow it to close the gap in this step instead. */
    c.surface.mode |= dContactMotionN;
    c.surface.motionN = pt->depth_m / w->cfg.dt_s;
  }
  for (int k = 0; k < 3; k++) {
    c.geom.pos[k] = pt->pos_m[k];
    c.geom.normal[k] = pt->normal[k];
  }
  c.geom.depth = pt->depth_m > 0.0 ? pt->depth_m : 0.0;
  dJointID j = dJointCreateContact(w->ode, w->contact_group, &c);
  dJointAttach(j, b1, b2);
  return j;
}

static void add_joints(balance_world_t *w, dBodyID b1, dBodyID b2, const balance_point_t *pts,
                       size_t n) {
  for (size_t i = 0; i < n; i++) add_joint(w, b1, b2, &pts[i], -1.0);
}

/* Room for n object-object contacts in this step's friction history. Called before the first
 * pair joint of a step: ODE keeps pointers into pair_feedback until the step is taken. */
static int pair_reserve(balance_world_t *w, size_t n) {
  if (n <= w->pair_capacity) return 1;
  balance_pair_force_t *p = realloc(w->pair_prev, n * sizeof *p);
  if (!p) return 0;
  w->pair_prev = p;
  p = realloc(w->pair_now, n * sizeof *p);
  if (!p) return 0;
  w->pair_now = p;
  dJointFeedback *f = realloc(w->pair_feedback, n * sizeof *f);
  if (!f) return 0;
  w->pair_feedback = f;
  w->pair_capacity = n;
  return 1;
}

/* Object-object contact joints. Friction: ODE's pyramid (dContactApprox1) takes each contact's
 * bound from its normal force inside the LCP, and its Dantzig solver leaves the bound of a
 * contact whose normal force is resolved late at zero. On a rock resting on a few bump tips only
 * one contact then carried friction, so nothing resisted a twist about the contact normal, and a
 * stack planned with millimetres of margin spun off its support within a second (docs/physics.md).
 * So each contact gets a fixed Coulomb bound, cfg.friction x the normal force the same pair
 * carried in the last step (1 ms earlier) at the nearest point within BALANCE_PAIR_MATCH_M. The
 * match is by position, not by vertex id: where a bump tip touches a face, the vertex of one body
 * and the nearby one of the other take turns as the contact (dedupe keeps one), and a contact
 * that lost its history every few steps slipped (a 1 mm/s creep on a 10-degree contact). A
 * contact with nothing near it last step gets the pair's mean force; a pair without history
 * keeps the pyramid. */
#define BALANCE_PAIR_MATCH_M 5e-4
static void add_pair_joints(balance_world_t *w, const balance_object_t *a,
                            const balance_object_t *b, const balance_point_t *pts, size_t n) {
  double sum = 0.0;
  size_t count = 0;
  for (size_t q = 0; q < w->pair_prev_count; q++)
    if (w->pair_prev[q].a == a && w->pair_prev[q].b == b) {
      sum += w->pair_prev[q].force_n > 0.0 ? w->pair_prev[q].force_n : 0.0;
      ++count;
    }
  for (size_t i = 0; i < n && w->pair_now_count < w->pair_capacity; i++) {
    double mu_abs = -1.0;
    if (count > 0) {
      double fn = sum / (double)count, d2min = BALANCE_PAIR_MATCH_M * BALANCE_PAIR_MATCH_M;
      for (size_t q = 0; q < w->pair_prev_count; q++) {
        const balance_pair_force_t *p = &w->pair_prev[q];
        if (p->a != a || p->b != b) continue;
        double d2 = 0.0;
        for (int k = 0; k < 3; k++)
          d2 += (p->pos_m[k] - pts[i].pos_m[k]) * (p->pos_m[k] - pts[i].pos_m[k]);
        if (d2 < d2min) {
          d2min = d2;
          fn = p->force_n > 0.0 ? p->force_n : 0.0;
        }
      }
      mu_abs = w->cfg.friction * fn;
    }
    dJointID j = add_joint(w, a->body, b->body, &pts[i], mu_abs);
    balance_pair_force_t *now = &w->pair_now[w->pair_now_count];
    now->a = a;
    now->b = b;
    memcpy(now->pos_m, pts[i].pos_m, sizeof now->pos_m);
    memcpy(now->normal, pts[i].normal, sizeof now->normal);
    now->force_n = 0.0;
    dJointSetFeedback(j, &w->pair_feedback[w->pair_now_count]);
    w->pair_now_count++;
  }
}

/* After the step: the normal force of every pair contact, which becomes the history. */
static void pair_forces_record(balance_world_t *w) {
  for (size_t i = 0; i < w->pair_now_count; i++) {
    const dReal *f = w->pair_feedback[i].f1;
    const double *nrm = w->pair_now[i].normal;
    w->pair_now[i].force_n = f[0] * nrm[0] + f[1] * nrm[1] + f[2] * nrm[2];
  }
  balance_pair_force_t *t = w->pair_prev;
  w->pair_prev = w->pair_now;
  w->pair_now = t;
  w->pair_prev_count = w->pair_now_count;
  w->pair_now_count = 0;
}

static int body_finite(dBodyID b) {
  const dReal *p = dBodyGetPosition(b), *q = dBodyGetQuaternion(b);
  const dReal *v = dBodyGetLinearVel(b), *a = dBodyGetAngularVel(b);
  for (int k = 0; k < 3; k++)
    if (!isfinite(p[k]) || !isfinite(v[k]) || !isfinite(a[k])) return 0;
  for (int k = 0; k < 4; k++)
    if (!isfinite(q[k])) return 0;
  return 1;
}

balance_status_t balance_world_step(balance_world_t *w) {
  if (!w) return BALANCE_E_ARG;
  const size_t k = (size_t)w->cfg.max_contacts;
  for (size_t i = 0; i < w->object_count; i++) {
    balance_object_t *o = w->objects[i];
    if (!o->placed) continue;
    size_t n;
    if (w->cfg.contact == BALANCE_CONTACT_FAST) {
      n = balance_fast_contacts_reduced(w, o, w->points, w->point_capacity, k);
    } else {
      long r = collide_all(w, o->geom, w->base_geom);
      if (r < 0 || !points_reserve(w, (size_t)r)) return BALANCE_E_NOMEM;
      n = balance_points_from_ode(w->raw, (size_t)r, w->points, w->point_capacity);
      tag_edge_points(w, w->points, n);
    }
    n = balance_points_reduce(w->points, n, k);
    add_joints(w, o->body, 0, w->points, n);
  }
  size_t placed = 0;
  for (size_t i = 0; i < w->object_count; i++) placed += w->objects[i]->placed ? 1u : 0u;
  w->pair_now_count = 0;
  if (placed > 1 && !pair_reserve(w, placed * (placed - 1) / 2 * k)) return BALANCE_E_NOMEM;
  for (size_t i = 0; i < w->object_count; i++) {
    balance_object_t *a = w->objects[i];
    if (!a->placed) continue;
    for (size_t j = i + 1; j < w->object_count; j++) {
      balance_object_t *b = w->objects[j];
      if (!b->placed) continue;
      const dReal *pa = dBodyGetPosition(a->body), *pb = dBodyGetPosition(b->body);
      double d2 = 0.0;
      for (int c = 0; c < 3; c++) d2 += (pa[c] - pb[c]) * (pa[c] - pb[c]);
      const double reach = a->radius_m + b->radius_m + BALANCE_CONTACT_BAND_M;
      if (d2 > reach * reach) continue;
      if (!points_reserve(w, a->mesh_link.vertex_count + b->mesh_link.vertex_count))
        return BALANCE_E_NOMEM;
      size_t n = balance_pair_contacts(a, b, w->points, w->point_capacity);
      n = balance_points_reduce(w->points, n, k);
      n = dedupe(w->points, n);
      add_pair_joints(w, a, b, w->points, n);
    }
  }
  int ok = dWorldStep(w->ode, w->cfg.dt_s);
  dJointGroupEmpty(w->contact_group);
  if (ok) pair_forces_record(w);
  if (!ok) return BALANCE_E_NOMEM;
  w->time_s += w->cfg.dt_s;
  balance_status_t st = BALANCE_OK;
  for (size_t i = 0; i < w->object_count; i++) {
    balance_object_t *o = w->objects[i];
    if (o->placed && !body_finite(o->body)) {
      balance_object_remove(o);
      st = BALANCE_E_DIVERGED;
    }
  }
  return st;
}
