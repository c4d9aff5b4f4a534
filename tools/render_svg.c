/* comlearn-rocks-svg: a picture of the bundled rocks as SVG. Orthographic views, painter's
 * algorithm (back faces culled, the rest drawn far to near), flat Lambert shading; fracture faces
 * drawn lighter, the uneven rock's dense layer red-brown; the CoMs of the even and the uneven rock
 * marked where they project (seen through the rock). Only sqrt, no trigonometry: the output is
 * byte-identical across builds. */
#define _POSIX_C_SOURCE 200809L

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "comlearn/cli_args.h"
#include "comlearn/cli_log.h"
#include "comlearn/math3d.h"
#include "comlearn/model.h"
#include "comlearn/model_inertial.h"
#include "rockgen.h"

#ifndef COMLEARN_ASSETS_DIR
#define COMLEARN_ASSETS_DIR "assets"
#endif

enum { PATCHES_MAX = 16 };

static const double kCellW = 330.0, kCellH = 270.0, kTop = 56.0, kScale_px_m = 3300.0;

typedef struct {
  double right[3], up[3], toward[3]; /* screen x, screen y (up), toward the viewer */
} view_t;

/* A view from direction `toward` (from the object to the eye) with the link z axis up. */
static void view_make(double tx, double ty, double tz, view_t *v) {
  const double z[3] = {0, 0, 1};
  v->toward[0] = tx;
  v->toward[1] = ty;
  v->toward[2] = tz;
  (void)cl_vec3_normalize(v->toward, v->toward);
  cl_vec3_cross(z, v->toward, v->right);
  (void)cl_vec3_normalize(v->right, v->right);
  cl_vec3_cross(v->toward, v->right, v->up);
}

typedef struct {
  double depth;
  size_t index;
} order_t;

static int cmp_order(const void *pa, const void *pb) {
  const order_t *a = pa, *b = pb;
  if (a->depth != b->depth) return a->depth < b->depth ? -1 : 1;
  return a->index < b->index ? -1 : (a->index > b->index ? 1 : 0);
}

/* Does triangle t lie in one of the planar patches? */
static int on_patch(const model_mesh_t *m, size_t t, const double n[3], const rockgen_patch_t *p,
                    size_t np) {
  for (size_t i = 0; i < np; ++i) {
    if (cl_vec3_dot(n, p[i].normal) < ROCKGEN_PLANE_COS) continue;
    int all = 1;
    for (int k = 0; k < 3; ++k) {
      const double s = cl_vec3_dot(p[i].normal, m->vertices_m[m->triangles[t][k]]) - p[i].offset_m;
      if (fabs(s) > ROCKGEN_PLANE_TOL_M) all = 0;
    }
    if (all) return 1;
  }
  return 0;
}

static void marker(FILE *f, double x, double y, int filled) {
  if (filled) {
    fprintf(f,
            "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"4.5\" fill=\"#d7191c\" stroke=\"#fff\" "
            "stroke-width=\"1.2\"/>\n",
            x, y);
  } else {
    fprintf(f,
            "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"4.5\" fill=\"#fff\" stroke=\"#111\" "
            "stroke-width=\"1.5\"/>\n",
            x, y);
  }
}

/* The triangles facing the viewer, sorted far to near; returns how many. */
static size_t cell_order(const model_mesh_t *m, const view_t *view, order_t *order) {
  size_t n = 0;
  for (size_t t = 0; t < m->triangle_count; ++t) {
    const double *a = m->vertices_m[m->triangles[t][0]], *b = m->vertices_m[m->triangles[t][1]],
                 *c = m->vertices_m[m->triangles[t][2]];
    double e1[3], e2[3], nn[3];
    for (int k = 0; k < 3; ++k) {
      e1[k] = b[k] - a[k];
      e2[k] = c[k] - a[k];
    }
    cl_vec3_cross(e1, e2, nn);
    if (cl_vec3_dot(nn, view->toward) <= 0.0) continue; /* facing away */
    order[n].depth = (cl_vec3_dot(a, view->toward) + cl_vec3_dot(b, view->toward) +
                      cl_vec3_dot(c, view->toward)) /
                     3.0;
    order[n].index = t;
    ++n;
  }
  qsort(order, n, sizeof *order, cmp_order);
  return n;
}

/* Splits triangle v at the dense region's plane: poly[1] is the part inside, poly[0] the rest
 * (all of it without a region). */
static void split_at_region(const double *const v[3], const model_halfspace_t *region,
                            double poly[2][4][3], int count[2]) {
  double sd[3];
  for (int j = 0; j < 3; ++j) {
    sd[j] = region != NULL ? cl_vec3_dot(region->normal, v[j]) - region->offset_m : -1.0;
  }
  for (int j = 0; j < 3; ++j) {
    const int a = j, b = (j + 1) % 3;
    const int side = sd[a] >= 0.0;
    memcpy(poly[side][count[side]++], v[a], sizeof poly[0][0]);
    if ((sd[a] >= 0.0) != (sd[b] >= 0.0)) {
      const double x = sd[a] / (sd[a] - sd[b]);
      double p[3];
      for (int k = 0; k < 3; ++k) p[k] = v[a][k] + x * (v[b][k] - v[a][k]);
      memcpy(poly[0][count[0]++], p, sizeof p);
      memcpy(poly[1][count[1]++], p, sizeof p);
    }
  }
}

/* One polygon of n points, colour base * shade, tinted red-brown when dense. */
static void draw_polygon(FILE *f, const double (*poly)[3], int n, const double base[3],
                         double shade, int dense, const view_t *view, double cx, double cy) {
  int rgb[3];
  for (int k = 0; k < 3; ++k) {
    const double tint = dense ? (k == 0 ? 0.92 : (k == 1 ? 0.62 : 0.52)) : 1.0;
    const double x = base[k] * tint * shade;
    rgb[k] = x > 255.0 ? 255 : (int)(x + 0.5);
  }
  fprintf(f, "<polygon points=\"");
  for (int j = 0; j < n; ++j) {
    fprintf(f, "%s%.1f,%.1f", j ? " " : "", cx + kScale_px_m * cl_vec3_dot(poly[j], view->right),
            cy - kScale_px_m * cl_vec3_dot(poly[j], view->up));
  }
  fprintf(f, "\" fill=\"#%02x%02x%02x\" stroke=\"#%02x%02x%02x\" stroke-width=\"0.4\"/>\n", rgb[0],
          rgb[1], rgb[2], rgb[0], rgb[1], rgb[2]);
}

/* Triangle t, shaded by `light`, split at the dense region's plane. */
static void draw_triangle(FILE *f, const model_mesh_t *m, size_t t, const view_t *view, double cx,
                          double cy, const double light[3], const model_halfspace_t *region,
                          const rockgen_patch_t *patches, size_t patch_count) {
  const double *v[3];
  double e1[3], e2[3], nn[3];
  for (int j = 0; j < 3; ++j) v[j] = m->vertices_m[m->triangles[t][j]];
  for (int k = 0; k < 3; ++k) {
    e1[k] = v[1][k] - v[0][k];
    e2[k] = v[2][k] - v[0][k];
  }
  cl_vec3_cross(e1, e2, nn);
  (void)cl_vec3_normalize(nn, nn);
  double base[3] = {146, 136, 122}; /* weathered surface */
  if (on_patch(m, t, nn, patches, patch_count)) {
    base[0] = 196;
    base[1] = 187;
    base[2] = 170; /* fresh fracture face */
  }
  const double lambert = cl_vec3_dot(nn, light) > 0.0 ? cl_vec3_dot(nn, light) : 0.0;
  const double shade = 0.30 + 0.80 * lambert;
  double poly[2][4][3];
  int count[2] = {0, 0};
  split_at_region(v, region, poly, count);
  for (int side = 0; side < 2; ++side) {
    if (count[side] < 3) continue;
    draw_polygon(f, (const double(*)[3])poly[side], count[side], base, shade, side, view, cx, cy);
  }
}

/* The two CoMs, joined by a line. */
static void draw_coms(FILE *f, const view_t *view, double cx, double cy,
                      const double com_uniform[3], const double com_true[3]) {
  fprintf(f,
          "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#fff\" "
          "stroke-width=\"1.5\"/>\n",
          cx + kScale_px_m * cl_vec3_dot(com_uniform, view->right),
          cy - kScale_px_m * cl_vec3_dot(com_uniform, view->up),
          cx + kScale_px_m * cl_vec3_dot(com_true, view->right),
          cy - kScale_px_m * cl_vec3_dot(com_true, view->up));
  marker(f, cx + kScale_px_m * cl_vec3_dot(com_uniform, view->right),
         cy - kScale_px_m * cl_vec3_dot(com_uniform, view->up), 0);
  marker(f, cx + kScale_px_m * cl_vec3_dot(com_true, view->right),
         cy - kScale_px_m * cl_vec3_dot(com_true, view->up), 1);
}

/* One view of one rock centered at (cx, cy). */
static int draw_cell(FILE *f, const model_mesh_t *m, const view_t *view, double cx, double cy,
                     const model_halfspace_t *region, const rockgen_patch_t *patches,
                     size_t patch_count, const double com_uniform[3], const double com_true[3]) {
  order_t *order = malloc(m->triangle_count * sizeof *order);
  if (order == NULL) return 1;
  const size_t n = cell_order(m, view, order);
  /* Light from the upper left, in front: fixed in the view. */
  double light[3];
  for (int k = 0; k < 3; ++k)
    light[k] = -0.45 * view->right[k] + 0.6 * view->up[k] + 0.65 * view->toward[k];
  (void)cl_vec3_normalize(light, light);
  for (size_t i = 0; i < n; ++i) {
    draw_triangle(f, m, order[i].index, view, cx, cy, light, region, patches, patch_count);
  }
  free(order);
  draw_coms(f, view, cx, cy, com_uniform, com_true);
  return 0;
}

/* The XML prologue, the background and the titles. */
static void render_header(FILE *f, double width, double height) {
  fprintf(f, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
  fprintf(f,
          "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" "
          "viewBox=\"0 0 %.0f %.0f\" font-family=\"DejaVu Sans, Arial, sans-serif\">\n",
          width, height, width, height);
  fprintf(f, "<!-- Generated by comlearn-rocks-svg from the assets; do not edit. -->\n");
  fprintf(f, "<rect width=\"100%%\" height=\"100%%\" fill=\"#fbfaf7\"/>\n");
  fprintf(f,
          "<text x=\"%.0f\" y=\"24\" font-size=\"16\" text-anchor=\"middle\">The bundled rocks "
          "(orthographic, to scale)</text>\n",
          width / 2.0);
  fprintf(f,
          "<text x=\"%.0f\" y=\"44\" font-size=\"12\" text-anchor=\"middle\" fill=\"#444\">"
          "from above</text>\n",
          10.0 + kCellW / 2.0);
  fprintf(f,
          "<text x=\"%.0f\" y=\"44\" font-size=\"12\" text-anchor=\"middle\" fill=\"#444\">"
          "from below (bottom fracture face)</text>\n",
          10.0 + 1.5 * kCellW);
}

/* Row i: rock spec's name, masses and its two views. */
static int render_rock(FILE *f, const char *assets_dir, size_t i, const view_t views[2]) {
  const rockgen_spec_t *spec = rockgen_spec_get(i);
  char path[4096];
  model_error_t err;
  model_object_t obj;
  model_mass_t even, uneven, prior;
  model_halfspace_t region;
  snprintf(path, sizeof path, "%s/rocks/%s_even.urdf", assets_dir, spec->name);
  model_status_t st = model_object_load(path, NULL, &obj, &err);
  if (st == MODEL_OK) st = model_inertial_load(path, NULL, &even, &err);
  if (st == MODEL_OK) {
    snprintf(path, sizeof path, "%s/rocks/%s_uneven.urdf", assets_dir, spec->name);
    st = model_inertial_load(path, NULL, &uneven, &err);
  }
  if (st != MODEL_OK) {
    LOG_E("%s: %s", path, err.msg);
    model_object_free(&obj);
    return 1;
  }
  rockgen_patch_t patches[PATCHES_MAX];
  size_t np = 0;
  st = rockgen_mass(spec, &obj.mesh, &prior, NULL, &region);
  if (st == MODEL_OK) st = rockgen_patches_find(&obj.mesh, 1e-4, patches, PATCHES_MAX, &np);
  if (st != MODEL_OK) {
    LOG_E("%s: %s", spec->name, model_status_str(st));
    model_object_free(&obj);
    return 1;
  }
  if (np > PATCHES_MAX) np = PATCHES_MAX;
  const double cy = kTop + ((double)i + 0.5) * kCellH;
  fprintf(f, "<text x=\"16\" y=\"%.0f\" font-size=\"14\" font-weight=\"bold\">%s</text>\n",
          kTop + (double)i * kCellH + 18.0, spec->name);
  fprintf(f,
          "<text x=\"16\" y=\"%.0f\" font-size=\"11\" fill=\"#444\">%.0f g even, %.0f g "
          "uneven</text>\n",
          kTop + (double)i * kCellH + 34.0, 1e3 * even.mass_kg, 1e3 * uneven.mass_kg);
  for (int c = 0; c < 2; ++c) {
    const double cx = 10.0 + ((double)c + 0.5) * kCellW;
    if (draw_cell(f, &obj.mesh, &views[c], cx, cy, &region, patches, np, even.com_m,
                  uneven.com_m)) {
      model_object_free(&obj);
      return 1;
    }
  }
  model_object_free(&obj);
  return 0;
}

/* The key to the markers and the 1 cm scale bar, at height ly. */
static void render_legend(FILE *f, double width, double ly) {
  marker(f, 24.0, ly, 0);
  fprintf(f,
          "<text x=\"34\" y=\"%.0f\" font-size=\"12\">uniform-density CoM (= CoM of "
          "rock_N_even)</text>\n",
          ly + 4.0);
  marker(f, 24.0, ly + 20.0, 1);
  fprintf(f,
          "<text x=\"34\" y=\"%.0f\" font-size=\"12\">true CoM of rock_N_uneven; its dense "
          "layer is red-brown, fracture faces are light</text>\n",
          ly + 24.0);
  const double bar = kScale_px_m * 0.01;
  fprintf(f,
          "<line x1=\"%.1f\" y1=\"%.0f\" x2=\"%.1f\" y2=\"%.0f\" stroke=\"#111\" "
          "stroke-width=\"2\"/>\n",
          width - 30.0 - bar, ly, width - 30.0, ly);
  fprintf(f, "<text x=\"%.1f\" y=\"%.0f\" font-size=\"12\" text-anchor=\"middle\">1 cm</text>\n",
          width - 30.0 - bar / 2.0, ly + 16.0);
}

static int render(const char *assets_dir, FILE *f) {
  const size_t rocks = rockgen_spec_count();
  const double width = 2.0 * kCellW + 20.0, height = kTop + (double)rocks * kCellH + 60.0;
  view_t views[2];
  view_make(0.9, -1.5, 1.1, &views[0]);   /* from above, front right */
  view_make(-0.7, -1.2, -1.3, &views[1]); /* from below, front left: the bottom face */
  render_header(f, width, height);
  for (size_t i = 0; i < rocks; ++i) {
    if (render_rock(f, assets_dir, i, views)) return 1;
  }
  render_legend(f, width, kTop + (double)rocks * kCellH + 14.0);
  fprintf(f, "</svg>\n");
  return 0;
}

static void usage(FILE *f) {
  fprintf(f,
          "usage: comlearn-rocks-svg [--assets-dir DIR] [--svg FILE]\n"
          "Draws the bundled rocks (two views each, CoMs marked) as SVG.\n"
          "  --assets-dir DIR  assets to draw (default: %s)\n"
          "  --svg FILE        SVG file to write (default: standard output); --out is the same\n"
          "  -h, --help        this text\n"
          "  -V, --version     print the version\n"
          "Exit status: 0 success, 1 runtime failure, 2 usage.\n",
          COMLEARN_ASSETS_DIR);
}

int main(int argc, char **argv) {
  cli_log_init("comlearn-rocks-svg");
  static const struct option opts[] = {
      {"assets-dir", required_argument, NULL, 'a'}, {"out", required_argument, NULL, 'o'},
      {"svg", required_argument, NULL, 'o'},        {"help", no_argument, NULL, 'h'},
      {"version", no_argument, NULL, 'V'},          {NULL, 0, NULL, 0}};
  const char *assets_dir = COMLEARN_ASSETS_DIR, *out = NULL;
  int c;
  opterr = 0;
  while ((c = getopt_long(argc, argv, "hV", opts, NULL)) != -1) {
    switch (c) {
      case 'a': assets_dir = optarg; break;
      case 'o': out = optarg; break;
      case 'h': usage(stdout); return 0;
      case 'V': cli_version_print(stdout, "comlearn-rocks-svg"); return 0;
      default: cli_getopt_complain("comlearn-rocks-svg", "hV", opts, argv); return 2;
    }
  }
  if (optind != argc) {
    usage(stderr);
    return 2;
  }
  FILE *f = out != NULL ? fopen(out, "w") : stdout;
  if (f == NULL) {
    perror(out);
    return 1;
  }
  int rc = render(assets_dir, f);
  if (out != NULL && fclose(f) != 0) rc = 1;
  if (rc != 0 && out != NULL) remove(out);
  return rc;
}
