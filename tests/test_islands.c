/*
 * test_islands.c — the island protocol (fit/search/islands.h) with a fake
 * transport: the ring's direction (an island sends to the next and takes
 * from the previous), the migrants picked evenly over the front, the rounds
 * and their end, the seeds of the islands (splitmix64, computed by hand in
 * Python).
 */
#include "fixture_search.h"
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "search/islands.h"

static void planted(bk_samples *s)
{
	fx_planted("0.3/(LoH*LoH + 0.7*r*r)", 0.3162, 1, 12, s);
}

static bk_search *island(const bk_samples *s, int r, int k, long evals)
{
	bk_search_options o;
	bk_search_defaults(&o);
	o.screen = s;
	o.shape = BK_SHAPE_PLAIN;
	char err[256];
	cr_assert_eq(bk_grammar_parse_ops("+,*,/,sq", &o.grammar.ops, err, sizeof err), 0);
	o.grammar.inputs = 1u << BK_IN_LOH | 1u << BK_IN_R;
	o.grammar.consts[0] = 1;
	o.grammar.nconsts = 1;
	o.grammar.max_params = 2;
	o.grammar.max_size = 12;
	o.threads = 1;
	o.evals = evals;
	o.generation = 64;
	o.island = r;
	o.islands = k;
	o.seed = bk_islands_seed(7, r);
	bk_search *S = bk_search_new(&o, err, sizeof err);
	cr_assert(S, "%s", err);
	return S;
}

/* The fake: island `rank` of 3; what it sends lands in box[rank + 1], what
 * it takes is box[rank] (put there by the test as island rank - 1's). */
static char *box[3];
static size_t boxlen[3];
static int fake_rank;
static long fake_sum(long v) { return v; }
static int fake_any(int v) { return v != 0; }
static int fake_ring(const char *buf, size_t n, char **in, size_t *nin)
{
	int to = (fake_rank + 1) % 3;
	free(box[to]);
	box[to] = malloc(n + 1);
	memcpy(box[to], buf, n);
	box[to][n] = '\0';
	boxlen[to] = n;
	*nin = boxlen[fake_rank];
	*in = malloc(*nin + 1);
	memcpy(*in, box[fake_rank] ? box[fake_rank] : "", *nin);
	(*in)[*nin] = '\0';
	return 0;
}

/* Island 0 runs, sends round the ring to island 1's box; island 1 takes
 * it: island 0's picks are then in island 1's search, marked island 0, and
 * island 1's own picks went on to island 2, not back to island 0. */
Test(islands, ring_goes_forward)
{
	bk_samples s;
	planted(&s);
	char err[256];
	bk_search *a = island(&s, 0, 3, 300), *b = island(&s, 1, 3, 300);
	cr_assert_geq(bk_search_run(a, NULL, NULL, err, sizeof err), 0);
	cr_assert_geq(bk_search_run(b, NULL, NULL, err, sizeof err), 0);
	memset(box, 0, sizeof box);
	memset(boxlen, 0, sizeof boxlen);
	FILE *f = open_memstream(&box[0], &boxlen[0]); /* island 2's migrants: none */
	cr_assert(f);
	cr_assert_eq(bk_search_export(b, NULL, 0, f), 0);
	fclose(f);
	char *none = strdup(box[0]);
	bk_islands_transport t = {0, 3, fake_ring, NULL, fake_sum, fake_any};
	fake_rank = 0;
	cr_assert_eq(bk_islands_migrate(a, &t, 4, err, sizeof err), 0, "%s", err);
	cr_expect(box[1] && boxlen[1] > 0, "island 0 sent nothing to island 1");
	cr_expect_null(box[2], "island 0 sent to island 2");
	cr_expect_str_eq(box[0], none, "island 0 sent backwards");
	free(none);
	size_t before = bk_search_count(b);
	t.rank = fake_rank = 1;
	cr_assert_eq(bk_islands_migrate(b, &t, 4, err, sizeof err), 0, "%s", err);
	cr_expect(box[2] && boxlen[2] > 0, "island 1 sent nothing to island 2");
	size_t from0 = 0;
	for (size_t i = before; i < bk_search_count(b); i++)
		from0 += bk_search_at(b, i)->island == 0;
	cr_expect_gt(from0, 0, "island 1 took nothing of island 0's");
	cr_expect_eq(from0, bk_search_count(b) - before);
	for (int k = 0; k < 3; k++)
		free(box[k]);
	bk_search_free(a);
	bk_search_free(b);
	bk_samples_free(&s);
}

/* Picks: min(migrants, front), the front's ends included; none for 0. */
Test(islands, picks_spread_over_the_front)
{
	bk_samples s;
	planted(&s);
	char err[256];
	bk_search *a = island(&s, 0, 1, 400);
	cr_assert_geq(bk_search_run(a, NULL, NULL, err, sizeof err), 0);
	size_t front[BK_ISLANDS_FRONT], pick[BK_ISLANDS_FRONT];
	size_t nf = bk_search_front(a, front, BK_ISLANDS_FRONT);
	cr_assert_geq(nf, 3, "front of %zu", nf);
	cr_expect_eq(bk_islands_pick(a, 0, pick), 0);
	cr_expect_eq(bk_islands_pick(a, 2, pick), 2);
	cr_expect(pick[0] == front[0] && pick[1] == front[nf - 1]);
	cr_expect_eq(bk_islands_pick(a, 48, pick), nf);
	bk_search_free(a);
	bk_samples_free(&s);
}

static int self_ring(const char *buf, size_t n, char **in, size_t *nin)
{
	*in = malloc(n + 1);
	memcpy(*in, buf, n);
	(*in)[n] = '\0';
	*nin = n;
	return 0;
}

typedef struct rounds {
	long seen[16];
	int more[16], n, stop_at;
} rounds;

static int on_round(void *ctx, long round, int more)
{
	rounds *r = ctx;
	r->seen[r->n] = round;
	r->more[r->n++] = more;
	return !more || round == r->stop_at || r->n == 16;
}

/* Rounds count on from where a resume left them, the last one says no
 * more, and a stop asked at round 2 ends there with budget left. */
Test(islands, rounds_and_their_end)
{
	bk_samples s;
	planted(&s);
	char err[256];
	bk_islands_transport t = {0, 1, self_ring, NULL, fake_sum, fake_any};
	bk_search *a = island(&s, 0, 1, 400);
	rounds r = {{0}, {0}, 0, -1};
	cr_assert_eq(bk_islands_run(a, &t, 100, 2, 1, on_round, &r, err, sizeof err), 0, "%s", err);
	cr_assert_geq(r.n, 2);
	cr_expect_eq(r.seen[0], 2); /* round 1 was the resumed run's */
	cr_expect_eq(r.seen[1], 3);
	cr_expect_eq(r.more[r.n - 1], 0);
	cr_expect_geq(bk_search_evals(a), 400);
	bk_search_free(a);
	bk_search *b = island(&s, 0, 1, 400);
	rounds q = {{0}, {0}, 0, 2};
	cr_assert_eq(bk_islands_run(b, &t, 100, 2, 0, on_round, &q, err, sizeof err), 0, "%s", err);
	cr_expect_eq(q.n, 2);
	cr_expect_lt(bk_search_evals(b), 400);
	bk_search_free(b);
	bk_samples_free(&s);
}

Test(islands, seeds_of_the_islands)
{
	/* splitmix64 of (seed, r) folded to 32 bits, by hand in Python */
	cr_expect_eq(bk_islands_seed(1, 1), 1703865447ul);
	cr_expect_eq(bk_islands_seed(1, 2), 4214379870ul);
	cr_expect_eq(bk_islands_seed(7, 1), 4097599004ul);
}
