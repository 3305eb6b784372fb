/*
 * pool.c — n independent jobs on a few threads, taken in index order
 * (pool.h).
 */
#include "pool.h"

#include <pthread.h>
#include <stdatomic.h>
#include <unistd.h>

/* The threads inside some pool's work() now, process-wide, and how deep this
 * thread is in pools' jobs (a pool run from a job is nested: pool.h). */
static atomic_int busy;
static _Thread_local int depth;

typedef struct pool {
	int n, next, stop, failed;
	bk_pool_job job;
	bk_pool_after after;
	void *ctx;
	pthread_mutex_t mu; /* next, stop, failed, and every after() call */
} pool;

static void *work(void *arg)
{
	pool *P = arg;
	atomic_fetch_add(&busy, 1);
	depth++;
	for (;;) {
		pthread_mutex_lock(&P->mu);
		int i = P->stop ? P->n : P->next++;
		pthread_mutex_unlock(&P->mu);
		if (i >= P->n)
			break;
		int rc = P->job(P->ctx, i);
		pthread_mutex_lock(&P->mu);
		if (rc)
			P->stop = P->failed = 1;
		if (P->after)
			P->after(P->ctx, i, rc);
		pthread_mutex_unlock(&P->mu);
	}
	depth--;
	atomic_fetch_sub(&busy, 1);
	return NULL;
}

int bk_pool_run(int n, int threads, bk_pool_job job, bk_pool_after after, void *ctx)
{
	if (n <= 0)
		return 0;
	pool P = {n, 0, 0, 0, job, after, ctx, PTHREAD_MUTEX_INITIALIZER};
	int nt = threads < 1 ? 1 : threads > BK_POOL_MAX_THREADS ? BK_POOL_MAX_THREADS : threads;
	if (nt > n)
		nt = n;
	if (depth > 0) { /* nested: this thread and the cores no pool's thread is on */
		int idle = bk_pool_cores(BK_POOL_MAX_THREADS) - atomic_load(&busy);
		if (nt > 1 + (idle > 0 ? idle : 0))
			nt = 1 + (idle > 0 ? idle : 0);
	}
	pthread_t th[BK_POOL_MAX_THREADS];
	int started = 0;
	while (started < nt - 1 && pthread_create(&th[started], NULL, work, &P) == 0)
		started++;
	work(&P); /* this thread is one of the nt */
	for (int t = 0; t < started; t++)
		pthread_join(th[t], NULL);
	pthread_mutex_destroy(&P.mu);
	return P.failed ? -1 : 0;
}

int bk_pool_cores(int cap)
{
	long cores = sysconf(_SC_NPROCESSORS_ONLN);
	return cores < 1 ? 1 : cores > cap ? cap : (int)cores;
}
