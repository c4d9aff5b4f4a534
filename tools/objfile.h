/*
 * objfile.h - writing generated objects to disk: binary STL meshes and the URDF elements that
 * carry them. Shared by comlearn-rockgen, comlearn-shapegen and the benchmarks that generate
 * objects (bench_coverage); part of the comlearn_rockgen library.
 *
 * Every function returns 0, or -1 with errno set by the failing call (the caller names the path
 * in its message). Nothing here allocates.
 */
#ifndef COMLEARN_TOOLS_OBJFILE_H
#define COMLEARN_TOOLS_OBJFILE_H

#include <stdio.h>

#include "comlearn/model.h"

#ifdef __cplusplus
extern "C" {
#endif

/* mkdir(path, 0777); an existing folder is fine. */
int objfile_mkdir(const char *path);

/* Binary STL (little-endian, metres, float32 coordinates, unit facet normals from the winding).
 * header: up to 80 bytes of text for the header (it must not start with "solid": readers would
 * take the file for ASCII STL); longer text is cut. */
int objfile_write_stl(const model_mesh_t *mesh, const char *path, const char *header);

/* The <inertial> element of a link (indented 4 spaces, every number %.17g): origin = the CoM,
 * rpy 0, the full inertia tensor about the CoM in link axes. */
void objfile_put_inertial(FILE *f, const model_mass_t *mass);

/* A link's <visual> (material `material`, colour `rgba`, e.g. "0.55 0.51 0.46 1") and
 * <collision> elements, both the mesh file `mesh_rel` (relative to the URDF). */
void objfile_put_mesh_geometry(FILE *f, const char *mesh_rel, const char *material,
                               const char *rgba);

#ifdef __cplusplus
}
#endif

#endif
