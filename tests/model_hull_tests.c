/* model_hull_tests.c - convex hull and bounding box. */
#define _POSIX_C_SOURCE 200809L

#include "comlearn/math3d.h"
#include "comlearn/model_support.h"
#include "model_suites.h"
#include "model_test_util.h"

/* A point set as a mesh with no triangles (the hull reads vertices only). */
static void points_alloc(model_mesh_t *m, size_t n) {
  memset(m, 0, sizeof *m);
  m->vertex_count = n;
  m->vertices_m = malloc(n * sizeof *m->vertices_m);
  ck_assert_ptr_nonnull(m->vertices_m);
}

/* UV sphere of radius r: every vertex is extreme and every band is planar, so the polyhedron is
 * convex and equals its own hull. */
static void uv_sphere(model_mesh_t *m, double r, unsigned rings, unsigned segs) {
  mt_rock(m, rings, segs); /* topology only; positions replaced */
  const double pi = CL_PI;
  m->vertices_m[0][0] = m->vertices_m[0][1] = 0.0;
  m->vertices_m[0][2] = r;
  m->vertices_m[1][0] = m->vertices_m[1][1] = 0.0;
  m->vertices_m[1][2] = -r;
  for (unsigned i = 1; i < rings; ++i) {
    for (unsigned j = 0; j < segs; ++j) {
      double th = pi * i / rings, ph = 2.0 * pi * j / segs;
      double *v = m->vertices_m[2 + (i - 1) * segs + j];
      v[0] = r * sin(th) * cos(ph);
      v[1] = r * sin(th) * sin(ph);
      v[2] = r * cos(th);
    }
  }
}

/* The properties every hull must have, checked against the input points:
 * closed and outward (model_mesh_check changes nothing), Euler characteristic 2, vertices taken
 * from the input, every input point and every hull vertex on the inner side of every face. */
static void assert_valid_hull(const model_mesh_t *pts, const model_mesh_t *hull, double tol) {
  model_mesh_t copy;
  ck_assert_int_eq(model_mesh_copy(hull, &copy), MODEL_OK);
  model_mesh_report_t rep;
  model_error_t err;
  ck_assert_msg(model_mesh_check(&copy, &rep, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_uint_eq(rep.merged_vertices + rep.removed_degenerate + rep.removed_unreferenced, 0);
  ck_assert_int_eq(rep.flipped, 0);
  model_mesh_free(&copy);
  /* V - E + F = 2 with E = 3F/2 for a closed triangulated sphere. */
  ck_assert_uint_eq(2 * hull->vertex_count, hull->triangle_count + 4);

  /* Check's asserts write a checkpoint each; keep them out of the O(n^2) loops. */
  size_t not_input = 0, outside = 0, flat = 0;
  double worst = -INFINITY;
  for (size_t i = 0; i < hull->vertex_count; ++i) {
    int found = 0;
    for (size_t j = 0; j < pts->vertex_count && !found; ++j) {
      found = memcmp(hull->vertices_m[i], pts->vertices_m[j], sizeof pts->vertices_m[0]) == 0;
    }
    not_input += !found;
  }
  for (size_t t = 0; t < hull->triangle_count; ++t) {
    const double *a = hull->vertices_m[hull->triangles[t][0]];
    const double *b = hull->vertices_m[hull->triangles[t][1]];
    const double *c = hull->vertices_m[hull->triangles[t][2]];
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    flat += !(len > 0.0);
    for (size_t i = 0; i < pts->vertex_count; ++i) {
      const double *p = pts->vertices_m[i];
      double dist = (n[0] * (p[0] - a[0]) + n[1] * (p[1] - a[1]) + n[2] * (p[2] - a[2])) / len;
      outside += !(dist <= tol);
      worst = fmax(worst, dist);
    }
  }
  ck_assert_msg(not_input == 0, "%zu hull vertices are not input points", not_input);
  ck_assert_msg(flat == 0, "%zu hull faces have zero area", flat);
  ck_assert_msg(outside == 0, "%zu point-face pairs outside by up to %g (tol %g)", outside, worst,
                tol);
}

START_TEST(test_hull_cube_interior_and_duplicates) {
  model_mesh_t cube, pts, hull;
  const double lo[3] = {-0.5, 2.0, 10.0}, hi[3] = {0.5, 3.0, 11.0};
  mt_box(&cube, lo, hi);
  /* corners three times each, then 300 interior points */
  points_alloc(&pts, 24 + 300);
  for (size_t i = 0; i < 24; ++i) {
    memcpy(pts.vertices_m[i], cube.vertices_m[(i * 5) % 8], sizeof pts.vertices_m[0]);
  }
  uint64_t s = 1;
  for (size_t i = 24; i < pts.vertex_count; ++i) {
    for (int k = 0; k < 3; ++k) {
      pts.vertices_m[i][k] = lo[k] + 0.01 + 0.98 * cl_rng_uniform(&s);
    }
  }
  model_error_t err;
  ck_assert_msg(model_mesh_hull(&pts, &hull, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_uint_eq(hull.vertex_count, 8);
  ck_assert_uint_eq(hull.triangle_count, 12);
  ck_assert(mt_same_vertices(&hull, &cube, 0.0));
  ck_assert_double_eq_tol(mt_volume(&hull), 1.0, 1e-12);
  assert_valid_hull(&pts, &hull, 1e-12);
  model_mesh_free(&hull);

  /* The cube mesh itself is its own hull. */
  ck_assert_int_eq(model_mesh_hull(&cube, &hull, NULL), MODEL_OK);
  ck_assert_uint_eq(hull.vertex_count, 8);
  ck_assert_uint_eq(hull.triangle_count, 12);
  model_mesh_free(&hull);
  model_mesh_free(&pts);
  model_mesh_free(&cube);
}
END_TEST

/* Many coplanar and collinear points: a 6 x 6 x 6 integer lattice, and points on a cube's faces. */
START_TEST(test_hull_lattice_and_face_points) {
  model_mesh_t pts, hull;
  points_alloc(&pts, 216);
  for (size_t i = 0; i < 216; ++i) {
    pts.vertices_m[i][0] = (double)(i % 6);
    pts.vertices_m[i][1] = (double)((i / 6) % 6);
    pts.vertices_m[i][2] = (double)(i / 36);
  }
  model_error_t err;
  ck_assert_msg(model_mesh_hull(&pts, &hull, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_double_eq_tol(mt_volume(&hull), 125.0, 1e-9);
  ck_assert_uint_ge(hull.vertex_count, 8);
  assert_valid_hull(&pts, &hull, 1e-9);
  model_mesh_free(&hull);
  model_mesh_free(&pts);

  /* 11 x 11 grid on each face of the unit cube, listed face by face. */
  points_alloc(&pts, 6 * 121);
  size_t n = 0;
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      for (int a = 0; a <= 10; ++a) {
        for (int b = 0; b <= 10; ++b) {
          double *p = pts.vertices_m[n++];
          p[axis] = side;
          p[(axis + 1) % 3] = a / 10.0;
          p[(axis + 2) % 3] = b / 10.0;
        }
      }
    }
  }
  ck_assert_msg(model_mesh_hull(&pts, &hull, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_double_eq_tol(mt_volume(&hull), 1.0, 1e-12);
  assert_valid_hull(&pts, &hull, 1e-12);
  model_mesh_free(&hull);
  model_mesh_free(&pts);
}
END_TEST

START_TEST(test_hull_random_points) {
  model_mesh_t pts, hull;
  uint64_t s = 42;
  points_alloc(&pts, 2000);
  for (size_t i = 0; i < pts.vertex_count;) {
    double p[3] = {2 * cl_rng_uniform(&s) - 1, 2 * cl_rng_uniform(&s) - 1,
                   2 * cl_rng_uniform(&s) - 1};
    if (p[0] * p[0] + p[1] * p[1] + p[2] * p[2] <= 1.0) {
      pts.vertices_m[i][0] = 0.03 * p[0] + 0.4; /* a 6 cm ball away from the origin */
      pts.vertices_m[i][1] = 0.03 * p[1] - 0.2;
      pts.vertices_m[i][2] = 0.03 * p[2] + 0.1;
      ++i;
    }
  }
  model_error_t err;
  ck_assert_msg(model_mesh_hull(&pts, &hull, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_uint_gt(hull.vertex_count, 50);
  ck_assert_uint_lt(hull.vertex_count, 2000);
  assert_valid_hull(&pts, &hull, 1e-12);
  const double ball = 4.0 / 3.0 * CL_PI * 0.03 * 0.03 * 0.03;
  double v = mt_volume(&hull);
  ck_assert_double_lt(v, ball);
  ck_assert_double_gt(v, 0.85 * ball); /* 2000 uniform points: about 0.89 of the ball */
  model_mesh_free(&hull);

  /* On the sphere: every point is extreme. */
  for (size_t i = 0; i < pts.vertex_count; ++i) {
    double *p = pts.vertices_m[i];
    double c[3] = {p[0] - 0.4, p[1] + 0.2, p[2] - 0.1};
    double r = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    for (int k = 0; k < 3; ++k) {
      c[k] /= r;
    }
    p[0] = c[0];
    p[1] = c[1];
    p[2] = c[2];
  }
  ck_assert_msg(model_mesh_hull(&pts, &hull, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_uint_eq(hull.vertex_count, 2000);
  assert_valid_hull(&pts, &hull, 1e-12);
  model_mesh_free(&hull);
  model_mesh_free(&pts);
}
END_TEST

START_TEST(test_hull_sphere_mesh) {
  model_mesh_t sphere, hull;
  uv_sphere(&sphere, 0.05, 40, 80);
  model_error_t err;
  ck_assert_int_eq(model_mesh_check(&sphere, NULL, &err), MODEL_OK);
  ck_assert_msg(model_mesh_hull(&sphere, &hull, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_uint_eq(hull.vertex_count, sphere.vertex_count);
  double v = mt_volume(&sphere);
  ck_assert_double_eq_tol(mt_volume(&hull), v, 1e-12 * v);
  assert_valid_hull(&sphere, &hull, 1e-13);
  model_mesh_free(&hull);
  model_mesh_free(&sphere);

  /* A non-convex rock: the hull holds it and is larger. */
  model_mesh_t rock;
  mt_rock(&rock, 30, 60);
  ck_assert_msg(model_mesh_hull(&rock, &hull, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_uint_lt(hull.vertex_count, rock.vertex_count);
  ck_assert_double_gt(mt_volume(&hull), 1.01 * mt_volume(&rock));
  assert_valid_hull(&rock, &hull, 1e-12);
  model_mesh_free(&hull);
  model_mesh_free(&rock);
}
END_TEST

START_TEST(test_hull_degenerate_input) {
  model_mesh_t pts, hull;
  model_error_t err;
  /* coplanar: a grid on the plane z = 0.3 x + 0.2 y */
  points_alloc(&pts, 100);
  for (size_t i = 0; i < 100; ++i) {
    double x = (double)(i % 10), y = (double)(i / 10);
    pts.vertices_m[i][0] = x;
    pts.vertices_m[i][1] = y;
    pts.vertices_m[i][2] = 0.25 * x + 0.5 * y;
  }
  ck_assert_int_eq(model_mesh_hull(&pts, &hull, &err), MODEL_E_HULL);
  ck_assert_ptr_nonnull(strstr(err.msg, "coplanar"));
  ck_assert_ptr_null(hull.vertices_m);
  /* one point lifted off the plane: a valid (flat) hull */
  pts.vertices_m[55][2] += 1e-3;
  ck_assert_int_eq(model_mesh_hull(&pts, &hull, &err), MODEL_OK);
  assert_valid_hull(&pts, &hull, 1e-12);
  model_mesh_free(&hull);
  /* collinear */
  for (size_t i = 0; i < 100; ++i) {
    pts.vertices_m[i][0] = (double)i;
    pts.vertices_m[i][1] = 2.0 * (double)i;
    pts.vertices_m[i][2] = -(double)i;
  }
  ck_assert_int_eq(model_mesh_hull(&pts, &hull, &err), MODEL_E_HULL);
  ck_assert_ptr_nonnull(strstr(err.msg, "collinear"));
  /* coincident */
  for (size_t i = 0; i < 100; ++i) {
    pts.vertices_m[i][0] = pts.vertices_m[i][1] = pts.vertices_m[i][2] = 0.125;
  }
  ck_assert_int_eq(model_mesh_hull(&pts, &hull, &err), MODEL_E_HULL);
  ck_assert_ptr_nonnull(strstr(err.msg, "coincide"));
  /* too few, non-finite, NULL */
  pts.vertex_count = 3;
  ck_assert_int_eq(model_mesh_hull(&pts, &hull, &err), MODEL_E_HULL);
  pts.vertex_count = 100;
  pts.vertices_m[7][1] = NAN;
  ck_assert_int_eq(model_mesh_hull(&pts, &hull, &err), MODEL_E_NONFINITE);
  ck_assert_ptr_nonnull(strstr(err.msg, "vertex 7"));
  ck_assert_int_eq(model_mesh_hull(NULL, &hull, &err), MODEL_E_ARG);
  ck_assert_int_eq(model_mesh_hull(&pts, NULL, &err), MODEL_E_ARG);
  model_mesh_free(&pts);
}
END_TEST

START_TEST(test_aabb_and_center) {
  model_mesh_t m;
  const double lo[3] = {-0.25, 1.5, 3.0}, hi[3] = {0.75, 2.0, 7.0};
  mt_box(&m, lo, hi);
  m.vertices_m[3][2] = 5.0; /* an inner value changes nothing */
  model_aabb_t box;
  ck_assert_int_eq(model_mesh_aabb(&m, &box), MODEL_OK);
  double c[3];
  model_aabb_center(&box, c);
  for (int k = 0; k < 3; ++k) {
    ck_assert_double_eq(box.min_m[k], lo[k]);
    ck_assert_double_eq(box.max_m[k], hi[k]);
    ck_assert_double_eq(c[k], 0.5 * (lo[k] + hi[k]));
  }
  ck_assert_double_eq(c[0], 0.25);
  ck_assert_double_eq(c[1], 1.75);
  ck_assert_double_eq(c[2], 5.0);

  /* The rock: the box is the per-axis extreme of its vertices. */
  model_mesh_t r;
  mt_rock(&r, 12, 24);
  ck_assert_int_eq(model_mesh_aabb(&r, &box), MODEL_OK);
  double want_lo[3] = {INFINITY, INFINITY, INFINITY},
         want_hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (size_t i = 0; i < r.vertex_count; ++i) {
    for (int k = 0; k < 3; ++k) {
      want_lo[k] = fmin(want_lo[k], r.vertices_m[i][k]);
      want_hi[k] = fmax(want_hi[k], r.vertices_m[i][k]);
    }
  }
  for (int k = 0; k < 3; ++k) {
    ck_assert_double_eq(box.min_m[k], want_lo[k]);
    ck_assert_double_eq(box.max_m[k], want_hi[k]);
  }
  model_mesh_free(&r);

  m.vertices_m[6][0] = NAN;
  ck_assert_int_eq(model_mesh_aabb(&m, &box), MODEL_E_NONFINITE);
  model_mesh_free(&m);
  ck_assert_int_eq(model_mesh_aabb(&m, &box), MODEL_E_DEGENERATE);
  ck_assert_int_eq(model_mesh_aabb(NULL, &box), MODEL_E_ARG);
  ck_assert_int_eq(model_mesh_aabb(&m, NULL), MODEL_E_ARG);
}
END_TEST

START_TEST(test_polygon_square) {
  /* A 40 x 20 mm rectangle's corners, shuffled, with interior and edge points. */
  double pts[9][2] = {{0.04, 0.02}, {0.01, 0.01},  {0.0, 0.0},   {0.02, 0.0}, {0.0, 0.02},
                      {0.04, 0.0},  {0.03, 0.005}, {0.02, 0.02}, {0.0, 0.01}};
  double hull[10][2];
  const size_t n = model_polygon_hull(pts, 9, hull);
  ck_assert_uint_eq(n, 4); /* collinear edge points dropped */
  const double(*h)[2] = (const double(*)[2])hull;
  ck_assert_double_eq_tol(model_polygon_area(h, n), 0.04 * 0.02, 1e-18); /* counter-clockwise */
  ck_assert_double_eq_tol(model_polygon_width(h, n), 0.02, 1e-15);
  const double inside[2] = {0.03, 0.015}, outside[2] = {0.05, 0.025}, corner[2] = {0.0, 0.0};
  ck_assert_double_eq_tol(model_polygon_margin(h, n, inside), 0.005, 1e-15);
  ck_assert_double_eq_tol(model_polygon_margin(h, n, outside), -hypot(0.01, 0.005), 1e-15);
  ck_assert_double_eq_tol(model_polygon_margin(h, n, corner), 0.0, 1e-15);
  ck_assert(model_polygon_margin(h, 2, inside) == -HUGE_VAL);
  ck_assert_double_eq(model_polygon_area(h, 2), 0.0);
}
END_TEST

/* model_hull_faces: a 3 x 2 x 1 box's hull is six faces of two facets each, with the box's
 * normals and areas, the largest first; a tilted facet joins only within the merge angle. */
START_TEST(test_hull_faces_box) {
  model_mesh_t box = {0}, hull = {0};
  const double lo[3] = {-1.5, -1.0, -0.5}, hi[3] = {1.5, 1.0, 0.5};
  ck_assert_int_eq(model_mesh_box(lo, hi, &box), MODEL_OK);
  ck_assert_int_eq(model_mesh_hull(&box, &hull, NULL), MODEL_OK);
  model_hull_face_t f[12];
  int of[12];
  size_t n = 0;
  ck_assert_int_eq(model_hull_faces(&hull, cos(1e-3), 1e-9, f, of, &n), MODEL_OK);
  ck_assert_uint_eq(n, 6);
  const double area[6] = {6.0, 6.0, 3.0, 3.0, 2.0, 2.0}; /* z, y, x faces: 3x2, 3x1, 2x1 */
  int per_face[6] = {0};
  for (size_t i = 0; i < 12; ++i) {
    ck_assert_int_ge(of[i], 0);
    ck_assert_int_lt(of[i], 6);
    ++per_face[of[i]];
  }
  for (size_t i = 0; i < 6; ++i) {
    ck_assert_int_eq(per_face[i], 2);
    ck_assert_double_eq_tol(f[i].area_m2, area[i], 1e-12);
    ck_assert_double_eq_tol(cl_vec3_norm(f[i].normal), 1.0, 1e-12);
    /* an axis normal: one component +-1 */
    const int axis = i < 2 ? 2 : i < 4 ? 1 : 0;
    ck_assert_double_eq_tol(fabs(f[i].normal[axis]), 1.0, 1e-12);
    ck_assert_int_ge(of[f[i].seed], 0);
    ck_assert_uint_eq((size_t)of[f[i].seed], i);
  }
  ck_assert_double_eq_tol(f[0].normal[2] + f[1].normal[2], 0.0, 1e-12); /* +z and -z */
  /* Lift one top corner by 1e-4: its two top facets now differ by ~1e-4 rad. Merged at 1e-3 rad
   * with a plane tolerance above the lift, split at 1e-5 rad. */
  for (size_t v = 0; v < hull.vertex_count; ++v)
    if (hull.vertices_m[v][0] > 0 && hull.vertices_m[v][1] > 0 && hull.vertices_m[v][2] > 0)
      hull.vertices_m[v][2] += 1e-4;
  ck_assert_int_eq(model_hull_faces(&hull, cos(1e-3), 2e-4, f, of, &n), MODEL_OK);
  ck_assert_uint_eq(n, 6);
  ck_assert_int_eq(model_hull_faces(&hull, cos(1e-5), 2e-4, f, of, &n), MODEL_OK);
  ck_assert_uint_ge(n, 7);
  ck_assert_int_eq(model_hull_faces(NULL, 0.9, 1e-6, f, of, &n), MODEL_E_ARG);
  ck_assert_int_eq(model_hull_faces(&hull, NAN, 1e-6, f, of, &n), MODEL_E_ARG);
  ck_assert_int_eq(model_hull_faces(&hull, 0.9, -1.0, f, of, &n), MODEL_E_ARG);
  model_mesh_free(&hull);
  model_mesh_free(&box);
}
END_TEST

Suite *model_hull_suite(void) {
  Suite *s = suite_create("model_hull");
  TCase *tc = tcase_create("hull");
  tcase_set_timeout(tc, 60);
  tcase_add_test(tc, test_polygon_square);
  tcase_add_test(tc, test_hull_cube_interior_and_duplicates);
  tcase_add_test(tc, test_hull_lattice_and_face_points);
  tcase_add_test(tc, test_hull_random_points);
  tcase_add_test(tc, test_hull_sphere_mesh);
  tcase_add_test(tc, test_hull_degenerate_input);
  tcase_add_test(tc, test_aabb_and_center);
  tcase_add_test(tc, test_hull_faces_box);
  suite_add_tcase(s, tc);
  return s;
}
