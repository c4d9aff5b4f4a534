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
 * distinct threads. Loading is reentrant per call, with two process-wide side effects of the
 * third-party libraries: assimp keeps its last error text in one global string (concurrent failing
 * loads may report each other's assimp detail), and the first URDF load installs a silent
 * console_bridge output handler for the whole process (see model_object_load).
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
  MODEL_E_ARG = -1,               /* NULL pointer, empty path, bad scale or density */
  MODEL_E_NOFILE = -2,            /* file does not exist or cannot be read */
  MODEL_E_PARSE = -3,             /* URDF or mesh file is corrupt or not understood */
  MODEL_E_NOLINK = -4,            /* the URDF has no link of that name */
  MODEL_E_NOGEOM = -5,            /* the link has no collision or visual geometry we can use */
  MODEL_E_OPEN = -6,              /* mesh not closed: a boundary or non-manifold edge */
  MODEL_E_ORIENT = -7,            /* triangles not consistently oriented (cannot tell outside) */
  MODEL_E_DEGENERATE = -8,        /* mesh with (near) zero volume, or too few triangles */
  MODEL_E_NONFINITE = -9,         /* a NaN or infinite number in the input */
  MODEL_E_INERTIAL = -10,         /* missing inertial, or mass / inertia not finite and positive */
  MODEL_E_INERTIA_TRIANGLE = -11, /* principal moments violate the triangle inequality */
  MODEL_E_NOMEM = -12,            /* allocation failed */
  MODEL_E_UNSUPPORTED = -13,      /* mesh format or URDF geometry type not supported */
  MODEL_E_REGION = -14,           /* a density region that is not valid (zero normal, ...) */
  MODEL_E_HULL = -15,             /* convex hull failed (all points coplanar, iteration cap) */
  MODEL_E_CHAIN = -16,            /* no kinematic chain between two links, or an unusable joint */
  MODEL_E_IMPLAUSIBLE = -17,      /* mass properties no real object of that shape can have */
  MODEL_E_POSE = -18,    /* absurd pose: not a unit quaternion, nothing of the object over B */
  MODEL_E_CAPACITY = -19 /* an output array or a fixed table too small */
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
  size_t removed_unreferenced; /* vertices no remaining triangle uses, dropped */
  int flipped;                 /* 1 when the mesh was inside-out and every triangle was flipped */
} model_mesh_report_t;

/* Release a mesh's arrays and zero it. NULL is fine. */
void model_mesh_free(model_mesh_t *mesh);

/* Deep copy of src into dst (dst must not own arrays). May allocate. */
model_status_t model_mesh_copy(const model_mesh_t *src, model_mesh_t *dst);

/* Validate a mesh in place, O(n log n) (sorting vertices and edges). In this order:
 *   rejected  MODEL_E_ARG         NULL arrays, a vertex index out of range, > 2^32 vertices
 *   rejected  MODEL_E_DEGENERATE  no vertices or triangles
 *   rejected  MODEL_E_NONFINITE   a NaN or infinite coordinate (the message names the vertex)
 *   repaired  vertices with bit-identical coordinates are joined (report->merged_vertices)
 *   repaired  triangles with a repeated vertex (after joining) or an exactly zero cross product
 *             are dropped (report->removed_degenerate); when the dropped triangle filled a hole
 *             the mesh then fails the closedness test below
 *   repaired  vertices no triangle uses are dropped (report->removed_unreferenced)
 *   rejected  MODEL_E_DEGENERATE  fewer than 4 triangles left
 *   rejected  MODEL_E_OPEN        an undirected edge used by 1 triangle (boundary) or by more than
 *                                 2 (non-manifold, e.g. two solids sharing an edge)
 *   rejected  MODEL_E_ORIENT      an edge used twice in the same direction (neighbouring
 *                                 triangles wound oppositely: which side is outside is unknown)
 *   rejected  MODEL_E_DEGENERATE  |signed volume| <= 1e-12 * (largest bbox extent)^3
 *   repaired  signed volume < 0 (inside-out): every triangle flipped (report->flipped = 1)
 * Orientation is judged for the whole mesh, not per shell: a shell inside another with inward
 * triangles is a cavity and is kept as it is. Vertices shared by otherwise separate sheets
 * (non-manifold vertices) are accepted. Surviving vertices keep their relative order.
 * On success the arrays may have been reallocated; on error the mesh is left unchanged.
 * `report` may be NULL; it is filled as far as the check got. Allocates temporary memory. */
model_status_t model_mesh_check(model_mesh_t *mesh, model_mesh_report_t *report,
                                model_error_t *err);

/* Limits of model_object_load's URDF (the file, its XML's nesting and size, its links and as
 * many joints; a robot of 200 links is far inside them) and of model_mesh_load (the file's size
 * and its triangles). */
#define MODEL_URDF_MAX_BYTES ((size_t)4 << 20)
#define MODEL_URDF_MAX_DEPTH 64
#define MODEL_URDF_MAX_ELEMENTS 100000
#define MODEL_URDF_MAX_LINKS 1000
#define MODEL_MESH_MAX_BYTES ((size_t)256 << 20)
#define MODEL_MESH_MAX_TRIANGLES 4000000

/* Load a mesh file through assimp's C API: STL (ascii and binary), OBJ, PLY (ascii and binary),
 * DAE, glTF and whatever else assimp 5.2 reads (chosen by extension, then by content). Every mesh
 * the node tree references is merged in, with its node transforms applied (in double); polygons
 * are triangulated, points and lines dropped. Vertices are joined by position (assimp's
 * JoinIdenticalVertices after dropping normals and texture coordinates; STL's three vertices per
 * facet become one), then scaled per axis by scale[3] (NULL means 1,1,1; a negative component
 * mirrors, and the winding is flipped with it so the mesh stays outward), then model_mesh_check()ed
 * and `report` filled. Collada: <unit meter="..."> is honoured; <up_axis> is ignored (no Y-up
 * rotation: coordinates as written, as ROS's rviz and geometric_shapes do). Files store floats,
 * so coordinates carry float precision.
 * Hostile files: only a regular file of at most MODEL_MESH_MAX_BYTES is opened (a device, pipe
 * or socket is refused before any read), and assimp runs in a child process (fork) with a CPU
 * limit of 2 s + 1 s per MB, a wall-time and a memory limit: a file that makes assimp crash,
 * abort or loop is refused with MODEL_E_PARSE naming what happened, and the caller's process is
 * untouched. At most MODEL_MESH_MAX_TRIANGLES triangles. docs/security.md.
 * Errors (the message names the file): MODEL_E_ARG (NULL/empty path, NULL out, a zero scale),
 * MODEL_E_NONFINITE (non-finite scale or vertex), MODEL_E_NOFILE (missing, unreadable, a folder,
 * not a regular file), MODEL_E_PARSE (empty, too large, corrupt, truncated, unknown format, no
 * triangles, too many, the reader crashed or ran over its limits), MODEL_E_NOMEM, and every error
 * of model_mesh_check(). On error *out is zeroed. Allocates; forks once. */
model_status_t model_mesh_load(const char *path, const double scale[3], model_mesh_t *out,
                               model_mesh_report_t *report, model_error_t *err);

/* Write a mesh through assimp's exporter (aiExportScene on a one-mesh scene built here). format is
 * an assimp export id: "stl" (ascii), "stlb" (binary), "obj" (also writes NAME.mtl beside it),
 * "ply" (ascii), "plyb" (binary), "collada", "glb2", ... Coordinates are written as float.
 * MODEL_E_ARG (NULL, empty mesh, index out of range), MODEL_E_NONFINITE, MODEL_E_UNSUPPORTED (no
 * exporter of that id), MODEL_E_NOFILE (assimp could not write the file). Allocates temporarily. */
model_status_t model_mesh_save(const model_mesh_t *mesh, const char *path, const char *format,
                               model_error_t *err);

/* The box [lo_m, hi_m] (axis-aligned, in the mesh frame) as a closed outward mesh: 8 vertices, 12
 * triangles; vertices 0..3 are the bottom face (z = lo) counter-clockwise seen from above, 4..7
 * the top face above them. MODEL_E_NONFINITE for a non-finite bound, MODEL_E_ARG unless lo < hi
 * on every axis. Allocates. */
model_status_t model_mesh_box(const double lo_m[3], const double hi_m[3], model_mesh_t *out);

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

/* Convex hull of a mesh's vertices (its triangles are ignored) as a closed, outward mesh whose
 * vertices are a subset of the input's, in input order. Quickhull with conflict lists and exact
 * visibility (which faces a new point sees is decided with exact arithmetic, so the surface stays
 * convex however many points are coplanar): a point counts as outside a face only when it is more
 * than 1e-10 x (bounding-box diagonal) above it, so duplicate, interior and coplanar points are
 * discarded; every input point lies within about that tolerance of the inner side of every hull
 * face, which the result is checked for. Coplanar hull facets come out triangulated, and a point
 * in the middle of a flat facet or of an edge (e.g. a midpoint of a subdivided mesh) may remain a
 * vertex. Iterations are capped at the point count. MODEL_E_ARG (NULL), MODEL_E_NONFINITE,
 * MODEL_E_HULL (fewer than 4 points, all coincident, collinear or coplanar, or a numerical failure
 * - reported, never patched). On error *hull is zeroed. Allocates; about 1 ms for a 1 000-vertex
 * rock, 20 ms for 10 000 vertices, 110 ms for 64 000 (docs/model.md). */
model_status_t model_mesh_hull(const model_mesh_t *mesh, model_mesh_t *hull, model_error_t *err);

/* Planar convex polygons, counter-clockwise, as arrays of (u, v) points in metres. Used for support
 * polygons and resting patches. None of these allocates. */

/* Convex hull of `count` points (sorted in place), counter-clockwise, collinear points dropped
 * (monotone chain). hull needs room for count + 1 points. Returns the hull's vertex count. */
size_t model_polygon_hull(double (*points)[2], size_t count, double (*hull)[2]);

/* Area of a convex counter-clockwise polygon; 0 for fewer than 3 vertices. */
double model_polygon_area(const double (*poly)[2], size_t count);

/* Smallest width of a convex polygon (attained with one side flush); 0 for fewer than 3. */
double model_polygon_width(const double (*poly)[2], size_t count);

/* Signed distance from p to the boundary of a convex counter-clockwise polygon: positive inside
 * (the distance to the nearest side), negative outside (minus the distance to the polygon);
 * -HUGE_VAL for fewer than 3 vertices. */
double model_polygon_margin(const double (*poly)[2], size_t count, const double p[2]);

/* Unit in-plane axes u, v of the plane with unit normal n, u x v = n: u from the coordinate axis
 * least aligned with n, made orthogonal to it. For projecting points onto a plane (u, v). */
void model_plane_basis(const double n[3], double u[3], double v[3]);

/* The rotation matrix of a unit quaternion (w, x, y, z): rot * v rotates v. The quaternion is
 * not normalised here. */
void model_quat_to_rot(const double q_wxyz[4], double rot[3][3]);

/* The unit quaternion (w, x, y, z), w >= 0, of a rotation matrix (Shepperd's method, then
 * normalised). The inverse of model_quat_to_rot up to the sign of q. C11 does not convert
 * double (*)[3] to const double (*)[3] implicitly: cast a non-const matrix. */
void model_rot_to_quat(const double rot[3][3], double q_wxyz[4]);

/* |q| within this of 1 is accepted as a unit quaternion (model_quat_unit). */
#define MODEL_QUAT_UNIT_TOL 1e-6

/* Validate q (finite, |q| within MODEL_QUAT_UNIT_TOL of 1) and write it normalised to unit.
 * MODEL_E_ARG (NULL), MODEL_E_NONFINITE, MODEL_E_POSE (not unit). */
model_status_t model_quat_unit(const double q_wxyz[4], double unit[4]);

/* Rotating, composing and comparing quaternions: comlearn/math3d.h (cl_quat_*). */

/* An object as the estimator sees it: the collision geometry of one URDF link. */
typedef struct {
  char robot_name[128];
  char link_name[128];
  char mesh_path[1024]; /* resolved path of the first mesh file, "" for primitives */
  model_mesh_t mesh;    /* all collision geometry of the link, in the link frame */
  model_aabb_t aabb;    /* bounding box of mesh, link frame */
} model_object_t;

/* Load a link's geometry from a URDF: all its <collision> elements (or all <visual> elements
 * when it has no <collision>), each placed in the link frame by its <origin> (xyz, rpy as URDF
 * defines it: R = Rz(yaw) Ry(pitch) Rx(roll)):
 *   <mesh>      loaded with model_mesh_load(), `scale` honoured (applied before the origin)
 *   <box>       8 vertices, 12 triangles, exact
 *   <sphere>    tessellated: UV sphere, 16 bands x 32 segments, vertices on the sphere (inscribed,
 *               1.6 % less volume than the sphere)
 *   <cylinder>  tessellated: 64-sided prism along z, vertices on the circles (inscribed)
 * Mesh file names:
 *   absolute "/..." or "file:///..."  used as is
 *   relative "a/b.stl", "../b.stl"    relative to the folder holding the URDF
 *   "package://NAME/REST"             ROOT/REST, ROOT the nearest of the URDF's folder and its
 *               parents (64 levels) holding a package.xml whose <name> is NAME, else the first
 *               package of that name in ROS_PACKAGE_PATH, crawled as rospack does (docs/model.md).
 *               MODEL_E_PARSE: an empty or non-ROS NAME, no REST, a ".." climbing above ROOT;
 *               MODEL_E_NOFILE: an unknown package. Reads package.xml files (64 KiB at most).
 *   any other "scheme://" (model:// too)  MODEL_E_UNSUPPORTED
 * mesh_path gets the canonical path (realpath) of the first mesh. All elements are concatenated
 * into one mesh and model_mesh_check()ed as a whole: elements must not share an edge (a
 * non-manifold edge is MODEL_E_OPEN); overlapping elements are accepted but their common volume
 * counts twice in mass properties. link_name NULL means the root link. Names longer than 127
 * bytes are truncated.
 * Reads no inertial data: this code cannot even name urdfdom's inertial member (a compile-time
 * guard) and a CTest checks the archive's symbols. urdfdom still parses the whole file, inertial
 * included, into a model that is freed before returning.
 * urdfdom: every exception is caught; its console output is captured by an output handler that
 * prints nothing (installed once per process with console_bridge::useOutputHandler, log level
 * ERROR); and because urdfdom drops an element it cannot parse (e.g. a <collision> with "nan" in
 * it) and carries on, any error it logs rejects the file as MODEL_E_PARSE with urdfdom's text.
 * Errors (messages name the URDF, the link and the mesh): MODEL_E_ARG, MODEL_E_NOFILE (URDF or
 * mesh missing), MODEL_E_PARSE (malformed XML, not a URDF, an element urdfdom rejected, a bad
 * package URI), MODEL_E_NOLINK (lists the links), MODEL_E_NOGEOM, MODEL_E_UNSUPPORTED,
 * MODEL_E_NONFINITE, MODEL_E_DEGENERATE (a zero box, sphere or cylinder) and the mesh errors.
 * On error *out is zeroed. Allocates. */
model_status_t model_object_load(const char *urdf_path, const char *link_name, model_object_t *out,
                                 model_error_t *err);

/* model_object_load for a file named by someone else (comlearn-sim's SIM_CONTROL LOAD): the URDF
 * and every mesh it names must resolve (realpath) inside one of the dir_count folders dirs
 * (canonical paths, as realpath gives them), each checked before it is opened; otherwise
 * MODEL_E_NOFILE, naming the file and "outside the folders". For package:// names, only the
 * package.xml files inside dirs are read (a package whose root is outside is unknown) and only
 * folders inside dirs or on the way down to them are listed. dir_count 0: no restriction. */
model_status_t model_object_load_within(const char *urdf_path, const char *link_name,
                                        const char *const *dirs, size_t dir_count,
                                        model_object_t *out, model_error_t *err);

/* Is path (canonical) inside one of the dir_count folders dirs (canonical)? 1 when dir_count is
 * 0. A folder holds a path when it is a prefix ending at a '/' of the path. */
int model_path_within(const char *path, const char *const *dirs, size_t dir_count);

/* Release an object's mesh and zero it. NULL is fine. */
void model_object_free(model_object_t *obj);

#ifdef __cplusplus
}
#endif

#endif /* COMLEARN_MODEL_H */
