/*
 * sources.c — the functions tests/vk runs (see sources.h): the catalog, the
 * rows of search fronts (libcsv, columns by name) and the functions of
 * committed GLSL files (their provenance comments parsed for the form).
 */
#include "sources.h"

#include "catalog.h"

#include <csv.h>
#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static vk_fn *grow(vk_fns *fns)
{
	if (fns->n == fns->cap) {
		int cap = fns->cap ? 2 * fns->cap : 128;
		vk_fn *v = realloc(fns->v, (size_t)cap * sizeof *v);
		if (!v)
			return NULL;
		fns->v = v;
		fns->cap = cap;
	}
	vk_fn *f = &fns->v[fns->n];
	memset(f, 0, sizeof *f);
	return f;
}

void vk_fns_free(vk_fns *fns)
{
	for (int i = 0; i < fns->n; i++) {
		bk_form_free(fns->v[i].form);
		free(fns->v[i].glsl);
	}
	free(fns->v);
	memset(fns, 0, sizeof *fns);
}

/* One emitted function: text parsed, bk_form_emit'd under a name unique in
 * the run (a catalog or front name may be a GLSL word). Group 0: emitted. */
static int add_emitted(vk_fns *fns, const char *label, const char *text, const double *params, int np,
                       char *err, size_t errlen)
{
	vk_fn *f = grow(fns);
	bk_form_error fe;
	if (!f) {
		snprintf(err, errlen, "out of memory");
		return -1;
	}
	snprintf(f->label, sizeof f->label, "%s", label);
	if (!(f->form = bk_form_parse(text, &fe))) {
		snprintf(err, errlen, "%s: '%.100s':%d: %s", label, text, fe.column, fe.message);
		return -1;
	}
	if (bk_form_nparams(f->form) > np) {
		snprintf(err, errlen, "%s: the form reads p%d, %d parameters given", label, bk_form_nparams(f->form) - 1, np);
		bk_form_free(f->form);
		return -1;
	}
	memcpy(f->params, params, sizeof f->params);
	snprintf(f->name, sizeof f->name, "bk_fn_%d", fns->n);
	bk_emit_info info = {.name = f->name, .source = label};
	f->args = bk_form_inputs(f->form);
	if (!(f->glsl = bk_form_emit(f->form, BK_LANG_GLSL, 0, f->params, &info))) {
		snprintf(err, errlen, "%s: bk_form_emit failed", label);
		bk_form_free(f->form);
		return -1;
	}
	fns->n++;
	return 0;
}

int vk_add_catalog(vk_fns *fns, char *err, size_t errlen)
{
	for (size_t i = 0; i < bk_catalog_count(); i++) {
		const bk_catalog_entry *e = bk_catalog_at(i);
		char label[200];
		snprintf(label, sizeof label, "catalog:%s%s", e->name, e->form_b ? ":A" : "");
		if (add_emitted(fns, label, e->form, e->defaults, e->nparams, err, errlen))
			return -1;
		snprintf(label, sizeof label, "catalog:%s:B", e->name);
		if (e->form_b && add_emitted(fns, label, e->form_b, e->defaults, e->nparams, err, errlen))
			return -1;
	}
	return 0;
}

/* ---- front.csv ------------------------------------------------------------ */

#define FR_FIELDS 64

typedef struct front {
	vk_fns *fns;
	const char *path;
	char dir[64];
	char *field[FR_FIELDS];
	int nfield, record, col[4];
	int bad;
	char *err;
	size_t errlen;
} front;

static void fr_field(void *s, size_t len, void *data)
{
	front *r = data;
	if (r->nfield < FR_FIELDS && !(r->field[r->nfield] = strndup(s ? s : "", len)))
		r->bad = 1;
	r->nfield++;
}

/* "p0=0.1;p1=2" into p; the count (highest index + 1), or -1. */
static int fr_params(const char *text, double *p)
{
	int n = 0;
	for (const char *t = text; *t;) {
		char *end;
		long i;
		if (*t != 'p' || (i = strtol(t + 1, &end, 10)) < 0 || i >= BK_MAX_PARAMS || *end != '=')
			return -1;
		p[i] = strtod(end + 1, &end);
		if (*end && *end != ';')
			return -1;
		n = (int)i + 1 > n ? (int)i + 1 : n;
		t = *end ? end + 1 : end;
	}
	return n;
}

static void fr_row(front *r)
{
	double p[BK_MAX_PARAMS] = {0};
	int np = fr_params(r->field[r->col[3]], p);
	const char *name = r->field[r->col[0]], *b = r->field[r->col[2]];
	char label[200];
	if (np < 0) {
		snprintf(r->err, r->errlen, "%s: row %d: parameters '%.60s' are not p0=X;p1=Y...", r->path, r->record,
		         r->field[r->col[3]]);
		r->bad = 1;
		return;
	}
	snprintf(label, sizeof label, "front:%s/%.80s%s", r->dir, name, *b ? ":A" : "");
	if (add_emitted(r->fns, label, r->field[r->col[1]], p, np, r->err, r->errlen)) {
		r->bad = 1;
		return;
	}
	snprintf(label, sizeof label, "front:%s/%.80s:B", r->dir, name);
	if (*b && add_emitted(r->fns, label, b, p, np, r->err, r->errlen))
		r->bad = 1;
}

static void fr_record(int c, void *data)
{
	(void)c;
	front *r = data;
	static const char *const want[4] = {"name", "form", "form_b", "parameters"};
	int n = r->nfield < FR_FIELDS ? r->nfield : FR_FIELDS;
	r->record++;
	if (r->bad) {
	} else if (r->record == 1) {
		for (int k = 0; k < 4 && !r->bad; k++) {
			r->col[k] = -1;
			for (int j = 0; j < n; j++)
				if (r->field[j] && !strcmp(r->field[j], want[k]))
					r->col[k] = j;
			if (r->col[k] < 0) {
				snprintf(r->err, r->errlen, "%s: no column '%s'", r->path, want[k]);
				r->bad = 1;
			}
		}
	} else if (n != r->nfield || n <= r->col[0] || n <= r->col[1] || n <= r->col[2] || n <= r->col[3]) {
		snprintf(r->err, r->errlen, "%s: row %d: %d fields, fewer than the header's", r->path, r->record, n);
		r->bad = 1;
	} else
		fr_row(r);
	for (int j = 0; j < n; j++)
		free(r->field[j]);
	memset(r->field, 0, sizeof r->field);
	r->nfield = 0;
}

/* The folder that holds path ("results/search/env/front.csv": "env"). */
static void parent_name(const char *path, char *out, size_t len)
{
	const char *slash = strrchr(path, '/'), *start = slash;
	while (start && start > path && start[-1] != '/')
		start--;
	if (slash && start && slash > start)
		snprintf(out, len, "%.*s", (int)(slash - start), start);
	else
		snprintf(out, len, "%s", path);
}

int vk_add_front(vk_fns *fns, const char *path, char *err, size_t errlen)
{
	FILE *f = fopen(path, "rb");
	if (!f) {
		snprintf(err, errlen, "%s: %s", path, strerror(errno));
		return -1;
	}
	front r = {.fns = fns, .path = path, .err = err, .errlen = errlen};
	parent_name(path, r.dir, sizeof r.dir);
	int first = fns->n;
	struct csv_parser p;
	char line[65536];
	int head = 1;
	if (csv_init(&p, CSV_APPEND_NULL)) {
		fclose(f);
		snprintf(err, errlen, "out of memory");
		return -1;
	}
	while (!r.bad && fgets(line, sizeof line, f)) {
		if (head && line[0] == '#') /* the provenance lines */
			continue;
		head = 0;
		size_t len = strlen(line);
		if (csv_parse(&p, line, len, fr_field, fr_record, &r) != len) {
			snprintf(err, errlen, "%s: %s", path, csv_strerror(csv_error(&p)));
			r.bad = 1;
		}
	}
	if (!r.bad && (ferror(f) || csv_fini(&p, fr_field, fr_record, &r))) {
		snprintf(err, errlen, "%s: read failed", path);
		r.bad = 1;
	}
	csv_free(&p);
	fclose(f);
	if (!r.bad && fns->n == first) {
		snprintf(err, errlen, "%s: no front member", path);
		r.bad = 1;
	}
	return r.bad ? -1 : 0;
}

/* ---- brdfkit's GLSL files ---------------------------------------------------- */

#define FN_HEAD "/*\n * Generated by brdfkit"

static char *slurp(const char *path, char *err, size_t errlen)
{
	FILE *f = fopen(path, "rb");
	char *s = NULL;
	size_t n = 0, cap = 0;
	if (!f) {
		snprintf(err, errlen, "%s: %s", path, strerror(errno));
		return NULL;
	}
	for (;;) {
		if (cap - n < 4096) {
			char *t = realloc(s, cap = cap ? 2 * cap : 65536);
			if (!t) {
				free(s);
				fclose(f);
				snprintf(err, errlen, "out of memory");
				return NULL;
			}
			s = t;
		}
		size_t k = fread(s + n, 1, cap - n - 1, f);
		n += k;
		if (k == 0)
			break;
	}
	s[n] = '\0';
	fclose(f);
	return s;
}

/* The text after "label" on the comment line " * label" inside [s, e), or NULL. */
static const char *comment_value(const char *s, const char *e, const char *label, size_t *len)
{
	size_t k = strlen(label);
	for (const char *t = s; t && t < e; t = strchr(t, '\n')) {
		t += *t == '\n';
		if (!strncmp(t, label, k)) {
			*len = strcspn(t + k, "\n");
			return t + k;
		}
	}
	return NULL;
}

/* The signature after the comment: "TYPE... NAME(TYPE... ARG, ...)". */
static int signature(vk_fn *f, const char *sig, char *err, size_t errlen)
{
	const char *open = strchr(sig, '('), *close = open ? strchr(open, ')') : NULL;
	const char *n = open;
	while (n && n > sig && (isalnum((unsigned char)n[-1]) || n[-1] == '_'))
		n--;
	if (!close || n == open) {
		snprintf(err, errlen, "%s: no function signature after the comment", f->label);
		return -1;
	}
	snprintf(f->name, sizeof f->name, "%.*s", (int)(open - n), n);
	for (const char *a = open + 1; a < close;) {
		size_t k = strcspn(a, ",)");
		const char *w = a + k;
		while (w > a && !(isalnum((unsigned char)w[-1]) || w[-1] == '_'))
			w--;
		const char *b = w;
		while (b > a && (isalnum((unsigned char)b[-1]) || b[-1] == '_'))
			b--;
		int found = -1;
		for (int i = 0; i < BK_IN_COUNT; i++)
			if ((size_t)(w - b) == strlen(bk_input_name((bk_input)i)) &&
			    !strncmp(b, bk_input_name((bk_input)i), (size_t)(w - b)))
				found = i;
		if (w > b && found < 0) {
			snprintf(err, errlen, "%s: argument '%.*s' is no input", f->label, (int)(w - b), b);
			return -1;
		}
		if (found >= 0)
			f->args |= 1u << found;
		a += k + 1;
	}
	return 0;
}

/* One function block [s, e) of a GLSL file. */
static int file_fn(vk_fns *fns, const char *where, const char *s, const char *e, char *err, size_t errlen)
{
	vk_fn *f = grow(fns);
	if (!f) {
		snprintf(err, errlen, "out of memory");
		return -1;
	}
	const char *cend = strstr(s, "\n */\n"), *body = cend ? strstr(cend, "\n{\n") : NULL;
	const char *fend = body ? strstr(body, "\n}\n") : NULL;
	size_t flen = 0;
	const char *form = comment_value(s, e, " * form: ", &flen);
	snprintf(f->label, sizeof f->label, "file:%.150s", where);
	if (!cend || !body || !fend || fend > e || !form || form > cend) {
		snprintf(err, errlen, "%s: a function block without its form line, comment or body", f->label);
		return -1;
	}
	if (signature(f, cend + 5, err, errlen))
		return -1;
	snprintf(f->label, sizeof f->label, "file:%.110s:%.80s", where, f->name);
	char *text = strndup(form, flen);
	bk_form_error fe;
	f->form = text ? bk_form_parse(text, &fe) : NULL;
	if (!f->form) {
		snprintf(err, errlen, "%s: form '%.100s':%d: %s", f->label, text ? text : "", fe.column, fe.message);
		free(text);
		return -1;
	}
	free(text);
	int have = 0;
	for (const char *t = s; t && t < cend; t = strchr(t + 1, '\n')) {
		int i, k;
		double v;
		if (sscanf(t, "\n *   p%d = %lf%n", &i, &v, &k) == 2 && i >= 0 && i < BK_MAX_PARAMS) {
			f->params[i] = v;
			have = i + 1 > have ? i + 1 : have;
		}
	}
	if (bk_form_nparams(f->form) > have || f->args != bk_form_inputs(f->form)) {
		snprintf(err, errlen, "%s: the comment gives %d parameters and the signature other inputs than the form",
		         f->label, have);
		bk_form_free(f->form);
		return -1;
	}
	if (!(f->glsl = strndup(s, (size_t)(fend + 3 - s)))) {
		bk_form_free(f->form);
		snprintf(err, errlen, "out of memory");
		return -1;
	}
	/* group: the first file group (from 1) without a function of this name */
	f->group = 1;
	for (int j = 0; j < fns->n; j++)
		if (fns->v[j].group == f->group && !strcmp(fns->v[j].name, f->name))
			f->group++, j = -1;
	fns->groups = f->group + 1 > fns->groups ? f->group + 1 : fns->groups;
	fns->n++;
	return 0;
}

int vk_add_glsl(vk_fns *fns, const char *path, char *err, size_t errlen)
{
	char *text = slurp(path, err, errlen);
	if (!text)
		return -1;
	int rc = 0, found = 0;
	for (char *s = strstr(text, FN_HEAD); !rc && s; found++) {
		char *next = strstr(s + 1, FN_HEAD);
		rc = file_fn(fns, path, s, next ? next : s + strlen(s), err, errlen);
		s = next;
	}
	if (!rc && !found) {
		snprintf(err, errlen, "%s: no brdfkit function in it", path);
		rc = -1;
	}
	free(text);
	return rc;
}
