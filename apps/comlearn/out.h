/* out.h - a forwarding shim to comlearn/cli_json.h and comlearn/cli_time.h (stdout), kept only
 * because cmd_estimate.c (owned by the estimator move, issue 12) still includes it. New code
 * calls cli_json_* with a FILE *; delete this file when cmd_estimate.c does. */
#ifndef COMLEARN_APP_OUT_H
#define COMLEARN_APP_OUT_H

#include <stddef.h>
#include <stdio.h>

#include "comlearn/cli_json.h"
#include "comlearn/cli_time.h"

static inline void out_json_string(const char *v, int escape_high) {
  cli_json_string(stdout, v, escape_high);
}
static inline void out_json_number(double v) { cli_json_number(stdout, v); }
static inline void out_json_array(const double *v, int n) {
  cli_json_array(stdout, v, n > 0 ? (size_t)n : 0);
}
static inline double out_now_s(void) { return cli_time_now_s(); }

#endif
