/* check_model: every suite of lib/model in one Check runner. */
#include <stdlib.h>

#include "model_suites.h"

int main(void) {
  SRunner *runner = srunner_create(model_mesh_suite());
  srunner_add_suite(runner, model_massprop_suite());
  srunner_add_suite(runner, model_hull_suite());
  srunner_add_suite(runner, model_urdf_suite());
  srunner_add_suite(runner, model_outcome_suite());
  srunner_run_all(runner, CK_NORMAL);
  int failed = srunner_ntests_failed(runner);
  srunner_free(runner);
  return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
