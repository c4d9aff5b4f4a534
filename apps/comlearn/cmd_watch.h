/* cmd_watch.h - `comlearn watch`: a live table of COM_TRIAL / COM_ESTIMATE traffic (a running
 * estimate, or an lcm-logplayer replay of one). */
#ifndef COMLEARN_APP_CMD_WATCH_H
#define COMLEARN_APP_CMD_WATCH_H

/* argv[0] is "watch". Returns the exit code: 0 success (SIGINT / SIGTERM, or --once saw the
 * final estimate), 1 runtime failure (LCM, or --timeout-s passed with --once), 2 usage. */
int cmd_watch(int argc, char **argv);

#endif
