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

/* ---- LUTs laid out for a scene ---------------------------------------------- */

static bk_fit_metrics score_layout(const bk_lut_layout *L, bk_lut_format fmt, bk_precision prec, const bk_samples *s)
{
	bk_fit_metrics m;
	cr_assert_eq(bk_lut_score_layout(L, fmt, BK_SMITH_CORRELATED, prec, s, &m, NULL), 0);
	cr_assert_eq(m.nonfinite, 0);
	return m;
}

/* Rows over r in [0.4, 1] (16 of them) sit on the cell centres of a 16²
 * target on that box, as the classic LUT's do on [0, 1]²: a float LUT,
 * folded or split, is off by float rounding only there, so the remap of the
 * shader's v and the bake's texel rows are one map. In mediump the fetched
 * values and f0 A + B land in half: then no more than half rounding (2^-12
 * below 1, with f0 itself rounded: 0.04 is not a half) and more than float's. */
Test(lutscore, remapped_rows_on_their_own_centres)
{
	const double f0 = 0.04;
	bk_samples s, split;
	env(&s, 16, 16, 0, 1, 0.4, 1, 1, &f0);
	env(&split, 16, 16, 0, 1, 0.4, 1, 0, NULL);
	bk_lut_layout folded = {16, 16, 0.4, 1, BK_LUT_WARP_NONE, f0}, two = {16, 16, 0.4, 1, BK_LUT_WARP_NONE, NAN};
	bk_fit_metrics a = score_layout(&folded, BK_LUT_FLOAT, BK_F64, &s), b = score_layout(&two, BK_LUT_FLOAT, BK_F64, &s),
	               c = score_layout(&two, BK_LUT_FLOAT, BK_F64, &split);
	cr_assert(a.max_abs < 1e-7 && b.max_abs < 1e-7 && c.max_abs < 1e-7, "%g %g %g", a.max_abs, b.max_abs, c.max_abs);
	bk_fit_metrics h = score_layout(&folded, BK_LUT_FLOAT, BK_F16, &s), h2 = score_layout(&two, BK_LUT_FLOAT, BK_F16, &s);
	cr_assert(h.max_abs > 1e-6 && h.max_abs <= HALF_STEP_F16, "folded, mediump: %g", h.max_abs);
	cr_assert(h2.max_abs > 1e-6 && h2.max_abs <= 3 * HALF_STEP_F16, "split, mediump: %g", h2.max_abs);
	/* a folded LUT is only right at its own f0 */
	const double other = 0.05;
	bk_samples o;
	env(&o, 4, 4, 0, 1, 0.4, 1, 1, &other);
	bk_fit_metrics m;
	cr_assert_eq(bk_lut_score_layout(&folded, BK_LUT_FLOAT, BK_SMITH_CORRELATED, BK_F64, &o, &m, NULL), -1);
	cr_assert_eq(bk_lut_score_layout(&folded, BK_LUT_FLOAT, BK_SMITH_CORRELATED, BK_F64, &split, &m, NULL), -1);
	cr_assert_eq(bk_lut_score_layout(&folded, BK_LUT_FLOAT, BK_SMITH_CORRELATED, BK_FLD, &s, &m, NULL), -1);
	bk_samples_free(&o);
	bk_samples_free(&s);
	bk_samples_free(&split);
}

/* Filtering is linear: a folded float LUT interpolates f0 A + B exactly as
 * f0 times the interpolated A plus the interpolated B, off the texel centres
 * too, so its error equals the split LUT's to rounding. */
Test(lutscore, folding_is_linear)
{
	const double f0 = 0.04;
	bk_samples s;
	env(&s, 23, 19, 0, 1, 0.2, 0.9, 1, &f0);
	for (int w = 0; w < BK_LUT_WARPS; w++) {
		bk_lut_layout folded = {24, 20, 0.2, 0.9, (bk_lut_warp)w, f0}, two = folded;
		two.f0 = NAN;
		bk_fit_metrics a = score_layout(&folded, BK_LUT_FLOAT, BK_F64, &s), b = score_layout(&two, BK_LUT_FLOAT, BK_F64, &s);
		cr_assert(a.max_abs > 1e-5 && fabs(a.max_abs - b.max_abs) < 1e-7 && fabs(a.rmse - b.rmse) < 1e-7,
		          "warp %s: %g vs %g", bk_lut_warp_name(folded.warp), a.max_abs, b.max_abs);
	}
	bk_samples_free(&s);
}

/* At smooth roughness B falls from about 1 to its plateau within NoV ~ a of
 * grazing, far narrower than a texel of a uniform 64-texel axis (a = 0.0025
 * at r = 0.05): texels at u = sqrt(NoV) put 8 of them below NoV = 1/64 where
 * the uniform axis has one, and the max error on r in [0.05, 0.3] falls by
 * far more than 3x (measured: about 13x at 64², float). */
Test(lutscore, sqrt_warp_resolves_the_grazing_edge)
{
	const double f0 = 0.04;
	bk_samples s;
	env(&s, 40, 40, 0, 1, 0.05, 0.3, 1, &f0);
	bk_lut_layout flat = {64, 64, 0.05, 0.3, BK_LUT_WARP_NONE, f0}, warped = flat;
	warped.warp = BK_LUT_WARP_SQRT;
	bk_fit_metrics a = score_layout(&flat, BK_LUT_FLOAT, BK_F64, &s), b = score_layout(&warped, BK_LUT_FLOAT, BK_F64, &s);
	cr_assert(b.max_abs < a.max_abs / 3, "sqrt %g, uniform %g", b.max_abs, a.max_abs);
	bk_samples_free(&s);
}

/* ---- the cloth channel (the sheen albedo) --------------------------------------- */

static void sheen(bk_samples *s, int n)
{
	bk_target_options o;
	char err[256];
	bk_target_defaults(BK_TARGET_SHEEN, &o);
	o.nx = o.nr = n;
	o.x_lo = 0, o.x_hi = 1, o.r_lo = 0, o.r_hi = 1;
	cr_assert_eq(bk_target_build(&o, s, NULL, NULL, err, sizeof err), 0, "%s", err);
}

/* A 16² cloth LUT scored on the 16² grid's cell centres, which are its own
 * texel centres: float storage is off by float rounding only (relative
 * 2^-24); unorm8 saturates at 1, so where the albedo exceeds 1 (Neubelt's V
 * near grazing: bk_sheen_albedo) the error is the excess, E - 1, and
 * elsewhere at most half a step. The DFG's E = A + B (folded at f0 = 1) on
 * the same samples is another function: the control that the scorer reads
 * the cloth channel, not the DFG. */
Test(lutscore, cloth_channel_at_its_texel_centres)
{
	bk_samples s;
	sheen(&s, 16);
	bk_lut_layout L = {16, 16, 0, 1, BK_LUT_WARP_NONE, NAN};
	bk_fit_metrics f, u, e;
	cr_assert_eq(bk_lut_score_cloth(&L, BK_LUT_FLOAT, BK_F64, &s, &f, NULL), 0);
	cr_assert(f.max_rel < 0x1p-24 * 1.0001 && f.max_abs > 0, "float: max_rel %g", f.max_rel);
	bk_fit_metrics h; /* control of that bound: half storage rounds far coarser */
	cr_assert_eq(bk_lut_score_cloth(&L, BK_LUT_HALF, BK_F64, &s, &h, NULL), 0);
	cr_assert(h.max_rel > 0x1p-24 * 1.0001, "half: max_rel %g", h.max_rel);
	cr_assert_eq(bk_lut_score_cloth(&L, BK_LUT_UNORM8, BK_F64, &s, &u, NULL), 0);
	double excess = 0;
	for (size_t i = 0; i < s.n; i++)
		excess = fmax(excess, s.y[i] - 1);
	cr_assert(excess > 0.5, "the 16² grid reaches the albedo above 1 (%g)", excess);
	cr_assert(fabs(u.max_abs - excess) < 1e-12, "unorm8: %.12g, the excess above 1 %.12g", u.max_abs, excess);
	bk_lut_layout ms = L;
	ms.f0 = 1;
	cr_assert_eq(bk_lut_score_layout(&ms, BK_LUT_FLOAT, BK_SMITH_CORRELATED, BK_F64, &s, &e, NULL), 0);
	cr_assert(e.max_abs > 0.1, "the DFG's E is not the sheen albedo: %g", e.max_abs);
	/* refused: a folded layout (no f0 in the cloth channel), samples with f0 */
	cr_assert_eq(bk_lut_score_cloth(&ms, BK_LUT_FLOAT, BK_F64, &s, &f, NULL), -1);
	bk_samples envs;
	const double f0 = 0.04;
	env(&envs, 4, 4, 0, 1, 0, 1, 1, &f0);
	cr_assert_eq(bk_lut_score_cloth(&L, BK_LUT_FLOAT, BK_F64, &envs, &f, NULL), -1);
	bk_samples_free(&envs);
	bk_samples_free(&s);
}
