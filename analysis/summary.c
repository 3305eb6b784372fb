/*
 * summary.c — the page's first screen from the CSVs (summary.h): the files
 * read by column name (csvtab.h, each row's first line kept), the rules, and
 * the table's HTML.
 */
#include "summary.h"

#include "brdf_math.h"
#include "csvtab.h"
#include "frontcsv.h"
#include "out.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* ---- a CSV read by column name (frontcsv.h's reader), with what its '#' lines state ---- */

typedef struct table {
	bk_csvtab t;
	const char *const *want; /* the columns, NULL-terminated */
	char objective[BK_SUMMARY_NAME], cost_model[BK_SUMMARY_NAME];
	int complete; /* "# certificate: every unique form ... up to N nodes": N; 0 "none"; -1 no such line */
	bk_frontcsv_head head; /* which file, target, objective, precision (frontcsv.h) */
	char *err;
	size_t errlen;
} table;

/* The objective a search's file states: "error: X in P precision" on its
 * '#' lines, the words kept as written (letters, digits, '_' and spaces). */
static int plain_words(const char *s, size_t n, const char *extra)
{
	for (size_t i = 0; i < n; i++)
		if (!(s[i] == '_' || s[i] == ' ' || (s[i] >= 'a' && s[i] <= 'z') || (s[i] >= '0' && s[i] <= '9') ||
		      (s[i] && strchr(extra, s[i]))))
			return 0;
	return 1;
}

/* the '#' lines frontcsv.h's head does not keep */
static void objective_line(void *ctx, const char *line)
{
	table *t = ctx;
	static const char cost[] = "# cost: ", cert[] = "# certificate: ", upto[] = "every unique form of the grammar up to ";
	if (!strncmp(line, cert, sizeof cert - 1) && t->complete < 0) {
		const char *c = line + sizeof cert - 1;
		int nodes, used = 0;
		t->complete = 0; /* "none: ..." or anything not read as a size */
		if (!strncmp(c, upto, sizeof upto - 1) && sscanf(c + sizeof upto - 1, "%d nodes%n", &nodes, &used) == 1 &&
		    used > 0 && nodes > 0 && nodes <= 64)
			t->complete = nodes;
	}
	const char *after = strstr(line, " after ");
	if (!strncmp(line, cost, sizeof cost - 1) && after && !t->cost_model[0] &&
	    (size_t)(after - line) - (sizeof cost - 1) < sizeof t->cost_model &&
	    plain_words(line + sizeof cost - 1, (size_t)(after - line) - (sizeof cost - 1), "*+."))
		snprintf(t->cost_model, sizeof t->cost_model, "%.*s", (int)((size_t)(after - line) - (sizeof cost - 1)),
		         line + sizeof cost - 1);
	const char *e = strstr(line, "; error: ");
	if (!e || t->objective[0])
		return;
	e += 9;
	const char *end = strstr(e, " precision");
	size_t n = end ? (size_t)(end - e) + 10 : 0;
	if (!end || n >= sizeof t->objective)
		return;
	if (!plain_words(e, n, ""))
		return;
	memcpy(t->objective, e, n);
	t->objective[n] = '\0';
}

static void table_free(table *t)
{
	bk_csvtab_free(&t->t);
	free(t);
}

/* path read whole (at most BK_FRONTCSV_MAX_ROWS rows); NULL with err set
 * (and nothing to free) on failure. */
static table *table_read(const char *path, const char *const *want, char *err, size_t errlen)
{
	table *t = calloc(1, sizeof *t);
	if (!t) {
		bk_csvtab_err(err, errlen, path, 0, "out of memory");
		return NULL;
	}
	*t = (table){.want = want, .complete = -1, .err = err, .errlen = errlen};
	if (bk_frontcsv_table(path, want, 0, NULL, objective_line, t, &t->head, &t->t, err, errlen)) {
		free(t);
		return NULL;
	}
	return t;
}

/* Cell (i, k) as a finite number >= 0; -1 with err set. */
static int number(table *t, int i, int k, double *v)
{
	return bk_frontcsv_score(&t->t, i, k, t->want[k], v, t->err, t->errlen);
}

/* ---- the rules ------------------------------------------------------------------------ */

static void pick(bk_summary_pick *p, const bk_summary_pt *x)
{
	p->line = x->line;
	snprintf(p->name, sizeof p->name, "%s", x->name ? x->name : "");
	p->cost = x->cost;
	p->error = x->error;
}

int bk_summary_compute(const bk_summary_pt *pub, int npub, const bk_summary_pt *front, int nfront,
                       bk_summary_row *row)
{
	memset(&row->pub, 0, sizeof row->pub);
	memset(&row->at_cost, 0, sizeof row->at_cost);
	memset(&row->match, 0, sizeof row->match);
	row->npub = npub;
	row->nbeaten = 0;
	row->has_search = nfront > 0;
	if (npub <= 0)
		return -1;
	int b = 0; /* least error, then lower cost; strict '<' keeps the earlier line */
	for (int i = 1; i < npub; i++)
		if (pub[i].error < pub[b].error || (pub[i].error == pub[b].error && pub[i].cost < pub[b].cost))
			b = i;
	pick(&row->pub, &pub[b]);
	int at = -1, m = -1;
	for (int i = 0; i < nfront; i++) {
		const bk_summary_pt *x = &front[i];
		if (x->cost <= pub[b].cost &&
		    (at < 0 || x->error < front[at].error || (x->error == front[at].error && x->cost < front[at].cost)))
			at = i;
		if (x->error <= pub[b].error &&
		    (m < 0 || x->cost < front[m].cost || (x->cost == front[m].cost && x->error < front[m].error)))
			m = i;
	}
	if (at >= 0)
		pick(&row->at_cost, &front[at]);
	if (m >= 0)
		pick(&row->match, &front[m]);
	for (int p = 0; p < npub; p++) {
		int beaten = 0;
		for (int i = 0; i < nfront && !beaten; i++)
			beaten = front[i].cost <= pub[p].cost && front[i].error < pub[p].error;
		row->nbeaten += beaten;
	}
	return 0;
}

double bk_summary_ratio(const bk_summary_row *row)
{
	if (!row->at_cost.line)
		return NAN;
	return row->at_cost.error > 0 ? row->pub.error / row->at_cost.error : INFINITY;
}

/* ---- reading a target ------------------------------------------------------------------ */

static int ends_with(const char *s, const char *tail)
{
	size_t n = strlen(s), k = strlen(tail);
	return n >= k && !strcmp(s + n - k, tail);
}

/* A catalog row that brdfkit made rather than someone published (summary.h). */
static int brdfkit_own(const char *name)
{
	return ends_with(name, " (refit)") || !strncmp(name, "start ", 6) || !strncmp(name, "LUT ", 4);
}

/* The points of t: name column 0, cost 1, error 2; when kind >= 0, only rows
 * whose column kind is "published", else the rows not brdfkit's own (or all
 * of them: all = 1). pts holds t->t.n. Returns the count, or -1 with err set. */
static int points(table *t, int kind, int all, bk_summary_pt *pts)
{
	int n = 0;
	for (int i = 0; i < t->t.n; i++) {
		const char *name = bk_csvtab_get(&t->t, i, 0);
		if (kind >= 0 ? strcmp(bk_csvtab_get(&t->t, i, kind), "published") != 0 : !all && brdfkit_own(name))
			continue;
		bk_summary_pt *x = &pts[n];
		x->line = t->t.line[i];
		x->name = name;
		if (number(t, i, 1, &x->cost) || number(t, i, 2, &x->error))
			return -1;
		n++;
	}
	return n;
}

static void path_join(char *buf, size_t len, const char *dir, const char *file)
{
	size_t n = strlen(dir);
	snprintf(buf, len, "%s%s%s", dir, n && dir[n - 1] == '/' ? "" : "/", file);
}

static int is_file(const char *path)
{
	struct stat st;
	return !stat(path, &st) && S_ISREG(st.st_mode);
}

static void target_name(char *buf, size_t len, const char *dir)
{
	size_t n = strlen(dir);
	while (n > 1 && dir[n - 1] == '/')
		n--;
	size_t s = n;
	while (s > 0 && dir[s - 1] != '/')
		s--;
	snprintf(buf, len, "%.*s", (int)(n - s), dir + s);
}

static const char *const search_cols[] = {"name", "cost", "error", NULL};
static const char *const compare_cols[] = {"name", "cost", "max_abs", "kind", NULL};

int bk_summary_read(const char *dir, bk_summary_row *row, char *err, size_t errlen)
{
	memset(row, 0, sizeof *row);
	target_name(row->target, sizeof row->target, dir);
	char front_path[BK_SUMMARY_PATH];
	path_join(front_path, sizeof front_path, dir, "front.csv");
	int search = is_file(front_path);
	path_join(row->pub_file, sizeof row->pub_file, dir, search ? "catalog.csv" : "compare.csv");
	if (!search && !is_file(row->pub_file)) {
		snprintf(err, errlen, "%.300s: neither front.csv (brdfkit search) nor compare.csv (brdfkit compare)", dir);
		return -1;
	}
	table *pt = table_read(row->pub_file, search ? search_cols : compare_cols, err, errlen), *ft = NULL;
	if (!pt)
		return -1;
	if (search) {
		snprintf(row->front_file, sizeof row->front_file, "%s", front_path);
		if (!(ft = table_read(front_path, search_cols, err, errlen))) {
			table_free(pt);
			return -1;
		}
	}
	int rc = -1, npub = -1, nfront = 0;
	bk_summary_pt *pp = calloc((size_t)pt->t.n + 1, sizeof *pp), *fp = calloc(ft ? (size_t)ft->t.n + 1 : 1, sizeof *fp);
	if (!pp || !fp)
		snprintf(err, errlen, "%.300s: out of memory", dir);
	else if ((npub = points(pt, search ? -1 : 3, 0, pp)) < 0 || (ft && (nfront = points(ft, -1, 1, fp)) < 0)) {
	} else if (npub == 0)
		snprintf(err, errlen, "%.300s: no published form (%s)", row->pub_file,
		         search ? "every row is a refit, a typed start or a LUT" : "no row of kind published");
	else if (ft && nfront == 0)
		snprintf(err, errlen, "%.300s: no member (an empty front)", front_path);
	else if (search && !pt->objective[0])
		snprintf(err, errlen, "%.300s: no '# ... error: OBJECTIVE in P precision' line (not a catalog.csv of brdfkit search)",
		         row->pub_file);
	/* the page sets the front's errors against the catalog's: both files of
	 * one search, of one target, objective and precision */
	else if (search && (bk_frontcsv_head_check(&pt->head, row->pub_file, BK_FRONTCSV_CATALOG, "", "", 1, NULL, NULL,
	                                           err, errlen) ||
	                    bk_frontcsv_head_check(&ft->head, front_path, BK_FRONTCSV_FRONT, "its catalog.csv's",
	                                           pt->head.target, 1, pt->head.objective, pt->head.precision, err,
	                                           errlen))) {
	} else {
		bk_summary_compute(pp, npub, fp, nfront, row);
		snprintf(row->objective, sizeof row->objective, "%s",
		         search ? pt->objective : "max_abs in f64 precision (brdfkit compare)");
		snprintf(row->cost_model, sizeof row->cost_model, "%s", pt->cost_model);
		row->complete = ft ? ft->complete : -1;
		/* the formula is shown, not checked: a file without form columns
		 * (a hand-made fixture) shows none */
		if (row->at_cost.line)
			bk_summary_formula(front_path, &row->at_cost, row->formula, sizeof row->formula);
		else if (!search)
			bk_summary_formula(row->pub_file, &row->pub, row->formula, sizeof row->formula);
		rc = 0;
	}
	free(pp);
	free(fp);
	table_free(pt);
	if (ft)
		table_free(ft);
	return rc;
}

/* ---- the formula ------------------------------------------------------------------------- */

/* text's MathML (its parameters p[]) appended at out + *at; -1 if it does
 * not parse or fit. */
static int put_math(const char *text, const double *p, char *out, size_t len, size_t *at)
{
	bk_form_error fe;
	bk_form *f = bk_form_parse(text, &fe);
	if (!f)
		return -1;
	char *m = bk_form_math(f, BK_MATH_MATHML, p, 4);
	bk_form_free(f);
	size_t n = m ? strlen(m) : 0;
	int ok = m && *at + n < len;
	if (ok) {
		memcpy(out + *at, m, n + 1);
		*at += n;
	}
	free(m);
	return ok ? 0 : -1;
}

int bk_summary_formula(const char *path, const bk_summary_pick *pick, char *out, size_t len)
{
	out[0] = '\0';
	bk_frontcsv fc;
	char err[256];
	if (!pick->line || len < 64 || bk_frontcsv_read(path, BK_FRONTCSV_FORMS, &fc, err, sizeof err))
		return -1;
	int rc = -1;
	for (int i = 0; i < fc.n; i++) {
		const bk_frontcsv_row *r = &fc.row[i];
		if (r->line != pick->line)
			continue;
		size_t at = 0;
		if (!r->form_b) {
			rc = put_math(r->form, r->p, out, len, &at);
		} else { /* a split sum f0 A + B: both parts, named as the conventions name them */
			at = (size_t)snprintf(out, len, "A = ");
			rc = put_math(r->form, r->p, out, len, &at);
			if (!rc && at + 8 < len) {
				at += (size_t)snprintf(out + at, len - at, ", B = ");
				rc = put_math(r->form_b, r->p, out, len, &at);
			} else {
				rc = -1;
			}
		}
		break;
	}
	if (rc)
		out[0] = '\0';
	bk_frontcsv_free(&fc);
	return rc;
}

/* ---- the table --------------------------------------------------------------------------- */

static void num(FILE *f, double v)
{
	fprintf(f, "%.3g", v);
}

static void file_of(const char *path, char *buf, size_t len)
{
	const char *s = strrchr(path, '/');
	snprintf(buf, len, "%s", s ? s + 1 : path);
}

/* <a href="HREF FILE" title="FILE, line N">NAME</a> */
static void cite(FILE *f, const char *href, const char *path, const bk_summary_pick *p)
{
	char file[64];
	file_of(path, file, sizeof file);
	fputs("<a href=\"", f);
	bk_html_link(f, href, file);
	fputs("\" title=\"", f);
	bk_html_text(f, file);
	fprintf(f, ", line %d\">", p->line);
	bk_html_text(f, p->name);
	fputs("</a>", f);
}

/* "max_abs in f64 precision" as "max_abs, f64": the table's rows stay one
 * line; the header's note spells the form out. Anything else as it is. */
static void objective(FILE *f, const char *o)
{
	const char *in = strstr(o, " in "), *prec = in ? strstr(in + 4, " precision") : NULL;
	if (!in || !prec) {
		bk_html_text(f, o);
		return;
	}
	char buf[BK_SUMMARY_NAME];
	snprintf(buf, sizeof buf, "%.*s, %.*s%s", (int)(in - o), o, (int)(prec - in - 4), in + 4, prec + 10);
	bk_html_text(f, buf);
}

static void row_html(FILE *f, const bk_summary_row *r, const char *href)
{
	fputs("<tr><th><a href=\"", f);
	bk_html_link(f, href, NULL);
	fputs("\">", f);
	bk_html_text(f, r->target);
	fputs("</a></th><td>", f);
	objective(f, r->objective);
	fputs("</td><td>", f);
	cite(f, href, r->pub_file, &r->pub);
	fputs("</td><td>", f);
	num(f, r->pub.cost);
	fputs("</td><td>", f);
	num(f, r->pub.error);
	fputs("</td>", f);
	if (!r->has_search) {
		fputs("<td colspan=\"6\">no search on this target</td></tr>\n", f);
		return;
	}
	if (r->at_cost.line) {
		double q = bk_summary_ratio(r);
		fputs("<td>", f);
		cite(f, href, r->front_file, &r->at_cost);
		fputs("</td><td>", f);
		num(f, r->at_cost.cost);
		fputs("</td><td>", f);
		num(f, r->at_cost.error);
		fputs(isinf(q) ? "</td><td>exact" : "</td><td>", f);
		if (!isinf(q))
			fprintf(f, "%.3g", q);
		fputs("</td>", f);
	} else
		fputs("<td colspan=\"4\">no member at that cost</td>", f);
	fputs("<td>", f);
	if (r->match.line) {
		cite(f, href, r->front_file, &r->match);
		fputs(" (", f);
		num(f, r->match.cost);
		fputs(")", f);
	} else
		fputs("none", f);
	fprintf(f, "</td><td>%d of %d</td><td>", r->nbeaten, r->npub);
	if (r->complete > 0)
		fprintf(f, "%d nodes", r->complete);
	else
		fputs(r->complete == 0 ? "none" : "not stated", f);
	fputs("</td></tr>\n", f);
}

void bk_summary_table(FILE *f, const bk_summary_row *rows, int n, const char *const *href)
{
	fputs("<table id=\"summary\" class=\"summary\">\n<tr><th rowspan=\"2\">target</th><th rowspan=\"2\">error, "
	      "precision</th><th colspan=\"3\">best published form</th><th colspan=\"4\">best searched form at "
	      "equal or lower cost</th><th rowspan=\"2\">cheapest searched form as accurate (cost)</th><th "
	      "rowspan=\"2\">published forms beaten at their cost</th><th rowspan=\"2\" title=\"every unique form of the "
	      "search's grammar up to this many nodes was fitted (front.csv's certificate)\">complete to</th></tr>\n<tr><th>form</th><th>cost</th><th>error"
	      "</th><th>form</th><th>cost</th><th>error</th><th>error ratio</th></tr>\n",
	      f);
	for (int i = 0; i < n; i++)
		row_html(f, &rows[i], href[i]);
	fputs("</table>\n", f);
}

/* ---- the findings ---------------------------------------------------------------------- */

/* The error name of an objective ("max_abs in f64 precision": "max_abs"). */
static void error_word(char *buf, size_t len, const char *objective)
{
	const char *in = strstr(objective, " in ");
	snprintf(buf, len, "%.*s", in ? (int)(in - objective) : (int)strlen(objective), objective);
}

/* The sentence into out (len bytes, room for every part: BK_SUMMARY_NAME
 * names and a few numbers), as bk_summary_finding describes it. */
static size_t finding_text(const bk_summary_row *r, char *out, size_t len)
{
	char err[BK_SUMMARY_NAME];
	error_word(err, sizeof err, r->objective);
	const bk_summary_pick *p = &r->pub, *a = &r->at_cost;
	if (!r->has_search)
		return (size_t)snprintf(out, len, "No search on %s; the best published form is %s (cost %.3g, %s %.3g).",
		                        r->target, p->name, p->cost, err, p->error);
	size_t n;
	int better = a->line && a->error < p->error;
	if (!a->line)
		n = (size_t)snprintf(out, len, "No searched form costs %.3g or less, the cost of %s (%s %.3g)", p->cost,
		                     p->name, err, p->error);
	else if (better && a->error == 0)
		n = (size_t)snprintf(out, len, "At %s's cost %.3g, %s (cost %.3g) is exact where %s has %s %.3g",
		                     p->name, p->cost, a->name, a->cost, p->name, err, p->error);
	else if (better)
		n = (size_t)snprintf(out, len, "At %s's cost %.3g, %s (cost %.3g) has %s %.3g, %.3gx less than %s's %.3g",
		                     p->name, p->cost, a->name, a->cost, err, a->error, p->error / a->error, p->name,
		                     p->error);
	else if (a->error == p->error)
		n = (size_t)snprintf(out, len, "No searched form at cost %.3g or less beats %s (%s %.3g): the best there, "
		                     "%s, equals it", p->cost, p->name, err, p->error, a->name);
	else
		n = (size_t)snprintf(out, len, "No searched form at cost %.3g or less beats %s (%s %.3g): the best there, "
		                     "%s, has %.3g", p->cost, p->name, err, p->error, a->name, a->error);
	if (n >= len)
		return n;
	if (!better && r->match.line && r->match.line != a->line)
		n += (size_t)snprintf(out + n, len - n, "; as accurate takes cost %.3g (%s)", r->match.cost, r->match.name);
	if (n >= len)
		return n;
	n += (size_t)snprintf(out + n, len - n, "%s %d of %d published form%s %s beaten at %s own cost.",
	                      better || !r->nbeaten ? ";" : ", yet", r->nbeaten, r->npub, r->npub == 1 ? "" : "s",
	                      r->nbeaten == 1 ? "is" : "are", r->nbeaten == 1 ? "its" : "their");
	return n;
}

size_t bk_summary_finding(const bk_summary_row *r, char *out, size_t len)
{
	char whole[8 * BK_SUMMARY_NAME + 512];
	finding_text(r, whole, sizeof whole);
	return (size_t)snprintf(out, len, "%s", whole);
}
