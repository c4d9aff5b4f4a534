/* check_model_noalloc: lib/model's outcome model (comlearn/model_outcome.h) allocates nothing
 * with a work area: every malloc / calloc / realloc is counted (this executable links with --wrap
 * for them, which reaches every reference in the project's static archives) while
 * model_support_polygon, model_outcome_support_build / _test and model_outcome_predict run.
 * model_outcome_predict without a work area must allocate: that shows the counting works. */
#define _POSIX_C_SOURCE 200809L

#include "comlearn/model_outcome.h"
#include "comlearn/model_support.h"
#include "model_test_util.h"

#include "alloc_count.h"

/* The irregular test rock (2 000 triangles) on its largest hull face, the CoM over that face's
 * middle set 0 to 40 mm inside B's +X edge at 41 yaws (from resting on the edge line to fully on
 * B), 100 CoMs each. */
START_TEST(test_outcome_allocates_nothing) {
  model_mesh_t m = {0};
  mt_rock(&m, 25, 40);
  for (size_t i = 0; i < m.vertex_count; ++i)
    for (int k = 0; k < 3; ++k) m.vertices_m[i][k] *= 0.03; /* ~5 cm */
  const size_t size = model_outcome_work_size(&m);
  void *mem = malloc(size);
  model_outcome_support_t *s = malloc(sizeof *s);
  ck_assert(mem && s);
  model_outcome_work_t *w = model_outcome_work_init(mem, size, &m);
  ck_assert_ptr_nonnull(w);
  const double base[3] = {0.3, 0.3, 0.1}, com0[3] = {0, 0, 0};
  model_face_t faces[64];
  size_t nf = 0; /* the largest hull face (model_faces_find allocates: before the counting) */
  ck_assert_int_eq(model_faces_find(&m, com0, NULL, faces, 64, &nf), MODEL_OK);
  ck_assert_uint_gt(nf, 0);
  const double *up = faces[0].orientation_wxyz;
  /* a CoM over the middle of that face: its support polygon's vertex mean, in the link frame */
  model_pose_t mid = {.position_m = {0, 0, 0.1}};
  memcpy(mid.orientation_wxyz, up, sizeof mid.orientation_wxyz);
  ck_assert_int_eq(model_outcome_support_build(&m, &mid, base, NULL, w, s), MODEL_OK);
  ck_assert(s->valid);
  double cw[3] = {0, 0, 0}, c0[3];
  for (size_t i = 0; i < s->vertex_count; ++i)
    for (int k = 0; k < 2; ++k) cw[k] += s->polygon_xy_m[i][k] / (double)s->vertex_count;
  cw[2] = s->support_z_m + 0.001;
  for (int k = 0; k < 3; ++k) cw[k] -= mid.position_m[k];
  for (int k = 0; k < 3; ++k)
    c0[k] = s->rot[0][k] * cw[0] + s->rot[1][k] * cw[1] + s->rot[2][k] * cw[2];
  double poly[MODEL_OUTCOME_MAX_VERTICES][2];
  size_t polygons = 0, in_total = 0, failures = 0;
  /* no Check assertion while counting: each one records a checkpoint (which may allocate) */
  counting = 1;
  for (int k = 0; k <= 40; ++k) {
    double q[4], r[3][3], p[3];
    model_orientation_yawed(up, 0.15 * k, q);
    model_quat_to_rot(q, r);
    for (int a = 0; a < 3; ++a) p[a] = c0[a] + 1e-3 * k * r[0][a]; /* c0 0 to 40 mm inside */
    model_pose_t pose;
    size_t n = 0;
    failures += model_pose_over_edge(&m, base, q, MODEL_EDGE_PX, p, 0.0, 1e-6, &pose) != MODEL_OK;
    failures += model_support_polygon(&m, &pose, base, 1e-6, w, poly, MODEL_OUTCOME_MAX_VERTICES,
                                      &n) != MODEL_OK;
    polygons += n > 0;
    failures += model_outcome_support_build(&m, &pose, base, NULL, w, s) != MODEL_OK;
    for (int c = 0; c < 100; ++c) {
      const double com[3] = {c0[0] + 2e-5 * (c - 50), c0[1] + 1e-5 * (c % 7), c0[2]};
      int in = 0, in2 = 0;
      double margin = 0.0, margin2 = 0.0;
      failures += model_outcome_support_test(s, com, &in, &margin) != MODEL_OK;
      failures += model_outcome_predict(&m, &pose, base, com, NULL, w, &in2, &margin2) != MODEL_OK;
      failures += in != in2 || margin != margin2;
      in_total += (size_t)in;
    }
  }
  counting = 0;
  ck_assert_uint_eq(allocations, 0);
  ck_assert_uint_eq(failures, 0);
  ck_assert_uint_eq(polygons, 41);
  ck_assert_uint_gt(in_total, 0);
  /* the counter counts: without a work area model_outcome_predict allocates one */
  const double com[3] = {0, 0, 0};
  int in = 0;
  double margin = 0.0;
  counting = 1;
  const model_status_t st = model_outcome_predict(&m, &mid, base, com, NULL, NULL, &in, &margin);
  counting = 0;
  ck_assert_int_eq(st, MODEL_OK);
  ck_assert_uint_gt(allocations, 0);
  free(s);
  free(mem);
  model_mesh_free(&m);
}
END_TEST

int main(void) {
  Suite *suite = suite_create("model_noalloc");
  TCase *tc = tcase_create("outcome");
  tcase_set_timeout(tc, 60);
  tcase_add_test(tc, test_outcome_allocates_nothing);
  suite_add_tcase(suite, tc);
  SRunner *runner = srunner_create(suite);
  srunner_run_all(runner, CK_NORMAL);
  const int failed = srunner_ntests_failed(runner);
  srunner_free(runner);
  return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
