/* model_test_util.h - small fixtures shared by the lib/model suites: meshes built in memory and a
 * scratch folder. Everything is static inline so each suite takes only what it uses. */
#ifndef COMLEARN_TESTS_MODEL_TEST_UTIL_H
#define COMLEARN_TESTS_MODEL_TEST_UTIL_H

#if !defined(_POSIX_C_SOURCE) || _POSIX_C_SOURCE < 200809L
#error "define _POSIX_C_SOURCE 200809L before any include (mkdtemp, rmdir, dup2)"
#endif

#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <unistd.h>

#include "comlearn/math3d.h"
#include "comlearn/model.h"

/* A box [lo, hi], 8 vertices, 12 outward triangles; allocated (model_mesh_free releases). */
static inline void mt_box(model_mesh_t *m, const double lo[3], const double hi[3]) {
  memset(m, 0, sizeof *m);
  ck_assert_int_eq(model_mesh_box(lo, hi, m), MODEL_OK);
}

static inline void mt_unit_cube(model_mesh_t *m) {
  const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
  mt_box(m, lo, hi);
}

/* A closed, non-convex, irregular "rock": a UV sphere (rings x segs) whose radius varies with a
 * fixed pattern, coordinates rounded to multiples of 1/1024 so they are exact in float (file
 * formats store floats) and every round trip can be compared bit for bit. */
static inline void mt_rock(model_mesh_t *m, unsigned rings, unsigned segs) {
  const double pi = CL_PI;
  m->vertex_count = 2 + (size_t)(rings - 1) * segs;
  m->triangle_count = 2 * (size_t)segs * (rings - 1);
  m->vertices_m = malloc(m->vertex_count * sizeof *m->vertices_m);
  m->triangles = malloc(m->triangle_count * sizeof *m->triangles);
  ck_assert_ptr_nonnull(m->vertices_m);
  ck_assert_ptr_nonnull(m->triangles);
  const double pole[2][3] = {{0.0, 0.0, 0.75}, {0.0, 0.0, -0.5}};
  memcpy(m->vertices_m[0], pole[0], sizeof pole[0]);
  memcpy(m->vertices_m[1], pole[1], sizeof pole[1]);
  for (unsigned i = 1; i < rings; ++i) {
    double th = pi * i / rings;
    for (unsigned j = 0; j < segs; ++j) {
      double ph = 2.0 * pi * j / segs;
      double r = 1.0 + 0.25 * sin(3.0 * ph + 1.0) * sin(2.0 * th) + 0.1 * cos(5.0 * ph);
      double *v = m->vertices_m[2 + (i - 1) * segs + j];
      v[0] = round(1024.0 * 1.5 * r * sin(th) * cos(ph)) / 1024.0;
      v[1] = round(1024.0 * r * sin(th) * sin(ph)) / 1024.0 + 0.25;
      v[2] = round(1024.0 * 0.8 * r * cos(th)) / 1024.0;
    }
  }
  size_t t = 0;
#define MT_RING(i, j) ((uint32_t)(2 + ((i)-1) * segs + ((j) % segs)))
  for (unsigned j = 0; j < segs; ++j) {
    uint32_t *a = m->triangles[t++];
    a[0] = 0, a[1] = MT_RING(1, j), a[2] = MT_RING(1, j + 1);
    uint32_t *b = m->triangles[t++];
    b[0] = 1, b[1] = MT_RING(rings - 1, j + 1), b[2] = MT_RING(rings - 1, j);
  }
  for (unsigned i = 1; i + 1 < rings; ++i) {
    for (unsigned j = 0; j < segs; ++j) {
      uint32_t *a = m->triangles[t++];
      a[0] = MT_RING(i, j), a[1] = MT_RING(i + 1, j), a[2] = MT_RING(i + 1, j + 1);
      uint32_t *b = m->triangles[t++];
      b[0] = MT_RING(i, j), b[1] = MT_RING(i + 1, j + 1), b[2] = MT_RING(i, j + 1);
    }
  }
#undef MT_RING
}

/* Volume through the library's own mass properties (density 1). */
static inline double mt_volume(const model_mesh_t *m) {
  model_mass_t mass;
  ck_assert_int_eq(model_mesh_mass(m, 1.0, &mass), MODEL_OK);
  return mass.mass_kg;
}

static inline int mt_cmp_vertex(const void *pa, const void *pb) {
  const double *a = pa, *b = pb;
  for (int k = 0; k < 3; ++k) {
    if (a[k] != b[k]) {
      return a[k] < b[k] ? -1 : 1;
    }
  }
  return 0;
}

/* 1 when the two meshes have the same vertex set (sorted, within tol). */
static inline int mt_same_vertices(const model_mesh_t *a, const model_mesh_t *b, double tol) {
  if (a->vertex_count != b->vertex_count) {
    return 0;
  }
  size_t n = a->vertex_count;
  double(*sa)[3] = malloc(n * sizeof *sa);
  double(*sb)[3] = malloc(n * sizeof *sb);
  ck_assert_ptr_nonnull(sa);
  ck_assert_ptr_nonnull(sb);
  memcpy(sa, a->vertices_m, n * sizeof *sa);
  memcpy(sb, b->vertices_m, n * sizeof *sb);
  qsort(sa, n, sizeof *sa, mt_cmp_vertex);
  qsort(sb, n, sizeof *sb, mt_cmp_vertex);
  int same = 1;
  for (size_t i = 0; i < n && same; ++i) {
    for (int k = 0; k < 3; ++k) {
      same = same && fabs(sa[i][k] - sb[i][k]) <= tol;
    }
  }
  free(sa);
  free(sb);
  return same;
}

/* A fresh scratch folder under $TMPDIR (or /tmp); removed by mt_tmpdir_remove(). */
typedef struct {
  char path[256];
} mt_tmpdir_t;

static inline void mt_tmpdir_make(mt_tmpdir_t *d) {
  const char *base = getenv("TMPDIR");
  snprintf(d->path, sizeof d->path, "%s/comlearn_model_XXXXXX",
           base != NULL && base[0] != '\0' ? base : "/tmp");
  ck_assert_ptr_nonnull(mkdtemp(d->path));
}

/* d/name into out. */
static inline const char *mt_join(const mt_tmpdir_t *d, const char *name, char *out, size_t size) {
  int n = snprintf(out, size, "%s/%s", d->path, name);
  ck_assert(n > 0 && (size_t)n < size);
  return out;
}

static inline void mt_write_text(const char *path, const char *text) {
  FILE *f = fopen(path, "wb");
  ck_assert_ptr_nonnull(f);
  ck_assert_uint_eq(fwrite(text, 1, strlen(text), f), strlen(text));
  ck_assert_int_eq(fclose(f), 0);
}

/* Remove the given files (relative to d; folders last, in the order given) and d itself. */
static inline void mt_tmpdir_remove(mt_tmpdir_t *d, const char *const *names, size_t count) {
  char p[512];
  for (size_t i = 0; i < count; ++i) {
    mt_join(d, names[i], p, sizeof p);
    if (remove(p) != 0) {
      (void)rmdir(p);
    }
  }
  ck_assert_int_eq(rmdir(d->path), 0);
}

/* Run a loader with stdout and stderr sent to a file; return how many bytes it printed. */
static inline long mt_printed_bytes(const char *capture_path, model_status_t (*fn)(const char *),
                                    const char *arg, model_status_t *status) {
  fflush(stdout);
  fflush(stderr);
  int saved_out = dup(1), saved_err = dup(2);
  FILE *cap = fopen(capture_path, "wb");
  ck_assert_ptr_nonnull(cap);
  ck_assert_int_ge(dup2(fileno(cap), 1), 0);
  ck_assert_int_ge(dup2(fileno(cap), 2), 0);
  *status = fn(arg);
  fflush(stdout);
  fflush(stderr);
  dup2(saved_out, 1);
  dup2(saved_err, 2);
  close(saved_out);
  close(saved_err);
  fclose(cap);
  FILE *f = fopen(capture_path, "rb");
  ck_assert_ptr_nonnull(f);
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  fclose(f);
  return n;
}

#endif /* COMLEARN_TESTS_MODEL_TEST_UTIL_H */
