/* cmd_plan.h - `comlearn plan OBJECT.urdf`: one placement on B's edge planned as the LCM backend
 * plans a trial, for a client in another language to execute (cmd_plan.c, docs/messages.md). */
#ifndef COMLEARN_CMD_PLAN_H
#define COMLEARN_CMD_PLAN_H

/* argv[0] is "plan". Returns the exit status: 0 planned, 1 no plan, 2 usage / bad input. */
int cmd_plan(int argc, char **argv);

#endif
