/* mesh_io.c - mesh files through assimp's C API: load (all meshes, node transforms applied) and
 * save (a one-mesh scene built here and handed to aiExportScene). */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <assimp/cexport.h>
#include <assimp/cimport.h>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include "model_internal.h"

enum { MAX_NODE_DEPTH = 256 };

/* Affine transform x' = m[:, 0:3] x + m[:, 3], in double. */
typedef struct {
  double m[3][4];
} xform_t;

static xform_t xform_from_ai(const struct aiMatrix4x4 *a) {
  xform_t x = {
      {{a->a1, a->a2, a->a3, a->a4}, {a->b1, a->b2, a->b3, a->b4}, {a->c1, a->c2, a->c3, a->c4}}};
  return x;
}

static xform_t xform_mul(const xform_t *a, const xform_t *b) {
  xform_t out;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) {
      double s = c == 3 ? a->m[r][3] : 0.0;
      for (int k = 0; k < 3; ++k) {
        s += a->m[r][k] * b->m[k][c];
      }
      out.m[r][c] = s;
    }
  }
  return out;
}

static double xform_det(const xform_t *x) {
  const double(*m)[4] = x->m;
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
         m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

typedef struct {
  const struct aiScene *scene;
  const char *path;
  double scale[3];
  model_mesh_t *out;   /* NULL in the counting pass */
  size_t vertex_count; /* running totals */
  size_t triangle_count;
  model_error_t *err;
} walk_t;

static model_status_t walk_node(walk_t *w, const struct aiNode *node, const xform_t *parent,
                                int depth) {
  if (depth > MAX_NODE_DEPTH) {
    return model_fail(w->err, MODEL_E_PARSE, "mesh %s: node tree deeper than %d", w->path,
                      MAX_NODE_DEPTH);
  }
  xform_t local = xform_from_ai(&node->mTransformation);
  xform_t global = xform_mul(parent, &local);
  int mirror = xform_det(&global) * w->scale[0] * w->scale[1] * w->scale[2] < 0.0;

  for (unsigned i = 0; i < node->mNumMeshes; ++i) {
    if (node->mMeshes[i] >= w->scene->mNumMeshes) {
      return model_fail(w->err, MODEL_E_PARSE, "mesh %s: node refers to missing mesh %u", w->path,
                        node->mMeshes[i]);
    }
    const struct aiMesh *m = w->scene->mMeshes[node->mMeshes[i]];
    size_t base = w->vertex_count;
    if (w->out != NULL) {
      for (unsigned v = 0; v < m->mNumVertices; ++v) {
        const double p[3] = {m->mVertices[v].x, m->mVertices[v].y, m->mVertices[v].z};
        double *q = w->out->vertices_m[base + v];
        for (int r = 0; r < 3; ++r) {
          double s = global.m[r][3];
          for (int k = 0; k < 3; ++k) {
            s += global.m[r][k] * p[k];
          }
          q[r] = s * w->scale[r];
        }
      }
    }
    w->vertex_count += m->mNumVertices;
    for (unsigned f = 0; f < m->mNumFaces; ++f) {
      const struct aiFace *face = &m->mFaces[f];
      if (face->mNumIndices != 3) {
        continue; /* points and lines; polygons were triangulated */
      }
      for (int k = 0; k < 3; ++k) {
        if (face->mIndices[k] >= m->mNumVertices) {
          return model_fail(w->err, MODEL_E_PARSE, "mesh %s: face %u uses a missing vertex",
                            w->path, f);
        }
      }
      if (w->out != NULL) {
        uint32_t *t = w->out->triangles[w->triangle_count];
        t[0] = (uint32_t)(base + face->mIndices[0]);
        t[1] = (uint32_t)(base + face->mIndices[mirror ? 2 : 1]);
        t[2] = (uint32_t)(base + face->mIndices[mirror ? 1 : 2]);
      }
      ++w->triangle_count;
    }
    if (w->vertex_count > UINT32_MAX) {
      return model_fail(w->err, MODEL_E_PARSE, "mesh %s: more than 2^32 vertices", w->path);
    }
  }
  for (unsigned c = 0; c < node->mNumChildren; ++c) {
    model_status_t st = walk_node(w, node->mChildren[c], &global, depth + 1);
    if (st != MODEL_OK) {
      return st;
    }
  }
  return MODEL_OK;
}

/* Checks the caller's scale and copies it to w_scale (which stays 1, 1, 1 for NULL). */
static model_status_t load_scale(const char *path, const double scale[3], double w_scale[3],
                                 model_error_t *err) {
  if (scale == NULL) {
    return MODEL_OK;
  }
  for (int k = 0; k < 3; ++k) {
    if (!isfinite(scale[k])) {
      return model_fail(err, MODEL_E_NONFINITE, "mesh %s: scale (%g, %g, %g) is not finite", path,
                        scale[0], scale[1], scale[2]);
    }
    if (scale[k] == 0.0) {
      return model_fail(err, MODEL_E_ARG, "mesh %s: scale (%g, %g, %g) has a zero component", path,
                        scale[0], scale[1], scale[2]);
    }
    w_scale[k] = scale[k];
  }
  return MODEL_OK;
}

/* Imports the file with assimp; the caller releases *scene_out with aiReleaseImport. */
static model_status_t load_scene(const char *path, const struct aiScene **scene_out,
                                 model_error_t *err) {
  /* Keep positions only: without normals and texture coordinates JoinIdenticalVertices joins by
   * position, which STL (one vertex triple per facet) needs. Points and lines are dropped. The
   * Collada up axis is ignored (the file's coordinates are the link frame, as in ROS); its unit
   * is honoured (assimp scales the root node). */
  struct aiPropertyStore *props = aiCreatePropertyStore();
  if (props == NULL) {
    return model_fail(err, MODEL_E_NOMEM, "mesh %s: out of memory", path);
  }
  aiSetImportPropertyInteger(props, AI_CONFIG_PP_RVC_FLAGS,
                             aiComponent_NORMALS | aiComponent_TANGENTS_AND_BITANGENTS |
                                 aiComponent_COLORS | aiComponent_TEXCOORDS |
                                 aiComponent_BONEWEIGHTS | aiComponent_ANIMATIONS |
                                 aiComponent_TEXTURES | aiComponent_LIGHTS | aiComponent_CAMERAS);
  aiSetImportPropertyInteger(props, AI_CONFIG_PP_SBP_REMOVE,
                             aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  aiSetImportPropertyInteger(props, AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, 1);
  const unsigned flags = aiProcess_RemoveComponent | aiProcess_Triangulate |
                         aiProcess_JoinIdenticalVertices | aiProcess_SortByPType |
                         aiProcess_ValidateDataStructure;
  const struct aiScene *scene = aiImportFileExWithProperties(path, flags, NULL, props);
  aiReleasePropertyStore(props);
  if (scene == NULL) {
    const char *why = aiGetErrorString();
    return model_fail(err, MODEL_E_PARSE, "mesh %s cannot be read: %s", path,
                      why != NULL && why[0] != '\0' ? why : "unknown format or corrupt file");
  }
  if ((scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) != 0 || scene->mRootNode == NULL) {
    aiReleaseImport(scene);
    return model_fail(err, MODEL_E_PARSE, "mesh %s: incomplete scene (no meshes)", path);
  }
  *scene_out = scene;
  return MODEL_OK;
}

/* Two walks over the node tree: count, allocate `out`, then fill it. */
static model_status_t load_walk(walk_t *w, model_mesh_t *out) {
  const char *path = w->path;
  xform_t identity = {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}}};
  model_status_t st = walk_node(w, w->scene->mRootNode, &identity, 0);
  if (st == MODEL_OK && w->triangle_count == 0) {
    st = model_fail(w->err, MODEL_E_PARSE, "mesh %s contains no triangles", path);
  }
  if (st == MODEL_OK && w->triangle_count > MODEL_MESH_MAX_TRIANGLES) {
    st = model_fail(w->err, MODEL_E_PARSE, "mesh %s has %zu triangles, over the limit of %d", path,
                    w->triangle_count, MODEL_MESH_MAX_TRIANGLES);
  }
  if (st == MODEL_OK) {
    st = model_mesh_alloc(out, w->vertex_count, w->triangle_count);
    if (st != MODEL_OK) {
      st = model_fail(w->err, st, "mesh %s: out of memory for %zu triangles", path,
                      w->triangle_count);
    }
  }
  if (st == MODEL_OK) {
    w->out = out;
    w->vertex_count = 0;
    w->triangle_count = 0;
    st = walk_node(w, w->scene->mRootNode, &identity, 0);
  }
  return st;
}

/* What the child process of model_mesh_parse_isolated runs: assimp and the node walk, scaled,
 * unchecked. */
static model_status_t parse_mesh(const char *path, const double scale[3], model_mesh_t *out,
                                 model_error_t *err) {
  walk_t w = {.path = path, .err = err};
  memcpy(w.scale, scale, sizeof w.scale);
  const struct aiScene *scene = NULL;
  model_status_t st = load_scene(path, &scene, err);
  if (st != MODEL_OK) return st;
  w.scene = scene;
  st = load_walk(&w, out);
  aiReleaseImport(scene);
  if (st != MODEL_OK) model_mesh_free(out);
  return st;
}

model_status_t model_mesh_load(const char *path, const double scale[3], model_mesh_t *out,
                               model_mesh_report_t *report, model_error_t *err) {
  if (report != NULL) {
    memset(report, 0, sizeof *report);
  }
  if (out == NULL) {
    return model_fail(err, MODEL_E_ARG, "output mesh is NULL");
  }
  memset(out, 0, sizeof *out);
  if (path == NULL || path[0] == '\0') {
    return model_fail(err, MODEL_E_ARG, "mesh path is NULL or empty");
  }
  walk_t w = {.path = path, .scale = {1.0, 1.0, 1.0}, .err = err};
  model_status_t st = load_scale(path, scale, w.scale, err);
  if (st != MODEL_OK) {
    return st;
  }
  int fd = -1;
  size_t bytes = 0;
  st = model_file_open_checked(path, "mesh", MODEL_MESH_MAX_BYTES, &fd, &bytes, err);
  if (st != MODEL_OK) {
    return st;
  }
  close(fd); /* assimp opens it by name, in the child */
  /* 2 s of CPU, and 1 s more per MB (assimp reads a 100 MB binary STL in ~5 s here) */
  st = model_mesh_parse_isolated(path, w.scale, 2.0 + 1e-6 * (double)bytes, bytes, parse_mesh, out,
                                 err);
  if (st == MODEL_OK) {
    st = model_mesh_check(out, report, err);
    if (st != MODEL_OK) {
      model_error_prefix(err, "mesh %s: ", path);
    }
  }
  if (st != MODEL_OK) {
    model_mesh_free(out);
  }
  return st;
}

/* ---- save ------------------------------------------------------------------------------------ */

static int export_format_known(const char *format) {
  int found = 0;
  size_t n = aiGetExportFormatCount();
  for (size_t i = 0; i < n && !found; ++i) {
    const struct aiExportFormatDesc *d = aiGetExportFormatDescription(i);
    if (d != NULL) {
      found = d->id != NULL && strcmp(d->id, format) == 0;
      aiReleaseExportFormatDescription(d);
    }
  }
  return found;
}

/* The checks of model_mesh_save on its mesh, in their order. */
static model_status_t save_check_mesh(const model_mesh_t *mesh, const char *path,
                                      model_error_t *err) {
  if (mesh->vertex_count == 0 || mesh->triangle_count == 0 || mesh->vertices_m == NULL ||
      mesh->triangles == NULL || mesh->vertex_count > UINT32_MAX ||
      mesh->triangle_count > UINT32_MAX) {
    return model_fail(err, MODEL_E_ARG, "cannot save %s: empty or oversized mesh", path);
  }
  for (size_t i = 0; i < mesh->vertex_count; ++i) {
    for (int k = 0; k < 3; ++k) {
      if (!isfinite(mesh->vertices_m[i][k])) {
        return model_fail(err, MODEL_E_NONFINITE, "cannot save %s: vertex %zu is not finite", path,
                          i);
      }
    }
  }
  for (size_t t = 0; t < mesh->triangle_count; ++t) {
    for (int k = 0; k < 3; ++k) {
      if (mesh->triangles[t][k] >= mesh->vertex_count) {
        return model_fail(err, MODEL_E_ARG, "cannot save %s: triangle %zu uses a missing vertex",
                          path, t);
      }
    }
  }
  return MODEL_OK;
}

/* A scene of one node, one mesh and one empty material, all owned here (assimp's exporter
 * deep-copies a user-built scene; it never frees ours). */
typedef struct {
  struct aiScene *scene;
  struct aiNode *root;
  struct aiMesh *am;
  struct aiMaterial *mat;
  struct aiMesh **mesh_list;
  struct aiMaterial **mat_list;
  unsigned *node_meshes;
  struct aiVector3D *vertices;
  struct aiFace *faces;
  unsigned *indices;
} save_scene_t;

/* Allocates every part of s (zeroed); returns 0 when one is missing (save_scene_free frees the
 * others). */
static int save_scene_alloc(save_scene_t *s, unsigned nv, unsigned nt) {
  s->scene = calloc(1, sizeof *s->scene);
  s->root = calloc(1, sizeof *s->root);
  s->am = calloc(1, sizeof *s->am);
  s->mat = calloc(1, sizeof *s->mat);
  s->mesh_list = calloc(1, sizeof *s->mesh_list);
  s->mat_list = calloc(1, sizeof *s->mat_list);
  s->node_meshes = calloc(1, sizeof *s->node_meshes);
  s->vertices = calloc(nv, sizeof *s->vertices);
  s->faces = calloc(nt, sizeof *s->faces);
  s->indices = calloc((size_t)nt * 3, sizeof *s->indices);
  return s->scene != NULL && s->root != NULL && s->am != NULL && s->mat != NULL &&
         s->mesh_list != NULL && s->mat_list != NULL && s->node_meshes != NULL &&
         s->vertices != NULL && s->faces != NULL && s->indices != NULL;
}

/* Copies the mesh into s and links its parts into one scene. */
static void save_scene_fill(save_scene_t *s, const model_mesh_t *mesh, unsigned nv, unsigned nt) {
  for (unsigned i = 0; i < nv; ++i) {
    s->vertices[i].x = (ai_real)mesh->vertices_m[i][0];
    s->vertices[i].y = (ai_real)mesh->vertices_m[i][1];
    s->vertices[i].z = (ai_real)mesh->vertices_m[i][2];
  }
  for (unsigned t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k) {
      s->indices[3 * (size_t)t + (size_t)k] = mesh->triangles[t][k];
    }
    s->faces[t].mNumIndices = 3;
    s->faces[t].mIndices = &s->indices[3 * (size_t)t];
  }
  struct aiMesh *am = s->am;
  am->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  am->mNumVertices = nv;
  am->mVertices = s->vertices;
  am->mNumFaces = nt;
  am->mFaces = s->faces;
  am->mMaterialIndex = 0;
  am->mName.length = 4;
  memcpy(am->mName.data, "mesh", 5);
  struct aiNode *root = s->root;
  root->mName.length = 4;
  memcpy(root->mName.data, "root", 5);
  root->mTransformation.a1 = root->mTransformation.b2 = 1;
  root->mTransformation.c3 = root->mTransformation.d4 = 1;
  root->mNumMeshes = 1;
  root->mMeshes = s->node_meshes;
  s->mesh_list[0] = am;
  s->mat_list[0] = s->mat;
  struct aiScene *scene = s->scene;
  scene->mFlags = AI_SCENE_FLAGS_NON_VERBOSE_FORMAT; /* vertices are shared between faces */
  scene->mRootNode = root;
  scene->mNumMeshes = 1;
  scene->mMeshes = s->mesh_list;
  scene->mNumMaterials = 1;
  scene->mMaterials = s->mat_list;
}

static void save_scene_free(save_scene_t *s) {
  free(s->indices);
  free(s->faces);
  free(s->vertices);
  free(s->node_meshes);
  free(s->mat_list);
  free(s->mesh_list);
  free(s->mat);
  free(s->am);
  free(s->root);
  free(s->scene);
}

model_status_t model_mesh_save(const model_mesh_t *mesh, const char *path, const char *format,
                               model_error_t *err) {
  if (mesh == NULL || path == NULL || path[0] == '\0' || format == NULL) {
    return model_fail(err, MODEL_E_ARG, "model_mesh_save: NULL mesh, path or format");
  }
  model_status_t st = save_check_mesh(mesh, path, err);
  if (st != MODEL_OK) {
    return st;
  }
  if (!export_format_known(format)) {
    return model_fail(err, MODEL_E_UNSUPPORTED, "cannot save %s: assimp has no exporter '%s'", path,
                      format);
  }

  const unsigned nv = (unsigned)mesh->vertex_count;
  const unsigned nt = (unsigned)mesh->triangle_count;
  save_scene_t s;
  if (!save_scene_alloc(&s, nv, nt)) {
    st = model_fail(err, MODEL_E_NOMEM, "cannot save %s: out of memory", path);
  } else {
    save_scene_fill(&s, mesh, nv, nt);
    if (aiExportScene(s.scene, format, path, 0) != aiReturn_SUCCESS) {
      st = model_fail(err, MODEL_E_NOFILE,
                      "assimp could not write %s as '%s' (folder missing or not writable?)", path,
                      format);
    }
  }
  save_scene_free(&s);
  return st;
}
