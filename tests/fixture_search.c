/*
 * fixture_search.c — the search tests' planted samples and plain options
 * (fixture_search.h).
 */
#include "fixture_search.h"

#include <criterion/criterion.h>
#include <string.h>

void fx_planted(const char *form, double loh_lo, int with_r, int nx, bk_samples *s)
{
	bk_target_options to;
	bk_target_defaults(BK_TARGET_FORM, &to);
	to.form_text = form;
	to.ndomain = with_r ? 2 : 1;
	to.dom_in[0] = BK_IN_LOH, to.dom_lo[0] = loh_lo, to.dom_hi[0] = 1;
	to.dom_in[1] = BK_IN_R, to.dom_lo[1] = 0, to.dom_hi[1] = 1;
	to.nx = nx;
	char err[256];
	cr_assert_eq(bk_target_build(&to, s, NULL, NULL, err, sizeof err), 0, "%s: %s", form, err);
}

void fx_plain_options(bk_search_options *o, const bk_samples *sm, unsigned inputs, int max_params, int max_size)
{
	bk_search_defaults(o);
	o->screen = sm;
	o->shape = BK_SHAPE_PLAIN;
	memset(&o->grammar, 0, sizeof o->grammar);
	o->grammar.ops = bk_grammar_default_ops();
	o->grammar.inputs = inputs;
	o->grammar.max_params = max_params;
	o->grammar.max_size = max_size;
}
