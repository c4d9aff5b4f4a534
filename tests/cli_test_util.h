/* cli_test_util.h - running a comlearn program from a test and reading its JSON output. Shared by
 * the suites that test programs (check_cli, check_estimate). Needs _POSIX_C_SOURCE (popen). */
#ifndef COMLEARN_TESTS_CLI_TEST_UTIL_H
#define COMLEARN_TESTS_CLI_TEST_UTIL_H

#include <check.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

/* Run a shell command; capture stdout into out (NUL-terminated); return the exit status. */
static inline int run(const char *cmd, char *out, size_t out_size) {
  FILE *p = popen(cmd, "r");
  ck_assert_ptr_nonnull(p);
  size_t n = fread(out, 1, out_size - 1, p);
  out[n] = '\0';
  int st = pclose(p);
  ck_assert(WIFEXITED(st));
  return WEXITSTATUS(st);
}

/* The three numbers after "key": [ in a JSON text. */
static inline void json_vec(const char *json, const char *key, double v[3]) {
  char pat[128];
  snprintf(pat, sizeof pat, "\"%s\": [", key);
  const char *p = strstr(json, pat);
  ck_assert_msg(p != NULL, "key %s missing in %s", key, json);
  p += strlen(pat);
  char *end;
  for (int i = 0; i < 3; ++i) {
    v[i] = strtod(p, &end);
    ck_assert_msg(end != p, "bad number for %s", key);
    p = end + 1;
  }
}

/* The number after "key": in a JSON text. */
static inline double json_num(const char *json, const char *key) {
  char pat[128];
  snprintf(pat, sizeof pat, "\"%s\": ", key);
  const char *p = strstr(json, pat);
  ck_assert_msg(p != NULL, "key %s missing", key);
  char *end;
  double v = strtod(p + strlen(pat), &end);
  ck_assert_msg(end != p + strlen(pat), "bad number for %s", key);
  return v;
}

#endif
