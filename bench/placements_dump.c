/* placements_dump: edge placements of objects and lib/balance's verdict on each, as JSON lines,
 * for a second engine to replay (bench/mujoco_crosscheck.py; docs/physics.md, "Cross-check with
 * MuJoCo").
 *
 * For each URDF (mesh + <inertial> truth, e.g. from comlearn-shapegen or comlearn-rockgen): the
 * hull faces the true CoM rests on with a margin >= --min-margin (model_faces_find), each
 * confirmed by a trial in the middle of B (balance_stable_confirm), up to --faces of them, largest
 * margin first. Each face at --yaws yaws k * 360 / N degrees is a "line": the link point
 * com + d u (u: the link-frame direction of B's +X edge normal) is set over the +X edge with
 * balance_pose_over_edge (along 0, touching, 1 um pre-penetrated), as the estimator plans its
 * edge trials, so d > 0 puts the CoM d inside the edge. Offsets are kept where the estimator
 * searches: the point over the edge 1 mm inside the object's extent along u. Per line: the
 * threshold d between "does not stay" (TIPS, SLIDES, INVALID) and STAYS, bisected in
 * [-bracket, bracket] to --resolution (as bench_regimes), and the tip threshold (INVALID counted
 * with STAYS: between "tips or slides" and "does not"), then --uniform placements with d
 * uniform in [-range, range] (seeded) and 12 dense ones at the threshold +-1, 3, 10, 30, 100 and
 * 300 um. Every placement is one balance_trial_run (default config, fast contact path, no noise).
 *
 * Output (stdout), one JSON object a line:
 *   {"type": "config", ...}      balance_config_t and the options
 *   {"type": "object", ...}      urdf, mesh, name, mass, com, inertia (link frame), radius
 *   {"type": "line", ...}        object, face, normal, margin, yaw, orientation, u, threshold
 *   {"type": "placement", ...}   line, d, release pose, outcome, rotation, displacement, steps
 * Deterministic. Exit 0, 1 (an object could not be loaded or simulated), 2 (usage). */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "comlearn/balance.h"
#include "comlearn/balance_poses.h"
#include "comlearn/cli_args.h"
#include "comlearn/cli_json.h"
#include "comlearn/cli_log.h"
#include "comlearn/math3d.h"
#include "comlearn/model.h"
#include "comlearn/model_inertial.h"
#include "tool_args.h"

enum { FACE_CAP = 512, FACES_MAX = 16, YAWS_MAX = 64, UNIFORM_MAX = 1000, DENSE_N = 12 };

typedef struct {
  int faces, yaws, uniform, stock;
  double range_m, bracket_m, min_margin_m, resolution_m;
  uint64_t seed;
} dump_opts_t;

/* One object in its world, and the counters of the output. */
typedef struct {
  const dump_opts_t *opt;
  const char *urdf;
  model_object_t obj;
  model_mass_t truth;
  balance_world_t *w;
  balance_object_t *o;
  int object_id;
  int line_id;
  uint64_t rng;
} dump_ctx_t;

/* One line: the resting orientation (yawed), the test direction u and the face it rests on. */
typedef struct {
  const model_face_t *face;
  int face_index;
  double yaw_rad;
  double q[4];
  double u[3];
  double lo_m, hi_m; /* the feasible offsets: the point 1 mm inside the object's extent along u */
} dump_line_t;

static const char *outcome_str(balance_outcome_t o) {
  switch (o) {
    case BALANCE_STAYS: return "STAYS";
    case BALANCE_TIPS: return "TIPS";
    case BALANCE_SLIDES: return "SLIDES";
    default: return "INVALID";
  }
}

static void key_num(const char *key, double v) {
  printf(", \"%s\": ", key);
  cli_json_number(stdout, v);
}

static void key_arr(const char *key, const double *v, size_t n) {
  printf(", \"%s\": ", key);
  cli_json_array(stdout, v, n);
}

/* The release pose for offset d on line ln, and the trial run from it. */
static balance_status_t dump_trial(dump_ctx_t *c, const dump_line_t *ln, double d,
                                   model_pose_t *pose, balance_trial_result_t *r) {
  double p[3];
  for (int k = 0; k < 3; ++k) p[k] = c->truth.com_m[k] + d * ln->u[k];
  balance_status_t st =
      balance_pose_over_edge(c->w, c->o, ln->q, MODEL_EDGE_PX, p, 0.0, 1e-6, pose);
  if (st == BALANCE_OK) st = balance_trial_run(c->w, c->o, pose, NULL, r);
  return st;
}

/* 1 stays, 0 does not (tips, slides, invalid), -1 error. With stays_or_moving, INVALID (still
 * moving at the horizon, never tipped nor slid) counts as staying: the "does not tip" rule. */
static int dump_stays(dump_ctx_t *c, const dump_line_t *ln, double d, int stays_or_moving) {
  model_pose_t pose;
  balance_trial_result_t r;
  if (dump_trial(c, ln, d, &pose, &r) != BALANCE_OK) return -1;
  return r.outcome == BALANCE_STAYS || (stays_or_moving && r.outcome == BALANCE_INVALID);
}

/* The flip between "not stays" (at -bracket) and STAYS (at +bracket), bisected to the resolution;
 * NAN without a bracket (or on an error). The same midpoints as bench/mujoco_crosscheck.py's
 * bisection.
 */
static double dump_bisect(dump_ctx_t *c, const dump_line_t *ln, int stays_or_moving, int *trials) {
  double lo = fmax(-c->opt->bracket_m, ln->lo_m), hi = fmin(c->opt->bracket_m, ln->hi_m);
  const int a = dump_stays(c, ln, lo, stays_or_moving), b = dump_stays(c, ln, hi, stays_or_moving);
  *trials = 2;
  if (a != 0 || b != 1) return NAN;
  for (int i = 0; i < 60 && hi - lo > c->opt->resolution_m; ++i) {
    const double mid = 0.5 * (lo + hi);
    const int s = dump_stays(c, ln, mid, stays_or_moving);
    ++*trials;
    if (s < 0) return NAN;
    if (s == 1)
      hi = mid;
    else
      lo = mid;
  }
  return 0.5 * (lo + hi);
}

static int dump_placement(dump_ctx_t *c, const dump_line_t *ln, double d, const char *kind) {
  model_pose_t pose;
  balance_trial_result_t r;
  const balance_status_t st = dump_trial(c, ln, d, &pose, &r);
  if (st != BALANCE_OK) {
    LOG_E("%s line %d d %.9g: %s", c->urdf, c->line_id, d, balance_status_str(st));
    return 1;
  }
  printf("{\"type\": \"placement\", \"object\": %d, \"line\": %d, \"kind\": \"%s\"", c->object_id,
         c->line_id, kind);
  key_num("d_m", d);
  key_arr("release_p", pose.position_m, 3);
  key_arr("release_q", pose.orientation_wxyz, 4);
  printf(", \"outcome\": \"%s\"", outcome_str(r.outcome));
  key_num("rotation_rad", r.rotation_rad);
  key_num("displacement_m", r.displacement_m);
  key_arr("settled_p", r.settled.position_m, 3);
  key_arr("settled_q", r.settled.orientation_wxyz, 4);
  printf(", \"steps\": %u}\n", (unsigned)r.steps);
  return 0;
}

/* Bisect the line, print it, then its uniform and dense placements. */
static int dump_line(dump_ctx_t *c, const dump_line_t *ln) {
  int trials = 0;
  int tip_trials = 0;
  const double th = dump_bisect(c, ln, 0, &trials);
  const double tip_th = dump_bisect(c, ln, 1, &tip_trials);
  printf("{\"type\": \"line\", \"object\": %d, \"line\": %d, \"face\": %d", c->object_id,
         c->line_id, ln->face_index);
  key_arr("normal_link", ln->face->normal_link, 3);
  key_num("com_margin_m", ln->face->com_margin_m);
  printf(", \"flat\": ");
  cli_json_bool(stdout, ln->face->flat);
  key_num("yaw_rad", ln->yaw_rad);
  key_arr("orientation_wxyz", ln->q, 4);
  key_arr("u_link", ln->u, 3);
  const double bracket[2] = {fmax(-c->opt->bracket_m, ln->lo_m), fmin(c->opt->bracket_m, ln->hi_m)};
  key_arr("bracket_m", bracket, 2);
  key_num("threshold_m", th);
  key_num("tip_threshold_m", tip_th);
  printf(", \"bisect_trials\": %d}\n", trials + tip_trials);
  int rc = 0;
  const double ulo = fmax(-c->opt->range_m, ln->lo_m), uhi = fmin(c->opt->range_m, ln->hi_m);
  for (int i = 0; i < c->opt->uniform && rc == 0; ++i)
    rc = dump_placement(c, ln, cl_rng_range(&c->rng, ulo, uhi), "uniform");
  static const double dense_um[DENSE_N / 2] = {1, 3, 10, 30, 100, 300};
  const double center = isfinite(th) ? th : 0.0;
  for (int i = 0; i < DENSE_N && rc == 0; ++i) {
    const double off = (i % 2 ? 1e-6 : -1e-6) * dense_um[i / 2];
    rc = dump_placement(c, ln, center + off, "dense");
  }
  ++c->line_id;
  return rc;
}

/* The lines of one face: its orientation at each yaw, u = that orientation's inverse applied to
 * world +X (the edge normal in the link frame). */
static int dump_face(dump_ctx_t *c, const model_face_t *f, int face_index) {
  int rc = 0;
  for (int k = 0; k < c->opt->yaws && rc == 0; ++k) {
    dump_line_t ln = {.face = f, .face_index = face_index};
    ln.yaw_rad = 2.0 * CL_PI * k / c->opt->yaws;
    model_orientation_yawed(f->orientation_wxyz, ln.yaw_rad, ln.q);
    const double qi[4] = {ln.q[0], -ln.q[1], -ln.q[2], -ln.q[3]}, ex[3] = {1, 0, 0};
    cl_quat_rotate(qi, ex, ln.u);
    /* As the estimator's search range: the point over the edge stays 1 mm inside the object's
     * extent along u (beyond it nothing of the object is over B). */
    double pmin = HUGE_VAL, pmax = -HUGE_VAL;
    for (size_t i = 0; i < c->obj.mesh.vertex_count; ++i) {
      const double p = cl_vec3_dot(c->obj.mesh.vertices_m[i], ln.u);
      pmin = fmin(pmin, p);
      pmax = fmax(pmax, p);
    }
    const double uc = cl_vec3_dot(c->truth.com_m, ln.u);
    ln.lo_m = pmin + 1e-3 - uc;
    ln.hi_m = pmax - 1e-3 - uc;
    rc = dump_line(c, &ln);
  }
  return rc;
}

static int margin_desc(const void *a, const void *b) {
  const double ma = ((const model_face_t *)a)->com_margin_m;
  const double mb = ((const model_face_t *)b)->com_margin_m;
  return (ma < mb) - (ma > mb);
}

/* The stable faces of the true CoM (margin >= min_margin, confirmed by a trial), largest margin
 * first, up to opt->faces; their lines. */
static int dump_faces(dump_ctx_t *c) {
  static model_face_t faces[FACE_CAP];
  size_t nf = 0;
  model_regime_config_t rc;
  model_regime_config_default(&rc);
  rc.min_com_margin_m = c->opt->min_margin_m;
  if (model_faces_find(&c->obj.mesh, c->truth.com_m, &rc, faces, FACE_CAP, &nf) != MODEL_OK) {
    LOG_E("%s: no convex hull faces", c->urdf);
    return 1;
  }
  if (nf > FACE_CAP) nf = FACE_CAP;
  qsort(faces, nf, sizeof faces[0], margin_desc);
  int used = 0;
  for (size_t i = 0; i < nf && used < c->opt->faces; ++i) {
    if (!faces[i].candidate) continue;
    int ok = 0;
    if (balance_stable_confirm(c->w, c->o, faces[i].orientation_wxyz, c->truth.com_m, NULL, NULL,
                               &ok) != BALANCE_OK ||
        !ok)
      continue;
    if (dump_face(c, &faces[i], (int)i) != 0) return 1;
    ++used;
  }
  if (used == 0)
    LOG_W("%s: no confirmed stable face with margin >= %g m", c->urdf, c->opt->min_margin_m);
  return 0;
}

static double mesh_radius(const model_mesh_t *m, const double com[3]) {
  double r = 0.0;
  for (size_t i = 0; i < m->vertex_count; ++i) {
    double d[3];
    for (int k = 0; k < 3; ++k) d[k] = m->vertices_m[i][k] - com[k];
    r = fmax(r, cl_vec3_norm(d));
  }
  return r;
}

static void print_object(const dump_ctx_t *c) {
  printf("{\"type\": \"object\", \"object\": %d, \"urdf\": ", c->object_id);
  cli_json_string(stdout, c->urdf, 0);
  printf(", \"mesh\": ");
  cli_json_string(stdout, c->obj.mesh_path, 0);
  printf(", \"name\": ");
  cli_json_string(stdout, c->obj.robot_name, 0);
  printf(", \"vertices\": %zu, \"triangles\": %zu", c->obj.mesh.vertex_count,
         c->obj.mesh.triangle_count);
  key_num("mass_kg", c->truth.mass_kg);
  key_arr("com_m", c->truth.com_m, 3);
  key_arr("inertia_kg_m2", &c->truth.inertia_kg_m2[0][0], 9);
  key_num("radius_m", mesh_radius(&c->obj.mesh, c->truth.com_m));
  printf("}\n");
}

static int dump_object(const dump_opts_t *opt, const balance_config_t *cfg, const char *urdf,
                       int object_id, int *line_id) {
  dump_ctx_t c = {.opt = opt, .urdf = urdf, .object_id = object_id, .line_id = *line_id};
  c.rng = opt->seed ^ (0x9e3779b97f4a7c15ull * (unsigned long long)(object_id + 1));
  model_error_t err;
  if (model_object_load(urdf, NULL, &c.obj, &err) != MODEL_OK ||
      model_inertial_load(urdf, NULL, &c.truth, &err) != MODEL_OK) {
    LOG_E("%s: %s", urdf, err.msg);
    return 1;
  }
  int rc = 1;
  balance_status_t st = balance_world_create(cfg, &c.w);
  if (st == BALANCE_OK) st = balance_object_create(c.w, &c.obj.mesh, &c.truth, &c.o);
  if (st != BALANCE_OK) {
    LOG_E("%s: %s", urdf, balance_status_str(st));
  } else {
    print_object(&c);
    rc = dump_faces(&c);
  }
  *line_id = c.line_id;
  balance_world_destroy(c.w);
  model_object_free(&c.obj);
  return rc;
}

static void print_config(const balance_config_t *cfg, const dump_opts_t *opt) {
  printf("{\"type\": \"config\"");
  key_arr("base_size_m", cfg->base_size_m, 3);
  key_num("gravity_m_s2", cfg->gravity_m_s2);
  key_num("dt_s", cfg->dt_s);
  key_num("friction", cfg->friction);
  key_num("rest_min_time_s", cfg->rest_min_time_s);
  key_num("rest_lin_m_s", cfg->rest_lin_m_s);
  key_num("rest_ang_rad_s", cfg->rest_ang_rad_s);
  printf(", \"rest_steps\": %d, \"tip_grow_steps\": %d", cfg->rest_steps, cfg->tip_grow_steps);
  key_num("horizon_s", cfg->horizon_s);
  key_num("tip_angle_rad", cfg->tip_angle_rad);
  key_num("slide_m", cfg->slide_m);
  printf(", \"contact\": \"%s\"", cfg->contact == BALANCE_CONTACT_STOCK ? "stock" : "fast");
  key_num("touch_depth_m", 1e-6);
  key_num("range_m", opt->range_m);
  key_num("bracket_m", opt->bracket_m);
  key_num("resolution_m", opt->resolution_m);
  printf(", \"faces\": %d, \"yaws\": %d, \"uniform\": %d, \"seed\": %llu}\n", opt->faces, opt->yaws,
         opt->uniform, (unsigned long long)opt->seed);
}

static void usage(FILE *f) {
  fprintf(
      f,
      "usage: placements_dump [options] URDF...\n"
      "Edge placements of each object over B's +X edge and lib/balance's verdict, as JSON\n"
      "lines on stdout (see the comment at the top of bench/placements_dump.c).\n"
      "  --faces N        stable faces per object, largest CoM margin first, 1 .. %d\n"
      "                   (default 2)\n"
      "  --yaws N         yaws per face, k * 360 / N degrees, 1 .. %d (default 4)\n"
      "  --uniform N      placements per line with d uniform in +-range, 0 .. %d (default 8)\n"
      "  --range M        half width of that range, metres (default 0.005)\n"
      "  --bracket M      the threshold is bisected in [-M, M], metres (default 0.015)\n"
      "  --min-margin M   stable faces: true CoM this far inside the support polygon, metres\n"
      "                   (default 0.001)\n"
      "  --resolution M   bisect the threshold until the bracket is this narrow, metres\n"
      "                   (default 2e-7)\n"
      "  --contact PATH   lib/balance's contact path: fast or stock (ODE's trimesh-box) (default\n"
      "                   fast)\n"
      "  --seed S         seed of the uniform offsets (default 1)\n"
      "  -h, --help       this text\n"
      "  -V, --version    print the version\n"
      "Exit status: 0 success, 1 runtime failure, 2 usage.\n",
      FACES_MAX, YAWS_MAX, UNIFORM_MAX);
}

/* Options into *opt; 0, or 2 for a usage error (1 with --help: exit 0). */
static int parse_args(int argc, char **argv, dump_opts_t *opt) {
  static const struct option lo[] = {
      {"faces", required_argument, NULL, 'f'},      {"yaws", required_argument, NULL, 'y'},
      {"uniform", required_argument, NULL, 'u'},    {"range", required_argument, NULL, 'r'},
      {"min-margin", required_argument, NULL, 'm'}, {"seed", required_argument, NULL, 's'},
      {"resolution", required_argument, NULL, 'e'}, {"bracket", required_argument, NULL, 'b'},
      {"contact", required_argument, NULL, 'c'},    {"help", no_argument, NULL, 'h'},
      {"version", no_argument, NULL, 'V'},          {NULL, 0, NULL, 0}};
  int ch, bad = 0;
  opterr = 0;
  while ((ch = getopt_long(argc, argv, "hV", lo, NULL)) != -1) {
    switch (ch) {
      case 'f': bad |= tool_parse_int(optarg, 1, FACES_MAX, &opt->faces); break;
      case 'y': bad |= tool_parse_int(optarg, 1, YAWS_MAX, &opt->yaws); break;
      case 'u': bad |= tool_parse_int(optarg, 0, UNIFORM_MAX, &opt->uniform); break;
      case 'r': bad |= tool_parse_double(optarg, 1e-4, 0.1, &opt->range_m); break;
      case 'm': bad |= tool_parse_double(optarg, 0.0, 0.1, &opt->min_margin_m); break;
      case 'b': bad |= tool_parse_double(optarg, 1e-4, 0.1, &opt->bracket_m); break;
      case 'c':
        if (strcmp(optarg, "fast") == 0)
          opt->stock = 0;
        else if (strcmp(optarg, "stock") == 0)
          opt->stock = 1;
        else
          bad = 1;
        break;
      case 'e': bad |= tool_parse_double(optarg, 1e-9, 1e-3, &opt->resolution_m); break;
      case 's': bad |= tool_parse_u64(optarg, &opt->seed); break;
      case 'h': usage(stdout); return 1;
      case 'V': cli_version_print(stdout, "placements_dump"); return 1;
      default: cli_getopt_complain("placements_dump", "hV", lo, argv); return 2;
    }
  }
  if (bad || optind >= argc) {
    if (bad) LOG_E("bad option value");
    usage(stderr);
    return 2;
  }
  return 0;
}

int main(int argc, char **argv) {
  cli_log_init("placements_dump");
  dump_opts_t opt = {.faces = 2,
                     .yaws = 4,
                     .uniform = 8,
                     .range_m = 0.005,
                     .bracket_m = 0.015,
                     .min_margin_m = 0.001,
                     .resolution_m = 2e-7,
                     .seed = 1};
  const int pr = parse_args(argc, argv, &opt);
  if (pr != 0) return pr == 1 ? 0 : 2;
  balance_config_t cfg;
  balance_config_default(&cfg);
  if (opt.stock) cfg.contact = BALANCE_CONTACT_STOCK;
  print_config(&cfg, &opt);
  int line_id = 0;
  for (int i = optind; i < argc; ++i) {
    if (dump_object(&opt, &cfg, argv[i], i - optind, &line_id) != 0) return 1;
    fflush(stdout);
  }
  return fflush(stdout) == 0 ? 0 : 1;
}
