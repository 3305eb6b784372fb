/*
 * summary.h — the page's first screen (brdfkit report --summary): per target,
 * the best published form against the search's front, computed from the
 * CSVs brdfkit wrote, read by column NAME (csvtab.h), every number tied to the
 * file and line it came from.
 *
 * A target is a directory. A search's (brdfkit search --out DIR) holds
 * catalog.csv (the published forms scored on the search's own samples and
 * objective, each also refitted) and front.csv (the front); both have the
 * columns name, cost, error, and a '#' line "... error: OBJECTIVE in P
 * precision ..." that says what error is. A directory without front.csv but
 * with compare.csv (brdfkit compare --out DIR) is a target with no search:
 * its published rows (kind = published) with cost and max_abs, compare's
 * own objective.
 *
 * The rules (each a plain scan in file order, so ties resolve to the earlier
 * line and the same files give the same row):
 *   published      a catalog row that is none of brdfkit's own: not "NAME
 *                  (refit)", not a typed start ("start K"), not a texture
 *                  ("LUT ..."); in compare.csv, kind == "published";
 *   best published the least error; a tie: the lower cost, then the earlier line;
 *   at cost        the front member of least error with cost <= the best
 *                  published's cost (a tie: lower cost, earlier line); the
 *                  ratio is published error / its error (0: +inf);
 *   match          the cheapest front member with error <= the best
 *                  published's error (a tie: lower error, earlier line);
 *   beaten         published forms p with a front member of cost <= p's
 *                  cost and error < p's error (strictly better at its cost).
 * A field that is empty or not a finite number >= 0 where one is read is an
 * error "FILE:LINE: COLUMN: ..."; a file with no published row, or a front
 * with no row, is an error naming the file.
 */
#ifndef ANALYSIS_SUMMARY_H
#define ANALYSIS_SUMMARY_H

#include <stddef.h>
#include <stdio.h>

#define BK_SUMMARY_NAME 160
#define BK_SUMMARY_PATH 512
#define BK_SUMMARY_FORMULA 32768 /* the largest front formula in results/ is about 9 KB of MathML */

/* One scored row of a file: what a summary cell shows and where it is from. */
typedef struct bk_summary_pick {
	int line; /* of the file, from 1; 0: no such row */
	char name[BK_SUMMARY_NAME];
	double cost, error;
} bk_summary_pick;

/* The rows of one file that the rules look at. */
typedef struct bk_summary_pt {
	int line;
	const char *name;
	double cost, error;
} bk_summary_pt;

typedef struct bk_summary_row {
	char target[BK_SUMMARY_NAME];    /* the directory's last component */
	char objective[BK_SUMMARY_NAME]; /* "max_abs in f64 precision" */
	char cost_model[BK_SUMMARY_NAME];/* "simple*1 + complex*4" from the '# cost:' line; "" when not stated */
	char pub_file[BK_SUMMARY_PATH];  /* catalog.csv or compare.csv, the path read */
	char front_file[BK_SUMMARY_PATH];/* front.csv; "" with no search */
	int has_search;
	int complete; /* front.csv's certificate: complete to this many nodes; 0 none, -1 not stated */
	bk_summary_pick pub, at_cost, match;
	int npub, nbeaten;
	/* The formula the row shows (the at-cost member's; with no search, the
	 * best published form's), constants baked in to 4 digits: MathML Core
	 * from brdf_math.h ("A = <math>..</math>, B = <math>..</math>" for a
	 * split sum); "" when its file has no form column or it does not fit. */
	char formula[BK_SUMMARY_FORMULA];
} bk_summary_row;

/* pick's formula as the page shows it (bk_summary_row.formula), from the row
 * at pick's line of path (a front.csv, catalog.csv or compare.csv: columns
 * form, form_b, parameters by name). 0; -1 with out "" when the file has no
 * such columns or row, or the formula does not fit in len. */
int bk_summary_formula(const char *path, const bk_summary_pick *pick, char *out, size_t len);

/* The rules over published rows pub[0..npub) and front rows front[0..nfront)
 * (nfront 0: no search; at_cost, match and nbeaten stay empty). Fills the
 * picks and counts of row; returns 0, or -1 when npub is 0. */
int bk_summary_compute(const bk_summary_pt *pub, int npub, const bk_summary_pt *front, int nfront,
                       bk_summary_row *row);

/* Reads the target directory dir (as above) into row. 0, or -1 with err:
 * "FILE:LINE: what" or "FILE: what" or "DIR: what". */
int bk_summary_read(const char *dir, bk_summary_row *row, char *err, size_t errlen);

/* published error / at-cost error: +inf when the latter is 0, NaN when
 * there is no at-cost member. */
double bk_summary_ratio(const bk_summary_row *row);

/* The first screen's table, every value escaped: per row, href[i] is the
 * directory as a link from the page (ending in '/', already escaped or
 * plain: it is escaped here). */
void bk_summary_table(FILE *f, const bk_summary_row *rows, int n, const char *const *href);

/* One sentence of what the row's numbers say, plain text (the caller
 * escapes it), written from the picks and counts alone: the searched form
 * at the best published form's cost against it ("At vf_talk_r's cost 8,
 * search_vf2d_7 (cost 8) has max_abs 0.00496, 51.5x less than vf_talk_r's
 * 0.256; 15 of 16 published forms are beaten at their own cost."), or that
 * none at that cost beats it (with what matching it costs, and ", yet N of
 * M ..." when some published forms are beaten), or that the target has no
 * search. Writes at most len bytes with the NUL; returns the whole length,
 * as snprintf. */
size_t bk_summary_finding(const bk_summary_row *row, char *out, size_t len);

#endif
