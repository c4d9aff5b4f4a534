/* check_assets: the bundled rocks and base block, checked against their requirements from the
 * files alone. Nothing written in the URDF comments is trusted: the inertial is recomputed from the
 * mesh and the density region in the generator's compiled-in parameter table.
 *
 * Requirements (docs/assets.md): every rock 4-10 cm across in each axis, 0.1-0.45 kg, 1000-3000
 * triangles, closed and outward with nothing for model_mesh_check to repair; planar fracture
 * faces at least 2 cm wide (smallest width), each the plane of one fracture in the table; at
 * least two non-parallel faces (>= 45 degrees apart) on which the rock rests with the CoM's
 * projection >= 3 mm inside the support polygon and the plane supporting the whole rock, for the
 * even and the uneven CoM (including the bottom face -z and a side face +-x); the uneven CoM
 * 3-10 mm from the uniform-density one; the URDF inertial equal to the recomputation to 1e-9. */
#define _POSIX_C_SOURCE 200809L
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "comlearn/math3d.h"
#include "comlearn/model.h"
#include "comlearn/model_inertial.h"
#include "model_test_util.h"
#include "rockgen.h"

enum { PATCHES_MAX = 16 };

static const double kRelTol = 1e-9;
static const double kMinMargin_m = 0.003;
static const double kMinFaceWidth_m = 0.02;
static const double kMinPatchArea_m2 = 1e-4; /* smaller flat spots are not looked at */
static const double kNonParallelCos = 0.70710678118654752; /* 45 degrees */

static void rock_path(char *buf, size_t n, const char *name, const char *kind) {
  snprintf(buf, n, "%s/rocks/%s_%s.urdf", COMLEARN_ASSETS_DIR, name, kind);
}

static double max_abs(const double m[3][3]) {
  double r = 0.0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) r = fabs(m[i][j]) > r ? fabs(m[i][j]) : r;
  }
  return r;
}

/* got == want to kRelTol: mass relative, CoM relative to the rock's size, inertia relative to its
 * largest entry. */
static void assert_mass_eq(const char *what, const model_mass_t *got, const model_mass_t *want,
                           double size_m) {
  ck_assert_msg(fabs(got->mass_kg - want->mass_kg) <= kRelTol * want->mass_kg,
                "%s: mass %.17g, recomputed %.17g", what, got->mass_kg, want->mass_kg);
  for (int k = 0; k < 3; ++k) {
    ck_assert_msg(fabs(got->com_m[k] - want->com_m[k]) <= kRelTol * size_m,
                  "%s: com[%d] %.17g, recomputed %.17g", what, k, got->com_m[k], want->com_m[k]);
  }
  const double scale = max_abs(want->inertia_kg_m2);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      ck_assert_msg(fabs(got->inertia_kg_m2[i][j] - want->inertia_kg_m2[i][j]) <= kRelTol * scale,
                    "%s: I[%d][%d] %.17g, recomputed %.17g", what, i, j, got->inertia_kg_m2[i][j],
                    want->inertia_kg_m2[i][j]);
    }
  }
}

/* Everything one rock's tests need, loaded once per test. */
typedef struct {
  const rockgen_spec_t *spec;
  model_object_t obj;
  model_mass_t even_urdf, uneven_urdf; /* what the simulator reads */
  model_mass_t even_calc, uneven_calc; /* recomputed here */
  double size_m;
} rock_t;

static void rock_load(size_t index, rock_t *r) {
  memset(r, 0, sizeof *r);
  r->spec = rockgen_spec_get(index);
  ck_assert_ptr_nonnull(r->spec);
  char path[4096];
  model_error_t err = {{0}};
  rock_path(path, sizeof path, r->spec->name, "even");
  ck_assert_msg(model_object_load(path, NULL, &r->obj, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_msg(model_inertial_load(path, NULL, &r->even_urdf, &err) == MODEL_OK, "%s", err.msg);
  rock_path(path, sizeof path, r->spec->name, "uneven");
  ck_assert_msg(model_inertial_load(path, NULL, &r->uneven_urdf, &err) == MODEL_OK, "%s", err.msg);
  /* The uneven rock's geometry is the even rock's: same mesh file, same link frame. */
  model_object_t other;
  ck_assert_msg(model_object_load(path, NULL, &other, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_str_eq(other.mesh_path, r->obj.mesh_path);
  ck_assert_uint_eq(other.mesh.vertex_count, r->obj.mesh.vertex_count);
  ck_assert_int_eq(memcmp(other.mesh.vertices_m, r->obj.mesh.vertices_m,
                          other.mesh.vertex_count * sizeof *other.mesh.vertices_m),
                   0);
  model_object_free(&other);

  /* Independent recomputation: uniform density from the table; the dense region from the
   * table's normal and offset, relative to the uniform-density CoM computed here. */
  ck_assert_int_eq(model_mesh_mass(&r->obj.mesh, r->spec->density_kg_m3, &r->even_calc), MODEL_OK);
  model_halfspace_t region;
  const double *n = r->spec->region_normal;
  const double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  region.offset_m = r->spec->region_offset_m;
  for (int k = 0; k < 3; ++k) {
    region.normal[k] = n[k] / len;
    region.offset_m += region.normal[k] * r->even_calc.com_m[k];
  }
  ck_assert_int_eq(model_mesh_mass_halfspace(&r->obj.mesh, r->spec->density_kg_m3, &region,
                                             r->spec->region_density_kg_m3, &r->uneven_calc),
                   MODEL_OK);
  for (int k = 0; k < 3; ++k) {
    const double e = r->obj.aabb.max_m[k] - r->obj.aabb.min_m[k];
    r->size_m = e > r->size_m ? e : r->size_m;
  }
}

/* ---- per rock (loop tests: _i is the rock's index in the table) --------------------------- */

START_TEST(rock_inertial_matches_mesh) {
  rock_t r;
  rock_load((size_t)_i, &r);
  assert_mass_eq(r.spec->name, &r.even_urdf, &r.even_calc, r.size_m);
  assert_mass_eq(r.spec->name, &r.uneven_urdf, &r.uneven_calc, r.size_m);
  model_error_t err;
  ck_assert_int_eq(model_mass_check(&r.even_urdf, &err), MODEL_OK);
  ck_assert_int_eq(model_mass_check(&r.uneven_urdf, &err), MODEL_OK);
  model_object_free(&r.obj);
}
END_TEST

START_TEST(rock_size_mass_triangles) {
  rock_t r;
  rock_load((size_t)_i, &r);
  for (int k = 0; k < 3; ++k) {
    const double e = r.obj.aabb.max_m[k] - r.obj.aabb.min_m[k];
    ck_assert_msg(e >= 0.04 && e <= 0.10, "%s: extent %d = %.4f m", r.spec->name, k, e);
    /* link origin at the bounding-box center (up to float32 rounding) */
    ck_assert_double_eq_tol(r.obj.aabb.max_m[k] + r.obj.aabb.min_m[k], 0.0, 1e-8);
  }
  ck_assert_msg(r.even_urdf.mass_kg >= 0.1 && r.even_urdf.mass_kg <= 0.45, "%s even: %.4f kg",
                r.spec->name, r.even_urdf.mass_kg);
  ck_assert_msg(r.uneven_urdf.mass_kg >= 0.1 && r.uneven_urdf.mass_kg <= 0.45, "%s uneven: %.4f kg",
                r.spec->name, r.uneven_urdf.mass_kg);
  ck_assert_uint_ge(r.obj.mesh.triangle_count, 1000);
  ck_assert_uint_le(r.obj.mesh.triangle_count, 3000);
  /* the uneven CoM moved 3-10 mm from the uniform-density CoM */
  const double shift = cl_vec3_dist(r.uneven_urdf.com_m, r.even_calc.com_m);
  ck_assert_msg(shift >= 0.003 && shift <= 0.010, "%s: CoM shift %.4f m", r.spec->name, shift);
  ck_assert_double_eq_tol(cl_vec3_dist(r.even_urdf.com_m, r.even_calc.com_m), 0.0, 1e-12);
  model_object_free(&r.obj);
}
END_TEST

START_TEST(rock_mesh_watertight_unrepaired) {
  rock_t r;
  rock_load((size_t)_i, &r);
  model_mesh_t mesh;
  model_mesh_report_t rep;
  model_error_t err = {{0}};
  ck_assert_msg(model_mesh_load(r.obj.mesh_path, NULL, &mesh, &rep, &err) == MODEL_OK, "%s",
                err.msg);
  ck_assert_uint_eq(rep.removed_degenerate, 0);
  ck_assert_uint_eq(rep.removed_unreferenced, 0);
  ck_assert_int_eq(rep.flipped, 0);
  /* Closed and every edge shared by two triangles (model_mesh_check) of a sphere-like surface:
   * Euler V - E + F = 2 with E = 3F/2. */
  ck_assert_uint_eq(mesh.vertex_count, mesh.triangle_count / 2 + 2);
  /* Checking again changes nothing. */
  model_mesh_t copy;
  ck_assert_int_eq(model_mesh_copy(&mesh, &copy), MODEL_OK);
  ck_assert_int_eq(model_mesh_check(&copy, &rep, &err), MODEL_OK);
  ck_assert_uint_eq(rep.merged_vertices + rep.removed_degenerate + rep.removed_unreferenced, 0);
  ck_assert_int_eq(rep.flipped, 0);
  ck_assert_uint_eq(copy.vertex_count, mesh.vertex_count);
  model_mesh_free(&copy);
  model_mesh_free(&mesh);
  model_object_free(&r.obj);
}
END_TEST

/* The mesh file holds exactly the generator's float32 vertices: what the inertial was computed
 * from is what the simulator loads. */
START_TEST(rock_mesh_is_generated_shape) {
  rock_t r;
  rock_load((size_t)_i, &r);
  model_mesh_t gen;
  ck_assert_int_eq(rockgen_shape_build(r.spec, &gen), MODEL_OK);
  ck_assert_uint_eq(gen.vertex_count, r.obj.mesh.vertex_count);
  ck_assert_uint_eq(gen.triangle_count, r.obj.mesh.triangle_count);
  for (size_t v = 0; v < gen.vertex_count; ++v) {
    int found = 0;
    for (size_t w = 0; w < r.obj.mesh.vertex_count && !found; ++w) {
      found = memcmp(gen.vertices_m[v], r.obj.mesh.vertices_m[w], sizeof gen.vertices_m[v]) == 0;
    }
    ck_assert_msg(found, "%s: generated vertex %zu not in the mesh file", r.spec->name, v);
  }
  model_mass_t m;
  ck_assert_int_eq(model_mesh_mass(&gen, r.spec->density_kg_m3, &m), MODEL_OK);
  assert_mass_eq(r.spec->name, &m, &r.even_calc, r.size_m);
  model_mesh_free(&gen);
  model_object_free(&r.obj);
}
END_TEST

START_TEST(rock_fracture_faces) {
  rock_t r;
  rock_load((size_t)_i, &r);
  rockgen_patch_t patches[PATCHES_MAX];
  size_t count = 0;
  ck_assert_int_eq(
      rockgen_patches_find(&r.obj.mesh, kMinPatchArea_m2, patches, PATCHES_MAX, &count), MODEL_OK);
  ck_assert_uint_le(count, PATCHES_MAX);
  /* One patch per fracture plane of the table, and nothing else flat. */
  ck_assert_uint_eq(count, r.spec->fracture_count);
  for (size_t f = 0; f < r.spec->fracture_count; ++f) {
    double n[3];
    const double *fn = r.spec->fractures[f].normal;
    const double len = sqrt(fn[0] * fn[0] + fn[1] * fn[1] + fn[2] * fn[2]);
    for (int k = 0; k < 3; ++k) n[k] = fn[k] / len;
    int matched = 0;
    for (size_t p = 0; p < count; ++p) {
      const double c =
          n[0] * patches[p].normal[0] + n[1] * patches[p].normal[1] + n[2] * patches[p].normal[2];
      if (c > 1.0 - 1e-9) ++matched;
    }
    ck_assert_msg(matched == 1, "%s: fracture %zu matched %d patches", r.spec->name, f, matched);
  }
  for (size_t p = 0; p < count; ++p) {
    ck_assert_msg(patches[p].width_m >= kMinFaceWidth_m, "%s: face %zu is %.4f m wide",
                  r.spec->name, p, patches[p].width_m);
    /* A fracture plane is a supporting plane of the rock. */
    ck_assert_msg(patches[p].support_excess_m <= ROCKGEN_PLANE_TOL_M,
                  "%s: face %zu: a vertex %.3g m beyond its plane", r.spec->name, p,
                  patches[p].support_excess_m);
  }
  model_object_free(&r.obj);
}
END_TEST

/* Count the faces on which a CoM rests with the margin; require two >= 45 degrees apart, the
 * bottom face (-z) and a side face (+-x) among them. */
static void assert_stable(const char *what, const rockgen_patch_t *patches, size_t count,
                          const double com[3]) {
  size_t stable[PATCHES_MAX], ns = 0;
  int bottom = 0, side = 0;
  for (size_t p = 0; p < count; ++p) {
    const double margin = rockgen_patch_margin(&patches[p], com);
    if (margin < kMinMargin_m || patches[p].support_excess_m > ROCKGEN_PLANE_TOL_M) continue;
    stable[ns++] = p;
    if (patches[p].normal[2] < -1.0 + 1e-12) bottom = 1;
    if (fabs(patches[p].normal[0]) > 1.0 - 1e-12) side = 1;
  }
  int pair = 0;
  for (size_t i = 0; i < ns; ++i) {
    for (size_t j = i + 1; j < ns; ++j) {
      const double *a = patches[stable[i]].normal, *b = patches[stable[j]].normal;
      if (fabs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) <= kNonParallelCos) pair = 1;
    }
  }
  ck_assert_msg(pair, "%s: fewer than two non-parallel stable faces (%zu stable)", what, ns);
  ck_assert_msg(bottom, "%s: does not rest on its bottom face", what);
  ck_assert_msg(side, "%s: does not rest on its +-x side face", what);
}

START_TEST(rock_rests_on_two_faces) {
  rock_t r;
  rock_load((size_t)_i, &r);
  rockgen_patch_t patches[PATCHES_MAX];
  size_t count = 0;
  ck_assert_int_eq(
      rockgen_patches_find(&r.obj.mesh, kMinPatchArea_m2, patches, PATCHES_MAX, &count), MODEL_OK);
  if (count > PATCHES_MAX) count = PATCHES_MAX;
  char what[64];
  snprintf(what, sizeof what, "%s_even", r.spec->name);
  assert_stable(what, patches, count, r.even_urdf.com_m);
  snprintf(what, sizeof what, "%s_uneven", r.spec->name);
  assert_stable(what, patches, count, r.uneven_urdf.com_m);
  model_object_free(&r.obj);
}
END_TEST

/* ---- base block ------------------------------------------------------------------------------ */

START_TEST(base_block) {
  char path[4096];
  snprintf(path, sizeof path, "%s/base/base.urdf", COMLEARN_ASSETS_DIR);
  model_object_t obj;
  model_mass_t m;
  model_error_t err = {{0}};
  ck_assert_msg(model_object_load(path, NULL, &obj, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_msg(model_inertial_load(path, NULL, &m, &err) == MODEL_OK, "%s", err.msg);
  /* 30 x 30 x 10 cm, link origin at the top-face center: top at z = 0. */
  const double lo[3] = {-0.15, -0.15, -0.10}, hi[3] = {0.15, 0.15, 0.0};
  for (int k = 0; k < 3; ++k) {
    ck_assert_double_eq_tol(obj.aabb.min_m[k], lo[k], 1e-12);
    ck_assert_double_eq_tol(obj.aabb.max_m[k], hi[k], 1e-12);
  }
  ck_assert_str_eq(obj.mesh_path, ""); /* a box primitive, not a mesh */
  model_mass_t box;
  ck_assert_int_eq(model_mesh_mass(&obj.mesh, m.mass_kg / (0.3 * 0.3 * 0.1), &box), MODEL_OK);
  assert_mass_eq("base", &m, &box, 0.3);
  ck_assert_int_eq(model_mass_check(&m, &err), MODEL_OK);
  model_object_free(&obj);
}
END_TEST

/* ---- the patch analysis itself, on shapes with known answers ------------------------------- */

START_TEST(patches_of_box) {
  const double lo[3] = {-0.02, -0.03, -0.01}, hi[3] = {0.04, 0.03, 0.02};
  model_mesh_t m;
  mt_box(&m, lo, hi);
  rockgen_patch_t p[PATCHES_MAX];
  size_t count = 0;
  ck_assert_int_eq(rockgen_patches_find(&m, 1e-6, p, PATCHES_MAX, &count), MODEL_OK);
  ck_assert_uint_eq(count, 6);
  /* Largest first: the two 6 x 6 cm faces (z), then 6 x 3 (x... y), then 3 x 6. */
  ck_assert_double_eq_tol(p[0].area_m2, 0.0036, 1e-15);
  ck_assert_double_eq_tol(fabs(p[0].normal[2]), 1.0, 1e-15);
  const double center[3] = {0.01, 0.0, 0.005};
  for (size_t i = 0; i < count; ++i) {
    ck_assert_uint_eq(p[i].triangle_count, 2);
    ck_assert_uint_eq(p[i].support_count, 4);
    ck_assert_double_eq_tol(p[i].support_excess_m, 0.0, 1e-15);
    /* the center is half the smaller side of the face from its edge */
    const int axis = fabs(p[i].normal[0]) > 0.5 ? 0 : (fabs(p[i].normal[1]) > 0.5 ? 1 : 2);
    double half[2];
    int h = 0;
    for (int k = 0; k < 3; ++k) {
      if (k != axis) half[h++] = 0.5 * (hi[k] - lo[k]);
    }
    const double want = half[0] < half[1] ? half[0] : half[1];
    ck_assert_double_eq_tol(rockgen_patch_margin(&p[i], center), want, 1e-12);
    ck_assert_double_eq_tol(p[i].width_m, 2.0 * want, 1e-12);
  }
  /* A CoM outside the footprint of the bottom face tips: negative margin. */
  const double outside[3] = {0.05, 0.0, 0.0};
  for (size_t i = 0; i < count; ++i) {
    if (p[i].normal[2] < -0.5) {
      ck_assert_double_eq_tol(rockgen_patch_margin(&p[i], outside), -0.01, 1e-12);
    }
  }
  model_mesh_free(&m);
}
END_TEST

START_TEST(patches_of_regular_tetrahedron) {
  /* Regular tetrahedron of edge a: the centroid projects onto each face's center, at the face's
   * inradius a / (2 sqrt 3) from its edges. */
  const double s = 0.02;
  double v[4][3] = {{s, s, s}, {s, -s, -s}, {-s, s, -s}, {-s, -s, s}};
  uint32_t tris[4][3] = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
  model_mesh_t m = {v, tris, 4, 4};
  model_mass_t mass;
  ck_assert_int_eq(model_mesh_mass(&m, 1.0, &mass), MODEL_OK); /* outward orientation */
  rockgen_patch_t p[PATCHES_MAX];
  size_t count = 0;
  ck_assert_int_eq(rockgen_patches_find(&m, 1e-8, p, PATCHES_MAX, &count), MODEL_OK);
  ck_assert_uint_eq(count, 4);
  const double a = 2.0 * sqrt(2.0) * s;
  for (size_t i = 0; i < count; ++i) {
    ck_assert_double_eq_tol(rockgen_patch_margin(&p[i], mass.com_m), a / (2.0 * sqrt(3.0)), 1e-12);
    ck_assert_double_eq_tol(p[i].diameter_m, a, 1e-12);
    ck_assert_double_eq_tol(p[i].width_m, a * sqrt(3.0) / 2.0, 1e-12);
  }
}
END_TEST

START_TEST(generator_is_deterministic) {
  for (size_t i = 0; i < rockgen_spec_count(); ++i) {
    model_mesh_t a, b;
    ck_assert_int_eq(rockgen_shape_build(rockgen_spec_get(i), &a), MODEL_OK);
    ck_assert_int_eq(rockgen_shape_build(rockgen_spec_get(i), &b), MODEL_OK);
    ck_assert_uint_eq(a.vertex_count, b.vertex_count);
    ck_assert_int_eq(memcmp(a.vertices_m, b.vertices_m, a.vertex_count * sizeof *a.vertices_m), 0);
    ck_assert_int_eq(memcmp(a.triangles, b.triangles, a.triangle_count * sizeof *a.triangles), 0);
    model_mesh_free(&a);
    model_mesh_free(&b);
  }
  model_mesh_t bad;
  rockgen_spec_t spec = *rockgen_spec_get(0);
  spec.frequency = 0;
  ck_assert_int_eq(rockgen_shape_build(&spec, &bad), MODEL_E_ARG);
  spec = *rockgen_spec_get(0);
  spec.fractures[0].depth_m = 1.0; /* the plane would pass behind the center */
  ck_assert_int_eq(rockgen_shape_build(&spec, &bad), MODEL_E_ARG);
  ck_assert_int_eq(rockgen_shape_build(NULL, &bad), MODEL_E_ARG);
}
END_TEST

static Suite *assets_suite(void) {
  Suite *s = suite_create("assets");
  const int rocks = (int)rockgen_spec_count();
  TCase *rock = tcase_create("rocks");
  tcase_set_timeout(rock, 120);
  tcase_add_loop_test(rock, rock_inertial_matches_mesh, 0, rocks);
  tcase_add_loop_test(rock, rock_size_mass_triangles, 0, rocks);
  tcase_add_loop_test(rock, rock_mesh_watertight_unrepaired, 0, rocks);
  tcase_add_loop_test(rock, rock_mesh_is_generated_shape, 0, rocks);
  tcase_add_loop_test(rock, rock_fracture_faces, 0, rocks);
  tcase_add_loop_test(rock, rock_rests_on_two_faces, 0, rocks);
  suite_add_tcase(s, rock);
  TCase *base = tcase_create("base");
  tcase_add_test(base, base_block);
  suite_add_tcase(s, base);
  TCase *tools = tcase_create("rockgen");
  tcase_add_test(tools, patches_of_box);
  tcase_add_test(tools, patches_of_regular_tetrahedron);
  tcase_add_test(tools, generator_is_deterministic);
  suite_add_tcase(s, tools);
  return s;
}

int main(void) {
  SRunner *runner = srunner_create(assets_suite());
  srunner_run_all(runner, CK_NORMAL);
  const int failed = srunner_ntests_failed(runner);
  srunner_free(runner);
  return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
