/*
 * shapegen.h - adversarial and realistic test objects: a seeded, deterministic generator of
 * shapes the estimator was not designed for (feet, rings, rims, mugs, pebbles, scanned noise,
 * near-degenerate plates, faceted blocks), each with two materials, in the conventions of
 * tools/rockgen.h.
 *
 * Every object is one closed, outward, manifold triangle mesh in its link frame: origin at the
 * bounding-box center of the mesh, vertices rounded to float32 through a volatile float exactly as
 * rockgen does (what binary STL stores and assimp reads back), so the mass properties computed
 * here with lib/model are exact for the stored file. Two materials: `even` (one density) and
 * `uneven` (a dense half-space, as rockgen's random rocks).
 *
 * Constructions (tools/shapegen_mesh.c):
 *   box       a box whose faces are split into a grid of cells (1 x 1 for plain boxes)
 *   slab      a height field over a rectangular footprint [-X, X] x [-Y, Y] on a rectilinear grid:
 *             bottom z = b(x, y), top z = t(x, y), vertical walls along the outline. Feet are the
 *             places where b = 0 exactly (coplanar patches); around them b rises to the
 *             clearance over a slope of width `slope_m` (steep cells, not vertical walls)
 *   revolve   a closed profile polygon in the (r, z) half-plane turned about z in N segments; a
 *             profile point with r = 0 becomes one pole vertex; the mug's handle is a tube swept
 *             along a half ellipse whose two ends are holes cut in the outer wall (a true union:
 *             one closed surface of genus 1, not a separate shell)
 *   rock      tools/rockgen's radial surface (pebble, lumpy, scanned rock)
 *
 * Determinism: only + - * / and sqrt on doubles. Round shapes take cos / sin of 2 pi j / n from a
 * Taylor series after an exact octant reduction (shapegen_cos_sin_turn), not from libm, so the
 * output is bit-identical across optimisation levels and the sanitizer build on IEEE-754 hardware
 * (as rockgen; C11 without GNU extensions compiles with -ffp-contract=off).
 *
 * Units SI, lengths in metres. Memory: shapegen_shape_build() and shapegen_generate() allocate
 * (the caller frees with model_mesh_free() / shapegen_object_free()); nothing is global, every
 * function is thread-safe.
 */
#ifndef COMLEARN_TOOLS_SHAPEGEN_H
#define COMLEARN_TOOLS_SHAPEGEN_H

#include <stddef.h>
#include <stdint.h>

#include "comlearn/model.h"
#include "comlearn/model_inertial.h"
#include "rockgen.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
  SHAPEGEN_BOX = 0, /* box of random dimensions, 20-120 mm each */
  SHAPEGEN_DOMINO,  /* 48 x 24 x 7.5 mm, each +-15 %: one pair of faces >= 10 mm wide */
  SHAPEGEN_FEET2,   /* a slab on two separate coplanar feet (rails or pads), >= 10 mm apart */
  SHAPEGEN_FEET3,   /* a slab on three small feet (round or square) */
  SHAPEGEN_FEET4,   /* a slab on four small feet (round or square) */
  SHAPEGEN_RING,    /* a torus lying flat: a ring of vertices at the bottom, no flat triangle */
  SHAPEGEN_RIM,     /* a bowl or plate on a narrow foot ring; the top rim a flat annulus */
  SHAPEGEN_MUG,     /* an open cup with a handle; a full bottom disk or a recessed foot ring */
  SHAPEGEN_PEBBLE,  /* a smooth lumpy ellipsoid without any flat face */
  SHAPEGEN_LUMPY,   /* a lumpy rock with one to three small, narrow or tilted flat faces */
  SHAPEGEN_SCANNED, /* a finely tessellated box or a rock with 1-20 um vertex noise */
  SHAPEGEN_PLATE,   /* near-degenerate: thin plate, thin disk, long bar, 64-128-sided cylinder */
  SHAPEGEN_TILTED,  /* a block whose bottom and top are facets at 0.1-1 degree to each other */
  SHAPEGEN_FAMILY_COUNT
} shapegen_family_t;

/* The family's name ("box", "feet2", ...); NULL for an out-of-range value. */
const char *shapegen_family_name(shapegen_family_t family);

/* The family named `name` into *out: 0, or -1 for an unknown name (or NULL). */
int shapegen_family_parse(const char *name, shapegen_family_t *out);

enum {
  SHAPEGEN_NAME_MAX = 48,
  SHAPEGEN_MAX_LINES = 192,   /* grid lines per axis of a slab */
  SHAPEGEN_MAX_PROFILE = 192, /* points of a revolve profile */
  SHAPEGEN_MAX_FEET = 4,
  SHAPEGEN_MAX_ATTEMPTS = 48
};

/* ---- shape parameters ---------------------------------------------------------------------- */

/* A box [-size/2, size/2] with every face split into cells: `cells[k]` along axis k (>= 1). */
typedef struct {
  double size_m[3];
  unsigned cells[3];
} shapegen_box_t;

/* A foot of a slab: where b = 0. Square: the rectangle |x - cx| <= half[0], |y - cy| <= half[1],
 * distance d = the L-infinity distance to it. Round: the disk of radius half[0], d = the
 * Euclidean distance to it. */
typedef struct {
  double center_m[2];
  double half_m[2];
  int round;
} shapegen_foot_t;

/* A slab (height field, see the file comment) over [-half[0], half[0]] x [-half[1], half[1]].
 * Grid lines lines_m[a][0 .. line_count[a]-1] ascending along axis a, first -half, last +half.
 * At grid vertex (x_i, y_j):
 *   b = bottom_m[0][i] + bottom_m[1][j] + clearance_m * min(1, d / slope_m)  (d = distance to the
 *       nearest foot; the last term only when foot_count > 0)
 *   t = top0_m + top_m[0][i] + top_m[1][j]
 * and both surfaces are linear on each grid triangle. Cells are split along the diagonal that
 * makes the bottom convex (the lower of the two diagonal midpoints) and the top concave, so a
 * square foot's slope is exactly b = clearance * min(1, d / slope) and every cell of a separable
 * part is planar: volume and moments have closed forms (tests/check_shapegen.c). */
typedef struct {
  double half_m[2];
  size_t line_count[2];
  double lines_m[2][SHAPEGEN_MAX_LINES];
  double bottom_m[2][SHAPEGEN_MAX_LINES];
  double top_m[2][SHAPEGEN_MAX_LINES];
  double top0_m;
  double clearance_m;
  double slope_m;
  size_t foot_count;
  shapegen_foot_t feet[SHAPEGEN_MAX_FEET];
} shapegen_slab_t;

/* A solid of revolution: the profile rz_m[0 .. point_count-1] (r >= 0, a simple polygon,
 * counter-clockwise in the (r, z) plane: interior to the left) turned about the z axis in
 * `segments` steps, vertex j of a circle at angle 2 pi j / segments from +x towards +y. Each quad
 * of the surface is a planar trapezoid, so the solid's volume is exactly
 * segments * sin(2 pi / segments) * (integral of r over the profile), and its CoM is on the axis at
 * z = (integral of r z) / (integral of r). */
typedef struct {
  size_t point_count;
  double rz_m[SHAPEGEN_MAX_PROFILE][2];
  unsigned segments;
} shapegen_revolve_t;

/* The mug's handle on a revolve whose profile edges upper_row .. upper_row + rows - 1 and
 * lower_row .. lower_row + rows - 1 are rows of the vertical outer wall (radius radius_m, rows of
 * equal height). Holes: those rows x the wall cells of columns -columns .. columns - 1 around
 * angle 0 (+x). The tube: loops of the hole's boundary swept along the half ellipse
 * (radius_m + reach_m cos p, 0, center_z_m + half_height_m sin p), p from 90 to -90 degrees, in
 * `loops` steps, their cross-section blended from the hole's rectangle to the inscribed ellipse
 * towards the middle. */
typedef struct {
  int present;
  unsigned columns;
  size_t upper_row, lower_row, rows;
  unsigned loops;
  double radius_m;
  double reach_m;
  double center_z_m;
  double half_height_m;
} shapegen_handle_t;

typedef enum {
  SHAPEGEN_SHAPE_BOX = 0,
  SHAPEGEN_SHAPE_SLAB,
  SHAPEGEN_SHAPE_REVOLVE,
  SHAPEGEN_SHAPE_ROCK
} shapegen_shape_t;

/* One object: everything drawn from its seed and attempt. The uneven material's dense region is
 * { x : n . (x - c_u) >= region_offset_m } with n drawn from region_seed (see shapegen_mass) and
 * c_u the uniform-density CoM of the mesh; region_offset_m is solved from region_shift_frac. */
typedef struct {
  shapegen_family_t family;
  uint64_t seed;
  unsigned attempt;
  char name[SHAPEGEN_NAME_MAX];    /* "<family>_s<seed>", e.g. "feet2_s17" */
  char variant[SHAPEGEN_NAME_MAX]; /* e.g. "round feet", "bowl", "foot ring", "cylinder 96" */
  shapegen_shape_t shape;
  shapegen_box_t box;
  shapegen_slab_t slab;
  shapegen_revolve_t rev;
  shapegen_handle_t handle;
  rockgen_spec_t rock;
  int lay_on_side; /* revolve: (x, y, z) -> (z, y, -x), the axis along x */
  double noise_m;  /* scanned: every coordinate + uniform(-noise, noise) */
  uint64_t noise_seed;
  char material[24];
  double density_kg_m3; /* 700-2700 */
  double region_ratio;  /* dense region density / density, 1.5-3 */
  uint64_t region_seed;
  double region_shift_frac; /* target CoM shift = 2 mm + frac * (span up to 6 mm) */
} shapegen_spec_t;

/* ---- the rule ------------------------------------------------------------------------------ */

/* Attempt k (k = 0, 1, ...) of (family, seed) draws every number from the splitmix64 stream whose
 * state is the (k+1)-th splitmix64 output of seed ^ fnv1a64(family name). shapegen_generate()
 * returns the first attempt that is accepted, at most SHAPEGEN_MAX_ATTEMPTS:
 *   - the mesh builds and model_mesh_check() repairs nothing (no merge, drop or flip);
 *   - model_mesh_hull() succeeds;
 *   - the largest bounding-box extent is 20-120 mm;
 *   - the dense region can move the CoM 2-6 mm (shapegen_mass) and model_mass_plausible() (which
 *     includes model_mass_check(); mass >= 1 g, ...) passes for both materials;
 *   - for each material some hull face has the CoM projecting >= SHAPEGEN_MIN_MARGIN_M inside its
 *     support polygon (the convex hull of the mesh vertices within SHAPEGEN_PLANE_TOL_M of the
 *     face's plane): the object can rest somewhere. */
#define SHAPEGEN_MIN_MARGIN_M 0.001
#define SHAPEGEN_PLANE_TOL_M 1e-6
#define SHAPEGEN_SHIFT_MIN_M 0.002
#define SHAPEGEN_SHIFT_MAX_M 0.006

/* Attempt `attempt` of (family, seed), unchecked. Does not allocate, except temporarily for a
 * scanned rock (rockgen_spec_random builds candidate rocks). MODEL_E_ARG for a bad family or NULL
 * out; MODEL_E_DEGENERATE when the drawn numbers do not make a valid shape (counts as "not
 * accepted"). */
model_status_t shapegen_spec_draw(shapegen_family_t family, uint64_t seed, unsigned attempt,
                                  shapegen_spec_t *out);

/* Build the mesh of a spec in its link frame (see above). out must not own arrays; allocates.
 * MODEL_E_ARG (NULL, invalid parameters), MODEL_E_NOMEM, rockgen's errors for rocks. */
model_status_t shapegen_shape_build(const shapegen_spec_t *spec, model_mesh_t *out);

/* Mass properties: `even` at spec->density, `uneven` with the dense half-space, written to *region
 * (link frame, unit normal). The normal is the first of up to 32 uniform random unit vectors of the
 * splitmix64 stream seeded with region_seed along which some offset moves the CoM at least 2.2 mm
 * (scanned over 33 offsets); the target shift is 2 mm + frac * (min(6 mm, 0.95 x that maximum) -
 * 2 mm) and the offset is found by bisection (48 steps) between the maximum and the far end of the
 * body. Any output may be NULL. MODEL_E_REGION when no normal reaches 2.2 mm; lib/model errors. */
model_status_t shapegen_mass(const shapegen_spec_t *spec, const model_mesh_t *mesh,
                             model_mass_t *even, model_mass_t *uneven, model_halfspace_t *region);

/* The best resting margin of a body with its CoM at com_m over the faces of `hull` (the convex
 * hull of `mesh`): max over hull triangles of the signed distance from the CoM's projection onto
 * the triangle's plane to the boundary of the support polygon there (positive inside). The
 * outward normal of the best face into best_normal when non-NULL. -HUGE_VAL for an empty hull.
 * Allocates temporarily; MODEL_E_ARG, MODEL_E_NOMEM. */
model_status_t shapegen_rest_margin(const model_mesh_t *mesh, const model_mesh_t *hull,
                                    const double com_m[3], double *margin_m, double best_normal[3]);

/* An accepted object. */
typedef struct {
  shapegen_spec_t spec;
  model_mesh_t mesh; /* owned */
  model_mass_t even, uneven;
  model_halfspace_t region;
  double shift_m;                        /* |uneven CoM - even CoM| */
  double margin_even_m, margin_uneven_m; /* shapegen_rest_margin of each CoM */
} shapegen_object_t;

/* Is `spec` accepted (rule above)? On acceptance *accepted = 1 and *out holds the object (the
 * caller frees it); otherwise *accepted = 0 and *out is zeroed. Allocates. Errors other than a
 * shape the rule rejects (MODEL_E_NOMEM, ...) are returned. */
model_status_t shapegen_accept(const shapegen_spec_t *spec, int *accepted, shapegen_object_t *out);

/* The first accepted attempt of (family, seed) into *out. MODEL_E_ARG; MODEL_E_DEGENERATE when no
 * attempt in SHAPEGEN_MAX_ATTEMPTS is accepted; MODEL_E_NOMEM. */
model_status_t shapegen_generate(shapegen_family_t family, uint64_t seed, shapegen_object_t *out);

/* Release an object's mesh and zero it. NULL is fine. */
void shapegen_object_free(shapegen_object_t *obj);

/* Write an object as files: DIR (created if missing) /meshes/NAME.stl (binary STL) and
 * DIR/NAME_even.urdf, DIR/NAME_uneven.urdf (exact inertials, the mesh by relative path, a comment
 * naming the family, seed, variant, materials and dense region), NAME = spec.name. Returns 0, or
 * -1 with errno set and the path that failed in `failed` (may be NULL). The only I/O here
 * (tools/shapegen_write.c); comlearn-shapegen, tests and benchmarks call it. */
int shapegen_write(const shapegen_object_t *obj, const char *dir, char *failed, size_t failed_size);

/* cos and sin of 2 pi j / n (n > 0, any j), by exact integer reduction to the nearest quarter turn
 * (ties to even) and Taylor series of 11 terms on |x| <= pi / 4: within ~1 ulp of libm, and
 * symmetric: j = 0 gives exactly (1, 0), a quarter turn exactly (0, 1), and j, n - j are exact
 * mirror images (same cos, opposite sin). */
void shapegen_cos_sin_turn(long j, long n, double *c, double *s);

#ifdef __cplusplus
}
#endif

#endif /* COMLEARN_TOOLS_SHAPEGEN_H */
