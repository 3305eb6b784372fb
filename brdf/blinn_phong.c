/*
 * blinn_phong.c — normalised Blinn-Phong and its spherical-Gaussian approximation.
 *
 * Exponent from alpha: n = 2/a^2 - 2 (Walter et al. 2007, the mapping that makes
 * Blinn-Phong and Beckmann agree near the peak). Normalisation (n + 2)/(2π)
 * makes ∫ D NoH dω = 1 exactly.
 */
#include "brdf.h"

#include <math.h>

/* n = 2/a^2 - 2: infinite at a = 0, 0 at a = 1 (the uniform cosine lobe). */
double bk_blinn_phong_exponent(double a)
{
	return 2.0 / (a * a) - 2.0;
}

/*
 * D_blinn_phong — Blinn 1977, normalised: (n + 2)/(2π) NoH^n.
 * Precision: fp16 cannot hold n above 65504 (a < 0.0055) and pow of a half NoH
 * rounds NoH to 1 within 2^-11 of the peak; a = 0 returns 0 (a delta).
 */
double bk_D_blinn_phong(double NoH, double a)
{
	if (NoH <= 0.0 || a <= 0.0)
		return 0.0;
	double n = bk_blinn_phong_exponent(a);
	return (n + 2.0) / (2.0 * BK_PI) * bk_dpow(NoH, n);
}

/*
 * D_blinn_phong_sg — Lagarde 2012, "Spherical Gaussian approximation for
 * Blinn-Phong, Phong and Fresnel": NoH^n ≈ exp((n + 0.775)(NoH - 1)), kept with the
 * Blinn-Phong normalisation (n + 2)/(2π). The 0.775 is the blog's fitted offset
 * (primary post read through a secondary copy; consistent with Unreal's
 * PhongApprox, whose 0.39674113·ln 2 = 0.275 = 0.775 - 0.5 for the Phong exponent
 * n/4). Not exactly normalised: ∫ D NoH dω = (n+2)(1/λ - (1 - e^-λ)/λ^2) with
 * λ = n + 0.775 (→ 1 + 0.225/n for large n, but 0.785 at a = 1, n = 0); the
 * tests check that closed form.
 */
double bk_D_blinn_phong_sg(double NoH, double a)
{
	if (NoH <= 0.0 || a <= 0.0)
		return 0.0;
	double n = bk_blinn_phong_exponent(a);
	return (n + 2.0) / (2.0 * BK_PI) * bk_dexp((n + 0.775) * (NoH - 1.0));
}
