/*
 * comlearn/math3d.h - the one small math kernel of comlearn: pi, 3-vectors, unit quaternions,
 * rigid poses and one seeded PRNG. Header-only (static inline), C11, no heap, no globals, no I/O;
 * every function is pure over caller arrays (outputs may alias inputs unless said otherwise) and
 * thread-safe. Link the INTERFACE target comlearn_math (it adds libm).
 *
 * Conventions:
 *   - double precision, SI units (metres, radians).
 *   - Vectors are double[3]. Rotation matrices are double[3][3], row-major, acting on column
 *     vectors: v_parent = rot * v_child.
 *   - Quaternions are double[4] in (w, x, y, z) order, Hamilton convention: q = w + x i + y j + z
 * k, q and -q are the same rotation. A quaternion q_a_in_b (frame a's orientation in frame b)
 *     rotates a vector given in a into b: v_b = q v_a q^-1 = cl_quat_rotate(q, v_a).
 *   - Composition order is right to left, as for matrices: cl_quat_mul(q_b_in_c, q_a_in_b)
 *     = q_a_in_c, i.e. the right factor is applied first.
 *   - The arithmetic of each function is fixed (order of operations included) because pinned
 *     results (tests/data/estimate_golden.txt, the bundled rocks) depend on it bit for bit: the
 *     copies these functions replaced computed exactly this. Do not "simplify" them.
 *   - Nothing here checks its input: a zero vector or quaternion gives infinities / NaN where a
 *     division by its norm is involved, as noted per function.
 */
#ifndef COMLEARN_MATH3D_H
#define COMLEARN_MATH3D_H

#include <math.h>
#include <stdint.h>
#include <string.h>

#ifdef __cplusplus
extern "C" {
#endif

/* pi, to more digits than a double holds (the double nearest pi, = acos(-1.0) and POSIX M_PI).
 * Derived constants are written from it: 2.0 * CL_PI, (CL_PI / 180.0) are exact or correctly
 * rounded as the literals they replaced were. */
#define CL_PI 3.14159265358979323846

/* ---- 3-vectors -------------------------------------------------------------------------- */

/* a . b */
static inline double cl_vec3_dot(const double a[3], const double b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* out = a x b (right-handed). out may alias a or b. */
static inline void cl_vec3_cross(const double a[3], const double b[3], double out[3]) {
  const double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                       a[0] * b[1] - a[1] * b[0]};
  out[0] = c[0];
  out[1] = c[1];
  out[2] = c[2];
}

/* out = a + b */
static inline void cl_vec3_add(const double a[3], const double b[3], double out[3]) {
  for (int k = 0; k < 3; ++k) out[k] = a[k] + b[k];
}

/* out = a - b */
static inline void cl_vec3_sub(const double a[3], const double b[3], double out[3]) {
  for (int k = 0; k < 3; ++k) out[k] = a[k] - b[k];
}

/* out = s * a */
static inline void cl_vec3_scale(const double a[3], double s, double out[3]) {
  for (int k = 0; k < 3; ++k) out[k] = s * a[k];
}

/* |a| (Euclidean length; no overflow guard, unlike hypot). */
static inline double cl_vec3_norm(const double a[3]) { return sqrt(cl_vec3_dot(a, a)); }

/* |a - b| */
static inline double cl_vec3_dist(const double a[3], const double b[3]) {
  const double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
  return sqrt(cl_vec3_dot(d, d));
}

/* out = a / |a| (each component divided by the norm, not multiplied by its inverse); returns |a|.
 * A zero a gives NaN components. out may alias a. */
static inline double cl_vec3_normalize(const double a[3], double out[3]) {
  const double n = cl_vec3_norm(a);
  for (int k = 0; k < 3; ++k) out[k] = a[k] / n;
  return n;
}

/* The unit normal of triangle (a, b, c), counter-clockwise seen from where it points: the cross
 * product (b - a) x (c - a) divided by its length, which is returned (twice the area). A degenerate
 * triangle (length 0) gives n = 0 and 0. */
static inline double cl_tri_normal(const double a[3], const double b[3], const double c[3],
                                   double n[3]) {
  const double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  cl_vec3_cross(e1, e2, n);
  const double len = sqrt(cl_vec3_dot(n, n));
  for (int k = 0; k < 3; ++k) n[k] = len > 0.0 ? n[k] / len : 0.0;
  return len;
}

/* ---- unit quaternions (w, x, y, z) ------------------------------------------------------ */

/* out = a * b (Hamilton product; rotation b first, then a). out may alias a or b. */
static inline void cl_quat_mul(const double a[4], const double b[4], double out[4]) {
  const double r[4] = {a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
                       a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
                       a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
                       a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]};
  memcpy(out, r, sizeof r);
}

/* out = conj(q) = (w, -x, -y, -z): the inverse rotation of a unit q. */
static inline void cl_quat_conj(const double q[4], double out[4]) {
  out[0] = q[0];
  out[1] = -q[1];
  out[2] = -q[2];
  out[3] = -q[3];
}

/* out = q / |q| (each component divided by the norm); returns |q|. A zero q gives NaN. */
static inline double cl_quat_normalize(const double q[4], double out[4]) {
  const double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  for (int k = 0; k < 4; ++k) out[k] = q[k] / n;
  return n;
}

/* The rotation by angle_rad about a UNIT axis (not normalised here), right-hand rule:
 * (cos(angle/2), sin(angle/2) axis). */
static inline void cl_quat_from_axis_angle(const double axis[3], double angle_rad, double q[4]) {
  q[0] = cos(0.5 * angle_rad);
  for (int i = 0; i < 3; ++i) q[i + 1] = sin(0.5 * angle_rad) * axis[i];
}

/* out = q v q^-1: v rotated by unit q (v in q's child frame -> parent frame), without forming the
 * matrix: v' = v + w t + u x t with u = (x, y, z), t = 2 u x v. out may alias v. */
static inline void cl_quat_rotate(const double q[4], const double v[3], double out[3]) {
  const double w = q[0], u[3] = {q[1], q[2], q[3]};
  const double t[3] = {2.0 * (u[1] * v[2] - u[2] * v[1]), 2.0 * (u[2] * v[0] - u[0] * v[2]),
                       2.0 * (u[0] * v[1] - u[1] * v[0])};
  const double r[3] = {v[0] + w * t[0] + (u[1] * t[2] - u[2] * t[1]),
                       v[1] + w * t[1] + (u[2] * t[0] - u[0] * t[2]),
                       v[2] + w * t[2] + (u[0] * t[1] - u[1] * t[0])};
  out[0] = r[0];
  out[1] = r[1];
  out[2] = r[2];
}

/* The rotation matrix of angle_rad about the unit axis (Rodrigues: t a a^T + c I + s [a]x, with
 * c = cos, s = sin, t = 1 - c); axis is not normalised here. The same arithmetic as lib/placement's
 * placement_rot_from_axis_angle, which calls it. */
static inline void cl_rot_from_axis_angle(const double axis[3], double angle_rad,
                                          double rot[3][3]) {
  const double c = cos(angle_rad), s = sin(angle_rad), t = 1.0 - c;
  const double x = axis[0], y = axis[1], z = axis[2];
  rot[0][0] = t * x * x + c;
  rot[0][1] = t * x * y - s * z;
  rot[0][2] = t * x * z + s * y;
  rot[1][0] = t * x * y + s * z;
  rot[1][1] = t * y * y + c;
  rot[1][2] = t * y * z - s * x;
  rot[2][0] = t * x * z - s * y;
  rot[2][1] = t * y * z + s * x;
  rot[2][2] = t * z * z + c;
}

/* The rotation matrix of a unit quaternion (not normalised here): rot * v = cl_quat_rotate(q, v)
 * up to rounding. The same arithmetic as lib/model's model_quat_to_rot. */
static inline void cl_quat_to_rot(const double q[4], double rot[3][3]) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  rot[0][0] = 1.0 - 2.0 * (y * y + z * z);
  rot[0][1] = 2.0 * (x * y - w * z);
  rot[0][2] = 2.0 * (x * z + w * y);
  rot[1][0] = 2.0 * (x * y + w * z);
  rot[1][1] = 1.0 - 2.0 * (x * x + z * z);
  rot[1][2] = 2.0 * (y * z - w * x);
  rot[2][0] = 2.0 * (x * z - w * y);
  rot[2][1] = 2.0 * (y * z + w * x);
  rot[2][2] = 1.0 - 2.0 * (x * x + y * y);
}

/* The unit quaternion, w >= 0, of a rotation matrix: Shepperd's method (divide by the largest
 * of the four 4 q_i^2 terms), then normalised. Inverse of cl_quat_to_rot up to the sign of q.
 * The same arithmetic as lib/model's model_rot_to_quat. rot must not alias q. C11 does not
 * convert double (*)[3] to const double (*)[3] implicitly: cast a non-const matrix. */
static inline void cl_quat_from_rot(const double rot[3][3], double q[4]) {
  const double(*r)[3] = rot;
  const double tr = r[0][0] + r[1][1] + r[2][2];
  if (tr > 0.0) {
    const double s = sqrt(tr + 1.0) * 2.0;
    q[0] = 0.25 * s;
    q[1] = (r[2][1] - r[1][2]) / s;
    q[2] = (r[0][2] - r[2][0]) / s;
    q[3] = (r[1][0] - r[0][1]) / s;
  } else if (r[0][0] > r[1][1] && r[0][0] > r[2][2]) {
    const double s = sqrt(1.0 + r[0][0] - r[1][1] - r[2][2]) * 2.0;
    q[0] = (r[2][1] - r[1][2]) / s;
    q[1] = 0.25 * s;
    q[2] = (r[0][1] + r[1][0]) / s;
    q[3] = (r[0][2] + r[2][0]) / s;
  } else if (r[1][1] > r[2][2]) {
    const double s = sqrt(1.0 + r[1][1] - r[0][0] - r[2][2]) * 2.0;
    q[0] = (r[0][2] - r[2][0]) / s;
    q[1] = (r[0][1] + r[1][0]) / s;
    q[2] = 0.25 * s;
    q[3] = (r[1][2] + r[2][1]) / s;
  } else {
    const double s = sqrt(1.0 + r[2][2] - r[0][0] - r[1][1]) * 2.0;
    q[0] = (r[1][0] - r[0][1]) / s;
    q[1] = (r[0][2] + r[2][0]) / s;
    q[2] = (r[1][2] + r[2][1]) / s;
    q[3] = 0.25 * s;
  }
  (void)cl_quat_normalize(q, q);
  if (q[0] < 0.0)
    for (int i = 0; i < 4; i++) q[i] = -q[i];
}

/* The angle [rad], in [0, pi], of the rotation from unit a to unit b (of conj(a) * b; the sign of
 * either quaternion does not matter): 2 atan2(|v|, |w|) of that relative quaternion. Accurate at
 * every angle, unlike 2 acos(|a . b|), which returns 0 below ~1e-8 rad and loses half the digits
 * near 0 (acos' slope is infinite at 1). For a single rotation's angle pass a = (1, 0, 0, 0): the
 * result is then bit for bit 2 atan2(|q_xyz|, |q_w|). */
static inline double cl_quat_angle(const double a[4], const double b[4]) {
  const double w = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
  const double x = a[0] * b[1] - a[1] * b[0] - a[2] * b[3] + a[3] * b[2];
  const double y = a[0] * b[2] + a[1] * b[3] - a[2] * b[0] - a[3] * b[1];
  const double z = a[0] * b[3] - a[1] * b[2] + a[2] * b[1] - a[3] * b[0];
  return 2.0 * atan2(sqrt(x * x + y * y + z * z), fabs(w));
}

/* Spherical linear interpolation from unit a (t = 0) to unit b (t = 1) along the shorter arc (b
 * is flipped when a . b < 0); normalised lerp when the two are within ~2 degrees (|a . b| >
 * 0.9995, where sin(theta) is too small to divide by). The result is normalised. t in [0, 1]. */
static inline void cl_quat_slerp(const double a[4], const double b[4], double t, double out[4]) {
  double bb[4];
  double dot = 0.0;
  for (int i = 0; i < 4; i++) dot += a[i] * b[i];
  const double sgn = dot < 0.0 ? -1.0 : 1.0;
  for (int i = 0; i < 4; i++) bb[i] = sgn * b[i];
  dot = fabs(dot);
  double wa, wb;
  if (dot > 0.9995) {
    wa = 1.0 - t;
    wb = t;
  } else {
    const double th = acos(dot), s = sin(th);
    wa = sin((1.0 - t) * th) / s;
    wb = sin(t * th) / s;
  }
  double n = 0.0;
  for (int i = 0; i < 4; i++) {
    out[i] = wa * a[i] + wb * bb[i];
    n += out[i] * out[i];
  }
  n = sqrt(n);
  for (int i = 0; i < 4; i++) out[i] /= n;
}

/* ---- rigid poses -------------------------------------------------------------------------- */

/* A frame's pose in a parent frame: x_parent = R(orientation_wxyz) x_child + position_m. The
 * orientation is a unit quaternion (w, x, y, z). Same layout and field names as model_pose_t. */
typedef struct {
  double position_m[3];
  double orientation_wxyz[4];
} cl_pose_t;

/* The identity pose (zero position, (1, 0, 0, 0)). */
static inline void cl_pose_identity(cl_pose_t *out) {
  memset(out, 0, sizeof *out);
  out->orientation_wxyz[0] = 1.0;
}

/* out = a's child point p in a's parent frame: R(a) p + a.position_m. out may alias p. */
static inline void cl_pose_apply(const cl_pose_t *a, const double p[3], double out[3]) {
  double r[3];
  cl_quat_rotate(a->orientation_wxyz, p, r);
  cl_vec3_add(r, a->position_m, out);
}

/* out = a * b: with a = frame1 in frame0 and b = frame2 in frame1, out = frame2 in frame0
 * (position R(a) b.p + a.p, orientation a.q * b.q). out may alias a or b. */
static inline void cl_pose_mul(const cl_pose_t *a, const cl_pose_t *b, cl_pose_t *out) {
  cl_pose_t r;
  cl_pose_apply(a, b->position_m, r.position_m);
  cl_quat_mul(a->orientation_wxyz, b->orientation_wxyz, r.orientation_wxyz);
  *out = r;
}

/* out = a^-1 (parent in child): orientation conj(a.q), position -R(a)^T a.p. out may alias a. */
static inline void cl_pose_inverse(const cl_pose_t *a, cl_pose_t *out) {
  cl_pose_t r;
  cl_quat_conj(a->orientation_wxyz, r.orientation_wxyz);
  cl_quat_rotate(r.orientation_wxyz, a->position_m, r.position_m);
  cl_vec3_scale(r.position_m, -1.0, r.position_m);
  *out = r;
}

/* ---- the PRNG: splitmix64 ------------------------------------------------------------------ */
/* Steele, Lea & Flood 2014: a Weyl sequence (step 0x9E3779B97F4A7C15) through a 64-bit mixer. One
 * uint64_t of caller-owned state; any seed (0 included) is fine. Every draw below advances
 * *state by exactly the number of cl_rng_next calls it states, so streams are reproducible
 * across platforms. Not for cryptography. */

/* The next 64 random bits (one step). */
static inline uint64_t cl_rng_next(uint64_t *state) {
  uint64_t z = (*state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

/* Uniform in [0, 1): the top 53 bits times 2^-53 (one step). May return 0, never 1. */
static inline double cl_rng_uniform(uint64_t *state) {
  return (double)(cl_rng_next(state) >> 11) * 0x1.0p-53;
}

/* Uniform in (0, 1): the top 53 bits plus one half, times 2^-53 (one step). Never 0 or 1, so
 * log() of it is finite (Box-Muller). */
static inline double cl_rng_uniform_open(uint64_t *state) {
  return ((double)(cl_rng_next(state) >> 11) + 0.5) * 0x1.0p-53;
}

/* Uniform in [lo, hi): lo + (hi - lo) cl_rng_uniform (one step). */
static inline double cl_rng_range(uint64_t *state, double lo, double hi) {
  return lo + (hi - lo) * cl_rng_uniform(state);
}

/* 0 .. n-1 by the remainder of 64 bits (bias below 2^-32 for n < 2^32); 0 for n == 0, then
 * without a step. */
static inline unsigned cl_rng_below(uint64_t *state, unsigned n) {
  return n == 0 ? 0 : (unsigned)(cl_rng_next(state) % n);
}

/* Two independent standard normal numbers (Box-Muller on u = open uniform, v = open uniform;
 * two steps): out[0] = r cos(2 pi v), out[1] = r sin(2 pi v), r = sqrt(-2 ln u). This is the
 * stream of lib/balance's trial noise (balance_noise_t): keep it so. */
static inline void cl_rng_normal2(uint64_t *state, double out[2]) {
  const double u = cl_rng_uniform_open(state), v = cl_rng_uniform_open(state);
  const double r = sqrt(-2.0 * log(u));
  out[0] = r * cos(2.0 * CL_PI * v);
  out[1] = r * sin(2.0 * CL_PI * v);
}

/* A uniformly random unit vector: dim 3 on the sphere, dim 2 in the xy plane (u[2] = 0), by
 * rejection from the cube [-1, 1]^dim (dim steps per try; acceptance 52 % in 3-D, 79 % in 2-D;
 * after 1000 rejected tries, never seen, the last try is normalised anyway). dim is 2 or 3. */
static inline void cl_rng_direction(uint64_t *state, int dim, double u[3]) {
  double n2 = 0.0;
  for (int tries = 0; tries < 1000; ++tries) {
    u[2] = 0.0;
    for (int k = 0; k < dim; ++k) u[k] = 2.0 * cl_rng_uniform(state) - 1.0;
    n2 = cl_vec3_dot(u, u);
    if (n2 > 1e-6 && n2 <= 1.0) break;
  }
  const double n = sqrt(n2);
  for (int k = 0; k < 3; ++k) u[k] /= n;
}

#ifdef __cplusplus
}
#endif

#endif
