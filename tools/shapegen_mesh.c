/* shapegen_mesh.c - the constructions: tessellated box, slab height field, solid of revolution
 * with a handle tube; the growable mesh and the deterministic cos / sin. */
#include "shapegen_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define NONE UINT32_MAX

/* ---- growable mesh --------------------------------------------------------------------------- */

void sg_build_init(sg_build_t *b) { memset(b, 0, sizeof *b); }

void sg_build_free(sg_build_t *b) {
  free(b->v);
  free(b->t);
  memset(b, 0, sizeof *b);
}

static int grow(void **arr, size_t *cap, size_t need, size_t elem) {
  if (need <= *cap) return 1;
  size_t c = *cap > 0 ? *cap : 256;
  while (c < need) c *= 2;
  void *p = realloc(*arr, c * elem);
  if (p == NULL) return 0;
  *arr = p;
  *cap = c;
  return 1;
}

uint32_t sg_vert(sg_build_t *b, double x, double y, double z) {
  if (b->nomem || b->nv >= NONE || !grow((void **)&b->v, &b->cap_v, b->nv + 1, sizeof *b->v)) {
    b->nomem = 1;
    return 0;
  }
  /* + 0.0 turns -0.0 into +0.0: one bit pattern per position. */
  b->v[b->nv][0] = x + 0.0;
  b->v[b->nv][1] = y + 0.0;
  b->v[b->nv][2] = z + 0.0;
  return (uint32_t)b->nv++;
}

void sg_tri(sg_build_t *b, uint32_t a, uint32_t c, uint32_t d) {
  if (b->nomem || !grow((void **)&b->t, &b->cap_t, b->nt + 1, sizeof *b->t)) {
    b->nomem = 1;
    return;
  }
  b->t[b->nt][0] = a;
  b->t[b->nt][1] = c;
  b->t[b->nt][2] = d;
  ++b->nt;
}

void sg_quad(sg_build_t *b, uint32_t a, uint32_t c, uint32_t d, uint32_t e) {
  sg_tri(b, a, c, d);
  sg_tri(b, a, d, e);
}

double sg_to_float32(double x) {
  volatile float f = (float)x;
  return (double)f;
}

model_status_t sg_build_finish(sg_build_t *b, model_mesh_t *out) {
  memset(out, 0, sizeof *out);
  if (b->nomem) {
    sg_build_free(b);
    return MODEL_E_NOMEM;
  }
  if (b->nv == 0 || b->nt == 0) {
    sg_build_free(b);
    return MODEL_E_DEGENERATE;
  }
  double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (size_t i = 0; i < b->nv; ++i) {
    for (int k = 0; k < 3; ++k) {
      if (b->v[i][k] < lo[k]) lo[k] = b->v[i][k];
      if (b->v[i][k] > hi[k]) hi[k] = b->v[i][k];
    }
  }
  double center[3];
  for (int k = 0; k < 3; ++k) center[k] = 0.5 * (lo[k] + hi[k]);
  for (size_t i = 0; i < b->nv; ++i) {
    for (int k = 0; k < 3; ++k) b->v[i][k] = sg_to_float32(b->v[i][k] - center[k]) + 0.0;
  }
  out->vertices_m = b->v;
  out->triangles = b->t;
  out->vertex_count = b->nv;
  out->triangle_count = b->nt;
  memset(b, 0, sizeof *b);
  return MODEL_OK;
}

/* ---- random numbers and angles --------------------------------------------------------------- */

void shapegen_cos_sin_turn(long j, long n, double *c, double *s) {
  if (n <= 0) {
    *c = 1.0;
    *s = 0.0;
    return;
  }
  long long m = (long long)(j % n);
  if (m < 0) m += n;
  /* nearest quarter turn q (ties to even, so that j and n - j are exact mirror images),
   * remainder x = (pi / 2) r / n with |r| <= n / 2 */
  long long q = (8 * m + n) / (2 * (long long)n);
  if ((8 * m + n) % (2 * (long long)n) == 0 && (q & 1)) --q;
  const long long r = 4 * m - q * n;
  const double x = (double)r * (0.5 * CL_PI) / (double)n;
  const double x2 = x * x;
  double cc = 1.0, ss = 1.0;
  for (int k = 10; k >= 1; --k) {
    cc = 1.0 - x2 * cc / (double)((2 * k) * (2 * k - 1));
    ss = 1.0 - x2 * ss / (double)((2 * k + 1) * (2 * k));
  }
  ss *= x;
  switch (q % 4) {
    case 0:
      *c = cc;
      *s = ss;
      break;
    case 1:
      *c = -ss;
      *s = cc;
      break;
    case 2:
      *c = -cc;
      *s = -ss;
      break;
    default:
      *c = ss;
      *s = -cc;
      break;
  }
  *c += 0.0;
  *s += 0.0;
}

/* ---- box ------------------------------------------------------------------------------------- */

model_status_t sg_box_build(const shapegen_box_t *box, sg_build_t *b) {
  unsigned n[3];
  for (int k = 0; k < 3; ++k) {
    n[k] = box->cells[k];
    if (n[k] < 1 || n[k] > 1024 || !(box->size_m[k] > 0.0) || !isfinite(box->size_m[k]))
      return MODEL_E_ARG;
  }
  const size_t dim = (size_t)(n[0] + 1) * (n[1] + 1) * (n[2] + 1);
  uint32_t *idx = malloc(dim * sizeof *idx);
  if (idx == NULL) return MODEL_E_NOMEM;
  for (size_t i = 0; i < dim; ++i) idx[i] = NONE;
  for (int a = 0; a < 3; ++a) {
    const int u = (a + 1) % 3, v = (a + 2) % 3; /* (u, v, a) right-handed */
    for (int side = 0; side < 2; ++side) {
      for (unsigned cu = 0; cu < n[u]; ++cu) {
        for (unsigned cv = 0; cv < n[v]; ++cv) {
          uint32_t p[4];
          static const unsigned du[4] = {0, 1, 1, 0}, dv[4] = {0, 0, 1, 1};
          for (int q = 0; q < 4; ++q) {
            unsigned c[3];
            c[a] = side ? n[a] : 0;
            c[u] = cu + du[q];
            c[v] = cv + dv[q];
            const size_t at = ((size_t)c[2] * (n[1] + 1) + c[1]) * (n[0] + 1) + c[0];
            if (idx[at] == NONE) {
              double x[3];
              for (int k = 0; k < 3; ++k) {
                const double h = 0.5 * box->size_m[k];
                x[k] = -h + 2.0 * h * (double)c[k] / (double)n[k];
              }
              idx[at] = sg_vert(b, x[0], x[1], x[2]);
            }
            p[q] = idx[at];
          }
          if (side) {
            sg_quad(b, p[0], p[1], p[2], p[3]); /* seen from +a: counter-clockwise in (u, v) */
          } else {
            sg_quad(b, p[0], p[3], p[2], p[1]);
          }
        }
      }
    }
  }
  free(idx);
  return MODEL_OK;
}

/* ---- slab ------------------------------------------------------------------------------------ */

double sg_slab_bottom(const shapegen_slab_t *s, size_t i, size_t j) {
  double z = s->bottom_m[0][i] + s->bottom_m[1][j];
  if (s->foot_count == 0) return z;
  const double x = s->lines_m[0][i], y = s->lines_m[1][j];
  double d = HUGE_VAL;
  for (size_t f = 0; f < s->foot_count; ++f) {
    const shapegen_foot_t *ft = &s->feet[f];
    const double ex = x - ft->center_m[0], ey = y - ft->center_m[1];
    double df;
    if (ft->round) {
      df = sqrt(ex * ex + ey * ey) - ft->half_m[0];
      if (df < 0.0) df = 0.0;
    } else {
      double dx = fabs(ex) - ft->half_m[0], dy = fabs(ey) - ft->half_m[1];
      if (dx < 0.0) dx = 0.0;
      if (dy < 0.0) dy = 0.0;
      df = dx > dy ? dx : dy;
    }
    if (df < d) d = df;
  }
  const double w = d / s->slope_m;
  return z + s->clearance_m * (w < 1.0 ? w : 1.0);
}

static int slab_valid(const shapegen_slab_t *s) {
  for (int a = 0; a < 2; ++a) {
    const size_t n = s->line_count[a];
    if (n < 2 || n > SHAPEGEN_MAX_LINES || !(s->half_m[a] > 0.0)) return 0;
    if (s->lines_m[a][0] != -s->half_m[a] || s->lines_m[a][n - 1] != s->half_m[a]) return 0;
    for (size_t i = 0; i < n; ++i) {
      if (!isfinite(s->lines_m[a][i]) || !isfinite(s->bottom_m[a][i]) || !isfinite(s->top_m[a][i]))
        return 0;
      if (i > 0 && !(s->lines_m[a][i] > s->lines_m[a][i - 1])) return 0;
    }
  }
  if (s->foot_count > SHAPEGEN_MAX_FEET) return 0;
  if (s->foot_count > 0 && !(s->slope_m > 0.0 && s->clearance_m >= 0.0)) return 0;
  for (size_t i = 0; i < s->line_count[0]; ++i) {
    for (size_t j = 0; j < s->line_count[1]; ++j) {
      const double t = s->top0_m + s->top_m[0][i] + s->top_m[1][j];
      if (!(t > sg_slab_bottom(s, i, j))) return 0;
    }
  }
  return 1;
}

model_status_t sg_slab_build(const shapegen_slab_t *s, sg_build_t *b) {
  if (!slab_valid(s)) return MODEL_E_ARG;
  const size_t nx = s->line_count[0], ny = s->line_count[1];
  const uint32_t base_bot = (uint32_t)b->nv, base_top = (uint32_t)(b->nv + nx * ny);
#define BOT(i, j) (base_bot + (uint32_t)((j)*nx + (i)))
#define TOP(i, j) (base_top + (uint32_t)((j)*nx + (i)))
  for (size_t j = 0; j < ny; ++j) {
    for (size_t i = 0; i < nx; ++i) {
      (void)sg_vert(b, s->lines_m[0][i], s->lines_m[1][j], sg_slab_bottom(s, i, j));
    }
  }
  for (size_t j = 0; j < ny; ++j) {
    for (size_t i = 0; i < nx; ++i) {
      (void)sg_vert(b, s->lines_m[0][i], s->lines_m[1][j],
                    s->top0_m + s->top_m[0][i] + s->top_m[1][j]);
    }
  }
  if (b->nomem) return MODEL_E_NOMEM; /* the heights are read back below */
  for (size_t j = 0; j + 1 < ny; ++j) {
    for (size_t i = 0; i + 1 < nx; ++i) {
      /* bottom, seen from below: P00 P01 P11 P10; the diagonal with the lower midpoint */
      const double b00 = b->v[BOT(i, j)][2], b10 = b->v[BOT(i + 1, j)][2],
                   b11 = b->v[BOT(i + 1, j + 1)][2], b01 = b->v[BOT(i, j + 1)][2];
      if (b00 + b11 <= b10 + b01) {
        sg_tri(b, BOT(i, j), BOT(i, j + 1), BOT(i + 1, j + 1));
        sg_tri(b, BOT(i, j), BOT(i + 1, j + 1), BOT(i + 1, j));
      } else {
        sg_tri(b, BOT(i, j), BOT(i, j + 1), BOT(i + 1, j));
        sg_tri(b, BOT(i + 1, j), BOT(i, j + 1), BOT(i + 1, j + 1));
      }
      /* top, seen from above: P00 P10 P11 P01; the diagonal with the higher midpoint */
      const double t00 = b->v[TOP(i, j)][2], t10 = b->v[TOP(i + 1, j)][2],
                   t11 = b->v[TOP(i + 1, j + 1)][2], t01 = b->v[TOP(i, j + 1)][2];
      if (t00 + t11 >= t10 + t01) {
        sg_tri(b, TOP(i, j), TOP(i + 1, j), TOP(i + 1, j + 1));
        sg_tri(b, TOP(i, j), TOP(i + 1, j + 1), TOP(i, j + 1));
      } else {
        sg_tri(b, TOP(i, j), TOP(i + 1, j), TOP(i, j + 1));
        sg_tri(b, TOP(i + 1, j), TOP(i + 1, j + 1), TOP(i, j + 1));
      }
    }
  }
  /* walls along the outline, counter-clockwise seen from above: p -> q, quad (pb, qb, qt, pt) */
  for (size_t i = 0; i + 1 < nx; ++i)
    sg_quad(b, BOT(i, 0), BOT(i + 1, 0), TOP(i + 1, 0), TOP(i, 0));
  for (size_t j = 0; j + 1 < ny; ++j) {
    sg_quad(b, BOT(nx - 1, j), BOT(nx - 1, j + 1), TOP(nx - 1, j + 1), TOP(nx - 1, j));
  }
  for (size_t i = nx - 1; i > 0; --i) {
    sg_quad(b, BOT(i, ny - 1), BOT(i - 1, ny - 1), TOP(i - 1, ny - 1), TOP(i, ny - 1));
  }
  for (size_t j = ny - 1; j > 0; --j)
    sg_quad(b, BOT(0, j), BOT(0, j - 1), TOP(0, j - 1), TOP(0, j));
#undef BOT
#undef TOP
  return MODEL_OK;
}

/* ---- solid of revolution and the handle ---------------------------------------------------- */

typedef struct {
  const shapegen_revolve_t *rev;
  sg_build_t *b;
  uint32_t *idx;  /* point_count x segments, created when first used */
  uint32_t *pole; /* per profile point on the axis */
  double *cs;     /* cos, sin per segment */
} revolve_t;

static uint32_t rv_vertex(revolve_t *r, size_t i, size_t j) {
  const size_t n = r->rev->segments;
  const double *p = r->rev->rz_m[i];
  if (p[0] == 0.0) {
    if (r->pole[i] == NONE) r->pole[i] = sg_vert(r->b, 0.0, 0.0, p[1]);
    return r->pole[i];
  }
  j %= n;
  uint32_t *at = &r->idx[i * n + j];
  if (*at == NONE) *at = sg_vert(r->b, p[0] * r->cs[2 * j], p[0] * r->cs[2 * j + 1], p[1]);
  return *at;
}

static int in_hole(const shapegen_handle_t *h, unsigned n, size_t i, size_t j) {
  if (h == NULL || !h->present) return 0;
  const int row = (i >= h->upper_row && i < h->upper_row + h->rows) ||
                  (i >= h->lower_row && i < h->lower_row + h->rows);
  return row && (j < h->columns || j >= n - h->columns);
}

static int handle_valid(const shapegen_revolve_t *rev, const shapegen_handle_t *h) {
  const size_t p = rev->point_count;
  if (h->rows < 1 || h->columns < 1 || 2 * h->columns >= rev->segments || h->loops < 2) return 0;
  if (h->lower_row + h->rows >= h->upper_row || h->upper_row + h->rows >= p) return 0;
  if (!(h->reach_m > 0.0) || !(h->half_height_m > 0.0) || !(h->radius_m > 0.0)) return 0;
  /* both holes on the wall, mirror images of each other about center_z */
  for (size_t m = 0; m <= h->rows; ++m) {
    const double *up = rev->rz_m[h->upper_row + m], *lo = rev->rz_m[h->lower_row + h->rows - m];
    if (up[0] != h->radius_m || lo[0] != h->radius_m) return 0;
    if (fabs((up[1] - h->center_z_m) + (lo[1] - h->center_z_m)) > 1e-12) return 0;
  }
  return 1;
}

/* One loop of the tube at path parameter m (1 .. loops-1), from the upper hole's loop (local
 * coordinates u along +y, v along +z about the hole center). */
static void tube_loop(revolve_t *r, const shapegen_handle_t *h, const double (*uv)[2], size_t len,
                      double a, double bh, unsigned m, uint32_t *out) {
  double cp, sp;
  shapegen_cos_sin_turn((long)h->loops - 2 * (long)m, 4 * (long)h->loops, &cp, &sp);
  const double px = h->radius_m + h->reach_m * cp, pz = h->center_z_m + h->half_height_m * sp;
  double tx = h->reach_m * sp, tz = -h->half_height_m * cp; /* direction of travel */
  const double tl = sqrt(tx * tx + tz * tz);
  tx /= tl;
  tz /= tl;
  const double nx = -tz, nz = tx; /* N = T x y */
  const double f = (double)m / (double)h->loops, beta = 4.0 * f * (1.0 - f);
  for (size_t l = 0; l < len; ++l) {
    const double u = uv[l][0], v = uv[l][1];
    const double e = 1.0 / sqrt((u / a) * (u / a) + (v / bh) * (v / bh));
    const double uu = (1.0 - beta) * u + beta * e * u, vv = (1.0 - beta) * v + beta * e * v;
    out[l] = sg_vert(r->b, px + vv * nx, uu, pz + vv * nz);
  }
}

static model_status_t handle_build(revolve_t *r, const shapegen_handle_t *h) {
  const unsigned n = r->rev->segments;
  const size_t k = h->columns, q = h->rows, len = 4 * k + 2 * q;
  const size_t i0 = h->upper_row, i1 = h->upper_row + q;
  size_t(*ij)[2] = malloc(len * sizeof *ij);
  double(*uv)[2] = malloc(len * sizeof *uv);
  uint32_t *loops = malloc((h->loops + 1) * len * sizeof *loops);
  if (ij == NULL || uv == NULL || loops == NULL) {
    free(ij);
    free(uv);
    free(loops);
    return MODEL_E_NOMEM;
  }
  /* the upper hole's boundary, counter-clockwise in (u, v) seen from outside */
  size_t l = 0;
  for (size_t c = 0; c < 2 * k; ++c, ++l) ij[l][0] = i0, ij[l][1] = (n - k + c) % n;
  for (size_t i = i0; i < i1; ++i, ++l) ij[l][0] = i, ij[l][1] = k;
  for (size_t c = 0; c < 2 * k; ++c, ++l) ij[l][0] = i1, ij[l][1] = (k + n - c) % n;
  for (size_t i = i1; i > i0; --i, ++l) ij[l][0] = i, ij[l][1] = n - k;
  const double zu = 0.5 * (r->rev->rz_m[i0][1] + r->rev->rz_m[i1][1]);
  for (l = 0; l < len; ++l) {
    uv[l][0] = h->radius_m * r->cs[2 * ij[l][1] + 1];
    uv[l][1] = r->rev->rz_m[ij[l][0]][1] - zu;
    loops[l] = rv_vertex(r, ij[l][0], ij[l][1]);
    /* the lower hole: the same column, mirrored row */
    loops[h->loops * len + l] = rv_vertex(r, h->lower_row + q - (ij[l][0] - i0), ij[l][1]);
  }
  const double a = h->radius_m * r->cs[2 * k + 1];
  const double bh = 0.5 * (r->rev->rz_m[i1][1] - r->rev->rz_m[i0][1]);
  for (unsigned m = 1; m < h->loops; ++m) {
    tube_loop(r, h, (const double(*)[2])uv, len, a, bh, m, loops + m * len);
  }
  for (unsigned m = 0; m < h->loops; ++m) {
    const uint32_t *p = loops + m * len, *s = loops + (m + 1) * len;
    for (l = 0; l < len; ++l) {
      const size_t l1 = (l + 1) % len;
      sg_quad(r->b, p[l], p[l1], s[l1], s[l]);
    }
  }
  free(ij);
  free(uv);
  free(loops);
  return MODEL_OK;
}

static int revolve_valid(const shapegen_revolve_t *rev) {
  const size_t p = rev->point_count;
  if (p < 3 || p > SHAPEGEN_MAX_PROFILE || rev->segments < 3 || rev->segments > 4096) return 0;
  double area2 = 0.0;
  for (size_t i = 0; i < p; ++i) {
    const double *a = rev->rz_m[i], *c = rev->rz_m[(i + 1) % p];
    if (!isfinite(a[0]) || !isfinite(a[1]) || a[0] < 0.0) return 0;
    if (a[0] == c[0] && a[1] == c[1]) return 0;
    area2 += a[0] * c[1] - c[0] * a[1];
  }
  return area2 > 0.0;
}

model_status_t sg_revolve_build(const shapegen_revolve_t *rev, const shapegen_handle_t *h,
                                sg_build_t *b) {
  if (!revolve_valid(rev) || (h != NULL && h->present && !handle_valid(rev, h))) return MODEL_E_ARG;
  const size_t p = rev->point_count, n = rev->segments;
  revolve_t r = {rev, b, malloc(p * n * sizeof(uint32_t)), malloc(p * sizeof(uint32_t)),
                 malloc(2 * n * sizeof(double))};
  if (r.idx == NULL || r.pole == NULL || r.cs == NULL) {
    free(r.idx);
    free(r.pole);
    free(r.cs);
    return MODEL_E_NOMEM;
  }
  for (size_t i = 0; i < p * n; ++i) r.idx[i] = NONE;
  for (size_t i = 0; i < p; ++i) r.pole[i] = NONE;
  for (size_t j = 0; j < n; ++j)
    shapegen_cos_sin_turn((long)j, (long)n, &r.cs[2 * j], &r.cs[2 * j + 1]);
  for (size_t i = 0; i < p; ++i) {
    const size_t i2 = (i + 1) % p;
    const int axis_a = rev->rz_m[i][0] == 0.0, axis_b = rev->rz_m[i2][0] == 0.0;
    if (axis_a && axis_b) continue; /* an edge along the axis sweeps nothing */
    for (size_t j = 0; j < n; ++j) {
      if (in_hole(h, (unsigned)n, i, j)) continue;
      const size_t j2 = (j + 1) % n;
      if (axis_a) {
        sg_tri(b, rv_vertex(&r, i, 0), rv_vertex(&r, i2, j2), rv_vertex(&r, i2, j));
      } else if (axis_b) {
        sg_tri(b, rv_vertex(&r, i, j), rv_vertex(&r, i, j2), rv_vertex(&r, i2, 0));
      } else {
        sg_quad(b, rv_vertex(&r, i, j), rv_vertex(&r, i, j2), rv_vertex(&r, i2, j2),
                rv_vertex(&r, i2, j));
      }
    }
  }
  model_status_t st = MODEL_OK;
  if (h != NULL && h->present) st = handle_build(&r, h);
  free(r.idx);
  free(r.pole);
  free(r.cs);
  return st;
}
