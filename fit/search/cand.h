/*
 * cand.h — a candidate's identity (internal to the search): the text that is
 * fitted (the shape applied to its trees), its forms (that text parsed once),
 * its cost, the cache's key, and freeing what it owns. The generation, the
 * checkpoint reader and the migrants' import all go through these, so a
 * candidate read back is judged exactly as one made here.
 */
#ifndef FIT_SEARCH_CAND_H
#define FIT_SEARCH_CAND_H

#include "search/search_int.h"

/* The fitted form's text from the trees t, the shape applied: A in a, B in b
 * (empty unless a pair), each of len bytes. 0, or -1 when a text does not fit. */
int bk_cand_text(const bk_search *s, const bk_expr *t, char *a, char *b, size_t len);

/* The cost the front is drawn against: op counts of the whole shader
 * expression after sharing (a pair: f0*(A) + (B), paid once where shared),
 * and the parameters it reads, of a form already parsed (bk_cand_parse
 * passes a pair's whole). */
void bk_cand_cost_of(const bk_search *s, const bk_form *f, bk_ops *ops, double *cost, int *np);

/* c's forms from texts a and b (NULL or empty: one tree): form, and for a
 * pair form_b and form_pair; its ops, cost and parameters from the whole.
 * 0, or -1 when a text is not a form or out of memory (c's forms NULL). */
int bk_cand_parse(const bk_search *s, bk_cand *c, const char *a, const char *b);
/* As bk_cand_parse, from the forms fa (fb: B of a pair) of the texts a and b,
 * already parsed (a seed given parsed: bk_search_options.seed_forms): copied,
 * not parsed again (a pair's one form is still made from the two texts). */
int bk_cand_adopt(const bk_search *s, bk_cand *c, const bk_form *fa, const bk_form *fb, const char *a, const char *b);

/* c's trees made t[0] and, when two, t[1] (those it had freed). 0, or -1
 * when out of memory (c's trees then none). */
int bk_cand_set_trees(bk_cand *c, const bk_expr *t, int two);

/* Frees c's forms (not its texts). */
void bk_cand_free_forms(bk_cand *c);

/* The cache's key of a candidate of texts a and b (NULL: none). */
uint64_t bk_cand_key(const char *a, const char *b);

/* Frees the texts and the forms c owns (not c). */
void bk_cand_free(bk_cand *c);

#endif
