/*
 * ir_math.c — a form as LaTeX, SymPy or MathML (brdf_math.h).
 *
 * The instruction list is walked from the result down, each operand written
 * in place (a shared subexpression at each of its uses); parentheses come
 * from a precedence per construct, the same for the three languages: a sum
 * below a product below a leading minus below a power below an atom (an
 * input, a number, a function call, a fraction bar or root in LaTeX and
 * MathML). An operand that starts with a minus is wrapped wherever it follows
 * an operator ("a - (-b)", "x·(-y)"), so no two signs ever meet.
 *
 * Meanings are brdfkit's (brdf/ir_ops.h): pow(x, y) = exp2(y log2 x), which
 * for x > 0 is x^y (written so; brdfkit has no value for x < 0 or x = 0 with
 * y <= 0); mix(x, y, t) = x + (y - x) t; saturate(x) = clamp(x, 0, 1);
 * clamp(x, lo, hi) = min(max(x, lo), hi); mad(a, b, c) = a b + c.
 */
#include "brdf_math.h"

#include "brdf_ops.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { P_ADD = 1, P_MUL, P_NEG, P_POW, P_ATOM };

typedef struct printer {
	FILE *o;
	const bk_instr *code;
	bk_math_lang lang;
	const double *params; /* NULL: symbols */
	int digits;
	int failed; /* out of memory outside the stream */
} printer;

/* ---- numbers ---------------------------------------------------------------- */

/* v in digits significant digits, or (0) the fewest that read back as the
 * float the shaders hold (as ir_emit.c's literals); SymPy gets every digit of
 * the double, so that its values are the IR's. */
static void number_text(char *out, size_t len, double v, int digits, bk_math_lang lang)
{
	if (lang == BK_MATH_SYMPY) {
		snprintf(out, len, "%.17g", v);
		return;
	}
	if (digits > 0) {
		snprintf(out, len, "%.*g", digits, v);
		return;
	}
	float x = (float)v;
	int d = 1;
	for (; d <= 9; d++) {
		snprintf(out, len, "%.*g", d, (double)x);
		if (strtof(out, NULL) == x)
			break;
	}
	/* Plain decimals where a reader expects them (1000, not 1e+03; 0.00061):
	 * the same d significant digits, so the same float. */
	double m = fabs((double)x);
	if (m >= 1e-4 && m < 1e7 && strchr(out, 'e')) {
		int dec = d - 1 - (int)floor(log10(m));
		snprintf(out, len, "%.*f", dec > 0 ? dec : 0, (double)x);
	}
}

/* The precedence of a number as written: a leading minus, or "m × 10^e". */
static int number_prec(double v, int digits, bk_math_lang lang)
{
	char s[40];
	if (!isfinite(v))
		return signbit(v) ? P_NEG : P_ATOM;
	number_text(s, sizeof s, v, digits, lang);
	return s[0] == '-' ? P_NEG : strchr(s, 'e') && lang != BK_MATH_SYMPY ? P_MUL : P_ATOM;
}

static void put_number(printer *p, double v)
{
	static const char *const special[3][3] = {
		{"\\infty", "-\\infty", "\\mathrm{NaN}"},
		{"sp.oo", "-sp.oo", "sp.nan"},
		{"<mi>&#x221E;</mi>", "<mo>-</mo><mi>&#x221E;</mi>", "<mi>NaN</mi>"},
	};
	if (!isfinite(v)) {
		fputs(special[p->lang][isnan(v) ? 2 : v < 0 ? 1 : 0], p->o);
		return;
	}
	char s[40];
	number_text(s, sizeof s, v, p->digits, p->lang);
	if (p->lang == BK_MATH_SYMPY) {
		fputs(s, p->o);
		return;
	}
	char *m = s, *e = strchr(s, 'e');
	if (e)
		*e++ = '\0';
	if (*m == '-') {
		fputs(p->lang == BK_MATH_LATEX ? "-" : "<mo>-</mo>", p->o);
		m++;
	}
	if (p->lang == BK_MATH_LATEX)
		fputs(m, p->o);
	else
		fprintf(p->o, "<mn>%s</mn>", m);
	if (!e)
		return;
	int ex = atoi(e); /* "1.5e-05": 1.5 × 10^{-5} */
	if (p->lang == BK_MATH_LATEX)
		fprintf(p->o, " \\times 10^{%d}", ex);
	else
		fprintf(p->o, "<mo>&#xD7;</mo><msup><mn>10</mn><mrow>%s<mn>%d</mn></mrow></msup>",
		        ex < 0 ? "<mo>-</mo>" : "", abs(ex));
}

/* ---- leaves ------------------------------------------------------------------ */

static void put_input(printer *p, int slot)
{
	const char *name = bk_input_name((bk_input)slot);
	int sub = strcmp(name, "f0") == 0; /* f_0, as papers write it */
	int word = strlen(name) > 1 && !sub;
	if (p->lang == BK_MATH_SYMPY)
		fputs(name, p->o);
	else if (p->lang == BK_MATH_LATEX)
		fputs(sub ? "f_0" : word ? "" : name, p->o);
	else
		fprintf(p->o, sub ? "<msub><mi>f</mi><mn>0</mn></msub>" : "<mi>%s</mi>", name);
	if (p->lang == BK_MATH_LATEX && word)
		fprintf(p->o, "\\mathrm{%s}", name);
}

static void put_param(printer *p, int slot)
{
	if (p->params && p->lang != BK_MATH_SYMPY)
		put_number(p, p->params[slot]);
	else if (p->lang == BK_MATH_SYMPY)
		fprintf(p->o, "p%d", slot);
	else if (p->lang == BK_MATH_LATEX)
		fprintf(p->o, "p_{%d}", slot);
	else
		fprintf(p->o, "<msub><mi>p</mi><mn>%d</mn></msub>", slot);
}

/* ---- precedence -------------------------------------------------------------- */

static int prec_of(const printer *p, int i)
{
	const bk_instr *in = &p->code[i];
	int sym = p->lang == BK_MATH_SYMPY;
	switch (in->op) {
	case BK_OP_CONST:
		return number_prec(in->k, p->digits, p->lang);
	case BK_OP_PARAM:
		return p->params && !sym ? number_prec(p->params[in->slot], p->digits, p->lang) : P_ATOM;
	case BK_OP_ADD: case BK_OP_SUB: case BK_OP_MAD: return P_ADD;
	case BK_OP_MIX: return sym ? P_ADD : P_ATOM;
	case BK_OP_MUL: return P_MUL;
	case BK_OP_DIV: case BK_OP_RCP: case BK_OP_RSQRT: return sym ? P_MUL : P_ATOM;
	case BK_OP_NEG: return P_NEG;
	case BK_OP_POW: case BK_OP_EXP2: return P_POW;
	case BK_OP_EXP: return sym ? P_ATOM : P_POW;
	default: return P_ATOM;
	}
}

static int is_number(const printer *p, int i)
{
	const bk_instr *in = &p->code[i];
	return in->op == BK_OP_CONST || (in->op == BK_OP_PARAM && p->params && p->lang != BK_MATH_SYMPY);
}

/* The factor of a product (MUL, MAD's a b) written first: a number before
 * the rest (4·LoH, as papers write it; the product commutes), else a. */
/* The factors of a product written as one: the operands of nested MULs
 * (not MAD), the numbers first (4·LoH, as papers write it), each other
 * factor in its order; the product commutes, so this is a display choice.
 * Into f (cap entries: a deeper chain stays nested); returns the count. */
enum { FACTORS = 32 };
static int gather(const printer *p, int i, int *f, int n)
{
	const bk_instr *in = &p->code[i];
	if (in->op == BK_OP_MUL && n + 2 <= FACTORS) {
		n = gather(p, in->a, f, n);
		return gather(p, in->b, f, n);
	}
	f[n] = i;
	return n + 1;
}

static int factors(const printer *p, int a, int b, int *f)
{
	int g[FACTORS], n = gather(p, b, g, gather(p, a, g, 0)), k = 0;
	for (int pass = 0; pass < 2; pass++)
		for (int j = 0; j < n; j++)
			if (is_number(p, g[j]) == !pass)
				f[k++] = g[j];
	return k;
}

static int factor_first(const printer *p, const bk_instr *in)
{
	int f[FACTORS];
	factors(p, in->a, in->b, f);
	return f[0];
}

/* 1 if register i is written with a leading minus. */
static int leads_minus(const printer *p, int i)
{
	const bk_instr *in = &p->code[i];
	switch (in->op) {
	case BK_OP_NEG: return 1;
	case BK_OP_CONST: return signbit(in->k) != 0;
	case BK_OP_PARAM: return p->params && p->lang != BK_MATH_SYMPY && signbit(p->params[in->slot]);
	case BK_OP_ADD: case BK_OP_SUB: return leads_minus(p, in->a);
	case BK_OP_MUL: case BK_OP_MAD: return leads_minus(p, factor_first(p, in));
	case BK_OP_MIX: return p->lang == BK_MATH_SYMPY && leads_minus(p, in->a);
	case BK_OP_POW: return 0; /* a minus base is wrapped */
	default: return 0;
	}
}

/* ---- tokens ------------------------------------------------------------------ */

static void open_paren(printer *p)
{
	fputs(p->lang == BK_MATH_LATEX ? "\\left(" : p->lang == BK_MATH_SYMPY ? "(" : "<mrow><mo>(</mo>", p->o);
}

static void close_paren(printer *p)
{
	fputs(p->lang == BK_MATH_LATEX ? "\\right)" : p->lang == BK_MATH_SYMPY ? ")" : "<mo>)</mo></mrow>", p->o);
}

/* An infix operator: '+', '-', '*' (LaTeX \cdot, MathML U+22C5), '/'. */
static void put_op(printer *p, char op)
{
	if (p->lang == BK_MATH_MATHML) {
		fprintf(p->o, "<mo>%s</mo>", op == '*' ? "&#x22C5;" : op == '-' ? "-" : op == '+' ? "+" : "/");
		return;
	}
	if (op == '*')
		fputs(p->lang == BK_MATH_LATEX ? " \\cdot " : "*", p->o);
	else
		fprintf(p->o, " %c ", op);
}

static void node(printer *p, int i);

/* Register i where at least precedence need is required, wrapped if lower,
 * or if it leads with a minus and minus_ok is 0. */
static void operand(printer *p, int i, int need, int minus_ok)
{
	if (prec_of(p, i) < need || (!minus_ok && leads_minus(p, i))) {
		open_paren(p);
		node(p, i);
		close_paren(p);
	} else {
		node(p, i);
	}
}

/* A group: LaTeX braces, MathML mrow, nothing in SymPy. */
static void group_open(printer *p)
{
	fputs(p->lang == BK_MATH_LATEX ? "{" : p->lang == BK_MATH_MATHML ? "<mrow>" : "", p->o);
}

static void group_close(printer *p)
{
	fputs(p->lang == BK_MATH_LATEX ? "}" : p->lang == BK_MATH_MATHML ? "</mrow>" : "", p->o);
}

/* A function applied to its operands: "\max\left(a, b\right)", "sp.Max(a, b)",
 * "<mi>max</mi><mo>(</mo>...". */
static void call(printer *p, const char *latex, const char *sympy, const char *mathml, const int *args, int n)
{
	if (p->lang == BK_MATH_LATEX)
		fputs(latex, p->o);
	else if (p->lang == BK_MATH_SYMPY)
		fputs(sympy, p->o);
	else
		fprintf(p->o, "<mrow><mi>%s</mi>", mathml);
	fputs(p->lang == BK_MATH_LATEX ? "\\left(" : p->lang == BK_MATH_SYMPY ? "(" : "<mo>(</mo>", p->o);
	for (int k = 0; k < n; k++) {
		if (k)
			fputs(p->lang == BK_MATH_MATHML ? "<mo>,</mo>" : ", ", p->o);
		node(p, args[k]);
	}
	fputs(p->lang == BK_MATH_LATEX ? "\\right)" : p->lang == BK_MATH_SYMPY ? ")" : "<mo>)</mo></mrow>", p->o);
}

/* A fraction: \frac{a}{b} or mfrac (SymPy: a/b, the divisor wrapped unless
 * an atom or power). num < 0: the numerator is 1. sq: the denominator is a
 * square root of den. */
static void fraction(printer *p, int num, int den, int sq)
{
	if (p->lang == BK_MATH_SYMPY) {
		if (num < 0)
			fputs("1", p->o);
		else
			operand(p, num, P_MUL, 1);
		fputs("/", p->o);
		if (sq) {
			fputs("sp.sqrt(", p->o);
			node(p, den);
			fputs(")", p->o);
		} else {
			operand(p, den, P_POW, 0);
		}
		return;
	}
	fputs(p->lang == BK_MATH_LATEX ? "\\frac{" : "<mfrac><mrow>", p->o);
	if (num < 0)
		fputs(p->lang == BK_MATH_LATEX ? "1" : "<mn>1</mn>", p->o);
	else
		node(p, num);
	fputs(p->lang == BK_MATH_LATEX ? "}{" : "</mrow><mrow>", p->o);
	if (sq)
		fputs(p->lang == BK_MATH_LATEX ? "\\sqrt{" : "<msqrt>", p->o);
	node(p, den);
	if (sq)
		fputs(p->lang == BK_MATH_LATEX ? "}" : "</msqrt>", p->o);
	fputs(p->lang == BK_MATH_LATEX ? "}" : "</mrow></mfrac>", p->o);
}

/* base^exponent; base < 0: the base is the constant text lit ("2", "e"). */
static void power(printer *p, int base, const char *lit, int ex)
{
	if (p->lang == BK_MATH_MATHML)
		fputs("<msup>", p->o);
	if (base < 0)
		fprintf(p->o, p->lang == BK_MATH_MATHML ? "<m%s>%s</m%s>" : "%.0s%s", *lit == 'e' ? "i" : "n", lit,
		        *lit == 'e' ? "i" : "n");
	else
		operand(p, base, P_ATOM, 0);
	if (p->lang == BK_MATH_SYMPY) {
		fputs("**", p->o);
		operand(p, ex, P_ATOM, 0);
		return;
	}
	fputs(p->lang == BK_MATH_LATEX ? "^" : "", p->o);
	group_open(p);
	node(p, ex);
	group_close(p);
	if (p->lang == BK_MATH_MATHML)
		fputs("</msup>", p->o);
}

static void infix(printer *p, int a, char op, int b, int prec)
{
	if (p->lang == BK_MATH_MATHML)
		fputs("<mrow>", p->o);
	operand(p, a, prec, 1);
	put_op(p, op);
	operand(p, b, op == '-' || op == '/' ? prec + 1 : prec, 0);
	if (p->lang == BK_MATH_MATHML)
		fputs("</mrow>", p->o);
}

/* mix(x, y, t) = x + (y - x) t, written out in SymPy (its meaning), by name
 * elsewhere (as the shader reads). */
static void mix(printer *p, const bk_instr *in)
{
	if (p->lang != BK_MATH_SYMPY) {
		call(p, "\\operatorname{mix}", "", "mix", (int[]){in->a, in->b, in->c}, 3);
		return;
	}
	operand(p, in->a, P_ADD, 1);
	fputs(" + (", p->o);
	operand(p, in->b, P_ADD, 1);
	fputs(" - ", p->o);
	operand(p, in->a, P_MUL, 0);
	fputs(")*", p->o);
	operand(p, in->c, P_POW, 0);
}

/* The value of a number (is_number). */
static double number_value(const printer *p, int i)
{
	const bk_instr *in = &p->code[i];
	return in->op == BK_OP_CONST ? in->k : p->params[in->slot];
}

/* a b of MUL or MAD as factors() orders them, a factor repeated (the same
 * register: a shared subexpression) written once as a power: LoH^2. */
static void product(printer *p, const bk_instr *in)
{
	int f[FACTORS], n = factors(p, in->a, in->b, f), done[FACTORS] = {0};
	if (p->lang == BK_MATH_MATHML)
		fputs("<mrow>", p->o);
	for (int j = 0, first = 1; j < n; j++) {
		if (done[j])
			continue;
		int times = 0;
		for (int k = j; k < n; k++)
			if (f[k] == f[j])
				times += done[k] = 1;
		if (!first)
			put_op(p, '*');
		if (times == 1) {
			operand(p, f[j], P_MUL, first);
		} else {
			if (p->lang == BK_MATH_MATHML)
				fputs("<msup>", p->o);
			operand(p, f[j], P_ATOM, 0);
			fprintf(p->o, p->lang == BK_MATH_LATEX ? "^{%d}" : p->lang == BK_MATH_SYMPY ? "**%d" : "<mn>%d</mn></msup>",
			        times);
		}
		first = 0;
	}
	if (p->lang == BK_MATH_MATHML)
		fputs("</mrow>", p->o);
}

/* "+ b", or "- 0.5" for a negative number b (not "+ (-0.5)"). */
static void plus(printer *p, int b)
{
	if (is_number(p, b) && number_value(p, b) < 0) {
		put_op(p, '-');
		put_number(p, -number_value(p, b));
	} else {
		put_op(p, '+');
		operand(p, b, P_ADD, 0);
	}
}

static void node(printer *p, int i)
{
	const bk_instr *in = &p->code[i];
	int a = in->a, b = in->b, c = in->c;
	switch (in->op) {
	case BK_OP_CONST: put_number(p, in->k); break;
	case BK_OP_INPUT: put_input(p, in->slot); break;
	case BK_OP_PARAM: put_param(p, in->slot); break;
	case BK_OP_ADD:
		if (p->lang == BK_MATH_MATHML)
			fputs("<mrow>", p->o);
		operand(p, a, P_ADD, 1);
		plus(p, b);
		if (p->lang == BK_MATH_MATHML)
			fputs("</mrow>", p->o);
		break;
	case BK_OP_SUB: infix(p, a, '-', b, P_ADD); break;
	case BK_OP_MUL: product(p, in); break;
	case BK_OP_DIV:
		if (p->lang == BK_MATH_SYMPY)
			infix(p, a, '/', b, P_MUL);
		else
			fraction(p, a, b, 0);
		break;
	case BK_OP_RCP: fraction(p, -1, a, 0); break;
	case BK_OP_RSQRT: fraction(p, -1, a, 1); break;
	case BK_OP_NEG:
		if (p->lang == BK_MATH_MATHML)
			fputs("<mrow><mo>-</mo>", p->o);
		else
			fputs("-", p->o);
		operand(p, a, P_MUL, 0);
		if (p->lang == BK_MATH_MATHML)
			fputs("</mrow>", p->o);
		break;
	case BK_OP_MAD: /* a b + c */
		if (p->lang == BK_MATH_MATHML)
			fputs("<mrow>", p->o);
		product(p, in);
		plus(p, c);
		if (p->lang == BK_MATH_MATHML)
			fputs("</mrow>", p->o);
		break;
	case BK_OP_POW: power(p, a, NULL, b); break;
	case BK_OP_EXP2: power(p, -1, "2", a); break;
	case BK_OP_EXP:
		if (p->lang == BK_MATH_SYMPY)
			call(p, "", "sp.exp", "", &a, 1);
		else
			power(p, -1, "e", a);
		break;
	case BK_OP_SQRT:
		if (p->lang == BK_MATH_SYMPY) {
			call(p, "", "sp.sqrt", "", &a, 1);
		} else {
			fputs(p->lang == BK_MATH_LATEX ? "\\sqrt{" : "<msqrt>", p->o);
			node(p, a);
			fputs(p->lang == BK_MATH_LATEX ? "}" : "</msqrt>", p->o);
		}
		break;
	case BK_OP_LOG: call(p, "\\ln", "sp.log", "ln", &a, 1); break;
	case BK_OP_LOG2:
		if (p->lang == BK_MATH_SYMPY) {
			fputs("sp.log(", p->o);
			node(p, a);
			fputs(", 2)", p->o);
		} else if (p->lang == BK_MATH_LATEX) {
			call(p, "\\log_2", "", "", &a, 1);
		} else {
			fputs("<mrow><msub><mi>log</mi><mn>2</mn></msub><mo>(</mo>", p->o);
			node(p, a);
			fputs("<mo>)</mo></mrow>", p->o);
		}
		break;
	case BK_OP_MIN: call(p, "\\min", "sp.Min", "min", (int[]){a, b}, 2); break;
	case BK_OP_MAX: call(p, "\\max", "sp.Max", "max", (int[]){a, b}, 2); break;
	case BK_OP_CLAMP:
		if (p->lang == BK_MATH_SYMPY) { /* min(max(x, lo), hi), as the IR (also for lo > hi) */
			fputs("sp.Min(sp.Max(", p->o);
			node(p, a);
			fputs(", ", p->o);
			node(p, b);
			fputs("), ", p->o);
			node(p, c);
			fputs(")", p->o);
		} else {
			call(p, "\\operatorname{clamp}", "", "clamp", (int[]){a, b, c}, 3);
		}
		break;
	case BK_OP_SATURATE:
		if (p->lang == BK_MATH_SYMPY) {
			fputs("sp.Min(sp.Max(", p->o);
			node(p, a);
			fputs(", 0), 1)", p->o);
		} else {
			call(p, "\\operatorname{saturate}", "", "saturate", &a, 1);
		}
		break;
	case BK_OP_MIX: mix(p, in); break;
	case BK_OP_ABS:
		if (p->lang == BK_MATH_SYMPY) {
			call(p, "", "sp.Abs", "", &a, 1);
		} else {
			fputs(p->lang == BK_MATH_LATEX ? "\\left|" : "<mrow><mo>|</mo>", p->o);
			node(p, a);
			fputs(p->lang == BK_MATH_LATEX ? "\\right|" : "<mo>|</mo></mrow>", p->o);
		}
		break;
	default: break; /* BK_OP_COUNT: not an instruction */
	}
}

/* ---- entry points ------------------------------------------------------------ */

/* Runs body into a malloc'd string; NULL when out of memory. */
static char *print(const bk_form *f, bk_math_lang lang, const double *params, int digits,
                   void (*body)(printer *, const void *), const void *ctx)
{
	if (!f || (unsigned)lang > BK_MATH_MATHML)
		return NULL;
	char *s = NULL;
	size_t len = 0;
	FILE *o = open_memstream(&s, &len);
	if (!o)
		return NULL;
	int out;
	printer p = {o, bk_form_code(f, NULL, &out), lang, params, digits, 0};
	body(&p, ctx ? ctx : &out);
	if (ferror(o) || p.failed) {
		fclose(o);
		free(s);
		return NULL;
	}
	if (fclose(o)) {
		free(s);
		return NULL;
	}
	return s;
}

static void expression(printer *p, const void *out)
{
	if (p->lang == BK_MATH_MATHML)
		fputs("<math><mrow>", p->o);
	node(p, *(const int *)out);
	if (p->lang == BK_MATH_MATHML)
		fputs("</mrow></math>", p->o);
}

char *bk_form_math(const bk_form *f, bk_math_lang lang, const double *params, int digits)
{
	return print(f, lang, params, digits, expression, NULL);
}

/* Caller text in a line comment: bk_comment_text's rule, each line break
 * opening a new comment line with lead ("% ", "# "). */
static void comment(printer *p, const char *lead, const char *label, const char *s)
{
	FILE *o = p->o;
	char nl[8];
	snprintf(nl, sizeof nl, "\n%s  ", lead);
	size_t n = bk_comment_text(NULL, 0, s, nl);
	char *buf = malloc(n + 1);
	if (!buf) {
		p->failed = 1;
		return;
	}
	bk_comment_text(buf, n + 1, s, nl);
	fprintf(o, "%s%s: %s\n", lead, label, buf);
	free(buf);
}

typedef struct doc {
	const bk_form *f;
	const bk_emit_info *info;
	const double *params;
} doc;

static void header(printer *p, const char *lead, const doc *d)
{
	FILE *o = p->o;
	const bk_emit_info *in = d->info;
	fprintf(o, "%sGenerated by brdfkit " BK_VERSION " — DO NOT EDIT (regenerate it instead).\n", lead);
	if (in->command)
		comment(p, lead, "command", in->command);
	comment(p, lead, "form", bk_form_text(d->f));
	comment(p, lead, "source", in->source ? in->source : "not given");
	comment(p, lead, "conventions", in->conventions ? in->conventions : "not given");
	comment(p, lead, "fitted domain", in->domain ? in->domain : "not fitted");
	comment(p, lead, "fitted error", in->error ? in->error : "unknown");
	for (int k = 0; k < bk_form_nparams(d->f); k++)
		fprintf(o, "%s  p%d = %.17g\n", lead, k, d->params[k]);
}

/* The symbols of the inputs the form reads, in bk_input order. */
static void input_list(FILE *o, const bk_form *f, const char *sep)
{
	const char *s = "";
	for (int i = 0; i < BK_IN_COUNT; i++)
		if (bk_form_inputs(f) >> i & 1) {
			fprintf(o, "%s%s", s, bk_input_name((bk_input)i));
			s = sep;
		}
}

/* \mathrm{name}, each of LaTeX's specials escaped (a checked identifier has
 * only '_', but the rule holds for any text). */
static void latex_name(FILE *o, const char *name)
{
	fputs("\\mathrm{", o);
	for (const char *s = name; *s; s++) {
		if (strchr("_%$#&{}", *s))
			fprintf(o, "\\%c", *s);
		else if (strchr("\\^~", *s) || (unsigned char)*s < ' ')
			fputs("?", o);
		else
			fputc(*s, o);
	}
	fputs("}", o);
}

static void latex_doc(printer *p, const void *ctx)
{
	const doc *d = ctx;
	int out;
	bk_form_code(d->f, NULL, &out);
	header(p, "% ", d);
	if (bk_form_nparams(d->f) > 0) { /* for a paper that tabulates its constants */
		fputs("% with the constants as symbols (p_k = the pk above):\n% ", p->o);
		const double *values = p->params;
		p->params = NULL;
		node(p, out);
		p->params = values;
		fputs("\n", p->o);
	}
	fputs("% constants: the fitted values as the generated shaders hold them (float)\n", p->o);
	fputs("\\begin{equation}\n", p->o);
	latex_name(p->o, d->info->name ? d->info->name : "brdfkit_form");
	fputs("\\left(", p->o);
	const char *sep = "";
	for (int i = 0; i < BK_IN_COUNT; i++)
		if (bk_form_inputs(d->f) >> i & 1) {
			fputs(sep, p->o);
			put_input(p, i);
			sep = ", ";
		}
	fputs("\\right) = ", p->o);
	node(p, out);
	fputs("\n\\end{equation}\n", p->o);
}

static void sympy_doc(printer *p, const void *ctx)
{
	const doc *d = ctx;
	FILE *o = p->o;
	int out, np = bk_form_nparams(d->f);
	bk_form_code(d->f, NULL, &out);
	header(p, "# ", d);
	fputs("# meanings (brdfkit's, brdf/ir_ops.h): pow(x, y) = exp2(y*log2(x)), written x**y, which it\n"
	      "#   equals for x > 0 (brdfkit has no value for x < 0, or x = 0 with y <= 0);\n"
	      "#   mix(x, y, t) = x + (y - x)*t; saturate(x) = Min(Max(x, 0), 1);\n"
	      "#   clamp(x, lo, hi) = Min(Max(x, lo), hi); rcp(x) = 1/x; rsqrt(x) = 1/sqrt(x)\n"
	      "import sympy as sp\n\n", o);
	if (bk_form_inputs(d->f)) { /* sp.symbols refuses an empty list */
		fputs("inputs = sp.symbols('", o);
		input_list(o, d->f, " ");
		fputs("', real=True, seq=True)\n", o);
		input_list(o, d->f, ", ");
		fputs(", = inputs\n", o);
	}
	fputs(bk_form_inputs(d->f) ? "inputs = tuple(inputs)\n" : "inputs = ()\n", o);
	if (np > 0) {
		fputs("p = sp.symbols('", o);
		for (int k = 0; k < np; k++)
			fprintf(o, "%sp%d", k ? " " : "", k);
		fputs("', real=True, seq=True)\n", o);
		for (int k = 0; k < np; k++)
			fprintf(o, "%sp%d", k ? ", " : "", k);
		fputs(", = p\n", o);
	}
	fputs("params = {", o);
	for (int k = 0; k < np; k++)
		fprintf(o, "%sp%d: sp.Float('%.17g', 17)", k ? ", " : "", k, d->params[k]);
	fputs("}\n", o);
	fputs("expr = ", o);
	node(p, out);
	fputs("\nfitted = expr.subs(params)\n", o);
}

char *bk_form_math_doc(const bk_form *f, bk_math_lang lang, const double *params, const bk_emit_info *info)
{
	static const bk_emit_info none;
	if (!f || (lang != BK_MATH_LATEX && lang != BK_MATH_SYMPY) || (bk_form_nparams(f) > 0 && !params))
		return NULL;
	doc d = {f, info ? info : &none, params};
	return print(f, lang, params, 0, lang == BK_MATH_LATEX ? latex_doc : sympy_doc, &d);
}
