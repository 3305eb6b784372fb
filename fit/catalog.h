/*
 * catalog.h — published approximations as formula-language entries, each with
 * its citation, its exact published constants as parameter defaults (so the
 * fitter can free them) and its convention.
 */
#ifndef FIT_CATALOG_H
#define FIT_CATALOG_H

#include "brdf.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct bk_catalog_entry {
	const char *name;       /* e.g. "vf_talk_r": unique, lowercase */
	const char *target;     /* what it approximates: "D", "V", "F", "VF" (V·F), "DVF",
	                           "env" (split sum: form = A, form_b = B) or
	                           "env_f0" (the whole environment BRDF, f0 inside) or
	                           "ms" (GGX directional albedo E = A + B, F = 1) or
	                           "sheen" (the Charlie sheen albedo) */
	const char *form;       /* formula-language text; A for "env" */
	const char *form_b;     /* B for "env", else NULL; shares the parameters */
	int nparams;
	double defaults[BK_MAX_PARAMS]; /* the published constants, p0.. */
	const char *source;     /* authors, year, title; "unverified" where so */
	const char *convention; /* roughness meaning, 1/4 in V, NoL, π, gating */
} bk_catalog_entry;

size_t bk_catalog_count(void);
const bk_catalog_entry *bk_catalog_at(size_t i);
const bk_catalog_entry *bk_catalog_find(const char *name);
/* The entry NAME's form parsed (for a split sum "env", its A half; the B half
 * is bk_form_parse(entry->form_b)), and its published constants copied into
 * params (BK_MAX_PARAMS doubles; those past nparams 0; params may be NULL).
 * Here, not in bk_form_parse: libbrdf knows the formula language, not the
 * catalog, which lives a layer above it (shared/DESIGN.md's data flow). Returns the
 * form (bk_form_free it), or NULL with err set: "unknown catalog form 'NAME'"
 * (column 0), or the parser's error. */
bk_form *bk_catalog_form(const char *name, double *params, bk_form_error *err);

#ifdef __cplusplus
}
#endif

#endif
