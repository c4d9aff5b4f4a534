/* stop.c - SIGINT / SIGTERM as a stop request (cli_stop.h). */
#define _DEFAULT_SOURCE /* SA_RESTART */

#include <signal.h>
#include <string.h>

#include "comlearn/cli_stop.h"

static volatile sig_atomic_t stop_flag;
static struct sigaction old_int, old_term;
static int installed; /* old_int / old_term hold what was there before */

static void on_signal(int sig) {
  (void)sig;
  stop_flag = 1;
}

void cli_stop_install(void) {
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_signal;
  sa.sa_flags = SA_RESTART;
  sigemptyset(&sa.sa_mask);
  stop_flag = 0;
  if (installed) return;
  sigaction(SIGINT, &sa, &old_int);
  sigaction(SIGTERM, &sa, &old_term);
  installed = 1;
}

int cli_stop_requested(void) { return stop_flag != 0; }

void cli_stop_restore(void) {
  if (!installed) return;
  sigaction(SIGINT, &old_int, NULL);
  sigaction(SIGTERM, &old_term, NULL);
  installed = 0;
}
