/*
 * glsl.c — the batched compute shaders of tests/vk, the float16_t rewrite of
 * a function's text and the negative control's perturbation (see glsl.h).
 */
#include "glsl.h"

#include "half.h"
#include "out.h"

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static int ident_char(char c)
{
	return isalnum((unsigned char)c) || c == '_';
}

/* The length of a float literal at s (digits, a '.', an exponent), 0 if
 * there is none or it runs into an identifier (0x7f800000u, 8u). */
static size_t literal_len(const char *s)
{
	if (!isdigit((unsigned char)*s) && !(*s == '.' && isdigit((unsigned char)s[1])))
		return 0;
	size_t k = strspn(s, "0123456789.");
	if (s[k] == 'e' || s[k] == 'E') {
		size_t j = k + 1 + (s[k + 1] == '+' || s[k + 1] == '-');
		if (isdigit((unsigned char)s[j]))
			k = j + strspn(s + j, "0123456789");
	}
	return ident_char(s[k]) ? 0 : k;
}

/* The length of the comment at s, 0 if s is no comment. */
static size_t comment_len(const char *s)
{
	if (s[0] == '/' && s[1] == '*') {
		const char *e = strstr(s + 2, "*/");
		return e ? (size_t)(e + 2 - s) : strlen(s);
	}
	return s[0] == '/' && s[1] == '/' ? strcspn(s, "\n") : 0;
}

/* A comment at s copied whole; its length, or 0 if s is no comment. */
static size_t put_comment(bk_strbuf *b, const char *s)
{
	size_t k = comment_len(s);
	if (k)
		bk_sb_put(b, "%.*s", (int)k, s);
	return k;
}

/* v as the exact decimal of its half rounding: a half has at most 11
 * significant bits and 24 fraction bits, which 30 digits always spell out. */
static void put_half_literal(bk_strbuf *b, double v)
{
	char num[64];
	double h = bk_half_round_inline((float)v);
	if (isinf(h)) { /* past 65504: no literal spells it (the IR's f16 has it infinite too) */
		bk_sb_put(b, "float16_t(uintBitsToFloat(0x7f800000u))");
		return;
	}
	snprintf(num, sizeof num, "%.30g", h);
	bk_sb_put(b, "%s%shf", num, strpbrk(num, ".e") ? "" : ".0");
}

char *vk_half_text(const char *s)
{
	bk_strbuf b = {0};
	while (*s) {
		size_t k = put_comment(&b, s);
		if (k) {
			s += k;
			continue;
		}
		if (isalpha((unsigned char)*s) || *s == '_') {
			k = 0;
			while (ident_char(s[k]))
				k++;
			if (k == 5 && !strncmp(s, "float", 5))
				bk_sb_put(&b, "float16_t");
			else if ((k == 5 && !strncmp(s, "highp", 5)) || (k == 7 && !strncmp(s, "mediump", 7)) ||
			         (k == 4 && !strncmp(s, "lowp", 4)))
				k += strspn(s + k, " "); /* the qualifier and its space */
			else if (k == 15 && !strncmp(s, "uintBitsToFloat", 15) && s[k] == '(') {
				size_t close = strcspn(s, ")"); /* its argument is one literal */
				bk_sb_put(&b, "float16_t(%.*s)", (int)(close + 1), s);
				k = close + (s[close] == ')');
			} else
				bk_sb_put(&b, "%.*s", (int)k, s);
			s += k;
		} else if ((k = literal_len(s)) > 0) {
			put_half_literal(&b, strtod(s, NULL));
			s += k;
		} else
			bk_sb_put(&b, "%c", *s++);
	}
	if (b.oom) {
		free(b.s);
		return NULL;
	}
	return b.s;
}

int vk_calls(const char *glsl, const char *fn)
{
	size_t n = strlen(fn);
	for (const char *s = glsl; *s;) {
		size_t k = comment_len(s);
		if (k)
			s += k;
		else if (!strncmp(s, fn, n) && (s == glsl || !ident_char(s[-1])) && s[n + strspn(s + n, " ")] == '(')
			return 1;
		else
			s++;
	}
	return 0;
}

/* ---- the shader --------------------------------------------------------------- */

/* The header: SignedZeroInfNanPreserve for the arithmetic's width, so that
 * NaN and infinities mean something (without it the driver may assume there
 * are none: "Precision and Operation of SPIR-V Instructions"); glslang keeps
 * one such mode per id, and the conversions of the f16 shader's main are exact. */
static void put_head(bk_strbuf *b, bk_precision prec)
{
	int w = prec == BK_F16 ? 16 : 32;
	bk_sb_put(b, "#version 450\n%s#extension GL_EXT_spirv_intrinsics : require\n"
	             "spirv_execution_mode(extensions = [\"SPV_KHR_float_controls\"], capabilities = [4466], 4461, %d);\n"
	             "layout(local_size_x = 64) in;\n"
	             "layout(std430, set = 0, binding = 0) readonly buffer Inputs { float v[]; } inb;\n"
	             "layout(std430, set = 0, binding = 1) writeonly buffer Outputs { float v[]; } outb;\n"
	             "layout(push_constant) uniform Pick { uint fn, in_off, out_off, n; } pc;\n\n",
	          prec == BK_F16 ? "#extension GL_EXT_shader_explicit_arithmetic_types_float16 : require\n" : "", w);
}

static void put_main(bk_strbuf *b, const vk_fn *const *fns, int n, bk_precision prec)
{
	const char *T = prec == BK_F16 ? "float16_t" : "float";
	bk_sb_put(b, "void main()\n{\n\tuint k = gl_GlobalInvocationID.x;\n\tif (k >= pc.n)\n\t\treturn;\n"
	             "\tuint i = (pc.in_off + k) * 8u;\n");
	for (int c = 0; c < BK_IN_COUNT; c++)
		bk_sb_put(b, "\t%s %s = %s(inb.v[i + %du]);\n", T, bk_input_name((bk_input)c), T, c);
	bk_sb_put(b, "\tfloat bk_res = 0.0;\n\tswitch (pc.fn) {\n");
	for (int j = 0; j < n; j++) {
		bk_sb_put(b, "\tcase %du: bk_res = float(%s(", j, fns[j]->name);
		const char *sep = "";
		for (int c = 0; c < BK_IN_COUNT; c++)
			if (fns[j]->args >> c & 1) {
				bk_sb_put(b, "%s%s", sep, bk_input_name((bk_input)c));
				sep = ", ";
			}
		bk_sb_put(b, ")); break;\n");
	}
	bk_sb_put(b, "\t}\n\toutb.v[pc.out_off + k] = bk_res;\n}\n");
}

char *vk_shader(const vk_fn *const *fns, int n, bk_precision prec)
{
	bk_strbuf b = {0};
	put_head(&b, prec);
	for (int j = 0; j < n && !b.oom; j++) {
		char *text = prec == BK_F16 ? vk_half_text(fns[j]->glsl) : NULL;
		if (prec == BK_F16 && !text)
			b.oom = 1;
		else
			bk_sb_put(&b, "%s\n", text ? text : fns[j]->glsl);
		free(text);
	}
	put_main(&b, fns, n, prec);
	if (b.oom) {
		free(b.s);
		return NULL;
	}
	return b.s;
}

/* ---- the negative control ------------------------------------------------------ */

char *vk_perturb(const char *glsl, const char *name, double factor, int how)
{
	char sig[96];
	snprintf(sig, sizeof sig, " %s(", name);
	const char *at = strstr(glsl, sig), *body = at ? strstr(at, "\n{\n") : NULL;
	const char *end = body ? strstr(body, "\n}\n") : NULL;
	if (!end)
		return NULL;
	const char *hit = NULL, *s = body;
	size_t k = 0;
	if (how == 1) { /* the return value times NaN */
		hit = strstr(body, "\treturn ");
		if (!hit || hit > end)
			return NULL;
		hit += strcspn(hit, ";");
	}
	while (!hit && s < end) {
		if (ident_char(*s) && !isdigit((unsigned char)*s))
			while (ident_char(*s))
				s++;
		else if ((k = literal_len(s)) > 0 && memchr(s, '.', k))
			hit = s;
		else
			s++;
	}
	if (!hit || hit > end)
		return NULL;
	bk_strbuf b = {0};
	bk_sb_put(&b, "%.*s", (int)(hit - glsl), glsl);
	if (how == 1)
		bk_sb_put(&b, " * uintBitsToFloat(0x7fc00000u)%s", hit);
	else {
		char num[40];
		snprintf(num, sizeof num, "%.9g", strtod(hit, NULL) * factor);
		bk_sb_put(&b, "%s%s%s", num, strpbrk(num, ".e") ? "" : ".0", hit + k);
	}
	if (b.oom) {
		free(b.s);
		return NULL;
	}
	return b.s;
}
