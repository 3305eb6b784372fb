/*
 * target.c — samples of the exact quantities a fit approximates.
 *
 * vf and spec sample the half vector on a grid in the GGX CDF variable u
 * (tan^2 θh = a^2 u / (1 - u), where D NoH dω_h = du dφ / 2π) and reflect the
 * view direction about it: the grid then follows the highlight at every
 * roughness, which a grid over the light hemisphere cannot do for r -> 0. With
 * dω_l = 4 VoH dω_h, each sample stands for
 *     D·NoL·dω_l = NoL · 4 VoH / NoH · du dφ / 2π
 * of "highlight energy", and for dω_l = 4 VoH / (D NoH) · du dφ / 2π of solid
 * angle; those are its weights (D·NoL or none) and, summed over a (NoV, r)
 * cell, they turn errors into directional-albedo errors.
 */
#include "target.h"


#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static const char *const names[BK_TARGET_COUNT] = {"vf2d", "vf",   "spec",  "env",   "d",   "f",
                                                            "form", "ms", "sheen", "table", "merl"};

const char *bk_target_name(bk_target_kind k) { return names[k]; }

int bk_target_parse(const char *name, bk_target_kind *kind)
{
	for (int k = 0; k < BK_TARGET_COUNT; k++)
		if (strcmp(name, names[k]) == 0) {
			*kind = (bk_target_kind)k;
			return 0;
		}
	return -1;
}

void bk_target_defaults(bk_target_kind kind, bk_target_options *o)
{
	memset(o, 0, sizeof *o);
	o->kind = kind;
	o->r_lo = 0.0;
	o->r_hi = 1.0;
	o->x_lo = 0.0;
	o->x_hi = 1.0;
	o->nx = o->nr = 64;
	o->nu = 32;
	o->nphi = 16;
	o->f0[0] = 0.04;
	o->nf0 = 1;
	o->smith = BK_SMITH_CORRELATED;
	o->eta = 1.5;
	switch (kind) {
	case BK_TARGET_VF2D:
		/* LoH^2 >= 0.1: the clamp Unity ships with the talk's form, without
		 * which its 1/LoH^2 pole rules a least-squares fit (see README) */
		o->x_lo = sqrt(0.1);
		o->nx = o->nr = 256;
		break;
	case BK_TARGET_VF:
	case BK_TARGET_SPEC:
		o->nx = o->nr = 16;
		break;
	case BK_TARGET_ENV:
		o->f0[0] = 0.04, o->f0[1] = 0.5, o->f0[2] = 1.0;
		o->nf0 = 3;
		break;
	case BK_TARGET_F:
		o->nx = 256;
		o->nr = 1;
		break;
	case BK_TARGET_FORM:
		o->nx = 0; /* bk_target_form_cells */
		o->nr = 1;
		break;
	case BK_TARGET_TABLE:
	case BK_TARGET_MERL:
		o->nx = 0; /* every sample of the file (build_table) */
		o->nr = 1;
		break;
	default:
		break;
	}
}

static int alloc(bk_samples *s, size_t n, char *err, size_t errlen)
{
	memset(s->in, 0, sizeof s->in);
	s->y = calloc(n ? n : 1, sizeof *s->y);
	s->w = calloc(n ? n : 1, sizeof *s->w);
	s->measure = calloc(n ? n : 1, sizeof *s->measure);
	s->cell = calloc(n ? n : 1, sizeof *s->cell);
	int ok = s->y && s->w && s->measure && s->cell;
	for (int i = 0; i < BK_IN_COUNT && ok; i++)
		ok = (s->in[i] = calloc(n ? n : 1, sizeof(double))) != NULL;
	if (!ok) {
		bk_samples_free(s);
		snprintf(err, errlen, "out of memory for %zu samples", n);
		return -1;
	}
	return 0;
}

void bk_samples_free(bk_samples *s)
{
	for (int i = 0; i < BK_IN_COUNT; i++) {
		free(s->in[i]);
		s->in[i] = NULL;
	}
	free(s->y);
	free(s->w);
	free(s->measure);
	free(s->cell);
	s->y = s->w = s->measure = NULL;
	s->cell = NULL;
}

static double centre(double lo, double hi, int i, int n) { return lo + (i + 0.5) * (hi - lo) / n; }

static void put(bk_samples *s, size_t i, double NoV, double NoL, double NoH, double LoH, double r,
                double f0)
{
	double v[BK_IN_COUNT] = {NoV, NoL, NoH, LoH, r, r * r, f0};
	for (int k = 0; k < BK_IN_COUNT; k++)
		s->in[k][i] = v[k];
}

/* Each roughness row weighs the same: its weights sum to 1/nr. */
static void normalise_rows(bk_samples *s, size_t lo, size_t hi, int nr, int nx)
{
	double *sum = calloc((size_t)nr, sizeof *sum);
	if (!sum)
		return;
	for (size_t i = lo; i < hi; i++)
		sum[s->cell[i] / nx] += s->w[i];
	for (size_t i = lo; i < hi; i++) {
		double t = sum[s->cell[i] / nx];
		s->w[i] = t > 0.0 ? s->w[i] / (t * nr) : 0.0;
	}
	free(sum);
}

static void plane(bk_samples *s, int nx, int ny, double x0, double x1, double y0, double y1,
                  const char *xn, const char *yn)
{
	/* the axes as inputs, for the fitter's check of the domain's edges */
	static const struct { const char *name; int in; } axes[] = {
		{"LoH", BK_IN_LOH}, {"NoV", BK_IN_NOV}, {"NoH", BK_IN_NOH}, {"r", BK_IN_R}};
	s->plane_x_input = s->plane_y_input = -1;
	for (size_t k = 0; k < sizeof axes / sizeof axes[0]; k++) {
		if (!strcmp(xn, axes[k].name))
			s->plane_x_input = axes[k].in;
		if (!strcmp(yn, axes[k].name))
			s->plane_y_input = axes[k].in;
	}
	s->plane_nx = nx, s->plane_ny = ny;
	s->plane_x0 = x0, s->plane_x1 = x1, s->plane_y0 = y0, s->plane_y1 = y1;
	s->plane_xname = xn, s->plane_yname = yn;
}

static int build_vf2d(const bk_target_options *o, bk_samples *s, char *err, size_t errlen)
{
	size_t n = (size_t)o->nx * o->nr, i = 0;
	if (alloc(s, n, err, errlen))
		return -1;
	double f0 = o->f0[0];
	for (int j = 0; j < o->nr; j++)
		for (int k = 0; k < o->nx; k++, i++) {
			double LoH = centre(o->x_lo, o->x_hi, k, o->nx), r = centre(o->r_lo, o->r_hi, j, o->nr);
			double talk_r = o->talk_alpha ? r * r : r;
			put(s, i, NAN, NAN, NAN, LoH, r, f0);
			s->y[i] = bk_V_kelemen_talk(LoH, talk_r) * bk_F_schlick(f0, 1.0, LoH);
			s->w[i] = 1.0;
			s->cell[i] = j * o->nx + k;
		}
	s->n = n;
	s->provides = (1u << BK_IN_LOH | 1u << BK_IN_R | 1u << BK_IN_A | 1u << BK_IN_F0);
	normalise_rows(s, 0, n, o->nr, o->nx);
	plane(s, o->nx, o->nr, o->x_lo, o->x_hi, o->r_lo, o->r_hi, "LoH", "r");
	snprintf(s->description, sizeof s->description,
	         "vf2d: the talk's modified Kelemen V = 0.25/(LoH^2 (1 - q^2) + q^2), q = %s, times Schlick F "
	         "with f0 = %g, f90 = 1, on LoH in [%g, %g] x r in [%g, %g] (%dx%d cell centres); V includes "
	         "the 1/4 the talk leaves out, so forms are written in the same units, e.g. f0/(4*LoH*LoH*(r+p0))",
	         o->talk_alpha ? "a = r^2 (the alpha reading)" : "r (perceptual)", f0, o->x_lo, o->x_hi,
	         o->r_lo, o->r_hi, o->nx, o->nr);
	return 0;
}

/* vf and spec: (r, NoV, u, φ) grid, φ in [0, π] (the integrand is even in φ). */
static int build_lobe(const bk_target_options *o, bk_samples *s, char *err, size_t errlen)
{
	size_t cap = (size_t)o->nr * o->nx * o->nu * o->nphi, i = 0;
	if (alloc(s, cap, err, errlen))
		return -1;
	int spec = o->kind == BK_TARGET_SPEC;
	bk_weight_kind wk = o->weight == BK_WEIGHT_DEFAULT ? (spec ? BK_WEIGHT_NONE : BK_WEIGHT_DNOL) : o->weight;
	double f0 = o->f0[0], du = 1.0 / o->nu, dphi = BK_PI / o->nphi;
	for (int j = 0; j < o->nr; j++) {
		double r = centre(o->r_lo, o->r_hi, j, o->nr), a = r * r, a2 = a * a;
		for (int k = 0; k < o->nx; k++) {
			double NoV = centre(o->x_lo, o->x_hi, k, o->nx), sv = sqrt((1 - NoV) * (1 + NoV));
			for (int q = 0; q < o->nu; q++) {
				double u = centre(0, 1, q, o->nu), tan2 = a2 * u / (1 - u);
				double NoH = 1 / sqrt(1 + tan2), sh = sqrt(tan2) * NoH;
				for (int p = 0; p < o->nphi; p++) {
					double phi = centre(0, BK_PI, p, o->nphi);
					double VoH = sv * sh * bk_dcos(phi) + NoV * NoH, NoL = 2 * VoH * NoH - NoV;
					if (NoL <= 0 || VoH <= 0)
						continue;
					/* ×2: φ in [0, π] stands for both halves */
					double energy = NoL * 4 * VoH / NoH * du * dphi * 2 / (2 * BK_PI);
					double D = bk_D_ggx_sin2(sh * sh, NoH, a);
					double vf = bk_V_smith_ggx_correlated(NoV, NoL, a) * bk_F_schlick(f0, 1, VoH);
					put(s, i, NoV, NoL, NoH, VoH, r, f0);
					s->y[i] = spec ? D * vf * NoL : vf;
					double solid = energy / (D * NoL); /* dω_l */
					s->measure[i] = spec ? solid : energy;
					s->w[i] = wk == BK_WEIGHT_DNOL ? energy : solid;
					s->cell[i] = j * o->nx + k;
					i++;
				}
			}
		}
	}
	s->n = i;
	s->provides = (1u << BK_IN_COUNT) - 1;
	normalise_rows(s, 0, i, o->nr, o->nx);
	plane(s, o->nx, o->nr, o->x_lo, o->x_hi, o->r_lo, o->r_hi, "NoV", "r");
	snprintf(s->description, sizeof s->description,
	         "%s: exact height-correlated Smith GGX V (1/4 included) x Schlick F (f0 = %g, f90 = 1)%s over "
	         "NoV in [%g, %g] (%d), r in [%g, %g] (%d), H on a %dx%d grid in the GGX CDF and azimuth; weight %s, "
	         "each roughness weighing the same",
	         names[o->kind], f0, spec ? " x GGX D x NoL (the whole rendered lobe)" : "", o->x_lo, o->x_hi, o->nx,
	         o->r_lo, o->r_hi, o->nr, o->nu, o->nphi,
	         wk == BK_WEIGHT_DNOL ? "D*NoL*dω (where the highlight's energy is)" : "dω (solid angle)");
	return 0;
}

/* ---- the reference integrals of env, ms and sheen (target.h) ---------------- */

size_t bk_target_reference_cells(const bk_target_options *o)
{
	int has = o->kind == BK_TARGET_ENV || o->kind == BK_TARGET_MS || o->kind == BK_TARGET_SHEEN;
	return has && o->nx > 0 && o->nr > 0 ? (size_t)o->nx * (size_t)o->nr : 0;
}

/* Cell c's centre: NoV (x below 0 reads as 0) and r. */
static void ref_centre(const bk_target_options *o, size_t c, double *NoV, double *r)
{
	int j = (int)(c / (size_t)o->nx), k = (int)(c % (size_t)o->nx);
	*NoV = centre(o->x_lo > 0 ? o->x_lo : 0.0, o->x_hi, k, o->nx);
	*r = centre(o->r_lo, o->r_hi, j, o->nr);
}

int bk_target_reference_cell(const bk_target_options *o, size_t c, double *A, double *B)
{
	double NoV, r;
	ref_centre(o, c, &NoV, &r);
	if (o->kind == BK_TARGET_SHEEN)
		return *B = 0, bk_sheen_albedo(NoV, r, 1e-8, A, NULL);
	return bk_dfg(NoV, r, o->smith, 1e-8, A, B, NULL);
}

static int ref_failed(const bk_target_options *o, size_t c, char *err, size_t errlen)
{
	double NoV, r;
	ref_centre(o, c, &NoV, &r);
	snprintf(err, errlen, "%s: reference integral failed at NoV %g, r %g", names[o->kind], NoV, r);
	return -1;
}

int bk_target_reference(const bk_target_options *o, double *AB, bk_progress_fn progress, void *ctx, char *err,
                        size_t errlen)
{
	size_t n = bk_target_reference_cells(o);
	for (size_t c = 0; c < n; c++) {
		if (bk_target_reference_cell(o, c, &AB[c], &AB[n + c]))
			return ref_failed(o, c, err, errlen);
		if (progress && (c + 1) % (size_t)o->nx == 0)
			progress(ctx, (int)((c + 1) / (size_t)o->nx), o->nr);
	}
	return 0;
}

/* Cell c's values: the options' own (o->reference) or integrated here; the
 * same bits either way. 0, or -1 with the message. */
static int ref_at(const bk_target_options *o, size_t c, double *A, double *B, char *err, size_t errlen)
{
	if (o->reference) {
		size_t n = (size_t)o->nx * (size_t)o->nr;
		*A = o->reference[c];
		*B = o->reference[n + c];
		return 0;
	}
	return bk_target_reference_cell(o, c, A, B) ? ref_failed(o, c, err, errlen) : 0;
}

static int build_env(const bk_target_options *o, bk_samples *s, bk_progress_fn progress, void *ctx,
                     char *err, size_t errlen)
{
	size_t cells = (size_t)o->nx * o->nr;
	int nf = o->env_f0_form ? o->nf0 : 2; /* in-f0 form: one sample per f0; split: A then B */
	if (alloc(s, cells * (size_t)nf, err, errlen))
		return -1;
	double x_lo = o->x_lo > 0 ? o->x_lo : 0.0;
	for (int j = 0; j < o->nr; j++) {
		double r = centre(o->r_lo, o->r_hi, j, o->nr);
		for (int k = 0; k < o->nx; k++) {
			double NoV = centre(x_lo, o->x_hi, k, o->nx), A, B;
			size_t c = (size_t)j * o->nx + k;
			if (ref_at(o, c, &A, &B, err, errlen)) {
				bk_samples_free(s);
				return -1;
			}
			for (int q = 0; q < nf; q++) {
				size_t i = (size_t)q * cells + c;
				double f0 = o->env_f0_form ? o->f0[q] : 0.0;
				put(s, i, NoV, NAN, NAN, NAN, r, o->env_f0_form ? f0 : NAN);
				s->y[i] = o->env_f0_form ? f0 * A + B : (q == 0 ? A : B);
				s->w[i] = 1.0;
				s->cell[i] = (int)c;
			}
		}
		if (progress)
			progress(ctx, j + 1, o->nr);
	}
	s->n = cells * (size_t)nf;
	s->provides = 1u << BK_IN_NOV | 1u << BK_IN_R | 1u << BK_IN_A | (o->env_f0_form ? 1u << BK_IN_F0 : 0u);
	s->ncomp = o->env_f0_form ? 1 : 2;
	for (int q = 0; q < nf; q++)
		normalise_rows(s, (size_t)q * cells, (size_t)(q + 1) * cells, o->nr, o->nx);
	if (!o->env_f0_form) {
		s->start[1] = cells;
		s->start[2] = 2 * cells;
	}
	plane(s, o->nx, o->nr, x_lo, o->x_hi, o->r_lo, o->r_hi, "NoV", "r");
	snprintf(s->description, sizeof s->description,
	         "env: split-sum environment BRDF, f0 A + B = integral of D V F NoL (GGX D, %s Smith, Schlick F, "
	         "f90 = 1), reference integrator at tol 1e-8, on NoV in [%g, %g] x r in [%g, %g] (%dx%d cell "
	         "centres); %s",
	         bk_smith_name(o->smith), x_lo, o->x_hi, o->r_lo, o->r_hi, o->nx, o->nr,
	         o->env_f0_form ? "one form in f0 fitted to f0 A + B over the f0 list" : "forms A and B share parameters");
	return 0;
}

/* ms and sheen: one directional albedo E per (NoV, r) cell, no f0.
 *
 * ms: the single-scattering GGX directional albedo with F = 1,
 *     E(NoV, r) = ∫ D V NoL dω_l = A + B,
 * the split sum's two halves added (f0 = 1 in f0 A + B): one integral per
 * cell, the DFG's. Multiple-scattering compensation (Kulla & Conty 2017,
 * Turquin 2019, Filament) reads 1 - E(μ) and E_avg = 2 ∫ E μ dμ; a fit of E
 * gives both (E_avg by the same quadrature an engine's 1-D table uses), so
 * one component, not two with shared parameters (see brdfkit-fit(1)).
 *
 * sheen: the directional albedo of the Charlie sheen lobe (Estevez & Kulla
 * 2017's D, Neubelt & Pettineo 2013's V, F = 1), bk_sheen_albedo, the
 * channel Filament bakes for cloth beside A and B; a = r^2 in D. It is what
 * a layered material scales the layer below by (1 - sheen albedo). Its
 * reference cell is E alone (the second value is not read). */
static int build_albedo(const bk_target_options *o, bk_samples *s, bk_progress_fn progress, void *ctx, char *err,
                        size_t errlen)
{
	int ms = o->kind == BK_TARGET_MS;
	size_t n = (size_t)o->nx * o->nr, i = 0;
	if (alloc(s, n, err, errlen))
		return -1;
	double x_lo = o->x_lo > 0 ? o->x_lo : 0.0;
	for (int j = 0; j < o->nr; j++) {
		double r = centre(o->r_lo, o->r_hi, j, o->nr);
		for (int k = 0; k < o->nx; k++, i++) {
			double NoV = centre(x_lo, o->x_hi, k, o->nx), A, B;
			if (ref_at(o, i, &A, &B, err, errlen)) {
				bk_samples_free(s);
				return -1;
			}
			put(s, i, NoV, NAN, NAN, NAN, r, NAN); /* F = 1: no f0 */
			s->y[i] = ms ? A + B : A;               /* ms: bk_ms_E's sum */
			s->w[i] = 1.0;
			s->cell[i] = j * o->nx + k;
		}
		if (progress)
			progress(ctx, j + 1, o->nr);
	}
	s->n = n;
	s->provides = 1u << BK_IN_NOV | 1u << BK_IN_R | 1u << BK_IN_A;
	normalise_rows(s, 0, n, o->nr, o->nx);
	plane(s, o->nx, o->nr, x_lo, o->x_hi, o->r_lo, o->r_hi, "NoV", "r");
	if (ms)
		snprintf(s->description, sizeof s->description,
		         "ms: single-scattering GGX directional albedo E = A + B = integral of D V NoL (%s Smith, F = 1), "
		         "the input of multiple-scattering compensation (1 - E), reference integrator at tol 1e-8, on NoV "
		         "in [%g, %g] x r in [%g, %g] (%dx%d cell centres)",
		         bk_smith_name(o->smith), x_lo, o->x_hi, o->r_lo, o->r_hi, o->nx, o->nr);
	else
		snprintf(s->description, sizeof s->description,
		         "sheen: directional albedo of the Charlie sheen lobe = integral of D_charlie(a = r^2) V_neubelt NoL "
		         "(Estevez & Kulla 2017, Neubelt & Pettineo 2013, F = 1), Filament's cloth DFG channel, reference "
		         "integrator at tol 1e-8, on NoV in [%g, %g] x r in [%g, %g] (%dx%d cell centres)",
		         x_lo, o->x_hi, o->r_lo, o->r_hi, o->nx, o->nr);
	return 0;
}

static int build_d(const bk_target_options *o, bk_samples *s, char *err, size_t errlen)
{
	size_t n = (size_t)o->nx * o->nr, i = 0;
	if (alloc(s, n, err, errlen))
		return -1;
	for (int j = 0; j < o->nr; j++)
		for (int k = 0; k < o->nx; k++, i++) {
			double NoH = centre(o->x_lo, o->x_hi, k, o->nx), r = centre(o->r_lo, o->r_hi, j, o->nr);
			put(s, i, NAN, NAN, NoH, NAN, r, NAN); /* D has no f0: a form reading it is refused */
			s->y[i] = bk_D_ggx(NoH, r * r);
			s->w[i] = 1.0;
			s->cell[i] = j * o->nx + k;
		}
	s->n = n;
	s->provides = 1u << BK_IN_NOH | 1u << BK_IN_R | 1u << BK_IN_A;
	normalise_rows(s, 0, n, o->nr, o->nx);
	plane(s, o->nx, o->nr, o->x_lo, o->x_hi, o->r_lo, o->r_hi, "NoH", "r");
	snprintf(s->description, sizeof s->description,
	         "d: GGX D (Walter 2007, a = r^2, normalised, 1/π included) on NoH in [%g, %g] x r in [%g, %g] "
	         "(%dx%d cell centres)", o->x_lo, o->x_hi, o->r_lo, o->r_hi, o->nx, o->nr);
	return 0;
}

static int build_f(const bk_target_options *o, bk_samples *s, char *err, size_t errlen)
{
	size_t n = (size_t)o->nx;
	if (alloc(s, n, err, errlen))
		return -1;
	double f0 = bk_f0_from_ior(o->eta, o->k);
	for (int k = 0; k < o->nx; k++) {
		double LoH = centre(o->x_lo, o->x_hi, k, o->nx);
		/* no roughness: F does not depend on it, so a form reading r or a
		 * would be fitted to a constant the target does not have */
		put(s, (size_t)k, NAN, NAN, NAN, LoH, NAN, f0);
		s->y[k] = o->k > 0 ? bk_F_conductor(LoH, o->eta, o->k) : bk_F_dielectric(LoH, o->eta);
		s->w[k] = 1.0 / o->nx;
		s->cell[k] = k;
	}
	s->n = n;
	s->provides = 1u << BK_IN_LOH | 1u << BK_IN_F0;
	plane(s, o->nx, 1, o->x_lo, o->x_hi, 0, 1, "LoH", "-");
	snprintf(s->description, sizeof s->description,
	         "f: exact unpolarised Fresnel of index %g + %gi (f0 = %.6g, the input f0 of forms) on LoH in "
	         "[%g, %g] (%d cell centres)", o->eta, o->k, f0, o->x_lo, o->x_hi, o->nx);
	return 0;
}

/* ---- form: a target given by a formula ----------------------------------- */

/* The inputs a domain gives: r gives a = r^2 too (a form in a reads it). */
static unsigned form_gives(const bk_target_options *o)
{
	unsigned g = 0;
	for (int d = 0; d < o->ndomain; d++)
		g |= 1u << o->dom_in[d];
	if (g >> BK_IN_R & 1)
		g |= 1u << BK_IN_A;
	return g;
}

static bk_form *form_parse_checked(const bk_target_options *o, char *err, size_t errlen)
{
	if (!o->form_text) {
		snprintf(err, errlen, "target form: no expression");
		return NULL;
	}
	bk_form_error fe;
	bk_form *f = bk_form_parse(o->form_text, &fe);
	if (!f) {
		snprintf(err, errlen, "target form:1:%d: %s", fe.column, fe.message);
		return NULL;
	}
	int np = bk_form_nparams(f), fail = 1;
	unsigned reads = bk_form_inputs(f), gives = 0, domain = form_gives(o);
	for (int d = 0; d < o->ndomain; d++) {
		bk_input in = (bk_input)o->dom_in[d];
		if (gives >> in & 1)
			snprintf(err, errlen, "the domain gives '%s' twice", bk_input_name(in));
		else if (in == BK_IN_A && (domain >> BK_IN_R & 1)) /* whatever the order: domain is all of it */
			snprintf(err, errlen, "the domain gives both 'r' and 'a': with r, a is r^2 (give one)");
		else if (!(reads >> in & 1) && !(in == BK_IN_R && (reads >> BK_IN_A & 1)))
			snprintf(err, errlen, "the domain gives '%s', which the target form does not read", bk_input_name(in));
		else {
			gives |= 1u << in;
			continue;
		}
		goto out;
	}
	for (int k = 0; k < BK_IN_COUNT; k++)
		if ((reads >> k & 1) && !(domain >> k & 1)) {
			snprintf(err, errlen, "the target form reads '%s', which the domain does not give (add %s=LO:HI)",
			         bk_input_name((bk_input)k), bk_input_name((bk_input)k));
			goto out;
		}
	if (np == 1)
		snprintf(err, errlen, "the target form uses p0: a target has no parameters (write its constants as numbers)");
	else if (np > 1)
		snprintf(err, errlen, "the target form uses p0..p%d: a target has no parameters (write its constants as "
		         "numbers)", np - 1);
	else if (o->ndomain == 0)
		snprintf(err, errlen, "the target form reads no input: give a form in the domain's inputs");
	else
		fail = 0;
	for (int d = 0; !fail && d < o->ndomain; d++)
		if (!(o->dom_lo[d] < o->dom_hi[d])) {
			snprintf(err, errlen, "the domain of '%s' is empty: [%g, %g]", bk_input_name((bk_input)o->dom_in[d]),
			         o->dom_lo[d], o->dom_hi[d]);
			fail = 1;
		} else if (!isfinite((o->dom_hi[d] - o->dom_lo[d]) * bk_target_form_cells(o))) {
			/* centre() computes (i + 0.5) (hi - lo) before dividing by the cells */
			snprintf(err, errlen, "the domain of '%s' is too wide: (%g - (%g)) x %d cells overflows double",
			         bk_input_name((bk_input)o->dom_in[d]), o->dom_hi[d], o->dom_lo[d], bk_target_form_cells(o));
			fail = 1;
		}
out:
	if (fail) {
		bk_form_free(f);
		return NULL;
	}
	return f;
}

int bk_target_form_check(const bk_target_options *o, char *err, size_t errlen)
{
	bk_form *f = form_parse_checked(o, err, errlen);
	bk_form_free(f);
	return f ? 0 : -1;
}

int bk_target_form_cells(const bk_target_options *o)
{
	static const int per_axis[BK_IN_COUNT] = {256, 64, 16, 8, 5, 4, 3}; /* about 4096 in all */
	if (o->nx > 0)
		return o->nx;
	return o->ndomain >= 1 && o->ndomain <= BK_IN_COUNT ? per_axis[o->ndomain - 1] : 1;
}

#define BK_FORM_MAX_SAMPLES (1u << 24)

static int build_form(const bk_target_options *o, bk_samples *s, char *err, size_t errlen)
{
	bk_form *f = form_parse_checked(o, err, errlen);
	if (!f)
		return -1;
	int n = bk_target_form_cells(o), k = o->ndomain;
	double total = pow(n, k);
	if (total > BK_FORM_MAX_SAMPLES) {
		snprintf(err, errlen, "target form: %d cells per axis over %d inputs is %.0f samples, more than %u",
		         n, k, total, BK_FORM_MAX_SAMPLES);
		bk_form_free(f);
		return -1;
	}
	size_t ns = (size_t)total;
	if (alloc(s, ns, err, errlen)) {
		bk_form_free(f);
		return -1;
	}
	for (size_t i = 0; i < ns; i++) {
		for (int q = 0; q < BK_IN_COUNT; q++)
			s->in[q][i] = NAN;
		size_t rest = i;
		for (int d = 0; d < k; d++, rest /= (size_t)n) /* the first axis varies fastest */
			s->in[o->dom_in[d]][i] = centre(o->dom_lo[d], o->dom_hi[d], (int)(rest % (size_t)n), n);
		if (!isnan(s->in[BK_IN_R][i]))
			s->in[BK_IN_A][i] = s->in[BK_IN_R][i] * s->in[BK_IN_R][i];
		s->w[i] = 1.0 / (double)ns;
		s->cell[i] = k <= 2 ? (int)i : 0;
	}
	s->n = ns;
	s->provides = form_gives(o);
	int rc = bk_form_eval(f, BK_F64, ns, (const double *const *)s->in, NULL, s->y);
	for (size_t i = 0; rc == 0 && i < ns; i++)
		if (!isfinite(s->y[i])) {
			char where[256];
			size_t w = 0;
			where[0] = '\0';
			for (int d = 0; d < k && w < sizeof where; d++)
				w += (size_t)snprintf(where + w, sizeof where - w, "%s%s = %.9g", d ? ", " : "",
				                      bk_input_name((bk_input)o->dom_in[d]), s->in[o->dom_in[d]][i]);
			snprintf(err, errlen, "the target form is %g at %s (sample %zu of %zu): a target must be finite on "
			         "its domain", s->y[i], where, i + 1, ns);
			rc = -1;
		}
	if (rc) {
		if (!*err)
			snprintf(err, errlen, "target form: evaluation failed");
		bk_form_free(f);
		bk_samples_free(s);
		return -1;
	}
	bk_form_free(f);
	/* the plane: one axis (n x 1), two (n x n); three or more have none */
	const char *xn = bk_input_name((bk_input)o->dom_in[0]), *yn = k >= 2 ? bk_input_name((bk_input)o->dom_in[1]) : "-";
	if (k == 1)
		plane(s, n, 1, o->dom_lo[0], o->dom_hi[0], 0, 1, xn, yn);
	else
		plane(s, k == 2 ? n : 1, k == 2 ? n : 1, o->dom_lo[0], o->dom_hi[0], o->dom_lo[1], o->dom_hi[1], xn, yn);
	s->plane_x_input = o->dom_in[0];
	s->plane_y_input = k >= 2 ? o->dom_in[1] : -1;
	size_t w = (size_t)snprintf(s->description, sizeof s->description, "form: %.240s%s evaluated in double on ",
	                            o->form_text, strlen(o->form_text) > 240 ? "..." : "");
	for (int d = 0; d < k && w < sizeof s->description; d++)
		w += (size_t)snprintf(s->description + w, sizeof s->description - w, "%s%s in [%g, %g]", d ? " x " : "",
		                      bk_input_name((bk_input)o->dom_in[d]), o->dom_lo[d], o->dom_hi[d]);
	if (w < sizeof s->description)
		snprintf(s->description + w, sizeof s->description - w, " (%d cell centres per axis%s); uniform weight", n,
		         s->provides >> BK_IN_R & 1 ? ", a = r^2" : "");
	for (char *c = s->description; *c; c++) /* a form read from a file may span lines; headers are one */
		if (*c == '\n' || *c == '\r' || *c == '\t')
			*c = ' ';
	return 0;
}

/* ---- table, merl: samples a reader made --------------------------------- */

/* Every stride-th of n values (stride 1: all of them). */
static int copy_array(double **dst, const double *src, size_t n, size_t stride)
{
	if (!src)
		return 0;
	size_t m = (n + stride - 1) / stride;
	*dst = malloc(m ? m * sizeof **dst : 1);
	for (size_t i = 0; *dst && i < m; i++)
		(*dst)[i] = src[i * stride];
	return *dst ? 0 : -1;
}

/* table, merl: the reader's samples; nx > 0 keeps at most about nx of them,
 * every stride-th in the file's order (search's screening: a MERL file's
 * million samples would make each of its many small fits slow), the weights
 * rescaled to sum to 1 again. */
static int build_table(const bk_target_options *o, bk_samples *s, char *err, size_t errlen)
{
	const bk_samples *t = o->table;
	if (!t || !t->n) {
		snprintf(err, errlen, "target %s: no samples were read", names[o->kind]);
		return -1;
	}
	*s = *t; /* the plane, the description, provides; arrays copied below */
	memset(s->in, 0, sizeof s->in);
	s->y = s->w = s->measure = NULL;
	s->cell = NULL;
	size_t stride = o->nx > 0 && t->n > (size_t)o->nx ? (t->n + (size_t)o->nx - 1) / (size_t)o->nx : 1;
	size_t n = (t->n + stride - 1) / stride;
	int bad = 0;
	for (int k = 0; k < BK_IN_COUNT; k++)
		bad |= copy_array(&s->in[k], t->in[k], t->n, stride);
	bad |= copy_array(&s->y, t->y, t->n, stride) | copy_array(&s->w, t->w, t->n, stride) |
	       copy_array(&s->measure, t->measure, t->n, stride);
	s->cell = malloc(n * sizeof *s->cell);
	if (bad || !s->cell || !s->y || !s->w || !s->measure) {
		bk_samples_free(s);
		snprintf(err, errlen, "out of memory for %zu samples", n);
		return -1;
	}
	s->n = n;
	double wsum = 0;
	for (size_t i = 0; i < n; i++) {
		s->cell[i] = t->cell[i * stride];
		wsum += s->w[i];
	}
	for (size_t i = 0; i < n; i++) /* uniform (--weight none), or the file's rescaled to sum to 1 */
		s->w[i] = o->weight == BK_WEIGHT_NONE || !(wsum > 0) ? 1.0 / (double)n : s->w[i] / wsum;
	size_t len = strlen(s->description);
	if (stride > 1 && len + 60 < sizeof s->description)
		len += (size_t)snprintf(s->description + len, sizeof s->description - len,
		                        "; one sample in %zu (%zu)", stride, n);
	if (o->weight == BK_WEIGHT_NONE && len + 45 < sizeof s->description)
		snprintf(s->description + len, sizeof s->description - len, "; weights replaced: uniform (--weight none)");
	return 0;
}

int bk_target_build(const bk_target_options *o, bk_samples *s, bk_progress_fn progress, void *ctx,
                    char *err, size_t errlen)
{
	memset(s, 0, sizeof *s);
	s->ncomp = 1;
	int rc;
	switch (o->kind) {
	case BK_TARGET_VF2D: rc = build_vf2d(o, s, err, errlen); break;
	case BK_TARGET_VF:
	case BK_TARGET_SPEC: rc = build_lobe(o, s, err, errlen); break;
	case BK_TARGET_ENV: rc = build_env(o, s, progress, ctx, err, errlen); break;
	case BK_TARGET_D: rc = build_d(o, s, err, errlen); break;
	case BK_TARGET_F: rc = build_f(o, s, err, errlen); break;
	case BK_TARGET_FORM: rc = build_form(o, s, err, errlen); break;
	case BK_TARGET_MS:
	case BK_TARGET_SHEEN: rc = build_albedo(o, s, progress, ctx, err, errlen); break;
	case BK_TARGET_TABLE:
	case BK_TARGET_MERL: rc = build_table(o, s, err, errlen); break;
	default: snprintf(err, errlen, "unknown target"); return -1;
	}
	if (rc == 0 && s->ncomp == 1) {
		s->start[0] = 0;
		s->start[1] = s->n;
	}
	return rc;
}

size_t bk_target_samples(const bk_target_options *o)
{
	size_t cells = (size_t)o->nx * (size_t)o->nr, n = 1;
	switch (o->kind) {
	case BK_TARGET_VF:
	case BK_TARGET_SPEC: return cells * (size_t)o->nu * (size_t)o->nphi; /* build_lobe's cap */
	case BK_TARGET_ENV: return cells * (size_t)(o->env_f0_form ? o->nf0 : 2);
	case BK_TARGET_F: return (size_t)o->nx;
	case BK_TARGET_FORM:
		for (int d = 0; d < o->ndomain; d++)
			n *= (size_t)bk_target_form_cells(o);
		return n;
	case BK_TARGET_TABLE:
	case BK_TARGET_MERL:
		n = o->table ? o->table->n : 0;
		return o->nx > 0 && n > (size_t)o->nx ? (n + (n + (size_t)o->nx - 1) / (size_t)o->nx - 1) /
		                                            ((n + (size_t)o->nx - 1) / (size_t)o->nx) : n;
	default: return cells; /* vf2d, d */
	}
}

static double seconds_now(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* The cost of an integral varies with NoV and r (grazing and smooth cells
 * need more panels), so the sample spreads over both: cells at 1/8, 3/8,
 * 5/8, 7/8 of each axis, the same tolerance as build_env. */
double bk_target_estimate(const bk_target_options *o, double *integrals)
{
	*integrals = 0;
	if (o->kind != BK_TARGET_ENV && o->kind != BK_TARGET_MS && o->kind != BK_TARGET_SHEEN)
		return 0;
	*integrals = (double)o->nx * (double)o->nr;
	double x_lo = o->x_lo > 0 ? o->x_lo : 0.0, t0 = seconds_now(), A, B;
	for (int j = 0; j < 4; j++)
		for (int k = 0; k < 4; k++)
			if (o->kind == BK_TARGET_SHEEN)
				bk_sheen_albedo(centre(x_lo, o->x_hi, k, 4), centre(o->r_lo, o->r_hi, j, 4), 1e-8, &A, NULL);
			else /* env and ms: the DFG's integral */
				bk_dfg(centre(x_lo, o->x_hi, k, 4), centre(o->r_lo, o->r_hi, j, 4), o->smith, 1e-8, &A, &B, NULL);
	return (seconds_now() - t0) / 16 * *integrals;
}
