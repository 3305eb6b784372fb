/*
 * half.h — THE IEEE 754 binary16 rounding rule (internal), inline so that the
 * f16 evaluator pays no call per operation; bk_half_round (half.c) is its
 * public face.
 *
 * 11 significant bits for normals (2^-14 <= |x| < 65520): the low 42 of the
 * double's 52 fraction bits are rounded off to nearest, ties to even, by
 * adding 2^41 - 1 plus the lowest kept bit and clearing them; a carry out of
 * the fraction moves into the exponent, which is the right result. Below 2^-14
 * the quantum stays 2^-24 (subnormals): scaling by 2^24 is exact and rint
 * rounds ties to even. From 65520 = 65504 + half an ulp of 32 (a tie, which
 * rounds to even 2048·32 = 65536, out of range) the result is infinite.
 */
#ifndef BRDF_HALF_H
#define BRDF_HALF_H

#include <math.h>
#include <stdint.h>
#include <string.h>

static inline double bk_half_round_inline(double x)
{
	double ax = fabs(x);
	if (!(ax < 65520.0))
		return isnan(x) ? x : copysign(INFINITY, x);
	if (ax < 0x1p-14)
		return copysign(rint(ax * 0x1p24) * 0x1p-24, x);
	uint64_t b;
	memcpy(&b, &ax, sizeof b);
	b += ((uint64_t)1 << 41) - 1 + ((b >> 42) & 1);
	b &= ~(((uint64_t)1 << 42) - 1);
	memcpy(&ax, &b, sizeof ax);
	return copysign(ax, x);
}

#endif
