/*
 * cmd_fit.c — brdfkit fit: a form (or a split-sum pair) fitted to a target,
 * with coefficient and metric tables, error heatmaps and shaders written into
 * one directory, whole or not at all.
 */
#include "brdf.h"
#include "catalog.h"
#include "cli.h"
#include "out.h"
#include "cmd.h"
#include "fit.h"
#include "fit_out.h"
#include "fitargs.h"
#include "tabtarget.h"
#include "form_check.h"
#include "member.h"
#include "params.h"
#include "heatmap.h"
#include "lutcache.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>


/* --bound's LO:HI: any two numbers with LO < HI (a bound is not sampled: no
 * least width; --hold is the way to keep a parameter fixed). */
static int bound_range(const char *text, double *lo, double *hi)
{
	const char *colon = strchr(text, ':');
	char lo_text[64] = "";
	if (colon && (size_t)(colon - text) < sizeof lo_text)
		memcpy(lo_text, text, (size_t)(colon - text));
	if (!colon || cli_number(lo_text, lo) || cli_number(colon + 1, hi) || !(*lo < *hi))
		return cli_bad("--bound: expected LO:HI with LO < HI, got '%s'", text);
	return 0;
}

/* "pN" with N a plain decimal in [0, BK_MAX_PARAMS): N, else -1 (the one
 * spelling, params.h). */
static int param_index(const char *t)
{
	return bk_param_index(t, strlen(t));
}

/* --bound p0=lo:hi[,p1=lo:hi...]; a parameter bounded twice is refused, as
 * the list's empty or repeated items are (cli_words). */
static int bounds(const cli_cmd *cmd, const char *text, double *lower, double *upper)
{
	const char *items[BK_MAX_PARAMS];
	int n = cli_words(cmd, "--bound", text, items, BK_MAX_PARAMS), seen[BK_MAX_PARAMS] = {0};
	for (int k = 0; k < n; k++) {
		char name[8] = "";
		const char *eq = strchr(items[k], '=');
		if (eq && (size_t)(eq - items[k]) < sizeof name)
			memcpy(name, items[k], (size_t)(eq - items[k]));
		int j = param_index(name);
		if (j < 0) {
			return cli_bad("--bound: expected pN=LO:HI, got '%s'", items[k]);
		}
		if (seen[j]++)
			return cli_usage(cmd, "--bound: p%d given twice in the list '%.200s'", j, text);
		if (bound_range(eq + 1, &lower[j], &upper[j]))
			return 2;
	}
	return n < 0 ? 2 : 0;
}

static int parse_form(const char *what, const char *text, bk_form **f)
{
	bk_form_error e;
	*f = bk_form_parse(text, &e);
	if (!*f) {
		fprintf(stderr, "brdfkit fit: %s:1:%d: %s\n", what, e.column, e.message);
		return 2;
	}
	return 0;
}

/* Which forms, and their published constants when they come from the catalog. */
typedef struct forms {
	bk_form *f[2];
	const char *text[2];
	const bk_catalog_entry *entry;
	int split;
	int member;  /* --form FILE.csv:NAME: m holds the texts and the starting values */
	cli_member m;
} forms;

/* The form in the report's first line: a catalog or member name, else "form". */
static const char *form_label(const forms *fs)
{
	return fs->entry ? fs->entry->name : fs->member ? fs->m.name : "form";
}

static int load_forms(const fitargs *a, bk_target_kind kind, forms *fs)
{
	memset(fs, 0, sizeof *fs);
	if (!!a->form == !!(a->form_a || a->form_b) || (!a->form && !(a->form_a && a->form_b))) {
		return cli_bad("give --form FORM|NAME, or --form-a and --form-b");
	}
	if (a->form && cli_member_split(a->form)) { /* a front member (member.h): its fitted values start the fit */
		int rc = cli_member_load(a->form, 1, &fs->m);
		if (rc)
			return rc;
		fs->member = 1;
		fs->text[0] = fs->m.form;
		fs->text[1] = fs->m.form_b;
	} else if (a->form && (fs->entry = bk_catalog_find(a->form))) {
		fs->text[0] = fs->entry->form;
		fs->text[1] = fs->entry->form_b;
	} else if (a->form) {
		fs->text[0] = a->form;
	} else {
		fs->text[0] = a->form_a;
		fs->text[1] = a->form_b;
	}
	fs->split = fs->text[1] != NULL;
	if (fs->split && kind != BK_TARGET_ENV) {
		return cli_bad("two forms (A and B) fit only the env target");
	}
	if (fs->member) { /* parsed as the file was read */
		fs->f[0] = fs->m.f, fs->f[1] = fs->m.f_b;
		fs->m.f = fs->m.f_b = NULL;
		return 0;
	}
	if (parse_form(fs->split ? "form-a" : "form", fs->text[0], &fs->f[0]))
		return 2;
	if (fs->split && parse_form("form-b", fs->text[1], &fs->f[1])) {
		bk_form_free(fs->f[0]);
		return 2;
	}
	return 0;
}

static int parse_enum(const char *opt, const char *text, const char *const *names, int n, int *out)
{
	for (int i = 0; i < n; i++)
		if (!strcmp(text, names[i])) {
			*out = i;
			return 0;
		}
	return cli_unknown_value(opt, text, names, n);
}

/* ---- outputs ------------------------------------------------------------ */

typedef struct run {
	const fitargs *a;
	forms fs;
	bk_target_options to;
	bk_samples s;
	bk_samples table; /* table, merl: as read from the file, until the build copies it */
	bk_fit_spec spec;
	bk_fit_result res;
	int has_published;
	const cli_cmd *cmd;
	char command[2048];
} run;

/* The view of a run that fit_out.c writes. */
static fitout_run view(const run *R)
{
	const bk_catalog_entry *e = R->fs.entry;
	const cli_member *m = R->fs.member ? &R->fs.m : NULL;
	fitout_run v = {R->command, &R->to, R->a->domain, &R->s, &R->spec, &R->res,
	             e ? e->name : m ? m->name : R->fs.split ? "form-a/form-b" : R->fs.text[0],
	             e ? e->name : m && m->fname[0] ? m->fname : "brdfkit_fit", e ? e->source : m ? m->source : "user form",
	             e ? e->convention : "as the target's units (see domain)", R->has_published ? e->defaults : NULL,
	             R->fs.split, {R->fs.f[0], R->fs.f[1]}, 1, 0, NULL, 0};
	return v;
}

/* One line on stderr before a reference build that computes integrals: how
 * many, and how long they will take here (bk_target_estimate times 16). No
 * size is refused: --nx, --nr <= 4096 bound it, and the line says the cost. */
static void say_estimate(const bk_target_options *to)
{
	double n, sec = bk_target_estimate(to, &n);
	if (n <= 0)
		return;
	char count[32], when[32];
	if (n < 1e4)
		snprintf(count, sizeof count, "%.0f", n);
	else
		snprintf(count, sizeof count, n < 1e6 ? "%.3gk" : "%.3gM", n < 1e6 ? n / 1e3 : n / 1e6);
	if (sec < 120)
		snprintf(when, sizeof when, "%.0f s", ceil(sec));
	else
		snprintf(when, sizeof when, sec < 7200 ? "%.0f min" : "%.1f h", sec < 7200 ? sec / 60 : sec / 3600);
	if (!cli_quiet())
		fprintf(stderr, "fit: %s target %dx%d = %s integrals, about %s on this machine\n", bk_target_name(to->kind),
	        to->nx, to->nr, count, when);
}

/* Everything into DIR.tmpXXXXXX, then swapped in whole (bk_out_dir): the
 * directory is the old result or the new one, and only a directory brdfkit
 * wrote is replaced. */
static int write_outputs(const run *R, const char *out)
{
	char err[512];
	bk_out_dir od;
	if (bk_out_dir_begin(&od, out, NULL, err, sizeof err))
		return cli_fail("fit", "--out %s", err);
	err[0] = '\0';
	fitout_run v = view(R);
	if (fitout_write_into(&v, od.tmp, err, sizeof err)) {
		bk_out_dir_abort(&od);
		return cli_fail("fit", "%s: writing the results failed%s%s", out, *err ? ": " : "", err);
	}
	return bk_out_dir_commit(&od, err, sizeof err) ? cli_fail("fit", "--out %s", err) : 0;
}

/* ---- the command ---------------------------------------------------------- */

static int setup_spec(run *R, char **pos, int npos)
{
	const fitargs *a = R->a;
	bk_fit_spec *sp = &R->spec;
	bk_fit_options defaults = BK_FIT_OPTIONS_INIT;
	sp->opt = defaults;
	sp->s = &R->s;
	sp->form[0] = R->fs.f[0];
	sp->form[1] = R->fs.f[1];
	sp->np = bk_form_nparams(R->fs.f[0]);
	if (R->fs.split && bk_form_nparams(R->fs.f[1]) > sp->np)
		sp->np = bk_form_nparams(R->fs.f[1]);
	for (int j = 0; j < BK_MAX_PARAMS; j++) {
		sp->lower[j] = -HUGE_VAL;
		sp->upper[j] = HUGE_VAL;
		sp->start[j] = R->fs.entry && j < R->fs.entry->nparams ? R->fs.entry->defaults[j]
		               : R->fs.member && j < R->fs.m.np ? R->fs.m.p[j] : NAN;
	}
	int given[BK_MAX_PARAMS] = {0};
	for (int i = 0; i < npos; i++) { /* p0=VALUE starts */
		int rc = form_param_set(NULL, pos[i], sp->start, given, NULL);
		if (rc == 0)
			return cli_bad("expected pN=VALUE (a starting value), got '%s'", pos[i]);
		if (rc != 1)
			return 2;
	}
	unsigned used = bk_form_params(R->fs.f[0]) | (R->fs.split ? bk_form_params(R->fs.f[1]) : 0);
	for (int j = 0; j < sp->np; j++) /* numbered from p0, as every command takes them (form_check.h) */
		if (!(used >> j & 1u))
			return cli_bad("the form uses p%d but not p%d: number the parameters from p0, without a gap", sp->np - 1,
			               j);
	for (int j = 0; j < sp->np; j++)
		if (!isfinite(sp->start[j])) {
			return cli_bad("no starting value for p%d: give p%d=VALUE", j, j);
		}
	if (a->bounds && bounds(R->cmd, a->bounds, sp->lower, sp->upper))
		return 2;
	const char *items[BK_MAX_PARAMS];
	int n = a->hold ? cli_words(R->cmd, "--hold", a->hold, items, BK_MAX_PARAMS) : 0;
	if (n < 0)
		return 2;
	for (int k = 0; k < n; k++) {
		int j = param_index(items[k]);
		if (j < 0 || j >= sp->np) {
			return cli_bad("--hold: expected parameters of the form (p0..p%d), got '%s'",
			               sp->np - 1, items[k]);
		}
		if (sp->hold[j]++)
			return cli_usage(R->cmd, "--hold: p%d given twice in the list '%.200s'", j, a->hold);
	}
	sp->relative = a->relative;
	sp->starts = (int)a->starts;
	sp->seed = (unsigned long)a->seed;
	int v = 0;
	static const char *const losses[] = {"none", "huber", "cauchy", "softl1"};
	static const char *const trs[] = {"lm", "dogleg"};
	static const char *const objs[] = {"lsq", "minimax"};
	if (parse_enum("--loss", a->loss, losses, 4, &v))
		return 2;
	sp->opt.loss = (bk_loss)v;
	sp->opt.loss_scale = a->loss_scale;
	if (parse_enum("--trust-region", a->tr, trs, 2, &v))
		return 2;
	sp->opt.trust_region = (bk_trust_region)v;
	if (parse_enum("--objective", a->objective, objs, 2, &v))
		return 2;
	sp->minimax = v;
	sp->opt.max_iterations = (int)a->max_iter;
	sp->opt.num_threads = (int)a->threads;
	if (a->digits) { /* the word half, or an integer 1..17 written plainly (17 digits round-trip a double) */
		char *end;
		long d = a->digits[0] >= '1' && a->digits[0] <= '9' ? strtol(a->digits, &end, 10) : 0;
		if (!strcmp(a->digits, "half"))
			sp->digits = -1;
		else if (d >= 1 && d <= 17 && !*end)
			sp->digits = (int)d;
		else
			return cli_usage(R->cmd, "--digits: expected an integer in [1, 17] or half, got '%s'", a->digits);
	} else {
		sp->digits = BK_FIT_DIGITS_SE;
	}
	return 0;
}


/* ---- where the options act (cli.h) ----------------------------------------- */

/* The target kind; whether the form has parameters (without, it is
 * evaluated, never fitted); whether --loss is robust; one form or an env
 * split pair; one start or several; which solver runs: Ceres' TinySolver
 * (single-threaded: no --loss, no --bound, Levenberg-Marquardt) or Ceres'
 * full solver (bk_fit_solve, tiny.cc). */
enum { DIM_TARGET, DIM_PARAMS, DIM_LOSS, DIM_FORMS, DIM_STARTS, DIM_SOLVER };
static const cli_dim dims[] = {
	FITARGS_TARGET_DIM,
	{"params", {"none", "some"}, {": the form has no parameters (it is evaluated, not fitted)", NULL}},
	{"loss", {"none", "robust"}, {" without --loss huber|cauchy|softl1", NULL}},
	{"forms", {"one", "split"}, {NULL, " on a split-sum env fit"}},
	{"starts", {"one", "several"}, {" with --starts 1", NULL}},
	{"solver", {"tiny", "ceres"},
	 {" with the default solver (Ceres' TinySolver, one thread; Ceres' full solver runs with --loss, --bound or "
	  "--trust-region dogleg)", NULL}},
};
#define FITTING(opt, example) {opt, NULL, DIM_PARAMS, 1u << 1, NULL, example}
#define EVERYWHERE(opt, example) {opt, NULL, CLI_EVERYWHERE, 0, NULL, example}
static const cli_rule rules[] = {
	{"--nu", NULL, DIM_TARGET, FITARGS_ON(VF) | FITARGS_ON(SPEC), "it sets the half-vector cells of targets vf and spec", "4"},
	{"--nphi", NULL, DIM_TARGET, FITARGS_ON(VF) | FITARGS_ON(SPEC), "it sets the azimuth cells of targets vf and spec", "4"},
	{"--talk-roughness", NULL, DIM_TARGET, FITARGS_ON(VF2D), "it sets how target vf2d reads the talk's roughness", "a"},
	{"--smith", NULL, DIM_TARGET, FITARGS_ON(ENV) | FITARGS_ON(MS), "it sets the Smith model of targets env and ms", "schlick"},
	{"--ior", NULL, DIM_TARGET, FITARGS_ON(F), "it sets the exact Fresnel of target f", "1.4"},
	{"--k", NULL, DIM_TARGET, FITARGS_ON(F), "it sets the exact Fresnel of target f", "3"},
	{"--f0", NULL, DIM_TARGET, FITARGS_ON(VF2D) | FITARGS_ON(VF) | FITARGS_ON(SPEC) | FITARGS_ON(ENV),
	 "it sets f0 of targets vf2d, vf, spec and env", "0.5"},
	{"--f0", NULL, DIM_FORMS, 1u << 0,
	 "A and B do not depend on f0; a single form in f0 is fitted to f0 A + B over the --f0 list", "0.5"},
	{"--nr", NULL, DIM_TARGET, FITARGS_ALL & ~FITARGS_ON(F), "target f has no roughness axis", "8"},
	{"--r-range", NULL, DIM_TARGET, FITARGS_ALL & ~FITARGS_ON(F), "target f has no roughness axis", "0:0.5"},
	{"--target-form", NULL, DIM_TARGET, FITARGS_ON(FORM), "it gives the expression of target form", "LoH"},
	FITARGS_FILE_RULES(DIM_TARGET),
	{"--domain", NULL, DIM_TARGET, FITARGS_ON(FORM), "it gives the domain of target form", "LoH=0:1"},
	{"--nr", NULL, DIM_TARGET, FITARGS_ALL & ~FITARGS_ON(FORM),
	 "--domain sets the inputs of target form; --nx the cells per axis", "8"},
	{"--r-range", NULL, DIM_TARGET, FITARGS_ALL & ~FITARGS_ON(FORM), "--domain sets the inputs of target form", "0:0.5"},
	{"--x-range", NULL, DIM_TARGET, FITARGS_ALL & ~FITARGS_ON(FORM), "--domain sets the inputs of target form", "0:0.5"},
	{"--weight", "dnol", DIM_TARGET, FITARGS_ON(VF) | FITARGS_ON(SPEC), "D*NoL weighs the samples of targets vf and spec",
	 NULL},
	/* the fitter's options: a form without parameters never runs it */
	FITTING("--loss", "huber"),
	FITTING("--loss-scale", "2"),
	{"--loss-scale", NULL, DIM_LOSS, 1u << 1, "it scales the robust loss", "2"},
	FITTING("--trust-region", "dogleg"),
	FITTING("--max-iterations", "50"),
	FITTING("--threads", "2"),
	{"--threads", NULL, DIM_SOLVER, 1u << 1, "it sets the threads of Ceres' full solver", "2"},
	FITTING("--bound", "p0=-10:10"),
	FITTING("--hold", "p0"),
	FITTING("--starts", "2"),
	FITTING("--seed", "7"),
	{"--seed", NULL, DIM_STARTS, 1u << 1, "it draws the starts after the first", "7"},
	FITTING("--objective", "minimax"),
	FITTING("--digits", "3"),
	EVERYWHERE("--target", NULL),
	EVERYWHERE("--form", NULL), /* --form or --form-a and --form-b: every setup gives one */
	EVERYWHERE("--form-a", NULL),
	EVERYWHERE("--form-b", NULL),
	EVERYWHERE("--out", NULL),
	EVERYWHERE("--nx", "8"),
	EVERYWHERE("--relative", NULL), /* residuals of the fit, and the cost an evaluation reports */
	EVERYWHERE("--weight", "none"),
};
/* the forms read no input (p0, 0.5), so that one form fits every target */
static const char *const setups[] = {
	"--target vf2d --form p0 p0=1 --out o",
	"--target vf --form p0 p0=1 --out o",
	"--target spec --form p0 p0=1 --out o",
	"--target env --form p0 p0=1 --out o",
	"--target d --form p0 p0=1 --out o",
	"--target f --form p0 p0=1 --out o",
	"--target form --target-form LoH --domain LoH=0:1 --form p0 p0=1 --out o",
	"--target ms --form p0 p0=1 --out o",
	"--target sheen --form p0 p0=1 --out o",
	"--target table --target-file t.csv --form p0 p0=1 --out o",
	"--target merl --target-file t.binary --form p0 p0=1 --out o",
	"--target f --form 0.5 --out o",
	"--target vf --form 0.5 --out o",
	"--target f --form p0 p0=1 --loss huber --out o",
	"--target env --form-a p0 --form-b p1 p0=1 p1=1 --out o",
	"--target f --form p0 p0=1 --starts 1 --out o",
	NULL};
static const cli_table table = {dims, 6, rules, sizeof rules / sizeof rules[0], setups};

/* The run's context (the table's dimensions), then cli_applicable. */
static int check_applicable(const run *R, bk_target_kind kind)
{
	const fitargs *a = R->a;
	int np = bk_form_nparams(R->fs.f[0]);
	if (R->fs.split && bk_form_nparams(R->fs.f[1]) > np)
		np = bk_form_nparams(R->fs.f[1]);
	int robust = strcmp(a->loss, "none") != 0;
	int ctx[] = {(int)kind, np > 0, robust, R->fs.split, a->starts > 1,
	             robust || strcmp(a->tr, "lm") != 0 || a->bounds != NULL}; /* tiny.cc: refuses() */
	return cli_applicable(R->cmd, ctx);
}

/* Refuses a value that would change nothing, or leave nothing to fit (the
 * options themselves: the table above): the run would look as asked for and
 * not be. Returns 0 or 2. */
static int check_effect(const run *R, bk_target_kind kind, char **pos, int npos)
{
	const cli_cmd *cmd = R->cmd;
	const fitargs *a = R->a;
	if (a->f0.n > 1 && kind != BK_TARGET_ENV)
		return cli_usage(cmd, "--f0: target %s uses one value, got %d", bk_target_name(kind), a->f0.n);
	const bk_fit_spec *sp = &R->spec;
	for (int i = 0; i < npos; i++) { /* pN=VALUE, checked by setup_spec */
		long j = atol(pos[i] + 1);
		if (j >= sp->np && sp->np == 0)
			return cli_usage(cmd, "'%s' has no effect: the form has no parameters", pos[i]);
		if (j >= sp->np && sp->np == 1)
			return cli_usage(cmd, "'%s' has no effect: the form uses p0 only", pos[i]);
		if (j >= sp->np)
			return cli_usage(cmd, "'%s' has no effect: the form uses p0..p%d", pos[i], sp->np - 1);
	}
	for (int j = sp->np; j < BK_MAX_PARAMS; j++)
		if (isfinite(sp->lower[j]) || isfinite(sp->upper[j]))
			return cli_usage(cmd, "--bound p%d has no effect: the form has no parameter p%d", j, j);
	int held = 0;
	for (int j = 0; j < sp->np; j++) {
		held += sp->hold[j];
		if (sp->hold[j] && (isfinite(sp->lower[j]) || isfinite(sp->upper[j])))
			return cli_usage(cmd, "--bound p%d has no effect: --hold keeps p%d at its start value", j, j);
	}
	char all[16] = "p0";
	if (sp->np > 1)
		snprintf(all, sizeof all, "p0..p%d", sp->np - 1);
	if (sp->np && held == sp->np) /* nothing would move: it would read "converged", p0 = 1 ± 0 */
		return cli_usage(cmd, "--hold holds every parameter of the form (%s): nothing is fitted; to evaluate the "
		                 "form at these values, write them into it as numbers", all);
	return 0;
}

/* A weight that is zero (or worse) at every sample leaves nothing to fit:
 * Ceres would stop at once with cost 0 and call it converged. */
static int check_weight(const run *R)
{
	const bk_samples *s = &R->s;
	double *uw = R->spec.weight ? malloc(sizeof(double) * s->n) : NULL;
	if (R->spec.weight && (!uw || bk_form_eval(R->spec.weight, BK_F64, s->n, (const double *const *)s->in,
	                                           R->spec.start, uw))) {
		free(uw);
		return 0; /* the fitter reports it */
	}
	size_t positive = 0;
	for (size_t i = 0; i < s->n; i++)
		positive += s->w[i] * (uw ? uw[i] : 1.0) > 0; /* false for NaN */
	free(uw);
	if (positive)
		return 0;
	return cli_usage(R->cmd, "--weight '%s' is not positive at any of the %zu samples: nothing to fit",
	                 R->a->weight ? R->a->weight : "default", s->n);
}

/* Forms may read only what the target provides; a non-finite form fails. */
static int check_forms(run *R)
{
	const bk_samples *s = &R->s;
	for (int q = 0; q < s->ncomp; q++) {
		unsigned extra = bk_form_inputs(R->spec.form[q]) & ~s->provides;
		for (int k = 0; k < BK_IN_COUNT; k++)
			if (extra >> k & 1)
				return cli_fail("fit", "the form reads %s, which target %s does not provide",
				                bk_input_name((bk_input)k), bk_target_name(R->to.kind));
	}
	char where[256];
	size_t bad = bk_fit_nonfinite(&R->spec, R->spec.start, where, sizeof where);
	if (bad)
		return cli_fail("fit", "the form is NaN or infinite at %zu of %zu samples where the target is finite "
		                "(first at %s): fix the form or the domain", bad, s->n, where);
	int edge = bk_fit_edge_check(&R->spec, R->spec.start, where, sizeof where);
	if (edge)
		fprintf(stderr, "brdfkit fit: warning: the form is infinite at %d points on the closed edge of the domain "
		        "(e.g. %s); where the target stays finite there, the samples next to them rule a least-squares fit\n",
		        edge, where);
	return 0;
}

static void report(const run *R, int rc)
{
	const bk_fit_result *res = &R->res;
	static const char *const term[] = {"converged", "did not converge", "failed"};
	unsigned t = (unsigned)res->summary.termination;
	if (R->spec.np == 0) /* the fitter never ran: no iterations, no cost to lower */
		printf("fit %s on %s: no parameters: evaluated, not fitted\n", form_label(&R->fs),
		       bk_target_name(R->to.kind));
	else
		printf("fit %s on %s: %s after %d iterations (%d bound re-solves), cost %.6g -> %.6g, %.2f s\n",
		       form_label(&R->fs), bk_target_name(R->to.kind),
		       rc == 0 ? term[0] : t < 3 && t ? term[t] : term[1], res->summary.iterations,
		       res->summary.bound_resolves, res->summary.initial_cost, res->summary.final_cost,
		       res->summary.seconds);
	if (R->spec.starts > 1 && R->spec.np > 0)
		printf("starts: %d, best cost %.6g, worst %.6g, failed %d\n", R->spec.starts, res->start_cost_min,
		       res->start_cost_max, res->starts_failed);
	for (int j = 0; j < R->spec.np; j++) {
		printf("  p%-2d = %-14.9g", j, res->p[j]);
		if (isfinite(res->se[j]))
			printf(" ± %.2g", res->se[j]);
		if (res->held[j])
			printf("  not identifiable: held at its start value");
		else if (res->unidentified[j])
			printf("  not identifiable (the data do not pin it)");
		else if (res->collinear[j])
			printf("  nearly collinear with others");
		if (R->has_published && j < R->fs.entry->nparams)
			printf("  (published %.9g)", R->fs.entry->defaults[j]);
		putchar('\n');
	}
	printf("%-10s rmse %.4g, max |err| %.4g, max rel %.4g", R->spec.np ? "fitted:" : "evaluated:",
	       res->fitted.rmse, res->fitted.max_abs, res->fitted.max_rel);
	if (isfinite(res->fitted.albedo_max_abs))
		printf(", albedo max |err| %.4g", res->fitted.albedo_max_abs);
	putchar('\n');
	if (R->has_published) {
		printf("published: rmse %.4g, max |err| %.4g, max rel %.4g", res->published.rmse, res->published.max_abs,
		       res->published.max_rel);
		if (isfinite(res->published.albedo_max_abs))
			printf(", albedo max |err| %.4g", res->published.albedo_max_abs);
		putchar('\n');
	}
	if (R->s.ncomp == 2)
		printf("split sum: max |err| A %.4g, B %.4g, A+B %.4g\n", res->fitted.comp_max_abs[0],
		       res->fitted.comp_max_abs[1], res->fitted.comp_max_abs[2]);
	if (isfinite(res->condition))
		printf("condition of the scaled JᵀJ: %.3g%s\n", res->condition,
		       res->condition > BK_FIT_COND_MAX ? " (ill-conditioned: nearly collinear parameters are marked)" : "");
	if (res->message[0])
		printf("note: %s\n", res->message);
	if (rc == 1)
		printf("warning: did not converge (%s)\n", res->summary.message);
	fitout_run v = view(R);
	if (!fitout_has_plane(&v) && R->to.kind == BK_TARGET_FORM)
		printf("no heatmap: target form has %d inputs; a heatmap needs 1 or 2\n", R->to.ndomain);
	else if (!fitout_has_plane(&v))
		printf("no heatmap: the samples of target %s lie on no 2-D grid\n", bk_target_name(R->to.kind));
}

int cmd_fit(int argc, char **argv)
{
	fitargs a = {.loss = "none", .tr = "lm", .objective = "lsq", .starts = 4, .seed = 1, .max_iter = 200,
	             .threads = 1, .loss_scale = 1.0};
	cli_opt opts[] = {
		{.name = "--target", .kind = CLI_STR, .metavar = "T", .help = "vf2d, vf, spec, env, d, f, form, ms, sheen, table FILE or merl FILE (FILE as --target-file)", .dest = &a.target, .required = 1, .then = "--target-file", .then_values = "table merl"},
		{.name = "--target-file", .kind = CLI_STR, .metavar = "FILE", .help = "table: a CSV of samples (input columns, value, optional weight) or an EXR table as lut writes it; merl: a MERL binary BRDF", .dest = &a.target_file},
		{.name = "--channel", .kind = CLI_STR, .metavar = "NAME", .help = "table: the EXR channel (default: its only one); merl: r, g, b or luminance (default)", .dest = &a.channel},
		{.name = "--target-form", .kind = CLI_FORM, .metavar = "EXPR", .help = "form: the target's expression (inputs only, no pN), evaluated in double", .dest = &a.target_form},
		{.name = "--domain", .kind = CLI_STR, .metavar = "IN=LO:HI,...", .help = "form: an interval for each input EXPR reads (r gives a = r^2 too); the first varies fastest and, with two, is the heatmap's x", .dest = &a.domain},
		{.name = "--form", .kind = CLI_FORM, .metavar = "FORM|NAME|FILE.csv:MEMBER", .help = "the form, a catalog entry (its constants start the fit) or a member of a search's front.csv (its fitted values start the fit)", .dest = &a.form},
		{.name = "--form-a", .kind = CLI_FORM, .metavar = "FORM", .help = "env: the form of A (with --form-b, sharing parameters)", .dest = &a.form_a},
		{.name = "--form-b", .kind = CLI_FORM, .metavar = "FORM", .help = "env: the form of B", .dest = &a.form_b},
		{.name = "--out", .kind = CLI_STR, .metavar = "DIR", .help = "results directory (replaced whole)", .dest = &a.out, .required = 1},
		{.name = "--r-range", .kind = CLI_STR, .metavar = "LO:HI", .help = "perceptual roughness range (default 0:1)", .dest = &a.r_range},
		{.name = "--x-range", .kind = CLI_STR, .metavar = "LO:HI", .help = "LoH (vf2d, f), NoV (vf, spec, env) or NoH (d) range", .dest = &a.x_range},
		{.name = "--nx", .kind = CLI_INT, .metavar = "N", .help = "cells along x (form: per domain input; default 256, 64, 16, 8 for 1-4 inputs)", .dest = &a.nx, .lo = 1, .hi = 4096},
		{.name = "--nr", .kind = CLI_INT, .metavar = "N", .help = "cells along roughness", .dest = &a.nr, .lo = 1, .hi = 4096},
		{.name = "--nu", .kind = CLI_INT, .metavar = "N", .help = "vf/spec: half-vector cells (GGX CDF)", .dest = &a.nu, .lo = 1, .hi = 1024},
		{.name = "--nphi", .kind = CLI_INT, .metavar = "N", .help = "vf/spec: azimuth cells", .dest = &a.nphi, .lo = 1, .hi = 1024},
		{.name = "--f0", .kind = CLI_LIST, .metavar = "F[,F...]", .help = "f0 (first used; env forms in f0 use all)", .dest = &a.f0, .lo = 0, .hi = 1},
		{.name = "--talk-roughness", .kind = CLI_STR, .metavar = "r|a", .help = "vf2d: read the talk's roughness as r (default) or alpha", .dest = &a.talk},
		{.name = "--smith", .kind = CLI_STR, .metavar = "MODEL", .help = "env, ms: correlated (default), separable, schlick", .dest = &a.smith},
		{.name = "--ior", .kind = CLI_NUM, .metavar = "N", .help = "f: real index of the exact Fresnel (default 1.5)", .dest = &a.ior, .lo = 0, .hi = 1e6, .lo_open = 1},
		{.name = "--k", .kind = CLI_NUM, .metavar = "K", .help = "f: extinction coefficient (conductor)", .dest = &a.k, .lo = 0, .hi = 1e6},
		{.name = "--relative", .kind = CLI_FLAG, .help = "relative residuals (f - y)/|y|", .dest = &a.relative},
		{.name = "--weight", .kind = CLI_FORM, .metavar = "none|dnol|FORM", .help = "weight: none, D*NoL (vf default), or a formula multiplying it", .dest = &a.weight},
		{.name = "--loss", .kind = CLI_STR, .metavar = "L", .help = "none (default), huber, cauchy, softl1 (per residual)", .dest = &a.loss},
		{.name = "--loss-scale", .kind = CLI_NUM, .metavar = "C", .help = "scale c of the robust loss, in units of the weighted residual sqrt(w)·(f - y) (default 1)", .dest = &a.loss_scale, .lo = 0, .hi = 1e30, .lo_open = 1},
		{.name = "--trust-region", .kind = CLI_STR, .metavar = "lm|dogleg", .help = "Levenberg-Marquardt (default) or dogleg", .dest = &a.tr},
		{.name = "--max-iterations", .kind = CLI_INT, .metavar = "N", .help = "per solve (default 200)", .dest = &a.max_iter, .lo = 1, .hi = 100000},
		{.name = "--threads", .kind = CLI_INT, .metavar = "N", .help = "threads of Ceres' full solver, which runs with --loss, --bound or dogleg (default 1, unlike search's all cores: Ceres sums each thread's share of the cost and gradient, in an order the scheduling picks, so more threads may change the last bits)", .dest = &a.threads, .lo = 1, .hi = 64},
		{.name = "--bound", .kind = CLI_STR, .metavar = "pN=LO:HI[,...]", .help = "parameter bounds", .dest = &a.bounds},
		{.name = "--hold", .kind = CLI_STR, .metavar = "pN[,pM...]", .help = "keep these parameters at their start values", .dest = &a.hold},
		{.name = "--starts", .kind = CLI_INT, .metavar = "K", .help = "deterministic starts (default 4)", .dest = &a.starts, .lo = 1, .hi = 1000},
		{.name = "--seed", .kind = CLI_INT, .metavar = "S", .help = "seed of the starts after the first (default 1)", .dest = &a.seed, .lo = 0, .hi = 4294967295.0},
		{.name = "--objective", .kind = CLI_STR, .metavar = "lsq|minimax", .help = "least squares (default) or minimise the max error", .dest = &a.objective},
		{.name = "--digits", .kind = CLI_STR, .metavar = "N|half", .help = "round constants to N significant digits (N in [1, 17]) or to fp16 (half), refitting the rest (default: to 1/100 of their standard errors, no refit)", .dest = &a.digits},
	};
	cli_cmd cmd = {"fit", "Fits a form to a target with Ceres and writes coefficients.csv, metrics.csv,\n"
	               "heatmap.{exr,png,csv} and shader.{c,glsl,hlsl} into DIR.",
	               "--target T (--form FORM|NAME | --form-a A --form-b B) --out DIR [p0=START ...] [options]",
	               "Target form: --target-form EXPR --domain IN=LO:HI[,...] samples EXPR at cell centres of a\n"
	               "grid over the domain (uniform weight); no heatmap with more than two inputs.\n"
	               "Targets table and merl: --target-file FILE, a CSV of samples, an EXR table as lut\n"
	               "writes it, or a MERL binary BRDF (--channel); see brdfkit-fit(1), Targets.\n"
	               "A form without parameters is evaluated, not fitted. Options that would have no effect (on\n"
	               "this target, without parameters, --loss-scale without --loss, --seed with --starts 1,\n"
	               "--threads on the default solver) are refused, and so is --hold of every parameter.\n"
	               "Exit status: 0 converged (or evaluated), 3 did not converge (results written), 1 failed,\n"
	               "2 bad usage.",
	               opts, (int)(sizeof opts / sizeof opts[0]), 16, 0, {0}};
	int rc = cli_parse_table(&cmd, &table, argc, argv);
	if (rc)
		return rc == 1 ? 0 : rc;
	run R;
	memset(&R, 0, sizeof R);
	R.a = &a;
	R.cmd = &cmd;
	snprintf(R.command, sizeof R.command, "%s", bk_out_command());
	bk_target_kind kind;
	if (bk_target_parse(a.target, &kind)) {
		return cli_unknown_value("--target", a.target, cli_targets, CLI_NTARGETS);
	}
	if ((rc = fitargs_setup_target(&a, kind, &R.to)) || (rc = load_forms(&a, kind, &R.fs))) {
		cli_member_free(&R.fs.m);
		return rc;
	}
	bk_form *wform = NULL;
	if ((rc = check_applicable(&R, kind)))
		goto done;
	R.to.env_f0_form = kind == BK_TARGET_ENV && !R.fs.split;
	if (a.weight && !strcmp(a.weight, "none"))
		R.to.weight = BK_WEIGHT_NONE;
	else if (a.weight && !strcmp(a.weight, "dnol"))
		R.to.weight = BK_WEIGHT_DNOL;
	else if (a.weight && (rc = parse_form("weight", a.weight, &wform)))
		goto done;
	char err[512];
	if ((rc = setup_spec(&R, cmd.pos, cmd.npos)) || (rc = check_effect(&R, kind, cmd.pos, cmd.npos)))
		goto done;
	if ((rc = fitargs_read_file(&cmd, &a, kind, &R.table)))
		goto done;
	R.to.table = &R.table;
	if (kind == BK_TARGET_FORM) {
		if (!a.target_form || !a.domain) {
			rc = cli_usage(&cmd, "target form needs --target-form EXPR and --domain IN=LO:HI[,...]");
			goto done;
		}
		R.to.form_text = a.target_form;
		if ((rc = fitargs_domain(&cmd, a.domain, &R.to)))
			goto done;
		if (bk_target_form_check(&R.to, err, sizeof err)) {
			rc = cli_usage(&cmd, "--target-form: %s", err);
			goto done;
		}
	}
	R.spec.weight = wform;
	char why[200];
	if (!bk_fit_options_valid(&R.spec.opt, why, sizeof why)) {
		fprintf(stderr, "brdfkit fit: %s\n", why);
		rc = 2;
		goto done;
	}
	if (bk_out_dir_check(a.out, err, sizeof err)) { /* before the work (hours for a big env grid), not after */
		rc = cli_fail("fit", "--out %s", err);
		goto done;
	}
	say_estimate(&R.to);
	fitargs_say_size(&R.to);
	rc = bk_lutcache_target_build(&R.to, &R.s, cli_progress, "reference", err, sizeof err);
	bk_samples_free(&R.table); /* copied: a MERL file's samples are 120 MB */
	if (rc) {
		rc = cli_fail("fit", "%s", err);
		goto done;
	}
	if ((rc = check_weight(&R)) || (rc = check_forms(&R)))
		goto samples;
	R.has_published = R.fs.entry != NULL;
	if (R.has_published) /* at the catalog's constants, not at a start the user gave */
		bk_fit_evaluate(&R.spec, R.fs.entry->defaults, &R.res.published);
	bk_fit_metrics published = R.res.published;
	rc = bk_fit_run(&R.spec, &R.res);
	R.res.published = published;
	if (rc < 0) {
		rc = cli_fail("fit", "%s", R.res.message);
		goto samples;
	}
	report(&R, rc);
	int status = rc == 1 ? 3 : 0;
	rc = write_outputs(&R, a.out);
	if (rc == 0)
		rc = status;
samples:
	bk_samples_free(&R.s);
done:
	bk_form_free(R.fs.f[0]);
	bk_form_free(R.fs.f[1]);
	cli_member_free(&R.fs.m);
	bk_form_free(wform);
	bk_samples_free(&R.table);
	return rc;
}
