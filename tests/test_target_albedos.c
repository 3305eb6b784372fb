/*
 * test_target_albedos.c — targets ms and sheen (fit/target.c), both
 * directional albedos with F = 1 over (NoV, r). ms: single-scattering GGX,
 * E(NoV, r) = ∫ D V NoL dω. sheen: Charlie D (a = r^2) with Neubelt V.
 *
 * The target's samples come from brdf/dfg.c's adaptive integrator (A + B).
 * Here E is integrated again by a different method: a tensor midpoint rule
 * over the half vector in the GGX CDF variable u (tan²θh = a² u / (1 − u),
 * D NoH dω_h = du dφ / 2π, dω_l = 4 VoH dω_h), so that
 *     E = ∫∫ V · NoL · 4 VoH / NoH  du dφ / 2π   over NoL > 0,
 * with V the exact height-correlated Smith written out here from its Λ. The
 * integrand is smooth but for the kink at the horizon, where it goes to 0
 * with NoL: the midpoint rule's error is O(h²); measured at these points,
 * 2000 × 500 cells differ from 4000 × 1000 by at most 4.3e-6, so the latter
 * are within about 1.5e-6 of E, inside the 1e-5 bound.
 */
#include "brdf.h"
#include "compare.h"
#include "target.h"

#include <criterion/criterion.h>

#include <math.h>

#define PI 3.14159265358979323846

/* Height-correlated Smith GGX: V = 1 / (4 NoV NoL (1 + Λv + Λl)), Λ from
 * Heitz 2014, Λ(μ) = (−1 + sqrt(1 + a² tan²θ)) / 2. */
static double lambda(double mu, double a)
{
	double t2 = (1 - mu * mu) / (mu * mu);
	return (-1 + sqrt(1 + a * a * t2)) / 2;
}

static double v_correlated(double NoV, double NoL, double a)
{
	return 1 / (4 * NoV * NoL * (1 + lambda(NoV, a) + lambda(NoL, a)));
}

/* E by the midpoint rule on (u, φ), φ over [0, 2π). */
static double albedo_midpoint(double NoV, double r, int nu, int nphi)
{
	double a = r * r, sv = sqrt(1 - NoV * NoV), sum = 0;
	for (int i = 0; i < nu; i++) {
		double u = (i + 0.5) / nu, t2 = a * a * u / (1 - u);
		double NoH = 1 / sqrt(1 + t2), sh = sqrt(t2) * NoH;
		for (int j = 0; j < nphi; j++) {
			double phi = 2 * PI * (j + 0.5) / nphi;
			double VoH = sv * sh * cos(phi) + NoV * NoH, NoL = 2 * VoH * NoH - NoV;
			if (NoL <= 0 || VoH <= 0)
				continue;
			sum += v_correlated(NoV, NoL, a) * NoL * 4 * VoH / NoH;
		}
	}
	return sum / ((double)nu * nphi); /* du dφ / 2π: the cell measure 1/nu · 2π/nphi / 2π */
}

/* One-cell target at (NoV, r): the cell centre is the point asked for. */
static double target_at(bk_target_kind kind, double NoV, double r, bk_samples *s)
{
	bk_target_options o;
	bk_target_defaults(kind, &o);
	o.nx = o.nr = 1;
	o.x_lo = NoV - 1e-3, o.x_hi = NoV + 1e-3;
	o.r_lo = r - 1e-3, o.r_hi = r + 1e-3;
	char err[256] = "";
	cr_assert_eq(bk_target_build(&o, s, NULL, NULL, err, sizeof err), 0, "%s", err);
	cr_assert_float_eq(s->in[BK_IN_NOV][0], NoV, 1e-15);
	cr_assert_float_eq(s->in[BK_IN_R][0], r, 1e-15);
	return s->y[0];
}

Test(target_ms, samples_are_the_albedo_by_a_second_quadrature)
{
	static const double pts[][2] = {{0.5, 0.5}, {0.9, 0.3}, {0.2, 0.8}, {0.7, 1.0}};
	for (size_t k = 0; k < sizeof pts / sizeof pts[0]; k++) {
		bk_samples s;
		double NoV = pts[k][0], r = pts[k][1];
		double got = target_at(BK_TARGET_MS, NoV, r, &s);
		double want = albedo_midpoint(NoV, r, 4000, 1000);
		cr_expect(fabs(got - want) < 1e-5, "E(%g, %g): target %.9f, midpoint %.9f", NoV, r, got, want);
		cr_expect(got > 0 && got <= 1, "E(%g, %g) = %g outside (0, 1]", NoV, r, got);
		bk_samples_free(&s);
		/* control: the check tells E at a roughness 2 % away from this one */
		double moved = albedo_midpoint(NoV, 1.02 * r, 4000, 1000);
		cr_expect(fabs(got - moved) > 1e-5, "control: E(%g, %g) = %.9f is within the bound of E at 1.02 r = %.9f",
		          NoV, r, got, moved);
	}
}

/* Physical identity: a nearly smooth mirror with F = 1 reflects all of the
 * light (E -> 1 as r -> 0, V -> 1/(4 NoV NoL) there), and rough GGX with
 * single scattering loses energy (E at r = 1, NoV = 1 is below 0.6, the
 * ~40-60 % loss energy compensation exists for). */
Test(target_ms, smooth_limit_and_rough_loss)
{
	bk_samples s;
	double e = target_at(BK_TARGET_MS, 0.6, 0.02, &s);
	bk_samples_free(&s);
	cr_expect(fabs(e - 1) < 1e-4, "E(0.6, 0.02) = %.9f, want 1", e);
	e = target_at(BK_TARGET_MS, 0.999, 0.999, &s);
	bk_samples_free(&s);
	cr_expect(e < 0.6 && e > 0.3, "E(1, 1) = %g", e);
}

/* E has no f0: the target provides NoV, r and a only, so a form reading f0
 * is refused by the fitter (the same rule as d and f). */
Test(target_ms, provides_nov_r_a_only)
{
	bk_target_options o;
	bk_target_defaults(BK_TARGET_MS, &o);
	o.nx = o.nr = 4;
	bk_samples s;
	char err[256] = "";
	cr_assert_eq(bk_target_build(&o, &s, NULL, NULL, err, sizeof err), 0, "%s", err);
	cr_expect_eq(s.provides, 1u << BK_IN_NOV | 1u << BK_IN_R | 1u << BK_IN_A);
	cr_expect_eq(s.n, 16u);
	cr_expect_eq(s.ncomp, 1);
	cr_expect(isnan(s.in[BK_IN_F0][0]));
	double wsum = 0;
	for (size_t i = 0; i < s.n; i++)
		wsum += s.w[i];
	cr_expect(fabs(wsum - 1) < 1e-12, "weights sum to %g", wsum);
	cr_expect_str_eq(bk_target_name(BK_TARGET_MS), "ms");
	bk_target_kind k;
	cr_expect_eq(bk_target_parse("ms", &k), 0);
	cr_expect_eq(k, BK_TARGET_MS);
	bk_samples_free(&s);
}

/* ---- sheen ---------------------------------------------------------------------
 * The target's samples come from bk_albedo's half-vector integrator
 * (brdf/sheen.c). Here: a midpoint rule over the light hemisphere in
 * (NoL, φ), dω = dNoL dφ, D and V written out from Estevez & Kulla 2017
 * (eq. 2, (2 + 1/a) sin^(1/a)θh / 2π) and Neubelt & Pettineo 2013
 * (1 / (4 (NoL + NoV - NoL NoV))). Measured: 2000² and 4000² cells agree to
 * the 6 decimals printed at (0.5, 0.5) and (0.1, 0.3), and to 1e-5 at
 * (0.05, 0.05), where D is narrow (hence that point's looser bound). */
static double sheen_midpoint(double NoV, double r, int n)
{
	double a = r * r, sv = sqrt(1 - NoV * NoV), sum = 0;
	for (int i = 0; i < n; i++) {
		double NoL = (i + 0.5) / n, sl = sqrt(1 - NoL * NoL);
		for (int j = 0; j < n; j++) {
			double phi = PI * (j + 0.5) / n; /* [0, π], doubled below: even in φ */
			double hx = sv + sl * cos(phi), hy = sl * sin(phi), hz = NoV + NoL;
			double NoH = hz / sqrt(hx * hx + hy * hy + hz * hz), s2 = (1 - NoH) * (1 + NoH);
			double D = (2 + 1 / a) * pow(s2, 0.5 / a) / (2 * PI), V = 1 / (4 * (NoL + NoV - NoL * NoV));
			sum += D * V * NoL;
		}
	}
	return sum * 2 * PI / ((double)n * n);
}

Test(target_sheen, samples_are_the_albedo_by_a_second_quadrature)
{
	static const double pts[][3] = {{0.5, 0.5, 1e-6}, {0.1, 0.3, 1e-6}, {0.9, 1.0, 1e-6}, {0.05, 0.05, 1e-4}};
	for (size_t k = 0; k < sizeof pts / sizeof pts[0]; k++) {
		bk_samples s;
		double NoV = pts[k][0], r = pts[k][1], tol = pts[k][2];
		double got = target_at(BK_TARGET_SHEEN, NoV, r, &s);
		bk_samples_free(&s);
		double want = sheen_midpoint(NoV, r, 4000);
		cr_expect(fabs(got - want) < tol, "sheen(%g, %g): target %.9f, midpoint %.9f", NoV, r, got, want);
		/* control: GGX's E at the same point (another lobe) is far outside the bound */
		double other = target_at(BK_TARGET_MS, NoV, r, &s);
		bk_samples_free(&s);
		cr_expect(fabs(other - want) > 100 * tol, "control: E_ggx = %g within the bound of %g", other, want);
	}
}

/* Neubelt's V is not a shadowing function's: the sheen albedo is not bounded
 * by 1. At grazing view and low roughness it is several times 1 (3.6757 at
 * NoV = r = 0.0234 by the midpoint rule above, 2000² and 4000² cells agreeing
 * to 1e-4), and the target says so rather than clamping. */
Test(target_sheen, exceeds_one_at_grazing_low_roughness)
{
	bk_samples s;
	double got = target_at(BK_TARGET_SHEEN, 0.0234, 0.0234, &s);
	bk_samples_free(&s);
	cr_expect(fabs(got - 3.6757) < 1e-3, "sheen(0.0234, 0.0234) = %.6f", got);
}

/* A DFG LUT scores ms (no f0) only as the albedo at f0 = 1, folded in one
 * channel (analysis/lutscore.c): A + B = E there. Any other layout is refused
 * rather than scored against a channel that is not E. The folded 128² float
 * LUT's error on a grid off its texel centres is interpolation alone, below
 * 0.02 (bilinear across the grazing column); control: a 16² LUT, with 8x
 * the texel spacing, fails the same bound. */
Test(target_ms, lut_scores_e_only_folded_at_f0_1)
{
	bk_target_options o;
	bk_target_defaults(BK_TARGET_MS, &o);
	o.nx = o.nr = 20;
	bk_samples s;
	char err[256] = "";
	cr_assert_eq(bk_target_build(&o, &s, NULL, NULL, err, sizeof err), 0, "%s", err);
	bk_lut_layout L = {128, 128, 0, 1, BK_LUT_WARP_NONE, 1.0};
	bk_fit_metrics m;
	cr_assert_eq(bk_lut_score_layout(&L, BK_LUT_FLOAT, BK_SMITH_CORRELATED, BK_F64, &s, &m, NULL), 0);
	cr_expect(m.max_abs < 0.02 && m.rmse < 1e-3, "folded LUT on E: max %g, rmse %g", m.max_abs, m.rmse);
	bk_lut_layout small = {16, 16, 0, 1, BK_LUT_WARP_NONE, 1.0};
	cr_assert_eq(bk_lut_score_layout(&small, BK_LUT_FLOAT, BK_SMITH_CORRELATED, BK_F64, &s, &m, NULL), 0);
	cr_expect(!(m.max_abs < 0.02 && m.rmse < 1e-3), "control: 16² LUT on E: max %g, rmse %g", m.max_abs, m.rmse);
	L.f0 = NAN;
	cr_expect_eq(bk_lut_score_layout(&L, BK_LUT_FLOAT, BK_SMITH_CORRELATED, BK_F64, &s, &m, NULL), -1);
	L.f0 = 0.04;
	cr_expect_eq(bk_lut_score_layout(&L, BK_LUT_FLOAT, BK_SMITH_CORRELATED, BK_F64, &s, &m, NULL), -1);
	bk_samples_free(&s);
}
