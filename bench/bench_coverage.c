/* bench_coverage: are the reported intervals honest on objects the estimator was not built for?
 *
 * Generates N shapes (tools/shapegen.h families in turn, plus tools/rockgen random rocks as one
 * more family), each as an even and an uneven object (2N URDFs in a temporary folder), and
 * estimates every object with every policy: once noiseless, and with placement and pose noise for
 * seeds 1..K (the estimator told the noise model, so its intervals are 95 % intervals). Run s of
 * object i (0-based, in the order generated) draws its noise from comlearn-sim seed
 * 1000 (i + 1) + s (noise_seed), so no two objects share a noise stream: with one stream per s,
 * as before 2026-12-02, the coverage of K seeds measured K noise draws, not thousands. The truth
 * is read after each estimate, for the statistics only. Per policy and mode it prints, over the
 * objects: how many the estimator refused (no component found, or an error), the components it
 * claimed (found) of those asked, coverage (claimed components whose |error| <= the reported half
 * width), the worst |error| in units of the reported half width, the mean half width and trials;
 * then the same per family for the first policy, and, for the first policy noiseless, the
 * components found on the objects that have two resting poses 30-150 deg apart in the world
 * (world_poses_find, from the truth). Optionally everything as JSON.
 *
 * Goals (issue 11): noiseless coverage 100 %, noisy coverage >= 95 % at the stated 95 % level.
 *
 * Usage: bench_coverage [--objects N] [--seed S] [--policies LIST] [--seeds K]
 *                       [--placement-noise-mm P] [--pose-noise-mm Q] [--jobs J] [--json-file FILE]
 *                       [--keep DIR] [--help]
 * Wall time: a few minutes for the defaults on two cores. */
#define _GNU_SOURCE

#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "comlearn/balance_poses.h"
#include "comlearn/cli_args.h"
#include "comlearn/cli_json.h"
#include "comlearn/cli_log.h"
#include "comlearn/cli_time.h"
#include "comlearn/math3d.h"
#include "comlearn/model.h"
#include "comlearn/model_inertial.h"
#include "estimate_backend.h"
#include "estimate_direct.h"
#include "objfile.h"
#include "rockgen.h"
#include "shapegen.h"
#include "tool_args.h"

enum { MAX_POLICIES = 4, MAX_JOBS = 16, FAMILIES = SHAPEGEN_FAMILY_COUNT + 1, ROCK = FAMILIES - 1 };

typedef struct {
  int objects, seeds, jobs, npol;
  uint64_t seed;
  qlearn_policy_kind_t pol[MAX_POLICIES];
  double placement_m, pose_m;
  double stop_m;   /* estimate_config_t.noise_stop_width_m of the noisy runs (0: the default) */
  double target_m; /* estimate_config_t.noise_target_halfwidth_m (< 0: the default) */
  const char *json, *keep;
} opts_t;

/* One estimate. */
typedef struct {
  int object; /* index into the object list */
  int policy; /* index into opts.pol */
  int seed;   /* 0: noiseless */
  int status; /* estimate_status_t */
  int found[3];
  int support_left[3]; /* not found, and the reason: a support point left B before the CoM
                          crossed the edge (estimate.c, contact_limited_note) */
  double err_m[3], hw_m[3];
  unsigned trials;
  double cpu_s;     /* CPU time of estimate_run (estimator and in-process simulation) */
  int world_poses;  /* first policy, noiseless run: resting directions confirmed with the truth */
  int determinable; /* ... two of them 30-150 deg apart (world_poses_find); -1 not asked */
} rec_t;

typedef struct {
  char urdf[4096];
  char name[72];
  int family; /* shapegen family, or ROCK */
  int uneven;
} obj_t;

static const char *family_name(int f) {
  return f == ROCK ? "rock" : shapegen_family_name((shapegen_family_t)f);
}

/* ---- objects -------------------------------------------------------------------------------- */

static int write_rock(uint64_t seed, const char *dir, char *name, size_t name_size) {
  rockgen_spec_t spec;
  model_mesh_t mesh = {0};
  model_mass_t even, uneven;
  model_halfspace_t region;
  model_status_t st = rockgen_spec_random(seed, &spec);
  if (st == MODEL_OK) st = rockgen_shape_build(&spec, &mesh);
  if (st == MODEL_OK) st = rockgen_mass(&spec, &mesh, &even, &uneven, &region);
  int rc = st == MODEL_OK ? 0 : -1;
  char path[4096];
  snprintf(name, name_size, "%s", spec.name);
  snprintf(path, sizeof path, "%.1024s/meshes/%.64s.stl", dir, spec.name);
  if (rc == 0) rc = objfile_write_stl(&mesh, path, "bench_coverage random rock");
  for (int u = 0; u < 2 && rc == 0; ++u) {
    snprintf(path, sizeof path, "%.1024s/%.64s_%s.urdf", dir, spec.name, u ? "uneven" : "even");
    FILE *f = fopen(path, "w");
    if (!f) {
      rc = -1;
      break;
    }
    fprintf(f, "<?xml version=\"1.0\"?>\n<robot name=\"%s\">\n  <link name=\"%s\">\n", spec.name,
            spec.name);
    objfile_put_inertial(f, u ? &uneven : &even);
    char rel[96];
    snprintf(rel, sizeof rel, "meshes/%s.stl", spec.name);
    objfile_put_mesh_geometry(f, rel, "rock", "0.55 0.51 0.46 1");
    fprintf(f, "  </link>\n</robot>\n");
    rc = fclose(f) == 0 ? 0 : -1;
  }
  model_mesh_free(&mesh);
  return rc;
}

/* Shape i: family i mod FAMILIES, seed S + i; both materials into objs[2i], objs[2i + 1]. */
static int make_objects(const opts_t *o, const char *dir, obj_t *objs) {
  char path[4096];
  snprintf(path, sizeof path, "%.1024s/meshes", dir);
  if (objfile_mkdir(path) != 0) return -1;
  shapegen_object_t *so = malloc(sizeof *so);
  if (!so) return -1;
  for (int i = 0; i < o->objects; ++i) {
    const int fam = i % FAMILIES;
    const uint64_t seed = o->seed + (uint64_t)i;
    char name[64], failed[4096] = "";
    int rc;
    if (fam == ROCK) {
      rc = write_rock(seed, dir, name, sizeof name);
    } else {
      rc = shapegen_generate((shapegen_family_t)fam, seed, so) == MODEL_OK ? 0 : -1;
      if (rc == 0) {
        snprintf(name, sizeof name, "%s", so->spec.name);
        rc = shapegen_write(so, dir, failed, sizeof failed);
        shapegen_object_free(so);
      }
    }
    if (rc != 0) {
      LOG_E("%s seed %llu: cannot generate or write %s", family_name(fam), (unsigned long long)seed,
            failed);
      free(so);
      return -1;
    }
    for (int u = 0; u < 2; ++u) {
      obj_t *ob = &objs[2 * i + u];
      ob->family = fam;
      ob->uneven = u;
      snprintf(ob->name, sizeof ob->name, "%.56s_%s", name, u ? "uneven" : "even");
      snprintf(ob->urdf, sizeof ob->urdf, "%.1024s/%.64s.urdf", dir, ob->name);
    }
  }
  free(so);
  return 0;
}

/* ---- estimates ------------------------------------------------------------------------------- */

/* The world's resting poses of an object, from the truth (the bench may read it; the estimator
 * never does): every hull face its true CoM can rest on (model_faces_stable, largest margin
 * first), set down over B's middle in lib/balance with the true mass properties, skipping faces
 * within 10 deg of one confirmed before and trying at most 48. *poses: the directions confirmed;
 * *determinable: two of them 30-150 deg apart, what the estimator needs for all three components
 * (two non-parallel resting poses). Errors leave both at -1. */
static void world_poses_find(const obj_t *ob, int *poses, int *determinable) {
  enum { FACES = 512, TRIES = 48, KEPT = 48 };
  *poses = *determinable = -1;
  model_object_t mo = {0};
  model_error_t err = {{0}};
  model_mass_t truth;
  balance_config_t bc;
  balance_config_default(&bc);
  balance_world_t *w = NULL;
  balance_object_t *obj = NULL;
  model_face_t *faces = malloc(FACES * sizeof *faces);
  size_t count = 0;
  if (faces == NULL || model_object_load(ob->urdf, NULL, &mo, &err) != MODEL_OK ||
      model_inertial_load(ob->urdf, NULL, &truth, &err) != MODEL_OK ||
      balance_world_create(&bc, &w) != BALANCE_OK ||
      balance_object_create(w, &mo.mesh, &truth, &obj) != BALANCE_OK ||
      model_faces_stable(&mo.mesh, truth.com_m, NULL, faces, FACES, &count) != MODEL_OK) {
    goto done;
  }
  double kept[KEPT][3];
  int nk = 0, tries = 0;
  for (size_t i = 0; i < count && i < FACES && tries < TRIES && nk < KEPT; ++i) {
    const double *n = faces[i].normal_link;
    int near = 0;
    for (int j = 0; j < nk && !near; ++j)
      near = n[0] * kept[j][0] + n[1] * kept[j][1] + n[2] * kept[j][2] > cos(10.0 * CL_PI / 180.0);
    if (near) continue;
    int ok = 0;
    ++tries;
    if (balance_stable_confirm(w, obj, faces[i].orientation_wxyz, truth.com_m, NULL, NULL, &ok) !=
        BALANCE_OK)
      goto done;
    if (ok) memcpy(kept[nk++], n, sizeof kept[0]);
  }
  *poses = nk;
  *determinable = 0;
  for (int i = 0; i < nk; ++i)
    for (int j = i + 1; j < nk; ++j) {
      const double c = kept[i][0] * kept[j][0] + kept[i][1] * kept[j][1] + kept[i][2] * kept[j][2];
      if (fabs(c) <= cos(30.0 * CL_PI / 180.0)) *determinable = 1;
    }
done:
  balance_world_destroy(w); /* and obj */
  model_object_free(&mo);
  free(faces);
}

/* The comlearn-sim / estimate --seed of noisy run s (1..K) of object i: distinct for every run. */
static uint64_t noise_seed(int object, int s) {
  return 1000u * (uint64_t)(object + 1) + (uint64_t)s;
}

static void run_one(const opts_t *o, const obj_t *ob, int object, int pi, int seed,
                    estimate_result_t *res, rec_t *r) {
  memset(r, 0, sizeof *r);
  r->policy = pi;
  r->seed = seed;
  r->status = ESTIMATE_E_ARG;
  model_object_t mo = {0};
  model_error_t err = {{0}};
  if (model_object_load(ob->urdf, NULL, &mo, &err) != MODEL_OK) return;
  estimate_direct_t *sim = NULL;
  estimate_backend_t backend;
  char msg[512];
  if (estimate_direct_open(ob->urdf, NULL, NULL, &sim, &backend, msg, sizeof msg) != 0) {
    model_object_free(&mo);
    return;
  }
  estimate_config_t cfg;
  estimate_config_default(&cfg);
  cfg.policy = o->pol[pi];
  if (seed > 0) {
    estimate_direct_set_noise(sim, noise_seed(object, seed), o->placement_m, o->pose_m);
    cfg.noise_sigma_m = o->placement_m;
    cfg.pose_noise_sigma_m = o->pose_m; /* rough faces with noise need it */
    cfg.noise_stop_width_m = o->stop_m;
    if (o->target_m >= 0.0) cfg.noise_target_halfwidth_m = o->target_m;
    cfg.seed = (uint64_t)seed;
  }
  const double cpu0 = cli_time_cpu_s();
  r->status = estimate_run(&mo.mesh, &backend, &cfg, res);
  r->cpu_s = cli_time_cpu_s() - cpu0;
  estimate_direct_close(sim);
  model_object_free(&mo);
  model_mass_t truth; /* read after the estimate, for the statistics only */
  if (model_inertial_load(ob->urdf, NULL, &truth, &err) != MODEL_OK) return;
  r->trials = (unsigned)res->trial_count;
  for (int k = 0; k < 3; ++k) {
    r->found[k] = r->status == ESTIMATE_OK && res->found[k];
    r->err_m[k] = r->found[k] ? res->com_m[k] - truth.com_m[k] : NAN;
    r->hw_m[k] = r->found[k] ? res->halfwidth_m[k] : NAN;
    r->support_left[k] = r->status == ESTIMATE_OK && !res->found[k] &&
                         strstr(res->reason[k], "support point left B") != NULL;
  }
}

/* Worker w of J: objects w, w + J, ... into file `path` (one rec_t per run). */
static int worker(const opts_t *o, const obj_t *objs, int nobj, int w, const char *path) {
  FILE *f = fopen(path, "wb");
  estimate_result_t *res = malloc(sizeof *res);
  if (!f || !res) return 1;
  for (int i = w; i < nobj; i += o->jobs) {
    for (int p = 0; p < o->npol; ++p) {
      for (int s = 0; s <= o->seeds; ++s) {
        rec_t r;
        run_one(o, &objs[i], i, p, s, res, &r);
        r.object = i;
        r.world_poses = r.determinable = -1;
        if (p == 0 && s == 0) world_poses_find(&objs[i], &r.world_poses, &r.determinable);
        if (fwrite(&r, sizeof r, 1, f) != 1) return 1;
      }
    }
    if (w == 0 && isatty(STDERR_FILENO))
      fprintf(stderr, "\rbench_coverage: object %d of %d", i + 1, nobj);
  }
  free(res);
  return fclose(f) == 0 ? 0 : 1;
}

/* ---- statistics ------------------------------------------------------------------------------ */

/* A growing list of values, for medians. */
typedef struct {
  double *v;
  size_t n, cap;
} list_t;

static void list_add(list_t *l, double x) {
  if (l->n == l->cap) {
    const size_t cap = l->cap ? 2 * l->cap : 64;
    double *v = realloc(l->v, cap * sizeof *v);
    if (v == NULL) return; /* the median then leaves this value out */
    l->v = v;
    l->cap = cap;
  }
  l->v[l->n++] = x;
}

static int cmp_double(const void *a, const void *b) {
  const double x = *(const double *)a, y = *(const double *)b;
  return x < y ? -1 : x > y ? 1 : 0;
}

static double list_median(list_t *l) {
  if (l->n == 0) return NAN;
  qsort(l->v, l->n, sizeof *l->v, cmp_double);
  return l->n % 2 ? l->v[l->n / 2] : 0.5 * (l->v[l->n / 2 - 1] + l->v[l->n / 2]);
}

typedef struct {
  int runs, refused, comps, found, covered;
  double worst, hw_sum, trials_sum, max_err, found_trials, cpu_sum;
  list_t err, per_comp; /* |error| of every found component; a run's trials per found one */
} stat_t;

static void add(stat_t *s, const rec_t *r) {
  ++s->runs;
  int any = 0;
  for (int k = 0; k < 3; ++k) {
    ++s->comps;
    if (!r->found[k]) continue;
    any = 1;
    ++s->found;
    const double q = fabs(r->err_m[k]) / r->hw_m[k];
    s->covered += q <= 1.0;
    if (q > s->worst) s->worst = q;
    if (fabs(r->err_m[k]) > s->max_err) s->max_err = fabs(r->err_m[k]);
    s->hw_sum += r->hw_m[k];
  }
  if (!any) ++s->refused;
  s->trials_sum += r->trials;
  if (any) s->found_trials += r->trials; /* all trials of runs that found something */
  s->cpu_sum += r->cpu_s;
  const int nf = r->found[0] + r->found[1] + r->found[2];
  for (int k = 0; k < 3; ++k)
    if (r->found[k]) list_add(&s->err, fabs(r->err_m[k]));
  if (nf > 0) list_add(&s->per_comp, (double)r->trials / nf);
}

/* One table row; frees the lists of s. */
static void row(FILE *f, const char *label, const char *mode, stat_t *s) {
  fprintf(f,
          "| %s | %s | %d | %d | %d of %d (%.0f %%) | %d of %d (%.1f %%) | %.2f | %.3f / %.3f | "
          "%.3f | %.1f | %.1f / %.1f | %.3f |\n",
          label, mode, s->runs, s->refused, s->found, s->comps,
          s->comps ? 100.0 * s->found / s->comps : 0.0, s->covered, s->found,
          s->found ? 100.0 * s->covered / s->found : 100.0, s->worst, 1e3 * list_median(&s->err),
          1e3 * s->max_err, s->found ? 1e3 * s->hw_sum / s->found : NAN,
          s->runs ? s->trials_sum / s->runs : 0.0, list_median(&s->per_comp),
          s->found ? s->found_trials / s->found : NAN, s->runs ? s->cpu_sum / s->runs : 0.0);
  free(s->err.v);
  free(s->per_comp.v);
}

static const char kHeader[] =
    "| %s | mode | runs | refused | components found | covered | worst \\|err\\| / hw | median / "
    "max \\|err\\| (mm) | mean hw (mm) | trials per run | trials per found component: median / "
    "pooled | CPU s per run |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";

static void report(const opts_t *o, const obj_t *objs, int nobj, const rec_t *recs, size_t n) {
  char target[48] = "the default";
  if (o->target_m >= 0.0) snprintf(target, sizeof target, "%.3g mm", 1e3 * o->target_m);
  printf(
      "# bench_coverage\n\n%d objects (%d shapes x even / uneven, families in turn, seeds "
      "%llu..), "
      "noiseless and with placement %.3g mm / pose %.3g mm noise for seeds 1..%d (per object: "
      "1000 (object + 1) + seed; searches first stop at a 95 %% interval %.3g mm wide, 0: the "
      "default; target half width %s); direct backend.\n\n",
      nobj, o->objects, (unsigned long long)o->seed, 1e3 * o->placement_m, 1e3 * o->pose_m,
      o->seeds, 1e3 * o->stop_m, target);
  printf(kHeader, "policy");
  for (int p = 0; p < o->npol; ++p)
    for (int noisy = 0; noisy < 2; ++noisy) {
      stat_t s = {0};
      for (size_t i = 0; i < n; ++i)
        if (recs[i].policy == p && (recs[i].seed > 0) == noisy) add(&s, &recs[i]);
      if (s.runs)
        row(stdout, estimate_policy_name(o->pol[p]), noisy ? "noisy (95 %)" : "noiseless (bound)",
            &s);
    }
  printf(
      "\nComponents not found, and of them those whose reason is that a support point left B "
      "before the CoM crossed the edge:\n\n| policy | mode | not found | a support point "
      "left B |\n|---|---|---:|---:|\n");
  for (int p = 0; p < o->npol; ++p)
    for (int noisy = 0; noisy < 2; ++noisy) {
      int miss = 0, left = 0, runs = 0;
      for (size_t i = 0; i < n; ++i) {
        if (recs[i].policy != p || (recs[i].seed > 0) != noisy) continue;
        ++runs;
        for (int k = 0; k < 3; ++k) miss += !recs[i].found[k], left += recs[i].support_left[k];
      }
      if (runs)
        printf("| %s | %s | %d | %d |\n", estimate_policy_name(o->pol[p]),
               noisy ? "noisy" : "noiseless", miss, left);
    }
  printf("\nPer family, %s:\n\n", estimate_policy_name(o->pol[0]));
  printf(kHeader, "family");
  for (int fam = 0; fam < FAMILIES; ++fam)
    for (int noisy = 0; noisy < 2; ++noisy) {
      stat_t s = {0};
      for (size_t i = 0; i < n; ++i)
        if (recs[i].policy == 0 && objs[recs[i].object].family == fam &&
            (recs[i].seed > 0) == noisy)
          add(&s, &recs[i]);
      if (s.runs) row(stdout, family_name(fam), noisy ? "noisy" : "noiseless", &s);
    }
  /* The target of issue 13: every component on every object with two non-parallel resting poses
   * (the world's, from the truth: world_poses_find). */
  int det[FAMILIES] = {0}, all[FAMILIES] = {0}, got[FAMILIES] = {0}, ndet = 0, ngot = 0;
  for (size_t i = 0; i < n; ++i) {
    const rec_t *r = &recs[i];
    if (r->policy != 0 || r->seed != 0 || r->determinable < 0) continue;
    const int fam = objs[r->object].family;
    ++all[fam];
    if (r->determinable) {
      ++det[fam];
      ++ndet;
      for (int k = 0; k < 3; ++k) got[fam] += r->found[k], ngot += r->found[k];
    }
  }
  printf(
      "\nObjects with two resting poses 30-150 deg apart in the world (from the truth, "
      "lib/balance), "
      "and the components %s found on them noiseless: %d of %d objects, %d of %d components.\n\n"
      "| family | objects | with two such poses | their components found |\n|---|---:|---:|---:|\n",
      estimate_policy_name(o->pol[0]), ndet, nobj, ngot, 3 * ndet);
  for (int fam = 0; fam < FAMILIES; ++fam)
    if (all[fam])
      printf("| %s | %d | %d | %d of %d |\n", family_name(fam), all[fam], det[fam], got[fam],
             3 * det[fam]);
  for (size_t i = 0; i < n; ++i) {
    const rec_t *r = &recs[i];
    if (r->policy == 0 && r->seed == 0 && r->determinable > 0 &&
        !(r->found[0] && r->found[1] && r->found[2])) {
      printf("- missed on %s (%d resting directions):", objs[r->object].name, r->world_poses);
      for (int k = 0; k < 3; ++k)
        if (!r->found[k])
          printf(" %c%s", "xyz"[k], r -> support_left[k] ? " (a support point left B)" : "");
      printf("\n");
    }
  }
  int shown = 0;
  for (size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k)
      if (recs[i].found[k] && fabs(recs[i].err_m[k]) > recs[i].hw_m[k] && recs[i].seed == 0) {
        if (!shown++) printf("\nNoiseless components outside their bound:\n\n");
        printf("- %s, %s, %c: |error| %.4f mm, bound %.4f mm\n", objs[recs[i].object].name,
               estimate_policy_name(o->pol[recs[i].policy]), "xyz"[k], 1e3 * fabs(recs[i].err_m[k]),
               1e3 * recs[i].hw_m[k]);
      }
}

/* v[k] where found[k], else null, comma separated. */
static void json_triple(FILE *f, const int found[3], const double v[3]) {
  for (int k = 0; k < 3; ++k) {
    if (k) fputs(", ", f);
    cli_json_number(f, found[k] ? v[k] : NAN);
  }
}

static void write_json(const opts_t *o, const obj_t *objs, const rec_t *recs, size_t n) {
  FILE *f = fopen(o->json, "w");
  if (!f) {
    LOG_E("cannot write %s: %s", o->json, strerror(errno));
    return;
  }
  fprintf(f, "{\"placement_noise_m\": %.9g, \"pose_noise_m\": %.9g, \"runs\": [", o->placement_m,
          o->pose_m);
  for (size_t i = 0; i < n; ++i) {
    const rec_t *r = &recs[i];
    fprintf(f, "%s\n{\"object\": ", i ? "," : "");
    cli_json_string(f, objs[r->object].name, 0);
    fprintf(f,
            ", \"family\": \"%s\", \"policy\": \"%s\", \"seed\": %d, \"noise_seed\": %llu, "
            "\"status\": %d, \"trials\": %u, \"found\": [%d, %d, %d], \"error_m\": [",
            family_name(objs[r->object].family), estimate_policy_name(o->pol[r->policy]), r->seed,
            r->seed ? (unsigned long long)noise_seed(r->object, r->seed) : 0ull, r->status,
            r->trials, r->found[0], r->found[1], r->found[2]);
    json_triple(f, r->found, r->err_m);
    fprintf(f, "], \"halfwidth_m\": [");
    json_triple(f, r->found, r->hw_m);
    fprintf(f, "], \"support_left\": [%d, %d, %d]", r->support_left[0], r->support_left[1],
            r->support_left[2]);
    if (r->world_poses >= 0) /* first policy, noiseless */
      fprintf(f, ", \"world_poses\": %d, \"determinable\": %s", r->world_poses,
              r->determinable ? "true" : "false");
    fprintf(f, "}");
  }
  fprintf(f, "\n]}\n");
  fclose(f);
}

/* ---- main ---------------------------------------------------------------------------------- */

static void usage(FILE *f) {
  fprintf(f,
          "usage: bench_coverage [options]\n"
          "Coverage of the reported intervals on generated objects (tools/shapegen families\n"
          "and "
          "random rocks, even and uneven), noiseless and noisy, per policy.\n"
          "  --objects N             shapes, each as an even and an uneven object, 1..2000\n"
          "                          (default: 112, i.e. 224 objects, 8 per family)\n"
          "  --seed S                first seed (default: 1)\n"
          "  --policies LIST         comma list of bisect, pba, paper-qtable, paper-mlp\n"
          "                          (default: bisect,pba,paper-qtable)\n"
          "  --seeds K               noisy runs per object and policy, 0..20 (default: 2)\n"
          "  --placement-noise-mm P  noisy runs' placement noise (default: 0.5)\n"
          "  --pose-noise-mm Q       noisy runs' pose noise (default: 0.2)\n"
          "  --noise-stop-mm W       noisy runs first stop a search at a 95 %% interval W mm\n"
          "                          wide, 0..10 (default: 0: the estimator's default)\n"
          "  --noise-target-mm T     noisy runs refine until every component's 95 %% half\n"
          "                          width is T mm, 0..10; 0: no refinement (default: the\n"
          "                          estimator's, 0.5)\n"
          "  --jobs J                worker processes, 1..%d (default: 2)\n"
          "  --json-file FILE        every run as JSON into FILE (default: none); --json FILE\n"
          "                          is the same (its old name)\n"
          "  --keep DIR              write the objects into DIR and keep them (default: a\n"
          "                          temporary folder, removed at the end)\n"
          "  -h, --help              this text\n"
          "  -V, --version           print the version\n",
          MAX_JOBS);
}

static int parse_policies(const char *arg, opts_t *o) {
  char buf[256];
  snprintf(buf, sizeof buf, "%s", arg);
  o->npol = 0;
  char *save = NULL;
  for (char *t = strtok_r(buf, ",", &save); t; t = strtok_r(NULL, ",", &save)) {
    if (o->npol == MAX_POLICIES || estimate_policy_parse(t, &o->pol[o->npol]) != 0) return -1;
    ++o->npol;
  }
  return o->npol > 0 ? 0 : -1;
}

/* An integer option in [lo, hi]: 0, or -1. */
/* A length option in mm within [0, 100], into metres: 0, or -1. */
static int mm_arg(const char *text, double *out_m) {
  double v = 0.0;
  if (tool_parse_double(text, 0.0, 100.0, &v) != 0) return -1;
  *out_m = 1e-3 * v;
  return 0;
}

static int parse_args(int argc, char **argv, opts_t *o) {
  static const struct option opts[] = {{"objects", required_argument, NULL, 'n'},
                                       {"seed", required_argument, NULL, 's'},
                                       {"policies", required_argument, NULL, 'p'},
                                       {"seeds", required_argument, NULL, 'k'},
                                       {"placement-noise-mm", required_argument, NULL, 'P'},
                                       {"pose-noise-mm", required_argument, NULL, 'Q'},
                                       {"noise-stop-mm", required_argument, NULL, 'W'},
                                       {"noise-target-mm", required_argument, NULL, 'T'},
                                       {"jobs", required_argument, NULL, 'j'},
                                       {"json-file", required_argument, NULL, 'J'},
                                       {"json", required_argument, NULL, 'J'},
                                       {"keep", required_argument, NULL, 'K'},
                                       {"help", no_argument, NULL, 'h'},
                                       {"version", no_argument, NULL, 'V'},
                                       {NULL, 0, NULL, 0}};
  int c, bad = 0;
  opterr = 0;
  while (!bad && (c = getopt_long(argc, argv, "hV", opts, NULL)) != -1) {
    switch (c) {
      case 'n': bad = tool_parse_int(optarg, 1, 2000, &o->objects); break;
      case 's': bad = tool_parse_u64(optarg, &o->seed); break;
      case 'p': bad = parse_policies(optarg, o); break;
      case 'k': bad = tool_parse_int(optarg, 0, 20, &o->seeds); break;
      case 'P': bad = mm_arg(optarg, &o->placement_m); break;
      case 'Q': bad = mm_arg(optarg, &o->pose_m); break;
      case 'W': bad = mm_arg(optarg, &o->stop_m) || o->stop_m > 0.01; break;
      case 'T': bad = mm_arg(optarg, &o->target_m) || o->target_m > 0.01; break;
      case 'j': bad = tool_parse_int(optarg, 1, MAX_JOBS, &o->jobs); break;
      case 'J': o->json = optarg; break;
      case 'K': o->keep = optarg; break;
      case 'h': usage(stdout); exit(0);
      case 'V': cli_version_print(stdout, "bench_coverage"); exit(0);
      default: cli_getopt_complain("bench_coverage", "hV", opts, argv); exit(2);
    }
  }
  return bad || optind != argc ? -1 : 0;
}

int main(int argc, char **argv) {
  cli_log_init("bench_coverage");
  opts_t o = {.objects = 112,
              .seeds = 2,
              .jobs = 2,
              .npol = 3,
              .seed = 1,
              .pol = {QLEARN_POLICY_BISECT, QLEARN_POLICY_PBA, QLEARN_POLICY_PAPER_QTABLE},
              .placement_m = 0.5e-3,
              .pose_m = 0.2e-3,
              .target_m = -1.0};
  if (parse_args(argc, argv, &o) != 0) {
    usage(stderr);
    return 2;
  }
  char dir[4096];
  if (o.keep) {
    snprintf(dir, sizeof dir, "%s", o.keep);
    if (objfile_mkdir(dir) != 0) return 1;
  } else {
    snprintf(dir, sizeof dir, "/tmp/bench_coverage.XXXXXX");
    if (!mkdtemp(dir)) return 1;
  }
  const int nobj = 2 * o.objects;
  obj_t *objs = calloc((size_t)nobj, sizeof *objs);
  if (!objs || make_objects(&o, dir, objs) != 0) return 1;
  pid_t pid[MAX_JOBS];
  for (int w = 0; w < o.jobs; ++w) {
    char path[4200];
    snprintf(path, sizeof path, "%s/runs.%d", dir, w);
    pid[w] = fork();
    if (pid[w] == 0) _exit(worker(&o, objs, nobj, w, path));
    if (pid[w] < 0) return 1;
  }
  int failed = 0;
  for (int w = 0; w < o.jobs; ++w) {
    int ws = 0;
    if (waitpid(pid[w], &ws, 0) < 0 || !WIFEXITED(ws) || WEXITSTATUS(ws) != 0) failed = 1;
  }
  if (isatty(STDERR_FILENO)) fprintf(stderr, "\n");
  const size_t cap = (size_t)nobj * (size_t)o.npol * (size_t)(o.seeds + 1);
  rec_t *recs = malloc(cap * sizeof *recs);
  size_t n = 0;
  for (int w = 0; w < o.jobs && recs; ++w) {
    char path[4200];
    snprintf(path, sizeof path, "%s/runs.%d", dir, w);
    FILE *f = fopen(path, "rb");
    if (!f) continue;
    n += fread(recs + n, sizeof *recs, cap - n, f);
    fclose(f);
    remove(path);
  }
  if (!recs || n != cap || failed) {
    LOG_E("a worker failed (%zu of %zu runs)", n, cap);
    return 1;
  }
  report(&o, objs, nobj, recs, n);
  if (o.json) write_json(&o, objs, recs, n);
  if (!o.keep) {
    char cmd[4200];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0) LOG_E("could not remove %s", dir);
  }
  free(recs);
  free(objs);
  return 0;
}
