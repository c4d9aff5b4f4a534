/* balance_regime_tests.c - the flat-patch regime geometry (comlearn/balance_poses.h): resting
 * patches, chords on the edge line, regime verdicts, yaws, hull faces. Pure geometry, no ODE. */
#include <check.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "balance_poses_fixtures.h"
#include "balance_suites.h"
#include "comlearn/balance_poses.h"
#include "comlearn/math3d.h"

static const double kBase[3] = {0.30, 0.30, 0.10};
static const double kIdentity[4] = {1.0, 0.0, 0.0, 0.0};

/* Rotate v by unit q through the matrix (test-side: another formula than the library's
 * quaternion rotation, balance_geom_quat_rotate / cl_quat_rotate). */
static void rot(const double q[4], const double v[3], double o[3]) {
  double r[3][3];
  cl_quat_to_rot(q, r);
  for (int i = 0; i < 3; ++i) o[i] = r[i][0] * v[0] + r[i][1] * v[1] + r[i][2] * v[2];
}

/* The pose with point p (link) over `edge` of kBase at `along` metres along it, lowest vertex at
 * z = -1e-6 (what balance_pose_over_edge is specified to give). */
static model_pose_t over_edge(const model_mesh_t *m, const double q[4], model_edge_t edge,
                              const double p[3], double along) {
  model_pose_t pose;
  memcpy(pose.orientation_wxyz, q, sizeof pose.orientation_wxyz);
  double zmin = HUGE_VAL, w[3];
  for (size_t v = 0; v < m->vertex_count; ++v) {
    rot(q, m->vertices_m[v], w);
    if (w[2] < zmin) zmin = w[2];
  }
  rot(q, p, w);
  const double half = 0.15;
  double target[2] = {along, along};
  switch (edge) {
    case MODEL_EDGE_PX: target[0] = half; break;
    case MODEL_EDGE_NX: target[0] = -half; break;
    case MODEL_EDGE_PY: target[1] = half; break;
    case MODEL_EDGE_NY: target[1] = -half; break;
  }
  pose.position_m[0] = target[0] - w[0];
  pose.position_m[1] = target[1] - w[1];
  pose.position_m[2] = -zmin - 1e-6;
  return pose;
}

/* Is the world point xy on one of the mesh triangles lying in the support plane of `pose`
 * (test-side: its own rotation, lowest vertex, 1 um tolerance, point-in-triangle)? */
static int on_contact(const model_mesh_t *m, const model_pose_t *pose, const double xy[2]) {
  double zmin = HUGE_VAL;
  double(*w)[3] = malloc(m->vertex_count * sizeof *w);
  for (size_t v = 0; v < m->vertex_count; ++v) {
    rot(pose->orientation_wxyz, m->vertices_m[v], w[v]);
    for (int k = 0; k < 3; ++k) w[v][k] += pose->position_m[k];
    if (w[v][2] < zmin) zmin = w[v][2];
  }
  int on = 0;
  for (size_t t = 0; t < m->triangle_count && !on; ++t) {
    const uint32_t *tri = m->triangles[t];
    if (w[tri[0]][2] - zmin > 1e-6 || w[tri[1]][2] - zmin > 1e-6 || w[tri[2]][2] - zmin > 1e-6)
      continue;
    int pos = 0, neg = 0;
    for (int k = 0; k < 3; ++k) {
      const double *a = w[tri[k]], *b = w[tri[(k + 1) % 3]];
      const double c = (b[0] - a[0]) * (xy[1] - a[1]) - (b[1] - a[1]) * (xy[0] - a[0]);
      pos += c >= 0.0;
      neg += c <= 0.0;
    }
    on = pos == 3 || neg == 3;
  }
  free(w);
  return on;
}

/* ---- boxes: exact answers ---------------------------------------------------------------- */

START_TEST(box_patch_is_its_bottom_face) {
  const double h[3] = {0.03, 0.02, 0.01}, c[3] = {0, 0, 0};
  model_mesh_t m = {0};
  bp_box(&m, h, 0.0);
  model_pose_t pose = over_edge(&m, kIdentity, MODEL_EDGE_PX, c, 0.0);
  model_regime_t r;
  ck_assert_int_eq(model_regime_classify(&m, &pose, kBase, MODEL_EDGE_PX, c, NULL, &r), MODEL_OK);
  ck_assert_uint_eq(r.patch.touch_count, 4);
  ck_assert_uint_eq(r.patch.face_count, 2);
  ck_assert_uint_eq(r.patch.vertex_count, 4);
  ck_assert_double_eq_tol(r.patch.support_z_m, -1e-6, 1e-15);
  ck_assert_double_eq_tol(r.patch.area_m2, 0.06 * 0.04, 1e-15);
  ck_assert_double_eq_tol(r.patch.faces_area_m2, 0.06 * 0.04, 1e-15);
  ck_assert_double_eq_tol(r.patch.width_m, 0.04, 1e-15);
  ck_assert(r.patch.flat);
  /* Over the X edge the chord runs along y across the whole face width. */
  ck_assert(r.chord_valid);
  ck_assert_double_eq_tol(r.chord_m[0], -0.02, 1e-15);
  ck_assert_double_eq_tol(r.chord_m[1], 0.02, 1e-15);
  ck_assert_double_eq_tol(r.com_along_m, 0.0, 1e-15);
  ck_assert_double_eq_tol(r.com_beyond_m, 0.0, 1e-15);
  ck_assert_double_eq_tol(r.chord_margin_m, 0.02, 1e-15);
  ck_assert_int_eq(r.kind, MODEL_REGIME_FLAT_PATCH);
  ck_assert(r.flat_patch_regime);
  /* Over the Y edge, 5 cm along it: the chord spans the 6 cm length, shifted with the object. */
  pose = over_edge(&m, kIdentity, MODEL_EDGE_PY, c, 0.05);
  ck_assert_int_eq(model_regime_classify(&m, &pose, kBase, MODEL_EDGE_PY, c, NULL, &r), MODEL_OK);
  ck_assert_double_eq_tol(r.chord_m[0], 0.02, 1e-15);
  ck_assert_double_eq_tol(r.chord_m[1], 0.08, 1e-15);
  ck_assert_double_eq_tol(r.com_along_m, 0.05, 1e-15);
  ck_assert_double_eq_tol(r.chord_margin_m, 0.03, 1e-15);
  model_mesh_free(&m);
}
END_TEST

START_TEST(box_margin_decides_the_regime) {
  const double h[3] = {0.03, 0.02, 0.01};
  model_mesh_t m = {0};
  bp_box(&m, h, 0.0);
  /* A CoM estimate 18.5 mm off the middle sideways: 1.5 mm from the chord end, under the 3 mm
   * default: it would roll sideways. */
  const double side[3] = {0.0, 0.0185, 0.0};
  model_pose_t pose = over_edge(&m, kIdentity, MODEL_EDGE_PX, side, 0.0);
  model_regime_t r;
  ck_assert_int_eq(model_regime_classify(&m, &pose, kBase, MODEL_EDGE_PX, side, NULL, &r),
                   MODEL_OK);
  ck_assert_double_eq_tol(r.chord_margin_m, 0.0015, 1e-12);
  ck_assert_int_eq(r.kind, MODEL_REGIME_EDGE_ROLL);
  ck_assert(!r.flat_patch_regime);
  /* Beyond the face sideways: the chord misses the CoM estimate (negative margin). */
  const double out[3] = {0.0, 0.025, 0.0};
  pose = over_edge(&m, kIdentity, MODEL_EDGE_PX, out, 0.0);
  ck_assert_int_eq(model_regime_classify(&m, &pose, kBase, MODEL_EDGE_PX, out, NULL, &r), MODEL_OK);
  ck_assert_double_eq_tol(r.chord_margin_m, -0.005, 1e-12);
  ck_assert_int_eq(r.kind, MODEL_REGIME_EDGE_ROLL);
  /* A looser threshold accepts the 1.5 mm case. */
  model_regime_config_t cfg;
  model_regime_config_default(&cfg);
  cfg.min_chord_margin_m = 0.001;
  pose = over_edge(&m, kIdentity, MODEL_EDGE_PX, side, 0.0);
  ck_assert_int_eq(model_regime_classify(&m, &pose, kBase, MODEL_EDGE_PX, side, &cfg, &r),
                   MODEL_OK);
  ck_assert_int_eq(r.kind, MODEL_REGIME_FLAT_PATCH);
  model_mesh_free(&m);
}
END_TEST

START_TEST(box_best_yaw_is_the_diagonal) {
  /* Through the middle of a 60 x 40 mm face the longest chord is the diagonal: margin half of
   * it, sqrt(30^2 + 20^2) mm. */
  const double h[3] = {0.03, 0.02, 0.01}, c[3] = {0, 0, 0};
  model_mesh_t m = {0};
  bp_box(&m, h, 0.0);
  double yaw = -1.0, margin = 0.0;
  ck_assert_int_eq(model_yaw_best(&m, kIdentity, c, MODEL_EDGE_PX, NULL, &yaw, &margin), MODEL_OK);
  ck_assert_double_eq_tol(margin, sqrt(0.03 * 0.03 + 0.02 * 0.02), 1e-9);
  ck_assert(yaw >= 0.0 && yaw < CL_PI);
  /* The edge (world y) seen in the object frame after yaw runs along a diagonal. */
  const double d[2] = {sin(yaw), cos(yaw)};
  const double along_diag = fabs(d[0] * 0.03 + d[1] * 0.02) / sqrt(0.03 * 0.03 + 0.02 * 0.02);
  const double along_anti = fabs(-d[0] * 0.03 + d[1] * 0.02) / sqrt(0.03 * 0.03 + 0.02 * 0.02);
  ck_assert_double_eq_tol(fmax(along_diag, along_anti), 1.0, 1e-12);
  /* model_yaw_margin agrees at that yaw and at yaw 0 (chord across the 40 mm width). */
  double m2 = 0.0;
  ck_assert_int_eq(model_yaw_margin(&m, kIdentity, c, MODEL_EDGE_PX, yaw, NULL, &m2), MODEL_OK);
  ck_assert_double_eq_tol(m2, margin, 1e-12);
  ck_assert_int_eq(model_yaw_margin(&m, kIdentity, c, MODEL_EDGE_PX, 0.0, NULL, &m2), MODEL_OK);
  ck_assert_double_eq_tol(m2, 0.02, 1e-12);
  ck_assert_int_eq(model_yaw_margin(&m, kIdentity, c, MODEL_EDGE_PY, 0.0, NULL, &m2), MODEL_OK);
  ck_assert_double_eq_tol(m2, 0.03, 1e-12);
  /* The classified trial at that yaw has the same margin. */
  double q[4];
  model_orientation_yawed(kIdentity, yaw, q);
  model_pose_t pose = over_edge(&m, q, MODEL_EDGE_PX, c, 0.0);
  model_regime_t r;
  ck_assert_int_eq(model_regime_classify(&m, &pose, kBase, MODEL_EDGE_PX, c, NULL, &r), MODEL_OK);
  ck_assert_double_eq_tol(r.chord_margin_m, margin, 1e-12);
  model_mesh_free(&m);
}
END_TEST

START_TEST(box_faces_with_offset_com) {
  /* 60 x 40 x 20 mm box, CoM 25 mm along +x. Analytic margins of its projection: on the +-x faces
   * (40 x 20) it is the face middle: min(20, 10) = 10 mm; on the +-y faces (60 x 20) and the
   * +-z faces (60 x 40) it is 5 mm from the x end. */
  const double h[3] = {0.03, 0.02, 0.01}, com[3] = {0.025, 0.0, 0.0};
  model_mesh_t m = {0};
  bp_box(&m, h, 0.0);
  model_face_t f[8];
  size_t n = 0;
  ck_assert_int_eq(model_faces_find(&m, com, NULL, f, 8, &n), MODEL_OK);
  ck_assert_uint_eq(n, 6);
  for (size_t i = 0; i < n; ++i) {
    const double *nl = f[i].normal_link;
    int axis = -1;
    for (int k = 0; k < 3; ++k) {
      if (fabs(fabs(nl[k]) - 1.0) < 1e-15) axis = k;
    }
    ck_assert_int_ge(axis, 0);
    const double a = 4.0 * h[(axis + 1) % 3] * h[(axis + 2) % 3];
    ck_assert_double_eq_tol(f[i].area_m2, a, 1e-15);
    ck_assert_double_eq_tol(f[i].patch_area_m2, a, 1e-15);
    ck_assert_double_eq_tol(f[i].offset_m, h[axis], 1e-15);
    ck_assert_uint_eq(f[i].face_count, 2);
    ck_assert_double_eq_tol(f[i].com_margin_m, axis == 0 ? 0.010 : 0.005, 1e-12);
    ck_assert(f[i].candidate);
    /* Resting on it turns its normal to -z. */
    double w[3];
    rot(f[i].orientation_wxyz, nl, w);
    ck_assert_double_eq_tol(w[2], -1.0, 1e-12);
    if (i > 0) ck_assert(f[i].area_m2 <= f[i - 1].area_m2);
  }
  ck_assert(f[0].flat && f[1].flat); /* 60 x 40 */
  ck_assert(f[2].flat && f[3].flat); /* 60 x 20 */
  ck_assert(f[4].flat && f[5].flat); /* 40 x 20: width 20 mm, area 8 cm^2 */
  /* With a 6 mm margin required, only the two x faces remain candidates (analytic count). */
  model_regime_config_t cfg;
  model_regime_config_default(&cfg);
  cfg.min_com_margin_m = 0.006;
  ck_assert_int_eq(model_faces_find(&m, com, &cfg, f, 8, &n), MODEL_OK);
  int cand = 0;
  for (size_t i = 0; i < n; ++i) {
    if (f[i].candidate) {
      ++cand;
      ck_assert_double_eq_tol(fabs(f[i].normal_link[0]), 1.0, 1e-15);
    }
  }
  ck_assert_int_eq(cand, 2);
  /* The count is reported even when the array is short. */
  ck_assert_int_eq(model_faces_find(&m, com, NULL, f, 2, &n), MODEL_OK);
  ck_assert_uint_eq(n, 6);
  model_mesh_free(&m);
}
END_TEST

START_TEST(leaning_box_com_outside_bottom) {
  /* Bottom 20 x 20 mm, top shifted 30 mm in x, 60 mm tall: the uniform-density CoM is at
   * x = 15 mm, 5 mm beyond the bottom face: the bottom face is no candidate (margin -5 mm). */
  const double h[3] = {0.01, 0.01, 0.03};
  model_mesh_t m = {0};
  bp_box(&m, h, 0.03);
  model_mass_t mass;
  ck_assert_int_eq(model_mesh_mass(&m, 1000.0, &mass), MODEL_OK);
  ck_assert_double_eq_tol(mass.com_m[0], 0.015, 1e-12);
  model_face_t f[8];
  size_t n = 0;
  ck_assert_int_eq(model_faces_find(&m, mass.com_m, NULL, f, 8, &n), MODEL_OK);
  ck_assert_uint_eq(n, 6);
  int seen = 0;
  for (size_t i = 0; i < n; ++i) {
    if (f[i].normal_link[2] < -1.0 + 1e-12) {
      seen = 1;
      ck_assert_double_eq_tol(f[i].com_margin_m, -0.005, 1e-12);
      ck_assert(!f[i].candidate);
    }
  }
  ck_assert(seen);
  model_mesh_free(&m);
}
END_TEST

/* ---- real contact: separate feet, a ring ----------------------------------------------- */

/* Feet 20 x 40 mm (x, y), 20 mm apart: x in [-30, -10] and [10, 30]. */
static void two_feet_check_chords(const model_mesh_t *m, const double mid[3]) {
  /* Over a Y edge (edge line along x) the line crosses both feet: the chord runs from one
   * foot's outer end to the other's, bridging the gap, and the edge line bounds the support
   * polygon all along it. */
  model_pose_t pose = over_edge(m, kIdentity, MODEL_EDGE_PY, mid, 0.0);
  model_regime_t r;
  ck_assert_int_eq(model_regime_classify(m, &pose, kBase, MODEL_EDGE_PY, mid, NULL, &r), MODEL_OK);
  ck_assert_uint_eq(r.patch.face_count, 4);
  ck_assert_uint_eq(r.patch.region_count, 2);
  ck_assert_double_eq_tol(r.patch.faces_area_m2, 2 * 0.02 * 0.04, 1e-15);
  ck_assert_double_eq_tol(r.patch.region_area_m2, 0.02 * 0.04, 1e-15);
  ck_assert_double_eq_tol(r.patch.region_width_m, 0.02, 1e-15);
  ck_assert_double_eq_tol(r.patch.area_m2, 0.06 * 0.04, 1e-15); /* the outline spans the gap */
  ck_assert(r.patch.flat);
  ck_assert_double_eq_tol(r.chord_m[0], -0.03, 1e-15);
  ck_assert_double_eq_tol(r.chord_m[1], 0.03, 1e-15);
  ck_assert_int_eq(r.kind, MODEL_REGIME_FLAT_PATCH);
  /* Over an X edge with the gap's middle on the edge line: the line meets no foot (the outline
   * would give a 40 mm chord there). The object rests on the inner foot, whose edge is 10 mm
   * inside: not a flat-patch trial. */
  pose = over_edge(m, kIdentity, MODEL_EDGE_PX, mid, 0.0);
  ck_assert_int_eq(model_regime_classify(m, &pose, kBase, MODEL_EDGE_PX, mid, NULL, &r), MODEL_OK);
  ck_assert(!r.chord_valid);
  ck_assert(r.chord_margin_m == -HUGE_VAL);
  ck_assert_int_eq(r.kind, MODEL_REGIME_POINT_SUPPORT);
  /* The edge line through one foot (x = 20 mm): that foot's chord, [-20, 20] mm in y. */
  const double on_foot[3] = {0.02, 0.005, 0.0};
  pose = over_edge(m, kIdentity, MODEL_EDGE_PX, on_foot, 0.0);
  ck_assert_int_eq(model_regime_classify(m, &pose, kBase, MODEL_EDGE_PX, on_foot, NULL, &r),
                   MODEL_OK);
  ck_assert_double_eq_tol(r.chord_m[0] - r.com_along_m, -0.025, 1e-15);
  ck_assert_double_eq_tol(r.chord_m[1] - r.com_along_m, 0.015, 1e-15);
  ck_assert_double_eq_tol(r.chord_margin_m, 0.015, 1e-15);
  ck_assert_int_eq(r.kind, MODEL_REGIME_FLAT_PATCH);
}

/* Yaw: the best line through the gap's middle runs corner to corner across both feet (half
 * length hypot(30, 20) mm); at yaw 0 the line runs in the gap. Returns the best yaw. */
static double two_feet_check_yaw(const model_mesh_t *m, const double mid[3]) {
  double yaw = 0.0, best = 0.0, at0 = 0.0;
  ck_assert_int_eq(model_yaw_best(m, kIdentity, mid, MODEL_EDGE_PX, NULL, &yaw, &best), MODEL_OK);
  ck_assert_double_eq_tol(best, hypot(0.03, 0.02), 1e-9);
  ck_assert(fabs(yaw - CL_PI / 2) > 0.1);
  ck_assert_int_eq(model_yaw_margin(m, kIdentity, mid, MODEL_EDGE_PX, 0.0, NULL, &at0), MODEL_OK);
  ck_assert(at0 == -HUGE_VAL);
  return yaw;
}

/* The batch form gives what the single calls give, pair by pair. */
static void two_feet_check_yaw_batch(const model_mesh_t *m, double yaw) {
  const double yaws[4] = {0.0, yaw, 1.0, 2.5};
  const double pts[4][3] = {{0, 0, 0}, {0, 0, 0}, {0.02, 0.005, 0}, {-0.015, 0.01, 0}};
  double batch[4];
  ck_assert_int_eq(model_yaw_margins(m, kIdentity, MODEL_EDGE_PX, NULL, 4, yaws, pts, batch),
                   MODEL_OK);
  for (int i = 0; i < 4; ++i) {
    double one = 0.0;
    ck_assert_int_eq(model_yaw_margin(m, kIdentity, pts[i], MODEL_EDGE_PX, yaws[i], NULL, &one),
                     MODEL_OK);
    ck_assert(batch[i] == one);
  }
  const double bad_yaws[2] = {0.0, NAN};
  ck_assert_int_eq(model_yaw_margins(m, kIdentity, MODEL_EDGE_PX, NULL, 2, bad_yaws, pts, batch),
                   MODEL_E_NONFINITE);
  ck_assert_int_eq(model_yaw_margins(m, kIdentity, MODEL_EDGE_PX, NULL, 0, NULL, NULL, NULL),
                   MODEL_OK);
}

/* The hull face under the feet: real area of one foot, two regions. */
static void two_feet_check_bottom_face(const model_mesh_t *m, const double mid[3]) {
  model_face_t f[16];
  size_t n = 0;
  ck_assert_int_eq(model_faces_find(m, mid, NULL, f, 16, &n), MODEL_OK);
  int bottom = 0;
  for (size_t i = 0; i < (n < 16 ? n : 16); ++i) {
    if (f[i].normal_link[2] > -1.0 + 1e-12) continue;
    bottom = 1;
    ck_assert_double_eq_tol(f[i].area_m2, 0.06 * 0.04, 1e-15);
    ck_assert_uint_eq(f[i].region_count, 2);
    ck_assert_double_eq_tol(f[i].patch_area_m2, 0.02 * 0.04, 1e-15);
    ck_assert_double_eq_tol(f[i].patch_width_m, 0.02, 1e-15);
  }
  ck_assert(bottom);
}

START_TEST(two_feet_chord_is_the_real_contact) {
  const double h[3] = {0.01, 0.02, 0.005};
  model_mesh_t m = {0};
  bp_two_feet(&m, h, 0.02);
  model_mesh_check(&m, NULL, NULL);
  const double mid[3] = {0.0, 0.0, 0.0};
  two_feet_check_chords(&m, mid);
  const double yaw = two_feet_check_yaw(&m, mid);
  two_feet_check_yaw_batch(&m, yaw);
  two_feet_check_bottom_face(&m, mid);
  model_mesh_free(&m);
}
END_TEST

START_TEST(narrow_feet_are_not_flat) {
  /* Feet 6 x 40 mm: each region is 6 mm wide, under the 10 mm a flat patch needs, although
   * the outline of the two (26 mm x 40 mm) would pass. */
  const double h[3] = {0.003, 0.02, 0.005};
  model_mesh_t m = {0};
  bp_two_feet(&m, h, 0.014);
  const double mid[3] = {0.0, 0.0, 0.0};
  model_pose_t pose = over_edge(&m, kIdentity, MODEL_EDGE_PY, mid, 0.0);
  model_regime_t r;
  ck_assert_int_eq(model_regime_classify(&m, &pose, kBase, MODEL_EDGE_PY, mid, NULL, &r), MODEL_OK);
  ck_assert(r.patch.width_m >= 0.02);
  ck_assert_double_eq_tol(r.patch.region_width_m, 0.006, 1e-15);
  ck_assert(!r.patch.flat);
  ck_assert_int_eq(r.kind, MODEL_REGIME_EDGE_ROLL);
  model_mesh_free(&m);
}
END_TEST

START_TEST(washer_is_one_ring_region) {
  const unsigned n = 64;
  const double r_in = 0.015, r_out = 0.025;
  model_mesh_t m = {0};
  bp_washer(&m, r_in, r_out, 0.004, n);
  const double mid[3] = {0.0, 0.0, 0.0};
  model_pose_t pose = over_edge(&m, kIdentity, MODEL_EDGE_PX, mid, 0.0);
  model_regime_t r;
  ck_assert_int_eq(model_regime_classify(&m, &pose, kBase, MODEL_EDGE_PX, mid, NULL, &r), MODEL_OK);
  const double poly = 0.5 * n * sin(2.0 * CL_PI / n); /* area of the unit n-gon */
  ck_assert_uint_eq(r.patch.region_count, 1);
  ck_assert_double_eq_tol(r.patch.faces_area_m2, poly * (r_out * r_out - r_in * r_in), 1e-12);
  ck_assert_double_eq_tol(r.patch.area_m2, poly * r_out * r_out, 1e-12);
  ck_assert(r.patch.flat);
  /* Through the hole: the chord spans both sides of the ring (n is a multiple of 4, so the edge
   * line x = const through the centre passes through two outer vertices, at +-r_out). */
  ck_assert_double_eq_tol(r.chord_margin_m, r_out, 1e-12);
  ck_assert_int_eq(r.kind, MODEL_REGIME_FLAT_PATCH);
  model_mesh_free(&m);
}
END_TEST

/* A finely tessellated outline (a 512-sided washer; MODEL_E_CAPACITY before) is reduced to
 * MODEL_PATCH_MAX_VERTICES vertices inside it: every kept vertex is one of the ring's, the area
 * is at most the 512-gon's and within 0.01 % of it, and the regime is found as for 64 sides. */
START_TEST(fine_washer_outline_reduced) {
  const unsigned n = 512;
  const double r_in = 0.015, r_out = 0.025;
  model_mesh_t m = {0};
  bp_washer(&m, r_in, r_out, 0.004, n);
  const double mid[3] = {0.0, 0.0, 0.0};
  model_pose_t pose = over_edge(&m, kIdentity, MODEL_EDGE_PX, mid, 0.0);
  model_regime_t r;
  ck_assert_int_eq(model_regime_classify(&m, &pose, kBase, MODEL_EDGE_PX, mid, NULL, &r), MODEL_OK);
  ck_assert_uint_eq(r.patch.vertex_count, MODEL_PATCH_MAX_VERTICES);
  const double full = 0.5 * n * sin(2.0 * CL_PI / n) * r_out * r_out;
  ck_assert_double_le(r.patch.area_m2, full);
  ck_assert_double_ge(r.patch.area_m2, 0.9999 * full);
  const double cx = pose.position_m[0], cy = pose.position_m[1]; /* the ring's centre */
  for (size_t i = 0; i < r.patch.vertex_count; ++i)
    ck_assert_double_eq_tol(hypot(r.patch.polygon_xy_m[i][0] - cx, r.patch.polygon_xy_m[i][1] - cy),
                            r_out, 1e-6);
  ck_assert(r.patch.flat);
  ck_assert_double_eq_tol(r.chord_margin_m, r_out, 1e-12);
  ck_assert_int_eq(r.kind, MODEL_REGIME_FLAT_PATCH);
  model_mesh_free(&m);
}
END_TEST

/* ---- closed patches: small convex contact ------------------------------------------------- */

/* A 8 x 6 x 4 mm box: no face is a flat patch (< 1 cm^2, < 10 mm wide), every face is closed
 * (two triangles whose area is their hull's). Over the edge it is in the closed-patch regime with
 * the chord across the whole face, whatever the margin. */
START_TEST(small_box_is_a_closed_patch) {
  const double h[3] = {0.004, 0.003, 0.002}, c[3] = {0, 0, 0};
  model_mesh_t m = {0};
  bp_box(&m, h, 0.0);
  const double p[3] = {0.001, 0.0025, 0.0}; /* 0.5 mm from the y side: margin under 3 mm */
  model_pose_t pose = over_edge(&m, kIdentity, MODEL_EDGE_PX, p, 0.0);
  model_regime_t r;
  ck_assert_int_eq(model_regime_classify(&m, &pose, kBase, MODEL_EDGE_PX, p, NULL, &r), MODEL_OK);
  ck_assert(!r.patch.flat);
  ck_assert(r.patch.closed);
  /* p is put at along = 0: the face's y extent [-3, 3] mm moves to [-5.5, 0.5] mm */
  ck_assert_double_eq_tol(r.chord_m[0], -0.0055, 1e-15);
  ck_assert_double_eq_tol(r.chord_m[1], 0.0005, 1e-15);
  ck_assert_double_eq_tol(r.chord_margin_m, 0.0005, 1e-15);
  ck_assert_int_eq(r.kind, MODEL_REGIME_CLOSED_PATCH);
  ck_assert(r.flat_patch_regime);
  /* Every face holds the centre: six, largest margin first (3 mm on the two 8 x 6 faces, 2 mm on
   * the four others), each closed, none flat. */
  model_face_t f[8];
  size_t n = 0;
  ck_assert_int_eq(model_faces_stable(&m, c, NULL, f, 8, &n), MODEL_OK);
  ck_assert_uint_eq(n, 6);
  const double want[6] = {0.003, 0.003, 0.002, 0.002, 0.002, 0.002};
  for (size_t i = 0; i < n; ++i) {
    ck_assert(f[i].closed && !f[i].flat);
    ck_assert_double_eq_tol(f[i].com_margin_m, want[i], 1e-15);
  }
  /* A guess 2.5 mm off along x: the +-x faces (6 x 4 mm, in y and z) keep their 2 mm; the four
   * others see it 1.5 mm from their x side (4 - 2.5 mm). */
  const double g[3] = {0.0025, 0.0, 0.0};
  ck_assert_int_eq(model_faces_stable(&m, g, NULL, f, 8, &n), MODEL_OK);
  ck_assert_uint_eq(n, 6);
  ck_assert_double_eq_tol(f[0].com_margin_m, 0.002, 1e-15);  /* +-x faces: 6 x 4, centred */
  ck_assert_double_eq_tol(f[5].com_margin_m, 0.0015, 1e-15); /* y / z faces: 4 - 2.5 mm */
  model_mesh_free(&m);
}
END_TEST

/* The face under a settled pose: a normal off by 1e-5 rad gives the exact face (its in-plane
 * triangles' normal), its support plane and its closed contact. */
START_TEST(face_at_refines_the_normal) {
  const double h[3] = {0.004, 0.003, 0.002}, c[3] = {0, 0, 0};
  model_mesh_t m = {0};
  bp_box(&m, h, 0.0);
  const double n_off[3] = {1e-5, 0.0, -1.0};
  model_face_t f;
  ck_assert_int_eq(model_face_at(&m, n_off, c, NULL, &f), MODEL_OK);
  ck_assert_double_eq_tol(f.normal_link[0], 0.0, 1e-15);
  ck_assert_double_eq_tol(f.normal_link[2], -1.0, 1e-15);
  ck_assert_double_eq_tol(f.offset_m, 0.002, 1e-15);
  ck_assert_double_eq_tol(f.area_m2, 0.008 * 0.006, 1e-15);
  ck_assert(f.closed && !f.flat);
  ck_assert_double_eq_tol(f.com_margin_m, 0.003, 1e-15);
  const double bad[3] = {NAN, 0.0, 1.0}, zero[3] = {0.0, 0.0, 0.0};
  ck_assert_int_eq(model_face_at(&m, bad, c, NULL, &f), MODEL_E_NONFINITE);
  ck_assert_int_eq(model_face_at(&m, zero, c, NULL, &f), MODEL_E_ARG);
  ck_assert_int_eq(model_face_at(&m, n_off, c, NULL, NULL), MODEL_E_ARG);
  model_mesh_free(&m);
}
END_TEST

/* Not closed: two feet (two regions) and a washer (one region around a hole, whose hull is larger
 * than its real area). */
START_TEST(feet_and_washer_are_not_closed) {
  const double h[3] = {0.003, 0.02, 0.005}, mid[3] = {0.0, 0.0, 0.0};
  model_mesh_t m = {0};
  bp_two_feet(&m, h, 0.014);
  model_pose_t pose = over_edge(&m, kIdentity, MODEL_EDGE_PY, mid, 0.0);
  model_regime_t r;
  ck_assert_int_eq(model_regime_classify(&m, &pose, kBase, MODEL_EDGE_PY, mid, NULL, &r), MODEL_OK);
  ck_assert_uint_eq(r.patch.region_count, 2);
  ck_assert(!r.patch.closed);
  model_mesh_free(&m);
  bp_washer(&m, 0.015, 0.025, 0.004, 64);
  pose = over_edge(&m, kIdentity, MODEL_EDGE_PX, mid, 0.0);
  ck_assert_int_eq(model_regime_classify(&m, &pose, kBase, MODEL_EDGE_PX, mid, NULL, &r), MODEL_OK);
  ck_assert_uint_eq(r.patch.region_count, 1);
  ck_assert(!r.patch.closed);
  model_mesh_free(&m);
}
END_TEST

/* A torus lying flat (R 20 mm, r 5 mm, 48 x 16): its contact is the bottom ring of 48 vertices
 * (radius R, under the tube's centre line) and the 48 edges between them, no triangle. The edges
 * close the ring's hull: a closed patch whose chord through the centre is the ring's diameter,
 * and the face under the centre holds it by the 48-gon's apothem. */
static void torus(model_mesh_t *m, double big_r, double r, unsigned n, unsigned k) {
  m->vertex_count = (size_t)n * k;
  m->triangle_count = 2 * (size_t)n * k;
  m->vertices_m = malloc(m->vertex_count * sizeof *m->vertices_m);
  m->triangles = malloc(m->triangle_count * sizeof *m->triangles);
  for (unsigned i = 0; i < n; ++i) {
    const double th = 2.0 * CL_PI * i / n;
    for (unsigned j = 0; j < k; ++j) {
      const double ph = 2.0 * CL_PI * j / k - 0.5 * CL_PI; /* j = 0: the bottom ring */
      double *v = m->vertices_m[(size_t)i * k + j];
      v[0] = (big_r + r * cos(ph)) * cos(th);
      v[1] = (big_r + r * cos(ph)) * sin(th);
      v[2] = j == 0 ? -r : r * sin(ph);
    }
  }
  size_t t = 0;
  for (unsigned i = 0; i < n; ++i) {
    for (unsigned j = 0; j < k; ++j) {
      const uint32_t a = i * k + j, b = ((i + 1) % n) * k + j;
      const uint32_t c = ((i + 1) % n) * k + (j + 1) % k, d = i * k + (j + 1) % k;
      const uint32_t t1[3] = {a, b, c}, t2[3] = {a, c, d};
      memcpy(m->triangles[t++], t1, sizeof t1);
      memcpy(m->triangles[t++], t2, sizeof t2);
    }
  }
}

START_TEST(torus_ring_is_a_closed_patch) {
  const double big_r = 0.02, r = 0.005, c[3] = {0, 0, 0};
  model_mesh_t m = {0};
  torus(&m, big_r, r, 48, 16);
  model_pose_t pose = over_edge(&m, kIdentity, MODEL_EDGE_PX, c, 0.0);
  model_regime_t reg;
  ck_assert_int_eq(model_regime_classify(&m, &pose, kBase, MODEL_EDGE_PX, c, NULL, &reg), MODEL_OK);
  ck_assert_uint_eq(reg.patch.touch_count, 48);
  ck_assert_uint_eq(reg.patch.face_count, 0);
  ck_assert(reg.patch.closed && !reg.patch.flat);
  ck_assert_uint_eq(reg.patch.vertex_count, 48);
  ck_assert(reg.chord_valid);
  ck_assert_double_eq_tol(reg.chord_m[0], -big_r, 1e-12); /* the ring under the tube: radius R */
  ck_assert_double_eq_tol(reg.chord_m[1], big_r, 1e-12);
  ck_assert_int_eq(reg.kind, MODEL_REGIME_CLOSED_PATCH);
  model_face_t f[8];
  size_t n = 0;
  ck_assert_int_eq(model_faces_stable(&m, c, NULL, f, 8, &n), MODEL_OK);
  ck_assert_uint_ge(n, 1);
  ck_assert_double_eq_tol(fabs(f[0].normal_link[2]), 1.0, 1e-12); /* a ring: largest margin */
  ck_assert(f[0].closed);
  ck_assert_double_eq_tol(f[0].com_margin_m, big_r * cos(CL_PI / 48), 1e-12);
  /* One ring edge missing (a vertex lifted by 10 um): not closed any more. */
  m.vertices_m[5 * 16][2] += 1e-5;
  pose = over_edge(&m, kIdentity, MODEL_EDGE_PX, c, 0.0);
  ck_assert_int_eq(model_regime_classify(&m, &pose, kBase, MODEL_EDGE_PX, c, NULL, &reg), MODEL_OK);
  ck_assert(!reg.patch.closed);
  ck_assert_int_eq(reg.kind, MODEL_REGIME_POINT_SUPPORT);
  model_mesh_free(&m);
}
END_TEST

/* ---- the bundled rocks ------------------------------------------------------------------- */

START_TEST(rock_bottom_face_spans_the_com) {
  const int which = _i / 2 + 1, uneven = _i % 2;
  bp_rock_t r;
  bp_rock_load(&r, which, uneven);
  const model_mesh_t *m = &r.obj.mesh;
  /* The estimator's prior (uniform CoM) and the truth both lie over the -z face's chord. */
  const double *coms[2] = {r.uniform.com_m, r.truth.com_m};
  for (int e = 0; e < 4; ++e) {
    for (int c = 0; c < 2; ++c) {
      model_pose_t pose = over_edge(m, kIdentity, (model_edge_t)e, coms[c], 0.0);
      model_regime_t reg;
      ck_assert_int_eq(model_regime_classify(m, &pose, kBase, (model_edge_t)e, coms[c], NULL, &reg),
                       MODEL_OK);
      ck_assert_msg(reg.patch.width_m >= 0.02, "rock %d: patch %.4f m wide", which,
                    reg.patch.width_m);
      ck_assert(reg.patch.area_m2 >= 4e-4);
      ck_assert(reg.patch.face_count >= 10);
      ck_assert(reg.patch.flat);
      ck_assert(reg.chord_valid);
      ck_assert_msg(reg.chord_margin_m >= 0.006, "rock %d edge %d: margin %.4f", which, e,
                    reg.chord_margin_m);
      ck_assert_int_eq(reg.kind, MODEL_REGIME_FLAT_PATCH);
      ck_assert_double_eq_tol(reg.com_beyond_m, 0.0, 1e-12);
      /* The chord ends lie on the real contact's boundary: half a micrometre outward leaves
       * every in-plane triangle, half a micrometre inward is on one. */
      const int x_edge = e < 2;
      for (int end = 0; end < 2; ++end) {
        for (int dir = -1; dir <= 1; dir += 2) {
          const double s = reg.chord_m[end] + dir * (end ? 5e-7 : -5e-7);
          const double probe[2] = {x_edge ? (e == 0 ? 0.15 : -0.15) : s,
                                   x_edge ? s : (e == 2 ? 0.15 : -0.15)};
          ck_assert_int_eq(on_contact(m, &pose, probe), dir < 0);
        }
      }
    }
  }
  /* The best yaw does at least as well as yaw 0. */
  double yaw = 0.0, best = 0.0, at0 = 0.0;
  ck_assert_int_eq(model_yaw_best(m, kIdentity, r.uniform.com_m, MODEL_EDGE_PX, NULL, &yaw, &best),
                   MODEL_OK);
  ck_assert_int_eq(model_yaw_margin(m, kIdentity, r.uniform.com_m, MODEL_EDGE_PX, 0.0, NULL, &at0),
                   MODEL_OK);
  ck_assert(best >= at0);
  ck_assert(best >= 0.010);
  bp_rock_free(&r);
}
END_TEST

START_TEST(rock_faces_are_the_fractures) {
  /* Each bundled rock has four fracture faces (docs/assets.md), each >= 20 mm wide; among them
   * the -z face (orientation: identity) and a +-x face. Nothing else on its hull is flat. */
  bp_rock_t r;
  bp_rock_load(&r, _i + 1, 0);
  size_t n = 0;
  ck_assert_int_eq(model_faces_find(&r.obj.mesh, r.uniform.com_m, NULL, NULL, 0, &n), MODEL_OK);
  ck_assert(n >= 4);
  model_face_t *f = malloc(n * sizeof *f);
  ck_assert_ptr_nonnull(f);
  ck_assert_int_eq(model_faces_find(&r.obj.mesh, r.uniform.com_m, NULL, f, n, &n), MODEL_OK);
  int flat = 0, bottom = 0, side = 0;
  for (size_t i = 0; i < n; ++i) {
    if (!f[i].flat) continue;
    ++flat;
    ck_assert(f[i].patch_width_m >= 0.02);
    ck_assert(f[i].patch_area_m2 <= f[i].area_m2 * (1.0 + 1e-9));
    if (f[i].normal_link[2] == -1.0) {
      bottom = 1;
      ck_assert(f[i].orientation_wxyz[0] == 1.0 && f[i].orientation_wxyz[1] == 0.0 &&
                f[i].orientation_wxyz[2] == 0.0 && f[i].orientation_wxyz[3] == 0.0);
      ck_assert(f[i].candidate);
    }
    if (fabs(f[i].normal_link[0]) == 1.0) side = 1;
  }
  ck_assert_int_eq(flat, 4);
  ck_assert(bottom && side);
  free(f);
  bp_rock_free(&r);
}
END_TEST

/* ---- rounded undersides ------------------------------------------------------------------ */

START_TEST(ellipsoid_is_point_support) {
  const double a[3] = {0.035, 0.03, 0.025}, c[3] = {0, 0, 0};
  model_mesh_t m = {0};
  bp_ellipsoid(&m, a, 24, 48);
  model_pose_t pose = over_edge(&m, kIdentity, MODEL_EDGE_PX, c, 0.0);
  model_regime_t r;
  ck_assert_int_eq(model_regime_classify(&m, &pose, kBase, MODEL_EDGE_PX, c, NULL, &r), MODEL_OK);
  ck_assert_uint_eq(r.patch.touch_count, 1); /* the pole */
  ck_assert_uint_eq(r.patch.face_count, 0);
  ck_assert(!r.patch.flat);
  ck_assert(!r.chord_valid);
  ck_assert(r.chord_margin_m == -HUGE_VAL);
  ck_assert_int_eq(r.kind, MODEL_REGIME_POINT_SUPPORT);
  ck_assert(!r.flat_patch_regime);
  double yaw = 1.0, margin = 0.0;
  ck_assert_int_eq(model_yaw_best(&m, kIdentity, c, MODEL_EDGE_PX, NULL, &yaw, &margin), MODEL_OK);
  ck_assert(margin == -HUGE_VAL);
  ck_assert(yaw == 0.0);
  /* Its hull faces are small triangles and quads: none is a flat patch. */
  model_face_t f[4];
  size_t n = 0;
  ck_assert_int_eq(model_faces_find(&m, c, NULL, f, 4, &n), MODEL_OK);
  ck_assert(n > 0);
  for (size_t i = 0; i < (n < 4 ? n : 4); ++i) ck_assert(!f[i].flat);
  model_mesh_free(&m);
}
END_TEST

START_TEST(rock_tilted_is_not_flat) {
  /* A rock turned 45 degrees about x and 30 about y rests on its rounded side. */
  bp_rock_t r;
  bp_rock_load(&r, _i + 1, 0);
  const double qx[4] = {cos(CL_PI / 8), sin(CL_PI / 8), 0, 0};
  const double qy[4] = {cos(CL_PI / 12), 0, sin(CL_PI / 12), 0};
  double q[4] = {qy[0] * qx[0] - qy[2] * 0.0, qy[0] * qx[1], qy[2] * qx[0], -qy[2] * qx[1]};
  model_pose_t pose = over_edge(&r.obj.mesh, q, MODEL_EDGE_PX, r.uniform.com_m, 0.0);
  model_regime_t reg;
  ck_assert_int_eq(
      model_regime_classify(&r.obj.mesh, &pose, kBase, MODEL_EDGE_PX, r.uniform.com_m, NULL, &reg),
      MODEL_OK);
  ck_assert(!reg.patch.flat);
  ck_assert(reg.kind != MODEL_REGIME_FLAT_PATCH);
  ck_assert(reg.patch.touch_count <= 3);
  bp_rock_free(&r);
}
END_TEST

/* ---- orientations ------------------------------------------------------------------------ */

START_TEST(resting_orientation_turns_normal_down) {
  const double normals[5][3] = {
      {0, 0, -1}, {0, 0, 2}, {1, 0, 0}, {0.3, -0.5, 0.8}, {-0.2, 0.1, -0.9}};
  for (int i = 0; i < 5; ++i) {
    double q[4], w[3];
    ck_assert_int_eq(model_orientation_resting(normals[i], q), MODEL_OK);
    ck_assert_double_eq_tol(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3], 1.0, 1e-15);
    rot(q, normals[i], w);
    const double len = sqrt(normals[i][0] * normals[i][0] + normals[i][1] * normals[i][1] +
                            normals[i][2] * normals[i][2]);
    ck_assert_double_eq_tol(w[0], 0.0, 1e-15);
    ck_assert_double_eq_tol(w[1], 0.0, 1e-15);
    ck_assert_double_eq_tol(w[2], -len, 1e-15);
  }
  /* Yaw about world z keeps the normal down and turns x. */
  double q[4], w[3];
  const double ex[3] = {1, 0, 0};
  model_orientation_yawed(kIdentity, CL_PI / 2, q);
  rot(q, ex, w);
  ck_assert_double_eq_tol(w[0], 0.0, 1e-15);
  ck_assert_double_eq_tol(w[1], 1.0, 1e-15);
}
END_TEST

/* ---- bad input --------------------------------------------------------------------------- */

START_TEST(bad_input_gives_status) {
  const double h[3] = {0.03, 0.02, 0.01}, c[3] = {0, 0, 0};
  model_mesh_t m = {0};
  bp_box(&m, h, 0.0);
  model_pose_t pose = over_edge(&m, kIdentity, MODEL_EDGE_PX, c, 0.0);
  model_regime_t r;
  model_patch_t p;
  ck_assert_int_eq(model_regime_classify(NULL, &pose, kBase, MODEL_EDGE_PX, c, NULL, &r),
                   MODEL_E_ARG);
  ck_assert_int_eq(model_regime_classify(&m, NULL, kBase, MODEL_EDGE_PX, c, NULL, &r), MODEL_E_ARG);
  ck_assert_int_eq(model_regime_classify(&m, &pose, kBase, MODEL_EDGE_PX, NULL, NULL, &r),
                   MODEL_E_ARG);
  ck_assert_int_eq(model_regime_classify(&m, &pose, kBase, MODEL_EDGE_PX, c, NULL, NULL),
                   MODEL_E_ARG);
  ck_assert_int_eq(model_regime_classify(&m, &pose, kBase, (model_edge_t)7, c, NULL, &r),
                   MODEL_E_ARG);
  const double bad_base[3] = {0.3, 0.0, 0.1};
  ck_assert_int_eq(model_regime_classify(&m, &pose, bad_base, MODEL_EDGE_PX, c, NULL, &r),
                   MODEL_E_ARG);
  const double nan_com[3] = {0, NAN, 0};
  ck_assert_int_eq(model_regime_classify(&m, &pose, kBase, MODEL_EDGE_PX, nan_com, NULL, &r),
                   MODEL_E_NONFINITE);
  /* Quaternions: not unit, non-finite. */
  model_pose_t bad = pose;
  bad.orientation_wxyz[0] = 1.01;
  ck_assert_int_eq(model_patch_resting(&m, &bad, NULL, &p), MODEL_E_POSE);
  bad.orientation_wxyz[0] = 0.0;
  ck_assert_int_eq(model_patch_resting(&m, &bad, NULL, &p), MODEL_E_POSE);
  bad.orientation_wxyz[0] = INFINITY;
  ck_assert_int_eq(model_patch_resting(&m, &bad, NULL, &p), MODEL_E_NONFINITE);
  bad = pose;
  bad.position_m[1] = NAN;
  ck_assert_int_eq(model_patch_resting(&m, &bad, NULL, &p), MODEL_E_NONFINITE);
  const double q_bad[4] = {2, 0, 0, 0};
  double yaw, margin;
  ck_assert_int_eq(model_yaw_best(&m, q_bad, c, MODEL_EDGE_PX, NULL, &yaw, &margin), MODEL_E_POSE);
  ck_assert_int_eq(model_yaw_best(&m, kIdentity, c, MODEL_EDGE_PX, NULL, NULL, &margin),
                   MODEL_E_ARG);
  ck_assert_int_eq(model_yaw_margin(&m, kIdentity, c, MODEL_EDGE_PX, NAN, NULL, &margin),
                   MODEL_E_NONFINITE);
  /* Config out of range. */
  model_regime_config_t cfg;
  model_regime_config_default(&cfg);
  ck_assert_int_eq(model_regime_config_check(&cfg), MODEL_OK);
  cfg.plane_tol_m = 0.0;
  ck_assert_int_eq(model_patch_resting(&m, &pose, &cfg, &p), MODEL_E_ARG);
  cfg.plane_tol_m = NAN;
  ck_assert_int_eq(model_patch_resting(&m, &pose, &cfg, &p), MODEL_E_NONFINITE);
  /* Normals. */
  double q[4];
  const double zero[3] = {0, 0, 0}, inf[3] = {INFINITY, 0, 0};
  ck_assert_int_eq(model_orientation_resting(zero, q), MODEL_E_ARG);
  ck_assert_int_eq(model_orientation_resting(inf, q), MODEL_E_NONFINITE);
  /* Meshes: a non-finite vertex, an index out of range, empty, NULL arrays. */
  model_face_t f[2];
  size_t n;
  m.vertices_m[3][2] = NAN;
  ck_assert_int_eq(model_patch_resting(&m, &pose, NULL, &p), MODEL_E_NONFINITE);
  ck_assert_int_eq(model_faces_find(&m, c, NULL, f, 2, &n), MODEL_E_NONFINITE);
  m.vertices_m[3][2] = -0.01;
  m.triangles[5][1] = 8;
  ck_assert_int_eq(model_patch_resting(&m, &pose, NULL, &p), MODEL_E_DEGENERATE);
  ck_assert_int_eq(model_faces_find(&m, c, NULL, f, 2, &n), MODEL_E_DEGENERATE);
  m.triangles[5][1] = 5;
  model_mesh_t empty = {0};
  ck_assert_int_eq(model_patch_resting(&empty, &pose, NULL, &p), MODEL_E_ARG);
  ck_assert_int_eq(model_faces_find(&empty, c, NULL, f, 2, &n), MODEL_E_ARG);
  ck_assert_int_eq(model_faces_find(&m, c, NULL, NULL, 2, &n), MODEL_E_ARG);
  ck_assert_int_eq(model_faces_find(&m, nan_com, NULL, f, 2, &n), MODEL_E_NONFINITE);
  /* A flat (zero-volume) mesh has no hull. */
  model_mesh_t flat = {0};
  const double hf[3] = {0.03, 0.02, 0.0};
  bp_box(&flat, hf, 0.0);
  ck_assert_int_eq(model_faces_find(&flat, c, NULL, f, 2, &n), MODEL_E_HULL);
  model_mesh_free(&flat);
  model_mesh_free(&m);
}
END_TEST

Suite *balance_regime_suite(void) {
  Suite *s = suite_create("balance_regime");
  TCase *tc = tcase_create("geometry");
  tcase_set_timeout(tc, 120);
  tcase_add_test(tc, box_patch_is_its_bottom_face);
  tcase_add_test(tc, box_margin_decides_the_regime);
  tcase_add_test(tc, box_best_yaw_is_the_diagonal);
  tcase_add_test(tc, box_faces_with_offset_com);
  tcase_add_test(tc, leaning_box_com_outside_bottom);
  tcase_add_test(tc, two_feet_chord_is_the_real_contact);
  tcase_add_test(tc, narrow_feet_are_not_flat);
  tcase_add_test(tc, washer_is_one_ring_region);
  tcase_add_test(tc, fine_washer_outline_reduced);
  tcase_add_test(tc, small_box_is_a_closed_patch);
  tcase_add_test(tc, face_at_refines_the_normal);
  tcase_add_test(tc, feet_and_washer_are_not_closed);
  tcase_add_test(tc, torus_ring_is_a_closed_patch);
  tcase_add_loop_test(tc, rock_bottom_face_spans_the_com, 0, 6);
  tcase_add_loop_test(tc, rock_faces_are_the_fractures, 0, 3);
  tcase_add_test(tc, ellipsoid_is_point_support);
  tcase_add_loop_test(tc, rock_tilted_is_not_flat, 0, 3);
  tcase_add_test(tc, resting_orientation_turns_normal_down);
  tcase_add_test(tc, bad_input_gives_status);
  suite_add_tcase(s, tc);
  return s;
}
