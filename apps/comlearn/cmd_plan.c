/*
 * cmd_plan.c - `comlearn plan OBJECT.urdf`: one placement, planned the way the LCM backend of
 * `comlearn estimate` plans each trial, printed for a client in any language to execute
 * (docs/messages.md, "Using the messages from Python"): the release pose on B, the grasp to hand
 * SIM_CONTROL, and the YuMi waypoints to send as YUMI_COMMAND. --simulate adds lib/balance's
 * outcome for the same release pose (the in-process trial of `comlearn estimate --direct`; it reads
 * the URDF <inertial>, as comlearn-sim does).
 */
#define _GNU_SOURCE
#include "cmd_plan.h"

#include <getopt.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "comlearn/balance.h"
#include "comlearn/cli_args.h"
#include "comlearn/cli_json.h"
#include "comlearn/cli_log.h"
#include "comlearn/cli_paths.h"
#include "comlearn/model.h"
#include "comlearn/model_support.h"
#include "comlearn/placement.h"
#include "comlearn/placement_plan.h"
#include "estimate_direct.h"
#include "estimate_lcm.h"

enum { EXIT_USAGE = 2 };

static void usage(FILE *out) {
  fprintf(out,
          "usage: comlearn plan OBJECT.urdf [options]\n"
          "\n"
          "Plans one placement on the edge of block B as `comlearn estimate` plans each trial\n"
          "over LCM: the object in ORIENTATION with the link-frame point POINT exactly over the\n"
          "edge, lowered until it touches B; the top-down grasp (arm, grasp pose, opening) for\n"
          "SIM_CONTROL; the YuMi waypoints (preplace, place, release, retreat) for YUMI_COMMAND.\n"
          "A client executes it (examples/python/one_trial.py, docs/messages.md).\n"
          "\n"
          "options:\n"
          "  --point-mm X,Y,Z   link-frame point over the edge, mm (default: 0,0,0, the origin)\n"
          "  --edge E           +x | -x | +y | -y: B's top edge by outward normal (default: +x)\n"
          "  --along-mm A       the point this far along the edge from its middle, mm, within\n"
          "                     +-150 (default: 0)\n"
          "  --orientation W,X,Y,Z  the object's orientation on B, a unit quaternion (default:\n"
          "                     1,0,0,0, as the URDF link frame stands)\n"
          "  --q-start Q        both arms' joints now, 14 numbers in rad, left arm first, chain\n"
          "                     order (YUMI_STATUS q_measured_rad) (default: comlearn-sim's start\n"
          "                     posture)\n"
          "  --simulate         add the outcome of lib/balance's trial at the same release pose\n"
          "                     (reads the URDF <inertial>, like the simulator) (default: off)\n"
          "  --link NAME        URDF link to read (default: the root link)\n"
          "  --json             print one JSON object on stdout (default: a table)\n"
          "  -v, --verbose      log debug messages on stderr (default: info)\n"
          "  -q, --quiet        log errors only (default: info)\n"
          "  -h, --help         show this help\n"
          "  -V, --version      print the version\n"
          "\n"
          "Frames: the release pose in B's frame (B's top at z = 0, its middle at x = y = 0);\n"
          "joints and the grasp as the messages carry them (docs/messages.md).\n"
          "exit status: 0 planned, 1 no plan (out of reach, a trial that failed), 2 usage or\n"
          "bad input\n");
}

typedef struct {
  const char *urdf, *link;
  double point_m[3], along_m, wxyz[4];
  double q_start[2][PLACEMENT_JOINTS];
  model_edge_t edge;
  int simulate, json;
} plan_args_t;

static int parse_edge(const char *s, model_edge_t *e) {
  static const char *names[] = {"+x", "-x", "+y", "-y"};
  for (int k = 0; k < 4; ++k)
    if (strcmp(s, names[k]) == 0) {
      *e = (model_edge_t)k;
      return 0;
    }
  return -1;
}

static const char *edge_name(model_edge_t e) {
  static const char *names[] = {"+x", "-x", "+y", "-y"};
  return (int)e >= 0 && (int)e < 4 ? names[e] : "?";
}

static int parse_option(int c, plan_args_t *a) {
  double v[14];
  switch (c) {
    case 'p':
      if (cli_args_numbers(optarg, v, 3) == 0) {
        for (int k = 0; k < 3; ++k) a->point_m[k] = v[k] * 1e-3;
        return 0;
      }
      LOG_E("--point-mm: '%s' is not three finite numbers X,Y,Z", optarg);
      return EXIT_USAGE;
    case 'e':
      if (parse_edge(optarg, &a->edge) == 0) return 0;
      LOG_E("--edge: '%s' is not one of +x, -x, +y, -y", optarg);
      return EXIT_USAGE;
    case 'a':
      if (cli_args_numbers(optarg, v, 1) == 0 && v[0] >= -150.0 && v[0] <= 150.0) {
        a->along_m = v[0] * 1e-3;
        return 0;
      }
      LOG_E("--along-mm: '%s' is not a number in [-150, 150]", optarg);
      return EXIT_USAGE;
    case 'o':
      if (cli_args_numbers(optarg, v, 4) == 0) {
        const double n2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + v[3] * v[3];
        if (n2 > (1 - 1e-6) * (1 - 1e-6) && n2 < (1 + 1e-6) * (1 + 1e-6)) {
          memcpy(a->wxyz, v, sizeof a->wxyz);
          return 0;
        }
      }
      LOG_E("--orientation: '%s' is not a unit quaternion W,X,Y,Z (norm 1 within 1e-6)", optarg);
      return EXIT_USAGE;
    case 'Q':
      if (cli_args_numbers(optarg, v, 14) == 0) {
        memcpy(a->q_start, v, sizeof a->q_start);
        return 0;
      }
      LOG_E("--q-start: '%s' is not 14 finite numbers (rad, left arm first)", optarg);
      return EXIT_USAGE;
    case 's': a->simulate = 1; return 0;
    case 'l': a->link = optarg; return 0;
    case 'j': a->json = 1; return 0;
    case 'v': cli_log_set_level(CLI_LOG_DEBUG); return 0;
    case 'q': cli_log_set_level(CLI_LOG_ERROR); return 0;
    case 'h': usage(stdout); return -1;
    case 'V': cli_version_print(stdout, "comlearn"); return -1;
    default: return EXIT_USAGE;
  }
}

/* The command line into *a: 0 to go on, -1 for exit 0 (--help), else an exit status. */
static int parse_args(int argc, char **argv, plan_args_t *a) {
  static const struct option opts[] = {{"point-mm", required_argument, NULL, 'p'},
                                       {"edge", required_argument, NULL, 'e'},
                                       {"along-mm", required_argument, NULL, 'a'},
                                       {"orientation", required_argument, NULL, 'o'},
                                       {"q-start", required_argument, NULL, 'Q'},
                                       {"simulate", no_argument, NULL, 's'},
                                       {"link", required_argument, NULL, 'l'},
                                       {"json", no_argument, NULL, 'j'},
                                       {"verbose", no_argument, NULL, 'v'},
                                       {"quiet", no_argument, NULL, 'q'},
                                       {"help", no_argument, NULL, 'h'},
                                       {"version", no_argument, NULL, 'V'},
                                       {NULL, 0, NULL, 0}};
  memset(a, 0, sizeof *a);
  a->wxyz[0] = 1.0;
  a->edge = MODEL_EDGE_PX;
  placement_yumi_nominal(PLACEMENT_ARM_LEFT, a->q_start[PLACEMENT_ARM_LEFT]);
  placement_yumi_nominal(PLACEMENT_ARM_RIGHT, a->q_start[PLACEMENT_ARM_RIGHT]);
  int c;
  optind = 1;
  opterr = 0;
  while ((c = getopt_long(argc, argv, "vqhV", opts, NULL)) != -1) {
    const int rc = parse_option(c, a);
    if (rc == EXIT_USAGE && (c == '?' || c == ':'))
      cli_getopt_complain("comlearn plan", "vqhV", opts, argv);
    if (rc != 0) return rc;
  }
  if (optind != argc - 1) {
    LOG_E("plan needs exactly one OBJECT.urdf");
    usage(stderr);
    return EXIT_USAGE;
  }
  a->urdf = argv[optind];
  return 0;
}

/* What the plan command computed. */
typedef struct {
  model_pose_t release; /* B's frame */
  placement_grasp_t g;
  placement_plan_config_t pc;
  balance_config_t bc; /* the outcome horizon and the slide rule */
  int simulated;
  estimate_trial_reply_t sim; /* --simulate */
} plan_out_t;

static void json_pose(FILE *f, const char *key, const double p[3], const double q[4]) {
  fprintf(f, "\"%s\": {\"position_m\": ", key);
  cli_json_array(f, p, 3);
  fputs(", \"orientation_wxyz\": ", f);
  cli_json_array(f, q, 4);
  fputc('}', f);
}

static void print_json(const plan_args_t *a, const plan_out_t *o) {
  FILE *f = stdout;
  double bib[4];
  model_rot_to_quat((const double(*)[3])o->pc.block_in_base.rot, bib);
  fputs("{\"object\": ", f);
  cli_json_string(f, a->urdf, 0);
  fprintf(f, ", \"edge\": \"%s\", ", edge_name(a->edge));
  json_pose(f, "release_in_block", o->release.position_m, o->release.orientation_wxyz);
  fputs(", ", f);
  json_pose(f, "block_in_world", o->pc.block_in_base.pos_m, bib);
  fprintf(f, ", \"arm\": %d, \"grip_width_m\": ", (int)o->g.side);
  cli_json_number(f, o->g.grip_width_m);
  fputs(", \"link_in_tool_position_m\": ", f);
  cli_json_array(f, o->g.object_in_tcp.position_m, 3);
  fputs(", \"link_in_tool_wxyz\": ", f);
  cli_json_array(f, o->g.object_in_tcp.orientation_wxyz, 4);
  fputs(", \"velocity_scale\": ", f);
  cli_json_number(f, o->pc.velocity_fraction);
  /* how a client tells the outcome, as the LCM backend does (lib/balance's horizon and slide
   * rule: off B after moving more than slide_m while rotating less than the rotation) */
  fputs(", \"outcome_horizon_s\": ", f);
  cli_json_number(f, o->bc.horizon_s);
  fputs(", \"slide_m\": ", f);
  cli_json_number(f, o->bc.slide_m);
  fputs(", \"slide_max_rotation_rad\": ", f);
  cli_json_number(f, balance_slide_max_rotation_rad(&o->bc));
  fputs(", \"waypoints\": [", f);
  for (int k = 0; k < PLACEMENT_PLAN_WAYPOINTS; ++k) {
    const placement_waypoint_t *w = &o->g.plan.waypoints[k];
    fprintf(f, "%s{\"kind\": \"%s\", \"q_rad\": ", k ? ", " : "",
            placement_waypoint_kind_str(w->kind));
    cli_json_array(f, w->q_rad, PLACEMENT_JOINTS);
    fputs(", \"gripper_width_m\": ", f);
    cli_json_number(f, w->gripper_width_m);
    fputs(", \"duration_s\": ", f);
    cli_json_number(f, w->duration_s);
    fputc('}', f);
  }
  fputc(']', f);
  if (o->simulated) {
    fprintf(f, ", \"simulated\": {\"outcome\": \"%s\", ", trial_outcome_name(o->sim.outcome));
    json_pose(f, "settled_in_block", o->sim.settled.position_m, o->sim.settled.orientation_wxyz);
    fputc('}', f);
  }
  fputs("}\n", f);
}

static void print_table(const plan_args_t *a, const plan_out_t *o) {
  const double *p = o->release.position_m, *q = o->release.orientation_wxyz;
  printf(
      "%s on edge %s: release (B's frame) at (%.5f, %.5f, %.5f) m, wxyz (%.6f, %.6f, %.6f, "
      "%.6f)\n",
      a->urdf, edge_name(a->edge), p[0], p[1], p[2], q[0], q[1], q[2], q[3]);
  printf("grasp: %s arm, opening %.4f m, finger yaw %.1f deg\n",
         o->g.side == PLACEMENT_ARM_LEFT ? "left" : "right", o->g.grip_width_m,
         o->g.yaw_rad * 57.29577951308232);
  for (int k = 0; k < PLACEMENT_PLAN_WAYPOINTS; ++k) {
    const placement_waypoint_t *w = &o->g.plan.waypoints[k];
    printf("  %-9s %5.2f s  gripper %.4f m  q", placement_waypoint_kind_str(w->kind), w->duration_s,
           w->gripper_width_m);
    for (int j = 0; j < PLACEMENT_JOINTS; ++j) printf(" %8.5f", w->q_rad[j]);
    printf("\n");
  }
  if (o->simulated) printf("simulated (lib/balance): %s\n", trial_outcome_name(o->sim.outcome));
}

/* lib/balance's trial at the release pose: 0, or an exit status (logged). */
static int simulate(const plan_args_t *a, plan_out_t *o) {
  estimate_direct_t *sim = NULL;
  estimate_backend_t be;
  char err[512] = "";
  int rc = estimate_direct_open(a->urdf, a->link, NULL, &sim, &be, err, sizeof err);
  if (rc == 0) {
    estimate_trial_request_t req;
    memset(&req, 0, sizeof req);
    req.kind = ESTIMATE_TRIAL_EDGE;
    req.edge = a->edge;
    req.release = o->release;
    req.search = -1;
    req.component = -1;
    rc = be.run(be.ctx, &req, &o->sim, err, sizeof err) == 0 ? 0 : EXIT_FAILURE;
  }
  estimate_direct_close(sim);
  if (rc != 0) LOG_E("--simulate: %s", err[0] ? err : "the trial failed");
  o->simulated = rc == 0;
  return rc;
}

/* The release pose, the grasp and the plan: 0, or an exit status (logged). */
static int plan(const plan_args_t *a, const model_mesh_t *mesh, plan_out_t *o) {
  balance_config_default(&o->bc);
  estimate_lcm_plan_config(&o->pc);
  const model_status_t ms = model_pose_over_edge(mesh, o->bc.base_size_m, a->wxyz, a->edge,
                                                 a->point_m, a->along_m, 1e-6, &o->release);
  if (ms != MODEL_OK) {
    LOG_E("%s: no release pose over edge %s: %s", a->urdf, edge_name(a->edge),
          model_status_str(ms));
    return EXIT_USAGE;
  }
  placement_arm_t arm[2];
  placement_error_t pe = {{0}};
  const char *yumi = cli_paths_yumi_urdf();
  placement_status_t ps = placement_arm_load_yumi(&arm[0], yumi, PLACEMENT_ARM_LEFT, &pe);
  if (ps == PLACEMENT_OK) ps = placement_arm_load_yumi(&arm[1], yumi, PLACEMENT_ARM_RIGHT, &pe);
  if (ps != PLACEMENT_OK) {
    LOG_E("%s: %s %s", yumi, placement_status_str(ps), pe.msg);
    return EXIT_FAILURE;
  }
  for (int side = 0; side < 2; ++side)
    for (int k = 0; k < PLACEMENT_JOINTS; ++k) {
      const double q = a->q_start[side][k];
      if (q < arm[side].lower_rad[k] || q > arm[side].upper_rad[k]) {
        LOG_E("--q-start: %s is %g rad, outside its limits [%g, %g]", arm[side].joint_names[k], q,
              arm[side].lower_rad[k], arm[side].upper_rad[k]);
        return EXIT_USAGE;
      }
    }
  placement_grasp_request_t req;
  memset(&req, 0, sizeof req);
  req.mesh_link = mesh;
  req.object_in_block = o->release;
  memcpy(req.q_start_rad, a->q_start, sizeof req.q_start_rad);
  const placement_grasp_config_t gcfg = PLACEMENT_GRASP_CONFIG_INIT;
  ps = placement_grasp_plan(arm, &o->pc, &gcfg, &req, &o->g, &pe);
  if (ps == PLACEMENT_OK) return 0;
  LOG_E("%s: no placement plan for the release pose (%.4f, %.4f, %.4f): %s %s", a->urdf,
        o->release.position_m[0], o->release.position_m[1], o->release.position_m[2],
        placement_status_str(ps), pe.msg);
  /* E_LIMITS: --q-start outside the arms' joint limits */
  return ps == PLACEMENT_E_ARG || ps == PLACEMENT_E_NONFINITE || ps == PLACEMENT_E_ROTATION ||
                 ps == PLACEMENT_E_LIMITS
             ? EXIT_USAGE
             : EXIT_FAILURE;
}

int cmd_plan(int argc, char **argv) {
  plan_args_t a;
  int rc = parse_args(argc, argv, &a);
  if (rc != 0) return rc < 0 ? EXIT_SUCCESS : rc;
  model_error_t merr = {{0}};
  model_object_t obj = {0};
  const model_status_t ms = model_object_load(a.urdf, a.link, &obj, &merr);
  if (ms != MODEL_OK) {
    LOG_E("%s (%s)", merr.msg[0] ? merr.msg : a.urdf, model_status_str(ms));
    model_object_free(&obj);
    return ms == MODEL_E_NOMEM ? EXIT_FAILURE : EXIT_USAGE; /* as inspect and estimate */
  }
  plan_out_t o;
  memset(&o, 0, sizeof o);
  rc = plan(&a, &obj.mesh, &o);
  model_object_free(&obj);
  if (rc == 0 && a.simulate) rc = simulate(&a, &o);
  if (rc != 0) return rc;
  if (a.json)
    print_json(&a, &o);
  else
    print_table(&a, &o);
  if (fflush(stdout) != 0 || ferror(stdout)) {
    LOG_E("writing the plan to stdout failed");
    return EXIT_FAILURE;
  }
  return EXIT_SUCCESS;
}
