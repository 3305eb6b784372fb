/*
 * lutrows.h — the one builder of LUT rows, the textures the formulas of the
 * environment BRDF (and of E and the sheen albedo) compete with: brdfkit compare's rows, search's
 * --fetch-cost rows and scene's env candidates. Sizes 16² to 128² in the
 * three formats (unorm8, half, float), bilinear, texel centres, each scored
 * on the caller's samples (compare.h, bk_lut_score_layout).
 *
 * Layouts: the generic one (brdfkit lut --size N: A and B over [0, 1]²),
 * and, for a scene's feature set, one per NoV warp with the rows over the
 * set's roughness range only and f0 folded into one channel where the set
 * has one f0 (brdf.h, bk_lut_layout) — a variant identical to the generic
 * is left out. Rows go layout by layout, size by size, format by format.
 */
#ifndef ANALYSIS_LUTROWS_H
#define ANALYSIS_LUTROWS_H

#include "brdf.h"
#include "compare.h"

#define BK_LUTROWS_SIZES 4 /* 16, 32, 64, 128 */
#define BK_LUTROWS_MAX_LAYOUTS (1 + BK_LUT_WARPS)
#define BK_LUTROWS_MAX (BK_LUTROWS_MAX_LAYOUTS * BK_LUTROWS_SIZES * BK_LUT_FORMATS)

typedef struct bk_lutrow {
	char name[96];        /* "LUT 32x32 half", "LUT 32x32 half f0 0.04 r 0.3-1 sqrt" */
	int size;             /* texels per side */
	int variant;          /* 0: the generic layout; > 0 laid out for the set */
	bk_lut_layout layout; /* nu, nr: size */
	bk_lut_format fmt;
	double bytes;         /* texture memory: size² x channel bytes x channels (1 with f0 folded, else 2) */
	bk_fit_metrics m;     /* on the samples, in the precision asked */
	int scored;           /* 0: the LUT could not be scored on the samples */
} bk_lutrow;

/* The layouts (nu, nr 0: set per row): the generic alone (for_set 0), or
 * also the set's: rows over [r_lo, r_hi] when narrower than [0, 1], f0
 * folded when not NaN, each warp. Returns how many (<= BK_LUTROWS_MAX_LAYOUTS). */
int bk_lutrows_layouts(int for_set, double r_lo, double r_hi, double f0, bk_lut_layout *L);

/* The rows of layouts L[0..nl): names, sizes, bytes, and their scores on s
 * in precision prec with Smith model smith, or (cloth 1) of the cloth
 * channel, the sheen albedo, on the sheen target's samples (layouts not
 * folded; bytes those of the three-channel texture lut --channels filament
 * writes); progress (may be NULL) after each row. Returns the row count
 * (nl x BK_LUTROWS_SIZES x BK_LUT_FORMATS). */
int bk_lutrows_build(const bk_lut_layout *L, int nl, bk_smith smith, int cloth, bk_precision prec,
                     const bk_samples *s, bk_progress_fn progress, void *ctx, bk_lutrow *rows);

#endif
