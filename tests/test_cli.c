/*
 * test_cli.c — the command line's shared conventions (analysis/cli/cli.c,
 * issue 24): the nearest name for a typing slip, counted by hand here (one
 * insertion, one deletion, one swap of neighbours), and none for a word too
 * far or too short to be a slip; one precision spelling, the old ones refused.
 */
#include "cli/cli.h"

#include <criterion/criterion.h>
#include <string.h>

static const char *const commands[] = {"terms", "dfg", "lut", "albedo", "eval", "ops", "codegen", "catalog",
                                       "fit", "time", "stability", "report", "search", "scene", "compare",
                                       "gpucost", "render"};
#define NCMD ((int)(sizeof commands / sizeof commands[0]))

static void suggests(const char *typed, const char *want, const char *const *names, int n)
{
	const char *got = cli_suggest(typed, names, n);
	if (!want)
		cr_assert_null(got, "'%s': suggested '%s', want none", typed, got);
	else
		cr_assert(got && !strcmp(got, want), "'%s': suggested '%s', want '%s'", typed, got ? got : "(none)", want);
}

Test(cli, one_edit_slips)
{
	suggests("serch", "search", commands, NCMD);  /* an 'a' left out */
	suggests("scenee", "scene", commands, NCMD);  /* one too many */
	suggests("comapre", "compare", commands, NCMD); /* a swap */
	static const char *const opts[] = {"--seed", "--evals", "--seconds", "--enum-max"};
	suggests("--evls", "--evals", opts, 4);
	static const char *const targets[] = {"vf2d", "vf", "spec", "env", "d", "f", "form"};
	suggests("vf2", "vf2d", targets, 7);
	static const char *const objs[] = {"rmse", "max", "albedo"};
	suggests("mx", "max", objs, 3);
}

/* "tmie" is one swap from "time" but two edits without the swap: a word of 4
 * letters is allowed one, so only the swap as one edit finds it. */
Test(cli, a_swap_is_one_edit)
{
	suggests("tmie", "time", commands, NCMD);
	/* control: two edits in 4 letters are too many */
	suggests("tqpe", NULL, commands, NCMD); /* two substitutions */
}

Test(cli, far_or_short_words_get_none)
{
	suggests("frobnicate", NULL, commands, NCMD);
	suggests("--zzzzzz", NULL, commands, NCMD);
	static const char *const targets[] = {"vf2d", "vf", "spec", "env", "d", "f", "form"};
	suggests("x", NULL, targets, 7); /* one edit from d and from f: means neither */
	suggests("vf2d", NULL, targets, 7); /* not a slip: the caller asks only for unknown words */
	char longw[80];
	memset(longw, 'a', sizeof longw - 1);
	longw[sizeof longw - 1] = '\0';
	suggests(longw, NULL, commands, NCMD);
}

Test(cli, two_edits_in_a_longer_word)
{
	suggests("stabilty", "stability", commands, NCMD); /* one */
	suggests("stablty", "stability", commands, NCMD);  /* two */
	suggests("stbty", NULL, commands, NCMD);           /* four: control */
}

Test(cli, ties_go_to_the_first_in_table_order)
{
	static const char *const a[] = {"vf2d", "vf2f"}, *const b[] = {"vf2f", "vf2d"};
	suggests("vf2e", "vf2d", a, 2);
	suggests("vf2e", "vf2f", b, 2);
}

Test(cli, one_precision_spelling)
{
	unsigned sh = CLI_PREC_BIT(CLI_PREC_SINGLE) | CLI_PREC_BIT(CLI_PREC_HALF);
	cli_prec p = CLI_PREC_BOTH;
	cr_assert_eq(cli_precision("half", sh, &p), 0);
	cr_assert_eq(p, CLI_PREC_HALF);
	cr_assert_eq(cli_precision("single", sh, &p), 0);
	cr_assert_eq(p, CLI_PREC_SINGLE);
	/* the old spellings and a precision the command lacks: refused, *out untouched */
	static const char *const old[] = {"fp16", "f16", "mediump", "fp32", "f32", "highp", "float"};
	for (size_t k = 0; k < sizeof old / sizeof old[0]; k++) {
		p = CLI_PREC_BOTH;
		cr_assert_eq(cli_precision(old[k], sh, &p), 2, "%s accepted", old[k]);
		cr_assert_eq(p, CLI_PREC_BOTH);
	}
	cr_assert_eq(cli_precision("double", sh, &p), 2);
	cr_assert_eq(cli_precision("both", sh | CLI_PREC_BIT(CLI_PREC_BOTH), &p), 0);
	cr_assert_eq(p, CLI_PREC_BOTH);
}
