/* cmd_record.h - `comlearn record FILE`: record LCM traffic into an lcm-logger format log without
 * dropping what waits to be written (cmd_record.c, docs/replay.md). */
#ifndef COMLEARN_CMD_RECORD_H
#define COMLEARN_CMD_RECORD_H

/* argv[0] is "record". Returns the exit status: 0 stopped by a signal, 1 failure, 2 usage. */
int cmd_record(int argc, char **argv);

#endif
