/*
 * test_search_driver.c — the loop a program drives a search with
 * (bk_search_drive, fit/search.h): stop is asked after every step and ends
 * the run there; progress comes once progress_every fits have been made
 * since the last call, and once more at the end, which sees the final
 * state; bk_search_run (one after_step callback) is the same loop.
 */
#include "fixture_search.h"
#include "search.h"

#include <criterion/criterion.h>
#include <stdlib.h>
#include <string.h>

typedef struct log {
	long at[64]; /* fits when called */
	int n;
	int stop_after; /* stop: say stop at this call (0: never) */
} log;

static void heard(void *ctx, const bk_search *s)
{
	log *l = ctx;
	cr_assert_lt(l->n, 64);
	l->at[l->n++] = bk_search_evals(s);
}

static int asked(void *ctx, const bk_search *s)
{
	log *l = ctx;
	cr_assert_lt(l->n, 64);
	l->at[l->n++] = bk_search_evals(s);
	return l->stop_after && l->n >= l->stop_after;
}

typedef struct both {
	log progress, stop;
} both;
static void both_progress(void *ctx, const bk_search *s) { heard(&((both *)ctx)->progress, s); }
static int both_stop(void *ctx, const bk_search *s) { return asked(&((both *)ctx)->stop, s); }

static bk_search *made(bk_samples *sm)
{
	fx_planted("0.45*LoH*LoH + 0.2", 0, 0, 16, sm);
	bk_search_options o;
	fx_plain_options(&o, sm, 1u << BK_IN_LOH, 2, 7);
	char err[256];
	o.generation = 30;
	o.evals = 400;
	bk_search *s = bk_search_new(&o, err, sizeof err);
	cr_assert(s, "%s", err);
	return s;
}

static void drive(int every, int stop_after, both *b, int *rc, long *evals)
{
	bk_samples sm;
	bk_search *s = made(&sm);
	memset(b, 0, sizeof *b);
	b->stop.stop_after = stop_after;
	bk_search_callbacks cb = {both_progress, both_stop, b, every};
	char err[256];
	*rc = bk_search_drive(s, &cb, err, sizeof err);
	*evals = bk_search_evals(s);
	bk_search_free(s);
	bk_samples_free(&sm);
}

Test(search_driver, progress_every_and_at_the_end)
{
	both b;
	int rc;
	long evals;
	drive(0, 0, &b, &rc, &evals);
	cr_assert_eq(rc, 0);
	cr_assert_geq(evals, 400, "the budget spent");
	/* every step but the last is asked to stop; progress after each of
	 * them and once at the end */
	cr_assert_gt(b.stop.n, 5);
	cr_assert_eq(b.progress.n, b.stop.n + 1);
	cr_assert_eq(b.progress.at[b.progress.n - 1], evals, "the last call sees the final state");
	long steps[64];
	int nsteps = b.stop.n;
	memcpy(steps, b.stop.at, sizeof steps);

	/* every 100 fits: called at the first step that reaches 100 fits past
	 * the last call (worked out from the steps' fit counts above) */
	drive(100, 0, &b, &rc, &evals);
	long want[64], last = 0;
	int nw = 0;
	for (int i = 0; i < nsteps; i++)
		if (steps[i] - last >= 100)
			want[nw++] = last = steps[i];
	want[nw++] = evals;
	cr_assert_lt(nw, b.stop.n + 1, "fewer calls than steps: the gate bites");
	cr_assert_eq(b.progress.n, nw);
	for (int i = 0; i < nw; i++)
		cr_assert_eq(b.progress.at[i], want[i], "call %d", i);
}

Test(search_driver, stop_ends_the_run_after_that_step)
{
	both b;
	int rc;
	long evals;
	drive(0, 3, &b, &rc, &evals);
	cr_assert_eq(rc, 1, "stopped");
	cr_assert_eq(b.stop.n, 3);
	cr_assert_eq(evals, b.stop.at[2], "no step after the one that said stop");
	cr_assert_lt(evals, 400);
	cr_assert_eq(b.progress.at[b.progress.n - 1], evals);
	/* negative control: a stop that never says so runs to the budget */
	drive(0, 0, &b, &rc, &evals);
	cr_assert_eq(rc, 0);
	cr_assert_geq(evals, 400);
}

static int after(void *ctx, const bk_search *s) { return asked(ctx, s); }

Test(search_driver, run_is_the_same_loop)
{
	bk_samples sm;
	bk_search *s = made(&sm);
	log l = {.stop_after = 3};
	char err[256];
	cr_assert_eq(bk_search_run(s, after, &l, err, sizeof err), 1);
	cr_assert_eq(l.n, 3);
	cr_assert_eq(bk_search_evals(s), l.at[2]);
	cr_assert_eq(bk_search_run(s, NULL, NULL, err, sizeof err), 0, "NULL: to the budget");
	cr_assert_geq(bk_search_evals(s), 400);
	bk_search_free(s);
	bk_samples_free(&sm);
}

/* Options are checked one by one, the option at fault named (as the
 * fitter's bk_fit_options_valid does); the defaults pass (the control). */
Test(search_driver, a_bad_option_is_named)
{
	bk_samples s;
	fx_planted("0.5*LoH", 0.3162, 0, 8, &s);
	bk_search_options good;
	fx_plain_options(&good, &s, 1u << BK_IN_LOH, 2, 8);
	char why[256];
	cr_assert_eq(bk_search_options_valid(&good, why, sizeof why), 1, "%s", why);
	static const char *const says[] = {"starts:", "threads:", "enum_size:", "grammar.max_params:", "max_cost:",
	                                   "island, islands:", "evals:", "screen:", "generation:", "grammar.consts[0]:"};
	for (size_t k = 0; k < sizeof says / sizeof says[0]; k++) {
		bk_search_options o = good;
		switch (k) {
		case 0: o.starts = 7; break;
		case 1: o.threads = 0; break;
		case 2: o.enum_size = -1; break;
		case 3: o.grammar.max_params = BK_MAX_PARAMS + 1; break;
		case 4: o.max_cost = 0; break;
		case 5: o.island = 2, o.islands = 2; break;
		case 6: o.evals = 0; break;
		case 7: o.screen = NULL; break;
		case 8: o.generation = 0; break;
		default: o.grammar.nconsts = 1, o.grammar.consts[0] = strtod("nan", NULL); break;
		}
		cr_assert_eq(bk_search_options_valid(&o, why, sizeof why), 0, "case %zu passed", k);
		cr_assert(!strncmp(why, says[k], strlen(says[k])), "case %zu: %s", k, why);
		char err[300];
		cr_assert_null(bk_search_new(&o, err, sizeof err));
		cr_assert(strstr(err, says[k]), "bk_search_new: %s", err);
	}
	bk_samples_free(&s);
}

/* The brief names what a reader needs: fits, unique forms, how far complete. */
Test(search_driver, the_brief_says_how_far_it_is_complete)
{
	bk_samples s;
	fx_planted("0.5*LoH + 0.25", 0.3162, 0, 8, &s);
	bk_search_options o;
	fx_plain_options(&o, &s, 1u << BK_IN_LOH, 2, 8);
	o.grammar.consts[0] = 1;
	o.grammar.nconsts = 1;
	o.enum_size = 3;
	o.enum_max = 100000;
	o.evals = 600;
	char err[256], brief[1024];
	bk_search *S = bk_search_new(&o, err, sizeof err);
	cr_assert(S, "%s", err);
	cr_assert_geq(bk_search_run(S, NULL, NULL, err, sizeof err), 0, "%s", err);
	cr_assert_gt(bk_search_brief(S, brief, sizeof brief), 0);
	cr_assert(strstr(brief, "complete to 3 nodes"), "%s", brief);
	cr_assert(strstr(brief, " fits, "), "%s", brief);
	cr_assert_eq(bk_search_brief(S, brief, 16), -1, "a short buffer is said to be cut");
	bk_search_free(S);
	bk_samples_free(&s);
}
