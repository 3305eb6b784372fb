/*
 * halfbound.c — a half front's float16_t code against its stated error, on
 * lavapipe (halfbound.h).
 */
#include "halfbound.h"
#include "envelope.h"

#include "fit.h"
#include "frontcsv.h"
#include "gpucost.h"
#include "ir.h"
#include "out.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SLOTS 8         /* floats per sample in the input buffer (lvp.h) */
#define PER_SHADER 24   /* members per compute shader, as vkrun's */
#define CSV_DIGITS 5e-6 /* front.csv's error is printed %.6g (search_write.c): half a unit of its last digit */

/* The shader of members [first, first + k): their float16_t text as
 * emitted, a switch on pc.fn; inputs converted to float16_t on load, as a
 * half shader gets them. */
static char *shader(char *const *text, const unsigned *args, int first, int k)
{
	bk_strbuf b = {0};
	bk_lvp_head(&b, BK_F16);
	for (int j = 0; j < k; j++)
		bk_sb_put(&b, "%s\n", text[first + j]);
	bk_sb_put(&b, "void main()\n{\n\tuint k = gl_GlobalInvocationID.x;\n\tif (k >= pc.n)\n\t\treturn;\n"
	              "\tuint i = (pc.in_off + k) * 8u;\n");
	for (int c = 0; c < BK_IN_COUNT; c++)
		bk_sb_put(&b, "\tfloat16_t %s = float16_t(inb.v[i + %du]);\n", bk_input_name((bk_input)c), c);
	bk_sb_put(&b, "\tfloat bk_res = 0.0;\n\tswitch (pc.fn) {\n");
	for (int j = 0; j < k; j++) {
		bk_sb_put(&b, "\tcase %du: bk_res = float(bk_hm%d(", j, first + j);
		const char *sep = "";
		for (int c = 0; c < BK_IN_COUNT; c++)
			if (args[first + j] >> c & 1) {
				bk_sb_put(&b, "%s%s", sep, bk_input_name((bk_input)c));
				sep = ", ";
			}
		bk_sb_put(&b, ")); break;\n");
	}
	bk_sb_put(&b, "\t}\n\toutb.v[pc.out_off + k] = bk_res;\n}\n");
	if (b.oom) {
		free(b.s);
		return NULL;
	}
	return b.s;
}

/* The objective of the front's "# cost:" line on values v. */
static double objective(const char *name, const bk_samples *s, const double *v)
{
	bk_fit_metrics m;
	bk_samples_metrics(s, v, NULL, &m);
	if (m.nonfinite)
		return HUGE_VAL;
	return !strcmp(name, "max_abs") ? m.max_abs : m.rmse;
}

typedef struct run {
	bk_samples s;
	bk_frontcsv fc;
	bk_form **f;       /* per row; NULL for a split-sum row (skipped) */
	char **text;       /* per one-form member, in run order */
	unsigned *args;
	int *row;          /* run order -> row */
	int n;             /* members run */
	int perturbed;     /* the control's p0 was changed */
	float *in, *out;
} run;

static void run_free(run *R)
{
	for (int i = 0; R->f && i < R->fc.n; i++)
		bk_form_free(R->f[i]);
	for (int j = 0; R->text && j < R->n; j++)
		free(R->text[j]);
	free(R->f);
	free(R->text);
	free(R->args);
	free(R->row);
	free(R->in);
	free(R->out);
	bk_frontcsv_free(&R->fc);
	bk_samples_free(&R->s);
}

/* Target, front and the members' texts; 0, or -1 with err. */
static int setup(run *R, const vk_halfbound_opts *o, char *err, size_t errlen)
{
	bk_target_kind kind;
	bk_target_options to;
	if (bk_target_parse(o->target, &kind) || kind == BK_TARGET_FORM) {
		snprintf(err, errlen, "--target '%s': not a built-in target", o->target);
		return -1;
	}
	bk_target_defaults(kind, &to);
	if (o->nx > 0)
		to.nx = o->nx;
	if (o->nr > 0)
		to.nr = o->nr;
	if (!isnan(o->ior))
		to.eta = o->ior;
	if (!isnan(o->k))
		to.k = o->k;
	if (bk_target_build(&to, &R->s, NULL, NULL, err, errlen) ||
	    bk_frontcsv_read(o->front, BK_FRONTCSV_FORMS | BK_FRONTCSV_SCORES, &R->fc, err, errlen) ||
	    bk_frontcsv_head_check(&R->fc.head, o->front, BK_FRONTCSV_FRONT, "this run's", R->s.description, 1, NULL,
	                           "f16", err, errlen))
		return -1;
	if (strcmp(R->fc.head.objective, "rmse") && strcmp(R->fc.head.objective, "max_abs")) {
		snprintf(err, errlen, "%s: objective %s: only rmse and max_abs are measured here", o->front,
		         R->fc.head.objective);
		return -1;
	}
	int n = R->fc.n;
	R->f = calloc((size_t)n + 1, sizeof *R->f);
	R->text = calloc((size_t)n + 1, sizeof *R->text);
	R->args = calloc((size_t)n + 1, sizeof *R->args);
	R->row = calloc((size_t)n + 1, sizeof *R->row);
	R->in = calloc(R->s.n * SLOTS + 1, sizeof *R->in);
	R->out = calloc(R->s.n * (size_t)n + 1, sizeof *R->out);
	if (!R->f || !R->text || !R->args || !R->row || !R->in || !R->out) {
		snprintf(err, errlen, "out of memory");
		return -1;
	}
	for (size_t i = 0; i < R->s.n; i++)
		for (int c = 0; c < BK_IN_COUNT; c++)
			if (R->s.provides >> c & 1)
				R->in[i * SLOTS + (size_t)c] = (float)R->s.in[c][i];
	for (int i = 0; i < n; i++) {
		bk_frontcsv_row *w = &R->fc.row[i];
		if (w->form_b)
			continue;
		bk_form_error fe;
		if (!(R->f[i] = bk_form_parse(w->form, &fe))) {
			snprintf(err, errlen, "%s: %s: the form does not parse", o->front, w->name);
			return -1;
		}
		double q[BK_MAX_PARAMS]; /* the shader's constants; the control changes them, not the IR's */
		memcpy(q, w->p, sizeof q);
		if (o->perturb && !strcmp(o->perturb, w->name) && w->np > 0) {
			q[0] *= o->factor;
			R->perturbed = 1;
		}
		char name[32];
		snprintf(name, sizeof name, "bk_hm%d", R->n);
		bk_emit_info info = {.name = name};
		if (!(R->text[R->n] = bk_form_emit(R->f[i], BK_LANG_GLSL, BK_EMIT_F16, q, &info))) {
			snprintf(err, errlen, "%s: %s: code generation failed", o->front, w->name);
			return -1;
		}
		if (o->precise) { /* every temporary precise: no contraction, no reassociation */
			bk_strbuf b = {0};
			for (const char *t = R->text[R->n]; *t; t++)
				bk_sb_put(&b, t[0] == '\t' && !strncmp(t + 1, "float16_t t", 11) ? "\tprecise " : "%c", *t);
			free(R->text[R->n]);
			if (b.oom) {
				free(b.s);
				snprintf(err, errlen, "out of memory");
				return -1;
			}
			R->text[R->n] = b.s;
		}
		R->args[R->n] = bk_form_inputs(R->f[i]);
		R->row[R->n++] = i;
	}
	return 0;
}

static int execute(bk_lvp *v, run *R, char *err, size_t errlen)
{
	int npipe = (R->n + PER_SHADER - 1) / PER_SHADER;
	unsigned **spirv = calloc((size_t)npipe + 1, sizeof *spirv);
	size_t *nwords = calloc((size_t)npipe + 1, sizeof *nwords);
	bk_lvp_dispatch *d = calloc((size_t)R->n + 1, sizeof *d);
	int rc = spirv && nwords && d ? 0 : (snprintf(err, errlen, "out of memory"), -1);
	for (int p = 0; !rc && p < npipe; p++) {
		int first = p * PER_SHADER, k = R->n - first < PER_SHADER ? R->n - first : PER_SHADER;
		char *glsl = shader(R->text, R->args, first, k);
		if (!glsl || !(spirv[p] = bk_gpucost_spirv(glsl, &nwords[p], err, errlen)))
			rc = glsl ? -1 : (snprintf(err, errlen, "out of memory"), -1);
		free(glsl);
		for (int j = 0; j < k; j++)
			d[first + j] = (bk_lvp_dispatch){p, (uint32_t)j, 0, (uint32_t)((size_t)(first + j) * R->s.n),
			                                 (uint32_t)R->s.n};
	}
	double t[2];
	if (!rc)
		rc = bk_lvp_run(v, spirv, nwords, npipe, R->in, R->s.n * SLOTS, d, R->n, R->out, R->s.n * (size_t)R->n, t,
		                err, errlen);
	for (int p = 0; spirv && p < npipe; p++)
		free(spirv[p]);
	free(spirv);
	free(nwords);
	free(d);
	return rc;
}

/* Each member's measured error against its stated one; returns how many
 * exceed it, -1 out of memory. */
static int compare(const run *R, const vk_halfbound_opts *o)
{
	size_t n = R->s.n;
	double *v = malloc(sizeof *v * n * (3 + BK_IN_COUNT) + 1);
	if (!v)
		return -1;
	double *ir = v + n, *ir32 = ir + n, *hin = ir32 + n;
	double *uf = malloc(sizeof *uf * n * 2 + 1); /* the IR's f16 unfused and fused (bk_ir_eval_half_orders) */
	vk_env *env = malloc(sizeof *env * n + 1);
	double *far = malloc(sizeof *far * n + 1);
	if (!env || !far || !uf) {
		free(v), free(env), free(far), free(uf);
		return -1;
	}
	const double *hcols[BK_IN_COUNT] = {0};
	for (int c = 0; c < BK_IN_COUNT; c++) /* the inputs as the shader holds them: in half */
		if (R->s.provides >> c & 1) {
			for (size_t i = 0; i < n; i++)
				hin[(size_t)c * n + i] = bk_half_round(R->s.in[c][i]);
			hcols[c] = hin + (size_t)c * n;
		}
	const char *obj = R->fc.head.objective;
	int over = 0;
	double worst = 0, worst_env = 0;
	int within_orders = 0;
	const char *worst_name = "-";
	for (int j = 0; j < R->n; j++) {
		const bk_frontcsv_row *w = &R->fc.row[R->row[j]];
		for (size_t i = 0; i < R->s.n; i++)
			v[i] = R->out[(size_t)j * R->s.n + i];
		double got = objective(obj, &R->s, v), stated = w->error, irv = NAN;
		long same16 = 0, same32 = 0, either = 0;
		double orders[2] = {NAN, NAN};
		if (bk_form_eval(R->f[R->row[j]], BK_F16, R->s.n, (const double *const *)R->s.in, w->p, ir) == 0 &&
		    bk_form_eval(R->f[R->row[j]], BK_F32, n, hcols, w->p, ir32) == 0 &&
		    bk_ir_eval_half_orders(R->f[R->row[j]], n, hcols, w->p, uf, uf + n) == 0) {
			for (int q = 0; q < 2; q++)
				orders[q] = objective(obj, &R->s, uf + (size_t)q * n);
			for (size_t i = 0; i < n; i++)
				either += v[i] == uf[i] || v[i] == uf[n + i];
			irv = objective(obj, &R->s, ir);
			/* what the driver's values are: the IR's f16 (each operation
			 * rounded to half), or its f32 on the same half inputs and
			 * constants rounded once at the end (half stored, f32 inside) */
			size_t first = n;
			for (size_t i = 0; i < n; i++) {
				same16 += v[i] == ir[i];
				same32 += v[i] == bk_half_round(ir32[i]);
				first = first == n && v[i] != ir[i] && fabs(v[i] - R->s.y[i]) > fabs(ir[i] - R->s.y[i]) ? i : first;
			}
			if (o->verbose && first < n) { /* the first sample where the driver is further from the target */
				printf("  %s: at", w->name);
				for (int c = 0; c < BK_IN_COUNT; c++)
					if (R->args[j] >> c & 1)
						printf(" %s=%.9g", bk_input_name((bk_input)c), hcols[c][first]);
				printf(": lavapipe %.9g, the IR's f16 %.9g, f32 %.9g, exact %.9g\n", v[first], ir[first], ir32[first],
				       R->s.y[first]);
			}
		}
		/* The bound every conforming driver holds: at each sample the end of
		 * the Vulkan specification's envelope (tests/vk/envelope.h: each
		 * statement within its operation's ULPs, a denormal flushed) furthest
		 * from the target, through the same objective */
		double envb = NAN;
		vk_rules rules = {BK_F16, 1, 0, 0, 0};
		if (vk_envelope(R->f[R->row[j]], w->p, &rules, n, hcols, env) == 0) {
			for (size_t i = 0; i < n; i++)
				far[i] = env[i].any ? NAN : fabs(env[i].lo - R->s.y[i]) > fabs(env[i].hi - R->s.y[i]) ? env[i].lo
				                                                                                     : env[i].hi;
			envb = objective(obj, &R->s, far);
		}
		int holds = got <= stated * (1 + CSV_DIGITS);
		over += !holds;
		/* the bound the IR could state instead: the worse of its two orders'
		 * errors against the target (NaN: not computed, not within) */
		within_orders += got <= fmax(orders[0], orders[1]) * (1 + 1e-12);
		if (got / stated > worst) {
			worst = got / stated;
			worst_name = w->name;
		}
		if (o->verbose || !holds)
			printf("%s: %s cost %g: %s on lavapipe %.9g, stated %.9g (the IR's f16 %.9g), ratio %.6f; samples equal "
			       "to the IR's f16 %ld, to one of its two mad orders %ld, to its f32 rounded once to half %ld, of %zu; "
			       "%s of the IR's orders: unfused %.9g, fused %.9g; the specification's envelope allows %.9g (%.3f x "
			       "stated)\n",
			       holds ? "holds" : "EXCEEDS", w->name, w->cost, obj, got, stated, irv, got / stated, same16, either,
			       same32, n, obj, orders[0], orders[1], envb, envb / stated);
		worst_env = fmax(worst_env, envb / stated);
	}
	printf("half-front: %d of %d members hold their stated f16 %s on lavapipe (float16_t as emitted, no precise; "
	       "%zu samples of the target in double), %d split-sum rows not run; the largest measured/stated %.4f (%s)\n",
	       R->n - over, R->n, obj, R->s.n, R->fc.n - R->n, worst, worst_name);
	printf("half-front: %d of %d within the worse of the IR's two mad orders' %s against the target\n", within_orders,
	       R->n, obj);
	if (o->verbose)
		printf("half-front: the Vulkan specification's envelope allows up to %.3f x the stated error\n", worst_env);
	free(v);
	free(env);
	free(far);
	free(uf);
	return over;
}

int vk_halfbound(bk_lvp *v, const vk_halfbound_opts *o)
{
	run R = {0};
	char err[1024];
	int rc = setup(&R, o, err, sizeof err);
	if (!rc && o->perturb && !R.perturbed)
		rc = (snprintf(err, sizeof err, "--perturb %s: no one-form member of that name with a p0", o->perturb), -1);
	if (!rc)
		rc = execute(v, &R, err, sizeof err);
	if (!rc)
		rc = compare(&R, o);
	if (rc < 0)
		fprintf(stderr, "vkrun: %s\n", rc == -1 && *err ? err : "out of memory");
	run_free(&R);
	return rc < 0 ? -1 : rc > 0;
}
