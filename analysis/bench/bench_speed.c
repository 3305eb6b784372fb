/*
 * bench_speed.c — make bench: the search's throughput (issue 22), old and new
 * side by side in one run, CPU time as well as wall time (the machine is
 * shared: CPU time is what a run costs, wall time what it waits).
 *
 *   1. screening fits/s: the search of bench_search (vf2d 32x32, 1,024
 *      samples, default grammar, <= 4 parameters, 20,000 fits), 1 and 2
 *      threads, median of REPS interleaved runs. Target: >= 10,000 on 2 threads.
 *   1b. the same screening fits, one per candidate of that run, from p = 1
 *      with the screening options, 1 thread, thread CPU time: the fitter as
 *      it was before issue 22's part 3 (TinySolver of dynamic sizes fed a
 *      row-major Jacobian, bk_tiny_fixed = bk_fit_ctx_cols = 0) against now
 *      (fixed sizes, the Jacobian by columns): a fixed workload, so the ratio
 *      is the fitter's alone (1.'s two sides may search apart).
 *   2. the fit's residual and Jacobian pass, old and new, over the run's
 *      candidates at their fitted constants: bk_form_eval_diff (every
 *      instruction at every call: old) against a bk_form_bind'ed form (what
 *      reads no parameter kept from the first call: new, what the fits use),
 *      the same values bit for bit (checked here too).
 *   3. IR tree nodes/s in f32 over the run's candidates, 1 thread, parsed
 *      once, median of 9 (bench_search's figure parses each candidate per
 *      8 evaluations, which this leaves out), thread CPU time: libm's scalar
 *      exp2f and log2f (old, bk_ir_force_libm) against brdf/vmath.h's (new),
 *      each in the baseline kernels and the AVX2 ones where the CPU has it
 *      (ir_eval.c's dispatch); the new side's two copies checked for the same
 *      bits in f32 and f16. Target: >= 6 G nodes/s per core.
 *
 * Issue 22 part 3 (TinySolver of fixed sizes fed the Jacobian by columns,
 * fit/tiny.cc, fit_ctx.c; a parameter's column written by vector stores,
 * brdf/ir_adjoint.h), this machine shared (load ~4 on 2 cores), CPU time:
 * 1. new, 1 thread, 1,751 fits per CPU-s (main before it, run in the same
 * hour) -> 2,291 (1.31x); 2 threads 1,834 -> 2,281 per CPU-s; 1b. the same
 * 20,104 fits 2,963 -> 3,676 per thread CPU-s (1.24x, iterations the same);
 * 3. unchanged (3.6 G: libm's scalar exp2f and log2f are ~45 % of the AVX2
 * path's time, so even free arithmetic stays under 6 G). The 10,000 fits/s
 * target stays out of reach: of a screening fit, the IR's passes are ~40 %
 * (libm's exp2 8 %), Eigen's blocked JᵀJ inside TinySolver ~18 %, its Jacobi
 * scaling and Jᵀr ~8 %, the residual glue ~9 % (perf).
 *
 * Issue 22, vectorised exp2 and log2 (brdf/vmath.h) and whole blocks' input
 * and output conversions vectorised (ir_eval.c), 3., AVX2, thread CPU time,
 * the 2 cores shared (load 9-17), medians of 9: libm 4.48-4.85 G -> vmath
 * 7.79-8.45 G nodes per CPU-s (1.68-1.74x); with the conversions as before
 * (what main ran: libm and scalar conversions) 3.87 G, vmath alone on them
 * 5.84 G. Per run of 3 medians the figure moved by +-20 % with the load.
 *
 * Issue 22, screening's iteration cap 40 -> 20 (fit/search/screen.c), idle,
 * wall: 1. 2,007 -> 3,103 fits/s on 1 thread, 3,701 -> 5,682 on 2 (1.54x;
 * the old side, 1,053 -> 1,544, moves with it: its searches fit with the same
 * cap); 3. 9.42 G nodes/s. make results' seven double searches, whose CPU
 * also holds the refit of the front and the outputs, took a sixth less CPU.
 *
 * Issue 22, f64 exp2 and log2 from brdf/vmath.h (bits independent of the
 * CPU's FMA; vectorised, 4 at a time in the AVX2 copy) in place of glibc's:
 * brdfkit search --target vf2d --evals 20000 --threads 1, farm-bench --vs
 * the tool before, 5 pairs, idle: CPU new/old 0.986 (0.956-1.133), the same
 * candidates.csv byte for byte. Neutral in speed: glibc's scalar exp2 was
 * ~7 % of the time, the vectorised one about as much (a 14-term polynomial
 * and exact products, for 0.62 ulp).
 *
 * Issue 22, 2-thread wall time (this machine: AMD EPYC, AVX-512, 48 KiB L1d,
 * idle), every step the same candidates byte for byte: a step's generation
 * was serial, 0.385 s of a 2.37 s run (16 %), while the other thread
 * waited. Neighbour lists tried whole are not made again (0.385 -> 0.138 s):
 * 8,397 -> ~9,250 fits/s; the fits start while the batch is made
 * (bk_screen_begin/ready/end): 9,552; a fit's set-up without libm calls and
 * the residuals' finiteness check with four partial sums: 9,943; the merge
 * beside the step's last fits: 10,038; the cols callback reporting
 * non-finite residuals (no second read) and one copy of a trial's values:
 * 9,911-10,072 over runs. Tried and dropped: the trial's Jacobian deferred
 * to its acceptance (the forward pass kept on a tape, ~240 KB a form; a
 * third of the trials are rejected, but the tape's traffic through L2 cost
 * more than their sweeps: 1 thread 5,040 -> 4,800 fits per CPU-s), and IR
 * blocks of 256 samples (no faster than 128).
 *
 * Issue 22, a bound form's later calls (brdf/ir_diff.c), the same machine,
 * idle, the same candidates byte for byte: the result's instruction written
 * straight into the caller's values (no copy of each block) and a
 * parameter's broadcast reading its value once (the compiler had reloaded
 * it at every sample, as the store might alias it, and left the loop
 * scalar): bound_eval 5.7 -> 3.3 % of a 1-thread run (perf); 1b-style A/B
 * of `bench_speed 20000 new`, five interleaved pairs: 5,149 -> 5,269 fits
 * per CPU-s; whole calls: 2 threads 10,417-10,524 (was 9,998-10,192).
 */
#include "brdf.h"
#include "clock.h"
#include "brdf_ops.h" /* bk_ir_force_generic: the old side */
#include "bench_vf2d.h"
#include "search.h"
#include "solver.h"
#include "switches.h" /* the old side */

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define REPS 3
#define EVALS 20000

static double thread_cpu_now(void)
{
	struct timespec t;
	clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
	return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static bk_search *run_search(const bk_search_options *o, double *wall, double *cpu)
{
	char err[256];
	bk_search *s = bk_search_new(o, err, sizeof err);
	if (!s) {
		fprintf(stderr, "bench_speed: %s\n", err);
		exit(1);
	}
	double t0 = bk_clock_now(), c0 = bk_clock_cpu();
	if (bk_search_run(s, NULL, NULL, err, sizeof err) < 0) {
		fprintf(stderr, "bench_speed: %s\n", err);
		exit(1);
	}
	*wall = bk_clock_now() - t0;
	*cpu = bk_clock_cpu() - c0;
	return s;
}

typedef struct cand {
	bk_form *f;
	double p[BK_MAX_PARAMS];
	double nodes; /* tree nodes, as bench_search counts them */
} cand;

int main(int argc, char **argv)
{
	/* bench_speed [EVALS [nodes|new]] (profiling): nodes skips the timed
	 * searches; new runs the new side's search once, 1 thread, and stops */
	int evals = argc > 1 ? atoi(argv[1]) : EVALS, only_nodes = argc > 2 && strcmp(argv[2], "nodes") == 0;
	int only_new = argc > 2 && strcmp(argv[2], "new") == 0;
	int only_fits = argc > 2 && strcmp(argv[2], "fits") == 0; /* 1b alone */
	bk_samples sm;
	bk_search_options o;
	bench_vf2d_case("bench_speed", evals, &sm, &o);

	printf("bench_speed: vf2d 32x32 (%zu samples), default grammar, <= 4 parameters, %d fits per run, median of %d\n",
	       sm.n, evals, REPS);
	/* old: every instruction at every call, the x86-64 baseline kernels, a
	 * trial point evaluated again when accepted, TinySolver with dynamic
	 * sizes fed a row-major Jacobian (what main had before issue 22, but for
	 * -fno-math-errno and the vectorised residual loops, which are per file);
	 * new: bound forms, AVX2 where the CPU has it, the trial's Jacobian kept,
	 * TinySolver of fixed sizes fed by columns. Interleaved. The fixed sizes
	 * sum in another order, so the two sides' searches may part ways (other
	 * candidates, other fits): 1b times the same fits on both. */
	bk_search *keep = NULL;
	if (only_new || only_fits) {
		double w, c;
		o.threads = 1;
		keep = run_search(&o, &w, &c);
		printf("  new, 1 thread: %.0f fits per CPU-s\n", evals / c);
		if (only_new) {
			bk_search_free(keep);
			bk_samples_free(&sm);
			return 0;
		}
	}
	double wall[2][2][REPS], cpu[2][2][REPS];
	for (int r = 0; r < (only_nodes ? 1 : only_fits ? 0 : REPS); r++)
		for (int side = only_nodes; side < 2; side++)
			for (int th = 1; th <= 2 - only_nodes; th++) {
				bk_fit_ctx_bind = side;
				bk_tiny_reuse_trial = side;
				bk_tiny_fixed = side;
				bk_fit_ctx_cols = side;
				bk_ir_force_generic(side == 0);
				o.threads = th;
				bk_search *s = run_search(&o, &wall[side][th - 1][r], &cpu[side][th - 1][r]);
				if (!keep)
					keep = s;
				else
					bk_search_free(s);
			}
	bk_fit_ctx_bind = 1;
	bk_tiny_reuse_trial = 1;
	bk_tiny_fixed = 1;
	bk_fit_ctx_cols = 1;
	bk_ir_force_generic(0);
	for (int th = 0; th < 2 && !only_nodes && !only_fits; th++) {
		double w[2], c[2];
		for (int side = 0; side < 2; side++)
			w[side] = bk_clock_median(wall[side][th], REPS), c[side] = bk_clock_median(cpu[side][th], REPS);
		printf("  screening fits/s, %d thread%s: old %6.0f wall %6.0f per CPU-s | new %6.0f wall %6.0f per CPU-s | "
		       "new/old CPU %.2fx%s\n",
		       th + 1, th ? "s" : " ", evals / w[0], evals / c[0], evals / w[1], evals / c[1], c[0] / c[1],
		       th ? (evals / w[1] >= 10000 ? "   (target >= 10000 wall: met)" : "   (target >= 10000 wall: NOT met)")
		          : "");
	}

	/* the run's candidates, parsed once */
	size_t nc = bk_search_count(keep), k = 0;
	cand *cs = calloc(nc, sizeof *cs);
	for (size_t i = 0; i < nc; i++) {
		const bk_cand *c = bk_search_at(keep, i);
		bk_form_error fe;
		if (c->text_b || !c->np || !(cs[k].f = bk_form_parse(c->text, &fe)))
			continue;
		memcpy(cs[k].p, c->p, sizeof cs[k].p);
		for (int j = 0; j < BK_MAX_PARAMS; j++)
			if (!isfinite(cs[k].p[j]))
				cs[k].p[j] = 1;
		cs[k].nodes = (double)(c->ntree[0] + 2);
		k++;
	}
	nc = k;
	/* 1b. the same screening fits, one per candidate of the run, from the
	 * same start, with the fitter as main had it before this change (TinySolver
	 * with dynamic sizes) and as now: a fixed workload, so unlike 1. its ratio
	 * is the fitter's speed alone (a change of the last bits changes the
	 * search's path and so its candidates) */
	double tf[2][REPS] = {{0}};
	long iters[2] = {0}, failed[2] = {0};
	for (int r = 0; r < (only_nodes ? 0 : REPS); r++)
		for (int side = 0; side < 2; side++) {
			bk_tiny_fixed = side;
			bk_fit_ctx_cols = side;
			failed[side] = 0, iters[side] = 0;
			double t0 = thread_cpu_now();
			for (size_t i = 0; i < nc; i++) {
				bk_fit_spec spec;
				memset(&spec, 0, sizeof spec);
				spec.s = &sm;
				spec.form[0] = spec.form[1] = cs[i].f;
				spec.np = bk_form_nparams(cs[i].f);
				bk_fit_options fo = BK_FIT_OPTIONS_INIT;
				fo.max_iterations = 40; /* fit/search/screen.c's screening options */
				fo.function_tolerance = 1e-6;
				fo.parameter_tolerance = 1e-8;
				spec.opt = fo;
				spec.relative = o.relative;
				spec.starts = 1;
				for (int j = 0; j < BK_MAX_PARAMS; j++)
					spec.lower[j] = -HUGE_VAL, spec.upper[j] = HUGE_VAL;
				bk_fit_problem *pb = bk_fit_problem_new(&spec);
				double p[BK_MAX_PARAMS];
				for (int j = 0; j < BK_MAX_PARAMS; j++)
					p[j] = 1;
				bk_fit_summary sum;
				if (pb && bk_fit_problem_solve(pb, p, NULL, &sum) == 0 && sum.termination != BK_TERM_FAILURE)
					iters[side] += sum.iterations;
				else
					failed[side]++;
				bk_fit_problem_free(pb);
			}
			tf[side][r] = thread_cpu_now() - t0;
		}
	bk_tiny_fixed = 1;
	bk_fit_ctx_cols = 1;
	if (!only_nodes) {
		double f0 = bk_clock_median(tf[0], REPS), f1 = bk_clock_median(tf[1], REPS);
		printf("  the same screening fits of the run's %zu candidates from p = 1, 1 thread, fits per thread CPU-s:\n"
		       "    before (dynamic sizes, rows) %.0f   now (fixed sizes, columns) %.0f   %.2fx"
		       "   (iterations %ld vs %ld, failed %ld vs %ld)\n",
		       nc, nc / f0, nc / f1, f0 / f1, iters[0], iters[1], failed[0], failed[1]);
	}
	const double *const *in = (const double *const *)sm.in;
	double *v0 = malloc(sizeof(double) * sm.n), *v1 = malloc(sizeof(double) * sm.n);
	double *j0 = malloc(sizeof(double) * sm.n * BK_MAX_PARAMS), *j1 = malloc(sizeof(double) * sm.n * BK_MAX_PARAMS);

	/* 2. residual + Jacobian passes: a fit's mix, ~2 with the Jacobian to 1
	 * without (TinySolver evaluates each accepted point with it) */
	enum { PASSES = 12 };
	double td[2][REPS] = {{0}};
	size_t differ = 0;
	for (int r = 0; r < (only_nodes || only_fits ? 0 : REPS); r++)
		for (int m = 0; m < 2; m++) {
			double t0 = thread_cpu_now();
			for (size_t i = 0; i < nc; i++) {
				if (m == 0) {
					for (int q = 0; q < PASSES; q++)
						if (q % 3 == 2)
							bk_form_eval(cs[i].f, BK_F64, sm.n, in, cs[i].p, v0);
						else
							bk_form_eval_diff(cs[i].f, sm.n, in, cs[i].p, v0, j0);
				} else {
					bk_form_bound *b = bk_form_bind(cs[i].f, sm.n, in);
					for (int q = 0; q < PASSES; q++)
						bk_form_bound_eval(b, cs[i].p, v1, q % 3 == 2 ? NULL : j1);
					bk_form_bound_free(b);
				}
			}
			td[m][r] = thread_cpu_now() - t0;
		}
	for (size_t i = 0; i < nc; i++) { /* the same bits */
		int np = bk_form_nparams(cs[i].f);
		bk_form_eval_diff(cs[i].f, sm.n, in, cs[i].p, v0, j0);
		bk_form_bound *b = bk_form_bind(cs[i].f, sm.n, in);
		bk_form_bound_eval(b, cs[i].p, v1, j1);
		bk_form_bound_eval(b, cs[i].p, v1, j1);
		bk_form_bound_free(b);
		differ += memcmp(v0, v1, sizeof(double) * sm.n) != 0 || memcmp(j0, j1, sizeof(double) * sm.n * np) != 0;
	}
	double old = bk_clock_median(td[0], REPS), new = bk_clock_median(td[1], REPS);
	if (!only_nodes && !only_fits)
		printf("  fit passes (values + Jacobian, 2 of 3 with it), %zu candidates x %d passes, thread CPU s:\n"
	       "    old (bk_form_eval_diff / bk_form_eval): %.3f s   new (bound): %.3f s   %.2fx; %zu differ in any bit%s\n",
	       nc, PASSES, old, new, old / new, differ, differ ? "   (MUST be 0)" : "");

	/* 3. f32 nodes/s, parsed once, thread CPU time: libm's scalar exp2f and
	 * log2f (old) against brdf/vmath.h's vectorised ones (new), each in the
	 * baseline kernels and in AVX2 (ir_eval.c's dispatch); interleaved */
	/* more runs than the searches: each is seconds, and the median of 9
	 * holds better than that of 3 against the other processes of a shared
	 * machine (their load moved the figure by +-20 % from run to run) */
	enum { NREPS = 9 };
	double tn[2][2][NREPS] = {{{0}}}, nodes = 0;
	for (size_t i = 0; i < nc; i++)
		nodes += 8.0 * (double)sm.n * cs[i].nodes;
	for (int r = 0; r < (only_fits ? 0 : NREPS); r++)
		for (int side = 0; side < 2; side++)
			for (int isa = 0; isa < 2; isa++) {
				bk_ir_force_libm(side == 0);
				bk_ir_force_generic(isa == 0);
				double t0 = thread_cpu_now();
				for (size_t i = 0; i < nc; i++)
					for (int q = 0; q < 8; q++)
						bk_form_eval(cs[i].f, BK_F32, sm.n, in, cs[i].p, v0);
				tn[side][isa][r] = thread_cpu_now() - t0;
			}
	/* the new side's two copies give the same bits, f32 and f16; and how
	 * many candidates' f32 values moved from libm's (near-ties of exp2f and
	 * log2f, an ulp each) */
	size_t copies_differ = 0, moved = 0, with_x2 = 0;
	for (size_t i = 0; i < nc && !only_fits; i++) {
		int ni;
		const bk_instr *code = bk_form_code(cs[i].f, &ni, NULL);
		int x2 = 0;
		for (int j = 0; j < ni; j++)
			x2 |= code[j].op == BK_OP_EXP2 || code[j].op == BK_OP_LOG2;
		with_x2 += x2;
		for (int p16 = 0; p16 < 2; p16++) {
			bk_precision pr = p16 ? BK_F16 : BK_F32;
			bk_ir_force_libm(0);
			bk_ir_force_generic(1);
			bk_form_eval(cs[i].f, pr, sm.n, in, cs[i].p, v0);
			bk_ir_force_generic(0);
			bk_form_eval(cs[i].f, pr, sm.n, in, cs[i].p, v1);
			copies_differ += memcmp(v0, v1, sizeof(double) * sm.n) != 0;
			if (!p16) {
				bk_ir_force_libm(1);
				bk_form_eval(cs[i].f, pr, sm.n, in, cs[i].p, v0);
				moved += memcmp(v0, v1, sizeof(double) * sm.n) != 0;
			}
		}
	}
	bk_ir_force_libm(0);
	bk_ir_force_generic(0);
	double gn[2][2];
	for (int side = 0; side < 2; side++)
		for (int isa = 0; isa < 2; isa++)
			gn[side][isa] = nodes / bk_clock_median(tn[side][isa], NREPS);
	if (!only_fits) {
		double g = gn[1][bk_ir_avx2()];
		printf("  IR tree nodes/s in f32, 1 thread, parsed once, per thread CPU-s, median of %d (%zu candidates, %zu with "
		       "exp2 or log2):\n"
		       "    old (libm exp2f/log2f): baseline %.3g, AVX2 %.3g | new (vmath.h): baseline %.3g, AVX2 %.3g | "
		       "new/old %.2fx%s\n"
		       "    new, baseline and AVX2 copies differ in any bit (f32, f16): %zu%s; candidates whose f32 values "
		       "moved from libm's: %zu\n",
		       (int)NREPS, nc, with_x2, gn[0][0], gn[0][1], gn[1][0], gn[1][1], g / gn[0][bk_ir_avx2()],
		       g >= 6e9 ? "   (target >= 6e9: met)" : "   (target >= 6e9: NOT met)", copies_differ,
		       copies_differ ? "   (MUST be 0)" : "", moved);
		if (!bk_ir_avx2())
			printf("    (no AVX2 on this CPU: the AVX2 columns ran the baseline copy)\n");
	}

	for (size_t i = 0; i < nc; i++)
		bk_form_free(cs[i].f);
	free(cs);
	free(v0), free(v1), free(j0), free(j1);
	bk_search_free(keep);
	bk_samples_free(&sm);
	return differ || copies_differ ? 1 : 0;
}
