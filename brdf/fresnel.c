/*
 * fresnel.c — Fresnel reflectance: Schlick and its approximations, and the exact
 * dielectric and conductor equations they approximate.
 *
 * Exact forms: Born & Wolf, "Principles of Optics", §1.5 (dielectric), and the
 * closed form for a complex index used by pbrt-v3's FrConductor (Lagarde 2013,
 * "Memo on Fresnel equations"). All reflectances are for unpolarised light.
 */
#include "brdf.h"

#include <math.h>

/* F_schlick — Schlick 1994, "An Inexpensive BRDF Model for Physically-based
 * Rendering": f0 + (f90 - f0)(1 - LoH)^5. The power is two squarings and a
 * multiply, as a shader writes it. */
double bk_F_schlick(double f0, double f90, double LoH)
{
	double m = 1.0 - LoH;
	double m2 = m * m;
	return f0 + (f90 - f0) * m2 * m2 * m;
}

/* F_schlick_sg — Karis 2013, "Real Shading in Unreal Engine 4": (1 - LoH)^5 ≈
 * exp2((-5.55473 LoH - 6.98316) LoH), a spherical-Gaussian fit; published cost
 * "1 mad, 1 mul, 1 exp". At LoH = 0.5: 0.03395 against 0.03125. */
double bk_F_schlick_sg(double f0, double f90, double LoH)
{
	return f0 + (f90 - f0) * bk_dexp2((-5.55473 * LoH - 6.98316) * LoH);
}

/* F_schuler — Schüler 2009, ShaderX7 ch. 2.5 (as the mobile talk quotes it; primary
 * text unverified): F ≈ f0 / LoH, meant to pair with Kelemen's V. Unbounded as
 * LoH -> 0 and above 1 for LoH < f0: it is not a reflectance on its own. */
double bk_F_schuler(double f0, double LoH)
{
	return f0 / LoH;
}

/*
 * Exact dielectric reflectance, s and p polarisations, for relative index
 * eta = n_t / n_i. Total internal reflection (eta < 1 past the critical angle)
 * gives Rs = Rp = 1. Zero p-reflectance at Brewster's angle tan θ = eta.
 */
void bk_fresnel_dielectric_sp(double cos_i, double eta, double *Rs, double *Rp)
{
	if (isinf(eta)) { /* f0 = 1: the perfect mirror, the limit of the formula */
		*Rs = *Rp = 1.0;
		return;
	}
	cos_i = fmin(fmax(cos_i, 0.0), 1.0);
	double sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
	if (sin2_t >= 1.0) {
		*Rs = *Rp = 1.0;
		return;
	}
	double cos_t = sqrt(1.0 - sin2_t);
	double rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
	double rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
	*Rs = rs * rs;
	*Rp = rp * rp;
}

/* F_dielectric — the unpolarised mean (Rs + Rp)/2. */
double bk_F_dielectric(double cos_i, double eta)
{
	double Rs, Rp;
	bk_fresnel_dielectric_sp(cos_i, eta, &Rs, &Rp);
	return 0.5 * (Rs + Rp);
}

/*
 * F_conductor — exact reflectance of a conductor with complex index eta + i k
 * seen from a medium of index 1 (Lagarde 2013, the form of pbrt-v3 FrConductor).
 * With k = 0 and eta > 1 it equals F_dielectric (tested).
 */
double bk_F_conductor(double cos_i, double eta, double k)
{
	if (isinf(eta) || isinf(k))
		return 1.0; /* the perfect mirror, the limit of the formula */
	cos_i = fmin(fmax(cos_i, 0.0), 1.0);
	double cos2 = cos_i * cos_i, sin2 = 1.0 - cos2;
	double eta2 = eta * eta, k2 = k * k;
	double t0 = eta2 - k2 - sin2;
	double a2b2 = sqrt(t0 * t0 + 4.0 * eta2 * k2);
	double t1 = a2b2 + cos2;
	double a = sqrt(fmax(0.0, 0.5 * (a2b2 + t0)));
	double t2 = 2.0 * cos_i * a;
	double Rs = (t1 - t2) / (t1 + t2);
	double t3 = cos2 * a2b2 + sin2 * sin2;
	double t4 = t2 * sin2;
	double Rp = Rs * (t3 - t4) / (t3 + t4);
	return 0.5 * (Rs + Rp);
}

/* Normal incidence: ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2). */
double bk_f0_from_ior(double eta, double k)
{
	return ((eta - 1.0) * (eta - 1.0) + k * k) / ((eta + 1.0) * (eta + 1.0) + k * k);
}

/* The inverse for k = 0: n = (1 + sqrt f0)/(1 - sqrt f0) (Unreal's F_Fresnel, which
 * clamps f0 to 0.99 to keep n finite; here the caller must pass f0 < 1). */
double bk_ior_from_f0(double f0)
{
	double s = sqrt(f0);
	return (1.0 + s) / (1.0 - s);
}
