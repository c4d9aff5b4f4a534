/* comlearn/cli_time.h - the wall clock of the comlearn programs' timings (target comlearn_cli). */
#ifndef COMLEARN_CLI_TIME_H
#define COMLEARN_CLI_TIME_H

/* Seconds of CLOCK_MONOTONIC (arbitrary origin: only differences mean something). Thread-safe. */
double cli_time_now_s(void);

/* Seconds of CPU time this process used (CLOCK_PROCESS_CPUTIME_ID, all its threads). */
double cli_time_cpu_s(void);

#endif
