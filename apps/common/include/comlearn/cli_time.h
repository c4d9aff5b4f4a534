/* comlearn/cli_time.h - the wall clock of the comlearn programs' timings (target comlearn_cli). */
#ifndef COMLEARN_CLI_TIME_H
#define COMLEARN_CLI_TIME_H

#include <stddef.h>

/* Seconds of CLOCK_MONOTONIC (arbitrary origin: only differences mean something). Thread-safe. */
double cli_time_now_s(void);

/* Seconds of CPU time this process used (CLOCK_PROCESS_CPUTIME_ID, all its threads). */
double cli_time_cpu_s(void);

/* Progress through `total` units of long work (runs, stacks), for a progress line: the count and
 * an estimate of the time left from the mean time per unit so far. */
typedef struct {
  size_t done, total;
  double start_s; /* cli_time_now_s() at cli_progress_start */
} cli_progress_t;

/* Start counting total units now. */
void cli_progress_start(cli_progress_t *p, size_t total);

/* One more unit done: "k/N, ETA T" into buf (T as "12 s", "3 min 5 s" or "1 h 2 min"; "k/N" only
 * while nothing is done or nothing is left). Returns buf. */
const char *cli_progress_step(cli_progress_t *p, char *buf, size_t size);

#endif
