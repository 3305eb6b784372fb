/*
 * search_front.h — the end of brdfkit search: the screening front and the
 * published seeds refitted on the full samples (search/refit.h's preset),
 * scored in the search's precision and in half, held to the search's
 * constraints (search/constraint.h; the published seeds exempt, as in the
 * search), judged for stability in half (stability.h: an analysis-level
 * verdict, hence here and not in fit/), with the catalog rows (published and
 * refitted) and env's DFG LUT rows beside them; the final front: the
 * refitted search members no other beats at no greater cost
 * (search/pareto.h); with --precision half only those safe in half ("as
 * is" or "with guards"): one that is not ("no", "not analysed", "not
 * finite") is left off as an inadmissible one is, and the next fill its
 * place.
 */
#ifndef ANALYSIS_SEARCH_FRONT_H
#define ANALYSIS_SEARCH_FRONT_H

#include "catalog.h"
#include "gpucost.h"
#include "search.h"
#include "search/seeds.h"

#define BK_SFRONT_MAX 48 /* screening front members refitted in full */

/* A member of the final front, or a catalog or LUT row, on the full samples. */
typedef struct bk_sfront_member {
	const bk_cand *c;              /* NULL for a catalog or LUT row */
	const bk_catalog_entry *entry; /* catalog rows */
	int refit;                     /* catalog: 0 published constants, 1 refitted */
	char name[96];
	const char *text, *text_b;
	bk_form *f[2];
	bk_fit_spec spec;
	bk_fit_result res;
	double cost;
	bk_ops ops;
	double err;                    /* the objective on the full samples, in the search precision */
	bk_fit_metrics prec;           /* metrics in the search precision */
	double f16_max;                /* max |error| evaluated in half */
	char verdict[24];              /* stability in half: as is / with guards / no */
	int status;                    /* 0 ok, 1 dropped (not finite or outside the constraints) */
	int front;
	int lut;                       /* a DFG texture row (--fetch-cost): no form, one fetch */
	double gpu_insn[BK_GPUCOST_MAX_CHIPS], gpu_transc[BK_GPUCOST_MAX_CHIPS]; /* NaN: not compiled */
	char *pruned;                  /* owned: text (and text_b after it) once dead branches are removed (search/prune.h), or NULL */
	int npruned;                   /* how many min/max/clamp/saturate nodes that removed */
} bk_sfront_member;

typedef struct bk_sfront {
	const bk_search_options *so; /* objective, precision, weights, constraints, seeds */
	const bk_search *S;
	const bk_samples *s;         /* the full samples */
	bk_target_kind kind;
	bk_smith smith;              /* env: of the LUT rows */
	int luts;                    /* env: add the DFG LUT rows at cost fetch_cost + 1 */
	double fetch_cost;
	bk_progress_fn progress;     /* progress(label, done, total) with the phase's label as ctx, or NULL */
	bk_sfront_member *m;         /* out: catalog rows, LUT rows, then the refitted front */
	int nm;
	int unsafe;                  /* out: --precision half: refitted members left off as not safe in half */
} bk_sfront;

/* 1 when m's stability in half is "as is" or "with guards". */
int bk_sfront_half_safe(const bk_sfront_member *m);

/* Scores the catalog rows of sd's seeds (published, refitted; not the seeds
 * read from a front, sd->from_front), the LUT
 * rows, and the screening front with every seed that fitted, refitted; marks
 * the final front. The members are scored on so->threads threads, each whole
 * by one: the same rows for any count. 0, or -1 (out of memory or a failed
 * refit). */
int bk_sfront_build(bk_sfront *F, const bk_seeds *sd);
void bk_sfront_free(bk_sfront *F);

/* --gpu: the front's members and the catalog rows compiled for each chip
 * (gpucost.h); screened candidates are not. 0, or -1 (message). */
int bk_sfront_gpu(bk_sfront *F, const char *const *chip, int nchips, char *driver, size_t dlen, char *err,
                  size_t errlen);

/* 1 when m beats catalog row q: no dearer and no worse, one of them strictly. */
int bk_sfront_beats(const bk_sfront_member *m, const bk_sfront_member *q);

/* The objective's column name: rmse, max_abs, albedo_max_abs, rmse_rel, max_rel. */
const char *bk_sfront_objective_name(const bk_search_options *so);

#endif
