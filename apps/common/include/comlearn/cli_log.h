/*
 * comlearn/cli_log.h - the one logger of the comlearn programs (comlearn, comlearn-sim, the tools
 * and the benches; target comlearn_cli). The libraries under lib/ never log: they return a status
 * and a message, and the program logs it.
 *
 * A line is "PROGRAM: LEVEL: message\n" on the log stream (stderr unless cli_log_set_stream),
 * LEVEL one of error, warning, info, debug. Messages above the current level are dropped.
 *
 * State: one program name, one level and one stream per process, set by the program's main
 * before any other thread runs. Not thread-safe to change; cli_log_msg itself takes no lock
 * (one fprintf per part: lines from two threads may interleave).
 */
#ifndef COMLEARN_CLI_LOG_H
#define COMLEARN_CLI_LOG_H

#include <stdio.h>

typedef enum {
  CLI_LOG_ERROR = 0,
  CLI_LOG_WARN = 1,
  CLI_LOG_INFO = 2, /* the default */
  CLI_LOG_DEBUG = 3
} cli_log_level_t;

/* The name prefixed to every line (borrowed: a string literal or argv[0] that outlives the
 * logging). NULL or never called: "comlearn". */
void cli_log_init(const char *program);

/* The most verbose level written; out-of-range values are clamped to ERROR..DEBUG. */
void cli_log_set_level(cli_log_level_t level);
cli_log_level_t cli_log_get_level(void);

/* Where lines go (borrowed; NULL: stderr). For tests and for programs that log to a file. */
void cli_log_set_stream(FILE *stream);

/* 1 when a message of this level would be written, else 0 (to skip building costly messages). */
int cli_log_enabled(cli_log_level_t level);

/* printf-style message at level; the prefix is added and a newline appended. */
void cli_log_msg(cli_log_level_t level, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#define LOG_E(...) cli_log_msg(CLI_LOG_ERROR, __VA_ARGS__)
#define LOG_W(...) cli_log_msg(CLI_LOG_WARN, __VA_ARGS__)
#define LOG_I(...) cli_log_msg(CLI_LOG_INFO, __VA_ARGS__)
#define LOG_D(...) cli_log_msg(CLI_LOG_DEBUG, __VA_ARGS__)

#endif
