/* Planar convex polygons: the support polygons and resting patches of lib/balance and the rock
 * tools (comlearn/model.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "comlearn/model.h"
#include "model_internal.h"

static double cross2(const double o[2], const double a[2], const double b[2]) {
  return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

/* ---- hull: heapsort by (x, y), in place and without allocating (qsort may call malloc) ------ */

static int xy_less(const double a[2], const double b[2]) {
  return a[0] < b[0] || (a[0] == b[0] && a[1] < b[1]);
}

static void xy_swap(double a[2], double b[2]) {
  const double t0 = a[0], t1 = a[1];
  a[0] = b[0];
  a[1] = b[1];
  b[0] = t0;
  b[1] = t1;
}

static void sift_down(double (*p)[2], size_t root, size_t n) {
  for (size_t child; (child = 2 * root + 1) < n; root = child) {
    if (child + 1 < n && xy_less(p[child], p[child + 1])) ++child;
    if (!xy_less(p[root], p[child])) return;
    xy_swap(p[root], p[child]);
  }
}

static void xy_sort(double (*p)[2], size_t n) {
  for (size_t i = n / 2; i-- > 0;) sift_down(p, i, n);
  for (size_t end = n; end-- > 1;) {
    xy_swap(p[0], p[end]);
    sift_down(p, 0, end);
  }
}

/* o -> a -> b turns left, by more than asin(sin_tol) when sin_tol > 0. */
static int turns_left(const double o[2], const double a[2], const double b[2], double sin_tol) {
  const double ax = a[0] - o[0], ay = a[1] - o[1], bx = b[0] - o[0], by = b[1] - o[1];
  const double c = ax * by - ay * bx;
  return c > 0.0 &&
         (sin_tol <= 0.0 || c * c > sin_tol * sin_tol * (ax * ax + ay * ay) * (bx * bx + by * by));
}

/* Andrew's monotone chain on sorted points. */
static size_t chain(const double (*pts)[2], size_t n, double (*hull)[2], double sin_tol) {
  if (n < 3) {
    memcpy(hull, pts, n * sizeof *pts);
    return n;
  }
  size_t k = 0;
  for (size_t i = 0; i < n; ++i) {
    while (k >= 2 && !turns_left(hull[k - 2], hull[k - 1], pts[i], sin_tol)) --k;
    memcpy(hull[k++], pts[i], sizeof *pts);
  }
  const size_t lower = k + 1;
  for (size_t i = n - 1; i-- > 0;) {
    while (k >= lower && !turns_left(hull[k - 2], hull[k - 1], pts[i], sin_tol)) --k;
    memcpy(hull[k++], pts[i], sizeof *pts);
  }
  return k - 1; /* the last point repeats the first */
}

size_t model_polygon_hull(double (*pts)[2], size_t n, double (*hull)[2]) {
  xy_sort(pts, n);
  return chain((const double(*)[2])pts, n, hull, 0.0);
}

size_t model_polygon_hull_tol(double (*pts)[2], size_t n, double (*hull)[2], double sin_tol) {
  xy_sort(pts, n);
  size_t m = 0;
  for (size_t i = 0; i < n; ++i) /* duplicates out first: a hull of 2 equal points is 1 point */
    if (m == 0 || pts[i][0] != pts[m - 1][0] || pts[i][1] != pts[m - 1][1]) {
      pts[m][0] = pts[i][0];
      pts[m++][1] = pts[i][1];
    }
  return chain((const double(*)[2])pts, m, hull, sin_tol);
}

double model_polygon_area(const double (*poly)[2], size_t n) {
  if (n < 3) return 0.0;
  double a = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double *p = poly[i], *q = poly[(i + 1) % n];
    a += p[0] * q[1] - p[1] * q[0];
  }
  return 0.5 * a;
}

double model_polygon_width(const double (*poly)[2], size_t n) {
  /* The smallest width of a convex polygon is attained with one side flush (rotating calipers);
   * brute force over sides is O(n^2), fine for a few hundred vertices. */
  if (n < 3) return 0.0;
  double w = HUGE_VAL;
  for (size_t i = 0; i < n; ++i) {
    const double *a = poly[i], *b = poly[(i + 1) % n];
    const double len = hypot(b[0] - a[0], b[1] - a[1]);
    double far = 0.0;
    for (size_t j = 0; j < n; ++j) {
      const double d = cross2(a, b, poly[j]) / len;
      if (d > far) far = d;
    }
    if (far < w) w = far;
  }
  return w;
}

double model_polygon_margin(const double (*poly)[2], size_t n, const double p[2]) {
  if (n < 3) return -HUGE_VAL;
  double inside = HUGE_VAL; /* min over sides of the signed distance (valid inside) */
  double outside = 0.0;     /* distance to the polygon when p is outside */
  int out = 0;
  for (size_t i = 0; i < n; ++i) {
    const double *a = poly[i], *b = poly[(i + 1) % n];
    const double ex = b[0] - a[0], ey = b[1] - a[1];
    const double len = hypot(ex, ey);
    const double d = cross2(a, b, p) / len;
    if (d < inside) inside = d;
    if (d < 0.0) out = 1;
  }
  if (!out) return inside;
  /* Outside: the distance to the nearest side segment, negated. */
  outside = HUGE_VAL;
  for (size_t i = 0; i < n; ++i) {
    const double *a = poly[i], *b = poly[(i + 1) % n];
    const double ex = b[0] - a[0], ey = b[1] - a[1];
    double s = ((p[0] - a[0]) * ex + (p[1] - a[1]) * ey) / (ex * ex + ey * ey);
    if (s < 0.0) s = 0.0;
    if (s > 1.0) s = 1.0;
    const double dist = hypot(p[0] - (a[0] + s * ex), p[1] - (a[1] + s * ey));
    if (dist < outside) outside = dist;
  }
  return -outside;
}

void model_plane_basis(const double n[3], double u[3], double v[3]) {
  /* u: the axis least aligned with n, made orthogonal to it; v = n x u. */
  int m = 0;
  for (int k = 1; k < 3; ++k) {
    if (fabs(n[k]) < fabs(n[m])) m = k;
  }
  double e[3] = {0.0, 0.0, 0.0};
  e[m] = 1.0;
  const double en = e[0] * n[0] + e[1] * n[1] + e[2] * n[2];
  for (int k = 0; k < 3; ++k) u[k] = e[k] - en * n[k];
  const double ul = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
  for (int k = 0; k < 3; ++k) u[k] /= ul;
  v[0] = n[1] * u[2] - n[2] * u[1];
  v[1] = n[2] * u[0] - n[0] * u[2];
  v[2] = n[0] * u[1] - n[1] * u[0];
}
