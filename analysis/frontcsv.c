/*
 * frontcsv.c — a front.csv of brdfkit search read back by column name
 * (frontcsv.h).
 */
#include "frontcsv.h"

#include "csvtab.h"
#include "params.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { C_NAME, C_FORM, C_FORM_B, C_PARAMS, C_COST, C_ERROR, C_N };
static const char *const col_name[C_N + 1] = {"name", "form", "form_b", "parameters", "cost", "error", NULL};

int bk_frontcsv_score(const bk_csvtab *t, int i, int k, const char *name, double *v, char *err, size_t errlen)
{
	const char *s = bk_csvtab_get(t, i, k);
	if (!bk_csvtab_number(s, v) && *v >= 0) /* decimal only: no hex, no space (csvtab.h) */
		return 0;
	return bk_csvtab_err(err, errlen, t->path, t->line[i], "%s: expected a finite number >= 0, got '%.40s'",
	                     name, s);
}

/* One form text through the parser, into *f: its parameter count (*used:
 * or-ed with the parameters it reads), or -1 with err. */
static int parse(const bk_csvtab *t, int line, const char *what, const char *text, bk_form **f, unsigned *used,
                 char *err, size_t errlen)
{
	bk_form_error fe;
	if (!(*f = bk_form_parse(text, &fe)))
		return bk_csvtab_err(err, errlen, t->path, line, "%s: column %d: %s", what, fe.column, fe.message);
	*used |= bk_form_params(*f);
	return bk_form_nparams(*f);
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
		int np = parse(t, line, "form", w->form, &w->f, &used, err, errlen);
		int nb = np < 0 ? 0 : w->form_b ? parse(t, line, "form_b", w->form_b, &w->f_b, &used, err, errlen) : 0;
		if (np < 0 || nb < 0)
			return -1;
		w->np = np > nb ? np : nb;
		for (int j = 0; j < w->np; j++) /* as every command takes them (analysis/cli/form_check.h) */
			if (!(used >> j & 1u))
				return bk_csvtab_err(err, errlen, t->path, line, "the form uses p%d but not p%d: number the "
				                     "parameters from p0, without a gap", w->np - 1, j);
		int given[BK_MAX_PARAMS] = {0};
		char msg[600];
		if (bk_params_list(pt, w->p, given, msg, sizeof msg)) /* the one reader (params.h) */
			return bk_csvtab_err(err, errlen, t->path, line, "%s", msg);
		for (int j = 0; j < w->np; j++)
			if (!given[j])
				return bk_csvtab_err(err, errlen, t->path, line,
				                     "parameters: the form uses p%d and gives no value for it", j);
	}
	if (need & BK_FRONTCSV_SCORES) {
		if (bk_frontcsv_score(t, i, C_COST, col_name[C_COST], &w->cost, err, errlen) ||
		    bk_frontcsv_score(t, i, C_ERROR, col_name[C_ERROR], &w->error, err, errlen))
			return -1;
	}
	return 0;
}

void bk_frontcsv_dir(const char *path, int dir_only, char *out, size_t len)
{
	const char *slash = strrchr(path, '/'), *start = slash;
	while (start && start > path && start[-1] != '/')
		start--;
	if (slash && start && slash > start)
		snprintf(out, len, "%.*s", (int)(slash - start), start);
	else
		snprintf(out, len, "%s", dir_only ? "" : path);
}

void bk_frontcsv_free(bk_frontcsv *fc)
{
	for (int i = 0; fc->row && i < fc->n; i++) {
		free(fc->row[i].name);
		free(fc->row[i].form);
		free(fc->row[i].form_b);
		bk_form_free(fc->row[i].f);
		bk_form_free(fc->row[i].f_b);
	}
	free(fc->row);
	fc->row = NULL;
	fc->n = 0;
}

/* ---- the '#' lines: what the file states it is ----------------------------- */

/* One '#' line (without its line break) into h. */
static void head_line(bk_frontcsv_head *h, const char *line)
{
	static const char by[] = "# brdfkit ", target[] = "# target: ", cost[] = "# cost: ";
	const char *s;
	if (!strncmp(line, by, sizeof by - 1) && h->kind == BK_FRONTCSV_UNKNOWN && (s = strstr(line, " search "))) {
		if (!strncmp(s + 8, "front", 5))
			h->kind = BK_FRONTCSV_FRONT;
		else if (!strncmp(s + 8, "published forms", 15))
			h->kind = BK_FRONTCSV_CATALOG;
	} else if (!strncmp(line, target, sizeof target - 1) && !h->target[0])
		snprintf(h->target, sizeof h->target, "%s", line + sizeof target - 1);
	else if (!strncmp(line, cost, sizeof cost - 1) && !h->objective[0] && (s = strstr(line, "; error: "))) {
		char o[sizeof h->objective], p[sizeof h->precision];
		int used = 0;
		if (sscanf(s + 9, "%31s in %15s precision%n", o, p, &used) == 2 && used > 0) {
			memcpy(h->objective, o, sizeof o);
			memcpy(h->precision, p, sizeof p);
		}
	}
}

typedef struct head_ctx {
	bk_frontcsv_head *head;
	void (*more)(void *ctx, const char *line);
	void *ctx;
} head_ctx;

static void head_comment(void *ctx, int line, const char *text)
{
	head_ctx *h = ctx;
	(void)line;
	head_line(h->head, text);
	if (h->more)
		h->more(h->ctx, text);
}

int bk_frontcsv_table(const char *path, const char *const *cols, unsigned optional, const char *hint,
                      void (*more)(void *ctx, const char *line), void *ctx, bk_frontcsv_head *head, bk_csvtab *t,
                      char *err, size_t errlen)
{
	memset(head, 0, sizeof *head);
	head_ctx h = {head, more, ctx};
	bk_csvtab_spec spec = {.cols = cols, .optional = optional, .hint = hint, .max_rows = BK_FRONTCSV_MAX_ROWS,
	                       .comment = head_comment, .ctx = &h};
	return bk_csvtab_read(path, &spec, t, err, errlen);
}

/* The target's name: its description up to the first ':'. */
static int name_len(const char *desc)
{
	size_t n = strcspn(desc, ":");
	return n > 40 ? 40 : (int)n;
}

/* desc with its sample counts as 'N': a run of digits (and "NxM") right
 * after '(' or "a ", not the start of a decimal number, is a count of cells
 * ("(256 cell centres)", "(64)", "a 32x16 grid"); the ranges, f0 and the
 * index of refraction stay. */
static void mask_counts(const char *in, char *out, size_t len)
{
	size_t k = 0;
	for (size_t i = 0; in[i] && k + 1 < len;) {
		int after = i > 0 && (in[i - 1] == '(' || (i > 2 && in[i - 1] == ' ' && in[i - 2] == 'a' && in[i - 3] == ' '));
		size_t j = i;
		while (after && (isdigit((unsigned char)in[j]) || (j > i && in[j] == 'x' && isdigit((unsigned char)in[j + 1]))))
			j++;
		if (j > i && in[j] != '.') {
			out[k++] = 'N';
			i = j;
		} else
			out[k++] = in[i++];
	}
	out[k] = '\0';
}

int bk_frontcsv_head_check(const bk_frontcsv_head *h, const char *path, int kind, const char *whose,
                           const char *target, int exact, const char *objective, const char *precision, char *err,
                           size_t errlen)
{
	static const char *const what[] = {"a file", "a front", "a catalog"};
	if (h->kind == BK_FRONTCSV_UNKNOWN)
		return bk_csvtab_err(err, errlen, path, 0, "no '# brdfkit ... search %s' line: not %s of brdfkit search",
		                     kind == BK_FRONTCSV_FRONT ? "front" : "published forms",
		                     kind == BK_FRONTCSV_FRONT ? "a front.csv" : "a catalog.csv");
	if (h->kind != kind)
		return bk_csvtab_err(err, errlen, path, 0, "%s of brdfkit search (%s), not %s", what[h->kind],
		                     h->kind == BK_FRONTCSV_CATALOG ? "its published forms" : "its searched forms", what[kind]);
	if (target && !h->target[0])
		return bk_csvtab_err(err, errlen, path, 0, "no '# target:' line: %s does not say which target it is of",
		                     what[kind]);
	if (target && target[0]) {
		int n = name_len(h->target), m = name_len(target);
		if (n != m || strncmp(h->target, target, (size_t)n))
			return bk_csvtab_err(err, errlen, path, 0, "%s of target %.*s, %s target is %.*s", what[kind], n, h->target,
			                     whose, m, target);
		char a[sizeof h->target], b[sizeof h->target];
		mask_counts(h->target, a, sizeof a);
		mask_counts(target, b, sizeof b);
		const char *x = exact ? h->target : a, *y = exact ? target : b;
		if (strcmp(x, y)) { /* shown from the first difference and the words before it */
			size_t i = 0, back = 0;
			int spaces = 0;
			while (x[i] && x[i] == y[i])
				i++;
			while (i > 0 && back < 30 && (x[i - 1] != ' ' || ++spaces < 3))
				i--, back++;
			return bk_csvtab_err(err, errlen, path, 0, "%s of target %.*s %s: it says '%s%.60s', %s '%s%.60s'",
			                     what[kind], n, h->target, exact ? "on other samples, domain or options" :
			                     "on another domain or with other options", i ? "..." : "", x + i, whose,
			                     i ? "..." : "", y + i);
		}
	}
	if (objective && strcmp(h->objective, objective))
		return bk_csvtab_err(err, errlen, path, 0, "%s of objective %s, %s objective is %s", what[kind],
		                     h->objective[0] ? h->objective : "(not stated)", whose, objective);
	if (precision && strcmp(h->precision, precision))
		return bk_csvtab_err(err, errlen, path, 0, "%s in %s precision, not %s", what[kind],
		                     h->precision[0] ? h->precision : "(not stated)", precision);
	return 0;
}

int bk_frontcsv_read(const char *path, unsigned need, bk_frontcsv *fc, char *err, size_t errlen)
{
	memset(fc, 0, sizeof *fc);
	*err = '\0';
	unsigned forms = need & BK_FRONTCSV_FORMS ? 0 : 1u << C_FORM | 1u << C_FORM_B | 1u << C_PARAMS;
	unsigned scores = need & BK_FRONTCSV_SCORES ? 0 : 1u << C_COST | 1u << C_ERROR;
	bk_csvtab t;
	if (bk_frontcsv_table(path, col_name, 1u << C_NAME | forms | scores, "not a front.csv of brdfkit search", NULL,
	                      NULL, &fc->head, &t, err, errlen))
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
