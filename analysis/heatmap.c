/*
 * heatmap.c — one error map, five files. The picture (PNG, SVG, PDF) is a figure of
 * plot.h: the cells as an image under axes in the plane's units, a diverging colour
 * bar (signed error); the EXR goes through bk_exr_write; the CSV is plain stdio.
 * Each file is first written whole to its bk_out temporary beside its final name
 * (out.h: the one safe-write module) and synced, and only then are all committed
 * (renamed into place), so a write error never touches the files already at those
 * names.
 */
#include "heatmap.h"
#include "prov.h"
#include "brdf.h" /* BK_VERSION */
#include "exr.h"
#include "out.h" /* bk_csv_field */
#include "plot.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---- the figure ---------------------------------------------------------------------- */

static const char no_data_text[] = "grey: no data";

typedef struct plan {
	const bk_heatmap *h;
	const char *title, *xname, *yname, *vname;
	double vmax; /* max |value| over finite cells; 0 when there are none */
	int has_nan;
	const bk_heatmap_style *st; /* NULL: diverging, numeric axes */
	int line;                   /* one row and no y categories: value against x, a line */
	double *xs;                 /* the line's cell centres (malloc'd; plan_free) */
	bk_plot_series series;
	bk_plot plot;
	bk_plot_heat heat;
} plan;

static void plan_free(plan *p)
{
	free(p->xs);
	p->xs = NULL;
}

static const char *or_default(const char *s, const char *d) { return s ? s : d; }

static int check(const bk_heatmap *h, const char *who, char *err, size_t errlen)
{
	if (!h || !h->value)
		snprintf(err, errlen, "%s: no %s given", who, h ? "values" : "heatmap");
	else if (h->nx < 1 || h->ny < 1 || h->nx > BK_HEATMAP_MAX_CELLS || h->ny > BK_HEATMAP_MAX_CELLS)
		snprintf(err, errlen, "%s: %d x %d cells: expected 1 to %d on each side", who, h->nx,
		         h->ny, BK_HEATMAP_MAX_CELLS);
	else if (!isfinite(h->x1 - h->x0) || h->x0 == h->x1) /* NaN, inf, or too wide */
		snprintf(err, errlen, "%s: x range %g to %g: expected distinct finite edges a finite width apart",
		         who, h->x0, h->x1);
	else if (!isfinite(h->y1 - h->y0) || h->y0 == h->y1)
		snprintf(err, errlen, "%s: y range %g to %g: expected distinct finite edges a finite width apart",
		         who, h->y0, h->y1);
	else
		return 0;
	return -1;
}

static void scan_values(plan *p)
{
	size_t n = (size_t)p->h->nx * p->h->ny;
	p->vmax = 0;
	p->has_nan = 0;
	for (size_t k = 0; k < n; k++) {
		double v = p->h->value[k];
		if (isnan(v))
			p->has_nan = 1;
		else if (isfinite(v) && fabs(v) > p->vmax)
			p->vmax = fabs(v);
	}
}

/* Single column wide (3.5 in), a little shorter than wide; the axes are the
 * plane's edges, the colour range +-max|value|. */
static int make_plan(const bk_heatmap *h, const bk_heatmap_style *st, plan *p, const char *who, char *err,
                     size_t errlen)
{
	if (check(h, who, err, errlen))
		return -1;
	memset(p, 0, sizeof *p);
	p->h = h;
	p->title = or_default(h->title, "");
	p->xname = or_default(h->xname, "x");
	p->yname = or_default(h->yname, "y");
	p->vname = or_default(h->value_name, "value");
	scan_values(p);
	p->st = st;
	p->heat = (bk_plot_heat){h->nx, h->ny, h->value, h->x0, h->x1, h->y0, h->y1, BK_PLOT_DIVERGING,
	                         -p->vmax, p->vmax, p->vname};
	if (st && st->sequential)
		p->heat.map = BK_PLOT_SEQUENTIAL, p->heat.vmin = 0.0, p->heat.vmax = st->top > 0 ? st->top : p->vmax;
	p->plot = (bk_plot){BK_PLOT_SINGLE_W, 2.9, h->title && *h->title ? p->title : NULL, p->has_nan ? no_data_text : NULL,
	                    NULL, {p->xname, 0, h->x0, h->x1, 0, 0, NULL}, {p->yname, 0, h->y0, h->y1, 0, 0, NULL}, NULL, 0,
	                    &p->heat};
	if (st && st->xcat)
		p->plot.x.ncat = h->nx, p->plot.x.cat = st->xcat;
	if (st && st->ycat)
		p->plot.y.ncat = h->ny, p->plot.y.cat = st->ycat;
	/* a plane one cell high is a 1-input target (f over LoH): a colour band under a
	 * meaningless y axis ("-") hides what a line shows, so it is value against x */
	p->line = h->ny == 1 && !(st && st->ycat);
	if (p->line) {
		if (!(p->xs = malloc(sizeof *p->xs * (size_t)h->nx))) {
			snprintf(err, errlen, "%s: out of memory", who);
			return -1;
		}
		for (int i = 0; i < h->nx; i++)
			p->xs[i] = h->x0 + (i + 0.5) * (h->x1 - h->x0) / h->nx;
		p->series = (bk_plot_series){NULL, BK_PLOT_LINE, BK_PLOT_CIRCLE, 0, 0x2166ac, h->nx, p->xs, h->value,
		                             NULL, NULL, NULL};
		p->plot.heat = NULL;
		p->plot.series = &p->series;
		p->plot.nseries = 1;
		p->plot.y = (bk_plot_axis){p->vname, 0, 0, 0, 0, 0, NULL};
		bk_plot_axis_fit(&p->plot.y, h->value, h->nx);
		if (p->heat.map == BK_PLOT_DIVERGING && p->vmax > 0) {
			/* signed error: symmetric about zero, as the colour scale would be */
			bk_plot_axis sym = {NULL, 0, 0, 0, 0, 0, NULL};
			double ends[2] = {-p->vmax, p->vmax};
			bk_plot_axis_fit(&sym, ends, 2);
			double t = fmax(-sym.lo, sym.hi);
			p->plot.y.lo = -t, p->plot.y.hi = t;
		}
	}
	return 0;
}

int bk_heatmap_figure(const bk_heatmap *h, const bk_heatmap_style *st, bk_heatmap_figure_info *out, char *err,
                      size_t errlen)
{
	plan p;
	if (err && errlen)
		err[0] = '\0';
	if (make_plan(h, st, &p, "heatmap", err, errlen))
		return -1;
	*out = (bk_heatmap_figure_info){p.line ? BK_HEATMAP_LINE : BK_HEATMAP_MAP, p.plot.x.label, p.plot.y.label,
	                                p.plot.heat != NULL, p.plot.y.lo, p.plot.y.hi};
	plan_free(&p);
	return 0;
}

int bk_heatmap_png_layout(const bk_heatmap *h, bk_heatmap_layout *out, char *err, size_t errlen)
{
	plan p;
	if (err && errlen)
		err[0] = '\0';
	if (make_plan(h, NULL, &p, "heatmap", err, errlen))
		return -1;
	double a[4], b[4], k = BK_PLOT_DPI / 72.0;
	bk_plot_areas(&p.plot, a, b);
	plan_free(&p);
	/* pixels whose centres lie inside each rectangle */
	int ax0 = (int)ceil(a[0] * k - 0.5), ay0 = (int)ceil(a[1] * k - 0.5);
	int bx0 = (int)ceil(b[0] * k - 0.5), by0 = (int)ceil(b[1] * k - 0.5);
	*out = (bk_heatmap_layout){(int)lround(p.plot.width_in * BK_PLOT_DPI), (int)lround(p.plot.height_in * BK_PLOT_DPI),
	                           ax0, ay0, (int)ceil(a[2] * k - 0.5) - ax0, (int)ceil(a[3] * k - 0.5) - ay0,
	                           bx0, by0, (int)ceil(b[2] * k - 0.5) - bx0, (int)ceil(b[3] * k - 0.5) - by0};
	return 0;
}

/* ---- texts shared by the files ------------------------------------------------- */

/* A malloc'd formatted string, or NULL when memory runs out. */
__attribute__((format(printf, 1, 2)))
static char *xprintf(const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	int n = vsnprintf(NULL, 0, fmt, ap);
	va_end(ap);
	char *s = n < 0 ? NULL : malloc((size_t)n + 1);
	if (s) {
		va_start(ap, fmt);
		vsnprintf(s, (size_t)n + 1, fmt, ap);
		va_end(ap);
	}
	return s;
}

/* "x = LoH: 40 cells between edges x0 = 0 and x1 = 1, cell i centred at
 * x0 + (i + 0.5)(x1 - x0)/nx" — the cell-centre rule, once, for every file. */
static char *axis_text(const char *axis, const char *name, int n, double a, double b)
{
	const char *i = axis[0] == 'x' ? "i" : "j";
	return xprintf("%s = %s: %d cells between edges %s0 = %.9g and %s1 = %.9g, cell %s centred at "
	               "%s0 + (%s + 0.5)(%s1 - %s0)/n%s", axis, name, n, axis, a, axis, b, i, axis, i,
	               axis, axis, axis);
}

static const char origin_text[] =
	"bottom: y0 at the bottom as in a plot; the last scanline (bottom as displayed) holds "
	"cell row j = 0 (nearest y0), scanline 0 holds j = ny - 1; column 0 holds i = 0 (nearest x0)";

/* A column name from a label: each run of characters outside [A-Za-z0-9_] becomes
 * one '_', none at either end: "r (perceptual roughness)" -> "r_perceptual_roughness",
 * "theta (deg)" -> "theta_deg"; an empty result takes the fallback. */
static void column_name(const char *label, const char *fallback, char *out, size_t len)
{
	size_t n = 0;
	int gap = 0;
	for (const char *s = label; *s && n + 2 < len; s++) {
		char ch = *s;
		if (!((ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') || ch == '_')) {
			gap = n > 0;
			continue;
		}
		if (gap)
			out[n++] = '_';
		gap = 0;
		out[n++] = ch;
	}
	out[n] = '\0';
	if (n == 0)
		snprintf(out, len, "%s", fallback);
}

enum { COL_LEN = 120 };

/* x, y and value columns; a name equal to an earlier one gets "_2", "_3" added. */
static void column_names(const plan *p, char col[3][COL_LEN + 8])
{
	column_name(p->xname, "x", col[0], COL_LEN);
	column_name(p->yname, "y", col[1], COL_LEN);
	column_name(p->vname, "value", col[2], COL_LEN);
	for (int k = 1; k < 3; k++)
		for (int m = 0; m < k; m++)
			if (strcmp(col[k], col[m]) == 0) {
				snprintf(col[k] + strlen(col[k]), 8, "_%d", k + 1);
				m = -1; /* compare again from the first */
			}
}

/* "# " + lead + text, each line of text its own comment line. */
static void comment(FILE *f, const char *lead, const char *text)
{
	fprintf(f, "# %s", lead);
	for (; *text; text++) {
		if (*text == '\n')
			fputs("\n# ", f);
		else if (*text != '\r')
			fputc(*text, f);
	}
	fputc('\n', f);
}

/* ---- the five files --------------------------------------------------------------- */

/* A file written whole under its bk_out temporary (o.tmp) before it is committed to final. */
typedef struct staged {
	char final[4096];
	bk_out o;
	int live; /* o is open: its temporary is ours to commit or remove */
} staged;

static int fail_errno(char *err, size_t errlen, const char *path, const char *what, int e)
{
	char shown[1024]; /* the path where the file goes, not its build tree's (out.h) */
	snprintf(err, errlen, "%s: %s: %s", bk_out_shown(path, shown, sizeof shown), what, bk_out_errtext(e));
	return -1;
}

/* Creates the temporary (bk_out_open); the EXR's is only a name for bk_exr_write
 * to rename its own file onto, which the commit then renames into place. */
static int stage_open(staged *s, char *err, size_t errlen)
{
	if (bk_out_open(&s->o, s->final, err, errlen))
		return -1;
	s->live = 1;
	return 0;
}

/* The file's text flushed and synced, so that a write error comes before any rename. */
static int stage_close(staged *s, char *err, size_t errlen)
{
	int bad = fflush(s->o.f) != 0 || ferror(s->o.f) || fsync(fileno(s->o.f)) != 0;
	return bad ? fail_errno(err, errlen, s->final, "write failed", errno) : 0;
}

enum { NFILES = 5 }; /* EXR, PNG, CSV, SVG, PDF */

static void discard(staged s[NFILES])
{
	for (int k = 0; k < NFILES; k++) {
		if (s[k].live)
			bk_out_abort(&s[k].o);
		s[k].live = 0;
	}
}

/* Messages from bk_exr_write name the temporary (as given, or as out.h shows a
 * path inside a build tree); the caller asked for final. */
static void restate(char *err, size_t errlen, const char *tmp, const char *final)
{
	char tmp_shown[1024], final_shown[1024];
	if (!err || errlen == 0)
		return;
	size_t n = strlen(tmp);
	if (strncmp(err, tmp, n) != 0) { /* bk_out's own messages show the path */
		tmp = bk_out_shown(tmp, tmp_shown, sizeof tmp_shown);
		final = bk_out_shown(final, final_shown, sizeof final_shown);
		n = strlen(tmp);
		if (strncmp(err, tmp, n) != 0)
			return;
	}
	char *rest = xprintf("%s%s", final, err + n);
	if (rest)
		snprintf(err, errlen, "%s", rest);
	free(rest);
}

static int out_of_memory(char *err, size_t errlen, const char *path)
{
	snprintf(err, errlen, "%s: out of memory", path);
	return -1;
}

/* The picture in one format; the description (PNG tEXt, PDF subject, SVG comment)
 * states the scale and the conventions. */
static int write_figure(plan *p, staged *s, bk_plot_format fmt, char *err, size_t errlen)
{
	int seq = p->heat.map == BK_PLOT_SEQUENTIAL;
	char *desc = p->line ? xprintf("%s against x = %s (a line: one cell high, no y); %s", p->vname, p->xname,
	                               or_default(p->h->conventions, "")) : xprintf("%s: %s, colour scale %.4g to %.4g, grey = no data; x = %s, y = %s, y0 at the bottom; %s",
	                     p->vname, seq ? "dark (low) to light (high)" : "blue < 0 < red", p->heat.vmin, p->heat.vmax,
	                     p->xname, p->yname, or_default(p->h->conventions, ""));
	if (!desc)
		return out_of_memory(err, errlen, s->final);
	p->plot.provenance = desc;
	int e = 0, rc = bk_plot_write(&p->plot, fmt, s->o.f);
	if (rc)
		e = errno;
	p->plot.provenance = NULL;
	free(desc);
	if (rc)
		return ferror(s->o.f) ? fail_errno(err, errlen, s->final, "write failed", e ? e : EIO)
		                    : (snprintf(err, errlen, "%s: drawing the figure failed (cairo)", s->final), -1);
	return stage_close(s, err, errlen);
}

static int write_csv(const plan *p, staged *s, char *err, size_t errlen)
{
	const bk_heatmap *h = p->h;
	char col[3][COL_LEN + 8];
	column_names(p, col);
	int xc = p->st && p->st->xcat, yc = p->st && p->st->ycat;
	char *ax = xc ? xprintf("x = %s: one of %d sampled values, a cell each", p->xname, h->nx)
	              : axis_text("x", p->xname, h->nx, h->x0, h->x1);
	char *ay = yc ? xprintf("y = %s: one of %d sampled values, a cell each", p->yname, h->ny)
	              : axis_text("y", p->yname, h->ny, h->y0, h->y1);
	if (!ax || !ay) {
		free(ax);
		free(ay);
		return out_of_memory(err, errlen, s->final);
	}
	FILE *f = s->o.f;
	char lead[COL_LEN + 40];
	bk_prov_title(f, "heatmap: %s", p->title);
	bk_prov_command(f, bk_out_command());
	snprintf(lead, sizeof lead, "column %s: ", col[0]);
	comment(f, lead, ax);
	snprintf(lead, sizeof lead, "column %s: ", col[1]);
	comment(f, lead, ay);
	snprintf(lead, sizeof lead, "column %s: %s", col[2], p->heat.map == BK_PLOT_DIVERGING ? "signed " : "");
	comment(f, lead, p->vname);
	comment(f, "an empty value is no data (NaN); one row per cell, x varies fastest", "");
	comment(f, "conventions: ", or_default(h->conventions, ""));
	fprintf(f, "%s,%s,%s\n", col[0], col[1], col[2]);
	double dx = (h->x1 - h->x0) / h->nx, dy = (h->y1 - h->y0) / h->ny;
	for (int j = 0; j < h->ny; j++)
		for (int i = 0; i < h->nx; i++) {
			double v = h->value[(size_t)j * h->nx + i];
			if (p->st && p->st->xcat) /* a category's label (e.g. its sample value), quoted as needed */
				bk_csv_field(f, p->st->xcat[i]), fputc(',', f);
			else
				fprintf(f, "%.9g,", h->x0 + (i + 0.5) * dx);
			if (p->st && p->st->ycat)
				bk_csv_field(f, p->st->ycat[j]), fputc(',', f);
			else
				fprintf(f, "%.9g,", h->y0 + (j + 0.5) * dy);
			if (isnan(v))
				fputc('\n', f);
			else
				fprintf(f, "%.9g\n", v);
		}
	free(ax);
	free(ay);
	return stage_close(s, err, errlen);
}

static int write_exr(const plan *p, staged *s, char *err, size_t errlen)
{
	const bk_heatmap *h = p->h;
	float *rows = malloc((size_t)h->nx * h->ny * sizeof *rows);
	char *ax = axis_text("x", p->xname, h->nx, h->x0, h->x1);
	char *ay = axis_text("y", p->yname, h->ny, h->y0, h->y1);
	char *axes = ax && ay ? xprintf("%s; %s; x, y and the ranges are cell edges", ax, ay) : NULL;
	char *value = xprintf("Y = %s: signed linear float, not a colour; NaN = no data", p->vname);
	int rc = -1;
	if (!rows || !axes || !value) {
		rc = out_of_memory(err, errlen, s->final);
	} else {
		for (int y = 0; y < h->ny; y++) /* file row y holds cell row j = ny - 1 - y */
			for (int i = 0; i < h->nx; i++)
				rows[(size_t)y * h->nx + i] = (float)h->value[(size_t)(h->ny - 1 - y) * h->nx + i];
		const bk_exr_attr attrs[] = {
			{"brdfkit:version", BK_EXR_ATTR_STRING, BK_VERSION, 0},
			{"brdfkit:title", BK_EXR_ATTR_STRING, p->title, 0},
			{"brdfkit:axes", BK_EXR_ATTR_STRING, axes, 0},
			{"brdfkit:origin", BK_EXR_ATTR_STRING, origin_text, 0},
			{"brdfkit:value", BK_EXR_ATTR_STRING, value, 0},
			{"brdfkit:conventions", BK_EXR_ATTR_STRING, or_default(h->conventions, ""), 0},
		};
		const char *names[1] = {"Y"};
		const float *data[1] = {rows};
		rc = bk_exr_write(s->o.tmp, h->nx, h->ny, 1, names, data, 0, attrs,
		                  (int)(sizeof attrs / sizeof attrs[0]), err, errlen);
		if (rc)
			restate(err, errlen, s->o.tmp, s->final);
	}
	free(rows);
	free(ax);
	free(ay);
	free(axes);
	free(value);
	return rc;
}

/* Renames the complete temporaries into place. A failure after the first
 * rename removes all final names (ours and any older ones not yet replaced):
 * a set of the stem is whole or absent, never a mix of two calls. */
static int place_all(staged s[NFILES], char *err, size_t errlen)
{
	int k = 0;
	for (; k < NFILES; k++) {
		s[k].live = 0; /* a commit puts its temporary in place or removes it */
		if (bk_out_commit(&s[k].o, err, errlen) != 0)
			break;
	}
	if (k == NFILES)
		return 0;
	for (int m = 0; k > 0 && m < NFILES; m++)
		unlink(s[m].final);
	discard(s);
	return -1;
}

int bk_heatmap_write(const bk_heatmap *h, const char *dir, const char *stem, char *err, size_t errlen)
{
	return bk_heatmap_write_styled(h, NULL, dir, stem, err, errlen);
}

int bk_heatmap_write_styled(const bk_heatmap *h, const bk_heatmap_style *st, const char *dir, const char *stem,
                            char *err, size_t errlen)
{
	static const char *const ext[NFILES] = {".exr", ".png", ".csv", ".svg", ".pdf"};
	if (err && errlen)
		err[0] = '\0';
	if (!dir || !*dir || !stem || !*stem || strchr(stem, '/')) {
		snprintf(err, errlen, "%s/%s: expected a directory and a file stem without '/'",
		         dir ? dir : "(null)", stem ? stem : "(null)");
		return -1;
	}
	char who[4090]; /* DIR/stem; + ".exr" still fits staged.final */
	const char *sep = dir[strlen(dir) - 1] == '/' ? "" : "/";
	int n = snprintf(who, sizeof who, "%s%s%s", dir, sep, stem);
	if (n < 0 || (size_t)n >= sizeof who) {
		snprintf(err, errlen, "%.64s...: path too long", dir);
		return -1;
	}
	plan p;
	if (make_plan(h, st, &p, who, err, errlen))
		return -1;
	staged s[NFILES];
	memset(s, 0, sizeof s);
	for (int k = 0; k < NFILES; k++)
		if (snprintf(s[k].final, sizeof s[k].final, "%s%s", who, ext[k]) < 0)
			return -1; /* cannot happen: who is at most 4089 bytes */
	int rc = stage_open(&s[0], err, errlen) || stage_open(&s[1], err, errlen) ||
	         stage_open(&s[2], err, errlen) || stage_open(&s[3], err, errlen) ||
	         stage_open(&s[4], err, errlen) || write_figure(&p, &s[1], BK_PLOT_PNG, err, errlen) ||
	         write_csv(&p, &s[2], err, errlen) || write_figure(&p, &s[3], BK_PLOT_SVG, err, errlen) ||
	         write_figure(&p, &s[4], BK_PLOT_PDF, err, errlen) || write_exr(&p, &s[0], err, errlen)
	             ? -1 : place_all(s, err, errlen);
	if (rc)
		discard(s);
	plan_free(&p);
	return rc;
}
