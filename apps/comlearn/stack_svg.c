/* PLACEHOLDER: replaced by the implementation. */
#include "stack.h"
