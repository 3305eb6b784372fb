/*
 * summary.c — the page's first screen from the CSVs (summary.h): a small
 * libcsv table reader (columns by name, each record's first line kept), the
 * rules, and the table's HTML.
 */
#include "summary.h"

#include "out.h"

#include <csv.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define FIELDS_MAX 256 /* compare.csv has about 50 columns; more is no file brdfkit wrote */
#define ROWS_MAX 4096  /* as frontcsv.h: more is no front or catalog brdfkit writes */
#define COLS_MAX 4

/* ---- a CSV read by column name ---------------------------------------------------- */

typedef struct table {
	const char *path;
	const char *const *want; /* column names, NULL-terminated; -1 col when absent */
	int col[COLS_MAX];
	char objective[BK_SUMMARY_NAME], cost_model[BK_SUMMARY_NAME];
	int line, rec_line, records, bad, nfield;
	int open;                   /* a record begun and not yet ended: its first line is rec_line */
	char *field[FIELDS_MAX];
	int n;                      /* data rows */
	int row_line[ROWS_MAX];
	char *cell[ROWS_MAX][COLS_MAX];
	char *err;
	size_t errlen;
} table;

static void fail(table *t, int line, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static void fail(table *t, int line, const char *fmt, ...)
{
	if (t->bad)
		return;
	t->bad = 1;
	int k = line > 0 ? snprintf(t->err, t->errlen, "%.300s:%d: ", t->path, line)
	                 : snprintf(t->err, t->errlen, "%.300s: ", t->path);
	if (k < 0 || (size_t)k >= t->errlen)
		return;
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(t->err + k, t->errlen - (size_t)k, fmt, ap);
	va_end(ap);
}

static void on_field(void *s, size_t len, void *data)
{
	table *t = data;
	if (t->nfield < FIELDS_MAX && !t->bad) {
		if (!(t->field[t->nfield] = malloc(len + 1)))
			fail(t, 0, "out of memory");
		else {
			memcpy(t->field[t->nfield], s ? s : "", len);
			t->field[t->nfield][len] = '\0';
		}
	}
	t->nfield++;
}

static void on_record(int c, void *data)
{
	(void)c;
	table *t = data;
	int n = t->nfield < FIELDS_MAX ? t->nfield : FIELDS_MAX, line = t->rec_line ? t->rec_line : t->line;
	if (t->bad) {
	} else if (t->records++ == 0) { /* the header: the columns by name */
		for (int k = 0; t->want[k] && !t->bad; k++) {
			t->col[k] = -1;
			for (int j = 0; j < n && t->col[k] < 0; j++)
				if (t->field[j] && !strcmp(t->field[j], t->want[k]))
					t->col[k] = j;
			if (t->col[k] < 0)
				fail(t, line, "no column '%s'", t->want[k]);
		}
	} else if (t->n >= ROWS_MAX)
		fail(t, line, "more than %d rows (no file brdfkit writes)", ROWS_MAX);
	else {
		for (int k = 0; t->want[k] && !t->bad; k++)
			if (t->col[k] >= n)
				fail(t, line, "%d fields, fewer than the header's", t->nfield);
		for (int k = 0; t->want[k] && !t->bad; k++) {
			t->cell[t->n][k] = t->field[t->col[k]];
			t->field[t->col[k]] = NULL;
		}
		if (!t->bad)
			t->row_line[t->n++] = line;
	}
	for (int j = 0; j < n; j++)
		free(t->field[j]);
	memset(t->field, 0, sizeof t->field);
	t->nfield = 0;
	t->rec_line = 0;
	t->open = 0;
}

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

static void objective_line(table *t, const char *line)
{
	static const char cost[] = "# cost: ";
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
	for (int i = 0; i < t->n; i++)
		for (int k = 0; k < COLS_MAX; k++)
			free(t->cell[i][k]);
	for (int j = 0; j < FIELDS_MAX; j++)
		free(t->field[j]);
	free(t);
}

/* path read whole; NULL with err set (and nothing to free) on failure. */
static table *table_read(const char *path, const char *const *want, char *err, size_t errlen)
{
	table *t = calloc(1, sizeof *t);
	if (!t) {
		snprintf(err, errlen, "%.300s: out of memory", path);
		return NULL;
	}
	*t = (table){.path = path, .want = want, .err = err, .errlen = errlen};
	FILE *f = fopen(path, "rb");
	if (!f) {
		fail(t, 0, "cannot be read (%s)", strerror(errno));
		table_free(t);
		return NULL;
	}
	struct csv_parser p;
	if (csv_init(&p, CSV_APPEND_NULL)) {
		fclose(f);
		fail(t, 0, "out of memory");
		table_free(t);
		return NULL;
	}
	char *line = NULL;
	size_t cap = 0;
	ssize_t len;
	int head = 1;
	while (!t->bad && (len = getline(&line, &cap, f)) >= 0) {
		t->line++;
		if (memchr(line, '\0', (size_t)len)) {
			fail(t, t->line, "a NUL byte (not a text file)");
			break;
		}
		if (head && line[0] == '#') { /* the provenance and conventions lines */
			objective_line(t, line);
			continue;
		}
		head = 0;
		if (!t->open && strspn(line, "\r\n") != (size_t)len) { /* libcsv skips blank lines between records */
			t->open = 1;
			t->rec_line = t->line;
		}
		if (csv_parse(&p, line, (size_t)len, on_field, on_record, t) != (size_t)len)
			fail(t, t->line, "%s", csv_strerror(csv_error(&p)));
	}
	if (!t->bad && ferror(f))
		fail(t, 0, "read failed");
	if (!t->bad && csv_fini(&p, on_field, on_record, t))
		fail(t, t->line, "%s", csv_strerror(csv_error(&p)));
	if (!t->bad && t->records == 0)
		fail(t, 0, "empty (no header)");
	free(line);
	csv_free(&p);
	fclose(f);
	if (t->bad) {
		table_free(t);
		return NULL;
	}
	return t;
}

/* Cell (i, k) as a finite number >= 0; -1 after fail. */
static int number(table *t, int i, int k, double *v)
{
	const char *s = t->cell[i][k];
	char *end;
	errno = 0;
	*v = strtod(s, &end);
	if (*s && !*end && errno != ERANGE && isfinite(*v) && *v >= 0)
		return 0;
	fail(t, t->row_line[i], "%s: expected a finite number >= 0, got '%.40s'", t->want[k], s);
	return -1;
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
 * of them: all = 1). pts holds t->n. Returns the count, or -1 after fail. */
static int points(table *t, int kind, int all, bk_summary_pt *pts)
{
	int n = 0;
	for (int i = 0; i < t->n; i++) {
		const char *name = t->cell[i][0];
		if (kind >= 0 ? strcmp(t->cell[i][kind], "published") != 0 : !all && brdfkit_own(name))
			continue;
		bk_summary_pt *x = &pts[n];
		x->line = t->row_line[i];
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
	bk_summary_pt *pp = calloc((size_t)pt->n + 1, sizeof *pp), *fp = calloc(ft ? (size_t)ft->n + 1 : 1, sizeof *fp);
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
	else {
		bk_summary_compute(pp, npub, fp, nfront, row);
		snprintf(row->objective, sizeof row->objective, "%s",
		         search ? pt->objective : "max_abs in f64 precision (brdfkit compare)");
		snprintf(row->cost_model, sizeof row->cost_model, "%s", pt->cost_model);
		rc = 0;
	}
	free(pp);
	free(fp);
	table_free(pt);
	if (ft)
		table_free(ft);
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
	bk_html_text(f, href);
	bk_html_text(f, file);
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
	bk_html_text(f, href);
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
		fputs("<td colspan=\"5\">no search on this target</td></tr>\n", f);
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
	fprintf(f, "</td><td>%d of %d</td></tr>\n", r->nbeaten, r->npub);
}

void bk_summary_table(FILE *f, const bk_summary_row *rows, int n, const char *const *href)
{
	fputs("<table id=\"summary\" class=\"summary\">\n<tr><th rowspan=\"2\">target</th><th rowspan=\"2\">error, "
	      "precision</th><th colspan=\"3\">best published form</th><th colspan=\"4\">best searched form at "
	      "equal or lower cost</th><th rowspan=\"2\">cheapest searched form as accurate (cost)</th><th "
	      "rowspan=\"2\">published forms beaten at their cost</th></tr>\n<tr><th>form</th><th>cost</th><th>error"
	      "</th><th>form</th><th>cost</th><th>error</th><th>error ratio</th></tr>\n",
	      f);
	for (int i = 0; i < n; i++)
		row_html(f, &rows[i], href[i]);
	fputs("</table>\n", f);
}
