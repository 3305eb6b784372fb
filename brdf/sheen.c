/*
 * sheen.c — sheen and cloth: the Charlie and velvet distributions (the
 * albedo is sheen_albedo.c's). brdf.h states the conventions.
 */
#include "brdf.h"

#include <math.h>

/* D_charlie — Estevez & Kulla 2017, "Production Friendly Microfacet Sheen
 * BRDF" (Imageworks), eq. 2: (2 + 1/a) sin(θh)^(1/a) / (2π). sin^(1/a) is
 * formed as (sin²)^(0.5/a) from sin² = (1 - NoH)(1 + NoH), exact near NoH = 1
 * where 1 - NoH² cancels. Filament's D_Charlie clamps sin² to 2^-7 for half
 * precision; this exact term does not. */
double bk_D_charlie(double NoH, double a)
{
	if (!(a > 0.0)) /* the limit a -> 0: (2 + 1/a) s^(1/a) -> 0 for s < 1 */
		return 0.0;
	double sin2h = (1.0 - NoH) * (1.0 + NoH);
	return (2.0 + 1.0 / a) * pow(sin2h, 0.5 / a) / (2.0 * BK_PI);
}

/* D_ashikhmin — Ashikhmin & Premože 2007, "Distribution-based BRDFs", the
 * velvet distribution as Filament's D_Ashikhmin writes it:
 * (1 + 4 exp(-cot²θh / a²) / sin⁴θh) / (π (1 + 4 a²)). At NoH = 1 the
 * exponential wins (exp(-1/(a² s²))/s⁴ -> 0), so D = 1/(π (1 + 4 a²)). */
double bk_D_ashikhmin(double NoH, double a)
{
	double sin2h = (1.0 - NoH) * (1.0 + NoH), a2 = a * a;
	double norm = 1.0 / (BK_PI * (1.0 + 4.0 * a2));
	if (sin2h <= 0.0 || !(a2 > 0.0))
		return norm;
	double cot2 = NoH * NoH / sin2h;
	return norm * (1.0 + 4.0 * exp(-cot2 / a2) / (sin2h * sin2h));
}
