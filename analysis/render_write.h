/*
 * render_write.h — the files of brdfkit render (analysis/render.h's images):
 * per render, in one directory the caller makes (bk_out_dir):
 *
 *   exact.exr|png            the exact shading in f32
 *   candidate_f32.exr|png    the candidate in f32
 *   diff_f32.png             the stated display difference (render.h) of
 *                            candidate_f32 against exact (the linear difference
 *                            is the two EXRs' difference)
 *   exact_f16, candidate_f16, diff_f16 (against the f32 exact image): the
 *                            same with the shading in float16_t; their EXRs are
 *                            HALF channels, which hold every f16 result exactly
 *   (a batch writes exact and exact_f16 once, in its top directory: the scene
 *   and the exact shading are the same for every candidate)
 *   spheres.csv              per sphere: where it is, its roughness and
 *                            material, and per image its non-finite pixels
 *                            and display differences
 *   shader_f32.comp, shader_f16.comp   the compute shaders that ran (lavapipe)
 *   section.html             the images side by side (exact | candidate |
 *                            difference, f32 and f16), every user string escaped
 *
 * EXR: linear radiance, RGB (FLOAT for f32, HALF for f16), attributes brdfkit:conventions (the scene,
 * the units), brdfkit:image, brdfkit:form, brdfkit:term, brdfkit:device,
 * brdfkit:command. PNG: 8-bit sRGB (render.h's display), tEXt Title,
 * Description (the conventions and the difference scale), Software, Command.
 * Images with NULL pixels (a precision not rendered) are skipped.
 */
#ifndef ANALYSIS_RENDER_WRITE_H
#define ANALYSIS_RENDER_WRITE_H

#include "render.h"

#include <stdio.h>

enum { BK_RI_EXACT_F32, BK_RI_CAND_F32, BK_RI_EXACT_F16, BK_RI_CAND_F16, BK_RI_COUNT };

typedef struct bk_render_out {
	const char *name;        /* a checked identifier: [A-Za-z0-9_.-], the render's directory in a batch */
	const char *form, *form_b, *params; /* as given (escaped wherever written) */
	const char *term;        /* bk_render_term_name */
	const char *device;      /* "lavapipe: llvmpipe Mesa ..." or "cpu (the IR: double and BK_F16)" */
	const bk_render_scene *scene;
	const bk_render_geom *g;
	float *img[BK_RI_COUNT]; /* width*height*3 each, or NULL */
	char *shader[2];         /* f32, f16 text, or NULL */
	int shared_exact;        /* the exact images are the batch's, one directory up:
	                            bk_render_write leaves them out, the section links there */
	/* filled by bk_render_write: per image, non-finite pixels; per precision,
	 * the largest and mean display difference over sphere pixels */
	size_t nonfinite[BK_RI_COUNT];
	double max_diff[2], mean_diff[2];
} bk_render_out;

/* The files above into dir (which exists). 0, or -1 with a message. */
int bk_render_write(const char *dir, bk_render_out *o, char *err, size_t errlen);

/* Whether name is one of the files above (section.html included): a batch
 * writes them in its top directory too, where each render is a directory by
 * its name, so a render may not be so named. */
int bk_render_file_name(const char *name);

/* One section.html for renders o[0..n) (written), each under
 * prefix + (n > 1 || in_subdirs ? name + "/" : ""). */
void bk_render_section(FILE *f, const bk_render_out *o, int n, const char *prefix, int in_subdirs);

/* The conventions line every file carries. */
extern const char bk_render_conventions[];

#endif
