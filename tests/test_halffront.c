/*
 * test_halffront.c — the half front against the double front
 * (analysis/halfvs.h) on planted pairs of fronts whose table is counted by
 * hand, and a front.csv read back by column name (analysis/frontcsv.h):
 * planted files, good and bad, each bad one named FILE:LINE.
 * (The front's exclusion of members not safe in half is the CLI's:
 * tests/cli_half.sh.)
 */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "frontcsv.h"
#include "halfvs.h"

/* Double front A (1, 0.2), B (4, 0.01), C (20, 0.001: past 16, no row of
 * its own); half front a (1, 0.22), b (5, 0.02), c (16, 0.011). Costs <= 16
 * of either: 1, 4, 5, 16. By hand:
 *   1: A 0.2 vs a 0.22 -> 1.1, pass
 *   4: B 0.01 vs a 0.22 -> 22, fail (the half front has nothing better yet)
 *   5: B 0.01 vs b 0.02 -> 2, fail
 *  16: B 0.01 vs c 0.011 -> 1.1, pass (C costs 20: not counted) */
static const bk_halfvs_member D[] = {{"A", 1, 0.2}, {"B", 4, 0.01}, {"C", 20, 0.001}};
static const bk_halfvs_member H[] = {{"a", 1, 0.22}, {"b", 5, 0.02}, {"c", 16, 0.011}};

Test(halfvs, planted_pair_counted_by_hand)
{
	bk_halfvs v;
	cr_assert_eq(bk_halfvs_build(&v, D, 3, H, 3, BK_HALFVS_MAX_COST), 0);
	cr_assert_eq(v.nrow, 4);
	const double cost[4] = {1, 4, 5, 16}, ratio[4] = {1.1, 22, 2, 1.1};
	const char *dn[4] = {"A", "B", "B", "B"}, *hn[4] = {"a", "a", "b", "c"};
	const int pass[4] = {1, 0, 0, 1};
	for (int i = 0; i < 4; i++) {
		cr_expect_eq(v.row[i].cost, cost[i], "row %d", i);
		cr_expect_str_eq(v.d[v.row[i].d].name, dn[i], "row %d", i);
		cr_expect_str_eq(v.h[v.row[i].h].name, hn[i], "row %d", i);
		cr_expect(fabs(v.row[i].ratio - ratio[i]) < 1e-12, "row %d: ratio %g, by hand %g", i, v.row[i].ratio,
		          ratio[i]);
		cr_expect_eq(v.row[i].pass, pass[i], "row %d", i);
	}
	cr_expect_eq(v.npass, 2);
	cr_expect(fabs(v.worst - 22) < 1e-12);
	bk_halfvs_free(&v);
}

/* The threshold itself: 0.3125 / 0.25 is 1.25 exactly (binary fractions):
 * it passes; 0.3126 / 0.25 does not (the negative control). */
Test(halfvs, threshold_is_inclusive)
{
	bk_halfvs_member d[] = {{"d", 2, 0.25}}, h[] = {{"h", 2, 0.3125}}, h2[] = {{"h", 2, 0.3126}};
	bk_halfvs v;
	cr_assert_eq(bk_halfvs_build(&v, d, 1, h, 1, 16), 0);
	cr_expect_eq(v.row[0].ratio, 1.25);
	cr_expect_eq(v.row[0].pass, 1);
	bk_halfvs_free(&v);
	cr_assert_eq(bk_halfvs_build(&v, d, 1, h2, 1, 16), 0);
	cr_expect_eq(v.row[0].pass, 0);
	cr_expect_eq(v.npass, 0);
	bk_halfvs_free(&v);
}

/* A cost with no half member below it fails (inf); one with no double
 * member has nothing to match (NaN, pass); two zero errors are ratio 1. */
Test(halfvs, missing_sides_and_zeros)
{
	bk_halfvs_member d[] = {{"d0", 0.5, 0.4}, {"dz", 3, 0}}, h[] = {{"h0", 0.25, 0.3}, {"hz", 3, 0}};
	bk_halfvs_member d2[] = {{"d0", 0.5, 0.4}}, h2[] = {{"h1", 2, 0.1}};
	bk_halfvs v;
	cr_assert_eq(bk_halfvs_build(&v, d, 2, h, 2, 16), 0);
	cr_assert_eq(v.nrow, 3); /* 0.25, 0.5, 3 */
	cr_expect(isnan(v.row[0].ratio) && v.row[0].pass && v.row[0].d < 0);
	cr_expect(fabs(v.row[1].ratio - 0.75) < 1e-15 && v.row[1].pass);
	cr_expect_eq(v.row[2].ratio, 1);
	bk_halfvs_free(&v);
	cr_assert_eq(bk_halfvs_build(&v, d2, 1, h2, 1, 16), 0);
	cr_assert_eq(v.nrow, 2); /* 0.5: no half member yet; 2: 0.1 / 0.4 */
	cr_expect(isinf(v.row[0].ratio) && !v.row[0].pass && v.row[0].h < 0);
	cr_expect(fabs(v.row[1].ratio - 0.25) < 1e-15 && v.row[1].pass);
	cr_expect(isinf(v.worst));
	bk_halfvs_free(&v);
}

/* vs_double.csv: the conventions in comments, then the rows as counted. */
Test(halfvs, csv_rows_and_header)
{
	bk_halfvs v;
	cr_assert_eq(bk_halfvs_build(&v, D, 3, H, 3, BK_HALFVS_MAX_COST), 0);
	char *buf = NULL;
	size_t len = 0;
	FILE *f = open_memstream(&buf, &len);
	cr_assert_not_null(f);
	bk_halfvs_csv(f, &v, "brdfkit search x", "d/front.csv", "rmse");
	fclose(f);
	cr_expect_not_null(strstr(buf, "# 2 of 4 costs pass\n"));
	cr_expect_not_null(strstr(buf, "# command: brdfkit search x\n"));
	cr_expect_not_null(strstr(buf, "\ncost,double_name,double_error,half_name,half_error,ratio,pass\n"
	                               "1,A,0.2,a,0.22,1.1,1\n4,B,0.01,a,0.22,22,0\n5,B,0.01,b,0.02,2,0\n"
	                               "16,B,0.01,c,0.011,1.1,1\n"),
	                   "%s", buf);
	free(buf);
	bk_halfvs_free(&v);
}

/* ---- front.csv read back ---------------------------------------------------- */

static char path[64];

static const char *planted(const char *text)
{
	snprintf(path, sizeof path, "/tmp/test_halffront_XXXXXX");
	int fd = mkstemp(path);
	cr_assert(fd >= 0);
	FILE *f = fdopen(fd, "w");
	fputs(text, f);
	fclose(f);
	return path;
}

/* Columns found by name in any order, '#' lines skipped, a quoted form with
 * commas, a pair, the parameters parsed; line numbers of the file. */
Test(frontcsv, reads_by_name)
{
	const char *p = planted("# brdfkit search front\n# command: x\n"
	                        "error,parameters,form_b,cost,name,form,stability_half\n"
	                        "0.5,p0=0.25;p1=-2,,3,one,\"max(p0, LoH) * p1\",as is\n"
	                        "0.125,p0=1e-3,LoH*p0,7.5,two,r + p0,no\n");
	bk_frontcsv fc;
	char err[700];
	cr_assert_eq(bk_frontcsv_read(p, BK_FRONTCSV_FORMS | BK_FRONTCSV_SCORES, &fc, err, sizeof err), 0, "%s", err);
	unlink(p);
	cr_assert_eq(fc.n, 2);
	cr_expect_str_eq(fc.row[0].name, "one");
	cr_expect_str_eq(fc.row[0].form, "max(p0, LoH) * p1");
	cr_expect_null(fc.row[0].form_b);
	cr_expect_eq(fc.row[0].np, 2);
	cr_expect_eq(fc.row[0].p[0], 0.25);
	cr_expect_eq(fc.row[0].p[1], -2);
	cr_expect_eq(fc.row[0].cost, 3);
	cr_expect_eq(fc.row[0].error, 0.5);
	cr_expect_eq(fc.row[0].line, 4);
	cr_expect_str_eq(fc.row[1].form_b, "LoH*p0");
	cr_expect_eq(fc.row[1].p[0], 1e-3);
	cr_expect_eq(fc.row[1].cost, 7.5);
	cr_expect_eq(fc.row[1].line, 5);
	bk_frontcsv_free(&fc);
}

/* A name quoted over lines 3-5: the row, and an error in it, are line 3
 * (the row's first), not 5 (where that field ends, the rule before). */
Test(frontcsv, a_quoted_name_over_lines_gives_the_row_first_line)
{
	const char *p = planted("# c\nname,form,form_b,parameters\n\"two\nline\nname\",LoH,,\nnext,NoV,,\n");
	bk_frontcsv fc;
	char err[700];
	cr_assert_eq(bk_frontcsv_read(p, BK_FRONTCSV_FORMS, &fc, err, sizeof err), 0, "%s", err);
	unlink(p);
	cr_assert_eq(fc.n, 2);
	cr_expect_str_eq(fc.row[0].name, "two\nline\nname");
	cr_expect_eq(fc.row[0].line, 3);
	cr_expect_neq(fc.row[0].line, 5, "the line where the quoted name ends");
	cr_expect_eq(fc.row[1].line, 6);
	bk_frontcsv_free(&fc);
	p = planted("# c\nname,form,form_b,parameters\n\"two\nline\nname\",LoH * (,,\n");
	cr_expect_eq(bk_frontcsv_read(p, BK_FRONTCSV_FORMS, &fc, err, sizeof err), -1);
	unlink(p);
	char want[128];
	snprintf(want, sizeof want, "%s:3: form: column", p);
	cr_expect(!strncmp(err, want, strlen(want)), "'%s' does not start with '%s'", err, want);
}

/* Each bad file fails naming path:line (the negative controls of the above). */
static void expect_bad(const char *text, unsigned need, const char *where, const char *what)
{
	const char *p = planted(text);
	bk_frontcsv fc;
	char err[700], want[256];
	cr_expect_eq(bk_frontcsv_read(p, need, &fc, err, sizeof err), -1, "%s: accepted", what);
	snprintf(want, sizeof want, "%s%s", p, where);
	cr_expect(!strncmp(err, want, strlen(want)), "%s: '%s' does not start with '%s'", what, err, want);
	cr_expect_eq(fc.n, 0);
	unlink(p);
}

Test(frontcsv, bad_files_name_file_and_line)
{
	unsigned F = BK_FRONTCSV_FORMS, S = BK_FRONTCSV_SCORES;
	expect_bad("# c\nname,form,form_b\nx,LoH,\n", F, ":2: no column 'parameters'", "missing column");
	expect_bad("name,form,form_b,parameters\nx,LoH,,\ny,LoH * (p0,,p0=1\n", F, ":3: form: column", "bad form");
	expect_bad("name,form,form_b,parameters\nx,LoH,,\ny,LoH,r +,\n", F, ":3: form_b: column", "bad form_b");
	expect_bad("name,form,form_b,parameters\nx,p0 * p1,,p0=1\n", F, ":2: parameters: the form uses p1", "missing p1");
	expect_bad("name,form,form_b,parameters\nx,p0,,p0=1;p0=2\n", F, ":2: parameters: p0 given twice in the list 'p0=1;p0=2' (item 2)", "p0 twice");
	expect_bad("name,form,form_b,parameters\nx,p0,,p0=nan\n", F, ":2: parameters: p0: expected a finite number, got 'nan' (item 1)", "nan");
	expect_bad("name,cost,error\nx,3,\n", S, ":2: error:", "empty error");
	expect_bad("name,cost,error\nx,-1,0.1\n", S, ":2: cost:", "negative cost");
	expect_bad("name,form,form_b,parameters\nx,LoH\n", F, ":2: 2 fields", "short row");
	expect_bad("# only comments\n", F, ": empty", "empty");
	bk_frontcsv fc;
	char err[700];
	cr_expect_eq(bk_frontcsv_read("/nonexistent/front.csv", F, &fc, err, sizeof err), -1);
	cr_expect(!strncmp(err, "/nonexistent/front.csv: cannot be read", 38), "%s", err);
}

Test(frontcsv, dir_is_the_folder_that_holds_the_file)
{
	char d[64];
	bk_frontcsv_dir("results/search/env/front.csv", 0, d, sizeof d);
	cr_assert_str_eq(d, "env");
	bk_frontcsv_dir("/tmp/x/front.csv", 1, d, sizeof d);
	cr_assert_str_eq(d, "x");
	bk_frontcsv_dir("front.csv", 1, d, sizeof d); /* no folder: "" or the path */
	cr_assert_str_eq(d, "");
	bk_frontcsv_dir("front.csv", 0, d, sizeof d);
	cr_assert_str_eq(d, "front.csv");
	bk_frontcsv_dir("/front.csv", 1, d, sizeof d); /* the root has no name */
	cr_assert_str_eq(d, "");
	char d4[4]; /* cut to fit */
	bk_frontcsv_dir("a/search_env/front.csv", 1, d4, sizeof d4);
	cr_assert_str_eq(d4, "sea");
}
