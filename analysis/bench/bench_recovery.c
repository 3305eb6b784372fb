/*
 * bench_recovery.c — make bench: how often the search finds a form that is
 * there to be found (issue 22).
 *
 *   1. the planted suite (analysis/bench/planted.txt): each form is the
 *      target of a search as `brdfkit search --target form` runs it (its
 *      screening grid, the default grammar or the line's --ops, at most 4
 *      parameters and 24 nodes, enumeration to 5 nodes and 5,000 fits, then
 *      generations of 256, no seeds), at a budget of EVALS fits on THREADS
 *      threads, for seeds 1 .. SEEDS. With --file
 *      analysis/bench/unseen.txt, the unseen suite instead: forms drawn at
 *      random from the grammar by analysis/bench/unseen.py, which nobody chose
 *      or tuned the search on (issue 38's independent suite). Each form's line
 *      ends with its size in nodes (nodes_of), and the summary says whether
 *      every form the enumeration certifies (at most ENUM_SIZE nodes) was
 *      recovered at every seed;
 *   2. the rediscovery of the catalog (fit/catalog.c): every form (env: A and
 *      B apart) with its published constants written in as literals is the
 *      target, on the domain of its kind; forms the grammar cannot write
 *      (pow, exp, clamp, registry terms), of more than MAX_NODES nodes, of
 *      more than three inputs or reading no input are listed as skipped.
 *
 * A run has RECOVERED its form when some candidate it fitted (and so its
 * front, whose best error is the least of all) has screening rmse <= TOL x
 * max(1, rms of the target) — an absolute 1e-6 for the O(1) forms, relative
 * for large ones (a target of scale 1e3 carries 1e3 x the rounding of its
 * fit). The run stops at its first such fit (it could only stay recovered);
 * evaluations to recovery is that candidate's found_at.
 *
 * Printed: per form and seed, recovered (+) or not (-) with its fits to
 * recovery or its best rmse; the suite's recovery rate over all runs and the
 * share of forms recovered at every seed; the median fits to recovery; the
 * catalog's rediscovery rate. --quick runs the forms marked * at 2 seeds
 * (a minute on 2 cores), --only NAME,... chosen forms, --file SUITE another
 * suite than planted.txt (without the catalog), --starts N the
 * screening starts per candidate (the search's default otherwise), --dump
 * PREFIX every candidate a run fitted into PREFIX.NAME.SEED.tsv (rmse to 9
 * digits: equal values mark one model spelled twice), --beyond N each run
 * on to N fits: the budget's figures are the same (check() says why), and
 * a second line says how many runs N fits recover, so that a rate short of
 * its target is also read as the budget it would take.
 */
#include "brdf.h"
#include "brdf_ops.h" /* the opcodes of a tree (nodes_of) */
#include "catalog.h"
#include "clock.h"
#include "params.h"
#include "search.h"
#include "target.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define TOL 1e-6
#define ENUM_SIZE 5 /* every unique form up to this many nodes is fitted first */
#define MAX_NODES 24
#define MAX_FORMS 128

typedef struct planted {
	char name[64], domain[160], form[1024], ops[160];
	int quick;
} planted;

typedef struct opts {
	const char *file, *only, *dump;
	long evals;
	long beyond; /* 0, or run each search on to this many fits (--beyond) */
	int seeds, threads, quick, catalog, verbose, first;
	int starts; /* screening starts per candidate; 0: the search's default */
} opts;

static char *trim(char *s)
{
	while (isspace((unsigned char)*s))
		s++;
	size_t n = strlen(s);
	while (n && isspace((unsigned char)s[n - 1]))
		s[--n] = '\0';
	return s;
}

static int read_suite(const char *path, planted *p, int max)
{
	FILE *f = fopen(path, "r");
	if (!f) {
		fprintf(stderr, "bench_recovery: %s: cannot open\n", path);
		exit(1);
	}
	char line[2048];
	int n = 0;
	while (fgets(line, sizeof line, f) && n < max) {
		char *t = trim(line);
		if (!*t || *t == '#')
			continue;
		char *field[4] = {0};
		int k = 0;
		for (char *q = t; q && k < 4; k++) {
			field[k] = q;
			if ((q = strchr(q, '|')))
				*q++ = '\0';
		}
		if (k < 3) {
			fprintf(stderr, "bench_recovery: %s: expected NAME | DOMAIN | FORM, got '%s'\n", path, t);
			exit(1);
		}
		char *name = trim(field[0]);
		p[n].quick = *name == '*';
		snprintf(p[n].name, sizeof p[n].name, "%s", name + p[n].quick);
		snprintf(p[n].domain, sizeof p[n].domain, "%s", trim(field[1]));
		snprintf(p[n].form, sizeof p[n].form, "%s", trim(field[2]));
		snprintf(p[n].ops, sizeof p[n].ops, "%s", field[3] ? trim(field[3]) : "");
		n++;
	}
	fclose(f);
	return n;
}

typedef struct result {
	int recovered; /* within the budget (the fits a run at --evals makes) */
	int later;     /* past it, within --beyond */
	long found_at, evals;
	double best; /* the least rmse of the run (screening) */
	int nodes;   /* the form's size in the grammar, its literals made parameters (nodes_of) */
	char text[256];
} result;

/* The form's size as the search measures it (bk_expr_size of the canonical
 * tree over the target's inputs), each literal but 1 and -1 a free
 * parameter, as the search would have to write it: the size the
 * enumeration must reach to certify it. -1 when the tree cannot hold the
 * form. */
static int nodes_of(const char *text, unsigned inputs)
{
	bk_form_error fe;
	bk_form *f = bk_form_parse(text, &fe);
	bk_expr e;
	int ok = f && !bk_expr_from_form(f, &e);
	bk_form_free(f);
	if (!ok)
		return -1;
	for (int i = 0, np = 0; i < e.n; i++)
		if (e.node[i].op == BK_OP_CONST && fabs(e.node[i].k) != 1.0)
			e.node[i] = (bk_enode){BK_OP_PARAM, np++, 0};
	return bk_expr_canon_in(&e, inputs) ? -1 : bk_expr_size(&e);
}

typedef struct watch {
	size_t seen;
	double tol;
	long budget;  /* --evals */
	int past;     /* a step has ended at or past the budget */
	result *r;
} watch;

/* After every step: any new candidate within tolerance stops the run. A run
 * with a larger budget makes the same batches (whole generations; the
 * enumeration's cap is not a share of the budget: driver.c, generate.c;
 * tests/test_search.c's resume_equals_an_uninterrupted_run holds a run at a
 * budget to be the start of one at a larger), so the fits of the steps up to
 * the one that reaches --evals are the fits of a run at --evals, and a
 * recovery after it is --beyond's. */
static int check(void *ctx, const bk_search *s)
{
	watch *w = ctx;
	for (size_t n = bk_search_count(s); w->seen < n; w->seen++) {
		const bk_cand *c = bk_search_at(s, w->seen);
		if (c->status != BK_CAND_OK || !(c->rmse < w->r->best))
			continue;
		w->r->best = c->rmse;
		snprintf(w->r->text, sizeof w->r->text, "%s", c->text);
		if (c->rmse <= w->tol && !w->r->recovered && !w->r->later) {
			*(w->past ? &w->r->later : &w->r->recovered) = 1;
			w->r->found_at = c->found_at;
		}
	}
	w->past |= bk_search_evals(s) >= w->budget;
	return w->r->recovered || w->r->later;
}

/* the name of the form being run, for --dump's file names */
static const char *dump_name = "";

/* One search of form on domain as brdfkit search --target form makes it. */
static int run_one(const char *form, const char *domain, const char *ops, unsigned long seed, const opts *O,
                   result *r)
{
	memset(r, 0, sizeof *r);
	r->best = HUGE_VAL;
	bk_target_options to;
	bk_target_defaults(BK_TARGET_FORM, &to);
	to.form_text = form;
	char err[512];
	if (bk_params_domain(domain, 0, &to, err, sizeof err) || bk_target_form_check(&to, err, sizeof err)) {
		fprintf(stderr, "bench_recovery: %s on %s: bad form or domain\n", form, domain);
		return -1;
	}
	static const int per[5] = {0, 256, 32, 10, 6}; /* cmd_search.c's screening grid */
	to.nx = per[to.ndomain < 5 ? to.ndomain : 4];
	bk_samples sm;
	if (bk_target_build(&to, &sm, NULL, NULL, err, sizeof err)) {
		fprintf(stderr, "bench_recovery: %s: %s\n", form, err);
		return -1;
	}
	r->nodes = nodes_of(form, sm.provides);
	double ss = 0;
	for (size_t i = 0; i < sm.n; i++)
		ss += sm.y[i] * sm.y[i];
	watch w = {0, TOL * fmax(1.0, sqrt(ss / (double)sm.n)), O->evals, 0, r};
	bk_search_options o;
	bk_search_defaults(&o);
	o.screen = &sm;
	o.shape = BK_SHAPE_PLAIN;
	memset(&o.grammar, 0, sizeof o.grammar);
	o.grammar.ops = bk_grammar_default_ops();
	if (*ops && bk_grammar_parse_ops(ops, &o.grammar.ops, err, sizeof err)) {
		fprintf(stderr, "bench_recovery: --ops %s: %s\n", ops, err);
		bk_samples_free(&sm);
		return -1;
	}
	o.grammar.consts[0] = 1.0;
	o.grammar.nconsts = 1;
	o.grammar.max_params = 4;
	o.grammar.max_size = 24;
	o.grammar.inputs = sm.provides;
	o.evals = O->beyond > O->evals ? O->beyond : O->evals;
	o.seed = seed;
	o.threads = O->threads;
	o.enum_size = ENUM_SIZE;
	o.enum_max = 5000;
	o.generation = 256;
	if (O->starts > 0)
		o.starts = O->starts;
	bk_search *s = bk_search_new(&o, err, sizeof err);
	int rc = s ? bk_search_run(s, check, &w, err, sizeof err) : -1;
	if (rc < 0)
		fprintf(stderr, "bench_recovery: %s: %s\n", form, err);
	if (s)
		r->evals = bk_search_evals(s);
	if (s && O->dump) { /* every candidate fitted: found_at, status, rmse, text */
		char path[512];
		snprintf(path, sizeof path, "%s.%s.%lu.tsv", O->dump, dump_name, seed);
		FILE *f = fopen(path, "w");
		for (size_t i = 0; f && i < bk_search_count(s); i++) {
			const bk_cand *c = bk_search_at(s, i);
			fprintf(f, "%ld\t%d\t%.9g\t%.3g\t%s\n", c->found_at, (int)c->status, c->rmse, c->cost, c->text);
		}
		if (f)
			fclose(f);
	}
	bk_search_free(s);
	bk_samples_free(&sm);
	return rc < 0 ? -1 : 0;
}

static int listed(const char *only, const char *name)
{
	size_t n = strlen(name);
	for (const char *p = only; p && *p;) {
		const char *e = strchr(p, ',');
		size_t k = e ? (size_t)(e - p) : strlen(p);
		if (k == n && !strncmp(p, name, n))
			return 1;
		p = e ? e + 1 : NULL;
	}
	return 0;
}

/* What a suite's runs came to: at the budget, and at --beyond's (which
 * counts the budget's recoveries too). */
typedef struct tally {
	int runs, forms, rec, every, rec2, every2, nfits, nfits2;
	int small, small_every; /* forms of at most ENUM_SIZE nodes, and of them recovered at every seed */
	long fits[MAX_FORMS * 16], fits2[MAX_FORMS * 16]; /* fits to recovery */
} tally;

static int cmp_long(const void *a, const void *b)
{
	long x = *(const long *)a, y = *(const long *)b;
	return (x > y) - (x < y);
}

static long median(long *v, int n)
{
	qsort(v, (size_t)n, sizeof *v, cmp_long);
	return n ? v[n / 2] : -1L;
}

/* Runs one form at every seed and prints its line: +N recovered at fit N,
 * (+N) at fit N past the budget (--beyond), -E not (best rmse E). */
static void bench_form(const char *name, const char *form, const char *domain, const char *ops, const opts *O,
                       tally *t)
{
	int ok = 0, ok2 = 0, nodes = -1;
	dump_name = name;
	printf("  %-22s", name);
	double t0 = bk_clock_now();
	for (int k = O->first; k < O->first + O->seeds; k++) {
		result r;
		if (run_one(form, domain, ops, (unsigned long)k, O, &r))
			exit(1);
		t->runs++;
		nodes = r.nodes;
		if (r.recovered || r.later) {
			ok2++;
			t->rec2++;
			t->fits2[t->nfits2++] = r.found_at;
		}
		if (r.recovered) {
			ok++;
			t->rec++;
			t->fits[t->nfits++] = r.found_at;
			printf(" +%-7ld", r.found_at);
		} else if (r.later) {
			char b[24];
			snprintf(b, sizeof b, "(+%ld)", r.found_at);
			printf(" %-8s", b);
		} else {
			printf(" -%-7.2g", r.best);
		}
		if (O->verbose)
			printf(" [%s]", r.text);
		fflush(stdout);
	}
	t->forms++;
	t->every += ok == O->seeds;
	t->every2 += ok2 == O->seeds;
	if (nodes >= 1 && nodes <= ENUM_SIZE)
		t->small++, t->small_every += ok == O->seeds;
	printf("  %5.1fs %2dn  %s\n", bk_clock_now() - t0, nodes, form);
}

/* The --beyond line under a suite's summary, and the fit by which share of
 * the runs (0: not asked) were recovered: the budget that rate takes. */
static void print_beyond(const opts *O, tally *t, const char *what, double share)
{
	if (O->beyond <= O->evals)
		return;
	printf("  the same runs at %ld fits (--beyond): %d of %d runs (%.1f %%), %d of %d %s at every seed; "
	       "median fits to recovery %ld\n",
	       O->beyond, t->rec2, t->runs, t->runs ? 100.0 * t->rec2 / t->runs : 0.0, t->every2, t->forms, what,
	       median(t->fits2, t->nfits2));
	if (share <= 0)
		return;
	int need = (int)ceil(share * t->runs - 1e-9); /* runs, at least share of them */
	if (need < 1)
		return;
	qsort(t->fits2, (size_t)t->nfits2, sizeof *t->fits2, cmp_long);
	if (need <= t->nfits2)
		printf("  %.0f %% of the runs (%d) were recovered by fit %ld\n", 100 * share, need, t->fits2[need - 1]);
	else
		printf("  %.0f %% of the runs (%d) were not recovered by fit %ld\n", 100 * share, need, O->beyond);
}

/* The catalog form's text with its published constants written in. */
static void with_constants(const char *t, const double *p, int np, char *out, size_t len)
{
	size_t k = 0;
	for (size_t i = 0; t[i] && k + 40 < len; i++) {
		int tok = t[i] == 'p' && isdigit((unsigned char)t[i + 1]) && (i == 0 || !(isalnum((unsigned char)t[i - 1]) || t[i - 1] == '_'));
		if (tok) {
			int j = atoi(t + i + 1);
			while (isdigit((unsigned char)t[i + 1]))
				i++;
			k += (size_t)snprintf(out + k, len - k, "(%.17g)", j < np ? p[j] : NAN);
		} else {
			out[k++] = t[i];
		}
	}
	out[k] = '\0';
}

/* The domain of a catalog form by its kind: where it is finite and means
 * something (a in r; LoH from 0.3162 where V has its 1/LoH^2 pole, as vf2d's
 * default; D from r = 0.2, GGX a delta below). Empty when it is skipped (why). */
static int catalog_domain(const bk_catalog_entry *e, const char *text, char *dom, size_t len, const char **why)
{
	bk_form_error fe;
	bk_form *f = bk_form_parse(text, &fe);
	if (!f) {
		*why = "does not parse";
		return -1;
	}
	unsigned in = bk_form_inputs(f);
	bk_expr t;
	int tree = bk_expr_from_form(f, &t);
	bk_form_free(f);
	if (tree) {
		*why = "no search tree: past 64 nodes expanded, or an op a tree cannot hold";
		return -1;
	}
	/* the tree's operations, read off its text: a call the default grammar
	 * does not name (pow, exp, clamp, abs, a registry term) is not its */
	static const char *const allowed[] = {"sq", "sqrt", "rsqrt", "rcp", "exp2", "log2", "min", "max", "saturate", "mix"};
	char pt[8192];
	if (bk_expr_print(&t, pt, sizeof pt) < 0) {
		*why = "does not print";
		return -1;
	}
	for (char *q = pt; *q; q++) {
		if (!(isalpha((unsigned char)*q) || *q == '_') || (q > pt && (isalnum((unsigned char)q[-1]) || q[-1] == '_')))
			continue;
		size_t k = 0;
		while (isalnum((unsigned char)q[k]) || q[k] == '_')
			k++;
		if (q[k] != '(')
			continue;
		int ok = 0;
		for (size_t j = 0; j < sizeof allowed / sizeof *allowed; j++)
			ok |= strlen(allowed[j]) == k && !strncmp(allowed[j], q, k);
		if (!ok) {
			*why = "an operation the default grammar lacks (pow, exp, clamp, ...)";
			return -1;
		}
	}
	if (bk_expr_size(&t) > MAX_NODES) {
		*why = "more than 24 nodes";
		return -1;
	}
	if (in & 1u << BK_IN_A)
		in = (in & ~(1u << BK_IN_A)) | 1u << BK_IN_R;
	size_t k = 0;
	int n = 0;
	for (int i = 0; i < BK_IN_COUNT; i++) {
		if (!(in >> i & 1))
			continue;
		const char *lo = "0", *hi = "1";
		if (i == BK_IN_LOH && (e->target[0] == 'V' || e->target[0] == 'D'))
			lo = "0.3162";
		if ((i == BK_IN_NOV || i == BK_IN_NOL) && e->target[0] == 'V')
			lo = "0.1";
		if (i == BK_IN_R && e->target[0] == 'D')
			lo = "0.2";
		k += (size_t)snprintf(dom + k, len - k, "%s%s=%s:%s", n ? "," : "", bk_input_name((bk_input)i), lo, hi);
		n++;
	}
	if (n == 0) {
		*why = "reads no input";
		return -1;
	}
	if (n > 3) {
		*why = "more than three inputs";
		return -1;
	}
	return 0;
}

int main(int argc, char **argv)
{
	opts O = {.file = "analysis/bench/planted.txt", .evals = 20000, .seeds = 3, .threads = 2, .catalog = 1, .first = 1};
	for (int i = 1; i < argc; i++) {
		if (!strcmp(argv[i], "--quick"))
			O.quick = 1, O.seeds = 2, O.catalog = 0;
		else if (!strcmp(argv[i], "--only") && i + 1 < argc)
			O.only = argv[++i], O.catalog = 0;
		else if (!strcmp(argv[i], "--first-seed") && i + 1 < argc)
			O.first = atoi(argv[++i]);
		else if (!strcmp(argv[i], "--seeds") && i + 1 < argc)
			O.seeds = atoi(argv[++i]);
		else if (!strcmp(argv[i], "--evals") && i + 1 < argc)
			O.evals = atol(argv[++i]);
		else if (!strcmp(argv[i], "--beyond") && i + 1 < argc)
			O.beyond = atol(argv[++i]);
		else if (!strcmp(argv[i], "--threads") && i + 1 < argc)
			O.threads = atoi(argv[++i]);
		else if (!strcmp(argv[i], "--file") && i + 1 < argc)
			O.file = argv[++i], O.catalog = 0; /* another suite: that suite alone */
		else if (!strcmp(argv[i], "--catalog"))
			O.catalog = 2; /* the catalog alone */
		else if (!strcmp(argv[i], "--dump") && i + 1 < argc)
			O.dump = argv[++i];
		else if (!strcmp(argv[i], "--starts") && i + 1 < argc)
			O.starts = atoi(argv[++i]);
		else if (!strcmp(argv[i], "-v"))
			O.verbose = 1;
		else {
			fprintf(stderr, "usage: bench_recovery [--quick] [--only NAME,...] [--catalog] [--seeds N] [--first-seed K] "
			                "[--evals N] [--beyond N] [--threads N] [--starts N] [--file PLANTED] [--dump PREFIX] [-v]\n");
			return 2;
		}
	}
	/* a tally holds 16 runs a form */
	if (O.seeds < 1 || O.seeds > 16 || O.evals < 1 || (O.beyond && O.beyond <= O.evals)) {
		fprintf(stderr, "bench_recovery: --seeds %d (1 to 16), --evals %ld (>= 1), --beyond %ld (0 or more than "
		                "--evals)\n", O.seeds, O.evals, O.beyond);
		return 2;
	}
	static planted P[MAX_FORMS];
	static tally T, C; /* the planted suite, the catalog */
	int np = read_suite(O.file, P, MAX_FORMS);
	double t0 = bk_clock_now();
	if (O.catalog != 2) {
		printf("recovery of planted forms (%s): %ld fits, %d threads, seeds %d..%d; "
		       "+N recovered at fit N (rmse <= %g x max(1, rms target)), -E not (best rmse E); then the "
		       "seconds, the form's nodes (Nn) and the form\n",
		       O.file, O.evals, O.threads, O.first, O.first + O.seeds - 1, TOL);
		if (O.beyond > O.evals)
			printf("each run goes on to %ld fits (--beyond): (+N) recovered at fit N past the budget\n", O.beyond);
		for (int i = 0; i < np; i++) {
			if ((O.quick && !P[i].quick) || (O.only && !listed(O.only, P[i].name)))
				continue;
			bench_form(P[i].name, P[i].form, P[i].domain, P[i].ops, &O, &T);
		}
		printf("planted: %d of %d runs recovered (%.1f %%; target >= 98 %%), %d of %d forms at every seed; "
		       "median fits to recovery %ld; %.0f s\n",
		       T.rec, T.runs, T.runs ? 100.0 * T.rec / T.runs : 0.0, T.every, T.forms, median(T.fits, T.nfits),
		       bk_clock_now() - t0);
		printf("  forms of <= %d nodes (the enumeration's certificate): %d of %d at every seed (target: all)\n",
		       ENUM_SIZE, T.small_every, T.small);
		print_beyond(&O, &T, "forms", 0.95);
	}
	if (!O.catalog)
		return 0;
	printf("rediscovery of the catalog (every form of <= %d nodes in the default grammar, its published "
	       "constants as literals): seeds %d..%d\n", MAX_NODES, O.first,
	       O.first + O.seeds - 1);
	double t1 = bk_clock_now();
	for (size_t i = 0; i < bk_catalog_count(); i++) {
		const bk_catalog_entry *e = bk_catalog_at(i);
		for (int h = 0; h < (e->form_b ? 2 : 1); h++) {
			char text[4096], dom[256], name[80];
			const char *why = NULL;
			with_constants(h ? e->form_b : e->form, e->defaults, e->nparams, text, sizeof text);
			snprintf(name, sizeof name, "%s%s", e->name, e->form_b ? (h ? ".B" : ".A") : "");
			if (catalog_domain(e, text, dom, sizeof dom, &why)) {
				printf("  %-22s skipped: %s\n", name, why);
				continue;
			}
			bench_form(name, text, dom, "", &O, &C);
		}
	}
	printf("catalog: %d of %d forms rediscovered at every seed (%.1f %%; target >= 90 %%), %d of %d runs; %.0f s\n",
	       C.every, C.forms, C.forms ? 100.0 * C.every / C.forms : 0.0, C.rec, C.runs, bk_clock_now() - t1);
	print_beyond(&O, &C, "forms", 0);
	return 0;
}
