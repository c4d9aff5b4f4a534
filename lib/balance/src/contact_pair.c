/* contact_pair.c - object-object contacts: the vertices of each object inside (or within
 * BALANCE_CONTACT_BAND_M of) the other's convex hull. The normal is the hull face the vertex is
 * least deep behind. ODE's trimesh-trimesh collider is not used: for two flat faces resting on
 * each other it returns normals along the faces with centimetre depths, which throw the upper
 * object off at the first step. */
#include <math.h>

#include "balance_internal.h"

/* Points of `src`'s vertices against `dst`'s hull. flip: the normal is negated (so that it always
 * points into the pair's first body). */
static size_t verts_in_hull(const balance_object_t *src, const balance_object_t *dst, int flip,
                            uint32_t id_base, balance_point_t *out, size_t cap, size_t n) {
  const dReal *ps = dBodyGetPosition(src->body), *qs = dBodyGetQuaternion(src->body);
  const dReal *pd = dBodyGetPosition(dst->body), *qd = dBodyGetQuaternion(dst->body);
  const double qs4[4] = {qs[0], qs[1], qs[2], qs[3]}, qd4[4] = {qd[0], qd[1], qd[2], qd[3]};
  double rs[3][3], rd[3][3];
  model_quat_to_rot(qs4, rs);
  model_quat_to_rot(qd4, rd);
  const double reach = dst->radius_m + BALANCE_CONTACT_BAND_M;
  for (size_t i = 0; i < src->mesh_link.vertex_count && n < cap; i++) {
    const double *v = src->verts_body_m[i];
    double w[3], rel[3], b[3];
    for (int k = 0; k < 3; k++) {
      w[k] = rs[k][0] * v[0] + rs[k][1] * v[1] + rs[k][2] * v[2] + ps[k];
      rel[k] = w[k] - pd[k];
    }
    if (rel[0] * rel[0] + rel[1] * rel[1] + rel[2] * rel[2] > reach * reach) continue;
    for (int k = 0; k < 3; k++) b[k] = rd[0][k] * rel[0] + rd[1][k] * rel[1] + rd[2][k] * rel[2];
    /* The plane that separated this vertex last time first: outside is outside whichever plane
     * shows it, so the decision is the one the full scan below makes. */
    uint32_t *hint = &src->sep_cache[i * BALANCE_SEP_SLOTS + dst->index % BALANCE_SEP_SLOTS];
    if (*hint < dst->hull_plane_count) {
      const double *pl = dst->hull_planes[*hint];
      if (pl[0] * b[0] + pl[1] * b[1] + pl[2] * b[2] - pl[3] >= BALANCE_CONTACT_BAND_M) continue;
    }
    double worst = -INFINITY;
    for (size_t f = 0; f < dst->hull_plane_count; f++) {
      const double *pl = dst->hull_planes[f];
      const double s = pl[0] * b[0] + pl[1] * b[1] + pl[2] * b[2] - pl[3];
      if (s > worst) {
        worst = s;
        if (s >= BALANCE_CONTACT_BAND_M) { /* outside: no contact */
          *hint = (uint32_t)f;
          break;
        }
      }
    }
    if (!(worst < BALANCE_CONTACT_BAND_M) || -worst > BALANCE_CONTACT_MAX_DEPTH_M) continue;
    /* Of the faces the vertex is about as deep behind (a rim or corner lies on several), take the
     * one most opposed to the vertex's own outward normal: two flat faces resting on each other
     * then push along their common normal, not sideways across a rim. */
    double vn[3], vnb[3];
    for (int k = 0; k < 3; k++)
      vn[k] = rs[k][0] * src->vert_normals[i][0] + rs[k][1] * src->vert_normals[i][1] +
              rs[k][2] * src->vert_normals[i][2];
    for (int k = 0; k < 3; k++) vnb[k] = rd[0][k] * vn[0] + rd[1][k] * vn[1] + rd[2][k] * vn[2];
    size_t face = SIZE_MAX;
    double best_align = INFINITY, depth = 0.0;
    for (size_t f = 0; f < dst->hull_plane_count; f++) {
      const double *pl = dst->hull_planes[f];
      const double s = pl[0] * b[0] + pl[1] * b[1] + pl[2] * b[2] - pl[3];
      if (s < worst - BALANCE_PAIR_TIE_M) continue;
      const double align = pl[0] * vnb[0] + pl[1] * vnb[1] + pl[2] * vnb[2];
      if (align < best_align) {
        best_align = align;
        face = f;
        depth = -s;
      }
    }
    if (face == SIZE_MAX) continue;
    const double *pl = dst->hull_planes[face];
    balance_point_t *c = &out[n++];
    for (int k = 0; k < 3; k++) {
      const double nw = rd[k][0] * pl[0] + rd[k][1] * pl[1] + rd[k][2] * pl[2];
      c->normal[k] = flip ? -nw : nw;
      c->pos_m[k] = w[k];
    }
    c->depth_m = depth;
    c->edge_plane = -1;
    c->id = id_base + (uint32_t)i;
  }
  return n;
}

size_t balance_pair_contacts(const balance_object_t *a, const balance_object_t *b,
                             balance_point_t *out, size_t cap) {
  size_t n = verts_in_hull(a, b, 0, 0, out, cap, 0);
  return verts_in_hull(b, a, 1, (uint32_t)a->mesh_link.vertex_count, out, cap, n);
}
