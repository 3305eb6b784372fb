/*
 * smith.h — the height-correlated Smith GGX visibility in its two halves
 * (internal, not installed): ggx.c's bk_V_smith_ggx_correlated and the
 * integrator (integrate.c), which forms the view half once per integral
 * instead of at every inner point, share these, so the formula is written
 * once and both give the same bits (no FMA contraction: -std=c11).
 *
 *   V = 0.5 / (NoL · Λv + NoV · Λl),  Λc = sqrt(c² (1 − a²) + a²)
 *   (Heitz 2014, eq. 99; a = r², the GGX width)
 */
#ifndef BRDF_SMITH_H
#define BRDF_SMITH_H

#include <math.h>

/* Λc for a cosine c and a² */
static inline double bk_smith_half(double c, double a2)
{
	return sqrt(c * c * (1.0 - a2) + a2);
}

/* V from the cosines and their halves sv = Λ(NoV), sl = Λ(NoL) */
static inline double bk_smith_correlated(double NoV, double NoL, double sv, double sl)
{
	return 0.5 / (NoL * sv + NoV * sl);
}

#endif
