/*
 * ir_adjoint.h — the adjoint updates of ir_diff.c, one op over one block
 * and the backward sweep that applies them over one block
 * (internal; included by ir_diff.c only, twice: SFX and ATTR name the copy,
 * the x86-64 baseline and AVX2, as ir_eval.c's kernels; the same C, so the
 * same bits, ir_eval.c says why). Why one operand at a time: ir_diff.c.
 */
/* dst[k] += e over the block, or, at the adjoint's first update (first),
 * dst[k] = 0.0 + e: the same bits as adding to a zeroed block (0.0 + -0.0 is
 * +0.0, and the zeroing pass is saved); DEC the same for -= */
#define ACC(dst, e) do { if (first) for (k = 0; k < BLOCK; k++) dst[k] = 0.0 + (e); \
	else for (k = 0; k < BLOCK; k++) dst[k] += (e); } while (0)
#define DEC(dst, e) do { if (first) for (k = 0; k < BLOCK; k++) dst[k] = 0.0 - (e); \
	else for (k = 0; k < BLOCK; k++) dst[k] -= (e); } while (0)
#define BW_ARGS const double *restrict g, const double *restrict r, const double *restrict A, \
	const double *restrict B, const double *restrict C
ATTR static void CAT(backward_a, SFX)(int op, BW_ARGS, double *restrict ga, int first)
{
	(void)C;
	size_t k;
	switch (op) {
	case BK_OP_ADD: case BK_OP_SUB: ACC(ga, g[k]); break;
	case BK_OP_MUL: case BK_OP_MAD: ACC(ga, g[k] * B[k]); break;
	case BK_OP_DIV: ACC(ga, g[k] / B[k]); break;
	case BK_OP_NEG: DEC(ga, g[k]); break;
	case BK_OP_POW: ACC(ga, g[k] * B[k] * bk_dpow(A[k], B[k] - 1.0)); break;
	case BK_OP_SQRT: ACC(ga, g[k] * 0.5 / r[k]); break;
	case BK_OP_RSQRT: DEC(ga, g[k] * 0.5 * r[k] / A[k]); break;
	case BK_OP_RCP: DEC(ga, g[k] * r[k] * r[k]); break;
	case BK_OP_EXP: ACC(ga, g[k] * r[k]); break;
	case BK_OP_EXP2: ACC(ga, g[k] * r[k] * LN2); break;
	case BK_OP_LOG: ACC(ga, g[k] / A[k]); break;
	case BK_OP_LOG2: ACC(ga, g[k] / (A[k] * LN2)); break;
	case BK_OP_MIN: ACC(ga, A[k] <= B[k] ? g[k] : 0.0); break;
	case BK_OP_MAX: ACC(ga, A[k] >= B[k] ? g[k] : 0.0); break;
	case BK_OP_CLAMP: ACC(ga, A[k] < B[k] || A[k] > C[k] ? 0.0 : g[k]); break;
	case BK_OP_SATURATE: ACC(ga, A[k] > 0.0 && A[k] < 1.0 ? g[k] : 0.0); break;
	case BK_OP_MIX: ACC(ga, g[k] * (1.0 - C[k])); break;
	case BK_OP_ABS: ACC(ga, A[k] < 0.0 ? -g[k] : g[k]); break;
	default: break;
	}
}

ATTR static void CAT(backward_b, SFX)(int op, BW_ARGS, double *restrict gb, int first)
{
	size_t k;
	switch (op) {
	case BK_OP_ADD: ACC(gb, g[k]); break;
	case BK_OP_SUB: DEC(gb, g[k]); break;
	case BK_OP_MUL: case BK_OP_MAD: ACC(gb, g[k] * A[k]); break;
	case BK_OP_DIV: DEC(gb, g[k] * r[k] / B[k]); break;
	case BK_OP_POW: ACC(gb, A[k] > 0.0 ? g[k] * r[k] * bk_dlog(A[k]) : 0.0); break;
	case BK_OP_MIN: ACC(gb, A[k] <= B[k] ? 0.0 : g[k]); break;
	case BK_OP_MAX: ACC(gb, A[k] >= B[k] ? 0.0 : g[k]); break;
	case BK_OP_CLAMP: ACC(gb, A[k] < B[k] ? g[k] : 0.0); break;
	case BK_OP_MIX: ACC(gb, g[k] * C[k]); break;
	default: break;
	}
}

ATTR static void CAT(backward_c, SFX)(int op, BW_ARGS, double *restrict gc, int first)
{
	(void)r;
	size_t k;
	switch (op) {
	case BK_OP_MAD: ACC(gc, g[k]); break;
	case BK_OP_CLAMP: ACC(gc, A[k] < B[k] || !(A[k] > C[k]) ? 0.0 : g[k]); break;
	case BK_OP_MIX: ACC(gc, g[k] * (B[k] - A[k])); break;
	default: break;
	}
}
#undef BW_ARGS
#undef ACC
#undef DEC

/* A parameter's adjoint g into its Jacobian column jc (n <= BLOCK rows, stride
 * 1): jc = 0.0 + g at the column's first write (first), jc += g after. The
 * count varies (a partial last block), which gcc -O2's cheap vectoriser does
 * not take (it was a scalar loop, ~1/4 of this sweep, perf): four at a time
 * (the straight-line four vectorise), the rest one by one; element-wise, so
 * the same bits either way. */
ATTR static void CAT(put_col, SFX)(double *restrict jc, const double *restrict g, size_t n, int first)
{
	size_t k = 0;
	if (first) {
		for (; k + 4 <= n; k += 4) {
			jc[k] = 0.0 + g[k];
			jc[k + 1] = 0.0 + g[k + 1];
			jc[k + 2] = 0.0 + g[k + 2];
			jc[k + 3] = 0.0 + g[k + 3];
		}
		for (; k < n; k++)
			jc[k] = 0.0 + g[k];
	} else {
		for (; k + 4 <= n; k += 4) {
			jc[k] += g[k];
			jc[k + 1] += g[k + 1];
			jc[k + 2] += g[k + 2];
			jc[k + 3] += g[k + 3];
		}
		for (; k < n; k++)
			jc[k] += g[k];
	}
}

/* The backward sweep over one block of n samples; val[i]: where register i's
 * values are (the kernel's registers, or the bound form's kept blocks).
 * Parameter j's derivatives go to col[j][k * stride] (NULL: not wanted): the
 * row-major Jacobian (stride np, zeroed before, each added to) or columns
 * (stride 1, not zeroed: a column's first write in the block is 0.0 + g, the
 * same bits as adding to zero, and wrote[j] is set; ir_diff.c zeroes those
 * left unwritten). */
ATTR static void CAT(backward, SFX)(const bk_form *f, const char *dep, size_t n, const double *const *val,
                                   double *adj, double *const *col, size_t stride, char *wrote, char *seen)
{
	/* The adjoints are not zeroed first (that pass was 40 % of this
	 * function): seen[i] says whether register i's adjoint has had its first
	 * update, which writes 0.0 + e (ACC above). Every parameter-dependent
	 * register but the result has a dependent user, processed before it; one
	 * that had none would read zeros, as before. */
	for (int i = 0; i < f->n; i++)
		seen[i] = 0;
	double *gout = adj + (size_t)f->out * BLOCK;
	for (size_t k = 0; k < BLOCK; k++)
		gout[k] = 1.0;
	seen[f->out] = 1;
	for (int i = f->n - 1; i >= 0; i--) {
		const bk_instr *c = &f->code[i];
		if (!dep[i])
			continue;
		double *g = adj + (size_t)i * BLOCK;
		if (!seen[i])
			for (size_t k = 0; k < BLOCK; k++)
				g[k] = 0.0;
		if (c->op == BK_OP_PARAM) {
			double *restrict jc = col[c->slot];
			if (!jc)
				continue;
			if (stride != 1) {
				for (size_t k = 0; k < n; k++)
					jc[k * stride] += g[k];
			} else {
				CAT(put_col, SFX)(jc, g, n, !wrote[c->slot]);
				wrote[c->slot] = 1;
			}
			continue;
		}
#define OPND(x) ((x) >= 0 ? val[x] : NULL)
#define ADJ(x) ((x) >= 0 && dep[x] ? adj + (size_t)(x) * BLOCK : NULL)
		const double *r = val[i], *A = OPND(c->a), *B = OPND(c->b), *C = OPND(c->c);
		double *ga = ADJ(c->a), *gb = ADJ(c->b), *gc = ADJ(c->c);
		/* in the order a, b, c: two operands may be one register (x*x) */
		if (ga) {
			CAT(backward_a, SFX)(c->op, g, r, A, B, C, ga, !seen[c->a]);
			seen[c->a] = 1;
		}
		if (gb) {
			CAT(backward_b, SFX)(c->op, g, r, A, B, C, gb, !seen[c->b]);
			seen[c->b] = 1;
		}
		if (gc) {
			CAT(backward_c, SFX)(c->op, g, r, A, B, C, gc, !seen[c->c]);
			seen[c->c] = 1;
		}
#undef OPND
#undef ADJ
	}
}
