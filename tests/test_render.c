/*
 * test_render.c — the CPU side of brdfkit render (analysis/render.h) against
 * closed forms and the library's own terms: the sphere geometry's identities,
 * the prefilter and irradiance of environments whose integrals are known, the
 * split sum's A and B against bk_dfg, and one exact pixel of the IR's render
 * against D·V·F·NoL·E + pref·(f0 A + B) + diffuse from brdf.h's functions.
 * Each threshold check has a negative control that shows it can fail.
 */
#include "brdf.h"
#include "render.h"

#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static bk_render_geom geom(int cell, int ncols, const double *r)
{
	bk_render_scene s = {.cell = cell, .ncols = ncols};
	memcpy(s.r, r, sizeof(double) * (size_t)ncols);
	bk_render_geom g;
	char err[200];
	cr_assert_eq(bk_render_geometry(&s, NULL, NULL, &g, err, sizeof err), 0, "%s", err);
	return g;
}

static const float *slot(const bk_render_geom *g, size_t i)
{
	return g->in + i * BK_RENDER_STRIDE;
}

/* The largest |NoH - (NoV + NoL)/(2 LoH)| over samples where neither NoV nor
 * NoL is clamped: H = (V + L)/|V + L| and |V + L| = 2 LoH, so N·H is that. */
static double noh_identity(const bk_render_geom *g, const float *noh_override, size_t at)
{
	double worst = 0;
	for (size_t i = 0; i < g->n; i++) {
		const float *s = slot(g, i);
		if (s[BK_RS_NOL] <= 0 || s[BK_RS_NOV] <= 1e-3f)
			continue;
		double noh = i == at && noh_override ? *noh_override : s[BK_RS_NOH];
		worst = fmax(worst, fabs(noh - (s[BK_RS_NOV] + s[BK_RS_NOL]) / (2.0 * s[BK_RS_LOH])));
	}
	return worst;
}

/* render.h's camera: a pinhole at 4 radii, the silhouette on the circle of
 * radius 0.45 cell, so the ray of a pixel at (u, v) (units of that radius
 * from the cell's centre) leaves the camera along (u t, v t, -1), t = tan of
 * the silhouette's half-angle = 1/sqrt(15), and V is its reverse. With the
 * light toward normalize(0.5, 0.6, 0.62), LoH = cos of half the angle between
 * V and L = sqrt((1 + V·L)/2), from the pixel's position alone (no sphere
 * intersection); it varies across a sphere (it would not under an
 * orthographic camera). NoH = (NoV + NoL)/(2 LoH); a = r^2 of the column; f0
 * the row's material. */
Test(render, sphere_geometry_identities)
{
	const double r[2] = {0.3, 0.8};
	bk_render_geom g = geom(16, 2, r);
	const double Ln = sqrt(0.25 + 0.36 + 0.62 * 0.62), t = 1 / sqrt(15.0);
	double lo = 1, hi = 0;
	cr_assert_eq(g.width, 32);
	cr_assert_eq(g.height, 32);
	cr_assert(g.n > 0 && g.n % 3 == 0);
	for (size_t i = 0; i < g.n; i++) {
		const float *s = slot(&g, i);
		int p = g.pixel[i] / 3, sph = g.sphere[p], row = sph / 2, col = sph % 2;
		cr_assert(sph >= 0);
		double u = ((p % 32) + 0.5 - (col + 0.5) * 16) / 7.2, v = -((p / 32) + 0.5 - (row + 0.5) * 16) / 7.2;
		double Vn = sqrt(u * u * t * t + v * v * t * t + 1);
		double VoL = (-u * t * 0.5 - v * t * 0.6 + 0.62) / (Vn * Ln), LoH = sqrt((1 + VoL) / 2);
		cr_assert_float_eq(s[BK_RS_LOH], LoH, 1e-6);
		lo = fmin(lo, LoH), hi = fmax(hi, LoH);
		cr_assert_float_eq(s[BK_RS_R], r[col], 1e-7);
		cr_assert_float_eq(s[BK_RS_A], r[col] * r[col], 1e-7);
		cr_assert(s[BK_RS_NOV] >= 1e-3f && s[BK_RS_NOV] <= 1 && s[BK_RS_NOL] >= 0 && s[BK_RS_NOL] <= 1);
		double f0 = row ? (double[]){1.00, 0.71, 0.29}[g.pixel[i] % 3] : 0.04;
		cr_assert_float_eq(s[BK_RS_F0], f0, 1e-7);
		cr_assert(row == 1 ? s[BK_RS_DIFF] == 0 : s[BK_RS_DIFF] > 0, "metal has no diffuse");
	}
	cr_assert(hi - lo > 0.05, "LoH %g..%g: the view does not vary across the spheres", lo, hi);
	/* float inputs: a few 2^-24 relative */
	cr_assert(noh_identity(&g, NULL, 0) < 1e-6, "%g", noh_identity(&g, NULL, 0));
	/* control: one NoH off by 1e-5 breaks it */
	size_t k = 0;
	while (slot(&g, k)[BK_RS_NOL] <= 0 || slot(&g, k)[BK_RS_NOV] <= 1e-3f)
		k++;
	float off = slot(&g, k)[BK_RS_NOH] - 1e-5f;
	cr_assert(noh_identity(&g, &off, k) > 1e-6);
	/* the sphere's pixel centres lie inside radius 0.45 cell: the centre pixel
	 * of each cell is on it, the corners are not */
	cr_assert(g.sphere[8 * 32 + 8] == 0 && g.sphere[8 * 32 + 24] == 1 && g.sphere[24 * 32 + 8] == 2);
	cr_assert(g.sphere[0] == -1 && g.sphere[31] == -1 && !isnan(g.background[0]));
	bk_render_geom_free(&g);
}

static void constant_env(void *ctx, const double d[3], double rgb[3])
{
	(void)d;
	const double *c = ctx;
	rgb[0] = c[0], rgb[1] = c[1], rgb[2] = c[2];
}

/* L(d) = max(d·z, 0) in every channel: its cosine-weighted mean over the
 * hemisphere of z is ∫cos^2 / ∫cos = (2π/3)/π = 2/3. */
static void cos_env(void *ctx, const double d[3], double rgb[3])
{
	(void)ctx;
	rgb[0] = rgb[1] = rgb[2] = fmax(d[2], 0);
}

Test(render, prefilter_of_a_constant_is_the_constant)
{
	const double c[3] = {0.25, 1.5, 7.0};
	const double R[4][3] = {{0, 0, 1}, {1, 0, 0}, {0, -1, 0}, {0.48, 0.6, 0.64}};
	const double a[4] = {0.01, 0.0625, 0.25, 1};
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++) {
			double out[3];
			bk_render_prefilter(constant_env, (void *)c, R[i], a[j], out);
			for (int k = 0; k < 3; k++)
				cr_assert(fabs(out[k] - c[k]) <= 1e-12 * c[k], "R %d a %g: %.17g", i, a[j], out[k]);
			bk_render_irradiance(constant_env, (void *)c, R[i], out);
			for (int k = 0; k < 3; k++)
				cr_assert(fabs(out[k] - c[k]) <= 1e-12 * c[k]);
		}
	/* control: an environment that is not constant is not returned as one,
	 * and a narrow lobe (a = 0.01) returns L(R): cos_env at R = z is 1 */
	double out[3], z[3] = {0, 0, 1};
	bk_render_prefilter(cos_env, NULL, z, 1, out);
	cr_assert(fabs(out[0] - 1) > 1e-3, "a wide lobe averages: %g", out[0]);
	bk_render_prefilter(cos_env, NULL, z, 0.01, out);
	cr_assert(fabs(out[0] - 1) < 1e-3, "%g", out[0]);
	bk_render_irradiance(cos_env, NULL, z, out);
	cr_assert(fabs(out[0] - 2.0 / 3) < 2e-3, "cosine-weighted mean of cos: %g, closed form 2/3", out[0]);
	cr_assert(fabs(out[0] - 0.5) > 0.1, "control: the uniform mean 1/2 is not it");
}

/* A and B of the samples against bk_dfg at the sample's own NoV and r (the
 * table is Catmull-Rom between 129 nodes in sqrt(NoV): 8e-5 at worst where B
 * bends at grazing NoV, so 1e-4 absolute); control: the next
 * column's roughness does not pass. */
Test(render, split_sum_pixels_against_the_dfg)
{
	const double r[2] = {0.25, 0.6};
	bk_render_geom g = geom(12, 2, r);
	double worst = 0, other = INFINITY;
	for (size_t i = 0; i < g.n; i += 37) {
		const float *s = slot(&g, i);
		int col = g.sphere[g.pixel[i] / 3] % 2;
		double A, B, A2, B2;
		cr_assert_eq(bk_dfg(s[BK_RS_NOV], r[col], BK_SMITH_CORRELATED, BK_DFG_TOL, &A, &B, NULL), 0);
		cr_assert_eq(bk_dfg(s[BK_RS_NOV], r[1 - col], BK_SMITH_CORRELATED, BK_DFG_TOL, &A2, &B2, NULL), 0);
		worst = fmax(worst, fmax(fabs(s[BK_RS_EA] - A), fabs(s[BK_RS_EB] - B)));
		other = fmin(other, fmax(fabs(s[BK_RS_EA] - A2), fabs(s[BK_RS_EB] - B2)));
	}
	cr_assert(worst < 1e-4, "A, B off the DFG by %g", worst);
	cr_assert(other > 1e-4, "control: the other roughness matched to %g", other);
	bk_render_geom_free(&g);
}

/* The IR's exact render of one pixel, in double, against the scene's
 * formula written with brdf.h's closed-form terms (not the IR). */
Test(render, exact_pixel_from_the_ir_against_brdf_h)
{
	const double r[1] = {0.35};
	bk_render_geom g = geom(16, 1, r);
	bk_form_error e;
	bk_form *f = bk_form_parse("V_kelemen(LoH)*F_schlick(f0, 1, LoH)", &e);
	cr_assert_not_null(f);
	bk_render_cand c = {BK_RT_VF, f, NULL, NULL, "test"};
	size_t np = (size_t)g.width * (size_t)g.height * 3;
	float *img[2] = {malloc(np * sizeof(float)), malloc(np * sizeof(float))};
	cr_assert_eq(bk_render_cpu(&g, &c, BK_F64, img), 0);
	int checked = 0;
	for (size_t i = 0; i < g.n; i += 11) {
		const float *s = slot(&g, i);
		double NoV = s[BK_RS_NOV], NoL = s[BK_RS_NOL], NoH = s[BK_RS_NOH], LoH = s[BK_RS_LOH], a = s[BK_RS_A],
		       f0 = s[BK_RS_F0];
		double spec = NoL > 0 ? bk_D_ggx(NoH, a) * bk_V_smith_ggx_correlated(NoV, NoL, a) *
		                            bk_F_schlick(f0, 1, LoH) * NoL * s[BK_RS_LIGHT] : 0;
		double want = spec + s[BK_RS_PREF] * (f0 * s[BK_RS_EA] + s[BK_RS_EB]) + s[BK_RS_DIFF];
		double cand = NoL > 0 ? bk_D_ggx(NoH, a) * bk_V_kelemen(LoH) * bk_F_schlick(f0, 1, LoH) * NoL * s[BK_RS_LIGHT] : 0;
		double want_c = cand + s[BK_RS_PREF] * (f0 * s[BK_RS_EA] + s[BK_RS_EB]) + s[BK_RS_DIFF];
		/* the image is float: half an f32 ulp, and the IR's D in its own spelling */
		cr_assert(fabs(img[0][g.pixel[i]] - want) <= 1e-6 * want, "exact %g, brdf.h %g", img[0][g.pixel[i]], want);
		cr_assert(fabs(img[1][g.pixel[i]] - want_c) <= 1e-6 * want_c, "candidate %g, %g", img[1][g.pixel[i]], want_c);
		/* control: the light 0.1 % brighter is caught where the light matters */
		if (spec > 0.01 * want) {
			double off = spec * 1.001 + (want - spec);
			cr_assert(fabs(img[0][g.pixel[i]] - off) > 1e-6 * off);
			checked++;
		}
	}
	cr_assert(checked > 3, "%d lit samples", checked);
	free(img[0]);
	free(img[1]);
	bk_form_free(f);
	bk_render_geom_free(&g);
}

Test(render, terms_and_display)
{
	bk_render_term t;
	cr_assert(bk_render_term_parse("vf2d", &t) == 0 && t == BK_RT_VF);
	cr_assert(bk_render_term_parse("env", &t) == 0 && t == BK_RT_ENV);
	cr_assert(bk_render_term_parse("vff", &t) == -1);
	cr_assert(bk_render_term_of_target("env_f0", &t) == 0 && t == BK_RT_ENV);
	cr_assert(bk_render_term_of_target("Fd", &t) == -1);
	/* Reinhard then sRGB: 1 -> 0.5 -> 1.055 * 0.5^(1/2.4) - 0.055 */
	cr_assert_float_eq(bk_render_display(1.0), 1.055 * pow(0.5, 1 / 2.4) - 0.055, 1e-12);
	cr_assert_float_eq(bk_render_display(0.001), 12.92 * 0.001 / 1.001, 1e-12);
	cr_assert(bk_render_display(INFINITY) == 1 && bk_render_display(-1) == 0 && bk_render_display(NAN) == 0);
}
