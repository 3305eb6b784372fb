/*
 * fit_out.c — the files of a fit's result directory (fit_out.h).
 */
#include "fit_out.h"
#include "prov.h"
#include "form_check.h"
#include "heatmap.h"
#include "msl.h"
#include "out.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static void metrics_row(FILE *f, const char *label, const bk_fit_metrics *m)
{
	fprintf(f, "%s,%.9g,%.9g,%.9g,%.9g,%.9g,", label, m->cost, m->rmse, m->weighted_rmse, m->max_abs,
	        m->max_rel);
	if (isfinite(m->albedo_max_abs))
		fprintf(f, "%.9g", m->albedo_max_abs);
	fputc('\n', f);
}


/* One file of the result: dir/name, its path kept in path for close_in. */
static FILE *open_in(const char *dir, const char *name, char path[4200], char *err, size_t errlen)
{
	snprintf(path, 4200, "%.4000s/%.150s", dir, name);
	return bk_out_fopen(path, err, errlen);
}

/* Closes f; the first failure goes into err, each is counted. */
static int close_in(FILE *f, const char *path, int bad, char *err, size_t errlen)
{
	char e[1200];
	if (!bk_out_fclose(f, path, e, sizeof e))
		return bad;
	if (!bad)
		snprintf(err, errlen, "%s", e);
	return 1;
}

static void header(FILE *f, const fitout_run *R, const char *what)
{
	bk_prov_header(f, R->command, R->s->description, "%s", what);
	if (R->to->kind == BK_TARGET_FORM) { /* the whole expression (the description may cut it), on one line */
		fputs("# target form: ", f);
		for (const char *c = R->to->form_text; *c; c++)
			fputc(*c == '\n' || *c == '\r' ? ' ' : *c, f);
		fprintf(f, "\n# domain: %s (cell centres, %d per axis)\n", R->domain, bk_target_form_cells(R->to));
	}
	fprintf(f, "# residuals: %s; conventions: r perceptual roughness, a = r^2, V includes 1/(4 NoL NoV)\n",
	        R->spec->relative ? "relative (f - y)/|y|" : "absolute f - y");
}

/* "# what p0, p3" for the parameters marked in held, if any. */
static void held_line(FILE *f, const int *held, int np, const char *what)
{
	for (int j = 0, k = 0; j < np; j++)
		if (held[j])
			fprintf(f, "%sp%d", k++ ? ", " : what, j);
	for (int j = 0; j < np; j++)
		if (held[j]) {
			fputc('\n', f);
			break;
		}
}

static int write_tables(const fitout_run *R, const char *dir, char *err, size_t errlen)
{
	char path[4200];
	FILE *f = open_in(dir, "coefficients.csv", path, err, errlen);
	if (!f)
		return -1;
	header(f, R, "fitted coefficients");
	/* held ones were not fitted: no standard error (an empty field), said here */
	held_line(f, R->res->held, R->spec->np, "# not identifiable, held at the start value: ");
	held_line(f, R->spec->hold, R->spec->np, "# held at the start value by --hold: ");
	fputs("form,parameter,value,standard_error\n", f);
	const char *form = R->name;
	for (int j = 0; j < R->spec->np; j++) {
		bk_csv_field(f, form);
		fprintf(f, ",p%d,%.9g,", j, R->res->p[j]);
		if (isfinite(R->res->se[j]))
			fprintf(f, "%.3g", R->res->se[j]);
		fputc('\n', f);
	}
	int bad = close_in(f, path, 0, err, errlen);
	if (!(f = open_in(dir, "metrics.csv", path, err, errlen)))
		return -1;
	header(f, R, "fit metrics");
	fputs("constants,cost,rmse,weighted_rmse,max_abs,max_rel,albedo_max_abs\n", f);
	metrics_row(f, "fitted", &R->res->fitted);
	if ((R->published != NULL))
		metrics_row(f, "published", &R->res->published);
	if (R->spec->digits && R->spec->digits != BK_FIT_DIGITS_SE) /* its last digits are the CPU's */
		metrics_row(f, "unrounded", &R->res->before_digits);
	bad = close_in(f, path, bad, err, errlen);
	if (R->s->ncomp == 2) { /* env split: A, B and A + B (the albedo at f0 = 1) */
		if (!(f = open_in(dir, "metrics_env.csv", path, err, errlen)))
			return -1;
		header(f, R, "split-sum errors");
		fputs("constants,component,rmse,max_abs\n", f);
		static const char *const comp[3] = {"A", "B", "A+B"};
		for (int k = 0; k < 3; k++)
			fprintf(f, "fitted,%s,%.9g,%.9g\n", comp[k], R->res->fitted.comp_rmse[k], R->res->fitted.comp_max_abs[k]);
		for (int k = 0; (R->published != NULL) && k < 3; k++)
			fprintf(f, "published,%s,%.9g,%.9g\n", comp[k], R->res->published.comp_rmse[k],
			        R->res->published.comp_max_abs[k]);
		bad = close_in(f, path, bad, err, errlen);
	}
	return bad ? -1 : 0;
}

/* The error over the target's plane with constants p, as DIR/<stem>.{exr,png,csv}. */
static int write_heatmap(const fitout_run *R, const char *dir, const char *stem, const double *p, const char *which,
                         char *err, size_t errlen)
{
	const bk_samples *s = R->s;
	size_t cells = (size_t)s->plane_nx * s->plane_ny;
	double *v = malloc(sizeof(double) * cells);
	if (!v)
		return -1;
	bk_fit_plane_error(R->spec, p, v);
	int albedo = R->res->fitted.albedo_max_abs == R->res->fitted.albedo_max_abs;
	char title[256], value_name[64];
	snprintf(title, sizeof title, "%s %s on %s: %s", R->name, which,
	         bk_target_name(R->to->kind),
	         albedo ? "directional albedo error" : s->ncomp == 2 ? "A+B error (albedo at f0 = 1)" : "error (approx - exact)");
	snprintf(value_name, sizeof value_name, "%s", albedo ? "albedo_error" : "error");
	bk_heatmap h = {s->plane_nx, s->plane_ny, v, s->plane_x0, s->plane_x1, s->plane_y0, s->plane_y1,
	                s->plane_xname, s->plane_yname, title, value_name, s->description};
	int rc = bk_heatmap_write(&h, dir, stem, err, errlen);
	free(v);
	return rc;
}

/* Whether the target has a plane to draw: a form target over three or more
 * inputs has none (report says so). */
int fitout_has_plane(const fitout_run *R)
{
	if (R->to->kind == BK_TARGET_TABLE || R->to->kind == BK_TARGET_MERL)
		return R->s->plane_x_input >= 0; /* an EXR table's grid; not a CSV's scattered samples, nor MERL's 3-D */
	return R->to->kind != BK_TARGET_FORM || R->to->ndomain <= 2;
}

static int write_heatmaps(const fitout_run *R, const char *dir, char *err, size_t errlen)
{
	if (!fitout_has_plane(R))
		return 0;
	int rc = write_heatmap(R, dir, "heatmap", R->res->p, "fitted", err, errlen);
	if (rc == 0 && (R->published != NULL)) /* the published constants on the same samples, same colour rule */
		rc = write_heatmap(R, dir, "heatmap_published", R->published, "published", err, errlen);
	return rc;
}

/* The shader files: name, language (-1: Metal, analysis/msl.c), precision
 * [single, half]. A half search's member is pasted as half code in both of
 * each language's half types (C has no half: float, with the half code's
 * constants), so a half front has two more files. */
static const struct shader_file {
	const char *file;
	int lang;
	int emit[2];
} shader_files[] = {
	{"shader.c", BK_LANG_C, {BK_EMIT_SINGLE, BK_EMIT_RELAXED}},
	{"shader.glsl", BK_LANG_GLSL, {BK_EMIT_SINGLE, BK_EMIT_RELAXED}},
	{"shader_f16.glsl", BK_LANG_GLSL, {-1, BK_EMIT_F16}},
	{"shader.hlsl", BK_LANG_HLSL, {BK_EMIT_SINGLE, BK_EMIT_RELAXED}},
	{"shader_f16.hlsl", BK_LANG_HLSL, {-1, BK_EMIT_F16}},
	{"shader.metal", -1, {BK_EMIT_SINGLE, BK_EMIT_F16}},
};

static int write_shader(const fitout_run *R, const char *dir, const struct shader_file *sf, const char *domain,
                        const char *error, char *err, size_t errlen)
{
	char path[4200];
	int emit = sf->emit[R->half != 0];
	if (emit < 0) /* a single-precision run has no explicit-half file */
		return 0;
	FILE *f = open_in(dir, sf->file, path, err, errlen);
	if (!f)
		return -1;
	bk_emit_style style = {R->signature, R->signature != 0};
	const bk_emit_style *st = R->signature ? &style : NULL;
	if (R->split && st && sf->lang >= 0) { /* NAME_A, NAME_B and NAME(NoV, r) returning both */
		bk_emit_info info = {R->fname, R->source, R->convention, domain, error, R->command};
		char *text = bk_form_emit_pair(R->f[0], R->f[1], (bk_lang)sf->lang, emit, R->res->p, &info, st);
		if (!text) {
			fclose(f); /* in the result's temporary tree, which goes */
			snprintf(err, errlen, "%s: out of memory, or a form outside its front's signature", path);
			return -1;
		}
		fputs(text, f);
		free(text);
		return close_in(f, path, 0, err, errlen) ? -1 : 0;
	}
	for (int q = 0; q < (R->split ? 2 : 1); q++) {
		char name[64], why[600] = "out of memory";
		snprintf(name, sizeof name, "%s%s", R->fname, R->split ? (q ? "_B" : "_A") : "");
		bk_emit_info info = {name, R->source, R->convention, domain, error, R->command};
		char *text = sf->lang < 0 ? bk_msl_emit(R->f[q], emit, R->res->p, &info, st, why, sizeof why)
		                          : bk_form_emit_styled(R->f[q], (bk_lang)sf->lang, emit, R->res->p, &info, st);
		if (!text) {
			fclose(f); /* in the result's temporary tree, which goes */
			snprintf(err, errlen, "%s: %s", path, why);
			return -1;
		}
		fprintf(f, "%s%s", q ? "\n" : "", text);
		free(text);
	}
	return close_in(f, path, 0, err, errlen) ? -1 : 0;
}

static int write_shaders(const fitout_run *R, const char *dir, char *err, size_t errlen)
{
	char domain[600], error[400];
	snprintf(domain, sizeof domain, "%s", R->s->description);
	if (R->error)
		snprintf(error, sizeof error, "%s", R->error);
	else
		snprintf(error, sizeof error, "in f64: rmse %.3g, max |error| %.3g, max relative %.3g (%s residuals)",
		         R->res->fitted.rmse, R->res->fitted.max_abs, R->res->fitted.max_rel,
		         R->spec->relative ? "relative" : "absolute");
	for (int q = 0; q < (R->split ? 2 : 1); q++)
		form_warn_precision(NULL, R->fname, R->f[q], R->res->p, R->half ? BK_F16 : BK_F32);
	for (size_t k = 0; k < sizeof shader_files / sizeof shader_files[0]; k++)
		if (write_shader(R, dir, &shader_files[k], domain, error, err, errlen))
			return -1;
	return 0;
}


int fitout_write_into(const fitout_run *R, const char *dir, char *err, size_t errlen)
{
	int rc = write_tables(R, dir, err, errlen);
	if (rc == 0 && (rc = write_heatmaps(R, dir, err, errlen)) == 0)
		rc = write_shaders(R, dir, err, errlen);
	for (int k = 0; rc == 0 && !R->cell_csv && k < 2; k++) { /* the per-cell tables: regenerated by one fit command */
		char path[4200];
		snprintf(path, sizeof path, "%.4000s/%s.csv", dir, k ? "heatmap_published" : "heatmap");
		unlink(path);
	}
	return rc;
}
