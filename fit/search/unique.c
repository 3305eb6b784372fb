/*
 * unique.c — semantically unique candidates (unique.h).
 */
#include "search/unique.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Parameter vector t's value of parameter j: magnitudes 0.37, 1.61 and 2.9
 * in turn over the three vectors (each parameter once below 1, twice
 * above, at different values), one of the three negative, and a small
 * drift with j so that no two parameters are equal at a vector (p0 - p1
 * must not vanish). */
static double probe_param(int t, int j)
{
	static const double mag[3] = {0.37, 1.61, 2.9};
	double v = mag[(t + j) % 3] * (1 + 0.013 * j);
	return (t + 2 * j) % 3 == 1 ? -v : v;
}

int bk_unique_init(bk_search *s)
{
	const bk_samples *sm = s->o.screen;
	bk_unique_probes *u = &s->uq;
	size_t m = sm->n < UNIQUE_PROBES ? sm->n : UNIQUE_PROBES;
	u->m = m;
	for (int k = 0; k < BK_IN_COUNT; k++) {
		u->in[k] = malloc(sizeof(double) * (m ? m : 1));
		if (!u->in[k])
			return -1;
		for (size_t i = 0; i < m; i++) /* evenly spread: sample i n / m */
			u->in[k][i] = sm->in[k] ? sm->in[k][i * sm->n / m] : NAN;
	}
	for (int t = 0; t < 3; t++)
		for (int j = 0; j < BK_MAX_PARAMS; j++)
			u->theta[t][j] = probe_param(t, j);
	return 0;
}

void bk_unique_free(bk_search *s)
{
	for (int k = 0; k < BK_IN_COUNT; k++) {
		free(s->uq.in[k]);
		s->uq.in[k] = NULL;
	}
	free(s->uq.fp);
	free(s->uq.cost);
	s->uq.fp = NULL;
	s->uq.cost = NULL;
	s->uq.cap = s->uq.n = 0;
}

/* One value into the fingerprint: a multiply-xorshift mix (FNV-1a byte by
 * byte was 9 % of an enumeration's CPU time, for 192 values a candidate). */
static uint64_t mix(uint64_t h, uint64_t q)
{
	h = (h ^ q) * 0x9e3779b97f4a7c15ull;
	return h ^ (h >> 29);
}

/* Value v as the fingerprint hashes it: its class, or its value rounded to
 * 32 significant bits. */
static uint64_t quantum(double v)
{
	if (isnan(v))
		return 1;
	if (isinf(v))
		return v > 0 ? 2 : 3;
	if (v == 0)
		return 4; /* -0 and +0 are one value */
	int e;
	double m = frexp(v, &e); /* |m| in [0.5, 1) */
	int64_t q = (int64_t)nearbyint(ldexp(m, 32));
	return ((uint64_t)q << 12) ^ (uint64_t)(e + 2048) ^ 0x5bd1e995u;
}

/* f's values hashed into *h. 0, or -1 when it does not evaluate. */
static int hash_parsed(const bk_search *s, const bk_form *f, uint64_t *h)
{
	const bk_unique_probes *u = &s->uq;
	*h = mix(*h, (uint64_t)bk_form_nparams(f));
	const double *in[BK_IN_COUNT];
	for (int k = 0; k < BK_IN_COUNT; k++)
		in[k] = u->in[k];
	double v[UNIQUE_PROBES];
	for (int t = 0; t < 3; t++) {
		if (bk_form_eval(f, BK_F64, u->m, in, u->theta[t], v))
			return -1;
		for (size_t i = 0; i < u->m; i++)
			*h = mix(*h, quantum(v[i]));
	}
	return 0;
}

/* A fingerprint is never 0: that value says "no fingerprint". */
static uint64_t nonzero(uint64_t h) { return h ? h : 1; }

uint64_t bk_unique_fingerprint_of(const bk_search *s, const bk_form *a, const bk_form *b)
{
	uint64_t h = BK_HASH_INIT;
	if (hash_parsed(s, a, &h))
		return 0;
	if (b) {
		h = mix(h, ';');
		if (hash_parsed(s, b, &h))
			return 0;
	}
	return nonzero(h);
}

uint64_t bk_unique_fingerprint(const bk_search *s, const char *a, const char *b)
{
	bk_form_error fe;
	bk_form *fa = bk_form_parse(a, &fe), *fb = b && *b ? bk_form_parse(b, &fe) : NULL;
	uint64_t h = fa && (!(b && *b) || fb) ? bk_unique_fingerprint_of(s, fa, fb) : 0;
	bk_form_free(fa);
	bk_form_free(fb);
	return h;
}

/* The slot of fp in the open-addressed table (0 marks a free slot). */
static size_t slot_of(const bk_unique_probes *u, uint64_t fp)
{
	size_t j = fp & (u->cap - 1);
	while (u->fp[j] && u->fp[j] != fp)
		j = (j + 1) & (u->cap - 1);
	return j;
}

static int grow(bk_unique_probes *u)
{
	size_t cap = u->cap ? 2 * u->cap : 1024;
	uint64_t *fp = calloc(cap, sizeof *fp);
	double *cost = malloc(cap * sizeof *cost);
	if (!fp || !cost) {
		free(fp);
		free(cost);
		return -1;
	}
	bk_unique_probes old = *u;
	u->fp = fp, u->cost = cost, u->cap = cap;
	for (size_t i = 0; i < old.cap; i++)
		if (old.fp[i]) {
			size_t j = slot_of(u, old.fp[i]);
			u->fp[j] = old.fp[i];
			u->cost[j] = old.cost[i];
		}
	free(old.fp);
	free(old.cost);
	return 0;
}

int bk_unique_twin(bk_search *s, uint64_t fp, double cost)
{
	bk_unique_probes *u = &s->uq;
	if (!fp) /* a form that does not parse is nobody's twin (its fit fails) */
		return 0;
	if (2 * (u->n + 1) > u->cap && grow(u))
		return -1;
	size_t j = slot_of(u, fp);
	if (u->fp[j] && u->cost[j] <= cost)
		return 1;
	if (!u->fp[j])
		u->n++;
	u->fp[j] = fp;
	u->cost[j] = cost;
	return 0;
}

/* ---- checkpoints ------------------------------------------------------------ */

void bk_unique_save(const bk_search *s, FILE *f)
{
	int top = 0;
	for (int k = 0; k <= BK_EXPR_MAX; k++)
		if (s->enum_drawn[k])
			top = k;
	fprintf(f, "enumerated %d %d\n", s->enum_complete, top);
	for (int k = 1; k <= top; k++)
		fprintf(f, "%ld %ld %ld\n", s->enum_drawn[k], s->enum_twins[k], s->enum_fitted[k]);
	fprintf(f, "twins %zu\n", s->uq.n);
	for (size_t i = 0; i < s->uq.cap; i++)
		if (s->uq.fp[i])
			fprintf(f, "%016llx %a\n", (unsigned long long)s->uq.fp[i], s->uq.cost[i]);
}

int bk_unique_load(bk_search *s, FILE *f, char *why, size_t len)
{
	int top;
	if (fscanf(f, " enumerated %d %d", &s->enum_complete, &top) != 2 || s->enum_complete < 0 ||
	    s->enum_complete > BK_EXPR_MAX || top < 0 || top > BK_EXPR_MAX)
		return snprintf(why, len, "no enumeration line, or a size out of 0 to %d", BK_EXPR_MAX), -1;
	for (int k = 1; k <= top; k++)
		if (fscanf(f, " %ld %ld %ld", &s->enum_drawn[k], &s->enum_twins[k], &s->enum_fitted[k]) != 3 ||
		    s->enum_drawn[k] < 0 || s->enum_twins[k] < 0 || s->enum_fitted[k] < 0 ||
		    s->enum_twins[k] + s->enum_fitted[k] > s->enum_drawn[k])
			return snprintf(why, len, "the enumeration's counts of size %d unreadable or inconsistent", k), -1;
	size_t n;
	if (fscanf(f, " twins %zu", &n) != 1)
		return snprintf(why, len, "no twins line"), -1;
	for (size_t i = 0; i < n; i++) {
		unsigned long long fp;
		double cost;
		if (fscanf(f, " %16llx %la", &fp, &cost) != 2 || fp == 0 || !(cost >= 0))
			return snprintf(why, len, "twin %zu of %zu unreadable", i + 1, n), -1;
		if (2 * (s->uq.n + 1) > s->uq.cap && grow(&s->uq))
			return snprintf(why, len, "out of memory"), -1;
		size_t j = slot_of(&s->uq, fp);
		if (s->uq.fp[j])
			return snprintf(why, len, "twin %zu of %zu repeated", i + 1, n), -1;
		s->uq.fp[j] = fp;
		s->uq.cost[j] = cost;
		s->uq.n++;
	}
	return 0;
}
