/* massprop_halfspace.c - exact mass properties of a body of two materials split by a plane.
 *
 * M = rho1 * (whole solid) + (rho2 - rho1) * (solid inside the region). The part inside is
 * bounded by the triangles clipped to the region plus a cap in the plane. Integrating the signed
 * tetrahedra from a reference point on the plane gives every cap triangle a zero-volume
 * tetrahedron, so the cap (never built) contributes nothing and the result stays exact. */
#include <math.h>
#include <string.h>

#include "comlearn/model_inertial.h"
#include "massprop_accum.h"

/* Point where the edge from an inside vertex (s_in >= 0) to an outside one (s_out < 0) crosses
 * the plane. Always computed from the inside end so that the two triangles sharing an edge get
 * the same point. */
static void crossing(const double in[3], double s_in, const double out_v[3], double s_out,
                     double x[3]) {
  const double t = s_in / (s_in - s_out);
  for (int k = 0; k < 3; ++k) x[k] = in[k] + t * (out_v[k] - in[k]);
}

/* Add the part of triangle (v0, v1, v2) with s >= 0 (Sutherland-Hodgman against one plane: at
 * most a quadrilateral, fanned from its first vertex, orientation kept). */
static void add_clipped(model_massprop_acc_t *acc, const double *const v[3], const double s[3]) {
  double poly[4][3];
  int n = 0;
  for (int e = 0; e < 3; ++e) {
    const double *p = v[e];
    const double *q = v[(e + 1) % 3];
    const double sp = s[e];
    const double sq = s[(e + 1) % 3];
    if (sp >= 0.0) {
      for (int k = 0; k < 3; ++k) poly[n][k] = p[k];
      ++n;
      if (sq < 0.0) crossing(p, sp, q, sq, poly[n++]);
    } else if (sq >= 0.0) {
      crossing(q, sq, p, sp, poly[n++]);
    }
  }
  for (int i = 1; i + 1 < n; ++i)
    model_massprop_acc_add_triangle(acc, poly[0], poly[i], poly[i + 1]);
}

model_status_t model_mesh_mass_halfspace(const model_mesh_t *mesh, double density_kg_m3,
                                         const model_halfspace_t *region,
                                         double region_density_kg_m3, model_mass_t *out) {
  if (out == NULL) return MODEL_E_ARG;
  memset(out, 0, sizeof *out);
  if (region == NULL) return MODEL_E_ARG;
  if (!isfinite(density_kg_m3) || !(density_kg_m3 > 0.0) || !isfinite(region_density_kg_m3) ||
      !(region_density_kg_m3 > 0.0)) {
    return MODEL_E_ARG;
  }
  /* Unit normal; scale by the largest component first so that |n|^2 cannot overflow. */
  double big = 0.0;
  for (int k = 0; k < 3; ++k) {
    if (!isfinite(region->normal[k])) return MODEL_E_REGION;
    if (fabs(region->normal[k]) > big) big = fabs(region->normal[k]);
  }
  if (!isfinite(region->offset_m) || !(big > 0.0)) return MODEL_E_REGION;
  double n[3];
  for (int k = 0; k < 3; ++k) n[k] = region->normal[k] / big;
  const double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (int k = 0; k < 3; ++k) n[k] /= len;
  const double offset = (region->offset_m / big) / len;
  if (!isfinite(offset)) return MODEL_E_REGION;

  double ref[3], extent;
  model_status_t st = model_massprop_mesh_validate(mesh, ref, &extent);
  if (st != MODEL_OK) return st;

  /* Reference point for the inside part: the box center projected onto the plane. */
  const double ref_dist = n[0] * ref[0] + n[1] * ref[1] + n[2] * ref[2] - offset;
  double on_plane[3];
  for (int k = 0; k < 3; ++k) on_plane[k] = ref[k] - ref_dist * n[k];

  model_massprop_acc_t whole, inside;
  model_massprop_acc_init(&whole, ref);
  model_massprop_acc_init(&inside, on_plane);
  size_t all_in = 0;
  for (size_t t = 0; t < mesh->triangle_count; ++t) {
    const double *v[3];
    double s[3];
    int n_in = 0;
    for (int i = 0; i < 3; ++i) {
      v[i] = mesh->vertices_m[mesh->triangles[t][i]];
      s[i] = n[0] * v[i][0] + n[1] * v[i][1] + n[2] * v[i][2] - offset;
      if (s[i] >= 0.0) ++n_in;
    }
    model_massprop_acc_add_triangle(&whole, v[0], v[1], v[2]);
    if (n_in == 3) {
      model_massprop_acc_add_triangle(&inside, v[0], v[1], v[2]);
      ++all_in;
    } else if (n_in > 0) {
      add_clipped(&inside, v, s);
    }
  }
  if (!(whole.vol > model_massprop_min_volume(extent))) return MODEL_E_DEGENERATE;
  /* A plane that misses the body may lie far from it, and moments about a far point lose digits:
   * when every triangle is inside, the inside part is the whole (when none is, it is empty). */
  if (all_in == mesh->triangle_count) inside = whole;

  model_massprop_acc_t total;
  model_massprop_acc_init(&total, ref);
  model_massprop_acc_add_scaled(&total, &whole, density_kg_m3);
  model_massprop_acc_add_scaled(&total, &inside, region_density_kg_m3 - density_kg_m3);
  const double rho_min =
      density_kg_m3 < region_density_kg_m3 ? density_kg_m3 : region_density_kg_m3;
  return model_massprop_acc_finish(&total, 1.0, rho_min * model_massprop_min_volume(extent), out);
}
