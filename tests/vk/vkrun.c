/*
 * vkrun — brdfkit's emitted GLSL run in a real Vulkan driver (Mesa's
 * lavapipe), compared with the IR's evaluation in the same precision.
 *
 *   vkrun [--samples N] [--perturb LABEL [--factor F] | --nan LABEL] [--ir-half]
 *         [--fuzz N [--seed S]] [--list] [--verbose] [FRONT.csv | SHADER.glsl]...
 *
 * Runs every catalog form, every member of the given search fronts and every
 * function of the given GLSL files brdfkit wrote (tests/vk/sources.h) on a grid of its
 * inputs over [0, 1] (each input it reads: about N samples in all; grid values
 * are exact in half), in f32 (the text as emitted) and in f16 (float16_t
 * arithmetic, tests/vk/glsl.h), and checks at every sample that
 *
 *   - the driver's value is one the Vulkan specification allows for the
 *     emitted statements (the envelope, tests/vk/envelope.h: the tolerance,
 *     derived per sample from the precision the specification gives each
 *     operation, exp2/log2 included);
 *   - the IR's value (bk_form_eval in that precision) is one too: the IR
 *     describes a driver the specification allows;
 *   - NaN, +inf and -inf match in kind exactly wherever the specification
 *     defines the operations, also where the envelope bounds nothing (past a
 *     division by zero); in f16 the driver's kind is that of one of the two
 *     orders of the mads (bk_ir_eval_half_orders), the IR reporting the worse;
 *   - where the specification defines nothing (pow of a negative base, 0^0,
 *     0/0, sqrt(-1)) the driver is free, and the IR must say NaN (or have made
 *     one that a min or max hid): it never reports a number there.
 *
 * --fuzz N adds N forms drawn from --seed (tests/vk/fuzz.c) to the catalog.
 *
 * --half-front FRONT.csv --target KIND [--nx N] [--nr N] [--ior X --k Y] instead runs the
 * members of a half search's front as their shader_f16.glsl is emitted
 * (float16_t, binary16 constants, no precise) over that target's samples and
 * holds each to the f16 error its files state (tests/vk/halfbound.h); there
 * --perturb NAME multiplies that member's p0 by F, the control; --precise
 * declares every temporary precise (no contraction or reassociation), the
 * diagnosis of a member that does not hold. Exit status there: 0 every
 * member holds, 1 some exceed their stated error, 3 an error (one line).
 *
 * --perturb LABEL multiplies the first literal in that function's body by F
 * (default 1.001), --nan LABEL makes it return NaN, --ir-half compares the f32
 * run with the IR's f16: negative controls of each check, which must fail. Exit status: 0 all agree, 1 a mismatch or a run-time error (one
 * line "vkrun: ..."), 2 usage.
 */
#include "envelope.h"
#include "glsl.h"
#include "halfbound.h"
#include "lvp.h" /* analysis/lvp.h */
#include "sources.h"

#include "clock.h"
#include "gpucost.h"
#include "half.h"
#include "ir.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PER_SHADER 24 /* functions per compute shader: a few shaders, each quick to compile */
#define SLOTS 8       /* floats per sample in the input buffer (7 inputs) */

typedef struct opts {
	int samples;
	const char *perturb, *nan;
	double factor;
	int list, verbose, ir_half;
	int fuzz;           /* forms drawn by tests/vk/fuzz.c */
	vk_halfbound_opts hb; /* --half-front: hb.front set */
	unsigned long seed; /* their seed */
} opts;

static int usage(const char *msg)
{
	fprintf(stderr, "vkrun: %s; usage: vkrun [--samples N] [--perturb LABEL [--factor F] | --nan LABEL] [--ir-half] "
	                "[--fuzz N [--seed S]] [--list] [--verbose] [FRONT.csv | SHADER.glsl]... | vkrun --half-front FRONT.csv --target KIND [--nx N] [--nr N] [--ior X] [--k Y] [--precise] [--perturb NAME [--factor F]] "
	                "[--verbose]\n", msg);
	return 2;
}

/* ---- the grid --------------------------------------------------------------- */

typedef struct grid {
	size_t *off, *n; /* per function: first sample, sample count */
	size_t total;
	float *in;       /* SLOTS floats per sample */
} grid;

static int popcount(unsigned x)
{
	int k = 0;
	for (; x; x &= x - 1)
		k++;
	return k;
}

/* m points per input read (m^k about samples), j/(m - 1) rounded to half, so
 * that both precisions load them exactly. */
static int make_grid(const vk_fns *fns, int samples, grid *g)
{
	g->off = calloc((size_t)fns->n + 1, sizeof *g->off);
	g->n = calloc((size_t)fns->n + 1, sizeof *g->n);
	int *m = calloc((size_t)fns->n + 1, sizeof *m);
	if (!g->off || !g->n || !m) {
		free(m);
		return -1;
	}
	for (int i = 0; i < fns->n; i++) {
		int k = popcount(fns->v[i].args);
		m[i] = k ? (int)floor(pow(samples, 1.0 / k) + 1e-9) : 1;
		m[i] = k && m[i] < 2 ? 2 : m[i];
		g->n[i] = (size_t)pow(m[i], k);
		g->off[i] = g->total;
		g->total += g->n[i];
	}
	g->in = calloc(g->total * SLOTS + 1, sizeof *g->in);
	for (int i = 0; g->in && i < fns->n; i++)
		for (size_t s = 0; s < g->n[i]; s++) {
			size_t q = s;
			for (int c = 0; c < BK_IN_COUNT; c++)
				if (fns->v[i].args >> c & 1) {
					double t = m[i] > 1 ? (double)(q % (size_t)m[i]) / (m[i] - 1) : 0;
					g->in[(g->off[i] + s) * SLOTS + (size_t)c] = (float)bk_half_round_inline(t);
					q /= (size_t)m[i];
				}
		}
	free(m);
	return g->in ? 0 : -1;
}

/* ---- one precision ---------------------------------------------------------- */

typedef struct stats {
	int verbose, ir_half;
	long samples, bounded, unbounded, undefined, flushed, folded;
	long driver_out, ir_out, kind, orders, irnan, flushkind, open, overkind, slack;
	int failed, flushed_fns, folded_fns, mostly_unbounded;
	double max_ulp, max_ulp_tol; /* the largest |driver - IR| in ulps, and the tolerance there */
	char max_at[200];
} stats;

/* The class of a value: a number, an infinity or NaN. The sign of an
 * infinity is not compared: it follows the sign of a zero (1/-0), which a
 * driver's algebra does not keep (x + y*0 folded to x gives -0 where IEEE
 * gives +0: measured on lavapipe), and no shader reads it. */
static int kind(double v)
{
	return isnan(v) ? 2 : isinf(v) ? 1 : 0;
}

static int uses_mix(const bk_form *f)
{
	for (int i = 0; i < f->n; i++)
		if (f->code[i].op == BK_OP_MIX)
			return 1;
	return 0;
}

static void print_sample(const vk_fn *f, const float *in)
{
	for (int c = 0; c < BK_IN_COUNT; c++)
		if (f->args >> c & 1)
			printf("%s=%.9g ", bk_input_name((bk_input)c), in[c]);
}

/* One function's comparison: its samples, the IR's values, the envelopes and
 * what was found. */
typedef struct fncheck {
	const vk_fn *f;
	bk_precision prec;
	size_t n;
	const float *in, *drv;        /* SLOTS floats per sample; the driver's values */
	const double *cols[BK_IN_COUNT];
	double *x, *ir;               /* the inputs as columns; the IR's values */
	double *alt;                  /* f16: the IR's values in each order a driver may take */
	int ir16;                     /* the IR ran in f16 (alt holds its two orders) */
	vk_env *env;                  /* n with every allowance, then n with none */
	int builtin;                  /* the text calls GLSL mix() */
	long bad, dout, iout, kinds, flushed, folded, slack, any, undefined, orders, irnan, flushkind, open, overkind;
	unsigned char *flags;         /* the IR's flags (bk_form_eval_flags): a NaN made on the way */
	double ulp, tol;              /* the largest |driver - IR| in ulps, the tolerance there */
	size_t first;                 /* the first failing sample */
} fncheck;

static int fc_prepare(fncheck *c, int ir_half)
{
	size_t n = c->n;
	c->x = malloc(sizeof *c->x * n * (BK_IN_COUNT + 3) + 1);
	c->env = malloc(sizeof *c->env * n * 2 + 1);
	c->flags = malloc(n + 1);
	if (!c->x || !c->env || !c->flags)
		return -1;
	c->ir = c->x + n * BK_IN_COUNT;
	c->alt = c->ir + n;
	for (int k = 0; k < BK_IN_COUNT; k++)
		if (c->f->args >> k & 1) {
			for (size_t s = 0; s < n; s++)
				c->x[(size_t)k * n + s] = c->in[s * SLOTS + (size_t)k];
			c->cols[k] = c->x + (size_t)k * n;
		}
	c->builtin = vk_calls(c->f->glsl, "mix");
	/* lavapipe's exp2 slack was measured in f32 (envelope.h) */
	vk_rules all = {c->prec, 1, 1, c->builtin, c->prec == BK_F32}, strict = {c->prec, 0, 0, c->builtin, 0};
	c->first = n;
	int half = c->ir16 = ir_half || c->prec == BK_F16;
	return bk_form_eval_flags(c->f->form, ir_half ? BK_F16 : c->prec, n, c->cols, c->f->params, c->ir, c->flags,
	                          NULL) ||
	       (half && bk_ir_eval_half_orders(c->f->form, n, c->cols, c->f->params, c->alt, c->alt + n)) ||
	       vk_envelope(c->f->form, c->f->params, &all, n, c->cols, c->env) ||
	       vk_envelope(c->f->form, c->f->params, &strict, n, c->cols, c->env + n) ? -1 : 0;
}

/* A value the strict envelope refuses and the full one allows: which
 * allowance it needed (the flush alone, the compiler's folding alone, else
 * lavapipe's exp2 slack). */
static void fc_allowance(fncheck *c, size_t s, double d)
{
	vk_env e;
	vk_rules flush_only = {c->prec, 1, 0, c->builtin, 0}, fold_only = {c->prec, 0, 1, c->builtin, 0};
	const double *one[BK_IN_COUNT];
	for (int k = 0; k < BK_IN_COUNT; k++)
		one[k] = c->cols[k] ? c->cols[k] + s : NULL;
	if (vk_envelope(c->f->form, c->f->params, &flush_only, 1, one, &e) == 0 && vk_env_allows(&e, d))
		c->flushed++;
	else if (vk_envelope(c->f->form, c->f->params, &fold_only, 1, one, &e) == 0 && vk_env_allows(&e, d))
		c->folded++;
	else
		c->slack++;
}

static void fc_sample(fncheck *c, size_t s, stats *st)
{
	double d = c->drv[s], v = c->ir[s];
	const vk_env *e = &c->env[s], *strict = &c->env[c->n + s];
	/* Where the IR made a NaN (its value, or one a later min, max or clamp
	 * hid: flags), brdfkit reports no number, and the driver is free: the
	 * specifications give such an operation no value (pow of a negative base,
	 * 0^0, 0/0, sqrt(-1)) and drivers differ there (lavapipe gives 0 for 0^-1,
	 * and a number for exp2 of a NaN, which it clamps; other GPUs NaN). So
	 * where the IR is infinite and the operations' allowed error can reach an
	 * undefined one (rsqrt of a difference that cancels to 0 in the IR, and
	 * to a negative in a driver within its ULPs): no number is reported. */
	int irnan = isnan(v) || (c->flags[s] & BK_FLAG_NAN) || (isinf(v) && e->any == VK_UNDEFINED);
	int od = !irnan && !vk_env_allows(e, d), oi = !vk_env_allows(e, v);
	int allowance = !irnan && !od && !vk_env_allows(strict, d);
	/* Everywhere else the kinds (a number, an infinity, NaN) must match, also
	 * where the envelope bounds or defines nothing (an interval that may hold
	 * a zero divisor) and where an allowance (a flushed denormal) moved the
	 * value. In half the driver may take either order of a mad (fused or
	 * not) and the IR reports the worse: the driver's kind must be that of
	 * one of the two. */
	double uf = c->ir16 ? c->alt[s] : v, fu = c->ir16 ? c->alt[c->n + s] : v;
	int kd = !irnan && kind(d) != kind(v) && kind(d) != kind(uf) && kind(d) != kind(fu);
	/* but for three cases the specification leaves open, each counted: a
	 * driver that flushes a denormal the IR keeps (allowed; the IR flags the
	 * denormal) may turn it into a division by zero, hence an infinity; and
	 * where the envelope is an interval past the largest finite value (a
	 * result within the operations' ULPs of overflow), both kinds are
	 * allowed values and the IR's is one of them */
	if (kd && (c->flags[s] & BK_FLAG_SUBNORMAL))
		kd = 0, c->flushkind++;
	else if (kd && !e->any && vk_env_allows(e, d) && vk_env_allows(e, v))
		kd = 0, c->open++;
	/* and an infinity the IR made on the way from finite operands (it flags
	 * it: a division by a zero whose sign max(0, -0) leaves to the driver,
	 * an overflow) where the specification bounds nothing after it */
	else if (kd && e->any && (c->flags[s] & BK_FLAG_OVERFLOW))
		kd = 0, c->overkind++;
	c->irnan += irnan;
	c->orders += kind(uf) != kind(fu);
	c->any += e->any != 0;
	c->undefined += e->any == VK_UNDEFINED;
	c->dout += od;
	c->iout += oi;
	c->kinds += kd;
	if (od || oi || kd) {
		c->bad++;
		c->first = c->first < c->n ? c->first : s;
		return;
	}
	if (allowance) { /* counted, not measured in ulps */
		fc_allowance(c, s, d);
		return;
	}
	if (e->any || kind(v))
		return;
	double u = vk_ulp(v, c->prec), err = fabs(d - v) / u, tol = fmax(e->hi - v, v - e->lo) / u;
	if (err > c->ulp) {
		c->ulp = err;
		c->tol = tol;
	}
	if (err > st->max_ulp) {
		st->max_ulp = err;
		st->max_ulp_tol = tol;
		snprintf(st->max_at, sizeof st->max_at, "%s", c->f->label);
	}
}

static void fc_report(const fncheck *c, stats *st)
{
	const char *p = bk_precision_name(c->prec), *label = c->f->label;
	st->samples += (long)c->n;
	st->unbounded += c->any - c->undefined;
	st->undefined += c->undefined;
	st->bounded += (long)c->n - c->any;
	st->driver_out += c->dout;
	st->ir_out += c->iout;
	st->kind += c->kinds;
	st->orders += c->orders;
	st->irnan += c->irnan;
	st->flushkind += c->flushkind;
	st->open += c->open;
	st->overkind += c->overkind;
	st->slack += c->slack;
	st->flushed += c->flushed;
	st->flushed_fns += c->flushed > 0;
	st->folded += c->folded;
	st->folded_fns += c->folded > 0;
	if (st->verbose)
		printf("  %s %s: %zu samples, %ld unbounded (%ld undefined), %ld flushed, %ld folded, max |driver - IR| "
		       "%.3g ulp (tolerance there %.3g ulp)\n", p, label, c->n, c->any, c->undefined, c->flushed, c->folded,
		       c->ulp, c->tol);
	if (2 * c->any > (long)c->n) { /* said, not failed: NaN/Inf kinds are still compared there */
		st->mostly_unbounded++;
		printf("note: %s %s: the specification bounds only %ld of %zu samples (an overflow or a division by "
		       "zero on the way; NaN/Inf kinds compared there)\n", p, label, (long)c->n - c->any, c->n);
	}
	if (!c->bad)
		return;
	st->failed++;
	size_t s = c->first;
	const vk_env *e = &c->env[s];
	printf("FAIL: %s %s: %ld of %zu samples (driver outside the envelope %ld, IR outside %ld, NaN/Inf kind %ld)%s; "
	       "first at ", p, label, c->bad, c->n, c->dout, c->iout, c->kinds,
	       c->builtin ? " [GLSL mix()]" : uses_mix(c->f->form) ? " [mix spelled out]" : "");
	print_sample(c->f, c->in + s * SLOTS);
	if (e->any)
		printf("driver %.9g, IR %.9g, envelope: %s\n", c->drv[s], c->ir[s],
		       e->any == VK_UNDEFINED ? "undefined" : "any value of the same kind");
	else
		printf("driver %.9g, IR %.9g, envelope [%.9g, %.9g]\n", c->drv[s], c->ir[s], e->lo, e->hi);
}

/* The comparison of one function's n samples; prints its FAIL line. */
static int check_fn(const vk_fn *f, const float *in, size_t n, const float *drv, bk_precision prec, stats *st)
{
	fncheck c = {.f = f, .prec = prec, .n = n, .in = in, .drv = drv};
	int rc = fc_prepare(&c, st->ir_half);
	for (size_t s = 0; !rc && s < n; s++)
		fc_sample(&c, s, st);
	if (!rc)
		fc_report(&c, st);
	free(c.x);
	free(c.env);
	free(c.flags);
	return rc;
}

/* The shaders of one precision: per group, PER_SHADER functions at a time. */
typedef struct batch {
	unsigned **spirv;
	size_t *nwords;
	int npipe;
	bk_lvp_dispatch *d;
} batch;

static void free_batch(batch *b)
{
	for (int i = 0; b->spirv && i < b->npipe; i++)
		free(b->spirv[i]);
	free(b->spirv);
	free(b->nwords);
	free(b->d);
}

static int compile_batch(const vk_fns *fns, const grid *g, bk_precision prec, batch *b, char *err, size_t errlen)
{
	int cap = fns->n + 1;
	const vk_fn **pick = calloc((size_t)cap, sizeof *pick);
	b->spirv = calloc((size_t)cap, sizeof *b->spirv);
	b->nwords = calloc((size_t)cap, sizeof *b->nwords);
	b->d = calloc((size_t)cap, sizeof *b->d);
	if (!pick || !b->spirv || !b->nwords || !b->d) {
		free(pick);
		snprintf(err, errlen, "out of memory");
		return -1;
	}
	int rc = 0;
	for (int grp = 0; !rc && grp < (fns->groups > 0 ? fns->groups : 1); grp++)
		for (int i = 0; !rc && i < fns->n;) {
			int k = 0;
			for (; i < fns->n && k < PER_SHADER; i++)
				if (fns->v[i].group == grp) {
					b->d[i] = (bk_lvp_dispatch){b->npipe, (uint32_t)k, (uint32_t)g->off[i], (uint32_t)g->off[i],
					                         (uint32_t)g->n[i]};
					pick[k++] = &fns->v[i];
				}
			if (!k)
				continue;
			char *glsl = vk_shader(pick, k, prec), e[512];
			unsigned *w = glsl ? bk_gpucost_spirv(glsl, &b->nwords[b->npipe], e, sizeof e) : NULL;
			if (!w) {
				snprintf(err, errlen, "%s shader of %s .. %s: %s", bk_precision_name(prec), pick[0]->label,
				         pick[k - 1]->label, glsl ? e : "out of memory");
				rc = -1;
			}
			b->spirv[b->npipe++] = w;
			free(glsl);
		}
	free(pick);
	return rc;
}

static int run_precision(bk_lvp *v, const vk_fns *fns, const grid *g, bk_precision prec, stats *st)
{
	char err[1024];
	batch b = {0};
	double t0 = bk_clock_now(), t[2] = {0, 0};
	float *out = malloc(sizeof *out * g->total + 1);
	int rc = out ? compile_batch(fns, g, prec, &b, err, sizeof err) : (snprintf(err, sizeof err, "out of memory"), -1);
	double t1 = bk_clock_now();
	if (!rc)
		rc = bk_lvp_run(v, b.spirv, b.nwords, b.npipe, g->in, g->total * SLOTS, b.d, fns->n, out, g->total, t, err,
		             sizeof err);
	double t2 = bk_clock_now();
	for (int i = 0; !rc && i < fns->n; i++)
		if (check_fn(&fns->v[i], g->in + g->off[i] * SLOTS, g->n[i], out + g->off[i], prec, st)) {
			snprintf(err, sizeof err, "out of memory");
			rc = -1;
		}
	if (rc)
		fprintf(stderr, "vkrun: %s\n", err);
	else
		printf("%s: %d functions in %d shaders, %ld samples (%ld bounded; %ld where the specification bounds "
		       "nothing: NaN/Inf kinds only; %ld where it defines nothing: 0/0 and the like; %d functions mostly "
		       "unbounded); failed %d: driver outside the envelope %ld, IR outside %ld, "
		       "NaN/Inf kind %ld; %ld samples whose kind depends on the order of a mad (the IR keeps the worse); %ld where the IR is NaN or infinite past an undefined operation (the driver free); kinds left open: %ld by a denormal the IR flags, %ld within the ULPs of overflow, %ld past an infinity the IR flags; allowances used: a denormal flushed %ld samples in %d functions, a constant folded in double %ld samples in %d functions, lavapipe's exp2 slack %ld samples; max |driver - IR| %.3g ulp "
		       "(%s, tolerance there %.3g ulp); time: glslang %.2f s, lavapipe "
		       "pipelines %.2f s, run %.2f s, check %.2f s\n",
		       bk_precision_name(prec), fns->n, b.npipe, st->samples, st->bounded, st->unbounded, st->undefined, st->mostly_unbounded,
		       st->failed,
		       st->driver_out, st->ir_out, st->kind, st->orders, st->irnan, st->flushkind, st->open, st->overkind, st->flushed, st->flushed_fns, st->folded, st->folded_fns, st->slack, st->max_ulp,
		       *st->max_at ? st->max_at : "-", st->max_ulp_tol, t1 - t0, t[0], t[1],
		       bk_clock_now() - t2);
	free_batch(&b);
	free(out);
	return rc;
}

/* ---- main ------------------------------------------------------------------- */

static int parse(int argc, char **argv, opts *o, vk_fns *fns, char *err, size_t errlen)
{
	for (int i = 1; i < argc; i++) {
		const char *a = argv[i], *val = i + 1 < argc ? argv[i + 1] : NULL;
		char *end;
		if (!strcmp(a, "--samples") && val) {
			long n = strtol(val, &end, 10);
			if (*end || n < 1 || n > 1 << 20)
				return usage("--samples: a count in [1, 1048576]"), 2;
			o->samples = (int)n, i++;
		} else if (!strcmp(a, "--fuzz") && val) {
			long n = strtol(val, &end, 10);
			if (*end || n < 1 || n > 100000)
				return usage("--fuzz: a count in [1, 100000]"), 2;
			o->fuzz = (int)n, i++;
		} else if (!strcmp(a, "--seed") && val) {
			unsigned long n = strtoul(val, &end, 10);
			if (*end || !*val || val[0] == '-')
				return usage("--seed: a non-negative integer"), 2;
			o->seed = n, i++;
		} else if (!strcmp(a, "--factor") && val) {
			o->factor = strtod(val, &end);
			if (*end || !isfinite(o->factor))
				return usage("--factor: a number"), 2;
			i++;
		} else if (!strcmp(a, "--perturb") && val && !o->nan)
			o->perturb = argv[++i];
		else if (!strcmp(a, "--nan") && val && !o->perturb)
			o->nan = argv[++i];
		else if (!strcmp(a, "--list"))
			o->list = 1;
		else if (!strcmp(a, "--verbose"))
			o->verbose = 1;
		else if (!strcmp(a, "--ir-half"))
			o->ir_half = 1;
		else if (!strcmp(a, "--precise"))
			o->hb.precise = 1;
		else if (!strcmp(a, "--half-front") && val)
			o->hb.front = argv[++i];
		else if (!strcmp(a, "--target") && val)
			o->hb.target = argv[++i];
		else if ((!strcmp(a, "--ior") || !strcmp(a, "--k")) && val) {
			double x = strtod(val, &end);
			if (*end || !*val || !isfinite(x))
				return usage("--ior, --k: a number"), 2;
			*(a[2] == 'i' ? &o->hb.ior : &o->hb.k) = x, i++;
		} else if ((!strcmp(a, "--nx") || !strcmp(a, "--nr")) && val) {
			long n = strtol(val, &end, 10);
			if (*end || n < 1 || n > 4096)
				return usage("--nx, --nr: a count in [1, 4096]"), 2;
			*(a[3] == 'x' ? &o->hb.nx : &o->hb.nr) = (int)n, i++;
		}
		else if (a[0] == '-')
			return usage("unknown option, a missing value, or --perturb with --nan"), 2;
		else {
			size_t n = strlen(a);
			int csv = n > 4 && !strcmp(a + n - 4, ".csv"), glsl = n > 5 && !strcmp(a + n - 5, ".glsl");
			if (!csv && !glsl)
				return usage("a file must be a front.csv or a shader.glsl"), 2;
			if ((csv ? vk_add_front : vk_add_glsl)(fns, a, err, errlen))
				return 1;
		}
	}
	return 0;
}

/* The negative control's edit of one function's text. */
static int apply_control(vk_fns *fns, const opts *o)
{
	const char *label = o->perturb ? o->perturb : o->nan;
	if (!label)
		return 0;
	for (int i = 0; i < fns->n; i++)
		if (!strcmp(fns->v[i].label, label)) {
			char *t = vk_perturb(fns->v[i].glsl, fns->v[i].name, o->factor, o->nan != NULL);
			if (!t) {
				fprintf(stderr, "vkrun: %s: no literal or return to change\n", label);
				return 1;
			}
			free(fns->v[i].glsl);
			fns->v[i].glsl = t;
			return 0;
		}
	fprintf(stderr, "vkrun: no function labelled '%s' (--list names them)\n", label);
	return 1;
}

/* --half-front: the front's float16_t code against its stated errors. */
static int half_front(opts *o, vk_fns *fns)
{
	char err[1024], driver[200] = "";
	bk_lvp *v = NULL;
	int rc;
	vk_fns_free(fns);
	if (!o->hb.front || !o->hb.target)
		return usage("--half-front and --target go together");
	o->hb.perturb = o->perturb;
	o->hb.factor = o->factor;
	o->hb.verbose = o->verbose;
	if ((rc = bk_lvp_open(&v, driver, sizeof driver, err, sizeof err)) != 0) {
		fprintf(stderr, "vkrun: %s\n", err);
		return 3;
	}
	printf("vkrun: %s; half front %s on target %s\n", driver, o->hb.front, o->hb.target);
	rc = vk_halfbound(v, &o->hb);
	bk_lvp_close(v);
	return rc < 0 ? 3 : rc;
}

int main(int argc, char **argv)
{
	opts o = {.samples = 1024, .factor = 1.001, .hb = {.ior = NAN, .k = NAN}};
	vk_fns fns = {.groups = 1};
	char err[1024], driver[200] = "";
	int rc = vk_add_catalog(&fns, err, sizeof err) ? 1 : parse(argc, argv, &o, &fns, err, sizeof err);
	if (!rc && (o.hb.front || o.hb.target))
		return half_front(&o, &fns);
	if (!rc && o.fuzz && vk_add_fuzz(&fns, o.fuzz, o.seed, err, sizeof err))
		rc = 1;
	if (rc == 1)
		fprintf(stderr, "vkrun: %s\n", err);
	if (!rc && o.list)
		for (int i = 0; i < fns.n; i++)
			printf("%s\n", fns.v[i].label);
	if (rc || o.list || (rc = apply_control(&fns, &o))) {
		vk_fns_free(&fns);
		return rc;
	}
	grid g = {0};
	bk_lvp *v = NULL;
	if (make_grid(&fns, o.samples, &g)) {
		fprintf(stderr, "vkrun: out of memory\n");
		rc = 1;
	} else if ((rc = bk_lvp_open(&v, driver, sizeof driver, err, sizeof err)) != 0) {
		fprintf(stderr, "vkrun: %s\n", err);
		rc = 1;
	}
	stats st[2] = {{.verbose = o.verbose, .ir_half = o.ir_half}, {.verbose = o.verbose}};
	if (!rc) {
		printf("vkrun: %s; %d functions, %zu samples each precision\n", driver, fns.n, g.total);
		rc = run_precision(v, &fns, &g, BK_F32, &st[0]) || run_precision(v, &fns, &g, BK_F16, &st[1]);
		int failed = st[0].failed + st[1].failed;
		if (!rc && failed)
			printf("vkrun: %d functions differ (f32 %d, f16 %d)\n", failed, st[0].failed, st[1].failed);
		rc = rc || failed ? 1 : 0;
	}
	bk_lvp_close(v);
	free(g.off);
	free(g.n);
	free(g.in);
	vk_fns_free(&fns);
	return rc;
}
