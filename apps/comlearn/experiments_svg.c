/* PLACEHOLDER: replaced by the implementation. */
#include "cmd_experiments.h"
