/* bench_pivot: how exact is a pivot trial (lib/estimate's knife-edge test, docs/estimate.md,
 * "Pivots") in lib/balance? For each object (URDFs on the command line, e.g. written by
 * comlearn-shapegen) it picks hull edges at random (seeded) that the estimator could plan for the
 * true CoM (estimate_pivot_plan: the object touches B only along the edge over the tilt range),
 * sorted into buckets by how far inside the edge's ends the CoM projects, and bisects the tilt
 * with real trials, each read as the estimator reads it (estimate_pivot_outcome), until a trial is
 * unclear or the bracket is 1 nm wide. The truth is known: the CoM balances straight over the
 * edge (x = u . c). A row per family: edges, ends that did not bracket (both ends the same or
 * unclear), brackets that hold the truth, the worst distance of the truth outside a bracket, and
 * the bracket widths where bisection stopped. Reads the URDF inertial: a bench, never the
 * estimator.
 *
 * --dump FILE also writes JSON lines for a second engine (bench/mujoco_pivots.py): a "config"
 * line (balance_config_t, as bench/placements_dump's), an "object" line per object (as
 * placements_dump's), a "pivot" line per edge (its geometry: ends, unit directions e, up, u, the
 * midpoint, h, gx, the tilt range, the truth's x and lib/balance's final bracket) and 12
 * "placement" lines per bracketed edge at the truth +- 1, 3, 10, 30, 100 and 300 um (release pose,
 * lib/balance's outcome, what the estimator counts it as, turn and rotation). */
#define _GNU_SOURCE

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "comlearn/balance.h"
#include "comlearn/cli_args.h"
#include "comlearn/cli_log.h"
#include "comlearn/math3d.h"
#include "comlearn/model.h"
#include "comlearn/model_inertial.h"
#include "comlearn/model_support.h"
#include "pivot.h" /* lib/estimate/src: the estimator's own pivot geometry */

enum { BUCKETS = 6, MAX_FAMILIES = 32, TRIES = 20000 };
static const double bucket_lo_mm[BUCKETS] = {0.05, 0.2, 0.5, 1.0, 2.0, 5.0};

typedef struct {
  char name[32];
  int edges, unbracketed, inside;
  double worst_outside_m;
  double width_m[4096];
  int widths;
} fam_t;

typedef struct {
  balance_world_t *w;
  balance_object_t *obj;
  const model_mesh_t *mesh;
  const double *base;
} sim_t;

static FILE *dump; /* --dump FILE, or NULL */
static int dump_object_id, dump_pivot_id;

/* One pivot trial at x: 0 and *r, or -1 when the pose is not a pivot or lib/balance refused it. */
static int pivot_run(const sim_t *s, const estimate_pivot_t *pv, double x,
                     balance_trial_result_t *r) {
  model_pose_t rel;
  if (!estimate_pivot_pose(pv, s->mesh, s->base, x, 1e-6, &rel)) return -1;
  return balance_trial_run(s->w, s->obj, &rel, NULL, r) == BALANCE_OK ? 0 : -1;
}

/* One pivot trial at x, read as the estimator reads it: ESTIMATE_TIPS / STAYS / INVALID, or -1
 * when lib/balance refused the pose. */
static int pivot_trial(const sim_t *s, const estimate_pivot_t *pv, double x) {
  balance_trial_result_t r;
  if (pivot_run(s, pv, x, &r) != 0) return -1;
  return (int)estimate_pivot_outcome((estimate_outcome_t)r.outcome, &r.released, &r.settled);
}

static void dump_arr(const char *key, const double *v, int n) {
  fprintf(dump, ", \"%s\": [", key);
  for (int i = 0; i < n; ++i) fprintf(dump, "%s%.17g", i ? ", " : "", v[i]);
  fprintf(dump, "]");
}

static const char *outcome_name(int o) {
  static const char *const names[] = {"INVALID", "STAYS", "TIPS", "SLIDES"};
  return o >= 0 && o <= 3 ? names[o] : "?";
}

/* The pivot line of pv and, when bracketed, its 12 placements at the truth +- 1 .. 300 um. */
static void dump_pivot(const sim_t *s, const estimate_pivot_t *pv, const double c[3], double lo,
                       double hi, int bracketed) {
  const int id = dump_pivot_id++;
  const double truth = cl_vec3_dot(pv->u, c);
  fprintf(dump, "{\"type\": \"pivot\", \"object\": %d, \"pivot\": %d", dump_object_id, id);
  dump_arr("p1_m", pv->p1_m, 3);
  dump_arr("p2_m", pv->p2_m, 3);
  dump_arr("mid_m", pv->mid_m, 3);
  dump_arr("e", pv->e, 3);
  dump_arr("up", pv->up, 3);
  dump_arr("u", pv->u, 3);
  const double tilt[2] = {pv->beta_lo_rad, pv->beta_hi_rad}, br[2] = {lo, hi};
  fprintf(dump, ", \"h_m\": %.17g, \"gx_m\": %.17g, \"truth_x_m\": %.17g, \"side_m\": %.17g",
          pv->h_m, pv->gx_m, truth, estimate_pivot_side_margin(pv, c));
  dump_arr("tilt_rad", tilt, 2);
  dump_arr("balance_bracket_m", br, 2);
  fprintf(dump, ", \"bracketed\": %s}\n", bracketed ? "true" : "false");
  static const double off_um[] = {-300, -100, -30, -10, -3, -1, 1, 3, 10, 30, 100, 300};
  for (size_t k = 0; bracketed && k < sizeof off_um / sizeof off_um[0]; ++k) {
    balance_trial_result_t r;
    const double x = truth + 1e-6 * off_um[k];
    if (pivot_run(s, pv, x, &r) != 0) continue;
    const int counted =
        (int)estimate_pivot_outcome((estimate_outcome_t)r.outcome, &r.released, &r.settled);
    fprintf(dump, "{\"type\": \"placement\", \"object\": %d, \"pivot\": %d, \"x_m\": %.17g",
            dump_object_id, id, x);
    dump_arr("release_p", r.released.position_m, 3);
    dump_arr("release_q", r.released.orientation_wxyz, 4);
    dump_arr("settled_q", r.settled.orientation_wxyz, 4);
    fprintf(dump,
            ", \"outcome\": \"%s\", \"counted\": \"%s\", \"rotation_rad\": %.17g, "
            "\"steps\": %u}\n",
            outcome_name(r.outcome), outcome_name(counted), r.rotation_rad, r.steps);
  }
}

/* What the bisection of one pivot found. */
typedef struct {
  int bracketed;    /* its range's ends tipped and turned back */
  double outside_m; /* how far the truth lies outside the final bracket (<= 0: inside) */
  double width_m;   /* the final bracket */
} bisect_t;

/* Bisect pivot pv over its range for the true CoM c. */
static bisect_t pivot_bisect(const sim_t *s, const estimate_pivot_t *pv, const double c[3],
                             const char *urdf) {
  bisect_t b = {0};
  double lo = pv->gx_m - pv->h_m * tan(pv->beta_hi_rad);
  double hi = pv->gx_m - pv->h_m * tan(pv->beta_lo_rad);
  if (pivot_trial(s, pv, lo) != ESTIMATE_TIPS || pivot_trial(s, pv, hi) != ESTIMATE_STAYS) {
    if (dump) dump_pivot(s, pv, c, lo, hi, 0);
    return b;
  }
  b.bracketed = 1;
  for (int it = 0; it < 80 && hi - lo > 1e-9; ++it) {
    const double mid = 0.5 * (lo + hi);
    const int o = pivot_trial(s, pv, mid);
    if (o == ESTIMATE_TIPS)
      lo = mid;
    else if (o == ESTIMATE_STAYS)
      hi = mid;
    else
      break; /* unclear: the CoM within a micron or so of the plane */
  }
  const double truth = cl_vec3_dot(pv->u, c); /* balanced straight over the edge */
  b.outside_m = fmax(lo - truth, truth - hi);
  if (dump) dump_pivot(s, pv, c, lo, hi, 1);
  b.width_m = hi - lo;
  if (b.outside_m > 0.0)
    LOG_I(
        "%s: edge %u-%u: the truth %.3f um outside [%.6f, %.6f] mm (side %.3f mm, h %.2f mm, "
        "tilts %.3f..%.3f rad)",
        urdf, pv->v[0], pv->v[1], 1e6 * b.outside_m, 1e3 * (lo - truth), 1e3 * (hi - truth),
        1e3 * estimate_pivot_side_margin(pv, c), 1e3 * pv->h_m, pv->beta_lo_rad, pv->beta_hi_rad);
  return b;
}

static void record(fam_t *f, const bisect_t *b) {
  ++f->edges;
  if (!b->bracketed) {
    ++f->unbracketed;
    return;
  }
  if (b->outside_m <= 0.0)
    ++f->inside;
  else
    f->worst_outside_m = fmax(f->worst_outside_m, b->outside_m);
  if (f->widths < (int)(sizeof f->width_m / sizeof f->width_m[0]))
    f->width_m[f->widths++] = b->width_m;
}

static int cmp_double(const void *a, const void *b) {
  const double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* The object's family: its file name up to the first '_' (rim_s21_even -> rim). */
static fam_t *family_of(const char *urdf, fam_t *fams, int *nf) {
  const char *base = strrchr(urdf, '/');
  base = base ? base + 1 : urdf;
  char name[32];
  snprintf(name, sizeof name, "%.*s", (int)strcspn(base, "_."), base);
  for (int i = 0; i < *nf; ++i)
    if (strcmp(fams[i].name, name) == 0) return &fams[i];
  if (*nf >= MAX_FAMILIES) return &fams[MAX_FAMILIES - 1];
  fam_t *f = &fams[(*nf)++];
  memset(f, 0, sizeof *f);
  snprintf(f->name, sizeof f->name, "%s", name);
  return f;
}

/* The object line of the dump (as bench/placements_dump's). */
static void dump_object(const model_object_t *mo, const model_mass_t *truth) {
  double r = 0.0;
  for (size_t i = 0; i < mo->mesh.vertex_count; ++i)
    r = fmax(r, cl_vec3_dist(mo->mesh.vertices_m[i], truth->com_m));
  fprintf(dump, "{\"type\": \"object\", \"object\": %d, \"mesh\": \"%s\", \"name\": \"%s\"",
          dump_object_id, mo->mesh_path, mo->robot_name);
  fprintf(dump, ", \"mass_kg\": %.17g, \"radius_m\": %.17g", truth->mass_kg, r);
  dump_arr("com_m", truth->com_m, 3);
  dump_arr("inertia_kg_m2", &truth->inertia_kg_m2[0][0], 9);
  fprintf(dump, "}\n");
}

/* The config line of the dump (as bench/placements_dump's). */
static void dump_config(void) {
  balance_config_t c;
  balance_config_default(&c);
  fprintf(dump, "{\"type\": \"config\"");
  dump_arr("base_size_m", c.base_size_m, 3);
  fprintf(dump,
          ", \"gravity_m_s2\": %.17g, \"dt_s\": %.17g, \"friction\": %.17g, "
          "\"rest_min_time_s\": %.17g, \"rest_lin_m_s\": %.17g, \"rest_ang_rad_s\": %.17g, "
          "\"rest_steps\": %d, \"tip_grow_steps\": %d, \"horizon_s\": %.17g, "
          "\"tip_angle_rad\": %.17g, \"slide_m\": %.17g, \"touch_depth_m\": 1e-06}\n",
          c.gravity_m_s2, c.dt_s, c.friction, c.rest_min_time_s, c.rest_lin_m_s, c.rest_ang_rad_s,
          c.rest_steps, c.tip_grow_steps, c.horizon_s, c.tip_angle_rad, c.slide_m);
}

/* Up to `per` edges per margin bucket of one object, recorded in its family f and the bucket's
 * row. 0, or -1 when it cannot be loaded. */
static int object_run(const char *urdf, int per, uint64_t *rng, fam_t *f, fam_t *buckets) {
  model_object_t mo = {0};
  model_error_t err = {{0}};
  model_mass_t truth;
  model_mesh_t hull = {0};
  balance_config_t bc;
  balance_config_default(&bc);
  sim_t s = {.mesh = &mo.mesh, .base = bc.base_size_m};
  model_hull_edge_t *edges = NULL;
  size_t n = 0;
  int rc = -1;
  if (model_object_load(urdf, NULL, &mo, &err) != MODEL_OK ||
      model_inertial_load(urdf, NULL, &truth, &err) != MODEL_OK ||
      model_mesh_hull(&mo.mesh, &hull, &err) != MODEL_OK ||
      balance_world_create(&bc, &s.w) != BALANCE_OK ||
      balance_object_create(s.w, &mo.mesh, &truth, &s.obj) != BALANCE_OK)
    goto done;
  if (dump) dump_object(&mo, &truth);
  edges = malloc(3 * hull.triangle_count * sizeof *edges);
  if (!edges ||
      model_hull_edges(&hull, cos(1e-3), edges, 3 * hull.triangle_count, &n) != MODEL_OK || !n)
    goto done;
  int done[BUCKETS] = {0};
  for (int t = 0; t < TRIES; ++t) {
    const model_hull_edge_t *he = &edges[cl_rng_below(rng, (unsigned)n)];
    estimate_pivot_t pv;
    if (!estimate_pivot_plan(&hull, he, (int)cl_rng_below(rng, 2), truth.com_m,
                             ESTIMATE_PIVOT_WEDGE_RAD, ESTIMATE_PIVOT_HEIGHT_M, &pv))
      continue;
    const double side_mm = 1e3 * estimate_pivot_side_margin(&pv, truth.com_m);
    int b = BUCKETS - 1;
    while (b >= 0 && side_mm < bucket_lo_mm[b]) --b;
    if (b < 0 || done[b] >= per) continue;
    ++done[b];
    const bisect_t r = pivot_bisect(&s, &pv, truth.com_m, urdf);
    record(f, &r);
    record(&buckets[b], &r);
  }
  rc = 0;
  ++dump_object_id;
done:
  if (rc != 0) LOG_W("%s: %s", urdf, err.msg[0] ? err.msg : "not usable");
  free(edges);
  balance_world_destroy(s.w);
  model_mesh_free(&hull);
  model_object_free(&mo);
  return rc;
}

static void print_row(fam_t *f) {
  qsort(f->width_m, (size_t)f->widths, sizeof f->width_m[0], cmp_double);
  const double med = f->widths ? f->width_m[f->widths / 2] : NAN;
  const double max = f->widths ? f->width_m[f->widths - 1] : NAN;
  printf("| %s | %d | %d | %d of %d | %.3f | %.4f / %.3f |\n", f->name, f->edges, f->unbracketed,
         f->inside, f->edges - f->unbracketed, 1e6 * f->worst_outside_m, 1e6 * med, 1e6 * max);
}

int main(int argc, char **argv) {
  cli_log_init("bench_pivot");
  static const struct option opts[] = {
      {"edges", required_argument, NULL, 'e'}, {"seed", required_argument, NULL, 's'},
      {"dump", required_argument, NULL, 'd'},  {"help", no_argument, NULL, 'h'},
      {"version", no_argument, NULL, 'V'},     {NULL, 0, NULL, 0}};
  long per = 1;
  unsigned long long seed = 1;
  int c;
  opterr = 0;
  while ((c = getopt_long(argc, argv, "hV", opts, NULL)) != -1) {
    char *end;
    switch (c) {
      case 'e':
        per = strtol(optarg, &end, 10);
        if (*end || end == optarg || per < 1 || per > 100) {
          LOG_E("--edges: '%s' is not a whole number in 1..100", optarg);
          return 2;
        }
        break;
      case 's':
        seed = strtoull(optarg, &end, 10);
        if (*end || end == optarg || optarg[0] == '-') {
          LOG_E("--seed: '%s' is not a whole number", optarg);
          return 2;
        }
        break;
      case 'd':
        dump = fopen(optarg, "w");
        if (!dump) {
          LOG_E("--dump: cannot write '%s'", optarg);
          return 2;
        }
        break;
      case 'h':
        printf(
            "usage: bench_pivot [--edges N] [--seed S] [--dump FILE] OBJECT.urdf...\n"
            "How exact a pivot trial (an object balanced on B's edge line along a hull edge,\n"
            "tilted) is in lib/balance: per object, N random hull edges (1..100, default 1) in\n"
            "each of six buckets of how far inside the edge's ends the true CoM projects\n"
            "(0.05, 0.2, 0.5, 1, 2, 5 mm and up), each bisected with trials read as the\n"
            "estimator reads them; a markdown row per family (the file name up to its first\n"
            "'_'). --seed S picks the edges (default 1). --dump FILE: every edge and 12\n"
            "placements around each threshold as JSON lines for bench/mujoco_pivots.py\n"
            "(default: none). Reads the URDF inertial (the truth).\n"
            "See the comment at the top of bench/bench_pivot.c.\n");
        return 0;
      case 'V': cli_version_print(stdout, "bench_pivot"); return 0;
      default: cli_getopt_complain("bench_pivot", "hV", opts, argv); return 2;
    }
  }
  if (optind >= argc) {
    LOG_E("no OBJECT.urdf (try --help)");
    return 2;
  }
  if (dump) dump_config();
  static fam_t fams[MAX_FAMILIES], buckets[BUCKETS];
  int nf = 0, failed = 0;
  uint64_t rng = seed;
  for (int b = 0; b < BUCKETS; ++b)
    snprintf(buckets[b].name, sizeof buckets[b].name, ">= %g mm", bucket_lo_mm[b]);
  for (int i = optind; i < argc; ++i)
    failed += object_run(argv[i], (int)per, &rng, family_of(argv[i], fams, &nf), buckets) != 0;
  static const char *const head =
      " | edges | not bracketed | truth inside the bracket | worst outside (um) | bracket at "
      "stop (um): median / max |\n|---|---:|---:|---:|---:|---:|\n";
  printf("| CoM inside the edge's ends%s", head);
  for (int b = 0; b < BUCKETS; ++b) print_row(&buckets[b]);
  printf("\n| family%s", head);
  fam_t all = {.name = "all"};
  for (int i = 0; i < nf; ++i) {
    all.edges += fams[i].edges;
    all.unbracketed += fams[i].unbracketed;
    all.inside += fams[i].inside;
    all.worst_outside_m = fmax(all.worst_outside_m, fams[i].worst_outside_m);
    for (int k = 0; k < fams[i].widths && all.widths < 4096; ++k)
      all.width_m[all.widths++] = fams[i].width_m[k];
    print_row(&fams[i]);
  }
  print_row(&all);
  if (dump && fclose(dump) != 0) {
    LOG_E("--dump: write failed");
    return 1;
  }
  return failed ? 1 : 0;
}
