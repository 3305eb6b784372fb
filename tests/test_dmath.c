/*
 * test_dmath.c — brdf/dmath.c: sin, cos and acos, exp2, log2, pow, exp and
 * log whose bits do not depend on the CPU, checked against glibc's long
 * double functions (an independent implementation with 11 more bits), at the
 * values known exactly, and in C11's special cases (Annex F, which libm
 * follows exactly). Each sweep's bound has a negative control: the same
 * sweep over a function doctored by two ulps must fail it.
 */
#include "dmath.h"

#include <criterion/criterion.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

/* π to double precision (PI is POSIX's, not C11's) */
#define PI 3.14159265358979323846

/* |got - ref| in units in the last place of the double nearest ref. */
static double ulps(double got, long double ref)
{
	double r = fabs((double)ref);
	double u = r == 0.0 ? 0x1p-1074 : nextafter(r, INFINITY) - r;
	return (double)(fabsl((long double)got - ref) / u);
}

Test(dmath, sin_cos_within_one_and_a_half_ulp_on_their_domain)
{
	double worst_s = 0, worst_c = 0;
	for (int i = -400000; i <= 400000; i++) {
		double x = 8.0 * i / 400000.0 + 1e-7 * (i % 7); /* off the grid too */
		if (fabs(x) > 8.0)
			continue;
		worst_s = fmax(worst_s, ulps(bk_dsin(x), sinl(x)));
		worst_c = fmax(worst_c, ulps(bk_dcos(x), cosl(x)));
	}
	cr_expect(worst_s <= 1.5, "sin: %.3f ulp", worst_s);
	cr_expect(worst_c <= 1.5, "cos: %.3f ulp", worst_c);
}

Test(dmath, acos_within_two_ulp_on_minus_one_to_one)
{
	double worst = 0;
	for (int i = -400000; i <= 400000; i++) {
		double c = i / 400000.0;
		worst = fmax(worst, ulps(bk_dacos(c), acosl(c)));
	}
	/* the ends, where acos has its square-root behaviour */
	const double ends[] = {1 - 0x1p-53, 1 - 0x1p-30, -1 + 0x1p-53, -1 + 0x1p-30, 0x1p-1074, -0.5, 0.5};
	for (size_t k = 0; k < sizeof ends / sizeof ends[0]; k++)
		worst = fmax(worst, ulps(bk_dacos(ends[k]), acosl(ends[k])));
	cr_expect(worst <= 2.0, "acos: %.3f ulp", worst);
}

Test(dmath, exact_angles)
{
	cr_expect_eq(bk_dcos(0.0), 1.0);
	cr_expect_eq(bk_dsin(0.0), 0.0);
	cr_expect_eq(bk_dsin(PI / 2), 1.0);      /* sin of the double nearest π/2 rounds to 1 */
	cr_expect_eq(bk_dacos(1.0), 0.0);
	cr_expect_eq(bk_dacos(0.0), PI / 2);     /* the double nearest π/2 */
	cr_expect_eq(bk_dacos(-1.0), PI);        /* the double nearest π */
	cr_expect(isnan(bk_dacos(1.5)));
	cr_expect(isnan(bk_dacos(NAN)));
	/* cos(π/3) = 1/2 and acos(1/2) = π/3, to rounding */
	cr_expect(fabs(bk_dcos(PI / 3) - 0.5) <= 0x1p-53);
	cr_expect(fabs(bk_dacos(0.5) - PI / 3) <= 0x1p-52);
}

/* ---- exp2, log2, pow, exp, log --------------------------------------------- */

static double U(uint64_t *s) /* uniform in [0, 1), a fixed LCG: the same sweep on every run */
{
	*s = *s * 6364136223846793005ull + 1442695040888963407ull;
	return (double)(*s >> 11) * 0x1p-53;
}

typedef double (*fn1)(double);

/* The worst error in ulps of f against ref over x in [lo, hi] (n points,
 * uniform, and every 2^-20 step of a window around w). */
static double sweep1(fn1 f, long double (*ref)(long double), double lo, double hi, double w, long n)
{
	uint64_t s = 7;
	double worst = 0;
	for (long i = 0; i < n; i++) {
		double x = lo + (hi - lo) * U(&s);
		worst = fmax(worst, ulps(f(x), ref(x)));
	}
	for (int i = -4096; i <= 4096; i++) {
		double x = w + i * 0x1p-20;
		worst = fmax(worst, ulps(f(x), ref(x)));
	}
	return worst;
}

/* log2 and log sweep x = m 2^e: every exponent, subnormals included, and
 * the window round 1 where the result is small */
static double sweep_log(fn1 f, long double (*ref)(long double), long n)
{
	uint64_t s = 11;
	double worst = 0;
	for (long i = 0; i < n; i++) {
		double x = ldexp(0.5 + U(&s), (int)(i % 2098) - 1074);
		if (x > 0)
			worst = fmax(worst, ulps(f(x), ref(x)));
	}
	for (int i = -8192; i <= 8192; i++)
		if (i)
			worst = fmax(worst, ulps(f(1.0 + i * 0x1p-30), ref(1.0L + i * 0x1p-30L)));
	return worst;
}

static double sweep_pow(double (*f)(double, double), long n)
{
	uint64_t s = 13;
	double worst = 0;
	for (long i = 0; i < n; i++) {
		/* bases over the whole range and near 1, exponents up to |y log2 x| ~ 1000 */
		double x = i % 3 ? ldexp(0.5 + U(&s), (int)(i % 200) - 100) : 1.0 + (U(&s) - 0.5) * 1e-3;
		double y = (U(&s) - 0.5) * (i % 5 ? 8.0 : 2000.0 / (fabs(log2(x)) + 1));
		long double r = powl(x, y);
		if (fabsl(r) < 0x1p-1022L || fabsl(r) > 0x1p1023L)
			continue; /* subnormal or past double: the exp2 sweep covers the ends */
		worst = fmax(worst, ulps(f(x, y), r));
	}
	return worst;
}

/* doctored by two ulps: the negative controls */
static double exp2_off(double x) { return bk_dexp2(x) * (1 + 0x1p-51); }
static double log2_off(double x) { return bk_dlog2(x) * (1 + 0x1p-51); }
static double pow_off(double x, double y) { return bk_dpow(x, y) * (1 + 0x1p-51); }
static double exp_off(double x) { return bk_dexp(x) * (1 + 0x1p-51); }
static double log_off(double x) { return bk_dlog(x) * (1 + 0x1p-51); }
/* subnormal results: two ulps there are two steps of the smallest subnormal */
static double exp2_sub_off(double x) { return bk_dexp2(x) + 0x1p-1073; }
static double exp_sub_off(double x) { return bk_dexp(x) + 0x1p-1073; }
static double log10_off(double x) { return bk_dlog10(x) * (1 + 0x1p-51); }
static double log1p_off(double x) { return bk_dlog1p(x) * (1 + 0x1p-51); }
static double erfc_off(double x) { return bk_derfc(x) * (1 + 0x1p-50); }

/* erfc sweeps [-6, 26.5] (its results normal: erfc(26.5) ~ 1e-307) and the
 * window [0, 2^-20 * 4096] round 0 where the series starts */
static double sweep_erfc(fn1 f, long n)
{
	uint64_t s = 17;
	double worst = 0;
	for (long i = 0; i < n; i++) {
		double x = -6.0 + 32.5 * U(&s);
		worst = fmax(worst, ulps(f(x), erfcl(x)));
	}
	for (int i = 0; i <= 4096; i++)
		worst = fmax(worst, ulps(f(i * 0x1p-20), erfcl(i * 0x1p-20)));
	return worst;
}

/* log1p sweeps u = ±m 2^e over every exponent (the negative side above -1,
 * where 1 + u is exact from -1/2 down), and the window round 0 where 1 + u
 * loses most of u */
static double sweep_log1p(fn1 f, long n)
{
	uint64_t s = 13;
	double worst = 0;
	for (long i = 0; i < n; i++) {
		double u = ldexp(0.5 + U(&s), (int)(i % 2098) - 1074);
		if (i % 2)
			u = -ldexp(0.5 + U(&s), -(int)(i % 1075)); /* in (-1, 0) */
		if (u > -1.0 && isfinite(u))
			worst = fmax(worst, ulps(f(u), log1pl(u)));
	}
	for (int i = -8192; i <= 8192; i++) {
		double u = i * 0x1p-40 + i * i * 0x1p-70;
		worst = fmax(worst, ulps(f(u), log1pl(u)));
	}
	return worst;
}

/* the double nearest 10^n, from its decimal text (strtod rounds correctly) */
static double strtod_pow10(int n)
{
	char buf[16];
	snprintf(buf, sizeof buf, "1e%d", n);
	return strtod(buf, NULL);
}

/* C11 Annex F's special cases, which glibc follows exactly: the same value
 * and sign (NaN: any NaN) */
static int same_value(double a, double b)
{
	return (isnan(a) && isnan(b)) || (a == b && signbit(a) == signbit(b));
}

Test(dmath, exp2_log2_within_two_thirds_of_an_ulp)
{
	/* measured: exp2 0.62 (normal results), 0.75 (subnormal ones: the one
	 * rounding to 53 bits comes before the scaling's rounding), log2 0.51
	 * (brdf/vmath.h) */
	double e = sweep1(bk_dexp2, exp2l, -1022.0, 1023.9, 0.0, 1000000);
	double es = sweep1(bk_dexp2, exp2l, -1074.0, -1022.0, -1023.0, 100000);
	double l = sweep_log(bk_dlog2, log2l, 1000000);
	cr_expect(e <= 0.65, "exp2: %.3f ulp", e);
	cr_expect(es <= 0.76, "exp2, subnormal results: %.3f ulp", es);
	cr_expect(l <= 0.52, "log2: %.3f ulp", l);
	cr_expect(sweep1(exp2_off, exp2l, -1022.0, 1023.9, 0.0, 100000) > 0.65, "the exp2 sweep cannot fail");
	cr_expect(sweep1(exp2_sub_off, exp2l, -1074.0, -1022.0, -1023.0, 10000) > 0.76, "the subnormal sweep cannot fail");
	cr_expect(sweep_log(log2_off, log2l, 100000) > 0.52, "the log2 sweep cannot fail");
}

Test(dmath, exp_log_pow_within_two_thirds_of_an_ulp)
{
	/* measured: exp 0.63 (normal results; subnormal ones as exp2's), log
	 * 0.51, pow 0.65 */
	double e = sweep1(bk_dexp, expl, -708.0, 709.7, 0.0, 1000000);
	double es = sweep1(bk_dexp, expl, -745.0, -708.4, -720.0, 100000);
	cr_expect(es <= 0.76, "exp, subnormal results: %.3f ulp", es);
	double l = sweep_log(bk_dlog, logl, 1000000);
	double p = sweep_pow(bk_dpow, 1000000);
	cr_expect(e <= 0.67, "exp: %.3f ulp", e);
	cr_expect(l <= 0.52, "log: %.3f ulp", l);
	cr_expect(p <= 0.67, "pow: %.3f ulp", p);
	cr_expect(sweep1(exp_off, expl, -708.0, 709.7, 0.0, 100000) > 0.67, "the exp sweep cannot fail");
	cr_expect(sweep_pow(pow_off, 100000) > 0.67, "the pow sweep cannot fail");
	cr_expect(sweep_log(log_off, logl, 100000) > 0.52, "the log sweep cannot fail");
	cr_expect(sweep1(exp_sub_off, expl, -745.0, -708.4, -720.0, 10000) > 0.76, "the subnormal exp sweep cannot fail");
}

Test(dmath, log10_within_about_half_an_ulp_and_exact_at_powers_of_ten)
{
	double l = sweep_log(bk_dlog10, log10l, 1000000);
	cr_expect(l <= 0.52, "log10: %.3f ulp", l);
	cr_expect(sweep_log(log10_off, log10l, 100000) > 0.52, "the log10 sweep cannot fail");
	/* the doubles nearest 10^n: floor(log10) must give n (a plot's ticks) */
	for (int n = -300; n <= 300; n++) {
		double x = strtod_pow10(n);
		cr_expect_eq(bk_dlog10(x), (double)n, "log10(1e%d) = %.17g", n, bk_dlog10(x));
	}
	cr_expect(same_value(bk_dlog10(1.0), 0.0) && same_value(bk_dlog10(0.0), -INFINITY) && isnan(bk_dlog10(-1.0)) &&
	          bk_dlog10(INFINITY) == INFINITY);
}

Test(dmath, log1p_within_about_half_an_ulp)
{
	double l = sweep_log1p(bk_dlog1p, 1000000);
	cr_expect(l <= 0.52, "log1p: %.3f ulp", l);
	cr_expect(sweep_log1p(log1p_off, 100000) > 0.52, "the log1p sweep cannot fail");
	/* C11's specials, against libm's (exact there) */
	static const double v[] = {0.0, -0.0, -1.0, -2.0, -0x1p-1074, 0x1p-1074, 0x1p-60, -0x1p-60, INFINITY, -INFINITY, NAN, 1e300};
	for (size_t i = 0; i < sizeof v / sizeof v[0]; i++)
		cr_expect(same_value(bk_dlog1p(v[i]), log1p(v[i])), "log1p(%a): %a, libm %a", v[i], bk_dlog1p(v[i]),
		          log1p(v[i]));
}

Test(dmath, erfc_within_four_and_a_half_ulp)
{
	double e = sweep_erfc(bk_derfc, 1000000);
	cr_expect(e <= 4.5, "erfc: %.3f ulp", e);
	cr_expect(sweep_erfc(erfc_off, 100000) > 4.5, "the erfc sweep cannot fail");
	/* values that are exact, against libm's */
	static const double v[] = {0.0, -0.0, INFINITY, -INFINITY, NAN, 30.0, -30.0, 1e300, -1e300};
	for (size_t i = 0; i < sizeof v / sizeof v[0]; i++)
		cr_expect(same_value(bk_derfc(v[i]), erfc(v[i])), "erfc(%a): %a, libm %a", v[i], bk_derfc(v[i]),
		          erfc(v[i]));
}

Test(dmath, exact_values)
{
	for (int n = -1074; n <= 1023; n++) {
		cr_expect_eq(bk_dexp2(n), ldexp(1.0, n), "exp2(%d)", n);
		cr_expect_eq(bk_dlog2(ldexp(1.0, n)), (double)n, "log2(2^%d)", n);
		cr_expect_eq(bk_dpow(2.0, n), ldexp(1.0, n), "pow(2, %d)", n);
	}
	cr_expect_eq(bk_dexp(0.0), 1.0);
	cr_expect(bk_dlog(1.0) == 0.0 && !signbit(bk_dlog(1.0)), "log(1) = +0");
	cr_expect(bk_dlog2(1.0) == 0.0 && !signbit(bk_dlog2(1.0)), "log2(1) = +0");
	cr_expect_eq(bk_dpow(3.0, 2.0), 9.0);
	cr_expect_eq(bk_dpow(-3.0, 3.0), -27.0);
	cr_expect_eq(bk_dpow(0.25, 0.5), 0.5);
	cr_expect_eq(bk_dpow(10.0, 22.0), 1e22); /* the largest power of ten a double holds exactly */
}

Test(dmath, c11_special_cases)
{
	static const double v[] = {0.0, -0.0, 1.0, -1.0, 0.5, -0.5, 2.0, -2.0, 3.0, -3.0, 2.5, -2.5, 0x1p60, -0x1p60,
	                           0x1p-1074, INFINITY, -INFINITY, NAN, 1024.0, -1075.0, 1e300, -1e300};
	enum { NV = sizeof v / sizeof v[0] };
	for (int i = 0; i < NV; i++) {
		cr_expect(same_value(bk_dexp2(v[i]), exp2(v[i])), "exp2(%a): %a, libm %a", v[i], bk_dexp2(v[i]), exp2(v[i]));
		cr_expect(same_value(bk_dexp(v[i]), exp(v[i])), "exp(%a): %a, libm %a", v[i], bk_dexp(v[i]), exp(v[i]));
		if (!(v[i] > 0) || isinf(v[i]) || v[i] == 1.0) { /* the specials of log */
			cr_expect(same_value(bk_dlog2(v[i]), log2(v[i])), "log2(%a)", v[i]);
			cr_expect(same_value(bk_dlog(v[i]), log(v[i])), "log(%a)", v[i]);
		}
		for (int j = 0; j < NV; j++) {
			double x = v[i], y = v[j];
			/* every pair that is a special case of pow (zero, one, infinite or
			 * NaN operand, a negative base) and a few that are not */
			int special = x == 0 || y == 0 || fabs(x) == 1 || isinf(x) || isinf(y) || isnan(x) || isnan(y) || x < 0;
			if (special || (x == 2.0 && fabs(y) < 100))
				cr_expect(same_value(bk_dpow(x, y), pow(x, y)), "pow(%a, %a): %a, libm %a", x, y, bk_dpow(x, y),
				          pow(x, y));
		}
	}
}
