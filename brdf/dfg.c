/*
 * dfg.c — the split-sum environment BRDF as engines bake it, the LUT, and the
 * Smith model names.
 *
 * The Hammersley bake follows Karis 2013 ("Real Shading in Unreal Engine 4",
 * IntegrateBRDF): H importance-sampled from D NoH, L = reflect(-V, H), and each
 * sample weighs V · NoL · 4 VoH / NoH (the pdf of L is D NoH / (4 VoH)).
 */
#include "brdf.h"

#include <math.h>
#include <string.h>

static const char *const smith_names[BK_SMITH_COUNT] = {"correlated", "separable", "schlick"};

const char *bk_smith_name(bk_smith m)
{
	return (unsigned)m < BK_SMITH_COUNT ? smith_names[m] : "?";
}

int bk_smith_parse(const char *s, bk_smith *out)
{
	for (int m = 0; m < BK_SMITH_COUNT; m++)
		if (strcmp(s, smith_names[m]) == 0) {
			*out = (bk_smith)m;
			return 0;
		}
	return -1;
}

/* Van der Corput radical inverse in base 2: the bits of i mirrored about the
 * binary point (exact in double for 32-bit i). */
static double radical_inverse2(unsigned i)
{
	i = (i << 16) | (i >> 16);
	i = ((i & 0x55555555u) << 1) | ((i & 0xAAAAAAAAu) >> 1);
	i = ((i & 0x33333333u) << 2) | ((i & 0xCCCCCCCCu) >> 2);
	i = ((i & 0x0F0F0F0Fu) << 4) | ((i & 0xF0F0F0F0u) >> 4);
	i = ((i & 0x00FF00FFu) << 8) | ((i & 0xFF00FF00u) >> 8);
	return (double)i * 0x1p-32;
}

int bk_dfg_hammersley(double NoV, double r, bk_smith m, unsigned n, double *A,
                      double *B)
{
	if (!(NoV > 0.0 && NoV <= 1.0) || !(r >= 0.0 && r <= 1.0) || n == 0 ||
	    (unsigned)m >= BK_SMITH_COUNT)
		return -1;
	double a = r * r;
	double v[3] = {sqrt((1.0 - NoV) * (1.0 + NoV)), 0.0, NoV};
	double sa = 0.0, sb = 0.0;
	for (unsigned i = 0; i < n; i++) {
		double h[3];
		bk_ggx_sample_h((double)i / n, radical_inverse2(i), a, h);
		double VoH = v[0] * h[0] + v[1] * h[1] + v[2] * h[2];
		double NoL = 2.0 * VoH * h[2] - NoV;
		if (NoL <= 0.0 || VoH <= 0.0)
			continue;
		double g = bk_V_smith(m, NoV, NoL, a) * NoL * 4.0 * VoH / h[2];
		double x = 1.0 - VoH, x2 = x * x, fc = x2 * x2 * x;
		sa += (1.0 - fc) * g;
		sb += fc * g;
	}
	*A = sa / n;
	*B = sb / n;
	return 0;
}

int bk_dfg_lut(int size, bk_smith m, unsigned samples, double tol, double *A,
               double *B, bk_progress_fn progress, void *ctx)
{
	if (size < 1 || (unsigned)m >= BK_SMITH_COUNT)
		return -1;
	for (int j = 0; j < size; j++) {
		double r = (j + 0.5) / size;
		for (int i = 0; i < size; i++) {
			double NoV = (i + 0.5) / size;
			size_t k = (size_t)j * size + i;
			int rc = samples ? bk_dfg_hammersley(NoV, r, m, samples, &A[k], &B[k])
			                 : bk_dfg(NoV, r, m, tol, &A[k], &B[k], NULL);
			if (rc)
				return rc;
		}
		if (progress)
			progress(ctx, j + 1, size);
	}
	return 0;
}

/* ---- LUT layouts ----------------------------------------------------------- */

const char *bk_lut_warp_name(bk_lut_warp w)
{
	static const char *const names[BK_LUT_WARPS] = {"none", "sqrt"};
	return (unsigned)w < BK_LUT_WARPS ? names[w] : "?";
}

const char *bk_lut_warp_form(bk_lut_warp w)
{
	static const char *const forms[BK_LUT_WARPS] = {"NoV", "sqrt(NoV)"};
	return (unsigned)w < BK_LUT_WARPS ? forms[w] : "NoV";
}

static double clamp01(double x) { return x < 0 ? 0 : x > 1 ? 1 : x; }

double bk_lut_u(const bk_lut_layout *L, double NoV)
{
	double x = clamp01(NoV);
	return L->warp == BK_LUT_WARP_SQRT ? sqrt(x) : x;
}

double bk_lut_v(const bk_lut_layout *L, double r)
{
	return clamp01((r - L->r_lo) / (L->r_hi - L->r_lo));
}

/* The inverse warp: NoV of the texel centre u. */
double bk_lut_texel_nov(const bk_lut_layout *L, int i)
{
	double u = (i + 0.5) / L->nu;
	return L->warp == BK_LUT_WARP_SQRT ? u * u : u;
}

double bk_lut_texel_r(const bk_lut_layout *L, int j)
{
	return L->r_lo + (L->r_hi - L->r_lo) * ((j + 0.5) / L->nr);
}

int bk_lut_layout_check(const bk_lut_layout *L)
{
	if (!L || L->nu < 1 || L->nr < 1 || L->nu > 65536 || L->nr > 65536 || (unsigned)L->warp >= BK_LUT_WARPS)
		return -1;
	if (!(L->r_lo >= 0 && L->r_lo < L->r_hi && L->r_hi <= 1))
		return -1;
	if (!isnan(L->f0) && !(L->f0 >= 0 && L->f0 <= 1))
		return -1;
	return 0;
}

int bk_dfg_lut_layout(const bk_lut_layout *L, bk_smith m, unsigned samples, double tol, double *A, double *B,
                      bk_progress_fn progress, void *ctx)
{
	if (bk_lut_layout_check(L) || (unsigned)m >= BK_SMITH_COUNT)
		return -1;
	for (int j = 0; j < L->nr; j++) {
		double r = bk_lut_texel_r(L, j);
		for (int i = 0; i < L->nu; i++) {
			double NoV = bk_lut_texel_nov(L, i);
			size_t k = (size_t)j * (size_t)L->nu + (size_t)i;
			int rc = samples ? bk_dfg_hammersley(NoV, r, m, samples, &A[k], &B[k])
			                 : bk_dfg(NoV, r, m, tol, &A[k], &B[k], NULL);
			if (rc)
				return rc;
		}
		if (progress)
			progress(ctx, j + 1, L->nr);
	}
	return 0;
}
