/*
 * fuzz_ir.c — libFuzzer harness for the formula IR: any bytes as a form;
 * what parses is evaluated in the three precisions, differentiated, counted
 * and turned into code. `make fuzz` builds it with clang, ASan and UBSan and
 * runs it for FUZZ_RUNS inputs (default 1,000,000) from tests/fuzz/corpus, up
 * to 20,000 bytes: past the length limit; the corpus holds forms at the
 * length, nesting and instruction limits for the mutations to cross;
 * inputs that crashed are kept in tests/fuzz/regress and replayed by
 * tests/test_ir.c in every `make test`.
 */
#include "exercise.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	/* past the parser's length limit (BK_FORM_MAX_LEN), not far past: longer
	 * inputs only slow the search (the Makefile's -max_len is the same) */
	if (size > 2 * BK_FORM_MAX_LEN)
		return 0;
	char *text = malloc(size + 1);
	if (!text)
		return 0;
	memcpy(text, data, size);
	text[size] = '\0';
	bk_exercise_form(text);
	free(text);
	return 0;
}
