/*
 * test_lutrows.c — the one builder of DFG LUT rows (analysis/lutrows.h):
 * rows per layout (4 sizes x 3 formats), the layouts a feature set gets,
 * names and texture bytes by hand, and the scores on env samples.
 */
#include "fixture_search.h"
#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

#include "lutrows.h"

static void form_samples(bk_samples *s)
{
	fx_planted("LoH", 0, 0, 4, s);
}

Test(lutrows, layouts_of_a_set)
{
	bk_lut_layout L[BK_LUTROWS_MAX_LAYOUTS];
	cr_expect_eq(bk_lutrows_layouts(0, 0.3, 1, 0.04, L), 1); /* compare, search: the generic alone */
	cr_expect_eq(bk_lutrows_layouts(1, 0, 1, NAN, L), 2);    /* the generic, and sqrt-warped */
	cr_expect_eq(L[1].warp, BK_LUT_WARP_SQRT);
	cr_expect_eq(bk_lutrows_layouts(1, 0.3, 1, NAN, L), 3);  /* rows over [0.3, 1]: both warps */
	cr_expect_eq(L[1].warp, BK_LUT_WARP_NONE);
	cr_expect(L[1].r_lo == 0.3 && L[1].r_hi == 1);
	cr_expect_eq(bk_lutrows_layouts(1, 0, 1, 0.04, L), 3);   /* f0 folded: both warps */
}

/* 12 rows a layout; on samples that are no env target none is scored
 * (negative control of scored). */
Test(lutrows, rows_per_layout_names_and_bytes)
{
	bk_samples s;
	form_samples(&s);
	bk_lut_layout L[BK_LUTROWS_MAX_LAYOUTS];
	bk_lutrow rows[BK_LUTROWS_MAX];
	int nl = bk_lutrows_layouts(1, 0.3, 1, 0.04, L);
	int n = bk_lutrows_build(L, nl, BK_SMITH_CORRELATED, 0, BK_F64, &s, NULL, NULL, rows);
	cr_assert_eq(n, 3 * 12);
	cr_expect_str_eq(rows[0].name, "LUT 16x16 unorm8");
	cr_expect_str_eq(rows[11].name, "LUT 128x128 float");
	cr_expect_str_eq(rows[12].name, "LUT 16x16 unorm8 f0 0.04 r 0.3-1");
	cr_expect_str_eq(rows[24].name, "LUT 16x16 unorm8 f0 0.04 r 0.3-1 sqrt");
	cr_expect_eq(rows[0].bytes, 16 * 16 * 1 * 2);   /* A and B, one byte each */
	cr_expect_eq(rows[11].bytes, 128 * 128 * 4 * 2);
	cr_expect_eq(rows[12].bytes, 16 * 16 * 1);      /* f0 folded: one channel */
	cr_expect_eq(rows[0].variant, 0);
	cr_expect_neq(rows[12].variant, 0);
	for (int k = 0; k < n; k++)
		cr_expect(!rows[k].scored, "%s scored on a form target", rows[k].name);
	bk_samples_free(&s);
}

/* On env samples (split A, B) every generic row is scored, and the
 * 128² float texture is closer than the 16² unorm8 one. */
Test(lutrows, scored_on_env_samples)
{
	bk_target_options to;
	bk_target_defaults(BK_TARGET_ENV, &to);
	to.nx = to.nr = 4;
	bk_samples s;
	char err[256];
	cr_assert_eq(bk_target_build(&to, &s, NULL, NULL, err, sizeof err), 0, "%s", err);
	bk_lut_layout L[BK_LUTROWS_MAX_LAYOUTS];
	bk_lutrow rows[BK_LUTROWS_MAX];
	int n = bk_lutrows_build(L, bk_lutrows_layouts(0, 0, 1, NAN, L), to.smith, 0, BK_F64, &s, NULL, NULL, rows);
	cr_assert_eq(n, 12);
	for (int k = 0; k < n; k++)
		cr_expect(rows[k].scored, "%s", rows[k].name);
	cr_expect_lt(rows[11].m.max_abs, rows[0].m.max_abs);
	bk_samples_free(&s);
}
