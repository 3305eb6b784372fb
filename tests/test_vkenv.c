/*
 * test_vkenv.c — the envelope of tests/vk (the values the Vulkan specification
 * lets a driver return for an emitted form), against values worked out by hand
 * from the specification's definitions: ulp(x) as the smallest gap between two
 * floats that enclose x, each operation's bound (correctly rounded; 2.5 ULP for
 * division; 3 + 2|x| ULP for exp2; absolute 2^-21 for log2 inside [0.5, 2]),
 * the overflow and denormal rules, and glslang's folding of literals in double.
 */
#include "vk/envelope.h"

#include <criterion/criterion.h>

#include <float.h>
#include <math.h>

/* The envelope of form at one sample: inputs NoV, NoL (the rest unread). */
static vk_env env_at(const char *form, const double *params, bk_precision prec, int flush, int fold, int builtin,
                     double nov, double nol)
{
	bk_form_error e;
	bk_form *f = bk_form_parse(form, &e);
	cr_assert_not_null(f, "%s: %s", form, e.message);
	const double *in[BK_IN_COUNT] = {0};
	in[BK_IN_NOV] = &nov;
	in[BK_IN_NOL] = &nol;
	vk_rules rules = {prec, flush, fold, builtin, 0};
	vk_env out;
	cr_assert_eq(vk_envelope(f, params, &rules, 1, in, &out), 0);
	bk_form_free(f);
	return out;
}

#define ASSERT_ENV(e, l, h)                                                                               \
	do {                                                                                                  \
		cr_assert(!(e).any, "envelope unbounded, want [%a, %a]", (double)(l), (double)(h));                 \
		cr_assert((e).lo == (l) && (e).hi == (h), "envelope [%a, %a], want [%a, %a]", (e).lo, (e).hi,        \
		          (double)(l), (double)(h));                                                              \
	} while (0)

Test(vkenv, ulp_is_the_smallest_enclosing_gap)
{
	cr_assert_eq(vk_ulp(1.5, BK_F32), 0x1p-23);
	cr_assert_eq(vk_ulp(1.0, BK_F32), 0x1p-24); /* the floats enclosing 1: 1 - 2^-24 and 1 */
	cr_assert_eq(vk_ulp(0.0, BK_F32), 0x1p-149);
	cr_assert_eq(vk_ulp(0x1p-126, BK_F32), 0x1p-149); /* below the smallest normal: denormals */
	cr_assert_eq(vk_ulp(1.5, BK_F16), 0x1p-10);
	cr_assert_eq(vk_ulp(1.0, BK_F16), 0x1p-11);
	cr_assert_eq(vk_ulp(1e-6, BK_F16), 0x1p-24);
}

Test(vkenv, correctly_rounded_ops_give_the_two_neighbours_or_the_exact_value)
{
	ASSERT_ENV(env_at("NoV + NoL", NULL, BK_F32, 1, 1, 0, 1, 0x1p-30), 1.0, 1 + 0x1p-23);
	ASSERT_ENV(env_at("NoV - NoL", NULL, BK_F32, 1, 1, 0, 1, 0x1p-30), 1 - 0x1p-24, 1.0);
	ASSERT_ENV(env_at("NoV * NoL", NULL, BK_F32, 1, 1, 0, 0.75, 0.5), 0.375, 0.375);
	ASSERT_ENV(env_at("NoV + NoL", NULL, BK_F16, 1, 1, 0, 1, 0x1p-12), 1.0, 1 + 0x1p-10);
}

Test(vkenv, division_is_2_5_ulp_and_unbounded_by_zero)
{
	/* 1/3 in [0.25, 0.5): floats 2^-25 apart; 2.5 of them each side */
	vk_env e = env_at("NoV / NoL", NULL, BK_F32, 1, 1, 0, 1, 3);
	double third = 1.0 / 3;
	cr_assert(!e.any && e.lo <= third && e.hi >= third);
	cr_assert(e.lo >= third - 2.5 * 0x1p-25 && e.lo - 0x1p-25 < third - 2.5 * 0x1p-25, "lo %a", e.lo);
	cr_assert(e.hi <= third + 2.5 * 0x1p-25 && e.hi + 0x1p-25 > third + 2.5 * 0x1p-25, "hi %a", e.hi);
	cr_assert((double)(float)e.lo == e.lo && (double)(float)e.hi == e.hi);
	cr_assert(env_at("NoV / NoL", NULL, BK_F32, 1, 1, 0, 1, 0).any);
	cr_assert(env_at("NoV / NoL", NULL, BK_F32, 1, 1, 0, 0, 0).any);
}

Test(vkenv, exp2_is_3_plus_2x_ulp_across_a_binade)
{
	/* exp2(0) = 1 exactly, 3 ULP of 1 (2^-24 each): below 1 the floats
	 * 1 - 3 * 2^-24 and up are in; above, only 1 + 2^-23 (2 * 2^-24) */
	ASSERT_ENV(env_at("exp2(NoV)", NULL, BK_F32, 1, 1, 0, 0, 0), 1 - 3 * 0x1p-24, 1 + 0x1p-23);
	/* exp2(-1) = 0.5: 3 + 2 = 5 ULP (2^-25 below 0.5, 2^-24 above) */
	ASSERT_ENV(env_at("exp2(-NoV)", NULL, BK_F32, 1, 1, 0, 1, 0), 0.5 - 5 * 0x1p-25, 0.5 + 2 * 0x1p-24);
	/* half: 1 + 2|x| ULP: exp2(0) within 1 ULP of 1 */
	ASSERT_ENV(env_at("exp2(NoV)", NULL, BK_F16, 1, 1, 0, 0, 0), 1 - 0x1p-11, 1.0);
}

Test(vkenv, log2_has_an_absolute_bound_inside_half_to_two)
{
	ASSERT_ENV(env_at("log2(NoV)", NULL, BK_F32, 1, 1, 0, 1, 0), -0x1p-21, 0x1p-21);
	ASSERT_ENV(env_at("log2(NoV)", NULL, BK_F16, 1, 1, 0, 1, 0), -0x1p-7, 0x1p-7);
	/* log2(0) = -inf (IEEE); past the largest finite, -FLT_MAX is allowed too */
	ASSERT_ENV(env_at("log2(NoV)", NULL, BK_F32, 1, 1, 0, 0, 0), -INFINITY, -FLT_MAX);
	cr_assert(env_at("log2(NoV - 1)", NULL, BK_F32, 1, 1, 0, 0.5, 0).any);
}

Test(vkenv, sqrt_of_zero_is_zero_and_overflow_may_be_inf_or_max)
{
	ASSERT_ENV(env_at("sqrt(NoV)", NULL, BK_F32, 1, 1, 0, 0, 0), 0.0, 0.0);
	ASSERT_ENV(env_at("NoV * 60000 * 2", NULL, BK_F16, 1, 1, 0, 1, 0), 65504.0, INFINITY);
	ASSERT_ENV(env_at("exp2(NoV * 200)", NULL, BK_F32, 1, 1, 0, 1, 0), FLT_MAX, INFINITY);
}

Test(vkenv, a_denormal_may_be_flushed_only_with_flush)
{
	/* 2^-140 is a float denormal: exact, or zero */
	ASSERT_ENV(env_at("NoV * NoL", NULL, BK_F32, 0, 0, 0, 0x1p-70, 0x1p-70), 0x1p-140, 0x1p-140);
	ASSERT_ENV(env_at("NoV * NoL", NULL, BK_F32, 1, 0, 0, 0x1p-70, 0x1p-70), 0.0, 0x1p-140);
}

Test(vkenv, half_constants_are_rounded_to_nearest)
{
	/* 0.1f = 0x1.99999ap-4: the bit after the half's ten is 0, down to
	 * 0x1.998p-4; 0.3f = 0x1.333334p-2: the next bit is 1 and more follow, up
	 * to 0x1.334p-2 (glslang's toward-zero conversion of "0.3hf" gives
	 * 0x1.330p-2, which tests/vk/glsl.c's exact literals avoid) */
	ASSERT_ENV(env_at("0.1 + NoV", NULL, BK_F16, 1, 1, 0, 0, 0), 0x1.998p-4, 0x1.998p-4);
	ASSERT_ENV(env_at("0.3 + NoV", NULL, BK_F16, 1, 1, 0, 0, 0), 0x1.334p-2, 0x1.334p-2);
}

Test(vkenv, literals_may_be_folded_in_double)
{
	/* 2.72721f - 2.71929f = 0.00792002678 in float; glslang folds the
	 * decimals in double: 0.00791999977 */
	const double p[2] = {2.72721, 2.71929};
	vk_env strict = env_at("p0 - p1 + NoV", p, BK_F32, 0, 0, 0, 0, 0);
	vk_env fold = env_at("p0 - p1 + NoV", p, BK_F32, 0, 1, 0, 0, 0);
	float f = 2.72721f - 2.71929f, d = (float)(2.72721 - 2.71929);
	cr_assert(f != d);
	ASSERT_ENV(strict, f, f);
	cr_assert(fold.lo <= d && fold.hi >= f && fold.hi - fold.lo < 4e-8, "[%a, %a]", fold.lo, fold.hi);
}

Test(vkenv, mix_builtin_allows_both_formulas_the_spelled_out_one_its_own)
{
	/* x = 1e4, y = 1e-4, t = 1 (x in NoV, t in NoL): x + (y - x) t loses y
	 * to the rounding of y - x; x (1 - t) + y t is y; mix() allows both, the
	 * spelled-out formula its own rounding (the floats bracketing y - x, plus x) */
	vk_env builtin = env_at("mix(NoV, 0.0001, NoL)", NULL, BK_F32, 1, 1, 1, 1e4, 1);
	vk_env spelled = env_at("mix(NoV, 0.0001, NoL)", NULL, BK_F32, 1, 1, 0, 1e4, 1);
	volatile float x = 1e4f, y = 0.0001f, t = 1.0f;
	float lerp = x + (y - x) * t, defined = x * (1 - t) + y * t;
	cr_assert(lerp != defined);
	cr_assert(vk_env_allows(&builtin, lerp) && vk_env_allows(&builtin, defined));
	ASSERT_ENV(spelled, 0.0, 0x1p-10);
	cr_assert(builtin.lo < spelled.lo && builtin.hi > spelled.hi);
}

Test(vkenv, nan_is_allowed_only_where_nothing_is_bounded)
{
	vk_env e = env_at("NoV", NULL, BK_F32, 1, 1, 0, 0.5, 0);
	cr_assert(!vk_env_allows(&e, NAN) && vk_env_allows(&e, 0.5) && !vk_env_allows(&e, 0.5000001));
	vk_env pole = env_at("1/NoV", NULL, BK_F32, 1, 1, 0, 0, 0);
	cr_assert(pole.any == VK_UNBOUNDED && vk_env_allows(&pole, INFINITY)); /* x/0: an infinity, its kind compared */
	vk_env inf_nan = env_at("exp2(NoV * 200) - exp2(NoL * 200)", NULL, BK_F32, 1, 1, 0, 1, 1);
	cr_assert(inf_nan.any == VK_UNBOUNDED); /* inf - inf: an IEEE NaN */
	cr_assert(env_at("0/NoV", NULL, BK_F32, 1, 1, 0, 0, 0).any == VK_UNDEFINED);
	cr_assert(env_at("pow(NoV, NoL)", NULL, BK_F16, 1, 1, 0, 0, 0).any == VK_UNDEFINED); /* pow(0, 0) */
	cr_assert(env_at("sqrt(NoV - 1)", NULL, BK_F32, 1, 1, 0, 0.5, 0).any == VK_UNDEFINED);
	cr_assert(env_at("sqrt(0/NoV) + 1/NoV", NULL, BK_F32, 1, 1, 0, 0, 0).any == VK_UNDEFINED); /* the worst wins */
}
