/*
 * islands.c — rounds, ring migration and the merge of the search's islands
 * (islands.h).
 */
#include "search/islands.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

unsigned long bk_islands_seed(unsigned long seed, int r)
{
	uint64_t z = (uint64_t)seed + 0x9e3779b97f4a7c15ull * (uint64_t)(r + 1);
	z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
	z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
	z ^= z >> 31;
	return (unsigned long)(z & 0xffffffffu);
}

/* The candidates idx[0..n) of s as text (malloc'd). */
static char *export_text(const bk_search *s, const size_t *idx, size_t n, size_t *len)
{
	char *buf = NULL;
	FILE *f = open_memstream(&buf, len);
	if (!f)
		return NULL;
	int bad = bk_search_export(s, idx, n, f);
	if (fclose(f) || bad) {
		free(buf);
		return NULL;
	}
	return buf;
}

static int import_text(bk_search *s, const char *in, size_t n, char *err, size_t errlen)
{
	FILE *f = fmemopen((void *)in, n, "r");
	if (!f) {
		snprintf(err, errlen, "out of memory reading migrants");
		return -1;
	}
	size_t added;
	int rc = bk_search_import(s, f, &added, err, errlen);
	fclose(f);
	return rc;
}

size_t bk_islands_pick(const bk_search *s, int migrants, size_t *pick)
{
	size_t front[BK_ISLANDS_FRONT];
	size_t nf = bk_search_front(s, front, BK_ISLANDS_FRONT), n = 0;
	size_t want = migrants > 0 ? (size_t)migrants : 0;
	if (want > nf)
		want = nf;
	for (size_t i = 0; i < want; i++) /* evenly over the front, its ends included */
		pick[n++] = front[want > 1 ? i * (nf - 1) / (want - 1) : 0];
	return n;
}

int bk_islands_migrate(bk_search *s, const bk_islands_transport *t, int migrants, char *err, size_t errlen)
{
	size_t pick[BK_ISLANDS_FRONT];
	size_t n = bk_islands_pick(s, migrants, pick), len = 0, nin = 0;
	char *out = export_text(s, pick, n, &len), *in = NULL;
	int ok = out != NULL;
	*err = '\0';
	if (t->any(!ok)) {
		free(out);
		if (!ok)
			snprintf(err, errlen, "out of memory");
		return -1;
	}
	ok = t->ring(out, len, &in, &nin) == 0;
	free(out);
	if (ok && import_text(s, in, nin, err, errlen))
		ok = 0;
	else if (!ok)
		snprintf(err, errlen, "out of memory");
	free(in);
	return t->any(!ok) ? -1 : 0;
}

typedef struct round_goal {
	long fits;
} round_goal;

static int round_done(void *ctx, const bk_search *s)
{
	return bk_search_evals(s) >= ((const round_goal *)ctx)->fits;
}

int bk_islands_run(bk_search *s, const bk_islands_transport *t, long migrate, int migrants, long round0,
                   bk_islands_round_end round_end, void *ctx, char *err, size_t errlen)
{
	int done = 0;
	*err = '\0';
	for (long round = round0 + 1;; round++) {
		int failed = 0;
		round_goal g = {round * migrate};
		if (!done && bk_search_evals(s) < g.fits) {
			int st = bk_search_run(s, round_done, &g, err, errlen);
			failed = st < 0;
			done = st == 0; /* the budget spent or nothing left: not this round's end */
		}
		if (t->any(failed))
			return BK_ISLANDS_FAIL_SEARCH;
		if (bk_islands_migrate(s, t, migrants, err, errlen))
			return BK_ISLANDS_FAIL_MIGRATION;
		int rc = round_end(ctx, round, t->any(!done));
		if (rc)
			return rc < 0 ? BK_ISLANDS_FAIL_CALLER : 0;
	}
}

typedef struct merge_ctx {
	bk_search *s;
	char *err;
	size_t errlen;
} merge_ctx;

static int take_island(void *ctx, int rank, const char *in, size_t n)
{
	merge_ctx *m = ctx;
	char why[256];
	if (rank == 0) /* island 0's own candidates are already in its search */
		return 0;
	if (import_text(m->s, in, n, why, sizeof why)) {
		snprintf(m->err, m->errlen, "merging island %d: %s", rank, why);
		return -1;
	}
	return 0;
}

int bk_islands_merge(bk_search *s, const bk_islands_transport *t, int fronts_only, long *bytes, char *err,
                     size_t errlen)
{
	size_t n = t->rank == 0 ? 0 : bk_search_count(s), len = 0;
	size_t *idx = malloc(sizeof(size_t) * (n ? n : 1));
	*err = '\0';
	if (idx && fronts_only)
		n = bk_search_front(s, idx, n); /* the whole front: its every member */
	else
		for (size_t i = 0; idx && i < n; i++)
			idx[i] = i;
	char *out = idx ? export_text(s, idx, n, &len) : NULL;
	free(idx);
	int ok = out != NULL;
	if (t->any(!ok)) {
		free(out);
		if (!ok)
			snprintf(err, errlen, "out of memory");
		return -1;
	}
	merge_ctx m = {s, err, errlen};
	ok = t->gather(out, len, take_island, &m) == 0;
	*bytes = t->sum((long)len);
	free(out);
	return ok ? 0 : -1;
}
