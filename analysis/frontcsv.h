/*
 * frontcsv.h — a front.csv of brdfkit search read back (csvtab.h), for
 * search's --start-front (its members as seeds) and --vs-front (its errors
 * beside the half front, halfvs.h). The file is a user's: its '#' lines
 * before the header are skipped, its columns are found by NAME in the
 * header, and every bad row is an error naming FILE:LINE (the line the row
 * starts on, csvtab.h); forms go through the formula parser.
 *
 * Columns read: name (optional; "row LINE" when absent), and what `need`
 * asks for: BK_FRONTCSV_FORMS form, form_b (empty: one form), parameters
 * ("p0=X;p1=Y", params.h: every p the forms use given, each once, finite);
 * BK_FRONTCSV_SCORES cost and error (finite, >= 0).
 */
#ifndef ANALYSIS_FRONTCSV_H
#define ANALYSIS_FRONTCSV_H

#include "brdf.h"
#include "csvtab.h"

#include <stddef.h>

#define BK_FRONTCSV_FORMS 1u
#define BK_FRONTCSV_SCORES 2u
#define BK_FRONTCSV_MAX_ROWS 4096 /* more is no front brdfkit writes */

typedef struct bk_frontcsv_row {
	int line;             /* of the file, from 1: where the row starts */
	char *name;           /* the name column, or "row LINE" */
	char *form, *form_b;  /* FORMS: the texts (form_b NULL for one form) */
	bk_form *f, *f_b;     /* FORMS: the texts parsed, here and only here (owned; a reader
	                       * uses or copies them rather than parse the texts again) */
	double p[BK_MAX_PARAMS];
	int np;               /* FORMS: the forms' highest p index + 1 */
	double cost, error;   /* SCORES; NaN otherwise */
} bk_frontcsv_row;

/* What a file of brdfkit search states in its '#' lines before the header
 * (analysis/search_write.c writes them): which file it is, the target
 * (the samples' description, bk_samples), the objective and precision
 * ("# cost: ...; error: OBJ in PREC precision ..."). "" where not stated. */
enum { BK_FRONTCSV_UNKNOWN, BK_FRONTCSV_FRONT, BK_FRONTCSV_CATALOG };
typedef struct bk_frontcsv_head {
	int kind;            /* "# brdfkit V search front ..." / "... search published forms ..." */
	char target[520];    /* the "# target: " line's text */
	char objective[32];  /* rmse, max_abs, ... */
	char precision[16];  /* f64, f32, f16 */
} bk_frontcsv_head;

typedef struct bk_frontcsv {
	bk_frontcsv_row *row;
	int n;
	bk_frontcsv_head head;
} bk_frontcsv;

/* Reads path; 0, or -1 with err "PATH:LINE: what" (or "PATH: what"), and
 * fc empty. */
int bk_frontcsv_read(const char *path, unsigned need, bk_frontcsv *fc, char *err, size_t errlen);
void bk_frontcsv_free(bk_frontcsv *fc);

/* The folder that holds path, which names its members where several fronts
 * meet (two searches both have a search_env_10): "results/search/env/
 * front.csv" gives "env"; a path without a folder gives "" (dir_only) or
 * path itself. Cut to fit len. */
void bk_frontcsv_dir(const char *path, int dir_only, char *out, size_t len);

/* The one reader of brdfkit's result CSVs, for bk_frontcsv_read and the
 * page's summary (summary.c: front.csv, catalog.csv, compare.csv): path
 * read by column name (csvtab.h: cols, optional, hint as in
 * bk_csvtab_spec; at most BK_FRONTCSV_MAX_ROWS rows), its '#' lines before
 * the header into head and, each, to more(ctx, LINE) when more is not
 * NULL. 0; or -1 / -2 with err as bk_csvtab_read (t then empty). */
int bk_frontcsv_table(const char *path, const char *const *cols, unsigned optional, const char *hint,
                      void (*more)(void *ctx, const char *line), void *ctx, bk_frontcsv_head *head, bk_csvtab *t,
                      char *err, size_t errlen);

/* Row i's column k of t (named name, for the message) as a cost or an
 * error: a finite decimal number >= 0 (bk_csvtab_number). 0, or -1 with
 * err "PATH:LINE: NAME: expected a finite number >= 0, got 'X'". */
int bk_frontcsv_score(const bk_csvtab *t, int i, int k, const char *name, double *v, char *err, size_t errlen);

/* The file at path is refused unless h states a file of brdfkit search of
 * kind (BK_FRONTCSV_FRONT or _CATALOG) of the target described by target
 * (whose: "this search's", whose target it is; "": stated, any; exact: the
 * whole description; else the sample counts, digits after '(' or "a ", may
 * differ, and are shown as N: the same target and domain on another grid),
 * and the objective and
 * precision given (NULL: any). 0, or -1 with err "PATH: a front of target
 * vf2d, this search's target is f" (one mismatch named, the first of kind,
 * target, objective, precision). */
int bk_frontcsv_head_check(const bk_frontcsv_head *h, const char *path, int kind, const char *whose,
                           const char *target, int exact, const char *objective, const char *precision, char *err,
                           size_t errlen);

#endif
