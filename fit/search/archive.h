/*
 * archive.h — the search's archive (internal): every candidate fitted, in
 * the order found, and MAP-Elites over cost on top of it: for each integer
 * cost level the per_level best (error, then cost, then canonical text).
 * Cheap and expensive forms stay alive together instead of collapsing onto
 * the currently best trade-off. The front (fit/search.h, bk_search_front)
 * is the one Pareto scan (search/pareto.h) over the candidates that fitted.
 */
#ifndef FIT_SEARCH_ARCHIVE_H
#define FIT_SEARCH_ARCHIVE_H

#include "search/search_int.h"

/* a before b: lower error, then lower cost, then text (then B's text). */
int bk_archive_better(const bk_cand *a, const bk_cand *b);

/* Appends *c to the candidates (s then owns its texts and forms: the forms
 * kept while no candidate dominates it, search.h) and enters it in its cost
 * level if it is OK and among the level's best. 0, or -1 when out of memory
 * (s has then not taken c: its texts and forms are still the caller's). */
int bk_archive_push(bk_search *s, const bk_cand *c);

/* Frees the levels and the candidates. */
void bk_archive_free(bk_search *s);

#endif
