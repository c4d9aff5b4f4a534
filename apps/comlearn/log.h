/* A small level-checked logger to stderr for the comlearn programs (libraries never log). */
#ifndef COMLEARN_APP_LOG_H
#define COMLEARN_APP_LOG_H

typedef enum { LOG_ERROR = 0, LOG_WARN = 1, LOG_INFO = 2, LOG_DEBUG = 3 } log_level_t;

/* Messages above this level are dropped. Default LOG_INFO. Not thread-safe to change. */
void log_set_level(log_level_t level);
log_level_t log_get_level(void);

/* printf-style; prefixes the program name and the level, appends a newline. */
void log_msg(log_level_t level, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#define LOG_E(...) log_msg(LOG_ERROR, __VA_ARGS__)
#define LOG_W(...) log_msg(LOG_WARN, __VA_ARGS__)
#define LOG_I(...) log_msg(LOG_INFO, __VA_ARGS__)
#define LOG_D(...) log_msg(LOG_DEBUG, __VA_ARGS__)

#endif
