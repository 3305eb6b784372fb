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
#include <string.h>

static bk_stability st;

static void run(const char *text)
{
	char err[256];
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
