/*
 * fuzz.c — forms drawn at random for tests/vk's differential run (see
 * sources.h): every op of the IR's language, nested up to four deep, over the
 * inputs, the inputs moved below zero (x - 1, x - 0.5: negative bases for pow
 * and the logs, negative zeros) and constants at the edges of the formats
 * (0, half's 65504 and past it, float's 3.4e38, half's subnormals). The
 * point is what make results' forms never do: an op outside its domain, an
 * overflow in half that a fused mad avoids, a NaN into min. A form the parser
 * refuses (a constant it folds to NaN, say) is drawn again; the draw is a
 * fixed xorshift, so a seed names the same corpus on every machine.
 */
#include "sources.h"

#include <stdio.h>
#include <string.h>

typedef struct rng {
	unsigned long long s;
} rng;

static unsigned pick(rng *g, unsigned n)
{
	g->s ^= g->s << 13;
	g->s ^= g->s >> 7;
	g->s ^= g->s << 17;
	return (unsigned)((g->s >> 11) % n);
}

static const char *const leaves[] = {
	"NoV", "NoL", "NoH", "LoH", "r", "a", "f0", "(NoV - 1)", "(LoH - 0.5)", "(r - 1)", "(-NoL)",
	"0", "1", "2", "0.5", "-1", "9", "2.5", "1e-5", "300", "65504", "70000", "3e38", "1e-7", "p0", "p1",
};
enum { NLEAF = sizeof leaves / sizeof leaves[0] };

static const char *const unary[] = {"sqrt", "rsqrt", "rcp", "exp", "exp2", "log", "log2", "saturate", "abs", "-"};
static const char *const binary[] = {"+", "-", "*", "/", "^", "pow", "min", "max"};
static const char *const powers[] = {"2", "3", "5", "9", "2.5", "-1.5", "0.5", "-3", "12"};

/* Appends a random expression of at most depth levels to b[*at..len). */
static void draw(rng *g, int depth, char *b, size_t len, size_t *at)
{
#define PUT(...) (*at += (size_t)snprintf(b + *at, *at < len ? len - *at : 0, __VA_ARGS__), *at = *at < len ? *at : len)
	unsigned kind = depth <= 0 ? 0 : pick(g, 10);
	if (kind < 3) {
		PUT("%s", leaves[pick(g, NLEAF)]);
	} else if (kind < 5) {
		const char *op = unary[pick(g, sizeof unary / sizeof unary[0])];
		PUT("%s(", op);
		draw(g, depth - 1, b, len, at);
		PUT(")");
	} else if (kind < 9) {
		const char *op = binary[pick(g, sizeof binary / sizeof binary[0])];
		int call = op[0] >= 'a' && op[0] <= 'z';
		PUT(call ? "%s(" : "(", op);
		draw(g, depth - 1, b, len, at);
		if (!strcmp(op, "^")) {
			PUT(")^%s", powers[pick(g, sizeof powers / sizeof powers[0])]);
			return;
		}
		PUT(call ? ", " : " %s ", op);
		draw(g, depth - 1, b, len, at);
		PUT(")");
	} else {
		int clamp = pick(g, 2);
		PUT("%s(", clamp ? "clamp" : "mix");
		draw(g, depth - 1, b, len, at);
		PUT(", ");
		draw(g, depth - 1, b, len, at);
		PUT(", ");
		draw(g, depth - 1, b, len, at);
		PUT(")");
	}
#undef PUT
}

/* 1 if codegen emits the form at all (analysis/cli/form_check.c): every
 * constant it computes is a finite float, it divides by no constant zero,
 * and it has a finite value somewhere on [0, 1]. */
static int emitted(const char *text, const double *params)
{
	bk_form_error fe;
	char what[200];
	bk_form *f = bk_form_parse(text, &fe);
	int ok = f && bk_form_nonfinite(f, params, what, sizeof what) == 0 &&
	         bk_form_nowhere_finite(f, params, NULL, 0) == 0;
	bk_form_free(f);
	return ok;
}

int vk_add_fuzz(vk_fns *fns, int n, unsigned long seed, char *err, size_t errlen)
{
	rng g = {seed * 0x9E3779B97F4A7C15ull + 1};
	static const double params[BK_MAX_PARAMS] = {0.75, -1.25};
	for (int k = 0, tries = 0; k < n; tries++) {
		char text[512], label[200], e[256];
		size_t at = 0;
		if (tries > 100 * n + 100) {
			snprintf(err, errlen, "fuzz: %d of %d forms after %d draws: the parser refuses the rest", k, n, tries);
			return -1;
		}
		draw(&g, 4, text, sizeof text, &at);
		if (at >= sizeof text - 1)
			continue;
		snprintf(label, sizeof label, "fuzz:%lu:%d %.160s", seed, k, text);
		if (!emitted(text, params))
			continue; /* a form codegen refuses */
		if (vk_add_emitted(fns, label, text, params, 2, e, sizeof e))
			continue; /* a form the parser refuses: the grammar's business, not this test's */
		k++;
	}
	return 0;
}
