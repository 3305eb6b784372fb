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

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const style =
	"body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222}"
	"table{border-collapse:collapse;font-size:13px;margin:1em 0}"
	"td,th{border:1px solid #ccc;padding:2px 6px;text-align:left;vertical-align:middle}"
	"th{background:#f4f4f4}code{background:#f4f4f4;padding:0 3px}"
	"section{margin-top:3em}svg{max-width:100%;height:auto}";

/* A section is HTML text: a binary file (an image given by mistake) would
 * make a page of megabytes of garbage, so it is refused, named. */
static int copy_into(FILE *out, const char *path)
{
	size_t len;
	char *buf = cli_read_file(path, &len), why[64];
	if (!buf)
		return cli_fail("report", "%s: cannot read: %s", path, strerror(errno));
	int bad = cli_check_text(buf, len, why, sizeof why);
	if (bad)
		cli_fail("report", "%s: not text (%s)", path, why);
	else
		fwrite(buf, 1, len, out);
	free(buf);
	return bad ? 1 : 0;
}

int cmd_report(int argc, char **argv)
{
	const char *out = NULL;
	cli_opt opts[] = {
		{.name = "--out", .kind = CLI_STR, .metavar = "FILE.html", .help = "the page (written atomically)", .dest = &out, .required = 1},
	};
	cli_cmd cmd = {"report", "Writes the study's page from the sections brdfkit compare wrote.",
	               "--out FILE.html SECTION.html [SECTION.html ...]", NULL, opts, 1, 16, 0, {0}};
	int rc = cli_parse(&cmd, argc, argv);
	if (rc)
		return rc == 1 ? 0 : rc;
	if (cmd.npos < 1) {
		fprintf(stderr, "brdfkit report: missing SECTION.html (see brdfkit report --help)\n");
		return 2;
	}
	bk_out co;
	char err[512];
	if (bk_out_open(&co, out, err, sizeof err))
		return cli_fail("report", "%s", err);
	FILE *f = co.f;
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
	for (int i = 0; i < cmd.npos; i++) {
		const char *slash = strrchr(cmd.pos[i], '/'), *start = cmd.pos[i];
		char name[64] = "";
		if (slash) { /* results/compare/<target>/section.html: the target's name */
			const char *p = slash - 1;
			while (p > start && p[-1] != '/')
				p--;
			snprintf(name, sizeof name, "%.*s", (int)(slash - p), p);
		}
		FILE *sf = fopen(cmd.pos[i], "r"); /* the section's own id, where it opens with one */
		char head[256] = "", *id;
		if (sf) {
			size_t got = fread(head, 1, sizeof head - 1, sf);
			head[got] = '\0';
			fclose(sf);
		}
		if (!strncmp(head, "<section id=\"", 13) && (id = strchr(head + 13, '"')) && id - head - 13 < 63)
			snprintf(name, sizeof name, "%.*s", (int)(id - head - 13), head + 13);
		fprintf(f, "%s<a href=\"#%s\">%s</a>", i ? ", " : "", name, name);
	}
	fputs(".</p>\n", f);
	for (int i = 0; i < cmd.npos; i++)
		if (copy_into(f, cmd.pos[i])) {
			bk_out_abort(&co);
			return 1;
		}
	fputs("</body></html>\n", f);
	return bk_out_commit(&co, err, sizeof err) ? cli_fail("report", "%s", err) : 0;
}
