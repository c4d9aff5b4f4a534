#define _POSIX_C_SOURCE 200809L
/* check_cli: the comlearn program as a user runs it: output values and exit codes (inspect,
 * `estimate --direct` refusing an implausible truth, `plan` against the geometry and lib/balance,
 * logcheck on logs written here). */
#include <check.h>
#include <lcm/eventlog.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli_test_util.h"
#include "comlearn/comlearn_com_estimate_t.h"
#include "comlearn/comlearn_com_trial_t.h"

#ifndef COMLEARN_BIN
#error "COMLEARN_BIN must name the comlearn executable"
#endif

static char tmpdir[256];

/* A 4 x 6 x 2 cm box whose geometry sits at (0.01, -0.02, 0.005) in the link frame, with a true
 * CoM elsewhere (an uneven body) so the truth cannot be confused with the geometry; mass and
 * CoM as given (the inertia is that of 0.2 kg). */
static void write_box_urdf_truth(const char *path, const char *mass_kg, const char *com_xyz) {
  FILE *f = fopen(path, "w");
  ck_assert_ptr_nonnull(f);
  fprintf(f,
          "<?xml version=\"1.0\"?>\n<robot name=\"cli_box\">\n <link name=\"body\">\n"
          "  <inertial><origin xyz=\"%s\"/><mass value=\"%s\"/>\n"
          "   <inertia ixx=\"6.67e-5\" iyy=\"3.33e-5\" izz=\"8.67e-5\" ixy=\"0\" ixz=\"0\" "
          "iyz=\"0\"/></inertial>\n"
          "  <collision><origin xyz=\"0.01 -0.02 0.005\"/>"
          "<geometry><box size=\"0.04 0.06 0.02\"/></geometry></collision>\n"
          " </link>\n</robot>\n",
          com_xyz, mass_kg);
  fclose(f);
}

static void write_box_urdf(const char *path) {
  write_box_urdf_truth(path, "0.2", "0.013 -0.021 0.004");
}

static void setup(void) {
  snprintf(tmpdir, sizeof tmpdir, "/tmp/check_cli.XXXXXX");
  ck_assert_ptr_nonnull(mkdtemp(tmpdir));
}

static void teardown(void) {
  char cmd[512];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
  ck_assert_int_eq(system(cmd), 0);
}

START_TEST(inspect_box_json) {
  char urdf[512], cmd[1024], out[8192];
  snprintf(urdf, sizeof urdf, "%s/box.urdf", tmpdir);
  write_box_urdf(urdf);
  snprintf(cmd, sizeof cmd, "'%s' inspect --json --truth '%s'", COMLEARN_BIN, urdf);
  ck_assert_int_eq(run(cmd, out, sizeof out), 0);

  double center[3], com[3], size[3], truth[3];
  json_vec(out, "bbox_center_m", center);
  json_vec(out, "uniform_com_m", com);
  json_vec(out, "size_m", size);
  json_vec(out, "truth_com_m", truth);
  const double want_center[3] = {0.01, -0.02, 0.005}, want_size[3] = {0.04, 0.06, 0.02};
  const double want_truth[3] = {0.013, -0.021, 0.004};
  for (int k = 0; k < 3; ++k) {
    ck_assert_double_eq_tol(center[k], want_center[k], 1e-9);
    ck_assert_double_eq_tol(com[k], want_center[k], 1e-9);
    ck_assert_double_eq_tol(size[k], want_size[k], 1e-9);
    ck_assert_double_eq_tol(truth[k], want_truth[k], 1e-9);
  }
  ck_assert_double_eq_tol(json_num(out, "volume_m3"), 0.04 * 0.06 * 0.02, 1e-15);
  ck_assert_double_eq_tol(json_num(out, "hull_volume_m3"), 0.04 * 0.06 * 0.02, 1e-15);
  ck_assert_double_eq_tol(json_num(out, "truth_mass_kg"), 0.2, 1e-12);
  /* |truth - uniform| = |(0.003, -0.001, -0.001)| */
  ck_assert_double_eq_tol(json_num(out, "truth_minus_uniform_m"), 0.00331662479, 1e-9);
}
END_TEST

START_TEST(inspect_without_truth_reports_no_truth) {
  char urdf[512], cmd[1024], out[8192];
  snprintf(urdf, sizeof urdf, "%s/box.urdf", tmpdir);
  write_box_urdf(urdf);
  snprintf(cmd, sizeof cmd, "'%s' inspect --json '%s'", COMLEARN_BIN, urdf);
  ck_assert_int_eq(run(cmd, out, sizeof out), 0);
  ck_assert_ptr_null(strstr(out, "truth"));
  ck_assert_ptr_nonnull(strstr(out, "\"robot\": \"cli_box\""));
  ck_assert_ptr_nonnull(strstr(out, "\"link\": \"body\""));
}
END_TEST

START_TEST(bad_input_exit_codes) {
  char urdf[512], cmd[1024], out[8192];
  snprintf(cmd, sizeof cmd, "'%s' 2>/dev/null", COMLEARN_BIN);
  ck_assert_int_eq(run(cmd, out, sizeof out), 2);
  snprintf(cmd, sizeof cmd, "'%s' frobnicate 2>/dev/null", COMLEARN_BIN);
  ck_assert_int_eq(run(cmd, out, sizeof out), 2);
  snprintf(cmd, sizeof cmd, "'%s' inspect 2>/dev/null", COMLEARN_BIN);
  ck_assert_int_eq(run(cmd, out, sizeof out), 2);
  snprintf(cmd, sizeof cmd, "'%s' inspect --bogus x.urdf 2>/dev/null", COMLEARN_BIN);
  ck_assert_int_eq(run(cmd, out, sizeof out), 2);
  snprintf(cmd, sizeof cmd, "'%s' inspect '%s/missing.urdf' 2>&1", COMLEARN_BIN, tmpdir);
  ck_assert_int_eq(run(cmd, out, sizeof out), 2);
  ck_assert_msg(strstr(out, "missing.urdf") != NULL, "error must name the file: %s", out);

  snprintf(urdf, sizeof urdf, "%s/box.urdf", tmpdir);
  write_box_urdf(urdf);
  snprintf(cmd, sizeof cmd, "'%s' inspect --link nosuch '%s' 2>&1", COMLEARN_BIN, urdf);
  ck_assert_int_eq(run(cmd, out, sizeof out), 2);
  ck_assert_msg(strstr(out, "nosuch") != NULL, "error must name the link: %s", out);

  snprintf(cmd, sizeof cmd, "'%s' --help", COMLEARN_BIN);
  ck_assert_int_eq(run(cmd, out, sizeof out), 0);
  ck_assert_ptr_nonnull(strstr(out, "--truth"));
}
END_TEST

/* `comlearn estimate --direct` refuses a truth no real object of that shape can have (the
 * simulator side's model_mass_plausible): exit 2, the URDF and the reason on stderr, nothing on
 * stdout. The same box with a sane truth estimates (exit 0), so the file itself is fine. */
START_TEST(estimate_direct_implausible_truth) {
  char urdf[512], cmd[1536], out[8192];
  const struct {
    const char *mass, *com, *why[2];
  } cases[] = {
      {"1e-300", "0.013 -0.021 0.004", {"mass 1e-300 kg", "[0.001, 10] kg"}},
      {"12", "0.013 -0.021 0.004", {"mass 12 kg", "[0.001, 10] kg"}},
      {"0.2", "0.013 0.021 0.004", {"outside the mesh's bounding box", "y = 0.021 m"}},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
    snprintf(urdf, sizeof urdf, "%s/implausible_%zu.urdf", tmpdir, i);
    write_box_urdf_truth(urdf, cases[i].mass, cases[i].com);
    snprintf(cmd, sizeof cmd, "'%s' estimate '%s' --direct --json 2>&1 >/dev/null", COMLEARN_BIN,
             urdf);
    ck_assert_int_eq(run(cmd, out, sizeof out), 2);
    ck_assert_msg(strstr(out, urdf) != NULL, "stderr must name the URDF: %s", out);
    for (int w = 0; w < 2; ++w)
      ck_assert_msg(strstr(out, cases[i].why[w]) != NULL, "stderr must say '%s': %s",
                    cases[i].why[w], out);
    snprintf(cmd, sizeof cmd, "'%s' estimate '%s' --direct --json 2>/dev/null", COMLEARN_BIN, urdf);
    ck_assert_int_eq(run(cmd, out, sizeof out), 2);
    ck_assert_str_eq(out, "");
  }
  snprintf(urdf, sizeof urdf, "%s/box.urdf", tmpdir);
  write_box_urdf(urdf);
  snprintf(cmd, sizeof cmd, "'%s' estimate '%s' --direct --json 2>/dev/null", COMLEARN_BIN, urdf);
  ck_assert_int_eq(run(cmd, out, sizeof out), 0);
  ck_assert_ptr_nonnull(strstr(out, "\"com_m\": ["));
}
END_TEST

/* ---- logcheck ---------------------------------------------------------------------------- */

static void log_event(lcm_eventlog_t *log, const char *channel, const void *data, int len) {
  static int64_t n;
  lcm_eventlog_event_t ev = {.eventnum = n, .timestamp = 1000 * ++n};
  ev.channellen = (int32_t)strlen(channel);
  ev.channel = (char *)channel;
  ev.datalen = len;
  ev.data = (void *)data;
  ck_assert_int_eq(lcm_eventlog_write_event(log, &ev), 0);
}

static void log_trial(lcm_eventlog_t *log, const char *channel, int64_t run_id, int32_t index) {
  comlearn_com_trial_t t;
  memset(&t, 0, sizeof t);
  t.run_id = run_id;
  t.trial_index = index;
  t.object_id = (char *)"box";
  t.policy = (char *)"bisect";
  unsigned char buf[4096];
  const int len = comlearn_com_trial_t_encode(buf, 0, sizeof buf, &t);
  ck_assert_int_gt(len, 0);
  log_event(log, channel, buf, len);
}

static void log_estimate(lcm_eventlog_t *log, const char *channel, int64_t run_id, int32_t trials,
                         int done) {
  comlearn_com_estimate_t e;
  memset(&e, 0, sizeof e);
  e.run_id = run_id;
  e.trials = trials;
  e.done = (int8_t)done;
  e.object_id = (char *)"box";
  e.policy = (char *)"bisect";
  unsigned char buf[4096];
  const int len = comlearn_com_estimate_t_encode(buf, 0, sizeof buf, &e);
  ck_assert_int_gt(len, 0);
  log_event(log, channel, buf, len);
}

/* A row of logcheck's channel table: the channel, its events and bytes. */
static int has_row(const char *out, const char *channel, int events, int bytes) {
  char row[128];
  snprintf(row, sizeof row, "  %-32s %10d %12d\n", channel, events, bytes);
  return strstr(out, row) != NULL;
}

/* comlearn logcheck counts the events per channel and checks, per run, the trial indices against
 * the final COM_ESTIMATE's count, on any robot's channels. One log holds a complete run (3
 * trials, a running estimate before the final one) and a status; a second log of the same
 * recording holds robot R1_'s runs: one missing trial 1, one with trial 0 twice, one with a
 * trial beyond its count, one without a final estimate, an undecodable COM_TRIAL, and a record on
 * "bad.COM_TRIAL" (not a robot's channel: counted, not checked). */
START_TEST(logcheck_finds_what_is_missing) {
  char good[512], bad[512], junk[512], cmd[2048], out[8192];
  snprintf(good, sizeof good, "%s/good.lcmlog", tmpdir);
  snprintf(bad, sizeof bad, "%s/bad.lcmlog", tmpdir);
  snprintf(junk, sizeof junk, "%s/junk.lcmlog", tmpdir);
  lcm_eventlog_t *log = lcm_eventlog_create(good, "w");
  ck_assert_ptr_nonnull(log);
  for (int i = 0; i < 3; ++i) {
    log_trial(log, "COM_TRIAL", 11, i);
    log_estimate(log, "COM_ESTIMATE", 11, i + 1, 0);
  }
  log_estimate(log, "COM_ESTIMATE", 11, 3, 1);
  log_event(log, "YUMI_STATUS", "abc", 3);
  lcm_eventlog_destroy(log);
  log = lcm_eventlog_create(bad, "w");
  ck_assert_ptr_nonnull(log);
  log_trial(log, "R1_COM_TRIAL", 21, 0); /* run 21: 0 and 2 of 3 */
  log_trial(log, "R1_COM_TRIAL", 21, 2);
  log_estimate(log, "R1_COM_ESTIMATE", 21, 3, 1);
  log_trial(log, "R1_COM_TRIAL", 22, 0); /* run 22: 0 twice, 1 */
  log_trial(log, "R1_COM_TRIAL", 22, 0);
  log_trial(log, "R1_COM_TRIAL", 22, 1);
  log_estimate(log, "R1_COM_ESTIMATE", 22, 2, 1);
  log_trial(log, "R1_COM_TRIAL", 23, 0); /* run 23: 0, 1 and 5 of 2 */
  log_trial(log, "R1_COM_TRIAL", 23, 1);
  log_trial(log, "R1_COM_TRIAL", 23, 5);
  log_estimate(log, "R1_COM_ESTIMATE", 23, 2, 1);
  log_trial(log, "R1_COM_TRIAL", 24, 0); /* run 24: no final estimate */
  log_estimate(log, "R1_COM_ESTIMATE", 24, 1, 0);
  log_event(log, "R1_COM_TRIAL", "garbage", 7);
  log_trial(log, "bad.COM_TRIAL", 25, 0);
  lcm_eventlog_destroy(log);

  snprintf(cmd, sizeof cmd, "'%s' logcheck '%s'", COMLEARN_BIN, good);
  ck_assert_int_eq(run(cmd, out, sizeof out), 0);
  ck_assert_msg(strstr(out, "8 events in 1 log\n") != NULL, "%s", out);
  ck_assert_msg(has_row(out, "COM_TRIAL", 3, 3 * 308) && has_row(out, "YUMI_STATUS", 1, 3), "%s",
                out);
  ck_assert_msg(
      strstr(out,
             "complete: 1 runs, 3 of 3 trial records, 0 missing, 0 repeated, 0 beyond "
             "the final count, 0 runs without a final COM_ESTIMATE, 0 undecodable") != NULL,
      "%s", out);
  snprintf(cmd, sizeof cmd, "'%s' logcheck -v '%s' '%s'", COMLEARN_BIN, good, bad);
  ck_assert_int_eq(run(cmd, out, sizeof out), 1);
  ck_assert_msg(
      strstr(out,
             "INCOMPLETE: 5 runs, 9 of 10 trial records, 1 missing, 1 repeated, 1 beyond "
             "the final count, 1 runs without a final COM_ESTIMATE, 1 undecodable") != NULL,
      "%s", out);
  ck_assert_msg(strstr(out, "run 21 box: 2 of 3 trials, 1 missing, 0 repeated, 0 beyond\n") &&
                    strstr(out, "run 22 box: 2 of 2 trials, 0 missing, 1 repeated, 0 beyond\n") &&
                    strstr(out, "run 23 box: 2 of 2 trials, 0 missing, 0 repeated, 1 beyond\n"),
                "%s", out);
  ck_assert_msg(strstr(out, "run 24 box: 1 trial records, no final COM_ESTIMATE") != NULL, "%s",
                out);
  ck_assert_msg(
      has_row(out, "bad.COM_TRIAL", 1, 308) && has_row(out, "R1_COM_TRIAL", 10, 9 * 308 + 7), "%s",
      out);
  /* no log, a missing one, one that is not an LCM log */
  snprintf(cmd, sizeof cmd, "'%s' logcheck 2>&1", COMLEARN_BIN);
  ck_assert_int_eq(run(cmd, out, sizeof out), 2);
  snprintf(cmd, sizeof cmd, "'%s' logcheck '%s/missing.lcmlog' 2>&1", COMLEARN_BIN, tmpdir);
  ck_assert_int_eq(run(cmd, out, sizeof out), 2);
  ck_assert_msg(strstr(out, "missing.lcmlog") != NULL, "%s", out);
  FILE *f = fopen(junk, "w");
  ck_assert_ptr_nonnull(f);
  fputs("not an LCM log at all\n", f);
  fclose(f);
  snprintf(cmd, sizeof cmd, "'%s' logcheck '%s' 2>&1", COMLEARN_BIN, junk);
  ck_assert_int_eq(run(cmd, out, sizeof out), 2);
  ck_assert_msg(strstr(out, "junk.lcmlog: no LCM events") != NULL, "%s", out);
}
END_TEST

/* `comlearn plan`: the box's true CoM (0.013, -0.021, 0.004) is 3 mm inside the point placed over
 * B's +x edge (x = 16 mm), so lib/balance keeps it on B; 3 mm past it (x = 10 mm) it tips. The
 * release pose follows from the geometry alone: the point on the edge line x = 0.15 m (B is 0.3 m
 * wide), over y = 0, and the box's underside (link z = -5 mm) 1e-6 m into B's top (z = 0). */
START_TEST(plan_box_release_and_outcome) {
  char urdf[512], cmd[1024], out[16384];
  snprintf(urdf, sizeof urdf, "%s/box.urdf", tmpdir);
  write_box_urdf(urdf);
  const struct {
    const char *point;
    double x_m;
    const char *outcome;
  } cases[] = {{"16,-21,-5", 0.134, "stays"}, {"10,-21,-5", 0.140, "tips"}};
  for (int c = 0; c < 2; ++c) {
    snprintf(cmd, sizeof cmd, "'%s' plan '%s' --point-mm %s --simulate --json", COMLEARN_BIN, urdf,
             cases[c].point);
    ck_assert_int_eq(run(cmd, out, sizeof out), 0);
    double rel[3], settled[3];
    json_vec(out, "release_in_block\": {\"position_m", rel);
    ck_assert_double_eq_tol(rel[0], cases[c].x_m, 1e-9);
    ck_assert_double_eq_tol(rel[1], 0.021, 1e-9);
    ck_assert_double_eq_tol(rel[2], 0.005 - 1e-6, 1e-9);
    char want[64];
    snprintf(want, sizeof want, "\"simulated\": {\"outcome\": \"%s\"", cases[c].outcome);
    ck_assert_msg(strstr(out, want) != NULL, "%s: want %s in %s", cases[c].point, want, out);
    json_vec(out, "settled_in_block\": {\"position_m", settled);
    if (c == 0) /* stays: where it was released */
      ck_assert_double_eq_tol(settled[0], cases[c].x_m, 1e-4);
    for (int k = 0; k < 4; ++k) { /* four waypoints of seven joints */
      char kind[64];
      snprintf(kind, sizeof kind, "\"kind\": \"%s\"",
               (const char *[]){"preplace", "place", "release", "retreat"}[k]);
      ck_assert_msg(strstr(out, kind) != NULL, "waypoint %s missing", kind);
    }
  }
}
END_TEST

/* `comlearn plan` refuses bad values with exit 2 and names the option (or joint) at fault. */
START_TEST(plan_bad_input) {
  char urdf[512], cmd[1024], out[8192];
  snprintf(urdf, sizeof urdf, "%s/box.urdf", tmpdir);
  write_box_urdf(urdf);
  const struct {
    const char *args, *says;
  } cases[] = {
      {"--point-mm 1,2", "--point-mm: '1,2' is not three finite numbers"},
      {"--point-mm 1,2,nan", "--point-mm: '1,2,nan' is not three"},
      {"--point-mm 1,2,3,4", "is not three finite numbers"},
      {"--orientation 1,0,0,0.1", "--orientation: '1,0,0,0.1' is not a unit quaternion"},
      {"--orientation 1,0,0", "is not a unit quaternion"},
      {"--q-start 0,0,0,0,0,0,0,0,0,0,0,0,0", "--q-start: '0,0,0,0,0,0,0,0,0,0,0,0,0' is not 14"},
      {"--q-start 9,0,0,0,0,0,0,0,0,0,0,0,0,0", "yumi_joint_1_l is 9 rad, outside its limits"},
      {"--q-start 0,0,0,0,0,0,0,0,0,0,0,0,0,-4", "yumi_joint_6_r is -4 rad, outside its limits"},
      {"--edge +z", "--edge: '+z' is not one of +x, -x, +y, -y"},
      {"--along-mm 151", "--along-mm: '151' is not a number in [-150, 150]"},
  };
  for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
    snprintf(cmd, sizeof cmd, "'%s' plan '%s' %s 2>&1", COMLEARN_BIN, urdf, cases[c].args);
    ck_assert_int_eq(run(cmd, out, sizeof out), 2);
    ck_assert_msg(strstr(out, cases[c].says) != NULL, "%s: want '%s' in: %s", cases[c].args,
                  cases[c].says, out);
  }
  snprintf(cmd, sizeof cmd, "'%s' plan '%s/missing.urdf' 2>&1", COMLEARN_BIN, tmpdir);
  ck_assert_int_eq(run(cmd, out, sizeof out), 2);
  ck_assert_msg(strstr(out, "missing.urdf") != NULL, "%s", out);
}
END_TEST

int main(void) {
  Suite *s = suite_create("cli");
  TCase *tc = tcase_create("inspect");
  tcase_add_checked_fixture(tc, setup, teardown);
  tcase_set_timeout(tc, 60);
  tcase_add_test(tc, inspect_box_json);
  tcase_add_test(tc, inspect_without_truth_reports_no_truth);
  tcase_add_test(tc, bad_input_exit_codes);
  tcase_add_test(tc, logcheck_finds_what_is_missing);
  suite_add_tcase(s, tc);
  TCase *est = tcase_create("estimate");
  tcase_add_checked_fixture(est, setup, teardown);
  tcase_set_timeout(est, 120);
  tcase_add_test(est, estimate_direct_implausible_truth);
  tcase_add_test(est, plan_box_release_and_outcome);
  tcase_add_test(est, plan_bad_input);
  suite_add_tcase(s, est);
  SRunner *r = srunner_create(s);
  srunner_run_all(r, CK_NORMAL);
  int failed = srunner_ntests_failed(r);
  srunner_free(r);
  return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
