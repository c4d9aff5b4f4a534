/* balance_stack_tests.c - stacks (comlearn/balance_stack.h): poses set onto another object, and
 * whether a stack stands. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "balance_poses_fixtures.h"
#include "balance_suites.h"
#include "comlearn/balance_poses.h"
#include "comlearn/balance_stack.h"
#include "comlearn/math3d.h"

static const double kBoxH[3] = {0.03, 0.02, 0.01};
static const double kUp[4] = {1, 0, 0, 0};

static balance_world_t *world_new(void) {
  balance_config_t cfg;
  balance_config_default(&cfg);
  balance_world_t *w = NULL;
  ck_assert_int_eq(balance_world_create(&cfg, &w), BALANCE_OK);
  return w;
}

/* Two 60 x 40 x 20 mm boxes, 0.2 kg each, CoM at the center; the top one's CoM at x = top_x. */
typedef struct {
  model_mesh_t mesh;
  balance_world_t *w;
  balance_object_t *obj[2];
  model_pose_t pose[2];
} two_boxes_t;

static void two_boxes(two_boxes_t *t, double top_x) {
  const double com[3] = {0, 0, 0};
  memset(t, 0, sizeof *t);
  bp_box(&t->mesh, kBoxH, 0.0);
  model_mass_t mass;
  bp_box_mass(kBoxH, 0.2, com, &mass);
  t->w = world_new();
  for (int i = 0; i < 2; ++i)
    ck_assert_int_eq(balance_object_create(t->w, &t->mesh, &mass, &t->obj[i]), BALANCE_OK);
  const model_pose_t bottom = {{0.0, 0.0, kBoxH[2] - 1e-6}, {1, 0, 0, 0}};
  t->pose[0] = bottom;
  const double at[2] = {top_x, 0.0};
  ck_assert_int_eq(
      balance_stack_pose_above(&t->mesh, &bottom, &t->mesh, kUp, com, at, 1e-6, &t->pose[1]),
      BALANCE_OK);
}

static void two_boxes_free(two_boxes_t *t) {
  balance_world_destroy(t->w);
  model_mesh_free(&t->mesh);
}

START_TEST(pose_above_is_exact_for_boxes) {
  two_boxes_t t;
  two_boxes(&t, 0.01);
  /* Bottom box top at 20 mm - 1 um; the top box's center 10 mm above that, less 1 um. */
  ck_assert_double_eq_tol(t.pose[1].position_m[2], 3.0 * kBoxH[2] - 2e-6, 1e-15);
  ck_assert_double_eq_tol(t.pose[1].position_m[0], 0.01, 1e-15);
  /* Turned 45 degrees about z, the top box still rests on the bottom's top face. */
  const double q45[4] = {cos(CL_PI / 8), 0, 0, sin(CL_PI / 8)}, c[3] = {0, 0, 0}, at[2] = {0, 0};
  model_pose_t p;
  ck_assert_int_eq(balance_stack_pose_above(&t.mesh, &t.pose[0], &t.mesh, q45, c, at, 0.0, &p),
                   BALANCE_OK);
  ck_assert_double_eq_tol(p.position_m[2], 3.0 * kBoxH[2] - 1e-6, 1e-15);
  /* Turned 90 degrees about x it stands on a 60 x 20 mm face: center 20 mm above the touch;
   * turned 45 degrees, on a 60 mm edge: (20 + 10) / sqrt(2) mm above it. */
  const double qx[4] = {cos(CL_PI / 4), sin(CL_PI / 4), 0, 0};
  ck_assert_int_eq(balance_stack_pose_above(&t.mesh, &t.pose[0], &t.mesh, qx, c, at, 0.0, &p),
                   BALANCE_OK);
  ck_assert_double_eq_tol(p.position_m[2], 2.0 * kBoxH[2] - 1e-6 + kBoxH[1], 1e-15);
  const double qx45[4] = {cos(CL_PI / 8), sin(CL_PI / 8), 0, 0};
  ck_assert_int_eq(balance_stack_pose_above(&t.mesh, &t.pose[0], &t.mesh, qx45, c, at, 0.0, &p),
                   BALANCE_OK);
  ck_assert_double_eq_tol(p.position_m[2],
                          2.0 * kBoxH[2] - 1e-6 + (kBoxH[1] + kBoxH[2]) / sqrt(2.0), 1e-15);
  /* No overlap seen from above. */
  const double far[2] = {0.5, 0.0};
  ck_assert_int_eq(balance_stack_pose_above(&t.mesh, &t.pose[0], &t.mesh, kUp, c, far, 0.0, &p),
                   BALANCE_E_POSE);
  two_boxes_free(&t);
}
END_TEST

START_TEST(two_boxes_centered_stand) {
  two_boxes_t t;
  two_boxes(&t, 0.0);
  balance_stack_config_t cfg;
  balance_stack_config_default(&cfg);
  cfg.duration_s = 2.0;
  balance_stack_result_t r;
  balance_stack_object_t per[2];
  ck_assert_int_eq(balance_stack_run(t.w, t.obj, t.pose, 2, &cfg, &r, per), BALANCE_OK);
  ck_assert_msg(r.stands, "fell at %.3f s: %.6f m %.6f rad / %.6f m %.6f rad", r.seconds_standing,
                per[0].displacement_m, per[0].rotation_rad, per[1].displacement_m,
                per[1].rotation_rad);
  ck_assert_double_eq(r.seconds_standing, 2.0);
  ck_assert_uint_eq(r.steps, 2000);
  ck_assert_double_eq_tol(r.sim_time_s, 2.0, 1e-9);
  for (int i = 0; i < 2; ++i) {
    ck_assert(per[i].displacement_m < 1e-4);
    ck_assert(per[i].rotation_rad < 1e-3);
    ck_assert(per[i].moved_at_s == -1.0);
    ck_assert_double_eq_tol(per[i].final_pose.position_m[2], t.pose[i].position_m[2], 1e-4);
    /* at rest: nothing moves in the last second (fprintf: what "rest" is on this machine) */
    fprintf(stderr, "two boxes at rest: object %d moved %.3g m, %.3g rad in the last second\n", i,
            per[i].late_displacement_m, per[i].late_rotation_rad);
    ck_assert(per[i].late_displacement_m < 1e-6 && per[i].late_rotation_rad < 1e-5);
  }
  two_boxes_free(&t);
}
END_TEST

START_TEST(top_box_beyond_edge_falls) {
  /* The lower box ends at x = 30 mm. The top box's CoM 5 mm inside stands, 5 mm beyond falls. */
  balance_stack_config_t cfg;
  balance_stack_config_default(&cfg);
  cfg.duration_s = 2.0;
  balance_stack_result_t r;
  balance_stack_object_t per[2];
  two_boxes_t t;
  two_boxes(&t, 0.025);
  ck_assert_int_eq(balance_stack_run(t.w, t.obj, t.pose, 2, &cfg, &r, per), BALANCE_OK);
  ck_assert(r.stands);
  two_boxes_free(&t);
  two_boxes(&t, 0.035);
  ck_assert_int_eq(balance_stack_run(t.w, t.obj, t.pose, 2, &cfg, &r, per), BALANCE_OK);
  ck_assert(!r.stands);
  ck_assert(r.seconds_standing < 1.0);
  ck_assert(r.seconds_standing > 0.0);
  ck_assert(per[1].moved_at_s == r.seconds_standing);
  ck_assert(per[1].displacement_m > cfg.max_displacement_m ||
            per[1].rotation_rad > cfg.max_rotation_rad);
  ck_assert(r.steps < 1000);
  /* stopped before the last second began: the late motion is measured from the release */
  double d[3];
  cl_vec3_sub(per[1].final_pose.position_m, t.pose[1].position_m, d);
  ck_assert_double_eq_tol(per[1].late_displacement_m, sqrt(cl_vec3_dot(d, d)), 1e-6);
  ck_assert_double_eq_tol(
      per[1].late_rotation_rad,
      cl_quat_angle(per[1].final_pose.orientation_wxyz, t.pose[1].orientation_wxyz), 1e-6);
  /* the run stopped on the step that took it past a threshold: so did its late motion */
  ck_assert(per[1].late_displacement_m > cfg.max_displacement_m ||
            per[1].late_rotation_rad > cfg.max_rotation_rad);
  /* Run to the end: it has tipped off the lower box's edge and leans against it with a corner on
   * B (rotated ~37 degrees, its CoM beyond the edge and below where it started). Until the
   * object-object friction bound became Coulomb (lib/balance/src/world.c) it ended inside the
   * lower box instead. */
  cfg.run_to_end = 1;
  ck_assert_int_eq(balance_stack_run(t.w, t.obj, t.pose, 2, &cfg, &r, per), BALANCE_OK);
  ck_assert(!r.stands);
  ck_assert_uint_eq(r.steps, 2000);
  ck_assert(per[1].final_pose.position_m[0] > 0.03);
  ck_assert(per[1].final_pose.position_m[2] < t.pose[1].position_m[2] - 0.005);
  ck_assert(per[1].rotation_rad > 0.5);
  /* the last second (1-2 s) is measured from the pose at 1 s, after the fall: much less than the
   * whole way from the release */
  fprintf(stderr, "fallen box: %.3g m, %.3g rad in the last second, %.3g m, %.3g rad at most\n",
          per[1].late_displacement_m, per[1].late_rotation_rad, per[1].displacement_m,
          per[1].rotation_rad);
  ck_assert(per[1].late_rotation_rad < 0.5 * per[1].rotation_rad);
  two_boxes_free(&t);
}
END_TEST

START_TEST(stack_is_deterministic) {
  two_boxes_t t;
  two_boxes(&t, 0.012);
  balance_stack_config_t cfg;
  balance_stack_config_default(&cfg);
  cfg.duration_s = 0.5;
  balance_stack_result_t r1, r2;
  balance_stack_object_t p1[2], p2[2];
  ck_assert_int_eq(balance_stack_run(t.w, t.obj, t.pose, 2, &cfg, &r1, p1), BALANCE_OK);
  ck_assert_int_eq(balance_stack_run(t.w, t.obj, t.pose, 2, &cfg, &r2, p2), BALANCE_OK);
  ck_assert_int_eq(memcmp(&r1, &r2, sizeof r1), 0);
  ck_assert_int_eq(memcmp(p1, p2, sizeof p1), 0);
  two_boxes_free(&t);
}
END_TEST

/* Three objects: two boxes, and on top rock_1_uneven on its -z fracture face (flat on the flat
 * top box) with its true CoM at x = top_x. The bundled rocks have no two parallel flat faces, so
 * a rock-on-rock stack rests a flat face on a rounded top; planning such stacks (CoM of all above
 * over each support) belongs to `comlearn stack`, not to this physics test. */
static void box_box_rock(double top_x, const balance_stack_config_t *cfg,
                         balance_stack_result_t *res, balance_stack_object_t per[3]) {
  two_boxes_t t;
  two_boxes(&t, 0.0);
  bp_rock_t rock;
  bp_rock_load(&rock, 1, 1);
  balance_object_t *obj[3] = {t.obj[0], t.obj[1], NULL};
  ck_assert_int_eq(balance_object_create(t.w, &rock.obj.mesh, &rock.truth, &obj[2]), BALANCE_OK);
  model_pose_t pose[3] = {t.pose[0], t.pose[1], {{0}, {0}}};
  const double at[2] = {top_x, 0.0};
  ck_assert_int_eq(balance_stack_pose_above(&t.mesh, &t.pose[1], &rock.obj.mesh, kUp,
                                            rock.truth.com_m, at, 1e-6, &pose[2]),
                   BALANCE_OK);
  /* The rock's -z face sits on the top box's top face (z = 40 mm - 2 um). */
  ck_assert_double_eq_tol(pose[2].position_m[2] + rock.obj.aabb.min_m[2], 4.0 * kBoxH[2] - 3e-6,
                          1e-9);
  ck_assert_int_eq(balance_stack_run(t.w, obj, pose, 3, cfg, res, per), BALANCE_OK);
  two_boxes_free(&t);
  bp_rock_free(&rock);
}

START_TEST(rock_on_two_boxes_stands_or_falls_by_its_com) {
  balance_stack_config_t cfg;
  balance_stack_config_default(&cfg);
  balance_stack_result_t res;
  balance_stack_object_t per[3];
  /* CoM over the middle of the top box: stands the full 5 s. */
  box_box_rock(0.0, &cfg, &res, per);
  ck_assert_msg(res.stands, "fell at %.3f s (rock moved %.4f m, %.4f rad)", res.seconds_standing,
                per[2].displacement_m, per[2].rotation_rad);
  ck_assert_double_eq(res.seconds_standing, 5.0);
  for (int i = 0; i < 3; ++i) ck_assert(per[i].displacement_m < 1e-4);
  /* CoM 5 mm beyond the top box's edge (x = 30 mm): the rock tips off, and only the rock moves. */
  box_box_rock(0.035, &cfg, &res, per);
  ck_assert(!res.stands);
  ck_assert(res.seconds_standing < 1.0);
  ck_assert(per[2].moved_at_s == res.seconds_standing);
  ck_assert(per[0].displacement_m < 1e-3);
}
END_TEST

START_TEST(bad_input_gives_status) {
  two_boxes_t t;
  two_boxes(&t, 0.0);
  balance_stack_result_t r;
  balance_world_t *other = world_new();
  ck_assert_int_eq(balance_stack_run(NULL, t.obj, t.pose, 2, NULL, &r, NULL), BALANCE_E_ARG);
  ck_assert_int_eq(balance_stack_run(t.w, t.obj, t.pose, 0, NULL, &r, NULL), BALANCE_E_ARG);
  ck_assert_int_eq(balance_stack_run(t.w, t.obj, t.pose, 2, NULL, NULL, NULL), BALANCE_E_ARG);
  ck_assert_int_eq(balance_stack_run(other, t.obj, t.pose, 2, NULL, &r, NULL), BALANCE_E_ARG);
  balance_object_t *dup[2] = {t.obj[0], t.obj[0]};
  ck_assert_int_eq(balance_stack_run(t.w, dup, t.pose, 2, NULL, &r, NULL), BALANCE_E_ARG);
  model_pose_t bad[2] = {t.pose[0], t.pose[1]};
  bad[1].orientation_wxyz[0] = 1.5;
  ck_assert_int_eq(balance_stack_run(t.w, t.obj, bad, 2, NULL, &r, NULL), BALANCE_E_POSE);
  bad[1].orientation_wxyz[0] = NAN;
  ck_assert_int_eq(balance_stack_run(t.w, t.obj, bad, 2, NULL, &r, NULL), BALANCE_E_NONFINITE);
  bad[1] = t.pose[1];
  bad[0].position_m[2] = 0.0; /* 10 mm inside B */
  ck_assert_int_eq(balance_stack_run(t.w, t.obj, bad, 2, NULL, &r, NULL), BALANCE_E_POSE);
  balance_stack_config_t cfg;
  balance_stack_config_default(&cfg);
  cfg.duration_s = -1.0;
  ck_assert_int_eq(balance_stack_run(t.w, t.obj, t.pose, 2, &cfg, &r, NULL), BALANCE_E_ARG);
  cfg.duration_s = NAN;
  ck_assert_int_eq(balance_stack_run(t.w, t.obj, t.pose, 2, &cfg, &r, NULL), BALANCE_E_NONFINITE);
  /* pose_above */
  const double c[3] = {0, 0, 0}, at[2] = {0, 0}, q_bad[4] = {0.5, 0, 0, 0};
  model_pose_t p;
  ck_assert_int_eq(balance_stack_pose_above(&t.mesh, &t.pose[0], &t.mesh, q_bad, c, at, 0.0, &p),
                   BALANCE_E_POSE);
  ck_assert_int_eq(balance_stack_pose_above(NULL, &t.pose[0], &t.mesh, kUp, c, at, 0.0, &p),
                   BALANCE_E_ARG);
  ck_assert_int_eq(balance_stack_pose_above(&t.mesh, &t.pose[0], &t.mesh, kUp, c, at, -1.0, &p),
                   BALANCE_E_ARG);
  const double at_nan[2] = {NAN, 0};
  ck_assert_int_eq(balance_stack_pose_above(&t.mesh, &t.pose[0], &t.mesh, kUp, c, at_nan, 0.0, &p),
                   BALANCE_E_NONFINITE);
  balance_world_destroy(other);
  two_boxes_free(&t);
}
END_TEST

Suite *balance_stack_suite(void) {
  Suite *s = suite_create("balance_stack");
  TCase *tc = tcase_create("stack");
  tcase_set_timeout(tc, 300);
  tcase_add_test(tc, pose_above_is_exact_for_boxes);
  tcase_add_test(tc, two_boxes_centered_stand);
  tcase_add_test(tc, top_box_beyond_edge_falls);
  tcase_add_test(tc, stack_is_deterministic);
  tcase_add_test(tc, rock_on_two_boxes_stands_or_falls_by_its_com);
  tcase_add_test(tc, bad_input_gives_status);
  suite_add_tcase(s, tc);
  return s;
}
