/*
 * test_report.c — analysis/report.c: the Pareto fronts, the CSV tables and the
 * SVG plot of error against cost.
 *
 * Seven hand-made rows whose fronts can be read off by eye (cost, max |error|, ns):
 *   A (1, 0.5, 1)    on both fronts: the cheapest placeable row
 *   B (2, 0.1, 2)    on both
 *   C (3, 0.2, 1.5)  dominated by B on cost; on the ns front (faster than B, better than A)
 *   D (4, 0.01, 4)   on both
 *   E (5, 0.01, 5)   dominated by D: equal error, more cost
 *   F (0.5, NaN, .5) never on a front, although cheapest
 *   G (6, 0.001, NaN) on the cost front; untimed, so not on the ns front
 * A LUT row (no ALU, one fetch, error 0.002) between an ALU row P (20, 0.01)
 * and Q (40, 0.001): at 16 ops a fetch it costs 16 and beats P; at 32 all three
 * are on the front; at 48 and 64 Q beats it.
 * The plots: what they hold (markers, the staircase's vertices, labels placed:
 * bk_compare_plot_points), the SVG well-formed (xmllint), no string reaching it as
 * markup, and two writes giving the same PNG, SVG and PDF bytes.
 */
#include "compare.h"
#include "plot.h"
#include "search_front.h"
#include "search_write.h"
#include "target.h"

#include <criterion/criterion.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static bk_compare_row make_row(const char *name, const char *kind, double cost, double err, double ns)
{
	bk_compare_row r;
	memset(&r, 0, sizeof r);
	snprintf(r.name, sizeof r.name, "%s", name);
	snprintf(r.kind, sizeof r.kind, "%s", kind);
	r.cost = cost;
	r.m.max_abs = err;
	r.m.rmse = err / 2;
	r.m.weighted_rmse = err / 3;
	r.m.max_rel = err * 4;
	r.m.albedo_max_abs = NAN;
	r.ns = ns;
	r.ns_min = ns * 0.9;
	r.ns_max = ns * 1.2;
	r.spirv = -1;
	return r;
}

enum { NBASIC = 7 };

static void basic_rows(bk_compare_row *rows)
{
	rows[0] = make_row("A", "published", 1, 0.5, 1);
	rows[1] = make_row("B", "refit", 2, 0.1, 2);
	rows[2] = make_row("C", "form", 3, 0.2, 1.5);
	rows[3] = make_row("D", "published", 4, 0.01, 4);
	rows[4] = make_row("E", "refit", 5, 0.01, 5);
	rows[5] = make_row("F", "form", 0.5, NAN, 0.5);
	rows[6] = make_row("G", "form", 6, 0.001, NAN);
}

static void lut_rows(bk_compare_row *rows)
{
	rows[0] = make_row("P", "published", 20, 0.01, 3);
	rows[1] = make_row("LUT 64x64 half", "lut", 0, 0.002, NAN);
	rows[1].tex_fetches = 1;
	rows[1].sampler_slots = 1;
	rows[2] = make_row("Q", "form", 40, 0.001, 6);
}

static void expect_flags(const bk_compare_row *rows, int n, const int *cost, const int *ns)
{
	for (int i = 0; i < n; i++) {
		cr_expect_eq(rows[i].pareto_cost, cost[i], "%s: pareto_cost %d, expected %d", rows[i].name,
		             rows[i].pareto_cost, cost[i]);
		if (ns)
			cr_expect_eq(rows[i].pareto_ns, ns[i], "%s: pareto_ns %d, expected %d", rows[i].name,
			             rows[i].pareto_ns, ns[i]);
	}
}

Test(report, ratios_are_the_talks)
{
	cr_expect_eq(bk_tier_alu_per_tex[0], 16);
	cr_expect_eq(bk_tier_alu_per_tex[1], 32);
	cr_expect_eq(bk_tier_alu_per_tex[2], 48);
	cr_expect_eq(bk_tier_alu_per_tex[3], 64);
}

Test(report, pareto_fronts_by_inspection)
{
	bk_compare_row rows[NBASIC];
	basic_rows(rows);
	rows[4].pareto_cost = rows[4].pareto_ns = 7; /* stale flags are overwritten */
	bk_pareto(rows, NBASIC, 0);
	static const int cost[NBASIC] = {1, 1, 0, 1, 0, 0, 1};
	static const int ns[NBASIC] = {1, 1, 1, 1, 0, 0, 0};
	expect_flags(rows, NBASIC, cost, ns);

	/* The order of the rows does not matter. */
	bk_compare_row rev[NBASIC];
	for (int i = 0; i < NBASIC; i++)
		rev[i] = rows[NBASIC - 1 - i];
	bk_pareto(rev, NBASIC, 0);
	for (int i = 0; i < NBASIC; i++) {
		cr_expect_eq(rev[i].pareto_cost, cost[NBASIC - 1 - i], "%s reversed", rev[i].name);
		cr_expect_eq(rev[i].pareto_ns, ns[NBASIC - 1 - i], "%s reversed", rev[i].name);
	}
}

Test(report, pareto_ties_and_degenerate_tables)
{
	bk_compare_row rows[3];
	rows[0] = make_row("twin 1", "form", 2, 0.1, 1);
	rows[1] = make_row("twin 2", "form", 2, 0.1, 1);
	rows[2] = make_row("inf", "form", 0, INFINITY, 0);
	bk_pareto(rows, 3, 0);
	static const int both[3] = {1, 1, 0}; /* exact ties: neither dominates; inf error never */
	expect_flags(rows, 3, both, both);

	rows[0] = make_row("alone", "form", 2, 0.0, 1); /* a zero error is an error like any other */
	bk_pareto(rows, 1, 0);
	cr_expect_eq(rows[0].pareto_cost, 1);
	cr_expect_eq(rows[0].pareto_ns, 1);
	bk_pareto(rows, 0, 0); /* nothing to do, nothing touched */
}

Test(report, lut_priced_per_tier)
{
	bk_compare_row rows[3];
	lut_rows(rows);
	static const int front[BK_TIERS][3] = {{0, 1, 1}, {1, 1, 1}, {1, 0, 1}, {1, 0, 1}};
	for (int t = 0; t < BK_TIERS; t++) {
		bk_pareto(rows, 3, t);
		for (int i = 0; i < 3; i++)
			cr_expect_eq(rows[i].pareto_cost, front[t][i], "tier %d (%d ops a fetch), %s: %d",
			             t, bk_tier_alu_per_tex[t], rows[i].name, rows[i].pareto_cost);
		/* untimed LUT is off the ns front whatever the tier; P and Q are both on it */
		cr_expect_eq(rows[0].pareto_ns, 1);
		cr_expect_eq(rows[1].pareto_ns, 0);
		cr_expect_eq(rows[2].pareto_ns, 1);
	}
}

/* ---- CSV ---------------------------------------------------------------------------- */

/* The writer's output in a malloc'd string. */
typedef void (*table_fn)(FILE *, const bk_compare_row *, int);

static void csv_default(FILE *f, const bk_compare_row *rows, int n)
{
	bk_compare_csv(f, rows, n, NULL);
}

static char *capture_table(table_fn fn, const bk_compare_row *rows, int n)
{
	char *buf = NULL;
	size_t len = 0;
	FILE *f = open_memstream(&buf, &len);
	cr_assert_not_null(f);
	fn(f, rows, n);
	cr_assert_eq(fclose(f), 0);
	return buf;
}

static int count_lines(const char *s)
{
	int n = 0;
	for (; *s; s++)
		n += *s == '\n';
	return n;
}

/* Field col (0-based) of the line starting at line, quotes understood, into out. */
static void csv_field(const char *line, int col, char *out, size_t len)
{
	size_t o = 0;
	int c = 0, quoted = 0;
	for (const char *p = line; *p && (quoted || *p != '\n'); p++) {
		if (*p == '"') {
			if (quoted && p[1] == '"') {
				if (c == col && o + 1 < len)
					out[o++] = '"';
				p++;
			} else
				quoted = !quoted;
		} else if (*p == ',' && !quoted)
			c++;
		else if (c == col && o + 1 < len)
			out[o++] = *p;
	}
	out[o] = '\0';
}

/* Fields on the line starting at line. */
static int csv_ncols(const char *line)
{
	int n = 1, quoted = 0;
	for (const char *p = line; *p && (quoted || *p != '\n'); p++) {
		if (*p == '"')
			quoted = !quoted; /* a doubled quote toggles twice */
		else if (*p == ',' && !quoted)
			n++;
	}
	return n;
}

static int header_col(const char *csv, const char *name)
{
	char field[64];
	for (int c = 0; c < 100; c++) {
		csv_field(csv, c, field, sizeof field);
		if (strcmp(field, name) == 0)
			return c;
	}
	cr_assert_fail("no column %s", name);
	return -1;
}

static const char *nth_line(const char *s, int k)
{
	for (; k > 0 && s; k--) {
		s = strchr(s, '\n');
		s = s ? s + 1 : NULL;
	}
	cr_assert_not_null(s);
	return s;
}

static void expect_field(const char *csv, int line, const char *col, const char *want)
{
	char got[1200];
	csv_field(nth_line(csv, line), header_col(csv, col), got, sizeof got);
	cr_expect_str_eq(got, want, "line %d, %s", line, col);
}

Test(report, compare_csv)
{
	bk_compare_row rows[NBASIC];
	basic_rows(rows);
	snprintf(rows[0].source, sizeof rows[0].source, "Karis 2014, \"Real Shading\"");
	snprintf(rows[0].form, sizeof rows[0].form, "1/(LoH*LoH*(r+p0))");
	rows[0].params[0] = 0.5;
	rows[0].params[1] = -2;
	rows[0].nparams = 2;
	rows[0].ops.n[BK_K_MAD] = 3;
	rows[0].ops.n[BK_K_RCP] = 1;
	rows[0].ops.simple = 3;
	rows[0].ops.complex = 1;
	rows[0].spirv = 12;
	rows[0].cheaper_than_fetch[0] = 1;
	rows[0].m.albedo_max_abs = 0.25;
	bk_pareto(rows, NBASIC, 0);
	char *csv = capture_table(csv_default, rows, NBASIC);

	const char header[] =
		"name,kind,source,form,form_b,parameters,rmse,weighted_rmse,max_abs,max_rel,"
		"albedo_max_abs,add,mul,mad,minmax,saturate,rcp,div,sqrt,rsqrt,exp2,log2,simple,"
		"complex,cost,tex_fetches,sampler_slots,spirv,cheaper_than_fetch_16,"
		"cheaper_than_fetch_32,cheaper_than_fetch_48,cheaper_than_fetch_64,pareto_cost\n";
	cr_assert_eq(strncmp(csv, header, strlen(header)), 0, "header:\n%.400s", csv);
	cr_expect_eq(count_lines(csv), NBASIC + 1);

	expect_field(csv, 1, "name", "A");
	expect_field(csv, 1, "source", "Karis 2014, \"Real Shading\"");
	expect_field(csv, 1, "form", "1/(LoH*LoH*(r+p0))");
	expect_field(csv, 1, "parameters", "p0=0.5;p1=-2");
	expect_field(csv, 1, "max_abs", "0.5");
	expect_field(csv, 1, "albedo_max_abs", "0.25");
	expect_field(csv, 1, "mad", "3");
	expect_field(csv, 1, "rcp", "1");
	expect_field(csv, 1, "cost", "1");
	expect_field(csv, 1, "spirv", "12");
	expect_field(csv, 1, "cheaper_than_fetch_16", "1");
	expect_field(csv, 1, "pareto_cost", "1");
	expect_field(csv, 2, "albedo_max_abs", ""); /* NaN */
	expect_field(csv, 2, "parameters", "");
	expect_field(csv, 2, "spirv", "");          /* -1: no SPIR-V */
	expect_field(csv, 5, "pareto_cost", "0");   /* E */
	expect_field(csv, 6, "max_abs", "");        /* F */
	expect_field(csv, 6, "rmse", "");
	expect_field(csv, 7, "max_abs", "0.001");   /* G */
	/* The quoted source holds a comma: every line still has the header's column count. */
	int ncols = csv_ncols(csv);
	cr_expect_eq(ncols, header_col(csv, "pareto_cost") + 1);
	for (int l = 1; l <= NBASIC; l++)
		cr_expect_eq(csv_ncols(nth_line(csv, l)), ncols, "line %d", l);

	char *again = capture_table(csv_default, rows, NBASIC);
	cr_expect_str_eq(csv, again);
	free(again);
	free(csv);
}

Test(report, timing_csv)
{
	bk_compare_row rows[NBASIC];
	basic_rows(rows);
	snprintf(rows[1].name, sizeof rows[1].name, "B, refit");
	bk_pareto(rows, NBASIC, 0);
	char *csv = capture_table(bk_timing_csv, rows, NBASIC);
	cr_assert_eq(strncmp(csv, "name,ns_per_eval,ns_min,ns_max,pareto_ns\n", 41), 0, "%.200s", csv);
	cr_expect_eq(count_lines(csv), NBASIC + 1);
	const char *b = nth_line(csv, 2);
	cr_expect_eq(strncmp(b, "\"B, refit\",2,1.8,2.4,1\n", 23), 0, "%.40s", b);
	cr_expect_eq(strncmp(nth_line(csv, 7), "G,,,,0\n", 7), 0, "%.40s", nth_line(csv, 7));
	free(csv);
}

/* ---- the plots (bk_compare_plot, drawn by analysis/plot.c) ----------------------------- */

static int count_of(const char *s, const char *what)
{
	int n = 0;
	for (const char *p = strstr(s, what); p; p = strstr(p + 1, what))
		n++;
	return n;
}

/* A file's bytes, NUL-terminated; *len its size. */
static char *slurp(const char *path, size_t *len)
{
	FILE *f = fopen(path, "rb");
	cr_assert_not_null(f, "%s", path);
	char *buf = NULL;
	size_t cap = 0, n = 0, k;
	do {
		if (n + 4096 + 1 > cap)
			buf = realloc(buf, cap = 2 * cap + 4096 + 1);
		k = fread(buf + n, 1, 4096, f);
		n += k;
	} while (k > 0);
	fclose(f);
	buf[n] = '\0';
	*len = n;
	return buf;
}

/* xmllint --noout on a file, when xmllint is there (Debian libxml2-utils). */
static void expect_well_formed(const char *path)
{
	if (system("command -v xmllint >/dev/null 2>&1") != 0) {
		cr_log_warn("xmllint not installed (libxml2-utils): well-formedness not checked");
		return;
	}
	char cmd[300];
	snprintf(cmd, sizeof cmd, "xmllint --noout %s", path);
	cr_expect_eq(system(cmd), 0, "xmllint rejected %s", path);
}

/* Writes the plot into a fresh directory; returns it (static buffer). */
static const char *plot_into(const bk_compare_row *rows, int n, int xaxis, const char *title,
                             const bk_compare_info *info)
{
	static char dir[64];
	snprintf(dir, sizeof dir, "/tmp/bk_test_report_XXXXXX");
	cr_assert_not_null(mkdtemp(dir));
	char err[600] = "";
	cr_assert_eq(bk_compare_plot(rows, n, xaxis, title, info, dir, "p", err, sizeof err), 0, "%s", err);
	return dir;
}

static void remove_plot(const char *dir)
{
	char path[128];
	static const char *const ext[3] = {"png", "svg", "pdf"};
	for (int k = 0; k < 3; k++) {
		snprintf(path, sizeof path, "%s/p.%s", dir, ext[k]);
		unlink(path);
	}
	rmdir(dir);
}

static const char title[] = "V & F <fit> \"vf_talk_r\"";

Test(report, plot_cost_axis)
{
	bk_compare_row rows[NBASIC];
	basic_rows(rows);
	snprintf(rows[2].name, sizeof rows[2].name, "C<1> & \"2\"");
	int shown, front, placed;
	cr_assert_eq(bk_compare_plot_points(rows, NBASIC, 0, NULL, &shown, &front, &placed), 0);
	cr_expect_eq(shown, NBASIC - 1, "one marker per row with a finite error (not F)");
	cr_expect_eq(front, 4, "the staircase through A B D G");
	cr_expect_eq(placed, NBASIC - 1, "six labels, room for all of them");

	char first[64];
	snprintf(first, sizeof first, "%s", plot_into(rows, NBASIC, 0, title, NULL));
	const char *again = plot_into(rows, NBASIC, 0, title, NULL);
	static const char *const ext[3] = {"png", "svg", "pdf"};
	for (int k = 0; k < 3; k++) { /* the same rows, the same bytes */
		char a[128], b[128];
		size_t la, lb;
		snprintf(a, sizeof a, "%s/p.%s", first, ext[k]);
		snprintf(b, sizeof b, "%s/p.%s", again, ext[k]);
		char *x = slurp(a, &la), *y = slurp(b, &lb);
		cr_expect(la == lb && memcmp(x, y, la) == 0, "%s: two writes differ", ext[k]);
		if (k == 1) {
			cr_expect_eq(strncmp(x, "<?xml", 5), 0);
			cr_expect_null(strstr(x, "<fit>"), "text is drawn as glyphs, never as markup");
			cr_expect_null(strstr(x, "nan"));
			expect_well_formed(a);
		}
		if (k == 2)
			cr_expect_eq(strncmp(x, "%PDF-", 5), 0);
		free(x);
		free(y);
	}
	remove_plot(first);
	remove_plot(again);
}

Test(report, plot_ns_axis)
{
	bk_compare_row rows[NBASIC];
	basic_rows(rows);
	int shown, front, placed;
	cr_assert_eq(bk_compare_plot_points(rows, NBASIC, 1, NULL, &shown, &front, &placed), 0);
	cr_expect_eq(shown, NBASIC - 2, "F (no error) and G (no timing) not drawn");
	cr_expect_eq(front, 4, "front A C B D");
	const char *dir = plot_into(rows, NBASIC, 1, title, NULL);
	char path[128];
	snprintf(path, sizeof path, "%s/p.svg", dir);
	expect_well_formed(path);
	remove_plot(dir);
}

/* Three rows at one point and a zero error: the labels spread round the point,
 * the exact row is drawn (on the axis' "0" level). */
Test(report, plot_zero_errors_and_collisions)
{
	bk_compare_row rows[5];
	rows[0] = make_row("exact", "form", 3, 0.0, 1);
	rows[1] = make_row("close", "published", 5, 0.02, 1);
	rows[2] = make_row("twin", "refit", 8, 0.003, 1);
	rows[3] = make_row("twin", "refit", 8, 0.003, 1);
	rows[4] = make_row("twin", "lut", 8, 0.003, 1);
	int shown, front, placed;
	cr_assert_eq(bk_compare_plot_points(rows, 5, 0, NULL, &shown, &front, &placed), 0);
	cr_expect_eq(shown, 5, "the zero-error row is drawn too");
	cr_expect_eq(placed, 5, "three labels at one point find three places");
	const char *dir = plot_into(rows, 5, 0, "zeros", NULL);
	remove_plot(dir);
}

Test(report, plot_empty_and_bad_text)
{
	int shown, front, placed;
	cr_assert_eq(bk_compare_plot_points(NULL, 0, 0, NULL, &shown, &front, &placed), 0);
	cr_expect_eq(shown + front + placed, 0);
	const char *dir = plot_into(NULL, 0, 0, NULL, NULL);
	remove_plot(dir);
	bk_compare_row row = make_row("bad \x01 \xff \xed\xa0\x80 utf-8 \xc3\xa9", "other kind", 1, 0.1, 1);
	dir = plot_into(&row, 1, 0, "t\x02", NULL);
	char path[128];
	snprintf(path, sizeof path, "%s/p.svg", dir);
	expect_well_formed(path);
	remove_plot(dir);
}

/* Every string in a plot is drawn text, whatever it holds: the row's name and
 * kind, the title, the chip and the cost model's name (option values). */
Test(report, plot_escapes_every_string)
{
	static const char evil[] = "</text><script>alert(1)</script>";
	bk_compare_row row = make_row(evil, evil, 1, 0.1, 1);
	row.gpu_insn[0] = 7;
	bk_compare_info info = BK_COMPARE_INFO_INIT;
	info.cost_model = evil;
	info.nchips = 1;
	info.chip[0] = evil;
	for (int xaxis = 0; xaxis < 3; xaxis++) {
		const char *dir = plot_into(&row, 1, xaxis, evil, &info);
		char path[128];
		size_t len;
		snprintf(path, sizeof path, "%s/p.svg", dir);
		char *buf = slurp(path, &len);
		cr_expect_null(strstr(buf, "<script"), "axis %d", xaxis);
		cr_expect_eq(count_of(buf, "alert"), 0, "axis %d", xaxis);
		expect_well_formed(path);
		free(buf);
		remove_plot(dir);
	}
}

/* Hollow markers (off the front) were drawn with no legend entry saying so
 * (results/compare/vf2d/pareto_ns.png): every marker style drawn is explained. */
Test(report, legend_explains_every_marker_drawn)
{
	bk_compare_row rows[NBASIC];
	basic_rows(rows);
	for (int xaxis = 0; xaxis < 2; xaxis++)
		cr_expect_eq(bk_compare_plot_unexplained(rows, NBASIC, xaxis, NULL), -1, "x axis %d", xaxis);
	/* negative control: the same legend without the hollow key leaves the hollow series unexplained */
	double x[2] = {1, 2}, y[2] = {0.1, 0.2};
	bk_plot_series s[3] = {
		{"published constants", BK_PLOT_POINTS, BK_PLOT_CIRCLE, 0, 0x1f77b4, 1, x, y, NULL, NULL, NULL},
		{NULL, BK_PLOT_POINTS, BK_PLOT_CIRCLE, 1, 0x1f77b4, 1, x + 1, y + 1, NULL, NULL, NULL},
		{"hollow: off the front", BK_PLOT_POINTS, BK_PLOT_CIRCLE, 1, 0x7f7f7f, 0, x, y, NULL, NULL, NULL},
	};
	bk_plot p = {BK_PLOT_DOUBLE_W, 4.2, NULL, NULL, NULL, {"x", 0, 0, 3, 0, 0, NULL}, {"y", 1, 0.01, 1, 0, 0, NULL},
	             s, 3, NULL};
	cr_expect_eq(bk_plot_unexplained(&p), -1, "with the key");
	p.nseries = 2;
	cr_expect_eq(bk_plot_unexplained(&p), 1, "without the key the hollow series is unexplained");
	s[0].marker = BK_PLOT_SQUARE;
	p.nseries = 3;
	cr_expect_eq(bk_plot_unexplained(&p), 1, "a key does not explain a shape no entry has");
}

/* results/search/env_f0 and env_mix's plots were titled "search on env" as env's:
 * a title names the study's own target. */
Test(report, search_titles_name_the_env_form_and_the_index)
{
	bk_sfront F;
	memset(&F, 0, sizeof F);
	bk_target_options to;
	memset(&to, 0, sizeof to);
	bk_swrite W;
	memset(&W, 0, sizeof W);
	W.F = &F;
	W.to = &to;
	char lab[4][160];
	F.kind = BK_TARGET_ENV;
	W.env_form = NULL;
	bk_swrite_target_label(&W, lab[0], sizeof lab[0]);
	W.env_form = "f0";
	bk_swrite_target_label(&W, lab[1], sizeof lab[1]);
	W.env_form = "mix";
	bk_swrite_target_label(&W, lab[2], sizeof lab[2]);
	cr_expect_str_eq(lab[0], "env");
	cr_expect_not_null(strstr(lab[1], "env_f0"), "%s", lab[1]);
	cr_expect_not_null(strstr(lab[2], "env_mix"), "%s", lab[2]);
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < i; j++)
			cr_expect_str_neq(lab[i], lab[j], "two env studies share a title");
	/* f: the index and its f0 (gold: 0.27 + 2.78i), computed here from the
	 * normal-incidence Fresnel ((n-1)^2 + k^2)/((n+1)^2 + k^2) */
	F.kind = BK_TARGET_F;
	to.eta = 0.27, to.k = 2.78;
	bk_swrite_target_label(&W, lab[3], sizeof lab[3]);
	double f0 = ((0.27 - 1) * (0.27 - 1) + 2.78 * 2.78) / ((0.27 + 1) * (0.27 + 1) + 2.78 * 2.78);
	char want[64];
	snprintf(want, sizeof want, "n = 0.27 + 2.78i, f0 = %.3g", f0);
	cr_expect_not_null(strstr(lab[3], want), "%s (want %s)", lab[3], want);
}
