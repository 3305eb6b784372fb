/*
 * frontcsv.c — a front.csv of brdfkit search read back by column name
 * (frontcsv.h).
 */
#include "frontcsv.h"

#include "csvtab.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { C_NAME, C_FORM, C_FORM_B, C_PARAMS, C_COST, C_ERROR, C_N };
static const char *const col_name[C_N + 1] = {"name", "form", "form_b", "parameters", "cost", "error", NULL};

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
		if (*t == ';')
			return "parameters: an empty item";
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
		if (*end == ';' && !end[1])
			return "parameters: an empty item";
		t = *end ? end + 1 : end;
	}
	return NULL;
}

/* One form text through the parser: its parameter count (*used: or-ed
 * with the parameters it reads), or -1 with err. */
static int parse(const bk_csvtab *t, int line, const char *what, const char *text, unsigned *used, char *err,
                 size_t errlen)
{
	bk_form_error fe;
	bk_form *f = bk_form_parse(text, &fe);
	if (!f)
		return bk_csvtab_err(err, errlen, t->path, line, "%s: column %d: %s", what, fe.column, fe.message);
	int np = bk_form_nparams(f);
	*used |= bk_form_params(f);
	bk_form_free(f);
	return np;
}

/* Row i of t into w (w->name etc. its own); 0, or -1 with err. */
static int data_row(const bk_csvtab *t, int i, unsigned need, bk_frontcsv_row *w, char *err, size_t errlen)
{
	int line = t->line[i];
	const char *name = bk_csvtab_get(t, i, C_NAME);
	memset(w, 0, sizeof *w);
	w->line = line;
	w->cost = w->error = NAN;
	if (*name)
		w->name = strdup(name);
	else if ((w->name = malloc(32)))
		snprintf(w->name, 32, "row %d", line);
	if (!w->name)
		return bk_csvtab_err(err, errlen, t->path, 0, "out of memory");
	if (need & BK_FRONTCSV_FORMS) {
		const char *fb = bk_csvtab_get(t, i, C_FORM_B), *pt = bk_csvtab_get(t, i, C_PARAMS);
		if (!(w->form = strdup(bk_csvtab_get(t, i, C_FORM))) || (*fb && !(w->form_b = strdup(fb))))
			return bk_csvtab_err(err, errlen, t->path, 0, "out of memory");
		unsigned used = 0;
		int np = parse(t, line, "form", w->form, &used, err, errlen);
		int nb = np < 0 ? 0 : w->form_b ? parse(t, line, "form_b", w->form_b, &used, err, errlen) : 0;
		if (np < 0 || nb < 0)
			return -1;
		w->np = np > nb ? np : nb;
		for (int j = 0; j < w->np; j++) /* as every command takes them (analysis/cli/form_check.h) */
			if (!(used >> j & 1u))
				return bk_csvtab_err(err, errlen, t->path, line, "the form uses p%d but not p%d: number the "
				                     "parameters from p0, without a gap", w->np - 1, j);
		int given[BK_MAX_PARAMS] = {0};
		const char *msg = params(pt, w, given);
		if (msg)
			return bk_csvtab_err(err, errlen, t->path, line, "%s, got '%.60s'", msg, pt);
		for (int j = 0; j < w->np; j++)
			if (!given[j])
				return bk_csvtab_err(err, errlen, t->path, line,
				                     "parameters: the form uses p%d and gives no value for it", j);
	}
	if (need & BK_FRONTCSV_SCORES) {
		const char *c = bk_csvtab_get(t, i, C_COST), *e = bk_csvtab_get(t, i, C_ERROR);
		if (number(c, &w->cost) || w->cost < 0)
			return bk_csvtab_err(err, errlen, t->path, line, "cost: expected a finite number >= 0, got '%.40s'", c);
		if (number(e, &w->error) || w->error < 0)
			return bk_csvtab_err(err, errlen, t->path, line, "error: expected a finite number >= 0, got '%.40s'", e);
	}
	return 0;
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
	unsigned forms = need & BK_FRONTCSV_FORMS ? 0 : 1u << C_FORM | 1u << C_FORM_B | 1u << C_PARAMS;
	unsigned scores = need & BK_FRONTCSV_SCORES ? 0 : 1u << C_COST | 1u << C_ERROR;
	bk_csvtab_spec spec = {.cols = col_name, .optional = 1u << C_NAME | forms | scores,
	                       .hint = "not a front.csv of brdfkit search", .max_rows = BK_FRONTCSV_MAX_ROWS};
	bk_csvtab t;
	if (bk_csvtab_read(path, &spec, &t, err, errlen))
		return -1;
	int rc = 0;
	if (t.n && !(fc->row = calloc((size_t)t.n, sizeof *fc->row)))
		rc = bk_csvtab_err(err, errlen, path, 0, "out of memory");
	for (int i = 0; !rc && i < t.n; i++)
		rc = data_row(&t, i, need, &fc->row[fc->n++], err, errlen); /* freed with the front whatever follows */
	bk_csvtab_free(&t);
	if (rc)
		bk_frontcsv_free(fc);
	return rc;
}
