/* check_balance: every suite of lib/balance in one Check runner. */
#include <stdlib.h>

#include "balance_suites.h"

int main(void) {
  SRunner *runner = srunner_create(balance_trial_suite());
  srunner_add_suite(runner, balance_accuracy_suite());
  srunner_add_suite(runner, balance_regime_suite());
  srunner_add_suite(runner, balance_stable_suite());
  srunner_add_suite(runner, balance_stack_suite());
  srunner_run_all(runner, CK_NORMAL);
  int failed = srunner_ntests_failed(runner);
  srunner_free(runner);
  return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
