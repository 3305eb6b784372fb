/*
 * ir_diff.c — derivatives of a form with respect to its parameters, reverse
 * mode over the same blocks: a forward sweep keeps every register's values, a
 * backward sweep carries adjoints from the result to the operands, and each
 * PARAM register's adjoint is its column of the Jacobian. One backward sweep
 * gives all parameters at once, whatever their number. Double precision only.
 *
 * At the kinks of min, max, clamp, saturate and abs the derivative of the
 * branch taken is used (the subgradient a fitter expects).
 */
#include "ir.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define BLOCK 128
#define LN2 0.693147180559945309417 /* ln 2 (M_LN2 is POSIX, not C11) */

static void forward(const bk_form *f, size_t n, const double *const *in, const double *par, double *v)
{
	for (int i = 0; i < f->n; i++) {
		const bk_instr *c = &f->code[i];
		double *r = v + (size_t)i * BLOCK;
		for (size_t k = 0; k < n; k++) {
			double a = c->a >= 0 ? v[(size_t)c->a * BLOCK + k] : 0.0;
			double b = c->b >= 0 ? v[(size_t)c->b * BLOCK + k] : 0.0;
			double cc = c->c >= 0 ? v[(size_t)c->c * BLOCK + k] : 0.0;
			switch (c->op) {
			case BK_OP_CONST: r[k] = c->k; break;
			case BK_OP_PARAM: r[k] = par[c->slot]; break;
			case BK_OP_INPUT: r[k] = in[c->slot][k]; break;
			default: r[k] = bk_ir_apply(c->op, a, b, cc); break;
			}
		}
	}
}

/* Adds g·∂R/∂operand to each operand's adjoint, for one sample. */
static void backward_one(const bk_instr *c, double r, double a, double b, double cc, double g,
                         double *ga, double *gb, double *gc)
{
	switch (c->op) {
	case BK_OP_ADD: *ga += g; *gb += g; break;
	case BK_OP_SUB: *ga += g; *gb -= g; break;
	case BK_OP_MUL: *ga += g * b; *gb += g * a; break;
	case BK_OP_DIV: *ga += g / b; *gb -= g * r / b; break;
	case BK_OP_NEG: *ga -= g; break;
	case BK_OP_MAD: *ga += g * b; *gb += g * a; *gc += g; break;
	case BK_OP_POW:
		*ga += g * b * pow(a, b - 1.0);
		if (a > 0.0)
			*gb += g * r * log(a);
		break;
	case BK_OP_SQRT: *ga += g * 0.5 / r; break;
	case BK_OP_RSQRT: *ga -= g * 0.5 * r / a; break;
	case BK_OP_RCP: *ga -= g * r * r; break;
	case BK_OP_EXP: *ga += g * r; break;
	case BK_OP_EXP2: *ga += g * r * LN2; break;
	case BK_OP_LOG: *ga += g / a; break;
	case BK_OP_LOG2: *ga += g / (a * LN2); break;
	case BK_OP_MIN: if (a <= b) *ga += g; else *gb += g; break;
	case BK_OP_MAX: if (a >= b) *ga += g; else *gb += g; break;
	case BK_OP_CLAMP:
		if (a < b) *gb += g;
		else if (a > cc) *gc += g;
		else *ga += g;
		break;
	case BK_OP_SATURATE: if (a > 0.0 && a < 1.0) *ga += g; break;
	case BK_OP_MIX: *ga += g * (1.0 - cc); *gb += g * cc; *gc += g * (b - a); break;
	case BK_OP_ABS: *ga += a < 0.0 ? -g : g; break;
	default: break;
	}
}

static void backward(const bk_form *f, size_t n, const double *v, double *adj, double *jac, int np)
{
	memset(adj, 0, sizeof(double) * (size_t)f->n * BLOCK);
	for (size_t k = 0; k < n; k++)
		adj[(size_t)f->out * BLOCK + k] = 1.0;
	static double sink; /* adjoint target for absent operands */
	for (int i = f->n - 1; i >= 0; i--) {
		const bk_instr *c = &f->code[i];
		const double *g = adj + (size_t)i * BLOCK;
		if (c->op == BK_OP_PARAM) {
			for (size_t k = 0; k < n; k++)
				jac[k * (size_t)np + (size_t)c->slot] += g[k];
			continue;
		}
		for (size_t k = 0; k < n; k++) {
			if (g[k] == 0.0)
				continue;
			double *ga = c->a >= 0 ? &adj[(size_t)c->a * BLOCK + k] : &sink;
			double *gb = c->b >= 0 ? &adj[(size_t)c->b * BLOCK + k] : &sink;
			double *gc = c->c >= 0 ? &adj[(size_t)c->c * BLOCK + k] : &sink;
			backward_one(c, v[(size_t)i * BLOCK + k], c->a >= 0 ? v[(size_t)c->a * BLOCK + k] : 0.0,
			             c->b >= 0 ? v[(size_t)c->b * BLOCK + k] : 0.0,
			             c->c >= 0 ? v[(size_t)c->c * BLOCK + k] : 0.0, g[k], ga, gb, gc);
		}
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
	if (!v || !adj) {
		free(v);
		free(adj);
		return -1;
	}
	int np = f->nparams;
	if (np)
		memset(jac, 0, sizeof(double) * n * (size_t)np);
	const double *blk[BK_IN_COUNT];
	for (size_t s = 0; s < n; s += BLOCK) {
		size_t m = n - s < BLOCK ? n - s : BLOCK;
		for (int i = 0; i < BK_IN_COUNT; i++)
			blk[i] = in[i] ? in[i] + s : NULL;
		forward(f, m, blk, params, v);
		for (size_t k = 0; k < m; k++)
			out[s + k] = v[(size_t)f->out * BLOCK + k];
		if (np)
			backward(f, m, v, adj, jac + s * (size_t)np, np);
	}
	free(v);
	free(adj);
	return 0;
}
