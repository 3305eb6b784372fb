/*
 * ir_eval.c — running the instruction list over arrays of samples: one kernel,
 * instantiated for double, single and half precision (FFTW's habit: the storage
 * type T and the rounding after each operation are named separately).
 *
 * Samples are taken BLOCK at a time; each instruction runs over the whole block
 * before the next (the per-sample tree walk this replaces is what a fit with
 * 10^6 samples per iteration cannot afford). Half precision stores floats and
 * rounds every result with the rule of half.h — what a mediump GPU does; the
 * transcendental ops are computed in single precision first, as GPUs do, and
 * pow, exp and log as the exp2, log2 and multiplies a GPU runs (below).
 */
#include "half.h"
#include "ir.h"
#include "doors.h"
#include "vmath.h"

#include <math.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <tgmath.h>

#define BLOCK BK_IR_BLOCK

static float round16(float x) { return (float)bk_half_round_inline(x); }
static float round32(float x) { return x; }
static double round64(double x) { return x; }
static long double roundld(long double x) { return x; }

/*
 * Why the kernel is shaped as it is (speed, not semantics: every result is
 * still rounded by R): each op runs over a whole BLOCK — a constant trip count
 * — inside a function whose register pointers are restrict (a result register
 * never overlaps its operands, which come earlier in the list; two operands
 * may be the same register, which restrict allows as both are only read).
 * Those two facts are what gcc -O2's cheap vectoriser needs to vectorise the
 * arithmetic loops without runtime alias checks or a scalar epilogue; with a
 * variable count and plain pointers every loop stayed scalar and the IR ran
 * about 4-5x slower than the same form compiled (analysis/bench/bench_ir.c). The
 * lanes past the last sample of a partial block hold copies of that sample's
 * inputs; they are computed and never copied out.
 *
 * The inputs come from arrays far larger than the caches, a block at a time:
 * asking for the next block's lines while this one computes hides the memory
 * latency that otherwise took ~40% of the f32 time (perf on bench_ir). A hint
 * only, on addresses inside the caller's arrays; where the compiler has no
 * prefetch builtin it compiles to nothing.
 */
#if defined(__GNUC__)
#define PREFETCH(p) __builtin_prefetch(p)
#else
#define PREFETCH(p) ((void)(p))
#endif
#define LINE 8 /* doubles per 64-byte cache line */

/*
 * min and max with fmin/fmax's meaning, written as selects: a NaN operand
 * yields the other operand, and of two equal operands (-0 and +0 included) the
 * second is returned, which is what glibc's x86-64 fmin/fmax (minsd/maxsd
 * behind an unordered test) return too, so the generated C, which calls
 * fminf/fmaxf, still agrees with the IR bit for bit. As calls, fmin and fmax
 * kept every min/max/clamp/saturate loop scalar (gcc vectorises them only
 * under -ffinite-math-only): a search's forms are full of them, and a
 * candidate with three such ops ran at half the node rate of one without.
 * The select compiles to a compare, an unordered compare and a blend per
 * vector. x != x is the NaN test (isnan is a macro that may call).
 */
#define MIN(x, y) ((((x) < (y)) | ((y) != (y))) ? (x) : (y))
#define MAX(x, y) ((((x) > (y)) | ((y) != (y))) ? (x) : (y))

/*
 * pow is exp2(y * log2(x)) in every precision: what GLSL and HLSL define it
 * as (GLSL 4.60 8.2: "Results are undefined if x < 0 ... x = 0 and y <= 0";
 * its precision is inherited from exp2(y log2 x)) and what every GPU runs, no
 * GPU having x^y in hardware. So one meaning everywhere: the IR in f64, f32,
 * f16 and long double, the generated C (exp2f(y * log2f(x))) and the shaders
 * (pow, which drivers lower to the same three steps) give NaN where the
 * specifications give pow no value: a negative base (log2 of it), and 0^y
 * for y <= 0 (a negative zero included; three steps would give NaN for 0^0
 * and +inf for 0^-1, but drivers differ there: lavapipe returns 0 for any
 * 0^y, measured by tests/vk), and also inf^0 and 1^inf (0 * inf); 0^y is 0
 * for y > 0. C's pow, which gives (-2)^9 = -512 and 0^0 = 1, is no
 * evaluator's any more. A NaN is what every command refuses to score, so no
 * number brdfkit reports stands where a GPU may compute anything. Each step
 * is rounded to the precision, the product too.
 * x^k for an integer |k| <= 8 never reaches pow: the parser writes it as
 * multiplies (brdf/ir_parse.c), the same in every language.
 *
 * exp and log as a GPU runs them too in half (the op table's classes: exp =
 * mul + exp2, log = log2 + mul): in half (D = 1) each step is a mediump
 * operation, rounded to half, the constants log2(e) and ln 2 included. The
 * other precisions compute C's exp and log, as the generated C does with expf
 * and logf (f32) or exp and log (f64), but on brdf/dmath.c's bk_dexp and
 * bk_dlog (f32: theirs rounded once to float), not libm's: glibc picks an FMA
 * or a non-FMA variant of these at run time and the two differ in the last
 * bit, so the IR's results would depend on the CPU (vmath.h). Within an ulp of
 * libm's; the domains are the GPU's (NaN below 0, log(0) = -inf).
 *
 * exp2 and log2 in f32 and f16 (V = 1), the exp2 and log2 inside pow, exp
 * and log included, are vmath.h's bk_v_exp2f and bk_v_log2f: branch-free
 * C that vectorises in both copies below with the same bits, within 1 ulp of
 * the correctly rounded value (vmath.h: rounded correctly for all but 1,442
 * and 4 of the 2^32 floats; glibc's exp2f and log2f, which the generated C
 * calls, may differ from them by an ulp). libm's were scalar calls and
 * about 45 % of the f32 time on the search's candidates. In f16 every exp2
 * and log2 reads a half and its result is rounded to half: over all 63,488
 * finite halves the two give the same halves, so no f16 result moved
 * (tests/test_vmath.c). f64's exp2 and log2 (V = 1 there too) are vmath.h's
 * bk_v_exp2 and bk_v_log2, for the same reason as exp's above (glibc's log2
 * has an FMA variant: a search's screening errors moved with the CPU), and
 * they vectorise as the float ones (libm's exp2 was ~7 % of a screening fit).
 * bk_ir_force_libm(1) puts libm's back in every precision (make bench's side
 * by side).
 */
#define LOG2E 1.44269504088896340736 /* log2(e) */
#define LN2 0.693147180559945309417  /* ln(2) */

/* 1: the kernels run libm's exp2, log2, pow, exp and log (bk_ir_force_libm);
 * read relaxed, once per instruction */
static _Atomic int use_libm = 0;

void bk_ir_force_libm(int on)
{
	atomic_store_explicit(&use_libm, on != 0, memory_order_relaxed);
}

/* The expressions of the ops that call exp2 or log2, with the pair of
 * functions (X2, L2) a parameter: vmath's or libm's (through tgmath). */
#define E_EXP2(R, X2, L2) R(X2(A[k]))
#define E_LOG2(R, X2, L2) R(L2(A[k]))
#define E_POW(R, X2, L2) (BK_POW_AT_ZERO_UNDEFINED(A[k], B[k]) ? R((float)NAN) : R(X2(R(B[k] * R(L2(A[k]))))))
#define E_EXP16(R, X2, L2) R(X2(R(A[k] * R((float)LOG2E))))
#define E_LOG16(R, X2, L2) R(R(L2(A[k])) * R((float)LN2))
/* vmath's functions of the kernel's type: the float ones in f32 and f16,
 * the double ones in f64 (long double's kernel never asks: V = 0) */
#define V_EXP2(x) _Generic((x), float: bk_v_exp2f, default: bk_v_exp2)(x)
#define V_LOG2(x) _Generic((x), float: bk_v_log2f, default: bk_v_log2)(x)
/* f32's exp and log (C's, not the GPU's decomposition): dmath's in
 * double, rounded once to float (glibc's expf and logf, like its double
 * ones, pick FMA code from the CPU) */
static float exp_f(float a) { return (float)bk_dexp(a); }
static float log_f(float a) { return (float)bk_dlog(a); }
#define V_EXP(x) _Generic((x), float: exp_f, default: bk_dexp)(x)
#define V_LOG(x) _Generic((x), float: log_f, default: bk_dlog)(x)

/* one loop each way, the choice made outside it (a branch inside would keep
 * the loop scalar) */
#define VM(E, R)                                                                                       \
	do {                                                                                               \
		if (vm)                                                                                        \
			for (k = 0; k < BLOCK; k++) r[k] = E(R, V_EXP2, V_LOG2);                                  \
		else                                                                                           \
			for (k = 0; k < BLOCK; k++) r[k] = E(R, exp2, log2);                                      \
	} while (0)
/* C's exp and log (D = 0): dmath's (vm) or libm's */
#define VC(R, CALL_V, CALL_L)                                                                           \
	do {                                                                                               \
		if (vm)                                                                                        \
			for (k = 0; k < BLOCK; k++) r[k] = R(CALL_V);                                             \
		else                                                                                           \
			for (k = 0; k < BLOCK; k++) r[k] = R(CALL_L);                                             \
	} while (0)

/* KERNEL(name, T, R, D, V, FUSE): R rounds a T to the precision being
 * modelled; D: the GPU's decomposed exp and log (pow is decomposed in every
 * precision); V: vmath's exp2 and log2 (above); FUSE: a * b + c rounded once,
 * the mad (and the mad inside mix) as a driver may fuse it (below). */
#define KERNEL(NAME, T, R, D, V, FUSE, ATTR)                                                   \
	ATTR static inline void NAME##_op(const bk_instr *c, T *restrict r, const T *restrict A,  \
	                             const T *restrict B, const T *restrict C)              \
	{                                                                                    \
		size_t k;                                                                        \
		const int vm = V && !atomic_load_explicit(&use_libm, memory_order_relaxed);      \
		switch (c->op) {                                                                 \
		case BK_OP_ADD: for (k = 0; k < BLOCK; k++) r[k] = R(A[k] + B[k]); break;       \
		case BK_OP_SUB: for (k = 0; k < BLOCK; k++) r[k] = R(A[k] - B[k]); break;       \
		case BK_OP_MUL: for (k = 0; k < BLOCK; k++) r[k] = R(A[k] * B[k]); break;       \
		case BK_OP_DIV: for (k = 0; k < BLOCK; k++) r[k] = R(A[k] / B[k]); break;       \
		case BK_OP_NEG: for (k = 0; k < BLOCK; k++) r[k] = -A[k]; break;                \
		case BK_OP_MAD: if (FUSE) { for (k = 0; k < BLOCK; k++) r[k] = R((T)((double)A[k] * B[k] + C[k])); } \
		                else { for (k = 0; k < BLOCK; k++) r[k] = R(R(A[k] * B[k]) + C[k]); } break; \
		case BK_OP_POW: VM(E_POW, R); break;                                              \
		case BK_OP_SQRT: for (k = 0; k < BLOCK; k++) r[k] = R(sqrt(A[k])); break;       \
		case BK_OP_RSQRT: for (k = 0; k < BLOCK; k++) r[k] = R((T)1 / sqrt(A[k])); break; \
		case BK_OP_RCP: for (k = 0; k < BLOCK; k++) r[k] = R((T)1 / A[k]); break;       \
		case BK_OP_EXP: if (D) { VM(E_EXP16, R); } \
		                else { VC(R, V_EXP(A[k]), exp(A[k])); } break;                            \
		case BK_OP_EXP2: VM(E_EXP2, R); break;                                           \
		case BK_OP_LOG: if (D) { VM(E_LOG16, R); } \
		                else { VC(R, V_LOG(A[k]), log(A[k])); } break;                            \
		case BK_OP_LOG2: VM(E_LOG2, R); break;                                           \
		case BK_OP_MIN: for (k = 0; k < BLOCK; k++) r[k] = MIN(A[k], B[k]); break;      \
		case BK_OP_MAX: for (k = 0; k < BLOCK; k++) r[k] = MAX(A[k], B[k]); break;      \
		case BK_OP_CLAMP: for (k = 0; k < BLOCK; k++) { T t = MAX(A[k], B[k]); r[k] = MIN(t, C[k]); } break; \
		case BK_OP_SATURATE: for (k = 0; k < BLOCK; k++) { T t = MAX(A[k], (T)0); r[k] = MIN(t, (T)1); } break; \
		case BK_OP_MIX: if (FUSE) { for (k = 0; k < BLOCK; k++) r[k] = R((T)((double)R(B[k] - A[k]) * C[k] + A[k])); } \
		                else { for (k = 0; k < BLOCK; k++) r[k] = R(A[k] + R(R(B[k] - A[k]) * C[k])); } break; \
		case BK_OP_ABS: for (k = 0; k < BLOCK; k++) r[k] = fabs(A[k]); break;           \
		default: for (k = 0; k < BLOCK; k++) r[k] = (T)NAN; break;                       \
		}                                                                                \
	}                                                                                    \
	/* n samples from in; ahead more follow them (prefetched). first: the first \
	 * block of a call, when constants and parameters are loaded; they stay in  \
	 * their registers for the blocks after it. */                                \
	ATTR static void NAME(const bk_form *f, size_t n, size_t ahead, int first,           \
	                 const double *const *in, const double *par, T *reg, double *out)    \
	{                                                                                    \
		for (int i = 0; i < f->n; i++) {                                                 \
			const bk_instr *c = &f->code[i];                                             \
			T *r = reg + (size_t)i * BLOCK;                                              \
			size_t k;                                                                    \
			switch (c->op) {                                                             \
			case BK_OP_CONST: if (first) { T v = R((T)c->k); for (k = 0; k < BLOCK; k++) r[k] = v; } break; \
			case BK_OP_PARAM: if (first) { T v = R((T)par[c->slot]); for (k = 0; k < BLOCK; k++) r[k] = v; } break; \
			case BK_OP_INPUT:                                                            \
				for (k = 0; k < ahead; k += LINE) PREFETCH(in[c->slot] + n + k);         \
				if (n == BLOCK) { /* a constant count: the conversion vectorises */      \
					const double *restrict x = in[c->slot];                              \
					for (k = 0; k < BLOCK; k++) r[k] = R((T)x[k]);                      \
					break;                                                               \
				}                                                                        \
				for (k = 0; k < n; k++) r[k] = R((T)in[c->slot][k]);                     \
				for (; k < BLOCK; k++) r[k] = r[n - 1];                                  \
				break;                                                                   \
			default:                                                                     \
				NAME##_op(c, r, reg + (size_t)(c->a < 0 ? 0 : c->a) * BLOCK,             \
				          reg + (size_t)(c->b < 0 ? 0 : c->b) * BLOCK,                   \
				          reg + (size_t)(c->c < 0 ? 0 : c->c) * BLOCK);                  \
			}                                                                            \
		}                                                                                \
		const T *res = reg + (size_t)f->out * BLOCK;                                     \
		if (out && n == BLOCK) /* as the inputs: a constant count vectorises */          \
			for (size_t k = 0; k < BLOCK; k++)                                           \
				out[k] = (double)res[k];                                                 \
		else                                                                             \
			for (size_t k = 0; out && k < n; k++)                                        \
				out[k] = (double)res[k];                                                 \
	}

/*
 * Each kernel twice: for the x86-64 baseline (SSE2: 2 doubles or 4 floats a
 * vector) and for AVX2 (4 or 8), picked at run time (bk_ir_avx2 below). No
 * global -march: the tool runs on any x86-64. The AVX2 copy gives the same
 * bits: it runs the same C, and the arithmetic that vectorises (+ - * /
 * sqrt, compares and selects) is IEEE element-wise, exact whatever the vector
 * width; libm's functions stay scalar calls to the same libm; -std=c11 keeps
 * -ffp-contract=off, and target("avx2") does not enable FMA, so no a*b + c is
 * ever fused (tests/test_simd.c: both paths against a scalar reference).
 */
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
#define BK_IR_HAVE_AVX2 1
#define AVX2 __attribute__((target("avx2")))
#else
#define BK_IR_HAVE_AVX2 0
#define AVX2
#endif

KERNEL(run64_gen, double, round64, 0, 1, 0, )
KERNEL(run32_gen, float, round32, 0, 1, 0, )
KERNEL(run16_gen, float, round16, 1, 1, 0, )
KERNEL(run16f_gen, float, round16, 1, 1, 1, )
KERNEL(runld, long double, roundld, 0, 0, 0, )
#if BK_IR_HAVE_AVX2
KERNEL(run64_avx2, double, round64, 0, 1, 0, AVX2)
KERNEL(run32_avx2, float, round32, 0, 1, 0, AVX2)
KERNEL(run16_avx2, float, round16, 1, 1, 0, AVX2)
KERNEL(run16f_avx2, float, round16, 1, 1, 1, AVX2)
#endif

/* -1 not asked yet, 0 baseline, 1 AVX2; read and written relaxed: every
 * thread that asks stores the same answer. bk_ir_force_generic() pins 0. */
static _Atomic int isa = -1;

int bk_ir_avx2(void)
{
	int v = atomic_load_explicit(&isa, memory_order_relaxed);
	if (v < 0) {
#if BK_IR_HAVE_AVX2
		__builtin_cpu_init();
		v = __builtin_cpu_supports("avx2") != 0;
#else
		v = 0;
#endif
		atomic_store_explicit(&isa, v, memory_order_relaxed);
	}
	return v;
}

#if BK_IR_HAVE_AVX2
/* asked once before main, on one thread: libgcc's CPU model is then filled
 * before any thread of the program can ask */
__attribute__((constructor)) static void isa_at_load(void)
{
	(void)bk_ir_avx2();
}
#endif

void bk_ir_force_generic(int on)
{
	atomic_store_explicit(&isa, on ? 0 : -1, memory_order_relaxed);
}

#if BK_IR_HAVE_AVX2
#define DISPATCH(NAME, ...) (bk_ir_avx2() ? NAME##_avx2(__VA_ARGS__) : NAME##_gen(__VA_ARGS__))
#else
#define DISPATCH(NAME, ...) NAME##_gen(__VA_ARGS__)
#endif

static void run64(const bk_form *f, size_t n, size_t ahead, int first, const double *const *in, const double *par,
                  double *reg, double *out)
{
	DISPATCH(run64, f, n, ahead, first, in, par, reg, out);
}

static void run32(const bk_form *f, size_t n, size_t ahead, int first, const double *const *in, const double *par,
                  float *reg, double *out)
{
	DISPATCH(run32, f, n, ahead, first, in, par, reg, out);
}

static void run16(const bk_form *f, size_t n, size_t ahead, int first, const double *const *in, const double *par,
                  float *reg, double *out)
{
	DISPATCH(run16, f, n, ahead, first, in, par, reg, out);
}

static void run16f(const bk_form *f, size_t n, size_t ahead, int first, const double *const *in,
                   const double *par, float *reg, double *out)
{
	DISPATCH(run16f, f, n, ahead, first, in, par, reg, out);
}

void bk_ir_op64(const bk_instr *c, double *restrict r, const double *restrict A, const double *restrict B,
                const double *restrict C)
{
#if BK_IR_HAVE_AVX2
	if (bk_ir_avx2()) {
		run64_avx2_op(c, r, A, B, C);
		return;
	}
#endif
	run64_gen_op(c, r, A, B, C);
}

void bk_ir_forward64(const bk_form *f, size_t n, size_t ahead, int first, const double *const *in,
                     const double *par, double *reg)
{
	run64(f, n, ahead, first, in, par, reg, NULL);
}

const char *bk_precision_name(bk_precision p)
{
	return p == BK_F64 ? "f64" : p == BK_F32 ? "f32" : p == BK_F16 ? "f16" : "fld";
}

static size_t width_of(bk_precision p)
{
	return p == BK_F64 ? sizeof(double) : p == BK_FLD ? sizeof(long double) : sizeof(float);
}

/* One block in the chosen precision; reg keeps every register's values. */
static void run_block(const bk_form *f, bk_precision prec, size_t m, size_t ahead, int first,
                      const double *const *blk, const double *params, void *reg, double *out)
{
	switch (prec) {
	case BK_F64: run64(f, m, ahead, first, blk, params, reg, out); break;
	case BK_F32: run32(f, m, ahead, first, blk, params, reg, out); break;
	case BK_F16: run16(f, m, ahead, first, blk, params, reg, out); break;
	default: runld(f, m, ahead, first, blk, params, reg, out); break;
	}
}

static long double reg_at(const void *reg, bk_precision prec, int i, size_t k)
{
	size_t at = (size_t)i * BLOCK + k;
	switch (prec) {
	case BK_F64: return ((const double *)reg)[at];
	case BK_FLD: return ((const long double *)reg)[at];
	default: return ((const float *)reg)[at];
	}
}

/* Smallest normal of each precision: where flush-to-zero hardware drops results. */
static long double min_normal(bk_precision p)
{
	return p == BK_F16 ? 0x1p-14L : p == BK_F32 ? 0x1p-126L : p == BK_F64 ? 0x1p-1022L : 0x1p-16382L;
}

/* What a leaf held before it was rounded to the precision: a constant, a
 * parameter or an input sample. */
static double leaf_source(const bk_instr *c, const double *const *blk, const double *params, size_t k)
{
	return c->op == BK_OP_CONST ? c->k : c->op == BK_OP_PARAM ? params[c->slot] : blk[c->slot][k];
}

/* Flags of one block, from the registers the kernel left. A leaf overflows
 * when the precision cannot hold its value (70000 in half is inf): that is
 * an intermediate like any other, which a later min or max may hide. Only
 * operations count as subnormal: an input near 0 is the input's. */
static void block_flags(const bk_form *f, bk_precision prec, size_t m, const void *reg,
                        const double *const *blk, const double *params, unsigned char *flags, int first_op[3])
{
	long double tiny = min_normal(prec);
	for (int i = 0; i < f->n; i++) {
		const bk_instr *c = &f->code[i];
		int leaf = c->op == BK_OP_CONST || c->op == BK_OP_PARAM || c->op == BK_OP_INPUT;
		int ops[3] = {c->a, c->b, c->c}, ar = leaf ? 0 : bk_opinfo_table[c->op].arity;
		for (size_t k = 0; k < m; k++) {
			long double r = reg_at(reg, prec, i, k);
			int any_nan = 0, all_finite = 1;
			if (leaf)
				all_finite = isfinite(leaf_source(c, blk, params, k));
			for (int j = 0; j < ar; j++) {
				long double x = reg_at(reg, prec, ops[j], k);
				any_nan |= isnan(x);
				all_finite &= isfinite(x);
			}
			unsigned bit = 0;
			if (isnan(r) && !any_nan && !leaf)
				bit = BK_FLAG_NAN;
			else if (isinf(r) && all_finite)
				bit = BK_FLAG_OVERFLOW;
			else if (r != 0 && fabsl(r) < tiny && !leaf)
				bit = BK_FLAG_SUBNORMAL;
			if (!bit)
				continue;
			flags[k] |= (unsigned char)bit;
			int b = bit == BK_FLAG_NAN ? 0 : bit == BK_FLAG_OVERFLOW ? 1 : 2;
			if (first_op && first_op[b] < 0)
				first_op[b] = i;
		}
	}
}

/*
 * Half precision under the orders a driver may pick. Without `precise` (SPIR-V
 * NoContraction), a compiler may fuse a * b + c into one rounding ("Evaluation
 * of Expressions": Mesa's nir_opt_algebraic fuses a multiply used once into
 * the add, LLVM contracts fmuladd, real mobile GPUs have a half fma): in half
 * that moves results by many ulps where a * b cancels against c, and changes
 * their kind where a * b alone passes 65504 (inf unfused, a number fused) or
 * rounds to just below it (the reverse). So where a form has a mad or a mix
 * (whose spelled-out x + (y - x) t ends in one), BK_F16 runs both orders and
 * keeps, per sample, the worse: NaN over inf over a number, and of two numbers
 * the one farther from the form's f64 value. A half score, a stability
 * verdict or a flag then holds whichever order the driver takes; the flags are
 * the union of both runs'. tests/vk runs the driver against both.
 */
static int fusable(const bk_form *f)
{
	for (int i = 0; i < f->n; i++)
		if (f->code[i].op == BK_OP_MAD || f->code[i].op == BK_OP_MIX)
			return 1;
	return 0;
}

static double worse(double u, double w, double ref)
{
	if (u != u || w != w)
		return u != u ? u : w;
	if (isinf(u) || isinf(w))
		return isinf(u) ? u : w;
	return isfinite(ref) && fabs(w - ref) > fabs(u - ref) ? w : u;
}

static int eval(const bk_form *f, bk_precision prec, size_t n, const double *const in[BK_IN_COUNT],
                const double *params, double *out, unsigned char *flags, int first_op[3])
{
	for (int i = 0; i < BK_IN_COUNT; i++)
		if ((f->inputs >> i & 1) && !in[i])
			return -1;
	BK_DOOR_FORM(f, n, in, params);
	BK_DOOR(out, sizeof(double) * n, "out");
	BK_DOOR(flags, n, "flags");
	int both = prec == BK_F16 && fusable(f);
	size_t regs = (size_t)f->n * BLOCK;
	/* the registers; with both orders also the fused run's, the f64 run's
	 * and their two blocks of results */
	char *reg = malloc(regs * width_of(prec) + (both ? regs * (sizeof(float) + sizeof(double)) +
	                                                      2 * BLOCK * sizeof(double) : 0));
	if (!reg)
		return -1;
	float *regf = (float *)(reg + regs * width_of(prec));
	double *reg64 = (double *)(regf + (both ? regs : 0)), *fused = reg64 + (both ? regs : 0), *ref = fused + BLOCK;
	if (first_op)
		first_op[0] = first_op[1] = first_op[2] = -1;
	const double *blk[BK_IN_COUNT];
	for (size_t s = 0; s < n; s += BLOCK) {
		size_t m = n - s < BLOCK ? n - s : BLOCK;
		size_t ahead = n - s - m < BLOCK ? n - s - m : BLOCK;
		for (int i = 0; i < BK_IN_COUNT; i++)
			blk[i] = in[i] ? in[i] + s : NULL;
		run_block(f, prec, m, ahead, s == 0, blk, params, reg, out + s);
		if (flags) {
			for (size_t k = 0; k < m; k++)
				flags[s + k] = 0;
			block_flags(f, prec, m, reg, blk, params, flags + s, first_op);
		}
		if (!both)
			continue;
		run16f(f, m, 0, s == 0, blk, params, regf, fused);
		run64(f, m, 0, s == 0, blk, params, reg64, ref);
		for (size_t k = 0; k < m; k++)
			out[s + k] = worse(out[s + k], fused[k], ref[k]);
		if (flags)
			block_flags(f, prec, m, regf, blk, params, flags + s, first_op);
	}
	free(reg);
	return 0;
}

int bk_ir_eval_half_orders(const bk_form *f, size_t n, const double *const in[BK_IN_COUNT], const double *params,
                           double *unfused, double *fused)
{
	for (int i = 0; i < BK_IN_COUNT; i++)
		if ((f->inputs >> i & 1) && !in[i])
			return -1;
	BK_DOOR_FORM(f, n, in, params);
	BK_DOOR(unfused, sizeof(double) * n, "unfused");
	BK_DOOR(fused, sizeof(double) * n, "fused");
	float *reg = malloc((size_t)f->n * BLOCK * sizeof *reg * 2);
	if (!reg)
		return -1;
	const double *blk[BK_IN_COUNT];
	for (size_t s = 0; s < n; s += BLOCK) {
		size_t m = n - s < BLOCK ? n - s : BLOCK;
		for (int i = 0; i < BK_IN_COUNT; i++)
			blk[i] = in[i] ? in[i] + s : NULL;
		if (unfused)
			run16(f, m, 0, s == 0, blk, params, reg, unfused + s);
		if (fused)
			run16f(f, m, 0, s == 0, blk, params, reg + (size_t)f->n * BLOCK, fused + s);
	}
	free(reg);
	return 0;
}

int bk_form_eval_half_vs(const bk_form *f, size_t n, const double *const in[BK_IN_COUNT], const double *params,
                         const double *y, double *out)
{
	BK_DOOR(y, sizeof(double) * n, "y");
	if (!fusable(f))
		return eval(f, BK_F16, n, in, params, out, NULL, NULL);
	double *fused = malloc((n ? n : 1) * sizeof *fused);
	if (!fused || bk_ir_eval_half_orders(f, n, in, params, out, fused)) {
		free(fused);
		return -1;
	}
	for (size_t k = 0; k < n; k++) /* worse() keeps the unfused where y[k] is no number */
		out[k] = worse(out[k], fused[k], y[k]);
	free(fused);
	return 0;
}

int bk_form_eval(const bk_form *f, bk_precision prec, size_t n,
                 const double *const in[BK_IN_COUNT], const double *params, double *out)
{
	return eval(f, prec, n, in, params, out, NULL, NULL);
}

int bk_form_eval_flags(const bk_form *f, bk_precision prec, size_t n,
                       const double *const in[BK_IN_COUNT], const double *params, double *out,
                       unsigned char *flags, int first_op[3])
{
	return eval(f, prec, n, in, params, out, flags, first_op);
}
