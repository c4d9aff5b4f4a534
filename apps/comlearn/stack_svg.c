/* stack_svg.c - a side view of a stack as SVG (stack_svg_write, stack_svg.h).
 *
 * Orthographic view looking along +y (world x to the right, z up). Painter's algorithm over the
 * triangles of all objects together: back faces (outward normal with y >= 0) culled, the rest
 * drawn far to near by the y of their centroid. Flat Lambert shading from a light at the upper
 * left front, quantised to 32 levels so that each (object, level) is one CSS class: about 65 bytes
 * per drawn triangle, ~200 KB for three 2000-triangle rocks. B's top is a wide box below z = 0;
 * believed CoMs are crosses; a scale bar in mm; coordinates with one decimal (px).
 *
 * Geometry only (no URDF inertial). The file is written to PATH.tmp and renamed
 * over PATH, so a failure never leaves a partial file at PATH (PATH.tmp is removed).
 * Errors: -1 with errno EINVAL (NULL path / meshes / poses, count 0, a NULL mesh, a non-finite or
 * zero quaternion, position, vertex or CoM, a triangle index out of range), ENOMEM, ENAMETOOLONG,
 * or the errno of fopen / fprintf / fclose / rename. */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "comlearn/cli_svg.h"
#include "stack_svg.h"

enum { SHADE_LEVELS = 32, PALETTE = 8 };

static const double kWidth_px = 720.0;
static const double kMargin_px = 40.0;
static const double kTitle_px = 46.0;   /* band above the drawing */
static const double kBelow_px = 70.0;   /* B's box and the scale bar below z = 0 */
static const double kMinSpanX_m = 0.12; /* a lone rock is not blown up past this */
static const double kMaxDrawH_px = 620.0;

/* One tint per object (input index mod 8): rock-ish but told apart. */
static const double kTint[PALETTE][3] = {{178, 142, 104}, {108, 140, 176}, {118, 162, 106},
                                         {184, 118, 140}, {196, 172, 86},  {100, 156, 160},
                                         {158, 128, 184}, {150, 150, 150}};

typedef struct {
  double depth_m; /* world y of the centroid: larger is farther */
  uint32_t object;
  uint32_t level;
  size_t triangle;
} face_t;

static int cmp_face(const void *pa, const void *pb) {
  const face_t *a = pa, *b = pb;
  if (a->depth_m != b->depth_m) return a->depth_m > b->depth_m ? -1 : 1; /* far first */
  if (a->object != b->object) return a->object < b->object ? -1 : 1;
  return a->triangle < b->triangle ? -1 : (a->triangle > b->triangle ? 1 : 0);
}

static int finite3(const double v[3]) { return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]); }

/* Rotation of a pose (quaternion normalised here), or 0 when it is not usable. */
static int pose_rot(const model_pose_t *p, double rot[3][3]) {
  const double *q = p->orientation_wxyz;
  if (!finite3(p->position_m) || !isfinite(q[0]) || !finite3(q + 1)) return 0;
  const double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (!(n > 1e-9) || !isfinite(n)) return 0;
  const double qn[4] = {q[0] / n, q[1] / n, q[2] / n, q[3] / n};
  model_quat_to_rot(qn, rot);
  return 1;
}

static void to_world(const double rot[3][3], const double pos[3], const double v[3],
                     double out[3]) {
  for (int r = 0; r < 3; ++r) {
    out[r] = pos[r] + rot[r][0] * v[0] + rot[r][1] * v[1] + rot[r][2] * v[2];
  }
}

/* The drawing: world (x, z) -> px. */
typedef struct {
  double scale_px_m, x0_m, z0_m, ox_px, oy_px;
} frame_t;

static double px_x(const frame_t *fr, double x_m) {
  return fr->ox_px + fr->scale_px_m * (x_m - fr->x0_m);
}

static double px_y(const frame_t *fr, double z_m) {
  return fr->oy_px - fr->scale_px_m * (z_m - fr->z0_m);
}

static void cross_marker(FILE *f, double x, double y, const char *label) {
  const double r = 6.0;
  for (int pass = 0; pass < 2; ++pass) {
    fprintf(f,
            "<path d=\"M%.1f %.1fL%.1f %.1fM%.1f %.1fL%.1f %.1f\" stroke=\"%s\" "
            "stroke-width=\"%s\" fill=\"none\"/>\n",
            x - r, y - r, x + r, y + r, x - r, y + r, x + r, y - r, pass ? "#b3001b" : "#ffffff",
            pass ? "1.8" : "4");
  }
  fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-size=\"11\" fill=\"#b3001b\">%s</text>\n", x + 8.0,
          y - 6.0, label);
}

/* The objects in the world: vertices, the visible faces far to near, bounds, shades used. */
typedef struct {
  double (*world)[3]; /* every object's vertices in the world, object i from first[i] */
  face_t *faces;      /* the visible faces, nf of them */
  size_t *first;
  size_t nf;
  double lo[2], hi[2]; /* x, z; the z range includes B's top */
  unsigned char used[PALETTE][SHADE_LEVELS];
} scene_t;

static void scene_free(scene_t *s) {
  free(s->world);
  free(s->faces);
  free(s->first);
}

/* Triangle t of object i as a face when it faces the viewer (at -y), shaded; 0 when culled. */
static int face_of(const double *a, const double *b, const double *c, size_t i, size_t t,
                   face_t *out) {
  static const double kLight[3] = {-0.45341, -0.65493, 0.60455}; /* unit, toward the light */
  double e1[3], e2[3], n[3];
  for (int k = 0; k < 3; ++k) {
    e1[k] = b[k] - a[k];
    e2[k] = c[k] - a[k];
  }
  n[0] = e1[1] * e2[2] - e1[2] * e2[1];
  n[1] = e1[2] * e2[0] - e1[0] * e2[2];
  n[2] = e1[0] * e2[1] - e1[1] * e2[0];
  const double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (!(n[1] < 0.0) || !(len > 0.0)) return 0; /* facing away (the viewer is at -y) */
  double lambert = (n[0] * kLight[0] + n[1] * kLight[1] + n[2] * kLight[2]) / len;
  if (lambert < 0.0) lambert = 0.0;
  out->depth_m = (a[1] + b[1] + c[1]) / 3.0;
  out->object = (uint32_t)i;
  out->level = (uint32_t)(lambert * (SHADE_LEVELS - 1) + 0.5);
  out->triangle = t;
  return 1;
}

/* World vertices, visible faces (sorted far to near), bounds. Returns 0 or -1 (ENOMEM; s is
 * freed). */
static int scene_build(const model_mesh_t *const *meshes, const model_pose_t *poses, size_t count,
                       double (*rot)[3][3], const unsigned char *skip, scene_t *s) {
  size_t total_v = 0, total_t = 0;
  for (size_t i = 0; i < count; ++i) {
    total_v += meshes[i]->vertex_count;
    total_t += meshes[i]->triangle_count;
  }
  s->world = malloc((total_v ? total_v : 1) * sizeof *s->world);
  s->faces = malloc((total_t ? total_t : 1) * sizeof *s->faces);
  s->first = malloc(count * sizeof *s->first);
  if (s->world == NULL || s->faces == NULL || s->first == NULL) {
    scene_free(s);
    errno = ENOMEM;
    return -1;
  }
  s->lo[0] = HUGE_VAL;
  s->hi[0] = -HUGE_VAL;
  s->lo[1] = s->hi[1] = 0.0;
  s->nf = 0;
  memset(s->used, 0, sizeof s->used);
  size_t base = 0;
  for (size_t i = 0; i < count; ++i) {
    const model_mesh_t *m = meshes[i];
    s->first[i] = base;
    if (skip != NULL && skip[i]) { /* not drawn: no faces, no bounds */
      base += m->vertex_count;
      continue;
    }
    for (size_t v = 0; v < m->vertex_count; ++v) {
      double *w = s->world[base + v];
      to_world((const double(*)[3])rot[i], poses[i].position_m, m->vertices_m[v], w);
      if (w[0] < s->lo[0]) s->lo[0] = w[0];
      if (w[0] > s->hi[0]) s->hi[0] = w[0];
      if (w[2] < s->lo[1]) s->lo[1] = w[2];
      if (w[2] > s->hi[1]) s->hi[1] = w[2];
    }
    for (size_t t = 0; t < m->triangle_count; ++t) {
      const uint32_t *tri = m->triangles[t];
      face_t *fc = &s->faces[s->nf];
      if (!face_of(s->world[base + tri[0]], s->world[base + tri[1]], s->world[base + tri[2]], i, t,
                   fc))
        continue;
      s->used[i % PALETTE][fc->level] = 1;
      ++s->nf;
    }
    base += m->vertex_count;
  }
  qsort(s->faces, s->nf, sizeof *s->faces, cmp_face);
  return 0;
}

/* Frame: fit the objects (and B's top) into the width; z = 0 at a fixed distance above the
 * bottom band. *height_px: the picture's height. */
static void frame_fit(const scene_t *s, double extra_below_px, frame_t *fr, double *height_px) {
  double span_x = s->hi[0] - s->lo[0], span_z = s->hi[1] - s->lo[1];
  if (!(span_x >= kMinSpanX_m)) span_x = kMinSpanX_m;
  if (!(span_z > 0.01)) span_z = 0.01;
  fr->scale_px_m = (kWidth_px - 2.0 * kMargin_px) / span_x;
  if (fr->scale_px_m * span_z > kMaxDrawH_px) fr->scale_px_m = kMaxDrawH_px / span_z;
  fr->x0_m = 0.5 * (s->lo[0] + s->hi[0]);
  fr->z0_m = s->lo[1];
  fr->ox_px = 0.5 * kWidth_px;
  const double draw_h = fr->scale_px_m * (s->hi[1] - s->lo[1]);
  fr->oy_px = kTitle_px + kMargin_px * 0.5 + draw_h;
  *height_px = fr->oy_px + kBelow_px + 20.0 + extra_below_px;
}

/* The XML and svg headers, one CSS class per (tint, shade) used, background and title. */
static void svg_head(FILE *f, double height, const unsigned char used[PALETTE][SHADE_LEVELS],
                     const char *title) {
  fprintf(f, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
  fprintf(f,
          "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" "
          "viewBox=\"0 0 %.0f %.0f\" font-family=\"DejaVu Sans, Arial, sans-serif\">\n",
          kWidth_px, height, kWidth_px, height);
  fprintf(f,
          "<!-- Generated by comlearn stack (stack_svg_write): side view looking along +y, "
          "x right, z up. -->\n<style>");
  for (int o = 0; o < PALETTE; ++o) {
    for (int l = 0; l < SHADE_LEVELS; ++l) {
      if (!used[o][l]) continue;
      const double shade = 0.38 + 0.72 * (double)l / (SHADE_LEVELS - 1);
      int rgb[3];
      for (int k = 0; k < 3; ++k) {
        const double x = kTint[o][k] * shade;
        rgb[k] = x > 255.0 ? 255 : (int)(x + 0.5);
      }
      fprintf(f, ".o%ds%d{fill:#%02x%02x%02x;stroke:#%02x%02x%02x}", o, l, rgb[0], rgb[1], rgb[2],
              rgb[0], rgb[1], rgb[2]);
    }
  }
  fprintf(f, "</style>\n<rect width=\"100%%\" height=\"100%%\" fill=\"#fbfaf7\"/>\n");
  if (title != NULL) {
    fprintf(f, "<text x=\"%.0f\" y=\"28\" font-size=\"16\" text-anchor=\"middle\">",
            0.5 * kWidth_px);
    cli_svg_text(f, title);
    fprintf(f, "</text>\n");
  }
}

/* B's top: a wide box below z = 0 (B is 300 mm across; the view shows its middle). */
static void svg_support(FILE *f, double top_px) {
  fprintf(f,
          "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"#c29a6b\" "
          "stroke=\"#6b4f2e\" stroke-width=\"1\"/>\n",
          8.0, top_px, kWidth_px - 16.0, 30.0);
  fprintf(f,
          "<text x=\"14\" y=\"%.1f\" font-size=\"11\" fill=\"#3b2a16\">B (top at z = 0)</text>\n",
          top_px + 19.0);
}

/* The visible faces, far to near. */
static void svg_faces(FILE *f, const model_mesh_t *const *meshes, const scene_t *s,
                      const frame_t *fr) {
  fprintf(f, "<g stroke-width=\"0.5\" stroke-linejoin=\"round\">\n");
  for (size_t i = 0; i < s->nf; ++i) {
    const face_t *fc = &s->faces[i];
    const model_mesh_t *m = meshes[fc->object];
    const uint32_t *tri = m->triangles[fc->triangle];
    fprintf(f, "<polygon class=\"o%us%u\" points=\"", (unsigned)(fc->object % PALETTE),
            (unsigned)fc->level);
    for (int j = 0; j < 3; ++j) {
      const double *w = s->world[s->first[fc->object] + tri[j]];
      fprintf(f, "%s%.1f,%.1f", j ? " " : "", px_x(fr, w[0]), px_y(fr, w[2]));
    }
    fprintf(f, "\"/>\n");
  }
  fprintf(f, "</g>\n");
}

/* The scale bar, 10, 20 or 50 mm, whichever is 60-200 px long (or the nearest), and with CoMs
 * the legend of their crosses. */
static void svg_scale_bar(FILE *f, const frame_t *fr, double top_px, int with_coms) {
  double bar_mm = 10.0;
  if (fr->scale_px_m * 0.010 < 60.0) bar_mm = 20.0;
  if (fr->scale_px_m * 0.020 < 60.0) bar_mm = 50.0;
  const double bar_px = fr->scale_px_m * bar_mm * 1e-3;
  const double by = top_px + 52.0, bx = kWidth_px - kMargin_px - bar_px;
  fprintf(f,
          "<path d=\"M%.1f %.1fV%.1fH%.1fV%.1f\" stroke=\"#111\" stroke-width=\"2\" "
          "fill=\"none\"/>\n",
          bx, by - 5.0, by, bx + bar_px, by - 5.0);
  fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-size=\"12\" text-anchor=\"middle\">%.0f mm</text>\n",
          bx + 0.5 * bar_px, by + 15.0, bar_mm);
  if (with_coms) {
    cross_marker(f, kMargin_px, by - 2.0, "");
    fprintf(f,
            "<text x=\"%.1f\" y=\"%.1f\" font-size=\"12\">believed CoM of object i (input "
            "index)</text>\n",
            kMargin_px + 14.0, by + 2.0);
  }
}

/* Everything after the checks; returns 0 or -1 (errno set by the failing call or ENOMEM). */
static int render(FILE *f, const model_mesh_t *const *meshes, const model_pose_t *poses,
                  const double (*com_link_m)[3], size_t count, const char *title,
                  double (*rot)[3][3]) {
  scene_t s;
  if (scene_build(meshes, poses, count, rot, NULL, &s) != 0) return -1;
  frame_t fr;
  double height;
  frame_fit(&s, 0.0, &fr, &height);
  svg_head(f, height, (const unsigned char(*)[SHADE_LEVELS])s.used, title);
  const double top_px = px_y(&fr, 0.0);
  svg_support(f, top_px);
  svg_faces(f, meshes, &s, &fr);
  if (com_link_m != NULL) {
    for (size_t i = 0; i < count; ++i) {
      double w[3];
      char label[32];
      to_world((const double(*)[3])rot[i], poses[i].position_m, com_link_m[i], w);
      snprintf(label, sizeof label, "%zu", i);
      cross_marker(f, px_x(&fr, w[0]), px_y(&fr, w[2]), label);
    }
  }
  svg_scale_bar(f, &fr, top_px, com_link_m != NULL);
  fprintf(f, "</svg>\n");
  scene_free(&s);
  return 0;
}

/* A mesh the picture can draw: vertices finite, triangle indices in range. */
static int mesh_ok(const model_mesh_t *m) {
  if (m == NULL || m->vertices_m == NULL || m->triangles == NULL || m->vertex_count == 0 ||
      m->triangle_count == 0)
    return 0;
  for (size_t v = 0; v < m->vertex_count; ++v)
    if (!finite3(m->vertices_m[v])) return 0;
  for (size_t t = 0; t < m->triangle_count; ++t)
    for (int k = 0; k < 3; ++k)
      if (m->triangles[t][k] >= m->vertex_count) return 0;
  return 1;
}

/* The picture as body(f, ctx) writes it, into PATH.tmp, then renamed over path. Returns 0 or -1
 * with errno (PATH.tmp removed). */
static int write_via_tmp(const char *path, int (*body)(FILE *, const void *), const void *ctx) {
  char tmp[4096];
  if ((size_t)snprintf(tmp, sizeof tmp, "%s.tmp", path) >= sizeof tmp) {
    errno = ENAMETOOLONG;
    return -1;
  }
  FILE *f = fopen(tmp, "w");
  if (f == NULL) return -1;
  errno = 0;
  int rc = body(f, ctx);
  int err = errno;
  if (rc == 0 && ferror(f)) {
    rc = -1;
    if (err == 0) err = EIO;
  }
  if (fclose(f) != 0 && rc == 0) {
    rc = -1;
    err = errno;
  }
  if (rc == 0 && rename(tmp, path) != 0) {
    rc = -1;
    err = errno;
  }
  if (rc != 0) {
    remove(tmp);
    errno = err != 0 ? err : EIO;
  }
  return rc;
}

typedef struct {
  const model_mesh_t *const *meshes;
  const model_pose_t *poses;
  const double (*com)[3];
  size_t count;
  const char *title;
  double (*rot)[3][3];
} plain_args_t;

static int plain_body(FILE *f, const void *ctx) {
  const plain_args_t *a = ctx;
  return render(f, a->meshes, a->poses, a->com, a->count, a->title, a->rot);
}

int stack_svg_write(const char *path, const model_mesh_t *const *meshes_link,
                    const model_pose_t *poses, const double (*com_link_m)[3], size_t count,
                    const char *title) {
  if (path == NULL || path[0] == '\0' || meshes_link == NULL || poses == NULL || count == 0 ||
      count > STACK_MAX_OBJECTS) {
    errno = EINVAL;
    return -1;
  }
  double rot[STACK_MAX_OBJECTS][3][3];
  for (size_t i = 0; i < count; ++i) {
    if (!mesh_ok(meshes_link[i]) || !pose_rot(&poses[i], rot[i]) ||
        (com_link_m != NULL && !finite3(com_link_m[i]))) {
      errno = EINVAL;
      return -1;
    }
  }
  const plain_args_t a = {meshes_link, poses, com_link_m, count, title, rot};
  return write_via_tmp(path, plain_body, &a);
}

/* ---- the stack after its simulation (stack_svg_write_run) ------------------------------------ */

static const double kContactTol_m = 5e-6; /* a vertex on the other's surface (poses: 1 um deep) */
static const double kOffB_m = 0.05;       /* lowest point this far below B's top: fell off B */
static const double kRunLegend_px = 50.0; /* the second and third legend rows */

typedef struct {
  const stack_svg_object_t *obj;
  size_t count;
  const size_t *order;
  const char *com_label, *title;
  double (*rot_final)[3][3];
  double (*rot_plan)[3][3];
} run_args_t;

/* Whether world point p lies within kContactTol_m of triangle (a, b, c), over its interior. */
static int near_triangle(const double *p, const double *a, const double *b, const double *c) {
  double e1[3], e2[3], d[3], n[3];
  for (int k = 0; k < 3; ++k) {
    e1[k] = b[k] - a[k];
    e2[k] = c[k] - a[k];
    d[k] = p[k] - a[k];
  }
  n[0] = e1[1] * e2[2] - e1[2] * e2[1];
  n[1] = e1[2] * e2[0] - e1[0] * e2[2];
  n[2] = e1[0] * e2[1] - e1[1] * e2[0];
  const double nn = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
  if (!(nn > 0.0)) return 0;
  const double h = (d[0] * n[0] + d[1] * n[1] + d[2] * n[2]) / sqrt(nn);
  if (fabs(h) > kContactTol_m) return 0;
  /* barycentric coordinates of the projection */
  const double d11 = e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2];
  const double d12 = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2];
  const double d22 = e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2];
  const double p1 = d[0] * e1[0] + d[1] * e1[1] + d[2] * e1[2];
  const double p2 = d[0] * e2[0] + d[1] * e2[1] + d[2] * e2[2];
  const double den = d11 * d22 - d12 * d12;
  if (!(den > 0.0)) return 0;
  const double u = (d22 * p1 - d12 * p2) / den, v = (d11 * p2 - d12 * p1) / den;
  const double eps = 1e-6;
  return u >= -eps && v >= -eps && u + v <= 1.0 + eps;
}

/* The (x, z) of the vertices of mesh a (world wa) within kContactTol_m of mesh b's surface (world
 * wb), appended at pts[*n]. */
static void touching(const model_mesh_t *a, const double (*wa)[3], const model_mesh_t *b,
                     const double (*wb)[3], double (*pts)[2], size_t *n) {
  double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (size_t v = 0; v < b->vertex_count; ++v)
    for (int k = 0; k < 3; ++k) {
      lo[k] = fmin(lo[k], wb[v][k] - kContactTol_m);
      hi[k] = fmax(hi[k], wb[v][k] + kContactTol_m);
    }
  for (size_t v = 0; v < a->vertex_count; ++v) {
    const double *p = wa[v];
    if (p[0] < lo[0] || p[0] > hi[0] || p[1] < lo[1] || p[1] > hi[1] || p[2] < lo[2] ||
        p[2] > hi[2])
      continue;
    for (size_t t = 0; t < b->triangle_count; ++t) {
      const uint32_t *tri = b->triangles[t];
      if (near_triangle(p, wb[tri[0]], wb[tri[1]], wb[tri[2]])) {
        pts[*n][0] = p[0];
        pts[*n][1] = p[2];
        ++*n;
        break;
      }
    }
  }
}

/* Every object's vertices at its planned pose (object i from first[i]), or NULL (ENOMEM). */
static double (*planned_world(const run_args_t *a, const size_t *first, size_t total))[3] {
  double(*w)[3] = malloc((total ? total : 1) * sizeof *w);
  if (w == NULL) return NULL;
  for (size_t i = 0; i < a->count; ++i) {
    const model_mesh_t *m = a->obj[i].mesh_link;
    for (size_t v = 0; v < m->vertex_count; ++v)
      to_world((const double(*)[3])a->rot_plan[i], a->obj[i].planned.position_m, m->vertices_m[v],
               w[first[i] + v]);
  }
  return w;
}

/* A polygon of (x, z) points in px, with a class and the data attributes given. */
static void svg_polygon(FILE *f, const frame_t *fr, const double (*pts)[2], size_t n,
                        const char *attrs) {
  fprintf(f, "<polygon %s points=\"", attrs);
  for (size_t j = 0; j < n; ++j)
    fprintf(f, "%s%.1f,%.1f", j ? " " : "", px_x(fr, pts[j][0]), px_y(fr, pts[j][1]));
  fprintf(f, "\"/>\n");
}

/* Planned poses as dashed outlines: the convex hull of each object's vertices seen along +y. */
static void svg_planned(FILE *f, const run_args_t *a, const frame_t *fr, const double (*pw)[3],
                        const size_t *first, double (*pts)[2], double (*hull)[2]) {
  for (size_t i = 0; i < a->count; ++i) {
    const size_t nv = a->obj[i].mesh_link->vertex_count;
    for (size_t v = 0; v < nv; ++v) {
      pts[v][0] = pw[first[i] + v][0];
      pts[v][1] = pw[first[i] + v][2];
    }
    const size_t nh = model_polygon_hull(pts, nv, hull);
    char attrs[160];
    snprintf(attrs, sizeof attrs,
             "class=\"planned\" data-object=\"%zu\" fill=\"none\" stroke=\"#5a5a5a\" "
             "stroke-width=\"1.3\" stroke-dasharray=\"5 3\"",
             i);
    svg_polygon(f, fr, (const double(*)[2])hull, nh, attrs);
  }
}

/* The plan's support polygons at the planned poses: order[0] on B (its vertices within
 * kContactTol_m of z = 0), order[k] on order[k - 1] (the vertices of either within kContactTol_m
 * of the other's convex hull: the planner's faces are hull faces, which may bridge the lumps of a
 * rounded surface), each the convex hull of those points seen from the side. Returns 0, or -1
 * (errno ENOMEM, or EINVAL for a mesh without a convex hull). */
static int svg_supports(FILE *f, const run_args_t *a, const frame_t *fr, const double (*pw)[3],
                        const size_t *first, double (*pts)[2], double (*hull)[2]) {
  model_mesh_t hl[STACK_MAX_OBJECTS];
  double(*hw[STACK_MAX_OBJECTS])[3];
  memset(hl, 0, sizeof hl);
  memset(hw, 0, sizeof hw);
  int rc = 0, err = ENOMEM;
  for (size_t i = 0; i < a->count && a->order != NULL && rc == 0; ++i) {
    const model_status_t ms = model_mesh_hull(a->obj[i].mesh_link, &hl[i], NULL);
    if (ms != MODEL_OK && ms != MODEL_E_NOMEM) err = EINVAL; /* a mesh without a hull */
    rc = ms == MODEL_OK ? 0 : -1;
    hw[i] = rc == 0 ? malloc(hl[i].vertex_count * sizeof *hw[i]) : NULL;
    if (hw[i] == NULL) rc = -1;
    for (size_t v = 0; rc == 0 && v < hl[i].vertex_count; ++v)
      to_world((const double(*)[3])a->rot_plan[i], a->obj[i].planned.position_m,
               hl[i].vertices_m[v], hw[i][v]);
  }
  for (size_t k = 0; a->order != NULL && rc == 0 && k < a->count; ++k) {
    const size_t up = a->order[k];
    const model_mesh_t *mu = a->obj[up].mesh_link;
    size_t n = 0;
    if (k == 0) {
      for (size_t v = 0; v < mu->vertex_count; ++v) {
        const double *p = pw[first[up] + v];
        if (p[2] > kContactTol_m) continue;
        pts[n][0] = p[0];
        pts[n][1] = p[2];
        ++n;
      }
    } else {
      const size_t lo = a->order[k - 1];
      const model_mesh_t *ml = a->obj[lo].mesh_link;
      touching(mu, pw + first[up], &hl[lo], (const double(*)[3])hw[lo], pts, &n);
      touching(ml, pw + first[lo], &hl[up], (const double(*)[3])hw[up], pts, &n);
    }
    if (n == 0) continue;
    char attrs[200];
    snprintf(attrs, sizeof attrs,
             "class=\"support\" data-level=\"%zu\" data-points=\"%zu\" fill=\"#19a34a\" "
             "fill-opacity=\"0.35\" stroke=\"#0b7a33\" stroke-width=\"3\" "
             "stroke-linejoin=\"round\"",
             k, n);
    const size_t nh = model_polygon_hull(pts, n, hull);
    svg_polygon(f, fr, (const double(*)[2])hull, nh, attrs);
  }
  for (size_t i = 0; i < a->count; ++i) {
    model_mesh_free(&hl[i]);
    free(hw[i]);
  }
  if (rc != 0) errno = err;
  return rc;
}

/* A label's box in px, to keep labels apart. */
typedef struct {
  double x0, y0, x1, y1;
} box_t;

static int boxes_meet(const box_t *a, const box_t *b) {
  return a->x0 < b->x1 && b->x0 < a->x1 && a->y0 < b->y1 && b->y0 < a->y1;
}

/* The true CoM (a ringed dot) and the CoM the plan used (a red cross, over the dot) of object i
 * at its final pose, and its name beside it: right of the object (x_m[1]), or left of it (x_m[0])
 * when that would leave the picture, moved down past the labels already placed (placed[0..i)). */
static void svg_object_marks(FILE *f, const run_args_t *a, size_t i, const frame_t *fr,
                             const double x_m[2], box_t *placed, size_t *nplaced) {
  const stack_svg_object_t *o = &a->obj[i];
  const char *name = o->name ? o->name : "object";
  double wt[3], wu[3];
  to_world((const double(*)[3])a->rot_final[i], o->final.position_m, o->com_true_m, wt);
  to_world((const double(*)[3])a->rot_final[i], o->final.position_m, o->com_used_m, wu);
  fprintf(f,
          "<circle class=\"com-true\" data-object=\"%zu\" data-world-m=\"%.9g %.9g %.9g\" "
          "cx=\"%.2f\" cy=\"%.2f\" r=\"4\" fill=\"#111\" stroke=\"#fff\" stroke-width=\"1.5\"/>\n",
          i, wt[0], wt[1], wt[2], px_x(fr, wt[0]), px_y(fr, wt[2]));
  const double ux = px_x(fr, wu[0]), uy = px_y(fr, wu[2]), r = 6.0;
  fprintf(f,
          "<path class=\"com-used\" data-object=\"%zu\" data-world-m=\"%.9g %.9g %.9g\" "
          "d=\"M%.1f %.1fL%.1f %.1fM%.1f %.1fL%.1f %.1f\" stroke=\"#d4001f\" stroke-width=\"2\" "
          "fill=\"none\"/>\n",
          i, wu[0], wu[1], wu[2], ux - r, uy - r, ux + r, uy + r, ux - r, uy + r, ux + r, uy - r);
  const double w = 7.0 * (double)strlen(name); /* about 7 px per character at 12 px */
  box_t b = {px_x(fr, x_m[1]) + 6.0, px_y(fr, wt[2]) - 8.0, 0.0, 0.0};
  int end = 0;
  if (b.x0 + w > kWidth_px - 4.0) {
    b.x0 = px_x(fr, x_m[0]) - 6.0 - w;
    end = 1;
  }
  if (b.x0 < 4.0) b.x0 = 4.0, end = 0;
  b.x1 = b.x0 + w;
  b.y1 = b.y0 + 14.0;
  for (int moved = 1, guard = 0; moved && guard < 16; ++guard) {
    moved = 0;
    for (size_t k = 0; k < *nplaced; ++k)
      if (boxes_meet(&b, &placed[k])) {
        b.y0 = placed[k].y1 + 1.0;
        b.y1 = b.y0 + 14.0;
        moved = 1;
      }
  }
  placed[(*nplaced)++] = b;
  fprintf(f,
          "<text class=\"name\" data-object=\"%zu\" x=\"%.1f\" y=\"%.1f\" font-size=\"12\"%s "
          "stroke=\"#fbfaf7\" stroke-width=\"3\" paint-order=\"stroke\">",
          i, end ? b.x1 : b.x0, b.y0 + 12.0, end ? " text-anchor=\"end\"" : "");
  cli_svg_text(f, name);
  fprintf(f, "</text>\n");
}

/* The legend rows under B: what each mark means; objects that fell off B by name. */
static void svg_run_legend(FILE *f, const run_args_t *a, double top_px, const unsigned char *off) {
  const double y1 = top_px + 48.0, y2 = top_px + 70.0, x = kMargin_px;
  fprintf(f,
          "<path d=\"M%.1f %.1fh22\" stroke=\"#5a5a5a\" stroke-width=\"1.3\" "
          "stroke-dasharray=\"5 3\"/><text x=\"%.1f\" y=\"%.1f\" font-size=\"12\">planned "
          "(release) pose</text>\n",
          x, y1 - 4.0, x + 28.0, y1);
  fprintf(f,
          "<rect x=\"%.1f\" y=\"%.1f\" width=\"22\" height=\"6\" fill=\"#19a34a\" "
          "fill-opacity=\"0.35\" stroke=\"#0b7a33\" stroke-width=\"2\"/><text x=\"%.1f\" "
          "y=\"%.1f\" font-size=\"12\">support polygon of the plan (side view)</text>\n",
          x + 170.0, y1 - 7.0, x + 198.0, y1);
  fprintf(f,
          "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"4\" fill=\"#111\" stroke=\"#fff\" "
          "stroke-width=\"1.5\"/><text x=\"%.1f\" y=\"%.1f\" font-size=\"12\">true CoM "
          "(URDF)</text>\n",
          x + 8.0, y2 - 4.0, x + 28.0, y2);
  fprintf(f,
          "<path d=\"M%.1f %.1fl10 10M%.1f %.1fl10 -10\" stroke=\"#d4001f\" stroke-width=\"2\"/>"
          "<text x=\"%.1f\" y=\"%.1f\" font-size=\"12\">",
          x + 165.0, y2 - 9.0, x + 165.0, y2 + 1.0, x + 181.0, y2);
  cli_svg_text(f, a->com_label ? a->com_label : "believed");
  fprintf(f, " CoM (used by the plan)</text>\n");
  fprintf(f,
          "<text x=\"%.1f\" y=\"%.1f\" font-size=\"12\">shaded: every object as the simulation "
          "left it</text>\n",
          x, y2 + 20.0);
  double ly = y2 + 40.0;
  for (size_t i = 0; i < a->count; ++i) {
    if (!off[i]) continue;
    fprintf(f, "<text class=\"off-b\" data-object=\"%zu\" x=\"%.1f\" y=\"%.1f\" font-size=\"12\">",
            i, x, ly);
    cli_svg_text(f, a->obj[i].name ? a->obj[i].name : "object");
    fprintf(f, ": fell off B (not drawn at its final pose)</text>\n");
    ly += 16.0;
  }
}

/* Everything of stack_svg_write_run after the checks; 0 or -1 (ENOMEM). */
static int run_body(FILE *f, const void *ctx) {
  const run_args_t *a = ctx;
  const model_mesh_t *meshes[STACK_MAX_OBJECTS] = {NULL};
  model_pose_t finals[STACK_MAX_OBJECTS];
  memset(finals, 0, sizeof finals);
  unsigned char off[STACK_MAX_OBJECTS] = {0};
  size_t first[STACK_MAX_OBJECTS], total = 0, most = 0, noff = 0;
  for (size_t i = 0; i < a->count; ++i) {
    meshes[i] = a->obj[i].mesh_link;
    finals[i] = a->obj[i].final;
    first[i] = total;
    total += meshes[i]->vertex_count;
    if (meshes[i]->vertex_count > most) most = meshes[i]->vertex_count;
    double lowest = HUGE_VAL, w[3];
    for (size_t v = 0; v < meshes[i]->vertex_count; ++v) {
      to_world((const double(*)[3])a->rot_final[i], finals[i].position_m, meshes[i]->vertices_m[v],
               w);
      lowest = fmin(lowest, w[2]);
    }
    off[i] = lowest < -kOffB_m;
    noff += off[i];
  }
  scene_t s;
  if (scene_build(meshes, finals, a->count, a->rot_final, off, &s) != 0) return -1;
  double(*pw)[3] = planned_world(a, first, total);
  double(*pts)[2] = malloc(2 * (most ? most : 1) * sizeof *pts);
  double(*hull)[2] = malloc((4 * most + 2) * sizeof *hull);
  if (pw == NULL || pts == NULL || hull == NULL) {
    free(pw);
    free(pts);
    free(hull);
    scene_free(&s);
    errno = ENOMEM;
    return -1;
  }
  double xr[STACK_MAX_OBJECTS][2]; /* each object's final x range */
  for (size_t i = 0; i < a->count; ++i) {
    xr[i][0] = HUGE_VAL;
    xr[i][1] = -HUGE_VAL;
    for (size_t v = 0; v < meshes[i]->vertex_count; ++v) {
      const double *p = pw[first[i] + v];
      s.lo[0] = fmin(s.lo[0], p[0]);
      s.hi[0] = fmax(s.hi[0], p[0]);
      s.lo[1] = fmin(s.lo[1], p[2]);
      s.hi[1] = fmax(s.hi[1], p[2]);
      if (off[i]) continue;
      xr[i][0] = fmin(xr[i][0], s.world[first[i] + v][0]);
      xr[i][1] = fmax(xr[i][1], s.world[first[i] + v][0]);
    }
  }
  frame_t fr;
  double height;
  frame_fit(&s, kRunLegend_px + 16.0 * (double)noff, &fr, &height);
  svg_head(f, height, (const unsigned char(*)[SHADE_LEVELS])s.used, a->title);
  fprintf(f,
          "<g class=\"frame\" data-scale-px-m=\"%.17g\" data-x0-m=\"%.17g\" data-z0-m=\"%.17g\" "
          "data-ox-px=\"%.17g\" data-oy-px=\"%.17g\"/>\n",
          fr.scale_px_m, fr.x0_m, fr.z0_m, fr.ox_px, fr.oy_px);
  const double top_px = px_y(&fr, 0.0);
  svg_support(f, top_px);
  svg_faces(f, meshes, &s, &fr);
  svg_planned(f, a, &fr, (const double(*)[3])pw, first, pts, hull);
  int rc = svg_supports(f, a, &fr, (const double(*)[3])pw, first, pts, hull);
  box_t placed[STACK_MAX_OBJECTS];
  size_t nplaced = 0;
  for (size_t i = 0; i < a->count; ++i)
    if (!off[i]) svg_object_marks(f, a, i, &fr, xr[i], placed, &nplaced);
  svg_scale_bar(f, &fr, top_px, 0);
  svg_run_legend(f, a, top_px, off);
  fprintf(f, "</svg>\n");
  free(pw);
  free(pts);
  free(hull);
  scene_free(&s);
  return rc;
}

int stack_svg_write_run(const char *path, const stack_svg_object_t *objects, size_t count,
                        const size_t *order, const char *com_label, const char *title) {
  if (path == NULL || path[0] == '\0' || objects == NULL || count == 0 ||
      count > STACK_MAX_OBJECTS) {
    errno = EINVAL;
    return -1;
  }
  double rot_final[STACK_MAX_OBJECTS][3][3], rot_plan[STACK_MAX_OBJECTS][3][3];
  unsigned char seen[STACK_MAX_OBJECTS] = {0};
  for (size_t i = 0; i < count; ++i) {
    const stack_svg_object_t *o = &objects[i];
    if (!mesh_ok(o->mesh_link) || !pose_rot(&o->final, rot_final[i]) ||
        !pose_rot(&o->planned, rot_plan[i]) || !finite3(o->com_used_m) || !finite3(o->com_true_m) ||
        (order != NULL && (order[i] >= count || seen[order[i]]++))) {
      errno = EINVAL;
      return -1;
    }
  }
  const run_args_t a = {objects, count, order, com_label, title, rot_final, rot_plan};
  return write_via_tmp(path, run_body, &a);
}
