/*
 * test_stability.c — the known ways BRDF code breaks in half precision, found
 * by the stability analysis and checked against closed forms: GGX D overflows
 * below a roughness the analysis computes; V terms divide by zero at grazing
 * angles; 1 - NoH^2 is lost near the highlight when NoH is rounded to half;
 * r^4 flushes to zero for small r; epsilons a half shader cannot hold.
 */
#include "brdf.h"
#include "stability.h"

#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

static bk_stability st;

static void run(const char *text)
{
	char err[256];
	bk_stability_free(&st); /* the previous test's */
	cr_assert_eq(bk_stability_run(text, text, NULL, BK_STAB_TOL, &st, err, sizeof err), 0, "%s", err);
}

static double half_eval(const char *text, double NoV, double NoL, double NoH, double LoH, double r)
{
	double a = r * r, f0 = 0.04, out;
	const double *in[BK_IN_COUNT] = {&NoV, &NoL, &NoH, &LoH, &r, &a, &f0};
	bk_form_error e;
	bk_form *f = bk_form_parse(text, &e);
	cr_assert_not_null(f);
	bk_form_eval(f, BK_F16, 1, in, NULL, &out);
	bk_form_free(f);
	return out;
}

/* GGX D peaks at 1/(π r^4): past 65504 below r = (π 65504)^(-1/4) = 0.0472,
 * so no half evaluation can hold it there; the analysis finds overflow and a
 * minimum safe roughness at or above that bound (the IR's (NoH² a²)² is
 * r^8 at the peak, which underflows half earlier still). */
Test(stability, ggx_d_overflows_below_a_computed_roughness)
{
	double bound = pow(BK_PI * 65504.0, -0.25);
	cr_assert(isinf(half_eval("D_ggx(NoH, a)", 0.5, 0.5, 1.0, 0.5, 0.04)), "r = 0.04 < %g must overflow", bound);
	run("D_ggx(NoH, a)");
	cr_assert(st.p[2].overflow > 0 && st.p[2].inf > 0);
	cr_assert(st.p[0].wrong == 0 && st.p[1].wrong == 0, "double and single are fine");
	cr_assert(st.r_min >= bound && st.r_min < 0.5, "r_min %g, bound %g", st.r_min, bound);
	cr_assert(st.guarded_ok && strstr(st.guards, "roughness floor"), "%s", st.guards);
	cr_assert_eq(st.constants[0], '\0', "guard constants must be half values: %s", st.constants);
}

/* st.guarded_form is st.guarded parsed (its users take the IR instead of
 * parsing the text again: issue 42): the same text and the same bits in half
 * at the extremes, for a form that needs a guard, one safe as is and one no
 * guard fixes. The control: D's guarded form is not the unguarded one (finite
 * in half at r = 0.04 where D_ggx overflows). */
Test(stability, the_guarded_form_is_the_guarded_text_parsed)
{
	static const char *const forms[] = {"D_ggx(NoH, a)", "F_schlick(f0, 1, LoH)", "0*(100000*NoV)"};
	double NoV = 0.5, NoL = 0.5, NoH = 1, LoH = 0.5, r = 0.04, a = r * r, f0 = 0.04;
	const double *in[BK_IN_COUNT] = {&NoV, &NoL, &NoH, &LoH, &r, &a, &f0};
	for (int i = 0; i < 3; i++) {
		run(forms[i]);
		cr_assert_not_null(st.guarded_form, "%s", forms[i]);
		cr_expect_str_eq(bk_form_text(st.guarded_form), st.guarded);
		bk_form *g = bk_form_parse(st.guarded, NULL);
		cr_assert_not_null(g, "%s", st.guarded);
		double v[2];
		bk_form_eval(st.guarded_form, BK_F16, 1, in, NULL, &v[0]);
		bk_form_eval(g, BK_F16, 1, in, NULL, &v[1]);
		cr_expect_eq(memcmp(&v[0], &v[1], sizeof v[0]), 0, "%s: %g against %g", st.guarded, v[0], v[1]);
		if (i == 0) {
			cr_expect(isfinite(v[0]), "D guarded: %g", v[0]);
			cr_expect(isinf(half_eval(forms[0], NoV, NoL, NoH, LoH, r)), "the control: D_ggx overflows");
		}
		bk_form_free(g);
	}
}

/* Smith V at NoV = NoL = 0 is 1/0 in every precision; the analysis counts the
 * reference's own poles apart from the precision's failures. */
Test(stability, v_terms_divide_by_zero_at_grazing)
{
	const char *v[] = {"V_smith_ggx_correlated(NoV, NoL, a)", "V_smith_ggx_separable(NoV, NoL, a)",
	                   "V_neubelt(NoV, NoL)", "V_neumann(NoV, NoL)", "V_hammon(NoV, NoL, a)"};
	for (size_t i = 0; i < sizeof v / sizeof v[0]; i++) {
		cr_assert(isinf(half_eval(v[i], 0.0, 0.0, 1.0, 1.0, 0.0)), "%s at grazing", v[i]);
		run(v[i]);
		cr_assert(st.ref_nonfinite > 0, "%s: the reference's poles", v[i]);
	}
	run("V_smith_ggx_correlated(NoV, NoL, a)");
	cr_assert(st.p[2].wrong > 0 && st.guarded_ok);
	/* the floors found make the guarded form pass in half, and both are half values */
	cr_assert(strstr(st.guards, "cosines >=") || strstr(st.guards, "65504"), "%s", st.guards);
	cr_assert_eq(st.constants[0], '\0', "%s", st.constants);
}

/* In half, NoH = 0.9999 rounds to 1 (half's spacing below 1 is 2^-11): the
 * 1 - NoH^2 of the highlight is gone before any arithmetic. The analysis
 * reports it as ill conditioned near NoH = 1 and advises |N x H|^2. */
Test(stability, one_minus_noh2_is_lost_near_the_highlight)
{
	cr_assert_eq(bk_half_round(0.9999), 1.0);
	run("D_ggx(NoH, a)");
	cr_assert(st.p[2].ill > 0 && st.p[2].ill_noh_min >= 0.999, "ill %zu at NoH >= %g", st.p[2].ill, st.p[2].ill_noh_min);
	cr_assert(st.p[1].ill == 0, "single precision keeps it");
	cr_assert_not_null(strstr(st.advice, "|N x H|^2"), "%s", st.advice);
}

/* r^4 at r = 0.01 is 1e-8, below half's smallest subnormal 2^-24 (5.96e-8)
 * by more than half a step: it flushes to zero. */
Test(stability, r4_flushes_to_zero_for_small_r)
{
	cr_assert_eq(half_eval("r^4", 0.5, 0.5, 0.5, 0.5, 0.01), 0.0);
	cr_assert(half_eval("r^4", 0.5, 0.5, 0.5, 0.5, 0.1) > 0.0); /* 1e-4: normal in half */
	run("r^4");
	cr_assert(st.p[2].subnormal > 0);
	run("a*a/(a*a*NoH*NoH + 1)");
	cr_assert(st.p[2].subnormal > 0);
}

/* 1/r^4 exceeds 65504 below r = 65504^(-1/4) = 0.0625: the minimum safe
 * roughness computed on the log grid is the first grid value above it. */
Test(stability, minimum_safe_roughness_of_a_closed_form)
{
	run("1/(r*r*r*r)");
	double bound = pow(65504.0, -0.25);
	cr_assert(st.r_min >= bound && st.r_min <= bound * 1.5, "r_min %g, bound %g", st.r_min, bound);
}

/* An epsilon of 1e-5 is subnormal in half: on GPUs that flush it is 0. */
Test(stability, epsilons_a_half_shader_cannot_hold)
{
	run("0.25/(LoH*LoH + 1e-5)");
	cr_assert_not_null(strstr(st.constants, "1e-05"), "%s", st.constants);
	run("0.25/(LoH*LoH + 1e-4)");
	cr_assert_eq(st.constants[0], '\0', "1e-4 is a normal half number: %s", st.constants);
}

/* Forms without trouble stay clean: Schlick F in half is within 2 % wherever
 * its value is a normal number. */
Test(stability, benign_forms_pass_as_is)
{
	run("F_schlick(f0, 1, LoH)");
	cr_assert(st.p[2].wrong == 0 && st.p[2].max_rel < 0.01 && st.r_min == 0);
}

/* 1e5 is past half's largest value 65504, so it is infinite in half and
 * 0 * Inf is NaN, where long double gives 0 * (1e5 NoV) = 0 at every sample:
 * half is wrong everywhere, though the reference (0) is not a normal number.
 * No guard fixes it: a clamp min(NaN, 65504) gives 65504 where the answer is
 * 0, and no floor of NoV or r makes 1e5 finite. */
Test(stability, nan_where_the_reference_is_finite_is_wrong)
{
	cr_assert(isnan(half_eval("0*(1e5*NoV)", 0.5, 0.5, 0.5, 0.5, 0.5)));
	run("0*(1e5*NoV)");
	size_t n = (size_t)bk_stab_nr * (size_t)bk_stab_ncos; /* it reads NoV only */
	cr_assert_eq(st.p[2].n, n);
	cr_assert_eq(st.p[2].nan, n);
	cr_assert_eq(st.p[2].wrong, n, "wrong %zu of %zu", st.p[2].wrong, n);
	cr_assert(st.p[0].wrong == 0 && st.p[1].wrong == 0, "1e5 is finite in single and double");
	cr_assert_eq(st.ref_nonfinite, 0);
	cr_assert_eq(st.guarded_ok, 0, "guards claimed to fix it: %s -> %s", st.guards, st.guarded);
}

/* A NaN swallowed on the way: min(NaN, 1) is 1 (IEEE minNum) where the
 * answer min(0, 1) is 0: a finite value off by 1 from a reference below
 * half's smallest normal is wrong too. */
Test(stability, a_nan_hidden_by_min_is_wrong)
{
	cr_assert_eq(half_eval("min(0*(1e5*NoV), 1)", 0.5, 0.5, 0.5, 0.5, 0.5), 1.0);
	run("min(0*(1e5*NoV), 1)");
	cr_assert_eq(st.p[2].wrong, st.p[2].n);
}

/* NoV/NoV is 0/0 = NaN at NoV = 0 in every precision, long double included
 * (one sample per roughness), and 1 elsewhere: NaN where the reference is NaN
 * is the form's own, not a precision's failure. */
Test(stability, nan_where_the_reference_is_nan_is_not_wrong)
{
	run("NoV/NoV");
	cr_assert_eq(st.ref_nonfinite, (size_t)bk_stab_nr);
	for (int p = 0; p < 3; p++)
		cr_assert(st.p[p].wrong == 0 && st.p[p].nan == 0, "precision %d: wrong %zu, nan %zu", p, st.p[p].wrong,
		          st.p[p].nan);
}

/* Below half's smallest normal 2^-14 a flush to zero is no failure: at NoV = 1,
 * NoV*1e-4*NoV*1e-4 = 1e-8 rounds to 0 in half (below half the smallest
 * subnormal, 2^-25), so the value is 0 where the reference is 1e-5. */
Test(stability, a_flush_below_the_smallest_normal_is_not_wrong)
{
	cr_assert_eq(half_eval("NoV*1e-4*NoV*1e-4*1e3", 1, 0.5, 0.5, 0.5, 0.5), 0.0);
	run("NoV*1e-4*NoV*1e-4*1e3");
	cr_assert_eq(st.p[2].wrong, 0);
}

/* The analysis has no form length limit of its own: 500 terms 0*r (0 in
 * every precision) in front of 1/r^4 make a form of 3 KB that overflows half
 * for small r like 1/r^4 alone, with the same guard: a roughness floor,
 * written into every r of the whole form. With 700 terms (4 KB) the guarded
 * text would pass the parser's 16384 characters: said so, not "nothing
 * fixes it". */
static void filler(char *text, size_t len, int terms)
{
	size_t k = 0;
	for (int i = 0; i < terms; i++)
		k += (size_t)snprintf(text + k, len - k, "0*r + ");
	snprintf(text + k, len - k, "1/(r*r*r*r)");
}

Test(stability, forms_of_any_length)
{
	static char text[8192], guards[256], tail[4096];
	run("1/(r*r*r*r)");
	cr_assert(st.guarded_ok && strstr(st.guards, "roughness floor r >= "), "%s", st.guards);
	snprintf(guards, sizeof guards, "%s", st.guards);
	snprintf(tail, sizeof tail, " + %s", st.guarded);
	size_t wrong = st.p[2].wrong;
	filler(text, sizeof text, 500);
	cr_assert_gt(strlen(text), 3000);
	run(text);
	cr_assert_eq(st.p[2].wrong, wrong);
	cr_assert(st.guarded_ok, "%s", st.guards);
	cr_assert_str_eq(st.guards, guards);
	size_t n = strlen(st.guarded), m = strlen(tail);
	cr_assert(n > 3000 + m && strcmp(st.guarded + n - m, tail) == 0, "%s", st.guarded + n - m);
	filler(text, sizeof text, 700);
	cr_assert_gt(strlen(text), 4000);
	run(text);
	cr_assert_eq(st.p[2].wrong, wrong);
	cr_assert_eq(st.guarded_ok, 0);
	cr_assert_not_null(strstr(st.guards, "form longer than 16384 characters"), "%s", st.guards);
}

/* A form with parameters needs their values: zeros would be a silent guess. */
Test(stability, parameters_without_values_are_refused)
{
	char err[256] = "";
	bk_stability_free(&st);
	cr_assert_eq(bk_stability_run("form", "p0*NoV", NULL, BK_STAB_TOL, &st, err, sizeof err), -1);
	cr_assert_str_eq(err, "form: the form uses p0 but no value was given");
	double p[BK_MAX_PARAMS] = {2};
	cr_assert_eq(bk_stability_run("form", "p0*NoV", p, BK_STAB_TOL, &st, err, sizeof err), 0, "%s", err);
}

/* Constants a half shader cannot hold are all accounted for, however many:
 * i * 1e-9 for i = 1..300 are all below half's smallest normal 2^-14
 * (3e-7 < 6.1e-5); the list names as many as fit and says how many more. */
Test(stability, every_constant_half_cannot_hold_is_counted)
{
	static char text[8192];
	size_t k = 0;
	for (int i = 1; i <= 300; i++)
		k += (size_t)snprintf(text + k, sizeof text - k, "NoV*%de-9 + ", i);
	snprintf(text + k, sizeof text - k, "NoV");
	run(text);
	int shown = 0, more = 0;
	for (const char *p = st.constants; (p = strstr(p, "(subnormal in half")); p++)
		shown++;
	const char *tail = strstr(st.constants, "and ");
	cr_assert_not_null(tail, "%s", st.constants);
	cr_assert_eq(sscanf(tail, "and %d more", &more), 1, "%s", tail);
	cr_assert_eq(shown + more, 300, "%d shown, %d more", shown, more);
}

/* ---- issue 21: nothing is safe that is not finite, or right only by luck ---- */

static void run_fails(const char *text, const char *want)
{
	char err[256] = "";
	bk_stability_free(&st);
	cr_assert_eq(bk_stability_run("form", text, NULL, BK_STAB_TOL, &st, err, sizeof err), -1, "%s accepted", text);
	cr_assert_not_null(strstr(err, want), "%s: %s", text, err);
}

/* NaN or infinite at every sample, in long double too: nothing can be judged
 * against such a reference, and nothing it holds is "safe". sqrt(NoV - 2) and
 * log2(NoV - 1) (NaN for NoV < 1, -inf at 1) read NoV only, 11 cosines x 13
 * roughness values of the grid; 1/0 reads nothing, one sample per r. */
Test(stability, a_form_nonfinite_everywhere_is_refused)
{
	run_fails("sqrt(NoV-2)", "NaN or infinite at every one of the 143 samples of the grid (NoV = 0: NaN)");
	run_fails("log2(NoV-1)", "NaN or infinite at every one of the 143 samples of the grid (NoV = 0: NaN)");
	run_fails("1/0", "NaN or infinite at every one of the 13 samples of the grid (it reads no input: +inf)");
	/* negative control: finite at one sample of 143 (NoV = 1) is judged */
	run("sqrt(NoV-1)");
	cr_assert_eq(st.ref_nonfinite, 130);
	cr_assert_eq(st.safe_as_is, 0);
}

/* A pole somewhere (NoV/NoV is 0/0 at NoV = 0, in every precision): no
 * precision is wrong there, but the form is not safe as is. */
Test(stability, a_form_with_a_pole_is_never_safe_as_is)
{
	run("NoV/NoV");
	cr_assert_eq(st.p[2].wrong, 0);
	cr_assert_eq(st.ref_nonfinite, (size_t)bk_stab_nr);
	cr_assert_eq(st.safe_as_is, 0);
	cr_assert_str_eq(st.pole, "NoV = 0: NaN");
	run("NoV/(NoV + 1)"); /* negative control */
	cr_assert_eq(st.safe_as_is, 1);
}

/* (300 NoV)^2 passes 65504 for NoV >= 0.9 and rounds to 0 below 2^-25 for
 * NoV <= 1e-7 (an overflow, or 0/0): half gets inf/inf or 0/0 = NaN, which
 * min(1, NaN) hides as 1, the right answer. Counted per grid cosine from
 * those bounds, at each of the 13 roughness values; in double only NoV = 0
 * is 0/0. The 201^2 = 40401 of the negative control stays in range. */
Test(stability, an_overflow_hidden_by_min_is_never_safe)
{
	size_t want = 0;
	for (int c = 0; c < bk_stab_ncos; c++) {
		double x = 300 * bk_stab_cos[c];
		want += (x * x > 65504 || x * x < 0x1p-25) * (size_t)bk_stab_nr;
	}
	cr_assert_eq(want, 6 * 13);
	cr_assert_eq(half_eval("min(1, sq(NoV*300)/sq(NoV*300))", 1, 0.5, 0.5, 0.5, 0.5), 1.0, "hidden in the value");
	run("min(1, sq(NoV*300)/sq(NoV*300))");
	cr_assert_eq(st.p[2].wrong, want);
	cr_assert_eq(st.p[2].hidden, want);
	cr_assert_eq(st.p[0].wrong, (size_t)bk_stab_nr, "0/0 at NoV = 0 in double too");
	cr_assert_eq(st.safe_as_is, 0);
	cr_assert_eq(st.guarded_ok, 0, "%s", st.guards);
	run("min(1, sq(NoV*200 + 1)/sq(NoV*200 + 1))");
	cr_assert_eq(st.p[2].wrong, 0);
	cr_assert_eq(st.safe_as_is, 1);
}

/* 70000 cannot be held in half: the constant itself overflows, and inf * NoV
 * = inf, min(1, inf) = 1 is the right value for NoV >= 1.5e-5. Every sample
 * fails in half; single holds 70000 and is right. */
Test(stability, a_constant_half_cannot_hold_is_an_overflow)
{
	run("min(1, 70000*NoV)");
	cr_assert_eq(st.p[2].wrong, st.p[2].n);
	cr_assert_eq(st.p[1].wrong, 0);
	cr_assert_eq(st.safe_as_is, 0);
}
