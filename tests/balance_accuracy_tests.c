/* balance_accuracy_tests.c - tipping thresholds against analytic truth.
 *
 * A threshold is bisected over the placement offset of a link point put over an edge of B (16
 * halvings of a 3.7 mm bracket: 0.06 um resolution). Boxes, a two-material box and an L-shaped
 * prism (two boxes joined) must hit their analytic CoM coordinate within 1 um, on X and Y edges,
 * in several orientations; the bundled rocks (2000 triangles) resting on their flat -z fracture
 * face, with the edge crossing that face along a chord that spans the CoM sideways, within 5 um. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>

#include "balance_phys_util.h"
#include "balance_suites.h"
#include "comlearn/math3d.h"

#define ITERS 16

/* Bisect the threshold of (mesh, mass) in orientation q over `edge` and compare it with the true
 * CoM com_true_m (link frame): returns threshold - truth along the edge normal (m). */
static double threshold_error(const model_mesh_t *mesh, const model_mass_t *mass,
                              const double com_true_m[3], const double q[4], model_edge_t edge,
                              balance_contact_t path) {
  balance_config_t cfg;
  balance_config_default(&cfg);
  cfg.contact = path;
  balance_world_t *w = NULL;
  balance_object_t *o = NULL;
  ck_assert_int_eq(balance_world_create(&cfg, &w), BALANCE_OK);
  ck_assert_int_eq(balance_object_create(w, mesh, mass, &o), BALANCE_OK);
  model_aabb_t box;
  ck_assert_int_eq(model_mesh_aabb(mesh, &box), MODEL_OK);
  double p0[3], n[3], d, u[3];
  model_aabb_center(&box, p0); /* the estimator's reference point, not the truth */
  model_edge_line(cfg.base_size_m, edge, n, &d);
  bp_edge_dir_link(q, n, u);
  /* Stays iff s > u.(com - p0): the true threshold in s. */
  const double truth = u[0] * (com_true_m[0] - p0[0]) + u[1] * (com_true_m[1] - p0[1]) +
                       u[2] * (com_true_m[2] - p0[2]);
  /* An asymmetric bracket, so that no midpoint lands on the truth itself. */
  const double s = bp_threshold(w, o, q, edge, p0, u, truth - 2.0e-3, truth + 1.7e-3, ITERS);
  balance_world_destroy(w);
  return s - truth;
}

static const double q_id[4] = {1, 0, 0, 0};

static void assert_um(double err_m, double tol_um, const char *what) {
  ck_assert_msg(fabs(err_m) <= tol_um * 1e-6, "%s: threshold - truth = %+.3f um (tolerance %.1f)",
                what, err_m * 1e6, tol_um);
}

START_TEST(box_uniform_edges) {
  model_mesh_t m;
  const double lo[3] = {-0.012, -0.021, -0.018}, hi[3] = {0.028, 0.039, 0.032};
  bp_box(&m, lo, hi);
  model_mass_t ms;
  ck_assert_int_eq(model_mesh_mass(&m, 2650.0, &ms), MODEL_OK); /* inertia */
  const double com[3] = {0.008, 0.009, 0.007};                  /* analytic: the box center */
  assert_um(threshold_error(&m, &ms, com, q_id, MODEL_EDGE_PX, BALANCE_CONTACT_FAST), 1.0,
            "box +X");
  assert_um(threshold_error(&m, &ms, com, q_id, MODEL_EDGE_PY, BALANCE_CONTACT_FAST), 1.0,
            "box +Y");
  assert_um(threshold_error(&m, &ms, com, q_id, MODEL_EDGE_NX, BALANCE_CONTACT_FAST), 1.0,
            "box -X");
  assert_um(threshold_error(&m, &ms, com, q_id, MODEL_EDGE_NY, BALANCE_CONTACT_FAST), 1.0,
            "box -Y");
  model_mesh_free(&m);
}
END_TEST

/* Box [-a,a] x [-b,b] x [-c,c], twice as dense where normal . x >= 0 (normal a coordinate axis):
 * the CoM moves from the center by half-extent / 6 along that axis. */
static void two_material_box(const double normal[3], model_mesh_t *m, model_mass_t *ms,
                             double com[3]) {
  const double lo[3] = {-0.025, -0.02, -0.03}, hi[3] = {0.025, 0.02, 0.03};
  bp_box(m, lo, hi);
  model_halfspace_t region = {{normal[0], normal[1], normal[2]}, 0.0};
  ck_assert_int_eq(model_mesh_mass_halfspace(m, 2000.0, &region, 4000.0, ms), MODEL_OK);
  for (int i = 0; i < 3; i++) {
    com[i] = normal[i] * hi[i] / 6.0;
    ck_assert_msg(fabs(ms->com_m[i] - com[i]) < 1e-12, "two-material CoM %d", i);
  }
}

START_TEST(box_two_material_orientations) {
  model_mesh_t m;
  model_mass_t ms;
  double com[3];
  const double nx[3] = {1, 0, 0}, nz[3] = {0, 0, 1}, ax[3] = {1, 0, 0}, az[3] = {0, 0, 1};
  double q[4];
  two_material_box(nx, &m, &ms, com);
  assert_um(threshold_error(&m, &ms, com, q_id, MODEL_EDGE_PX, BALANCE_CONTACT_FAST), 1.0,
            "two-material box, +X");
  assert_um(threshold_error(&m, &ms, com, q_id, MODEL_EDGE_NX, BALANCE_CONTACT_FAST), 1.0,
            "two-material box, -X");
  cl_quat_from_axis_angle(az, 30.0 * CL_PI / 180.0,
                          q); /* yaw: the edge crosses the bottom face obliquely */
  assert_um(threshold_error(&m, &ms, com, q, MODEL_EDGE_PX, BALANCE_CONTACT_FAST), 1.0,
            "two-material box, yaw 30 deg, +X");
  model_mesh_free(&m);
  two_material_box(nz, &m, &ms, com);
  cl_quat_from_axis_angle(ax, 0.5 * CL_PI,
                          q); /* 90 deg about x: the face y = -b is down, link z is world -y */
  assert_um(threshold_error(&m, &ms, com, q, MODEL_EDGE_NY, BALANCE_CONTACT_FAST), 1.0,
            "two-material box, 90 deg about x, -Y");
  assert_um(threshold_error(&m, &ms, com, q, MODEL_EDGE_PY, BALANCE_CONTACT_FAST), 1.0,
            "two-material box, 90 deg about x, +Y");
  assert_um(threshold_error(&m, &ms, com, q, MODEL_EDGE_PX, BALANCE_CONTACT_FAST), 1.0,
            "two-material box, 90 deg about x, +X");
  model_mesh_free(&m);
}
END_TEST

START_TEST(ell_prism) {
  model_mesh_t m;
  double com[3];
  bp_ell(&m, com);
  model_mesh_report_t rep;
  ck_assert_int_eq(model_mesh_check(&m, &rep, NULL), MODEL_OK);
  ck_assert_int_eq(rep.flipped, 0);
  model_mass_t ms;
  ck_assert_int_eq(model_mesh_mass(&m, 2650.0, &ms), MODEL_OK);
  for (int i = 0; i < 3; i++) ck_assert(fabs(ms.com_m[i] - com[i]) < 1e-12);
  const double ax[3] = {1, 0, 0};
  double q[4];
  assert_um(threshold_error(&m, &ms, com, q_id, MODEL_EDGE_PX, BALANCE_CONTACT_FAST), 1.0,
            "L prism on its bar, +X");
  assert_um(threshold_error(&m, &ms, com, q_id, MODEL_EDGE_PY, BALANCE_CONTACT_FAST), 1.0,
            "L prism on its bar, +Y");
  cl_quat_from_axis_angle(ax, 0.5 * CL_PI, q); /* resting on the L-shaped face itself */
  assert_um(threshold_error(&m, &ms, com, q, MODEL_EDGE_PX, BALANCE_CONTACT_FAST), 1.0,
            "L prism on its L face, +X");
  model_mesh_free(&m);
}
END_TEST

static const char *const rocks[6] = {"rock_1_even",   "rock_1_uneven", "rock_2_even",
                                     "rock_2_uneven", "rock_3_even",   "rock_3_uneven"};

/* The bundled rocks stand on their -z fracture face as they are (identity orientation); the
 * edge at the CoM crosses that face along a chord spanning the CoM by >= 8 mm each side
 * (docs/assets.md, margin). */
START_TEST(rock_flat_face_x_edge) {
  model_object_t obj;
  model_mass_t ms;
  bp_rock(rocks[_i], &obj, &ms);
  ck_assert_uint_ge(obj.mesh.triangle_count, 1000);
  char what[64];
  snprintf(what, sizeof what, "%s on -z, +X", rocks[_i]);
  assert_um(threshold_error(&obj.mesh, &ms, ms.com_m, q_id, MODEL_EDGE_PX, BALANCE_CONTACT_FAST),
            5.0, what);
  model_object_free(&obj);
}
END_TEST

START_TEST(rock_flat_face_y_edge) {
  model_object_t obj;
  model_mass_t ms;
  bp_rock(rocks[_i], &obj, &ms);
  char what[64];
  snprintf(what, sizeof what, "%s on -z, -Y", rocks[_i]);
  assert_um(threshold_error(&obj.mesh, &ms, ms.com_m, q_id, MODEL_EDGE_NY, BALANCE_CONTACT_FAST),
            5.0, what);
  model_object_free(&obj);
}
END_TEST

Suite *balance_accuracy_suite(void) {
  Suite *s = suite_create("balance_accuracy");
  TCase *boxes = tcase_create("boxes");
  tcase_set_timeout(boxes, 600);
  tcase_add_test(boxes, box_uniform_edges);
  tcase_add_test(boxes, box_two_material_orientations);
  tcase_add_test(boxes, ell_prism);
  suite_add_tcase(s, boxes);
  TCase *rk = tcase_create("rocks");
  tcase_set_timeout(rk, 600);
  tcase_add_loop_test(rk, rock_flat_face_x_edge, 0, 6);
  tcase_add_loop_test(rk, rock_flat_face_y_edge, 0, 6);
  suite_add_tcase(s, rk);
  return s;
}
