/*
 * unique.c — semantically unique candidates (unique.h).
 */
#include "search/unique.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Parameter vector t's value of parameter j: 0.37, 1.61, -1.27 and 2.9 in
 * turn over the four vectors, so that every parameter is once in (0, 1),
 * once in (1, 2), once negative and once above 2 (a gate p1 / r, min(p1,
 * LoH), saturate(p1 + exp2(r)) is probed open, shut and with its break
 * among the inputs), with a small drift with j so that no two parameters
 * are equal at a vector (p0 - p4 must not vanish). Before, three vectors
 * put p1, p4, p7 in (0, 1) only with a minus sign: saturate(p1 / r) and
 * saturate(p1 / LoH) were one model (bench_enum --audit found it). */
static double probe_param(int t, int j)
{
	static const double v[UNIQUE_VECTORS] = {0.37, 1.61, -1.27, 2.9};
	return v[(t + j) % UNIQUE_VECTORS] * (1 + 0.013 * j);
}

/* How many strides bk_unique_init weighs (the nearest coprime ones to
 * n / phi): 256 x (64 probes sorted for each input, and their 2,016 pairs),
 * about a million comparisons, once a search. */
#define STRIDES 256

static int cmp_double(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

static size_t gcd(size_t a, size_t b)
{
	while (b) {
		size_t t = a % b;
		a = b, b = t;
	}
	return a;
}

/* How well the m probes i k mod n spread over sm's inputs: the distinct
 * values summed over the inputs (*distinct), and the least squared distance
 * between two probes with each input scaled by its range over the samples
 * (*gap). */
static void spread(const bk_samples *sm, const double *range, size_t m, size_t k, long *distinct, double *gap)
{
	size_t idx[UNIQUE_PROBES];
	double v[UNIQUE_PROBES];
	for (size_t i = 0; i < m; i++)
		idx[i] = (size_t)(((unsigned long long)i * k) % sm->n);
	*distinct = 0;
	*gap = HUGE_VAL;
	for (int c = 0; c < BK_IN_COUNT; c++) {
		if (!sm->in[c])
			continue;
		for (size_t i = 0; i < m; i++)
			v[i] = sm->in[c][idx[i]];
		qsort(v, m, sizeof v[0], cmp_double);
		for (size_t i = 0; i < m; i++)
			*distinct += i == 0 || v[i] != v[i - 1];
	}
	for (size_t i = 0; i < m; i++)
		for (size_t j = i + 1; j < m; j++) {
			double d = 0;
			for (int c = 0; c < BK_IN_COUNT; c++)
				if (sm->in[c] && range[c] > 0) {
					double x = (sm->in[c][idx[i]] - sm->in[c][idx[j]]) / range[c];
					d += x * x;
				}
			*gap = fmin(*gap, d);
		}
}

/* The probes: screening sample i k mod n for i < 64 (all the samples when
 * there are no more), a rank-1 lattice over the sample index. Why not
 * sample i n / 64: on a grid whose size is a multiple of 64 that stride
 * lands on two values of its fastest axis (env's 512 samples gave NoV at 2
 * of its 16 values, vf2d's 1,024 LoH at 2 of 32), and gates that are open
 * at both and shut between were taken for their cheaper twins (unique.h).
 * k is coprime to n (no sample twice) and, of the STRIDES such strides
 * nearest n / phi (the golden ratio spreads a lattice best), the one whose
 * probes see the most distinct values of the inputs, then the widest least
 * distance between two probes; the nearest to n / phi at a tie. So the
 * choice depends on the samples alone, and a user's table gets it too. */
static size_t stride(const bk_samples *sm, size_t m)
{
	if (sm->n <= m)
		return 1;
	double range[BK_IN_COUNT] = {0};
	for (int c = 0; c < BK_IN_COUNT; c++)
		if (sm->in[c]) {
			double lo = HUGE_VAL, hi = -HUGE_VAL;
			for (size_t i = 0; i < sm->n; i++)
				if (isfinite(sm->in[c][i]))
					lo = fmin(lo, sm->in[c][i]), hi = fmax(hi, sm->in[c][i]);
			range[c] = hi > lo ? hi - lo : 0;
		}
	size_t g = (size_t)nearbyint((double)sm->n * 0.6180339887498949), best = 0;
	long best_d = -1;
	double best_gap = 0;
	/* g, g + 1, g - 1, g + 2, ...: the nearest first, so a tie keeps it */
	for (size_t j = 0, seen = 0; seen < STRIDES && j < 2 * sm->n; j++) {
		long off = j % 2 ? (long)(j + 1) / 2 : -(long)(j / 2);
		long k = (long)g + off;
		if (k < 1 || k >= (long)sm->n || gcd((size_t)k, sm->n) != 1)
			continue;
		seen++;
		long d;
		double gap;
		spread(sm, range, m, (size_t)k, &d, &gap);
		if (d > best_d || (d == best_d && gap > best_gap))
			best = (size_t)k, best_d = d, best_gap = gap;
	}
	return best ? best : 1;
}

int bk_unique_init(bk_search *s)
{
	const bk_samples *sm = s->o.screen;
	bk_unique_probes *u = &s->uq;
	size_t m = sm->n < UNIQUE_PROBES ? sm->n : UNIQUE_PROBES;
	size_t k = stride(sm, m);
	u->m = m;
	u->stride = k;
	for (int c = 0; c < BK_IN_COUNT; c++) {
		u->in[c] = malloc(sizeof(double) * (m ? m : 1));
		if (!u->in[c])
			return -1;
		for (size_t i = 0; i < m; i++)
			u->in[c][i] = sm->in[c] ? sm->in[c][((unsigned long long)i * k) % sm->n] : NAN;
	}
	for (int t = 0; t < UNIQUE_VECTORS; t++)
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

/* (unique.h) For v = m 2^e, |m| in [0.5, 1), the value kept is q =
 * nearbyint(ldexp(m, 32)): a normal double gives it from its bits alone, its
 * 53-bit significand over 2^21, rounded half to even, and its e from its
 * exponent field. frexp, ldexp and nearbyint took 4 % of the f enumeration's
 * CPU samples (perf; 192 values a candidate); subnormals still take them. */
uint64_t bk_unique_quantum(double v)
{
	uint64_t b;
	memcpy(&b, &v, sizeof b);
	const uint64_t frac = (1ull << 52) - 1, half = 1ull << 20;
	int E = (int)((b >> 52) & 0x7ff);
	if (E == 0x7ff)
		return b & frac ? 1 : b >> 63 ? 3 : 2; /* NaN, -inf, +inf */
	int64_t q;
	int e;
	if (E == 0) {
		if (v == 0)
			return 4; /* -0 and +0 are one value */
		double m = frexp(v, &e);
		q = (int64_t)nearbyint(ldexp(m, 32));
	} else {
		uint64_t M = (b & frac) | (1ull << 52), u = M >> 21, rem = M & (2 * half - 1);
		u += rem > half || (rem == half && (u & 1));
		q = b >> 63 ? -(int64_t)u : (int64_t)u;
		e = E - 1022;
	}
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
	for (int t = 0; t < UNIQUE_VECTORS; t++) {
		if (bk_form_eval(f, BK_F64, u->m, in, u->theta[t], v))
			return -1;
		for (size_t i = 0; i < u->m; i++)
			*h = mix(*h, bk_unique_quantum(v[i]));
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

/* ---- the audit's way in (search.h) ------------------------------------------ */

void bk_search_on_twin(bk_search *s, bk_search_twin_fn fn, void *ctx)
{
	s->twin_audit = fn;
	s->twin_audit_ctx = ctx;
}

int bk_search_twin_probes(const bk_search *s, double (*theta)[BK_MAX_PARAMS], int max, size_t *probes, size_t *stride)
{
	for (int t = 0; theta && t < max && t < UNIQUE_VECTORS; t++)
		memcpy(theta[t], s->uq.theta[t], sizeof theta[t]);
	if (probes)
		*probes = s->uq.m;
	if (stride)
		*stride = s->uq.stride;
	return UNIQUE_VECTORS;
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
