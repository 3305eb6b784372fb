/*
 * test_search_screen.c — the search's screening (fit/search/screen.h): a
 * planted one-parameter form is fitted to its known constant, a form of the
 * wrong structure is not; the one constraint predicate decides the status
 * (a form negative on the samples is refused under nonneg, kept without it
 * and kept when it is a published seed); a batch on two threads gives the
 * bits of one; the form a candidate is made with is the one fitted.
 */
#include "fixture_search.h"
#include "search/screen.h"

#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *const seed_text[] = {"LoH - p0"};

static bk_search *search_on(bk_samples *sm, const char *target, int nonneg, int threads)
{
	fx_planted(target, 0.3162, strchr(target, 'r') != NULL, 8, sm); /* r: when the target reads it */
	bk_search_options o;
	fx_plain_options(&o, sm, 1u << BK_IN_LOH | 1u << BK_IN_R, 2, 9);
	char err[256];
	o.nonneg = nonneg;
	o.threads = threads;
	o.seeds = seed_text;
	o.nseeds = 1;
	bk_search *s = bk_search_new(&o, err, sizeof err);
	cr_assert(s, "%s", err);
	return s;
}

static bk_cand cand(const char *text, int np)
{
	bk_cand c;
	memset(&c, 0, sizeof c);
	c.text = (char *)text;
	c.np = np;
	return c;
}

Test(search_screen, planted_constant_is_found)
{
	bk_samples sm;
	bk_search *s = search_on(&sm, "1/(LoH*LoH + 0.7*r*r)", 0, 1);
	bk_cand c = cand("1/(LoH*LoH + p0*r*r)", 1);
	bk_screen_one(s, &c, NULL);
	cr_assert_eq(c.status, BK_CAND_OK);
	cr_assert_float_eq(c.p[0], 0.7, 1e-6, "the planted 0.7, got %.17g", c.p[0]);
	cr_assert_lt(c.rmse, 1e-9);
	cr_assert_eq(c.err, bk_search_round_err(c.rmse), "the objective is the rmse, rounded");
	/* negative control: the wrong structure cannot reach the target */
	bk_cand w = cand("1/(LoH + p0*r*r)", 1);
	bk_screen_one(s, &w, NULL);
	cr_assert_eq(w.status, BK_CAND_OK);
	cr_assert_gt(w.rmse, 1e-3, "a wrong form's rmse %g", w.rmse);
	bk_search_free(s);
	bk_samples_free(&sm);
}

/* The form a candidate is made with (bk_cand.form, parsed once) is what the
 * screening fits, and is left on it (the archive keeps a front member's for
 * the front's refit): the same bits as the candidate's text parsed there.
 * The control: a form of another text on the same candidate is fitted
 * instead (the planted 0.7 is not found), so the check would see screening
 * parse text again. */
Test(search_screen, the_form_made_with_a_candidate_is_the_one_fitted)
{
	bk_samples sm;
	bk_search *s = search_on(&sm, "1/(LoH*LoH + 0.7*r*r)", 0, 1);
	bk_cand t = cand("1/(LoH*LoH + p0*r*r)", 1), f = t, o = t;
	f.form = bk_form_parse(f.text, NULL);
	o.form = bk_form_parse("1/(LoH + p0*r*r)", NULL);
	cr_assert(f.form && o.form);
	bk_form *made = f.form;
	bk_screen_one(s, &t, NULL);
	bk_screen_one(s, &f, NULL);
	bk_screen_one(s, &o, NULL);
	cr_expect(f.form == made, "the screening leaves the form on the candidate");
	cr_expect_null(t.form, "a candidate made by hand keeps none");
	cr_assert_eq(f.status, BK_CAND_OK);
	cr_expect_eq(memcmp(f.p, t.p, sizeof f.p), 0, "p0 %.17g, from the text %.17g", f.p[0], t.p[0]);
	cr_expect_eq(memcmp(&f.rmse, &t.rmse, sizeof f.rmse), 0);
	cr_expect_float_eq(f.p[0], 0.7, 1e-6);
	cr_expect_gt(o.rmse, 1e-3, "the control's form is fitted: rmse %g", o.rmse);
	cr_expect_neq(memcmp(o.p, t.p, sizeof o.p), 0);
	bk_form_free(f.form);
	bk_form_free(o.form);
	bk_search_free(s);
	bk_samples_free(&sm);
}

Test(search_screen, constraint_decides_the_status)
{
	/* LoH - 0.5 is negative for LoH < 0.5, inside the domain [0.3162, 1] */
	bk_samples sm;
	bk_search *s = search_on(&sm, "LoH - 0.5", 1, 1);
	bk_cand c = cand("LoH - p0", 1);
	bk_screen_one(s, &c, NULL);
	cr_assert_eq(c.status, BK_CAND_CONSTRAINT, "negative somewhere: refused under nonneg");
	cr_assert_eq(c.err, HUGE_VAL);
	/* the same form as the published seed: exempt */
	c = cand("LoH - p0", 1);
	c.seed_name = s->seed_name[0];
	bk_screen_one(s, &c, NULL);
	cr_assert_eq(c.status, BK_CAND_OK);
	cr_assert_float_eq(c.p[0], 0.5, 1e-6);
	bk_search_free(s);
	bk_samples_free(&sm);
	/* negative control: without nonneg the generated form is kept */
	s = search_on(&sm, "LoH - 0.5", 0, 1);
	c = cand("LoH - p0", 1);
	bk_screen_one(s, &c, NULL);
	cr_assert_eq(c.status, BK_CAND_OK);
	cr_assert_float_eq(c.p[0], 0.5, 1e-6, "screening tolerances: p0 %.17g", c.p[0]);
	bk_search_free(s);
	bk_samples_free(&sm);
}

/* each() of bk_screen_end: the order the candidates are handed on in */
typedef struct handed {
	size_t order[16];
	int n;
} handed;

static void hand(void *ctx, size_t i)
{
	handed *h = ctx;
	h->order[h->n++] = i;
}

/* A batch as a step screens it (published in two parts while the workers
 * wait, then closed): one thread and two give the same bits, and the
 * candidates are handed on once each, in index order. */
Test(search_screen, batch_on_threads_gives_the_same_bits)
{
	static const char *const texts[] = {"1/(LoH*LoH + p0*r*r)", "p0/(LoH + p1*r)", "p0*LoH + p1", "sq(p0 - r)*LoH",
	                                    "p0/(LoH*LoH + p1)", "exp2(p0*LoH)*p1"};
	enum { N = sizeof texts / sizeof *texts };
	bk_cand c[2][N];
	const double *start[N] = {0};
	for (int t = 0; t < 2; t++) {
		bk_samples sm;
		bk_search *s = search_on(&sm, "1/(LoH*LoH + 0.7*r*r)", 0, t + 1);
		for (int i = 0; i < N; i++)
			c[t][i] = cand(texts[i], 1 + (strstr(texts[i], "p1") != NULL));
		bk_screen_crew crew;
		handed h = {{0}, 0};
		bk_screen_begin(&crew, s, c[t], start, N);
		bk_screen_ready(&crew, 2);
		bk_screen_end(&crew, N, hand, &h);
		cr_assert_eq(h.n, N, "%d handed on", h.n);
		for (int i = 0; i < N; i++)
			cr_assert_eq(h.order[i], (size_t)i, "threads %d: place %d holds candidate %zu", t + 1, i, h.order[i]);
		bk_search_free(s);
		bk_samples_free(&sm);
	}
	for (int i = 0; i < N; i++) {
		cr_assert_eq(c[0][i].status, c[1][i].status);
		cr_assert_eq(memcmp(c[0][i].p, c[1][i].p, sizeof c[0][i].p), 0, "%s", texts[i]);
		cr_assert_eq(memcmp(&c[0][i].err, &c[1][i].err, sizeof(double)), 0, "%s", texts[i]);
	}
	cr_assert_eq(c[0][0].status, BK_CAND_OK);
}
