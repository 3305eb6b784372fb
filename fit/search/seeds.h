/*
 * seeds.h — what a search starts from, the same for brdfkit search and
 * scene's short search: the catalog's forms of the target as seeds (the
 * mapping of catalogmap.h, so the front starts at the published state of
 * the art), the screening grid the candidates are fitted on, and the
 * grammar's defaults.
 *
 * A bk_seeds holds the seeds' texts, names and starting constants; it owns
 * the texts it made (V x Schlick, a pair as one form) and points at the
 * catalog's or the caller's otherwise, which must outlive it. It holds each
 * seed's forms too, parsed once as the seed is added: the search copies
 * them (bk_search_options.seed_forms) rather than parse the texts again.
 */
#ifndef FIT_SEARCH_SEEDS_H
#define FIT_SEARCH_SEEDS_H

#include "search.h"

#define BK_SEEDS_MAX 64

typedef struct bk_seeds {
	const char *text[BK_SEEDS_MAX], *text_b[BK_SEEDS_MAX], *name[BK_SEEDS_MAX];
	char *owned[BK_SEEDS_MAX]; /* the texts made here, freed by bk_seeds_free */
	/* text's and text_b's forms (owned); NULL where a text does not parse
	 * (the search then skips the seed, as it skips every such text) */
	bk_form *form[BK_SEEDS_MAX], *form_b[BK_SEEDS_MAX];
	double p[BK_SEEDS_MAX][BK_MAX_PARAMS];
	/* 1: a member of a front read back (search --start-front), added after
	 * the published seeds: a start of the search, held to its constraints,
	 * not a catalog row */
	unsigned char from_front[BK_SEEDS_MAX];
	int n;
} bk_seeds;

/* Adds every catalog entry that answers target k (one_form: env scored as
 * f0 A + B, catalogmap.h) and reads only inputs of provides, whatever its
 * size, at its published constants and under its catalog name (but no V
 * entry on vf2d: one of them is that target itself); for target
 * f also Schlick's F, the baseline every F form is held to (name
 * "F_schlick", constants 1). Stops silently at BK_SEEDS_MAX. 0, or -1 out
 * of memory. */
int bk_seeds_catalog(bk_seeds *sd, bk_target_kind k, int one_form, unsigned provides);

/* Adds one seed (text_b: B of a pair, or NULL; name may be NULL; p:
 * BK_MAX_PARAMS constants, NULL for 1.0 each), texts not copied. 0, or -1
 * when full. */
int bk_seeds_add(bk_seeds *sd, const char *text, const char *text_b, const char *name, const double *p);

/* As bk_seeds_add, with the texts' forms already parsed by the caller
 * (form: bk_form_parse(text); form_b: of text_b, or NULL): copied, not
 * parsed again. 0, or -1 when full. */
int bk_seeds_add_forms(bk_seeds *sd, const char *text, const char *text_b, const char *name, const double *p,
                       const bk_form *form, const bk_form *form_b);

/* Points o's seeds at sd's (sd must outlive the search made from o). */
void bk_seeds_apply(const bk_seeds *sd, bk_search_options *o);

void bk_seeds_free(bk_seeds *sd);

/* The screening grid of o's target: about a thousand samples, where a fit
 * takes well under a millisecond (the front is refitted on the full grid):
 * sets o's cells (nx, nr, and nu, nphi for vf and spec). */
void bk_seeds_screening_grid(bk_target_options *o);

/* The grammar's defaults: the default operations, the constant 1, at most
 * 4 fitted constants (env: 10, A and B together), 24 nodes; inputs none
 * (the target's to give). */
void bk_seeds_grammar(bk_grammar *g, bk_target_kind k);

#endif
