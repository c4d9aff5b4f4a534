/* model_outcome_tests.c - the geometric outcome model (comlearn/model_outcome.h): support polygons
 * against hand-computed ones, margins against analytic distances, bad input. */
#define _POSIX_C_SOURCE 200809L

#include "comlearn/math3d.h"
#include "comlearn/model_outcome.h"
#include "comlearn/model_support.h"
#include "model_suites.h"
#include "model_test_util.h"

static const double BASE[3] = {0.30, 0.30, 0.10};
#define HX 0.15 /* B's +X edge line: x = sx / 2 */
#define EPS 1e-12

/* A work area for mesh, malloc'd (free() it). */
static model_outcome_work_t *work_new(const model_mesh_t *m) {
  const size_t n = model_outcome_work_size(m);
  ck_assert_uint_gt(n, 0);
  void *mem = malloc(n);
  ck_assert_ptr_nonnull(mem);
  model_outcome_work_t *w = model_outcome_work_init(mem, n, m);
  ck_assert_ptr_eq(w, mem);
  return w;
}

/* The link point p over the +X edge, orientation q, touching 1 um deep (as the estimator). */
static model_pose_t over_edge(const model_mesh_t *m, const double q[4], const double p[3]) {
  model_pose_t pose;
  ck_assert_int_eq(model_pose_over_edge(m, BASE, q, MODEL_EDGE_PX, p, 0.0, 1e-6, &pose), MODEL_OK);
  return pose;
}

/* The support and the verdict for com at pose; also checks model_support_polygon and
 * model_outcome_predict (with and without a work area) agree with it bit for bit. */
static void support_at(const model_mesh_t *m, const model_pose_t *pose, model_outcome_work_t *w,
                       model_outcome_support_t *s) {
  ck_assert_int_eq(model_outcome_support_build(m, pose, BASE, NULL, w, s), MODEL_OK);
  double poly[MODEL_OUTCOME_MAX_VERTICES][2];
  size_t n = 0;
  ck_assert_int_eq(
      model_support_polygon(m, pose, BASE, 1e-6, w, poly, MODEL_OUTCOME_MAX_VERTICES, &n),
      MODEL_OK);
  ck_assert_uint_eq(n, s->vertex_count);
  ck_assert_int_eq(memcmp(poly, s->polygon_xy_m, n * sizeof poly[0]), 0);
}

static double verdict(const model_mesh_t *m, const model_pose_t *pose, model_outcome_work_t *w,
                      const model_outcome_support_t *s, const double com[3], int *in_place) {
  double margin = 0.0, m1 = 0.0, m2 = 0.0;
  int i1 = -1, i2 = -1;
  ck_assert_int_eq(model_outcome_support_test(s, com, in_place, &margin), MODEL_OK);
  ck_assert_int_eq(model_outcome_predict(m, pose, BASE, com, NULL, w, &i1, &m1), MODEL_OK);
  ck_assert_int_eq(model_outcome_predict(m, pose, BASE, com, NULL, NULL, &i2, &m2), MODEL_OK);
  ck_assert(i1 == *in_place && i2 == *in_place && m1 == margin && m2 == margin);
  return margin;
}

/* The polygon equals `want` (n vertices, any starting vertex, counter-clockwise) within EPS. */
static void assert_polygon(const model_outcome_support_t *s, const double (*want)[2], size_t n) {
  ck_assert_uint_eq(s->vertex_count, n);
  size_t start = n;
  for (size_t i = 0; i < n && start == n; ++i)
    if (fabs(s->polygon_xy_m[i][0] - want[0][0]) < EPS &&
        fabs(s->polygon_xy_m[i][1] - want[0][1]) < EPS)
      start = i;
  ck_assert_msg(start < n, "vertex (%.15g, %.15g) not in the polygon", want[0][0], want[0][1]);
  for (size_t i = 0; i < n; ++i) {
    const double *got = s->polygon_xy_m[(start + i) % n];
    ck_assert_msg(fabs(got[0] - want[i][0]) < EPS && fabs(got[1] - want[i][1]) < EPS,
                  "vertex %zu: got (%.15g, %.15g), want (%.15g, %.15g)", i, got[0], got[1],
                  want[i][0], want[i][1]);
  }
}

/* ---- a box on its face -------------------------------------------------------------------- */

static void box_40_60_50(model_mesh_t *m) {
  const double lo[3] = {-0.02, -0.03, -0.025}, hi[3] = {0.02, 0.03, 0.025};
  mt_box(m, lo, hi);
}

/* The CoM d inside the edge (link point com + d x over it): the bottom 40 x 60 mm clipped by the
 * edge line, x in [hx - d - 0.02, hx] (d < 0: the CoM beyond it), y in [-0.03, 0.03]. */
START_TEST(test_outcome_box_straddling) {
  model_mesh_t m;
  box_40_60_50(&m);
  model_outcome_work_t *w = work_new(&m);
  model_outcome_support_t s;
  const double up[4] = {1, 0, 0, 0}, com[3] = {0, 0, 0};
  const double ds[4] = {0.005, 0.0123, -0.005, 0.019};
  for (int k = 0; k < 4; ++k) {
    const double d = ds[k], p[3] = {d, 0, 0};
    const model_pose_t pose = over_edge(&m, up, p);
    support_at(&m, &pose, w, &s);
    const double x0 = HX - d - 0.02;
    const double want[4][2] = {{x0, -0.03}, {HX, -0.03}, {HX, 0.03}, {x0, 0.03}};
    assert_polygon(&s, want, 4);
    ck_assert(s.valid);
    ck_assert_double_eq_tol(s.area_m2, (0.02 + d) * 0.06, EPS);
    ck_assert_double_eq_tol(s.support_z_m, -1e-6, EPS);
    int in = -1;
    /* the CoM at hx - d: distance d to the edge line, 0.02 to the far side, 0.03 sideways */
    const double mg = verdict(&m, &pose, w, &s, com, &in);
    ck_assert_double_eq_tol(mg, fmin(d, 0.02), EPS);
    ck_assert_int_eq(in, d > 0.0);
    /* a hypothesis off the centre: x 4 mm towards the edge, y 26 mm to the side */
    const double c2[3] = {0.004, 0.026, 0.02};
    const double m2 = verdict(&m, &pose, w, &s, c2, &in);
    const double want2 = d - 0.004 > 0.0 ? fmin(d - 0.004, 0.004) : -(0.004 - d);
    ck_assert_double_eq_tol(m2, want2, EPS);
    ck_assert_int_eq(in, want2 > 0.0);
  }
  free(w);
  model_mesh_free(&m);
}
END_TEST

/* Sutherland-Hodgman: the convex polygon p (n, counter-clockwise) clipped to x <= c. */
static size_t clip_x(const double (*p)[2], size_t n, double c, double (*out)[2]) {
  size_t k = 0;
  for (size_t i = 0; i < n; ++i) {
    const double *a = p[i], *b = p[(i + 1) % n];
    const int ina = a[0] <= c, inb = b[0] <= c;
    if (ina) memcpy(out[k++], a, sizeof out[0]);
    if (ina != inb) {
      const double t = (c - a[0]) / (b[0] - a[0]);
      out[k][0] = c;
      out[k++][1] = a[1] + t * (b[1] - a[1]);
    }
  }
  return k;
}

/* Yawed 30 degrees: the rotated bottom rectangle clipped by x <= hx (computed here by clipping). */
START_TEST(test_outcome_box_yawed) {
  model_mesh_t m;
  box_40_60_50(&m);
  model_outcome_work_t *w = work_new(&m);
  model_outcome_support_t s;
  const double up[4] = {1, 0, 0, 0}, p[3] = {0.003, -0.002, 0};
  double q[4];
  model_orientation_yawed(up, CL_PI / 6.0, q);
  const model_pose_t pose = over_edge(&m, q, p);
  support_at(&m, &pose, w, &s);
  const double c = cos(CL_PI / 6.0), sn = sin(CL_PI / 6.0);
  const double corner[4][2] = {{-0.02, -0.03}, {0.02, -0.03}, {0.02, 0.03}, {-0.02, 0.03}};
  double rect[4][2], want[8][2];
  for (int i = 0; i < 4; ++i) {
    rect[i][0] = c * corner[i][0] - sn * corner[i][1] + pose.position_m[0];
    rect[i][1] = sn * corner[i][0] + c * corner[i][1] + pose.position_m[1];
  }
  const size_t n = clip_x((const double(*)[2])rect, 4, HX, want);
  ck_assert_uint_eq(n, 5); /* the edge line cuts one corner off */
  assert_polygon(&s, (const double(*)[2])want, n);
  ck_assert_double_eq_tol(s.area_m2, model_polygon_area((const double(*)[2])want, n), EPS);
  int in = -1;
  const double com[3] = {0, 0, 0};
  const double mg = verdict(&m, &pose, w, &s, com, &in);
  ck_assert_double_eq_tol(
      mg,
      model_polygon_margin((const double(*)[2])want, n,
                           (const double[2]){pose.position_m[0], pose.position_m[1]}),
      EPS);
  ck_assert_int_eq(in, 1);
  free(w);
  model_mesh_free(&m);
}
END_TEST

/* Fully on B, floating 1 mm above, resting exactly, 1 um deep: the whole bottom face. */
START_TEST(test_outcome_box_on_b) {
  model_mesh_t m;
  box_40_60_50(&m);
  model_outcome_work_t *w = work_new(&m);
  model_outcome_support_t s;
  const double heights[3] = {0.026, 0.025, 0.025 - 1e-6};
  for (int k = 0; k < 3; ++k) {
    const model_pose_t pose = {.position_m = {0.01, -0.02, heights[k]},
                               .orientation_wxyz = {1, 0, 0, 0}};
    support_at(&m, &pose, w, &s);
    const double want[4][2] = {{-0.01, -0.05}, {0.03, -0.05}, {0.03, 0.01}, {-0.01, 0.01}};
    assert_polygon(&s, want, 4);
    ck_assert_double_eq_tol(s.support_z_m, heights[k] - 0.025, EPS);
    ck_assert_double_eq_tol(s.width_m, 0.04, EPS);
    int in = -1;
    const double c1[3] = {0.005, -0.01, 0.01}; /* 15 mm from the +x side, 20 from -y */
    ck_assert_double_eq_tol(verdict(&m, &pose, w, &s, c1, &in), 0.015, EPS);
    ck_assert_int_eq(in, 1);
    const double c2[3] = {0.023, 0.034, 0.0}; /* beyond the corner by (3, 4) mm */
    ck_assert_double_eq_tol(verdict(&m, &pose, w, &s, c2, &in), -0.005, EPS);
    ck_assert_int_eq(in, 0);
  }
  free(w);
  model_mesh_free(&m);
}
END_TEST

/* The band and the tilt: a box tilted about y so that its bottom's +x corners are `rise` above
 * its -x corners, 40 cos(a) mm away. The default band (1 um) takes them up to a 1 um rise; with a
 * tilt of 2e-4 rad also up to 1 um + 2e-4 x 40 cos(a) mm = 9 um (the box settles onto them by
 * less than 2e-4 rad); model_support_polygon is the band alone. */
START_TEST(test_outcome_band_and_tilt) {
  model_mesh_t m;
  box_40_60_50(&m);
  model_outcome_work_t *w = work_new(&m);
  model_outcome_support_t s, s0;
  const model_outcome_config_t tilt = {.tol_m = 1e-6, .tilt_rad = 2e-4, .min_width_m = 1e-7};
  const double rise[5] = {0.7e-6, 1.5e-6, 8.9e-6, 9.1e-6, 12e-6};
  for (int k = 0; k < 5; ++k) {
    const double a = -asin(rise[k] / 0.04), axis[3] = {0, 1, 0};
    model_pose_t pose = {.position_m = {0, 0, 0.1}};
    cl_quat_from_axis_angle(axis, a, pose.orientation_wxyz);
    /* corner (x, y, -0.025) -> world x = x cos a - 0.025 sin a */
    const double ca = cos(a), sa = sin(a);
    const double x0 = -0.02 * ca - 0.025 * sa, x1 = 0.02 * ca - 0.025 * sa;
    const double full[4][2] = {{x0, -0.03}, {x1, -0.03}, {x1, 0.03}, {x0, 0.03}};
    const double line[2][2] = {{x0, -0.03}, {x0, 0.03}};
    const int in_band = rise[k] <= 1e-6, in_tilt = rise[k] <= 1e-6 + 2e-4 * 0.04 * ca;
    ck_assert_int_eq(model_outcome_support_build(&m, &pose, BASE, &tilt, w, &s), MODEL_OK);
    ck_assert_int_eq(model_outcome_support_build(&m, &pose, BASE, NULL, w, &s0), MODEL_OK);
    if (in_tilt)
      assert_polygon(&s, full, 4);
    else
      assert_polygon(&s, line, 2);
    if (in_band)
      assert_polygon(&s0, full, 4);
    else
      assert_polygon(&s0, line, 2);
    ck_assert_int_eq(s.valid, in_tilt);
    ck_assert_int_eq(s0.valid, in_band);
    double poly[8][2];
    size_t n = 0;
    ck_assert_int_eq(model_support_polygon(&m, &pose, BASE, 1e-6, w, poly, 8, &n), MODEL_OK);
    ck_assert_uint_eq(n, s0.vertex_count);
    ck_assert_int_eq(memcmp(poly, s0.polygon_xy_m, n * sizeof poly[0]), 0);
    /* on a line support: no rest; the margin is minus the distance from x = 0 to the segment */
    int in = -1;
    double mg = 0.0;
    const double com[3] = {0, 0, 0};
    ck_assert_int_eq(model_outcome_support_test(&s0, com, &in, &mg), MODEL_OK);
    ck_assert_double_eq_tol(mg, (in_band ? -x0 : x0), 1e-15); /* the nearest side: x = x0 */
    ck_assert_int_eq(in, in_band);
    /* lib/balance's 3 um contact band takes the corners raised up to 3 um */
    ck_assert_int_eq(model_support_polygon(&m, &pose, BASE, 3e-6, w, poly, 8, &n), MODEL_OK);
    ck_assert_uint_eq(n, rise[k] <= 3e-6 ? 4 : 2);
  }
  free(w);
  model_mesh_free(&m);
}
END_TEST

/* Tilted 10 degrees about y with the low side beyond the edge: model_pose_over_edge sets it on the
 * edge line, where the bottom face crosses the edge plane: a segment, no rest. */
START_TEST(test_outcome_on_edge_line) {
  model_mesh_t m;
  box_40_60_50(&m);
  model_outcome_work_t *w = work_new(&m);
  model_outcome_support_t s;
  const double a = 10.0 * CL_PI / 180.0, axis[3] = {0, 1, 0}, p[3] = {-0.005, 0, 0};
  double q[4];
  cl_quat_from_axis_angle(axis, a, q);
  const model_pose_t pose = over_edge(&m, q, p);
  support_at(&m, &pose, w, &s);
  const double want[2][2] = {{HX, -0.03}, {HX, 0.03}};
  assert_polygon(&s, want, 2);
  ck_assert_int_eq(s.valid, 0);
  ck_assert_double_eq_tol(s.support_z_m, -1e-6, EPS);
  int in = -1;
  const double com[3] = {0, 0, 0}; /* 5 mm cos(a) beyond the edge line */
  ck_assert_double_eq_tol(verdict(&m, &pose, w, &s, com, &in), -0.005 * cos(a), EPS);
  ck_assert_int_eq(in, 0);
  free(w);
  model_mesh_free(&m);
}
END_TEST

/* ---- two feet ----------------------------------------------------------------------------- */

/* A table-like slab, mm: the profile (x, z) (-40,0) (-20,0) (-20,10) (20,10) (20,0) (40,0)
 * (40,20) (-40,20) extruded along y in [-15, 15]: two rail feet [-40,-20] and [20,40] x [-15,15]
 * at z = 0 under a plate. */
static void two_feet(model_mesh_t *m) {
  static const double prof[8][2] = {{-40, 0}, {-20, 0}, {-20, 10}, {20, 10},
                                    {20, 0},  {40, 0},  {40, 20},  {-40, 20}};
  static const uint32_t cap[6][3] = {{0, 1, 2}, {0, 2, 7}, {2, 3, 7},
                                     {3, 6, 7}, {3, 4, 5}, {3, 5, 6}};
  memset(m, 0, sizeof *m);
  m->vertex_count = 16;
  m->triangle_count = 12 + 16;
  m->vertices_m = malloc(m->vertex_count * sizeof *m->vertices_m);
  m->triangles = malloc(m->triangle_count * sizeof *m->triangles);
  ck_assert(m->vertices_m && m->triangles);
  for (int i = 0; i < 8; ++i)
    for (int b = 0; b < 2; ++b) {
      double *v = m->vertices_m[8 * b + i];
      v[0] = prof[i][0] * 1e-3;
      v[1] = (b ? 15.0 : -15.0) * 1e-3;
      v[2] = prof[i][1] * 1e-3;
    }
  size_t t = 0;
  for (int i = 0; i < 6; ++i) { /* front cap (y = -15) counter-clockwise in (x, z): normal -y */
    memcpy(m->triangles[t++], cap[i], sizeof cap[i]);
    const uint32_t back[3] = {8 + cap[i][0], 8 + cap[i][2], 8 + cap[i][1]};
    memcpy(m->triangles[t++], back, sizeof back);
  }
  for (uint32_t i = 0; i < 8; ++i) {
    const uint32_t j = (i + 1) % 8;
    const uint32_t t0[3] = {i, 8 + j, j}, t1[3] = {i, 8 + i, 8 + j};
    memcpy(m->triangles[t++], t0, sizeof t0);
    memcpy(m->triangles[t++], t1, sizeof t1);
  }
  model_mesh_report_t rep;
  model_error_t err;
  ck_assert_msg(model_mesh_check(m, &rep, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_int_eq(rep.flipped, 0);
  ck_assert_uint_eq(rep.merged_vertices + rep.removed_degenerate + rep.removed_unreferenced, 0);
}

/* The edge line runs through link (20, 0) and (30, 15) mm: it cuts foot 2 into the triangle
 * (20,0) (20,15) (30,15) on B's side and misses foot 1. The support polygon is the hull of foot 1
 * and that triangle: (-40,-15) (-20,-15) (20,0) (30,15) (-40,15). The clipped hull of both feet,
 * (-40,-15) (10,-15) (30,15) (-40,15), would hold the CoM (0, -10); the real support does not. */
START_TEST(test_outcome_two_feet) {
  model_mesh_t m;
  two_feet(&m);
  model_outcome_work_t *w = work_new(&m);
  model_outcome_support_t s;
  const double up[4] = {1, 0, 0, 0}, p[3] = {0.020, 0, 0};
  double q[4];
  const double yaw = atan2(10.0, 15.0); /* link (10, 15) to world +y */
  model_orientation_yawed(up, yaw, q);
  const model_pose_t pose = over_edge(&m, q, p);
  support_at(&m, &pose, w, &s);
  const double hull_mm[5][2] = {{-40, -15}, {-20, -15}, {20, 0}, {30, 15}, {-40, 15}};
  double want[5][2];
  const double c = cos(yaw), sn = sin(yaw);
  for (int i = 0; i < 5; ++i) {
    const double x = hull_mm[i][0] * 1e-3, y = hull_mm[i][1] * 1e-3;
    want[i][0] = c * x - sn * y + pose.position_m[0];
    want[i][1] = sn * x + c * y + pose.position_m[1];
  }
  ck_assert_double_eq_tol(want[2][0], HX, EPS);
  ck_assert_double_eq_tol(want[3][0], HX, EPS);
  assert_polygon(&s, (const double(*)[2])want, 5);
  int in = -1;
  /* (0, -10): beyond the side (-20,-15)-(20,0) by |cross((40,15), (20,5))| / |(40,15)| */
  const double c1[3] = {0.0, -0.010, 0.012};
  ck_assert_double_eq_tol(verdict(&m, &pose, w, &s, c1, &in), -100e-3 / sqrt(1825.0), EPS);
  ck_assert_int_eq(in, 0);
  /* (0, -3): inside, nearest that side, at 180 / sqrt(1825) mm */
  const double c2[3] = {0.0, -0.003, 0.005};
  ck_assert_double_eq_tol(verdict(&m, &pose, w, &s, c2, &in), 180e-3 / sqrt(1825.0), EPS);
  ck_assert_int_eq(in, 1);
  free(w);
  model_mesh_free(&m);
}
END_TEST

/* ---- a triangular prism on its triangle ---------------------------------------------------- */

/* Triangle (0,0) (40,0) (0,30) mm (one mesh triangle) extruded to z = 20 mm. */
static void prism(model_mesh_t *m) {
  static const double tri[3][2] = {{0, 0}, {0.04, 0}, {0, 0.03}};
  static const uint32_t t[8][3] = {{0, 2, 1}, {3, 4, 5}, {0, 1, 4}, {0, 4, 3},
                                   {1, 2, 5}, {1, 5, 4}, {2, 0, 3}, {2, 3, 5}};
  memset(m, 0, sizeof *m);
  m->vertex_count = 6;
  m->triangle_count = 8;
  m->vertices_m = malloc(6 * sizeof *m->vertices_m);
  m->triangles = malloc(8 * sizeof *m->triangles);
  ck_assert(m->vertices_m && m->triangles);
  for (int i = 0; i < 6; ++i) {
    m->vertices_m[i][0] = tri[i % 3][0];
    m->vertices_m[i][1] = tri[i % 3][1];
    m->vertices_m[i][2] = i < 3 ? 0.0 : 0.02;
  }
  memcpy(m->triangles, t, sizeof t);
  model_mesh_report_t rep;
  model_error_t err;
  ck_assert_msg(model_mesh_check(m, &rep, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_int_eq(rep.flipped, 0);
}

/* On B: the triangle, the incentre (10, 10) mm at the inradius 10 mm. Over the edge at link
 * x = 20 mm: the quadrilateral (0,0) (20,0) (20,15) (0,30); the CoM (14, 8) is 6 mm from the edge
 * line (8 mm from y = 0, 9.2 from the hypotenuse 3x + 4y = 120). */
START_TEST(test_outcome_prism) {
  model_mesh_t m;
  prism(&m);
  model_outcome_work_t *w = work_new(&m);
  model_outcome_support_t s;
  int in = -1;
  const model_pose_t on_b = {.position_m = {-0.05, 0.02, 0}, .orientation_wxyz = {1, 0, 0, 0}};
  support_at(&m, &on_b, w, &s);
  const double tri[3][2] = {{-0.05, 0.02}, {-0.01, 0.02}, {-0.05, 0.05}};
  assert_polygon(&s, tri, 3);
  ck_assert_double_eq_tol(s.area_m2, 0.5 * 0.04 * 0.03, EPS);
  const double inc[3] = {0.01, 0.01, 0.007}, c2[3] = {0.014, 0.008, 0.002};
  ck_assert_double_eq_tol(verdict(&m, &on_b, w, &s, inc, &in), 0.010, EPS);
  ck_assert_int_eq(in, 1);
  ck_assert_double_eq_tol(verdict(&m, &on_b, w, &s, c2, &in), 0.008, EPS);
  const double up[4] = {1, 0, 0, 0}, p[3] = {0.02, 0.0, 0.0};
  const model_pose_t pose = over_edge(&m, up, p);
  support_at(&m, &pose, w, &s);
  const double ox = HX - 0.02, oy = pose.position_m[1];
  const double quad[4][2] = {{ox, oy}, {HX, oy}, {HX, oy + 0.015}, {ox, oy + 0.03}};
  assert_polygon(&s, quad, 4);
  ck_assert_double_eq_tol(verdict(&m, &pose, w, &s, c2, &in), 0.006, EPS);
  ck_assert_int_eq(in, 1);
  const double beyond[3] = {0.021, 0.008, 0.002};
  ck_assert_double_eq_tol(verdict(&m, &pose, w, &s, beyond, &in), -0.001, EPS);
  ck_assert_int_eq(in, 0);
  free(w);
  model_mesh_free(&m);
}
END_TEST

/* ---- many points, capacity ------------------------------------------------------------------ */

/* A flat sheet (not closed: the model does not need it) of n x n grid cells over [0, a]^2. */
static void sheet(model_mesh_t *m, unsigned n, double a) {
  memset(m, 0, sizeof *m);
  m->vertex_count = (size_t)(n + 1) * (n + 1);
  m->triangle_count = 2 * (size_t)n * n;
  m->vertices_m = malloc(m->vertex_count * sizeof *m->vertices_m);
  m->triangles = malloc(m->triangle_count * sizeof *m->triangles);
  ck_assert(m->vertices_m && m->triangles);
  for (unsigned i = 0; i <= n; ++i)
    for (unsigned j = 0; j <= n; ++j) {
      double *v = m->vertices_m[i * (n + 1) + j];
      v[0] = a * i / n;
      v[1] = a * j / n;
      v[2] = 0.0;
    }
  size_t t = 0;
  for (uint32_t i = 0; i < n; ++i)
    for (uint32_t j = 0; j < n; ++j) {
      const uint32_t v0 = i * (n + 1) + j, v1 = v0 + n + 1;
      const uint32_t a0[3] = {v0, v1, v1 + 1}, a1[3] = {v0, v1 + 1, v0 + 1};
      memcpy(m->triangles[t++], a0, sizeof a0);
      memcpy(m->triangles[t++], a1, sizeof a1);
    }
}

/* 3721 vertices and 21 600 edge sides in the band: gathered in chunks, the hull is the square
 * clipped by the edge line. */
START_TEST(test_outcome_many_points) {
  model_mesh_t m;
  sheet(&m, 60, 0.06);
  model_outcome_work_t *w = work_new(&m);
  model_outcome_support_t s;
  const model_pose_t pose = {.position_m = {HX - 0.0401, -0.03, 0},
                             .orientation_wxyz = {1, 0, 0, 0}};
  support_at(&m, &pose, w, &s);
  ck_assert_uint_gt(s.point_count, 2 * MODEL_OUTCOME_MAX_VERTICES);
  const double x0 = HX - 0.0401;
  const double want[4][2] = {{x0, -0.03}, {HX, -0.03}, {HX, 0.03}, {x0, 0.03}};
  assert_polygon(&s, want, 4);
  free(w);
  model_mesh_free(&m);
}
END_TEST

/* A fan of k rim vertices on a circle: a support polygon of k vertices. */
static void fan(model_mesh_t *m, unsigned k) {
  memset(m, 0, sizeof *m);
  m->vertex_count = k + 1;
  m->triangle_count = k;
  m->vertices_m = calloc(k + 1, sizeof *m->vertices_m);
  m->triangles = malloc(k * sizeof *m->triangles);
  ck_assert(m->vertices_m && m->triangles);
  for (unsigned i = 0; i < k; ++i) {
    m->vertices_m[i + 1][0] = 0.03 * cos(2.0 * CL_PI * i / k);
    m->vertices_m[i + 1][1] = 0.03 * sin(2.0 * CL_PI * i / k);
    const uint32_t t[3] = {0, i + 1, (i + 1) % k + 1};
    memcpy(m->triangles[i], t, sizeof t);
  }
}

START_TEST(test_outcome_capacity) {
  const unsigned ks[2] = {MODEL_OUTCOME_MAX_VERTICES, MODEL_OUTCOME_MAX_VERTICES + 1};
  const model_pose_t pose = {.position_m = {0, 0, 0}, .orientation_wxyz = {1, 0, 0, 0}};
  for (int c = 0; c < 2; ++c) {
    model_mesh_t m;
    fan(&m, ks[c]);
    model_outcome_work_t *w = work_new(&m);
    model_outcome_support_t s;
    const model_status_t want = c == 0 ? MODEL_OK : MODEL_E_CAPACITY;
    ck_assert_int_eq(model_outcome_support_build(&m, &pose, BASE, NULL, w, &s), want);
    ck_assert_uint_eq(s.vertex_count, c == 0 ? ks[0] : 0);
    double poly[8][2];
    size_t n = 99;
    ck_assert_int_eq(model_support_polygon(&m, &pose, BASE, 3e-6, w, poly, 8, &n),
                     MODEL_E_CAPACITY);
    ck_assert_uint_eq(n, c == 0 ? ks[0] : 0);
    free(w);
    model_mesh_free(&m);
  }
}
END_TEST

/* ---- bad input ----------------------------------------------------------------------------- */

START_TEST(test_outcome_bad_input) {
  model_mesh_t m;
  box_40_60_50(&m);
  model_outcome_work_t *w = work_new(&m);
  model_outcome_support_t s;
  const model_pose_t ok = {.position_m = {0, 0, 0.025}, .orientation_wxyz = {1, 0, 0, 0}};
  const double com[3] = {0, 0, 0};
  double poly[8][2], mg;
  size_t n;
  int in;
  model_pose_t bad = ok;
  bad.position_m[1] = NAN;
  ck_assert_int_eq(model_outcome_support_build(&m, &bad, BASE, NULL, w, &s), MODEL_E_NONFINITE);
  bad = ok;
  bad.orientation_wxyz[2] = INFINITY;
  ck_assert_int_eq(model_support_polygon(&m, &bad, BASE, 3e-6, w, poly, 8, &n), MODEL_E_NONFINITE);
  bad.orientation_wxyz[2] = 0.1; /* not unit */
  ck_assert_int_eq(model_support_polygon(&m, &bad, BASE, 3e-6, w, poly, 8, &n), MODEL_E_POSE);
  const double base_nan[3] = {0.3, NAN, 0.1}, base_zero[3] = {0.3, 0.0, 0.1};
  ck_assert_int_eq(model_outcome_predict(&m, &ok, base_nan, com, NULL, w, &in, &mg),
                   MODEL_E_NONFINITE);
  ck_assert_int_eq(model_outcome_predict(&m, &ok, base_zero, com, NULL, w, &in, &mg), MODEL_E_ARG);
  ck_assert_int_eq(model_support_polygon(&m, &ok, BASE, NAN, w, poly, 8, &n), MODEL_E_NONFINITE);
  ck_assert_int_eq(model_support_polygon(&m, &ok, BASE, -1e-6, w, poly, 8, &n), MODEL_E_ARG);
  model_outcome_config_t cfg = MODEL_OUTCOME_CONFIG_DEFAULT;
  cfg.min_width_m = NAN;
  ck_assert_int_eq(model_outcome_predict(&m, &ok, BASE, com, &cfg, w, &in, &mg), MODEL_E_NONFINITE);
  ck_assert_int_eq(model_outcome_support_build(&m, &ok, BASE, NULL, w, &s), MODEL_OK);
  const double com_nan[3] = {0, NAN, 0};
  ck_assert_int_eq(model_outcome_support_test(&s, com_nan, &in, &mg), MODEL_E_NONFINITE);
  ck_assert_int_eq(in, 0);
  ck_assert_int_eq(model_outcome_predict(&m, &ok, BASE, com_nan, NULL, NULL, &in, &mg),
                   MODEL_E_NONFINITE);
  m.vertices_m[3][0] = NAN;
  ck_assert_int_eq(model_outcome_predict(&m, &ok, BASE, com, NULL, w, &in, &mg), MODEL_E_NONFINITE);
  m.vertices_m[3][0] = 0.02;
  m.triangles[5][1] = 8;
  ck_assert_int_eq(model_outcome_predict(&m, &ok, BASE, com, NULL, w, &in, &mg),
                   MODEL_E_DEGENERATE);
  m.triangles[5][1] = 0;
  /* a work area of another mesh, NULLs */
  model_mesh_t other;
  prism(&other);
  ck_assert_int_eq(model_outcome_support_build(&other, &ok, BASE, NULL, w, &s), MODEL_E_ARG);
  ck_assert_int_eq(model_outcome_support_build(&m, &ok, BASE, NULL, NULL, &s), MODEL_E_ARG);
  ck_assert_int_eq(model_support_polygon(&m, &ok, BASE, 3e-6, w, NULL, 8, &n), MODEL_E_ARG);
  ck_assert_ptr_null(model_outcome_work_init(w, 8, &m));
  ck_assert_uint_eq(model_outcome_work_size(NULL), 0);
  model_mesh_free(&other);
  free(w);
  model_mesh_free(&m);
}
END_TEST

/* Nothing over B: no support, margin -HUGE_VAL. */
START_TEST(test_outcome_off_b) {
  model_mesh_t m;
  box_40_60_50(&m);
  model_outcome_work_t *w = work_new(&m);
  model_outcome_support_t s;
  const model_pose_t pose = {.position_m = {0.5, 0, 0.025}, .orientation_wxyz = {1, 0, 0, 0}};
  ck_assert_int_eq(model_outcome_support_build(&m, &pose, BASE, NULL, w, &s), MODEL_OK);
  ck_assert_uint_eq(s.vertex_count, 0);
  ck_assert_uint_eq(s.point_count, 0);
  int in = -1;
  const double com[3] = {0, 0, 0};
  ck_assert(verdict(&m, &pose, w, &s, com, &in) == -HUGE_VAL);
  ck_assert_int_eq(in, 0);
  free(w);
  model_mesh_free(&m);
}
END_TEST

Suite *model_outcome_suite(void) {
  Suite *s = suite_create("model_outcome");
  TCase *tc = tcase_create("outcome");
  tcase_set_timeout(tc, 60);
  tcase_add_test(tc, test_outcome_box_straddling);
  tcase_add_test(tc, test_outcome_box_yawed);
  tcase_add_test(tc, test_outcome_box_on_b);
  tcase_add_test(tc, test_outcome_band_and_tilt);
  tcase_add_test(tc, test_outcome_on_edge_line);
  tcase_add_test(tc, test_outcome_two_feet);
  tcase_add_test(tc, test_outcome_prism);
  tcase_add_test(tc, test_outcome_many_points);
  tcase_add_test(tc, test_outcome_capacity);
  tcase_add_test(tc, test_outcome_bad_input);
  tcase_add_test(tc, test_outcome_off_b);
  suite_add_tcase(s, tc);
  return s;
}
