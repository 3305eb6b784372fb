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

/* Which channels the EXR holds, as engines lay them out (the CSV always has
 * the named columns A, B and, beyond split, E, cloth, E_avg):
 *   split     R = A, G = B (Karis 2013): specular = f0 R + G.
 *   filament  R = B, G = E = A + B, B = cloth, as Filament's cmgen bakes its
 *             DFG LUT with multiscatter and cloth (CubemapIBL::DFG,
 *             DFV_Multiscatter: x = Σ V Fc, y = Σ V; b = DFV_Charlie_Uniform):
 *             specular = mix(R, G, f0), energy compensation 1 + f0 (1/G - 1),
 *             sheen albedo B.
 *   full      R = A, G = B, B = cloth, A = E_avg(r) (Kulla & Conty 2017's
 *             average albedo, the same along a row): the compensation lobe
 *             needs E = R + G at both directions and A.
 * cloth is bk_sheen_albedo (Charlie D, Neubelt V, F = 1) and E_avg
 * bk_ms_E_avg for the LUT's Smith model. */
typedef enum bk_lut_chan { BK_LUT_SPLIT, BK_LUT_FILAMENT, BK_LUT_FULL, BK_LUT_CHANS } bk_lut_chan;
const char *bk_lut_chan_name(bk_lut_chan c); /* "split", "filament", "full" */

typedef struct bk_lut_desc {
	bk_lut_layout L;   /* texels, roughness range, NoV warp, f0 folded (brdf.h);
	                      {size, size, 0, 1, none, NaN}: the engines' usual LUT */
	int half;          /* store HALF channels instead of FLOAT */
	int origin_top;    /* 1: first scanline holds r = 0.5/size */
	bk_smith smith;
	long samples;      /* 0: deterministic integrator with tol */
	double tol;
	const char *command; /* the command line, recorded for provenance */
	bk_lut_chan chan;  /* BK_LUT_SPLIT (0) unless set; not with a folded f0 */
	const double *cloth; /* beyond split: nu*nr sheen albedos, as A */
	const double *e_avg; /* beyond split: nr values, E_avg of row j */
} bk_lut_desc;

/* The extra channels of a LUT beyond split at d's texels: cloth (nu*nr, as
 * A) and e_avg (nr, one per row), integrated to d->tol. Deterministic, one
 * thread. 0, or -1 on a bad layout or a failed integral. */
int bk_lut_extra(const bk_lut_desc *d, double *cloth, double *e_avg, bk_progress_fn progress, void *ctx);

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
