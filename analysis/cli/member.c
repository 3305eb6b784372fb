/*
 * member.c — a front member by name (member.h), read through frontcsv.h.
 */
#include "member.h"

#include "cli.h"
#include "frontcsv.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *cli_member_split(const char *arg)
{
	const char *at = NULL;
	for (const char *s = strstr(arg, ".csv:"); s; s = strstr(s + 1, ".csv:"))
		at = s;
	return at ? at + 4 : NULL;
}

/* The row named rest (NAME exactly, else NAME:PART split at the last ':',
 * *part then set), or NULL. */
static const bk_frontcsv_row *find_row(const bk_frontcsv *fc, const char *rest, const char **part)
{
	size_t nlen = strlen(rest);
	*part = NULL;
	for (int pass = 0; pass < 2; pass++) {
		if (pass == 1) {
			if (!(*part = strrchr(rest, ':')))
				return NULL;
			nlen = (size_t)((*part)++ - rest);
		}
		for (int i = 0; i < fc->n; i++)
			if (strlen(fc->row[i].name) == nlen && !strncmp(fc->row[i].name, rest, nlen))
				return &fc->row[i];
	}
	return NULL;
}

/* The provenance codegen states, from the file's '#' lines and the row. */
static void provenance(cli_member *m, const bk_frontcsv *fc, const bk_frontcsv_row *r, const char *path)
{
	if (snprintf(m->source, sizeof m->source, "member %s of %s (brdfkit search front)", r->name, path) < 0)
		m->source[0] = '\0';
	snprintf(m->domain, sizeof m->domain, "%s", fc->head.target[0] ? fc->head.target : "not stated in the file");
	snprintf(m->errtext, sizeof m->errtext, "%s %.6g in %s precision on the target's samples (%s)",
	         fc->head.objective[0] ? fc->head.objective : "error", r->error,
	         fc->head.precision[0] ? fc->head.precision : "unstated", r->form_b ? "A and B as a pair" : "one form");
	size_t t = strcspn(fc->head.target, ": ");
	if (t < sizeof m->target)
		snprintf(m->target, sizeof m->target, "%.*s", (int)t, fc->head.target);
}

/* The inputs every row of r's kind reads (member.h's signature) into *sig;
 * -1 if a row has no form (frontcsv.h parsed them all as it read the file),
 * else 0. */
static int signature(const bk_frontcsv *fc, const bk_frontcsv_row *r, unsigned *sig)
{
	unsigned in = 0;
	for (int i = 0; i < fc->n; i++) {
		const bk_frontcsv_row *w = &fc->row[i];
		if (!w->form_b != !r->form_b)
			continue;
		for (int k = 0; k < 2; k++) {
			const bk_form *f = k ? w->f_b : w->f; /* parsed as the file was read */
			if (!f && (k == 0 || w->form_b))
				return -1;
			in |= f ? bk_form_inputs(f) : 0;
		}
	}
	if (in >> BK_IN_A & 1)
		in = (in & ~(1u << BK_IN_A)) | 1u << BK_IN_R;
	*sig = in;
	return 0;
}

int cli_member_load(const char *arg, int pair, cli_member *m)
{
	memset(m, 0, sizeof *m);
	const char *colon = cli_member_split(arg);
	char path[1024], err[600];
	if (!colon)
		return cli_bad("'%s': not FILE.csv:MEMBER", arg);
	if ((size_t)(colon - arg) >= sizeof path)
		return cli_bad("%.40s...: path too long", arg);
	memcpy(path, arg, (size_t)(colon - arg));
	path[colon - arg] = '\0';
	const char *rest = colon + 1;
	bk_frontcsv fc;
	if (bk_frontcsv_read(path, BK_FRONTCSV_FORMS | BK_FRONTCSV_SCORES, &fc, err, sizeof err))
		return cli_bad("%s", err);
	if (fc.head.kind != BK_FRONTCSV_FRONT) {
		bk_frontcsv_free(&fc);
		return cli_bad("%s: not a front.csv of brdfkit search (no '# brdfkit ... search front' line)", path);
	}
	const char *part;
	const bk_frontcsv_row *r = find_row(&fc, rest, &part);
	int rc = 0;
	if (!r) {
		rc = cli_bad("%s: no member '%s' (%d members: %s%s%s%s)", path, rest, fc.n, fc.n ? fc.row[0].name : "",
		             fc.n > 1 ? ", " : "", fc.n > 1 ? fc.row[1].name : "", fc.n > 2 ? ", ..." : "");
	} else if (r->form_b && !part && !pair) {
		rc = cli_bad("'%s' has two forms (split sum): write %s:A or %s:B", r->name, arg, arg);
	} else if (part && (!r->form_b || (strcmp(part, "A") && strcmp(part, "a") && strcmp(part, "B") &&
	                                   strcmp(part, "b")))) {
		rc = cli_bad("'%s': unknown part '%s'", r->name, part);
	}
	if (rc) {
		bk_frontcsv_free(&fc);
		return rc;
	}
	int want_b = part && (*part == 'B' || *part == 'b');
	m->part = part ? (want_b ? 'B' : 'A') : 0;
	m->form = strdup(want_b ? r->form_b : r->form);
	if (r->form_b && !part)
		m->form_b = strdup(r->form_b);
	m->f = bk_form_dup(want_b ? r->f_b : r->f);
	m->f_b = m->form_b ? bk_form_dup(r->f_b) : NULL;
	if (!m->form || (r->form_b && !part && !m->form_b) || !m->f || (m->form_b && !m->f_b)) {
		bk_frontcsv_free(&fc);
		cli_member_free(m);
		return cli_fail(NULL, "out of memory");
	}
	snprintf(m->name, sizeof m->name, "%s", r->name);
	m->np = r->np;
	memcpy(m->p, r->p, sizeof m->p);
	m->cost = r->cost;
	m->error = r->error;
	/* too long a name leaves fname "": the command's default */
	if (snprintf(m->fname, sizeof m->fname, "%s%s", r->name, part ? (want_b ? "_B" : "_A") : "") >=
	    (int)sizeof m->fname)
		m->fname[0] = '\0';
	provenance(m, &fc, r, path);
	int bad = signature(&fc, r, &m->signature);
	bk_frontcsv_free(&fc);
	if (bad) {
		cli_member_free(m);
		return cli_fail(NULL, "out of memory");
	}
	return 0;
}

void cli_member_free(cli_member *m)
{
	free(m->form);
	free(m->form_b);
	bk_form_free(m->f);
	bk_form_free(m->f_b);
	m->form = m->form_b = NULL;
	m->f = m->f_b = NULL;
}
