/*
 * render_write.c — EXR, PNG, CSV, shaders and the page section of brdfkit
 * render (see render_write.h).
 */
#include "render_write.h"
#include "prov.h"

#include "exr.h"
#include "out.h"
#include "pngio.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

const char bk_render_conventions[] =
	"linear radiance (RGB), brdfkit render's scene (analysis/render.h): columns of roughness r (perceptual, a = "
	"r^2); top row a dielectric f0 = 0.04 over a Lambert base (0.30, 0.04, 0.03), bottom row gold f0 = (1.00, "
	"0.71, 0.29); perspective view, a pinhole per sphere at 4 radii; one directional light toward normalize(0.5, 0.6, 0.62), E = "
	"(3.0, 2.9, 2.7); a procedural sky, prefiltered per pixel (Karis, N = V = R, 24x48 GGX samples) times the "
	"split sum f0 A + B of brdfkit's DFG (correlated Smith); specular D_ggx V_smith_ggx_correlated F_schlick(f0, "
	"1); the candidate replaces one term; background 0.02 flat. PNG: Reinhard x/(1+x) per channel, then sRGB; "
	"non-finite pixels magenta (255, 0, 255).";

static const char *const image_stem[BK_RI_COUNT] = {"exact", "candidate_f32", "exact_f16", "candidate_f16"};
static const char *const image_title[BK_RI_COUNT] = {"exact BRDF, f32", "candidate, f32", "exact BRDF, float16_t",
                                                     "candidate, float16_t"};

static const char diff_text[] =
	"difference: per pixel, the largest over R, G, B of |display(candidate) - display(exact f32)|, display = sRGB of "
	"Reinhard x/(1+x), times 8, clamped to 1, as a ramp black (0) - red - yellow - white (1/8 of the display range "
	"or more); magenta where either value is not finite.";

/* ---- PNG ------------------------------------------------------------------------- */

/* 8-bit RGB, sRGB chunk, the texts as tEXt (pngio.h: the bytes depend on the
 * pixels and texts alone). */
static int write_png(const char *path, int w, int h, const unsigned char *rgb, const char *title, const char *desc,
                     char *err, size_t errlen)
{
	FILE *f = bk_out_fopen(path, err, errlen);
	if (!f)
		return -1;
	const bk_png_text text[4] = {
		{"Title", title},
		{"Description", desc},
		{"Software", "brdfkit " BK_VERSION},
		{"Command", bk_out_command()},
	};
	char e2[256];
	int rc = bk_png_write(f, w, h, 3, 1, 0, rgb, text, 4, e2, sizeof e2);
	if (bk_out_fclose(f, path, err, errlen)) /* the file and the errno */
		return -1;
	if (rc) {
		snprintf(err, errlen, "%s: %s", path, e2);
		return -1;
	}
	return 0;
}

static unsigned char byte(double v)
{
	return (unsigned char)lrint(fmin(fmax(v, 0), 1) * 255);
}

static int finite3(const float *p)
{
	return isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]);
}

static const unsigned char magenta[3] = {255, 0, 255};

static void radiance_png(const float *img, size_t npix, unsigned char *rgb)
{
	for (size_t p = 0; p < npix; p++)
		for (int c = 0; c < 3; c++)
			rgb[p * 3 + c] = finite3(img + p * 3) ? byte(bk_render_display(img[p * 3 + c])) : magenta[c];
}

/* The display difference of candidate pixel a against exact pixel b
 * (render.h): NaN where b is not finite (the reference has no value there:
 * the exact image's own non-finite count says so); 1, the whole display
 * range, where a alone is not finite (L7: a candidate must not read better
 * for the pixels it has no value at, in the max, the mean or the PNG). */
static double display_diff(const float *a, const float *b)
{
	if (!finite3(b))
		return NAN;
	if (!finite3(a))
		return 1;
	double m = 0;
	for (int c = 0; c < 3; c++)
		m = fmax(m, fabs(bk_render_display(a[c]) - bk_render_display(b[c])));
	return m;
}

static void ramp(double t, unsigned char out[3])
{
	/* black -> red -> yellow -> white in equal thirds */
	t = fmin(fmax(t, 0), 1) * 3;
	out[0] = byte(t);
	out[1] = byte(t - 1);
	out[2] = byte(t - 2);
}

/* ---- EXR ------------------------------------------------------------------------- */

static int write_exr(const char *path, const bk_render_out *o, const float *img, const char *what, int half,
                     char *err, size_t errlen)
{
	int w = o->g->width, h = o->g->height;
	size_t npix = (size_t)w * (size_t)h;
	float *plane = malloc(npix * 3 * sizeof *plane);
	if (!plane) {
		snprintf(err, errlen, "out of memory");
		return -1;
	}
	for (size_t p = 0; p < npix; p++)
		for (int c = 0; c < 3; c++)
			plane[(size_t)c * npix + p] = img[p * 3 + c];
	const char *names[3] = {"R", "G", "B"};
	const float *data[3] = {plane, plane + npix, plane + 2 * npix};
	bk_exr_attr attrs[] = {
		{"brdfkit:conventions", BK_EXR_ATTR_STRING, bk_render_conventions, 0},
		{"brdfkit:image", BK_EXR_ATTR_STRING, what, 0},
		{"brdfkit:form", BK_EXR_ATTR_STRING, o->form, 0},
		{"brdfkit:form_b", BK_EXR_ATTR_STRING, o->form_b ? o->form_b : "", 0},
		{"brdfkit:parameters", BK_EXR_ATTR_STRING, o->params ? o->params : "", 0},
		{"brdfkit:term", BK_EXR_ATTR_STRING, o->term, 0},
		{"brdfkit:device", BK_EXR_ATTR_STRING, o->device, 0},
		{"brdfkit:command", BK_EXR_ATTR_STRING, bk_out_command(), 0},
		{"brdfkit:version", BK_EXR_ATTR_STRING, BK_VERSION, 0},
	};
	int rc = bk_exr_write(path, w, h, 3, names, data, half, attrs, (int)(sizeof attrs / sizeof *attrs), err, errlen);
	free(plane);
	return rc;
}

/* ---- one render ------------------------------------------------------------------- */

static int write_text(const char *path, const char *text, char *err, size_t errlen)
{
	FILE *f = bk_out_fopen(path, err, errlen);
	if (!f)
		return -1;
	fputs(text, f);
	return bk_out_fclose(f, path, err, errlen);
}

static int write_spheres(const char *path, const bk_render_out *o, char *err, size_t errlen)
{
	const bk_render_geom *g = o->g;
	int ns = 2 * g->ncols, cell = g->width / g->ncols;
	size_t *cnt = calloc((size_t)ns * (BK_RI_COUNT + 1), sizeof *cnt);
	double *dmax = calloc((size_t)ns * 4, sizeof *dmax);
	FILE *f = cnt && dmax ? bk_out_fopen(path, err, errlen) : NULL;
	if (!f) {
		if (!cnt || !dmax)
			snprintf(err, errlen, "%s: out of memory", path);
		free(cnt);
		free(dmax);
		return -1;
	}
	size_t npix = (size_t)g->width * (size_t)g->height;
	for (size_t p = 0; p < npix; p++) {
		int s = g->sphere[p];
		if (s < 0)
			continue;
		cnt[(size_t)s * (BK_RI_COUNT + 1) + BK_RI_COUNT]++;
		for (int i = 0; i < BK_RI_COUNT; i++)
			if (o->img[i] && !finite3(o->img[i] + p * 3))
				cnt[(size_t)s * (BK_RI_COUNT + 1) + (size_t)i]++;
		for (int k = 0; k < 2; k++) {
			const float *c = o->img[k ? BK_RI_CAND_F16 : BK_RI_CAND_F32];
			if (!c || !o->img[BK_RI_EXACT_F32])
				continue;
			double d = display_diff(c + p * 3, o->img[BK_RI_EXACT_F32] + p * 3);
			if (isfinite(d)) {
				dmax[s * 4 + k] = fmax(dmax[s * 4 + k], d);
				dmax[s * 4 + 2 + k] += d;
			}
		}
	}
	bk_prov_title(f, "render: per sphere, its cell (pixels, x0 y0 inclusive, x1 y1 exclusive, y down), "
	              "material and roughness; per image the pixels that are not finite (NaN or Inf in any channel; "
	              "empty: not rendered); the largest and mean display difference against the exact f32 image over "
	              "the sphere's pixels where that image is finite, a candidate pixel that is not finite counting as 1, "
	              "the whole display range (display = sRGB of Reinhard x/(1+x), 0..1; the PNGs show it x8)");
	bk_prov_command(f, bk_out_command());
	fprintf(f, "row,col,material,r,x0,y0,x1,y1,pixels,nonfinite_exact_f32,nonfinite_candidate_f32,"
	           "nonfinite_exact_f16,nonfinite_candidate_f16,max_diff_f32,max_diff_f16,mean_diff_f32,mean_diff_f16\n");
	for (int s = 0; s < ns; s++) {
		int row = s / g->ncols, col = s % g->ncols;
		size_t *c = cnt + (size_t)s * (BK_RI_COUNT + 1);
		fprintf(f, "%d,%d,%s,%.9g,%d,%d,%d,%d,%zu", row, col, row ? "gold" : "dielectric", o->scene->r[col],
		        col * cell, row * cell, (col + 1) * cell, (row + 1) * cell, c[BK_RI_COUNT]);
		for (int i = 0; i < BK_RI_COUNT; i++)
			if (o->img[i])
				fprintf(f, ",%zu", c[i]);
			else
				fputs(",", f);
		for (int k = 0; k < 4; k++) {
			int have = o->img[(k % 2) ? BK_RI_CAND_F16 : BK_RI_CAND_F32] != NULL;
			double v = k >= 2 && c[BK_RI_COUNT] ? dmax[s * 4 + k] / (double)c[BK_RI_COUNT] : dmax[s * 4 + k];
			if (have)
				fprintf(f, ",%.6g", v);
			else
				fputs(",", f);
		}
		fputc('\n', f);
	}
	free(cnt);
	free(dmax);
	return bk_out_fclose(f, path, err, errlen);
}

int bk_render_file_name(const char *name)
{
	static const char *const fixed[] = {"diff_f32.png", "diff_f16.png", "shader_f32.comp", "shader_f16.comp",
	                                    "spheres.csv", "section.html", NULL};
	char file[128];
	for (const char *const *s = fixed; *s; s++)
		if (!strcmp(name, *s))
			return 1;
	for (int i = 0; i < BK_RI_COUNT; i++)
		for (int k = 0; k < 2; k++) {
			snprintf(file, sizeof file, "%s.%s", image_stem[i], k ? "png" : "exr");
			if (!strcmp(name, file))
				return 1;
		}
	return 0;
}

int bk_render_write(const char *dir, bk_render_out *o, char *err, size_t errlen)
{
	const bk_render_geom *g = o->g;
	size_t npix = (size_t)g->width * (size_t)g->height;
	unsigned char *rgb = malloc(npix * 3);
	char path[4200], title[600], desc[4096];
	int rc = rgb ? 0 : -1;
	if (rc)
		snprintf(err, errlen, "out of memory");
	for (int i = 0; !rc && i < BK_RI_COUNT; i++) {
		o->nonfinite[i] = 0;
		if (!o->img[i])
			continue;
		for (size_t p = 0; p < npix; p++)
			o->nonfinite[i] += !finite3(o->img[i] + p * 3);
		if (o->shared_exact && (i == BK_RI_EXACT_F32 || i == BK_RI_EXACT_F16))
			continue;
		snprintf(title, sizeof title, "brdfkit render: %s: %.400s", image_title[i], o->form);
		snprintf(desc, sizeof desc, "%s device: %.200s", bk_render_conventions, o->device);
		snprintf(path, sizeof path, "%s/%s.exr", dir, image_stem[i]);
		rc = write_exr(path, o, o->img[i], image_title[i], i == BK_RI_EXACT_F16 || i == BK_RI_CAND_F16, err, errlen);
		snprintf(path, sizeof path, "%s/%s.png", dir, image_stem[i]);
		radiance_png(o->img[i], npix, rgb);
		if (!rc)
			rc = write_png(path, g->width, g->height, rgb, title, desc, err, errlen);
	}
	for (int k = 0; !rc && k < 2; k++) {
		const float *c = o->img[k ? BK_RI_CAND_F16 : BK_RI_CAND_F32], *e = o->img[BK_RI_EXACT_F32];
		o->max_diff[k] = o->mean_diff[k] = NAN;
		if (!c || !e)
			continue;
		double sum = 0, mx = 0;
		size_t n = 0;
		for (size_t p = 0; p < npix; p++) {
			double d = display_diff(c + p * 3, e + p * 3);
			if (isnan(d) || !finite3(c + p * 3)) /* magenta marks it; its difference counts as 1 */
				memcpy(rgb + p * 3, magenta, 3);
			else
				ramp(d * BK_RENDER_DIFF_GAIN, rgb + p * 3);
			if (g->sphere[p] >= 0 && isfinite(d)) {
				sum += d;
				mx = fmax(mx, d);
				n++;
			}
		}
		o->max_diff[k] = mx;
		o->mean_diff[k] = n ? sum / (double)n : 0;
		const char *stem = k ? "diff_f16" : "diff_f32";
		snprintf(title, sizeof title, "brdfkit render: difference, candidate %s - exact f32: %.400s",
		         k ? "float16_t" : "f32", o->form);
		snprintf(desc, sizeof desc, "%s %s", diff_text, bk_render_conventions);
		snprintf(path, sizeof path, "%s/%s.png", dir, stem);
		rc = write_png(path, g->width, g->height, rgb, title, desc, err, errlen);
	}
	for (int k = 0; !rc && k < 2; k++)
		if (o->shader[k]) {
			snprintf(path, sizeof path, "%s/shader_%s.comp", dir, k ? "f16" : "f32");
			rc = write_text(path, o->shader[k], err, errlen);
		}
	if (!rc) {
		snprintf(path, sizeof path, "%s/spheres.csv", dir);
		rc = write_spheres(path, o, err, errlen);
	}
	free(rgb);
	return rc;
}

/* ---- the page section ---------------------------------------------------------- */

static void cell_img(FILE *f, const char *prefix, const char *sub, const char *stem, int have, const char *alt)
{
	if (!have) {
		fputs("<td>(not rendered)</td>", f);
		return;
	}
	char path[300];
	snprintf(path, sizeof path, "%s%s.%s", sub, stem, strncmp(stem, "diff", 4) ? "exr" : "png");
	fputs("<td><a href=\"", f);
	bk_html_link(f, prefix, path);
	snprintf(path, sizeof path, "%s%s.png", sub, stem);
	fputs("\"><img src=\"", f);
	bk_html_link(f, prefix, path);
	fprintf(f, "\" width=\"320\" alt=\"%s\"></a></td>", alt);
}

void bk_render_section(FILE *f, const bk_render_out *o, int n, const char *prefix, int in_subdirs)
{
	fputs("<section id=\"render\">\n<h2>Rendered comparisons (brdfkit render, emitted GLSL on lavapipe)</h2>\n<p>", f);
	bk_html_text(f, bk_render_conventions);
	fputs("</p>\n<p>", f);
	bk_html_text(f, diff_text);
	fputs(" The f16 images run the candidate and the shading around it in float16_t, as a mobile mediump "
	      "shader would; their differences are against the exact f32 image.</p>\n<figure>\n<table>\n", f);
	for (int i = 0; i < n; i++) {
		char sub[200] = "";
		if (n > 1 || in_subdirs)
			snprintf(sub, sizeof sub, "%s/", o[i].name);
		fputs("<tr><th colspan=\"3\">", f);
		bk_html_text(f, o[i].name);
		fputs(" (replaces ", f);
		bk_html_text(f, o[i].term);
		fputs("): <code>", f);
		bk_html_text(f, o[i].form);
		if (o[i].form_b) {
			fputs("</code>, B <code>", f);
			bk_html_text(f, o[i].form_b);
		}
		fputs("</code>", f);
		if (o[i].params && *o[i].params) {
			fputs(" with ", f);
			bk_html_text(f, o[i].params);
		}
		fputs("</th></tr>\n<tr><th>exact</th><th>candidate</th><th>difference</th></tr>\n<tr>", f);
		const char *esub = o[i].shared_exact ? "" : sub;
		cell_img(f, prefix, esub, "exact", o[i].img[BK_RI_EXACT_F32] != NULL, "exact f32");
		cell_img(f, prefix, sub, "candidate_f32", o[i].img[BK_RI_CAND_F32] != NULL, "candidate f32");
		cell_img(f, prefix, sub, "diff_f32", o[i].img[BK_RI_CAND_F32] != NULL, "difference f32");
		fprintf(f, "</tr>\n<tr><td>f32: non-finite pixels %zu</td><td>", o[i].nonfinite[BK_RI_CAND_F32]);
		if (isfinite(o[i].max_diff[0]))
			fprintf(f, "display difference max %.3g, mean %.3g", o[i].max_diff[0], o[i].mean_diff[0]);
		fputs("</td><td></td></tr>\n<tr>", f);
		cell_img(f, prefix, esub, "exact_f16", o[i].img[BK_RI_EXACT_F16] != NULL, "exact f16");
		cell_img(f, prefix, sub, "candidate_f16", o[i].img[BK_RI_CAND_F16] != NULL, "candidate f16");
		cell_img(f, prefix, sub, "diff_f16", o[i].img[BK_RI_CAND_F16] != NULL, "difference f16");
		fprintf(f, "</tr>\n<tr><td>float16_t: non-finite pixels exact %zu</td><td>candidate %zu", o[i].nonfinite[BK_RI_EXACT_F16],
		        o[i].nonfinite[BK_RI_CAND_F16]);
		if (isfinite(o[i].max_diff[1]))
			fprintf(f, "; display difference max %.3g, mean %.3g", o[i].max_diff[1], o[i].mean_diff[1]);
		fputs("</td><td></td></tr>\n", f);
	}
	fputs("</table>\n<figcaption>Per candidate, left to right: the exact term rendered, the candidate in its place, "
	      "and their difference (as the paragraph above states), in f32 (first row of pictures) and in float16_t "
	      "(second); each picture links to its values (EXR; the difference to its full-size PNG). Data: each "
	      "candidate's folder holds the images, its shaders and spheres.csv.</figcaption></figure>\n<p>Device: ", f);
	if (n)
		bk_html_text(f, o[0].device);
	fputs(". Command: <code>", f);
	bk_html_text(f, bk_out_command());
	fputs("</code></p>\n</section>\n", f);
}
