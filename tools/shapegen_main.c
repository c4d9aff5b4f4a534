/* comlearn-shapegen: write adversarial test objects (tools/shapegen.h) as URDF + binary STL. */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "comlearn/cli_args.h"
#include "comlearn/cli_log.h"

#include "objfile.h"
#include "shapegen.h"
#include "tool_args.h"

enum { COUNT_MAX = 100000 };

static int fail(const char *what, const char *path) {
  LOG_E("%s %s: %s", what, path, strerror(errno));
  return 1;
}

static int make_dir(const char *path) {
  return objfile_mkdir(path) == 0 ? 0 : fail("cannot create", path);
}

static int generate(const char *dir, int all, shapegen_family_t family, uint64_t seed,
                    uint64_t count) {
  char path[4096];
  snprintf(path, sizeof path, "%s", dir);
  if (make_dir(path)) return 1;
  snprintf(path, sizeof path, "%s/meshes", dir);
  if (make_dir(path)) return 1;
  const int progress = isatty(2);
  shapegen_object_t *o = malloc(sizeof *o);
  if (o == NULL) {
    LOG_E("out of memory");
    return 1;
  }
  int rc = 0;
  for (uint64_t i = 0; i < count && rc == 0; ++i) {
    const shapegen_family_t fam = all ? (shapegen_family_t)(i % SHAPEGEN_FAMILY_COUNT) : family;
    const uint64_t s = seed + i;
    if (progress) {
      fprintf(stderr, "\r[%llu/%llu] %s seed %llu ", (unsigned long long)(i + 1),
              (unsigned long long)count, shapegen_family_name(fam), (unsigned long long)s);
    }
    const model_status_t st = shapegen_generate(fam, s, o);
    if (st != MODEL_OK) {
      LOG_E("%s seed %llu: %s", shapegen_family_name(fam), (unsigned long long)s,
            model_status_str(st));
      rc = 1;
      break;
    }
    char path_failed[4096];
    rc = shapegen_write(o, dir, path_failed, sizeof path_failed) == 0
             ? 0
             : fail("cannot write", path_failed);
    if (rc == 0) {
      printf(
          "%s %s (%s): %zu triangles, %.3f cm^3, even %.4f kg, uneven %.4f kg, "
          "uneven CoM %.3f mm from uniform\n",
          shapegen_family_name(fam), o->spec.name, o->spec.variant, o->mesh.triangle_count,
          1e6 * o->even.mass_kg / o->spec.density_kg_m3, o->even.mass_kg, o->uneven.mass_kg,
          1e3 * o->shift_m);
      fflush(stdout);
    }
    shapegen_object_free(o);
  }
  if (progress) fprintf(stderr, "\n");
  free(o);
  return rc != 0 || fflush(stdout) != 0 ? 1 : 0;
}

static void usage(FILE *f) {
  fprintf(
      f,
      "usage: comlearn-shapegen --family NAME|all --seed S [--count N] --out-dir DIR\n"
      "Writes adversarial test objects (docs/assets.md, \"Adversarial shapes\"),\n"
      "deterministically: for each object DIR/NAME_even.urdf, DIR/NAME_uneven.urdf and\n"
      "DIR/meshes/NAME.stl, NAME = <family>_s<seed>, and one line per object on stdout.\n"
      "Object i (i = 0 .. N-1) has seed S+i; with --family all its family is the (i mod %d)-th\n"
      "of the list below, so N objects cover every family evenly.\n"
      "  --family NAME   required (default: none); all, or one of\n"
      "                 ",
      SHAPEGEN_FAMILY_COUNT);
  for (unsigned i = 0; i < SHAPEGEN_FAMILY_COUNT; ++i) {
    fprintf(f, " %s", shapegen_family_name((shapegen_family_t)i));
  }
  fprintf(f,
          "\n"
          "  --seed S        required (default: none); first seed, 0 .. 2^64-1, decimal or 0x hex\n"
          "  --count N       number of objects, 1 .. %d (default: 1)\n"
          "  --out-dir DIR   required (default: none); folder to write, created if missing;\n"
          "                  --out is the same\n"
          "  -h, --help      this text\n"
          "  -V, --version   print the version\n"
          "Exit status: 0 success, 1 runtime failure, 2 usage.\n",
          COUNT_MAX);
}

int main(int argc, char **argv) {
  cli_log_init("comlearn-shapegen");
  static const struct option opts[] = {
      {"family", required_argument, NULL, 'f'}, {"seed", required_argument, NULL, 's'},
      {"count", required_argument, NULL, 'n'},  {"out-dir", required_argument, NULL, 'o'},
      {"out", required_argument, NULL, 'o'},    {"help", no_argument, NULL, 'h'},
      {"version", no_argument, NULL, 'V'},      {NULL, 0, NULL, 0}};
  const char *out_dir = NULL;
  int have_family = 0, have_seed = 0, all = 0, c;
  shapegen_family_t family = SHAPEGEN_BOX;
  uint64_t seed = 0, count = 1;
  opterr = 0;
  while ((c = getopt_long(argc, argv, "hV", opts, NULL)) != -1) {
    switch (c) {
      case 'f':
        all = strcmp(optarg, "all") == 0;
        if (!all && shapegen_family_parse(optarg, &family) != 0) {
          LOG_E("--family: unknown family: %s", optarg);
          return 2;
        }
        have_family = 1;
        break;
      case 's':
        if (tool_parse_u64(optarg, &seed) != 0) {
          LOG_E("--seed: not a seed: %s", optarg);
          return 2;
        }
        have_seed = 1;
        break;
      case 'n':
        if (tool_parse_u64(optarg, &count) != 0 || count < 1 || count > COUNT_MAX) {
          LOG_E("--count: not in 1 .. %d: %s", COUNT_MAX, optarg);
          return 2;
        }
        break;
      case 'o': out_dir = optarg; break;
      case 'h': usage(stdout); return 0;
      case 'V': cli_version_print(stdout, "comlearn-shapegen"); return 0;
      default: cli_getopt_complain("comlearn-shapegen", "hV", opts, argv); return 2;
    }
  }
  if (optind != argc || !have_family || !have_seed || out_dir == NULL || out_dir[0] == '\0') {
    usage(stderr);
    return 2;
  }
  if (count - 1 > UINT64_MAX - seed) {
    LOG_E("--seed %llu --count %llu: seeds past 2^64-1", (unsigned long long)seed,
          (unsigned long long)count);
    return 2;
  }
  return generate(out_dir, all, family, seed, count);
}
