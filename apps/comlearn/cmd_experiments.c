/* PLACEHOLDER: replaced by the implementation. */
#include "cmd_experiments.h"

#include "log.h"

int cmd_experiments(int argc, char **argv) {
  (void)argc;
  (void)argv;
  LOG_E("experiments: not implemented yet");
  return 1;
}
