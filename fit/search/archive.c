/*
 * archive.c — the MAP-Elites levels and the front (archive.h).
 */
#include "search/archive.h"
#include "search/cand.h"
#include "search/pareto.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int bk_archive_better(const bk_cand *a, const bk_cand *b)
{
	if (a->err != b->err)
		return a->err < b->err;
	if (a->cost != b->cost)
		return a->cost < b->cost;
	int t = strcmp(a->text, b->text);
	if (t == 0 && a->text_b && b->text_b)
		t = strcmp(a->text_b, b->text_b);
	return t < 0;
}

/* Enters candidate i in its level (kept best first, at most per_level). */
static int level_add(bk_search *s, size_t i)
{
	const bk_cand *c = &s->cand[i];
	if (c->status != BK_CAND_OK)
		return 0;
	/* 1e-9: a cost is a sum of integer-weighted op counts; an integer
	 * reached by rounding a little below stays on its level */
	int L = (int)floor(c->cost + 1e-9);
	int k = 0;
	while (k < s->nlv && s->lv[k].cost < L)
		k++;
	if (k == s->nlv || s->lv[k].cost != L) {
		bk_level *t = realloc(s->lv, sizeof *t * (size_t)(s->nlv + 1));
		if (!t)
			return -1;
		s->lv = t;
		memmove(&s->lv[k + 1], &s->lv[k], sizeof *t * (size_t)(s->nlv - k));
		s->lv[k] = (bk_level){L, malloc(sizeof(size_t) * (size_t)(s->o.per_level + 1)), 0};
		s->nlv++;
		if (!s->lv[k].idx)
			return -1;
	}
	bk_level *l = &s->lv[k];
	/* one member per error in a level: equal errors at equal cost are
	 * mostly one model spelled twice (p*(p' + x) and p*x + p'), and a level
	 * full of them breeds one model */
	for (int j = 0; j < l->n; j++) {
		if (s->cand[l->idx[j]].err != c->err)
			continue;
		if (!bk_archive_better(c, &s->cand[l->idx[j]]))
			return 0;
		memmove(&l->idx[j], &l->idx[j + 1], sizeof(size_t) * (size_t)(l->n - j - 1));
		l->n--;
		break;
	}
	int pos = l->n;
	while (pos > 0 && bk_archive_better(c, &s->cand[l->idx[pos - 1]]))
		pos--;
	if (pos >= s->o.per_level)
		return 0;
	memmove(&l->idx[pos + 1], &l->idx[pos], sizeof(size_t) * (size_t)(l->n - pos));
	l->idx[pos] = i;
	if (l->n < s->o.per_level)
		l->n++;
	return 0;
}

/* a has no more cost and no more error than b, and less of one of them:
 * b is then on no front (pareto.h) while a is in the archive */
static int dominates(const bk_cand *a, const bk_cand *b)
{
	return a->cost <= b->cost && a->err <= b->err && (a->cost < b->cost || a->err < b->err);
}

/* Candidate i keeps its forms (cand.h) while no other dominates it: the
 * front's refit reads a member's forms from the search instead of parsing
 * its text again, and the forms held are the front's and its ties', not
 * the archive's. A candidate another dominates drops them for good (the
 * archive only grows, so it stays dominated); so does every candidate i
 * dominates. Out of memory for the list: i drops its forms (its text is
 * then parsed where the front is refitted, as a checkpoint's). */
static void keep_forms(bk_search *s, size_t i)
{
	bk_cand *c = &s->cand[i];
	int keep = c->status == BK_CAND_OK;
	for (size_t k = 0; keep && k < s->nheld; k++)
		keep = !dominates(&s->cand[s->held[k]], c);
	if (keep && s->nheld == s->held_cap) {
		size_t cap = s->held_cap ? 2 * s->held_cap : 16;
		size_t *t = realloc(s->held, sizeof *t * cap);
		keep = t != NULL;
		if (t)
			s->held = t, s->held_cap = cap;
	}
	if (!keep) {
		bk_cand_free_forms(c);
		return;
	}
	size_t w = 0;
	for (size_t k = 0; k < s->nheld; k++)
		if (dominates(c, &s->cand[s->held[k]]))
			bk_cand_free_forms(&s->cand[s->held[k]]);
		else
			s->held[w++] = s->held[k];
	s->nheld = w;
	s->held[s->nheld++] = i;
}

int bk_archive_push(bk_search *s, const bk_cand *c)
{
	if (s->n == s->cap) {
		/* from 32, not 1,024: a first block of 1,024 candidates (2.4 MB
		 * while a candidate held its two trees whole) for a search that
		 * keeps a dozen made every small search, a checkpoint's load
		 * included, map and poison it whole under AddressSanitizer (the
		 * sanitized unit runner's mutated-checkpoint test spent four
		 * fifths of its time there) */
		size_t cap = s->cap ? 2 * s->cap : 32;
		bk_cand *t = realloc(s->cand, sizeof *t * cap);
		if (!t)
			return -1;
		s->cand = t;
		s->cap = cap;
	}
	s->cand[s->n++] = *c;
	if (level_add(s, s->n - 1)) {
		s->n--; /* not taken: the caller still owns c's texts and forms */
		return -1;
	}
	keep_forms(s, s->n - 1);
	return 0;
}

void bk_archive_free(bk_search *s)
{
	for (size_t i = 0; i < s->n; i++)
		bk_cand_free(&s->cand[i]);
	free(s->cand);
	free(s->held);
	for (int k = 0; k < s->nlv; k++)
		free(s->lv[k].idx);
	free(s->lv);
}

/* The tie-break key of a candidate: its text, and for a pair "A\1B" (\1
 * sorts below every character of a form, so the order is A's, then B's,
 * as bk_archive_better's). NULL when out of memory. */
static char *front_key(const bk_cand *c)
{
	if (!c->text_b)
		return c->text;
	size_t na = strlen(c->text), nb = strlen(c->text_b);
	char *k = malloc(na + nb + 2);
	if (k) {
		memcpy(k, c->text, na);
		k[na] = '\1';
		memcpy(k + na + 1, c->text_b, nb + 1);
	}
	return k;
}

size_t bk_search_front(const bk_search *s, size_t *idx, size_t max)
{
	size_t m = 0;
	for (size_t i = 0; i < s->n; i++)
		m += s->cand[i].status == BK_CAND_OK;
	bk_pareto_pt *pt = malloc(sizeof *pt * (m ? m : 1));
	if (!pt)
		return 0;
	size_t k = 0;
	int oom = 0;
	for (size_t i = 0; i < s->n; i++)
		if (s->cand[i].status == BK_CAND_OK) {
			const bk_cand *c = &s->cand[i];
			pt[k] = (bk_pareto_pt){c->cost, c->err, front_key(c), i};
			oom |= !pt[k++].key;
		}
	size_t nf = oom ? 0 : bk_pareto_scan(pt, m);
	for (size_t i = 0; i < nf && i < max; i++)
		idx[i] = pt[i].id;
	for (size_t i = 0; i < m; i++)
		if (pt[i].key != s->cand[pt[i].id].text)
			free((char *)pt[i].key);
	free(pt);
	return nf < max ? nf : max;
}
