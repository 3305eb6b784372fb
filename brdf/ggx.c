/*
 * ggx.c — the GGX / Trowbridge-Reitz distribution, whole: D, Smith Lambda, G1,
 * the two Smith visibilities built from Lambda, and importance sampling of H.
 *
 * Walter, Marschner, Li, Torrance 2007, "Microfacet Models for Refraction through
 * Rough Surfaces" (D, Smith G1); Heitz 2014, "Understanding the Masking-Shadowing
 * Function in Microfacet-Based BRDFs" (Lambda, height-correlated G2).
 * Convention: a = alpha = r^2 (Walter's alpha_g); a2 = a^2.
 */
#include "brdf.h"
#include "smith.h"

#include <math.h>

/* 1 - c^2 without the cancellation of 1 - c*c near c = 1: (1 - c) is exact for
 * c in [0.5, 1] (Sterbenz), so the product keeps full relative precision of the
 * input. This is the sin^2 of the half-vector angle around the highlight. */
static double one_minus_sq(double c) { return (1.0 - c) * (1.0 + c); }

/*
 * D_ggx — Walter et al. 2007, eq. 33: a2 / (π (NoH^2 (a2 - 1) + 1)^2).
 * The denominator is rewritten sin^2θh + NoH^2·a2 so that it does not cancel at
 * the peak. Precision: NoH itself carries the limit — with sin^2θh taken as
 * 1 - NoH^2, the rounding of NoH (2^-53) makes a relative error of about
 * 2^-53/a2 at the peak, where sin^2θh ~ a2 (1e-6 at r = 0.003), so callers that
 * know the angle pass its sine to bk_D_ggx_sin2 instead. a = 0 is a delta: returns 0
 * (integrators take the smooth limit analytically). In fp16, D reaches 1/(π a2)
 * at the peak, above 65504 once a2 < 4.9e-6 (r < 0.047): a shader must clamp.
 */
double bk_D_ggx(double NoH, double a)
{
	return bk_D_ggx_sin2(one_minus_sq(NoH), NoH, a);
}

/* D_ggx with sin^2θh supplied by a caller that has it to full precision. */
double bk_D_ggx_sin2(double sin2h, double NoH, double a)
{
	if (NoH <= 0.0 || a <= 0.0)
		return 0.0;
	double a2 = a * a;
	double d = sin2h + NoH * NoH * a2;
	return a2 / (BK_PI * d * d);
}

/*
 * Lambda_ggx — Heitz 2014, eq. 72: (-1 + sqrt(1 + a^2 tan^2θ)) / 2, computed as
 * x / (2 (sqrt(1 + x) + 1)) with x = a^2 tan^2θ, which does not cancel for small x
 * (the pbrt-v4 note). NoX <= 0 is grazing or below: Lambda is +inf (G1 = 0).
 */
double bk_Lambda_ggx(double NoX, double a)
{
	if (NoX <= 0.0)
		return INFINITY;
	if (NoX >= 1.0)
		return 0.0;
	double tan2 = one_minus_sq(NoX) / (NoX * NoX);
	double x = a * a * tan2;
	if (isinf(x))
		return INFINITY;
	return x / (2.0 * (sqrt(1.0 + x) + 1.0));
}

/* G1_ggx — Smith masking from Lambda: 1 / (1 + Lambda) (Heitz 2014, eq. 43). */
double bk_G1_ggx(double NoX, double a)
{
	return 1.0 / (1.0 + bk_Lambda_ggx(NoX, a));
}

/*
 * V_smith_ggx_separable — G1(v) G1(l) / (4 NoL NoV), with 2 NoX (1 + Lambda) =
 * NoX + sqrt(a2 + (1 - a2) NoX^2) substituted so that NoX = 0 needs no division
 * by zero. Equal to the Lambda form to rounding (tested). At NoV = NoL = 0 and
 * a = 0 the true value is infinite and so is the result.
 */
double bk_V_smith_ggx_separable(double NoV, double NoL, double a)
{
	double a2 = a * a;
	double gv = NoV + sqrt(a2 + (1.0 - a2) * NoV * NoV);
	double gl = NoL + sqrt(a2 + (1.0 - a2) * NoL * NoL);
	return 1.0 / (gv * gl);
}

/*
 * V_smith_ggx_correlated — Heitz 2014, eq. 99, height-correlated
 * G2 = 1 / (1 + Lambda(v) + Lambda(l)), divided by 4 NoL NoV:
 * 0.5 / (NoL sqrt(NoV^2 (1 - a2) + a2) + NoV sqrt(NoL^2 (1 - a2) + a2)).
 * Finite at NoL = 0 (0.5 / (NoV a)); infinite only when both cosines and a are 0.
 * In fp16 the denominator underflows below 6.1e-5 at grazing angles of smooth
 * surfaces: Filament clamps the result to 65504.
 */
double bk_V_smith_ggx_correlated(double NoV, double NoL, double a)
{
	double a2 = a * a;
	return bk_smith_correlated(NoV, NoL, bk_smith_half(NoV, a2), bk_smith_half(NoL, a2));
}

/*
 * Importance sampling of H with density D(h) NoH (Walter 2007, eq. 35-36, in the
 * cosine form of Karis 2013): cos^2θ = (1 - u1) / (1 + (a2 - 1) u1), φ = 2π u2.
 * Writes H in the frame of a +Z normal.
 */
void bk_ggx_sample_h(double u1, double u2, double a, double h[3])
{
	double a2 = a * a;
	double cos2 = (1.0 - u1) / (1.0 + (a2 - 1.0) * u1);
	double cos_t = sqrt(cos2);
	double sin_t = sqrt(fmax(0.0, 1.0 - cos2));
	double phi = 2.0 * BK_PI * u2;
	h[0] = sin_t * bk_dcos(phi); /* brdfkit's own (dmath.c): glibc's cos and sin */
	h[1] = sin_t * bk_dsin(phi); /* differ by an ulp between CPUs with and without FMA */
	h[2] = cos_t;
}
