/*
 * halfvs.h — a half-precision front against the double front of the same
 * target and objective (brdfkit search --precision half --vs-front FILE;
 * issue 23's target): at every cost c <= max_cost at which either front has
 * a member, the least double error among the double front's members of cost
 * <= c, the least half error among the half front's, their ratio
 * half / double, and pass = ratio <= BK_HALFVS_TARGET.
 *
 * Conventions (written in vs_double.csv's header): costs are taken from both
 * fronts, distinct, ascending; "best at cost <= c" is the least error, ties
 * to the cheaper member, then the first given; ratio is +inf where the half
 * front has no member of cost <= c (fail), NaN where the double front has
 * none (nothing to match: pass), 1 where both errors are 0.
 */
#ifndef ANALYSIS_HALFVS_H
#define ANALYSIS_HALFVS_H

#include <stdio.h>

#define BK_HALFVS_MAX_COST 16.0 /* the "every cost <= 16" */
#define BK_HALFVS_TARGET 1.25   /* half error <= 1.25 x double error */

typedef struct bk_halfvs_member {
	const char *name; /* borrowed: must outlive the table */
	double cost, err;
} bk_halfvs_member;

typedef struct bk_halfvs_row {
	double cost;
	int d, h;     /* the best member of each front at cost <= c, or -1 */
	double ratio; /* see above */
	int pass;
} bk_halfvs_row;

typedef struct bk_halfvs {
	bk_halfvs_member *d, *h; /* copies of the fronts */
	int nd, nh;
	bk_halfvs_row *row;
	int nrow, npass;
	double worst; /* the largest finite ratio, or NaN; +inf when a row has no half member */
} bk_halfvs;

/* The table of d (double front) and h (half front) up to max_cost; 0, or -1
 * out of memory (v empty). */
int bk_halfvs_build(bk_halfvs *v, const bk_halfvs_member *d, int nd, const bk_halfvs_member *h, int nh,
                    double max_cost);
void bk_halfvs_free(bk_halfvs *v);

/* vs_double.csv: header comments (the command, the double front's path,
 * the objective, the conventions), then cost,double_name,double_error,
 * half_name,half_error,ratio,pass. */
void bk_halfvs_csv(FILE *f, const bk_halfvs *v, const char *command, const char *dpath, const char *objective);
/* The section's part: the two fronts side by side by cost, and how many
 * costs pass (HTML, names escaped; prefix: of the link to vs_double.csv). */
void bk_halfvs_html(FILE *f, const bk_halfvs *v, const char *dpath, const char *objective, const char *prefix);

#endif
