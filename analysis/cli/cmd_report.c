/*
 * cmd_report.c — brdfkit report: the study's page. Wraps the sections that
 * brdfkit compare wrote (inline SVG, tables, heatmap thumbnails beside it)
 * into one self-contained results/index.html. No timings: the page is
 * byte-identical on a rerun; run times live in each section's timing.csv.
 */
#include "brdf.h"
#include "cli.h"
#include "out.h"
#include "cmd.h"
#include "page.h"
#include "plot.h"
#include "summary.h"

#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static const char *const style =
	"body{font-family:sans-serif;max-width:1200px;margin:2em auto;padding:0 1em;color:#222}"
	"table{border-collapse:collapse;font-size:13px;margin:1em 0}"
	"td,th{border:1px solid #ccc;padding:2px 6px;text-align:left;vertical-align:middle}"
	"th{background:#f4f4f4}code{background:#f4f4f4;padding:0 3px}"
	"section{margin-top:3em}svg{max-width:100%;height:auto}"
	"figure{margin:1em 0}figcaption{font-size:13px;color:#444;margin-top:.3em}"
	"details.fold>summary{cursor:pointer;font-size:13px;color:#444;margin:.5em 0}"
	"table.summary{font-size:11px;line-height:1.25;margin:.4em 0}table.summary td,table.summary th{padding:0 5px}table.summary td{white-space:nowrap}"
	/* its headers break between words only: a target's name or "cost" split
	 * mid-word doubles a row (DejaVu Sans, the wide default, pushed Figure 1
	 * off the first screen so; tests/page.sh) */
	"table.summary th{overflow-wrap:normal}"
	"figure.main{display:flex;gap:1em;align-items:flex-start;margin:.5em 0}"
	"figure.main>a{flex:0 0 64%}figure.main img{width:100%;height:auto}figure.main figcaption{flex:1}"
	/* wide tables fit the window: the render table's three pictures shrink with it (their
	 * width attribute is the most), a long formula or header ("polaris10/vega10/...") breaks
	 * anywhere rather than push a column off (tests/page.sh, at 1280 and 1900 px) */
	"#render table{table-layout:fixed;width:100%}#render img{max-width:100%;height:auto}"
	"td code,th code,th{overflow-wrap:anywhere}"
	"h1{margin:.2em 0 .3em}p.lead{margin:.3em 0}p.note{font-size:12px;color:#444;margin:.2em 0}"
	/* a formula is as wide as its form (MathML does not wrap): its own line,
	 * scrolled sideways when wider than the page, never widening it */
	"p.finding{font-size:13px;margin:.3em 0}span.formula{display:block;overflow-x:auto;padding:2px 0}";

/* A table of more rows than this is folded (page.h): the first screen is
 * the summary, and a reader opens what they want. */
#define FOLD_ROWS 6

/* One section, read and checked before anything is written. */
typedef struct section {
	const char *path;
	char *text;
	size_t len;
	char id[64];
	struct stat st;
} section;

/* A section over the size cap: a binary given by mistake, the usual case,
 * is named as one from its first 4 KiB (cut back to a whole character). */
static int refuse_big(const char *path, const char *err)
{
	char head[4096], why[64];
	FILE *f = fopen(path, "rb");
	size_t n = f ? fread(head, 1, sizeof head, f) : 0;
	if (f)
		fclose(f);
	while (n && ((unsigned char)head[n - 1] & 0xc0) == 0x80)
		n--;
	if (n && (unsigned char)head[n - 1] >= 0xc0)
		n--;
	if (n && cli_check_text(head, n, why, sizeof why))
		return cli_fail("report", "%s: not text (%s)", path, why);
	return cli_fail("report", "%s: %s (a section brdfkit writes is well under that)", path, err);
}

/* Reads and checks section k of S against --out and the sections before it:
 * a section is HTML text brdfkit wrote (page.h's check), not the page being
 * written, and not a second copy (two elements with one id). Returns 0 or 1. */
static int load_section(section *S, int k, const char *out, const struct stat *out_st)
{
	section *x = &S[k];
	char err[512], why[64];
	x->text = bk_read_regular(x->path, BK_PAGE_SECTION_MAX, &x->len, err, sizeof err);
	if (!x->text && !stat(x->path, &x->st) && S_ISREG(x->st.st_mode) && (size_t)x->st.st_size > BK_PAGE_SECTION_MAX)
		return refuse_big(x->path, err);
	if (!x->text)
		return cli_fail("report", "%s: %s", x->path, err);
	if (stat(x->path, &x->st) && strcmp(x->path, "-"))
		return cli_fail("report", "%s: cannot be read: %s", x->path, strerror(errno));
	if (out_st && x->st.st_dev == out_st->st_dev && x->st.st_ino == out_st->st_ino)
		return cli_fail("report", "%s: is --out %s itself (the page would overwrite its own section)", x->path, out);
	if (cli_check_text(x->text, x->len, why, sizeof why))
		return cli_fail("report", "%s: not text (%s)", x->path, why);
	if (bk_section_check(x->text, x->len, x->id, sizeof x->id, err, sizeof err))
		return cli_fail("report", "%s: %s", x->path, err);
	for (int j = 0; j < k; j++) {
		if (S[j].st.st_dev == x->st.st_dev && S[j].st.st_ino == x->st.st_ino)
			return cli_fail("report", "%s: given twice (also as %s)", x->path, S[j].path);
		if (!strcmp(S[j].id, x->id))
			return cli_fail("report", "%s: its id '%s' is also %s's (the page would have two elements with one id)",
			                x->path, x->id, S[j].path);
	}
	return 0;
}

/* The first screen's figure: the first searched target's Pareto plot
 * (brdfkit search writes pareto.png, .svg and .pdf beside front.csv). */
static void main_figure(FILE *f, const bk_summary_row *r, const char *href)
{
	fputs("<figure class=\"main\" id=\"main-figure\"><a href=\"", f);
	bk_html_link(f, href, "pareto.pdf");
	fputs("\"><img src=\"", f);
	bk_html_link(f, href, "pareto.png");
	/* the PNG's tick labels in its own pixels, for the page's check of their size on screen */
	fprintf(f, "\" data-tick-px=\"%.4g\" alt=\"error against cost of the search on ", BK_PLOT_TICK_PT * BK_PLOT_DPI / 72.0);
	bk_html_text(f, r->target);
	fputs("\"></a>\n<figcaption><b>Figure 1.</b> The search on <code>", f);
	bk_html_text(f, r->target);
	fputs("</code>: error (", f);
	bk_html_text(f, r->objective);
	fputs(", log scale) against cost (brdfkit ops, ", f);
	bk_html_text(f, r->cost_model[0] ? r->cost_model : "weighted as the file's header states");
	fputs("). Blue: the front, refitted on the full samples, "
	      "a staircase; triangles: the published forms with their published constants; squares: the same forms "
	      "refitted; grey: every candidate at screening. Data: <a href=\"", f);
	bk_html_link(f, href, "front.csv");
	fputs("\">front.csv</a> and <a href=\"", f);
	bk_html_link(f, href, "catalog.csv");
	fputs("\">catalog.csv</a>; as <a href=\"", f);
	bk_html_link(f, href, "pareto.pdf");
	fputs("\">PDF</a>, <a href=\"", f);
	bk_html_link(f, href, "pareto.svg");
	fputs("\">SVG</a>.</figcaption></figure>\n", f);
}

/* Row r's finding (summary.h) and formula, escaped (the formula is MathML
 * brdf_math.h wrote: numbers and input names only). */
static void finding(FILE *f, const bk_summary_row *r)
{
	char text[1024];
	bk_summary_finding(r, text, sizeof text);
	fputs("<b>", f);
	bk_html_text(f, r->target);
	fputs("</b>: ", f);
	bk_html_text(f, text);
	if (!r->formula[0])
		return;
	fputs(" <span class=\"formula\"><code>", f);
	bk_html_text(f, r->has_search ? r->at_cost.name : r->pub.name);
	fputs(strncmp(r->formula, "A = ", 4) ? "</code> = " : "</code>: ", f); /* a split sum's "A = .., B = .." */
	fputs(r->formula, f);
	fputs("</span>", f);
}

/* Every row's finding and formula, after Figure 1: a formula is as wide as
 * its form (MathML does not wrap), too wide for the summary's cells. */
static void findings(FILE *f, const bk_summary_row *R, int n)
{
	fputs("<div id=\"findings\" class=\"findings\"><h2>Findings</h2>\n<p class=\"note\">Per target, written from "
	      "the summary's numbers; each formula is the searched form at the best published form's cost (with no "
	      "search, the best published form), its constants to 4 digits (the exact ones: the row of its file, or "
	      "<code>brdfkit codegen --lang latex|sympy FILE.csv:MEMBER</code>).</p>\n", f);
	for (int i = 0; i < n; i++) {
		fputs("<p class=\"finding\" id=\"finding-", f);
		bk_html_text(f, R[i].target);
		fputs("\">", f);
		finding(f, &R[i]);
		fputs("</p>\n", f);
	}
	fputs("</div>\n", f);
}

/* The summary: what was found, first (summary.h), with its figure. */
static void page_summary(FILE *f, const bk_summary_row *R, int n, const char *const *href)
{
	fputs("<p class=\"lead\">Per target: the most accurate published form against the search's front on the same "
	      "samples and objective; the error ratio is the published error over the searched one (larger is better). "
	      "Each name links to the file it is read from (the line in its tooltip).</p>\n", f);
	for (int i = 0; i < n; i++) /* the first screen's finding: Figure 1's target */
		if (R[i].has_search) {
			fputs("<p class=\"finding\" id=\"first-finding\">", f);
			finding(f, &R[i]);
			fputs("</p>\n", f);
			break;
		}
	bk_summary_table(f, R, n, href);
	int same = R[0].cost_model[0] != '\0';
	for (int i = 1; i < n; i++)
		same &= !strcmp(R[i].cost_model, R[0].cost_model);
	fputs("<p class=\"note\">Error as each row's files state it: max_abs the largest absolute error over the target's "
	      "samples, rmse their root mean square, albedo_max_abs the largest error of the directional albedo "
	      "(the integral of the term times NoL); f64 or f16 the precision the forms are evaluated in. A ratio compares "
	      "the errors of its own row only. Cost in brdfkit ops after folding, sharing and multiply-add fusion", f);
	if (same) {
		fputs(", every row: ", f);
		bk_html_text(f, R[0].cost_model);
		fputs(" (complex: rcp, div, sqrt, rsqrt, exp2, log2)", f);
	} else
		fputs(", weighted as each row's files state", f);
	fputs(".</p>\n", f);
	for (int i = 0; i < n; i++)
		if (R[i].has_search) {
			main_figure(f, &R[i], href[i]);
			break;
		}
	findings(f, R, n);
}

static void page_head(FILE *f, const section *S, int n, const bk_summary_row *R, int nr, const char *const *href)
{
	fprintf(f, "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
	           "<title>brdfkit %s: cheap BRDF approximations, error against cost</title>\n<style>%s</style>\n"
	           "</head><body>\n<h1>brdfkit %s — error against cost</h1>\n", BK_VERSION, style, BK_VERSION);
	if (nr)
		page_summary(f, R, nr, href);
	fputs("<p>Every published approximation in brdfkit's catalog, scored on the same samples of the exact term it "
	      "replaces, with its published constants and refitted with Ceres; for the environment BRDF also the "
	      "texture it replaces (16² to 128² LUTs in 8-bit unorm, half and float, sampled bilinearly with clamp to "
	      "edge). Cost is ALU ops after folding, sharing and multiply-add fusion, simple = 1, complex "
	      "(rcp, div, sqrt, rsqrt, exp2, log2) = 4; a texture fetch is priced with the talk's ALU:TEX ratios "
	      "(16, 32, 48, 64 simple ops per bilinear fetch per GPU tier). Conventions: r perceptual roughness, "
	      "a = r², V = G/(4 NoL NoV), split sum f0·A + B, Schlick F with f90 = 1. Made by <code>make results</code>; "
	      "the tidy CSVs are in <code>notebooks_data/</code>. Tables longer than a few rows are folded: click a "
	      "table's line to open it.</p>\n<p>Sections: ", f);
	for (int i = 0; i < n; i++) {
		fputs(i ? ", <a href=\"#" : "<a href=\"#", f);
		bk_html_text(f, S[i].id);
		fputs("\">", f);
		bk_html_text(f, S[i].id);
		fputs("</a>", f);
	}
	fputs(".</p>\n", f);
}

/* --summary's targets read, each with its link from the page; 0 or 1. */
static int load_summary(const cli_cmd *cmd, const char *list, const char *out, bk_summary_row **R, char ***href,
                        int *n)
{
	const char *dirs[32];
	char err[1024];
	*n = cli_words(cmd, "--summary", list, dirs, 32);
	if (*n < 0)
		return 2;
	*R = calloc((size_t)*n, sizeof **R);
	*href = calloc((size_t)*n, sizeof **href);
	if (!*R || !*href)
		return cli_fail("report", "out of memory");
	for (int i = 0; i < *n; i++) {
		char rel[PATH_MAX];
		if (bk_summary_read(dirs[i], &(*R)[i], err, sizeof err) ||
		    bk_page_rel_dir(out, dirs[i], rel, sizeof rel, err, sizeof err))
			return cli_fail("report", "--summary: %s", err);
		if (!((*href)[i] = strdup(rel)))
			return cli_fail("report", "out of memory");
	}
	for (int i = 0; i < *n; i++) /* the figure: the first searched target's plot, there */
		if ((*R)[i].has_search) {
			char png[PATH_MAX + 16];
			snprintf(png, sizeof png, "%s/pareto.png", dirs[i]);
			struct stat st;
			if (stat(png, &st) || !S_ISREG(st.st_mode))
				return cli_fail("report", "--summary: %s: no such file (the first screen's figure; brdfkit search "
				                "writes it beside front.csv)", png);
			break;
		}
	return 0;
}

/* ---- where the options act (cli.h) ----------------------------------------- */

/* report's options act everywhere: the page it always writes, and the summary. */
static const cli_rule rules[] = {
	{"--out", NULL, CLI_EVERYWHERE, 0, NULL, NULL},
	{"--summary", NULL, CLI_EVERYWHERE, 0, NULL, NULL},
};
static const char *const setups[] = {"--out p.html s.html", NULL};
static const cli_table table = {NULL, 0, rules, sizeof rules / sizeof rules[0], setups};

int cmd_report(int argc, char **argv)
{
	const char *out = NULL, *summary = NULL;
	cli_opt opts[] = {
		{.name = "--out", .kind = CLI_STR, .metavar = "FILE.html", .help = "the page (written atomically)", .dest = &out, .required = 1},
		{.name = "--summary", .kind = CLI_STR, .metavar = "DIR,DIR,...", .help = "the first screen: per target DIR (a brdfkit search --out, or a compare --out with no search) the best published form against the search's front", .dest = &summary},
	};
	cli_cmd cmd = {"report", "Writes the study's page from the sections brdfkit compare wrote.",
	               "--out FILE.html [--summary DIR,DIR,...] SECTION.html [SECTION.html ...]",
	               "A section is a file brdfkit compare, stability, search, scene, lut --specular --sweep or\n"
	               "render wrote (at most 4 MiB; at most 32 sections): it\n"
	               "opens with <section id=\"ID\"> and holds only the elements and attributes those commands\n"
	               "write (no script, no event handler, links relative or http(s), none to //host); each is\n"
	               "given once, with an id of its own, and none is --out itself. Tables of more than 6 rows\n"
	               "are folded (<details>). --summary reads each DIR's catalog.csv and front.csv (or, with no\n"
	               "search, compare.csv) by column name and writes, first, one row per DIR: the most accurate\n"
	               "published form (cost, error), the most accurate front member at equal or lower cost and\n"
	               "the error ratio, the cheapest member as accurate, and how many published forms the front\n"
	               "beats at their own cost, in the objective the files state (front.csv must state its\n"
	               "catalog.csv's target, objective and precision); then the first searched DIR's pareto.png\n"
	               "as Figure 1, and per DIR a findings sentence written from those numbers with the formula of\n"
	               "the member at cost (MathML, constants to 4 digits; from the files' form, form_b and\n"
	               "parameters columns). Links are relative from the page's folder, percent-encoded.",
	               opts, 2, 32, 0, {0}};
	int rc = cli_parse_table(&cmd, &table, argc, argv);
	if (rc || (rc = cli_applicable(&cmd, NULL)))
		return rc == 1 ? 0 : rc;
	if (cmd.npos < 1) {
		fprintf(stderr, "brdfkit report: missing SECTION.html (see brdfkit report --help)\n");
		return 2;
	}
	struct stat out_st; /* --out is checked as it is opened (bk_out_open_file): the sections, read first,
	                     * say more precisely when it is one of them */
	int out_exists = !stat(out, &out_st);
	bk_summary_row *R = NULL;
	char **href = NULL;
	int nr = 0;
	section *S = calloc((size_t)cmd.npos, sizeof *S);
	if (!S)
		return cli_fail("report", "out of memory");
	if (summary)
		rc = load_summary(&cmd, summary, out, &R, &href, &nr);
	for (int i = 0; i < cmd.npos && !rc; i++) { /* every section checked before the page is begun */
		S[i].path = cmd.pos[i];
		rc = load_section(S, i, out, out_exists ? &out_st : NULL);
	}
	bk_out co;
	char err[512];
	if (!rc && bk_out_open_file(&co, out, err, sizeof err))
		rc = cli_fail("report", "%s", err);
	if (!rc) {
		page_head(co.f, S, cmd.npos, R, nr, (const char *const *)href);
		for (int i = 0; i < cmd.npos; i++)
			bk_page_fold(co.f, S[i].text, S[i].len, FOLD_ROWS);
		fputs("</body></html>\n", co.f);
		if (bk_out_commit(&co, err, sizeof err))
			rc = cli_fail("report", "%s", err);
	}
	for (int i = 0; i < cmd.npos; i++)
		free(S[i].text);
	free(S);
	for (int i = 0; href && i < nr; i++)
		free(href[i]);
	free(href);
	free(R);
	return rc;
}
