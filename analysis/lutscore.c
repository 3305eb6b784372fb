/*
 * lutscore.c — the LUT alternative, scored honestly. For the environment BRDF
 * the competitor of every formula is a texture: a size x size DFG LUT (texel
 * centres, as brdfkit lut writes it) stored as 8-bit unorm, half or float and
 * sampled the way a GPU does, scored on the same samples and with the same
 * metrics as a fitted form (bk_fit_evaluate, bk_fit_plane_error).
 *
 * The texels are baked with the deterministic reference integrator
 * (bk_dfg_lut, samples = 0, tol BK_DFG_TOL = 1e-8): the best a baked LUT can
 * be. An engine's Hammersley bake adds its Monte Carlo error on top, so these
 * rows are a lower bound on what a shipped LUT gets wrong; what is left is
 * storage (quantisation) and filtering (interpolation, clamp to edge).
 */
#include "compare.h"

#include <math.h>
#include <stdlib.h>

/* Sub-texel precision of the bilinear weights. GPUs do not filter with the
 * float coordinate: they convert it to fixed point first. Direct3D 11 requires
 * at least 8 fractional bits (D3D11_SUBTEXEL_FRACTIONAL_BIT_COUNT = 8 in
 * d3d11.h; D3D10 asked for 6), and the CUDA programming guide (texture
 * fetching, linear filtering) states that the weights are stored in 9-bit
 * fixed point with 8 fractional bits, so 1.0 is exact; most hardware has
 * exactly 8. Modelled here as the texel-space coordinate rounded to the
 * nearest 1/256 (hardware that truncates differs by one step of the weight). */
#define LUT_SUBTEXEL_BITS 8
#define LUT_SUBTEXEL_STEPS (1 << LUT_SUBTEXEL_BITS)

const char *bk_lut_format_name(bk_lut_format f)
{
	static const char *const names[BK_LUT_FORMATS] = {"unorm8", "half", "float"};
	return (unsigned)f < BK_LUT_FORMATS ? names[f] : "?";
}

/* The reference texels of the (size, smith) pairs asked for, A then B: a 128²
 * bake takes seconds, a table scores three formats of it and brdfkit scene
 * every size for each feature set. One table per thread, a few entries (the
 * oldest replaced), kept until exit. */
#define LUT_CACHE 8
static _Thread_local struct {
	int size;
	bk_smith smith;
	double *AB;
} cache[LUT_CACHE];
static _Thread_local int cache_next;

static const double *reference(int size, bk_smith smith)
{
	for (int k = 0; k < LUT_CACHE; k++)
		if (cache[k].AB && cache[k].size == size && cache[k].smith == smith)
			return cache[k].AB;
	size_t n = (size_t)size * (size_t)size;
	double *AB = malloc(sizeof(double) * 2 * n);
	if (!AB || bk_dfg_lut(size, smith, 0, BK_DFG_TOL, AB, AB + n, NULL, NULL)) {
		free(AB);
		return NULL;
	}
	int k = cache_next;
	cache_next = (cache_next + 1) % LUT_CACHE;
	free(cache[k].AB);
	cache[k].AB = AB, cache[k].size = size, cache[k].smith = smith;
	return AB;
}

/* The stored value. unorm8 saturates to [0, 1] as a GPU's conversion does: A
 * and B of the reference are in [0, 1] (each is an integral of a non-negative
 * integrand, and A + B is the albedo at f0 = 1, at most 1), so the clamp never
 * acts on them. */
static double quantise(double x, bk_lut_format fmt)
{
	switch (fmt) {
	case BK_LUT_UNORM8: return round(fmin(fmax(x, 0.0), 1.0) * 255.0) / 255.0;
	case BK_LUT_HALF: return bk_half_round(x);
	default: return (float)x;
	}
}

static int clampi(int i, int size) { return i < 0 ? 0 : i >= size ? size - 1 : i; }

/* One axis of the filter: x in [0, 1] to texel space (u = x size - 0.5 puts
 * texel centres on integers), the coordinate to fixed point, the two texels
 * either side clamped to the edge, and the weight of the second. */
static double axis(double x, int size, int *i0, int *i1)
{
	double u = fmin(fmax(x * size - 0.5, -1.0), (double)size); /* beyond that the clamp gives the same */
	u = round(u * LUT_SUBTEXEL_STEPS) / LUT_SUBTEXEL_STEPS;
	double f = floor(u);
	*i0 = clampi((int)f, size);
	*i1 = clampi((int)f + 1, size);
	return u - f;
}

static double lerp(double a, double b, double t) { return a + t * (b - a); } /* t = 0 or a = b: a exactly */

/* Bilinear fetch of t (size x size, row-major in r) at (NoV, r). */
static double sample(const double *t, int size, double NoV, double r)
{
	if (isnan(NoV) || isnan(r))
		return NAN;
	int i0, i1, j0, j1;
	double s = axis(NoV, size, &i0, &i1), w = axis(r, size, &j0, &j1);
	const double *row0 = t + (size_t)j0 * (size_t)size, *row1 = t + (size_t)j1 * (size_t)size;
	return lerp(lerp(row0[i0], row0[i1], s), lerp(row1[i0], row1[i1], s), w);
}

int bk_lut_score(int size, bk_lut_format fmt, bk_smith smith, const bk_samples *s, bk_fit_metrics *m,
                 double *plane)
{
	if (size < 1 || (unsigned)fmt >= BK_LUT_FORMATS || (unsigned)smith >= BK_SMITH_COUNT || !s || !m || !s->n)
		return -1;
	/* an env target: (NoV, r), and f0 for the one-form variant */
	unsigned need = 1u << BK_IN_NOV | 1u << BK_IN_R | (s->ncomp == 1 ? 1u << BK_IN_F0 : 0u);
	if ((s->provides & need) != need || (s->ncomp == 2 ? s->start[2] != s->n || 2 * s->start[1] != s->n
	                                                   : s->ncomp != 1))
		return -1;
	const double *ref = reference(size, smith);
	size_t n = (size_t)size * (size_t)size;
	double *tex = malloc(sizeof(double) * 2 * n), *v = malloc(sizeof(double) * s->n);
	if (!ref || !tex || !v) {
		free(tex);
		free(v);
		return -1;
	}
	for (size_t k = 0; k < 2 * n; k++)
		tex[k] = quantise(ref[k], fmt);
	const double *A = tex, *B = tex + n;
	for (size_t i = 0; i < s->n; i++) {
		double NoV = s->in[BK_IN_NOV][i], r = s->in[BK_IN_R][i];
		if (s->ncomp == 2)
			v[i] = sample(i < s->start[1] ? A : B, size, NoV, r);
		else /* the shader's f0 A + B from one fetch of both channels */
			v[i] = s->in[BK_IN_F0][i] * sample(A, size, NoV, r) + sample(B, size, NoV, r);
	}
	bk_samples_metrics(s, v, NULL, m);
	if (plane)
		bk_samples_plane_error(s, v, plane);
	int rc = 0;
	free(tex);
	free(v);
	return rc;
}
