/*
 * stability.c — a form under stress (see stability.h).
 *
 * The grid crosses every input the form reads: perceptual roughness from 0
 * through 1e-4 to 1 (a = r^2 follows it), each cosine from 0 through 1e-7 to 1
 * (and up to 0.99999, where 1 - NoH^2 cancels), f0 in {0, 0.02, 0.04, 1}. Each
 * precision's value is compared with long double. A NaN or an infinity where
 * the reference is finite always counts against the precision (rounding
 * never turns a number into NaN). A relative error counts where the
 * reference is at least half's smallest normal (2^-14, below which no
 * precision keeps relative accuracy in half; below it only an error larger
 * than 2^-14 counts), and, for the largest error reported, is well
 * conditioned — moving any input by half's rounding (2^-11 relative) moves
 * the reference by at most 8 x that. Elsewhere a large error is the
 * problem's, not the precision's.
 */
#include "stability.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const double bk_stab_r[] = {0, 1e-4, 1e-3, 0.01, 0.02, 0.05, 0.089, 0.1, 0.2, 0.3, 0.5, 0.7, 1};
const int bk_stab_nr = (int)(sizeof bk_stab_r / sizeof bk_stab_r[0]);
const double bk_stab_cos[] = {0, 1e-7, 1e-4, 1e-3, 0.01, 0.1, 0.5, 0.9, 0.999, 0.99999, 1};
const int bk_stab_ncos = (int)(sizeof bk_stab_cos / sizeof bk_stab_cos[0]);
static const double f0s[] = {0, 0.02, 0.04, 1};

#define HALF_NORMAL 0x1p-14 /* half's smallest normal */
#define HALF_MAX 65504.0
#define MAX_SAMPLES 400000  /* cosine combinations are strided beyond this */

static const int cosine_inputs[4] = {BK_IN_NOV, BK_IN_NOL, BK_IN_NOH, BK_IN_LOH};

/* The samples: the cross product of the inputs the form reads. */
typedef struct grid {
	size_t n;
	double *in[BK_IN_COUNT];
	int *cell_c, *cell_r; /* indices of the first cosine and of r, for the map */
} grid;

static void grid_free(grid *g)
{
	for (int i = 0; i < BK_IN_COUNT; i++)
		free(g->in[i]);
	free(g->cell_c);
	free(g->cell_r);
	memset(g, 0, sizeof *g);
}

/* rs, coss: the values to cross (nr, nc of them). */
static int grid_build(unsigned reads, const double *rs, int nr, const double *coss, int nc, grid *g)
{
	int ncos = 0, idx[4] = {0};
	int cin[4];
	for (int k = 0; k < 4; k++)
		if (reads >> cosine_inputs[k] & 1)
			cin[ncos++] = cosine_inputs[k];
	int nf = reads >> BK_IN_F0 & 1 ? 4 : 1;
	size_t combos = 1;
	for (int k = 0; k < ncos; k++)
		combos *= (size_t)nc;
	size_t stride = 1;
	while ((size_t)nr * nf * ((combos + stride - 1) / stride) > MAX_SAMPLES)
		stride++;
	size_t cap = (size_t)nr * nf * ((combos + stride - 1) / stride);
	memset(g, 0, sizeof *g);
	for (int i = 0; i < BK_IN_COUNT; i++)
		if (!(g->in[i] = malloc(sizeof(double) * cap)))
			return -1;
	g->cell_c = malloc(sizeof(int) * cap);
	g->cell_r = malloc(sizeof(int) * cap);
	if (!g->cell_c || !g->cell_r)
		return -1;
	size_t n = 0;
	for (int j = 0; j < nr; j++)
		for (size_t c = 0; c < combos; c += stride)
			for (int q = 0; q < nf; q++) {
				size_t rest = c;
				for (int k = 0; k < ncos; k++) {
					idx[k] = (int)(rest % (size_t)nc);
					rest /= (size_t)nc;
				}
				for (int i = 0; i < BK_IN_COUNT; i++)
					g->in[i][n] = 0.5; /* inputs the form does not read */
				for (int k = 0; k < ncos; k++)
					g->in[cin[k]][n] = coss[idx[k]];
				g->in[BK_IN_R][n] = rs[j];
				g->in[BK_IN_A][n] = rs[j] * rs[j];
				g->in[BK_IN_F0][n] = nf > 1 ? f0s[q] : 0.04;
				g->cell_c[n] = ncos ? idx[0] : 0;
				g->cell_r[n] = j;
				n++;
			}
	g->n = n;
	return 0;
}

/* Long-double references: at the exact inputs, and at the inputs rounded to
 * half and to single as a shader holds them. A precision's arithmetic is
 * judged against the reference at its own rounded inputs; what the rounding
 * of the inputs alone does (1 - NoH^2 near the highlight) is the difference
 * between the references: the sample is ill conditioned in that precision. */
typedef struct ref {
	double *v, *vp[3]; /* exact; at inputs rounded like BK_F64, BK_F32, BK_F16 */
} ref;

static int reference(const bk_form *f, const double *params, grid *g, ref *R)
{
	size_t n = g->n;
	double *rin[BK_IN_COUNT] = {0};
	int rc = 0;
	memset(R, 0, sizeof *R);
	R->v = malloc(sizeof(double) * n);
	for (int p = 0; p < 3; p++)
		R->vp[p] = malloc(sizeof(double) * n);
	for (int i = 0; i < BK_IN_COUNT; i++)
		rin[i] = malloc(sizeof(double) * n);
	for (int i = 0; i < BK_IN_COUNT; i++)
		rc |= !rin[i];
	if (rc || !R->v || !R->vp[0] || !R->vp[1] || !R->vp[2])
		rc = -1;
	else {
		bk_form_eval(f, BK_FLD, n, (const double *const *)g->in, params, R->v);
		memcpy(R->vp[0], R->v, sizeof(double) * n); /* double inputs are exact */
		for (int p = 1; p < 3; p++) {
			for (int i = 0; i < BK_IN_COUNT; i++)
				for (size_t k = 0; k < n; k++)
					rin[i][k] = p == 2 ? bk_half_round(g->in[i][k]) : (double)(float)g->in[i][k];
			bk_form_eval(f, BK_FLD, n, (const double *const *)rin, params, R->vp[p]);
		}
	}
	for (int i = 0; i < BK_IN_COUNT; i++)
		free(rin[i]);
	return rc;
}

static void ref_free(ref *R)
{
	free(R->v);
	for (int p = 0; p < 3; p++)
		free(R->vp[p]);
}

/* A number to compare with: finite and at least half's smallest normal
 * (below it no precision keeps relative accuracy in half). */
static int normal(double r)
{
	return isfinite(r) && fabs(r) >= HALF_NORMAL;
}

/* A value is wrong: NaN or infinite where its reference is finite (whatever
 * the reference's size: no rounding turns a number into NaN, and 0 * Inf in
 * half is NaN where long double multiplies 0 by 1e5); off by more than tol
 * relative where the reference is a normal number; below half's smallest
 * normal, where no precision keeps relative accuracy in half and a GPU may
 * flush to 0, off by more than that normal: a flush passes, a NaN turned into
 * 65504 by a clamp where the answer is 0 does not. */
static int wrong(double v, double r, double tol)
{
	if (!isfinite(r))
		return 0; /* the form's own pole: the problem's, not the precision's */
	if (!isfinite(v))
		return 1;
	return normal(r) ? fabs(v - r) > tol * fabs(r) : fabs(v - r) > HALF_NORMAL;
}

/* A sample fails in a precision: its value is wrong, or, where the reference
 * is finite, an operation on the way overflowed or made a NaN (flag: the
 * evaluator's BK_FLAG_ bits), even one a later min, max or clamp hid. The
 * IR's min(1, NaN) is 1 as HLSL's, but GLSL leaves min and clamp of a NaN
 * undefined, and GLSL ES does not require a GPU to produce an infinity at
 * all (a mediump float's guaranteed range ends at 2^14): a value that is
 * right only because an infinity or a NaN was hidden is luck. */
#define HIDDEN_FLAGS (BK_FLAG_NAN | BK_FLAG_OVERFLOW)
static int fails(double v, double r, unsigned char flag, double tol)
{
	return isfinite(r) && (wrong(v, r, tol) || (flag & HIDDEN_FLAGS));
}

/* Sample k in words: the inputs the form reads and its long-double value,
 * e.g. "NoV = 0, r = 0.5: +inf" ("it reads no input: NaN" for a constant). */
static void sample_text(const bk_form *f, const grid *g, size_t k, double v, char *buf, size_t len)
{
	unsigned reads = bk_form_inputs(f);
	size_t at = 0;
	buf[0] = '\0';
	for (int i = 0; i < BK_IN_COUNT && at < len; i++)
		if ((reads >> i & 1) && !(i == BK_IN_A && reads >> BK_IN_R & 1))
			at += (size_t)snprintf(buf + at, len - at, "%s%s = %.3g", at ? ", " : "", bk_input_name((bk_input)i),
			                       g->in[i][k]);
	if (at < len)
		snprintf(buf + at, len - at, "%s%s", at ? ": " : "it reads no input: ",
		         isnan(v) ? "NaN" : v > 0 ? "+inf" : "-inf");
}

static void describe_region(const bk_form *f, const grid *g, const unsigned char *bad, char *buf, size_t len)
{
	unsigned reads = bk_form_inputs(f);
	size_t k = 0;
	buf[0] = '\0';
	for (int i = 0; i < BK_IN_COUNT; i++) {
		if (!(reads >> i & 1) || (i == BK_IN_A && reads >> BK_IN_R & 1))
			continue;
		double lo = INFINITY, hi = -INFINITY;
		for (size_t s = 0; s < g->n; s++)
			if (bad[s])
				lo = fmin(lo, g->in[i][s]), hi = fmax(hi, g->in[i][s]);
		if (lo <= hi && k < len)
			k += (size_t)snprintf(buf + k, len - k, "%s%s in [%.3g, %.3g]", k ? ", " : "", bk_input_name((bk_input)i), lo, hi);
	}
}

/* One precision over the grid: counts, max relative error, where it breaks. */
static void score(const bk_form *f, const double *params, bk_precision prec, int pi, const grid *g, const ref *R,
                  double tol, bk_stab_prec *sp)
{
	size_t n = g->n;
	double *v = malloc(sizeof(double) * n);
	const double *rp = R->vp[pi];
	unsigned char *fl = malloc(n), *bad = calloc(n, 1), *ill = calloc(n, 1);
	memset(sp, 0, sizeof *sp);
	sp->n = n;
	sp->ill_noh_min = NAN;
	if (!v || !fl || !bad || !ill)
		goto out;
	int first[3];
	bk_form_eval_flags(f, prec, n, (const double *const *)g->in, params, v, fl, first);
	for (size_t k = 0; k < n; k++) {
		int rf = isfinite(rp[k]);
		sp->nan += rf && isnan(v[k]);
		sp->inf += rf && isinf(v[k]);
		sp->overflow += (fl[k] & BK_FLAG_OVERFLOW) != 0;
		sp->subnormal += (fl[k] & BK_FLAG_SUBNORMAL) != 0;
		sp->zeroed += v[k] == 0 && normal(rp[k]);
		bad[k] = (unsigned char)fails(v[k], rp[k], fl[k], tol);
		sp->wrong += bad[k];
		sp->hidden += bad[k] && !wrong(v[k], rp[k], tol);
		if (!normal(R->v[k]))
			continue;
		double moved = fabs(rp[k] - R->v[k]) / fabs(R->v[k]); /* what input rounding alone does */
		if (moved <= tol) {
			sp->well++;
			/* L7: NaN or inf where the reference is a normal number is the
			 * largest error of all, not a sample left out of it */
			sp->max_rel = fmax(sp->max_rel, isfinite(v[k]) ? fabs(v[k] - R->v[k]) / fabs(R->v[k]) : HUGE_VAL);
		} else {
			ill[k] = 1;
			sp->ill++;
			sp->max_rel_ill = fmax(sp->max_rel_ill, moved);
		}
	}
	if (sp->wrong)
		describe_region(f, g, bad, sp->region, sizeof sp->region);
	if (sp->ill) {
		describe_region(f, g, ill, sp->ill_region, sizeof sp->ill_region);
		if (bk_form_inputs(f) >> BK_IN_NOH & 1)
			for (size_t k = 0; k < n; k++)
				if (ill[k])
					sp->ill_noh_min = isnan(sp->ill_noh_min) ? g->in[BK_IN_NOH][k] : fmin(sp->ill_noh_min, g->in[BK_IN_NOH][k]);
	}
out:
	free(v);
	free(fl);
	free(bad);
	free(ill);
}

/* Is half precision right at every sample of this grid? Only where the form
 * itself is finite (a pole is no precision's fault, and no precision's
 * success either), and with no overflow or NaN hidden on the way. */
static int half_ok(const bk_form *f, const double *params, const double *rs, int nr, const double *coss, int nc,
                   double tol)
{
	grid g;
	ref R = {0};
	int ok = -1;
	if (grid_build(bk_form_inputs(f), rs, nr, coss, nc, &g) == 0 && reference(f, params, &g, &R) == 0) {
		double *v = malloc(sizeof(double) * g.n);
		unsigned char *fl = malloc(g.n);
		if (v && fl) {
			bk_form_eval_flags(f, BK_F16, g.n, (const double *const *)g.in, params, v, fl, NULL);
			ok = 1;
			for (size_t k = 0; k < g.n && ok; k++)
				ok = isfinite(R.v[k]) && isfinite(R.vp[2][k]) && !fails(v[k], R.vp[2][k], fl[k], tol);
		}
		free(v);
		free(fl);
	}
	ref_free(&R);
	grid_free(&g);
	return ok;
}

static int isalnum_c(char c)
{
	return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
}

/* printf into a new string (NULL if out of memory): forms have no length limit. */
static char *str_printf(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
static char *str_printf(const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	int n = vsnprintf(NULL, 0, fmt, ap);
	va_end(ap);
	char *out = n >= 0 ? malloc((size_t)n + 1) : NULL;
	if (out) {
		va_start(ap, fmt);
		vsnprintf(out, (size_t)n + 1, fmt, ap);
		va_end(ap);
	}
	return out;
}

/* The identifier id stands as a whole word at p of text. */
static int word_at(const char *text, const char *p, const char *id, size_t m)
{
	return !strncmp(p, id, m) && (p == text || !isalnum_c(p[-1])) && !isalnum_c(p[m]);
}

/* text with the identifier id replaced by repl wherever it stands as a whole
 * word, as a new string (NULL if out of memory). */
static char *substitute(const char *text, const char *id, const char *repl)
{
	size_t m = strlen(id), r = strlen(repl), len = 0;
	for (const char *p = text; *p;)
		if (word_at(text, p, id, m))
			len += r, p += m;
		else
			len++, p++;
	char *out = malloc(len + 1), *o = out;
	if (!out)
		return NULL;
	for (const char *p = text; *p;)
		if (word_at(text, p, id, m))
			memcpy(o, repl, r), o += r, p += m;
		else
			*o++ = *p++;
	*o = '\0';
	return out;
}

/* The smallest half-precision value >= x: guards are written in literals a
 * mediump shader holds exactly. */
static double half_at_least(double x)
{
	double h = bk_half_round(x);
	while (h < x)
		h = bk_half_round(h + fmax(h * 0x1p-11, 0x1p-24));
	return h;
}

/* Smallest value of the ascending list from which every later one passes
 * (NaN if the last fails, list[0] if all pass). */
static double safe_from(const double *list, const int *ok, int n)
{
	if (n == 0 || ok[n - 1] != 1)
		return NAN;
	int i = n - 1;
	while (i > 0 && ok[i - 1] == 1)
		i--;
	return list[i];
}

#define FINE 24

/* Smallest r of a fine log grid from which half is right with every cosine
 * >= cfloor (the list's values above it, and cfloor itself). */
static double min_safe_r(const bk_form *f, const double *params, double cfloor, double tol)
{
	double rs[FINE + 1], coss[32];
	int ok[FINE + 1], nc = 0;
	coss[nc++] = cfloor;
	for (int k = 0; k < bk_stab_ncos; k++)
		if (bk_stab_cos[k] > cfloor)
			coss[nc++] = bk_stab_cos[k];
	rs[0] = 0;
	for (int i = 1; i <= FINE; i++)
		rs[i] = 1e-4 * bk_dpow(1e4, (double)(i - 1) / (FINE - 1)); /* 1e-4 .. 1, log-spaced */
	for (int i = 0; i <= FINE; i++)
		ok[i] = half_ok(f, params, &rs[i], 1, coss, nc, tol);
	return safe_from(rs, ok, FINE + 1);
}

/* Largest relative change a guarded form h makes to the unguarded one in long
 * double, where the unguarded reference is meaningful: the guard's own error
 * (h NULL: not written, NaN). */
static double guard_cost(const bk_form *h, const double *params, const grid *g, const ref *R)
{
	double *v = h ? malloc(sizeof(double) * g->n) : NULL, worst = NAN;
	if (v && bk_form_eval(h, BK_FLD, g->n, (const double *const *)g->in, params, v) == 0) {
		worst = 0; /* where the value is one half can hold: beyond 65504 nothing can be kept */
		for (size_t k = 0; k < g->n; k++)
			if (normal(R->v[k]) && fabs(R->v[k]) <= HALF_MAX)
				worst = fmax(worst, fabs(v[k] - R->v[k]) / fabs(R->v[k]));
	}
	free(v);
	return worst;
}

/* The guarded forms below are new strings (NULL if out of memory). */
static char *guard_r(const char *text, double R)
{
	char rep[64];
	snprintf(rep, sizeof rep, "max(r, %.9g)", R);
	char *tmp = substitute(text, "r", rep);
	snprintf(rep, sizeof rep, "max(a, %.9g)", half_at_least(R * R));
	char *out = tmp ? substitute(tmp, "a", rep) : NULL;
	free(tmp);
	return out;
}

static char *guard_cos(const char *text, unsigned reads, double C)
{
	static const char *const names[5] = {"NoV", "NoL", "NoH", "LoH", "VoH"}; /* VoH is LoH */
	static const int in_of[5] = {BK_IN_NOV, BK_IN_NOL, BK_IN_NOH, BK_IN_LOH, BK_IN_LOH};
	char rep[64], *a = str_printf("%s", text);
	for (int k = 0; k < 5 && a; k++) {
		if (!(reads >> in_of[k] & 1))
			continue;
		snprintf(rep, sizeof rep, "max(%s, %.9g)", names[k], C);
		char *b = substitute(a, names[k], rep);
		free(a);
		a = b;
	}
	return a;
}

/* Constants and parameter values a half shader cannot hold, into buf: every
 * one of them, or as many as fit and how many more. */
static void check_constants(const bk_form *f, const double *params, char *buf, size_t len)
{
	int nk = bk_form_constants(f, NULL, 0), np = bk_form_nparams(f), left = 0;
	double *k = malloc(sizeof(double) * (size_t)(nk + np + 1));
	size_t at = 0;
	buf[0] = '\0';
	if (!k) {
		snprintf(buf, len, "not checked: out of memory");
		return;
	}
	bk_form_constants(f, k, nk);
	for (int j = 0; j < np; j++)
		k[nk + j] = params[j];
	for (int i = 0; i < nk + np; i++) {
		double x = fabs(k[i]);
		const char *why = x > HALF_MAX ? "infinite in half" : x != 0 && x < HALF_NORMAL ? "subnormal in half: 0 where GPUs flush" : NULL;
		char one[96];
		int m = why ? snprintf(one, sizeof one, "%s%.3g (%s)", at ? "; " : "", k[i], why) : 0;
		if (m && at + (size_t)m + 24 < len) /* 24: room for "; and N more" */
			memcpy(buf + at, one, (size_t)m + 1), at += (size_t)m;
		else if (m)
			left++;
	}
	if (left)
		snprintf(buf + at, len - at, "%sand %d more", at ? "; " : "", left);
	free(k);
}

static void failure_map(const bk_form *f, const double *params, const grid *g, const ref *R, double tol,
                        bk_stability *st)
{
	st->map_nx = bk_stab_ncos;
	st->map_ny = bk_stab_nr;
	double *v = malloc(sizeof(double) * g->n);
	unsigned char *fl = malloc(g->n);
	int count[16 * 16] = {0}, badc[16 * 16] = {0};
	if (v && fl) {
		bk_form_eval_flags(f, BK_F16, g->n, (const double *const *)g->in, params, v, fl, NULL);
		for (size_t k = 0; k < g->n; k++) {
			int c = g->cell_r[k] * st->map_nx + g->cell_c[k];
			count[c]++;
			badc[c] += fails(v[k], R->vp[2][k], fl[k], tol);
		}
	}
	for (int c = 0; c < st->map_nx * st->map_ny; c++)
		st->map[c] = count[c] ? (double)badc[c] / count[c] : NAN;
	free(v);
	free(fl);
}

/* One candidate: a cosine floor C (0: none), a roughness floor R (0: none).
 * No clamp of the result to 65504: it only ever acts on an infinity, which
 * a mediump GPU need not produce (fails() above), so it guards nothing. */
static char *build_guarded(const char *text, unsigned reads, double R, double C)
{
	char *a = str_printf("%s", text), *b;
	if (a && R > 0)
		b = guard_r(a, R), free(a), a = b;
	if (a && C > 0)
		b = guard_cos(a, reads, C), free(a), a = b;
	return a;
}

/* build_guarded's text parsed, each guarded text once (its error cost and its
 * check in half read the same form). NULL when the parser refuses it (e says
 * why: a form too long once guarded) or out of memory (e's message empty). */
static bk_form *parse_guarded(const char *text, unsigned reads, double R, double C, bk_form_error *e)
{
	char *t = build_guarded(text, reads, R, C);
	bk_form *h = t ? bk_form_parse(t, e) : NULL;
	if (!t)
		*e = (bk_form_error){0, ""};
	free(t);
	return h;
}

/* The guards that can be written into the form: for each cosine floor of the
 * minimum-safe-inputs table, that floor with its roughness floor. Each
 * guard's error is measured alone against the unguarded form; the passing
 * candidate whose worst guard error is smallest wins. */
static void propose_guards(const bk_form *f, const char *text, const double *params, const grid *g, const ref *R,
                           double tol, bk_stability *st)
{
	bk_form *best = NULL; /* st->guarded's form once a guard passes */
	unsigned reads = bk_form_inputs(f);
	int reads_r = (reads >> BK_IN_R & 1) || (reads >> BK_IN_A & 1);
	double best_err = INFINITY;
	char unwritable[200] = ""; /* a candidate the parser refused: a form too long once guarded */
	st->guarded_ok = 0;
	snprintf(st->guards, sizeof st->guards, "none of the floors fixes it");
	st->guarded = str_printf("%s", text);
	st->guard_error[0] = st->guard_error[1] = NAN;
	for (int i = 0; i < 5; i++) {
		double Cf = st->floor_cos[i], Rf = st->floor_r[i];
		if (isnan(Rf))
			continue;
		double C = Cf > 0 ? half_at_least(Cf) : 0, Rr = reads_r && Rf > 0 ? half_at_least(Rf) : 0;
		bk_form_error er_e, ec_e, e;
		bk_form *hr = Rr > 0 ? parse_guarded(text, reads, Rr, 0, &er_e) : NULL;
		bk_form *hc = C > 0 ? parse_guarded(text, reads, 0, C, &ec_e) : NULL;
		double er = Rr > 0 ? guard_cost(hr, params, g, R) : 0, ec = C > 0 ? guard_cost(hc, params, g, R) : 0;
		double err = fmax(er, ec);
		bk_form *h = NULL;
		if (!(err < best_err)) {
			bk_form_free(hr);
			bk_form_free(hc);
			continue;
		}
		/* both floors: a text of its own; one: that floor's form, already parsed */
		if (Rr > 0 && C > 0) {
			bk_form_free(hr);
			bk_form_free(hc);
			h = parse_guarded(text, reads, Rr, C, &e);
		} else if (Rr > 0 || C > 0) {
			h = Rr > 0 ? hr : hc;
			e = Rr > 0 ? er_e : ec_e;
		} else { /* no floor: the text itself */
			h = bk_form_dup(f);
			e = (bk_form_error){0, ""};
		}
		int ok = h ? half_ok(h, params, bk_stab_r, bk_stab_nr, bk_stab_cos, bk_stab_ncos, tol) : 0;
		if (!h && e.message[0])
			snprintf(unwritable, sizeof unwritable, "%s", e.message);
		char *cur = ok == 1 ? str_printf("%s", bk_form_text(h)) : NULL;
		if (!cur) {
			bk_form_free(h);
			continue;
		}
		best_err = err;
		st->guarded_ok = 1;
		free(st->guarded);
		st->guarded = cur;
		bk_form_free(best); /* the winner's form is kept for its constants below: parsed once */
		best = h;
		st->guard_error[0] = Rr > 0 ? er : NAN;
		st->guard_error[1] = C > 0 ? ec : NAN;
		size_t k = 0;
		st->guards[0] = '\0';
		if (Rr > 0)
			k += (size_t)snprintf(st->guards + k, sizeof st->guards - k, "roughness floor r >= %.4g", Rr);
		if (C > 0)
			snprintf(st->guards + k, sizeof st->guards - k, "%scosines >= %.4g", k ? ", " : "", C);
	}
	if (!st->guarded_ok && unwritable[0]) /* not "nothing fixes it": it could not be tried */
		snprintf(st->guards, sizeof st->guards, "none of the floors that could be written fixes it (a guarded "
		         "form was refused: %.150s)", unwritable);
	/* no guard passed: st->guarded is text itself, f */
	if (st->guarded)
		check_constants(best ? best : f, params, st->constants, sizeof st->constants);
	st->guarded_form = best ? best : bk_form_dup(f);
}

int bk_stability_run(const char *name, const char *text, const double *params, double tol, bk_stability *st,
                     char *err, size_t errlen)
{
	bk_form_error e;
	bk_form *f = bk_form_parse(text, &e);
	if (!f) {
		memset(st, 0, sizeof *st);
		snprintf(st->name, sizeof st->name, "%s", name);
		bk_stability_parse_error(name, &e, err, errlen);
		return -1;
	}
	int rc = bk_stability_run_form(name, f, params, tol, st, err, errlen);
	bk_form_free(f);
	return rc;
}

void bk_stability_parse_error(const char *name, const bk_form_error *e, char *err, size_t errlen)
{
	snprintf(err, errlen, "%s:1:%d: %s", name, e->column, e->message);
}

int bk_stability_run_form(const char *name, const bk_form *f, const double *params, double tol, bk_stability *st,
                          char *err, size_t errlen)
{
	memset(st, 0, sizeof *st);
	snprintf(st->name, sizeof st->name, "%s", name);
	const char *text = bk_form_text(f); /* the guards are rewrites of the text (substitute) */
	double none[BK_MAX_PARAMS] = {0};
	if (!params && bk_form_nparams(f) > 0) { /* zeros would be a silent guess */
		int np = bk_form_nparams(f);
		if (np == 1)
			snprintf(err, errlen, "%s: the form uses p0 but no value was given", name);
		else
			snprintf(err, errlen, "%s: the form uses p0..p%d but no values were given", name, np - 1);
		return -1;
	}
	if (!params)
		params = none;
	grid g;
	ref R = {0};
	if (grid_build(bk_form_inputs(f), bk_stab_r, bk_stab_nr, bk_stab_cos, bk_stab_ncos, &g) ||
	    reference(f, params, &g, &R)) {
		grid_free(&g);
		ref_free(&R);
		snprintf(err, errlen, "%s: out of memory", name);
		return -1;
	}
	size_t first_pole = g.n;
	for (size_t k = g.n; k-- > 0;)
		if (!isfinite(R.v[k]))
			st->ref_nonfinite++, first_pole = k;
	if (first_pole < g.n)
		sample_text(f, &g, first_pole, R.v[first_pole], st->pole, sizeof st->pole);
	if (st->ref_nonfinite == g.n) { /* nothing to judge: as fit and compare, refuse it */
		snprintf(err, errlen, "%s: the form is NaN or infinite at every one of the %zu samples of the grid (%s): "
		         "no precision can be judged against it", name, g.n, st->pole);
		grid_free(&g);
		ref_free(&R);
		return -1;
	}
	static const bk_precision order[3] = {BK_F64, BK_F32, BK_F16};
	for (int p = 0; p < 3; p++)
		score(f, params, order[p], p, &g, &R, tol, &st->p[p]);
	/* minimum safe inputs: for each cosine floor, the smallest safe roughness */
	static const double floors[5] = {0, 1e-4, 1e-3, 1e-2, 0.1};
	unsigned reads = bk_form_inputs(f);
	int reads_cos = (reads & (1u << BK_IN_NOV | 1u << BK_IN_NOL | 1u << BK_IN_NOH | 1u << BK_IN_LOH)) != 0;
	st->r_min = st->cos_min = NAN;
	for (int i = 0; i < 5; i++) {
		st->floor_cos[i] = floors[i];
		st->floor_r[i] = (i == 0 || reads_cos) ? min_safe_r(f, params, floors[i], tol) : st->floor_r[0];
		if (isnan(st->r_min) && !isnan(st->floor_r[i])) {
			st->r_min = st->floor_r[i];
			st->cos_min = floors[i];
		}
	}
	failure_map(f, params, &g, &R, tol, st);
	if (st->p[2].ill && st->p[2].ill_noh_min >= 0.9)
		snprintf(st->advice, sizeof st->advice,
		         "compute 1 - NoH^2 as |N x H|^2 from the vectors (Filament's mobile path): NoH rounded to half "
		         "loses sin^2 of the half angle near the highlight (errors up to %.2g at NoH >= %.3g)",
		         st->p[2].max_rel_ill, st->p[2].ill_noh_min);
	/* Safe as is: right at every sample, nothing hidden, and the form itself
	 * finite everywhere (a pole is a NaN or Inf in any precision). */
	st->safe_as_is = st->p[2].wrong == 0 && st->ref_nonfinite == 0;
	if (!st->safe_as_is)
		propose_guards(f, text, params, &g, &R, tol, st);
	else {
		st->guarded_ok = 1;
		st->guarded = str_printf("%s", text);
		st->guarded_form = bk_form_dup(f);
		check_constants(f, params, st->constants, sizeof st->constants);
	}
	grid_free(&g);
	ref_free(&R);
	if (!st->guarded || !st->guarded_form) {
		bk_stability_free(st);
		snprintf(err, errlen, "%s: out of memory", name);
		return -1;
	}
	return 0;
}

void bk_stability_free(bk_stability *st)
{
	free(st->guarded);
	st->guarded = NULL;
	bk_form_free(st->guarded_form);
	st->guarded_form = NULL;
}
