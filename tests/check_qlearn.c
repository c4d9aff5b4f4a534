/* check_qlearn: every suite of lib/qlearn in one Check runner. */
#include <stdlib.h>

#include "qlearn_suites.h"

int main(void) {
  SRunner *runner = srunner_create(qlearn_learner_suite());
  srunner_add_suite(runner, qlearn_paper_suite());
  srunner_add_suite(runner, qlearn_search_suite());
  srunner_add_suite(runner, qlearn_solve_suite());
  srunner_run_all(runner, CK_NORMAL);
  int failed = srunner_ntests_failed(runner);
  srunner_free(runner);
  return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
