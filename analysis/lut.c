/*
 * lut.c — writing the DFG LUT. The most reported LUT bugs in engines' trackers
 * are flipped axes, alpha-vs-roughness mix-ups and LUTs loaded as sRGB, so the
 * EXR header says which is which, and the CSV carries the same in comments.
 */
#include "lut.h"
#include "prov.h"
#include "out.h"
#include "exr.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const smith_text[BK_SMITH_COUNT] = {
	"correlated: exact height-correlated Smith GGX (Heitz 2014)",
	"separable: exact separable Smith GGX, G1(v) G1(l)",
	"schlick: Schlick-GGX with k = a/2 (Karis 2013)",
};

/* The engines' usual layout: its files read as they always have. */
static int classic(const bk_lut_layout *L)
{
	return L->r_lo == 0 && L->r_hi == 1 && L->warp == BK_LUT_WARP_NONE && isnan(L->f0);
}

static const char *const chan_names[BK_LUT_CHANS] = {"split", "filament", "full"};

const char *bk_lut_chan_name(bk_lut_chan c)
{
	return (unsigned)c < BK_LUT_CHANS ? chan_names[c] : "?";
}

/* What each channel of the EXR holds (brdfkit:layout). */
static const char *const chan_text[BK_LUT_CHANS] = {
	"split: R = A, G = B (Karis 2013); specular = f0*R + G",
	"filament: R = B, G = E = A + B, B = cloth, as Filament's cmgen bakes its DFG with multiscatter and cloth; "
	"specular = mix(R, G, f0) = (1 - f0)*R + f0*G, energy compensation 1 + f0*(1/G - 1), sheen albedo B",
	"full: R = A, G = B, B = cloth, A = E_avg(r) (the same along a row); E = R + G; Kulla & Conty 2017's "
	"lobe (1 - E(NoV))(1 - E(NoL))/(pi (1 - A))",
};

int bk_lut_extra(const bk_lut_desc *d, double *cloth, double *e_avg, bk_progress_fn progress, void *ctx)
{
	const bk_lut_layout *L = &d->L;
	if (bk_lut_layout_check(L))
		return -1;
	for (int j = 0; j < L->nr; j++) {
		double r = bk_lut_texel_r(L, j);
		if (bk_ms_E_avg(r, d->smith, d->tol, &e_avg[j], NULL))
			return -1;
		for (int i = 0; i < L->nu; i++)
			if (bk_sheen_albedo(bk_lut_texel_nov(L, i), r, d->tol, &cloth[(size_t)j * (size_t)L->nu + (size_t)i], NULL))
				return -1;
		if (progress)
			progress(ctx, j + 1, L->nr);
	}
	return 0;
}

static void describe(const bk_lut_desc *d, char *method, size_t mlen, char *origin, size_t olen)
{
	if (d->samples)
		snprintf(method, mlen, "Hammersley Monte Carlo, GGX importance sampling, %ld samples", d->samples);
	else
		snprintf(method, mlen, "deterministic adaptive Gauss-Kronrod over the half vector, tol %g", d->tol);
	if (classic(&d->L))
		snprintf(origin, olen, "%s", d->origin_top
		         ? "top: scanline 0 (first in file, top as displayed) holds r = 0.5/height; uv (0,0) = first texel"
		         : "bottom: the last scanline (bottom as displayed) holds r = 0.5/height; scanline 0 holds r = 1 - 0.5/height");
	else
		snprintf(origin, olen, "%s", d->origin_top
		         ? "top: scanline 0 (first in file, top as displayed) holds v = 0.5/height; uv (0,0) = first texel"
		         : "bottom: the last scanline (bottom as displayed) holds v = 0.5/height; scanline 0 holds v = 1 - 0.5/height");
}

/* The axes, in words: where the texel centres are. */
static void axes_text(const bk_lut_desc *d, char *buf, size_t len)
{
	const bk_lut_layout *L = &d->L;
	if (classic(L)) {
		snprintf(buf, len, "x: NoV = (i + 0.5)/width at texel centres; y: perceptual roughness r = (j + 0.5)/height");
		return;
	}
	snprintf(buf, len,
	         "x: u = %s at texel centres u = (i + 0.5)/width%s; y: v = (r - %.9g)/%.9g at texel centres v = (j + 0.5)/height, "
	         "r perceptual roughness",
	         bk_lut_warp_form(L->warp), L->warp == BK_LUT_WARP_SQRT ? " (texel i holds NoV = u^2)" : "", L->r_lo,
	         L->r_hi - L->r_lo);
}

static void write_csv(FILE *f, const bk_lut_desc *d, const char *method, const char *axes, const double *A,
                      const double *B)
{
	const bk_lut_layout *L = &d->L;
	int folded = !isnan(L->f0);
	bk_prov_title(f, "DFG LUT, %dx%d, Smith %s", L->nu, L->nr, smith_text[d->smith]);
	fputs("# f0*A + B = integral of D*V*F*NoL over the light hemisphere; GGX D, Schlick F with f90 = 1\n", f);
	if (folded)
		fprintf(f, "# one channel: env = %.9g*A + B (f0 folded in)\n", L->f0);
	if (classic(L))
		fprintf(f, "# nov and roughness (perceptual, alpha = r^2) at texel centres (i + 0.5)/%d; method: %s\n", L->nu,
		        method);
	else
		fprintf(f, "# %s; alpha = r^2; method: %s\n", axes, method);
	if (d->chan != BK_LUT_SPLIT)
		fprintf(f, "# E = A + B (F = 1); cloth = integral of D_charlie*V_neubelt*NoL (F = 1); E_avg = 2 integral of "
		        "E(mu) mu dmu at the row's r; the EXR's channels: %s\n", chan_text[d->chan]);
	bk_prov_command(f, d->command);
	fputs(folded ? "nov,roughness,env\n" : d->chan != BK_LUT_SPLIT ? "nov,roughness,A,B,E,cloth,E_avg\n" : "nov,roughness,A,B\n", f);
	for (int j = 0; j < L->nr; j++)
		for (int i = 0; i < L->nu; i++) {
			size_t k = (size_t)j * (size_t)L->nu + (size_t)i;
			fprintf(f, "%.9g,%.9g,", bk_lut_texel_nov(L, i), bk_lut_texel_r(L, j));
			if (folded)
				fprintf(f, "%.9g\n", L->f0 * A[k] + B[k]);
			else if (d->chan != BK_LUT_SPLIT)
				fprintf(f, "%.9g,%.9g,%.9g,%.9g,%.9g\n", A[k], B[k], A[k] + B[k], d->cloth[k], d->e_avg[j]);
			else
				fprintf(f, "%.9g,%.9g\n", A[k], B[k]);
		}
}

/* The value of EXR channel c (0..3: R, G, B, A) at texel k of row j, by the
 * channel layout (lut.h). */
static double chan_value(const bk_lut_desc *d, int c, const double *A, const double *B, size_t k, int j)
{
	if (!isnan(d->L.f0))
		return d->L.f0 * A[k] + B[k];
	switch (d->chan) {
	case BK_LUT_FILAMENT:
		return c == 0 ? B[k] : c == 1 ? A[k] + B[k] : d->cloth[k];
	case BK_LUT_FULL:
		return c == 0 ? A[k] : c == 1 ? B[k] : c == 2 ? d->cloth[k] : d->e_avg[j];
	default:
		return c == 0 ? A[k] : B[k];
	}
}

static int chan_count(const bk_lut_desc *d)
{
	if (!isnan(d->L.f0))
		return 1;
	return d->chan == BK_LUT_FILAMENT ? 3 : d->chan == BK_LUT_FULL ? 4 : 2;
}

/* File row y holds roughness row j: y = j with the origin at the top. */
static void to_rows(const bk_lut_desc *d, const double *A, const double *B, float *const *ch)
{
	const bk_lut_layout *L = &d->L;
	size_t nu = (size_t)L->nu;
	int nc = chan_count(d);
	for (int y = 0; y < L->nr; y++) {
		int j = d->origin_top ? y : L->nr - 1 - y;
		for (size_t i = 0; i < nu; i++)
			for (int c = 0; c < nc; c++)
				ch[c][(size_t)y * nu + i] = (float)chan_value(d, c, A, B, (size_t)j * nu + i, j);
	}
}

int bk_lut_write(const bk_lut_desc *d, const char *dir, const double *A,
                 const double *B, char *err, size_t errlen)
{
	char csv[4200], exr_path[4200], method[160], origin[200], axes[400], channels[400];
	snprintf(csv, sizeof csv, "%.4000s/" BK_LUT_CSV, dir);
	snprintf(exr_path, sizeof exr_path, "%.4000s/" BK_LUT_EXR, dir);
	if (bk_lut_layout_check(&d->L)) {
		snprintf(err, errlen, "%s: not a valid LUT layout", exr_path);
		return -1;
	}
	int folded = !isnan(d->L.f0);
	if ((unsigned)d->chan >= BK_LUT_CHANS || (d->chan != BK_LUT_SPLIT && (folded || !d->cloth || !d->e_avg))) {
		snprintf(err, errlen, "%s: channels '%s' %s", exr_path, bk_lut_chan_name(d->chan),
		         folded ? "keep A and B apart: not with a folded f0" : "without its cloth and E_avg values");
		return -1;
	}
	size_t n = (size_t)d->L.nu * (size_t)d->L.nr;
	int nc = chan_count(d);
	float *ch[4] = {NULL, NULL, NULL, NULL};
	int oom = 0;
	for (int c = 0; c < nc; c++)
		oom |= !(ch[c] = malloc(n * sizeof *ch[c]));
	if (oom) {
		for (int c = 0; c < 4; c++)
			free(ch[c]);
		snprintf(err, errlen, "%s: out of memory for a %dx%d table", exr_path, d->L.nu, d->L.nr);
		return -1;
	}
	describe(d, method, sizeof method, origin, sizeof origin);
	axes_text(d, axes, sizeof axes);
	if (folded)
		snprintf(channels, sizeof channels, "R = %.9g*A + B = integral of D*V*F*NoL at f0 = %.9g (folded in), GGX D, "
		         "Schlick F with f90 = 1; linear data, never load as sRGB", d->L.f0, d->L.f0);
	else if (d->chan == BK_LUT_FILAMENT)
		snprintf(channels, sizeof channels, "R = B (bias), G = A + B = E (F = 1), B = cloth (D_charlie*V_neubelt*NoL, "
		         "F = 1): f0*A + B = (1 - f0)*R + f0*G = integral of D*V*F*NoL, GGX D, Schlick F with f90 = 1; "
		         "linear data, never load as sRGB");
	else if (d->chan == BK_LUT_FULL)
		snprintf(channels, sizeof channels, "R = A (scale of f0), G = B (bias), B = cloth (D_charlie*V_neubelt*NoL, "
		         "F = 1), A = E_avg of the row's r: f0*A + B = integral of D*V*F*NoL, GGX D, Schlick F with f90 = 1; "
		         "linear data, never load as sRGB");
	else
		snprintf(channels, sizeof channels, "R = A (scale of f0), G = B (bias): f0*A + B = integral of D*V*F*NoL, GGX D, "
		         "Schlick F with f90 = 1; linear data, never load as sRGB");
	to_rows(d, A, B, ch);
	size_t bad = 0;
	for (int c = 0; c < nc; c++)
		bad += bk_exr_nonfinite(ch[c], n, d->half);
	if (bad) { /* never a file whose texels are not numbers (H3) */
		snprintf(err, errlen, "%s: %zu texels are NaN or infinite in %s: nothing written", exr_path, bad,
		         d->half ? "half" : "float32");
		for (int c = 0; c < 4; c++)
			free(ch[c]);
		return -1;
	}

	bk_out co;
	int rc = bk_out_open(&co, csv, err, errlen);
	if (rc == 0) {
		write_csv(co.f, d, method, axes, A, B);
		const bk_exr_attr attrs[] = {
			{"brdfkit:version", BK_EXR_ATTR_STRING, BK_VERSION, 0},
			{"brdfkit:axes", BK_EXR_ATTR_STRING, axes, 0},
			{"brdfkit:origin", BK_EXR_ATTR_STRING, origin, 0},
			{"brdfkit:roughness", BK_EXR_ATTR_STRING, "perceptual roughness r, linear in y; GGX alpha = r^2", 0},
			{"brdfkit:channels", BK_EXR_ATTR_STRING, channels, 0},
			{"brdfkit:layout", BK_EXR_ATTR_STRING, folded ? "folded: R = f0*A + B" : chan_text[d->chan], 0},
			{"brdfkit:smith", BK_EXR_ATTR_STRING, smith_text[d->smith], 0},
			{"brdfkit:method", BK_EXR_ATTR_STRING, method, 0},
			{"brdfkit:samples", BK_EXR_ATTR_INT, NULL, (int)d->samples},
			{"brdfkit:command", BK_EXR_ATTR_STRING, d->command ? d->command : "", 0},
		};
		const char *names[4] = {"R", "G", "B", "A"};
		const float *data[4] = {ch[0], ch[1], ch[2], ch[3]};
		rc = bk_exr_write(exr_path, d->L.nu, d->L.nr, nc, names, data, d->half, attrs,
		                  (int)(sizeof attrs / sizeof attrs[0]), err, errlen);
		if (rc)
			bk_out_abort(&co);
		else
			rc = bk_out_commit(&co, err, errlen);
	}
	for (int c = 0; c < 4; c++)
		free(ch[c]);
	return rc;
}

/* The brdfkit:axes text of a layout, for readers that check a file against
 * it (tabtarget.c): one writer of the wording. */
void bk_lut_axes_text(const bk_lut_layout *L, char *buf, size_t len)
{
	bk_lut_desc d = {.L = *L};
	axes_text(&d, buf, len);
}
