/*
 * cmd_logcheck.c - `comlearn logcheck LOG...`: what an LCM log (lcm-logger's file) holds, per
 * channel, and whether it holds every trial record of every run it names. A run is a run_id of
 * COM_TRIAL / COM_ESTIMATE on any robot's channels (P + COM_TRIAL, comlearn/msg.h); its final
 * COM_ESTIMATE (done) gives its trial count n, and the log must hold the trial indices 0 .. n-1,
 * each once. Records are decoded with comlearn_msg_decode (counted when they do not decode).
 */
#define _GNU_SOURCE
#include "cmd_logcheck.h"

#include <getopt.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <lcm/eventlog.h>

#include "comlearn/cli_args.h"
#include "comlearn/cli_log.h"
#include "comlearn/comlearn_com_estimate_t.h"
#include "comlearn/comlearn_com_trial_t.h"
#include "comlearn/msg.h"

/* LCM's longest channel name is 63 bytes. */
enum { EXIT_USAGE = 2, CHANNELS_MAX = 256, CHANNEL_NAME_MAX = 63, TRIALS_MAX = 1 << 20 };

static void usage(FILE *out) {
  fprintf(out,
          "usage: comlearn logcheck LOG.lcmlog... [options]\n"
          "\n"
          "Reads LCM logs (lcm-logger's files), prints the events per channel, and checks that\n"
          "they hold every trial record of every run: for each run (run_id) with a final\n"
          "COM_ESTIMATE (done), its COM_TRIAL indices 0 .. trials - 1, each once, on any\n"
          "robot's channels (P + COM_TRIAL). The logs of one recording are checked together.\n"
          "\n"
          "options:\n"
          "  -v, --verbose      one line per run (default: the totals)\n"
          "  -q, --quiet        only the verdict line, and errors (default: channels too)\n"
          "  -h, --help         show this help\n"
          "  -V, --version      print the version\n"
          "\n"
          "exit status: 0 every run complete, 1 a record missing or repeated, a run without its\n"
          "final COM_ESTIMATE, or an undecodable record, 2 usage or an unreadable log\n");
}

typedef struct {
  char name[CHANNEL_NAME_MAX + 1];
  uint64_t events, bytes;
} channel_count_t;

typedef struct {
  int64_t run_id;
  char object[64];
  int64_t final_trials; /* of the final COM_ESTIMATE; -1: none seen */
  uint64_t records;     /* COM_TRIAL records, repeats included */
  uint64_t repeated;    /* an index seen before */
  unsigned char *seen;  /* per trial index < seen_cap (indices >= TRIALS_MAX: out of range) */
  size_t seen_cap;
} run_t;

typedef struct {
  channel_count_t ch[CHANNELS_MAX];
  size_t n_ch;
  uint64_t other_channels; /* events on channels beyond CHANNELS_MAX */
  run_t *runs;
  size_t n_runs, cap_runs;
  uint64_t events, undecodable, trials_out_of_range;
} logcheck_t;

/* The channel is NAME or P + NAME for a robot prefix P (comlearn_msg_channel_prefix_ok). */
static int is_record_channel(const char *channel, const char *name) {
  const size_t n = strlen(channel), k = strlen(name);
  if (n < k || strcmp(channel + n - k, name) != 0) return 0;
  char prefix[CHANNEL_NAME_MAX + 1];
  if (n - k >= sizeof prefix) return 0;
  memcpy(prefix, channel, n - k);
  prefix[n - k] = '\0';
  return comlearn_msg_channel_prefix_ok(prefix);
}

static void count_channel(logcheck_t *c, const char *name, size_t bytes) {
  for (size_t i = 0; i < c->n_ch; ++i)
    if (strcmp(c->ch[i].name, name) == 0) {
      c->ch[i].events++;
      c->ch[i].bytes += bytes;
      return;
    }
  if (c->n_ch == CHANNELS_MAX || strlen(name) >= sizeof c->ch[0].name) {
    c->other_channels++;
    return;
  }
  channel_count_t *e = &c->ch[c->n_ch++];
  snprintf(e->name, sizeof e->name, "%s", name);
  e->events = 1;
  e->bytes = bytes;
}

/* The run of run_id (created when new); NULL when out of memory. */
static run_t *run_of(logcheck_t *c, int64_t run_id, const char *object) {
  for (size_t i = 0; i < c->n_runs; ++i)
    if (c->runs[i].run_id == run_id) return &c->runs[i];
  if (c->n_runs == c->cap_runs) {
    const size_t cap = c->cap_runs ? 2 * c->cap_runs : 64;
    run_t *r = realloc(c->runs, cap * sizeof *r);
    if (!r) return NULL;
    c->runs = r;
    c->cap_runs = cap;
  }
  run_t *r = &c->runs[c->n_runs++];
  memset(r, 0, sizeof *r);
  r->run_id = run_id;
  r->final_trials = -1;
  snprintf(r->object, sizeof r->object, "%s", object ? object : "");
  return r;
}

/* Mark trial index i of run r seen. 0, or -1 when out of memory. */
static int mark_trial(logcheck_t *c, run_t *r, int32_t i) {
  r->records++;
  if (i < 0 || i >= TRIALS_MAX) {
    c->trials_out_of_range++;
    return 0;
  }
  if ((size_t)i >= r->seen_cap) {
    size_t cap = r->seen_cap ? r->seen_cap : 64;
    while (cap <= (size_t)i) cap *= 2;
    unsigned char *s = realloc(r->seen, cap);
    if (!s) return -1;
    memset(s + r->seen_cap, 0, cap - r->seen_cap);
    r->seen = s;
    r->seen_cap = cap;
  }
  if (r->seen[i]) r->repeated++;
  r->seen[i] = 1;
  return 0;
}

/* One event of a log. 0, or -1 when out of memory. */
static int on_event(logcheck_t *c, const lcm_eventlog_event_t *ev) {
  c->events++;
  if (ev->datalen < 0 || ev->channel == NULL) {
    c->undecodable++;
    return 0;
  }
  const size_t len = (size_t)ev->datalen;
  count_channel(c, ev->channel, len);
  if (is_record_channel(ev->channel, COMLEARN_MSG_CHANNEL_COM_TRIAL)) {
    comlearn_com_trial_t t;
    if (comlearn_msg_decode(comlearn_com_trial_t_get_type_info(), ev->data, len, &t, NULL) !=
        COMLEARN_MSG_OK) {
      c->undecodable++;
      return 0;
    }
    run_t *r = run_of(c, t.run_id, t.object_id);
    const int rc = r ? mark_trial(c, r, t.trial_index) : -1;
    comlearn_com_trial_t_decode_cleanup(&t);
    return rc;
  }
  if (is_record_channel(ev->channel, COMLEARN_MSG_CHANNEL_COM_ESTIMATE)) {
    comlearn_com_estimate_t e;
    if (comlearn_msg_decode(comlearn_com_estimate_t_get_type_info(), ev->data, len, &e, NULL) !=
        COMLEARN_MSG_OK) {
      c->undecodable++;
      return 0;
    }
    run_t *r = run_of(c, e.run_id, e.object_id);
    if (r && e.done) r->final_trials = e.trials;
    comlearn_com_estimate_t_decode_cleanup(&e);
    return r ? 0 : -1;
  }
  return 0;
}

/* Read one log into c. 0; -1 when it cannot be opened or a read failed midway (logged). */
static int read_log(logcheck_t *c, const char *path) {
  lcm_eventlog_t *log = lcm_eventlog_create(path, "r");
  if (!log) {
    LOG_E("%s: cannot be opened as an LCM log", path);
    return -1;
  }
  int rc = 0;
  const uint64_t before = c->events;
  for (lcm_eventlog_event_t *ev; rc == 0 && (ev = lcm_eventlog_read_next_event(log)) != NULL;) {
    if (on_event(c, ev) != 0) {
      LOG_E("out of memory");
      rc = -1;
    }
    lcm_eventlog_free_event(ev);
  }
  lcm_eventlog_destroy(log);
  if (rc == 0 && c->events == before) {
    LOG_E("%s: no LCM events (empty, or not an LCM log)", path);
    rc = -1;
  }
  return rc;
}

/* Missing indices of a run with a final estimate: those in 0 .. n-1 not seen. */
static uint64_t missing_of(const run_t *r) {
  uint64_t m = 0;
  for (int64_t i = 0; i < r->final_trials; ++i) m += (size_t)i >= r->seen_cap || !r->seen[i];
  return m;
}

static uint64_t beyond_of(const run_t *r) {
  uint64_t b = 0;
  for (size_t i = 0; i < r->seen_cap; ++i) b += r->seen[i] && (int64_t)i >= r->final_trials;
  return b;
}

static int cmp_channel(const void *a, const void *b) {
  return strcmp(((const channel_count_t *)a)->name, ((const channel_count_t *)b)->name);
}

int cmd_logcheck(int argc, char **argv) {
  static const struct option opts[] = {{"verbose", no_argument, NULL, 'v'},
                                       {"quiet", no_argument, NULL, 'q'},
                                       {"help", no_argument, NULL, 'h'},
                                       {"version", no_argument, NULL, 'V'},
                                       {NULL, 0, NULL, 0}};
  int verbose = 0, quiet = 0, o;
  opterr = 0;
  optind = 1;
  while ((o = getopt_long(argc, argv, "vqhV", opts, NULL)) != -1) {
    switch (o) {
      case 'v': verbose = 1; break;
      case 'q': quiet = 1; break;
      case 'h': usage(stdout); return 0;
      case 'V': cli_version_print(stdout, "comlearn"); return 0;
      default: cli_getopt_complain("comlearn logcheck", "vqhV", opts, argv); return EXIT_USAGE;
    }
  }
  if (optind >= argc) {
    LOG_E("logcheck: no LOG given");
    usage(stderr);
    return EXIT_USAGE;
  }
  logcheck_t *c = calloc(1, sizeof *c);
  if (!c) {
    LOG_E("out of memory");
    return 1;
  }
  int rc = 0;
  for (int i = optind; i < argc && rc == 0; ++i)
    if (read_log(c, argv[i]) != 0) rc = EXIT_USAGE;
  uint64_t expected = 0, missing = 0, repeated = 0, beyond = 0, no_final = 0;
  for (size_t i = 0; i < c->n_runs; ++i) {
    const run_t *r = &c->runs[i];
    repeated += r->repeated;
    if (r->final_trials < 0) {
      no_final++;
    } else {
      expected += (uint64_t)r->final_trials;
      missing += missing_of(r);
      beyond += beyond_of(r);
    }
  }
  if (rc == 0 && !quiet) {
    qsort(c->ch, c->n_ch, sizeof c->ch[0], cmp_channel);
    printf("%" PRIu64 " events in %d log%s\n", c->events, argc - optind,
           argc - optind == 1 ? "" : "s");
    printf("  %-32s %10s %12s\n", "channel", "events", "bytes");
    for (size_t i = 0; i < c->n_ch; ++i)
      printf("  %-32s %10" PRIu64 " %12" PRIu64 "\n", c->ch[i].name, c->ch[i].events,
             c->ch[i].bytes);
    if (c->other_channels)
      printf("  (%" PRIu64 " events on more than %d channels, not listed)\n", c->other_channels,
             CHANNELS_MAX);
  }
  if (rc == 0 && verbose)
    for (size_t i = 0; i < c->n_runs; ++i) {
      const run_t *r = &c->runs[i];
      if (r->final_trials < 0)
        printf("  run %" PRId64 " %s: %" PRIu64 " trial records, no final COM_ESTIMATE\n",
               r->run_id, r->object, r->records);
      else
        printf("  run %" PRId64 " %s: %" PRIu64 " of %" PRId64 " trials, %" PRIu64
               " missing, %" PRIu64 " repeated, %" PRIu64 " beyond\n",
               r->run_id, r->object, (uint64_t)r->final_trials - missing_of(r), r->final_trials,
               missing_of(r), r->repeated, beyond_of(r));
      if (r->final_trials >= 0 && missing_of(r) > 0) {
        printf("    missing:");
        int shown = 0;
        for (int64_t k = 0; k < r->final_trials && shown < 20; ++k)
          if ((size_t)k >= r->seen_cap || !r->seen[k]) {
            printf(" %" PRId64, k);
            shown++;
          }
        printf("%s\n", (uint64_t)shown < missing_of(r) ? " ..." : "");
      }
    }
  if (rc == 0) {
    const int complete = missing == 0 && repeated == 0 && beyond == 0 && no_final == 0 &&
                         c->undecodable == 0 && c->trials_out_of_range == 0;
    printf("%s: %zu runs, %" PRIu64 " of %" PRIu64 " trial records, %" PRIu64 " missing, %" PRIu64
           " repeated, %" PRIu64 " beyond the final count, %" PRIu64
           " runs without a final COM_ESTIMATE, %" PRIu64 " undecodable\n",
           complete ? "complete" : "INCOMPLETE", c->n_runs, expected - missing, expected, missing,
           repeated, beyond + c->trials_out_of_range, no_final, c->undecodable);
    rc = complete ? 0 : 1;
  }
  for (size_t i = 0; i < c->n_runs; ++i) free(c->runs[i].seen);
  free(c->runs);
  free(c);
  return rc;
}
