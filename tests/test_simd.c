/*
 * test_simd.c — the IR's kernels (brdf/ir_eval.c, ir_diff.c) bit for bit
 * against a scalar reference, on both of their paths (the x86-64 baseline and
 * AVX2, picked at run time), and forms bound to fixed samples (bk_form_bind)
 * against the plain evaluators.
 *
 * The reference below walks the instruction list one sample at a time and
 * applies each op as the IR defines it (ir_ops.h; min and max: a NaN operand
 * gives the other one, of two equal operands the second; mad and mix rounded
 * at every step; f16 rounding every result to binary16 and running pow, exp
 * and log as exp2/log2 and multiplies, as a GPU does; f64's exp2, log2,
 * pow, exp and log and f32's pow, exp and log are brdf/dmath.c's, whose
 * precision tests/test_dmath.c checks against long double; f32's exp2 and
 * log2 are libm's, which vmath.h's match on these samples). Vectorised arithmetic
 * must give these bits exactly: + - * / sqrt are IEEE element-wise, and FMA
 * contraction (one rounding for a*b + c) must never happen. The negative
 * control is a reference doctored to fuse the multiply-add: it must disagree.
 */
#include "brdf.h"
#include "ir.h"

#include <criterion/criterion.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define N 300 /* two full blocks of BK_IR_BLOCK and a partial one */

static bk_form *form(const char *text)
{
	bk_form_error e;
	bk_form *f = bk_form_parse(text, &e);
	cr_assert_not_null(f, "%s: %s", text, e.message);
	return f;
}

/* Inputs: a fixed sequence over [-3, 3) with the edges mixed in (0, -0, 1,
 * NaN, inf, a subnormal, a large value), different per input. */
static double *in_buf[BK_IN_COUNT];
static void make_inputs(void)
{
	static const double edge[] = {0.0, -0.0, 1.0, NAN, INFINITY, -INFINITY, 1e-310, 1e300, 0.5, -2.0};
	uint64_t s = 12345;
	for (int i = 0; i < BK_IN_COUNT; i++) {
		in_buf[i] = malloc(sizeof(double) * N);
		for (size_t k = 0; k < N; k++) {
			s = s * 6364136223846793005ull + 1442695040888963407ull;
			double u = (double)(s >> 11) * 0x1p-53;
			in_buf[i][k] = (k * 7 + (size_t)i) % 23 == 0 ? edge[(k + (size_t)i) % 10] : -3.0 + 6.0 * u;
		}
	}
}

static void free_inputs(void)
{
	for (int i = 0; i < BK_IN_COUNT; i++)
		free(in_buf[i]);
}

static float h16(float x) { return (float)bk_half_round(x); }
static double min_ir(double x, double y) { return (x < y || y != y) ? x : y; }
static double max_ir(double x, double y) { return (x > y || y != y) ? x : y; }
static float minf_ir(float x, float y) { return (x < y || y != y) ? x : y; }
static float maxf_ir(float x, float y) { return (x > y || y != y) ? x : y; }

/* fused: the doctored reference (negative control) */
static double ref64_op(bk_op op, double A, double B, double C, int fused)
{
	switch (op) {
	case BK_OP_ADD: return A + B;
	case BK_OP_SUB: return A - B;
	case BK_OP_MUL: return A * B;
	case BK_OP_DIV: return A / B;
	case BK_OP_NEG: return -A;
	case BK_OP_MAD: return fused ? fma(A, B, C) : A * B + C;
	case BK_OP_POW: return A == 0 && !(B > 0) ? NAN : bk_dexp2(B * bk_dlog2(A));
	case BK_OP_SQRT: return sqrt(A);
	case BK_OP_RSQRT: return 1.0 / sqrt(A);
	case BK_OP_RCP: return 1.0 / A;
	case BK_OP_EXP: return bk_dexp(A);
	case BK_OP_EXP2: return bk_dexp2(A);
	case BK_OP_LOG: return bk_dlog(A);
	case BK_OP_LOG2: return bk_dlog2(A);
	case BK_OP_MIN: return min_ir(A, B);
	case BK_OP_MAX: return max_ir(A, B);
	case BK_OP_CLAMP: return min_ir(max_ir(A, B), C);
	case BK_OP_SATURATE: return min_ir(max_ir(A, 0.0), 1.0);
	case BK_OP_MIX: return A + (B - A) * C;
	case BK_OP_ABS: return fabs(A);
	default: return NAN;
	}
}

static float ref32_op(bk_op op, float A, float B, float C, int fused)
{
	switch (op) {
	case BK_OP_ADD: return A + B;
	case BK_OP_SUB: return A - B;
	case BK_OP_MUL: return A * B;
	case BK_OP_DIV: return A / B;
	case BK_OP_NEG: return -A;
	case BK_OP_MAD: return fused ? fmaf(A, B, C) : A * B + C;
	case BK_OP_POW: return A == 0 && !(B > 0) ? NAN : exp2f(B * log2f(A));
	case BK_OP_SQRT: return sqrtf(A);
	case BK_OP_RSQRT: return 1.0f / sqrtf(A);
	case BK_OP_RCP: return 1.0f / A;
	case BK_OP_EXP: return (float)bk_dexp(A);
	case BK_OP_EXP2: return exp2f(A);
	case BK_OP_LOG: return (float)bk_dlog(A);
	case BK_OP_LOG2: return log2f(A);
	case BK_OP_MIN: return minf_ir(A, B);
	case BK_OP_MAX: return maxf_ir(A, B);
	case BK_OP_CLAMP: return minf_ir(maxf_ir(A, B), C);
	case BK_OP_SATURATE: return minf_ir(maxf_ir(A, 0.0f), 1.0f);
	case BK_OP_MIX: return A + (B - A) * C;
	case BK_OP_ABS: return fabsf(A);
	default: return NAN;
	}
}

static float ref16_op(bk_op op, float A, float B, float C, int fused)
{
	switch (op) {
	case BK_OP_NEG: return -A;
	case BK_OP_ABS: return fabsf(A);
	case BK_OP_MIN: case BK_OP_MAX: case BK_OP_CLAMP: case BK_OP_SATURATE: return ref32_op(op, A, B, C, 0);
	case BK_OP_MAD: return fused ? h16((float)((double)A * B + C)) : h16(h16(A * B) + C);
	case BK_OP_MIX: return fused ? h16((float)((double)h16(B - A) * C + A)) : h16(A + h16(h16(B - A) * C));
	case BK_OP_POW: return A == 0 && !(B > 0) ? NAN : h16(exp2f(h16(B * h16(log2f(A)))));
	case BK_OP_EXP: return h16(exp2f(h16(A * h16((float)1.44269504088896340736))));
	case BK_OP_LOG: return h16(h16(log2f(A)) * h16((float)0.693147180559945309417));
	default: return h16(ref32_op(op, A, B, C, 0));
	}
}

/* The reference value of f at sample k in precision p; fused: every mad (and
 * mix's) rounded once. */
static double reference_order(const bk_form *f, bk_precision p, size_t k, const double *par, int fused)
{
	double v[BK_FORM_MAX_INSTR];
	for (int i = 0; i < f->n; i++) {
		const bk_instr *c = &f->code[i];
		double x = c->op == BK_OP_CONST ? c->k : c->op == BK_OP_PARAM ? par[c->slot] : in_buf[c->slot][k];
		double A = c->a >= 0 ? v[c->a] : 0, B = c->b >= 0 ? v[c->b] : 0, C = c->c >= 0 ? v[c->c] : 0;
		int leaf = c->op == BK_OP_CONST || c->op == BK_OP_PARAM || c->op == BK_OP_INPUT;
		if (p == BK_F64)
			v[i] = leaf ? x : ref64_op(c->op, A, B, C, fused);
		else if (p == BK_F32)
			v[i] = leaf ? (float)x : ref32_op(c->op, (float)A, (float)B, (float)C, fused);
		else
			v[i] = leaf ? h16((float)x) : ref16_op(c->op, (float)A, (float)B, (float)C, fused);
	}
	return v[f->out];
}

static int has_mad(const bk_form *f)
{
	for (int i = 0; i < f->n; i++)
		if (f->code[i].op == BK_OP_MAD || f->code[i].op == BK_OP_MIX)
			return 1;
	return 0;
}

/* The reference of bk_form_eval: in half, where a driver may fuse, the worse
 * of the two orders (NaN over inf over a number, else the farther from f64's
 * value: brdf/ir_eval.c); fused (the negative control): the fused order alone. */
static double reference(const bk_form *f, bk_precision p, size_t k, const double *par, int fused)
{
	double u = reference_order(f, p, k, par, fused);
	if (p != BK_F16 || fused || !has_mad(f))
		return u;
	double w = reference_order(f, p, k, par, 1), e = reference_order(f, BK_F64, k, par, 0);
	if (isnan(u) || isnan(w))
		return NAN;
	if (isinf(u) || isinf(w))
		return isinf(u) ? u : w;
	return isfinite(e) && fabs(w - e) > fabs(u - e) ? w : u;
}

/* Every op, with and without parameters; the last are fused into MAD. */
static const char *const forms[] = {
	"LoH + r*NoV - LoH/r",
	"p0*LoH + p1/(r + p2)",
	"sqrt(LoH) + rsqrt(r) + rcp(NoV)",
	"exp2(LoH) + log2(r) + exp(NoV) + log(NoH)",
	"pow(LoH, r) + pow(NoV, p0)",
	"min(LoH, r) + max(NoV, LoH) + clamp(LoH, r, NoV) + saturate(r)",
	"mix(LoH, r, NoV) + abs(NoV) - NoH",
	"clamp(LoH, p0, p1) * mix(p2, r, NoV)",
	"LoH*r + NoV*NoH",
	"p0*LoH*LoH + p1*LoH + p2",
};
enum { NFORMS = sizeof forms / sizeof forms[0] };
static const double par[BK_MAX_PARAMS] = {0.75, -1.3, 2.5, 0.1};

static int same_bits(double x, double y)
{
	return memcmp(&x, &y, sizeof x) == 0 || (isnan(x) && isnan(y));
}

/* Samples where bk_form_eval's bits differ from the reference. */
static int mismatches(const bk_form *f, bk_precision p, int fused)
{
	double out[N];
	cr_assert_eq(bk_form_eval(f, p, N, (const double *const *)in_buf, par, out), 0);
	int bad = 0;
	for (size_t k = 0; k < N; k++)
		bad += !same_bits(out[k], reference(f, p, k, par, fused));
	return bad;
}

static void check_all(void)
{
	static const bk_precision prec[] = {BK_F64, BK_F32, BK_F16};
	for (int j = 0; j < NFORMS; j++) {
		bk_form *f = form(forms[j]);
		for (int q = 0; q < 3; q++)
			cr_expect_eq(mismatches(f, prec[q], 0), 0, "%s in %s (%s path): differs from the scalar reference",
			             forms[j], bk_precision_name(prec[q]), bk_ir_avx2() ? "AVX2" : "baseline");
		bk_form_free(f);
	}
}

Test(simd, baseline_path_matches_scalar_reference, .init = make_inputs, .fini = free_inputs)
{
	bk_ir_force_generic(1);
	cr_assert_eq(bk_ir_avx2(), 0);
	check_all();
	bk_ir_force_generic(0);
}

Test(simd, avx2_path_matches_scalar_reference, .init = make_inputs, .fini = free_inputs)
{
	if (!__builtin_cpu_supports("avx2"))
		cr_skip_test("no AVX2 on this CPU: the baseline test covers what runs here");
	cr_assert_eq(bk_ir_avx2(), 1);
	check_all();
}

/* Negative control: a reference that fuses a*b + c (FMA) differs on these
 * samples, in every precision, so the tests above would catch a kernel that
 * contracted; and the two fused forms are where it shows. */
Test(simd, fused_reference_is_caught, .init = make_inputs, .fini = free_inputs)
{
	static const bk_precision prec[] = {BK_F64, BK_F32, BK_F16};
	for (int path = 0; path < 2; path++) {
		bk_ir_force_generic(path == 0);
		for (int j = NFORMS - 2; j < NFORMS; j++) {
			bk_form *f = form(forms[j]);
			for (int q = 0; q < 3; q++)
				cr_expect_gt(mismatches(f, prec[q], 1), 0, "%s in %s: the fused reference was not caught", forms[j],
				             bk_precision_name(prec[q]));
			bk_form_free(f);
		}
	}
	bk_ir_force_generic(0);
}

/* The Jacobian on both paths: the same bits (the reverse sweep has the same
 * two copies as the forward kernel). */
Test(simd, jacobian_same_on_both_paths, .init = make_inputs, .fini = free_inputs)
{
	for (int j = 0; j < NFORMS; j++) {
		bk_form *f = form(forms[j]);
		int np = bk_form_nparams(f);
		double o[2][N], jac[2][N * 4];
		for (int path = 0; path < 2; path++) {
			bk_ir_force_generic(path == 0);
			cr_assert_eq(bk_form_eval_diff(f, N, (const double *const *)in_buf, par, o[path], jac[path]), 0);
		}
		bk_ir_force_generic(0);
		for (size_t k = 0; k < N; k++) {
			cr_expect(same_bits(o[0][k], o[1][k]), "%s: value %zu", forms[j], k);
			for (int q = 0; q < np; q++)
				cr_expect(same_bits(jac[0][k * np + q], jac[1][k * np + q]), "%s: d/dp%d at %zu", forms[j], q, k);
		}
		bk_form_free(f);
	}
}

/* ---- bound forms ------------------------------------------------------------ */

/* Forms whose parts read no parameter (kept), or all of them, or none. */
static const char *const bound_forms[] = {
	"p0 * log2(LoH) + exp2(p1 * r)",
	"f0 * (p0 + sqrt(LoH*LoH + r)) / (p1 + min(NoV, r))",
	"p0",
	"LoH*r + 1",
	"mix(p0, LoH*r, saturate(NoV)) + p1*(p2 + rcp(NoH))",
	"pow(LoH, p0) * clamp(r, 0.1, 0.9) + p1",
};
enum { NBOUND = sizeof bound_forms / sizeof bound_forms[0] };

/* Calls with changing parameters, with and without the Jacobian: each equal
 * to bk_form_eval_diff (and bk_form_eval f64) at the same parameters. */
Test(bound, same_bits_as_the_plain_evaluators, .init = make_inputs, .fini = free_inputs)
{
	const double *const *in = (const double *const *)in_buf;
	for (int j = 0; j < NBOUND; j++) {
		bk_form *f = form(bound_forms[j]);
		int np = bk_form_nparams(f);
		bk_form_bound *b = bk_form_bind(f, N, in);
		cr_assert_not_null(b);
		for (int call = 0; call < 4; call++) {
			double p[BK_MAX_PARAMS];
			for (int q = 0; q < BK_MAX_PARAMS; q++)
				p[q] = 0.3 + 0.7 * q - 0.45 * call;
			double o0[N], o1[N], o2[N], j0[N * 4], j1[N * 4];
			cr_assert_eq(bk_form_eval_diff(f, N, in, p, o0, j0), 0);
			cr_assert_eq(bk_form_eval(f, BK_F64, N, in, p, o2), 0);
			int with_jac = call != 2;
			cr_assert_eq(bk_form_bound_eval(b, p, o1, with_jac ? j1 : NULL), 0);
			for (size_t k = 0; k < N; k++) {
				cr_expect(same_bits(o0[k], o1[k]), "%s call %d: value %zu: %a vs %a", bound_forms[j], call, k,
				          o0[k], o1[k]);
				cr_expect(same_bits(o2[k], o1[k]), "%s call %d: value %zu (bk_form_eval)", bound_forms[j], call, k);
				for (int q = 0; with_jac && q < np; q++)
					cr_expect(same_bits(j0[k * np + q], j1[k * np + q]), "%s call %d: d/dp%d at %zu", bound_forms[j],
					          call, q, k);
			}
		}
		bk_form_bound_free(b);
		bk_form_free(f);
	}
}

/* What reads no parameter is computed once: after the first call, changing
 * the samples (which the contract forbids) moves only the parameter-dependent
 * leaves read in place, not the kept log2(LoH); so the bound form then gives
 * the first samples' log2 with the new r. The negative control: a fresh
 * binding sees the new samples everywhere. */
Test(bound, keeps_what_reads_no_parameter, .init = make_inputs, .fini = free_inputs)
{
	const double *const *in = (const double *const *)in_buf;
	bk_form *f = form("p0 * log2(LoH) + p1 * r");
	double p[2] = {2.0, 3.0}, o[N], fresh[N];
	bk_form_bound *b = bk_form_bind(f, N, in);
	cr_assert_eq(bk_form_bound_eval(b, p, o, NULL), 0);
	double old_loh[N];
	memcpy(old_loh, in_buf[BK_IN_LOH], sizeof old_loh);
	for (size_t k = 0; k < N; k++)
		in_buf[BK_IN_LOH][k] = 0.5; /* log2: -1 */
	cr_assert_eq(bk_form_bound_eval(b, p, o, NULL), 0);
	bk_form_bound *b2 = bk_form_bind(f, N, in);
	cr_assert_eq(bk_form_bound_eval(b2, p, fresh, NULL), 0);
	int kept = 0, moved = 0;
	for (size_t k = 0; k < N; k++) {
		double r = in_buf[BK_IN_R][k];
		double want_kept = 2.0 * log2(old_loh[k]) + 3.0 * r;
		kept += same_bits(o[k], want_kept);
		moved += same_bits(fresh[k], 2.0 * -1.0 + 3.0 * r) && !same_bits(fresh[k], want_kept);
	}
	cr_expect_eq(kept, N, "the kept log2(LoH) was recomputed");
	cr_expect_gt(moved, N / 2, "a fresh binding should see the new LoH");
	bk_form_bound_free(b);
	bk_form_bound_free(b2);
	bk_form_free(f);
}

/* ---- TinySolver keeping a trial's Jacobian (fit/tiny.cc) --------------------- */

#include "solver.h"
#include "switches.h" /* bk_tiny_reuse_trial */

/* y = a exp(b x) at 40 points, from a start far off: a solve with accepted and
 * rejected steps. Counts the calls and those that asked for the Jacobian. */
typedef struct counting {
	int calls, with_jac;
} counting;

static int exp_fit(void *ctx, int block, const double *p, double *r, double *jac)
{
	(void)block;
	counting *c = ctx;
	c->calls++;
	c->with_jac += jac != NULL;
	for (int i = 0; i < 40; i++) {
		double x = i / 39.0, e = exp(p[1] * x);
		r[i] = p[0] * e - 2.0 * exp(-1.5 * x) - 0.01 * sin(7.0 * x);
		if (jac)
			jac[2 * i] = e, jac[2 * i + 1] = p[0] * x * e;
	}
	return 0;
}

/* The same bits and summary as bk_solve_tiny, with fewer calls: each accepted
 * trial is not evaluated again. The negative control is bk_solve_tiny itself
 * (and bk_solve_tiny_reusing with the reuse switched off): more calls. */
Test(reuse, same_solution_fewer_calls)
{
	int size[] = {40};
	counting c[3] = {{0, 0}, {0, 0}, {0, 0}};
	double q[3][2];
	bk_fit_summary s[3];
	bk_fit_options o = BK_FIT_OPTIONS_INIT;
	for (int k = 0; k < 3; k++) {
		bk_problem p = {2, 1, size, exp_fit, &c[k], NULL, NULL, NULL};
		q[k][0] = 0.2, q[k][1] = 1.0;
		bk_tiny_reuse_trial = k != 2;
		int rc = k == 0 ? bk_solve_tiny(&p, &o, q[k], &s[k]) : bk_solve_tiny_reusing(&p, &o, q[k], &s[k]);
		cr_assert_eq(rc, 0, "%s", s[k].message);
		cr_assert_eq(s[k].termination, BK_TERM_CONVERGENCE, "%s", s[k].message);
	}
	bk_tiny_reuse_trial = 1;
	for (int k = 1; k < 3; k++) {
		cr_expect(memcmp(q[0], q[k], sizeof q[0]) == 0, "solve %d: other parameters", k);
		cr_expect(memcmp(&s[0].final_cost, &s[k].final_cost, sizeof(double)) == 0, "solve %d: other cost", k);
		cr_expect_eq(s[0].iterations, s[k].iterations);
		cr_expect_str_eq(s[0].message, s[k].message);
	}
	cr_expect_gt(s[0].iterations, 3, "a solve of several steps");
	cr_expect_lt(c[1].calls, c[0].calls, "reusing: %d calls, plain: %d", c[1].calls, c[0].calls);
	cr_expect_eq(c[2].calls, c[0].calls, "reuse off: as plain");
	/* every call of the reusing solve asks for the Jacobian */
	cr_expect_eq(c[1].with_jac, c[1].calls);
}

/* No samples: nothing to keep, nothing written, no error. */
Test(bound, no_samples)
{
	double x = 0.5;
	const double *in[BK_IN_COUNT] = {&x, &x, &x, &x, &x, &x, &x};
	bk_form *f = form("p0 * log2(LoH)");
	bk_form_bound *b = bk_form_bind(f, 0, in);
	cr_assert_not_null(b);
	double out = 7, jac = 7, p = 1;
	cr_assert_eq(bk_form_bound_eval(b, &p, &out, &jac), 0);
	cr_expect_eq(out, 7);
	cr_expect_eq(jac, 7);
	bk_form_bound_free(b);
	bk_form_free(f);
}
