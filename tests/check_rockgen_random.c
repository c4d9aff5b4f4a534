/* check_rockgen_random: random rocks (rockgen_spec_random, `comlearn-rockgen --random`) and the
 * stack picture (stack_svg_write, apps/comlearn/stack_svg.c, target comlearn_stack_svg, linked so
 * that the test does not need the rest of comlearn).
 *
 * Requirements (docs/assets.md, "Random rocks"): a seed names one rock, byte for byte; every spec
 * is drawn within the documented ranges; every accepted rock is a closed mesh whose largest planar
 * patch is the bottom face -z, on which it rests with both CoMs >= 5 mm inside; the uneven CoM
 * lies 2-7 mm from the uniform one (measured over seeds 1-300: 2.8-5.6 mm); the files load with
 * lib/model and their inertial equals the recomputation; bad arguments are refused. */
#define _POSIX_C_SOURCE 200809L
#include <check.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "comlearn/math3d.h"
#include "comlearn/model.h"
#include "comlearn/model_inertial.h"
#include "file_test_util.h"
#include "model_test_util.h"
#include "rockgen.h"
#include "stack_svg.h"

enum { PATCHES_MAX = 16, SEEDS = 60 };

static const double kMinPatchArea_m2 = 1e-4;
static const uint64_t kFirstSeed = 1000; /* the bench's default seed base */

/* Run comlearn-rockgen with argv (NULL-terminated), output discarded; its exit status or -1. */
static int run_rockgen(char *const argv[]) {
  fflush(stdout);
  fflush(stderr);
  const pid_t pid = fork();
  ck_assert_int_ge(pid, 0);
  if (pid == 0) {
    const int null = open("/dev/null", O_WRONLY);
    if (null >= 0) {
      dup2(null, 1);
      dup2(null, 2);
    }
    execv(COMLEARN_ROCKGEN, argv);
    _exit(127);
  }
  int ws = 0;
  ck_assert_int_eq(waitpid(pid, &ws, 0), pid);
  return WIFEXITED(ws) ? WEXITSTATUS(ws) : -1;
}

static int generate(const char *dir, const char *seed, const char *count) {
  char *argv[] = {(char *)"comlearn-rockgen",
                  (char *)"--random",
                  (char *)seed,
                  (char *)"--count",
                  (char *)count,
                  (char *)"--out-dir",
                  (char *)dir,
                  NULL};
  return run_rockgen(argv);
}

/* ---- the spec ----------------------------------------------------------------------------- */

START_TEST(spec_in_documented_ranges) {
  for (uint64_t seed = kFirstSeed; seed < kFirstSeed + SEEDS; ++seed) {
    rockgen_spec_t s;
    ck_assert_int_eq(rockgen_spec_random(seed, &s), MODEL_OK);
    char name[ROCKGEN_NAME_MAX];
    snprintf(name, sizeof name, "rock_r%llu", (unsigned long long)seed);
    ck_assert_str_eq(s.name, name);
    ck_assert_uint_eq(s.frequency, 10);
    ck_assert(s.semi_axes_m[0] >= 0.030 && s.semi_axes_m[0] <= 0.038);
    ck_assert(s.semi_axes_m[1] >= 0.026 && s.semi_axes_m[1] <= 0.031);
    ck_assert(s.semi_axes_m[2] >= 0.024 && s.semi_axes_m[2] <= 0.028);
    ck_assert_uint_eq(s.lobe_count, 6);
    ck_assert_uint_eq(s.bump_count, 26);
    ck_assert_uint_eq(s.fracture_count, 4);
    const rockgen_fracture_t *f = s.fractures;
    ck_assert(f[0].normal[0] == 0.0 && f[0].normal[1] == 0.0 && f[0].normal[2] == -1.0);
    ck_assert(f[0].depth_m >= 0.006 && f[0].depth_m <= 0.007);
    ck_assert(fabs(f[1].normal[0]) == 1.0 && f[1].normal[1] == 0.0 && f[1].normal[2] == 0.0);
    ck_assert(f[1].depth_m >= 0.0065 && f[1].depth_m <= 0.0075);
    for (int i = 2; i < 4; ++i) {
      ck_assert_double_eq_tol(cl_vec3_norm(f[i].normal), 1.0, 1e-12);
      ck_assert(f[i].normal[2] >= 0.4 && f[i].normal[2] <= 0.75);
      ck_assert(f[i].depth_m >= 0.003 && f[i].depth_m <= 0.0055);
    }
    ck_assert_double_eq(s.density_kg_m3, 2650.0);
    ck_assert_double_eq(s.region_density_kg_m3, 5200.0);
    ck_assert_double_eq_tol(cl_vec3_norm(s.region_normal), 1.0, 1e-12);
    ck_assert(s.region_offset_m >= 0.002 && s.region_offset_m <= 0.004);
  }
}
END_TEST

/* Same seed, same spec; different seeds, different specs; the documented redraw rule. */
START_TEST(spec_deterministic_and_rule) {
  rockgen_spec_t a, b;
  ck_assert_int_eq(rockgen_spec_random(7, &a), MODEL_OK);
  ck_assert_int_eq(rockgen_spec_random(7, &b), MODEL_OK);
  ck_assert_int_eq(memcmp(&a, &b, sizeof a), 0);
  ck_assert_int_eq(rockgen_spec_random(8, &b), MODEL_OK);
  ck_assert(a.seed != b.seed && a.semi_axes_m[0] != b.semi_axes_m[0]);
  /* Seed 0 and the largest seed are seeds like any other. */
  ck_assert_int_eq(rockgen_spec_random(0, &b), MODEL_OK);
  ck_assert_str_eq(b.name, "rock_r0");
  ck_assert_int_eq(rockgen_spec_random(UINT64_MAX, &b), MODEL_OK);
  ck_assert_str_eq(b.name, "rock_r18446744073709551615");

  /* rockgen_spec_random is the first accepted attempt, and some seeds need a redraw. */
  unsigned redrawn = 0;
  for (uint64_t seed = kFirstSeed; seed < kFirstSeed + SEEDS; ++seed) {
    unsigned k = 0;
    int ok = 0;
    rockgen_spec_t d;
    for (; k < ROCKGEN_RANDOM_MAX_ATTEMPTS; ++k) {
      ck_assert_int_eq(rockgen_spec_random_draw(seed, k, &d), MODEL_OK);
      ck_assert_int_eq(rockgen_random_accept(&d, &ok, NULL), MODEL_OK);
      if (ok) break;
    }
    ck_assert(ok);
    redrawn += k > 0;
    ck_assert_int_eq(rockgen_spec_random(seed, &a), MODEL_OK);
    ck_assert_int_eq(memcmp(&a, &d, sizeof a), 0);
  }
  /* ~19 % of seeds 1-300 need a redraw (the bottom face is not the largest). */
  ck_assert_uint_ge(redrawn, 1);
  ck_assert_uint_le(redrawn, SEEDS / 2);
}
END_TEST

START_TEST(bad_arguments_refused) {
  rockgen_spec_t s;
  int ok = 1;
  double margin = 0.0;
  ck_assert_int_eq(rockgen_spec_random(1, NULL), MODEL_E_ARG);
  ck_assert_int_eq(rockgen_spec_random_draw(1, 0, NULL), MODEL_E_ARG);
  ck_assert_int_eq(rockgen_random_accept(NULL, &ok, &margin), MODEL_E_ARG);
  ck_assert_int_eq(rockgen_spec_random_draw(1, 0, &s), MODEL_OK);
  ck_assert_int_eq(rockgen_random_accept(&s, NULL, &margin), MODEL_E_ARG);
  /* A spec the shape cannot take is "not accepted", not an error. */
  s.fractures[0].depth_m = 1.0;
  ck_assert_int_eq(rockgen_random_accept(&s, &ok, &margin), MODEL_OK);
  ck_assert_int_eq(ok, 0);
  ck_assert(isnan(margin));

  mt_tmpdir_t d;
  mt_tmpdir_make(&d);
  char *const cases[][9] = {
      {"g", "--random", "-1", "--out-dir", d.path, NULL},
      {"g", "--random", "12x", "--out-dir", d.path, NULL},
      {"g", "--random", "", "--out-dir", d.path, NULL},
      {"g", "--random", "18446744073709551616", "--out-dir", d.path, NULL},
      {"g", "--random", "18446744073709551615", "--count", "2", "--out-dir", d.path, NULL},
      {"g", "--random", "5", "--count", "0", "--out-dir", d.path, NULL},
      {"g", "--random", "5", "--count", "100001", "--out-dir", d.path, NULL},
      {"g", "--count", "2", "--out-dir", d.path, NULL},
      {"g", "--random", "5", NULL},
      {"g", "--random", "5", "--table", NULL},
      {"g", "--random", "5", "--out-dir", d.path, "extra", NULL},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
    ck_assert_msg(run_rockgen(cases[i]) == 2, "case %zu: %s %s", i, cases[i][1], cases[i][2]);
  }
  /* Nothing was written. */
  char p[512];
  struct stat st;
  ck_assert_int_ne(stat(mt_join(&d, "meshes", p, sizeof p), &st), 0);
  /* An output folder that cannot be created: runtime failure. */
  char *const unwritable[] = {"g", "--random", "5", "--out-dir", "/proc/comlearn/x", NULL};
  ck_assert_int_eq(run_rockgen(unwritable), 1);
  mt_tmpdir_remove(&d, NULL, 0);
}
END_TEST

/* ---- the meshes, from the library ---------------------------------------------------------- */

START_TEST(every_seed_rests_on_its_bottom_face) {
  double lo_shift = HUGE_VAL, hi_shift = 0.0, lo_margin = HUGE_VAL;
  for (uint64_t seed = kFirstSeed; seed < kFirstSeed + SEEDS; ++seed) {
    rockgen_spec_t s;
    model_mesh_t m;
    ck_assert_int_eq(rockgen_spec_random(seed, &s), MODEL_OK);
    ck_assert_int_eq(rockgen_shape_build(&s, &m), MODEL_OK);
    /* Closed, outward, nothing for model_mesh_check to repair; V = F/2 + 2. */
    model_mesh_t copy;
    model_mesh_report_t rep;
    model_error_t err = {{0}};
    ck_assert_int_eq(model_mesh_copy(&m, &copy), MODEL_OK);
    ck_assert_msg(model_mesh_check(&copy, &rep, &err) == MODEL_OK, "%s: %s", s.name, err.msg);
    ck_assert_uint_eq(rep.merged_vertices + rep.removed_degenerate + rep.removed_unreferenced, 0);
    ck_assert_int_eq(rep.flipped, 0);
    ck_assert_uint_eq(copy.vertex_count, m.vertex_count);
    ck_assert_uint_eq(m.vertex_count, m.triangle_count / 2 + 2);
    model_mesh_free(&copy);

    model_mass_t even, uneven;
    ck_assert_int_eq(rockgen_mass(&s, &m, &even, &uneven, NULL), MODEL_OK);
    rockgen_patch_t p[PATCHES_MAX];
    size_t count = 0;
    ck_assert_int_eq(rockgen_patches_find(&m, kMinPatchArea_m2, p, PATCHES_MAX, &count), MODEL_OK);
    ck_assert_uint_ge(count, 1);
    ck_assert_msg(p[0].normal[2] < -ROCKGEN_PLANE_COS, "%s: largest face (%.3f, %.3f, %.3f)",
                  s.name, p[0].normal[0], p[0].normal[1], p[0].normal[2]);
    ck_assert(p[0].width_m >= ROCKGEN_RANDOM_MIN_WIDTH_M);
    ck_assert(p[0].support_excess_m <= ROCKGEN_PLANE_TOL_M);
    const double me = rockgen_patch_margin(&p[0], even.com_m);
    const double mu = rockgen_patch_margin(&p[0], uneven.com_m);
    ck_assert_msg(me >= 0.005 && mu >= 0.005, "%s: margins %.4f %.4f m", s.name, me, mu);
    lo_margin = mu < lo_margin ? mu : lo_margin;
    /* Size and mass like the bundled rocks (a little wider: 35-100 mm, 0.1-0.6 kg). */
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (size_t v = 0; v < m.vertex_count; ++v) {
      for (int k = 0; k < 3; ++k) {
        lo[k] = m.vertices_m[v][k] < lo[k] ? m.vertices_m[v][k] : lo[k];
        hi[k] = m.vertices_m[v][k] > hi[k] ? m.vertices_m[v][k] : hi[k];
      }
    }
    for (int k = 0; k < 3; ++k) {
      ck_assert_msg(hi[k] - lo[k] >= 0.035 && hi[k] - lo[k] <= 0.10, "%s: extent %d %.4f m", s.name,
                    k, hi[k] - lo[k]);
      ck_assert_double_eq_tol(hi[k] + lo[k], 0.0, 1e-8); /* link origin: bounding-box center */
    }
    ck_assert(even.mass_kg >= 0.1 && uneven.mass_kg <= 0.6 && uneven.mass_kg > even.mass_kg);
    /* The dense layer moves the CoM a few mm (seeds 1-300: 2.8-5.6 mm). */
    const double shift = cl_vec3_dist(even.com_m, uneven.com_m);
    ck_assert_msg(shift >= 0.002 && shift <= 0.007, "%s: CoM shift %.4f m", s.name, shift);
    lo_shift = shift < lo_shift ? shift : lo_shift;
    hi_shift = shift > hi_shift ? shift : hi_shift;
    model_mesh_free(&m);
  }
  /* Not all alike: the shifts spread over at least 1 mm. */
  ck_assert_msg(hi_shift - lo_shift >= 0.001, "shifts %.4f-%.4f m", lo_shift, hi_shift);
  ck_assert(lo_margin >= 0.005);
}
END_TEST

/* ---- the files, from comlearn-rockgen ------------------------------------------------------ */

static const char *const kKinds[] = {"even", "uneven"};

START_TEST(files_deterministic_and_loadable) {
  mt_tmpdir_t a, b;
  mt_tmpdir_make(&a);
  mt_tmpdir_make(&b);
  ck_assert_int_eq(generate(a.path, "1000", "3"), 0);
  ck_assert_int_eq(generate(b.path, "1000", "3"), 0);
  char pa[512], pb[512], rel[128];
  for (int r = 0; r < 3; ++r) {
    const unsigned seed = 1000u + (unsigned)r;
    snprintf(rel, sizeof rel, "meshes/rock_r%u.stl", seed);
    ck_assert_msg(test_same_file(mt_join(&a, rel, pa, sizeof pa), mt_join(&b, rel, pb, sizeof pb)),
                  "%s differs between two runs", rel);
    for (int k = 0; k < 2; ++k) {
      snprintf(rel, sizeof rel, "rock_r%u_%s.urdf", seed, kKinds[k]);
      ck_assert_msg(
          test_same_file(mt_join(&a, rel, pa, sizeof pa), mt_join(&b, rel, pb, sizeof pb)),
          "%s differs between two runs", rel);
    }
  }
  /* Different seeds, different files. */
  ck_assert(!test_same_file(mt_join(&a, "meshes/rock_r1000.stl", pa, sizeof pa),
                            mt_join(&a, "meshes/rock_r1001.stl", pb, sizeof pb)));
  ck_assert(!test_same_file(mt_join(&a, "rock_r1000_uneven.urdf", pa, sizeof pa),
                            mt_join(&a, "rock_r1001_uneven.urdf", pb, sizeof pb)));
  /* A seed written alone equals the same seed written in a batch. */
  mt_tmpdir_t c;
  mt_tmpdir_make(&c);
  ck_assert_int_eq(generate(c.path, "1001", "1"), 0);
  ck_assert(test_same_file(mt_join(&a, "rock_r1001_uneven.urdf", pa, sizeof pa),
                           mt_join(&c, "rock_r1001_uneven.urdf", pb, sizeof pb)));

  /* The files load with lib/model; the mesh is the generated one and the inertial is exact. */
  for (int r = 0; r < 3; ++r) {
    const uint64_t seed = 1000u + (uint64_t)r;
    rockgen_spec_t s;
    model_mesh_t gen;
    model_mass_t even, uneven;
    ck_assert_int_eq(rockgen_spec_random(seed, &s), MODEL_OK);
    ck_assert_int_eq(rockgen_shape_build(&s, &gen), MODEL_OK);
    ck_assert_int_eq(rockgen_mass(&s, &gen, &even, &uneven, NULL), MODEL_OK);
    for (int k = 0; k < 2; ++k) {
      snprintf(rel, sizeof rel, "%s_%s.urdf", s.name, kKinds[k]);
      model_object_t obj;
      model_mass_t mass;
      model_error_t err = {{0}};
      mt_join(&a, rel, pa, sizeof pa);
      ck_assert_msg(model_object_load(pa, NULL, &obj, &err) == MODEL_OK, "%s", err.msg);
      ck_assert_msg(model_inertial_load(pa, NULL, &mass, &err) == MODEL_OK, "%s", err.msg);
      ck_assert_int_eq(model_mass_check(&mass, &err), MODEL_OK);
      ck_assert_uint_eq(obj.mesh.vertex_count, gen.vertex_count);
      ck_assert_uint_eq(obj.mesh.triangle_count, gen.triangle_count);
      const model_mass_t *want = k ? &uneven : &even;
      ck_assert_double_eq_tol(mass.mass_kg, want->mass_kg, 1e-9 * want->mass_kg);
      for (int j = 0; j < 3; ++j) ck_assert_double_eq_tol(mass.com_m[j], want->com_m[j], 1e-12);
      model_mass_t recomputed;
      ck_assert_int_eq(model_mesh_mass(&obj.mesh, s.density_kg_m3, &recomputed), MODEL_OK);
      ck_assert_double_eq_tol(recomputed.mass_kg, even.mass_kg, 1e-9 * even.mass_kg);
      model_object_free(&obj);
    }
    model_mesh_free(&gen);
  }
  const char *const names[] = {"meshes/rock_r1000.stl",  "meshes/rock_r1001.stl",
                               "meshes/rock_r1002.stl",  "rock_r1000_even.urdf",
                               "rock_r1000_uneven.urdf", "rock_r1001_even.urdf",
                               "rock_r1001_uneven.urdf", "rock_r1002_even.urdf",
                               "rock_r1002_uneven.urdf", "meshes"};
  mt_tmpdir_remove(&a, names, sizeof names / sizeof names[0]);
  mt_tmpdir_remove(&b, names, sizeof names / sizeof names[0]);
  const char *const one[] = {"meshes/rock_r1001.stl", "rock_r1001_even.urdf",
                             "rock_r1001_uneven.urdf", "meshes"};
  mt_tmpdir_remove(&c, one, sizeof one / sizeof one[0]);
}
END_TEST

/* ---- stack_svg_write ------------------------------------------------------------------------ */

static size_t count_substr(const char *hay, const char *needle) {
  size_t n = 0;
  for (const char *p = strstr(hay, needle); p != NULL; p = strstr(p + 1, needle)) ++n;
  return n;
}

/* Triangles facing the viewer (at -y) of a mesh at a pose: what the picture must draw. */
static size_t front_facing(const model_mesh_t *m, const model_pose_t *pose) {
  double rot[3][3];
  model_quat_to_rot(pose->orientation_wxyz, rot);
  size_t n = 0;
  for (size_t t = 0; t < m->triangle_count; ++t) {
    double w[3][3];
    for (int j = 0; j < 3; ++j) {
      const double *v = m->vertices_m[m->triangles[t][j]];
      for (int r = 0; r < 3; ++r) w[j][r] = rot[r][0] * v[0] + rot[r][1] * v[1] + rot[r][2] * v[2];
    }
    /* y of (b - a) x (c - a) */
    const double ny =
        (w[1][2] - w[0][2]) * (w[2][0] - w[0][0]) - (w[1][0] - w[0][0]) * (w[2][2] - w[0][2]);
    n += ny < 0.0;
  }
  return n;
}

/* The largest distance of a vertex of mesh above a face plane of hull, over every pair. */
static double worst_above(const model_mesh_t *mesh, const model_mesh_t *hull) {
  double worst = -HUGE_VAL;
  for (size_t t = 0; t < hull->triangle_count; ++t) {
    const double *a = hull->vertices_m[hull->triangles[t][0]];
    double n[3];
    if (!(cl_tri_normal(a, hull->vertices_m[hull->triangles[t][1]],
                        hull->vertices_m[hull->triangles[t][2]], n) > 0.0))
      return HUGE_VAL; /* a zero-area face: not a hull */
    for (size_t i = 0; i < mesh->vertex_count; ++i) {
      const double *v = mesh->vertices_m[i];
      worst = fmax(worst, n[0] * (v[0] - a[0]) + n[1] * (v[1] - a[1]) + n[2] * (v[2] - a[2]));
    }
  }
  return worst;
}

/* The quickhull failure that made some random rocks unusable: draw 0 of seed 1273 got MODEL_E_HULL
 * ("a point above a hull face": the depth-first walk over the faces the new point sees stopped at
 * faces it was within tolerance of, and left a sheet of two opposite faces through the middle),
 * so the rule took draw 1 for rock_r1273 while that lasted. With the exact walk its hull holds
 * every vertex (checked here independently) and draw 0 is the rock again, as before the hull
 * joined the rule. The same walk failed on 16 of these 27 finer rocks (6 480 - 32 000 triangles,
 * issue 13); each now builds, and the three smallest are checked independently too. */
START_TEST(hull_of_former_failures) {
  rockgen_spec_t d, spec;
  ck_assert_int_eq(rockgen_spec_random_draw(1273, 0, &d), MODEL_OK);
  model_mesh_t mesh, hull;
  ck_assert_int_eq(rockgen_shape_build(&d, &mesh), MODEL_OK);
  model_error_t err = {{0}};
  ck_assert_msg(model_mesh_hull(&mesh, &hull, &err) == MODEL_OK, "%s", err.msg);
  ck_assert_double_lt(worst_above(&mesh, &hull), 1e-11);
  model_mesh_free(&hull);
  model_mesh_free(&mesh);
  ck_assert_int_eq(rockgen_spec_random(1273, &spec), MODEL_OK);
  ck_assert_int_eq(memcmp(&spec, &d, sizeof d), 0); /* attempt 0 */
  for (uint64_t seed = 1; seed <= 27; ++seed) {
    ck_assert_int_eq(rockgen_spec_random(seed, &spec), MODEL_OK);
    spec.frequency = 18 + (unsigned)((seed - 1) * 22 / 26); /* 20 f^2: 6 480 - 32 000 */
    ck_assert_int_eq(rockgen_shape_build(&spec, &mesh), MODEL_OK);
    ck_assert_uint_eq(mesh.triangle_count, 20 * spec.frequency * spec.frequency);
    ck_assert_msg(model_mesh_hull(&mesh, &hull, &err) == MODEL_OK, "seed %llu: %s",
                  (unsigned long long)seed, err.msg);
    if (seed <= 3) ck_assert_double_lt(worst_above(&mesh, &hull), 1e-11);
    model_mesh_free(&hull);
    model_mesh_free(&mesh);
  }
}
END_TEST

START_TEST(stack_svg_side_view) {
  model_mesh_t m[3];
  const model_mesh_t *mp[3];
  model_pose_t pose[3];
  double com[3][3];
  double z = 0.0;
  size_t want = 0;
  for (int i = 0; i < 3; ++i) {
    rockgen_spec_t s;
    model_mass_t even;
    ck_assert_int_eq(rockgen_spec_random(kFirstSeed + (uint64_t)i, &s), MODEL_OK);
    ck_assert_int_eq(rockgen_shape_build(&s, &m[i]), MODEL_OK);
    ck_assert_int_eq(rockgen_mass(&s, &m[i], &even, NULL, NULL), MODEL_OK);
    mp[i] = &m[i];
    memcpy(com[i], even.com_m, sizeof com[i]);
    double lo = HUGE_VAL, hi = -HUGE_VAL;
    for (size_t v = 0; v < m[i].vertex_count; ++v) {
      lo = m[i].vertices_m[v][2] < lo ? m[i].vertices_m[v][2] : lo;
      hi = m[i].vertices_m[v][2] > hi ? m[i].vertices_m[v][2] : hi;
    }
    /* upright, stacked; the middle one turned 90 degrees about z */
    const double h = sqrt(0.5);
    const model_pose_t p = {{0.002 * i, 0.0, z - lo},
                            {i == 1 ? h : 1.0, 0.0, 0.0, i == 1 ? h : 0.0}};
    pose[i] = p;
    z += hi - lo;
    want += front_facing(&m[i], &pose[i]);
  }
  mt_tmpdir_t d;
  mt_tmpdir_make(&d);
  char path[512], tmp[600];
  mt_join(&d, "stack.svg", path, sizeof path);
  snprintf(tmp, sizeof tmp, "%s.tmp", path);
  ck_assert_int_eq(stack_svg_write(path, mp, pose, (const double(*)[3])com, 3, "A <&> \"B\""), 0);
  size_t size = 0;
  char *svg = test_slurp(path, &size);
  ck_assert_uint_lt(size, 400000);
  ck_assert_int_eq(strncmp(svg, "<?xml", 5), 0);
  ck_assert_ptr_nonnull(strstr(svg, "<svg xmlns=\"http://www.w3.org/2000/svg\""));
  ck_assert_int_eq(strcmp(svg + size - 7, "</svg>\n"), 0);
  ck_assert_ptr_nonnull(strstr(svg, "A &lt;&amp;&gt; &quot;B&quot;"));
  ck_assert_uint_eq(count_substr(svg, "<polygon"), want);
  ck_assert_uint_ge(want, 1500); /* about half of 3 x 2000 triangles face the viewer */
  /* A tint per object. */
  for (int i = 0; i < 3; ++i) {
    char cls[16];
    snprintf(cls, sizeof cls, "class=\"o%ds", i);
    ck_assert_uint_ge(count_substr(svg, cls), 300);
  }
  /* Three CoM crosses and the legend's: 4 x (white + red) paths; a scale bar in mm. */
  ck_assert_uint_eq(count_substr(svg, "stroke=\"#b3001b\""), 4);
  ck_assert_ptr_nonnull(strstr(svg, " mm</text>"));
  ck_assert_uint_eq(count_substr(svg, "<"), count_substr(svg, ">"));
  free(svg);
  struct stat st;
  ck_assert_int_ne(stat(tmp, &st), 0);

  /* No CoMs: no crosses. */
  ck_assert_int_eq(stack_svg_write(path, mp, pose, NULL, 3, NULL), 0);
  svg = test_slurp(path, &size);
  ck_assert_uint_eq(count_substr(svg, "stroke=\"#b3001b\""), 0);
  free(svg);

  /* Errors: EINVAL, and the previous file stays as it was. */
  ck_assert_int_eq(stack_svg_write(path, mp, pose, NULL, 3, "kept"), 0);
  char *before = test_slurp(path, &size);
  const size_t before_size = size;
  errno = 0;
  ck_assert_int_eq(stack_svg_write(NULL, mp, pose, NULL, 3, "t"), -1);
  ck_assert_int_eq(errno, EINVAL);
  errno = 0;
  ck_assert_int_eq(stack_svg_write(path, NULL, pose, NULL, 3, "t"), -1);
  ck_assert_int_eq(errno, EINVAL);
  errno = 0;
  ck_assert_int_eq(stack_svg_write(path, mp, NULL, NULL, 3, "t"), -1);
  ck_assert_int_eq(errno, EINVAL);
  errno = 0;
  ck_assert_int_eq(stack_svg_write(path, mp, pose, NULL, 0, "t"), -1);
  ck_assert_int_eq(errno, EINVAL);
  model_pose_t bad[3];
  memcpy(bad, pose, sizeof bad);
  bad[1].position_m[2] = NAN;
  errno = 0;
  ck_assert_int_eq(stack_svg_write(path, mp, bad, NULL, 3, "t"), -1);
  ck_assert_int_eq(errno, EINVAL);
  memcpy(bad, pose, sizeof bad);
  memset(bad[2].orientation_wxyz, 0, sizeof bad[2].orientation_wxyz);
  errno = 0;
  ck_assert_int_eq(stack_svg_write(path, mp, bad, NULL, 3, "t"), -1);
  ck_assert_int_eq(errno, EINVAL);
  double bad_com[3][3];
  memcpy(bad_com, com, sizeof bad_com);
  bad_com[0][1] = INFINITY;
  errno = 0;
  ck_assert_int_eq(stack_svg_write(path, mp, pose, (const double(*)[3])bad_com, 3, "t"), -1);
  ck_assert_int_eq(errno, EINVAL);
  const model_mesh_t *with_null[3] = {mp[0], NULL, mp[2]};
  errno = 0;
  ck_assert_int_eq(stack_svg_write(path, with_null, pose, NULL, 3, "t"), -1);
  ck_assert_int_eq(errno, EINVAL);
  char *after = test_slurp(path, &size);
  ck_assert_uint_eq(size, before_size);
  ck_assert_int_eq(memcmp(before, after, size), 0);
  free(before);
  free(after);
  /* A folder that does not exist: fopen's errno, nothing written. */
  char missing[600];
  snprintf(missing, sizeof missing, "%s/no/such/dir.svg", d.path);
  errno = 0;
  ck_assert_int_eq(stack_svg_write(missing, mp, pose, NULL, 3, "t"), -1);
  ck_assert_int_eq(errno, ENOENT);

  const char *const names[] = {"stack.svg"};
  mt_tmpdir_remove(&d, names, 1);
  for (int i = 0; i < 3; ++i) model_mesh_free(&m[i]);
}
END_TEST

static Suite *rockgen_random_suite(void) {
  Suite *s = suite_create("rockgen_random");
  TCase *spec = tcase_create("spec");
  tcase_set_timeout(spec, 120);
  tcase_add_test(spec, spec_in_documented_ranges);
  tcase_add_test(spec, spec_deterministic_and_rule);
  tcase_add_test(spec, bad_arguments_refused);
  tcase_add_test(spec, every_seed_rests_on_its_bottom_face);
  tcase_add_test(spec, files_deterministic_and_loadable);
  tcase_add_test(spec, hull_of_former_failures);
  suite_add_tcase(s, spec);
  TCase *svg = tcase_create("stack_svg");
  tcase_set_timeout(svg, 60);
  tcase_add_test(svg, stack_svg_side_view);
  suite_add_tcase(s, svg);
  return s;
}

int main(void) {
  SRunner *runner = srunner_create(rockgen_random_suite());
  srunner_run_all(runner, CK_NORMAL);
  const int failed = srunner_ntests_failed(runner);
  srunner_free(runner);
  return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
