/*
 * test_summary.c — the page's first screen (analysis/summary.c): the rules
 * on planted points whose answers are counted by hand (ties to the lower
 * cost, then the earlier line; "beaten" strictly), a target with no search,
 * files read by column name whatever their order, brdfkit's own catalog rows
 * left out, and every bad field an error naming FILE:LINE. Each rule has a
 * control that moves one value across its edge and sees the answer change.
 */
#include "summary.h"
#include "fixture_tmpdir.h"

#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---- the rules --------------------------------------------------------------------- */

#define PT(l, n, c, e) {(l), (n), (c), (e)}

/* pub: A and C tie on error and cost (A's line first), B is cheaper and
 * worse. front: f3 and f4 tie (f3 first), f5 is better and dearer. By hand:
 * best published A (8, 0.2); at cost <= 8 the least error is 0.1, f3 (line
 * 13) before f4; ratio 0.2/0.1 = 2; as accurate (<= 0.2) the cheapest is
 * cost 8, f3; beaten: A and C by f3 (8, 0.1), B (4, 0.3) by f2 (4, 0.25). */
static const bk_summary_pt pub[] = {PT(5, "A", 8, 0.2), PT(6, "B", 4, 0.3), PT(7, "C", 8, 0.2)};
static const bk_summary_pt front[] = {PT(11, "f1", 1, 0.5), PT(12, "f2", 4, 0.25), PT(13, "f3", 8, 0.1),
                                      PT(14, "f4", 8, 0.1), PT(15, "f5", 10, 0.05)};

Test(summary_rules, picks_counted_by_hand)
{
	bk_summary_row r;
	cr_assert_eq(bk_summary_compute(pub, 3, front, 5, &r), 0);
	cr_expect_str_eq(r.pub.name, "A");
	cr_expect_eq(r.pub.line, 5);
	cr_expect_str_eq(r.at_cost.name, "f3");
	cr_expect_eq(r.at_cost.line, 13);
	cr_expect_float_eq(bk_summary_ratio(&r), 2.0, 1e-12);
	cr_expect_str_eq(r.match.name, "f3");
	cr_expect_eq(r.nbeaten, 3);
	cr_expect_eq(r.npub, 3);
	cr_expect(r.has_search);
}

Test(summary_rules, ties_go_to_the_lower_cost_then_the_earlier_line)
{
	/* published: equal error, the cheaper wins even when it comes later */
	bk_summary_pt p[] = {PT(2, "dear", 10, 0.1), PT(3, "cheap", 6, 0.1)};
	bk_summary_pt f[] = {PT(2, "x", 6, 0.05), PT(3, "y", 5, 0.05), PT(4, "z", 5, 0.05)};
	bk_summary_row r;
	cr_assert_eq(bk_summary_compute(p, 2, f, 3, &r), 0);
	cr_expect_str_eq(r.pub.name, "cheap");
	/* at cost <= 6: all three at 0.05; y and z cost 5, y first */
	cr_expect_str_eq(r.at_cost.name, "y");
	cr_expect_str_eq(r.match.name, "y");
	/* control: z a hair better, and it wins both */
	f[2].error = 0.049;
	cr_assert_eq(bk_summary_compute(p, 2, f, 3, &r), 0);
	cr_expect_str_eq(r.at_cost.name, "z");
	cr_expect_str_eq(r.match.name, "z", "as accurate: y and z tie on the least cost, 5; z has the lower error");
}

Test(summary_rules, beaten_is_strict_and_at_own_cost)
{
	bk_summary_pt p[] = {PT(2, "P", 4, 0.25)};
	bk_summary_pt f[] = {PT(2, "same", 4, 0.25), PT(3, "dearer", 5, 0.01)};
	bk_summary_row r;
	cr_assert_eq(bk_summary_compute(p, 1, f, 2, &r), 0);
	cr_expect_eq(r.nbeaten, 0, "equal error is no win, and a better form at cost 5 is not at P's cost 4");
	cr_expect_float_eq(bk_summary_ratio(&r), 1.0, 1e-12);
	f[0].error = 0.2499; /* control: a hair better at the same cost */
	cr_assert_eq(bk_summary_compute(p, 1, f, 2, &r), 0);
	cr_expect_eq(r.nbeaten, 1);
}

Test(summary_rules, nothing_at_that_cost_and_nothing_as_accurate)
{
	bk_summary_pt p[] = {PT(2, "P", 2, 0.1)};
	bk_summary_pt f[] = {PT(2, "f", 3, 0.2)};
	bk_summary_row r;
	cr_assert_eq(bk_summary_compute(p, 1, f, 1, &r), 0);
	cr_expect_eq(r.at_cost.line, 0);
	cr_expect(isnan(bk_summary_ratio(&r)));
	cr_expect_eq(r.match.line, 0);
	f[0].cost = 2; /* control: at the cost, and then there */
	f[0].error = 0.1;
	cr_assert_eq(bk_summary_compute(p, 1, f, 1, &r), 0);
	cr_expect_eq(r.at_cost.line, 2);
	cr_expect_eq(r.match.line, 2, "error 0.1 <= 0.1 is as accurate");
}

Test(summary_rules, an_exact_member_and_no_search)
{
	bk_summary_pt p[] = {PT(2, "P", 4, 0.1)};
	bk_summary_pt f[] = {PT(2, "exact", 3, 0.0)};
	bk_summary_row r;
	cr_assert_eq(bk_summary_compute(p, 1, f, 1, &r), 0);
	cr_expect(isinf(bk_summary_ratio(&r)));
	cr_assert_eq(bk_summary_compute(p, 1, NULL, 0, &r), 0);
	cr_expect(!r.has_search);
	cr_expect_eq(r.at_cost.line, 0);
	cr_expect_eq(r.nbeaten, 0);
	cr_expect_str_eq(r.pub.name, "P");
	cr_expect_eq(bk_summary_compute(p, 0, f, 1, &r), -1, "no published row: nothing to compare");
}

/* ---- reading planted files -------------------------------------------------------- */

static char dir[64], err[1024];

static void make_dir(void) { fx_tmpdir_make(dir, sizeof dir, "summary"); }

static void remove_dir(void) { fx_tmpdir_remove(dir); }

static const char *put(const char *sub, const char *name, const char *text)
{
	static char path[256];
	snprintf(path, sizeof path, "%s/%s", dir, sub);
	mkdir(path, 0700);
	snprintf(path, sizeof path, "%s/%s/%s", dir, sub, name);
	FILE *f = fopen(path, "w");
	cr_assert_not_null(f);
	fputs(text, f);
	cr_assert_eq(fclose(f), 0);
	snprintf(path, sizeof path, "%s/%s", dir, sub);
	return path;
}

TestSuite(summary_read, .init = make_dir, .fini = remove_dir, .timeout = 30);

/* a catalog's and a front's '#' lines: one search's (frontcsv.h checks them) */
#define TARGET_COST "# target: t: a test target on x in [0, 1] (4 cell centres)\n" \
                    "# cost: simple*1 + complex*4 after folding; error: max_abs in f16 precision on the target's samples\n"
#define HEAD "# brdfkit search published forms\n" TARGET_COST
#define FHEAD "# brdfkit search front (refitted)\n" TARGET_COST

/* Columns in another order than brdfkit writes them and one more: read by
 * name. Lines: 1-3 comments, 4 header, 5 on. Published: p (8, 0.25) and q
 * (6, 0.25, line 7: the cheaper on a tie); "q (refit)" (line 8, error 0.01)
 * and the LUT (line 9, error 0) are brdfkit's own and left out, or they
 * would be the best. Front: by hand, at cost <= 6 the least error is s2
 * (line 6, 5, 0.05): ratio 5; as accurate (<= 0.25) the cheapest is s1. */
static const char catalog[] = HEAD "error,extra,cost,name\n"
                              "0.25,x,8,p\n"
                              "0.3,x,9,\"r, with a comma\"\n"
                              "0.25,x,6,q\n"
                              "0.01,x,6,q (refit)\n"
                              "0,x,1,LUT 16x16 unorm8\n";
static const char front_csv[] = FHEAD "name,cost,error\n"
                                "s1,2,0.2\n"
                                "s2,5,0.05\n"
                                "s3,9,0.001\n";

Test(summary_read, a_search_by_column_name)
{
	put("t", "catalog.csv", catalog);
	bk_summary_row r;
	cr_assert_eq(bk_summary_read(put("t", "front.csv", front_csv), &r, err, sizeof err), 0, "%s", err);
	cr_expect_str_eq(r.target, "t");
	cr_expect_str_eq(r.objective, "max_abs in f16 precision");
	cr_expect_str_eq(r.cost_model, "simple*1 + complex*4");
	cr_expect_str_eq(r.pub.name, "q");
	cr_expect_eq(r.pub.line, 7);
	cr_expect_eq(r.npub, 3, "p, r and q; not the refit, not the LUT");
	cr_expect_str_eq(r.at_cost.name, "s2");
	cr_expect_eq(r.at_cost.line, 6);
	cr_expect_float_eq(bk_summary_ratio(&r), 5.0, 1e-12);
	cr_expect_str_eq(r.match.name, "s1");
	cr_expect_eq(r.nbeaten, 3, "p (8), r (9) and q (6) each by s2 (5, 0.05)");
	cr_expect(strstr(r.front_file, "/t/front.csv") != NULL);
	cr_expect(strstr(r.pub_file, "/t/catalog.csv") != NULL);
}

/* The certificate on the first screen: front.csv's "# certificate:" line
 * read for its size; "none" is 0, no line is -1 (a front written before
 * certificates), and a line that does not state a size is not read as one. */
Test(summary_read, the_certificate_from_front_csv)
{
	static const struct {
		const char *line;
		int complete;
	} cases[] = {
		{"# certificate: every unique form of the grammar up to 7 nodes and cost <= 15 was fitted\n", 7},
		{"# certificate: none: the enumeration completed no size (grammar: ...)\n", 0},
		{"", -1},
		{"# certificate: every unique form of the grammar up to many nodes\n", 0},
		{"# certificate: every unique form of the grammar up to 99 nodes\n", 0}, /* past BK_EXPR_MAX */
	};
	put("t", "catalog.csv", catalog);
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		char text[1024];
		snprintf(text, sizeof text, FHEAD "%sname,cost,error\ns1,2,0.2\n", cases[i].line);
		bk_summary_row r;
		cr_assert_eq(bk_summary_read(put("t", "front.csv", text), &r, err, sizeof err), 0, "%s", err);
		cr_expect_eq(r.complete, cases[i].complete, "case %zu: %d", i, r.complete);
	}
}

Test(summary_read, a_target_with_no_search_reads_compare_csv)
{
	const char *d = put("spec", "compare.csv", "name,kind,cost,max_abs,rmse\n"
	                                           "a,published,17,3,1\n"
	                                           "a (refit),refit,17,2,1\n"
	                                           "lut,lut,5,,\n"
	                                           "b,published,24,3,1\n");
	bk_summary_row r;
	cr_assert_eq(bk_summary_read(d, &r, err, sizeof err), 0, "%s", err);
	cr_expect(!r.has_search);
	cr_expect_str_eq(r.pub.name, "a", "a and b tie on 3; a is cheaper");
	cr_expect_eq(r.npub, 2, "the refit and the LUT (its empty error unread) are not published");
	cr_expect_eq(r.front_file[0], '\0');
}

/* err holds "PATH:LINE: tail" for the file name under dir */
static void expect_error(const char *sub, const char *file, int line, const char *tail)
{
	bk_summary_row r;
	char d[256], want[512];
	snprintf(d, sizeof d, "%s/%s", dir, sub);
	cr_assert_eq(bk_summary_read(d, &r, err, sizeof err), -1, "read %s", sub);
	if (line)
		snprintf(want, sizeof want, "%s/%s/%s:%d: %s", dir, sub, file, line, tail);
	else
		snprintf(want, sizeof want, "%s/%s/%s: %s", dir, sub, file, tail);
	cr_expect_str_eq(err, want);
}

Test(summary_read, bad_fields_name_file_and_line)
{
	put("ok", "catalog.csv", catalog);
	put("ok", "front.csv", front_csv);
	bk_summary_row r;
	cr_assert_eq(bk_summary_read(put("ok", "front.csv", front_csv), &r, err, sizeof err), 0, "control: %s", err);

	put("empty", "catalog.csv", catalog);
	put("empty", "front.csv", FHEAD "name,cost,error\ns1,2,0.2\ns2,5,\n");
	expect_error("empty", "front.csv", 6, "error: expected a finite number >= 0, got ''");

	put("nan", "catalog.csv", HEAD "name,cost,error\np,8,nan\n");
	put("nan", "front.csv", front_csv);
	expect_error("nan", "catalog.csv", 5, "error: expected a finite number >= 0, got 'nan'");

	put("neg", "catalog.csv", HEAD "name,cost,error\np,-1,0.2\n");
	put("neg", "front.csv", front_csv);
	expect_error("neg", "catalog.csv", 5, "cost: expected a finite number >= 0, got '-1'");

	put("short", "catalog.csv", catalog);
	put("short", "front.csv", FHEAD "name,cost,error\ns1,2\n");
	expect_error("short", "front.csv", 5, "2 fields, fewer than the header's");

	put("nocol", "catalog.csv", HEAD "name,cost,err\np,8,0.2\n");
	put("nocol", "front.csv", front_csv);
	expect_error("nocol", "catalog.csv", 4, "no column 'error'");

	/* a quoted field over two lines: the error names the line the row starts on */
	put("multi", "catalog.csv", catalog);
	put("multi", "front.csv", FHEAD "name,cost,error\n\"s\n1\",2,x\n");
	expect_error("multi", "front.csv", 5, "error: expected a finite number >= 0, got 'x'");
}

Test(summary_read, files_that_say_nothing)
{
	put("own", "catalog.csv", HEAD "name,cost,error\np (refit),8,0.2\nstart 1,3,0.1\n");
	put("own", "front.csv", front_csv);
	expect_error("own", "catalog.csv", 0, "no published form (every row is a refit, a typed start or a LUT)");

	put("nofront", "catalog.csv", catalog);
	put("nofront", "front.csv", FHEAD "name,cost,error\n");
	expect_error("nofront", "front.csv", 0, "no member (an empty front)");

	put("noobj", "catalog.csv", "name,cost,error\np,8,0.2\n");
	put("noobj", "front.csv", front_csv);
	expect_error("noobj", "catalog.csv", 0,
	             "no '# ... error: OBJECTIVE in P precision' line (not a catalog.csv of brdfkit search)");

	put("zero", "catalog.csv", "");
	put("zero", "front.csv", front_csv);
	expect_error("zero", "catalog.csv", 0, "empty (no header)");

	bk_summary_row r;
	char d[256];
	snprintf(d, sizeof d, "%s/none", dir);
	mkdir(d, 0700);
	cr_expect_eq(bk_summary_read(d, &r, err, sizeof err), -1);
	cr_expect(strstr(err, "none: neither front.csv (brdfkit search) nor compare.csv (brdfkit compare)") != NULL, "%s",
	          err);
}

/* front.csv and catalog.csv of one search: the same target, objective and
 * precision stated (H2), each mismatch named */
Test(summary_read, front_and_catalog_of_one_search)
{
	static const struct {
		const char *sub, *front, *tail;
	} cases[] = {
		{"tgt", "# brdfkit search front\n# target: u: another on x in [0, 1] (4 cell centres)\n"
		        "# cost: x after y; error: max_abs in f16 precision on the samples\n",
		 "a front of target u, its catalog.csv's target is t"},
		{"dom", "# brdfkit search front\n# target: t: a test target on x in [0, 2] (4 cell centres)\n"
		        "# cost: x after y; error: max_abs in f16 precision on the samples\n",
		 "a front of target t on other samples, domain or options: it says '...in [0, 2] (4 cell centres)', "
		 "its catalog.csv's '...in [0, 1] (4 cell centres)'"},
		{"obj", "# brdfkit search front\n# target: t: a test target on x in [0, 1] (4 cell centres)\n"
		        "# cost: x after y; error: rmse in f16 precision on the samples\n",
		 "a front of objective rmse, its catalog.csv's objective is max_abs"},
		{"prec", "# brdfkit search front\n# target: t: a test target on x in [0, 1] (4 cell centres)\n"
		         "# cost: x after y; error: max_abs in f64 precision on the samples\n",
		 "a front in f64 precision, not f16"},
		{"cat", HEAD, "a catalog of brdfkit search (its published forms), not a front"},
		{"none", "# a front\n", "no '# brdfkit ... search front' line: not a front.csv of brdfkit search"},
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		char text[1024];
		put(cases[i].sub, "catalog.csv", catalog);
		snprintf(text, sizeof text, "%sname,cost,error\ns1,2,0.2\n", cases[i].front);
		put(cases[i].sub, "front.csv", text);
		expect_error(cases[i].sub, "front.csv", 0, cases[i].tail);
	}
}

/* ---- the table: every value escaped --------------------------------------------------- */

Test(summary_read, the_table_escapes_what_it_read)
{
	put("x", "catalog.csv", HEAD "name,cost,error\n\"<script>alert(1)</script> & \"\"q\"\"\",8,0.2\n");
	bk_summary_row r;
	cr_assert_eq(bk_summary_read(put("x", "front.csv", FHEAD "name,cost,error\n<b>,2,0.1\n"), &r, err, sizeof err), 0,
	             "%s", err);
	char *buf = NULL;
	size_t len = 0;
	FILE *f = open_memstream(&buf, &len);
	const char *href[] = {"a\"b/"};
	bk_summary_table(f, &r, 1, href);
	fclose(f);
	cr_expect(strstr(buf, "&lt;script&gt;alert(1)&lt;/script&gt; &amp; &quot;q&quot;") != NULL, "%s", buf);
	cr_expect(strstr(buf, "&lt;b&gt;") != NULL);
	cr_expect(strstr(buf, "href=\"a%22b/front.csv\"") != NULL, "a link percent-encoded (out.h)");
	cr_expect(strstr(buf, "<script") == NULL && strstr(buf, "<b>") == NULL && strstr(buf, "a\"b") == NULL);
	/* the numbers: ratio 0.2/0.1 = 2, the line of each name */
	cr_expect(strstr(buf, "<td>2</td>") != NULL);
	cr_expect(strstr(buf, "title=\"front.csv, line 5\"") != NULL);
	cr_expect(strstr(buf, "<td>1 of 1</td>") != NULL);
	free(buf);
}

/* ---- the findings (issue 40): one sentence from the numbers --------------------------- */

/* The planted rule points above: A (8, 0.2) against f3 (8, 0.1) at its cost,
 * 3 of 3 beaten; the sentence says so, with the ratio 2. The control moves
 * the front's members above A's error: the sentence turns to "no searched
 * form ... beats", names what matching costs and how many are still beaten. */
Test(summary_findings, a_sentence_from_the_numbers)
{
	bk_summary_row r;
	cr_assert_eq(bk_summary_compute(pub, 3, front, 5, &r), 0);
	snprintf(r.target, sizeof r.target, "t");
	snprintf(r.objective, sizeof r.objective, "max_abs in f64 precision");
	char s[512];
	bk_summary_finding(&r, s, sizeof s);
	cr_expect_str_eq(s, "At A's cost 8, f3 (cost 8) has max_abs 0.1, 2x less than A's 0.2; 3 of 3 published forms "
	                    "are beaten at their own cost.");
	/* control: the front at cost <= 8 no better than 0.3; f5 (dearer) matches */
	bk_summary_pt worse[] = {PT(11, "g1", 4, 0.25), PT(12, "g2", 8, 0.3), PT(13, "g3", 12, 0.15)};
	cr_assert_eq(bk_summary_compute(pub, 3, worse, 3, &r), 0);
	bk_summary_finding(&r, s, sizeof s);
	cr_expect_str_eq(s, "No searched form at cost 8 or less beats A (max_abs 0.2): the best there, g1, has 0.25; as "
	                    "accurate takes cost 12 (g3), yet 1 of 3 published forms is beaten at its own cost.",
	                 "B (4, 0.3) is beaten by g1 (4, 0.25): %s", s);
	/* and no search at all */
	cr_assert_eq(bk_summary_compute(pub, 3, NULL, 0, &r), 0);
	bk_summary_finding(&r, s, sizeof s);
	cr_expect_str_eq(s, "No search on t; the best published form is A (cost 8, max_abs 0.2).");
}

/* snprintf's contract: the whole length returned, the text cut and ended. */
Test(summary_findings, cut_to_the_buffer)
{
	bk_summary_row r;
	cr_assert_eq(bk_summary_compute(pub, 3, front, 5, &r), 0);
	snprintf(r.target, sizeof r.target, "t");
	snprintf(r.objective, sizeof r.objective, "rmse in f16 precision");
	char whole[512], cut[20];
	size_t n = bk_summary_finding(&r, whole, sizeof whole);
	cr_expect_eq(n, strlen(whole));
	cr_expect_eq(bk_summary_finding(&r, cut, sizeof cut), n);
	cr_expect_eq(strlen(cut), sizeof cut - 1);
	cr_expect(!strncmp(cut, whole, sizeof cut - 1));
	cr_expect(strstr(whole, "rmse 0.1"), "the objective's error name: %s", whole);
}

/* The formula of the at-cost member (s2, line 6) from the front's form and
 * parameters columns, found by line: its MathML with p0 = 0.5 baked in; a
 * split sum gives both parts. Control: the same front without those
 * columns (the fixtures above) shows no formula. */
Test(summary_read, the_formula_of_the_member_at_cost)
{
	put("t", "catalog.csv", catalog);
	bk_summary_row r;
	cr_assert_eq(bk_summary_read(put("t", "front.csv", FHEAD "name,form,form_b,parameters,cost,error\n"
	                                                          "s1,NoV,,,2,0.2\n"
	                                                          "s2,r + p0,,p0=0.5,5,0.05\n"),
	                             &r, err, sizeof err),
	             0, "%s", err);
	cr_expect_str_eq(r.at_cost.name, "s2");
	cr_expect_str_eq(r.formula, "<math><mrow><mrow><mi>r</mi><mo>+</mo><mn>0.5</mn></mrow></mrow></math>");
	cr_assert_eq(bk_summary_read(put("t", "front.csv", FHEAD "name,form,form_b,parameters,cost,error\n"
	                                                          "s2,r + p0,NoV*p1,p0=0.5;p1=2,5,0.05\n"),
	                             &r, err, sizeof err),
	             0, "%s", err);
	cr_expect(!strncmp(r.formula, "A = <math>", 10) && strstr(r.formula, ", B = <math>") &&
	          strstr(r.formula, "<mn>2</mn>"), "%s", r.formula);
	cr_assert_eq(bk_summary_read(put("t", "front.csv", front_csv), &r, err, sizeof err), 0, "%s", err);
	cr_expect_str_eq(r.formula, "", "no form column: no formula");
}
