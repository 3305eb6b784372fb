/*
 * cmd_compare.c — brdfkit compare: every candidate for a target on the same
 * samples — published constants, their refits, the LUT alternative — with
 * error, ALU cost, texture fetches, CPU run time and SPIR-V size, the Pareto
 * front, CSV tables, SVG plots and an HTML section for the report page.
 */
#include "brdf.h"
#include "catalog.h"
#include "cli.h"
#include "out.h"
#include "page.h"
#include "prov.h"
#include "cmd.h"
#include "compare.h"
#include "fit.h"
#include "fitargs.h"
#include "form_check.h"
#include "gpucost.h"
#include "heatmap.h"
#include "lutcache.h"
#include "lutrows.h"
#include "speclut.h"
#include "search/catalogmap.h"
#include "search/refit.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define MAX_ROWS 128

typedef struct study {
	bk_target_options to;
	bk_samples s;
	bk_compare_row rows[MAX_ROWS];
	int n;
	int relative, refit, tier;   /* tier: index into bk_tier_alu_per_tex */
	char untimed[300];           /* why the CPU time was not measured, or "" */
	long reps;
	bk_compare_info info; /* the cost model, and the chips of --gpu */
	char driver[256];     /* the Vulkan driver that compiled for --gpu */
	char self[300];               /* the catalog entries left out as the target itself, or "" */
	int speclut[MAX_ROWS];        /* 1: the row is a specular LUT (spec), laid out as spec_layout[i] */
	bk_speclut spec_layout[MAX_ROWS];
	int lut[MAX_ROWS];            /* 1: a DFG LUT (env, ms) or a cloth one (sheen), laid out as lut_layout[i] */
	bk_lut_layout lut_layout[MAX_ROWS];
	bk_lut_format lut_fmt[MAX_ROWS];
} study;

static void row_text(bk_compare_row *r, const char *name, const char *kind, const char *source)
{
	snprintf(r->name, sizeof r->name, "%s", name);
	snprintf(r->kind, sizeof r->kind, "%s", kind);
	snprintf(r->source, sizeof r->source, "%s", source);
}

static void score(study *S, bk_compare_row *r, const bk_form *f)
{
	bk_fit_spec sp;
	memset(&sp, 0, sizeof sp);
	sp.s = &S->s;
	sp.form[0] = f;
	sp.np = bk_form_nparams(f);
	sp.relative = S->relative;
	memcpy(sp.start, r->params, sizeof sp.start);
	bk_fit_evaluate(&sp, r->params, &r->m);
	bk_form_count(f, &r->ops);
	r->cost = bk_ops_cost(&r->ops, S->info.simple, S->info.complex);
	char err[256];
	r->spirv = bk_spirv_count(f, r->params, err, sizeof err);
	for (int t = 0; t < BK_TIERS; t++)
		r->cheaper_than_fetch[t] = r->cost < bk_tier_alu_per_tex[t];
}

/* The refit of a row: its constants freed, from the published ones. */
static int refit(study *S, const bk_compare_row *pub, const bk_form *f, bk_compare_row *r)
{
	bk_fit_spec sp;
	bk_refit_spec(&sp, &S->s, f, NULL, pub->params); /* its iteration cap: search/refit.h */
	sp.relative = S->relative;
	char where[128];
	if (sp.np == 0 || bk_fit_nonfinite(&sp, sp.start, where, sizeof where))
		return -1;
	bk_fit_result res;
	int rc_fit = bk_fit_run(&sp, &res);
	if (rc_fit < 0)
		return -1;
	*r = *pub;
	r->f[0] = bk_form_dup(f); /* its own copy of the IR: rows free theirs */
	r->f[1] = NULL;
	if (!r->f[0])
		return -1;
	memcpy(r->params, res.p, sizeof r->params);
	char name[96];
	snprintf(name, sizeof name, "%.80s (refit)", pub->name);
	char source[200] = "brdfkit fit, constants freed from the published ones";
	for (int j = 0, k = 0; j < sp.np; j++) /* the ones the data do not pin stay published (fit.c) */
		if (res.held[j] && strlen(source) + 48 < sizeof source)
			snprintf(source + strlen(source), sizeof source - strlen(source), "%sp%d", k++ ? ", " : " but ", j);
	for (int j = 0; j < sp.np; j++)
		if (res.held[j]) {
			snprintf(source + strlen(source), sizeof source - strlen(source), " (not identifiable)");
			break;
		}
	if (rc_fit == 1) /* never a silent "refit": its constants are where the solver stopped */
		snprintf(source + strlen(source), sizeof source - strlen(source), "; did not converge");
	row_text(r, name, "refit", source);
	score(S, r, f);
	return 0;
}

/* 1 if f (at params) is NaN or infinite at every sample: 0/0, sqrt(-1), or
 * an input the target does not provide. */
static int nowhere_finite(const bk_samples *s, const bk_form *f, const double *params)
{
	double *v = malloc(s->n * sizeof *v);
	const double *in[BK_IN_COUNT];
	for (int k = 0; k < BK_IN_COUNT; k++)
		in[k] = s->in[k];
	int none = v && bk_form_eval(f, BK_F64, s->n, in, params, v) == 0;
	for (size_t k = 0; none && k < s->n; k++)
		none = !isfinite(v[k]);
	free(v);
	return none;
}

static int add_entry(study *S, const bk_catalog_entry *e)
{
	if (S->n + 2 > MAX_ROWS)
		return -1;
	bk_compare_row *r = &S->rows[S->n];
	memset(r, 0, sizeof *r);
	char *text = bk_catmap_form(S->to.kind, 1, e);
	if (!text)
		return -1;
	snprintf(r->form, sizeof r->form, "%s", text);
	free(text);
	if (bk_compare_row_parse(r, NULL, 0) || (bk_form_inputs(r->f[0]) & ~S->s.provides)) {
		bk_compare_rows_free(r, 1); /* reads what this target does not provide (e.g. NoV on vf2d) */
		return 0;
	}
	const bk_form *f = r->f[0]; /* the entry's one parse: both rows read it */
	row_text(r, !strcmp(e->target, "V") ? e->name : e->name, "published", e->source);
	if (!strcmp(e->target, "V")) {
		char name[96];
		snprintf(name, sizeof name, "%.70s x F_schlick", e->name);
		snprintf(r->name, sizeof r->name, "%s", name);
	}
	r->nparams = e->nparams;
	memcpy(r->params, e->defaults, sizeof r->params);
	r->ns = r->ns_min = r->ns_max = NAN;
	score(S, r, f);
	if (r->m.max_abs == 0.0 && r->m.rmse == 0.0) {
		/* exact on every sample: the entry is the target itself (vf2d is the talk's
		 * Kelemen V times Schlick F, v_kelemen_talk_r x F_schlick), no competitor:
		 * drawn at error 0 it would stand on every front; named in section.html */
		size_t at = strlen(S->self);
		snprintf(S->self + at, sizeof S->self - at, "%s%.120s", at ? ", " : "", r->name);
		bk_compare_rows_free(r, 1);
		return 0;
	}
	S->n++;
	if (S->refit && refit(S, r, f, &S->rows[S->n]) == 0)
		S->n++;
	return 0;
}

static void add_luts(study *S)
{
	bk_lut_layout L[BK_LUTROWS_MAX_LAYOUTS];
	bk_lutrow rows[BK_LUTROWS_MAX];
	int nl = bk_lutrows_layouts(0, 0, 1, NAN, L);
	if (S->to.kind == BK_TARGET_MS) /* E = A + B in one channel: the DFG folded at f0 = 1 */
		L[0].f0 = 1.0;
	int n = bk_lutrows_build(L, nl, S->to.smith, S->to.kind == BK_TARGET_SHEEN, BK_F64, &S->s, NULL, NULL, rows);
	for (int k = 0; k < n && S->n < MAX_ROWS; k++) {
		if (!rows[k].scored)
			continue;
		bk_compare_row *r = &S->rows[S->n];
		memset(r, 0, sizeof *r);
		row_text(r, "", "lut", S->to.kind == BK_TARGET_SHEEN
		                       ? "cloth channel (the sheen albedo; brdfkit lut --channels filament's B) from the reference "
		                         "integrator, bilinear, clamp to edge"
		                       : "DFG texture from the reference integrator, bilinear, clamp to edge");
		snprintf(r->name, sizeof r->name, "%.*s", (int)sizeof r->name - 1, rows[k].name);
		r->m = rows[k].m;
		r->tex_fetches = 1;
		r->sampler_slots = 1;
		r->spirv = -1;
		r->ns = r->ns_min = r->ns_max = NAN;
		S->lut[S->n] = 1;
		S->lut_layout[S->n] = rows[k].layout;
		S->lut_fmt[S->n] = rows[k].fmt;
		S->n++;
	}
}

/* spec: the low tier's specular LUT (speclut.h), the talk's choices (R·L,
 * warp 4, 1/16, 8 bits, no Fresnel) at 32² to 128², the same over N·H, and
 * the talk's with Schlick F in the shader and stored as float (the 8 bits'
 * share); brdfkit lut --specular --sweep has the rest. ALU cost: the
 * shader's ops beyond the fetch (bk_speclut_ops), the fetch priced by the
 * tier as every LUT row's. */
static void add_speclut_rows(study *S)
{
	static const struct { bk_speclut_axis axis; int size; bk_speclut_fresnel fr; bk_lut_format fmt; } rows[] = {
		{BK_SPECLUT_ROL, 32, BK_SPECLUT_F_NONE, BK_LUT_UNORM8},  {BK_SPECLUT_ROL, 64, BK_SPECLUT_F_NONE, BK_LUT_UNORM8},
		{BK_SPECLUT_ROL, 128, BK_SPECLUT_F_NONE, BK_LUT_UNORM8}, {BK_SPECLUT_NOH, 32, BK_SPECLUT_F_NONE, BK_LUT_UNORM8},
		{BK_SPECLUT_NOH, 64, BK_SPECLUT_F_NONE, BK_LUT_UNORM8},  {BK_SPECLUT_NOH, 128, BK_SPECLUT_F_NONE, BK_LUT_UNORM8},
		{BK_SPECLUT_ROL, 64, BK_SPECLUT_F_SCHLICK, BK_LUT_UNORM8}, {BK_SPECLUT_ROL, 64, BK_SPECLUT_F_NONE, BK_LUT_FLOAT},
	};
	for (size_t k = 0; k < sizeof rows / sizeof rows[0] && S->n < MAX_ROWS; k++) {
		bk_speclut L = BK_SPECLUT_TALK;
		L.axis = rows[k].axis;
		L.nu = L.nr = rows[k].size;
		L.fresnel = rows[k].fr;
		L.fmt = rows[k].fmt;
		bk_compare_row *r = &S->rows[S->n];
		memset(r, 0, sizeof *r);
		if (bk_speclut_score(&L, BK_F64, &S->s, &r->m, NULL) || bk_speclut_ops(&L, &r->ops))
			continue;
		char name[96], src[256];
		bk_speclut_name(&L, name, sizeof name);
		snprintf(src, sizeof src, "specular LUT (brdfkit lut --specular --axis %s --warp %d --scale %g --size %d): "
		         "GGX D/4/%g, bilinear, clamp to edge; shader: texel*%g*NoL*%s", bk_speclut_axis_name(L.axis), L.warp,
		         L.scale, L.nu, L.scale, L.scale, L.fresnel == BK_SPECLUT_F_SCHLICK ? "F_schlick(f0, 1, LoH)" : "f0");
		row_text(r, name, "lut", src);
		r->cost = bk_ops_cost(&r->ops, S->info.simple, S->info.complex);
		r->tex_fetches = 1;
		r->sampler_slots = 1;
		r->spirv = -1;
		r->ns = r->ns_min = r->ns_max = NAN;
		for (int c = 0; c < BK_COMPARE_CHIPS; c++)
			r->gpu_insn[c] = r->gpu_transc[c] = r->gpu_vgprs[c] = NAN;
		S->speclut[S->n] = 1;
		S->spec_layout[S->n] = L;
		S->n++;
	}
}

/* --gpu: every row with a form compiled for each chip by brdfkit gpucost's
 * code (one Vulkan instance per chip for the whole table); LUT rows stay NaN. */
static int gpu_columns(study *S)
{
	int n = S->n, nc = S->info.nchips, rc = 0;
	const bk_form **a = calloc((size_t)n, sizeof *a);
	const double **p = calloc((size_t)n, sizeof *p);
	double *v = calloc(3 * (size_t)n * (size_t)nc + 1, sizeof *v), *insn = v, *transc = v + n * nc, *vgprs = transc + n * nc;
	char err[700];
	if (!a || !p || !v)
		rc = cli_fail("compare", "out of memory");
	for (int i = 0; !rc && i < n; i++) {
		a[i] = S->rows[i].f[0]; /* NULL for a LUT row */
		p[i] = S->rows[i].params;
	}
	if (!rc && bk_gpucost_forms(a, NULL, p, n, S->info.chip, nc, insn, transc, vgprs, S->driver, sizeof S->driver,
	                            err, sizeof err))
		rc = cli_fail("compare", "--gpu: %s", err);
	for (int i = 0; !rc && i < n; i++)
		for (int c = 0; c < nc; c++) {
			S->rows[i].gpu_insn[c] = insn[i * nc + c];
			S->rows[i].gpu_transc[c] = transc[i * nc + c];
			S->rows[i].gpu_vgprs[c] = vgprs[i * nc + c];
		}
	free(a);
	free(p);
	free(v);
	return rc;
}

/* The published row a refit came from (the row just before it). */
static const bk_compare_row *published_of(const study *S, int i)
{
	return i > 0 && !strcmp(S->rows[i].kind, "refit") ? &S->rows[i - 1] : NULL;
}

/* Row i's file stem and its shaders' function name: the slug of its name
 * when that is an identifier the emitters take (a catalog name, "name
 * (refit)", "LUT 64x64 half"), else "form_N" (N = i + 1: a typed form's
 * name is its text, whose slug may start with a digit or run past
 * BK_NAME_MAX). */
static void row_stem(const study *S, const bk_compare_row *r, char *sl, size_t len)
{
	bk_slug(r->name, sl, len);
	if (!bk_identifier(sl) || strlen(sl) > BK_NAME_MAX)
		snprintf(sl, len, "form_%d", (int)(r - S->rows) + 1);
}

static void write_section(const study *S, FILE *f, const char *dir, const char *prefix)
{
	fprintf(f, "<section id=\"%s\">\n<h2>Target <code>%s</code></h2>\n<p>", bk_target_name(S->to.kind),
	        bk_target_name(S->to.kind));
	bk_html_text(f, S->s.description);
	fprintf(f, ". Residuals %s. Error on the plots: the largest absolute error over the samples. ALU cost: "
	           "cost model <code>%s</code>, simple \xc3\x97 %g + complex \xc3\x97 %g (brdfkit ops).</p>\n",
	        S->relative ? "relative" : "absolute", S->info.cost_model, S->info.simple, S->info.complex);
	(void)dir; /* the plot is a picture (plot.h), beside it as PDF and PNG for a paper */
	fprintf(f, "<figure><img src=\"%spareto_cost.svg\" width=\"100%%\" alt=\"max |error| against cost\">\n"
	           "<figcaption>The largest absolute error over the target's samples (log scale) against ALU cost (cost "
	           "model <code>%s</code>: simple \xc3\x97 %g + complex \xc3\x97 %g, a texture fetch priced at %d simple ops), "
	           "one marker per entry, its shape and colour by kind (legend), filled on the Pareto front (the dashed "
	           "staircase). Data: <a href=\"%scompare.csv\">compare.csv</a> (columns max_abs, cost, tex_fetches); "
	           "as <a href=\"%spareto_cost.pdf\">PDF</a>, <a href=\"%spareto_cost.png\">PNG</a>.</figcaption></figure>\n",
	        prefix, S->info.cost_model, S->info.simple, S->info.complex, bk_tier_alu_per_tex[S->tier], prefix, prefix,
	        prefix);
	if (!S->untimed[0]) {
		fprintf(f, "<p>Against CPU run time (a file of its own: timings change from run to run): "
		           "<a href=\"%spareto_ns.svg\">pareto_ns.svg</a>; tables: <a href=\"%scompare.csv\">compare.csv</a>, "
		           "<a href=\"%stiming.csv\">timing.csv</a>.</p>\n", prefix, prefix, prefix);
	} else { /* no plot without points, no table of empty fields */
		fputs("<p>CPU run time: not measured (", f);
		bk_html_text(f, S->untimed);
		fprintf(f, "). Table: <a href=\"%scompare.csv\">compare.csv</a>.</p>\n", prefix);
	}
	if (S->self[0]) {
		fputs("<p>Left out as the target itself (exact on every sample): ", f);
		bk_html_text(f, S->self);
		fputs(".</p>\n", f);
	}
	fprintf(f, "<p><b>On the Pareto front</b> (no other entry both cheaper and more accurate; a texture fetch priced "
	           "at %d simple ops, %s): ", bk_tier_alu_per_tex[S->tier],
	        S->tier ? "the ALU:TEX tier of --fetch-cost" : "the talk's lowest ALU:TEX tier");
	int first = 1;
	for (int i = 0; i < S->n; i++)
		if (S->rows[i].pareto_cost) {
			fputs(first ? "" : ", ", f);
			bk_html_text(f, S->rows[i].name);
			first = 0;
		}
	fputs(".</p>\n<figure>\n<table>\n<tr><th>entry</th><th>kind</th><th>max |error|</th><th>rmse</th><th>vs published</th>"
	      "<th>ALU cost</th><th>simple</th><th>complex</th><th>fetches</th><th>SPIR-V</th>", f);
	if (S->info.nchips) {
		fputs("<th>AMD instructions (", f);
		for (int c = 0; c < S->info.nchips; c++)
			fprintf(f, "%s%s", c ? "/" : "", S->info.chip[c]);
		fputs(")</th>", f);
	}
	fputs("<th>cheaper than a fetch at 16/32/48/64</th><th>front</th><th>heatmap</th></tr>\n", f);
	for (int i = 0; i < S->n; i++) {
		const bk_compare_row *r = &S->rows[i], *p = published_of(S, i);
		char sl[128];
		row_stem(S, r, sl, sizeof sl);
		fputs("<tr><td>", f);
		bk_html_text(f, r->name);
		fprintf(f, "</td><td>%s</td><td>%.3g</td><td>%.3g</td><td>", r->kind, r->m.max_abs, r->m.rmse);
		if (p && p->m.max_abs > 0)
			fprintf(f, "%+.0f %% max, %+.0f %% rmse", 100 * (r->m.max_abs / p->m.max_abs - 1),
			        100 * (r->m.rmse / p->m.rmse - 1));
		fprintf(f, "</td><td>%g</td><td>%d</td><td>%d</td><td>%d</td><td>", r->cost, r->ops.simple, r->ops.complex,
		        r->tex_fetches);
		if (r->spirv >= 0)
			fprintf(f, "%d", r->spirv);
		fputs("</td><td>", f);
		for (int c = 0; c < S->info.nchips; c++) {
			if (isnan(r->gpu_insn[c]))
				fprintf(f, "%s-", c ? "/" : "");
			else
				fprintf(f, "%s%.0f", c ? "/" : "", r->gpu_insn[c]);
			if (c == S->info.nchips - 1)
				fputs("</td><td>", f);
		}
		for (int t = 0; t < BK_TIERS; t++)
			fprintf(f, "%s%s", t ? "/" : "", r->tex_fetches ? "-" : r->cheaper_than_fetch[t] ? "yes" : "no");
		fprintf(f, "</td><td>%s</td><td><a href=\"%sheatmaps/%s.png\"><img src=\"%sheatmaps/%s.png\" width=\"120\" "
		        "alt=\"heatmap\"></a></td></tr>\n", r->pareto_cost ? "&#9733;" : "", prefix, sl, prefix, sl);
	}
	fputs("</table>\n<figcaption>Heatmaps (last column): each entry's signed error (approximation \xe2\x88\x92 exact; "
	      "the directional albedo's where the term is scored on it) over the target's plane, ", f);
	bk_html_text(f, S->s.plane_xname);
	fputs(" across, ", f);
	bk_html_text(f, S->s.plane_yname);
	fprintf(f, " up, in diverging colours symmetric about zero (blue below, red above); each links to its PNG, "
	           "beside it in <a href=\"%sheatmaps/\">heatmaps/</a> the values as EXR and the figure as SVG and "
	           "PDF.</figcaption></figure>\n", prefix);
	if (S->info.nchips) {
		/* pictures, not inline plots: four more full-size plots per target would bury the table */
		fprintf(f, "<p>Error against AMD instruction counts, per chip (Mesa RADV's null device and its ACO "
		           "compiler, %s; net of a load/store baseline; closed forms only). Where an order differs from the "
		           "ALU cost's, the IR's model and the compiler disagree: see <code>brdfkit gpucost "
		           "--calibrate</code>. AMD only: no mobile GPU compiler runs offline.</p>\n<figure>",
		        S->driver);
		for (int c = 0; c < S->info.nchips; c++)
			fprintf(f, "<a href=\"%saco_%s.pdf\"><img src=\"%saco_%s.svg\" width=\"49%%\" alt=\"error against %s "
			           "instructions\"></a>",
			        prefix, S->info.chip[c], prefix, S->info.chip[c], S->info.chip[c]);
		fputs("\n<figcaption>The largest absolute error over the target's samples (log scale) against the "
		      "instructions AMD's ACO compiler emits for each closed form, one plot per chip (", f);
		for (int c = 0; c < S->info.nchips; c++)
			fprintf(f, "%s%s", c ? ", " : "", S->info.chip[c]);
		fprintf(f, "; net of a load/store baseline), markers as in the plot above; each links to its PDF. Data: "
		           "<a href=\"%scompare.csv\">compare.csv</a> (columns aco_CHIP_instructions).</figcaption></figure>\n",
		        prefix);
	}
	fputs("</section>\n", f);
}

static int write_row_files(const study *S, const bk_compare_row *r, const char *dir, char *err, size_t errlen)
{
	char sl[128], path[4400];
	row_stem(S, r, sl, sizeof sl);
	size_t cells = (size_t)S->s.plane_nx * S->s.plane_ny;
	double *v = malloc(sizeof(double) * cells);
	if (!v)
		return -1;
	const bk_form *f = r->f[0]; /* the row's IR; NULL for a LUT */
	if (f) {
		bk_fit_spec sp;
		memset(&sp, 0, sizeof sp);
		sp.s = &S->s;
		sp.form[0] = f;
		sp.np = bk_form_nparams(f);
		bk_fit_plane_error(&sp, r->params, v);
	} else {
		/* the row's own layout, as scored (a LUT re-read from its name once
		 * scored ms's rows, folded at f0 = 1, as the generic layout: refused,
		 * and the heatmap showed what the buffer held) */
		size_t i = (size_t)(r - S->rows);
		bk_fit_metrics m;
		int bad = S->speclut[i] ? bk_speclut_score(&S->spec_layout[i], BK_F64, &S->s, &m, v)
		        : !S->lut[i]    ? -1
		        : S->to.kind == BK_TARGET_SHEEN
		            ? bk_lut_score_cloth(&S->lut_layout[i], S->lut_fmt[i], BK_F64, &S->s, &m, v)
		            : bk_lut_score_layout(&S->lut_layout[i], S->lut_fmt[i], S->to.smith, BK_F64, &S->s, &m, v);
		if (bad) {
			snprintf(err, errlen, "%s: its heatmap could not be scored", r->name);
			free(v);
			return -1;
		}
	}
	int albedo = isfinite(r->m.albedo_max_abs);
	char title[200];
	snprintf(title, sizeof title, "%.90s on %s: %s", r->name, bk_target_name(S->to.kind),
	         albedo ? "directional albedo error" : "error (approx - exact)");
	bk_heatmap h = {S->s.plane_nx, S->s.plane_ny, v, S->s.plane_x0, S->s.plane_x1, S->s.plane_y0,
	                S->s.plane_y1, S->s.plane_xname, S->s.plane_yname, title,
	                albedo ? "albedo_error" : "error", S->s.description};
	snprintf(path, sizeof path, "%.4000s/heatmaps", dir);
	int rc = bk_heatmap_write(&h, path, sl, err, errlen);
	free(v);
	/* Per row, the EXR (every value) and the PNG (for a person) are kept; the
	 * per-cell CSV would be 19 MB over the study's ~90 rows, and the tables a
	 * notebook wants are compare.csv and the fits' heatmap.csv. */
	snprintf(path, sizeof path, "%.4000s/heatmaps/%.120s.csv", dir, sl);
	if (rc == 0)
		unlink(path);
	/* shaders for every form row: published and refit constants alike */
	static const struct { const char *ext; bk_lang lang; } langs[] = {
		{"c", BK_LANG_C}, {"glsl", BK_LANG_GLSL}, {"hlsl", BK_LANG_HLSL}};
	if (f && rc == 0) /* the shaders are single precision */
		form_warn_precision("compare", sl, f, r->params, BK_F32);
	for (size_t k = 0; f && rc == 0 && k < 3; k++) {
		char domain[600], error[160], fname[128];
		snprintf(domain, sizeof domain, "%s", S->s.description);
		snprintf(error, sizeof error, "max |error| %.3g, rmse %.3g", r->m.max_abs, r->m.rmse);
		snprintf(fname, sizeof fname, "%s", sl);
		bk_emit_info info = {fname, r->source, "brdfkit conventions: r perceptual, a = r^2, V includes 1/4",
		                     domain, error, "brdfkit compare (see results/index.html)"};
		char *text = bk_form_emit(f, langs[k].lang, 0, r->params, &info);
		snprintf(path, sizeof path, "%.4000s/shaders/%.120s.%s", dir, sl, langs[k].ext);
		if (!text)
			snprintf(err, errlen, "%.100s: its %s shader could not be generated", r->name, langs[k].ext);
		FILE *o = text ? bk_out_fopen(path, err, errlen) : NULL;
		if (o)
			fputs(text, o);
		if (!o || bk_out_fclose(o, path, err, errlen))
			rc = -1;
		free(text);
	}
	return rc;
}

static int write_dir(study *S, const char *out, const char *prefix)
{
	char path[4400], err[512] = "";
	bk_out_dir od;
	if (bk_out_dir_begin(&od, out, NULL, err, sizeof err))
		return cli_fail("compare", "--out %s", err);
	const char *tmp = od.tmp;
	err[0] = '\0';
	snprintf(path, sizeof path, "%s/heatmaps", tmp);
	int rc = mkdir(path, 0777);
	snprintf(path, sizeof path, "%s/shaders", tmp);
	rc |= mkdir(path, 0777);
	static const char *const files[] = {"compare.csv", "timing.csv", NULL, NULL, "section.html"};
	FILE *f[5] = {0};
	char paths[5][4400];
	for (int k = 0; k < 5 && rc == 0; k++) {
		if (!files[k] || (S->untimed[0] && k == 1))
			continue; /* not measured: no table of empty fields, no plot without points */
		snprintf(paths[k], sizeof paths[k], "%s/%s", tmp, files[k]);
		if (!(f[k] = bk_out_fopen(paths[k], err, sizeof err))) /* a failure named with its errno */
			rc = -1;
	}
	if (rc == 0) {
		char title[160];
		bk_prov_header(f[0], bk_out_command(), S->s.description,
		               "compare: published forms, their refits and LUTs on the same samples: error, op counts, cost");
		bk_compare_csv(f[0], S->rows, S->n, &S->info);
		if (f[1]) {
			bk_prov_header(f[1], bk_out_command(), S->s.description,
			               "compare timing: CPU ns per evaluation of compare.csv's forms (median, min, max of the "
			               "runs): not reproducible");
			bk_timing_csv(f[1], S->rows, S->n);
		}
		snprintf(title, sizeof title, "%s: max |error| against cost", bk_target_name(S->to.kind));
		rc = bk_compare_plot(S->rows, S->n, 0, title, &S->info, tmp, "pareto_cost", err, sizeof err);
		snprintf(title, sizeof title, "%s: max |error| against CPU ns per evaluation", bk_target_name(S->to.kind));
		if (!S->untimed[0] && rc == 0)
			rc = bk_compare_plot(S->rows, S->n, 1, title, &S->info, tmp, "pareto_ns", err, sizeof err);
		for (int c = 0; c < S->info.nchips && rc == 0; c++) {
			char stem[80];
			snprintf(stem, sizeof stem, "aco_%.60s", S->info.chip[c]);
			snprintf(title, sizeof title, "%s: max |error| against AMD %s instructions", bk_target_name(S->to.kind),
			         S->info.chip[c]);
			rc = bk_compare_plot(S->rows, S->n, 2 + c, title, &S->info, tmp, stem, err, sizeof err);
		}
		write_section(S, f[4], tmp, prefix);
	}
	for (int k = 0; k < 5; k++) {
		char e[1200];
		if (f[k] && bk_out_fclose(f[k], paths[k], e, sizeof e)) {
			if (!rc)
				snprintf(err, sizeof err, "%.500s", e);
			rc = -1;
		}
	}
	for (int i = 0; i < S->n && rc == 0; i++) {
		rc = write_row_files(S, &S->rows[i], tmp, err, sizeof err);
		cli_progress("compare: heatmaps and shaders", i + 1, S->n);
	}
	if (rc) {
		bk_out_dir_abort(&od);
		return cli_fail("compare", "%s: writing the results failed%s%s", out, *err ? ": " : "", err);
	}
	/* replaced whole, and only if brdfkit wrote what is there */
	return bk_out_dir_commit(&od, err, sizeof err) ? cli_fail("compare", "--out %s", err) : 0;
}

/* ---- where the options act (cli.h) ----------------------------------------- */

/* The target (form is refused before: no catalog entry answers it); whether
 * the CPU time is measured; whether the catalog forms are refitted; whether
 * there are LUT rows, the only rows with a texture fetch (env, not --no-lut). */
enum { DIM_TARGET, DIM_TIME, DIM_REFIT, DIM_FETCH };
static const cli_dim dims[] = {
	{"target", /* bk_target_kind's order; form is refused before any context */
	 {"vf2d", "vf", "spec", "env", "d", "f", "form", "ms", "sheen"},
	 {" on target vf2d", " on target vf", " on target spec", " on target env", " on target d", " on target f",
	  cli_unreached, " on target ms", " on target sheen"}},
	{"time", {"measured", "skipped"}, {NULL, " with --no-time"}},
	{"refit", {"refits", "none"}, {NULL, " with --no-refit"}},
	{"fetches", {"lut", "none"}, {NULL, " without LUT rows (targets env, spec, ms and sheen only, not with --no-lut)"}},
};
static const cli_rule rules[] = {
	{"--no-lut", NULL, DIM_TARGET, FITARGS_ON(ENV) | FITARGS_ON(SPEC) | FITARGS_ON(MS) | FITARGS_ON(SHEEN),
	 "LUT rows are scored for targets env, spec, ms and sheen only", NULL},
	{"--nr", NULL, DIM_TARGET, FITARGS_ALL & ~FITARGS_ON(F) & ~FITARGS_ON(FORM) & ~FITARGS_FILE, "target f has no roughness axis", "8"},
	{"--reps", NULL, DIM_TIME, 1u << 0, NULL, "3"},
	{"--relative", NULL, DIM_REFIT, 1u << 0, "it sets the residuals of the refits", NULL},
	{"--fetch-cost", NULL, DIM_FETCH, 1u << 0, "it prices a texture fetch, and only LUT rows fetch", "32"},
	{"--target", NULL, CLI_EVERYWHERE, 0, NULL, NULL},
	{"--out", NULL, CLI_EVERYWHERE, 0, NULL, NULL},
	{"--nx", NULL, CLI_EVERYWHERE, 0, NULL, "8"},
	{"--no-refit", NULL, CLI_EVERYWHERE, 0, NULL, NULL},
	{"--no-time", NULL, CLI_EVERYWHERE, 0, NULL, NULL},
	{"--link-prefix", NULL, CLI_EVERYWHERE, 0, NULL, "x/"},
	{"--cost-model", NULL, CLI_EVERYWHERE, 0, NULL, "aco-navi21"},
	{"--gpu", NULL, CLI_EVERYWHERE, 0, NULL, "navi21"},
};
static const char *const setups[] = {
	"--target vf2d --out o", "--target vf --out o", "--target spec --out o", "--target env --out o",
	"--target d --out o", "--target f --out o", "--target vf2d --no-time --out o", "--target vf2d --no-refit --out o",
	"--target env --no-lut --out o", "--target ms --out o", "--target sheen --out o", NULL};
static const cli_table table = {dims, 4, rules, sizeof rules / sizeof rules[0], setups};

/* The typed forms, parsed once here, the command line's edge: each row,
 * check and score after reads this IR. 0, or 2 after the column of a syntax
 * error (typed[0..npos) then hold what parsed; the caller frees them). */
static int parse_typed(const cli_cmd *cmd, bk_form **typed)
{
	for (int i = 0; i < cmd->npos; i++) {
		bk_form_error fe;
		if (!(typed[i] = bk_form_parse(cmd->pos[i], &fe))) {
			fprintf(stderr, "brdfkit compare: form:1:%d: %s\n", fe.column, fe.message);
			return 2;
		}
	}
	return 0;
}

/* Refuses typed forms that cannot be scored as written: with parameters
 * (there are no values to give them) or reading an input the target does not
 * provide (NaN at every sample, which the metrics skip: rmse 0). provides:
 * the target's inputs, or 0 before the samples exist. Returns 0 or 2. */
static int check_args(const cli_cmd *cmd, bk_form *const *typed, bk_target_kind kind, unsigned provides)
{
	for (int i = 0; i < cmd->npos; i++) {
		unsigned used = bk_form_params(typed[i]), extra = bk_form_inputs(typed[i]) & ~provides;
		char uses[80];
		form_params_text(used, uses, sizeof uses);
		if (used)
			return cli_usage(cmd, "'%s' uses %s: compare scores a typed form as written (write its constants "
			                 "as numbers, or fit it with brdfkit fit)", cmd->pos[i], uses);
		for (int k = 0; provides && k < BK_IN_COUNT; k++)
			if (extra >> k & 1)
				return cli_usage(cmd, "'%s' reads %s, which target %s does not provide", cmd->pos[i],
				                 bk_input_name((bk_input)k), bk_target_name(kind));
	}
	return 0;
}

/* The study itself, after the options: the reference samples, the
 * catalog's rows and their refits, the typed forms (typed: their IR, which
 * the rows take), the LUTs, the timings and the files. Returns the exit code;
 * the rows' IR is freed here, typed[] (what no row took) by the caller. */
static int study_run(study *S, const cli_cmd *cmd, bk_form **typed, bk_target_kind kind, int t, long nx, long nr,
                     int relative, int no_refit, int no_time, int no_lut, long reps, const char *model,
                     const char *gpu, const char *out, const char *prefix)
{
	int rc = check_args(cmd, typed, kind, 0);
	if (rc)
		return rc;
	bk_target_defaults(kind, &S->to);
	S->to.env_f0_form = kind == BK_TARGET_ENV;
	if (kind == BK_TARGET_VF2D)
		S->to.nx = S->to.nr = 128; /* the study's grid: 128² keeps every heatmap CSV under 1 MB */
	if (kind == BK_TARGET_ENV || kind == BK_TARGET_MS || kind == BK_TARGET_SHEEN)
		S->to.nx = S->to.nr = 100; /* cell centres that are no LUT's texel centres (16..128): a
		                          * LUT scored at its own texels would show no interpolation error */
	if (nx) S->to.nx = (int)nx;
	if (nr) S->to.nr = (int)nr;
	S->relative = relative;
	S->refit = !no_refit;
	S->tier = t;
	S->info = (bk_compare_info)BK_COMPARE_INFO_INIT;
	if (model && cli_cost_model(cmd, model, &S->info.simple, &S->info.complex))
		return 2;
	if (model)
		S->info.cost_model = model;
	static char chipbuf[512];
	if (gpu) {
		char gerr[700];
		snprintf(chipbuf, sizeof chipbuf, "%s", gpu);
		if (bk_gpucost_chips(chipbuf, S->info.chip, BK_COMPARE_CHIPS, &S->info.nchips, gerr, sizeof gerr))
			return cli_usage(cmd, "--gpu: %s", gerr);
	}
	char err[700];
	if (bk_out_dir_check(out, err, sizeof err)) /* before minutes of work, not after */
		return cli_fail("compare", "--out %s", err);
	if (S->info.nchips && bk_gpucost_check(S->info.chip, S->info.nchips, S->driver, sizeof S->driver, err, sizeof err))
		return cli_fail("compare", "--gpu: %s", err);
	if (bk_lutcache_target_build(&S->to, &S->s, cli_progress, "compare: reference", err, sizeof err))
		return cli_fail("compare", "%s", err);
	if ((rc = check_args(cmd, typed, kind, S->s.provides))) {
		bk_samples_free(&S->s);
		return rc;
	}
	for (int i = 0; i < cmd->npos; i++) { /* typed forms, before the minutes of refits */
		const double zero[BK_MAX_PARAMS] = {0};
		if (nowhere_finite(&S->s, typed[i], zero)) { /* a row of blank metrics is no score */
			fprintf(stderr, "brdfkit compare: form '%s': not finite at any of the %zu samples of the "
			                "target\n", cmd->pos[i], S->s.n);
			bk_samples_free(&S->s);
			return 2;
		}
	}
	for (size_t i = 0; i < bk_catalog_count(); i++) {
		const bk_catalog_entry *e = bk_catalog_at(i);
		if (bk_catmap_answers(kind, 1, e))
			add_entry(S, e);
		cli_progress("compare: catalog forms and refits", (int)i + 1, (int)bk_catalog_count());
	}
	for (int i = 0; i < cmd->npos && S->n < MAX_ROWS; i++) {
		bk_compare_row *r = &S->rows[S->n];
		memset(r, 0, sizeof *r);
		r->f[0] = typed[i]; /* the row takes the form's IR */
		typed[i] = NULL;
		snprintf(r->form, sizeof r->form, "%s", cmd->pos[i]);
		row_text(r, cmd->pos[i], "form", "typed on the command line");
		score(S, r, r->f[0]);
		S->n++;
	}
	if ((kind == BK_TARGET_ENV || kind == BK_TARGET_MS || kind == BK_TARGET_SHEEN) && !no_lut)
		add_luts(S);
	for (int i = 0; kind == BK_TARGET_ENV && i < S->n; i++) /* ms: the fetch is E, no ALU */
		if (!strcmp(S->rows[i].kind, "lut")) { /* f0·A + B after the fetch: one mad */
			S->rows[i].ops.n[BK_K_MAD] = 1;
			S->rows[i].ops.simple = 1;
			S->rows[i].cost = S->info.simple;
		}
	if (kind == BK_TARGET_SPEC && !no_lut) /* after the loop above: their ops are their own */
		add_speclut_rows(S);
	if (no_time)
		snprintf(S->untimed, sizeof S->untimed, "--no-time");
	else if (bk_time_rows(S->rows, S->n, (int)reps, err, sizeof err)) {
		fprintf(stderr, "brdfkit compare: warning: timing skipped: %s\n", err);
		snprintf(S->untimed, sizeof S->untimed, "timing failed: %.270s", err);
	}
	if (S->info.nchips && (rc = gpu_columns(S))) {
		bk_compare_rows_free(S->rows, S->n);
		bk_samples_free(&S->s);
		return rc;
	}
	bk_pareto(S->rows, S->n, t);
	char *pre = bk_html_link_text(prefix, NULL); /* the one link writer (out.h): encoded, escaped */
	rc = pre ? write_dir(S, out, pre) : cli_fail("compare", "out of memory");
	free(pre);
	bk_compare_rows_free(S->rows, S->n);
	bk_samples_free(&S->s);
	return rc;
}

int cmd_compare(int argc, char **argv)
{
	const char *target = NULL, *out = NULL, *prefix = "", *model = NULL, *gpu = NULL;
	long nx = 0, nr = 0, reps = 7, tier = 16;
	int relative = 0, no_refit = 0, no_time = 0, no_lut = 0;
	cli_opt opts[] = {
		{.name = "--target", .kind = CLI_STR, .metavar = "T", .help = "vf2d, vf, spec, env, d, f, ms or sheen", .dest = &target, .required = 1},
		{.name = "--out", .kind = CLI_STR, .metavar = "DIR", .help = "results directory (replaced whole)", .dest = &out, .required = 1},
		{.name = "--nx", .kind = CLI_INT, .metavar = "N", .help = "cells along x (default: the target's)", .dest = &nx, .lo = 1, .hi = 1024},
		{.name = "--nr", .kind = CLI_INT, .metavar = "N", .help = "cells along roughness", .dest = &nr, .lo = 1, .hi = 1024},
		{.name = "--relative", .kind = CLI_FLAG, .help = "relative residuals for the refits", .dest = &relative},
		{.name = "--no-refit", .kind = CLI_FLAG, .help = "published constants only", .dest = &no_refit},
		{.name = "--no-time", .kind = CLI_FLAG, .help = "skip CPU timing", .dest = &no_time},
		{.name = "--no-lut", .kind = CLI_FLAG, .help = "env, spec, ms, sheen: leave out the LUT rows", .dest = &no_lut},
		{.name = "--reps", .kind = CLI_INT, .metavar = "N", .help = "timing runs per form (default 7)", .dest = &reps, .lo = 1, .hi = 1000},
		{.name = "--fetch-cost", .kind = CLI_INT, .metavar = "16|32|48|64", .help = "a texture fetch priced as K simple ops, the talk's ALU:TEX tiers, for the front (env's and spec's LUT rows; default 16)", .dest = &tier, .lo = 16, .hi = 64},
		{.name = "--link-prefix", .kind = CLI_LINK, .metavar = "PATH/", .help = "prefix of links in section.html (where DIR is seen from the page): a path relative to the page (no scheme, no //host), percent-encoded where written", .dest = &prefix},
		{.name = "--cost-model", .kind = CLI_STR, .metavar = "NAME", .help = "weights of the ALU cost: ir (default; simple 1, complex 4) or aco-polaris10, aco-vega10, aco-navi21, aco-gfx1100", .dest = &model},
		{.name = "--gpu", .kind = CLI_STR, .metavar = "CHIPS", .help = "AMD instruction counts per chip (brdfkit gpucost), e.g. " BK_GPUCOST_DEFAULT_CHIPS, .dest = &gpu},
	};
	cli_cmd cmd = {"compare", "Scores every catalog form for a target, its refit and (env, spec, ms, sheen) the LUT alternative on\n"
	               "the same samples: error, ALU cost, texture fetches, CPU ns, SPIR-V size, the Pareto front.",
	               "--target T --out DIR [FORM ...] [options]",
	               "Writes DIR/compare.csv, timing.csv, pareto_cost.svg, pareto_ns.svg, section.html (for the\n"
	               "report page), heatmaps/ and shaders/ (no timing.csv or pareto_ns.svg with --no-time).\n"
	               "Extra FORM arguments are scored as typed forms.\n"
	               "--gpu compiles every closed form for each chip as brdfkit gpucost does (Mesa RADV's\n"
	               "null device; needs mesa-vulkan-drivers) and adds aco_CHIP_instructions,\n"
	               "aco_CHIP_transcendental and aco_CHIP_vgprs to compare.csv and aco_CHIP.svg plots.",
	               opts, (int)(sizeof opts / sizeof opts[0]), 32, 0, {0}};
	int rc = cli_parse_table(&cmd, &table, argc, argv);
	if (rc)
		return rc == 1 ? 0 : rc;
	if (cli_form_positionals(&cmd, 0))
		return 2;
	bk_target_kind kind;
	if (bk_target_parse(target, &kind)) {
		return cli_unknown_value("--target", target, cli_targets, CLI_NTARGETS);
	}
	if (kind == BK_TARGET_FORM) { /* no catalog entry answers a user's formula */
		return cli_bad("--target form: compare scores the catalog; fit a form target with brdfkit fit");
	}
	if (kind == BK_TARGET_TABLE || kind == BK_TARGET_MERL) /* the catalog's forms answer brdfkit's own targets */
		return cli_bad("--target %s: compare scores the catalog on brdfkit's own targets; fit or search a file's "
		               "samples with brdfkit fit or brdfkit search", bk_target_name(kind));
	int t = -1;
	for (int k = 0; k < BK_TIERS; k++)
		if (bk_tier_alu_per_tex[k] == tier)
			t = k;
	if (t < 0) {
		return cli_usage(&cmd, "--fetch-cost: expected 16, 32, 48 or 64 (the talk's ALU:TEX tiers), got %ld", tier);
	}
	int ctx[] = {(int)kind, no_time, no_refit,
	             (kind != BK_TARGET_ENV && kind != BK_TARGET_SPEC && kind != BK_TARGET_MS && kind != BK_TARGET_SHEEN) ||
	                 no_lut};
	if ((rc = cli_applicable(&cmd, ctx)))
		return rc;
	/* 4.3 MB, on the heap: as a static it sat in every process's .bss, which
	 * LeakSanitizer reads whole at each sanitized exit (a page fault per
	 * 4 KB, whatever the command) */
	study *S = calloc(1, sizeof *S);
	if (!S)
		return cli_fail("compare", "out of memory");
	bk_form *typed[sizeof cmd.pos / sizeof cmd.pos[0]] = {NULL};
	if ((rc = parse_typed(&cmd, typed)) == 0)
		rc = study_run(S, &cmd, typed, kind, t, nx, nr, relative, no_refit, no_time, no_lut, reps, model, gpu, out,
		               prefix);
	for (int i = 0; i < cmd.npos; i++)
		bk_form_free(typed[i]);
	free(S);
	return rc;
}
