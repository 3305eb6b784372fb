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
 * storage (quantisation) and filtering (interpolation, clamp to edge), and,
 * for a shader in half or single precision (brdfkit scene), the rounding of
 * its texture coordinates and of the values it reads.
 *
 * Besides the engines' layout, a LUT may be laid out for a scene (brdf.h,
 * bk_lut_layout): f0 folded into one channel, rows over a roughness range,
 * NoV warped; the texels are then baked at that layout's centres.
 *
 * The cloth channel (the sheen albedo, bk_sheen_albedo: Filament's third DFG
 * channel, brdfkit lut --channels filament) is scored the same way, baked by
 * its own integrator at the same tolerance.
 */
#include "compare.h"
#include "lutcache.h"
#include "pool.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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

/* The reference texels of the (layout, smith, channel) triples asked for, A
 * then B (the cloth channel: its one channel, then zeros): a
 * 128² bake takes seconds, a table scores three formats of it, and brdfkit
 * scene asks every size for each feature set, the same layouts again for
 * the sets that share a roughness range, from several threads. One table
 * per process, kept until exit: the first LUT_CACHE pairs asked (at most
 * 64 x 256 KB), each baked once (a thread asking a pair being baked waits
 * for it); beyond them a pair is baked for its call alone. The texels are
 * the same bits either way (bake_table). */
#define LUT_CACHE 64
static struct {
	pthread_mutex_t mu;
	pthread_cond_t cv;
	int n;
	struct {
		bk_lut_layout L;
		bk_smith smith;
		int cloth;
		double *AB;
		int state; /* 0 being baked, 1 ready, -1 failed */
	} e[LUT_CACHE];
} cache = {PTHREAD_MUTEX_INITIALIZER, PTHREAD_COND_INITIALIZER, 0, {{{0}, 0, 0, NULL, 0}}};

static int same_layout(const bk_lut_layout *a, const bk_lut_layout *b)
{
	return a->nu == b->nu && a->nr == b->nr && a->r_lo == b->r_lo && a->r_hi == b->r_hi && a->warp == b->warp;
}

/* The bake on up to BAKE_THREADS threads (pool.h), a row a job: each texel
 * is one bk_dfg call whatever thread makes it, so the table is the same
 * bytes for any thread count. */
#define BAKE_THREADS 8
typedef struct bake {
	const bk_lut_layout *L;
	bk_smith smith;
	int cloth; /* 1: A is the sheen albedo, B zeros */
	double *A, *B;
} bake;

/* Texel (i, j) of the table: A and B, or the sheen albedo and 0. */
static int texel(const bk_lut_layout *L, bk_smith smith, int cloth, int i, int j, double *A, double *B)
{
	double NoV = bk_lut_texel_nov(L, i), r = bk_lut_texel_r(L, j);
	return cloth ? (*B = 0, bk_sheen_albedo(NoV, r, BK_DFG_TOL, A, NULL)) : bk_dfg(NoV, r, smith, BK_DFG_TOL, A, B, NULL);
}

static int bake_row(void *ctx, int j)
{
	const bake *b = ctx;
	for (int i = 0; i < b->L->nu; i++) {
		size_t k = (size_t)j * (size_t)b->L->nu + (size_t)i;
		if (texel(b->L, b->smith, b->cloth, i, j, &b->A[k], &b->B[k]))
			return -1;
	}
	return 0;
}

/* The key of a table in the disk cache (lutcache.h): what its bake depends on. */
void bk_lut_table_key(const bk_lut_layout *L, bk_smith smith, int cloth, char *key, size_t len)
{
	snprintf(key, len, "smith %d cloth %d nu %d nr %d r %a %a warp %d tol %a", (int)smith, cloth, L->nu, L->nr,
	         L->r_lo, L->r_hi, (int)L->warp, (double)BK_DFG_TOL);
}

/* The table from the disk cache when it holds this one: three texels baked
 * again here (two corners and the middle) must equal the file's bit for bit,
 * or a file another integrator wrote would be read as this one's. */
int bk_lut_table_cached(const char *dir, const bk_lut_layout *L, bk_smith smith, int cloth, double *AB)
{
	size_t n = (size_t)L->nu * (size_t)L->nr;
	char key[256];
	bk_lut_table_key(L, smith, cloth, key, sizeof key);
	if (bk_lut_layout_check(L) || bk_lutcache_read(dir, key, AB, 2 * n))
		return -1;
	const int probe[3][2] = {{0, 0}, {L->nu / 2, L->nr / 2}, {L->nu - 1, L->nr - 1}};
	for (int p = 0; p < 3; p++) {
		int i = probe[p][0], j = probe[p][1];
		size_t k = (size_t)j * (size_t)L->nu + (size_t)i;
		double A, B;
		if (texel(L, smith, cloth, i, j, &A, &B) || memcmp(&A, &AB[k], sizeof A) || memcmp(&B, &AB[n + k], sizeof B))
			return -1;
	}
	return 0;
}

/* bk_lutcache_fetch's two steps for a table */
typedef struct table_job {
	const bk_lut_layout *L;
	bk_smith smith;
	int cloth;
	const char *dir;
} table_job;

static int table_cached(void *ctx, double *AB)
{
	const table_job *j = ctx;
	return bk_lut_table_cached(j->dir, j->L, j->smith, j->cloth, AB);
}

static int table_make(void *ctx, double *AB)
{
	const table_job *j = ctx;
	bake b = {j->L, j->smith, j->cloth, AB, AB + (size_t)j->L->nu * (size_t)j->L->nr};
	return bk_pool_run(j->L->nr, bk_pool_cores(BAKE_THREADS), bake_row, NULL, &b) ? -1 : 0;
}

/* The table into AB: A, then B (nu nr each). */
static int bake_table(const bk_lut_layout *L, bk_smith smith, int cloth, double *AB)
{
	table_job j = {L, smith, cloth, bk_lutcache_dir()};
	char key[256];
	bk_lut_table_key(L, smith, cloth, key, sizeof key);
	return bk_lutcache_fetch(j.dir, key, AB, 2 * (size_t)L->nu * (size_t)L->nr, table_cached, table_make, &j);
}

/* The table of (L, smith, cloth), NULL if it could not be baked; *own: the
 * table when it is this call's alone (the caller frees it), else NULL. */
static const double *reference(const bk_lut_layout *L, bk_smith smith, int cloth, double **own)
{
	*own = NULL;
	pthread_mutex_lock(&cache.mu);
	int k;
	for (;;) {
		for (k = 0; k < cache.n && !(same_layout(&cache.e[k].L, L) && cache.e[k].smith == smith && cache.e[k].cloth == cloth);
		     k++)
			;
		if (k == cache.n || cache.e[k].state != 0)
			break;
		pthread_cond_wait(&cache.cv, &cache.mu); /* another thread bakes it */
	}
	if (k < cache.n && cache.e[k].state == 1) {
		const double *AB = cache.e[k].AB;
		pthread_mutex_unlock(&cache.mu);
		return AB;
	}
	int slot = k < cache.n ? k : cache.n < LUT_CACHE ? cache.n++ : -1; /* a failed bake is tried again */
	if (slot >= 0) {
		cache.e[slot].L = *L;
		cache.e[slot].smith = smith;
		cache.e[slot].cloth = cloth;
		cache.e[slot].AB = NULL;
		cache.e[slot].state = 0;
	}
	pthread_mutex_unlock(&cache.mu);
	size_t n = (size_t)L->nu * (size_t)L->nr;
	double *AB = malloc(sizeof(double) * 2 * n);
	if (AB && bake_table(L, smith, cloth, AB)) {
		free(AB);
		AB = NULL;
	}
	if (slot < 0) {
		*own = AB;
		return AB;
	}
	pthread_mutex_lock(&cache.mu);
	cache.e[slot].AB = AB;
	cache.e[slot].state = AB ? 1 : -1;
	pthread_cond_broadcast(&cache.cv);
	pthread_mutex_unlock(&cache.mu);
	return AB;
}

/* The stored value. unorm8 saturates to [0, 1] as a GPU's conversion does: A
 * and B of the reference are in [0, 1] (each is an integral of a non-negative
 * integrand, and A + B is the albedo at f0 = 1, at most 1), so the clamp never
 * acts on them; the sheen albedo exceeds 1 near grazing (Neubelt's V does not
 * conserve energy: bk_sheen_albedo), and there the clamp is what a unorm8
 * cloth channel stores. */
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

/* Bilinear fetch of t (nu x nr, row-major in r) at texture coordinates (u, v). */
static double sample(const double *t, int nu, int nr, double u, double v)
{
	if (isnan(u) || isnan(v))
		return NAN;
	int i0, i1, j0, j1;
	double s = axis(u, nu, &i0, &i1), w = axis(v, nr, &j0, &j1);
	const double *row0 = t + (size_t)j0 * (size_t)nu, *row1 = t + (size_t)j1 * (size_t)nu;
	return lerp(lerp(row0[i0], row0[i1], s), lerp(row1[i0], row1[i1], s), w);
}

int bk_lut_score(int size, bk_lut_format fmt, bk_smith smith, const bk_samples *s, bk_fit_metrics *m,
                 double *plane)
{
	bk_lut_layout L = {size, size, 0, 1, BK_LUT_WARP_NONE, NAN};
	return bk_lut_score_layout(&L, fmt, smith, BK_F64, s, m, plane);
}

/* A value in the shader's precision: what a fetch returns into a mediump or
 * highp variable, and what the multiply-add then leaves. */
static double in_precision(double x, bk_precision p)
{
	return p == BK_F16 ? bk_half_round(x) : p == BK_F32 ? (double)(float)x : x;
}

/* The texture coordinates as the shader computes them in its precision:
 * the inputs, the square root and the multiply-add of the remap (with its
 * constants) each rounded; in BK_F64 the exact map of bk_lut_u and bk_lut_v. */
static void coords(const bk_lut_layout *L, bk_precision prec, double NoV, double r, double *u, double *v)
{
	if (isnan(NoV) || isnan(r)) {
		*u = *v = NAN;
		return;
	}
	if (prec == BK_F64) {
		*u = bk_lut_u(L, NoV);
		*v = bk_lut_v(L, r);
		return;
	}
	double x = in_precision(NoV, prec), y = in_precision(r, prec);
	*u = L->warp == BK_LUT_WARP_SQRT ? in_precision(sqrt(fmax(x, 0)), prec) : x;
	if (L->r_lo > 0 || L->r_hi < 1) { /* v = r*k + c, one fused multiply-add */
		double k = in_precision(1 / (L->r_hi - L->r_lo), prec), c = in_precision(-L->r_lo / (L->r_hi - L->r_lo), prec);
		y = in_precision(y * k + c, prec);
	}
	*v = y;
}

/* bk_lut_score_layout and bk_lut_score_cloth: cloth 1 scores the sheen
 * albedo's texture (one channel, never folded) on one-form samples without f0. */
static int score(const bk_lut_layout *L, bk_lut_format fmt, bk_smith smith, int cloth, bk_precision prec,
                 const bk_samples *s, bk_fit_metrics *m, double *plane)
{
	if (bk_lut_layout_check(L) || (unsigned)fmt >= BK_LUT_FORMATS || (unsigned)smith >= BK_SMITH_COUNT || !s || !m ||
	    !s->n || (prec != BK_F64 && prec != BK_F32 && prec != BK_F16))
		return -1;
	/* an env target: (NoV, r), and f0 for the one-form variant; or ms, one
	 * form without f0: E = A + B, the albedo at f0 = 1, which only a layout
	 * folded at f0 = 1 stores; or the sheen albedo, one form without f0, in
	 * a channel of its own (A, unfolded) */
	int albedo = s->ncomp == 1 && !(s->provides >> BK_IN_F0 & 1);
	if (cloth ? !albedo || !isnan(L->f0) : albedo && L->f0 != 1.0)
		return -1;
	unsigned need = 1u << BK_IN_NOV | 1u << BK_IN_R | (s->ncomp == 1 && !albedo ? 1u << BK_IN_F0 : 0u);
	if ((s->provides & need) != need || (s->ncomp == 2 ? s->start[2] != s->n || 2 * s->start[1] != s->n
	                                                   : s->ncomp != 1))
		return -1;
	int folded = !isnan(L->f0);
	if (folded && s->ncomp != 1) /* one channel holds f0 A + B: no split A, B to compare with */
		return -1;
	for (size_t i = 0; folded && !albedo && i < s->n; i++)
		if (s->in[BK_IN_F0][i] != L->f0) /* it is right at its own f0 only */
			return -1;
	double *own;
	const double *ref = reference(L, smith, cloth, &own);
	size_t n = (size_t)L->nu * (size_t)L->nr;
	double *tex = malloc(sizeof(double) * 2 * n), *v = malloc(sizeof(double) * s->n);
	if (!ref || !tex || !v) {
		free(own);
		free(tex);
		free(v);
		return -1;
	}
	for (size_t k = 0; k < n; k++) { /* the stored channels: A, B or f0 A + B */
		tex[k] = quantise(folded ? L->f0 * ref[k] + ref[n + k] : ref[k], fmt);
		tex[n + k] = quantise(ref[n + k], fmt);
	}
	const double *A = tex, *B = tex + n;
	for (size_t i = 0; i < s->n; i++) {
		double u, w;
		coords(L, prec, s->in[BK_IN_NOV][i], s->in[BK_IN_R][i], &u, &w);
		/* the filter itself runs at full precision (modelled exact); its
		 * result lands in the shader's precision, and so does f0 A + B (one
		 * rounding: a fused multiply-add) */
		if (s->ncomp == 2)
			v[i] = in_precision(sample(i < s->start[1] ? A : B, L->nu, L->nr, u, w), prec);
		else if (folded || cloth) /* one fetch is the term */
			v[i] = in_precision(sample(A, L->nu, L->nr, u, w), prec);
		else /* the shader's f0 A + B from one fetch of both channels */
			v[i] = in_precision(in_precision(s->in[BK_IN_F0][i], prec) * in_precision(sample(A, L->nu, L->nr, u, w), prec) +
			                    in_precision(sample(B, L->nu, L->nr, u, w), prec), prec);
	}
	bk_samples_metrics(s, v, NULL, m);
	if (plane)
		bk_samples_plane_error(s, v, plane);
	free(own);
	free(tex);
	free(v);
	return 0;
}

int bk_lut_score_layout(const bk_lut_layout *L, bk_lut_format fmt, bk_smith smith, bk_precision prec,
                        const bk_samples *s, bk_fit_metrics *m, double *plane)
{
	return score(L, fmt, smith, 0, prec, s, m, plane);
}

int bk_lut_score_cloth(const bk_lut_layout *L, bk_lut_format fmt, bk_precision prec, const bk_samples *s,
                       bk_fit_metrics *m, double *plane)
{
	return score(L, fmt, BK_SMITH_CORRELATED, 1, prec, s, m, plane);
}
