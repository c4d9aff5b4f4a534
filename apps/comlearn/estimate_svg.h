/*
 * estimate_svg.h - the picture of one estimate that `comlearn estimate --svg FILE` writes
 * (estimate_svg.c; docs/estimate.md, "Picture").
 *
 * Why here and not in lib/estimate: the picture is output (it opens, writes and renames a file),
 * and lib/ does no I/O. It draws what the estimator reported (estimate_result_t: the CoM, its
 * intervals, the faces and every trial's released and settled pose) over the object's mesh; the
 * true CoM only when the caller passes one (`--truth`: read from the URDF by the program, after
 * the estimate; never by lib/estimate).
 *
 * What the SVG holds, top to bottom:
 *   - a title: the object, policy, backend, trials, the kind of interval;
 *   - three orthographic views of the mesh in its link frame, one scale: front (x right, z up,
 *     seen from -y), side (y right, z up, seen from +x), top (x right, y up, seen from +z); on
 *     each the resting faces confirmed stable (outlined: the support polygon of the first trial
 *     released on the face), every edge trial's edge line in the link frame (B's edge at its
 *     released pose; green stayed, red tipped, grey unclear, dashed when flagged), the estimate,
 *     the truth and the interval box;
 *   - the same three views zoomed on the estimate, where the box is visible: the interval per
 *     axis (bound or 95 %); a component not found is an unbounded band across the view;
 *   - a legend and per axis: estimate +- half width (with the truth: the truth and the error), or
 *     why it was not found;
 *   - the trial strip: the first ESTIMATE_SVG_TRIAL_PANELS trials, each the object's outline
 *     (the hull of its projected vertices) before (released, dashed) and after (settled, filled
 *     in the outcome's colour), world frame, seen along the trial's edge with B's outward normal
 *     to the right (stable checks: seen from -y, world x right), with B, the estimate at both
 *     poses and the outcome.
 * Every view is a <g class="view" id="front|side|top|front-zoom|side-zoom|top-zoom"> whose
 * data-u / data-v name the link axes drawn right / up and whose data attributes give the
 * projection: px = data-ox-px + data-px-per-m * (u - data-u0-m),
 * py = data-oy-px - data-px-per-m * (v - data-v0-m) (u, v in metres, link frame). Markers and
 * boxes name their view in data-view: <circle class="com-est">, <circle class="com-truth"> (only
 * with a truth), <rect class="interval"> (data-unbounded="u", "v" or "uv" for a component not
 * found: it spans the view that way). Faces are <polygon class="face" data-face="I">, edge lines
 * <path class="edge-line" data-trial="N">. Trial panels are <g class="trial" data-trial="N"
 * data-kind="stable|edge" data-outcome="stays|tips|slides|invalid">, N 1-based.
 */
#ifndef COMLEARN_APP_ESTIMATE_SVG_H
#define COMLEARN_APP_ESTIMATE_SVG_H

#include "comlearn/estimate.h"
#include "comlearn/model.h"

/* Trials drawn in the strip: the first 8 (fewer when the estimate ran fewer). */
enum { ESTIMATE_SVG_TRIAL_PANELS = 8 };

/* What to draw. All pointers are borrowed for the call. */
typedef struct {
  const char *object;              /* name in the title (e.g. the URDF's path) */
  const char *policy;              /* "bisect", ... */
  const char *backend;             /* "direct", "lcm" */
  const model_mesh_t *mesh_link;   /* the object's geometry, link frame */
  const estimate_result_t *result; /* the estimate (comlearn/estimate.h) */
  const double *truth_com_m;       /* the true CoM [3], link frame; NULL: not drawn */
  double base_size_m[3];           /* B, world x, y, z: its edges and the trial strip */
} estimate_svg_input_t;

/* Write the picture of *in to path: to a temporary file beside it first (PATH.XXXXXX), then
 * renamed, so that a failure never leaves a file at path, nor the temporary one. Allocates
 * working memory, freed before it returns. Returns 0, or -1 with errno set: EINVAL (NULL or empty
 * path, NULL input, strings or result, an unusable mesh, a base size that is not finite and
 * positive, a non-finite truth), ENOMEM, ENAMETOOLONG, or the errno of mkstemp / write / close /
 * rename (ENOENT for a folder that does not exist, EISDIR for a path that is a folder). */
int estimate_svg_write(const char *path, const estimate_svg_input_t *in);

#endif
