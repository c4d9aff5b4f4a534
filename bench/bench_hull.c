/* bench_hull: CPU time of lib/model's convex hull (model_mesh_hull) and of the resting faces on it
 * (model_faces_find_hull) on fine meshes, and the objects to time a whole estimate on (issue 13,
 * "Geometry at scale"; figures in docs/model.md, "Convex hull").
 *
 * Rows: the three bundled rocks (2 000 triangles) and their midpoint subdivisions 1x, 2x, 3x
 * (8 000 - 128 000 triangles; exact midpoints: the same solid, every edge midpoint of a hull facet
 * on the hull); rock_3's subdivisions with the midpoints rounded to float as an STL file holds
 * them; random rocks (tools/rockgen.h) at geodesic frequencies 32, 40 and 64 (20 480, 32 000 and
 * 81 920 triangles). Per row: triangles, vertices, the hull's vertices, the best CPU time of
 * --repeat hull builds and of one model_faces_find_hull on that hull, or the hull's error.
 *
 * --write DIR also writes the objects of kObjects as DIR/NAME.stl and DIR/NAME.urdf (uniform
 * 2650 kg/m^3, the inertial exact for the float mesh as stored): random rocks at frequencies 32,
 * 40, 64 (20 480, 32 000, 81 920 triangles; named rock_rSEED_fFREQ), random rock 1 at frequency
 * 35 subdivided once (rock_r1_f35_s1, 98 000) and rock_3 subdivided twice and three times
 * (rock_3_s2, rock_3_s3: 32 000, 128 000).
 *
 * Usage: bench_hull [--repeat N] [--write DIR] [--help]. Deterministic meshes; times are CPU
 * seconds of this process (CLOCK_PROCESS_CPUTIME_ID). */
#define _GNU_SOURCE

#include <errno.h>
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "comlearn/cli_args.h"
#include "comlearn/cli_log.h"
#include "comlearn/model.h"
#include "comlearn/model_support.h"
#include "mesh_subdivide.h"
#include "objfile.h"
#include "rockgen.h"

#define LOG_E(...) cli_log_msg(CLI_LOG_ERROR, __VA_ARGS__)

static double cpu_s(void) {
  struct timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* One table row: the hull of m, timed. */
static int row(const char *name, const model_mesh_t *m, int repeat) {
  double best = 1e300, faces_s = 0.0;
  model_mesh_t hull = {0};
  model_error_t err = {{0}};
  model_status_t st = MODEL_OK;
  for (int r = 0; r < repeat && st == MODEL_OK; ++r) {
    model_mesh_free(&hull);
    const double t0 = cpu_s();
    st = model_mesh_hull(m, &hull, &err);
    const double dt = cpu_s() - t0;
    if (dt < best) best = dt;
  }
  if (st != MODEL_OK) {
    printf("| %s | %zu | %zu | %s | | |\n", name, m->triangle_count, m->vertex_count, err.msg);
    return 0;
  }
  model_mass_t mass;
  size_t nf = 0;
  st = model_mesh_mass(m, 1.0, &mass);
  const double t0 = cpu_s();
  if (st == MODEL_OK) st = model_faces_find_hull(m, &hull, mass.com_m, NULL, NULL, 0, &nf);
  faces_s = cpu_s() - t0;
  printf("| %s | %zu | %zu | %zu | %.1f | %.1f (%zu faces) |\n", name, m->triangle_count,
         m->vertex_count, hull.vertex_count, 1e3 * best, 1e3 * faces_s, nf);
  model_mesh_free(&hull);
  return st == MODEL_OK ? 0 : -1;
}

static int rock_load(int r, model_mesh_t *m) {
  char path[512];
  snprintf(path, sizeof path, "%s/rocks/rock_%d_even.urdf", COMLEARN_ASSETS_DIR, r);
  model_object_t obj;
  model_error_t err;
  if (model_object_load(path, NULL, &obj, &err) != MODEL_OK) {
    LOG_E("%s", err.msg);
    return -1;
  }
  const int rc = model_mesh_copy(&obj.mesh, m) == MODEL_OK ? 0 : -1;
  model_object_free(&obj);
  return rc;
}

/* Random rock `seed` (its accepted spec) built at geodesic frequency f. */
static int random_rock(uint64_t seed, unsigned f, model_mesh_t *m) {
  rockgen_spec_t spec;
  if (rockgen_spec_random(seed, &spec) != MODEL_OK) return -1;
  spec.frequency = f;
  return rockgen_shape_build(&spec, m) == MODEL_OK ? 0 : -1;
}

/* m subdivided `levels` times (m itself for 0) into out. */
static int subdivided(const model_mesh_t *m, int levels, int round_f32, model_mesh_t *out) {
  if (model_mesh_copy(m, out) != MODEL_OK) return -1;
  for (int l = 0; l < levels; ++l) {
    model_mesh_t next;
    if (mesh_subdivide(out, &next, round_f32) != 0) return -1;
    model_mesh_free(out);
    *out = next;
  }
  return 0;
}

static int table(int repeat) {
  printf("| mesh | triangles | vertices | hull vertices | hull CPU ms | faces CPU ms |\n");
  printf("|---|---|---|---|---|---|\n");
  int rc = 0;
  for (int r = 1; r <= 3 && rc == 0; ++r) {
    model_mesh_t rock;
    if (rock_load(r, &rock) != 0) return -1;
    for (int round_f32 = 0; round_f32 <= (r == 3) && rc == 0; ++round_f32) {
      for (int l = round_f32; l <= 3 && rc == 0; ++l) {
        model_mesh_t m;
        char name[64];
        snprintf(name, sizeof name, "rock_%d%s%.0d%s", r, l ? " x" : "", l,
                 round_f32 ? " float midpoints" : "");
        rc = subdivided(&rock, l, round_f32, &m);
        if (rc == 0) rc = row(name, &m, repeat);
        model_mesh_free(&m);
      }
    }
    model_mesh_free(&rock);
  }
  /* random rocks: 20 480, 32 000 and 81 920 triangles (the old hull built r2, r4 and r7) */
  const struct {
    uint64_t seed;
    unsigned freq;
  } rr[] = {{1, 32}, {2, 32}, {3, 32}, {4, 40}, {5, 40}, {1, 64}, {7, 64}};
  for (size_t k = 0; k < sizeof rr / sizeof rr[0] && rc == 0; ++k) {
    model_mesh_t m;
    char name[64];
    snprintf(name, sizeof name, "rock_r%llu at frequency %u", (unsigned long long)rr[k].seed,
             rr[k].freq);
    rc = random_rock(rr[k].seed, rr[k].freq, &m);
    if (rc == 0) rc = row(name, &m, repeat);
    model_mesh_free(&m);
  }
  return rc;
}

/* DIR/name.stl and DIR/name.urdf for m. */
static int write_object(const char *dir, const char *name, const model_mesh_t *m) {
  char path[4096];
  snprintf(path, sizeof path, "%.2000s/%.200s.stl", dir, name);
  if (objfile_write_stl(m, path, "bench_hull object") != 0) {
    LOG_E("%s: %s", path, strerror(errno));
    return -1;
  }
  model_mesh_t stored; /* what a reader gets: float vertices, joined */
  model_mass_t mass;
  model_error_t err;
  if (model_mesh_load(path, NULL, &stored, NULL, &err) != MODEL_OK) {
    LOG_E("%s", err.msg);
    return -1;
  }
  const model_status_t st = model_mesh_mass(&stored, 2650.0, &mass);
  model_mesh_free(&stored);
  if (st != MODEL_OK) return -1;
  snprintf(path, sizeof path, "%.2000s/%.200s.urdf", dir, name);
  FILE *f = fopen(path, "w");
  if (f == NULL) {
    LOG_E("%s: %s", path, strerror(errno));
    return -1;
  }
  fprintf(f,
          "<?xml version=\"1.0\"?>\n<!-- Written by bench_hull: %zu triangles, 2650 kg/m^3. -->\n"
          "<robot name=\"%s\">\n  <link name=\"%s\">\n",
          m->triangle_count, name, name);
  objfile_put_inertial(f, &mass);
  char rel[256];
  snprintf(rel, sizeof rel, "%s.stl", name);
  objfile_put_mesh_geometry(f, rel, "rock", "0.55 0.51 0.46 1");
  fprintf(f, "  </link>\n</robot>\n");
  if (fclose(f) != 0) {
    LOG_E("%s: %s", path, strerror(errno));
    return -1;
  }
  printf("wrote %s (%zu triangles)\n", path, m->triangle_count);
  return 0;
}

/* The objects of --write: a bundled rock (rock > 0) or random rock `seed` at geodesic frequency
 * `freq`, subdivided `levels` times (exact midpoints, stored as float). */
typedef struct {
  const char *name;
  int rock;
  uint64_t seed;
  unsigned freq;
  int levels;
} object_t;

static const object_t kObjects[] = {
    {"rock_r1_f32", 0, 1, 32, 0},    /* 20 480 triangles; the old hull failed on it */
    {"rock_r2_f32", 0, 2, 32, 0},    /* 20 480; the old hull built it */
    {"rock_r4_f40", 0, 4, 40, 0},    /* 32 000; the old hull built it */
    {"rock_3_s2", 3, 0, 0, 2},       /* 32 000; the old hull failed */
    {"rock_r7_f64", 0, 7, 64, 0},    /* 81 920; the old hull built it */
    {"rock_r1_f35_s1", 0, 1, 35, 1}, /* 98 000 */
    {"rock_3_s3", 3, 0, 0, 3},       /* 128 000; the old hull failed */
};

static int write_all(const char *dir) {
  if (objfile_mkdir(dir) != 0) {
    LOG_E("%s: %s", dir, strerror(errno));
    return -1;
  }
  int rc = 0;
  for (size_t i = 0; i < sizeof kObjects / sizeof kObjects[0] && rc == 0; ++i) {
    const object_t *o = &kObjects[i];
    model_mesh_t base, m;
    rc = o->rock > 0 ? rock_load(o->rock, &base) : random_rock(o->seed, o->freq, &base);
    if (rc != 0) break;
    rc = subdivided(&base, o->levels, 0, &m);
    if (rc == 0) rc = write_object(dir, o->name, &m);
    model_mesh_free(&m);
    model_mesh_free(&base);
  }
  return rc;
}

static void usage(FILE *f) {
  fprintf(f,
          "usage: bench_hull [options]\n"
          "CPU time of model_mesh_hull and model_faces_find_hull on the bundled rocks subdivided\n"
          "up to 128 000 triangles and on random rocks of 20 480 - 81 920 triangles (markdown).\n"
          "  --repeat N   hull builds per row, the best one counts, 1..100 (default: 3)\n"
          "  --write DIR  also write seven objects of 20 480 - 128 000 triangles as\n"
          "               DIR/NAME.stl + DIR/NAME.urdf for `comlearn estimate` (default: none)\n"
          "  -h, --help   this text\n"
          "  -V, --version  print the version\n");
}

int main(int argc, char **argv) {
  cli_log_init("bench_hull");
  static const struct option opts[] = {{"repeat", required_argument, NULL, 'r'},
                                       {"write", required_argument, NULL, 'w'},
                                       {"help", no_argument, NULL, 'h'},
                                       {"version", no_argument, NULL, 'V'},
                                       {NULL, 0, NULL, 0}};
  int c, repeat = 3;
  const char *dir = NULL;
  opterr = 0;
  while ((c = getopt_long(argc, argv, "hV", opts, NULL)) != -1) {
    switch (c) {
      case 'r': {
        char *end = NULL;
        errno = 0;
        const long v = strtol(optarg, &end, 10);
        if (errno != 0 || end == optarg || *end != '\0' || v < 1 || v > 100) {
          usage(stderr);
          return 2;
        }
        repeat = (int)v;
        break;
      }
      case 'w': dir = optarg; break;
      case 'h': usage(stdout); return 0;
      case 'V': cli_version_print(stdout, "bench_hull"); return 0;
      default: cli_getopt_complain("bench_hull", "hV", opts, argv); return 2;
    }
  }
  if (optind != argc) {
    usage(stderr);
    return 2;
  }
  if (dir != NULL && write_all(dir) != 0) return 1;
  return table(repeat) == 0 ? 0 : 1;
}
