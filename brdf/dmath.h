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

#endif
