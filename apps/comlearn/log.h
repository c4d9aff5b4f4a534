/* log.h - a forwarding shim to comlearn/cli_log.h, kept only because cmd_estimate.c (owned by the
 * estimator move, issue 12) still includes it. New code includes comlearn/cli_log.h; delete this
 * file when cmd_estimate.c does. */
#ifndef COMLEARN_APP_LOG_H
#define COMLEARN_APP_LOG_H

#include "comlearn/cli_log.h"

#define LOG_ERROR CLI_LOG_ERROR
#define LOG_WARN CLI_LOG_WARN
#define LOG_INFO CLI_LOG_INFO
#define LOG_DEBUG CLI_LOG_DEBUG

static inline void log_set_level(cli_log_level_t level) { cli_log_set_level(level); }

#endif
