/*
 * cmd_time.c — brdfkit time: what forms cost, measured (CPU ns per evaluation
 * of the generated C) and counted (IR op classes, SPIR-V instructions), one
 * CSV row per form. The measuring is analysis/timing.c's; this file turns
 * arguments into rows and rows into CSV.
 */
#include "catalog.h"
#include "prov.h"
#include "cli.h"
#include "out.h"
#include "cmd.h"
#include "compare.h"
#include "form_check.h"
#include "member.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define TIME_MAX_ROWS 32 /* cli_parse keeps at most 32 positionals */

/* The rows, contiguous as bk_time_rows takes them, and for each which
 * parameters the command line or the catalog gave. */
typedef struct time_table {
	bk_compare_row rows[TIME_MAX_ROWS];
	int have[TIME_MAX_ROWS][BK_MAX_PARAMS];
	int given[TIME_MAX_ROWS][BK_MAX_PARAMS]; /* pN= on the command line */
	int typed[TIME_MAX_ROWS]; /* formula text, not a catalog name: takes p0=... */
	int n;
} time_table;

/* NAME, NAME:A or NAME:B from the catalog; 0 when arg names no entry, 1 when
 * it does, 2 after an error message. A split-sum entry without a part is
 * timed as one evaluation of A and B. */
static int catalog_row(const char *arg, bk_compare_row *r, int *have)
{
	char name[128];
	const char *colon = strchr(arg, ':');
	size_t len = colon ? (size_t)(colon - arg) : strlen(arg);
	if (len >= sizeof name)
		return 0;
	memcpy(name, arg, len);
	name[len] = '\0';
	const bk_catalog_entry *e = bk_catalog_find(name);
	if (!e)
		return 0;
	const char *part = colon ? colon + 1 : "";
	int a = !strcmp(part, "A") || !strcmp(part, "a"), b = !strcmp(part, "B") || !strcmp(part, "b");
	if (colon && (!e->form_b || !(a || b))) {
		return cli_bad("'%s': unknown part '%s'", name, part);
	}
	snprintf(r->form, sizeof r->form, "%s", b ? e->form_b : e->form);
	if (!colon && e->form_b)
		snprintf(r->form_b, sizeof r->form_b, "%s", e->form_b);
	snprintf(r->name, sizeof r->name, "%s", arg);
	snprintf(r->kind, sizeof r->kind, "published");
	snprintf(r->source, sizeof r->source, "%s", e->source);
	r->nparams = e->nparams;
	for (int i = 0; i < e->nparams; i++) {
		r->params[i] = e->defaults[i];
		have[i] = 1;
	}
	return 1;
}

/* FILE.csv:NAME (member.h): 0 when arg names no member, 1 when it does, 2
 * after its line on stderr (a bad member, or out of memory). A split-sum member
 * without a part is timed as one evaluation of A and B, as a catalog pair. */
static int member_row(const char *arg, bk_compare_row *r, int *have)
{
	if (!cli_member_split(arg))
		return 0;
	cli_member m;
	int rc = cli_member_load(arg, 1, &m);
	if (rc)
		return 2;
	if (strlen(m.form) >= sizeof r->form || (m.form_b && strlen(m.form_b) >= sizeof r->form_b)) {
		cli_member_free(&m);
		return cli_bad("%s: form longer than %zu characters", arg, sizeof r->form - 1);
	}
	snprintf(r->form, sizeof r->form, "%s", m.form);
	snprintf(r->form_b, sizeof r->form_b, "%s", m.form_b ? m.form_b : "");
	snprintf(r->name, sizeof r->name, "%s", m.fname[0] ? m.fname : m.name);
	snprintf(r->kind, sizeof r->kind, "member");
	snprintf(r->source, sizeof r->source, "%.255s", m.source);
	r->nparams = m.np;
	memcpy(r->params, m.p, sizeof r->params);
	for (int i = 0; i < m.np; i++)
		have[i] = 1;
	cli_member_free(&m);
	return 1;
}

static int typed_row(const char *arg, int index, bk_compare_row *r)
{
	if (strlen(arg) >= sizeof r->form) {
		return cli_bad("form %d: longer than %zu characters", index, sizeof r->form - 1);
	}
	snprintf(r->form, sizeof r->form, "%s", arg);
	snprintf(r->name, sizeof r->name, "form%d", index);
	snprintf(r->kind, sizeof r->kind, "form");
	snprintf(r->source, sizeof r->source, "typed on the command line");
		return 0;
}

/* Positionals into rows: FORM|NAME starts a row, pN=V binds to the typed
 * form before it. */
static int read_rows(char **pos, int npos, time_table *T)
{
	for (int i = 0; i < npos; i++) {
		int k, rc, last = T->n - 1;
		double v;
		if ((rc = form_param(pos[i], &k, &v)) == 2)
			return 2;
		if (rc == 1) {
			if (last < 0 || !T->typed[last]) {
				return cli_bad("'%s' must follow a typed form (catalog entries use their published constants)",
				               pos[i]);
			}
			if (form_param_set(T->rows[last].name, pos[i], T->rows[last].params, T->given[last], &k) != 1)
				return 2;
			T->have[last][k] = 1;
			continue;
		}
		int j = T->n++;
		if ((rc = member_row(pos[i], &T->rows[j], T->have[j])) == 2 ||
		    (rc == 0 && (rc = catalog_row(pos[i], &T->rows[j], T->have[j])) == 2))
			return 2;
		T->typed[j] = rc == 0;
		if (rc == 0 && typed_row(pos[i], T->n, &T->rows[j]))
			return 2;
	}
	return 0;
}

/* Parses a row's form(s) into the row's IR, r->f, the one parse of its
 * text (what SPIR-V, the timing and the op counts read): the column of a
 * syntax error; the shared checks (form_check.h: parameters given and used,
 * a value somewhere); op counts and cost of A and B together. */
static int check_row(time_table *T, int i)
{
	bk_compare_row *r = &T->rows[i];
	const char *text[2] = {r->form, r->form_b};
	bk_form **f = r->f;
	unsigned used = 0;
	int rc = 0, np = 0;
	for (int p = 0; p < 2 && text[p][0] && !rc; p++) {
		bk_form_error fe;
		if (!(f[p] = bk_form_parse(text[p], &fe))) {
			fprintf(stderr, "brdfkit time: %s:1:%d: %s\n", T->typed[i] ? "form" : r->name, fe.column, fe.message);
			rc = 2;
		} else {
			used |= bk_form_params(f[p]);
			np = bk_form_nparams(f[p]) > np ? bk_form_nparams(f[p]) : np;
		}
	}
	if (!rc)
		rc = form_check_params("time", r->name, used, T->have[i], T->typed[i] ? T->given[i] : NULL);
	for (int p = 0; p < 2 && f[p] && !rc; p++)
		rc = form_check_finite("time", r->name, f[p], r->params);
	for (int p = 0; p < 2 && f[p] && !rc; p++) /* the C it times is float: codegen's warning (M3) */
		form_warn_precision("time", r->name, f[p], r->params, BK_F32);
	if (rc)
		return rc; /* the row's IR is freed with the others' */
	memset(&r->ops, 0, sizeof r->ops);
	r->nparams = r->nparams > np ? r->nparams : np;
	for (int p = 0; p < 2 && f[p]; p++) {
		bk_ops o;
		bk_form_count(f[p], &o);
		for (int k = 0; k < BK_K_COUNT; k++)
			r->ops.n[k] += o.n[k];
		r->ops.simple += o.simple;
		r->ops.complex += o.complex;
	}
	r->cost = bk_ops_cost(&r->ops, BK_COST_SIMPLE, BK_COST_COMPLEX);
	for (int k = 0; T->typed[i] && k < r->nparams; k++) /* "form2 (p0=0.5;p1=2)" */
		snprintf(r->name + strlen(r->name), sizeof r->name - strlen(r->name), "%sp%d=%.9g%s", k ? ";" : " (", k,
		         r->params[k], k + 1 == r->nparams ? ")" : "");
	return 0;
}

/* SPIR-V instructions of A (+ B); -1 with one warning when the tools are missing. */
static void spirv_row(bk_compare_row *r, int *warned)
{
	r->spirv = 0;
	for (int p = 0; p < 2 && r->f[p] && r->spirv >= 0; p++) {
		char err[512];
		int k = bk_spirv_count(r->f[p], r->params, err, sizeof err);
		if (k < 0 && !*warned) {
			fprintf(stderr, "brdfkit time: warning: spirv column is -1: %s\n", err);
			*warned = 1;
		}
		r->spirv = k < 0 ? -1 : r->spirv + k;
	}
}

static void write_csv(FILE *f, const bk_compare_row *rows, int n)
{
	/* the provenance line every brdfkit CSV opens with: it also lets a later
	 * --out replace this file (out.h, bk_out_file_check) */
	bk_prov_title(f, "time: CPU ns per evaluation (median, min, max of the runs), op counts, SPIR-V size");
	bk_prov_command(f, bk_out_command());
	fputs("name,form,ns_per_eval,ns_min,ns_max", f);
	for (int k = 1; k < BK_K_COUNT; k++)
		fprintf(f, ",%s", bk_opclass_name((bk_opclass)k));
	fputs(",simple,complex,cost,spirv\n", f);
	for (int i = 0; i < n; i++) {
		const bk_compare_row *r = &rows[i];
		char form[2 * sizeof r->form + 4];
		snprintf(form, sizeof form, "%s%s%s", r->form, r->form_b[0] ? "; " : "", r->form_b);
		bk_csv_field(f, r->name);
		fputc(',', f);
		bk_csv_field(f, form);
		fprintf(f, ",%.4g,%.4g,%.4g", r->ns, r->ns_min, r->ns_max);
		for (int k = 1; k < BK_K_COUNT; k++)
			fprintf(f, ",%d", r->ops.n[k]);
		fprintf(f, ",%d,%d,%g,%d\n", r->ops.simple, r->ops.complex, r->cost, r->spirv);
	}
}

static int output(const char *path, const bk_compare_row *rows, int n)
{
	if (!path) {
		write_csv(stdout, rows, n);
		return fflush(stdout) ? cli_fail("time", "stdout: write failed") : 0;
	}
	bk_out o;
	char err[512];
	if (bk_out_open_file(&o, path, err, sizeof err))
		return cli_fail("time", "%s", err);
	write_csv(o.f, rows, n);
	if (bk_out_commit(&o, err, sizeof err))
		return cli_fail("time", "%s", err);
	return 0;
}

/* ---- where the options act (cli.h) ----------------------------------------- */

/* Every run times every row and writes one CSV: both options always act. */
static const cli_rule rules[] = {
	{"--reps", NULL, CLI_EVERYWHERE, 0, NULL, "3"},
	{"--out", NULL, CLI_EVERYWHERE, 0, NULL, "o.csv"},
};
static const char *const setups[] = {"NoV", NULL};
static const cli_table table = {NULL, 0, rules, sizeof rules / sizeof rules[0], setups};

int cmd_time(int argc, char **argv)
{
	long reps = 15;
	const char *out = NULL;
	cli_opt opts[] = {
		{.name = "--reps", .kind = CLI_INT, .metavar = "N", .help = "timed runs per form (default 15)", .dest = &reps, .lo = 1, .hi = 1000},
		{.name = "--out", .kind = CLI_STR, .metavar = "FILE", .help = "write the CSV there (atomically) instead of stdout", .dest = &out},
	};
	cli_cmd cmd = {"time", "Measures what forms cost: CPU ns per evaluation of the generated C (cc -std=c11 -O2,\n"
	               "no fast-math, scalar), the IR's op counts and the SPIR-V instructions of the\n"
	               "generated GLSL after spirv-opt -O. One CSV row per form.",
	               "'FORM'|NAME|FILE.csv:MEMBER [p0=X ...] ['FORM'|NAME [p0=X ...] ...] [--reps N] [--out FILE]",
	               "NAME is a catalog entry (brdfkit catalog) with its published constants, FILE.csv:MEMBER\n"
	               "a member of a front.csv of brdfkit search with its parameters (the same); a split-sum\n"
	               "entry is timed as one evaluation of A and B together (form column 'A; B', op counts\n"
	               "and SPIR-V summed), NAME:A or NAME:B for one part. pN=X after a typed FORM gives its\n"
	               "parameters. Every form runs over the same 2^20 inputs (cosines in (0.01, 1],\n"
	               "r in (0.02, 1], a = r^2, f0 in [0.02, 1]); after a warm-up, N runs with the forms\n"
	               "interleaved; ns_per_eval is their median, ns_min and ns_max the extremes. Compare\n"
	               "rows of one run on one machine only. spirv: instructions in the optimised\n"
	               "shader's functions net of a load/store-only baseline (-1 without spirv-tools).\n"
	               "Columns: name,form,ns_per_eval,ns_min,ns_max, the op classes of brdfkit ops,\n"
	               "simple,complex,cost,spirv.",
	               opts, 2, TIME_MAX_ROWS, 0, {0}};
	int rc = cli_parse_table(&cmd, &table, argc, argv);
	if (rc || (rc = cli_applicable(&cmd, NULL)))
		return rc == 1 ? 0 : rc;
	if (cli_form_positionals(&cmd, 0))
		return 2;
	if ((rc = cli_out_file("time", out))) /* before the compiles and the timing, not after */
		return rc;
	time_table *T = calloc(1, sizeof *T);
	if (!T)
		return cli_fail("time", "out of memory");
	rc = read_rows(cmd.pos, cmd.npos, T);
	if (!rc && T->n == 0) {
		fprintf(stderr, "brdfkit time: missing FORM (see brdfkit time --help)\n");
		rc = 2;
	}
	for (int i = 0; !rc && i < T->n; i++)
		rc = check_row(T, i);
	int warned = 0;
	for (int i = 0; !rc && i < T->n; i++) {
		spirv_row(&T->rows[i], &warned);
		cli_progress("time: spirv", i + 1, T->n);
	}
	char err[512];
	if (!rc) {
		cli_progress("time: timing", 0, 1);
		int bad = bk_time_rows(T->rows, T->n, (int)reps, err, sizeof err);
		cli_progress("time: timing", 1, 1);
		if (bad)
			rc = cli_fail("time", "%s", err);
	}
	if (!rc)
		rc = output(out, T->rows, T->n);
	bk_compare_rows_free(T->rows, T->n);
	free(T);
	return rc;
}
