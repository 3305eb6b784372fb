/*
 * gpucost.h — what a form costs in real GPU machine code: its GLSL inside a
 * compute shader, compiled to SPIR-V in-process (glslang's C interface), then
 * to AMD ISA by Mesa RADV's null device (the ACO compiler, no GPU needed), one
 * RADV_FORCE_FAMILY chip at a time. Figures are read from
 * VK_KHR_pipeline_executable_properties (statistics and the disassembly) and
 * reported net of a load/store baseline shader with the same inputs.
 *
 * AMD only: no mobile compiler runs offline on Debian amd64
 * (shared/references/gpu_compilers.md).
 */
#ifndef ANALYSIS_GPUCOST_H
#define ANALYSIS_GPUCOST_H

#include "brdf.h"

#include <stddef.h>

#define BK_GPUCOST_MAX_CHIPS 16
#define BK_GPUCOST_DEFAULT_CHIPS "polaris10,vega10,navi21,gfx1100"

/* What a missing driver's line ends with (bk_gpucost_run returns
 * BK_GPUCOST_NO_DRIVER) when RADV's ICD file is not installed; when it is,
 * the line names what keeps it from loading (a VK_ICD_FILENAMES elsewhere). */
#define BK_GPUCOST_INSTALL "install it: apt-get install mesa-vulkan-drivers"
#define BK_GPUCOST_NO_DRIVER 1

/* One shader's figures. The first five come from ACO's statistics, the rest
 * are counted in the disassembly (repeats expanded): transcendental v_rcp,
 * v_exp, v_sqrt, v_rsq, v_log in any float width; fma every float multiply-add
 * (v_fma*, v_mad*, v_mac*, v_fmac, v_fmaak, v_fmamk, v_pk_fma); packed v_pk_*;
 * convert v_cvt_*. In a result they are the form's shader minus the baseline. */
typedef struct bk_gpucost_stats {
	long instructions, vgprs, sgprs, latency, throughput;
	long transcendental, fma, packed, convert;
} bk_gpucost_stats;

/* One job: a form (a split-sum entry: A and B, evaluated in one shader, both
 * stored) with its parameters baked in. bk_gpucost_run fills net[] per chip;
 * ok[c] is 0 where the chip cannot run it (fp16 on a chip without
 * shaderFloat16). */
typedef struct bk_gpucost_job {
	const bk_form *form[2]; /* form[1] NULL unless split */
	const double *params;   /* may be NULL for a form without parameters */
	bk_gpucost_stats net[BK_GPUCOST_MAX_CHIPS];
	int ok[BK_GPUCOST_MAX_CHIPS];
} bk_gpucost_job;

/* 0 if chip is a name RADV's null device takes (case-insensitive; Mesa
 * aborts on any other), with its generation ("gfx10.3") in *gfx; -1 if not.
 * bk_gpucost_chip_list: the accepted names, comma-separated. */
int bk_gpucost_chip(const char *chip, const char **gfx);
const char *bk_gpucost_chip_list(void);
/* A comma-separated list (cut in place) into at most max names; 0, or -1 with
 * a message naming the bad one: unknown, named twice (case-insensitive), or
 * an empty item ("navi21,"). */
int bk_gpucost_chips(char *list, const char **chip, int max, int *n, char *err, size_t errlen);

/* The compute shader of a job (form NULL: the baseline for the given input
 * set and part count), fp16: float16_t arithmetic. Malloc'd GLSL, or NULL when
 * code generation fails (out of memory, parameters missing). */
char *bk_gpucost_glsl(const bk_form *const form[2], const double *params, unsigned inputs, int nparts,
                      int fp16);

/* GLSL to SPIR-V in-process. Returns malloc'd words and their count in *n, or
 * NULL with glslang's log in err. */
unsigned *bk_gpucost_spirv(const char *glsl, size_t *n, char *err, size_t errlen);

/* Adds the counts of one ISA listing into s (the last four fields only). */
void bk_gpucost_isa_count(const char *isa, bk_gpucost_stats *s);

/* Compiles every job and its baseline for every chip (one Vulkan instance
 * per chip: RADV reads RADV_FORCE_FAMILY when the instance enumerates its
 * devices). Sets VK_ICD_FILENAMES (unless already set) and
 * MESA_SHADER_CACHE_DISABLE for this process. driver gets the driver's name
 * and version ("radv Mesa 22.3.6"). Returns 0; BK_GPUCOST_NO_DRIVER with one
 * line in err naming the package to install; -1 with a message. isa, if not
 * NULL, is n * nchips pointers: [i * nchips + c] gets a malloc'd copy of job
 * i's disassembly on chip c, NULL where it was not compiled (the caller frees
 * each, whatever the return). */
int bk_gpucost_run(bk_gpucost_job *jobs, int n, const char *const *chips, int nchips, int fp16, char *driver,
                   size_t driverlen, char **isa, char *err, size_t errlen);
/* Progress of the bk_gpucost_run calls that follow: fn(ctx, done, n * nchips)
 * after each job on each chip (NULL: none, the default). For the command
 * line, which sets it once before its one run. */
void bk_gpucost_progress(bk_progress_fn fn, void *ctx);

/* The columns other commands join (compare, search, scene): n forms given
 * as text (a[i], b[i] the second part of a split-sum entry or NULL; a[i]
 * NULL: no form, e.g. a LUT row) with params[i] baked in, fp32, every chip.
 * Fills [i * nchips + c] of insn, transc and vgprs (net instructions,
 * transcendental ops, VGPRs; any of them may be NULL) with NaN where nothing
 * was compiled. Returns as bk_gpucost_run; a form that does not parse is an
 * error. */
int bk_gpucost_texts(const char *const *a, const char *const *b, const double *const *params, int n,
                     const char *const *chips, int nchips, double *insn, double *transc, double *vgprs,
                     char *driver, size_t driverlen, char *err, size_t errlen);

/* The same for forms held as IR (a[i] NULL: no form; b NULL, or b[i] NULL:
 * no second part): bk_gpucost_texts is this after parsing its text. */
int bk_gpucost_forms(const bk_form *const *a, const bk_form *const *b, const double *const *params, int n,
                     const char *const *chips, int nchips, double *insn, double *transc, double *vgprs,
                     char *driver, size_t driverlen, char *err, size_t errlen);

/* Compiles one trivial form on every chip: a missing driver or a chip it
 * refuses is said before a long run that would need it, not after. Returns as
 * bk_gpucost_texts. */
int bk_gpucost_check(const char *const *chips, int nchips, char *driver, size_t driverlen, char *err,
                     size_t errlen);

/* ---- calibration: the IR's cost model against ACO's counts ------------------------ */

/* Spearman's rank correlation of x and y over n pairs (ties get their average
 * rank, so it is Pearson's on ranks); NaN when n < 2 or a series is constant. */
double bk_gpucost_spearman(const double *x, const double *y, int n);

/* Least squares y ~ wa a + wb b with no intercept, as bk_ops_cost has none
 * (the 2x2 normal equations). 0, or -1 when a and b are collinear. */
int bk_gpucost_fit2(const double *a, const double *b, const double *y, int n, double *wa, double *wb);

#endif
