/*
 * integrate.c — deterministic reference integrals over the light hemisphere:
 * directional albedo of any D·V·F and the split-sum A, B of the DFG LUT.
 *
 * Parametrisation. The integral runs over the half vector H = (θh, φ) with
 * dω_l = 4 VoH dω_h, so ∫ f NoL dω_l = ∫∫ D(θh) sinθh · 2 ∫_0^φmax V F NoL 4 VoH dφ dθh
 * (the integrand is even in φ). D depends on θh alone and is kept outside the
 * inner integral. L is below the horizon unless cos φ > c(θh) with
 *     c = -cosθv cos2θh / (sinθv sin2θh),
 * so the inner range is [0, acos c] and the outer one stops at
 * θ2 = (π/2 + θv)/2, past which no azimuth gives NoL > 0; at θ1 = (π/2 - θv)/2 the
 * inner range starts to shrink (a square-root kink), so θ1 is a breakpoint.
 * The lobe of D has width ~a in θh; breakpoints at (a/2)·8^k let the adaptive rule
 * find it without searching (GGX's tail ~a^2/θ^3 then needs few panels; the
 * spacing was chosen by measurement, make bench: denser grids cost time, not error).
 *
 * Error control: the outer rule gets tol/2; each inner integral tol/8. The inner
 * error enters the total weighted by ∫ D sinθ dθ · 2 = E_D[1/NoH]/π ≤ 2/π, so the
 * inner share stays below tol/4 (a loose bound; the outer rule also sees inner
 * noise, hence the margin).
 */
#include "brdf.h"
#include "dmath.h"
#include "doors.h"
#include "quad.h"
#include "smith.h"

#include <math.h>
#include <string.h>

/* What the inner integrand multiplies: either the registry's V and F, or the
 * split-sum pair for one Smith model. */
typedef struct hemi {
	double sin_v, cos_v; /* the view direction */
	double tol;
	int ncomp;           /* 1: albedo, 2: the (A, B) pair */
	const bk_term *D, *V, *F;
	bk_smith smith;
	bk_sample s;         /* material, and the current geometry */
	double cos_h, sin_h; /* current outer point */
	bk_quad_stats inner;
	/* the correlated Smith V's view half Λ(NoV) (smith.h): the same for every
	 * point of one integral, so formed once (integrate), not at each inner point */
	double sv;
} hemi;

/* bk_V_smith_ggx_correlated(NoV, NoL, a), its view half h->sv kept (smith.h) */
static inline double v_cor(const hemi *h, double NoL)
{
	return bk_smith_correlated(h->cos_v, NoL, h->sv, bk_smith_half(NoL, h->s.a * h->s.a));
}

/* Inner integrand in φ at the current θh. */
static void inner_fn(double phi, void *ctx, double *y)
{
	hemi *h = ctx;
	double VoH = h->sin_v * h->sin_h * bk_dcos(phi) + h->cos_v * h->cos_h;
	double NoL = 2.0 * VoH * h->cos_h - h->cos_v;
	if (NoL <= 0.0 || VoH <= 0.0) {
		y[0] = 0.0;
		if (h->ncomp == 2)
			y[1] = 0.0;
		return;
	}
	double jac = NoL * 4.0 * VoH; /* NoL · dω_l/dω_h */
	if (h->ncomp == 2) {
		double vis = (h->smith == BK_SMITH_CORRELATED ? v_cor(h, NoL) : bk_V_smith(h->smith, h->cos_v, NoL, h->s.a)) *
		             jac;
		double m = 1.0 - VoH, m2 = m * m;
		double fc = m2 * m2 * m;
		y[0] = vis * (1.0 - fc);
		y[1] = vis * fc;
		return;
	}
	h->s.NoL = NoL;
	h->s.LoH = VoH;
	y[0] = h->V->eval(&h->s) * h->F->eval(&h->s) * jac;
}

/* The azimuth range [0, φmax] at the current θh. */
static double phi_max(const hemi *h)
{
	double den = h->sin_v * 2.0 * h->sin_h * h->cos_h;
	double num = -h->cos_v * (h->cos_h * h->cos_h - h->sin_h * h->sin_h);
	if (den <= 0.0) /* V at the normal or H at the pole: NoL = cos 2θh alone */
		return num < 0.0 ? BK_PI : 0.0;
	double c = num / den;
	if (c <= -1.0)
		return BK_PI;
	if (c >= 1.0)
		return 0.0;
	return bk_dacos(c);
}

static void outer_fn(double theta, void *ctx, double *y)
{
	hemi *h = ctx;
	h->cos_h = bk_dcos(theta);
	h->sin_h = bk_dsin(theta);
	y[0] = 0.0;
	if (h->ncomp == 2)
		y[1] = 0.0;
	double pm = phi_max(h);
	if (pm <= 0.0)
		return;
	double d;
	if (h->ncomp == 2) {
		d = bk_D_ggx_sin2(h->sin_h * h->sin_h, h->cos_h, h->s.a);
	} else {
		h->s.NoH = h->cos_h;
		d = h->D->eval(&h->s);
	}
	double w = 2.0 * d * h->sin_h;
	if (w == 0.0)
		return;
	double pts[2] = {0.0, pm}, in[BK_QUAD_MAXCOMP];
	bk_quad(inner_fn, h, pts, 2, h->ncomp, h->tol / 8.0, in, &h->inner);
	for (int m = 0; m < h->ncomp; m++)
		y[m] = w * in[m];
}

/* Outer breakpoints: 0, (a/2)·q^k below θ2, θ1, θ2 — sorted, as bk_quad wants.
 * q = 8 (measured, see the top), widened when twelve steps of 8 from a/2 do not
 * reach θ2 (a < ~1e-10, only integrated at grazing NoV: see smooth_enough) so
 * that the lobe's tail never sits in one panel spanning many decades. The loop
 * runs at most 12 times whatever a is (at a = 0 a loop "until b >= θ2" would
 * never end: 0·8 = 0). */
#define OUTER_STEPS 12
static int outer_points(double a, double theta_v, double *pts)
{
	double t1 = 0.5 * (0.5 * BK_PI - theta_v), t2 = 0.5 * (0.5 * BK_PI + theta_v);
	/* x^(1/12) as sqrt(sqrt(cbrt(x))): glibc's pow differs in the last bit
	 * between CPUs, sqrt and cbrt do not (dmath.h) */
	double q = fmax(8.0, sqrt(sqrt(cbrt(t2 / (0.5 * a)))));
	int n = 0;
	pts[n++] = 0.0;
	int t1_done = 0;
	double b = 0.5 * a;
	for (int k = 0; k < OUTER_STEPS && b < t2; k++, b *= q) {
		if (!t1_done && t1 <= b) {
			if (t1 > pts[n - 1])
				pts[n++] = t1;
			t1_done = 1;
		}
		if (b > pts[n - 1])
			pts[n++] = b;
	}
	if (!t1_done && t1 > pts[n - 1])
		pts[n++] = t1;
	if (t2 > pts[n - 1])
		pts[n++] = t2;
	return n; /* at most 1 + OUTER_STEPS + 2 = 15 */
}

/* Whether a lobe of width ~a is below what doubles resolve, so that the
 * smooth limit (H = N, L = mirror(V), V and F evaluated at this a) is the
 * integral to rounding. The limit's error is the spread of H about N: the
 * integrand is smooth in H with curvature ~1/NoV² (the mirror direction's
 * distance from the horizon), GGX's tail makes E[θh²] ~ a² ln(1/a), and the
 * Smith terms move by ~a² tan²θv; so
 *     |∫ - limit| <= a² (1 + ln(1/a)) (1 + 1/NoV²)
 * (measured over NoV in [0.001, 1], r in [1e-5, 0.1]: at most 0.3 of it;
 * Beckmann and Blinn-Phong lobes have lighter tails than GGX). Below 2^-60 of
 * the result's scale (<= 1 here) the two agree to rounding: at NoV = 1 that is
 * a < ~4e-10, at NoV = 0.01 a < ~6e-12. Also when a^2 is not a normal double
 * (a < 1e-150, r < 1e-75): D = a²/(π d²) cannot be evaluated there at all, so
 * the limit is taken whatever NoV is (only NoV below ~1e-140 would still see
 * the lobe: no renderer's input). */
#define SMOOTH_EPS 0x1p-60
static int smooth_enough(double a, double NoV)
{
	if (a < 1e-150)
		return 1;
	/* ln(1/a) <= (1 - e) ln 2 for a = m 2^e, m in [0.5, 1): an upper bound
	 * from the exponent alone, the same on every CPU (glibc's log is not) */
	int e;
	frexp(a, &e);
	double bound = a * a * (1.0 + (1 - e) * 0.69314718055994530942) * (1.0 + 1.0 / (NoV * NoV));
	return bound <= SMOOTH_EPS;
}

/* Every loop is bounded: outer_points runs at most OUTER_STEPS times, bk_quad
 * at most BK_QUAD_MAXINT bisections (quad.c), so one integral costs at most
 * 15 BK_QUAD_MAXINT outer points, each an inner integral of at most
 * 15 BK_QUAD_MAXINT points. */
static int integrate(hemi *h, double NoV, double tol, double *out, bk_quad_stats *st)
{
	double pts[1 + OUTER_STEPS + 2];
	h->cos_v = NoV;
	h->sin_v = sqrt((1.0 - NoV) * (1.0 + NoV));
	h->tol = tol;
	h->s.NoV = NoV;
	h->sv = bk_smith_half(NoV, h->s.a * h->s.a);
	h->inner = (bk_quad_stats){0.0, 0, 1};
	int n = outer_points(h->s.a, bk_dacos(NoV), pts);
	bk_quad_stats outer = {0.0, 0, 1};
	bk_quad(outer_fn, h, pts, n, h->ncomp, tol / 2.0, out, &outer);
	if (st) {
		st->err = outer.err;
		st->evals = h->inner.evals;
		st->converged = outer.converged && h->inner.converged;
	}
	return 0;
}

static int bad_nov(double NoV) { return !(NoV > 0.0 && NoV <= 1.0); }
static int bad_r(double r) { return !(r >= 0.0 && r <= 1.0); }

int bk_dfg(double NoV, double r, bk_smith m, double tol, double *A, double *B,
           bk_quad_stats *stats)
{
	if (bad_nov(NoV) || bad_r(r) || (unsigned)m >= BK_SMITH_COUNT || !(tol > 0.0))
		return -1;
	BK_DOOR(A, sizeof *A, "A");
	BK_DOOR(B, sizeof *B, "B");
	BK_DOOR(stats, sizeof *stats, "stats");
	double a = r * r;
	if (r == 0.0 || smooth_enough(a, NoV)) {
		/* Smooth limit: D is a delta at H = N, L = mirror(V), so the integrand
		 * is V F NoL 4 VoH / NoH there. At r = 0 every Smith V is 1/(4 NoV^2)
		 * and that factor is exactly 1; below what doubles resolve, V is taken
		 * at this a (Schlick's k = a/2 moves V by ~a/NoV, far more than the
		 * lobe's width does). */
		double m1 = 1.0 - NoV, m2 = m1 * m1, fc = m2 * m2 * m1;
		double vis = r == 0.0 ? 1.0 : bk_V_smith(m, NoV, NoV, a) * 4.0 * NoV * NoV;
		*A = vis * (1.0 - fc);
		*B = vis * fc;
		if (stats)
			*stats = (bk_quad_stats){0.0, 0, 1};
		return 0;
	}
	hemi h = {0};
	h.ncomp = 2;
	h.smith = m;
	bk_sample_roughness(&h.s, r);
	double out[2];
	integrate(&h, NoV, tol, out, stats);
	*A = out[0];
	*B = out[1];
	return 0;
}

/* Whether D's lobe gathers at H = N as a -> 0, so that smooth_enough's limit
 * holds: not for the sheen distributions, whose mass goes to the horizon
 * (Charlie) or stays spread with a rim (velvet); they are integrated at every a. */
static int normal_peaked(const bk_term *D)
{
	return strcmp(D->name, "D_charlie") != 0 && strcmp(D->name, "D_ashikhmin") != 0;
}

int bk_albedo(const bk_term *D, const bk_term *V, const bk_term *F,
              const bk_sample *material, double NoV, double tol, double *out,
              bk_quad_stats *stats)
{
	BK_DOOR(D, sizeof *D, "D");
	BK_DOOR(V, sizeof *V, "V");
	BK_DOOR(F, sizeof *F, "F");
	BK_DOOR(material, sizeof *material, "material");
	BK_DOOR(out, sizeof *out, "out");
	BK_DOOR(stats, sizeof *stats, "stats");
	if (!D || !V || !F || D->role != BK_ROLE_D || V->role != BK_ROLE_V ||
	    F->role != BK_ROLE_F || bad_nov(NoV) || bad_r(material->r) || !(tol > 0.0))
		return -1;
	hemi h = {0};
	h.ncomp = 1;
	h.D = D;
	h.V = V;
	h.F = F;
	h.s = *material;
	bk_sample_roughness(&h.s, material->r);
	if (normal_peaked(D) && (material->r == 0.0 || smooth_enough(h.s.a, NoV))) {
		/* Smooth limit: H = N, L = mirror(V); ∫ = V F NoL · 4 VoH / NoH there
		 * (V and F at this a: see smooth_enough). */
		h.s.NoV = h.s.NoL = h.s.LoH = NoV;
		h.s.NoH = 1.0;
		*out = V->eval(&h.s) * F->eval(&h.s) * 4.0 * NoV * NoV;
		if (stats)
			*stats = (bk_quad_stats){0.0, 0, 1};
		return 0;
	}
	integrate(&h, NoV, tol, out, stats);
	return 0;
}
