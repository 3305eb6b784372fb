/*
 * speclut.h — the low tier's specular look-up table ("Optimizing PBR for
 * Mobile", seed 001, "Optimizing for Low-end" / "LUT specular"): the whole
 * punctual specular intensity read from one 2-D texture instead of computed,
 * for GPUs whose ALU:TEX ratio is low (16).
 *
 * What a texel holds (the bake), for axis value x and perceptual roughness r
 * (GGX alpha a = r^2):
 *
 *   T(x, r) = D_ggx(NoH(x), a) * V_implicit / s,   V_implicit = 1/4
 *
 * V_implicit is the talk's "implicit geometric term": G = NoL NoV, so that
 * V = G/(4 NoL NoV) = 1/4 (brdf.h's V includes the 1/4). s is the scale
 * ("store 1/16 intensity": s = 16, so intensities up to s fit in [0, 1]).
 * The texture holds no f0 and no Fresnel: the shader multiplies back,
 *
 *   spec = fetch(u, v) * s * NoL * F,   F = f0            (fresnel none: the
 *                                                          talk's "no Fresnel";
 *                                                          f0 = the specular colour)
 *                                       F = F_schlick(f0, 1, LoH) (fresnel schlick:
 *                                                          in the shader's ALU)
 *
 * and the result is compared with the exact D·V·F·NoL (height-correlated
 * Smith V, Schlick F), brdfkit's spec target.
 *
 * The axes. u = x^p (the warp: "multiplying N·H or R·L with itself a couple
 * of times", p an integer power, p = 1 no warp) at texel centres
 * u = (i + 0.5)/nu, so texel i holds x = u^(1/p); v = (r - r_lo)/(r_hi - r_lo)
 * at v = (j + 0.5)/nr. x is
 *   noh  NoH;                 NoH(x) = x exactly;
 *   rol  saturate(R·L), R = reflect(-V, N) = 2 NoV N - V (the vector the
 *        shader has for its environment fetch), so R·L = 2 NoV NoL - VoL
 *        with VoL = 2 VoH^2 - 1. The bake uses NoH(x) = sqrt((1 + x)/2),
 *        which is exact only when L lies in the plane of V and N (there the
 *        angle between R and L is twice the angle between N and H); out of
 *        that plane R·L is the Phong lobe's cosine, not the Blinn one's, and
 *        the difference is part of the LUT's error. R·L < 0 (L more than 90
 *        degrees from R) is clamped to 0 by the saturate: with an even power
 *        the lobe would otherwise come back behind.
 *
 * The lookup as a GPU does it: texel centres, clamp to edge, bilinear with
 * the weights in 8-bit fixed point (as lutscore.c models the DFG LUT: the
 * D3D11 / CUDA sub-texel rule), on the stored values: UNORM8 saturates to
 * [0, 1] and rounds to the nearest 1/255 (so intensities above s are cut
 * to s, and the storage error is at most 0.5/255 * s before NoL F); HALF and
 * FLOAT keep the value (no cut). Linear data: never loaded as sRGB.
 */
#ifndef ANALYSIS_SPECLUT_H
#define ANALYSIS_SPECLUT_H

#include "brdf.h"
#include "compare.h"
#include "fit.h"

#include <stddef.h>
#include <stdio.h>

typedef enum bk_speclut_axis { BK_SPECLUT_NOH, BK_SPECLUT_ROL, BK_SPECLUT_AXES } bk_speclut_axis;
typedef enum bk_speclut_fresnel { BK_SPECLUT_F_NONE, BK_SPECLUT_F_SCHLICK, BK_SPECLUT_FRESNELS } bk_speclut_fresnel;

#define BK_SPECLUT_MAX_WARP 16
#define BK_SPECLUT_MAX_SIZE 4096

typedef struct bk_speclut {
	bk_speclut_axis axis;
	int warp;                   /* p in 1..BK_SPECLUT_MAX_WARP: u = x^p */
	int nu, nr;                 /* texels along u (x) and v (r) */
	double r_lo, r_hi;          /* rows over r_lo..r_hi, 0 <= r_lo < r_hi <= 1 */
	double scale;               /* s > 0: texel = intensity / s */
	bk_speclut_fresnel fresnel;
	bk_lut_format fmt;          /* storage: unorm8 (what ships), half, float */
} bk_speclut;

/* The talk's choices: R·L, warp 4, 1/16, 8 bits, no Fresnel. The talk gives
 * no size; 64 x 64 is brdfkit's reading of it (stated wherever it is used). */
#define BK_SPECLUT_TALK {BK_SPECLUT_ROL, 4, 64, 64, 0.0, 1.0, 16.0, BK_SPECLUT_F_NONE, BK_LUT_UNORM8}

const char *bk_speclut_axis_name(bk_speclut_axis a);       /* "noh", "rol" */
const char *bk_speclut_fresnel_name(bk_speclut_fresnel f); /* "none", "schlick" */
int bk_speclut_axis_parse(const char *s, bk_speclut_axis *a);
int bk_speclut_fresnel_parse(const char *s, bk_speclut_fresnel *f);

/* NULL when L is a valid layout, else what is wrong ("warp 0 is outside 1..16"). */
const char *bk_speclut_check(const bk_speclut *L);

/* 1 if a texel of L (intensity/scale cast to float32, spec.exr's) is
 * infinite, or not 0 but 0 or subnormal (0 where GPUs flush), or the shader's
 * constant (the scale) is not a normal float32; why then says which and
 * the scales this LUT admits ("39 of 4096 texels are +inf in float32; ...
 * for a scale in [LO, HI]"). 0 if every one is, -1 on a bad layout or no
 * memory. */
int bk_speclut_float_check(const bk_speclut *L, char *why, size_t len);

/* "spec LUT 64x64 unorm8 rol^4 /16" (+ " schlick" with Fresnel in the shader). */
void bk_speclut_name(const bk_speclut *L, char *buf, size_t len);

/* The axis value and roughness at texel centres, and NoH(x) of the axis. */
double bk_speclut_texel_x(const bk_speclut *L, int i);
double bk_speclut_texel_r(const bk_speclut *L, int j);
double bk_speclut_noh(bk_speclut_axis axis, double x);

/* The intensity the LUT encodes, D_ggx(NoH(x), r^2)/4 (before the scale). */
double bk_speclut_intensity(bk_speclut_axis axis, double x, double r);

/* R·L from the cosines a sample carries: 2 NoV NoL - (2 VoH^2 - 1). */
double bk_speclut_rol(double NoV, double NoL, double VoH);

/* The texels, nu*nr, row j = roughness row j (row-major in r): raw (NULL
 * allowed) gets intensity/s unrounded, stored the value the format holds
 * (UNORM8: k/255). Returns 0 or -1 (bad layout). */
int bk_speclut_bake(const bk_speclut *L, double *raw, double *stored);

/* A bilinear fetch of tex (nu x nr, as bk_speclut_bake) at texture
 * coordinates (u, v) in [0, 1]: texel centres, clamp to edge, 8-bit weights. */
double bk_speclut_fetch(const bk_speclut *L, const double *tex, double u, double v);

/* The shader's specular intensity at one configuration, in precision prec
 * (BK_F64: storage and filtering alone; BK_F32, BK_F16: the coordinates,
 * fetched value and products rounded), from the stored texels tex. */
double bk_speclut_shade(const bk_speclut *L, const double *tex, bk_precision prec, double NoV, double NoL,
                        double NoH, double VoH, double r, double f0);

/* Scores L on samples of the spec target (or any samples providing NoV,
 * NoL, NoH, LoH, r, f0; s->y the exact D·V·F·NoL) as compare scores a form:
 * metrics into m (cost NaN), the plane's error per cell into plane (may be
 * NULL). Returns 0, or -1 (bad layout, samples without those inputs, no
 * memory). */
int bk_speclut_score(const bk_speclut *L, bk_precision prec, const bk_samples *s, bk_fit_metrics *m,
                     double *plane);

/* The function the LUT encodes at one configuration, exact (no texture,
 * no storage, no cut): D_ggx(NoH(x), r^2)/4 * NoL * F. The LUT's storage
 * error is its error against this; its model error (implicit V, F, R·L for
 * N·H) is this one's against the exact D·V·F·NoL. */
double bk_speclut_model(const bk_speclut *L, double NoV, double NoL, double NoH, double VoH, double r, double f0);

/* bk_speclut_score against bk_speclut_model instead of s->y: what the
 * texture's storage and filtering alone get wrong (warp, scale, size and
 * format). Returns 0 or -1 as bk_speclut_score. */
int bk_speclut_score_storage(const bk_speclut *L, const bk_samples *s, bk_fit_metrics *m, double *plane);

/* The root mean square over the plane's cells of plane (the directional
 * albedo error per (NoV, r) cell on the spec target): the cells' typical
 * error, where the largest is the same for every LUT (the smoothest,
 * most grazing cell, which no texture of D/4 gets right). */
double bk_speclut_plane_rms(const bk_samples *s, const double *plane);

/* The exact directional albedo per cell of the plane of s (the spec
 * target's (NoV, r) cells): minus the plane error of a LUT of zeros. Returns
 * 0, or -1 with no memory. */
int bk_speclut_plane_albedo(const bk_samples *s, double *albedo);

/* The root mean square over the cells of plane / albedo (albedo from
 * bk_speclut_plane_albedo; cells whose albedo is 0 or not finite left out;
 * +inf if plane is not finite in a cell that counts):
 * the error relative to the energy each cell has, so that every cell counts
 * the same and a LUT that outputs 0 scores exactly 1 (M5: the absolute rms
 * is dominated by the grazing and smoothest cells, whose albedo is largest
 * and which no 8-bit LUT of D/4 gets right, and puts a LUT of zeros within
 * 3 % of the best). NAN when no cell counts. */
double bk_speclut_plane_rel_rms(const bk_samples *s, const double *plane, const double *albedo);

/* The shader's ALU ops beyond the fetch, counted by the IR on the text it
 * runs: rol: dot(R, L) as 3 simple ops (one mul, two mad: a scalar ALU's
 * dot3; NoH, like every form's input, is free in brdfkit), saturate(x) for
 * rol, x^p, v = r*k + c where the rows cover less than 0..1, and the
 * multiply back fetch*s*NoL*F (f0 counted as an input). Returns 0 or -1. */
int bk_speclut_ops(const bk_speclut *L, bk_ops *ops);

/* Writes dir/spec.exr (FLOAT, the raw texels intensity/s), dir/spec.png
 * (8-bit grey, the UNORM8 texels an engine ships) and dir/spec.csv (every
 * texel: its x, NoH, r, intensity, raw and 8-bit values), each with the
 * layout and conventions (EXR header attributes, PNG tEXt chunks, CSV
 * comments) and command (provenance). Scanline / row 0 holds v = 0.5/nr
 * (smallest roughness; uv (0,0) is the first texel). dir exists (a
 * bk_out_dir's temporary). Returns 0, or -1 with a message. */
#define BK_SPECLUT_EXR "spec.exr"
#define BK_SPECLUT_PNG "spec.png"
#define BK_SPECLUT_CSV "spec.csv"
int bk_speclut_write(const bk_speclut *L, const char *dir, const char *command, char *err, size_t errlen);

/* The layout in words, one line each (for headers, chunks, comments). */
void bk_speclut_describe(const bk_speclut *L, char *axes, size_t alen, char *texel, size_t tlen, char *shader,
                         size_t slen);

#endif
