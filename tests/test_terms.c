/*
 * test_terms.c — the exact terms of libbrdf (D, Smith Λ/G1/V, Fresnel, diffuse),
 * the published approximations at their limits, the registry and GGX sampling,
 * each against a fact that does not come from the code under test:
 *
 *   - normalisation and the Smith masking identity by quadratures written here
 *     (composite Gauss-Legendre with breakpoints that resolve the peaks and kinks;
 *     the library's bk_quad / bk_albedo are NOT used);
 *   - textbook closed forms (Λ_GGX in long double, the complex-index Fresnel
 *     equations with C99 <complex.h>, the Oren-Nayar angular form, the reference
 *     formulas of shared/references/approximations.md written out again);
 *   - published constants (0.04 for n = 1.5, SG Schlick's 0.03395 at LoH = 0.5,
 *     pbrt-v3's rational Beckmann Λ within Mitsuba's stated 0.35 %);
 *   - physical identities (Helmholtz reciprocity, Brewster's angle, total internal
 *     reflection, Stokes reciprocity of the dielectric reflectance);
 *   - a χ² test of the GGX sampler against the analytic CDF of D·NoH.
 *
 * Numbers quoted as "mpmath" were computed offline at 30 significant digits on a
 * 20001-point grid; they only justify bounds, never serve as an expected value.
 */
#include "brdf.h"

#include <criterion/criterion.h>

#include <complex.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846
#define HALF_PI (0.5 * PI)

/* ---- assertion helpers ----------------------------------------------------- */

/* |got - want| <= rel |want| + abs_floor, with the values and the context printed
 * on failure. NaN never passes. */
static void check_close(double got, double want, double rel, double abs_floor,
                        const char *fmt, ...)
{
	double err = fabs(got - want);
	if (err <= rel * fabs(want) + abs_floor)
		return;
	char ctx[256];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(ctx, sizeof ctx, fmt, ap);
	va_end(ap);
	cr_assert_fail("%s: got %.17g, want %.17g (abs err %.3g, rel err %.3g; allowed rel %.3g + abs %.3g)",
	               ctx, got, want, err, want != 0.0 ? err / fabs(want) : INFINITY, rel, abs_floor);
}

/* ---- Gauss-Legendre quadrature, written here --------------------------------
 * 20-point rule on [-1, 1], nodes by Newton's method on the Legendre recurrence;
 * composite over sorted breakpoints. The self-test pins it on closed forms. */

enum { GLN = 20, MAXB = 512 };
static double gl_x[GLN], gl_w[GLN];

static void gl_init(void)
{
	static int ready;
	if (ready)
		return;
	for (int i = 0; i < GLN; i++) {
		double x = cos(PI * (i + 0.75) / (GLN + 0.5)), dp = 0.0;
		for (int it = 0; it < 12; it++) { /* quadratic convergence: 12 is plenty */
			double p0 = 1.0, p1 = x;
			for (int k = 2; k <= GLN; k++) {
				double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
				p0 = p1;
				p1 = p2;
			}
			dp = GLN * (x * p1 - p0) / (x * x - 1.0);
			x -= p1 / dp;
		}
		double p0 = 1.0, p1 = x; /* derivative at the converged node, for the weight */
		for (int k = 2; k <= GLN; k++) {
			double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
			p0 = p1;
			p1 = p2;
		}
		dp = GLN * (x * p1 - p0) / (x * x - 1.0);
		gl_x[i] = x;
		gl_w[i] = 2.0 / ((1.0 - x * x) * dp * dp);
	}
	ready = 1;
}

typedef double (*fn1)(double x, void *ctx);

static double gl_panel(fn1 f, void *ctx, double lo, double hi)
{
	double c = 0.5 * (lo + hi), h = 0.5 * (hi - lo), s = 0.0;
	for (int i = 0; i < GLN; i++)
		s += gl_w[i] * f(c + h * gl_x[i], ctx);
	return s * h;
}

typedef struct breaks {
	double v[MAXB];
	int n;
	double lo, hi;
} breaks;

static void brk_init(breaks *b, double lo, double hi)
{
	b->n = 0;
	b->lo = lo;
	b->hi = hi;
	b->v[b->n++] = lo;
	b->v[b->n++] = hi;
}

static void brk_add(breaks *b, double x)
{
	if (x > b->lo && x < b->hi) {
		cr_assert(b->n < MAXB, "test quadrature: too many breakpoints");
		b->v[b->n++] = x;
	}
}

/* x0 and x0 ± h0 2^k inside (lo, hi): panels that shrink geometrically towards a
 * peak or a kink at x0, so each panel sees a smooth integrand on its own scale. */
static void brk_geometric(breaks *b, double x0, double h0)
{
	brk_add(b, x0);
	for (double h = h0; x0 - h > b->lo || x0 + h < b->hi; h *= 2.0) {
		brk_add(b, x0 - h);
		brk_add(b, x0 + h);
	}
}

static int cmp_double(const void *p, const void *q)
{
	double x = *(const double *)p, y = *(const double *)q;
	return (x > y) - (x < y);
}

static double integrate(fn1 f, void *ctx, breaks *b)
{
	gl_init();
	qsort(b->v, (size_t)b->n, sizeof b->v[0], cmp_double);
	double s = 0.0;
	for (int i = 0; i + 1 < b->n; i++)
		if (b->v[i + 1] > b->v[i])
			s += gl_panel(f, ctx, b->v[i], b->v[i + 1]);
	return s;
}

static double f_monomial(double x, void *ctx) { return pow(x, *(int *)ctx); }
static double f_sin(double x, void *ctx) { (void)ctx; return sin(x); }
static double f_peak(double x, void *ctx)
{
	double a = *(double *)ctx, d = x * x + a * a;
	return 2.0 * a * a * x / (d * d);
}

/* The test's own quadrature against closed forms: the 20-point rule integrates
 * x^k exactly for k <= 39 (pins every node and weight), and the composite rule
 * resolves a peak of width 1e-4 (the shape of GGX D·NoH·sinθ). */
Test(test_quadrature, closed_forms)
{
	gl_init();
	for (int k = 0; k < 2 * GLN; k++) {
		double s = gl_panel(f_monomial, &k, 0.0, 1.0);
		/* nodes and weights from the recurrence carry ~1e-15 relative error */
		check_close(s, 1.0 / (k + 1), 1e-14, 0.0, "GL20 x^%d on [0,1]", k);
	}
	breaks b;
	brk_init(&b, 0.0, HALF_PI);
	for (int i = 1; i < 8; i++)
		brk_add(&b, i * HALF_PI / 8);
	/* smooth integrand, 8 panels of a degree-39 rule: rounding only */
	check_close(integrate(f_sin, NULL, &b), 1.0, 1e-14, 0.0, "∫ sin over [0, π/2]");
	double a = 1e-4;
	brk_init(&b, 0.0, 1.0);
	brk_geometric(&b, 0.0, a / 16);
	/* ∫_0^1 2a²x/(x²+a²)² dx = 1 - a²/(1+a²); geometric panels, rounding only */
	check_close(integrate(f_peak, &a, &b), 1.0 - a * a / (1.0 + a * a), 1e-13, 0.0, "Lorentzian peak");
}

/* ---- own vectors ------------------------------------------------------------ */

typedef struct geom {
	double v[3], l[3], h[3];
	double NoV, NoL, NoH, LoH, VoH, VoL;
} geom;

static double dot3(const double *x, const double *y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; }

/* V in the xz-plane at polar angle tv, L at polar angle tl and azimuth phi. */
static geom make_geom(double tv, double tl, double phi)
{
	geom g;
	g.v[0] = sin(tv); g.v[1] = 0.0; g.v[2] = cos(tv);
	g.l[0] = sin(tl) * cos(phi); g.l[1] = sin(tl) * sin(phi); g.l[2] = cos(tl);
	double s[3] = {g.v[0] + g.l[0], g.v[1] + g.l[1], g.v[2] + g.l[2]};
	double len = sqrt(dot3(s, s));
	for (int i = 0; i < 3; i++)
		g.h[i] = s[i] / len;
	g.NoV = g.v[2];
	g.NoL = g.l[2];
	g.NoH = g.h[2];
	g.LoH = dot3(g.l, g.h);
	g.VoH = dot3(g.v, g.h);
	g.VoL = dot3(g.v, g.l);
	return g;
}

static bk_sample make_sample(double tv, double tl, double phi, double r)
{
	bk_sample s;
	memset(&s, 0, sizeof s);
	bk_sample_roughness(&s, r);
	bk_sample_geometry(&s, tv, tl, phi);
	s.f0 = 0.04;
	s.f90 = 1.0;
	s.eta = 1.5;
	s.k = 0.0;
	return s;
}

/* Angles used for geometry grids: from near-normal to 80° (0.1 to 1.4 rad). */
static const double thetas[] = {0.0, 0.1, 0.5, 1.0, 1.4};
static const double phis[] = {0.0, 1.0, 2.5, PI};
#define NELEM(x) (sizeof(x) / sizeof((x)[0]))

/* bk_sample_geometry against unit vectors built here: cosines of the polar
 * angles, of the half vector, and LoH = VoH. */
Test(geometry, sample_geometry_matches_own_vectors)
{
	for (size_t i = 0; i < NELEM(thetas); i++)
		for (size_t j = 0; j < NELEM(thetas); j++)
			for (size_t k = 0; k < NELEM(phis); k++) {
				double tv = thetas[i], tl = thetas[j], phi = phis[k];
				geom g = make_geom(tv, tl, phi);
				bk_sample s = make_sample(tv, tl, phi, 0.5);
				/* unit vectors, |V+L| >= 0.33 on this grid: a few roundings of O(1) numbers */
				const double tol = 1e-14;
				check_close(s.NoV, g.NoV, 0.0, tol, "NoV tv=%g tl=%g phi=%g", tv, tl, phi);
				check_close(s.NoL, g.NoL, 0.0, tol, "NoL tv=%g tl=%g phi=%g", tv, tl, phi);
				check_close(s.NoH, g.NoH, 0.0, tol, "NoH tv=%g tl=%g phi=%g", tv, tl, phi);
				check_close(s.LoH, g.LoH, 0.0, tol, "LoH tv=%g tl=%g phi=%g", tv, tl, phi);
				check_close(s.LoH, g.VoH, 0.0, tol, "VoH tv=%g tl=%g phi=%g", tv, tl, phi);
				/* the roughness helper: a = r^2 */
				check_close(s.a, 0.25, 0.0, 0.0, "a from r = 0.5");
			}
}

/* ---- 1. NDF normalisation: ∫ D(h) NoH dω_h = 1 -------------------------------- */

typedef struct ndf_ctx {
	double (*D)(double, double);
	double a;
} ndf_ctx;

static double ndf_theta(double t, void *p)
{
	const ndf_ctx *c = p;
	double ct = cos(t);
	return 2.0 * PI * c->D(ct, c->a) * ct * sin(t);
}

/* ∫_0^θmax 2π D(cosθ) cosθ sinθ dθ, with geometric panels on the peak's scale a
 * at θ = 0 and towards π/2 (Beckmann's exp(-tan²θ/a²) is flat but not analytic
 * there). */
static double ndf_integral(double (*D)(double, double), double a, double theta_max)
{
	ndf_ctx c = {D, a};
	breaks b;
	brk_init(&b, 0.0, theta_max);
	brk_geometric(&b, 0.0, a / 16.0);
	brk_geometric(&b, theta_max, 1e-6);
	return integrate(ndf_theta, &c, &b);
}

static const double ndf_r[] = {0.05, 0.2, 0.5, 1.0};

Test(ndf, normalised_ggx_beckmann_blinn_phong)
{
	struct { const char *name; double (*D)(double, double); } ds[] = {
		{"D_ggx", bk_D_ggx}, {"D_beckmann", bk_D_beckmann}, {"D_blinn_phong", bk_D_blinn_phong}};
	for (size_t i = 0; i < NELEM(ds); i++)
		for (size_t j = 0; j < NELEM(ndf_r); j++) {
			double a = ndf_r[j] * ndf_r[j];
			double s = ndf_integral(ds[i].D, a, HALF_PI);
			/* analytic integrand on geometric panels (the self-test reaches 1e-13);
			 * 1e-10 leaves room for the rounding of NoH near the r = 0.05 peak */
			check_close(s, 1.0, 0.0, 1e-10, "%s r=%g: ∫ D NoH dω", ds[i].name, ndf_r[j]);
		}
}

/* Lagarde's SG Blinn-Phong keeps the (n+2)/(2π) factor of NoH^n while its lobe
 * exp(λ(NoH - 1)), λ = n + 0.775, integrates to (n+2)(1/λ - (1 - e^-λ)/λ²). */
Test(ndf, blinn_phong_sg_closed_form)
{
	for (size_t j = 0; j < NELEM(ndf_r); j++) {
		double a = ndf_r[j] * ndf_r[j];
		double n = 2.0 / (a * a) - 2.0, lam = n + 0.775;
		double want = (n + 2.0) * (1.0 / lam + expm1(-lam) / (lam * lam));
		double s = ndf_integral(bk_D_blinn_phong_sg, a, HALF_PI);
		/* as for the exact NDFs */
		check_close(s, want, 1e-10, 0.0, "D_blinn_phong_sg r=%g", ndf_r[j]);
		/* and it is not normalised (≈ 1 + 0.225/n for large n, 0.785 at n = 0): the
		 * check above would catch a lobe that integrated to 1 */
		cr_assert(fabs(want - 1.0) > 1e-7, "D_blinn_phong_sg r=%g: closed form %.17g too close to 1", ndf_r[j], want);
	}
}

/* The closed-form CDF of GGX D·NoH, u(θ) = tan²θ/(a² + tan²θ), which the sampling
 * test relies on, is the integral of bk_D_ggx itself. */
Test(ndf, ggx_cdf_closed_form)
{
	const double as[] = {0.0025, 0.09, 0.49, 1.0};
	for (size_t i = 0; i < NELEM(as); i++) {
		double a = as[i];
		const double ts[] = {0.5 * a, a, 3.0 * a, 0.5, 1.2};
		for (size_t j = 0; j < NELEM(ts); j++) {
			if (ts[j] >= HALF_PI)
				continue;
			double t2 = tan(ts[j]) * tan(ts[j]);
			/* geometric panels, analytic integrand: rounding and peak-NoH rounding */
			check_close(ndf_integral(bk_D_ggx, a, ts[j]), t2 / (a * a + t2), 1e-10, 0.0,
			            "GGX CDF a=%g θ=%g", a, ts[j]);
		}
	}
}

/* bk_D_ggx keeps full relative precision for the NoH it is given, even at the
 * peak of a smooth surface where 1 - NoH² ~ a² (the claim of its comment): against
 * a²/(π (1 - NoH² + NoH² a²)²) in long double, where 1 - NoH² = (1 - NoH)(1 + NoH)
 * is exact before the final rounding (1 - NoH by Sterbenz, 1 + NoH in 64 bits). */
Test(ndf, ggx_peak_precision_for_the_given_NoH)
{
	const double as[] = {1e-4, 0.0025, 0.04};
	for (size_t i = 0; i < NELEM(as); i++)
		for (int k = 0; k <= 40; k++) {
			double a = as[i], NoH = cos(a * 0.25 * k); /* across the peak, 0 to 10 a */
			long double c = NoH, al = a, s2 = (1.0L - c) * (1.0L + c);
			long double d = s2 + c * c * al * al;
			double want = (double)(al * al / (3.14159265358979323846264338327950288L * d * d));
			/* a few roundings of O(1) relative size each, squared: 1e-13 (a form with
			 * 1 - NoH*NoH would be off by ~1e-16/a², 1e-8 at a = 1e-4) */
			check_close(bk_D_ggx(NoH, a), want, 1e-13, 0.0, "D_ggx a=%g NoH=%.17g", a, NoH);
		}
}

/* bk_D_ggx_sin2 takes sin²θh from a caller that knows the angle, so it keeps full
 * precision where 1 - NoH² cannot (r < 0.02): against the closed form
 * a²/(π (sin²θ + cos²θ a²)²) in long double from the angle, and normalised. */
static double ndf_sin2_theta(double t, void *p)
{
	double a = *(double *)p, st = sin(t), ct = cos(t);
	return 2.0 * PI * bk_D_ggx_sin2(st * st, ct, a) * ct * st;
}

Test(ndf, ggx_sin2_full_precision_for_tiny_roughness)
{
	const double rs[] = {0.001, 0.003, 0.01, 0.3};
	for (size_t i = 0; i < NELEM(rs); i++) {
		double a = rs[i] * rs[i];
		for (int k = 0; k <= 40; k++) {
			double t = a * 0.25 * k; /* across the peak, 0 to 10 a */
			long double s = sinl(t), c = cosl(t), al = a;
			long double d = s * s + c * c * al * al;
			double want = (double)(al * al / (3.14159265358979323846264338327950288L * d * d));
			double st = sin(t);
			/* inputs rounded to ~ε each, squared into D: 1e-13 */
			check_close(bk_D_ggx_sin2(st * st, cos(t), a), want, 1e-13, 0.0, "D_ggx_sin2 r=%g θ=%g", rs[i], t);
		}
		breaks b;
		brk_init(&b, 0.0, HALF_PI);
		brk_geometric(&b, 0.0, a / 16.0);
		/* as the other NDFs, now without NoH's rounding at the peak */
		check_close(integrate(ndf_sin2_theta, &a, &b), 1.0, 0.0, 1e-12, "∫ D_ggx_sin2 NoH dω r=%g", rs[i]);
		/* and the NoH entry point is the same function where 1 - NoH² is exact enough */
		for (int k = 1; k <= 10; k++) {
			double NoH = 0.1 * k;
			check_close(bk_D_ggx(NoH, 0.25), bk_D_ggx_sin2((1.0 - NoH) * (1.0 + NoH), NoH, 0.25), 1e-15, 0.0,
			            "D_ggx vs D_ggx_sin2 NoH=%g", NoH);
		}
	}
}

/* ---- 2. Smith masking identity (Heitz 2014, eq. 17-18) -------------------------
 * G1(v) ∫ max(0, v·m) D(m) dω_m = NoV, for any microsurface with Smith masking.
 * 2-D quadrature: θm by composite Gauss-Legendre, φm by Gauss-Legendre on the
 * part of the circle where v·m > 0, [-φ0, φ0] with cos φ0 = -cotθv cotθm. */

typedef struct smith_ctx {
	double (*D)(double, double);
	double a, sv, cv;
} smith_ctx;

static double f_phi(double phi, void *p)
{
	const double *ab = p;
	return ab[0] * cos(phi) + ab[1];
}

static double smith_theta(double t, void *p)
{
	const smith_ctx *c = p;
	double st = sin(t), ct = cos(t);
	double ab[2] = {c->sv * st, c->cv * ct}; /* v·m = A cos φ + B */
	double phi0 = ab[1] >= ab[0] ? PI : acos(-ab[1] / ab[0]);
	return c->D(ct, c->a) * st * 2.0 * gl_panel(f_phi, ab, 0.0, phi0);
}

static double projected_area(double (*D)(double, double), double a, double NoV)
{
	smith_ctx c = {D, a, sqrt((1.0 - NoV) * (1.0 + NoV)), NoV};
	breaks b;
	brk_init(&b, 0.0, HALF_PI);
	brk_geometric(&b, 0.0, a / 16.0);        /* the peak of D */
	brk_geometric(&b, HALF_PI, 1e-6);        /* Beckmann's flat end */
	double tk = HALF_PI - acos(NoV);         /* where the circle starts to be cut */
	if (tk > 0.0 && tk < HALF_PI)
		brk_geometric(&b, tk, ldexp(1.0, -30)); /* (θ - θk)^{3/2} kink */
	return integrate(smith_theta, &c, &b);
}

static const double smith_nov[] = {0.05, 0.3, 0.7, 0.99, 1.0};
static const double smith_r[] = {0.05, 0.3, 0.7, 1.0};

static void check_masking_identity(const char *name, double (*D)(double, double),
                                   double (*G1)(double, double))
{
	for (size_t i = 0; i < NELEM(smith_r); i++)
		for (size_t j = 0; j < NELEM(smith_nov); j++) {
			double a = smith_r[i] * smith_r[i], NoV = smith_nov[j];
			double got = G1(NoV, a) * projected_area(D, a, NoV);
			/* analytic panels plus a graded kink: ~1e-13 reached; 1e-10 relative margin */
			check_close(got, NoV, 1e-10, 0.0, "%s r=%g NoV=%g: G1 · ∫ <v,m>+ D dω", name,
			            smith_r[i], NoV);
		}
}

Test(smith, masking_identity_ggx)
{
	check_masking_identity("GGX", bk_D_ggx, bk_G1_ggx);
}

Test(smith, masking_identity_beckmann)
{
	check_masking_identity("Beckmann", bk_D_beckmann, bk_G1_beckmann);
}

/* ---- 3. Λ forms ------------------------------------------------------------ */

/* Heitz 2014 eq. 72, the textbook form, in long double: its cancellation
 * -1 + sqrt(1 + x) costs an absolute ~LDBL_EPSILON, not a relative error. */
static long double lambda_ggx_text(double NoX, double a)
{
	long double c = NoX, t2 = (1.0L - c * c) / (c * c);
	return (-1.0L + sqrtl(1.0L + (long double)a * a * t2)) / 2.0L;
}

static const double lam_nox[] = {0.01, 0.05, 0.2, 0.5, 0.8, 0.95, 0.999};
static const double lam_a[] = {0.0025, 0.04, 0.25, 0.6, 1.0};

Test(smith, ggx_lambda_g1_v_from_textbook_lambda)
{
	/* 1e-12: the library rearranges the algebra; only roundings separate the forms.
	 * Absolute floor 4 LDBL_EPSILON: the textbook form's own cancellation. */
	const double rel = 1e-12, abs_floor = 4.0 * LDBL_EPSILON;
	for (size_t i = 0; i < NELEM(lam_a); i++)
		for (size_t j = 0; j < NELEM(lam_nox); j++) {
			double a = lam_a[i], c = lam_nox[j];
			long double L = lambda_ggx_text(c, a);
			check_close(bk_Lambda_ggx(c, a), (double)L, rel, abs_floor, "Λ_ggx a=%g NoX=%g", a, c);
			check_close(bk_G1_ggx(c, a), (double)(1.0L / (1.0L + L)), rel, 0.0, "G1_ggx a=%g NoX=%g", a, c);
			for (size_t k = 0; k < NELEM(lam_nox); k++) {
				double cl = lam_nox[k];
				long double Ll = lambda_ggx_text(cl, a);
				long double f = 4.0L * c * cl;
				double sep = (double)(1.0L / ((1.0L + L) * (1.0L + Ll) * f));
				double cor = (double)(1.0L / ((1.0L + L + Ll) * f));
				check_close(bk_V_smith_ggx_separable(c, cl, a), sep, rel, 0.0,
				            "V_separable a=%g NoV=%g NoL=%g", a, c, cl);
				check_close(bk_V_smith_ggx_correlated(c, cl, a), cor, rel, 0.0,
				            "V_correlated a=%g NoV=%g NoL=%g", a, c, cl);
				/* 1 + Λv + Λl <= (1 + Λv)(1 + Λl): correlation never masks more */
				cr_assert(bk_V_smith_ggx_correlated(c, cl, a) >= bk_V_smith_ggx_separable(c, cl, a) * (1.0 - 1e-15),
				          "correlated < separable at a=%g NoV=%g NoL=%g", a, c, cl);
			}
		}
	/* NoX = 1: no masking */
	cr_assert(bk_Lambda_ggx(1.0, 0.5) == 0.0 && bk_G1_ggx(1.0, 0.5) == 1.0);
}

/* bk_V_smith(m, ...), the switch the integrators use, against the textbook form of
 * each model: height-correlated and separable from Λ in long double, and Karis's
 * Schlick-GGX 0.25/((NoV(1-k)+k)(NoL(1-k)+k)) with k = a/2; names round-trip. */
Test(smith, v_smith_switch_matches_each_model)
{
	for (int m = 0; m < BK_SMITH_COUNT; m++) {
		bk_smith back;
		cr_assert(bk_smith_parse(bk_smith_name((bk_smith)m), &back) == 0 && back == (bk_smith)m,
		          "bk_smith_name/parse round trip for %d (%s)", m, bk_smith_name((bk_smith)m));
		for (size_t i = 0; i < NELEM(lam_a); i++)
			for (size_t j = 0; j < NELEM(lam_nox); j++)
				for (size_t k = 0; k < NELEM(lam_nox); k++) {
					double a = lam_a[i], v = lam_nox[j], l = lam_nox[k], want;
					long double Lv = lambda_ggx_text(v, a), Ll = lambda_ggx_text(l, a), f = 4.0L * v * l;
					if (m == BK_SMITH_CORRELATED)
						want = (double)(1.0L / ((1.0L + Lv + Ll) * f));
					else if (m == BK_SMITH_SEPARABLE)
						want = (double)(1.0L / ((1.0L + Lv) * (1.0L + Ll) * f));
					else {
						double kk = 0.5 * a;
						want = 0.25 / ((v * (1.0 - kk) + kk) * (l * (1.0 - kk) + kk));
					}
					/* as for the named visibilities: rearranged algebra only */
					check_close(bk_V_smith((bk_smith)m, v, l, a), want, 1e-12, 0.0, "bk_V_smith(%s) a=%g NoV=%g NoL=%g",
					            bk_smith_name((bk_smith)m), a, v, l);
				}
	}
	bk_smith out;
	cr_assert(bk_smith_parse("nonsense", &out) != 0, "bk_smith_parse accepted nonsense");
}

/* NoX with c = 1/(a tanθ) = the given value: tanθ = 1/(a c). */
static double nox_from_c(double c, double a)
{
	double t = 1.0 / (a * c);
	return 1.0 / sqrt(1.0 + t * t);
}

static double lambda_pbrt(double c)
{
	return c >= 1.6 ? 0.0 : (1.0 - 1.259 * c + 0.396 * c * c) / (3.535 * c + 2.181 * c * c);
}

/* pbrt-v3's rational Beckmann Λ; Mitsuba states < 0.35 % relative error for the
 * matching G1 (mpmath: the largest is 0.313 % at c = 1.336), so the exact G1 must
 * agree with it to 0.35 % everywhere, including c >= 1.6 where pbrt returns 0. */
Test(smith, beckmann_lambda_vs_pbrt_rational)
{
	const double as[] = {0.02, 0.5};
	for (size_t i = 0; i < NELEM(as); i++)
		for (int k = 1; k <= 400; k++) {
			double c = 0.01 * k, a = as[i], NoX = nox_from_c(c, a);
			double g_exact = bk_G1_beckmann(NoX, a), g_pbrt = 1.0 / (1.0 + lambda_pbrt(c));
			check_close(g_pbrt, g_exact, 0.0035, 0.0, "Beckmann G1 vs pbrt a=%g c=%g", a, c);
		}
	/* beyond 1.6 Λ falls monotonically to 0 (never negative, never stuck at 0 early) */
	double prev = INFINITY;
	for (int k = 0; k <= 36; k++) {
		double c = 1.6 + 0.5 * k, L = bk_Lambda_beckmann(nox_from_c(c, 0.5), 0.5);
		cr_assert(L > 0.0 && L < prev && L < 0.0019, "Λ_beckmann(c=%g) = %.17g (prev %.17g)", c, L, prev);
		prev = L;
	}
}

/* Λ from its definition (Heitz 2014, eq. 70): Λ(μ) = (1/μ) ∫_μ^∞ (q - μ) P2(q) dq,
 * μ = cotθ, with Beckmann's marginal slope density P2(q) = exp(-q²/a²)/(a√π).
 * With q = μ + t and exp(-c²) factored out (c = μ/a), the integrand
 * t exp(-(2μt + t²)/a²) has no cancellation, so this is accurate at large c where
 * the closed form subtracts two nearly equal terms. */
typedef struct lam_ctx {
	double mu, a;
} lam_ctx;

static double f_lambda_beckmann(double t, void *p)
{
	const lam_ctx *c = p;
	return t * exp(-(2.0 * c->mu * t + t * t) / (c->a * c->a));
}

Test(smith, beckmann_lambda_vs_integral_definition)
{
	const double as[] = {0.02, 0.5};
	const double cs[] = {0.05, 0.1, 0.3, 0.6, 1.0, 1.6, 2.5, 4.0, 7.0, 12.0, 20.0};
	for (size_t i = 0; i < NELEM(as); i++)
		for (size_t j = 0; j < NELEM(cs); j++) {
			double a = as[i], c = cs[j], NoX = nox_from_c(c, a);
			double mu = NoX / sqrt((1.0 - NoX) * (1.0 + NoX)); /* cot θ of that NoX */
			lam_ctx lc = {mu, a};
			double scale = fmin(a, a * a / (2.0 * mu));  /* decay length of the integrand */
			double T = -mu + sqrt(mu * mu + 800.0 * a * a); /* exponent -800 beyond T */
			breaks b;
			brk_init(&b, 0.0, T);
			brk_geometric(&b, 0.0, scale / 16.0);
			double integral = integrate(f_lambda_beckmann, &lc, &b);
			double cm = mu / a;
			double want = exp(-cm * cm) * integral / (a * sqrt(PI) * mu);
			/* quadrature ~1e-14 and the sensitivity 2c² ulp to the rounding of c
			 * (this c and Λ's own are rounded apart): 1e-12 + 8c²ε. The closed
			 * form as a difference of e^{-c²}/(c√π) and erfc(c) lost 2c⁴ε more
			 * (2.3e-11 at c = 20, over this bound); brdf/beckmann.c takes the
			 * difference in closed form from erfc's continued fraction */
			double tol = 1e-12 + 8.0 * c * c * DBL_EPSILON;
			check_close(bk_Lambda_beckmann(NoX, a), want, tol, 0.0, "Λ_beckmann a=%g c=%g", a, c);
		}
}

/* ---- 4. reciprocity -------------------------------------------------------- */

/* Helmholtz reciprocity: every registered term (D and F see only NoH and LoH,
 * V and Fd see both directions) is unchanged when V and L swap. */
Test(reciprocity, every_registered_term)
{
	const double rs[] = {0.1, 0.5, 0.9};
	const double ks[] = {0.0, 2.0};
	for (size_t t = 0; t < bk_term_count(); t++) {
		const bk_term *term = bk_term_at(t);
		for (size_t i = 0; i < NELEM(thetas); i++)
			for (size_t j = 0; j < NELEM(thetas); j++)
				for (size_t p = 0; p < NELEM(phis); p++)
					for (size_t q = 0; q < NELEM(rs); q++)
						for (size_t m = 0; m < NELEM(ks); m++) {
							double tv = thetas[i], tl = thetas[j], phi = phis[p];
							bk_sample s1 = make_sample(tv, tl, phi, rs[q]);
							bk_sample s2 = make_sample(tl, tv, phi, rs[q]);
							s1.k = s2.k = ks[m];
							double x = term->eval(&s1), y = term->eval(&s2);
							cr_assert(isfinite(x) && isfinite(y), "%s not finite: %g %g", term->name, x, y);
							/* the two cosine sets differ by the order of a few products */
							check_close(y, x, 1e-13, 0.0, "%s swapped, θv=%g θl=%g φ=%g r=%g",
							            term->name, tv, tl, phi, rs[q]);
						}
	}
}

/* ---- 5. limits ------------------------------------------------------------- */

static const double cosines[] = {0.05, 0.1, 0.3, 0.5, 0.8, 1.0};

Test(limits, ggx_and_blinn_phong_uniform_at_alpha_one)
{
	for (int i = 1; i <= 100; i++) {
		double NoH = 0.01 * i;
		/* (1-c)(1+c) + c² = 1 to a few ulp */
		check_close(bk_D_ggx(NoH, 1.0), 1.0 / PI, 2e-15, 0.0, "D_ggx(a=1, NoH=%g)", NoH);
		/* n = 0: NoH^0 = 1 exactly */
		check_close(bk_D_blinn_phong(NoH, 1.0), 1.0 / PI, 1e-15, 0.0, "D_blinn_phong(a=1, NoH=%g)", NoH);
	}
	/* Walter's mapping: n = 2/a² - 2 is 0 at a = 1 and 2/0.01 - 2 = 198 at a = 0.1 */
	check_close(bk_blinn_phong_exponent(1.0), 0.0, 0.0, 0.0, "Blinn-Phong n(a=1)");
	check_close(bk_blinn_phong_exponent(0.1), 198.0, 1e-14, 0.0, "Blinn-Phong n(a=0.1)");
}

/* Smith visibilities tend to the smooth limit 1/(4 NoL NoV): exactly at a = 0,
 * and at small a with a first-order deviation below 2a/min(NoV, NoL) (each
 * form's expansion: Hammon a((NoL+NoV)/(2NoLNoV) - 1), Schlick k(1/NoV + 1/NoL)
 * with k = a/2, the exact forms O(a²/NoX²)). */
Test(limits, smith_visibilities_smooth_limit)
{
	for (size_t i = 0; i < NELEM(cosines); i++)
		for (size_t j = 0; j < NELEM(cosines); j++) {
			double v = cosines[i], l = cosines[j], want = 0.25 / (v * l);
			double V0[4] = {bk_V_smith_ggx_separable(v, l, 0.0), bk_V_smith_ggx_correlated(v, l, 0.0),
			                bk_V_schlick_ggx(v, l, 0.0), bk_V_hammon(v, l, 0.0)};
			const char *names[4] = {"separable", "correlated", "schlick k=0", "hammon"};
			for (int m = 0; m < 4; m++) /* a = 0: a few roundings */
				check_close(V0[m], want, 1e-15, 0.0, "V_%s(a=0) NoV=%g NoL=%g", names[m], v, l);
			check_close(bk_V_schlick_ggx_ibl(v, l, 0.0), want, 1e-15, 0.0, "V_schlick_ibl(a=0)");
			for (double a = 1e-2; a >= 1e-8; a *= 1e-2) {
				double bound = 2.0 * a / fmin(v, l) + 1e-15;
				double Va[5] = {bk_V_smith_ggx_separable(v, l, a), bk_V_smith_ggx_correlated(v, l, a),
				                bk_V_schlick_ggx(v, l, 0.5 * a), bk_V_hammon(v, l, a),
				                bk_V_schlick_ggx_ibl(v, l, a)};
				const char *na[5] = {"separable", "correlated", "schlick k=a/2", "hammon", "schlick_ggx_ibl"};
				for (int m = 0; m < 5; m++)
					check_close(Va[m], want, bound, 0.0, "V_%s a=%g NoV=%g NoL=%g", na[m], a, v, l);
			}
		}
}

Test(limits, simple_visibilities)
{
	for (size_t i = 0; i < NELEM(cosines); i++)
		for (size_t j = 0; j < NELEM(cosines); j++) {
			double v = cosines[i], l = cosines[j];
			/* Hammon at a = 1 is mix(..., NoL + NoV, 1): 0.5/(NoL + NoV); rounding only */
			check_close(bk_V_hammon(v, l, 1.0), 0.5 / (v + l), 1e-15, 0.0, "V_hammon(a=1) %g %g", v, l);
		}
	cr_assert(bk_V_implicit() == 0.25, "V_implicit = %.17g", bk_V_implicit());
	for (int i = 1; i <= 20; i++) {
		double LoH = 0.05 * i;
		/* Kelemen: G/(NoL NoV) = 1/LoH², V = 0.25/LoH²; one division */
		check_close(bk_V_kelemen(LoH), 0.25 / (LoH * LoH), 1e-15, 0.0, "V_kelemen(%g)", LoH);
		/* Hable's k = a/2 -> 0 gives back Kelemen exactly ... */
		check_close(bk_V_kelemen_hable(LoH, 0.0), bk_V_kelemen(LoH), 1e-15, 0.0, "V_kelemen_hable(a=0)");
		/* ... and the talk's form at r is Hable's at a = 2r (k = r): k² = 0.25 (2r)² */
		for (double r = 0.1; r < 1.0; r += 0.2)
			check_close(bk_V_kelemen_talk(LoH, r), bk_V_kelemen_hable(LoH, 2.0 * r), 1e-15, 0.0,
			            "V_kelemen_talk(r=%g) vs hable(a=2r)", r);
		check_close(bk_V_kelemen_talk(LoH, 0.0), bk_V_kelemen(LoH), 1e-15, 0.0, "V_kelemen_talk(r=0)");
		/* Hable at small a (k = a/2): the relative deviation is
		 * k²(1 - LoH²)/(LoH² + k²(1 - LoH²)), below k²/LoH² by a relative k² or
		 * more (2.5e-9 here), far above rounding, so the bound k²/LoH² is safe */
		double a = 1e-4, k2 = 0.25 * a * a;
		check_close(bk_V_kelemen_hable(LoH, a), bk_V_kelemen(LoH), k2 / (LoH * LoH) + 1e-15, 0.0,
		            "V_kelemen_hable(a=1e-4) LoH=%g", LoH);
	}
	/* Kelemen at V = L (LoH = 1) is the implicit 0.25 */
	check_close(bk_V_kelemen(1.0), 0.25, 0.0, 0.0, "V_kelemen(1)");
}

/* Cook-Torrance's V-groove G = min(1, 2NoH NoV/VoH, 2NoH NoL/VoH) from vectors built
 * here: G <= 1 everywhere, G = 1 at the mirror direction (NoH = 1), and masking
 * active somewhere on the grid (so G <= 1 is not vacuous). */
Test(limits, cook_torrance_v_groove)
{
	int masked = 0;
	for (int i = 1; i <= 15; i++)
		for (int j = 1; j <= 15; j++)
			for (size_t p = 0; p < NELEM(phis); p++) {
				double tv = 0.1 * i, tl = 0.1 * j, phi = phis[p];
				geom g = make_geom(tv, tl, phi);
				double V = bk_V_cook_torrance(g.NoV, g.NoL, g.NoH, g.VoH);
				double G = 4.0 * g.NoL * g.NoV * V;
				double want = fmin(1.0, fmin(2.0 * g.NoH * g.NoV / g.VoH, 2.0 * g.NoH * g.NoL / g.VoH));
				/* G reassembled from V: a few roundings */
				cr_assert(G <= 1.0 + 4e-16, "Cook-Torrance G = %.17g > 1 at θv=%g θl=%g φ=%g", G, tv, tl, phi);
				check_close(G, want, 1e-14, 0.0, "Cook-Torrance G θv=%g θl=%g φ=%g", tv, tl, phi);
				masked += want < 0.9;
			}
	cr_assert(masked > 10, "V-groove masking never active on the grid (%d)", masked);
	for (size_t i = 0; i < NELEM(cosines); i++) {
		double c = cosines[i];
		/* NoH = 1: VoH = NoV = NoL, 2NoH NoV/VoH = 2, so G = 1 */
		double G = 4.0 * c * c * bk_V_cook_torrance(c, c, 1.0, c);
		check_close(G, 1.0, 4e-16, 0.0, "Cook-Torrance G at NoH = 1, NoV = NoL = %g", c);
	}
}

/* ---- 6. Fresnel ---------------------------------------------------------------
 * Independent: the Fresnel equations for a complex index ñ = n + ik seen from
 * index 1 (Born & Wolf §1.5 / §14.2), with C99 complex arithmetic. */

static double fresnel_complex(double cos_i, double n, double k)
{
	double complex nn = CMPLX(n, k), n2 = nn * nn;
	double s2 = (1.0 - cos_i) * (1.0 + cos_i);
	double complex root = csqrt(n2 - s2);
	double complex rs = (cos_i - root) / (cos_i + root);
	double complex rp = (n2 * cos_i - root) / (n2 * cos_i + root);
	double as = cabs(rs), ap = cabs(rp);
	return 0.5 * (as * as + ap * ap);
}

Test(fresnel, dielectric_normal_incidence_and_brewster)
{
	/* ((n-1)/(n+1))² = (0.5/2.5)² = 0.04: a few ulp of 0.04 */
	check_close(bk_F_dielectric(1.0, 1.5), 0.04, 1e-15, 0.0, "F_dielectric(1, 1.5)");
	check_close(bk_F_dielectric(1.0, 1.0 / 1.5), 0.04, 1e-15, 0.0, "F_dielectric(1, 1/1.5)");
	const double ns[] = {1.33, 1.5, 2.4, 1.0 / 1.5};
	for (size_t i = 0; i < NELEM(ns); i++) {
		double n = ns[i], cb = cos(atan(n)), Rs, Rp;
		bk_fresnel_dielectric_sp(cb, n, &Rs, &Rp);
		/* Brewster: rp is a difference of equal terms, Rp = O(ulp²) */
		cr_assert(fabs(Rp) <= 1e-15, "Rp at Brewster (n=%g) = %.3g", n, Rp);
		/* there rs = (1 - n²)/(1 + n²) (cos θt = n cos θi) */
		double rs = (1.0 - n * n) / (1.0 + n * n);
		check_close(Rs, rs * rs, 1e-13, 0.0, "Rs at Brewster n=%g", n);
		/* 5° away, Rp is clearly not 0 (Rs/Rp not swapped, not both zero) */
		bk_fresnel_dielectric_sp(cos(atan(n) + 0.09), n, &Rs, &Rp);
		cr_assert(Rp > 1e-4 && Rs > Rp, "Rs=%g Rp=%g 5° past Brewster n=%g", Rs, Rp, n);
	}
}

Test(fresnel, total_internal_reflection_and_stokes)
{
	double eta = 1.0 / 1.5, cos_c = sqrt(1.0 - eta * eta); /* sin θc = eta */
	for (int i = 0; i <= 100; i++) {
		double c = cos_c * (1.0 - 1e-9) * i / 100.0;
		cr_assert(bk_F_dielectric(c, eta) == 1.0, "no TIR at cos=%.17g (critical %.17g): %.17g", c, cos_c,
		          bk_F_dielectric(c, eta));
	}
	/* just inside the critical angle it is a reflectance below 1, tending to 1 */
	double c = cos_c * 1.01;
	cr_assert(bk_F_dielectric(c, eta) < 1.0 && bk_F_dielectric(c, eta) > 0.3, "F(cos=%g) = %g", c,
	          bk_F_dielectric(c, eta));
	/* Stokes: the reflectance is the same from either side of the interface,
	 * F(cos θi, n) = F(cos θt, 1/n) with sin θt = sin θi / n */
	for (int i = 0; i <= 64; i++) {
		double ci = i / 64.0, n = 1.5;
		double ct = sqrt(1.0 - (1.0 - ci * ci) / (n * n));
		/* a handful of roundings through a smooth map; grazing stays O(1) */
		check_close(bk_F_dielectric(ct, 1.0 / n), bk_F_dielectric(ci, n), 1e-13, 1e-15, "Stokes cos=%g", ci);
	}
}

Test(fresnel, conductor_vs_complex_fresnel)
{
	const double nk[][2] = {{0.2, 3.0}, {1.5, 2.0}, {0.27, 2.78}, {2.9, 3.0}, {1.0, 0.1}, {1.5, 0.01},
	                        {1.5, 0.0}, {2.4, 0.0}, {1.0 / 1.5, 0.0} /* TIR */};
	for (size_t i = 0; i < NELEM(nk); i++)
		for (int j = 0; j <= 200; j++) {
			double ci = j / 200.0;
			/* two exact closed forms in different algebra; 1e-12 as briefed */
			check_close(bk_F_conductor(ci, nk[i][0], nk[i][1]), fresnel_complex(ci, nk[i][0], nk[i][1]),
			            1e-12, 1e-15, "F_conductor n=%g k=%g cos=%g", nk[i][0], nk[i][1], ci);
		}
	/* with k = 0 the conductor is the dielectric (n > 1) */
	const double ns[] = {1.33, 1.5, 2.4, 4.0};
	for (size_t i = 0; i < NELEM(ns); i++)
		for (int j = 0; j <= 200; j++) {
			double ci = j / 200.0;
			/* the same physics by two algebraic routes */
			check_close(bk_F_conductor(ci, ns[i], 0.0), bk_F_dielectric(ci, ns[i]), 1e-13, 1e-15,
			            "F_conductor(k=0) vs F_dielectric n=%g cos=%g", ns[i], ci);
			check_close(bk_F_dielectric(ci, ns[i]), fresnel_complex(ci, ns[i], 0.0), 1e-12, 1e-15,
			            "F_dielectric vs complex n=%g cos=%g", ns[i], ci);
		}
	/* ... and below 1 with total internal reflection, the complex form agrees */
	for (int j = 0; j <= 200; j++) {
		double ci = j / 200.0;
		check_close(bk_F_dielectric(ci, 1.0 / 1.5), fresnel_complex(ci, 1.0 / 1.5, 0.0), 1e-12, 1e-15,
		            "F_dielectric vs complex n=1/1.5 cos=%g", ci);
	}
}

Test(fresnel, ior_f0_round_trip)
{
	/* |(ñ - 1)/(ñ + 1)|² by complex arithmetic */
	const double nk[][2] = {{1.5, 0.0}, {0.2, 3.0}, {2.9, 3.0}, {1.33, 0.0}};
	for (size_t i = 0; i < NELEM(nk); i++) {
		double complex nn = CMPLX(nk[i][0], nk[i][1]);
		double r = cabs((nn - 1.0) / (nn + 1.0));
		check_close(bk_f0_from_ior(nk[i][0], nk[i][1]), r * r, 1e-14, 0.0, "f0 n=%g k=%g", nk[i][0], nk[i][1]);
		/* and it is the conductor formula at normal incidence */
		check_close(bk_F_conductor(1.0, nk[i][0], nk[i][1]), r * r, 1e-13, 0.0, "F_conductor(1) n=%g", nk[i][0]);
	}
	/* n = 1.5 <-> f0 = 0.04: (1 + 0.2)/(1 - 0.2) */
	check_close(bk_ior_from_f0(0.04), 1.5, 1e-15, 0.0, "ior_from_f0(0.04)");
	const double f0s[] = {1e-4, 0.02, 0.04, 0.5, 0.9};
	for (size_t i = 0; i < NELEM(f0s); i++) {
		/* condition number ~ 1/(1 - sqrt f0) ≈ 20 at f0 = 0.9: 1e-13 */
		check_close(bk_f0_from_ior(bk_ior_from_f0(f0s[i]), 0.0), f0s[i], 1e-13, 0.0, "f0 round trip %g", f0s[i]);
	}
	const double etas[] = {1.01, 1.5, 2.4, 4.0};
	for (size_t i = 0; i < NELEM(etas); i++)
		check_close(bk_ior_from_f0(bk_f0_from_ior(etas[i], 0.0)), etas[i], 1e-13, 0.0, "ior round trip %g", etas[i]);
}

Test(fresnel, schlick_and_sg)
{
	const double f0s[] = {0.0, 0.02, 0.04, 0.5, 0.95};
	const double f90s[] = {1.0, 0.5, 0.0};
	for (size_t i = 0; i < NELEM(f0s); i++)
		for (size_t j = 0; j < NELEM(f90s); j++) {
			double f0 = f0s[i], f90 = f90s[j];
			/* endpoints: f0 exactly; f90 up to one rounding of f0 + (f90 - f0) */
			check_close(bk_F_schlick(f0, f90, 1.0), f0, 0.0, 0.0, "Schlick(LoH=1) f0=%g", f0);
			check_close(bk_F_schlick(f0, f90, 0.0), f90, 0.0, 2.3e-16, "Schlick(LoH=0) f90=%g", f90);
			/* (1 - 0.5)^5 = 1/32 exactly */
			check_close(bk_F_schlick(f0, f90, 0.5), f0 + (f90 - f0) / 32.0, 1e-15, 1e-17, "Schlick(0.5)");
			/* SG Schlick has the same endpoints at LoH = 0 (exp2(0) = 1) */
			check_close(bk_F_schlick_sg(f0, f90, 0.0), f90, 0.0, 2.3e-16, "SG Schlick(LoH=0)");
		}
	/* Karis 2013: at LoH = 0.5 the SG form gives 0.03395 (vs 0.03125), published
	 * to 5 digits: within half a unit of the last digit */
	double sg = bk_F_schlick_sg(0.0, 1.0, 0.5);
	cr_assert(fabs(sg - 0.03395) <= 0.5e-5, "SG Schlick(0.5) = %.7f, published 0.03395", sg);
	/* within 0.01 of (1 - x)^5 on [0, 1] (mpmath: max 0.00377 at x = 0.055) */
	double worst = 0.0;
	for (int i = 0; i <= 10000; i++) {
		double x = i / 10000.0, e = fabs(bk_F_schlick_sg(0.0, 1.0, x) - pow(1.0 - x, 5.0));
		worst = fmax(worst, e);
	}
	cr_assert(worst < 0.01, "SG Schlick deviates from (1-x)^5 by %g", worst);
	cr_assert(worst > 0.003, "SG Schlick suspiciously equal to (1-x)^5: %g", worst);
}

/* Schlick with f0 = 0.04 against the exact n = 1.5 dielectric. The error is NOT a
 * few 1e-3 over the whole range: mpmath gives max |Schlick - exact| = 0.03569 at
 * cos θ = 0.0876 (≈ 85°), and -0.0196 near 62°. Within a few 1e-3 only for
 * cos θ >= 0.8 (θ <= 37°): max 0.003588 there. Bounds: 0.004 on [0.8, 1], 0.036
 * overall, and the overall maximum must exceed 0.035 (else the exact term is not
 * the exact term). */
Test(fresnel, schlick_vs_exact_dielectric)
{
	double near = 0.0, all = 0.0;
	for (int i = 0; i <= 20000; i++) {
		double c = i / 20000.0;
		double e = fabs(bk_F_schlick(0.04, 1.0, c) - bk_F_dielectric(c, 1.5));
		all = fmax(all, e);
		if (c >= 0.8)
			near = fmax(near, e);
	}
	cr_assert(near <= 0.004, "Schlick vs exact on cos >= 0.8: %g > 0.004", near);
	cr_assert(all <= 0.036 && all >= 0.035, "Schlick vs exact overall: %g not in [0.035, 0.036]", all);
}

/* ---- 7. diffuse -------------------------------------------------------------- */

typedef struct alb_ctx {
	const bk_term *fd;
	double tv, r, tl;
} alb_ctx;

static double alb_phi(double phi, void *p)
{
	const alb_ctx *c = p;
	bk_sample s = make_sample(c->tv, c->tl, phi, c->r);
	return c->fd->eval(&s);
}

static double alb_theta(double tl, void *p)
{
	alb_ctx *c = p;
	c->tl = tl;
	breaks b; /* Oren-Nayar's max(0, cos φ) kinks at ±π/2 */
	brk_init(&b, 0.0, 2.0 * PI);
	brk_add(&b, HALF_PI);
	brk_add(&b, PI);
	brk_add(&b, 1.5 * PI);
	return integrate(alb_phi, c, &b) * cos(tl) * sin(tl);
}

/* ∫ Fd NoL dω_l through the registry, by a product Gauss-Legendre rule. */
static double diffuse_albedo(const char *name, double tv, double r)
{
	alb_ctx c = {bk_term_find(name), tv, r, 0.0};
	cr_assert_not_null(c.fd, "%s not registered", name);
	breaks b; /* the max(NoV, NoL) kink at θl = θv */
	brk_init(&b, 0.0, HALF_PI);
	brk_add(&b, tv);
	for (int i = 1; i < 4; i++)
		brk_add(&b, i * HALF_PI / 4);
	return integrate(alb_theta, &c, &b);
}

Test(diffuse, white_furnace_and_closed_form_albedos)
{
	/* smooth integrands on GL panels: rounding of a few thousand terms */
	const double tol = 1e-12;
	const double tvs[] = {0.0, 0.7, 1.3};
	for (size_t i = 0; i < NELEM(tvs); i++) {
		check_close(diffuse_albedo("Fd_lambert", tvs[i], 0.5), 1.0, tol, 0.0, "Lambert furnace θv=%g", tvs[i]);
		check_close(diffuse_albedo("Fd_oren_nayar", tvs[i], 0.0), 1.0, tol, 0.0, "Oren-Nayar σ=0 furnace θv=%g",
		            tvs[i]);
	}
	/* Burley at NoV = 1: f90 = 0.5 + r(1 + μ), albedo = 2∫(1 + (f90-1)(1-μ)^5) μ dμ.
	 * r = 0: 1 - 1/42 (B(2,6) = 1/42); r = 1: 1 + 1/42 + 2 B(3,6) = 1 + 1/28. */
	double b0 = diffuse_albedo("Fd_burley", 0.0, 0.0), b1 = diffuse_albedo("Fd_burley", 0.0, 1.0);
	check_close(b0, 41.0 / 42.0, tol, 0.0, "Burley albedo r=0 NoV=1");
	cr_assert(b0 < 1.0, "Burley at r = 0 has no retro-reflection: albedo %g should be < 1", b0);
	check_close(b1, 29.0 / 28.0, tol, 0.0, "Burley albedo r=1 NoV=1");
	/* Oren-Nayar at NoV = 1: β = 0, tan β = 0, albedo = A = 1 - 0.5σ²/(σ²+0.33) */
	const double sig[] = {0.2, 0.5, 1.0};
	for (size_t i = 0; i < NELEM(sig); i++) {
		double s2 = sig[i] * sig[i];
		check_close(diffuse_albedo("Fd_oren_nayar", 0.0, sig[i]), 1.0 - 0.5 * s2 / (s2 + 0.33), tol, 0.0,
		            "Oren-Nayar albedo NoV=1 σ=%g", sig[i]);
	}
}

/* Oren & Nayar 1994's qualitative model in its angular form, from angles here:
 * (A + B max(0, cos Δφ) sin α tan β)/π, α = max(θv, θl), β = min(θv, θl). */
static double oren_nayar_text(double tv, double tl, double phi, double sigma)
{
	double s2 = sigma * sigma;
	double A = 1.0 - 0.5 * s2 / (s2 + 0.33), B = 0.45 * s2 / (s2 + 0.09);
	double al = fmax(tv, tl), be = fmin(tv, tl);
	return (A + B * fmax(0.0, cos(phi)) * sin(al) * tan(be)) / PI;
}

Test(diffuse, oren_nayar_angular_form_and_lambert_limit)
{
	const double sig[] = {0.0, 0.1, 0.3, 0.5, 1.0};
	const double ps[] = {0.0, 0.5, 1.3, HALF_PI, 2.0, PI};
	for (int i = 0; i <= 15; i++)
		for (int j = 0; j <= 15; j++)
			for (size_t p = 0; p < NELEM(ps); p++)
				for (size_t q = 0; q < NELEM(sig); q++) {
					double tv = 0.1 * i, tl = 0.1 * j;
					geom g = make_geom(tv, tl, ps[p]);
					double got = bk_Fd_oren_nayar(g.NoV, g.NoL, g.VoL, sig[q]);
					/* VoL - NoV NoL vs sinθv sinθl cosφ: absolute ~1e-16 on a value >= A/π */
					check_close(got, oren_nayar_text(tv, tl, ps[p], sig[q]), 1e-13, 1e-16,
					            "Oren-Nayar θv=%g θl=%g φ=%g σ=%g", tv, tl, ps[p], sig[q]);
					if (sig[q] == 0.0) /* A = 1, B = 0: exactly Lambert */
						cr_assert(got == bk_Fd_lambert(), "Oren-Nayar σ=0: %.17g", got);
					/* reciprocal: swapping V and L swaps the two cosines */
					check_close(bk_Fd_oren_nayar(g.NoL, g.NoV, g.VoL, sig[q]), got, 1e-15, 0.0, "ON swap");
				}
	check_close(bk_Fd_lambert(), 1.0 / PI, 1e-16, 0.0, "Lambert 1/π");
}

Test(diffuse, burley_normal_incidence_and_reciprocity)
{
	const double rs[] = {0.0, 0.25, 0.5, 1.0};
	for (size_t i = 0; i < NELEM(rs); i++) {
		/* V = L = N: both Schlick factors are exactly 1 */
		check_close(bk_Fd_burley(1.0, 1.0, 1.0, rs[i]), 1.0 / PI, 1e-16, 0.0, "Burley NoL=NoV=1 r=%g", rs[i]);
		for (size_t j = 0; j < NELEM(cosines); j++)
			for (size_t k = 0; k < NELEM(cosines); k++) {
				double v = cosines[j], l = cosines[k], LoH = 0.7;
				cr_assert(bk_Fd_burley(v, l, LoH, rs[i]) == bk_Fd_burley(l, v, LoH, rs[i]),
				          "Burley not reciprocal at %g %g", v, l);
			}
	}
	/* retro-reflection at grazing: rough surfaces brighter than Lambert when V ≈ L at
	 * grazing (f90 > 1), smooth ones darker (f90 = 0.5) */
	geom g = make_geom(1.4, 1.4, 0.0);
	cr_assert(bk_Fd_burley(g.NoV, g.NoL, g.LoH, 1.0) > 1.0 / PI, "Burley r=1 no retro-reflection");
	cr_assert(bk_Fd_burley(g.NoV, g.NoL, g.LoH, 0.0) < 1.0 / PI, "Burley r=0 not darkened at grazing");
}

/* ---- 8. registry -------------------------------------------------------------- */

/* Every bk_D_, bk_V_, bk_F_, bk_Fd_ function of brdf.h that takes (angles,
 * roughness, material): all must be registered under their IR name and role.
 * (bk_V_schlick_ggx with a raw k is reached through its _ibl and _direct forms.) */
static const struct { const char *name; bk_role role; } expected_terms[] = {
	{"D_ggx", BK_ROLE_D}, {"D_beckmann", BK_ROLE_D}, {"D_blinn_phong", BK_ROLE_D},
	{"D_blinn_phong_sg", BK_ROLE_D},
	{"V_smith_ggx_separable", BK_ROLE_V}, {"V_smith_ggx_correlated", BK_ROLE_V},
	{"V_schlick_ggx_ibl", BK_ROLE_V}, {"V_schlick_ggx_direct", BK_ROLE_V}, {"V_kelemen", BK_ROLE_V},
	{"V_kelemen_hable", BK_ROLE_V}, {"V_kelemen_talk", BK_ROLE_V}, {"V_neubelt", BK_ROLE_V},
	{"V_neumann", BK_ROLE_V}, {"V_implicit", BK_ROLE_V}, {"V_cook_torrance", BK_ROLE_V},
	{"V_hammon", BK_ROLE_V},
	{"F_schlick", BK_ROLE_F}, {"F_schlick_sg", BK_ROLE_F}, {"F_schuler", BK_ROLE_F},
	{"F_dielectric", BK_ROLE_F}, {"F_conductor", BK_ROLE_F},
	{"Fd_lambert", BK_ROLE_FD}, {"Fd_burley", BK_ROLE_FD}, {"Fd_oren_nayar", BK_ROLE_FD},
};

Test(registry, hygiene)
{
	size_t n = bk_term_count();
	cr_assert(n >= NELEM(expected_terms), "%zu terms registered, brdf.h declares %zu", n, NELEM(expected_terms));
	cr_assert_null(bk_term_at(n), "bk_term_at(count) must be NULL");
	for (size_t i = 0; i < n; i++) {
		const bk_term *t = bk_term_at(i);
		cr_assert_not_null(t);
		cr_assert(t->name && t->name[0], "term %zu has no name", i);
		cr_assert(t->role >= BK_ROLE_D && t->role <= BK_ROLE_FD, "%s: bad role %d", t->name, (int)t->role);
		const char *rn = bk_role_name(t->role);
		size_t rl = strlen(rn);
		cr_assert(strncmp(t->name, rn, rl) == 0 && t->name[rl] == '_' && t->name[rl + 1] != '\0',
		          "%s does not start with its role prefix %s_", t->name, rn);
		cr_assert(t->args != NULL, "%s: args NULL", t->name);
		cr_assert(t->summary && t->summary[0], "%s: empty summary", t->name);
		cr_assert(t->convention && t->convention[0], "%s: empty convention", t->name);
		cr_assert(t->citation && t->citation[0], "%s: empty citation", t->name);
		cr_assert_not_null(t->eval, "%s: no evaluator", t->name);
		for (size_t j = 0; j < i; j++)
			cr_assert(strcmp(bk_term_at(j)->name, t->name) != 0, "duplicate name %s", t->name);
		cr_assert(bk_term_find(t->name) == t, "bk_term_find(%s) does not return it", t->name);
		cr_assert(bk_term_find_role(t->role, t->name + rl + 1) == t, "find_role(%s, %s)", rn, t->name + rl + 1);
	}
	for (size_t i = 0; i < NELEM(expected_terms); i++) {
		const bk_term *t = bk_term_find(expected_terms[i].name);
		cr_assert_not_null(t, "%s from brdf.h is not registered", expected_terms[i].name);
		cr_assert(t->role == expected_terms[i].role, "%s: role %d", t->name, (int)t->role);
	}
	const char *want_roles[] = {"D", "V", "F", "Fd"};
	for (int r = BK_ROLE_D; r <= BK_ROLE_FD; r++)
		cr_assert_str_eq(bk_role_name((bk_role)r), want_roles[r]);
}

Test(registry, lookups)
{
	const bk_term *t = bk_term_find("D_ggx");
	cr_assert_not_null(t);
	cr_assert_str_eq(t->name, "D_ggx");
	cr_assert(t->role == BK_ROLE_D);
	cr_assert(bk_term_find_role(BK_ROLE_D, "ggx") == t, "find_role(D, ggx)");
	cr_assert(bk_term_find_role(BK_ROLE_D, "D_ggx") == t, "find_role(D, D_ggx)");
	cr_assert_null(bk_term_find_role(BK_ROLE_V, "ggx"), "role mismatch must give NULL");
	cr_assert_null(bk_term_find_role(BK_ROLE_V, "D_ggx"), "full name of another role must give NULL");
	cr_assert_null(bk_term_find_role(BK_ROLE_F, "lambert"), "F must not find Fd_lambert");
	cr_assert(bk_term_find_role(BK_ROLE_FD, "lambert") == bk_term_find("Fd_lambert"));
	cr_assert_null(bk_term_find("ggx"), "short name without a role must give NULL");
	cr_assert_null(bk_term_find("D_nonexistent"));
	cr_assert_null(bk_term_find(""));
	/* the evaluator computes D_ggx at the sample: mirror direction, a = 0.25 */
	bk_sample s = make_sample(0.3, 0.3, PI, 0.5);
	/* peak 1/(π a²) at NoH = 1 */
	check_close(t->eval(&s), 1.0 / (PI * 0.0625), 1e-14, 0.0, "registry D_ggx at the peak");
}

/* Every registered term against its reference formula as printed in
 * shared/references/approximations.md (or the textbook for the exact terms),
 * written out here from angles and vectors built here. A term without a
 * reference here fails: a new term must come with its check. */
static double ref_term(const char *name, double tv, double tl, double phi, double r, double k, int *known)
{
	geom g = make_geom(tv, tl, phi);
	double a = r * r, a2 = a * a, f0 = 0.04, f90 = 1.0, eta = 1.5;
	double NoV = g.NoV, NoL = g.NoL, NoH = g.NoH, LoH = g.LoH;
	double n = 2.0 / a2 - 2.0;
	*known = 1;
	if (!strcmp(name, "D_ggx")) {
		double d = NoH * NoH * (a2 - 1.0) + 1.0;
		return a2 / (PI * d * d);
	}
	if (!strcmp(name, "D_beckmann")) {
		double t2 = (g.h[0] * g.h[0] + g.h[1] * g.h[1]) / (NoH * NoH);
		return exp(-t2 / a2) / (PI * a2 * pow(NoH, 4.0));
	}
	if (!strcmp(name, "D_blinn_phong"))
		return (n + 2.0) / (2.0 * PI) * pow(NoH, n);
	if (!strcmp(name, "D_blinn_phong_sg"))
		return (n + 2.0) / (2.0 * PI) * exp((n + 0.775) * (NoH - 1.0));
	if (!strcmp(name, "D_charlie") || !strcmp(name, "D_ashikhmin")) {
		/* Estevez & Kulla 2017 eq. 2; Ashikhmin & Premoze 2007 as Filament's
		 * D_Ashikhmin: from sin θh of the half vector built here */
		double s2 = g.h[0] * g.h[0] + g.h[1] * g.h[1];
		if (!strcmp(name, "D_charlie")) /* at a cosine that rounds to 1 the term sees
		                                 * sin θh = 0 (it takes NoH only): D = 0 there */
			return (1.0 - NoH) * (1.0 + NoH) == 0.0 ? 0.0 : (2.0 + 1.0 / a) * pow(sqrt(s2), 1.0 / a) / (2.0 * PI);
		if (s2 == 0.0)
			return 1.0 / (PI * (1.0 + 4.0 * a2));
		return (1.0 + 4.0 * exp(-(NoH * NoH / s2) / a2) / (s2 * s2)) / (PI * (1.0 + 4.0 * a2));
	}
	if (!strcmp(name, "V_smith_ggx_separable"))
		return 1.0 / ((NoV + sqrt(a2 + (1.0 - a2) * NoV * NoV)) * (NoL + sqrt(a2 + (1.0 - a2) * NoL * NoL)));
	if (!strcmp(name, "V_smith_ggx_correlated"))
		return 0.5 / (NoL * sqrt(NoV * NoV * (1.0 - a2) + a2) + NoV * sqrt(NoL * NoL * (1.0 - a2) + a2));
	if (!strcmp(name, "V_schlick_ggx_ibl") || !strcmp(name, "V_schlick_ggx_direct")) {
		double kk = !strcmp(name, "V_schlick_ggx_ibl") ? a / 2.0 : (r + 1.0) * (r + 1.0) / 8.0;
		return 0.25 / ((NoV * (1.0 - kk) + kk) * (NoL * (1.0 - kk) + kk));
	}
	if (!strcmp(name, "V_kelemen"))
		return 0.25 / (LoH * LoH);
	if (!strcmp(name, "V_kelemen_hable")) {
		double kk = a / 2.0;
		return 0.25 / (LoH * LoH * (1.0 - kk * kk) + kk * kk);
	}
	if (!strcmp(name, "V_kelemen_talk"))
		return 0.25 / (LoH * LoH * (1.0 - r * r) + r * r);
	if (!strcmp(name, "V_neubelt"))
		return 1.0 / (4.0 * (NoL + NoV - NoL * NoV));
	if (!strcmp(name, "V_neumann"))
		return 1.0 / (4.0 * fmax(NoL, NoV));
	if (!strcmp(name, "V_implicit"))
		return 0.25;
	if (!strcmp(name, "V_cook_torrance"))
		return fmin(1.0, fmin(2.0 * NoH * NoV / g.VoH, 2.0 * NoH * NoL / g.VoH)) / (4.0 * NoL * NoV);
	if (!strcmp(name, "V_hammon")) {
		double x = 2.0 * NoL * NoV, y = NoL + NoV;
		return 0.5 / (x + (y - x) * a);
	}
	if (!strcmp(name, "F_schlick"))
		return f0 + (f90 - f0) * pow(1.0 - LoH, 5.0);
	if (!strcmp(name, "F_schlick_sg"))
		return f0 + (f90 - f0) * exp2((-5.55473 * LoH - 6.98316) * LoH);
	if (!strcmp(name, "F_schuler"))
		return f0 / LoH;
	if (!strcmp(name, "F_dielectric"))
		return fresnel_complex(LoH, eta, 0.0);
	if (!strcmp(name, "F_conductor"))
		return fresnel_complex(LoH, eta, k);
	if (!strcmp(name, "Fd_lambert"))
		return 1.0 / PI;
	if (!strcmp(name, "Fd_burley")) {
		double fb = 0.5 + 2.0 * r * LoH * LoH;
		return (1.0 + (fb - 1.0) * pow(1.0 - NoL, 5.0)) * (1.0 + (fb - 1.0) * pow(1.0 - NoV, 5.0)) / PI;
	}
	if (!strcmp(name, "Fd_oren_nayar")) /* registry convention: σ = r */
		return oren_nayar_text(tv, tl, phi, r);
	*known = 0;
	return 0.0;
}

Test(registry, every_term_matches_its_reference_formula)
{
	const double rs[] = {0.3, 0.7};
	const double ts[] = {0.1, 0.5, 1.0, 1.3};
	const double ps[] = {0.0, 1.0, 2.5, PI};
	for (size_t t = 0; t < bk_term_count(); t++) {
		const bk_term *term = bk_term_at(t);
		for (size_t i = 0; i < NELEM(ts); i++)
			for (size_t j = 0; j < NELEM(ts); j++)
				for (size_t p = 0; p < NELEM(ps); p++)
					for (size_t q = 0; q < NELEM(rs); q++) {
						int known;
						double k = 2.0;
						double want = ref_term(term->name, ts[i], ts[j], ps[p], rs[q], k, &known);
						cr_assert(known, "%s has no reference formula in test_terms.c", term->name);
						bk_sample s = make_sample(ts[i], ts[j], ps[p], rs[q]);
						s.k = k;
						double got = term->eval(&s);
						/* different algebra and cosines from different vector code;
						 * Beckmann's exponent tan²/a² reaches ~200, amplifying ulps */
						check_close(got, want, 1e-11, 1e-300, "%s θv=%g θl=%g φ=%g r=%g", term->name, ts[i],
						            ts[j], ps[p], rs[q]);
					}
	}
}

/* ---- 9. GGX sampling ---------------------------------------------------------- */

/* Knuth's MMIX LCG, top 53 bits: a fixed stream of uniforms in [0, 1). */
static double lcg_uniform(uint64_t *state)
{
	*state = *state * 6364136223846793005ULL + 1442695040888963407ULL;
	return (double)(*state >> 11) * 0x1.0p-53;
}

/* The sampler must give H with density D(h) NoH. Under that density
 * u(θ) = tan²θ/(a² + tan²θ) (the CDF, checked against D by quadrature in
 * ndf/ggx_cdf_closed_form) is uniform on [0, 1), and φ is uniform. χ² over 20
 * equal bins has 19 degrees of freedom; 43.82 is its upper 0.1 % point, so a
 * correct sampler fails with probability 0.001 for a random seed (the seed here
 * is fixed, so the result is deterministic). */
Test(ggx_sampling, unit_upper_hemisphere_and_chi2)
{
	enum { NS = 100000, NB = 20 };
	const double chi2_crit = 43.82;
	const double as[] = {0.0025, 0.09, 0.49, 1.0};
	for (size_t i = 0; i < NELEM(as); i++) {
		double a = as[i];
		uint64_t state = 0x2545F4914F6CDD1DULL + i;
		long bins_u[NB] = {0}, bins_phi[NB] = {0};
		for (int s = 0; s < NS; s++) {
			double u1 = lcg_uniform(&state), u2 = lcg_uniform(&state), h[3];
			bk_ggx_sample_h(u1, u2, a, h);
			double len = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
			/* built from sqrt(cos²) and sqrt(1 - cos²): a few ulp from unit length */
			if (!(fabs(len - 1.0) <= 1e-15) || !(h[2] >= 0.0))
				cr_assert_fail("a=%g u=(%.17g, %.17g): h = (%g, %g, %g), |h| - 1 = %g", a, u1, u2, h[0], h[1],
				               h[2], len - 1.0);
			double s2 = h[0] * h[0] + h[1] * h[1], c2 = h[2] * h[2];
			double u = c2 > 0.0 ? s2 / (a * a * c2 + s2) : 1.0;
			int b = (int)(u * NB);
			bins_u[b < NB ? b : NB - 1]++;
			double phi = atan2(h[1], h[0]);
			if (phi < 0.0)
				phi += 2.0 * PI;
			b = (int)(phi / (2.0 * PI) * NB);
			bins_phi[b < NB ? b : NB - 1]++;
		}
		double e = (double)NS / NB, chi_u = 0.0, chi_phi = 0.0;
		for (int b = 0; b < NB; b++) {
			chi_u += (bins_u[b] - e) * (bins_u[b] - e) / e;
			chi_phi += (bins_phi[b] - e) * (bins_phi[b] - e) / e;
		}
		cr_assert(chi_u < chi2_crit, "a=%g: χ² of the θ CDF = %g >= %g (19 dof, p = 0.001)", a, chi_u, chi2_crit);
		cr_assert(chi_phi < chi2_crit, "a=%g: χ² of φ = %g >= %g (19 dof, p = 0.001)", a, chi_phi, chi2_crit);
	}
}
