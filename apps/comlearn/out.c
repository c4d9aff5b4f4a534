#define _POSIX_C_SOURCE 200809L
#include "out.h"

#include <math.h>
#include <stdio.h>
#include <time.h>

void out_json_string(const char *v, int escape_high) {
  putchar('"');
  for (const unsigned char *p = (const unsigned char *)(v ? v : ""); *p; ++p) {
    if (*p == '"' || *p == '\\') printf("\\%c", *p);
    else if (*p < 0x20 || (escape_high && *p >= 0x7f)) printf("\\u%04x", *p);
    else putchar(*p);
  }
  putchar('"');
}

void out_json_number(double v) {
  if (isfinite(v)) printf("%.9g", v);
  else printf("null");
}

void out_json_array(const double *v, int n) {
  putchar('[');
  for (int i = 0; i < n; ++i) {
    if (i) printf(", ");
    out_json_number(v[i]);
  }
  putchar(']');
}

double out_now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}
