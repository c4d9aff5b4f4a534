/*
 * cmd_estimate.c - `comlearn estimate OBJECT.urdf`: load the geometry (never the inertial), run
 * the estimate through a trial backend, print the result. --truth reads the URDF inertial after
 * the estimate, for the report only.
 */
#define _GNU_SOURCE
#include "cmd_estimate.h"

#include <errno.h>
#include <getopt.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "comlearn/balance_poses.h"
#include "comlearn/cli_args.h"
#include "comlearn/cli_json.h"
#include "comlearn/cli_log.h"
#include "comlearn/cli_net.h"
#include "comlearn/cli_paths.h"
#include "comlearn/cli_time.h"
#include "comlearn/model.h"
#include "comlearn/model_inertial.h"
#include "comlearn/msg.h"
#include "estimate_backend.h"
#include "estimate_direct.h"
#include "estimate_lcm.h"
#include "estimate_svg.h"

enum { EXIT_USAGE = 2 };

static void usage(FILE *out) {
  fprintf(out,
          "usage: comlearn estimate OBJECT.urdf [options]\n"
          "\n"
          "Learns the object's center of mass from placements on the edge of block B: a\n"
          "resting-pose check and two edge searches on a flat face, a check and one search on a\n"
          "second flat face, then a 3-D solve (docs/estimate.md).\n"
          "\n"
          "options:\n"
          "  --policy P         bisect | pba | paper-qtable | paper-mlp (default: bisect)\n"
          "  --resolution-mm R  search resolution in mm, 0.001..10 (default: 0.1)\n"
          "  --start S          where the searches start: uniform (the mesh's uniform-density\n"
          "                     CoM) | bbox (the bounding-box centre, the paper's state 0)\n"
          "                     (default: uniform)\n"
          "  --pivots N         noiseless: at most N pivot searches (the object balanced on B's\n"
          "                     edge line along a hull edge, tilted) for components the faces\n"
          "                     leave not found, 0..8; 0: none (default: 4)\n"
          "  --noise-mm S       the noise model: std. dev. of the placement error along the edge\n"
          "                     normal, 0..100 mm; > 0 makes every interval a 95 %% interval\n"
          "                     (default: --placement-noise-mm with --direct, else 0: noiseless,\n"
          "                     intervals are bounds)\n"
          "  --noise-target-mm T  with a noise model, the 95 %% half width every component is\n"
          "                     taken to: searches stop at 2T, then the one that widens a\n"
          "                     component most goes on; 0..10, 0: no refinement (default: 0.5)\n"
          "  --noise-stop-mm W  with a noise model, a search first stops when its 95 %% interval\n"
          "                     is at most W mm wide, 0..10 (default: 0: max(resolution, noise,\n"
          "                     2 x --noise-target-mm))\n"
          "  --placement-noise-mm S  --direct: std. dev. of the horizontal release offset, as\n"
          "                     comlearn-sim's option, 0..100 mm (default: 0)\n"
          "  --pose-noise-mm S  --direct: std. dev. of the perceived settled position, 0..100 mm;\n"
          "                     the estimator is told it too (rough faces with noise)\n"
          "                     (default: 0)\n"
          "  --seed N           --direct: noise seed, as comlearn-sim --seed (default: 1)\n"
          "  --direct           run the trials in-process on lib/balance (no LCM, no arm)\n"
          "  --lcm-url URL      LCM URL of the YuMi controller and perception (comlearn-sim)\n"
          "                     (default: udpm://239.255.76.67:7667?ttl=0; with --spawn-sim:\n"
          "                     udpm://239.255.76.67:<7700 + pid %% 1000>?ttl=0)\n"
          "  --spawn-sim        start a comlearn-sim on the URL for the call and stop it at the\n"
          "                     end (default: off: one must already run there)\n"
          "  --channel-prefix P the robot's channels on a shared URL: P before every channel\n"
          "                     name, as comlearn-sim --channel-prefix (e.g. R2_ for\n"
          "                     R2_YUMI_COMMAND); at most 32 of A-Z a-z 0-9 _ (default: none)\n"
          "  --link NAME        URDF link to read (default: the root link)\n"
          "  --json             print one JSON object on stdout (default: a table)\n"
          "  --truth            after the estimate, read the URDF <inertial> and report the\n"
          "                     error; for reporting only (default: off)\n"
          "  --svg FILE         also write a picture of the estimate: three views of the mesh\n"
          "                     with the CoM, its interval box, the truth with --truth, the\n"
          "                     resting faces and edge lines, and the first %d trials' poses\n"
          "                     (default: none)\n"
          "  -v, --verbose      log debug messages on stderr (default: info)\n"
          "  -q, --quiet        log errors only; no progress (default: info, progress on a tty)\n"
          "  -h, --help         show this help\n"
          "  -V, --version      print the version\n"
          "\n"
          "exit status: 0 success, 1 runtime failure, 2 usage or bad input\n",
          (int)ESTIMATE_SVG_TRIAL_PANELS);
}

static const char *regime_name(int r) {
  switch (r) {
    case MODEL_REGIME_FLAT_PATCH: return "flat_patch";
    case MODEL_REGIME_EDGE_ROLL: return "edge_roll";
    case MODEL_REGIME_POINT_SUPPORT: return "point_support";
    case MODEL_REGIME_CLOSED_PATCH: return "closed_patch";
    default: return "none";
  }
}

static void progress(void *ctx, size_t index, const char *what) {
  (void)ctx;
  fprintf(stderr, "\rcomlearn estimate: trial %3zu  %-60s", index, what);
  fflush(stderr);
}

static void lcm_log(void *ctx, const char *msg) {
  (void)ctx;
  LOG_D("lcm: %s", msg);
}

static void json_vec(const char *key, const double *v, int n) {
  printf("\"%s\": ", key);
  cli_json_array(stdout, v, n > 0 ? (size_t)n : 0);
}

/* The JSON arrays of the checked faces, the searches and every trial (print_json). */
static void json_faces(const estimate_result_t *r) {
  for (size_t i = 0; i < r->face_count; ++i) {
    const estimate_face_t *f = &r->face[i];
    printf("%s{", i ? ", " : "");
    json_vec("normal_link", f->normal_link, 3);
    printf(", \"area_m2\": ");
    cli_json_number(stdout, f->area_m2);
    printf(", \"contact_area_m2\": ");
    cli_json_number(stdout, f->contact_area_m2);
    printf(", \"regions\": %zu", f->regions);
    printf(", \"com_margin_m\": ");
    cli_json_number(stdout, f->com_margin_m);
    printf(", \"stable\": %s, \"rough\": %s}", f->confirmed ? "true" : "false",
           f->rough ? "true" : "false");
  }
}

static void json_searches(const estimate_result_t *r) {
  for (size_t i = 0; i < r->search_count; ++i) {
    const estimate_search_t *s = &r->search[i];
    printf("%s{\"face\": %d, \"yaw_rad\": ", i ? ", " : "", s->face);
    cli_json_number(stdout, s->yaw_rad);
    printf(", ");
    json_vec("dir_link", s->dir_link, 3);
    printf(", \"chord_margin_m\": ");
    cli_json_number(stdout, s->chord_margin_m);
    printf(", \"prior_m\": ");
    cli_json_number(stdout, s->prior_m);
    printf(", \"range_m\": [");
    cli_json_number(stdout, s->range_lo_m);
    printf(", ");
    cli_json_number(stdout, s->range_hi_m);
    printf("], \"c_m\": ");
    cli_json_number(stdout, s->c_m);
    printf(", \"halfwidth_m\": ");
    cli_json_number(stdout, s->halfwidth_m);
    printf(", \"bias_m\": ");
    cli_json_number(stdout, s->bias_m);
    printf(", \"verified_margin_m\": ");
    cli_json_number(stdout, s->verified_margin_m);
    printf(", \"verify_need_m\": ");
    cli_json_number(stdout, isnan(s->verified_margin_m) ? NAN : s->verify_need_m);
    printf(
        ", \"trials\": %u, \"handover_trials\": %u, \"refines\": %u, \"retest_of\": %d, "
        "\"mirror_of\": %d, \"added\": %s, \"pivot\": %s, ",
        s->trials, s->handover_trials, s->refines, s->retest_of, s->mirror_of,
        s->added ? "true" : "false", s->pivot ? "true" : "false");
    if (s->pivot) {
      printf("\"pivot_link_m\": [");
      cli_json_array(stdout, s->pivot_link_m[0], 3);
      printf(", ");
      cli_json_array(stdout, s->pivot_link_m[1], 3);
      printf("], ");
    }
    printf("\"fed\": %s, \"note\": ", s->fed ? "true" : "false");
    cli_json_string(stdout, s->note, 0);
    printf("}");
  }
}

static void json_trials(const estimate_result_t *r) {
  for (size_t i = 0; i < r->trial_count; ++i) {
    const estimate_trial_t *t = &r->trial[i];
    const int pivot = t->search >= 0 && r->search[t->search].pivot;
    printf("%s{\"kind\": \"%s\", \"face\": %d, \"search\": %d, \"x_m\": ", i ? ", " : "",
           t->kind == ESTIMATE_TRIAL_STABLE ? "stable"
           : pivot                          ? "pivot"
                                            : "edge",
           t->face, t->search);
    cli_json_number(stdout, t->x_m);
    printf(", \"outcome\": \"%s\", \"counted\": \"%s\", \"regime\": \"%s\", \"flagged\": %s}",
           trial_outcome_name(t->outcome), trial_outcome_name(t->counted),
           pivot ? "pivot" : regime_name(t->regime), t->flagged ? "true" : "false");
  }
}

static void print_json(const char *urdf, qlearn_policy_kind_t policy, double res_m,
                       const char *backend, estimate_status_t status, const estimate_result_t *r,
                       double wall_s, const model_mass_t *truth) {
  printf("{\"object\": ");
  cli_json_string(stdout, urdf, 0);
  printf(", \"status\": ");
  cli_json_string(stdout, status == ESTIMATE_OK ? "ok" : estimate_status_str(status), 0);
  printf(", \"policy\": \"%s\", \"backend\": \"%s\", \"resolution_m\": ",
         estimate_policy_name(policy), backend);
  cli_json_number(stdout, res_m);
  printf(", ");
  static const double none[3] = {NAN, NAN, NAN}; /* a failed estimate has none */
  json_vec("com_m", status == ESTIMATE_OK ? r->com_m : none, 3);
  printf(", ");
  json_vec("halfwidth_m", status == ESTIMATE_OK ? r->halfwidth_m : none, 3);
  printf(", \"found\": [%s, %s, %s], \"reason\": [", r->found[0] ? "true" : "false",
         r->found[1] ? "true" : "false", r->found[2] ? "true" : "false");
  for (int k = 0; k < 3; ++k) {
    printf("%s", k ? ", " : "");
    if (r->found[k])
      printf("null");
    else
      cli_json_string(stdout, r->reason[k], 0);
  }
  printf("], \"interval\": \"%s\", ", r->noisy ? "95%" : "bound");
  printf("\"trials\": %zu, \"stable_trials\": %zu, \"edge_trials\": %zu, \"flagged_trials\": %zu, ",
         r->trial_count, r->stable_trials, r->trial_count - r->stable_trials, r->flagged_trials);
  json_vec("uniform_com_m", r->uniform_com_m, 3);
  printf(", ");
  json_vec("start_m", r->start_m, 3);
  printf(", \"rank\": %d, \"chi2\": ", r->rank);
  cli_json_number(stdout, r->chi2);
  printf(", \"wall_s\": %.6f", wall_s);
  if (truth) {
    double e[3];
    for (int k = 0; k < 3; ++k) e[k] = r->found[k] ? r->com_m[k] - truth->com_m[k] : NAN;
    printf(", ");
    json_vec("truth_m", truth->com_m, 3);
    printf(", ");
    json_vec("error_m", e, 3);
  }
  printf(", \"note\": ");
  cli_json_string(stdout, r->msg, 0);
  printf(", \"faces\": [");
  json_faces(r);
  printf("], \"searches\": [");
  json_searches(r);
  printf("], \"trial_log\": [");
  json_trials(r);
  printf("]}\n");
}

static void print_table(const char *urdf, qlearn_policy_kind_t policy, const estimate_result_t *r,
                        double wall_s, const model_mass_t *truth) {
  static const char axis[3] = {'x', 'y', 'z'};
  printf("%s: policy %s, %zu trials (%zu stable-pose checks, %zu flagged), %.3f s\n", urdf,
         estimate_policy_name(policy), r->trial_count, r->stable_trials, r->flagged_trials, wall_s);
  printf("axis  estimate (mm)  +- (mm)  found%s\n", truth ? "   truth (mm)  error (mm)" : "");
  for (int k = 0; k < 3; ++k) {
    printf("  %c   %12.4f  %7.4f  %5s", axis[k], 1e3 * r->com_m[k], 1e3 * r->halfwidth_m[k],
           r->found[k] ? "yes" : "no");
    if (truth)
      printf("   %10.4f  %10.4f", 1e3 * truth->com_m[k],
             r->found[k] ? 1e3 * (r->com_m[k] - truth->com_m[k]) : NAN);
    printf("\n");
  }
  printf("intervals: %s\n", r->noisy ? "95 % under the noise model" : "bounds (noiseless)");
  for (size_t i = 0; i < r->search_count; ++i)
    printf("search %zu: face %d, %u trials, %s%s\n", i, r->search[i].face, r->search[i].trials,
           r->search[i].fed ? "fed to the solve" : "not used: ", r->search[i].note);
  for (int k = 0; k < 3; ++k)
    if (!r->found[k]) printf("%c not found: %s\n", axis[k], r->reason[k]);
}

static int exit_for_model(model_status_t s) {
  return s == MODEL_E_NOMEM ? EXIT_FAILURE : EXIT_USAGE;
}

/* A length option in mm within [min_mm, max_mm], into metres; -1 (message logged) when it is
 * not. */
static int parse_mm(const char *opt, const char *text, double min_mm, double max_mm,
                    double *out_m) {
  char *end;
  errno = 0;
  const double mm = strtod(text, &end);
  if (end == text || *end != '\0' || errno != 0 || !isfinite(mm) || mm < min_mm || mm > max_mm) {
    LOG_E("--%s: '%s' is not a number in [%g, %g]", opt, text, min_mm, max_mm);
    return -1;
  }
  *out_m = 1e-3 * mm;
  return 0;
}

/* --svg FILE before any trial: its folder exists and is writable, FILE is not a folder. 0, or -1
 * (message logged, naming the path): bad input, found before the trials are spent. */
static int svg_path_check(const char *path) {
  char dir[PATH_MAX];
  const char *slash = strrchr(path, '/');
  const size_t n = slash ? (size_t)(slash - path) : 0;
  if (n >= sizeof dir) {
    LOG_E("--svg %s: %s", path, strerror(ENAMETOOLONG));
    return -1;
  }
  if (slash) {
    memcpy(dir, path, n);
    dir[n] = '\0';
  }
  if (!slash || n == 0) snprintf(dir, sizeof dir, "%s", slash ? "/" : ".");
  struct stat st;
  if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode)) {
    LOG_E("--svg %s: the folder '%s' does not exist", path, dir);
    return -1;
  }
  if (access(dir, W_OK | X_OK) != 0) {
    LOG_E("--svg %s: cannot write in the folder '%s': %s", path, dir, strerror(errno));
    return -1;
  }
  if (stat(path, &st) == 0 && S_ISDIR(st.st_mode)) {
    LOG_E("--svg %s: is a folder", path);
    return -1;
  }
  return 0;
}

/* What the command line asks for. */
typedef struct {
  estimate_config_t cfg;
  const char *urdf, *link, *lcm_url, *channel_prefix, *svg;
  int direct, spawn, json, truth, quiet, noise_given, sim_noise;
  double placement_noise_m, pose_noise_m;
  uint64_t seed;
} est_args_t;

/* One option of est_args_t (c as getopt_long returns it): 0, or an exit status. */
static int parse_option(int c, est_args_t *a) {
  switch (c) {
    case 'p':
      if (estimate_policy_parse(optarg, &a->cfg.policy) == 0) return 0;
      LOG_E("--policy: '%s' is not one of bisect, pba, paper-qtable, paper-mlp", optarg);
      return EXIT_USAGE;
    case 'r':
      return parse_mm("resolution-mm", optarg, 0.001, 10.0, &a->cfg.resolution_m) ? EXIT_USAGE : 0;
    case 'S':
      if (strcmp(optarg, "uniform") == 0)
        a->cfg.start = ESTIMATE_START_UNIFORM;
      else if (strcmp(optarg, "bbox") == 0)
        a->cfg.start = ESTIMATE_START_BBOX;
      else {
        LOG_E("--start: '%s' is not one of uniform, bbox", optarg);
        return EXIT_USAGE;
      }
      return 0;
    case 'K': {
      char *end;
      errno = 0;
      const long v = strtol(optarg, &end, 10);
      if (end == optarg || *end != '\0' || errno != 0 || v < 0 || v > 8) {
        LOG_E("--pivots: '%s' is not a whole number in 0..8", optarg);
        return EXIT_USAGE;
      }
      a->cfg.max_pivots = (uint32_t)v;
      return 0;
    }
    case 'n':
      a->noise_given = 1;
      return parse_mm("noise-mm", optarg, 0.0, 100.0, &a->cfg.noise_sigma_m) ? EXIT_USAGE : 0;
    case 'W':
      return parse_mm("noise-stop-mm", optarg, 0.0, 10.0, &a->cfg.noise_stop_width_m) ? EXIT_USAGE
                                                                                      : 0;
    case 'T':
      return parse_mm("noise-target-mm", optarg, 0.0, 10.0, &a->cfg.noise_target_halfwidth_m)
                 ? EXIT_USAGE
                 : 0;
    case 'P':
      a->sim_noise = 1;
      return parse_mm("placement-noise-mm", optarg, 0.0, 100.0, &a->placement_noise_m) ? EXIT_USAGE
                                                                                       : 0;
    case 'O':
      a->sim_noise = 1;
      return parse_mm("pose-noise-mm", optarg, 0.0, 100.0, &a->pose_noise_m) ? EXIT_USAGE : 0;
    case 'e': {
      char *end;
      errno = 0;
      const unsigned long long v = strtoull(optarg, &end, 0);
      if (end == optarg || *end != '\0' || errno != 0 || optarg[0] == '-') {
        LOG_E("--seed: '%s' is not a number in [0, 2^64 - 1]", optarg);
        return EXIT_USAGE;
      }
      a->seed = (uint64_t)v;
      a->sim_noise = 1;
      return 0;
    }
    case 'd': a->direct = 1; return 0;
    case 'u':
      if (optarg[0]) {
        a->lcm_url = optarg;
        return 0;
      }
      LOG_E("--lcm-url: empty URL");
      return EXIT_USAGE;
    case 's': a->spawn = 1; return 0;
    case 'c':
      if (comlearn_msg_channel_prefix_ok(optarg)) {
        a->channel_prefix = optarg;
        return 0;
      }
      LOG_E("--channel-prefix: need at most %d of A-Z a-z 0-9 _, got '%s'",
            COMLEARN_MSG_CHANNEL_PREFIX_MAX, optarg);
      return EXIT_USAGE;
    case 'l': a->link = optarg; return 0;
    case 'j': a->json = 1; return 0;
    case 't': a->truth = 1; return 0;
    case 'g':
      if (optarg[0]) {
        a->svg = optarg;
        return 0;
      }
      LOG_E("--svg: empty file name");
      return EXIT_USAGE;
    case 'v': cli_log_set_level(CLI_LOG_DEBUG); return 0;
    case 'q':
      a->quiet = 1;
      cli_log_set_level(CLI_LOG_ERROR);
      return 0;
    case 'h': usage(stdout); return -1; /* done: exit 0 */
    case 'V': cli_version_print(stdout, "comlearn"); return -1;
    default: return EXIT_USAGE; /* parse_args says why */
  }
}

/* The command line into *a: 0 to go on, -1 for exit 0 (--help), else an exit status. */
static int parse_args(int argc, char **argv, est_args_t *a) {
  static const struct option opts[] = {{"policy", required_argument, NULL, 'p'},
                                       {"resolution-mm", required_argument, NULL, 'r'},
                                       {"direct", no_argument, NULL, 'd'},
                                       {"lcm-url", required_argument, NULL, 'u'},
                                       {"spawn-sim", no_argument, NULL, 's'},
                                       {"channel-prefix", required_argument, NULL, 'c'},
                                       {"link", required_argument, NULL, 'l'},
                                       {"json", no_argument, NULL, 'j'},
                                       {"truth", no_argument, NULL, 't'},
                                       {"svg", required_argument, NULL, 'g'},
                                       {"verbose", no_argument, NULL, 'v'},
                                       {"quiet", no_argument, NULL, 'q'},
                                       {"start", required_argument, NULL, 'S'},
                                       {"pivots", required_argument, NULL, 'K'},
                                       {"noise-mm", required_argument, NULL, 'n'},
                                       {"noise-stop-mm", required_argument, NULL, 'W'},
                                       {"noise-target-mm", required_argument, NULL, 'T'},
                                       {"placement-noise-mm", required_argument, NULL, 'P'},
                                       {"pose-noise-mm", required_argument, NULL, 'O'},
                                       {"seed", required_argument, NULL, 'e'},
                                       {"help", no_argument, NULL, 'h'},
                                       {"version", no_argument, NULL, 'V'},
                                       {NULL, 0, NULL, 0}};
  memset(a, 0, sizeof *a);
  estimate_config_default(&a->cfg);
  a->seed = 1;
  int c;
  optind = 1;
  opterr = 0;
  while ((c = getopt_long(argc, argv, "vqhV", opts, NULL)) != -1) {
    const int rc = parse_option(c, a);
    if (rc == EXIT_USAGE && (c == '?' || c == ':'))
      cli_getopt_complain("comlearn estimate", "vqhV", opts, argv);
    if (rc != 0) return rc;
  }
  if (optind != argc - 1) {
    LOG_E("estimate needs exactly one OBJECT.urdf");
    usage(stderr);
    return EXIT_USAGE;
  }
  a->urdf = argv[optind];
  if (a->direct && (a->spawn || a->lcm_url || a->channel_prefix)) {
    LOG_E("--direct runs in-process: it takes neither --spawn-sim, --lcm-url nor --channel-prefix");
    return EXIT_USAGE;
  }
  if (a->sim_noise && !a->direct) {
    LOG_E(
        "--placement-noise-mm, --pose-noise-mm and --seed perturb the --direct trials; over LCM "
        "the simulator's own options set the noise (comlearn-sim --placement-noise-mm ...)");
    return EXIT_USAGE;
  }
  if (a->svg && svg_path_check(a->svg) != 0) return EXIT_USAGE;
  if (!a->noise_given) a->cfg.noise_sigma_m = a->placement_noise_m; /* the trials' noise */
  a->cfg.pose_noise_sigma_m = a->pose_noise_m; /* --direct: the perception's noise is known */
  return 0;
}

/* The trial backend and what it owns. */
typedef struct {
  estimate_backend_t backend;
  estimate_direct_t *sim;
  estimate_lcm_t *lcm;
  pid_t child;
  char url[128];
} est_backend_t;

static void backend_close(est_backend_t *b) {
  estimate_direct_close(b->sim);
  estimate_lcm_close(b->lcm);
  b->sim = NULL;
  b->lcm = NULL;
  if (b->child > 0) {
    int ws = estimate_lcm_sim_stop(b->child, 2.0);
    if (ws == -1 || !WIFEXITED(ws) || WEXITSTATUS(ws) != 0)
      LOG_W("comlearn-sim (pid %d) did not exit cleanly (wait status %d)", (int)b->child, ws);
  }
  b->child = -1;
}

/* Open the backend a asks for: 0, or an exit status (message logged). */
static int backend_open(const est_args_t *a, const model_object_t *obj, est_backend_t *b) {
  char err[512] = "";
  b->child = -1;
  if (a->direct) {
    int rc = estimate_direct_open(a->urdf, a->link, NULL, &b->sim, &b->backend, err, sizeof err);
    if (rc == 0 && (a->placement_noise_m > 0.0 || a->pose_noise_m > 0.0) &&
        estimate_direct_set_noise(b->sim, a->seed, a->placement_noise_m, a->pose_noise_m) != 0) {
      snprintf(err, sizeof err, "noise out of range");
      rc = EXIT_USAGE;
    }
    if (rc != 0) {
      LOG_E("%s", err);
      backend_close(b);
    }
    return rc;
  }
  const char *url = a->lcm_url;
  if (a->spawn) {
    if (!url) {
      snprintf(b->url, sizeof b->url, "udpm://239.255.76.67:%u?ttl=0",
               7700u + (unsigned)getpid() % 1000u);
      url = b->url;
    }
    const char *exe = getenv("COMLEARN_SIM");
    if (!exe || !exe[0]) exe = cli_paths_sim_exe();
    /* the simulator may read the object's folder and the bundled assets */
    char dir[PATH_MAX];
    if (realpath(a->urdf, dir) == NULL) {
      LOG_E("--spawn-sim: %s: %s", a->urdf, strerror(errno));
      return EXIT_USAGE;
    }
    *strrchr(dir, '/') = '\0';
    const char *dirs[] = {dir[0] ? dir : "/", cli_paths_assets_dir(), NULL};
    b->child = estimate_lcm_sim_spawn(exe, url, a->channel_prefix, dirs, err, sizeof err);
    if (b->child < 0) {
      LOG_E("--spawn-sim: %s", err);
      return EXIT_FAILURE;
    }
    LOG_I("started comlearn-sim (pid %d) on %s", (int)b->child, url);
  }
  estimate_lcm_config_t lc;
  estimate_lcm_config_default(&lc);
  lc.lcm_url = url;
  lc.channel_prefix = a->channel_prefix;
  lc.urdf_path = a->urdf;
  lc.mesh_link = &obj->mesh;
  lc.yumi_urdf = cli_paths_yumi_urdf();
  lc.policy = estimate_policy_name(a->cfg.policy);
  lc.log = lcm_log;
  const int rc = estimate_lcm_open(&lc, &b->lcm, &b->backend, err, sizeof err);
  if (rc != 0) {
    LOG_E("%s", err);
    backend_close(b);
  }
  return rc;
}

/* After the run over LCM: COM_ESTIMATE, and the message counts in the debug log. */
static void lcm_report(estimate_lcm_t *lcmb, estimate_status_t es, const estimate_result_t *res,
                       double resolution_m) {
  if (es == ESTIMATE_OK && estimate_lcm_publish_estimate(lcmb, res, resolution_m, 1) != 0)
    LOG_W("publishing COM_ESTIMATE failed");
  estimate_lcm_stats_t ls;
  estimate_lcm_stats(lcmb, &ls);
  if (ls.rcvbuf_overflows > 0) /* what may never have reached LCM */
    LOG_W(
        "lcm: %lld datagrams were dropped for a full receive buffer on this host during the "
        "estimate (RcvbufErrors; any process's)",
        (long long)ls.rcvbuf_overflows);
  LOG_D(
      "lcm: %llu trials, %llu commands (%llu resent), %llu sim controls, %llu trial "
      "restarts, %llu statuses, %llu object states, %llu undecodable, %llu refused",
      (unsigned long long)ls.trials, (unsigned long long)ls.commands_sent,
      (unsigned long long)ls.commands_resent, (unsigned long long)ls.controls_sent,
      (unsigned long long)ls.trial_restarts, (unsigned long long)ls.statuses,
      (unsigned long long)ls.object_states, (unsigned long long)ls.undecodable,
      (unsigned long long)ls.refused);
}

/* --svg: the picture of the estimate (the truth only when read for --truth). 0, or -1 (logged). */
static int write_picture(const est_args_t *a, const char *backend_name, const model_mesh_t *mesh,
                         const double base_size_m[3], const estimate_result_t *res,
                         const model_mass_t *truth) {
  estimate_svg_input_t in = {.object = a->urdf,
                             .policy = estimate_policy_name(a->cfg.policy),
                             .backend = backend_name,
                             .mesh_link = mesh,
                             .result = res,
                             .truth_com_m = truth ? truth->com_m : NULL};
  memcpy(in.base_size_m, base_size_m, sizeof in.base_size_m);
  if (estimate_svg_write(a->svg, &in) != 0) {
    LOG_E("--svg %s: %s", a->svg, strerror(errno));
    return -1;
  }
  LOG_D("wrote %s", a->svg);
  return 0;
}

/* Print the result (the truth read now, after the estimate, when asked), and with --svg draw it:
 * the exit status. */
static int report(const est_args_t *a, const char *backend_name, estimate_status_t status,
                  const estimate_result_t *res, double wall_s, const model_mesh_t *mesh,
                  const double base_size_m[3]) {
  int found = 0;
  for (int k = 0; k < 3; ++k) {
    if (res->found[k])
      ++found;
    else if (status == ESTIMATE_OK)
      LOG_W("component %c not found: %s", "xyz"[k], res -> reason[k]);
  }
  model_mass_t tm;
  const model_mass_t *tp = NULL;
  if (a->truth) {
    model_error_t merr = {{0}};
    const model_status_t ms = model_inertial_load(a->urdf, a->link, &tm, &merr);
    if (ms != MODEL_OK) {
      LOG_E("--truth: %s (%s)", merr.msg[0] ? merr.msg : a->urdf, model_status_str(ms));
      return exit_for_model(ms);
    }
    tp = &tm;
  }
  if (a->json)
    print_json(a->urdf, a->cfg.policy, a->cfg.resolution_m, backend_name, status, res, wall_s, tp);
  else
    print_table(a->urdf, a->cfg.policy, res, wall_s, tp);
  if (status != ESTIMATE_OK) return EXIT_FAILURE;
  if (a->svg && write_picture(a, backend_name, mesh, base_size_m, res, tp) != 0)
    return EXIT_FAILURE;
  if (found == 0) {
    LOG_E("%s: no component could be estimated", a->urdf);
    return EXIT_FAILURE;
  }
  return EXIT_SUCCESS;
}

int cmd_estimate(int argc, char **argv) {
  est_args_t a;
  int rc = parse_args(argc, argv, &a);
  if (rc != 0) return rc < 0 ? EXIT_SUCCESS : rc;
  /* The estimator's view: geometry only. */
  model_error_t merr = {{0}};
  model_object_t obj = {0};
  model_status_t ms = model_object_load(a.urdf, a.link, &obj, &merr);
  if (ms != MODEL_OK) {
    LOG_E("%s (%s)", merr.msg[0] ? merr.msg : a.urdf, model_status_str(ms));
    return exit_for_model(ms);
  }
  est_backend_t b;
  memset(&b, 0, sizeof b);
  estimate_result_t *res = malloc(sizeof *res);
  rc = res ? backend_open(&a, &obj, &b) : EXIT_FAILURE;
  if (rc != 0) {
    if (!res) LOG_E("out of memory");
    free(res);
    model_object_free(&obj);
    return rc;
  }
  if (!a.quiet && isatty(STDERR_FILENO)) b.backend.progress = progress;
  const double t0 = cli_time_now_s();
  const estimate_status_t es = estimate_run(&obj.mesh, &b.backend, &a.cfg, res);
  const double wall = cli_time_now_s() - t0;
  if (b.backend.progress) fprintf(stderr, "\n");
  if (b.lcm) lcm_report(b.lcm, es, res, a.cfg.resolution_m);
  const char *name = b.backend.name;
  backend_close(&b);
  if (es != ESTIMATE_OK) {
    LOG_E("%s: %s%s%s", a.urdf, estimate_status_str(es), res->msg[0] ? ": " : "", res->msg);
    /* geometry that gives no flat face or no stable pose: the object does not suit the method;
     * with --json the trials run so far and the faces tried are printed all the same */
    rc = es == ESTIMATE_E_ARG ? EXIT_USAGE
         : a.json             ? report(&a, name, es, res, wall, &obj.mesh, b.backend.base_size_m)
                              : EXIT_FAILURE;
    free(res);
    model_object_free(&obj);
    return rc;
  }
  rc = report(&a, name, es, res, wall, &obj.mesh, b.backend.base_size_m);
  free(res);
  model_object_free(&obj);
  return rc;
}
