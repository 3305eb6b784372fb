/*
 * bench_ir.c — make bench: the formula IR's evaluator (bk_form_eval, f64, f32
 * and f16) against the C that bk_form_emit writes for the same form, compiled
 * with the same compiler and flags (-O2), on the same 10^6 samples, side by
 * side. Time per sample is the median of REPS runs, the methods interleaved so
 * that machine noise hits them alike. The target (the IR issue): the IR within
 * 3x of the compiled code, so that fitting on 10^6 samples does not need a
 * compiler in the loop.
 *
 * One file, built twice (Makefile): with -DBENCH_IR_EMIT it is the generator
 * and prints, for each form, bk_form_emit's C byte for byte followed by a
 * sample loop calling it; the second build includes that output
 * (build/bench_ir_gen.h) and times it.
 *
 * Issue 22: the last two forms call exp2 and log2, which the f32 and f16
 * kernels now run as brdf/vmath.h's vectorised functions; "IR f32, libm" is
 * the same kernel with libm's exp2f and log2f (bk_ir_force_libm: what it ran
 * before), side by side.
 */
#include "clock.h"
#include "brdf.h"
#include "brdf_ops.h" /* the instruction count, for node evaluations per second */

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef struct bench_form {
	const char *name; /* of the generated function */
	const char *what;
	const char *text;
	double params[BK_MAX_PARAMS];
} bench_form;

static const bench_form forms[] = {
	{"bench_talk", "talk's specular D*VF (r^4, one division)",
	 "r^4 / (4*3.14159265*sq(NoH*NoH*(r^4 - 1) + 1) * LoH*LoH*(r + 0.5))", {0}},
	{"bench_ggx", "GGX D * correlated Smith V * Schlick F",
	 "D_ggx(NoH,a) * V_smith_ggx_correlated(NoV,NoL,a) * F_schlick(f0,1,LoH)", {0}},
	{"bench_sg", "Schlick's Fresnel as a spherical Gaussian (exp2)",
	 "f0 + (1 - f0)*exp2((-5.55473*LoH - 6.98316)*LoH)", {0}},
	{"bench_phong", "a normalised Blinn-Phong lobe through exp2 and log2",
	 "(34/8)*exp2(32*log2(NoH)) * NoL", {0}},
};
enum { NFORMS = sizeof forms / sizeof forms[0] };

static bk_form *parse_or_die(const char *text)
{
	bk_form_error err;
	bk_form *f = bk_form_parse(text, &err);
	if (!f) {
		fprintf(stderr, "bench_ir: '%s': column %d: %s\n", text, err.column, err.message);
		exit(1);
	}
	return f;
}

#ifdef BENCH_IR_EMIT

/* The loop is the bench's, not the generator's: the same double arrays
 * bk_form_eval reads, rounded to float on the way in as the f32 kernel does. */
static void print_loop(const bench_form *b, const bk_form *f)
{
	printf("static void run_%s(size_t n, const double *const *in, double *out)\n{\n", b->name);
	printf("\tfor (size_t k = 0; k < n; k++)\n\t\tout[k] = %s(", b->name);
	const char *sep = "";
	for (int i = 0; i < BK_IN_COUNT; i++)
		if (bk_form_inputs(f) >> i & 1) {
			printf("%s(float)in[%d][k]", sep, i);
			sep = ", ";
		}
	printf(");\n}\n\n");
}

int main(void)
{
	printf("/* build/bench_ir_gen.h: made by build/bench_ir_emit (make bench). */\n#include <stddef.h>\n\n");
	for (int i = 0; i < NFORMS; i++) {
		bk_form *f = parse_or_die(forms[i].text);
		bk_emit_info info = {forms[i].name, forms[i].what, NULL, NULL, NULL,
		                     "build/bench_ir_emit > build/bench_ir_gen.h"};
		char *code = bk_form_emit(f, BK_LANG_C, 0, forms[i].params, &info);
		if (!code) {
			fprintf(stderr, "bench_ir: cannot emit '%s'\n", forms[i].text);
			return 1;
		}
		fputs(code, stdout);
		putchar('\n');
		print_loop(&forms[i], f);
		free(code);
		bk_form_free(f);
	}
	printf("static void (*const compiled[])(size_t, const double *const *, double *) = {");
	for (int i = 0; i < NFORMS; i++)
		printf("%srun_%s", i ? ", " : "", forms[i].name);
	printf("};\n");
	return ferror(stdout) ? 1 : 0;
}

#else

#include "bench_ir_gen.h"

#define N 1000000
#define REPS 9

enum { IR64, IR32, IR16, COMPILED, IR32_LIBM, NMETHODS };
static const char *const method_name[NMETHODS] = {"IR f64", "IR f32", "IR f16", "emitted C, -O2", "IR f32, libm"};


/* Cosines in (0, 1], r in [0.02, 1] (a = r*r), f0 in [0.02, 1]: the physical
 * domain, from a fixed sequence so that every run times the same samples. */
static void fill_inputs(double *in[BK_IN_COUNT])
{
	unsigned long long s = 1;
	for (size_t k = 0; k < N; k++)
		for (int i = 0; i < BK_IN_COUNT; i++) {
			s = s * 6364136223846793005ull + 1442695040888963407ull;
			double u = (double)(s >> 11) * 0x1p-53;
			in[i][k] = i == BK_IN_R || i == BK_IN_F0 ? 0.02 + 0.98 * u : 1.0 - u;
		}
	for (size_t k = 0; k < N; k++)
		in[BK_IN_A][k] = in[BK_IN_R][k] * in[BK_IN_R][k];
}

/* thread CPU time: the machine may be shared (wall time counts the others) */
static double cpu_now(void)
{
	struct timespec t;
	clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
	return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static double run(int method, const bk_form *f, int form, const double *const *in, double *out)
{
	double t = cpu_now();
	bk_ir_force_libm(method == IR32_LIBM);
	if (method == COMPILED)
		compiled[form](N, in, out);
	else if (bk_form_eval(f, method == IR64 ? BK_F64 : method == IR16 ? BK_F16 : BK_F32, N, in,
	                      forms[form].params, out)) {
		fprintf(stderr, "bench_ir: bk_form_eval failed\n");
		exit(1);
	}
	t = cpu_now() - t;
	bk_ir_force_libm(0);
	return t;
}

/* The emitted C and the f32 kernel do the same float operations: they should
 * agree exactly (but where vmath's exp2 or log2 and libm's, which the C
 * calls, round a near-tie apart: an ulp there); a larger difference would
 * make the timing comparison meaningless. */
static double max_rel_diff(const double *x, const double *y)
{
	double m = 0;
	for (size_t k = 0; k < N; k++)
		if (x[k] != y[k])
			m = fmax(m, fabs(x[k] - y[k]) / fmax(fabs(x[k]), fabs(y[k])));
	return m;
}

int main(void)
{
	double *in[BK_IN_COUNT], *out[NMETHODS];
	for (int i = 0; i < BK_IN_COUNT; i++)
		if (!(in[i] = malloc(N * sizeof(double))))
			return 1;
	for (int m = 0; m < NMETHODS; m++)
		if (!(out[m] = malloc(N * sizeof(double))))
			return 1;
	fill_inputs(in);
	const double *const *cin = (const double *const *)in;

	static double times[NFORMS][NMETHODS][REPS];
	bk_form *f[NFORMS];
	for (int j = 0; j < NFORMS; j++) {
		f[j] = parse_or_die(forms[j].text);
		for (int m = 0; m < NMETHODS; m++) /* warm-up: page faults, caches */
			run(m, f[j], j, cin, out[m]);
	}
	fprintf(stderr, "bench_ir: %d forms x %d methods, %d runs each, interleaved\n", NFORMS, NMETHODS, REPS);
	for (int rep = 0; rep < REPS; rep++)
		for (int j = 0; j < NFORMS; j++)
			for (int m = 0; m < NMETHODS; m++)
				times[j][m][rep] = run(m, f[j], j, cin, out[m]);

	printf("formula IR vs emitted C, %d samples, median of %d interleaved runs, single thread, thread CPU time\n", N,
	       REPS);
	int met = 1;
	for (int j = 0; j < NFORMS; j++) {
		for (int m = 0; m < NMETHODS; m++)
			run(m, f[j], j, cin, out[m]);
		bk_ops ops;
		bk_form_count(f[j], &ops);
		printf("\n%s: %s\n  %s\n  %d ops (%d simple, %d complex); emitted C vs IR f32: max rel diff %.3g\n",
		       forms[j].name, forms[j].what, forms[j].text, ops.simple + ops.complex, ops.simple,
		       ops.complex, max_rel_diff(out[IR32], out[COMPILED]));
		double tc = bk_clock_median(times[j][COMPILED], REPS);
		/* node evaluations per second (the issue-10 figure; PySR publishes
		 * ~0.5 G per thread): operations x samples / time, and the same
		 * counting every IR instruction, loads of inputs, constants and
		 * parameters included (a tree's leaves are nodes too) */
		int ops_n = ops.simple + ops.complex, instrs;
		bk_form_code(f[j], &instrs, NULL);
		printf("  %-16s %12s %14s %14s %14s\n", "method", "ns/sample", "x emitted C", "G ops/s", "G instr/s");
		for (int m = 0; m < NMETHODS; m++) {
			double t = bk_clock_median(times[j][m], REPS);
			printf("  %-16s %12.2f %14.2f %14.3f %14.3f\n", method_name[m], 1e9 * t / N, t / tc,
			       1e-9 * ops_n * N / t, 1e-9 * instrs * N / t);
			if ((m == IR64 || m == IR32) && t > 3 * tc)
				met = 0;
		}
		bk_form_free(f[j]);
	}
	printf("\ntarget: IR f64 and f32 within 3x of the emitted C -> %s\n", met ? "met" : "NOT met");
	for (int i = 0; i < BK_IN_COUNT; i++)
		free(in[i]);
	for (int m = 0; m < NMETHODS; m++)
		free(out[m]);
	return 0;
}

#endif
