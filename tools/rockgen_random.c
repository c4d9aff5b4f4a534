/* rockgen_random.c - random rocks in the style of the bundled table, named by a seed. */
#include "rockgen.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "comlearn/math3d.h"
enum { PATCHES_MAX = 16 };

/* Patches smaller than this are not fracture faces (as in comlearn-rockgen and check_assets). */
static const double kMinPatchArea_m2 = 1e-4;
/* Azimuths of the side and oblique faces at least 60 degrees apart (cos 60 deg). */
static const double kMaxAzimuthCos = 0.5;

model_status_t rockgen_spec_random_draw(uint64_t seed, unsigned attempt, rockgen_spec_t *out) {
  if (out == NULL) return MODEL_E_ARG;
  uint64_t outer = seed, state = 0;
  for (unsigned k = 0; k <= attempt; ++k) state = cl_rng_next(&outer);

  memset(out, 0, sizeof *out);
  snprintf(out->name, sizeof out->name, "rock_r%llu", (unsigned long long)seed);
  out->seed = cl_rng_next(&state);
  out->frequency = 10;
  out->semi_axes_m[0] = cl_rng_range(&state, 0.030, 0.038);
  out->semi_axes_m[1] = cl_rng_range(&state, 0.026, 0.031);
  out->semi_axes_m[2] = cl_rng_range(&state, 0.024, 0.028);
  out->lobe_count = 6;
  out->lobe_amplitude = 0.20;
  out->lobe_cos = cl_rng_range(&state, 0.25, 0.35);
  out->bump_count = 26;
  out->bump_amplitude = 0.06;
  out->bump_cos = cl_rng_range(&state, 0.86, 0.88);

  out->fracture_count = 4;
  rockgen_fracture_t *fr = out->fractures;
  fr[0].normal[2] = -1.0;
  fr[0].depth_m = cl_rng_range(&state, 0.006, 0.007);
  fr[1].normal[0] = cl_rng_uniform(&state) < 0.5 ? -1.0 : 1.0;
  fr[1].depth_m = cl_rng_range(&state, 0.0065, 0.0075);
  /* Oblique faces: z in [0.4, 0.75], the horizontal part of the normal pointing away from the
   * side face and from the other oblique face (each try draws a fresh azimuth; the cap keeps the
   * loop bounded, the last draw is used when it is reached). */
  for (int i = 2; i < 4; ++i) {
    const double z = cl_rng_range(&state, 0.4, 0.75);
    const double h = sqrt(1.0 - z * z);
    double a[3];
    for (int tries = 0; tries < 64; ++tries) {
      cl_rng_direction(&state, 2, a);
      int ok = a[0] * fr[1].normal[0] <= kMaxAzimuthCos;
      if (i == 3) {
        const double b0 = fr[2].normal[0], b1 = fr[2].normal[1];
        const double bn = sqrt(b0 * b0 + b1 * b1);
        ok = ok && (a[0] * b0 + a[1] * b1) / bn <= kMaxAzimuthCos;
      }
      if (ok) break;
    }
    fr[i].normal[0] = h * a[0];
    fr[i].normal[1] = h * a[1];
    fr[i].normal[2] = z;
    fr[i].depth_m = cl_rng_range(&state, 0.003, 0.0055);
  }

  out->density_kg_m3 = 2650.0;
  cl_rng_direction(&state, 3, out->region_normal);
  out->region_offset_m = cl_rng_range(&state, 0.002, 0.004);
  out->region_density_kg_m3 = 5200.0;
  return MODEL_OK;
}

model_status_t rockgen_random_accept(const rockgen_spec_t *spec, int *accepted, double *margin_m) {
  if (spec == NULL || accepted == NULL) return MODEL_E_ARG;
  *accepted = 0;
  if (margin_m != NULL) *margin_m = NAN;
  model_mesh_t mesh;
  model_status_t st = rockgen_shape_build(spec, &mesh);
  if (st == MODEL_E_ARG) return MODEL_OK; /* lobes or planes this shape cannot take */
  if (st != MODEL_OK) return st;
  /* Its convex hull must build: nothing downstream can use a rock without one. Quickhull failed
   * (MODEL_E_HULL, a point above a hull face) on about 4 % of these shapes until its walk over
   * the visible faces became exact; now no draw is known to fail here (docs/model.md). */
  model_mesh_t hull;
  st = model_mesh_hull(&mesh, &hull, NULL);
  model_mesh_free(&hull);
  if (st == MODEL_E_HULL) {
    model_mesh_free(&mesh);
    return MODEL_OK;
  }
  if (st != MODEL_OK) {
    model_mesh_free(&mesh);
    return st;
  }
  model_mass_t even, uneven;
  rockgen_patch_t patches[PATCHES_MAX];
  size_t count = 0;
  st = rockgen_mass(spec, &mesh, &even, &uneven, NULL);
  if (st == MODEL_OK)
    st = rockgen_patches_find(&mesh, kMinPatchArea_m2, patches, PATCHES_MAX, &count);
  model_mesh_free(&mesh);
  if (st == MODEL_E_DEGENERATE) return MODEL_OK; /* a zero-area triangle: not this shape */
  if (st != MODEL_OK) return st;
  if (count == 0 || !(patches[0].normal[2] < -ROCKGEN_PLANE_COS)) return MODEL_OK;
  const double m_even = rockgen_patch_margin(&patches[0], even.com_m);
  const double m_uneven = rockgen_patch_margin(&patches[0], uneven.com_m);
  if (margin_m != NULL) *margin_m = m_uneven;
  *accepted = patches[0].width_m >= ROCKGEN_RANDOM_MIN_WIDTH_M &&
              patches[0].support_excess_m <= ROCKGEN_PLANE_TOL_M &&
              m_even >= ROCKGEN_RANDOM_MIN_MARGIN_M && m_uneven >= ROCKGEN_RANDOM_MIN_MARGIN_M;
  return MODEL_OK;
}

model_status_t rockgen_spec_random(uint64_t seed, rockgen_spec_t *out) {
  if (out == NULL) return MODEL_E_ARG;
  for (unsigned k = 0; k < ROCKGEN_RANDOM_MAX_ATTEMPTS; ++k) {
    int ok = 0;
    model_status_t st = rockgen_spec_random_draw(seed, k, out);
    if (st == MODEL_OK) st = rockgen_random_accept(out, &ok, NULL);
    if (st != MODEL_OK) return st;
    if (ok) return MODEL_OK;
  }
  return MODEL_E_DEGENERATE;
}
