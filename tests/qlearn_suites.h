/* The suites of check_qlearn, one source file each. */
#ifndef COMLEARN_TESTS_QLEARN_SUITES_H
#define COMLEARN_TESTS_QLEARN_SUITES_H

#include <check.h>

Suite *qlearn_learner_suite(void); /* tests/qlearn_learner_tests.c: Q-table, MLP */
Suite *qlearn_paper_suite(void);   /* tests/qlearn_paper_tests.c: the paper's Algorithm 1 */
Suite *qlearn_search_suite(void);  /* tests/qlearn_search_tests.c: bisect, PBA, the interface */
Suite *qlearn_solve_suite(void);   /* tests/qlearn_solve_tests.c: the 3-D solve */

#endif
