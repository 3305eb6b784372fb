/*
 * fuzz_ckpt.c — libFuzzer harness for the search's checkpoint reader
 * (fit/search/state.c, bk_search_load): any bytes as the body of a checkpoint of
 * a small search (a planted form on 8 x 8 cells, a seed, 3-node
 * enumeration, generations of 8). `make fuzz` builds it with clang, ASan
 * and UBSan and runs it for FUZZ_RUNS inputs.
 *
 * So that the checks behind the checksum are what is fuzzed, the harness
 * writes the right fingerprint into an input's fingerprint line and appends
 * the checksum line of the input (the input is the body); one input in
 * eight is read as it is, for the checksum's own check. A state that loads
 * is saved again and stepped once: what the reader let through is used as
 * a resumed search uses it. At start the harness writes the checkpoint of
 * a real run of that search into every corpus directory it is given
 * (valid_checkpoint), the seed the mutations start from.
 */
#define _GNU_SOURCE /* memmem */
#include "search.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static bk_samples screen;
static bk_search_options opt;
static char fingerprint[17];
static const char *const seed[] = {"p0/(LoH*LoH + p1)"};

static void options(void)
{
	bk_target_options to;
	bk_target_defaults(BK_TARGET_FORM, &to);
	to.form_text = "0.3/(LoH*LoH + 0.7*r*r)";
	to.ndomain = 2;
	to.dom_in[0] = BK_IN_LOH, to.dom_lo[0] = 0.3162, to.dom_hi[0] = 1;
	to.dom_in[1] = BK_IN_R, to.dom_lo[1] = 0, to.dom_hi[1] = 1;
	to.nx = 8;
	char err[256];
	if (bk_target_build(&to, &screen, NULL, NULL, err, sizeof err)) {
		fprintf(stderr, "fuzz_ckpt: %s\n", err);
		exit(1);
	}
	bk_search_defaults(&opt);
	opt.screen = &screen;
	opt.shape = BK_SHAPE_PLAIN;
	memset(&opt.grammar, 0, sizeof opt.grammar);
	bk_grammar_parse_ops("+,*,/,sq", &opt.grammar.ops, err, sizeof err);
	opt.grammar.inputs = 1u << BK_IN_LOH | 1u << BK_IN_R | 1u << BK_IN_A;
	opt.grammar.consts[0] = 1;
	opt.grammar.nconsts = 1;
	opt.grammar.max_params = 2;
	opt.grammar.max_size = 16;
	opt.evals = 24;
	opt.seeds = seed;
	opt.nseeds = 1;
	opt.seed = 7;
	opt.generation = 8;
	opt.enum_size = 3;
	opt.enum_max = 12;
}

/* The checkpoint of s (malloc'd). */
static char *text_of(const bk_search *s, size_t *len)
{
	char *buf = NULL;
	FILE *f = open_memstream(&buf, len);
	if (!f || bk_search_save(s, f)) {
		fprintf(stderr, "fuzz_ckpt: cannot save\n");
		exit(1);
	}
	fclose(f);
	return buf;
}

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
	options();
	char err[256];
	bk_search *s = bk_search_new(&opt, err, sizeof err);
	if (!s) {
		fprintf(stderr, "fuzz_ckpt: %s\n", err);
		exit(1);
	}
	while (bk_search_step(s, err, sizeof err) == 1)
		;
	size_t len;
	char *text = text_of(s, &len);
	const char *fp = strstr(text, "\nfingerprint ");
	memcpy(fingerprint, fp + 13, 16);
	char *end = strstr(text, "\nchecksum ");
	size_t body = (size_t)(end - text) + 1;
	for (int i = 1; i < *argc; i++) { /* the corpus directories: the seed */
		struct stat st;
		char path[4096];
		if ((*argv)[i][0] == '-' || stat((*argv)[i], &st) || !S_ISDIR(st.st_mode))
			continue;
		snprintf(path, sizeof path, "%s/valid_checkpoint", (*argv)[i]);
		FILE *f = fopen(path, "w");
		if (f) {
			fwrite(text, 1, body, f);
			fclose(f);
		}
	}
	free(text);
	bk_search_free(s);
	return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (size > 1 << 20)
		return 0;
	char *in = malloc(size + 40);
	if (!in)
		return 0;
	memcpy(in, data, size);
	in[size] = '\0';
	size_t len = size;
	uint64_t h = bk_hash_bytes(BK_HASH_INIT, data, size);
	if (h % 8) { /* the checks behind the fingerprint and the checksum */
		char *fp = memmem(in, size, "\nfingerprint ", 13);
		if (fp && (size_t)(fp - in) + 13 + 16 <= size)
			memcpy(fp + 13, fingerprint, 16);
		len += (size_t)snprintf(in + size, 40, "checksum %016llx\n",
		                        (unsigned long long)bk_hash_bytes(BK_HASH_INIT, in, size));
	}
	char err[512];
	bk_search *s = bk_search_new(&opt, err, sizeof err);
	FILE *f = s ? fmemopen(in, len ? len : 1, "r") : NULL;
	if (f && bk_search_load(s, f, err, sizeof err) == 0) {
		size_t n;
		free(text_of(s, &n));
		bk_search_step(s, err, sizeof err);
	}
	if (f)
		fclose(f);
	bk_search_free(s);
	free(in);
	return 0;
}
