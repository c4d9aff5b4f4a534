/*
 * stack_svg.h - the side-view picture of a stack that `comlearn stack --svg` writes (stack_svg.c).
 *
 * Why here and not in lib/stack: the picture is output. It opens, writes and renames a file,
 * and the libraries under lib/ do no I/O; the planner hands back poses (stack_plan_t) and the
 * program decides what to draw and where. Geometry only: no URDF inertial.
 */
#ifndef COMLEARN_APP_STACK_SVG_H
#define COMLEARN_APP_STACK_SVG_H

#include <stddef.h>

#include "comlearn/stack.h"

/* A side view (looking along +y: x right, z up) of meshes_link[i] at poses[i] (world, SI), with
 * B's top, each object's believed CoM (com_link_m[i], link frame; the array may be NULL) as a
 * marker, and a title (may be NULL); 1 <= count <= STACK_MAX_OBJECTS. Writes the SVG file at path
 * (PATH.tmp, then renamed; never a partial file at path). All pointers are borrowed. Allocates a
 * working set, freed before it returns. Returns 0, or -1 with errno set (EINVAL for bad input,
 * ENOMEM, ENAMETOOLONG, or the errno of fopen / fprintf / fclose / rename). */
int stack_svg_write(const char *path, const model_mesh_t *const *meshes_link,
                    const model_pose_t *poses, const double (*com_link_m)[3], size_t count,
                    const char *title);

/* One object of a simulated stack (stack_svg_write_run). Poses are the link frame's in the world
 * (SI); CoMs are link-frame points. */
typedef struct {
  const model_mesh_t *mesh_link; /* geometry, link frame (borrowed) */
  const char *name;              /* label, e.g. "rock_1_uneven" (escaped here); NULL: "object" */
  model_pose_t planned;          /* the release pose of the plan */
  model_pose_t final;            /* the pose when the simulation ended */
  double com_used_m[3];          /* the CoM the plan was made on (learned, bbox or true) */
  double com_true_m[3];          /* the URDF truth */
} stack_svg_object_t;

/* The stack as the simulation left it, over the plan: each object shaded at its final pose; its
 * planned pose as a dashed outline (the convex hull of its vertices seen along +y, class
 * "planned"); at the final pose its true CoM (a ringed dot, class "com-true") and the CoM the plan
 * used (a red cross, class "com-used"; legend "<com_label> CoM (used by the plan)"), each with
 * data-world-m="x y z" (m), and its name (class "name") to its right; the plan's support
 * polygons in green (class "support", data-level k): with order (bottom first, count distinct
 * indices; NULL: none) order[0] on B (its vertices within 5 um of z = 0) and order[k] on
 * order[k - 1] (the vertices of either within 5 um of the other's surface, over a triangle's
 * interior), each the convex hull of those points seen from the side. An object whose final
 * lowest point is more than 50 mm below B's top fell off B (the simulated world has nothing
 * below B): it is named in the legend and not drawn at its final pose. The frame's mapping is
 * on <g class="frame"> (data-scale-px-m, data-x0-m, data-z0-m, data-ox-px, data-oy-px: px x = ox +
 * scale (x - x0), px y = oy - scale (z - z0)). title may be NULL. Written as stack_svg_write
 * writes (PATH.tmp, renamed). Allocates a working set, freed before it returns. Returns 0, or -1
 * with errno (EINVAL: NULL path / objects, count outside 1..STACK_MAX_OBJECTS, a bad mesh, pose
 * or CoM, order not a permutation; ENOMEM, ENAMETOOLONG, or the errno of fopen / fprintf / fclose /
 * rename). */
int stack_svg_write_run(const char *path, const stack_svg_object_t *objects, size_t count,
                        const size_t *order, const char *com_label, const char *title);

#endif
