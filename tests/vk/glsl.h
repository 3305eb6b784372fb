/*
 * glsl.h — the compute shaders tests/vk runs: many functions in one shader,
 * a push constant picks the one a dispatch calls.
 */
#ifndef TESTS_VK_GLSL_H
#define TESTS_VK_GLSL_H

#include "sources.h"

/* fns[0..n) in one compute shader, in f32 (the text as it is) or f16 (each
 * function rewritten to float16_t, see bk_lvp_half_text in analysis/lvp.h). Inputs: 8 floats per
 * sample in binding 0 (slot i: input i of brdf.h); outputs: one float per
 * sample in binding 1; push constants (fn, in_off, out_off, n): dispatch k
 * runs fns[fn] on samples in_off.. into out_off... Malloc'd, or NULL. */
char *vk_shader(const vk_fn *const *fns, int n, bk_precision prec);

/* 1 if the code of glsl (comments aside) calls function fn. */
int vk_calls(const char *glsl, const char *fn);

/* The negative control: text with the first literal of the body of function
 * name multiplied by factor (how = 0), or its return value replaced by NaN
 * (how = 1). NULL if name has no body or no literal. */
char *vk_perturb(const char *glsl, const char *name, double factor, int how);

#endif
