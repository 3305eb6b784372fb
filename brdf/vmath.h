/*
 * vmath.h — exp2 and log2 of floats and of doubles that a compiler
 * vectorises (prefix bk_v_; not installed). For the IR's kernels
 * (brdf/ir_eval.c): in f32 and f16 libm's exp2f and log2f, scalar calls,
 * were about 45 % of the time; in f64 libm's log2 (and log, exp, pow) gave
 * other bits on a CPU without FMA (the double-precision part, below).
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

/* ---- double precision ----------------------------------------------------
 *
 * bk_v_exp2(x), bk_v_log2(x): the IR's f64 exp2 and log2 (the fits' and the
 * search's), and through bk_v_log2_dd and bk_v_exp2_dd the pow, exp and log
 * of brdf/dmath.c. Why not libm's: glibc picks an FMA or a non-FMA variant of
 * log2, log, exp and pow at run time from the CPU (ifunc), and they differ in
 * the last bit (GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA changes log2 of
 * 1e-3 + 1.37e-7 i on some of 2e7 points), so a search's screening errors
 * moved with the CPU (tests/cli_search.sh). These use + - * / on doubles,
 * integer and bit operations only, as the float ones above, so their bits
 * depend on the input alone, and a loop of them vectorises.
 *
 * Precision (tests/test_dmath.c, against glibc's long double exp2l and
 * log2l, 11 more bits): exp2 within 0.62 ulp for normal results (2^r's
 * low-order terms are summed apart from 1 + r ln 2, which is formed
 * exactly; what is left is r^2 T's rounding, at r near -1/2) and 0.75 for
 * subnormal ones (rounded to 53 bits before the scaling rounds again); log2
 * within 0.51 ulp (its double-double value, before the last rounding, has a
 * relative error below 2^-62, which is what pow needs: y log2 x carries it
 * times |y log2 x| into the exponent). Exact at exp2 of integers, log2 of powers of two and
 * log2(1) = +0. Specials as C's: exp2(+inf) = +inf, exp2(-inf) = +0, +inf
 * from x >= 1024, gradual underflow below -1022 (rounded once), +0 below
 * -1075; log2(+-0) = -inf, log2(x < 0) = NaN, log2(+inf) = +inf, NaNs stay
 * NaN, subnormal inputs to the same bound.
 *
 * The series are Taylor's, not minimax: at these degrees their truncation
 * (below 1e-19 relative) is far under the rounding, and their coefficients
 * are checked by anyone with ln 2: BK_V_Dn = ln(2)^(n+1)/(n+1)! rounded to
 * double (mpmath, 50 digits), and log's 2/(2k+1) are written as divisions
 * the compiler rounds once.
 */
/* inlined even where gcc finds them too long to: a call inside the IR's
 * loops keeps them scalar (a call of bk_v_exp2_dd was 20 % of a screening
 * fit; inlined, the loop runs 4 at a time in the AVX2 copy) */
#define BK_V_INLINE static inline __attribute__((always_inline))

#define BK_V_D0 0x1.62e42fefa39efp-1  /* ln 2 */
#define BK_V_D1 0x1.ebfbdff82c58fp-3
#define BK_V_D2 0x1.c6b08d704a0c0p-5
#define BK_V_D3 0x1.3b2ab6fba4e77p-7
#define BK_V_D4 0x1.5d87fe78a6731p-10
#define BK_V_D5 0x1.430912f86c787p-13
#define BK_V_D6 0x1.ffcbfc588b0c7p-17
#define BK_V_D7 0x1.62c0223a5c824p-20
#define BK_V_D8 0x1.b5253d395e7c4p-24
#define BK_V_D9 0x1.e4cf5158b8ecap-28
#define BK_V_D10 0x1.e8cac7351bb25p-32
#define BK_V_D11 0x1.c3bd650fc2986p-36
#define BK_V_D12 0x1.816193166d0f9p-40
#define BK_V_D13 0x1.314964d5878a9p-44
#define BK_V_LN2_HI 0x1.62e42fefa39efp-1 /* ln 2 = HI + LO to ~2^-107 */
#define BK_V_LN2_LO 0x1.abc9e3b39803fp-56
#define BK_V_INVLN2_HI 0x1.71547652b82fep+0 /* 1/ln 2 = log2(e) = HI + LO */
#define BK_V_INVLN2_LO 0x1.777d0ffda0d24p-56
#define BK_V_TWO3_HI 0x1.5555555555555p-1 /* 2/3 = HI + LO to 2^-108 */
#define BK_V_TWO3_LO 0x1.5555555555555p-55

BK_V_INLINE double bk_v_dbits(uint64_t b)
{
	double d;
	memcpy(&d, &b, sizeof d);
	return d;
}

BK_V_INLINE uint64_t bk_v_dword(double d)
{
	uint64_t b;
	memcpy(&b, &d, sizeof b);
	return b;
}

/* a*b = *hi + *lo exactly (Dekker's product on Veltkamp's halves; no FMA:
 * none is allowed here). |a|, |b| < 2^995, so that the splits cannot
 * overflow. */
BK_V_INLINE void bk_v_two_prod(double a, double b, double *hi, double *lo)
{
	const double split = 134217729.0; /* 2^27 + 1 */
	double ca = split * a, cb = split * b;
	double ah = ca - (ca - a), al = a - ah;
	double bh = cb - (cb - b), bl = b - bh;
	double p = a * b;
	*hi = p;
	*lo = ((ah * bh - p) + ah * bl + al * bh) + al * bl;
}

/*
 * 2^(hi + lo), |lo| <= 2^-40 |hi| or so (the low half of a double-double):
 * k = the integer nearest hi (1.5*2^52 added and taken off: exact for
 * |hi| <= 2^51, and hi is clamped to [-1100, 1100] first, which changes no
 * result: 2^1024 overflows and 2^-1100 rounds to 0), r = hi - k exact in
 * [-1/2, 1/2]. 2^r = 1 + r ln2 + r^2 T(r): r ln2 as an exact pair (ln 2's
 * low part added), 1 + its high part by Fast2Sum, and every low-order term
 * (the pair's low part, the sum's error, r^2 T, and lo's share 2^r lo ln2)
 * added to that error before the one rounding. Then 2^k in two factors 2^k1 2^k2 (both
 * normal: |k1|, |k2| <= 550), so that a subnormal result is rounded once and
 * an overflow gives +inf. NaN: every comparison fails, it goes through.
 */
BK_V_INLINE double bk_v_exp2_dd(double hi, double lo)
{
	const double shift = 0x1.8p52;
	/* the clamp on the bits, as bk_v_exp2f's (a NaN, above 0x7ff0..., stays) */
	uint64_t u = bk_v_dword(hi), a = u & 0x7fffffffffffffffu;
	uint64_t big = -(uint64_t)((a > 0x4091300000000000u) & (a <= 0x7ff0000000000000u)); /* |hi| > 1100 */
	u = (u & ~big) | (((u & 0x8000000000000000u) | 0x4091300000000000u) & big);
	lo = bk_v_dbits(bk_v_dword(lo) & ~big);
	double c = bk_v_dbits(u);
	double t = c + shift;
	double kd = t - shift;
	double r = c - kd;
	/* k1 = floor(k/2): k/2 is an integer or a half, and rounding k/2 - 1/4
	 * to the nearest integer floors both */
	double k1 = ((0.5 * kd - 0.25) + shift) - shift, k2 = kd - k1;
	uint64_t b1 = (bk_v_dword(k1 + shift) + 1023u) << 52, b2 = (bk_v_dword(k2 + shift) + 1023u) << 52;
	double ph, pl;
	bk_v_two_prod(r, BK_V_LN2_HI, &ph, &pl);
	pl += r * BK_V_LN2_LO;
	double q = BK_V_D13;
	q = q * r + BK_V_D12;
	q = q * r + BK_V_D11;
	q = q * r + BK_V_D10;
	q = q * r + BK_V_D9;
	q = q * r + BK_V_D8;
	q = q * r + BK_V_D7;
	q = q * r + BK_V_D6;
	q = q * r + BK_V_D5;
	q = q * r + BK_V_D4;
	q = q * r + BK_V_D3;
	q = q * r + BK_V_D2;
	q = q * r + BK_V_D1;
	double s = 1.0 + ph;
	double e = (1.0 - s) + ph; /* Fast2Sum: |1| >= |ph| (<= 0.35) */
	double t2 = r * r * q;
	/* 2^(r + lo) = 2^r + 2^r lo ln2 (lo^2 is below 2^-80): 2^r to 2^-50 is s + t2 */
	double low = e + (pl + (t2 + lo * BK_V_LN2_HI * (s + t2)));
	double p = s + low;
	return p * bk_v_dbits(b1) * bk_v_dbits(b2);
}

BK_V_INLINE double bk_v_exp2(double x)
{
	return bk_v_exp2_dd(x, 0.0);
}

/*
 * log2(x) as a double-double *hi + *lo (|lo| <= ulp(hi)/2). x = m 2^e,
 * m in [sqrt(1/2), sqrt(2)) (0x3fe6a09e667f3bcc: the double below sqrt(1/2)),
 * from x's bits, a subnormal first scaled by 2^52 (exact) and 52 taken off e.
 * f = m - 1 is exact (Sterbenz), and ln m = 2 atanh(s), s = f/(2 + f):
 * 2 + f as an exact pair, s as a pair (its remainder from Dekker's product,
 * f - s_hi (2 + f)_hi exact again by Sterbenz), ln m = 2s + s z P(z),
 * z = s^2 <= 0.0295, P's twelve terms 2/3 .. 2/25 (truncation below
 * 2^-64 of ln m). The tail s z P = s^3 P is ~1 % of 2s; formed in plain
 * doubles its roundings cost 2^-57 of the result, so s^3, P and their
 * product are pairs too (below 2^-62). Times 1/ln 2 as a pair, plus e by
 * TwoSum. The specials
 * are selected at the end by masks on the bits (as bk_v_log2f: selects kept
 * gcc from vectorising the loop).
 */
BK_V_INLINE double bk_v_log2_dd(double x, double *lo_out)
{
	uint64_t u = bk_v_dword(x), us = bk_v_dword(x * 0x1p52);
	uint64_t sub = -(uint64_t)(u < 0x0010000000000000u); /* +0 and the positive subnormals */
	uint64_t v = (us & sub) | (u & ~sub);
	uint64_t t = v - 0x3fe6a09e667f3bccu;
	/* e = floor(t / 2^52) as a signed count, as a double: (t + 2^63) >> 52 is
	 * e + 2048 in [0, 4096), put into 1.5*2^52's low bits and taken off */
	uint64_t eb = 0x4338000000000000u + ((t + 0x8000000000000000u) >> 52) - (sub & 52u);
	double ed = bk_v_dbits(eb) - (0x1.8p52 + 2048.0);
	double m = bk_v_dbits((t & 0x000fffffffffffffu) + 0x3fe6a09e667f3bccu);
	double f = m - 1.0;
	double dh = 2.0 + f, dl = (2.0 - dh) + f; /* Fast2Sum: |2| >= |f| */
	double sh = f / dh;
	double ph, pl;
	bk_v_two_prod(sh, dh, &ph, &pl);
	double sl = (((f - ph) - pl) - sh * dl) / dh;
	/* s^3 as an exact pair, P(z) = 2/3 + z P2(z) as a pair (2/3 itself is
	 * two doubles) and T = s^3 P as a pair: T is ~1 % of ln m, and each
	 * rounding left in it (they were four) cost 2^-59 of the result */
	double zh, zl, ch, cl;
	bk_v_two_prod(sh, sh, &zh, &zl);
	bk_v_two_prod(sh, zh, &ch, &cl);
	cl += sh * zl;
	double z = zh;
	double P2 = 2.0 / 25;
	P2 = P2 * z + 2.0 / 23;
	P2 = P2 * z + 2.0 / 21;
	P2 = P2 * z + 2.0 / 19;
	P2 = P2 * z + 2.0 / 17;
	P2 = P2 * z + 2.0 / 15;
	P2 = P2 * z + 2.0 / 13;
	P2 = P2 * z + 2.0 / 11;
	P2 = P2 * z + 2.0 / 9;
	P2 = P2 * z + 2.0 / 7;
	P2 = P2 * z + 2.0 / 5;
	double zp = z * P2;
	double Ph = BK_V_TWO3_HI + zp, Pl = ((BK_V_TWO3_HI - Ph) + zp) + BK_V_TWO3_LO; /* Fast2Sum: 2/3 > zp */
	double Th, Tl;
	bk_v_two_prod(ch, Ph, &Th, &Tl);
	Tl += ch * Pl + cl * Ph;
	/* ln m = 2s + T, s's low part through the slope 2/(1 - z) = 2 + 2z + ... */
	double Lh0 = 2.0 * sh;
	double Lh = Lh0 + Th, Ll = ((Lh0 - Lh) + Th) + (Tl + (2.0 * sl + 2.0 * z * sl)); /* Fast2Sum: |2s| > |T| */
	double qh, ql;
	bk_v_two_prod(Lh, BK_V_INVLN2_HI, &qh, &ql);
	ql += Lh * BK_V_INVLN2_LO + Ll * BK_V_INVLN2_HI;
	/* TwoSum(e, qh) */
	double yh = ed + qh, bb = yh - ed;
	double yl = ((ed - (yh - bb)) + (qh - bb)) + ql;
	double hi = yh + yl;
	double lo = yl - (hi - yh);
	/* the specials: +inf stays, NaNs and negatives give the quiet NaN, +-0
	 * gives -inf (lo 0 for all of them) */
	uint64_t zero = -(uint64_t)((u << 1) == 0), inf = -(uint64_t)(u == 0x7ff0000000000000u);
	uint64_t nan = -(uint64_t)(u > 0x7ff0000000000000u) & ~zero;
	uint64_t spec = zero | inf | nan;
	hi = bk_v_dbits((bk_v_dword(hi) & ~spec) | (0xfff0000000000000u & zero) | (u & inf) | (0x7ff8000000000000u & nan));
	*lo_out = bk_v_dbits(bk_v_dword(lo) & ~spec);
	return hi;
}

BK_V_INLINE double bk_v_log2(double x)
{
	double lo;
	return bk_v_log2_dd(x, &lo);
}

/* y[i] = bk_v_exp2f(x[i]), y[i] = bk_v_log2f(x[i]) for i < n; y may be x.
 * avx2: run the AVX2 copy when the CPU has it (the same bits either way;
 * tests compare them). */
void bk_v_exp2f_n(float *y, const float *x, size_t n, int avx2);
void bk_v_log2f_n(float *y, const float *x, size_t n, int avx2);
/* 1 when avx2 = 1 would run the AVX2 copy on this CPU */
int bk_v_have_avx2(void);

#endif
