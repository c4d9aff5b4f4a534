/*
 * experiments_svg.c - Fig. 2 of `comlearn experiments` as SVG (see experiments_svg.h).
 */
#include "experiments_svg.h"

#include <math.h>
#include <string.h>

#include "comlearn/cli_svg.h"

/* Layout (px): three panels side by side, the legend below them. */
#define PANEL_W 300.0
#define PANEL_H 230.0
#define MARGIN_L 58.0
#define MARGIN_T 44.0
#define GAP 22.0
#define LEGEND_H 26.0
#define PLOT_W (PANEL_W - MARGIN_L)
#define PLOT_H (PANEL_H - 50.0)

static const char *const colors[EXPERIMENTS_SVG_MAX_SERIES] = {
    "#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf"};
/* Dash pattern per series ("" solid): lines that coincide stay told apart. */
static const char *const dashes[EXPERIMENTS_SVG_MAX_SERIES] = {
    "", "7 3", "2 2", "10 3 2 3", "4 4", "1 3", "8 2 2 2 2 2", "12 4"};

/* A step of 1, 2 or 5 times a power of ten giving about `want` intervals over span. */
static double nice_step(double span, double want) {
  double raw = span / want;
  if (!(raw > 0.0) || !isfinite(raw)) return 1.0;
  double p = pow(10.0, floor(log10(raw)));
  double m = raw / p;
  return (m < 1.5 ? 1.0 : m < 3.5 ? 2.0 : m < 7.5 ? 5.0 : 10.0) * p;
}

typedef struct {
  double x0, y0;   /* top-left of the plot area */
  double tmax;     /* trial axis: 0 .. tmax */
  double vlo, vhi; /* value axis */
} panel_t;

static double px(const panel_t *p, double t) { return p->x0 + PLOT_W * t / p->tmax; }
static double py(const panel_t *p, double v) {
  return p->y0 + PLOT_H * (1.0 - (v - p->vlo) / (p->vhi - p->vlo));
}

static void panel_axes(FILE *f, const panel_t *p, char axis) {
  fprintf(f,
          "<g class=\"panel\" data-axis=\"%c\" data-x0=\"%.3f\" data-y0=\"%.3f\" data-w=\"%.3f\" "
          "data-h=\"%.3f\" data-tmax=\"%.17g\" data-vlo=\"%.17g\" data-vhi=\"%.17g\">\n",
          axis, p->x0, p->y0, PLOT_W, PLOT_H, p->tmax, p->vlo, p->vhi);
  fprintf(f,
          "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"none\" "
          "stroke=\"#444\"/>\n",
          p->x0, p->y0, PLOT_W, PLOT_H);
  double ts = nice_step(p->tmax, 5.0);
  if (ts < 1.0) ts = 1.0;
  for (int i = 0; i <= 50; ++i) {
    double t = i * ts;
    if (t > p->tmax + 1e-9) break;
    double x = px(p, t);
    fprintf(f,
            "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#444\"/>"
            "<text class=\"xtick\" x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">%g</text>\n",
            x, p->y0 + PLOT_H, x, p->y0 + PLOT_H + 4, x, p->y0 + PLOT_H + 16, t);
  }
  double vs = nice_step(p->vhi - p->vlo, 5.0);
  double v0 = ceil(p->vlo / vs - 1e-9) * vs;
  for (int i = 0; i <= 50; ++i) {
    double v = v0 + i * vs;
    if (v > p->vhi + 1e-9 * vs) break;
    if (fabs(v) < 1e-9 * vs) v = 0.0;
    double y = py(p, v);
    fprintf(f,
            "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>"
            "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\">%g</text>\n",
            p->x0, y, p->x0 + PLOT_W, y, p->x0 - 4, y + 4, v);
  }
  fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">trial</text>\n",
          p->x0 + PLOT_W / 2, p->y0 + PLOT_H + 32);
  fprintf(f,
          "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\" transform=\"rotate(-90 %.1f "
          "%.1f)\">%c estimate (mm)</text>\n",
          p->x0 - 42, p->y0 + PLOT_H / 2, p->x0 - 42, p->y0 + PLOT_H / 2, axis);
  fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-weight=\"bold\">%c</text>\n", p->x0, p->y0 - 6,
          axis);
}

/* Series s's marker (circle, square, triangle, diamond, then again) at (x, y), radius r. */
static void marker(FILE *f, size_t s, double x, double y, double r, const char *fill) {
  const char *c = colors[s % EXPERIMENTS_SVG_MAX_SERIES];
  switch (s % 4) {
    case 0:
      fprintf(f, "<circle cx=\"%.1f\" cy=\"%.2f\" r=\"%.1f\" fill=\"%s\" stroke=\"%s\"/>", x, y, r,
              fill ? fill : c, c);
      break;
    case 1:
      fprintf(f,
              "<rect x=\"%.1f\" y=\"%.2f\" width=\"%.1f\" height=\"%.1f\" fill=\"%s\" "
              "stroke=\"%s\"/>",
              x - r, y - r, 2 * r, 2 * r, fill ? fill : c, c);
      break;
    case 2:
      fprintf(f, "<path d=\"M%.1f %.2fL%.1f %.2fL%.1f %.2fZ\" fill=\"%s\" stroke=\"%s\"/>", x,
              y - 1.2 * r, x + 1.1 * r, y + 0.8 * r, x - 1.1 * r, y + 0.8 * r, fill ? fill : c, c);
      break;
    default:
      fprintf(f,
              "<path d=\"M%.1f %.2fL%.1f %.2fL%.1f %.2fL%.1f %.2fZ\" fill=\"%s\" stroke=\"%s\"/>",
              x, y - 1.3 * r, x + 1.3 * r, y, x, y + 1.3 * r, x - 1.3 * r, y, fill ? fill : c, c);
  }
}

/* The index of an earlier series with the same points as series s (to 1e-9 mm), or s. */
static size_t same_as(const experiments_svg_series_t *series, size_t s) {
  for (size_t e = 0; e < s; ++e) {
    if (series[e].n != series[s].n) continue;
    int same = 1;
    for (int k = 0; k < 3 && same; ++k)
      for (size_t i = 0; i < series[s].n && same; ++i) {
        const double a = series[e].value_mm[k][i], b = series[s].value_mm[k][i];
        /* 1e-9 mm: runs over LCM round the release pose at ~1e-16 mm */
        same = fabs(a - b) <= 1e-9 || a == b || (isnan(a) && isnan(b));
      }
    if (same) return e;
  }
  return s;
}

size_t experiments_svg_trial_limit(size_t nseries, const experiments_svg_series_t *series) {
  size_t l1 = 1, l2 = 0;
  for (size_t s = 0; s < nseries; ++s) {
    const size_t n = series[s].n;
    if (n > l1) {
      l2 = l1;
      l1 = n;
    } else if (n > l2) {
      l2 = n;
    }
  }
  if (nseries < 2 || 2 * l1 <= 3 * l2 + 10) return l1;
  const size_t lim = (l2 * 5 + 3) / 4; /* 1.25 x the second longest, up to a multiple of 5 */
  return (lim + 4) / 5 * 5;
}

/* One series in one panel: the step line cut at the panel's trial limit, a marker per trial, the
 * final estimate (filled, larger; hollow at the right edge when the run goes on past it). */
static void panel_series(FILE *f, const panel_t *p, const experiments_svg_series_t *sr, size_t s,
                         size_t nseries, int k) {
  fprintf(f,
          "<polyline class=\"series\" data-series=\"%zu\" fill=\"none\" stroke=\"%s\" "
          "stroke-width=\"%.1f\" stroke-dasharray=\"%s\" stroke-opacity=\"0.9\" points=\"",
          s, colors[s], 1.3 + 1.2 * (double)(nseries - 1 - s), dashes[s][0] ? dashes[s] : "none");
  int any = 0;
  for (size_t i = 0; i < sr->n; ++i) {
    const double v = sr->value_mm[k][i];
    const double t0 = (double)(i + 1), t1 = fmin(i + 1 < sr->n ? t0 + 1.0 : t0, p->tmax);
    if (t0 > p->tmax) break;
    if (!isfinite(v)) continue;
    fprintf(f, "%s%.1f,%.2f %.1f,%.2f", any ? " " : "", px(p, t0), py(p, v), px(p, t1), py(p, v));
    any = 1;
  }
  fprintf(f, "\"/>\n");
  for (size_t i = 0; i + 1 < sr->n && (double)(i + 1) <= p->tmax; ++i)
    if (isfinite(sr->value_mm[k][i]))
      marker(f, s, px(p, (double)(i + 1)), py(p, sr->value_mm[k][i]), 1.8, "white");
  const double vend = sr->value_mm[k][sr->n - 1];
  if (!isfinite(vend)) return;
  const int clipped = (double)sr->n > p->tmax;
  fprintf(f, "<g class=\"final\" data-series=\"%zu\">", s);
  marker(f, s, px(p, clipped ? p->tmax : (double)sr->n), py(p, vend), 3.0,
         clipped ? "white" : NULL);
  fprintf(f, "</g>\n");
}

/* Panel k: axes, the dashed truth, every series, and a note per series cut at the trial limit. */
static void panel_draw(FILE *f, panel_t *p, int k, double truth_mm, size_t nseries,
                       const experiments_svg_series_t *series) {
  p->vlo = HUGE_VAL;
  p->vhi = -HUGE_VAL;
  if (isfinite(truth_mm)) p->vlo = p->vhi = truth_mm;
  for (size_t s = 0; s < nseries; ++s)
    for (size_t i = 0; i < series[s].n; ++i) {
      const double v = series[s].value_mm[k][i];
      if (!isfinite(v) || (double)(i + 1) > p->tmax) continue;
      if (v < p->vlo) p->vlo = v;
      if (v > p->vhi) p->vhi = v;
    }
  if (!(p->vlo <= p->vhi)) p->vlo = -1.0, p->vhi = 1.0;
  /* at least 1 mm tall, 8 % padding */
  const double mid = 0.5 * (p->vlo + p->vhi), half = fmax(0.5 * (p->vhi - p->vlo), 0.5) * 1.08;
  p->vlo = mid - half;
  p->vhi = mid + half;
  panel_axes(f, p, "xyz"[k]);
  if (isfinite(truth_mm))
    fprintf(f,
            "<line class=\"truth\" x1=\"%.1f\" y1=\"%.2f\" x2=\"%.1f\" y2=\"%.2f\" stroke=\"#000\" "
            "stroke-width=\"1.2\" stroke-dasharray=\"6 4\"/>\n",
            p->x0, py(p, truth_mm), p->x0 + PLOT_W, py(p, truth_mm));
  double note_y = p->y0 - 6; /* above the plot, right-aligned, upwards */
  for (size_t s = 0; s < nseries; ++s) {
    panel_series(f, p, &series[s], s, nseries, k);
    if ((double)series[s].n <= p->tmax) continue;
    fprintf(f,
            "<text class=\"continues\" x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\" fill=\"%s\" "
            "font-size=\"10\">",
            p->x0 + PLOT_W - 4, note_y, colors[s]);
    cli_svg_text(f, series[s].name ? series[s].name : series[s].label);
    fprintf(f, " continues to %zu trials &#8594;</text>\n", series[s].n - 1);
    note_y -= 12;
  }
  fprintf(f, "</g>\n");
}

/* The legend row: the truth, then per series its line, marker and label. */
static void legend(FILE *f, double lx, double ly, size_t nseries,
                   const experiments_svg_series_t *series) {
  fprintf(f,
          "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#000\" "
          "stroke-dasharray=\"6 4\"/><text x=\"%.1f\" y=\"%.1f\">true CoM</text>\n",
          lx, ly, lx + 24, ly, lx + 28, ly + 4);
  lx += 90;
  for (size_t s = 0; s < nseries; ++s) {
    fprintf(f,
            "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"%s\" "
            "stroke-width=\"2\" stroke-dasharray=\"%s\"/>",
            lx, ly, lx + 28, ly, colors[s], dashes[s][0] ? dashes[s] : "none");
    marker(f, s, lx + 14, ly, 2.5, NULL);
    fprintf(f, "<text class=\"legend\" data-series=\"%zu\" x=\"%.1f\" y=\"%.1f\">", s, lx + 32,
            ly + 4);
    cli_svg_text(f, series[s].label);
    const size_t e = same_as(series, s);
    if (e != s) {
      fputs(" = ", f);
      cli_svg_text(f, series[e].name ? series[e].name : series[e].label);
      fputs(" (same walk)", f);
    }
    fprintf(f, "</text>\n");
    /* about 5.4 px per character at 11 px */
    lx += 44.0 +
          6.2 * (double)(strlen(series[s].label) +
                         (e != s ? 15 + strlen(series[e].name ? series[e].name : series[e].label)
                                 : 0));
  }
}

int experiments_svg_fig2(FILE *f, const char *title, const double truth_mm[3], size_t nseries,
                         const experiments_svg_series_t *series) {
  if (!f || !truth_mm || (nseries && !series) || nseries > EXPERIMENTS_SVG_MAX_SERIES) return -1;
  for (size_t s = 0; s < nseries; ++s) {
    if (series[s].n == 0) return -1;
    for (int k = 0; k < 3; ++k)
      if (!series[s].value_mm[k]) return -1;
  }
  const size_t tmax = experiments_svg_trial_limit(nseries, series);
  const double width = 3 * PANEL_W + 2 * GAP + 20, height = MARGIN_T + PANEL_H + LEGEND_H + 10;
  fprintf(f,
          "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" "
          "viewBox=\"0 0 %.0f %.0f\" font-family=\"sans-serif\" font-size=\"11\">\n",
          width, height, width, height);
  fprintf(f,
          "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n<text x=\"%.1f\" y=\"18\" "
          "text-anchor=\"middle\" font-size=\"14\">",
          width / 2);
  cli_svg_text(f, title);
  fprintf(f, "</text>\n");
  for (int k = 0; k < 3; ++k) {
    panel_t p = {10 + k * (PANEL_W + GAP) + MARGIN_L, MARGIN_T, (double)tmax, 0.0, 0.0};
    panel_draw(f, &p, k, truth_mm[k], nseries, series);
  }
  legend(f, 10 + MARGIN_L, MARGIN_T + PANEL_H + 12, nseries, series);
  fprintf(f, "</svg>\n");
  return ferror(f) ? -1 : 0;
}

/* ---- the noisy runs: errors and 95 % intervals ------------------------------------------------
 */

#define IV_LEFT 120.0  /* group labels */
#define IV_TOP 58.0    /* title, legend */
#define IV_PANEL 290.0 /* plot width per axis */
#define IV_GAP 26.0
#define IV_BOTTOM 40.0 /* tick labels, axis title */

static int iv_found(const experiments_svg_interval_t *r, int k) {
  return r->found[k] && isfinite(r->error_mm[k]) && isfinite(r->halfwidth_mm[k]) &&
         r->halfwidth_mm[k] >= 0.0;
}

/* One axis's panel of the forest plot; rows at y0 + (i + 0.5) * row_h. */
static void iv_panel(FILE *f, int k, double x0, double y0, double row_h, size_t nrows,
                     const experiments_svg_interval_t *rows) {
  double span = 0.5;
  size_t found = 0, hold = 0;
  for (size_t i = 0; i < nrows; ++i) {
    if (!iv_found(&rows[i], k)) continue;
    span = fmax(span, fabs(rows[i].error_mm[k]) + rows[i].halfwidth_mm[k]);
    ++found;
    hold += fabs(rows[i].error_mm[k]) <= rows[i].halfwidth_mm[k];
  }
  span *= 1.08;
  const double h = row_h * (double)nrows;
  const double w = IV_PANEL;
#define IVX(v) (x0 + w * ((v) + span) / (2.0 * span))
  fprintf(f,
          "<g class=\"panel\" data-axis=\"%c\" data-x0=\"%.3f\" data-w=\"%.3f\" data-vlo=\"%.17g\" "
          "data-vhi=\"%.17g\" data-found=\"%zu\" data-hold=\"%zu\">\n",
          "xyz"[k], x0, w, -span, span, found, hold);
  fprintf(f,
          "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"none\" "
          "stroke=\"#444\"/>\n",
          x0, y0, w, h);
  const double vs = nice_step(2.0 * span, 6.0);
  for (int i = -50; i <= 50; ++i) {
    const double v = i * vs;
    if (fabs(v) > span) continue;
    fprintf(f,
            "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"%s\"/>"
            "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">%g</text>\n",
            IVX(v), y0, IVX(v), y0 + h, i == 0 ? "#000" : "#e4e4e4", IVX(v), y0 + h + 14, v);
  }
  fprintf(f,
          "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">%c error (mm): estimate - truth, "
          "+- 95 %% half width</text>\n",
          x0 + w / 2, y0 + h + 30, "xyz"[k]);
  fprintf(f,
          "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\" font-weight=\"bold\">%c: %zu of %zu "
          "intervals hold the truth</text>\n",
          x0 + w / 2, y0 - 6, "xyz"[k], hold, found);
  for (size_t i = 0; i < nrows; ++i) {
    const experiments_svg_interval_t *r = &rows[i];
    const double y = y0 + ((double)i + 0.5) * row_h;
    if (!iv_found(r, k)) {
      fprintf(
          f,
          "<text class=\"nf\" x=\"%.1f\" y=\"%.1f\" font-size=\"%.1f\" fill=\"#888\">n/f</text>\n",
          x0 + 2, y + 0.35 * fmin(row_h * 1.6, 9.0), fmin(row_h * 1.6, 9.0));
      continue;
    }
    const double e = r->error_mm[k], hw = r->halfwidth_mm[k];
    const int miss = fabs(e) > hw;
    const char *c = colors[r->series % EXPERIMENTS_SVG_MAX_SERIES];
    fprintf(f,
            "<line class=\"bar\" data-row=\"%zu\" x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" "
            "stroke=\"%s\" stroke-width=\"%.1f\"/>",
            i, IVX(e - hw), y, IVX(e + hw), y, miss ? "#000" : c, miss ? 1.8 : fmin(1.2, row_h));
    fprintf(f,
            "<circle class=\"pt\" data-row=\"%zu\" cx=\"%.2f\" cy=\"%.2f\" r=\"%.1f\" "
            "fill=\"%s\"%s/>\n",
            i, IVX(e), y, fmin(2.0, 0.5 * row_h + 0.4), miss ? "#e00000" : c,
            miss ? " stroke=\"#000\" stroke-width=\"0.6\"" : "");
  }
#undef IVX
  fprintf(f, "</g>\n");
}

int experiments_svg_intervals(FILE *f, const char *title, const char *const *series_names,
                              size_t nseries, const experiments_svg_interval_t *rows,
                              size_t nrows) {
  if (!f || !series_names || nseries == 0 || nseries > EXPERIMENTS_SVG_MAX_SERIES ||
      (nrows && !rows))
    return -1;
  for (size_t i = 0; i < nrows; ++i)
    if (rows[i].series >= nseries) return -1;
  double row_h = nrows ? 600.0 / (double)nrows : 7.0;
  row_h = row_h > 7.0 ? 7.0 : row_h < 1.5 ? 1.5 : row_h;
  const double h = row_h * (double)nrows;
  const double width = IV_LEFT + 3 * IV_PANEL + 2 * IV_GAP + 16,
               height = IV_TOP + h + IV_BOTTOM + 8;
  fprintf(f,
          "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" "
          "viewBox=\"0 0 %.0f %.0f\" font-family=\"sans-serif\" font-size=\"11\">\n",
          width, height, width, height);
  fprintf(f,
          "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n<text x=\"%.1f\" y=\"18\" "
          "text-anchor=\"middle\" font-size=\"14\">",
          width / 2);
  cli_svg_text(f, title);
  fprintf(f, "</text>\n");
  double lx = IV_LEFT;
  for (size_t s = 0; s < nseries; ++s) {
    fprintf(f,
            "<line x1=\"%.1f\" y1=\"34\" x2=\"%.1f\" y2=\"34\" stroke=\"%s\" stroke-width=\"1.5\"/>"
            "<circle cx=\"%.1f\" cy=\"34\" r=\"2\" fill=\"%s\"/><text x=\"%.1f\" y=\"38\">",
            lx, lx + 20, colors[s], lx + 10, colors[s], lx + 24);
    cli_svg_text(f, series_names[s]);
    fprintf(f, "</text>\n");
    lx += 110;
  }
  fprintf(f,
          "<circle cx=\"%.1f\" cy=\"34\" r=\"2.2\" fill=\"#e00000\" stroke=\"#000\" "
          "stroke-width=\"0.6\"/><text x=\"%.1f\" y=\"38\">interval misses the truth (black "
          "bar)</text>\n",
          lx + 10, lx + 18);
  /* group labels and separators */
  for (size_t i = 0; i < nrows; ++i) {
    if (i > 0 && rows[i].group && rows[i - 1].group &&
        strcmp(rows[i].group, rows[i - 1].group) == 0)
      continue;
    size_t j = i + 1;
    while (j < nrows && rows[j].group && rows[i].group && strcmp(rows[j].group, rows[i].group) == 0)
      ++j;
    const double ya = IV_TOP + (double)i * row_h, yb = IV_TOP + (double)j * row_h;
    if (i > 0)
      fprintf(f, "<line x1=\"8\" y1=\"%.2f\" x2=\"%.1f\" y2=\"%.2f\" stroke=\"#999\"/>\n", ya,
              width - 8, ya);
    fprintf(f, "<text class=\"group\" x=\"%.1f\" y=\"%.2f\" text-anchor=\"end\">", IV_LEFT - 8,
            0.5 * (ya + yb) + 4);
    cli_svg_text(f, rows[i].group ? rows[i].group : "");
    fprintf(f, "</text>\n");
  }
  for (int k = 0; k < 3; ++k)
    iv_panel(f, k, IV_LEFT + k * (IV_PANEL + IV_GAP), IV_TOP, row_h, nrows, rows);
  fprintf(f, "</svg>\n");
  return ferror(f) ? -1 : 0;
}
