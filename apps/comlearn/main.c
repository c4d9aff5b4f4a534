/*
 * comlearn - the command-line front end. A thin shell: it turns a command line into library calls
 * and prints the results (a table, or JSON with --json). Exit codes: 0 success, 1 runtime failure,
 * 2 usage or bad input.
 *
 * Commands:
 *   inspect OBJECT.urdf...   what perception knows of an object (geometry only); --truth adds the
 *                            URDF inertial for reporting, read after the geometry.
 *   estimate OBJECT.urdf     learn the CoM from edge placements (cmd_estimate.c).
 *   watch                    live table of COM_TRIAL / COM_ESTIMATE traffic (cmd_watch.c).
 *   stack OBJECT.urdf...     plan and simulate a stack on the objects' CoMs (cmd_stack.c).
 *   experiments OBJECT.urdf... the paper's Table I and Fig. 2 (cmd_experiments.c).
 *   record FILE              record LCM traffic, losing nothing that arrived (cmd_record.c).
 *   plan OBJECT.urdf         one placement planned for a client to execute (cmd_plan.c).
 *   logcheck LOG...          an LCM log's channels, and whether every trial record is in it
 *                            (cmd_logcheck.c).
 */
#define _GNU_SOURCE
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cmd_estimate.h"
#include "cmd_experiments.h"
#include "cmd_logcheck.h"
#include "cmd_plan.h"
#include "cmd_record.h"
#include "cmd_stack.h"
#include "cmd_watch.h"
#include "comlearn/cli_args.h"
#include "comlearn/cli_json.h"
#include "comlearn/cli_log.h"
#include "comlearn/math3d.h"
#include "comlearn/model.h"
#include "comlearn/model_inertial.h"

enum { EXIT_USAGE = 2 };

/* What inspect learns of one object. */
typedef struct {
  const char *urdf_path;
  model_object_t object;
  model_mass_t uniform; /* density 1: mass_kg is the volume in m^3 */
  size_t hull_triangles;
  double hull_volume_m3;
  int have_truth;
  model_mass_t truth;
} inspect_result_t;

static void usage(FILE *out) {
  fprintf(out,
          "usage: comlearn COMMAND [options] ...\n"
          "       comlearn --help | --version\n"
          "\n"
          "commands:\n"
          "  inspect OBJECT.urdf...   geometry of each object as the estimator sees it:\n"
          "                           triangles, bounding box and its center, volume,\n"
          "                           uniform-density CoM, convex hull\n"
          "  estimate OBJECT.urdf     learn the center of mass from placements on the edge\n"
          "                           of block B (over LCM with comlearn-sim / a YuMi, or\n"
          "                           --direct: in-process); see `comlearn estimate --help`\n"
          "  watch                    live table of the trials and estimates on LCM (a run,\n"
          "                           or an lcm-logplayer replay); see `comlearn watch --help`\n"
          "  stack OBJECT.urdf...     plan a stack on the objects' CoMs (learned, bounding-box\n"
          "                           center or true) and simulate it for 5 s; see\n"
          "                           `comlearn stack --help`\n"
          "  experiments              the paper's Table I and Fig. 2 for every rock and policy,\n"
          "                           noiseless and noisy; see `comlearn experiments --help`\n"
          "  record FILE              record the LCM traffic into FILE (lcm-logger's format)\n"
          "                           without dropping any; see `comlearn record --help`\n"
          "  logcheck LOG...          the events per channel of LCM logs, and whether they hold\n"
          "                           every trial record of every run; see\n"
          "                           `comlearn logcheck --help`\n"
          "  plan OBJECT.urdf         one placement on B's edge planned as estimate plans a\n"
          "                           trial (grasp, YuMi waypoints) for a client to execute;\n"
          "                           see `comlearn plan --help`\n"
          "\n"
          "inspect options:\n"
          "  --link NAME      URDF link to read (default: the root link)\n"
          "  --json           print one JSON object on stdout instead of a table (default: off)\n"
          "  --truth          also read the URDF <inertial> (mass, true CoM) and report the\n"
          "                   distance to the uniform-density CoM; for reporting only\n"
          "                   (default: off)\n"
          "  -v, --verbose    log debug messages on stderr (default: info)\n"
          "  -q, --quiet      log errors only (default: info)\n"
          "  -h, --help       show this help\n"
          "  -V, --version    print the version\n"
          "\n"
          "exit status: 0 success, 1 runtime failure, 2 usage or bad input\n");
}

static int exit_code_for(model_status_t s) {
  if (s == MODEL_OK) return EXIT_SUCCESS;
  return s == MODEL_E_NOMEM ? EXIT_FAILURE : EXIT_USAGE;
}

static model_status_t inspect_one(const char *path, const char *link, int want_truth,
                                  inspect_result_t *r) {
  model_error_t err = {{0}};
  memset(r, 0, sizeof *r);
  r->urdf_path = path;

  model_status_t s = model_object_load(path, link, &r->object, &err);
  if (s != MODEL_OK) goto fail;
  s = model_mesh_mass(&r->object.mesh, 1.0, &r->uniform);
  if (s != MODEL_OK) {
    snprintf(err.msg, sizeof err.msg, "%s: mass properties of the mesh", path);
    goto fail;
  }
  model_mesh_t hull = {0};
  s = model_mesh_hull(&r->object.mesh, &hull, &err);
  if (s != MODEL_OK) goto fail;
  model_mass_t hull_mass;
  s = model_mesh_mass(&hull, 1.0, &hull_mass);
  r->hull_triangles = hull.triangle_count;
  r->hull_volume_m3 = hull_mass.mass_kg;
  model_mesh_free(&hull);
  if (s != MODEL_OK) {
    snprintf(err.msg, sizeof err.msg, "%s: mass properties of the convex hull", path);
    goto fail;
  }
  /* The truth is read last and only for the report: nothing above depends on it. */
  if (want_truth) {
    s = model_inertial_load(path, link, &r->truth, &err);
    if (s != MODEL_OK) goto fail;
    r->have_truth = 1;
  }
  return MODEL_OK;

fail:
  LOG_E("%s (%s)", err.msg[0] ? err.msg : path, model_status_str(s));
  return s;
}

static void json_vec(const char *key, const double v[3], int comma) {
  printf("\"%s\": ", key);
  cli_json_array(stdout, v, 3);
  printf("%s", comma ? ", " : "");
}

static void json_str(const char *key, const char *v, int comma) {
  printf("\"%s\": ", key);
  cli_json_string(stdout, v, 0);
  printf("%s", comma ? ", " : "");
}

static void print_json(const inspect_result_t *results, size_t n) {
  printf("{\"objects\": [");
  for (size_t i = 0; i < n; ++i) {
    const inspect_result_t *r = &results[i];
    const model_object_t *o = &r->object;
    double size[3], center[3];
    for (int k = 0; k < 3; ++k) size[k] = o->aabb.max_m[k] - o->aabb.min_m[k];
    model_aabb_center(&o->aabb, center);
    printf("%s{", i ? ", " : "");
    json_str("urdf", r->urdf_path, 1);
    json_str("robot", o->robot_name, 1);
    json_str("link", o->link_name, 1);
    json_str("mesh", o->mesh_path, 1);
    printf("\"triangles\": %zu, \"vertices\": %zu, ", o->mesh.triangle_count, o->mesh.vertex_count);
    json_vec("aabb_min_m", o->aabb.min_m, 1);
    json_vec("aabb_max_m", o->aabb.max_m, 1);
    json_vec("size_m", size, 1);
    json_vec("bbox_center_m", center, 1);
    printf("\"volume_m3\": %.9g, ", r->uniform.mass_kg);
    json_vec("uniform_com_m", r->uniform.com_m, 1);
    printf("\"hull_triangles\": %zu, \"hull_volume_m3\": %.9g", r->hull_triangles,
           r->hull_volume_m3);
    if (r->have_truth) {
      printf(", \"truth_mass_kg\": %.9g, ", r->truth.mass_kg);
      json_vec("truth_com_m", r->truth.com_m, 1);
      printf("\"truth_minus_uniform_m\": %.9g", cl_vec3_dist(r->truth.com_m, r->uniform.com_m));
    }
    printf("}");
  }
  printf("]}\n");
}

static void print_table(const inspect_result_t *results, size_t n, int truth) {
  printf("%-18s %6s %22s %25s %24s", "object", "tris", "size (mm)", "bbox center (mm)",
         "uniform CoM (mm)");
  if (truth) printf(" %8s %24s %9s", "mass(kg)", "true CoM (mm)", "|d| (mm)");
  printf("\n");
  for (size_t i = 0; i < n; ++i) {
    const inspect_result_t *r = &results[i];
    const model_aabb_t *b = &r->object.aabb;
    double c[3];
    model_aabb_center(b, c);
    const double *u = r->uniform.com_m;
    printf("%-18s %6zu   %6.1f %6.1f %6.1f   %7.2f %7.2f %7.2f  %7.2f %7.2f %7.2f",
           r->object.robot_name, r->object.mesh.triangle_count, 1e3 * (b->max_m[0] - b->min_m[0]),
           1e3 * (b->max_m[1] - b->min_m[1]), 1e3 * (b->max_m[2] - b->min_m[2]), 1e3 * c[0],
           1e3 * c[1], 1e3 * c[2], 1e3 * u[0], 1e3 * u[1], 1e3 * u[2]);
    if (truth) {
      const double *t = r->truth.com_m;
      printf(" %8.4f  %7.2f %7.2f %7.2f %9.3f", r->truth.mass_kg, 1e3 * t[0], 1e3 * t[1],
             1e3 * t[2], 1e3 * cl_vec3_dist(t, u));
    }
    printf("\n");
  }
}

static int cmd_inspect(int argc, char **argv) {
  static const struct option opts[] = {
      {"link", required_argument, NULL, 'l'}, {"json", no_argument, NULL, 'j'},
      {"truth", no_argument, NULL, 't'},      {"verbose", no_argument, NULL, 'v'},
      {"quiet", no_argument, NULL, 'q'},      {"help", no_argument, NULL, 'h'},
      {"version", no_argument, NULL, 'V'},    {NULL, 0, NULL, 0}};
  const char *link = NULL;
  int json = 0, truth = 0, c;
  optind = 1;
  opterr = 0;
  while ((c = getopt_long(argc, argv, "vqhV", opts, NULL)) != -1) {
    switch (c) {
      case 'l': link = optarg; break;
      case 'j': json = 1; break;
      case 't': truth = 1; break;
      case 'v': cli_log_set_level(CLI_LOG_DEBUG); break;
      case 'q': cli_log_set_level(CLI_LOG_ERROR); break;
      case 'h': usage(stdout); return EXIT_SUCCESS;
      case 'V': cli_version_print(stdout, "comlearn"); return EXIT_SUCCESS;
      default: cli_getopt_complain("comlearn inspect", "vqhV", opts, argv); return EXIT_USAGE;
    }
  }
  if (optind >= argc) {
    LOG_E("inspect needs at least one OBJECT.urdf");
    usage(stderr);
    return EXIT_USAGE;
  }
  size_t n = (size_t)(argc - optind);
  inspect_result_t *results = calloc(n, sizeof *results);
  if (!results) {
    LOG_E("out of memory");
    return EXIT_FAILURE;
  }
  int rc = EXIT_SUCCESS;
  size_t ok = 0;
  for (size_t i = 0; i < n; ++i) {
    model_status_t s = inspect_one(argv[optind + (int)i], link, truth, &results[ok]);
    if (s == MODEL_OK) {
      ++ok;
    } else {
      model_object_free(&results[ok].object);
      int code = exit_code_for(s);
      if (code == EXIT_FAILURE || rc == EXIT_SUCCESS) rc = code;
    }
  }
  if (json)
    print_json(results, ok);
  else
    print_table(results, ok, truth);
  for (size_t i = 0; i < ok; ++i) model_object_free(&results[i].object);
  free(results);
  return rc;
}

int main(int argc, char **argv) {
  cli_log_init("comlearn");
  if (argc < 2) {
    usage(stderr);
    return EXIT_USAGE;
  }
  const char *cmd = argv[1];
  if (strcmp(cmd, "-h") == 0 || strcmp(cmd, "--help") == 0 || strcmp(cmd, "help") == 0) {
    usage(stdout);
    return EXIT_SUCCESS;
  }
  if (strcmp(cmd, "-V") == 0 || strcmp(cmd, "--version") == 0 || strcmp(cmd, "version") == 0) {
    cli_version_print(stdout, "comlearn");
    return EXIT_SUCCESS;
  }
  if (strcmp(cmd, "inspect") == 0) return cmd_inspect(argc - 1, argv + 1);
  if (strcmp(cmd, "estimate") == 0) return cmd_estimate(argc - 1, argv + 1);
  if (strcmp(cmd, "watch") == 0) return cmd_watch(argc - 1, argv + 1);
  if (strcmp(cmd, "stack") == 0) return cmd_stack(argc - 1, argv + 1);
  if (strcmp(cmd, "experiments") == 0) return cmd_experiments(argc - 1, argv + 1);
  if (strcmp(cmd, "logcheck") == 0) return cmd_logcheck(argc - 1, argv + 1);
  if (strcmp(cmd, "record") == 0) return cmd_record(argc - 1, argv + 1);
  if (strcmp(cmd, "plan") == 0) return cmd_plan(argc - 1, argv + 1);
  if (cmd[0] == '-')
    LOG_E("unknown option '%s'", cmd);
  else
    LOG_E("unknown command '%s'", cmd);
  usage(stderr);
  return EXIT_USAGE;
}
