/*
 * test_islands.c — the island protocol (fit/search/islands.h) with a fake
 * transport: the ring's direction (an island sends to the next and takes
 * from the previous), the migrants picked evenly over the front, the rounds
 * and their end, the seeds of the islands (splitmix64, computed by hand in
 * Python).
 */
#include "fixture_search.h"
#include <criterion/criterion.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "search/islands.h"

static void planted(bk_samples *s)
{
	fx_planted("0.3/(LoH*LoH + 0.7*r*r)", 0.3162, 1, 12, s);
}

/* The small search these tests run: its grammar over LoH and r, one thread,
 * generations of 64. 0, or the grammar's error (no assertion here: the
 * split's ranks call it on threads of their own). */
static int small_search(const bk_samples *s, bk_search_options *o, char *err, size_t len)
{
	bk_search_defaults(o);
	o->screen = s;
	o->shape = BK_SHAPE_PLAIN;
	o->grammar.inputs = 1u << BK_IN_LOH | 1u << BK_IN_R;
	o->grammar.consts[0] = 1;
	o->grammar.nconsts = 1;
	o->grammar.max_params = 2;
	o->grammar.max_size = 12;
	o->threads = 1;
	o->generation = 64;
	return bk_grammar_parse_ops("+,*,/,sq", &o->grammar.ops, err, len);
}

static bk_search *island(const bk_samples *s, int r, int k, long evals)
{
	bk_search_options o;
	char err[256];
	cr_assert_eq(small_search(s, &o, err, sizeof err), 0, "%s", err);
	o.evals = evals;
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

/* ---- ranks that split one search's fits (bk_search_split) ----------------- */

/* Two "ranks" as two threads: the fake share meets at a barrier, each copies
 * the records it wrote into a common array, and each takes the other's. */
typedef struct fake_split {
	pthread_barrier_t bar;
	unsigned char *common;
	size_t cap;
	pthread_mutex_t mu;
	int fail; /* the share fails from this call on (1: the first; 0: never) */
} fake_split;

typedef struct rank_run {
	fake_split *f;
	bk_search_split sp;
	const bk_samples *s;
	bk_search *S;
	int rc, calls;
	char err[256];
} rank_run;

static int fake_share(void *ctx, void *rec, size_t recsize, size_t n)
{
	rank_run *r = ctx;
	fake_split *f = r->f;
	pthread_mutex_lock(&f->mu);
	if (f->cap < n * recsize) {
		unsigned char *c = realloc(f->common, n * recsize);
		if (!c) /* no assertion on a rank's thread */
			abort();
		f->common = c;
		f->cap = n * recsize;
	}
	pthread_mutex_unlock(&f->mu);
	pthread_barrier_wait(&f->bar);
	for (size_t i = (size_t)r->sp.rank; rec && i < n; i += 2)
		memcpy(f->common + i * recsize, (unsigned char *)rec + i * recsize, recsize);
	pthread_barrier_wait(&f->bar);
	for (size_t i = (size_t)(1 - r->sp.rank); rec && i < n; i += 2)
		memcpy((unsigned char *)rec + i * recsize, f->common + i * recsize, recsize);
	pthread_barrier_wait(&f->bar); /* neither grows common while the other reads it */
	r->calls++;
	return !rec || (f->fail && r->calls >= f->fail) ? -1 : 0; /* rec NULL: this rank failed (both, in this fake) */
}

static void *rank_main(void *arg)
{
	rank_run *r = arg;
	bk_search_options o; /* island()'s, with the enumeration and the split */
	if (small_search(r->s, &o, r->err, sizeof r->err)) {
		r->rc = -9;
		return NULL;
	}
	o.threads = 2;
	o.evals = 1500;
	o.enum_size = 4;
	o.seed = 7;
	o.split = &r->sp;
	r->S = bk_search_new(&o, r->err, sizeof r->err);
	r->rc = r->S ? bk_search_run(r->S, NULL, NULL, r->err, sizeof r->err) : -9;
	return NULL;
}

/* What a fit gave each candidate, and when: the same on both. */
static int same_search(const bk_search *a, const bk_search *b)
{
	if (bk_search_count(a) != bk_search_count(b))
		return 0;
	for (size_t i = 0; i < bk_search_count(a); i++) {
		const bk_cand *x = bk_search_at(a, i), *y = bk_search_at(b, i);
		if (strcmp(x->text, y->text) || x->status != y->status || x->found_at != y->found_at ||
		    memcmp(&x->err, &y->err, sizeof x->err) || memcmp(x->p, y->p, sizeof x->p))
			return 0;
	}
	return 1;
}

static void split_run(const bk_samples *s, int fail, rank_run r[2])
{
	static fake_split f;
	memset(&f, 0, sizeof f);
	pthread_barrier_init(&f.bar, NULL, 2);
	pthread_mutex_init(&f.mu, NULL);
	f.fail = fail;
	pthread_t th[2];
	for (int k = 0; k < 2; k++) {
		r[k] = (rank_run){&f, {k, 2, fake_share, &r[k]}, s, NULL, 0, 0, ""};
		cr_assert_eq(pthread_create(&th[k], NULL, rank_main, &r[k]), 0);
	}
	for (int k = 0; k < 2; k++)
		pthread_join(th[k], NULL);
	pthread_barrier_destroy(&f.bar);
	pthread_mutex_destroy(&f.mu);
	free(f.common);
}

/* A share with no other rank: rank 0 of 2 fitting its half alone (the
 * other half as the generation left it), the control's. */
static int alone_share(void *ctx, void *rec, size_t recsize, size_t n)
{
	(void)ctx;
	(void)rec;
	(void)recsize;
	(void)n;
	return 0;
}

/* Two ranks splitting the fits hold the search of one process (2 threads),
 * candidate by candidate: its text, status, fit number, error and
 * constants; the control: rank 0 of 2 whose share brings nothing from the
 * other rank holds another search, and the comparison fails. */
Test(islands, split_fits_hold_one_process_search)
{
	bk_samples s;
	planted(&s);
	rank_run one[1];
	fake_split none;
	memset(&none, 0, sizeof none);
	one[0] = (rank_run){&none, {0, 1, fake_share, &one[0]}, &s, NULL, 0, 0, ""};
	rank_main(&one[0]);
	cr_assert_geq(one[0].rc, 0, "%s", one[0].err);
	cr_assert_gt(bk_search_count(one[0].S), 500);
	rank_run r[2];
	split_run(&s, 0, r);
	for (int k = 0; k < 2; k++) {
		cr_assert_geq(r[k].rc, 0, "rank %d: %s", k, r[k].err);
		cr_expect(same_search(one[0].S, r[k].S), "rank %d of 2 differs from one process", k);
		bk_search_free(r[k].S);
	}
	rank_run lone = {&none, {0, 2, alone_share, NULL}, &s, NULL, 0, 0, ""};
	rank_main(&lone);
	cr_expect(lone.rc >= 0 && !same_search(one[0].S, lone.S), "control: rank 0 of 2 without the other's fits: %d %s",
	          lone.rc, lone.err);
	bk_search_free(lone.S);
	bk_search_free(one[0].S);
	bk_samples_free(&s);
}

/* A failed share fails the step on every rank, the message saying so:
 * from the first, second and third call on (the seeds' fits, the
 * enumeration's first trees looked at ahead, their fits; a search that ran
 * whole makes more than three calls, its premise). */
Test(islands, split_share_failure_fails_the_step)
{
	bk_samples s;
	planted(&s);
	rank_run r[2];
	split_run(&s, 0, r);
	cr_assert_gt(r[0].calls, 3, "premise: %d calls", r[0].calls);
	for (int k = 0; k < 2; k++)
		bk_search_free(r[k].S);
	for (int from = 1; from <= 3; from++) {
		split_run(&s, from, r);
		for (int k = 0; k < 2; k++) {
			cr_expect_eq(r[k].rc, -1, "from call %d, rank %d: %d", from, k, r[k].rc);
			cr_expect(strstr(r[k].err, "sharing a step's work among the 2 ranks failed"), "from call %d, rank %d: %s",
			          from, k, r[k].err);
			bk_search_free(r[k].S);
		}
	}
	bk_samples_free(&s);
}
