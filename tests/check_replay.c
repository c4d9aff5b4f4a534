#define _GNU_SOURCE
/* check_replay: record and replay (issue 6, docs/replay.md). Each test records a real run -
 * `comlearn estimate OBJECT --spawn-sim` on a udpm URL of its own - with lcm-logger, replays the
 * log with lcm-logplayer on a second URL into `comlearn watch --once --json`, and checks that the
 * replayed trial outcomes and the final estimate equal the live ones (the live `--json`). It then
 * recomputes the estimate in-process from the log's COM_TRIAL outcomes and released / settled
 * poses (a backend that plays the log back) and compares it with the log's COM_ESTIMATE. Also:
 * `comlearn watch` exits 1 on a --once timeout and 0 on SIGINT, and `comlearn record` keeps a
 * backlog far beyond lcm-logger's 30 waiting messages. */
#include <check.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <lcm/eventlog.h>
#include <lcm/lcm.h>

#include "comlearn/comlearn_com_estimate_t.h"
#include "comlearn/comlearn_com_trial_t.h"
#include "comlearn/model.h"
#include "comlearn/msg.h"
#include "comlearn/placement_plan.h"
#include "estimate_backend.h"
#include "estimate_test_util.h"

enum { MAX_CHILDREN = 4, MAX_TRIALS = 256 };

static char tmpdir[256];
static unsigned url_counter;
static pid_t children[MAX_CHILDREN];

static double now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void sleep_s(double s) {
  struct timespec ts = {(time_t)s, (long)((s - (double)(time_t)s) * 1e9)};
  while (nanosleep(&ts, &ts) != 0 && errno == EINTR) {}
}

/* Wait up to timeout_s for pid; SIGKILL after that. Returns the wait status, -1 if it had to be
 * killed. */
static int wait_child(pid_t pid, double timeout_s) {
  const double t0 = now_s();
  int ws = 0;
  for (;;) {
    pid_t r = waitpid(pid, &ws, WNOHANG);
    if (r == pid) break;
    if (r < 0 && errno != EINTR) return -1;
    if (now_s() - t0 > timeout_s) {
      kill(pid, SIGKILL);
      waitpid(pid, &ws, 0);
      ws = -1;
      break;
    }
    sleep_s(0.01);
  }
  for (int i = 0; i < MAX_CHILDREN; ++i)
    if (children[i] == pid) children[i] = 0;
  return ws;
}

/* Start argv with stdout / stderr into files (NULL: /dev/null); it gets SIGKILL if we die. */
static pid_t spawn(char *const argv[], const char *out_path, const char *err_path) {
  pid_t pid = fork();
  ck_assert_int_ge(pid, 0);
  if (pid == 0) {
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    signal(SIGINT, SIG_DFL); /* check's fork mode handles SIGINT by killing its group */
    signal(SIGTERM, SIG_DFL);
    int o = open(out_path ? out_path : "/dev/null", O_WRONLY | O_CREAT | O_TRUNC, 0644);
    int e = open(err_path ? err_path : "/dev/null", O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (o < 0 || e < 0) _exit(126);
    dup2(o, STDOUT_FILENO);
    dup2(e, STDERR_FILENO);
    execvp(argv[0], argv);
    _exit(127);
  }
  for (int i = 0; i < MAX_CHILDREN; ++i)
    if (children[i] == 0) {
      children[i] = pid;
      break;
    }
  return pid;
}

static void setup(void) {
  snprintf(tmpdir, sizeof tmpdir, "/tmp/check_replay.XXXXXX");
  ck_assert_ptr_nonnull(mkdtemp(tmpdir));
}

static void teardown(void) {
  for (int i = 0; i < MAX_CHILDREN; ++i) /* a failed assertion left early (CK_FORK=no) */
    if (children[i] > 0) {
      kill(children[i], SIGKILL);
      waitpid(children[i], NULL, 0);
      children[i] = 0;
    }
  char cmd[512];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
  ck_assert_int_eq(system(cmd), 0);
}

/* A port range of its own (check_estimate_lcm uses 7700..8699 the same way). */
static void unique_url(char *url, size_t n) {
  const unsigned port = 8700u + ((unsigned)getpid() * 7u + url_counter++) % 1000u;
  snprintf(url, n, "udpm://239.255.76.67:%u?ttl=0", port);
}

static char *read_file(const char *path) {
  FILE *f = fopen(path, "rb");
  ck_assert_msg(f != NULL, "%s: %s", path, strerror(errno));
  ck_assert_int_eq(fseek(f, 0, SEEK_END), 0);
  long n = ftell(f);
  ck_assert_int_ge(n, 0);
  rewind(f);
  char *s = malloc((size_t)n + 1);
  ck_assert_ptr_nonnull(s);
  ck_assert_uint_eq(fread(s, 1, (size_t)n, f), (size_t)n);
  s[n] = '\0';
  fclose(f);
  return s;
}

static off_t file_size(const char *path) {
  struct stat st;
  return stat(path, &st) == 0 ? st.st_size : -1;
}

/* Wait until `path` contains `needle` (a child's "ready" line). */
static int wait_for_text(const char *path, const char *needle, double timeout_s) {
  const double t0 = now_s();
  while (now_s() - t0 < timeout_s) {
    FILE *f = fopen(path, "rb");
    if (f) {
      char buf[4096];
      size_t n = fread(buf, 1, sizeof buf - 1, f);
      buf[n] = '\0';
      fclose(f);
      if (strstr(buf, needle)) return 1;
    }
    sleep_s(0.01);
  }
  return 0;
}

/* The text of `"key": [...]` in json from p on (NULL if absent). */
static int json_array(const char *p, const char *key, char *out, size_t n) {
  char k[64];
  snprintf(k, sizeof k, "\"%s\": [", key);
  const char *a = strstr(p, k);
  if (!a) return 0;
  const char *b = strchr(a, ']');
  if (!b) return 0;
  snprintf(out, n, "%.*s", (int)(b - a + 1), a);
  return 1;
}

static long json_int(const char *p, const char *key) {
  char k[64];
  snprintf(k, sizeof k, "\"%s\": ", key);
  const char *a = strstr(p, k);
  ck_assert_msg(a != NULL, "no %s", key);
  return strtol(a + strlen(k), NULL, 10);
}

/* Next `"key": "value"` after *p: copies value, advances *p; 0 when there is none. */
static int json_next_str(const char **p, const char *key, char *out, size_t n) {
  char k[64];
  snprintf(k, sizeof k, "\"%s\": \"", key);
  const char *a = strstr(*p, k);
  if (!a) return 0;
  a += strlen(k);
  const char *b = strchr(a, '"');
  if (!b) return 0;
  snprintf(out, n, "%.*s", (int)(b - a), a);
  *p = b + 1;
  return 1;
}

/* ---- recomputation from the log ------------------------------------------------------------ */

typedef struct {
  size_t n, next;
  int8_t kind[MAX_TRIALS];
  estimate_trial_reply_t reply[MAX_TRIALS];
  comlearn_com_trial_t rec[MAX_TRIALS];     /* the logged records (strings cleared) */
  estimate_trial_request_t req[MAX_TRIALS]; /* what the recomputation asked for */
} log_backend_t;

static estimate_outcome_t outcome_from_msg(int8_t o) {
  switch (o) {
    case COMLEARN_COM_TRIAL_T_OUTCOME_STAYS: return ESTIMATE_STAYS;
    case COMLEARN_COM_TRIAL_T_OUTCOME_TIPS: return ESTIMATE_TIPS;
    case COMLEARN_COM_TRIAL_T_OUTCOME_SLIDES: return ESTIMATE_SLIDES;
    default: return ESTIMATE_INVALID;
  }
}

static int log_run(void *ctx, const estimate_trial_request_t *req, estimate_trial_reply_t *reply,
                   char *err, size_t err_size) {
  log_backend_t *b = ctx;
  if (b->next >= b->n) {
    snprintf(err, err_size, "the log has only %zu trials", b->n);
    return -1;
  }
  const int8_t want = req->kind == ESTIMATE_TRIAL_EDGE ? COMLEARN_COM_TRIAL_T_KIND_EDGE
                                                       : COMLEARN_COM_TRIAL_T_KIND_REST;
  if (b->kind[b->next] != want) {
    snprintf(err, err_size, "trial %zu: the log has another kind", b->next);
    return -1;
  }
  b->req[b->next] = *req;
  *reply = b->reply[b->next++];
  return 0;
}

/* COM_TRIAL poses are in world (yumi_body); the estimator works in B's frame. */
static void world_to_block(const placement_pose_t *bib, const double p_w[3], const double q_w[4],
                           model_pose_t *out) {
  for (int i = 0; i < 3; ++i) {
    const double d[3] = {p_w[0] - bib->pos_m[0], p_w[1] - bib->pos_m[1], p_w[2] - bib->pos_m[2]};
    out->position_m[i] = bib->rot[0][i] * d[0] + bib->rot[1][i] * d[1] + bib->rot[2][i] * d[2];
  }
  memcpy(out->orientation_wxyz, q_w, sizeof out->orientation_wxyz);
}

static int same_bits(const double *a, const double *b, size_t n) {
  return memcmp(a, b, n * sizeof *a) == 0;
}

/* The estimator-side fields of each logged COM_TRIAL against the recomputation's own request
 * and trial record for it (the recomputation replays the run exactly, so bit for bit). Returns
 * how many edge trials were planned outside the flat-patch regime. */
static int check_estimator_fields(const log_backend_t *lb, const estimate_result_t *res,
                                  const int *live_flagged) {
  int planned_off = 0;
  for (size_t i = 0; i < lb->n; ++i) {
    const comlearn_com_trial_t *t = &lb->rec[i];
    const estimate_trial_request_t *q = &lb->req[i];
    const estimate_trial_t *tr = &res->trial[i];
    ck_assert_int_eq(t->component, q->component);
    ck_assert_int_eq(t->direction, q->direction);
    ck_assert_msg(same_bits(t->target_point_link_m, q->target_link_m, 3) &&
                      same_bits(t->target_point_link_m, tr->target_link_m, 3),
                  "trial %zu: target point differs from the estimator's", i);
    ck_assert(same_bits(t->com_estimated_m, q->com_before_m, 3));
    ck_assert(same_bits(t->halfwidth_m, q->halfwidth_before_m, 3));
    ck_assert_int_eq(t->flat_patch != 0, q->flat_patch != 0);
    ck_assert(same_bits(&t->sideways_margin_m, &q->sideways_margin_m, 1));
    if (t->kind == COMLEARN_COM_TRIAL_T_KIND_EDGE) {
      ck_assert_int_ge(tr->search, 0);
      ck_assert_int_eq(q->search, tr->search);
      ck_assert_msg(t->component >= 0 && t->component <= 2, "trial %zu: component %d", i,
                    t->component);
      ck_assert_msg(t->direction == 1 || t->direction == -1, "trial %zu: direction %d", i,
                    t->direction);
      /* the component and sign of the search's test direction */
      const double *u = res->search[tr->search].dir_link;
      for (int k = 0; k < 3; ++k) ck_assert(fabs(u[k]) <= fabs(u[t->component]));
      ck_assert_int_eq(t->direction, u[t->component] >= 0 ? 1 : -1);
      /* the target point lies on the search's line, at x_m (placement noise aside) */
      double x = 0.0;
      for (int k = 0; k < 3; ++k) x += u[k] * t->target_point_link_m[k];
      ck_assert_msg(fabs(x - tr->x_m) < 1e-3, "trial %zu: target at %.6f, x_m %.6f", i, x, tr->x_m);
      /* placement noise: the target point within a millimetre of the edge line at release */
      ck_assert_msg(fabs(t->target_offset_m) < 1e-3, "trial %zu: target_offset_m %g", i,
                    t->target_offset_m);
      /* a trial the live run fed (not flagged) was planned in the flat-patch regime */
      if (!t->flat_patch) ++planned_off;
      if (live_flagged && !live_flagged[i])
        ck_assert_msg(t->flat_patch, "trial %zu: fed, but flat_patch false (margin %g)", i,
                      t->sideways_margin_m);
    } else {
      ck_assert_int_eq(t->component, -1);
      ck_assert_int_eq(t->direction, 0);
      ck_assert(!t->flat_patch);
      ck_assert_int_eq(q->search, -1);
    }
  }
  return planned_off;
}

/* Reads COM_TRIAL / COM_ESTIMATE of the log (counted decoding) and reruns the estimate from the
 * trials; returns how many bits-equal components there are (0..3) after asserting 1e-12. */
static int recompute_from_log(const char *log_path, const char *urdf, size_t live_trials,
                              const int *live_flagged) {
  placement_plan_config_t pc;
  placement_plan_config_default(&pc);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      ck_assert_msg(pc.block_in_base.rot[i][j] == (i == j ? 1.0 : 0.0),
                    "the recomputation assumes B unrotated in yumi_body");
  log_backend_t *lb = calloc(1, sizeof *lb);
  ck_assert_ptr_nonnull(lb);
  comlearn_com_estimate_t final_e;
  memset(&final_e, 0, sizeof final_e);
  int have_final = 0;
  comlearn_msg_stats_t stats = {0};
  lcm_eventlog_t *log = lcm_eventlog_create(log_path, "r");
  ck_assert_ptr_nonnull(log);
  for (lcm_eventlog_event_t *ev; (ev = lcm_eventlog_read_next_event(log)) != NULL;
       lcm_eventlog_free_event(ev)) {
    if (strcmp(ev->channel, COMLEARN_MSG_CHANNEL_COM_TRIAL) == 0) {
      comlearn_com_trial_t t;
      ck_assert_int_eq(comlearn_msg_decode(comlearn_com_trial_t_get_type_info(), ev->data,
                                           (size_t)ev->datalen, &t, &stats),
                       COMLEARN_MSG_OK);
      ck_assert_uint_lt(lb->n, MAX_TRIALS);
      ck_assert_int_eq(t.trial_index, (int)lb->n); /* none lost, none twice */
      lb->kind[lb->n] = t.kind;
      lb->rec[lb->n] = t;
      lb->rec[lb->n].object_id = lb->rec[lb->n].policy = NULL;
      estimate_trial_reply_t *r = &lb->reply[lb->n++];
      r->outcome = outcome_from_msg(t.outcome);
      world_to_block(&pc.block_in_base, t.released_position_m, t.released_orientation_wxyz,
                     &r->released);
      world_to_block(&pc.block_in_base, t.settled_position_m, t.settled_orientation_wxyz,
                     &r->settled);
      comlearn_com_trial_t_decode_cleanup(&t);
    } else if (strcmp(ev->channel, COMLEARN_MSG_CHANNEL_COM_ESTIMATE) == 0) {
      comlearn_com_estimate_t e;
      ck_assert_int_eq(comlearn_msg_decode(comlearn_com_estimate_t_get_type_info(), ev->data,
                                           (size_t)ev->datalen, &e, &stats),
                       COMLEARN_MSG_OK);
      if (e.done) {
        final_e = e;
        final_e.object_id = final_e.policy = NULL;
        have_final = 1;
      }
      comlearn_com_estimate_t_decode_cleanup(&e);
    }
  }
  lcm_eventlog_destroy(log);
  ck_assert_msg(have_final, "no final COM_ESTIMATE in the log");
  ck_assert_uint_eq(lb->n, live_trials);
  ck_assert_uint_eq(comlearn_msg_stats_rejected(&stats), 0);

  model_object_t obj = {0};
  model_error_t merr = {{0}};
  ck_assert_msg(model_object_load(urdf, NULL, &obj, &merr) == MODEL_OK, "%s", merr.msg);
  placement_plan_config_t pc2;
  placement_plan_config_default(&pc2);
  estimate_backend_t be = {.ctx = lb, .name = "log", .run = log_run};
  memcpy(be.base_size_m, pc2.block_size_m, sizeof be.base_size_m);
  estimate_config_t cfg;
  estimate_config_default(&cfg);
  estimate_result_t *res = malloc(sizeof *res);
  ck_assert_ptr_nonnull(res);
  estimate_status_t s = estimate_run(&obj.mesh, &be, &cfg, res);
  ck_assert_msg(s == ESTIMATE_OK, "recompute: %s: %s", estimate_status_str(s), res->msg);
  ck_assert_uint_eq(res->trial_count, lb->n); /* every logged trial used, no more asked */
  ck_assert_int_eq(final_e.trials, (int)lb->n);
  int bits_equal = 0;
  for (int k = 0; k < 3; ++k) {
    ck_assert_int_eq(res->found[k] != 0, final_e.found[k] != 0);
    ck_assert_msg(fabs(res->com_m[k] - final_e.com_estimated_m[k]) <= 1e-12,
                  "component %d: recomputed %.17g, logged %.17g", k, res->com_m[k],
                  final_e.com_estimated_m[k]);
    bits_equal += memcmp(&res->com_m[k], &final_e.com_estimated_m[k], sizeof(double)) == 0;
  }
  const int planned_off = check_estimator_fields(lb, res, live_flagged);
  fprintf(stderr,
          "check_replay: %s: estimator-side fields of %zu COM_TRIALs equal the "
          "estimator's; %d edge trials planned outside the flat-patch regime\n",
          urdf, lb->n, planned_off);
  free(res);
  free(lb);
  model_object_free(&obj);
  return bits_equal;
}

/* ---- record, replay, compare --------------------------------------------------------------- */

/* Publish a probe on a logged channel until the logger has written something: then it is
 * subscribed (it flushes every 100 ms). */
static void wait_logger_ready(const char *url, const char *log_path) {
  lcm_t *lcm = lcm_create(url);
  ck_assert_ptr_nonnull(lcm);
  const double t0 = now_s();
  int ready = 0;
  while (!ready && now_s() - t0 < 20.0) {
    const char probe[] = "probe";
    ck_assert_int_eq(lcm_publish(lcm, "COM_PROBE", probe, sizeof probe), 0);
    sleep_s(0.05);
    ready = file_size(log_path) > 0;
  }
  lcm_destroy(lcm);
  ck_assert_msg(ready, "lcm-logger wrote nothing to %s within 20 s", log_path);
}

static void record_replay(const char *urdf) {
  char url[128], url2[128], logger_url[192], log_path[512], live_path[512], watch_out[512],
      watch_err[512], cmd[2048];
  unique_url(url, sizeof url);
  unique_url(url2, sizeof url2);
  snprintf(log_path, sizeof log_path, "%s/run.lcmlog", tmpdir);
  snprintf(live_path, sizeof live_path, "%s/live.json", tmpdir);
  snprintf(watch_out, sizeof watch_out, "%s/watch.json", tmpdir);
  snprintf(watch_err, sizeof watch_err, "%s/watch.err", tmpdir);

  /* 1. record. Only COM_* : lcm-logger 1.3.1 queues at most 30 messages per subscription, and
   * comlearn-sim's bursts of YUMI_STATUS can overflow a catch-all subscription (a COM_TRIAL was
   * seen lost that way); a subscription of its own keeps the records whole (docs/replay.md). */
  snprintf(logger_url, sizeof logger_url, "--lcm-url=%s&recv_buf_size=4194304", url);
  char *logger_argv[] = {"lcm-logger", "-q", "-f", "-c", "COM_.*", logger_url, log_path, NULL};
  pid_t logger = spawn(logger_argv, NULL, NULL);
  wait_logger_ready(url, log_path);

  snprintf(cmd, sizeof cmd,
           "timeout 120 '%s' estimate '%s' --spawn-sim --lcm-url '%s' --json -q > '%s'",
           COMLEARN_BIN, urdf, url, live_path);
  int ws = system(cmd);
  ck_assert_msg(WIFEXITED(ws) && WEXITSTATUS(ws) == 0, "live estimate: wait status %d", ws);
  /* the final COM_ESTIMATE reaches the logger: lcm-logger writes what it has read when SIGINT
   * comes, not what is still in its socket; 0.3 s was once too short with both cores busy */
  sleep_s(1.0);
  ck_assert_int_eq(kill(logger, SIGINT), 0);
  ws = wait_child(logger, 10.0);
  ck_assert_msg(ws != -1 && WIFEXITED(ws) && WEXITSTATUS(ws) == 0, "lcm-logger: %d", ws);
  /* which side lost it, if the replay below finds no final estimate */
  const size_t loglen = (size_t)file_size(log_path);
  char *logbytes = read_file(log_path);
  ck_assert_msg(memmem(logbytes, loglen, "COM_ESTIMATE", strlen("COM_ESTIMATE")) != NULL,
                "%s has no COM_ESTIMATE: lcm-logger had not read it when SIGINT came", log_path);
  free(logbytes);

  /* 2. replay into comlearn watch */
  char *watch_argv[] = {(char *)COMLEARN_BIN, "watch", "--once", "--json", "--timeout-s", "60",
                        "--lcm-url",          url2,    NULL};
  pid_t watch = spawn(watch_argv, watch_out, watch_err);
  ck_assert_msg(wait_for_text(watch_err, "listening on", 20.0), "comlearn watch did not start");
  snprintf(cmd, sizeof cmd, "timeout 60 lcm-logplayer --lcm-url='%s' '%s' > /dev/null", url2,
           log_path);
  ws = system(cmd);
  ck_assert_msg(WIFEXITED(ws) && WEXITSTATUS(ws) == 0, "lcm-logplayer: wait status %d", ws);
  ws = wait_child(watch, 30.0);
  ck_assert_msg(ws != -1 && WIFEXITED(ws) && WEXITSTATUS(ws) == 0, "comlearn watch: %d", ws);

  /* 3. compare */
  char *live = read_file(live_path), *rep = read_file(watch_out);
  const long n = json_int(live, "trials");
  ck_assert_int_gt(n, 0);
  const char *est = strstr(rep, "{\"type\": \"estimate\"");
  ck_assert_msg(est != NULL, "no estimate from watch: %s", rep);
  ck_assert_ptr_nonnull(strstr(est, "\"done\": true"));
  ck_assert_int_eq(json_int(est, "trials"), n);
  char a[256], b[256];
  ck_assert(json_array(live, "com_m", a, sizeof a));
  ck_assert(json_array(est, "com_m", b, sizeof b));
  ck_assert_str_eq(b, a); /* both %.9g of the same doubles */
  ck_assert(json_array(live, "found", a, sizeof a));
  ck_assert(json_array(est, "found", b, sizeof b));
  ck_assert_str_eq(b, a);
  ck_assert(json_array(live, "halfwidth_m", a, sizeof a));
  ck_assert(json_array(est, "halfwidth_m", b, sizeof b));
  ck_assert_str_eq(b, a);

  /* trial by trial: the live trial_log against the replayed COM_TRIAL records, in order */
  const char *lp = strstr(live, "\"trial_log\": [");
  ck_assert_ptr_nonnull(lp);
  const char *rp = rep;
  long i = 0;
  char lk[32], lo[32], rk[32], ro[32], rc[32];
  int *flagged = calloc((size_t)n, sizeof *flagged);
  ck_assert_ptr_nonnull(flagged);
  for (; json_next_str(&lp, "kind", lk, sizeof lk); ++i) {
    ck_assert(json_next_str(&lp, "outcome", lo, sizeof lo));
    ck_assert_int_lt(i, n);
    const char *fl = strstr(lp, "\"flagged\": ");
    ck_assert_ptr_nonnull(fl);
    flagged[i] = strncmp(fl + strlen("\"flagged\": "), "true", 4) == 0;
    const char *line = strstr(rp, "{\"type\": \"trial\"");
    ck_assert_msg(line != NULL, "replay has %ld trials, live %ld", i, n);
    ck_assert_int_eq(json_int(line, "trial_index"), i);
    rp = line + 1;
    ck_assert(json_next_str(&rp, "kind", rk, sizeof rk));
    ck_assert(json_next_str(&rp, "component", rc, sizeof rc));
    const long dir = json_int(rp, "direction");
    ck_assert(json_next_str(&rp, "outcome", ro, sizeof ro));
    ck_assert_msg(strcmp(ro, lo) == 0, "trial %ld: replayed %s, live %s", i, ro, lo);
    ck_assert_str_eq(rk, strcmp(lk, "stable") == 0 ? "rest" : "edge");
    /* the estimator-side fields, as watch prints them */
    const char *fp = strstr(rp, "\"flat_patch\": ");
    ck_assert_ptr_nonnull(fp);
    const int flat = strncmp(fp + strlen("\"flat_patch\": "), "true", 4) == 0;
    if (strcmp(rk, "edge") == 0) {
      ck_assert_msg(strcmp(rc, "x") == 0 || strcmp(rc, "y") == 0 || strcmp(rc, "z") == 0,
                    "trial %ld: component %s", i, rc);
      ck_assert_msg(dir == 1 || dir == -1, "trial %ld: direction %ld", i, dir);
      if (!flagged[i]) ck_assert_msg(flat, "trial %ld: fed but not flat_patch", i);
    } else {
      ck_assert_str_eq(rc, "-");
      ck_assert_int_eq(dir, 0);
      ck_assert(!flat);
    }
  }
  ck_assert_int_eq(i, n);
  ck_assert_ptr_null(strstr(rp, "{\"type\": \"trial\"")); /* none extra */
  free(live);
  free(rep);

  /* 4. the estimate recomputed from the logged outcomes and poses */
  const int bits = recompute_from_log(log_path, urdf, (size_t)n, flagged);
  free(flagged);
  fprintf(stderr,
          "check_replay: %s: %ld trials replayed equal; recomputed estimate: %d of 3 "
          "components bit-identical to the logged COM_ESTIMATE\n",
          urdf, n, bits);
  ck_assert_int_eq(bits, 3);
}

START_TEST(replay_box) {
  char urdf[512];
  snprintf(urdf, sizeof urdf, "%s/box.urdf", tmpdir);
  model_mass_t exact;
  write_two_material_box(urdf, &exact);
  record_replay(urdf);
}
END_TEST

START_TEST(replay_rock) { record_replay(COMLEARN_ASSETS_DIR "/rocks/rock_1_uneven.urdf"); }
END_TEST

START_TEST(watch_timeout_and_sigint) {
  char url[128], out[512], err[512], err2[512];
  unique_url(url, sizeof url);
  snprintf(out, sizeof out, "%s/w.out", tmpdir);
  snprintf(err, sizeof err, "%s/w.err", tmpdir);
  snprintf(err2, sizeof err2, "%s/w2.err", tmpdir); /* a file of its own: "listening on" */
  /* --once with nothing on the URL: exit 1 after the timeout */
  char *a1[] = {(char *)COMLEARN_BIN, "watch", "--once", "--timeout-s", "0.3",
                "--lcm-url",          url,     NULL};
  const double t0 = now_s();
  int ws = wait_child(spawn(a1, out, err), 20.0);
  ck_assert_msg(ws != -1 && WIFEXITED(ws) && WEXITSTATUS(ws) == 1, "timeout: %d", ws);
  ck_assert_double_lt(now_s() - t0, 15.0);
  /* without a timeout: SIGINT exits 0 */
  char *a2[] = {(char *)COMLEARN_BIN, "watch", "--lcm-url", url, NULL};
  pid_t p = spawn(a2, out, err2);
  ck_assert(wait_for_text(err2, "listening on", 20.0));
  ck_assert_int_eq(kill(p, SIGINT), 0);
  ws = wait_child(p, 10.0);
  ck_assert_msg(ws != -1 && WIFEXITED(ws) && WEXITSTATUS(ws) == 0, "sigint: %d", ws);
  /* usage */
  char *a3[] = {(char *)COMLEARN_BIN, "watch", "--timeout-s", "x", NULL};
  ws = wait_child(spawn(a3, out, err), 10.0);
  ck_assert_msg(ws != -1 && WIFEXITED(ws) && WEXITSTATUS(ws) == 2, "usage: %d", ws);
}
END_TEST

/* ---- comlearn record ------------------------------------------------------------------------ */

/* `comlearn record` keeps what piles up while it is busy: it records into a FIFO that this test
 * stops reading, so that its writes block with the pipe full while a burst of n messages on 4
 * channels arrives; LCM's thread queues them (lcm-logger's subscription would keep 30 waiting
 * and drop the rest). Then SIGINT, and the FIFO read to its end: the log, parsed by LCM's own
 * reader, holds the readiness probes and then exactly the burst, in the order sent, byte for
 * byte. Bad input: an existing FILE without --force, no FILE, a bad --flush-ms, an unwritable
 * FILE: exit 2. */
START_TEST(record_keeps_a_backlog) {
  char url[128], fifo[512], log_path[512], err[512];
  unique_url(url, sizeof url);
  snprintf(fifo, sizeof fifo, "%s/rec.fifo", tmpdir);
  snprintf(log_path, sizeof log_path, "%s/rec.lcmlog", tmpdir);
  snprintf(err, sizeof err, "%s/rec.err", tmpdir);
  ck_assert_int_eq(mkfifo(fifo, 0600), 0);
  char *argv[] = {(char *)COMLEARN_BIN, "record", fifo, "-f", "--lcm-url", url, NULL};
  const pid_t rec = spawn(argv, NULL, err);
  const int rd = open(fifo, O_RDONLY); /* returns once the recorder opened it */
  ck_assert_int_ge(rd, 0);
  ck_assert_int_eq(fcntl(rd, F_SETFL, O_NONBLOCK), 0);
  FILE *copy = fopen(log_path, "wb");
  ck_assert_ptr_nonnull(copy);
  char buf[65536];
  lcm_t *lcm = lcm_create(url);
  ck_assert_ptr_nonnull(lcm);
  size_t got = 0;
  for (const double t0 = now_s(); got == 0 && now_s() - t0 < 20.0;) { /* subscribed? */
    const char probe[] = "probe";
    ck_assert_int_eq(lcm_publish(lcm, "COM_PROBE", probe, sizeof probe), 0);
    sleep_s(0.15); /* past its 100 ms flush */
    for (ssize_t k; (k = read(rd, buf, sizeof buf)) > 0; got += (size_t)k)
      ck_assert_uint_eq(fwrite(buf, 1, (size_t)k, copy), (size_t)k);
  }
  ck_assert_msg(got > 0, "comlearn record wrote nothing within 20 s");
  const char *channels[4] = {"YUMI_STATUS", "OBJECT_STATE", "R3_YUMI_STATUS", "COM_TRIAL"};
  const int n = 2000; /* ~110 bytes of log each: over 3 times the pipe's 64 KiB */
  for (int i = 0; i < n; ++i) {
    char payload[64];
    const int len = snprintf(payload, sizeof payload, "message %d of %d", i, n);
    ck_assert_int_eq(lcm_publish(lcm, channels[i % 4], payload, (unsigned)len), 0);
    if (i % 100 == 99) sleep_s(0.002); /* within the socket's buffer, whatever rmem_max */
  }
  lcm_destroy(lcm);
  sleep_s(0.3); /* the recorder blocked on the full pipe all along */
  ck_assert_int_eq(kill(rec, SIGINT), 0);
  ck_assert_int_eq(fcntl(rd, F_SETFL, 0), 0);
  for (ssize_t k; (k = read(rd, buf, sizeof buf)) > 0;)
    ck_assert_uint_eq(fwrite(buf, 1, (size_t)k, copy), (size_t)k);
  close(rd);
  ck_assert_int_eq(fclose(copy), 0);
  int ws = wait_child(rec, 10.0);
  ck_assert_msg(ws != -1 && WIFEXITED(ws) && WEXITSTATUS(ws) == 0, "comlearn record: %d", ws);
  lcm_eventlog_t *log = lcm_eventlog_create(log_path, "r");
  ck_assert_ptr_nonnull(log);
  int next = 0, probes = 0;
  for (lcm_eventlog_event_t *ev; (ev = lcm_eventlog_read_next_event(log)) != NULL;) {
    if (strcmp(ev->channel, "COM_PROBE") == 0) {
      ck_assert_int_eq(next, 0); /* the probes come before the burst */
      probes++;
    } else {
      char want[64];
      const int len = snprintf(want, sizeof want, "message %d of %d", next, n);
      ck_assert_msg(next < n, "more than %d messages", n);
      ck_assert_str_eq(ev->channel, channels[next % 4]);
      ck_assert_int_eq(ev->datalen, len);
      ck_assert_mem_eq(ev->data, want, (size_t)len);
      ck_assert_int_eq(ev->eventnum, probes + next);
      next++;
    }
    lcm_eventlog_free_event(ev);
  }
  lcm_eventlog_destroy(log);
  ck_assert_int_gt(probes, 0);
  ck_assert_msg(next == n, "%d of %d messages recorded", next, n);

  char *exists[] = {(char *)COMLEARN_BIN, "record", log_path, "--lcm-url", url, NULL};
  ws = wait_child(spawn(exists, NULL, err), 10.0);
  ck_assert_msg(ws != -1 && WIFEXITED(ws) && WEXITSTATUS(ws) == 2, "existing file: %d", ws);
  char *text = read_file(err);
  ck_assert_msg(strstr(text, "exists (--force overwrites it)") != NULL, "%s", text);
  free(text);
  char *none[] = {(char *)COMLEARN_BIN, "record", NULL};
  ws = wait_child(spawn(none, NULL, NULL), 10.0);
  ck_assert_msg(ws != -1 && WIFEXITED(ws) && WEXITSTATUS(ws) == 2, "no file: %d", ws);
  char *flush[] = {(char *)COMLEARN_BIN, "record", "x.lcmlog", "--flush-ms", "0", NULL};
  ws = wait_child(spawn(flush, NULL, NULL), 10.0);
  ck_assert_msg(ws != -1 && WIFEXITED(ws) && WEXITSTATUS(ws) == 2, "--flush-ms 0: %d", ws);
  char bad_dir[600];
  snprintf(bad_dir, sizeof bad_dir, "%s/no/such/dir.lcmlog", tmpdir);
  char *unwritable[] = {(char *)COMLEARN_BIN, "record", bad_dir, "--lcm-url", url, NULL};
  ws = wait_child(spawn(unwritable, NULL, err), 10.0);
  ck_assert_msg(ws != -1 && WIFEXITED(ws) && WEXITSTATUS(ws) == 2, "unwritable: %d", ws);
  text = read_file(err);
  ck_assert_msg(strstr(text, "dir.lcmlog") != NULL, "%s", text);
  free(text);
}
END_TEST

int main(void) {
  Suite *s = suite_create("replay");
  TCase *tc = tcase_create("replay");
  tcase_add_checked_fixture(tc, setup, teardown);
  tcase_set_timeout(tc, 240);
  tcase_add_test(tc, watch_timeout_and_sigint);
  tcase_add_test(tc, replay_box);
  tcase_add_test(tc, replay_rock);
  tcase_add_test(tc, record_keeps_a_backlog);
  suite_add_tcase(s, tc);
  SRunner *sr = srunner_create(s);
  srunner_run_all(sr, CK_NORMAL);
  const int failed = srunner_ntests_failed(sr);
  srunner_free(sr);
  return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
