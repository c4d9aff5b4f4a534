/* estimate_test_util.h - fixtures shared by check_estimate, check_estimate_lcm and
 * check_estimate_faults. */
#ifndef COMLEARN_TESTS_ESTIMATE_TEST_UTIL_H
#define COMLEARN_TESTS_ESTIMATE_TEST_UTIL_H

#include <check.h>
#include <math.h>
#include <stdio.h>

#include "comlearn/model.h"
#include "comlearn/model_inertial.h"
#include "estimate_backend.h"

/* A two-material box 60 x 50 x 40 mm centred at (0.004, -0.003, 0.002): density 1000, and 4000
 * where x > 0.014 and (second cut) nothing else; its exact inertial (model_mesh_mass_halfspace)
 * goes into the URDF. */
static inline void write_two_material_box(const char *path, model_mass_t *truth) {
  const double lo[3] = {-0.026, -0.028, -0.018}, hi[3] = {0.034, 0.022, 0.022};
  model_mesh_t box = {0};
  ck_assert_int_eq(model_mesh_box(lo, hi, &box), MODEL_OK);
  const model_halfspace_t region = {{1.0, 0.3, -0.2}, 0.012};
  ck_assert_int_eq(model_mesh_mass_halfspace(&box, 1000.0, &region, 4000.0, truth), MODEL_OK);
  model_mesh_free(&box);
  const double(*I)[3] = (const double(*)[3])truth->inertia_kg_m2;
  FILE *f = fopen(path, "w");
  ck_assert_ptr_nonnull(f);
  fprintf(f,
          "<?xml version=\"1.0\"?>\n<robot name=\"two_material_box\">\n <link name=\"body\">\n"
          "  <inertial><origin xyz=\"%.17g %.17g %.17g\"/><mass value=\"%.17g\"/>\n"
          "   <inertia ixx=\"%.17g\" ixy=\"%.17g\" ixz=\"%.17g\" iyy=\"%.17g\" iyz=\"%.17g\" "
          "izz=\"%.17g\"/></inertial>\n"
          "  <collision><origin xyz=\"0.004 -0.003 0.002\"/>"
          "<geometry><box size=\"0.06 0.05 0.04\"/></geometry></collision>\n"
          " </link>\n</robot>\n",
          truth->com_m[0], truth->com_m[1], truth->com_m[2], truth->mass_kg, I[0][0], I[0][1],
          I[0][2], I[1][1], I[1][2], I[2][2]);
  fclose(f);
}

/* Noiseless, the LCM backend releases exactly where --direct does (up to the rounding of
 * FK(q) * grasp, ~1e-16 m), so every trial has the same outcome and the same achieved x, and the
 * estimates agree to that rounding; asserted at 1e-12 m. */
static inline void check_agree(const estimate_result_t *d, const estimate_result_t *l) {
  ck_assert_uint_eq(l->trial_count, d->trial_count);
  ck_assert_uint_eq(l->stable_trials, d->stable_trials);
  ck_assert_uint_eq(l->search_count, d->search_count);
  for (size_t i = 0; i < d->trial_count; ++i) {
    const estimate_trial_t *a = &d->trial[i], *b = &l->trial[i];
    ck_assert_int_eq(b->kind, a->kind);
    ck_assert_int_eq(b->search, a->search);
    ck_assert_msg(b->outcome == a->outcome, "trial %zu: lcm outcome %d, direct %d", i,
                  (int)b->outcome, (int)a->outcome);
    ck_assert_int_eq(b->flagged, a->flagged);
    ck_assert_msg(fabs(b->x_m - a->x_m) <= 1e-12, "trial %zu: x %.17g vs %.17g", i, b->x_m, a->x_m);
    for (int k = 0; k < 3; ++k) {
      ck_assert_double_eq_tol(b->released.position_m[k], a->released.position_m[k], 1e-12);
      /* the settled pose: same physics from the same release (played back by the simulator) */
      ck_assert_double_eq_tol(b->settled.position_m[k], a->settled.position_m[k], 1e-9);
    }
  }
  for (int k = 0; k < 3; ++k) {
    ck_assert_int_eq(l->found[k], d->found[k]);
    ck_assert_msg(fabs(l->com_m[k] - d->com_m[k]) <= 1e-12, "component %d: lcm %.17g direct %.17g",
                  k, l->com_m[k], d->com_m[k]);
  }
}

#endif
