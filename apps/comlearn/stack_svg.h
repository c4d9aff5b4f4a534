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

#endif
