/*
 * bench_vf2d.h — the one screening case bench_search and bench_speed time:
 * vf2d on a 32x32 grid, the talk's f0*(g) shape, the default operations
 * over LoH, r and a with the literal 1, at most 4 constants and 24 nodes,
 * non-negative forms, `evals` fits. Exits with a message if the target
 * cannot be built (who: the program's name).
 */
#ifndef BENCH_VF2D_H
#define BENCH_VF2D_H

#include "search.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void bench_vf2d_case(const char *who, long evals, bk_samples *sm, bk_search_options *o)
{
	bk_target_options to;
	bk_target_defaults(BK_TARGET_VF2D, &to);
	to.nx = to.nr = 32;
	char err[256];
	if (bk_target_build(&to, sm, NULL, NULL, err, sizeof err)) {
		fprintf(stderr, "%s: %s\n", who, err);
		exit(1);
	}
	bk_search_defaults(o);
	o->screen = sm;
	o->shape = BK_SHAPE_F0;
	memset(&o->grammar, 0, sizeof o->grammar);
	o->grammar.ops = bk_grammar_default_ops();
	o->grammar.inputs = 1u << BK_IN_LOH | 1u << BK_IN_R | 1u << BK_IN_A;
	o->grammar.consts[0] = 1;
	o->grammar.nconsts = 1;
	o->grammar.max_params = 4;
	o->grammar.max_size = 24;
	o->nonneg = 1;
	o->evals = evals;
}

#endif
