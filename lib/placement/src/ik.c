/* ik.c - inverse kinematics of a 7R arm: Levenberg-Marquardt on the 6-D pose error with joint
 * clamping, a nullspace pull toward the nominal posture and restarts from random seeds. */
#include <math.h>
#include <string.h>

#include "placement_internal.h"

enum { N = PLACEMENT_JOINTS };

/* One evaluated configuration. */
typedef struct {
  double q[N];
  placement_pose_t frames[N];
  placement_pose_t tip;
  double e[6]; /* target - current: position (m), rotation vector in the base frame (rad) */
  double pos;  /* |e[0..2]| */
  double rot;  /* |e[3..5]| = rotation angle */
  double cost; /* pos^2 + rot^2 */
} ik_eval_t;

static void evaluate(const placement_arm_t *arm, const placement_pose_t *target, ik_eval_t *v) {
  placement_fk_frames(arm, v->q, v->frames, &v->tip);
  double r[3][3]; /* target * tip^T: the rotation still to go, in the base frame */
  for (int i = 0; i < 3; ++i) {
    v->e[i] = target->pos_m[i] - v->tip.pos_m[i];
    for (int j = 0; j < 3; ++j) {
      r[i][j] = target->rot[i][0] * v->tip.rot[j][0] + target->rot[i][1] * v->tip.rot[j][1] +
                target->rot[i][2] * v->tip.rot[j][2];
    }
  }
  placement_rot_log((const double(*)[3])r, &v->e[3]);
  v->pos = sqrt(v->e[0] * v->e[0] + v->e[1] * v->e[1] + v->e[2] * v->e[2]);
  v->rot = sqrt(v->e[3] * v->e[3] + v->e[4] * v->e[4] + v->e[5] * v->e[5]);
  v->cost = v->pos * v->pos + v->rot * v->rot;
}

/* Cholesky factorisation in place (lower triangle); 0 when not positive definite. */
static int cholesky6(double a[6][6]) {
  for (int j = 0; j < 6; ++j) {
    double d = a[j][j];
    for (int k = 0; k < j; ++k) {
      d -= a[j][k] * a[j][k];
    }
    if (!(d > 0.0)) {
      return 0;
    }
    a[j][j] = sqrt(d);
    for (int i = j + 1; i < 6; ++i) {
      double s = a[i][j];
      for (int k = 0; k < j; ++k) {
        s -= a[i][k] * a[j][k];
      }
      a[i][j] = s / a[j][j];
    }
  }
  return 1;
}

static void cholesky6_solve(const double l[6][6], double b[6]) {
  for (int i = 0; i < 6; ++i) {
    for (int k = 0; k < i; ++k) {
      b[i] -= l[i][k] * b[k];
    }
    b[i] /= l[i][i];
  }
  for (int i = 5; i >= 0; --i) {
    for (int k = i + 1; k < 6; ++k) {
      b[i] -= l[k][i] * b[k];
    }
    b[i] /= l[i][i];
  }
}

/* Into the limits: a revolute joint past a limit first tries the same angle one turn back
 * (identical FK; YuMi's axes 4 and 6 span more than a turn), else it is clamped. */
static void clamp_q(const placement_arm_t *arm, double q[N]) {
  const double turn = 2.0 * CL_PI;
  for (int k = 0; k < N; ++k) {
    if (q[k] > arm->upper_rad[k] && q[k] - turn >= arm->lower_rad[k]) {
      q[k] -= turn;
    } else if (q[k] < arm->lower_rad[k] && q[k] + turn <= arm->upper_rad[k]) {
      q[k] += turn;
    }
    q[k] = q[k] < arm->lower_rad[k]   ? arm->lower_rad[k]
           : q[k] > arm->upper_rad[k] ? arm->upper_rad[k]
                                      : q[k];
  }
}

/* The damped least-squares task step and the nullspace pull toward the nominal posture, with the
 * joints in `fixed` left out. Returns 0 when the damped normal matrix is not positive definite. */
static int step_masked(const placement_arm_t *arm, const ik_eval_t *cur,
                       const double jac_full[6][N], const int fixed[N], double lambda, double gain,
                       double dq_task[N], double dq_null[N]) {
  double jac[6][N];
  for (int i = 0; i < 6; ++i) {
    for (int k = 0; k < N; ++k) {
      jac[i][k] = fixed[k] ? 0.0 : jac_full[i][k];
    }
  }
  double a[6][6];
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j <= i; ++j) {
      double s = 0.0;
      for (int k = 0; k < N; ++k) {
        s += jac[i][k] * jac[j][k];
      }
      a[i][j] = a[j][i] = s;
    }
    a[i][i] += lambda;
  }
  if (!cholesky6(a)) {
    return 0;
  }
  /* Task step dq = J^T (J J^T + lambda I)^-1 e; nullspace step z - J^T (J J^T + lambda I)^-1 J z
   * with z the pull toward the nominal posture (an exact projection as lambda -> 0). */
  double y[6], z[N], u[6];
  memcpy(y, cur->e, sizeof y);
  cholesky6_solve((const double(*)[6])a, y);
  for (int k = 0; k < N; ++k) {
    dq_task[k] = 0.0;
    for (int i = 0; i < 6; ++i) {
      dq_task[k] += jac[i][k] * y[i];
    }
    z[k] = fixed[k] ? 0.0 : gain * (arm->nominal_rad[k] - cur->q[k]);
  }
  for (int i = 0; i < 6; ++i) {
    u[i] = 0.0;
    for (int k = 0; k < N; ++k) {
      u[i] += jac[i][k] * z[k];
    }
  }
  cholesky6_solve((const double(*)[6])a, u);
  for (int k = 0; k < N; ++k) {
    dq_null[k] = z[k];
    for (int i = 0; i < 6; ++i) {
      dq_null[k] -= jac[i][k] * u[i];
    }
  }
  return 1;
}

/* Largest joint step per iteration (rad): keeps the linearisation honest far from the target. */
#define IK_MAX_STEP_RAD 1.0
#define IK_LAMBDA_START 1e-3
#define IK_LAMBDA_MIN 1e-12
#define IK_LAMBDA_MAX 1e6
/* LM iterations allowed to pull a nullspace step back onto the pose. */
#define IK_CORRECTION_ITERATIONS 4u
/* The redundancy phase stops when the projected step is this small (rad). */
#define IK_NULL_STEP_MIN_RAD 1e-4

/* One LM run from cur->q. Returns 1 when the tolerances are met (cur holds the solution). */
static int converged(const ik_eval_t *v, const placement_ik_config_t *cfg) {
  return v->pos <= 0.5 * cfg->tol_pos_m && v->rot <= 0.5 * cfg->tol_rot_rad;
}

/* Levenberg-Marquardt from cur->q (already evaluated) for at most max_it iterations; 1 when the
 * tolerances are met (halved, so the final FK check has margin), cur then holds the solution. */
static int solve_from(const placement_arm_t *arm, const placement_pose_t *target,
                      const placement_ik_config_t *cfg, unsigned max_it, ik_eval_t *cur,
                      ik_eval_t *trial, unsigned *iterations) {
  double lambda = IK_LAMBDA_START;
  for (unsigned it = 0; it < max_it; ++it) {
    if (converged(cur, cfg)) {
      return 1;
    }
    ++*iterations;
    double jac[6][N];
    placement_jacobian_from_frames(arm, cur->frames, &cur->tip, jac);
    /* Joints resting on a limit that the step would push further are taken out (their
     * Jacobian column zeroed) and the step recomputed: clamping alone would waste the step. */
    int fixed[N] = {0};
    double dq_task[N], dq_null[N];
    int factored = 0;
    for (int pass = 0; pass < N; ++pass) {
      if (!step_masked(arm, cur, (const double(*)[N])jac, fixed, lambda, 0.0, dq_task, dq_null)) {
        break;
      }
      factored = 1;
      int changed = 0;
      for (int k = 0; k < N; ++k) {
        double d = dq_task[k] + dq_null[k];
        if (!fixed[k] && ((cur->q[k] <= arm->lower_rad[k] && d < 0.0) ||
                          (cur->q[k] >= arm->upper_rad[k] && d > 0.0))) {
          fixed[k] = 1;
          changed = 1;
        }
      }
      if (!changed) {
        break;
      }
    }
    if (!factored) {
      lambda *= 10.0;
      continue;
    }
    double big = 0.0;
    for (int k = 0; k < N; ++k) {
      big = fabs(dq_task[k]) > big ? fabs(dq_task[k]) : big;
    }
    double scale = big > IK_MAX_STEP_RAD ? IK_MAX_STEP_RAD / big : 1.0;
    for (int k = 0; k < N; ++k) {
      trial->q[k] = cur->q[k] + scale * dq_task[k];
    }
    clamp_q(arm, trial->q);
    evaluate(arm, target, trial);
    int accepted = trial->cost < cur->cost;
    if (accepted) {
      *cur = *trial;
    }
    if (accepted) {
      lambda = lambda * 0.2 > IK_LAMBDA_MIN ? lambda * 0.2 : IK_LAMBDA_MIN;
    } else {
      lambda *= 8.0;
      if (lambda > IK_LAMBDA_MAX) {
        return 0; /* a local minimum (or a limit) this seed cannot leave */
      }
    }
  }
  return converged(cur, cfg);
}

static double nominal_dist2(const placement_arm_t *arm, const double q[N]) {
  double d = 0.0;
  for (int k = 0; k < N; ++k) {
    d += (q[k] - arm->nominal_rad[k]) * (q[k] - arm->nominal_rad[k]);
  }
  return d;
}

/* Redundancy: from a converged cur, step along the Jacobian's nullspace toward the nominal
 * posture (the projected gradient of |q - nominal|^2 / 2), pull back onto the pose with a few LM
 * iterations, and keep the move only when the pose still meets the tolerances and the posture is
 * nearer the nominal one. The step halves on every rejection. */
static void prefer_nominal(const placement_arm_t *arm, const placement_pose_t *target,
                           const placement_ik_config_t *cfg, ik_eval_t *cur, ik_eval_t *trial,
                           ik_eval_t *scratch, unsigned *iterations) {
  double gain = cfg->nullspace_gain;
  for (unsigned r = 0; r < cfg->redundancy_iterations && gain > 1e-3; ++r) {
    ++*iterations;
    double jac[6][N], dq_task[N], dq_null[N];
    int fixed[N] = {0};
    placement_jacobian_from_frames(arm, cur->frames, &cur->tip, jac);
    if (!step_masked(arm, cur, (const double(*)[N])jac, fixed, IK_LAMBDA_MIN, gain, dq_task,
                     dq_null)) {
      return;
    }
    double big = 0.0;
    for (int k = 0; k < N; ++k) {
      big = fabs(dq_null[k]) > big ? fabs(dq_null[k]) : big;
    }
    if (big < IK_NULL_STEP_MIN_RAD) {
      return; /* near a stationary point of the distance on the self-motion manifold */
    }
    double scale = big > IK_MAX_STEP_RAD ? IK_MAX_STEP_RAD / big : 1.0;
    for (int k = 0; k < N; ++k) {
      trial->q[k] = cur->q[k] + scale * dq_null[k];
    }
    clamp_q(arm, trial->q);
    evaluate(arm, target, trial);
    if (solve_from(arm, target, cfg, IK_CORRECTION_ITERATIONS, trial, scratch, iterations) &&
        nominal_dist2(arm, trial->q) < nominal_dist2(arm, cur->q)) {
      *cur = *trial;
    } else {
      gain *= 0.5;
    }
  }
}

static int is_rotation(const double r[3][3]) {
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      double d = r[0][i] * r[0][j] + r[1][i] * r[1][j] + r[2][i] * r[2][j] - (i == j ? 1.0 : 0.0);
      if (fabs(d) > 1e-9) {
        return 0;
      }
    }
  }
  double det = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1]) -
               r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0]) +
               r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
  return det > 0.0;
}

placement_status_t placement_ik(const placement_arm_t *arm, const placement_pose_t *target,
                                const double q_seed_rad[PLACEMENT_JOINTS],
                                const placement_ik_config_t *cfg, placement_ik_result_t *out) {
  static const placement_ik_config_t defaults = PLACEMENT_IK_CONFIG_INIT;
  if (out == NULL) {
    return PLACEMENT_E_ARG;
  }
  memset(out, 0, sizeof *out);
  if (arm == NULL || target == NULL) {
    return PLACEMENT_E_ARG;
  }
  if (cfg == NULL) {
    cfg = &defaults;
  }
  if (!(cfg->tol_pos_m > 0.0) || !(cfg->tol_rot_rad > 0.0) || !isfinite(cfg->tol_pos_m) ||
      !isfinite(cfg->tol_rot_rad) || cfg->max_iterations == 0 || cfg->max_seeds == 0 ||
      !(cfg->nullspace_gain >= 0.0 && cfg->nullspace_gain <= 1.0)) {
    return PLACEMENT_E_ARG;
  }
  if (!placement_finite(&target->rot[0][0], 9) || !placement_finite(target->pos_m, 3) ||
      (q_seed_rad != NULL && !placement_finite(q_seed_rad, N))) {
    return PLACEMENT_E_NONFINITE;
  }
  if (!is_rotation(target->rot)) {
    return PLACEMENT_E_ROTATION;
  }
  double dx = target->pos_m[0] - arm->origin[0].pos_m[0];
  double dy = target->pos_m[1] - arm->origin[0].pos_m[1];
  double dz = target->pos_m[2] - arm->origin[0].pos_m[2];
  if (sqrt(dx * dx + dy * dy + dz * dz) > arm->reach_m) {
    return PLACEMENT_E_OUT_OF_REACH;
  }
  uint64_t rng = cfg->rng_seed;
  ik_eval_t cur, trial, scratch, best;
  best.cost = HUGE_VAL;
  memcpy(best.q, arm->nominal_rad, sizeof best.q);
  best.pos = best.rot = HUGE_VAL;
  for (unsigned s = 0; s < cfg->max_seeds; ++s) {
    if (s == 0 && q_seed_rad != NULL) {
      memcpy(cur.q, q_seed_rad, sizeof cur.q);
    } else if (s == 0 || (s == 1 && q_seed_rad != NULL)) {
      memcpy(cur.q, arm->nominal_rad, sizeof cur.q);
    } else {
      for (int k = 0; k < N; ++k) {
        cur.q[k] =
            arm->lower_rad[k] + (arm->upper_rad[k] - arm->lower_rad[k]) * cl_rng_uniform(&rng);
      }
    }
    clamp_q(arm, cur.q);
    out->seeds = s + 1;
    evaluate(arm, target, &cur);
    int ok = solve_from(arm, target, cfg, cfg->max_iterations, &cur, &trial, &out->iterations);
    if (ok) {
      prefer_nominal(arm, target, cfg, &cur, &trial, &scratch, &out->iterations);
    }
    if (cur.cost < best.cost || ok) {
      best = cur;
    }
    if (ok) {
      break;
    }
  }
  /* Never a wrong answer: verify the best configuration by an independent FK. */
  memcpy(out->q_rad, best.q, sizeof out->q_rad);
  placement_pose_t tip;
  placement_fk(arm, out->q_rad, &tip);
  placement_pose_distance(&tip, target, &out->pos_err_m, &out->rot_err_rad);
  if (placement_arm_check(arm, out->q_rad) == PLACEMENT_OK && out->pos_err_m <= cfg->tol_pos_m &&
      out->rot_err_rad <= cfg->tol_rot_rad) {
    return PLACEMENT_OK;
  }
  return PLACEMENT_E_NO_SOLUTION;
}
