/* shapegen.c - the rule: attempts, acceptance, the dense region, resting margins. */
#include "shapegen_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const kFamilyNames[SHAPEGEN_FAMILY_COUNT] = {
    "box", "domino", "feet2", "feet3",   "feet4", "ring",  "rim",
    "mug", "pebble", "lumpy", "scanned", "plate", "tilted"};

const char *shapegen_family_name(shapegen_family_t family) {
  return (unsigned)family < SHAPEGEN_FAMILY_COUNT ? kFamilyNames[family] : NULL;
}

int shapegen_family_parse(const char *name, shapegen_family_t *out) {
  if (name == NULL || out == NULL) return -1;
  for (unsigned f = 0; f < SHAPEGEN_FAMILY_COUNT; ++f) {
    if (strcmp(name, kFamilyNames[f]) == 0) {
      *out = (shapegen_family_t)f;
      return 0;
    }
  }
  return -1;
}

static uint64_t fnv1a64(const char *s) {
  uint64_t h = 0xcbf29ce484222325u;
  for (; *s != '\0'; ++s) h = (h ^ (unsigned char)*s) * 0x100000001b3u;
  return h;
}

model_status_t shapegen_spec_draw(shapegen_family_t family, uint64_t seed, unsigned attempt,
                                  shapegen_spec_t *out) {
  if (out == NULL || (unsigned)family >= SHAPEGEN_FAMILY_COUNT) return MODEL_E_ARG;
  memset(out, 0, sizeof *out);
  uint64_t outer = seed ^ fnv1a64(kFamilyNames[family]), state = 0;
  for (unsigned k = 0; k <= attempt; ++k) state = cl_rng_next(&outer);
  out->family = family;
  out->seed = seed;
  out->attempt = attempt;
  snprintf(out->name, sizeof out->name, "%s_s%llu", kFamilyNames[family], (unsigned long long)seed);
  if (sg_family_draw(family, &state, out) != 0) return MODEL_E_DEGENERATE;
  if (out->shape == SHAPEGEN_SHAPE_ROCK && out->noise_m == 0.0) {
    snprintf(out->rock.name, sizeof out->rock.name, "%.31s", out->name);
  }
  out->region_ratio = cl_rng_range(&state, 1.5, 3.0);
  out->region_seed = cl_rng_next(&state);
  out->region_shift_frac = cl_rng_uniform(&state);
  return MODEL_OK;
}

/* ---- the mesh -------------------------------------------------------------------------------- */

static model_status_t build_from_mesh(const model_mesh_t *m, sg_build_t *b) {
  for (size_t i = 0; i < m->vertex_count; ++i) {
    (void)sg_vert(b, m->vertices_m[i][0], m->vertices_m[i][1], m->vertices_m[i][2]);
  }
  for (size_t t = 0; t < m->triangle_count; ++t) {
    sg_tri(b, m->triangles[t][0], m->triangles[t][1], m->triangles[t][2]);
  }
  return b->nomem ? MODEL_E_NOMEM : MODEL_OK;
}

model_status_t shapegen_shape_build(const shapegen_spec_t *spec, model_mesh_t *out) {
  if (out == NULL) return MODEL_E_ARG;
  memset(out, 0, sizeof *out);
  if (spec == NULL || !(spec->noise_m >= 0.0) || spec->noise_m > 1e-3) return MODEL_E_ARG;
  sg_build_t b;
  sg_build_init(&b);
  model_status_t st = MODEL_E_ARG;
  switch (spec->shape) {
    case SHAPEGEN_SHAPE_BOX: st = sg_box_build(&spec->box, &b); break;
    case SHAPEGEN_SHAPE_SLAB: st = sg_slab_build(&spec->slab, &b); break;
    case SHAPEGEN_SHAPE_REVOLVE:
      st = sg_revolve_build(&spec->rev, spec->handle.present ? &spec->handle : NULL, &b);
      break;
    case SHAPEGEN_SHAPE_ROCK: {
      st = rockgen_shape_build(&spec->rock, out);
      if (st != MODEL_OK || spec->noise_m == 0.0) return st; /* centred and float32 already */
      st = build_from_mesh(out, &b);
      model_mesh_free(out);
      break;
    }
  }
  if (st != MODEL_OK) {
    sg_build_free(&b);
    return st;
  }
  if (spec->lay_on_side) { /* (x, y, z) -> (z, y, -x): a rotation, orientation kept */
    for (size_t i = 0; i < b.nv; ++i) {
      const double x = b.v[i][0];
      b.v[i][0] = b.v[i][2];
      b.v[i][2] = -x + 0.0;
    }
  }
  if (spec->noise_m > 0.0) {
    uint64_t ns = spec->noise_seed;
    for (size_t i = 0; i < b.nv; ++i) {
      for (int k = 0; k < 3; ++k) b.v[i][k] += cl_rng_range(&ns, -spec->noise_m, spec->noise_m);
    }
  }
  return sg_build_finish(&b, out);
}

/* ---- the dense region ------------------------------------------------------------------------ */

enum { REGION_NORMAL_TRIES = 32, REGION_SCAN = 32, REGION_BISECT = 48 };
static const double kRegionMinMax_m = 0.0022;

static model_status_t shift_at(const shapegen_spec_t *spec, const model_mesh_t *mesh,
                               const model_mass_t *even, const double n[3], double t, double *shift,
                               model_mass_t *mass) {
  model_halfspace_t reg;
  memcpy(reg.normal, n, sizeof reg.normal);
  reg.offset_m = cl_vec3_dot(n, even->com_m) + t;
  model_mass_t m;
  const model_status_t st = model_mesh_mass_halfspace(mesh, spec->density_kg_m3, &reg,
                                                      spec->density_kg_m3 * spec->region_ratio, &m);
  if (st != MODEL_OK) return st;
  *shift = cl_vec3_dist(m.com_m, even->com_m);
  if (mass != NULL) *mass = m;
  return MODEL_OK;
}

model_status_t shapegen_mass(const shapegen_spec_t *spec, const model_mesh_t *mesh,
                             model_mass_t *even, model_mass_t *uneven, model_halfspace_t *region) {
  if (spec == NULL || mesh == NULL || !(spec->region_ratio > 1.0)) return MODEL_E_ARG;
  model_mass_t e, u;
  model_status_t st = model_mesh_mass(mesh, spec->density_kg_m3, &e);
  if (st != MODEL_OK) return st;
  uint64_t rs = spec->region_seed;
  double n[3] = {0, 0, 1}, best_t = 0.0, best = 0.0, ext = 0.0;
  for (int tries = 0; tries < REGION_NORMAL_TRIES && best < kRegionMinMax_m; ++tries) {
    cl_rng_direction(&rs, 3, n);
    ext = 0.0;
    for (size_t i = 0; i < mesh->vertex_count; ++i) {
      const double s = fabs(cl_vec3_dot(n, mesh->vertices_m[i]) - cl_vec3_dot(n, e.com_m));
      if (s > ext) ext = s;
    }
    best = 0.0;
    for (int k = 0; k <= REGION_SCAN; ++k) {
      const double t = -ext + 2.0 * ext * k / REGION_SCAN;
      double s = 0.0;
      st = shift_at(spec, mesh, &e, n, t, &s, NULL);
      if (st != MODEL_OK) return st;
      if (s > best) {
        best = s;
        best_t = t;
      }
    }
  }
  if (best < kRegionMinMax_m) return MODEL_E_REGION;
  const double top = 0.95 * best < SHAPEGEN_SHIFT_MAX_M ? 0.95 * best : SHAPEGEN_SHIFT_MAX_M;
  const double target =
      SHAPEGEN_SHIFT_MIN_M + spec->region_shift_frac * (top - SHAPEGEN_SHIFT_MIN_M);
  double lo = best_t, hi = ext;
  for (int it = 0; it < REGION_BISECT; ++it) {
    const double mid = 0.5 * (lo + hi);
    double s = 0.0;
    st = shift_at(spec, mesh, &e, n, mid, &s, NULL);
    if (st != MODEL_OK) return st;
    if (s >= target) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  double s = 0.0;
  st = shift_at(spec, mesh, &e, n, lo, &s, &u);
  if (st != MODEL_OK) return st;
  if (even != NULL) *even = e;
  if (uneven != NULL) *uneven = u;
  if (region != NULL) {
    memcpy(region->normal, n, sizeof region->normal);
    region->offset_m = cl_vec3_dot(n, e.com_m) + lo;
  }
  return MODEL_OK;
}

/* ---- resting margins ------------------------------------------------------------------------- */

model_status_t shapegen_rest_margin(const model_mesh_t *mesh, const model_mesh_t *hull,
                                    const double com_m[3], double *margin_m,
                                    double best_normal[3]) {
  if (mesh == NULL || hull == NULL || com_m == NULL || margin_m == NULL) return MODEL_E_ARG;
  *margin_m = -HUGE_VAL;
  const size_t nv = mesh->vertex_count, nh = hull->triangle_count;
  double(*pts)[2] = malloc((nv + 1) * sizeof *pts);
  double(*poly)[2] = malloc((nv + 1) * sizeof *poly);
  double(*planes)[4] = malloc((nh + 1) * sizeof *planes);
  if (pts == NULL || poly == NULL || planes == NULL) {
    free(pts);
    free(poly);
    free(planes);
    return MODEL_E_NOMEM;
  }
  size_t seen = 0;
  for (size_t t = 0; t < nh; ++t) {
    const double *a = hull->vertices_m[hull->triangles[t][0]];
    const double *b = hull->vertices_m[hull->triangles[t][1]];
    const double *c = hull->vertices_m[hull->triangles[t][2]];
    double n[3];
    if (!(cl_tri_normal(a, b, c, n) > 0.0)) continue;
    double h = cl_vec3_dot(n, a);
    if (cl_vec3_dot(n, b) > h) h = cl_vec3_dot(n, b);
    if (cl_vec3_dot(n, c) > h) h = cl_vec3_dot(n, c);
    /* a facet split into several hull triangles: evaluate its plane once */
    int dup = 0;
    for (size_t p = 0; p < seen && !dup; ++p) {
      dup =
          cl_vec3_dot(n, planes[p]) > 1.0 - 1e-12 && fabs(h - planes[p][3]) < SHAPEGEN_PLANE_TOL_M;
    }
    if (dup) continue;
    memcpy(planes[seen], n, sizeof n);
    planes[seen++][3] = h;
    double u[3], v[3];
    model_plane_basis(n, u, v);
    size_t np = 0;
    for (size_t i = 0; i < nv; ++i) {
      const double *x = mesh->vertices_m[i];
      if (cl_vec3_dot(n, x) < h - SHAPEGEN_PLANE_TOL_M) continue;
      pts[np][0] = cl_vec3_dot(u, x);
      pts[np][1] = cl_vec3_dot(v, x);
      ++np;
    }
    const size_t count = model_polygon_hull(pts, np, poly);
    const double p2[2] = {cl_vec3_dot(u, com_m), cl_vec3_dot(v, com_m)};
    const double m = model_polygon_margin((const double(*)[2])poly, count, p2);
    if (m > *margin_m) {
      *margin_m = m;
      if (best_normal != NULL) memcpy(best_normal, n, sizeof n);
    }
  }
  free(pts);
  free(poly);
  free(planes);
  return MODEL_OK;
}

/* ---- acceptance ------------------------------------------------------------------------------ */

/* Statuses that mean "this draw is not a valid object" rather than a failure. */
static int rejects(model_status_t st) {
  return st == MODEL_E_ARG || st == MODEL_E_DEGENERATE || st == MODEL_E_OPEN ||
         st == MODEL_E_ORIENT || st == MODEL_E_HULL || st == MODEL_E_REGION ||
         st == MODEL_E_INERTIAL || st == MODEL_E_INERTIA_TRIANGLE || st == MODEL_E_NONFINITE ||
         st == MODEL_E_IMPLAUSIBLE;
}

static model_status_t check_clean(const model_mesh_t *mesh, int *clean) {
  model_mesh_t copy;
  model_mesh_report_t rep;
  *clean = 0;
  model_status_t st = model_mesh_copy(mesh, &copy);
  if (st != MODEL_OK) return st;
  st = model_mesh_check(&copy, &rep, NULL);
  if (st == MODEL_OK) {
    *clean = rep.merged_vertices == 0 && rep.removed_degenerate == 0 &&
             rep.removed_unreferenced == 0 && rep.flipped == 0 &&
             copy.vertex_count == mesh->vertex_count && copy.triangle_count == mesh->triangle_count;
  }
  model_mesh_free(&copy);
  return st;
}

/* Largest extent of the bounding box within the documented 20-120 mm. */
static int size_ok(const model_mesh_t *mesh) {
  model_aabb_t box;
  if (model_mesh_aabb(mesh, &box) != MODEL_OK) return 0;
  double e = 0.0;
  for (int k = 0; k < 3; ++k) {
    if (box.max_m[k] - box.min_m[k] > e) e = box.max_m[k] - box.min_m[k];
  }
  return e >= 0.020 - 1e-9 && e <= 0.120 + 1e-9;
}

static model_status_t accept_mesh(const shapegen_spec_t *spec, shapegen_object_t *o, int *ok) {
  int clean = 0;
  model_status_t st = check_clean(&o->mesh, &clean);
  if (st != MODEL_OK || !clean || !size_ok(&o->mesh)) return st;
  model_mesh_t hull;
  st = model_mesh_hull(&o->mesh, &hull, NULL);
  if (st != MODEL_OK) return st;
  st = shapegen_mass(spec, &o->mesh, &o->even, &o->uneven, &o->region);
  /* model_mass_check, and what the simulator side also demands (>= 1 g, ...) */
  if (st == MODEL_OK) st = model_mass_plausible(&o->even, &o->mesh, NULL);
  if (st == MODEL_OK) st = model_mass_plausible(&o->uneven, &o->mesh, NULL);
  if (st == MODEL_OK)
    st = shapegen_rest_margin(&o->mesh, &hull, o->even.com_m, &o->margin_even_m, NULL);
  if (st == MODEL_OK) {
    st = shapegen_rest_margin(&o->mesh, &hull, o->uneven.com_m, &o->margin_uneven_m, NULL);
  }
  model_mesh_free(&hull);
  if (st != MODEL_OK) return st;
  o->shift_m = cl_vec3_dist(o->even.com_m, o->uneven.com_m);
  *ok = o->margin_even_m >= SHAPEGEN_MIN_MARGIN_M && o->margin_uneven_m >= SHAPEGEN_MIN_MARGIN_M;
  return MODEL_OK;
}

model_status_t shapegen_accept(const shapegen_spec_t *spec, int *accepted, shapegen_object_t *out) {
  if (spec == NULL || accepted == NULL || out == NULL) return MODEL_E_ARG;
  *accepted = 0;
  memset(out, 0, sizeof *out);
  model_status_t st = shapegen_shape_build(spec, &out->mesh);
  int ok = 0;
  if (st == MODEL_OK) st = accept_mesh(spec, out, &ok);
  if (st != MODEL_OK || !ok) {
    shapegen_object_free(out);
    return rejects(st) ? MODEL_OK : st;
  }
  out->spec = *spec;
  *accepted = 1;
  return MODEL_OK;
}

model_status_t shapegen_generate(shapegen_family_t family, uint64_t seed, shapegen_object_t *out) {
  if (out == NULL) return MODEL_E_ARG;
  memset(out, 0, sizeof *out);
  if ((unsigned)family >= SHAPEGEN_FAMILY_COUNT) return MODEL_E_ARG;
  shapegen_spec_t *spec = malloc(sizeof *spec);
  if (spec == NULL) return MODEL_E_NOMEM;
  model_status_t result = MODEL_E_DEGENERATE;
  for (unsigned k = 0; k < SHAPEGEN_MAX_ATTEMPTS; ++k) {
    model_status_t st = shapegen_spec_draw(family, seed, k, spec);
    if (st == MODEL_E_DEGENERATE) continue;
    int ok = 0;
    if (st == MODEL_OK) st = shapegen_accept(spec, &ok, out);
    if (st != MODEL_OK) {
      result = st;
      break;
    }
    if (ok) {
      result = MODEL_OK;
      break;
    }
  }
  free(spec);
  return result;
}

void shapegen_object_free(shapegen_object_t *obj) {
  if (obj == NULL) return;
  model_mesh_free(&obj->mesh);
  memset(obj, 0, sizeof *obj);
}
