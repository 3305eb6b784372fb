/*
 * test_page_fold.c — what brdfkit report does to a section on its way into
 * the page (analysis/page.c): a table of more than the given rows is folded
 * into <details> with its header cells as the one-line summary, a short one
 * and one already folded are not, the rest is copied byte for byte; and the
 * links from the page's folder to a summary target are relative.
 */
#include "page.h"

#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static char *fold(const char *text, int rows, int *folded)
{
	char *buf = NULL;
	size_t len = 0;
	FILE *f = open_memstream(&buf, &len);
	cr_assert_not_null(f);
	*folded = bk_page_fold(f, text, strlen(text), rows);
	cr_assert_eq(fclose(f), 0);
	return buf;
}

/* n data rows under a header of two cells */
static void table_of(char *buf, size_t len, int n)
{
	size_t k = (size_t)snprintf(buf, len, "<table>\n<tr><th>name</th><th>max |err| &amp; <code>x</code></th></tr>\n");
	for (int i = 0; i < n; i++)
		k += (size_t)snprintf(buf + k, len - k, "<tr><td>r%d</td><td>%d</td></tr>\n", i, i);
	snprintf(buf + k, len - k, "</table>\n");
}

Test(fold, long_tables_only)
{
	char t6[2048], t7[2048], text[8192];
	table_of(t6, sizeof t6, 5); /* 6 rows with its header: not more than 6 */
	table_of(t7, sizeof t7, 6); /* 7 rows */
	snprintf(text, sizeof text, "<section id=\"s\">\n<p>a</p>\n%s<p>b</p>\n%s</section>\n", t6, t7);
	int n;
	char *out = fold(text, 6, &n);
	cr_expect_eq(n, 1);
	char want[8192];
	snprintf(want, sizeof want,
	         "<section id=\"s\">\n<p>a</p>\n%s<p>b</p>\n<details class=\"fold\"><summary>7 rows: name, max |err| "
	         "&amp; x</summary>\n%.*s</details>\n</section>\n",
	         t6, (int)strlen(t7) - 1, t7); /* </details> right after </table>, before its newline */
	cr_expect_str_eq(out, want);
	free(out);
	/* control: with 5 as the bound the first folds too */
	out = fold(text, 5, &n);
	cr_expect_eq(n, 2);
	cr_expect(strstr(out, "<summary>6 rows: name,") != NULL);
	free(out);
}

Test(fold, already_folded_and_nested_tables)
{
	char t[2048], text[8192];
	table_of(t, sizeof t, 9);
	snprintf(text, sizeof text, "<section id=\"s\"><details><summary>mine</summary>%s</details></section>", t);
	int n;
	char *out = fold(text, 6, &n);
	cr_expect_eq(n, 0);
	cr_expect_str_eq(out, text);
	free(out);
	/* a table inside a cell counts its own rows, not the outer one's */
	snprintf(text, sizeof text, "<section id=\"s\"><table><tr><td>%s</td></tr></table></section>", t);
	out = fold(text, 6, &n);
	cr_expect_eq(n, 0, "the outer table has one row; the inner one sits inside it");
	free(out);
}

Test(fold, a_long_header_is_cut_after_a_whole_cell)
{
	char text[16384];
	size_t k = (size_t)snprintf(text, sizeof text, "<section id=\"s\"><table><tr>");
	for (int i = 0; i < 40; i++)
		k += (size_t)snprintf(text + k, sizeof text - k, "<th>column &amp; %02d</th>", i);
	k += (size_t)snprintf(text + k, sizeof text - k, "</tr>");
	for (int i = 0; i < 8; i++)
		k += (size_t)snprintf(text + k, sizeof text - k, "<tr><td>%d</td></tr>", i);
	snprintf(text + k, sizeof text - k, "</table></section>");
	int n;
	char *out = fold(text, 6, &n);
	cr_expect_eq(n, 1);
	char *s = strstr(out, "<summary>"), *e = strstr(out, "</summary>");
	cr_assert(s && e);
	s += 9;
	/* each cell "column &amp; NN" is 15 characters, 17 with ", ": 9 cells are
	 * 151; the tenth would end at 168, past 160, so it stops after the ninth */
	cr_expect_eq(e - s, (long)strlen("9 rows: ") + 9 * 15 + 8 * 2 + (long)strlen(", \xe2\x80\xa6"), "%.*s", (int)(e - s),
	             s);
	cr_expect(strstr(out, "column &amp; 08, \xe2\x80\xa6</summary>") != NULL);
	free(out);
}

/* A URL scheme: a ':' before the first '/', '?' or '#' (RFC 3986, 4.2). */
static int has_scheme(const char *href)
{
	size_t n = strcspn(href, "/?#");
	return memchr(href, ':', n) != NULL;
}

Test(rel_dir, relative_from_the_page_folder)
{
	char d[64], p[256], q[256], rel[512], err[256];
	snprintf(d, sizeof d, "/tmp/bk_rel_XXXXXX");
	cr_assert_not_null(mkdtemp(d));
	snprintf(p, sizeof p, "%s/site", d);
	mkdir(p, 0700);
	snprintf(p, sizeof p, "%s/site/search", d);
	mkdir(p, 0700);
	snprintf(p, sizeof p, "%s/data", d);
	mkdir(p, 0700);
	snprintf(p, sizeof p, "%s/site/index.html", d); /* need not exist */
	snprintf(q, sizeof q, "%s/site/search/", d);
	cr_assert_eq(bk_page_rel_dir(p, q, rel, sizeof rel, err, sizeof err), 0, "%s", err);
	cr_expect_str_eq(rel, "./search/");
	snprintf(q, sizeof q, "%s/data", d);
	cr_assert_eq(bk_page_rel_dir(p, q, rel, sizeof rel, err, sizeof err), 0, "%s", err);
	cr_expect_str_eq(rel, "../data/");
	snprintf(q, sizeof q, "%s/site/search/..", d);
	cr_assert_eq(bk_page_rel_dir(p, q, rel, sizeof rel, err, sizeof err), 0, "%s", err);
	cr_expect_str_eq(rel, "./");
	/* a folder whose name reads as a URL scheme stays a path in an href */
	snprintf(q, sizeof q, "%s/site/javascript:alert(1)", d);
	mkdir(q, 0700);
	cr_assert_eq(bk_page_rel_dir(p, q, rel, sizeof rel, err, sizeof err), 0, "%s", err);
	cr_expect_str_eq(rel, "./javascript:alert(1)/");
	cr_expect(!has_scheme(rel), "%s", rel);
	cr_expect(has_scheme("javascript:alert(1)/"), "control: the bare name is a scheme"); /* negative control */
	snprintf(q, sizeof q, "%s/nowhere", d);
	cr_expect_eq(bk_page_rel_dir(p, q, rel, sizeof rel, err, sizeof err), -1);
	cr_expect(strstr(err, "nowhere: cannot be resolved: ") != NULL, "%s", err);
	char cmd[128];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", d);
	cr_expect_eq(system(cmd), 0);
}

/* The elements the captions and folds add pass the section check; one
 * brdfkit does not write, in the same place, does not (the control). */
Test(fold, figures_and_folds_pass_the_section_check)
{
	static const char ok[] = "<section id=\"s\">\n<figure><img src=\"a.png\" alt=\"x\">\n<figcaption>Error against "
	                         "cost; data: <a href=\"a.csv\">a.csv</a></figcaption></figure>\n<details><summary>2 rows"
	                         "</summary><table><tr><td>1</td></tr></table></details>\n</section>\n";
	char id[64], err[256], bad[sizeof ok + 16];
	cr_expect_eq(bk_section_check(ok, strlen(ok), id, sizeof id, err, sizeof err), 0, "%s", err);
	snprintf(bad, sizeof bad, "%s", ok);
	memcpy(strstr(bad, "<details>"), "<dialog> ", 9);
	cr_expect_eq(bk_section_check(bad, strlen(bad), id, sizeof id, err, sizeof err), -1);
	cr_expect(strstr(err, "line 4: <dialog>: not an element brdfkit writes") != NULL, "%s", err);
}
