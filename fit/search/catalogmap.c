/*
 * catalogmap.c — which catalog entries answer a target (catalogmap.h).
 */
#include "search/catalogmap.h"

#include "search/pair.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *bk_catmap_tag(bk_target_kind k)
{
	switch (k) {
	case BK_TARGET_VF2D:
	case BK_TARGET_VF: return "VF";
	case BK_TARGET_SPEC: return "DVF";
	case BK_TARGET_ENV: return "env";
	case BK_TARGET_D: return "D";
	case BK_TARGET_F: return "F";
	case BK_TARGET_MS: return "ms";
	case BK_TARGET_SHEEN: return "sheen";
	default: return NULL;
	}
}

int bk_catmap_answers(bk_target_kind k, int one_form, const bk_catalog_entry *e)
{
	const char *tag = bk_catmap_tag(k);
	if (!tag)
		return 0;
	if (!strcmp(e->target, tag))
		return 1;
	if ((k == BK_TARGET_VF2D || k == BK_TARGET_VF) && !strcmp(e->target, "V"))
		return 1;
	return k == BK_TARGET_ENV && one_form && !strcmp(e->target, "env_f0");
}

static char *format(const char *fmt, const char *a)
{
	int n = snprintf(NULL, 0, fmt, a);
	char *t = n < 0 ? NULL : malloc((size_t)n + 1);
	if (t)
		snprintf(t, (size_t)n + 1, fmt, a);
	return t;
}

char *bk_catmap_form(bk_target_kind k, int one_form, const bk_catalog_entry *e)
{
	if (!strcmp(e->target, "V"))
		return format("(%s)*F_schlick(f0, 1, LoH)", e->form);
	if (k == BK_TARGET_SPEC)
		return format("(%s)*NoL", e->form);
	if (k == BK_TARGET_ENV && one_form && e->form_b)
		return bk_pair_dup(e->form, e->form_b);
	return format("%s", e->form);
}

int bk_catmap_reads_only(const bk_catalog_entry *e, unsigned provides)
{
	bk_form_error fe;
	for (int h = 0; h < 2; h++) {
		const char *t = h ? e->form_b : e->form;
		if (!t)
			continue;
		bk_form *f = bk_form_parse(t, &fe);
		int ok = f && !(bk_form_inputs(f) & ~provides);
		bk_form_free(f);
		if (!ok)
			return 0;
	}
	return 1;
}
