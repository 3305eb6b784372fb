/*
 * search_setup.c — brdfkit search's options into the search's (search_setup.h).
 */
#include "search_setup.h"

#include "catalog.h"
#include "form_check.h"
#include "islands.h"
#include "out.h"
#include "search/catalogmap.h"
#include "search/islands.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- option helpers ------------------------------------------------------- */

static int parse_word(const cli_cmd *cmd, const char *opt, const char *text, const char *const *names, int n,
                      int *out)
{
	for (int i = 0; i < n; i++)
		if (!strcmp(text, names[i])) {
			*out = i;
			return 0;
		}
	(void)cmd;
	return cli_unknown_value(opt, text, names, n);
}

/* A comma list of opt: no empty item (a stray comma is a typo, not a
 * request for nothing) and none twice (a list that names one twice was
 * meant to name another). 0, or 2 after a usage error. */
static int check_list(const cli_cmd *cmd, const char *opt, const char *text)
{
	for (const char *p = text;;) {
		const char *e = strchr(p, ',');
		size_t n = e ? (size_t)(e - p) : strlen(p);
		if (n == 0)
			return cli_usage(cmd, "%s: an empty item in '%.60s'", opt, text);
		for (const char *q = e ? e + 1 : NULL; q;) {
			const char *f = strchr(q, ',');
			size_t m = f ? (size_t)(f - q) : strlen(q);
			if (m == n && !strncmp(p, q, n))
				return cli_usage(cmd, "%s: '%.*s' given twice", opt, (int)(n > 40 ? 40 : n), p);
			q = f ? f + 1 : NULL;
		}
		if (!e)
			return 0;
		p = e + 1;
	}
}

/* --inputs NoV,r,...: bits of bk_input */
static int parse_inputs(const cli_cmd *cmd, const char *text, unsigned provides, unsigned *bits)
{
	char buf[256];
	if (check_list(cmd, "--inputs", text))
		return 2;
	if (strlen(text) >= sizeof buf)
		return cli_usage(cmd, "--inputs: longer than the %zu characters of every input named once", sizeof buf - 1);
	snprintf(buf, sizeof buf, "%s", text);
	*bits = 0;
	char *save = NULL;
	for (char *t = strtok_r(buf, ",", &save); t; t = strtok_r(NULL, ",", &save)) {
		int in = -1;
		for (int k = 0; k < BK_IN_COUNT; k++)
			if (!strcmp(t, bk_input_name((bk_input)k)))
				in = k;
		if (in < 0)
			return cli_usage(cmd, "--inputs: '%s' is not an input (NoV, NoL, NoH, LoH, r, a, f0)", t);
		if (!(provides >> in & 1))
			return cli_usage(cmd, "--inputs: the target does not provide %s", t);
		*bits |= 1u << in;
	}
	return *bits ? 0 : cli_usage(cmd, "--inputs: empty list");
}

/* --cost-weights simple=1,complex=4 */
static int parse_weights(const cli_cmd *cmd, const char *text, double *simple, double *complex)
{
	char buf[128];
	if (check_list(cmd, "--cost-weights", text))
		return 2;
	snprintf(buf, sizeof buf, "%s", text);
	char *save = NULL;
	int given[2] = {0, 0};
	for (char *t = strtok_r(buf, ",", &save); t; t = strtok_r(NULL, ",", &save)) {
		char *eq = strchr(t, '=');
		double v;
		if (!eq || cli_number(eq + 1, &v) || !(v >= 0))
			return cli_usage(cmd, "--cost-weights: expected simple=W,complex=W with W >= 0, got '%s'", t);
		*eq = '\0';
		int k = !strcmp(t, "simple") ? 0 : !strcmp(t, "complex") ? 1 : -1;
		if (k < 0)
			return cli_usage(cmd, "--cost-weights: '%s' is not simple or complex", t);
		if (given[k]++)
			return cli_usage(cmd, "--cost-weights: %s given twice", t);
		*(k ? complex : simple) = v;
	}
	return *simple + *complex > 0 ? 0 : cli_usage(cmd, "--cost-weights: both weights are 0");
}

/* --env-form f0: env candidates are one form in f0 (Pesce-Iwanicki's,
 * Narkowicz's kind), not a split pair. */
int search_env_in_f0(const job *J)
{
	return J->kind == BK_TARGET_ENV && J->a->env_form && (!strcmp(J->a->env_form, "f0") || !strcmp(J->a->env_form, "mix"));
}

/* --env-form mix: the same forms in f0, seeded also with mix(B, S, f0) of
 * the fronts of two searches run first, one of S = A + B (f0 = 1) and one
 * of B (f0 = 0) (halves below). */
int search_env_halves(const job *J)
{
	return J->kind == BK_TARGET_ENV && J->a->env_form && !strcmp(J->a->env_form, "mix");
}

/* ---- set-up ----------------------------------------------------------------- */

/* bk_search_split's share over the ranks (islands.h, isl_share). */
static int share_fits(void *ctx, void *rec, size_t recsize, size_t n)
{
	(void)ctx;
	return isl_share(rec, recsize, n);
}

int search_setup(job *J)
{
	search_cli *a = J->a;
	const cli_cmd *cmd = J->cmd;
	bk_search_options *so = &J->so;
	bk_search_defaults(so);
	/* islands: --evals is the budget of the whole run, shared out; island 0
	 * keeps --seed, so one rank is the run brdfkit makes */
	int K = isl_size(), R = isl_rank();
	/* --split-fits: every rank runs the one search and fits its share of
	 * each step (fit/search.h, bk_search_split); the islands' options are
	 * refused there (the table below, decided from argv alike on every rank) */
	J->islands = K > 1 && !a->split_fits;
	if (!J->islands) {
		K = 1;
		R = 0;
		J->split = (bk_search_split){isl_rank(), isl_size(), share_fits, NULL};
		so->split = &J->split;
	}
	if (a->evals < K) /* decided alike on every rank: no rank may leave alone */
		return cli_usage(cmd, "--evals %ld: fewer fits than the %d islands", a->evals, K);
	so->islands = K;
	so->island = R;
	so->evals = a->evals / K + (R < a->evals % K);
	/* and so is the enumeration's cap: the islands together fit the trees one
	 * process would, each its share, and the mix of enumerated and evolved
	 * fits stays that of one process at the same total budget */
	so->enum_max = a->enum_max / K + (R < a->enum_max % K);
	so->seed = R == 0 ? (unsigned long)a->seed : bk_islands_seed((unsigned long)a->seed, R);
	so->threads = (int)a->threads;
	so->enum_size = (int)a->enum_size;
	so->generation = (int)a->generation;
	so->relative = a->relative;
	so->max_cost = a->max_cost > 0 ? a->max_cost : HUGE_VAL;
	int v = 0;
	static const char *const objs[] = {"rmse", "max", "albedo"};
	if (parse_word(cmd, "--objective", a->objective, objs, 3, &v))
		return 2;
	so->objective = (bk_objective)v;
	static const bk_precision pv[] = {BK_F64, BK_F32, BK_F16}; /* by cli_prec */
	cli_prec prec;
	if (cli_precision(a->precision, CLI_PREC_BIT(CLI_PREC_DOUBLE) | CLI_PREC_BIT(CLI_PREC_SINGLE) | CLI_PREC_BIT(CLI_PREC_HALF),
	                  &prec))
		return 2;
	so->precision = pv[prec];
	if (a->weights && parse_weights(cmd, a->weights, &so->simple_cost, &so->complex_cost))
		return 2;
	if (a->cost_model && cli_cost_model(cmd, a->cost_model, &so->simple_cost, &so->complex_cost))
		return 2;
	if (a->gpu) {
		char gerr[700];
		if (check_list(cmd, "--gpu", a->gpu))
			return 2;
		snprintf(J->chipbuf, sizeof J->chipbuf, "%s", a->gpu);
		if (bk_gpucost_chips(J->chipbuf, J->chip, BK_GPUCOST_MAX_CHIPS, &J->nchips, gerr, sizeof gerr))
			return cli_usage(cmd, "--gpu: %s", gerr);
	}
	bk_grammar *g = &so->grammar;
	bk_seeds_grammar(g, J->kind);
	char err[256];
	if (a->ops && bk_grammar_parse_ops(a->ops, &g->ops, err, sizeof err))
		return cli_usage(cmd, "--ops: %s", err);
	if (a->max_params >= 0)
		g->max_params = (int)a->max_params;
	g->max_size = (int)a->max_size;
	switch (J->kind) {
	case BK_TARGET_VF2D:
	case BK_TARGET_VF:
	case BK_TARGET_SPEC: so->shape = BK_SHAPE_F0; break;
	case BK_TARGET_ENV: so->shape = BK_SHAPE_PAIR; break;
	default: so->shape = BK_SHAPE_PLAIN; break;
	}
	if (search_env_halves(J) && K > 1) /* --checkpoint and --resume: the table */
		return cli_usage(cmd, "--env-form mix runs three searches in turn: no islands with it");
	if (search_env_halves(J) && so->max_cost <= 3)
		return cli_usage(cmd, "--env-form mix: --max-cost %g leaves nothing to the halves (mix(B, S, f0) costs 2 itself)",
		                 so->max_cost);
	if (search_env_halves(J) && a->evals < 8 * (long)so->generation)
		return cli_usage(cmd, "--env-form mix: --evals %ld is too few to share among three searches (at least %d)",
		                 a->evals, 8 * so->generation);
	if (search_env_in_f0(J)) { /* one tree in f0, NoV, r scored on f0 A + B over the f0 list, as compare scores */
		so->shape = BK_SHAPE_PLAIN;
		J->to.env_f0_form = 1;
	}
	/* constraints that hold for the target: on unless --no-constraints */
	so->inherit = a->inherit;
	so->nonneg = !a->no_constraints && J->kind != BK_TARGET_FORM;
	so->env_bound = !a->no_constraints && J->kind == BK_TARGET_ENV && !search_env_in_f0(J);
	return 0;
}

/* The inputs a candidate may read: --inputs, or what the target provides
 * (f0 is the shape's own factor for the F0 shape; a with r: both, the
 * convention gives shaders both). */
int search_setup_inputs(job *J)
{
	unsigned prov = J->screen.provides;
	if (J->a->inputs)
		return parse_inputs(J->cmd, J->a->inputs, prov, &J->so.grammar.inputs);
	if (J->so.shape == BK_SHAPE_F0)
		prov &= ~(1u << BK_IN_F0);
	J->so.grammar.inputs = prov;
	return 0;
}

/* Samples of s where seed k of sd, at its start constants, is NaN or
 * infinite and the target is not (where: the first); s->n if it does not
 * evaluate. */
static size_t seed_nonfinite(const bk_seeds *sd, int k, const bk_samples *s, char *where, size_t len)
{
	const bk_form *f[2] = {sd->form[k], sd->form_b[k]}; /* parsed once, as the seed was added */
	if (!f[0] || (sd->text_b[k] && !f[1])) {
		snprintf(where, len, "no sample: the form does not compile");
		return s->n;
	}
	bk_fit_spec sp;
	memset(&sp, 0, sizeof sp);
	sp.s = s;
	sp.form[0] = f[0];
	sp.form[1] = f[1] ? f[1] : f[0];
	return bk_fit_nonfinite(&sp, sd->p[k], where, len);
}

/* A --start form that is NaN or infinite on the samples s at its start is
 * refused, as fit refuses it: its error over the samples where it is finite
 * would be no error of the form. (The catalog's own forms, seeded when no
 * --start is given, are scored whatever they are: catalog rows say "not
 * finite".) Returns 0, or 1 after the message. */
int search_check_starts(const job *J, const bk_seeds *sd, const bk_samples *s)
{
	char where[256];
	for (int k = 0; k < J->a->nstart && k < sd->n; k++) { /* --start's, not --start-front's */
		size_t bad = seed_nonfinite(sd, k, s, where, sizeof where);
		if (bad)
			return cli_fail("search", "--start '%.60s': the form is NaN or infinite at %zu of %zu samples where "
			                "the target is finite (first at %s): fix the form or the domain", J->a->start[k], bad,
			                s->n, where);
	}
	return 0;
}

/* Where a form of a front read back is not fit for this run: an input the
 * target does not provide, a shape it does not take, NaN or infinite on the
 * screening samples at its constants; NULL when it is fit. */
static const char *front_row_unfit(const job *J, const bk_frontcsv_row *w, char *why, size_t len)
{
	int pair = J->kind == BK_TARGET_ENV && !search_env_in_f0(J);
	if (pair != (w->form_b != NULL))
		return pair ? "target env searches split pairs: form_b is empty" :
		              "form_b is given but this search takes one form";
	const bk_form *f[2] = {w->f, w->f_b}; /* parsed as the file was read */
	const char *msg = NULL;
	if (!f[0] || (w->form_b && !f[1]))
		msg = "the form does not compile";
	else if ((bk_form_inputs(f[0]) | (f[1] ? bk_form_inputs(f[1]) : 0)) & ~J->screen.provides)
		msg = "the form reads an input the target does not provide";
	else {
		bk_fit_spec sp;
		memset(&sp, 0, sizeof sp);
		sp.s = &J->screen;
		sp.form[0] = f[0];
		sp.form[1] = f[1] ? f[1] : f[0];
		char where[200];
		size_t bad = bk_fit_nonfinite(&sp, w->p, where, sizeof where);
		if (bad) {
			snprintf(why, len, "NaN or infinite at %zu of %zu screening samples (first at %s)", bad, J->screen.n,
			         where);
			msg = why;
		}
	}
	return msg;
}

/* --start-front FILE and --start-forms FILE (each time given): every member
 * of a front.csv (columns by name, frontcsv.h) as a seed at its constants,
 * after the published seeds; one whose texts are a seed's already is that
 * seed (a form on two fronts, or on a front and in the catalog, is fitted
 * once). A front's member is written under the run's own names
 * (search_front.c), so its name only has to differ from the published
 * seeds' (which keep theirs: the constraints exempt them by name).
 * --start-front takes a front of this target and domain, and a member that
 * does not fit it is an error; --start-forms takes the forms of any
 * target's front (vf2d's for vf: the talk's V x F in LoH and r is vf's too),
 * its '# target:' line unread, and leaves out the members that do not fit
 * this one (an input it lacks, another shape, NaN on its samples), counted;
 * none fitting is an error. 0, or 1 after the message. */
static int add_front_seeds(job *J, bk_seeds *sd, const char *opt, const char *path, bk_frontcsv *fc, int same)
{
	char err[700];
	int before = sd->n, left = 0, first_left = -1;
	char first_why[300] = "";
	/* a seed is a start: the objective and precision it was searched with
	 * may differ (a double front seeds a half search and back); with
	 * --start-front the target and its domain may not (its forms would
	 * answer another question) */
	if (bk_frontcsv_read(path, BK_FRONTCSV_FORMS, fc, err, sizeof err) ||
	    bk_frontcsv_head_check(&fc->head, path, BK_FRONTCSV_FRONT, "this search's",
	                           same ? J->screen.description : NULL, 0, NULL, NULL, err, sizeof err))
		return cli_fail("search", "%s %s", opt, err);
	for (int r = 0; r < fc->n; r++) {
		const bk_frontcsv_row *w = &fc->row[r];
		char why[300];
		const char *msg = front_row_unfit(J, w, why, sizeof why);
		if (msg && same)
			return cli_fail("search", "%s %s:%d: %.60s: %s", opt, path, w->line, w->name, msg);
		if (msg) {
			if (left++ == 0) {
				first_left = r;
				snprintf(first_why, sizeof first_why, "%s", msg);
			}
			continue;
		}
		int dup = 0;
		char slug[80], other[80];
		bk_slug(w->name, slug, sizeof slug);
		for (int k = 0; k < sd->n && !dup; k++)
			dup = !strcmp(sd->text[k], w->form) && !sd->text_b[k] == !w->form_b &&
			      (!w->form_b || !strcmp(sd->text_b[k], w->form_b));
		for (int q = 0; q < r; q++) { /* a file's names are its members' (FILE.csv:NAME): one each */
			bk_slug(fc->row[q].name, other, sizeof other);
			if (!strcmp(slug, other))
				return cli_fail("search", "%s %s:%d: the name '%.60s' is on line %d already", opt, path, w->line,
				                w->name, fc->row[q].line);
		}
		for (int k = 0; k < J->ncatalog && !dup; k++) {
			if (!sd->name[k])
				continue;
			bk_slug(sd->name[k], other, sizeof other);
			if (!strcmp(slug, other))
				return cli_fail("search", "%s %s:%d: the name '%.60s' is a published seed's", opt, path, w->line,
				                w->name);
		}
		if (dup)
			continue;
		if (bk_seeds_add_forms(sd, w->form, w->form_b, w->name, w->p, w->f, w->f_b))
			return cli_fail("search", "%s %s: more than %d seeds with the %d published ones", opt, path, MAX_SEEDS,
			                J->ncatalog);
		sd->from_front[sd->n - 1] = 1;
	}
	if (left && left == fc->n)
		return cli_fail("search", "%s %s: none of its %d members fits target %s (line %d, %.60s: %s)", opt, path,
		                fc->n, bk_target_name(J->kind), fc->row[first_left].line, fc->row[first_left].name,
		                first_why);
	fprintf(stderr, "search: %s %s: %d members, %d new seeds beside the %d before", opt, path, fc->n,
	        sd->n - before, before);
	if (left)
		fprintf(stderr, ", %d left out as not fitting target %s (the first, line %d, %.60s: %s)", left,
		        bk_target_name(J->kind), fc->row[first_left].line, fc->row[first_left].name, first_why);
	fputc('\n', stderr);
	return 0;
}

int search_setup_seeds(job *J, bk_seeds *sd)
{
	const char *tag = bk_catmap_tag(J->kind);
	if (J->a->nstart == 0 && bk_seeds_catalog(sd, J->kind, search_env_in_f0(J), J->screen.provides))
		return cli_fail("search", "out of memory");
	for (int k = 0; k < J->a->nstart; k++) {
		for (int j = 0; j < k; j++)
			if (!strcmp(J->a->start[j], J->a->start[k]))
				return cli_usage(J->cmd, "--start '%.60s' given twice", J->a->start[k]);
		const bk_catalog_entry *e = bk_catalog_find(J->a->start[k]);
		if (e && tag && strcmp(e->target, tag) && !(search_env_in_f0(J) && !strcmp(e->target, "env_f0")))
			return cli_usage(J->cmd, "--start %s: a %s form, not one of target %s", e->name, e->target,
			                 bk_target_name(J->kind));
		if (e && e->form_b && search_env_in_f0(J))
			return cli_usage(J->cmd, "--start %s: a split pair; with --env-form f0 write it as 'f0*(A) + (B)'",
			                 e->name);
		if (!e && J->kind == BK_TARGET_ENV && !search_env_in_f0(J))
			return cli_usage(J->cmd, "--start '%s': target env takes catalog names (A and B)", J->a->start[k]);
		if (e && !bk_catmap_reads_only(e, J->screen.provides))
			return cli_usage(J->cmd, "--start %s reads an input target %s does not provide", e->name,
			                 bk_target_name(J->kind));
		bk_form_error fe;
		bk_form *f = e ? NULL : bk_form_parse(J->a->start[k], &fe);
		if (!e && !f) {
			fprintf(stderr, "brdfkit search: --start:1:%d: %s\n", fe.column, fe.message);
			return 2;
		}
		int missing, top = f ? form_gap(bk_form_params(f), &missing) : -1;
		if (top >= 0) { /* as every command takes parameters (form_check.h) */
			bk_form_free(f);
			return cli_usage(J->cmd, "--start '%s' uses p%d but not p%d: number the parameters from p0, without a "
			                 "gap", J->a->start[k], top, missing);
		}
		if (f && (bk_form_inputs(f) & ~J->screen.provides)) {
			bk_form_free(f);
			return cli_usage(J->cmd, "--start '%s' reads an input target %s does not provide", J->a->start[k],
			                 bk_target_name(J->kind));
		}
		/* at most MAX_SEEDS: --start's repeat; a typed form goes in as parsed here */
		if (e)
			bk_seeds_add(sd, e->form, e->form_b, e->name, e->defaults);
		else
			bk_seeds_add_forms(sd, J->a->start[k], NULL, NULL, NULL, f, NULL);
		bk_form_free(f);
	}
	int rc = search_check_starts(J, sd, &J->screen);
	J->ncatalog = sd->n;
	for (int i = 0; !rc && i < J->a->nstart_front; i++)
		rc = add_front_seeds(J, sd, "--start-front", J->a->start_front[i], &J->start_fc[i], 1);
	for (int i = 0; !rc && i < J->a->nstart_forms; i++)
		rc = add_front_seeds(J, sd, "--start-forms", J->a->start_forms[i], &J->forms_fc[i], 0);
	bk_seeds_apply(sd, &J->so);
	/* the published seeds alone are kept whatever the constraints say (a
	 * front's members are starts like any other) */
	J->so.exempt_seeds = J->ncatalog;
	return rc;
}

/* ---- where the options act (cli.h) ----------------------------------------- */

/* The target kind; the env candidates (one form for the other targets; env:
 * split pairs A, B, or one form in f0, or mix: that seeded by two searches run
 * first); whether --checkpoint is given; whether anything is enumerated;
 * whether --cost-model names the weights; one process, the islands of an MPI
 * job or its ranks splitting one search (mpirun alone reaches those two: no
 * setup of the walk can). */
enum { DIM_TARGET, DIM_CANDS, DIM_CHECKPOINT, DIM_ENUM, DIM_MODEL, DIM_PROCS };
enum { CANDS_ONE, CANDS_PAIR, CANDS_F0, CANDS_MIX };
static const cli_dim dims[] = {
	FITARGS_TARGET_DIM,
	{"candidates", {"one", "pair", "f0", "mix"}, {NULL, " on env split pairs", " with --env-form f0", " with --env-form mix"}},
	{"checkpoint", {"none", "file"}, {" without --checkpoint FILE", NULL}},
	{"enumeration", {"none", "some"}, {" with --enum-size 0", NULL}},
	{"weights", {"given", "model"}, {NULL, " with --cost-model"}},
	{"processes", {"one", "islands", "split"}, {" on one process", cli_unreached, cli_unreached}},
};
#define EVERYWHERE(opt, example) {opt, NULL, CLI_EVERYWHERE, 0, NULL, example}
#define CANDS_ON(c) (1u << CANDS_##c)
static const cli_rule rules[] = {
	{"--nu", NULL, DIM_TARGET, FITARGS_ON(VF) | FITARGS_ON(SPEC), "it sets the half-vector cells of targets vf and spec", "4"},
	{"--nphi", NULL, DIM_TARGET, FITARGS_ON(VF) | FITARGS_ON(SPEC), "it sets the azimuth cells of targets vf and spec", "4"},
	{"--smith", NULL, DIM_TARGET, FITARGS_ON(ENV) | FITARGS_ON(MS), "it sets the Smith model of targets env and ms", "schlick"},
	{"--ior", NULL, DIM_TARGET, FITARGS_ON(F), "it sets the exact Fresnel of target f", "1.4"},
	{"--k", NULL, DIM_TARGET, FITARGS_ON(F), "it sets the exact Fresnel of target f", "3"},
	{"--f0", NULL, DIM_TARGET, FITARGS_ON(VF2D) | FITARGS_ON(VF) | FITARGS_ON(SPEC) | FITARGS_ON(ENV),
	 "it sets f0 of targets vf2d, vf and spec, and env's f0 list with --env-form f0", "0.5"},
	{"--f0", NULL, DIM_CANDS, CANDS_ON(ONE) | CANDS_ON(F0) | CANDS_ON(MIX),
	 "their A and B hold no f0: give --env-form f0", "0.5"},
	{"--target-form", NULL, DIM_TARGET, FITARGS_ON(FORM), "it gives the expression of target form", "LoH"},
	{"--domain", NULL, DIM_TARGET, FITARGS_ON(FORM), "it gives the domain of target form", "LoH=0:1"},
	FITARGS_FILE_RULES(DIM_TARGET),
	{"--r-range", NULL, DIM_TARGET, FITARGS_ALL & ~(FITARGS_ON(FORM) | FITARGS_ON(F)),
	 "the target has no roughness axis or takes --domain", "0:0.5"},
	{"--nr", NULL, DIM_TARGET, FITARGS_ALL & ~FITARGS_ON(F), "target f has no roughness axis", "8"},
	{"--nr", NULL, DIM_TARGET, FITARGS_ALL & ~FITARGS_ON(FORM),
	 "--domain sets the inputs of target form; --nx the cells per axis", "8"},
	{"--env-form", NULL, DIM_TARGET, FITARGS_ON(ENV), "it sets the form of the candidates of target env", "f0"},
	{"--no-constraints", NULL, DIM_TARGET, FITARGS_ALL & ~FITARGS_ON(FORM), "target form has no constraints to lift", NULL},
	{"--x-range", NULL, DIM_TARGET, FITARGS_ALL & ~FITARGS_ON(FORM), "--domain sets the inputs of target form", "0:0.5"},
	{"--fetch-cost", NULL, DIM_TARGET, FITARGS_ON(ENV), "LUT rows exist for target env only", "16"},
	{"--objective", "albedo", DIM_TARGET, FITARGS_ON(VF) | FITARGS_ON(SPEC),
	 "only targets vf and spec have a directional albedo", NULL},
	/* mix runs three searches in turn: none is checkpointed */
	{"--checkpoint", NULL, DIM_CANDS, ~CANDS_ON(MIX) & 0xfu, "mix runs three searches in turn, none checkpointed",
	 "ck"},
	{"--resume", NULL, DIM_CANDS, ~CANDS_ON(MIX) & 0xfu, "mix runs three searches in turn, none checkpointed", "ck"},
	{"--every", NULL, DIM_CHECKPOINT, 1u << 1, "it sets the fits between checkpoints", "100"},
	{"--enum-max", NULL, DIM_ENUM, 1u << 1, "nothing is enumerated", "5"},
	{"--cost-weights", NULL, DIM_MODEL, 1u << 0, "it sets both weights", "simple=1,complex=2"},
#define ISLANDS "it sets the islands of an MPI job: mpirun -np K brdfkit-mpi search ..."
	{"--migrate", NULL, DIM_PROCS, 1u << 1, ISLANDS, "500"},
	{"--merge-fronts", NULL, DIM_PROCS, 1u << 1, ISLANDS, NULL},
	{"--migrants", NULL, DIM_PROCS, 1u << 1, ISLANDS, "3"},
	{"--split-fits", NULL, DIM_PROCS, 1u << 2,
	 "it has the ranks of an MPI job split one search's fits: mpirun -np K brdfkit-mpi search ...", NULL},
#undef ISLANDS
	EVERYWHERE("--target", NULL),
	EVERYWHERE("--out", NULL),
	EVERYWHERE("--nx", "8"),
	EVERYWHERE("--evals", "100"),
	EVERYWHERE("--seconds", "5"),
	EVERYWHERE("--seed", "7"),
	EVERYWHERE("--threads", "2"),
	EVERYWHERE("--inputs", NULL), /* which inputs exist is the target's: checked with the screening samples */
	EVERYWHERE("--ops", "+,*"),
	EVERYWHERE("--max-cost", "20"),
	EVERYWHERE("--max-params", "3"),
	EVERYWHERE("--max-size", "12"),
	EVERYWHERE("--enum-size", "3"),
	EVERYWHERE("--generation", "64"),
	EVERYWHERE("--objective", "max"),
	EVERYWHERE("--relative", NULL),
	EVERYWHERE("--precision", "half"),
	EVERYWHERE("--gpu", NULL), /* its chips are checked against the driver when the run starts */
	EVERYWHERE("--cost-model", "ir"),
	EVERYWHERE("--start", NULL), /* a start is checked against the target's inputs */
	EVERYWHERE("--start-front", NULL), /* its members are checked against the target's inputs and shape */
	EVERYWHERE("--start-forms", NULL), /* those that do not fit the target are left out */
	EVERYWHERE("--vs-front", NULL),    /* with --precision half: checked in search_main */
	EVERYWHERE("--inherit", NULL),
	EVERYWHERE("--link-prefix", "x/"),
};
#undef EVERYWHERE
static const char *const setups[] = {
	"--target vf2d --out o",
	"--target vf --out o",
	"--target spec --out o",
	"--target env --out o",
	"--target d --out o",
	"--target f --out o",
	"--target form --target-form LoH --domain LoH=0:1 --out o",
	"--target ms --out o",
	"--target sheen --out o",
	"--target table --target-file t.csv --out o",
	"--target merl --target-file t.binary --out o",
	"--target env --env-form f0 --out o",
	"--target env --env-form mix --out o",
	"--target f --checkpoint ck --out o",
	"--target f --enum-size 0 --out o",
	"--target f --cost-model ir --out o",
	NULL};
const cli_table search_table = {dims, 6, rules, sizeof rules / sizeof rules[0], setups};

/* The run's context (the table's dimensions), then cli_applicable. */
int search_check_applicable(const job *J)
{
	const search_cli *a = J->a;
	int cands = J->kind != BK_TARGET_ENV ? CANDS_ONE : search_env_halves(J) ? CANDS_MIX : search_env_in_f0(J) ? CANDS_F0 : CANDS_PAIR;
	int ctx[] = {(int)J->kind, cands, a->checkpoint != NULL, a->enum_size > 0, a->cost_model != NULL,
	             isl_size() == 1 ? 0 : a->split_fits ? 2 : 1};
	return cli_applicable(J->cmd, ctx);
}
