/*
 * catalogmap.h — the one catalog-to-target mapping: which published entries
 * (fit/catalog.h) answer a target, and the text each is scored with there.
 * compare's rows, the search's seeds and scene's candidates all ask it.
 *
 *   vf2d, vf  VF entries; V entries times Schlick's F, (V)*F_schlick(f0, 1, LoH)
 *   spec      DVF entries times NoL (the spec target is the rendered lobe)
 *   env       env split pairs; with one_form (f0 A + B scored as one form in
 *             f0, as compare and scene score it) also the env_f0 entries, and
 *             the split pairs as f0*(A) + (B) (search/pair.h)
 *   d, f      D, F entries
 * Whether an entry reads only what a target's samples provide is
 * bk_catmap_reads_only (e.g. most V entries read NoV, which vf2d lacks).
 */
#ifndef FIT_SEARCH_CATALOGMAP_H
#define FIT_SEARCH_CATALOGMAP_H

#include "catalog.h"
#include "target.h"

/* The catalog's tag of a target's own forms ("VF", "DVF", "env", "D",
 * "F"), NULL when none (form). */
const char *bk_catmap_tag(bk_target_kind k);

/* 1 when entry e answers target k (see above). */
int bk_catmap_answers(bk_target_kind k, int one_form, const bk_catalog_entry *e);

/* The text e is scored with on target k, malloc'd (NULL: out of memory).
 * A split pair without one_form has two texts: this is A (e->form_b is B). */
char *bk_catmap_form(bk_target_kind k, int one_form, const bk_catalog_entry *e);

/* 1 when both texts of e read only inputs in provides (bits of bk_input). */
int bk_catmap_reads_only(const bk_catalog_entry *e, unsigned provides);

#endif
