/*
 * rockgen.h - the bundled rocks: a seeded, deterministic generator of rock-like meshes with planar
 * fracture faces, their two-material mass properties, and the analysis of planar patches that the
 * asset tests and the documentation table use.
 *
 * A rock is a star-shaped surface around the origin: a geodesic sphere (20 f^2 triangles) whose
 * vertex in direction d sits at radius r(d) = ellipsoid(d) * (1 + smooth random lobes). Each
 * fracture plane (n, h) clamps r(d) <= h / (d . n) where d . n > 0, so the vertices it clamps lie
 * on the plane and the plane supports the rock. A radial surface over a sphere triangulation is
 * closed, outward and free of self-intersection by construction (every triangle subtends a
 * positive solid angle from the origin).
 *
 * The link frame of a rock: origin at the bounding-box center of its mesh, axes as generated.
 * Vertices are rounded to float32, which is what binary STL stores and what assimp reads, so the
 * mass properties computed here are those of the mesh the simulator loads.
 *
 * Units SI. Memory: rockgen_shape_build() fills a model_mesh_t (caller frees with
 * model_mesh_free()); nothing else allocates except rockgen_patches_find()'s temporary memory.
 * Determinism: only +, -, *, / and sqrt on doubles (no libm transcendental functions), so the
 * output is bit-identical across optimisation levels and sanitizer builds on IEEE-754 hardware.
 */
#ifndef COMLEARN_TOOLS_ROCKGEN_H
#define COMLEARN_TOOLS_ROCKGEN_H

#include <stddef.h>
#include <stdint.h>

#include "comlearn/model.h"
#include "comlearn/model_inertial.h"

#ifdef __cplusplus
extern "C" {
#endif

enum { ROCKGEN_MAX_FRACTURES = 6, ROCKGEN_MAX_SUPPORT = 256, ROCKGEN_NAME_MAX = 32 };

/* A fracture face: the plane with outward normal `normal` (any length, normalised by the
 * generator) placed `depth_m` inside the unfractured surface's farthest vertex along it. */
typedef struct {
  double normal[3];
  double depth_m;
} rockgen_fracture_t;

/* One bundled rock shape and its two materials. The uneven rock's dense region is the half-space
 * { x : n . (x - com_uniform) >= region_offset_m }, n = region_normal normalised, com_uniform the
 * uniform-density CoM of the generated mesh. */
typedef struct {
  char name[ROCKGEN_NAME_MAX]; /* file stem and URDF link name, e.g. "rock_1" (a value, so a
                                     copied spec is self-contained) */
  uint64_t seed;               /* seeds the lobes */
  unsigned frequency;          /* geodesic frequency f: 20 f^2 triangles, 10 f^2 + 2 vertices */
  double semi_axes_m[3];       /* base ellipsoid */
  unsigned lobe_count;         /* broad lobes: shape */
  double lobe_amplitude;       /* relative radius change, +-, of each broad lobe */
  double lobe_cos;             /* cosine of a broad lobe's angular radius */
  unsigned bump_count;         /* small lobes: surface irregularity */
  double bump_amplitude;
  double bump_cos;
  size_t fracture_count;
  rockgen_fracture_t fractures[ROCKGEN_MAX_FRACTURES];
  double density_kg_m3;    /* the rock (even rock: everywhere) */
  double region_normal[3]; /* uneven rock: dense half-space, see above */
  double region_offset_m;
  double region_density_kg_m3;
} rockgen_spec_t;

/* The parameter table of the bundled rocks (tools/rockgen_table.c). Index out of range: NULL. */
size_t rockgen_spec_count(void);
const rockgen_spec_t *rockgen_spec_get(size_t index);

/* ---- random rocks (tools/rockgen_random.c) -------------------------------------------------- */

/* A random rock in the style of the table: name "rock_r<seed>" (seed in decimal), frequency 10,
 * 6 lobes of amplitude 0.20 (cos 0.25-0.35), 26 bumps of 0.06 (cos 0.86-0.88), semi-axes
 * x 30-38, y 26-31, z 24-28 mm, four fractures: bottom (0, 0, -1) depth 6-7 mm, side (+-1, 0, 0)
 * depth 6.5-7.5 mm, two oblique faces with unit normals whose z is in [0.4, 0.75] (azimuths at
 * least 60 degrees apart from each other and from the side face) depth 3-5.5 mm; 2650 kg/m^3
 * with a 5200 kg/m^3 half-space of random unit normal at 2-4 mm from the uniform-density CoM.
 *
 * Rule: attempt k (k = 0, 1, ...) draws every number from the splitmix64 stream whose state is the
 * (k+1)-th splitmix64 output of `seed`; rockgen_spec_random() returns the first attempt that
 * rockgen_random_accept() accepts, at most ROCKGEN_RANDOM_MAX_ATTEMPTS. Deterministic (only
 * + - * / sqrt), so a seed names one rock on every build. */
enum { ROCKGEN_RANDOM_MAX_ATTEMPTS = 32 };

/* Acceptance: the mesh builds (closed by construction), its convex hull builds (model_mesh_hull;
 * it failed on ~4 % of these shapes until its visibility walk became exact, docs/model.md), its
 * largest planar patch (area >= 1
 * cm^2) is the bottom face with normal (0, 0, -1), that face is >= ROCKGEN_RANDOM_MIN_WIDTH_M wide,
 * and both the uniform and the uneven CoM project >= ROCKGEN_RANDOM_MIN_MARGIN_M inside its support
 * polygon (the rock rests upright for either material). */
#define ROCKGEN_RANDOM_MIN_MARGIN_M 0.005
#define ROCKGEN_RANDOM_MIN_WIDTH_M 0.020

/* Attempt `attempt` of `seed`, unchecked. Does not allocate. MODEL_E_ARG for NULL out. */
model_status_t rockgen_spec_random_draw(uint64_t seed, unsigned attempt, rockgen_spec_t *out);

/* Does `spec` pass the acceptance rule above? Writes 1 or 0 to *accepted and, when non-NULL, the
 * bottom face's margin for the uneven CoM to *margin_m (NaN when there is no bottom face).
 * Builds the mesh (allocates temporarily). Errors of rockgen_shape_build / rockgen_mass other than
 * a spec the shape cannot take (MODEL_E_ARG there counts as "not accepted") are returned. */
model_status_t rockgen_random_accept(const rockgen_spec_t *spec, int *accepted, double *margin_m);

/* The first accepted attempt of `seed` (see the rule above) into *out. Allocates temporarily.
 * MODEL_E_ARG for NULL out; MODEL_E_DEGENERATE when no attempt in ROCKGEN_RANDOM_MAX_ATTEMPTS is
 * accepted (not seen in practice); MODEL_E_NOMEM. Thread-safe (no globals). */
model_status_t rockgen_spec_random(uint64_t seed, rockgen_spec_t *out);

/* Build a rock's mesh in its link frame (see above). out must not own arrays; allocates.
 * MODEL_E_ARG for a NULL or invalid spec (frequency 0 or > 64, non-positive axes, depth < 0),
 * MODEL_E_NOMEM. */
model_status_t rockgen_shape_build(const rockgen_spec_t *spec, model_mesh_t *out);

/* Mass properties of a rock's mesh: `even` at the uniform density, `uneven` with the dense
 * region, which is written to *region (link frame, unit normal). Any output may be NULL. */
model_status_t rockgen_mass(const rockgen_spec_t *spec, const model_mesh_t *mesh,
                            model_mass_t *even, model_mass_t *uneven, model_halfspace_t *region);

/* ---- planar patches (analysis of any closed mesh) ------------------------------------------ */

/* A maximal edge-connected group of coplanar triangles, and the polygon on which the body rests
 * when that plane is put on a table. */
typedef struct {
  double normal[3]; /* outward unit normal (area-weighted mean of its triangles) */
  double offset_m;  /* plane: normal . x = offset_m (mean over its vertices) */
  double area_m2;
  size_t triangle_count;
  double width_m;          /* smallest width of the convex hull of the patch's vertices */
  double diameter_m;       /* largest distance between two of its vertices */
  double support_excess_m; /* max over all mesh vertices of normal . v - offset_m: the plane
                                  supports the body when this is <= the coplanarity tolerance */
  double basis[2][3];      /* in-plane axes u, v (unit, u x v = normal) */
  size_t support_count;    /* counter-clockwise convex polygon (u, v) of every mesh vertex on
                                  the plane: where the body touches the table */
  double support_uv[ROCKGEN_MAX_SUPPORT][2];
} rockgen_patch_t;

/* Coplanarity: every vertex within ROCKGEN_PLANE_TOL_M of the plane and every normal within
 * ROCKGEN_PLANE_COS of the patch's first triangle's. The tolerance covers float32 rounding of
 * vertices (~4e-9 m at 5 cm) and stays far below how much a curved 3 mm triangle bends (~1e-4 m).
 */
#define ROCKGEN_PLANE_TOL_M 1e-6
#define ROCKGEN_PLANE_COS 0.99999999 /* ~1.4e-4 rad */

/* Find the planar patches of a closed mesh with area >= min_area_m2, largest first. Writes up to
 * `capacity` patches and the number found (which may exceed capacity) to *count. Allocates
 * temporary memory. MODEL_E_ARG, MODEL_E_NOMEM, MODEL_E_DEGENERATE (a zero-area triangle). */
model_status_t rockgen_patches_find(const model_mesh_t *mesh, double min_area_m2,
                                    rockgen_patch_t *patches, size_t capacity, size_t *count);

/* Static stability margin of a body with its CoM at com_m resting on `patch` under gravity along
 * -normal: the signed distance from the CoM's projection onto the plane to the boundary of the
 * support polygon, positive inside (the body rests), negative outside (it tips). */
double rockgen_patch_margin(const rockgen_patch_t *patch, const double com_m[3]);

#ifdef __cplusplus
}
#endif

#endif /* COMLEARN_TOOLS_ROCKGEN_H */
