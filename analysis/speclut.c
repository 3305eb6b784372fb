/*
 * speclut.c — the low tier's specular LUT: layout, bake, the lookup as a GPU
 * does it, its score on the spec target, its ALU ops and its files
 * (speclut.h has the contract and the conventions).
 */
#include "speclut.h"
#include "prov.h"
#include "exr.h"
#include "out.h"
#include "pngio.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Sub-texel precision of the bilinear weights: the rule of lutscore.c (8
 * fractional bits, D3D11_SUBTEXEL_FRACTIONAL_BIT_COUNT and the CUDA guide's
 * 9-bit fixed-point weights), the texel-space coordinate rounded to 1/256. */
#define SUBTEXEL_STEPS 256

const char *bk_speclut_axis_name(bk_speclut_axis a)
{
	return a == BK_SPECLUT_NOH ? "noh" : a == BK_SPECLUT_ROL ? "rol" : "?";
}

const char *bk_speclut_fresnel_name(bk_speclut_fresnel f)
{
	return f == BK_SPECLUT_F_NONE ? "none" : f == BK_SPECLUT_F_SCHLICK ? "schlick" : "?";
}

int bk_speclut_axis_parse(const char *s, bk_speclut_axis *a)
{
	for (int k = 0; k < BK_SPECLUT_AXES; k++)
		if (!strcmp(s, bk_speclut_axis_name((bk_speclut_axis)k))) {
			*a = (bk_speclut_axis)k;
			return 0;
		}
	return -1;
}

int bk_speclut_fresnel_parse(const char *s, bk_speclut_fresnel *f)
{
	for (int k = 0; k < BK_SPECLUT_FRESNELS; k++)
		if (!strcmp(s, bk_speclut_fresnel_name((bk_speclut_fresnel)k))) {
			*f = (bk_speclut_fresnel)k;
			return 0;
		}
	return -1;
}

const char *bk_speclut_check(const bk_speclut *L)
{
	if (!L || (unsigned)L->axis >= BK_SPECLUT_AXES)
		return "unknown axis";
	if (L->warp < 1 || L->warp > BK_SPECLUT_MAX_WARP)
		return "warp power outside 1..16";
	if (L->nu < 2 || L->nr < 2 || L->nu > BK_SPECLUT_MAX_SIZE || L->nr > BK_SPECLUT_MAX_SIZE)
		return "size outside 2..4096";
	if (!(L->r_lo >= 0 && L->r_lo < L->r_hi && L->r_hi <= 1))
		return "roughness range not 0 <= LO < HI <= 1";
	if (!(L->scale > 0 && isfinite(L->scale)))
		return "scale not a positive number";
	if ((unsigned)L->fresnel >= BK_SPECLUT_FRESNELS)
		return "unknown fresnel";
	if ((unsigned)L->fmt >= BK_LUT_FORMATS)
		return "unknown format";
	return NULL;
}

/* The scales at which every texel of L's layout is 0 or a finite normal
 * float32, whatever L's own scale: the texel is intensity/scale cast to float
 * (spec.exr), so the largest intensity bounds the scale from below (FLT_MAX)
 * and the smallest non-zero one from above (FLT_MIN); the shader constant is
 * the scale itself, a normal float too: [FLT_MIN, FLT_MAX]. Inward by 1 %
 * of the bound, past double's rounding of the quotient and printing to 3
 * digits. raw: the texels at L's scale (bk_speclut_bake). */
static void scale_range(const bk_speclut *L, const double *raw, size_t n, double *lo, double *hi)
{
	double imax = 0, imin = INFINITY;
	for (size_t k = 0; k < n; k++) {
		double t = raw[k] * L->scale;
		imax = fmax(imax, t);
		if (t > 0)
			imin = fmin(imin, t);
	}
	*lo = fmax(FLT_MIN, imax / FLT_MAX) * 1.01;
	*hi = fmin(FLT_MAX, imin / FLT_MIN) * 0.99;
}

/* bk_speclut_float_check on texels raw already baked. */
static int float_bad(const bk_speclut *L, const double *raw, char *why, size_t len)
{
	size_t n = (size_t)L->nu * (size_t)L->nr, inf = 0, sub = 0;
	for (size_t k = 0; k < n; k++) {
		float t = (float)raw[k];
		inf += isinf(t) || isnan(t);
		sub += raw[k] != 0 && fabsf(t) < FLT_MIN;
	}
	float s = (float)L->scale;
	int bad_s = !(isfinite(s) && s >= FLT_MIN);
	if (inf || sub || bad_s) {
		double lo, hi;
		scale_range(L, raw, n, &lo, &hi);
		char what[160];
		if (inf)
			snprintf(what, sizeof what, "%zu of %zu texels are +inf in float32", inf, n);
		else if (sub)
			snprintf(what, sizeof what, "%zu of %zu texels are 0 or subnormal in float32", sub, n);
		else
			snprintf(what, sizeof what, "the shader constant %g is %s in float32", L->scale, s == 0 ? "0" : "subnormal");
		snprintf(why, len, "%s; this LUT's texels and constant are normal floats for a scale in [%.3g, %.3g]", what,
		         lo, hi);
	}
	return inf || sub || bad_s;
}

int bk_speclut_float_check(const bk_speclut *L, char *why, size_t len)
{
	if (bk_speclut_check(L))
		return -1;
	double *raw = malloc((size_t)L->nu * (size_t)L->nr * sizeof *raw);
	if (!raw)
		return -1;
	bk_speclut_bake(L, raw, NULL);
	int rc = float_bad(L, raw, why, len);
	free(raw);
	return rc;
}

void bk_speclut_name(const bk_speclut *L, char *buf, size_t len)
{
	snprintf(buf, len, "spec LUT %dx%d %s %s^%d /%g%s", L->nu, L->nr, bk_lut_format_name(L->fmt),
	         bk_speclut_axis_name(L->axis), L->warp, L->scale, L->fresnel == BK_SPECLUT_F_SCHLICK ? " schlick" : "");
}

double bk_speclut_texel_x(const bk_speclut *L, int i)
{
	double u = (i + 0.5) / L->nu;
	return L->warp == 1 ? u : bk_dpow(u, 1.0 / L->warp);
}

double bk_speclut_texel_r(const bk_speclut *L, int j)
{
	return L->r_lo + (j + 0.5) / L->nr * (L->r_hi - L->r_lo);
}

double bk_speclut_noh(bk_speclut_axis axis, double x)
{
	/* in the plane of incidence angle(R, L) = 2 angle(N, H): x = cos 2θ = 2 NoH^2 - 1 */
	return axis == BK_SPECLUT_ROL ? sqrt(0.5 * (1 + x)) : x;
}

double bk_speclut_intensity(bk_speclut_axis axis, double x, double r)
{
	return bk_D_ggx(bk_speclut_noh(axis, x), r * r) * 0.25;
}

double bk_speclut_rol(double NoV, double NoL, double VoH)
{
	return 2 * NoV * NoL - (2 * VoH * VoH - 1);
}

static double quantise(double x, bk_lut_format fmt)
{
	switch (fmt) {
	case BK_LUT_UNORM8: return round(fmin(fmax(x, 0.0), 1.0) * 255.0) / 255.0; /* the GPU's UNORM conversion */
	case BK_LUT_HALF: return bk_half_round(x);
	default: return (float)x;
	}
}

int bk_speclut_bake(const bk_speclut *L, double *raw, double *stored)
{
	if (bk_speclut_check(L))
		return -1;
	for (int j = 0; j < L->nr; j++) {
		double r = bk_speclut_texel_r(L, j);
		for (int i = 0; i < L->nu; i++) {
			size_t k = (size_t)j * (size_t)L->nu + (size_t)i;
			double t = bk_speclut_intensity(L->axis, bk_speclut_texel_x(L, i), r) / L->scale;
			if (raw)
				raw[k] = t;
			if (stored)
				stored[k] = quantise(t, L->fmt);
		}
	}
	return 0;
}

static int clampi(int i, int n) { return i < 0 ? 0 : i >= n ? n - 1 : i; }

/* One axis of the filter: x to texel space (centres on integers), the
 * coordinate to 8-bit fixed point, the two texels clamped to the edge, and
 * the weight of the second. */
static double axis_weight(double x, int n, int *i0, int *i1)
{
	double u = fmin(fmax(x * n - 0.5, -1.0), (double)n); /* beyond, the clamp gives the same */
	u = round(u * SUBTEXEL_STEPS) / SUBTEXEL_STEPS;
	double f = floor(u);
	*i0 = clampi((int)f, n);
	*i1 = clampi((int)f + 1, n);
	return u - f;
}

static double lerp(double a, double b, double t) { return a + t * (b - a); }

double bk_speclut_fetch(const bk_speclut *L, const double *tex, double u, double v)
{
	if (isnan(u) || isnan(v))
		return NAN;
	int i0, i1, j0, j1;
	double s = axis_weight(u, L->nu, &i0, &i1), w = axis_weight(v, L->nr, &j0, &j1);
	const double *row0 = tex + (size_t)j0 * (size_t)L->nu, *row1 = tex + (size_t)j1 * (size_t)L->nu;
	return lerp(lerp(row0[i0], row0[i1], s), lerp(row1[i0], row1[i1], s), w);
}

static double in_prec(double x, bk_precision p)
{
	return p == BK_F16 ? bk_half_round(x) : p == BK_F32 ? (double)(float)x : x;
}

double bk_speclut_shade(const bk_speclut *L, const double *tex, bk_precision prec, double NoV, double NoL,
                        double NoH, double VoH, double r, double f0)
{
	double x;
	if (L->axis == BK_SPECLUT_ROL) { /* dot(R, L), then saturate */
		double rol = prec == BK_F64 ? bk_speclut_rol(NoV, NoL, VoH) : in_prec(bk_speclut_rol(NoV, NoL, VoH), prec);
		x = fmin(fmax(rol, 0.0), 1.0);
	} else {
		x = in_prec(NoH, prec);
	}
	double u = x; /* x^p by repeated products, each rounded in the shader's precision */
	for (int k = 1; k < L->warp; k++)
		u = in_prec(u * x, prec);
	double v = (r - L->r_lo) / (L->r_hi - L->r_lo);
	if (prec != BK_F64) { /* v = r*k + c, one fused multiply-add, as lutscore.c's remap */
		double y = in_prec(r, prec), k = in_prec(1 / (L->r_hi - L->r_lo), prec);
		v = L->r_lo > 0 || L->r_hi < 1 ? in_prec(y * k + in_prec(-L->r_lo * (1 / (L->r_hi - L->r_lo)), prec), prec) : y;
	}
	double t = in_prec(bk_speclut_fetch(L, tex, u, v), prec);
	double F = L->fresnel == BK_SPECLUT_F_SCHLICK ? in_prec(bk_F_schlick(f0, 1, VoH), prec) : in_prec(f0, prec);
	return in_prec(in_prec(in_prec(t * L->scale, prec) * in_prec(NoL, prec), prec) * F, prec);
}

int bk_speclut_score(const bk_speclut *L, bk_precision prec, const bk_samples *s, bk_fit_metrics *m,
                     double *plane)
{
	unsigned need = 1u << BK_IN_NOV | 1u << BK_IN_NOL | 1u << BK_IN_NOH | 1u << BK_IN_LOH | 1u << BK_IN_R |
	                1u << BK_IN_F0;
	if (bk_speclut_check(L) || !s || !m || !s->n || (s->provides & need) != need ||
	    (prec != BK_F64 && prec != BK_F32 && prec != BK_F16))
		return -1;
	size_t n = (size_t)L->nu * (size_t)L->nr;
	double *tex = malloc(n * sizeof *tex), *v = malloc(s->n * sizeof *v);
	if (!tex || !v || bk_speclut_bake(L, NULL, tex)) {
		free(tex);
		free(v);
		return -1;
	}
	for (size_t i = 0; i < s->n; i++)
		v[i] = bk_speclut_shade(L, tex, prec, s->in[BK_IN_NOV][i], s->in[BK_IN_NOL][i], s->in[BK_IN_NOH][i],
		                        s->in[BK_IN_LOH][i], s->in[BK_IN_R][i], s->in[BK_IN_F0][i]);
	bk_samples_metrics(s, v, NULL, m);
	m->cost = NAN;
	if (plane)
		bk_samples_plane_error(s, v, plane);
	free(tex);
	free(v);
	return 0;
}

static double x_of(const bk_speclut *L, double NoV, double NoL, double NoH, double VoH)
{
	return L->axis == BK_SPECLUT_ROL ? fmin(fmax(bk_speclut_rol(NoV, NoL, VoH), 0.0), 1.0) : NoH;
}

double bk_speclut_model(const bk_speclut *L, double NoV, double NoL, double NoH, double VoH, double r, double f0)
{
	double F = L->fresnel == BK_SPECLUT_F_SCHLICK ? bk_F_schlick(f0, 1, VoH) : f0;
	return bk_speclut_intensity(L->axis, x_of(L, NoV, NoL, NoH, VoH), r) * NoL * F;
}

int bk_speclut_score_storage(const bk_speclut *L, const bk_samples *s, bk_fit_metrics *m, double *plane)
{
	if (bk_speclut_check(L) || !s || !s->n)
		return -1;
	bk_samples t = *s; /* the same samples, y the function the LUT encodes */
	double *y = malloc(s->n * sizeof *y);
	if (!y)
		return -1;
	for (size_t i = 0; i < s->n; i++)
		y[i] = bk_speclut_model(L, s->in[BK_IN_NOV][i], s->in[BK_IN_NOL][i], s->in[BK_IN_NOH][i],
		                        s->in[BK_IN_LOH][i], s->in[BK_IN_R][i], s->in[BK_IN_F0][i]);
	t.y = y;
	int rc = bk_speclut_score(L, BK_F64, &t, m, plane);
	free(y);
	return rc;
}

double bk_speclut_plane_rms(const bk_samples *s, const double *plane)
{
	size_t n = (size_t)s->plane_nx * (size_t)s->plane_ny, k, used = 0;
	double sum = 0;
	for (k = 0; k < n; k++)
		if (isfinite(plane[k])) {
			sum += plane[k] * plane[k];
			used++;
		}
	return used ? sqrt(sum / (double)used) : NAN;
}

int bk_speclut_plane_albedo(const bk_samples *s, double *albedo)
{
	size_t n = (size_t)s->plane_nx * (size_t)s->plane_ny;
	double *zero = calloc(s->n ? s->n : 1, sizeof *zero);
	if (!zero)
		return -1;
	bk_samples_plane_error(s, zero, albedo); /* 0 - exact, per cell */
	for (size_t k = 0; k < n; k++)
		albedo[k] = -albedo[k];
	free(zero);
	return 0;
}

double bk_speclut_plane_rel_rms(const bk_samples *s, const double *plane, const double *albedo)
{
	size_t n = (size_t)s->plane_nx * (size_t)s->plane_ny, used = 0;
	double sum = 0;
	for (size_t k = 0; k < n; k++)
		if (isfinite(albedo[k]) && albedo[k] > 0) { /* a cell with samples and energy */
			if (!isfinite(plane[k]))
				return HUGE_VAL; /* L7: a LUT with no value in a cell is not scored without it */
			double e = plane[k] / albedo[k];
			sum += e * e;
			used++;
		}
	return used ? sqrt(sum / (double)used) : NAN;
}

int bk_speclut_ops(const bk_speclut *L, bk_ops *ops)
{
	memset(ops, 0, sizeof *ops);
	if (bk_speclut_check(L))
		return -1;
	char coord[64];
	/* the coordinate, x standing in as NoH (an input: its own cost is free) */
	snprintf(coord, sizeof coord, L->axis == BK_SPECLUT_ROL ? "saturate(NoH)^%d" : "NoH^%d", L->warp);
	if (L->axis == BK_SPECLUT_ROL) { /* dot(R, L) on a scalar ALU: mul + 2 mad */
		ops->n[BK_K_MUL] += 1;
		ops->n[BK_K_MAD] += 2;
		ops->simple += 3;
	}
	/* the multiply back (f0 an input: a scene with one f0 could fold s f0 into one constant, one mul less) */
	const char *back = L->fresnel == BK_SPECLUT_F_SCHLICK ? "p0*16*NoL*F_schlick(f0, 1, LoH)" : "p0*16*NoL*f0";
	/* the rows over r_lo..r_hi: v = r*k + c, one multiply-add */
	const char *v = L->r_lo > 0 || L->r_hi < 1 ? "r*p1 + p2" : "r";
	return bk_form_count_add(coord, ops) || bk_form_count_add(back, ops) || bk_form_count_add(v, ops) ? -1 : 0;
}

void bk_speclut_describe(const bk_speclut *L, char *axes, size_t alen, char *texel, size_t tlen, char *shader,
                         size_t slen)
{
	const char *xname = L->axis == BK_SPECLUT_ROL ? "x = saturate(R.L), R = reflect(-V, N)" : "x = N.H";
	snprintf(axes, alen,
	         "u (first index, across a scanline): %s, u = x^%d at texel centres u = (i + 0.5)/%d (texel i holds "
	         "x = u^(1/%d)); v (scanlines): v = (r - %.9g)/%.9g at texel centres v = (j + 0.5)/%d, r perceptual "
	         "roughness (GGX alpha = r^2); scanline 0 (first in file, top as displayed) holds v = 0.5/%d; "
	         "uv (0,0) = first texel; sample bilinear, clamp to edge",
	         xname, L->warp, L->nu, L->warp, L->r_lo, L->r_hi - L->r_lo, L->nr, L->nr);
	snprintf(texel, tlen,
	         "texel = D_ggx(NoH(x), r^2) * V / %g, V = 1/4 (the implicit geometric term G = NoL NoV), D GGX "
	         "(Walter 2007, 1/pi included); NoH(x) = %s; no f0, no Fresnel in the texel; linear data, never "
	         "load as sRGB",
	         L->scale, L->axis == BK_SPECLUT_ROL ? "sqrt((1 + x)/2), exact only in the plane of incidence" : "x");
	snprintf(shader, slen, "specular = texel(u, v) * %g * NoL * %s", L->scale,
	         L->fresnel == BK_SPECLUT_F_SCHLICK ? "F_schlick(f0, 1, LoH) (f90 = 1, in the shader's ALU)"
	                                            : "f0 (the specular colour; no Fresnel, as in the talk)");
}

/* ---- files -------------------------------------------------------------------- */

static void write_csv(FILE *f, const bk_speclut *L, const double *raw, const char *axes, const char *texel,
                      const char *shader, const char *command)
{
	bk_prov_title(f, "specular LUT, %dx%d, scale %g, warp %d, axis %s", L->nu, L->nr, L->scale, L->warp,
	              bk_speclut_axis_name(L->axis));
	fprintf(f, "# axes: %s\n# texel: %s\n# shader: %s\n", axes, texel, shader);
	fputs("# columns: i, j texel indices (j = scanline); x the axis value and noh = NoH(x) at the centre; r; "
	      "intensity = D*V with V = 1/4 (before the scale); float = intensity/scale (spec.exr); "
	      "unorm8 = round(saturate(float)*255) (spec.png)\n", f);
	bk_prov_command(f, command);
	fputs("i,j,x,noh,r,intensity,float,unorm8\n", f);
	for (int j = 0; j < L->nr; j++)
		for (int i = 0; i < L->nu; i++) {
			size_t k = (size_t)j * (size_t)L->nu + (size_t)i;
			double x = bk_speclut_texel_x(L, i);
			fprintf(f, "%d,%d,%.9g,%.9g,%.9g,%.9g,%.9g,%d\n", i, j, x, bk_speclut_noh(L->axis, x),
			        bk_speclut_texel_r(L, j), raw[k] * L->scale, raw[k],
			        (int)round(fmin(fmax(raw[k], 0.0), 1.0) * 255.0));
		}
}

int bk_speclut_write(const bk_speclut *L, const char *dir, const char *command, char *err, size_t errlen)
{
	char csv[4200], exr_path[4200], png_path[4200], axes[700], texel[400], shader[200], layout[200];
	snprintf(csv, sizeof csv, "%.4000s/" BK_SPECLUT_CSV, dir);
	snprintf(exr_path, sizeof exr_path, "%.4000s/" BK_SPECLUT_EXR, dir);
	snprintf(png_path, sizeof png_path, "%.4000s/" BK_SPECLUT_PNG, dir);
	const char *bad = bk_speclut_check(L);
	if (bad) {
		snprintf(err, errlen, "%s: %s", exr_path, bad);
		return -1;
	}
	size_t n = (size_t)L->nu * (size_t)L->nr;
	double *raw = malloc(n * sizeof *raw);
	float *fl = malloc(n * sizeof *fl);
	unsigned char *codes = malloc(n);
	if (!raw || !fl || !codes) {
		free(raw);
		free(fl);
		free(codes);
		snprintf(err, errlen, "%s: out of memory", exr_path);
		return -1;
	}
	bk_speclut_bake(L, raw, NULL);
	/* a file that holds +inf where its CSV lists a number is never written
	 * (H3): the command refuses such a scale first, this is the last guard */
	char why[300];
	if (float_bad(L, raw, why, sizeof why)) {
		snprintf(err, errlen, "%s: scale %g: %s", exr_path, L->scale, why);
		free(raw);
		free(fl);
		free(codes);
		return -1;
	}
	for (size_t k = 0; k < n; k++) {
		fl[k] = (float)raw[k];
		codes[k] = (unsigned char)round(fmin(fmax(raw[k], 0.0), 1.0) * 255.0);
	}
	bk_speclut_describe(L, axes, sizeof axes, texel, sizeof texel, shader, sizeof shader);
	snprintf(layout, sizeof layout, "axis=%s warp=%d width=%d height=%d r_lo=%.9g r_hi=%.9g scale=%.9g fresnel=%s",
	         bk_speclut_axis_name(L->axis), L->warp, L->nu, L->nr, L->r_lo, L->r_hi, L->scale,
	         bk_speclut_fresnel_name(L->fresnel));
	const char *cmd = command ? command : "";
	int rc = 0;
	bk_out co, po;
	if (bk_out_open(&co, csv, err, errlen))
		rc = -1;
	if (rc == 0) {
		write_csv(co.f, L, raw, axes, texel, shader, cmd);
		const bk_exr_attr attrs[] = {
			{"brdfkit:version", BK_EXR_ATTR_STRING, BK_VERSION, 0},
			{"brdfkit:layout", BK_EXR_ATTR_STRING, layout, 0},
			{"brdfkit:axes", BK_EXR_ATTR_STRING, axes, 0},
			{"brdfkit:texel", BK_EXR_ATTR_STRING, texel, 0},
			{"brdfkit:shader", BK_EXR_ATTR_STRING, shader, 0},
			{"brdfkit:warp", BK_EXR_ATTR_INT, NULL, L->warp},
			{"brdfkit:command", BK_EXR_ATTR_STRING, cmd, 0},
		};
		const char *names[1] = {"R"};
		const float *data[1] = {fl};
		rc = bk_exr_write(exr_path, L->nu, L->nr, 1, names, data, 0, attrs, (int)(sizeof attrs / sizeof attrs[0]),
		                  err, errlen);
		if (rc)
			bk_out_abort(&co);
	}
	if (rc == 0 && bk_out_open(&po, png_path, err, errlen)) {
		bk_out_abort(&co);
		rc = -1;
	} else if (rc == 0) {
		char unorm[160];
		snprintf(unorm, sizeof unorm, "8-bit UNORM: code/255 = texel (saturated to [0, 1], so intensities above %g "
		         "are cut); upload as a linear R8/L8 texture", L->scale);
		const bk_png_text text[] = {
			{"Title", "brdfkit specular LUT"},
			{"Software", "brdfkit " BK_VERSION},
			{"brdfkit:layout", layout},
			{"brdfkit:axes", axes},
			{"brdfkit:texel", texel},
			{"brdfkit:storage", unorm},
			{"brdfkit:shader", shader},
			{"brdfkit:command", cmd},
		};
		char e2[256];
		/* 8-bit grey, the UNORM8 codes; no colour chunk: linear data */
		if (bk_png_write(po.f, L->nu, L->nr, 1, 0, 0, codes, text, (int)(sizeof text / sizeof text[0]), e2, sizeof e2)) {
			snprintf(err, errlen, "%s: %s", png_path, e2);
			bk_out_abort(&po);
			bk_out_abort(&co);
			rc = -1;
		} else if (bk_out_commit(&po, err, errlen)) {
			bk_out_abort(&co);
			rc = -1;
		} else {
			rc = bk_out_commit(&co, err, errlen);
		}
	}
	free(raw);
	free(fl);
	free(codes);
	return rc;
}
