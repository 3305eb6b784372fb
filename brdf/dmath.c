/*
 * dmath.c — sine, cosine and arc cosine that give the same bits on every
 * x86-64 machine, for the reference integrals; and (the second half, on
 * vmath.h's double exp2 and log2) exp2, log2, pow, exp, log, log10 and log1p.
 *
 * Why: glibc picks FMA or non-FMA variants of cos, sin, acos, pow, log, exp at
 * run time (ifunc on the CPU's features), and they differ in the last bit
 * (GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA changes ~1 result in 1,000 of
 * cos and pow here). The targets' reference values then differ by an ulp,
 * and a fit whose optimum sits on a kink of saturate() or min() walks to a
 * different point: make results did not reproduce on another machine. These
 * functions use only +, -, *, /, sqrt and comparisons in double (C11 with no
 * -ffp-contract means no fused multiply-add), so their bits depend on nothing
 * but the input. sqrt is correctly rounded by IEEE 754, hence the same
 * everywhere.
 *
 * Precision (tests/test_dmath.c, against long double): within 1.5 ulp for
 * sin and cos on [-8, 8] (measured 1.32, 1.46) and 2 ulp for acos on [-1, 1]
 * (1.66; a third Newton step gives 1.29 but costs 56 ns instead of 35, and
 * the integrator needs acos only for its breakpoints). The domain is what the
 * integrators need (angles of the hemisphere), not the whole real line.
 */
#include "dmath.h"
#include "vmath.h"

/* π/2 in two parts (fdlibm's pio2_1, pio2_1t): the first has 33 significant
 * bits, so k·PIO2_HI is exact for |k| < 2^20 and x - k·PIO2_HI is exact
 * (Sterbenz) for the k nearest x·2/π. */
#define PIO2_HI 1.57079632673412561417e+00
#define PIO2_LO 6.07710050650619224932e-11
/* π/2 as the nearest double and what it misses, for acos. */
#define PIO2_D 1.57079632679489655800e+00
#define PIO2_DLO 6.12323399573676603587e-17

/* Taylor coefficients 1/n!, alternating: on |r| <= π/4 the first omitted term
 * is below r^19/19! < 1e-19 (sin) and r^20/20! < 1e-21 (cos) relative to 1. */
static double sin_k(double r)
{
	double z = r * r;
	/* Horner from the top; the two largest terms last, so the error is that
	 * of r - r·z·q with q near 1/6. */
	double q = -1.0 / 355687428096000.0;
	q = q * z + 1.0 / 1307674368000.0;
	q = q * z - 1.0 / 6227020800.0;
	q = q * z + 1.0 / 39916800.0;
	q = q * z - 1.0 / 362880.0;
	q = q * z + 1.0 / 5040.0;
	q = q * z - 1.0 / 120.0;
	q = q * z + 1.0 / 6.0;
	return r - r * z * q;
}

static double cos_k(double r)
{
	double z = r * r;
	double q = 1.0 / 6402373705728000.0;          /*  1/18! */
	q = q * z - 1.0 / 20922789888000.0;           /* -1/16! */
	q = q * z + 1.0 / 87178291200.0;              /*  1/14! */
	q = q * z - 1.0 / 479001600.0;                /* -1/12! */
	q = q * z + 1.0 / 3628800.0;                  /*  1/10! */
	q = q * z - 1.0 / 40320.0;                    /* -1/8!  */
	q = q * z + 1.0 / 720.0;                      /*  1/6!  */
	q = q * z - 1.0 / 24.0;                       /* -1/4!  */
	/* 1 - z/2 + z²·q: 1 - z/2 is formed as (1 - h) + (h - z/2) with h = z/2
	 * rounded, fdlibm's way of keeping the cancellation exact near r = π/4. */
	double h = 0.5 * z;
	double w = 1.0 - h;
	return w + (((1.0 - w) - h) + z * z * -q);
}

/* x = k·π/2 + r with |r| <= π/4 (a little more at the rounding edge). */
static int reduce(double x, double *r)
{
	double t = x * 0.63661977236758134308; /* 2/π */
	int k = (int)(t < 0.0 ? t - 0.5 : t + 0.5);
	*r = (x - k * PIO2_HI) - k * PIO2_LO;
	return k;
}

double bk_dsin(double x)
{
	double r;
	switch (reduce(x, &r) & 3) {
	case 0: return sin_k(r);
	case 1: return cos_k(r);
	case 2: return -sin_k(r);
	default: return -cos_k(r);
	}
}

double bk_dcos(double x)
{
	double r;
	switch (reduce(x, &r) & 3) {
	case 0: return cos_k(r);
	case 1: return -sin_k(r);
	case 2: return -cos_k(r);
	default: return sin_k(r);
	}
}

/* asin on [0, 0.5]: its series to s^13 (the first omitted term,
 * (143/10240) s^15, is below 5e-7 at s = 0.5), then Newton on sin y = s,
 * which squares the error (f''/2f' is below 0.3 there): two steps reach
 * rounding. The count is fixed, not a test on convergence whose outcome could
 * differ by a rounding. */
static double asin_small(double s)
{
	double z = s * s;
	double q = 231.0 / 13312.0;                   /* c6 = (12)!/(4^6 (6!)^2 13) */
	q = q * z + 63.0 / 2816.0;                    /* c5 */
	q = q * z + 35.0 / 1152.0;                    /* c4 */
	q = q * z + 5.0 / 112.0;                      /* c3 */
	q = q * z + 3.0 / 40.0;                       /* c2 */
	q = q * z + 1.0 / 6.0;                        /* c1 */
	double y = s + s * z * q;
	for (int i = 0; i < 2; i++)
		y -= (sin_k(y) - s) / cos_k(y);
	return y;
}

double bk_dacos(double c)
{
	if (!(c >= -1.0 && c <= 1.0))
		return (c - c) / (c - c); /* NaN, as acos outside [-1, 1] */
	if (c > 0.5) /* acos c = 2 asin sqrt((1 - c)/2): 1 - c is exact here */
		return 2.0 * asin_small(sqrt(0.5 * (1.0 - c)));
	if (c < -0.5) /* acos c = π - 2 asin sqrt((1 + c)/2) */
		return 2.0 * ((PIO2_D - asin_small(sqrt(0.5 * (1.0 + c)))) + PIO2_DLO);
	double a = c < 0.0 ? -asin_small(-c) : asin_small(c);
	return (PIO2_D - a) + PIO2_DLO;
}

/* ---- exp2, log2, pow, exp, log -------------------------------------------
 *
 * The IR's f64 ops (brdf/ir_eval.c, ir_adjoint.h, ir_code.c's folding) and
 * the reference terms that need them (Beckmann, Blinn-Phong), on vmath.h's
 * double-precision exp2 and log2, whose bits depend on the input alone
 * (glibc's log2, log, exp and pow have FMA variants picked from the CPU at
 * run time; see vmath.h). Precision, against long double libm
 * (tests/test_dmath.c): exp2 and log2 as vmath.h states; log within 0.51
 * ulp (log2's double-double times ln 2 as a pair); exp within 0.63 ulp
 * (x log2 e as a pair, then exp2's); pow within 0.65 ulp for normal results
 * (y log2 x as a pair from log2's: its error of 2^-62 times |y log2 x| <=
 * 1075 stays under 2^-52); subnormal results of exp and pow as exp2's.
 */

double bk_dexp2(double x)
{
	return bk_v_exp2(x);
}

double bk_dlog2(double x)
{
	return bk_v_log2(x);
}

/* The pair hi + lo times c_hi + c_lo as ph + tail, ph the exact product's
 * high part: log2_times rounds it once, log1p adds to it first. */
static double times_pair(double hi, double lo, double c_hi, double c_lo, double *tail)
{
	double ph, pl;
	bk_v_two_prod(hi, c_hi, &ph, &pl);
	*tail = pl + (hi * c_lo + lo * c_hi);
	return ph;
}

/* log2(x) times c = c_hi + c_lo, both as pairs, rounded once: log and log10 */
static double log2_times(double x, double c_hi, double c_lo)
{
	double lo, hi = bk_v_log2_dd(x, &lo);
	if (!isfinite(hi) || hi == 0.0)
		return hi * c_hi; /* +-inf, NaN and log(1) = +0 as they are */
	double tail, ph = times_pair(hi, lo, c_hi, c_lo, &tail);
	return ph + tail;
}

double bk_dlog(double x)
{
	return log2_times(x, BK_V_LN2_HI, BK_V_LN2_LO);
}

double bk_dexp(double x)
{
	/* |x| > 800: exp over- or underflows whatever the rounding, and the
	 * product's split must not overflow */
	if (!(fabs(x) <= 800.0))
		return bk_v_exp2(x * BK_V_INVLN2_HI); /* +-inf, NaN, and far past the ends */
	double wh, wl;
	bk_v_two_prod(x, BK_V_INVLN2_HI, &wh, &wl);
	return bk_v_exp2_dd(wh, wl + x * BK_V_INVLN2_LO);
}

/* 1 if y is an odd integer (every double of magnitude >= 2^53 is even) */
static int odd_integer(double y)
{
	return fabs(y) < 0x1p53 && y == nearbyint(y) && nearbyint(0.5 * y) != 0.5 * y;
}

/* C11's pow (Annex F.10.4.4) in its specials; otherwise 2^(y log2 |x|) with
 * log2 |x| as a pair, y times it as a pair (exact product plus y times the
 * low part), and the sign of an odd integer power of a negative x. */
double bk_dpow(double x, double y)
{
	if (y == 0.0 || x == 1.0)
		return 1.0; /* even for a NaN in the other */
	if (isnan(x) || isnan(y))
		return x + y;
	int neg = signbit(x) != 0;
	double ax = fabs(x);
	if (neg && ax != 0.0 && !isinf(ax) && isfinite(y) && y != nearbyint(y))
		return (x - x) / (x - x); /* a negative base, a non-integer power: NaN */
	double sign = neg && odd_integer(y) ? -1.0 : 1.0;
	if (ax == 1.0)
		return sign; /* (-1)^(+-inf) = 1, (-1)^n = +-1 */
	if (ax == 0.0 || isinf(ax) || isinf(y)) {
		/* 0, inf or an infinite power: 0 or inf, the sign as above */
		int big = (ax > 1.0) == (y > 0.0);
		return sign * (big ? HUGE_VAL : 0.0);
	}
	double ll, lh = bk_v_log2_dd(ax, &ll);
	double w = y * lh;
	if (!(fabs(w) <= 2048.0))
		return sign * bk_v_exp2(w); /* over- or underflows; the split could overflow */
	double wh, wl;
	bk_v_two_prod(y, lh, &wh, &wl);
	return sign * bk_v_exp2_dd(wh, wl + y * ll);
}

/* log10: log2's pair times log10(2) as a pair (log10(2) = HI + LO to
 * 2^-110), for the plots' log axes and the reports' digits, where glibc's
 * log10 has an FMA variant too. Exact at the doubles nearest 10^n that
 * glibc's is exact at (tests/test_dmath.c), as a tick's floor(log10) needs. */
#define LOG10_2_HI 0x1.34413509f79ffp-2
#define LOG10_2_LO -0x1.9dc1da994fd21p-59

double bk_dlog10(double x)
{
	return log2_times(x, LOG10_2_HI, LOG10_2_LO);
}

/* log1p(u) = ln(1 + u): the robust losses' rho (Cauchy's c² log1p(s/c²), in
 * solver.cc and fit_stats.c), where glibc's log1p has an FMA variant too.
 * w = 1 + u is rounded; d = u - (w - 1) is what the rounding lost, exactly
 * (w - 1 is exact for w < 2^53, and u and w - 1 are within a factor of 2 of
 * each other, Sterbenz), so ln(1 + u) = ln(w) + ln(1 + d/w) = ln(w) + q - q²/2
 * with q = d/w, to within |q|³/3 < 2^-160; ln(w) is log2's pair times ln 2's
 * (q² matters: it is 0.06 ulp of the result at u = 1.5 2^-53). Where w
 * rounds to 1 (|u| < 2^-53), log1p(u) rounds to u. C11's specials: ±0 as
 * they are, -1 gives -inf, below -1 NaN. */
double bk_dlog1p(double u)
{
	if (isnan(u) || u == 0.0 || u == HUGE_VAL)
		return u + u;
	if (u <= -1.0)
		return u == -1.0 ? -HUGE_VAL : NAN;
	double w = 1.0 + u;
	if (w == 1.0)
		return u;
	double d = w < 0x1p53 ? u - (w - 1.0) : 0.0;
	double lo, hi = bk_v_log2_dd(w, &lo);
	double tail, ph = times_pair(hi, lo, BK_V_LN2_HI, BK_V_LN2_LO, &tail);
	/* d/w is up to a fifth of the result where |u| is just past 2^-53, so it
	 * is added as a pair: q and its remainder (d - q w exactly, Dekker's
	 * product), q to ln(w) by TwoSum */
	double q = d / w, qh, ql;
	bk_v_two_prod(q, w, &qh, &ql);
	double qe = ((d - qh) - ql) / w;
	double sum = ph + q, b = sum - ph, e = (ph - (sum - b)) + (q - b);
	return sum + (e + (tail + (qe - 0.5 * q * q)));
}

/* ---- erfc ------------------------------------------------------------------ */

/* e^{-x²} for x >= 0, with x² as an exact pair: e^{-hi} (1 - lo), since
 * e^{-lo} = 1 - lo to 2^-106 (|lo| <= ulp(hi)/2); rounding x² first would cost
 * x² ulps (625 at x = 25) */
double bk_dmath_exp_minus_sq(double x)
{
	double hi, lo;
	bk_v_two_prod(x, x, &hi, &lo);
	return bk_dexp(-hi) * (1.0 - lo);
}

/* The tail T(x) of erfc's continued fraction (Abramowitz & Stegun 7.1.14;
 * Cuyt et al. 2008, 13.2.20a): erfc(x) = e^{-x²}/√π · 1/(x + T),
 * T = (1/2)/(x + (2/2)/(x + (3/2)/(x + ...))), x >= 1/2. Evaluated from the
 * bottom at depth 12 + 200/x²: every term positive, no cancellation, and
 * within 1.5e-16 of the limit from depth 178/x² (measured at x = 0.5 .. 5
 * against erfcl; 712 terms at x = 1/2, 16 at 5). */
double bk_dmath_erfc_tail(double x)
{
	int depth = 12 + (int)(200.0 / (x * x));
	double t = 0.0;
	for (int n = depth; n >= 1; n--)
		t = (0.5 * n) / (x + t);
	return t;
}

/* 1/√π as the nearest double */
#define INV_SQRT_PI 0x1.20dd750429b6dp-1

/* erfc(x): the complementary error function, for Beckmann's Smith Λ
 * (beckmann.c), where glibc's erfc has an FMA variant. x < 1/2: 1 - erf(x),
 * erf by its Taylor series (Abramowitz & Stegun 7.1.5; alternating, terms
 * below x^{2n+1}/n! ≤ 2^-n/n!, 18 of them), erfc >= 0.48 there so the
 * subtraction loses under a bit; x >= 1/2: the continued fraction above;
 * x < 0: 2 - erfc(-x). Within 4.5 ulp for normal results (tests/test_dmath.c;
 * glibc's is within about 1): the continued fraction's bottom-up evaluation
 * carries ~2.7 ulp of its own, then e^{-x²}, 1/√π and the division add
 * theirs. Enough for Λ, which takes its tail directly. Past x = 26.5 the
 * result is subnormal, then 0. */
double bk_derfc(double x)
{
	if (isnan(x))
		return x + x;
	if (x < 0.0)
		return 2.0 - bk_derfc(-x);
	if (x < 0.5) {
		double z = x * x, term = x, sum = x; /* term: (-1)^n x^{2n+1}/n! */
		for (int n = 1; n <= 18; n++) {
			term *= -z / n;
			sum += term / (2 * n + 1);
		}
		return 1.0 - 2.0 * INV_SQRT_PI * sum;
	}
	if (x >= 28.0)
		return 0.0; /* below half the least subnormal (erfc(27.3) < 2^-1075) */
	return bk_dmath_exp_minus_sq(x) * INV_SQRT_PI / (x + bk_dmath_erfc_tail(x));
}
