/* qlearn_noalloc: a whole estimate allocates nothing. Linked with
 * -Wl,--wrap=malloc,--wrap=calloc,--wrap=realloc,--wrap=free, so every allocator call from this
 * program's own objects and from the comlearn_qlearn archive goes through the counters below.
 * The measured section runs all four policies through qlearn_policy_* (three components each,
 * noiseless threshold oracle) and a 3-D solve of the nine thresholds; nothing in it may call the
 * allocator. Check is not used (it allocates); stdio only outside the measured section. Also
 * prints sizeof of every state struct and enforces the 16 KiB budget. Exit 0 on success. */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>

#include "comlearn/qlearn.h"
#include "comlearn/qlearn_solve.h"

void *__real_malloc(size_t n);
void *__real_calloc(size_t n, size_t m);
void *__real_realloc(void *p, size_t n);
void __real_free(void *p);
void *__wrap_malloc(size_t n);
void *__wrap_calloc(size_t n, size_t m);
void *__wrap_realloc(void *p, size_t n);
void __wrap_free(void *p);

static volatile unsigned long alloc_calls; /* volatile: GCC assumes malloc touches no global */

void *__wrap_malloc(size_t n) {
  alloc_calls++;
  return __real_malloc(n);
}
void *__wrap_calloc(size_t n, size_t m) {
  alloc_calls++;
  return __real_calloc(n, m);
}
void *__wrap_realloc(void *p, size_t n) {
  alloc_calls++;
  return __real_realloc(p, n);
}
void __wrap_free(void *p) {
  alloc_calls++;
  __real_free(p);
}

/* The whole estimator state, as a caller would own it. */
typedef struct {
  qlearn_policy_t policy;
  qlearn_solve_t solve;
} estimator_state_t;
_Static_assert(sizeof(estimator_state_t) <= 16 * 1024, "estimator state exceeds 16 KiB");

static estimator_state_t g_state; /* the test's storage; the library has no globals */

/* One search to the end; returns the trials or -1. */
static int search(qlearn_policy_t *pol, double c) {
  for (int i = 0; i <= QLEARN_MAX_TRIALS; ++i) {
    double x = 0.0;
    qlearn_status_t st = qlearn_policy_next(pol, &x);
    if (st == QLEARN_E_DONE) return (int)pol->trials;
    if (st != QLEARN_OK) return -1;
    if (qlearn_policy_observe(pol, x, c > x ? QLEARN_TIPS : QLEARN_STAYS) != QLEARN_OK) {
      return -1;
    }
  }
  return -1;
}

int main(void) {
  const qlearn_policy_kind_t kinds[] = {QLEARN_POLICY_BISECT, QLEARN_POLICY_PBA,
                                        QLEARN_POLICY_PAPER_QTABLE, QLEARN_POLICY_PAPER_MLP};
  const char *names[] = {"bisect", "pba", "paper-qtable", "paper-mlp"};
  const double com[3] = {0.0123, -0.0071, 0.0345};
  int trials[4][3] = {{0}};
  int failures = 0;
  qlearn_solve_result_t res[4];
  qlearn_status_t solve_st[4];

  /* Self-check: the wrap is active (this call must be counted). */
  unsigned long before_probe = alloc_calls;
  void *volatile probe = malloc(16); /* volatile: the pair may not be optimized away */
  free(probe);
  if (alloc_calls != before_probe + 2) {
    fprintf(stderr, "FAIL: --wrap=malloc is not active (%lu calls counted)\n",
            alloc_calls - before_probe);
    return EXIT_FAILURE;
  }

  /* ---- measured section: init included ---- */
  unsigned long before = alloc_calls;
  for (int p = 0; p < 4; ++p) {
    estimator_state_t *s = &g_state;
    if (qlearn_solve_init(&s->solve) != QLEARN_OK) failures++;
    for (int axis = 0; axis < 3; ++axis) {
      qlearn_policy_config_t cfg;
      qlearn_policy_config_default(kinds[p], &cfg);
      cfg.sigma_m = 0.0;
      if (qlearn_policy_init(&s->policy, &cfg) != QLEARN_OK) {
        failures++;
        continue;
      }
      trials[p][axis] = search(&s->policy, com[axis]);
      if (trials[p][axis] < 0) failures++;
      double c = 0.0;
      double hw = 0.0;
      if (qlearn_policy_estimate(&s->policy, &c, &hw) != QLEARN_OK) failures++;
      /* one resting pose per axis: the edge normal along that object axis */
      double n[3] = {0.0, 0.0, 0.0};
      n[axis] = 1.0;
      double sigma = hw > 0.0 ? hw / sqrt(3.0) : 1e-6;
      if (qlearn_solve_add_plane(&s->solve, n, c, sigma) != QLEARN_OK) failures++;
    }
    solve_st[p] = qlearn_solve_compute(&s->solve, 1.96, 1e-3, &res[p]);
  }
  unsigned long during = alloc_calls - before;
  /* ---- end of measured section ---- */

  printf(
      "sizeof: qlearn_policy_config_t %zu, qlearn_bisect_t %zu, qlearn_pba_t %zu, "
      "qlearn_paper_t %zu, qlearn_policy_t %zu, qlearn_solve_t %zu, "
      "qlearn_solve_result_t %zu; estimator (policy + solve) %zu of 16384\n",
      sizeof(qlearn_policy_config_t), sizeof(qlearn_bisect_t), sizeof(qlearn_pba_t),
      sizeof(qlearn_paper_t), sizeof(qlearn_policy_t), sizeof(qlearn_solve_t),
      sizeof(qlearn_solve_result_t), sizeof(estimator_state_t));
  for (int p = 0; p < 4; ++p) {
    printf("%-12s trials %3d %3d %3d  solve %s  com [%.6f %.6f %.6f]\n", names[p], trials[p][0],
           trials[p][1], trials[p][2], qlearn_status_str(solve_st[p]), res[p].com_m[0],
           res[p].com_m[1], res[p].com_m[2]);
    if (solve_st[p] != QLEARN_OK) {
      failures++;
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      if (!(fabs(res[p].com_m[k] - com[k]) <= 2e-4)) {
        fprintf(stderr, "FAIL: %s component %d off by %g m\n", names[p], k,
                res[p].com_m[k] - com[k]);
        failures++;
      }
    }
  }
  printf("allocator calls in the measured section: %lu\n", during);
  if (during != 0) {
    fprintf(stderr, "FAIL: the estimate called the allocator %lu times\n", during);
    failures++;
  }
  return failures == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
