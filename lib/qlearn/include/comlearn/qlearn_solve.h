/*
 * comlearn/qlearn_solve.h - the 3-D CoM from thresholds found along several directions and in
 * several resting poses, by weighted least squares in fixed memory.
 *
 * A trial released in pose (R, t) (object frame -> world: p_world = R p_obj + t) over an edge
 * whose outward normal is n (world) and whose offset is d_edge (the edge line is n . p = d_edge)
 * stays exactly when n . (R c + t) <= d_edge, i.e. when n_obj . c <= d with n_obj = R^T n and
 * d = d_edge - n . t, in the object frame. R is the pose at release of that trial (possibly tilted
 * onto the edge), not a nominal one. A threshold found by a search is the plane n_obj . c = d,
 * known to a standard deviation sigma (for a bisect bracket of half width h, sigma = h / sqrt(3);
 * for a PBA 95 % interval of half width h, sigma ~ h / 1.96).
 *
 * The solve minimizes sum_i (n_i . c - d_i)^2 / sigma_i^2 over c. With A = sum n_i n_i^T /
 * sigma_i^2 (the normal matrix, eigenvalues lambda_j, unit eigenvectors v_j):
 *   - eigenvalue j is null when lambda_j <= QLEARN_SOLVE_REL_EIG * lambda_max (or all are 0);
 *   - component k (x, y or z of the object frame) is determined when e_k is orthogonal to the null
 *     space, sum over null j of v_j[k]^2 <= QLEARN_SOLVE_NULL_LEAK, and its half width
 *     z * sqrt(Var c_k) with Var c_k = sum over non-null j of v_j[k]^2 / lambda_j is at most the
 *     caller's max_halfwidth_m. Otherwise it is not found (e.g. the out-of-plane component when
 *     every normal lies in one plane).
 * No heap, no I/O, no globals; every loop is bounded (Jacobi: QLEARN_SOLVE_MAX_SWEEPS).
 * Thread safety: functions touch only their arguments.
 */
#ifndef COMLEARN_QLEARN_SOLVE_H
#define COMLEARN_QLEARN_SOLVE_H

#include <stdint.h>

#include "comlearn/qlearn_types.h"

#ifdef __cplusplus
extern "C" {
#endif

#define QLEARN_SOLVE_MAX_PLANES 48   /* thresholds one solve holds */
#define QLEARN_SOLVE_REL_EIG 1e-10   /* eigenvalues below this fraction of the largest are null */
#define QLEARN_SOLVE_NULL_LEAK 1e-12 /* allowed squared projection of e_k on the null space */
#define QLEARN_SOLVE_MAX_SWEEPS 32   /* Jacobi sweep cap (3x3 converges in < 10) */

/* One threshold plane in the object frame: n_obj . c = d_m, n_obj unit length. */
typedef struct {
  double n_obj[3];
  double d_m;
  double sigma_m;
} qlearn_solve_plane_t;

/* Caller-owned, fixed size, memcpy-able. */
typedef struct {
  uint32_t count;
  qlearn_solve_plane_t plane[QLEARN_SOLVE_MAX_PLANES];
} qlearn_solve_t;

typedef struct {
  double com_m[3];          /* object frame; for a component not found, the minimum-norm value */
  double halfwidth_m[3];    /* z * standard deviation; INFINITY when not found */
  int found[3];             /* 1 when the component is determined (see above) */
  double eigenvalue[3];     /* of the normal matrix A (1/m^2), ascending */
  double eigenvector[3][3]; /* eigenvector[j] belongs to eigenvalue[j] */
  int rank;                 /* non-null eigenvalues */
  double chi2;              /* weighted residual sum: ~ count - rank for consistent data */
} qlearn_solve_result_t;

_Static_assert(QLEARN_SOLVE_MAX_PLANES >= 9, "room for three directions in three poses");
_Static_assert(sizeof(qlearn_solve_t) <= 4096, "solve state must stay small (16 KiB budget)");

/* Empty the set. QLEARN_E_ARG for NULL. Never allocates. */
qlearn_status_t qlearn_solve_init(qlearn_solve_t *solve);

/* Add the plane n_obj . c = d_m (n_obj any nonzero length: it is normalized, with d_m scaled
 * alike) with standard deviation sigma_m > 0 (of d_m, before normalizing). QLEARN_E_ARG (NULL),
 * QLEARN_E_NONFINITE, QLEARN_E_RANGE (zero normal, sigma <= 0), QLEARN_E_CAPACITY (full). On error
 * the set is unchanged. */
qlearn_status_t qlearn_solve_add_plane(qlearn_solve_t *solve, const double n_obj[3], double d_m,
                                       double sigma_m);

/* Add the threshold of a trial in pose (R, t): rot_obj_to_world row-major 3x3 (a rotation; not
 * checked beyond finiteness), pos_obj_in_world_m = t, the edge's outward normal n_world (any
 * nonzero length) and offset d_edge_m (n_world . p = d_edge_m on the edge line, same scale as
 * n_world), sigma_m as above. Adds n_obj = R^T n, d = d_edge - n . t. Errors as _add_plane. */
qlearn_status_t qlearn_solve_add_trial(qlearn_solve_t *solve, const double rot_obj_to_world[9],
                                       const double pos_obj_in_world_m[3], const double n_world[3],
                                       double d_edge_m, double sigma_m);

/* Solve. z > 0 scales the half widths (1.96 for ~95 %), max_halfwidth_m > 0 is the widest half
 * width still called found. QLEARN_OK when all three components are found; QLEARN_E_SINGULAR
 * when some are not (result still filled: see found[]); QLEARN_E_ARG / _NONFINITE / _RANGE for
 * bad arguments (result untouched); QLEARN_E_NOCONVERGE if Jacobi hits its cap. */
qlearn_status_t qlearn_solve_compute(const qlearn_solve_t *solve, double z, double max_halfwidth_m,
                                     qlearn_solve_result_t *result);

#ifdef __cplusplus
}
#endif

#endif /* COMLEARN_QLEARN_SOLVE_H */
