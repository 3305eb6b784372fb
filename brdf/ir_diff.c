/*
 * ir_diff.c — derivatives of a form with respect to its parameters, reverse
 * mode over the same blocks: the f64 kernel's forward sweep leaves every
 * register's values, a backward sweep carries adjoints from the result to the
 * operands, and each PARAM register's adjoint is its column of the Jacobian.
 * One backward sweep gives all parameters at once, whatever their number.
 *
 * Only instructions that depend on a parameter carry adjoints (the rest are
 * constants of the fit); each op's adjoint update runs over a whole block, as
 * the forward kernel does, so that it vectorises (backward_a below: why one
 * operand at a time).
 *
 * At the kinks of min, max, clamp, saturate and abs the derivative of the
 * branch taken is used (the subgradient a fitter expects).
 */
#include "ir.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define BLOCK BK_IR_BLOCK
#define LN2 0.693147180559945309417 /* ln 2 (M_LN2 is POSIX, not C11) */

/* dep[i]: instruction i depends on a parameter. */
static void dependence(const bk_form *f, char *dep)
{
	for (int i = 0; i < f->n; i++) {
		const bk_instr *c = &f->code[i];
		dep[i] = c->op == BK_OP_PARAM || (c->a >= 0 && dep[c->a]) || (c->b >= 0 && dep[c->b]) ||
		         (c->c >= 0 && dep[c->c]);
	}
}

/*
 * Adjoint update of one instruction over a block, one operand at a time: the
 * adjoint of operand a (b, c) of instruction c, given the adjoint g and value
 * r of its result and the operands' values A, B, C. Split per operand so that
 * the one array written (an operand's adjoint) never overlaps anything read:
 * g is the adjoint of a later register, r, A, B, C are values, not adjoints.
 * So every pointer is restrict (two operands may be the same register, x*x,
 * but both are only read), which is what lets gcc -O2 vectorise the loops as
 * it does the forward kernel's: 20 of them now, 1 when one function updated
 * ga and gb, which may be the same array (-fopt-info-vec; those with a
 * branch, min max clamp saturate, or a libm call, pow, stay scalar). Each
 * element still gets the same operations in the same order, and the
 * operands' updates come in the same order (a, then b, then c), so the
 * results are those of the unsplit loops, bit for bit (tests/test_resid.c).
 */
#define BW_ARGS const double *restrict g, const double *restrict r, const double *restrict A, \
	const double *restrict B, const double *restrict C
static void backward_a(int op, BW_ARGS, double *restrict ga)
{
	(void)C;
	size_t k;
	switch (op) {
	case BK_OP_ADD: case BK_OP_SUB: for (k = 0; k < BLOCK; k++) ga[k] += g[k]; break;
	case BK_OP_MUL: case BK_OP_MAD: for (k = 0; k < BLOCK; k++) ga[k] += g[k] * B[k]; break;
	case BK_OP_DIV: for (k = 0; k < BLOCK; k++) ga[k] += g[k] / B[k]; break;
	case BK_OP_NEG: for (k = 0; k < BLOCK; k++) ga[k] -= g[k]; break;
	case BK_OP_POW: for (k = 0; k < BLOCK; k++) ga[k] += g[k] * B[k] * pow(A[k], B[k] - 1.0); break;
	case BK_OP_SQRT: for (k = 0; k < BLOCK; k++) ga[k] += g[k] * 0.5 / r[k]; break;
	case BK_OP_RSQRT: for (k = 0; k < BLOCK; k++) ga[k] -= g[k] * 0.5 * r[k] / A[k]; break;
	case BK_OP_RCP: for (k = 0; k < BLOCK; k++) ga[k] -= g[k] * r[k] * r[k]; break;
	case BK_OP_EXP: for (k = 0; k < BLOCK; k++) ga[k] += g[k] * r[k]; break;
	case BK_OP_EXP2: for (k = 0; k < BLOCK; k++) ga[k] += g[k] * r[k] * LN2; break;
	case BK_OP_LOG: for (k = 0; k < BLOCK; k++) ga[k] += g[k] / A[k]; break;
	case BK_OP_LOG2: for (k = 0; k < BLOCK; k++) ga[k] += g[k] / (A[k] * LN2); break;
	case BK_OP_MIN: for (k = 0; k < BLOCK; k++) ga[k] += A[k] <= B[k] ? g[k] : 0.0; break;
	case BK_OP_MAX: for (k = 0; k < BLOCK; k++) ga[k] += A[k] >= B[k] ? g[k] : 0.0; break;
	case BK_OP_CLAMP: for (k = 0; k < BLOCK; k++) ga[k] += A[k] < B[k] || A[k] > C[k] ? 0.0 : g[k]; break;
	case BK_OP_SATURATE: for (k = 0; k < BLOCK; k++) ga[k] += A[k] > 0.0 && A[k] < 1.0 ? g[k] : 0.0; break;
	case BK_OP_MIX: for (k = 0; k < BLOCK; k++) ga[k] += g[k] * (1.0 - C[k]); break;
	case BK_OP_ABS: for (k = 0; k < BLOCK; k++) ga[k] += A[k] < 0.0 ? -g[k] : g[k]; break;
	default: break;
	}
}

static void backward_b(int op, BW_ARGS, double *restrict gb)
{
	size_t k;
	switch (op) {
	case BK_OP_ADD: for (k = 0; k < BLOCK; k++) gb[k] += g[k]; break;
	case BK_OP_SUB: for (k = 0; k < BLOCK; k++) gb[k] -= g[k]; break;
	case BK_OP_MUL: case BK_OP_MAD: for (k = 0; k < BLOCK; k++) gb[k] += g[k] * A[k]; break;
	case BK_OP_DIV: for (k = 0; k < BLOCK; k++) gb[k] -= g[k] * r[k] / B[k]; break;
	case BK_OP_POW: for (k = 0; k < BLOCK; k++) gb[k] += A[k] > 0.0 ? g[k] * r[k] * log(A[k]) : 0.0; break;
	case BK_OP_MIN: for (k = 0; k < BLOCK; k++) gb[k] += A[k] <= B[k] ? 0.0 : g[k]; break;
	case BK_OP_MAX: for (k = 0; k < BLOCK; k++) gb[k] += A[k] >= B[k] ? 0.0 : g[k]; break;
	case BK_OP_CLAMP: for (k = 0; k < BLOCK; k++) gb[k] += A[k] < B[k] ? g[k] : 0.0; break;
	case BK_OP_MIX: for (k = 0; k < BLOCK; k++) gb[k] += g[k] * C[k]; break;
	default: break;
	}
}

static void backward_c(int op, BW_ARGS, double *restrict gc)
{
	(void)r;
	size_t k;
	switch (op) {
	case BK_OP_MAD: for (k = 0; k < BLOCK; k++) gc[k] += g[k]; break;
	case BK_OP_CLAMP: for (k = 0; k < BLOCK; k++) gc[k] += A[k] < B[k] || !(A[k] > C[k]) ? 0.0 : g[k]; break;
	case BK_OP_MIX: for (k = 0; k < BLOCK; k++) gc[k] += g[k] * (B[k] - A[k]); break;
	default: break;
	}
}
#undef BW_ARGS

static void backward(const bk_form *f, const char *dep, size_t n, const double *v, double *adj, double *jac, int np)
{
	for (int i = 0; i < f->n; i++)
		if (dep[i])
			memset(adj + (size_t)i * BLOCK, 0, sizeof(double) * BLOCK);
	double *gout = adj + (size_t)f->out * BLOCK;
	for (size_t k = 0; k < BLOCK; k++)
		gout[k] = 1.0;
	for (int i = f->n - 1; i >= 0; i--) {
		const bk_instr *c = &f->code[i];
		if (!dep[i])
			continue;
		const double *g = adj + (size_t)i * BLOCK;
		if (c->op == BK_OP_PARAM) {
			for (size_t k = 0; k < n; k++)
				jac[k * (size_t)np + (size_t)c->slot] += g[k];
			continue;
		}
#define OPND(x) ((x) >= 0 ? v + (size_t)(x) * BLOCK : NULL)
#define ADJ(x) ((x) >= 0 && dep[x] ? adj + (size_t)(x) * BLOCK : NULL)
		const double *r = v + (size_t)i * BLOCK, *A = OPND(c->a), *B = OPND(c->b), *C = OPND(c->c);
		double *ga = ADJ(c->a), *gb = ADJ(c->b), *gc = ADJ(c->c);
		if (ga)
			backward_a(c->op, g, r, A, B, C, ga);
		if (gb)
			backward_b(c->op, g, r, A, B, C, gb);
		if (gc)
			backward_c(c->op, g, r, A, B, C, gc);
#undef OPND
#undef ADJ
	}
}

int bk_form_eval_diff(const bk_form *f, size_t n, const double *const in[BK_IN_COUNT],
                      const double *params, double *out, double *jac)
{
	for (int i = 0; i < BK_IN_COUNT; i++)
		if ((f->inputs >> i & 1) && !in[i])
			return -1;
	double *v = malloc(sizeof(double) * (size_t)f->n * BLOCK);
	double *adj = malloc(sizeof(double) * (size_t)f->n * BLOCK);
	char *dep = malloc((size_t)f->n);
	if (!v || !adj || !dep) {
		free(v);
		free(adj);
		free(dep);
		return -1;
	}
	dependence(f, dep);
	int np = f->nparams;
	if (np)
		memset(jac, 0, sizeof(double) * n * (size_t)np);
	const double *blk[BK_IN_COUNT];
	for (size_t s = 0; s < n; s += BLOCK) {
		size_t m = n - s < BLOCK ? n - s : BLOCK;
		size_t ahead = n - s - m < BLOCK ? n - s - m : BLOCK;
		for (int i = 0; i < BK_IN_COUNT; i++)
			blk[i] = in[i] ? in[i] + s : NULL;
		bk_ir_forward64(f, m, ahead, s == 0, blk, params, v);
		memcpy(out + s, v + (size_t)f->out * BLOCK, sizeof(double) * m);
		if (np && dep[f->out])
			backward(f, dep, m, v, adj, jac + s * (size_t)np, np);
	}
	free(v);
	free(adj);
	free(dep);
	return 0;
}
