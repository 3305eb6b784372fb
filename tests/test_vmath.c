/*
 * test_vmath.c — brdf/vmath.h's exp2 and log2 of floats: within 1 ulp of the
 * correctly rounded value (the reference: glibc's double exp2 and log2 of the
 * same float, rounded once to float — an independent implementation with 29
 * more bits), exact where the value is a float (exp2 of integers, log2 of
 * powers of two), IEEE specials and underflow as libm has them, monotone
 * across the range reduction's seams, the same bits from the baseline and
 * the AVX2 copies; and in the IR: f32 runs them, f16 results stay within a
 * half ulp of what libm's exp2f and log2f gave.
 *
 * The sweeps take every 331st float of the ranges that matter plus every
 * float of the windows where errors hide (x near 0 and 1, subnormal results
 * and inputs). Every one of the 2^32 floats (the figures in ir_eval.c; about
 * 2.5 CPU-minutes) with BK_VMATH_ALL=1 build/test_brdfkit --filter
 * 'vmath/every_float' (skipped otherwise: too long for make test).
 */
#include "brdf.h"
#include "brdf_ops.h" /* bk_ir_force_libm */
#include "vmath.h"

#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <stdint.h>
#include <string.h>

static float from_bits(uint32_t u)
{
	float f;
	memcpy(&f, &u, sizeof f);
	return f;
}

static uint32_t bits_of(float f)
{
	uint32_t u;
	memcpy(&u, &f, sizeof u);
	return u;
}

/* Floats between a and b (finite or equal): their distance on the ordered
 * integer line, -0 and +0 one point. */
static int64_t fdist(float a, float b)
{
	int64_t ia = (int32_t)bits_of(a), ib = (int32_t)bits_of(b);
	ia = ia < 0 ? -(ia & 0x7fffffff) : ia;
	ib = ib < 0 ? -(ib & 0x7fffffff) : ib;
	return ia > ib ? ia - ib : ib - ia;
}

typedef float (*fn_f)(float);
typedef double (*ref_f)(double);

/* One sweep's account: against the reference, the worst distance in floats
 * from the correctly rounded value and the worst error in ulps of the exact
 * value (libm's double), samples outside the bound; monotonicity; and the
 * baseline against the AVX2 copy. */
typedef struct account {
	long n, over, nonmono, copies_differ;
	int64_t worst_dist;
	double worst_ulp;
	float worst_at;
} account;

static double ulp_at(double v)
{
	float f = (float)fabs(v);
	if (f < 0x1p-126f)
		return 0x1p-149;
	if (isinf(f))
		f = 0x1p127f;
	int e;
	frexpf(f, &e);
	return ldexp(1.0, e - 24);
}

/* got against ref at one input: 1 when within 1 ulp (the same NaN-ness,
 * the same infinity) */
static int within_one(float got, double ref, account *a, float x)
{
	float cr = (float)ref;
	if (isnan(cr) || isnan(got))
		return isnan(cr) && isnan(got);
	if (isinf(cr) || isinf(got))
		return got == cr || fdist(got, cr) <= 1; /* the largest float next to +inf is 1 away */
	int64_t d = fdist(got, cr);
	double u = fabs((double)got - ref) / ulp_at(ref);
	if (d > a->worst_dist || (d == a->worst_dist && u > a->worst_ulp)) {
		a->worst_dist = d > a->worst_dist ? d : a->worst_dist;
		a->worst_at = x;
	}
	if (u > a->worst_ulp)
		a->worst_ulp = u;
	return d <= 1 && u <= 1.0;
}

enum { CH = 4096 };

/* Floats of bits lo, lo + stride, ... <= hi, in the order of their bits
 * (increasing |x|: dir = +1 for positive x, -1 for negative, the order in
 * which fn must not decrease or increase). fn_n: the array function (NULL:
 * fn one at a time, for the perturbed controls). */
static void sweep(account *a, fn_f fn, void (*fn_n)(float *, const float *, size_t, int), ref_f ref,
                  uint32_t lo, uint32_t hi, uint32_t stride, int dir)
{
	static float x[CH], y[CH], y2[CH];
	float prev = NAN;
	uint64_t u = lo;
	while (u <= hi) {
		size_t m = 0;
		for (; m < CH && u <= hi; m++, u += stride)
			x[m] = from_bits((uint32_t)u);
		if (fn_n) {
			fn_n(y, x, m, 0);
			fn_n(y2, x, m, 1);
		} else {
			for (size_t i = 0; i < m; i++)
				y[i] = y2[i] = fn(x[i]);
		}
		for (size_t i = 0; i < m; i++) {
			a->n++;
			a->copies_differ += bits_of(y[i]) != bits_of(y2[i]);
			a->over += !within_one(y[i], ref((double)x[i]), a, x[i]);
			if (!isnan(prev) && !isnan(y[i]) && (dir > 0 ? y[i] < prev : y[i] > prev))
				a->nonmono++;
			prev = y[i];
		}
	}
}

#define F(x) bits_of(x##f)

/* The ranges where exp2's value is neither 0 nor inf, the window of
 * subnormal results densely, and around 0 densely. vec = 0 (the controls,
 * one call at a time): every 16th of these. */
static void sweep_exp2(account *a, fn_f fn, int vec)
{
	void (*fn_n)(float *, const float *, size_t, int) = vec ? bk_v_exp2f_n : NULL;
	uint32_t c = vec ? 1 : 16;
	sweep(a, fn, fn_n, exp2, 0, F(129.0), 331 * c, 1);
	sweep(a, fn, fn_n, exp2, F(-0.0), F(-151.0), 331 * c, -1);
	sweep(a, fn, fn_n, exp2, F(-126.0), F(-150.0), 2 * c, -1); /* subnormal results */
	sweep(a, fn, fn_n, exp2, F(127.5), F(128.5), c, 1);        /* the last floats and +inf */
	sweep(a, fn, fn_n, exp2, F(0x1p-30), F(0x1p-30) + (1u << 18), c, 1);
	sweep(a, fn, fn_n, exp2, F(0.3), F(0.3) + (1u << 18), c, 1);
}

/* Every positive float's class: subnormals and around 1 densely. */
static void sweep_log2(account *a, fn_f fn, int vec)
{
	void (*fn_n)(float *, const float *, size_t, int) = vec ? bk_v_log2f_n : NULL;
	uint32_t c = vec ? 1 : 16;
	sweep(a, fn, fn_n, log2, 0, 0x7f800000u, 331 * c, 1);
	sweep(a, fn, fn_n, log2, 1, 0x00800000u + 4096, 7 * c, 1);
	sweep(a, fn, fn_n, log2, F(1.0) - (1u << 18), F(1.0) + (1u << 18), c, 1);
}

static float exp2_el(float x) { return bk_v_exp2f(x); }
static float log2_el(float x) { return bk_v_log2f(x); }

Test(vmath, exp2_within_one_ulp_of_correctly_rounded_and_monotone)
{
	account a = {0};
	sweep_exp2(&a, exp2_el, 1);
	cr_assert_gt(a.n, 7000000);
	cr_expect_eq(a.copies_differ, 0, "exp2: the baseline and AVX2 copies differ on %ld", a.copies_differ);
	cr_expect_eq(a.over, 0, "exp2: %ld of %ld over 1 ulp; worst %lld floats, %.3f ulp at %a", a.over, a.n,
	             (long long)a.worst_dist, a.worst_ulp, (double)a.worst_at);
	/* rounded in double after an error of 2^-40: every one within half an
	 * ulp of the exact value, give or take the reference's own error */
	cr_expect_leq(a.worst_ulp, 0.5001, "exp2: worst %.6f ulp at %a", a.worst_ulp, (double)a.worst_at);
	cr_expect_eq(a.nonmono, 0, "exp2: %ld decreases", a.nonmono);
}

Test(vmath, log2_within_one_ulp_of_correctly_rounded_and_monotone)
{
	account a = {0};
	sweep_log2(&a, log2_el, 1);
	cr_assert_gt(a.n, 7000000);
	cr_expect_eq(a.copies_differ, 0, "log2: the baseline and AVX2 copies differ on %ld", a.copies_differ);
	cr_expect_eq(a.over, 0, "log2: %ld of %ld over 1 ulp; worst %lld floats, %.3f ulp at %a", a.over, a.n,
	             (long long)a.worst_dist, a.worst_ulp, (double)a.worst_at);
	cr_expect_leq(a.worst_ulp, 0.5001, "log2: worst %.6f ulp at %a", a.worst_ulp, (double)a.worst_at);
	cr_expect_eq(a.nonmono, 0, "log2: %ld decreases", a.nonmono);
}

/* Negative controls: the same sweeps catch an implementation 2 ulps off
 * (one ulp up twice), and one that is monotone nowhere (a sawtooth). */
static float exp2_2ulp(float x) { return nextafterf(nextafterf(bk_v_exp2f(x), INFINITY), INFINITY); }
static float log2_2ulp(float x) { return nextafterf(nextafterf(bk_v_log2f(x), INFINITY), INFINITY); }
static float exp2_1ulp(float x) { return nextafterf(bk_v_exp2f(x), INFINITY); }
static float log2_saw(float x) /* 2^-16 relative down where bit 4 is set */
{
	float y = bk_v_log2f(x);
	return (bits_of(x) >> 4 & 1) ? y - fabsf(y) * 0x1p-16f - 0x1p-30f : y;
}

Test(vmath, the_checker_catches_two_ulps_and_a_sawtooth)
{
	account a = {0}, b = {0}, c = {0}, d = {0};
	sweep_exp2(&a, exp2_2ulp, 0);
	sweep_log2(&b, log2_2ulp, 0);
	sweep_log2(&c, log2_saw, 0);
	cr_expect_gt(a.over, a.n / 2, "exp2 2 ulps off: only %ld of %ld caught", a.over, a.n);
	cr_expect_gt(b.over, b.n / 2, "log2 2 ulps off: only %ld of %ld caught", b.over, b.n);
	cr_expect_gt(c.nonmono, 1000, "the sawtooth: %ld decreases", c.nonmono);
	/* and one ulp off fails the half-ulp accuracy asked above */
	sweep_exp2(&d, exp2_1ulp, 0);
	cr_expect_gt(d.worst_ulp, 0.5001, "exp2 1 ulp off: worst %.4f", d.worst_ulp);
}

Test(vmath, exact_values)
{
	for (int k = -149; k <= 127; k++) {
		float want = ldexpf(1.0f, k);
		cr_expect_eq(bits_of(bk_v_exp2f((float)k)), bits_of(want), "exp2(%d)", k);
		float l = bk_v_log2f(want);
		cr_expect_eq(l, (float)k, "log2(2^%d) = %a", k, (double)l);
	}
	cr_expect_eq(bits_of(bk_v_log2f(1.0f)), 0u, "log2(1) is +0");
	cr_expect_eq(bk_v_exp2f(0.0f), 1.0f);
	cr_expect_eq(bk_v_exp2f(-0.0f), 1.0f);
	cr_expect_eq(bk_v_exp2f(0.5f), (float)1.41421356237309504880); /* sqrt(2) rounded */
	cr_expect_eq(bk_v_log2f(8.0f), 3.0f);
	cr_expect_eq(bk_v_log2f(0x1p-149f), -149.0f); /* the smallest subnormal */
	cr_expect_eq(bk_v_log2f(0x1p-140f), -140.0f);
}

Test(vmath, ieee_specials_and_underflow)
{
	cr_expect_eq(bk_v_exp2f(INFINITY), INFINITY);
	cr_expect_eq(bits_of(bk_v_exp2f(-INFINITY)), 0u, "exp2(-inf) is +0");
	cr_expect(isnan(bk_v_exp2f(NAN)));
	cr_expect(isnan(bk_v_exp2f(-NAN)));
	cr_expect_eq(bk_v_exp2f(128.0f), INFINITY);
	cr_expect_eq(bk_v_exp2f(1000.0f), INFINITY);
	cr_expect_eq(bk_v_exp2f(0x1.fffffep6f), (float)exp2(0x1.fffffep6)); /* the largest below 128: finite */
	cr_expect(isfinite(bk_v_exp2f(0x1.fffffep6f)));
	/* gradual underflow: subnormal results rounded once */
	cr_expect_eq(bk_v_exp2f(-127.0f), 0x1p-127f);
	cr_expect_eq(bk_v_exp2f(-149.0f), 0x1p-149f);
	cr_expect_eq(bk_v_exp2f(-140.5f), (float)exp2(-140.5));
	cr_expect_eq(bk_v_exp2f(-149.4f), 0x1p-149f);                 /* 2^-149.4 rounds up to the smallest */
	cr_expect_eq(bits_of(bk_v_exp2f(-150.0f)), 0u, "a tie at half the smallest rounds to even: +0");
	cr_expect_eq(bk_v_exp2f(-149.9f), 0x1p-149f);                 /* above the tie */
	cr_expect_eq(bits_of(bk_v_exp2f(-151.0f)), 0u);
	cr_expect_eq(bits_of(bk_v_exp2f(-1e30f)), 0u);
	cr_expect_eq(bk_v_log2f(0.0f), -INFINITY);
	cr_expect_eq(bk_v_log2f(-0.0f), -INFINITY);
	cr_expect(isnan(bk_v_log2f(-1.0f)));
	cr_expect(isnan(bk_v_log2f(-0x1p-149f)));
	cr_expect(isnan(bk_v_log2f(-INFINITY)));
	cr_expect(isnan(bk_v_log2f(NAN)));
	cr_expect_eq(bk_v_log2f(INFINITY), INFINITY);
	cr_expect_eq(bk_v_log2f(0x1.fffffep127f), (float)log2(0x1.fffffep127)); /* 128 rounded */
	cr_expect_eq(bk_v_log2f(0x1.8p-140f), (float)log2(0x1.8p-140));         /* a subnormal */
}

/* The seams: exp2 where round(x) steps (k + 1/2), log2 where m wraps
 * (sqrt(1/2) 2^e, bits 0x3f3504f3 + e 2^23) and where subnormals begin;
 * 64 floats each side must not decrease. */
static long steps_down(fn_f fn, float mid)
{
	long bad = 0;
	float x = mid, prev;
	for (int i = 0; i < 64; i++)
		x = nextafterf(x, -INFINITY);
	prev = fn(x);
	for (int i = 0; i < 128; i++) {
		x = nextafterf(x, INFINITY);
		float y = fn(x);
		bad += y < prev;
		prev = y;
	}
	return bad;
}

Test(vmath, monotone_across_the_reductions_seams)
{
	long bad = 0;
	for (int k = -151; k <= 128; k++)
		bad += steps_down(exp2_el, (float)k + 0.5f);
	for (int e = -149; e <= 128; e++)
		bad += steps_down(log2_el, ldexpf(0.70710677f, e));
	bad += steps_down(log2_el, 0x1p-126f);
	bad += steps_down(exp2_el, -126.0f);
	cr_expect_eq(bad, 0, "%ld steps down at the seams", bad);
	/* control: a function with a step down at sqrt(1/2) is caught */
	cr_expect_gt(steps_down(log2_saw, 0.70710677f), 0);
}

/* The sweeps above compare the two copies too (on a CPU without AVX2 both
 * are the baseline); here that this CPU runs the AVX2 one, and that the
 * arrays' copies give the inline function's bits, one float at a time. */
Test(vmath, baseline_and_avx2_copies_same_bits)
{
	if (!bk_v_have_avx2())
		cr_skip_test("no AVX2 on this CPU: only the baseline copy runs here");
	for (uint64_t u = 0; u <= 0xffffffffu; u += 7919 * 997) {
		float x = from_bits((uint32_t)u), y1, y2;
		bk_v_exp2f_n(&y1, &x, 1, 1);
		bk_v_log2f_n(&y2, &x, 1, 1);
		float e = bk_v_exp2f(x), l = bk_v_log2f(x);
		cr_expect(bits_of(y1) == bits_of(e) || (isnan(y1) && isnan(e)), "exp2(%a)", (double)x);
		cr_expect(bits_of(y2) == bits_of(l) || (isnan(y2) && isnan(l)), "log2(%a)", (double)x);
	}
}

Test(vmath, every_float, .timeout = 1200)
{
	if (!getenv("BK_VMATH_ALL"))
		cr_skip_test("every float: set BK_VMATH_ALL=1 (minutes)");
	account a = {0}, b = {0};
	sweep(&a, exp2_el, bk_v_exp2f_n, exp2, 0, 0x7fffffffu, 1, 1);
	sweep(&a, exp2_el, bk_v_exp2f_n, exp2, 0x80000000u, 0xffffffffu, 1, -1);
	sweep(&b, log2_el, bk_v_log2f_n, log2, 0, 0xffffffffu, 1, 1);
	cr_log_info("exp2: %ld floats, worst %lld floats from the rounded reference, %.4f ulp at %a; log2: %ld floats, "
	            "worst %lld, %.4f ulp at %a", a.n, (long long)a.worst_dist, a.worst_ulp, (double)a.worst_at, b.n,
	            (long long)b.worst_dist, b.worst_ulp, (double)b.worst_at);
	cr_expect_eq(a.over + b.over, 0, "exp2 %ld, log2 %ld over 1 ulp", a.over, b.over);
	cr_expect_eq(a.copies_differ + b.copies_differ, 0);
	cr_expect_eq(a.nonmono, 0);
}

/* ---- in the IR ---------------------------------------------------------------- */

static bk_form *form(const char *text)
{
	bk_form_error e;
	bk_form *f = bk_form_parse(text, &e);
	cr_assert_not_null(f, "%s: %s", text, e.message);
	return f;
}

Test(vmath, ir_f32_runs_them_and_libm_on_request)
{
	enum { N = 1000 };
	static double x[N], out[N];
	for (int i = 0; i < N; i++)
		x[i] = (float)(-30.0 + 60.0 * i / N + 1e-4 * (i % 7)); /* floats: no rounding on the way in */
	const double *in[BK_IN_COUNT] = {x};
	static const char *const texts[] = {"exp2(NoV)", "log2(NoV)"};
	for (int t = 0; t < 2; t++) {
		bk_form *f = form(texts[t]);
		for (int libm = 0; libm < 2; libm++) {
			bk_ir_force_libm(libm);
			cr_assert_eq(bk_form_eval(f, BK_F32, N, in, NULL, out), 0);
			for (int i = 0; i < N; i++) {
				float xi = (float)x[i];
				float want = libm ? (t ? log2f(xi) : exp2f(xi)) : (t ? bk_v_log2f(xi) : bk_v_exp2f(xi));
				cr_expect(out[i] == want || (isnan(out[i]) && isnan(want)), "%s at %a (%s): %a, want %a", texts[t],
				          x[i], libm ? "libm" : "vmath", out[i], (double)want);
			}
		}
		bk_ir_force_libm(0);
		bk_form_free(f);
	}
}

/* The half ulp at |v| (half: 11 significant bits, subnormals below 2^-14). */
static double half_ulp(double v)
{
	v = fabs(v);
	if (v < 0x1p-14)
		return 0x1p-24;
	int e;
	frexp(v, &e);
	return ldexp(1.0, e - 11);
}

/* Every finite half as an input of exp2, log2, exp, log and pow in f16:
 * vmath's and libm's exp2f/log2f give the same half or neighbours (a float
 * result an ulp apart can round to the other side of a half midpoint). In
 * f16 every exp2 and log2 reads a half (its operand was rounded to half), so
 * these are all the inputs it can see: with glibc's exp2f and log2f (Debian
 * 12) none moved, so no f16 result anywhere changed with vmath. The control:
 * pow with another exponent is counted as moved. */
Test(vmath, ir_f16_within_a_half_ulp_of_libm)
{
	enum { NH = 63488 }; /* the finite halves: 2 signs x 31 exponents x 1024 */
	static double x[NH], o0[NH], o1[NH];
	size_t n = 0;
	for (int s = 0; s < 2; s++)
		for (int e = 0; e < 31; e++)
			for (int m = 0; m < 1024; m++) {
				double v = e ? ldexp(1.0 + m / 1024.0, e - 15) : ldexp(m / 1024.0, -14);
				x[n++] = s ? -v : v;
			}
	cr_assert_eq(n, (size_t)NH);
	const double *in[BK_IN_COUNT] = {x};
	double p[1] = {2.5};
	static const char *const texts[] = {"exp2(NoV)", "log2(NoV)", "exp(NoV)", "log(NoV)", "pow(NoV, p0)"};
	long moved = 0;
	for (int t = 0; t < 5; t++) {
		bk_form *f = form(texts[t]);
		bk_ir_force_libm(1);
		cr_assert_eq(bk_form_eval(f, BK_F16, NH, in, p, o0), 0);
		bk_ir_force_libm(0);
		cr_assert_eq(bk_form_eval(f, BK_F16, NH, in, p, o1), 0);
		for (size_t i = 0; i < NH; i++) {
			if (isnan(o0[i]) || isnan(o1[i]) || isinf(o0[i]) || isinf(o1[i])) {
				cr_expect(o0[i] == o1[i] || (isnan(o0[i]) && isnan(o1[i])), "%s at %a: libm %a, vmath %a", texts[t],
				          x[i], o0[i], o1[i]);
				continue;
			}
			moved += o0[i] != o1[i];
			cr_expect_leq(fabs(o0[i] - o1[i]), half_ulp(fmax(fabs(o0[i]), fabs(o1[i]))),
			              "%s at %a: libm %a, vmath %a", texts[t], x[i], o0[i], o1[i]);
		}
		bk_form_free(f);
	}
	cr_log_info("f16: %ld of %d results moved by a half ulp", moved, 5 * NH);
	cr_expect_eq(moved, 0, "%ld of %d f16 results moved", moved, 5 * NH);
	bk_form *f = form("pow(NoV, p0)");
	double p2[1] = {2.4};
	cr_assert_eq(bk_form_eval(f, BK_F16, NH, in, p2, o0), 0);
	long control = 0;
	for (size_t i = 0; i < NH; i++)
		control += o0[i] != o1[i] && !(isnan(o0[i]) && isnan(o1[i]));
	cr_expect_gt(control, 1000, "pow(x, 2.4) against pow(x, 2.5): %ld moved", control);
	bk_form_free(f);
}
