/*
 * target.h — what a fit approximates: samples of an exact quantity from
 * brdf/ (inputs, value, weight) over a domain, and the 2-D plane its error is
 * shown on.
 */
#ifndef FIT_TARGET_H
#define FIT_TARGET_H

#include "brdf.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" { /* C linkage for a C++ program (tests/install.sh links one) */
#endif

typedef enum bk_target_kind {
	BK_TARGET_VF2D, /* talk's modified Kelemen V × Schlick F on (LoH, r) */
	BK_TARGET_VF,   /* exact correlated Smith V × Schlick F over (NoV, L, r), D·NoL weighted */
	BK_TARGET_SPEC, /* the whole D·V·F·NoL over the same configurations */
	BK_TARGET_ENV,  /* split-sum A, B over (NoV, r) */
	BK_TARGET_D,    /* GGX D over (NoH, r) */
	BK_TARGET_F,    /* exact Fresnel over LoH */
	BK_TARGET_FORM, /* a formula (form_text) on a box of the inputs it reads (domain) */
	BK_TARGET_MS,   /* GGX directional albedo E = A + B (F = 1) over (NoV, r): multiscatter's input */
	BK_TARGET_SHEEN, /* sheen albedo (Charlie D, Neubelt V, F = 1) over (NoV, r): Filament's cloth DFG */
	BK_TARGET_TABLE, /* samples read from a user's file (CSV or EXR 2-D table): table */
	BK_TARGET_MERL,  /* samples of a MERL measured BRDF (one channel): table */
	BK_TARGET_COUNT
} bk_target_kind;

typedef enum bk_weight_kind { BK_WEIGHT_DEFAULT, BK_WEIGHT_NONE, BK_WEIGHT_DNOL } bk_weight_kind;

#define BK_TARGET_MAX_F0 8

typedef struct bk_target_options {
	bk_target_kind kind;
	double r_lo, r_hi;   /* perceptual roughness range */
	double x_lo, x_hi;   /* LoH (vf2d, f), NoV (vf, spec, env), NoH (d) */
	int nx, nr;          /* grid cells along x and r */
	int nu, nphi;        /* vf/spec: half-vector cells (GGX CDF) and azimuths */
	double f0[BK_TARGET_MAX_F0];
	int nf0;             /* vf2d, vf, spec use f0[0]; env in-f0 forms use all */
	int talk_alpha;      /* vf2d: read the talk's "roughness" as alpha */
	bk_smith smith;      /* env, ms */
	double eta, k;       /* f: complex index (k = 0: dielectric) */
	bk_weight_kind weight;
	int env_f0_form;     /* env: one form in f0, fitted to f0 A + B */
	/* form: the expression (no parameters) and its domain, one closed
	 * interval per input it reads, axes in the order given (the first varies
	 * fastest; r stands for a = r^2 too); nx cells per axis (0: about 4096
	 * samples in all) */
	const char *form_text;
	int ndomain;
	int dom_in[BK_IN_COUNT];
	double dom_lo[BK_IN_COUNT], dom_hi[BK_IN_COUNT];
	/* table, merl: the samples as a reader made them (analysis/tabtarget.h:
	 * fit/ reads no file formats); bk_target_build copies them, so one
	 * reading serves several builds (search's screen and full samples);
	 * nx > 0 keeps about nx of them, every k-th (0, the default: all) */
	const struct bk_samples *table;
	/* env, ms, sheen: the reference integrals of the cells, already made
	 * (bk_target_reference; analysis/lutcache.h keeps them on disk between
	 * runs), 2 nx nr doubles; NULL: the build integrates them itself. The
	 * samples are the same bits either way. */
	const double *reference;
} bk_target_options;

/* Defaults for a kind (domain, sizes): the and the talk's. */
void bk_target_defaults(bk_target_kind kind, bk_target_options *o);
const char *bk_target_name(bk_target_kind kind);
int bk_target_parse(const char *name, bk_target_kind *kind);

/* Samples: component c (0 or 1: A and B of a split-sum fit) occupies
 * [start[c], start[c + 1]); cell[i] is the plane cell a sample's error goes to. */
typedef struct bk_samples {
	size_t n;
	double *in[BK_IN_COUNT];
	double *y;         /* the exact value */
	double *w;         /* least-squares weight (each roughness weighs the same) */
	double *measure;   /* what turns a sum over a cell into an integral (albedo), or 0 */
	int *cell;
	size_t start[3];
	int ncomp;
	unsigned provides; /* bit i: input i is meaningful for this target (others are NaN) */
	int plane_nx, plane_ny;
	double plane_x0, plane_x1, plane_y0, plane_y1;
	const char *plane_xname, *plane_yname;
	int plane_x_input, plane_y_input; /* the input each plane axis is, or -1 */
	char description[512]; /* the target, its units and conventions, one paragraph */
} bk_samples;

/* Builds the samples; progress (may be NULL) for the slow env reference.
 * Returns 0, or -1 with a message. */
int bk_target_build(const bk_target_options *o, bk_samples *s, bk_progress_fn progress,
                    void *ctx, char *err, size_t errlen);
void bk_samples_free(bk_samples *s);

/* form: checks the expression against the domain before any sample is
 * built: it parses, has no parameters, every input it reads is in the
 * domain (a is covered by r) and every domain input is read. Returns 0, or
 * -1 with a message. */
int bk_target_form_check(const bk_target_options *o, char *err, size_t errlen);
/* form: the cells per axis a build will use. */
int bk_target_form_cells(const bk_target_options *o);
/* The samples bk_target_build allocates for o (vf/spec: before the cells
 * under the horizon are dropped), so a caller can say the memory before. */
size_t bk_target_samples(const bk_target_options *o);

/* The work of bk_target_build up front: *integrals, the reference integrals
 * it will compute (env: one per cell; 0 for the targets whose samples are
 * closed forms), and the return value, the seconds they will take on this
 * machine, timed on a 4x4 sample of the cells (about 1/250 of a default
 * 64x64 build). */
double bk_target_estimate(const bk_target_options *o, double *integrals);

/* The reference integrals of env, ms and sheen, one per cell (j nx + k: r's
 * row j, x's column k, the cell centres bk_target_build samples), each by
 * the reference integrator at tol 1e-8: the DFG's A (first nx nr doubles)
 * and B (the next) for env and ms (ms samples A + B), the sheen albedo and
 * 0 for sheen. bk_target_reference_cells: how many cells (0: a target whose
 * samples are closed forms or a file's, which has none). */
size_t bk_target_reference_cells(const bk_target_options *o);
/* Cell c's two values. 0, or -1 when the integral failed. */
int bk_target_reference_cell(const bk_target_options *o, size_t c, double *A, double *B);
/* Every cell's into AB (2 bk_target_reference_cells doubles), progress by
 * rows of r. 0, or -1 with a message naming the cell. */
int bk_target_reference(const bk_target_options *o, double *AB, bk_progress_fn progress, void *ctx, char *err,
                        size_t errlen);

#ifdef __cplusplus
}
#endif

#endif
