/*
 * ir_emit.c — one C, GLSL or HLSL function from the instruction list, with the
 * provenance comment FFTW's generated files carry (DO NOT EDIT, the command,
 * the form, where it comes from, how well it fits, what it costs).
 *
 * Every instruction that is not a leaf becomes one statement "T tN = ...;" from
 * the opcode table's template, so a template's operands are always identifiers
 * or literals and no precedence is ever at stake; the only operands wrapped in
 * parentheses are negative literals ("t1 - (-0.5f)", never "-" "-0.5f" = "--").
 * Inputs are inlined by name, constants and parameters as float literals.
 */
#include "ir.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- a growing string; the first failure sticks, as on the parser -------- */

typedef struct text {
	char *s;
	size_t len, cap;
	int failed;
} text;

static void put(text *t, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void put(text *t, const char *fmt, ...)
{
	if (t->failed)
		return;
	va_list ap;
	va_start(ap, fmt);
	int k = vsnprintf(t->s + t->len, t->cap - t->len, fmt, ap);
	va_end(ap);
	if (k >= 0 && (size_t)k >= t->cap - t->len) { /* did not fit: grow, print again */
		size_t cap = 2 * t->cap + (size_t)k;
		char *s = realloc(t->s, cap);
		if (!s) {
			t->failed = 1;
			return;
		}
		t->s = s;
		t->cap = cap;
		va_start(ap, fmt);
		k = vsnprintf(t->s + t->len, t->cap - t->len, fmt, ap);
		va_end(ap);
	}
	if (k < 0)
		t->failed = 1;
	else
		t->len += (size_t)k;
}

/* ---- comment text ---------------------------------------------------------- */

/* A backslash (or C's trigraph "??" "/", which is one) that only blanks
 * follow up to a line break or the end: at the end of a line it would
 * continue a "//" comment onto the next (and gcc -Wall warns of it in any
 * comment), so bk_comment_text puts a '.' after it. */
static int ends_in_splice(const char *src, const char *s)
{
	if (*s != '\\' && !(*s == '/' && s - src >= 2 && s[-1] == '?' && s[-2] == '?'))
		return 0;
	while (*++s && *s != '\n')
		if ((unsigned char)*s > ' ' && *s != 0x7f)
			return 0;
	return 1;
}

size_t bk_comment_text(char *dst, size_t cap, const char *src, const char *newline)
{
	size_t n = 0;
#define OUT(c) (n + 1 < cap ? (void)(dst[n] = (c)) : (void)0, n++)
	for (const char *s = src; *s; s++) {
		if ((s[0] == '*' && s[1] == '/') || (s[0] == '/' && s[1] == '*')) {
			OUT(s[0]);
			OUT(' ');
		} else if (*s == '\n' && newline) {
			for (const char *p = newline; *p; p++)
				OUT(*p);
		} else if ((unsigned char)*s < ' ' || *s == 0x7f) {
			OUT(' ');
		} else {
			OUT(*s);
			if (ends_in_splice(src, s))
				OUT('.');
		}
	}
#undef OUT
	if (cap)
		dst[n < cap ? n : cap - 1] = '\0';
	return n;
}

/* Caller text inside the block comment (bk_comment_text's rule), a line break
 * continuing the comment's left margin. */
static void put_comment(text *t, const char *s)
{
	size_t n = bk_comment_text(NULL, 0, s, "\n *   ");
	char *buf = malloc(n + 1);
	if (!buf) {
		t->failed = 1;
		return;
	}
	bk_comment_text(buf, n + 1, s, "\n *   ");
	put(t, "%s", buf);
	free(buf);
}

static void put_line(text *t, const char *label, const char *value, const char *fallback)
{
	put(t, " * %s: ", label);
	put_comment(t, value ? value : fallback);
	put(t, "\n");
}

/* [lang][BK_EMIT_*]: what the type means, and what the code needs. */
#define C_FLOAT_NOTE " *   contraction (-ffp-contract=off, implied by -std=c11), but for exp2f and\n" \
	" *   log2f: libm's here, brdfkit's (0.5 ulp from exact) there; they may differ by an ulp"
static const char *const precision_line[3][3] = {
	{"C11 float; rounds like bk_form_eval BK_F32 when built without FMA\n" C_FLOAT_NOTE,
	 "C11 float with the half code's constants (binary16 values); rounds like\n"
	 " *   bk_form_eval BK_F32 of those constants when built without FMA\n" C_FLOAT_NOTE,
	 "C11 float with the half code's constants (binary16 values); rounds like\n"
	 " *   bk_form_eval BK_F32 of those constants when built without FMA\n" C_FLOAT_NOTE},
	{"GLSL ES 3.00 highp (fp32)",
	 "GLSL ES 3.00 mediump with binary16 constants (fp16 on mobile GPUs; bk_form_eval BK_F16)",
	 "GLSL float16_t with binary16 constants (fp16; bk_form_eval BK_F16); needs\n"
	 " *   #extension GL_EXT_shader_explicit_arithmetic_types_float16 : require"},
	{"HLSL float (fp32)",
	 "HLSL min16float with binary16 constants (fp16 where the GPU has it; bk_form_eval BK_F16)",
	 "HLSL half with binary16 constants (fp16; bk_form_eval BK_F16); needs dxc\n"
	 " *   -enable-16bit-types (shader model 6.2+): without it half is float"},
};
#undef C_FLOAT_NOTE

/* A value as the code holds it: the float, or under a half precision the
 * binary16 value bk_form_eval BK_F16 computes with (its rounding of the
 * float, brdf/ir_eval.c). */
static double written(double v, int half)
{
	return half ? bk_half_round((float)v) : (double)(float)v;
}

/* The op counts, from the same counter analysis/ reads (bk_form_count). */
static void put_counts(text *t, const bk_form *f)
{
	bk_ops ops;
	bk_form_count(f, &ops);
	put(t, " * op counts (after folding, sharing and multiply-add fusion):\n");
	for (int k = 0; k < BK_K_COUNT; k++)
		if (k != BK_K_FREE && ops.n[k])
			put(t, " *   %s %d\n", bk_opclass_name((bk_opclass)k), ops.n[k]);
	put(t, " *   simple %d, complex %d, cost %g (simple = %g, complex = %g)\n", ops.simple,
	    ops.complex, bk_ops_cost(&ops, BK_COST_SIMPLE, BK_COST_COMPLEX), BK_COST_SIMPLE,
	    BK_COST_COMPLEX);
}

static void put_header(text *t, const bk_form *f, bk_lang lang, int half, const double *params,
                       const bk_emit_info *info)
{
	put(t, "/*\n * Generated by brdfkit " BK_VERSION " — DO NOT EDIT (regenerate it instead).\n");
	if (info->command)
		put_line(t, "command", info->command, "");
	put_line(t, "form", bk_form_text(f), "");
	put_line(t, "source", info->source, "not given");
	put_line(t, "conventions", info->conventions, "not given");
	put(t, " * inputs: NoV NoL NoH LoH cosines on the +Z hemisphere, r perceptual roughness,\n"
	       " *   a = r*r, f0 normal-incidence reflectance (brdf.h)\n");
	put_line(t, "fitted domain", info->domain, "not fitted");
	put_line(t, "fitted error", info->error, "unknown");
	if (bk_form_nparams(f) == 0)
		put(t, " * parameters: none\n");
	else
		put(t, " * parameters baked in:\n");
	for (int p = 0; p < bk_form_nparams(f); p++) {
		put(t, " *   p%d = %.9g", p, params[p]);
		if (half && written(params[p], half) != (double)(float)params[p]) /* the half grid's value, as the code writes it */
			put(t, " (%.9g in half, as written below)", written(params[p], half));
		put(t, "\n");
	}
	put(t, " * precision: %s\n", precision_line[lang][half]);
	put_counts(t, f);
	put(t, " */\n");
}

/* ---- code ------------------------------------------------------------------ */

enum { OPERAND = 48 }; /* "uintBitsToFloat(0x7f800000u)", "(-1.17549435e-38f)" */

/* Spellings of what has no literal, per language: +inf, -inf, NaN (only a
 * parameter can be NaN, and a constant can be inf only once rounded to float,
 * as 1e40 is: folding refuses to make either). */
static const char *const special[3][3] = {
	{"INFINITY", "(-INFINITY)", "NAN"},
	{"uintBitsToFloat(0x7f800000u)", "uintBitsToFloat(0xff800000u)", "uintBitsToFloat(0x7fc00000u)"},
	{"asfloat(0x7f800000u)", "asfloat(0xff800000u)", "asfloat(0x7fc00000u)"},
};

/* A literal's suffix, [lang][BK_EMIT_*]: C's 'f' keeps the arithmetic in
 * float; GLSL never converts float to float16_t implicitly (hf); HLSL's h
 * makes a half, as a bare literal (a float) would not under 16-bit types. */
static const char *const suffix[3][3] = {{"f", "f", "f"}, {"", "", "hf"}, {"", "", "h"}};

/* v as the code computes with it (written()), in the fewest significant
 * digits that read back as that float (0.1, not 0.100000001; 9 always do),
 * or under a half precision as exactly that binary16 value in double
 * (0.0999755859375 for 0.1; 17 always do), so that the text is the half
 * grid's value, and a float or half parse of it gives the same value too
 * (it is far nearer to it than to any neighbour). A '.' or an exponent makes
 * it a floating literal in every language. */
static void literal(char *out, double v, bk_lang lang, int half)
{
	double x = written(v, half);
	if (isnan(x) || isinf(x)) {
		const char *s = special[lang][isnan(x) ? 2 : x < 0 ? 1 : 0];
		if (half == BK_EMIT_F16 && lang != BK_LANG_C) /* bits of a float, converted */
			snprintf(out, OPERAND, "%s(%s)", lang == BK_LANG_GLSL ? "float16_t" : "half", s);
		else
			snprintf(out, OPERAND, "%s", s);
		return;
	}
	char num[40];
	for (int digits = 1; digits <= 17; digits++) {
		snprintf(num, sizeof num, "%.*g", digits, x);
		if (half ? strtod(num, NULL) == x : strtof(num, NULL) == (float)x)
			break;
	}
	if (!strpbrk(num, ".e"))
		strcat(num, ".0");
	snprintf(out, OPERAND, signbit(x) ? "(%s%s)" : "%s%s", num, suffix[lang][half]);
}

static int is_leaf(bk_op op)
{
	return op == BK_OP_CONST || op == BK_OP_INPUT || op == BK_OP_PARAM;
}

/* Register i as an operand: a leaf inlined, anything else its temporary. */
static void operand(char *out, const bk_form *f, int i, bk_lang lang, int half, const double *params)
{
	const bk_instr *in = &f->code[i];
	if (in->op == BK_OP_INPUT)
		snprintf(out, OPERAND, "%s", bk_input_name((bk_input)in->slot));
	else if (in->op == BK_OP_CONST)
		literal(out, in->k, lang, half);
	else if (in->op == BK_OP_PARAM)
		literal(out, params[in->slot], lang, half);
	else
		snprintf(out, OPERAND, "t%d", i);
}

/* A template with %0 %1 %2 replaced by the operands; a number of the
 * template itself ("1.0 / %0") takes the literal suffix sfx. */
static void put_spelled(text *t, const char *tmpl, char ops[3][OPERAND], const char *sfx)
{
	for (const char *s = tmpl; *s; s++) {
		if (s[0] == '%' && s[1] >= '0' && s[1] <= '2') {
			put(t, "%s", ops[*++s - '0']);
		} else if (*sfx && s[0] >= '0' && s[0] <= '9' && s[1] == '.') {
			size_t k = 1 + strspn(s + 1, ".0123456789");
			put(t, "%.*s%s", (int)k, s, sfx);
			s += k - 1;
		} else {
			put(t, "%c", *s);
		}
	}
}

/* A bound as the code holds it: the float literal of a constant or a
 * baked-in parameter. */
static float bound(const bk_form *f, int i, const double *params)
{
	const bk_instr *in = &f->code[i];
	return (float)(in->op == BK_OP_CONST ? in->k : params[in->slot]);
}
/* (rounding to half is monotonic: bounds in order as floats stay in order) */

/* An instruction's template. GLSL's and HLSL's clamp(x, lo, hi) are
 * undefined for lo > hi, where the IR (and C's fminf(fmaxf())) give hi: the
 * call is kept only where both bounds are fixed and in order, and written
 * min(max(x, lo), hi) elsewhere, which is defined and what the IR computes. */
static const char *spelling(const bk_form *f, const bk_instr *in, bk_lang lang, const double *params)
{
	if (in->op == BK_OP_CLAMP && lang != BK_LANG_C &&
	    !(bk_ir_clamp_fixed_bounds(f, in) && bound(f, in->b, params) <= bound(f, in->c, params)))
		return "min(max(%0, %1), %2)";
	return bk_opinfo_table[in->op].spell[lang];
}

static const char *const type_name[3][3] = {
	{"float", "float", "float"},
	{"highp float", "mediump float", "float16_t"},
	{"float", "min16float", "half"},
};

/* Only the inputs the form reads (or a member's, bk_emit_style's inputs),
 * in bk_input order, so a call site can be written from the input names
 * alone. */
static void put_signature(text *t, const bk_form *f, const char *type, const char *name, bk_lang lang,
                          unsigned inputs)
{
	put(t, "%s%s %s(", lang == BK_LANG_C ? "static inline " : "", type, name);
	const char *sep = "";
	for (int i = 0; i < BK_IN_COUNT; i++) {
		if (!((inputs ? inputs : bk_form_inputs(f)) >> i & 1))
			continue;
		put(t, "%s%s %s", sep, type, bk_input_name((bk_input)i));
		sep = ", ";
	}
	put(t, "%s)\n", *sep || lang != BK_LANG_C ? "" : "void");
}

/* A parameter read by name (bk_emit_style's named_params): NAME_pK. */
static void param_name(char *out, const bk_form *f, int i, const char *named)
{
	if (named && f->code[i].op == BK_OP_PARAM)
		snprintf(out, OPERAND, "%.40s_p%d", named, f->code[i].slot);
}

static void put_body(text *t, const bk_form *f, const char *type, bk_lang lang, int half, const double *params,
                     const char *named)
{
	char ops[3][OPERAND];
	for (int i = 0; i < f->n; i++) {
		const bk_instr *in = &f->code[i];
		if (is_leaf(in->op))
			continue;
		int args[3] = {in->a, in->b, in->c};
		for (int j = 0; j < bk_opinfo_table[in->op].arity; j++) {
			operand(ops[j], f, args[j], lang, half, params);
			param_name(ops[j], f, args[j], named);
		}
		put(t, "\t%s t%d = ", type, i);
		put_spelled(t, spelling(f, in, lang, params), ops, lang == BK_LANG_C ? "" : suffix[lang][half]);
		put(t, ";\n");
	}
	operand(ops[0], f, f->out, lang, half, params);
	param_name(ops[0], f, f->out, named);
	put(t, "\treturn %s;\n", ops[0]);
}

/* The top of a member's body (bk_emit_style): a computed from r, C's
 * (void) for an input the signature takes and the code does not read (no
 * -Wunused-parameter at the user's), the named constants. */
static void put_prologue(text *t, const bk_form *f, const char *type, bk_lang lang, int half, const double *params,
                         const bk_emit_style *st, const char *name)
{
	unsigned reads = bk_form_inputs(f), derive_a = st->inputs && (reads >> BK_IN_A & 1) &&
	                                                !(st->inputs >> BK_IN_A & 1);
	if (derive_a)
		put(t, "\t%s a = r * r; /* alpha from the signature's r: one mul beyond the op counts above */\n", type);
	for (int i = 0; lang == BK_LANG_C && i < BK_IN_COUNT; i++)
		if ((st->inputs >> i & 1) && !(reads >> i & 1) && !(i == BK_IN_R && derive_a))
			put(t, "\t(void)%s;\n", bk_input_name((bk_input)i));
	for (int p = 0; st->named_params && p < bk_form_nparams(f); p++) {
		if (!(bk_form_params(f) >> p & 1)) /* a pair's B may read p2..p4 of its p0..p4 */
			continue;
		char v[OPERAND];
		literal(v, params[p], lang, half);
		put(t, "\tconst %s %.40s_p%d = %s;\n", type, name, p, v);
	}
}

/* ---- constants the generated code would compute as NaN or infinity -------- */

static void spell_const_op(char *what, size_t len, const bk_instr *in, const double *val)
{
	const char *name = bk_opinfo_table[in->op].name;
	double a = val[in->a], b = in->b >= 0 ? val[in->b] : 0, c = in->c >= 0 ? val[in->c] : 0;
	static const char infix[] = {[BK_OP_ADD] = '+', [BK_OP_SUB] = '-', [BK_OP_MUL] = '*', [BK_OP_DIV] = '/'};
	if (in->op == BK_OP_NEG)
		snprintf(what, len, "-(%.9g)", a);
	else if (in->op == BK_OP_MAD)
		snprintf(what, len, "%.9g*%.9g + %.9g", a, b, c);
	else if (!*name)
		snprintf(what, len, "%.9g %c %.9g", a, infix[in->op], b);
	else if (bk_opinfo_table[in->op].arity == 1)
		snprintf(what, len, "%s(%.9g)", name, a);
	else if (bk_opinfo_table[in->op].arity == 2)
		snprintf(what, len, "%s(%.9g, %.9g)", name, a, b);
	else
		snprintf(what, len, "%s(%.9g, %.9g, %.9g)", name, a, b, c);
}

/* A value rounded as precision prec holds it (single, or half). */
static double held(double v, bk_precision prec)
{
	return prec == BK_F16 ? bk_half_round((float)v) : (double)(float)v;
}

/* The value of every instruction that reads only constants (known[i]), in
 * precision prec as the code computes it (the rest left unset). */
static void const_values(const bk_form *f, const double *params, bk_precision prec, double *exact, double *val,
                         char *known)
{
	for (int i = 0; i < f->n; i++) {
		const bk_instr *in = &f->code[i];
		int ops[3] = {in->a, in->b, in->c}, ar = bk_opinfo_table[in->op].arity;
		known[i] = in->op == BK_OP_CONST || (in->op == BK_OP_PARAM && params);
		for (int j = 0; j < ar; j++)
			known[i] = (char)(j == 0 ? known[ops[j]] : known[i] && known[ops[j]]);
		if (!known[i])
			continue;
		double a = ar > 0 ? val[ops[0]] : 0, b = ar > 1 ? val[ops[1]] : 0, c = ar > 2 ? val[ops[2]] : 0;
		double v = in->op == BK_OP_CONST ? in->k : in->op == BK_OP_PARAM ? params[in->slot] : bk_ir_apply(in->op, a, b, c);
		exact[i] = v;
		val[i] = prec == BK_F16 && !is_leaf(in->op) ? bk_ir_apply_half(in->op, a, b, c) : held(v, prec);
	}
}

/* Walks the instructions the code computes from constants alone (literals,
 * baked-in parameters; params NULL: parameters are not constants) in
 * precision prec, each on its operands as prec holds them, as the code
 * computes it; stops at the first for which bad(exact, held) says so, and
 * names it in what: "exp2(127.99)", "the constant 1e-46", "p0 = 1e+39".
 * Returns how many are bad (the first named), -1 if out of memory. */
static int const_walk(const bk_form *f, const double *params, bk_precision prec,
                      int (*bad)(double, double, bk_precision),
                      char *what, size_t len, double *first)
{
	double *val = malloc(sizeof(double) * (size_t)f->n * 2);
	char *known = malloc((size_t)f->n);
	int found = 0;
	if (!val || !known) {
		free(val);
		free(known);
		return -1;
	}
	double *exact = val + f->n;
	const_values(f, params, prec, exact, val, known);
	for (int i = 0; i < f->n; i++) {
		const bk_instr *in = &f->code[i];
		if (!known[i] || !bad(exact[i], val[i], prec) || found++)
			continue;
		*first = val[i];
		if (in->op == BK_OP_CONST)
			snprintf(what, len, "the constant %.9g", exact[i]);
		else if (in->op == BK_OP_PARAM)
			snprintf(what, len, "p%d = %.9g", in->slot, exact[i]);
		else
			spell_const_op(what, len, in, val);
	}
	free(val);
	free(known);
	return found;
}

/* 1 if some division's divisor is a constant zero (x / 0, x / min(p0, 0)):
 * an infinity or NaN wherever it runs, and drivers disagree on which
 * (lavapipe gives 0 for NoV / 0.0, tests/vk); -1 out of memory. */
static int divides_by_zero(const bk_form *f, const double *params)
{
	double *val = malloc(sizeof(double) * (size_t)f->n * 2);
	char *known = malloc((size_t)f->n);
	int found = val && known ? 0 : -1;
	if (found == 0) {
		const_values(f, params, BK_F32, val + f->n, val, known);
		for (int i = 0; i < f->n && !found; i++)
			found = f->code[i].op == BK_OP_DIV && known[f->code[i].b] && val[f->code[i].b] == 0;
	}
	free(val);
	free(known);
	return found;
}

static int not_finite(double exact, double h, bk_precision prec)
{
	(void)exact, (void)prec;
	return !isfinite(h);
}

int bk_form_nonfinite(const bk_form *f, const double *params, char *what, size_t len)
{
	char op[96];
	double v = 0;
	int n = const_walk(f, params, BK_F32, not_finite, op, sizeof op, &v);
	if (n > 0)
		snprintf(what, len, "%s is %s in single precision", op, isnan(v) ? "NaN" : v > 0 ? "+inf" : "-inf");
	if (n == 0 && (n = divides_by_zero(f, params)) > 0)
		snprintf(what, len, "a division by the constant 0 (an infinity or NaN at every input)");
	return n < 0 ? -1 : n > 0;
}

/* Finite and non-zero in double, but infinite, NaN, zero or subnormal once
 * held (below the precision's smallest normal: 0 where GPUs flush). */
static int out_of_range(double exact, double h, bk_precision prec)
{
	double tiny = prec == BK_F16 ? 0x1p-14 : 0x1p-126;
	return isfinite(exact) && exact != 0 && !(isfinite(h) && fabs(h) >= tiny);
}

int bk_form_const_range(const bk_form *f, const double *params, bk_precision prec, char *what, size_t len)
{
	char op[96];
	double v = 0;
	int n = const_walk(f, params, prec, out_of_range, op, sizeof op, &v);
	if (n > 0)
		snprintf(what, len, "%s is %s in %s precision", op,
		         isnan(v) ? "NaN" : isinf(v) ? (v > 0 ? "+inf" : "-inf") : v == 0 ? "0" : "subnormal (0 where GPUs flush)",
		         prec == BK_F16 ? "half" : "single");
	return n;
}

int bk_form_clamp_reversed(const bk_form *f, const double *params, char *what, size_t len)
{
	int n = 0;
	for (int i = 0; i < f->n; i++) {
		const bk_instr *in = &f->code[i];
		if (in->op != BK_OP_CLAMP || !bk_ir_clamp_fixed_bounds(f, in) ||
		    (!params && (f->code[in->b].op == BK_OP_PARAM || f->code[in->c].op == BK_OP_PARAM)))
			continue;
		float lo = bound(f, in->b, params), hi = bound(f, in->c, params);
		if (lo > hi && !n++)
			snprintf(what, len, "clamp(x, %.9g, %.9g)", lo, hi);
	}
	return n;
}

char *bk_form_emit(const bk_form *f, bk_lang lang, int half, const double *params,
                   const bk_emit_info *info)
{
	return bk_form_emit_styled(f, lang, half, params, info, NULL);
}

char *bk_form_emit_styled(const bk_form *f, bk_lang lang, int half, const double *params, const bk_emit_info *info,
                          const bk_emit_style *st)
{
	static const bk_emit_info none;
	static const bk_emit_style plain;
	if (!st)
		st = &plain;
	if (!f || (unsigned)lang > BK_LANG_HLSL || (unsigned)half > BK_EMIT_F16 || (bk_form_nparams(f) > 0 && !params))
		return NULL;
	if (!info)
		info = &none;
	if (info->name && bk_lang_reserved(lang, info->name))
		return NULL;
	unsigned outside = st->inputs ? bk_form_inputs(f) & ~st->inputs : 0;
	if (outside & ~(1u << BK_IN_A) || (outside && !(st->inputs >> BK_IN_R & 1)))
		return NULL; /* an input the signature neither takes nor gives */
	const char *type = type_name[lang][half];
	text t = {malloc(1024), 0, 1024, 0};
	t.failed = !t.s;
	put_header(&t, f, lang, half, params, info);
	if (lang == BK_LANG_C)
		put(&t, "#include <math.h>\n");
	const char *name = info->name ? info->name : "brdfkit_form";
	put_signature(&t, f, type, name, lang, st->inputs);
	put(&t, "{\n");
	put_prologue(&t, f, type, lang, half, params, st, name);
	put_body(&t, f, type, lang, half, params, st->named_params ? name : NULL);
	put(&t, "}\n");
	if (t.failed) {
		free(t.s);
		return NULL;
	}
	return t.s;
}

/* The wrapper's return type and constructor from the scalar type: C
 * returns through pointers; GLSL's vec2 keeps the precision qualifier (no
 * default float precision in a fragment shader), float16_t's is f16vec2;
 * HLSL's is the scalar's name with 2 (float2, half2, min16float2). */
static void pair_type(char *ret, char *ctor, size_t len, const char *type, bk_lang lang)
{
	const char *fl = strstr(type, "float");
	if (lang == BK_LANG_C) {
		snprintf(ret, len, "void");
	} else if (lang == BK_LANG_GLSL && strstr(type, "float16_t")) {
		snprintf(ret, len, "f16vec2");
	} else if (lang == BK_LANG_GLSL && fl) {
		snprintf(ret, len, "%.*svec2", (int)(fl - type) & 31, type); /* "highp float" -> "highp vec2" */
	} else {
		snprintf(ret, len, "%.20s2", type); /* the longest, "min16float" */
	}
	snprintf(ctor, len, "%s", lang == BK_LANG_GLSL && strchr(ret, ' ') ? strchr(ret, ' ') + 1 : ret);
}

char *bk_form_emit_pair(const bk_form *fa, const bk_form *fb, bk_lang lang, int half, const double *params,
                        const bk_emit_info *info, const bk_emit_style *style)
{
	static const bk_emit_info none;
	static const bk_emit_style plain;
	if (!style)
		style = &plain;
	if (!fa || !fb || (unsigned)lang > BK_LANG_HLSL)
		return NULL;
	if (!info)
		info = &none;
	const char *name = info->name ? info->name : "brdfkit_form";
	char part[2][BK_NAME_MAX + 8];
	bk_emit_info pi[2] = {*info, *info};
	bk_emit_style st = *style;
	unsigned inputs = st.inputs ? st.inputs : bk_form_inputs(fa) | bk_form_inputs(fb);
	st.inputs = inputs;
	char *code[2] = {NULL, NULL};
	for (int k = 0; k < 2; k++) {
		snprintf(part[k], sizeof part[k], "%s_%c", name, "AB"[k]);
		pi[k].name = part[k];
		code[k] = bk_form_emit_styled(k ? fb : fa, lang, half, params, &pi[k], &st);
	}
	if (!code[0] || !code[1] || bk_lang_reserved(lang, name)) {
		free(code[0]);
		free(code[1]);
		return NULL;
	}
	const char *type = type_name[lang][half]; /* the scalar type NAME_A and NAME_B take (half checked there) */
	text t = {malloc(1024), 0, 1024, 0};
	t.failed = !t.s;
	char ret[32], ctor[32];
	pair_type(ret, ctor, sizeof ret, type, lang);
	put(&t, "%s\n%s\n", code[0], code[1]);
	put(&t, "/* %s: the split sum's A and B at once, as engines call an environment BRDF:\n"
	        " * specular = prefiltered * (f0 * A + B). DO NOT EDIT (see %s_A and %s_B). */\n", name, name, name);
	put(&t, "%s%s %s(", lang == BK_LANG_C ? "static inline " : "", ret, name);
	const char *sep = "";
	for (int i = 0; i < BK_IN_COUNT; i++)
		if (inputs >> i & 1) {
			put(&t, "%s%s %s", sep, type, bk_input_name((bk_input)i));
			sep = ", ";
		}
	if (lang == BK_LANG_C)
		put(&t, "%s%s *A, %s *B", sep, type, type);
	put(&t, ")\n{\n");
	char args[BK_IN_COUNT * 8] = "";
	for (int i = 0; i < BK_IN_COUNT; i++)
		if (inputs >> i & 1)
			snprintf(args + strlen(args), sizeof args - strlen(args), "%s%s", *args ? ", " : "",
			         bk_input_name((bk_input)i));
	if (lang == BK_LANG_C)
		put(&t, "\t*A = %s(%s);\n\t*B = %s(%s);\n", part[0], args, part[1], args);
	else
		put(&t, "\treturn %s(%s(%s), %s(%s));\n", ctor, part[0], args, part[1], args);
	put(&t, "}\n");
	free(code[0]);
	free(code[1]);
	if (t.failed) {
		free(t.s);
		return NULL;
	}
	return t.s;
}
