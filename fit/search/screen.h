/*
 * screen.h — screening (internal to the search): each candidate of a batch
 * fitted on the screening samples with the fast solver (few iterations,
 * deterministic starts), its values judged by the one constraint predicate
 * (search/constraint.h) and scored by the objective, rounded to
 * BK_SEARCH_ERR_BITS. A batch runs on the search's threads; each candidate's
 * result depends on it alone, so any thread count gives the same bytes.
 */
#ifndef FIT_SEARCH_SCREEN_H
#define FIT_SEARCH_SCREEN_H

#include "search/search_int.h"

#include <pthread.h>
#include <stdatomic.h>

/* Fits c (its text, text_b and np set) and fills p, status, err and the
 * metrics. seed_p: the first start (a seed's published constants, a child's
 * inherited ones), or NULL for the default starts alone. */
void bk_screen_one(const bk_search *s, bk_cand *c, const double *seed_p);

/* A batch: bk_screen_one of c[i] from seed_p[i] on s->o.threads threads,
 * the fits under way while the batch is made and the results handed on
 * while the last fits run (the step's generation and merge are serial: ~7 %
 * and ~1 % of a 2-thread step, idle threads beside them). begin starts threads - 1 workers for a batch of at most cap candidates;
 * they fit c[i] once ready(n) has said i < n. end says the batch is n long,
 * fits what is left on this thread too, calls each(ctx, i) on this thread
 * for i = 0 .. n-1 in order, each as soon as c[0..i] are fitted, and joins
 * the workers. c[i] and seed_p[i] must be whole before ready names them;
 * between begin and end the caller must not write what bk_screen_one reads
 * of s (its options), nor each() touch a candidate after i. Each fit is its
 * own, so the results do not depend on the threads or on when ready is
 * called. */
typedef struct bk_screen_crew {
	const bk_search *s;
	bk_cand *c;
	const double *const *seed_p;
	atomic_size_t next;  /* the next candidate a worker takes */
	size_t ready;        /* candidates published; under mu */
	int closed;          /* no more will be; under mu */
	unsigned char *done; /* fitted, by candidate; under mu (NULL: out of memory) */
	int waiting;         /* end's thread waits for one; under mu */
	pthread_mutex_t mu;
	pthread_cond_t cv;
	pthread_t th[64];
	int started;
} bk_screen_crew;
void bk_screen_begin(bk_screen_crew *w, const bk_search *s, bk_cand *c, const double *const *seed_p, size_t cap);
void bk_screen_ready(bk_screen_crew *w, size_t n);
/* Split among ranks (bk_search_options.split), this process fits only its
 * share of the batch, and end shares the results (bk_search_split) before
 * it hands any on: 0, or -1 when the sharing failed (nothing handed on). */
int bk_screen_end(bk_screen_crew *w, size_t n, void (*each)(void *ctx, size_t i), void *ctx);

#endif
