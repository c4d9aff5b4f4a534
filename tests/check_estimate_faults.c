#define _GNU_SOURCE
/* check_estimate_faults: whole estimates over LCM against the real comlearn-sim (a udpm URL of its
 * own per test) under faults, each compared trial by trial with the noiseless --direct estimate
 * of the same object (issue 6, "Faults"):
 *   - the daemon at --drop-rate 0.2 (incoming and outgoing messages dropped);
 *   - the daemon SIGKILLed in the middle of a trial and a new one started on the same URL;
 *   - garbage, truncated and wrong-fingerprint buffers published on YUMI_STATUS and OBJECT_STATE
 *     (the channels the backend subscribes to) during the whole estimate.
 * The estimate must be equal to --direct's (outcomes deterministic; faults only cost resends and
 * trial restarts) and the daemon must exit 0 on SIGTERM afterwards.
 *
 * Helper threads (the killer, the garbage publisher) never call ck_assert; the fixture teardown
 * stops them and every daemon even when an assertion left the test early (CK_FORK=no). */
#include <check.h>
#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <lcm/lcm.h>

#include "comlearn/comlearn_com_trial_t.h"
#include "comlearn/comlearn_object_state_t.h"
#include "comlearn/comlearn_yumi_status_t.h"
#include "comlearn/model.h"
#include "comlearn/model_inertial.h"
#include "comlearn/msg.h"
#include "estimate_backend.h"
#include "estimate_direct.h"
#include "estimate_lcm.h"
#include "estimate_test_util.h"

static char tmpdir[256];
static unsigned url_counter;
static char url[128];

/* the daemon currently running (replaced by the killer thread) */
static _Atomic pid_t sim_pid = -1;
static double ack_timeout_s; /* 0: the backend's default (0.5 s) */

/* helper threads */
static atomic_int stop_threads;
static pthread_t killer, garbler;
static int killer_running, garbler_running;

static void sleep_ms(long ms) {
  struct timespec ts = {ms / 1000, (ms % 1000) * 1000000L};
  while (nanosleep(&ts, &ts) != 0 && errno == EINTR) {}
}

/* comlearn-sim on `url` with extra arguments (NULL-terminated, at most 6). The child gets SIGKILL
 * when the thread that forked it ends (PR_SET_PDEATHSIG), so helper threads stay alive until the
 * teardown has stopped their daemon. */
static pid_t spawn_sim(const char *const *extra) {
  const char *argv[20] = {COMLEARN_SIM_EXE, "--lcm-url", url, "-q", "--object-dir", tmpdir};
  int n = 6;
  for (; extra && *extra && n < 18; ++extra) argv[n++] = *extra;
  argv[n] = NULL;
  const pid_t pid = fork();
  if (pid == 0) {
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    execv(COMLEARN_SIM_EXE, (char *const *)argv);
    _exit(127);
  }
  return pid;
}

static void setup(void) {
  snprintf(tmpdir, sizeof tmpdir, "/tmp/check_estimate_faults.XXXXXX");
  ck_assert_ptr_nonnull(mkdtemp(tmpdir));
  const unsigned port = 8700u + ((unsigned)getpid() * 7u + url_counter++) % 1000u;
  snprintf(url, sizeof url, "udpm://239.255.76.67:%u?ttl=0", port);
  atomic_store(&stop_threads, 0);
  atomic_store(&sim_pid, -1);
  ack_timeout_s = 0;
}

static void teardown(void) {
  atomic_store(&stop_threads, 1);
  /* the daemon first: the helper that forked it must outlive it (PR_SET_PDEATHSIG) */
  if (killer_running) {
    /* the killer may be between kill and spawn: let it finish (it checks stop_threads) */
    pthread_join(killer, NULL);
    killer_running = 0;
  }
  const pid_t p = atomic_exchange(&sim_pid, -1);
  if (p > 0) estimate_lcm_sim_stop(p, 1.0);
  if (garbler_running) {
    pthread_join(garbler, NULL);
    garbler_running = 0;
  }
  char cmd[512];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
  ck_assert_int_eq(system(cmd), 0);
}

/* ---- the estimates ------------------------------------------------------------------------- */

static atomic_int trials_started;

/* The LCM backend wrapped to count trial requests (the killer's trigger). */
static estimate_backend_t inner;
static int counting_run(void *ctx, const estimate_trial_request_t *req,
                        estimate_trial_reply_t *reply, char *err, size_t err_size) {
  atomic_fetch_add(&trials_started, 1);
  return inner.run(ctx, req, reply, err, err_size);
}

static char log_buf[8192];
static void log_cb(void *ctx, const char *msg) {
  (void)ctx;
  const size_t n = strlen(log_buf);
  if (n + strlen(msg) + 2 < sizeof log_buf) {
    strcat(log_buf, msg);
    strcat(log_buf, "\n");
  }
}

static void estimate_direct_urdf(const char *urdf, const model_mesh_t *mesh, estimate_result_t *r) {
  estimate_direct_t *d = NULL;
  estimate_backend_t b;
  char msg[512] = "";
  ck_assert_msg(estimate_direct_open(urdf, NULL, NULL, &d, &b, msg, sizeof msg) == 0, "%s", msg);
  estimate_config_t cfg;
  estimate_config_default(&cfg);
  estimate_status_t s = estimate_run(mesh, &b, &cfg, r);
  ck_assert_msg(s == ESTIMATE_OK, "direct %s: %s: %s", urdf, estimate_status_str(s), r->msg);
  estimate_direct_close(d);
}

/* The estimate over LCM on `url` (the daemon already running); stats filled. */
static void estimate_lcm_urdf(const char *urdf, const model_mesh_t *mesh, estimate_result_t *r,
                              estimate_lcm_stats_t *stats) {
  char msg[512] = "";
  estimate_lcm_config_t lc;
  estimate_lcm_config_default(&lc);
  lc.lcm_url = url;
  lc.urdf_path = urdf;
  lc.mesh_link = mesh;
  lc.yumi_urdf = COMLEARN_ASSETS_DIR "/yumi/yumi.urdf";
  lc.policy = "bisect";
  lc.log = log_cb;
  if (ack_timeout_s > 0) lc.ack_timeout_s = ack_timeout_s;
  log_buf[0] = '\0';
  estimate_lcm_t *l = NULL;
  ck_assert_msg(estimate_lcm_open(&lc, &l, &inner, msg, sizeof msg) == 0,
                "%s (udpm needs a multicast route: `ip route add 224.0.0.0/4 dev lo` as root, "
                "scripts/setup.sh)",
                msg);
  estimate_backend_t b = inner;
  b.run = counting_run;
  atomic_store(&trials_started, 0);
  estimate_config_t cfg;
  estimate_config_default(&cfg);
  estimate_status_t s = estimate_run(mesh, &b, &cfg, r);
  estimate_lcm_stats(l, stats);
  estimate_lcm_close(l);
  ck_assert_msg(s == ESTIMATE_OK, "lcm %s: %s: %s\nbackend log:\n%s", urdf, estimate_status_str(s),
                r->msg, log_buf);
}

typedef struct {
  model_object_t obj;
  model_mass_t truth;
  estimate_result_t *d, *l;
  estimate_lcm_stats_t st;
  double wall_s;
} box_run_t;

static double now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The two-material box: --direct, then over LCM (the daemon started by the caller). */
static void box_run(box_run_t *b) {
  char urdf[512];
  snprintf(urdf, sizeof urdf, "%s/box.urdf", tmpdir);
  write_two_material_box(urdf, &b->truth);
  model_error_t err = {{0}};
  ck_assert_msg(model_object_load(urdf, NULL, &b->obj, &err) == MODEL_OK, "%s", err.msg);
  b->d = calloc(1, sizeof *b->d);
  b->l = calloc(1, sizeof *b->l);
  ck_assert_ptr_nonnull(b->d);
  ck_assert_ptr_nonnull(b->l);
  estimate_direct_urdf(urdf, &b->obj.mesh, b->d);
  const double t0 = now_s();
  estimate_lcm_urdf(urdf, &b->obj.mesh, b->l, &b->st);
  b->wall_s = now_s() - t0;
  check_agree(b->d, b->l);
  for (int k = 0; k < 3; ++k)
    ck_assert_msg(fabs(b->l->com_m[k] - b->truth.com_m[k]) <= 1e-4, "component %d %.4f mm off", k,
                  1e3 * (b->l->com_m[k] - b->truth.com_m[k]));
  ck_assert_uint_eq(b->st.trials, b->l->trial_count);
}

static void box_free(box_run_t *b) {
  free(b->d);
  free(b->l);
  model_object_free(&b->obj);
}

/* SIGTERM the current daemon: it must exit 0 (nothing crashed). */
static void stop_sim_clean(void) {
  const pid_t p = atomic_exchange(&sim_pid, -1);
  ck_assert_int_gt(p, 0);
  const int ws = estimate_lcm_sim_stop(p, 2.0);
  ck_assert_msg(ws != -1 && WIFEXITED(ws) && WEXITSTATUS(ws) == 0, "comlearn-sim exit %d", ws);
}

static void report(const char *name, const box_run_t *b) {
  fprintf(stderr,
          "%s: %zu trials in %.2f s; commands %llu (resent %llu), sim controls %llu, trial "
          "restarts %llu, statuses %llu, object states %llu, undecodable %llu\n",
          name, b->l->trial_count, b->wall_s, (unsigned long long)b->st.commands_sent,
          (unsigned long long)b->st.commands_resent, (unsigned long long)b->st.controls_sent,
          (unsigned long long)b->st.trial_restarts, (unsigned long long)b->st.statuses,
          (unsigned long long)b->st.object_states, (unsigned long long)b->st.undecodable);
}

/* ---- 20 % drops both ways ------------------------------------------------------------------- */

START_TEST(drops_20_percent) {
  static const char *const extra[] = {"--drop-rate", "0.2", "--seed", "6", NULL};
  /* each lost command costs one acknowledgement timeout: 0.25 s instead of the default 0.5 s
   * keeps the test near 10 s (~30 resends); the estimate does not depend on it */
  ack_timeout_s = 0.25;
  atomic_store(&sim_pid, spawn_sim(extra));
  ck_assert_int_gt(atomic_load(&sim_pid), 0);
  box_run_t b = {0};
  box_run(&b);
  report("drops_20_percent", &b);
  /* the drops cost resends (a lost command or SIM_CONTROL is sent again with a new seq) */
  ck_assert_uint_gt(b.st.commands_resent + (b.st.controls_sent - b.st.trials), 0);
  ck_assert_uint_eq(b.st.undecodable, 0);
  stop_sim_clean();
  box_free(&b);
}
END_TEST

/* ---- kill -9 and restart mid-estimate -------------------------------------------------------- */

/* Loop test i kills in trial request kill_at[i], kill_delay_us[i] after it started: in the
 * SIM_CONTROL, a waypoint, the outcome wait or between trials, depending on the machine (a trial
 * takes 2-5 ms against a sim as fast as possible). */
enum { KILL_CASES = 4, RESTART_DELAY_MS = 200 };
static const int kill_at[KILL_CASES] = {3, 6, 10, 16},
                 kill_delay_us[KILL_CASES] = {0, 300, 900, 1800};
static int kill_case;
static atomic_int killed_at; /* trials_started when the daemon was killed; 0: not yet */

static void *killer_main(void *arg) {
  (void)arg;
  const struct timespec poll = {0, 100000L};
  while (!atomic_load(&stop_threads) && atomic_load(&trials_started) < kill_at[kill_case])
    nanosleep(&poll, NULL);
  if (atomic_load(&stop_threads)) return NULL;
  const struct timespec in_trial = {0, 1000L * kill_delay_us[kill_case]};
  nanosleep(&in_trial, NULL);
  const pid_t old = atomic_load(&sim_pid);
  kill(old, SIGKILL);
  int ws;
  waitpid(old, &ws, 0);
  atomic_store(&killed_at, atomic_load(&trials_started));
  sleep_ms(RESTART_DELAY_MS); /* the backend sees nothing for a while */
  if (atomic_load(&stop_threads)) {
    atomic_store(&sim_pid, -1);
    return NULL;
  }
  atomic_store(&sim_pid, spawn_sim(NULL));
  /* stay alive while the new daemon runs (PR_SET_PDEATHSIG is per thread) */
  while (!atomic_load(&stop_threads)) sleep_ms(5);
  /* the teardown / test has stopped the daemon by now or stops it right after the join */
  return NULL;
}

START_TEST(daemon_killed_and_restarted) {
  kill_case = _i;
  atomic_store(&sim_pid, spawn_sim(NULL));
  ck_assert_int_gt(atomic_load(&sim_pid), 0);
  atomic_store(&killed_at, 0);
  atomic_store(&trials_started, 0);
  ck_assert_int_eq(pthread_create(&killer, NULL, killer_main, NULL), 0);
  killer_running = 1;
  box_run_t b = {0};
  box_run(&b);
  report("daemon_killed_and_restarted", &b);
  fprintf(stderr,
          "daemon_killed_and_restarted: killed in trial request %d + %d us; backend "
          "log:\n%s",
          kill_at[kill_case], kill_delay_us[kill_case], log_buf);
  /* killed mid-estimate, and the estimate went on against the new daemon */
  ck_assert_int_ge(atomic_load(&killed_at), kill_at[kill_case]);
  ck_assert_int_lt(atomic_load(&killed_at), (int)b.l->trial_count);
  ck_assert_msg(strstr(log_buf, "loading it again") || b.st.trial_restarts > 0,
                "no reload after the restart; backend log:\n%s", log_buf);
  ck_assert_uint_gt(b.st.commands_resent + b.st.trial_restarts + (b.st.controls_sent - b.st.trials),
                    0);
  /* the new daemon exits cleanly; then let the killer go */
  stop_sim_clean();
  atomic_store(&stop_threads, 1);
  pthread_join(killer, NULL);
  killer_running = 0;
  box_free(&b);
}
END_TEST

/* ---- garbage on the subscribed channels ---------------------------------------------------- */

static atomic_ullong garbage_sent, forged_sent; /* bad buffers; decodable but absurd messages */

static void *garbler_main(void *arg) {
  (void)arg;
  lcm_t *lcm = lcm_create(url);
  if (!lcm) return NULL;
  static unsigned char st_buf[4096], os_buf[4096], tr_buf[4096], bad[4096];
  comlearn_yumi_status_t st;
  memset(&st, 0, sizeof st);
  st.error_text = (char *)"";
  const int st_len = comlearn_yumi_status_t_encode(st_buf, 0, sizeof st_buf, &st);
  comlearn_object_state_t os;
  memset(&os, 0, sizeof os);
  os.object_id = (char *)"box";
  const int os_len = comlearn_object_state_t_encode(os_buf, 0, sizeof os_buf, &os);
  comlearn_com_trial_t tr;
  memset(&tr, 0, sizeof tr);
  tr.object_id = (char *)"box";
  tr.policy = (char *)"bisect";
  const int tr_len = comlearn_com_trial_t_encode(tr_buf, 0, sizeof tr_buf, &tr);
  /* decodable but absurd: clocks and seqs at INT64_MAX (the client's expiry and seq arithmetic
   * would overflow on them), a NaN position */
  static unsigned char fst_buf[4096], fos_buf[4096];
  comlearn_yumi_status_t fst = st;
  fst.utime = INT64_MAX;
  fst.last_accepted_seq = INT64_MAX;
  const int fst_len = comlearn_yumi_status_t_encode(fst_buf, 0, sizeof fst_buf, &fst);
  comlearn_object_state_t fos = os;
  fos.utime = INT64_MAX;
  fos.sim_control_seq = INT64_MAX;
  fos.position_measured_m[0] = NAN;
  const int fos_len = comlearn_object_state_t_encode(fos_buf, 0, sizeof fos_buf, &fos);
  /* sane but not the estimator's: a seq it never sent, the state of another object */
  static unsigned char xst_buf[4096], xos_buf[4096];
  comlearn_yumi_status_t xst = st;
  xst.last_accepted_seq = (int64_t)1 << 40;
  const int xst_len = comlearn_yumi_status_t_encode(xst_buf, 0, sizeof xst_buf, &xst);
  comlearn_object_state_t xos = os;
  xos.object_id = (char *)"intruder";
  xos.tracked = 1;
  xos.at_rest = 1;
  const int xos_len = comlearn_object_state_t_encode(xos_buf, 0, sizeof xos_buf, &xos);
  if (st_len <= 16 || os_len <= 16 || tr_len <= 16 || fst_len <= 16 || fos_len <= 16 ||
      xst_len <= 16 || xos_len <= 16) {
    lcm_destroy(lcm);
    return NULL;
  }
  /* object_id's length field in the object state ("box\0" preceded by 00 00 00 04) */
  int id_len_at = -1;
  for (int i = 8; i + 8 <= os_len; ++i)
    if (memcmp(os_buf + i, "\0\0\0\004box", 8) == 0) id_len_at = i;
  unsigned seed = 11;
  const char *const ch[2] = {COMLEARN_MSG_CHANNEL_YUMI_STATUS, COMLEARN_MSG_CHANNEL_OBJECT_STATE};
  while (!atomic_load(&stop_threads)) {
    for (int c = 0; c < 2; ++c) {
      const unsigned char *own = c == 0 ? st_buf : os_buf;
      const int own_len = c == 0 ? st_len : os_len;
      unsigned long long n = 0;
      n += lcm_publish(lcm, ch[c], own, (unsigned)(own_len - 1)) == 0; /* truncated */
      n += lcm_publish(lcm, ch[c], own, (unsigned)(own_len / 2)) == 0; /* truncated */
      n += lcm_publish(lcm, ch[c], c == 0 ? os_buf : st_buf,           /* the other type */
                       (unsigned)(c == 0 ? os_len : st_len)) == 0;
      n += lcm_publish(lcm, ch[c], tr_buf, (unsigned)tr_len) == 0; /* COM_TRIAL */
      memcpy(bad, own, (size_t)own_len);
      bad[own_len] = 0x42;
      n += lcm_publish(lcm, ch[c], bad, (unsigned)own_len + 1) == 0; /* trailing byte */
      memcpy(bad, own, (size_t)own_len);
      bad[3] ^= 0x10; /* fingerprint off by one bit */
      n += lcm_publish(lcm, ch[c], bad, (unsigned)own_len) == 0;
      if (c == 1 && id_len_at >= 0) { /* string length -1 */
        memcpy(bad, own, (size_t)own_len);
        memset(bad + id_len_at, 0xff, 4);
        n += lcm_publish(lcm, ch[c], bad, (unsigned)own_len) == 0;
      }
      for (int i = 0; i < 300; ++i) bad[i] = (unsigned char)(rand_r(&seed) & 0xff);
      n += lcm_publish(lcm, ch[c], bad, 300) == 0; /* garbage */
      n += lcm_publish(lcm, ch[c], bad, 3) == 0;   /* shorter than a fingerprint */
      n += lcm_publish(lcm, ch[c], bad, 0) == 0;   /* empty */
      atomic_fetch_add(&garbage_sent, n);
      atomic_fetch_add(&forged_sent, lcm_publish(lcm, ch[c], c == 0 ? fst_buf : fos_buf,
                                                 (unsigned)(c == 0 ? fst_len : fos_len)) == 0);
      atomic_fetch_add(&forged_sent, lcm_publish(lcm, ch[c], c == 0 ? xst_buf : xos_buf,
                                                 (unsigned)(c == 0 ? xst_len : xos_len)) == 0);
    }
    sleep_ms(2);
  }
  lcm_destroy(lcm);
  return NULL;
}

START_TEST(garbage_on_subscribed_channels) {
  atomic_store(&sim_pid, spawn_sim(NULL));
  ck_assert_int_gt(atomic_load(&sim_pid), 0);
  atomic_store(&garbage_sent, 0);
  atomic_store(&forged_sent, 0);
  ck_assert_int_eq(pthread_create(&garbler, NULL, garbler_main, NULL), 0);
  garbler_running = 1;
  box_run_t b = {0};
  box_run(&b);
  atomic_store(&stop_threads, 1);
  pthread_join(garbler, NULL);
  garbler_running = 0;
  report("garbage_on_subscribed_channels", &b);
  fprintf(stderr, "garbage_on_subscribed_channels: %llu bad buffers published\n",
          (unsigned long long)atomic_load(&garbage_sent));
  ck_assert_uint_gt(atomic_load(&garbage_sent), 0);
  ck_assert_uint_gt(b.st.undecodable, 0);
  ck_assert_uint_le(b.st.undecodable, atomic_load(&garbage_sent));
  /* the forged ones decoded and were refused, and the estimate is as without them (box_run) */
  ck_assert_uint_gt(b.st.refused, 0);
  ck_assert_uint_le(b.st.refused, atomic_load(&forged_sent));
  stop_sim_clean();
  box_free(&b);
}
END_TEST

int main(void) {
  Suite *s = suite_create("estimate_faults");
  TCase *tc = tcase_create("faults");
  tcase_add_checked_fixture(tc, setup, teardown);
  tcase_set_timeout(tc, 120);
  tcase_add_test(tc, drops_20_percent);
  tcase_add_loop_test(tc, daemon_killed_and_restarted, 0, KILL_CASES);
  tcase_add_test(tc, garbage_on_subscribed_channels);
  suite_add_tcase(s, tc);
  SRunner *sr = srunner_create(s);
  srunner_run_all(sr, CK_NORMAL);
  const int failed = srunner_ntests_failed(sr);
  srunner_free(sr);
  return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
