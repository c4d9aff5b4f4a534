/* comlearn-sim: the YuMi controller and world stand-in on LCM (docs/sim.md). */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <getopt.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <lcm/lcm.h>

#include "comlearn/cli_args.h"
#include "comlearn/cli_log.h"
#include "comlearn/cli_net.h"
#include "comlearn/cli_paths.h"
#include "comlearn/cli_stop.h"
#include "comlearn/math3d.h"
#include "comlearn/msg.h"
#include "sim.h"

typedef struct {
  const char *lcm_url;
  int realtime;
  uint64_t seed;
  double placement_noise_mm, pose_noise_mm, drop_rate;
  const char *prefix;
  const char *yumi_urdf;
  const char *object_dirs[SIM_OBJECT_DIRS_MAX];
  size_t object_dir_count;
  double workspace_margin_mm;
} options_t;

static void usage(FILE *f) {
  fprintf(
      f,
      "usage: comlearn-sim [OPTIONS]\n"
      "\n"
      "Stand-in for the YuMi controller and the world: subscribes YUMI_COMMAND and SIM_CONTROL,\n"
      "publishes YUMI_STATUS and OBJECT_STATE every 4 ms of the simulated clock (docs/sim.md).\n"
      "Runs until SIGINT or SIGTERM, then exits 0.\n"
      "\n"
      "  --lcm-url URL             LCM URL (default: %s)\n"
      "  --realtime                pace the simulated clock to wall-clock time (default: off:\n"
      "                            motions and trials run as fast as possible, idle time at\n"
      "                            wall-clock speed)\n"
      "  --seed N                  seed of the placement / pose noise and of --drop-rate\n"
      "                            (default: 1)\n"
      "  --placement-noise-mm S    std. dev. of a horizontal offset of each release [mm], 0..100\n"
      "                            (default: 0)\n"
      "  --pose-noise-mm S         std. dev. of the perceived settled position [mm], 0..100\n"
      "                            (default: 0)\n"
      "  --drop-rate P             fraction of incoming and outgoing messages dropped, 0..1\n"
      "                            (default: 0)\n"
      "  --channel-prefix P        prefix of every channel name, e.g. R2_ for R2_YUMI_COMMAND:\n"
      "                            one robot among many on a URL; at most 32 of A-Z a-z 0-9 _\n"
      "                            (default: none)\n"
      "  --yumi-urdf PATH          YuMi model (default: %s)\n"
      "  --object-dir DIR          a folder SIM_CONTROL LOAD may read URDFs and meshes from,\n"
      "                            with everything below it; repeat for more, at most %d\n"
      "                            (default: the bundled assets, %s, and the current folder)\n"
      "  --workspace-margin-mm M   the arm's tool stays in the box over B grown by M mm on every\n"
      "                            side, from 50 mm under B to 600 mm over it, 0..10000\n"
      "                            (default: %.0f)\n"
      "  -v, --verbose             log every command: refused (why) or accepted (when)\n"
      "  -q, --quiet               errors only (default: off)\n"
      "  -h, --help                this help\n"
      "  -V, --version             print the version\n"
      "\n"
      "Exit codes: 0 stopped by a signal, 1 runtime failure, 2 bad usage.\n",
      COMLEARN_MSG_LCM_URL_DEFAULT, cli_paths_yumi_urdf(), SIM_OBJECT_DIRS_MAX,
      cli_paths_assets_dir(), 1e3 * SIM_WORKSPACE_MARGIN_DEFAULT_M);
}

static int parse_double(const char *s, double lo, double hi, double *out) {
  char *end;
  errno = 0;
  double v = strtod(s, &end);
  if (errno != 0 || end == s || *end != '\0' || !isfinite(v) || v < lo || v > hi) return -1;
  *out = v;
  return 0;
}

static int parse_options(int argc, char **argv, options_t *o) {
  static const struct option longopts[] = {{"lcm-url", required_argument, NULL, 'u'},
                                           {"realtime", no_argument, NULL, 'r'},
                                           {"seed", required_argument, NULL, 's'},
                                           {"placement-noise-mm", required_argument, NULL, 'P'},
                                           {"pose-noise-mm", required_argument, NULL, 'N'},
                                           {"drop-rate", required_argument, NULL, 'd'},
                                           {"channel-prefix", required_argument, NULL, 'c'},
                                           {"yumi-urdf", required_argument, NULL, 'y'},
                                           {"object-dir", required_argument, NULL, 'o'},
                                           {"workspace-margin-mm", required_argument, NULL, 'w'},
                                           {"verbose", no_argument, NULL, 'v'},
                                           {"quiet", no_argument, NULL, 'q'},
                                           {"help", no_argument, NULL, 'h'},
                                           {"version", no_argument, NULL, 'V'},
                                           {NULL, 0, NULL, 0}};
  int c;
  opterr = 0;
  while ((c = getopt_long(argc, argv, "vqhV", longopts, NULL)) != -1) {
    switch (c) {
      case 'u': o->lcm_url = optarg; break;
      case 'r': o->realtime = 1; break;
      case 's': {
        char *end;
        errno = 0;
        unsigned long long v = strtoull(optarg, &end, 0);
        if (errno != 0 || end == optarg || *end != '\0' || optarg[0] == '-') {
          LOG_E("--seed: not an unsigned integer: '%s'", optarg);
          return 2;
        }
        o->seed = (uint64_t)v;
        break;
      }
      case 'P':
      case 'N':
        if (parse_double(optarg, 0.0, 100.0,
                         c == 'P' ? &o->placement_noise_mm : &o->pose_noise_mm)) {
          LOG_E("--%s: need a number in [0, 100], got '%s'",
                c == 'P' ? "placement-noise-mm" : "pose-noise-mm", optarg);
          return 2;
        }
        break;
      case 'd':
        if (parse_double(optarg, 0.0, 1.0, &o->drop_rate)) {
          LOG_E("--drop-rate: need a number in [0, 1], got '%s'", optarg);
          return 2;
        }
        break;
      case 'c':
        if (!comlearn_msg_channel_prefix_ok(optarg)) {
          LOG_E("--channel-prefix: need at most %d of A-Z a-z 0-9 _, got '%s'",
                COMLEARN_MSG_CHANNEL_PREFIX_MAX, optarg);
          return 2;
        }
        o->prefix = optarg;
        break;
      case 'y': o->yumi_urdf = optarg; break;
      case 'w':
        if (parse_double(optarg, 0.0, 10000.0, &o->workspace_margin_mm)) {
          LOG_E("--workspace-margin-mm: need a number in [0, 10000], got '%s'", optarg);
          return 2;
        }
        break;
      case 'o':
        if (o->object_dir_count >= SIM_OBJECT_DIRS_MAX) {
          LOG_E("--object-dir: at most %d folders", SIM_OBJECT_DIRS_MAX);
          return 2;
        }
        o->object_dirs[o->object_dir_count++] = optarg;
        break;
      case 'v': cli_log_set_level(CLI_LOG_DEBUG); break;
      case 'q': cli_log_set_level(CLI_LOG_ERROR); break;
      case 'h': usage(stdout); return -1;
      case 'V': cli_version_print(stdout, "comlearn-sim"); return -1;
      default: cli_getopt_complain("comlearn-sim", "vqhV", longopts, argv); return 2;
    }
  }
  return cli_args_none_left("comlearn-sim", argc, argv);
}

/* ---- the LCM shell -------------------------------------------------------------------------- */

typedef struct {
  lcm_t *lcm;
  sim_t sim;
  double drop_rate;
  uint64_t drop_rng;
  comlearn_msg_stats_t stats;
  comlearn_msg_channels_t ch;   /* with --channel-prefix */
  int realtime;                 /* --realtime: the clock paced to the wall clock throughout */
  int publish_now;              /* PUB_* to publish before the next tick */
  int64_t last_publish_wall_us; /* when the last status went out (monotonic wall clock) */
  uint64_t dropped_in, dropped_out;
} daemon_t;

/* What publish() sends: a mask. */
enum { PUB_STATUS = 1, PUB_OBJECT = 2, PUB_BOTH = 3 };

static int drop(daemon_t *d) {
  if (d->drop_rate <= 0.0) return 0;
  return cl_rng_uniform(&d->drop_rng) < d->drop_rate;
}

/* Raw handlers: the drop dice first (a dropped message never arrived), then comlearn_msg_decode's
 * schema check, which counts every buffer that does not decode. */
/* One incoming buffer: 1 when it arrived (not dropped) and decoded into msg, else 0 (counted). */
static int receive(daemon_t *d, const lcm_recv_buf_t *rbuf, const char *channel,
                   const lcm_type_info_t *type, void *msg) {
  if (drop(d)) {
    d->dropped_in++;
    return 0;
  }
  comlearn_msg_status_t st = comlearn_msg_decode(type, rbuf->data, rbuf->data_size, msg, &d->stats);
  if (st != COMLEARN_MSG_OK) {
    sim_undecodable(&d->sim, channel, comlearn_msg_status_str(st));
    LOG_D("undecodable buffer on %s (%u bytes): %s", channel, rbuf->data_size,
          comlearn_msg_status_str(st));
    return 0;
  }
  sim_received(&d->sim);
  return 1;
}

static void on_command_raw(const lcm_recv_buf_t *rbuf, const char *channel, void *user) {
  daemon_t *d = user;
  comlearn_yumi_command_t cmd;
  if (!receive(d, rbuf, channel, comlearn_yumi_command_t_get_type_info(), &cmd)) return;
  int32_t r = sim_command(&d->sim, &cmd);
  if (r != 0)
    LOG_D("%s", d->sim.error_text);
  else
    LOG_D("command seq %lld accepted at sim utime %lld", (long long)cmd.seq,
          (long long)d->sim.utime);
  comlearn_yumi_command_t_decode_cleanup(&cmd);
  /* The status after a command: at once when refused (its error) or already in position. An
   * accepted motion as fast as possible lasts a burst of ticks: the status at its end (or the
   * next periodic one, at most SIM_STATUS_PERIOD_US of wall time later) says both accepted and
   * in position, one message instead of two (docs/sim.md). Paced, at once. */
  if (r != 0 || d->realtime || !sim_busy(&d->sim)) d->publish_now |= PUB_BOTH;
}

static void on_control_raw(const lcm_recv_buf_t *rbuf, const char *channel, void *user) {
  daemon_t *d = user;
  comlearn_sim_control_t sc;
  if (!receive(d, rbuf, channel, comlearn_sim_control_t_get_type_info(), &sc)) return;
  int32_t r = sim_control(&d->sim, &sc);
  cli_log_msg(r == 0 ? CLI_LOG_INFO : CLI_LOG_WARN,
              "SIM_CONTROL seq %lld action %d object '%s': result %d", (long long)sc.seq,
              (int)sc.action, sc.object_id, (int)r);
  if (r == COMLEARN_OBJECT_STATE_T_SIM_CONTROL_ERR_LOAD) LOG_W("%s", d->sim.error_text);
  comlearn_sim_control_t_decode_cleanup(&sc);
  d->publish_now |= PUB_BOTH;
}

static int64_t wall_us(void);

/* YUMI_STATUS and / or OBJECT_STATE now (what: PUB_*). */
static void publish(daemon_t *d, int what) {
  if (what & PUB_STATUS) {
    d->last_publish_wall_us = wall_us();
    comlearn_yumi_status_t st;
    sim_status_fill(&d->sim, &st);
    if (drop(d))
      d->dropped_out++;
    else if (comlearn_yumi_status_t_publish(d->lcm, d->ch.yumi_status, &st) != 0)
      LOG_W("publish %s failed", d->ch.yumi_status);
  }
  if (!(what & PUB_OBJECT)) return;
  comlearn_object_state_t os;
  sim_object_fill(&d->sim, &os);
  if (drop(d))
    d->dropped_out++;
  else if (comlearn_object_state_t_publish(d->lcm, d->ch.object_state, &os) != 0)
    LOG_W("publish %s failed", d->ch.object_state);
}

static int64_t wall_us(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (int64_t)ts.tv_sec * 1000000 + ts.tv_nsec / 1000;
}

/* Handle what LCM has queued, without waiting (bounded: a flood cannot starve the clock). */
static int drain(daemon_t *d) {
  for (int i = 0; i < 1000; i++) {
    int r = lcm_handle_timeout(d->lcm, 0);
    if (r == 0) return 0;
    if (r < 0) return cli_stop_requested() ? 0 : -1;
  }
  return 0;
}

static int run(daemon_t *d) {
  const int realtime = d->realtime;
  /* Pacing anchor: when paced, sim time = anchor_sim + (wall - anchor_wall). Re-anchored when a
   * fast burst ends, so the clock continues from where the burst left it. */
  int64_t anchor_wall = wall_us(), anchor_sim = d->sim.utime;
  int paced_prev = 1;
  int failures = 0;
  publish(d, PUB_BOTH);
  while (!cli_stop_requested()) {
    const int paced = realtime || !sim_busy(&d->sim);
    if (paced && !paced_prev) {
      anchor_wall = wall_us();
      anchor_sim = d->sim.utime;
    }
    paced_prev = paced;
    int rc;
    if (paced) {
      const int64_t due = anchor_wall + (d->sim.utime + SIM_DT_US - anchor_sim);
      const int64_t wait = due - wall_us();
      rc = lcm_handle_timeout(d->lcm, wait > 0 ? (int)((wait + 999) / 1000) : 0);
      if (rc >= 0) rc = drain(d) < 0 ? -1 : rc;
    } else {
      rc = drain(d);
    }
    if (rc < 0 && !cli_stop_requested()) {
      if (++failures > 100) {
        LOG_E("lcm_handle_timeout keeps failing; giving up");
        return 1;
      }
    } else {
      failures = 0;
    }
    if (d->publish_now) {
      publish(d, d->publish_now);
      d->publish_now = 0;
    }
    /* Advance the clock: when fast, up to SIM_FAST_BATCH ticks before LCM is read again (one
     * poll per tick cost more than the tick), fewer when a step makes an event; when paced,
     * every tick that is due (at most 100 at once, after which the anchor moves: a stalled host
     * does not cause a burst of catch-up). */
    int ticks = 0;
    while (!cli_stop_requested()) {
      const int now_paced = realtime || !sim_busy(&d->sim);
      if (now_paced && d->sim.utime + SIM_DT_US > anchor_sim + (wall_us() - anchor_wall)) break;
      if (!now_paced && ticks >= SIM_FAST_BATCH) break;
      const int event = sim_step(&d->sim);
      /* Paced, the period is of wall time too. Fast, a status at most every period of wall time
       * (a motion is a burst of ticks), and at once what a step changed that a client waits
       * for: the arms' events both messages, a trial's end the object's. */
      if (d->sim.utime % SIM_STATUS_PERIOD_US == 0 &&
          (now_paced || wall_us() - d->last_publish_wall_us >= SIM_STATUS_PERIOD_US))
        publish(d, PUB_BOTH);
      else if (event)
        publish(d, event & SIM_EVENT_ARM ? PUB_BOTH : PUB_OBJECT);
      ++ticks;
      if (event && !now_paced) break; /* let the client's answer in at once */
      if (ticks >= 100) {
        anchor_wall = wall_us();
        anchor_sim = d->sim.utime;
        break;
      }
    }
  }
  return 0;
}

int main(int argc, char **argv) {
  cli_log_init("comlearn-sim");
  options_t o = {.lcm_url = COMLEARN_MSG_LCM_URL_DEFAULT,
                 .seed = 1,
                 .prefix = "",
                 .yumi_urdf = cli_paths_yumi_urdf(),
                 .workspace_margin_mm = 1e3 * SIM_WORKSPACE_MARGIN_DEFAULT_M};
  int prc = parse_options(argc, argv, &o);
  if (prc < 0) return 0;
  if (prc > 0) return prc;

  cli_stop_install();

  static daemon_t d;
  d.drop_rate = o.drop_rate;
  d.realtime = o.realtime;
  d.drop_rng = o.seed ^ 0xD5A61266F0C9392Cull;
  (void)comlearn_msg_channels(o.prefix, &d.ch); /* checked by --channel-prefix */

  sim_config_t cfg = {.yumi_urdf = o.yumi_urdf,
                      .seed = o.seed,
                      .placement_noise_m = o.placement_noise_mm * 1e-3,
                      .pose_noise_m = o.pose_noise_mm * 1e-3};
  if (o.object_dir_count == 0) { /* the bundled assets and the current folder */
    o.object_dirs[o.object_dir_count++] = cli_paths_assets_dir();
    o.object_dirs[o.object_dir_count++] = ".";
  }
  memcpy(cfg.object_dirs, o.object_dirs, sizeof cfg.object_dirs);
  cfg.object_dir_count = o.object_dir_count;
  cfg.workspace_margin_m = 1e-3 * o.workspace_margin_mm;
  char err[512];
  if (sim_init(&d.sim, &cfg, err, sizeof err) != 0) {
    LOG_E("%s", err);
    return 1;
  }
  char url[1024]; /* with comlearn's receive buffer (cli_net.h) */
  if (cli_lcm_url_buffered(o.lcm_url, url, sizeof url) != 0)
    snprintf(url, sizeof url, "%s", o.lcm_url);
  d.lcm = lcm_create(url);
  if (d.lcm == NULL) {
    LOG_E(
        "cannot open LCM at '%s' (udpm needs a multicast route: "
        "ip route add 224.0.0.0/4 dev lo, as root; scripts/setup.sh does it)",
        o.lcm_url);
    sim_fini(&d.sim);
    return 1;
  }
  cli_socket_set_t before;
  cli_socket_set_now(&before);
  lcm_subscription_t *s1 = lcm_subscribe(d.lcm, d.ch.yumi_command, on_command_raw, &d);
  lcm_subscription_t *s2 = lcm_subscribe(d.lcm, d.ch.sim_control, on_control_raw, &d);
  if (s1 == NULL || s2 == NULL) {
    LOG_E("lcm_subscribe failed");
    lcm_destroy(d.lcm);
    sim_fini(&d.sim);
    return 1;
  }
  /* LCM opens its receive socket on the first subscription: check its buffer, and let the
   * kernel drop what the sim does not read, its own statuses first (cli_net.h) */
  const char *heard[] = {d.ch.yumi_command, d.ch.sim_control};
  const int filtered = cli_lcm_receive_setup(url, &before, heard, 2);
  uint64_t overflows_start = 0;
  const int overflows_known = cli_udp_rcvbuf_errors(&overflows_start) == 0;
  /* Latest command only: a backlog of old commands is worth nothing. */
  lcm_subscription_set_queue_capacity(s1, 100);
  LOG_I("running on %s (%s), channels %s %s -> %s %s", url,
        o.realtime ? "realtime" : "as fast as possible", d.ch.yumi_command, d.ch.sim_control,
        d.ch.yumi_status, d.ch.object_state);
  int rc = run(&d);
  LOG_I(
      "stopping at sim time %.3f s: %lld received, %lld rejected, %lld undecodable, "
      "%llu dropped in, %llu dropped out",
      (double)d.sim.utime * 1e-6, (long long)d.sim.n_received, (long long)d.sim.n_rejected,
      (long long)d.sim.n_undecodable, (unsigned long long)d.dropped_in,
      (unsigned long long)d.dropped_out);
  char refusals[512];
  sim_refusals_str(&d.sim, refusals, sizeof refusals);
  LOG_I("%s", refusals);
  /* datagrams that never reached LCM (cli_net.h): on its socket, filtered on purpose or lost
   * to a full buffer; on the host, lost to a full buffer */
  uint64_t socket_drops = 0, overflows_end = 0;
  if (cli_udp_drops(&socket_drops) == 0)
    LOG_I("%llu datagrams dropped by the kernel on its sockets (%s)",
          (unsigned long long)socket_drops,
          filtered > 0 ? "filtered: channels it does not read; or a full buffer" : "a full buffer");
  if (overflows_known && cli_udp_rcvbuf_errors(&overflows_end) == 0)
    LOG_I("%llu datagrams lost to a full receive buffer on this host while it ran (RcvbufErrors)",
          (unsigned long long)(overflows_end - overflows_start));
  lcm_unsubscribe(d.lcm, s1);
  lcm_unsubscribe(d.lcm, s2);
  lcm_destroy(d.lcm);
  sim_fini(&d.sim);
  return rc;
}
