/*
 * halfbound.h — a half front's emitted float16_t code held to the error its
 * files state (issue 40), on lavapipe: every one-form member of a front.csv
 * of brdfkit search --precision half is emitted as shader_f16.glsl is
 * (bk_form_emit, BK_EMIT_F16: binary16 constants, no `precise`, so LLVM may
 * fuse and reassociate as a driver does), run over the target's own samples,
 * and its error against the target's exact values in double (fit/target.c,
 * bk_target_build: not the IR's f16) is compared with the member's error
 * column, the error its shaders' headers state.
 */
#ifndef TESTS_VK_HALFBOUND_H
#define TESTS_VK_HALFBOUND_H

#include "lvp.h" /* analysis/lvp.h */

typedef struct vk_halfbound_opts {
	const char *front;   /* FRONT.csv */
	const char *target;  /* the target kind's name, as search's --target */
	int nx, nr;          /* search's --nx, --nr (0: the target's defaults) */
	double ior, k;       /* target f: search's --ior, --k (NaN: the defaults) */
	const char *perturb; /* the negative control: this member's p0 times factor */
	double factor;
	int verbose;         /* a line per member */
	int precise;         /* the diagnosis: every temporary declared precise */
} vk_halfbound_opts;

/* Runs the check on v and prints a line per member that exceeds its stated
 * error (every member with verbose) and a summary. 0 every member holds, 1
 * some exceed it, -1 an error (one line "vkrun: ..." on stderr). */
int vk_halfbound(bk_lvp *v, const vk_halfbound_opts *o);

#endif
