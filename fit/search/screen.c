/*
 * screen.c — screening a batch of candidates (screen.h), and the objective
 * (bk_search_error, bk_search_round_err of fit/search.h).
 */
#include "search/screen.h"
#include "search/constraint.h"
#include "search/starts.h"
#include "albfit.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

/* Screening fits stop early: a candidate only has to be ranked (errors are
 * compared at 20 bits, ~1e-6), and the front's members are refitted in full
 * afterwards with fit's tolerances.
 *
 * The cap, 20 (40 before). Measured with analysis/bench/fronts_ab.py, make
 * results' seven double searches at seeds 1-3, 40 against 20 on the same
 * machine: the fronts moved both ways, as any change to the search's path
 * moves them (cost levels <= 16 over the three seeds: 20 better at 106,
 * worse at 95, the same at 85; the geometric mean of 20's errors over 40's
 * 0.999), for a sixth less CPU (the seven searches, one thread each, two at a
 * time: 453-512 CPU-s a seed, against 544-602 at 40).
 * A fit the cap stops is not lost: it ends "not converged", so the next start
 * is tried (below), and a near one is polished; the recovery suite at 20,000
 * fits, seeds 1-3 (bench_recovery): 126 -> 131 of 153 runs, catalog 8 -> 9 of
 * 16 forms. What a lower cap loses: a right structure from a poor start that
 * needs more than 20 iterations and is not yet near (tests/test_search_nb.c,
 * the Beckmann peak from 0.1: 0.08 rmse after 20, its constants after 40)
 * waits for a neighbour or the refit. 12 lost the polish of near fits too. */
#define SCREEN_ITERATIONS 20
#define SCREEN_FTOL 1e-6
#define SCREEN_PTOL 1e-8

/* A polish: a fit stopped by the iteration cap that is already near the
 * target (a right structure whose constants are still moving: beckmann_fix
 * of the recovery suite stopped at 2e-6) goes on from where it stopped, up to
 * POLISH_ROUNDS more solves, while it stays unconverged and its cost falls.
 * "Near": 2 cost <= POLISH_REL^2 x sum of y^2. The fit's weights sum to 1,
 * so this is a weighted rms residual within POLISH_REL x sqrt(n) of the
 * target's rms (1.6e-3 at 256 samples, 3.2e-3 at 1,024): looser than the
 * name says, and what the recovery suite was measured with. Few candidates
 * come that close (vf2d at 20,000 fits: the same CPU time as without). */
#define POLISH_REL 1e-4
#define RETRIES 2
#define POLISH_ROUNDS 4

double bk_search_error(const bk_search_options *o, const bk_samples *sm, const double *v, const bk_fit_metrics *m)
{
	/* the metrics leave out the samples where the values are not finite:
	 * over those alone an error is no error of the form (over none it reads
	 * 0, a perfect fit), so a form not finite somewhere has none */
	if (m->nonfinite)
		return HUGE_VAL;
	if (o->objective == BK_OBJ_MAX)
		return o->relative ? m->max_rel : m->max_abs;
	if (o->objective == BK_OBJ_ALBEDO)
		return m->albedo_max_abs;
	if (!o->relative)
		return m->rmse;
	if (!v)
		return NAN;
	double se = 0, ymax = 0; /* the rmse of the relative residuals, floored as fit's (fit_ctx.c) */
	for (size_t i = 0; i < sm->n; i++)
		ymax = fmax(ymax, fabs(sm->y[i]));
	for (size_t i = 0; i < sm->n; i++) {
		double r = (v[i] - sm->y[i]) / fmax(fabs(sm->y[i]), 1e-6 * ymax);
		se += r * r;
	}
	return sqrt(se / (double)sm->n);
}

double bk_search_round_err(double e)
{
	if (!isfinite(e) || e == 0)
		return e;
	int x;
	double m = frexp(e, &x);
	return ldexp(nearbyint(ldexp(m, BK_SEARCH_ERR_BITS)), x - BK_SEARCH_ERR_BITS);
}

/* ---- fitting one candidate ------------------------------------------------ */

/* The starts: search/starts.h (ones, 0.1, then random ones from the seed and
 * the candidate's text, the same on any thread). */

void bk_screen_one(const bk_search *s, bk_cand *c, const double *seed_p)
{
	const bk_samples *sm = s->o.screen;
	c->status = BK_CAND_FAILED;
	c->err = c->rmse = c->max_abs = c->albedo_max_abs = HUGE_VAL;
	c->starts_run = c->start_won = 0;
	/* the forms made with the candidate (cand.h: parsed once), read and left
	 * on it; one made by hand without them has its texts parsed here, for
	 * this fit alone */
	bk_form_error fe;
	bk_form *own[2] = {c->form ? NULL : bk_form_parse(c->text, &fe),
	                   c->text_b && !c->form_b ? bk_form_parse(c->text_b, &fe) : NULL};
	bk_form *f[2] = {c->form ? c->form : own[0], c->form_b ? c->form_b : own[1]};
	double *v = malloc(sizeof(double) * sm->n);
	if (!f[0] || (c->text_b && !f[1]) || !v)
		goto done;
	bk_fit_spec spec;
	memset(&spec, 0, sizeof spec);
	spec.s = sm;
	spec.form[0] = f[0];
	spec.form[1] = f[1] ? f[1] : f[0];
	spec.np = c->np;
	bk_fit_options opt = BK_FIT_OPTIONS_INIT;
	opt.max_iterations = SCREEN_ITERATIONS;
	opt.function_tolerance = SCREEN_FTOL;
	opt.parameter_tolerance = SCREEN_PTOL;
	spec.opt = opt;
	spec.relative = s->o.relative;
	spec.starts = 1;
	for (int j = 0; j < BK_MAX_PARAMS; j++) {
		spec.lower[j] = -HUGE_VAL;
		spec.upper[j] = HUGE_VAL;
	}
	bk_fit_problem *pb = bk_fit_problem_new(&spec);
	if (!pb)
		goto done;
	double best[BK_MAX_PARAMS], best_cost = HUGE_VAL;
	int best_term = BK_TERM_CONVERGENCE;
	int nstart = c->np ? s->o.starts + (seed_p != NULL) : 1;
	/* twice the cost of the best constant: the weighted variance of the
	 * target (weights sum to 1; relative residuals: the constant 0 would
	 * cost 1 each, taken as the bound) */
	double flat = 0, mean = 0;
	for (size_t i = 0; i < sm->n; i++)
		mean += sm->w[i] * sm->y[i];
	for (size_t i = 0; i < sm->n; i++)
		flat += s->o.relative ? sm->w[i] : sm->w[i] * (sm->y[i] - mean) * (sm->y[i] - mean);
	for (int k = 0; k < nstart; k++) {
		double p[BK_MAX_PARAMS];
		for (int j = 0; seed_p && j < BK_MAX_PARAMS; j++)
			p[j] = seed_p[j];
		if (!seed_p || k > 0)
			bk_search_start(s->o.seed, c->text, k - (seed_p != NULL), BK_MAX_PARAMS, p);
		bk_fit_summary sum;
		if (c->np) {
			if (bk_fit_problem_solve(pb, p, NULL, &sum))
				continue;
			/* a trial step into a pole (sqrt or log2 of a negative, 1/0) is
			 * rejected inside the solve (fit/tiny.cc); a point it accepts
			 * whose Jacobian is not finite fails the solve, which hands back
			 * its last good point: the fit goes on from there (afresh, so
			 * from a more damped step), and the point stands as this start's
			 * result if it fails again */
			for (int retry = 0; retry < RETRIES && sum.termination == BK_TERM_FAILURE && isfinite(sum.final_cost) &&
			                    sum.final_cost < sum.initial_cost;
			     retry++) {
				double before = sum.final_cost;
				if (bk_fit_problem_solve(pb, p, NULL, &sum))
					break;
				if (sum.termination == BK_TERM_FAILURE && !(sum.final_cost < before))
					sum.final_cost = before; /* p is back at the good point */
			}
			if (!isfinite(sum.final_cost))
				continue;
		} else {
			sum.final_cost = 0;
		}
		c->starts_run = k + 1;
		/* costs within the tie tolerance: the earlier start wins (fit.h) */
		if (sum.final_cost < best_cost * (1 - BK_FIT_COST_TIE)) {
			c->start_won = k;
			best_cost = sum.final_cost;
			best_term = sum.termination;
			memcpy(best, p, sizeof best);
		}
		/* the next start only where this one did not converge, or converged
		 * no better than a constant would (2 cost >= flat: exp2(p*x) with its
		 * scale gone to 0 is such a minimum, and the next start often finds
		 * the right one): most candidates converge from the first, and a
		 * screening fit is most of the search */
		if (c->np && sum.termination == BK_TERM_CONVERGENCE && 2 * sum.final_cost < flat)
			break;
	}
	if (c->np && best_term == BK_TERM_NO_CONVERGENCE && best_cost < HUGE_VAL) {
		double scale = 0; /* sum of y^2, unweighted (relative residuals: 1 each) */
		for (size_t i = 0; i < sm->n; i++)
			scale += s->o.relative ? 1.0 : sm->y[i] * sm->y[i];
		for (int k = 0; k < POLISH_ROUNDS && 2 * best_cost <= POLISH_REL * POLISH_REL * scale; k++) {
			double p[BK_MAX_PARAMS];
			memcpy(p, best, sizeof p);
			bk_fit_summary sum;
			if (bk_fit_problem_solve(pb, p, NULL, &sum) || sum.termination == BK_TERM_FAILURE ||
			    !(sum.final_cost < best_cost))
				break;
			best_cost = sum.final_cost;
			memcpy(best, p, sizeof best);
			if (sum.termination != BK_TERM_NO_CONVERGENCE)
				break;
		}
	}
	if (!(best_cost < HUGE_VAL)) {
		bk_fit_problem_free(pb);
		goto done;
	}
	/* the albedo objective: one more solve, least squares of the cells'
	 * albedo errors from the values' fit (fit/albfit.h), kept where it lowers
	 * the albedo's max error (the front's refit then goes on to its minimax) */
	if (s->o.objective == BK_OBJ_ALBEDO && c->np && sm->ncomp == 1 && !s->o.relative) {
		bk_albfit *af = bk_albfit_new(sm, f[0], c->np);
		double q[BK_MAX_PARAMS], e1;
		memcpy(q, best, sizeof q);
		if (af && bk_albfit_run(af, q, 0, &opt, &e1) == 0 && e1 < bk_albfit_max(af, best))
			memcpy(best, q, sizeof best);
		bk_albfit_free(af);
	}
	memcpy(c->p, best, sizeof c->p);
	/* the values in the search's precision; in f64, from the fit's bound
	 * forms (the same bits, without what reads no parameter) */
	int bad = s->o.precision == BK_F64 && bk_fit_problem_values(pb, c->p, v);
	for (int q = 0; !bad && s->o.precision != BK_F64 && q < sm->ncomp; q++) {
		size_t lo = sm->start[q];
		const double *in[BK_IN_COUNT];
		for (int k = 0; k < BK_IN_COUNT; k++)
			in[k] = sm->in[k] + lo;
		bad = bk_form_eval(spec.form[q], s->o.precision, sm->start[q + 1] - lo, in, c->p, v + lo) != 0;
	}
	bk_fit_problem_free(pb);
	if (bad)
		goto done;
	c->status = BK_CAND_OK;
	for (size_t i = 0; i < sm->n; i++)
		if (!isfinite(v[i]) && isfinite(sm->y[i]))
			c->status = BK_CAND_NONFINITE;
	/* the published seeds are kept whatever the constraints say (the front
	 * starts at the state of the art; Karis' env fit dips below 0) */
	int exempt = 0;
	for (int k = 0; c->seed_name && k < s->o.nseeds && k < s->o.exempt_seeds; k++)
		exempt |= c->seed_name == s->seed_name[k];
	if (c->status == BK_CAND_OK && !exempt && !bk_search_admissible(&s->o, sm, v))
		c->status = BK_CAND_CONSTRAINT;
	if (c->status != BK_CAND_OK)
		goto done;
	bk_fit_metrics m;
	bk_samples_metrics(sm, v, NULL, &m);
	c->rmse = m.rmse;
	c->max_abs = m.max_abs;
	c->albedo_max_abs = m.albedo_max_abs;
	double e = bk_search_error(&s->o, sm, v, &m);
	c->err = isfinite(e) ? bk_search_round_err(e) : HUGE_VAL;
	if (!isfinite(e))
		c->status = BK_CAND_NONFINITE;
done:
	free(v);
	bk_form_free(own[0]);
	bk_form_free(own[1]);
}

/* ---- a batch on threads ----------------------------------------------------- */

/* c[i] is fitted: say so to end's thread, which hands the candidates on in
 * order (done is NULL when there is no one to tell) */
static void finished(bk_screen_crew *w, size_t i)
{
	if (!w->done)
		return;
	pthread_mutex_lock(&w->mu);
	w->done[i] = 1;
	if (w->waiting)
		pthread_cond_broadcast(&w->cv);
	pthread_mutex_unlock(&w->mu);
}

/* The workers take candidates in order from `next` and fit each once it is
 * published (i < ready) or leave once the batch is closed: so they may start
 * while the generation still makes the batch (bk_screen_begin), on the
 * candidates it has made. What a candidate's fit reads of s (the options,
 * the samples, the seeds' names) neither the generation nor the merge
 * writes. */
/* Split among ranks (bk_search_split), this process fits the candidates
 * R, R + K, R + 2K, ...: the j-th it takes is R + jK. */
static int split_size(const bk_search *s) { return s->o.split ? s->o.split->size : 1; }
static size_t own(const bk_screen_crew *w, size_t j)
{
	const bk_search_split *sp = w->s->o.split;
	return sp ? (size_t)sp->rank + j * (size_t)sp->size : j;
}

static void *worker(void *arg)
{
	bk_screen_crew *w = arg;
	for (;;) {
		size_t i = own(w, atomic_fetch_add(&w->next, 1));
		pthread_mutex_lock(&w->mu);
		while (i >= w->ready && !w->closed)
			pthread_cond_wait(&w->cv, &w->mu);
		int go = i < w->ready;
		pthread_mutex_unlock(&w->mu);
		if (!go)
			return NULL;
		bk_screen_one(w->s, &w->c[i], w->seed_p[i]);
		finished(w, i);
	}
}

void bk_screen_begin(bk_screen_crew *w, const bk_search *s, bk_cand *c, const double *const *seed_p, size_t cap)
{
	w->s = s;
	w->c = c;
	w->seed_p = seed_p;
	atomic_init(&w->next, 0);
	w->ready = 0;
	w->closed = 0;
	w->waiting = 0;
	w->started = 0;
	w->done = calloc(cap ? cap : 1, 1); /* NULL: end hands them on after the join */
	pthread_mutex_init(&w->mu, NULL);
	pthread_cond_init(&w->cv, NULL);
	int nt = s->o.threads < 1 ? 1 : s->o.threads > 64 ? 64 : s->o.threads;
	if (cap < (size_t)nt) /* no more threads than candidates (the seeds' first step may be one) */
		nt = cap ? (int)cap : 1;
	for (int t = 1; t < nt; t++)
		if (pthread_create(&w->th[w->started], NULL, worker, w) == 0)
			w->started++;
}

void bk_screen_ready(bk_screen_crew *w, size_t n)
{
	pthread_mutex_lock(&w->mu);
	if (n > w->ready) {
		w->ready = n;
		pthread_cond_broadcast(&w->cv);
	}
	pthread_mutex_unlock(&w->mu);
}

/* each() of the fitted candidates from `from` on, in order, up to the first
 * not yet fitted (with wait: up to n, waiting for them); returns where it
 * stopped. Called on end's thread alone, outside the lock: a candidate
 * marked done was written before its worker let go of the lock. */
static size_t hand_on(bk_screen_crew *w, size_t from, size_t n, int wait, void (*each)(void *, size_t), void *ctx)
{
	size_t to = from;
	pthread_mutex_lock(&w->mu);
	for (;;) {
		while (to < n && w->done[to])
			to++;
		if (!wait || to == n)
			break;
		w->waiting = 1;
		pthread_cond_wait(&w->cv, &w->mu);
	}
	w->waiting = 0;
	pthread_mutex_unlock(&w->mu);
	for (size_t i = from; i < to; i++)
		each(ctx, i);
	return to;
}

/* What a fit writes into its candidate (bk_screen_one), as the ranks
 * that split a batch send it to each other: bytes, between processes of one
 * job (one build, one machine kind). */
typedef struct fit_result {
	double p[BK_MAX_PARAMS];
	double err, rmse, max_abs, albedo_max_abs;
	int status, starts_run, start_won;
} fit_result;

/* The split's exchange: this rank's results out, the others' in. rec NULL
 * (out of memory) still calls share, which fails on every rank then. */
static int share_results(bk_screen_crew *w, size_t n)
{
	const bk_search_split *sp = w->s->o.split;
	fit_result *rec = calloc(n ? n : 1, sizeof *rec);
	for (size_t j = 0, i; rec && (i = own(w, j)) < n; j++) {
		const bk_cand *c = &w->c[i];
		memcpy(rec[i].p, c->p, sizeof rec[i].p);
		rec[i].err = c->err;
		rec[i].rmse = c->rmse;
		rec[i].max_abs = c->max_abs;
		rec[i].albedo_max_abs = c->albedo_max_abs;
		rec[i].status = (int)c->status;
		rec[i].starts_run = c->starts_run;
		rec[i].start_won = c->start_won;
	}
	int rc = sp->share(sp->ctx, rec, sizeof *rec, n);
	for (size_t i = 0; rc == 0 && i < n; i++) {
		if ((int)(i % (size_t)sp->size) == sp->rank)
			continue;
		bk_cand *c = &w->c[i];
		memcpy(c->p, rec[i].p, sizeof c->p);
		c->err = rec[i].err;
		c->rmse = rec[i].rmse;
		c->max_abs = rec[i].max_abs;
		c->albedo_max_abs = rec[i].albedo_max_abs;
		c->status = (bk_cand_status)rec[i].status;
		c->starts_run = rec[i].starts_run;
		c->start_won = rec[i].start_won;
	}
	free(rec);
	return rc ? -1 : 0;
}

int bk_screen_end(bk_screen_crew *w, size_t n, void (*each)(void *ctx, size_t i), void *ctx)
{
	bk_screen_ready(w, n);
	pthread_mutex_lock(&w->mu);
	w->closed = 1;
	pthread_cond_broadcast(&w->cv);
	pthread_mutex_unlock(&w->mu);
	/* this thread fits too (a thread that failed to start is only slower),
	 * and between its fits hands on, in order, what is fitted: the merge
	 * then runs beside the other threads' last fits, not after them */
	size_t handed = 0;
	int alone = split_size(w->s) == 1, rc = 0;
	for (size_t i; (i = own(w, atomic_fetch_add(&w->next, 1))) < n;) {
		bk_screen_one(w->s, &w->c[i], w->seed_p[i]);
		finished(w, i);
		if (alone && each && w->done)
			handed = hand_on(w, handed, n, 0, each, ctx);
	}
	if (alone && each && w->done)
		handed = hand_on(w, handed, n, 1, each, ctx);
	for (int t = 0; t < w->started; t++)
		pthread_join(w->th[t], NULL);
	/* split: the batch is whole once every rank's results are in */
	if (!alone)
		rc = share_results(w, n);
	for (size_t i = handed; rc == 0 && each && i < n; i++) /* without done, or split: after the join */
		each(ctx, i);
	pthread_cond_destroy(&w->cv);
	pthread_mutex_destroy(&w->mu);
	free(w->done);
	return rc;
}
