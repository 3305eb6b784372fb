/*
 * diffuse.c — diffuse lobes, with the 1/π included (Lambert = 1/π); the albedo
 * multiplies outside.
 */
#include "brdf.h"

#include <math.h>

/* Fd_lambert — Lambert 1760: 1/π. ∫ Fd NoL dω = 1 (the white furnace). */
double bk_Fd_lambert(void)
{
	return 1.0 / BK_PI;
}

/*
 * Fd_burley — Burley 2012, "Physically-Based Shading at Disney":
 * (1/π)(1 + (f90 - 1)(1 - NoL)^5)(1 + (f90 - 1)(1 - NoV)^5), f90 = 0.5 + 2 r LoH^2,
 * r perceptual. Not energy conserving by design (albedo up to ~1.2 at r = 1).
 */
double bk_Fd_burley(double NoV, double NoL, double LoH, double r)
{
	double f90 = 0.5 + 2.0 * r * LoH * LoH;
	return bk_F_schlick(1.0, f90, NoL) * bk_F_schlick(1.0, f90, NoV) / BK_PI;
}

/*
 * Fd_oren_nayar — Oren & Nayar 1994, "Generalization of Lambert's Reflectance
 * Model", the qualitative model: (1/π)(A + B max(0, cos Δφ) sin α tan β), with
 * A = 1 - 0.5 σ^2/(σ^2 + 0.33), B = 0.45 σ^2/(σ^2 + 0.09), σ the slope-angle
 * deviation in radians. Since cos Δφ sinθv sinθl = VoL - NoV NoL, the angular
 * factor is max(0, VoL - NoV NoL) / max(NoV, NoL): no trigonometry, no 0/0 except
 * at NoV = NoL = 0, where the factor's limit is taken as 0.
 */
double bk_Fd_oren_nayar(double NoV, double NoL, double VoL, double sigma)
{
	double s2 = sigma * sigma;
	double A = 1.0 - 0.5 * s2 / (s2 + 0.33);
	double B = 0.45 * s2 / (s2 + 0.09);
	double m = fmax(NoV, NoL);
	double g = m > 0.0 ? fmax(0.0, VoL - NoV * NoL) / m : 0.0;
	return (A + B * g) / BK_PI;
}
