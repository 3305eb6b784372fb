/*
 * tabtarget.h — a user's file read as the samples of a fit target (fit/
 * target.h kinds table and merl): fit/ reads no file formats, so the command
 * line reads the file here and hands the samples over (bk_target_options
 * .table).
 *
 *   CSV    one sample a row: input columns named as the formula language's
 *          inputs (NoV NoL NoH LoH r a f0; r gives a = r^2, a gives
 *          r = sqrt(a)), a column 'value', an optional column 'weight'
 *          (>= 0; default 1), '#' comment lines before the header; weights
 *          are scaled to sum to 1.
 *   EXR    a 2-D table as brdfkit lut writes it: x = NoV, y = perceptual
 *          roughness at texel centres, the layout read from the attributes
 *          brdfkit:axes and brdfkit:origin; one channel (chosen, or the
 *          image's only one); uniform weight.
 *   MERL   Matusik et al. 2003's binary format (see bk_tabtarget_merl).
 *
 * Every error is one line naming the file and where: "PATH:LINE: column 'X'
 * ...", "PATH: texel (x, y) ...", "PATH: byte N: ...".
 */
#ifndef ANALYSIS_TABTARGET_H
#define ANALYSIS_TABTARGET_H

#include "target.h"

#include <stddef.h>

/* MERL's channels, and Rec. 709's luminance of the three. */
typedef enum bk_merl_channel { BK_MERL_R, BK_MERL_G, BK_MERL_B, BK_MERL_LUMINANCE, BK_MERL_CHANNELS } bk_merl_channel;
extern const char *const bk_merl_channel_names[BK_MERL_CHANNELS]; /* "r", "g", "b", "luminance" */

/* MERL's grid and its per-channel scales (Matusik et al.'s BRDFRead.cpp). */
#define BK_MERL_NTH 90  /* θh, stored at u = sqrt(θh / (π/2)) */
#define BK_MERL_NTD 90  /* θd over [0, π/2) */
#define BK_MERL_NPD 180 /* φd over [0, π) (reciprocity folds φd + π) */
#define BK_MERL_N ((size_t)BK_MERL_NTH * BK_MERL_NTD * BK_MERL_NPD)
extern const double bk_merl_scale[3]; /* 1/1500, 1.15/1500, 1.66/1500 */

/* The bin centre of MERL sample (i, j, k): θh = ((i + 0.5)/90)^2 π/2,
 * θd = (j + 0.5)/90 π/2, φd = (k + 0.5)/180 π (MERL's own lookup, which
 * truncates, maps each back to (i, j, k)); and the cosines of its
 * directions, the half vector at (θh, 0), ω_l = rotate_y(θh) d(θd, φd),
 * ω_v its reflection about h:
 *   NoH = cos θh, LoH = cos θd,
 *   NoL = cos θh cos θd - sin θh sin θd cos φd,
 *   NoV = cos θh cos θd + sin θh sin θd cos φd. */
void bk_merl_angles(int i, int j, int k, double *th, double *td, double *pd);
void bk_merl_cosines(double th, double td, double pd, double *NoV, double *NoL, double *NoH, double *LoH);

/* CSV or EXR by the name's ending (.csv, .exr); channel: the EXR channel's
 * name or NULL (the only one). 0, or -1 with err; s holds nothing then. */
int bk_tabtarget_table(const char *path, const char *channel, bk_samples *s, char *err, size_t errlen);

/* A MERL binary file, one channel. Samples: every measured bin (value >= 0;
 * luminance: all three measured) whose directions are above the horizon
 * (NoL > 0, NoV > 0), value = stored value times the channel's scale (the
 * BRDF in 1/sr), weight = the bin's share of the solid angle dω_l dω_v =
 * 4 cos θd sin θh sin θd dθh dθd dφd dφh (Rusinkiewicz 1998), so the fit is
 * an integral over pairs of directions, not over MERL's warped grid. */
int bk_tabtarget_merl(const char *path, bk_merl_channel ch, bk_samples *s, char *err, size_t errlen);

#endif
