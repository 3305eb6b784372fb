/*
 * cmd_render.c — brdfkit render: spheres shaded with the exact BRDF and with
 * a candidate in place of one term, by the emitted GLSL on Mesa's lavapipe in
 * f32 and float16_t (or by the IR on the CPU), written as EXR, PNG and a page
 * section (analysis/render.h, analysis/render_write.h). One form, or a batch
 * CSV of them (columns read by name: name, term, form, form_b, parameters).
 */
#include "brdf.h"
#include "catalog.h"
#include "cli.h"
#include "cmd.h"
#include "csvtab.h"
#include "form_check.h"
#include "member.h"
#include "out.h"
#include "render.h"
#include "render_write.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define MAX_ITEMS 64

/* One render: the candidate as given and as parsed. */
typedef struct item {
	char name[64];
	char *form, *form_b, *params_text; /* the texts (catalog's or given) */
	double params[BK_MAX_PARAMS];
	int have[BK_MAX_PARAMS];
	bk_render_term term;
	int member;                        /* a front member: its parameter count (else 0) */
	bk_form *f, *fb;
	float *img[BK_RI_COUNT];
	char *shader[2];
} item;

static void free_item(item *it)
{
	free(it->form);
	free(it->form_b);
	free(it->params_text);
	bk_form_free(it->f);
	bk_form_free(it->fb);
	for (int i = 0; i < BK_RI_COUNT; i++)
		free(it->img[i]);
	free(it->shader[0]);
	free(it->shader[1]);
}

static char *dup_or_null(const char *s)
{
	return s && *s ? strdup(s) : NULL;
}

/* A name that may be a directory and an HTML word: [A-Za-z0-9_.-], not
 * starting with '.' or '-', 1..63 characters. */
static int name_ok(const char *s)
{
	size_t n = strlen(s);
	if (n < 1 || n > 63 || s[0] == '.' || s[0] == '-')
		return 0;
	return strspn(s, "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_.-") == n;
}

/* Resolves and checks one candidate: a catalog NAME (its published
 * parameters, its target's term unless term is given), a front member
 * FILE.csv:NAME (its fitted parameters, its front's target's term unless
 * term is given, named NAME unless name is) or a form. 0, or 2 after one
 * line naming the input. */
static int resolve(item *it, const char *name, const char *form, const char *form_b, const char *params,
                   const char *term)
{
	if (form_b && !*form_b) /* an empty field of a batch: none */
		form_b = NULL;
	if (params && !*params)
		params = NULL;
	const bk_catalog_entry *e = cli_member_split(form) ? NULL : bk_catalog_find(form);
	cli_member m = {0};
	if (!e && cli_member_split(form)) { /* FILE.csv:NAME (member.h): a pair whole */
		int rc = cli_member_load(form, 1, &m);
		if (rc)
			return rc;
	}
	snprintf(it->name, sizeof it->name, "%.63s",
	         name ? name : e ? e->name : m.form ? (m.fname[0] ? m.fname : m.name) : "candidate");
	if (!name_ok(it->name)) {
		cli_member_free(&m);
		return cli_bad("name '%.80s': use 1 to 63 of A-Z a-z 0-9 _ . - (not first . or -)", it->name);
	}
	if (term && bk_render_term_parse(term, &it->term)) {
		cli_member_free(&m);
		return cli_bad("%s: --term: expected vf2d, vf, d, v, f, dvf or env, got '%.40s'", it->name, term);
	}
	if (m.form) { /* the member's texts move to it; its target is the term unless --term says */
		it->member = m.np;
		it->form = m.form;
		it->form_b = m.form_b;
		it->f = m.f, it->fb = m.f_b; /* parsed as the file was read */
		memcpy(it->params, m.p, sizeof it->params);
		for (int j = 0; j < m.np; j++)
			it->have[j] = 1;
		if (!term && bk_render_term_parse(m.target, &it->term)) {
			return cli_bad("%s: its front's target '%s' replaces no term of the render (give --term)", it->name,
			               m.target);
		}
		if (form_b) {
			return cli_bad("%s: --form-b: a front member brings its own B", it->name);
		}
	} else if (e) {
		it->form = strdup(e->form);
		it->form_b = dup_or_null(e->form_b);
		memcpy(it->params, e->defaults, sizeof it->params);
		for (int j = 0; j < e->nparams; j++)
			it->have[j] = 1;
		if (!term && bk_render_term_of_target(e->target, &it->term)) {
			return cli_bad("%s: its target %s replaces no term of the render (give --term)",
			               it->name, e->target);
		}
		if (form_b) {
			return cli_bad("%s: --form-b: a catalog entry brings its own B", it->name);
		}
	} else {
		if (!term) {
			return cli_bad("%s: a typed form needs --term (vf2d, vf, d, v, f, dvf or env)", it->name);
		}
		it->form = strdup(form);
		it->form_b = dup_or_null(form_b);
	}
	if (!it->form || (form_b && *form_b && !it->form_b))
		return cli_fail("render", "out of memory");
	if (it->form_b && it->term != BK_RT_ENV) {
		return cli_bad("%s: a B form is only for --term env (f0 A + B)", it->name);
	}
	int given[BK_MAX_PARAMS] = {0};
	if (params && *params) {
		if (form_param_list(it->name, params, it->params, given))
			return 2;
		for (int j = 0; j < BK_MAX_PARAMS; j++)
			it->have[j] |= given[j];
		it->params_text = strdup(params);
	} else if (e || it->member) { /* the published values (9 digits, as the catalog states them) or the
	                                * fitted ones (17, as front.csv writes them) */
		char buf[1024] = "";
		size_t len = 0;
		for (int j = 0, np = e ? e->nparams : it->member; j < np && len < sizeof buf - 40; j++)
			len += (size_t)snprintf(buf + len, sizeof buf - len, e ? "%sp%d=%.9g" : "%sp%d=%.17g", j ? ";" : "",
			                        j, it->params[j]);
		it->params_text = strdup(buf);
	}
	bk_form_error fe;
	const char *texts[2] = {it->form, it->form_b};
	bk_form **fs[2] = {&it->f, &it->fb};
	unsigned used = 0;
	for (int k = 0; k < 2; k++) {
		if (!texts[k])
			continue;
		if (!*fs[k] && !(*fs[k] = bk_form_parse(texts[k], &fe))) {
			fprintf(stderr, "brdfkit render: %s: %s: column %d: %s\n", it->name, k ? "form B" : "form", fe.column,
			        fe.message);
			return 2;
		}
		used |= bk_form_params(*fs[k]);
	}
	int rc = form_check_params("render", it->name, used, it->have, params && *params ? given : NULL);
	for (int k = 0; !rc && k < 2; k++)
		if (*fs[k])
			rc = form_check_finite("render", it->name, *fs[k], it->params);
	return rc;
}

/* ---- a batch CSV (name, term, form, form_b, parameters by name) ------------------- */

static const char *const batch_cols[] = {"name", "term", "form", "form_b", "parameters", NULL};

/* "brdfkit render: --batch PATH[:LINE]: what"; 2, the file being bad input. */
static int batch_fail(const char *err)
{
	fprintf(stderr, "brdfkit render: --batch %s\n", err);
	return 2;
}

/* The rows of a batch CSV (its first line per row in the errors) into items;
 * 0, or non-zero after one line on stderr. */
static int read_batch(const char *path, item *items, int *n)
{
	char err[600];
	bk_csvtab_spec spec = {.cols = batch_cols, .optional = 1u << 3 | 1u << 4,
	                       .hint = "want name, term, form, form_b, parameters", .max_rows = MAX_ITEMS};
	bk_csvtab t;
	*n = 0;
	int rc = bk_csvtab_read(path, &spec, &t, err, sizeof err);
	if (rc)
		return rc == -2 ? cli_fail("render", "--batch %s", err) : batch_fail(err);
	if (!t.n) {
		bk_csvtab_err(err, sizeof err, path, 0, "no rows");
		rc = batch_fail(err);
	}
	for (int i = 0; !rc && i < t.n; i++) {
		const char *term = bk_csvtab_get(&t, i, 1);
		rc = resolve(&items[*n], bk_csvtab_get(&t, i, 0), bk_csvtab_get(&t, i, 2), bk_csvtab_get(&t, i, 3),
		             bk_csvtab_get(&t, i, 4), *term ? term : NULL); /* resolve says what is wrong */
		++*n;
		if (!rc && bk_render_file_name(items[*n - 1].name)) { /* the batch's own top-level file */
			bk_csvtab_err(err, sizeof err, path, t.line[i], "the name '%s' is a file the batch writes beside the "
			              "renders' directories; choose another", items[*n - 1].name);
			rc = batch_fail(err);
		}
		for (int j = 0; j < *n - 1 && !rc; j++)
			if (!strcmp(items[j].name, items[*n - 1].name)) {
				bk_csvtab_err(err, sizeof err, path, t.line[i], "the name '%s' twice", items[j].name);
				rc = batch_fail(err);
			}
	}
	bk_csvtab_free(&t);
	return rc;
}

/* ---- the command ------------------------------------------------------------------ */

static const cli_dim dims[] = {
	{"input", {"form", "batch"}, {" with --form", " with --batch"}},
};
enum { IN_FORM, IN_BATCH };
static const cli_rule rules[] = {
	{"--form", NULL, CLI_EVERYWHERE, 0, NULL, "vf_talk_r"},
	{"--form-b", NULL, 0, 1u << IN_FORM, "the B of a split env form", "1"},
	{"--params", NULL, 0, 1u << IN_FORM, "the form's parameters", "p0=1"},
	{"--term", NULL, 0, 1u << IN_FORM, "the term the form replaces", "vf"},
	{"--name", NULL, 0, 1u << IN_FORM, "the render's name", "x"},
	{"--batch", NULL, CLI_EVERYWHERE, 0, NULL, "b.csv"},
	{"--precision", NULL, CLI_EVERYWHERE, 0, NULL, "single"},
	{"--size", NULL, CLI_EVERYWHERE, 0, NULL, "64"},
	{"--roughness", NULL, CLI_EVERYWHERE, 0, NULL, "0.5,1"},
	{"--device", NULL, CLI_EVERYWHERE, 0, NULL, "cpu"},
	{"--link-prefix", NULL, CLI_EVERYWHERE, 0, NULL, "x/"},
	{"--out", NULL, CLI_EVERYWHERE, 0, NULL, NULL},
};
static const char *const setups[] = {"--form vf_talk_r --out o", "--batch b.csv --out o", NULL};
static const cli_table table = {dims, 1, rules, sizeof rules / sizeof rules[0], setups};

static int render_item(item *it, bk_lvp *v, const bk_render_geom *g, int want_f32, int want_f16, double *secs)
{
	char err[1200];
	size_t npix = (size_t)g->width * (size_t)g->height * 3;
	bk_render_cand c = {it->term, it->f, it->fb, it->params, it->name};
	/* the exact f32 image is every difference's reference: it runs for f16 alone too */
	for (int k = 0; k < 2; k++) {
		if (k && !want_f16)
			continue;
		bk_precision prec = k ? BK_F16 : BK_F32;
		float *img[2] = {malloc(npix * sizeof(float)), malloc(npix * sizeof(float))};
		it->img[k ? BK_RI_EXACT_F16 : BK_RI_EXACT_F32] = img[0];
		it->img[k ? BK_RI_CAND_F16 : BK_RI_CAND_F32] = img[1];
		if (!img[0] || !img[1])
			return cli_fail("render", "out of memory");
		if (v) {
			double t[2];
			if (!(it->shader[k] = bk_render_shader(&c, prec)))
				return cli_fail("render", "%s: cannot write the shader", it->name);
			if (bk_render_gpu(v, g, &c, prec, img, t, err, sizeof err))
				return cli_fail("render", "%s: %s", it->name, err);
			secs[0] += t[0];
			secs[1] += t[1];
		} else if (bk_render_cpu(g, &c, k ? BK_F16 : BK_F64, img))
			return cli_fail("render", "out of memory");
		if (!k && !want_f32) {
			free(it->img[BK_RI_CAND_F32]);
			it->img[BK_RI_CAND_F32] = NULL;
			free(it->shader[0]);
			it->shader[0] = NULL;
		}
	}
	return 0;
}

static int write_all(const char *out, item *items, int n, int batch, const bk_render_scene *sc,
                     const bk_render_geom *g, const char *device, const char *prefix)
{
	char err[1200], path[4400];
	bk_render_out *o = calloc((size_t)n, sizeof *o);
	bk_out_dir od;
	if (!o)
		return cli_fail("render", "out of memory");
	if (bk_out_dir_begin(&od, out, NULL, err, sizeof err)) {
		free(o);
		return cli_fail("render", "--out %s", err);
	}
	int rc = 0;
	for (int i = 0; i < n && !rc; i++) {
		o[i] = (bk_render_out){.name = items[i].name, .form = items[i].form, .form_b = items[i].form_b,
		                       .params = items[i].params_text, .term = bk_render_term_name(items[i].term),
		                       .device = device, .scene = sc, .g = g};
		memcpy(o[i].img, items[i].img, sizeof o[i].img);
		o[i].shader[0] = items[i].shader[0];
		o[i].shader[1] = items[i].shader[1];
		snprintf(path, sizeof path, "%s", od.tmp);
		if (batch && i == 0) { /* the batch's exact images, once, at the top */
			bk_render_out top = o[0];
			top.img[BK_RI_CAND_F32] = top.img[BK_RI_CAND_F16] = NULL;
			top.shader[0] = top.shader[1] = NULL;
			top.name = "exact";
			top.form = "the exact BRDF (D_ggx, V_smith_ggx_correlated, F_schlick; split sum f0 A + B)";
			top.form_b = top.params = NULL;
			top.term = "none";
			rc = bk_render_write(od.tmp, &top, err, sizeof err);
		}
		if (batch) {
			o[i].shared_exact = 1;
			snprintf(path, sizeof path, "%s/%s", od.tmp, items[i].name);
			if (!rc && mkdir(path, 0777)) {
				snprintf(err, sizeof err, "%.1000s: %s", path, strerror(errno));
				rc = -1;
			}
		}
		if (!rc)
			rc = bk_render_write(path, &o[i], err, sizeof err);
	}
	if (!rc) {
		snprintf(path, sizeof path, "%s/section.html", od.tmp);
		FILE *f = bk_out_fopen(path, err, sizeof err);
		if (f)
			bk_render_section(f, o, n, prefix, batch);
		if (!f || bk_out_fclose(f, path, err, sizeof err))
			rc = -1;
	}
	for (int i = 0; i < n && !rc; i++) {
		printf("render: %s (replaces %s): non-finite pixels", items[i].name, o[i].term);
		if (o[i].img[BK_RI_CAND_F32])
			printf(" f32 %zu%s", o[i].nonfinite[BK_RI_CAND_F32], o[i].img[BK_RI_CAND_F16] ? "," : "");
		if (o[i].img[BK_RI_CAND_F16])
			printf(" f16 %zu (exact f16 %zu)", o[i].nonfinite[BK_RI_CAND_F16], o[i].nonfinite[BK_RI_EXACT_F16]);
		for (int k = 0; k < 2; k++)
			if (isfinite(o[i].max_diff[k]))
				printf("; %s display difference max %.3g mean %.3g", k ? "f16" : "f32", o[i].max_diff[k],
				       o[i].mean_diff[k]);
		printf("\n");
	}
	free(o);
	if (rc) {
		bk_out_dir_abort(&od);
		return cli_fail("render", "%s: writing failed: %s", out, err);
	}
	if (bk_out_dir_commit(&od, err, sizeof err))
		return cli_fail("render", "--out %s", err);
	return 0;
}

int cmd_render(int argc, char **argv)
{
	const char *form = NULL, *form_b = NULL, *params = NULL, *term = NULL, *name = NULL, *batch = NULL;
	const char *precision = "both", *device = "lavapipe", *out = NULL, *prefix = "";
	long size = 640;
	cli_list rough = {5, {0.1, 0.25, 0.5, 0.75, 1}};
	cli_opt opts[] = {
		{.name = "--form", .kind = CLI_FORM, .metavar = "NAME|FILE.csv:MEMBER|FORM", .help = "the candidate: a catalog name (its published parameters and target), a member of a search's front.csv (its fitted parameters and target) or a form", .dest = &form},
		{.name = "--form-b", .kind = CLI_FORM, .metavar = "FORM", .help = "with --term env: B of f0 A + B (--form is then A)", .dest = &form_b},
		{.name = "--params", .kind = CLI_STR, .metavar = "p0=X;p1=Y", .help = "parameter values (front.csv's parameters column; override a catalog entry's)", .dest = &params},
		{.name = "--term", .kind = CLI_STR, .metavar = "vf2d|vf|d|v|f|dvf|env", .help = "the term the candidate replaces (default: a catalog entry's target)", .dest = &term},
		{.name = "--name", .kind = CLI_STR, .metavar = "NAME", .help = "the render's name in the outputs (default: the catalog name or 'candidate')", .dest = &name},
		{.name = "--batch", .kind = CLI_STR, .metavar = "CSV", .help = "many candidates: columns name, term, form, form_b, parameters (read by name); each into DIR/NAME/", .dest = &batch},
		{.name = "--precision", .kind = CLI_STR, .metavar = "single|half|both", .help = "which shaders run: float (f32 outputs), float16_t (f16 outputs) or both (default)", .dest = &precision},
		{.name = "--size", .kind = CLI_INT, .metavar = "W", .help = "image width in pixels (default 640); cells are W / columns square (8 to 4096 pixels), two rows", .dest = &size, .lo = 16, .hi = 8192},
		{.name = "--roughness", .kind = CLI_LIST, .metavar = "R,...", .help = "the columns' roughness (default 0.1,0.25,0.5,0.75,1)", .dest = &rough, .lo = 0, .hi = 1, .lo_open = 1},
		{.name = "--device", .kind = CLI_STR, .metavar = "lavapipe|cpu", .help = "lavapipe: the emitted GLSL on Mesa's software Vulkan (default); cpu: the IR (double for f32, BK_F16 for f16), the reference", .dest = &device},
		{.name = "--link-prefix", .kind = CLI_LINK, .metavar = "PATH/", .help = "prefix of the links in section.html: a path relative to the page (no scheme, no //host), percent-encoded where written", .dest = &prefix},
		{.name = "--out", .kind = CLI_STR, .metavar = "DIR", .help = "the output directory, replaced whole (EXR, PNG, spheres.csv, shaders, section.html)", .dest = &out, .required = 1},
	};
	cli_cmd cmd = {"render",
	               "Renders a grid of spheres (columns: roughness; rows: a dielectric, f0 0.04, and gold) lit by\n"
	               "one directional light and a procedural sky prefiltered as engines do (split sum with brdfkit's\n"
	               "DFG), with the exact BRDF and with a candidate in place of one term, by brdfkit's emitted GLSL\n"
	               "on Mesa's lavapipe (software Vulkan; no GPU needed) in f32 and in float16_t, as a mobile\n"
	               "mediump shader computes. Writes linear EXR, sRGB PNG, the display difference at a stated\n"
	               "scale, per-sphere counts (spheres.csv) and a page section.",
	               "--form NAME|FILE.csv:MEMBER|FORM [--form-b FORM] [--params p0=X;...] [--term T] --out DIR | --batch CSV --out DIR",
	               "Terms: vf (vf2d) replaces V·F in D·V·F·NoL; d, v, f one factor; dvf the whole D·V·F; env\n"
	               "the environment BRDF f0 A + B (a form reading f0, or --form A --form-b B).\n"
	               "FILE.csv:MEMBER (--form, or a batch's form column) is a member of a front.csv of brdfkit\n"
	               "search: its form(s), fitted parameters and the term of its front's target.\n"
	               "Difference images: the largest over R, G, B of |display(candidate) - display(exact f32)|,\n"
	               "display = sRGB of Reinhard x/(1 + x), times 8 (a ramp black-red-yellow-white); magenta\n"
	               "marks non-finite pixels. The summary's max and mean are over the pixels where the exact\n"
	               "f32 image is finite; a candidate pixel that is not finite counts as 1, the whole display\n"
	               "range. The scene's numbers: analysis/render.h and every file's header.\n"
	               "lavapipe needs the Debian package mesa-vulkan-drivers.",
	               opts, (int)(sizeof opts / sizeof opts[0]), 0, 0, {0}};
	int rc = cli_parse_table(&cmd, &table, argc, argv);
	if (rc)
		return rc == 1 ? 0 : rc;
	/* --form and --batch exclude each other (said below); the options of one
	 * candidate act only with --form */
	if ((rc = cli_applicable(&cmd, (int[]){form ? IN_FORM : IN_BATCH})))
		return rc;
	if (!form == !batch)
		return cli_usage(&cmd, "give one of --form and --batch");
	cli_prec prec;
	if (cli_precision(precision, CLI_PREC_BIT(CLI_PREC_SINGLE) | CLI_PREC_BIT(CLI_PREC_HALF) | CLI_PREC_BIT(CLI_PREC_BOTH),
	                  &prec))
		return 2;
	int want_f32 = prec != CLI_PREC_HALF, want_f16 = prec != CLI_PREC_SINGLE; /* outputs keep f32/f16 in their names */
	static const char *const devices[] = {"lavapipe", "cpu"};
	int di = cli_choice("--device", device, devices, 2);
	if (di < 0)
		return 2;
	int lvp_dev = di == 0;
	if (rough.n > BK_RENDER_MAX_COLS)
		return cli_usage(&cmd, "--roughness: at most %d columns", BK_RENDER_MAX_COLS);
	bk_render_scene sc = {.cell = (int)(size / rough.n), .ncols = rough.n};
	memcpy(sc.r, rough.v, sizeof(double) * (size_t)rough.n);
	if (sc.cell < BK_RENDER_MIN_CELL || sc.cell > BK_RENDER_MAX_CELL) /* the help's [16, 8192] is W's, not a cell's */
		return cli_usage(&cmd, "--size %ld: cells of %d pixels for %d column%s (a cell is %d to %d pixels: W from %ld "
		                 "to %ld here)", size, sc.cell, rough.n, rough.n > 1 ? "s" : "", BK_RENDER_MIN_CELL,
		                 BK_RENDER_MAX_CELL, (long)BK_RENDER_MIN_CELL * rough.n,
		                 (long)BK_RENDER_MAX_CELL * rough.n < 8192 ? (long)BK_RENDER_MAX_CELL * rough.n : 8192L);
	char err[1200];
	if (bk_out_dir_check(out, err, sizeof err))
		return cli_fail("render", "--out %s", err);

	item *items = calloc(MAX_ITEMS, sizeof *items);
	if (!items)
		return cli_fail("render", "out of memory");
	int n = 0;
	if (batch)
		rc = read_batch(batch, items, &n);
	else {
		n = 1;
		rc = resolve(&items[0], name, form, form_b, params, term);
	}
	bk_render_geom g = {0};
	bk_lvp *v = NULL;
	char driver[256] = "", devname[400];
	if (!rc) { /* M8: --size 2048 or a 64-row batch runs for many minutes: said before */
		/* samples: 3 channels of the sphere pixels, pi (0.45 cell)^2 in each of 2 x ncols cells;
		 * the sky's integral at each costs about 0.2 ms, each candidate's images about 0.02 ms
		 * (measured at --size 160 and 320, one and two candidates) */
		double ns = 3 * 2 * sc.ncols * 3.14159 * 0.2025 * (double)sc.cell * sc.cell;
		char what[64];
		snprintf(what, sizeof what, "%d candidate%s at %ldx%d pixels", n, n == 1 ? "" : "s", size, 2 * sc.cell);
		cli_estimate(what, ns * (2e-4 + n * 2e-5), 0, "0.2 ms a sample for the sky, 0.02 ms for each candidate");
	}
	if (!rc && bk_render_geometry(&sc, NULL, NULL, &g, err, sizeof err))
		rc = cli_fail("render", "%s", err);
	if (!rc && lvp_dev) {
		int o = bk_lvp_open(&v, driver, sizeof driver, err, sizeof err);
		if (o)
			rc = cli_fail("render", "%s", err);
		snprintf(devname, sizeof devname, "lavapipe: %s", driver);
	} else
		snprintf(devname, sizeof devname, "cpu: the IR, double for the f32 images, BK_F16 for the float16_t ones");
	double secs[2] = {0, 0};
	for (int i = 0; i < n && !rc; i++) {
		rc = render_item(&items[i], v, &g, want_f32, want_f16, secs);
		if (!rc && batch) /* one candidate is one step: no line for it */
			cli_progress("render: candidates", i + 1, n);
	}
	if (!rc)
		rc = write_all(out, items, n, batch != NULL, &sc, &g, devname, prefix);
	if (!rc && v)
		printf("render: %d candidates, %dx%d pixels, %zu samples; %s; glslang %.2f s, lavapipe %.2f s\n", n,
		       g.width, g.height, g.n, driver, secs[0], secs[1]);
	bk_lvp_close(v);
	bk_render_geom_free(&g);
	for (int i = 0; i < n; i++)
		free_item(&items[i]);
	free(items);
	return rc;
}
