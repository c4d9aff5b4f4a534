/* support_geom.h - private geometry shared by support.c and support_faces.c: mesh validation
 * and the real contact of a mesh on a plane. Defined in support.c. */
#ifndef COMLEARN_MODEL_SUPPORT_GEOM_H
#define COMLEARN_MODEL_SUPPORT_GEOM_H

#include <stddef.h>

#include "comlearn/model_support.h"

/* Planar hull, area, width and margin: model_polygon_*() in comlearn/model.h. */

/* The real contact of a mesh on a plane: the mesh triangles whose three vertices lie on it. */
typedef struct {
  size_t triangle_count; /* triangles in the plane */
  double area_m2;        /* the sum of their areas (the real contact area) */
  size_t region_count;   /* groups of them that touch (share a vertex), transitively */
  double region_area_m2; /* the largest group's real area */
  double region_width_m; /* the smallest width of that group's convex hull */
} model_support_contact_t;

/* Analyse the real contact: on[v] != 0 marks the vertices on the plane, xy[v] their 2-D
 * coordinates in it (every vertex has an entry; only those marked are read). When tri_xy is not
 * NULL it receives the in-plane triangles' corners (room for mesh->triangle_count). Allocates
 * temporary memory: MODEL_E_NOMEM, else MODEL_OK. */
model_status_t model_support_contact(const model_mesh_t *mesh, const double (*xy)[2],
                                     const unsigned char *on, double (*tri_xy)[3][2],
                                     model_support_contact_t *out);

/* How far the vertices of the in-plane triangles (all three marked in on[]) lie inside the plane
 * n . x = top, at most: max of top - n . p[v] (p: the vertices in the frame of n and top). */
double model_support_spread(const model_mesh_t *mesh, const double (*p)[3], const double n[3],
                            double top, const unsigned char *on);

/* The contact is a flat patch (model_patch_t.flat, model_face_t.flat): its largest region is as
 * large and wide as cfg asks, and its vertices lie within cfg->flat_spread_m of the plane. */
int model_support_flat(const model_support_contact_t *ct, double spread_m,
                       const model_regime_config_t *cfg);

/* The contact is closed (model_patch_t.closed): one region whose real area is hull_area_m2, the
 * area of the convex hull of every touching vertex, to a relative 1e-6. */
int model_support_closed(const model_support_contact_t *ct, double hull_area_m2);

/* The in-plane mesh edges (both ends marked in on[]) close the convex polygon hull (nh vertices,
 * in the coordinates xy of its vertices): each of its sides is one such edge, as the bottom ring
 * of a torus. Then the contact's hull clipped by any line is the hull of the contact on that side
 * (the line crosses the ring's edges), as for a closed patch. 0 for fewer than 3 sides. */
int model_support_edges_close(const model_mesh_t *mesh, const double (*xy)[2],
                              const unsigned char *on, const double (*hull)[2], size_t nh);

/* The chord of the line p + s d (d unit) across the convex polygon poly (n vertices): 1 with
 * [*s0, *s1] when it crosses it along a positive length, else 0. */
int model_polygon_chord(const double (*poly)[2], size_t n, const double p[2], const double d[2],
                        double *s0, double *s1);

/* Extent of the real contact along the line p + s d (d unit): the smallest and the largest s at
 * which the line meets one of the n triangles (corners in tri_xy). Returns 1 with [*s0, *s1] when
 * that extent has a positive length, 0 otherwise (no triangle met, or only at one point). The
 * extent may bridge gaps between separate regions: over a line, the convex hull of the contact is
 * the interval between its outermost points, whatever lies between. */
int model_support_tris_chord(const double (*tri_xy)[3][2], size_t n, const double p[2],
                             const double d[2], double *s0, double *s1);

#endif
