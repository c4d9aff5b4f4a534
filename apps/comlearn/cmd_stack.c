/*
 * cmd_stack.c - `comlearn stack OBJECT.urdf...`: believe a CoM for every object (learned with the
 * estimator, the bounding-box center, or the URDF truth as an oracle), plan a stack on those
 * beliefs from geometry only (lib/stack), then release it in simulation with the truth
 * (stack_simulate) and report whether it stands.
 */
#define _GNU_SOURCE
#include "cmd_stack.h"

#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "comlearn/cli_args.h"
#include "comlearn/cli_json.h"
#include "comlearn/cli_log.h"
#include "comlearn/cli_paths.h"
#include "comlearn/cli_time.h"
#include "comlearn/math3d.h"
#include "comlearn/model.h"
#include "comlearn/model_inertial.h"
#include "comlearn/stack.h"
#include "estimate_backend.h"
#include "estimate_direct.h"
#include "estimate_lcm.h"
#include "stack_svg.h"

enum { EXIT_USAGE = 2 };

static const double kDensity = 2650.0; /* nominal rock density for the mass guesses */
static const double kMissingHalfwidth = 3e-3;

static void usage(FILE *out) {
  fprintf(
      out,
      "usage: comlearn stack OBJECT.urdf... [options]   (2..%d objects)\n"
      "\n"
      "Plans a stack of the objects on their believed CoMs from geometry only (each object\n"
      "resting with a hull face on a facet of the one below, the CoM of everything above\n"
      "each contact over its support polygon), then simulates it with the true mass\n"
      "properties and reports whether it stands (docs/stack.md).\n"
      "\n"
      "options:\n"
      "  --com SRC          where the believed CoMs come from (default: learned):\n"
      "                       learned  estimate each CoM first (comlearn estimate); its half\n"
      "                                widths are the planner's uncertainty\n"
      "                       bbox     the mesh's bounding-box center (what a camera gives)\n"
      "                       true     the URDF <inertial> CoM: the oracle, for comparison\n"
      "  --lcm-url URL      learned: run the trials over LCM against a running comlearn-sim\n"
      "                     (default: in-process, as `comlearn estimate --direct`)\n"
      "  --direct           learned: in-process, on lib/balance (the default; as estimate's)\n"
      "  --policy P         learned: bisect | pba | paper-qtable | paper-mlp (default: bisect)\n"
      "  --mass-uncertainty U  relative mass uncertainty; plans hold for masses in\n"
      "                     m*[1/(1+U), 1+U], m = mesh volume x 2650 kg/m^3 (default: 0.3)\n"
      "  --max-tilt-deg D   steepest contact plane of the first plan, 1..45 (default: 20);\n"
      "                     a plan that falls in rehearsal, or still moves in its last\n"
      "                     second (creeps), is replaced by one with contacts at most\n"
      "                     4 degrees flatter, down to 4 degrees;\n"
      "                     with no plan at all at D, steeper ones, up to D + 12\n"
      "  --no-rehearse      build the first plan without rehearsing it on the beliefs\n"
      "                     (default: rehearse each plan in simulation on the believed\n"
      "                     CoMs and mass guesses before the real run)\n"
      "  --duration-s S     simulated time the stack must stand, 0.01..600 (default: 5)\n"
      "  --svg FILE         write a side view of the stack as the simulation left it, over\n"
      "                     the planned poses (default: none)\n"
      "  --json             print one JSON object on stdout (default: a table)\n"
      "  -v, --verbose      log debug messages on stderr (default: info)\n"
      "  -q, --quiet        log errors only (default: info, progress lines on stderr)\n"
      "  -h, --help         show this help\n"
      "  -V, --version      print the version\n"
      "\n"
      "exit status: 0 planned and simulated (standing or not), 1 runtime failure (e.g. no\n"
      "stable plan), 2 usage or bad input\n",
      STACK_MAX_OBJECTS);
}

static int com_parse(const char *s, stack_com_source_t *out) {
  static const stack_com_source_t all[] = {STACK_COM_LEARNED, STACK_COM_BBOX, STACK_COM_TRUE};
  for (size_t i = 0; i < sizeof all / sizeof all[0]; ++i)
    if (strcmp(s, stack_com_source_str(all[i])) == 0) {
      *out = all[i];
      return 0;
    }
  return -1;
}

static int number_arg(const char *opt, const char *s, double lo, double hi, double *out) {
  char *end;
  errno = 0;
  const double v = strtod(s, &end);
  if (end == s || *end != '\0' || errno != 0 || !isfinite(v) || v < lo || v > hi) {
    LOG_E("%s: '%s' is not a number in [%g, %g]", opt, s, lo, hi);
    return -1;
  }
  *out = v;
  return 0;
}

static void lcm_log(void *ctx, const char *msg) {
  (void)ctx;
  LOG_D("lcm: %s", msg);
}

/* What we believe of one object, and how we came to believe it. */
typedef struct {
  const char *urdf;
  model_object_t geo;
  double mass_kg;
  double com_m[3], halfwidth_m[3];
  int found[3];
  size_t trials;
} belief_t;

/* Learn the CoM of b->urdf with the estimator (direct backend, or LCM when lcm_url). Returns an
 * exit status (0 ok). */
static int learn(belief_t *b, const char *lcm_url, qlearn_policy_kind_t policy,
                 const char *policy_name) {
  char err[512] = "";
  estimate_backend_t backend;
  estimate_direct_t *sim = NULL;
  estimate_lcm_t *lcmb = NULL;
  int rc;
  if (lcm_url) {
    estimate_lcm_config_t lc;
    estimate_lcm_config_default(&lc);
    lc.lcm_url = lcm_url;
    lc.urdf_path = b->urdf;
    lc.mesh_link = &b->geo.mesh;
    lc.yumi_urdf = cli_paths_yumi_urdf();
    lc.policy = policy_name;
    lc.log = lcm_log;
    rc = estimate_lcm_open(&lc, &lcmb, &backend, err, sizeof err);
  } else {
    rc = estimate_direct_open(b->urdf, NULL, NULL, &sim, &backend, err, sizeof err);
  }
  if (rc != 0) {
    LOG_E("%s: %s", b->urdf, err);
    return rc;
  }
  estimate_config_t cfg;
  estimate_config_default(&cfg);
  cfg.policy = policy;
  estimate_result_t *res = malloc(sizeof *res);
  if (!res) {
    estimate_direct_close(sim);
    estimate_lcm_close(lcmb);
    LOG_E("out of memory");
    return EXIT_FAILURE;
  }
  const estimate_status_t es = estimate_run(&b->geo.mesh, &backend, &cfg, res);
  if (lcmb && es == ESTIMATE_OK &&
      estimate_lcm_publish_estimate(lcmb, res, cfg.resolution_m, 1) != 0)
    LOG_W("publishing COM_ESTIMATE failed");
  estimate_direct_close(sim);
  estimate_lcm_close(lcmb);
  if (es != ESTIMATE_OK) {
    LOG_E("%s: estimate: %s%s%s", b->urdf, estimate_status_str(es), res->msg[0] ? ": " : "",
          res->msg);
    free(res);
    return es == ESTIMATE_E_ARG ? EXIT_USAGE : EXIT_FAILURE;
  }
  b->trials = res->trial_count;
  for (int k = 0; k < 3; ++k) {
    b->found[k] = res->found[k] && isfinite(res->com_m[k]) && isfinite(res->halfwidth_m[k]);
    if (b->found[k]) {
      b->com_m[k] = res->com_m[k];
      b->halfwidth_m[k] = res->halfwidth_m[k];
    } else {
      b->com_m[k] = res->uniform_com_m[k];
      b->halfwidth_m[k] = kMissingHalfwidth;
      LOG_W(
          "%s: CoM component %c not found (%s): planning with the uniform-density value "
          "%.2f mm +- %.1f mm",
          b->urdf, "xyz"[k], res -> msg[0] ? res -> msg : "no usable plane", 1e3 * b->com_m[k],
          1e3 * kMissingHalfwidth);
    }
  }
  LOG_I("%s: learned CoM (%.2f, %.2f, %.2f) mm +- (%.3f, %.3f, %.3f) mm in %zu trials", b->urdf,
        1e3 * b->com_m[0], 1e3 * b->com_m[1], 1e3 * b->com_m[2], 1e3 * b->halfwidth_m[0],
        1e3 * b->halfwidth_m[1], 1e3 * b->halfwidth_m[2], b->trials);
  free(res);
  return 0;
}

/* What rehearsing the plans on the beliefs gave. */
typedef struct {
  int tried;       /* rehearsals run */
  int stood;       /* the built plan stood in rehearsal */
  double tilt_deg; /* the contact-slope limit of the built plan */
  double seconds;  /* wall time of the rehearsals */
} rehearsal_t;

static void print_json(const belief_t *bel, size_t n, stack_com_source_t src,
                       const stack_plan_t *plan, const stack_sim_result_t *sim,
                       const rehearsal_t *reh, double learn_s, double plan_s, double sim_s,
                       double duration_s) {
  size_t level[STACK_MAX_OBJECTS] = {0};
  for (size_t k = 0; k < n; ++k) level[plan->order[k]] = k;
  printf("{\"stands\": %s, \"seconds_standing\": ", sim->run.stands ? "true" : "false");
  cli_json_number(stdout, sim->run.seconds_standing);
  printf(", \"duration_s\": ");
  cli_json_number(stdout, duration_s);
  printf(", \"com_source\": \"%s\", \"oracle\": %s, \"order\": [", stack_com_source_str(src),
         src == STACK_COM_TRUE ? "true" : "false");
  for (size_t k = 0; k < n; ++k) printf("%s%zu", k ? ", " : "", plan->order[k]);
  double mn = HUGE_VAL;
  for (size_t k = 0; k < n; ++k) mn = fmin(mn, plan->margin_m[k]);
  printf("], \"min_margin_m\": ");
  cli_json_number(stdout, mn);
  printf(", \"objects\": [");
  for (size_t i = 0; i < n; ++i) {
    const belief_t *b = &bel[i];
    const size_t k = level[i];
    printf("%s{\"urdf\": ", i ? ", " : "");
    cli_json_string(stdout, b->urdf, 0);
    printf(", \"level\": %zu, \"com_m\": ", k);
    cli_json_array(stdout, b->com_m, 3);
    printf(", \"halfwidth_m\": ");
    cli_json_array(stdout, b->halfwidth_m, 3);
    printf(", \"found\": [%s, %s, %s], \"trials\": %zu, \"mass_guess_kg\": ",
           b->found[0] ? "true" : "false", b->found[1] ? "true" : "false",
           b->found[2] ? "true" : "false", b->trials);
    cli_json_number(stdout, b->mass_kg);
    printf(", \"margin_m\": ");
    cli_json_number(stdout, plan->margin_m[k]);
    printf(", \"tilt_rad\": ");
    cli_json_number(stdout, plan->tilt_rad[k]);
    printf(", \"pose\": {\"position_m\": ");
    cli_json_array(stdout, plan->pose[i].position_m, 3);
    printf(", \"orientation_wxyz\": ");
    cli_json_array(stdout, plan->pose[i].orientation_wxyz, 4);
    printf("}, \"final_pose\": {\"position_m\": ");
    cli_json_array(stdout, sim->object[i].final_pose.position_m, 3);
    printf(", \"orientation_wxyz\": ");
    cli_json_array(stdout, sim->object[i].final_pose.orientation_wxyz, 4);
    printf("}, \"moved_at_s\": ");
    cli_json_number(stdout, sim->object[i].moved_at_s);
    printf(", \"displacement_m\": ");
    cli_json_number(stdout, sim->object[i].displacement_m);
    printf(", \"rotation_rad\": ");
    cli_json_number(stdout, sim->object[i].rotation_rad);
    printf("}");
  }
  printf("], \"rehearsals\": %d, \"rehearsal_stands\": %s, \"max_tilt_deg\": ", reh->tried,
         reh->stood ? "true" : "false");
  cli_json_number(stdout, reh->tilt_deg);
  printf(
      ", \"learn_seconds\": %.6f, \"plan_seconds\": %.6f, \"rehearse_seconds\": %.6f, "
      "\"sim_seconds\": %.6f, \"sim_time_s\": ",
      learn_s, plan_s, reh->seconds, sim_s);
  cli_json_number(stdout, sim->run.sim_time_s);
  printf("}\n");
}

static void print_table(const belief_t *bel, size_t n, stack_com_source_t src,
                        const stack_plan_t *plan, const stack_sim_result_t *sim,
                        const rehearsal_t *reh, double learn_s, double plan_s, double sim_s,
                        double duration_s) {
  printf("CoM source: %s%s\n", stack_com_source_str(src),
         src == STACK_COM_TRUE ? " (ORACLE: the URDF truth, for comparison only)" : "");
  printf("order (bottom first):");
  for (size_t k = 0; k < n; ++k) printf(" %s", bel[plan->order[k]].urdf);
  printf("\n");
  printf(
      "level  object                         believed CoM (mm)           +- (mm)"
      "               margin (mm)  tilt (deg)  position (mm)                   "
      "orientation (w x y z)\n");
  for (size_t k = 0; k < n; ++k) {
    const size_t i = plan->order[k];
    const belief_t *b = &bel[i];
    const model_pose_t *p = &plan->pose[i];
    printf(
        "%5zu  %-30s (%6.2f %6.2f %6.2f)  (%6.3f %6.3f %6.3f)  %11.2f  %10.1f  "
        "(%7.2f %7.2f %7.2f)  (%.4f %.4f %.4f %.4f)\n",
        k, b->urdf, 1e3 * b->com_m[0], 1e3 * b->com_m[1], 1e3 * b->com_m[2],
        1e3 * b->halfwidth_m[0], 1e3 * b->halfwidth_m[1], 1e3 * b->halfwidth_m[2],
        1e3 * plan->margin_m[k], plan->tilt_rad[k] * 180.0 / CL_PI, 1e3 * p->position_m[0],
        1e3 * p->position_m[1], 1e3 * p->position_m[2], p->orientation_wxyz[0],
        p->orientation_wxyz[1], p->orientation_wxyz[2], p->orientation_wxyz[3]);
  }
  for (size_t i = 0; i < n; ++i)
    if (sim->object[i].moved_at_s >= 0.0)
      printf("moved: %s at %.3f s (%.2f mm, %.3f rad at most)\n", bel[i].urdf,
             sim->object[i].moved_at_s, 1e3 * sim->object[i].displacement_m,
             sim->object[i].rotation_rad);
  printf("contacts up to %.0f deg; %d rehearsal(s) on the beliefs, the built plan %s\n",
         reh->tilt_deg, reh->tried,
         reh->tried == 0 ? "not rehearsed"
         : reh->stood    ? "stood"
                         : "fell there too");
  printf("learn %.2f s, plan %.2f s, rehearse %.2f s, simulation %.2f s wall\n", learn_s, plan_s,
         reh->seconds, sim_s);
  if (sim->run.stands)
    printf("STANDS for %.2f s\n", duration_s);
  else
    printf("FELL after %.3f s\n", sim->run.seconds_standing);
}

/* The command line of `comlearn stack`. */
typedef struct {
  stack_com_source_t src;
  qlearn_policy_kind_t policy;
  const char *policy_name, *lcm_url, *svg;
  double duration_s, mass_u, tilt_deg;
  int rehearse, json, direct;
} stack_args_t;

/* Options into a (defaults as usage() says). Returns -1 to go on, else the exit status (0 after
 * --help, EXIT_USAGE). */
static int parse_args(int argc, char **argv, stack_args_t *a) {
  static const struct option opts[] = {{"com", required_argument, NULL, 'c'},
                                       {"lcm-url", required_argument, NULL, 'u'},
                                       {"direct", no_argument, NULL, 'd'},
                                       {"policy", required_argument, NULL, 'p'},
                                       {"svg", required_argument, NULL, 'S'},
                                       {"duration-s", required_argument, NULL, 'D'},
                                       {"mass-uncertainty", required_argument, NULL, 'M'},
                                       {"max-tilt-deg", required_argument, NULL, 'T'},
                                       {"json", no_argument, NULL, 'j'},
                                       {"no-rehearse", no_argument, NULL, 'N'},
                                       {"verbose", no_argument, NULL, 'v'},
                                       {"quiet", no_argument, NULL, 'q'},
                                       {"help", no_argument, NULL, 'h'},
                                       {"version", no_argument, NULL, 'V'},
                                       {NULL, 0, NULL, 0}};
  *a = (stack_args_t){.src = STACK_COM_LEARNED,
                      .policy = QLEARN_POLICY_BISECT,
                      .policy_name = "bisect",
                      .duration_s = 5.0,
                      .mass_u = 0.3,
                      .tilt_deg = 20.0,
                      .rehearse = 1};
  int c;
  optind = 1;
  opterr = 0;
  while ((c = getopt_long(argc, argv, "vqhV", opts, NULL)) != -1) {
    switch (c) {
      case 'c':
        if (com_parse(optarg, &a->src) != 0) {
          LOG_E("--com: '%s' is not one of learned, bbox, true", optarg);
          return EXIT_USAGE;
        }
        break;
      case 'u':
        if (!optarg[0]) {
          LOG_E("--lcm-url: empty URL");
          return EXIT_USAGE;
        }
        a->lcm_url = optarg;
        break;
      case 'p':
        if (estimate_policy_parse(optarg, &a->policy) != 0) {
          LOG_E("--policy: '%s' is not one of bisect, pba, paper-qtable, paper-mlp", optarg);
          return EXIT_USAGE;
        }
        a->policy_name = optarg;
        break;
      case 'S':
        if (!optarg[0]) {
          LOG_E("--svg: empty file name");
          return EXIT_USAGE;
        }
        a->svg = optarg;
        break;
      case 'D':
        if (number_arg("--duration-s", optarg, 0.01, 600.0, &a->duration_s) != 0) return EXIT_USAGE;
        break;
      case 'M':
        if (number_arg("--mass-uncertainty", optarg, 0.0, 10.0, &a->mass_u) != 0) return EXIT_USAGE;
        break;
      case 'T':
        if (number_arg("--max-tilt-deg", optarg, 1.0, 45.0, &a->tilt_deg) != 0) return EXIT_USAGE;
        break;
      case 'N': a->rehearse = 0; break;
      case 'd': a->direct = 1; break;
      case 'j': a->json = 1; break;
      case 'v': cli_log_set_level(CLI_LOG_DEBUG); break;
      case 'q': cli_log_set_level(CLI_LOG_ERROR); break;
      case 'h': usage(stdout); return EXIT_SUCCESS;
      case 'V': cli_version_print(stdout, "comlearn"); return EXIT_SUCCESS;
      default: cli_getopt_complain("comlearn stack", "vqhV", opts, argv); return EXIT_USAGE;
    }
  }
  if (a->direct && a->lcm_url) {
    LOG_E("--direct and --lcm-url exclude each other (in-process, or over LCM)");
    return EXIT_USAGE;
  }
  return -1;
}

/* Geometry and the mass guess of every object, first: bad input fails before any long work.
 * Returns an exit status. */
static int beliefs_load(char *const *urdfs, size_t n, belief_t *bel) {
  for (size_t i = 0; i < n; ++i) {
    belief_t *b = &bel[i];
    b->urdf = urdfs[i];
    model_error_t merr = {{0}};
    model_status_t ms = model_object_load(b->urdf, NULL, &b->geo, &merr);
    model_mass_t mm;
    if (ms == MODEL_OK) ms = model_mesh_mass(&b->geo.mesh, kDensity, &mm);
    if (ms != MODEL_OK) {
      LOG_E("%s (%s)", merr.msg[0] ? merr.msg : b->urdf, model_status_str(ms));
      return ms == MODEL_E_NOMEM ? EXIT_FAILURE : EXIT_USAGE;
    }
    b->mass_kg = mm.mass_kg;
  }
  return 0;
}

/* --com true: the URDF <inertial> CoM as the belief (an oracle). Returns an exit status. */
static int believe_truth(belief_t *b) {
  model_error_t merr = {{0}};
  model_mass_t truth;
  model_status_t ms = model_inertial_load(b->urdf, NULL, &truth, &merr);
  if (ms != MODEL_OK) {
    LOG_E("--com true: %s (%s)", merr.msg[0] ? merr.msg : b->urdf, model_status_str(ms));
    return ms == MODEL_E_NOMEM ? EXIT_FAILURE : EXIT_USAGE;
  }
  memcpy(b->com_m, truth.com_m, sizeof b->com_m);
  for (int k = 0; k < 3; ++k) b->found[k] = 1;
  return 0;
}

/* A CoM for every object, from where a->src says. Returns an exit status. */
static int beliefs_form(belief_t *bel, size_t n, const stack_args_t *a) {
  int rc = 0;
  for (size_t i = 0; i < n && rc == 0; ++i) {
    belief_t *b = &bel[i];
    switch (a->src) {
      case STACK_COM_LEARNED:
        LOG_I("learning the CoM of %s (%zu/%zu, %s)", b->urdf, i + 1, n,
              a->lcm_url ? "over LCM" : "in-process");
        rc = learn(b, a->lcm_url, a->policy, a->policy_name);
        break;
      case STACK_COM_BBOX:
        model_aabb_center(&b->geo.aabb, b->com_m);
        for (int k = 0; k < 3; ++k) b->found[k] = 1;
        break;
      case STACK_COM_TRUE: rc = believe_truth(b); break;
    }
  }
  if (a->src == STACK_COM_TRUE && rc == 0)
    LOG_I("--com true: planning on the URDF truth (an oracle, not a measurement)");
  return rc;
}

/* What the planner gets of the beliefs (the mass uncertainty comes from the config). */
static void planner_inputs(const belief_t *bel, size_t n, stack_object_t *in) {
  for (size_t i = 0; i < n; ++i) {
    in[i].mesh_link = &bel[i].geo.mesh;
    memcpy(in[i].com_m, bel[i].com_m, sizeof in[i].com_m);
    memcpy(in[i].com_halfwidth_m, bel[i].halfwidth_m, sizeof in[i].com_halfwidth_m);
    in[i].mass_kg = bel[i].mass_kg;
    in[i].mass_rel_uncertainty = 0.0;
  }
}

/* The search over contact slopes and what it has so far. */
typedef struct {
  stack_plan_t *cand;     /* scratch: the plan of the current slope */
  stack_sim_result_t *rr; /* scratch: its rehearsal */
  stack_status_t st;      /* status of the plan kept in plan */
  int have;               /* a plan was found at some slope */
  double step_deg;        /* -4: flatter next; +4: steeper (nothing found at the first slope) */
} slope_search_t;

/* One slope of the search: plan on contacts up to tilt_deg, keep it when it is the first plan or
 * it stands in rehearsal. Returns 1 when the search is over, 0 to try the next slope. */
static int plan_at_slope(const stack_object_t *in, size_t n, const stack_args_t *a, double tilt_deg,
                         stack_plan_config_t *pc, const balance_stack_config_t *rsc,
                         slope_search_t *ss, stack_plan_t *plan, rehearsal_t *reh) {
  pc->max_tilt_rad = tilt_deg * CL_PI / 180.0;
  LOG_I("planning a stack of %zu objects (%s CoMs, contacts up to %.0f deg)", n,
        stack_com_source_str(a->src), tilt_deg);
  const stack_status_t ps = stack_plan(in, n, pc, ss->cand);
  if (ps != STACK_OK) {
    if (!ss->have) {
      ss->st = ps;
      memcpy(plan, ss->cand, sizeof *plan);
    }
    if (ps == STACK_E_ARG || ps == STACK_E_NOMEM) return 1;
    if (!ss->have) ss->step_deg = 4.0; /* nothing at this slope: flatter contacts will not help */
    return 0;
  }
  if (!ss->have) {
    memcpy(plan, ss->cand, sizeof *plan);
    ss->have = 1;
    ss->st = STACK_OK;
    reh->tilt_deg = tilt_deg;
  }
  if (!a->rehearse) return 1;
  const double tr = cli_time_now_s();
  const stack_status_t rs = stack_rehearse(in, n, ss->cand, NULL, rsc, ss->rr);
  reh->seconds += cli_time_now_s() - tr;
  ++reh->tried;
  if (rs != STACK_OK) {
    LOG_W("rehearsal failed: %s: %s", stack_status_str(rs), ss->rr->msg);
    return 1;
  }
  LOG_I("rehearsal on the beliefs (contacts up to %.0f deg): %s", tilt_deg,
        ss->rr->run.stands ? "stands" : "falls");
  if (!ss->rr->run.stands) return 0;
  for (size_t i = 0; i < n; ++i) {
    const balance_stack_object_t *o = &ss->rr->object[i];
    if (o->late_displacement_m > STACK_REST_DISPLACEMENT_M ||
        o->late_rotation_rad > STACK_REST_ROTATION_RAD) {
      LOG_I(
          "  but it creeps: object %zu (input order) moved %.3f mm and %.4f rad in the last %.0f s",
          i, 1e3 * o->late_displacement_m, o->late_rotation_rad, BALANCE_STACK_REST_WINDOW_S);
      return 0;
    }
  }
  memcpy(plan, ss->cand, sizeof *plan);
  reh->stood = 1;
  reh->tilt_deg = tilt_deg;
  return 1;
}

/* Plan on contacts at most a->tilt_deg steep; rehearse the plan in simulation on the beliefs; if
 * it falls there, plan again 4 degrees flatter (the first slope may be below 4 degrees, no retry
 * is). When there is no plan at a->tilt_deg at all, try steeper contacts instead (4 degrees at a
 * time, up to 12 more). The first plan found is kept in case none stands in rehearsal. *st: the
 * kept plan's status (on failure plan holds the first attempt, for its msg); *plan_s: planning
 * wall time without the rehearsals. Returns an exit status (EXIT_FAILURE: out of memory). */
static int plan_rehearsed(const stack_object_t *in, size_t n, const stack_args_t *a,
                          stack_plan_t *plan, rehearsal_t *reh, stack_status_t *st,
                          double *plan_s) {
  stack_plan_config_t pc;
  stack_plan_config_default(&pc);
  pc.mass_rel_uncertainty = a->mass_u;
  balance_stack_config_t rsc;
  balance_stack_config_default(&rsc);
  rsc.duration_s = a->duration_s;
  slope_search_t ss = {malloc(sizeof *ss.cand), malloc(sizeof *ss.rr), STACK_E_NOPLAN, 0, -4.0};
  int rc = 0;
  if (!ss.cand || !ss.rr) {
    LOG_E("out of memory");
    rc = EXIT_FAILURE;
  }
  const double t0 = cli_time_now_s();
  const double steepest = fmin(45.0, a->tilt_deg + 12.0);
  const double flattest = fmin(4.0, a->tilt_deg); /* the first slope is always tried */
  for (double tilt = a->tilt_deg; rc == 0 && tilt >= flattest - 1e-9 && tilt <= steepest + 1e-9;
       tilt += ss.step_deg)
    if (plan_at_slope(in, n, a, tilt, &pc, &rsc, &ss, plan, reh)) break;
  *plan_s = cli_time_now_s() - t0 - reh->seconds;
  if (rc == 0 && ss.have && a->rehearse && !reh->stood)
    LOG_W("no plan stood in rehearsal; building the first one (contacts up to %.0f deg)",
          reh->tilt_deg);
  free(ss.cand);
  free(ss.rr);
  *st = ss.st;
  return rc;
}

/* No plan: say why (and with --json, a JSON object saying so). Returns the exit status. */
static int report_no_plan(const stack_args_t *a, stack_status_t st, const stack_plan_t *plan,
                          double learn_s, double plan_s) {
  const char *why = plan->msg[0] ? plan->msg : stack_status_str(st);
  LOG_E("plan: %s: %s", stack_status_str(st), why);
  if (a->json) {
    printf(
        "{\"stands\": false, \"planned\": false, \"seconds_standing\": 0, \"com_source\": "
        "\"%s\", \"error\": ",
        stack_com_source_str(a->src));
    cli_json_string(stdout, why, 0);
    printf(", \"learn_seconds\": %.6f, \"plan_seconds\": %.6f}\n", learn_s, plan_s);
  }
  return st == STACK_E_ARG ? EXIT_USAGE : EXIT_FAILURE;
}

/* The planned stack released with the true mass properties. Returns an exit status. */
static int simulate_truth(const belief_t *bel, size_t n, double duration_s,
                          const stack_plan_t *plan, stack_sim_result_t *sim, double *sim_s) {
  const char *paths[STACK_MAX_OBJECTS];
  for (size_t i = 0; i < n; ++i) paths[i] = bel[i].urdf;
  balance_stack_config_t sc;
  balance_stack_config_default(&sc);
  sc.duration_s = duration_s;
  sc.run_to_end = 1; /* a fallen stack runs on too: the picture and final_pose show the end */
  LOG_I("simulating the stack for %.2f s with the true mass properties", duration_s);
  const double t0 = cli_time_now_s();
  const stack_status_t st = stack_simulate(paths, n, plan, NULL, &sc, sim);
  *sim_s = cli_time_now_s() - t0;
  if (st != STACK_OK) {
    LOG_E("simulation: %s: %s", stack_status_str(st), sim->msg);
    return st == STACK_E_ARG ? EXIT_USAGE : EXIT_FAILURE;
  }
  return 0;
}

/* The name of a URDF for the picture: its file name without ".urdf". */
static void urdf_stem(const char *path, char *out, size_t size) {
  const char *b = strrchr(path, '/');
  b = b ? b + 1 : path;
  size_t n = strlen(b);
  if (n > 5 && strcmp(b + n - 5, ".urdf") == 0) n -= 5;
  snprintf(out, size, "%.*s", (int)n, b);
}

/* --svg: the stack as the simulation left it over the planned poses, each object named with its
 * true CoM (the URDF <inertial>, read here for the picture only, as stack_simulate reads it) and
 * the CoM the plan used, and the plan's support polygons. Returns 0, or -1 (logged). */
static int write_picture(const stack_args_t *a, const belief_t *bel, size_t n,
                         const stack_plan_t *plan, const stack_sim_result_t *sim) {
  stack_svg_object_t obj[STACK_MAX_OBJECTS];
  char names[STACK_MAX_OBJECTS][128];
  for (size_t i = 0; i < n; ++i) {
    model_error_t merr = {{0}};
    model_mass_t truth;
    const model_status_t ms = model_inertial_load(bel[i].urdf, NULL, &truth, &merr);
    if (ms != MODEL_OK) {
      LOG_E("--svg: %s (%s)", merr.msg[0] ? merr.msg : bel[i].urdf, model_status_str(ms));
      return -1;
    }
    urdf_stem(bel[i].urdf, names[i], sizeof names[i]);
    obj[i] = (stack_svg_object_t){.mesh_link = &bel[i].geo.mesh,
                                  .name = names[i],
                                  .planned = plan->pose[i],
                                  .final = sim->object[i].final_pose};
    memcpy(obj[i].com_used_m, bel[i].com_m, sizeof obj[i].com_used_m);
    memcpy(obj[i].com_true_m, truth.com_m, sizeof obj[i].com_true_m);
  }
  char title[200];
  if (sim->run.stands)
    snprintf(title, sizeof title, "%s CoMs: stood %.2f s (drawn: the poses at %.2f s)",
             stack_com_source_str(a->src), sim->run.seconds_standing, sim->run.sim_time_s);
  else
    snprintf(title, sizeof title, "%s CoMs: fell after %.3f s (drawn: the poses at %.2f s)",
             stack_com_source_str(a->src), sim->run.seconds_standing, sim->run.sim_time_s);
  if (stack_svg_write_run(a->svg, obj, n, plan->order, stack_com_source_str(a->src), title) != 0) {
    LOG_E("--svg %s: %s", a->svg, strerror(errno));
    return -1;
  }
  return 0;
}

int cmd_stack(int argc, char **argv) {
  stack_args_t a;
  const int prc = parse_args(argc, argv, &a);
  if (prc >= 0) return prc;
  const size_t n = (size_t)(argc - optind);
  if (n < 2 || n > STACK_MAX_OBJECTS) {
    LOG_E("stack needs 2..%d OBJECT.urdf files, got %zu", STACK_MAX_OBJECTS, n);
    usage(stderr);
    return EXIT_USAGE;
  }
  if (a.lcm_url && a.src != STACK_COM_LEARNED) LOG_W("--lcm-url is used only with --com learned");

  belief_t bel[STACK_MAX_OBJECTS];
  memset(bel, 0, sizeof bel);
  int rc = beliefs_load(argv + optind, n, bel);
  const double t_learn = cli_time_now_s();
  if (rc == 0) rc = beliefs_form(bel, n, &a);
  const double learn_s = cli_time_now_s() - t_learn;

  stack_plan_t *plan = NULL;
  stack_sim_result_t *sim = NULL;
  if (rc == 0) {
    plan = calloc(1, sizeof *plan); /* zeroed: an empty msg unless the planner says why */
    sim = malloc(sizeof *sim);
    if (!plan || !sim) {
      LOG_E("out of memory");
      rc = EXIT_FAILURE;
    }
  }
  double plan_s = 0.0, sim_s = 0.0;
  rehearsal_t reh = {0, 0, 0.0, 0.0};
  stack_status_t st = STACK_E_NOPLAN;
  if (rc == 0) {
    stack_object_t in[STACK_MAX_OBJECTS];
    planner_inputs(bel, n, in);
    rc = plan_rehearsed(in, n, &a, plan, &reh, &st, &plan_s);
    if (rc == 0 && st != STACK_OK) rc = report_no_plan(&a, st, plan, learn_s, plan_s);
  }
  if (rc == 0) rc = simulate_truth(bel, n, a.duration_s, plan, sim, &sim_s);
  /* a failed picture still prints the result; the exit status says the picture failed */
  const int svg_failed = rc == 0 && a.svg && write_picture(&a, bel, n, plan, sim) != 0;
  if (rc == 0) {
    if (a.json)
      print_json(bel, n, a.src, plan, sim, &reh, learn_s, plan_s, sim_s, a.duration_s);
    else
      print_table(bel, n, a.src, plan, sim, &reh, learn_s, plan_s, sim_s, a.duration_s);
    if (svg_failed) rc = EXIT_FAILURE;
  }
  free(plan);
  free(sim);
  for (size_t i = 0; i < n; ++i) model_object_free(&bel[i].geo);
  return rc;
}
