/* contact_fast.c - comlearn's mesh-on-block contact generator and the support-preserving contact
 * reduction shared by every contact path.
 *
 * Mesh-on-block: B's top is the rectangle |x| <= hx, |y| <= hy at z = 0. Contacts are
 *   - mesh vertices below the top (or within BALANCE_CONTACT_BAND_M above it) inside the
 *     footprint, and
 *   - points where mesh edges cross the vertical planes through B's top edges, below the top:
 *     where the mesh rolls over the edge line; without them a flat face pivoting on the edge
 *     would be held only by its vertices, which lie off the edge line.
 * all with normal +z. Only vertices near the top are transformed each step: the candidate set
 * (every edge with an endpoint within a band of the top, and those edges' endpoints) is rebuilt
 * after BALANCE_FAST_REBUILD_M or BALANCE_FAST_REBUILD_RAD of motion, and the band covers the most
 * any vertex can descend in between. */
#include <math.h>
#include <string.h>

#include "balance_internal.h"
#include "comlearn/math3d.h"

size_t balance_fast_capacity(const balance_object_t *o) {
  return o->mesh_link.vertex_count + 4 * o->edge_count;
}

static void rebuild(balance_fast_cache_t *fc, const balance_object_t *o, double r[3][3],
                    const double p[3], const double q[4]) {
  for (uint32_t i = 0; i < fc->vert_count; i++) fc->local[fc->verts[i]] = UINT32_MAX;
  fc->vert_count = 0;
  fc->edge_count = 0;
  /* A vertex above `band` now cannot get below the contact band before the next rebuild. */
  const double band = BALANCE_FAST_REBUILD_M + BALANCE_FAST_REBUILD_RAD * o->radius_m +
                      BALANCE_CONTACT_BAND_M + 1e-5;
  const double(*v)[3] = (const double(*)[3])o->verts_body_m;
  for (size_t e = 0; e < o->edge_count; e++) {
    const uint32_t a = o->edges[e][0], b = o->edges[e][1];
    const double za = r[2][0] * v[a][0] + r[2][1] * v[a][1] + r[2][2] * v[a][2] + p[2];
    const double zb = r[2][0] * v[b][0] + r[2][1] * v[b][1] + r[2][2] * v[b][2] + p[2];
    if (za >= band && zb >= band) continue;
    uint32_t ends[2] = {a, b};
    for (int k = 0; k < 2; k++)
      if (fc->local[ends[k]] == UINT32_MAX) {
        fc->local[ends[k]] = fc->vert_count;
        fc->verts[fc->vert_count++] = ends[k];
      }
    fc->edges[fc->edge_count][0] = fc->local[a];
    fc->edges[fc->edge_count][1] = fc->local[b];
    fc->edge_ids[fc->edge_count] = (uint32_t)e;
    fc->edge_count++;
  }
  memcpy(fc->pos_m, p, sizeof fc->pos_m);
  memcpy(fc->quat_wxyz, q, sizeof fc->quat_wxyz);
  fc->valid = 1;
}

static void push(balance_point_t *out, size_t cap, size_t *n, const double pos[3], int plane,
                 uint32_t id) {
  if (*n >= cap) return;
  balance_point_t *c = &out[(*n)++];
  c->pos_m[0] = pos[0];
  c->pos_m[1] = pos[1];
  c->pos_m[2] = pos[2];
  c->normal[0] = 0.0;
  c->normal[1] = 0.0;
  c->normal[2] = 1.0;
  c->depth_m = -pos[2];
  c->edge_plane = plane;
  c->id = id;
}

size_t balance_fast_contacts(const balance_world_t *w, balance_object_t *o, balance_point_t *out,
                             size_t cap) {
  const double hx = 0.5 * w->cfg.base_size_m[0], hy = 0.5 * w->cfg.base_size_m[1];
  const dReal *bp = dBodyGetPosition(o->body), *bq = dBodyGetQuaternion(o->body);
  const double p[3] = {bp[0], bp[1], bp[2]}, q[4] = {bq[0], bq[1], bq[2], bq[3]};
  double r[3][3];
  model_quat_to_rot(q, r);
  balance_fast_cache_t *fc = &o->fast;
  if (!fc->valid) {
    rebuild(fc, o, r, p, q);
  } else {
    const double dx = p[0] - fc->pos_m[0], dy = p[1] - fc->pos_m[1], dz = p[2] - fc->pos_m[2];
    if (dx * dx + dy * dy + dz * dz > BALANCE_FAST_REBUILD_M * BALANCE_FAST_REBUILD_M ||
        cl_quat_angle(q, fc->quat_wxyz) > BALANCE_FAST_REBUILD_RAD)
      rebuild(fc, o, r, p, q);
  }
  const double zmax = BALANCE_CONTACT_BAND_M, zmin = -BALANCE_CONTACT_MAX_DEPTH_M;
  size_t n = 0;
  /* Out-codes against the four vertical planes: an edge crosses a plane only where its ends'
   * codes differ, so most edges (both ends inside the footprint) cost one compare. */
  uint8_t *code = fc->code;
  for (uint32_t i = 0; i < fc->vert_count; i++) {
    const double *v = o->verts_body_m[fc->verts[i]];
    double *x = fc->verts_w[i];
    x[0] = r[0][0] * v[0] + r[0][1] * v[1] + r[0][2] * v[2] + p[0];
    x[1] = r[1][0] * v[0] + r[1][1] * v[1] + r[1][2] * v[2] + p[1];
    x[2] = r[2][0] * v[0] + r[2][1] * v[1] + r[2][2] * v[2] + p[2];
    code[i] = (uint8_t)((x[0] > hx) | (x[0] < -hx) << 1 | (x[1] > hy) << 2 | (x[1] < -hy) << 3);
    if (code[i] == 0 && x[2] < zmax && x[2] > zmin) push(out, cap, &n, x, -1, fc->verts[i]);
  }
  static const model_edge_t planes[4] = {MODEL_EDGE_PX, MODEL_EDGE_NX, MODEL_EDGE_PY,
                                         MODEL_EDGE_NY};
  for (uint32_t e = 0; e < fc->edge_count; e++) {
    const uint32_t ia = fc->edges[e][0], ib = fc->edges[e][1];
    const unsigned diff = (unsigned)(code[ia] ^ code[ib]);
    if (diff == 0) continue;
    const double *a = fc->verts_w[ia], *b = fc->verts_w[ib];
    if (a[2] >= zmax && b[2] >= zmax) continue;
    for (int k = 0; k < 4; k++) {
      if (!(diff & (1u << k))) continue;
      const int axis = k < 2 ? 0 : 1;
      const double plane = (k % 2 == 0) ? (axis == 0 ? hx : hy) : -(axis == 0 ? hx : hy);
      const double other = axis == 0 ? hy : hx;
      const double da = a[axis] - plane, db = b[axis] - plane;
      const double t = da / (da - db);
      double x[3];
      for (int c = 0; c < 3; c++) x[c] = a[c] + t * (b[c] - a[c]);
      if (x[2] < zmax && x[2] > zmin && fabs(x[1 - axis]) <= other)
        push(out, cap, &n, x, (int)planes[k],
             (uint32_t)(o->mesh_link.vertex_count + 4 * (size_t)fc->edge_ids[e] + (size_t)k));
    }
  }
  return n;
}

/* Recompute a previously chosen point from its id; 0 if it no longer exists. */
static int refresh_point(const balance_world_t *w, const balance_object_t *o, double r[3][3],
                         const double p[3], uint32_t id, int plane, balance_point_t *out) {
  const double hx = 0.5 * w->cfg.base_size_m[0], hy = 0.5 * w->cfg.base_size_m[1];
  const size_t nv = o->mesh_link.vertex_count;
  double x[3];
  if (plane < 0) {
    if (id >= nv) return 0;
    const double *v = o->verts_body_m[id];
    for (int c = 0; c < 3; c++) x[c] = r[c][0] * v[0] + r[c][1] * v[1] + r[c][2] * v[2] + p[c];
    if (!(fabs(x[0]) <= hx && fabs(x[1]) <= hy)) return 0;
  } else {
    if (id < nv) return 0;
    const size_t e = (id - nv) / 4;
    const int k = (int)((id - nv) % 4);
    if (e >= o->edge_count || k != plane) return 0;
    double a[3], b[3];
    const double *va = o->verts_body_m[o->edges[e][0]], *vb = o->verts_body_m[o->edges[e][1]];
    for (int c = 0; c < 3; c++) {
      a[c] = r[c][0] * va[0] + r[c][1] * va[1] + r[c][2] * va[2] + p[c];
      b[c] = r[c][0] * vb[0] + r[c][1] * vb[1] + r[c][2] * vb[2] + p[c];
    }
    const int axis = k < 2 ? 0 : 1;
    const double pl = (k % 2 == 0) ? (axis == 0 ? hx : hy) : -(axis == 0 ? hx : hy);
    const double da = a[axis] - pl, db = b[axis] - pl;
    if (!(da * db < 0.0)) return 0;
    const double t = da / (da - db);
    for (int c = 0; c < 3; c++) x[c] = a[c] + t * (b[c] - a[c]);
    if (!(fabs(x[1 - axis]) <= (axis == 0 ? hy : hx))) return 0;
  }
  if (!(x[2] < BALANCE_CONTACT_BAND_M && x[2] > -BALANCE_CONTACT_MAX_DEPTH_M)) return 0;
  size_t one = 0;
  push(out, 1, &one, x, plane, id);
  return 1;
}

size_t balance_fast_contacts_reduced(const balance_world_t *w, balance_object_t *o,
                                     balance_point_t *out, size_t cap, size_t k) {
  balance_fast_cache_t *fc = &o->fast;
  const dReal *bp = dBodyGetPosition(o->body), *bq = dBodyGetQuaternion(o->body);
  const double p[3] = {bp[0], bp[1], bp[2]}, q[4] = {bq[0], bq[1], bq[2], bq[3]};
  if (fc->valid && fc->sel_valid) {
    const double dx = p[0] - fc->sel_pos_m[0], dy = p[1] - fc->sel_pos_m[1],
                 dz = p[2] - fc->sel_pos_m[2];
    const double moved =
        sqrt(dx * dx + dy * dy + dz * dz) + cl_quat_angle(q, fc->sel_quat_wxyz) * o->radius_m;
    if (moved < BALANCE_FAST_RESELECT_M && fc->sel_count <= cap) {
      double r[3][3];
      model_quat_to_rot(q, r);
      size_t n = 0;
      for (size_t i = 0; i < fc->sel_count; i++)
        if (refresh_point(w, o, r, p, fc->sel_id[i], fc->sel_plane[i], &out[n])) n++;
      if (n == fc->sel_count) return n;
    }
  }
  size_t n = balance_fast_contacts(w, o, out, cap);
  n = balance_points_reduce(out, n, k);
  fc->sel_count = n < 64 ? n : 64;
  for (size_t i = 0; i < fc->sel_count; i++) {
    fc->sel_id[i] = out[i].id;
    fc->sel_plane[i] = out[i].edge_plane;
  }
  memcpy(fc->sel_pos_m, p, sizeof fc->sel_pos_m);
  memcpy(fc->sel_quat_wxyz, q, sizeof fc->sel_quat_wxyz);
  fc->sel_valid = 1;
  return n;
}

/* The 17 reduction keys of a point (larger is better): 0-7 the low and high end along each of the
 * four edge lines (only for points on that line), 8 the depth, 9-16 eight directions in the
 * contact plane. valid gets a bit per key the point takes part in. */
enum { NKEYS = 17 };

static inline void point_keys(const balance_point_t *p, const double t1[3], const double t2[3],
                              double key[NKEYS], uint32_t *valid) {
  const double s = 0.7071067811865476;
  const double a = t1[0] * p->pos_m[0] + t1[1] * p->pos_m[1] + t1[2] * p->pos_m[2];
  const double b = t2[0] * p->pos_m[0] + t2[1] * p->pos_m[1] + t2[2] * p->pos_m[2];
  *valid = 0x1ff00u;
  if (p->edge_plane >= 0 && p->edge_plane < 4) {
    const int pl = p->edge_plane, along = pl < 2 ? 1 : 0;
    key[2 * pl] = -p->pos_m[along];
    key[2 * pl + 1] = p->pos_m[along];
    *valid |= 3u << (2 * pl);
  }
  key[8] = p->depth_m;
  key[9] = a;
  key[10] = -a;
  key[11] = b;
  key[12] = -b;
  key[13] = s * (a + b);
  key[14] = -s * (a + b);
  key[15] = s * (a - b);
  key[16] = -s * (a - b);
}

size_t balance_points_reduce(balance_point_t *p, size_t n, size_t k) {
  if (n <= k) return n;
  if (k > 64) k = 64;
  /* The plane of the contacts: perpendicular to their mean normal. */
  double nm[3] = {0.0, 0.0, 0.0};
  for (size_t i = 0; i < n; i++)
    for (int c = 0; c < 3; c++) nm[c] += p[i].normal[c];
  double len = sqrt(nm[0] * nm[0] + nm[1] * nm[1] + nm[2] * nm[2]);
  if (!(len > 1e-9)) {
    nm[0] = 0.0;
    nm[1] = 0.0;
    nm[2] = 1.0;
    len = 1.0;
  }
  for (int c = 0; c < 3; c++) nm[c] /= len;
  double t1[3], t2[3];
  if (fabs(nm[2]) < 0.9) {
    t1[0] = -nm[1];
    t1[1] = nm[0];
    t1[2] = 0.0;
  } else {
    t1[0] = 0.0;
    t1[1] = -nm[2];
    t1[2] = nm[1];
  }
  len = sqrt(t1[0] * t1[0] + t1[1] * t1[1] + t1[2] * t1[2]);
  for (int c = 0; c < 3; c++) t1[c] /= len;
  t2[0] = nm[1] * t1[2] - nm[2] * t1[1];
  t2[1] = nm[2] * t1[0] - nm[0] * t1[2];
  t2[2] = nm[0] * t1[1] - nm[1] * t1[0];

  /* Two passes: the extremes among the points that touch (depth >= 0) first, then among all,
   * the speculative ones of the band included, into the slots left. A speculative point kept as
   * the extreme of a support that has a touching point nearby lets the body rock onto it (a
   * neighbour facet's edge crossing 0.9 um above B's top, kept as a chord's end while the facet's
   * own end 0.18 mm short of it was dropped: a tilted block tipped 28-43 um early; docs/
   * physics.md). In each pass a key within BALANCE_REDUCE_TIE_M of the best so far counts as a
   * tie and goes to the lower id. On a flat face every point is about as deep: a choice by
   * rounding would flip from step to step and rock the body. */
  size_t kept[64]; /* indices into p */
  size_t m = 0;
  int speculative = 0; /* pass 0 skipped a point: pass 1 has more to choose from */
  for (int pass = 0; pass < 2 && m < k && (pass == 0 || speculative); pass++) {
    double best[NKEYS], key[NKEYS];
    size_t pick[NKEYS];
    uint32_t pick_id[NKEYS];
    for (int j = 0; j < NKEYS; j++) {
      best[j] = -INFINITY;
      pick[j] = SIZE_MAX;
      pick_id[j] = UINT32_MAX;
    }
    for (size_t i = 0; i < n; i++) {
      if (pass == 0 && !(p[i].depth_m >= 0.0)) {
        speculative = 1;
        continue;
      }
      uint32_t valid;
      point_keys(&p[i], t1, t2, key, &valid);
      const uint32_t id = p[i].id;
      for (int j = valid & 0xffu ? 0 : 8; j < NKEYS; j++) {
        if (!(valid >> j & 1u)) continue;
        const double kj = key[j];
        int take = kj > best[j] + BALANCE_REDUCE_TIE_M;
        if (!take && kj >= best[j] - BALANCE_REDUCE_TIE_M) { /* a tie: deeper, then lower id */
          const double dd = p[i].depth_m - p[pick[j]].depth_m;
          take = dd > BALANCE_REDUCE_DEPTH_TIE_M ||
                 (dd >= -BALANCE_REDUCE_DEPTH_TIE_M && id < pick_id[j]);
        }
        if (take) {
          pick[j] = i;
          pick_id[j] = id;
        }
        if (kj > best[j]) best[j] = kj;
      }
    }
    for (int j = 0; j < NKEYS && m < k; j++) {
      if (pick[j] == SIZE_MAX) continue;
      int dup = 0;
      for (size_t q = 0; q < m; q++) dup |= kept[q] == pick[j];
      if (!dup) kept[m++] = pick[j];
    }
  }
  balance_point_t out[64];
  for (size_t i = 0; i < m; i++) out[i] = p[kept[i]];
  for (size_t i = 0; i < m; i++) p[i] = out[i];
  return m;
}
