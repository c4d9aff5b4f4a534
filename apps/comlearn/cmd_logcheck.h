/* cmd_logcheck.h - `comlearn logcheck LOG...`: an LCM log's events per channel, and whether it
 * holds every trial record of every run (cmd_logcheck.c, docs/replay.md). */
#ifndef COMLEARN_CMD_LOGCHECK_H
#define COMLEARN_CMD_LOGCHECK_H

/* argv[0] is "logcheck". Returns the exit status: 0 complete, 1 incomplete, 2 usage / bad log. */
int cmd_logcheck(int argc, char **argv);

#endif
