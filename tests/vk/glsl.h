/*
 * glsl.h — the compute shaders tests/vk runs: many functions in one shader,
 * a push constant picks the one a dispatch calls.
 */
#ifndef TESTS_VK_GLSL_H
#define TESTS_VK_GLSL_H

#include "sources.h"

/* fns[0..n) in one compute shader, in f32 (the text as it is) or f16 (each
 * function rewritten to float16_t, see vk_half_text). Inputs: 8 floats per
 * sample in binding 0 (slot i: input i of brdf.h); outputs: one float per
 * sample in binding 1; push constants (fn, in_off, out_off, n): dispatch k
 * runs fns[fn] on samples in_off.. into out_off... Malloc'd, or NULL. */
char *vk_shader(const vk_fn *const *fns, int n, bk_precision prec);

/* A function's text with float16_t arithmetic: "float" becomes float16_t,
 * precision qualifiers go (desktop drivers ignore mediump, so that is the
 * only way to run half), and every literal becomes the exact decimal of its
 * float value rounded to half (nearest, ties to even: what bk_form_eval
 * BK_F16 loads), with the hf suffix. Exact, because glslang 12 converts a
 * half literal toward zero: "0.040618896hf" (the float of a half value 1331
 * * 2^-15) would compile to 1330 * 2^-15. Comments are kept. Malloc'd, or NULL. */
char *vk_half_text(const char *glsl);

/* 1 if the code of glsl (comments aside) calls function fn. */
int vk_calls(const char *glsl, const char *fn);

/* The negative control: text with the first literal of the body of function
 * name multiplied by factor (how = 0), or its return value replaced by NaN
 * (how = 1). NULL if name has no body or no literal. */
char *vk_perturb(const char *glsl, const char *name, double factor, int how);

#endif
