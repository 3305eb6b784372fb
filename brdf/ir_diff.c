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
 * operand at a time; the loops themselves are in ir_adjoint.h, built twice,
 * for the x86-64 baseline and AVX2, as ir_eval.c's kernels).
 *
 * A form bound to fixed samples (bk_form_bind, below) keeps what reads no
 * parameter between calls: a fit's tens of evaluations compute it once.
 *
 * At the kinks of min, max, clamp, saturate and abs the derivative of the
 * branch taken is used (the subgradient a fitter expects).
 */
#include "ir.h"
#include "doors.h"

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
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
#define HAVE_AVX2 1
#else
#define HAVE_AVX2 0
#endif
#define CAT2(a, b) a##b
#define CAT(a, b) CAT2(a, b)
#define SFX _gen
#define ATTR
#include "ir_adjoint.h"
#undef SFX
#undef ATTR
#if HAVE_AVX2
#define SFX _avx2
#define ATTR __attribute__((target("avx2")))
#include "ir_adjoint.h"
#undef SFX
#undef ATTR
#endif

/* The backward sweep (ir_adjoint.h) on the kernels' path (ir_eval.c). */
static void backward(const bk_form *f, const char *dep, size_t n, const double *const *val, double *adj,
                     double *const *col, size_t stride, char *wrote, char *seen)
{
#if HAVE_AVX2
	if (bk_ir_avx2()) {
		backward_avx2(f, dep, n, val, adj, col, stride, wrote, seen);
		return;
	}
#endif
	backward_gen(f, dep, n, val, adj, col, stride, wrote, seen);
}

/* The row-major Jacobian's block at sample s as columns of stride np. */
static void row_cols(double *jac, size_t s, int np, double **col)
{
	for (int j = 0; j < np; j++)
		col[j] = jac + s * (size_t)np + (size_t)j;
}

int bk_form_eval_diff(const bk_form *f, size_t n, const double *const in[BK_IN_COUNT],
                      const double *params, double *out, double *jac)
{
	for (int i = 0; i < BK_IN_COUNT; i++)
		if ((f->inputs >> i & 1) && !in[i])
			return -1;
	BK_DOOR_FORM(f, n, in, params);
	BK_DOOR(out, sizeof(double) * n, "out");
	BK_DOOR(jac, sizeof(double) * n * (size_t)f->nparams, "jac");
	double *v = malloc(sizeof(double) * (size_t)f->n * BLOCK);
	double *adj = malloc(sizeof(double) * (size_t)f->n * BLOCK);
	const double **val = malloc(sizeof *val * (size_t)f->n);
	char *dep = malloc(2 * (size_t)f->n), *seen = dep + f->n;
	if (!v || !adj || !val || !dep) {
		free(v);
		free(adj);
		free(val);
		free(dep);
		return -1;
	}
	dependence(f, dep);
	for (int i = 0; i < f->n; i++)
		val[i] = v + (size_t)i * BLOCK;
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
		if (np && dep[f->out]) {
			double *col[BK_MAX_PARAMS];
			char wrote[BK_MAX_PARAMS] = {0}; /* np 1: stride 1, the first write assigns */
			row_cols(jac, s, np, col);
			backward(f, dep, m, val, adj, col, (size_t)np, wrote, seen);
		}
	}
	free(v);
	free(adj);
	free(val);
	free(dep);
	return 0;
}

/* ---- a form bound to fixed samples ------------------------------------------
 *
 * A fit evaluates one form on the same samples tens of times, only the
 * parameters changing; whatever reads no parameter (log2(LoH), r*r, ...) comes
 * out the same every time, and in a search's candidates that is a good part of
 * the work (perf: libm's log2 alone was 16 % of the screening fits). Those of
 * its registers that a parameter-dependent instruction (or the result) reads
 * are kept, block by block, from the first call; later calls run only the
 * instructions that depend on a parameter and the leaves they read, over the
 * same kernel: the same operations on the same values, so the results are
 * bk_form_eval_diff's (and bk_form_eval's in f64) bit for bit
 * (tests/test_simd.c, suite bound). Inputs are read in place where a block is full. */

/* What is kept (blocks x registers x BLOCK doubles) at most: beyond it a fit
 * of millions of samples would keep more than it saves. */
#define BOUND_MAX_BYTES ((size_t)256 << 20)

struct bk_form_bound {
	const bk_form *f;
	size_t n, nblk;
	const double *in[BK_IN_COUNT];
	char *dep;          /* instruction depends on a parameter */
	char *live;         /* run at every call: dep, or a leaf that a dep instruction reads */
	char *seen;         /* the backward sweep's scratch (ir_adjoint.h) */
	int *keep;          /* its row among the kept registers, -1 if not kept */
	int nkeep;
	int filled;         /* kept holds the values (the first call made them) */
	double *kept;       /* nblk x nkeep x BLOCK */
	double *v, *adj;    /* the kernel's registers and their adjoints, f->n x BLOCK */
	const double **val; /* where register i's values are for the current block */
};

void bk_form_bound_free(bk_form_bound *b)
{
	if (!b)
		return;
	free(b->dep);
	free(b->live);
	free(b->seen);
	free(b->keep);
	free(b->kept);
	free(b->v);
	free(b->adj);
	free(b->val);
	free(b);
}

static int is_leaf(bk_op op)
{
	return op == BK_OP_CONST || op == BK_OP_PARAM || op == BK_OP_INPUT;
}

bk_form_bound *bk_form_bind(const bk_form *f, size_t n, const double *const in[BK_IN_COUNT])
{
	for (int i = 0; i < BK_IN_COUNT; i++)
		if ((f->inputs >> i & 1) && !in[i])
			return NULL;
	BK_DOOR_FORM(f, n, in, (const double *)NULL);
	bk_form_bound *b = calloc(1, sizeof *b);
	if (!b)
		return NULL;
	b->f = f;
	b->n = n;
	b->nblk = (n + BLOCK - 1) / BLOCK;
	for (int i = 0; i < BK_IN_COUNT; i++)
		b->in[i] = in[i];
	size_t nr = (size_t)f->n;
	b->dep = malloc(nr);
	b->live = calloc(nr, 1);
	b->seen = malloc(nr);
	b->keep = malloc(sizeof(int) * nr);
	b->v = malloc(sizeof(double) * nr * BLOCK);
	b->adj = malloc(sizeof(double) * nr * BLOCK);
	b->val = calloc(nr, sizeof *b->val);
	if (!b->dep || !b->live || !b->seen || !b->keep || !b->v || !b->adj || !b->val) {
		bk_form_bound_free(b);
		return NULL;
	}
	dependence(f, b->dep);
	for (int i = 0; i < f->n; i++)
		b->keep[i] = -1;
	/* mark what a parameter-dependent instruction reads, and the result */
	for (int i = 0; i <= f->n; i++) {
		int ops[3] = {-1, -1, -1};
		if (i == f->n)
			ops[0] = f->out;
		else if (b->dep[i] && !is_leaf(f->code[i].op))
			ops[0] = f->code[i].a, ops[1] = f->code[i].b, ops[2] = f->code[i].c;
		else
			continue;
		for (int j = 0; j < 3; j++) {
			int x = ops[j];
			if (x < 0 || b->dep[x])
				continue;
			if (is_leaf(f->code[x].op))
				b->live[x] = 1;
			else if (b->keep[x] < 0)
				b->keep[x] = b->nkeep++;
		}
	}
	for (int i = 0; i < f->n; i++)
		b->live[i] |= b->dep[i];
	if (b->nkeep && b->nblk && (size_t)b->nkeep > BOUND_MAX_BYTES / (sizeof(double) * BLOCK * b->nblk)) {
		bk_form_bound_free(b);
		return NULL;
	}
	if (b->nkeep && b->nblk && !(b->kept = malloc(sizeof(double) * BLOCK * b->nblk * (size_t)b->nkeep))) {
		bk_form_bound_free(b);
		return NULL;
	}
	return b;
}

/* Block blk (samples s..s+m) at the first call: the whole kernel, and the kept
 * registers copied out of it. */
static void bound_fill(bk_form_bound *b, size_t blk, size_t s, size_t m, const double *params)
{
	const bk_form *f = b->f;
	const double *in[BK_IN_COUNT];
	for (int i = 0; i < BK_IN_COUNT; i++)
		in[i] = b->in[i] ? b->in[i] + s : NULL;
	size_t ahead = b->n - s - m < BLOCK ? b->n - s - m : BLOCK;
	bk_ir_forward64(f, m, ahead, blk == 0, in, params, b->v);
	for (int i = 0; i < f->n; i++) {
		b->val[i] = b->v + (size_t)i * BLOCK;
		if (b->keep[i] >= 0)
			memcpy(b->kept + (blk * (size_t)b->nkeep + (size_t)b->keep[i]) * BLOCK, b->val[i],
			       sizeof(double) * BLOCK);
	}
}

/* Block blk at a later call: the live instructions, the kept ones read in
 * place; the result's instruction, when it is computed here over a whole
 * block, straight into dst (the caller's values), which saves their copy. */
static void bound_run(bk_form_bound *b, size_t blk, size_t s, size_t m, const double *params, double *dst)
{
	const bk_form *f = b->f;
	for (int i = 0; i < f->n; i++) {
		const bk_instr *c = &f->code[i];
		if (b->keep[i] >= 0) {
			b->val[i] = b->kept + (blk * (size_t)b->nkeep + (size_t)b->keep[i]) * BLOCK;
			continue;
		}
		if (!b->live[i])
			continue;
		double *r = b->v + (size_t)i * BLOCK;
		b->val[i] = r;
		size_t k;
		/* the value read once: r might alias c or params to the compiler,
		 * which would then load it at every k and not vectorise */
		double x;
		switch (c->op) {
		case BK_OP_CONST:
			x = c->k;
			if (blk == 0)
				for (k = 0; k < BLOCK; k++)
					r[k] = x;
			break;
		case BK_OP_PARAM:
			x = params[c->slot];
			if (blk == 0)
				for (k = 0; k < BLOCK; k++)
					r[k] = x;
			break;
		case BK_OP_INPUT:
			if (m == BLOCK) { /* a full block: read in place */
				b->val[i] = b->in[c->slot] + s;
				break;
			}
			for (k = 0; k < m; k++)
				r[k] = b->in[c->slot][s + k];
			for (; k < BLOCK; k++)
				r[k] = r[m - 1];
			break;
		default: {
			if (i == f->out && m == BLOCK)
				b->val[i] = r = dst;
			/* an operand the op does not read: any block that is not r */
			const double *none = b->v;
			bk_ir_op64(c, r, c->a >= 0 ? b->val[c->a] : none, c->b >= 0 ? b->val[c->b] : none,
			           c->c >= 0 ? b->val[c->c] : none);
		}
		}
	}
}

/* Values into out and the Jacobian's block at sample s: row-major into jac
 * (stride np, zeroed by the caller) or, jac NULL, into the columns cols (NULL:
 * none; each column NULL or n long). */
static void bound_eval(bk_form_bound *b, const double *params, double *out, double *jac, double *const *cols)
{
	const bk_form *f = b->f;
	int np = f->nparams;
	BK_DOOR_FORM(f, b->n, b->in, params);
	BK_DOOR(out, sizeof(double) * b->n, "out");
	BK_DOOR(jac, sizeof(double) * b->n * (size_t)np, "jac");
	for (int j = 0; cols && j < np; j++)
		BK_DOOR(cols[j], sizeof(double) * b->n, "a Jacobian column");
	for (size_t blk = 0, s = 0; s < b->n; blk++, s += BLOCK) {
		size_t m = b->n - s < BLOCK ? b->n - s : BLOCK;
		if (b->filled)
			bound_run(b, blk, s, m, params, out + s);
		else
			bound_fill(b, blk, s, m, params);
		if (b->val[f->out] != out + s)
			memcpy(out + s, b->val[f->out], sizeof(double) * m);
		if (!np || (!jac && !cols))
			continue;
		double *col[BK_MAX_PARAMS];
		char wrote[BK_MAX_PARAMS] = {0};
		if (jac)
			row_cols(jac, s, np, col);
		else
			for (int j = 0; j < np; j++)
				col[j] = cols[j] ? cols[j] + s : NULL;
		if (b->dep[f->out])
			backward(f, b->dep, m, b->val, b->adj, col, jac ? (size_t)np : 1, wrote, b->seen);
		for (int j = 0; !jac && j < np; j++) /* what no path from the result reached */
			if (col[j] && !wrote[j])
				memset(col[j], 0, sizeof(double) * m);
	}
	b->filled = 1;
}

int bk_form_bound_eval(bk_form_bound *b, const double *params, double *out, double *jac)
{
	if (jac && b->f->nparams)
		memset(jac, 0, sizeof(double) * b->n * (size_t)b->f->nparams);
	bound_eval(b, params, out, jac, NULL);
	return 0;
}

int bk_form_bound_eval_cols(bk_form_bound *b, const double *params, double *out, double *const *cols)
{
	bound_eval(b, params, out, NULL, cols);
	return 0;
}
