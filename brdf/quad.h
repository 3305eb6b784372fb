/*
 * quad.h — adaptive Gauss-Kronrod quadrature (internal to libbrdf).
 */
#ifndef BRDF_QUAD_H
#define BRDF_QUAD_H

#include "brdf.h"

#define BK_QUAD_MAXCOMP 2  /* components of a vector integrand */
/* Intervals before giving up (converged = 0): 400 panels are 6000 evaluations;
 * the reference integrals at tol 1e-10 need at most 32 panels over NoV in
 * [0.01, 1] and r in [0.004, 1] (measured), so the budget only stops integrands
 * that never settle (a singularity the breakpoints miss, or rounding noise above
 * the tolerance), and the caller is told. */
#define BK_QUAD_MAXINT 400

/* Writes ncomp values of the integrand at x into y. */
typedef void (*bk_quad_fn)(double x, void *ctx, double *y);

/* ∫ f over [pts[0], pts[npts-1]], split first at the sorted breakpoints pts,
 * then bisecting the interval with the largest error until the summed error
 * estimate is at most tol (absolute, maximum over components). Adds to stats
 * (which may be NULL). Returns 0 if converged, 1 if the interval budget ran out
 * (out still holds the best estimate). */
int bk_quad(bk_quad_fn f, void *ctx, const double *pts, int npts, int ncomp,
            double tol, double *out, bk_quad_stats *stats);

#endif
