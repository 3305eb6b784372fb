/*
 * switches.h — the fitter's benchmark switches (internal: not installed, not
 * exported from libbrdfkit-fit.so). They select the old side of make bench's
 * side-by-side (analysis/bench/bench_speed.c) and the tests that compare the
 * two sides bit for bit; a program of the installed API has no reason to
 * touch them, so they stay out of its headers (issue 40).
 * Each is 1 by default; set before any fit or solve starts, never during one.
 */
#ifndef FIT_SWITCHES_H
#define FIT_SWITCHES_H

#ifdef __cplusplus
extern "C" {
#endif

/* 1: bk_solve_tiny_reusing keeps the trial step's values (fit/tiny.cc); 0:
 * it is bk_solve_tiny (bench_speed's "old" side). */
extern int bk_tiny_reuse_trial;
/* 1: TinySolver is instantiated with the free parameters' count fixed at
 * compile time where it is 1..4 (fit/tiny.cc, solve_n); 0: always with
 * dynamic sizes (bench_speed's "old" side; other last bits). */
extern int bk_tiny_fixed;
/* 1: residual blocks use forms bound to their samples (brdf.h, bk_form_bind);
 * 0: the plain evaluators, every instruction at every call (the same bits,
 * only slower). */
extern int bk_fit_ctx_bind;
/* 1: TinySolver's fits take the Jacobian by columns (bk_solve_tiny_cols); 0:
 * row-major (bk_solve_tiny_reusing), as before (the same bits). */
extern int bk_fit_ctx_cols;

#ifdef __cplusplus
}
#endif

#endif
