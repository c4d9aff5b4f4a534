#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <time.h>

#include "comlearn/cli_time.h"

double cli_time_now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

double cli_time_cpu_s(void) {
  struct timespec ts;
  if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts) != 0) return 0.0;
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void cli_progress_start(cli_progress_t *p, size_t total) {
  p->done = 0;
  p->total = total;
  p->start_s = cli_time_now_s();
}

const char *cli_progress_step(cli_progress_t *p, char *buf, size_t size) {
  if (p->done < p->total) ++p->done;
  const int n = snprintf(buf, size, "%zu/%zu", p->done, p->total);
  if (n < 0 || (size_t)n >= size || p->done == 0 || p->done >= p->total) return buf;
  const double left =
      (cli_time_now_s() - p->start_s) / (double)p->done * (double)(p->total - p->done);
  const long s = lround(left);
  if (s < 60)
    snprintf(buf + n, size - (size_t)n, ", ETA %ld s", s);
  else if (s < 3600)
    snprintf(buf + n, size - (size_t)n, ", ETA %ld min %ld s", s / 60, s % 60);
  else
    snprintf(buf + n, size - (size_t)n, ", ETA %ld h %ld min", s / 3600, s / 60 % 60);
  return buf;
}
