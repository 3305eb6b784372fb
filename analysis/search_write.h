/*
 * search_write.h — brdfkit search's files: front.csv, catalog.csv,
 * candidates.csv, pareto.{svg,png,pdf}, section.html, and the lines of its report, all
 * from the refitted front (search_front.h) and what the run was (its
 * command, islands, seed, fits). Writers only: the directory, whole or not
 * at all, is the caller's (out.h).
 */
#ifndef ANALYSIS_SEARCH_WRITE_H
#define ANALYSIS_SEARCH_WRITE_H

#include "halfvs.h"
#include "search_front.h"

#include <stdio.h>

typedef struct bk_swrite {
	const bk_sfront *F;
	const bk_target_options *to;
	const char *command;      /* the command line, in every header */
	const char *out;          /* --out: the section's id is its last component */
	const char *prefix;       /* links of section.html (--link-prefix), or NULL */
	const char *cost_model;   /* --cost-model, or NULL */
	long seed, total_evals;
	const char *islands_name; /* the MPI library (islands > 1) */
	long migrate, migrants;
	int merge_fronts;
	const char *const *chip;  /* --gpu */
	int nchips;
	const bk_halfvs *vs;      /* --vs-front: the half front against the double one, or NULL */
	const char *vs_path;      /* its front.csv */
	const bk_search_cert *cert; /* how far the run is complete (all islands) */
	const char *env_form;     /* env: --env-form (pair, f0, mix), or NULL */
} bk_swrite;

/* What was searched, for titles: the target's name and what sets this study apart
 * from another on the same target: env's form ("env_f0: f0 A + B as one form in f0",
 * "env_mix: ..."), f's index ("f: Fresnel of n = 0.27 + 2.78i, f0 = 0.884"). */
void bk_swrite_target_label(const bk_swrite *W, char *out, size_t len);


void bk_swrite_front_csv(FILE *f, const bk_swrite *W);
void bk_swrite_catalog_csv(FILE *f, const bk_swrite *W);
void bk_swrite_candidates_csv(FILE *f, const bk_swrite *W);
/* DIR/pareto.png, .svg, .pdf (plot.h). Returns 0, or -1 with "path: what" in err. */
int bk_swrite_plot(const bk_swrite *W, const char *dir, char *err, size_t errlen);
void bk_swrite_section(FILE *f, const bk_swrite *W);
/* vs_double.csv (--vs-front; halfvs.h). */
void bk_swrite_vs_csv(FILE *f, const bk_swrite *W);
/* The front, then the catalog rows, one line each (brdfkit search's stdout). */
void bk_swrite_report(FILE *f, const bk_swrite *W);

#endif
