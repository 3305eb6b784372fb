/*
 * doors.c — the negative controls of brdf/doors.h: linked as the sanitized
 * brdfkit links the hot numeric files (built without per-access
 * instrumentation, BK_DOORS at their entry points), each case hands one
 * entry point a caller's buffer that is one element short, or freed, and
 * must abort naming that buffer; the case "whole" gives every buffer its
 * full length and must return the closed forms' values (tests/doors.sh).
 *
 * usage: doors CASE (the cases: USAGE below)
 */
#include "brdf.h"
#include "quad.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define N 300 /* more than one block (BK_IR_BLOCK), and not a multiple of it */
#define USAGE "usage: doors whole|out|input|params|jac|cols|bind|freed|half|quad_pts|quad_out|dfg_B|albedo_material\n"

static void square(double x, void *ctx, double *y)
{
	(void)ctx;
	y[0] = x * x;
	y[1] = 1;
}

/* The integrators' doors: 0 when the call returned (whole buffers: the
 * closed forms), nothing when a door aborted it. */
static int integrators(const char *c)
{
	int bad = 0;
	if (!strcmp(c, "quad_pts") || !strcmp(c, "quad_out") || !strcmp(c, "whole")) {
		double *pts = malloc(sizeof(double) * (3 - !strcmp(c, "quad_pts")));
		double *out = malloc(sizeof(double) * (2 - !strcmp(c, "quad_out")));
		pts[0] = 0, pts[1] = 0.5;
		if (strcmp(c, "quad_pts"))
			pts[2] = 1;
		/* int x^2 over [0, 1] = 1/3, int 1 = 1 (Gauss-Kronrod is exact on both) */
		bad = bk_quad(square, NULL, pts, 3, 2, 1e-12, out, NULL) || fabs(out[0] - 1.0 / 3) > 1e-15 ||
		      fabs(out[1] - 1) > 1e-15;
		free(pts);
		free(out);
	}
	if (!strcmp(c, "dfg_B") || !strcmp(c, "whole")) {
		double A, *B = malloc(strcmp(c, "dfg_B") ? sizeof(double) : 4);
		/* at r = 0 the split sum is 1 - (1 - NoV)^5 and (1 - NoV)^5 (brdf.h) */
		bad |= bk_dfg(0.5, 0, BK_SMITH_CORRELATED, 1e-8, &A, B, NULL) || fabs(A - (1 - 0.03125)) > 1e-15 ||
		       fabs(*B - 0.03125) > 1e-15;
		free(B);
	}
	if (!strcmp(c, "albedo_material") || !strcmp(c, "whole")) {
		const bk_term *D = bk_term_find("D_ggx"), *V = bk_term_find("V_smith_ggx_correlated"),
		              *F = bk_term_find("F_schlick");
		bk_sample *m = malloc(sizeof *m - (strcmp(c, "albedo_material") ? 0 : 8));
		double out;
		memset(m, 0, sizeof *m - (strcmp(c, "albedo_material") ? 0 : 8));
		m->r = 0.5;
		m->f0 = m->f90 = 1;
		double A, B;
		/* Schlick at f0 = f90 = 1 is F = 1: the albedo is A + B of the split sum (brdf.h) */
		bad |= !D || !V || !F || bk_albedo(D, V, F, m, 0.5, 1e-8, &out, NULL) ||
		       bk_dfg(0.5, 0.5, BK_SMITH_CORRELATED, 1e-8, &A, &B, NULL) || fabs(out - (A + B)) > 1e-6;
		free(m);
	}
	return bad;
}

int main(int argc, char **argv)
{
	if (argc != 2) {
		fputs(USAGE, stderr);
		return 2;
	}
	const char *c = argv[1];
	if (!strncmp(c, "quad_", 5) || !strncmp(c, "dfg_", 4) || !strncmp(c, "albedo_", 7)) {
		int bad = integrators(c);
		printf("doors %s: %s\n", c, bad ? "failed" : "returned");
		return bad;
	}
	bk_form_error err;
	bk_form *f = bk_form_parse("p0 * NoV + p1 * r", &err);
	if (!f) {
		fprintf(stderr, "doors: %s\n", err.message);
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
	if (!strcmp(c, "whole"))
		bad |= integrators(c);
	printf("doors %s: %s\n", c, bad ? "failed" : "returned");
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
