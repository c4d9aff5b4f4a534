/*
 * experiments_svg.h - the paper's Fig. 2 as a hand-written SVG (no libraries): for one object,
 * three panels (x, y, z) of the running CoM estimate against the trial number, one line per
 * policy, the true value as a dashed line. Used by `comlearn experiments` (cmd_experiments.c).
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
  size_t n;          /* points per component (trials + 1), >= 1 */
  const double *value_mm[3];
} experiments_svg_series_t;

/* Write one figure: title (plain text; escaped here), truth_mm[k] (non-finite: no dashed line
 * for that panel), nseries <= EXPERIMENTS_SVG_MAX_SERIES series. Returns 0, or -1 for a bad
 * argument (NULL, too many series, a series with n == 0) or a write error (ferror). */
int experiments_svg_fig2(FILE *f, const char *title, const double truth_mm[3], size_t nseries,
                         const experiments_svg_series_t *series);

#endif
