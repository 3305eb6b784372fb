/*
 * cmd_stability.c — brdfkit stability: a form, catalog entry or registry term
 * under stress in half, single and double precision (analysis/stability.c);
 * --all runs every term and catalog form and writes the table and the page
 * section of the study.
 */
#include "brdf.h"
#include "catalog.h"
#include "cli.h"
#include "out.h"
#include "cmd.h"
#include "form_check.h"
#include "heatmap.h"
#include "member.h"
#include "page.h"
#include "prov.h"
#include "search/pair.h"
#include "stability.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* A registry term as a call in the language: its C arguments mapped to the
 * inputs, fixed material values where the argument is not an input
 * (f90 = 1, glass eta = 1.5, a conductor 0.2 + 3i, sigma = r, VoL from LoH).
 * Returns a new string, or NULL if out of memory. */
static char *term_call(const bk_term *t)
{
	char *buf = NULL;
	size_t size = 0;
	FILE *m = open_memstream(&buf, &size);
	if (!m)
		return NULL;
	fprintf(m, "%s(", t->name);
	const char *p = t->args;
	int first = 1;
	while (*p) {
		const char *e = strchr(p, ',');
		int n = e ? (int)(e - p) : (int)strlen(p);
		const char *v = NULL;
		if (!strncmp(p, "f90", 3) && n == 3) v = "1";
		else if (!strncmp(p, "eta", 3) && n == 3) v = strcmp(t->name, "F_conductor") ? "1.5" : "0.2";
		else if (!strncmp(p, "k", 1) && n == 1) v = "3";
		else if (!strncmp(p, "sigma", 5) && n == 5) v = "r";
		else if (!strncmp(p, "VoL", 3) && n == 3) v = "2*LoH*LoH - 1";
		if (v)
			fprintf(m, "%s%s", first ? "" : ", ", v);
		else
			fprintf(m, "%s%.*s", first ? "" : ", ", n, p);
		first = 0;
		p += n + (e != NULL);
	}
	fputc(')', m);
	if (fclose(m)) {
		free(buf);
		return NULL;
	}
	return buf;
}

/* One form to analyse: its text (allocated: a form has no length limit) and
 * the values of its parameters, published (catalog) or given as pN=VALUE. */
typedef struct item {
	char name[96];
	char *text;
	bk_form *f;       /* text parsed, once (check_params), NULL where it does not parse: */
	bk_form_error fe; /* why, reported when its turn to run comes */
	double params[BK_MAX_PARAMS];
	int have[BK_MAX_PARAMS];
} item;

/* FILE.csv:NAME (member.h): the member's form (a pair whole, as a catalog
 * pair is analysed) and parameters, named NAME (NAME_A, NAME_B for a part).
 * Returns 0, -1 if out of memory, or 2 after a line naming the input. */
static int resolve_member(const char *arg, item *it)
{
	cli_member m;
	int rc = cli_member_load(arg, 1, &m);
	if (rc)
		return rc == 1 ? -1 : rc;
	snprintf(it->name, sizeof it->name, "%s", m.fname[0] ? m.fname : m.name);
	it->text = m.form_b ? bk_pair_dup(m.form, m.form_b) : strdup(m.form);
	memcpy(it->params, m.p, sizeof it->params);
	for (int j = 0; j < m.np; j++)
		it->have[j] = 1;
	cli_member_free(&m);
	return it->text ? 0 : -1;
}

/* Returns 0, -1 if out of memory, or 2 after a usage line. */
static int resolve(const char *arg, item *it)
{
	memset(it, 0, sizeof *it);
	if (cli_member_split(arg))
		return resolve_member(arg, it);
	snprintf(it->name, sizeof it->name, "%s", arg);
	const bk_catalog_entry *e = bk_catalog_find(arg);
	const bk_term *t = bk_term_find(arg);
	if (e) {
		it->text = e->form_b ? bk_pair_dup(e->form, e->form_b) : strdup(e->form);
		memcpy(it->params, e->defaults, sizeof it->params);
		for (int j = 0; j < e->nparams; j++)
			it->have[j] = 1;
	} else if (t) {
		it->text = term_call(t);
	} else {
		snprintf(it->name, sizeof it->name, "form");
		it->text = malloc(strlen(arg) + 1);
		if (it->text)
			strcpy(it->text, arg);
	}
	return it->text ? 0 : -1;
}

/* pN=VALUE into values[] and given[]: a parameter value for every form
 * given (a catalog entry's published value is overridden). Returns 0 or 2
 * (usage error). */
static int assignment(const cli_cmd *cmd, const char *arg, double *values, int *given)
{
	int rc = form_param_set(NULL, arg, values, given, NULL);
	if (rc == 0)
		return cli_usage(cmd, "expected pN=VALUE with N in 0..%d, got '%s'", BK_MAX_PARAMS - 1, arg);
	return rc == 1 ? 0 : 2;
}

/* Every parameter a form uses has a value, and every value given is used by
 * some form: zeros in place of a missing value, or a value that changes
 * nothing, would be a silent wrong answer. Returns 0 or 2. */
static int check_params(const cli_cmd *cmd, item *items, int n, const int *given)
{
	int used = 0;
	for (int i = 0; i < n; i++) {
		bk_form *f = items[i].f = bk_form_parse(items[i].text, &items[i].fe);
		int np = f ? bk_form_nparams(f) : 0; /* a parse error is reported by the run */
		unsigned mask = f ? bk_form_params(f) : 0;
		used = np > used ? np : used;
		int rc = form_check_params("stability", items[i].name, mask, items[i].have, NULL);
		if (rc)
			return rc;
	}
	for (int j = used; j < BK_MAX_PARAMS; j++)
		if (given[j])
			return cli_usage(cmd, "p%d=VALUE has no effect: no form given uses p%d", j, j);
	return 0;
}

static void csv_header(FILE *f)
{
	fputs("name,form,precision,samples,nan,inf,overflow,subnormal,zeroed,well_conditioned,wrong,max_rel,"
	      "ill_conditioned,max_rel_ill,region\n", f);
}

static void csv_rows(FILE *f, const bk_stability *st, const char *text)
{
	static const char *const pn[3] = {"f64", "f32", "f16"};
	for (int p = 0; p < 3; p++) {
		const bk_stab_prec *s = &st->p[p];
		bk_csv_field(f, st->name);
		fputc(',', f);
		bk_csv_field(f, text);
		fprintf(f, ",%s,%zu,%zu,%zu,%zu,%zu,%zu,%zu,%zu,%.3g,%zu,%.3g,", pn[p], s->n, s->nan, s->inf, s->overflow,
		        s->subnormal, s->zeroed, s->well, s->wrong, s->max_rel, s->ill, s->max_rel_ill);
		bk_csv_field(f, s->region);
		fputc('\n', f);
	}
}

static void summary_header(FILE *f)
{
	fputs("name,form,f16_wrong,f16_nan,f16_inf,f16_overflow,f16_subnormal,f16_max_rel,f32_max_rel,f64_max_rel,"
	      "f16_ill_conditioned,r_min,cos_min,r_min_cos0,r_min_cos1e-4,r_min_cos1e-3,r_min_cos1e-2,r_min_cos0.1,"
	      "safe_in_half,guards,guard_error_r,guard_error_cos,guarded_form,constants,advice\n", f);
}

/* x, "inf" for an infinity (a max_rel with a NaN or inf value in it: the
 * largest error, not none), empty for NaN (none found, nothing measured). */
static void num(FILE *f, double x)
{
	if (isfinite(x))
		fprintf(f, ",%.4g", x);
	else
		fputs(isinf(x) ? (x > 0 ? ",inf" : ",-inf") : ",", f);
}

static void summary_row(FILE *f, const bk_stability *st, const char *text)
{
	bk_csv_field(f, st->name);
	fputc(',', f);
	bk_csv_field(f, text);
	const bk_stab_prec *h = &st->p[2];
	fprintf(f, ",%zu,%zu,%zu,%zu,%zu", h->wrong, h->nan, h->inf, h->overflow, h->subnormal);
	num(f, h->max_rel);
	num(f, st->p[1].max_rel);
	num(f, st->p[0].max_rel);
	fprintf(f, ",%zu", h->ill);
	num(f, st->r_min);
	num(f, st->cos_min);
	for (int i = 0; i < 5; i++)
		num(f, st->floor_r[i]);
	fprintf(f, ",%s,", st->safe_as_is ? "as is" : st->guarded_ok ? "with guards" : "no");
	bk_csv_field(f, st->guards);
	num(f, st->guard_error[0]);
	num(f, st->guard_error[1]);
	fputc(',', f);
	bk_csv_field(f, st->guarded);
	fputc(',', f);
	bk_csv_field(f, st->constants);
	fputc(',', f);
	bk_csv_field(f, st->advice);
	fputc('\n', f);
}

/* The failure map: a share in [0, 1] on the sequential scale (0 dark, 1 light),
 * each axis cell labelled with the sample value it stands for. */
static int write_map(const bk_stability *st, const char *dir, char *err, size_t errlen)
{
	char title[160], stem[128], cx[32][16], cy[32][16];
	const char *xcat[32], *ycat[32];
	for (int i = 0; i < st->map_nx && i < 32; i++)
		snprintf(cx[i], sizeof cx[i], "%g", bk_stab_cos[i]), xcat[i] = cx[i];
	for (int j = 0; j < st->map_ny && j < 32; j++)
		snprintf(cy[j], sizeof cy[j], "%g", bk_stab_r[j]), ycat[j] = cy[j];
	snprintf(title, sizeof title, "%.80s: share of wrong half-precision results", st->name);
	bk_slug(st->name, stem, sizeof stem);
	bk_heatmap h = {st->map_nx, st->map_ny, st->map, 0, st->map_nx, 0, st->map_ny,
	                "first cosine", "r (perceptual roughness)", title, "wrong share",
	                "fraction of samples of the cell (over the other inputs) whose half-precision value is wrong: not "
	                "finite where the long-double reference at the same half-rounded inputs is finite, or off from it "
	                "by more than 2 % (by more than 2^-14 where it is below 2^-14), or right only because a min, max or "
	                "clamp hid an overflow or a NaN on the way; the axes are the sampled values, one cell each"};
	bk_heatmap_style style = {1, 1.0, st->map_nx <= 32 ? xcat : NULL, st->map_ny <= 32 ? ycat : NULL};
	return bk_heatmap_write_styled(&h, &style, dir, stem, err, errlen);
}

static void section_row(FILE *f, const bk_stability *st, const char *prefix)
{
	char stem[128];
	bk_slug(st->name, stem, sizeof stem);
	const bk_stab_prec *h = &st->p[2];
	fputs("<tr><td>", f);
	bk_html_text(f, st->name);
	fprintf(f, "</td><td>%s</td><td>%zu / %zu</td><td>%zu / %zu</td><td>%.2g</td><td>",
	        st->safe_as_is ? "safe as is" : st->guarded_ok ? "safe with guards" : "<b>not safe</b>", h->wrong, h->n,
	        h->nan + h->inf, h->overflow, h->max_rel);
	if (isfinite(st->r_min))
		fprintf(f, "r &ge; %.3g with cosines &ge; %.3g", st->r_min, st->cos_min);
	else
		fputs("none found", f);
	fputs("</td><td>", f);
	bk_html_text(f, st->safe_as_is ? "" : st->guards);
	if (st->advice[0]) {
		fputs("<br><i>", f);
		bk_html_text(f, st->advice);
		fputs("</i>", f);
	}
	if (st->constants[0]) {
		fputs("<br>constants: ", f);
		bk_html_text(f, st->constants);
	}
	fprintf(f, "</td><td><a href=\"%smaps/%s.png\"><img src=\"%smaps/%s.png\" width=\"100\" alt=\"map\"></a></td></tr>\n",
	        prefix, stem, prefix, stem);
}

static void print_one(const bk_stability *st, const char *text)
{
	static const char *const pn[3] = {"f64", "f32", "f16"};
	printf("%s: %s\n", st->name, text);
	printf("precision  samples  wrong  nan  inf  overflow  subnormal  zeroed  max_rel(well)  ill  where it breaks\n");
	for (int p = 2; p >= 0; p--) {
		const bk_stab_prec *s = &st->p[p];
		printf("%-9s  %7zu  %5zu  %3zu  %3zu  %8zu  %9zu  %6zu  %13.3g  %3zu  %s\n", pn[p], s->n, s->wrong, s->nan,
		       s->inf, s->overflow, s->subnormal, s->zeroed, s->max_rel, s->ill, s->region);
	}
	if (st->ref_nonfinite)
		printf("the form itself is NaN or infinite at %zu of %zu samples (first at %s): not safe in any precision "
		       "there\n", st->ref_nonfinite, st->p[2].n, st->pole);
	if (st->p[2].hidden)
		printf("in half, an overflow or a NaN on the way is hidden by min, max or clamp at %zu samples (counted "
		       "wrong: GLSL leaves min/clamp of a NaN undefined and need not produce an infinity)\n",
		       st->p[2].hidden);
	if (st->p[2].ill)
		printf("ill conditioned in half (input rounding alone moves the value by up to %.3g): %s\n",
		       st->p[2].max_rel_ill, st->p[2].ill_region);
	printf("minimum safe inputs in half (cosine floor: smallest safe r):");
	for (int i = 0; i < 5; i++)
		printf(" %g: %s%.4g", st->floor_cos[i], isnan(st->floor_r[i]) ? "" : "", st->floor_r[i]);
	printf("\n");
	if (!st->safe_as_is) {
		printf("guards: %s (%s)\n", st->guards, st->guarded_ok ? "passes in half" : "still fails");
		printf("error each guard adds alone: r floor %.3g, cosine floor %.3g\n", st->guard_error[0],
		       st->guard_error[1]);
		printf("guarded form: %s\n", st->guarded);
	} else {
		printf("safe in half as is\n");
	}
	if (st->advice[0])
		printf("advice: %s\n", st->advice);
	if (st->constants[0])
		printf("constants a half shader cannot hold: %s\n", st->constants);
}

static void free_items(item *items, bk_stability *st, int n)
{
	for (int i = 0; i < n; i++) {
		free(items[i].text);
		bk_form_free(items[i].f);
		bk_stability_free(&st[i]);
	}
	free(items);
	free(st);
}

/* ---- where the options act (cli.h) ----------------------------------------- */

/* Without --out the forms are printed, no page section is written. */
enum { TO_STDOUT, TO_DIR };
static const cli_dim dims[] = {
	{"out", {"stdout", "dir"}, {" without --out", " with --out"}},
};
static const cli_rule rules[] = {
	{"--link-prefix", NULL, 0, 1u << TO_DIR, "it prefixes links in DIR/section.html", "x/"},
	{"--out", NULL, CLI_EVERYWHERE, 0, NULL, "o"},
	{"--all", NULL, CLI_EVERYWHERE, 0, NULL, NULL},
	{"--tol", NULL, CLI_EVERYWHERE, 0, NULL, "0.1"},
};
static const char *const setups[] = {"NoV", "NoV --out o", "--all --out o", NULL};
static const cli_table table = {dims, 1, rules, sizeof rules / sizeof rules[0], setups};

int cmd_stability(int argc, char **argv)
{
	const char *out = NULL, *prefix = "";
	int all = 0;
	double tol = BK_STAB_TOL;
	cli_opt opts[] = {
		{.name = "--out", .kind = CLI_STR, .metavar = "DIR", .help = "directory for stability.csv, maps/ (EXR, PNG, SVG, PDF) and section.html (replaced whole)", .dest = &out},
		{.name = "--all", .kind = CLI_FLAG, .help = "every registry term and catalog form", .dest = &all},
		{.name = "--tol", .kind = CLI_NUM, .metavar = "T", .help = "relative error that counts as wrong (default 0.02)", .dest = &tol, .lo = 1e-6, .hi = 1},
		{.name = "--link-prefix", .kind = CLI_LINK, .metavar = "PATH/", .help = "prefix of links in section.html: a path relative to the page (no scheme, no //host), percent-encoded where written", .dest = &prefix},
	};
	cli_cmd cmd = {"stability", "Evaluates forms on a stress grid with the extremes (r from 0, cosines from 0 and up to\n"
	               "0.99999, f0 from 0) in half, single and double precision against long double; reports\n"
	               "NaN, Inf, overflow past 65504, subnormals, the largest error, where it breaks, the minimum\n"
	               "safe inputs in half, and guards that fix it with the error each adds.",
	               "FORM|NAME|TERM|FILE.csv:MEMBER ... [pN=VALUE ...] [--out DIR] | --all --out DIR",
	               "A precision is judged against the long-double value at inputs rounded as it holds them\n"
	               "(half: mediump); where that rounding alone moves the value by more than the tolerance\n"
	               "the sample is ill conditioned (reported apart: 1 - NoH^2 near the highlight). NaN or\n"
	               "Inf where that value is finite is always wrong.\n"
	               "Parameters: pN=VALUE, for every form given; a typed form must have a value for each\n"
	               "parameter it uses, and a catalog entry's published values apply unless pN=VALUE\n"
	               "overrides them. FILE.csv:MEMBER is a member of a front.csv of brdfkit search with its\n"
	               "fitted parameters (a split-sum member's pair whole, or MEMBER:A or MEMBER:B).",
	               opts, 4, 32, 0, {0}};
	int rc = cli_parse_table(&cmd, &table, argc, argv);
	if (rc || (rc = cli_applicable(&cmd, (int[]){out ? TO_DIR : TO_STDOUT})))
		return rc == 1 ? 0 : rc;
	double values[BK_MAX_PARAMS];
	int given[BK_MAX_PARAMS] = {0}, nforms = 0;
	char *forms[32];
	for (int i = 0; i < cmd.npos; i++) { /* the IR has no '=': an argument with one is pN=VALUE */
		if (!strchr(cmd.pos[i], '=')) { /* a form, a name, @FILE or - */
			const char *text;
			if (cli_form_arg(cmd.pos[i], &text))
				return 2;
			forms[nforms++] = (char *)text;
			continue;
		}
		if ((rc = assignment(&cmd, cmd.pos[i], values, given)))
			return rc;
	}
	if (!all && nforms == 0)
		return cli_usage(&cmd, "give FORM|NAME|TERM or --all");
	if (all && cmd.npos)
		return cli_usage(&cmd, "--all analyses the registry and the catalog: '%s' would be ignored", cmd.pos[0]);
	if (all && !out)
		return cli_usage(&cmd, "--all needs --out DIR");
	char err[512];
	if (out && bk_out_dir_check(out, err, sizeof err)) /* before the work, not after */
		return cli_fail("stability", "--out %s", err);
	int n = all ? (int)(bk_term_count() + bk_catalog_count()) : nforms;
	item *items = calloc((size_t)n, sizeof *items);
	bk_stability *st = calloc((size_t)n, sizeof *st);
	if (!items || !st) {
		free(items);
		free(st);
		return cli_fail("stability", "out of memory");
	}
	for (int i = 0; i < n && rc == 0; i++) {
		if (!all)
			rc = resolve(forms[i], &items[i]);
		else if ((size_t)i < bk_term_count())
			rc = resolve(bk_term_at((size_t)i)->name, &items[i]);
		else
			rc = resolve(bk_catalog_at((size_t)i - bk_term_count())->name, &items[i]);
		for (int j = 0; j < BK_MAX_PARAMS; j++)
			if (given[j])
				items[i].params[j] = values[j], items[i].have[j] = 1;
	}
	if (rc == -1)
		rc = cli_fail("stability", "out of memory");
	else if (rc == 0)
		rc = check_params(&cmd, items, n, given);
	for (int i = 0; i < n && rc == 0; i++) {
		if (!items[i].f)
			bk_stability_parse_error(items[i].name, &items[i].fe, err, sizeof err);
		if (!items[i].f ||
		    bk_stability_run_form(items[i].name, items[i].f, items[i].params, tol, &st[i], err, sizeof err)) {
			fprintf(stderr, "brdfkit stability: %s\n", err);
			rc = 2;
			break; /* the error is the one line on stderr: no progress after it */
		}
		cli_progress("stability", i + 1, n);
	}
	if (rc) {
		free_items(items, st, n);
		return rc;
	}
	if (!all)
		for (int i = 0; i < n; i++)
			print_one(&st[i], items[i].text);
	rc = 0;
	if (out) {
		char path[4400];
		bk_out_dir od;
		if (bk_out_dir_begin(&od, out, NULL, err, sizeof err)) {
			rc = cli_fail("stability", "--out %s", err);
		} else {
			const char *tmp = od.tmp;
			err[0] = '\0';
			snprintf(path, sizeof path, "%s/maps", tmp);
			mkdir(path, 0777);
			/* the three files, each failure named with its errno (out.h) */
			static const char *const names[3] = {"stability.csv", "details.csv", "section.html"};
			char paths[3][4400];
			FILE *fs[3] = {NULL, NULL, NULL};
			for (int k = 0; k < 3; k++) {
				snprintf(paths[k], sizeof paths[k], "%s/%s", tmp, names[k]);
				if (!*err && !(fs[k] = bk_out_fopen(paths[k], err, sizeof err)))
					rc = -1;
			}
			FILE *f = fs[0], *d = fs[1], *h = fs[2];
			char *pre = bk_html_link_text(prefix, NULL); /* the one link writer (out.h): encoded, escaped */
			if (!f || !d || !h || !pre)
				rc = -1;
			if (rc == 0) {
				bk_prov_header(f, bk_out_command(), NULL,
				               "stability: each term or form in half, single and double against long double on a "
				               "stress grid (details.csv: each precision)");
				summary_header(f);
				bk_prov_header(d, bk_out_command(), NULL,
				               "stability details: each term or form in each precision (half, single, double) "
				               "against long double on the stress grid");
				csv_header(d);
				fputs("<section id=\"stability\">\n<h2>Numerical stability in half precision</h2>\n<p>Every term and "
				      "catalog form on a stress grid with the extremes included, in half (IEEE binary16, rounded "
				      "after every operation, inputs rounded to half as mediump holds them), single and double, "
				      "against long double at the same rounded inputs. <i>Wrong</i>: not finite where the reference "
				      "is finite, or off by more than 2 % (by more than 2^-14 where the reference is below 2^-14, "
				      "half's smallest normal), or right only because a min, max or clamp hid an overflow or a NaN on "
				      "the way. A form that is itself NaN or infinite somewhere on the grid is never safe as is. The "
				      "minimum safe inputs are computed, and the "
				      "guard proposed is the floor that makes the form pass with the smallest error of its "
				      "own. Table: <a href=\"", h);
				fprintf(h, "%sstability.csv\">stability.csv</a>.</p>\n<figure>\n<table>\n<tr><th>term or form</th><th>half</th>"
				           "<th>wrong / samples</th><th>non-finite / overflows</th><th>max rel. error (well "
				           "conditioned)</th><th>safe from</th><th>guard</th><th>map</th></tr>\n", pre);
				for (int i = 0; i < n && rc == 0; i++) {
					summary_row(f, &st[i], items[i].text);
					csv_rows(d, &st[i], items[i].text);
					section_row(h, &st[i], pre);
					snprintf(path, sizeof path, "%s/maps", tmp);
					if (write_map(&st[i], path, err, sizeof err))
						rc = -1;
				}
				fprintf(h, "</table>\n<figcaption>Maps (last column): per term or form, the share of wrong "
				           "half-precision results (a sequential scale from 0, dark, to 1, light) over the first cosine "
				           "(across) and the perceptual roughness r (up) of the stress grid, the other inputs "
				           "pooled; each links to its PNG, beside it in <a href=\"%smaps/\">maps/</a> as SVG and PDF. "
				           "Data: <a href=\"%sstability.csv\">stability.csv</a>.</figcaption></figure>\n</section>\n",
				        pre, pre);
			}
			for (int k = 0; k < 3; k++) {
				char e[1200];
				if (fs[k] && bk_out_fclose(fs[k], paths[k], e, sizeof e)) {
					if (!*err)
						snprintf(err, sizeof err, "%.500s", e);
					rc = -1;
				}
			}
			free(pre);
			if (rc) {
				bk_out_dir_abort(&od);
				rc = cli_fail("stability", "%s: writing the results failed%s%s", out, *err ? ": " : "", err);
			} else if (bk_out_dir_commit(&od, err, sizeof err)) {
				rc = cli_fail("stability", "--out %s", err);
			}
		}
	}
	free_items(items, st, n);
	return rc;
}
