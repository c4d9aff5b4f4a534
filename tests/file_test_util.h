/* file_test_util.h - whole files in tests: read one into memory, compare two byte for byte.
 * Static inline; every failure is a Check assertion naming the path. */
#ifndef COMLEARN_TESTS_FILE_TEST_UTIL_H
#define COMLEARN_TESTS_FILE_TEST_UTIL_H

#include <check.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The whole file, malloc'd and NUL-terminated (the caller frees); *size (may be NULL) its
 * length. */
static inline char *test_slurp(const char *path, size_t *size) {
  FILE *f = fopen(path, "rb");
  ck_assert_msg(f != NULL, "%s: %s", path, strerror(errno));
  ck_assert_int_eq(fseek(f, 0, SEEK_END), 0);
  const long n = ftell(f);
  ck_assert_int_ge(n, 0);
  rewind(f);
  char *buf = malloc((size_t)n + 1);
  ck_assert_ptr_nonnull(buf);
  ck_assert_uint_eq(fread(buf, 1, (size_t)n, f), (size_t)n);
  buf[n] = '\0';
  fclose(f);
  if (size) *size = (size_t)n;
  return buf;
}

/* 1 when the two files hold the same bytes. */
static inline int test_same_file(const char *a, const char *b) {
  size_t na, nb;
  char *x = test_slurp(a, &na), *y = test_slurp(b, &nb);
  const int same = na == nb && memcmp(x, y, na) == 0;
  free(x);
  free(y);
  return same;
}

#endif
