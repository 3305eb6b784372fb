/*
 * quad.c — globally adaptive Gauss-Kronrod quadrature, the 7/15-point pair of
 * QUADPACK's QK15 (Piessens et al. 1983), for vector integrands.
 *
 * Why our own: libbrdf is pure C11 + libm (shared/DESIGN.md), the reference integrals
 * need a vector integrand (A and B share every evaluation) and a deterministic
 * evaluation order. The error estimate is the plain |K15 - G7| per interval, more
 * conservative than QUADPACK's scaled one; the tests check the rule is exact for
 * polynomials up to degree 22 and the integrals against independent quadratures.
 */
#include "quad.h"
#include "doors.h"

#include <math.h>

/* Kronrod abscissae (index 1, 3, 5 are the Gauss points, 7 is the centre) and
 * weights; Gauss weights for the points at index 1, 3, 5, 7. */
static const double xk[8] = {
	0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
	0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
	0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
	0.207784955007898467600689403773245, 0.0};
static const double wk[8] = {
	0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
	0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
	0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
	0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
static const double wg[4] = {
	0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
	0.381830050505118944950369775488975, 0.417959183673469387755102040816327};

typedef struct interval {
	double lo, hi, err;
	double val[BK_QUAD_MAXCOMP];
} interval;

/* One K15 panel; err is the largest |K15 - G7| over the components. */
static void qk15(bk_quad_fn f, void *ctx, int ncomp, interval *iv, long *evals)
{
	double c = 0.5 * (iv->lo + iv->hi), h = 0.5 * (iv->hi - iv->lo);
	double k[BK_QUAD_MAXCOMP] = {0}, g[BK_QUAD_MAXCOMP] = {0};
	double y[BK_QUAD_MAXCOMP], y2[BK_QUAD_MAXCOMP];

	f(c, ctx, y);
	/* all loops here run a fixed count (15 points, ncomp components) */
	for (int m = 0; m < ncomp; m++) {
		k[m] = wk[7] * y[m];
		g[m] = wg[3] * y[m];
	}
	for (int j = 0; j < 7; j++) {
		f(c - h * xk[j], ctx, y);
		f(c + h * xk[j], ctx, y2);
		for (int m = 0; m < ncomp; m++) {
			k[m] += wk[j] * (y[m] + y2[m]);
			if (j & 1)
				g[m] += wg[j / 2] * (y[m] + y2[m]);
		}
	}
	*evals += 15;
	iv->err = 0.0;
	for (int m = 0; m < ncomp; m++) {
		iv->val[m] = k[m] * h;
		iv->err = fmax(iv->err, fabs((k[m] - g[m]) * h));
	}
}

int bk_quad(bk_quad_fn f, void *ctx, const double *pts, int npts, int ncomp,
            double tol, double *out, bk_quad_stats *stats)
{
	interval iv[BK_QUAD_MAXINT];
	int n = 0;
	long evals = 0;
	BK_DOOR(pts, sizeof(double) * (size_t)(npts > 0 ? npts : 0), "pts");
	BK_DOOR(out, sizeof(double) * (size_t)(ncomp > 0 ? ncomp : 0), "out");
	BK_DOOR(stats, sizeof *stats, "stats");

	/* bounded by npts */
	for (int i = 0; i + 1 < npts && n < BK_QUAD_MAXINT; i++) {
		if (!(pts[i + 1] > pts[i]))
			continue; /* empty or reversed panel: nothing to integrate */
		iv[n].lo = pts[i];
		iv[n].hi = pts[i + 1];
		qk15(f, ctx, ncomp, &iv[n++], &evals);
	}
	int converged = 0;
	/* Bounded: every pass that does not break adds one interval (n++), and
	 * n == BK_QUAD_MAXINT breaks, so at most BK_QUAD_MAXINT passes. */
	for (;;) {
		double total = 0.0;
		int worst = 0;
		for (int i = 0; i < n; i++) {
			total += iv[i].err;
			if (iv[i].err > iv[worst].err)
				worst = i;
		}
		if (total <= tol) {
			converged = 1;
			break;
		}
		if (n == BK_QUAD_MAXINT)
			break;
		double mid = 0.5 * (iv[worst].lo + iv[worst].hi);
		if (!(mid > iv[worst].lo && mid < iv[worst].hi))
			break; /* interval at the resolution of doubles: cannot improve */
		iv[n] = iv[worst];
		iv[worst].hi = mid;
		iv[n].lo = mid;
		qk15(f, ctx, ncomp, &iv[worst], &evals);
		qk15(f, ctx, ncomp, &iv[n++], &evals);
	}
	double err = 0.0;
	for (int m = 0; m < ncomp; m++)
		out[m] = 0.0;
	for (int i = 0; i < n; i++) {
		err += iv[i].err;
		for (int m = 0; m < ncomp; m++)
			out[m] += iv[i].val[m];
	}
	if (stats) {
		stats->err += err;
		stats->evals += evals;
		if (!converged)
			stats->converged = 0;
	}
	return converged ? 0 : 1;
}
