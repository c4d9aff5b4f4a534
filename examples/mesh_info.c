/* cc mesh_info.c $(pkg-config --cflags --libs comlearn-model) -o mesh_info
 * Load one link of a URDF with lib/model (comlearn::model) and print the bounding box and the
 * uniform-density center of mass of its collision geometry, in the link frame, in metres.
 * usage: mesh_info URDF   e.g. mesh_info PREFIX/share/comlearn/rocks/rock_1_even.urdf */
#include <stdio.h>

#include "comlearn/model.h"

int main(int argc, char **argv) {
  if (argc != 2) {
    fprintf(stderr, "usage: mesh_info URDF\n");
    return 2;
  }
  model_object_t obj;
  model_error_t err;
  model_status_t rc = model_object_load(argv[1], NULL, &obj, &err);
  if (rc != MODEL_OK) {
    fprintf(stderr, "mesh_info: %s: %s\n", model_status_str(rc), err.msg);
    return 1;
  }
  model_mass_t mass;
  rc = model_mesh_mass(&obj.mesh, 1000.0, &mass);
  if (rc == MODEL_OK) {
    const model_aabb_t *b = &obj.aabb;
    printf("%s: %zu triangles\n", obj.link_name, obj.mesh.triangle_count);
    printf("bbox_min_m %.6f %.6f %.6f\n", b->min_m[0], b->min_m[1], b->min_m[2]);
    printf("bbox_max_m %.6f %.6f %.6f\n", b->max_m[0], b->max_m[1], b->max_m[2]);
    printf("com_m %.6f %.6f %.6f\n", mass.com_m[0], mass.com_m[1], mass.com_m[2]);
  } else {
    fprintf(stderr, "mesh_info: %s\n", model_status_str(rc));
  }
  model_object_free(&obj);
  return rc == MODEL_OK ? 0 : 1;
}
