/*
 * lut.c — writing the DFG LUT. The most reported LUT bugs in engines' trackers
 * are flipped axes, alpha-vs-roughness mix-ups and LUTs loaded as sRGB, so the
 * EXR header says which is which, and the CSV carries the same in comments.
 */
#include "lut.h"
#include "out.h"
#include "exr.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const smith_text[BK_SMITH_COUNT] = {
	"correlated: exact height-correlated Smith GGX (Heitz 2014)",
	"separable: exact separable Smith GGX, G1(v) G1(l)",
	"schlick: Schlick-GGX with k = a/2 (Karis 2013)",
};

static void describe(const bk_lut_desc *d, char *method, size_t mlen, char *origin, size_t olen)
{
	if (d->samples)
		snprintf(method, mlen, "Hammersley Monte Carlo, GGX importance sampling, %ld samples", d->samples);
	else
		snprintf(method, mlen, "deterministic adaptive Gauss-Kronrod over the half vector, tol %g", d->tol);
	snprintf(origin, olen, "%s", d->origin_top
	         ? "top: scanline 0 (first in file, top as displayed) holds r = 0.5/height; uv (0,0) = first texel"
	         : "bottom: the last scanline (bottom as displayed) holds r = 0.5/height; scanline 0 holds r = 1 - 0.5/height");
}

static void write_csv(FILE *f, const bk_lut_desc *d, const char *method, const double *A,
                      const double *B)
{
	int n = d->size;
	fprintf(f, "# brdfkit %s DFG LUT, %dx%d, Smith %s\n", BK_VERSION, n, n, smith_text[d->smith]);
	fputs("# f0*A + B = integral of D*V*F*NoL over the light hemisphere; GGX D, Schlick F with f90 = 1\n", f);
	fprintf(f, "# nov and roughness (perceptual, alpha = r^2) at texel centres (i + 0.5)/%d; method: %s\n",
	        n, method);
	fprintf(f, "# command: %s\n", d->command ? d->command : "");
	fputs("nov,roughness,A,B\n", f);
	for (int j = 0; j < n; j++)
		for (int i = 0; i < n; i++)
			fprintf(f, "%.9g,%.9g,%.9g,%.9g\n", (i + 0.5) / n, (j + 0.5) / n,
			        A[(size_t)j * n + i], B[(size_t)j * n + i]);
}

/* File row y holds roughness row j: y = j with the origin at the top. */
static void to_rows(const bk_lut_desc *d, const double *A, const double *B, float *R, float *G)
{
	int n = d->size;
	for (int y = 0; y < n; y++) {
		int j = d->origin_top ? y : n - 1 - y;
		for (int i = 0; i < n; i++) {
			R[(size_t)y * n + i] = (float)A[(size_t)j * n + i];
			G[(size_t)y * n + i] = (float)B[(size_t)j * n + i];
		}
	}
}

int bk_lut_write(const bk_lut_desc *d, const char *dir, const double *A,
                 const double *B, char *err, size_t errlen)
{
	char csv[4200], exr_path[4200], method[160], origin[200];
	snprintf(csv, sizeof csv, "%.4000s/" BK_LUT_CSV, dir);
	snprintf(exr_path, sizeof exr_path, "%.4000s/" BK_LUT_EXR, dir);
	size_t n = (size_t)d->size * (size_t)d->size;
	float *R = malloc(n * sizeof *R), *G = malloc(n * sizeof *G);
	if (!R || !G) {
		free(R);
		free(G);
		snprintf(err, errlen, "%s: out of memory for a %dx%d table", exr_path, d->size, d->size);
		return -1;
	}
	describe(d, method, sizeof method, origin, sizeof origin);
	to_rows(d, A, B, R, G);

	bk_out co;
	int rc = bk_out_open(&co, csv, err, errlen);
	if (rc == 0) {
		write_csv(co.f, d, method, A, B);
		const bk_exr_attr attrs[] = {
			{"brdfkit:version", BK_EXR_ATTR_STRING, BK_VERSION, 0},
			{"brdfkit:axes", BK_EXR_ATTR_STRING, "x: NoV = (i + 0.5)/width at texel centres; y: perceptual roughness r = (j + 0.5)/height", 0},
			{"brdfkit:origin", BK_EXR_ATTR_STRING, origin, 0},
			{"brdfkit:roughness", BK_EXR_ATTR_STRING, "perceptual roughness r, linear in y; GGX alpha = r^2", 0},
			{"brdfkit:channels", BK_EXR_ATTR_STRING, "R = A (scale of f0), G = B (bias): f0*A + B = integral of D*V*F*NoL, GGX D, Schlick F with f90 = 1; linear data, never load as sRGB", 0},
			{"brdfkit:smith", BK_EXR_ATTR_STRING, smith_text[d->smith], 0},
			{"brdfkit:method", BK_EXR_ATTR_STRING, method, 0},
			{"brdfkit:samples", BK_EXR_ATTR_INT, NULL, (int)d->samples},
			{"brdfkit:command", BK_EXR_ATTR_STRING, d->command ? d->command : "", 0},
		};
		const char *names[2] = {"R", "G"};
		const float *data[2] = {R, G};
		rc = bk_exr_write(exr_path, d->size, d->size, 2, names, data, d->half, attrs,
		                  (int)(sizeof attrs / sizeof attrs[0]), err, errlen);
		if (rc)
			bk_out_abort(&co);
		else
			rc = bk_out_commit(&co, err, errlen);
	}
	free(R);
	free(G);
	return rc;
}
