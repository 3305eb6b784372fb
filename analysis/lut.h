/*
 * lut.h — the DFG look-up table on disk: a directory holding dfg.exr (OpenEXR,
 * R = A, G = B, or R = f0 A + B with f0 folded in; its conventions and layout
 * as header attributes) and dfg.csv (the same
 * table). The two are one result, so they live in one directory that is
 * replaced whole (bk_out_dir): a pair of plain files cannot be swapped at once.
 */
#ifndef ANALYSIS_LUT_H
#define ANALYSIS_LUT_H

#include "brdf.h"

#include <stddef.h>

typedef struct bk_lut_desc {
	bk_lut_layout L;   /* texels, roughness range, NoV warp, f0 folded (brdf.h);
	                      {size, size, 0, 1, none, NaN}: the engines' usual LUT */
	int half;          /* store HALF channels instead of FLOAT */
	int origin_top;    /* 1: first scanline holds r = 0.5/size */
	bk_smith smith;
	long samples;      /* 0: deterministic integrator with tol */
	double tol;
	const char *command; /* the command line, recorded for provenance */
} bk_lut_desc;

#define BK_LUT_EXR "dfg.exr"
#define BK_LUT_CSV "dfg.csv"

/* Writes dir/dfg.exr and dir/dfg.csv from A, B as bk_dfg_lut_layout fills
 * them (row j = roughness bk_lut_texel_r(j); a folded layout stores the one
 * channel f0 A + B) into the existing directory dir: each file
 * whole or absent; the pair is made one by writing dir as a bk_out_dir's
 * temporary. Returns 0, or -1 with a one-line message in err. */
int bk_lut_write(const bk_lut_desc *d, const char *dir, const double *A,
                 const double *B, char *err, size_t errlen);

/* The brdfkit:axes attribute bk_lut_write gives layout L (where the texel
 * centres are, in words), so a reader can check a file's against it. */
void bk_lut_axes_text(const bk_lut_layout *L, char *buf, size_t len);

#endif
