/* fuzz_urdf.c - libFuzzer harness: a URDF of arbitrary bytes through both readers, the geometry
 * (model_object_load) and the truth (model_inertial_load): tinyxml and urdfdom behind lib/model's
 * file and XML shape checks. Nothing may crash, leak or hang. docs/security.md, "Fuzzing". */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "comlearn/model.h"
#include "comlearn/model_inertial.h"
#include "fuzz_file.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  const char *path = fuzz_file(data, size, "urdf");
  if (path == NULL) return 0;
  model_object_t obj;
  model_error_t err;
  if (model_object_load(path, NULL, &obj, &err) == MODEL_OK) model_object_free(&obj);
  model_mass_t mass;
  (void)model_inertial_load(path, NULL, &mass, &err);
  remove(path);
  return 0;
}
