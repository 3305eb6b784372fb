/*
 * test_refit.c — the one refit preset (fit/search/refit.h): its caps (one
 * iteration cap for compare, search and scene: 2000, where a cut-off solve
 * would make the constants depend on libm) and the per-component values.
 */
#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

#include "search/refit.h"

Test(refit, caps)
{
	bk_form_error fe;
	bk_form *a = bk_form_parse("p0*r", &fe), *b = bk_form_parse("p0 + p1*r + p2*NoV", &fe);
	cr_assert(a && b);
	double start[BK_MAX_PARAMS] = {1, 2, 3};
	bk_fit_spec sp;
	bk_refit_spec(&sp, NULL, a, b, start);
	cr_expect_eq(sp.opt.max_iterations, 2000);
	cr_expect_eq(sp.starts, 2);
	cr_expect_eq(sp.seed, 1);
	cr_expect_eq(sp.digits, BK_FIT_DIGITS_SE);
	cr_expect_eq(sp.np, 3); /* the larger of 1 and 3 */
	cr_expect_eq(sp.start[2], 3.0);
	cr_expect(isinf(sp.lower[0]) && sp.lower[0] < 0 && isinf(sp.upper[BK_MAX_PARAMS - 1]));
	cr_expect_eq(sp.form[1], b);
	bk_refit_spec(&sp, NULL, a, NULL, start);
	cr_expect_eq(sp.np, 1);
	cr_expect_eq(sp.form[1], a); /* one form: both components read it */
	cr_expect_eq(bk_refit_albedo_options().max_iterations, 500);
	bk_form_free(a);
	bk_form_free(b);
}

/* The values of p0*LoH on LoH = cell centres of [0, 1] (4 cells: 1/8, 3/8,
 * 5/8, 7/8) at p0 = 1/3: in double exactly x/3; in half the nearest binary16
 * of it, which differs (negative control of the precision). */
Test(refit, values_in_the_precision_asked)
{
	bk_target_options to;
	bk_target_defaults(BK_TARGET_FORM, &to);
	to.form_text = "LoH";
	to.ndomain = 1;
	to.dom_in[0] = BK_IN_LOH, to.dom_lo[0] = 0, to.dom_hi[0] = 1;
	to.nx = 4;
	bk_samples s;
	char err[256];
	cr_assert_eq(bk_target_build(&to, &s, NULL, NULL, err, sizeof err), 0, "%s", err);
	cr_assert_eq(s.n, 4);
	bk_form_error fe;
	bk_form *f = bk_form_parse("p0*LoH", &fe);
	double start[BK_MAX_PARAMS] = {1.0 / 3}, v[4], h[4];
	bk_fit_spec sp;
	bk_refit_spec(&sp, &s, f, NULL, start);
	cr_assert_eq(bk_refit_values(&sp, start, BK_F64, v), 0);
	cr_assert_eq(bk_refit_values(&sp, start, BK_F16, h), 0);
	int differ = 0;
	for (size_t i = 0; i < 4; i++) {
		cr_expect(fabs(v[i] - s.in[BK_IN_LOH][i] / 3) < 1e-16, "%zu: %g", i, v[i]);
		cr_expect(fabs(h[i] - v[i]) < 1e-3); /* binary16 keeps 11 bits */
		differ |= h[i] != v[i];
	}
	cr_expect(differ, "half gave the double values");
	bk_form_free(f);
	bk_samples_free(&s);
}
