/*
 * sources.h — the GLSL functions tests/vk runs, each with the IR form it is
 * compared with:
 *
 *   catalog   every entry of fit/catalog (A and B of a split-sum entry), its
 *             published constants baked in, emitted by bk_form_emit;
 *   fuzz      forms drawn at random from the IR's ops (vk_add_fuzz), emitted
 *             by bk_form_emit;
 *   front     every row of a search's front.csv (columns read by name: name,
 *             form, form_b, parameters), emitted by bk_form_emit;
 *   file      every function of a committed GLSL file (make results' scene
 *             shaders, front members' and catalog comparisons' shaders), its
 *             text run as committed; the IR form is the function's own "form:"
 *             line and its "pN = V" lines, so the comparison is with what the
 *             file says it computes, independent of the emitted body. (A
 *             scene's shader.c comes from the same instruction list through
 *             the same emitter, so running it would compare the emitter with
 *             itself, and C has no half to check the f16 run against.)
 */
#ifndef TESTS_VK_SOURCES_H
#define TESTS_VK_SOURCES_H

#include "brdf.h"

#include <stddef.h>

typedef struct vk_fn {
	char label[200];  /* "catalog:vf_talk_r", "front:env/search_env_3:B", "file:PATH:NAME" */
	bk_form *form;    /* the IR it is compared with */
	double params[BK_MAX_PARAMS];
	char *glsl;       /* the function's text as emitted or committed (highp or mediump float) */
	char name[80];    /* its name in that text */
	unsigned args;    /* the inputs its signature takes (bk_input bits; declared in that order) */
	int group;        /* functions of one group may share a shader: their names differ */
} vk_fn;

typedef struct vk_fns {
	vk_fn *v;
	int n, cap;
	int groups;
} vk_fns;

/* Each appends to fns; 0, or -1 with one line in err naming the bad input. */
int vk_add_catalog(vk_fns *fns, char *err, size_t errlen);
int vk_add_front(vk_fns *fns, const char *path, char *err, size_t errlen);
int vk_add_glsl(vk_fns *fns, const char *path, char *err, size_t errlen);
/* One form's text emitted as the catalog's are (label unique in the run). */
int vk_add_emitted(vk_fns *fns, const char *label, const char *text, const double *params, int np, char *err,
                   size_t errlen);
/* n forms drawn from seed (tests/vk/fuzz.c): every op of the IR, negative
 * bases and arguments, constants past half's and float's range, emitted as
 * the catalog's are; labelled "fuzz:SEED:K FORM". */
int vk_add_fuzz(vk_fns *fns, int n, unsigned long seed, char *err, size_t errlen);

void vk_fns_free(vk_fns *fns);

#endif
