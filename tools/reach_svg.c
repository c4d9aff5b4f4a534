/* comlearn-reach-svg: which edge positions and yaws of block B each YuMi arm reaches, as SVG.
 *
 * For each arm, each of B's four top edges, positions along the edge and object yaws about the
 * block's z, it builds a full placement plan (placement_plan_build: IK for pre-place, place and
 * retreat, the gripper-into-B check, the IK-branch continuity check) for a nominal object and
 * grasp: the 40 x 60 x 50 mm test box, its centre over the edge, held top-down 15 mm below its
 * top face, fingers closing across its 40 mm side, starting from the arm's nominal posture.
 * A cell is reachable when the plan succeeds. Results go to stdout (a summary per arm and edge);
 * the picture to --out. Exit codes: 0 done, 1 failure (URDF, plan setup, file), 2 usage. */
#define _POSIX_C_SOURCE 200809L

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "comlearn/cli_args.h"
#include "comlearn/cli_log.h"
#include "comlearn/cli_time.h"
#include "comlearn/math3d.h"
#include "comlearn/model.h"
#include "comlearn/placement.h"
#include "comlearn/placement_plan.h"

#ifndef COMLEARN_ASSETS_DIR
#define COMLEARN_ASSETS_DIR "assets"
#endif

enum { ALONG_N = 13, YAW_N = 24, EDGES = 4, ARMS = 2 };
static const double kAlongStep_m = 0.02;         /* positions -0.12 .. +0.12 m */
static const double kYawStep_rad = CL_PI / 12.0; /* 0 .. 345 degrees, 15 degree steps */
static const char *const kEdgeName[EDGES] = {"+x (far)", "-x (near)", "+y (left)", "-y (right)"};
static const char *const kArmName[ARMS] = {"left arm", "right arm"};

typedef struct {
  const char *urdf;
  const char *out;
  double block_x_m, block_y_m, block_z_m;
  double max_step_rad;
  int quiet;
} options_t;

static void usage(FILE *f) {
  fprintf(f,
          "usage: comlearn-reach-svg [options]\n"
          "  --urdf PATH       YuMi URDF (default %s/yumi/yumi.urdf)\n"
          "  --svg PATH        write the SVG here, with a sweep of B's x; --out is the same\n"
          "                    (default: no picture, summary only)\n"
          "  --block-x M       B's top-face centre x in yumi_body (default 0.40, the plan's)\n"
          "  --block-y M       ... y (default 0)\n"
          "  --block-z M       ... z (default 0: B's top in the plane of yumi_body)\n"
          "  --max-joint-step R  placement_plan_config_t.max_joint_step_rad (default 0.5)\n"
          "  --quiet           no progress on stderr (shown only when stderr is a terminal)\n"
          "  -h, --help        this text\n"
          "  -V, --version     print the version\n",
          COMLEARN_ASSETS_DIR);
}

static int parse_double(const char *s, double *out) {
  char *end = NULL;
  const double v = strtod(s, &end);
  if (end == s || *end != '\0' || !isfinite(v)) return -1;
  *out = v;
  return 0;
}

/* ok[arm][edge][yaw][along]: 1 reachable, 0 not; counts per arm and edge. */
typedef struct {
  unsigned char ok[ARMS][EDGES][YAW_N][ALONG_N];
  int counts[ARMS][EDGES];
  int planned[ARMS][EDGES];
  int by_status[ARMS][16]; /* failures per status, index -status */
} reach_t;

static int arms_load(const char *urdf, placement_arm_t arms[ARMS]) {
  for (int a = 0; a < ARMS; ++a) {
    placement_error_t err = {{0}};
    if (placement_arm_load_yumi(&arms[a], urdf, (placement_side_t)a, &err) != PLACEMENT_OK) {
      LOG_E("%s", err.msg);
      return 1;
    }
  }
  return 0;
}

/* Plan every stride-th position and yaw of the grid; cells not planned stay 0 and are not
 * counted (r->planned says how many were). */
static int compute(const placement_arm_t arms[ARMS], const placement_plan_config_t *cfg,
                   int stride_along, int stride_yaw, int quiet, reach_t *r) {
  memset(r, 0, sizeof *r);
  const double lo[3] = {-0.020, -0.030, -0.025}, hi[3] = {0.020, 0.030, 0.025};
  model_mesh_t box;
  if (model_mesh_box(lo, hi, &box) != MODEL_OK) return 1;
  placement_plan_request_t req;
  memset(&req, 0, sizeof req);
  req.mesh_link = &box;
  placement_pose_identity(&req.object_in_tcp);
  req.object_in_tcp.rot[1][1] = -1.0;
  req.object_in_tcp.rot[2][2] = -1.0;
  req.object_in_tcp.pos_m[2] = hi[2] - 0.015;
  req.grip_width_m = 0.040;
  const double hx = 0.5 * cfg->block_size_m[0], hy = 0.5 * cfg->block_size_m[1];
  for (int a = 0; a < ARMS; ++a) {
    memcpy(req.q_start_rad, arms[a].nominal_rad, sizeof req.q_start_rad);
    for (int e = 0; e < EDGES; ++e) {
      if (!quiet) fprintf(stderr, "  %s, edge %s\n", kArmName[a], kEdgeName[e]);
      for (int y = 0; y < YAW_N; y += stride_yaw) {
        for (int i = 0; i < ALONG_N; i += stride_along) {
          const double along = (i - (ALONG_N - 1) / 2) * kAlongStep_m;
          placement_pose_t *t = &req.object_in_block;
          placement_pose_identity(t);
          const double axis[3] = {0.0, 0.0, 1.0};
          placement_rot_from_axis_angle(axis, y * kYawStep_rad, t->rot);
          t->pos_m[0] = e == 0 ? hx : (e == 1 ? -hx : along);
          t->pos_m[1] = e == 2 ? hy : (e == 3 ? -hy : along);
          placement_plan_t plan;
          const placement_status_t st = placement_plan_build(&arms[a], cfg, &req, &plan, NULL);
          r->ok[a][e][y][i] = st == PLACEMENT_OK;
          r->counts[a][e] += st == PLACEMENT_OK;
          r->planned[a][e] += 1;
          if (st != PLACEMENT_OK && -(int)st < 16) r->by_status[a][-(int)st] += 1;
        }
      }
    }
  }
  model_mesh_free(&box);
  return 0;
}

/* The sweep: B's centre x from kSweepX0 in kSweepN steps of kSweepStep (z and y as configured),
 * every 4 cm and 45 degrees: the share of plans each arm completes per edge. */
enum { SWEEP_N = 17 };
static const double kSweepX0 = 0.20, kSweepStep = 0.025;

typedef struct {
  double x_m[SWEEP_N];
  double share[SWEEP_N][ARMS][EDGES];
} sweep_t;

static int sweep(const placement_arm_t arms[ARMS], const placement_plan_config_t *base, int quiet,
                 sweep_t *sw) {
  static reach_t r;
  for (int k = 0; k < SWEEP_N; ++k) {
    placement_plan_config_t cfg = *base;
    cfg.block_in_base.pos_m[0] = kSweepX0 + k * kSweepStep;
    sw->x_m[k] = cfg.block_in_base.pos_m[0];
    if (!quiet) fprintf(stderr, "sweep: B at x = %.3f m\n", sw->x_m[k]);
    if (compute(arms, &cfg, 2, 3, 1, &r) != 0) return 1;
    for (int a = 0; a < ARMS; ++a) {
      for (int e = 0; e < EDGES; ++e) {
        sw->share[k][a][e] = (double)r.counts[a][e] / (double)r.planned[a][e];
      }
    }
  }
  return 0;
}

/* Panel layout (px). */
static const double kCell = 9.0, kPanelW = ALONG_N * 9.0, kPanelH = YAW_N * 9.0;
static const double kMarginL = 60.0, kGapX = 34.0, kTopY = 490.0, kGapY = 60.0;
static const double kSweepH = 240.0;

static void svg_panel(FILE *f, double x0, double y0, const reach_t *r, int a, int e,
                      const char *title) {
  const int count = r->counts[a][e];
  fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" class=\"t\">%s: %d/%d</text>\n", x0, y0 - 6.0, title,
          count, ALONG_N * YAW_N);
  fprintf(f, "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" class=\"no\"/>\n", x0, y0,
          kPanelW - 1.0, kPanelH - 1.0);
  for (int y = 0; y < YAW_N; ++y) {
    for (int i = 0; i < ALONG_N; ++i) {
      if (!r->ok[a][e][y][i]) continue;
      fprintf(f, "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.0f\" height=\"%.0f\" class=\"ok\"/>\n",
              x0 + i * kCell, y0 + y * kCell, kCell - 1.0, kCell - 1.0);
    }
  }
}

/* Top view: yumi_body origin, B, and per edge and arm a strip coloured by the share of yaws
 * reached at each position. Scale 500 px/m, x forward drawn upward, y left drawn leftward. */
static void svg_top(FILE *f, const placement_plan_config_t *cfg, const reach_t *r) {
  const double s = 500.0, ox = 340.0, oy = 350.0; /* body origin on the page */
  const double bx = cfg->block_in_base.pos_m[0], by = cfg->block_in_base.pos_m[1];
  const double hx = 0.5 * cfg->block_size_m[0], hy = 0.5 * cfg->block_size_m[1];
#define PX(yy) (ox - s * (yy))
#define PY(xx) (oy - s * (xx))
  fprintf(f,
          "<text x=\"20\" y=\"24\" class=\"h\">Top view (yumi_body frame, x forward = "
          "up)</text>\n");
  /* body footprint from the coarse mesh: x in [-0.36, 0.135], y +-0.2; drawn to x = -0.06 */
  fprintf(f, "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" class=\"body\"/>\n",
          PX(0.1997), PY(0.1349), s * 0.3994, s * (0.1349 + 0.06));
  fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" class=\"s\">body (front part)</text>\n", PX(0.1997) + 4.0,
          PY(-0.06) - 4.0);
  fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"3\" class=\"o\"/>\n", PX(0.0), PY(0.0));
  fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" class=\"s\">yumi_body origin</text>\n", PX(0.0) + 6.0,
          PY(0.0) + 14.0);
  fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" class=\"s\">left shoulder</text>\n", PX(0.0725) - 70.0,
          PY(0.05355) + 4.0);
  fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" class=\"s\">right shoulder</text>\n", PX(-0.0725) + 6.0,
          PY(0.05355) + 4.0);
  fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"3\" class=\"o\"/>\n", PX(0.0725), PY(0.05355));
  fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"3\" class=\"o\"/>\n", PX(-0.0725), PY(0.05355));
  fprintf(f, "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" class=\"blk\"/>\n",
          PX(by + hy), PY(bx + hx), 2.0 * s * hy, 2.0 * s * hx);
  fprintf(f,
          "<text x=\"%.1f\" y=\"%.1f\" class=\"s\" text-anchor=\"middle\">B, top centre</text>\n"
          "<text x=\"%.1f\" y=\"%.1f\" class=\"s\" text-anchor=\"middle\">(%.3f, %.3f, %.3f) m"
          "</text>\n<text x=\"%.1f\" y=\"%.1f\" class=\"s\" text-anchor=\"middle\">%.2f x %.2f m"
          "</text>\n",
          PX(by), PY(bx) - 8.0, PX(by), PY(bx) + 5.0, bx, by, cfg->block_in_base.pos_m[2], PX(by),
          PY(bx) + 18.0, 2.0 * hx, 2.0 * hy);
  /* strips: left arm outside-offset 8 px, right arm 18 px, along each edge's outward normal */
  for (int a = 0; a < ARMS; ++a) {
    const double off = (a == 0 ? 8.0 : 18.0) / s;
    for (int e = 0; e < EDGES; ++e) {
      for (int i = 0; i < ALONG_N; ++i) {
        int n = 0;
        for (int y = 0; y < YAW_N; ++y) n += r->ok[a][e][y][i];
        const double along = (i - (ALONG_N - 1) / 2) * kAlongStep_m;
        double px, py; /* block point on the page */
        if (e < 2) {
          const double x = bx + (e == 0 ? hx + off : -hx - off);
          px = PX(by + along);
          py = PY(x);
        } else {
          const double yv = by + (e == 2 ? hy + off : -hy - off);
          px = PX(yv);
          py = PY(bx + along);
        }
        const double frac = (double)n / YAW_N;
        const int red = (int)lround(220.0 * (1.0 - frac)), green = (int)lround(170.0 * frac);
        fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"4\" fill=\"rgb(%d,%d,60)\"/>\n", px, py,
                red, green);
      }
    }
  }
  fprintf(f,
          "<text x=\"20\" y=\"%.1f\" class=\"s\">Dots outside each edge, one per position "
          "(every 2 cm): inner row left arm, outer row right arm;</text>\n<text x=\"20\" "
          "y=\"%.1f\" class=\"s\">green = plans completed at every yaw, red = at none.</text>\n",
          oy + 50.0, oy + 63.0);
#undef PX
#undef PY
}

/* The sweep chart: share of plans completed against B's centre x, one colour per edge, solid
 * left arm, dashed right arm; the chosen x marked. */
static void svg_sweep(FILE *f, double x0, double y0, const placement_plan_config_t *cfg,
                      const sweep_t *sw) {
  static const char *const colour[EDGES] = {"#d62728", "#1f77b4", "#2ca02c", "#9467bd"};
  const double w = 560.0, h = 150.0;
  const double xmin = kSweepX0, xmax = kSweepX0 + (SWEEP_N - 1) * kSweepStep;
#define SX(v) (x0 + w * ((v)-xmin) / (xmax - xmin))
#define SY(v) (y0 + h * (1.0 - (v)))
  fprintf(f,
          "<text x=\"20\" y=\"%.1f\" class=\"h\">Share of plans completed against B's "
          "centre x</text>\n<text x=\"20\" y=\"%.1f\" class=\"s\">B's top at z = %.3f m; "
          "every 4 cm along each edge, every 45 deg of yaw</text>\n",
          y0 - 30.0, y0 - 14.0, cfg->block_in_base.pos_m[2]);
  fprintf(f,
          "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"none\" "
          "stroke=\"#999\"/>\n",
          x0, y0, w, h);
  for (int k = 0; k < SWEEP_N; k += 2) {
    fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" class=\"s\" text-anchor=\"middle\">%.2f</text>\n",
            SX(sw->x_m[k]), y0 + h + 14.0, sw->x_m[k]);
  }
  fprintf(f,
          "<text x=\"%.1f\" y=\"%.1f\" class=\"s\" text-anchor=\"middle\">B centre x "
          "(m, yumi_body)</text>\n",
          x0 + 0.5 * w, y0 + h + 28.0);
  for (int p = 0; p <= 4; ++p) {
    fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" class=\"s\" text-anchor=\"end\">%d%%</text>\n",
            x0 - 4.0, SY(p / 4.0) + 3.0, p * 25);
  }
  const double xc = cfg->block_in_base.pos_m[0];
  fprintf(f,
          "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#000\" "
          "stroke-dasharray=\"2,2\"/>\n",
          SX(xc), y0, SX(xc), y0 + h);
  fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" class=\"s\">chosen</text>\n", SX(xc) + 3.0, y0 + 10.0);
  for (int a = 0; a < ARMS; ++a) {
    for (int e = 0; e < EDGES; ++e) {
      fprintf(f, "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"1.5\"%s points=\"",
              colour[e], a == 1 ? " stroke-dasharray=\"5,3\"" : "");
      for (int k = 0; k < SWEEP_N; ++k) {
        /* offset the lines by a pixel per edge so that coincident ones stay visible */
        fprintf(f, "%.1f,%.1f ", SX(sw->x_m[k]), SY(sw->share[k][a][e]) + (e - 1.5) * 1.2);
      }
      fprintf(f, "\"/>\n");
    }
  }
  for (int e = 0; e < EDGES; ++e) {
    fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" class=\"s\" fill=\"%s\">edge %s</text>\n", x0 + w + 6.0,
            y0 + 12.0 + 14.0 * e, colour[e], kEdgeName[e]);
  }
  fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" class=\"s\">solid: left arm</text>\n", x0 + w + 6.0,
          y0 + 12.0 + 14.0 * EDGES);
  fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" class=\"s\">dashed: right arm</text>\n", x0 + w + 6.0,
          y0 + 26.0 + 14.0 * EDGES);
#undef SX
#undef SY
}

static int write_svg(const char *path, const placement_plan_config_t *cfg, const reach_t *r,
                     const sweep_t *sw) {
  FILE *f = fopen(path, "w");
  if (!f) {
    LOG_E("cannot write %s", path);
    return 1;
  }
  const double w = 760.0;
  const double h = kTopY + ARMS * (kPanelH + kGapY) + kSweepH;
  fprintf(f,
          "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" "
          "viewBox=\"0 0 %.0f %.0f\" font-family=\"sans-serif\">\n",
          w, h, w, h);
  fprintf(f,
          "<style>.ok{fill:#2e9d4a}.no{fill:#d9d9d9}.t{font-size:11px}.s{font-size:10px}"
          ".h{font-size:13px;font-weight:bold}.body{fill:#bbb;stroke:#777}"
          ".blk{fill:#c29a6b;stroke:#7a5c36}.o{fill:#000}</style>\n");
  fprintf(f, "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n");
  svg_top(f, cfg, r);
  fprintf(f,
          "<text x=\"20\" y=\"%.1f\" class=\"h\">Plans completed (green) per arm and edge"
          "</text>\n<text x=\"20\" y=\"%.1f\" class=\"s\">columns: position along the edge, "
          "-0.12 .. +0.12 m every 2 cm (block y or x increasing to the right); rows: object yaw "
          "0 .. 345 deg every 15 deg</text>\n",
          kTopY - 44.0, kTopY - 28.0);
  for (int a = 0; a < ARMS; ++a) {
    const double y0 = kTopY + a * (kPanelH + kGapY);
    fprintf(f, "<text x=\"8\" y=\"%.1f\" class=\"t\">%s</text>\n", y0 + kPanelH / 2.0, kArmName[a]);
    for (int e = 0; e < EDGES; ++e) {
      svg_panel(f, kMarginL + e * (kPanelW + kGapX), y0, r, a, e, kEdgeName[e]);
    }
  }
  svg_sweep(f, 60.0, kTopY + ARMS * (kPanelH + kGapY) + 40.0, cfg, sw);
  fprintf(f, "</svg>\n");
  if (fclose(f) != 0) {
    LOG_E("error writing %s", path);
    return 1;
  }
  return 0;
}

/* Options into o (defaults as usage() says). Returns -1 to go on, else the exit status. */
static int parse_args(int argc, char **argv, options_t *o) {
  static const struct option longopts[] = {{"urdf", required_argument, NULL, 'u'},
                                           {"out", required_argument, NULL, 'o'},
                                           {"svg", required_argument, NULL, 'o'},
                                           {"block-x", required_argument, NULL, 'x'},
                                           {"block-y", required_argument, NULL, 'y'},
                                           {"block-z", required_argument, NULL, 'z'},
                                           {"quiet", no_argument, NULL, 'q'},
                                           {"max-joint-step", required_argument, NULL, 's'},
                                           {"help", no_argument, NULL, 'h'},
                                           {"version", no_argument, NULL, 'V'},
                                           {NULL, 0, NULL, 0}};
  int c;
  opterr = 0;
  while ((c = getopt_long(argc, argv, "hV", longopts, NULL)) != -1) {
    switch (c) {
      case 'u': o->urdf = optarg; break;
      case 'o': o->out = optarg; break;
      case 'x':
      case 'y':
      case 'z':
      case 's': {
        double *dst = c == 'x'   ? &o->block_x_m
                      : c == 'y' ? &o->block_y_m
                      : c == 'z' ? &o->block_z_m
                                 : &o->max_step_rad;
        if (parse_double(optarg, dst) != 0) {
          LOG_E("bad number '%s'", optarg);
          return 2;
        }
        break;
      }
      case 'q': o->quiet = 1; break;
      case 'h': usage(stdout); return 0;
      case 'V': cli_version_print(stdout, "comlearn-reach-svg"); return 0;
      default: cli_getopt_complain("comlearn-reach-svg", "hV", longopts, argv); return 2;
    }
  }
  if (optind != argc) {
    usage(stderr);
    return 2;
  }
  return -1;
}

/* The summary on stdout: plans completed per arm and edge, failures by status, the cost. */
static void print_summary(const placement_plan_config_t *cfg, const reach_t *reach, double wall_s) {
  printf("B top centre (%.3f, %.3f, %.3f) m in yumi_body; %d positions x %d yaws per edge\n",
         cfg->block_in_base.pos_m[0], cfg->block_in_base.pos_m[1], cfg->block_in_base.pos_m[2],
         ALONG_N, YAW_N);
  for (int a = 0; a < ARMS; ++a) {
    printf("%-9s", kArmName[a]);
    for (int e = 0; e < EDGES; ++e) {
      printf("  %s %3d/%d", kEdgeName[e], reach->counts[a][e], ALONG_N * YAW_N);
    }
    printf("\n          failures:");
    for (int k = 1; k < 16; ++k) {
      if (reach->by_status[a][k]) {
        printf(" %s %d;", placement_status_str((placement_status_t)-k), reach->by_status[a][k]);
      }
    }
    printf("\n");
  }
  printf("%d plans in %.2f s: %.0f us per plan (IK included)\n", ARMS * EDGES * ALONG_N * YAW_N,
         wall_s, 1e6 * wall_s / (ARMS * EDGES * ALONG_N * YAW_N));
}

/* The sweep of B's x on stdout. */
static void print_sweep(const sweep_t *sw) {
  printf("sweep of B's centre x (share of plans completed, left / right arm):\n");
  for (int k = 0; k < SWEEP_N; ++k) {
    printf("  x %.3f", sw->x_m[k]);
    for (int e = 0; e < EDGES; ++e) {
      printf("  %s %3.0f%% / %3.0f%%", kEdgeName[e], 100.0 * sw->share[k][0][e],
             100.0 * sw->share[k][1][e]);
    }
    printf("\n");
  }
}

int main(int argc, char **argv) {
  cli_log_init("comlearn-reach-svg");
  options_t o = {COMLEARN_ASSETS_DIR "/yumi/yumi.urdf", NULL, NAN, NAN, NAN, NAN, 0};
  const int prc = parse_args(argc, argv, &o);
  if (prc >= 0) return prc;
  placement_plan_config_t cfg;
  placement_plan_config_default(&cfg);
  if (isfinite(o.block_x_m)) cfg.block_in_base.pos_m[0] = o.block_x_m;
  if (isfinite(o.block_y_m)) cfg.block_in_base.pos_m[1] = o.block_y_m;
  if (isfinite(o.block_z_m)) cfg.block_in_base.pos_m[2] = o.block_z_m;
  if (isfinite(o.max_step_rad)) cfg.max_joint_step_rad = o.max_step_rad;
  if (placement_plan_config_check(&cfg) != PLACEMENT_OK) {
    LOG_E("option out of range");
    return 2;
  }
  static placement_arm_t arms[ARMS];
  if (arms_load(o.urdf, arms) != 0) return 1;
  if (!isatty(STDERR_FILENO)) o.quiet = 1;
  static reach_t reach;
  const double t0 = cli_time_now_s();
  if (compute(arms, &cfg, 1, 1, o.quiet, &reach) != 0) return 1;
  print_summary(&cfg, &reach, cli_time_now_s() - t0);
  if (!o.out) return 0;
  static sweep_t sw;
  if (sweep(arms, &cfg, o.quiet, &sw) != 0) return 1;
  print_sweep(&sw);
  if (write_svg(o.out, &cfg, &reach, &sw) != 0) return 1;
  return 0;
}
