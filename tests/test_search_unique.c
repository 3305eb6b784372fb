/*
 * test_search_unique.c — the enumeration's unique forms and the certificate
 * (fit/search/unique.h, bk_search_certificate of fit/search.h): twins are
 * recognised by their values, a form of the grammar within the certified
 * size is on the front at every seed, and the same search with that one
 * structure taken out of the enumeration by hand does not have it (the
 * negative control: the test can fail).
 */
#include "fixture_search.h"
#include "search/search_int.h"
#include "search/seeds.h"
#include "search/unique.h"

#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* 0.5 LoH (r + 0.3): the tree LoH*(p0 + r), 5 nodes, scaled p0*(LoH*(p1 +
 * r)) as the search fits it; no tree of 4 nodes or fewer spells it (the
 * control below shows it: without the one tree nothing reaches it). */
#define PLANTED "0.5*LoH*(r + 0.3)"
#define PLANTED_TREE "LoH * (p0 + r)"
#define PLANTED_SIZE 5

static bk_search *planted_search(const bk_samples *s, unsigned long seed)
{
	bk_search_options o;
	fx_plain_options(&o, s, 1u << BK_IN_LOH | 1u << BK_IN_R | 1u << BK_IN_A, 4, 24);
	o.grammar.consts[0] = 1;
	o.grammar.nconsts = 1;
	o.enum_size = PLANTED_SIZE;
	o.enum_max = 1000000;
	o.generation = 8192; /* one batch holds the whole enumeration (5,801 fits) */
	o.evals = 1;         /* and the run ends with it: no evolution */
	o.seed = seed;
	o.threads = 2;
	char err[256];
	bk_search *S = bk_search_new(&o, err, sizeof err);
	cr_assert(S, "%s", err);
	return S;
}

static double best_rmse(const bk_search *S)
{
	double best = HUGE_VAL;
	for (size_t i = 0; i < bk_search_count(S); i++) {
		const bk_cand *c = bk_search_at(S, i);
		if (c->status == BK_CAND_OK && c->rmse < best)
			best = c->rmse;
	}
	return best;
}

static int leave_out_planted(void *ctx, const bk_expr *t)
{
	char text[256];
	(void)ctx;
	return bk_expr_print(t, text, sizeof text) > 0 && !strcmp(text, PLANTED_TREE);
}

Test(search_unique, twins_are_one_model_and_branches_are_not)
{
	bk_samples s;
	fx_planted(PLANTED, 0.3162, 1, 16, &s);
	bk_search *S = planted_search(&s, 1);
	uint64_t r = bk_unique_fingerprint(S, "p0*r", NULL);
	cr_assert_neq(r, 0);
	/* identities over the domain r in [0, 1], a = r^2 */
	cr_assert_eq(bk_unique_fingerprint(S, "p0*saturate(r)", NULL), r);
	cr_assert_eq(bk_unique_fingerprint(S, "p0*sqrt(a)", NULL), r);
	cr_assert_eq(bk_unique_fingerprint(S, "p0*max(r, 0)", NULL), r);
	/* not one model: another input, a branch a parameter decides (the
	 * vectors put p1 below and above r), a reparametrisation (documented:
	 * unique.h counts it as two) */
	cr_assert_neq(bk_unique_fingerprint(S, "p0*a", NULL), r);
	cr_assert_neq(bk_unique_fingerprint(S, "p0*max(r, p1)", NULL), bk_unique_fingerprint(S, "p0*max(r, 0*p1)", NULL));
	cr_assert_neq(bk_unique_fingerprint(S, "p0*(r + p1)", NULL), bk_unique_fingerprint(S, "p0*r + p1", NULL));
	/* a twin of one fitted at no greater cost is left out, a cheaper twin
	 * is not (it becomes the model's fitted spelling) */
	cr_assert_eq(bk_unique_twin(S, r, 3), 0);
	cr_assert_eq(bk_unique_twin(S, r, 3), 1);
	cr_assert_eq(bk_unique_twin(S, r, 5), 1);
	cr_assert_eq(bk_unique_twin(S, r, 2), 0);
	cr_assert_eq(bk_unique_twin(S, 0, 1), 0, "an unparsed form is nobody's twin");
	bk_search_free(S);
	bk_samples_free(&s);
}

/* A search on kind's screening samples as brdfkit search makes them
 * (fit/search/seeds.h), for its fingerprints. */
static bk_search *grid_search(bk_target_kind kind, bk_samples *sm)
{
	bk_target_options to;
	bk_target_defaults(kind, &to);
	bk_seeds_screening_grid(&to);
	char err[256];
	cr_assert_eq(bk_target_build(&to, sm, NULL, NULL, err, sizeof err), 0, "%s", err);
	bk_search_options o;
	fx_plain_options(&o, sm, sm->provides & ~(1u << BK_IN_F0), 4, 9);
	bk_search *S = bk_search_new(&o, err, sizeof err);
	cr_assert(S, "%s", err);
	return S;
}

/* How many distinct values the m values v hold (one input's column). */
static size_t distinct(const double *v, size_t m)
{
	size_t d = 0;
	for (size_t i = 0; i < m; i++) {
		size_t j = 0;
		while (j < i && v[j] != v[i])
			j++;
		d += j == i;
	}
	return d;
}

/* Gates that are open at some inputs or parameters and shut at others are
 * not their cheaper twins: p0*saturate(rcp(NoV) - NoV) is p0 for NoV <=
 * 0.618 only, p0*saturate(p1 / r) is not p0*saturate(p1 / LoH) where p1 is
 * in (0, 1). Env's 512 and vf2d's 1,024 samples are grids whose sizes are
 * multiples of 64: probes at sample i n / 64 saw NoV (LoH) at 2 values and
 * took these for twins (the controls below put those probes, and vectors
 * whose p1 is never in (0, 1), back: the assertions then fail). */
Test(search_unique, gates_that_shut_between_probes_are_not_twins)
{
	bk_samples env, vf2d;
	bk_search *E = grid_search(BK_TARGET_ENV, &env), *V = grid_search(BK_TARGET_VF2D, &vf2d);
	/* the probes see every NoV of env's grid and every LoH of vf2d's */
	cr_assert_eq(distinct(E->uq.in[BK_IN_NOV], E->uq.m), distinct(env.in[BK_IN_NOV], env.n));
	cr_assert_eq(distinct(V->uq.in[BK_IN_LOH], V->uq.m), distinct(vf2d.in[BK_IN_LOH], vf2d.n));
	cr_assert_geq(distinct(env.in[BK_IN_NOV], env.n), 16);
	uint64_t p0 = bk_unique_fingerprint(E, "p0", NULL);
	cr_assert_neq(bk_unique_fingerprint(E, "p0*saturate(rcp(NoV) - NoV)", NULL), p0);
	cr_assert_neq(bk_unique_fingerprint(E, "p0*max(rcp(NoV), exp2(NoV))", NULL), bk_unique_fingerprint(E, "p0/NoV", NULL));
	cr_assert_neq(bk_unique_fingerprint(V, "p0*saturate(rcp(LoH) - sq(LoH))", NULL), bk_unique_fingerprint(V, "p0", NULL));
	cr_assert_neq(bk_unique_fingerprint(V, "p0*saturate(p1/r)", NULL), bk_unique_fingerprint(V, "p0*saturate(p1/LoH)", NULL));
	cr_assert_neq(bk_unique_fingerprint(V, "p0*saturate(p1 + exp2(LoH))", NULL),
	              bk_unique_fingerprint(V, "p0*saturate(p1 + rsqrt(LoH))", NULL));
	/* an identity over the domain is still one model on these grids */
	cr_assert_eq(bk_unique_fingerprint(E, "p0*saturate(r)", NULL), bk_unique_fingerprint(E, "p0*r", NULL));
	cr_assert_eq(bk_unique_fingerprint(V, "p0*sqrt(a)", NULL), bk_unique_fingerprint(V, "p0*r", NULL));

	/* the controls: the probes of before (sample i n / 64) */
	for (int k = 0; k < BK_IN_COUNT; k++)
		for (size_t i = 0; E->uq.in[k] && env.in[k] && i < E->uq.m; i++)
			E->uq.in[k][i] = env.in[k][i * env.n / E->uq.m];
	cr_assert_eq(distinct(E->uq.in[BK_IN_NOV], E->uq.m), 2);
	cr_assert_eq(bk_unique_fingerprint(E, "p0*saturate(rcp(NoV) - NoV)", NULL), bk_unique_fingerprint(E, "p0", NULL),
	             "with NoV probed at two values the gate is not seen (the assertion above can fail)");
	/* and p1 never in (0, 1): 1.61, 2.9, -0.37 as before, the fourth vector
	 * a copy of the first */
	static const double before[UNIQUE_VECTORS] = {1.61, 2.9, -0.37, 1.61};
	for (int t = 0; t < UNIQUE_VECTORS; t++)
		V->uq.theta[t][1] = before[t];
	cr_assert_eq(bk_unique_fingerprint(V, "p0*saturate(p1/r)", NULL), bk_unique_fingerprint(V, "p0*saturate(p1/LoH)", NULL),
	             "with p1 never in (0, 1) the gate is not seen (the assertion above can fail)");
	bk_search_free(E), bk_search_free(V);
	bk_samples_free(&env), bk_samples_free(&vf2d);
}

Test(search_unique, a_planted_form_within_the_certificate_is_on_the_front_at_every_seed)
{
	bk_samples s;
	fx_planted(PLANTED, 0.3162, 1, 16, &s);
	for (unsigned long seed = 1; seed <= 3; seed++) {
		bk_search *S = planted_search(&s, seed);
		char err[256];
		cr_assert_geq(bk_search_run(S, NULL, NULL, err, sizeof err), 0, "%s", err);
		bk_search_cert c;
		bk_search_certificate(S, &c);
		cr_assert_eq(c.complete_size, PLANTED_SIZE, "seed %lu: complete to %d nodes", seed, c.complete_size);
		long drawn = 0, twins = 0, fitted = 0;
		for (int k = 1; k <= PLANTED_SIZE; k++) {
			cr_assert_geq(c.drawn[k], c.twins[k] + c.fitted[k], "size %d", k);
			drawn += c.drawn[k], twins += c.twins[k], fitted += c.fitted[k];
		}
		cr_assert_eq(fitted, bk_search_evals(S), "every fit of this run is one of the enumeration's");
		cr_assert_gt(twins, drawn / 10, "%ld twins of %ld trees", twins, drawn);
		double e = best_rmse(S);
		cr_assert_leq(e, 1e-9, "seed %lu: the planted form not recovered (rmse %g)", seed, e);
		bk_search_free(S);
	}
	/* the negative control: the same search without the one tree does not
	 * reach the target (so the assertion above is about that tree) */
	bk_search *S = planted_search(&s, 1);
	S->enum_leave_out = leave_out_planted;
	char err[256];
	cr_assert_geq(bk_search_run(S, NULL, NULL, err, sizeof err), 0, "%s", err);
	cr_assert_gt(best_rmse(S), 1e-4, "without " PLANTED_TREE " the target is still reached: %g", best_rmse(S));
	bk_search_free(S);
	bk_samples_free(&s);
}

/* The certificate says how far the enumeration got, not how far it was
 * asked to go: cut by its cap of fits it is complete to a smaller size. */
Test(search_unique, a_cut_enumeration_certifies_less)
{
	bk_samples s;
	fx_planted(PLANTED, 0.3162, 1, 16, &s);
	bk_search *S = planted_search(&s, 1);
	S->o.enum_max = 300; /* size 4 alone needs more fits */
	char err[256];
	cr_assert_geq(bk_search_run(S, NULL, NULL, err, sizeof err), 0, "%s", err);
	bk_search_cert c;
	bk_search_certificate(S, &c);
	cr_assert_eq(c.complete_size, 3, "a cap of 300 fits: complete to %d nodes", c.complete_size);
	cr_assert_gt(c.drawn[4], 0, "size 4 begun");
	bk_search_free(S);
	bk_samples_free(&s);
}

/* A run stopped in the middle of the enumeration and resumed from its
 * checkpoint leaves out the same twins as one that never stopped (the
 * fingerprints fitted travel in the checkpoint): the same candidates, the
 * same counts. The control: a resumed run whose checkpoint lost its twins
 * (the line emptied by hand) fits some twins again, so the comparison can
 * fail. */
static bk_search *enum_run(const bk_samples *s, long evals, const char *ck, size_t len, int drop_twins)
{
	bk_search *S = planted_search(s, 1);
	S->o.generation = 256;
	S->o.evals = evals;
	char err[256];
	if (ck) {
		char *text = malloc(len + 1);
		memcpy(text, ck, len);
		text[len] = '\0';
		if (drop_twins) { /* "twins N" and its N lines out, the checksum made again */
			char *t = strstr(text, "\ntwins "), *c;
			cr_assert(t);
			long n = strtol(t + 7, &c, 10);
			for (long i = 0; i < n; i++) /* past the N lines of fingerprints */
				c = strchr(c + 1, '\n');
			memmove(t + 8, c, strlen(c) + 1);
			memcpy(t, "\ntwins 0", 8);
			char *sum = strstr(text, "checksum ");
			cr_assert(sum);
			snprintf(sum, 32, "checksum %016llx\n", (unsigned long long)bk_hash_bytes(BK_HASH_INIT, text, (size_t)(sum - text)));
			len = strlen(text);
		}
		FILE *f = fmemopen(text, len, "r");
		cr_assert_eq(bk_search_load(S, f, err, sizeof err), 0, "%s", err);
		fclose(f);
		free(text);
	}
	cr_assert_geq(bk_search_run(S, NULL, NULL, err, sizeof err), 0, "%s", err);
	return S;
}

Test(search_unique, a_resume_in_the_enumeration_leaves_out_the_same_twins)
{
	bk_samples s;
	fx_planted(PLANTED, 0.3162, 1, 16, &s);
	bk_search *part = enum_run(&s, 700, NULL, 0, 0);
	bk_search_cert c;
	bk_search_certificate(part, &c);
	cr_assert_lt(c.complete_size, PLANTED_SIZE, "the part stops inside the enumeration");
	char *ck = NULL;
	size_t len = 0;
	FILE *f = open_memstream(&ck, &len);
	cr_assert_eq(bk_search_save(part, f), 0);
	fclose(f);
	bk_search *whole = enum_run(&s, 3000, NULL, 0, 0), *resumed = enum_run(&s, 3000, ck, len, 0);
	bk_search *lost = enum_run(&s, 3000, ck, len, 1);
	cr_assert_eq(bk_search_count(resumed), bk_search_count(whole));
	for (size_t i = 0; i < bk_search_count(whole); i++)
		cr_assert_str_eq(bk_search_at(resumed, i)->text, bk_search_at(whole, i)->text, "candidate %zu", i);
	bk_search_cert a, b, l;
	bk_search_certificate(whole, &a);
	bk_search_certificate(resumed, &b);
	bk_search_certificate(lost, &l);
	long ta = 0, tl = 0;
	for (int k = 1; k <= BK_EXPR_MAX; k++) {
		cr_assert_eq(a.twins[k], b.twins[k], "size %d", k);
		cr_assert_eq(a.fitted[k], b.fitted[k], "size %d", k);
		ta += a.twins[k], tl += l.twins[k];
	}
	cr_assert_lt(tl, ta, "without its twins the resumed run left out as many (%ld, %ld)", tl, ta);
	free(ck);
	bk_search_free(part), bk_search_free(whole), bk_search_free(resumed), bk_search_free(lost);
	bk_samples_free(&s);
}

/* The fingerprint's rounding (unique.h, bk_unique_quantum): 32 significant
 * bits, half to even, as frexp, ldexp and nearbyint define it (ref, below),
 * which the bit path it takes for normal doubles must equal. Closed forms
 * first: 1 + 2^-32 is m 2^32 = 2^31 + 1/2, so it rounds to the even 2^31,
 * the value of 1 itself (half up would make it 1 + 2^-31's); 1 + 3 2^-32 is
 * 2^31 + 3/2, up to 2^31 + 2, 1 + 2^-30's; 2 - 2^-52 carries to 2^32. */
static uint64_t ref(double v)
{
	if (isnan(v))
		return 1;
	if (isinf(v))
		return v > 0 ? 2 : 3;
	if (v == 0)
		return 4;
	int e;
	double m = frexp(v, &e);
	int64_t q = (int64_t)nearbyint(ldexp(m, 32));
	return ((uint64_t)q << 12) ^ (uint64_t)(e + 2048) ^ 0x5bd1e995u;
}

Test(search_unique, values_are_kept_to_32_significant_bits_half_to_even)
{
	cr_assert_eq(bk_unique_quantum(1 + 0x1p-32), bk_unique_quantum(1.0));
	cr_assert_neq(bk_unique_quantum(1 + 0x1p-31), bk_unique_quantum(1.0));
	cr_assert_eq(bk_unique_quantum(1 + 3 * 0x1p-32), bk_unique_quantum(1 + 0x1p-30));
	cr_assert_eq(bk_unique_quantum(-1 - 3 * 0x1p-32), bk_unique_quantum(-1 - 0x1p-30));
	cr_assert_neq(bk_unique_quantum(-1.0), bk_unique_quantum(1.0));
	cr_assert_eq(bk_unique_quantum(1 + 0x1p-33), bk_unique_quantum(1.0));
	cr_assert_eq(bk_unique_quantum(2 - 0x1p-52), ref(2 - 0x1p-52));
	cr_assert_eq(bk_unique_quantum(0.0), bk_unique_quantum(-0.0));
	cr_assert_eq(bk_unique_quantum(NAN), 1);
	cr_assert_eq(bk_unique_quantum(INFINITY), 2);
	cr_assert_eq(bk_unique_quantum(-INFINITY), 3);
	const double edge[] = {0x1p-1074, -0x1p-1074, 0x1.8p-1070, 0x1.fffffffffffffp-1023, 0x1p-1022, -0x1p-1022,
	                       0x1.fffffffffffffp+1023, -0x1.fffffffffffffp+1023, 0.5, 1e-300, 6.1e-5, 65504};
	for (size_t i = 0; i < sizeof edge / sizeof *edge; i++)
		cr_assert_eq(bk_unique_quantum(edge[i]), ref(edge[i]), "%a", edge[i]);
	/* random bit patterns, and the same with their 21 low bits exactly half
	 * (ties) and all ones (a carry into the next power of two) */
	uint64_t x = 0x9e3779b97f4a7c15ull;
	for (int i = 0; i < 300000; i++) {
		x ^= x << 13, x ^= x >> 7, x ^= x << 17;
		uint64_t b = i % 3 == 0 ? x : i % 3 == 1 ? (x & ~0x1fffffull) | 0x100000u : x | 0x1fffffu;
		double v;
		memcpy(&v, &b, sizeof v);
		cr_assert_eq(bk_unique_quantum(v), ref(v), "%a", v);
	}
}
