/*
 * cmd_search.c — brdfkit search: the search for closed forms of fit/search.h
 * on a target, its front refitted in full, written into one directory whole
 * or not at all: front.csv, candidates.csv, front/NAME/ (what fit writes),
 * pareto.svg and section.html.
 */
#include "albfit.h"
#include "brdf.h"
#include "catalog.h"
#include "cli.h"
#include "clock.h"
#include "cmd.h"
#include "compare.h"
#include "fit_out.h"
#include "gpucost.h"
#include "islands.h"
#include "out.h"
#include "search.h"
#include "search_ck.h"
#include "stability.h"

#include <ctype.h>
#include <errno.h>
#include <stdint.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define MAX_SEEDS 64
#define MAX_FRONT 48   /* screening front members refitted in full */
#define PROGRESS_EVERY 10.0 /* seconds between log lines */

typedef struct search_cli {
	fit_cli t; /* the target options, as fit reads them */
	const char *out, *prefix, *inputs, *ops, *objective, *precision, *weights, *cost_model, *gpu, *env_form, *checkpoint, *resume;
	const char *start[MAX_SEEDS];
	int nstart;
	long evals, seed, threads, max_params, max_size, enum_size, enum_max, every, generation, migrate, migrants;
	double seconds, max_cost, fetch_cost;
	int relative, no_constraints, merge_fronts, inherit;
} search_cli;

/* A member of the final front, or a catalog form, on the full samples. */
typedef struct member {
	const bk_cand *c;              /* NULL for a catalog row */
	const bk_catalog_entry *entry; /* catalog rows */
	int refit;                     /* catalog: 0 published constants, 1 refitted */
	char name[96];
	const char *text, *text_b;
	bk_form *f[2];
	bk_fit_spec spec;
	bk_fit_result res;
	double cost;
	bk_ops ops;
	double err;                    /* the objective on the full samples, in the search precision */
	bk_fit_metrics prec;           /* metrics in the search precision */
	double f16_max;                /* max |error| evaluated in half */
	char verdict[24];              /* stability in half: safe as is / with guards / no */
	int status;                    /* 0 ok, 1 dropped (not finite or outside the constraints) */
	int front;
	int lut;                       /* a DFG texture row (--fetch-cost): no form, one fetch */
	double gpu_insn[BK_GPUCOST_MAX_CHIPS], gpu_transc[BK_GPUCOST_MAX_CHIPS]; /* --gpu; NaN: not compiled */
} member;

typedef struct job {
	search_cli *a;
	const cli_cmd *cmd;
	bk_target_kind kind;
	bk_target_options to, to_screen;
	bk_samples s, screen;
	bk_search_options so;
	bk_search *S;
	member *m;
	int nm;
	char command[2048];
	double seconds;
	long start_evals;  /* fits done before this process started (a resume): not counted in fits/s */
	int interrupted;
	long total_evals;  /* over all islands */
	const char *chip[BK_GPUCOST_MAX_CHIPS]; /* --gpu */
	int nchips;
	char chipbuf[512], driver[256];
} job;

static volatile sig_atomic_t stop_asked;
static void on_interrupt(int sig)
{
	(void)sig;
	stop_asked = 1;
}

/* A stop at the end of the generation (or round) for sig, unless whoever
 * started us ignores it (a background job of a script has SIGINT ignored:
 * POSIX; it stays ignored in every phase, as bk_out_init leaves it). The
 * old action is kept in *old to be put back. */
static void catch_stop(int sig, struct sigaction *old)
{
	if (sigaction(sig, NULL, old) != 0 || old->sa_handler == SIG_IGN)
		return;
	struct sigaction sa;
	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_interrupt;
	sigemptyset(&sa.sa_mask);
	sigaction(sig, &sa, NULL);
}

/* SIGINT asks for a stop while the search runs (the refit after it is
 * bk_out_init's: removed temporaries, death by the signal); so does SIGUSR1,
 * for the whole run: mpirun forwards SIGUSR1 to every rank, while it answers
 * SIGINT and SIGTERM by killing them (Open MPI's rule), so SIGUSR1 is how an
 * MPI job is stopped with its front. */
static void catch_interrupt(struct sigaction *old)
{
	struct sigaction usr1;
	catch_stop(SIGINT, old);
	catch_stop(SIGUSR1, &usr1);
}

/* ---- option helpers ------------------------------------------------------- */

static int parse_word(const cli_cmd *cmd, const char *opt, const char *text, const char *const *names, int n,
                      int *out)
{
	for (int i = 0; i < n; i++)
		if (!strcmp(text, names[i])) {
			*out = i;
			return 0;
		}
	char list[200] = "";
	for (int i = 0; i < n; i++)
		snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", i ? ", " : "", names[i]);
	return cli_usage(cmd, "%s: unknown value '%s' (%s)", opt, text, list);
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
static int env_in_f0(const job *J)
{
	return J->kind == BK_TARGET_ENV && J->a->env_form && (!strcmp(J->a->env_form, "f0") || !strcmp(J->a->env_form, "mix"));
}

/* --env-form mix: the same forms in f0, seeded also with mix(B, S, f0) of
 * the fronts of two searches run first, one of S = A + B (f0 = 1) and one
 * of B (f0 = 0) (halves below). */
static int env_halves(const job *J)
{
	return J->kind == BK_TARGET_ENV && J->a->env_form && !strcmp(J->a->env_form, "mix");
}

/* The catalog's tag for the forms of a target, NULL when none fits it. */
static const char *catalog_tag(bk_target_kind k)
{
	switch (k) {
	case BK_TARGET_VF2D:
	case BK_TARGET_VF: return "VF";
	case BK_TARGET_SPEC: return "DVF";
	case BK_TARGET_ENV: return "env";
	case BK_TARGET_D: return "D";
	case BK_TARGET_F: return "F";
	default: return NULL;
	}
}

/* Whether a catalog form reads only what the samples provide. */
static int entry_fits(const bk_catalog_entry *e, unsigned provides)
{
	bk_form_error fe;
	for (int h = 0; h < 2; h++) {
		const char *t = h ? e->form_b : e->form;
		if (!t)
			continue;
		bk_form *f = bk_form_parse(t, &fe);
		int ok = f && !(bk_form_inputs(f) & ~provides);
		bk_form_free(f);
		if (!ok)
			return 0;
	}
	return 1;
}

/* ---- set-up ----------------------------------------------------------------- */

/* The screening grid: about a thousand samples, where a fit takes well under a
 * millisecond; the front is refitted on the full grid. */
static void screening_grid(bk_target_options *o)
{
	switch (o->kind) {
	case BK_TARGET_VF2D:
	case BK_TARGET_D: o->nx = o->nr = 32; break;
	case BK_TARGET_VF:
	case BK_TARGET_SPEC: o->nx = o->nr = 8, o->nu = 8, o->nphi = 4; break; /* 2,048 samples */
	case BK_TARGET_ENV: o->nx = o->nr = 16; break;
	case BK_TARGET_F: o->nx = 64; break;
	case BK_TARGET_FORM: {
		static const int per[5] = {0, 256, 32, 10, 6};
		o->nx = per[o->ndomain];
		break;
	}
	default: break;
	}
}

/* The seed of island r > 0: splitmix64 of (seed, r), folded to 32 bits as
 * --seed is; distinct islands draw distinct streams. */
static unsigned long island_seed(unsigned long seed, int r)
{
	uint64_t z = (uint64_t)seed + 0x9e3779b97f4a7c15ull * (uint64_t)(r + 1);
	z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
	z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
	z ^= z >> 31;
	return (unsigned long)(z & 0xffffffffu);
}

static int setup(job *J)
{
	search_cli *a = J->a;
	const cli_cmd *cmd = J->cmd;
	bk_search_options *so = &J->so;
	bk_search_defaults(so);
	/* islands: --evals is the budget of the whole run, shared out; island 0
	 * keeps --seed, so one rank is the run brdfkit makes */
	int K = isl_size(), R = isl_rank();
	if (a->evals < K) /* decided alike on every rank: no rank may leave alone */
		return cli_usage(cmd, "--evals %ld: fewer fits than the %d islands", a->evals, K);
	so->islands = K;
	so->island = R;
	so->evals = a->evals / K + (R < a->evals % K);
	/* and so is the enumeration's cap: the islands together fit the trees one
	 * process would, each its share, and the mix of enumerated and evolved
	 * fits stays that of one process at the same total budget */
	so->enum_max = a->enum_max / K + (R < a->enum_max % K);
	so->seed = R == 0 ? (unsigned long)a->seed : island_seed((unsigned long)a->seed, R);
	so->threads = (int)a->threads;
	so->enum_size = (int)a->enum_size;
	so->generation = (int)a->generation;
	so->relative = a->relative;
	so->max_cost = a->max_cost > 0 ? a->max_cost : HUGE_VAL;
	int v;
	static const char *const objs[] = {"rmse", "max", "albedo"};
	if (parse_word(cmd, "--objective", a->objective, objs, 3, &v))
		return 2;
	so->objective = (bk_objective)v;
	static const char *const precs[] = {"double", "single", "half"};
	static const bk_precision pv[] = {BK_F64, BK_F32, BK_F16};
	if (parse_word(cmd, "--precision", a->precision, precs, 3, &v))
		return 2;
	so->precision = pv[v];
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
	memset(g, 0, sizeof *g);
	g->ops = bk_grammar_default_ops();
	char err[256];
	if (a->ops && bk_grammar_parse_ops(a->ops, &g->ops, err, sizeof err))
		return cli_usage(cmd, "--ops: %s", err);
	g->consts[0] = 1.0;
	g->nconsts = 1;
	g->max_params = a->max_params >= 0 ? (int)a->max_params : J->kind == BK_TARGET_ENV ? 10 : 4;
	g->max_size = (int)a->max_size;
	switch (J->kind) {
	case BK_TARGET_VF2D:
	case BK_TARGET_VF:
	case BK_TARGET_SPEC: so->shape = BK_SHAPE_F0; break;
	case BK_TARGET_ENV: so->shape = BK_SHAPE_PAIR; break;
	default: so->shape = BK_SHAPE_PLAIN; break;
	}
	if (env_halves(J) && K > 1) /* --checkpoint and --resume: the table */
		return cli_usage(cmd, "--env-form mix runs three searches in turn: no islands with it");
	if (env_halves(J) && so->max_cost <= 3)
		return cli_usage(cmd, "--env-form mix: --max-cost %g leaves nothing to the halves (mix(B, S, f0) costs 2 itself)",
		                 so->max_cost);
	if (env_halves(J) && a->evals < 8 * (long)so->generation)
		return cli_usage(cmd, "--env-form mix: --evals %ld is too few to share among three searches (at least %d)",
		                 a->evals, 8 * so->generation);
	if (env_in_f0(J)) { /* one tree in f0, NoV, r scored on f0 A + B over the f0 list, as compare scores */
		so->shape = BK_SHAPE_PLAIN;
		J->to.env_f0_form = 1;
	}
	/* constraints that hold for the target: on unless --no-constraints */
	so->inherit = a->inherit;
	so->nonneg = !a->no_constraints && J->kind != BK_TARGET_FORM;
	so->env_bound = !a->no_constraints && J->kind == BK_TARGET_ENV && !env_in_f0(J);
	return 0;
}

/* The inputs a candidate may read: --inputs, or what the target provides
 * (f0 is the shape's own factor for the F0 shape; a with r: both, the
 * convention gives shaders both). */
static int setup_inputs(job *J)
{
	unsigned prov = J->screen.provides;
	if (J->kind == BK_TARGET_F)
		prov &= 1u << BK_IN_LOH | 1u << BK_IN_F0; /* r is a dummy there */
	if (J->a->inputs)
		return parse_inputs(J->cmd, J->a->inputs, prov, &J->so.grammar.inputs);
	if (J->so.shape == BK_SHAPE_F0)
		prov &= ~(1u << BK_IN_F0);
	J->so.grammar.inputs = prov;
	return 0;
}

typedef struct seeds {
	const char *text[MAX_SEEDS], *text_b[MAX_SEEDS], *name[MAX_SEEDS];
	char *owned[MAX_SEEDS]; /* texts made here (V x Schlick) */
	double p[MAX_SEEDS][BK_MAX_PARAMS];
	int n;
} seeds;

/* Samples of s where seed k of sd, at its start constants, is NaN or
 * infinite and the target is not (where: the first); s->n if it does not
 * evaluate. */
static size_t seed_nonfinite(const seeds *sd, int k, const bk_samples *s, char *where, size_t len)
{
	bk_form_error fe;
	bk_form *f[2] = {bk_form_parse(sd->text[k], &fe), sd->text_b[k] ? bk_form_parse(sd->text_b[k], &fe) : NULL};
	size_t bad = s->n;
	snprintf(where, len, "no sample: the form does not compile");
	if (f[0] && (!sd->text_b[k] || f[1])) {
		bk_fit_spec sp;
		memset(&sp, 0, sizeof sp);
		sp.s = s;
		sp.form[0] = f[0];
		sp.form[1] = f[1] ? f[1] : f[0];
		bad = bk_fit_nonfinite(&sp, sd->p[k], where, len);
	}
	bk_form_free(f[0]);
	bk_form_free(f[1]);
	return bad;
}

/* A --start form that is NaN or infinite on the samples s at its start is
 * refused, as fit refuses it: its error over the samples where it is finite
 * would be no error of the form. (The catalog's own forms, seeded when no
 * --start is given, are scored whatever they are: catalog rows say "not
 * finite".) Returns 0, or 1 after the message. */
static int check_starts(const job *J, const seeds *sd, const bk_samples *s)
{
	char where[256];
	for (int k = 0; J->a->nstart && k < sd->n; k++) {
		size_t bad = seed_nonfinite(sd, k, s, where, sizeof where);
		if (bad)
			return cli_fail("search", "--start '%.60s': the form is NaN or infinite at %zu of %zu samples where "
			                "the target is finite (first at %s): fix the form or the domain", J->a->start[k], bad,
			                s->n, where);
	}
	return 0;
}

static int setup_seeds(job *J, seeds *sd)
{
	const char *tag = catalog_tag(J->kind);
	memset(sd, 0, sizeof *sd);
	if (J->a->nstart == 0 && tag) /* every catalog entry of the target */
		for (size_t i = 0; i < bk_catalog_count() && sd->n < MAX_SEEDS; i++) {
			const bk_catalog_entry *e = bk_catalog_at(i);
			/* vf: the V-only entries times Schlick's F, as compare scores them */
			int v_only = J->kind == BK_TARGET_VF && !strcmp(e->target, "V");
			/* env in f0: the forms in f0, and each split pair as f0*(A) + (B) */
			int in_f0 = env_in_f0(J) && !strcmp(e->target, "env_f0");
			if ((strcmp(e->target, tag) && !v_only && !in_f0) || !entry_fits(e, J->screen.provides))
				continue; /* published forms seed whatever their size */
			char *t = NULL; /* a text made here: V x Schlick, or a pair as one form in f0 */
			if (v_only || (env_in_f0(J) && e->form_b)) {
				size_t len = strlen(e->form) + (e->form_b ? strlen(e->form_b) : 0) + 32;
				if (!(t = malloc(len)))
					return cli_fail("search", "out of memory");
				if (v_only)
					snprintf(t, len, "(%s)*F_schlick(f0, 1, LoH)", e->form);
				else
					snprintf(t, len, "f0*(%s) + (%s)", e->form, e->form_b);
			}
			sd->owned[sd->n] = t;
			sd->text[sd->n] = t ? t : e->form;
			sd->text_b[sd->n] = t ? NULL : e->form_b;
			sd->name[sd->n] = e->name;
			memcpy(sd->p[sd->n], e->defaults, sizeof e->defaults);
			sd->n++;
		}
	if (J->a->nstart == 0 && J->kind == BK_TARGET_F && sd->n < MAX_SEEDS) { /* the baseline every F form is held to */
		sd->text[sd->n] = "F_schlick(f0, 1, LoH)";
		sd->text_b[sd->n] = NULL;
		sd->name[sd->n] = "F_schlick";
		for (int j = 0; j < BK_MAX_PARAMS; j++)
			sd->p[sd->n][j] = 1.0;
		sd->n++;
	}
	for (int k = 0; k < J->a->nstart; k++) {
		for (int j = 0; j < k; j++)
			if (!strcmp(J->a->start[j], J->a->start[k]))
				return cli_usage(J->cmd, "--start '%.60s' given twice", J->a->start[k]);
		const bk_catalog_entry *e = bk_catalog_find(J->a->start[k]);
		if (e && tag && strcmp(e->target, tag) && !(env_in_f0(J) && !strcmp(e->target, "env_f0")))
			return cli_usage(J->cmd, "--start %s: a %s form, not one of target %s", e->name, e->target,
			                 bk_target_name(J->kind));
		if (e && e->form_b && env_in_f0(J))
			return cli_usage(J->cmd, "--start %s: a split pair; with --env-form f0 write it as 'f0*(A) + (B)'",
			                 e->name);
		if (!e && J->kind == BK_TARGET_ENV && !env_in_f0(J))
			return cli_usage(J->cmd, "--start '%s': target env takes catalog names (A and B)", J->a->start[k]);
		if (e && !entry_fits(e, J->screen.provides))
			return cli_usage(J->cmd, "--start %s reads an input target %s does not provide", e->name,
			                 bk_target_name(J->kind));
		bk_form_error fe;
		bk_form *f = e ? NULL : bk_form_parse(J->a->start[k], &fe);
		if (!e && !f) {
			fprintf(stderr, "brdfkit search: --start:1:%d: %s\n", fe.column, fe.message);
			return 2;
		}
		if (f && (bk_form_inputs(f) & ~J->screen.provides)) {
			bk_form_free(f);
			return cli_usage(J->cmd, "--start '%s' reads an input target %s does not provide", J->a->start[k],
			                 bk_target_name(J->kind));
		}
		bk_form_free(f);
		sd->text[sd->n] = e ? e->form : J->a->start[k];
		sd->text_b[sd->n] = e ? e->form_b : NULL;
		sd->name[sd->n] = e ? e->name : NULL;
		for (int j = 0; j < BK_MAX_PARAMS; j++)
			sd->p[sd->n][j] = e ? e->defaults[j] : 1.0;
		sd->n++;
	}
	J->so.seeds = sd->text;
	J->so.seeds_b = sd->text_b;
	J->so.seed_names = sd->name;
	J->so.seed_p = (const double(*)[BK_MAX_PARAMS])sd->p;
	J->so.nseeds = sd->n;
	return check_starts(J, sd, &J->screen);
}

/* ---- --env-form mix: the two halves first ------------------------------------ */

/* f0 A + B is linear in f0: it is mix(B, S, f0) with S = A + B (the albedo,
 * f0 = 1) and B (f0 = 0), exactly. Each half is a smooth function of (NoV, r)
 * that a cheap form fits well (S within 0.013 rmse at cost 7, B within 0.008),
 * while f0 A + B as one form is harder to grow: so 3/8 of the budget
 * searches S, 3/8 B (the same grammar without f0, the same seed), and
 * the pairs of their fronts, as mix(B, S, f0) with B's parameters after S's
 * and each half's fitted constants as the start, seed the search of the forms
 * in f0 with the last quarter (measured: 1,200,000 fits split 1/4, 1/4, 1/2
 * put only compositions on the front at cost <= 15; the halves' fits are
 * both where the gain is and faster, 256 screening samples against 3 x 256
 * per form, and no f0). Only the compositions on the
 * Pareto front of (cost after sharing, the halves' combined rmse) are kept:
 * the others are dominated before any fit. They are held to the constraints
 * as generated forms are, and listed in no catalog row. */
#define MAX_HALVES 24

typedef struct halves {
	char *text[MAX_HALVES], name[MAX_HALVES][32];
	double p[MAX_HALVES][BK_MAX_PARAMS];
	int n;
	long evals;  /* the two searches' fits */
} halves;

typedef struct half_member {
	bk_expr tree;
	int np;
	double p[BK_MAX_PARAMS], err;
} half_member;

/* One half's search on the screening grid at that f0; its front out. */
static int half_search(job *J, double f0, half_member *out, size_t *nout, long *evals, char *err, size_t errlen)
{
	bk_target_options t = J->to_screen;
	t.nf0 = 1;
	t.f0[0] = f0;
	bk_samples sm;
	if (bk_target_build(&t, &sm, NULL, NULL, err, errlen))
		return -1;
	bk_search_options o = J->so;
	o.screen = &sm;
	o.seeds = o.seeds_b = o.seed_names = NULL;
	o.seed_p = NULL;
	o.nseeds = 0;
	o.exempt_seeds = INT_MAX;
	o.evals = J->so.evals / 8 * 3;
	o.max_cost = J->so.max_cost - 2; /* mix(B, S, f0) adds a subtract and a multiply-add */
	o.grammar.inputs &= ~(1u << BK_IN_F0); /* f0 is the composition's */
	const char *what = f0 == 1 ? "S = A + B" : "B";
	int rc = -1;
	bk_search *S = bk_search_new(&o, err, errlen);
	if (S) {
		double t0 = bk_clock_now(), last = t0;
		while ((rc = bk_search_step(S, err, errlen)) == 1)
			if (bk_clock_now() - last >= PROGRESS_EVERY) {
				last = bk_clock_now();
				fprintf(stderr, "search: %s half: %ld fits\n", what, bk_search_evals(S));
			}
		if (rc >= 0) {
			size_t idx[MAX_FRONT];
			size_t n = bk_search_front(S, idx, MAX_FRONT);
			*nout = 0;
			for (size_t i = 0; i < n; i++) {
				const bk_cand *c = bk_search_at(S, idx[i]);
				half_member *h = &out[(*nout)++];
				h->tree = c->tree[0];
				h->np = bk_expr_nparams(&c->tree[0]);
				memcpy(h->p, c->p, sizeof h->p);
				h->err = c->err; /* rounded (search.h): no choice below hinges on a last bit */
			}
			*evals = bk_search_evals(S);
			fprintf(stderr, "search: %s half: %ld fits in %.1f s, front %zu\n", what, *evals, bk_clock_now() - t0,
			        *nout);
			rc = 0;
		}
		bk_search_free(S);
	}
	bk_samples_free(&sm);
	return rc;
}

typedef struct composed {
	char *text;
	double cost, est, p[BK_MAX_PARAMS];
} composed;

static int by_cost_then_est(const void *a, const void *b)
{
	const composed *x = a, *y = b;
	if (x->cost != y->cost)
		return x->cost < y->cost ? -1 : 1;
	if (x->est != y->est)
		return x->est < y->est ? -1 : 1;
	return strcmp(x->text, y->text);
}

static int run_halves(job *J, halves *hv)
{
	char err[512];
	static half_member hs[MAX_FRONT], hb[MAX_FRONT];
	size_t ns = 0, nb = 0;
	long es = 0, eb = 0;
	memset(hv, 0, sizeof *hv);
	if (half_search(J, 1.0, hs, &ns, &es, err, sizeof err) || half_search(J, 0.0, hb, &nb, &eb, err, sizeof err))
		return cli_fail("search", "--env-form mix: %s", err);
	hv->evals = es + eb;
	composed *c = calloc(ns * nb + 1, sizeof *c);
	size_t nc = 0;
	if (!c)
		return cli_fail("search", "out of memory");
	int rc = 0;
	for (size_t i = 0; i < ns && !rc; i++)
		for (size_t j = 0; j < nb && !rc; j++) {
			if (hs[i].np + hb[j].np > J->so.grammar.max_params)
				continue;
			bk_expr b = hb[j].tree;
			bk_expr_shift_params(&b, hs[i].np);
			char ts[4200], tb[4200], text[8600];
			if (bk_expr_print(&hs[i].tree, ts, sizeof ts) < 0 || bk_expr_print(&b, tb, sizeof tb) < 0)
				continue;
			snprintf(text, sizeof text, "mix(%s, %s, f0)", tb, ts);
			bk_form_error fe;
			bk_form *f = bk_form_parse(text, &fe);
			if (!f)
				continue;
			bk_ops ops;
			bk_form_count(f, &ops);
			bk_form_free(f);
			double cost = bk_ops_cost(&ops, J->so.simple_cost, J->so.complex_cost);
			if (cost > J->so.max_cost)
				continue;
			composed *m = &c[nc];
			if (!(m->text = strdup(text))) {
				rc = -1;
				break;
			}
			m->cost = cost;
			/* the rmse of f0 A + B over the f0 list if the halves' errors were
			 * independent and equal across f0: a ranking, not a promise */
			m->est = bk_search_round_err(sqrt((hs[i].err * hs[i].err + hb[j].err * hb[j].err) / 2));
			memcpy(m->p, hs[i].p, sizeof(double) * (size_t)hs[i].np);
			memcpy(m->p + hs[i].np, hb[j].p, sizeof(double) * (size_t)hb[j].np);
			nc++;
		}
	if (!rc) {
		qsort(c, nc, sizeof *c, by_cost_then_est);
		double best = HUGE_VAL; /* the Pareto front: each cheaper than all better-ranked */
		for (size_t k = 0; k < nc && hv->n < MAX_HALVES; k++)
			if (c[k].est < best) {
				best = c[k].est;
				hv->text[hv->n] = c[k].text;
				c[k].text = NULL;
				memcpy(hv->p[hv->n], c[k].p, sizeof hv->p[0]);
				snprintf(hv->name[hv->n], sizeof hv->name[0], "halves %d", hv->n + 1);
				hv->n++;
			}
	}
	for (size_t k = 0; k < nc; k++)
		free(c[k].text);
	free(c);
	if (rc)
		return cli_fail("search", "out of memory");
	fprintf(stderr, "search: %d compositions mix(B, S, f0) seed the search of forms in f0\n", hv->n);
	return 0;
}

static void halves_free(halves *hv)
{
	for (int k = 0; k < hv->n; k++)
		free(hv->text[k]);
	hv->n = 0;
}

/* The compositions after the seeds of sd (which alone get catalog rows),
 * held to the constraints, and the rest of the budget to the search. */
static void seed_halves(job *J, const seeds *sd, const halves *hv)
{
	static const char *text[MAX_SEEDS + MAX_HALVES], *text_b[MAX_SEEDS + MAX_HALVES], *name[MAX_SEEDS + MAX_HALVES];
	static double p[MAX_SEEDS + MAX_HALVES][BK_MAX_PARAMS];
	int n = 0;
	for (int k = 0; k < sd->n; k++, n++) {
		text[n] = sd->text[k];
		text_b[n] = sd->text_b[k];
		name[n] = sd->name[k];
		memcpy(p[n], sd->p[k], sizeof p[0]);
	}
	for (int k = 0; k < hv->n; k++, n++) {
		text[n] = hv->text[k];
		text_b[n] = NULL;
		name[n] = hv->name[k];
		memcpy(p[n], hv->p[k], sizeof p[0]);
	}
	J->so.seeds = text;
	J->so.seeds_b = text_b;
	J->so.seed_names = name;
	J->so.seed_p = (const double(*)[BK_MAX_PARAMS])p;
	J->so.nseeds = n;
	J->so.exempt_seeds = sd->n;
	J->so.evals -= hv->evals;
}

/* ---- the run ------------------------------------------------------------------ */

static void progress(const job *J, int final)
{
	size_t idx[MAX_FRONT];
	size_t nf = bk_search_front(J->S, idx, MAX_FRONT);
	char best[256] = "";
	size_t k = 0;
	for (size_t i = 0; i < nf && k < sizeof best - 40; i += (nf + 3) / 4) { /* a few cost levels */
		const bk_cand *c = bk_search_at(J->S, idx[i]);
		k += (size_t)snprintf(best + k, sizeof best - k, "%scost %g: %.3g", k ? ", " : "", c->cost, c->err);
	}
	double dt = bk_clock_now() - J->seconds;
	long n = bk_search_evals(J->S);
	fprintf(stderr, "%ssearch: %ld fits, %.0f fits/s, front %zu (%s)%s", isatty(2) && !final ? "\r" : "", n,
	        dt > 0 ? (double)(n - J->start_evals) / dt : 0.0, nf, best, isatty(2) && !final ? "\033[K" : "\n");
}

/* The checkpoint's text: header (an island's line, or NULL), then the
 * search's state (malloc'd into *text). 0, or -1 (out of memory). */
static int checkpoint_text(const job *J, const char *header, char **text, size_t *len)
{
	*text = NULL;
	FILE *m = open_memstream(text, len);
	if (!m)
		return -1;
	if (header)
		fputs(header, m);
	int bad = bk_search_save(J->S, m);
	if (fclose(m) || bad) {
		free(*text);
		*text = NULL;
		return -1;
	}
	return 0;
}

/* A checkpoint that cannot be written is an error, intermediate ones too:
 * the run stops (the last one written stays whole, and --resume goes on
 * from it), never a shorter run that looks whole. */
static int save_checkpoint(const job *J, char *err, size_t errlen)
{
	char *text;
	size_t len;
	ck_file c;
	if (checkpoint_text(J, NULL, &text, &len)) {
		snprintf(err, errlen, "%s: out of memory", J->a->checkpoint);
		return -1;
	}
	int rc = ck_write(&c, J->a->checkpoint, text, len, err, errlen) || ck_commit(&c, NULL, err, errlen) ? -1 : 0;
	free(text);
	return rc;
}

static int run_search(job *J)
{
	char err[512];
	if (!(J->S = bk_search_new(&J->so, err, sizeof err)))
		return cli_fail("search", "%s", err);
	if (J->a->resume) {
		FILE *f = fopen(J->a->resume, "r");
		if (!f)
			return cli_fail("search", "--resume %s: cannot be read (%s)", J->a->resume, strerror(errno));
		int rc = bk_search_load(J->S, f, err, sizeof err);
		fclose(f);
		if (rc)
			return cli_fail("search", "--resume %s: %s", J->a->resume, err);
		fprintf(stderr, "search: resumed at %ld fits\n", bk_search_evals(J->S));
	}
	struct sigaction old;
	catch_interrupt(&old);
	J->seconds = bk_clock_now();
	J->start_evals = bk_search_evals(J->S);
	double last = J->seconds;
	long next_ck = J->a->every > 0 ? (bk_search_evals(J->S) / J->a->every + 1) * J->a->every : -1;
	int rc, ck_failed = 0;
	while ((rc = bk_search_step(J->S, err, sizeof err)) == 1 && !stop_asked) {
		double now = bk_clock_now();
		if (now - last >= (isatty(2) ? 0.25 : PROGRESS_EVERY)) {
			progress(J, 0);
			last = now;
		}
		if (J->a->checkpoint && next_ck > 0 && bk_search_evals(J->S) >= next_ck) {
			if ((ck_failed = save_checkpoint(J, err, sizeof err) != 0))
				break;
			next_ck = (bk_search_evals(J->S) / J->a->every + 1) * J->a->every;
		}
		if (J->a->seconds > 0 && now - J->seconds >= J->a->seconds)
			break;
	}
	sigaction(SIGINT, &old, NULL);
	J->interrupted = stop_asked;
	if (ck_failed)
		return cli_fail("search", "--checkpoint %s", err);
	if (rc < 0)
		return cli_fail("search", "%s", err);
	progress(J, 1);
	if (J->a->checkpoint && save_checkpoint(J, err, sizeof err))
		return cli_fail("search", "--checkpoint %s", err);
	return 0;
}

/* ---- islands (an MPI job: analysis/cli/islands.h) --------------------------- */

/* A rank's checkpoint is FILE.RANK, with the previous round kept as
 * FILE.RANK.prev: a job killed while the ranks commit a round leaves each
 * rank the round before it at least, and a resume takes the newest round
 * every rank has (save_islands, load_islands). */
#define ISLAND_MAGIC "brdfkit-island-checkpoint 1"

static void island_path(const char *base, int r, const char *suffix, char *buf, size_t len)
{
	snprintf(buf, len, "%s.%d%s", base, r, suffix);
}

/* Every rank's failure text (empty: none) printed by rank 0, one line each.
 * Collective. Returns 1. */
static int islands_fail(const char *what, const char *mine)
{
	int K = isl_size();
	char (*all)[256] = isl_rank() == 0 ? calloc((size_t)K, 256) : NULL;
	isl_gather_text(mine, all);
	for (int r = 0; all && r < K; r++)
		if (all[r][0])
			fprintf(stderr, "search: %s: rank %d: %s\n", what, r, all[r]);
	if (isl_rank() == 0 && !all)
		fprintf(stderr, "search: %s failed on some rank (out of memory for the messages)\n", what);
	free(all);
	return 1;
}

/* The round a checkpoint file holds: -1 absent, -2 not one of this job's. */
static long island_round(const char *path, const job *J)
{
	FILE *f = fopen(path, "r");
	if (!f)
		return errno == ENOENT ? -1 : -2;
	int r, k;
	long round, m, n;
	int ok = fscanf(f, ISLAND_MAGIC " island %d of %d round %ld migrate %ld migrants %ld", &r, &k, &round, &m, &n) == 5;
	fclose(f);
	return ok && r == isl_rank() && k == isl_size() && m == J->a->migrate && n == J->a->migrants ? round : -2;
}

/* Two phases, so that no rank moves to round `round` before all have it on
 * disk: each writes a temporary; only when all succeeded does each keep its
 * last round as .prev and rename the new one into place. Collective. */
static int save_islands(const job *J, long round)
{
	char path[4096], prev[4112], err[256] = "", head[256];
	int R = isl_rank();
	island_path(J->a->checkpoint, R, "", path, sizeof path);
	island_path(J->a->checkpoint, R, ".prev", prev, sizeof prev);
	snprintf(head, sizeof head, ISLAND_MAGIC " island %d of %d round %ld migrate %ld migrants %ld\n", R, isl_size(),
	         round, J->a->migrate, J->a->migrants);
	char *text;
	size_t len;
	ck_file c;
	int ok = checkpoint_text(J, head, &text, &len) == 0;
	if (!ok)
		snprintf(err, sizeof err, "%.200s: out of memory", path);
	ok = ok && ck_write(&c, path, text, len, err, sizeof err) == 0;
	free(text);
	if (isl_any(!ok)) {
		if (ok)
			ck_abort(&c);
		return islands_fail("--checkpoint", ok ? "" : err);
	}
	ok = ck_commit(&c, prev, err, sizeof err) == 0;
	return isl_any(!ok) ? islands_fail("--checkpoint", ok ? "" : err) : 0;
}

/* The newest round every rank has, loaded. Collective. */
static int load_islands(job *J, long *round)
{
	char path[4096], prev[4112], err[512] = "";
	int R = isl_rank();
	island_path(J->a->resume, R, "", path, sizeof path);
	island_path(J->a->resume, R, ".prev", prev, sizeof prev);
	long cur = island_round(path, J), old = island_round(prev, J);
	long want = isl_min(cur > old ? cur : old);
	const char *from = cur == want ? path : old == want ? prev : NULL;
	int ok = want >= 0 && from;
	if (!ok)
		snprintf(err, sizeof err, "%.200s: no checkpoint of this job's round %ld (island %d of %d, --migrate %ld, "
		         "--migrants %ld; a resume needs the same ranks and options)", path, want, R, isl_size(),
		         J->a->migrate, J->a->migrants);
	if (ok) {
		FILE *f = fopen(from, "r");
		char line[256];
		ok = f && fgets(line, sizeof line, f) && bk_search_load(J->S, f, err, sizeof err) == 0;
		if (!ok && f) {
			char why[400];
			snprintf(why, sizeof why, "%.390s", err);
			snprintf(err, sizeof err, "%.100s: %.300s", from, why);
		} else if (!f) {
			snprintf(err, sizeof err, "%.200s: cannot be read", from);
		}
		if (f)
			fclose(f);
	}
	if (isl_any(!ok))
		return islands_fail("--resume", ok ? "" : err);
	*round = want;
	if (R == 0)
		fprintf(stderr, "search: resumed %d islands at round %ld (%ld fits)\n", isl_size(), want,
		        isl_sum(bk_search_evals(J->S)));
	else
		isl_sum(bk_search_evals(J->S));
	return 0;
}

/* Writes the candidates idx[0..n) of the search to a buffer (malloc'd). */
static char *export_text(const bk_search *S, const size_t *idx, size_t n, size_t *len)
{
	char *buf = NULL;
	FILE *f = open_memstream(&buf, len);
	if (!f)
		return NULL;
	int bad = bk_search_export(S, idx, n, f);
	if (fclose(f) || bad) {
		free(buf);
		return NULL;
	}
	return buf;
}

static int import_text(bk_search *S, const char *in, size_t n, char *err, size_t errlen)
{
	FILE *f = fmemopen((void *)in, n, "r");
	if (!f) {
		snprintf(err, errlen, "out of memory reading migrants");
		return -1;
	}
	size_t added;
	int rc = bk_search_import(S, f, &added, err, errlen);
	fclose(f);
	return rc;
}

/* Migration: up to --migrants members of this island's front, spread over
 * its cost range, to the next rank of the ring. Collective. */
static int migrate(job *J)
{
	size_t front[MAX_FRONT], pick[MAX_FRONT];
	size_t nf = bk_search_front(J->S, front, MAX_FRONT), n = 0;
	size_t want = (size_t)J->a->migrants < nf ? (size_t)J->a->migrants : nf;
	for (size_t i = 0; i < want; i++) /* evenly over the front, its ends included */
		pick[n++] = front[want > 1 ? i * (nf - 1) / (want - 1) : 0];
	size_t len = 0, nin = 0;
	char *out = export_text(J->S, pick, n, &len), *in = NULL, err[256] = "";
	int ok = out != NULL;
	if (isl_any(!ok)) {
		free(out);
		return islands_fail("migration", ok ? "" : "out of memory");
	}
	ok = isl_ring(out, len, &in, &nin) == 0;
	free(out);
	if (ok && import_text(J->S, in, nin, err, sizeof err))
		ok = 0;
	free(in);
	return isl_any(!ok) ? islands_fail("migration", ok ? "" : *err ? err : "out of memory") : 0;
}

static int take_island(void *ctx, int rank, const char *in, size_t n)
{
	job *J = ctx;
	char err[256];
	if (rank == 0) /* rank 0's own candidates are already in its search */
		return 0;
	if (import_text(J->S, in, n, err, sizeof err)) {
		fprintf(stderr, "search: merging island %d: %s\n", rank, err);
		return -1;
	}
	return 0;
}

/* The final merge: every island's candidates into rank 0's search, in rank
 * order (a candidate found on several islands is kept as the lowest rank
 * found it). With --merge-fronts each island sends its screening front alone:
 * the final front is drawn from the screening front of the merged candidates,
 * and a member of the front of a union is on the front of its own part, so
 * front.csv is the same (tests/mpi.sh) for a merge of O(K x front) candidates
 * instead of O(fits) (README "On a cluster"). Rank 0 sends nothing: its
 * candidates are already in its search. Collective. */
static int merge_islands(job *J)
{
	size_t n = isl_rank() == 0 ? 0 : bk_search_count(J->S), len = 0;
	size_t *idx = malloc(sizeof(size_t) * (n ? n : 1));
	if (idx && J->a->merge_fronts)
		n = bk_search_front(J->S, idx, n); /* the whole front: its every member, not MAX_FRONT */
	else
		for (size_t i = 0; idx && i < n; i++)
			idx[i] = i;
	char *out = idx ? export_text(J->S, idx, n, &len) : NULL;
	free(idx);
	int ok = out != NULL;
	if (isl_any(!ok)) {
		free(out);
		return islands_fail("merge", ok ? "" : "out of memory");
	}
	double t0 = bk_clock_now();
	ok = isl_gather(out, len, take_island, J) == 0;
	long bytes = isl_sum((long)len);
	free(out);
	if (!ok)
		return 1; /* rank 0 said why */
	if (isl_rank() == 0)
		fprintf(stderr, "search: merged %d islands%s: %ld bytes, %.3f s\n", isl_size(),
		        J->a->merge_fronts ? " (fronts)" : "", bytes, bk_clock_now() - t0);
	return 0;
}

/* The checkpoint files, checked before any work (else a bad path is found
 * when the first is written, minutes on, or the last, with the whole run
 * lost): each rank its own, FILE.RANK and FILE.RANK.prev on islands. Then
 * the temporaries of killed saves to them that prove themselves ours are
 * removed (search_ck.h). Collective. 0, or 1 after the message. */
static int check_checkpoints(const job *J)
{
	const search_cli *a = J->a;
	char err[700] = "", path[4096], prev[4112];
	int K = isl_size(), bad = 0;
	for (int pass = 0; pass < 2; pass++) {
		const char *base = pass ? a->resume : a->checkpoint;
		island_path(base ? base : "", isl_rank(), "", path, sizeof path);
		island_path(base ? base : "", isl_rank(), ".prev", prev, sizeof prev);
		if (base && pass == 0)
			bad = K > 1 ? ck_check_write(path, a->out, err, sizeof err) || ck_check_write(prev, a->out, err, sizeof err)
			            : ck_check_write(base, a->out, err, sizeof err);
		else if (base)
			bad = K > 1 ? ck_check_read(path, a->out, 0, err, sizeof err) || ck_check_read(prev, a->out, 0, err, sizeof err)
			            : ck_check_read(base, a->out, 1, err, sizeof err);
		const char *what = pass ? "--resume" : "--checkpoint";
		if (K > 1 && isl_any(bad))
			return islands_fail(what, bad ? err : "");
		if (bad)
			return cli_fail("search", "%s %s", what, err);
		if (base) /* the rank's own */
			ck_clean(K > 1 ? path : base);
	}
	return 0;
}

/* The search as an island of an MPI job: rounds of --migrate fits per
 * island, a migration after each, checkpoints at round ends, the merge into
 * rank 0. Every rank runs this; each decision that ends a round is agreed
 * (isl_any), so the ranks always make the same collective calls. */
static int run_islands(job *J)
{
	char err[512] = "";
	int R = isl_rank();
	J->S = bk_search_new(&J->so, err, sizeof err);
	if (isl_any(!J->S))
		return islands_fail("setting up", J->S ? "" : err);
	long round = 0;
	if (J->a->resume && load_islands(J, &round))
		return 1;
	struct sigaction old;
	catch_interrupt(&old);
	J->seconds = bk_clock_now();
	double last = J->seconds;
	long every = J->a->every, M = J->a->migrate, start_evals = isl_sum(bk_search_evals(J->S));
	J->start_evals = start_evals;
	int done = 0, rc = 0;
	for (;;) {
		round++;
		int failed = 0;
		while (!done && bk_search_evals(J->S) < round * M) {
			int st = bk_search_step(J->S, err, sizeof err);
			failed = st < 0;
			done = st != 1;
		}
		if (isl_any(failed)) {
			rc = islands_fail("search", failed ? err : "");
			break;
		}
		if (migrate(J)) {
			rc = 1;
			break;
		}
		long total = isl_sum(bk_search_evals(J->S));
		double now = bk_clock_now();
		int more = isl_any(!done);
		int stop = isl_any(stop_asked || (R == 0 && J->a->seconds > 0 && now - J->seconds >= J->a->seconds));
		if (R == 0 && (now - last >= (isatty(2) ? 0.25 : PROGRESS_EVERY) || !more || stop)) {
			size_t one;
			double dt = now - J->seconds;
			fprintf(stderr, "%ssearch: round %ld, %ld fits on %d islands, %.0f fits/s, island 0's front %zu%s",
			        isatty(2) && more && !stop ? "\r" : "", round, total, isl_size(),
			        dt > 0 ? (double)(total - start_evals) / dt : 0.0, bk_search_front(J->S, &one, MAX_FRONT),
			        isatty(2) && more && !stop ? "\033[K" : "\n");
			last = now;
		}
		int last_round = !more || stop;
		if (J->a->checkpoint && (last_round || (round * M) / every > ((round - 1) * M) / every) &&
		    save_islands(J, round)) {
			rc = 1;
			break;
		}
		if (last_round) {
			J->interrupted = isl_any(stop_asked);
			break;
		}
	}
	sigaction(SIGINT, &old, NULL);
	if (rc)
		return rc;
	J->total_evals = isl_sum(bk_search_evals(J->S));
	return merge_islands(J);
}

/* Values of the member's forms on the samples in precision prec. */
static int member_values(const member *m, const bk_samples *s, const double *p, bk_precision prec, double *v)
{
	for (int q = 0; q < s->ncomp; q++) {
		size_t lo = s->start[q];
		const double *in[BK_IN_COUNT];
		for (int k = 0; k < BK_IN_COUNT; k++)
			in[k] = s->in[k] + lo;
		if (bk_form_eval(m->f[q < 1 || !m->f[1] ? 0 : 1], prec, s->start[q + 1] - lo, in, p, v + lo))
			return -1;
	}
	return 0;
}



/* --objective albedo: the least-squares point of fit's fitter minimises the
 * values' error, not the albedo's; from it, Lawson's minimax on the cells'
 * albedo errors (fit/albfit.h). The constants are rounded to 7 significant
 * digits (a float literal, and no last-bit difference of libm survives it)
 * and kept where they lower the albedo's max error; the standard errors stay
 * those of the least-squares point, and the message says so. */
static void albedo_minimax(job *J, member *m)
{
	bk_albfit *af = bk_albfit_new(&J->s, m->f[0], m->spec.np);
	if (!af)
		return;
	double p[BK_MAX_PARAMS], before = bk_albfit_max(af, m->res.p), after;
	memcpy(p, m->res.p, sizeof p);
	bk_fit_options o = BK_FIT_OPTIONS_INIT;
	o.max_iterations = 500;
	if (bk_albfit_run(af, p, 1, &o, &after) == 0 && after < before) {
		for (int j = 0; j < m->spec.np; j++) {
			char lit[32];
			snprintf(lit, sizeof lit, "%.7g", p[j]);
			p[j] = strtod(lit, NULL);
		}
		if (bk_albfit_max(af, p) < before) {
			memcpy(m->res.p, p, sizeof p);
			size_t k = strlen(m->res.message);
			snprintf(m->res.message + k, sizeof m->res.message - k, "%sconstants moved from the least-squares point "
			         "by the albedo minimax (standard errors: of that point)", k ? "; " : "");
		}
	}
	bk_albfit_free(af);
}

/* The member on the full samples: fitted with fit's full fitter (several
 * starts, minimax for the max objective, optimality check, constants rounded
 * to what their standard errors justify) unless it is a catalog row at its
 * published constants; then its error in the search precision, constraints
 * on the denser grid, half-precision error and stability. */
static int score_member(job *J, member *m, const double *start, int fit)
{
	bk_form_error fe;
	m->f[0] = bk_form_parse(m->text, &fe);
	m->f[1] = m->text_b ? bk_form_parse(m->text_b, &fe) : NULL;
	if (!m->f[0] || (m->text_b && !m->f[1]))
		return -1;
	bk_fit_spec *sp = &m->spec;
	memset(sp, 0, sizeof *sp);
	bk_fit_options o = BK_FIT_OPTIONS_INIT;
	sp->opt = o;
	sp->opt.max_iterations = 500;
	sp->s = &J->s;
	sp->form[0] = m->f[0];
	sp->form[1] = m->f[1] ? m->f[1] : m->f[0];
	sp->np = bk_form_nparams(m->f[0]);
	if (m->f[1] && bk_form_nparams(m->f[1]) > sp->np)
		sp->np = bk_form_nparams(m->f[1]);
	for (int j = 0; j < BK_MAX_PARAMS; j++) {
		sp->lower[j] = -HUGE_VAL;
		sp->upper[j] = HUGE_VAL;
		sp->start[j] = start[j];
	}
	sp->relative = J->so.relative;
	sp->starts = 2;
	sp->seed = 1;
	sp->minimax = J->so.objective == BK_OBJ_MAX;
	sp->digits = BK_FIT_DIGITS_SE;
	if (fit && sp->np > 0) {
		if (bk_fit_run(sp, &m->res) < 0) {
			if (!m->c)
				return -1;
			/* a screening member the full fitter cannot start from (not finite
			 * on the denser grid: a pole between the screening samples) is
			 * dropped, not the search */
			memset(&m->res, 0, sizeof m->res);
			memcpy(m->res.p, start, sizeof m->res.p);
			m->status = 1;
			m->err = HUGE_VAL;
			snprintf(m->verdict, sizeof m->verdict, "not analysed");
			return 0;
		}
		if (J->so.objective == BK_OBJ_ALBEDO && !m->f[1])
			albedo_minimax(J, m);
	} else {
		memset(&m->res, 0, sizeof m->res);
		memcpy(m->res.p, start, sizeof m->res.p);
		m->res.optimal = -1;
	}
	bk_fit_evaluate(sp, m->res.p, &m->res.fitted);
	double *v = malloc(sizeof(double) * J->s.n);
	if (!v)
		return -1;
	int rc = member_values(m, &J->s, m->res.p, J->so.precision, v);
	m->status = 0;
	int finite = 1;
	if (rc == 0) {
		bk_samples_metrics(&J->s, v, NULL, &m->prec);
		finite = m->prec.nonfinite == 0;
		size_t na = J->s.ncomp == 2 ? J->s.start[1] : 0;
		for (size_t i = 0; i < J->s.n; i++) {
			if (!isfinite(v[i]) && isfinite(J->s.y[i]))
				m->status = 1;
			if (m->c && m->c->seed_name) /* published seeds: kept whatever the constraints (search.c) */
				continue;
			if (J->so.nonneg && v[i] < 0)
				m->status = 1;
			if (J->so.env_bound && i < na && (v[i] < -BK_SEARCH_ENV_SLACK || v[na + i] < -BK_SEARCH_ENV_SLACK ||
			                                  v[i] + v[na + i] > 1 + BK_SEARCH_ENV_SLACK))
				m->status = 1;
		}
		m->err = bk_search_round_err(bk_search_error(&J->so, &J->s, v, &m->prec));
		if (!isfinite(m->err))
			m->status = 1;
		bk_fit_metrics h;
		rc = member_values(m, &J->s, m->res.p, BK_F16, v);
		bk_samples_metrics(&J->s, v, NULL, &h);
		m->f16_max = h.nonfinite ? HUGE_VAL : h.max_abs;
	}
	free(v);
	if (!finite) { /* the metrics skip what is not finite: over none they would read 0, a perfect fit */
		m->prec.rmse = m->prec.max_abs = m->prec.max_rel = HUGE_VAL;
		m->err = m->f16_max = HUGE_VAL;
	}
	size_t blen = strlen(m->text) + (m->text_b ? strlen(m->text_b) : 0) + 16; /* a --start form may be 16 KB */
	char *buf = malloc(blen);
	if (!buf)
		return -1;
	if (m->text_b)
		snprintf(buf, blen, "f0*(%s) + (%s)", m->text, m->text_b);
	else
		snprintf(buf, blen, "%s", m->text);
	bk_form *whole = bk_form_parse(buf, &fe);
	free(buf);
	if (!whole)
		return -1;
	bk_form_count(whole, &m->ops);
	m->cost = bk_ops_cost(&m->ops, J->so.simple_cost, J->so.complex_cost);
	bk_form_free(whole);
	/* stability in half, each half of a pair on its own: the worse verdict */
	static const char *const verdict[3] = {"as is", "with guards", "no"};
	int worst = 0, analysed = 1;
	for (int q = 0; finite && q < (m->text_b ? 2 : 1); q++) {
		bk_stability st;
		char e2[256];
		if (bk_stability_run(m->name, q ? m->text_b : m->text, sp->np ? m->res.p : NULL, BK_STAB_TOL, &st, e2,
		                     sizeof e2)) {
			analysed = 0;
			continue;
		}
		int w = st.safe_as_is ? 0 : st.guarded_ok ? 1 : 2; /* stability.h: a pole is never "as is" */
		if (w > worst) /* the worse of A and B */
			worst = w;
		bk_stability_free(&st);
	}
	snprintf(m->verdict, sizeof m->verdict, "%s", !finite ? "not finite" : analysed ? verdict[worst] : "not analysed");
	return rc;
}

static void member_free(member *m)
{
	bk_form_free(m->f[0]);
	bk_form_free(m->f[1]);
}

/* env --fetch-cost K: the DFG LUTs of compare (16² to 128², unorm8, half,
 * float, bilinear, clamp to edge) as rows of cost K (the fetch) + 1 (the mad
 * of f0·A + B), scored on the same samples. */
static void add_luts(job *J)
{
	static const int sizes[] = {16, 32, 64, 128};
	for (int q = 0; q < 4; q++)
		for (int fm = 0; fm < BK_LUT_FORMATS; fm++) {
			member *m = &J->m[J->nm];
			memset(m, 0, sizeof *m);
			snprintf(m->name, sizeof m->name, "LUT %dx%d %s", sizes[q], sizes[q], bk_lut_format_name((bk_lut_format)fm));
			cli_progress("LUT rows", 4 * fm + q + 1, 4 * BK_LUT_FORMATS);
			if (bk_lut_score(sizes[q], (bk_lut_format)fm, J->to.smith, &J->s, &m->prec, NULL))
				continue;
			m->lut = 1;
			m->text = "";
			m->ops.n[BK_K_MAD] = m->ops.simple = 1;
			m->cost = 1 + J->a->fetch_cost;
			m->err = bk_search_round_err(bk_search_error(&J->so, &J->s, NULL, &m->prec)); /* NaN for a relative rmse: no values */
			m->f16_max = NAN;
			snprintf(m->verdict, sizeof m->verdict, "-");
			J->nm++;
		}
}

/* Catalog rows (published and refitted), then the screening front refitted;
 * the final front: the refitted members no other beats at no greater cost. */
static int build_members(job *J, const seeds *sd)
{
	/* the screening front, and every seed that fitted: the published forms
	 * compete for the final front on the full samples, refitted, even where
	 * a generated form beat them on the screening grid */
	size_t idx[MAX_FRONT + MAX_SEEDS];
	size_t nf = bk_search_front(J->S, idx, MAX_FRONT);
	for (size_t i = 0, n = bk_search_count(J->S); i < n && nf < MAX_FRONT + MAX_SEEDS; i++) {
		const bk_cand *c = bk_search_at(J->S, i);
		int on = 0;
		for (size_t k = 0; k < nf && !on; k++)
			on = idx[k] == i;
		if (c->seed_name && c->status == BK_CAND_OK && !on)
			idx[nf++] = i;
	}
	J->m = calloc((size_t)(2 * sd->n) + nf + 4 * BK_LUT_FORMATS + 1, sizeof *J->m);
	if (!J->m)
		return -1;
	for (int k = 0; k < sd->n; k++) { /* catalog names, and typed --start forms as "start K" */
		const bk_catalog_entry *e = sd->name[k] ? bk_catalog_find(sd->name[k]) : NULL;
		for (int r = 0; r < 2; r++) {
			member *m = &J->m[J->nm++];
			m->entry = e;
			m->refit = r;
			if (e)
				snprintf(m->name, sizeof m->name, "%s%s%s", e->name, !strcmp(e->target, "V") ? " x F_schlick" : "",
				         r ? " (refit)" : "");
			else if (sd->name[k])
				snprintf(m->name, sizeof m->name, "%s%s", sd->name[k], r ? " (refit)" : "");
			else
				snprintf(m->name, sizeof m->name, "start %d%s", k + 1, r ? " (refit)" : "");
			m->text = sd->text[k];
			m->text_b = sd->text_b[k];
			cli_progress("catalog", J->nm, 2 * sd->n);
			if (score_member(J, m, sd->p[k], r))
				return -1;
		}
	}
	if (cli_seen(J->cmd, "--fetch-cost")) /* the textures the formulas compete with, on compare's axis (K = 0 too) */
		add_luts(J);
	for (size_t i = 0; i < nf; i++) {
		const bk_cand *c = bk_search_at(J->S, idx[i]);
		member *m = &J->m[J->nm++];
		m->c = c;
		if (c->seed_name) { /* a seed on the front: named after it */
			char slug[80];
			bk_slug(c->seed_name, slug, sizeof slug);
			snprintf(m->name, sizeof m->name, "seed_%s", slug);
		} else {
			snprintf(m->name, sizeof m->name, "search_%s_%zu", bk_target_name(J->kind), i + 1);
		}
		m->text = c->text;
		m->text_b = c->text_b;
		cli_progress("refit of the front", (int)i + 1, (int)nf);
		if (score_member(J, m, c->p, 1))
			return -1;
	}
	/* the final front over the refitted search members */
	double best = HUGE_VAL;
	int order[MAX_FRONT + 3 * MAX_SEEDS];
	int n = 0;
	for (int i = 0; i < J->nm; i++)
		if (J->m[i].c && J->m[i].status == 0)
			order[n++] = i;
	for (int i = 1; i < n; i++) /* by cost, then error, then text (insertion sort: n <= 48) */
		for (int j = i; j > 0; j--) {
			const member *x = &J->m[order[j - 1]], *y = &J->m[order[j]];
			int swap = y->cost < x->cost || (y->cost == x->cost && (y->err < x->err ||
			           (y->err == x->err && strcmp(y->text, x->text) < 0)));
			if (!swap)
				break;
			int t = order[j - 1];
			order[j - 1] = order[j];
			order[j] = t;
		}
	for (int i = 0; i < n; i++)
		if (J->m[order[i]].err < best) {
			best = J->m[order[i]].err;
			J->m[order[i]].front = 1;
		}
	return 0;
}

/* ---- outputs ------------------------------------------------------------------ */

static const char *objective_name(const job *J)
{
	static const char *const n[] = {"rmse", "max_abs", "albedo_max_abs"};
	if (J->so.relative && J->so.objective != BK_OBJ_ALBEDO)
		return J->so.objective == BK_OBJ_MAX ? "max_rel" : "rmse_rel";
	return n[J->so.objective];
}

static void header(FILE *f, const job *J, const char *what)
{
	fprintf(f, "# brdfkit %s search %s\n# command: %s\n# target: %s\n", BK_VERSION, what, J->command, J->s.description);
	if (J->so.islands > 1)
		fprintf(f, "# islands: %d MPI ranks (%s), --evals shared out, --migrate %ld fits per island between "
		        "migrations of %ld front members round a ring; found_at counts the fits of the member's island%s\n",
		        J->so.islands, isl_name(), J->a->migrate, J->a->migrants,
		        J->a->merge_fronts ? "; --merge-fronts: the candidates of island 0, and of the others their "
		                             "screening fronts" : "");
	fprintf(f, "# cost: simple*%g + complex*%g after folding, sharing and multiply-add fusion (brdfkit ops%s%s); "
	        "error: %s in %s precision on the target's samples; conventions: r perceptual roughness, a = r^2, "
	        "V includes 1/(4 NoL NoV)\n", J->so.simple_cost, J->so.complex_cost,
	        J->a->cost_model ? ", cost model " : "", J->a->cost_model ? J->a->cost_model : "", objective_name(J),
	        bk_precision_name(J->so.precision));
}

static void params_field(FILE *f, const double *p, int np)
{
	for (int j = 0; j < np; j++)
		fprintf(f, "%sp%d=%.17g", j ? ";" : "", j, p[j]);
}

/* m beats catalog row q: no dearer and no worse, one of them strictly. */
static int beats(const member *m, const member *q)
{
	return !q->c && !q->status && m->cost <= q->cost && m->err <= q->err && (m->cost < q->cost || m->err < q->err);
}

/* The first fields of a row: name, form, form_b, parameters. */
static void row_lead(FILE *f, const member *m)
{
	bk_csv_field(f, m->name);
	fputc(',', f);
	bk_csv_field(f, m->text);
	fputc(',', f);
	bk_csv_field(f, m->text_b ? m->text_b : "");
	fputc(',', f);
	params_field(f, m->res.p, m->spec.np);
}

/* --gpu columns: per chip ACO's net instructions and transcendental ops,
 * empty where nothing was compiled (a LUT row); each ends the line. */
static void gpu_header(FILE *f, const job *J)
{
	for (int c = 0; c < J->nchips; c++)
		fprintf(f, ",aco_%s_instructions,aco_%s_transcendental", J->chip[c], J->chip[c]);
	fputc('\n', f);
}

static void gpu_fields(FILE *f, const job *J, const member *m)
{
	for (int c = 0; c < J->nchips; c++)
		if (isnan(m->gpu_insn[c]))
			fputs(",,", f);
		else
			fprintf(f, ",%.0f,%.0f", m->gpu_insn[c], m->gpu_transc[c]);
	fputc('\n', f);
}

/* --gpu: the front's members and the catalog rows compiled for each chip
 * (brdfkit gpucost's shaders); screened candidates are not. */
static int gpu_columns(job *J)
{
	int n = J->nm, nc = J->nchips, rc = 0;
	const char **a = calloc((size_t)n + 1, sizeof *a), **b = calloc((size_t)n + 1, sizeof *b);
	const double **p = calloc((size_t)n + 1, sizeof *p);
	double *insn = calloc(2 * (size_t)n * (size_t)nc + 1, sizeof *insn), *transc = insn + n * nc;
	char err[700];
	if (!a || !b || !p || !insn)
		rc = cli_fail("search", "out of memory");
	for (int i = 0; !rc && i < n; i++) {
		const member *m = &J->m[i];
		int want = !m->lut && !m->status && (m->front || !m->c);
		a[i] = want ? m->text : NULL;
		b[i] = want ? m->text_b : NULL;
		p[i] = m->res.p;
	}
	if (!rc && bk_gpucost_texts(a, b, p, n, J->chip, nc, insn, transc, NULL, J->driver, sizeof J->driver, err,
	                            sizeof err))
		rc = cli_fail("search", "--gpu: %s", err);
	for (int i = 0; !rc && i < n; i++)
		for (int c = 0; c < nc; c++) {
			J->m[i].gpu_insn[c] = insn[i * nc + c];
			J->m[i].gpu_transc[c] = transc[i * nc + c];
		}
	free(a);
	free(b);
	free(p);
	free(insn);
	return rc;
}

static void write_front_csv(FILE *f, const job *J)
{
	header(f, J, "front (refitted on the full samples)");
	fprintf(f, "name,form,form_b,parameters,simple,complex,cost,error,rmse,max_abs,max_rel,albedo_max_abs,f16_max_abs,"
	        "stability_half,found_at,%sdominates", J->so.islands > 1 ? "island," : "");
	gpu_header(f, J);
	for (int i = 0; i < J->nm; i++) {
		const member *m = &J->m[i];
		if (!m->front)
			continue;
		row_lead(f, m);
		fprintf(f, ",%d,%d,%g,%.6g,%.6g,%.6g,%.6g,", m->ops.simple, m->ops.complex, m->cost, m->err, m->prec.rmse,
		        m->prec.max_abs, m->prec.max_rel);
		if (isfinite(m->prec.albedo_max_abs))
			fprintf(f, "%.6g", m->prec.albedo_max_abs);
		fprintf(f, ",%.6g,%s,%ld,", m->f16_max, m->verdict, m->c->found_at);
		if (J->so.islands > 1)
			fprintf(f, "%d,", m->c->island);
		char dom[2048] = "";
		for (int k = 0; k < J->nm; k++) /* the catalog rows this member beats */
			if (beats(m, &J->m[k]))
				snprintf(dom + strlen(dom), sizeof dom - strlen(dom), "%s%s", *dom ? ";" : "", J->m[k].name);
		bk_csv_field(f, dom);
		gpu_fields(f, J, m);
	}
}

static void write_catalog_csv(FILE *f, const job *J)
{
	header(f, J, "published forms on the same samples, published and refitted");
	fputs("name,form,form_b,parameters,cost,error,rmse,max_abs,albedo_max_abs,f16_max_abs,stability_half", f);
	gpu_header(f, J);
	for (int i = 0; i < J->nm; i++) {
		const member *m = &J->m[i];
		if (m->c)
			continue;
		row_lead(f, m);
		fprintf(f, ",%g,%.6g,%.6g,%.6g,", m->cost, m->err, m->prec.rmse, m->prec.max_abs);
		if (isfinite(m->prec.albedo_max_abs))
			fprintf(f, "%.6g", m->prec.albedo_max_abs);
		fputc(',', f);
		if (!isnan(m->f16_max)) /* NaN: no form (a LUT row); inf: not finite in half */
			fprintf(f, "%.6g", m->f16_max);
		fprintf(f, ",%s", m->verdict);
		gpu_fields(f, J, m);
	}
}

static void write_candidates_csv(FILE *f, const job *J)
{
	static const char *const st[] = {"ok", "not finite", "constraint", "fit failed"};
	size_t n = bk_search_count(J->S);
	size_t *idx = malloc(sizeof(size_t) * (n ? n : 1));
	char *on = calloc(n ? n : 1, 1);
	size_t nf = idx && on ? bk_search_front(J->S, idx, n) : 0;
	for (size_t i = 0; i < nf; i++)
		on[idx[i]] = 1;
	header(f, J, "every distinct candidate fitted (screening samples); front: on the screening front");
	fprintf(f, "found_at,%scost,error,status,front,seed,form,form_b\n", J->so.islands > 1 ? "island," : "");
	for (size_t i = 0; i < n; i++) {
		const bk_cand *c = bk_search_at(J->S, i);
		fprintf(f, "%ld,", c->found_at);
		if (J->so.islands > 1)
			fprintf(f, "%d,", c->island);
		fprintf(f, "%g,", c->cost);
		if (c->status == BK_CAND_OK)
			fprintf(f, "%.9g", c->err);
		fprintf(f, ",%s,%d,", st[c->status], on ? on[i] : 0);
		bk_csv_field(f, c->seed_name ? c->seed_name : "");
		fputc(',', f);
		bk_csv_field(f, c->text);
		fputc(',', f);
		bk_csv_field(f, c->text_b ? c->text_b : "");
		fputc('\n', f);
	}
	free(idx);
	free(on);
}

/* The cloud (grey), the front (joined, blue), the catalog published (red
 * triangles) and refitted (orange squares): error (log) against cost. */
static void write_svg(FILE *f, const job *J)
{
	const int W = 720, H = 460, L = 70, R = 20, T = 40, B = 50;
	double cmax = 1, emin = HUGE_VAL, emax = 0;
	for (int i = 0; i < J->nm; i++)
		if (J->m[i].status == 0 && (J->m[i].front || !J->m[i].c)) {
			cmax = fmax(cmax, J->m[i].cost);
			emin = fmin(emin, J->m[i].err);
			emax = fmax(emax, J->m[i].err);
		}
	if (!(emin < HUGE_VAL)) {
		emin = 1e-3;
		emax = 1;
	}
	cmax = ceil(cmax * 1.1);
	double l0 = floor(log10(fmax(emin, 1e-12))), l1 = ceil(log10(fmax(emax, 1e-12)) + 0.3);
	if (l1 <= l0)
		l1 = l0 + 1;
#define X(c) (L + (c) / cmax * (W - L - R))
#define Y(e) (T + (l1 - log10(e)) / (l1 - l0) * (H - T - B))
	fprintf(f, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" font-family=\"sans-serif\" "
	        "font-size=\"11\">\n<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n", W, H);
	fprintf(f, "<text x=\"%d\" y=\"20\" font-size=\"13\">search on %s: %s (%s precision) against cost</text>\n", L,
	        bk_target_name(J->kind), objective_name(J), bk_precision_name(J->so.precision));
	for (double d = l0; d <= l1; d++)
		fprintf(f, "<line x1=\"%d\" x2=\"%d\" y1=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/><text x=\"%d\" y=\"%.1f\" "
		        "text-anchor=\"end\">1e%g</text>\n", L, W - R, Y(pow(10, d)), Y(pow(10, d)), L - 4, Y(pow(10, d)) + 4, d);
	double step = cmax <= 20 ? 2 : cmax <= 60 ? 5 : 10;
	for (double c = 0; c <= cmax; c += step)
		fprintf(f, "<text x=\"%.1f\" y=\"%d\" text-anchor=\"middle\">%g</text>\n", X(c), H - B + 16, c);
	fprintf(f, "<text x=\"%d\" y=\"%d\" text-anchor=\"middle\">cost (simple*%g + complex*%g)</text>\n",
	        (L + W - R) / 2, H - 12, J->so.simple_cost, J->so.complex_cost);
	fprintf(f, "<rect x=\"%d\" y=\"%d\" width=\"%d\" height=\"%d\" fill=\"none\" stroke=\"black\"/>\n", L, T,
	        W - L - R, H - T - B);
	/* the cloud, one dot per pixel it covers (tens of thousands of candidates
	 * fall on a few thousand pixels: the file stays small) */
	unsigned char *seen = calloc((size_t)W * H, 1);
	for (size_t i = 0; seen && i < bk_search_count(J->S); i++) {
		const bk_cand *c = bk_search_at(J->S, i);
		if (c->status != BK_CAND_OK || c->cost > cmax || !(c->err >= pow(10, l0) && c->err <= pow(10, l1)))
			continue;
		int px = (int)lround(X(c->cost)), py = (int)lround(Y(c->err));
		if (px < 0 || px >= W || py < 0 || py >= H || seen[(size_t)py * W + px]++)
			continue;
		fprintf(f, "<circle cx=\"%d\" cy=\"%d\" r=\"1.5\" fill=\"#bbb\"/>\n", px, py);
	}
	free(seen);
	fputs("<polyline fill=\"none\" stroke=\"#1f5fbf\" stroke-width=\"1.5\" points=\"", f);
	for (int i = 0; i < J->nm; i++)
		if (J->m[i].front)
			fprintf(f, "%.1f,%.1f ", X(J->m[i].cost), Y(J->m[i].err));
	fputs("\"/>\n", f);
	for (int i = 0; i < J->nm; i++) {
		const member *m = &J->m[i];
		if (m->status || !(m->front || !m->c) || !(m->err > 0))
			continue;
		double x = X(m->cost), y = Y(m->err);
		if (m->front)
			fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"3.5\" fill=\"#1f5fbf\"><title>", x, y);
		else if (!m->refit)
			fprintf(f, "<path d=\"M%.1f %.1f l4 7 h-8 z\" fill=\"#c0392b\"><title>", x, y - 4);
		else
			fprintf(f, "<rect x=\"%.1f\" y=\"%.1f\" width=\"7\" height=\"7\" fill=\"#e67e22\"><title>", x - 3.5, y - 3.5);
		bk_html_text(f, m->name);
		fputs(": ", f);
		bk_html_text(f, m->text);
		fprintf(f, "</title></%s>\n", m->front ? "circle" : !m->refit ? "path" : "rect");
	}
	fprintf(f, "<g transform=\"translate(%d,%d)\"><circle cx=\"0\" cy=\"0\" r=\"3.5\" fill=\"#1f5fbf\"/><text x=\"8\" "
	        "y=\"4\">search front (refitted)</text><path d=\"M0 10 l4 7 h-8 z\" fill=\"#c0392b\"/><text x=\"8\" y=\"18\">"
	        "published</text><rect x=\"-3.5\" y=\"24\" width=\"7\" height=\"7\" fill=\"#e67e22\"/><text x=\"8\" "
	        "y=\"32\">published, refitted</text><circle cx=\"0\" cy=\"42\" r=\"1.5\" fill=\"#bbb\"/><text x=\"8\" "
	        "y=\"46\">every candidate (screening)</text></g>\n</svg>\n", W - R - 190, T + 12);
#undef X
#undef Y
}

static void write_section(FILE *f, const job *J)
{
	char base[256], id[256];
	const char *b = strrchr(J->a->out, '/');
	snprintf(base, sizeof base, "%s", b && b[1] ? b + 1 : J->a->out);
	bk_slug(base, id, sizeof id);
	fprintf(f, "<section id=\"search-%s\">\n<h2>Search on <code>%s</code> (%s)</h2>\n<p>", id,
	        bk_target_name(J->kind), id);
	bk_html_text(f, J->s.description);
	fprintf(f, "</p>\n<p>%ld candidate fits (seed %ld); error: %s in %s precision; cost: simple*%g + complex*%g. "
	        "<code>", J->total_evals, J->a->seed, objective_name(J), bk_precision_name(J->so.precision),
	        J->so.simple_cost, J->so.complex_cost);
	bk_html_text(f, J->command);
	const char *P = J->a->prefix ? J->a->prefix : "";
	fputs("</code></p>\n<img src=\"", f);
	bk_html_text(f, P);
	fputs("pareto.svg\" alt=\"error against cost\">\n<table>\n<tr><th>name</th><th>form</th><th>cost</th>"
	      "<th>error</th><th>rmse</th><th>max |err|</th><th>half</th><th>beats</th><th>files</th></tr>\n", f);
	for (int pass = 0; pass < 2; pass++)
		for (int i = 0; i < J->nm; i++) {
			const member *m = &J->m[i];
			if (pass == 0 ? !m->front : m->c != NULL)
				continue;
			fputs("<tr><td>", f);
			bk_html_text(f, m->name);
			fputs("</td><td><code>", f);
			bk_html_text(f, m->text);
			if (m->text_b) {
				fputs(" | ", f);
				bk_html_text(f, m->text_b);
			}
			fprintf(f, "</code></td><td>%g</td><td>%.3g</td><td>%.3g</td><td>%.3g</td><td>%s</td><td>", m->cost,
			        m->err, m->prec.rmse, m->prec.max_abs, m->verdict);
			for (int k = 0, first = 1; pass == 0 && k < J->nm; k++)
				if (beats(m, &J->m[k])) {
					fputs(first ? "" : ", ", f);
					bk_html_text(f, J->m[k].name);
					first = 0;
				}
			fputs("</td><td>", f);
			for (int k = 0; pass == 0 && k < 3; k++) { /* the member's heatmap and shaders */
				static const char *const file[3] = {"heatmap.png", "shader.glsl", "shader.hlsl"};
				if (k == 0 && !(J->to.kind != BK_TARGET_FORM || J->to.ndomain <= 2))
					continue;
				fputs("<a href=\"", f);
				bk_html_text(f, P);
				fprintf(f, "front/%s/%s\">%s</a> ", m->name, file[k], file[k]);
			}
			fputs("</td></tr>\n", f);
		}
	fputs("</table>\n</section>\n", f);
}

static int write_file(const char *dir, const char *name, void (*fn)(FILE *, const job *), const job *J)
{
	char path[4300];
	snprintf(path, sizeof path, "%.4000s/%s", dir, name);
	FILE *f = fopen(path, "w");
	if (!f)
		return -1;
	fn(f, J);
	return ferror(f) | fclose(f) ? -1 : 0;
}

static int write_outputs(const job *J)
{
	char err[512] = "";
	bk_out_dir od;
	if (bk_out_dir_begin(&od, J->a->out, J->command, err, sizeof err))
		return cli_fail("search", "--out %s", err);
	int rc = write_file(od.tmp, "front.csv", write_front_csv, J);
	rc |= write_file(od.tmp, "catalog.csv", write_catalog_csv, J);
	rc |= write_file(od.tmp, "candidates.csv", write_candidates_csv, J);
	rc |= write_file(od.tmp, "pareto.svg", write_svg, J);
	rc |= write_file(od.tmp, "section.html", write_section, J);
	char dir[4300];
	snprintf(dir, sizeof dir, "%.4000s/front", od.tmp);
	rc |= mkdir(dir, 0777);
	for (int i = 0; rc == 0 && i < J->nm; i++) {
		const member *m = &J->m[i];
		if (!m->front)
			continue;
		snprintf(dir, sizeof dir, "%.4000s/front/%s", od.tmp, m->name);
		char source[512];
		if (J->so.islands > 1)
			snprintf(source, sizeof source, "found by brdfkit search on %d islands (seed %ld, island %d's fit %ld; "
			         "%ld fits in all)", J->so.islands, J->a->seed, m->c->island, m->c->found_at, J->total_evals);
		else
			snprintf(source, sizeof source, "found by brdfkit search (seed %ld, fit %ld of %ld)", J->a->seed,
			         m->c->found_at, J->total_evals);
		fit_run v = {J->command, &J->to, J->a->t.domain, &J->s, &m->spec, &m->res, m->name, m->name, source,
		             "as the target's (see domain)", NULL, m->text_b != NULL, {m->f[0], m->f[1]}, 0};
		rc = mkdir(dir, 0777) || fit_write_into(&v, dir, err, sizeof err);
	}
	if (rc) {
		bk_out_dir_abort(&od);
		return cli_fail("search", "%s: writing the results failed%s%s", J->a->out, *err ? ": " : "", err);
	}
	return bk_out_dir_commit(&od, err, sizeof err) ? cli_fail("search", "--out %s", err) : 0;
}

static void report(const job *J)
{
	printf("search on %s: %ld fits, %zu distinct candidates; front (refitted on %zu samples, %s in %s):\n",
	       bk_target_name(J->kind), J->total_evals, bk_search_count(J->S), J->s.n, objective_name(J),
	       bk_precision_name(J->so.precision));
	for (int pass = 0; pass < 2; pass++)
		for (int i = 0; i < J->nm; i++) {
			const member *m = &J->m[i];
			if (pass == 0 ? !m->front : m->c != NULL)
				continue;
			printf("  %-28s cost %-4g %s %-10.4g %s%s%s\n", m->name, m->cost, objective_name(J), m->err, m->text,
			       m->text_b ? " | " : "", m->text_b ? m->text_b : "");
		}
}

/* ---- where the options act (cli.h) ----------------------------------------- */

/* The target kind; the env candidates (one form for the other targets; env:
 * split pairs A, B, or one form in f0, or mix: that seeded by two searches run
 * first); whether --checkpoint is given; whether anything is enumerated;
 * whether --cost-model names the weights; one process or the islands of an MPI
 * job (mpirun alone reaches them: no setup of the walk can). */
enum { DIM_TARGET, DIM_CANDS, DIM_CHECKPOINT, DIM_ENUM, DIM_MODEL, DIM_PROCS };
enum { CANDS_ONE, CANDS_PAIR, CANDS_F0, CANDS_MIX };
static const cli_dim dims[] = {
	FIT_TARGET_DIM,
	{"candidates", {"one", "pair", "f0", "mix"}, {NULL, " on env split pairs", " with --env-form f0", " with --env-form mix"}},
	{"checkpoint", {"none", "file"}, {" without --checkpoint FILE", NULL}},
	{"enumeration", {"none", "some"}, {" with --enum-size 0", NULL}},
	{"weights", {"given", "model"}, {NULL, " with --cost-model"}},
	{"processes", {"one", "islands"}, {" on one process", cli_unreached}},
};
#define EVERYWHERE(opt, example) {opt, NULL, CLI_EVERYWHERE, 0, NULL, example}
#define CANDS_ON(c) (1u << CANDS_##c)
static const cli_rule rules[] = {
	{"--nu", NULL, DIM_TARGET, FIT_ON(VF) | FIT_ON(SPEC), "it sets the half-vector cells of targets vf and spec", "4"},
	{"--nphi", NULL, DIM_TARGET, FIT_ON(VF) | FIT_ON(SPEC), "it sets the azimuth cells of targets vf and spec", "4"},
	{"--smith", NULL, DIM_TARGET, FIT_ON(ENV), "it sets the Smith model of target env", "schlick"},
	{"--ior", NULL, DIM_TARGET, FIT_ON(F), "it sets the exact Fresnel of target f", "1.4"},
	{"--k", NULL, DIM_TARGET, FIT_ON(F), "it sets the exact Fresnel of target f", "3"},
	{"--f0", NULL, DIM_TARGET, FIT_ON(VF2D) | FIT_ON(VF) | FIT_ON(SPEC) | FIT_ON(ENV),
	 "it sets f0 of targets vf2d, vf and spec, and env's f0 list with --env-form f0", "0.5"},
	{"--f0", NULL, DIM_CANDS, CANDS_ON(ONE) | CANDS_ON(F0) | CANDS_ON(MIX),
	 "their A and B hold no f0: give --env-form f0", "0.5"},
	{"--target-form", NULL, DIM_TARGET, FIT_ON(FORM), "it gives the expression of target form", "LoH"},
	{"--domain", NULL, DIM_TARGET, FIT_ON(FORM), "it gives the domain of target form", "LoH=0:1"},
	{"--r-range", NULL, DIM_TARGET, FIT_ALL & ~(FIT_ON(FORM) | FIT_ON(F)),
	 "the target has no roughness axis or takes --domain", "0:0.5"},
	{"--nr", NULL, DIM_TARGET, FIT_ALL & ~FIT_ON(F), "target f has no roughness axis", "8"},
	{"--nr", NULL, DIM_TARGET, FIT_ALL & ~FIT_ON(FORM),
	 "--domain sets the inputs of target form; --nx the cells per axis", "8"},
	{"--env-form", NULL, DIM_TARGET, FIT_ON(ENV), "it sets the form of the candidates of target env", "f0"},
	{"--no-constraints", NULL, DIM_TARGET, FIT_ALL & ~FIT_ON(FORM), "target form has no constraints to lift", NULL},
	{"--x-range", NULL, DIM_TARGET, FIT_ALL & ~FIT_ON(FORM), "--domain sets the inputs of target form", "0:0.5"},
	{"--fetch-cost", NULL, DIM_TARGET, FIT_ON(ENV), "LUT rows exist for target env only", "16"},
	{"--objective", "albedo", DIM_TARGET, FIT_ON(VF) | FIT_ON(SPEC),
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
	"--target env --env-form f0 --out o",
	"--target env --env-form mix --out o",
	"--target f --checkpoint ck --out o",
	"--target f --enum-size 0 --out o",
	"--target f --cost-model ir --out o",
	NULL};
static const cli_table table = {dims, 6, rules, sizeof rules / sizeof rules[0], setups};

/* The run's context (the table's dimensions), then cli_applicable. */
static int check_applicable(const job *J)
{
	const search_cli *a = J->a;
	int cands = J->kind != BK_TARGET_ENV ? CANDS_ONE : env_halves(J) ? CANDS_MIX : env_in_f0(J) ? CANDS_F0 : CANDS_PAIR;
	int ctx[] = {(int)J->kind, cands, a->checkpoint != NULL, a->enum_size > 0, a->cost_model != NULL,
	             isl_size() > 1};
	return cli_applicable(J->cmd, ctx);
}

static int search_main(int argc, char **argv)
{
	search_cli a = {.objective = "rmse", .precision = "double", .evals = 20000, .seed = 1, .threads = 0,
	                .max_params = -1, .max_size = 24, .enum_size = 5, .enum_max = 5000, .every = 5000, .generation = 256,
	                .migrate = 2000, .migrants = 8};
	cli_opt opts[] = {
		{.name = "--target", .kind = CLI_STR, .metavar = "T", .help = "vf2d, vf, spec, env, d, f or form", .dest = &a.t.target, .required = 1},
		{.name = "--target-form", .kind = CLI_FORM, .metavar = "EXPR", .help = "form: the expression to approximate (inputs only)", .dest = &a.t.target_form},
		{.name = "--domain", .kind = CLI_STR, .metavar = "IN=LO:HI,...", .help = "form: an interval for each input EXPR reads", .dest = &a.t.domain},
		{.name = "--out", .kind = CLI_STR, .metavar = "DIR", .help = "results directory (replaced whole)", .dest = &a.out, .required = 1},
		{.name = "--r-range", .kind = CLI_STR, .metavar = "LO:HI", .help = "perceptual roughness range (default 0:1)", .dest = &a.t.r_range},
		{.name = "--x-range", .kind = CLI_STR, .metavar = "LO:HI", .help = "LoH (vf2d, f), NoV (vf, spec, env) or NoH (d) range", .dest = &a.t.x_range},
		{.name = "--nx", .kind = CLI_INT, .metavar = "N", .help = "cells along x of the full grid the front is refitted on", .dest = &a.t.nx, .lo = 1, .hi = 4096},
		{.name = "--nr", .kind = CLI_INT, .metavar = "N", .help = "cells along roughness of that grid", .dest = &a.t.nr, .lo = 1, .hi = 4096},
		{.name = "--nu", .kind = CLI_INT, .metavar = "N", .help = "vf/spec: half-vector cells", .dest = &a.t.nu, .lo = 1, .hi = 1024},
		{.name = "--nphi", .kind = CLI_INT, .metavar = "N", .help = "vf/spec: azimuth cells", .dest = &a.t.nphi, .lo = 1, .hi = 1024},
		{.name = "--f0", .kind = CLI_LIST, .metavar = "F[,F...]", .help = "f0 of vf2d, vf, spec (default 0.04); env with --env-form f0: the f0 list f0 A + B is scored over (default 0.04,0.5,1)", .dest = &a.t.f0, .lo = 0, .hi = 1},
		{.name = "--smith", .kind = CLI_STR, .metavar = "MODEL", .help = "env: correlated (default), separable, schlick", .dest = &a.t.smith},
		{.name = "--ior", .kind = CLI_NUM, .metavar = "N", .help = "f: real index (default 1.5)", .dest = &a.t.ior, .lo = 0, .hi = 1e6, .lo_open = 1},
		{.name = "--k", .kind = CLI_NUM, .metavar = "K", .help = "f: extinction coefficient (conductor)", .dest = &a.t.k, .lo = 0, .hi = 1e6},
		{.name = "--evals", .kind = CLI_INT, .metavar = "N", .help = "budget: candidate fits (default 20000; reproducible); every candidate is kept: about 2.5 KB of memory a fit", .dest = &a.evals, .lo = 1, .hi = 1e9},
		{.name = "--seconds", .kind = CLI_NUM, .metavar = "S", .help = "also stop after S seconds (not reproducible)", .dest = &a.seconds, .lo = 0, .hi = 1e7, .lo_open = 1},
		{.name = "--seed", .kind = CLI_INT, .metavar = "S", .help = "seed of the generator (default 1)", .dest = &a.seed, .lo = 0, .hi = 4294967295.0},
		{.name = "--threads", .kind = CLI_INT, .metavar = "N", .help = "fitting threads (default: all cores); the result does not depend on it", .dest = &a.threads, .lo = 1, .hi = 64},
		{.name = "--inputs", .kind = CLI_STR, .metavar = "LIST", .help = "inputs a candidate may read (default: what the target provides)", .dest = &a.inputs},
		{.name = "--ops", .kind = CLI_STR, .metavar = "LIST", .help = "operations (default + - * / sq sqrt rsqrt rcp exp2 log2 min max saturate mix; also abs, clamp, pow, exp, log, and registry terms of 1 to 3 arguments by name, e.g. F_schlick, D_ggx, V_smith_ggx_correlated)", .dest = &a.ops},
		{.name = "--max-cost", .kind = CLI_NUM, .metavar = "C", .help = "candidates costlier than C are not fitted", .dest = &a.max_cost, .lo = 0, .hi = 1e6, .lo_open = 1},
		{.name = "--max-params", .kind = CLI_INT, .metavar = "K", .help = "constants fitted per candidate (default 4; env 10, A and B together)", .dest = &a.max_params, .lo = 0, .hi = BK_MAX_PARAMS},
		{.name = "--max-size", .kind = CLI_INT, .metavar = "N", .help = "nodes per tree (default 24)", .dest = &a.max_size, .lo = 1, .hi = BK_EXPR_MAX},
		{.name = "--enum-size", .kind = CLI_INT, .metavar = "N", .help = "enumerate every tree up to N nodes first (default 5), drawn as the fits need them: at most 1,048,576 trees (about 160 MB), then evolution", .dest = &a.enum_size, .lo = 0, .hi = 9},
		{.name = "--enum-max", .kind = CLI_INT, .metavar = "N", .help = "at most N fits of the enumeration (default 5000)", .dest = &a.enum_max, .lo = 0, .hi = 1e9},
		{.name = "--generation", .kind = CLI_INT, .metavar = "N", .help = "children per generation (default 256)", .dest = &a.generation, .lo = 1, .hi = 65536},
		{.name = "--objective", .kind = CLI_STR, .metavar = "rmse|max|albedo", .help = "the error of the front (default rmse; albedo: vf, spec)", .dest = &a.objective},
		{.name = "--relative", .kind = CLI_FLAG, .help = "relative residuals and errors", .dest = &a.relative},
		{.name = "--precision", .kind = CLI_STR, .metavar = "P", .help = "double (default), single or half: the precision a candidate's error is measured in", .dest = &a.precision},
		{.name = "--cost-weights", .kind = CLI_STR, .metavar = "simple=W,complex=W", .help = "weights of the cost (default simple=1,complex=4)", .dest = &a.weights},
		{.name = "--env-form", .kind = CLI_STR, .metavar = "pair|f0|mix", .help = "env: candidates are split pairs A, B (default) or one form in f0 scored on f0 A + B (as compare scores); mix: as f0, seeded also with mix(B, S, f0) of the fronts of searches of S = A + B and of B (3/8 of --evals each)", .dest = &a.env_form},
		{.name = "--gpu", .kind = CLI_STR, .metavar = "CHIPS", .help = "AMD instruction counts of the front and the catalog rows per chip (brdfkit gpucost), e.g. " BK_GPUCOST_DEFAULT_CHIPS, .dest = &a.gpu},
		{.name = "--cost-model", .kind = CLI_STR, .metavar = "NAME", .help = "named weights: ir (the default) or aco-polaris10, aco-vega10, aco-navi21, aco-gfx1100 (fitted to AMD's instruction counts)", .dest = &a.cost_model},
		{.name = "--start", .kind = CLI_FORM, .metavar = "NAME|FORM", .help = "seed the search with this (default: every catalog form of the target)", .dest = a.start, .repeat = MAX_SEEDS},
		{.name = "--fetch-cost", .kind = CLI_NUM, .metavar = "K", .help = "env: add compare's DFG LUT rows at cost K + 1 (a fetch priced as K simple ops; the talk's tiers: 16, 32, 48, 64)", .dest = &a.fetch_cost, .lo = 0, .hi = 1e6},
		{.name = "--no-constraints", .kind = CLI_FLAG, .help = "allow negative values (and env A + B > 1)", .dest = &a.no_constraints},
		{.name = "--inherit", .kind = CLI_FLAG, .help = "children start their fits from their parents' constants", .dest = &a.inherit},
		{.name = "--link-prefix", .kind = CLI_STR, .metavar = "P", .help = "prefix of the links in section.html (its place relative to the page)", .dest = &a.prefix},
		{.name = "--checkpoint", .kind = CLI_STR, .metavar = "FILE", .help = "write the state here every --every fits and at the end", .dest = &a.checkpoint},
		{.name = "--every", .kind = CLI_INT, .metavar = "K", .help = "fits between checkpoints (default 5000)", .dest = &a.every, .lo = 1, .hi = 1e9},
		{.name = "--resume", .kind = CLI_STR, .metavar = "FILE", .help = "continue from a checkpoint (same options; --evals may grow)", .dest = &a.resume},
		{.name = "--migrate", .kind = CLI_INT, .metavar = "M", .help = "MPI: fits per island between migrations (default 2000)", .dest = &a.migrate, .lo = 1, .hi = 1e9},
		{.name = "--merge-fronts", .kind = CLI_FLAG, .help = "MPI: rank 0 takes each island's front, not all its candidates (the same front.csv; fewer rows in candidates.csv)", .dest = &a.merge_fronts},
		{.name = "--migrants", .kind = CLI_INT, .metavar = "N", .help = "MPI: front members each island sends round the ring (default 8)", .dest = &a.migrants, .lo = 0, .hi = MAX_FRONT},
	};
	cli_cmd cmd = {"search", "Searches closed forms for a target: candidates over the formula IR, each fitted,\n"
	               "the Pareto front of error against GPU cost refitted in full. Writes front.csv,\n"
	               "catalog.csv, candidates.csv, front/NAME/ (as fit --out), pareto.svg, section.html into DIR.",
	               "--target T --out DIR [options]",
	               "The same --seed and --evals give the same files for any --threads. SIGINT (or SIGUSR1)\n"
	               "stops at the end of the current generation, writes the checkpoint and the front so far,\n"
	               "exits 130 (a SIGINT that was ignored when brdfkit started, as in a script's background\n"
	               "job, stays ignored). A checkpoint that cannot be written stops the run: exit 1, the last\n"
	               "one written kept for --resume.\n"
	               "On a cluster: mpirun -np K build/brdfkit-mpi search ... runs K islands (--evals shared\n"
	               "out, --migrate, --migrants; checkpoints FILE.RANK); rank 0 merges and writes DIR. The\n"
	               "same --seed, --evals and K give the same files for any --threads (README). To stop an\n"
	               "MPI job with its front, send SIGUSR1 to mpirun (it passes it to every rank); SIGINT or\n"
	               "SIGTERM to mpirun kill the ranks at once (Open MPI's rule): no front, exit 1, the\n"
	               "checkpoints of the last round kept for --resume.\n"
	               "Exit status: 0 done, 1 failed, 2 bad usage, 130 interrupted (results written).",
	               opts, (int)(sizeof opts / sizeof opts[0]), 0, 0, {0}};
	int rc = cli_parse_table(&cmd, &table, argc, argv);
	if (rc)
		return rc == 1 ? 0 : rc;
	job J;
	memset(&J, 0, sizeof J);
	seeds sd;
	memset(&sd, 0, sizeof sd);
	halves hv;
	memset(&hv, 0, sizeof hv);
	J.a = &a;
	J.cmd = &cmd;
	a.nstart = cli_seen(&cmd, "--start");
	if (!a.threads) {
		long n = sysconf(_SC_NPROCESSORS_ONLN);
		a.threads = n < 1 ? 1 : n > 64 ? 64 : n;
	}
	size_t k = isl_size() > 1 ? (size_t)snprintf(J.command, sizeof J.command, "mpirun -np %d brdfkit-mpi search",
	                                             isl_size())
	                          : (size_t)snprintf(J.command, sizeof J.command, "brdfkit search");
	for (int i = 0; i < argc && k < sizeof J.command; i++)
		k += (size_t)snprintf(J.command + k, sizeof J.command - k, " %s", argv[i]);
	if (bk_target_parse(a.t.target, &J.kind))
		return cli_usage(&cmd, "--target: unknown target '%s' (vf2d, vf, spec, env, d, f, form)", a.t.target);
	if (J.kind == BK_TARGET_ENV && a.env_form && strcmp(a.env_form, "pair") && strcmp(a.env_form, "f0") &&
	    strcmp(a.env_form, "mix")) /* before the context, which it sets */
		return cli_usage(&cmd, "--env-form: expected pair, f0 or mix, got '%.40s'", a.env_form);
	if ((rc = check_applicable(&J)))
		return rc;
	if (a.t.f0.n > 1 && !env_in_f0(&J))
		return cli_usage(&cmd, "--f0: one value, got %d (a list only for env with --env-form f0)", a.t.f0.n);
	if ((rc = fit_setup_target(&a.t, J.kind, &J.to)))
		return rc;
	char err[512];
	if (J.kind == BK_TARGET_FORM) {
		if (!a.t.target_form || !a.t.domain)
			return cli_usage(&cmd, "target form needs --target-form EXPR and --domain IN=LO:HI[,...]");
		J.to.form_text = a.t.target_form;
		if ((rc = fit_domain(&cmd, a.t.domain, &J.to)))
			return rc;
		if (bk_target_form_check(&J.to, err, sizeof err))
			return cli_usage(&cmd, "--target-form: %s", err);
	}
	if (cli_seen(&cmd, "--enum-size") && a.enum_size > a.max_size)
		return cli_usage(&cmd, "--enum-size %ld has no effect past --max-size %ld (no tree is larger)", a.enum_size,
		                 a.max_size);
	if ((rc = setup(&J)))
		return rc;
	/* rank 0 alone writes DIR and refits the front on the full samples:
	 * what it alone checks or builds is agreed on before the first exchange */
	int R = isl_rank(), K = isl_size();
	/* the checkpoint paths first: one inside --out is named as such, not as
	 * an entry --out does not list */
	if ((rc = check_checkpoints(&J)))
		return rc;
	rc = R == 0 && bk_out_dir_check(a.out, err, sizeof err) ? cli_fail("search", "--out %s", err) : 0;
	if (rc == 0 && R == 0 && J.nchips) { /* a missing driver is said now, not after the search */
		char gerr[700];
		if (bk_gpucost_check(J.chip, J.nchips, J.driver, sizeof J.driver, gerr, sizeof gerr))
			rc = cli_fail("search", "--gpu: %s", gerr);
	}
	if (K > 1 && isl_any(rc))
		return 1;
	if (rc)
		return rc;
	J.to_screen = J.to;
	screening_grid(&J.to_screen);
	/* the screening samples first: they are cheap, and the checks of --inputs
	 * and --start need what the target provides before the long reference */
	if (bk_target_build(&J.to_screen, &J.screen, NULL, NULL, err, sizeof err)) {
		rc = cli_fail("search", "%s", err);
		goto done;
	}
	if ((rc = setup_inputs(&J)) || (rc = setup_seeds(&J, &sd)))
		goto done;
	if (R == 0 && bk_target_build(&J.to, &J.s, cli_progress, "reference", err, sizeof err))
		rc = cli_fail("search", "%s", err);
	else if (R == 0) /* a pole between the screening samples */
		rc = check_starts(&J, &sd, &J.s);
	if (K > 1 && isl_any(rc))
		rc = 1;
	if (rc)
		goto done;
	J.so.screen = &J.screen;
	if (env_halves(&J)) {
		if ((rc = run_halves(&J, &hv)))
			goto done;
		seed_halves(&J, &sd, &hv);
	}
	if ((rc = K > 1 ? run_islands(&J) : run_search(&J)) || R > 0)
		goto done;
	if (K == 1)
		J.total_evals = bk_search_evals(J.S) + hv.evals;
	size_t one;
	if (bk_search_front(J.S, &one, 1) == 0) { /* nothing to write: say why instead of an empty front */
		rc = cli_fail("search", "no candidate fitted the target within the limits (--max-cost, --max-params, "
		              "--max-size, --ops, --inputs and the constraints) in %ld fits", J.total_evals);
		goto done;
	}
	if (build_members(&J, &sd)) {
		rc = cli_fail("search", "out of memory or a failed refit of the front");
		goto done;
	}
	report(&J);
	if (J.nchips && (rc = gpu_columns(&J)))
		goto done;
	rc = write_outputs(&J);
	if (rc == 0 && J.interrupted)
		rc = 130;
done:
	halves_free(&hv);
	for (int k = 0; k < sd.n; k++)
		free(sd.owned[k]);
	for (int i = 0; i < J.nm; i++)
		member_free(&J.m[i]);
	free(J.m);
	bk_search_free(J.S);
	bk_samples_free(&J.s);
	bk_samples_free(&J.screen);
	return rc;
}

int cmd_search(int argc, char **argv)
{
	if (isl_init(&argc, &argv))
		return 1;
	int rc = search_main(argc, argv);
	isl_end(rc);
	return rc;
}
