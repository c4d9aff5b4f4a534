/* orient.c - exact orientation and cross product (orient.h), after Shewchuk's predicates.c
 * (public domain): orient3d's error bound A and orient3dexact, with bounds-checked expansion
 * loops. An expansion is a sum of doubles, nonoverlapping and in increasing magnitude, whose
 * largest component has the sign of the sum. */
#include "orient.h"

#include <float.h>
#include <math.h>

#if !defined(FLT_EVAL_METHOD) || FLT_EVAL_METHOD != 0
#error "orient.c needs double arithmetic without extended precision (FLT_EVAL_METHOD 0)"
#endif

/* x + y = a + b exactly, x = fl(a + b). */
static void two_sum(double a, double b, double *x, double *y) {
  const double s = a + b, bv = s - a, av = s - bv;
  *x = s;
  *y = (a - av) + (b - bv);
}

/* The same when |a| >= |b| (or a == 0). */
static void fast_two_sum(double a, double b, double *x, double *y) {
  const double s = a + b;
  *x = s;
  *y = b - (s - a);
}

static void two_diff(double a, double b, double *x, double *y) {
  const double d = a - b, bv = a - d, av = d + bv;
  *x = d;
  *y = (a - av) + (bv - b);
}

/* Dekker's split: a = hi + lo, each with at most 26 significant bits. */
static void split(double a, double *hi, double *lo) {
  const double c = 134217729.0 * a; /* 2^27 + 1 */
  const double big = c - a;
  *hi = c - big;
  *lo = a - *hi;
}

/* x + y = a * b exactly, x = fl(a * b). */
static void two_product(double a, double b, double *x, double *y) {
  double ahi, alo, bhi, blo;
  const double p = a * b;
  split(a, &ahi, &alo);
  split(b, &bhi, &blo);
  const double e1 = p - ahi * bhi, e2 = e1 - alo * bhi, e3 = e2 - ahi * blo;
  *x = p;
  *y = alo * blo - e3;
}

/* a * b - c * d as a 4-component expansion x[0..3]. */
static void two_two_diff_of_products(double a, double b, double c, double d, double x[4]) {
  double p1, p0, q1, q0, i, j, k;
  two_product(a, b, &p1, &p0);
  two_product(c, d, &q1, &q0);
  /* (p1 + p0) - (q1 + q0): Shewchuk's Two_Two_Diff */
  two_diff(p0, q0, &i, &x[0]);
  two_sum(p1, i, &j, &k);
  two_diff(k, q1, &i, &x[1]);
  two_sum(j, i, &x[3], &x[2]);
}

/* h = e + f (Shewchuk's fast_expansion_sum_zeroelim); h has room for elen + flen. */
static int expansion_sum(int elen, const double *e, int flen, const double *f, double *h) {
  int i = 0, j = 0, n = 0;
  double q, qn, hh;
  /* merge by magnitude, smallest first */
  if (j >= flen || (i < elen && fabs(e[i]) <= fabs(f[j])))
    q = e[i++];
  else
    q = f[j++];
  if (i < elen && j < flen) {
    if (fabs(e[i]) <= fabs(f[j]))
      fast_two_sum(e[i++], q, &qn, &hh);
    else
      fast_two_sum(f[j++], q, &qn, &hh);
    q = qn;
    if (hh != 0.0) h[n++] = hh;
    while (i < elen && j < flen) {
      if (fabs(e[i]) <= fabs(f[j]))
        two_sum(q, e[i++], &qn, &hh);
      else
        two_sum(q, f[j++], &qn, &hh);
      q = qn;
      if (hh != 0.0) h[n++] = hh;
    }
  }
  while (i < elen) {
    two_sum(q, e[i++], &qn, &hh);
    q = qn;
    if (hh != 0.0) h[n++] = hh;
  }
  while (j < flen) {
    two_sum(q, f[j++], &qn, &hh);
    q = qn;
    if (hh != 0.0) h[n++] = hh;
  }
  if (q != 0.0 || n == 0) h[n++] = q;
  return n;
}

/* h = b * e (Shewchuk's scale_expansion_zeroelim); h has room for 2 elen. */
static int expansion_scale(int elen, const double *e, double b, double *h) {
  double q, hh, p1, p0, s;
  int n = 0;
  two_product(e[0], b, &q, &hh);
  if (hh != 0.0) h[n++] = hh;
  for (int i = 1; i < elen; ++i) {
    two_product(e[i], b, &p1, &p0);
    two_sum(q, p0, &s, &hh);
    if (hh != 0.0) h[n++] = hh;
    fast_two_sum(p1, s, &q, &hh);
    if (hh != 0.0) h[n++] = hh;
  }
  if (q != 0.0 || n == 0) h[n++] = q;
  return n;
}

/* The exact det[a - d; b - d; c - d] (Shewchuk's orient3dexact): its sign. */
static int orient_exact(const double *pa, const double *pb, const double *pc, const double *pd) {
  double ab[4], bc[4], cd[4], da[4], ac[4], bd[4], t8[8];
  double abc[12], bcd[12], cda[12], dab[12];
  double adet[24], bdet[24], cdet[24], ddet[24], abdet[48], cddet[48], det[96];
  two_two_diff_of_products(pa[0], pb[1], pb[0], pa[1], ab);
  two_two_diff_of_products(pb[0], pc[1], pc[0], pb[1], bc);
  two_two_diff_of_products(pc[0], pd[1], pd[0], pc[1], cd);
  two_two_diff_of_products(pd[0], pa[1], pa[0], pd[1], da);
  two_two_diff_of_products(pa[0], pc[1], pc[0], pa[1], ac);
  two_two_diff_of_products(pb[0], pd[1], pd[0], pb[1], bd);
  int tl = expansion_sum(4, cd, 4, da, t8);
  const int cdal = expansion_sum(tl, t8, 4, ac, cda);
  tl = expansion_sum(4, da, 4, ab, t8);
  const int dabl = expansion_sum(tl, t8, 4, bd, dab);
  for (int i = 0; i < 4; ++i) {
    bd[i] = -bd[i];
    ac[i] = -ac[i];
  }
  tl = expansion_sum(4, ab, 4, bc, t8);
  const int abcl = expansion_sum(tl, t8, 4, ac, abc);
  tl = expansion_sum(4, bc, 4, cd, t8);
  const int bcdl = expansion_sum(tl, t8, 4, bd, bcd);
  const int al = expansion_scale(bcdl, bcd, pa[2], adet);
  const int bl = expansion_scale(cdal, cda, -pb[2], bdet);
  const int cl = expansion_scale(dabl, dab, pc[2], cdet);
  const int dl = expansion_scale(abcl, abc, -pd[2], ddet);
  const int abl = expansion_sum(al, adet, bl, bdet, abdet);
  const int cdl = expansion_sum(cl, cdet, dl, ddet, cddet);
  const int n = expansion_sum(abl, abdet, cdl, cddet, det);
  const double top = det[n - 1];
  return (top > 0.0) - (top < 0.0);
}

int model_orient3d(const double a[3], const double b[3], const double c[3], const double d[3]) {
  /* Shewchuk's orient3d is det[a - d; b - d; c - d] = -((b - a) x (c - a)) . (d - a). */
  const double adx = a[0] - d[0], bdx = b[0] - d[0], cdx = c[0] - d[0];
  const double ady = a[1] - d[1], bdy = b[1] - d[1], cdy = c[1] - d[1];
  const double adz = a[2] - d[2], bdz = b[2] - d[2], cdz = c[2] - d[2];
  const double bc = bdx * cdy, cb = cdx * bdy, ca = cdx * ady, ac = adx * cdy;
  const double ab = adx * bdy, ba = bdx * ady;
  const double det = adz * (bc - cb) + bdz * (ca - ac) + cdz * (ab - ba);
  const double perm = (fabs(bc) + fabs(cb)) * fabs(adz) + (fabs(ca) + fabs(ac)) * fabs(bdz) +
                      (fabs(ab) + fabs(ba)) * fabs(cdz);
  const double eps = 0.5 * DBL_EPSILON; /* 2^-53 */
  const double bound = (7.0 + 56.0 * eps) * eps * perm;
  if (det > bound) return -1;
  if (-det > bound) return 1;
  return -orient_exact(a, b, c, d);
}

/* p_i q_j - p_j q_i + q_i r_j - q_j r_i + r_i p_j - r_j p_i, exactly, then rounded. */
static double cross_component(const double *p, const double *q, const double *r, int i, int j) {
  double m0[4], m1[4], m2[4], t8[8], s[12];
  two_two_diff_of_products(p[i], q[j], p[j], q[i], m0);
  two_two_diff_of_products(q[i], r[j], q[j], r[i], m1);
  two_two_diff_of_products(r[i], p[j], r[j], p[i], m2);
  const int tl = expansion_sum(4, m0, 4, m1, t8);
  const int n = expansion_sum(tl, t8, 4, m2, s);
  double sum = 0.0;
  for (int k = 0; k < n; ++k) sum += s[k]; /* smallest first */
  return sum;
}

void model_tri_cross(const double a[3], const double b[3], const double c[3], double n[3]) {
  /* (b - a) x (c - a) = a x b + b x c + c x a */
  n[0] = cross_component(a, b, c, 1, 2);
  n[1] = cross_component(a, b, c, 2, 0);
  n[2] = cross_component(a, b, c, 0, 1);
}
