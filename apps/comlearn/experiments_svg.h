/*
 * experiments_svg.h - the paper's Fig. 2 as a hand-written SVG (no libraries): for one object,
 * three panels (x, y, z) of the running CoM estimate against the trial number, one line per
 * policy, the true value as a dashed line. Used by `comlearn experiments` (cmd_experiments.c).
 *
 * Also the noisy runs' errors and 95 % intervals per component (experiments_svg_intervals).
 *
 * Units: millimetres on the value axis (the caller converts), trial numbers on the other.
 * Nothing here allocates; the output goes to the caller's FILE.
 */
#ifndef COMLEARN_APP_EXPERIMENTS_SVG_H
#define COMLEARN_APP_EXPERIMENTS_SVG_H

#include <stddef.h>
#include <stdio.h>

enum { EXPERIMENTS_SVG_MAX_SERIES = 8 };

/* One policy's run. value_mm[k][i] is the estimate of component k reported before trial i + 1
 * (i < n - 1) and the final estimate (i = n - 1); drawn as a step line over trial numbers 1..n
 * (the estimate holds until the next trial). Arrays are borrowed; non-finite values are not
 * drawn. */
typedef struct {
  const char *label; /* legend text, e.g. "bisect (22 trials)" */
  const char *name;  /* short name for notes, e.g. "bisect"; NULL: the label */
  size_t n;          /* points per component (trials + 1), >= 1 */
  const double *value_mm[3];
} experiments_svg_series_t;

/* The trial axis's right end: the longest series' n, unless it is more than 1.5 x the second
 * longest + 5, when one long run would squash the rest: then 1.25 x the second longest, rounded
 * up to a multiple of 5 (a series cut there gets a "NAME continues to N trials" note and its
 * final estimate as a hollow marker at the right edge). */
size_t experiments_svg_trial_limit(size_t nseries, const experiments_svg_series_t *series);

/* Write one figure: title (plain text; escaped here), truth_mm[k] (non-finite: no dashed line
 * for that panel), nseries <= EXPERIMENTS_SVG_MAX_SERIES series. Every series has its own colour,
 * dash pattern and marker shape (circle, square, triangle, diamond) at every trial, and earlier
 * series are drawn wider, so runs that coincide stay visible; the legend says "= NAME (same walk)"
 * for a series whose points equal an earlier one's to 1e-9 mm (drawn over it). Each panel is a <g
 * class="panel"> whose data-x0, data-y0, data-w, data-h (px) and data-tmax, data-vlo, data-vhi give
 * the axes' mapping; each series' line is a <polyline class="series" data-series="S">. Returns 0,
 * or -1 for a bad argument (NULL, too many series, a series with n == 0) or a write error (ferror).
 */
int experiments_svg_fig2(FILE *f, const char *title, const double truth_mm[3], size_t nseries,
                         const experiments_svg_series_t *series);

/* One row of the noisy plot: one run's error (estimate - truth, mm) and 95 % half width per
 * component. */
typedef struct {
  const char *group; /* e.g. the object's name; a label and a separator where it changes */
  size_t series;     /* colour and marker (the policy), < EXPERIMENTS_SVG_MAX_SERIES */
  int found[3];      /* 0: drawn as "not found" at the panel's left edge */
  double error_mm[3];
  double halfwidth_mm[3];
} experiments_svg_interval_t;

/* The noisy runs as a forest plot: one panel per axis, one row per run (in the given order), a
 * point at the error and a bar over error +- half width, against 0 = the truth (a solid line).
 * Rows whose interval misses the truth are drawn bold in black-outlined red; rows of a component
 * not found or with a non-finite error or half width show "n/f". series_names[s] label the
 * legend. Each panel is a <g class="panel" data-axis="x|y|z" data-x0 data-w (px) data-vlo
 * data-vhi (mm)>; each found row is a <line class="bar" data-row="R"> and a
 * <circle class="pt" data-row="R">. Returns 0, or -1 for a bad argument (NULL, nseries 0 or too
 * many, a series index out of range) or a write error. Nothing allocates. */
int experiments_svg_intervals(FILE *f, const char *title, const char *const *series_names,
                              size_t nseries, const experiments_svg_interval_t *rows, size_t nrows);

#endif
