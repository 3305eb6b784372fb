/*
 * cmd_search.c — brdfkit search: the search for closed forms of fit/search.h
 * on a target, its front refitted in full, written into one directory whole
 * or not at all: front.csv, candidates.csv, front/NAME/ (what fit writes),
 * pareto.svg and section.html.
 */
#include "clock.h"
#include "cmd.h"
#include "islands.h"
#include "lutcache.h"
#include "out.h"
#include "search/halves.h"
#include "search/islands.h"
#include "fit_out.h"
#include "search_setup.h"
#include "search_write.h"

#include <errno.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define PROGRESS_EVERY 10.0 /* seconds between log lines */

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
	if (bk_clock_now() - h->last >= PROGRESS_EVERY && !cli_quiet()) {
		h->last = bk_clock_now();
		fprintf(stderr, "search: %s half: %ld fits\n", half, bk_search_evals(s));
	}
}

static void half_done(void *ctx, const char *half, long fits, size_t front)
{
	half_clock *h = ctx;
	if (!cli_quiet())
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
	if (!cli_quiet())
		fprintf(stderr, "search: %d compositions mix(B, S, f0) seed the search of forms in f0\n", hv->n);
	return 0;
}

/* ---- the run ------------------------------------------------------------------ */

static void progress(const job *J, int final)
{
	if (cli_quiet())
		return;
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

/* What the run does between steps: a stop asked for, progress, checkpoints
 * every --every fits (a failed one stops the run), --seconds. With
 * --split-fits on several ranks every rank runs this after every step:
 * rank 0 alone writes the checkpoint (each holds the same search), and the
 * stop is agreed (a signal, a clock or a failed save of one rank stops all
 * of them after the same step). */
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
	int split = isl_size() > 1, stop = stop_asked;
	double now = bk_clock_now();
	if (!stop && now - r->last >= (isatty(2) ? 0.25 : PROGRESS_EVERY)) {
		progress(J, 0);
		r->last = now;
	}
	if (!stop && J->a->checkpoint && r->next_ck > 0 && bk_search_evals(S) >= r->next_ck) {
		if (isl_rank() == 0)
			r->ck_failed = ck_search_save(S, J->a->checkpoint, r->err, sizeof r->err) != 0;
		if (split)
			r->ck_failed = isl_any(r->ck_failed);
		r->next_ck = (bk_search_evals(S) / J->a->every + 1) * J->a->every;
	}
	stop = stop || r->ck_failed || (J->a->seconds > 0 && now - J->seconds >= J->a->seconds);
	return split ? isl_any(stop) : stop;
}

/* The run's certificate (fit/search.h): this process's, or over the islands
 * (each enumerates every K-th tree) the least size all of them completed and
 * their counts summed. Collective. */
static void certify(job *J)
{
	bk_search_certificate(J->S, &J->cert);
	if (!J->islands) /* one process, or --split-fits: each rank holds the whole search */
		return;
	int c = 0;
	while (c < BK_EXPR_MAX && !isl_any(J->cert.complete_size < c + 1))
		c++;
	J->cert.complete_size = c;
	for (int k = 0; k <= BK_EXPR_MAX; k++) {
		J->cert.drawn[k] = isl_sum(J->cert.drawn[k]);
		J->cert.twins[k] = isl_sum(J->cert.twins[k]);
		J->cert.fitted[k] = isl_sum(J->cert.fitted[k]);
	}
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
		if (!cli_quiet())
			fprintf(stderr, "search: resumed at %ld fits\n", bk_search_evals(J->S));
	}
	struct sigaction old;
	catch_interrupt(&old);
	J->seconds = bk_clock_now();
	J->start_evals = bk_search_evals(J->S);
	run_state st = {J, J->seconds, J->a->every > 0 ? (bk_search_evals(J->S) / J->a->every + 1) * J->a->every : -1, 0, ""};
	int rc = bk_search_run(J->S, after_step, &st, err, sizeof err);
	sigaction(SIGINT, &old, NULL);
	J->interrupted = isl_size() > 1 ? isl_any(stop_asked) : stop_asked; /* split: a signal to any rank */
	if (st.ck_failed) /* split: rank 0's message (the others' stderr is /dev/null) */
		return cli_fail("search", "--checkpoint %s", *st.err ? st.err : "failed on rank 0");
	if (rc < 0)
		return cli_fail("search", "%s", err);
	progress(J, 1);
	certify(J);
	int failed = J->a->checkpoint && isl_rank() == 0 && ck_search_save(J->S, J->a->checkpoint, err, sizeof err);
	if (isl_size() > 1 ? isl_any(failed) : failed)
		return cli_fail("search", "--checkpoint %s", failed ? err : "failed on rank 0");
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
 * (brdfkit-mpi(1), "The merge"). Collective. */
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
		size_t front[MAX_FRONT]; /* room for all it may write (main wrote 48 into one size_t) */
		double dt = now - J->seconds;
		fprintf(stderr, "%ssearch: round %ld, %ld fits on %d islands, %.0f fits/s, island 0's front %zu%s",
		        isatty(2) && more && !stop ? "\r" : "", round, total, isl_size(),
		        dt > 0 ? (double)(total - is->start_evals) / dt : 0.0, bk_search_front(J->S, front, MAX_FRONT),
		        isatty(2) && more && !stop ? "\033[K" : "\n");
		is->last = now;
	}
	int last_round = !more || stop;
	if (J->a->checkpoint && (last_round || (round * M) / every > ((round - 1) * M) / every) && ck_islands_save(&J->ck, J->S, round))
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
		return ck_islands_fail("setting up", J->S ? "" : err);
	long round = 0;
	if (J->a->resume && ck_islands_load(&J->ck, J->S, &round))
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
		return ck_islands_fail(rc == BK_ISLANDS_FAIL_SEARCH ? "search" : "migration", err);
	if (rc)
		return 1;
	J->total_evals = isl_sum(bk_search_evals(J->S));
	certify(J);
	return merge_islands(J);
}

/* ---- outputs: search_write.h's writers, fit's files per member ------------- */

/* dir/name written by fn; a failure names the file and the errno in err
 * (the first one: later files are not tried once one failed). */
static int write_file(const char *dir, const char *name, void (*fn)(FILE *, const bk_swrite *), const bk_swrite *W,
                      char *err, size_t errlen)
{
	char path[4300];
	if (*err)
		return -1;
	snprintf(path, sizeof path, "%.4000s/%s", dir, name);
	FILE *f = bk_out_fopen(path, err, errlen);
	if (!f)
		return -1;
	fn(f, W);
	return bk_out_fclose(f, path, err, errlen);
}

static int write_outputs(const job *J, const bk_swrite *W)
{
	char err[512] = "";
	bk_out_dir od;
	if (bk_out_dir_begin(&od, J->a->out, J->command, err, sizeof err))
		return cli_fail("search", "--out %s", err);
	int rc = write_file(od.tmp, "front.csv", bk_swrite_front_csv, W, err, sizeof err);
	rc |= write_file(od.tmp, "catalog.csv", bk_swrite_catalog_csv, W, err, sizeof err);
	rc |= write_file(od.tmp, "candidates.csv", bk_swrite_candidates_csv, W, err, sizeof err);
	if (!rc && bk_swrite_plot(W, od.tmp, err, sizeof err))
		rc = -1;
	rc |= write_file(od.tmp, "section.html", bk_swrite_section, W, err, sizeof err);
	if (W->vs)
		rc |= write_file(od.tmp, "vs_double.csv", bk_swrite_vs_csv, W, err, sizeof err);
	char dir[4300];
	snprintf(dir, sizeof dir, "%.4000s/front", od.tmp);
	if (!rc && mkdir(dir, 0777))
		rc = -1, snprintf(err, sizeof err, "%s/front: cannot create: %s", J->a->out, strerror(errno));
	/* one signature per kind (one form, or pairs): the inputs its front
	 * members read, r for a, as codegen FILE.csv:MEMBER writes them
	 * (member.c), so that members swap at one call site */
	unsigned sig[2] = {0, 0};
	for (int i = 0; i < J->F.nm; i++)
		for (int q = 0; J->F.m[i].front && q < 2; q++)
			sig[J->F.m[i].text_b != NULL] |= J->F.m[i].f[q] ? bk_form_inputs(J->F.m[i].f[q]) : 0;
	for (int k = 0; k < 2; k++)
		if (sig[k] >> BK_IN_A & 1)
			sig[k] = (sig[k] & ~(1u << BK_IN_A)) | 1u << BK_IN_R;
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
		/* a half front's member: its code in half (fit_out.c), its error the
		 * front's in f16, each sample in the order of its mads (each rounded
		 * twice, or fused) farther from the target (bk_form_eval_half_vs):
		 * whichever of the two a driver takes, the error is at most this
		 * (tests/lavapipe.sh holds lavapipe's float16_t run to it) */
		char error[400];
		int half = J->so.precision == BK_F16;
		snprintf(error, sizeof error, "%s %.3g in f16, as this half code computes it in either order of its mads "
		         "(each sample in the order farther from the target), max |error| %.3g; in f64: rmse %.3g",
		         bk_sfront_objective_name(&J->so), m->err, m->f16_max, m->res.fitted.rmse);
		fitout_run v = {J->command, &J->to, J->a->t.domain, &J->s, &m->spec, &m->res, m->name, m->name, source,
		             "as the target's (see domain)", NULL, m->text_b != NULL, {m->f[0], m->f[1]}, 0,
		             half, half ? error : NULL, sig[m->text_b != NULL]};
		if (mkdir(dir, 0777))
			rc = -1, snprintf(err, sizeof err, "%s/front/%s: cannot create: %s", J->a->out, m->name, strerror(errno));
		else
			rc = fitout_write_into(&v, dir, err, sizeof err);
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
	                 cli_progress, NULL, 0, 0};
	if (bk_sfront_build(F, sd))
		return cli_fail("search", "out of memory or a failed refit of the front");
	bk_swrite W = {F, &J->to, J->command, J->a->out, J->a->prefix, J->a->cost_model, J->a->seed, J->total_evals,
	               isl_name(), J->a->migrate, J->a->migrants, J->a->merge_fronts, J->chip, J->nchips, NULL, NULL, &J->cert,
	               J->a->env_form};
	bk_swrite_report(stdout, &W);
	char err[700];
	if (J->nchips && bk_sfront_gpu(F, J->chip, J->nchips, J->driver, sizeof J->driver, err, sizeof err))
		return cli_fail("search", "--gpu: %s", err);
	bk_halfvs vs;
	memset(&vs, 0, sizeof vs);
	if (J->a->vs_front) { /* read before the search (vs_front): the double front beside the half one */
		bk_halfvs_member *h = calloc((size_t)F->nm + 1, sizeof *h), *d = calloc((size_t)J->vs_fc.n + 1, sizeof *d);
		int nh = 0;
		for (int i = 0; h && i < F->nm; i++)
			if (F->m[i].front)
				h[nh++] = (bk_halfvs_member){F->m[i].name, F->m[i].cost, F->m[i].err};
		for (int i = 0; d && i < J->vs_fc.n; i++)
			d[i] = (bk_halfvs_member){J->vs_fc.row[i].name, J->vs_fc.row[i].cost, J->vs_fc.row[i].error};
		int bad = !h || !d || bk_halfvs_build(&vs, d, J->vs_fc.n, h, nh, BK_HALFVS_MAX_COST);
		free(h);
		free(d);
		if (bad)
			return cli_fail("search", "out of memory");
		W.vs = &vs;
		W.vs_path = J->a->vs_front;
		fprintf(stderr, "search: against the double front %s: %d of %d costs <= %g within %gx\n", J->a->vs_front,
		        vs.npass, vs.nrow, BK_HALFVS_MAX_COST, BK_HALFVS_TARGET);
	}
	int rc = write_outputs(J, &W);
	bk_halfvs_free(&vs);
	return rc;
}

static int search_main(int argc, char **argv)
{
	search_cli a = {.objective = "rmse", .precision = "double", .evals = 20000, .seed = 1, .threads = 0,
	                .max_params = -1, .max_size = 24, .enum_size = 5, .enum_max = 5000, .every = 5000, .generation = 256,
	                .migrate = 2000, .migrants = 8};
	cli_opt opts[] = {
		{.name = "--target", .kind = CLI_STR, .metavar = "T", .help = "vf2d, vf, spec, env, d, f, form, ms, sheen, table FILE or merl FILE (FILE as --target-file)", .dest = &a.t.target, .required = 1, .then = "--target-file", .then_values = "table merl"},
		{.name = "--target-file", .kind = CLI_STR, .metavar = "FILE", .help = "table: a CSV of samples (input columns, value, optional weight) or an EXR table as lut writes it; merl: a MERL binary BRDF (screening on about 4,096 of its samples, every k-th; the front refitted on all)", .dest = &a.t.target_file},
		{.name = "--channel", .kind = CLI_STR, .metavar = "NAME", .help = "table: the EXR channel (default: its only one); merl: r, g, b or luminance (default)", .dest = &a.t.channel},
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
		{.name = "--evals", .kind = CLI_INT, .metavar = "N", .help = "budget: candidate fits (default 20000; reproducible); every candidate is kept: under 1 KB of memory a fit (f to 8 nodes: 1.85 million fits in 1,387 MiB)", .dest = &a.evals, .lo = 1, .hi = 1e9},
		{.name = "--seconds", .kind = CLI_NUM, .metavar = "S", .help = "also stop after S seconds (not reproducible)", .dest = &a.seconds, .lo = 0, .hi = 1e7, .lo_open = 1},
		{.name = "--seed", .kind = CLI_INT, .metavar = "S", .help = "seed of the generator (default 1)", .dest = &a.seed, .lo = 0, .hi = 4294967295.0},
		{.name = "--threads", .kind = CLI_INT, .metavar = "N", .help = "fitting threads (default: all cores); the result does not depend on it", .dest = &a.threads, .lo = 1, .hi = 64},
		{.name = "--inputs", .kind = CLI_STR, .metavar = "LIST", .help = "inputs a candidate may read (default: what the target provides)", .dest = &a.inputs},
		{.name = "--ops", .kind = CLI_STR, .metavar = "LIST", .help = "operations (default + - * / sq sqrt rsqrt rcp exp2 log2 min max saturate mix; also abs, clamp, pow, exp, log, and registry terms of 1 to 3 arguments by name, e.g. F_schlick, D_ggx, V_smith_ggx_correlated)", .dest = &a.ops},
		{.name = "--max-cost", .kind = CLI_NUM, .metavar = "C", .help = "candidates costlier than C are not fitted", .dest = &a.max_cost, .lo = 0, .hi = 1e6, .lo_open = 1},
		{.name = "--max-params", .kind = CLI_INT, .metavar = "K", .help = "constants fitted per candidate (default 4; env 10, A and B together)", .dest = &a.max_params, .lo = 0, .hi = BK_MAX_PARAMS},
		{.name = "--max-size", .kind = CLI_INT, .metavar = "N", .help = "nodes per tree (default 24)", .dest = &a.max_size, .lo = 1, .hi = BK_EXPR_MAX},
		{.name = "--enum-size", .kind = CLI_INT, .metavar = "N", .help = "enumerate every tree up to N nodes first (default 5), drawn as the fits need them, each unique form fitted once (at most 16,777,216 trees kept as operands of larger ones, about 2.5 GB: vf2d keeps 1.37 million to reach 8 nodes), then evolution; front.csv's certificate says how far it got", .dest = &a.enum_size, .lo = 0, .hi = 9},
		{.name = "--enum-max", .kind = CLI_INT, .metavar = "N", .help = "at most N fits of the enumeration (default 5000)", .dest = &a.enum_max, .lo = 0, .hi = 1e9},
		{.name = "--generation", .kind = CLI_INT, .metavar = "N", .help = "children per generation (default 256)", .dest = &a.generation, .lo = 1, .hi = 65536},
		{.name = "--objective", .kind = CLI_STR, .metavar = "rmse|max|albedo", .help = "the error of the front (default rmse; albedo: vf, spec)", .dest = &a.objective},
		{.name = "--relative", .kind = CLI_FLAG, .help = "relative residuals and errors", .dest = &a.relative},
		{.name = "--precision", .kind = CLI_STR, .metavar = "P", .help = "double (default), single or half: the precision a candidate's error is measured in (fits stay in double); half: the front holds only members safe in half (stability as is or with guards), the others are left off, and its constants are moved on the half grid to the least error in half", .dest = &a.precision},
		{.name = "--cost-weights", .kind = CLI_STR, .metavar = "simple=W,complex=W", .help = "weights of the cost (default simple=1,complex=4)", .dest = &a.weights},
		{.name = "--env-form", .kind = CLI_STR, .metavar = "pair|f0|mix", .help = "env: candidates are split pairs A, B (default) or one form in f0 scored on f0 A + B (as compare scores); mix: as f0, seeded also with mix(B, S, f0) of the fronts of searches of S = A + B and of B (3/8 of --evals each)", .dest = &a.env_form},
		{.name = "--gpu", .kind = CLI_STR, .metavar = "CHIPS", .help = "AMD instruction counts of the front and the catalog rows per chip (brdfkit gpucost), e.g. " BK_GPUCOST_DEFAULT_CHIPS, .dest = &a.gpu},
		{.name = "--cost-model", .kind = CLI_STR, .metavar = "NAME", .help = "named weights: ir (the default) or aco-polaris10, aco-vega10, aco-navi21, aco-gfx1100 (fitted to AMD's instruction counts)", .dest = &a.cost_model},
		{.name = "--start", .kind = CLI_FORM, .metavar = "NAME|FORM", .help = "seed the search with this (default: every catalog form of the target)", .dest = a.start, .repeat = MAX_SEEDS},
		{.name = "--start-front", .kind = CLI_STR, .metavar = "FILE", .help = "also seed the search with every member of a front.csv of brdfkit search (columns form, form_b, parameters), after the catalog's (or --start's) seeds; its '# target:' line must state this target and domain (the grid may differ), its objective and precision may (a double front seeds a half search and back); may be given up to 8 times (make results merges a target's double and half fronts so), a form on two fronts seeded once", .dest = a.start_front, .repeat = MAX_START_FRONTS},
		{.name = "--start-forms", .kind = CLI_STR, .metavar = "FILE", .help = "also seed the search with the forms of a front.csv of any target (vf2d's for vf), each at its constants and refitted here; its '# target:' line is not read, and members that do not fit this target (an input it lacks, another shape, NaN on its samples) are left out and counted; up to 8 times", .dest = a.start_forms, .repeat = MAX_START_FRONTS},
		{.name = "--vs-front", .kind = CLI_STR, .metavar = "FILE", .help = "with --precision half: the double front.csv of the same target, samples and objective (its '#' lines are checked) beside this front in section.html, and DIR/vs_double.csv (at each cost <= 16 the best of each, their ratio, pass = ratio <= 1.25)", .dest = &a.vs_front},
		{.name = "--fetch-cost", .kind = CLI_NUM, .metavar = "K", .help = "env: add compare's DFG LUT rows at cost K + 1 (a fetch priced as K simple ops; the talk's tiers: 16, 32, 48, 64)", .dest = &a.fetch_cost, .lo = 0, .hi = 1e6},
		{.name = "--no-constraints", .kind = CLI_FLAG, .help = "allow negative values (and env A + B > 1)", .dest = &a.no_constraints},
		{.name = "--inherit", .kind = CLI_FLAG, .help = "children start their fits from their parents' constants", .dest = &a.inherit},
		{.name = "--link-prefix", .kind = CLI_LINK, .metavar = "P", .help = "prefix of the links in section.html (its place relative to the page): a path relative to the page (no scheme, no //host), percent-encoded where written", .dest = &a.prefix},
		{.name = "--checkpoint", .kind = CLI_STR, .metavar = "FILE", .help = "write the state here every --every fits and at the end", .dest = &a.checkpoint},
		{.name = "--every", .kind = CLI_INT, .metavar = "K", .help = "fits between checkpoints (default 5000)", .dest = &a.every, .lo = 1, .hi = 1e9},
		{.name = "--resume", .kind = CLI_STR, .metavar = "FILE", .help = "continue from a checkpoint (same options; --evals may grow)", .dest = &a.resume},
		{.name = "--migrate", .kind = CLI_INT, .metavar = "M", .help = "MPI: fits per island between migrations (default 2000)", .dest = &a.migrate, .lo = 1, .hi = 1e9},
		{.name = "--merge-fronts", .kind = CLI_FLAG, .help = "MPI: rank 0 takes each island's front, not all its candidates (the same front.csv; fewer rows in candidates.csv)", .dest = &a.merge_fronts},
		{.name = "--migrants", .kind = CLI_INT, .metavar = "N", .help = "MPI: front members each island sends round the ring (default 8)", .dest = &a.migrants, .lo = 0, .hi = MAX_FRONT},
		{.name = "--split-fits", .kind = CLI_FLAG, .help = "MPI: the ranks run one search and split each step's fits (the same files as one process, whatever the ranks)", .dest = &a.split_fits},
	};
	cli_cmd cmd = {"search", "Searches closed forms for a target: candidates over the formula IR, each fitted,\n"
	               "the Pareto front of error against GPU cost refitted in full. Writes front.csv,\n"
	               "catalog.csv, candidates.csv, front/NAME/ (as fit --out), pareto.svg (and .png, .pdf), section.html into DIR.",
	               "--target T --out DIR [options]",
	               "The same --seed and --evals give the same files for any --threads. SIGINT (or SIGUSR1)\n"
	               "stops at the end of the current generation, writes the checkpoint and the front so far,\n"
	               "exits 130 (a SIGINT that was ignored when brdfkit started, as in a script's background\n"
	               "job, stays ignored). A checkpoint that cannot be written stops the run: exit 1, the last\n"
	               "one written kept for --resume.\n"
	               "On a cluster: mpirun -np K build/brdfkit-mpi search ... runs K islands (--evals shared\n"
	               "out, --migrate, --migrants; checkpoints FILE.RANK); rank 0 merges and writes DIR. The\n"
	               "same --seed, --evals and K give the same files for any --threads (brdfkit-mpi(1)). To stop an\n"
	               "MPI job with its front, send SIGUSR1 to mpirun (it passes it to every rank); SIGINT or\n"
	               "SIGTERM to mpirun kill the ranks at once (Open MPI's rule): no front, exit 1, the\n"
	               "checkpoints of the last round kept for --resume.\n"
	               "With --split-fits the K ranks run one search instead and fit each step's candidates in\n"
	               "turn: the same files as one process (but the command line) for any K and --threads; the\n"
	               "checkpoint is FILE, written by rank 0, and resumes on any K or in one process.\n"
	               "With --precision half each member's error is the form's as the IR's f16 evaluation (the\n"
	               "emitted code's) computes it, and a refitted member whose stability in half is not \"as is\"\n"
	               "or \"with guards\" (brdfkit stability) is left off the front as an inadmissible one is;\n"
	               "catalog.csv keeps the published forms evaluated in half with their verdict.\n"
	               "Exit status: 0 done, 1 failed, 2 bad usage, 130 interrupted (results written).",
	               opts, (int)(sizeof opts / sizeof opts[0]), 0, 0, {0}};
	int rc = cli_parse_table(&cmd, &search_table, argc, argv);
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
	a.nstart_front = cli_seen(&cmd, "--start-front");
	a.nstart_forms = cli_seen(&cmd, "--start-forms");
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
		return cli_unknown_value("--target", a.t.target, cli_targets, CLI_NTARGETS);
	static const char *const env_forms[] = {"pair", "f0", "mix"};
	if (J.kind == BK_TARGET_ENV && a.env_form && cli_choice("--env-form", a.env_form, env_forms, 3) < 0)
		return 2; /* before the context, which it sets */
	if ((rc = search_check_applicable(&J)))
		return rc;
	if (a.t.f0.n > 1 && !search_env_in_f0(&J))
		return cli_usage(&cmd, "--f0: one value, got %d (a list only for env with --env-form f0)", a.t.f0.n);
	if ((rc = fitargs_setup_target(&a.t, J.kind, &J.to)))
		return rc;
	static bk_samples table; /* table, merl: the file's samples, copied by both builds */
	if ((rc = fitargs_read_file(&cmd, &a.t, J.kind, &table)))
		return rc;
	J.to.table = &table;
	char err[512];
	if (J.kind == BK_TARGET_FORM) {
		if (!a.t.target_form || !a.t.domain)
			return cli_usage(&cmd, "target form needs --target-form EXPR and --domain IN=LO:HI[,...]");
		J.to.form_text = a.t.target_form;
		if ((rc = fitargs_domain(&cmd, a.t.domain, &J.to)))
			return rc;
		if (bk_target_form_check(&J.to, err, sizeof err))
			return cli_usage(&cmd, "--target-form: %s", err);
	}
	if (a.vs_front && strcmp(a.precision, "half"))
		return cli_usage(&cmd, "--vs-front compares a half-precision front with a double one: give --precision half");
	if (cli_seen(&cmd, "--enum-size") && a.enum_size > a.max_size)
		return cli_usage(&cmd, "--enum-size %ld has no effect past --max-size %ld (no tree is larger)", a.enum_size,
		                 a.max_size);
	if ((rc = search_setup(&J)))
		return rc;
	/* rank 0 alone writes DIR and refits the front on the full samples:
	 * what it alone checks or builds is agreed on before the first exchange */
	int R = isl_rank(), K = isl_size();
	/* the checkpoint paths first: one inside --out is named as such, not as
	 * an entry --out does not list */
	J.ck = (ck_islands){a.checkpoint, a.resume, a.out, a.migrate, a.migrants, J.islands};
	if ((rc = ck_islands_check(&J.ck)))
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
	if (bk_lutcache_target_build(&J.to_screen, &J.screen, NULL, NULL, err, sizeof err)) {
		rc = cli_fail("search", "%s", err);
		goto done;
	}
	if ((rc = search_setup_inputs(&J)) || (rc = search_setup_seeds(&J, &sd)))
		goto done;
	if (R == 0)
		fitargs_say_size(&J.to); /* before the reference: --nx 4096 --nr 4096 is GBs */
	/* --vs-front: the double front of the same target and objective, said
	 * now, not after the search; its samples are checked with the full ones */
	if (R == 0 && a.vs_front &&
	    (bk_frontcsv_read(a.vs_front, BK_FRONTCSV_SCORES, &J.vs_fc, err, sizeof err) ||
	     bk_frontcsv_head_check(&J.vs_fc.head, a.vs_front, BK_FRONTCSV_FRONT, "this search's", J.screen.description, 0,
	                            bk_sfront_objective_name(&J.so), bk_precision_name(BK_F64), err, sizeof err)))
		rc = cli_fail("search", "--vs-front %s", err);
	else if (R == 0 && bk_lutcache_target_build(&J.to, &J.s, cli_progress, "reference", err, sizeof err))
		rc = cli_fail("search", "%s", err);
	else if (R == 0 && a.vs_front &&
	         bk_frontcsv_head_check(&J.vs_fc.head, a.vs_front, BK_FRONTCSV_FRONT, "this search's", J.s.description, 1,
	                                NULL, NULL, err, sizeof err))
		rc = cli_fail("search", "--vs-front %s", err);
	else if (R == 0) /* a pole between the screening samples */
		rc = search_check_starts(&J, &sd, &J.s);
	if (K > 1 && isl_any(rc))
		rc = 1;
	if (rc)
		goto done;
	J.so.screen = &J.screen;
	if (search_env_halves(&J)) {
		if ((rc = run_halves(&J, &hv)))
			goto done;
		bk_halves_seed(&hv, &sd, &J.so);
		J.so.exempt_seeds = J.ncatalog; /* the published seeds only: not --start-front's, nor the compositions */
	}
	if ((rc = J.islands ? run_islands(&J) : run_search(&J)) || R > 0)
		goto done;
	if (!J.islands)
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
	bk_samples_free(&table);
	bk_halves_free(&hv);
	bk_seeds_free(&sd);
	for (int i = 0; i < MAX_START_FRONTS; i++)
		bk_frontcsv_free(&J.start_fc[i]), bk_frontcsv_free(&J.forms_fc[i]);
	bk_frontcsv_free(&J.vs_fc);
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
