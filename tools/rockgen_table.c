/* rockgen_table.c - the parameter table of the bundled rocks. Changing a number here changes the
 * committed assets: regenerate them (docs/assets.md) and commit both.
 *
 * Each rock has a bottom fracture face with normal exactly -z (it stands upright in its link
 * frame) and a side face with normal exactly +-x (the paper's pose for the z component: rotated
 * about Y so that Z lies along the table), plus oblique fracture faces and a rounded, lumpy
 * surface elsewhere. Rock: 2650 kg/m^3 (granite, quartz). Uneven rocks: one side of a plane
 * through (or near) the uniform-density CoM is a magnetite-rich layer at 5200 kg/m^3. */
#include "rockgen.h"

static const rockgen_spec_t kRocks[] = {
    {
        .name = "rock_1",
        .seed = 0x5eed0001u,
        .frequency = 10,
        .semi_axes_m = {0.037, 0.029, 0.026},
        .lobe_count = 6,
        .lobe_amplitude = 0.20,
        .lobe_cos = 0.30,
        .bump_count = 26,
        .bump_amplitude = 0.06,
        .bump_cos = 0.86,
        .fracture_count = 4,
        .fractures = {{{0.0, 0.0, -1.0}, 0.0065},
                      {{1.0, 0.0, 0.0}, 0.0070},
                      {{-0.35, 0.75, 0.55}, 0.0050},
                      {{-0.70, -0.55, 0.45}, 0.0040}},
        .density_kg_m3 = 2650.0,
        .region_normal = {0.62, 0.48, 0.30},
        .region_offset_m = 0.003,
        .region_density_kg_m3 = 5200.0,
    },
    {
        .name = "rock_2",
        .seed = 0x5eed0002u,
        .frequency = 10,
        .semi_axes_m = {0.0355, 0.027, 0.025},
        .lobe_count = 6,
        .lobe_amplitude = 0.20,
        .lobe_cos = 0.25,
        .bump_count = 26,
        .bump_amplitude = 0.06,
        .bump_cos = 0.88,
        .fracture_count = 4,
        .fractures = {{{0.0, 0.0, -1.0}, 0.0060},
                      {{-1.0, 0.0, 0.0}, 0.0075},
                      {{0.20, -1.0, 0.15}, 0.0055},
                      {{0.55, 0.45, 0.70}, 0.0045}},
        .density_kg_m3 = 2650.0,
        .region_normal = {-0.55, 0.35, 0.55},
        .region_offset_m = 0.003,
        .region_density_kg_m3 = 5200.0,
    },
    {
        .name = "rock_3",
        .seed = 0x5eed0003u,
        .frequency = 10,
        .semi_axes_m = {0.032, 0.030, 0.027},
        .lobe_count = 6,
        .lobe_amplitude = 0.20,
        .lobe_cos = 0.35,
        .bump_count = 26,
        .bump_amplitude = 0.06,
        .bump_cos = 0.86,
        .fracture_count = 4,
        .fractures = {{{0.0, 0.0, -1.0}, 0.0070},
                      {{1.0, 0.0, 0.0}, 0.0065},
                      {{-0.45, -0.80, 0.35}, 0.0055},
                      {{-0.60, 0.60, 0.55}, 0.0030}},
        .density_kg_m3 = 2650.0,
        .region_normal = {0.25, -0.70, -0.45},
        .region_offset_m = 0.003,
        .region_density_kg_m3 = 5200.0,
    },
};

size_t rockgen_spec_count(void) { return sizeof kRocks / sizeof kRocks[0]; }

const rockgen_spec_t *rockgen_spec_get(size_t index) {
  return index < rockgen_spec_count() ? &kRocks[index] : NULL;
}
