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

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static const char *const style =
	"body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222}"
	"table{border-collapse:collapse;font-size:13px;margin:1em 0}"
	"td,th{border:1px solid #ccc;padding:2px 6px;text-align:left;vertical-align:middle}"
	"th{background:#f4f4f4}code{background:#f4f4f4;padding:0 3px}"
	"section{margin-top:3em}svg{max-width:100%;height:auto}";

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
	x->text = bk_read_bounded(x->path, BK_PAGE_SECTION_MAX, &x->len, err, sizeof err);
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

static void page_head(FILE *f, const section *S, int n)
{
	fprintf(f, "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
	           "<title>brdfkit %s: cheap BRDF approximations, error against cost</title>\n<style>%s</style>\n"
	           "</head><body>\n<h1>brdfkit %s — error against cost</h1>\n", BK_VERSION, style, BK_VERSION);
	fputs("<p>Every published approximation in brdfkit's catalog, scored on the same samples of the exact term it "
	      "replaces, with its published constants and refitted with Ceres; for the environment BRDF also the "
	      "texture it replaces (16² to 128² LUTs in 8-bit unorm, half and float, sampled bilinearly with clamp to "
	      "edge). Cost is ALU ops after folding, sharing and multiply-add fusion, simple = 1, complex "
	      "(rcp, div, sqrt, rsqrt, exp2, log2) = 4; a texture fetch is priced with the talk's ALU:TEX ratios "
	      "(16, 32, 48, 64 simple ops per bilinear fetch per GPU tier). Conventions: r perceptual roughness, "
	      "a = r², V = G/(4 NoL NoV), split sum f0·A + B, Schlick F with f90 = 1. Made by <code>make results</code>; "
	      "the tidy CSVs are in <code>notebooks_data/</code>.</p>\n<p>Sections: ", f);
	for (int i = 0; i < n; i++) {
		fputs(i ? ", <a href=\"#" : "<a href=\"#", f);
		bk_html_text(f, S[i].id);
		fputs("\">", f);
		bk_html_text(f, S[i].id);
		fputs("</a>", f);
	}
	fputs(".</p>\n", f);
}

/* ---- where the options act (cli.h) ----------------------------------------- */

/* report has one option, the page it always writes. */
static const cli_rule rules[] = {
	{"--out", NULL, CLI_EVERYWHERE, 0, NULL, NULL},
};
static const char *const setups[] = {"--out p.html s.html", NULL};
static const cli_table table = {NULL, 0, rules, sizeof rules / sizeof rules[0], setups};

int cmd_report(int argc, char **argv)
{
	const char *out = NULL;
	cli_opt opts[] = {
		{.name = "--out", .kind = CLI_STR, .metavar = "FILE.html", .help = "the page (written atomically)", .dest = &out, .required = 1},
	};
	cli_cmd cmd = {"report", "Writes the study's page from the sections brdfkit compare wrote.",
	               "--out FILE.html SECTION.html [SECTION.html ...]",
	               "A section is a file brdfkit compare, stability, search, scene, lut --specular --sweep or\n"
	               "render wrote (at most 4 MiB; at most 32 sections): it\n"
	               "opens with <section id=\"ID\"> and holds only the elements and attributes those commands\n"
	               "write (no script, no event handler, links relative or http(s)); each is given once, with\n"
	               "an id of its own, and none is --out itself.",
	               opts, 1, 32, 0, {0}};
	int rc = cli_parse_table(&cmd, &table, argc, argv);
	if (rc || (rc = cli_applicable(&cmd, NULL)))
		return rc == 1 ? 0 : rc;
	if (cmd.npos < 1) {
		fprintf(stderr, "brdfkit report: missing SECTION.html (see brdfkit report --help)\n");
		return 2;
	}
	struct stat out_st;
	int out_exists = !stat(out, &out_st);
	section *S = calloc((size_t)cmd.npos, sizeof *S);
	if (!S)
		return cli_fail("report", "out of memory");
	for (int i = 0; i < cmd.npos && !rc; i++) { /* every section checked before the page is begun */
		S[i].path = cmd.pos[i];
		rc = load_section(S, i, out, out_exists ? &out_st : NULL);
	}
	bk_out co;
	char err[512];
	if (!rc && bk_out_open(&co, out, err, sizeof err))
		rc = cli_fail("report", "%s", err);
	if (!rc) {
		page_head(co.f, S, cmd.npos);
		for (int i = 0; i < cmd.npos; i++)
			fwrite(S[i].text, 1, S[i].len, co.f);
		fputs("</body></html>\n", co.f);
		if (bk_out_commit(&co, err, sizeof err))
			rc = cli_fail("report", "%s", err);
	}
	for (int i = 0; i < cmd.npos; i++)
		free(S[i].text);
	free(S);
	return rc;
}
