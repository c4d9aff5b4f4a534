/*
 * experiments_svg.c - Fig. 2 of `comlearn experiments` as SVG (see experiments_svg.h).
 */
#include "experiments_svg.h"

#include <math.h>

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

static void text_escaped(FILE *f, const char *s) {
  for (; s && *s; ++s) {
    switch (*s) {
      case '<': fputs("&lt;", f); break;
      case '>': fputs("&gt;", f); break;
      case '&': fputs("&amp;", f); break;
      case '"': fputs("&quot;", f); break;
      default: fputc(*s, f);
    }
  }
}

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
            "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">%g</text>\n",
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
  fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\" font-weight=\"bold\">%c</text>\n",
          p->x0 + PLOT_W / 2, p->y0 - 6, axis);
}

int experiments_svg_fig2(FILE *f, const char *title, const double truth_mm[3], size_t nseries,
                         const experiments_svg_series_t *series) {
  if (!f || !truth_mm || (nseries && !series) || nseries > EXPERIMENTS_SVG_MAX_SERIES) return -1;
  size_t tmax = 1;
  for (size_t s = 0; s < nseries; ++s) {
    if (series[s].n == 0) return -1;
    for (int k = 0; k < 3; ++k)
      if (!series[s].value_mm[k]) return -1;
    if (series[s].n > tmax) tmax = series[s].n;
  }
  const double width = 3 * PANEL_W + 2 * GAP + 20, height = MARGIN_T + PANEL_H + LEGEND_H + 10;
  fprintf(f,
          "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" "
          "viewBox=\"0 0 %.0f %.0f\" font-family=\"sans-serif\" font-size=\"11\">\n",
          width, height, width, height);
  fprintf(f,
          "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n<text x=\"%.1f\" y=\"18\" "
          "text-anchor=\"middle\" font-size=\"14\">",
          width / 2);
  text_escaped(f, title);
  fprintf(f, "</text>\n");
  for (int k = 0; k < 3; ++k) {
    panel_t p = {10 + k * (PANEL_W + GAP) + MARGIN_L, MARGIN_T, (double)tmax, HUGE_VAL, -HUGE_VAL};
    if (isfinite(truth_mm[k])) p.vlo = p.vhi = truth_mm[k];
    for (size_t s = 0; s < nseries; ++s)
      for (size_t i = 0; i < series[s].n; ++i) {
        double v = series[s].value_mm[k][i];
        if (!isfinite(v)) continue;
        if (v < p.vlo) p.vlo = v;
        if (v > p.vhi) p.vhi = v;
      }
    if (!(p.vlo <= p.vhi)) p.vlo = -1.0, p.vhi = 1.0;
    /* at least 1 mm tall, 8 % padding */
    double mid = 0.5 * (p.vlo + p.vhi), half = fmax(0.5 * (p.vhi - p.vlo), 0.5) * 1.08;
    p.vlo = mid - half;
    p.vhi = mid + half;
    panel_axes(f, &p, "xyz"[k]);
    if (isfinite(truth_mm[k]))
      fprintf(f,
              "<line x1=\"%.1f\" y1=\"%.2f\" x2=\"%.1f\" y2=\"%.2f\" stroke=\"#000\" "
              "stroke-width=\"1.2\" stroke-dasharray=\"6 4\"/>\n",
              p.x0, py(&p, truth_mm[k]), p.x0 + PLOT_W, py(&p, truth_mm[k]));
    for (size_t s = 0; s < nseries; ++s) {
      const experiments_svg_series_t *sr = &series[s];
      /* earlier series wider, so identical runs (the two paper policies often are) stay visible */
      fprintf(f,
              "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"%.1f\" "
              "stroke-opacity=\"0.85\" points=\"",
              colors[s], 1.2 + 0.9 * (double)(nseries - 1 - s));
      int any = 0;
      for (size_t i = 0; i < sr->n; ++i) {
        double v = sr->value_mm[k][i];
        if (!isfinite(v)) continue;
        double t0 = (double)(i + 1), t1 = i + 1 < sr->n ? (double)(i + 2) : t0;
        fprintf(f, "%s%.1f,%.2f %.1f,%.2f", any ? " " : "", px(&p, t0), py(&p, v), px(&p, t1),
                py(&p, v));
        any = 1;
      }
      fprintf(f, "\"/>\n");
      double vend = sr->value_mm[k][sr->n - 1];
      if (isfinite(vend))
        fprintf(f, "<circle cx=\"%.1f\" cy=\"%.2f\" r=\"2.5\" fill=\"%s\"/>\n",
                px(&p, (double)sr->n), py(&p, vend), colors[s]);
    }
  }
  /* legend */
  double lx = 10 + MARGIN_L, ly = MARGIN_T + PANEL_H + 12;
  fprintf(f,
          "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#000\" "
          "stroke-dasharray=\"6 4\"/><text x=\"%.1f\" y=\"%.1f\">true CoM</text>\n",
          lx, ly, lx + 24, ly, lx + 28, ly + 4);
  lx += 100;
  for (size_t s = 0; s < nseries; ++s) {
    fprintf(f,
            "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"%s\" "
            "stroke-width=\"2\"/><text x=\"%.1f\" y=\"%.1f\">",
            lx, ly, lx + 24, ly, colors[s], lx + 28, ly + 4);
    text_escaped(f, series[s].label);
    fprintf(f, "</text>\n");
    lx += 190;
  }
  fprintf(f, "</svg>\n");
  return ferror(f) ? -1 : 0;
}
