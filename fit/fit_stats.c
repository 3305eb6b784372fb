/*
 * fit_stats.c — what is reported about a fit: error metrics, the error over
 * the target's plane, standard errors and identifiability from the Jacobian
 * at the solution, and the checks for forms that are not finite.
 */
#include "fit.h"
#include "fit_int.h"
#include "linalg.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int bk_fit_eval_forms(const bk_fit_spec *spec, const double *p, double *v)
{
	const bk_samples *s = spec->s;
	for (int q = 0; q < s->ncomp; q++) {
		size_t lo = s->start[q];
		const double *in[BK_IN_COUNT];
		for (int k = 0; k < BK_IN_COUNT; k++)
			in[k] = s->in[k] + lo;
		if (bk_form_eval(spec->form[q], BK_F64, s->start[q + 1] - lo, in, p, v + lo))
			return -1;
	}
	return 0;
}

void bk_fit_evaluate(const bk_fit_spec *spec, const double *p, bk_fit_metrics *m)
{
	const bk_samples *s = spec->s;
	memset(m, 0, sizeof *m);
	m->albedo_max_abs = NAN;
	double *v = malloc(sizeof(double) * s->n);
	bk_fit_ctx c;
	if (!v || bk_fit_ctx_init(&c, spec) || bk_fit_eval_forms(spec, p, v)) {
		free(v);
		m->cost = m->rmse = NAN;
		return;
	}
	double se = 0, swe = 0, sw = 0, cost = 0, comp_se[2] = {0, 0}, ymax = 0;
	for (size_t i = 0; i < s->n; i++)
		ymax = fmax(ymax, fabs(s->y[i]));
	for (size_t i = 0; i < s->n; i++) {
		double e = v[i] - s->y[i];
		if (!isfinite(e)) {
			m->nonfinite++;
			continue;
		}
		se += e * e;
		swe += c.base[i] * e * e;
		sw += c.base[i];
		double ri = c.sw[i] * c.inv[i] * e;
		cost += 0.5 * ri * ri;
		m->max_abs = fmax(m->max_abs, fabs(e));
		if (fabs(s->y[i]) >= BK_REL_METRIC * ymax && s->y[i] != 0)
			m->max_rel = fmax(m->max_rel, fabs(e / s->y[i]));
		int q = s->ncomp == 2 && i >= s->start[1];
		comp_se[q] += e * e;
		m->comp_max_abs[q] = fmax(m->comp_max_abs[q], fabs(e));
	}
	m->cost = cost;
	m->rmse = sqrt(se / (double)s->n);
	m->weighted_rmse = sw > 0 ? sqrt(swe / sw) : NAN;
	if (s->ncomp == 2) {
		size_t na = s->start[1], nb = s->n - na;
		m->comp_rmse[0] = sqrt(comp_se[0] / (double)na);
		m->comp_rmse[1] = sqrt(comp_se[1] / (double)nb);
		double sab = 0;
		for (size_t i = 0; i < na; i++) { /* A and B samples are the same cells in order */
			double e = (v[i] - s->y[i]) + (v[na + i] - s->y[na + i]);
			sab += e * e;
			m->comp_max_abs[2] = fmax(m->comp_max_abs[2], fabs(e));
		}
		m->comp_rmse[2] = sqrt(sab / (double)na);
	}
	int albedo = 0;
	for (size_t i = 0; i < s->n && !albedo; i++)
		albedo = s->measure[i] != 0.0;
	if (albedo) {
		size_t cells = (size_t)s->plane_nx * s->plane_ny;
		double *acc = calloc(cells, sizeof *acc);
		if (acc) {
			m->albedo_max_abs = 0;
			for (size_t i = 0; i < s->n; i++)
				acc[s->cell[i]] += s->measure[i] * (v[i] - s->y[i]);
			for (size_t k = 0; k < cells; k++)
				m->albedo_max_abs = fmax(m->albedo_max_abs, fabs(acc[k]));
			free(acc);
		}
	}
	bk_fit_ctx_free(&c);
	free(v);
}

void bk_fit_plane_error(const bk_fit_spec *spec, const double *p, double *cells)
{
	const bk_samples *s = spec->s;
	size_t nc = (size_t)s->plane_nx * s->plane_ny;
	double *v = malloc(sizeof(double) * s->n);
	int *count = calloc(nc, sizeof *count);
	for (size_t k = 0; k < nc; k++)
		cells[k] = NAN;
	if (!v || !count || bk_fit_eval_forms(spec, p, v)) {
		free(v);
		free(count);
		return;
	}
	int albedo = 0;
	for (size_t i = 0; i < s->n && !albedo; i++)
		albedo = s->measure[i] != 0.0;
	/* env split: A and B errors add (the albedo at f0 = 1); an env form in f0:
	 * the last f0's samples, which come last and overwrite the earlier ones */
	for (size_t i = 0; i < s->n; i++) {
		int k = s->cell[i];
		double e = v[i] - s->y[i];
		if (albedo)
			e *= s->measure[i];
		if (albedo || (s->ncomp == 2 && count[k]))
			cells[k] = (count[k] ? cells[k] : 0.0) + e;
		else
			cells[k] = e;
		count[k]++;
	}
	free(v);
	free(count);
}

/* Standard errors from J at the solution: cov = σ² (JᵀJ)⁺, σ² = Σ r² / (m - p).
 * Directions with eigenvalue below 1e-10 of the largest are not identifiable
 * (the data do not pin them: 1e-10 is ~sqrt of double epsilon squared, where
 * JᵀJ's own rounding begins); the parameters with weight >= 0.3 in such a
 * direction are named, and their standard errors are NaN. */
#define NULL_RATIO 1e-10
#define NULL_LOADING 0.3

void bk_fit_stderr(bk_fit_ctx *c, bk_fit_result *res)
{
	const bk_fit_spec *spec = c->spec;
	int np = spec->np;
	double jtj[BK_MAX_PARAMS * BK_MAX_PARAMS] = {0}, rss = 0;
	size_t m = 0;
	for (int b = 0; b < c->nblocks; b++) {
		int sz = c->size[b];
		double *r = malloc(sizeof(double) * (size_t)sz * (size_t)(np + 1));
		if (!r)
			return;
		double *J = r + sz;
		if (bk_fit_residual_block(c, b, res->p, r, J) == 0) {
			for (int i = 0; i < sz; i++) {
				rss += r[i] * r[i];
				for (int a = 0; a < np; a++)
					for (int d = 0; d < np; d++)
						jtj[a * np + d] += J[(size_t)i * np + a] * J[(size_t)i * np + d];
			}
			m += (size_t)sz;
		}
		free(r);
	}
	double val[BK_MAX_PARAMS], vec[BK_MAX_PARAMS * BK_MAX_PARAMS];
	for (int j = 0; j < np; j++)
		res->se[j] = NAN;
	if (m <= (size_t)np || bk_sym_eigen(np, jtj, val, vec))
		return;
	double sigma2 = rss / (double)(m - (size_t)np), top = val[np - 1];
	for (int j = 0; j < np; j++) {
		double var = 0;
		for (int k = 0; k < np; k++) {
			if (val[k] > NULL_RATIO * top)
				var += vec[j * np + k] * vec[j * np + k] / val[k];
			else if (fabs(vec[j * np + k]) >= NULL_LOADING)
				res->unidentified[j] = 1;
		}
		res->se[j] = res->unidentified[j] ? NAN : sqrt(sigma2 * var);
		if (spec->hold[j])
			res->se[j] = 0.0, res->unidentified[j] = 0;
	}
}

static void describe_sample(const bk_samples *s, size_t i, char *buf, size_t len)
{
	size_t k = 0;
	buf[0] = '\0';
	for (int in = 0; in < BK_IN_COUNT && k < len; in++)
		if ((s->provides >> in & 1) && in != BK_IN_A)
			k += (size_t)snprintf(buf + k, len - k, "%s%s = %.4g", k ? ", " : "", bk_input_name((bk_input)in),
			                      s->in[in][i]);
}

size_t bk_fit_nonfinite(const bk_fit_spec *spec, const double *p, char *where, size_t len)
{
	const bk_samples *s = spec->s;
	double *v = malloc(sizeof(double) * s->n);
	size_t bad = 0;
	if (!v || bk_fit_eval_forms(spec, p, v)) {
		free(v);
		snprintf(where, len, "evaluation failed");
		return s->n;
	}
	for (size_t i = 0; i < s->n; i++)
		if (!isfinite(v[i]) && isfinite(s->y[i]) && bad++ == 0)
			describe_sample(s, i, where, len);
	free(v);
	return bad;
}

/* The closed edges of the plane, where cell centres never go: a form with a
 * pole there (the talk's 1/LoH^2 at LoH = 0) has a least-squares fit ruled by
 * the samples next to it. 33 points per edge. */
int bk_fit_edge_check(const bk_fit_spec *spec, const double *p, char *where, size_t len)
{
	const bk_samples *s = spec->s;
	unsigned plane = 0;
	if (s->plane_x_input >= 0)
		plane |= 1u << s->plane_x_input;
	if (s->plane_y_input >= 0)
		plane |= 1u << s->plane_y_input;
	if (s->plane_y_input == BK_IN_R)
		plane |= 1u << BK_IN_A;
	enum { K = 33 };
	double in_v[BK_IN_COUNT][4 * K];
	const double *in[BK_IN_COUNT];
	for (int k = 0; k < BK_IN_COUNT; k++) {
		in[k] = in_v[k];
		for (int i = 0; i < 4 * K; i++)
			in_v[k][i] = s->in[k][0]; /* inputs off the plane keep the first sample's value */
	}
	for (int e = 0; e < 4; e++)
		for (int i = 0; i < K; i++) {
			double t = (double)i / (K - 1);
			double x = e < 2 ? (e == 0 ? s->plane_x0 : s->plane_x1) : s->plane_x0 + t * (s->plane_x1 - s->plane_x0);
			double y = e >= 2 ? (e == 2 ? s->plane_y0 : s->plane_y1) : s->plane_y0 + t * (s->plane_y1 - s->plane_y0);
			if (s->plane_x_input >= 0)
				in_v[s->plane_x_input][e * K + i] = x;
			if (s->plane_y_input >= 0)
				in_v[s->plane_y_input][e * K + i] = y;
			if (s->plane_y_input == BK_IN_R)
				in_v[BK_IN_A][e * K + i] = y * y;
		}
	int bad = 0;
	for (int q = 0; q < s->ncomp; q++) {
		if (bk_form_inputs(spec->form[q]) & ~(plane | 1u << BK_IN_F0))
			continue; /* the form reads inputs the plane does not fix */
		double v[4 * K];
		if (bk_form_eval(spec->form[q], BK_F64, 4 * K, in, p, v))
			continue;
		for (int i = 0; i < 4 * K; i++)
			if (!isfinite(v[i]) && ++bad) /* the last one: corners (r = 0) come first */
				snprintf(where, len, "%s = %.4g, %s = %.4g", s->plane_xname, in_v[s->plane_x_input < 0 ? 0 : s->plane_x_input][i],
				         s->plane_yname, s->plane_y_input < 0 ? NAN : in_v[s->plane_y_input][i]);
	}
	return bad;
}
