/*
 * dmath.h — sin, cos, acos, exp2, log2, pow, exp, log, log10 and log1p with the
 * same bits on every x86-64 machine (glibc's own pick FMA or non-FMA code at
 * run time). For the reference integrals, the IR and the plots; see dmath.c
 * for the domains and precision.
 */
#ifndef BRDF_DMATH_H
#define BRDF_DMATH_H

#include "brdf.h" /* bk_dsin, ..., bk_dlog1p: declared there, public (fit/target.c uses them) */

#include <math.h>

/* The tail T of erfc's continued fraction, erfc(x) = e^{-x²}/√π / (x + T),
 * for x >= 1/2 (dmath.c): Beckmann's Λ takes it to subtract without
 * cancellation. */
double bk_dmath_erfc_tail(double x);
/* e^{-x²} with x² taken as an exact pair (rounding x² first costs x² ulps) */
double bk_dmath_exp_minus_sq(double x);

#endif
