/*
 * fit_stats.c — what is reported about a fit: error metrics, the error over
 * the target's plane, standard errors and identifiability from the Jacobian
 * at the solution, and the checks for forms that are not finite.
 */
#include "fit.h"
#include "fit_int.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* fmax(acc, x) for an acc that is not NaN: x where x > acc, else acc (a NaN
 * x too, as fmax drops it). The same value as fmax here (every operand below
 * is a fabs, so no -0 against +0 either), inline: gcc calls libm's fmax at
 * the x86-64 baseline, and those calls were a third of the metrics' pass
 * (perf, a half search's polish). */
static inline double max_nn(double acc, double x)
{
	return x > acc ? x : acc;
}

/* Metrics of values v against the samples (fit.h): the part of
 * bk_fit_evaluate that does not need forms, shared with the LUT scoring. */
void bk_samples_metrics(const bk_samples *s, const double *v, const double *weight, bk_fit_metrics *m)
{
	memset(m, 0, sizeof *m);
	m->cost = m->albedo_max_abs = NAN;
	double se = 0, swe = 0, sw = 0, comp_se[2] = {0, 0}, ymax = 0;
	for (size_t i = 0; i < s->n; i++)
		ymax = max_nn(ymax, fabs(s->y[i]));
	for (size_t i = 0; i < s->n; i++) {
		double e = v[i] - s->y[i], w = weight ? weight[i] : s->w[i];
		if (!isfinite(e)) {
			m->nonfinite++;
			continue;
		}
		se += e * e;
		swe += w * e * e;
		sw += w;
		m->max_abs = max_nn(m->max_abs, fabs(e));
		if (fabs(s->y[i]) >= BK_REL_METRIC * ymax && s->y[i] != 0)
			m->max_rel = max_nn(m->max_rel, fabs(e / s->y[i]));
		int q = s->ncomp == 2 && i >= s->start[1];
		comp_se[q] += e * e;
		m->comp_max_abs[q] = max_nn(m->comp_max_abs[q], fabs(e));
	}
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
			m->comp_max_abs[2] = max_nn(m->comp_max_abs[2], fabs(e));
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
				m->albedo_max_abs = max_nn(m->albedo_max_abs, fabs(acc[k]));
			free(acc);
		}
	}
}

void bk_fit_evaluate(const bk_fit_spec *spec, const double *p, bk_fit_metrics *m)
{
	const bk_samples *s = spec->s;
	double *v = malloc(sizeof(double) * s->n);
	bk_fit_ctx c;
	if (!v || bk_fit_ctx_init(&c, spec) || bk_fit_eval_forms(spec, p, v)) {
		free(v);
		memset(m, 0, sizeof *m);
		m->cost = m->rmse = m->albedo_max_abs = NAN;
		return;
	}
	/* the weighted rmse uses the target's weight times the user's */
	bk_samples_metrics(s, v, c.base, m);
	double cost = 0;
	for (size_t i = 0; i < s->n; i++) {
		double ri = c.sw[i] * c.inv[i] * (v[i] - s->y[i]);
		if (isfinite(ri))
			cost += 0.5 * ri * ri;
	}
	m->cost = cost;
	bk_fit_ctx_free(&c);
	free(v);
}

/* The error per plane cell of values v (fit.h). */
void bk_samples_plane_error(const bk_samples *s, const double *v, double *cells)
{
	size_t nc = (size_t)s->plane_nx * s->plane_ny;
	int *count = calloc(nc ? nc : 1, sizeof *count);
	for (size_t k = 0; k < nc; k++)
		cells[k] = NAN;
	if (!count)
		return;
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
	free(count);
}

void bk_fit_plane_error(const bk_fit_spec *spec, const double *p, double *cells)
{
	const bk_samples *s = spec->s;
	double *v = malloc(sizeof(double) * s->n);
	size_t nc = (size_t)s->plane_nx * s->plane_ny;
	if (!v || bk_fit_eval_forms(spec, p, v)) {
		for (size_t k = 0; k < nc; k++)
			cells[k] = NAN;
		free(v);
		return;
	}
	bk_samples_plane_error(s, v, cells);
	free(v);
}

/* Standard errors from J at the solution: cov = σ² (JᵀJ)⁺ over the free
 * parameters, σ² = Σ r² / (m - free). JᵀJ is never formed: J is reduced to its
 * triangular factor R (Householder QR, a block of rows at a time, so JᵀJ =
 * RᵀR), the columns of R are scaled to unit norm (the norms of J's columns:
 * D = diag ||J_j||), and the scaled R = U Σ Vᵀ comes from one-sided Jacobi,
 * which gives even the smallest singular values to high relative accuracy
 * (Demmel & Veselić 1992) where the eigenvalues of a formed JᵀJ are lost below
 * eps of the largest. The eigenvalues of the scaled JᵀJ are λ_k = σ_k², its
 * eigenvectors V, and (JᵀJ)⁻¹ = D⁻¹ V Σ⁻² Vᵀ D⁻¹.
 * Directions with λ below 1e-10 of the largest are not identifiable (the data
 * do not pin them: 1e-10 is ~sqrt of double epsilon squared, where a formed
 * JᵀJ's own rounding begins); the parameters with weight >= 0.3 in such a
 * direction are named, and their standard errors are NaN. Directions below
 * 1/BK_FIT_COND_MAX mark their parameters collinear[] (fit.h). Scaling the
 * columns makes both tests independent of the parameters' units: unscaled, a
 * parameter whose column is 1e-5 of another's would read as unidentified
 * however well the data pin it. A zero column (a parameter no form reads) is
 * unidentified and makes the condition infinite. */
#define NULL_RATIO 1e-10
#define NULL_LOADING 0.3

/* Householder QR of the rows-by-n row-major matrix a in place; the
 * first n rows end as R (upper triangle; below it, zeros). */
static void householder(int rows, int n, double *a)
{
	for (int k = 0; k < n && k < rows; k++) {
		double norm = 0;
		for (int i = k; i < rows; i++)
			norm += a[(size_t)i * n + k] * a[(size_t)i * n + k];
		if (norm == 0)
			continue;
		norm = sqrt(norm);
		double alpha = a[(size_t)k * n + k] > 0 ? -norm : norm;
		double v0 = a[(size_t)k * n + k] - alpha; /* v = (v0, a[k+1.., k]); vᵀv = -2 alpha v0 */
		double beta = -alpha * v0;                /* vᵀv / 2 */
		for (int j = k + 1; j < n; j++) {
			double t = v0 * a[(size_t)k * n + j];
			for (int i = k + 1; i < rows; i++)
				t += a[(size_t)i * n + k] * a[(size_t)i * n + j];
			t /= beta;
			a[(size_t)k * n + j] -= t * v0;
			for (int i = k + 1; i < rows; i++)
				a[(size_t)i * n + j] -= t * a[(size_t)i * n + k];
		}
		a[(size_t)k * n + k] = alpha;
		for (int i = k + 1; i < rows; i++)
			a[(size_t)i * n + k] = 0;
	}
}

/* One-sided Jacobi SVD of the rows x n row-major b (Hestenes): rotates pairs
 * of columns until all are orthogonal to rounding; then the column norms are
 * the singular values and v (n x n, row-major, v[i * n + k]: component i of
 * vector k) holds the right singular vectors. */
static void jacobi_svd(int rows, int n, double *b, double *sigma, double *v)
{
	for (int i = 0; i < n * n; i++)
		v[i] = i % (n + 1) == 0;
	for (int sweep = 0; sweep < 60; sweep++) {
		int rotated = 0;
		for (int p = 0; p < n - 1; p++)
			for (int q = p + 1; q < n; q++) {
				double a = 0, d = 0, c = 0;
				for (int i = 0; i < rows; i++) {
					a += b[i * n + p] * b[i * n + p];
					d += b[i * n + q] * b[i * n + q];
					c += b[i * n + p] * b[i * n + q];
				}
				if (c == 0 || fabs(c) <= 1e-15 * sqrt(a * d))
					continue;
				rotated = 1;
				double zeta = (d - a) / (2 * c);
				double t = fabs(zeta) > 1e150 ? 0.5 / zeta
				                              : copysign(1.0, zeta) / (fabs(zeta) + sqrt(1 + zeta * zeta));
				double cs = 1 / sqrt(1 + t * t), sn = cs * t;
				for (int i = 0; i < rows; i++) {
					double x = b[i * n + p], y = b[i * n + q];
					b[i * n + p] = cs * x - sn * y;
					b[i * n + q] = sn * x + cs * y;
				}
				for (int i = 0; i < n; i++) {
					double x = v[i * n + p], y = v[i * n + q];
					v[i * n + p] = cs * x - sn * y;
					v[i * n + q] = sn * x + cs * y;
				}
			}
		if (!rotated)
			break;
	}
	for (int k = 0; k < n; k++) {
		double s = 0;
		for (int i = 0; i < rows; i++)
			s += b[i * n + k] * b[i * n + k];
		sigma[k] = sqrt(s);
	}
}

int bk_fit_stderr(bk_fit_ctx *c, bk_fit_result *res)
{
	const bk_fit_spec *spec = c->spec;
	int np = spec->np, nf = 0, col[BK_MAX_PARAMS];
	for (int j = 0; j < np; j++) {
		res->se[j] = NAN;
		res->unidentified[j] = res->collinear[j] = 0;
		if (!spec->hold[j] && spec->lower[j] != spec->upper[j])
			col[nf++] = j; /* held ones are not fitted: no standard error (NaN) */
	}
	res->condition = NAN;
	if (nf == 0)
		return 0;
	int maxsz = 0;
	for (int b = 0; b < c->nblocks; b++)
		maxsz = c->size[b] > maxsz ? c->size[b] : maxsz;
	/* a: R on top of the next block's rows (free columns only) */
	double *a = malloc(sizeof(double) * ((size_t)(nf + maxsz) * (size_t)nf + (size_t)maxsz * (size_t)(np + 1)));
	if (!a)
		return -1;
	double *r = a + (size_t)(nf + maxsz) * (size_t)nf, *J = r + maxsz, rss = 0;
	memset(a, 0, sizeof(double) * (size_t)nf * (size_t)nf);
	size_t m = 0;
	for (int b = 0; b < c->nblocks; b++) {
		int sz = c->size[b];
		if (bk_fit_residual_block(c, b, res->p, r, J))
			continue;
		for (int i = 0; i < sz; i++) {
			rss += r[i] * r[i];
			for (int k = 0; k < nf; k++)
				a[(size_t)(nf + i) * nf + k] = J[(size_t)i * np + col[k]];
		}
		householder(nf + sz, nf, a);
		m += (size_t)sz;
	}
	/* D: column norms of J (= those of R); scale R's columns to unit norm */
	double d[BK_MAX_PARAMS], sigma[BK_MAX_PARAMS], v[BK_MAX_PARAMS * BK_MAX_PARAMS], bm[BK_MAX_PARAMS * BK_MAX_PARAMS];
	int live[BK_MAX_PARAMS], nl = 0;
	for (int k = 0; k < nf; k++) {
		d[k] = 0;
		for (int i = 0; i <= k; i++)
			d[k] += a[(size_t)i * nf + k] * a[(size_t)i * nf + k];
		d[k] = sqrt(d[k]);
		if (d[k] > 0 && isfinite(d[k]))
			live[nl++] = k;
		else
			res->unidentified[col[k]] = res->collinear[col[k]] = 1; /* no form reads it */
	}
	/* all nf rows of R: a zero column leaves entries in its row of the others */
	for (int i = 0; i < nf; i++)
		for (int k = 0; k < nl; k++)
			bm[i * nl + k] = a[(size_t)i * nf + live[k]] / d[live[k]];
	free(a);
	if (m == 0)
		return -1;
	if (nl > 0)
		jacobi_svd(nf, nl, bm, sigma, v);
	double top = 0, bottom = INFINITY;
	int nnull = nf - nl; /* zero columns, then the directions below NULL_RATIO */
	for (int k = 0; k < nl; k++)
		top = fmax(top, sigma[k]), bottom = fmin(bottom, sigma[k]);
	for (int k = 0; k < nl; k++)
		nnull += !(sigma[k] * sigma[k] > NULL_RATIO * top * top);
	res->condition = nl < nf || bottom == 0 ? INFINITY : (top / bottom) * (top / bottom);
	double sigma2 = m > (size_t)nf ? rss / (double)(m - (size_t)nf) : NAN;
	for (int i = 0; i < nl; i++) {
		int j = col[live[i]];
		double var = 0;
		for (int k = 0; k < nl; k++) {
			double lam = sigma[k] * sigma[k], load = fabs(v[i * nl + k]);
			if (lam > NULL_RATIO * top * top)
				var += v[i * nl + k] * v[i * nl + k] / lam;
			else if (load >= NULL_LOADING)
				res->unidentified[j] = 1;
			if (lam * BK_FIT_COND_MAX < top * top && load >= NULL_LOADING)
				res->collinear[j] = 1;
		}
		res->collinear[j] |= res->unidentified[j];
		res->se[j] = res->unidentified[j] ? NAN : sqrt(sigma2 * var) / d[live[i]];
	}
	return nnull;
}

/* ---- first-order optimality (fit.h, BK_FIT_GRAD_TOL) ------------------------------ */

/* The per-residual robust loss exactly as the bridge applies it (solver.cc,
 * robustify): s = sign(r) sqrt(rho(r²)), ds = rho'(r²) |r| / sqrt(rho(r²)) dr,
 * so that 1/2 Σ s² is the cost Ceres minimises and Jᵀs its gradient. */
static void robustify(bk_loss loss, double c, int m, int np, double *r, double *jac)
{
	if (loss == BK_LOSS_NONE)
		return;
	for (int i = 0; i < m; i++) {
		double a = fabs(r[i]), u = (r[i] / c) * (r[i] / c), rho, drho;
		if (loss == BK_LOSS_HUBER) {
			if (a <= c)
				continue;
			rho = 2 * c * a - c * c, drho = c / a;
		} else if (loss == BK_LOSS_CAUCHY) {
			rho = c * c * bk_dlog1p(u), drho = 1 / (1 + u); /* solver.cc's */
		} else {
			double q = sqrt(1 + u);
			rho = 2 * r[i] * r[i] / (q + 1), drho = 1 / q;
		}
		if (drho == 1.0)
			continue;
		double root = sqrt(rho), k = drho * a / root;
		r[i] = copysign(root, r[i]);
		for (int j = 0; j < np; j++)
			jac[(size_t)i * np + j] *= k;
	}
}

/* Ceres' "sits on a bound" (solver.cc, kOnBound) */
#define ON_BOUND 1e-12

int bk_fit_optimality(bk_fit_ctx *c, const double *p, const int *held, bk_fit_result *res, int *flat)
{
	const bk_fit_spec *spec = c->spec;
	const bk_samples *s = spec->s;
	int np = spec->np, maxsz = 0;
	double g[BK_MAX_PARAMS] = {0}, cn[BK_MAX_PARAMS] = {0}, ss = 0, yy = 0;
	for (int j = 0; j < np; j++)
		res->grad[j] = res->grad_rel[j] = NAN;
	res->optimal = -1;
	for (int b = 0; b < c->nblocks; b++)
		maxsz = c->size[b] > maxsz ? c->size[b] : maxsz;
	double *r = malloc(sizeof(double) * (size_t)maxsz * (size_t)(np + 1));
	if (!r)
		return -2;
	double *J = r + maxsz;
	for (int b = 0; b < c->nblocks; b++) {
		int sz = c->size[b];
		size_t lo = c->lo[b];
		if (bk_fit_residual_block(c, b, p, r, J)) {
			free(r);
			return -2;
		}
		robustify(spec->opt.loss, spec->opt.loss_scale, sz, np, r, J);
		for (int i = 0; i < sz; i++) {
			/* the target in the units of s: robustified like a residual (a
			 * Huber scale of 1e-300 makes s ~ sqrt(2 c |r|) ~ 1e-151, and an
			 * unrobustified ||ŷ|| ~ 1 would make every gradient look small) */
			double yh = c->sw[lo + i] * c->inv[lo + i] * s->y[lo + i], zero = 0;
			robustify(spec->opt.loss, spec->opt.loss_scale, 1, 1, &yh, &zero);
			ss += r[i] * r[i];
			yy += yh * yh;
			for (int j = 0; j < np; j++) {
				double e = J[(size_t)i * np + j];
				g[j] += e * r[i];
				cn[j] += e * e;
			}
		}
	}
	free(r);
	int fixed[BK_MAX_PARAMS];
	double step = 0; /* ||J Δp|| <= Σ ||J_j|| |Δp_j| for |Δp_j| = |p_j|: see fit.h */
	for (int j = 0; j < np; j++) {
		fixed[j] = (held && held[j]) || spec->lower[j] == spec->upper[j];
		if (!fixed[j])
			step += sqrt(cn[j]) * fabs(p[j]);
	}
	double floor = spec->opt.parameter_tolerance * step + BK_FIT_EXACT * sqrt(yy);
	double scale = sqrt(ss) + floor / BK_FIT_GRAD_TOL;
	int worst = -1;
	res->optimal = 1;
	if (flat)
		*flat = 0;
	for (int j = 0; j < np; j++) {
		res->grad[j] = g[j];
		if (fixed[j])
			continue;
		if (flat && !(cn[j] > 0 && isfinite(cn[j])))
			(*flat)++;
		double lo = spec->lower[j], hi = spec->upper[j];
		int on_lower = isfinite(lo) && p[j] - lo <= ON_BOUND * fmax(1, fabs(lo));
		int on_upper = isfinite(hi) && hi - p[j] <= ON_BOUND * fmax(1, fabs(hi));
		if ((on_lower && g[j] >= 0) || (on_upper && g[j] <= 0))
			continue; /* the descent direction leaves the box: KKT holds */
		double den = sqrt(cn[j]) * scale;
		res->grad_rel[j] = g[j] == 0 ? 0.0 : den > 0 ? fabs(g[j]) / den : INFINITY;
		if (!(res->grad_rel[j] <= BK_FIT_GRAD_TOL)) {
			res->optimal = 0;
			if (worst < 0 || !(res->grad_rel[j] <= res->grad_rel[worst]))
				worst = j;
		}
	}
	return worst;
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
