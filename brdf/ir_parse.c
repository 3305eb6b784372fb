/*
 * ir_parse.c — the formula language to instructions, in one pass (no tree):
 * each rule emits into the form as it recognises its input, as Lua's parser
 * drives its code generator. Errors accumulate on the parser, first one wins.
 */
#include "ir.h"
#include "ir_lex.h"
#include "ir_terms.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_DEPTH BK_FORM_MAX_DEPTH /* nesting of parentheses, calls and operators */
#define MAX_LOCALS 32
#define MAX_ARGS 8

typedef struct scope {
	const char *name[MAX_LOCALS]; /* into the term's params or body (static text) */
	size_t len[MAX_LOCALS];
	int reg[MAX_LOCALS];
	int n;
	const bk_ir_term *term;       /* NULL: the user's form */
} scope;

typedef struct parser {
	bk_lexer lx;
	bk_form *f;
	bk_form_error *err;
	int failed;
	int depth;
	int call_column; /* column of the outermost term call, for errors inside it */
	scope *sc;
} parser;

static const struct binop {
	char tok;
	int left, right; /* priorities: left > right is right-associative */
	bk_op op;
} binops[] = {
	{'+', 1, 1, BK_OP_ADD}, {'-', 1, 1, BK_OP_SUB},
	{'*', 2, 2, BK_OP_MUL}, {'/', 2, 2, BK_OP_DIV},
	{'^', 5, 4, BK_OP_POW},
};
#define UNARY_PRIORITY 3 /* between * and ^: -x^2 is -(x^2), 2*-x is 2*(-x) */

static const char *const input_names[BK_IN_COUNT] = {"NoV", "NoL", "NoH", "LoH", "r", "a", "f0"};

const char *bk_input_name(bk_input i) { return input_names[i]; }

/* The one place errors are formatted: "what near 'token'" and the token's
 * column (or the column of the term call when the error is inside a term's
 * definition, which only a broken table can cause). */
static int verror_at(parser *P, const bk_token *t, const char *fmt, va_list ap)
{
	if (P->failed)
		return -1;
	P->failed = 1;
	if (!P->err)
		return -1;
	char what[160];
	vsnprintf(what, sizeof what, fmt, ap);
	P->err->column = P->sc->term ? P->call_column : t->column;
	if (t->type == TK_EOF)
		snprintf(P->err->message, sizeof P->err->message, "%s at end of form", what);
	else
		snprintf(P->err->message, sizeof P->err->message, "%s near '%.*s'", what,
		         (int)(t->len > 24 ? 24 : t->len), P->lx.src + t->start);
	if (P->sc->term) {
		size_t k = strlen(P->err->message);
		snprintf(P->err->message + k, sizeof P->err->message - k, " (in the definition of %s)",
		         P->sc->term->name);
	}
	return -1;
}

static int error_at(parser *P, const bk_token *t, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static int error_at(parser *P, const bk_token *t, const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	verror_at(P, t, fmt, ap);
	va_end(ap);
	return -1;
}

/* An error at the current token. */
static int error(parser *P, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static int error(parser *P, const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	verror_at(P, &P->lx.tok, fmt, ap);
	va_end(ap);
	return -1;
}

/* A failed emit: the instruction limit, or malloc. */
static int check(parser *P, int reg)
{
	if (reg < 0 && !P->failed) {
		if (P->f->n >= BK_FORM_MAX_INSTR)
			return error(P, "form too large (more than %d instructions)", BK_FORM_MAX_INSTR);
		return error(P, "out of memory");
	}
	return reg;
}

static int expect(parser *P, int type, const char *what)
{
	if ((int)P->lx.tok.type != type)
		return error(P, "expected %s", what);
	bk_lex_next(&P->lx);
	return 0;
}

static int subexpr(parser *P, int limit);

/* x^n for a small integer n by squaring; x^-n = rcp(x^n). */
static int power(parser *P, int x, int y)
{
	const bk_instr *yi = &P->f->code[y];
	double k = yi->k;
	/* range first: converting an out-of-range double to int is undefined */
	if (yi->op != BK_OP_CONST || !(k >= -8 && k <= 8) || k != (int)k)
		return bk_ir_emit(P->f, BK_OP_POW, x, y, -1);
	int n = k < 0 ? -(int)k : (int)k;
	int acc = -1, sq = x;
	for (; n; n >>= 1) {
		if (n & 1)
			acc = acc < 0 ? sq : bk_ir_emit(P->f, BK_OP_MUL, acc, sq, -1);
		if (n > 1)
			sq = bk_ir_emit(P->f, BK_OP_MUL, sq, sq, -1);
	}
	if (acc < 0)
		return bk_ir_const(P->f, 1.0); /* x^0 */
	return k < 0 ? bk_ir_emit(P->f, BK_OP_RCP, acc, -1, -1) : acc;
}

static int binary(parser *P, bk_op op, int a, int b)
{
	return check(P, op == BK_OP_POW ? power(P, a, b) : bk_ir_emit(P->f, op, a, b, -1));
}

/* args := '(' [expr {',' expr}] ')' ; returns the count or -1 */
static int arguments(parser *P, int *args)
{
	int n = 0;
	if (expect(P, '(', "'('"))
		return -1;
	if (P->lx.tok.type != ')') {
		for (;;) {
			if (n == MAX_ARGS)
				return error(P, "too many arguments");
			if ((args[n++] = subexpr(P, 0)) < 0)
				return -1;
			if (P->lx.tok.type != ',')
				break;
			bk_lex_next(&P->lx);
		}
	}
	if (expect(P, ')', "')' or ','"))
		return -1;
	return n;
}

static int count_params(const char *list)
{
	if (!*list)
		return 0;
	int n = 1;
	for (; *list; list++)
		n += *list == ',';
	return n;
}

static int statements(parser *P);

/* A term call: its definition parsed with its arguments bound to registers. */
static int expand(parser *P, const bk_ir_term *t, const int *args, int nargs)
{
	scope sc = {.term = t, .n = nargs};
	const char *p = t->params;
	for (int i = 0; i < nargs; i++) {
		const char *e = strchr(p, ',');
		sc.name[i] = p;
		sc.len[i] = e ? (size_t)(e - p) : strlen(p);
		sc.reg[i] = args[i];
		p += sc.len[i] + (e != NULL);
	}
	bk_lexer saved = P->lx;
	scope *outer = P->sc;
	if (!outer->term)
		P->call_column = saved.tok.column;
	P->sc = &sc;
	P->lx = (bk_lexer){.src = t->body};
	bk_lex_next(&P->lx);
	int r = statements(P);
	P->lx = saved;
	P->sc = outer;
	return r;
}

static int lookup(const parser *P, const bk_token *t)
{
	const scope *sc = P->sc;
	for (int i = sc->n - 1; i >= 0; i--)
		if (sc->len[i] == t->len && strncmp(sc->name[i], P->lx.src + t->start, t->len) == 0)
			return sc->reg[i];
	return -1;
}

static const struct builtin {
	const char *name;
	bk_op op; /* BK_OP_COUNT: sq */
} builtins[] = {
	{"sqrt", BK_OP_SQRT}, {"rsqrt", BK_OP_RSQRT}, {"rcp", BK_OP_RCP}, {"exp", BK_OP_EXP},
	{"exp2", BK_OP_EXP2}, {"log", BK_OP_LOG}, {"log2", BK_OP_LOG2}, {"pow", BK_OP_POW},
	{"min", BK_OP_MIN}, {"max", BK_OP_MAX}, {"clamp", BK_OP_CLAMP}, {"saturate", BK_OP_SATURATE},
	{"mix", BK_OP_MIX}, {"abs", BK_OP_ABS}, {"sq", BK_OP_COUNT},
};

/* call := NAME args */
static int call(parser *P, bk_token name)
{
	const char *s = P->lx.src + name.start;
	int args[MAX_ARGS], n;
	for (size_t i = 0; i < sizeof builtins / sizeof builtins[0]; i++) {
		const struct builtin *b = &builtins[i];
		if (!bk_tok_is(&name, P->lx.src, b->name))
			continue;
		int want = b->op == BK_OP_COUNT ? 1 : bk_opinfo_table[b->op].arity;
		if ((n = arguments(P, args)) < 0)
			return -1;
		if (n != want)
			return error_at(P, &name, "'%s' takes %d argument%s, got %d", b->name, want, want == 1 ? "" : "s", n);
		if (b->op == BK_OP_COUNT)
			return check(P, bk_ir_emit(P->f, BK_OP_MUL, args[0], args[0], -1));
		if (b->op == BK_OP_POW)
			return binary(P, BK_OP_POW, args[0], args[1]);
		return check(P, bk_ir_emit(P->f, b->op, args[0], n > 1 ? args[1] : -1, n > 2 ? args[2] : -1));
	}
	const bk_ir_term *t = bk_ir_term_find(s, name.len);
	if (!t)
		return error_at(P, &name, "unknown function");
	if ((n = arguments(P, args)) < 0)
		return -1;
	int want = count_params(t->params);
	if (n != want)
		return error_at(P, &name, "'%s' takes %d argument%s (%s), got %d", t->name, want, want == 1 ? "" : "s",
		             t->params, n);
	return expand(P, t, args, n);
}

/* name := local | input | parameter ; in a term's definition only its own names */
static int name(parser *P, bk_token t)
{
	const char *s = P->lx.src + t.start;
	int r = lookup(P, &t);
	if (r >= 0)
		return r;
	if (P->sc->term)
		return error_at(P, &t, "unknown name");
	if (bk_tok_is(&t, P->lx.src, "VoH")) /* V·H = L·H for the half vector */
		return check(P, bk_ir_input(P->f, BK_IN_LOH));
	for (int i = 0; i < BK_IN_COUNT; i++)
		if (bk_tok_is(&t, P->lx.src, input_names[i]))
			return check(P, bk_ir_input(P->f, (bk_input)i));
	int k = bk_param_index(s, t.len);
	if (k >= 0)
		return check(P, bk_ir_param(P->f, k));
	if (t.len == 3 && s[0] == 'p' && s[1] > '0' && s[1] <= '9' && s[2] >= '0' && s[2] <= '9') /* p16..p99 */
		return error_at(P, &t, "parameter out of range (p0..p%d)", BK_MAX_PARAMS - 1);
	return error_at(P, &t, "unknown name (inputs: NoV NoL NoH LoH VoH r a f0; parameters p0..p%d)",
	                BK_MAX_PARAMS - 1);
}

/* Whether a number's digits before its exponent are not all zeros. */
static int nonzero_digits(const char *s, size_t len)
{
	for (size_t i = 0; i < len && s[i] != 'e' && s[i] != 'E'; i++)
		if (s[i] >= '1' && s[i] <= '9')
			return 1;
	return 0;
}

/* primary := NUMBER | NAME | NAME args | '(' expr ')' */
static int primary(parser *P)
{
	bk_token t = P->lx.tok;
	switch ((int)t.type) {
	case TK_NUMBER:
		/* the value typed or an error: never inf (1e999), never a silent 0 (1e-400) */
		if (!isfinite(t.num))
			return error(P, "number too large (overflows double)");
		if (t.num == 0.0 && nonzero_digits(P->lx.src + t.start, t.len))
			return error(P, "number too small (underflows to zero)");
		bk_lex_next(&P->lx);
		return check(P, bk_ir_const(P->f, t.num));
	case TK_IDENT:
		bk_lex_next(&P->lx);
		return P->lx.tok.type == '(' ? call(P, t) : name(P, t);
	case '(': {
		bk_lex_next(&P->lx);
		int r = subexpr(P, 0);
		if (r < 0 || expect(P, ')', "')'"))
			return -1;
		return r;
	}
	case TK_BAD:
		return error(P, "invalid character");
	default:
		return error(P, "expected a number, a name or '('");
	}
}

static const struct binop *find_binop(int tok)
{
	for (size_t i = 0; i < sizeof binops / sizeof binops[0]; i++)
		if (binops[i].tok == tok)
			return &binops[i];
	return NULL;
}

/* subexpr := ('-' subexpr | primary) { binop subexpr }, binops whose left
 * priority exceeds limit (precedence climbing, as Lua's subexpr). */
static int subexpr(parser *P, int limit)
{
	/* levels: the outermost expression is level 0, each parenthesis, call,
	 * operand of an operator or unary minus one deeper, so 200 nested
	 * parentheses are 200 levels (the README's limit) and pass */
	if (++P->depth > MAX_DEPTH + 1) {
		P->depth--;
		return error(P, "expression nested too deeply (more than %d levels)", MAX_DEPTH);
	}
	int r;
	if (P->lx.tok.type == '-') {
		bk_lex_next(&P->lx);
		r = subexpr(P, UNARY_PRIORITY);
		if (r >= 0)
			r = check(P, bk_ir_emit(P->f, BK_OP_NEG, r, -1, -1));
	} else {
		r = primary(P);
	}
	const struct binop *op;
	while (r >= 0 && (op = find_binop(P->lx.tok.type)) && op->left > limit) {
		bk_lex_next(&P->lx);
		int rhs = subexpr(P, op->right);
		r = rhs < 0 ? -1 : binary(P, op->op, r, rhs);
	}
	P->depth--;
	return r;
}

/* statements := { NAME '=' expr ';' } expr EOF   (locals: term definitions only) */
static int statements(parser *P)
{
	for (;;) {
		bk_lexer peek = P->lx;
		bk_lex_next(&peek);
		if (!P->sc->term || P->lx.tok.type != TK_IDENT || peek.tok.type != '=')
			break;
		scope *sc = P->sc;
		if (sc->n == MAX_LOCALS)
			return error(P, "too many locals");
		sc->name[sc->n] = P->lx.src + P->lx.tok.start;
		sc->len[sc->n] = P->lx.tok.len;
		P->lx = peek;
		bk_lex_next(&P->lx);
		int r = subexpr(P, 0);
		if (r < 0 || expect(P, ';', "';'"))
			return -1;
		sc->reg[sc->n++] = r;
	}
	int r = subexpr(P, 0);
	if (r >= 0 && P->lx.tok.type == TK_BAD)
		return error(P, "invalid character");
	if (r >= 0 && P->lx.tok.type != TK_EOF)
		return error(P, "expected an operator or the end of the form");
	return r;
}

bk_form *bk_form_parse(const char *text, bk_form_error *err)
{
	if (err)
		*err = (bk_form_error){0, ""};
	if (strlen(text) > BK_FORM_MAX_LEN) {
		if (err) {
			err->column = BK_FORM_MAX_LEN + 1;
			snprintf(err->message, sizeof err->message, "form longer than %d characters", BK_FORM_MAX_LEN);
		}
		return NULL;
	}
	bk_form *f = calloc(1, sizeof *f);
	if (!f || !(f->text = malloc(strlen(text) + 1))) {
		free(f);
		if (err)
			snprintf(err->message, sizeof err->message, "out of memory");
		return NULL;
	}
	strcpy(f->text, text);
	scope top = {0};
	parser P = {.f = f, .err = err, .sc = &top};
	P.lx.src = f->text;
	bk_lex_next(&P.lx);
	int out = statements(&P);
	if (out < 0 || bk_ir_finish(f, out) < 0) {
		check(&P, -1); /* finish fuses: a NEG it adds can meet the limit */
		bk_form_free(f);
		return NULL;
	}
	return f;
}

void bk_form_free(bk_form *f)
{
	if (!f)
		return;
	free(f->text);
	free(f->code);
	free(f->hash);
	free(f);
}

bk_form *bk_form_dup(const bk_form *f)
{
	bk_form *d = calloc(1, sizeof *d);
	size_t lt = strlen(f->text) + 1, lc = sizeof *f->code * (size_t)(f->n ? f->n : 1);
	if (!d || !(d->text = malloc(lt)) || !(d->code = malloc(lc))) {
		bk_form_free(d);
		return NULL;
	}
	memcpy(d->text, f->text, lt);
	memcpy(d->code, f->code, sizeof *f->code * (size_t)f->n);
	d->n = d->cap = f->n;
	d->out = f->out;
	d->nparams = f->nparams;
	d->inputs = f->inputs;
	d->params = f->params;
	return d; /* built: no hash (bk_ir_finish dropped it) */
}

const char *bk_form_text(const bk_form *f) { return f->text; }
int bk_form_nparams(const bk_form *f) { return f->nparams; }
unsigned bk_form_inputs(const bk_form *f) { return f->inputs; }
unsigned bk_form_params(const bk_form *f) { return f->params; }

int bk_param_index(const char *text, size_t len)
{
	if (len < 2 || len > 3 || text[0] != 'p')
		return -1;
	int k = 0;
	for (size_t i = 1; i < len; i++) {
		if (text[i] < '0' || text[i] > '9')
			return -1;
		k = 10 * k + (text[i] - '0');
	}
	if (text[1] == '0' && len > 2) /* "p01": no second name for p1 */
		return -1;
	return k < BK_MAX_PARAMS ? k : -1;
}
