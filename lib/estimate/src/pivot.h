/*
 * pivot.h - internal to lib/estimate: the geometry of a pivot trial. The object is set down
 * balanced on B's edge line along an edge of its convex hull (a knife edge), tilted about it; it
 * turns back onto B when its CoM lies on B's side of the vertical plane through that edge and
 * falls off when beyond. A search over the tilt finds the plane through the edge that holds the
 * CoM (docs/estimate.md, "Pivots"). Pure functions, no allocation.
 *
 * Frames: the object's link frame; the world of comlearn/model_support.h with the pivot along B's
 * +X edge (world +y), world +x its outward normal.
 */
#ifndef COMLEARN_ESTIMATE_PIVOT_H
#define COMLEARN_ESTIMATE_PIVOT_H

#include <stdint.h>

#include "comlearn/estimate.h"
#include "comlearn/model_support.h"

/* The planning rules of pivot searches, measured with bench/bench_pivot.c (docs/estimate.md,
 * "Pivots"): the CoM must project ESTIMATE_PIVOT_SIDE_M inside the edge's ends (the interval box
 * included: a CoM 0.16 mm inside rolled over an end and fell off 0.39 mm short of its threshold);
 * a tilt keeps ESTIMATE_PIVOT_WEDGE_RAD from where a face next to the edge would touch B's top or
 * side; the CoM must lie ESTIMATE_PIVOT_HEIGHT_M from the edge line (the tilt's lever). The bias
 * budget of a pivot's plane is a flat patch's. */
#define ESTIMATE_PIVOT_SIDE_M 2.5e-4
#define ESTIMATE_PIVOT_WEDGE_RAD 0.05
#define ESTIMATE_PIVOT_HEIGHT_M 2e-3
#define ESTIMATE_PIVOT_BIAS_M 5e-6

/* A hull edge planned for pivot trials under a CoM estimate g. At tilt 0 the object's link-frame
 * directions u, e and up point along world +x, +y and +z: g lies straight above the edge. Tilt
 * beta turns the object about world +y (beta > 0: the top moves outward). The search coordinate
 * x = gx_m - h_m tan(beta) is the offset along u at which a CoM at height h_m over the edge would
 * balance: a CoM beyond it tips the object off (TIPS below x, as for an edge test), one short of
 * it lets the object turn back onto B. */
typedef struct {
  uint32_t v[2]; /* its hull vertices, in the order p1 -> p2 (along e) */
  double p1_m[3], p2_m[3], mid_m[3];
  double e[3], up[3], u[3]; /* unit, link frame */
  double len_m;             /* |p2 - p1| */
  double h_m;               /* the estimate's distance from the edge line */
  double gx_m;              /* u . g */
  double reach_m;           /* the farthest hull vertex from the edge line (estimate_pivot_reach) */
  double beta_lo_rad, beta_hi_rad; /* the tilts at which only the edge touches B (wedge margin
                                      kept), beta_lo < 0 < beta_hi */
} estimate_pivot_t;

/* Plan edge `he` of `hull` for the estimate g, turned so that p1 -> p2 runs along world +y when
 * flip is 0 (v[0] -> v[1]) or the other way when 1: 1 when the object, tilted within
 * [-wedge_margin, +wedge_margin] of balancing g over the edge, touches B only along the edge (the
 * hull's wedge at the edge clears B's top on B's side and B's side face beyond it) and g is at
 * least min_height_m from the edge line; 0 otherwise (*out unspecified). */
int estimate_pivot_plan(const model_mesh_t *hull, const model_hull_edge_t *he, int flip,
                        const double g[3], double wedge_margin_rad, double min_height_m,
                        estimate_pivot_t *out);

/* Set pv->reach_m from the hull's vertices (O(vertices)). */
void estimate_pivot_reach(const model_mesh_t *hull, estimate_pivot_t *pv);

/* How far inside the edge's ends the projection of c onto the edge line lies (negative: beyond
 * an end). */
double estimate_pivot_side_margin(const estimate_pivot_t *pv, const double c[3]);

/* The object's orientation (world from link) for search coordinate x. */
void estimate_pivot_orientation(const estimate_pivot_t *pv, double x, double q_wxyz[4]);

/* The release pose of a pivot trial at x: the orientation of estimate_pivot_orientation, the
 * edge's midpoint over B's +X edge line (its middle), lowered as lib/placement's plans and
 * model_mesh_lowest_over_rect lower an object, until the lowest point of the mesh over B's top
 * (size base_size_m) is touch_m deep. 1 when that point is the edge (both its ends touch_m deep,
 * to 1e-8 m); 0 when something else of the object over B is lower, or nothing is over B. */
int estimate_pivot_pose(const estimate_pivot_t *pv, const model_mesh_t *mesh,
                        const double base_size_m[3], double x, double touch_m, model_pose_t *out);

/* The search coordinate of a released orientation (its tilt about the edge). */
double estimate_pivot_x(const estimate_pivot_t *pv, const double q_wxyz[4]);

/* The link-frame direction of world +x (the plane normal of a pivot trial) for orientation q. */
void estimate_pivot_normal(const double q_wxyz[4], double n[3]);

/* What a pivot trial says, from the turn between its released and settled poses: ESTIMATE_TIPS
 * when the object fell off as it started to turn (a CoM beyond the edge: lib/balance calls TIPS
 * within ~20 ms, turned by under 1e-2 rad) or turned outward about the edge line, ESTIMATE_STAYS
 * when it turned back onto B about the edge line (whatever the trial was called: TIPS at 0.35
 * rad, STAYS after landing, SLIDES, the horizon), else ESTIMATE_INVALID (it fell back and then
 * rolled off, or had not turned clearly by the horizon). A clear turn: over 1e-2 rad, at least
 * half of it about the edge line. */
estimate_outcome_t estimate_pivot_outcome(estimate_outcome_t outcome, const model_pose_t *released,
                                          const model_pose_t *settled);

#endif
