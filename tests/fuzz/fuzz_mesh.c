/* fuzz_mesh.c - libFuzzer harness: model_mesh_load on arbitrary bytes, as an STL, PLY, OBJ or
 * Collada file (the first byte picks the extension, the rest is the file). assimp runs in
 * lib/model's child process, so an assimp crash or loop must come back as an error: the harness
 * process may not crash, leak or hang. docs/security.md, "Fuzzing". */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "comlearn/model.h"
#include "fuzz_file.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  if (size < 1) return 0;
  static const char *const ext[] = {"stl", "ply", "obj", "dae"};
  const char *path = fuzz_file(data + 1, size - 1, ext[data[0] % 4]);
  if (path == NULL) return 0;
  model_mesh_t m;
  model_error_t err;
  if (model_mesh_load(path, NULL, &m, NULL, &err) == MODEL_OK) model_mesh_free(&m);
  remove(path);
  return 0;
}
