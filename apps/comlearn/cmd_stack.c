/*
 * cmd_stack.c - `comlearn stack OBJECT.urdf...`: believe a CoM for every object (learned with the
 * estimator, the bounding-box center, or the URDF truth as an oracle), plan a stack on those
 * beliefs from geometry only (stack_plan.c), then release it in simulation with the truth
 * (stack_sim.c) and report whether it stands.
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

#include "comlearn/model.h"
#include "comlearn/model_inertial.h"
#include "estimate_backend.h"
#include "estimate_direct.h"
#include "estimate_lcm.h"
#include "log.h"
#include "out.h"
#include "stack.h"

enum { EXIT_USAGE = 2 };

static const double kDensity = 2650.0;      /* nominal rock density for the mass guesses */
static const double kMissingHalfwidth = 3e-3;

static void usage(FILE *out) {
  fprintf(out,
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
          "  --policy P         learned: bisect | pba | paper-qtable | paper-mlp (default: bisect)\n"
          "  --mass-uncertainty U  relative mass uncertainty; plans hold for masses in\n"
          "                     m*[1/(1+U), 1+U], m = mesh volume x 2650 kg/m^3 (default: 0.3)\n"
          "  --max-tilt-deg D   steepest contact plane of the first plan, 1..45 (default: 20);\n"
          "                     a plan that falls in rehearsal is replaced by one with\n"
          "                     contacts at most 4 degrees flatter, down to 4 degrees;\n"
          "                     with no plan at all at D, steeper ones, up to D + 12\n"
          "  --no-rehearse      build the first plan without rehearsing it on the beliefs\n"
          "                     (default: rehearse each plan in simulation on the believed\n"
          "                     CoMs and mass guesses before the real run)\n"
          "  --duration-s S     simulated time the stack must stand, 0.01..600 (default: 5)\n"
          "  --svg FILE         write a side view of the stack after the simulation\n"
          "  --json             print one JSON object on stdout (default: a table)\n"
          "  -v, --verbose      log debug messages on stderr (default: info)\n"
          "  -q, --quiet        log errors only (default: info, progress lines on stderr)\n"
          "  -h, --help         show this help\n"
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
    lc.yumi_urdf = COMLEARN_YUMI_URDF;
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
  if (lcmb && es == ESTIMATE_OK && estimate_lcm_publish_estimate(lcmb, res, cfg.resolution_m, 1) != 0)
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
      LOG_W("%s: CoM component %c not found (%s): planning with the uniform-density value "
            "%.2f mm +- %.1f mm",
            b->urdf, "xyz"[k], res->msg[0] ? res->msg : "no usable plane", 1e3 * b->com_m[k],
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
  int tried;        /* rehearsals run */
  int stood;        /* the built plan stood in rehearsal */
  double tilt_deg;  /* the contact-slope limit of the built plan */
  double seconds;   /* wall time of the rehearsals */
} rehearsal_t;

static void print_json(const belief_t *bel, size_t n, stack_com_source_t src, const stack_plan_t *plan,
                       const stack_sim_result_t *sim, const rehearsal_t *reh, double learn_s,
                       double plan_s, double sim_s, double duration_s) {
  size_t level[STACK_MAX_OBJECTS] = {0};
  for (size_t k = 0; k < n; ++k) level[plan->order[k]] = k;
  printf("{\"stands\": %s, \"seconds_standing\": ", sim->run.stands ? "true" : "false");
  out_json_number(sim->run.seconds_standing);
  printf(", \"duration_s\": ");
  out_json_number(duration_s);
  printf(", \"com_source\": \"%s\", \"oracle\": %s, \"order\": [", stack_com_source_str(src),
         src == STACK_COM_TRUE ? "true" : "false");
  for (size_t k = 0; k < n; ++k) printf("%s%zu", k ? ", " : "", plan->order[k]);
  double mn = HUGE_VAL;
  for (size_t k = 0; k < n; ++k) mn = fmin(mn, plan->margin_m[k]);
  printf("], \"min_margin_m\": ");
  out_json_number(mn);
  printf(", \"objects\": [");
  for (size_t i = 0; i < n; ++i) {
    const belief_t *b = &bel[i];
    const size_t k = level[i];
    printf("%s{\"urdf\": ", i ? ", " : "");
    out_json_string(b->urdf, 0);
    printf(", \"level\": %zu, \"com_m\": ", k);
    out_json_array(b->com_m, 3);
    printf(", \"halfwidth_m\": ");
    out_json_array(b->halfwidth_m, 3);
    printf(", \"found\": [%s, %s, %s], \"trials\": %zu, \"mass_guess_kg\": ",
           b->found[0] ? "true" : "false", b->found[1] ? "true" : "false",
           b->found[2] ? "true" : "false", b->trials);
    out_json_number(b->mass_kg);
    printf(", \"margin_m\": ");
    out_json_number(plan->margin_m[k]);
    printf(", \"tilt_rad\": ");
    out_json_number(plan->tilt_rad[k]);
    printf(", \"pose\": {\"position_m\": ");
    out_json_array(plan->pose[i].position_m, 3);
    printf(", \"orientation_wxyz\": ");
    out_json_array(plan->pose[i].orientation_wxyz, 4);
    printf("}, \"moved_at_s\": ");
    out_json_number(sim->object[i].moved_at_s);
    printf(", \"displacement_m\": ");
    out_json_number(sim->object[i].displacement_m);
    printf(", \"rotation_rad\": ");
    out_json_number(sim->object[i].rotation_rad);
    printf("}");
  }
  printf("], \"rehearsals\": %d, \"rehearsal_stands\": %s, \"max_tilt_deg\": ", reh->tried,
         reh->stood ? "true" : "false");
  out_json_number(reh->tilt_deg);
  printf(", \"learn_seconds\": %.6f, \"plan_seconds\": %.6f, \"rehearse_seconds\": %.6f, "
         "\"sim_seconds\": %.6f, \"sim_time_s\": ",
         learn_s, plan_s, reh->seconds, sim_s);
  out_json_number(sim->run.sim_time_s);
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
  printf("level  object                         believed CoM (mm)           +- (mm)"
         "               margin (mm)  tilt (deg)  position (mm)                   "
         "orientation (w x y z)\n");
  for (size_t k = 0; k < n; ++k) {
    const size_t i = plan->order[k];
    const belief_t *b = &bel[i];
    const model_pose_t *p = &plan->pose[i];
    printf("%5zu  %-30s (%6.2f %6.2f %6.2f)  (%6.3f %6.3f %6.3f)  %11.2f  %10.1f  "
           "(%7.2f %7.2f %7.2f)  (%.4f %.4f %.4f %.4f)\n",
           k, b->urdf, 1e3 * b->com_m[0], 1e3 * b->com_m[1], 1e3 * b->com_m[2],
           1e3 * b->halfwidth_m[0], 1e3 * b->halfwidth_m[1], 1e3 * b->halfwidth_m[2],
           1e3 * plan->margin_m[k], plan->tilt_rad[k] * 180.0 / 3.14159265358979323846,
           1e3 * p->position_m[0], 1e3 * p->position_m[1], 1e3 * p->position_m[2],
           p->orientation_wxyz[0], p->orientation_wxyz[1], p->orientation_wxyz[2],
           p->orientation_wxyz[3]);
  }
  for (size_t i = 0; i < n; ++i)
    if (sim->object[i].moved_at_s >= 0.0)
      printf("moved: %s at %.3f s (%.2f mm, %.3f rad at most)\n", bel[i].urdf,
             sim->object[i].moved_at_s, 1e3 * sim->object[i].displacement_m,
             sim->object[i].rotation_rad);
  printf("contacts up to %.0f deg; %d rehearsal(s) on the beliefs, the built plan %s\n",
         reh->tilt_deg, reh->tried,
         reh->tried == 0 ? "not rehearsed" : reh->stood ? "stood" : "fell there too");
  printf("learn %.2f s, plan %.2f s, rehearse %.2f s, simulation %.2f s wall\n", learn_s, plan_s,
         reh->seconds, sim_s);
  if (sim->run.stands) printf("STANDS for %.2f s\n", duration_s);
  else printf("FELL after %.3f s\n", sim->run.seconds_standing);
}

int cmd_stack(int argc, char **argv) {
  static const struct option opts[] = {
      {"com", required_argument, NULL, 'c'},        {"lcm-url", required_argument, NULL, 'u'},
      {"policy", required_argument, NULL, 'p'},     {"svg", required_argument, NULL, 'S'},
      {"duration-s", required_argument, NULL, 'D'}, {"mass-uncertainty", required_argument, NULL, 'M'},
      {"max-tilt-deg", required_argument, NULL, 'T'}, {"json", no_argument, NULL, 'j'},
      {"no-rehearse", no_argument, NULL, 'N'},
      {"verbose", no_argument, NULL, 'v'},          {"quiet", no_argument, NULL, 'q'},
      {"help", no_argument, NULL, 'h'},             {NULL, 0, NULL, 0}};
  stack_com_source_t src = STACK_COM_LEARNED;
  qlearn_policy_kind_t policy = QLEARN_POLICY_BISECT;
  const char *policy_name = "bisect", *lcm_url = NULL, *svg = NULL;
  double duration_s = 5.0, mass_u = 0.3, tilt_deg = 20.0;
  int rehearse = 1;
  int json = 0, c;
  optind = 1;
  while ((c = getopt_long(argc, argv, "vqh", opts, NULL)) != -1) {
    switch (c) {
      case 'c':
        if (com_parse(optarg, &src) != 0) {
          LOG_E("--com: '%s' is not one of learned, bbox, true", optarg);
          return EXIT_USAGE;
        }
        break;
      case 'u':
        if (!optarg[0]) {
          LOG_E("--lcm-url: empty URL");
          return EXIT_USAGE;
        }
        lcm_url = optarg;
        break;
      case 'p':
        if (estimate_policy_parse(optarg, &policy) != 0) {
          LOG_E("--policy: '%s' is not one of bisect, pba, paper-qtable, paper-mlp", optarg);
          return EXIT_USAGE;
        }
        policy_name = optarg;
        break;
      case 'S':
        if (!optarg[0]) {
          LOG_E("--svg: empty file name");
          return EXIT_USAGE;
        }
        svg = optarg;
        break;
      case 'D':
        if (number_arg("--duration-s", optarg, 0.01, 600.0, &duration_s) != 0) return EXIT_USAGE;
        break;
      case 'M':
        if (number_arg("--mass-uncertainty", optarg, 0.0, 10.0, &mass_u) != 0) return EXIT_USAGE;
        break;
      case 'T':
        if (number_arg("--max-tilt-deg", optarg, 1.0, 45.0, &tilt_deg) != 0) return EXIT_USAGE;
        break;
      case 'N':
        rehearse = 0;
        break;
      case 'j': json = 1; break;
      case 'v': log_set_level(LOG_DEBUG); break;
      case 'q': log_set_level(LOG_ERROR); break;
      case 'h': usage(stdout); return EXIT_SUCCESS;
      default: usage(stderr); return EXIT_USAGE;
    }
  }
  const size_t n = (size_t)(argc - optind);
  if (n < 2 || n > STACK_MAX_OBJECTS) {
    LOG_E("stack needs 2..%d OBJECT.urdf files, got %zu", STACK_MAX_OBJECTS, n);
    usage(stderr);
    return EXIT_USAGE;
  }
  if (lcm_url && src != STACK_COM_LEARNED) LOG_W("--lcm-url is used only with --com learned");

  belief_t bel[STACK_MAX_OBJECTS];
  memset(bel, 0, sizeof bel);
  int rc = 0;
  /* Geometry first, for every object: bad input fails before any long work. */
  for (size_t i = 0; i < n && rc == 0; ++i) {
    belief_t *b = &bel[i];
    b->urdf = argv[optind + (int)i];
    model_error_t merr = {{0}};
    model_status_t ms = model_object_load(b->urdf, NULL, &b->geo, &merr);
    model_mass_t mm;
    if (ms == MODEL_OK) ms = model_mesh_mass(&b->geo.mesh, kDensity, &mm);
    if (ms != MODEL_OK) {
      LOG_E("%s (%s)", merr.msg[0] ? merr.msg : b->urdf, model_status_str(ms));
      rc = ms == MODEL_E_NOMEM ? EXIT_FAILURE : EXIT_USAGE;
      break;
    }
    b->mass_kg = mm.mass_kg;
  }
  /* The beliefs. */
  const double t_learn = out_now_s();
  for (size_t i = 0; i < n && rc == 0; ++i) {
    belief_t *b = &bel[i];
    switch (src) {
      case STACK_COM_LEARNED:
        LOG_I("learning the CoM of %s (%zu/%zu, %s)", b->urdf, i + 1, n,
              lcm_url ? "over LCM" : "in-process");
        rc = learn(b, lcm_url, policy, policy_name);
        break;
      case STACK_COM_BBOX:
        model_aabb_center(&b->geo.aabb, b->com_m);
        for (int k = 0; k < 3; ++k) b->found[k] = 1;
        break;
      case STACK_COM_TRUE: {
        model_error_t merr = {{0}};
        model_mass_t truth;
        model_status_t ms = model_inertial_load(b->urdf, NULL, &truth, &merr);
        if (ms != MODEL_OK) {
          LOG_E("--com true: %s (%s)", merr.msg[0] ? merr.msg : b->urdf, model_status_str(ms));
          rc = ms == MODEL_E_NOMEM ? EXIT_FAILURE : EXIT_USAGE;
          break;
        }
        memcpy(b->com_m, truth.com_m, sizeof b->com_m);
        for (int k = 0; k < 3; ++k) b->found[k] = 1;
        break;
      }
    }
  }
  if (src == STACK_COM_TRUE && rc == 0)
    LOG_I("--com true: planning on the URDF truth (an oracle, not a measurement)");
  const double learn_s = out_now_s() - t_learn;

  stack_plan_t *plan = NULL;
  stack_sim_result_t *sim = NULL;
  if (rc == 0) {
    plan = malloc(sizeof *plan);
    sim = malloc(sizeof *sim);
    if (!plan || !sim) {
      LOG_E("out of memory");
      rc = EXIT_FAILURE;
    }
  }
  double plan_s = 0.0, sim_s = 0.0;
  rehearsal_t reh = {0, 0, 0.0, 0.0};
  stack_object_t in[STACK_MAX_OBJECTS];
  if (rc == 0) {
    for (size_t i = 0; i < n; ++i) {
      in[i].mesh_link = &bel[i].geo.mesh;
      memcpy(in[i].com_m, bel[i].com_m, sizeof in[i].com_m);
      memcpy(in[i].com_halfwidth_m, bel[i].halfwidth_m, sizeof in[i].com_halfwidth_m);
      in[i].mass_kg = bel[i].mass_kg;
      in[i].mass_rel_uncertainty = 0.0;
    }
    stack_plan_config_t pc;
    stack_plan_config_default(&pc);
    pc.mass_rel_uncertainty = mass_u;
    balance_stack_config_t rsc;
    balance_stack_config_default(&rsc);
    rsc.duration_s = duration_s;
    /* Plan on contacts at most tilt_deg steep; rehearse the plan in simulation on the beliefs;
     * if it falls there, plan again 4 degrees flatter. When there is no plan at tilt_deg at all,
     * try steeper contacts instead (4 degrees at a time, up to 12 more). The first plan found is
     * kept in case none stands in rehearsal. */
    stack_plan_t *cand = malloc(sizeof *cand);
    stack_sim_result_t *rr = malloc(sizeof *rr);
    stack_status_t st = STACK_E_NOPLAN;
    int have = 0;
    if (!cand || !rr) {
      LOG_E("out of memory");
      rc = EXIT_FAILURE;
    }
    const double t0 = out_now_s();
    double step = -4.0;
    const double steepest = fmin(45.0, tilt_deg + 12.0);
    for (double tilt = tilt_deg; rc == 0 && tilt >= 4.0 - 1e-9 && tilt <= steepest + 1e-9;
         tilt += step) {
      pc.max_tilt_rad = tilt * 3.14159265358979323846 / 180.0;
      LOG_I("planning a stack of %zu objects (%s CoMs, contacts up to %.0f deg)", n,
            stack_com_source_str(src), tilt);
      const stack_status_t ps = stack_plan(in, n, &pc, cand);
      if (ps != STACK_OK) {
        if (!have) {
          st = ps;
          memcpy(plan, cand, sizeof *plan);
        }
        if (ps == STACK_E_ARG || ps == STACK_E_NOMEM) break;
        if (!have) step = 4.0; /* nothing at this slope: flatter contacts will not help */
        continue;
      }
      if (!have) {
        memcpy(plan, cand, sizeof *plan);
        have = 1;
        st = STACK_OK;
        reh.tilt_deg = tilt;
      }
      if (!rehearse) break;
      const double tr = out_now_s();
      const stack_status_t rs = stack_rehearse(in, n, cand, NULL, &rsc, rr);
      reh.seconds += out_now_s() - tr;
      ++reh.tried;
      if (rs != STACK_OK) {
        LOG_W("rehearsal failed: %s: %s", stack_status_str(rs), rr->msg);
        break;
      }
      LOG_I("rehearsal on the beliefs (contacts up to %.0f deg): %s", tilt,
            rr->run.stands ? "stands" : "falls");
      if (rr->run.stands) {
        memcpy(plan, cand, sizeof *plan);
        reh.stood = 1;
        reh.tilt_deg = tilt;
        break;
      }
    }
    plan_s = out_now_s() - t0 - reh.seconds;
    if (rc == 0 && have && rehearse && !reh.stood)
      LOG_W("no plan stood in rehearsal; building the first one (contacts up to %.0f deg)",
            reh.tilt_deg);
    free(cand);
    free(rr);
    if (rc == 0 && st != STACK_OK) {
      LOG_E("plan: %s: %s", stack_status_str(st), plan->msg);
      if (json) {
        printf("{\"stands\": false, \"planned\": false, \"seconds_standing\": 0, \"com_source\": "
               "\"%s\", \"error\": ",
               stack_com_source_str(src));
        out_json_string(plan->msg, 0);
        printf(", \"learn_seconds\": %.6f, \"plan_seconds\": %.6f}\n", learn_s, plan_s);
      }
      rc = st == STACK_E_ARG ? EXIT_USAGE : EXIT_FAILURE;
    }
  }
  if (rc == 0) {
    const char *paths[STACK_MAX_OBJECTS];
    for (size_t i = 0; i < n; ++i) paths[i] = bel[i].urdf;
    balance_stack_config_t sc;
    balance_stack_config_default(&sc);
    sc.duration_s = duration_s;
    LOG_I("simulating the stack for %.2f s with the true mass properties", duration_s);
    const double t0 = out_now_s();
    const stack_status_t st = stack_simulate(paths, n, plan, NULL, &sc, sim);
    sim_s = out_now_s() - t0;
    if (st != STACK_OK) {
      LOG_E("simulation: %s: %s", stack_status_str(st), sim->msg);
      rc = st == STACK_E_ARG ? EXIT_USAGE : EXIT_FAILURE;
    }
  }
  int svg_failed = 0;
  if (rc == 0 && svg) {
    const model_mesh_t *meshes[STACK_MAX_OBJECTS];
    double coms[STACK_MAX_OBJECTS][3];
    for (size_t i = 0; i < n; ++i) {
      meshes[i] = &bel[i].geo.mesh;
      memcpy(coms[i], bel[i].com_m, sizeof coms[i]);
    }
    char title[160];
    if (sim->run.stands)
      snprintf(title, sizeof title, "%s CoMs: stands %.1f s", stack_com_source_str(src),
               duration_s);
    else
      snprintf(title, sizeof title, "%s CoMs: fell after %.2f s", stack_com_source_str(src),
               sim->run.seconds_standing);
    if (stack_svg_write(svg, meshes, plan->pose, (const double(*)[3])coms, n, title) != 0) {
      LOG_E("--svg %s: %s", svg, strerror(errno));
      svg_failed = 1; /* the result is still printed; the exit status says the picture failed */
    }
  }
  if (rc == 0) {
    if (json) print_json(bel, n, src, plan, sim, &reh, learn_s, plan_s, sim_s, duration_s);
    else print_table(bel, n, src, plan, sim, &reh, learn_s, plan_s, sim_s, duration_s);
    if (svg_failed) rc = EXIT_FAILURE;
  }
  free(plan);
  free(sim);
  for (size_t i = 0; i < n; ++i) model_object_free(&bel[i].geo);
  return rc;
}
