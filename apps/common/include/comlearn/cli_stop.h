/* cli_stop.h - SIGINT and SIGTERM as a request to stop, for the programs' main loops (comlearn
 * watch and record, comlearn-sim): the handler only raises a flag that the loop reads, so that
 * the loop can finish its work (flush a log, log its counters) before it returns. */
#ifndef COMLEARN_CLI_STOP_H
#define COMLEARN_CLI_STOP_H

/* Clear the flag and catch SIGINT and SIGTERM from now on (with SA_RESTART: a write blocked on a
 * slow file goes on; select and LCM's waits still return early). The handlers that were there
 * before are kept for cli_stop_restore; a second call only clears the flag. */
void cli_stop_install(void);

/* 1 once SIGINT or SIGTERM arrived since cli_stop_install, else 0. Async-signal-safe. */
int cli_stop_requested(void);

/* Put back the handlers cli_stop_install found (a command run in-process leaves none behind);
 * nothing when not installed. */
void cli_stop_restore(void);

#endif
