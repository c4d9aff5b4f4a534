/* cmd_experiments.h - `comlearn experiments` (cmd_experiments.c). */
#ifndef COMLEARN_APP_CMD_EXPERIMENTS_H
#define COMLEARN_APP_CMD_EXPERIMENTS_H

/* argv[0] is "experiments". Returns the program's exit status. */
int cmd_experiments(int argc, char **argv);

#endif
