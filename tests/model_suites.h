/* The suites of check_model, one source file each. */
#ifndef COMLEARN_TESTS_MODEL_SUITES_H
#define COMLEARN_TESTS_MODEL_SUITES_H

#include <check.h>

Suite *model_mesh_suite(void);     /* tests/model_mesh_tests.c: loading, checks, repairs, formats */
Suite *model_massprop_suite(void); /* tests/model_massprop_tests.c: closed-form mass properties */
Suite *model_hull_suite(void);     /* tests/model_hull_tests.c: convex hull, bounding box */
Suite *model_urdf_suite(void);     /* tests/model_urdf_tests.c: URDF geometry and inertial */
Suite *model_outcome_suite(void);  /* tests/model_outcome_tests.c: support polygon, outcome model */

#endif
