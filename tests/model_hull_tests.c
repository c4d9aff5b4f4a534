/* model_hull_tests.c - convex hull and bounding box. */
#define _POSIX_C_SOURCE 200809L

#include "comlearn/math3d.h"
#include "comlearn/model_support.h"
#include "mesh_subdivide.h"
#include "model_internal.h" /* lib/model/src: model_hull_verify_faces */
#include "model_suites.h"
#include "model_test_util.h"
#include "orient.h" /* lib/model/src: the exact predicate under the hull */

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

/* ---- the hull at scale: fine, coplanar and noisy meshes (issue 13) -------------------------- */

static void hull_ok(const model_mesh_t *pts, model_mesh_t *hull) {
  model_error_t err = {{0}};
  ck_assert_msg(model_mesh_hull(pts, hull, &err) == MODEL_OK, "%zu points: %s", pts->vertex_count,
                err.msg);
}

/* The face planes of a hull, n . x = d with unit n: planes[t] = (n, d). Allocated (free it). */
static double (*hull_planes(const model_mesh_t *hull))[4] {
  double(*pl)[4] = malloc(hull->triangle_count * sizeof *pl);
  ck_assert_ptr_nonnull(pl);
  for (size_t t = 0; t < hull->triangle_count; ++t) {
    const double *a = hull->vertices_m[hull->triangles[t][0]];
    cl_tri_normal(a, hull->vertices_m[hull->triangles[t][1]],
                  hull->vertices_m[hull->triangles[t][2]], pl[t]);
    pl[t][3] = cl_vec3_dot(pl[t], a);
  }
  return pl;
}

/* The largest signed distance of p above one of the n planes (positive: outside). */
static double above_planes(const double (*pl)[4], size_t n, const double p[3]) {
  double worst = -HUGE_VAL;
  for (size_t t = 0; t < n; ++t) worst = fmax(worst, cl_vec3_dot(pl[t], p) - pl[t][3]);
  return worst;
}

/* A bundled rock's mesh (link frame, as the estimator loads it). */
static void rock_load(int r, model_mesh_t *m) {
  char path[512];
  snprintf(path, sizeof path, "%s/rocks/rock_%d_even.urdf", COMLEARN_ASSETS_DIR, r);
  model_object_t obj;
  model_error_t err;
  ck_assert_msg(model_object_load(path, NULL, &obj, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_int_eq(model_mesh_copy(&obj.mesh, m), MODEL_OK);
  model_object_free(&obj);
}

/* The hull h of the rock subdivided (exact midpoints) against the rock's own hull h0: the same
 * solid (volume within 1e-9), every vertex of h on h0's surface and every vertex of h0 on h's,
 * and h's vertices at most the mesh's points on that surface. */
static void assert_same_solid(const model_mesh_t *sub, const model_mesh_t *h,
                              const model_mesh_t *h0, double v0) {
  ck_assert_double_eq_tol(mt_volume(h), v0, 1e-9 * v0);
  double(*p0)[4] = hull_planes(h0), (*p1)[4] = hull_planes(h);
  const size_t n0 = h0->triangle_count, n1 = h->triangle_count;
  size_t off = 0, missed = 0, on_surface = 0;
  for (size_t i = 0; i < h->vertex_count; ++i)
    off += !(fabs(above_planes((const double(*)[4])p0, n0, h->vertices_m[i])) <= 1e-12);
  /* within tol = 1e-10 x diagonal: h0 may keep a point the subdivided hull dropped as coplanar */
  for (size_t i = 0; i < h0->vertex_count; ++i)
    missed += !(fabs(above_planes((const double(*)[4])p1, n1, h0->vertices_m[i])) <= 1e-11);
  for (size_t i = 0; i < sub->vertex_count; ++i)
    on_surface += above_planes((const double(*)[4])p0, n0, sub->vertices_m[i]) >= -1e-12;
  free(p0);
  free(p1);
  ck_assert_msg(off == 0, "%zu of %zu hull vertices off the rock's hull", off, h->vertex_count);
  ck_assert_msg(missed == 0, "%zu rock hull vertices off the subdivided hull", missed);
  ck_assert_uint_le(h->vertex_count, on_surface);
  ck_assert_uint_ge(h->vertex_count, 9 * h0->vertex_count / 10); /* the extreme points stay */
}

/* The bundled rocks subdivided 1x, 2x, 3x (8 000 to 128 000 triangles): every edge midpoint of a
 * hull facet lies exactly on the hull, so many points are coplanar with the faces the new hull
 * point sees. The inexact walk of old failed its own check on all of these from 32 000 triangles
 * (rock_3 from 8 000); with float midpoints (as an STL stores them) it failed from 8 000. */
START_TEST(test_hull_subdivided_rocks) {
  for (int r = 1; r <= 3; ++r) {
    model_mesh_t rock, h0;
    rock_load(r, &rock);
    hull_ok(&rock, &h0);
    assert_valid_hull(&rock, &h0, 1e-12);
    const double v0 = mt_volume(&h0);
    for (int round_f32 = 0; round_f32 <= 1; ++round_f32) {
      model_mesh_t cur;
      ck_assert_int_eq(model_mesh_copy(&rock, &cur), MODEL_OK);
      for (int level = 1; level <= 3; ++level) {
        model_mesh_t sub, h;
        ck_assert_int_eq(mesh_subdivide(&cur, &sub, round_f32), 0);
        model_mesh_free(&cur);
        cur = sub;
        ck_assert_uint_eq(sub.triangle_count, rock.triangle_count << (2 * level));
        model_mesh_report_t rep;
        ck_assert_int_eq(model_mesh_check(&cur, &rep, NULL), MODEL_OK); /* closed, outward */
        ck_assert_uint_eq(rep.merged_vertices + rep.removed_degenerate, 0);
        ck_assert_int_eq(rep.flipped, 0);
        sub = cur;
        hull_ok(&sub, &h);
        /* float midpoints: within the hull's tolerance (1e-10 x the 75 mm diagonal) of a face */
        if (level == 1) assert_valid_hull(&sub, &h, round_f32 ? 1e-11 : 1e-12);
        if (round_f32) {
          /* the rounded midpoints move the surface by < 4e-9 m: 1e-7 of the volume at most */
          ck_assert_double_eq_tol(mt_volume(&h), v0, 1e-6 * v0);
          ck_assert_uint_lt(h.vertex_count, sub.vertex_count / 2);
        } else {
          assert_same_solid(&sub, &h, &h0, v0);
        }
        model_mesh_free(&h);
      }
      model_mesh_free(&cur);
    }
    model_mesh_free(&h0);
    model_mesh_free(&rock);
  }
}
END_TEST

/* A sphere mesh of 9 024 triangles with every coordinate moved by up to 1 um, and by up to 20 um
 * (the sagitta between neighbours is ~27 um here: noise of that size makes points interior). */
START_TEST(test_hull_noisy_sphere) {
  const double r = 0.05, sigma[2] = {1e-6, 2e-5};
  for (int k = 0; k < 2; ++k) {
    model_mesh_t sphere, hull;
    uv_sphere(&sphere, r, 48, 96);
    const double v_exact = mt_volume(&sphere);
    uint64_t s = 7 + (uint64_t)k;
    for (size_t i = 0; i < sphere.vertex_count; ++i) {
      for (int c = 0; c < 3; ++c) sphere.vertices_m[i][c] += cl_rng_range(&s, -sigma[k], sigma[k]);
    }
    hull_ok(&sphere, &hull);
    assert_valid_hull(&sphere, &hull, 1e-12);
    /* every point moved by <= sqrt(3) sigma: the volume by about 3 sqrt(3) sigma / r of it */
    ck_assert_double_eq_tol(mt_volume(&hull), v_exact, 4.0 * sqrt(3.0) * sigma[k] / r * v_exact);
    ck_assert_uint_le(hull.vertex_count, sphere.vertex_count);
    ck_assert_uint_ge(hull.vertex_count, (k == 0 ? 95 : 50) * sphere.vertex_count / 100);
    model_mesh_free(&hull);
    model_mesh_free(&sphere);
  }
}
END_TEST

/* The points of a 100 x 60 x 40 mm box whose every face is a 100 x 100 grid (60 002 points, all
 * but the corners coplanar with a face or collinear with an edge), axis-aligned (exactly coplanar)
 * and rotated (coplanar within rounding). */
START_TEST(test_hull_box_grid) {
  const double lo[3] = {-0.05, -0.03, 0.01}, hi[3] = {0.05, 0.03, 0.05};
  double q[4] = {0.9, 0.3, -0.2, 0.25}, rot[3][3];
  (void)cl_quat_normalize(q, q);
  cl_quat_to_rot(q, rot);
  for (int rotated = 0; rotated <= 1; ++rotated) {
    model_mesh_t pts, hull;
    points_alloc(&pts, 101 * 101 * 101 - 99 * 99 * 99);
    size_t n = 0;
    for (int i = 0; i <= 100; ++i) {
      for (int j = 0; j <= 100; ++j) {
        for (int k = 0; k <= 100; ++k) {
          if (i % 100 != 0 && j % 100 != 0 && k % 100 != 0) continue;
          const int ijk[3] = {i, j, k};
          double v[3];
          for (int c = 0; c < 3; ++c) v[c] = lo[c] + (hi[c] - lo[c]) / 100.0 * ijk[c];
          double *p = pts.vertices_m[n++];
          for (int c = 0; c < 3; ++c)
            p[c] = rotated ? rot[c][0] * v[0] + rot[c][1] * v[1] + rot[c][2] * v[2] : v[c];
        }
      }
    }
    ck_assert_uint_eq(n, pts.vertex_count);
    hull_ok(&pts, &hull);
    assert_valid_hull(&pts, &hull, 1e-12);
    ck_assert_double_eq_tol(mt_volume(&hull), 0.1 * 0.06 * 0.04, 1e-12 * 0.1 * 0.06 * 0.04);
    if (!rotated) {
      model_mesh_t box;
      double top[3]; /* the grid's last points, as computed above */
      for (int c = 0; c < 3; ++c) top[c] = lo[c] + (hi[c] - lo[c]) / 100.0 * 100;
      mt_box(&box, lo, top);
      ck_assert_uint_eq(hull.vertex_count, 8); /* the corners, nothing coplanar */
      ck_assert(mt_same_vertices(&hull, &box, 0.0));
      model_mesh_free(&box);
    } else {
      ck_assert_uint_ge(hull.vertex_count, 8);
      ck_assert_uint_le(hull.vertex_count, 16);
    }
    model_mesh_free(&hull);
    model_mesh_free(&pts);
  }
}
END_TEST

/* 20 000 random points: uniform in a cube, and normal (a hull of a few hundred of them). */
START_TEST(test_hull_random_clouds) {
  for (int kind = 0; kind < 2; ++kind) {
    model_mesh_t pts, hull;
    uint64_t s = 99 + (uint64_t)kind;
    points_alloc(&pts, 20000);
    for (size_t i = 0; i < pts.vertex_count; ++i) {
      double g[2], g2[2];
      cl_rng_normal2(&s, g);
      cl_rng_normal2(&s, g2);
      for (int c = 0; c < 3; ++c) {
        pts.vertices_m[i][c] =
            kind == 0 ? 0.02 * cl_rng_uniform(&s) + 0.3 : 0.01 * (c < 2 ? g[c] : g2[0]);
      }
    }
    hull_ok(&pts, &hull);
    assert_valid_hull(&pts, &hull, 1e-12);
    ck_assert_uint_gt(hull.vertex_count, kind == 0 ? 100 : 20);
    ck_assert_uint_lt(hull.vertex_count, 1000);
    if (kind == 0) {
      const double v = mt_volume(&hull), cube = 0.02 * 0.02 * 0.02;
      ck_assert_double_le(v, cube * (1 + 1e-12));
      ck_assert_double_gt(v, 0.97 * cube);
    }
    model_mesh_free(&hull);
    model_mesh_free(&pts);
  }
}
END_TEST

/* model_orient3d (lib/model/src/orient.h): exact where the double formula cannot tell. Points on
 * one plane (midpoints and dyadic combinations of three points of 30-bit coordinates, exact in
 * double) are coplanar (0); one unit in the last place above or below the plane is +1 or -1.
 * The plain double determinant gets a wrong sign or a nonzero for many of these. */
START_TEST(test_orient3d_exact) {
  uint64_t s = 5;
  size_t naive_wrong = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    double a[3], b[3], c[3], d[3];
    for (int k = 0; k < 3; ++k) {
      a[k] = ldexp((double)cl_rng_below(&s, 1u << 30), -31) + 0.25;
      b[k] = ldexp((double)cl_rng_below(&s, 1u << 30), -31) - 0.5;
      c[k] = ldexp((double)cl_rng_below(&s, 1u << 30), -31) + 0.125;
    }
    /* d = a + (b - a) / 4 + (c - a) * 3 / 8, exact: every term has few bits */
    for (int k = 0; k < 3; ++k) d[k] = a[k] + 0.25 * (b[k] - a[k]) + 0.375 * (c[k] - a[k]);
    ck_assert_int_eq(model_orient3d(a, b, c, d), 0);
    ck_assert_int_eq(model_orient3d(b, c, a, d), 0);
    double n[3];
    model_tri_cross(a, b, c, n);
    /* move d off the plane by one ulp along the axis where the normal is largest */
    int ax = 0;
    for (int k = 1; k < 3; ++k)
      if (fabs(n[k]) > fabs(n[ax])) ax = k;
    const int up = trial % 2 ? 1 : -1;
    d[ax] = nextafter(d[ax], up * HUGE_VAL);
    const int want = (n[ax] > 0) == (up > 0) ? 1 : -1;
    ck_assert_int_eq(model_orient3d(a, b, c, d), want);
    ck_assert_int_eq(model_orient3d(a, c, b, d), -want);
    ck_assert_int_eq(model_orient3d(d, a, c, b), want); /* an even permutation */
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double e[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
    const double naive = (u[1] * w[2] - u[2] * w[1]) * e[0] + (u[2] * w[0] - u[0] * w[2]) * e[1] +
                         (u[0] * w[1] - u[1] * w[0]) * e[2];
    naive_wrong += !((naive > 0) == (want > 0) && naive != 0);
  }
  ck_assert_uint_gt(naive_wrong, 1000); /* the cases are hard ones */
  /* the exact cross product of a sliver: b - a and c - a 1e-12 rad apart */
  const double a[3] = {0.1, 0.2, 0.3}, b[3] = {0.6, 0.2, 0.3}, c[3] = {1.1, 0.2 + 1e-12, 0.3};
  double n[3];
  model_tri_cross(a, b, c, n);
  ck_assert_double_eq(n[0], 0.0);
  ck_assert_double_eq(n[1], 0.0);
  ck_assert_double_gt(n[2], 0.0);
}
END_TEST

/* A bipyramid over k ring points (radius 1, apexes at +-h) visited in steps of `step` k-ths of a
 * turn, plus `extra` free points after them; its faces, outward, into tris (2k of them). */
static void bipyramid(model_mesh_t *pts, uint32_t (*tris)[3], unsigned k, unsigned step, double h,
                      size_t extra) {
  points_alloc(pts, 2 + k + extra);
  const double apex[2][3] = {{0.0, 0.0, h}, {0.0, 0.0, -h}};
  memcpy(pts->vertices_m[0], apex[0], sizeof apex[0]);
  memcpy(pts->vertices_m[1], apex[1], sizeof apex[1]);
  for (unsigned i = 0; i < k; ++i) {
    const double a = 2.0 * CL_PI * (double)(i * step % k) / k;
    pts->vertices_m[2 + i][0] = cos(a);
    pts->vertices_m[2 + i][1] = sin(a);
    pts->vertices_m[2 + i][2] = 0.0;
    const uint32_t b = 2 + i, c = 2 + (i + 1) % k;
    memcpy(tris[2 * i], (uint32_t[3]){0, b, c}, sizeof tris[0]);
    memcpy(tris[2 * i + 1], (uint32_t[3]){1, c, b}, sizeof tris[0]);
  }
}

static void assert_verify(const model_mesh_t *pts, const uint32_t (*tris)[3], size_t nt,
                          const char *why) {
  model_error_t err;
  err.msg[0] = '\0';
  const model_status_t st = model_hull_verify_faces(pts, tris, nt, &err);
  if (why == NULL) {
    ck_assert_msg(st == MODEL_OK, "%s", err.msg);
  } else {
    ck_assert_int_eq(st, MODEL_E_HULL);
    ck_assert_msg(strstr(err.msg, why) != NULL, "'%s' does not say '%s'", err.msg, why);
  }
}

/* The checks on model_mesh_hull's result: the hull's own vertices are covered by the convexity of
 * the surface, so each way a surface can fail to be convex must be caught by one of them. */
START_TEST(test_hull_verify_catches) {
  model_mesh_t pts;
  uint32_t tris[16][3];
  bipyramid(&pts, tris, 4, 1, 1.0, 0); /* an octahedron */
  assert_verify(&pts, (const uint32_t(*)[3])tris, 8, NULL);
  /* the same faces wound inward */
  uint32_t inward[8][3];
  for (int t = 0; t < 8; ++t) {
    memcpy(inward[t], (uint32_t[3]){tris[t][0], tris[t][2], tris[t][1]}, sizeof inward[0]);
  }
  assert_verify(&pts, (const uint32_t(*)[3])inward, 8, "non-positive volume");
  /* an apex pushed through the ring: a dent */
  pts.vertices_m[0][2] = -0.2;
  assert_verify(&pts, (const uint32_t(*)[3])tris, 8, "a reflex edge");
  model_mesh_free(&pts);
  /* a point that is no vertex, inside and then outside (x + y + z = 1.2 > 1) */
  bipyramid(&pts, tris, 4, 1, 1.0, 1);
  for (int c = 0; c < 3; ++c) pts.vertices_m[6][c] = 0.1;
  assert_verify(&pts, (const uint32_t(*)[3])tris, 8, NULL);
  for (int c = 0; c < 3; ++c) pts.vertices_m[6][c] = 0.4;
  assert_verify(&pts, (const uint32_t(*)[3])tris, 8, "a point above a hull face");
  model_mesh_free(&pts);
  /* over a pentagram: every edge convex, but the surface goes twice around the axis */
  bipyramid(&pts, tris, 5, 2, 3.0, 0);
  assert_verify(&pts, (const uint32_t(*)[3])tris, 10, "do not go once around");
  model_mesh_free(&pts);
  /* two separate octahedra: every edge twinned and convex, positive volume, not one sphere */
  model_mesh_t two;
  bipyramid(&pts, tris, 4, 1, 1.0, 0);
  points_alloc(&two, 12);
  for (int i = 0; i < 12; ++i) {
    for (int c = 0; c < 3; ++c) {
      two.vertices_m[i][c] = pts.vertices_m[i % 6][c] + (i >= 6 && c == 0 ? 5.0 : 0.0);
    }
  }
  for (int t = 0; t < 8; ++t) {
    for (int c = 0; c < 3; ++c) tris[8 + t][c] = tris[t][c] + 6;
  }
  assert_verify(&two, (const uint32_t(*)[3])tris, 16, "one sphere");
  model_mesh_free(&two);
  model_mesh_free(&pts);
}
END_TEST

/* model_faces_find, _hull (the caller's hull) and _in (the hull kept in a work area) give the same
 * faces bit for bit; the work area builds its hull once per mesh. */
START_TEST(test_faces_find_variants) {
  model_mesh_t rock, hull;
  rock_load(1, &rock);
  hull_ok(&rock, &hull);
  model_mass_t mass;
  ck_assert_int_eq(model_mesh_mass(&rock, 1000.0, &mass), MODEL_OK);
  enum { CAP = 256 };
  model_face_t f0[CAP], f1[CAP], f2[CAP];
  size_t n0 = 0, n1 = 0, n2 = 0;
  memset(f0, 0, sizeof f0);
  memset(f1, 0, sizeof f1);
  memset(f2, 0, sizeof f2);
  ck_assert_int_eq(model_faces_find(&rock, mass.com_m, NULL, f0, CAP, &n0), MODEL_OK);
  ck_assert_int_eq(model_faces_find_hull(&rock, &hull, mass.com_m, NULL, f1, CAP, &n1), MODEL_OK);
  const size_t size = model_support_work_size(&rock);
  void *mem = malloc(size);
  ck_assert_ptr_nonnull(mem);
  model_support_work_t *work = model_support_work_init(mem, size, &rock);
  ck_assert_ptr_nonnull(work);
  ck_assert_int_eq(model_faces_find_in(&rock, mass.com_m, NULL, work, f2, CAP, &n2), MODEL_OK);
  ck_assert_uint_ge(n0, 4);
  ck_assert_uint_le(n0, CAP);
  ck_assert_uint_eq(n1, n0);
  ck_assert_uint_eq(n2, n0);
  ck_assert_int_eq(memcmp(f0, f1, n0 * sizeof f0[0]), 0);
  ck_assert_int_eq(memcmp(f0, f2, n0 * sizeof f0[0]), 0);
  /* the kept hull: model_mesh_hull's, bit for bit, and the same array on a second call */
  const model_mesh_t *kept = NULL, *again = NULL;
  ck_assert_int_eq(model_support_work_hull(work, &rock, &kept), MODEL_OK);
  ck_assert_uint_eq(kept->vertex_count, hull.vertex_count);
  ck_assert_uint_eq(kept->triangle_count, hull.triangle_count);
  ck_assert_int_eq(memcmp(kept->vertices_m, hull.vertices_m, hull.vertex_count * 24), 0);
  ck_assert_int_eq(memcmp(kept->triangles, hull.triangles, hull.triangle_count * 12), 0);
  ck_assert_int_eq(model_support_work_hull(work, &rock, &again), MODEL_OK);
  ck_assert_ptr_eq(again, kept);
  /* another mesh of the same counts: its own hull (here the rock moved by 1 m in x) */
  model_mesh_t moved;
  ck_assert_int_eq(model_mesh_copy(&rock, &moved), MODEL_OK);
  for (size_t i = 0; i < moved.vertex_count; ++i) moved.vertices_m[i][0] += 1.0;
  ck_assert_int_eq(model_support_work_hull(work, &moved, &again), MODEL_OK);
  ck_assert_double_eq(again->vertices_m[0][0], hull.vertices_m[0][0] + 1.0);
  /* wrong counts and NULLs */
  model_mesh_t small;
  mt_unit_cube(&small);
  ck_assert_int_eq(model_support_work_hull(work, &small, &again), MODEL_E_ARG);
  ck_assert_ptr_null(again);
  ck_assert_int_eq(model_faces_find_in(&small, mass.com_m, NULL, work, f2, CAP, &n2), MODEL_E_ARG);
  ck_assert_int_eq(model_faces_find_in(&rock, mass.com_m, NULL, NULL, f2, CAP, &n2), MODEL_E_ARG);
  ck_assert_int_eq(model_faces_find_hull(&rock, NULL, mass.com_m, NULL, f1, CAP, &n1), MODEL_E_ARG);
  model_mesh_free(&small);
  model_mesh_free(&moved);
  free(mem);
  model_mesh_free(&hull);
  model_mesh_free(&rock);
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

/* model_hull_edges: a 3 x 2 x 1 box's hull has 18 edges, of which its 12 box edges meet at right
 * angles (each once, ends ascending, both triangles' third vertices off the edge's line) and the
 * 6 face diagonals lie inside a face; an octahedron has 12 edges and no face diagonal. A short
 * array, an open mesh and a repeated vertex are refused. */
START_TEST(test_hull_edges_box) {
  model_mesh_t box = {0}, hull = {0};
  const double lo[3] = {-1.5, -1.0, -0.5}, hi[3] = {1.5, 1.0, 0.5};
  ck_assert_int_eq(model_mesh_box(lo, hi, &box), MODEL_OK);
  ck_assert_int_eq(model_mesh_hull(&box, &hull, NULL), MODEL_OK);
  model_hull_edge_t e[36];
  size_t n = 0;
  ck_assert_int_eq(model_hull_edges(&hull, cos(1e-3), e, 36, &n), MODEL_OK);
  ck_assert_uint_eq(n, 12);
  double total = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double *a = hull.vertices_m[e[i].v[0]], *b = hull.vertices_m[e[i].v[1]];
    ck_assert_uint_lt(e[i].v[0], e[i].v[1]);
    if (i > 0) ck_assert(e[i - 1].v[0] < e[i].v[0] || e[i - 1].v[1] < e[i].v[1]);
    int differ = 0; /* a box edge: its ends differ in one coordinate only */
    for (int k = 0; k < 3; ++k) differ += a[k] != b[k];
    ck_assert_int_eq(differ, 1);
    total += cl_vec3_dist(a, b);
    for (int j = 0; j < 2; ++j) { /* the two faces' normals: (v0, v1, o0) and (v1, v0, o1) */
      double n0[3], n1[3];
      cl_tri_normal(a, b, hull.vertices_m[e[i].opposite[0]], n0);
      cl_tri_normal(b, a, hull.vertices_m[e[i].opposite[1]], n1);
      ck_assert_double_eq_tol(cl_vec3_dot(n0, n1), 0.0, 1e-12);
      for (size_t v = 0; v < hull.vertex_count; ++v) { /* outward: the box behind both */
        double d[3];
        cl_vec3_sub(hull.vertices_m[v], a, d);
        ck_assert_double_le(cl_vec3_dot(d, j ? n1 : n0), 1e-12);
      }
    }
  }
  ck_assert_double_eq_tol(total, 4.0 * (3.0 + 2.0 + 1.0), 1e-12);
  /* every edge when nothing counts as coplanar */
  ck_assert_int_eq(model_hull_edges(&hull, 2.0, e, 36, &n), MODEL_OK);
  ck_assert_uint_eq(n, 18);
  ck_assert_int_eq(model_hull_edges(&hull, cos(1e-3), e, 35, &n), MODEL_E_ARG);
  ck_assert_int_eq(model_hull_edges(NULL, cos(1e-3), e, 36, &n), MODEL_E_ARG);
  ck_assert_int_eq(model_hull_edges(&hull, NAN, e, 36, &n), MODEL_E_ARG);
  /* one triangle fewer: an open mesh */
  --hull.triangle_count;
  ck_assert_int_eq(model_hull_edges(&hull, cos(1e-3), e, 36, &n), MODEL_E_OPEN);
  ++hull.triangle_count;
  hull.triangles[0][1] = hull.triangles[0][0];
  ck_assert_int_eq(model_hull_edges(&hull, cos(1e-3), e, 36, &n), MODEL_E_DEGENERATE);
  model_mesh_free(&hull);
  model_mesh_free(&box);
  /* an octahedron: 8 triangles, 12 edges at 109.5 degrees */
  double oct_v[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  uint32_t oct_t[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                          {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  const model_mesh_t oct = {
      .vertices_m = oct_v, .triangles = oct_t, .vertex_count = 6, .triangle_count = 8};
  ck_assert_int_eq(model_hull_edges(&oct, cos(1e-3), e, 24, &n), MODEL_OK);
  ck_assert_uint_eq(n, 12);
  for (size_t i = 0; i < n; ++i) { /* the opposite vertices are the other two on the equator */
    const double *a = oct_v[e[i].v[0]], *b = oct_v[e[i].v[1]];
    ck_assert_double_eq(cl_vec3_dot(a, b), 0.0);
    ck_assert_uint_ne(e[i].opposite[0], e[i].opposite[1]);
  }
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
  tcase_add_test(tc, test_hull_edges_box);
  tcase_add_test(tc, test_orient3d_exact);
  tcase_add_test(tc, test_hull_verify_catches);
  tcase_add_test(tc, test_faces_find_variants);
  suite_add_tcase(s, tc);
  TCase *scale = tcase_create("hull_scale"); /* 8 000 - 128 000 triangles, 60 002 points */
  tcase_set_timeout(scale, 240);
  tcase_add_test(scale, test_hull_subdivided_rocks);
  tcase_add_test(scale, test_hull_noisy_sphere);
  tcase_add_test(scale, test_hull_box_grid);
  tcase_add_test(scale, test_hull_random_clouds);
  suite_add_tcase(s, scale);
  return s;
}
