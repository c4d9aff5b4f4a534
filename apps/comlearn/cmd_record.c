/*
 * cmd_record.c - `comlearn record FILE`: an LCM recorder that loses nothing its socket received.
 *
 * It writes the log format of lcm-logger (lcm_eventlog: lcm-logplayer, lcm-spy's log view and
 * comlearn logcheck read it). Debian's lcm-logger (LCM 1.3.1) keeps at most 30 received
 * messages waiting for its main thread and drops what arrives beyond; with two robots on one
 * URL and the machine busy, a catch-all lcm-logger lost a few trial records in every main job
 * (docs/replay.md). Here the subscription's queue has no limit, the handler writes each message
 * to the file's stdio buffer at once, and the file is flushed every --flush-ms.
 */
#define _GNU_SOURCE
#include "cmd_record.h"

#include <errno.h>
#include <getopt.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <lcm/eventlog.h>
#include <lcm/lcm.h>

#include "comlearn/cli_args.h"
#include "comlearn/cli_log.h"
#include "comlearn/cli_net.h"
#include "comlearn/cli_stop.h"
#include "comlearn/cli_time.h"
#include "comlearn/msg.h"

enum { EXIT_USAGE = 2, DRAIN_MAX = 1000000 };

static void usage(FILE *out) {
  fprintf(out,
          "usage: comlearn record FILE [options]\n"
          "\n"
          "Records the LCM traffic on a URL into FILE, in the log format of lcm-logger (for\n"
          "lcm-logplayer, lcm-spy and comlearn logcheck), until SIGINT or SIGTERM. Unlike\n"
          "Debian's lcm-logger, which drops what arrives while 30 received messages wait for\n"
          "it, it keeps every message its socket received (docs/replay.md).\n"
          "\n"
          "options:\n"
          "  --lcm-url URL      LCM URL to record (default: " COMLEARN_MSG_LCM_URL_DEFAULT
          ", with\n"
          "                     comlearn's receive buffer)\n"
          "  -c, --channel RE   channels to record, an LCM regular expression (default: .*)\n"
          "  -f, --force        overwrite FILE when it exists (default: refuse)\n"
          "  --flush-ms MS      write what is buffered to FILE every MS ms of wall time,\n"
          "                     1..60000 (default: 100)\n"
          "  -v, --verbose      log debug messages on stderr (default: info)\n"
          "  -q, --quiet        log errors only (default: info)\n"
          "  -h, --help         show this help\n"
          "  -V, --version      print the version\n"
          "\n"
          "exit status: 0 stopped by a signal with everything written, 1 a write or LCM\n"
          "failure, 2 usage or bad input\n");
}

typedef struct {
  lcm_eventlog_t *log;
  uint64_t events, bytes;
  int failed; /* a write failed (errno kept in err) */
  int err;
} recorder_t;

static void on_message(const lcm_recv_buf_t *rbuf, const char *channel, void *user) {
  recorder_t *r = user;
  if (r->failed) return;
  lcm_eventlog_event_t ev;
  memset(&ev, 0, sizeof ev);
  ev.timestamp = rbuf->recv_utime;
  ev.channellen = (int32_t)strlen(channel);
  ev.channel = (char *)channel;
  ev.datalen = (int32_t)rbuf->data_size;
  ev.data = rbuf->data;
  if (lcm_eventlog_write_event(r->log, &ev) != 0) {
    r->failed = 1;
    r->err = errno;
    return;
  }
  r->events++;
  r->bytes += rbuf->data_size;
}

static int parse_args(int argc, char **argv, const char **url, const char **regex, int *force,
                      int *flush_ms, const char **path) {
  static const struct option opts[] = {{"lcm-url", required_argument, NULL, 'u'},
                                       {"channel", required_argument, NULL, 'c'},
                                       {"force", no_argument, NULL, 'f'},
                                       {"flush-ms", required_argument, NULL, 'F'},
                                       {"verbose", no_argument, NULL, 'v'},
                                       {"quiet", no_argument, NULL, 'q'},
                                       {"help", no_argument, NULL, 'h'},
                                       {"version", no_argument, NULL, 'V'},
                                       {NULL, 0, NULL, 0}};
  int o;
  opterr = 0;
  optind = 1;
  while ((o = getopt_long(argc, argv, "c:fvqhV", opts, NULL)) != -1) {
    switch (o) {
      case 'u': *url = optarg; break;
      case 'c': *regex = optarg; break;
      case 'f': *force = 1; break;
      case 'F': {
        char *end = NULL;
        errno = 0;
        const long v = strtol(optarg, &end, 10);
        if (errno != 0 || end == optarg || *end != '\0' || v < 1 || v > 60000) {
          LOG_E("record: --flush-ms: need a whole number in [1, 60000], got '%s'", optarg);
          return EXIT_USAGE;
        }
        *flush_ms = (int)v;
        break;
      }
      case 'v': cli_log_set_level(CLI_LOG_DEBUG); break;
      case 'q': cli_log_set_level(CLI_LOG_ERROR); break;
      case 'h': usage(stdout); return 0;
      case 'V': cli_version_print(stdout, "comlearn"); return 0;
      default: cli_getopt_complain("comlearn record", "c:fvqhV", opts, argv); return EXIT_USAGE;
    }
  }
  if (optind != argc - 1) {
    LOG_E("record: need exactly one FILE");
    usage(stderr);
    return EXIT_USAGE;
  }
  *path = argv[optind];
  if ((*regex)[0] == '\0') {
    LOG_E("record: --channel: empty");
    return EXIT_USAGE;
  }
  return -1;
}

int cmd_record(int argc, char **argv) {
  const char *url_arg = COMLEARN_MSG_LCM_URL_DEFAULT, *regex = ".*", *path = NULL;
  int force = 0, flush_ms = 100;
  const int prc = parse_args(argc, argv, &url_arg, &regex, &force, &flush_ms, &path);
  if (prc >= 0) return prc;
  if (!force && access(path, F_OK) == 0) {
    LOG_E("record: %s exists (--force overwrites it)", path);
    return EXIT_USAGE;
  }
  char url[1024];
  if (cli_lcm_url_buffered(url_arg, url, sizeof url) != 0) snprintf(url, sizeof url, "%s", url_arg);
  recorder_t r = {0};
  r.log = lcm_eventlog_create(path, "w");
  if (!r.log) {
    LOG_E("record: %s: %s", path, strerror(errno));
    return EXIT_USAGE;
  }
  lcm_t *lcm = lcm_create(url);
  if (!lcm) {
    LOG_E("record: lcm_create(%s) failed (udpm needs a multicast route: scripts/setup.sh)", url);
    lcm_eventlog_destroy(r.log);
    return 1;
  }
  lcm_subscription_t *sub = lcm_subscribe(lcm, regex, on_message, &r);
  /* no limit on what waits for the handler: LCM drops nothing (its default keeps 30) */
  if (!sub || lcm_subscription_set_queue_capacity(sub, 0) != 0) {
    LOG_E("record: subscribing to '%s' on %s failed", regex, url);
    lcm_destroy(lcm);
    lcm_eventlog_destroy(r.log);
    return 1;
  }
  cli_lcm_buffer_check(url);
  uint64_t lost0 = 0, lost1 = 0;
  const int lost_known = cli_udp_rcvbuf_errors(&lost0) == 0;
  cli_stop_install(); /* SA_RESTART: a write blocked on a slow FILE goes on */
  LOG_I("recording '%s' on %s into %s", regex, url, path);
  int rc = 0;
  double next_flush = cli_time_now_s() + 1e-3 * flush_ms;
  while (!cli_stop_requested() && !r.failed) {
    if (lcm_handle_timeout(lcm, flush_ms < 100 ? flush_ms : 100) < 0 && !cli_stop_requested()) {
      LOG_E("record: lcm_handle_timeout failed on %s", url);
      rc = 1;
      break;
    }
    if (cli_time_now_s() >= next_flush) {
      if (fflush(r.log->f) != 0) {
        r.failed = 1;
        r.err = errno;
      }
      next_flush = cli_time_now_s() + 1e-3 * flush_ms;
    }
  }
  cli_stop_restore();
  /* what LCM's thread had already queued goes in too */
  for (int i = 0; i < DRAIN_MAX && !r.failed && lcm_handle_timeout(lcm, 0) > 0; ++i) {}
  lcm_unsubscribe(lcm, sub);
  lcm_destroy(lcm);
  if (!r.failed && (fflush(r.log->f) != 0 || ferror(r.log->f))) {
    r.failed = 1;
    r.err = errno;
  }
  lcm_eventlog_destroy(r.log);
  if (r.failed) {
    LOG_E("record: writing %s failed: %s", path, strerror(r.err));
    rc = 1;
  }
  if (lost_known && cli_udp_rcvbuf_errors(&lost1) == 0 && lost1 > lost0)
    LOG_W("record: %" PRIu64
          " datagrams were lost to full receive buffers on this host meanwhile "
          "(RcvbufErrors; any process's)",
          lost1 - lost0);
  LOG_I("record: %" PRIu64 " events, %" PRIu64 " bytes of messages in %s", r.events, r.bytes, path);
  return rc;
}
