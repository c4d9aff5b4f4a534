/* 3-D CoM solve: weighted least squares over threshold planes (comlearn/qlearn_solve.h). */
#include <math.h>
#include <stddef.h>

#include "comlearn/qlearn_solve.h"

qlearn_status_t qlearn_solve_init(qlearn_solve_t *solve) {
  if (solve == NULL) return QLEARN_E_ARG;
  solve->count = 0;
  for (int i = 0; i < QLEARN_SOLVE_MAX_PLANES; ++i) {
    qlearn_solve_plane_t *p = &solve->plane[i];
    p->n_obj[0] = p->n_obj[1] = p->n_obj[2] = 0.0;
    p->d_m = 0.0;
    p->sigma_m = 0.0;
  }
  return QLEARN_OK;
}

qlearn_status_t qlearn_solve_add_plane(qlearn_solve_t *solve, const double n_obj[3], double d_m,
                                       double sigma_m) {
  if (solve == NULL || n_obj == NULL) return QLEARN_E_ARG;
  if (!isfinite(n_obj[0]) || !isfinite(n_obj[1]) || !isfinite(n_obj[2]) || !isfinite(d_m) ||
      !isfinite(sigma_m)) {
    return QLEARN_E_NONFINITE;
  }
  double len = sqrt(n_obj[0] * n_obj[0] + n_obj[1] * n_obj[1] + n_obj[2] * n_obj[2]);
  if (!(len > 0.0) || !isfinite(len) || !(sigma_m > 0.0)) return QLEARN_E_RANGE;
  if (solve->count >= QLEARN_SOLVE_MAX_PLANES) return QLEARN_E_CAPACITY;
  qlearn_solve_plane_t p;
  for (int k = 0; k < 3; ++k) p.n_obj[k] = n_obj[k] / len;
  p.d_m = d_m / len;
  p.sigma_m = sigma_m / len;
  if (!isfinite(p.d_m) || !(p.sigma_m > 0.0)) return QLEARN_E_RANGE; /* overflow / underflow */
  solve->plane[solve->count++] = p;
  return QLEARN_OK;
}

qlearn_status_t qlearn_solve_add_trial(qlearn_solve_t *solve, const double rot_obj_to_world[9],
                                       const double pos_obj_in_world_m[3], const double n_world[3],
                                       double d_edge_m, double sigma_m) {
  if (solve == NULL || rot_obj_to_world == NULL || pos_obj_in_world_m == NULL || n_world == NULL) {
    return QLEARN_E_ARG;
  }
  for (int k = 0; k < 9; ++k) {
    if (!isfinite(rot_obj_to_world[k])) return QLEARN_E_NONFINITE;
  }
  for (int k = 0; k < 3; ++k) {
    if (!isfinite(pos_obj_in_world_m[k]) || !isfinite(n_world[k])) return QLEARN_E_NONFINITE;
  }
  double n_obj[3];
  double n_dot_t = 0.0;
  for (int k = 0; k < 3; ++k) {
    /* (R^T n)_k = sum_r R[r][k] n[r] */
    n_obj[k] = rot_obj_to_world[0 * 3 + k] * n_world[0] + rot_obj_to_world[1 * 3 + k] * n_world[1] +
               rot_obj_to_world[2 * 3 + k] * n_world[2];
    n_dot_t += n_world[k] * pos_obj_in_world_m[k];
  }
  return qlearn_solve_add_plane(solve, n_obj, d_edge_m - n_dot_t, sigma_m);
}

/* Eigen decomposition of a symmetric 3x3 by cyclic Jacobi: a becomes diagonal, v holds the
 * eigenvectors as columns. Returns 0 on convergence. */
static int jacobi3(double a[3][3], double v[3][3]) {
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) v[i][j] = i == j ? 1.0 : 0.0;
  }
  for (int sweep = 0; sweep < QLEARN_SOLVE_MAX_SWEEPS; ++sweep) {
    double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    double diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
    /* Off-diagonal entries at rounding level of the matrix (1e-15 of its norm) are as small as
     * rotations can make them: where eigenvalues are (near) null, as with one plane, the null
     * block keeps entries ~1e-16 of the largest eigenvalue, and a relative 1e-18 never came. */
    if (off == 0.0 || off <= 1e-30 * (diag + 2.0 * off)) return 0;
    for (int p = 0; p < 2; ++p) {
      for (int q = p + 1; q < 3; ++q) {
        if (a[p][q] == 0.0) continue;
        double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
        double t = (theta >= 0.0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
        double c = 1.0 / sqrt(t * t + 1.0);
        double s = t * c;
        for (int k = 0; k < 3; ++k) { /* a <- a J (columns p, q) */
          double akp = a[k][p];
          double akq = a[k][q];
          a[k][p] = c * akp - s * akq;
          a[k][q] = s * akp + c * akq;
        }
        for (int k = 0; k < 3; ++k) { /* a <- J^T a (rows p, q) */
          double apk = a[p][k];
          double aqk = a[q][k];
          a[p][k] = c * apk - s * aqk;
          a[q][k] = s * apk + c * aqk;
        }
        for (int k = 0; k < 3; ++k) {
          double vkp = v[k][p];
          double vkq = v[k][q];
          v[k][p] = c * vkp - s * vkq;
          v[k][q] = s * vkp + c * vkq;
        }
      }
    }
  }
  return -1;
}

qlearn_status_t qlearn_solve_compute(const qlearn_solve_t *solve, double z, double max_halfwidth_m,
                                     qlearn_solve_result_t *result) {
  if (solve == NULL || result == NULL) return QLEARN_E_ARG;
  if (!isfinite(z) || !isfinite(max_halfwidth_m)) return QLEARN_E_NONFINITE;
  if (!(z > 0.0) || !(max_halfwidth_m > 0.0) || solve->count > QLEARN_SOLVE_MAX_PLANES) {
    return QLEARN_E_RANGE;
  }
  double a[3][3] = {{0.0}};
  double b[3] = {0.0, 0.0, 0.0};
  for (uint32_t i = 0; i < solve->count; ++i) {
    const qlearn_solve_plane_t *p = &solve->plane[i];
    double w = 1.0 / (p->sigma_m * p->sigma_m);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) a[r][c] += w * p->n_obj[r] * p->n_obj[c];
      b[r] += w * p->n_obj[r] * p->d_m;
    }
  }
  double v[3][3];
  if (jacobi3(a, v) != 0) return QLEARN_E_NOCONVERGE;
  /* Sort ascending. */
  int order[3] = {0, 1, 2};
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < 2 - i; ++j) {
      if (a[order[j]][order[j]] > a[order[j + 1]][order[j + 1]]) {
        int t = order[j];
        order[j] = order[j + 1];
        order[j + 1] = t;
      }
    }
  }
  qlearn_solve_result_t r;
  double lmax = a[order[2]][order[2]];
  int is_null[3];
  r.rank = 0;
  for (int j = 0; j < 3; ++j) {
    int col = order[j];
    r.eigenvalue[j] = a[col][col];
    for (int k = 0; k < 3; ++k) r.eigenvector[j][k] = v[k][col];
    is_null[j] = !(lmax > 0.0) || !(r.eigenvalue[j] > QLEARN_SOLVE_REL_EIG * lmax);
    if (!is_null[j]) r.rank++;
  }
  /* Minimum-norm solution over the non-null eigenspace. */
  double c[3] = {0.0, 0.0, 0.0};
  for (int j = 0; j < 3; ++j) {
    if (is_null[j]) continue;
    const double *e = r.eigenvector[j];
    double coef = (e[0] * b[0] + e[1] * b[1] + e[2] * b[2]) / r.eigenvalue[j];
    for (int k = 0; k < 3; ++k) c[k] += coef * e[k];
  }
  int all = 1;
  for (int k = 0; k < 3; ++k) {
    double leak = 0.0;
    double var = 0.0;
    for (int j = 0; j < 3; ++j) {
      double e2 = r.eigenvector[j][k] * r.eigenvector[j][k];
      if (is_null[j]) {
        leak += e2;
      } else {
        var += e2 / r.eigenvalue[j];
      }
    }
    double hw = z * sqrt(var);
    r.com_m[k] = c[k];
    r.found[k] = leak <= QLEARN_SOLVE_NULL_LEAK && isfinite(hw) && hw <= max_halfwidth_m;
    r.halfwidth_m[k] = r.found[k] ? hw : INFINITY;
    if (!r.found[k]) all = 0;
  }
  r.chi2 = 0.0;
  for (uint32_t i = 0; i < solve->count; ++i) {
    const qlearn_solve_plane_t *p = &solve->plane[i];
    double res =
        (p->n_obj[0] * c[0] + p->n_obj[1] * c[1] + p->n_obj[2] * c[2] - p->d_m) / p->sigma_m;
    r.chi2 += res * res;
  }
  *result = r;
  return all ? QLEARN_OK : QLEARN_E_SINGULAR;
}
