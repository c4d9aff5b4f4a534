/* cmd_estimate.h - `comlearn estimate`: the command-line shell around estimate_run. */
#ifndef COMLEARN_APP_CMD_ESTIMATE_H
#define COMLEARN_APP_CMD_ESTIMATE_H

/* argv[0] is "estimate". Returns the exit code: 0 success, 1 runtime failure, 2 usage / bad
 * input. */
int cmd_estimate(int argc, char **argv);

#endif
