#include <stdarg.h>
#include <stdio.h>

#include "comlearn/cli_log.h"

static const char *log_program = "comlearn";
static cli_log_level_t log_level = CLI_LOG_INFO;
static FILE *log_stream = NULL; /* NULL: stderr (not a constant initializer) */

void cli_log_init(const char *program) { log_program = program ? program : "comlearn"; }

void cli_log_set_level(cli_log_level_t level) {
  const int v = (int)level;
  log_level = v < (int)CLI_LOG_ERROR   ? CLI_LOG_ERROR
              : v > (int)CLI_LOG_DEBUG ? CLI_LOG_DEBUG
                                       : level;
}

cli_log_level_t cli_log_get_level(void) { return log_level; }

void cli_log_set_stream(FILE *stream) { log_stream = stream; }

int cli_log_enabled(cli_log_level_t level) {
  return (int)level >= (int)CLI_LOG_ERROR && (int)level <= (int)log_level;
}

void cli_log_msg(cli_log_level_t level, const char *fmt, ...) {
  static const char *const names[] = {"error", "warning", "info", "debug"};
  if (!cli_log_enabled(level)) return;
  FILE *f = log_stream ? log_stream : stderr;
  fprintf(f, "%s: %s: ", log_program, names[level]);
  va_list ap;
  va_start(ap, fmt);
  vfprintf(f, fmt, ap);
  va_end(ap);
  fputc('\n', f);
}
