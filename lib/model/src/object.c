/* object.c - one URDF link's collision geometry as one closed mesh in the link frame. */
#define _XOPEN_SOURCE 700 /* realpath */

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "comlearn/math3d.h"
#include "model_internal.h"

enum { PATH_BUF = 4096, SPHERE_SEGMENTS = 32, SPHERE_RINGS = 16, CYLINDER_SEGMENTS = 64 };

/* Copy the canonical form of an existing path (no "..", no symlinks) into out. */
static int canonical(const char *path, char *out, size_t out_size) {
  char *real = realpath(path, NULL);
  if (real == NULL) {
    return 0;
  }
  size_t len = strlen(real);
  int fits = len < out_size;
  if (fits) {
    memcpy(out, real, len + 1);
  }
  free(real);
  return fits;
}

/* Resolve a URDF mesh reference (see model_object_load in model.h for the rule). */
static model_status_t resolve_mesh_path(const char *urdf_path, const char *link, const char *uri,
                                        const char *const *dirs, size_t dir_count, char *out,
                                        size_t out_size, model_error_t *err) {
  char dir[PATH_BUF];
  /* The URDF's folder, absolute so that its parents can be walked. */
  char *real = realpath(urdf_path, NULL);
  if (real == NULL) {
    return model_fail(err, MODEL_E_NOFILE, "cannot resolve the folder of URDF %s", urdf_path);
  }
  char *slash = strrchr(real, '/');
  if (slash == real) {
    slash[1] = '\0';
  } else if (slash != NULL) {
    *slash = '\0';
  }
  int n = snprintf(dir, sizeof dir, "%s", real);
  free(real);
  if (n < 0 || (size_t)n >= sizeof dir) {
    return model_fail(err, MODEL_E_ARG, "URDF path %s is too long", urdf_path);
  }

  if (strncmp(uri, "package://", 10) == 0) {
    model_status_t st = model_package_resolve(uri, dir, dirs, dir_count, out, out_size, err);
    if (st != MODEL_OK) {
      model_error_prefix(err, "URDF %s: link '%s': ", urdf_path, link);
    }
    return st;
  }

  const char *path = uri;
  if (strncmp(uri, "file://", 7) == 0) {
    path = uri + 7;
  } else if (strstr(uri, "://") != NULL) {
    return model_fail(err, MODEL_E_UNSUPPORTED,
                      "URDF %s: link '%s': mesh URI scheme of '%s' is not supported (package://, "
                      "file:// or a path)",
                      urdf_path, link, uri);
  }
  char buf[PATH_BUF];
  if (path[0] == '/') {
    n = snprintf(buf, sizeof buf, "%s", path);
  } else {
    n = snprintf(buf, sizeof buf, "%s/%s", dir, path);
  }
  if (n < 0 || (size_t)n >= sizeof buf) {
    return model_fail(err, MODEL_E_ARG, "URDF %s: link '%s': mesh path too long", urdf_path, link);
  }
  /* stat, never open: opening a named pipe would wait for a writer */
  struct stat st;
  if (stat(buf, &st) != 0 || !canonical(buf, out, out_size)) {
    return model_fail(err, MODEL_E_NOFILE, "URDF %s: link '%s': mesh '%s' not found (tried %s)",
                      urdf_path, link, uri, buf);
  }
  if (!S_ISREG(st.st_mode)) {
    return model_fail(err, MODEL_E_NOFILE,
                      "URDF %s: link '%s': mesh '%s' (%s) is not a regular file (a folder, device, "
                      "pipe or socket): refused",
                      urdf_path, link, uri, buf);
  }
  return MODEL_OK;
}

/* ---- primitives ------------------------------------------------------------------------------ */

model_status_t model_mesh_box(const double lo_m[3], const double hi_m[3], model_mesh_t *out) {
  static const uint32_t tris[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7},
                                       {0, 1, 5}, {0, 5, 4}, {1, 2, 6}, {1, 6, 5},
                                       {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  if (lo_m == NULL || hi_m == NULL || out == NULL) {
    return MODEL_E_ARG;
  }
  for (int k = 0; k < 3; ++k) {
    if (!isfinite(lo_m[k]) || !isfinite(hi_m[k])) {
      return MODEL_E_NONFINITE;
    }
    if (!(lo_m[k] < hi_m[k])) {
      return MODEL_E_ARG;
    }
  }
  model_status_t st = model_mesh_alloc(out, 8, 12);
  if (st != MODEL_OK) {
    return st;
  }
  for (uint32_t i = 0; i < 8; ++i) {
    /* 0..3 bottom (z-) counter-clockwise seen from above, 4..7 top above them. */
    out->vertices_m[i][0] = (i % 4 == 1 || i % 4 == 2) ? hi_m[0] : lo_m[0];
    out->vertices_m[i][1] = (i % 4 >= 2) ? hi_m[1] : lo_m[1];
    out->vertices_m[i][2] = i >= 4 ? hi_m[2] : lo_m[2];
  }
  memcpy(out->triangles, tris, sizeof tris);
  return MODEL_OK;
}

static model_status_t make_box(const double size[3], model_mesh_t *out) {
  const double lo[3] = {-0.5 * size[0], -0.5 * size[1], -0.5 * size[2]};
  const double hi[3] = {0.5 * size[0], 0.5 * size[1], 0.5 * size[2]};
  return model_mesh_box(lo, hi, out);
}

/* UV sphere: poles on z, SPHERE_RINGS bands, vertices on the sphere (inscribed polyhedron). */
static model_status_t make_sphere(double r, model_mesh_t *out) {
  const uint32_t S = SPHERE_SEGMENTS, R = SPHERE_RINGS;
  model_status_t st = model_mesh_alloc(out, 2 + (size_t)(R - 1) * S, 2 * (size_t)S * (R - 1));
  if (st != MODEL_OK) {
    return st;
  }
  out->vertices_m[0][0] = 0.0;
  out->vertices_m[0][1] = 0.0;
  out->vertices_m[0][2] = r;
  out->vertices_m[1][0] = 0.0;
  out->vertices_m[1][1] = 0.0;
  out->vertices_m[1][2] = -r;
  for (uint32_t i = 1; i < R; ++i) {
    double theta = CL_PI * i / R;
    for (uint32_t j = 0; j < S; ++j) {
      double phi = 2.0 * CL_PI * j / S;
      double *v = out->vertices_m[2 + (i - 1) * S + j];
      v[0] = r * sin(theta) * cos(phi);
      v[1] = r * sin(theta) * sin(phi);
      v[2] = r * cos(theta);
    }
  }
  size_t t = 0;
#define RING(i, j) (2 + ((i)-1) * S + ((j) % S))
  for (uint32_t j = 0; j < S; ++j) {
    uint32_t *a = out->triangles[t++];
    a[0] = 0;
    a[1] = RING(1, j);
    a[2] = RING(1, j + 1);
    uint32_t *b = out->triangles[t++];
    b[0] = 1;
    b[1] = RING(R - 1, j + 1);
    b[2] = RING(R - 1, j);
  }
  for (uint32_t i = 1; i + 1 < R; ++i) {
    for (uint32_t j = 0; j < S; ++j) {
      uint32_t *a = out->triangles[t++];
      a[0] = RING(i, j);
      a[1] = RING(i + 1, j);
      a[2] = RING(i + 1, j + 1);
      uint32_t *b = out->triangles[t++];
      b[0] = RING(i, j);
      b[1] = RING(i + 1, j + 1);
      b[2] = RING(i, j + 1);
    }
  }
#undef RING
  return MODEL_OK;
}

/* Prism along z with CYLINDER_SEGMENTS sides, vertices on the circles, caps fanned from centres. */
static model_status_t make_cylinder(double r, double length, model_mesh_t *out) {
  const uint32_t S = CYLINDER_SEGMENTS;
  model_status_t st = model_mesh_alloc(out, 2 + 2 * (size_t)S, 4 * (size_t)S);
  if (st != MODEL_OK) {
    return st;
  }
  double h = 0.5 * length;
  out->vertices_m[0][0] = out->vertices_m[0][1] = 0.0;
  out->vertices_m[0][2] = h;
  out->vertices_m[1][0] = out->vertices_m[1][1] = 0.0;
  out->vertices_m[1][2] = -h;
  for (uint32_t j = 0; j < S; ++j) {
    double phi = 2.0 * CL_PI * j / S;
    for (uint32_t k = 0; k < 2; ++k) {
      double *v = out->vertices_m[2 + 2 * j + k];
      v[0] = r * cos(phi);
      v[1] = r * sin(phi);
      v[2] = k == 0 ? h : -h;
    }
  }
  size_t t = 0;
  for (uint32_t j = 0; j < S; ++j) {
    uint32_t top0 = 2 + 2 * j, bot0 = top0 + 1;
    uint32_t top1 = 2 + 2 * ((j + 1) % S), bot1 = top1 + 1;
    uint32_t *a = out->triangles[t++];
    a[0] = 0, a[1] = top0, a[2] = top1;
    uint32_t *b = out->triangles[t++];
    b[0] = 1, b[1] = bot1, b[2] = bot0;
    uint32_t *c = out->triangles[t++];
    c[0] = top0, c[1] = bot0, c[2] = bot1;
    uint32_t *d = out->triangles[t++];
    d[0] = top0, d[1] = bot1, d[2] = top1;
  }
  return MODEL_OK;
}

static int all_finite(const double *v, size_t n) {
  for (size_t i = 0; i < n; ++i) {
    if (!isfinite(v[i])) {
      return 0;
    }
  }
  return 1;
}

int model_path_within(const char *path, const char *const *dirs, size_t dir_count) {
  if (dir_count == 0) {
    return 1;
  }
  for (size_t i = 0; path != NULL && i < dir_count; ++i) {
    const size_t n = strlen(dirs[i]);
    if (n > 0 && strncmp(path, dirs[i], n) == 0 && (path[n] == '/' || dirs[i][n - 1] == '/')) {
      return 1;
    }
  }
  return 0;
}

/* The folders a load may read from (model_object_load_within). */
typedef struct {
  const char *const *dirs;
  size_t count;
} load_dirs_t;

/* One geometry element as a checked mesh in the link frame. */
static model_status_t load_geom(const char *urdf_path, const model_urdf_link_t *link,
                                const model_urdf_geom_t *g, size_t index, const load_dirs_t *dirs,
                                model_mesh_t *piece, char *first_mesh_path, model_error_t *err) {
  const char *ln = link->link_name;
  if (!all_finite(g->xyz_m, 3) || !all_finite(&g->rot[0][0], 9)) {
    return model_fail(err, MODEL_E_NONFINITE,
                      "URDF %s: link '%s': origin of geometry %zu is not finite", urdf_path, ln,
                      index);
  }
  model_status_t st = MODEL_OK;
  switch (g->shape) {
    case MODEL_URDF_MESH: {
      char path[PATH_BUF];
      st = resolve_mesh_path(urdf_path, ln, g->filename, dirs->dirs, dirs->count, path, sizeof path,
                             err);
      if (st != MODEL_OK) {
        return st;
      }
      if (!model_path_within(path, dirs->dirs, dirs->count)) {
        return model_fail(err, MODEL_E_NOFILE,
                          "URDF %s: link '%s': mesh %s is outside the folders this program may "
                          "read",
                          urdf_path, ln, path);
      }
      if (!all_finite(g->scale, 3)) {
        return model_fail(err, MODEL_E_NONFINITE, "URDF %s: link '%s': scale of %s is not finite",
                          urdf_path, ln, g->filename);
      }
      st = model_mesh_load(path, g->scale, piece, NULL, err);
      if (st != MODEL_OK) {
        model_error_prefix(err, "URDF %s: link '%s': ", urdf_path, ln);
        return st;
      }
      if (first_mesh_path[0] == '\0') {
        size_t len = strlen(path);
        if (len >= MODEL_URDF_PATH_MAX) {
          return model_fail(err, MODEL_E_ARG, "URDF %s: link '%s': mesh path too long", urdf_path,
                            ln);
        }
        memcpy(first_mesh_path, path, len + 1);
      }
      break;
    }
    case MODEL_URDF_BOX:
      if (!all_finite(g->size_m, 3)) {
        return model_fail(err, MODEL_E_NONFINITE, "URDF %s: link '%s': box size is not finite",
                          urdf_path, ln);
      }
      if (!(g->size_m[0] > 0.0 && g->size_m[1] > 0.0 && g->size_m[2] > 0.0)) {
        return model_fail(err, MODEL_E_DEGENERATE,
                          "URDF %s: link '%s': box size %g x %g x %g is not positive", urdf_path,
                          ln, g->size_m[0], g->size_m[1], g->size_m[2]);
      }
      st = make_box(g->size_m, piece);
      break;
    case MODEL_URDF_SPHERE:
      if (!isfinite(g->radius_m) || !(g->radius_m > 0.0)) {
        return model_fail(err, isfinite(g->radius_m) ? MODEL_E_DEGENERATE : MODEL_E_NONFINITE,
                          "URDF %s: link '%s': sphere radius %g is not finite and positive",
                          urdf_path, ln, g->radius_m);
      }
      st = make_sphere(g->radius_m, piece);
      break;
    case MODEL_URDF_CYLINDER:
      if (!isfinite(g->radius_m) || !isfinite(g->length_m) || !(g->radius_m > 0.0) ||
          !(g->length_m > 0.0)) {
        return model_fail(
            err,
            isfinite(g->radius_m) && isfinite(g->length_m) ? MODEL_E_DEGENERATE : MODEL_E_NONFINITE,
            "URDF %s: link '%s': cylinder radius %g / length %g not finite and "
            "positive",
            urdf_path, ln, g->radius_m, g->length_m);
      }
      st = make_cylinder(g->radius_m, g->length_m, piece);
      break;
    default:
      return model_fail(err, MODEL_E_UNSUPPORTED, "URDF %s: link '%s': geometry type %d", urdf_path,
                        ln, (int)g->shape);
  }
  if (st != MODEL_OK) {
    return model_fail(err, st, "URDF %s: link '%s': out of memory", urdf_path, ln);
  }
  /* Geometry frame -> link frame. */
  for (size_t i = 0; i < piece->vertex_count; ++i) {
    double p[3];
    memcpy(p, piece->vertices_m[i], sizeof p);
    for (int r = 0; r < 3; ++r) {
      piece->vertices_m[i][r] =
          g->rot[r][0] * p[0] + g->rot[r][1] * p[1] + g->rot[r][2] * p[2] + g->xyz_m[r];
    }
  }
  return MODEL_OK;
}

model_status_t model_object_load(const char *urdf_path, const char *link_name, model_object_t *out,
                                 model_error_t *err) {
  return model_object_load_within(urdf_path, link_name, NULL, 0, out, err);
}

model_status_t model_object_load_within(const char *urdf_path, const char *link_name,
                                        const char *const *dir_list, size_t dir_count,
                                        model_object_t *out, model_error_t *err) {
  if (out == NULL) {
    return model_fail(err, MODEL_E_ARG, "model_object_load: NULL output");
  }
  memset(out, 0, sizeof *out);
  if (urdf_path == NULL || urdf_path[0] == '\0') {
    return model_fail(err, MODEL_E_ARG, "URDF path is NULL or empty");
  }
  if (dir_count > 0 && dir_list == NULL) {
    return model_fail(err, MODEL_E_ARG, "model_object_load_within: NULL folder list");
  }
  const load_dirs_t dirs = {dir_list, dir_count};
  if (dir_count > 0) {
    char *real = realpath(urdf_path, NULL);
    if (real == NULL) {
      return model_fail(err, MODEL_E_NOFILE, "cannot open URDF %s: %s", urdf_path, strerror(errno));
    }
    const int inside = model_path_within(real, dir_list, dir_count);
    free(real);
    if (!inside) {
      return model_fail(err, MODEL_E_NOFILE, "URDF %s is outside the folders this program may read",
                        urdf_path);
    }
  }
  model_urdf_link_t link;
  model_status_t st = model_urdf_link_read(urdf_path, link_name, &link, err);
  if (st != MODEL_OK) {
    return st;
  }
  if (link.geom_count == 0) {
    st = model_fail(err, MODEL_E_NOGEOM, "URDF %s: link '%s' has no collision or visual geometry",
                    urdf_path, link.link_name);
    model_urdf_link_free(&link);
    return st;
  }
  model_mesh_t *pieces = calloc(link.geom_count, sizeof *pieces);
  if (pieces == NULL) {
    model_urdf_link_free(&link);
    return model_fail(err, MODEL_E_NOMEM, "URDF %s: out of memory", urdf_path);
  }
  size_t nv = 0, nt = 0;
  for (size_t i = 0; i < link.geom_count && st == MODEL_OK; ++i) {
    st = load_geom(urdf_path, &link, &link.geoms[i], i, &dirs, &pieces[i], out->mesh_path, err);
    nv += pieces[i].vertex_count;
    nt += pieces[i].triangle_count;
  }
  if (st == MODEL_OK && nv > UINT32_MAX) {
    st = model_fail(err, MODEL_E_ARG, "URDF %s: link '%s': too many vertices", urdf_path,
                    link.link_name);
  }
  if (st == MODEL_OK) {
    st = model_mesh_alloc(&out->mesh, nv, nt);
    if (st != MODEL_OK) {
      (void)model_fail(err, st, "URDF %s: out of memory", urdf_path);
    }
  }
  if (st == MODEL_OK) {
    size_t v0 = 0, t0 = 0;
    for (size_t i = 0; i < link.geom_count; ++i) {
      const model_mesh_t *p = &pieces[i];
      memcpy(out->mesh.vertices_m[v0], p->vertices_m, p->vertex_count * sizeof p->vertices_m[0]);
      for (size_t t = 0; t < p->triangle_count; ++t) {
        for (int k = 0; k < 3; ++k) {
          out->mesh.triangles[t0 + t][k] = p->triangles[t][k] + (uint32_t)v0;
        }
      }
      v0 += p->vertex_count;
      t0 += p->triangle_count;
    }
    st = model_mesh_check(&out->mesh, NULL, err);
    if (st != MODEL_OK) {
      model_error_prefix(err, "URDF %s: link '%s': the merged geometry: ", urdf_path,
                         link.link_name);
    }
  }
  if (st == MODEL_OK) {
    st = model_mesh_aabb(&out->mesh, &out->aabb);
  }
  if (st == MODEL_OK) {
    memcpy(out->robot_name, link.robot_name, sizeof out->robot_name);
    memcpy(out->link_name, link.link_name, sizeof out->link_name);
  }
  for (size_t i = 0; i < link.geom_count; ++i) {
    model_mesh_free(&pieces[i]);
  }
  free(pieces);
  model_urdf_link_free(&link);
  if (st != MODEL_OK) {
    model_object_free(out);
  }
  return st;
}

void model_object_free(model_object_t *obj) {
  if (obj != NULL) {
    model_mesh_free(&obj->mesh);
    memset(obj, 0, sizeof *obj);
  }
}
