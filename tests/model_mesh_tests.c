/* model_mesh_tests.c - mesh validation and repair, loading and saving through assimp. */
#define _POSIX_C_SOURCE 200809L

#include <sys/stat.h>
#include <unistd.h>

#include "comlearn/math3d.h"
#include "file_test_util.h"
#include "model_suites.h"
#include "model_test_util.h"

/* ---- helpers --------------------------------------------------------------------------------- */

static void rock(model_mesh_t *m) { mt_rock(m, 12, 24); }

static void write_bytes(const char *path, const char *data, size_t n) {
  FILE *f = fopen(path, "wb");
  ck_assert_ptr_nonnull(f);
  ck_assert_uint_eq(fwrite(data, 1, n, f), n);
  ck_assert_int_eq(fclose(f), 0);
}

/* Replace the first occurrence of `from` in file `path` by `to`; fails when absent. */
static void edit_file(const char *src, const char *dst, const char *from, const char *to) {
  size_t n;
  char *text = test_slurp(src, &n);
  char *at = strstr(text, from);
  ck_assert_msg(at != NULL, "'%s' not found in %s", from, src);
  FILE *f = fopen(dst, "wb");
  ck_assert_ptr_nonnull(f);
  fwrite(text, 1, (size_t)(at - text), f);
  fputs(to, f);
  fputs(at + strlen(from), f);
  ck_assert_int_eq(fclose(f), 0);
  free(text);
}

static size_t count_substr(const char *text, const char *needle) {
  size_t c = 0;
  for (const char *p = strstr(text, needle); p != NULL; p = strstr(p + 1, needle)) {
    ++c;
  }
  return c;
}

static void flip_triangle(model_mesh_t *m, size_t t) {
  uint32_t tmp = m->triangles[t][1];
  m->triangles[t][1] = m->triangles[t][2];
  m->triangles[t][2] = tmp;
}

static model_status_t load_mesh_quiet(const char *path) {
  model_mesh_t m;
  model_status_t st = model_mesh_load(path, NULL, &m, NULL, NULL);
  model_mesh_free(&m);
  return st;
}

/* ---- status ---------------------------------------------------------------------------------- */

START_TEST(test_status_strings) {
  const model_status_t all[] = {MODEL_OK,          MODEL_E_ARG,         MODEL_E_NOFILE,
                                MODEL_E_PARSE,     MODEL_E_NOLINK,      MODEL_E_NOGEOM,
                                MODEL_E_OPEN,      MODEL_E_ORIENT,      MODEL_E_DEGENERATE,
                                MODEL_E_NONFINITE, MODEL_E_INERTIAL,    MODEL_E_INERTIA_TRIANGLE,
                                MODEL_E_NOMEM,     MODEL_E_UNSUPPORTED, MODEL_E_REGION,
                                MODEL_E_HULL,      MODEL_E_CHAIN,       MODEL_E_IMPLAUSIBLE};
  const size_t n = sizeof all / sizeof all[0];
  ck_assert_uint_eq(n, 18);
  for (size_t i = 0; i < n; ++i) {
    const char *s = model_status_str(all[i]);
    ck_assert_ptr_nonnull(s);
    ck_assert_uint_gt(strlen(s), 1);
    ck_assert_ptr_null(strstr(s, "unknown"));
    for (size_t j = 0; j < i; ++j) {
      ck_assert_str_ne(s, model_status_str(all[j]));
    }
  }
  ck_assert_str_eq(model_status_str(MODEL_OK), "ok");
  ck_assert_ptr_nonnull(strstr(model_status_str((model_status_t)-99), "unknown"));
  ck_assert_ptr_nonnull(strstr(model_status_str((model_status_t)1), "unknown"));
}
END_TEST

/* ---- model_mesh_check ------------------------------------------------------------------------ */

START_TEST(test_check_clean_cube) {
  model_mesh_t m;
  mt_unit_cube(&m);
  model_mesh_report_t rep;
  model_error_t err = {{0}};
  ck_assert_int_eq(model_mesh_check(&m, &rep, &err), MODEL_OK);
  ck_assert_uint_eq(m.vertex_count, 8);
  ck_assert_uint_eq(m.triangle_count, 12);
  ck_assert_uint_eq(rep.merged_vertices, 0);
  ck_assert_uint_eq(rep.removed_degenerate, 0);
  ck_assert_uint_eq(rep.removed_unreferenced, 0);
  ck_assert_int_eq(rep.flipped, 0);
  ck_assert_double_eq_tol(mt_volume(&m), 1.0, 1e-15);
  ck_assert_str_eq(err.msg, ""); /* written on failure only */
  model_mesh_free(&m);
  ck_assert_ptr_null(m.vertices_m);
  ck_assert_uint_eq(m.vertex_count, 0);
  model_mesh_free(NULL);
}
END_TEST

/* STL-like triangle soup: 3 vertices per triangle, joined back to 8. */
START_TEST(test_check_soup_joined) {
  model_mesh_t cube, soup;
  mt_unit_cube(&cube);
  soup.vertex_count = 36;
  soup.triangle_count = 12;
  soup.vertices_m = malloc(36 * sizeof *soup.vertices_m);
  soup.triangles = malloc(12 * sizeof *soup.triangles);
  for (uint32_t t = 0; t < 12; ++t) {
    for (uint32_t k = 0; k < 3; ++k) {
      memcpy(soup.vertices_m[3 * t + k], cube.vertices_m[cube.triangles[t][k]],
             sizeof soup.vertices_m[0]);
      soup.triangles[t][k] = 3 * t + k;
    }
  }
  model_mesh_report_t rep;
  ck_assert_int_eq(model_mesh_check(&soup, &rep, NULL), MODEL_OK);
  ck_assert_uint_eq(rep.merged_vertices, 28);
  ck_assert_uint_eq(soup.vertex_count, 8);
  ck_assert_uint_eq(soup.triangle_count, 12);
  ck_assert(mt_same_vertices(&soup, &cube, 0.0));
  ck_assert_double_eq_tol(mt_volume(&soup), 1.0, 1e-15);
  model_mesh_free(&soup);
  model_mesh_free(&cube);
}
END_TEST

START_TEST(test_check_degenerate_dropped) {
  model_mesh_t m;
  mt_unit_cube(&m);
  /* + a triangle with a repeated vertex, + a zero-area triangle on 3 new collinear vertices. */
  m.vertices_m = realloc(m.vertices_m, 11 * sizeof *m.vertices_m);
  m.triangles = realloc(m.triangles, 14 * sizeof *m.triangles);
  const double extra[3][3] = {{5, 5, 5}, {6, 6, 6}, {7, 7, 7}};
  memcpy(m.vertices_m[8], extra, sizeof extra);
  const uint32_t bad[2][3] = {{0, 0, 1}, {8, 9, 10}};
  memcpy(m.triangles[12], bad, sizeof bad);
  m.vertex_count = 11;
  m.triangle_count = 14;
  model_mesh_report_t rep;
  ck_assert_int_eq(model_mesh_check(&m, &rep, NULL), MODEL_OK);
  ck_assert_uint_eq(rep.removed_degenerate, 2);
  ck_assert_uint_eq(rep.removed_unreferenced, 3);
  ck_assert_uint_eq(rep.merged_vertices, 0);
  ck_assert_uint_eq(m.vertex_count, 8);
  ck_assert_uint_eq(m.triangle_count, 12);
  ck_assert_double_eq_tol(mt_volume(&m), 1.0, 1e-15);
  model_mesh_free(&m);
}
END_TEST

START_TEST(test_check_open_rejected) {
  model_mesh_t m;
  mt_unit_cube(&m);
  m.triangle_count = 11; /* a hole */
  const void *v = m.vertices_m;
  model_error_t err;
  ck_assert_int_eq(model_mesh_check(&m, NULL, &err), MODEL_E_OPEN);
  ck_assert_ptr_nonnull(strstr(err.msg, "3 boundary and 0 non-manifold edges"));
  ck_assert_ptr_eq(m.vertices_m, v); /* unchanged on error */
  ck_assert_uint_eq(m.triangle_count, 11);
  model_mesh_free(&m);
}
END_TEST

/* Two cubes that share an edge: after joining vertices the edge has four triangles. */
START_TEST(test_check_nonmanifold_rejected) {
  model_mesh_t a, b, m;
  const double lo[3] = {1, 1, 0}, hi[3] = {2, 2, 1};
  mt_unit_cube(&a);
  mt_box(&b, lo, hi);
  m.vertex_count = 16;
  m.triangle_count = 24;
  m.vertices_m = malloc(16 * sizeof *m.vertices_m);
  m.triangles = malloc(24 * sizeof *m.triangles);
  memcpy(m.vertices_m, a.vertices_m, 8 * sizeof *m.vertices_m);
  memcpy(m.vertices_m + 8, b.vertices_m, 8 * sizeof *m.vertices_m);
  for (int t = 0; t < 12; ++t) {
    for (int k = 0; k < 3; ++k) {
      m.triangles[t][k] = a.triangles[t][k];
      m.triangles[12 + t][k] = b.triangles[t][k] + 8;
    }
  }
  model_error_t err;
  model_mesh_report_t rep;
  ck_assert_int_eq(model_mesh_check(&m, &rep, &err), MODEL_E_OPEN);
  ck_assert_uint_eq(rep.merged_vertices, 2);
  ck_assert_ptr_nonnull(strstr(err.msg, "0 boundary and 1 non-manifold edges"));
  ck_assert_ptr_nonnull(strstr(err.msg, "used by 4 triangle(s)"));
  model_mesh_free(&a);
  model_mesh_free(&b);
  model_mesh_free(&m);
}
END_TEST

START_TEST(test_check_inside_out_repaired) {
  model_mesh_t m, ref;
  mt_rock(&m, 10, 16);
  mt_rock(&ref, 10, 16);
  const double v = mt_volume(&ref);
  ck_assert_double_gt(v, 1.0);
  for (size_t t = 0; t < m.triangle_count; ++t) {
    flip_triangle(&m, t);
  }
  model_mesh_report_t rep;
  ck_assert_int_eq(model_mesh_check(&m, &rep, NULL), MODEL_OK);
  ck_assert_int_eq(rep.flipped, 1);
  ck_assert_int_eq(memcmp(m.triangles, ref.triangles, ref.triangle_count * sizeof *ref.triangles),
                   0);
  ck_assert_double_eq_tol(mt_volume(&m), v, 1e-12 * v);
  model_mesh_free(&m);
  model_mesh_free(&ref);
}
END_TEST

START_TEST(test_check_inconsistent_rejected) {
  model_mesh_t m;
  mt_rock(&m, 10, 16);
  flip_triangle(&m, 40);
  model_error_t err;
  ck_assert_int_eq(model_mesh_check(&m, NULL, &err), MODEL_E_ORIENT);
  ck_assert_ptr_nonnull(strstr(err.msg, "3 edges are traversed twice in the same direction"));
  ck_assert_ptr_nonnull(strstr(err.msg, "40"));
  model_mesh_free(&m);
}
END_TEST

START_TEST(test_check_nonfinite_rejected) {
  const double bad[3] = {NAN, INFINITY, -INFINITY};
  for (int i = 0; i < 3; ++i) {
    model_mesh_t m;
    mt_unit_cube(&m);
    m.vertices_m[5][i] = bad[i];
    model_error_t err;
    ck_assert_int_eq(model_mesh_check(&m, NULL, &err), MODEL_E_NONFINITE);
    ck_assert_ptr_nonnull(strstr(err.msg, "vertex 5 is not finite"));
    model_mesh_free(&m);
  }
}
END_TEST

START_TEST(test_check_bad_input) {
  model_mesh_t m;
  mt_unit_cube(&m);
  m.triangles[3][1] = 8;
  model_error_t err;
  ck_assert_int_eq(model_mesh_check(&m, NULL, &err), MODEL_E_ARG);
  ck_assert_ptr_nonnull(strstr(err.msg, "triangle 3 uses vertex 8"));
  model_mesh_free(&m);
  ck_assert_int_eq(model_mesh_check(NULL, NULL, NULL), MODEL_E_ARG);
  model_mesh_t empty = {0};
  ck_assert_int_eq(model_mesh_check(&empty, NULL, &err), MODEL_E_DEGENERATE);
  ck_assert_ptr_nonnull(strstr(err.msg, "empty mesh"));
}
END_TEST

/* Closed and consistently oriented but flat: a double-sided square. And too few triangles. */
START_TEST(test_check_zero_volume_rejected) {
  model_mesh_t m;
  m.vertex_count = 4;
  m.triangle_count = 4;
  m.vertices_m = malloc(4 * sizeof *m.vertices_m);
  m.triangles = malloc(4 * sizeof *m.triangles);
  const double v[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  /* front split along 0-2, back along 1-3, so every edge has exactly two opposite uses */
  const uint32_t t[4][3] = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}};
  memcpy(m.vertices_m, v, sizeof v);
  memcpy(m.triangles, t, sizeof t);
  model_error_t err;
  ck_assert_int_eq(model_mesh_check(&m, NULL, &err), MODEL_E_DEGENERATE);
  ck_assert_ptr_nonnull(strstr(err.msg, "encloses no volume"));
  m.triangle_count = 3;
  ck_assert_int_eq(model_mesh_check(&m, NULL, &err), MODEL_E_DEGENERATE);
  ck_assert_ptr_nonnull(strstr(err.msg, "needs >= 4"));
  model_mesh_free(&m);
}
END_TEST

START_TEST(test_copy) {
  model_mesh_t a, b;
  rock(&a);
  ck_assert_int_eq(model_mesh_copy(&a, &b), MODEL_OK);
  ck_assert_uint_eq(b.vertex_count, a.vertex_count);
  ck_assert_uint_eq(b.triangle_count, a.triangle_count);
  ck_assert_ptr_ne(b.vertices_m, a.vertices_m);
  ck_assert_int_eq(memcmp(a.vertices_m, b.vertices_m, a.vertex_count * sizeof *a.vertices_m), 0);
  ck_assert_int_eq(memcmp(a.triangles, b.triangles, a.triangle_count * sizeof *a.triangles), 0);
  ck_assert_int_eq(model_mesh_copy(NULL, &b), MODEL_E_ARG);
  model_mesh_free(&a);
  model_mesh_free(&b);
}
END_TEST

/* ---- load / save round trips ----------------------------------------------------------------- */

typedef struct {
  const char *format;
  const char *ext;
  const char *marker; /* a string the file must contain (ascii vs binary), or NULL */
  int binary;         /* 1: the file must not start with the ascii marker */
} format_case_t;

static const format_case_t FORMATS[] = {
    {"stl", "stl", "facet normal", 0},
    {"stlb", "stl", NULL, 1},
    {"obj", "obj", "\nf ", 0},
    {"ply", "ply", "format ascii", 0},
    {"plyb", "ply", "format binary", 1},
    {"collada", "dae", "<COLLADA", 0},
    {"glb2", "glb", NULL, 1},
};

START_TEST(test_roundtrip_formats) {
  const format_case_t *fc = &FORMATS[_i];
  mt_tmpdir_t d;
  mt_tmpdir_make(&d);
  char name[64], path[512], mtl[64];
  snprintf(name, sizeof name, "rock.%s", fc->ext);
  mt_join(&d, name, path, sizeof path);

  model_mesh_t src, back;
  rock(&src);
  const double v = mt_volume(&src);
  model_error_t err = {{0}};
  ck_assert_msg(model_mesh_save(&src, path, fc->format, &err) == MODEL_OK, "%s", err.msg);
  size_t size;
  char *bytes = test_slurp(path, &size);
  ck_assert_uint_gt(size, 100);
  if (fc->marker != NULL) {
    ck_assert_msg(strstr(bytes, fc->marker) != NULL, "%s lacks '%s'", fc->format, fc->marker);
  }
  if (strcmp(fc->format, "stlb") == 0) {
    /* Binary STL: 80-byte header, uint32 count, 50 bytes per triangle. */
    ck_assert_uint_eq(size, 84 + 50 * src.triangle_count);
  }
  free(bytes);

  model_mesh_report_t rep;
  ck_assert_msg(model_mesh_load(path, NULL, &back, &rep, &err) == MODEL_OK, "%s: %s", fc->format,
                err.msg);
  ck_assert_uint_eq(back.vertex_count, src.vertex_count);
  ck_assert_uint_eq(back.triangle_count, src.triangle_count);
  ck_assert_int_eq(rep.flipped, 0);
  ck_assert_uint_eq(rep.removed_degenerate, 0);
  /* Coordinates are multiples of 1/1024, exact in float: the round trip is exact. */
  ck_assert_msg(mt_same_vertices(&src, &back, 0.0), "%s changed vertices", fc->format);
  ck_assert_double_eq_tol(mt_volume(&back), v, 1e-12 * v);
  model_mesh_free(&back);
  model_mesh_free(&src);

  snprintf(mtl, sizeof mtl, "rock.mtl"); /* the OBJ exporter writes materials next to it */
  const char *names[] = {name, mtl};
  mt_tmpdir_remove(&d, names, strcmp(fc->format, "obj") == 0 ? 2 : 1);
}
END_TEST

/* STL stores three vertices per facet; the loader joins them (assimp joins by position once
 * normals are dropped; model_mesh_check joins what is left). */
START_TEST(test_stl_facets_joined) {
  mt_tmpdir_t d;
  mt_tmpdir_make(&d);
  char path[512];
  mt_join(&d, "cube.stl", path, sizeof path);
  model_mesh_t cube, back;
  mt_unit_cube(&cube);
  ck_assert_int_eq(model_mesh_save(&cube, path, "stl", NULL), MODEL_OK);
  size_t size;
  char *text = test_slurp(path, &size);
  ck_assert_uint_eq(count_substr(text, "vertex "), 36);
  free(text);
  ck_assert_int_eq(model_mesh_load(path, NULL, &back, NULL, NULL), MODEL_OK);
  ck_assert_uint_eq(back.vertex_count, 8);
  ck_assert_uint_eq(back.triangle_count, 12);
  ck_assert(mt_same_vertices(&cube, &back, 0.0));
  model_mesh_free(&cube);
  model_mesh_free(&back);
  const char *names[] = {"cube.stl"};
  mt_tmpdir_remove(&d, names, 1);
}
END_TEST

/* Collada: <unit meter="0.01"> is honoured; <up_axis>Z_UP</up_axis> does not rotate (ROS
 * convention: coordinates as written); a node <matrix> is applied, a mirroring one keeps the
 * mesh outward. */
START_TEST(test_dae_unit_up_axis_and_nodes) {
  mt_tmpdir_t d;
  mt_tmpdir_make(&d);
  char base[512], unit[512], moved[512], mirror[512];
  mt_join(&d, "box.dae", base, sizeof base);
  mt_join(&d, "unit.dae", unit, sizeof unit);
  mt_join(&d, "moved.dae", moved, sizeof moved);
  mt_join(&d, "mirror.dae", mirror, sizeof mirror);
  const double lo[3] = {0, 0, 0}, hi[3] = {1, 2, 3};
  model_mesh_t box, m;
  mt_box(&box, lo, hi);
  ck_assert_int_eq(model_mesh_save(&box, base, "collada", NULL), MODEL_OK);
  model_mesh_free(&box);

  char tmp[512];
  mt_join(&d, "tmp.dae", tmp, sizeof tmp);
  edit_file(base, tmp, "meter=\"1\"", "meter=\"0.01\"");
  edit_file(tmp, unit, "Y_UP", "Z_UP");
  model_aabb_t bb;
  ck_assert_int_eq(model_mesh_load(unit, NULL, &m, NULL, NULL), MODEL_OK);
  ck_assert_int_eq(model_mesh_aabb(&m, &bb), MODEL_OK);
  for (int k = 0; k < 3; ++k) {
    ck_assert_double_eq_tol(bb.min_m[k], 0.0, 1e-9);
    ck_assert_double_eq_tol(bb.max_m[k], 0.01 * hi[k], 1e-9);
  }
  model_mesh_free(&m);

  /* Rotation by 90 degrees about z and a translation: x' = -y + 10, y' = x + 20, z' = z + 30. */
  edit_file(base, moved, "1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1", "0 -1 0 10 1 0 0 20 0 0 1 30 0 0 0 1");
  ck_assert_int_eq(model_mesh_load(moved, NULL, &m, NULL, NULL), MODEL_OK);
  ck_assert_int_eq(model_mesh_aabb(&m, &bb), MODEL_OK);
  const double want_lo[3] = {8, 20, 30}, want_hi[3] = {10, 21, 33};
  for (int k = 0; k < 3; ++k) {
    ck_assert_double_eq_tol(bb.min_m[k], want_lo[k], 1e-6);
    ck_assert_double_eq_tol(bb.max_m[k], want_hi[k], 1e-6);
  }
  ck_assert_double_eq_tol(mt_volume(&m), 6.0, 1e-5);
  model_mesh_free(&m);

  model_mesh_report_t rep;
  edit_file(base, mirror, "1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1", "-1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1");
  ck_assert_int_eq(model_mesh_load(mirror, NULL, &m, &rep, NULL), MODEL_OK);
  ck_assert_int_eq(rep.flipped, 0); /* winding flipped with the mirror, not by the repair */
  ck_assert_int_eq(model_mesh_aabb(&m, &bb), MODEL_OK);
  ck_assert_double_eq_tol(bb.min_m[0], -1.0, 1e-9);
  ck_assert_double_eq_tol(mt_volume(&m), 6.0, 1e-9);
  model_mesh_free(&m);
  const char *names[] = {"box.dae", "unit.dae", "moved.dae", "mirror.dae", "tmp.dae"};
  mt_tmpdir_remove(&d, names, 5);
}
END_TEST

/* An OBJ with two objects: both meshes merged. */
START_TEST(test_obj_two_objects_merged) {
  mt_tmpdir_t d;
  mt_tmpdir_make(&d);
  char path[512];
  mt_join(&d, "two.obj", path, sizeof path);
  mt_write_text(path,
                "o a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"
                "o b\nv 5 0 0\nv 7 0 0\nv 5 2 0\nv 5 0 2\nf 5 7 6\nf 5 6 8\nf 5 8 7\nf 6 7 8\n");
  model_mesh_t m;
  model_error_t err;
  ck_assert_msg(model_mesh_load(path, NULL, &m, NULL, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_uint_eq(m.vertex_count, 8);
  ck_assert_uint_eq(m.triangle_count, 8);
  ck_assert_double_eq_tol(mt_volume(&m), 1.0 / 6.0 + 8.0 / 6.0, 1e-12);
  model_aabb_t bb;
  ck_assert_int_eq(model_mesh_aabb(&m, &bb), MODEL_OK);
  ck_assert_double_eq(bb.max_m[0], 7.0);
  model_mesh_free(&m);
  const char *names[] = {"two.obj"};
  mt_tmpdir_remove(&d, names, 1);
}
END_TEST

/* Per-axis scale, including a mirror (negative component): vertices scaled, still outward. */
START_TEST(test_load_scale) {
  mt_tmpdir_t d;
  mt_tmpdir_make(&d);
  char path[512];
  mt_join(&d, "rock.ply", path, sizeof path);
  model_mesh_t src, m;
  rock(&src);
  const double v = mt_volume(&src);
  ck_assert_int_eq(model_mesh_save(&src, path, "plyb", NULL), MODEL_OK);
  const double scale[3] = {2.0, -3.0, 0.5};
  model_mesh_report_t rep;
  ck_assert_int_eq(model_mesh_load(path, scale, &m, &rep, NULL), MODEL_OK);
  ck_assert_int_eq(rep.flipped, 0);
  for (size_t i = 0; i < src.vertex_count; ++i) {
    for (int k = 0; k < 3; ++k) {
      src.vertices_m[i][k] *= scale[k];
    }
  }
  ck_assert(mt_same_vertices(&src, &m, 0.0));
  ck_assert_double_eq_tol(mt_volume(&m), 3.0 * v, 1e-12 * v);
  model_mesh_free(&m);

  model_error_t err;
  const double zero[3] = {1, 0, 1}, nan3[3] = {1, NAN, 1};
  ck_assert_int_eq(model_mesh_load(path, zero, &m, NULL, &err), MODEL_E_ARG);
  ck_assert_ptr_nonnull(strstr(err.msg, path));
  ck_assert_int_eq(model_mesh_load(path, nan3, &m, NULL, &err), MODEL_E_NONFINITE);
  ck_assert_ptr_null(m.vertices_m);
  model_mesh_free(&src);
  const char *names[] = {"rock.ply"};
  mt_tmpdir_remove(&d, names, 1);
}
END_TEST

/* Defective files: each rejected (or repaired) with a message naming the file. */
START_TEST(test_load_defective_files) {
  mt_tmpdir_t d;
  mt_tmpdir_make(&d);
  char inside_out[512], open[512], orient[512], nan_obj[512];
  mt_join(&d, "inside_out.stl", inside_out, sizeof inside_out);
  mt_join(&d, "open.stl", open, sizeof open);
  mt_join(&d, "orient.ply", orient, sizeof orient);
  mt_join(&d, "nan.obj", nan_obj, sizeof nan_obj);
  model_mesh_t m, out;
  model_mesh_report_t rep;
  model_error_t err;

  rock(&m);
  for (size_t t = 0; t < m.triangle_count; ++t) {
    flip_triangle(&m, t);
  }
  ck_assert_int_eq(model_mesh_save(&m, inside_out, "stlb", NULL), MODEL_OK);
  ck_assert_int_eq(model_mesh_load(inside_out, NULL, &out, &rep, &err), MODEL_OK);
  ck_assert_int_eq(rep.flipped, 1);
  ck_assert_double_gt(mt_volume(&out), 1.0);
  model_mesh_free(&out);
  model_mesh_free(&m);

  rock(&m);
  m.triangle_count -= 1;
  ck_assert_int_eq(model_mesh_save(&m, open, "stlb", NULL), MODEL_OK);
  ck_assert_int_eq(model_mesh_load(open, NULL, &out, NULL, &err), MODEL_E_OPEN);
  ck_assert_ptr_nonnull(strstr(err.msg, open));
  ck_assert_ptr_nonnull(strstr(err.msg, "not closed"));
  ck_assert_ptr_null(out.vertices_m);
  model_mesh_free(&m);

  rock(&m);
  flip_triangle(&m, 7);
  ck_assert_int_eq(model_mesh_save(&m, orient, "ply", NULL), MODEL_OK);
  ck_assert_int_eq(model_mesh_load(orient, NULL, &out, NULL, &err), MODEL_E_ORIENT);
  ck_assert_ptr_nonnull(strstr(err.msg, orient));
  model_mesh_free(&m);

  mt_write_text(nan_obj,
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 nan\nf 1 3 2\nf 1 2 4\nf 1 4 3\n"
                "f 2 3 4\n");
  ck_assert_int_eq(model_mesh_load(nan_obj, NULL, &out, NULL, &err), MODEL_E_NONFINITE);
  ck_assert_ptr_nonnull(strstr(err.msg, nan_obj));
  ck_assert_ptr_nonnull(strstr(err.msg, "not finite"));
  const char *names[] = {"inside_out.stl", "open.stl", "orient.ply", "nan.obj"};
  mt_tmpdir_remove(&d, names, 4);
}
END_TEST

/* Files that crash, hang or exhaust a parser, or that are no files (docs/security.md): each is
 * refused with a message naming the file and what happened, and the process goes on. Debian's
 * assimp 5.2.5 segfaults on the 21-byte PLY and loops forever on the 29-byte one (in a child
 * process here: "crashed", "time limit", after 2 s of CPU); a pipe, /dev/zero and a file over
 * MODEL_MESH_MAX_BYTES are refused before any parser reads a byte. A good mesh loads after them. */
START_TEST(test_load_hostile_files) {
  mt_tmpdir_t d;
  mt_tmpdir_make(&d);
  char path[512];
  model_mesh_t out;
  model_error_t err;
  mt_join(&d, "segv.ply", path, sizeof path);
  write_bytes(path, "ply\nformat binary_\0\0\0", 21);
  ck_assert_int_eq(model_mesh_load(path, NULL, &out, NULL, &err), MODEL_E_PARSE);
  ck_assert_ptr_nonnull(strstr(err.msg, path));
  ck_assert_msg(strstr(err.msg, "crashed") != NULL, "%s", err.msg);
  ck_assert_ptr_null(out.vertices_m);

  mt_join(&d, "loop.ply", path, sizeof path);
  write_bytes(path, "ply\nformat ascii 1.0\ncomment\n", 29);
  ck_assert_int_eq(model_mesh_load(path, NULL, &out, NULL, &err), MODEL_E_PARSE);
  ck_assert_msg(strstr(err.msg, "time limit") != NULL, "%s", err.msg);

  mt_join(&d, "pipe.stl", path, sizeof path);
  ck_assert_int_eq(mkfifo(path, 0600), 0); /* no writer: opening it must not wait */
  ck_assert_int_eq(model_mesh_load(path, NULL, &out, NULL, &err), MODEL_E_NOFILE);
  ck_assert_msg(strstr(err.msg, "not a regular file") != NULL, "%s", err.msg);
  ck_assert_int_eq(model_mesh_load("/dev/zero", NULL, &out, NULL, &err), MODEL_E_NOFILE);
  ck_assert_ptr_nonnull(strstr(err.msg, "not a regular file"));

  mt_join(&d, "huge.stl", path, sizeof path); /* sparse: no disk used */
  FILE *f = fopen(path, "wb");
  ck_assert_ptr_nonnull(f);
  ck_assert_int_eq(ftruncate(fileno(f), (off_t)MODEL_MESH_MAX_BYTES + 1), 0);
  fclose(f);
  ck_assert_int_eq(model_mesh_load(path, NULL, &out, NULL, &err), MODEL_E_PARSE);
  ck_assert_msg(strstr(err.msg, "limit") != NULL, "%s", err.msg);

  model_mesh_t m;
  rock(&m);
  mt_join(&d, "good.stl", path, sizeof path);
  ck_assert_int_eq(model_mesh_save(&m, path, "stlb", NULL), MODEL_OK);
  ck_assert_int_eq(model_mesh_load(path, NULL, &out, NULL, &err), MODEL_OK);
  ck_assert_uint_eq(out.triangle_count, m.triangle_count);
  model_mesh_free(&out);
  model_mesh_free(&m);
  const char *names[] = {"segv.ply", "loop.ply", "pipe.stl", "huge.stl", "good.stl"};
  mt_tmpdir_remove(&d, names, 5);
}
END_TEST

/* Missing, unreadable, empty, garbage and truncated files. */
START_TEST(test_load_unreadable_files) {
  mt_tmpdir_t d;
  mt_tmpdir_make(&d);
  char path[512];
  model_mesh_t out;
  model_error_t err;

  mt_join(&d, "missing.stl", path, sizeof path);
  ck_assert_int_eq(model_mesh_load(path, NULL, &out, NULL, &err), MODEL_E_NOFILE);
  ck_assert_ptr_nonnull(strstr(err.msg, path));
  ck_assert_ptr_nonnull(strstr(err.msg, "No such file"));
  ck_assert_int_eq(model_mesh_load(d.path, NULL, &out, NULL, &err), MODEL_E_NOFILE);
  ck_assert_ptr_nonnull(strstr(err.msg, "is a folder"));
  ck_assert_int_eq(model_mesh_load("", NULL, &out, NULL, &err), MODEL_E_ARG);
  ck_assert_int_eq(model_mesh_load(NULL, NULL, &out, NULL, &err), MODEL_E_ARG);
  ck_assert_int_eq(model_mesh_load(path, NULL, NULL, NULL, &err), MODEL_E_ARG);

  mt_join(&d, "empty.stl", path, sizeof path);
  write_bytes(path, "", 0);
  ck_assert_int_eq(model_mesh_load(path, NULL, &out, NULL, &err), MODEL_E_PARSE);
  ck_assert_ptr_nonnull(strstr(err.msg, path));

  /* Garbage bytes (a fixed pseudo-random pattern) under each extension. */
  char garbage[600];
  uint64_t x = 12345u;
  for (size_t i = 0; i < sizeof garbage; ++i) garbage[i] = (char)(cl_rng_next(&x) >> 56);
  const char *exts[] = {"stl", "obj", "ply", "dae"};
  for (int i = 0; i < 4; ++i) {
    char name[32];
    snprintf(name, sizeof name, "garbage.%s", exts[i]);
    mt_join(&d, name, path, sizeof path);
    write_bytes(path, garbage, sizeof garbage);
    ck_assert_msg(model_mesh_load(path, NULL, &out, NULL, &err) == MODEL_E_PARSE, "%s", name);
    ck_assert_ptr_nonnull(strstr(err.msg, path));
    ck_assert_ptr_null(out.vertices_m);
    /* and assimp prints nothing about it */
    char capture[512];
    model_status_t st;
    mt_join(&d, "capture.txt", capture, sizeof capture);
    ck_assert_int_eq(mt_printed_bytes(capture, load_mesh_quiet, path, &st), 0);
    ck_assert_int_eq(st, MODEL_E_PARSE);
  }

  /* A binary STL cut after 5 of its triangles. */
  model_mesh_t m;
  rock(&m);
  char full[512];
  mt_join(&d, "full.stl", full, sizeof full);
  ck_assert_int_eq(model_mesh_save(&m, full, "stlb", NULL), MODEL_OK);
  model_mesh_free(&m);
  size_t size;
  char *bytes = test_slurp(full, &size);
  mt_join(&d, "truncated.stl", path, sizeof path);
  write_bytes(path, bytes, 84 + 5 * 50);
  free(bytes);
  ck_assert_int_eq(model_mesh_load(path, NULL, &out, NULL, &err), MODEL_E_PARSE);
  ck_assert_ptr_nonnull(strstr(err.msg, path));
  const char *names[] = {"empty.stl",   "garbage.stl", "garbage.obj",   "garbage.ply",
                         "garbage.dae", "full.stl",    "truncated.stl", "capture.txt"};
  mt_tmpdir_remove(&d, names, 8);
}
END_TEST

START_TEST(test_save_errors) {
  mt_tmpdir_t d;
  mt_tmpdir_make(&d);
  char path[512];
  model_mesh_t m;
  model_error_t err;
  mt_unit_cube(&m);
  mt_join(&d, "cube.xyz", path, sizeof path);
  ck_assert_int_eq(model_mesh_save(&m, path, "no-such-format", &err), MODEL_E_UNSUPPORTED);
  ck_assert_ptr_nonnull(strstr(err.msg, "no-such-format"));
  mt_join(&d, "no/such/folder/cube.stl", path, sizeof path);
  ck_assert_int_eq(model_mesh_save(&m, path, "stlb", &err), MODEL_E_NOFILE);
  ck_assert_ptr_nonnull(strstr(err.msg, path));
  ck_assert_int_eq(model_mesh_save(&m, NULL, "stl", &err), MODEL_E_ARG);
  ck_assert_int_eq(model_mesh_save(NULL, path, "stl", &err), MODEL_E_ARG);
  m.triangles[0][0] = 99;
  ck_assert_int_eq(model_mesh_save(&m, path, "stl", &err), MODEL_E_ARG);
  m.triangles[0][0] = 0;
  m.vertices_m[2][1] = NAN;
  ck_assert_int_eq(model_mesh_save(&m, path, "stl", &err), MODEL_E_NONFINITE);
  model_mesh_free(&m);
  mt_tmpdir_remove(&d, NULL, 0);
}
END_TEST

START_TEST(test_box_primitive) {
  const double lo[3] = {-0.01, 0.02, -0.03}, hi[3] = {0.03, 0.05, 0.01};
  model_mesh_t m = {0};
  ck_assert_int_eq(model_mesh_box(lo, hi, &m), MODEL_OK);
  model_mesh_report_t rep;
  ck_assert_int_eq(model_mesh_check(&m, &rep, NULL), MODEL_OK);
  ck_assert_int_eq(rep.flipped, 0); /* already outward */
  ck_assert_uint_eq(m.vertex_count, 8);
  ck_assert_uint_eq(m.triangle_count, 12);
  model_mass_t mass;
  ck_assert_int_eq(model_mesh_mass(&m, 1.0, &mass), MODEL_OK);
  ck_assert_double_eq_tol(mass.mass_kg, 0.04 * 0.03 * 0.04, 1e-18);
  for (int k = 0; k < 3; ++k) ck_assert_double_eq_tol(mass.com_m[k], 0.5 * (lo[k] + hi[k]), 1e-15);
  model_mesh_free(&m);
  const double flat[3] = {0.03, 0.02, 0.01}, nan_hi[3] = {0.03, NAN, 0.01};
  ck_assert_int_eq(model_mesh_box(lo, flat, &m), MODEL_E_ARG); /* hi.y == lo.y */
  ck_assert_int_eq(model_mesh_box(lo, nan_hi, &m), MODEL_E_NONFINITE);
  ck_assert_int_eq(model_mesh_box(NULL, hi, &m), MODEL_E_ARG);
  ck_assert_ptr_null(m.vertices_m);
}
END_TEST

/* model_rot_to_quat inverts model_quat_to_rot (up to the sign of q) in every branch of
 * Shepperd's method: the identity, half turns about each axis (trace -1, each diagonal entry
 * largest in turn) and a spread of seeded rotations; the result is unit with w >= 0. */
START_TEST(test_rot_quat_round_trip) {
  double qs[64][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}, {0, 0.6, 0.8, 0}};
  uint64_t x = 1;
  for (int i = 5; i < 64; ++i)
    for (int k = 0; k < 4; ++k) qs[i][k] = cl_rng_uniform(&x) - 0.5;
  for (int i = 0; i < 64; ++i) {
    double n = 0.0;
    for (int k = 0; k < 4; ++k) n += qs[i][k] * qs[i][k];
    for (int k = 0; k < 4; ++k) qs[i][k] /= sqrt(n);
    double r[3][3], q[4], r2[3][3];
    model_quat_to_rot(qs[i], r);
    model_rot_to_quat((const double(*)[3])r, q);
    ck_assert_double_eq_tol(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3], 1.0, 1e-14);
    ck_assert(q[0] >= 0.0);
    const double sgn =
        (q[0] * qs[i][0] + q[1] * qs[i][1] + q[2] * qs[i][2] + q[3] * qs[i][3]) < 0.0 ? -1.0 : 1.0;
    for (int k = 0; k < 4; ++k) ck_assert_double_eq_tol(q[k], sgn * qs[i][k], 1e-12);
    model_quat_to_rot(q, r2);
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) ck_assert_double_eq_tol(r2[a][b], r[a][b], 1e-14);
  }
}
END_TEST

Suite *model_mesh_suite(void) {
  Suite *s = suite_create("model_mesh");
  TCase *tc = tcase_create("check");
  tcase_add_test(tc, test_status_strings);
  tcase_add_test(tc, test_check_clean_cube);
  tcase_add_test(tc, test_box_primitive);
  tcase_add_test(tc, test_check_soup_joined);
  tcase_add_test(tc, test_check_degenerate_dropped);
  tcase_add_test(tc, test_check_open_rejected);
  tcase_add_test(tc, test_check_nonmanifold_rejected);
  tcase_add_test(tc, test_check_inside_out_repaired);
  tcase_add_test(tc, test_check_inconsistent_rejected);
  tcase_add_test(tc, test_check_nonfinite_rejected);
  tcase_add_test(tc, test_check_bad_input);
  tcase_add_test(tc, test_check_zero_volume_rejected);
  tcase_add_test(tc, test_copy);
  tcase_add_test(tc, test_rot_quat_round_trip);
  suite_add_tcase(s, tc);
  TCase *io = tcase_create("io");
  tcase_set_timeout(io, 60);
  tcase_add_loop_test(io, test_roundtrip_formats, 0, (int)(sizeof FORMATS / sizeof FORMATS[0]));
  tcase_add_test(io, test_stl_facets_joined);
  tcase_add_test(io, test_dae_unit_up_axis_and_nodes);
  tcase_add_test(io, test_obj_two_objects_merged);
  tcase_add_test(io, test_load_scale);
  tcase_add_test(io, test_load_defective_files);
  tcase_add_test(io, test_load_unreadable_files);
  tcase_add_test(io, test_load_hostile_files);
  tcase_add_test(io, test_save_errors);
  suite_add_tcase(s, io);
  return s;
}
