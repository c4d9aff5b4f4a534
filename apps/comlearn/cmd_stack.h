/* cmd_stack.h - `comlearn stack` (cmd_stack.c). */
#ifndef COMLEARN_APP_CMD_STACK_H
#define COMLEARN_APP_CMD_STACK_H

/* argv[0] is "stack". Returns the program's exit status. */
int cmd_stack(int argc, char **argv);

#endif
