/*
 * beckmann.c — the Beckmann distribution: D, exact Smith Lambda (with erf), G1.
 *
 * Beckmann & Spizzichino 1963 (D); Walter et al. 2007, eq. 25-27 (Smith G1);
 * Heitz 2014, eq. 80 (Lambda). Convention: a = alpha = r^2 is the RMS slope.
 */
#include "brdf.h"
#include "dmath.h" /* bk_dmath_erfc_tail, bk_dmath_exp_minus_sq */

#include <math.h>

/*
 * D_beckmann — exp(-tan^2θ / a^2) / (π a^2 cos^4θ).
 * Precision: for NoH -> 0 the exponential underflows long before cos^4 does, so
 * the grazing limit 0 is returned explicitly; a = 0 is a delta (returns 0).
 * In fp16 the peak 1/(π a^2) exceeds 65504 once a < 0.0022.
 */
double bk_D_beckmann(double NoH, double a)
{
	if (NoH <= 0.0 || a <= 0.0)
		return 0.0;
	double c2 = NoH * NoH;
	double tan2 = (1.0 - NoH) * (1.0 + NoH) / c2;
	return bk_dexp(-tan2 / (a * a)) / (BK_PI * a * a * c2 * c2);
}

/*
 * Lambda_beckmann — Heitz 2014, eq. 80, with c = 1 / (a tanθ):
 * (erf(c) - 1 + exp(-c^2) / (c sqrt(π))) / 2, i.e. (e^{-c²}/(c√π) - erfc(c))/2.
 * For c >= 1/2 the two terms nearly cancel (their difference is 1/(2c²) of
 * either: 8c⁴ε relative error at large c, 2e-11 at c = 20), so there erfc is
 * written as its continued fraction e^{-c²}/√π / (c + T) (brdf/dmath.c) and
 * the difference taken in closed form: e^{-c²}/√π (1/c - 1/(c + T)) =
 * e^{-c²}/√π T/(c (c + T)), every term positive. Below 1/2 the first term is
 * at least 1.8 times erfc (the difference loses under 1.3 bits), and
 * bk_derfc's series serves. brdfkit's exp and erfc, so
 * the bits do not depend on the CPU (glibc's erfc has an FMA variant).
 * NoX <= 0 gives +inf (G1 = 0); a = 0 or NoX = 1 gives 0.
 */
double bk_Lambda_beckmann(double NoX, double a)
{
	if (NoX <= 0.0)
		return INFINITY;
	if (NoX >= 1.0 || a <= 0.0)
		return 0.0;
	double sin_t = sqrt((1.0 - NoX) * (1.0 + NoX));
	double c = NoX / (a * sin_t);
	if (c < 0.5)
		return 0.5 * (bk_dexp(-c * c) / (c * sqrt(BK_PI)) - bk_derfc(c));
	if (c >= 28.0)
		return 0.0; /* e^{-c²} < 2^-1075: below the least subnormal */
	double t = bk_dmath_erfc_tail(c);
	return 0.5 * bk_dmath_exp_minus_sq(c) / sqrt(BK_PI) * (t / (c * (c + t)));
}

/* G1_beckmann — 1 / (1 + Lambda). */
double bk_G1_beckmann(double NoX, double a)
{
	return 1.0 / (1.0 + bk_Lambda_beckmann(NoX, a));
}
