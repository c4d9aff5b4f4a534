/*
 * cmd_watch.c - `comlearn watch`: subscribes COM_TRIAL and COM_ESTIMATE (counted decoding,
 * comlearn_msg_subscribe) and prints a live table of the trials and the running / final estimate,
 * or one JSON object per record (--json). It reads only LCM traffic, so it works the same on a
 * running `comlearn estimate` and on an lcm-logplayer replay of a recorded one (docs/replay.md).
 */
#define _GNU_SOURCE
#include "cmd_watch.h"

#include <errno.h>
#include <getopt.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <lcm/lcm.h>

#include "comlearn/cli_args.h"
#include "comlearn/cli_json.h"
#include "comlearn/cli_log.h"
#include "comlearn/cli_net.h"
#include "comlearn/cli_stop.h"
#include "comlearn/cli_time.h"
#include "comlearn/comlearn_com_estimate_t.h"
#include "comlearn/comlearn_com_trial_t.h"
#include "comlearn/math3d.h"
#include "comlearn/msg.h"

enum { EXIT_USAGE = 2 };

static void usage(FILE *out) {
  fprintf(out,
          "usage: comlearn watch [options]\n"
          "\n"
          "Prints the trials (COM_TRIAL) and the running and final estimate (COM_ESTIMATE) of\n"
          "`comlearn estimate` runs as they arrive on LCM: live, or from an lcm-logplayer\n"
          "replay of a recorded run (docs/replay.md). Undecodable buffers are counted, never\n"
          "printed.\n"
          "\n"
          "options:\n"
          "  --lcm-url URL      LCM URL to listen on (default: " COMLEARN_MSG_LCM_URL_DEFAULT
          ")\n"
          "  --channel-prefix P the records of one robot on a shared URL: P before both\n"
          "                     channel names, as comlearn estimate --channel-prefix (default:\n"
          "                     none)\n"
          "  --once             exit 0 after the first final estimate (COM_ESTIMATE with\n"
          "                     done = true) (default: off: until SIGINT / SIGTERM)\n"
          "  --timeout-s T      stop after T seconds of wall time, 0 = never; with --once a\n"
          "                     timeout exits 1, without it exits 0 (default: 0)\n"
          "  --json             one JSON object per record on stdout, one per line:\n"
          "                     {\"type\": \"trial\", ...} or {\"type\": \"estimate\", ...}\n"
          "                     (default: a table)\n"
          "  -v, --verbose      log debug messages on stderr (default: info)\n"
          "  -q, --quiet        log errors only (default: info)\n"
          "  -h, --help         show this help\n"
          "  -V, --version      print the version\n"
          "\n"
          "exit status: 0 success (signal, or --once saw the final estimate), 1 runtime\n"
          "failure or --once timed out, 2 usage or bad input\n");
}

typedef struct {
  int json;
  int once;
  int done_seen;       /* a COM_ESTIMATE with done = true arrived */
  int64_t last_run_id; /* of the last record printed, to head a new run in the table */
  int have_run;
  uint64_t trials, estimates;
  comlearn_msg_channels_t ch; /* with --channel-prefix (COM_TRIAL and COM_ESTIMATE used) */
} watch_t;

static const char *kind_name(int8_t k) {
  switch (k) {
    case COMLEARN_COM_TRIAL_T_KIND_EDGE: return "edge";
    case COMLEARN_COM_TRIAL_T_KIND_REST: return "rest";
  }
  return "?";
}

/* The same words as `comlearn estimate --json`'s trial_log. */
static const char *outcome_name(int8_t o) {
  switch (o) {
    case COMLEARN_COM_TRIAL_T_OUTCOME_INVALID: return "invalid";
    case COMLEARN_COM_TRIAL_T_OUTCOME_STAYS: return "stays";
    case COMLEARN_COM_TRIAL_T_OUTCOME_TIPS: return "tips";
    case COMLEARN_COM_TRIAL_T_OUTCOME_SLIDES: return "slides";
  }
  return "?";
}

static const char *component_name(int8_t c) {
  switch (c) {
    case COMLEARN_COM_TRIAL_T_COMPONENT_X: return "x";
    case COMLEARN_COM_TRIAL_T_COMPONENT_Y: return "y";
    case COMLEARN_COM_TRIAL_T_COMPONENT_Z: return "z";
  }
  return "?";
}

static void json_str(const char *key, const char *v) {
  printf("\"%s\": ", key);
  cli_json_string(stdout, v, 1); /* bytes as Latin-1, like lcm-spy */
  printf(", ");
}

static void json_vec(const char *key, const double *v, int n) {
  printf("\"%s\": ", key);
  cli_json_array(stdout, v, (size_t)n);
  printf(", ");
}

static void json_bools(const char *key, const int8_t *v, int n) {
  printf("\"%s\": [", key);
  for (int i = 0; i < n; ++i) printf("%s%s", i ? ", " : "", v[i] ? "true" : "false");
  printf("], ");
}

/* The angle of a unit quaternion's rotation [rad], in [0, pi]. */
static double quat_angle(const double q[4]) {
  static const double identity[4] = {1.0, 0.0, 0.0, 0.0};
  return cl_quat_angle(identity, q);
}

static void table_header(watch_t *w, int64_t run_id, const char *object, const char *policy) {
  if (w->have_run && w->last_run_id == run_id) return;
  w->have_run = 1;
  w->last_run_id = run_id;
  printf("\nrun %" PRId64 ": object %s, policy %s\n", run_id, object, policy);
  printf("%6s %-14s %5s %4s %4s %-7s %10s %26s %8s %8s %4s\n", "run", "object", "trial", "kind",
         "comp", "outcome", "offset(mm)", "released x y z (mm)", "tilt deg", "rot deg", "flat");
}

static void on_trial(const lcm_recv_buf_t *rbuf, const char *channel, const void *msg, void *user) {
  (void)rbuf;
  (void)channel;
  watch_t *w = user;
  const comlearn_com_trial_t *t = msg;
  ++w->trials;
  /* The estimator-side fields (component, direction, regime) are known iff direction is +-1
   * (records of an older publisher leave them 0): axis and flat-patch then show "?". A rest check
   * has neither: "-". */
  const int edge = t->kind == COMLEARN_COM_TRIAL_T_KIND_EDGE;
  const int known = t->direction != 0;
  const char *comp = !edge ? "-" : known ? component_name(t->component) : "?";
  if (w->json) {
    printf("{\"type\": \"trial\", \"run_id\": %" PRId64 ", ", t->run_id);
    json_str("object", t->object_id);
    json_str("policy", t->policy);
    printf("\"trial_index\": %" PRId32
           ", \"kind\": \"%s\", \"component\": \"%s\", "
           "\"direction\": %d, \"outcome\": \"%s\", ",
           t->trial_index, kind_name(t->kind), comp, (int)t->direction, outcome_name(t->outcome));
    json_vec("edge_normal_world", t->edge_normal_world, 3);
    printf("\"edge_offset_m\": ");
    cli_json_number(stdout, t->edge_offset_m);
    printf(", ");
    json_vec("target_point_link_m", t->target_point_link_m, 3);
    printf("\"target_offset_m\": ");
    cli_json_number(stdout, t->target_offset_m);
    printf(", ");
    json_vec("released_position_m", t->released_position_m, 3);
    json_vec("released_orientation_wxyz", t->released_orientation_wxyz, 4);
    json_vec("settled_position_m", t->settled_position_m, 3);
    json_vec("settled_orientation_wxyz", t->settled_orientation_wxyz, 4);
    printf("\"displacement_m\": ");
    cli_json_number(stdout, t->displacement_m);
    printf(", \"rotation_rad\": ");
    cli_json_number(stdout, t->rotation_rad);
    printf(", \"flat_patch\": %s, \"sideways_margin_m\": ", t->flat_patch ? "true" : "false");
    cli_json_number(stdout, t->sideways_margin_m);
    printf(", ");
    json_vec("com_estimated_m", t->com_estimated_m, 3);
    printf("\"halfwidth_m\": [");
    for (int k = 0; k < 3; ++k) {
      if (k) printf(", ");
      cli_json_number(stdout, t->halfwidth_m[k]);
    }
    printf("]}\n");
  } else {
    table_header(w, t->run_id, t->object_id, t->policy);
    /* flat: the planned edge trial was in the flat-patch regime; "no": approximate. */
    printf(
        "%06" PRId64 " %-14.14s %5" PRId32
        " %4s %4s %-7s %10.4f %8.2f %8.2f %8.2f %8.2f "
        "%8.2f %4s\n",
        (t->run_id % 1000000 + 1000000) % 1000000, t->object_id, t->trial_index, kind_name(t->kind),
        comp, outcome_name(t->outcome), 1e3 * t->target_offset_m, 1e3 * t->released_position_m[0],
        1e3 * t->released_position_m[1], 1e3 * t->released_position_m[2],
        quat_angle(t->released_orientation_wxyz) * 180.0 / CL_PI, t->rotation_rad * 180.0 / CL_PI,
        !edge           ? "-"
        : !known        ? "?"
        : t->flat_patch ? "yes"
                        : "no");
  }
  fflush(stdout);
}

static void on_estimate(const lcm_recv_buf_t *rbuf, const char *channel, const void *msg,
                        void *user) {
  (void)rbuf;
  (void)channel;
  watch_t *w = user;
  const comlearn_com_estimate_t *e = msg;
  ++w->estimates;
  if (w->json) {
    printf("{\"type\": \"estimate\", \"run_id\": %" PRId64 ", ", e->run_id);
    json_str("object", e->object_id);
    json_str("policy", e->policy);
    printf("\"resolution_m\": ");
    cli_json_number(stdout, e->resolution_m);
    printf(", ");
    json_vec("com_m", e->com_estimated_m, 3);
    json_vec("halfwidth_m", e->halfwidth_m, 3);
    json_bools("found", e->found, 3);
    printf("\"trials\": %" PRId32 ", \"done\": %s}\n", e->trials, e->done ? "true" : "false");
  } else {
    table_header(w, e->run_id, e->object_id, e->policy);
    printf("%s estimate after %" PRId32 " trials (mm):", e->done ? "final" : "running", e->trials);
    for (int k = 0; k < 3; ++k) {
      if (e->found[k])
        printf("  %c %.4f +- %.4f", "xyz"[k], 1e3 * e -> com_estimated_m[k],
               1e3 * e -> halfwidth_m[k]);
      else
        printf("  %c %s", "xyz"[k], e -> done ? "N/A" : "searching");
    }
    printf("\n");
  }
  fflush(stdout);
  if (e->done) w->done_seen = 1;
}

static void on_reject(const lcm_recv_buf_t *rbuf, const char *channel, comlearn_msg_status_t reason,
                      void *user) {
  (void)user;
  LOG_D("%s: undecodable buffer of %u bytes (%s)", channel, rbuf->data_size,
        comlearn_msg_status_str(reason));
}

/* Options into *url, *timeout_s and w (defaults as usage() says). Returns -1 to go on, else the
 * exit status (0 after --help, EXIT_USAGE). */
static int parse_args(int argc, char **argv, const char **url, double *timeout_s, watch_t *w) {
  static const struct option opts[] = {
      {"lcm-url", required_argument, NULL, 'u'}, {"channel-prefix", required_argument, NULL, 'c'},
      {"once", no_argument, NULL, 'o'},          {"timeout-s", required_argument, NULL, 't'},
      {"json", no_argument, NULL, 'j'},          {"verbose", no_argument, NULL, 'v'},
      {"quiet", no_argument, NULL, 'q'},         {"help", no_argument, NULL, 'h'},
      {"version", no_argument, NULL, 'V'},       {NULL, 0, NULL, 0}};
  int c;
  optind = 1;
  opterr = 0;
  while ((c = getopt_long(argc, argv, "vqhV", opts, NULL)) != -1) {
    switch (c) {
      case 'u':
        if (!optarg[0]) {
          LOG_E("--lcm-url: empty URL");
          return EXIT_USAGE;
        }
        *url = optarg;
        break;
      case 'c':
        if (comlearn_msg_channels(optarg, &w->ch) != COMLEARN_MSG_OK) {
          LOG_E("--channel-prefix: need at most %d of A-Z a-z 0-9 _, got '%s'",
                COMLEARN_MSG_CHANNEL_PREFIX_MAX, optarg);
          return EXIT_USAGE;
        }
        break;
      case 'o': w->once = 1; break;
      case 't': {
        char *end;
        errno = 0;
        double t = strtod(optarg, &end);
        if (end == optarg || *end != '\0' || errno != 0 || !isfinite(t) || t < 0 || t > 1e6) {
          LOG_E("--timeout-s: '%s' is not a number of seconds in [0, 1e6]", optarg);
          return EXIT_USAGE;
        }
        *timeout_s = t;
        break;
      }
      case 'j': w->json = 1; break;
      case 'v': cli_log_set_level(CLI_LOG_DEBUG); break;
      case 'q': cli_log_set_level(CLI_LOG_ERROR); break;
      case 'h': usage(stdout); return EXIT_SUCCESS;
      case 'V': cli_version_print(stdout, "comlearn"); return EXIT_SUCCESS;
      default: cli_getopt_complain("comlearn watch", "vqhV", opts, argv); return EXIT_USAGE;
    }
  }
  if (optind != argc) {
    LOG_E("watch takes no arguments ('%s')", argv[optind]);
    usage(stderr);
    return EXIT_USAGE;
  }
  return -1;
}

/* COM_TRIAL and COM_ESTIMATE into w, rejects counted in stats, no record dropped. Returns 0, or
 * EXIT_FAILURE (logged; nothing left subscribed). */
static int watch_subscribe(lcm_t *lcm, const char *url, watch_t *w, comlearn_msg_stats_t *stats,
                           comlearn_msg_subscription_t **ts, comlearn_msg_subscription_t **es) {
  comlearn_msg_sub_config_t tc = {.type = comlearn_com_trial_t_get_type_info(),
                                  .on_message = on_trial,
                                  .on_reject = on_reject,
                                  .user = w,
                                  .stats = stats};
  comlearn_msg_sub_config_t ec = {.type = comlearn_com_estimate_t_get_type_info(),
                                  .on_message = on_estimate,
                                  .on_reject = on_reject,
                                  .user = w,
                                  .stats = stats};
  *ts = NULL;
  *es = NULL;
  comlearn_msg_status_t s1 = comlearn_msg_subscribe(lcm, w->ch.com_trial, &tc, ts);
  comlearn_msg_status_t s2 =
      s1 == COMLEARN_MSG_OK ? comlearn_msg_subscribe(lcm, w->ch.com_estimate, &ec, es) : s1;
  if (s1 != COMLEARN_MSG_OK || s2 != COMLEARN_MSG_OK) {
    LOG_E("subscribing on %s: %s", url, comlearn_msg_status_str(s1 != COMLEARN_MSG_OK ? s1 : s2));
    comlearn_msg_unsubscribe(lcm, *ts);
    comlearn_msg_unsubscribe(lcm, *es);
    return EXIT_FAILURE;
  }
  /* a replay may be fast: never drop a record because the terminal is slow */
  comlearn_msg_subscription_set_queue_capacity(*ts, 0);
  comlearn_msg_subscription_set_queue_capacity(*es, 0);
  return 0;
}

/* Handle messages until SIGINT / SIGTERM, the final estimate (--once) or the timeout (0: none).
 * w is filled in by the callbacks. Returns an exit status (EXIT_FAILURE: --once timed out, or LCM
 * failed). */
static int watch_loop(lcm_t *lcm, const char *url, double timeout_s, watch_t *w) {
  cli_stop_install();

  /* Tests and scripts wait for this line before they start publishing. */
  LOG_I("listening on %s for %s and %s", url, w->ch.com_trial, w->ch.com_estimate);
  const double t0 = cli_time_now_s();
  int rc = EXIT_SUCCESS;
  while (!cli_stop_requested() && !(w->once && w->done_seen)) {
    if (timeout_s > 0) {
      const double left = timeout_s - (cli_time_now_s() - t0);
      if (left <= 0) {
        if (w->once) {
          LOG_E("no final COM_ESTIMATE on %s within %g s", url, timeout_s);
          rc = EXIT_FAILURE;
        }
        break;
      }
    }
    /* bounded: SIGINT and the timeout are seen within 100 ms */
    if (lcm_handle_timeout(lcm, 100) < 0 && !cli_stop_requested()) {
      LOG_E("lcm_handle_timeout failed on %s", url);
      rc = EXIT_FAILURE;
      break;
    }
  }
  cli_stop_restore();
  return rc;
}

int cmd_watch(int argc, char **argv) {
  const char *url = COMLEARN_MSG_LCM_URL_DEFAULT;
  double timeout_s = 0.0;
  watch_t w;
  memset(&w, 0, sizeof w);
  (void)comlearn_msg_channels(NULL, &w.ch);
  const int prc = parse_args(argc, argv, &url, &timeout_s, &w);
  if (prc >= 0) return prc;

  char buffered[1024]; /* with comlearn's receive buffer (cli_net.h) */
  if (cli_lcm_url_buffered(url, buffered, sizeof buffered) == 0) url = buffered;
  lcm_t *lcm = lcm_create(url);
  if (!lcm) {
    LOG_E(
        "cannot open LCM on %s (udpm needs a multicast route: `ip route add 224.0.0.0/4 dev "
        "lo` as root)",
        url);
    return EXIT_FAILURE;
  }
  comlearn_msg_stats_t stats = {0};
  comlearn_msg_subscription_t *ts, *es;
  if (watch_subscribe(lcm, url, &w, &stats, &ts, &es) != 0) {
    lcm_destroy(lcm);
    return EXIT_FAILURE;
  }
  cli_lcm_buffer_check(url); /* LCM opens its receive socket on the first subscription */
  const int rc = watch_loop(lcm, url, timeout_s, &w);
  LOG_I("%" PRIu64 " trials, %" PRIu64 " estimates, %" PRIu64 " undecodable buffers", w.trials,
        w.estimates, comlearn_msg_stats_rejected(&stats));
  comlearn_msg_unsubscribe(lcm, ts);
  comlearn_msg_unsubscribe(lcm, es);
  lcm_destroy(lcm);
  return rc;
}
