/*
 * visibility.c — published approximations of V = G / (4 NoL NoV).
 *
 * Every function here returns V with the 1/4 included, whatever its source
 * printed; each comment says what the source wrote and how it was normalised.
 * The exact Smith visibilities live with their distribution (ggx.c).
 */
#include "brdf.h"

#include <math.h>

/*
 * V_schlick_ggx — Schlick 1994's G1 form with GGX-matched k (Karis 2013):
 * 0.25 / ((NoV (1 - k) + k)(NoL (1 - k) + k)). Finite for k > 0 at any angle.
 */
double bk_V_schlick_ggx(double NoV, double NoL, double k)
{
	return 0.25 / ((NoV * (1.0 - k) + k) * (NoL * (1.0 - k) + k));
}

/* V_schlick_ggx_ibl — Karis 2013, "Real Shading in Unreal Engine 4": k = a/2
 * (Unreal's Vis_Schlick; the k used for image-based lighting). */
double bk_V_schlick_ggx_ibl(double NoV, double NoL, double a)
{
	return bk_V_schlick_ggx(NoV, NoL, 0.5 * a);
}

/* V_schlick_ggx_direct — Karis 2013 course notes (unverified; as LearnOpenGL
 * reproduces it): the "hotness" remap k = (r + 1)^2 / 8 for analytic lights,
 * later dropped by Unreal. Takes perceptual r. */
double bk_V_schlick_ggx_direct(double NoV, double NoL, double r)
{
	return bk_V_schlick_ggx(NoV, NoL, (r + 1.0) * (r + 1.0) / 8.0);
}

/*
 * V_kelemen — Kelemen & Szirmay-Kalos 2001, "A Microfacet Based Coupled
 * Specular-Matte BRDF Model with Importance Sampling": G / (NoL NoV) ≈ 1/LoH^2,
 * so V = 0.25 / LoH^2. Independent of roughness. Infinite at LoH = 0 (only
 * reached for V and L opposite; Unreal adds 1e-5 to 4 LoH^2).
 */
double bk_V_kelemen(double LoH)
{
	return 0.25 / (LoH * LoH);
}

/*
 * V_kelemen_hable — Hable 2014, "Optimizing GGX Shaders with dot(L,H)":
 * k = a/2, vis = 1 / (LoH^2 (1 - k^2) + k^2). Hable's vis leaves out the 1/4;
 * here V = vis / 4. Bounded by 0.25/k^2 at LoH = 0.
 */
double bk_V_kelemen_hable(double LoH, double a)
{
	double k2 = 0.25 * a * a;
	return 0.25 / (LoH * LoH * (1.0 - k2) + k2);
}

/*
 * V_kelemen_talk — the modified KSK as the mobile talk prints it (Unity,
 * "Optimizing PBR for Mobile", SIGGRAPH 2015 course, seed 001):
 * 1 / (LoH^2 (1 - roughness^2) + roughness^2), with the talk's "roughness" read as
 * perceptual r (its GGX uses roughness^4 = a2). The talk's V omits the 1/4 (its
 * final BRDF carries 4π explicitly); here V = 0.25 / (...).
 */
double bk_V_kelemen_talk(double LoH, double r)
{
	double r2 = r * r;
	return 0.25 / (LoH * LoH * (1.0 - r2) + r2);
}

/* V_neubelt — Neubelt & Pettineo 2013, "Crafting a Next-Gen Material Pipeline for
 * The Order: 1886": 1 / (4 (NoL + NoV - NoL NoV)). Infinite only at NoL = NoV = 0. */
double bk_V_neubelt(double NoV, double NoL)
{
	return 0.25 / (NoL + NoV - NoL * NoV);
}

/* V_neumann — Neumann et al. 1999, as Unreal's Vis_Neumann: 1 / (4 max(NoL, NoV)). */
double bk_V_neumann(double NoV, double NoL)
{
	return 0.25 / fmax(NoL, NoV);
}

/* V_implicit — G = NoL NoV, so V = 1/4 (Hoffman 2010's "implicit" geometry term). */
double bk_V_implicit(void)
{
	return 0.25;
}

/*
 * V_cook_torrance — Cook & Torrance 1982, "A Reflectance Model for Computer
 * Graphics": G = min(1, 2 NoH NoV / VoH, 2 NoH NoL / VoH). Divided by 4 NoL NoV
 * term by term, V = min(1/(4 NoL NoV), NoH / (2 VoH max(NoL, NoV))), which has no
 * 0/0 at grazing angles.
 */
double bk_V_cook_torrance(double NoV, double NoL, double NoH, double VoH)
{
	double v_flat = 0.25 / (NoL * NoV);
	double v_mask = NoH / (2.0 * VoH * fmax(NoL, NoV));
	return fmin(v_flat, v_mask);
}

/*
 * V_hammon — Hammon 2017, "PBR Diffuse Lighting for GGX+Smith Microsurfaces"
 * (slides unverified; quoted by Filament; identical to Unreal's
 * Vis_SmithJointApprox): 0.5 / mix(2 NoL NoV, NoL + NoV, a).
 */
double bk_V_hammon(double NoV, double NoL, double a)
{
	return 0.5 / (2.0 * NoL * NoV * (1.0 - a) + (NoL + NoV) * a);
}

/* The visibility of each Smith model the split sum is tabulated for: one
 * switch shared by the Hammersley bake (dfg.c) and the integrator
 * (integrate.c), which both call down to here. */
double bk_V_smith(bk_smith m, double NoV, double NoL, double a)
{
	switch (m) {
	case BK_SMITH_SEPARABLE: return bk_V_smith_ggx_separable(NoV, NoL, a);
	case BK_SMITH_SCHLICK: return bk_V_schlick_ggx_ibl(NoV, NoL, a);
	default: return bk_V_smith_ggx_correlated(NoV, NoL, a);
	}
}
