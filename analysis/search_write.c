/*
 * search_write.c — brdfkit search's files and report (search_write.h).
 */
#include "search_write.h"
#include "prov.h"

#include "out.h"
#include "plot.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The certificate in words (fit/search.h, bk_search_cert_text). */
static void cert_text(const bk_swrite *W, char *buf, size_t len)
{
	bk_search_cert_text(W->cert, &W->F->so->grammar, buf, len);
}

static void header(FILE *f, const bk_swrite *W, const char *what)
{
	bk_prov_header(f, W->command, W->F->s->description, "search %s", what);
	if (W->F->so->islands > 1)
		fprintf(f, "# islands: %d MPI ranks (%s), --evals shared out, --migrate %ld fits per island between "
		        "migrations of %ld front members round a ring; found_at counts the fits of the member's island%s\n",
		        W->F->so->islands, W->islands_name, W->migrate, W->migrants,
		        W->merge_fronts ? "; --merge-fronts: the candidates of island 0, and of the others their "
		                             "screening fronts" : "");
	if (W->cert) {
		char cert[2048];
		cert_text(W, cert, sizeof cert);
		fprintf(f, "# certificate: %s\n", cert);
	}
	fprintf(f, "# cost: simple*%g + complex*%g after folding, sharing and multiply-add fusion (brdfkit ops%s%s); "
	        "error: %s in %s precision on the target's samples; conventions: r perceptual roughness, a = r^2, "
	        "V includes 1/(4 NoL NoV)\n", W->F->so->simple_cost, W->F->so->complex_cost,
	        W->cost_model ? ", cost model " : "", W->cost_model ? W->cost_model : "", bk_sfront_objective_name(W->F->so),
	        bk_precision_name(W->F->so->precision));
}

static void params_field(FILE *f, const double *p, int np)
{
	for (int j = 0; j < np; j++)
		fprintf(f, "%sp%d=%.17g", j ? ";" : "", j, p[j]);
}

/* The first fields of a row: name, form, form_b, parameters. */
static void row_lead(FILE *f, const bk_sfront_member *m)
{
	bk_csv_field(f, m->name);
	fputc(',', f);
	bk_csv_field(f, m->text);
	fputc(',', f);
	bk_csv_field(f, m->text_b ? m->text_b : "");
	fputc(',', f);
	params_field(f, m->res.p, m->spec.np);
}

/* --gpu columns: per chip ACO's net instructions and transcendental ops,
 * empty where nothing was compiled (a LUT row); each ends the line. */
static void gpu_header(FILE *f, const bk_swrite *W)
{
	for (int c = 0; c < W->nchips; c++)
		fprintf(f, ",aco_%s_instructions,aco_%s_transcendental", W->chip[c], W->chip[c]);
	fputc('\n', f);
}

static void gpu_fields(FILE *f, const bk_swrite *W, const bk_sfront_member *m)
{
	for (int c = 0; c < W->nchips; c++)
		if (isnan(m->gpu_insn[c]))
			fputs(",,", f);
		else
			fprintf(f, ",%.0f,%.0f", m->gpu_insn[c], m->gpu_transc[c]);
	fputc('\n', f);
}

void bk_swrite_front_csv(FILE *f, const bk_swrite *W)
{
	header(f, W, "front (refitted on the full samples)");
	fprintf(f, "name,form,form_b,parameters,simple,complex,cost,error,rmse,max_abs,max_rel,albedo_max_abs,f16_max_abs,"
	        "stability_half,found_at,%sdominates", W->F->so->islands > 1 ? "island," : "");
	gpu_header(f, W);
	for (int i = 0; i < W->F->nm; i++) {
		const bk_sfront_member *m = &W->F->m[i];
		if (!m->front)
			continue;
		row_lead(f, m);
		fprintf(f, ",%d,%d,%g,%.6g,%.6g,%.6g,%.6g,", m->ops.simple, m->ops.complex, m->cost, m->err, m->prec.rmse,
		        m->prec.max_abs, m->prec.max_rel);
		if (isfinite(m->prec.albedo_max_abs))
			fprintf(f, "%.6g", m->prec.albedo_max_abs);
		fprintf(f, ",%.6g,%s,%ld,", m->f16_max, m->verdict, m->c->found_at);
		if (W->F->so->islands > 1)
			fprintf(f, "%d,", m->c->island);
		char dom[2048] = "";
		for (int k = 0; k < W->F->nm; k++) /* the catalog rows this member beats */
			if (bk_sfront_beats(m, &W->F->m[k]))
				snprintf(dom + strlen(dom), sizeof dom - strlen(dom), "%s%s", *dom ? ";" : "", W->F->m[k].name);
		bk_csv_field(f, dom);
		gpu_fields(f, W, m);
	}
}

void bk_swrite_catalog_csv(FILE *f, const bk_swrite *W)
{
	header(f, W, "published forms on the same samples, published and refitted");
	fputs("name,form,form_b,parameters,cost,error,rmse,max_abs,albedo_max_abs,f16_max_abs,stability_half", f);
	gpu_header(f, W);
	for (int i = 0; i < W->F->nm; i++) {
		const bk_sfront_member *m = &W->F->m[i];
		if (m->c)
			continue;
		row_lead(f, m);
		fprintf(f, ",%g,%.6g,%.6g,%.6g,", m->cost, m->err, m->prec.rmse, m->prec.max_abs);
		if (isfinite(m->prec.albedo_max_abs))
			fprintf(f, "%.6g", m->prec.albedo_max_abs);
		fputc(',', f);
		if (!isnan(m->f16_max)) /* NaN: no form (a LUT row); inf: not finite in half */
			fprintf(f, "%.6g", m->f16_max);
		fprintf(f, ",%s", m->verdict);
		gpu_fields(f, W, m);
	}
}

void bk_swrite_candidates_csv(FILE *f, const bk_swrite *W)
{
	static const char *const st[] = {"ok", "not finite", "constraint", "fit failed"};
	size_t n = bk_search_count(W->F->S);
	size_t *idx = malloc(sizeof(size_t) * (n ? n : 1));
	char *on = calloc(n ? n : 1, 1);
	size_t nf = idx && on ? bk_search_front(W->F->S, idx, n) : 0;
	for (size_t i = 0; i < nf; i++)
		on[idx[i]] = 1;
	header(f, W, "every distinct candidate fitted (screening samples); front: on the screening front");
	fprintf(f, "found_at,%scost,error,status,front,seed,form,form_b\n", W->F->so->islands > 1 ? "island," : "");
	for (size_t i = 0; i < n; i++) {
		const bk_cand *c = bk_search_at(W->F->S, i);
		fprintf(f, "%ld,", c->found_at);
		if (W->F->so->islands > 1)
			fprintf(f, "%d,", c->island);
		fprintf(f, "%g,", c->cost);
		if (c->status == BK_CAND_OK)
			fprintf(f, "%.9g", c->err);
		fprintf(f, ",%s,%d,", st[c->status], on ? on[i] : 0);
		bk_csv_field(f, c->seed_name ? c->seed_name : "");
		fputc(',', f);
		bk_csv_field(f, c->text);
		fputc(',', f);
		bk_csv_field(f, c->text_b ? c->text_b : "");
		fputc('\n', f);
	}
	free(idx);
	free(on);
}

void bk_swrite_target_label(const bk_swrite *W, char *out, size_t len)
{
	const char *ef = W->F->kind == BK_TARGET_ENV ? W->env_form : NULL;
	const bk_target_options *to = W->to;
	if (ef && !strcmp(ef, "f0"))
		snprintf(out, len, "env_f0 (f0 A + B as one form in f0)");
	else if (ef && !strcmp(ef, "mix"))
		snprintf(out, len, "env_mix (f0 A + B in f0, seeded with mix(B, A + B, f0))");
	else if (W->F->kind == BK_TARGET_F && to && to->k > 0)
		snprintf(out, len, "f (Fresnel of n = %g + %gi, f0 = %.3g)", to->eta, to->k, bk_f0_from_ior(to->eta, to->k));
	else if (W->F->kind == BK_TARGET_F && to)
		snprintf(out, len, "f (Fresnel of n = %g, f0 = %.3g)", to->eta, bk_f0_from_ior(to->eta, 0.0));
	else
		snprintf(out, len, "%s", bk_target_name(W->F->kind));
}

/* The figure (plot.h, 7 x 4.2 in): every screened candidate as a grey dot (one per
 * 1/72 in cell it covers: tens of thousands of candidates fall on a few thousand
 * cells), the front as a blue staircase with labelled circles, the catalog
 * published (red triangles) and refitted (orange squares), error (log) against cost,
 * in the style of compare's plots. */
int bk_swrite_plot(const bk_swrite *sw, const char *dir, char *err, size_t errlen)
{
	const bk_sfront *F = sw->F;
	size_t nc = bk_search_count(F->S), nm = (size_t)F->nm;
	double *x = malloc(sizeof *x * (nc + 3 * nm + 1)), *y = malloc(sizeof *y * (nc + 3 * nm + 1));
	const char **lab = calloc(nm + 1, sizeof *lab);
	if (!x || !y || !lab) {
		free(x);
		free(y);
		free(lab);
		snprintf(err, errlen, "%s/pareto: out of memory", dir);
		return -1;
	}
	/* members first (the front in cost order, as the front list keeps it), then the cloud */
	bk_plot_series s[5] = {
		{"search front (refitted)", BK_PLOT_STEPS, BK_PLOT_CIRCLE, 0, 0x1f5fbf, 0, x, y, NULL, NULL, NULL},
		{NULL, BK_PLOT_POINTS, BK_PLOT_CIRCLE, 0, 0x1f5fbf, 0, x + nm, y + nm, lab, NULL, NULL},
		{"published", BK_PLOT_POINTS, BK_PLOT_TRIANGLE, 0, 0xc0392b, 0, x + 2 * nm, y + 2 * nm, NULL, NULL, NULL},
		{"published, refitted", BK_PLOT_POINTS, BK_PLOT_SQUARE, 0, 0xe67e22, 0, x + 2 * nm + nm / 2 + 1,
		 y + 2 * nm + nm / 2 + 1, NULL, NULL, NULL},
		{"every candidate (screening)", BK_PLOT_POINTS, BK_PLOT_DOT, 0, 0xb0b0b0, 0, x + 3 * nm + 1, y + 3 * nm + 1,
		 NULL, NULL, NULL},
	};
	/* refitted and published share 2 nm.. 3 nm: at most nm catalog rows in all */
	size_t off[5] = {0, nm, 2 * nm, 0, 3 * nm + 1};
	int npub = 0, nref = 0;
#define PUT(k, X, Y) (x[off[k] + (size_t)s[k].n] = (X), y[off[k] + (size_t)s[k].n++] = (Y))
	for (int i = 0; i < F->nm; i++) {
		const bk_sfront_member *m = &F->m[i];
		if (m->status || !(m->err > 0))
			continue;
		if (m->front) {
			PUT(0, m->cost, m->err);
			lab[s[1].n] = m->name;
			PUT(1, m->cost, m->err);
		} else if (!m->c)
			npub += !m->refit, nref += m->refit;
	}
	off[3] = 2 * nm + (size_t)npub;
	s[3].x = x + off[3];
	s[3].y = y + off[3];
	for (int i = 0; i < F->nm; i++) {
		const bk_sfront_member *m = &F->m[i];
		if (m->status || !(m->err > 0) || m->front || m->c)
			continue;
		PUT(m->refit ? 3 : 2, m->cost, m->err);
	}
	(void)nref;
	bk_plot p = {BK_PLOT_DOUBLE_W, 4.2, NULL, NULL, NULL, {0}, {0}, NULL, 0, NULL};
	char title[300], xl[200], note[200], what[160];
	bk_swrite_target_label(sw, what, sizeof what);
	snprintf(title, sizeof title, "search on %s: %s (%s precision) against cost", what,
	         bk_sfront_objective_name(F->so), bk_precision_name(F->so->precision));
	snprintf(xl, sizeof xl, "cost (simple ALU ops \xc3\x97 %g + complex \xc3\x97 %g)", F->so->simple_cost,
	         F->so->complex_cost);
	p.title = title;
	p.x.label = xl;
	p.y.label = "error (log scale)";
	p.y.log = 1;
	for (int k = 0; k < 4; k++) {
		bk_plot_axis_grow(&p.x, s[k].x, s[k].n);
		bk_plot_axis_grow(&p.y, s[k].y, s[k].n);
	}
	if (!(p.y.hi > p.y.lo))
		bk_plot_axis_fit(&p.y, NULL, 0);
	if (!(p.x.hi > p.x.lo)) {
		double one = 1.0;
		bk_plot_axis_fit(&p.x, &one, 1);
	}
	/* the cloud within the axes, one dot per 1-point cell (a dot is wider than
	 * that: more dots would only overdraw, and each is a path in the SVG and
	 * PDF, which at the PNG's pixel grid reached 6.5 MB for env_f0) */
	int gw = 72 * 7, gh = 72 * 5;
	unsigned char *seen = calloc((size_t)gw * gh, 1);
	for (size_t i = 0; seen && i < nc; i++) {
		const bk_cand *c = bk_search_at(F->S, i);
		if (c->status != BK_CAND_OK || !(c->cost >= p.x.lo && c->cost <= p.x.hi) ||
		    !(c->err >= p.y.lo && c->err <= p.y.hi))
			continue;
		int gx = (int)((c->cost - p.x.lo) / (p.x.hi - p.x.lo) * (gw - 1));
		int gy = (int)((bk_dlog10(c->err) - bk_dlog10(p.y.lo)) / (bk_dlog10(p.y.hi) - bk_dlog10(p.y.lo)) * (gh - 1));
		if (seen[(size_t)gy * gw + gx]++)
			continue;
		PUT(4, c->cost, c->err);
	}
	free(seen);
#undef PUT
	/* the cloud first: drawn under the members; its series order is the legend's last */
	bk_plot_series order[5] = {s[4], s[0], s[2], s[3], s[1]};
	p.series = order;
	p.nseries = 5;
	snprintf(note, sizeof note, "%ld candidate fits, seed %ld; the front refitted on the full samples",
	         sw->total_evals, sw->seed);
	p.note = note;
	p.provenance = sw->command;
	int rc = bk_plot_write_files(&p, dir, "pareto", err, errlen);
	free(x);
	free(y);
	free(lab);
	return rc;
}

void bk_swrite_section(FILE *f, const bk_swrite *W)
{
	char base[256], id[256];
	const char *b = strrchr(W->out, '/');
	snprintf(base, sizeof base, "%s", b && b[1] ? b + 1 : W->out);
	bk_slug(base, id, sizeof id);
	fprintf(f, "<section id=\"search-%s\">\n<h2>Search on <code>%s</code> (%s)</h2>\n<p>", id,
	        bk_target_name(W->F->kind), id);
	bk_html_text(f, W->F->s->description);
	fprintf(f, "</p>\n<p>%ld candidate fits (seed %ld); error: %s in %s precision; cost: simple*%g + complex*%g. "
	        "<code>", W->total_evals, W->seed, bk_sfront_objective_name(W->F->so), bk_precision_name(W->F->so->precision),
	        W->F->so->simple_cost, W->F->so->complex_cost);
	bk_html_text(f, W->command);
	const char *P = W->prefix ? W->prefix : "";
	fputs("</code></p>\n", f);
	if (W->cert) {
		char cert[2048];
		cert_text(W, cert, sizeof cert);
		fputs("<p class=\"certificate\">Complete: ", f);
		bk_html_text(f, cert);
		fputs(".</p>\n", f);
	}
	fputs("<figure><img src=\"", f);
	bk_html_link(f, P, "pareto.svg");
	fprintf(f, "\" width=\"100%%\" alt=\"error against cost\">\n<figcaption>Error (%s in %s precision, "
	        "log scale) against cost (brdfkit ops: simple \xc3\x97 %g + complex \xc3\x97 %g) on <code>%s</code>: the "
	        "front refitted on the full samples (the dashed staircase), the published forms with their published "
	        "and their refitted constants (as the legend marks them), every candidate at screening (grey, %ld fits). "
	        "Data: <a href=\"", bk_sfront_objective_name(W->F->so), bk_precision_name(W->F->so->precision),
	        W->F->so->simple_cost, W->F->so->complex_cost, id, W->total_evals);
	bk_html_link(f, P, "front.csv");
	fputs("\">front.csv</a>, <a href=\"", f);
	bk_html_link(f, P, "catalog.csv");
	fputs("\">catalog.csv</a>; as <a href=\"", f);
	bk_html_link(f, P, "pareto.pdf");
	fputs("\">PDF</a>, <a href=\"", f);
	bk_html_link(f, P, "pareto.png");
	fputs("\">PNG</a>.</figcaption></figure>\n<table>\n<tr><th>name</th><th>form</th><th>cost</th>"
	      "<th>error</th><th>rmse</th><th>max |err|</th><th>half</th><th>beats</th><th>files</th></tr>\n", f);
	for (int pass = 0; pass < 2; pass++)
		for (int i = 0; i < W->F->nm; i++) {
			const bk_sfront_member *m = &W->F->m[i];
			if (pass == 0 ? !m->front : m->c != NULL)
				continue;
			fputs("<tr><td>", f);
			bk_html_text(f, m->name);
			fputs("</td><td><code>", f);
			bk_html_text(f, m->text);
			if (m->text_b) {
				fputs(" | ", f);
				bk_html_text(f, m->text_b);
			}
			fprintf(f, "</code></td><td>%g</td><td>%.3g</td><td>%.3g</td><td>%.3g</td><td>%s</td><td>", m->cost,
			        m->err, m->prec.rmse, m->prec.max_abs, m->verdict);
			for (int k = 0, first = 1; pass == 0 && k < W->F->nm; k++)
				if (bk_sfront_beats(m, &W->F->m[k])) {
					fputs(first ? "" : ", ", f);
					bk_html_text(f, W->F->m[k].name);
					first = 0;
				}
			fputs("</td><td>", f);
			for (int k = 0; pass == 0 && k < 6; k++) { /* the member's heatmap and shaders (fit_out.c) */
				static const char *const file[6] = {"heatmap.png", "shader.glsl", "shader.hlsl", "shader.metal",
				                                    "shader_f16.glsl", "shader_f16.hlsl"};
				if (k == 0 && !(W->to->kind != BK_TARGET_FORM || W->to->ndomain <= 2))
					continue;
				if (k >= 4 && W->F->so->precision != BK_F16) /* float16_t and half: half fronts only */
					continue;
				char path[300];
				snprintf(path, sizeof path, "front/%s/%s", m->name, file[k]);
				fputs("<a href=\"", f);
				bk_html_link(f, P, path);
				fprintf(f, "\">%s</a> ", file[k]);
			}
			fputs("</td></tr>\n", f);
		}
	fputs("</table>\n", f);
	if (W->F->so->precision == BK_F16)
		fprintf(f, "<p>In half precision the front holds only members safe in half (as is or with their computed "
		        "guards); %d refitted member%s not safe in half %s left off it. The published forms above are "
		        "evaluated in half, with their verdict.</p>\n", W->F->unsafe, W->F->unsafe == 1 ? "" : "s",
		        W->F->unsafe == 1 ? "was" : "were");
	if (W->vs)
		bk_halfvs_html(f, W->vs, W->vs_path, bk_sfront_objective_name(W->F->so), W->prefix);
	fputs("</section>\n", f);
}

void bk_swrite_vs_csv(FILE *f, const bk_swrite *W)
{
	bk_halfvs_csv(f, W->vs, W->command, W->vs_path, bk_sfront_objective_name(W->F->so));
}

void bk_swrite_report(FILE *f, const bk_swrite *W)
{
	fprintf(f, "search on %s: %ld fits, %zu distinct candidates; front (refitted on %zu samples, %s in %s):\n",
	       bk_target_name(W->F->kind), W->total_evals, bk_search_count(W->F->S), W->F->s->n, bk_sfront_objective_name(W->F->so),
	       bk_precision_name(W->F->so->precision));
	if (W->cert) {
		char cert[2048];
		cert_text(W, cert, sizeof cert);
		fprintf(f, "complete: %s\n", cert);
	}
	for (int pass = 0; pass < 2; pass++)
		for (int i = 0; i < W->F->nm; i++) {
			const bk_sfront_member *m = &W->F->m[i];
			if (pass == 0 ? !m->front : m->c != NULL)
				continue;
			fprintf(f, "  %-28s cost %-4g %s %-10.4g %s%s%s\n", m->name, m->cost, bk_sfront_objective_name(W->F->so), m->err, m->text,
			       m->text_b ? " | " : "", m->text_b ? m->text_b : "");
		}
}

