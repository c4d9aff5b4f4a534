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

static void xml_text(FILE *f, const char *s) {
  for (; *s != '\0'; ++s) {
    switch (*s) {
      case '&': fputs("&amp;", f); break;
      case '<': fputs("&lt;", f); break;
      case '>': fputs("&gt;", f); break;
      case '"': fputs("&quot;", f); break;
      default: fputc(*s, f); break;
    }
  }
}

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
                       double (*rot)[3][3], scene_t *s) {
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
static void frame_fit(const scene_t *s, frame_t *fr, double *height_px) {
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
  *height_px = fr->oy_px + kBelow_px + 20.0;
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
    xml_text(f, title);
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
  if (scene_build(meshes, poses, count, rot, &s) != 0) return -1;
  frame_t fr;
  double height;
  frame_fit(&s, &fr, &height);
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
    const model_mesh_t *m = meshes_link[i];
    if (m == NULL || m->vertices_m == NULL || m->triangles == NULL || m->vertex_count == 0 ||
        m->triangle_count == 0 || !pose_rot(&poses[i], rot[i]) ||
        (com_link_m != NULL && !finite3(com_link_m[i]))) {
      errno = EINVAL;
      return -1;
    }
    for (size_t v = 0; v < m->vertex_count; ++v) {
      if (!finite3(m->vertices_m[v])) {
        errno = EINVAL;
        return -1;
      }
    }
    for (size_t t = 0; t < m->triangle_count; ++t) {
      for (int k = 0; k < 3; ++k) {
        if (m->triangles[t][k] >= m->vertex_count) {
          errno = EINVAL;
          return -1;
        }
      }
    }
  }
  char tmp[4096];
  if ((size_t)snprintf(tmp, sizeof tmp, "%s.tmp", path) >= sizeof tmp) {
    errno = ENAMETOOLONG;
    return -1;
  }
  FILE *f = fopen(tmp, "w");
  if (f == NULL) return -1;
  errno = 0;
  int rc = render(f, meshes_link, poses, com_link_m, count, title, rot);
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
