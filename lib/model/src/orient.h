/* orient.h - private to lib/model: exact geometric predicates for the convex hull (hull.c).
 *
 * Shewchuk's floating-point expansions ("Adaptive Precision Floating-Point Arithmetic and Fast
 * Robust Geometric Predicates", 1997): a double-precision evaluation with a forward error bound,
 * and the exact evaluation when the bound cannot decide the sign. The answers are exact for any
 * finite input whose products do not underflow or overflow; hull.c guarantees that by scaling
 * its points into [-1, 1] and flushing coordinates below 2^-250 to zero. Needs IEEE-754 double
 * arithmetic rounded to nearest, without extended precision or fused multiply-add contraction
 * (orient.c is compiled with -ffp-contract=off and refuses FLT_EVAL_METHOD != 0). */
#ifndef COMLEARN_MODEL_ORIENT_H
#define COMLEARN_MODEL_ORIENT_H

/* Sign of ((b - a) x (c - a)) . (d - a): +1 when d lies on the side the normal of the
 * counter-clockwise triangle a, b, c points to, -1 on the other side, 0 when the four points are
 * coplanar. Exact. */
int model_orient3d(const double a[3], const double b[3], const double c[3], const double d[3]);

/* (b - a) x (c - a), each component the exact value summed from its expansion, smallest part
 * first (within a unit or two in the last place; measured below 2^-51 relative), so a sliver
 * triangle's normal is as accurate as a fat one's. */
void model_tri_cross(const double a[3], const double b[3], const double c[3], double n[3]);

#endif
