/* tool_args.h - command-line numbers shared by the asset tools (comlearn-rockgen,
 * comlearn-shapegen) and the benchmarks (bench_coverage, bench_outcome, placements_dump). Static
 * inline. */
#ifndef COMLEARN_TOOLS_TOOL_ARGS_H
#define COMLEARN_TOOLS_TOOL_ARGS_H

#include <errno.h>
#include <stdint.h>
#include <stdlib.h>

/* A whole decimal or 0x-hex unsigned 64-bit number (no sign, no trailing characters) into *out:
 * 0, or -1 (nothing written). */
static inline int tool_parse_u64(const char *text, uint64_t *out) {
  if (text == NULL || text[0] < '0' || text[0] > '9') return -1;
  char *end = NULL;
  errno = 0;
  const unsigned long long v = strtoull(text, &end, 0);
  if (errno != 0 || end == text || *end != '\0') return -1;
  *out = (uint64_t)v;
  return 0;
}

/* A whole decimal integer in [lo, hi] into *out: 0, or -1 (nothing written). */
static inline int tool_parse_int(const char *text, int lo, int hi, int *out) {
  if (text == NULL) return -1;
  char *end = NULL;
  errno = 0;
  const long v = strtol(text, &end, 10);
  if (errno != 0 || end == text || *end != '\0' || v < lo || v > hi) return -1;
  *out = (int)v;
  return 0;
}

/* A whole number in [lo, hi] (not NaN) into *out: 0, or -1 (nothing written). */
static inline int tool_parse_double(const char *text, double lo, double hi, double *out) {
  if (text == NULL) return -1;
  char *end = NULL;
  errno = 0;
  const double v = strtod(text, &end);
  if (errno != 0 || end == text || *end != '\0' || !(v >= lo && v <= hi)) return -1;
  *out = v;
  return 0;
}

#endif
