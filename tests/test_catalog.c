/*
 * test_catalog.c — the catalog of published forms (fit/catalog.c).
 *
 * Every entry's form is parsed and evaluated with its default parameters, and
 * compared with the published formula written out again here in plain C,
 * transcribed from shared/references/approximations.md and the sources' code as
 * quoted there (vector constants as arrays, the sources' own variable names and
 * operation order where they have one) — never from the formula text. The
 * geometry is built here from vectors (N = +Z), not with bk_sample_geometry, and
 * R·L for PhongApprox is computed from the reflected vector, not from the
 * LoH identity the form uses.
 *
 * Tolerance: 1e-12 relative (exact equality where the value is 0) at three
 * generic points of moderate roughness whose condition numbers are small. The
 * edge checks at r = 0.06 near the mirror direction use a looser bound where the
 * form is ill conditioned there, with the reason next to each.
 */
#include "brdf.h"
#include "catalog.h"

#include <criterion/criterion.h>

#include <ctype.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#define PI 3.14159265358979323846

/* ---- helpers ------------------------------------------------------------------- */

static void check_close(double got, double want, double rel, const char *fmt, ...)
{
	double err = fabs(got - want);
	if (got == want || err <= rel * fabs(want))
		return;
	char ctx[256];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(ctx, sizeof ctx, fmt, ap);
	va_end(ap);
	cr_assert_fail("%s: got %.17g, want %.17g (abs err %.3g, rel err %.3g, allowed rel %.3g)", ctx, got,
	               want, err, want != 0.0 ? err / fabs(want) : INFINITY, rel);
}

static double sat(double x) { return x < 0 ? 0 : x > 1 ? 1 : x; }
static double clampd(double x, double lo, double hi) { return x < lo ? lo : x > hi ? hi : x; }
static double lerp(double x, double y, double t) { return x + (y - x) * t; }
static double pow5(double x) { return x * x * x * x * x; }

/* One evaluation point: geometry from angles, material. */
typedef struct pt {
	double NoV, NoL, NoH, LoH, RoL;
	double r, a, f0;
} pt;

static pt make_pt(double theta_v, double theta_l, double phi, double r, double f0)
{
	double V[3] = {sin(theta_v), 0, cos(theta_v)};
	double L[3] = {sin(theta_l) * cos(phi), sin(theta_l) * sin(phi), cos(theta_l)};
	double H[3] = {V[0] + L[0], V[1] + L[1], V[2] + L[2]};
	double h = sqrt(H[0] * H[0] + H[1] * H[1] + H[2] * H[2]);
	for (int i = 0; i < 3; i++)
		H[i] /= h;
	/* R = reflect(-V, N) = 2 (N·V) N - V with N = +Z */
	double R[3] = {-V[0], -V[1], 2 * V[2] * 1.0 - V[2]};
	pt p;
	p.NoV = V[2];
	p.NoL = L[2];
	p.NoH = H[2];
	p.LoH = L[0] * H[0] + L[1] * H[1] + L[2] * H[2];
	p.RoL = R[0] * L[0] + R[1] * L[1] + R[2] * L[2];
	p.r = r;
	p.a = r * r;
	p.f0 = f0;
	return p;
}

/* Evaluates text at the points with params; out[n]. */
static void eval_form(const char *text, const double *params, const pt *p, size_t n, double *out)
{
	bk_form_error err;
	bk_form *f = bk_form_parse(text, &err);
	cr_assert_not_null(f, "parse failed at column %d: %s\n  form: %s", err.column, err.message, text);
	double in[BK_IN_COUNT][8];
	cr_assert_leq(n, 8);
	for (size_t k = 0; k < n; k++) {
		in[BK_IN_NOV][k] = p[k].NoV;
		in[BK_IN_NOL][k] = p[k].NoL;
		in[BK_IN_NOH][k] = p[k].NoH;
		in[BK_IN_LOH][k] = p[k].LoH;
		in[BK_IN_R][k] = p[k].r;
		in[BK_IN_A][k] = p[k].a;
		in[BK_IN_F0][k] = p[k].f0;
	}
	const double *ptrs[BK_IN_COUNT];
	for (int i = 0; i < BK_IN_COUNT; i++)
		ptrs[i] = in[i];
	cr_assert_eq(bk_form_eval(f, BK_F64, n, ptrs, params, out), 0);
	bk_form_free(f);
}

/* ---- the published formulas, by hand ------------------------------------------
 * Each fills out[0] (and out[1] = B for "env" entries, out[0] = A). */

/* The talk: V*F = specColor / ((L·H)^2 (roughness + 0.5)) in its convention (no
 * 1/4: the final BRDF carries 4 in its denominator), roughness = r. */
static void h_vf_talk_r(const pt *p, double *o)
{
	double vf_talk = 1.0 / (p->LoH * p->LoH * (p->r + 0.5));
	o[0] = p->f0 * vf_talk / 4.0;
}
static void h_vf_talk_a(const pt *p, double *o)
{
	double vf_talk = 1.0 / (p->LoH * p->LoH * (p->a + 0.5));
	o[0] = p->f0 * vf_talk / 4.0;
}
/* the printed final BRDF */
static double talk_brdf(double NoH, double LoH, double r, double specColor)
{
	double r4 = r * r * r * r;
	double den = NoH * NoH * (r4 - 1) + 1;
	return r4 / (4 * PI * den * den * LoH * LoH * (r + 0.5)) * specColor;
}
static void h_dvf_talk_r(const pt *p, double *o) { o[0] = talk_brdf(p->NoH, p->LoH, p->r, p->f0); }

/* Unity URP DirectBRDFSpecular: roughness = alpha, π-scaled. */
static double urp_specular_term(double NoH, double LoH, double roughness, double roughness2)
{
	double normalizationTerm = roughness * 4.0 + 2.0;
	double roughness2MinusOne = roughness2 - 1.0;
	double d = NoH * NoH * roughness2MinusOne + 1.00001;
	double LoH2 = LoH * LoH;
	return roughness2 / ((d * d) * fmax(0.1, LoH2) * normalizationTerm);
}
static void h_vf_talk_unity_urp(const pt *p, double *o)
{
	double normalizationTerm = p->a * 4.0 + 2.0;
	o[0] = p->f0 / (fmax(0.1, p->LoH * p->LoH) * normalizationTerm);
}
static void h_dvf_unity_urp(const pt *p, double *o)
{
	o[0] = p->f0 * urp_specular_term(p->NoH, p->LoH, p->a, p->a * p->a) / PI;
}
static void h_dvf_unity_urp_half(const pt *p, double *o)
{
	const double HALF_MIN = 6.103515625e-5, HALF_MIN_SQRT = 0.0078125;
	double roughness = fmax(p->a, HALF_MIN_SQRT);
	double roughness2 = fmax(roughness * roughness, HALF_MIN);
	double s = urp_specular_term(p->NoH, p->LoH, roughness, roughness2);
	s = s - HALF_MIN;
	s = clampd(s, 0.0, 1000.0);
	o[0] = p->f0 * s / PI;
}
/* built-in BRDF2, gamma space: a/(max(0.32, lh)(1.5 + a) d) ≈ sqrt(linear term) */
static void h_dvf_unity_builtin_gamma(const pt *p, double *o)
{
	double a = p->a, a2 = a * a;
	double d = p->NoH * p->NoH * (a2 - 1.0) + 1.00001;
	double specularTerm = a / (fmax(0.32, p->LoH) * (1.5 + a) * d);
	o[0] = p->f0 * specularTerm * specularTerm / PI;
}
/* Unreal PhongApprox, π-scaled, times SpecularColor = f0. */
static double phong_approx(double Roughness, double RoL)
{
	double a = Roughness * Roughness;
	a = fmax(a, 0.008);
	double a2 = a * a;
	double rcp_a2 = 1.0 / a2;
	double c = 0.72134752 * rcp_a2 + 0.39674113;
	double p = rcp_a2 * exp2(c * RoL - c);
	return fmin(p, rcp_a2);
}
static void h_spec_unreal_phongapprox(const pt *p, double *o)
{
	o[0] = p->f0 * phong_approx(p->r, fmax(0.0, p->RoL)) / PI;
}
/* Schüler F = f0/LoH with Kelemen V = 1/(4 LoH^2) */
static void h_fv_schuler(const pt *p, double *o)
{
	double F = p->f0 / p->LoH, V = 1.0 / (4.0 * p->LoH * p->LoH);
	o[0] = F * V;
}

/* ---- V ---- */
static void h_v_hammon(const pt *p, double *o) /* as Unreal's Vis_SmithJointApprox */
{
	double a = p->a;
	double Vis_SmithV = p->NoL * (p->NoV * (1 - a) + a);
	double Vis_SmithL = p->NoV * (p->NoL * (1 - a) + a);
	o[0] = 0.5 / (Vis_SmithV + Vis_SmithL);
}
static void h_v_kelemen(const pt *p, double *o) { o[0] = 1.0 / (4.0 * p->LoH * p->LoH); }
static void h_v_kelemen_unreal(const pt *p, double *o) { o[0] = 1.0 / (4 * p->LoH * p->LoH + 1e-5); }
static void h_v_kelemen_hable(const pt *p, double *o) /* Hable's code, vis without the 1/4 */
{
	double k = p->a / 2.0;
	double k2 = k * k;
	double invK2 = 1.0 - k2;
	double vis = 1.0 / (p->LoH * p->LoH * invK2 + k2);
	o[0] = vis / 4.0;
}
static void h_v_kelemen_talk_r(const pt *p, double *o)
{
	double rough = p->r;
	o[0] = 0.25 * (1.0 / (p->LoH * p->LoH * (1 - rough * rough) + rough * rough));
}
static void h_v_kelemen_talk_a(const pt *p, double *o)
{
	double rough = p->a;
	o[0] = 0.25 * (1.0 / (p->LoH * p->LoH * (1 - rough * rough) + rough * rough));
}

/* ---- F ---- */
static void h_f_schlick_sg(const pt *p, double *o)
{
	double v = p->LoH;
	o[0] = p->f0 + (1 - p->f0) * pow(2.0, (-5.55473 * v - 6.98316) * v);
}
static void h_f_schlick_unreal_gated(const pt *p, double *o)
{
	double Fc = pow5(1 - p->LoH);
	o[0] = sat(50.0 * p->f0) * Fc + (1 - Fc) * p->f0;
}
static void h_f_schlick_filament_gated(const pt *p, double *o)
{
	double w = 50.0 * 0.33; /* dot(f0, vec3(50.0 * 0.33)) with a grey f0 */
	double f90 = sat(p->f0 * w + p->f0 * w + p->f0 * w);
	o[0] = p->f0 + (f90 - p->f0) * pow5(1.0 - p->LoH);
}

/* ---- environment ---- */
static void h_env_talk_r(const pt *p, double *o)
{
	double m = 1 - fmax(p->r, p->NoV);
	o[0] = 1;
	o[1] = m * m * m;
}
static void h_env_talk_a(const pt *p, double *o)
{
	double m = 1 - fmax(p->a, p->NoV);
	o[0] = 1;
	o[1] = m * m * m;
}

/* Karis 2014 EnvBRDFApprox, A and B */
static void karis_ab(double NoV, double Roughness, double *A, double *B)
{
	const double c0[4] = {-1, -0.0275, -0.572, 0.022};
	const double c1[4] = {1, 0.0425, 1.04, -0.04};
	double t[4];
	for (int i = 0; i < 4; i++)
		t[i] = Roughness * c0[i] + c1[i];
	double a004 = fmin(t[0] * t[0], exp2(-9.28 * NoV)) * t[0] + t[1];
	*A = -1.04 * a004 + t[2];
	*B = 1.04 * a004 + t[3];
}
static double karis_env(double NoV, double r, double f0)
{
	double A, B;
	karis_ab(NoV, r, &A, &B);
	return f0 * A + sat(50.0 * f0) * B;
}
static void h_env_karis2014(const pt *p, double *o) { o[0] = karis_env(p->NoV, p->r, p->f0); }
static void h_env_karis2014_split(const pt *p, double *o) { karis_ab(p->NoV, p->r, &o[0], &o[1]); }
static void h_env_karis2014_nonmetal(const pt *p, double *o)
{
	const double c0[2] = {-1, -0.0275}, c1[2] = {1, 0.0425};
	double t0 = p->r * c0[0] + c1[0], t1 = p->r * c0[1] + c1[1];
	o[0] = fmin(t0 * t0, exp2(-9.28 * p->NoV)) * t0 + t1;
}

/* Lazarov 2013 EnvironmentBRDF(g, NoV, rf0) */
static double lazarov_env(double g, double NoV, double rf0)
{
	double t[4] = {1 / 0.96, 0.475, (0.0275 - 0.25 * 0.04) / 0.96, 0.25};
	for (int i = 0; i < 4; i++)
		t[i] *= g;
	const double add[4] = {0, 0, (0.015 - 0.75 * 0.04) / 0.96, 0.75};
	for (int i = 0; i < 4; i++)
		t[i] += add[i];
	double a0 = t[0] * fmin(t[1], exp2(-9.28 * NoV)) + t[2];
	double a1 = t[3];
	return sat(a0 + rf0 * (a1 - a0));
}
static void h_env_lazarov2013_g1mr(const pt *p, double *o) { o[0] = lazarov_env(1 - p->r, p->NoV, p->f0); }
static void h_env_lazarov2013(const pt *p, double *o)
{
	double n = 2 / (p->a * p->a) - 2; /* Blinn-Phong exponent of the same GGX alpha */
	double g = sat(log(n) / log(8192.0)); /* 8192^g = n */
	o[0] = lazarov_env(g, p->NoV, p->f0);
}

/* Narkowicz 2014 EnvDFGLazarov and EnvDFGPolynomial */
static double narkowicz_lazarov(double specularColor, double gloss, double ndotv)
{
	const double p0[4] = {0.5745, 1.548, -0.02397, 1.301};
	const double p1[4] = {0.5753, -0.2511, -0.02066, 0.4755};
	double t[4];
	for (int i = 0; i < 4; i++)
		t[i] = gloss * p0[i] + p1[i];
	double bias = sat(t[0] * fmin(t[1], exp2(-7.672 * ndotv)) + t[2]);
	double delta = sat(t[3]);
	double scale = delta - bias;
	bias *= sat(50.0 * specularColor);
	return specularColor * scale + bias;
}
static double narkowicz_poly(double specularColor, double gloss, double ndotv)
{
	double x = gloss, y = ndotv;
	double b1 = -0.1688, b2 = 1.895, b3 = 0.9903, b4 = -4.853, b5 = 8.404, b6 = -5.069;
	double bias = sat(fmin(b1 * x + b2 * x * x, b3 + b4 * y + b5 * y * y + b6 * y * y * y));
	double d0 = 0.6045, d1 = 1.699, d2 = -0.5228, d3 = -3.603, d4 = 1.404, d5 = 0.1939, d6 = 2.661;
	double delta = sat(d0 + d1 * x + d2 * y + d3 * x * x + d4 * x * y + d5 * y * y + d6 * x * x * x);
	double scale = delta - bias;
	bias *= sat(50.0 * specularColor);
	return specularColor * scale + bias;
}
static void h_env_narkowicz2014_lazarov(const pt *p, double *o)
{
	o[0] = narkowicz_lazarov(p->f0, 1 - sqrt(p->r), p->NoV);
}
static void h_env_narkowicz2014_lazarov_g1mr(const pt *p, double *o)
{
	o[0] = narkowicz_lazarov(p->f0, 1 - p->r, p->NoV);
}
static void h_env_narkowicz2014_poly(const pt *p, double *o) { o[0] = narkowicz_poly(p->f0, 1 - sqrt(p->r), p->NoV); }
static void h_env_narkowicz2014_poly_g1mr(const pt *p, double *o) { o[0] = narkowicz_poly(p->f0, 1 - p->r, p->NoV); }

static void h_env_pesce_iwanicki2015(const pt *p, double *o)
{
	double m = p->a;
	double bias = exp2(-(7 * p->NoV + 4 * m));
	double b = fmin(p->r, 0.739 + 0.323 * p->NoV) - 0.434;
	double scale = 1 - bias - m * fmax(bias, b);
	o[0] = sat(p->f0 * scale + bias);
}
static void h_env_ross(const pt *p, double *o)
{
	double m = p->a;
	double f = pow(1.0 - p->NoV, 5.0 * exp(-2.69 * m)) / (1.0 + 22.7 * pow(m, 1.5));
	o[0] = sat(p->f0 * (1 - f) + f); /* = Rf0 + (1 - Rf0) f, saturated */
}
static void h_env_materialx(const pt *p, double *o)
{
	static const double c[9][4] = {
		{0.1003, 0.9345, 1.0, 1.0},       {-0.6303, -2.323, -1.765, 0.2281}, {9.748, 2.229, 8.263, 15.94},
		{-2.038, -3.748, 11.53, -55.83}, {29.34, 1.424, 28.96, 13.08},      {-8.245, -0.7684, -7.507, 41.26},
		{-26.44, 1.436, -36.11, 54.9},   {19.99, 0.2913, 15.86, 300.2},     {-5.448, 0.6286, 33.37, -285.1},
	};
	double x = p->NoV, y = p->a, x2 = x * x, y2 = y * y;
	double w[9] = {1, x, y, x * y, x2, y2, x2 * y, x * y2, x2 * y2};
	double r[4] = {0, 0, 0, 0};
	for (int k = 0; k < 9; k++)
		for (int i = 0; i < 4; i++)
			r[i] += c[k][i] * w[k];
	o[0] = clampd(r[0] / r[2], 0.0, 1.0);
	o[1] = clampd(r[1] / r[3], 0.0, 1.0);
}
static void h_env_unity_urp(const pt *p, double *o)
{
	double roughness2 = p->a * p->a, smoothness = 1 - p->r, reflectivity = p->f0;
	double surfaceReduction = 1.0 / (roughness2 + 1.0);
	double grazingTerm = sat(smoothness + reflectivity);
	double x = 1 - p->NoV, fresnelTerm = x * x * x * x;
	o[0] = surfaceReduction * lerp(p->f0, grazingTerm, fresnelTerm);
}
static void h_env_unity_builtin_brdf2(const pt *p, double *o)
{
	double perceptualRoughness = p->r, roughness = p->a;
	double surfaceReduction = (0.6 - 0.08 * perceptualRoughness);
	surfaceReduction = 1.0 - roughness * perceptualRoughness * surfaceReduction;
	double grazingTerm = sat((1 - p->r) + p->f0);
	double x = 1 - p->NoV, t = x * x * x * x;
	o[0] = surfaceReduction * lerp(p->f0, grazingTerm, t);
}

/* ms: each source's environment BRDF evaluated at f0 = 1 (E = A + B there),
 * through the hand functions above with f0 set, not from the entries' text. */
static pt at_f0_1(const pt *p)
{
	pt q = *p;
	q.f0 = 1.0;
	return q;
}
static void h_ms_materialx(const pt *p, double *o)
{
	double ab[2];
	h_env_materialx(p, ab);
	o[0] = ab[0] + ab[1]; /* mx_ggx_dir_albedo(NdotV, alpha, F0 = 1, F90 = 1) */
}
static void h_ms_karis2014(const pt *p, double *o) { o[0] = karis_env(p->NoV, p->r, 1.0); }
static void h_ms_narkowicz2014_poly(const pt *p, double *o)
{
	pt q = at_f0_1(p);
	h_env_narkowicz2014_poly(&q, o);
}
static void h_ms_pesce_iwanicki2015(const pt *p, double *o)
{
	pt q = at_f0_1(p);
	h_env_pesce_iwanicki2015(&q, o);
}

/* MaterialX mx_imageworks_sheen_dir_albedo_curve_fit(NdotV, roughness), its
 * vec2 constants as pairs, clamped as mx_imageworks_sheen_dir_albedo does;
 * MaterialX's roughness is the Charlie a = r^2. */
static void h_sheen_materialx(const pt *p, double *o)
{
	static const double c[6][2] = {{13.67300, 1.0},         {-68.78018, 61.57746},  {799.08825, 442.78211},
	                               {-905.00061, 2597.49308}, {60.28956, 121.81241}, {1086.96473, 3045.55075}};
	double NdotV = p->NoV, roughness = p->a;
	double w[6] = {1, NdotV, roughness, NdotV * roughness, NdotV * NdotV, roughness * roughness};
	double r[2] = {0, 0};
	for (int k = 0; k < 6; k++)
		for (int i = 0; i < 2; i++)
			r[i] += c[k][i] * w[k];
	o[0] = clampd(r[0] / r[1], 0.0, 1.0);
}

static const struct hand {
	const char *name;
	void (*fn)(const pt *, double *);
} hands[] = {
	{"vf_talk_r", h_vf_talk_r},
	{"vf_talk_a", h_vf_talk_a},
	{"dvf_talk_r", h_dvf_talk_r},
	{"vf_talk_unity_urp", h_vf_talk_unity_urp},
	{"dvf_unity_urp", h_dvf_unity_urp},
	{"dvf_unity_urp_half", h_dvf_unity_urp_half},
	{"dvf_unity_builtin_gamma", h_dvf_unity_builtin_gamma},
	{"spec_unreal_phongapprox", h_spec_unreal_phongapprox},
	{"fv_schuler", h_fv_schuler},
	{"v_hammon", h_v_hammon},
	{"v_kelemen", h_v_kelemen},
	{"v_kelemen_unreal", h_v_kelemen_unreal},
	{"v_kelemen_hable", h_v_kelemen_hable},
	{"v_kelemen_talk_r", h_v_kelemen_talk_r},
	{"v_kelemen_talk_a", h_v_kelemen_talk_a},
	{"f_schlick_sg", h_f_schlick_sg},
	{"f_schlick_unreal_gated", h_f_schlick_unreal_gated},
	{"f_schlick_filament_gated", h_f_schlick_filament_gated},
	{"env_talk_r", h_env_talk_r},
	{"env_talk_a", h_env_talk_a},
	{"env_karis2014", h_env_karis2014},
	{"env_karis2014_split", h_env_karis2014_split},
	{"env_karis2014_nonmetal", h_env_karis2014_nonmetal},
	{"env_lazarov2013_g1mr", h_env_lazarov2013_g1mr},
	{"env_lazarov2013", h_env_lazarov2013},
	{"env_narkowicz2014_lazarov", h_env_narkowicz2014_lazarov},
	{"env_narkowicz2014_lazarov_g1mr", h_env_narkowicz2014_lazarov_g1mr},
	{"env_narkowicz2014_poly", h_env_narkowicz2014_poly},
	{"env_narkowicz2014_poly_g1mr", h_env_narkowicz2014_poly_g1mr},
	{"env_pesce_iwanicki2015", h_env_pesce_iwanicki2015},
	{"env_ross", h_env_ross},
	{"env_materialx", h_env_materialx},
	{"env_unity_urp", h_env_unity_urp},
	{"env_unity_builtin_brdf2", h_env_unity_builtin_brdf2},
	{"ms_materialx", h_ms_materialx},
	{"ms_karis2014", h_ms_karis2014},
	{"ms_narkowicz2014_poly", h_ms_narkowicz2014_poly},
	{"ms_pesce_iwanicki2015", h_ms_pesce_iwanicki2015},
	{"sheen_materialx", h_sheen_materialx},
};
#define NHANDS (sizeof hands / sizeof hands[0])

static const struct hand *hand_for(const char *name)
{
	for (size_t i = 0; i < NHANDS; i++)
		if (strcmp(hands[i].name, name) == 0)
			return &hands[i];
	return NULL;
}

/* Three generic points: G1 a dielectric near normal view (Karis's exp2 branch),
 * G2 grazing view of a rough metal (t.x^2 branch, Unity's grazing term clamped,
 * Pesce's b branch), G3 light and view nearly opposite (LoH^2 < 0.1: Unity's
 * floor and the gamma variant's max(0.32, LoH) act) with f0 < 0.02 (the
 * saturate(50 f0) gates act). */
static void generic_points(pt p[3])
{
	p[0] = make_pt(0.3, 0.9, 0.7, 0.35, 0.04);
	p[1] = make_pt(1.2, 0.4, 2.5, 0.8, 0.9);
	p[2] = make_pt(1.3, 1.35, 2.9, 0.55, 0.012);
}

/* Evaluates entry e (A or B) at the points with its defaults. */
static void eval_entry(const bk_catalog_entry *e, int b, const pt *p, size_t n, double *out)
{
	eval_form(b ? e->form_b : e->form, e->defaults, p, n, out);
}

/* ---- the catalog's shape ---------------------------------------------------------- */

Test(catalog, at_least_15_entries_unique_lowercase_names)
{
	size_t n = bk_catalog_count();
	cr_assert_geq(n, 15, "only %zu entries", n);
	for (size_t i = 0; i < n; i++) {
		const bk_catalog_entry *e = bk_catalog_at(i);
		cr_assert_not_null(e);
		cr_assert_not_null(e->name);
		cr_assert_gt(strlen(e->name), 0);
		for (const char *s = e->name; *s; s++)
			cr_assert(islower((unsigned char)*s) || isdigit((unsigned char)*s) || *s == '_',
			          "%s: name must be lowercase [a-z0-9_]", e->name);
		for (size_t j = 0; j < i; j++)
			cr_assert_str_neq(e->name, bk_catalog_at(j)->name, "duplicate name %s", e->name);
		cr_assert_eq(bk_catalog_find(e->name), e, "find(%s)", e->name);
	}
	cr_assert_null(bk_catalog_at(n));
	cr_assert_null(bk_catalog_find("no_such_entry"));
	cr_assert_null(bk_catalog_find(""));
}

Test(catalog, every_entry_has_source_convention_and_a_valid_target)
{
	static const char *const targets[] = {"D", "V", "F", "VF", "DVF", "env", "env_f0", "ms", "sheen"};
	for (size_t i = 0; i < bk_catalog_count(); i++) {
		const bk_catalog_entry *e = bk_catalog_at(i);
		cr_assert(e->source && strlen(e->source) > 10, "%s: no source", e->name);
		cr_assert(e->convention && strlen(e->convention) > 10, "%s: no convention", e->name);
		int ok = 0;
		for (size_t k = 0; k < sizeof targets / sizeof targets[0]; k++)
			ok |= e->target && strcmp(e->target, targets[k]) == 0;
		cr_assert(ok, "%s: target '%s'", e->name, e->target ? e->target : "(null)");
		cr_assert_not_null(e->form, "%s: no form", e->name);
		if (strcmp(e->target, "env") == 0)
			cr_assert_not_null(e->form_b, "%s: env entry without B", e->name);
		else
			cr_assert_null(e->form_b, "%s: form_b set on a %s entry", e->name, e->target);
		cr_assert(e->nparams >= 0 && e->nparams <= BK_MAX_PARAMS, "%s: nparams %d", e->name, e->nparams);
	}
}

/* Sources the reference marks unverified say so. */
Test(catalog, unverified_sources_say_so)
{
	static const char *const unverified[] = {
		"v_hammon", "fv_schuler", "env_lazarov2013_g1mr", "env_lazarov2013",
		"env_talk_r", "env_talk_a", "env_ross",
	};
	for (size_t i = 0; i < sizeof unverified / sizeof unverified[0]; i++) {
		const bk_catalog_entry *e = bk_catalog_find(unverified[i]);
		cr_assert_not_null(e, "%s missing", unverified[i]);
		cr_assert_not_null(strstr(e->source, "unverified"), "%s: source must say unverified", e->name);
	}
}

/* Every form parses; it uses no parameter beyond the entry's nparams, and the
 * entry declares none that its forms leave unused. */
Test(catalog, forms_parse_and_parameter_counts_match)
{
	for (size_t i = 0; i < bk_catalog_count(); i++) {
		const bk_catalog_entry *e = bk_catalog_at(i);
		int used = 0;
		for (int b = 0; b < 2; b++) {
			const char *text = b ? e->form_b : e->form;
			if (!text)
				continue;
			bk_form_error err;
			bk_form *f = bk_form_parse(text, &err);
			cr_assert_not_null(f, "%s (%s): parse error at column %d: %s", e->name, b ? "B" : "A", err.column,
			                   err.message);
			int np = bk_form_nparams(f);
			cr_assert_leq(np, e->nparams, "%s: form uses %d parameters, entry has %d", e->name, np, e->nparams);
			if (np > used)
				used = np;
			bk_form_free(f);
		}
		cr_assert_eq(used, e->nparams, "%s: entry declares %d parameters, forms use %d", e->name, e->nparams,
		             used);
	}
}

/* ---- every entry against its published formula ---------------------------------- */

Test(catalog, every_entry_has_a_hand_check)
{
	for (size_t i = 0; i < bk_catalog_count(); i++)
		cr_assert_not_null(hand_for(bk_catalog_at(i)->name), "%s: no hand formula in the test",
		                   bk_catalog_at(i)->name);
	for (size_t i = 0; i < NHANDS; i++)
		cr_assert_not_null(bk_catalog_find(hands[i].name), "hand formula %s has no entry", hands[i].name);
}

Test(catalog, every_entry_matches_the_published_formula)
{
	pt p[3];
	generic_points(p);
	for (size_t i = 0; i < bk_catalog_count(); i++) {
		const bk_catalog_entry *e = bk_catalog_at(i);
		const struct hand *h = hand_for(e->name);
		cr_assert_not_null(h);
		int is_env = strcmp(e->target, "env") == 0;
		for (int b = 0; b <= is_env; b++) {
			double got[3];
			eval_entry(e, b, p, 3, got);
			for (int k = 0; k < 3; k++) {
				double want[2];
				h->fn(&p[k], want);
				cr_assert(isfinite(want[b]), "%s: hand value not finite at G%d", e->name, k + 1);
				check_close(got[k], want[b], 1e-12, "%s %s at G%d", e->name, is_env ? (b ? "B" : "A") : "",
				            k + 1);
			}
		}
	}
}

/* The generic points exercise what they claim to (so the branches above are
 * really compared). */
Test(catalog, generic_points_reach_the_branches)
{
	pt p[3];
	generic_points(p);
	double t0 = 1 - p[0].r, t1 = 1 - p[1].r;
	cr_assert_gt(t0 * t0, exp2(-9.28 * p[0].NoV));
	cr_assert_lt(t1 * t1, exp2(-9.28 * p[1].NoV));
	cr_assert_lt(p[2].LoH * p[2].LoH, 0.1);
	cr_assert_lt(p[2].LoH, 0.32);
	cr_assert_lt(50 * p[2].f0, 1);
	cr_assert_gt(1 - p[1].r + p[1].f0, 1);
	cr_assert_gt(fmin(p[1].r, 0.739 + 0.323 * p[1].NoV) - 0.434, exp2(-(7 * p[1].NoV + 4 * p[1].a)));
	for (int k = 0; k < 3; k++) {
		cr_assert_gt(p[k].LoH, 0);
		cr_assert_gt(p[k].NoH, 0);
	}
}

/* ---- published check values and the talk's printed BRDF -------------------------- */

/* Unreal's comment: EnvBRDFApprox at r = 1, NoV = 1 equals 0.4524 f0 - 0.0024. */
Test(catalog, karis_env_published_check_value)
{
	pt p[3];
	for (int k = 0; k < 3; k++) {
		p[k] = make_pt(0, 0.5, 0, 1.0, (double[]){0.04, 0.5, 1.0}[k]);
		cr_assert_eq(p[k].NoV, 1.0);
	}
	const bk_catalog_entry *e = bk_catalog_find("env_karis2014_split");
	cr_assert_not_null(e);
	double A[3], B[3];
	eval_entry(e, 0, p, 3, A);
	eval_entry(e, 1, p, 3, B);
	check_close(A[0], 0.4524, 1e-12, "EnvBRDFApprox A(NoV=1, r=1)");
	check_close(B[0], -0.0024, 1e-12, "EnvBRDFApprox B(NoV=1, r=1)");

	e = bk_catalog_find("env_karis2014");
	cr_assert_not_null(e);
	double v[3];
	eval_entry(e, 0, p, 3, v);
	for (int k = 0; k < 3; k++) /* f0 >= 0.02: the gate is 1 */
		check_close(v[k], 0.4524 * p[k].f0 - 0.0024, 1e-12, "EnvBRDFApprox(f0=%g, NoV=1, r=1)", p[k].f0);
}

/* The same printed check at f0 = 1 is the directional albedo ms_karis2014
 * claims: 0.4524 - 0.0024 = 0.45 at r = 1, NoV = 1; control: at r = 0.5 the
 * entry is 1 - 0.55 r = 0.725, not 0.45. */
Test(catalog, ms_karis_published_check_value)
{
	pt p[2] = {make_pt(0, 0.5, 0, 1.0, 0.04), make_pt(0, 0.5, 0, 0.5, 0.04)};
	const bk_catalog_entry *e = bk_catalog_find("ms_karis2014");
	cr_assert_not_null(e);
	double v[2];
	eval_entry(e, 0, p, 2, v);
	check_close(v[0], 0.4524 - 0.0024, 1e-12, "EnvBRDFApprox(1, r=1, NoV=1)");
	cr_assert_gt(fabs(v[1] - 0.45), 0.2, "control: r = 0.5 gives %g", v[1]);
	check_close(v[1], 0.725, 1e-12, "1 - 0.55 r at r = 0.5");
}

/* The talk's printed final BRDF = D_ggx(NoH, a) * (the V*F entry): its 4π is
 * GGX D's π and V's 1/4; its roughness^4 = a^2 with a = r^2. */
Test(catalog, talk_vf_times_ggx_is_the_printed_brdf)
{
	pt p[3];
	generic_points(p);
	const bk_term *D = bk_term_find("D_ggx");
	cr_assert_not_null(D);
	double vf[3], dvf[3];
	eval_entry(bk_catalog_find("vf_talk_r"), 0, p, 3, vf);
	eval_entry(bk_catalog_find("dvf_talk_r"), 0, p, 3, dvf);
	for (int k = 0; k < 3; k++) {
		bk_sample s = {0};
		s.NoV = p[k].NoV;
		s.NoL = p[k].NoL;
		s.NoH = p[k].NoH;
		s.LoH = p[k].LoH;
		bk_sample_roughness(&s, p[k].r);
		double printed = talk_brdf(p[k].NoH, p[k].LoH, p[k].r, p[k].f0);
		check_close(D->eval(&s) * vf[k], printed, 1e-12, "D_ggx * vf_talk_r vs printed BRDF at G%d", k + 1);
		check_close(dvf[k], printed, 1e-12, "dvf_talk_r vs printed BRDF at G%d", k + 1);
	}
}

/* Unity's DVF is D_ggx times its V*F entry once its d offset 1.00001 is set to 1
 * (the parameters really are the constants), and differs by about 1e-5 relative
 * otherwise (more near the highlight). */
Test(catalog, unity_dvf_is_ggx_times_unity_vf)
{
	pt p[3];
	generic_points(p);
	const bk_term *D = bk_term_find("D_ggx");
	const bk_catalog_entry *vf = bk_catalog_find("vf_talk_unity_urp");
	const bk_catalog_entry *dvf = bk_catalog_find("dvf_unity_urp");
	cr_assert(D && vf && dvf);
	double params[BK_MAX_PARAMS];
	memcpy(params, dvf->defaults, sizeof params);
	params[3] = 1.0;
	double v[3], d1[3], d0[3];
	eval_entry(vf, 0, p, 3, v);
	eval_form(dvf->form, params, p, 3, d1);
	eval_entry(dvf, 0, p, 3, d0);
	for (int k = 0; k < 3; k++) {
		bk_sample s = {0};
		s.NoH = p[k].NoH;
		bk_sample_roughness(&s, p[k].r);
		double want = D->eval(&s) * v[k];
		check_close(d1[k], want, 1e-12, "dvf_unity_urp(p3 = 1) vs D_ggx * vf_talk_unity_urp at G%d", k + 1);
		cr_assert(fabs(d0[k] / want - 1) > 1e-7 && fabs(d0[k] / want - 1) < 1e-3,
		          "the 1.00001 offset should matter slightly at G%d: ratio %.12g", k + 1, d0[k] / want);
	}
}

/* ---- edge checks: floors, clamps and gates -------------------------------------- */

/* r = 0.06 at the mirror direction: Unity's fp16 floors (a < 2^-7) and its
 * clamp to 1000 act, and PhongApprox's max(r^2, 0.008) and min(p, 1/a^2) act. */
Test(catalog, floors_and_clamps_at_a_sharp_highlight)
{
	pt p[1] = {make_pt(0.5, 0.5, PI, 0.06, 0.5)};
	cr_assert_lt(p[0].a, 0.0078125);
	cr_assert_lt(p[0].a, 0.008);

	/* Unity half: the clamp gives exactly 1000 f0/π. */
	double v, want[2];
	eval_entry(bk_catalog_find("dvf_unity_urp_half"), 0, p, 1, &v);
	h_dvf_unity_urp_half(&p[0], want);
	check_close(want[0], 1000 * p[0].f0 / PI, 1e-15, "hand Unity half clamp");
	check_close(v, want[0], 1e-15, "dvf_unity_urp_half at the clamp");

	/* PhongApprox at R·L = 1 ± 1 ulp: min(p, 1/a^2) gives 1/0.008^2. The form
	 * computes R·L = 2 NoV NoL - 2 LoH^2 + 1, the hand from the reflected vector;
	 * they may differ by an ulp, amplified by c ln 2 ≈ 7.8e3 in the exponent (c =
	 * 0.72134752/0.008^2): hence 1e-10, not 1e-12. */
	eval_entry(bk_catalog_find("spec_unreal_phongapprox"), 0, p, 1, &v);
	h_spec_unreal_phongapprox(&p[0], want);
	check_close(want[0], p[0].f0 / (0.008 * 0.008) / PI, 1e-10, "hand PhongApprox peak with the floor");
	check_close(v, want[0], 1e-10, "spec_unreal_phongapprox at the peak");
}

/* Lazarov's Blinn-Phong gloss reading at r = 1: exponent 2/a^2 - 2 = 0, log2 0 =
 * -inf, g = 0 (no NaN); at r = 0.1 the exponent 19998 > 8192 gives g = 1. */
Test(catalog, lazarov_gloss_reading_limits)
{
	pt p[2] = {make_pt(0.7, 0.2, 1.0, 1.0, 0.3), make_pt(0.7, 0.2, 1.0, 0.1, 0.3)};
	double v[2];
	const bk_catalog_entry *e = bk_catalog_find("env_lazarov2013");
	eval_entry(e, 0, p, 2, v);
	check_close(v[0], lazarov_env(0.0, p[0].NoV, 0.3), 1e-12, "g = 0 at r = 1");
	check_close(v[1], lazarov_env(1.0, p[1].NoV, 0.3), 1e-12, "g = 1 at r = 0.1");
	for (int k = 0; k < 2; k++)
		cr_assert(isfinite(v[k]));
}

/* The non-metal Karis variant is EnvBRDFApprox at f0 = 0.04 to within the
 * 0.0016 - 0.00088 r offset its derivation drops (and q's 0.9984 weight). */
Test(catalog, karis_nonmetal_is_close_to_f0_004)
{
	pt p[3];
	generic_points(p);
	for (int k = 0; k < 3; k++)
		p[k].f0 = 0.04;
	double nm[3], full[3];
	eval_entry(bk_catalog_find("env_karis2014_nonmetal"), 0, p, 3, nm);
	eval_entry(bk_catalog_find("env_karis2014"), 0, p, 3, full);
	for (int k = 0; k < 3; k++)
		cr_assert_lt(fabs(nm[k] - full[k]), 3e-3, "G%d: nonmetal %.6g vs EnvBRDFApprox(0.04) %.6g", k + 1, nm[k],
		             full[k]);
}

/* The split Karis entry equals the gated one wherever the gate is 1. */
Test(catalog, karis_split_equals_gated_above_2_percent)
{
	pt p[3];
	generic_points(p);
	p[2].f0 = 0.3;
	const bk_catalog_entry *s = bk_catalog_find("env_karis2014_split");
	double A[3], B[3], g[3];
	eval_entry(s, 0, p, 3, A);
	eval_entry(s, 1, p, 3, B);
	eval_entry(bk_catalog_find("env_karis2014"), 0, p, 3, g);
	for (int k = 0; k < 3; k++)
		check_close(g[k], p[k].f0 * A[k] + B[k], 1e-12, "G%d", k + 1);
}

/* bk_catalog_form: every entry by its name is its form text with its published
 * constants (those past nparams 0), and the talk's V·F at one point is its
 * printed f0/(4 LoH^2 (r + 0.5)) by hand; an unknown name is an error naming
 * it, and a form parsed from the text alone (not a catalog name) is refused
 * (the control: bk_form_parse does not know the catalog). */
Test(catalog, form_by_name)
{
	for (size_t i = 0; i < bk_catalog_count(); i++) {
		const bk_catalog_entry *e = bk_catalog_at(i);
		double p[BK_MAX_PARAMS];
		bk_form_error fe;
		bk_form *f = bk_catalog_form(e->name, p, &fe);
		cr_assert(f, "%s: %s", e->name, fe.message);
		cr_expect_str_eq(bk_form_text(f), e->form);
		for (int k = 0; k < BK_MAX_PARAMS; k++)
			cr_expect_eq(p[k], k < e->nparams ? e->defaults[k] : 0, "%s p%d", e->name, k);
		bk_form_free(f);
	}
	double p[BK_MAX_PARAMS], loh = 0.6, r = 0.3, f0 = 0.04, v = -1;
	bk_form_error fe;
	bk_form *f = bk_catalog_form("vf_talk_r", p, &fe);
	const double *in[BK_IN_COUNT] = {0};
	in[BK_IN_LOH] = &loh, in[BK_IN_R] = &r, in[BK_IN_F0] = &f0;
	cr_assert(f && bk_form_eval(f, BK_F64, 1, in, p, &v) == 0);
	double want = 0.04 / (4 * 0.6 * 0.6 * (0.3 + 0.5));
	cr_expect(fabs(v - want) <= 2e-16 * want, "%.17g vs %.17g", v, want);
	bk_form_free(f);
	cr_expect_null(bk_catalog_form("zz_none", NULL, &fe));
	cr_expect_str_eq(fe.message, "unknown catalog form 'zz_none'");
	cr_expect_eq(fe.column, 0);
	cr_expect_null(bk_form_parse("vf_talk_r", &fe));
}
