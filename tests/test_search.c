/*
 * test_search.c — the search (fit/search.h): a planted form recovered,
 * the same bytes for any thread count, a resumed run equal to an
 * uninterrupted one, the front non-dominated and complete, constraints held
 * on a denser grid, the error resolution; islands sharing out the
 * enumeration and taking each other's migrants.
 */
#include "search.h"

#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The planted target 0.3/(LoH^2 + 0.7 r^2) on LoH in [0.3162, 1], r in [0, 1]. */
static void planted(bk_samples *s, int cells)
{
	bk_target_options to;
	bk_target_defaults(BK_TARGET_FORM, &to);
	to.form_text = "0.3/(LoH*LoH + 0.7*r*r)";
	to.ndomain = 2;
	to.dom_in[0] = BK_IN_LOH, to.dom_lo[0] = 0.3162, to.dom_hi[0] = 1;
	to.dom_in[1] = BK_IN_R, to.dom_lo[1] = 0, to.dom_hi[1] = 1;
	to.nx = cells;
	char err[256];
	cr_assert_eq(bk_target_build(&to, s, NULL, NULL, err, sizeof err), 0, "%s", err);
}

static const char *const plant_seed[] = {"p0/(LoH*LoH + p1)"};

static void plant_options(bk_search_options *o, const bk_samples *s, int threads, long evals)
{
	bk_search_defaults(o);
	o->screen = s;
	o->shape = BK_SHAPE_PLAIN;
	memset(&o->grammar, 0, sizeof o->grammar);
	char err[128];
	cr_assert_eq(bk_grammar_parse_ops("+,*,/,sq", &o->grammar.ops, err, sizeof err), 0, "%s", err);
	o->grammar.inputs = 1u << BK_IN_LOH | 1u << BK_IN_R | 1u << BK_IN_A; /* the domain's r gives a */
	o->grammar.consts[0] = 1;
	o->grammar.nconsts = 1;
	o->grammar.max_params = 2;
	o->grammar.max_size = 16;
	o->threads = threads;
	o->evals = evals;
	o->seeds = plant_seed;
	o->nseeds = 1;
	o->seed = 7;
}

static bk_search *run(const bk_search_options *o)
{
	char err[256];
	bk_search *s = bk_search_new(o, err, sizeof err);
	cr_assert(s, "%s", err);
	int rc;
	while ((rc = bk_search_step(s, err, sizeof err)) == 1)
		;
	cr_assert_eq(rc, 0, "%s", err);
	return s;
}

/* Every candidate, field by field, bit for bit. */
static void same(const bk_search *a, const bk_search *b)
{
	cr_assert_eq(bk_search_count(a), bk_search_count(b));
	for (size_t i = 0; i < bk_search_count(a); i++) {
		const bk_cand *x = bk_search_at(a, i), *y = bk_search_at(b, i);
		cr_assert_str_eq(x->text, y->text, "candidate %zu", i);
		cr_assert_eq(x->found_at, y->found_at);
		cr_assert_eq(x->status, y->status);
		cr_assert_eq(memcmp(&x->err, &y->err, sizeof x->err), 0, "%s", x->text);
		cr_assert_eq(memcmp(x->p, y->p, sizeof(double) * (size_t)x->np), 0, "%s", x->text);
	}
}

Test(search, planted_form_recovered)
{
	bk_samples s;
	planted(&s, 32);
	bk_search_options o;
	plant_options(&o, &s, 2, 3000);
	bk_search *S = run(&o);
	double best = HUGE_VAL;
	const char *text = "";
	for (size_t i = 0; i < bk_search_count(S); i++) {
		const bk_cand *c = bk_search_at(S, i);
		if (c->status == BK_CAND_OK && c->rmse < best)
			best = c->rmse, text = c->text;
	}
	cr_assert_leq(best, 1e-9, "best %g (%s)", best, text);
	bk_search_free(S);
	bk_samples_free(&s);
}

Test(search, threads_do_not_change_the_result)
{
	bk_samples s;
	planted(&s, 16);
	bk_search_options o;
	plant_options(&o, &s, 1, 1500);
	bk_search *a = run(&o);
	o.threads = 2;
	bk_search *b = run(&o);
	same(a, b);
	bk_search_free(a);
	bk_search_free(b);
	bk_samples_free(&s);
}

/* A search with options o continued from part's checkpoint to o's budget. */
static bk_search *resume(const bk_search *part, const bk_search_options *o)
{
	FILE *f = tmpfile();
	cr_assert(f);
	cr_assert_eq(bk_search_save(part, f), 0);
	rewind(f);
	char err[256];
	bk_search *s = bk_search_new(o, err, sizeof err);
	cr_assert(s, "%s", err);
	cr_assert_eq(bk_search_load(s, f, err, sizeof err), 0, "%s", err);
	fclose(f);
	int rc;
	while ((rc = bk_search_step(s, err, sizeof err)) == 1)
		;
	cr_assert_eq(rc, 0, "%s", err);
	return s;
}

Test(search, resume_equals_an_uninterrupted_run)
{
	bk_samples s;
	planted(&s, 16);
	bk_search_options o;
	plant_options(&o, &s, 2, 700);
	bk_search *part = run(&o);
	o.evals = 1500;
	bk_search *resumed = resume(part, &o);
	char err[256];
	FILE *f;
	bk_search *whole = run(&o);
	same(whole, resumed);
	/* a checkpoint of other options is refused */
	f = tmpfile();
	bk_search_save(part, f);
	rewind(f);
	o.seed = 8;
	bk_search *other = bk_search_new(&o, err, sizeof err);
	cr_assert_eq(bk_search_load(other, f, err, sizeof err), -1);
	cr_assert(strstr(err, "other options"), "%s", err);
	fclose(f);
	bk_search_free(other);
	bk_search_free(part);
	bk_search_free(resumed);
	bk_search_free(whole);
	bk_samples_free(&s);
}

/* --inherit (children start from their parents' constants): the planted form
 * is still recovered, the threads and a resume still change nothing, and a
 * checkpoint made without it is refused (its children started elsewhere). */
Test(search, inherit_keeps_recovery_and_determinism)
{
	bk_samples s;
	planted(&s, 16);
	bk_search_options o;
	plant_options(&o, &s, 1, 1500);
	o.inherit = 1;
	bk_search *a = run(&o);
	double best = HUGE_VAL;
	for (size_t i = 0; i < bk_search_count(a); i++)
		if (bk_search_at(a, i)->status == BK_CAND_OK)
			best = fmin(best, bk_search_at(a, i)->rmse);
	cr_assert_leq(best, 1e-9);
	o.threads = 2;
	bk_search *b = run(&o);
	same(a, b);
	o.evals = 700;
	bk_search *part = run(&o);
	o.evals = 1500;
	bk_search *resumed = resume(part, &o);
	char err[256];
	FILE *f;
	same(a, resumed);
	o.inherit = 0;
	o.evals = 700;
	bk_search *plain = run(&o);
	f = tmpfile();
	bk_search_save(plain, f);
	rewind(f);
	o.inherit = 1;
	bk_search *other = bk_search_new(&o, err, sizeof err);
	cr_assert_eq(bk_search_load(other, f, err, sizeof err), -1);
	cr_assert(strstr(err, "other options"), "%s", err);
	fclose(f);
	bk_search_free(other);
	bk_search_free(plain);
	bk_search_free(part);
	bk_search_free(resumed);
	bk_search_free(a);
	bk_search_free(b);
	bk_samples_free(&s);
}

/* No ok candidate is at most as costly and at most as wrong as a front
 * member, one of them strictly; and every ok candidate off the front is
 * matched or beaten by a member (the front is complete). */
Test(search, front_is_the_pareto_front)
{
	bk_samples s;
	planted(&s, 16);
	bk_search_options o;
	plant_options(&o, &s, 2, 1500);
	bk_search *S = run(&o);
	size_t n = bk_search_count(S), *idx = malloc(sizeof(size_t) * n);
	size_t nf = bk_search_front(S, idx, n);
	cr_assert_gt(nf, 1);
	for (size_t k = 0; k < nf; k++) {
		const bk_cand *m = bk_search_at(S, idx[k]);
		cr_assert_eq(m->status, BK_CAND_OK);
		for (size_t i = 0; i < n; i++) {
			const bk_cand *c = bk_search_at(S, i);
			if (c->status != BK_CAND_OK || i == idx[k])
				continue;
			cr_assert_not(c->cost <= m->cost && c->err <= m->err && (c->cost < m->cost || c->err < m->err),
			              "%s dominates front member %s", c->text, m->text);
		}
	}
	for (size_t i = 0; i < n; i++) {
		const bk_cand *c = bk_search_at(S, i);
		int covered = c->status != BK_CAND_OK;
		for (size_t k = 0; k < nf && !covered; k++) {
			const bk_cand *m = bk_search_at(S, idx[k]);
			covered = m->cost <= c->cost && m->err <= c->err;
		}
		cr_assert(covered, "%s (cost %g, error %g) is neither on the front nor beaten by it", c->text, c->cost, c->err);
	}
	free(idx);
	bk_search_free(S);
	bk_samples_free(&s);
}

/* vf2d with the non-negativity constraint: every front member stays finite
 * and >= 0 on a grid four times denser along each axis than it was fitted on. */
Test(search, constraints_hold_on_a_denser_grid)
{
	bk_target_options to;
	bk_target_defaults(BK_TARGET_VF2D, &to);
	to.nx = to.nr = 16;
	bk_samples s, dense;
	char err[256];
	cr_assert_eq(bk_target_build(&to, &s, NULL, NULL, err, sizeof err), 0);
	to.nx = to.nr = 64;
	cr_assert_eq(bk_target_build(&to, &dense, NULL, NULL, err, sizeof err), 0);
	bk_search_options o;
	bk_search_defaults(&o);
	o.screen = &s;
	o.shape = BK_SHAPE_F0;
	memset(&o.grammar, 0, sizeof o.grammar);
	o.grammar.ops = bk_grammar_default_ops();
	o.grammar.inputs = 1u << BK_IN_LOH | 1u << BK_IN_R;
	o.grammar.consts[0] = 1;
	o.grammar.nconsts = 1;
	o.grammar.max_params = 3;
	o.grammar.max_size = 16;
	o.nonneg = 1;
	o.evals = 1500;
	o.threads = 2;
	bk_search *S = run(&o);
	size_t idx[64], nf = bk_search_front(S, idx, 64);
	cr_assert_gt(nf, 2);
	double *v = malloc(sizeof(double) * dense.n);
	for (size_t k = 0; k < nf; k++) {
		const bk_cand *m = bk_search_at(S, idx[k]);
		bk_form_error fe;
		bk_form *f = bk_form_parse(m->text, &fe);
		cr_assert(f);
		bk_form_eval(f, BK_F64, dense.n, (const double *const *)dense.in, m->p, v);
		for (size_t i = 0; i < dense.n; i++)
			cr_assert(isfinite(v[i]) && v[i] >= 0, "%s = %g at LoH %g, r %g", m->text, v[i], dense.in[BK_IN_LOH][i],
			          dense.in[BK_IN_R][i]);
		bk_form_free(f);
	}
	free(v);
	bk_search_free(S);
	bk_samples_free(&s);
	bk_samples_free(&dense);
}

/* 20 significant bits (the step in [1, 2) is 2^-19), ties to even: values
 * built from their bits. */
Test(search, error_resolution)
{
	cr_assert_eq(bk_search_round_err(1.0), 1.0);
	cr_assert_eq(bk_search_round_err(1.0 + ldexp(1, -22)), 1.0);            /* an eighth of a step: down */
	cr_assert_eq(bk_search_round_err(1.0 + 3 * ldexp(1, -21)), 1.0 + ldexp(1, -19)); /* three quarters: up */
	cr_assert_eq(bk_search_round_err(1.0 + ldexp(1, -20)), 1.0);            /* a tie: to even, down */
	cr_assert_eq(bk_search_round_err(1.0 + 3 * ldexp(1, -20)), 1.0 + ldexp(1, -18)); /* a tie: to even, up */
	cr_assert_eq(bk_search_round_err(0.75 * ldexp(1, -40)), 0.75 * ldexp(1, -40));
	cr_assert(isinf(bk_search_round_err(HUGE_VAL)));
	cr_assert_eq(bk_search_round_err(0.0), 0.0);
}

/* The texts of the enumeration a search fitted (found after the seed, up to
 * the end of the exhaustive phase: enum_max caps it below the budget). */
static size_t enumerated(const bk_search *s, char ***out)
{
	size_t n = 0;
	char **t = malloc(sizeof(char *) * (bk_search_count(s) + 1));
	for (size_t i = 0; i < bk_search_count(s); i++)
		if (!bk_search_at(s, i)->seed_name)
			t[n++] = bk_search_at(s, i)->text;
	*out = t;
	return n;
}

static int by_text(const void *a, const void *b) { return strcmp(*(char *const *)a, *(char *const *)b); }

/* Islands share out the enumeration: together two islands' enumerated
 * candidates are the one island's, text for text. */
Test(search, islands_share_the_enumeration)
{
	bk_samples s;
	planted(&s, 16);
	bk_search_options o;
	plant_options(&o, &s, 2, 100000);
	o.enum_size = 3;
	o.enum_max = 100000;
	o.generation = 100000; /* one batch holds the whole enumeration: no evolution after it */
	bk_search *one = bk_search_new(&o, (char[256]){0}, 256);
	char err[256];
	cr_assert_eq(bk_search_step(one, err, sizeof err), 1, "%s", err); /* the seed */
	cr_assert_geq(bk_search_step(one, err, sizeof err), 0, "%s", err); /* the enumeration */
	bk_search *isl[2];
	for (int k = 0; k < 2; k++) {
		o.islands = 2;
		o.island = k;
		isl[k] = bk_search_new(&o, err, sizeof err);
		cr_assert(isl[k], "%s", err);
		cr_assert_eq(bk_search_step(isl[k], err, sizeof err), 1, "%s", err);
		cr_assert_geq(bk_search_step(isl[k], err, sizeof err), 0, "%s", err);
	}
	char **a, **b, **c;
	size_t na = enumerated(one, &a), nb = enumerated(isl[0], &b), nc = enumerated(isl[1], &c);
	cr_assert(nb > 0 && nb < na && nc > 0 && nc < na, "each island its share: %zu and %zu of %zu", nb, nc, na);
	/* two trees the islands enumerate apart may scale to one candidate, which
	 * one island fits once (its cache) and two islands each fit: so the sets
	 * are compared, duplicates merged */
	char **u = malloc(sizeof(char *) * (nb + nc + 1));
	memcpy(u, b, sizeof(char *) * nb);
	memcpy(u + nb, c, sizeof(char *) * nc);
	qsort(u, nb + nc, sizeof *u, by_text);
	qsort(a, na, sizeof *a, by_text);
	size_t nu = 0;
	for (size_t i = 0; i < nb + nc; i++)
		if (nu == 0 || strcmp(u[nu - 1], u[i]))
			u[nu++] = u[i];
	cr_assert_eq(nu, na, "islands %zu + %zu (%zu distinct), one island %zu", nb, nc, nu, na);
	for (size_t i = 0; i < na; i++)
		cr_assert_str_eq(u[i], a[i], "candidate %zu", i);
	free(a), free(b), free(c), free(u);
	bk_search_free(one);
	bk_search_free(isl[0]);
	bk_search_free(isl[1]);
	bk_samples_free(&s);
}

/* Migrants: island 1's front taken by island 0 as fitted there (same error,
 * constants and island), once only; a search with other options is refused. */
Test(search, migrants_are_taken_once)
{
	bk_samples s;
	planted(&s, 16);
	bk_search_options o;
	plant_options(&o, &s, 2, 1500);
	o.islands = 2;
	o.island = 1;
	o.seed = 11;
	bk_search *from = run(&o);
	o.island = 0;
	o.seed = 7;
	bk_search *to = run(&o);
	size_t idx[64];
	size_t nf = bk_search_front(from, idx, 64);
	cr_assert_gt(nf, 2);
	char *buf = NULL;
	size_t len = 0;
	FILE *f = open_memstream(&buf, &len);
	cr_assert_eq(bk_search_export(from, idx, nf, f), 0);
	fclose(f);
	size_t before = bk_search_count(to), added = 0;
	char err[256];
	f = fmemopen(buf, len, "r");
	cr_assert_eq(bk_search_import(to, f, &added, err, sizeof err), 0, "%s", err);
	fclose(f);
	cr_assert_eq(bk_search_count(to), before + added);
	for (size_t i = before; i < bk_search_count(to); i++) { /* each new one is one of the front, bit for bit */
		const bk_cand *c = bk_search_at(to, i);
		int found = 0;
		for (size_t k = 0; k < nf && !found; k++) {
			const bk_cand *q = bk_search_at(from, idx[k]);
			found = !strcmp(q->text, c->text) && !memcmp(&q->err, &c->err, sizeof c->err) &&
			        !memcmp(q->p, c->p, sizeof(double) * (size_t)q->np) && q->found_at == c->found_at;
		}
		cr_assert(found, "%s", c->text);
		cr_assert_eq(c->island, 1);
	}
	f = fmemopen(buf, len, "r"); /* the same migrants again: nothing new */
	cr_assert_eq(bk_search_import(to, f, &added, err, sizeof err), 0, "%s", err);
	fclose(f);
	cr_assert_eq(added, 0);
	o.grammar.max_params = 1; /* other options: refused */
	bk_search *other = bk_search_new(&o, err, sizeof err);
	f = fmemopen(buf, len, "r");
	cr_assert_eq(bk_search_import(other, f, &added, err, sizeof err), -1);
	fclose(f);
	cr_assert(strstr(err, "other options"), "%s", err);
	free(buf);
	bk_search_free(from);
	bk_search_free(to);
	bk_search_free(other);
	bk_samples_free(&s);
}

/* Seeds are published forms, kept whatever the constraints say, unless they
 * come after exempt_seeds (compositions of searched halves, --env-form mix):
 * then a seed negative on the samples is rejected as a generated form is.
 * The planted target is positive; the seed -p0/(LoH^2 + p1) fits it only
 * with p0 < 0, which is not negative at all then: so a seed that stays
 * negative, -(LoH*LoH) - 1 (no parameter to flip its sign), is the test. */
Test(search, seeds_after_exempt_seeds_meet_the_constraints)
{
	bk_samples s;
	planted(&s, 8);
	static const char *const seeds[] = {"-(LoH*LoH) - 1", "-(LoH*LoH) - 2"};
	for (int exempt = 0; exempt <= 2; exempt++) {
		bk_search_options o;
		plant_options(&o, &s, 1, 300);
		o.seeds = seeds;
		o.nseeds = 2;
		o.nonneg = 1;
		o.exempt_seeds = exempt;
		bk_search *S = run(&o);
		int ok[2] = {-1, -1};
		for (size_t i = 0; i < bk_search_count(S); i++) {
			const bk_cand *c = bk_search_at(S, i);
			for (int k = 0; k < 2; k++)
				if (c->seed_name && !strcmp(c->text, seeds[k]))
					ok[k] = c->status == BK_CAND_OK;
		}
		for (int k = 0; k < 2; k++)
			cr_expect_eq(ok[k], k < exempt, "exempt_seeds %d: seed %d status %d", exempt, k, ok[k]);
		bk_search_free(S);
	}
	bk_samples_free(&s);
}
