/* bench_regimes: the threshold bias of an edge test in each regime of comlearn/balance_poses.h.
 *
 * For each case the object is set down (balance_pose_over_edge, touching) with the link point
 * com_true + d * u over the +X edge, u the link-frame direction of the edge's outward normal, so
 * the true CoM is d inside the edge. d is bisected to 1 um between "tips" and "stays": the bias is
 * the d at the flip (positive: the object tips although its CoM is inside by d; the estimate lands
 * inside the truth by that much). Printed as a table with the regime verdict of the planned trial
 * at the flip. Usage: bench_regimes (no options). Deterministic.
 *
 * Rows: every flat face of the three even rocks at its worst and best yaw (range +-8 mm); the
 * rocks' stable rounded faces (no mesh triangle in the plane: the rock rests on isolated
 * vertices, CoM >= 0.5 mm inside their support polygon, confirmed by balance_stable_confirm) at
 * four yaws (range +-15 mm); an ellipsoid on its pole. Placements whose support lies beyond the
 * edge are set down on B's edge line (balance_pose_over_edge touches B as a solid box). */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "comlearn/balance.h"
#include "comlearn/balance_poses.h"
#include "comlearn/cli_args.h"
#include "comlearn/cli_log.h"
#include "comlearn/math3d.h"
#include "comlearn/model.h"
#include "comlearn/model_inertial.h"

/* v rotated by unit q through the matrix (the bench's numbers were taken with this rounding). */
static void rot(const double q[4], const double v[3], double o[3]) {
  double r[3][3];
  cl_quat_to_rot(q, r);
  for (int i = 0; i < 3; ++i) o[i] = r[i][0] * v[0] + r[i][1] * v[1] + r[i][2] * v[2];
}

static int invalid_count; /* trials that hit the horizon still moving (BALANCE_INVALID) */

/* Outcome with the true CoM d inside the +X edge: 1 stays, 0 tips/slides/invalid, -1 error. */
static int trial(balance_world_t *w, balance_object_t *o, const double q[4], const double com[3],
                 double d) {
  const double qi[4] = {q[0], -q[1], -q[2], -q[3]}, ex[3] = {1, 0, 0};
  double u[3];
  rot(qi, ex, u);
  const double p[3] = {com[0] + d * u[0], com[1] + d * u[1], com[2] + d * u[2]};
  model_pose_t pose;
  if (balance_pose_over_edge(w, o, q, MODEL_EDGE_PX, p, 0.0, 1e-6, &pose) != BALANCE_OK) return -1;
  balance_trial_result_t r;
  if (balance_trial_run(w, o, &pose, NULL, &r) != BALANCE_OK) return -1;
  invalid_count += r.outcome == BALANCE_INVALID;
  return r.outcome == BALANCE_STAYS ? 1 : 0;
}

/* Bisect the flip in [-range, range]; NAN when the ends do not bracket it. */
static double bisect(balance_world_t *w, balance_object_t *o, const double q[4],
                     const double com[3], double range, int *trials) {
  double lo = -range, hi = range; /* lo: CoM beyond the edge (tips); hi: inside (stays) */
  const int a = trial(w, o, q, com, lo), b = trial(w, o, q, com, hi);
  *trials = 2;
  if (a != 0 || b != 1) {
    LOG_E("no bracket: d=-%gmm -> %d, d=+%gmm -> %d (1 stays, 0 tips, -1 error)", range * 1e3, a,
          range * 1e3, b);
    return NAN;
  }
  for (int i = 0; i < 40 && hi - lo > 1e-6; ++i) {
    const double mid = 0.5 * (lo + hi);
    const int r = trial(w, o, q, com, mid);
    ++*trials;
    if (r < 0) return NAN;
    if (r == 1)
      hi = mid;
    else
      lo = mid;
  }
  return 0.5 * (lo + hi);
}

static void report(const char *name, const model_mesh_t *m, balance_world_t *w, balance_object_t *o,
                   const double q[4], const double com_true[3], const double com_est[3],
                   double range) {
  int trials = 0;
  invalid_count = 0;
  const double bias = bisect(w, o, q, com_true, range, &trials);
  /* The outcome need not be monotone in d (a rock that drops onto the edge can roll to a new
   * rest or keep rolling): scan d in 0.5 mm steps for the innermost d that does not stay. */
  double last_not_stay = -HUGE_VAL;
  for (int k = 0; k <= (int)lround(4000.0 * range); ++k) {
    const double d = -range + 0.0005 * k;
    if (trial(w, o, q, com_true, d) == 0) last_not_stay = d;
    ++trials;
  }
  model_pose_t pose;
  model_regime_t reg;
  const double base[3] = {0.30, 0.30, 0.10};
  const char *kind = "?";
  double margin = NAN;
  if (balance_pose_over_edge(w, o, q, MODEL_EDGE_PX, com_est, 0.0, 1e-6, &pose) == BALANCE_OK &&
      model_regime_classify(m, &pose, base, MODEL_EDGE_PX, com_est, NULL, &reg) == MODEL_OK) {
    kind = reg.kind == MODEL_REGIME_FLAT_PATCH  ? "flat patch"
           : reg.kind == MODEL_REGIME_EDGE_ROLL ? "edge roll"
                                                : "point support";
    margin = reg.chord_margin_m;
  }
  printf("| %-38s | %-13s | %9.2f | %10.1f | %7.1f | %4d | %6d |\n", name, kind,
         margin == -HUGE_VAL ? -99.0 : margin * 1e3, bias * 1e6, last_not_stay * 1e3, invalid_count,
         trials);
}

static int rock(int which, int uneven, model_object_t *obj, model_mass_t *truth,
                model_mass_t *uni) {
  char path[1024];
  snprintf(path, sizeof path, "%s/rocks/rock_%d_%s.urdf", COMLEARN_ASSETS_DIR, which,
           uneven ? "uneven" : "even");
  if (model_object_load(path, NULL, obj, NULL) != MODEL_OK) return 0;
  if (model_inertial_load(path, NULL, truth, NULL) != MODEL_OK) return 0;
  return model_mesh_mass(&obj->mesh, 2650.0, uni) == MODEL_OK;
}

/* The -z face at yaw 0 and at the yaw of the largest chord margin, then every flat face at the
 * yaw with the smallest chord margin (sweep) and at the best one. */
static void rows_flat(int which, const model_mesh_t *mesh, balance_world_t *w, balance_object_t *o,
                      const double com_m[3]) {
  char name[96];
  const double up[4] = {1, 0, 0, 0};
  snprintf(name, sizeof name, "rock_%d -z face, yaw 0", which);
  report(name, mesh, w, o, up, com_m, com_m, 0.008);
  double yaw = 0.0, mbest = 0.0, q[4];
  model_yaw_best(mesh, up, com_m, MODEL_EDGE_PX, NULL, &yaw, &mbest);
  model_orientation_yawed(up, yaw, q);
  snprintf(name, sizeof name, "rock_%d -z face, best yaw %.0f deg", which, yaw * 180.0 / CL_PI);
  report(name, mesh, w, o, q, com_m, com_m, 0.008);
  model_face_t faces[256];
  size_t nf = 0;
  model_regime_config_t rc;
  model_regime_config_default(&rc);
  rc.min_com_margin_m = -1.0; /* list all faces, stable or not */
  model_faces_find(mesh, com_m, &rc, faces, 256, &nf);
  for (size_t i = 0; i < nf && i < 256; ++i) {
    if (!faces[i].flat || faces[i].normal_link[2] == -1.0 || faces[i].com_margin_m < 0.0) continue;
    double worst = HUGE_VAL, wyaw = 0.0;
    for (int k = 0; k < 180; ++k) {
      double mk;
      model_yaw_margin(mesh, faces[i].orientation_wxyz, com_m, MODEL_EDGE_PX, k * CL_PI / 180.0,
                       NULL, &mk);
      if (mk > -HUGE_VAL && mk < worst) {
        worst = mk;
        wyaw = k * CL_PI / 180.0;
      }
    }
    model_orientation_yawed(faces[i].orientation_wxyz, wyaw, q);
    snprintf(name, sizeof name, "rock_%d face n=(%.2f,%.2f,%.2f) worst yaw", which,
             faces[i].normal_link[0], faces[i].normal_link[1], faces[i].normal_link[2]);
    report(name, mesh, w, o, q, com_m, com_m, 0.008);
    model_yaw_best(mesh, faces[i].orientation_wxyz, com_m, MODEL_EDGE_PX, NULL, &yaw, &mbest);
    model_orientation_yawed(faces[i].orientation_wxyz, yaw, q);
    snprintf(name, sizeof name, "rock_%d face n=(%.2f,%.2f,%.2f) best yaw", which,
             faces[i].normal_link[0], faces[i].normal_link[1], faces[i].normal_link[2]);
    report(name, mesh, w, o, q, com_m, com_m, 0.008);
  }
}

/* Point support: hull faces that are not flat patches (no mesh triangle in the plane: the rock
 * rests on isolated vertices of its rounded side), stable (CoM margin >= 0.5 mm: none of the
 * bundled rocks' rounded faces reaches the 2 mm candidate margin) and confirmed by a trial. Four
 * yaws; range +-15 mm (the flip may lie millimetres inside). */
static void rows_points(int which, const model_mesh_t *mesh, balance_world_t *w,
                        balance_object_t *o, const double com_m[3]) {
  char name[96];
  double q[4];
  model_face_t faces[256];
  size_t nf = 0;
  model_regime_config_t rc;
  model_regime_config_default(&rc);
  rc.min_com_margin_m = 0.5e-3;
  model_faces_find(mesh, com_m, &rc, faces, 256, &nf);
  for (size_t i = 0; i < nf && i < 256; ++i) {
    if (faces[i].flat || faces[i].face_count > 0 || !faces[i].candidate) continue;
    int confirmed = 0;
    if (balance_stable_confirm(w, o, faces[i].orientation_wxyz, com_m, NULL, NULL, &confirmed) !=
            BALANCE_OK ||
        !confirmed)
      continue;
    for (int k = 0; k < 4; ++k) {
      model_orientation_yawed(faces[i].orientation_wxyz, k * CL_PI / 4.0, q);
      snprintf(name, sizeof name, "rock_%d points n=(%.2f,%.2f,%.2f) m %.2f yaw %d", which,
               faces[i].normal_link[0], faces[i].normal_link[1], faces[i].normal_link[2],
               faces[i].com_margin_m * 1e3, 45 * k);
      report(name, mesh, w, o, q, com_m, com_m, 0.015);
    }
  }
}

/* The rows of even rock `which`. Returns 0, or 1 when it cannot be loaded or simulated. */
static int rock_rows(int which, const balance_config_t *cfg) {
  model_object_t obj;
  model_mass_t truth, uni;
  if (!rock(which, 0, &obj, &truth, &uni)) return 1;
  balance_world_t *w = NULL;
  balance_object_t *o = NULL;
  if (balance_world_create(cfg, &w) != BALANCE_OK ||
      balance_object_create(w, &obj.mesh, &truth, &o) != BALANCE_OK)
    return 1;
  rows_flat(which, &obj.mesh, w, o, truth.com_m);
  rows_points(which, &obj.mesh, w, o, truth.com_m);
  balance_world_destroy(w);
  model_object_free(&obj);
  return 0;
}

/* A UV ellipsoid, semi-axes a, rings x segs, poles first. Returns 0, or 1 out of memory. */
static int ellipsoid_mesh(const double a[3], unsigned rings, unsigned segs, model_mesh_t *m) {
  m->vertex_count = 2 + (size_t)(rings - 1) * segs;
  m->triangle_count = 2 * (size_t)segs * (rings - 1);
  m->vertices_m = malloc(m->vertex_count * sizeof *m->vertices_m);
  m->triangles = malloc(m->triangle_count * sizeof *m->triangles);
  if (m->vertices_m == NULL || m->triangles == NULL) return 1;
  m->vertices_m[0][0] = m->vertices_m[0][1] = m->vertices_m[1][0] = m->vertices_m[1][1] = 0.0;
  m->vertices_m[0][2] = a[2];
  m->vertices_m[1][2] = -a[2];
  for (unsigned i = 1; i < rings; ++i) {
    for (unsigned j = 0; j < segs; ++j) {
      const double th = CL_PI * i / rings, ph = 2.0 * CL_PI * j / segs;
      double *v = m->vertices_m[2 + (i - 1) * segs + j];
      v[0] = a[0] * sin(th) * cos(ph);
      v[1] = a[1] * sin(th) * sin(ph);
      v[2] = a[2] * cos(th);
    }
  }
  size_t t = 0;
#define RING(i, j) ((uint32_t)(2 + ((i)-1) * segs + ((j) % segs)))
  for (unsigned j = 0; j < segs; ++j) {
    const uint32_t t0[3] = {0, RING(1, j), RING(1, j + 1)};
    const uint32_t t1[3] = {1, RING(rings - 1, j + 1), RING(rings - 1, j)};
    memcpy(m->triangles[t++], t0, sizeof t0);
    memcpy(m->triangles[t++], t1, sizeof t1);
  }
  for (unsigned i = 1; i + 1 < rings; ++i) {
    for (unsigned j = 0; j < segs; ++j) {
      const uint32_t t0[3] = {RING(i, j), RING(i + 1, j), RING(i + 1, j + 1)};
      const uint32_t t1[3] = {RING(i, j), RING(i + 1, j + 1), RING(i, j + 1)};
      memcpy(m->triangles[t++], t0, sizeof t0);
      memcpy(m->triangles[t++], t1, sizeof t1);
    }
  }
#undef RING
  return 0;
}

/* Rounded underside: a UV ellipsoid (semi-axes 35, 30, 25 mm; 24 x 48) resting on its pole.
 * Returns 0 or 1. */
static int ellipsoid_row(const balance_config_t *cfg) {
  const double a[3] = {0.035, 0.03, 0.025};
  model_mesh_t m = {0};
  if (ellipsoid_mesh(a, 24, 48, &m) != 0) return 1;
  model_mass_t mass;
  if (model_mesh_mass(&m, 1000.0, &mass) != MODEL_OK) return 1;
  balance_world_t *w = NULL;
  balance_object_t *o = NULL;
  if (balance_world_create(cfg, &w) != BALANCE_OK ||
      balance_object_create(w, &m, &mass, &o) != BALANCE_OK)
    return 1;
  const double up[4] = {1, 0, 0, 0};
  report("ellipsoid on its pole", &m, w, o, up, mass.com_m, mass.com_m, 0.008);
  balance_world_destroy(w);
  model_mesh_free(&m);
  return 0;
}

int main(int argc, char **argv) {
  cli_log_init("bench_regimes");
  static const struct option opts[] = {
      {"help", no_argument, NULL, 'h'}, {"version", no_argument, NULL, 'V'}, {NULL, 0, NULL, 0}};
  int c;
  opterr = 0;
  while ((c = getopt_long(argc, argv, "hV", opts, NULL)) != -1) {
    switch (c) {
      case 'h':
        printf(
            "usage: bench_regimes [-h | --help] [-V | --version]\n"
            "The threshold bias of an edge test in each regime, as a markdown table (a few\n"
            "seconds): see the comment at the top of bench/bench_regimes.c.\n");
        return 0;
      case 'V': cli_version_print(stdout, "bench_regimes"); return 0;
      default: cli_getopt_complain("bench_regimes", "hV", opts, argv); return 2;
    }
  }
  if (cli_args_none_left("bench_regimes", argc, argv)) return 2;
  balance_config_t cfg;
  balance_config_default(&cfg);
  printf(
      "| case | regime (planned) | chord margin mm | bias um | innermost not-stay mm | invalid "
      "| trials |\n|---|---|---|---|---|---|---|\n");
  for (int which = 1; which <= 3; ++which)
    if (rock_rows(which, &cfg) != 0) return 1;
  return ellipsoid_row(&cfg);
}
