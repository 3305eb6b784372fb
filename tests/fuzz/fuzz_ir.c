/*
 * fuzz_ir.c — libFuzzer harness for the formula IR: any bytes as a form;
 * what parses is evaluated in the three precisions, differentiated, counted
 * and turned into code. `make fuzz` builds it with clang, ASan and UBSan and
 * runs it for FUZZ_RUNS inputs (default 1,000,000) from tests/fuzz/corpus;
 * inputs that crashed are kept in tests/fuzz/regress and replayed by
 * tests/test_ir.c in every `make test`.
 */
#include "brdf.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (size > 4096) /* forms are short; longer inputs only slow the search */
		return 0;
	char *text = malloc(size + 1);
	if (!text)
		return 0;
	memcpy(text, data, size);
	text[size] = '\0';
	bk_form_error err;
	bk_form *f = bk_form_parse(text, &err);
	free(text);
	if (!f)
		return 0;
	/* a few points, including the edges where forms divide by zero */
	enum { N = 4 };
	static const double NoV[N] = {0.5, 1.0, 1e-4, 0.0}, NoL[N] = {0.7, 0.0, 1.0, 0.3},
	                    NoH[N] = {0.9, 1.0, 0.0, 0.5}, LoH[N] = {0.8, 0.0, 1.0, 0.1},
	                    r[N] = {0.5, 0.0, 1.0, 0.089}, a[N] = {0.25, 0.0, 1.0, 0.007921},
	                    f0[N] = {0.04, 1.0, 0.0, 0.5};
	const double *in[BK_IN_COUNT] = {NoV, NoL, NoH, LoH, r, a, f0};
	double params[BK_MAX_PARAMS], out[N], jac[N * BK_MAX_PARAMS];
	for (int i = 0; i < BK_MAX_PARAMS; i++)
		params[i] = 0.25 * (i + 1);
	for (int p = BK_F64; p <= BK_F16; p++)
		bk_form_eval(f, (bk_precision)p, N, in, params, out);
	bk_form_eval_diff(f, N, in, params, out, jac);
	bk_ops ops;
	bk_form_count(f, &ops);
	for (int lang = BK_LANG_C; lang <= BK_LANG_HLSL; lang++)
		free(bk_form_emit(f, (bk_lang)lang, lang != BK_LANG_C, params, NULL));
	bk_form_free(f);
	return 0;
}
