/* estimate_svg.c - the picture of one estimate (estimate_svg_write, estimate_svg.h).
 *
 * The three link-frame views are painted with the painter's algorithm (back faces culled, the
 * rest far to near, flat Lambert shading in SHADES CSS classes); the trial strip draws outlines
 * only (the 2-D convex hull of the projected vertices), which keeps the file near 300 KB for a
 * 2000-triangle rock. Coordinates in px with three decimals, projections in the data attributes
 * with nine digits: a reader maps a marker back to metres well under a pixel. Geometry and the
 * estimator's report only; the truth only when the caller passes it. */
#define _POSIX_C_SOURCE 200809L

#include "estimate_svg.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "comlearn/cli_svg.h"
#include "comlearn/math3d.h"
#include "comlearn/model_support.h"
#include "estimate_backend.h"

enum { SHADES = 24, VIEWS = 3, TRIALS_PER_ROW = 4, WRAP_CHARS = 140 };

static const double kWidth_px = 960.0;
static const double kPad_px = 15.0;    /* picture sides and gaps between panels */
static const double kPanel_px = 300.0; /* a main view, square */
static const double kRow0_px = 64.0;   /* top of the main views */
static const double kZoomH_px = 190.0; /* a zoomed view */
static const double kLine_px = 15.0;   /* a legend line */
static const double kTrialH_px = 170.0;
static const double kTrialText_px = 44.0;             /* three lines under a trial's drawing */
static const double kTint[3] = {190.0, 160.0, 124.0}; /* the object's colour, lit */

static const char *const kViewId[VIEWS] = {"front", "side", "top"};
static const char *const kViewText[VIEWS] = {"front: x right, z up (seen from -y)",
                                             "side: y right, z up (seen from +x)",
                                             "top: x right, y up (seen from +z)"};
static const int kAxisU[VIEWS] = {0, 1, 0}, kAxisV[VIEWS] = {2, 2, 1};
static const char kAxis[3] = {'x', 'y', 'z'};

typedef struct {
  double r[3], u[3], t[3]; /* drawn right, drawn up, toward the viewer (r x u) */
} view_t;

/* A panel and its projection: px = ox + s (u - u0), py = oy - s (v - v0). */
typedef struct {
  double s, u0, v0, ox, oy;
  double x, y, w, h;
} map_t;

static double px_u(const map_t *m, double u) { return m->ox + m->s * (u - m->u0); }
static double px_v(const map_t *m, double v) { return m->oy - m->s * (v - m->v0); }

static void view_link(int i, view_t *v) {
  memset(v, 0, sizeof *v);
  v->r[kAxisU[i]] = 1.0;
  v->u[kAxisV[i]] = 1.0;
  cl_vec3_cross(v->r, v->u, v->t);
}

static const char *outcome_colour(estimate_outcome_t o) {
  return o == ESTIMATE_STAYS ? "#2e8b57" : (o == ESTIMATE_TIPS ? "#c0392b" : "#888888");
}

/* A pose with its quaternion normalised (the released and settled poses are unit to rounding). */
static void pose_unit(const model_pose_t *p, model_pose_t *out) {
  *out = *p;
  (void)cl_quat_normalize(p->orientation_wxyz, out->orientation_wxyz);
}

/* ---- the painted mesh ----------------------------------------------------------------------- */

typedef struct {
  double depth;
  size_t tri;
  int level;
} tri_t;

static int cmp_tri(const void *pa, const void *pb) {
  const tri_t *a = pa, *b = pb;
  if (a->depth != b->depth) return a->depth < b->depth ? -1 : 1; /* far (small t) first */
  return a->tri < b->tri ? -1 : (a->tri > b->tri ? 1 : 0);
}

/* One visible triangle's depth and shade; 0 when it faces away. */
static int tri_shade(const double *a, const double *b, const double *c, const view_t *v,
                     tri_t *out) {
  static const double kLight[3] = {-0.40, 0.55, 0.733}; /* view coordinates: upper left, front */
  double e1[3], e2[3], n[3];
  cl_vec3_sub(b, a, e1);
  cl_vec3_sub(c, a, e2);
  cl_vec3_cross(e1, e2, n);
  const double len = cl_vec3_norm(n), nt = cl_vec3_dot(n, v->t);
  if (!(nt > 0.0) || !(len > 0.0)) return 0;
  double lambert =
      (cl_vec3_dot(n, v->r) * kLight[0] + cl_vec3_dot(n, v->u) * kLight[1] + nt * kLight[2]) / len;
  if (lambert < 0.0) lambert = 0.0;
  if (lambert > 1.0) lambert = 1.0;
  out->depth = (cl_vec3_dot(a, v->t) + cl_vec3_dot(b, v->t) + cl_vec3_dot(c, v->t)) / 3.0;
  out->level = (int)(lambert * (SHADES - 1) + 0.5);
  return 1;
}

/* The mesh (link frame) seen in view v, far to near, with tl room for every triangle. */
static void draw_mesh(FILE *f, const model_mesh_t *m, const view_t *v, const map_t *mp, tri_t *tl) {
  size_t n = 0;
  for (size_t t = 0; t < m->triangle_count; ++t) {
    const uint32_t *tri = m->triangles[t];
    if (tri_shade(m->vertices_m[tri[0]], m->vertices_m[tri[1]], m->vertices_m[tri[2]], v, &tl[n])) {
      tl[n].tri = t;
      ++n;
    }
  }
  qsort(tl, n, sizeof *tl, cmp_tri);
  fprintf(f, "<g class=\"mesh\" stroke-width=\"0.4\" stroke-linejoin=\"round\">\n");
  for (size_t i = 0; i < n; ++i) {
    const uint32_t *tri = m->triangles[tl[i].tri];
    fprintf(f, "<polygon class=\"s%d\" points=\"", tl[i].level);
    for (int j = 0; j < 3; ++j) {
      const double *p = m->vertices_m[tri[j]];
      fprintf(f, "%s%.2f,%.2f", j ? " " : "", px_u(mp, cl_vec3_dot(p, v->r)),
              px_v(mp, cl_vec3_dot(p, v->u)));
    }
    fprintf(f, "\"/>\n");
  }
  fprintf(f, "</g>\n");
}

/* ---- outlines ------------------------------------------------------------------------------- */

static int cmp_xy(const void *pa, const void *pb) {
  const double *a = pa, *b = pb;
  if (a[0] != b[0]) return a[0] < b[0] ? -1 : 1;
  return a[1] < b[1] ? -1 : (a[1] > b[1] ? 1 : 0);
}

static double turn(const double *o, const double *a, const double *b) {
  return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

/* Convex hull of n points (sorted in place) into out (room for n + 1): Andrew's monotone chain.
 * Returns its vertex count. */
static size_t hull2d(double (*p)[2], size_t n, double (*out)[2]) {
  if (n < 3) {
    memcpy(out, p, n * sizeof *p);
    return n;
  }
  qsort(p, n, sizeof *p, cmp_xy);
  size_t k = 0;
  for (size_t i = 0; i < n; ++i) { /* lower */
    while (k >= 2 && turn(out[k - 2], out[k - 1], p[i]) <= 0.0) --k;
    memcpy(out[k++], p[i], sizeof *p);
  }
  const size_t lower = k + 1;
  for (size_t i = n - 1; i-- > 0;) { /* upper */
    while (k >= lower && turn(out[k - 2], out[k - 1], p[i]) <= 0.0) --k;
    memcpy(out[k++], p[i], sizeof *p);
  }
  return k - 1; /* the last point is the first */
}

static void polygon(FILE *f, const double (*p)[2], size_t n, const char *attrs) {
  fprintf(f, "<polygon %s points=\"", attrs);
  for (size_t i = 0; i < n; ++i) fprintf(f, "%s%.2f,%.2f", i ? " " : "", p[i][0], p[i][1]);
  fprintf(f, "\"/>\n");
}

/* ---- markers, boxes, lines ------------------------------------------------------------------ */

static void marker_est(FILE *f, const char *view, double x, double y) {
  fprintf(f,
          "<circle class=\"com-est\" data-view=\"%s\" cx=\"%.3f\" cy=\"%.3f\" r=\"5\" "
          "fill=\"none\" stroke=\"#ffffff\" stroke-width=\"3.5\"/>\n",
          view, x, y);
  fprintf(f,
          "<circle cx=\"%.3f\" cy=\"%.3f\" r=\"5\" fill=\"none\" stroke=\"#1f4fbf\" "
          "stroke-width=\"1.8\"/><path d=\"M%.3f %.3fh14M%.3f %.3fv14\" stroke=\"#1f4fbf\" "
          "stroke-width=\"1\"/>\n",
          x, y, x - 7.0, y, x, y - 7.0);
}

static void marker_truth(FILE *f, const char *view, double x, double y) {
  fprintf(f,
          "<circle class=\"com-truth\" data-view=\"%s\" cx=\"%.3f\" cy=\"%.3f\" r=\"2.6\" "
          "fill=\"#d62728\" stroke=\"#ffffff\" stroke-width=\"1\"/>\n",
          view, x, y);
}

/* The interval of components ua (right) and va (up) in a view: a box, or a band across the view
 * for a component not found. */
static void draw_interval(FILE *f, const map_t *m, const char *view, const estimate_result_t *r,
                          int ua, int va) {
  const int fu = r->found[ua] && isfinite(r->halfwidth_m[ua]);
  const int fv = r->found[va] && isfinite(r->halfwidth_m[va]);
  double x0 = m->x, x1 = m->x + m->w, y0 = m->y, y1 = m->y + m->h;
  if (fu) {
    x0 = px_u(m, r->com_m[ua] - r->halfwidth_m[ua]);
    x1 = px_u(m, r->com_m[ua] + r->halfwidth_m[ua]);
  }
  if (fv) {
    y0 = px_v(m, r->com_m[va] + r->halfwidth_m[va]);
    y1 = px_v(m, r->com_m[va] - r->halfwidth_m[va]);
  }
  const char *unb = !fu && !fv ? "uv" : (!fu ? "u" : (!fv ? "v" : NULL));
  fprintf(f, "<rect class=\"interval\" data-view=\"%s\"", view);
  if (unb) fprintf(f, " data-unbounded=\"%s\"", unb);
  fprintf(f,
          " x=\"%.3f\" y=\"%.3f\" width=\"%.3f\" height=\"%.3f\" fill=\"%s\" fill-opacity=\"%s\" "
          "stroke=\"#1f4fbf\" stroke-width=\"1\"%s/>\n",
          x0, y0, x1 - x0, y1 - y0, unb ? "#f0a030" : "#6f9fef", unb ? "0.22" : "0.35",
          unb ? " stroke-dasharray=\"4 3\"" : "");
}

/* The edge of B an edge trial was set over: the one its target link point lies nearest to at the
 * released pose (the request put it exactly over that edge; a robot misses by its placement
 * error). 1 with the edge's outward normal and offset (comlearn/model_support.h), or 0 for a
 * stable check. */
static int trial_edge(const estimate_trial_t *t, const double base[3], double normal[3],
                      double *offset_m) {
  if (t->kind != ESTIMATE_TRIAL_EDGE) return 0;
  model_pose_t p;
  double w[3], best = HUGE_VAL;
  pose_unit(&t->released, &p);
  cl_pose_apply(&p, t->target_link_m, w);
  for (int e = MODEL_EDGE_PX; e <= MODEL_EDGE_NY; ++e) {
    double n[3], d;
    model_edge_line(base, (model_edge_t)e, n, &d);
    const double miss = fabs(cl_vec3_dot(n, w) - d);
    if (miss < best) {
      best = miss;
      memcpy(normal, n, sizeof n);
      *offset_m = d;
    }
  }
  return 1;
}

/* Clip the line q + s d to the box [lo, hi] (slabs): 1 and the ends, or 0 when it misses. */
static int clip_line(const double q[3], const double d[3], const double lo[3], const double hi[3],
                     double a[3], double b[3]) {
  double s0 = -HUGE_VAL, s1 = HUGE_VAL;
  for (int k = 0; k < 3; ++k) {
    if (fabs(d[k]) < 1e-12) {
      if (q[k] < lo[k] || q[k] > hi[k]) return 0;
      continue;
    }
    double ta = (lo[k] - q[k]) / d[k], tb = (hi[k] - q[k]) / d[k];
    if (ta > tb) {
      const double x = ta;
      ta = tb;
      tb = x;
    }
    if (ta > s0) s0 = ta;
    if (tb < s1) s1 = tb;
  }
  if (!(s0 < s1)) return 0;
  for (int k = 0; k < 3; ++k) {
    a[k] = q[k] + s0 * d[k];
    b[k] = q[k] + s1 * d[k];
  }
  return 1;
}

/* Every edge trial's edge line (B's top edge, world z = 0), in the link frame at its released
 * pose, within the box [lo, hi]. */
static void draw_edge_lines(FILE *f, const estimate_svg_input_t *in, const view_t *v,
                            const map_t *m, const double lo[3], const double hi[3]) {
  const estimate_result_t *r = in->result;
  fprintf(f, "<g class=\"edge-lines\" stroke-width=\"1\" stroke-opacity=\"0.7\">\n");
  for (size_t i = 0; i < r->trial_count; ++i) {
    const estimate_trial_t *t = &r->trial[i];
    double n[3], d, a[3], b[3];
    if (!trial_edge(t, in->base_size_m, n, &d)) continue;
    const double z[3] = {0, 0, 1}, on_edge[3] = {d * n[0], d * n[1], 0.0};
    double along[3], rel[3], q[3], dir[3], inv[4];
    model_pose_t p;
    pose_unit(&t->released, &p);
    cl_vec3_cross(z, n, along);
    cl_quat_conj(p.orientation_wxyz, inv);
    cl_vec3_sub(on_edge, p.position_m, rel);
    cl_quat_rotate(inv, rel, q);
    cl_quat_rotate(inv, along, dir);
    if (!clip_line(q, dir, lo, hi, a, b)) continue;
    fprintf(f,
            "<path class=\"edge-line\" data-trial=\"%zu\" d=\"M%.2f %.2fL%.2f %.2f\" "
            "stroke=\"%s\"%s/>\n",
            i + 1, px_u(m, cl_vec3_dot(a, v->r)), px_v(m, cl_vec3_dot(a, v->u)),
            px_u(m, cl_vec3_dot(b, v->r)), px_v(m, cl_vec3_dot(b, v->u)),
            outcome_colour(t->outcome), t->flagged ? " stroke-dasharray=\"3 2\"" : "");
  }
  fprintf(f, "</g>\n");
}

/* The support polygon of every confirmed face (model_patch_resting at the first trial released on
 * it), outlined in the link frame. */
static void draw_faces(FILE *f, const estimate_svg_input_t *in, const view_t *v, const map_t *m,
                       model_patch_t *patch) {
  const estimate_result_t *r = in->result;
  for (size_t fi = 0; fi < r->face_count; ++fi) {
    if (!r->face[fi].confirmed) continue;
    size_t ti = 0;
    while (ti < r->trial_count && r->trial[ti].face != (int)fi) ++ti;
    if (ti == r->trial_count) continue;
    model_pose_t p;
    pose_unit(&r->trial[ti].released, &p);
    if (model_patch_resting(in->mesh_link, &p, NULL, patch) != MODEL_OK || patch->vertex_count < 3)
      continue;
    double pts[MODEL_PATCH_MAX_VERTICES][2], inv[4], cu = 0.0, cv = 0.0;
    cl_quat_conj(p.orientation_wxyz, inv);
    for (size_t k = 0; k < patch->vertex_count; ++k) {
      const double w[3] = {patch->polygon_xy_m[k][0] - p.position_m[0],
                           patch->polygon_xy_m[k][1] - p.position_m[1],
                           patch->support_z_m - p.position_m[2]};
      double l[3];
      cl_quat_rotate(inv, w, l);
      pts[k][0] = px_u(m, cl_vec3_dot(l, v->r));
      pts[k][1] = px_v(m, cl_vec3_dot(l, v->u));
      cu += pts[k][0] / (double)patch->vertex_count;
      cv += pts[k][1] / (double)patch->vertex_count;
    }
    char attrs[96];
    snprintf(attrs, sizeof attrs,
             "class=\"face\" data-face=\"%zu\" fill=\"none\" stroke=\"#7b3fa0\" "
             "stroke-width=\"2\"",
             fi);
    polygon(f, (const double(*)[2])pts, patch->vertex_count, attrs);
    const int left = cu + 45.0 > m->x + m->w; /* keep the label inside the view */
    fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-size=\"10\" fill=\"#7b3fa0\"%s>face %zu</text>\n",
            left ? cu - 3.0 : cu + 3.0, cv - 3.0, left ? " text-anchor=\"end\"" : "", fi);
  }
}

/* ---- views ---------------------------------------------------------------------------------- */

/* A view's frame, clip path and group, with its projection in data attributes. */
static void view_open(FILE *f, const char *id, int ua, int va, const map_t *m, const char *label) {
  fprintf(f,
          "<clipPath id=\"clip-%s\"><rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" "
          "height=\"%.1f\"/></clipPath>\n",
          id, m->x, m->y, m->w, m->h);
  fprintf(f,
          "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"#ffffff\" "
          "stroke=\"#b8b8b8\"/>\n",
          m->x, m->y, m->w, m->h);
  fprintf(f,
          "<g class=\"view\" id=\"%s\" data-u=\"%c\" data-v=\"%c\" data-px-per-m=\"%.9g\" "
          "data-u0-m=\"%.9g\" data-v0-m=\"%.9g\" data-ox-px=\"%.9g\" data-oy-px=\"%.9g\" "
          "clip-path=\"url(#clip-%s)\">\n",
          id, kAxis[ua], kAxis[va], m->s, m->u0, m->v0, m->ox, m->oy, id);
  fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-size=\"11\" fill=\"#333\">", m->x + 5.0,
          m->y + 14.0);
  cli_svg_text(f, label);
  fprintf(f, "</text>\n");
}

/* A scale bar of 1, 2 or 5 x 10^n m, 40-100 px long, at the panel's lower right. */
static void scale_bar(FILE *f, const map_t *m) {
  static const double kMant[] = {1.0, 2.0, 5.0, 10.0};
  const double base = pow(10.0, floor(log10(40.0 / m->s))); /* base * s in (4, 40] */
  double len = base;
  for (int i = 0; i < 3 && len * m->s < 40.0; ++i) len = base * kMant[i + 1];
  const double x1 = m->x + m->w - 10.0, x0 = x1 - len * m->s, y = m->y + m->h - 10.0;
  fprintf(f, "<path d=\"M%.2f %.2fV%.2fH%.2fV%.2f\" stroke=\"#111\" fill=\"none\"/>\n", x0, y - 4.0,
          y, x1, y - 4.0);
  const int um = len < 1e-3;
  fprintf(f, "<text x=\"%.2f\" y=\"%.2f\" font-size=\"10\" text-anchor=\"middle\">%g %s</text>\n",
          0.5 * (x0 + x1), y - 6.0, len * (um ? 1e6 : 1e3), um ? "um" : "mm");
}

/* The estimate, the truth and the interval in a view. */
static void draw_coms(FILE *f, const estimate_svg_input_t *in, const char *id, int ua, int va,
                      const map_t *m) {
  const estimate_result_t *r = in->result;
  draw_interval(f, m, id, r, ua, va);
  marker_est(f, id, px_u(m, r->com_m[ua]), px_v(m, r->com_m[va]));
  if (in->truth_com_m) /* on top: the truth is often within the estimate's marker */
    marker_truth(f, id, px_u(m, in->truth_com_m[ua]), px_v(m, in->truth_com_m[va]));
}

/* Working memory of one picture. */
typedef struct {
  tri_t *tris;       /* a view's visible triangles: triangle_count */
  double (*pts)[2];  /* projected vertices: vertex_count + 1 */
  double (*hull)[2]; /* their hull: vertex_count + 1 */
  model_patch_t *patch;
} work_t;

/* The edge lines' box: the mesh's bounding box grown by 8 % of its largest extent. */
static void line_box(const model_aabb_t *box, double span, double lo[3], double hi[3]) {
  for (int k = 0; k < 3; ++k) {
    lo[k] = box->min_m[k] - 0.08 * span;
    hi[k] = box->max_m[k] + 0.08 * span;
  }
}

/* The three views of the mesh in its link frame, at one scale. */
static void main_views(FILE *f, const estimate_svg_input_t *in, const model_aabb_t *box,
                       double span, work_t *w) {
  double lo[3], hi[3];
  line_box(box, span, lo, hi);
  const double s = (kPanel_px - 50.0) / span;
  for (int i = 0; i < VIEWS; ++i) {
    const int ua = kAxisU[i], va = kAxisV[i];
    map_t m = {.s = s,
               .u0 = 0.5 * (box->min_m[ua] + box->max_m[ua]),
               .v0 = 0.5 * (box->min_m[va] + box->max_m[va]),
               .x = kPad_px + i * (kPanel_px + kPad_px),
               .y = kRow0_px,
               .w = kPanel_px,
               .h = kPanel_px};
    m.ox = m.x + 0.5 * m.w;
    m.oy = m.y + 0.5 * m.h + 6.0;
    view_t v;
    view_link(i, &v);
    view_open(f, kViewId[i], ua, va, &m, kViewText[i]);
    draw_mesh(f, in->mesh_link, &v, &m, w->tris);
    draw_faces(f, in, &v, &m, w->patch);
    draw_edge_lines(f, in, &v, &m, lo, hi);
    draw_coms(f, in, kViewId[i], ua, va, &m);
    fprintf(f, "</g>\n");
    scale_bar(f, &m);
  }
}

/* The three views again, zoomed on the estimate so that the intervals and the truth fit; the edge
 * lines that cross the window too (a search's bracket: its last TIPS on one side, STAYS on the
 * other). */
static void zoom_views(FILE *f, const estimate_svg_input_t *in, const model_aabb_t *box,
                       double span_mesh) {
  const estimate_result_t *r = in->result;
  double span = 0.0, lo[3], hi[3];
  line_box(box, span_mesh, lo, hi);
  for (int k = 0; k < 3; ++k) {
    if (r->found[k] && isfinite(r->halfwidth_m[k]) && r->halfwidth_m[k] > span)
      span = r->halfwidth_m[k];
    if (in->truth_com_m && r->found[k] && fabs(in->truth_com_m[k] - r->com_m[k]) > span)
      span = fabs(in->truth_com_m[k] - r->com_m[k]);
  }
  if (!(span > 1e-6)) span = 1e-6;
  const double s = (0.5 * kZoomH_px - 26.0) / span;
  for (int i = 0; i < VIEWS; ++i) {
    const int ua = kAxisU[i], va = kAxisV[i];
    char id[32], label[96];
    snprintf(id, sizeof id, "%s-zoom", kViewId[i]);
    map_t m = {.s = s,
               .u0 = r->com_m[ua],
               .v0 = r->com_m[va],
               .x = kPad_px + i * (kPanel_px + kPad_px),
               .y = kRow0_px + kPanel_px + kPad_px,
               .w = kPanel_px,
               .h = kZoomH_px};
    m.ox = m.x + 0.5 * m.w;
    m.oy = m.y + 0.5 * m.h + 6.0;
    snprintf(label, sizeof label, "%s zoomed: %c right, %c up, around the estimate", kViewId[i],
             kAxis[ua], kAxis[va]);
    view_t v;
    view_link(i, &v);
    view_open(f, id, ua, va, &m, label);
    fprintf(f,
            "<path d=\"M%.2f %.2fH%.2fM%.2f %.2fV%.2f\" stroke=\"#dddddd\" "
            "stroke-width=\"1\"/>\n",
            m.x, m.oy, m.x + m.w, m.ox, m.y, m.y + m.h);
    draw_edge_lines(f, in, &v, &m, lo, hi);
    draw_coms(f, in, id, ua, va, &m);
    fprintf(f, "</g>\n");
    scale_bar(f, &m);
  }
}

/* ---- the legend ----------------------------------------------------------------------------- */

/* s in lines of at most WRAP_CHARS (broken at spaces) from (x, y), kLine_px apart; with f NULL
 * only counted. Returns the lines. */
static size_t text_wrapped(FILE *f, double x, double y, const char *s) {
  size_t lines = 0, len = strlen(s);
  while (len > 0) {
    size_t n = len;
    if (n > WRAP_CHARS) {
      n = WRAP_CHARS;
      while (n > WRAP_CHARS / 2 && s[n] != ' ') --n;
    }
    if (f) {
      fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-size=\"12\">", x, y + kLine_px * (double)lines);
      char part[WRAP_CHARS + 1];
      memcpy(part, s, n);
      part[n] = '\0';
      cli_svg_text(f, part);
      fprintf(f, "</text>\n");
    }
    ++lines;
    s += n;
    len -= n;
    while (len > 0 && *s == ' ') {
      ++s;
      --len;
    }
  }
  return lines;
}

/* Per axis: estimate +- half width (and the truth, the error), or why it was not found. */
static void axis_text(const estimate_svg_input_t *in, int k, char *buf, size_t size) {
  const estimate_result_t *r = in->result;
  if (!r->found[k]) {
    snprintf(buf, size, "%c: not found (drawn as an unbounded band): %s", kAxis[k],
             r->reason[k][0] ? r->reason[k] : "no reason given");
    return;
  }
  int n = snprintf(buf, size, "%c = %.4f mm +- %.4f mm (%s)", kAxis[k], 1e3 * r->com_m[k],
                   1e3 * r->halfwidth_m[k], r->noisy ? "95 % interval" : "bound");
  if (in->truth_com_m && n > 0 && (size_t)n < size)
    snprintf(buf + n, size - (size_t)n, "; truth %.4f mm, error %+.4f mm", 1e3 * in->truth_com_m[k],
             1e3 * (r->com_m[k] - in->truth_com_m[k]));
}

/* The legend's height, px (legend() draws that many lines). */
static double legend_height(const estimate_svg_input_t *in) {
  char buf[512];
  size_t lines = 2;
  for (int k = 0; k < 3; ++k) {
    axis_text(in, k, buf, sizeof buf);
    lines += text_wrapped(NULL, 0.0, 0.0, buf);
  }
  return kLine_px * (double)lines + 10.0;
}

/* One sample of the legend at (x, y): a marker or line and its text. Returns the next x. */
static double legend_item(FILE *f, double x, double y, const char *svg, const char *text) {
  fprintf(f, "<g transform=\"translate(%.1f %.1f)\">%s</g>\n", x, y - 4.0, svg);
  fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-size=\"11\">%s</text>\n", x + 10.0, y, text);
  return x + 24.0 + 6.4 * (double)strlen(text);
}

static void legend(FILE *f, const estimate_svg_input_t *in, double y) {
  const double x0 = kPad_px + 4.0;
  double x = x0;
  fprintf(f, "<g class=\"legend\">\n");
  x = legend_item(f, x, y,
                  "<circle r=\"5\" fill=\"none\" stroke=\"#1f4fbf\" stroke-width=\"1.8\"/>",
                  "estimate");
  if (in->truth_com_m)
    x = legend_item(f, x, y, "<circle r=\"2.6\" fill=\"#d62728\"/>", "true CoM (--truth)");
  x = legend_item(f, x, y,
                  "<rect x=\"-5\" y=\"-5\" width=\"10\" height=\"10\" fill=\"#6f9fef\" "
                  "fill-opacity=\"0.35\" stroke=\"#1f4fbf\"/>",
                  in->result->noisy ? "95 % interval" : "bound");
  x = legend_item(f, x, y,
                  "<rect x=\"-5\" y=\"-5\" width=\"10\" height=\"10\" fill=\"#f0a030\" "
                  "fill-opacity=\"0.22\" stroke=\"#1f4fbf\" stroke-dasharray=\"4 3\"/>",
                  "not found: unbounded");
  x = legend_item(f, x, y, "<path d=\"M-6 0h12\" stroke=\"#2e8b57\" stroke-width=\"2\"/>",
                  "edge line: stayed");
  x = legend_item(f, x, y, "<path d=\"M-6 0h12\" stroke=\"#c0392b\" stroke-width=\"2\"/>",
                  "tipped");
  x = legend_item(f, x, y, "<path d=\"M-6 0h12\" stroke=\"#888888\" stroke-width=\"2\"/>",
                  "unclear");
  (void)legend_item(f, x, y, "<path d=\"M-6 0h12\" stroke=\"#7b3fa0\" stroke-width=\"2\"/>",
                    "resting face used");
  double ly = y + 1.5 * kLine_px;
  char buf[512];
  for (int k = 0; k < 3; ++k) {
    axis_text(in, k, buf, sizeof buf);
    ly += kLine_px * (double)text_wrapped(f, x0, ly, buf);
  }
  fprintf(f, "</g>\n");
}

/* ---- the trial strip ------------------------------------------------------------------------ */

/* How a trial panel sees the world: u = right . p - u_edge (0 at the edge, B to the left), v = z;
 * stable checks: u = x, centred on B. */
typedef struct {
  double right[3], u_edge, b_lo, b_hi; /* B spans u in [b_lo, b_hi], z in [-sz, 0] */
  char label[24];
} trial_view_t;

static void trial_view(const estimate_svg_input_t *in, const estimate_trial_t *t,
                       trial_view_t *tv) {
  double n[3], d;
  memset(tv, 0, sizeof *tv);
  if (trial_edge(t, in->base_size_m, n, &d)) {
    memcpy(tv->right, n, sizeof n);
    tv->u_edge = d;
    tv->b_lo = -2.0 * d;
    tv->b_hi = 0.0;
    snprintf(tv->label, sizeof tv->label, "edge %c%c", n[0] + n[1] > 0.0 ? '+' : '-',
             fabs(n[0]) > 0.5 ? 'x' : 'y');
  } else {
    tv->right[0] = 1.0;
    tv->b_lo = -0.5 * in->base_size_m[0];
    tv->b_hi = 0.5 * in->base_size_m[0];
    snprintf(tv->label, sizeof tv->label, "stable check");
  }
}

/* The object's outline at pose p in panel m (the hull of its projected vertices). */
static void trial_outline(FILE *f, const estimate_svg_input_t *in, const trial_view_t *tv,
                          const model_pose_t *pose, const map_t *m, const char *attrs, work_t *w) {
  const model_mesh_t *mesh = in->mesh_link;
  model_pose_t p;
  pose_unit(pose, &p);
  for (size_t i = 0; i < mesh->vertex_count; ++i) {
    double q[3];
    cl_pose_apply(&p, mesh->vertices_m[i], q);
    w->pts[i][0] = px_u(m, cl_vec3_dot(tv->right, q) - tv->u_edge);
    w->pts[i][1] = px_v(m, q[2]);
  }
  const size_t n = hull2d(w->pts, mesh->vertex_count, w->hull);
  polygon(f, (const double(*)[2])w->hull, n, attrs);
}

/* The estimate at pose p in panel m: a cross. */
static void trial_com(FILE *f, const estimate_svg_input_t *in, const trial_view_t *tv,
                      const model_pose_t *pose, const map_t *m, const char *colour) {
  model_pose_t p;
  double q[3];
  pose_unit(pose, &p);
  cl_pose_apply(&p, in->result->com_m, q);
  const double x = px_u(m, cl_vec3_dot(tv->right, q) - tv->u_edge), y = px_v(m, q[2]);
  fprintf(f, "<path d=\"M%.2f %.2fl8 8m0 -8l-8 8\" stroke=\"%s\" stroke-width=\"1.6\"/>\n", x - 4.0,
          y - 4.0, colour);
}

/* One trial's panel at (x, y), w x kTrialH_px, at scale s (px per m). */
static void trial_panel(FILE *f, const estimate_svg_input_t *in, size_t i, double x, double y,
                        double w, double s, work_t *wk) {
  const estimate_trial_t *t = &in->result->trial[i];
  trial_view_t tv;
  trial_view(in, t, &tv);
  model_pose_t rel;
  pose_unit(&t->released, &rel);
  /* centred on the edge (stable checks: on the released link origin), the released pose's link
   * origin at mid height */
  const double u_mid = t->kind == ESTIMATE_TRIAL_EDGE ? 0.0 : rel.position_m[0];
  map_t m = {.s = s, .u0 = u_mid, .v0 = rel.position_m[2], .x = x, .y = y, .w = w, .h = kTrialH_px};
  m.ox = x + 0.5 * w;
  m.oy = y + 0.5 * (kTrialH_px - kTrialText_px) + 4.0;
  fprintf(f, "<g class=\"trial\" data-trial=\"%zu\" data-kind=\"%s\" data-outcome=\"%s\">\n", i + 1,
          t->kind == ESTIMATE_TRIAL_EDGE ? "edge" : "stable", trial_outcome_name(t->outcome));
  fprintf(f,
          "<clipPath id=\"clip-trial-%zu\"><rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" "
          "height=\"%.1f\"/></clipPath>\n",
          i + 1, x, y, w, kTrialH_px - kTrialText_px);
  fprintf(f,
          "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"#ffffff\" "
          "stroke=\"#b8b8b8\"/>\n<g clip-path=\"url(#clip-trial-%zu)\">\n",
          x, y, w, kTrialH_px, i + 1);
  const double bx0 = px_u(&m, tv.b_lo), bx1 = px_u(&m, tv.b_hi), by0 = px_v(&m, 0.0);
  fprintf(f,
          "<rect class=\"block\" x=\"%.2f\" y=\"%.2f\" width=\"%.2f\" height=\"%.2f\" "
          "fill=\"#d0d0d0\" stroke=\"#909090\"/>\n",
          bx0, by0, bx1 - bx0, s * in->base_size_m[2]);
  const char *col = outcome_colour(t->outcome);
  char attrs[160];
  snprintf(attrs, sizeof attrs,
           "class=\"settled\" fill=\"%s\" fill-opacity=\"0.3\" stroke=\"%s\" stroke-width=\"1\"",
           col, col);
  trial_outline(f, in, &tv, &t->settled, &m, attrs, wk);
  trial_outline(f, in, &tv, &t->released, &m,
                "class=\"released\" fill=\"none\" stroke=\"#333333\" stroke-width=\"1.2\" "
                "stroke-dasharray=\"4 3\"",
                wk);
  if (t->kind == ESTIMATE_TRIAL_EDGE) /* the edge's vertical: which side the CoM is on */
    fprintf(f,
            "<path d=\"M%.2f %.2fV%.2f\" stroke=\"#606060\" stroke-width=\"0.8\" "
            "stroke-dasharray=\"2 2\"/>\n",
            bx1, by0, y);
  trial_com(f, in, &tv, &t->released, &m, "#333333");
  trial_com(f, in, &tv, &t->settled, &m, col);
  model_pose_t set;
  pose_unit(&t->settled, &set);
  fprintf(f, "</g>\n<text x=\"%.1f\" y=\"%.1f\" font-size=\"10\">#%zu %s", x + 5.0,
          y + kTrialH_px - 30.0, i + 1, tv.label);
  if (t->kind == ESTIMATE_TRIAL_EDGE)
    fprintf(f, ", search %d, x = %.3f mm", t->search, 1e3 * t->x_m);
  double c[3];
  cl_pose_apply(&rel, in->result->com_m, c);
  const double over_m = cl_vec3_dot(tv.right, c) - tv.u_edge; /* > 0: beyond the edge */
  fprintf(f, "</text>\n<text x=\"%.1f\" y=\"%.1f\" font-size=\"10\">", x + 5.0,
          y + kTrialH_px - 17.0);
  if (t->kind == ESTIMATE_TRIAL_EDGE)
    fprintf(f, "the estimate %.3f mm %s the edge", 1e3 * fabs(over_m),
            over_m > 0.0 ? "beyond" : "inside");
  else
    fprintf(f, "set down on face %d, in the middle of B", t->face);
  fprintf(f,
          "</text>\n<text x=\"%.1f\" y=\"%.1f\" font-size=\"10\" fill=\"%s\">%s%s: turned "
          "%.2f deg, moved %.2f mm</text>\n",
          x + 5.0, y + kTrialH_px - 4.0, col, trial_outcome_name(t->outcome),
          t->flagged ? " (flagged)" : "",
          cl_quat_angle(rel.orientation_wxyz, set.orientation_wxyz) * 180.0 / CL_PI,
          1e3 * cl_vec3_dist(rel.position_m, set.position_m));
  fprintf(f, "</g>\n");
}

/* The first ESTIMATE_SVG_TRIAL_PANELS trials from y: their panels and a heading. */
static void trial_strip(FILE *f, const estimate_svg_input_t *in, double span, double y,
                        work_t *wk) {
  const estimate_result_t *r = in->result;
  const size_t n =
      r->trial_count < ESTIMATE_SVG_TRIAL_PANELS ? r->trial_count : ESTIMATE_SVG_TRIAL_PANELS;
  const double w = (kWidth_px - (TRIALS_PER_ROW + 1) * kPad_px) / TRIALS_PER_ROW;
  /* the released object's extent and as much again beside it; B's edge in the middle */
  const double sw = (w - 10.0) / (2.4 * span),
               sh = (kTrialH_px - kTrialText_px - 10.0) / (1.6 * span);
  const double s = sw < sh ? sw : sh;
  fprintf(f,
          "<text x=\"%.1f\" y=\"%.1f\" font-size=\"12\">Trials 1 to %zu of %zu (world frame, "
          "seen along the edge, B to the left): released dashed, settled filled; x: the "
          "estimate in each pose</text>\n",
          kPad_px, y + 12.0, n, r->trial_count);
  for (size_t i = 0; i < n; ++i)
    trial_panel(f, in, i, kPad_px + (double)(i % TRIALS_PER_ROW) * (w + kPad_px),
                y + 20.0 + (double)(i / TRIALS_PER_ROW) * (kTrialH_px + kPad_px), w, s, wk);
}

static double trial_strip_height(const estimate_result_t *r) {
  const size_t n =
      r->trial_count < ESTIMATE_SVG_TRIAL_PANELS ? r->trial_count : ESTIMATE_SVG_TRIAL_PANELS;
  const size_t rows = (n + TRIALS_PER_ROW - 1) / TRIALS_PER_ROW;
  return 20.0 + (double)rows * (kTrialH_px + kPad_px);
}

/* ---- the file ------------------------------------------------------------------------------- */

static void title(FILE *f, const estimate_svg_input_t *in) {
  const estimate_result_t *r = in->result;
  fprintf(f, "<text x=\"%.1f\" y=\"24\" font-size=\"16\" font-weight=\"bold\">", kPad_px);
  cli_svg_text(f, in->object);
  fprintf(f, "</text>\n<text x=\"%.1f\" y=\"44\" font-size=\"12\">policy ", kPad_px);
  cli_svg_text(f, in->policy);
  fprintf(f, ", backend ");
  cli_svg_text(f, in->backend);
  fprintf(f,
          ", %zu trials (%zu stable-pose checks, %zu edge tests, %zu flagged); intervals: %s; "
          "link frame, mm</text>\n",
          r->trial_count, r->stable_trials, r->trial_count - r->stable_trials, r->flagged_trials,
          r->noisy ? "95 % under the noise model" : "bounds (noiseless)");
}

static int input_ok(const char *path, const estimate_svg_input_t *in) {
  if (!path || !path[0] || !in || !in->object || !in->policy || !in->backend || !in->result ||
      !in->mesh_link || model_mesh_usable(in->mesh_link) != MODEL_OK)
    return 0;
  for (int k = 0; k < 3; ++k) {
    if (!isfinite(in->base_size_m[k]) || !(in->base_size_m[k] > 0.0)) return 0;
    if (in->truth_com_m && !isfinite(in->truth_com_m[k])) return 0;
    if (!isfinite(in->result->com_m[k])) return 0;
  }
  return in->result->trial_count <= ESTIMATE_MAX_TRIALS &&
         in->result->face_count <= ESTIMATE_MAX_FACES;
}

/* The whole picture into f. */
static void draw(FILE *f, const estimate_svg_input_t *in, const model_aabb_t *box, double span,
                 work_t *w) {
  const double legend_y = kRow0_px + kPanel_px + kZoomH_px + 2.0 * kPad_px + 12.0;
  const double strip_y = legend_y + legend_height(in);
  const double height = strip_y + trial_strip_height(in->result) + kPad_px;
  fprintf(f,
          "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
          "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" "
          "viewBox=\"0 0 %.0f %.0f\" font-family=\"DejaVu Sans, sans-serif\">\n<style>",
          kWidth_px, height, kWidth_px, height);
  for (int i = 0; i < SHADES; ++i) {
    const double l = 0.35 + 0.65 * (double)i / (SHADES - 1);
    fprintf(f, ".s%d{fill:rgb(%d,%d,%d);stroke:rgb(%d,%d,%d)}", i, (int)(kTint[0] * l),
            (int)(kTint[1] * l), (int)(kTint[2] * l), (int)(kTint[0] * l * 0.8),
            (int)(kTint[1] * l * 0.8), (int)(kTint[2] * l * 0.8));
  }
  fprintf(f, "</style>\n<rect width=\"100%%\" height=\"100%%\" fill=\"#fafafa\"/>\n");
  title(f, in);
  main_views(f, in, box, span, w);
  zoom_views(f, in, box, span);
  legend(f, in, legend_y);
  trial_strip(f, in, span, strip_y, w);
  fprintf(f, "</svg>\n");
}

static int work_alloc(const model_mesh_t *m, work_t *w) {
  w->tris = malloc(m->triangle_count * sizeof *w->tris);
  w->pts = malloc((m->vertex_count + 1) * sizeof *w->pts);
  w->hull = malloc((m->vertex_count + 1) * sizeof *w->hull);
  w->patch = malloc(sizeof *w->patch);
  return w->tris && w->pts && w->hull && w->patch ? 0 : -1;
}

static void work_free(work_t *w) {
  free(w->tris);
  free(w->pts);
  free(w->hull);
  free(w->patch);
}

int estimate_svg_write(const char *path, const estimate_svg_input_t *in) {
  model_aabb_t box;
  if (!input_ok(path, in) || model_mesh_aabb(in->mesh_link, &box) != MODEL_OK) {
    errno = EINVAL;
    return -1;
  }
  double span = 0.0;
  for (int k = 0; k < 3; ++k)
    if (box.max_m[k] - box.min_m[k] > span) span = box.max_m[k] - box.min_m[k];
  if (!(span > 0.0)) span = 1e-3;
  char tmp[4096];
  if (snprintf(tmp, sizeof tmp, "%s.XXXXXX", path) >= (int)sizeof tmp) {
    errno = ENAMETOOLONG;
    return -1;
  }
  work_t w;
  if (work_alloc(in->mesh_link, &w) != 0) {
    work_free(&w);
    errno = ENOMEM;
    return -1;
  }
  const int fd = mkstemp(tmp);
  if (fd < 0) {
    const int e = errno;
    work_free(&w);
    errno = e;
    return -1;
  }
  const mode_t mask = umask(0); /* mkstemp makes 0600: give the picture the usual mode */
  umask(mask);
  FILE *f = fchmod(fd, 0666 & ~mask) == 0 ? fdopen(fd, "w") : NULL;
  if (!f) {
    const int e = errno;
    close(fd);
    unlink(tmp);
    work_free(&w);
    errno = e;
    return -1;
  }
  draw(f, in, &box, span, &w);
  work_free(&w);
  int e = ferror(f) ? (errno ? errno : EIO) : 0;
  if (fclose(f) != 0 && e == 0) e = errno ? errno : EIO;
  if (e == 0 && rename(tmp, path) != 0) e = errno;
  if (e != 0) {
    unlink(tmp);
    errno = e;
    return -1;
  }
  return 0;
}
