/*
 * seeds.c — the catalog's seeds, the screening grid and the grammar's
 * defaults of a search (seeds.h).
 */
#include "search/seeds.h"

#include "catalog.h"
#include "search/catalogmap.h"

#include <stdlib.h>
#include <string.h>

/* Seed k's fields but its forms */
static int add(bk_seeds *sd, const char *text, const char *text_b, const char *name, const double *p)
{
	if (sd->n >= BK_SEEDS_MAX)
		return -1;
	int k = sd->n++;
	sd->text[k] = text;
	sd->text_b[k] = text_b;
	sd->name[k] = name;
	sd->owned[k] = NULL;
	sd->form[k] = sd->form_b[k] = NULL;
	sd->from_front[k] = 0;
	for (int j = 0; j < BK_MAX_PARAMS; j++)
		sd->p[k][j] = p ? p[j] : 1.0;
	return 0;
}

int bk_seeds_add(bk_seeds *sd, const char *text, const char *text_b, const char *name, const double *p)
{
	if (add(sd, text, text_b, name, p))
		return -1;
	bk_form_error fe; /* a text that does not parse: no form (the search skips the seed) */
	sd->form[sd->n - 1] = bk_form_parse(text, &fe);
	sd->form_b[sd->n - 1] = text_b ? bk_form_parse(text_b, &fe) : NULL;
	return 0;
}

int bk_seeds_add_forms(bk_seeds *sd, const char *text, const char *text_b, const char *name, const double *p,
                       const bk_form *form, const bk_form *form_b)
{
	if (add(sd, text, text_b, name, p))
		return -1;
	int k = sd->n - 1; /* a copy out of memory: no form (the search parses the text) */
	sd->form[k] = form ? bk_form_dup(form) : NULL;
	sd->form_b[k] = text_b && form_b ? bk_form_dup(form_b) : NULL;
	return 0;
}

int bk_seeds_catalog(bk_seeds *sd, bk_target_kind k, int one_form, unsigned provides)
{
	for (size_t i = 0; i < bk_catalog_count() && sd->n < BK_SEEDS_MAX; i++) {
		const bk_catalog_entry *e = bk_catalog_at(i);
		if (!bk_catmap_answers(k, one_form, e) || !bk_catmap_reads_only(e, provides))
			continue;
		/* V entries (times Schlick's F) seed vf only: vf2d is the talk's
		 * modified Kelemen V times Schlick's F itself (fit/target.h), so
		 * v_kelemen_talk_r would seed the target at error 0 and end the
		 * front at its cost; compare still lists them on vf2d as rows */
		if (k == BK_TARGET_VF2D && !strcmp(e->target, "V"))
			continue;
		/* a split pair searched as a pair stays two texts; every other entry
		 * is the one text it is scored with */
		int split = e->form_b && !(k == BK_TARGET_ENV && one_form);
		char *t = split ? NULL : bk_catmap_form(k, one_form, e);
		if (!split && !t)
			return -1;
		bk_seeds_add(sd, split ? e->form : t, split ? e->form_b : NULL, e->name, e->defaults);
		sd->owned[sd->n - 1] = t;
	}
	if (k == BK_TARGET_F)
		bk_seeds_add(sd, "F_schlick(f0, 1, LoH)", NULL, "F_schlick", NULL);
	return 0;
}

void bk_seeds_apply(const bk_seeds *sd, bk_search_options *o)
{
	o->seeds = sd->text;
	o->seeds_b = sd->text_b;
	o->seed_forms = (const bk_form *const *)sd->form;
	o->seed_forms_b = (const bk_form *const *)sd->form_b;
	o->seed_names = sd->name;
	o->seed_p = (const double(*)[BK_MAX_PARAMS])sd->p;
	o->nseeds = sd->n;
}

void bk_seeds_free(bk_seeds *sd)
{
	for (int k = 0; k < sd->n; k++) {
		free(sd->owned[k]);
		bk_form_free(sd->form[k]);
		bk_form_free(sd->form_b[k]);
		sd->owned[k] = NULL;
		sd->form[k] = sd->form_b[k] = NULL;
	}
	sd->n = 0;
}

void bk_seeds_screening_grid(bk_target_options *o)
{
	switch (o->kind) {
	case BK_TARGET_VF2D:
	case BK_TARGET_D: o->nx = o->nr = 32; break;
	case BK_TARGET_VF:
	case BK_TARGET_SPEC: o->nx = o->nr = 8, o->nu = 8, o->nphi = 4; break; /* 2,048 samples */
	case BK_TARGET_ENV:
	case BK_TARGET_MS:
	case BK_TARGET_SHEEN: o->nx = o->nr = 16; break;
	case BK_TARGET_F: o->nx = 64; break;
	case BK_TARGET_FORM: {
		/* samples per axis for 1 to 4 inputs: 256, 1,024, 1,000, 1,296 in all */
		static const int per[5] = {0, 256, 32, 10, 6};
		o->nx = per[o->ndomain];
		break;
	}
	case BK_TARGET_TABLE:
	case BK_TARGET_MERL: o->nx = 4096; break; /* about 4,096 of the file's samples, every k-th */
	default: break;
	}
}

void bk_seeds_grammar(bk_grammar *g, bk_target_kind k)
{
	memset(g, 0, sizeof *g);
	g->ops = bk_grammar_default_ops();
	g->consts[0] = 1.0;
	g->nconsts = 1;
	g->max_params = k == BK_TARGET_ENV ? 10 : 4;
	g->max_size = 24;
}
