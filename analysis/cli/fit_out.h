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

typedef struct fitout_run {
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
} fitout_run;

/* Whether the target has a plane to draw: a form target over three or more
 * inputs has none. */
int fitout_has_plane(const fitout_run *R);

/* Writes everything into the existing directory dir. Returns 0, or -1 (err
 * may then say why). */
int fitout_write_into(const fitout_run *R, const char *dir, char *err, size_t errlen);

#endif
