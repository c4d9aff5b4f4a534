/* cmd_estimate.h - `comlearn estimate`: the command-line shell around estimate_run. */
#ifndef COMLEARN_APP_CMD_ESTIMATE_H
#define COMLEARN_APP_CMD_ESTIMATE_H

#include "comlearn/cli_paths.h"

/* cmd_estimate.c spells these paths as the compile definitions they were before cli_paths.h. */
#define COMLEARN_SIM_EXE cli_paths_sim_exe()
#define COMLEARN_YUMI_URDF cli_paths_yumi_urdf()

/* argv[0] is "estimate". Returns the exit code: 0 success, 1 runtime failure, 2 usage / bad
 * input. */
int cmd_estimate(int argc, char **argv);

#endif
