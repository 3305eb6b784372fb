/*
 * fit_out.h — what `brdfkit fit --out DIR` writes (coefficients.csv,
 * metrics.csv, metrics_env.csv, heatmap*.{exr,png,csv}, shader.{c,glsl,hlsl},
 * shader.metal, and a half run's shader_f16.{glsl,hlsl}), shared by fit and
 * by search, which writes the same for each front member.
 */
#ifndef ANALYSIS_CLI_FIT_OUT_H
#define ANALYSIS_CLI_FIT_OUT_H

#include "cli.h"
#include "fit.h"

#include <stddef.h>

typedef struct fit_run {
	const char *command;          /* the command line, for headers and shaders */
	const bk_target_options *to;
	const char *domain;           /* target form: the --domain text */
	const bk_samples *s;
	const bk_fit_spec *spec;
	const bk_fit_result *res;
	const char *name;             /* the form in tables and titles: catalog name or "form" */
	const char *fname;            /* the generated function's name */
	const char *source;           /* citation, "user form", or the search's provenance */
	const char *convention;
	const double *published;      /* the catalog's constants, or NULL */
	int split;                    /* env: two forms A, B */
	const bk_form *f[2];
	int cell_csv;                 /* 1: heatmaps also as per-cell CSV */
	int half;                     /* the shaders in half precision (a half search's front member) */
	const char *error;            /* the shaders' "fitted error" line, or NULL: the fit's f64 metrics */
	unsigned signature;           /* a front member: its front's one signature (member.h; bk_emit_style's
	                               * inputs, constants named; a pair also wrapped); 0: the form's own inputs */
} fit_run;

/* Whether the target has a plane to draw: a form target over three or more
 * inputs has none. */
int fit_has_plane(const fit_run *R);

/* Writes everything into the existing directory dir. Returns 0, or -1 (err
 * may then say why). */
int fit_write_into(const fit_run *R, const char *dir, char *err, size_t errlen);

/* ---- the target options of fit, shared with search (cmd_fit.c) ---------- */

/* The target kind as a dimension of an applicability table (cli.h): value k
 * is bk_target_kind k. */
#define FIT_TARGET_DIM                                                                                    \
	{"target",                                                                                        \
	 {"vf2d", "vf", "spec", "env", "d", "f", "form", "ms", "sheen", "table", "merl"},                  \
	 {" on target vf2d", " on target vf", " on target spec", " on target env", " on target d",        \
	  " on target f", " on target form", " on target ms", " on target sheen", " on target table",    \
	  " on target merl"}}
_Static_assert(BK_TARGET_COUNT == 11, "FIT_TARGET_DIM names every target kind in order");
#define FIT_ON(k) (1u << BK_TARGET_##k)
#define FIT_ALL ((1u << BK_TARGET_COUNT) - 1)
#define FIT_FILE (FIT_ON(TABLE) | FIT_ON(MERL)) /* the targets whose samples a file gives */

typedef struct fit_cli {
	const char *target, *form, *form_a, *form_b, *out, *weight, *loss, *tr, *objective, *digits;
	const char *r_range, *x_range, *bounds, *talk, *smith, *hold, *target_form, *domain;
	const char *target_file, *channel; /* table, merl */
	cli_list f0;
	long nx, nr, nu, nphi, starts, seed, max_iter, threads;
	double loss_scale, ior, k;
	int relative;
} fit_cli;

/* fit and search: the memory and time of the target's samples, said before
 * they are built when that is much (cli_estimate): about 168 bytes and 15 us
 * a sample for the reference, the fits and the refit (measured: search on
 * vf2d at --nx 512 --nr 512, and 2.8 GB at 4096 x 4096). */
void fit_say_size(const bk_target_options *to);
/* --domain NAME=LO:HI[,...] into to's domain; 2 after a usage error. */
int fit_domain(const cli_cmd *cmd, const char *text, bk_target_options *to);
/* Defaults of kind, then the target options of a; 2 after an error. */
int fit_setup_target(const fit_cli *a, bk_target_kind kind, bk_target_options *to);
/* table, merl: reads --target-file into *t (zeroed for other targets); 0 or an exit status. */
int fit_read_file(const cli_cmd *cmd, const fit_cli *a, bk_target_kind kind, bk_samples *t);

#endif
