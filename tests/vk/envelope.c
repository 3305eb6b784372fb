/*
 * envelope.c — interval evaluation of a form under the Vulkan specification's
 * precision rules (see envelope.h for the rules and where they come from).
 *
 * Every interval end is a value of the precision (or an infinity), so the
 * products of + - * are exact in double (two 24-bit significands fit in 53)
 * and a sum's rounding error is found exactly (Knuth's two-sum); rounding such
 * an exact result outward to the precision is then exact too.
 */
#include "envelope.h"

#include "half.h"
#include "ir.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* ---- the precision's floats ----------------------------------------------- */

typedef struct fmt {
	int p;           /* significant bits */
	int emin;        /* exponent of the smallest normal */
	double max;      /* largest finite value */
	double div_lo;   /* OpFDiv's 2.5 ULP hold for |divisor| in [div_lo, div_hi] */
	double div_hi;
	double exp_base; /* exp, exp2: exp_base + 2|x| ULP */
	double log_abs;  /* log, log2: absolute error inside [0.5, 2] */
} fmt;

static const fmt F32 = {24, -126, FLT_MAX, 0x1p-126, 0x1p126, 3, 0x1p-21};
static const fmt F16 = {11, -14, 65504, 0x1p-14, 0x1p14, 1, 0x1p-7};

static const fmt *fmt_of(bk_precision p)
{
	return p == BK_F16 ? &F16 : &F32;
}

/* The spacing of the precision's values around |v| (v finite). */
static double quantum(double v, const fmt *F)
{
	int e = v == 0 ? F->emin : ilogb(v);
	return ldexp(1, (e < F->emin ? F->emin : e) - F->p + 1);
}

double vk_ulp(double x, bk_precision prec)
{
	const fmt *F = fmt_of(prec);
	double ax = fabs(x);
	if (!(ax <= F->max))
		return ldexp(1, ilogb(F->max) - F->p + 1);
	double q = quantum(ax, F);
	/* at a power of two the enclosing pair is the one below it */
	if (ax >= ldexp(1, F->emin + 1) && ax == ldexp(1, ilogb(ax)))
		return q / 2;
	return q;
}

/* The largest value of the precision <= v, and the smallest >= v. */
static double fl_down(double v, const fmt *F)
{
	if (isinf(v) || isnan(v))
		return v;
	if (v > F->max)
		return F->max;
	if (v < -F->max)
		return -INFINITY;
	double q = quantum(v, F);
	return floor(v / q) * q;
}

static double fl_up(double v, const fmt *F)
{
	return -fl_down(-v, F);
}

/* The neighbours of a value d of the precision. */
static double fl_succ(double d, const fmt *F)
{
	return d < 0 ? -fl_down(nextafter(-d, 0), F) : fl_up(nextafter(d, INFINITY), F);
}

static double fl_pred(double d, const fmt *F)
{
	return -fl_succ(-d, F);
}

/* Outward rounding of an exact result known as s + err (err's sign only). */
static double down_exact(double s, double err, const fmt *F)
{
	double d = fl_down(s, F);
	return d == s && err < 0 ? fl_pred(d, F) : d;
}

static double up_exact(double s, double err, const fmt *F)
{
	double u = fl_up(s, F);
	return u == s && err > 0 ? fl_succ(u, F) : u;
}

/* ---- intervals ------------------------------------------------------------- */

static const vk_env ANY = {-INFINITY, INFINITY, VK_UNBOUNDED};
static const vk_env UNDEFINED = {-INFINITY, INFINITY, VK_UNDEFINED};

/* Of operands without bounds, the one that bounds least (undefined over unbounded). */
static vk_env worst(vk_env a, vk_env b)
{
	return a.any >= b.any ? (a.any ? a : b) : b;
}

/* The rules every result obeys: past the largest finite an infinity or the
 * largest finite is allowed; a denormal may be flushed to zero. */
static vk_env finish(vk_env e, const vk_rules *R, const fmt *F)
{
	if (e.any)
		return e;
	if (e.hi > F->max) { /* ends were rounded outward, so an end past max is inf */
		e.hi = INFINITY;
		e.lo = fmin(e.lo, F->max);
	}
	if (e.lo < -F->max) {
		e.lo = -INFINITY;
		e.hi = fmax(e.hi, -F->max);
	}
	double tiny = ldexp(1, F->emin);
	if (R->flush && e.lo < tiny && e.hi > -tiny) {
		e.lo = fmin(e.lo, 0);
		e.hi = fmax(e.hi, 0);
	}
	return e;
}

static vk_env point(double v, const vk_rules *R, const fmt *F)
{
	return finish((vk_env){v, v, 0}, R, F);
}

/* The value of a constant or parameter in the shader: the emitter's float
 * literal, in half rounded to nearest (tests/vk/glsl.c writes it exactly). */
static double literal(double k, bk_precision p)
{
	float x = (float)k;
	return p == BK_F16 ? bk_half_round_inline(x) : x;
}

/* The decimal value of that literal as written, which a compiler folds: in
 * f32 the fewest digits that read back as the float (brdf/ir_emit.c's rule),
 * in f16 the half itself (written exactly). */
static double decimal(double k, bk_precision p)
{
	float x = (float)k;
	if (p == BK_F16 || !isfinite(x))
		return literal(k, p);
	char num[32];
	for (int digits = 1; digits <= 9; digits++) {
		snprintf(num, sizeof num, "%.*g", digits, (double)x);
		if (strtof(num, NULL) == x)
			break;
	}
	return strtod(num, NULL);
}

/* e widened to hold either neighbour of a value folded in double. */
static vk_env with_folded(vk_env e, double v, const vk_rules *R, const fmt *F)
{
	if (e.any || isnan(v)) /* a literal statement without a value: 0.0/0.0 */
		return e.any ? e : UNDEFINED;
	return finish((vk_env){fmin(e.lo, fl_down(v, F)), fmax(e.hi, fl_up(v, F)), 0}, R, F);
}

static int is_literal(const bk_instr *c)
{
	return c->op == BK_OP_CONST || c->op == BK_OP_PARAM;
}

/* Correctly rounded +, -: the exact result's outward rounding over the corners. */
static vk_env add(vk_env a, vk_env b, const vk_rules *R, const fmt *F)
{
	if (a.any || b.any)
		return worst(a, b);
	if ((a.hi == INFINITY && b.lo == -INFINITY) || (a.lo == -INFINITY && b.hi == INFINITY))
		return ANY; /* inf - inf is a value the operands may take: NaN (IEEE, so kinds still compare) */
	double lo = a.lo + b.lo, hi = a.hi + b.hi;
	double elo = 0, ehi = 0;
	if (isfinite(lo)) { /* two-sum: lo + elo is exact */
		double bb = lo - a.lo;
		elo = (a.lo - (lo - bb)) + (b.lo - bb);
	}
	if (isfinite(hi)) {
		double bb = hi - a.hi;
		ehi = (a.hi - (hi - bb)) + (b.hi - bb);
	}
	return finish((vk_env){down_exact(lo, elo, F), up_exact(hi, ehi, F), 0}, R, F);
}

static vk_env neg(vk_env a)
{
	return a.any ? a : (vk_env){-a.hi, -a.lo, 0};
}

static int has_zero(vk_env a)
{
	return a.lo <= 0 && a.hi >= 0;
}

static int has_inf(vk_env a)
{
	return isinf(a.lo) || isinf(a.hi);
}

static vk_env mul(vk_env a, vk_env b, const vk_rules *R, const fmt *F)
{
	if (a.any || b.any)
		return worst(a, b);
	if ((has_zero(a) && has_inf(b)) || (has_inf(a) && has_zero(b)))
		return ANY; /* 0 * inf is a value the operands may take: NaN */
	double c[4] = {a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi}, lo = INFINITY, hi = -INFINITY;
	for (int i = 0; i < 4; i++) {
		if (isnan(c[i]))
			return ANY; /* 0 * inf */
		lo = fmin(lo, c[i]);
		hi = fmax(hi, c[i]);
	}
	/* exact: the operands carry at most 24 significant bits each */
	return finish((vk_env){fl_down(lo, F), fl_up(hi, F), 0}, R, F);
}

/* The smallest value an operation with a k-ULP bound may return for an exact
 * result in [xl, xh]: x - k ulp(x) is smallest at xl, or just past the first
 * power of two above xl, where the ulp doubles. */
static double k_ulp_low(double xl, double xh, double k, const fmt *F, bk_precision prec)
{
	if (isinf(xl))
		return xl;
	double lo = xl - k * vk_ulp(xl, prec);
	if (xl > 0) {
		double b = ldexp(1, ilogb(xl) + 1);
		if (b <= xh)
			lo = fmin(lo, b - k * quantum(b, F));
	}
	return lo;
}

/* An end computed by libm in double, pushed outward past its error (< 2^-52
 * relative) unless it is known exact: next to a power of two the spec's ulp
 * doubles, so an exact result must not be nudged across it. */
static double nudge(double x, int exact, int up)
{
	return exact ? x : up ? x + fabs(x) * 0x1p-50 : x - fabs(x) * 0x1p-50;
}

/* The exact results' range [xl, xh] widened by k ULP, then the values of the
 * precision inside. */
static vk_env widen(double xl, double xh, int exact, double k, const vk_rules *R, const fmt *F)
{
	xl = nudge(xl, exact, 0);
	xh = nudge(xh, exact, 1);
	double lo = k_ulp_low(xl, xh, k, F, R->prec), hi = -k_ulp_low(-xh, -xl, k, F, R->prec);
	/* the values of the precision inside, an end past max staying past it */
	lo = lo < -F->max ? lo : fl_up(lo, F);
	hi = hi > F->max ? hi : fl_down(hi, F);
	return finish((vk_env){lo, hi, 0}, R, F);
}

/* OpFDiv: 2.5 ULP while the divisor's magnitude is in the bounded range. */
static vk_env divide(vk_env a, vk_env b, const vk_rules *R, const fmt *F)
{
	if (a.any || b.any)
		return worst(a, b);
	if (has_zero(b)) /* x/0 is an infinity, 0/0 has no value */
		return has_zero(a) ? UNDEFINED : ANY;
	double mlo = fmin(fabs(b.lo), fabs(b.hi)), mhi = fmax(fabs(b.lo), fabs(b.hi));
	if (mlo < F->div_lo || mhi > F->div_hi)
		return ANY;
	double n[4] = {a.lo, a.lo, a.hi, a.hi}, d[4] = {b.lo, b.hi, b.lo, b.hi}, lo = INFINITY, hi = -INFINITY;
	int exact = 1;
	for (int i = 0; i < 4; i++) {
		double q = n[i] / d[i];
		exact = exact && isfinite(q) && fma(-q, d[i], n[i]) == 0; /* the remainder */
		lo = fmin(lo, q);
		hi = fmax(hi, q);
	}
	return widen(lo, hi, exact, 2.5, R, F);
}

/* inversesqrt: 2 ULP; +0 (or a flushed denormal) gives +inf. */
static vk_env rsqrt(vk_env a, const vk_rules *R, const fmt *F)
{
	if (a.any || a.lo < 0)
		return a.any ? a : UNDEFINED;
	if (a.hi == 0 || (a.lo == 0 && signbit(a.lo))) /* 1/sqrt(+-0) = +-inf (IEEE): the sign of a
	                                                * zero the intervals do not keep; kinds alone */
		return ANY;
	vk_env e = widen(1 / sqrt(a.hi), a.lo > 0 ? 1 / sqrt(a.lo) : INFINITY, 0, 2, R, F);
	if (a.lo < ldexp(1, F->emin))
		e.hi = INFINITY;
	return e;
}

/* sqrt: inherited from 1.0 / inversesqrt(); sqrt(+0) = +0 (IEEE), and a
 * denormal flushed to zero gives 0. */
static vk_env root(vk_env a, const vk_rules *R, const fmt *F)
{
	if (a.any || a.lo < 0)
		return a.any ? a : UNDEFINED;
	double tiny = ldexp(1, F->emin);
	if (a.hi < tiny) /* zero or a denormal: 0 up to sqrt(hi), rounded loosely */
		return finish((vk_env){0, fl_up(sqrt(a.hi) * (1 + 0x1p-20), F), 0}, R, F);
	vk_env part = a;
	part.lo = fmax(part.lo, tiny);
	vk_env e = divide(point(1, R, F), rsqrt(part, R, F), R, F);
	if (!e.any && a.lo < tiny)
		e.lo = fmin(e.lo, 0);
	return e;
}

/* exp2 (base 2) or exp (base e): exp_base + 2|x| ULP of the result. */
static vk_env expo(vk_env a, int base2, const vk_rules *R, const fmt *F)
{
	if (a.any)
		return a;
	double k = F->exp_base + 2 * fmax(fabs(a.lo), fabs(a.hi)) + R->exp_slack;
	if (!isfinite(k)) /* an argument reaching an infinity: no ULP bound, any of [0, inf] */
		return finish((vk_env){0, INFINITY, 0}, R, F);
	double lo = base2 ? exp2(a.lo) : exp(a.lo), hi = base2 ? exp2(a.hi) : exp(a.hi);
	/* exact: 2 to an integer power, e^0 */
	int exact = base2 ? a.lo == floor(a.lo) && a.hi == floor(a.hi) : a.lo == 0 && a.hi == 0;
	return widen(lo, hi, exact, k, R, F);
}

/* log2 (base 2) or log (base e): 3 ULP outside [0.5, 2], an absolute error
 * inside; log(+0) = -inf (IEEE), and a flushed denormal gives it too. */
static vk_env loga(vk_env a, int base2, const vk_rules *R, const fmt *F)
{
	if (a.any || a.lo < 0)
		return a.any ? a : UNDEFINED;
	if (a.hi == 0)
		return point(-INFINITY, R, F);
	double lo = a.lo > 0 ? (base2 ? log2(a.lo) : log(a.lo)) : -INFINITY;
	double hi = base2 ? log2(a.hi) : log(a.hi);
	int m;
	/* exact: log2 of a power of two, log(1) */
	int exact = base2 ? frexp(a.lo, &m) == 0.5 && frexp(a.hi, &m) == 0.5 : a.lo == 1 && a.hi == 1;
	vk_env e = widen(lo, hi, exact, 3, R, F);
	if (!e.any && a.lo <= 2 && a.hi >= 0.5) { /* the absolute bound, the floats inside */
		e.lo = fmin(e.lo, fl_up(nudge(lo, exact, 0) - F->log_abs, F));
		e.hi = fmax(e.hi, fl_down(nudge(hi, exact, 1) + F->log_abs, F));
	}
	if (!e.any && a.lo < ldexp(1, F->emin))
		e.lo = -INFINITY;
	return e;
}

/* pow(x, y): inherited from exp2(y * log2(x)); undefined for x < 0, and for
 * x = 0 with y <= 0. */
static vk_env power(vk_env x, vk_env y, const vk_rules *R, const fmt *F)
{
	if (x.any || y.any)
		return worst(x, y);
	if (x.lo < 0 || (x.lo <= 0 && y.lo <= 0))
		return UNDEFINED;
	return expo(mul(y, loga(x, 1, R, F), R, F), 1, R, F);
}

/* min, max: exact. A NaN operand is never in a bounded envelope. */
static vk_env minimum(vk_env a, vk_env b)
{
	if (a.any || b.any)
		return worst(a, b);
	return (vk_env){fmin(a.lo, b.lo), fmin(a.hi, b.hi), 0};
}

static vk_env maximum(vk_env a, vk_env b)
{
	if (a.any || b.any)
		return worst(a, b);
	return (vk_env){fmax(a.lo, b.lo), fmax(a.hi, b.hi), 0};
}

/* x + (y - x) * t, op by op: the IR's formula, and the emitter's spelling;
 * folded: (y - x) as a compiler folds it, NAN where x or y is no literal. */
static vk_env lerp(vk_env x, vk_env y, vk_env t, double folded, const vk_rules *R, const fmt *F)
{
	vk_env d = add(y, neg(x), R, F);
	if (R->fold && !isnan(folded))
		d = with_folded(d, folded, R, F);
	return add(x, mul(d, t, R, F), R, F);
}

/* GLSL mix(x, y, t): inherited from x * (1 - t) + y * t or an equivalent
 * formula (here also x + (y - x) * t): within E of the exact value, E the
 * farthest either formula's envelope lies from it. The exact value is
 * multilinear in x, y, t, so its range over the operands' box is spanned by
 * the eight corners (long double: exact far beyond the precision's ulp). */
static vk_env mix(vk_env x, vk_env y, vk_env t, double folded, const vk_rules *R, const fmt *F)
{
	if (!R->mix_builtin)
		return lerp(x, y, t, folded, R, F);
	vk_env d = add(mul(x, add(point(1, R, F), neg(t), R, F), R, F), mul(y, t, R, F), R, F);
	vk_env l = lerp(x, y, t, NAN, R, F);
	/* where a formula can make a NaN the specification lets mix() return
	 * anything; unbounded, not undefined, here: the kinds still compare, as
	 * the IR must say what the emitted code computes (issue 21) */
	if (d.any || l.any)
		return worst(d, l).any == VK_UNDEFINED ? UNDEFINED : ANY;
	long double clo = INFINITY, chi = -INFINITY;
	for (int c = 0; c < 8; c++) {
		long double X = c & 1 ? x.hi : x.lo, Y = c & 2 ? y.hi : y.lo, T = c & 4 ? t.hi : t.lo;
		long double v = X + (Y - X) * T;
		if (isnan(v))
			return ANY; /* NaN */
		clo = fminl(clo, v);
		chi = fmaxl(chi, v);
	}
	double flo = fmin(d.lo, l.lo), fhi = fmax(d.hi, l.hi);
	double e = (double)fmaxl(chi - flo, fhi - clo);
	double lo = (double)clo - e, hi = (double)chi + e;
	lo -= fabs(lo) * 0x1p-50;
	hi += fabs(hi) * 0x1p-50;
	return finish((vk_env){fl_down(lo, F), fl_up(hi, F), 0}, R, F);
}

/* dec: the decimal values of literal registers (NAN for any other). */
static vk_env apply(const bk_instr *c, const vk_env *r, const double *dec, const double *in, const double *params,
                    const vk_rules *R, const fmt *F)
{
	int ar = bk_opinfo_table[c->op].arity;
	vk_env A = ar > 0 ? r[c->a] : ANY, B = ar > 1 ? r[c->b] : ANY, C = ar > 2 ? r[c->c] : ANY;
	if (c->op == BK_OP_MIX)
		return mix(A, B, C, dec[c->b] - dec[c->a], R, F);
	switch (c->op) {
	case BK_OP_CONST: return point(literal(c->k, R->prec), R, F);
	case BK_OP_PARAM: return point(literal(params[c->slot], R->prec), R, F);
	case BK_OP_INPUT: return point(in[c->slot], R, F);
	case BK_OP_ADD: return add(A, B, R, F);
	case BK_OP_SUB: return add(A, neg(B), R, F);
	case BK_OP_MUL: return mul(A, B, R, F);
	case BK_OP_DIV: return divide(A, B, R, F);
	case BK_OP_NEG: return neg(A);
	case BK_OP_MAD: return add(mul(A, B, R, F), C, R, F);
	case BK_OP_POW: return power(A, B, R, F);
	case BK_OP_SQRT: return root(A, R, F);
	case BK_OP_RSQRT: return rsqrt(A, R, F);
	case BK_OP_RCP: return divide(point(1, R, F), A, R, F);
	case BK_OP_EXP: return expo(A, 0, R, F);
	case BK_OP_EXP2: return expo(A, 1, R, F);
	case BK_OP_LOG: return loga(A, 0, R, F);
	case BK_OP_LOG2: return loga(A, 1, R, F);
	case BK_OP_MIN: return minimum(A, B);
	case BK_OP_MAX: return maximum(A, B);
	case BK_OP_CLAMP: return minimum(maximum(A, B), C);
	case BK_OP_SATURATE: return minimum(maximum(A, point(0, R, F)), point(1, R, F));
	case BK_OP_ABS:
		if (A.any)
			return A;
		return A.lo >= 0 ? A : A.hi <= 0 ? neg(A) : (vk_env){0, fmax(-A.lo, A.hi), 0};
	default: return ANY;
	}
}

int vk_envelope(const bk_form *f, const double *params, const vk_rules *rules, size_t n,
                const double *const in[BK_IN_COUNT], vk_env *out)
{
	for (int i = 0; i < BK_IN_COUNT; i++)
		if ((f->inputs >> i & 1) && !in[i])
			return -1;
	vk_env *r = malloc(sizeof *r * (size_t)(f->n > 0 ? f->n : 1));
	if (!r)
		return -1;
	const fmt *F = fmt_of(rules->prec);
	double x[BK_IN_COUNT] = {0}, *dec = malloc(sizeof *dec * (size_t)(f->n > 0 ? f->n : 1));
	if (!dec) {
		free(r);
		return -1;
	}
	for (int i = 0; i < f->n; i++) {
		const bk_instr *c = &f->code[i];
		dec[i] = c->op == BK_OP_CONST ? decimal(c->k, rules->prec)
		       : c->op == BK_OP_PARAM ? decimal(params[c->slot], rules->prec) : NAN;
	}
	for (size_t k = 0; k < n; k++) {
		for (int i = 0; i < BK_IN_COUNT; i++)
			x[i] = in[i] ? in[i][k] : 0;
		for (int i = 0; i < f->n; i++) {
			const bk_instr *c = &f->code[i];
			int ar = bk_opinfo_table[c->op].arity, lit = ar > 0;
			r[i] = apply(c, r, dec, x, params, rules, F);
			for (int j = 0; j < ar; j++)
				lit = lit && is_literal(&f->code[j == 0 ? c->a : j == 1 ? c->b : c->c]);
			if (lit && rules->fold) /* a statement of literals: a constant expression */
				r[i] = with_folded(r[i], bk_ir_apply(c->op, dec[c->a], ar > 1 ? dec[c->b] : 0,
				                                     ar > 2 ? dec[c->c] : 0), rules, F);
		}
		out[k] = r[f->out];
	}
	free(dec);
	free(r);
	return 0;
}

int vk_env_allows(const vk_env *e, double v)
{
	if (e->any)
		return 1;
	return !isnan(v) && v >= e->lo && v <= e->hi;
}
