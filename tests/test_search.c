/*
 * test_search.c — the search (fit/search.h): a planted form recovered,
 * the same bytes for any thread count, a resumed run equal to an
 * uninterrupted one, the front non-dominated and complete, constraints held
 * on a denser grid, the error resolution; islands sharing out the
 * enumeration and taking each other's migrants; checkpoints checksummed and
 * checked field by field (damage refused, mutations never a crash), the
 * budget of a resume, no error for a form not finite, the enumeration
 * drawn as the fits need it.
 */
#include "search.h"
#include "ir.h" /* the opcodes a checkpoint's trees are written with */

#include <criterion/criterion.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

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
 * candidates hold the one island's, text for text. An island leaves out the
 * twins of the models it fitted (search/unique.h), not those of the models
 * the other island fitted, which it does not see: so the two may fit a few
 * spellings of one model that one island fits once (a superset: the
 * certificate holds for the union). */
Test(search, islands_share_the_enumeration)
{
	bk_samples s;
	planted(&s, 16);
	bk_search_options o;
	plant_options(&o, &s, 2, 100000);
	o.enum_size = 3;
	o.enum_max = 100000;
	o.generation = 1024; /* one batch holds the whole enumeration (31 fits): no evolution after it */
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
	cr_assert_geq(nu, na, "islands %zu + %zu (%zu distinct), one island %zu", nb, nc, nu, na);
	size_t j = 0; /* a in u, both sorted */
	for (size_t i = 0; i < na; i++) {
		while (j < nu && strcmp(u[j], a[i]) < 0)
			j++;
		cr_assert(j < nu && !strcmp(u[j], a[i]), "candidate %s of one island is neither island's", a[i]);
	}
	cr_assert_leq(nu - na, na / 2, "islands fit %zu twins more than one island's %zu", nu - na, na);
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

/* ---- checkpoints and bounds (issue 21) ------------------------------------- */

/* FNV-1a 64 as published (offset basis 14695981039346656037, prime
 * 1099511628211), written here apart from expr.c's. */
static uint64_t fnv1a(const char *p, size_t n)
{
	uint64_t h = 14695981039346656037ull;
	for (size_t i = 0; i < n; i++)
		h = (h ^ (unsigned char)p[i]) * 1099511628211ull;
	return h;
}

/* A small search and its checkpoint's text (malloc'd, NUL-terminated). */
static char *checkpoint_of(const bk_search *S, size_t *len)
{
	char *buf = NULL;
	FILE *f = open_memstream(&buf, len);
	cr_assert(f);
	cr_assert_eq(bk_search_save(S, f), 0);
	fclose(f);
	return buf;
}

/* text (a checkpoint, its last line the checksum) with the checksum of its
 * body recomputed: damage the checksum cannot see, for the checks behind it. */
static char *resealed_at(const char *text, size_t body, size_t *len)
{
	char *out = malloc(body + 32);
	memcpy(out, text, body);
	*len = body + (size_t)snprintf(out + body, 32, "checksum %016llx\n", (unsigned long long)fnv1a(text, body));
	return out;
}

static char *resealed(const char *text, size_t *len)
{
	const char *last = strstr(text, "\nchecksum ");
	cr_assert(last, "no checksum line");
	return resealed_at(text, (size_t)(last - text) + 1, len);
}

/* A new search of options o loaded from text: its return code, err. */
static int load_text(const bk_search_options *o, const char *text, size_t len, char *err, size_t errlen,
                     bk_search **out)
{
	bk_search *s = bk_search_new(o, err, errlen);
	cr_assert(s, "%s", err);
	FILE *f = fmemopen((void *)text, len, "r");
	cr_assert(f);
	int rc = bk_search_load(s, f, err, errlen);
	fclose(f);
	if (out && rc == 0)
		*out = s;
	else
		bk_search_free(s);
	return rc;
}

/* text with the first occurrence of from replaced by to (malloc'd). */
static char *replaced(const char *text, const char *from, const char *to)
{
	const char *at = strstr(text, from);
	cr_assert(at, "'%s' not in the checkpoint", from);
	size_t a = (size_t)(at - text), lf = strlen(from), lt = strlen(to), n = strlen(text);
	char *out = malloc(n - lf + lt + 1);
	memcpy(out, text, a);
	memcpy(out + a, to, lt);
	memcpy(out + a + lt, at + lf, n - a - lf + 1);
	return out;
}

/* The small search the checkpoint tests share: a seed, a short enumeration,
 * a few generations of 8 (about 40 candidates). */
static void small_options(bk_search_options *o, const bk_samples *s)
{
	plant_options(o, s, 1, 24);
	o->generation = 8;
	o->enum_size = 3;
	o->enum_max = 12;
}

/* The last line is "checksum H", H the FNV-1a 64 of every byte before it:
 * any change of a byte, a missing line or a cut is refused, by name. */
Test(search, checkpoint_ends_with_its_checksum)
{
	bk_samples s;
	planted(&s, 8);
	bk_search_options o;
	small_options(&o, &s);
	bk_search *S = run(&o);
	size_t len;
	char *text = checkpoint_of(S, &len), err[512];
	cr_assert(strstr(text, "\nchecksum "), "no checksum line");
	const char *last = strstr(text, "\nchecksum ") + 1;
	char want[40];
	snprintf(want, sizeof want, "checksum %016llx\n", (unsigned long long)fnv1a(text, (size_t)(last - text)));
	cr_assert_str_eq(last, want);
	cr_assert_eq(load_text(&o, text, len, err, sizeof err, NULL), 0, "%s", err); /* the negative control */
	char *flip = strdup(text);
	flip[strstr(flip, "state ") - flip + 6] ^= 1; /* a digit of the fits done */
	cr_assert_eq(load_text(&o, flip, len, err, sizeof err, NULL), -1);
	cr_assert_str_eq(err, "its checksum does not match: the file was changed or damaged after it was written");
	cr_assert_eq(load_text(&o, text, (size_t)(last - text), err, sizeof err, NULL), -1);
	cr_assert_str_eq(err, "no checksum line at its end: cut short or not written by this version");
	cr_assert_eq(load_text(&o, text, len / 2, err, sizeof err, NULL), -1);
	cr_assert(strstr(err, "cut short"), "%s", err);
	free(flip);
	free(text);
	bk_search_free(S);
	bk_samples_free(&s);
}

/* Damage behind a valid checksum (a file rewritten by hand, or by a tool
 * that recomputes it): each refused with what is wrong, before any of it
 * is used (M1: a tree's input slot of 99999 crashed the printing; M1b: a
 * phase of 7, negative fits, an enumeration position far past its end were
 * taken; since checkpoint 4 the phase is a stage named by its generators,
 * each generator named with its state: an unknown or misplaced name is
 * refused alike). */
Test(search, damaged_checkpoints_are_refused_with_what_is_wrong)
{
	bk_samples s;
	planted(&s, 8);
	bk_search_options o;
	small_options(&o, &s);
	bk_search *S = run(&o);
	size_t len;
	char *text = checkpoint_of(S, &len), err[512];
	long evals = bk_search_evals(S);
	char state[64], input[32], bad_input[32];
	snprintf(state, sizeof state, "\nstate %ld\n", evals);
	snprintf(input, sizeof input, " %d:%d:", BK_OP_INPUT, BK_IN_LOH);
	snprintf(bad_input, sizeof bad_input, " %d:99999:", BK_OP_INPUT);
	char more[64];
	snprintf(more, sizeof more, "\nstate %ld\n", evals + 100);
	const char *evolution = "\nstage neighbours+semantic+children\n"; /* where the small search ends */
	char *pos0 = strstr(text, "\nposition ");
	cr_assert(strstr(text, evolution) && pos0, "no evolution stage or enumeration position:\n%.400s", text);
	char position[64];
	snprintf(position, sizeof position, "%.*s", (int)(strchr(pos0 + 1, '\n') - pos0 + 1), pos0);
	/* the enumeration's counts and twins (search/unique.h): the line
	 * "enumerated COMPLETE TOP" with the counts of size 1 after it, and
	 * "twins N" */
	char *en0 = strstr(text, "\nenumerated "), *tw0 = strstr(text, "\ntwins ");
	cr_assert(en0 && tw0, "no enumeration counts or twins:\n%.600s", text);
	char counts[96], counts_bad[96], twins[64];
	const char *en1 = strchr(strchr(en0 + 1, '\n') + 1, '\n'); /* the end of the size-1 line */
	snprintf(counts, sizeof counts, "%.*s", (int)(en1 - en0 + 1), en0);
	snprintf(counts_bad, sizeof counts_bad, "%.*s1 1 1\n", (int)(strchr(en0 + 1, '\n') - en0 + 1), en0);
	snprintf(twins, sizeof twins, "%.*s", (int)(strchr(tw0 + 1, '\n') - tw0 + 1), tw0);
	const struct {
		const char *from, *to, *says;
	} damage[] = {
		{input, bad_input, "input out of range"},
		{evolution, "\nstage sevens\n",
		 "stage sevens: not one of this search's (seeds, enumeration, neighbours+semantic+children, done)"},
		{evolution, "\nstage seeds\n", "before its stage"},
		{"\ngenerator enumeration\n", "\ngenerator zebra\n",
		 "generator zebra: not in this search's schedule (seeds, enumeration, neighbours, semantic, children)"},
		{"\ngenerator seeds\n", "\ngenerator children\n", "generator children where this search's schedule has seeds"},
		{"\ngenerator children\n", "\n", "no generator line for children"},
		{"\ngenerator children\n", "\ngenerator children\ngenerator zebra\n", "generator zebra: not in this search's"},
		{position, "\nposition x\n", "enumeration: no position line"},
		{"\nenumerated ", "\nenumerated 99 ", "a size out of 0 to 64"},
		{counts, counts_bad, "counts of size 1 unreadable or inconsistent"},
		{twins, "\ntwins 999999\n", "of 999999 unreadable"},
		{twins, "\ntwinz 1\n", "no twins line"},
		{state, "\nstate -5\n", "-5 fits"},
		{state, more, "fits for a budget of 24"},
		{"\nbudget 24\n", "\nbudget 0\n", "for a budget of 0"},
		{"\nc 1 0 ", "\nc 1 5 ", "island 5"},
		{"\nc 1 0 0 ", "\nc 1 0 9 ", "status 9"},
		{"p0 * LoH", "p0 * r", "its text"},
		{" -1 0\n", " 7 0\n", "seed (-1 to 0)"},
		{"\nc 2 ", "\nc 3 ", "found at fit 3"},
	};
	for (size_t k = 0; k < sizeof damage / sizeof damage[0]; k++) {
		char *d = replaced(text, damage[k].from, damage[k].to);
		size_t dl;
		char *sealed = resealed(d, &dl);
		cr_assert_eq(load_text(&o, sealed, dl, err, sizeof err, NULL), -1, "'%s' -> '%s' loaded", damage[k].from,
		             damage[k].to);
		cr_assert(strstr(err, damage[k].says), "'%s' -> '%s': %s", damage[k].from, damage[k].to, err);
		free(d);
		free(sealed);
	}
	/* the enumeration's position past its end: drawn again to there, and refused */
	char *d = replaced(text, position, "\nposition 999\n");
	size_t dl;
	char *sealed = resealed(d, &dl);
	cr_assert_eq(load_text(&o, sealed, dl, err, sizeof err, NULL), -1);
	cr_assert(strstr(err, "enumeration position 999 past its end"), "%s", err);
	free(d), free(sealed);
	/* the seeds' stage (the first) after fits, the enumeration not begun */
	char *d1 = replaced(text, evolution, "\nstage seeds\n");
	d = replaced(d1, position, "\nposition 0\n");
	sealed = resealed(d, &dl);
	cr_assert_eq(load_text(&o, sealed, dl, err, sizeof err, NULL), -1);
	snprintf(more, sizeof more, "stage seeds (the first) after %ld fits", evals);
	cr_assert(strstr(err, more), "%s", err);
	free(d1), free(d), free(sealed);
	/* migrants are candidates of the same format, checked alike */
	size_t idx[64], nf = bk_search_front(S, idx, 64), ml = 0;
	char *mig = NULL;
	FILE *f = open_memstream(&mig, &ml);
	cr_assert_eq(bk_search_export(S, idx, nf, f), 0);
	fclose(f);
	o.seed = 8; /* another island of the same run: the same options but the seed */
	bk_search *other = bk_search_new(&o, err, sizeof err);
	f = fmemopen(mig, ml, "r"); /* the negative control: as exported, taken */
	size_t added;
	cr_assert_eq(bk_search_import(other, f, &added, err, sizeof err), 0, "%s", err);
	fclose(f);
	bk_search_free(other);
	other = bk_search_new(&o, err, sizeof err);
	char *bad = replaced(mig, input, bad_input);
	f = fmemopen(bad, strlen(bad), "r");
	cr_assert_eq(bk_search_import(other, f, &added, err, sizeof err), -1);
	cr_assert(strstr(err, "input out of range"), "%s", err);
	fclose(f);
	free(bad), free(mig), free(text);
	bk_search_free(other);
	bk_search_free(S);
	bk_samples_free(&s);
}

/* What a state that loaded must be, checked apart from the loader: trees
 * that print, texts that compile, an OK candidate's error finite; and it
 * saves to a checkpoint that loads again, and steps on. */
static void usable(bk_search *L, const bk_search_options *o)
{
	char err[512], t[4096];
	for (size_t i = 0; i < bk_search_count(L); i++) {
		const bk_cand *c = bk_search_at(L, i);
		bk_expr e[2];
		bk_cand_trees(c, e);
		cr_assert_geq(bk_expr_print(&e[0], t, sizeof t), 0);
		bk_form_error fe;
		bk_form *f = bk_form_parse(c->text, &fe);
		cr_assert(f, "candidate %zu: '%s' does not compile", i, c->text);
		bk_form_free(f);
		cr_assert(c->status != BK_CAND_OK || isfinite(c->err));
	}
	size_t len, idx[64];
	bk_search_front(L, idx, 64);
	char *again = checkpoint_of(L, &len);
	cr_assert_eq(load_text(o, again, len, err, sizeof err, NULL), 0, "saved again: %s", err);
	free(again);
	cr_assert_geq(bk_search_step(L, err, sizeof err), 0, "%s", err);
}

/* Every byte of a small checkpoint changed three ways: with its checksum
 * as written every change is refused; with the checksum recomputed, the
 * checks behind it refuse it or what loads is usable. Never a crash (the
 * sanitized run of the suite reads every out-of-bounds access). */
Test(search, mutated_checkpoints_never_crash, .timeout = 300)
{
	bk_samples s;
	planted(&s, 8);
	bk_search_options o;
	small_options(&o, &s);
	bk_search *S = run(&o);
	o.evals = 32; /* one more generation after a load */
	size_t len;
	char *text = checkpoint_of(S, &len), err[512];
	static const int way[3] = {0x01, 0x10, 0x40};
	long refused = 0, loaded = 0;
	cr_assert(strstr(text, "\nchecksum "), "no checksum line");
	size_t body = (size_t)(strstr(text, "\nchecksum ") - text) + 1;
	for (size_t i = 0; i < len; i++)
		for (int w = 0; w < 3; w++) {
			char *m = malloc(len + 1);
			memcpy(m, text, len + 1);
			m[i] = (char)(m[i] ^ way[w]);
			cr_assert_eq(load_text(&o, m, len, err, sizeof err, NULL), -1, "byte %zu ^ %#x loaded", i, way[w]);
			if (i < body) {
				size_t sl;
				char *sealed = resealed_at(m, body, &sl);
				bk_search *L = NULL;
				if (load_text(&o, sealed, sl, err, sizeof err, &L) == 0) {
					if (loaded++ % 16 == 0) /* stepping on is the slow part: a sample of them */
						usable(L, &o);
					bk_search_free(L);
				} else {
					refused++;
				}
				free(sealed);
			}
			free(m);
		}
	printf("mutated checkpoint of %zu bytes: %ld resealed changes refused, %ld loaded\n", len, refused, loaded);
	cr_assert_gt(refused, 0);
	free(text);
	bk_search_free(S);
	bk_samples_free(&s);
}

/* L14: a budget below the fits a checkpoint holds and below its run's
 * budget is refused (the result would hold more fits than asked for); its
 * own budget, or a larger one, continues. */
Test(search, resume_with_a_smaller_budget_is_refused)
{
	bk_samples s;
	planted(&s, 8);
	bk_search_options o;
	small_options(&o, &s);
	bk_search *S = run(&o);
	long done = bk_search_evals(S);
	cr_assert_gt(done, 24); /* whole generations: past the budget */
	size_t len;
	char *text = checkpoint_of(S, &len), err[512];
	o.evals = 23;
	cr_assert_eq(load_text(&o, text, len, err, sizeof err, NULL), -1);
	char want[160];
	snprintf(want, sizeof want, "it holds %ld fits, more than --evals 23 (its run had --evals 24)", done);
	cr_assert_str_eq(err, want);
	o.evals = 24;
	cr_assert_eq(load_text(&o, text, len, err, sizeof err, NULL), 0, "%s", err);
	o.evals = 400;
	cr_assert_eq(load_text(&o, text, len, err, sizeof err, NULL), 0, "%s", err);
	free(text);
	bk_search_free(S);
	bk_samples_free(&s);
}

/* H1: the metrics leave out samples where a form is not finite; over none
 * they are 0. A form not finite somewhere has no error: +inf, whatever the
 * objective. */
Test(search, nonfinite_values_are_no_error)
{
	bk_samples s;
	planted(&s, 4);
	bk_search_options o;
	plant_options(&o, &s, 1, 10);
	bk_fit_metrics m;
	memset(&m, 0, sizeof m);
	m.nonfinite = s.n; /* NaN everywhere: every metric 0 */
	m.albedo_max_abs = 0;
	for (int obj = 0; obj < 3; obj++) {
		o.objective = (bk_objective)obj;
		cr_assert(isinf(bk_search_error(&o, &s, NULL, &m)), "objective %d: %g", obj, bk_search_error(&o, &s, NULL, &m));
	}
	m.nonfinite = 0; /* the negative control: finite values, error 0 */
	o.objective = BK_OBJ_RMSE;
	cr_assert_eq(bk_search_error(&o, &s, NULL, &m), 0);
	/* a seed NaN everywhere is never OK, and the front is of the others */
	static const char *const seeds[] = {"sqrt(LoH - 2)", "p0/(LoH*LoH + p1)"};
	plant_options(&o, &s, 1, 200);
	o.seeds = seeds;
	o.nseeds = 2;
	bk_search *S = run(&o);
	const bk_cand *c = bk_search_at(S, 0);
	cr_assert_str_eq(c->text, seeds[0]);
	cr_assert_eq(c->status, BK_CAND_NONFINITE);
	size_t idx[64], nf = bk_search_front(S, idx, 64);
	for (size_t k = 0; k < nf; k++)
		cr_assert_neq(idx[k], 0);
	bk_search_free(S);
	bk_samples_free(&s);
}

/* Every seed is fitted in the first step, however small the generation
 * (it took only the first `generation` of them). */
Test(search, every_seed_is_fitted_however_small_the_generation)
{
	bk_samples s;
	planted(&s, 8);
	static const char *const seeds[] = {"p0/(LoH*LoH + p1)", "p0*LoH", "p0 + LoH"};
	bk_search_options o;
	plant_options(&o, &s, 1, 20);
	o.seeds = seeds;
	o.nseeds = 3;
	o.generation = 2;
	bk_search *S = bk_search_new(&o, (char[256]){0}, 256);
	char err[256];
	cr_assert_eq(bk_search_step(S, err, sizeof err), 1, "%s", err);
	cr_assert_eq(bk_search_count(S), 3);
	for (int k = 0; k < 3; k++)
		cr_assert_str_eq(bk_search_at(S, (size_t)k)->text, seeds[k]);
	bk_search_free(S);
	bk_samples_free(&s);
}

/* M5: --enum-size 9 with a small budget builds only the trees it fits (the
 * enumeration was drawn whole up front: hundreds of millions of trees, out
 * of memory before the first fit), and fits the same candidates as
 * --enum-size 5 where the budget ends before size 6. Under a 512 MB limit
 * on the address space past what the test uses (not under AddressSanitizer,
 * whose shadow memory no such limit allows). */
Test(search, enumeration_of_size_9_is_drawn_as_needed, .timeout = 120)
{
#ifndef __SANITIZE_ADDRESS__
	long pages = 0;
	FILE *f = fopen("/proc/self/statm", "r");
	cr_assert(f && fscanf(f, "%ld", &pages) == 1);
	fclose(f);
	rlim_t lim = (rlim_t)pages * (rlim_t)sysconf(_SC_PAGESIZE) + (512ul << 20);
	struct rlimit rl = {lim, lim};
	cr_assert_eq(setrlimit(RLIMIT_AS, &rl), 0);
#endif
	bk_samples s;
	planted(&s, 8);
	bk_search_options o;
	plant_options(&o, &s, 1, 300);
	o.grammar.ops = bk_grammar_default_ops();
	o.grammar.max_params = 3;
	o.grammar.max_size = 24;
	o.enum_max = 300;
	o.enum_size = 9;
	bk_search *nine = run(&o);
	o.enum_size = 5;
	bk_search *five = run(&o);
	same(five, nine);
	bk_search_free(nine);
	bk_search_free(five);
	bk_samples_free(&s);
}

/* A seed given parsed (bk_search_options.seed_forms, as bk_seeds hands it on)
 * is the form fitted, not its text parsed again. Told apart by a form that
 * carries the seed's text on another program (its text field swapped, which
 * only a test can do): the planted seed p0/(LoH*LoH + p1) against the
 * program p0*LoH, which fits the planted target far worse. Its controls: with
 * no forms given the text is parsed, and with the text's own form given the
 * seed scores the same. */
static double seed_error(const bk_search_options *o)
{
	char err[256];
	bk_search *s = bk_search_new(o, err, sizeof err);
	cr_assert(s, "%s", err);
	cr_assert_geq(bk_search_step(s, err, sizeof err), 0, "%s", err); /* the seeds */
	double e = NAN;
	for (size_t i = 0; i < bk_search_count(s); i++)
		if (bk_search_at(s, i)->seed_name)
			e = bk_search_at(s, i)->err;
	bk_search_free(s);
	return e;
}

Test(search, a_seed_given_parsed_is_not_parsed_again)
{
	bk_samples s;
	planted(&s, 16);
	bk_search_options o;
	plant_options(&o, &s, 1, 1000);
	bk_form_error fe;
	bk_form *other = bk_form_parse("p0*LoH", &fe), *same = bk_form_parse(plant_seed[0], &fe);
	cr_assert(other && same);
	free(other->text); /* the seed's text on another program */
	other->text = strdup(plant_seed[0]);
	const bk_form *given[1] = {other};
	double as_text = seed_error(&o);
	o.seed_forms = given;
	double as_given = seed_error(&o);
	given[0] = same;
	double as_same = seed_error(&o);
	cr_expect(as_given > 1.5 * as_text, "the given form scored %g, its text %g: the text was parsed again", as_given,
	          as_text);
	cr_expect_eq(as_same, as_text, "the seed's own form, given: %g, parsed: %g", as_same, as_text);
	bk_form_free(other);
	bk_form_free(same);
	bk_samples_free(&s);
}
