/*
 * model_internal.h - private to lib/model: error helpers, mesh allocation, and the C API of
 * urdf.cpp (the only file that touches urdfdom).
 *
 * urdf.cpp is compiled twice (see lib/model/CMakeLists.txt). Without MODEL_URDF_INERTIAL it defines
 * model_urdf_link_read() / model_urdf_link_free() (geometry only) for comlearn_model; with it, it
 * defines only model_urdf_inertial_read() for comlearn_model_sim. Both declarations are visible
 * here; each archive defines exactly one side.
 */
#ifndef COMLEARN_MODEL_INTERNAL_H
#define COMLEARN_MODEL_INTERNAL_H

#include "comlearn/model.h"
#include "comlearn/model_chain.h"

#ifdef __cplusplus
extern "C" {
#endif

#if defined(__GNUC__)
#define MODEL_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define MODEL_PRINTF(a, b)
#endif

/* Write a message into err (NULL is fine). Returns status, so `return model_fail(...)` reads. */
model_status_t model_fail(model_error_t *err, model_status_t status, const char *fmt, ...)
    MODEL_PRINTF(3, 4);

/* Prepend a context ("mesh /a/b.stl: ") to err's message. NULL err is fine. */
void model_error_prefix(model_error_t *err, const char *fmt, ...) MODEL_PRINTF(2, 3);

/* model_polygon_hull, also for nearly collinear points: exact duplicates are dropped first, then
 * every point where the chain turns by less than asin(sin_tol) (a point so dropped lies within
 * sin_tol x the side's length of it). sin_tol 0: exactly collinear points only. No allocation. */
size_t model_polygon_hull_tol(double (*points)[2], size_t count, double (*hull)[2], double sin_tol);

/* Allocate a mesh's arrays (uninitialised contents). out must not own arrays. */
/* The checks model_mesh_hull runs on its result, on a surface given as triangles over the
 * points' vertices (counter-clockwise seen from outside): MODEL_E_HULL, "convex hull: numerical
 * failure (why)", when it is not the convex hull of the points. For tests; O(nt^2). */
model_status_t model_hull_verify_faces(const model_mesh_t *points, const uint32_t (*tris)[3],
                                       size_t nt, model_error_t *err);

model_status_t model_mesh_alloc(model_mesh_t *out, size_t vertex_count, size_t triangle_count);

/* ---- file_guard.c: before a third-party parser sees a file ---------------------------------- */

/* Open path read-only when it is a regular file of 1 .. max_bytes bytes: a folder, device, pipe
 * or socket is refused (MODEL_E_NOFILE), as is a file over the limit or empty (MODEL_E_PARSE);
 * messages name `what` ("mesh", "URDF") and the path. A pipe is opened without blocking. *fd_out
 * (-1 on error) is the caller's to close. */
model_status_t model_file_open_checked(const char *path, const char *what, size_t max_bytes,
                                       int *fd_out, size_t *size_out, model_error_t *err);

/* The shape of a URDF's XML, before tinyxml and urdfdom see it (both recurse: 60 000 nested
 * elements overflow tinyxml's stack, a chain of 200 000 joints urdfdom's): at most
 * MODEL_URDF_MAX_DEPTH levels, MODEL_URDF_MAX_ELEMENTS elements, MODEL_URDF_MAX_LINKS <link> and
 * as many <joint> elements, no DOCTYPE internal subset. Comments, CDATA and processing
 * instructions are skipped; attribute values may hold '>'. Malformed XML is left to tinyxml.
 * MODEL_E_PARSE naming the limit. */
model_status_t model_xml_check(const char *text, size_t n, const char *path, model_error_t *err);

/* A mesh parser: path and scale to an unchecked mesh, or an error. */
typedef model_status_t (*model_mesh_parse_fn)(const char *path, const double scale[3],
                                              model_mesh_t *out, model_error_t *err);

/* Run parse in a child process (fork) limited to cpu_s seconds of CPU (and twice that plus 5 s of
 * wall time, 4 GiB + 16 x file_bytes of memory without a sanitizer, no core file), and take its
 * mesh back through a pipe. A child that crashes, aborts or runs over its limits gives
 * MODEL_E_PARSE naming the signal; the caller's process is untouched. *out is the caller's on
 * MODEL_OK. */
model_status_t model_mesh_parse_isolated(const char *path, const double scale[3], double cpu_s,
                                         size_t file_bytes, model_mesh_parse_fn parse,
                                         model_mesh_t *out, model_error_t *err);

/* ---- package.c: package://NAME/REST mesh URIs ------------------------------------------------ */

enum {
  MODEL_PACKAGE_NAME_MAX = 255,            /* bytes of NAME */
  MODEL_PACKAGE_XML_MAX_BYTES = 64 * 1024, /* a package.xml larger than this is not read */
  MODEL_PACKAGE_PARENT_LEVELS = 64,        /* folders walked up from the URDF's */
  MODEL_PACKAGE_CRAWL_DEPTH = 8,           /* levels searched below a ROS_PACKAGE_PATH entry */
  MODEL_PACKAGE_CRAWL_FOLDERS = 10000      /* folders listed per URI, all entries together */
};

/* The text of the first <name> element of a package.xml (comments and processing instructions
 * skipped, surrounding white space trimmed) into name: 0, or -1 when there is none, it is empty,
 * or it does not fit name_size. No allocation. */
int model_package_xml_name(const char *text, size_t n, char *name, size_t name_size);

/* Resolve uri, which starts with "package://", for a URDF in the canonical folder urdf_dir, into
 * the canonical path of an existing regular file (out). NAME is letters, digits, '_' and '-'; REST
 * is not empty and no ".." in it climbs above the package root (else MODEL_E_PARSE naming why).
 * The package root is the nearest of urdf_dir and its parents that holds a package.xml whose
 * <name> is NAME, else the first found in ROS_PACKAGE_PATH (colon-separated; each entry crawled
 * as rospack does, see package.c); none: MODEL_E_NOFILE "unknown package". With dir_count > 0,
 * only package.xml files inside dirs (canonical) are read, and only folders inside them or on the
 * way down to them are listed. The caller still checks out against dirs. Messages name the URI;
 * the caller prefixes the URDF and link. Allocates (scandir, realpath). */
model_status_t model_package_resolve(const char *uri, const char *urdf_dir, const char *const *dirs,
                                     size_t dir_count, char *out, size_t out_size,
                                     model_error_t *err);

/* ---- urdf.cpp, geometry side (comlearn_model) ------------------------------------------------ */

typedef enum {
  MODEL_URDF_MESH = 0,
  MODEL_URDF_BOX = 1,
  MODEL_URDF_SPHERE = 2,
  MODEL_URDF_CYLINDER = 3
} model_urdf_shape_t;

enum { MODEL_URDF_NAME_MAX = 128, MODEL_URDF_PATH_MAX = 1024 };

/* One <collision> (or <visual>) element. The geometry frame is placed in the link frame by
 * x_link = rot * x_geom + xyz_m. */
typedef struct {
  model_urdf_shape_t shape;
  double xyz_m[3];
  double rot[3][3];                   /* from the origin's rpy (urdfdom's quaternion) */
  double scale[3];                    /* mesh only */
  double size_m[3];                   /* box only: full edge lengths */
  double radius_m;                    /* sphere, cylinder */
  double length_m;                    /* cylinder, along the geometry's z */
  char filename[MODEL_URDF_PATH_MAX]; /* mesh only: as written in the URDF */
} model_urdf_geom_t;

typedef struct {
  char robot_name[MODEL_URDF_NAME_MAX];
  char link_name[MODEL_URDF_NAME_MAX];
  int from_visual; /* 1 when the link has no <collision> and <visual> was used */
  size_t geom_count;
  model_urdf_geom_t *geoms; /* malloc, released by model_urdf_link_free() */
} model_urdf_link_t;

/* Parse a URDF and return one link's geometry (link_name NULL: the root link). Never reads
 * <inertial>. MODEL_E_NOFILE, MODEL_E_PARSE, MODEL_E_NOLINK, MODEL_E_NOMEM, MODEL_E_ARG. */
model_status_t model_urdf_link_read(const char *urdf_path, const char *link_name,
                                    model_urdf_link_t *out, model_error_t *err);
void model_urdf_link_free(model_urdf_link_t *link);

/* The joints from base_link to tip_link as urdfdom holds them (names, types, origins, axes,
 * limits), copied without numeric checks (model_chain_load does those). Structural errors:
 * MODEL_E_NOLINK, MODEL_E_CHAIN (tip not below base, too many joints, floating/planar joint, a
 * name too long), plus those of parsing. Geometry build only. */
model_status_t model_urdf_chain_read(const char *urdf_path, const char *base_link,
                                     const char *tip_link, model_chain_t *out, model_error_t *err);

/* ---- urdf.cpp, inertial side (comlearn_model_sim only) --------------------------------------- */

/* A link's <inertial> as written: inertia about the CoM in the inertial frame, whose axes are
 * rot (link <- inertial) and whose origin is com_m in the link frame. */
typedef struct {
  char link_name[MODEL_URDF_NAME_MAX];
  double mass_kg;
  double com_m[3];
  double rot[3][3];
  double inertia_kg_m2[3][3];
} model_urdf_inertial_t;

/* MODEL_E_NOFILE, MODEL_E_PARSE, MODEL_E_NOLINK, MODEL_E_INERTIAL (no <inertial>),
 * MODEL_E_NOMEM. */
model_status_t model_urdf_inertial_read(const char *urdf_path, const char *link_name,
                                        model_urdf_inertial_t *out, model_error_t *err);

#ifdef __cplusplus
}
#endif

#endif /* COMLEARN_MODEL_INTERNAL_H */
