/*
 * cmd_gpucost.c — brdfkit gpucost: forms compiled to AMD machine code by Mesa
 * RADV's null device, one CSV row per form and chip, net of a load/store
 * baseline. The compiling and counting is analysis/gpucost.c's; this file
 * turns arguments into jobs and jobs into CSV.
 */
#include "catalog.h"
#include "prov.h"
#include "cli.h"
#include "cmd.h"
#include "form_check.h"
#include "frontcsv.h"
#include "member.h"
#include "gpucost.h"
#include "out.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define GC_MAX_ROWS 32 /* cli_parse keeps at most 32 positionals */

typedef struct gc_row {
	char name[160];
	const char *text[2]; /* formula text of A (and B for a split-sum entry) */
	double params[BK_MAX_PARAMS];
	int have[BK_MAX_PARAMS];
	int given[BK_MAX_PARAMS]; /* pN= on the command line */
	int typed;           /* typed on the command line: takes p0=... */
	bk_form *f[2];
	char *own[2];        /* text read from a search front, freed with the row */
} gc_row;

/* pN=VALUE after a typed form: 1 when arg is one (stored), 0 when not, 2 after an error. */
static int param_arg(const char *arg, gc_row *last)
{
	int i;
	double v;
	int rc = form_param(arg, &i, &v);
	if (rc != 1)
		return rc;
	if (!last || !last->typed) {
		return cli_bad("'%.100s' must follow a typed form (catalog entries use their published constants)", arg);
	}
	if ((rc = form_param_set(last->name, arg, last->params, last->given, &i)) == 1)
		last->have[i] = 1;
	return rc;
}

/* NAME, NAME:A or NAME:B from the catalog, else the argument as formula
 * text; 2 after an error. A split-sum entry without a part is one shader
 * evaluating A and B. */
static int read_row(const char *arg, int index, gc_row *r)
{
	if (cli_member_split(arg)) { /* FILE.csv:NAME (member.h): a pair whole, as a catalog pair */
		cli_member m;
		int rc = cli_member_load(arg, 1, &m);
		if (rc)
			return rc;
		snprintf(r->name, sizeof r->name, "%.150s", m.fname[0] ? m.fname : m.name);
		r->text[0] = r->own[0] = m.form; /* the member's texts move to r, and their forms */
		r->text[1] = r->own[1] = m.form_b;
		r->f[0] = m.f, r->f[1] = m.f_b;
		memcpy(r->params, m.p, sizeof r->params);
		for (int j = 0; j < m.np; j++)
			r->have[j] = 1;
		return 0;
	}
	char name[128];
	const char *colon = strchr(arg, ':');
	size_t len = colon ? (size_t)(colon - arg) : strlen(arg);
	const bk_catalog_entry *e = NULL;
	if (len < sizeof name) {
		memcpy(name, arg, len);
		name[len] = '\0';
		e = bk_catalog_find(name);
	}
	if (!e) {
		r->text[0] = arg;
		r->typed = 1;
		snprintf(r->name, sizeof r->name, "form%d", index);
		return 0;
	}
	const char *part = colon ? colon + 1 : "";
	int a = !strcmp(part, "A") || !strcmp(part, "a"), b = !strcmp(part, "B") || !strcmp(part, "b");
	if (colon && (!e->form_b || !(a || b))) {
		return cli_bad("'%s': unknown part '%.20s'", name, part);
	}
	r->text[0] = b ? e->form_b : e->form;
	r->text[1] = !colon ? e->form_b : NULL;
	snprintf(r->name, sizeof r->name, "%.150s", arg);
	for (int i = 0; i < e->nparams; i++) {
		r->params[i] = e->defaults[i];
		r->have[i] = 1;
	}
	return 0;
}

/* Parses a row's form(s) (a member's came parsed): the column of a syntax error; then the shared
 * checks: a value for every parameter used, none given that is unused, and
 * a form with a value somewhere (form_check.h). */
static int parse_row(gc_row *r)
{
	unsigned used = 0;
	int rc;
	for (int p = 0; p < 2 && r->text[p]; p++) {
		bk_form_error fe;
		if (!r->f[p] && !(r->f[p] = bk_form_parse(r->text[p], &fe))) {
			fprintf(stderr, "brdfkit gpucost: %s:1:%d: %s\n", r->typed ? "form" : r->name, fe.column, fe.message);
			return 2;
		}
		used |= bk_form_params(r->f[p]);
	}
	if ((rc = form_check_params("gpucost", r->name, used, r->have, r->typed ? r->given : NULL)))
		return rc;
	for (int p = 0; p < 2 && r->f[p]; p++)
		if ((rc = form_check_finite("gpucost", r->name, r->f[p], r->params)))
			return rc;
	return 0;
}

/* --chips a,b,c into names (pointing into buf); 2 after a usage error. */
static int read_chips(const cli_cmd *cmd, char *buf, const char **chip, int *n)
{
	char err[700];
	return bk_gpucost_chips(buf, chip, BK_GPUCOST_MAX_CHIPS, n, err, sizeof err) ? cli_usage(cmd, "--chips: %s", err)
	                                                                             : 0;
}

static void write_csv(FILE *f, const gc_row *rows, const bk_gpucost_job *jobs, int n, const char *const *chip,
                      int nchips, int fp16, const char *driver)
{
	bk_prov_title(f, "gpucost: AMD machine code from Mesa RADV's null device and its ACO compiler (driver: %s), %s",
	              driver, fp16 ? "fp16 (float16_t arithmetic)" : "fp32");
	bk_prov_command(f, bk_out_command());
	fputs("# every figure is the form's compute shader minus a load/store baseline with the same inputs: "
	      "instructions, vgprs, sgprs, latency and inv_throughput from ACO's statistics (latency and "
	      "throughput are ACO's cycle estimates, dominated by the buffer load in both shaders: use "
	      "differences); transcendental (v_rcp v_exp v_sqrt v_rsq v_log, f32 and f16), fma (float "
	      "multiply-adds, fused or not, packed included), packed (v_pk_*), convert (v_cvt_*) counted in "
	      "the disassembly. AMD only: no mobile GPU compiler runs offline\n", f);
	if (fp16)
		fputs("# fp16: AMD fp16 figures are packed-math opportunities, not a proxy for mediump on mobile "
		      "GPUs; inputs are converted to half on load and results to float on store, in the baseline "
		      "too, but the baseline shares its result's conversion with an input's, so convert counts one "
		      "v_cvt per result; empty fields: the chip has no shaderFloat16\n", f);
	fputs("name,form,chip,gfx,precision,instructions,vgprs,sgprs,latency,inv_throughput,transcendental,fma,"
	      "packed,convert\n", f);
	for (int i = 0; i < n; i++)
		for (int c = 0; c < nchips; c++) {
			const gc_row *r = &rows[i];
			const bk_gpucost_stats *s = &jobs[i].net[c];
			const char *gfx = "";
			char form[4096];
			snprintf(form, sizeof form, "%.2000s%s%.2000s", r->text[0], r->text[1] ? "; " : "",
			         r->text[1] ? r->text[1] : "");
			bk_gpucost_chip(chip[c], &gfx);
			bk_csv_field(f, r->name);
			fputc(',', f);
			bk_csv_field(f, form);
			fprintf(f, ",%s,%s,%s", chip[c], gfx, fp16 ? "fp16" : "fp32");
			if (!jobs[i].ok[c])
				fputs(",,,,,,,,,\n", f);
			else
				fprintf(f, ",%ld,%ld,%ld,%ld,%ld,%ld,%ld,%ld,%ld\n", s->instructions, s->vgprs, s->sgprs,
				        s->latency, s->throughput, s->transcendental, s->fma, s->packed, s->convert);
		}
}

static int output(const char *path, const gc_row *rows, const bk_gpucost_job *jobs, int n,
                  const char *const *chip, int nchips, int fp16, const char *driver)
{
	if (!path) {
		write_csv(stdout, rows, jobs, n, chip, nchips, fp16, driver);
		return fflush(stdout) ? cli_fail("gpucost", "stdout: write failed") : 0;
	}
	bk_out o;
	char err[512];
	if (bk_out_open_file(&o, path, err, sizeof err))
		return cli_fail("gpucost", "%s", err);
	write_csv(o.f, rows, jobs, n, chip, nchips, fp16, driver);
	if (bk_out_commit(&o, err, sizeof err))
		return cli_fail("gpucost", "%s", err);
	return 0;
}


/* ---- --calibrate: the IR's cost weights against ACO ---------------------------------- */

typedef struct cal_row {
	const char *name;
	double simple, complex, insn, fitted;
	double thr;  /* ACO's inverse throughput, net */
} cal_row;

static const cal_row *cal_sorted; /* qsort has no context argument */
static int by_residual(const void *a, const void *b)
{
	const cal_row *x = &cal_sorted[*(const int *)a], *y = &cal_sorted[*(const int *)b];
	double dx = fabs(x->insn - x->fitted), dy = fabs(y->insn - y->fitted);
	return dx < dy ? 1 : dx > dy ? -1 : strcmp(x->name, y->name); /* ties by name: same bytes every run */
}

typedef struct cal_info {
	const char *chip;
	int fp16;
	const char *driver;
	double ws, wc;    /* the fitted weights */
	double ts, tc;    /* the same fit to ACO's inverse throughput (0, 0: collinear) */
	int ncat, nfront, nfiles;
} cal_info;

static void write_calibration(FILE *f, const cal_row *c, const int *order, int n, const cal_info *ci)
{
	const char *chip = ci->chip, *driver = ci->driver;
	int fp16 = ci->fp16;
	double ws = ci->ws, wc = ci->wc;
	double *a = malloc(4 * (size_t)n * sizeof *a);
	if (!a)
		return;
	double *b = a + n, *y = b + n, *fit = y + n, ss = 0;
	for (int i = 0; i < n; i++) {
		a[i] = bk_ops_cost(&(bk_ops){.simple = (int)c[i].simple, .complex = (int)c[i].complex}, BK_COST_SIMPLE,
		                   BK_COST_COMPLEX);
		y[i] = c[i].insn;
		fit[i] = c[i].fitted;
		ss += (c[i].insn - c[i].fitted) * (c[i].insn - c[i].fitted);
	}
	const char *gfx = "";
	bk_gpucost_chip(chip, &gfx);
	char fronts[160] = "";
	if (ci->nfiles)
		snprintf(fronts, sizeof fronts, " and %d members of %d search fronts (their seed_ rows, catalog forms, left out)",
		         ci->nfront, ci->nfiles);
	bk_prov_title(f, "gpucost --calibrate: the IR cost model (brdfkit ops: simple, complex) against ACO's "
	                 "net instruction counts on %s (%s) %s, driver %s; %d forms: the catalog's %d (a split-sum entry: "
	                 "A and B in one shader)%s",
	              chip, gfx, fp16 ? "fp16" : "fp32", driver, n, ci->ncat, fronts);
	bk_prov_command(f, bk_out_command());
	fprintf(f, "# least squares, no intercept: instructions ~ %.4g simple + %.4g complex (rms residual %.3g; "
	           "the ir model's weights are %g and %g)\n",
	        ws, wc, sqrt(ss / n), BK_COST_SIMPLE, BK_COST_COMPLEX);
	fprintf(f, "# Spearman rank correlation with instructions: IR cost %.4f, fitted cost %.4f; rows from the "
	           "worst outlier (|instructions - fitted|) down\n",
	        bk_gpucost_spearman(a, y, n), bk_gpucost_spearman(fit, y, n));
	for (int i = 0; i < n; i++) { /* the throughput fit, for the note below */
		b[i] = c[i].thr;
		fit[i] = ci->ts * c[i].simple + ci->tc * c[i].complex;
	}
	fprintf(f, "# the same fit to ACO's inverse throughput (its cycle estimate, coarse: a few units for a form): "
	           "%.4g simple + %.4g complex; Spearman IR cost %.4f, fitted %.4f\n",
	        ci->ts, ci->tc, bk_gpucost_spearman(a, b, n), bk_gpucost_spearman(fit, b, n));
	const bk_cost_model *cm = NULL;
	char name[80];
	snprintf(name, sizeof name, "aco-%s", chip);
	if (!fp16 && (cm = bk_cost_model_find(name))) {
		for (int i = 0; i < n; i++) /* the recorded weights, ranked the same way */
			b[i] = cm->simple * c[i].simple + cm->complex * c[i].complex;
		fprintf(f, "# the named cost model %s (--cost-model) holds simple %g, complex %g: Spearman %.4f here\n",
		        cm->name, cm->simple, cm->complex, bk_gpucost_spearman(b, y, n));
	}
	fputs("name,simple,complex,ir_cost,instructions,fitted,residual,inv_throughput\n", f);
	for (int k = 0; k < n; k++) {
		const cal_row *r = &c[order[k]];
		fprintf(f, "%s,%g,%g,%g,%g,%.4g,%.4g,%g\n", r->name, r->simple, r->complex, a[order[k]], r->insn, r->fitted,
		        r->insn - r->fitted, r->thr);
	}
	free(a);
}

/* ---- search fronts read back (front.csv of brdfkit search, frontcsv.h) ---------------- */

/* Appends the members of one front.csv to *rows, not its seed_ rows (catalog
 * forms, counted already); 0, or 1 after one line on stderr. */
static int read_front(const char *path, gc_row **rows, int *n, int *cap)
{
	char dir[64], err[700]; /* the front's folder names its rows: two searches both have a search_env_10 */
	bk_frontcsv_dir(path, 1, dir, sizeof dir);
	bk_frontcsv fc;
	if (bk_frontcsv_read(path, BK_FRONTCSV_FORMS, &fc, err, sizeof err))
		return cli_fail("gpucost", "%s", err);
	int rc = 0;
	for (int i = 0; !rc && i < fc.n; i++) {
		bk_frontcsv_row *w = &fc.row[i];
		if (!strncmp(w->name, "seed_", 5))
			continue;
		if (*n == *cap) {
			gc_row *g = realloc(*rows, 2 * (size_t)*cap * sizeof *g);
			if (!g) {
				rc = cli_fail("gpucost", "out of memory");
				break;
			}
			*rows = g;
			*cap *= 2;
		}
		gc_row *g = &(*rows)[(*n)++];
		memset(g, 0, sizeof *g);
		snprintf(g->name, sizeof g->name, "%.60s%s%.90s", dir, *dir ? "/" : "", w->name);
		g->text[0] = g->own[0] = w->form; /* the row's texts move to g */
		g->text[1] = g->own[1] = w->form_b;
		w->form = w->form_b = NULL;
		memcpy(g->params, w->p, sizeof g->params);
		for (int j = 0; j < w->np; j++) /* every one the forms use is given (frontcsv.h) */
			g->have[j] = 1;
	}
	bk_frontcsv_free(&fc);
	return rc;
}

static int calibrate(cli_cmd *cmd, const char *chip, int fp16, const char *out)
{
	int ncat = (int)bk_catalog_count(), n = 0, cap = ncat + 64, rc = 0;
	const char *gfx;
	if (strchr(chip, ',') || bk_gpucost_chip(chip, &gfx))
		return cli_usage(cmd, "--calibrate: --chips must name one known chip, got '%.60s'", chip);
	gc_row *rows = calloc((size_t)cap, sizeof *rows);
	if (!rows)
		return cli_fail("gpucost", "out of memory");
	for (int i = 0; !rc && i < ncat; i++, n++)
		rc = read_row(bk_catalog_at((size_t)i)->name, i + 1, &rows[i]);
	for (int k = 0; !rc && k < cmd->npos; k++)
		rc = read_front(cmd->pos[k], &rows, &n, &cap);
	bk_gpucost_job *jobs = rc ? NULL : calloc((size_t)n, sizeof *jobs);
	cal_row *c = rc ? NULL : calloc((size_t)n, sizeof *c);
	int *order = rc ? NULL : calloc((size_t)n, sizeof *order);
	double *s = rc ? NULL : calloc(3 * (size_t)n, sizeof *s);
	if (!rc && !(jobs && c && order && s))
		rc = cli_fail("gpucost", "out of memory");
	for (int i = 0; !rc && i < n; i++) {
		if ((rc = parse_row(&rows[i])))
			break;
		jobs[i] = (bk_gpucost_job){.form = {rows[i].f[0], rows[i].f[1]}, .params = rows[i].params};
		c[i].name = rows[i].name;
		for (int p = 0; p < 2 && rows[i].f[p]; p++) {
			bk_ops o;
			bk_form_count(rows[i].f[p], &o);
			c[i].simple += o.simple;
			c[i].complex += o.complex;
		}
	}
	char driver[256] = "", err[600];
	if (!rc && (rc = bk_gpucost_run(jobs, n, &chip, 1, fp16, driver, sizeof driver, NULL, err, sizeof err)))
		rc = cli_fail("gpucost", "%s", err);
	/* a job the chip could not compile (fp16 without shaderFloat16) has no
	 * counts: zeros fitted as counts made "rms 0, Spearman 1" of nothing */
	for (int i = 0; !rc && i < n; i++)
		if (!jobs[i].ok[0])
			rc = cli_usage(cmd, "--calibrate: nothing measured: %s has no shaderFloat16, so no fp16 count (calibrate "
			               "fp16 on a chip that has it, or fp32 here)", chip);
	double ws = 0, wc = 0;
	for (int i = 0; !rc && i < n; i++) {
		s[i] = c[i].simple;
		s[n + i] = c[i].complex;
		s[2 * n + i] = c[i].insn = (double)jobs[i].net[0].instructions;
		c[i].thr = (double)jobs[i].net[0].throughput;
	}
	if (!rc && bk_gpucost_fit2(s, s + n, s + 2 * n, n, &ws, &wc))
		rc = cli_fail("gpucost", "--calibrate: simple and complex counts are collinear over these forms");
	if (!rc) {
		for (int i = 0; i < n; i++) {
			c[i].fitted = ws * c[i].simple + wc * c[i].complex;
			order[i] = i;
		}
		cal_sorted = c;
		qsort(order, (size_t)n, sizeof *order, by_residual);
		bk_out o;
		cal_info ci = {chip, fp16, driver, ws, wc, 0, 0, ncat, n - ncat, cmd->npos};
		for (int i = 0; i < n; i++)
			s[2 * n + i] = c[i].thr;
		if (bk_gpucost_fit2(s, s + n, s + 2 * n, n, &ci.ts, &ci.tc))
			ci.ts = ci.tc = 0;
		if (!out) {
			write_calibration(stdout, c, order, n, &ci);
			rc = fflush(stdout) ? cli_fail("gpucost", "stdout: write failed") : 0;
		} else if (bk_out_open_file(&o, out, err, sizeof err))
			rc = cli_fail("gpucost", "%s", err);
		else {
			write_calibration(o.f, c, order, n, &ci);
			rc = bk_out_commit(&o, err, sizeof err) ? cli_fail("gpucost", "%s", err) : 0;
		}
	}
	for (int i = 0; i < n; i++) {
		bk_form_free(rows[i].f[0]);
		bk_form_free(rows[i].f[1]);
		free(rows[i].own[0]);
		free(rows[i].own[1]);
	}
	free(rows);
	free(jobs);
	free(c);
	free(order);
	free(s);
	return rc;
}

static int run(cli_cmd *cmd, gc_row *rows, bk_gpucost_job *jobs, const char *chips, const char *precision,
               const char *out, int cal)
{
	cli_prec prec;
	if (cli_precision(precision, CLI_PREC_BIT(CLI_PREC_SINGLE) | CLI_PREC_BIT(CLI_PREC_HALF), &prec))
		return 2;
	int fp16 = prec == CLI_PREC_HALF; /* the CSV's precision column keeps fp32/fp16 (AMD's words) */
	bk_gpucost_progress(cli_progress, "gpucost: forms on chips");
	if (cal)
		return calibrate(cmd, cli_seen(cmd, "--chips") ? chips : "navi21", fp16, out);
	char chipbuf[1024];
	const char *chip[BK_GPUCOST_MAX_CHIPS];
	int nchips, n = 0;
	snprintf(chipbuf, sizeof chipbuf, "%s", chips);
	if (read_chips(cmd, chipbuf, chip, &nchips))
		return 2;
	for (int i = 0; i < cmd->npos; i++) {
		int rc = param_arg(cmd->pos[i], n ? &rows[n - 1] : NULL);
		if (rc == 2)
			return 2;
		if (rc == 0 && read_row(cmd->pos[i], n + 1, &rows[n]))
			return 2;
		n += rc == 0;
	}
	if (n == 0)
		return cli_usage(cmd, "missing FORM");
	for (int i = 0; i < n; i++) {
		if (parse_row(&rows[i]))
			return 2;
		for (int p = 0; p < 2 && rows[i].f[p]; p++) /* the code it compiles: codegen's warning (M3) */
			form_warn_precision("gpucost", rows[i].name, rows[i].f[p], rows[i].params, fp16 ? BK_F16 : BK_F32);
		jobs[i].form[0] = rows[i].f[0];
		jobs[i].form[1] = rows[i].f[1];
		jobs[i].params = rows[i].params;
	}
	char driver[256] = "", err[600];
	int rc = bk_gpucost_run(jobs, n, chip, nchips, fp16, driver, sizeof driver, NULL, err, sizeof err);
	if (rc)
		return cli_fail("gpucost", "%s", err);
	return output(out, rows, jobs, n, chip, nchips, fp16, driver);
}

/* ---- where the options act (cli.h) ----------------------------------------- */

/* Both modes (forms; --calibrate) compile for the chips of --chips (one chip
 * under --calibrate, checked there), in the arithmetic of --precision, and
 * write one CSV: every option acts in both. */
static const cli_rule rules[] = {
	{"--calibrate", NULL, CLI_EVERYWHERE, 0, NULL, NULL},
	{"--chips", NULL, CLI_EVERYWHERE, 0, NULL, "navi21"},
	{"--precision", NULL, CLI_EVERYWHERE, 0, NULL, "half"},
	{"--out", NULL, CLI_EVERYWHERE, 0, NULL, "o.csv"},
};
static const char *const setups[] = {"NoV", "--calibrate", NULL};
static const cli_table table = {NULL, 0, rules, sizeof rules / sizeof rules[0], setups};

int cmd_gpucost(int argc, char **argv)
{
	const char *chips = BK_GPUCOST_DEFAULT_CHIPS, *precision = "single", *out = NULL;
	int cal = 0;
	cli_opt opts[] = {
		{.name = "--calibrate", .kind = CLI_FLAG, .help = "fit the IR cost weights to ACO's counts over the catalog and the fronts given (one chip, default navi21)", .dest = &cal},
		{.name = "--chips", .kind = CLI_STR, .metavar = "LIST", .help = "RADV chip names, comma-separated (default " BK_GPUCOST_DEFAULT_CHIPS ")", .dest = &chips},
		{.name = "--precision", .kind = CLI_STR, .metavar = "single|half", .help = "float (default) or float16_t arithmetic", .dest = &precision},
		{.name = "--out", .kind = CLI_STR, .metavar = "FILE", .help = "write the CSV there (atomically) instead of stdout", .dest = &out},
	};
	cli_cmd cmd = {"gpucost", "Compiles each form to AMD machine code with Mesa RADV's null device (the ACO\n"
	               "compiler; no GPU needed) for each chip, and counts what it costs net of a\n"
	               "load/store baseline shader: one CSV row per form and chip.",
	               "'FORM'|NAME|FILE.csv:MEMBER [p0=X ...] ... [--chips LIST] [--precision single|half] [--out FILE]\n"
	               "       brdfkit gpucost --calibrate [FRONT.csv ...] [--chips CHIP] [--out FILE]",
	               "NAME is a catalog entry with its published constants (NAME:A, NAME:B for one part\n"
	               "of a split-sum entry; without a part both are evaluated in one shader).\n"
	               "FILE.csv:MEMBER is a member of a front.csv of brdfkit search with its parameters\n"
	               "(MEMBER:A, MEMBER:B for one part of a split-sum member). The form's\n"
	               "GLSL runs in a compute shader that reads its inputs from a storage buffer and\n"
	               "stores the result, compiled in-process by glslang. Columns: name,form,chip,gfx,\n"
	               "precision,instructions,vgprs,sgprs,latency,inv_throughput (ACO's statistics),\n"
	               "transcendental,fma,packed,convert (counted in the disassembly), each net of the\n"
	               "baseline; '# ' lines first state the driver and what the columns mean. half:\n"
	               "float16_t arithmetic (precision column fp16) (packed-math opportunities on AMD, not a proxy for mediump on\n"
	               "mobile GPUs); a chip without shaderFloat16 gets empty fields. Needs\n"
	               "mesa-vulkan-drivers; VK_ICD_FILENAMES is set to RADV's unless already set.\n"
	               "--calibrate: every catalog form and every member of the given search fronts\n"
	               "(front.csv of brdfkit search; its seed_ rows are catalog forms and are left out) on\n"
	               "one chip; least squares of the net instructions on the IR's simple and complex\n"
	               "counts (no intercept), Spearman rank correlations of the IR cost, the fitted cost and\n"
	               "the named model aco-CHIP (--cost-model of ops, compare, search) with them, and one\n"
	               "row per form from the worst outlier down:\n"
	               "name,simple,complex,ir_cost,instructions,fitted,residual,inv_throughput; the same fit\n"
	               "to ACO's inverse throughput is reported in a '# ' line.",
	               opts, 4, GC_MAX_ROWS, 0, {0}};
	int rc = cli_parse_table(&cmd, &table, argc, argv);
	if (rc || (rc = cli_applicable(&cmd, NULL)))
		return rc == 1 ? 0 : rc;
	if (cli_form_positionals(&cmd, 0))
		return 2;
	if ((rc = cli_out_file("gpucost", out))) /* before the compiles, not after */
		return rc;
	/* room for the whole catalog (--calibrate) or the positionals */
	int max = GC_MAX_ROWS > (int)bk_catalog_count() ? GC_MAX_ROWS : (int)bk_catalog_count();
	gc_row *rows = calloc((size_t)max, sizeof *rows);
	bk_gpucost_job *jobs = calloc((size_t)max, sizeof *jobs);
	rc = rows && jobs ? run(&cmd, rows, jobs, chips, precision, out, cal) : cli_fail("gpucost", "out of memory");
	for (int i = 0; rows && i < max; i++) {
		bk_form_free(rows[i].f[0]);
		bk_form_free(rows[i].f[1]);
		free(rows[i].own[0]);
		free(rows[i].own[1]);
	}
	free(rows);
	free(jobs);
	return rc;
}
