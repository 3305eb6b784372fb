/*
 * frontcsv.c — a front.csv of brdfkit search read back by column name
 * (frontcsv.h).
 */
#include "frontcsv.h"

#include <csv.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define FIELDS_MAX 256 /* front.csv has 20-odd columns; more is no front */

enum { C_NAME, C_FORM, C_FORM_B, C_PARAMS, C_COST, C_ERROR, C_N };
static const char *const col_name[C_N] = {"name", "form", "form_b", "parameters", "cost", "error"};

typedef struct reader {
	const char *path;
	unsigned need;
	int line;      /* the line being fed */
	int rec_line;  /* where the record being read started (0: none yet) */
	char *field[FIELDS_MAX];
	int nfield, records, bad;
	int col[C_N];
	bk_frontcsv *fc;
	char *err;
	size_t errlen;
} reader;

static void fail(reader *r, int line, const char *fmt, ...)
{
	if (r->bad)
		return;
	r->bad = 1;
	int k = line > 0 ? snprintf(r->err, r->errlen, "%.300s:%d: ", r->path, line)
	                 : snprintf(r->err, r->errlen, "%.300s: ", r->path);
	if (k < 0 || (size_t)k >= r->errlen)
		return;
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(r->err + k, r->errlen - (size_t)k, fmt, ap);
	va_end(ap);
}

static void on_field(void *s, size_t len, void *data)
{
	reader *r = data;
	if (!r->rec_line)
		r->rec_line = r->line;
	if (r->nfield < FIELDS_MAX && !r->bad) {
		if (!(r->field[r->nfield] = malloc(len + 1)))
			fail(r, 0, "out of memory");
		else {
			memcpy(r->field[r->nfield], s ? s : "", len);
			r->field[r->nfield][len] = '\0';
		}
	}
	r->nfield++;
}

/* A whole field as a finite number; -1 when it is not one. */
static int number(const char *t, double *v)
{
	char *end;
	errno = 0;
	*v = strtod(t, &end);
	return *t && !*end && errno != ERANGE && isfinite(*v) ? 0 : -1;
}

/* "p0=0.1;p1=2" into row->p; a message, or NULL. */
static const char *params(const char *text, bk_frontcsv_row *w, int *given)
{
	for (const char *t = text; *t;) {
		char *end;
		long i;
		if (*t != 'p' || t[1] < '0' || t[1] > '9' || (i = strtol(t + 1, &end, 10)) < 0 || i >= BK_MAX_PARAMS ||
		    *end != '=')
			return "parameters: expected p0=X;p1=Y;... (p0 to p15)";
		if (given[i])
			return "parameters: one given twice";
		const char *v = end + 1;
		double x = strtod(v, &end);
		if (end == v || !isfinite(x) || (*end && *end != ';'))
			return "parameters: a value is not a finite number";
		w->p[i] = x;
		given[i] = 1;
		t = *end ? end + 1 : end;
	}
	return NULL;
}

/* One form text through the parser: its parameter count, or -1 after fail. */
static int parse(reader *r, int line, const char *what, const char *text)
{
	bk_form_error fe;
	bk_form *f = bk_form_parse(text, &fe);
	if (!f) {
		fail(r, line, "%s: column %d: %s", what, fe.column, fe.message);
		return -1;
	}
	int np = bk_form_nparams(f);
	bk_form_free(f);
	return np;
}

static void data_row(reader *r, int line)
{
	bk_frontcsv *fc = r->fc;
	int n = r->nfield < FIELDS_MAX ? r->nfield : FIELDS_MAX;
	for (int k = 0; k < C_N; k++)
		if (r->col[k] >= n) {
			fail(r, line, "%d fields, fewer than the header's", r->nfield);
			return;
		}
	if (fc->n >= BK_FRONTCSV_MAX_ROWS) {
		fail(r, line, "more than %d rows (not a front of brdfkit search)", BK_FRONTCSV_MAX_ROWS);
		return;
	}
	bk_frontcsv_row *w = &fc->row[fc->n];
	memset(w, 0, sizeof *w);
	w->line = line;
	w->cost = w->error = NAN;
	fc->n++; /* freed with the file whatever follows */
	if (r->col[C_NAME] >= 0 && r->field[r->col[C_NAME]][0]) {
		w->name = r->field[r->col[C_NAME]];
		r->field[r->col[C_NAME]] = NULL;
	} else if ((w->name = malloc(32)))
		snprintf(w->name, 32, "row %d", line);
	if (!w->name) {
		fail(r, 0, "out of memory");
		return;
	}
	if (r->need & BK_FRONTCSV_FORMS) {
		w->form = r->field[r->col[C_FORM]];
		r->field[r->col[C_FORM]] = NULL;
		if (r->field[r->col[C_FORM_B]][0]) {
			w->form_b = r->field[r->col[C_FORM_B]];
			r->field[r->col[C_FORM_B]] = NULL;
		}
		int np = parse(r, line, "form", w->form), nb = w->form_b ? parse(r, line, "form_b", w->form_b) : 0;
		if (np < 0 || nb < 0)
			return;
		w->np = np > nb ? np : nb;
		int given[BK_MAX_PARAMS] = {0};
		const char *msg = params(r->field[r->col[C_PARAMS]], w, given);
		if (msg) {
			fail(r, line, "%s, got '%.60s'", msg, r->field[r->col[C_PARAMS]]);
			return;
		}
		for (int j = 0; j < w->np; j++)
			if (!given[j]) {
				fail(r, line, "parameters: the form uses p%d and gives no value for it", j);
				return;
			}
	}
	if (r->need & BK_FRONTCSV_SCORES) {
		if (number(r->field[r->col[C_COST]], &w->cost) || w->cost < 0)
			fail(r, line, "cost: expected a finite number >= 0, got '%.40s'", r->field[r->col[C_COST]]);
		else if (number(r->field[r->col[C_ERROR]], &w->error) || w->error < 0)
			fail(r, line, "error: expected a finite number >= 0, got '%.40s'", r->field[r->col[C_ERROR]]);
	}
}

static void on_record(int c, void *data)
{
	(void)c;
	reader *r = data;
	int n = r->nfield < FIELDS_MAX ? r->nfield : FIELDS_MAX, line = r->rec_line ? r->rec_line : r->line;
	if (r->bad) {
	} else if (r->records++ == 0) { /* the header: the columns by name */
		int want[C_N] = {0, !!(r->need & BK_FRONTCSV_FORMS), !!(r->need & BK_FRONTCSV_FORMS),
		                 !!(r->need & BK_FRONTCSV_FORMS), !!(r->need & BK_FRONTCSV_SCORES),
		                 !!(r->need & BK_FRONTCSV_SCORES)};
		for (int k = 0; k < C_N && !r->bad; k++) {
			r->col[k] = -1;
			for (int j = 0; j < n; j++)
				if (r->field[j] && !strcmp(r->field[j], col_name[k]) && r->col[k] < 0)
					r->col[k] = j;
			if (r->col[k] < 0 && want[k])
				fail(r, line, "no column '%s' (not a front.csv of brdfkit search)", col_name[k]);
		}
	} else
		data_row(r, line);
	for (int j = 0; j < n; j++)
		free(r->field[j]);
	memset(r->field, 0, sizeof r->field);
	r->nfield = 0;
	r->rec_line = 0;
}

void bk_frontcsv_free(bk_frontcsv *fc)
{
	for (int i = 0; fc->row && i < fc->n; i++) {
		free(fc->row[i].name);
		free(fc->row[i].form);
		free(fc->row[i].form_b);
	}
	free(fc->row);
	fc->row = NULL;
	fc->n = 0;
}

int bk_frontcsv_read(const char *path, unsigned need, bk_frontcsv *fc, char *err, size_t errlen)
{
	memset(fc, 0, sizeof *fc);
	*err = '\0';
	reader r = {.path = path, .need = need, .fc = fc, .err = err, .errlen = errlen};
	FILE *f = fopen(path, "rb");
	if (!f) {
		fail(&r, 0, "cannot be read (%s)", strerror(errno));
		return -1;
	}
	struct csv_parser p;
	if (csv_init(&p, CSV_APPEND_NULL) || !(fc->row = calloc(BK_FRONTCSV_MAX_ROWS, sizeof *fc->row))) {
		fclose(f);
		fail(&r, 0, "out of memory");
		return -1;
	}
	char *line = NULL;
	size_t cap = 0;
	ssize_t len;
	int head = 1;
	while (!r.bad && (len = getline(&line, &cap, f)) >= 0) {
		r.line++;
		if (head && line[0] == '#') /* the provenance lines */
			continue;
		head = 0;
		if (memchr(line, '\0', (size_t)len))
			fail(&r, r.line, "a NUL byte (not a text file)");
		else if (csv_parse(&p, line, (size_t)len, on_field, on_record, &r) != (size_t)len)
			fail(&r, r.line, "%s", csv_strerror(csv_error(&p)));
	}
	if (!r.bad && ferror(f))
		fail(&r, 0, "read failed");
	if (!r.bad && csv_fini(&p, on_field, on_record, &r))
		fail(&r, r.line, "%s", csv_strerror(csv_error(&p)));
	if (!r.bad && r.records == 0)
		fail(&r, 0, "empty (not a front.csv of brdfkit search)");
	for (int j = 0; j < FIELDS_MAX; j++)
		free(r.field[j]);
	free(line);
	csv_free(&p);
	fclose(f);
	if (r.bad) {
		bk_frontcsv_free(fc);
		return -1;
	}
	return 0;
}
