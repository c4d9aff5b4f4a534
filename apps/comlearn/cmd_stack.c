/* PLACEHOLDER: replaced by the implementation. */
#include "cmd_stack.h"

#include "log.h"

int cmd_stack(int argc, char **argv) {
  (void)argc;
  (void)argv;
  LOG_E("stack: not implemented yet");
  return 1;
}
