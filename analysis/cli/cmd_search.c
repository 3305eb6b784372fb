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
#include "search/catalogmap.h"
#include "search/halves.h"
#include "search/islands.h"
#include "search/seeds.h"
#include "search_front.h"
#include "search_write.h"
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

#define MAX_SEEDS BK_SEEDS_MAX
#define MAX_FRONT BK_SFRONT_MAX
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

typedef struct job {
	search_cli *a;
	const cli_cmd *cmd;
	bk_target_kind kind;
	bk_target_options to, to_screen;
	bk_samples s, screen;
	bk_search_options so;
	bk_search *S;
	bk_sfront F;
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

/* ---- set-up ----------------------------------------------------------------- */

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
	so->seed = R == 0 ? (unsigned long)a->seed : bk_islands_seed((unsigned long)a->seed, R);
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

/* Samples of s where seed k of sd, at its start constants, is NaN or
 * infinite and the target is not (where: the first); s->n if it does not
 * evaluate. */
static size_t seed_nonfinite(const bk_seeds *sd, int k, const bk_samples *s, char *where, size_t len)
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
static int check_starts(const job *J, const bk_seeds *sd, const bk_samples *s)
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

static int setup_seeds(job *J, bk_seeds *sd)
{
	const char *tag = bk_catmap_tag(J->kind);
	if (J->a->nstart == 0 && bk_seeds_catalog(sd, J->kind, env_in_f0(J), J->screen.provides))
		return cli_fail("search", "out of memory");
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
		if (e && !bk_catmap_reads_only(e, J->screen.provides))
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
		bk_seeds_add(sd, e ? e->form : J->a->start[k], e ? e->form_b : NULL, e ? e->name : NULL,
		             e ? e->defaults : NULL); /* at most MAX_SEEDS: --start's repeat */
	}
	bk_seeds_apply(sd, &J->so);
	return check_starts(J, sd, &J->screen);
}

/* ---- --env-form mix: the two halves first (fit/search/halves.h) ------------- */

typedef struct half_clock {
	const char *what;
	double t0, last;
} half_clock;

static void half_step(void *ctx, const char *half, const bk_search *s)
{
	half_clock *h = ctx;
	if (h->what != half) { /* a new half */
		h->what = half;
		h->t0 = h->last = bk_clock_now();
	}
	if (bk_clock_now() - h->last >= PROGRESS_EVERY) {
		h->last = bk_clock_now();
		fprintf(stderr, "search: %s half: %ld fits\n", half, bk_search_evals(s));
	}
}

static void half_done(void *ctx, const char *half, long fits, size_t front)
{
	half_clock *h = ctx;
	fprintf(stderr, "search: %s half: %ld fits in %.1f s, front %zu\n", half, fits,
	        h->what == half ? bk_clock_now() - h->t0 : 0.0, front);
}

static int run_halves(job *J, bk_halves *hv)
{
	char err[512];
	half_clock hc = {NULL, 0, 0};
	bk_halves_report rep = {half_step, half_done, &hc};
	if (bk_halves_run(&J->so, &J->to_screen, &rep, hv, err, sizeof err))
		return cli_fail("search", "--env-form mix: %s", err);
	fprintf(stderr, "search: %d compositions mix(B, S, f0) seed the search of forms in f0\n", hv->n);
	return 0;
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

/* What the run does between steps: a stop asked for, progress, checkpoints
 * every --every fits (a failed one stops the run), --seconds. */
typedef struct run_state {
	job *J;
	double last;
	long next_ck;
	int ck_failed;
	char err[512];
} run_state;

static int after_step(void *ctx, const bk_search *S)
{
	run_state *r = ctx;
	job *J = r->J;
	if (stop_asked)
		return 1;
	double now = bk_clock_now();
	if (now - r->last >= (isatty(2) ? 0.25 : PROGRESS_EVERY)) {
		progress(J, 0);
		r->last = now;
	}
	if (J->a->checkpoint && r->next_ck > 0 && bk_search_evals(S) >= r->next_ck) {
		if ((r->ck_failed = save_checkpoint(J, r->err, sizeof r->err) != 0))
			return 1;
		r->next_ck = (bk_search_evals(S) / J->a->every + 1) * J->a->every;
	}
	return J->a->seconds > 0 && now - J->seconds >= J->a->seconds;
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
	run_state st = {J, J->seconds, J->a->every > 0 ? (bk_search_evals(J->S) / J->a->every + 1) * J->a->every : -1, 0, ""};
	int rc = bk_search_run(J->S, after_step, &st, err, sizeof err);
	sigaction(SIGINT, &old, NULL);
	J->interrupted = stop_asked;
	if (st.ck_failed)
		return cli_fail("search", "--checkpoint %s", st.err);
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

/* The transport of the islands: analysis/cli/islands.h's collectives. */
static const bk_islands_transport *transport(void)
{
	static bk_islands_transport t;
	t = (bk_islands_transport){isl_rank(), isl_size(), isl_ring, isl_gather, isl_sum, isl_any};
	return &t;
}

/* The final merge into rank 0 (fit/search/islands.h): with --merge-fronts
 * each island sends its screening front alone; the final front is drawn from
 * the screening front of the merged candidates, and a member of the front of
 * a union is on the front of its own part, so front.csv is the same
 * (tests/mpi.sh) for a merge of O(K x front) candidates instead of O(fits)
 * (README "On a cluster"). Collective. */
static int merge_islands(job *J)
{
	char err[512];
	long bytes = 0;
	double t0 = bk_clock_now();
	if (bk_islands_merge(J->S, transport(), J->a->merge_fronts, &bytes, err, sizeof err)) {
		if (isl_rank() == 0 && *err)
			fprintf(stderr, "search: %s\n", err);
		return 1;
	}
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

/* The end of a round on every rank (fit/search/islands.h): progress on
 * rank 0, the agreed stop (SIGUSR1 on any rank, --seconds on rank 0),
 * checkpoints when a multiple of --every is crossed and at the last round. */
typedef struct isl_state {
	job *J;
	double last;
	long start_evals;
} isl_state;

static int round_end(void *ctx, long round, int more)
{
	isl_state *is = ctx;
	job *J = is->J;
	int R = isl_rank();
	long total = isl_sum(bk_search_evals(J->S)), M = J->a->migrate, every = J->a->every;
	double now = bk_clock_now();
	int stop = isl_any(stop_asked || (R == 0 && J->a->seconds > 0 && now - J->seconds >= J->a->seconds));
	if (R == 0 && (now - is->last >= (isatty(2) ? 0.25 : PROGRESS_EVERY) || !more || stop)) {
		size_t one;
		double dt = now - J->seconds;
		fprintf(stderr, "%ssearch: round %ld, %ld fits on %d islands, %.0f fits/s, island 0's front %zu%s",
		        isatty(2) && more && !stop ? "\r" : "", round, total, isl_size(),
		        dt > 0 ? (double)(total - is->start_evals) / dt : 0.0, bk_search_front(J->S, &one, MAX_FRONT),
		        isatty(2) && more && !stop ? "\033[K" : "\n");
		is->last = now;
	}
	int last_round = !more || stop;
	if (J->a->checkpoint && (last_round || (round * M) / every > ((round - 1) * M) / every) && save_islands(J, round))
		return -1;
	if (last_round)
		J->interrupted = isl_any(stop_asked);
	return last_round;
}

/* The search as an island of an MPI job: rounds of --migrate fits per
 * island, a migration after each, checkpoints at round ends, the merge into
 * rank 0. Every rank runs this; each decision that ends a round is agreed
 * (isl_any), so the ranks always make the same collective calls. */
static int run_islands(job *J)
{
	char err[512] = "";
	J->S = bk_search_new(&J->so, err, sizeof err);
	if (isl_any(!J->S))
		return islands_fail("setting up", J->S ? "" : err);
	long round = 0;
	if (J->a->resume && load_islands(J, &round))
		return 1;
	struct sigaction old;
	catch_interrupt(&old);
	J->seconds = bk_clock_now();
	isl_state is = {J, J->seconds, isl_sum(bk_search_evals(J->S))};
	J->start_evals = is.start_evals;
	int rc = bk_islands_run(J->S, transport(), J->a->migrate, (int)J->a->migrants, round, round_end, &is, err,
	                        sizeof err);
	sigaction(SIGINT, &old, NULL);
	if (rc == BK_ISLANDS_FAIL_SEARCH || rc == BK_ISLANDS_FAIL_MIGRATION)
		return islands_fail(rc == BK_ISLANDS_FAIL_SEARCH ? "search" : "migration", err);
	if (rc)
		return 1;
	J->total_evals = isl_sum(bk_search_evals(J->S));
	return merge_islands(J);
}

/* ---- outputs: search_write.h's writers, fit's files per member ------------- */

static int write_file(const char *dir, const char *name, void (*fn)(FILE *, const bk_swrite *), const bk_swrite *W)
{
	char path[4300];
	snprintf(path, sizeof path, "%.4000s/%s", dir, name);
	FILE *f = fopen(path, "w");
	if (!f)
		return -1;
	fn(f, W);
	return ferror(f) | fclose(f) ? -1 : 0;
}

static int write_outputs(const job *J, const bk_swrite *W)
{
	char err[512] = "";
	bk_out_dir od;
	if (bk_out_dir_begin(&od, J->a->out, J->command, err, sizeof err))
		return cli_fail("search", "--out %s", err);
	int rc = write_file(od.tmp, "front.csv", bk_swrite_front_csv, W);
	rc |= write_file(od.tmp, "catalog.csv", bk_swrite_catalog_csv, W);
	rc |= write_file(od.tmp, "candidates.csv", bk_swrite_candidates_csv, W);
	rc |= write_file(od.tmp, "pareto.svg", bk_swrite_svg, W);
	rc |= write_file(od.tmp, "section.html", bk_swrite_section, W);
	char dir[4300];
	snprintf(dir, sizeof dir, "%.4000s/front", od.tmp);
	rc |= mkdir(dir, 0777);
	for (int i = 0; rc == 0 && i < J->F.nm; i++) {
		const bk_sfront_member *m = &J->F.m[i];
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

/* The front refitted, the report, --gpu's columns, the files. */
static int finish(job *J, const bk_seeds *sd)
{
	bk_sfront *F = &J->F;
	*F = (bk_sfront){&J->so, J->S, &J->s, J->kind, J->to.smith, cli_seen(J->cmd, "--fetch-cost"), J->a->fetch_cost,
	                 cli_progress, NULL, 0};
	if (bk_sfront_build(F, sd))
		return cli_fail("search", "out of memory or a failed refit of the front");
	bk_swrite W = {F, &J->to, J->command, J->a->out, J->a->prefix, J->a->cost_model, J->a->seed, J->total_evals,
	               isl_name(), J->a->migrate, J->a->migrants, J->a->merge_fronts, J->chip, J->nchips};
	bk_swrite_report(stdout, &W);
	char err[700];
	if (J->nchips && bk_sfront_gpu(F, J->chip, J->nchips, J->driver, sizeof J->driver, err, sizeof err))
		return cli_fail("search", "--gpu: %s", err);
	return write_outputs(J, &W);
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
	bk_seeds sd;
	memset(&sd, 0, sizeof sd);
	bk_halves hv;
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
	bk_seeds_screening_grid(&J.to_screen);
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
		bk_halves_seed(&hv, &sd, &J.so);
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
	rc = finish(&J, &sd);
	if (rc == 0 && J.interrupted)
		rc = 130;
done:
	bk_halves_free(&hv);
	bk_seeds_free(&sd);
	bk_sfront_free(&J.F);
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
