/*
 * test_page.c — what brdfkit report takes in (analysis/page.c): files read
 * with a bound whatever they are (a regular file over the cap is refused
 * from its size, /dev/zero and a FIFO after cap + 1 bytes), and the section
 * check: every section make results writes passes it, and each way to run
 * code in a page is refused with its line.
 */
#include "page.h"
#include "out.h"
#include "fixture_tmpdir.h"

#include <criterion/criterion.h>
#include <fcntl.h>
#include <glob.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

static char err[512];

/* ---- reading with a bound -------------------------------------------------------- */

static char dir[64];

static void make_dir(void) { fx_tmpdir_make(dir, sizeof dir, "page"); }

static void remove_dir(void) { fx_tmpdir_remove(dir); }

static const char *file_of(const char *name, size_t bytes)
{
	static char path[128];
	snprintf(path, sizeof path, "%s/%s", dir, name);
	FILE *f = fopen(path, "w");
	cr_assert_not_null(f);
	for (size_t i = 0; i < bytes; i++)
		fputc('a' + (int)(i % 26), f);
	cr_assert_eq(fclose(f), 0);
	return path;
}

TestSuite(bounded, .init = make_dir, .fini = remove_dir, .timeout = 30);

Test(bounded, a_regular_file_up_to_the_cap)
{
	size_t len = 0;
	char *t = bk_read_bounded(file_of("ok", 1000), 1000, &len, err, sizeof err);
	cr_assert_not_null(t, "%s", err);
	cr_expect_eq(len, 1000u);
	cr_expect_eq(t[0], 'a');
	cr_expect_eq(t[999], 'a' + 999 % 26);
	cr_expect_eq(t[1000], '\0');
	free(t);
	cr_expect_null(bk_read_bounded(file_of("big", 1001), 1000, &len, err, sizeof err));
	cr_expect_str_eq(err, "is 1001 bytes, more than 1000");
	t = bk_read_bounded(file_of("empty", 0), 1000, &len, err, sizeof err);
	cr_assert_not_null(t, "%s", err);
	cr_expect_eq(len, 0u);
	free(t);
}

Test(bounded, devices_fifos_and_what_is_not_a_file)
{
	size_t len;
	cr_expect_null(bk_read_bounded("/dev/zero", 4096, &len, err, sizeof err));
	cr_expect_str_eq(err, "is longer than 4096 bytes");
	char path[128];
	snprintf(path, sizeof path, "%s/missing", dir);
	cr_expect_null(bk_read_bounded(path, 4096, &len, err, sizeof err));
	cr_expect_str_eq(err, "cannot be read: no such file or directory");
	cr_expect_null(bk_read_bounded(dir, 4096, &len, err, sizeof err));
	cr_expect_str_eq(err, "is a directory");
	/* a FIFO fed 5000 bytes: read to its end under a cap of 8000, refused under 1000 */
	snprintf(path, sizeof path, "%s/fifo", dir);
	cr_assert_eq(mkfifo(path, 0600), 0);
	for (int pass = 0; pass < 2; pass++) {
		pid_t pid = fork();
		cr_assert_geq(pid, 0);
		if (pid == 0) {
			signal(SIGPIPE, SIG_IGN);
			int fd = open(path, O_WRONLY);
			char buf[5000];
			memset(buf, 'x', sizeof buf);
			_exit(fd < 0 || write(fd, buf, sizeof buf) < 0);
		}
		char *t = bk_read_bounded(path, pass ? 1000 : 8000, &len, err, sizeof err);
		if (pass) {
			cr_expect_null(t);
			cr_expect_str_eq(err, "is longer than 1000 bytes");
		} else {
			cr_expect(t && len == 5000, "%s", t ? "wrong length" : err);
		}
		free(t);
		int status;
		waitpid(pid, &status, 0);
	}
}

/* ---- the section check ------------------------------------------------------------- */

static int check(const char *text)
{
	char id[64];
	err[0] = '\0';
	return bk_section_check(text, strlen(text), id, sizeof id, err, sizeof err);
}

static void refused(const char *text, const char *message)
{
	cr_expect_eq(check(text), -1, "accepted: %s", text);
	cr_expect_str_eq(err, message, "for %s", text);
}

#define OPEN "<section id=\"s\">\n<h2>t</h2>\n"
#define CLOSE "</section>\n"

Test(section, every_section_make_results_writes_passes)
{
	glob_t g;
	cr_assert_eq(glob("results/*/section.html", 0, NULL, &g), 0, "run from the repository's root");
	cr_assert_eq(glob("results/*/*/section.html", GLOB_APPEND, NULL, &g), 0);
	cr_assert_geq(g.gl_pathc, 14u, "the committed sections");
	for (size_t i = 0; i < g.gl_pathc; i++) {
		size_t len;
		char *t = bk_read_bounded(g.gl_pathv[i], BK_PAGE_SECTION_MAX, &len, err, sizeof err), id[64];
		cr_assert_not_null(t, "%s: %s", g.gl_pathv[i], err);
		cr_expect_eq(bk_section_check(t, len, id, sizeof id, err, sizeof err), 0, "%s: %s", g.gl_pathv[i], err);
		free(t);
	}
	globfree(&g);
	char id[64];
	const char *s = OPEN "<p>a &lt;b&gt; &amp; c</p><a href=\"https://example.org/x?a=1&amp;b=2#c\">x</a>"
	                     "<img src=\"d/e:f.png\" alt=\"\">" CLOSE;
	cr_expect_eq(bk_section_check(s, strlen(s), id, sizeof id, err, sizeof err), 0, "%s", err);
	cr_expect_str_eq(id, "s");
}

Test(section, the_marker)
{
	refused("<p>hello</p>\n", "line 1: does not open with <section id=\"...\"> (not a section brdfkit wrote)");
	refused("<section id=\"a b\">" CLOSE, "line 1: the section's id is not made of letters, digits, '-' and '_'");
	refused("<section id=\"x\"><p>cut", "line 1: does not end with </section> (not a whole section)");
	refused(" <section id=\"s\">" CLOSE, "line 1: does not open with <section id=\"...\"> (not a section brdfkit wrote)");
}

Test(section, nothing_that_runs)
{
	refused(OPEN "<script>alert(1)</script>" CLOSE, "line 3: <script>: not an element brdfkit writes");
	refused(OPEN "<SCRIPT>alert(1)</SCRIPT>" CLOSE, "line 3: <SCRIPT>: not an element brdfkit writes");
	refused(OPEN "<svg><script>alert(1)</script></svg>" CLOSE, "line 3: <script>: not an element brdfkit writes");
	refused(OPEN "<iframe src=\"x\"></iframe>" CLOSE, "line 3: <iframe>: not an element brdfkit writes");
	refused(OPEN "<img src=\"x\" onerror=\"alert(1)\">" CLOSE, "line 3: onerror=: not an attribute brdfkit writes");
	refused(OPEN "<p style=\"x\">" CLOSE, "line 3: style=: not an attribute brdfkit writes");
	refused(OPEN "<a xlink:href=\"x\">" CLOSE, "line 3: xlink:href=: not an attribute brdfkit writes");
	refused(OPEN "<a href=\"javascript:alert(1)\">x</a>" CLOSE,
	        "line 3: a link with the scheme 'javascript:' (only relative, http: and https: links)");
	refused(OPEN "<a href=\"JaVaScRiPt:alert(1)\">x</a>" CLOSE,
	        "line 3: a link with the scheme 'JaVaScRiPt:' (only relative, http: and https: links)");
	refused(OPEN "<img src=\"data:text/html,x\">" CLOSE,
	        "line 3: a link with the scheme 'data:' (only relative, http: and https: links)");
	refused(OPEN "<a href=\"java\tscript:alert(1)\">x</a>" CLOSE, "line 3: a control character in a link");
	refused(OPEN "<a href=\"javascript&#58;alert(1)\">x</a>" CLOSE,
	        "line 3: a character reference in a link (brdfkit writes only &amp; &lt; &gt; &quot;)");
	refused(OPEN "<a href=x>x</a>" CLOSE, "line 3: href: a value not written as =\"...\"");
	refused(OPEN "<a href=\"x\"onclick=\"y\">x</a>" CLOSE, "line 3: 'o' inside a tag");
	refused(OPEN "<style>p{background:url(javascript:x)}</style>" CLOSE,
	        "line 3: <style>: '(' (a section's style is selectors and properties only)");
	refused(OPEN "<style>@import 'x';</style>" CLOSE,
	        "line 3: <style>: '@' (a section's style is selectors and properties only)");
	refused(OPEN "<!-- x -->" CLOSE, "line 3: a '<' that opens no tag (brdfkit writes text with '<' escaped)");
	refused(OPEN "<p>1 < 2</p>" CLOSE, "line 3: a '<' that opens no tag (brdfkit writes text with '<' escaped)");
	/* an unescaped link prefix (L3): the quote ends the value, and what follows is refused */
	refused(OPEN "<a href=\"x'\"<b>/stability.csv\">t</a>" CLOSE, "line 3: '<' inside a tag");
	refused(OPEN "<a href=\"x\" title=\"</section><script>\">t</a>" CLOSE,
	        "line 3: title=: not an attribute brdfkit writes");
	refused(OPEN "<a href=\"x\" alt=\"</section><script>\">t</a>" CLOSE,
	        "line 3: alt: a raw '<' in an attribute's value");
	/* a network path is another host whichever slashes spell it (L3) */
	static const char *const net[] = {"//evil.example/x", "\\\\evil.example\\x", "/\\evil", "\\/evil",
	                                  " //evil", "&#47;/evil"};
	for (size_t i = 0; i < sizeof net / sizeof net[0]; i++) {
		char text[256];
		snprintf(text, sizeof text, OPEN "<a href=\"%s\">x</a>" CLOSE, net[i]);
		refused(text, strncmp(net[i], "&#", 2) ? "line 3: a network-path link ('//host' or '\\\\host': another host, "
		                                         "not a relative link)"
		                                       : "line 3: a character reference in a link (brdfkit writes only "
		                                         "&amp; &lt; &gt; &quot;)");
	}
}

/* the controls of the network paths: a path from the root, or one step down */
Test(section, relative_links_pass)
{
	static const char text[] = OPEN "<a href=\"/abs/x\">a</a><a href=\"./a%23b/front.csv\">b</a>"
	                                "<a href=\"\\x\">c</a><a href=\"http://h/x\">d</a>" CLOSE;
	cr_expect_eq(check(text), 0, "%s", err);
}

/* The one link writer (out.h): RFC 3986 path segments, then '&' escaped. */
Test(section, links_percent_encoded)
{
	static const struct {
		const char *prefix, *path, *want;
	} cases[] = {
		{"./a#b/", "front.csv", "./a%23b/front.csv"},
		{"./c%41d/", NULL, "./c%2541d/"},
		{"e?f/", "x y.png", "e%3Ff/x%20y.png"},
		{NULL, "caf\xc3\xa9/x", "caf%C3%A9/x"},
		{"x'\"<b>&/", "a:b", "x'%22%3Cb%3E&amp;/a%3Ab"},
		{"../r_1-2.~/", "!$()*+,;=@", "../r_1-2.~/!$()*+,;=@"},
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		char *s = bk_html_link_text(cases[i].prefix, cases[i].path);
		cr_assert_not_null(s);
		cr_expect_str_eq(s, cases[i].want, "case %zu", i);
		free(s);
	}
}

/* --link-prefix: a relative path, nothing else (H4) */
Test(section, link_prefix_rule)
{
	static const char *const bad[] = {"javascript:alert(1)//", "data:text/html;base64,PHN#", "http://x/", "//evil/",
	                                  "\\\\evil/", "/\\evil/", "a\\b/", "a\nb/"};
	static const char *const good[] = {"x/", "search/vf2d/", "../up/", "/abs/", "a b#c?/", "x/y:z/"};
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
		cr_expect_eq(bk_link_prefix_check(bad[i], err, sizeof err), -1, "bad %zu accepted", i);
	for (size_t i = 0; i < sizeof good / sizeof good[0]; i++)
		cr_expect_eq(bk_link_prefix_check(good[i], err, sizeof err), 0, "good %zu: %s", i, err);
	bk_link_prefix_check("javascript:x/", err, sizeof err);
	cr_expect_str_eq(err, "--link-prefix 'javascript:x/': a URL scheme: give a path relative to the page (no "
	                      "javascript:, data:, http: ...)");
}

Test(section, html_escaped)
{
	char *s = bk_html_escaped("x'\"<b>&/");
	cr_assert_not_null(s);
	cr_expect_str_eq(s, "x'&quot;&lt;b&gt;&amp;/");
	free(s);
}
