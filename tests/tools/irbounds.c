/*
 * irbounds.c — the negative controls of brdf/ir_bounds.h: linked as the
 * sanitized brdfkit links the IR's kernels (built without per-access
 * instrumentation, BK_IR_BOUNDS at their entry points), each case hands one
 * kernel entry point a caller's buffer that is one element short, or freed,
 * and must abort naming that buffer; the case "whole" gives every buffer its
 * full length and must return the closed form's values (tests/irbounds.sh).
 *
 * usage: irbounds whole|out|input|params|jac|cols|bind|freed|half
 */
#include "brdf.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define N 300 /* more than one block (BK_IR_BLOCK), and not a multiple of it */

int main(int argc, char **argv)
{
	if (argc != 2) {
		fprintf(stderr, "usage: irbounds whole|out|input|params|jac|cols|bind|freed|half\n");
		return 2;
	}
	const char *c = argv[1];
	bk_form_error err;
	bk_form *f = bk_form_parse("p0 * NoV + p1 * r", &err);
	if (!f) {
		fprintf(stderr, "irbounds: %s\n", err.message);
		return 2;
	}
	/* each buffer exactly as long as the call needs, or one element short */
	int s_in = !strcmp(c, "input") || !strcmp(c, "bind"), s_par = !strcmp(c, "params");
	int s_out = !strcmp(c, "out"), s_jac = !strcmp(c, "jac"), s_col = !strcmp(c, "cols");
	double *nov = malloc(sizeof(double) * (N - s_in)), *r = malloc(sizeof(double) * N);
	double *p = malloc(sizeof(double) * (2 - s_par)), *out = malloc(sizeof(double) * (N - s_out));
	double *jac = malloc(sizeof(double) * (2 * N - s_jac));
	double *c0 = malloc(sizeof(double) * N), *c1 = malloc(sizeof(double) * (N - s_col));
	for (int k = 0; k < N - s_in; k++)
		nov[k] = (k + 0.5) / N;
	for (int k = 0; k < N; k++)
		r[k] = 1 - (k + 0.5) / N;
	p[0] = 0.75;
	if (!s_par)
		p[1] = -0.25;
	const double *in[BK_IN_COUNT] = {0};
	in[BK_IN_NOV] = nov;
	in[BK_IN_R] = r;
	if (!strcmp(c, "freed"))
		free(r); /* r is read after this: a use after free */
	int bad = 0;
	if (!strcmp(c, "half")) {
		double y[N - 1] = {0}; /* y one short */
		bad = bk_form_eval_half_vs(f, N, in, p, y, out);
	} else if (!strcmp(c, "bind") || !strcmp(c, "cols")) {
		bk_form_bound *b = bk_form_bind(f, N, in);
		double *cols[2] = {c0, c1};
		bad = !b || bk_form_bound_eval_cols(b, p, out, cols);
		bk_form_bound_free(b);
	} else if (!strcmp(c, "jac")) {
		bad = bk_form_eval_diff(f, N, in, p, out, jac);
	} else {
		bad = bk_form_eval(f, BK_F64, N, in, p, out);
		if (!bad && !strcmp(c, "whole")) {
			bk_form_bound *b = bk_form_bind(f, N, in);
			double *cols[2] = {c0, c1};
			double *out2 = malloc(sizeof(double) * N);
			bad = !b || !out2 || bk_form_bound_eval_cols(b, p, out2, cols) || bk_form_eval_diff(f, N, in, p, out2, jac);
			bk_form_bound_free(b);
			/* the closed form: 0.75 NoV - 0.25 r, d/dp0 = NoV, d/dp1 = r */
			for (int k = 0; !bad && k < N; k++)
				if (fabs(out[k] - (0.75 * nov[k] - 0.25 * r[k])) > 1e-15 || out2[k] != out[k] ||
				    c0[k] != nov[k] || c1[k] != r[k] || jac[2 * k] != nov[k] || jac[2 * k + 1] != r[k])
					bad = 1;
			free(out2);
		}
	}
	printf("irbounds %s: %s\n", c, bad ? "failed" : "returned");
	bk_form_free(f);
	free(nov);
	if (strcmp(c, "freed"))
		free(r);
	free(p);
	free(out);
	free(jac);
	free(c0);
	free(c1);
	return bad;
}
