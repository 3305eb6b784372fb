/*
 * dmath.h — sin, cos and acos with the same bits on every x86-64 machine
 * (glibc's own pick FMA or non-FMA code at run time). For the reference
 * integrals of brdf/ and fit/; see dmath.c for the domain and precision.
 */
#ifndef BRDF_DMATH_H
#define BRDF_DMATH_H

#include "brdf.h" /* bk_dsin, bk_dcos, bk_dacos: declared there, public (fit/target.c uses them) */

#include <math.h>

#endif
