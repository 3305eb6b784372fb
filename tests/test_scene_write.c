/*
 * test_scene_write.c — nothing a scene file or the command line holds runs
 * as code (issue 21, section 4). First the one comment rule, bk_comment_text,
 * on hand-written cases; then a seeded list of hostile names (comment ends
 * and starts, line breaks, CR, a backslash at the end, C's "?\?/", HTML that
 * closes a tag and opens <script>, quotes, '&', Unicode, control
 * characters) through every writer of brdfkit scene at once, judged by the
 * tools that read the files, never by brdfkit:
 *   C     gcc -std=c11 -Wall -Wextra -Werror compiles it and nm finds the
 *         same symbols as with plain names; the preprocessor's output (the
 *         comments gone, lines spliced, trigraphs read) is, once whitespace
 *         is dropped, that of the same files with plain names;
 *   GLSL, HLSL  glslangValidator compiles them, and its preprocessor's
 *         output is that of the plain files;
 *   CSV   build/csvget (libcsv) reads every row and column where they were;
 *   HTML  page.h's section check accepts the section, and xmllint --html
 *         parses a page of it into as many elements and attributes as the
 *         plain one, with no <script>, the names as text.
 * No fitting runs: the choices are made up, only the strings matter.
 */
#include "brdf.h"
#include "ir.h"
#include "page.h"
#include "scene_write.h"

#include <criterion/criterion.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* ---- bk_comment_text ------------------------------------------------------ */

static const char *commented(const char *src, const char *newline)
{
	static char buf[256];
	size_t n = bk_comment_text(buf, sizeof buf, src, newline);
	cr_assert_lt(n, sizeof buf);
	cr_assert_eq(strlen(buf), n, "the length returned is the text's");
	return buf;
}

Test(comment, ends_and_starts_are_broken)
{
	cr_expect_str_eq(commented("a */ b", NULL), "a * / b");
	cr_expect_str_eq(commented("a /* b", NULL), "a / * b");
	cr_expect_str_eq(commented("**/", NULL), "** /");
	cr_expect_str_eq(commented("/*/", NULL), "/ * /");
	cr_expect_str_eq(commented("x */ int injected = 1; /* y", NULL), "x * / int injected = 1; / * y");
	cr_expect_str_eq(commented("a / b * c // d", NULL), "a / b * c // d"); /* nothing else changes */
}

Test(comment, line_breaks_and_control_characters)
{
	cr_expect_str_eq(commented("x\nfloat inj(){return 1.0;}\n//", NULL), "x float inj(){return 1.0;} //");
	cr_expect_str_eq(commented("x\ny", "\n *   "), "x\n *   y");
	cr_expect_str_eq(commented("cr\rtab\tesc\x1b" "del\x7f" "bell\x07", NULL), "cr tab esc del bell ");
	cr_expect_str_eq(commented("\xc3\xa9 \xe6\x97\xa5", NULL), "\xc3\xa9 \xe6\x97\xa5"); /* UTF-8 stays */
}

Test(comment, no_line_ends_in_a_continuation)
{
	cr_expect_str_eq(commented("end\\", NULL), "end\\.");
	cr_expect_str_eq(commented("end\\  ", NULL), "end\\.  ");  /* gcc splices a backslash-space-newline too */
	cr_expect_str_eq(commented("end\\\n", NULL), "end\\. ");
	cr_expect_str_eq(commented("a\\ \nb", "\n *   "), "a\\. \n *   b"); /* before a line break too */
	cr_expect_str_eq(commented("end?\?/", NULL), "end?\?/.");     /* the trigraph for a backslash (C11) */
	cr_expect_str_eq(commented("a\\b c?\?/d ?/", NULL), "a\\b c?\?/d ?/"); /* inside a line: harmless */
}

Test(comment, truncates_like_snprintf)
{
	char buf[5];
	cr_expect_eq(bk_comment_text(buf, sizeof buf, "a */ b", NULL), 7u); /* "a * / b" */
	cr_expect_str_eq(buf, "a * ");
	cr_expect_eq(bk_comment_text(NULL, 0, "x\ny", "\n// "), 6u);
}

/* ---- the fuzzed names ------------------------------------------------------- */

#define NDOC 300
#define NAME_CAP BK_SCENE_NAME_MAX

static unsigned long long rng_state;

static unsigned rnd(unsigned n) /* xorshift64*: seeded, so every run tries the same names */
{
	rng_state ^= rng_state >> 12;
	rng_state ^= rng_state << 25;
	rng_state ^= rng_state >> 27;
	return (unsigned)((rng_state * 2685821657736338717ull) >> 33) % n;
}

static const char *const pieces[] = {
	"*/", "/*", "\n", "\r", "\\", "?\?/", "</pre><script>alert(1)</script>", "\"", "'", "&", "&amp;", "<", ">",
	"\xc3\xa9", "\xe6\x97\xa5\xe6\x9c\xac", "\xf0\x9f\x98\x80", "\t", "\x1b[31m", "\x7f", "\x01", "//", "x", " ",
	"int injected_c = 1;", "float inj(){return 1.0;}", "#define D_ggx 0", "]]>", "<!--", "-->", ",", ";",
	"\" onmouseover=\"alert(1)", "javascript:", "\f", "\v", "%s%n", "\\\n"};

/* Up to NAME_CAP - 1 bytes of pieces, cut at a character's boundary (a JSON
 * string is UTF-8); every fourth ends in a backslash. */
static void fuzz_name(char *out)
{
	size_t n = 0;
	int k = 1 + (int)rnd(6);
	out[0] = '\0';
	for (int i = 0; i < k; i++) {
		const char *p = pieces[rnd(sizeof pieces / sizeof pieces[0])];
		if (n + strlen(p) >= NAME_CAP - 1)
			break;
		strcpy(out + n, p);
		n += strlen(p);
	}
	if (!rnd(4) && n + 1 < NAME_CAP - 1)
		strcpy(out + n, "\\");
	if (!out[0])
		strcpy(out, "*/");
}

/* One made-up scene: a set with D, V*F, env (a LUT in odd docs) and the
 * diffuse; every string a user or the catalog could give is name-like. */
typedef struct doc {
	bk_scene sc;
	bk_scene_result R;
	char names[6][NAME_CAP];
	char command[512], prefix[NAME_CAP + 8];
} doc;

static void choice(bk_scene_choice *c, bk_scene_term t, const char *name, const char *guards, const char *source,
                   int lut)
{
	memset(c, 0, sizeof *c);
	c->term = t;
	snprintf(c->name, sizeof c->name, "%s", name);
	snprintf(c->source, sizeof c->source, "%s", source);
	snprintf(c->guards, sizeof c->guards, "%s", guards);
	static const char *const text[] = {"D_ggx(NoH, a)", "V_smith_ggx_correlated(NoV, NoL, a)*F_schlick(f0, 1, LoH)",
	                                   "f0*p0 + p1*(1 - NoV)"};
	c->text = lut ? NULL : (char *)text[t];
	c->form = lut ? NULL : bk_form_parse(text[t], NULL); /* as bk_scene_choose leaves it (freed in teardown) */
	cr_assert(lut || c->form, "%s", text[t]);
	c->p[0] = 0.5;
	c->p[1] = 0.25;
	c->lut = lut;
	c->lut_size = 32;
	c->lut_layout = (bk_lut_layout){32, 32, 0.25, 1, BK_LUT_WARP_SQRT, lut == 2 ? 0.04 : NAN};
	c->lut_fmt = BK_LUT_UNORM8;
	c->cost = 10 + t;
	c->err = 0.01 * (t + 1);
	c->budget = t == BK_SCENE_TERM_D ? NAN : 0.05;
	c->meets = 1;
	c->scored = 3;
	snprintf(c->eq_name, sizeof c->eq_name, "%s", t == BK_SCENE_TERM_ENV ? name : "");
	c->eq_cost = 12;
	c->eq_err = 0.005;
}

/* Doc i: fuzzed names, or "plain" everywhere (the control); the numbers
 * and identifiers are the same in both. */
static void make_doc(doc *d, int i, int plain)
{
	memset(d, 0, sizeof *d);
	for (int k = 0; k < 6; k++)
		if (plain)
			strcpy(d->names[k], "plain");
		else
			fuzz_name(d->names[k]);
	bk_scene *sc = &d->sc;
	snprintf(sc->name, sizeof sc->name, "%s", d->names[0]);
	sc->nmat = 1;
	snprintf(sc->mat[0].name, sizeof sc->mat[0].name, "%s", d->names[1]);
	sc->mat[0].r_hi = 1;
	sc->mat[0].f0_lo = 0.04;
	sc->mat[0].f0_hi = 1;
	sc->mat[0].specular = 1;
	sc->punctual = sc->ibl = sc->diffuse = 1;
	sc->nov_hi = 1;
	sc->half = i % 2;
	sc->alu_tex = 32;
	sc->simple_cost = 1;
	sc->complex_cost = 4;
	sc->fetch_cost = 32;
	sc->lut = 1;
	sc->languages = BK_SCENE_GLSL | BK_SCENE_HLSL | BK_SCENE_C;
	sc->budget_vf = sc->budget_env = 0.05;
	bk_scene_result *R = &d->R;
	bk_scene_set *S = &R->set;
	snprintf(S->name, sizeof S->name, "s%d", i); /* identifiers: unique across the batch */
	S->needs = (bk_scene_needs){1, 1, 1, 0, NAN, 0, 0, 0};
	S->r_hi = 1;
	S->f0_lo = 0.04;
	S->f0_hi = 1;
	S->nmat = 1;
	for (int t = 0; t <= BK_SCENE_TERM_ENV; t++) { /* the terms of every scene (ms, sheen, cloth: asked for) */
		R->has[t] = 1;
		int lut = t == BK_SCENE_TERM_ENV && i % 2 ? 1 + (i % 4 == 1) : 0;
		choice(&R->ch[t], (bk_scene_term)t, d->names[2 + t], d->names[5], d->names[2], lut);
		choice(&R->gen[t], (bk_scene_term)t, "generic", "none", "generic", lut);
	}
	R->cost = R->gen_cost = 40;
	R->spirv = R->gen_spirv = i % 3 ? 20 : -1;
	R->ns = R->gen_ns = i % 3 ? 5 : NAN;
	/* the command line: argv joined, anything a shell can pass (also bytes that are not UTF-8) */
	snprintf(d->command, sizeof d->command, "brdfkit scene %s%s.json --out o --link-prefix %s", plain ? "" : "\xff",
	         d->names[3], d->names[4]);
	snprintf(d->prefix, sizeof d->prefix, "d/%s/", d->names[4]); /* a path: a scheme is the user's own choice */
}

static bk_scene_doc doc_view(const doc *d)
{
	bk_scene_doc v = {&d->sc, &d->R, 1, "0123456789abcdef", d->command, 0, NULL, NULL};
	return v;
}

/* ---- running the tools ----------------------------------------------------------- */

static char dir[64], csvget[4200];

static char *slurp(const char *path)
{
	FILE *f = fopen(path, "rb");
	cr_assert_not_null(f, "cannot read %s", path);
	fseek(f, 0, SEEK_END);
	long n = ftell(f);
	rewind(f);
	char *s = malloc((size_t)n + 1);
	cr_assert_not_null(s);
	cr_assert_eq(fread(s, 1, (size_t)n, f), (size_t)n);
	s[n] = '\0';
	fclose(f);
	return s;
}

/* Runs a shell command in dir; its output (stdout and stderr) malloc'd. */
static char *run(int *status, const char *fmt, ...)
{
	char cmd[8192], full[8400], out[128];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(cmd, sizeof cmd, fmt, ap);
	va_end(ap);
	snprintf(out, sizeof out, "%s/.out", dir);
	snprintf(full, sizeof full, "cd '%s' && ( %s ) > .out 2>&1", dir, cmd);
	*status = system(full);
	return slurp(out);
}

static void run_ok(const char *what, const char *fmt, ...)
{
	char cmd[8192];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(cmd, sizeof cmd, fmt, ap);
	va_end(ap);
	int status;
	char *out = run(&status, "%s", cmd);
	cr_assert_eq(status, 0, "%s: %s failed:\n%.3000s", what, cmd, out);
	free(out);
}

/* The text with every whitespace byte dropped: two outputs that differ only
 * in where comments were compare equal, an injected token never does. */
static char *squeeze(char *s)
{
	char *w = s;
	for (char *r = s; *r; r++)
		if (!strchr(" \t\n\r\f\v", *r))
			*w++ = *r;
	*w = '\0';
	return s;
}

static void need_tools(void)
{
	int s = system("command -v glslangValidator > /dev/null && command -v xmllint > /dev/null && "
	               "command -v cc > /dev/null && command -v nm > /dev/null && test -x build/csvget");
	cr_assert_eq(s, 0, "needs glslangValidator (glslang-tools), xmllint (libxml2-utils), cc, nm and build/csvget "
	                   "(make build/csvget), run from the repository's root");
}

/* [0] fuzzed, [1] plain; on the heap (15 MB): a static would sit in the
 * runner's .bss, which LeakSanitizer reads whole as each test's process ends */
static doc (*docs)[NDOC];

static void setup(void)
{
	need_tools();
	char cwd[4096];
	cr_assert_not_null(getcwd(cwd, sizeof cwd));
	snprintf(csvget, sizeof csvget, "%s/build/csvget", cwd);
	snprintf(dir, sizeof dir, "/tmp/bk_inject_XXXXXX");
	cr_assert_not_null(mkdtemp(dir));
	rng_state = 0x5eed2101ull;
	docs = calloc(2, sizeof *docs);
	cr_assert_not_null(docs);
	for (int i = 0; i < NDOC; i++) {
		make_doc(&docs[0][i], i, 0);
		make_doc(&docs[1][i], i, 1);
	}
}

static void teardown(void)
{
	for (int k = 0; k < 2; k++)
		for (int i = 0; i < NDOC; i++)
			for (int t = 0; t < BK_SCENE_TERMS; t++) {
				bk_form_free(docs[k][i].R.ch[t].form);
				bk_form_free(docs[k][i].R.gen[t].form);
			}
	free(docs);
	char cmd[128];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
	if (system(cmd))
		cr_log_warn("could not remove %s", dir);
}

static FILE *open_in_dir(const char *name)
{
	char path[128];
	snprintf(path, sizeof path, "%s/%s", dir, name);
	FILE *f = fopen(path, "w");
	cr_assert_not_null(f, "cannot write %s", path);
	return f;
}

/* Every doc's shader in language li, one file, as a program around them needs. */
static void write_shaders(int plain, int li, const char *name)
{
	FILE *f = open_in_dir(name);
	if (li == 0)
		fputs("#version 300 es\nprecision mediump float;\n", f);
	for (int i = 0; i < NDOC; i++) {
		bk_scene_doc v = doc_view(&docs[plain][i]);
		char err[256];
		cr_assert_eq(bk_scene_shader(f, &v, 0, li, err, sizeof err), 0, "doc %d: %s", i, err);
	}
	if (li == 0)
		fputs("out vec4 o;\nvoid main() { o = vec4(0); }\n", f);
	if (li == 1)
		fputs("float4 main(float4 u : TEXCOORD0) : SV_Target { return u; }\n", f);
	cr_assert_eq(fclose(f), 0);
}

/* What the preprocessor leaves of a file, squeezed (the comments are gone). */
static char *preprocessed(int li, const char *name)
{
	static const char *const cmd[3] = {"glslangValidator -E %s", "glslangValidator -E -D -S frag -e main %s",
	                                   "cc -std=c11 -E -P %s"};
	int status;
	char *out = run(&status, cmd[li], name);
	cr_assert_eq(status, 0, "%s: preprocessing failed:\n%.2000s", name, out);
	return squeeze(out);
}

TestSuite(inject, .init = setup, .fini = teardown, .timeout = 120);

Test(inject, shaders_compile_and_hold_only_the_plain_code)
{
	static const char *const file[2][3] = {{"all.frag", "all.hlsl", "all.c"}, {"plain.frag", "plain.hlsl", "plain.c"}};
	for (int li = 0; li < 3; li++)
		for (int plain = 0; plain < 2; plain++)
			write_shaders(plain, li, file[plain][li]);
	run_ok("GLSL", "glslangValidator all.frag");
	run_ok("HLSL", "glslangValidator -V -D -S frag -e main -o all.spv all.hlsl");
	run_ok("C", "cc -std=c11 -Wall -Wextra -Werror -c all.c -o all.o && cc -std=c11 -c plain.c -o plain.o");
	int s1, s2;
	char *syms = run(&s1, "nm --defined-only all.o"), *plain_syms = run(&s2, "nm --defined-only plain.o");
	cr_expect_str_eq(syms, plain_syms, "symbols a name defined:\n%.2000s", syms);
	cr_expect_null(strstr(syms, "inj"));
	free(syms);
	free(plain_syms);
	for (int li = 0; li < 3; li++) {
		char *a = preprocessed(li, file[0][li]), *b = preprocessed(li, file[1][li]);
		cr_expect(strcmp(a, b) == 0, "%s: code outside the comments differs from %s's", file[0][li], file[1][li]);
		free(a);
		free(b);
	}
}

/* The column NAME of every file made by fn, read by one csvget --each, with
 * "@@\n" after each file's rows. */
static char *columns(const char *prefix, const char *column)
{
	int status;
	char *out = run(&status, "'%s' --each %s $(for i in $(seq 0 %d); do echo %s$i.csv; done)", csvget, column,
	                NDOC - 1, prefix);
	cr_assert_eq(status, 0, "csvget could not read a column %s:\n%.2000s", column, out);
	return out;
}

static void expect_column(const char *prefix, const char *column, const char *(*want)(int i, char *buf))
{
	char *got = columns(prefix, column), *p = got, buf[512];
	for (int i = 0; i < NDOC; i++) {
		char row[600];
		snprintf(row, sizeof row, "%s@@\n", want(i, buf));
		cr_assert(!strncmp(p, row, strlen(row)), "%s%d.csv, column %s: expected '%s', read '%.200s'", prefix, i,
		          column, row, p);
		p += strlen(row);
	}
	free(got);
}

static const char *want_terms(int i, char *buf)
{
	(void)i;
	return strcpy(buf, "D\nvf\nenv\n");
}

static const char *want_material(int i, char *buf)
{
	const char *m = docs[0][i].sc.mat[0].name;
	snprintf(buf, 512, "%s\n%s\n%s\n", m, m, m);
	return buf;
}

static const char *want_set(int i, char *buf)
{
	snprintf(buf, 512, "s%d\n", i);
	return buf;
}

static const char *want_spirv(int i, char *buf)
{
	return strcpy(buf, i % 3 ? "20\n" : "\n"); /* not measured: empty, never -1 */
}

static const char *want_ns(int i, char *buf)
{
	return strcpy(buf, i % 3 ? "5.000\n" : "\n");
}

Test(inject, tables_keep_their_rows_and_columns)
{
	for (int i = 0; i < NDOC; i++) {
		char name[32];
		bk_scene_doc v = doc_view(&docs[0][i]);
		snprintf(name, sizeof name, "scene%d.csv", i);
		FILE *f = open_in_dir(name);
		bk_scene_csv(f, &v);
		cr_assert_eq(fclose(f), 0);
		snprintf(name, sizeof name, "sets%d.csv", i);
		f = open_in_dir(name);
		bk_scene_sets_csv(f, &v);
		cr_assert_eq(fclose(f), 0);
		snprintf(name, sizeof name, "timing%d.csv", i);
		f = open_in_dir(name);
		bk_scene_timing_csv(f, &v, 7);
		cr_assert_eq(fclose(f), 0);
	}
	expect_column("scene", "term", want_terms);
	expect_column("scene", "material", want_material);
	expect_column("sets", "feature_set", want_set);
	expect_column("sets", "spirv", want_spirv);
	expect_column("timing", "ns_per_eval", want_ns);
}

/* One page around the section of every doc of the batch. */
static void write_page(int plain, const char *name)
{
	char *sec = NULL;
	size_t len = 0;
	FILE *m = open_memstream(&sec, &len);
	cr_assert_not_null(m);
	bk_scene_section_open(m, "scenes");
	for (int i = 0; i < NDOC; i++) {
		bk_scene_doc v = doc_view(&docs[plain][i]);
		bk_scene_section_body(m, &v, docs[plain][i].prefix);
	}
	bk_scene_section_close(m);
	cr_assert_eq(fclose(m), 0);
	char id[64], err[256];
	cr_expect_eq(bk_section_check(sec, len, id, sizeof id, err, sizeof err), 0, "the section check refuses it: %s", err);
	FILE *f = open_in_dir(name);
	fprintf(f, "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>t</title></head><body>\n%s</body></html>\n",
	        sec);
	cr_assert_eq(fclose(f), 0);
	free(sec);
}

static long xpath_number(const char *page, const char *expr)
{
	int status;
	char *out = run(&status, "xmllint --html --xpath '%s' %s 2>/dev/null", expr, page);
	long n = strtol(out, NULL, 10);
	free(out);
	return n;
}

Test(inject, page_has_the_names_as_text_and_nothing_else)
{
	write_page(0, "all.html");
	write_page(1, "plain.html");
	cr_expect_eq(xpath_number("all.html", "count(//script)"), 0);
	cr_expect_eq(xpath_number("all.html", "count(//*[@onmouseover])"), 0);
	long elements = xpath_number("plain.html", "count(//*)"), attrs = xpath_number("plain.html", "count(//@*)");
	cr_assert_gt(elements, NDOC * 10, "xmllint found %ld elements in the plain page", elements);
	cr_expect_eq(xpath_number("all.html", "count(//*)"), elements, "elements added or lost");
	cr_expect_eq(xpath_number("all.html", "count(//@*)"), attrs, "attributes added or lost");
	/* the names read back as text: the heading of each scene whose name has no control character
	   (the HTML parser drops those) */
	for (int i = 0; i < NDOC; i++) {
		const char *name = docs[0][i].sc.name;
		int plain_text = 1;
		for (const char *c = name; *c; c++)
			plain_text &= (unsigned char)*c >= 0x20 && *c != 0x7f;
		if (!plain_text || !strstr(name, "<"))
			continue;
		int status;
		char *out = run(&status, "xmllint --html --xpath 'string(//h3[%d])' all.html 2>/dev/null", i + 1);
		cr_expect(strlen(out) == strlen(name) + 1 && !strncmp(out, name, strlen(name)), "heading %d: '%s' read as '%s'",
		          i + 1, name, out);
		free(out);
	}
}

/* report.txt and stdout are text for a terminal: no name in them holds a
 * control character (a line break, an escape sequence). */
static char *report_of(const doc *d)
{
	char *text = NULL;
	size_t len = 0;
	FILE *f = open_memstream(&text, &len);
	cr_assert_not_null(f);
	bk_scene_doc v = doc_view(d);
	bk_scene_report(f, &v, 1);
	cr_assert_eq(fclose(f), 0);
	return text;
}

static int lines_of(const char *s)
{
	int n = 0;
	for (; *s; s++)
		n += *s == '\n';
	return n;
}

Test(inject, report_text_has_no_control_character)
{
	for (int i = 0; i < NDOC; i++) {
		char *text = report_of(&docs[0][i]), *plain = report_of(&docs[1][i]);
		for (const char *c = text; *c; c++)
			cr_assert(*c == '\n' || ((unsigned char)*c >= ' ' && *c != 0x7f), "doc %d: byte 0x%02x in:\n%s", i,
			          (unsigned char)*c, text);
		cr_expect_eq(lines_of(text), lines_of(plain), "doc %d: the report's lines:\n%s", i, text);
		free(text);
		free(plain);
	}
}

/* ---- not measured (M8) ------------------------------------------------------------ */

/* A set without a specular term (cost 0) and without tools: every ratio and
 * count that does not exist is an empty field, and the words say so. */
Test(scene_write, not_measured_is_empty_never_a_number)
{
	doc d;
	make_doc(&d, 0, 1); /* i = 0: spirv -1, ns NaN */
	bk_scene_doc v = doc_view(&d);
	char *text = NULL;
	size_t len = 0;
	FILE *f = open_memstream(&text, &len);
	bk_scene_sets_csv(f, &v);
	bk_scene_timing_csv(f, &v, 7);
	bk_scene_report(f, &v, 1);
	fclose(f);
	/* sets.csv's row: cost 40 against 40 (ratio 1), spirv and generic_spirv not measured, errors 0.03/0.03 */
	cr_expect_not_null(strstr(text, "\ns0,plain,0,1,0.04,1,40,40,1,,,0.03,0.03,1\n"), "%s", text);
	cr_expect_not_null(strstr(text, "\ns0,,\n"), "timing.csv: %s", text);
	cr_expect_not_null(strstr(text, "SPIR-V not measured"), "%s", text);
	cr_expect_not_null(strstr(text, "CPU time not measured"), "%s", text);
	cr_expect_null(strstr(text, "-1"), "%s", text);
	cr_expect_null(strstr(text, "nan"), "%s", text);
	free(text);
	/* diffuse only: cost 0 against 0 has no ratio */
	d.R.cost = d.R.gen_cost = 0;
	d.R.has[0] = d.R.has[1] = d.R.has[2] = 0;
	d.R.spirv = d.R.gen_spirv = 0;
	text = NULL;
	f = open_memstream(&text, &len);
	bk_scene_sets_csv(f, &v);
	bk_scene_section_body(f, &v, "");
	fclose(f);
	cr_expect_not_null(strstr(text, "\ns0,plain,0,1,0.04,1,0,0,,0,0,,,\n"), "%s", text);
	cr_expect_null(strstr(text, "nan"), "%s", text);
	free(text);
}
