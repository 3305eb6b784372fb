/*
 * exercise.h — what the fuzz harness does to one input, shared with the
 * replay test in tests/test_ir.c: parse; if it parses, evaluate in the three
 * precisions at points including the edges where forms divide by zero,
 * differentiate, count, look for constants that are not finite and emit in
 * the three languages.
 * Returns 1 if the text parsed, 0 if not, -1 if a step that must succeed on a
 * parsed form failed (a bug: the replay test asserts it never happens).
 */
#ifndef TESTS_FUZZ_EXERCISE_H
#define TESTS_FUZZ_EXERCISE_H

#include "brdf.h"

#include <stdlib.h>

static int bk_exercise_form(const char *text)
{
	bk_form_error err;
	bk_form *f = bk_form_parse(text, &err);
	if (!f)
		return err.column >= 1 && err.message[0] ? 0 : -1;
	enum { N = 4 };
	static const double NoV[N] = {0.5, 1.0, 1e-4, 0.0}, NoL[N] = {0.7, 0.0, 1.0, 0.3},
	                    NoH[N] = {0.9, 1.0, 0.0, 0.5}, LoH[N] = {0.8, 0.0, 1.0, 0.1},
	                    r[N] = {0.5, 0.0, 1.0, 0.089}, a[N] = {0.25, 0.0, 1.0, 0.007921},
	                    f0[N] = {0.04, 1.0, 0.0, 0.5};
	const double *in[BK_IN_COUNT] = {NoV, NoL, NoH, LoH, r, a, f0};
	double params[BK_MAX_PARAMS], out[N], jac[N * BK_MAX_PARAMS];
	int rc = 1;
	for (int i = 0; i < BK_MAX_PARAMS; i++)
		params[i] = 0.25 * (i + 1);
	for (int p = BK_F64; p <= BK_F16; p++)
		if (bk_form_eval(f, (bk_precision)p, N, in, params, out))
			rc = -1;
	if (bk_form_eval_diff(f, N, in, params, out, jac))
		rc = -1;
	bk_ops ops;
	bk_form_count(f, &ops);
	char what[160];
	if (bk_form_nonfinite(f, params, what, sizeof what) < 0 || bk_form_nonfinite(f, NULL, what, sizeof what) < 0)
		rc = -1;
	/* codegen's warnings and stability's intermediate flags */
	if (bk_form_const_range(f, params, BK_F16, what, sizeof what) < 0 ||
	    bk_form_const_range(f, params, BK_F32, what, sizeof what) < 0)
		rc = -1;
	bk_form_clamp_reversed(f, params, what, sizeof what);
	unsigned char flags[N];
	int first[3];
	if (bk_form_eval_flags(f, BK_F16, N, in, params, out, flags, first))
		rc = -1;
	for (int lang = BK_LANG_C; lang <= BK_LANG_HLSL; lang++) {
		char *code = bk_form_emit(f, (bk_lang)lang, lang != BK_LANG_C, params, NULL);
		if (!code)
			rc = -1;
		free(code);
	}
	bk_form_free(f);
	return rc;
}

#endif
