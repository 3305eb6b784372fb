/*
 * half.c — the IEEE 754 binary16 rounding rule used by the f16 evaluator and
 * by constant folding: 11 significant bits, exponent down to 2^-14 for normals
 * and subnormals in steps of 2^-24, round to nearest with ties to even, and
 * overflow to infinity at 65520 (= 65504 + half an ulp of 32, the tie rounding
 * to even 2048·32 = 65536, which is out of range).
 */
#include "brdf.h"

#include <math.h>

double bk_half_round(double x)
{
	if (!isfinite(x) || x == 0.0)
		return x;
	double ax = fabs(x);
	if (ax >= 65520.0)
		return copysign(INFINITY, x);
	int e;
	frexp(ax, &e);    /* ax = m·2^e, m in [0.5, 1) */
	int q = e - 11;   /* the quantum of an 11-bit significand */
	if (q < -24)
		q = -24;      /* below 2^-14 the quantum stays 2^-24: subnormals */
	double r = rint(ldexp(ax, -q)); /* exact scaling; rint ties to even */
	return copysign(ldexp(r, q), x);
}
