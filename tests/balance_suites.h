/* The suites of check_balance, one source file each. */
#ifndef COMLEARN_TESTS_BALANCE_SUITES_H
#define COMLEARN_TESTS_BALANCE_SUITES_H

#include <check.h>

Suite *balance_trial_suite(
    void); /* tests/balance_trial_tests.c: trials, outcomes, determinism, bad input */
Suite *balance_accuracy_suite(
    void); /* tests/balance_accuracy_tests.c: thresholds against analytic truth */
Suite *balance_regime_suite(void); /* tests/balance_regime_tests.c: flat-patch regime geometry */
Suite *balance_stable_suite(void); /* tests/balance_stable_tests.c: stable poses */
Suite *balance_stack_suite(void);  /* tests/balance_stack_tests.c: stacks */

#endif
