/* shapegen_internal.h - what the shapegen sources share: a growable mesh, the PRNG and the
 * constructions. Not installed. */
#ifndef COMLEARN_TOOLS_SHAPEGEN_INTERNAL_H
#define COMLEARN_TOOLS_SHAPEGEN_INTERNAL_H

#include "comlearn/math3d.h"
#include "shapegen.h"

/* A mesh under construction. Appends never fail visibly: an allocation failure sets `nomem` and
 * later appends are ignored; sg_build_finish() then returns MODEL_E_NOMEM. */
typedef struct {
  double (*v)[3];
  uint32_t (*t)[3];
  size_t nv, nt, cap_v, cap_t;
  int nomem;
} sg_build_t;

void sg_build_init(sg_build_t *b);
void sg_build_free(sg_build_t *b);
uint32_t sg_vert(sg_build_t *b, double x, double y, double z);
void sg_tri(sg_build_t *b, uint32_t a, uint32_t c, uint32_t d);
/* Quad a b c d, counter-clockwise seen from outside: triangles (a, b, c), (a, c, d). */
void sg_quad(sg_build_t *b, uint32_t a, uint32_t c, uint32_t d, uint32_t e);
/* Move the mesh so that its bounding-box center is the origin, round to float32 and hand the
 * arrays to *out (b is left empty). */
model_status_t sg_build_finish(sg_build_t *b, model_mesh_t *out);

/* x rounded to float32 through a volatile (see tools/rockgen.c for why). */
double sg_to_float32(double x);

/* The constructions (shapegen_mesh.c). Errors: MODEL_E_ARG for invalid parameters. */
model_status_t sg_box_build(const shapegen_box_t *box, sg_build_t *b);
model_status_t sg_slab_build(const shapegen_slab_t *slab, sg_build_t *b);
model_status_t sg_revolve_build(const shapegen_revolve_t *rev, const shapegen_handle_t *handle,
                                sg_build_t *b);
/* Bottom height of a slab at grid vertex (i, j) (shapegen.h, shapegen_slab_t). */
double sg_slab_bottom(const shapegen_slab_t *slab, size_t i, size_t j);

/* Family parameters (shapegen_family.c): fill the shape part of *out from the stream. 0 on
 * success, -1 when the draw makes no valid shape. */
int sg_family_draw(shapegen_family_t family, uint64_t *state, shapegen_spec_t *out);

#endif /* COMLEARN_TOOLS_SHAPEGEN_INTERNAL_H */
