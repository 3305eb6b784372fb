/*
 * pool.h — the analysis floor's one worker pool: n independent jobs on up
 * to T threads (issue 42; it was written three times: cmd_scene.c's
 * spec_pool, search_front.c's score_pool, lutscore.c's bake split).
 *
 * The contract that keeps output bytes independent of the thread count:
 *   - job i writes its result to a place of its own (index i), reads only
 *     what no job writes, and its result depends on i alone;
 *   - jobs are handed out in index order, each to one thread;
 *   - after(ctx, i, rc) runs under the pool's lock, one at a time, as each
 *     job ends (in the order they end: progress lines and counts, nothing
 *     that lands in a file);
 *   - a job that returns nonzero stops the handing out (the jobs running
 *     finish; those not started are not run), so the caller reads which
 *     jobs failed from its own results, in index order.
 * The calling thread works too; a thread that cannot start only makes the
 * run slower. Pools nest (a job may run a pool of its own): all state is
 * the call's but one count, of the threads running pools' jobs now; a
 * nested pool starts threads only for the cores none of those is on (scene:
 * sets on the cores, each refitting its forms on the cores the other sets
 * left idle), so its thread count is a most, not a promise: by the contract
 * above, the results are the same whatever it comes to.
 *
 * fit/search/screen.c's screening crew is not this pool: its workers start
 * before the batch is made and fit what is published so far, and the
 * merge takes the fitted candidates in order while the others still fit;
 * a pool over a fixed n cannot do that, and fit/ does not reach up here.
 */
#ifndef ANALYSIS_POOL_H
#define ANALYSIS_POOL_H

#define BK_POOL_MAX_THREADS 64 /* the search's --threads limit (fit/search) */

/* Job i (0 <= i < n); 0, or nonzero to stop the handing out. */
typedef int (*bk_pool_job)(void *ctx, int i);
/* After job i returned rc; under the pool's lock. */
typedef void (*bk_pool_after)(void *ctx, int i, int rc);

/* Runs job(ctx, i) for i = 0 .. n-1 on min(threads, n) threads, at least
 * one and at most BK_POOL_MAX_THREADS; after may be NULL. Returns 0 when
 * every job returned 0, else -1 (some job failed, or stopped the rest). */
int bk_pool_run(int n, int threads, bk_pool_job job, bk_pool_after after, void *ctx);

/* The online cores, at least 1 and at most cap: the default thread count
 * of a command without --threads. */
int bk_pool_cores(int cap);

#endif
