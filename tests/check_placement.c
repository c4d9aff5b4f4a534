/* check_placement: every suite of lib/placement in one Check runner. */
#include <stdlib.h>

#include "placement_suites.h"

int main(void) {
  SRunner *runner = srunner_create(placement_kin_suite());
  srunner_add_suite(runner, placement_plan_suite());
  srunner_add_suite(runner, placement_grasp_suite());
  srunner_run_all(runner, CK_NORMAL);
  int failed = srunner_ntests_failed(runner);
  srunner_free(runner);
  return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
