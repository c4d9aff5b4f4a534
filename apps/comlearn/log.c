#include "log.h"

#include <stdarg.h>
#include <stdio.h>

static log_level_t current_level = LOG_INFO;

void log_set_level(log_level_t level) { current_level = level; }

log_level_t log_get_level(void) { return current_level; }

void log_msg(log_level_t level, const char *fmt, ...) {
  static const char *const names[] = {"error", "warning", "info", "debug"};
  if (level > current_level) return;
  fprintf(stderr, "comlearn: %s: ", names[level]);
  va_list ap;
  va_start(ap, fmt);
  vfprintf(stderr, fmt, ap);
  va_end(ap);
  fputc('\n', stderr);
}
