/*
 * comlearn/model.h - object geometry: meshes, convex hulls, bounding boxes, URDF geometry.
 *
 * This is the estimator's view of an object: what perception could give (the surface, its
 * bounding box, its convex hull) and nothing of its inertial truth. The URDF `<inertial>` element
 * is read only through comlearn/model_inertial.h, which lives in a separate library
 * (comlearn_model_sim) that the estimator does not link.
 *
 * Units are SI (metres, kilograms). Frames: a mesh's vertices are in the frame they were loaded in;
 * an object's mesh is in its URDF link frame (the collision origin and scale already applied).
 *
 * Memory: functions that fill a model_mesh_t or model_object_t allocate with malloc; the caller
 * releases with model_mesh_free() / model_object_free(). Nothing else allocates unless it says so.
 * On error, output structs are left zeroed (safe to free). No function prints anything.
 *
 * Thread safety: functions touch only their arguments; distinct objects may be used from
 * distinct threads. Loading (assimp, urdfdom) is reentrant per call.
 */
#ifndef COMLEARN_MODEL_H
#define COMLEARN_MODEL_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* One status enum for the module: 0 is success, negative values are errors. */
typedef enum {
  MODEL_OK = 0,
  MODEL_E_ARG = -1,           /* NULL pointer, empty path, bad scale or density */
  MODEL_E_NOFILE = -2,        /* file does not exist or cannot be read */
  MODEL_E_PARSE = -3,         /* URDF or mesh file is corrupt or not understood */
  MODEL_E_NOLINK = -4,        /* the URDF has no link of that name */
  MODEL_E_NOGEOM = -5,        /* the link has no collision or visual geometry we can use */
  MODEL_E_OPEN = -6,          /* mesh not closed: a boundary or non-manifold edge */
  MODEL_E_ORIENT = -7,        /* triangles not consistently oriented (cannot tell outside) */
  MODEL_E_DEGENERATE = -8,    /* mesh with (near) zero volume, or too few triangles */
  MODEL_E_NONFINITE = -9,     /* a NaN or infinite number in the input */
  MODEL_E_INERTIAL = -10,     /* missing inertial, or mass / inertia not finite and positive */
  MODEL_E_INERTIA_TRIANGLE = -11, /* principal moments violate the triangle inequality */
  MODEL_E_NOMEM = -12,        /* allocation failed */
  MODEL_E_UNSUPPORTED = -13,  /* mesh format or URDF geometry type not supported */
  MODEL_E_REGION = -14,       /* a density region that is not valid (zero normal, ...) */
  MODEL_E_HULL = -15          /* convex hull failed (all points coplanar, iteration cap) */
} model_status_t;

/* A static English description of a status; never NULL. */
const char *model_status_str(model_status_t status);

/* Caller-owned buffer for a human-readable error detail (names the file, link or triangle).
 * Every function taking `model_error_t *err` accepts NULL and writes a NUL-terminated message on
 * failure only. */
typedef struct {
  char msg[512];
} model_error_t;

/* A closed, outward-oriented triangle mesh. Triangles are counter-clockwise seen from outside.
 * Both arrays are owned by the struct (malloc), released by model_mesh_free(). */
typedef struct {
  double (*vertices_m)[3];
  uint32_t (*triangles)[3];
  size_t vertex_count;
  size_t triangle_count;
} model_mesh_t;

/* What model_mesh_check() changed. Repairs are reported, never silent. */
typedef struct {
  size_t merged_vertices;      /* exact-duplicate vertices joined */
  size_t removed_degenerate;   /* triangles with a repeated vertex index or zero area, dropped */
  int flipped;                 /* 1 when the mesh was inside-out and every triangle was flipped */
} model_mesh_report_t;

/* Release a mesh's arrays and zero it. NULL is fine. */
void model_mesh_free(model_mesh_t *mesh);

/* Deep copy of src into dst (dst must not own arrays). May allocate. */
model_status_t model_mesh_copy(const model_mesh_t *src, model_mesh_t *dst);

/* Validate a mesh in place: every number finite; exact-duplicate vertices joined; degenerate
 * triangles dropped; every edge shared by exactly two triangles with opposite orientation
 * (else MODEL_E_OPEN or MODEL_E_ORIENT); a mesh whose signed volume is negative (inside-out) is
 * repaired by flipping all triangles. `report` may be NULL. May reallocate the arrays. */
model_status_t model_mesh_check(model_mesh_t *mesh, model_mesh_report_t *report,
                                model_error_t *err);

/* Load a mesh file through assimp (STL, OBJ, PLY, DAE and whatever else assimp reads), all its
 * meshes merged with their node transforms applied, triangulated, scaled per axis by scale[3]
 * (NULL means 1,1,1), then model_mesh_check()ed. DAE files carry a unit; it is honoured. */
model_status_t model_mesh_load(const char *path, const double scale[3], model_mesh_t *out,
                               model_mesh_report_t *report, model_error_t *err);

/* Write a mesh through assimp's exporter. format: "stl" (binary), "stlb", "obj", "ply",
 * "plyb", "collada" - any assimp export format id. */
model_status_t model_mesh_save(const model_mesh_t *mesh, const char *path, const char *format,
                               model_error_t *err);

/* Axis-aligned bounding box. */
typedef struct {
  double min_m[3];
  double max_m[3];
} model_aabb_t;

/* Bounding box of the vertices. An empty mesh gives MODEL_E_DEGENERATE. */
model_status_t model_mesh_aabb(const model_mesh_t *mesh, model_aabb_t *out);

/* Center of a box, (min + max) / 2. */
void model_aabb_center(const model_aabb_t *box, double center_m[3]);

/* Mass properties of a rigid body: mass, center of mass and the inertia tensor about the CoM,
 * all in the frame of the mesh (or URDF link). inertia is symmetric, row-major. */
typedef struct {
  double mass_kg;
  double com_m[3];
  double inertia_kg_m2[3][3];
} model_mass_t;

/* Exact mass properties of a closed, outward mesh of uniform density, by polyhedral integration
 * (signed tetrahedra, exact up to rounding). This is geometry, not truth: it is the estimator's
 * prior (the uniform-density CoM). density_kg_m3 must be finite and > 0. */
model_status_t model_mesh_mass(const model_mesh_t *mesh, double density_kg_m3, model_mass_t *out);

/* Convex hull of a mesh's vertices as a closed, outward mesh whose vertices are a subset of the
 * input's. Coplanar hull facets come out triangulated. Allocates. */
model_status_t model_mesh_hull(const model_mesh_t *mesh, model_mesh_t *hull, model_error_t *err);

/* An object as the estimator sees it: the collision geometry of one URDF link. */
typedef struct {
  char robot_name[128];
  char link_name[128];
  char mesh_path[1024];   /* resolved path of the first mesh file, "" for primitives */
  model_mesh_t mesh;      /* all collision geometry of the link, in the link frame */
  model_aabb_t aabb;      /* bounding box of mesh, link frame */
} model_object_t;

/* Load a link's geometry from a URDF: its <collision> elements (or <visual> when it has none):
 * meshes (relative and package:// paths resolved against the URDF's folder, `scale` honoured) and
 * boxes, each placed by its <origin>. link_name NULL means the root link. Reads no inertial data.
 * urdfdom's console output is silenced and its exceptions caught. */
model_status_t model_object_load(const char *urdf_path, const char *link_name,
                                 model_object_t *out, model_error_t *err);

/* Release an object's mesh and zero it. NULL is fine. */
void model_object_free(model_object_t *obj);

#ifdef __cplusplus
}
#endif

#endif /* COMLEARN_MODEL_H */
