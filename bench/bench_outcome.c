/* bench_outcome: the geometric outcome model (comlearn/model_outcome.h) against lib/balance.
 *
 * For each object class (tools/shapegen families, and "rock": tools/rockgen random rocks) and each
 * of its objects, random placements as the estimator makes them: a hull face of the object
 * (model_faces_find) and its resting orientation, a random yaw, a CoM hypothesis drawn inside the
 * convex hull at most half the object's height above that face with its vertical line inside the
 * face's support polygon (in B's middle, lib/balance's 3 um contact band: fixed, whatever
 * band the model is run with), and the link point `CoM + d x` (x: world +x in the link frame) set
 * over B's +X edge with model_pose_over_edge (touching, 1 um deep), d uniform in [-2 mm, s + 1 mm],
 * s the face polygon's reach beyond the CoM towards the edge (so both outcomes occur). lib/balance
 * runs the trial (balance_trial_run, fast contact path, default config) on an object with that CoM
 * and the uniform-density mass and inertia; "in place" = STAYS with a settled rotation below
 * 2e-4 rad and the CoM moved less than 20 um (docs/DESIGN physics notes). The model says in place
 * iff its margin is > 0.
 *
 * Printed (markdown): per class the placements, how often the model's verdict equals lib/balance's
 * in-place verdict (all, and where |margin| > 0.1 mm and > 0.5 mm), how often it equals plain
 * STAYS, the disagreements by kind; then per class, at the threshold, lines (object, face, yaw,
 * CoM) whose d is bisected to 0.05 um in lib/balance and in the model: the bias d_balance - d_model
 * (positive: lib/balance needs the CoM further inside), median and max |bias|; the model's cost per
 * pose and per CoM; the agreement of other model settings (support band, tilt); the first
 * disagreements of each class in detail, and the threshold lines whose flips differ by more than
 * 5 um, with what lib/balance does halfway between them.
 *
 * Usage: bench_outcome [--placements N] [--objects K] [--per-com M] [--lines L] [--seed S]
 *                      [--families LIST] [--show D] [--tol-um T] [--tilt A] [--help]
 * Deterministic for given options. Wall time: a few minutes for the defaults. */
#define _POSIX_C_SOURCE 200809L

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "comlearn/balance.h"
#include "comlearn/cli_args.h"
#include "comlearn/cli_log.h"
#include "comlearn/math3d.h"
#include "comlearn/model.h"
#include "comlearn/model_outcome.h"
#include "comlearn/model_support.h"
#include "rockgen.h"
#include "shapegen.h"
#include "tool_args.h"

enum { MAX_FACES = 4096, MAX_CLASSES = 16, MAX_SHOW = 64, NTOL = 8 };

/* The model settings of the sweep: support band and tilt (the library's defaults: 1 um, 0). */
static const model_outcome_config_t SWEEP[NTOL] = {
    {.tol_m = 0.1e-6, .tilt_rad = 0.0, .min_width_m = 1e-7},
    {.tol_m = 1e-6, .tilt_rad = 0.0, .min_width_m = 1e-7},
    {.tol_m = 3e-6, .tilt_rad = 0.0, .min_width_m = 1e-7},
    {.tol_m = 0.1e-6, .tilt_rad = 2e-4, .min_width_m = 1e-7},
    {.tol_m = 1e-6, .tilt_rad = 1e-4, .min_width_m = 1e-7},
    {.tol_m = 1e-6, .tilt_rad = 2e-4, .min_width_m = 1e-7},
    {.tol_m = 1e-6, .tilt_rad = 4e-4, .min_width_m = 1e-7},
    {.tol_m = 3e-6, .tilt_rad = 2e-4, .min_width_m = 1e-7}};

static const double BASE[3] = {0.30, 0.30, 0.10};
#define IN_PLACE_ROT_RAD 2e-4
#define IN_PLACE_MOVE_M 20e-6
#define BISECT_TOL_M 5e-8
/* Faces and CoM hypotheses are drawn on the support polygon in B's middle with lib/balance's
 * contact band (3 um): a superset of the model's, fixed, so the draws do not depend on the model
 * settings under test. */
static const model_outcome_config_t DRAW_CFG = {.tol_m = 3e-6, .min_width_m = 1e-7};

typedef struct {
  int placements, objects, per_com, lines, show;
  uint64_t seed;
  model_outcome_config_t cfg;
  int nclass;
  int family[MAX_CLASSES]; /* shapegen family, or -1: random rock */
} opts_t;

/* One object of a class, with what the placements need. */
typedef struct {
  char name[64];
  model_mesh_t mesh;
  model_mass_t uniform;
  double (*plane)[4]; /* hull planes n . x <= d, link frame */
  size_t nplane;
  model_face_t *face; /* resting faces with a usable support polygon */
  size_t nface;
  model_outcome_work_t *work;
  model_outcome_support_t *support; /* at the release pose */
  model_outcome_support_t *mid;     /* the drawn face resting in B's middle */
  model_outcome_config_t cfg;       /* the model's settings under test */
} object_t;

/* A placement drawn for an object. */
typedef struct {
  size_t face;
  double com_link_m[3];
  double yaw_rad;
  double q[4];    /* Rz(yaw) q_face */
  double reach_m; /* s: the face polygon's reach beyond the CoM along world +x after the yaw */
} draw_t;

/* What one trial gave. */
typedef struct {
  int model_in;
  double margin_m;
  int in_tol[NTOL]; /* the verdict with each band of the sweep */
  size_t support_vertices;
  double support_width_m;
  int stays, bal_in;
  balance_outcome_t outcome;
  double rotation_rad, moved_m;
  unsigned steps;
} trial_t;

typedef struct {
  char object[64];
  size_t face;
  double normal[3], yaw_rad, d_m, com_m[3];
  trial_t t;
} shown_t;

/* A threshold line whose flips differ by more than LINE_SHOW_M: where, and what lib/balance
 * does halfway between the two flips. */
#define LINE_SHOW_M 5e-6
typedef struct {
  char object[64];
  double normal[3], com_m[3], yaw_rad, d_model_m, d_balance_m;
  trial_t mid;
} line_t;

/* Per-class tallies. */
typedef struct {
  long n, agree, n01, agree01, n05, agree05, stays_agree, stays_agree05;
  long model_in, bal_in, stays, errors;
  long agree_tol[NTOL], agree01_tol[NTOL];
  long band_only; /* disagreements: the model says in, the 0.1 um band's polygon does not */
  /* model in, lib/balance not in place: STAYS but turned >= 2e-4 rad or moved >= 20 um (settled
   * nearby), TIPS, INVALID though still (its rest test never met), INVALID moving or SLIDES */
  long in_out_settled, in_out_tips, in_out_still, in_out_other;
  long out_in;            /* model not in, lib/balance in place */
  long out_in_degenerate; /* ... of them with no valid polygon */
  int lines, bracketed;
  double bias_m[256];
  double build_s, test_s;
  long builds, tests, batch_in; /* timing: support builds, CoM tests (batch_in: their verdicts) */
  int nshow;
  shown_t show[MAX_SHOW];
  int nline;
  line_t line[MAX_SHOW];
} tally_t;

/* ---- objects -------------------------------------------------------------------------------- */

static int object_mesh(int family, uint64_t seed, object_t *o) {
  if (family < 0) {
    rockgen_spec_t spec;
    if (rockgen_spec_random(seed, &spec) != MODEL_OK ||
        rockgen_shape_build(&spec, &o->mesh) != MODEL_OK)
      return -1;
    snprintf(o->name, sizeof o->name, "%s", spec.name);
    return 0;
  }
  shapegen_object_t so;
  if (shapegen_generate((shapegen_family_t)family, seed, &so) != MODEL_OK) return -1;
  snprintf(o->name, sizeof o->name, "%s", so.spec.name);
  o->mesh = so.mesh; /* taken over */
  return 0;
}

static int object_planes(object_t *o) {
  model_mesh_t hull = {0};
  model_error_t err;
  if (model_mesh_hull(&o->mesh, &hull, &err) != MODEL_OK) {
    LOG_E("%s: hull: %s", o->name, err.msg);
    return -1;
  }
  o->plane = malloc(hull.triangle_count * sizeof *o->plane);
  if (!o->plane) return -1;
  for (size_t t = 0; t < hull.triangle_count; ++t) {
    const uint32_t *tri = hull.triangles[t];
    double n[3];
    if (cl_tri_normal(hull.vertices_m[tri[0]], hull.vertices_m[tri[1]], hull.vertices_m[tri[2]],
                      n) <= 0.0)
      continue;
    memcpy(o->plane[o->nplane], n, sizeof n);
    o->plane[o->nplane++][3] = cl_vec3_dot(n, hull.vertices_m[tri[0]]);
  }
  model_mesh_free(&hull);
  return 0;
}

/* The face's orientation resting in the middle of B, 1 um deep. */
static model_pose_t mid_pose(const object_t *o, const double q[4]) {
  model_pose_t p = {.position_m = {0, 0, 0}};
  memcpy(p.orientation_wxyz, q, 4 * sizeof q[0]);
  p.position_m[2] = -model_mesh_bottom_z(&o->mesh, q) - 1e-6;
  return p;
}

/* Faces of area >= 1 mm^2 whose support polygon in the middle of B is a polygon. */
static int object_faces(object_t *o) {
  model_regime_config_t rc;
  model_regime_config_default(&rc);
  rc.min_face_area_m2 = 1e-6;
  rc.min_com_margin_m = -1.0;
  model_face_t *all = malloc(MAX_FACES * sizeof *all);
  o->face = malloc(MAX_FACES * sizeof *o->face);
  size_t n = 0;
  if (!all || !o->face || model_faces_find(&o->mesh, o->uniform.com_m, &rc, all, MAX_FACES, &n))
    return -1;
  for (size_t i = 0; i < n && i < MAX_FACES; ++i) {
    const model_pose_t p = mid_pose(o, all[i].orientation_wxyz);
    if (model_outcome_support_build(&o->mesh, &p, BASE, &DRAW_CFG, o->work, o->mid) != MODEL_OK)
      continue;
    if (o->mid->valid && o->mid->width_m >= 5e-4) o->face[o->nface++] = all[i];
  }
  free(all);
  return o->nface > 0 ? 0 : -1;
}

static int object_load(int family, uint64_t seed, object_t *o) {
  memset(o, 0, sizeof *o);
  if (object_mesh(family, seed, o) != 0) {
    LOG_E("family %d seed %llu: cannot generate", family, (unsigned long long)seed);
    return -1;
  }
  const size_t wsize = model_outcome_work_size(&o->mesh);
  void *mem = malloc(wsize);
  o->work = mem ? model_outcome_work_init(mem, wsize, &o->mesh) : NULL;
  o->support = malloc(sizeof *o->support);
  o->mid = malloc(sizeof *o->mid);
  if (!o->work || !o->support || !o->mid ||
      model_mesh_mass(&o->mesh, 1000.0, &o->uniform) != MODEL_OK || object_planes(o) != 0 ||
      object_faces(o) != 0) {
    LOG_E("%s: cannot prepare (no resting face?)", o->name);
    return -1;
  }
  return 0;
}

static void object_free(object_t *o) {
  model_mesh_free(&o->mesh);
  free(o->plane);
  free(o->face);
  free(o->work);
  free(o->support);
  free(o->mid);
  memset(o, 0, sizeof *o);
}

/* ---- drawing placements --------------------------------------------------------------------- */

static int inside_hull(const object_t *o, const double c[3]) {
  for (size_t i = 0; i < o->nplane; ++i)
    if (cl_vec3_dot(o->plane[i], c) > o->plane[i][3] - 1e-5) return 0;
  return 1;
}

/* A CoM hypothesis for face f: its vertical line inside the face's support polygon (resting in
 * B's middle), 0.5 mm to half the object's height (at most 25 mm) above the face, inside the
 * hull. Leaves the mid-B support in o->mid. Returns 0, or -1 after 200 failed tries. */
static int draw_com(object_t *o, size_t f, uint64_t *rng, double com_link[3]) {
  const model_pose_t p = mid_pose(o, o->face[f].orientation_wxyz);
  model_outcome_support_t *s = o->mid;
  if (model_outcome_support_build(&o->mesh, &p, BASE, &DRAW_CFG, o->work, s) != MODEL_OK) return -1;
  double lo[2] = {HUGE_VAL, HUGE_VAL}, hi[2] = {-HUGE_VAL, -HUGE_VAL};
  for (size_t i = 0; i < s->vertex_count; ++i)
    for (int k = 0; k < 2; ++k) {
      lo[k] = fmin(lo[k], s->polygon_xy_m[i][k]);
      hi[k] = fmax(hi[k], s->polygon_xy_m[i][k]);
    }
  double top = -HUGE_VAL;
  for (size_t i = 0; i < o->mesh.vertex_count; ++i) {
    const double *v = o->mesh.vertices_m[i];
    top = fmax(top, s->rot[2][0] * v[0] + s->rot[2][1] * v[1] + s->rot[2][2] * v[2]);
  }
  top += p.position_m[2];
  const double hmax = fmax(1e-3, fmin(0.5 * (top - s->support_z_m), 0.025));
  for (int tries = 0; tries < 200; ++tries) {
    const double w[3] = {cl_rng_range(rng, lo[0], hi[0]), cl_rng_range(rng, lo[1], hi[1]),
                         s->support_z_m + cl_rng_range(rng, 5e-4, hmax)};
    double d[3], c[3], margin;
    int in;
    for (int k = 0; k < 3; ++k) d[k] = w[k] - p.position_m[k];
    for (int k = 0; k < 3; ++k)
      c[k] = s->rot[0][k] * d[0] + s->rot[1][k] * d[1] + s->rot[2][k] * d[2];
    if (model_outcome_support_test(s, c, &in, &margin) != MODEL_OK || !in) continue;
    if (!inside_hull(o, c)) continue;
    memcpy(com_link, c, sizeof c);
    return 0;
  }
  return -1;
}

/* A yaw for the drawn CoM and the reach of the face polygon beyond it along world +x; o->mid
 * holds the mid-B support of the face (draw_com). */
static void draw_yaw(const object_t *o, uint64_t *rng, draw_t *dr) {
  const model_outcome_support_t *s = o->mid;
  dr->yaw_rad = cl_rng_range(rng, 0.0, 2.0 * CL_PI);
  model_orientation_yawed(o->face[dr->face].orientation_wxyz, dr->yaw_rad, dr->q);
  double cw[2];
  for (int k = 0; k < 2; ++k)
    cw[k] = s->rot[k][0] * dr->com_link_m[0] + s->rot[k][1] * dr->com_link_m[1] +
            s->rot[k][2] * dr->com_link_m[2] + s->position_m[k];
  const double c = cos(dr->yaw_rad), sn = sin(dr->yaw_rad);
  dr->reach_m = -HUGE_VAL;
  for (size_t i = 0; i < s->vertex_count; ++i) {
    const double x = s->polygon_xy_m[i][0] - cw[0], y = s->polygon_xy_m[i][1] - cw[1];
    dr->reach_m = fmax(dr->reach_m, c * x - sn * y);
  }
}

/* ---- trials -----------------------------------------------------------------------------------
 */

static double now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The release pose of draw dr at offset d (the CoM d inside the +X edge line). */
static int release_pose(const object_t *o, const draw_t *dr, double d, model_pose_t *pose) {
  double r[3][3], p[3];
  model_quat_to_rot(dr->q, r);
  for (int k = 0; k < 3; ++k) p[k] = dr->com_link_m[k] + d * r[0][k]; /* + d x, x in link */
  return model_pose_over_edge(&o->mesh, BASE, dr->q, MODEL_EDGE_PX, p, 0.0, 1e-6, pose) == MODEL_OK
             ? 0
             : -1;
}

/* The model's verdict at pose, timed into tl (a batch of 32 CoM tests for the per-CoM cost). */
static int model_at(object_t *o, const model_pose_t *pose, const double com[3], tally_t *tl,
                    trial_t *t) {
  const double t0 = now_s();
  if (model_outcome_support_build(&o->mesh, pose, BASE, &o->cfg, o->work, o->support) != MODEL_OK)
    return -1;
  const double t1 = now_s();
  int batch_in = 0;
  for (int i = 0; i < 32; ++i) {
    const double c[3] = {com[0] + 1e-5 * i, com[1] - 1e-5 * i, com[2]};
    int in;
    double m;
    model_outcome_support_test(o->support, c, &in, &m);
    batch_in += in;
  }
  const double t2 = now_s();
  if (tl) {
    tl->build_s += t1 - t0;
    tl->test_s += (t2 - t1) / 32.0;
    ++tl->builds;
    ++tl->tests;
    tl->batch_in += batch_in;
  }
  if (model_outcome_support_test(o->support, com, &t->model_in, &t->margin_m) != MODEL_OK)
    return -1;
  t->support_vertices = o->support->vertex_count;
  t->support_width_m = o->support->valid ? o->support->width_m : 0.0;
  for (int k = 0; k < NTOL && tl; ++k) {
    double m;
    if (model_outcome_predict(&o->mesh, pose, BASE, com, &SWEEP[k], o->work, &t->in_tol[k], &m) !=
        MODEL_OK)
      return -1;
  }
  return 0;
}

static int balance_at(balance_world_t *w, balance_object_t *bo, const model_pose_t *pose,
                      const double com[3], trial_t *t) {
  balance_trial_result_t res;
  if (balance_trial_run(w, bo, pose, NULL, &res) != BALANCE_OK) return -1;
  double a[3], b[3];
  cl_pose_apply(&res.released, com, a);
  cl_pose_apply(&res.settled, com, b);
  t->outcome = res.outcome;
  t->stays = res.outcome == BALANCE_STAYS;
  t->rotation_rad = res.rotation_rad;
  t->moved_m = cl_vec3_dist(a, b);
  t->steps = res.steps;
  t->bal_in = t->stays && t->rotation_rad < IN_PLACE_ROT_RAD && t->moved_m < IN_PLACE_MOVE_M;
  return 0;
}

/* A world with one object: the mesh, the uniform mass and inertia, the CoM com. */
static int balance_open(const object_t *o, const double com[3], balance_world_t **w,
                        balance_object_t **bo) {
  balance_config_t cfg;
  balance_config_default(&cfg);
  memcpy(cfg.base_size_m, BASE, sizeof cfg.base_size_m);
  model_mass_t mass = o->uniform;
  memcpy(mass.com_m, com, sizeof mass.com_m);
  *w = NULL;
  *bo = NULL;
  if (balance_world_create(&cfg, w) != BALANCE_OK) return -1;
  if (balance_object_create(*w, &o->mesh, &mass, bo) != BALANCE_OK) {
    balance_world_destroy(*w);
    *w = NULL;
    return -1;
  }
  return 0;
}

/* ---- tallies ----------------------------------------------------------------------------------
 */

static void tally_add(tally_t *tl, const object_t *o, const draw_t *dr, double d, const trial_t *t,
                      int show) {
  const int agree = t->model_in == t->bal_in, sagree = t->model_in == t->stays;
  const double am = fabs(t->margin_m);
  ++tl->n;
  tl->agree += agree;
  tl->stays_agree += sagree;
  tl->model_in += t->model_in;
  tl->bal_in += t->bal_in;
  tl->stays += t->stays;
  if (am > 1e-4) {
    ++tl->n01;
    tl->agree01 += agree;
  }
  if (am > 5e-4) {
    ++tl->n05;
    tl->agree05 += agree;
    tl->stays_agree05 += sagree;
  }
  for (int k = 0; k < NTOL; ++k) {
    tl->agree_tol[k] += t->in_tol[k] == t->bal_in;
    tl->agree01_tol[k] += am > 1e-4 && t->in_tol[k] == t->bal_in;
  }
  if (agree) return;
  tl->band_only += t->model_in && !t->in_tol[0];
  const int still = t->rotation_rad < IN_PLACE_ROT_RAD && t->moved_m < IN_PLACE_MOVE_M;
  if (t->model_in) {
    if (t->stays)
      ++tl->in_out_settled;
    else if (t->outcome == BALANCE_TIPS)
      ++tl->in_out_tips;
    else if (t->outcome == BALANCE_INVALID && still)
      ++tl->in_out_still;
    else
      ++tl->in_out_other;
  } else {
    ++tl->out_in;
    tl->out_in_degenerate += t->support_width_m == 0.0;
  }
  if (tl->nshow < show && tl->nshow < MAX_SHOW) {
    shown_t *sh = &tl->show[tl->nshow++];
    snprintf(sh->object, sizeof sh->object, "%s", o->name);
    sh->face = dr->face;
    memcpy(sh->normal, o->face[dr->face].normal_link, sizeof sh->normal);
    sh->yaw_rad = dr->yaw_rad;
    sh->d_m = d;
    memcpy(sh->com_m, dr->com_link_m, sizeof sh->com_m);
    sh->t = *t;
  }
}

/* ---- one object: placements and threshold lines ------------------------------------------------
 */

/* `quota` placements of object o: per CoM hypothesis, per_com (yaw, d) pairs. */
static int object_placements(object_t *o, const opts_t *op, int quota, uint64_t *rng, tally_t *tl) {
  int done = 0, failures = 0;
  while (done < quota && failures < 100) {
    draw_t dr = {.face = cl_rng_below(rng, (unsigned)o->nface)};
    balance_world_t *w = NULL;
    balance_object_t *bo = NULL;
    if (draw_com(o, dr.face, rng, dr.com_link_m) != 0 || balance_open(o, dr.com_link_m, &w, &bo)) {
      ++failures;
      continue;
    }
    for (int m = 0; m < op->per_com && done < quota; ++m) {
      draw_yaw(o, rng, &dr);
      const double d = cl_rng_range(rng, -2e-3, dr.reach_m + 1e-3);
      model_pose_t pose;
      trial_t t;
      memset(&t, 0, sizeof t);
      if (release_pose(o, &dr, d, &pose) != 0 || model_at(o, &pose, dr.com_link_m, tl, &t) != 0 ||
          balance_at(w, bo, &pose, dr.com_link_m, &t) != 0) {
        ++tl->errors;
        continue;
      }
      tally_add(tl, o, &dr, d, &t, op->show);
      ++done;
    }
    balance_world_destroy(w);
  }
  return done;
}

/* In place at offset d: the model (which 0) or lib/balance (1). 1, 0, or -1 on error. */
static int in_place_at(object_t *o, balance_world_t *w, balance_object_t *bo, const draw_t *dr,
                       double d, int which) {
  model_pose_t pose;
  trial_t t;
  memset(&t, 0, sizeof t);
  if (release_pose(o, dr, d, &pose) != 0) return -1;
  if (which == 0) return model_at(o, &pose, dr->com_link_m, NULL, &t) == 0 ? t.model_in : -1;
  return balance_at(w, bo, &pose, dr->com_link_m, &t) == 0 ? t.bal_in : -1;
}

/* The flip of `which` in [lo, hi] (not in place at lo, in place at hi) to BISECT_TOL_M. */
static double bisect(object_t *o, balance_world_t *w, balance_object_t *bo, const draw_t *dr,
                     double lo, double hi, int which) {
  for (int i = 0; i < 64 && hi - lo > BISECT_TOL_M; ++i) {
    const double mid = 0.5 * (lo + hi);
    const int r = in_place_at(o, w, bo, dr, mid, which);
    if (r < 0) return NAN;
    if (r)
      hi = mid;
    else
      lo = mid;
  }
  return 0.5 * (lo + hi);
}

/* One threshold line: a face, a CoM, a yaw; d bisected in both. */
static void object_line(object_t *o, uint64_t *rng, tally_t *tl) {
  draw_t dr = {.face = cl_rng_below(rng, (unsigned)o->nface)};
  balance_world_t *w = NULL;
  balance_object_t *bo = NULL;
  ++tl->lines;
  if (draw_com(o, dr.face, rng, dr.com_link_m) != 0 || balance_open(o, dr.com_link_m, &w, &bo))
    return;
  draw_yaw(o, rng, &dr);
  const double lo = -2e-3, hi = dr.reach_m + 1e-3;
  if (in_place_at(o, w, bo, &dr, lo, 0) == 0 && in_place_at(o, w, bo, &dr, hi, 0) == 1 &&
      in_place_at(o, w, bo, &dr, lo, 1) == 0 && in_place_at(o, w, bo, &dr, hi, 1) == 1) {
    const double dm = bisect(o, w, bo, &dr, lo, hi, 0), db = bisect(o, w, bo, &dr, lo, hi, 1);
    if (isfinite(dm) && isfinite(db) && tl->bracketed < 256) tl->bias_m[tl->bracketed++] = db - dm;
    model_pose_t pose;
    if (isfinite(dm) && isfinite(db) && fabs(db - dm) > LINE_SHOW_M && tl->nline < MAX_SHOW &&
        release_pose(o, &dr, 0.5 * (dm + db), &pose) == 0) {
      line_t *ln = &tl->line[tl->nline];
      snprintf(ln->object, sizeof ln->object, "%s", o->name);
      memcpy(ln->normal, o->face[dr.face].normal_link, sizeof ln->normal);
      memcpy(ln->com_m, dr.com_link_m, sizeof ln->com_m);
      ln->yaw_rad = dr.yaw_rad;
      ln->d_model_m = dm;
      ln->d_balance_m = db;
      memset(&ln->mid, 0, sizeof ln->mid);
      if (model_at(o, &pose, dr.com_link_m, NULL, &ln->mid) == 0 &&
          balance_at(w, bo, &pose, dr.com_link_m, &ln->mid) == 0)
        ++tl->nline;
    }
  }
  balance_world_destroy(w);
}

/* ---- the report -------------------------------------------------------------------------------
 */

static const char *class_name(int family) {
  return family < 0 ? "rock" : shapegen_family_name((shapegen_family_t)family);
}

static double pct(long a, long n) { return n > 0 ? 100.0 * (double)a / (double)n : NAN; }

static int cmp_abs(const void *pa, const void *pb) {
  const double a = fabs(*(const double *)pa), b = fabs(*(const double *)pb);
  return a < b ? -1 : a > b;
}

static int cmp_val(const void *pa, const void *pb) {
  const double a = *(const double *)pa, b = *(const double *)pb;
  return a < b ? -1 : a > b;
}

static void report_agreement(const opts_t *op, const tally_t *tl) {
  printf(
      "\n| class | placements (skipped) | model in | lib/balance in place | agree | agree, "
      "\\|margin\\| > "
      "0.1 mm | agree, \\|margin\\| > 0.5 mm | STAYS, of them not in place | plain STAYS agrees "
      "(> 0.5 mm) | model in, "
      "lib/balance not: settled nearby / tips / still at horizon / other | model not, "
      "lib/balance in (no polygon) |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (int c = 0; c < op->nclass; ++c) {
    const tally_t *t = &tl[c];
    printf(
        "| %s | %ld (%ld) | %.1f %% | %.1f %% | %.2f %% | %.2f %% (%ld) | %.2f %% (%ld) | %.1f %%, "
        "%.1f %% | %.1f %% "
        "(%.1f %%) | %ld / %ld / %ld / %ld | %ld (%ld) |\n",
        class_name(op->family[c]), t->n, t->errors, pct(t->model_in, t->n), pct(t->bal_in, t->n),
        pct(t->agree, t->n), pct(t->agree01, t->n01), t->n01, pct(t->agree05, t->n05), t->n05,
        pct(t->stays, t->n), pct(t->stays - t->bal_in, t->n), pct(t->stays_agree, t->n),
        pct(t->stays_agree05, t->n05), t->in_out_settled, t->in_out_tips, t->in_out_still,
        t->in_out_other, t->out_in, t->out_in_degenerate);
  }
}

static void report_threshold(const opts_t *op, tally_t *tl) {
  printf(
      "\n| class | lines | bracketed | bias median um | bias max \\|um\\| | within 1 um | model "
      "us/pose | model ns/CoM |\n|---|---|---|---|---|---|---|---|\n");
  for (int c = 0; c < op->nclass; ++c) {
    tally_t *t = &tl[c];
    double med = NAN, worst = NAN;
    int within = 0;
    if (t->bracketed > 0) {
      double sorted[256];
      memcpy(sorted, t->bias_m, (size_t)t->bracketed * sizeof sorted[0]);
      qsort(sorted, (size_t)t->bracketed, sizeof sorted[0], cmp_val);
      med = sorted[t->bracketed / 2];
      qsort(sorted, (size_t)t->bracketed, sizeof sorted[0], cmp_abs);
      worst = fabs(sorted[t->bracketed - 1]);
      for (int i = 0; i < t->bracketed; ++i) within += fabs(sorted[i]) <= 1e-6;
    }
    printf("| %s | %d | %d | %+.2f | %.1f | %d | %.1f | %.0f |\n", class_name(op->family[c]),
           t->lines, t->bracketed, med * 1e6, worst * 1e6, within,
           1e6 * t->build_s / (double)(t->builds ? t->builds : 1),
           1e9 * t->test_s / (double)(t->tests ? t->tests : 1));
  }
}

static void report_tols(const opts_t *op, const tally_t *tl) {
  printf("\n| class | disagreements | of them: model in, outside the 0.1 um band's polygon |");
  for (int k = 0; k < NTOL; ++k)
    printf(" band %.1f um, tilt %.0e |", SWEEP[k].tol_m * 1e6, SWEEP[k].tilt_rad);
  printf("\n|---|---|---|");
  for (int k = 0; k < NTOL; ++k) printf("---|");
  printf("\n");
  for (int c = 0; c < op->nclass; ++c) {
    const tally_t *t = &tl[c];
    printf("| %s | %ld | %ld |", class_name(op->family[c]), t->n - t->agree, t->band_only);
    for (int k = 0; k < NTOL; ++k) printf(" %.2f %% |", pct(t->agree_tol[k], t->n));
    printf("\n");
  }
}

static const char *outcome_name(balance_outcome_t o) {
  return o == BALANCE_STAYS    ? "STAYS"
         : o == BALANCE_TIPS   ? "TIPS"
         : o == BALANCE_SLIDES ? "SLIDES"
                               : "INVALID";
}

static void report_shown(const opts_t *op, const tally_t *tl) {
  printf(
      "\n| class | object | face normal (link) | CoM (link) mm | yaw deg | d mm | margin mm | "
      "polygon n, width mm | model | lib/balance | rotation rad | CoM moved um | steps |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (int c = 0; c < op->nclass; ++c)
    for (int i = 0; i < tl[c].nshow; ++i) {
      const shown_t *s = &tl[c].show[i];
      printf(
          "| %s | %s | (%.2f, %.2f, %.2f) | (%.3f, %.3f, %.3f) | %.1f | %.4f | %.4f | %zu, %.3f | "
          "%s | %s | %.2e | %.1f | %u |\n",
          class_name(op->family[c]), s->object, s->normal[0], s->normal[1], s->normal[2],
          s->com_m[0] * 1e3, s->com_m[1] * 1e3, s->com_m[2] * 1e3, s->yaw_rad * 180.0 / CL_PI,
          s->d_m * 1e3, s->t.margin_m * 1e3, s->t.support_vertices, s->t.support_width_m * 1e3,
          s->t.model_in ? "in" : "not", outcome_name(s->t.outcome), s->t.rotation_rad,
          s->t.moved_m * 1e6, s->t.steps);
    }
}

static void report_lines(const opts_t *op, const tally_t *tl) {
  printf(
      "\n| class | object | face normal (link) | CoM (link) mm | yaw deg | flip d mm: model | "
      "lib/balance | halfway: model margin mm, polygon n | lib/balance | rotation rad | CoM "
      "moved um |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (int c = 0; c < op->nclass; ++c)
    for (int i = 0; i < tl[c].nline; ++i) {
      const line_t *l = &tl[c].line[i];
      printf(
          "| %s | %s | (%.2f, %.2f, %.2f) | (%.3f, %.3f, %.3f) | %.1f | %.4f | %.4f | %.4f, "
          "%zu | %s | %.2e | %.1f |\n",
          class_name(op->family[c]), l->object, l->normal[0], l->normal[1], l->normal[2],
          l->com_m[0] * 1e3, l->com_m[1] * 1e3, l->com_m[2] * 1e3, l->yaw_rad * 180.0 / CL_PI,
          l->d_model_m * 1e3, l->d_balance_m * 1e3, l->mid.margin_m * 1e3, l->mid.support_vertices,
          outcome_name(l->mid.outcome), l->mid.rotation_rad, l->mid.moved_m * 1e6);
    }
}

/* ---- main -------------------------------------------------------------------------------------
 */

static void usage(FILE *f) {
  fprintf(f,
          "usage: bench_outcome [--placements N] [--objects K] [--per-com M] [--lines L]\n"
          "                     [--seed S] [--families LIST] [--show D] [--tol-um T] [--tilt A]\n"
          "The geometric outcome model (comlearn/model_outcome.h) against lib/balance on random\n"
          "placements over B's +X edge; markdown tables on stdout (docs/physics.md).\n"
          "  --placements N  placements per class (default 2000)\n"
          "  --objects K     objects per class, seeds S .. S+K-1 (default 5)\n"
          "  --per-com M     placements per CoM hypothesis (default 4)\n"
          "  --lines L       threshold lines bisected per class (default 24, at most 256)\n"
          "  --seed S        first object seed; also seeds the draws (default 1)\n"
          "  --families LIST comma-separated classes: shapegen families and rock (default\n"
          "                  box,feet2,feet3,ring,rim,mug,pebble,lumpy,scanned,plate,rock)\n"
          "  --show D        disagreements listed per class (default 4)\n"
          "  --tol-um T      the model's support band, um (default: the library's)\n"
          "  --tilt A        the model's tilt, rad (default: the library's)\n"
          "  -h, --help      this text\n"
          "  -V, --version   print the version\n");
}

static int families_arg(const char *list, opts_t *o) {
  char buf[512];
  snprintf(buf, sizeof buf, "%s", list);
  o->nclass = 0;
  for (char *save = NULL, *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
    shapegen_family_t f;
    if (o->nclass == MAX_CLASSES) return 1;
    if (strcmp(tok, "rock") == 0)
      o->family[o->nclass++] = -1;
    else if (shapegen_family_parse(tok, &f) == 0)
      o->family[o->nclass++] = (int)f;
    else
      return 1;
  }
  return o->nclass == 0;
}

static int parse_args(int argc, char **argv, opts_t *o) {
  static const struct option opts[] = {
      {"placements", required_argument, NULL, 'n'}, {"objects", required_argument, NULL, 'k'},
      {"per-com", required_argument, NULL, 'm'},    {"lines", required_argument, NULL, 'l'},
      {"seed", required_argument, NULL, 's'},       {"families", required_argument, NULL, 'f'},
      {"show", required_argument, NULL, 'd'},       {"tol-um", required_argument, NULL, 't'},
      {"tilt", required_argument, NULL, 'T'},       {"help", no_argument, NULL, 'h'},
      {"version", no_argument, NULL, 'V'},          {NULL, 0, NULL, 0}};
  int c, bad = families_arg("box,feet2,feet3,ring,rim,mug,pebble,lumpy,scanned,plate,rock", o);
  opterr = 0;
  while (!bad && (c = getopt_long(argc, argv, "hV", opts, NULL)) != -1) {
    switch (c) {
      case 'n': bad = tool_parse_int(optarg, 1, 1000000, &o->placements); break;
      case 'k': bad = tool_parse_int(optarg, 1, 1000, &o->objects); break;
      case 'm': bad = tool_parse_int(optarg, 1, 100, &o->per_com); break;
      case 'l': bad = tool_parse_int(optarg, 0, 256, &o->lines); break;
      case 's': bad = tool_parse_u64(optarg, &o->seed); break;
      case 'f': bad = families_arg(optarg, o); break;
      case 'd': bad = tool_parse_int(optarg, 0, MAX_SHOW, &o->show); break;
      case 't': {
        char *end = NULL;
        o->cfg.tol_m = 1e-6 * strtod(optarg, &end);
        bad = end == optarg || *end != '\0' || model_outcome_config_check(&o->cfg) != MODEL_OK;
        break;
      }
      case 'T': {
        char *end = NULL;
        o->cfg.tilt_rad = strtod(optarg, &end);
        bad = end == optarg || *end != '\0' || model_outcome_config_check(&o->cfg) != MODEL_OK;
        break;
      }
      case 'h': usage(stdout); exit(0);
      case 'V': cli_version_print(stdout, "bench_outcome"); exit(0);
      default: cli_getopt_complain("bench_outcome", "hV", opts, argv); exit(2);
    }
  }
  return bad || optind != argc ? -1 : 0;
}

/* Every object of class c: its share of the placements and of the lines. */
static int run_class(const opts_t *op, int c, tally_t *tl) {
  uint64_t rng = op->seed * UINT64_C(0x9e3779b97f4a7c15) + (uint64_t)c;
  for (int k = 0; k < op->objects; ++k) {
    object_t o;
    if (object_load(op->family[c], op->seed + (uint64_t)k, &o) != 0) return -1;
    o.cfg = op->cfg;
    const int quota = op->placements / op->objects + (k < op->placements % op->objects);
    object_placements(&o, op, quota, &rng, tl);
    for (int l = k; l < op->lines; l += op->objects) object_line(&o, &rng, tl);
    if (isatty(STDERR_FILENO))
      fprintf(stderr, "\rbench_outcome: %s: object %d of %d ", class_name(op->family[c]), k + 1,
              op->objects);
    object_free(&o);
  }
  return 0;
}

int main(int argc, char **argv) {
  cli_log_init("bench_outcome");
  opts_t o = {.placements = 2000, .objects = 5, .per_com = 4, .lines = 24, .show = 4, .seed = 1};
  model_outcome_config_default(&o.cfg);
  if (parse_args(argc, argv, &o) != 0) {
    usage(stderr);
    return 2;
  }
  tally_t *tl = calloc((size_t)o.nclass, sizeof *tl);
  if (!tl) return 1;
  const double t0 = now_s();
  for (int c = 0; c < o.nclass; ++c)
    if (run_class(&o, c, &tl[c]) != 0) return 1;
  if (isatty(STDERR_FILENO)) fprintf(stderr, "\n");
  printf(
      "bench_outcome --placements %d --objects %d --per-com %d --lines %d --seed %llu --tol-um "
      "%g --tilt %g: %.0f s\n",
      o.placements, o.objects, o.per_com, o.lines, (unsigned long long)o.seed, o.cfg.tol_m * 1e6,
      o.cfg.tilt_rad, now_s() - t0);
  report_agreement(&o, tl);
  report_threshold(&o, tl);
  report_tols(&o, tl);
  report_shown(&o, tl);
  report_lines(&o, tl);
  long errors = 0;
  for (int c = 0; c < o.nclass; ++c) errors += tl[c].errors;
  if (errors)
    LOG_W(
        "%ld placements skipped: no pose over the edge (no part of the mesh over B) or a trial "
        "error",
        errors);
  free(tl);
  return 0;
}
