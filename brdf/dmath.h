/*
 * dmath.h — sin, cos and acos with the same bits on every x86-64 machine
 * (glibc's own pick FMA or non-FMA code at run time). For the reference
 * integrals of brdf/ and fit/; see dmath.c for the domain and precision.
 */
#ifndef BRDF_DMATH_H
#define BRDF_DMATH_H

#include <math.h>

double bk_dsin(double x); /* |x| <= 8 */
double bk_dcos(double x); /* |x| <= 8 */
double bk_dacos(double c); /* c in [-1, 1] */

#endif
