/*
 * ir_adjoint.h — the adjoint updates of ir_diff.c, one op over one block
 * and the backward sweep that applies them over one block
 * (internal; included by ir_diff.c only, twice: SFX and ATTR name the copy,
 * the x86-64 baseline and AVX2, as ir_eval.c's kernels; the same C, so the
 * same bits, ir_eval.c says why). Why one operand at a time: ir_diff.c.
 */
#define BW_ARGS const double *restrict g, const double *restrict r, const double *restrict A, \
	const double *restrict B, const double *restrict C
ATTR static void CAT(backward_a, SFX)(int op, BW_ARGS, double *restrict ga)
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

ATTR static void CAT(backward_b, SFX)(int op, BW_ARGS, double *restrict gb)
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

ATTR static void CAT(backward_c, SFX)(int op, BW_ARGS, double *restrict gc)
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

/* The backward sweep over one block of m samples; val[i]: where register i's
 * values are (the kernel's registers, or the bound form's kept blocks). */
ATTR static void CAT(backward, SFX)(const bk_form *f, const char *dep, size_t n, const double *const *val,
                                   double *adj, double *jac, int np)
{
	/* zeroed by a loop of vector stores (the Makefile keeps gcc from making
	 * it a memset, which it inlined as rep stos: 40 % of this function) */
	for (int i = 0; i < f->n; i++)
		if (dep[i]) {
			double *restrict z = adj + (size_t)i * BLOCK;
			for (size_t k = 0; k < BLOCK; k++)
				z[k] = 0.0;
		}
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
#define OPND(x) ((x) >= 0 ? val[x] : NULL)
#define ADJ(x) ((x) >= 0 && dep[x] ? adj + (size_t)(x) * BLOCK : NULL)
		const double *r = val[i], *A = OPND(c->a), *B = OPND(c->b), *C = OPND(c->c);
		double *ga = ADJ(c->a), *gb = ADJ(c->b), *gc = ADJ(c->c);
		if (ga)
			CAT(backward_a, SFX)(c->op, g, r, A, B, C, ga);
		if (gb)
			CAT(backward_b, SFX)(c->op, g, r, A, B, C, gb);
		if (gc)
			CAT(backward_c, SFX)(c->op, g, r, A, B, C, gc);
#undef OPND
#undef ADJ
	}
}
