/*
 * render.h — brdfkit render: a grid of spheres shaded with the exact BRDF and
 * with a candidate form in place of one term, by brdfkit's emitted GLSL on
 * Mesa's lavapipe (analysis/lvp.h) in f32 and in explicit float16_t, and by
 * the IR on the CPU (bk_form_eval, double and BK_F16) as the reference.
 *
 * THE SCENE (every number here is the contract; the outputs restate it)
 *   grid      columns: the roughness list (perceptual r, a = r^2); row 0 a
 *             dielectric, f0 = 0.04 (grey) over a Lambert base of albedo
 *             (0.30, 0.04, 0.03); row 1 gold, f0 = (1.00, 0.71, 0.29), no
 *             diffuse. Cells are cell x cell pixels; sphere radius 0.45 cell.
 *   camera    perspective, one pinhole per sphere at 4 radii on +z (x right,
 *             y up, z toward the viewer) with the silhouette on the sphere's
 *             circle: V = the ray back to the camera, so V, H and LoH vary
 *             across a sphere; pixel centres; NoV floored at 1e-3.
 *   light     one directional light toward L = normalize(0.5, 0.6, 0.62),
 *             irradiance at normal incidence E = (3.0, 2.9, 2.7).
 *   sky       procedural (bk_render_sky): ground (0.20, 0.16, 0.12) blending
 *             into a horizon (0.90, 0.85, 0.80) to zenith (0.20, 0.35, 0.80)
 *             gradient, a sun glow 8 exp(200 (d.L - 1)) (1, 0.95, 0.85) and a
 *             window-like patch 4 exp(40 (d.P - 1)), P = normalize(-0.6, 0.4, 0.7).
 *   specular  direct: D·V·F·NoL·E where NoL > 0, D = D_ggx(NoH, a), V =
 *             V_smith_ggx_correlated(NoV, NoL, a), F = F_schlick(f0, 1, LoH);
 *             environment, the split sum as engines do it: prefiltered
 *             radiance × (f0·A + B), A and B brdfkit's DFG (bk_dfg,
 *             correlated Smith) at 129 nodes in sqrt(NoV) per column,
 *             Catmull-Rom between them (within 1e-4 of bk_dfg, tests/
 *             test_render.c); the prefiltered radiance is Karis'
 *             (N = V = R): ∫ L(l) D(R·h) (R·l)+ / ∫ D(R·h) (R·l)+, on a fixed
 *             24 x 48 grid of GGX samples of h (bk_ggx_sample_h) per pixel.
 *   diffuse   albedo · (E NoL/π + the sky's cosine-weighted mean over the
 *             hemisphere of N, 24 x 48 fixed samples), computed on the CPU.
 *   output    linear radiance per channel:
 *             spec + pref·env + diffuse, each colour channel one sample.
 *   background a flat (0.02, 0.02, 0.025), not shaded.
 *
 * THE CANDIDATE replaces one term (bk_render_term): vf: V·F (D·cand·NoL·E);
 * d, v, f: that factor; dvf: D·V·F; env: f0·A + B (one form reading f0, or
 * f0·A + B with a split form's A and B). Each shading's product is evaluated
 * left to right, ((((D·V)·F)·NoL)·E), then (spec + pref·env) + diffuse, in
 * the same order on the GPU and the CPU (in f16 every step rounds to half).
 *
 * THE SAMPLES: each sphere pixel's channel is one sample of BK_RENDER_STRIDE
 * floats (slots BK_RS_*), what the CPU computed in double rounded to float.
 */
#ifndef ANALYSIS_RENDER_H
#define ANALYSIS_RENDER_H

#include "brdf.h"
#include "lvp.h"

#include <stddef.h>

#define BK_RENDER_MAX_COLS 16
/* A cell's side in pixels: 8 shows a sphere, 4096 bounds one cell's
 * buffers (render.c checks it; render --size says it in terms of W). */
#define BK_RENDER_MIN_CELL 8
#define BK_RENDER_MAX_CELL 4096
#define BK_RENDER_STRIDE 12
enum {
	BK_RS_NOV, BK_RS_NOL, BK_RS_NOH, BK_RS_LOH, BK_RS_R, BK_RS_A, BK_RS_F0, /* the form inputs, brdf.h's order */
	BK_RS_LIGHT, /* E of the channel */
	BK_RS_PREF,  /* prefiltered sky radiance of the channel */
	BK_RS_EA, BK_RS_EB, /* the DFG's A and B */
	BK_RS_DIFF   /* the diffuse radiance of the channel */
};

typedef enum bk_render_term { BK_RT_VF, BK_RT_D, BK_RT_V, BK_RT_F, BK_RT_DVF, BK_RT_ENV, BK_RT_COUNT } bk_render_term;
const char *bk_render_term_name(bk_render_term t); /* "vf", "d", "v", "f", "dvf", "env" */
/* "vf2d" reads as vf (the same V·F function on its plane). 0 or -1. */
int bk_render_term_parse(const char *s, bk_render_term *t);
/* The term a catalog target replaces ("VF", "DVF", "V", "F", "env", "env_f0";
 * "D"): 0, or -1 when the target has no term in the render. */
int bk_render_term_of_target(const char *target, bk_render_term *t);

typedef struct bk_render_scene {
	int cell;                       /* pixels per cell, BK_RENDER_MIN_CELL..BK_RENDER_MAX_CELL */
	int ncols;                      /* 1..BK_RENDER_MAX_COLS */
	double r[BK_RENDER_MAX_COLS];   /* roughness of each column, in (0, 1] */
} bk_render_scene;

/* The procedural sky: radiance (linear RGB) in unit direction d. */
void bk_render_sky(const double d[3], double rgb[3]);
typedef void (*bk_render_env_fn)(void *ctx, const double d[3], double rgb[3]);

/* Karis' prefiltered radiance of env in direction R (unit) for GGX a, and the
 * cosine-weighted mean of env over the hemisphere of N (see the scene). */
void bk_render_prefilter(bk_render_env_fn env, void *ctx, const double R[3], double a, double rgb[3]);
void bk_render_irradiance(bk_render_env_fn env, void *ctx, const double N[3], double rgb[3]);

typedef struct bk_render_geom {
	int width, height, ncols;
	size_t n;          /* samples: sphere pixels x 3 */
	float *in;         /* n x BK_RENDER_STRIDE */
	int *pixel;        /* sample -> pixel index (y * width + x) * 3 + channel */
	int *sphere;       /* pixel -> row * ncols + col, -1 off the spheres */
	float *background; /* width * height * 3: the image off the spheres (NaN on them) */
} bk_render_geom;

/* The scene's samples (env NULL: the sky). 0, or -1 with a message. */
int bk_render_geometry(const bk_render_scene *s, bk_render_env_fn env, void *ctx, bk_render_geom *g, char *err,
                       size_t errlen);
void bk_render_geom_free(bk_render_geom *g);

typedef struct bk_render_cand {
	bk_render_term term;
	const bk_form *form, *form_b; /* form_b: B of a split env form (then form is A), else NULL */
	const double *params;         /* the parameters of form (and form_b) */
	const char *label;            /* for provenance comments only (escaped there) */
} bk_render_cand;

/* The compute shader (layout: lvp.h; 12 floats in, 1 out per sample; pc.fn
 * 0 the exact shading, 1 the candidate's), exact terms and candidate as
 * bk_form_emit writes them, in f32 or with every function and the shading
 * in float16_t (BK_F16; bk_lvp_half_text). Malloc'd, or NULL. */
char *bk_render_shader(const bk_render_cand *c, bk_precision prec);

/* Both shadings of every sample on lavapipe: img[0] exact, img[1] candidate,
 * width*height*3 floats each (background included). seconds: glslang,
 * pipelines + run. 0, or -1 with a message. */
int bk_render_gpu(bk_lvp *v, const bk_render_geom *g, const bk_render_cand *c, bk_precision prec, float *img[2],
                  double seconds[2], char *err, size_t errlen);

/* The same from the IR on the CPU: prec BK_F64 (double throughout, from the
 * same float samples) or BK_F16 (bk_form_eval BK_F16, the shading rounded to
 * half after each operation). 0, or -1 (out of memory). */
int bk_render_cpu(const bk_render_geom *g, const bk_render_cand *c, bk_precision prec, float *img[2]);

/* The sample's A, B from the table (for the test against bk_dfg). */
int bk_render_dfg(double NoV, double r, double *A, double *B);

/* ---- display --------------------------------------------------------------
 * A pixel as a viewer sees it: Reinhard x/(1 + x) per channel, then the sRGB
 * transfer function, in [0, 1]. The difference images: per pixel the largest
 * over the channels of |display(candidate) - display(exact)|, times
 * BK_RENDER_DIFF_GAIN, clamped to 1, through a black-red-yellow-white ramp;
 * non-finite values are magenta (255, 0, 255) in every PNG. The summaries
 * (max and mean per image and per sphere) are over the pixels where the
 * exact f32 image is finite; a candidate pixel that is not finite there
 * counts as 1, the whole display range, so that an image with non-finite
 * pixels never reads better than one without. */
#define BK_RENDER_DIFF_GAIN 8.0
double bk_render_display(double x);

#endif
