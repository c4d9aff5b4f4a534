/* model_urdf_tests.c - URDF geometry (comlearn_model) and inertial truth (comlearn_model_sim). */
#define _XOPEN_SOURCE 700 /* realpath */

#include <limits.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include "comlearn/math3d.h"
#include "comlearn/model_chain.h"
#include "comlearn/model_inertial.h"
#include "model_internal.h"
#include "model_suites.h"
#include "model_test_util.h"

#define HALF_PI "1.5707963267948966"
#define QUARTER_PI "0.78539816339744831"

/* ---- fixtures -------------------------------------------------------------------------------- */

/* An asymmetric tetrahedron (0,0,0), (1,0,0), (0,2,0), (0,0,3), outward. */
static void tetra(model_mesh_t *m) {
  static const double v[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {0, 0, 3}};
  static const uint32_t t[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  m->vertex_count = 4;
  m->triangle_count = 4;
  m->vertices_m = malloc(sizeof v);
  m->triangles = malloc(sizeof t);
  memcpy(m->vertices_m, v, sizeof v);
  memcpy(m->triangles, t, sizeof t);
}

static void save_tetra(const char *path) {
  model_mesh_t m;
  tetra(&m);
  model_error_t err;
  ck_assert_msg(model_mesh_save(&m, path, "stlb", &err) == MODEL_OK, "%s", err.msg);
  model_mesh_free(&m);
}

/* A one-link URDF whose <link> body is `body`. */
static void write_urdf(const char *path, const char *link, const char *body) {
  char text[4096];
  int n = snprintf(text, sizeof text,
                   "<?xml version=\"1.0\"?>\n<robot name=\"testbot\">\n  <link name=\"%s\">\n%s\n"
                   "  </link>\n</robot>\n",
                   link, body);
  ck_assert(n > 0 && (size_t)n < sizeof text);
  mt_write_text(path, text);
}

/* 1 when m has a vertex within tol of p. */
static int has_vertex(const model_mesh_t *m, double x, double y, double z, double tol) {
  for (size_t i = 0; i < m->vertex_count; ++i) {
    const double *v = m->vertices_m[i];
    if (fabs(v[0] - x) <= tol && fabs(v[1] - y) <= tol && fabs(v[2] - z) <= tol) {
      return 1;
    }
  }
  return 0;
}

static model_status_t print_something(const char *text) {
  fputs(text, stderr);
  return MODEL_OK;
}

static model_status_t load_object_quiet(const char *urdf) {
  model_object_t obj;
  model_status_t st = model_object_load(urdf, NULL, &obj, NULL);
  model_object_free(&obj);
  return st;
}

static model_status_t load_inertial_quiet(const char *urdf) {
  model_mass_t m;
  return model_inertial_load(urdf, NULL, &m, NULL);
}

/* ---- geometry -------------------------------------------------------------------------------- */

/* Mesh with scale and a full rpy origin. rpy (pi/2, 0, pi/2): R = Rz Ry Rx maps (x, y, z) to
 * (z, x, y). scale (2, 0.5, 0.25), xyz (0.1, 0.2, 0.3). */
START_TEST(test_urdf_mesh_scale_origin) {
  mt_tmpdir_t d;
  mt_tmpdir_make(&d);
  char urdf[512], mesh[512];
  mt_join(&d, "tetra.stl", mesh, sizeof mesh);
  mt_join(&d, "obj.urdf", urdf, sizeof urdf);
  save_tetra(mesh);
  write_urdf(urdf, "rock",
             "<collision><origin xyz=\"0.1 0.2 0.3\" rpy=\"" HALF_PI " 0 " HALF_PI
             "\"/>"
             "<geometry><mesh filename=\"tetra.stl\" scale=\"2 0.5 0.25\"/></geometry>"
             "</collision>");
  model_object_t obj;
  model_error_t err;
  ck_assert_msg(model_object_load(urdf, "rock", &obj, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_str_eq(obj.robot_name, "testbot");
  ck_assert_str_eq(obj.link_name, "rock");
  ck_assert_str_eq(obj.mesh_path + strlen(obj.mesh_path) - strlen("/tetra.stl"), "/tetra.stl");
  ck_assert_uint_eq(obj.mesh.vertex_count, 4);
  ck_assert_uint_eq(obj.mesh.triangle_count, 4);
  const double tol = 1e-12;
  ck_assert(has_vertex(&obj.mesh, 0.1, 0.2, 0.3, tol));  /* (0,0,0) */
  ck_assert(has_vertex(&obj.mesh, 0.1, 2.2, 0.3, tol));  /* (1,0,0) -> (2,0,0) -> (0,2,0) */
  ck_assert(has_vertex(&obj.mesh, 0.1, 0.2, 1.3, tol));  /* (0,2,0) -> (0,1,0) -> (0,0,1) */
  ck_assert(has_vertex(&obj.mesh, 0.85, 0.2, 0.3, tol)); /* (0,0,3) -> (0,0,.75) -> (.75,0,0) */
  ck_assert_double_eq_tol(obj.aabb.min_m[0], 0.1, tol);
  ck_assert_double_eq_tol(obj.aabb.max_m[0], 0.85, tol);
  ck_assert_double_eq_tol(obj.aabb.max_m[1], 2.2, tol);
  ck_assert_double_eq_tol(obj.aabb.max_m[2], 1.3, tol);
  /* volume 1 * 2 * 3 / 6 = 1, times |det scale| = 0.25 */
  ck_assert_double_eq_tol(mt_volume(&obj.mesh), 0.25, 1e-12);
  model_object_free(&obj);
  ck_assert_ptr_null(obj.mesh.vertices_m);
  model_object_free(NULL);
  const char *names[] = {"tetra.stl", "obj.urdf"};
  mt_tmpdir_remove(&d, names, 2);
}
END_TEST

/* Box, plus a second collision element (a mesh), merged into one mesh; and <visual> used only
 * when there is no <collision>. */
START_TEST(test_urdf_box_and_merge) {
  mt_tmpdir_t d;
  mt_tmpdir_make(&d);
  char urdf[512], mesh[512];
  mt_join(&d, "tetra.stl", mesh, sizeof mesh);
  mt_join(&d, "box.urdf", urdf, sizeof urdf);
  save_tetra(mesh);
  write_urdf(urdf, "block",
             "<collision><origin xyz=\"1 2 3\"/><geometry><box size=\"0.1 0.2 0.4\"/></geometry>"
             "</collision>");
  model_object_t obj;
  model_error_t err;
  ck_assert_msg(model_object_load(urdf, NULL, &obj, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_uint_eq(obj.mesh.vertex_count, 8);
  ck_assert_uint_eq(obj.mesh.triangle_count, 12);
  ck_assert_str_eq(obj.mesh_path, "");
  const double lo[3] = {0.95, 1.9, 2.8}, hi[3] = {1.05, 2.1, 3.2};
  for (int k = 0; k < 3; ++k) {
    ck_assert_double_eq_tol(obj.aabb.min_m[k], lo[k], 1e-15);
    ck_assert_double_eq_tol(obj.aabb.max_m[k], hi[k], 1e-15);
  }
  ck_assert_double_eq_tol(mt_volume(&obj.mesh), 0.008, 1e-15);
  model_object_free(&obj);

  /* Two collision elements and a visual that must be ignored. */
  write_urdf(urdf, "block",
             "<visual><geometry><box size=\"9 9 9\"/></geometry></visual>"
             "<collision><origin xyz=\"1 2 3\"/><geometry><box size=\"0.1 0.2 0.4\"/></geometry>"
             "</collision>"
             "<collision><origin xyz=\"-5 0 0\"/><geometry><mesh filename=\"tetra.stl\"/>"
             "</geometry></collision>");
  ck_assert_msg(model_object_load(urdf, NULL, &obj, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_uint_eq(obj.mesh.vertex_count, 12);
  ck_assert_uint_eq(obj.mesh.triangle_count, 16);
  ck_assert_double_eq_tol(mt_volume(&obj.mesh), 0.008 + 1.0, 1e-12);
  ck_assert_double_eq_tol(obj.aabb.min_m[0], -5.0, 1e-15);
  ck_assert_double_eq_tol(obj.aabb.max_m[2], 3.2, 1e-15);
  ck_assert_str_eq(obj.mesh_path + strlen(obj.mesh_path) - strlen("/tetra.stl"), "/tetra.stl");
  model_object_free(&obj);

  /* Visual only. */
  write_urdf(urdf, "block", "<visual><geometry><box size=\"1 2 4\"/></geometry></visual>");
  ck_assert_msg(model_object_load(urdf, NULL, &obj, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_double_eq_tol(mt_volume(&obj.mesh), 8.0, 1e-12);
  model_object_free(&obj);

  /* No geometry at all. */
  write_urdf(urdf, "block", "");
  ck_assert_int_eq(model_object_load(urdf, NULL, &obj, &err), MODEL_E_NOGEOM);
  ck_assert_ptr_nonnull(strstr(err.msg, "'block'"));
  ck_assert_ptr_nonnull(strstr(err.msg, urdf));

  /* Two boxes sharing an edge: the merged surface is non-manifold. */
  write_urdf(urdf, "block",
             "<collision><origin xyz=\"0.5 0.5 0.5\"/><geometry><box size=\"1 1 1\"/></geometry>"
             "</collision><collision><origin xyz=\"1.5 1.5 0.5\"/><geometry><box size=\"1 1 1\"/>"
             "</geometry></collision>");
  ck_assert_int_eq(model_object_load(urdf, NULL, &obj, &err), MODEL_E_OPEN);
  ck_assert_ptr_nonnull(strstr(err.msg, "merged geometry"));
  const char *names[] = {"tetra.stl", "box.urdf"};
  mt_tmpdir_remove(&d, names, 2);
}
END_TEST

/* Spheres and cylinders are tessellated (documented in model.h). */
START_TEST(test_urdf_sphere_cylinder) {
  mt_tmpdir_t d;
  mt_tmpdir_make(&d);
  char urdf[512];
  mt_join(&d, "prims.urdf", urdf, sizeof urdf);
  write_urdf(urdf, "ball",
             "<collision><origin xyz=\"0 0 1\"/><geometry><sphere radius=\"0.1\"/></geometry>"
             "</collision>");
  model_object_t obj;
  model_error_t err;
  const double pi = CL_PI;
  ck_assert_msg(model_object_load(urdf, NULL, &obj, &err) == MODEL_OK, "%s", err.msg);
  for (int k = 0; k < 3; ++k) {
    ck_assert_double_eq_tol(obj.aabb.min_m[k], (k == 2 ? 1.0 : 0.0) - 0.1, 1e-12);
    ck_assert_double_eq_tol(obj.aabb.max_m[k], (k == 2 ? 1.0 : 0.0) + 0.1, 1e-12);
  }
  double v = mt_volume(&obj.mesh), ball = 4.0 / 3.0 * pi * 0.001;
  ck_assert_double_lt(v, ball);
  ck_assert_double_eq_tol(v / ball, 0.98404110477, 1e-9); /* inscribed 16 x 32 UV sphere */
  model_object_free(&obj);

  /* Cylinder along its z, turned by roll pi/2 onto -y: extents 0.05, 0.1, 0.05. The prism of
   * 64 sides has volume 32 r^2 sin(2 pi / 64) L exactly. */
  write_urdf(urdf, "can",
             "<collision><origin rpy=\"" HALF_PI
             " 0 0\"/><geometry><cylinder radius=\"0.05\" "
             "length=\"0.2\"/></geometry></collision>");
  ck_assert_msg(model_object_load(urdf, NULL, &obj, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_double_eq_tol(obj.aabb.max_m[0], 0.05, 1e-12);
  ck_assert_double_eq_tol(obj.aabb.max_m[1], 0.1, 1e-12);
  ck_assert_double_eq_tol(obj.aabb.min_m[1], -0.1, 1e-12);
  ck_assert_double_eq_tol(obj.aabb.max_m[2], 0.05, 1e-12);
  double prism = 32.0 * 0.05 * 0.05 * sin(2.0 * pi / 64.0) * 0.2;
  ck_assert_double_eq_tol(mt_volume(&obj.mesh), prism, 1e-12 * prism);
  model_object_free(&obj);
  const char *names[] = {"prims.urdf"};
  mt_tmpdir_remove(&d, names, 1);
}
END_TEST

/* ---- mesh file names: package://NAME/REST, relative, absolute, file:// ------------------------
 */

/* A scratch tree of packages (docs/model.md, "URDF objects"):
 *   ws/mypkg       package.xml <name>mypkg</name> (after a comment naming another), urdf/obj.urdf,
 *                  urdf/here.stl, meshes/t.stl, meshes/out.stl -> ws/other/meshes/o.stl (symlink)
 *   ws/other       package.xml <name>other_pkg</name> (the folder's name is not the package's)
 *   rpp/a/b/third  package.xml <name>third</name>, meshes/th.stl (two levels below the entry)
 *   rpp/a/skip     CATKIN_IGNORE, and skip/ign holding package.xml <name>ign</name>
 *   rpp/.hid       package.xml <name>hid</name> (hidden: not crawled)
 *   dup1/dup, dup2/dup  package.xml <name>dup</name>, meshes/d.stl of 1 and of 2 tetrahedra */
static const char *const kPkgDirs[] = {"ws",
                                       "ws/mypkg",
                                       "ws/mypkg/urdf",
                                       "ws/mypkg/meshes",
                                       "ws/other",
                                       "ws/other/meshes",
                                       "rpp",
                                       "rpp/a",
                                       "rpp/a/b",
                                       "rpp/a/b/third",
                                       "rpp/a/b/third/meshes",
                                       "rpp/a/skip",
                                       "rpp/a/skip/ign",
                                       "rpp/.hid",
                                       "dup1",
                                       "dup1/dup",
                                       "dup1/dup/meshes",
                                       "dup2",
                                       "dup2/dup",
                                       "dup2/dup/meshes"};
static const char *const kPkgFiles[] = {
    "ws/mypkg/package.xml",     "ws/mypkg/meshes/t.stl",      "ws/mypkg/meshes/out.stl",
    "ws/mypkg/urdf/here.stl",   "ws/mypkg/urdf/obj.urdf",     "ws/other/package.xml",
    "ws/other/meshes/o.stl",    "rpp/a/b/third/package.xml",  "rpp/a/b/third/meshes/th.stl",
    "rpp/a/skip/CATKIN_IGNORE", "rpp/a/skip/ign/package.xml", "rpp/.hid/package.xml",
    "dup1/dup/package.xml",     "dup1/dup/meshes/d.stl",      "dup2/dup/package.xml",
    "dup2/dup/meshes/d.stl",    "ws/mypkg/meshes/pipe.stl"};
enum {
  PKG_DIRS = sizeof kPkgDirs / sizeof kPkgDirs[0],
  PKG_FILES = sizeof kPkgFiles / sizeof kPkgFiles[0]
};

static void package_xml(const mt_tmpdir_t *d, const char *where, const char *name) {
  char p[512], text[512];
  snprintf(
      text, sizeof text,
      "<?xml version=\"1.0\"?>\n<?xml-model href=\"x\"?>\n<!-- not this: <name>decoy</name> -->\n"
      "<package format=\"3\">\n  <name>\n    %s\n  </name>\n  <version>1.0.0</version>\n"
      "</package>\n",
      name);
  char rel[256];
  snprintf(rel, sizeof rel, "%s/package.xml", where);
  mt_write_text(mt_join(d, rel, p, sizeof p), text);
}

static void package_tree_make(mt_tmpdir_t *d) {
  mt_tmpdir_make(d);
  char p[512], q[512];
  for (size_t i = 0; i < PKG_DIRS; ++i) {
    ck_assert_int_eq(mkdir(mt_join(d, kPkgDirs[i], p, sizeof p), 0700), 0);
  }
  package_xml(d, "ws/mypkg", "mypkg");
  package_xml(d, "ws/other", "other_pkg");
  package_xml(d, "rpp/a/b/third", "third");
  package_xml(d, "rpp/a/skip/ign", "ign");
  package_xml(d, "rpp/.hid", "hid");
  package_xml(d, "dup1/dup", "dup");
  package_xml(d, "dup2/dup", "dup");
  mt_write_text(mt_join(d, "rpp/a/skip/CATKIN_IGNORE", p, sizeof p), "");
  save_tetra(mt_join(d, "ws/mypkg/meshes/t.stl", p, sizeof p));
  save_tetra(mt_join(d, "ws/other/meshes/o.stl", p, sizeof p));
  save_tetra(mt_join(d, "ws/mypkg/urdf/here.stl", p, sizeof p));
  save_tetra(mt_join(d, "rpp/a/b/third/meshes/th.stl", p, sizeof p));
  save_tetra(mt_join(d, "dup1/dup/meshes/d.stl", p, sizeof p));
  /* dup2's mesh: two tetrahedra apart, so which package was taken shows in the triangle count */
  model_mesh_t a, b, two;
  tetra(&a);
  tetra(&b);
  ck_assert_int_eq(model_mesh_alloc(&two, 8, 8), MODEL_OK);
  memcpy(two.vertices_m, a.vertices_m, 4 * sizeof a.vertices_m[0]);
  for (int i = 0; i < 4; ++i) {
    memcpy(two.vertices_m[4 + i], b.vertices_m[i], sizeof b.vertices_m[0]);
    two.vertices_m[4 + i][0] += 10.0;
    for (int k = 0; k < 3; ++k) {
      two.triangles[i][k] = a.triangles[i][k];
      two.triangles[4 + i][k] = b.triangles[i][k] + 4;
    }
  }
  model_error_t err;
  ck_assert_msg(model_mesh_save(&two, mt_join(d, "dup2/dup/meshes/d.stl", p, sizeof p), "stlb",
                                &err) == MODEL_OK,
                "%s", err.msg);
  model_mesh_free(&a);
  model_mesh_free(&b);
  model_mesh_free(&two);
  /* a named pipe with no writer: resolving must not open it (that would wait) */
  ck_assert_int_eq(mkfifo(mt_join(d, "ws/mypkg/meshes/pipe.stl", p, sizeof p), 0600), 0);
  ck_assert_int_eq(symlink(mt_join(d, "ws/other/meshes/o.stl", q, sizeof q),
                           mt_join(d, "ws/mypkg/meshes/out.stl", p, sizeof p)),
                   0);
}

static void package_tree_remove(mt_tmpdir_t *d) {
  const char *names[PKG_FILES + PKG_DIRS];
  for (size_t i = 0; i < PKG_FILES; ++i) names[i] = kPkgFiles[i];
  for (size_t i = 0; i < PKG_DIRS; ++i) names[PKG_FILES + i] = kPkgDirs[PKG_DIRS - 1 - i];
  mt_tmpdir_remove(d, names, PKG_FILES + PKG_DIRS);
}

/* ws/mypkg/urdf/obj.urdf with one collision mesh named uri; returns its path in urdf. */
static void package_urdf(const mt_tmpdir_t *d, const char *uri, char *urdf, size_t size) {
  char body[1024];
  snprintf(body, sizeof body, "<collision><geometry><mesh filename=\"%s\"/></geometry></collision>",
           uri);
  write_urdf(mt_join(d, "ws/mypkg/urdf/obj.urdf", urdf, size), "rock", body);
}

/* Load uri with model_object_load (dirs NULL) or model_object_load_within: the status, and on
 * success the tail of the resolved path and the triangle count. */
static model_status_t package_load(const mt_tmpdir_t *d, const char *uri, const char *const *dirs,
                                   size_t dir_count, const char *tail, size_t triangles,
                                   model_error_t *err) {
  char urdf[512];
  package_urdf(d, uri, urdf, sizeof urdf);
  model_object_t obj;
  model_status_t st = dirs == NULL
                          ? model_object_load(urdf, NULL, &obj, err)
                          : model_object_load_within(urdf, NULL, dirs, dir_count, &obj, err);
  if (st == MODEL_OK) {
    size_t len = strlen(obj.mesh_path), n = strlen(tail);
    ck_assert_msg(len >= n && strcmp(obj.mesh_path + len - n, tail) == 0, "%s -> %s (want %s)", uri,
                  obj.mesh_path, tail);
    ck_assert_uint_eq(obj.mesh.triangle_count, triangles);
    ck_assert_double_eq_tol(mt_volume(&obj.mesh), (double)triangles / 4.0, 1e-12);
    model_object_free(&obj);
  } else {
    ck_assert_ptr_null(obj.mesh.vertices_m);
  }
  return st;
}

/* Resolving: package://NAME from the URDF's folder up (by package.xml <name>, not folder name),
 * then ROS_PACKAGE_PATH (crawled, hidden and CATKIN_IGNORE folders skipped, first entry wins);
 * relative, absolute and file:// paths as before. */
START_TEST(test_urdf_package_and_relative_paths) {
  mt_tmpdir_t d;
  package_tree_make(&d);
  char abs_mesh[512], file_uri[600], rpp[2048], p[512], q[512], r[512];
  mt_join(&d, "ws/mypkg/meshes/t.stl", abs_mesh, sizeof abs_mesh);
  snprintf(file_uri, sizeof file_uri, "file://%s", abs_mesh);
  model_error_t err;
  ck_assert_int_eq(unsetenv("ROS_PACKAGE_PATH"), 0);
  const struct {
    const char *uri, *found;
  } cases[] = {
      {"package://mypkg/meshes/t.stl", "ws/mypkg/meshes/t.stl"},
      {"package://mypkg/./urdf/../meshes//t.stl", "ws/mypkg/meshes/t.stl"}, /* stays inside */
      {"package://mypkg/urdf/here.stl", "ws/mypkg/urdf/here.stl"},
      {"../meshes/t.stl", "ws/mypkg/meshes/t.stl"},
      {"here.stl", "ws/mypkg/urdf/here.stl"},
      {abs_mesh, "ws/mypkg/meshes/t.stl"},
      {file_uri, "ws/mypkg/meshes/t.stl"},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
    ck_assert_msg(package_load(&d, cases[i].uri, NULL, 0, cases[i].found, 4, &err) == MODEL_OK,
                  "%s: %s", cases[i].uri, err.msg);
  }
  /* a sibling package is not found by walking up, only through ROS_PACKAGE_PATH */
  ck_assert_int_eq(package_load(&d, "package://other_pkg/meshes/o.stl", NULL, 0, "", 0, &err),
                   MODEL_E_NOFILE);
  ck_assert_msg(strstr(err.msg, "unknown package 'other_pkg'") && strstr(err.msg, "'rock'"), "%s",
                err.msg);
  ck_assert_int_eq(package_load(&d, "package://other/meshes/o.stl", NULL, 0, "", 0, &err),
                   MODEL_E_NOFILE); /* the folder's name is not the package's */
  snprintf(rpp, sizeof rpp, ":%s:/nonexistent::%s:%s:%s", mt_join(&d, "ws", p, sizeof p),
           mt_join(&d, "rpp", q, sizeof q), mt_join(&d, "dup2", r, sizeof r), d.path);
  ck_assert_int_eq(setenv("ROS_PACKAGE_PATH", rpp, 1), 0);
  const struct {
    const char *uri, *found;
    size_t triangles;
  } env_cases[] = {
      {"package://other_pkg/meshes/o.stl", "ws/other/meshes/o.stl", 4},
      {"package://third/meshes/th.stl", "rpp/a/b/third/meshes/th.stl", 4}, /* two levels down */
      {"package://dup/meshes/d.stl", "dup2/dup/meshes/d.stl", 8},   /* dup2 is listed before d */
      {"package://mypkg/meshes/t.stl", "ws/mypkg/meshes/t.stl", 4}, /* the URDF's own first */
  };
  for (size_t i = 0; i < sizeof env_cases / sizeof env_cases[0]; ++i) {
    ck_assert_msg(package_load(&d, env_cases[i].uri, NULL, 0, env_cases[i].found,
                               env_cases[i].triangles, &err) == MODEL_OK,
                  "%s: %s", env_cases[i].uri, err.msg);
  }
  const char *skipped[] = {"package://ign/x.stl", "package://hid/x.stl"};
  for (size_t i = 0; i < 2; ++i) {
    ck_assert_int_eq(package_load(&d, skipped[i], NULL, 0, "", 0, &err), MODEL_E_NOFILE);
    ck_assert_msg(strstr(err.msg, "unknown package"), "%s", err.msg);
  }
  ck_assert_int_eq(unsetenv("ROS_PACKAGE_PATH"), 0);
  package_tree_remove(&d);
}
END_TEST

/* Hostile or broken mesh names: each refused with its reason, by model_object_load and by
 * model_object_load_within (what comlearn-sim calls), the same way. */
START_TEST(test_urdf_package_refused) {
  mt_tmpdir_t d;
  package_tree_make(&d);
  char real[PATH_MAX];
  ck_assert_ptr_nonnull(realpath(d.path, real));
  const char *all[] = {real};
  ck_assert_int_eq(unsetenv("ROS_PACKAGE_PATH"), 0);
  const struct {
    const char *uri;
    model_status_t status;
    const char *why;
  } bad[] = {
      {"package://nopkg/meshes/none.stl", MODEL_E_NOFILE, "unknown package 'nopkg'"},
      {"package://mypkg/meshes/none.stl", MODEL_E_NOFILE, "not found"},
      {"package://mypkg", MODEL_E_PARSE, "no path after the package name"},
      {"package://mypkg/", MODEL_E_PARSE, "no path after the package name"},
      {"package:///meshes/t.stl", MODEL_E_PARSE, "empty package name"},
      {"package://mypkg/../other/meshes/o.stl", MODEL_E_PARSE, "climbs out of the package root"},
      {"package://mypkg/meshes/../../../../etc/passwd", MODEL_E_PARSE, "climbs out"},
      {"package://mypkg/meshes/../..", MODEL_E_PARSE, "climbs out"},
      {"package://../ws/mypkg/meshes/t.stl", MODEL_E_PARSE, "not a ROS package name"},
      {"package://my.pkg/meshes/t.stl", MODEL_E_PARSE, "not a ROS package name"},
      {"package://my pkg/meshes/t.stl", MODEL_E_PARSE, "not a ROS package name"},
      {"model://mypkg/meshes/t.stl", MODEL_E_UNSUPPORTED, "scheme"},
      {"http://example.com/t.stl", MODEL_E_UNSUPPORTED, "scheme"},
      {"PACKAGE://mypkg/meshes/t.stl", MODEL_E_UNSUPPORTED, "scheme"},
      {"../meshes/none.stl", MODEL_E_NOFILE, "not found"},
      {"../meshes/pipe.stl", MODEL_E_NOFILE, "not a regular file"},
      {"package://mypkg/meshes/pipe.stl", MODEL_E_NOFILE, "not a regular file"},
      {"../meshes", MODEL_E_NOFILE, "not a regular file"},
  };
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
    for (int within = 0; within < 2; ++within) {
      model_error_t err;
      ck_assert_int_eq(package_load(&d, bad[i].uri, within ? all : NULL, 1, "", 0, &err),
                       bad[i].status);
      ck_assert_msg(strstr(err.msg, bad[i].uri) && strstr(err.msg, bad[i].why) &&
                        strstr(err.msg, "'rock'") && strstr(err.msg, "obj.urdf"),
                    "%s: %s", bad[i].uri, err.msg);
    }
  }
  package_tree_remove(&d);
}
END_TEST

/* comlearn-sim's --object-dir rule holds for package:// too: a package.xml outside the allowed
 * folders is not read (so its package is unknown), ROS_PACKAGE_PATH finds nothing outside them,
 * and a mesh reached through a symlink out of the package is refused as outside. */
START_TEST(test_urdf_package_within) {
  mt_tmpdir_t d;
  package_tree_make(&d);
  char pkg[PATH_MAX], urdf_dir[PATH_MAX], root[PATH_MAX], p[512];
  ck_assert_ptr_nonnull(realpath(mt_join(&d, "ws/mypkg", p, sizeof p), pkg));
  ck_assert_ptr_nonnull(realpath(mt_join(&d, "ws/mypkg/urdf", p, sizeof p), urdf_dir));
  ck_assert_ptr_nonnull(realpath(d.path, root));
  const char *in_pkg[] = {pkg}, *in_urdf[] = {urdf_dir}, *in_root[] = {root};
  model_error_t err;
  ck_assert_int_eq(unsetenv("ROS_PACKAGE_PATH"), 0);
  ck_assert_msg(package_load(&d, "package://mypkg/meshes/t.stl", in_pkg, 1, "ws/mypkg/meshes/t.stl",
                             4, &err) == MODEL_OK,
                "%s", err.msg);
  /* the URDF is inside, its package.xml one folder above is not: not read */
  ck_assert_int_eq(package_load(&d, "package://mypkg/urdf/here.stl", in_urdf, 1, "", 0, &err),
                   MODEL_E_NOFILE);
  ck_assert_msg(strstr(err.msg, "unknown package 'mypkg'") &&
                    strstr(err.msg, "inside the folders this program may read"),
                "%s", err.msg);
  ck_assert_msg(
      package_load(&d, "here.stl", in_urdf, 1, "ws/mypkg/urdf/here.stl", 4, &err) == MODEL_OK, "%s",
      err.msg);
  /* a symlink in the package to a mesh outside the folders */
  ck_assert_int_eq(package_load(&d, "package://mypkg/meshes/out.stl", in_pkg, 1, "", 0, &err),
                   MODEL_E_NOFILE);
  ck_assert_msg(strstr(err.msg, "outside the folders") && strstr(err.msg, "ws/other/meshes/o.stl"),
                "%s", err.msg);
  ck_assert_msg(package_load(&d, "package://mypkg/meshes/out.stl", in_root, 1,
                             "ws/other/meshes/o.stl", 4, &err) == MODEL_OK,
                "%s", err.msg);
  /* ROS_PACKAGE_PATH: the sibling package is found without folders, and not from inside mypkg */
  ck_assert_int_eq(setenv("ROS_PACKAGE_PATH", d.path, 1), 0);
  ck_assert_msg(package_load(&d, "package://other_pkg/meshes/o.stl", NULL, 0,
                             "ws/other/meshes/o.stl", 4, &err) == MODEL_OK,
                "%s", err.msg);
  ck_assert_int_eq(package_load(&d, "package://other_pkg/meshes/o.stl", in_pkg, 1, "", 0, &err),
                   MODEL_E_NOFILE);
  ck_assert_msg(strstr(err.msg, "unknown package 'other_pkg'"), "%s", err.msg);
  ck_assert_msg(package_load(&d, "package://other_pkg/meshes/o.stl", in_root, 1,
                             "ws/other/meshes/o.stl", 4, &err) == MODEL_OK,
                "%s", err.msg);
  ck_assert_int_eq(unsetenv("ROS_PACKAGE_PATH"), 0);
  package_tree_remove(&d);
}
END_TEST

/* The bundled rocks name their mesh as package://comlearn/rocks/meshes/NAME.stl and resolve in
 * the source tree through assets/package.xml; the same text in a folder outside the package
 * resolves through ROS_PACKAGE_PATH only, as for a ROS user's own URDF. */
START_TEST(test_urdf_package_bundled) {
  const char *urdf = COMLEARN_ASSETS_DIR "/rocks/rock_1_even.urdf";
  char want[PATH_MAX], text[8192];
  ck_assert_ptr_nonnull(realpath(COMLEARN_ASSETS_DIR "/rocks/meshes/rock_1.stl", want));
  FILE *f = fopen(urdf, "rb");
  ck_assert_ptr_nonnull(f);
  size_t n = fread(text, 1, sizeof text - 1, f);
  fclose(f);
  text[n] = '\0';
  ck_assert_ptr_nonnull(strstr(text, "filename=\"package://comlearn/rocks/meshes/rock_1.stl\""));
  ck_assert_ptr_null(strstr(text, "filename=\"meshes/"));
  ck_assert_int_eq(unsetenv("ROS_PACKAGE_PATH"), 0);
  model_object_t obj;
  model_error_t err;
  ck_assert_msg(model_object_load(urdf, NULL, &obj, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_str_eq(obj.mesh_path, want);
  ck_assert_uint_eq(obj.mesh.triangle_count, 2000);
  model_object_free(&obj);

  mt_tmpdir_t d;
  mt_tmpdir_make(&d);
  char copy[512], assets[PATH_MAX];
  mt_write_text(mt_join(&d, "rock.urdf", copy, sizeof copy), text);
  ck_assert_int_eq(model_object_load(copy, NULL, &obj, &err), MODEL_E_NOFILE);
  ck_assert_msg(strstr(err.msg, "unknown package 'comlearn'"), "%s", err.msg);
  ck_assert_ptr_nonnull(realpath(COMLEARN_ASSETS_DIR, assets));
  ck_assert_int_eq(setenv("ROS_PACKAGE_PATH", assets, 1), 0);
  ck_assert_msg(model_object_load(copy, NULL, &obj, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_str_eq(obj.mesh_path, want);
  model_object_free(&obj);
  ck_assert_int_eq(unsetenv("ROS_PACKAGE_PATH"), 0);
  const char *names[] = {"rock.urdf"};
  mt_tmpdir_remove(&d, names, 1);
}
END_TEST

/* package.xml <name>: comments and processing instructions skipped, white space trimmed. */
START_TEST(test_urdf_package_xml_name) {
  char name[16];
  const char *ok = "<?xml version=\"1.0\"?><!-- <name>no</name> --><package><name> a_b </name>";
  ck_assert_int_eq(model_package_xml_name(ok, strlen(ok), name, sizeof name), 0);
  ck_assert_str_eq(name, "a_b");
  const char *bad[] = {"<package/>", "<name></name>",       "<name>  </name>",
                       "<name>abc",  "<!-- <name>x</name>", "<name>0123456789abcdef</name>"};
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
    ck_assert_msg(model_package_xml_name(bad[i], strlen(bad[i]), name, sizeof name) == -1, "%s",
                  bad[i]);
  }
}
END_TEST

/* The YuMi's visual shapes (assets/yumi/README.md, "Visual geometry"): each arm link's shapes
 * reach from its joint to the next one (chain origins, model_chain_load), the fingers are the
 * reference's finger box, and no link carries mass (no <inertial>). The chain's kinematics are
 * checked against RobotStudio in check_placement. */
START_TEST(test_urdf_yumi_visuals) {
  const char *urdf = COMLEARN_ASSETS_DIR "/yumi/yumi.urdf";
  const char *arms[] = {"r", "l"};
  model_error_t err;
  for (int a = 0; a < 2; ++a) {
    char tip[64];
    snprintf(tip, sizeof tip, "yumi_tool0_%s", arms[a]);
    model_chain_t chain;
    ck_assert_msg(model_chain_load(urdf, "yumi_body", tip, &chain, &err) == MODEL_OK, "%s",
                  err.msg);
    ck_assert_uint_eq(chain.joint_count, 8);
    for (size_t j = 0; j + 1 < chain.joint_count; ++j) {
      model_object_t obj;
      const char *link = chain.joints[j].child_link;
      ck_assert_msg(model_object_load(urdf, link, &obj, &err) == MODEL_OK, "%s: %s", link, err.msg);
      const double *next = chain.joints[j + 1].origin_xyz_m;
      for (int k = 0; k < 3; ++k) {
        ck_assert_msg(obj.aabb.min_m[k] <= fmin(0.0, next[k]) - 0.02 + 1e-12 &&
                          obj.aabb.max_m[k] >= fmax(0.0, next[k]) + 0.02 - 1e-12,
                      "%s: axis %d [%g, %g] does not hold 0 and %g with 20 mm around", link, k,
                      obj.aabb.min_m[k], obj.aabb.max_m[k], next[k]);
        ck_assert_double_le(obj.aabb.max_m[k] - obj.aabb.min_m[k], 0.25);
      }
      model_object_free(&obj);
    }
    char finger[64];
    snprintf(finger, sizeof finger, "yumi_finger_b_%s", arms[a]);
    model_object_t obj;
    ck_assert_msg(model_object_load(urdf, finger, &obj, &err) == MODEL_OK, "%s", err.msg);
    const double lo[3] = {-0.01089, -0.0045, 0.0}, hi[3] = {0.0, 0.0167, 0.05218};
    for (int k = 0; k < 3; ++k) {
      ck_assert_double_eq_tol(obj.aabb.min_m[k], lo[k], 1e-12);
      ck_assert_double_eq_tol(obj.aabb.max_m[k], hi[k], 1e-12);
    }
    model_object_free(&obj);
  }
  model_object_t body;
  ck_assert_msg(model_object_load(urdf, NULL, &body, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_str_eq(body.link_name, "yumi_body");
  const double body_lo[3] = {-0.3607, -0.1997, -0.1}, body_hi[3] = {0.1349, 0.1997, 0.47085};
  for (int k = 0; k < 3; ++k) {
    ck_assert_double_eq_tol(body.aabb.min_m[k], body_lo[k], 1e-12);
    ck_assert_double_eq_tol(body.aabb.max_m[k], body_hi[k], 1e-12);
  }
  model_object_free(&body);
  const char *links[] = {"yumi_body", "yumi_link_1_r", "yumi_link_7_l", "yumi_tool0_r",
                         "yumi_finger_a_r"};
  for (size_t i = 0; i < sizeof links / sizeof links[0]; ++i) {
    model_mass_t m;
    ck_assert_int_eq(model_inertial_load(urdf, links[i], &m, &err), MODEL_E_INERTIAL);
  }
}
END_TEST

/* Root link by default, any link by name, a clear error for a missing one. */
START_TEST(test_urdf_links) {
  mt_tmpdir_t d;
  mt_tmpdir_make(&d);
  char urdf[512];
  mt_join(&d, "two.urdf", urdf, sizeof urdf);
  mt_write_text(urdf,
                "<robot name=\"pair\">"
                "<link name=\"rock\"><collision><geometry><box size=\"1 1 1\"/></geometry>"
                "</collision></link>"
                "<link name=\"base\"><collision><geometry><box size=\"2 2 2\"/></geometry>"
                "</collision></link>"
                "<joint name=\"j\" type=\"fixed\"><parent link=\"base\"/><child link=\"rock\"/>"
                "</joint></robot>");
  model_object_t obj;
  model_error_t err;
  ck_assert_msg(model_object_load(urdf, NULL, &obj, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_str_eq(obj.link_name, "base");
  ck_assert_str_eq(obj.robot_name, "pair");
  ck_assert_double_eq_tol(mt_volume(&obj.mesh), 8.0, 1e-12);
  model_object_free(&obj);
  ck_assert_int_eq(model_object_load(urdf, "rock", &obj, &err), MODEL_OK);
  ck_assert_str_eq(obj.link_name, "rock");
  ck_assert_double_eq_tol(mt_volume(&obj.mesh), 1.0, 1e-12);
  model_object_free(&obj);

  ck_assert_int_eq(model_object_load(urdf, "pebble", &obj, &err), MODEL_E_NOLINK);
  ck_assert_ptr_nonnull(strstr(err.msg, "'pebble'"));
  ck_assert_ptr_nonnull(strstr(err.msg, urdf));
  ck_assert_ptr_nonnull(strstr(err.msg, "base, rock"));
  ck_assert_ptr_null(obj.mesh.vertices_m);
  model_mass_t mass;
  ck_assert_int_eq(model_inertial_load(urdf, "pebble", &mass, &err), MODEL_E_NOLINK);
  ck_assert_ptr_nonnull(strstr(err.msg, "'pebble'"));
  ck_assert_ptr_nonnull(strstr(err.msg, urdf));
  const char *names[] = {"two.urdf"};
  mt_tmpdir_remove(&d, names, 1);
}
END_TEST

/* Broken files: missing, malformed XML, not a robot, elements urdfdom drops, broken meshes. None
 * of them prints anything. */
START_TEST(test_urdf_bad_files) {
  mt_tmpdir_t d;
  mt_tmpdir_make(&d);
  char urdf[512], capture[512], mesh[512];
  mt_join(&d, "bad.urdf", urdf, sizeof urdf);
  mt_join(&d, "capture.txt", capture, sizeof capture);
  mt_join(&d, "open.stl", mesh, sizeof mesh);
  model_object_t obj;
  model_mass_t mass;
  model_error_t err;
  model_status_t st;
  /* the capture itself works */
  ck_assert_int_eq(mt_printed_bytes(capture, print_something, "12345", &st), 5);

  char missing[512];
  mt_join(&d, "missing.urdf", missing, sizeof missing);
  ck_assert_int_eq(model_object_load(missing, NULL, &obj, &err), MODEL_E_NOFILE);
  ck_assert_ptr_nonnull(strstr(err.msg, missing));
  ck_assert_int_eq(model_inertial_load(missing, NULL, &mass, &err), MODEL_E_NOFILE);
  ck_assert_int_eq(model_object_load(NULL, NULL, &obj, &err), MODEL_E_ARG);
  ck_assert_int_eq(model_object_load(urdf, NULL, NULL, &err), MODEL_E_ARG);

  const struct {
    const char *text;
    const char *why; /* part of the message */
  } cases[] = {
      {"<robot name=\"r\"><link name=\"a\"><collision><geometry><box size=\"1 1 1\"/></geometry>"
       "</collision></link>",
       "not valid"}, /* unterminated XML */
      {"this is not XML at all", "not valid"},
      {"<?xml version=\"1.0\"?><building name=\"r\"/>", "not valid"}, /* no <robot> */
      {"<robot name=\"r\"><link name=\"a\"><collision><origin xyz=\"nan 0 0\"/><geometry>"
       "<box size=\"1 1 1\"/></geometry></collision></link></robot>",
       "nan"}, /* dropped */
      {"<robot name=\"r\"><link name=\"a\"><collision><geometry><box size=\"1 x 1\"/></geometry>"
       "</collision></link></robot>",
       "not valid"},
      {"<robot name=\"r\"><link name=\"a\"/><link name=\"a\"/></robot>", "not valid"},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
    mt_write_text(urdf, cases[i].text);
    ck_assert_int_eq(model_object_load(urdf, NULL, &obj, &err), MODEL_E_PARSE);
    ck_assert_msg(strstr(err.msg, urdf) != NULL && strstr(err.msg, cases[i].why) != NULL,
                  "case %zu: %s", i, err.msg);
    ck_assert_int_eq(model_inertial_load(urdf, NULL, &mass, &err), MODEL_E_PARSE);
    ck_assert_int_eq(mt_printed_bytes(capture, load_object_quiet, urdf, &st), 0);
    ck_assert_int_eq(st, MODEL_E_PARSE);
    ck_assert_int_eq(mt_printed_bytes(capture, load_inertial_quiet, urdf, &st), 0);
    ck_assert_int_eq(st, MODEL_E_PARSE);
  }

  /* A referenced mesh that is open: the message names the URDF, the link and the mesh. */
  model_mesh_t m;
  mt_unit_cube(&m);
  m.triangle_count = 11;
  ck_assert_int_eq(model_mesh_save(&m, mesh, "stlb", NULL), MODEL_OK);
  model_mesh_free(&m);
  write_urdf(urdf, "rock",
             "<collision><geometry><mesh filename=\"open.stl\"/></geometry></collision>");
  ck_assert_int_eq(model_object_load(urdf, NULL, &obj, &err), MODEL_E_OPEN);
  ck_assert_ptr_nonnull(strstr(err.msg, urdf));
  ck_assert_ptr_nonnull(strstr(err.msg, "'rock'"));
  ck_assert_ptr_nonnull(strstr(err.msg, mesh));
  /* Zero box. */
  write_urdf(urdf, "rock", "<collision><geometry><box size=\"1 0 1\"/></geometry></collision>");
  ck_assert_int_eq(model_object_load(urdf, NULL, &obj, &err), MODEL_E_DEGENERATE);
  ck_assert_ptr_nonnull(strstr(err.msg, "box size"));
  const char *names[] = {"bad.urdf", "capture.txt", "open.stl"};
  mt_tmpdir_remove(&d, names, 3);
}
END_TEST

/* URDFs that crash tinyxml or urdfdom, or that are no files (docs/security.md): 60 000 nested
 * elements overflow tinyxml's stack, a chain of 200 000 fixed joints urdfdom's; both are refused
 * by the shape check before either parser runs (here with 100 levels and 1 001 joints, over the
 * limits), as are a pipe, /dev/zero and a file over MODEL_URDF_MAX_BYTES; by both loaders (the
 * geometry and the inertial). A '>' inside an attribute value and a comment do not count. */
/* model_object_load_within: the URDF and every mesh it names inside the folders, each checked
 * before it is opened (the second mesh here lies in another folder: refused, naming it); a
 * folder holds a path only at a '/' ("/a/b" does not hold "/a/bc"); no folders, no limit. */
START_TEST(test_urdf_load_within) {
  mt_tmpdir_t in, out;
  mt_tmpdir_make(&in);
  mt_tmpdir_make(&out);
  char urdf[512], mesh_in[512], mesh_out[512], geo[1400];
  mt_join(&in, "tetra.stl", mesh_in, sizeof mesh_in);
  mt_join(&out, "tetra.stl", mesh_out, sizeof mesh_out);
  mt_join(&in, "two.urdf", urdf, sizeof urdf);
  save_tetra(mesh_in);
  save_tetra(mesh_out);
  snprintf(geo, sizeof geo,
           "<collision><geometry><mesh filename=\"%s\"/></geometry></collision><collision>"
           "<origin xyz=\"1 0 0\"/><geometry><mesh filename=\"%s\"/></geometry></collision>",
           mesh_in, mesh_out);
  write_urdf(urdf, "two", geo);
  char real_in[PATH_MAX], real_out[PATH_MAX];
  ck_assert_ptr_nonnull(realpath(in.path, real_in));
  ck_assert_ptr_nonnull(realpath(out.path, real_out));
  const char *only_in[] = {real_in}, *both[] = {real_in, real_out}, *only_out[] = {real_out};
  model_object_t obj;
  model_error_t err;
  ck_assert_int_eq(model_object_load_within(urdf, NULL, only_in, 1, &obj, &err), MODEL_E_NOFILE);
  ck_assert_msg(strstr(err.msg, "outside the folders") && strstr(err.msg, "tetra.stl") &&
                    strstr(err.msg, real_out),
                "%s", err.msg);
  ck_assert_int_eq(model_object_load_within(urdf, NULL, only_out, 1, &obj, &err), MODEL_E_NOFILE);
  ck_assert_msg(strstr(err.msg, "URDF") && strstr(err.msg, "outside the folders"), "%s", err.msg);
  ck_assert_msg(model_object_load_within(urdf, NULL, both, 2, &obj, &err) == MODEL_OK, "%s",
                err.msg);
  ck_assert_uint_eq(obj.mesh.triangle_count, 8);
  model_object_free(&obj);
  ck_assert_msg(model_object_load_within(urdf, NULL, NULL, 0, &obj, &err) == MODEL_OK, "%s",
                err.msg);
  model_object_free(&obj);
  ck_assert_int_eq(model_object_load_within(urdf, NULL, NULL, 1, &obj, &err), MODEL_E_ARG);
  const char *ab[] = {"/a/b"}, *ab_slash[] = {"/a/b/"};
  ck_assert_int_eq(model_path_within("/a/b/c.stl", ab, 1), 1);
  ck_assert_int_eq(model_path_within("/a/bc/c.stl", ab, 1), 0);
  ck_assert_int_eq(model_path_within("/a/b", ab, 1), 0);
  ck_assert_int_eq(model_path_within("/a/b/c.stl", ab_slash, 1), 1);
  ck_assert_int_eq(model_path_within("/x.stl", NULL, 0), 1);
  const char *names[] = {"tetra.stl", "two.urdf"};
  mt_tmpdir_remove(&in, names, 2);
  mt_tmpdir_remove(&out, names, 1);
}
END_TEST

START_TEST(test_urdf_hostile_files) {
  mt_tmpdir_t d;
  mt_tmpdir_make(&d);
  char urdf[512];
  mt_join(&d, "hostile.urdf", urdf, sizeof urdf);
  model_object_t obj;
  model_mass_t mass;
  model_error_t err;
  const size_t cap = 200000;
  char *text = malloc(cap);
  ck_assert_ptr_nonnull(text);

  size_t n = (size_t)snprintf(text, cap, "<robot name=\"r\"><link name=\"a\">");
  for (int i = 0; i < 100; ++i) n += (size_t)snprintf(text + n, cap - n, "<x>");
  for (int i = 0; i < 100; ++i) n += (size_t)snprintf(text + n, cap - n, "</x>");
  snprintf(text + n, cap - n, "</link></robot>");
  mt_write_text(urdf, text);
  ck_assert_int_eq(model_object_load(urdf, NULL, &obj, &err), MODEL_E_PARSE);
  ck_assert_msg(strstr(err.msg, "nested deeper") && strstr(err.msg, urdf), "%s", err.msg);
  ck_assert_int_eq(model_inertial_load(urdf, NULL, &mass, &err), MODEL_E_PARSE);
  ck_assert_ptr_nonnull(strstr(err.msg, "nested deeper"));

  n = (size_t)snprintf(text, cap, "<robot name=\"r\"><link name=\"l0\"/>");
  for (int i = 1; i <= 1001; ++i)
    n += (size_t)snprintf(text + n, cap - n,
                          "<link name=\"l%d\"/><joint name=\"j%d\" type=\"fixed\"><parent "
                          "link=\"l%d\"/><child link=\"l%d\"/></joint>",
                          i, i, i - 1, i);
  snprintf(text + n, cap - n, "</robot>");
  mt_write_text(urdf, text);
  ck_assert_int_eq(model_object_load(urdf, NULL, &obj, &err), MODEL_E_PARSE);
  ck_assert_msg(strstr(err.msg, "links or joints") != NULL, "%s", err.msg);

  /* joints that close a loop, or a link with two parents: refused before urdfdom, which would
   * leak the loop of shared pointers (the fuzzer's find) */
  const char *const bad_trees[][2] = {
      {"<joint name=\"j1\" type=\"fixed\"><parent link=\"a\"/><child link=\"b\"/></joint>"
       "<joint name=\"j2\" type=\"fixed\"><parent link=\"b\"/><child link=\"a\"/></joint>",
       "loop through link"},
      {"<link name=\"r\"/><joint name=\"j0\" type=\"fixed\"><parent link=\"r\"/><child "
       "link=\"a\"/></joint><joint name=\"j1\" type=\"fixed\"><parent link=\"a\"/><child "
       "link=\"b\"/></joint><joint name=\"j2\" type=\"fixed\"><parent link=\"b\"/><child "
       "link=\"a\"/></joint>",
       "child of two joints"},
      {"<joint name=\"j1\" type=\"fixed\"><parent link=\"b\"/><child link=\"b\"/></joint>",
       "loop through link 'b'"},
  };
  for (size_t i = 0; i < sizeof bad_trees / sizeof bad_trees[0]; ++i) {
    snprintf(text, cap,
             "<robot name=\"r\"><link name=\"a\"><collision><geometry><box size=\"1 1 1\"/>"
             "</geometry></collision></link><link name=\"b\"/>%s</robot>",
             bad_trees[i][0]);
    mt_write_text(urdf, text);
    ck_assert_int_eq(model_object_load(urdf, "a", &obj, &err), MODEL_E_PARSE);
    ck_assert_msg(strstr(err.msg, bad_trees[i][1]) && strstr(err.msg, urdf), "%zu: %s", i, err.msg);
    ck_assert_int_eq(model_inertial_load(urdf, "a", &mass, &err), MODEL_E_PARSE);
    ck_assert_msg(strstr(err.msg, bad_trees[i][1]) != NULL, "%zu: %s", i, err.msg);
  }
  /* the same links as a tree: loads */
  snprintf(text, cap,
           "<robot name=\"r\"><link name=\"a\"><collision><geometry><box size=\"1 1 1\"/>"
           "</geometry></collision></link><link name=\"b\"/><joint name=\"j1\" "
           "type=\"fixed\"><parent link=\"a\"/><child link=\"b\"/></joint></robot>");
  mt_write_text(urdf, text);
  ck_assert_msg(model_object_load(urdf, "a", &obj, &err) == MODEL_OK, "%s", err.msg);
  model_object_free(&obj);

  /* within the limits, with '>' in a value and a comment: loads */
  write_urdf(urdf, "rock",
             "<!-- a <comment> --><collision name=\"a>b\"><geometry><box size=\"1 1 1\"/>"
             "</geometry></collision>");
  ck_assert_int_eq(model_object_load(urdf, NULL, &obj, &err), MODEL_OK);
  model_object_free(&obj);

  char fifo[512];
  mt_join(&d, "pipe.urdf", fifo, sizeof fifo);
  ck_assert_int_eq(mkfifo(fifo, 0600), 0);
  ck_assert_int_eq(model_object_load(fifo, NULL, &obj, &err), MODEL_E_NOFILE);
  ck_assert_msg(strstr(err.msg, "not a regular file") != NULL, "%s", err.msg);
  ck_assert_int_eq(model_inertial_load("/dev/zero", NULL, &mass, &err), MODEL_E_NOFILE);
  FILE *f = fopen(urdf, "wb");
  ck_assert_ptr_nonnull(f);
  ck_assert_int_eq(ftruncate(fileno(f), (off_t)MODEL_URDF_MAX_BYTES + 1), 0);
  fclose(f);
  ck_assert_int_eq(model_object_load(urdf, NULL, &obj, &err), MODEL_E_PARSE);
  ck_assert_msg(strstr(err.msg, "limit") != NULL, "%s", err.msg);
  free(text);
  const char *names[] = {"hostile.urdf", "pipe.urdf"};
  mt_tmpdir_remove(&d, names, 2);
}
END_TEST

/* ---- inertial -------------------------------------------------------------------------------- */

static void write_inertial(const char *path, const char *origin, const char *mass,
                           const char *inertia) {
  char body[1024];
  snprintf(body, sizeof body,
           "<inertial>%s<mass value=\"%s\"/><inertia %s/></inertial>"
           "<collision><geometry><box size=\"1 1 1\"/></geometry></collision>",
           origin, mass, inertia);
  write_urdf(path, "rock", body);
}

static void assert_tensor(double got[3][3], const double want[3][3], double tol) {
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      ck_assert_msg(fabs(got[i][j] - want[i][j]) <= tol, "I[%d][%d] = %.17g, want %.17g", i, j,
                    got[i][j], want[i][j]);
    }
  }
}

START_TEST(test_inertial_rotated_origin) {
  mt_tmpdir_t d;
  mt_tmpdir_make(&d);
  char urdf[512];
  mt_join(&d, "in.urdf", urdf, sizeof urdf);
  model_mass_t m;
  model_error_t err;

  /* yaw pi/4 of diag(1, 2, 2.5): xx = yy = (1 + 2) / 2, xy = (1 - 2) / 2. */
  write_inertial(urdf, "<origin xyz=\"0.01 -0.02 0.03\" rpy=\"0 0 " QUARTER_PI "\"/>", "2.5",
                 "ixx=\"1\" iyy=\"2\" izz=\"2.5\" ixy=\"0\" ixz=\"0\" iyz=\"0\"");
  ck_assert_msg(model_inertial_load(urdf, NULL, &m, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_double_eq(m.mass_kg, 2.5);
  ck_assert_double_eq_tol(m.com_m[0], 0.01, 1e-15);
  ck_assert_double_eq_tol(m.com_m[1], -0.02, 1e-15);
  ck_assert_double_eq_tol(m.com_m[2], 0.03, 1e-15);
  const double want1[3][3] = {{1.5, -0.5, 0}, {-0.5, 1.5, 0}, {0, 0, 2.5}};
  assert_tensor(m.inertia_kg_m2, want1, 1e-14);

  /* rpy (pi/2, 0, pi/2): R (x, y, z) = (z, x, y), so I_link[i][j] = I[p(i)][p(j)] with
   * p = (z, x, y): diag (izz, ixx, iyy) and the xy product moves to [1][2]. */
  write_inertial(urdf, "<origin rpy=\"" HALF_PI " 0 " HALF_PI "\"/>", "0.75",
                 "ixx=\"1\" iyy=\"2\" izz=\"2.5\" ixy=\"0.1\" ixz=\"0\" iyz=\"0\"");
  ck_assert_msg(model_inertial_load(urdf, "rock", &m, &err) == MODEL_OK, "%s", err.msg);
  const double want2[3][3] = {{2.5, 0, 0}, {0, 1, 0.1}, {0, 0.1, 2}};
  assert_tensor(m.inertia_kg_m2, want2, 1e-14);
  ck_assert_double_eq(m.inertia_kg_m2[1][2], m.inertia_kg_m2[2][1]);
  ck_assert_double_eq(m.com_m[0], 0.0);

  /* No rotation: the tensor as written. */
  write_inertial(urdf, "", "1",
                 "ixx=\"1\" iyy=\"1.5\" izz=\"2\" ixy=\"0.1\" ixz=\"-0.2\" "
                 "iyz=\"0.05\"");
  ck_assert_msg(model_inertial_load(urdf, NULL, &m, &err) == MODEL_OK, "%s", err.msg);
  const double want3[3][3] = {{1, 0.1, -0.2}, {0.1, 1.5, 0.05}, {-0.2, 0.05, 2}};
  assert_tensor(m.inertia_kg_m2, want3, 0.0);
  const char *names[] = {"in.urdf"};
  mt_tmpdir_remove(&d, names, 1);
}
END_TEST

START_TEST(test_inertial_invalid) {
  mt_tmpdir_t d;
  mt_tmpdir_make(&d);
  char urdf[512];
  mt_join(&d, "in.urdf", urdf, sizeof urdf);
  model_mass_t m;
  model_error_t err;
  const char *ok = "ixx=\"1\" iyy=\"1\" izz=\"1\" ixy=\"0\" ixz=\"0\" iyz=\"0\"";
  const struct {
    const char *mass;
    const char *inertia;
    model_status_t status;
    const char *why;
  } cases[] = {
      {"0", "ixx=\"1\" iyy=\"1\" izz=\"1\" ixy=\"0\" ixz=\"0\" iyz=\"0\"", MODEL_E_INERTIAL,
       "not positive"},
      {"-1", "ixx=\"1\" iyy=\"1\" izz=\"1\" ixy=\"0\" ixz=\"0\" iyz=\"0\"", MODEL_E_INERTIAL,
       "not positive"},
      {"1", "ixx=\"1\" iyy=\"1\" izz=\"3\" ixy=\"0\" ixz=\"0\" iyz=\"0\"", MODEL_E_INERTIA_TRIANGLE,
       "triangle"},
      {"1", "ixx=\"-1\" iyy=\"1\" izz=\"1\" ixy=\"0\" ixz=\"0\" iyz=\"0\"", MODEL_E_INERTIAL,
       "positive definite"},
      {"1", "ixx=\"0\" iyy=\"0\" izz=\"0\" ixy=\"0\" ixz=\"0\" iyz=\"0\"", MODEL_E_INERTIAL,
       "positive definite"},
      {"1", "ixx=\"1\" iyy=\"1\" izz=\"1\" ixy=\"2\" ixz=\"0\" iyz=\"0\"", MODEL_E_INERTIAL,
       "positive definite"},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
    write_inertial(urdf, "", cases[i].mass, cases[i].inertia);
    ck_assert_int_eq(model_inertial_load(urdf, NULL, &m, &err), cases[i].status);
    ck_assert_msg(strstr(err.msg, cases[i].why) != NULL && strstr(err.msg, urdf) != NULL &&
                      strstr(err.msg, "'rock'") != NULL,
                  "case %zu: %s", i, err.msg);
    ck_assert_double_eq(m.mass_kg, 0.0); /* zeroed on error */
  }
  /* Unparseable numbers: urdfdom drops the element; we reject the file. */
  write_inertial(urdf, "", "nan", ok);
  ck_assert_int_eq(model_inertial_load(urdf, NULL, &m, &err), MODEL_E_PARSE);
  ck_assert_ptr_nonnull(strstr(err.msg, "nan"));
  write_inertial(urdf, "", "1e999", ok);
  ck_assert_int_eq(model_inertial_load(urdf, NULL, &m, &err), MODEL_E_PARSE);
  /* No <inertial> at all. */
  write_urdf(urdf, "rock", "<collision><geometry><box size=\"1 1 1\"/></geometry></collision>");
  ck_assert_int_eq(model_inertial_load(urdf, NULL, &m, &err), MODEL_E_INERTIAL);
  ck_assert_ptr_nonnull(strstr(err.msg, "no <inertial>"));
  ck_assert_int_eq(model_inertial_load(urdf, NULL, NULL, &err), MODEL_E_ARG);
  const char *names[] = {"in.urdf"};
  mt_tmpdir_remove(&d, names, 1);
}
END_TEST

static model_mass_t valid_mass(void) {
  model_mass_t m = {.mass_kg = 0.3,
                    .com_m = {0.01, 0.02, -0.03},
                    .inertia_kg_m2 = {{2e-4, 1e-5, 0}, {1e-5, 3e-4, -2e-5}, {0, -2e-5, 4e-4}}};
  return m;
}

START_TEST(test_mass_check) {
  model_error_t err;
  model_mass_t m = valid_mass();
  ck_assert_int_eq(model_mass_check(&m, &err), MODEL_OK);
  ck_assert_int_eq(model_mass_check(NULL, &err), MODEL_E_ARG);

  /* Triangle inequality: equality (a flat plate, 1 + 2 = 3) is physical, beyond is not. */
  model_mass_t t = {.mass_kg = 1.0, .inertia_kg_m2 = {{1, 0, 0}, {0, 2, 0}, {0, 0, 3}}};
  ck_assert_int_eq(model_mass_check(&t, &err), MODEL_OK);
  t.inertia_kg_m2[2][2] = 3.001;
  ck_assert_int_eq(model_mass_check(&t, &err), MODEL_E_INERTIA_TRIANGLE);
  ck_assert_ptr_nonnull(strstr(err.msg, "triangle inequality"));

  m = valid_mass();
  m.mass_kg = 0.0;
  ck_assert_int_eq(model_mass_check(&m, &err), MODEL_E_INERTIAL);
  m.mass_kg = -0.3;
  ck_assert_int_eq(model_mass_check(&m, &err), MODEL_E_INERTIAL);
  m.mass_kg = NAN;
  ck_assert_int_eq(model_mass_check(&m, &err), MODEL_E_INERTIAL);
  ck_assert_ptr_nonnull(strstr(err.msg, "not finite"));
  m = valid_mass();
  m.com_m[1] = INFINITY;
  ck_assert_int_eq(model_mass_check(&m, &err), MODEL_E_INERTIAL);
  m = valid_mass();
  m.inertia_kg_m2[2][1] = NAN;
  ck_assert_int_eq(model_mass_check(&m, &err), MODEL_E_INERTIAL);
  m = valid_mass();
  m.inertia_kg_m2[0][1] = 2e-5; /* [1][0] stays 1e-5 */
  ck_assert_int_eq(model_mass_check(&m, &err), MODEL_E_INERTIAL);
  ck_assert_ptr_nonnull(strstr(err.msg, "not symmetric"));
  m = valid_mass();
  m.inertia_kg_m2[0][0] = -2e-4;
  ck_assert_int_eq(model_mass_check(&m, &err), MODEL_E_INERTIAL);
  ck_assert_ptr_nonnull(strstr(err.msg, "positive definite"));
}
END_TEST

START_TEST(test_inertia_principal) {
  /* A = R diag(1, 2, 3) R^T with R = Rz(0.3) Ry(-0.7) Rx(1.1). */
  const double r = 1.1, p = -0.7, y = 0.3;
  const double R[3][3] = {{cos(y) * cos(p), cos(y) * sin(p) * sin(r) - sin(y) * cos(r),
                           cos(y) * sin(p) * cos(r) + sin(y) * sin(r)},
                          {sin(y) * cos(p), sin(y) * sin(p) * sin(r) + cos(y) * cos(r),
                           sin(y) * sin(p) * cos(r) - cos(y) * sin(r)},
                          {-sin(p), cos(p) * sin(r), cos(p) * cos(r)}};
  const double d[3] = {1.0, 2.0, 3.0};
  double A[3][3];
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      A[i][j] = 0.0;
      for (int k = 0; k < 3; ++k) {
        A[i][j] += R[i][k] * d[k] * R[j][k];
      }
    }
  }
  double mom[3], ax[3][3];
  ck_assert_int_eq(model_inertia_principal((const double(*)[3])A, mom, ax), MODEL_OK);
  for (int i = 0; i < 3; ++i) {
    ck_assert_double_eq_tol(mom[i], d[i], 1e-13);
    /* Each axis is +- the matching column of R, and A v = lambda v. */
    double dot = 0.0;
    for (int k = 0; k < 3; ++k) {
      dot += ax[k][i] * R[k][i];
      double av = A[k][0] * ax[0][i] + A[k][1] * ax[1][i] + A[k][2] * ax[2][i];
      ck_assert_double_eq_tol(av, mom[i] * ax[k][i], 1e-13);
    }
    ck_assert_double_eq_tol(fabs(dot), 1.0, 1e-13);
  }
  double det = ax[0][0] * (ax[1][1] * ax[2][2] - ax[1][2] * ax[2][1]) -
               ax[0][1] * (ax[1][0] * ax[2][2] - ax[1][2] * ax[2][0]) +
               ax[0][2] * (ax[1][0] * ax[2][1] - ax[1][1] * ax[2][0]);
  ck_assert_double_eq_tol(det, 1.0, 1e-13);

  /* Already diagonal, unsorted: sorted moments, permuted unit axes. */
  const double D[3][3] = {{3, 0, 0}, {0, 1, 0}, {0, 0, 2}};
  ck_assert_int_eq(model_inertia_principal(D, mom, ax), MODEL_OK);
  ck_assert_double_eq(mom[0], 1.0);
  ck_assert_double_eq(mom[1], 2.0);
  ck_assert_double_eq(mom[2], 3.0);
  ck_assert_double_eq(fabs(ax[1][0]), 1.0);
  ck_assert_double_eq(fabs(ax[2][1]), 1.0);
  ck_assert_double_eq(fabs(ax[0][2]), 1.0);

  A[1][2] = NAN;
  ck_assert_int_eq(model_inertia_principal((const double(*)[3])A, mom, ax), MODEL_E_INERTIAL);
  ck_assert_int_eq(model_inertia_principal(NULL, mom, ax), MODEL_E_ARG);
}
END_TEST

Suite *model_urdf_suite(void) {
  Suite *s = suite_create("model_urdf");
  TCase *geo = tcase_create("geometry");
  tcase_set_timeout(geo, 60);
  tcase_add_test(geo, test_urdf_mesh_scale_origin);
  tcase_add_test(geo, test_urdf_box_and_merge);
  tcase_add_test(geo, test_urdf_sphere_cylinder);
  tcase_add_test(geo, test_urdf_package_and_relative_paths);
  tcase_add_test(geo, test_urdf_package_refused);
  tcase_add_test(geo, test_urdf_package_within);
  tcase_add_test(geo, test_urdf_package_bundled);
  tcase_add_test(geo, test_urdf_package_xml_name);
  tcase_add_test(geo, test_urdf_yumi_visuals);
  tcase_add_test(geo, test_urdf_links);
  tcase_add_test(geo, test_urdf_bad_files);
  tcase_add_test(geo, test_urdf_hostile_files);
  tcase_add_test(geo, test_urdf_load_within);
  suite_add_tcase(s, geo);
  TCase *in = tcase_create("inertial");
  tcase_add_test(in, test_inertial_rotated_origin);
  tcase_add_test(in, test_inertial_invalid);
  tcase_add_test(in, test_mass_check);
  tcase_add_test(in, test_inertia_principal);
  suite_add_tcase(s, in);
  return s;
}
