/*
 * halfvs.c — the half front against the double front (halfvs.h).
 */
#include "halfvs.h"
#include "prov.h"

#include "brdf.h"
#include "out.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int by_value(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

/* The least error among m's members of cost <= c (ties: cheaper, then first); -1 none. */
static int best(const bk_halfvs_member *m, int n, double c)
{
	int k = -1;
	for (int i = 0; i < n; i++)
		if (m[i].cost <= c && (k < 0 || m[i].err < m[k].err || (m[i].err == m[k].err && m[i].cost < m[k].cost)))
			k = i;
	return k;
}

int bk_halfvs_build(bk_halfvs *v, const bk_halfvs_member *d, int nd, const bk_halfvs_member *h, int nh,
                    double max_cost)
{
	memset(v, 0, sizeof *v);
	v->d = malloc(sizeof *d * (size_t)(nd + 1));
	v->h = malloc(sizeof *h * (size_t)(nh + 1));
	double *c = malloc(sizeof *c * (size_t)(nd + nh + 1));
	v->row = calloc((size_t)(nd + nh + 1), sizeof *v->row);
	if (!v->d || !v->h || !c || !v->row) {
		free(c);
		bk_halfvs_free(v);
		return -1;
	}
	memcpy(v->d, d, sizeof *d * (size_t)nd);
	memcpy(v->h, h, sizeof *h * (size_t)nh);
	v->nd = nd;
	v->nh = nh;
	int nc = 0;
	for (int i = 0; i < nd; i++)
		if (d[i].cost <= max_cost)
			c[nc++] = d[i].cost;
	for (int i = 0; i < nh; i++)
		if (h[i].cost <= max_cost)
			c[nc++] = h[i].cost;
	qsort(c, (size_t)nc, sizeof *c, by_value);
	v->worst = NAN;
	for (int i = 0; i < nc; i++) {
		if (i && c[i] == c[i - 1])
			continue;
		bk_halfvs_row *r = &v->row[v->nrow++];
		r->cost = c[i];
		r->d = best(v->d, nd, c[i]);
		r->h = best(v->h, nh, c[i]);
		if (r->d < 0)
			r->ratio = NAN; /* nothing to match */
		else if (r->h < 0)
			r->ratio = HUGE_VAL;
		else if (v->d[r->d].err == 0)
			r->ratio = v->h[r->h].err == 0 ? 1 : HUGE_VAL;
		else
			r->ratio = v->h[r->h].err / v->d[r->d].err;
		r->pass = isnan(r->ratio) || r->ratio <= BK_HALFVS_TARGET;
		v->npass += r->pass;
		if (!isnan(r->ratio) && !(r->ratio <= v->worst))
			v->worst = r->ratio;
	}
	free(c);
	return 0;
}

void bk_halfvs_free(bk_halfvs *v)
{
	free(v->d);
	free(v->h);
	free(v->row);
	memset(v, 0, sizeof *v);
}

/* x in fmt; inf as "inf", NaN as nothing. */
static void num(FILE *f, const char *fmt, double x)
{
	if (isinf(x))
		fputs("inf", f);
	else if (!isnan(x))
		fprintf(f, fmt, x);
}

void bk_halfvs_csv(FILE *f, const bk_halfvs *v, const char *command, const char *dpath, const char *objective)
{
	bk_prov_header(f, command, NULL, "search vs_double: the half-precision front against the double front of the same "
	               "target");
	fputs("# double front: ", f);
	for (const char *p = dpath; *p; p++) /* a comment line stays one line */
		fputc(*p == '\n' || *p == '\r' ? '?' : *p, f);
	fprintf(f, " (its error column: %s in double precision); half front: this search's front.csv (%s evaluated "
	        "in half, f16 as the emitted code computes it)\n", objective, objective);
	fprintf(f, "# cost: every cost <= %g at which either front has a member; double_error, half_error: the least "
	        "error among that front's members of cost <= cost (ties: the cheaper, then the first; empty name: "
	        "none); ratio = half_error / double_error (inf: no half member of cost <= cost; empty: no double "
	        "member, nothing to match; 1 where both are 0); pass = 1 when ratio <= %g (issue 23's target) or "
	        "empty, else 0\n# %d of %d costs pass\n", BK_HALFVS_MAX_COST, BK_HALFVS_TARGET, v->npass, v->nrow);
	fputs("cost,double_name,double_error,half_name,half_error,ratio,pass\n", f);
	for (int i = 0; i < v->nrow; i++) {
		const bk_halfvs_row *r = &v->row[i];
		fprintf(f, "%g,", r->cost);
		bk_csv_field(f, r->d >= 0 ? v->d[r->d].name : "");
		fputc(',', f);
		if (r->d >= 0)
			num(f, "%.6g", v->d[r->d].err);
		fputc(',', f);
		bk_csv_field(f, r->h >= 0 ? v->h[r->h].name : "");
		fputc(',', f);
		if (r->h >= 0)
			num(f, "%.6g", v->h[r->h].err);
		fputc(',', f);
		num(f, "%.6g", r->ratio);
		fprintf(f, ",%d\n", r->pass);
	}
}

void bk_halfvs_html(FILE *f, const bk_halfvs *v, const char *dpath, const char *objective, const char *prefix)
{
	fprintf(f, "<h3>Half front against the double front</h3>\n<p>At %d of %d costs &le; %g the half front's %s "
	        "(evaluated in half, as a mediump GPU computes it) is within %g&times; the double front's (in double, "
	        "from <code>", v->npass, v->nrow, BK_HALFVS_MAX_COST, objective, BK_HALFVS_TARGET);
	bk_html_text(f, dpath);
	fputs("</code>)", f);
	if (!isnan(v->worst))
		fprintf(f, "; the worst ratio is %.3g", v->worst);
	fputs(". Each row: the best member of each front at that cost or below; every member of the half front is "
	      "safe in half (as is or with its guards). <a href=\"", f);
	bk_html_link(f, prefix, "vs_double.csv");
	fputs("\">vs_double.csv</a></p>\n<table>\n<tr><th>cost &le;</th><th>double front</th><th>error (double)</th><th>half front</th>"
	      "<th>error (half)</th><th>ratio</th><th>&le; 1.25</th></tr>\n", f);
	for (int i = 0; i < v->nrow; i++) {
		const bk_halfvs_row *r = &v->row[i];
		fprintf(f, "<tr><td>%g</td><td>", r->cost);
		if (r->d >= 0)
			bk_html_text(f, v->d[r->d].name);
		fputs("</td><td>", f);
		if (r->d >= 0)
			fprintf(f, "%.3g", v->d[r->d].err);
		fputs("</td><td>", f);
		if (r->h >= 0)
			bk_html_text(f, v->h[r->h].name);
		fputs("</td><td>", f);
		if (r->h >= 0)
			fprintf(f, "%.3g", v->h[r->h].err);
		fputs("</td><td>", f);
		num(f, "%.3g", r->ratio);
		fprintf(f, "</td><td>%s</td></tr>\n", r->pass ? "yes" : "<b>no</b>");
	}
	fputs("</table>\n", f);
}
