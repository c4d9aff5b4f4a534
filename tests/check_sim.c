/* check_sim: integration tests of comlearn-sim. Every test starts the real daemon binary as a
 * child process on an LCM URL of its own (udpm, port derived from the pid and a counter) and talks
 * to it over LCM like the estimator does. */
#define _POSIX_C_SOURCE 200809L
#include <check.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
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

#include <lcm/lcm.h>

#include "comlearn/comlearn_object_state_t.h"
#include "comlearn/comlearn_sim_control_t.h"
#include "comlearn/comlearn_yumi_command_t.h"
#include "comlearn/comlearn_yumi_status_t.h"
#include "comlearn/math3d.h"
#include "comlearn/model.h"
#include "comlearn/msg.h"
#include "comlearn/placement.h"
#include "comlearn/placement_plan.h"
#include "file_test_util.h"

#define YUMI_URDF COMLEARN_ASSETS_DIR "/yumi/yumi.urdf"
#define ST(name) COMLEARN_YUMI_STATUS_T_##name
#define CMD(name) COMLEARN_YUMI_COMMAND_T_##name
#define OS(name) COMLEARN_OBJECT_STATE_T_##name
#define SCA(name) COMLEARN_SIM_CONTROL_T_##name

enum { HIST_MAX = 20000 };

typedef struct {
  int64_t utime, seq;
  int in_position;
  double q[2][7], qdot[2][7];
} hist_t;

typedef struct {
  pid_t pid;
  lcm_t *lcm;
  char url[128];
  comlearn_msg_subscription_t *sub_st, *sub_os;
  comlearn_msg_stats_t stats;
  comlearn_yumi_status_t st;
  char st_text[512];
  int64_t n_st;
  comlearn_object_state_t os;
  char os_id[128];
  int64_t n_os;
  hist_t *hist;
  size_t n_hist;
} fx_t;

static double now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void on_status(const lcm_recv_buf_t *rb, const char *ch, const void *msg, void *user) {
  (void)rb;
  (void)ch;
  fx_t *f = user;
  const comlearn_yumi_status_t *s = msg;
  f->st = *s;
  snprintf(f->st_text, sizeof f->st_text, "%s", s->error_text);
  f->st.error_text = f->st_text;
  f->n_st++;
  if (f->hist && f->n_hist < HIST_MAX) {
    hist_t *h = &f->hist[f->n_hist++];
    h->utime = s->utime;
    h->seq = s->last_accepted_seq;
    h->in_position = s->in_position;
    memcpy(h->q, s->q_measured_rad, sizeof h->q);
    memcpy(h->qdot, s->qdot_estimated_rad_s, sizeof h->qdot);
  }
}

static void on_object(const lcm_recv_buf_t *rb, const char *ch, const void *msg, void *user) {
  (void)rb;
  (void)ch;
  fx_t *f = user;
  const comlearn_object_state_t *o = msg;
  f->os = *o;
  snprintf(f->os_id, sizeof f->os_id, "%s", o->object_id);
  f->os.object_id = f->os_id;
  f->n_os++;
}

typedef int (*pred_t)(const fx_t *f, const void *arg);

/* Handle LCM until pred holds or timeout_s of wall time passed; 1 when it held. */
static int wait_for(fx_t *f, pred_t pred, const void *arg, double timeout_s) {
  const double end = now_s() + timeout_s;
  while (now_s() < end) {
    if (pred(f, arg)) return 1;
    lcm_handle_timeout(f->lcm, 20);
  }
  return pred(f, arg);
}

static int have_status(const fx_t *f, const void *arg) {
  (void)arg;
  return f->n_st > 0 && f->n_os > 0;
}

static int received_at_least(const fx_t *f, const void *arg) {
  return f->n_st > 0 && f->st.messages_received >= *(const int64_t *)arg;
}

static int undecodable_at_least(const fx_t *f, const void *arg) {
  return f->n_st > 0 && f->st.messages_undecodable >= *(const int64_t *)arg;
}

static int seq_in_position(const fx_t *f, const void *arg) {
  return f->n_st > 0 && f->st.last_accepted_seq == *(const int64_t *)arg && f->st.in_position;
}

static int rejected_at_least(const fx_t *f, const void *arg) {
  return f->n_st > 0 && f->st.messages_rejected >= *(const int64_t *)arg;
}

static int sc_acked(const fx_t *f, const void *arg) {
  return f->n_os > 0 && f->os.sim_control_seq == *(const int64_t *)arg;
}

/* Publish sc and wait up to wait_s for the acknowledgement of `acked` (sc->seq, or what the sim
 * keeps naming for a refused seq); sent again, same seq, while none comes (at most 3 times): a
 * datagram can be lost on a loaded machine. A copy that arrives after its original is refused as
 * a repeated seq, so the callers check the outcome, not only the result code. Returns the copies
 * sent. */
static int sc_send(fx_t *f, const comlearn_sim_control_t *sc, int64_t acked, double wait_s) {
  for (int copies = 1; copies <= 3; ++copies) {
    ck_assert_int_eq(comlearn_sim_control_t_publish(f->lcm, COMLEARN_MSG_CHANNEL_SIM_CONTROL, sc),
                     0);
    if (wait_for(f, sc_acked, &acked, wait_s)) return copies;
  }
  ck_abort_msg("SIM_CONTROL seq %lld: no acknowledgement of %lld", (long long)sc->seq,
               (long long)acked);
  return 0;
}

static unsigned url_counter;

/* Daemons started by this process: a failed assertion (CK_FORK=no) leaves the test early, so the
 * teardown kills whatever is still running. */
enum { PIDS_MAX = 64 };
static pid_t pids[PIDS_MAX];
static int n_pids;

static void kill_leftovers(void) {
  for (int i = 0; i < n_pids; i++) {
    if (pids[i] > 0 && waitpid(pids[i], NULL, WNOHANG) == 0) {
      kill(pids[i], SIGKILL);
      waitpid(pids[i], NULL, 0);
    }
    pids[i] = 0;
  }
  n_pids = 0;
}

static void self_check_udpm(lcm_t *lcm, const char *url);

/* When set, the next spawned sim's stderr goes to this file (its log). */
static const char *spawn_log_path;

static void spawn(fx_t *f, const char *const *extra) {
  memset(f, 0, sizeof *f);
  const unsigned port = 20000u + ((unsigned)getpid() * 8u + url_counter++) % 40000u;
  snprintf(f->url, sizeof f->url, "udpm://239.255.76.67:%u?ttl=0", port);
  f->lcm = lcm_create(f->url);
  ck_assert_msg(f->lcm != NULL,
                "lcm_create(%s) failed: udpm is not usable here. It needs a multicast route: "
                "`ip route add 224.0.0.0/4 dev lo` as root (scripts/setup.sh does it)",
                f->url);
  self_check_udpm(f->lcm, f->url);
  comlearn_msg_sub_config_t c1 = {.type = comlearn_yumi_status_t_get_type_info(),
                                  .on_message = on_status,
                                  .user = f,
                                  .stats = &f->stats};
  comlearn_msg_sub_config_t c2 = {.type = comlearn_object_state_t_get_type_info(),
                                  .on_message = on_object,
                                  .user = f,
                                  .stats = &f->stats};
  ck_assert_int_eq(
      comlearn_msg_subscribe(f->lcm, COMLEARN_MSG_CHANNEL_YUMI_STATUS, &c1, &f->sub_st),
      COMLEARN_MSG_OK);
  ck_assert_int_eq(
      comlearn_msg_subscribe(f->lcm, COMLEARN_MSG_CHANNEL_OBJECT_STATE, &c2, &f->sub_os),
      COMLEARN_MSG_OK);
  comlearn_msg_subscription_set_queue_capacity(f->sub_st, 0);
  /* objects come from $TMPDIR (the tests write them there) and the bundled assets, unless the
   * test names its own --object-dir folders */
  const char *tmp = getenv("TMPDIR") && getenv("TMPDIR")[0] ? getenv("TMPDIR") : "/tmp";
  const char *argv[32] = {COMLEARN_SIM_EXE, "--lcm-url", f->url, "-q"};
  int n = 4, own_dirs = 0;
  for (int i = 0; extra && extra[i]; i++) own_dirs |= strcmp(extra[i], "--object-dir") == 0;
  if (!own_dirs) {
    const char *dirs[] = {"--object-dir", tmp, "--object-dir", COMLEARN_ASSETS_DIR};
    for (int i = 0; i < 4; i++) argv[n++] = dirs[i];
  }
  for (int i = 0; extra && extra[i] && n < 30; i++) argv[n++] = extra[i];
  argv[n] = NULL;
  f->pid = fork();
  ck_assert_int_ge(f->pid, 0);
  if (f->pid > 0 && n_pids < PIDS_MAX) pids[n_pids++] = f->pid;
  if (f->pid == 0) {
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (spawn_log_path) {
      const int fd = open(spawn_log_path, O_WRONLY | O_CREAT | O_TRUNC, 0600);
      if (fd >= 0) dup2(fd, 2);
    }
    execv(COMLEARN_SIM_EXE, (char *const *)argv);
    _exit(127);
  }
  ck_assert_msg(wait_for(f, have_status, NULL, 10.0),
                "no YUMI_STATUS / OBJECT_STATE from comlearn-sim on %s within 10 s", f->url);
}

/* Wait up to timeout_s for the child; returns its wait status or -1. */
static int reap(pid_t pid, double timeout_s) {
  const double end = now_s() + timeout_s;
  int ws;
  while (now_s() < end) {
    pid_t r = waitpid(pid, &ws, WNOHANG);
    if (r == pid) return ws;
    struct timespec ts = {0, 5000000};
    nanosleep(&ts, NULL);
  }
  return -1;
}

static void finish(fx_t *f) {
  ck_assert_msg(kill(f->pid, 0) == 0, "comlearn-sim died during the test");
  kill(f->pid, SIGTERM);
  int ws = reap(f->pid, 1.0);
  if (ws == -1) {
    kill(f->pid, SIGKILL);
    reap(f->pid, 5.0);
    ck_abort_msg("comlearn-sim did not exit within 1 s of SIGTERM");
  }
  ck_assert_msg(WIFEXITED(ws) && WEXITSTATUS(ws) == 0, "comlearn-sim exit status %d", ws);
  comlearn_msg_unsubscribe(f->lcm, f->sub_st);
  comlearn_msg_unsubscribe(f->lcm, f->sub_os);
  lcm_destroy(f->lcm);
  free(f->hist);
}

static volatile int ping_seen;
static void on_ping(const lcm_recv_buf_t *rb, const char *ch, void *u) {
  (void)rb;
  (void)ch;
  (void)u;
  ping_seen = 1;
}

static void self_check_udpm(lcm_t *lcm, const char *url) {
  ping_seen = 0;
  lcm_subscription_t *s = lcm_subscribe(lcm, "CHECK_SIM_PING", on_ping, NULL);
  const char b[4] = "png";
  const double end = now_s() + 3.0;
  while (!ping_seen && now_s() < end) {
    lcm_publish(lcm, "CHECK_SIM_PING", b, sizeof b);
    lcm_handle_timeout(lcm, 100);
  }
  lcm_unsubscribe(lcm, s);
  ck_assert_msg(ping_seen,
                "udpm loopback does not work on %s: a published message never came back. udpm "
                "needs a multicast route: `ip route add 224.0.0.0/4 dev lo` as root "
                "(scripts/setup.sh does it)",
                url);
}

static void send_cmd(fx_t *f, int64_t seq, int8_t mode, const double q[2][7], const double w[2],
                     double scale, int64_t expire) {
  comlearn_yumi_command_t c;
  memset(&c, 0, sizeof c);
  c.utime = seq > 0 && seq < INT64_MAX / 10 ? seq * 10 : 0; /* seq INT64_MAX: envelope_rules */
  c.seq = seq;
  c.expire_utime = expire;
  c.mode = mode;
  c.velocity_scale = scale;
  memcpy(c.q_commanded_rad, q, sizeof c.q_commanded_rad);
  memcpy(c.gripper_width_commanded_m, w, sizeof c.gripper_width_commanded_m);
  ck_assert_int_eq(comlearn_yumi_command_t_publish(f->lcm, COMLEARN_MSG_CHANNEL_YUMI_COMMAND, &c),
                   0);
}

/* Send and wait until the daemon's status reflects it (messages_received grew to `count`). */
static void send_cmd_sync(fx_t *f, int64_t *count, int64_t seq, int8_t mode, const double q[2][7],
                          const double w[2], double scale, int64_t expire) {
  send_cmd(f, seq, mode, q, w, scale, expire);
  ++*count;
  ck_assert_msg(wait_for(f, received_at_least, count, 5.0), "no status after command seq %lld",
                (long long)seq);
}

/* ---- tests ----------------------------------------------------------------------------------- */

static int run_exit(const char *const *args, char *out, size_t out_len) {
  int fd[2];
  ck_assert_int_eq(pipe(fd), 0);
  pid_t pid = fork();
  ck_assert_int_ge(pid, 0);
  if (pid == 0) {
    dup2(fd[1], 1);
    close(fd[0]);
    execv(COMLEARN_SIM_EXE, (char *const *)args);
    _exit(127);
  }
  close(fd[1]);
  size_t n = 0;
  ssize_t r;
  while (n + 1 < out_len && (r = read(fd[0], out + n, out_len - 1 - n)) > 0) n += (size_t)r;
  out[n] = '\0';
  close(fd[0]);
  int ws = reap(pid, 10.0);
  ck_assert_int_ne(ws, -1);
  ck_assert(WIFEXITED(ws));
  return WEXITSTATUS(ws);
}

START_TEST(help_and_bad_options) {
  static char out[8192];
  const char *help[] = {COMLEARN_SIM_EXE, "--help", NULL};
  ck_assert_int_eq(run_exit(help, out, sizeof out), 0);
  const char *opts[] = {"--lcm-url",        "--realtime",
                        "--seed",           "--placement-noise-mm",
                        "--pose-noise-mm",  "--drop-rate",
                        "--channel-prefix", "--yumi-urdf",
                        "--help",           COMLEARN_MSG_LCM_URL_DEFAULT};
  for (size_t i = 0; i < sizeof opts / sizeof opts[0]; i++)
    ck_assert_msg(strstr(out, opts[i]) != NULL, "--help does not mention %s", opts[i]);
  /* every option line carries its default */
  ck_assert_ptr_nonnull(strstr(out, "(default: 1)"));
  ck_assert_ptr_nonnull(strstr(out, "(default: 0)"));
  const char *bad[][4] = {{COMLEARN_SIM_EXE, "--bogus", NULL, NULL},
                          {COMLEARN_SIM_EXE, "--drop-rate", "1.5", NULL},
                          {COMLEARN_SIM_EXE, "--drop-rate", "nan", NULL},
                          {COMLEARN_SIM_EXE, "--seed", "abc", NULL},
                          {COMLEARN_SIM_EXE, "--pose-noise-mm", "-1", NULL},
                          {COMLEARN_SIM_EXE, "--placement-noise-mm", NULL, NULL},
                          {COMLEARN_SIM_EXE, "stray", NULL, NULL}};
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
    ck_assert_msg(run_exit(bad[i], out, sizeof out) == 2, "%s %s: exit code not 2", bad[i][1],
                  bad[i][2] ? bad[i][2] : "");
  const char *nourdf[] = {COMLEARN_SIM_EXE, "--yumi-urdf", "/nonexistent.urdf", NULL};
  ck_assert_int_eq(run_exit(nourdf, out, sizeof out), 1);
}
END_TEST

START_TEST(signals_exit_zero) {
  const int sigs[2] = {SIGTERM, SIGINT};
  for (int i = 0; i < 2; i++) {
    fx_t f;
    spawn(&f, NULL);
    ck_assert_int_eq(f.st.state, ST(STATE_HOLD));
    ck_assert_int_eq(f.st.last_accepted_seq, -1);
    ck_assert(!f.os.tracked);
    ck_assert_int_eq(f.os.sim_control_seq, -1);
    const double t0 = now_s();
    kill(f.pid, sigs[i]);
    int ws = reap(f.pid, 1.0);
    ck_assert_msg(ws != -1, "no exit within 1 s of signal %d", sigs[i]);
    ck_assert(WIFEXITED(ws) && WEXITSTATUS(ws) == 0);
    ck_assert(now_s() - t0 < 1.0);
    comlearn_msg_unsubscribe(f.lcm, f.sub_st);
    comlearn_msg_unsubscribe(f.lcm, f.sub_os);
    lcm_destroy(f.lcm);
  }
}
END_TEST

/* Spawn a sim logging at debug level and up (-v, after the fixture's -q) into
 * TMPDIR/NAME_PID.txt, whose path goes to log. */
static void spawn_logged(fx_t *f, const char *name, char *log, size_t log_size) {
  snprintf(log, log_size, "%s/%s_%d.txt",
           getenv("TMPDIR") && getenv("TMPDIR")[0] ? getenv("TMPDIR") : "/tmp", name,
           (int)getpid());
  spawn_log_path = log;
  const char *info[] = {"-v", NULL};
  spawn(f, info);
  spawn_log_path = NULL;
}

/* As fast as possible, a motion is a burst of ticks: statuses go out at most every 4 ms of wall
 * time, plus at once when the arms come into position, and the acceptance of a command that
 * starts a motion rides on the next of those (docs/sim.md). A 0.67 s motion (167 statuses at 250
 * Hz of sim time) then gives at most 2 + 250 per wall second of statuses, and the one that says
 * "in position" carries the tick the motion ended on, not the next multiple of 4 ms: the sim's
 * log (-v) names the tick it accepted the command on. */
START_TEST(status_events) {
  char log[256];
  fx_t f;
  spawn_logged(&f, "check_sim_events", log, sizeof log);
  f.hist = calloc(HIST_MAX, sizeof *f.hist);
  ck_assert_ptr_nonnull(f.hist);
  placement_arm_t arm;
  ck_assert_int_eq(placement_arm_load_yumi(&arm, YUMI_URDF, PLACEMENT_ARM_RIGHT, NULL),
                   PLACEMENT_OK);
  double q[2][7], w[2] = {0, 0};
  memcpy(q, f.st.q_measured_rad, sizeof q);
  /* 0.21 rad at 180 deg/s x 0.1: 0.6685 s, ending on tick 669 ms, between two multiples of 4 */
  q[1][0] += 0.21;
  const double scale = 0.1, t_exp = 0.21 / (arm.velocity_rad_s[0] * scale);
  f.n_hist = 0;
  int64_t seq = 1;
  const double t0 = now_s();
  send_cmd(&f, seq, CMD(MODE_POSITION), (const double(*)[7])q, w, scale, f.st.utime + 60000000);
  ck_assert(wait_for(&f, seq_in_position, &seq, 10.0));
  const double wall = now_s() - t0;
  int64_t t_done = -1;
  size_t during = 0;
  for (size_t i = 0; i < f.n_hist; i++) {
    const hist_t *h = &f.hist[i];
    if (h->seq != 1) continue;
    if (!h->in_position)
      during++;
    else if (t_done < 0)
      t_done = h->utime;
  }
  ck_assert_int_ge(t_done, 0);
  ck_assert_msg((double)during <= 2.0 + 250.0 * wall,
                "%zu statuses during a motion of %.3f s of sim time, %.4f s of wall time", during,
                t_exp, wall);
  finish(&f);
  size_t len = 0;
  char *text = test_slurp(log, &len);
  ck_assert_ptr_nonnull(text);
  const char *a = strstr(text, "command seq 1 accepted at sim utime ");
  ck_assert_msg(a != NULL, "the sim's log names no acceptance: %s", text);
  const long long t_acc = atoll(a + strlen("command seq 1 accepted at sim utime "));
  const double dur = (double)(t_done - t_acc) * 1e-6;
  ck_assert_msg(dur >= t_exp && dur <= t_exp + 0.001 + 1e-9,
                "in position after %.6f s of controller time, the motion takes %.6f s", dur, t_exp);
  free(text);
  remove(log);
}
END_TEST

/* The receive buffer a URL asks for: comlearn-sim says when net.core.rmem_max gives it less
 * (checked after its first subscription, when LCM has opened the socket), and says nothing when
 * it got it. Asking for twice rmem_max must warn; 64 KiB, below any rmem_max, must not. */
START_TEST(receive_buffer_warned) {
  FILE *f = fopen("/proc/sys/net/core/rmem_max", "r");
  long rmem_max = 0;
  ck_assert_ptr_nonnull(f);
  ck_assert_int_eq(fscanf(f, "%ld", &rmem_max), 1);
  fclose(f);
  const long asked[2] = {2 * rmem_max < INT_MAX ? 2 * rmem_max : INT_MAX, 65536};
  for (int i = 0; i < 2; ++i) {
    char cmd[1024], out[4096];
    const unsigned port = 20000u + ((unsigned)getpid() * 8u + url_counter++) % 40000u;
    snprintf(cmd, sizeof cmd,
             "timeout -s INT 1 '%s' --lcm-url 'udpm://239.255.76.67:%u?ttl=0&recv_buf_size=%ld' "
             "2>&1",
             COMLEARN_SIM_EXE, port, asked[i]);
    FILE *p = popen(cmd, "r");
    ck_assert_ptr_nonnull(p);
    const size_t n = fread(out, 1, sizeof out - 1, p);
    out[n] = '\0';
    pclose(p);
    ck_assert_msg(strstr(out, "running on") != NULL, "the sim did not start: %s", out);
    const int warned = strstr(out, "LCM's receive buffer is") != NULL;
    ck_assert_msg(warned == (i == 0), "recv_buf_size %ld, rmem_max %ld: %s", asked[i], rmem_max,
                  out);
  }
}
END_TEST

/* The trajectory, sampled by the statuses of a --realtime sim (as fast as possible, a motion is
 * a burst of ticks with a status only every 4 ms of wall time, test status_events). */
START_TEST(joint_tracking_velocity_limit) {
  fx_t f;
  const char *realtime[] = {"--realtime", NULL};
  spawn(&f, realtime);
  f.hist = calloc(HIST_MAX, sizeof *f.hist);
  ck_assert_ptr_nonnull(f.hist);
  placement_arm_t arm;
  ck_assert_int_eq(placement_arm_load_yumi(&arm, YUMI_URDF, PLACEMENT_ARM_RIGHT, NULL),
                   PLACEMENT_OK);
  double q0[2][7], q[2][7], w[2] = {0, 0};
  memcpy(q0, f.st.q_measured_rad, sizeof q0);
  memcpy(q, q0, sizeof q);
  q[1][0] += 0.5;
  q[1][4] += 0.8;
  const double scale = 0.5;
  const double t_exp =
      fmax(0.5 / (arm.velocity_rad_s[0] * scale), 0.8 / (arm.velocity_rad_s[4] * scale));
  ck_assert_double_eq_tol(arm.velocity_rad_s[0], CL_PI, 1e-12); /* 180 deg/s */
  f.n_hist = 0;
  int64_t seq = 1;
  send_cmd(&f, seq, CMD(MODE_POSITION), (const double(*)[7])q, w, scale, f.st.utime + 60000000);
  ck_assert(wait_for(&f, seq_in_position, &seq, 10.0));
  /* the acceptance time: the first status naming seq 1 */
  int64_t t_acc = -1, t_done = -1, t_last_moving = -1;
  size_t moving = 0;
  for (size_t i = 0; i < f.n_hist; i++) {
    const hist_t *h = &f.hist[i];
    if (h->seq != 1) continue;
    if (t_acc < 0) t_acc = h->utime;
    const double tt = (double)(h->utime - t_acc) * 1e-6;
    if (!h->in_position) {
      /* straight line at the limiting joint's limit x scale: q(t) = q0 + d t / T */
      const double fr = fmin(1.0, tt / t_exp);
      ck_assert_double_eq_tol(h->q[1][0], q0[1][0] + 0.5 * fr, 1e-5);
      ck_assert_double_eq_tol(h->q[1][4], q0[1][4] + 0.8 * fr, 1e-5);
      if (tt > 0) {
        ck_assert_double_eq_tol(h->qdot[1][0], CL_PI * scale, 1e-5);
        ck_assert_double_eq_tol(h->qdot[1][4], 0.8 / t_exp, 1e-5);
      }
      ck_assert_double_eq_tol(h->q[0][0], q0[0][0], 1e-15);
      t_last_moving = h->utime;
      moving++;
    } else if (t_done < 0) {
      t_done = h->utime;
    }
  }
  ck_assert_int_ge(t_acc, 0);
  ck_assert_int_ge(t_done, 0);
  ck_assert_msg(moving >= 20, "only %zu statuses during the motion", moving);
  const double dur = (double)(t_done - t_acc) * 1e-6;
  ck_assert_msg(dur >= t_exp && dur <= t_exp + 0.005 + 1e-9,
                "motion took %.6f s of controller time, formula %.6f s", dur, t_exp);
  ck_assert((double)(t_last_moving - t_acc) * 1e-6 < t_exp + 0.001);
  ck_assert_double_eq_tol(f.st.q_measured_rad[1][0], q[1][0], 1e-12);
  ck_assert_double_eq_tol(f.st.q_measured_rad[1][4], q[1][4], 1e-12);
  ck_assert_double_eq(f.st.qdot_estimated_rad_s[1][0], 0.0);
  ck_assert_int_eq(f.st.state, ST(STATE_POSITION));
  ck_assert_int_eq(f.st.error_code, ST(ERR_NONE));
  finish(&f);
}
END_TEST

START_TEST(seq_rules) {
  fx_t f;
  spawn(&f, NULL);
  double q[2][7], w[2] = {0, 0};
  memcpy(q, f.st.q_measured_rad, sizeof q);
  int64_t n = 0;
  const int64_t far = f.st.utime + 30000000; /* within SIM_EXPIRE_MAX_US */
  send_cmd_sync(&f, &n, 5, CMD(MODE_HOLD), (const double(*)[7])q, w, 1.0, far);
  ck_assert_int_eq(f.st.last_accepted_seq, 5);
  ck_assert_int_eq(f.st.last_accepted_utime, 50);
  ck_assert_int_eq(f.st.error_code, ST(ERR_NONE));
  /* duplicate and out of order: ignored with ERR_SEQ */
  double q2[2][7];
  memcpy(q2, q, sizeof q2);
  q2[1][0] += 0.3;
  send_cmd_sync(&f, &n, 5, CMD(MODE_POSITION), (const double(*)[7])q2, w, 1.0, far);
  ck_assert_int_eq(f.st.error_code, ST(ERR_SEQ));
  ck_assert_int_eq(f.st.last_accepted_seq, 5);
  ck_assert_int_eq(f.st.state, ST(STATE_HOLD));
  ck_assert_int_eq(f.st.messages_rejected, 1);
  send_cmd_sync(&f, &n, 3, CMD(MODE_POSITION), (const double(*)[7])q2, w, 1.0, far);
  ck_assert_int_eq(f.st.error_code, ST(ERR_SEQ));
  ck_assert_int_eq(f.st.messages_rejected, 2);
  ck_assert_double_eq(f.st.q_measured_rad[1][0], q[1][0]);
  /* stale: the controller clock is at or past expire_utime */
  send_cmd_sync(&f, &n, 6, CMD(MODE_POSITION), (const double(*)[7])q2, w, 1.0, f.st.utime - 1);
  ck_assert_int_eq(f.st.error_code, ST(ERR_STALE));
  ck_assert_int_eq(f.st.last_accepted_seq, 5);
  ck_assert_int_eq(f.st.messages_rejected, 3);
  ck_assert_ptr_nonnull(strstr(f.st.error_text, "stale"));
  /* the next good one is accepted and clears the error */
  send_cmd_sync(&f, &n, 7, CMD(MODE_POSITION), (const double(*)[7])q2, w, 1.0, far);
  ck_assert_int_eq(f.st.last_accepted_seq, 7);
  ck_assert_int_eq(f.st.error_code, ST(ERR_NONE));
  int64_t seq = 7;
  ck_assert(wait_for(&f, seq_in_position, &seq, 5.0));
  ck_assert_double_eq_tol(f.st.q_measured_rad[1][0], q2[1][0], 1e-12);
  /* expiry while executing: stop and hold with ERR_EXPIRED */
  double q3[2][7];
  memcpy(q3, q2, sizeof q3);
  q3[1][0] -= 0.6;
  const int64_t exp_at = f.st.utime + 100000; /* motion needs ~0.19 s */
  send_cmd_sync(&f, &n, 8, CMD(MODE_POSITION), (const double(*)[7])q3, w, 1.0, exp_at);
  const double end = now_s() + 5.0;
  while (now_s() < end && f.st.error_code != ST(ERR_EXPIRED)) lcm_handle_timeout(f.lcm, 20);
  ck_assert_int_eq(f.st.error_code, ST(ERR_EXPIRED));
  ck_assert_int_eq(f.st.state, ST(STATE_HOLD));
  ck_assert(f.st.q_measured_rad[1][0] > q3[1][0] + 0.1); /* stopped part-way */
  ck_assert_double_eq(f.st.q_commanded_rad[1][0], f.st.q_measured_rad[1][0]);
  finish(&f);
}
END_TEST

/* The safety envelope (docs/sim.md): a command whose seq jumps far ahead (INT64_MAX), that never
 * expires (expire_utime INT64_MAX) or expires more than 60 s ahead, with velocity_scale 1e-300
 * (its motion time overflows), a motion over 120 s long, or a target that swings the tool out of
 * the workspace box over B is refused with its reason, and the next normal command is accepted
 * and executed; a SIM_CONTROL with seq INT64_MAX is ignored (ERR_SEQ) and the next one
 * processed. */
START_TEST(envelope_rules) {
  fx_t f;
  spawn(&f, NULL);
  double q[2][7], w[2] = {0, 0};
  memcpy(q, f.st.q_measured_rad, sizeof q);
  int64_t n = 0;
  const int64_t soon = f.st.utime + 30000000;
  send_cmd_sync(&f, &n, 1, CMD(MODE_HOLD), (const double(*)[7])q, w, 1.0, soon);
  ck_assert_int_eq(f.st.last_accepted_seq, 1);
  double q2[2][7];
  memcpy(q2, q, sizeof q2);
  q2[1][0] += 0.3;
  const struct {
    int64_t seq, expire;
    double scale, width;
    int32_t code;
    const char *why;
  } cases[] = {
      {INT64_MAX, soon, 1.0, 0.0, ST(ERR_SEQ), "jumps"},
      {2, INT64_MAX, 1.0, 0.0, ST(ERR_INVALID), "more than 60 s"},
      {2, f.st.utime + 61000000, 1.0, 0.0, ST(ERR_INVALID), "more than 60 s"},
      {2, soon, 1e-300, 0.0, ST(ERR_INVALID), "velocity_scale"},
      {2, soon, 1e-3, 0.05, ST(ERR_INVALID), "would take"}, /* 50 mm of gripper: 2000 s */
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
    const int64_t rejected = f.st.messages_rejected;
    const double wi[2] = {0.0, cases[i].width};
    send_cmd_sync(&f, &n, cases[i].seq, CMD(MODE_POSITION), (const double(*)[7])q2, wi,
                  cases[i].scale, cases[i].expire);
    ck_assert_msg(f.st.error_code == cases[i].code, "case %zu: error %d (%s)", i,
                  (int)f.st.error_code, f.st.error_text);
    ck_assert_msg(strstr(f.st.error_text, cases[i].why) != NULL, "case %zu: %s", i,
                  f.st.error_text);
    ck_assert_int_eq(f.st.last_accepted_seq, 1);
    ck_assert_int_eq(f.st.messages_rejected, rejected + 1);
  }
  /* the workspace box: the right arm's base joint near its limit swings the tool behind the
   * robot, far outside the box over B (B spans x in [0.25, 0.55] m of the robot's frame) */
  placement_arm_t arm;
  ck_assert_int_eq(placement_arm_load_yumi(&arm, YUMI_URDF, PLACEMENT_ARM_RIGHT, NULL),
                   PLACEMENT_OK);
  double q4[2][7];
  memcpy(q4, q, sizeof q4);
  q4[1][0] = arm.lower_rad[0] + 0.05;
  placement_pose_t tip;
  ck_assert_int_eq(placement_fk(&arm, q4[1], &tip), PLACEMENT_OK);
  ck_assert_msg(tip.pos_m[0] < 0.40 - 0.15 - 0.35, "the test pose is inside the box: x %.3f m",
                tip.pos_m[0]);
  send_cmd_sync(&f, &n, 2, CMD(MODE_POSITION), (const double(*)[7])q4, w, 1.0, soon);
  ck_assert_int_eq(f.st.error_code, ST(ERR_INVALID));
  ck_assert_msg(strstr(f.st.error_text, "workspace box") != NULL, "%s", f.st.error_text);
  ck_assert_int_eq(f.st.last_accepted_seq, 1);
  send_cmd_sync(&f, &n, 2, CMD(MODE_POSITION), (const double(*)[7])q2, w, 1.0, soon);
  ck_assert_int_eq(f.st.last_accepted_seq, 2);
  ck_assert_int_eq(f.st.error_code, ST(ERR_NONE));
  int64_t seq = 2;
  ck_assert(wait_for(&f, seq_in_position, &seq, 5.0));
  ck_assert_double_eq_tol(f.st.q_measured_rad[1][0], q2[1][0], 1e-12);

  comlearn_sim_control_t sc;
  memset(&sc, 0, sizeof sc);
  sc.action = SCA(ACTION_REMOVE);
  sc.object_id = (char *)"nothing";
  sc.urdf_path = (char *)"";
  sc.seq = INT64_MAX;
  sc_send(&f, &sc, -1, 2.5); /* nothing processed yet: the acknowledgement keeps naming -1 */
  sc.seq = 1;
  sc_send(&f, &sc, 1, 2.5); /* processed after INT64_MAX */
  finish(&f);
}
END_TEST

/* Refusals are counted by reason and logged when the sim stops: 1 duplicate seq, 2 stale and
 * 1 unknown-mode command, 1 SIM_CONTROL with action 0 and 1 with a seq already processed. */
START_TEST(refusals_counted) {
  char log[256];
  fx_t f;
  spawn_logged(&f, "check_sim_log", log, sizeof log);
  double q[2][7], w[2] = {0, 0};
  memcpy(q, f.st.q_measured_rad, sizeof q);
  int64_t n = 0;
  const int64_t soon = f.st.utime + 30000000;
  send_cmd_sync(&f, &n, 1, CMD(MODE_HOLD), (const double(*)[7])q, w, 1.0, soon);
  send_cmd_sync(&f, &n, 1, CMD(MODE_HOLD), (const double(*)[7])q, w, 1.0, soon); /* seq */
  send_cmd_sync(&f, &n, 2, CMD(MODE_HOLD), (const double(*)[7])q, w, 1.0, 0);    /* stale */
  send_cmd_sync(&f, &n, 3, CMD(MODE_HOLD), (const double(*)[7])q, w, 1.0, 0);    /* stale */
  send_cmd_sync(&f, &n, 4, 9, (const double(*)[7])q, w, 1.0, soon);              /* mode */
  ck_assert_int_eq(f.st.messages_rejected, 4);
  comlearn_sim_control_t sc;
  memset(&sc, 0, sizeof sc);
  sc.object_id = (char *)"x";
  sc.urdf_path = (char *)"";
  sc.seq = 1; /* action 0: SIM_CONTROL_ERR_INVALID */
  ck_assert_int_eq(comlearn_sim_control_t_publish(f.lcm, COMLEARN_MSG_CHANNEL_SIM_CONTROL, &sc), 0);
  int64_t one = 1;
  ck_assert(wait_for(&f, sc_acked, &one, 5.0));
  ck_assert_int_eq(comlearn_sim_control_t_publish(f.lcm, COMLEARN_MSG_CHANNEL_SIM_CONTROL, &sc), 0);
  int64_t rejected = 6;
  ck_assert(wait_for(&f, rejected_at_least, &rejected, 5.0));
  finish(&f);
  size_t len = 0;
  char *text = test_slurp(log, &len);
  ck_assert_ptr_nonnull(text);
  ck_assert_msg(strstr(text,
                       "commands refused: 1 seq, 2 stale, 1 invalid, 0 stopped; SIM_CONTROL "
                       "not applied: 1 seq, 1 invalid, 0 load, 0 unknown id") != NULL,
                "log: %s", text);
  free(text);
  remove(log);
}
END_TEST

START_TEST(invalid_commands_refused) {
  fx_t f;
  spawn(&f, NULL);
  placement_arm_t arm;
  ck_assert_int_eq(placement_arm_load_yumi(&arm, YUMI_URDF, PLACEMENT_ARM_RIGHT, NULL),
                   PLACEMENT_OK);
  double q[2][7], w[2] = {0.01, 0.01};
  memcpy(q, f.st.q_measured_rad, sizeof q);
  const int64_t far = f.st.utime + 30000000; /* within SIM_EXPIRE_MAX_US */
  int64_t n = 0, seq = 0;
  struct {
    int arm, joint;
    double v;
  } bad_q[] = {{1, 0, NAN}, {0, 3, INFINITY}, {1, 1, 0.0}, {0, 6, -INFINITY}};
  bad_q[2].v = arm.upper_rad[1] + 1e-9;
  for (size_t i = 0; i < sizeof bad_q / sizeof bad_q[0]; i++) {
    double qb[2][7];
    memcpy(qb, q, sizeof qb);
    qb[bad_q[i].arm][bad_q[i].joint] = bad_q[i].v;
    send_cmd_sync(&f, &n, ++seq, CMD(MODE_POSITION), (const double(*)[7])qb, w, 1.0, far);
    ck_assert_int_eq(f.st.error_code, ST(ERR_INVALID));
    ck_assert_ptr_nonnull(strstr(f.st.error_text, "q_commanded_rad"));
  }
  const double bad_w[] = {0.0500001, -1e-9, NAN};
  for (size_t i = 0; i < 3; i++) {
    double wb[2] = {0.01, bad_w[i]};
    send_cmd_sync(&f, &n, ++seq, CMD(MODE_POSITION), (const double(*)[7])q, wb, 1.0, far);
    ck_assert_int_eq(f.st.error_code, ST(ERR_INVALID));
  }
  const double bad_scale[] = {0.0, 1.0000001, NAN, INFINITY, -0.5};
  for (size_t i = 0; i < 5; i++) {
    send_cmd_sync(&f, &n, ++seq, CMD(MODE_POSITION), (const double(*)[7])q, w, bad_scale[i], far);
    ck_assert_int_eq(f.st.error_code, ST(ERR_INVALID));
    ck_assert_ptr_nonnull(strstr(f.st.error_text, "velocity_scale"));
  }
  send_cmd_sync(&f, &n, ++seq, 9, (const double(*)[7])q, w, 1.0, far);
  ck_assert_int_eq(f.st.error_code, ST(ERR_INVALID));
  ck_assert_int_eq(f.st.last_accepted_seq, -1);
  ck_assert_int_eq(f.st.messages_rejected, seq);
  ck_assert_int_eq(f.st.state, ST(STATE_HOLD));
  /* STOP latches; POSITION refused with ERR_STOPPED until a HOLD */
  send_cmd_sync(&f, &n, ++seq, CMD(MODE_STOP), (const double(*)[7])q, w, 0.0, far);
  ck_assert_int_eq(f.st.state, ST(STATE_STOPPED));
  send_cmd_sync(&f, &n, ++seq, CMD(MODE_POSITION), (const double(*)[7])q, w, 1.0, far);
  ck_assert_int_eq(f.st.error_code, ST(ERR_STOPPED));
  send_cmd_sync(&f, &n, ++seq, CMD(MODE_HOLD), (const double(*)[7])q, w, 0.0, far);
  ck_assert_int_eq(f.st.state, ST(STATE_HOLD));
  send_cmd_sync(&f, &n, ++seq, CMD(MODE_POSITION), (const double(*)[7])q, w, 1.0, far);
  ck_assert_int_eq(f.st.error_code, ST(ERR_NONE));
  ck_assert_int_eq(f.st.state, ST(STATE_POSITION));
  ck_assert_int_eq(f.st.last_accepted_seq, seq);

  /* SIM_CONTROL refusals, acknowledged on OBJECT_STATE */
  comlearn_sim_control_t sc;
  memset(&sc, 0, sizeof sc);
  sc.object_id = (char *)"box";
  sc.urdf_path = (char *)"";
  sc.link_in_tool_wxyz[0] = 1.0;
  sc.gripper_width_m = 0.02;
  struct {
    int8_t action;
    const char *path;
    double qw;
    int32_t want;
  } cases[] = {{0, "", 1.0, OS(SIM_CONTROL_ERR_INVALID)},
               {SCA(ACTION_RESET), "", 1.0, OS(SIM_CONTROL_ERR_UNKNOWN_ID)},
               {SCA(ACTION_REMOVE), "", 1.0, OS(SIM_CONTROL_ERR_UNKNOWN_ID)},
               {SCA(ACTION_LOAD), "/nonexistent/box.urdf", 1.0, OS(SIM_CONTROL_ERR_LOAD)},
               {SCA(ACTION_LOAD), YUMI_URDF, 1.0, OS(SIM_CONTROL_ERR_LOAD)}, /* no geometry */
               {SCA(ACTION_LOAD), "/x.urdf", NAN, OS(SIM_CONTROL_ERR_INVALID)},
               {SCA(ACTION_LOAD), "/x.urdf", 0.5, OS(SIM_CONTROL_ERR_INVALID)}};
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    sc.seq = (int64_t)i + 1;
    sc.action = cases[i].action;
    sc.urdf_path = (char *)cases[i].path;
    sc.link_in_tool_wxyz[0] = cases[i].qw;
    const int copies = sc_send(&f, &sc, sc.seq, 2.5);
    ck_assert_msg(f.os.sim_control_result == cases[i].want ||
                      (copies > 1 && f.os.sim_control_result == OS(SIM_CONTROL_ERR_SEQ)),
                  "case %zu: result %d, want %d", i, f.os.sim_control_result, cases[i].want);
    ck_assert(!f.os.tracked);
  }
  /* a repeated seq: ERR_SEQ; the acknowledgement keeps the last processed seq */
  const int64_t rejected = f.st.messages_rejected;
  ck_assert_int_eq(comlearn_sim_control_t_publish(f.lcm, COMLEARN_MSG_CHANNEL_SIM_CONTROL, &sc), 0);
  const double end = now_s() + 5.0;
  while (now_s() < end && f.os.sim_control_result != OS(SIM_CONTROL_ERR_SEQ))
    lcm_handle_timeout(f.lcm, 20);
  ck_assert_int_eq(f.os.sim_control_result, OS(SIM_CONTROL_ERR_SEQ));
  ck_assert_int_eq(f.os.sim_control_seq, sc.seq);
  ck_assert(wait_for(&f, have_status, NULL, 1.0));
  lcm_handle_timeout(f.lcm, 50);
  ck_assert_int_eq(f.st.messages_rejected, rejected + 1);
  finish(&f);
}
END_TEST

static void publish_raw(fx_t *f, const char *ch, const void *b, size_t n) {
  ck_assert_int_eq(lcm_publish(f->lcm, ch, b, (unsigned)n), 0);
}

START_TEST(garbage_counted) {
  fx_t f;
  spawn(&f, NULL);
  static unsigned char buf[4096], buf2[4096];
  int64_t sent = 0;
  /* YUMI_COMMAND */
  comlearn_yumi_command_t c;
  memset(&c, 0, sizeof c);
  c.seq = 1;
  c.expire_utime = INT64_MAX;
  int len = comlearn_yumi_command_t_encode(buf, 0, sizeof buf, &c);
  ck_assert_int_gt(len, 20);
  publish_raw(&f, COMLEARN_MSG_CHANNEL_YUMI_COMMAND, buf, (size_t)len - 5); /* truncated */
  memcpy(buf2, buf, (size_t)len);
  buf2[len] = 0x42;
  publish_raw(&f, COMLEARN_MSG_CHANNEL_YUMI_COMMAND, buf2, (size_t)len + 1); /* trailing byte */
  comlearn_yumi_status_t st;
  memset(&st, 0, sizeof st);
  st.error_text = (char *)"";
  int slen = comlearn_yumi_status_t_encode(buf2, 0, sizeof buf2, &st);
  publish_raw(&f, COMLEARN_MSG_CHANNEL_YUMI_COMMAND, buf2, (size_t)slen); /* wrong fingerprint */
  uint64_t rng = 7;
  for (int i = 0; i < 300; i++) buf2[i] = (unsigned char)(cl_rng_next(&rng) & 0xff);
  publish_raw(&f, COMLEARN_MSG_CHANNEL_YUMI_COMMAND, buf2, 300); /* garbage */
  publish_raw(&f, COMLEARN_MSG_CHANNEL_YUMI_COMMAND, buf2, 3);   /* shorter than a fingerprint */
  sent += 5;
  /* SIM_CONTROL */
  comlearn_sim_control_t sc;
  memset(&sc, 0, sizeof sc);
  sc.seq = 1;
  sc.object_id = (char *)"box";
  sc.urdf_path = (char *)"/tmp/x.urdf";
  len = comlearn_sim_control_t_encode(buf, 0, sizeof buf, &sc);
  ck_assert_int_gt(len, 30);
  publish_raw(&f, COMLEARN_MSG_CHANNEL_SIM_CONTROL, buf, (size_t)len - 1); /* truncated */
  memcpy(buf2, buf, (size_t)len);
  /* object_id's length after fingerprint, utime, seq, action: -1 (crashes lcm-gen's decoder) */
  memset(buf2 + 25, 0xff, 4);
  publish_raw(&f, COMLEARN_MSG_CHANNEL_SIM_CONTROL, buf2, (size_t)len);
  memcpy(buf2, buf, (size_t)len);
  buf2[25 + 4 + 3] = 'X'; /* object_id "box\0" -> "boxX": NUL missing */
  publish_raw(&f, COMLEARN_MSG_CHANNEL_SIM_CONTROL, buf2, (size_t)len);
  publish_raw(&f, COMLEARN_MSG_CHANNEL_SIM_CONTROL, buf2 + 8, 40); /* garbage */
  slen = comlearn_yumi_status_t_encode(buf2, 0, sizeof buf2, &st);
  publish_raw(&f, COMLEARN_MSG_CHANNEL_SIM_CONTROL, buf2, (size_t)slen); /* wrong fingerprint */
  sent += 5;
  ck_assert_msg(wait_for(&f, undecodable_at_least, &sent, 5.0),
                "messages_undecodable %lld, sent %lld bad buffers",
                (long long)f.st.messages_undecodable, (long long)sent);
  ck_assert_int_eq(f.st.messages_undecodable, sent);
  ck_assert_int_eq(f.st.messages_received, 0);
  ck_assert_int_eq(f.st.error_code, ST(ERR_DECODE));
  ck_assert_ptr_nonnull(strstr(f.st.error_text, "SIM_CONTROL"));
  ck_assert_int_eq(f.os.sim_control_seq, -1);
  /* still alive and obeying */
  double q[2][7], w[2] = {0, 0};
  memcpy(q, f.st.q_measured_rad, sizeof q);
  int64_t n = 0;
  send_cmd_sync(&f, &n, 1, CMD(MODE_HOLD), (const double(*)[7])q, w, 1.0, f.st.utime + 60000000);
  ck_assert_int_eq(f.st.last_accepted_seq, 1);
  ck_assert_int_eq(f.st.error_code, ST(ERR_NONE));
  ck_assert_int_eq(f.st.messages_undecodable, sent);
  finish(&f);
}
END_TEST

/* A 1.5 MiB buffer on YUMI_COMMAND (24 datagrams of 64 KiB in one burst) is counted either way:
 * as undecodable when it arrives whole, or, when the burst overflows the sim's receive buffer
 * and LCM drops the incomplete message, among the datagrams lost to a full receive buffer that
 * the sim logs when it stops (cli_udp_rcvbuf_errors: its socket's own drop count also holds what
 * its filter turned away, its own statuses first); the sim goes on obeying. Five are sent. */
START_TEST(oversized_message_counted) {
  char log[256];
  fx_t f;
  spawn_logged(&f, "check_sim_big", log, sizeof log);
  const size_t big = 1536u * 1024u;
  unsigned char *buf = malloc(big);
  ck_assert_ptr_nonnull(buf);
  uint64_t rng = 11;
  for (size_t i = 0; i < big; i++) buf[i] = (unsigned char)(cl_rng_next(&rng) & 0xff);
  for (int i = 0; i < 5; i++) publish_raw(&f, COMLEARN_MSG_CHANNEL_YUMI_COMMAND, buf, big);
  free(buf);
  double q[2][7], w[2] = {0, 0};
  memcpy(q, f.st.q_measured_rad, sizeof q);
  int64_t n = 0;
  send_cmd_sync(&f, &n, 1, CMD(MODE_HOLD), (const double(*)[7])q, w, 1.0, f.st.utime + 60000000);
  ck_assert_int_eq(f.st.last_accepted_seq, 1);
  const long long undecodable = (long long)f.st.messages_undecodable;
  finish(&f);
  size_t len = 0;
  char *text = test_slurp(log, &len);
  ck_assert_ptr_nonnull(text);
  const char *k = strstr(text, "datagrams lost to a full receive buffer");
  ck_assert_msg(k != NULL, "log: %s", text);
  while (k > text && k[-1] != ' ') --k; /* back to the count before the phrase */
  while (k > text && k[-1] == ' ') --k;
  while (k > text && k[-1] >= '0' && k[-1] <= '9') --k;
  const long long dropped = atoll(k);
  fprintf(stderr, "oversized messages: %lld undecodable, %lld datagrams lost to full buffers\n",
          undecodable, dropped);
  ck_assert_msg(undecodable >= 1 || dropped >= 1,
                "neither undecodable (%lld) nor lost to a full buffer (%lld): %s", undecodable,
                dropped, text);
  ck_assert_int_le(undecodable, 5);
  free(text);
  remove(log);
}
END_TEST

/* ---- a placement trial end to end ---------------------------------------------------------- */

/* A 40 x 60 x 50 mm box with its CoM at (com_x, 0, 0) and mass mass_kg (the inertia is that of
 * about 0.2 kg). */
static void write_box_urdf_mass(const char *path, double com_x, double mass_kg) {
  FILE *fp = fopen(path, "w");
  ck_assert_ptr_nonnull(fp);
  fprintf(
      fp,
      "<?xml version=\"1.0\"?>\n<robot name=\"box\">\n <link name=\"box\">\n"
      "  <inertial><origin xyz=\"%.17g 0 0\" rpy=\"0 0 0\"/><mass value=\"%.17g\"/>\n"
      "   <inertia ixx=\"1.0e-4\" ixy=\"0\" ixz=\"0\" iyy=\"0.7e-4\" iyz=\"0\" izz=\"0.9e-4\"/>"
      "</inertial>\n"
      "  <collision><origin xyz=\"0 0 0\" rpy=\"0 0 0\"/><geometry><box size=\"0.04 0.06 0.05\"/>"
      "</geometry></collision>\n </link>\n</robot>\n",
      com_x, mass_kg);
  fclose(fp);
}

static void write_box_urdf(const char *path, double com_x) {
  write_box_urdf_mass(path, com_x, 0.2);
}

static int trial_over(const fx_t *f, const void *arg) {
  const int64_t t = *(const int64_t *)arg;
  return f->n_os > 0 && f->os.utime > t && (f->os.at_rest || !f->os.on_base);
}

/* Load / reset the box into the right gripper, plan with lib/placement so that link point
 * (point_x, 0, 0) is over B's +x edge, drive the four waypoints over LCM, and return the outcome
 * OBJECT_STATE reports: 1 stays (at rest on B), 2 tips (off B). */
static int place_trial(fx_t *f, const char *urdf, int first, int64_t *sc_seq, int64_t *seq,
                       double point_x) {
  comlearn_sim_control_t sc;
  memset(&sc, 0, sizeof sc);
  sc.seq = ++*sc_seq;
  sc.action = first ? SCA(ACTION_LOAD) : SCA(ACTION_RESET);
  sc.object_id = (char *)"box_test";
  sc.urdf_path = (char *)(first ? urdf : "");
  sc.arm = SCA(ARM_RIGHT);
  /* top-down grasp: tcp z down, the tcp 15 mm below the box top; fingers across the 40 mm side */
  sc.link_in_tool_position_m[2] = 0.010;
  sc.link_in_tool_wxyz[1] = 1.0;
  sc.gripper_width_m = 0.04;
  const int sc_copies = sc_send(f, &sc, sc.seq, 2.5);
  ck_assert(f->os.sim_control_result == OS(SIM_CONTROL_APPLIED) ||
            (sc_copies > 1 && f->os.sim_control_result == OS(SIM_CONTROL_ERR_SEQ)));
  ck_assert(f->os.tracked);
  ck_assert(!f->os.on_base);
  ck_assert_str_eq(f->os.object_id, "box_test");

  placement_arm_t arm;
  ck_assert_int_eq(placement_arm_load_yumi(&arm, YUMI_URDF, PLACEMENT_ARM_RIGHT, NULL),
                   PLACEMENT_OK);
  model_object_t mo;
  ck_assert_int_eq(model_object_load(urdf, NULL, &mo, NULL), MODEL_OK);
  placement_plan_config_t cfg;
  placement_plan_config_default(&cfg);
  placement_plan_request_t req;
  memset(&req, 0, sizeof req);
  req.mesh_link = &mo.mesh;
  const double g_pos[3] = {0, 0, 0.010}, g_q[4] = {0, 1, 0, 0};
  ck_assert_int_eq(placement_pose_from_wxyz(g_pos, g_q, &req.object_in_tcp), PLACEMENT_OK);
  placement_pose_identity(&req.object_in_block);
  req.object_in_block.pos_m[0] = 0.5 * cfg.block_size_m[0] - point_x;
  req.grip_width_m = 0.04;
  memcpy(req.q_start_rad, f->st.q_measured_rad[1], sizeof req.q_start_rad);
  placement_plan_t plan;
  placement_error_t pe;
  placement_status_t ps = placement_plan_build(&arm, &cfg, &req, &plan, &pe);
  ck_assert_msg(ps == PLACEMENT_OK, "plan: %s %s", placement_status_str(ps), pe.msg);

  int64_t t_released = 0;
  for (int k = 0; k < PLACEMENT_PLAN_WAYPOINTS; k++) {
    const placement_waypoint_t *wp = &plan.waypoints[k];
    double q[2][7], w[2];
    memcpy(q, f->st.q_measured_rad, sizeof q);
    memcpy(q[1], wp->q_rad, sizeof q[1]);
    w[0] = f->st.gripper_width_measured_m[0];
    w[1] = wp->gripper_width_m;
    ++*seq;
    /* sent again while not in position, as the estimator resends: a datagram can be lost when
     * the machine is loaded (the sim's receive buffer overflows); a copy that arrives after the
     * first is refused as a duplicate seq, which leaves the command running */
    int reached = 0, copies = 0;
    for (; copies < 10 && !reached; ++copies) {
      send_cmd(f, *seq, CMD(MODE_POSITION), (const double(*)[7])q, w, 1.0,
               f->st.utime + (int64_t)(wp->duration_s * 4e6) + 2000000);
      reached = wait_for(f, seq_in_position, seq, 1.0 + 4.0 * wp->duration_s);
    }
    ck_assert_msg(reached, "waypoint %d not reached", k);
    ck_assert_msg(
        f->st.error_code == ST(ERR_NONE) || (copies > 1 && f->st.error_code == ST(ERR_SEQ)),
        "waypoint %d: error %d", k, (int)f->st.error_code);
    if (wp->kind == PLACEMENT_WAYPOINT_PLACE) {
      /* still held, exactly at the planned pose (world = yumi_body; B at block_in_base) */
      ck_assert(wait_for(f, have_status, NULL, 1.0));
      lcm_handle_timeout(f->lcm, 50);
      placement_pose_t want;
      placement_pose_mul(&cfg.block_in_base, &plan.object_in_block, &want);
      for (int i = 0; i < 3; i++)
        ck_assert_double_eq_tol(f->os.position_measured_m[i], want.pos_m[i], 1e-6);
      ck_assert(!f->os.on_base);
    }
    if (wp->kind == PLACEMENT_WAYPOINT_RELEASE) {
      t_released = f->st.utime;
      break;
    }
  }
  model_object_free(&mo);
  ck_assert_msg(wait_for(f, trial_over, &t_released, 10.0), "no trial outcome on OBJECT_STATE");
  ck_assert(f->os.tracked);
  if (f->os.at_rest && f->os.on_base) return 1;
  ck_assert(!f->os.on_base);
  return 2;
}

START_TEST(place_box_over_edge) {
  fx_t f;
  spawn(&f, NULL);
  char urdf[256];
  snprintf(urdf, sizeof urdf, "%s/check_sim_box_%d.urdf",
           getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp", (int)getpid());
  const double com_x = 0.006; /* the truth, known to this test and the simulator only */
  write_box_urdf(urdf, com_x);
  int64_t sc_seq = 0, seq = 0;
  /* CoM 2 mm inside B's edge: stays. 2 mm beyond: tips. And closer: 0.3 mm either way. */
  ck_assert_int_eq(place_trial(&f, urdf, 1, &sc_seq, &seq, com_x + 0.002), 1);
  ck_assert_int_eq(place_trial(&f, urdf, 0, &sc_seq, &seq, com_x - 0.002), 2);
  ck_assert_int_eq(place_trial(&f, urdf, 0, &sc_seq, &seq, com_x + 0.0003), 1);
  ck_assert_int_eq(place_trial(&f, urdf, 0, &sc_seq, &seq, com_x - 0.0003), 2);

  /* a release far above B is refused and flagged, not simulated as a drop */
  comlearn_sim_control_t sc;
  memset(&sc, 0, sizeof sc);
  sc.seq = ++sc_seq;
  sc.action = SCA(ACTION_RESET);
  sc.object_id = (char *)"box_test";
  sc.urdf_path = (char *)"";
  sc.arm = SCA(ARM_RIGHT);
  sc.link_in_tool_wxyz[0] = 1.0;
  sc.gripper_width_m = 0.02;
  sc_send(&f, &sc, sc_seq, 2.5);
  double q[2][7], w[2];
  memcpy(q, f.st.q_measured_rad, sizeof q);
  w[0] = f.st.gripper_width_measured_m[0];
  w[1] = 0.03;
  ++seq;
  send_cmd(&f, seq, CMD(MODE_POSITION), (const double(*)[7])q, w, 1.0, f.st.utime + 5000000);
  ck_assert(wait_for(&f, seq_in_position, &seq, 5.0));
  ck_assert_int_eq(f.st.error_code, ST(ERR_FAULT));
  ck_assert_ptr_nonnull(strstr(f.st.error_text, "release refused"));
  ck_assert(!f.os.on_base);
  ck_assert(!f.os.at_rest);
  remove(urdf);
  finish(&f);
}
END_TEST

static int status_says_load_refused(const fx_t *f, const void *arg) {
  return f->n_st > 0 && strstr(f->st.error_text, (const char *)arg) != NULL;
}

/* SIM_CONTROL LOAD of urdf as id into the right gripper (the next seq); it must be answered
 * within wait_s with SIM_CONTROL_ERR_LOAD. */
static void load_refused(fx_t *f, int64_t *sc_seq, const char *id, const char *urdf,
                         double wait_s) {
  comlearn_sim_control_t sc;
  memset(&sc, 0, sizeof sc);
  sc.seq = ++*sc_seq;
  sc.action = SCA(ACTION_LOAD);
  sc.object_id = (char *)id;
  sc.urdf_path = (char *)urdf;
  sc.arm = SCA(ARM_RIGHT);
  sc.link_in_tool_position_m[2] = 0.010;
  sc.link_in_tool_wxyz[1] = 1.0;
  sc.gripper_width_m = 0.04;
  const int copies = sc_send(f, &sc, sc.seq, wait_s);
  ck_assert_msg(f->os.sim_control_result == OS(SIM_CONTROL_ERR_LOAD) ||
                    (copies > 1 && f->os.sim_control_result == OS(SIM_CONTROL_ERR_SEQ)),
                "LOAD of %s: result %d", urdf, f->os.sim_control_result);
}

/* A LOAD of a URDF whose truth no real object of that shape can have (model_mass_plausible) is
 * refused with SIM_CONTROL_ERR_LOAD and the reason in YUMI_STATUS.error_text; the object loaded
 * before stays and still simulates with its own truth; a valid LOAD still works afterwards. */
START_TEST(implausible_load_refused) {
  fx_t f;
  spawn(&f, NULL);
  const char *tmp = getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp";
  char urdf[256], bad_mass[256], bad_com[256];
  snprintf(urdf, sizeof urdf, "%s/check_sim_ok_%d.urdf", tmp, (int)getpid());
  snprintf(bad_mass, sizeof bad_mass, "%s/check_sim_1e-300kg_%d.urdf", tmp, (int)getpid());
  snprintf(bad_com, sizeof bad_com, "%s/check_sim_com_out_%d.urdf", tmp, (int)getpid());
  const double com_x = 0.006;
  write_box_urdf(urdf, com_x);
  write_box_urdf_mass(bad_mass, com_x, 1e-300);
  write_box_urdf_mass(bad_com, 0.021, 0.2); /* the box spans x in [-0.02, 0.02] */
  int64_t sc_seq = 0, seq = 0;
  ck_assert_int_eq(place_trial(&f, urdf, 1, &sc_seq, &seq, com_x + 0.002), 1);

  const struct {
    const char *path, *why[3];
  } cases[] = {
      {bad_mass, {"SIM_CONTROL load of 'box_bad' refused", "mass 1e-300 kg", "[0.001, 10] kg"}},
      {bad_com,
       {"SIM_CONTROL load of 'box_bad' refused", "outside the mesh's bounding box", "x = 0.021 m"}},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    const int64_t rejected = f.st.messages_rejected;
    load_refused(&f, &sc_seq, "box_bad", cases[i].path, 5.0);
    ck_assert_msg(wait_for(&f, status_says_load_refused, cases[i].why[0], 2.0),
                  "case %zu: status error_text: %s", i, f.st.error_text);
    ck_assert_int_eq(f.st.error_code, ST(ERR_INVALID));
    for (int w = 1; w < 3; w++)
      ck_assert_msg(strstr(f.st.error_text, cases[i].why[w]) != NULL, "case %zu: '%s' not in %s", i,
                    cases[i].why[w], f.st.error_text);
    ck_assert_msg(strstr(f.st.error_text, cases[i].path) != NULL, "case %zu: no URDF in %s", i,
                  f.st.error_text);
    ck_assert_int_eq(f.st.messages_rejected, rejected + 1);
    /* nothing lost: the box placed before is still tracked where the trial left it */
    ck_assert(f.os.tracked);
    ck_assert_str_eq(f.os.object_id, "box_test");
    ck_assert(f.os.on_base);
  }
  /* the old object still simulates with its own truth: 2 mm beyond its CoM it tips */
  ck_assert_int_eq(place_trial(&f, urdf, 0, &sc_seq, &seq, com_x - 0.002), 2);
  /* and a valid LOAD still works */
  ck_assert_int_eq(place_trial(&f, urdf, 1, &sc_seq, &seq, com_x + 0.0003), 1);
  remove(urdf);
  remove(bad_mass);
  remove(bad_com);
  finish(&f);
}
END_TEST

/* Files that crash, hang or exhaust a parser, named in SIM_CONTROL LOAD (docs/security.md): a
 * URDF whose mesh makes Debian's assimp segfault (21 bytes) or loop (29 bytes, refused after the
 * mesh reader's 2 s CPU limit), a URDF nested 100 levels deep (tinyxml recurses), a named pipe
 * as the URDF; and files outside the sim's --object-dir folders ($TMPDIR and the assets here):
 * /dev/zero as the URDF, a URDF whose mesh lies elsewhere. Each is refused with
 * SIM_CONTROL_ERR_LOAD and a reason naming the file; the sim keeps running, and the object loaded
 * before gives the same outcomes after. */
static void write_mesh_urdf(const char *path, const char *mesh) {
  FILE *fp = fopen(path, "w");
  ck_assert_ptr_nonnull(fp);
  fprintf(fp,
          "<?xml version=\"1.0\"?>\n<robot name=\"m\"><link name=\"m\"><inertial><mass "
          "value=\"0.2\"/><inertia ixx=\"1e-4\" ixy=\"0\" ixz=\"0\" iyy=\"1e-4\" iyz=\"0\" "
          "izz=\"1e-4\"/></inertial><collision><geometry><mesh filename=\"%s\"/></geometry>"
          "</collision></link></robot>\n",
          mesh);
  fclose(fp);
}

START_TEST(hostile_load_refused) {
  /* the sim may read `allowed` (and the assets); `other` beside it is not inside */
  const char *base = getenv("TMPDIR") && getenv("TMPDIR")[0] ? getenv("TMPDIR") : "/tmp";
  char allowed[200], other[200];
  snprintf(allowed, sizeof allowed, "%s/check_sim_allowed_XXXXXX", base);
  snprintf(other, sizeof other, "%s/check_sim_other_XXXXXX", base);
  ck_assert_ptr_nonnull(mkdtemp(allowed));
  ck_assert_ptr_nonnull(mkdtemp(other));
  const char *dirs[] = {"--object-dir", allowed, "--object-dir", COMLEARN_ASSETS_DIR, NULL};
  fx_t f;
  spawn(&f, dirs);
  const char *tmp = allowed;
  char urdf[512], segv[512], segv_urdf[512], loop[512], loop_urdf[512], deep[512], fifo[512];
  const int pid = (int)getpid();
  snprintf(urdf, sizeof urdf, "%s/check_sim_ok_h%d.urdf", tmp, pid);
  snprintf(segv, sizeof segv, "%s/check_sim_segv_%d.ply", tmp, pid);
  snprintf(segv_urdf, sizeof segv_urdf, "%s/check_sim_segv_%d.urdf", tmp, pid);
  snprintf(loop, sizeof loop, "%s/check_sim_loop_%d.ply", tmp, pid);
  snprintf(loop_urdf, sizeof loop_urdf, "%s/check_sim_loop_%d.urdf", tmp, pid);
  snprintf(deep, sizeof deep, "%s/check_sim_deep_%d.urdf", tmp, pid);
  snprintf(fifo, sizeof fifo, "%s/check_sim_fifo_%d.urdf", tmp, pid);
  const double com_x = 0.006;
  write_box_urdf(urdf, com_x);
  FILE *fp = fopen(segv, "wb");
  ck_assert_ptr_nonnull(fp);
  fwrite("ply\nformat binary_\0\0\0", 1, 21, fp);
  fclose(fp);
  write_mesh_urdf(segv_urdf, segv);
  fp = fopen(loop, "wb");
  ck_assert_ptr_nonnull(fp);
  fwrite("ply\nformat ascii 1.0\ncomment\n", 1, 29, fp);
  fclose(fp);
  write_mesh_urdf(loop_urdf, loop);
  fp = fopen(deep, "w");
  ck_assert_ptr_nonnull(fp);
  fprintf(fp, "<robot name=\"d\"><link name=\"d\">");
  for (int i = 0; i < 100; ++i) fprintf(fp, "<x>");
  for (int i = 0; i < 100; ++i) fprintf(fp, "</x>");
  fprintf(fp, "</link></robot>\n");
  fclose(fp);
  ck_assert_int_eq(mkfifo(fifo, 0600), 0);
  /* a URDF the sim may read whose mesh is not */
  char outside_mesh[PATH_MAX], outside_urdf[512];
  snprintf(outside_mesh, sizeof outside_mesh, "%s/check_sim_outside_%d.obj", other, pid);
  fp = fopen(outside_mesh, "w");
  ck_assert_ptr_nonnull(fp);
  fprintf(fp, "v 0 0 0\nv 0.02 0 0\nv 0 0.02 0\nv 0 0 0.02\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  fclose(fp);
  snprintf(outside_urdf, sizeof outside_urdf, "%s/check_sim_outside_%d.urdf", tmp, pid);
  write_mesh_urdf(outside_urdf, outside_mesh);
  /* a second mesh outside (the first inside): refused before it is opened, though opening it
   * would crash the parser (the PLY above, copied beside the outside mesh) */
  char inside_mesh[512], outside_ply[PATH_MAX], second_urdf[512];
  snprintf(inside_mesh, sizeof inside_mesh, "%s/check_sim_inside_%d.obj", tmp, pid);
  snprintf(outside_ply, sizeof outside_ply, "%s/check_sim_segv_%d.ply", other, pid);
  snprintf(second_urdf, sizeof second_urdf, "%s/check_sim_second_%d.urdf", tmp, pid);
  fp = fopen(inside_mesh, "w");
  ck_assert_ptr_nonnull(fp);
  fprintf(fp, "v 0 0 0\nv 0.02 0 0\nv 0 0.02 0\nv 0 0 0.02\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  fclose(fp);
  fp = fopen(outside_ply, "wb");
  ck_assert_ptr_nonnull(fp);
  fwrite("ply\nformat binary_\0\0\0", 1, 21, fp);
  fclose(fp);
  fp = fopen(second_urdf, "w");
  ck_assert_ptr_nonnull(fp);
  fprintf(fp,
          "<?xml version=\"1.0\"?>\n<robot name=\"m\"><link name=\"m\"><inertial><mass "
          "value=\"0.2\"/><inertia ixx=\"1e-4\" ixy=\"0\" ixz=\"0\" iyy=\"1e-4\" iyz=\"0\" "
          "izz=\"1e-4\"/></inertial><collision><geometry><mesh filename=\"%s\"/></geometry>"
          "</collision><collision><origin xyz=\"0.05 0 0\"/><geometry><mesh filename=\"%s\"/>"
          "</geometry></collision></link></robot>\n",
          inside_mesh, outside_ply);
  fclose(fp);
  int64_t sc_seq = 0, seq = 0;
  ck_assert_int_eq(place_trial(&f, urdf, 1, &sc_seq, &seq, com_x + 0.002), 1);
  const struct {
    const char *path, *why;
    double wait_s;
  } cases[] = {
      {segv_urdf, "crashed", 5.0},
      {loop_urdf, "time limit", 20.0},
      {deep, "nested deeper", 5.0},
      {fifo, "not a regular file", 5.0},
      {"/dev/zero", "outside the folders", 5.0}, /* --object-dir */
      {outside_urdf, "outside the folders", 5.0},
      {second_urdf, "outside the folders", 5.0},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    load_refused(&f, &sc_seq, "hostile", cases[i].path, cases[i].wait_s);
    ck_assert_msg(wait_for(&f, status_says_load_refused, cases[i].why, 2.0),
                  "case %zu: status error_text: %s", i, f.st.error_text);
    ck_assert_msg(strstr(f.st.error_text, cases[i].path) != NULL, "case %zu: no file in %s", i,
                  f.st.error_text);
    ck_assert(f.os.tracked);
    ck_assert_str_eq(f.os.object_id, "box_test");
  }
  /* the sim still answers, with the same physics */
  ck_assert_int_eq(place_trial(&f, urdf, 0, &sc_seq, &seq, com_x - 0.002), 2);
  ck_assert_int_eq(place_trial(&f, urdf, 1, &sc_seq, &seq, com_x + 0.002), 1);
  const char *files[] = {urdf, segv,         segv_urdf,    loop,        loop_urdf,   deep,
                         fifo, outside_urdf, outside_mesh, inside_mesh, outside_ply, second_urdf};
  for (size_t i = 0; i < sizeof files / sizeof files[0]; ++i) remove(files[i]);
  rmdir(allowed);
  rmdir(other);
  finish(&f);
}
END_TEST

START_TEST(drop_rate_survives) {
  const char *extra[] = {"--drop-rate", "0.5", "--seed", "3", NULL};
  fx_t f;
  spawn(&f, extra);
  double q[2][7], w[2] = {0, 0};
  memcpy(q, f.st.q_measured_rad, sizeof q);
  /* retransmit with new seqs until one is acknowledged, as the estimator does */
  int64_t seq = 0;
  for (int i = 0; i < 40 && f.st.last_accepted_seq < 0; i++) {
    send_cmd(&f, ++seq, CMD(MODE_HOLD), (const double(*)[7])q, w, 1.0, f.st.utime + 60000000);
    wait_for(&f, have_status, NULL, 0.05);
    lcm_handle_timeout(f.lcm, 30);
  }
  ck_assert_int_ge(f.st.last_accepted_seq, 1);
  /* About half of what is sent is dropped. (Not "fewer received than sent" in the loop above:
   * when the statuses are dropped instead, every command of a short run can arrive.) Forty more
   * commands: the received count must grow by 8..32 (binomial(40, 0.5) is outside that with
   * probability 1e-4); the status that reports it can itself be dropped, so wait for a later one.
   */
  const int64_t before = f.st.messages_received;
  for (int i = 0; i < 40; i++) {
    send_cmd(&f, ++seq, CMD(MODE_HOLD), (const double(*)[7])q, w, 1.0, f.st.utime + 60000000);
    lcm_handle_timeout(f.lcm, 5);
  }
  const int64_t enough = before + 8;
  ck_assert(wait_for(&f, received_at_least, &enough, 5.0));
  for (int i = 0; i < 20; i++) lcm_handle_timeout(f.lcm, 20); /* the last ones to arrive */
  const int64_t got = f.st.messages_received - before;
  ck_assert_msg(got >= 8 && got <= 32, "%lld of 40 commands arrived at --drop-rate 0.5",
                (long long)got);
  finish(&f);
}
END_TEST

int main(void) {
  Suite *s = suite_create("sim");
  TCase *tc = tcase_create("daemon");
  tcase_set_timeout(tc, 60);
  tcase_add_checked_fixture(tc, NULL, kill_leftovers);
  tcase_add_test(tc, help_and_bad_options);
  tcase_add_test(tc, signals_exit_zero);
  tcase_add_test(tc, joint_tracking_velocity_limit);
  tcase_add_test(tc, status_events);
  tcase_add_test(tc, receive_buffer_warned);
  tcase_add_test(tc, seq_rules);
  tcase_add_test(tc, invalid_commands_refused);
  tcase_add_test(tc, envelope_rules);
  tcase_add_test(tc, refusals_counted);
  tcase_add_test(tc, garbage_counted);
  tcase_add_test(tc, place_box_over_edge);
  tcase_add_test(tc, implausible_load_refused);
  tcase_add_test(tc, hostile_load_refused);
  tcase_add_test(tc, oversized_message_counted);
  tcase_add_test(tc, drop_rate_survives);
  suite_add_tcase(s, tc);
  SRunner *sr = srunner_create(s);
  srunner_run_all(sr, CK_NORMAL);
  const int failed = srunner_ntests_failed(sr);
  srunner_free(sr);
  return failed == 0 ? 0 : 1;
}
