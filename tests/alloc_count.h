/* alloc_count.h - counts malloc / calloc / realloc calls while `counting` is 1, for a test
 * program linked with -Wl,--wrap=malloc,--wrap=calloc,--wrap=realloc (check_model_noalloc,
 * check_estimate_noalloc). Include it in one file of the program: it defines the wrappers. */
#ifndef COMLEARN_TESTS_ALLOC_COUNT_H
#define COMLEARN_TESTS_ALLOC_COUNT_H

#include <stddef.h>

void *__real_malloc(size_t n);
void *__real_calloc(size_t n, size_t size);
void *__real_realloc(void *p, size_t n);
void *__wrap_malloc(size_t n);
void *__wrap_calloc(size_t n, size_t size);
void *__wrap_realloc(void *p, size_t n);

/* volatile: the compiler takes malloc for a call that reads no global */
static volatile size_t counting; /* 1 while the code under test runs */
static volatile size_t allocations;

void *__wrap_malloc(size_t n) {
  allocations += counting;
  return __real_malloc(n);
}
void *__wrap_calloc(size_t n, size_t size) {
  allocations += counting;
  return __real_calloc(n, size);
}
void *__wrap_realloc(void *p, size_t n) {
  allocations += counting;
  return __real_realloc(p, n);
}

#endif
