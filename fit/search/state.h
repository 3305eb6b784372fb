/*
 * state.h — the search's state as text (internal): checkpoints
 * (bk_search_save, bk_search_load) and migrants between islands
 * (bk_search_export, bk_search_import), declared in fit/search.h; here the
 * fingerprint that ties a text to the options that wrote it.
 *
 * Formats: lines of text, numbers exact (%a), each candidate a line of
 * numbers and its trees followed by its texts on lines of their own. A
 * checkpoint ends with "checksum H" (64-bit FNV-1a of every byte before it).
 * Whatever is read is checked field by field against what a search with
 * these options can hold before anything uses it: a damaged file is refused
 * with what is wrong, never followed.
 */
#ifndef FIT_SEARCH_STATE_H
#define FIT_SEARCH_STATE_H

#include "search/search_int.h"

/* What must agree between a checkpoint and the run resuming it (own = 1),
 * or between the islands of one run (own = 0: not the seed, the island or
 * its share of the enumeration). */
uint64_t bk_state_fingerprint(const bk_search *s, int own);

#endif
