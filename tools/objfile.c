/* objfile.c - binary STL and URDF elements of generated objects (objfile.h). */
#include "objfile.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <string.h>
#include <sys/stat.h>

#include "comlearn/math3d.h"

int objfile_mkdir(const char *path) { return mkdir(path, 0777) == 0 || errno == EEXIST ? 0 : -1; }

static void put_u32(unsigned char *b, uint32_t v) {
  for (int i = 0; i < 4; ++i) b[i] = (unsigned char)(v >> (8 * i));
}

static void put_f32(unsigned char *b, float f) {
  uint32_t u;
  memcpy(&u, &f, sizeof u);
  put_u32(b, u);
}

int objfile_write_stl(const model_mesh_t *m, const char *path, const char *header_text) {
  FILE *f = fopen(path, "wb");
  if (f == NULL) return -1;
  unsigned char header[84];
  memset(header, ' ', 80);
  const size_t n = strlen(header_text);
  memcpy(header, header_text, n < 80 ? n : 80);
  put_u32(header + 80, (uint32_t)m->triangle_count);
  int ok = fwrite(header, 1, sizeof header, f) == sizeof header;
  for (size_t t = 0; ok && t < m->triangle_count; ++t) {
    const double *a = m->vertices_m[m->triangles[t][0]], *b = m->vertices_m[m->triangles[t][1]],
                 *c = m->vertices_m[m->triangles[t][2]];
    double nv[3];
    cl_tri_normal(a, b, c, nv);
    unsigned char rec[50];
    for (int k = 0; k < 3; ++k) put_f32(rec + 4 * k, (float)nv[k]);
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < 3; ++k) {
        put_f32(rec + 12 + 12 * i + 4 * k, (float)m->vertices_m[m->triangles[t][i]][k]);
      }
    }
    rec[48] = rec[49] = 0;
    ok = fwrite(rec, 1, sizeof rec, f) == sizeof rec;
  }
  const int saved = errno;
  if (fclose(f) != 0)
    ok = 0;
  else if (!ok)
    errno = saved;
  return ok ? 0 : -1;
}

void objfile_put_inertial(FILE *f, const model_mass_t *m) {
  const double(*i)[3] = (const double(*)[3])m->inertia_kg_m2;
  fprintf(f, "    <inertial>\n");
  fprintf(f, "      <origin xyz=\"%.17g %.17g %.17g\" rpy=\"0 0 0\"/>\n", m->com_m[0], m->com_m[1],
          m->com_m[2]);
  fprintf(f, "      <mass value=\"%.17g\"/>\n", m->mass_kg);
  fprintf(f,
          "      <inertia ixx=\"%.17g\" ixy=\"%.17g\" ixz=\"%.17g\" iyy=\"%.17g\" iyz=\"%.17g\" "
          "izz=\"%.17g\"/>\n",
          i[0][0], i[0][1], i[0][2], i[1][1], i[1][2], i[2][2]);
  fprintf(f, "    </inertial>\n");
}

void objfile_put_mesh_geometry(FILE *f, const char *mesh_rel, const char *material,
                               const char *rgba) {
  fprintf(f,
          "    <visual>\n      <geometry>\n        <mesh filename=\"%s\"/>\n"
          "      </geometry>\n      <material name=\"%s\">\n"
          "        <color rgba=\"%s\"/>\n      </material>\n    </visual>\n",
          mesh_rel, material, rgba);
  fprintf(f,
          "    <collision>\n      <geometry>\n        <mesh filename=\"%s\"/>\n"
          "      </geometry>\n    </collision>\n",
          mesh_rel);
}
