/*
 * compare.h — one row of the error-against-cost table (brdfkit compare), and
 * the modules that fill and draw it: run time (timing.c), the LUT alternative
 * (lutscore.c), plots and the report page (report.c).
 */
#ifndef ANALYSIS_COMPARE_H
#define ANALYSIS_COMPARE_H

#include "brdf.h"
#include "fit.h"

#include <stdio.h>

/* The talk's ALU:TEX ratios: simple ALU ops one bilinear fetch costs, per tier. */
#define BK_TIERS 4
extern const int bk_tier_alu_per_tex[BK_TIERS]; /* {16, 32, 48, 64} */

/* What the whole table shares: the cost model its cost column uses, and the
 * chips of its AMD columns (compare --gpu; brdfkit gpucost's figures). */
#define BK_COMPARE_CHIPS 8
typedef struct bk_compare_info {
	const char *cost_model; /* "ir", "aco-navi21", ... */
	double simple, complex; /* its weights */
	int nchips;
	const char *chip[BK_COMPARE_CHIPS];
} bk_compare_info;
#define BK_COMPARE_INFO_INIT {"ir", BK_COST_SIMPLE, BK_COST_COMPLEX, 0, {0}}

typedef struct bk_compare_row {
	char name[96];          /* catalog name, "name (refit)", or "LUT 64x64 half" */
	char kind[16];          /* "published", "refit", "lut", "form" */
	char source[256];       /* citation, or how the row was made */
	/* formula text (A; B for split sums in form_b), "" for LUTs: as long as
	 * the formula language allows (BK_FORM_MAX_LEN), so that no form the
	 * parser takes is ever cut (compare's rows were 1,024 bytes, and a
	 * longer typed form was scored whole but written and timed cut) */
	char form[BK_FORM_MAX_LEN + 1];
	char form_b[BK_FORM_MAX_LEN + 1];
	/* the same forms as IR, made once where the row is made (a command's
	 * edge: bk_compare_row_parse, or a copy of IR it holds), and what the
	 * scores, the timing, the GPU counts and the shaders read: text is for
	 * the files. Owned by the row (bk_compare_rows_free); NULL for LUTs. */
	bk_form *f[2];
	double params[BK_MAX_PARAMS];
	int nparams;
	bk_fit_metrics m;       /* on the target's samples; NaN where not applicable */
	bk_ops ops;             /* zero for LUTs */
	double cost;            /* the cost model's simple and complex weights (ALU only) */
	int tex_fetches;        /* bilinear fetches per evaluation */
	int sampler_slots;
	double ns, ns_min, ns_max; /* CPU ns per evaluation (generated C, -O2); NaN if not timed */
	int spirv;              /* SPIR-V instructions of the GLSL after spirv-opt -O; -1 if none */
	/* per chip of bk_compare_info (NaN: not compiled, e.g. a LUT row), net of
	 * gpucost's load/store baseline: ACO instructions, transcendental ops, VGPRs */
	double gpu_insn[BK_COMPARE_CHIPS], gpu_transc[BK_COMPARE_CHIPS], gpu_vgprs[BK_COMPARE_CHIPS];
	int cheaper_than_fetch[BK_TIERS]; /* ALU cost below one fetch at that tier (LUT rows: 0) */
	int pareto_cost, pareto_ns; /* on the front of error vs cost / vs ns */
} bk_compare_row;

/* ---- timing.c ---------------------------------------------------------------- */

/* Generates C for each row's form(s) (its IR, rows[i].f: a row with text and
 * none is refused; params baked in), compiles them into
 * one shared object with the system compiler (cc -O2 -fPIC -shared), loads it
 * and measures ns per evaluation over the same stream of varied inputs
 * (warm-up, reps runs, rows interleaved; median, min, max) into rows[i].ns*.
 * Rows without a form (LUTs) are skipped. Returns 0, or -1 with a message. */
int bk_time_rows(bk_compare_row *rows, int n, int reps, char *err, size_t errlen);

/* Makes r->form (and r->form_b when set) the row's IR, r->f, replacing any it
 * held: the one parse of a row's text. 0, or -1 with "NAME: form:1:COL:
 * message" in err (r->f then NULL). */
int bk_compare_row_parse(bk_compare_row *r, char *err, size_t errlen);
/* Frees the IR of rows[0..n) (the rows themselves are the caller's). */
void bk_compare_rows_free(bk_compare_row *rows, int n);

/* SPIR-V instruction count of the form's generated GLSL (highp) after
 * glslang (in-process, bk_gpucost_spirv) and spirv-opt -O, counted by
 * spirv-dis; -1 and a message when the tools are missing. */
int bk_spirv_count(const bk_form *f, const double *params, char *err, size_t errlen);

/* ---- lutscore.c ---------------------------------------------------------------- */

typedef enum bk_lut_format { BK_LUT_UNORM8, BK_LUT_HALF, BK_LUT_FLOAT, BK_LUT_FORMATS } bk_lut_format;
const char *bk_lut_format_name(bk_lut_format f); /* "unorm8", "half", "float" */

/* A size x size DFG LUT (texel centres, as brdfkit lut writes it) stored in
 * format, sampled the way a GPU does (bilinear between texel centres, clamp to
 * edge), scored on the env target's samples s (split A/B, or f0 A + B) into m
 * like bk_fit_evaluate (cost NaN). plane, if not NULL, gets the error per
 * plane cell as bk_fit_plane_error would. Returns 0 or -1. */
int bk_lut_score(int size, bk_lut_format fmt, bk_smith smith, const bk_samples *s, bk_fit_metrics *m,
                 double *plane);
/* The same for a LUT laid out for a scene (brdf.h, bk_lut_layout): rows over
 * [r_lo, r_hi], the NoV axis warped, and, with f0 folded into one channel,
 * scored only on samples at that f0 (s one-form, every f0 equal to L->f0;
 * else -1); prec is the shader's (BK_F16: mediump, the fetched values and
 * f0 A + B rounded to half; BK_F32; BK_F64: storage and filtering alone).
 * bk_lut_score is the layout {size, size, 0, 1, none, NaN} in BK_F64. */
int bk_lut_score_layout(const bk_lut_layout *L, bk_lut_format fmt, bk_smith smith, bk_precision prec,
                        const bk_samples *s, bk_fit_metrics *m, double *plane);
/* The cloth channel alone (brdfkit lut --channels filament's B: the sheen
 * albedo, bk_sheen_albedo) in layout L (f0 NaN: never folded), scored on
 * the sheen target's samples (one form of NoV and r, no f0; else -1) as
 * bk_lut_score_layout scores the DFG: one fetch is the term. */
int bk_lut_score_cloth(const bk_lut_layout *L, bk_lut_format fmt, bk_precision prec, const bk_samples *s,
                       bk_fit_metrics *m, double *plane);
/* The reference tables these score, kept on disk when BRDFKIT_TABLE_CACHE
 * names a directory (lutcache.h): the key the table of (L, smith, cloth)
 * is stored under (what its bake depends on), and that table read from dir
 * into AB (A then B, nu nr each; cloth: the albedo then zeros): 0 when dir
 * holds it whole, under its own key, and three of its texels baked again
 * (two corners, the middle) agree bit for bit; else -1. */
void bk_lut_table_key(const bk_lut_layout *L, bk_smith smith, int cloth, char *key, size_t len);
int bk_lut_table_cached(const char *dir, const bk_lut_layout *L, bk_smith smith, int cloth, double *AB);

/* ---- report.c ------------------------------------------------------------------- */

/* Marks rows[i].pareto_cost / pareto_ns: no other row both at most as costly
 * (ALU cost plus fetches at the given tier's ratio) and at most as wrong
 * (error = m.max_abs), one of them strictly. */
void bk_pareto(bk_compare_row *rows, int n, int tier);

/* The table as CSV, deterministic: everything but timings (and so without
 * pareto_ns). Header: name,kind,source,form,form_b,parameters,rmse,
 * weighted_rmse,max_abs,max_rel,albedo_max_abs,<one column per op class>,
 * simple,complex,cost,tex_fetches,sampler_slots,spirv,cheaper_than_fetch_16,
 * _32,_48,_64,pareto_cost, then per chip of info aco_CHIP_instructions,
 * aco_CHIP_transcendental, aco_CHIP_vgprs. Parameters as p0=..;p1=.. (%.9g).
 * info NULL: BK_COMPARE_INFO_INIT. */
void bk_compare_csv(FILE *f, const bk_compare_row *rows, int n, const bk_compare_info *info);
/* Timings in a file of their own: name,ns_per_eval,ns_min,ns_max,pareto_ns. */
void bk_timing_csv(FILE *f, const bk_compare_row *rows, int n);

/* The plot of error (max_abs, log axis) against cost (xaxis 0), ns/eval (xaxis 1)
 * or ACO's net instructions on info's chip xaxis - 2, as DIR/STEM.png, .svg and
 * .pdf (plot.h; 7 x 4.2 in, a paper's double column): the front as a dashed
 * staircase, its members filled, the others hollow, a marker shape and colour per
 * kind, every point labelled where its label meets nothing (the others named in
 * the footnote). info NULL: BK_COMPARE_INFO_INIT. Returns 0, or -1 with a message. */
int bk_compare_plot(const bk_compare_row *rows, int n, int xaxis, const char *title, const bk_compare_info *info,
                    const char *dir, const char *stem, char *err, size_t errlen);
/* What that plot holds, for tests: points drawn, front staircase vertices, labels placed. */
int bk_compare_plot_points(const bk_compare_row *rows, int n, int xaxis, const bk_compare_info *info,
                           int *shown, int *front, int *labels_placed);
/* bk_plot_unexplained of that plot: -1 when the legend explains every marker drawn;
 * -2 when out of memory. */
int bk_compare_plot_unexplained(const bk_compare_row *rows, int n, int xaxis, const bk_compare_info *info);

#endif
