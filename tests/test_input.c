/*
 * test_input.c — no silent wrong answer from what the user types, at the
 * library's side: literals that are not the value typed, the form's limits
 * (length, nesting, instructions) as errors naming them, constants the
 * generated code would compute as NaN or infinity, and function names each
 * target language refuses.
 */
#include "brdf.h"

#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void parse_fails(const char *text, int column, const char *message)
{
	bk_form_error e;
	bk_form *f = bk_form_parse(text, &e);
	cr_assert_null(f, "'%.40s' parsed", text);
	cr_assert_eq(e.column, column, "'%.40s': column %d, want %d (%s)", text, e.column, column, e.message);
	cr_assert_str_eq(e.message, message, "'%.40s'", text);
}

static double eval_at_one(const char *text)
{
	double one = 1.0, out;
	const double *in[BK_IN_COUNT] = {&one, &one, &one, &one, &one, &one, &one};
	bk_form_error e;
	bk_form *f = bk_form_parse(text, &e);
	cr_assert_not_null(f, "'%.40s': %d: %s", text, e.column, e.message);
	cr_assert_eq(bk_form_eval(f, BK_F64, 1, in, NULL, &out), 0);
	bk_form_free(f);
	return out;
}

/* A string of n copies of unit joined by sep. */
static char *repeat(const char *unit, const char *sep, int n)
{
	size_t lu = strlen(unit), ls = strlen(sep);
	char *s = malloc((size_t)n * (lu + ls) + 1), *p = s;
	for (int i = 0; i < n; i++) {
		if (i) {
			memcpy(p, sep, ls);
			p += ls;
		}
		memcpy(p, unit, lu);
		p += lu;
	}
	*p = '\0';
	return s;
}

/* ---- literals ---------------------------------------------------------------- */

/* 1e999 would be inf and 1e-400 zero: neither is the number typed. A
 * subnormal is a number like any other: 1e-320 is the compiler's 1e-320. */
Test(literal, overflow_and_underflow_are_errors_subnormals_are_numbers)
{
	parse_fails("1e999", 1, "number too large (overflows double) near '1e999'");
	parse_fails("NoV * 2e308", 7, "number too large (overflows double) near '2e308'");
	parse_fails("NoV*1e-400", 5, "number too small (underflows to zero) near '1e-400'");
	cr_assert_eq(eval_at_one("1e-320"), 1e-320);
	cr_assert_eq(eval_at_one("0e-999 + NoV"), 1.0); /* a zero typed is zero */
	cr_assert_eq(eval_at_one("1.7976931348623157e308"), 0x1.fffffffffffffp+1023);
}

/* ---- limits -------------------------------------------------------------------- */

/* Text: BK_FORM_MAX_LEN characters parse, one more is an error at the first
 * character past the limit. */
Test(limits, length)
{
	cr_assert_eq(BK_FORM_MAX_LEN, 16384);
	char *s = malloc(BK_FORM_MAX_LEN + 2);
	memset(s, ' ', BK_FORM_MAX_LEN + 1);
	s[0] = '1';
	s[BK_FORM_MAX_LEN] = '\0';
	cr_assert_eq(eval_at_one(s), 1.0);
	s[BK_FORM_MAX_LEN] = ' ';
	s[BK_FORM_MAX_LEN + 1] = '\0';
	parse_fails(s, 16385, "form longer than 16384 characters");
	free(s);
}

/* Instructions: r+r+...+r with n terms is n instructions (the input and n-1
 * additions, none shared) and equals n at r = 1. */
Test(limits, instructions)
{
	char *s = repeat("r", "+", 4096);
	cr_assert_eq(eval_at_one(s), 4096.0);
	free(s);
	s = repeat("r", "+", 4097);
	parse_fails(s, 8194, "form too large (more than 4096 instructions) at end of form");
	free(s);
}

/* Nesting: the whole form is level 0, each '(' or unary minus one more
 * (brdfkit(1): "200 levels deep"); 200 levels parse, the operand at level 201 is
 * the error. */
Test(limits, depth)
{
	char buf[1000];
	memset(buf, '(', 200);
	strcpy(buf + 200, "NoV");
	memset(buf + 203, ')', 200);
	buf[403] = '\0';
	cr_assert_eq(eval_at_one(buf), 1.0);
	memset(buf, '(', 201);
	strcpy(buf + 201, "NoV");
	memset(buf + 204, ')', 201);
	buf[405] = '\0';
	parse_fails(buf, 202, "expression nested too deeply (more than 200 levels) near 'NoV'");
	char *neg = repeat("-", "", 199), text[300];
	snprintf(text, sizeof text, "-%sNoV", neg);
	cr_assert_eq(eval_at_one(text), 1.0); /* an even number of minus signs */
	snprintf(text, sizeof text, "--%sNoV", neg);
	parse_fails(text, 202, "expression nested too deeply (more than 200 levels) near 'NoV'");
	free(neg);
}

/* ---- constants that are not finite in the generated code -------------------- */

static void nonfinite(const char *text, const double *params, const char *want)
{
	bk_form *f = bk_form_parse(text, NULL);
	cr_assert_not_null(f, "'%s'", text);
	char what[160] = "";
	int rc = bk_form_nonfinite(f, params, what, sizeof what);
	if (want) {
		cr_assert_eq(rc, 1, "'%s': none found", text);
		cr_assert_str_eq(what, want, "'%s'", text);
	} else {
		cr_assert_eq(rc, 0, "'%s': %s", text, what);
	}
	bk_form_free(f);
}

Test(nonfinite, ops_on_constants_and_literals_past_float)
{
	nonfinite("sqrt(-1)*NoV", NULL, "sqrt(-1) is NaN in single precision");
	nonfinite("NoV + 1/0", NULL, "1 / 0 is +inf in single precision");
	nonfinite("0/0", NULL, "0 / 0 is NaN in single precision");
	nonfinite("log(0) + NoV", NULL, "log(0) is -inf in single precision");
	nonfinite("NoV*1e39", NULL, "the constant 1e+39 is +inf in single precision"); /* FLT_MAX ~ 3.4e38 */
	nonfinite("p0*NoV", (const double[]){-1e39}, "p0 = -1e+39 is -inf in single precision");
	nonfinite("sqrt(p0)*NoV", (const double[]){-4}, "sqrt(-4) is NaN in single precision");
	/* not constant: a pole at an input is the form's, not the code's */
	nonfinite("NoL/NoV + sqrt(-NoL)", NULL, NULL);
	/* but a division by a constant zero is the code's at every input, also
	 * where a max hides it at some (drivers disagree on x / 0.0: tests/vk) */
	nonfinite("NoV/0 + sqrt(-NoL)", NULL, "a division by the constant 0 (an infinity or NaN at every input)");
	nonfinite("max(NoL, NoV/min(p0, 0))", (const double[]){0.75},
	          "a division by the constant 0 (an infinity or NaN at every input)");
	nonfinite("max(NoL, NoV/min(p0, 0))", NULL, NULL); /* p0 not baked in: not a constant */
	nonfinite("sqrt(p0)*NoV", NULL, NULL); /* parameters not baked in */
	nonfinite("sqrt(0.5)*NoV + 3.4e38", NULL, NULL);
}

/* ---- names of the generated function -------------------------------------------- */

/* C11 6.4.1, typed from the standard (not from the table under test). */
static const char *const c11_keywords[] = {
	"auto", "break", "case", "char", "const", "continue", "default", "do", "double", "else",
	"enum", "extern", "float", "for", "goto", "if", "inline", "int", "long", "register",
	"restrict", "return", "short", "signed", "sizeof", "static", "struct", "switch", "typedef",
	"union", "unsigned", "void", "volatile", "while", "_Alignas", "_Alignof", "_Atomic", "_Bool",
	"_Complex", "_Generic", "_Imaginary", "_Noreturn", "_Static_assert", "_Thread_local",
};

Test(names, c11_keywords_refused)
{
	for (size_t i = 0; i < sizeof c11_keywords / sizeof c11_keywords[0]; i++)
		cr_assert_eq(bk_lang_reserved(BK_LANG_C, c11_keywords[i]), 1, "%s", c11_keywords[i]);
}

Test(names, glsl_and_hlsl_types_and_reserved_words_refused)
{
	static const char *const glsl[] = {"float", "int", "vec3", "mat4x3", "highp", "mediump", "precision",
	                                   "sampler2D", "half", "input", "gl_Position", "my__name", "sqrt",
	                                   "mix", "inversesqrt"};
	static const char *const hlsl[] = {"float", "half", "float4", "half3x3", "int2", "min16float",
	                                   "cbuffer", "Texture2D", "matrix", "lerp", "saturate", "rsqrt",
	                                   "mad", "asfloat"};
	for (size_t i = 0; i < sizeof glsl / sizeof glsl[0]; i++)
		cr_assert_eq(bk_lang_reserved(BK_LANG_GLSL, glsl[i]), 1, "glsl %s", glsl[i]);
	for (size_t i = 0; i < sizeof hlsl / sizeof hlsl[0]; i++)
		cr_assert_eq(bk_lang_reserved(BK_LANG_HLSL, hlsl[i]), 1, "hlsl %s", hlsl[i]);
	/* the names the body declares: the inputs (parameters) and temporaries */
	for (int lang = BK_LANG_C; lang <= BK_LANG_HLSL; lang++) {
		cr_assert_eq(bk_lang_reserved((bk_lang)lang, "NoV"), 1);
		cr_assert_eq(bk_lang_reserved((bk_lang)lang, "t0"), 1);
		cr_assert_eq(bk_lang_reserved((bk_lang)lang, "t12"), 1);
	}
	cr_assert_eq(bk_lang_reserved(BK_LANG_C, "_x"), 1); /* C11 7.1.3: file scope */
	cr_assert_eq(bk_lang_reserved(BK_LANG_C, "sqrtf"), 1);
}

/* What is no identifier is refused by the emitter too: a name from a
 * user's text (compare's typed form, slugged) once reached a shader as
 * "float 0_25_r(...)"; the control is the same name with a letter before. */
Test(names, what_is_no_identifier_refused)
{
	static const char *const bad[] = {"0_25_r", "9", "", "a-b", "a b", "a.b", "caf\xc3\xa9", "a$", "x\n"};
	bk_form_error fe;
	bk_form *f = bk_form_parse("NoV * 0.5", &fe);
	cr_assert_not_null(f);
	for (int lang = BK_LANG_C; lang <= BK_LANG_HLSL; lang++)
		for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
			cr_assert_eq(bk_identifier(bad[i]), 0, "%s", bad[i]);
			cr_assert_eq(bk_lang_reserved((bk_lang)lang, bad[i]), 1, "lang %d: '%s'", lang, bad[i]);
			bk_emit_info info = {bad[i], NULL, NULL, NULL, NULL, NULL};
			cr_assert_null(bk_form_emit(f, (bk_lang)lang, 0, NULL, &info), "lang %d emitted '%s'", lang, bad[i]);
		}
	bk_emit_info ok = {"f_0_25_r", NULL, NULL, NULL, NULL, NULL};
	for (int lang = BK_LANG_C; lang <= BK_LANG_HLSL; lang++) {
		char *text = bk_form_emit(f, (bk_lang)lang, 0, NULL, &ok);
		cr_assert(text && strstr(text, "f_0_25_r("), "lang %d", lang);
		free(text);
	}
	cr_assert_eq(bk_identifier("_x9"), 1);
	bk_form_free(f);
}

Test(names, ordinary_names_accepted)
{
	static const char *const fine[] = {"int_", "my_term", "brdfkit_form", "vec3_", "float5", "t", "tx",
	                                   "t1a", "D_ggx_fit", "half_", "Float"};
	for (int lang = BK_LANG_C; lang <= BK_LANG_HLSL; lang++)
		for (size_t i = 0; i < sizeof fine / sizeof fine[0]; i++)
			cr_assert_eq(bk_lang_reserved((bk_lang)lang, fine[i]), 0, "lang %d: %s", lang, fine[i]);
}

/* Every entry of every table is refused, by bk_lang_reserved and by the
 * emitter itself (which would otherwise write code that does not compile). */
Test(names, every_table_entry_refused_by_the_emitter)
{
	bk_form *f = bk_form_parse("NoV*NoL", NULL);
	cr_assert_not_null(f);
	size_t total = 0;
	for (int lang = BK_LANG_C; lang <= BK_LANG_HLSL; lang++) {
		const char *w;
		size_t i = 0;
		for (; (w = bk_lang_word((bk_lang)lang, i)); i++) {
			cr_assert_eq(bk_lang_reserved((bk_lang)lang, w), 1, "lang %d: %s", lang, w);
			bk_emit_info info = {.name = w};
			char *code = bk_form_emit(f, (bk_lang)lang, 0, NULL, &info);
			cr_assert_null(code, "lang %d: emitted a function named %s", lang, w);
		}
		cr_assert(i > 40, "lang %d: only %zu entries", lang, i);
		total += i;
		bk_emit_info info = {.name = "my_term"};
		char *code = bk_form_emit(f, (bk_lang)lang, 0, NULL, &info);
		cr_assert_not_null(code);
		cr_assert_not_null(strstr(code, " my_term("));
		free(code);
	}
	cr_assert(total > 300);
	bk_form_free(f);
}
