/* The suites of check_placement, one source file each. */
#ifndef COMLEARN_TESTS_PLACEMENT_SUITES_H
#define COMLEARN_TESTS_PLACEMENT_SUITES_H

#include <check.h>

Suite *placement_kin_suite(void);   /* tests/placement_kin_tests.c: URDF chain, FK, IK */
Suite *placement_plan_suite(void);  /* tests/placement_plan_tests.c: placement plans */
Suite *placement_grasp_suite(void); /* tests/placement_grasp_tests.c: top-down grasps */

#endif
