/*
 * test_lutscore.c — the DFG LUT scored as a GPU samples it: exact at its own
 * texel centres, interpolation error falling with size, quantisation error of
 * unorm8 (half a step, 1/510) and half between float and unorm8, clamp to
 * edge outside the texel centres, the f0 form against the split A + B, and the
 * metrics identical to bk_fit_evaluate's for a LUT that is a constant.
 */
#include "brdf.h"
#include "compare.h"
#include "fit.h"
#include "target.h"

#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define HALF_STEP_U8 (1.0 / 510.0) /* largest unorm8 rounding error */
#define HALF_STEP_F16 0x1p-12      /* largest half rounding error below 1 (ulp 2^-11 on [0.5, 1)) */

/* An env target on NoV in [x_lo, x_hi] x r in [r_lo, r_hi] (cell centres),
 * split, or one form in f0 over the nf0 values f0 (f0_form). */
static void env(bk_samples *s, int nx, int nr, double x_lo, double x_hi, double r_lo, double r_hi, int nf0,
                const double *f0)
{
	bk_target_options o;
	char err[256];
	bk_target_defaults(BK_TARGET_ENV, &o);
	o.nx = nx, o.nr = nr;
	o.x_lo = x_lo, o.x_hi = x_hi, o.r_lo = r_lo, o.r_hi = r_hi;
	if (nf0) {
		o.env_f0_form = 1;
		o.nf0 = nf0;
		memcpy(o.f0, f0, sizeof(double) * (size_t)nf0);
	}
	cr_assert_eq(bk_target_build(&o, s, NULL, NULL, err, sizeof err), 0, "%s", err);
}

static bk_fit_metrics score(int size, bk_lut_format fmt, const bk_samples *s, double *plane)
{
	bk_fit_metrics m;
	cr_assert_eq(bk_lut_score(size, fmt, BK_SMITH_CORRELATED, s, &m, plane), 0);
	cr_assert_eq(m.nonfinite, 0);
	cr_assert(isnan(m.cost) && isnan(m.albedo_max_abs));
	return m;
}

Test(lutscore, names_and_bad_arguments)
{
	cr_assert_str_eq(bk_lut_format_name(BK_LUT_UNORM8), "unorm8");
	cr_assert_str_eq(bk_lut_format_name(BK_LUT_HALF), "half");
	cr_assert_str_eq(bk_lut_format_name(BK_LUT_FLOAT), "float");
	bk_samples s, d;
	bk_fit_metrics m;
	env(&s, 2, 2, 0, 1, 0, 1, 0, NULL);
	cr_assert_eq(bk_lut_score(0, BK_LUT_FLOAT, BK_SMITH_CORRELATED, &s, &m, NULL), -1);
	cr_assert_eq(bk_lut_score(4, BK_LUT_FORMATS, BK_SMITH_CORRELATED, &s, &m, NULL), -1);
	cr_assert_eq(bk_lut_score(4, BK_LUT_FLOAT, BK_SMITH_COUNT, &s, &m, NULL), -1);
	cr_assert_eq(bk_lut_score(4, BK_LUT_FLOAT, BK_SMITH_CORRELATED, NULL, &m, NULL), -1);
	/* not an env target: no NoV */
	bk_target_options o;
	char err[256];
	bk_target_defaults(BK_TARGET_D, &o);
	o.nx = o.nr = 2;
	cr_assert_eq(bk_target_build(&o, &d, NULL, NULL, err, sizeof err), 0, "%s", err);
	cr_assert_eq(bk_lut_score(4, BK_LUT_FLOAT, BK_SMITH_CORRELATED, &d, &m, NULL), -1);
	bk_samples_free(&d);
	bk_samples_free(&s);
}

/* A 16² target on the default domain has its cell centres at the texel
 * centres of a 16² LUT: the same reference at the same points, so a float LUT
 * is off by float rounding only (at most 2^-25 per value below 1), and unorm8
 * and half by their rounding: unorm8 comes close to half a step (1/510) in
 * some of the 256 texels, never beyond; half below 2^-12; float < half < unorm8. */
Test(lutscore, own_texel_centres_quantisation_only)
{
	bk_samples s;
	env(&s, 16, 16, 0, 1, 0, 1, 0, NULL);
	double plane[16 * 16];
	bk_fit_metrics f = score(16, BK_LUT_FLOAT, &s, plane), h = score(16, BK_LUT_HALF, &s, NULL),
	               u = score(16, BK_LUT_UNORM8, &s, NULL);
	cr_assert(f.max_abs < 1e-7 && f.comp_max_abs[2] < 1e-7, "float %g", f.max_abs);
	for (int k = 0; k < 16 * 16; k++)
		cr_assert(fabs(plane[k]) < 1e-7);
	for (int q = 0; q < 2; q++) {
		cr_assert(u.comp_max_abs[q] > 0.8 * HALF_STEP_U8 && u.comp_max_abs[q] <= HALF_STEP_U8 + 1e-12, "unorm8 %g",
		          u.comp_max_abs[q]);
		cr_assert(h.comp_max_abs[q] <= HALF_STEP_F16, "half %g", h.comp_max_abs[q]);
	}
	for (int q = 0; q < 3; q++)
		cr_assert(f.comp_max_abs[q] < h.comp_max_abs[q] && h.comp_max_abs[q] < u.comp_max_abs[q], "component %d", q);
	cr_assert(f.rmse < h.rmse && h.rmse < u.rmse);
	/* each roughness row weighs the same and every cell is one sample a row */
	cr_assert(fabs(u.weighted_rmse - u.rmse) < 1e-12 * u.rmse);
	bk_samples_free(&s);
}

/* Away from grazing (NoV >= 0.1), where A and B are smooth, bilinear error
 * goes as h²: about 4x per doubling of the size; asserted: falling, at least
 * 2x per doubling, on a grid (24²) whose points are not texel centres. Below
 * NoV ~ 0.05 it is not: the clamp below the first texel centre is first order
 * and A + B has a sharp dip there at small r (r ~ 0.08 at NoV = 1/128). The
 * storage error adds at most its half step to the float error per component. */
Test(lutscore, interpolation_error_falls_with_size)
{
	bk_samples s;
	env(&s, 24, 24, 0.1, 1, 0, 1, 0, NULL);
	bk_fit_metrics prev = {0};
	for (int size = 16; size <= 64; size *= 2) {
		bk_fit_metrics f = score(size, BK_LUT_FLOAT, &s, NULL), h = score(size, BK_LUT_HALF, &s, NULL),
		               u = score(size, BK_LUT_UNORM8, &s, NULL);
		cr_assert(f.max_abs > 1e-5, "size %d: %g is interpolation error, not rounding", size, f.max_abs);
		if (size > 16)
			cr_assert(f.max_abs <= 0.5 * prev.max_abs && f.rmse <= 0.5 * prev.rmse, "size %d: %g %g after %g %g",
			          size, f.max_abs, f.rmse, prev.max_abs, prev.rmse);
		for (int q = 0; q < 2; q++) {
			cr_assert(u.comp_max_abs[q] <= f.comp_max_abs[q] + HALF_STEP_U8 + 1e-12);
			cr_assert(h.comp_max_abs[q] <= f.comp_max_abs[q] + HALF_STEP_F16 + 1e-12);
		}
		prev = f;
	}
	bk_samples_free(&s);
}

/* Clamp to edge: outside the outermost texel centres (NoV = 0.001 < 1/32,
 * NoV = 0.999 > 31/32, the same for r) the sample is the edge texel's value
 * exactly. One target line across the edge (A + B per cell, split) and the
 * same in f0 form at f0 = 0 (B alone), against the texels of an independent
 * bake stored as float. */
static void edge(int along_r, double at, int texel)
{
	enum { N = 16 };
	static double A[N * N], B[N * N];
	cr_assert_eq(bk_dfg_lut(N, BK_SMITH_CORRELATED, 0, BK_DFG_TOL, A, B, NULL, NULL), 0);
	double lo = at - 0.0005, hi = at + 0.0005, zero = 0;
	for (int form = 0; form < 2; form++) {
		bk_samples s;
		double plane[N];
		if (along_r) /* NoV at the texel centres, r at the edge */
			env(&s, N, 1, 0, 1, lo, hi, form, &zero);
		else
			env(&s, 1, N, lo, hi, 0, 1, form, &zero);
		score(N, BK_LUT_FLOAT, &s, plane);
		for (int k = 0; k < N; k++) {
			int t = along_r ? texel * N + k : k * N + texel;
			double want = form ? (double)(float)B[t] : (double)(float)A[t] + (double)(float)B[t];
			double y = form ? s.y[k] : s.y[k] + s.y[N + k];
			cr_assert(fabs(plane[k] + y - want) < 1e-15, "%s %g, cell %d: %.17g vs edge texel %.17g",
			          along_r ? "r" : "NoV", at, k, plane[k] + y, want);
		}
		bk_samples_free(&s);
	}
}

Test(lutscore, clamp_to_edge)
{
	edge(0, 0.001, 0);
	edge(0, 0.999, 15);
	edge(1, 0.001, 0);
	edge(1, 0.999, 15);
}

/* The filter weights have 8 fractional bits, as on GPUs: on a 2² LUT at
 * NoV = 0.4 the texel-space coordinate is 0.4 * 2 - 0.5 = 0.3, which the
 * sampler rounds to 77/256 = 0.30078 (r at the texel centres: weight 0). B
 * alone (f0 form at f0 = 0), against an independent bake stored as float. */
Test(lutscore, weights_have_8_fractional_bits)
{
	double A[4], B[4], zero = 0, plane[2];
	cr_assert_eq(bk_dfg_lut(2, BK_SMITH_CORRELATED, 0, BK_DFG_TOL, A, B, NULL, NULL), 0);
	bk_samples s;
	env(&s, 1, 2, 0.3995, 0.4005, 0, 1, 1, &zero);
	cr_assert(fabs(s.in[BK_IN_NOV][0] - 0.4) < 1e-12);
	score(2, BK_LUT_FLOAT, &s, plane);
	for (int j = 0; j < 2; j++) {
		double b0 = (float)B[2 * j], b1 = (float)B[2 * j + 1];
		double got = plane[j] + s.y[j], want = b0 + 77.0 / 256 * (b1 - b0), exact = b0 + 0.3 * (b1 - b0);
		cr_assert(fabs(got - want) < 1e-15, "r row %d: %.17g vs %.17g", j, got, want);
		cr_assert(fabs(got - exact) > 1e-5, "r row %d: the weight was not quantised", j);
	}
	bk_samples_free(&s);
}

/* The one form in f0 at f0 = 1 is f0 A + B = A + B: the same error as the
 * split target's A + B, cell by cell (the plane shows the last f0, here 1)
 * and in the metrics (f0 = 1 alone), for every format. */
Test(lutscore, f0_form_at_one_is_split_a_plus_b)
{
	const double list[3] = {0.04, 0.5, 1.0}, one = 1.0;
	bk_samples split, three, single;
	env(&split, 20, 20, 0, 1, 0, 1, 0, NULL);
	env(&three, 20, 20, 0, 1, 0, 1, 3, list);
	env(&single, 20, 20, 0, 1, 0, 1, 1, &one);
	for (int fmt = 0; fmt < BK_LUT_FORMATS; fmt++) {
		double ps[400], p3[400];
		bk_fit_metrics a = score(32, fmt, &split, ps), b = score(32, fmt, &single, NULL);
		score(32, fmt, &three, p3);
		for (int k = 0; k < 400; k++)
			cr_assert(fabs(ps[k] - p3[k]) < 1e-15, "%s cell %d: %g vs %g", bk_lut_format_name(fmt), k, ps[k], p3[k]);
		cr_assert(fabs(a.comp_max_abs[2] - b.max_abs) < 1e-15 && fabs(a.comp_rmse[2] - b.rmse) < 1e-15,
		          "%s: %g %g vs %g %g", bk_lut_format_name(fmt), a.comp_max_abs[2], a.comp_rmse[2], b.max_abs, b.rmse);
		cr_assert(a.comp_max_abs[2] > 1e-4);
	}
	bk_samples_free(&split);
	bk_samples_free(&three);
	bk_samples_free(&single);
}

/* A 1x1 LUT is a constant everywhere (both neighbours clamp to the one
 * texel): the constant forms p0 (A), p1 (B) and f0 p0 + p1 with the stored
 * texel as parameters must get the very metrics and plane bk_fit_evaluate and
 * bk_fit_plane_error give them. */
static void same_metrics(const bk_fit_metrics *a, const bk_fit_metrics *b)
{
	const double x[] = {a->rmse, a->weighted_rmse, a->max_abs, a->max_rel, a->comp_rmse[0], a->comp_rmse[1],
	                    a->comp_rmse[2], a->comp_max_abs[0], a->comp_max_abs[1], a->comp_max_abs[2]};
	const double y[] = {b->rmse, b->weighted_rmse, b->max_abs, b->max_rel, b->comp_rmse[0], b->comp_rmse[1],
	                    b->comp_rmse[2], b->comp_max_abs[0], b->comp_max_abs[1], b->comp_max_abs[2]};
	for (size_t i = 0; i < sizeof x / sizeof x[0]; i++)
		cr_assert(fabs(x[i] - y[i]) <= 1e-14 * fmax(1.0, fabs(y[i])), "metric %zu: %.17g vs %.17g", i, x[i], y[i]);
	cr_assert(a->max_rel > 0 && a->comp_max_abs[0] >= 0);
}

Test(lutscore, constant_lut_scores_as_bk_fit_evaluate)
{
	double A, B, list[2] = {0.04, 1.0};
	cr_assert_eq(bk_dfg_lut(1, BK_SMITH_CORRELATED, 0, BK_DFG_TOL, &A, &B, NULL, NULL), 0);
	double p[2] = {round(A * 255) / 255, round(B * 255) / 255}; /* unorm8 */
	bk_form_error fe;
	bk_form *fa = bk_form_parse("p0", &fe), *fb = bk_form_parse("p1", &fe), *ff = bk_form_parse("f0*p0 + p1", &fe);
	cr_assert(fa && fb && ff);
	for (int form = 0; form < 2; form++) {
		bk_samples s;
		env(&s, 8, 8, 0, 1, 0, 1, form ? 2 : 0, list);
		bk_fit_spec sp;
		memset(&sp, 0, sizeof sp);
		sp.s = &s;
		sp.form[0] = form ? ff : fa;
		sp.form[1] = form ? NULL : fb;
		sp.np = 2;
		bk_fit_metrics want, got;
		double pw[64], pg[64];
		bk_fit_evaluate(&sp, p, &want);
		bk_fit_plane_error(&sp, p, pw);
		cr_assert_eq(bk_lut_score(1, BK_LUT_UNORM8, BK_SMITH_CORRELATED, &s, &got, pg), 0);
		same_metrics(&got, &want);
		for (int k = 0; k < 64; k++)
			cr_assert(fabs(pg[k] - pw[k]) < 1e-15, "cell %d: %g vs %g", k, pg[k], pw[k]);
		bk_samples_free(&s);
	}
	bk_form_free(fa);
	bk_form_free(fb);
	bk_form_free(ff);
}
