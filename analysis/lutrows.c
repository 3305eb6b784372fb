/*
 * lutrows.c — the DFG and cloth LUT rows of compare, search and scene (lutrows.h).
 */
#include "lutrows.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static const int sizes[BK_LUTROWS_SIZES] = {16, 32, 64, 128};
static const double channel_bytes[BK_LUT_FORMATS] = {1, 2, 4};

int bk_lutrows_layouts(int for_set, double r_lo, double r_hi, double f0, bk_lut_layout *L)
{
	int n = 0, remap = r_lo > 0 || r_hi < 1;
	L[n++] = (bk_lut_layout){0, 0, 0, 1, BK_LUT_WARP_NONE, NAN};
	for (int w = 0; for_set && w < BK_LUT_WARPS; w++) {
		if (w == BK_LUT_WARP_NONE && !remap && isnan(f0))
			continue; /* the generic itself */
		bk_lut_layout v = {0, 0, 0, 1, (bk_lut_warp)w, f0};
		if (remap)
			v.r_lo = r_lo, v.r_hi = r_hi;
		L[n++] = v;
	}
	return n;
}

int bk_lutrows_build(const bk_lut_layout *L, int nl, bk_smith smith, int cloth, bk_precision prec,
                     const bk_samples *s, bk_progress_fn progress, void *ctx, bk_lutrow *rows)
{
	int n = 0, total = nl * BK_LUTROWS_SIZES * BK_LUT_FORMATS;
	for (int l = 0; l < nl; l++) {
		int variant = !(L[l].warp == BK_LUT_WARP_NONE && L[l].r_lo == 0 && L[l].r_hi == 1 && isnan(L[l].f0));
		for (int q = 0; q < BK_LUTROWS_SIZES; q++)
			for (int fm = 0; fm < BK_LUT_FORMATS; fm++) {
				bk_lutrow *r = &rows[n++];
				memset(r, 0, sizeof *r);
				r->layout = L[l];
				r->layout.nu = r->layout.nr = sizes[q];
				r->size = sizes[q];
				r->variant = variant ? l : 0;
				r->fmt = (bk_lut_format)fm;
				/* cloth: the file brdfkit lut --channels filament writes, B
				 * beside the DFG's B and A + B (Filament's layout) */
				r->bytes = (double)sizes[q] * sizes[q] * channel_bytes[fm] * (cloth ? 3 : isnan(L[l].f0) ? 2 : 1);
				const bk_lut_layout *y = &r->layout;
				char f0t[32] = "", rt[48] = "";
				if (!isnan(y->f0))
					snprintf(f0t, sizeof f0t, " f0 %g", y->f0);
				if (y->r_lo > 0 || y->r_hi < 1)
					snprintf(rt, sizeof rt, " r %g-%g", y->r_lo, y->r_hi);
				snprintf(r->name, sizeof r->name, "LUT %dx%d %s%s%s%s%s", sizes[q], sizes[q],
				         bk_lut_format_name(r->fmt), f0t, rt, y->warp ? " " : "",
				         y->warp ? bk_lut_warp_name(y->warp) : "");
				r->scored = (cloth ? bk_lut_score_cloth(y, r->fmt, prec, s, &r->m, NULL)
				                   : bk_lut_score_layout(y, r->fmt, smith, prec, s, &r->m, NULL)) == 0;
				if (progress)
					progress(ctx, n, total);
			}
	}
	return n;
}
