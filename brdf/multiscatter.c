/*
 * multiscatter.c — multiple-scattering energy compensation for GGX (Kulla &
 * Conty 2017, "Revisiting Physically Based Shading at Imageworks", SIGGRAPH
 * course; Turquin 2019, "Practical multiple scattering compensation for
 * microfacet models"). brdf.h states the conventions.
 *
 * E(μ) is the split sum with F = 1, so it comes from bk_dfg (one integrator for
 * the DFG and for E). E_avg integrates it over μ with the same adaptive
 * Gauss-Kronrod rule; the tests check both against an independent quadrature
 * of the full BRDF (tests/test_multiscatter.c).
 */
#include "brdf.h"
#include "quad.h"

#include <math.h>

int bk_ms_E(double NoV, double r, bk_smith m, double tol, double *E)
{
	double A, B;
	if (bk_dfg(NoV, r, m, tol, &A, &B, NULL))
		return -1;
	*E = A + B;
	return 0;
}

typedef struct eavg_ctx {
	double r, tol;
	bk_smith m;
	bk_quad_stats inner;
} eavg_ctx;

/* 2 E(μ) μ: bk_quad's nodes are interior, so μ > 0 here. */
static void eavg_fn(double mu, void *ctx, double *y)
{
	eavg_ctx *c = ctx;
	double A, B;
	bk_quad_stats st;
	bk_dfg(mu, c->r, c->m, c->tol, &A, &B, &st);
	c->inner.evals += st.evals;
	c->inner.converged &= st.converged;
	y[0] = 2.0 * (A + B) * mu;
}

/* Breakpoints: E(μ) bends where the mirror direction meets the lobe's width,
 * μ ~ a (the Smith terms' Λ(μ) ~ a/μ); points a·4^k below 1 let the adaptive
 * rule see that without searching. */
int bk_ms_E_avg(double r, bk_smith m, double tol, double *E_avg, bk_quad_stats *stats)
{
	if (!(r >= 0.0 && r <= 1.0) || (unsigned)m >= BK_SMITH_COUNT || !(tol > 0.0))
		return -1;
	if (r == 0.0) { /* a mirror with F = 1 reflects everything: E = 1 */
		*E_avg = 1.0;
		if (stats)
			*stats = (bk_quad_stats){0.0, 0, 1};
		return 0;
	}
	double a = r * r, pts[24];
	int n = 0;
	pts[n++] = 0.0;
	for (double b = a; b < 1.0 && n < 22; b *= 4.0)
		if (b > 1e-6)
			pts[n++] = b;
	pts[n++] = 1.0;
	/* the inner error enters weighted by 2μ <= 2 over a unit range: tol/4 each
	 * keeps its share at tol/2 */
	eavg_ctx c = {r, tol / 4.0, m, {0.0, 0, 1}};
	bk_quad_stats outer = {0.0, 0, 1};
	bk_quad(eavg_fn, &c, pts, n, 1, tol / 2.0, E_avg, &outer);
	if (stats) {
		stats->err = outer.err;
		stats->evals = c.inner.evals + outer.evals;
		stats->converged = outer.converged && c.inner.converged;
	}
	return 0;
}

double bk_ms_lobe(double E_o, double E_i, double E_avg)
{
	if (E_avg >= 1.0)
		return 0.0;
	return (1.0 - E_o) * (1.0 - E_i) / (BK_PI * (1.0 - E_avg));
}

double bk_ms_F_avg_schlick(double f0, double f90)
{
	return f0 + (f90 - f0) / 21.0;
}

double bk_ms_fresnel_scale(double F_avg, double E_avg)
{
	return F_avg * F_avg * E_avg / (1.0 - F_avg * (1.0 - E_avg));
}

double bk_ms_energy_compensation(double f0, double E)
{
	return 1.0 + f0 * (1.0 / E - 1.0);
}
