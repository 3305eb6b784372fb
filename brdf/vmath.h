/*
 * vmath.h — exp2 and log2 of floats that a compiler vectorises (prefix bk_v_;
 * not installed). For the IR's f32 and f16 kernels (brdf/ir_eval.c), where
 * libm's exp2f and log2f, scalar calls, were about 45 % of the time.
 *
 * Contract:
 *  - bk_v_exp2f(x), bk_v_log2f(x): within 1 ulp of the correctly rounded
 *    result for every float (tests/test_vmath.c measures it against double
 *    libm rounded once; the computation is in double with a relative error
 *    below 2^-39, so all but rare near-ties round correctly); exact at exp2
 *    of integers and log2 of powers of two (log2(1) = +0); IEEE specials as
 *    libm's: exp2(+inf) = +inf, exp2(-inf) = +0, exp2(NaN) = NaN, +inf from
 *    x >= 128, gradual underflow below -126 (subnormals, rounded once) and +0
 *    from -150 down (2^-150 is a tie, to even); log2(+-0) = -inf,
 *    log2(x < 0) = NaN, log2(+inf) = +inf, log2 of subnormals to the same
 *    bound. Measured over all 2^32 floats: at most 0.5000 ulp from the exact
 *    value; the rounded reference differs on 1,442 (exp2) and 4 (log2) floats,
 *    near-ties, by one ulp.
 *  - Their bits depend on the input alone, not on the CPU or the vector width:
 *    + - * / and conversions in double and float, integer and bit operations,
 *    selects; no libm call, no table, no FMA (C11 compiles with
 *    -ffp-contract=off; no target here enables FMA). So a loop over them
 *    vectorises (gcc -O2) in the x86-64 baseline (SSE2) copy and in an AVX2
 *    copy alike, with the same bits.
 *  - They are static inline so that the kernel's loop of constant trip count
 *    (BK_IR_BLOCK) inlines them and vectorises whole; bk_v_exp2f_n and
 *    bk_v_log2f_n run them over arrays (any n), in the AVX2 copy where asked
 *    and the CPU has it.
 *
 * The polynomial coefficients are fitted by brdf/vmath_fit.py (Remez,
 * minimising the relative error; its output is pasted below as is).
 */
#ifndef BRDF_VMATH_H
#define BRDF_VMATH_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

/* exp2: 2^r = 1 + r*q(r), |r| <= 1/2; relative error 8.14e-13 (2^-40.2), 8.14e-13 with the doubles */
#define BK_V_E0 0x1.62e42fef89d1fp-1
#define BK_V_E1 0x1.ebfbdff8ede84p-3
#define BK_V_E2 0x1.c6b08dced3448p-5
#define BK_V_E3 0x1.3b2ab5ed6fc30p-7
#define BK_V_E4 0x1.5d874d070f75ap-10
#define BK_V_E5 0x1.430aa882de145p-13
#define BK_V_E6 0x1.00d8533840456p-16
#define BK_V_E7 0x1.61c4f0a5f0effp-20
/* log2: log2(m) = s*Q(s^2), s^2 <= 0.02944; relative error 2.66e-14 (2^-45.1), 2.66e-14 with the doubles */
#define BK_V_L0 0x1.71547652b8251p+1
#define BK_V_L1 0x1.ec709dc53c63ep-1
#define BK_V_L2 0x1.2776c29342b43p-1
#define BK_V_L3 0x1.a61a2ec62bec2p-2
#define BK_V_L4 0x1.479556d4f9c4ep-2
#define BK_V_L5 0x1.21b0e0fa41627p-2

/*
 * exp2(x) = 2^k * 2^r, k the integer nearest x, r = x - k in [-1/2, 1/2].
 * In double: x is clamped to [-160, 160] (2^160 overflows a float and 2^-160
 * is below half its smallest subnormal, so the clamp changes no result; it
 * keeps 2^k a normal double); adding 1.5*2^52 rounds x to k in the low bits
 * (ties to even; the sum and the difference are exact), and those bits,
 * shifted into the exponent field, are 2^k. The product p*2^k is exact, so
 * the one rounding to float — to a subnormal or to +inf where it belongs —
 * is the only one after the polynomial's. A NaN fails both comparisons and
 * goes through every operation as a NaN.
 */
static inline float bk_v_exp2f(float x)
{
	const double shift = 0x1.8p52;
	uint32_t u;
	memcpy(&u, &x, sizeof u);
	/* the clamp on the bits: integer compares and selects vectorise where
	 * float ones (which may trap, -ftrapping-math) beside double arithmetic
	 * kept gcc 12 from if-converting the loop; a NaN (above 0x7f800000) is
	 * left alone */
	uint32_t a = u & 0x7fffffffu;
	u = (a > 0x43200000u) & (a <= 0x7f800000u) ? (u & 0x80000000u) | 0x43200000u : u; /* +-160 */
	float xc;
	memcpy(&xc, &u, sizeof xc);
	double c = (double)xc;
	double t = c + shift;
	double r = c - (t - shift);
	uint64_t b;
	memcpy(&b, &t, sizeof b);
	b = (b + 1023u) << 52; /* the low bits of t are k + 2^51: (k + 1023) mod 2^12 survives the shift */
	double s;
	memcpy(&s, &b, sizeof s);
	double q = BK_V_E7;
	q = q * r + BK_V_E6;
	q = q * r + BK_V_E5;
	q = q * r + BK_V_E4;
	q = q * r + BK_V_E3;
	q = q * r + BK_V_E2;
	q = q * r + BK_V_E1;
	q = q * r + BK_V_E0;
	return (float)((1.0 + r * q) * s);
}

/*
 * log2(x) = e + log2(m), m in [sqrt(1/2), sqrt(2)) (0x3f3504f3 is the float
 * below sqrt(1/2)), from x's bits; a subnormal is first scaled by 2^23 (exact)
 * and 23 taken off e. log2(m) = (2/ln 2) atanh(s) = s*Q(s^2) with
 * s = (m - 1)/(m + 1), |s| <= 0.1716, in double: m - 1 and m + 1 are exact,
 * so near x = 1 the result keeps its relative precision, and e + s*Q, of
 * |e| <= 149, rounds to float once. log2(1) = 0 + 0*Q = +0. Zero, negatives,
 * +inf and NaN are selected at the end (their bits run through the same
 * arithmetic, harmlessly).
 */
static inline float bk_v_log2f(float x)
{
	uint32_t u, us;
	float xs = x * 0x1p23f;
	memcpy(&u, &x, sizeof u);
	memcpy(&us, &xs, sizeof us);
	/* all ones for +0 and the positive subnormals; a mask, not a select: with
	 * a select gcc 12 moved the multiply into a branch (it may trap, so the
	 * loop was no longer if-converted and stayed scalar) */
	uint32_t sub = -(uint32_t)(u < 0x00800000u);
	uint32_t v = (us & sub) | (u & ~sub);
	/* e = floor((v - bits(m's lower end)) / 2^23) as a signed count, without
	 * shifting a negative int (implementation-defined in C11) */
	uint32_t t = v - 0x3f3504f3u;
	int32_t e = (int32_t)((t + 0x80000000u) >> 23) - 256 - (int32_t)(sub & 23u);
	uint32_t mb = (t & 0x007fffffu) + 0x3f3504f3u;
	float m;
	memcpy(&m, &mb, sizeof m);
	double md = (double)m;
	double s = (md - 1.0) / (md + 1.0);
	double z = s * s;
	double q = BK_V_L5;
	q = q * z + BK_V_L4;
	q = q * z + BK_V_L3;
	q = q * z + BK_V_L2;
	q = q * z + BK_V_L1;
	q = q * z + BK_V_L0;
	float y = (float)((double)e + s * q);
	/* the specials, by masks on the bits (as sub above: with selects gcc
	 * moved the conversion to float into a branch): +inf stays, NaNs and
	 * negatives give the quiet NaN, +-0 gives -inf */
	uint32_t yb, zero = -(uint32_t)((u << 1) == 0), inf = -(uint32_t)(u == 0x7f800000u);
	uint32_t nan = -(uint32_t)(u > 0x7f800000u) & ~zero;
	memcpy(&yb, &y, sizeof yb);
	yb = (yb & ~(zero | inf | nan)) | (0xff800000u & zero) | (u & inf) | (0x7fc00000u & nan);
	memcpy(&y, &yb, sizeof y);
	return y;
}

/* y[i] = bk_v_exp2f(x[i]), y[i] = bk_v_log2f(x[i]) for i < n; y may be x.
 * avx2: run the AVX2 copy when the CPU has it (the same bits either way;
 * tests compare them). */
void bk_v_exp2f_n(float *y, const float *x, size_t n, int avx2);
void bk_v_log2f_n(float *y, const float *x, size_t n, int avx2);
/* 1 when avx2 = 1 would run the AVX2 copy on this CPU */
int bk_v_have_avx2(void);

#endif
