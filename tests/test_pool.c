/*
 * test_pool.c — the analysis floor's worker pool (analysis/pool.h): every
 * job once, results by index the same bits for any thread count, jobs
 * handed out in index order, a failing job stops the handing out, after()
 * once per job, a nested pool starts threads only for idle cores; each
 * check beside a control that shows it can fail.
 */
#include <criterion/criterion.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "pool.h"

TestSuite(pool, .timeout = 30);

#define N 200

typedef struct run {
	int calls[N];        /* how often job i ran */
	double out[N];       /* job i's result */
	int order[N], norder; /* the jobs in the order they started (under mu) */
	int after_calls, after_rc[N];
	int fail_at;         /* the job that returns 1; -1: none */
	int nap_ms;          /* each job sleeps this long */
	pthread_t who[N];
	pthread_mutex_t mu;
} run;

static int job(void *ctx, int i)
{
	run *R = ctx;
	pthread_mutex_lock(&R->mu);
	R->calls[i]++;
	R->order[R->norder++] = i;
	pthread_mutex_unlock(&R->mu);
	R->who[i] = pthread_self();
	if (R->nap_ms && i != R->fail_at) { /* the failing job ends at once: the others are still asleep */
		struct timespec ts = {0, R->nap_ms * 1000000L};
		nanosleep(&ts, NULL);
	}
	double x = i + 0.5; /* a value that depends on i alone: a few rounding steps */
	for (int k = 0; k < 50; k++)
		x = x * 1.0000001 + 1.0 / (k + 1.0);
	R->out[i] = x;
	return i == R->fail_at;
}

/* under the pool's lock: no lock of its own */
static void after(void *ctx, int i, int rc)
{
	run *R = ctx;
	R->after_calls++;
	R->after_rc[i] = rc;
}

static void start(run *R, int fail_at, int nap_ms)
{
	memset(R, 0, sizeof *R);
	R->fail_at = fail_at;
	R->nap_ms = nap_ms;
	pthread_mutex_init(&R->mu, NULL);
}

static int distinct_threads(const run *R, int n)
{
	int d = 0;
	for (int i = 0; i < n; i++) {
		int seen = 0;
		for (int j = 0; j < i && !seen; j++)
			seen = pthread_equal(R->who[i], R->who[j]);
		d += !seen;
	}
	return d;
}

Test(pool, every_job_once_and_the_same_bits_for_any_thread_count)
{
	static run one, many;
	start(&one, -1, 0);
	cr_assert_eq(bk_pool_run(N, 1, job, after, &one), 0);
	const int counts[] = {2, 3, 7, 64, 1000, 0, -5}; /* 1000: clamped to 64; 0 and -5: one thread */
	for (size_t c = 0; c < sizeof counts / sizeof *counts; c++) {
		start(&many, -1, 0);
		cr_assert_eq(bk_pool_run(N, counts[c], job, after, &many), 0);
		for (int i = 0; i < N; i++)
			cr_assert_eq(many.calls[i], 1, "%d threads: job %d ran %d times", counts[c], i, many.calls[i]);
		cr_assert_eq(many.after_calls, N);
		cr_assert_eq(memcmp(one.out, many.out, sizeof one.out), 0, "%d threads: other bits", counts[c]);
	}
	/* control: the comparison sees one job's result changed */
	many.out[N / 2] += 1e-12;
	cr_assert_neq(memcmp(one.out, many.out, sizeof one.out), 0);
}

Test(pool, one_thread_takes_the_jobs_in_index_order_on_this_thread)
{
	static run R;
	start(&R, -1, 0);
	cr_assert_eq(bk_pool_run(N, 1, job, NULL, &R), 0);
	cr_assert_eq(R.norder, N);
	for (int i = 0; i < N; i++) {
		cr_assert_eq(R.order[i], i);
		cr_assert(pthread_equal(R.who[i], pthread_self()));
	}
}

Test(pool, runs_on_several_threads_and_no_more_than_asked)
{
	static run R;
	start(&R, -1, 20); /* 16 jobs of 20 ms: every thread gets some */
	cr_assert_eq(bk_pool_run(16, 4, job, NULL, &R), 0);
	int d = distinct_threads(&R, 16);
	cr_assert(d >= 2 && d <= 4, "%d threads ran the jobs", d);
	/* control: one thread asked, one ran them */
	start(&R, -1, 1);
	cr_assert_eq(bk_pool_run(16, 1, job, NULL, &R), 0);
	cr_assert_eq(distinct_threads(&R, 16), 1);
	/* no more threads than jobs: two jobs, at most two threads */
	start(&R, -1, 20);
	cr_assert_eq(bk_pool_run(2, 8, job, NULL, &R), 0);
	cr_assert_leq(distinct_threads(&R, 2), 2);
}

Test(pool, a_failing_job_stops_the_handing_out)
{
	static run R;
	start(&R, 5, 0);
	cr_assert_eq(bk_pool_run(N, 1, job, after, &R), -1);
	for (int i = 0; i < N; i++)
		cr_assert_eq(R.calls[i], i <= 5, "job %d ran %d times", i, R.calls[i]);
	cr_assert_eq(R.after_calls, 6);
	cr_assert_eq(R.after_rc[5], 1);
	cr_assert_eq(R.after_rc[4], 0);
	/* with threads the jobs running finish, and no job after them starts:
	 * at most threads - 1 past the failure */
	start(&R, 5, 20);
	cr_assert_eq(bk_pool_run(N, 4, job, after, &R), -1);
	int ran = 0;
	for (int i = 0; i < N; i++)
		ran += R.calls[i];
	cr_assert(R.calls[5] == 1 && ran <= 5 + 1 + 3, "%d jobs ran", ran);
	/* control: the last job failing is still a failure; none failing is not */
	start(&R, N - 1, 0);
	cr_assert_eq(bk_pool_run(N, 3, job, NULL, &R), -1);
	start(&R, -1, 0);
	cr_assert_eq(bk_pool_run(N, 3, job, NULL, &R), 0);
}

Test(pool, no_jobs_run_nothing)
{
	static run R;
	start(&R, 0, 0); /* job 0 would fail: it is never called */
	cr_assert_eq(bk_pool_run(0, 4, job, after, &R), 0);
	cr_assert_eq(bk_pool_run(-3, 4, job, after, &R), 0);
	cr_assert_eq(R.norder, 0);
	cr_assert_eq(R.after_calls, 0);
	/* control: one job, the failing one, is called */
	cr_assert_eq(bk_pool_run(1, 4, job, after, &R), -1);
	cr_assert_eq(R.norder, 1);
}

Test(pool, cores_are_capped)
{
	cr_assert_eq(bk_pool_cores(1), 1);
	int c = bk_pool_cores(BK_POOL_MAX_THREADS);
	cr_assert(c >= 1 && c <= BK_POOL_MAX_THREADS);
	cr_assert_geq(bk_pool_cores(1000), c);
}

/* A pool run from a job (nested) starts threads only for the cores no pool
 * thread is on (pool.h): with every core running an outer job at once (a
 * barrier holds them together), each inner pool asking 8 threads runs its
 * jobs on its own thread alone; with one outer thread, the inner pool gets
 * the other cores (the control: the cap lets threads through where cores
 * are idle). */
typedef struct nest {
	pthread_barrier_t all_in; /* every outer job started */
	int inner_threads[BK_POOL_MAX_THREADS];
	int wait;
} nest;

static int nested_job(void *ctx, int k)
{
	nest *Q = ctx;
	if (Q->wait)
		pthread_barrier_wait(&Q->all_in);
	/* no assertion here, off the test's thread: what is seen is kept, and
	 * the test checks it (-1: the inner pool failed) */
	run *R = calloc(1, sizeof *R);
	if (R) {
		start(R, -1, 10);
		Q->inner_threads[k] = bk_pool_run(8, 8, job, NULL, R) ? -1 : distinct_threads(R, 8);
	}
	if (Q->wait)
		pthread_barrier_wait(&Q->all_in); /* no outer job ends before every inner pool has */
	free(R);
	return 0;
}

Test(pool, a_nested_pool_takes_only_the_idle_cores)
{
	int c = bk_pool_cores(BK_POOL_MAX_THREADS);
	static nest Q;
	memset(&Q, 0, sizeof Q);
	Q.wait = 1;
	cr_assert_eq(pthread_barrier_init(&Q.all_in, NULL, (unsigned)c), 0);
	cr_assert_eq(bk_pool_run(c, c, nested_job, NULL, &Q), 0);
	pthread_barrier_destroy(&Q.all_in);
	for (int k = 0; k < c; k++)
		cr_assert_eq(Q.inner_threads[k], 1, "outer job %d of %d: its inner pool ran on %d threads", k, c,
		             Q.inner_threads[k]);
	/* control: one outer thread; its inner pool may take every other core */
	memset(&Q, 0, sizeof Q);
	cr_assert_eq(bk_pool_run(1, 1, nested_job, NULL, &Q), 0);
	cr_assert_leq(Q.inner_threads[0], c);
	if (c >= 2)
		cr_assert_geq(Q.inner_threads[0], 2, "idle cores left unused: %d thread", Q.inner_threads[0]);
}
