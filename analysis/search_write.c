/*
 * search_write.c — brdfkit search's files and report (search_write.h).
 */
#include "search_write.h"

#include "out.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void header(FILE *f, const bk_swrite *W, const char *what)
{
	fprintf(f, "# brdfkit %s search %s\n# command: %s\n# target: %s\n", BK_VERSION, what, W->command, W->F->s->description);
	if (W->F->so->islands > 1)
		fprintf(f, "# islands: %d MPI ranks (%s), --evals shared out, --migrate %ld fits per island between "
		        "migrations of %ld front members round a ring; found_at counts the fits of the member's island%s\n",
		        W->F->so->islands, W->islands_name, W->migrate, W->migrants,
		        W->merge_fronts ? "; --merge-fronts: the candidates of island 0, and of the others their "
		                             "screening fronts" : "");
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

/* The cloud (grey), the front (joined, blue), the catalog published (red
 * triangles) and refitted (orange squares): error (log) against cost. */
void bk_swrite_svg(FILE *f, const bk_swrite *sw)
{
	const int W = 720, H = 460, L = 70, R = 20, T = 40, B = 50;
	double cmax = 1, emin = HUGE_VAL, emax = 0;
	for (int i = 0; i < sw->F->nm; i++)
		if (sw->F->m[i].status == 0 && (sw->F->m[i].front || !sw->F->m[i].c)) {
			cmax = fmax(cmax, sw->F->m[i].cost);
			emin = fmin(emin, sw->F->m[i].err);
			emax = fmax(emax, sw->F->m[i].err);
		}
	if (!(emin < HUGE_VAL)) {
		emin = 1e-3;
		emax = 1;
	}
	cmax = ceil(cmax * 1.1);
	double l0 = floor(log10(fmax(emin, 1e-12))), l1 = ceil(log10(fmax(emax, 1e-12)) + 0.3);
	if (l1 <= l0)
		l1 = l0 + 1;
#define X(c) (L + (c) / cmax * (W - L - R))
#define Y(e) (T + (l1 - log10(e)) / (l1 - l0) * (H - T - B))
	fprintf(f, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" font-family=\"sans-serif\" "
	        "font-size=\"11\">\n<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n", W, H);
	fprintf(f, "<text x=\"%d\" y=\"20\" font-size=\"13\">search on %s: %s (%s precision) against cost</text>\n", L,
	        bk_target_name(sw->F->kind), bk_sfront_objective_name(sw->F->so), bk_precision_name(sw->F->so->precision));
	for (double d = l0; d <= l1; d++)
		fprintf(f, "<line x1=\"%d\" x2=\"%d\" y1=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/><text x=\"%d\" y=\"%.1f\" "
		        "text-anchor=\"end\">1e%g</text>\n", L, W - R, Y(pow(10, d)), Y(pow(10, d)), L - 4, Y(pow(10, d)) + 4, d);
	double step = cmax <= 20 ? 2 : cmax <= 60 ? 5 : 10;
	for (double c = 0; c <= cmax; c += step)
		fprintf(f, "<text x=\"%.1f\" y=\"%d\" text-anchor=\"middle\">%g</text>\n", X(c), H - B + 16, c);
	fprintf(f, "<text x=\"%d\" y=\"%d\" text-anchor=\"middle\">cost (simple*%g + complex*%g)</text>\n",
	        (L + W - R) / 2, H - 12, sw->F->so->simple_cost, sw->F->so->complex_cost);
	fprintf(f, "<rect x=\"%d\" y=\"%d\" width=\"%d\" height=\"%d\" fill=\"none\" stroke=\"black\"/>\n", L, T,
	        W - L - R, H - T - B);
	/* the cloud, one dot per pixel it covers (tens of thousands of candidates
	 * fall on a few thousand pixels: the file stays small) */
	unsigned char *seen = calloc((size_t)W * H, 1);
	for (size_t i = 0; seen && i < bk_search_count(sw->F->S); i++) {
		const bk_cand *c = bk_search_at(sw->F->S, i);
		if (c->status != BK_CAND_OK || c->cost > cmax || !(c->err >= pow(10, l0) && c->err <= pow(10, l1)))
			continue;
		int px = (int)lround(X(c->cost)), py = (int)lround(Y(c->err));
		if (px < 0 || px >= W || py < 0 || py >= H || seen[(size_t)py * W + px]++)
			continue;
		fprintf(f, "<circle cx=\"%d\" cy=\"%d\" r=\"1.5\" fill=\"#bbb\"/>\n", px, py);
	}
	free(seen);
	fputs("<polyline fill=\"none\" stroke=\"#1f5fbf\" stroke-width=\"1.5\" points=\"", f);
	for (int i = 0; i < sw->F->nm; i++)
		if (sw->F->m[i].front)
			fprintf(f, "%.1f,%.1f ", X(sw->F->m[i].cost), Y(sw->F->m[i].err));
	fputs("\"/>\n", f);
	for (int i = 0; i < sw->F->nm; i++) {
		const bk_sfront_member *m = &sw->F->m[i];
		if (m->status || !(m->front || !m->c) || !(m->err > 0))
			continue;
		double x = X(m->cost), y = Y(m->err);
		if (m->front)
			fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"3.5\" fill=\"#1f5fbf\"><title>", x, y);
		else if (!m->refit)
			fprintf(f, "<path d=\"M%.1f %.1f l4 7 h-8 z\" fill=\"#c0392b\"><title>", x, y - 4);
		else
			fprintf(f, "<rect x=\"%.1f\" y=\"%.1f\" width=\"7\" height=\"7\" fill=\"#e67e22\"><title>", x - 3.5, y - 3.5);
		bk_html_text(f, m->name);
		fputs(": ", f);
		bk_html_text(f, m->text);
		fprintf(f, "</title></%s>\n", m->front ? "circle" : !m->refit ? "path" : "rect");
	}
	fprintf(f, "<g transform=\"translate(%d,%d)\"><circle cx=\"0\" cy=\"0\" r=\"3.5\" fill=\"#1f5fbf\"/><text x=\"8\" "
	        "y=\"4\">search front (refitted)</text><path d=\"M0 10 l4 7 h-8 z\" fill=\"#c0392b\"/><text x=\"8\" y=\"18\">"
	        "published</text><rect x=\"-3.5\" y=\"24\" width=\"7\" height=\"7\" fill=\"#e67e22\"/><text x=\"8\" "
	        "y=\"32\">published, refitted</text><circle cx=\"0\" cy=\"42\" r=\"1.5\" fill=\"#bbb\"/><text x=\"8\" "
	        "y=\"46\">every candidate (screening)</text></g>\n</svg>\n", W - R - 190, T + 12);
#undef X
#undef Y
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
	fputs("</code></p>\n<img src=\"", f);
	bk_html_text(f, P);
	fputs("pareto.svg\" alt=\"error against cost\">\n<table>\n<tr><th>name</th><th>form</th><th>cost</th>"
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
			for (int k = 0; pass == 0 && k < 3; k++) { /* the member's heatmap and shaders */
				static const char *const file[3] = {"heatmap.png", "shader.glsl", "shader.hlsl"};
				if (k == 0 && !(W->to->kind != BK_TARGET_FORM || W->to->ndomain <= 2))
					continue;
				fputs("<a href=\"", f);
				bk_html_text(f, P);
				fprintf(f, "front/%s/%s\">%s</a> ", m->name, file[k], file[k]);
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
	for (int pass = 0; pass < 2; pass++)
		for (int i = 0; i < W->F->nm; i++) {
			const bk_sfront_member *m = &W->F->m[i];
			if (pass == 0 ? !m->front : m->c != NULL)
				continue;
			fprintf(f, "  %-28s cost %-4g %s %-10.4g %s%s%s\n", m->name, m->cost, bk_sfront_objective_name(W->F->so), m->err, m->text,
			       m->text_b ? " | " : "", m->text_b ? m->text_b : "");
		}
}

