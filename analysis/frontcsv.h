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
 * ("p0=X;p1=Y", every p the forms use given, each once, finite);
 * BK_FRONTCSV_SCORES cost and error (finite, >= 0).
 */
#ifndef ANALYSIS_FRONTCSV_H
#define ANALYSIS_FRONTCSV_H

#include "brdf.h"

#include <stddef.h>

#define BK_FRONTCSV_FORMS 1u
#define BK_FRONTCSV_SCORES 2u
#define BK_FRONTCSV_MAX_ROWS 4096 /* more is no front brdfkit writes */

typedef struct bk_frontcsv_row {
	int line;             /* of the file, from 1: where the row starts */
	char *name;           /* the name column, or "row LINE" */
	char *form, *form_b;  /* FORMS: the texts (form_b NULL for one form) */
	double p[BK_MAX_PARAMS];
	int np;               /* FORMS: the forms' highest p index + 1 */
	double cost, error;   /* SCORES; NaN otherwise */
} bk_frontcsv_row;

typedef struct bk_frontcsv {
	bk_frontcsv_row *row;
	int n;
} bk_frontcsv;

/* Reads path; 0, or -1 with err "PATH:LINE: what" (or "PATH: what"), and
 * fc empty. */
int bk_frontcsv_read(const char *path, unsigned need, bk_frontcsv *fc, char *err, size_t errlen);
void bk_frontcsv_free(bk_frontcsv *fc);

#endif
