/*
 * plot.c — brdfkit's one figure module on cairo (plot.h states the contract). A figure
 * is laid out once in points (the frame, the ticks, the label boxes), then drawn by one
 * function onto whichever cairo surface the format asks for.
 */
#include "plot.h"
#include "out.h"
#include "brdf.h" /* BK_VERSION */
#include "pngio.h"

#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <cairo.h>
#include <errno.h>
#include <fontconfig/fontconfig.h>
#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

/* Cairo's font caches and fontconfig's, emptied at exit once a figure has set a
 * font (set_font registers it; atexit runs it before LeakSanitizer's check, which
 * was registered first). Without it the blocks fontconfig allocates under cairo's
 * toy font API (a few hundred bytes, once per process) are unreachable at exit,
 * and the sanitized build had to suppress them: LeakSanitizer then symbolised
 * every suppressed block's allocation stack to match it, parsing brdfkit's debug
 * information in each process that drew text (`brdfkit stability NoV --out D`,
 * sanitized: 0.23 to 0.56 s with the suppression, 0.07 s with this and none).
 * Safe at exit only: every cairo object this module creates is destroyed
 * before its function returns, and no worker thread outlives its pool. */
static void fonts_release(void)
{
	cairo_debug_reset_static_data();
	FcFini();
}
static void fonts_release_at_exit(void)
{
	atexit(fonts_release);
}
static pthread_once_t fonts_once = PTHREAD_ONCE_INIT;
/* LeakSanitizer (the sanitized build of make test) asks for this by name: so
 * that stderr stays the tool's own, without the table of the suppressions used
 * (tests/lsan.supp's, for Mesa's Vulkan driver under brdfkit gpucost) */
const char *__lsan_default_options(void);
const char *__lsan_default_options(void)
{
	return "print_suppressions=0";
}

/* ---- colour maps ------------------------------------------------------------------- */

/* Sequential: 33 anchors of our own computation (OKLab L = 0.30 + 0.62 t, hue
 * 295 deg - 190 t, chroma 0.13 + 0.04 sin(pi t) reduced in steps of 0.002 until the
 * colour is inside sRGB, then sRGB-encoded and rounded), so lightness rises evenly. */
static const unsigned char seq[33][3] = {
	{53, 22, 102},   {52, 30, 113},   {50, 37, 123},   {46, 45, 132},   {40, 53, 141},
	{31, 62, 149},   {11, 70, 157},   {1, 81, 153},    {2, 90, 149},    {2, 98, 148},
	{1, 105, 149},   {2, 113, 149},   {4, 120, 151},   {4, 127, 152},   {1, 135, 154},
	{8, 142, 154},   {11, 149, 155},  {12, 157, 156},  {11, 164, 155},  {10, 172, 154},
	{10, 180, 152},  {2, 188, 148},   {6, 196, 141},   {46, 202, 133},  {83, 207, 128},
	{110, 211, 123}, {134, 215, 119}, {155, 218, 116}, {174, 222, 115}, {193, 225, 115},
	{210, 228, 117}, {226, 231, 120}, {241, 234, 126},
};

/* Diverging: ColorBrewer RdBu, 11 classes (Brewer, colorbrewer2.org), reversed so
 * that blue is negative; 0.5 is its white middle. */
static const unsigned char rdbu[11][3] = {
	{0x05, 0x30, 0x61}, {0x21, 0x66, 0xac}, {0x43, 0x93, 0xc3}, {0x92, 0xc5, 0xde},
	{0xd1, 0xe5, 0xf0}, {0xf7, 0xf7, 0xf7}, {0xfd, 0xdb, 0xc7}, {0xf4, 0xa5, 0x82},
	{0xd6, 0x60, 0x4d}, {0xb2, 0x18, 0x2b}, {0x67, 0x00, 0x1f},
};

void bk_plot_colour(int map, double t, unsigned char rgb[3])
{
	const unsigned char(*tab)[3] = map == BK_PLOT_DIVERGING ? rdbu : seq;
	int n = map == BK_PLOT_DIVERGING ? 11 : 33;
	double u = (isnan(t) ? 0.0 : fmax(0.0, fmin(1.0, t))) * (n - 1);
	int k = u >= n - 1 ? n - 2 : (int)u;
	double f = u - k;
	for (int c = 0; c < 3; c++)
		rgb[c] = (unsigned char)floor(tab[k][c] + (tab[k + 1][c] - tab[k][c]) * f + 0.5);
}

/* ---- axes ------------------------------------------------------------------------ */

/* The smallest of 1, 2, 5 x 10^k at least raw. */
static double nice_step(double raw)
{
	double mag = bk_dpow(10.0, floor(bk_dlog10(raw))), r = raw / mag;
	return (r <= 1.0 ? 1.0 : r <= 2.0 ? 2.0 : r <= 5.0 ? 5.0 : 10.0) * mag;
}

/* The colour bar's value range: -m..m (m = max |vmin|, |vmax|) on a diverging map,
 * vmin..vmax on a sequential one; a range of nothing is widened to one unit. */
static void bar_range(const bk_plot_heat *h, double *a, double *b)
{
	double m = fmax(fabs(h->vmin), fabs(h->vmax));
	*a = h->map == BK_PLOT_DIVERGING ? -m : h->vmin;
	*b = h->map == BK_PLOT_DIVERGING ? m : h->vmax;
	if (!(*b > *a))
		*b = *a + 1.0;
}

enum { BAR_TICKS = 4 }; /* intervals asked of the colour bar's ticks */

/* The rounded range of v alone (see bk_plot_axis_fit); 0 when v has no value to show. */
static int axis_range(const bk_plot_axis *a, const double *v, int n, double *rlo, double *rhi)
{
	double lo = INFINITY, hi = -INFINITY;
	for (int i = 0; i < n; i++) {
		if (!isfinite(v[i]) || (a->log && v[i] <= 0.0))
			continue;
		lo = fmin(lo, v[i]);
		hi = fmax(hi, v[i]);
	}
	if (!(hi >= lo))
		return 0;
	if (a->log) {
		double d0 = floor(bk_dlog10(lo)), d1 = ceil(bk_dlog10(hi));
		if (d1 <= d0)
			d1 = d0 + 1.0;
		*rlo = pow(10.0, d0);
		*rhi = pow(10.0, d1);
		return 1;
	}
	lo = fmin(lo, 0.0); /* costs and times start at zero: ratios read honestly */
	if (hi <= lo)
		hi = lo + 1.0;
	hi += 0.02 * (hi - lo); /* a marker at the largest value stays clear of the frame */
	double s = nice_step((hi - lo) / 6.0);
	*rlo = floor(lo / s) * s;
	*rhi = ceil(hi / s) * s;
	if (*rhi <= *rlo)
		*rhi = *rlo + s;
	return 1;
}

void bk_plot_axis_grow(bk_plot_axis *a, const double *v, int n)
{
	double lo, hi;
	int had = a->hi > a->lo;
	if (!axis_range(a, v, n, &lo, &hi))
		return; /* nothing to show: the range stays as it was */
	a->lo = had ? fmin(a->lo, lo) : lo;
	a->hi = had ? fmax(a->hi, hi) : hi;
}

void bk_plot_axis_fit(bk_plot_axis *a, const double *v, int n)
{
	a->lo = a->hi = 0.0;
	bk_plot_axis_grow(a, v, n);
	if (!(a->hi > a->lo))
		a->lo = a->log ? 1e-3 : 0.0, a->hi = 1.0;
}

enum { MAX_TICKS = 24 };

typedef struct ticks {
	int n;
	double v[MAX_TICKS];
	int major[MAX_TICKS]; /* labelled */
	char text[MAX_TICKS][BK_PLOT_TICK_LEN];
} ticks;

/* The 1-2-5 step just below s (s itself one of them). */
static double smaller_step(double s)
{
	double mag = bk_dpow(10.0, floor(bk_dlog10(s) + 1e-9)), r = s / mag;
	return r > 4.5 ? 2.0 * mag : r > 1.5 ? mag : 0.5 * mag;
}

/* Labels v[0..n) with the fewest significant digits (1..17) that make every label
 * read back within a thousandth of step of its value, so two ticks never share a label
 * ("%g"'s six digits would turn 1.0000001 and 1.0000002 into one "1"). */
static void label_ticks(ticks *t, int from, double step)
{
	for (int prec = 1; prec <= 17; prec++) {
		int ok = 1;
		for (int i = from; i < t->n; i++) {
			snprintf(t->text[i], BK_PLOT_TICK_LEN, "%.*g", prec, t->v[i]);
			ok = ok && fabs(strtod(t->text[i], NULL) - t->v[i]) <= 1e-3 * step;
		}
		if (ok)
			return;
	}
}

/* Linear ticks: multiples of a 1-2-5 step for about `want` intervals, the step made
 * smaller until at least BK_PLOT_MIN_TICKS of them lie in [lo, hi] (a colour bar of
 * -4e-4..4e-4 at want 4 would otherwise get the step 5e-4 and the one tick "0"). */
static void linear_ticks(double lo, double hi, int want, ticks *t)
{
	double s = nice_step((hi - lo) / want);
	while (floor(hi / s + 1e-9) - ceil(lo / s - 1e-9) + 1 < BK_PLOT_MIN_TICKS)
		s = smaller_step(s);
	while (floor(hi / s + 1e-9) - ceil(lo / s - 1e-9) + 1 > MAX_TICKS) /* rounding at the extremes */
		s = nice_step(s * 1.01);
	t->n = 0;
	for (double k = ceil(lo / s - 1e-9); t->n < MAX_TICKS && k * s <= hi + 1e-9 * s; k++) {
		t->v[t->n] = fabs(k * s) < 1e-9 * s ? 0.0 : k * s;
		t->major[t->n++] = 1;
	}
	label_ticks(t, 0, s);
}

/* Log ticks in [lo, hi]: every decade labelled (every other one when there are many),
 * 2..9 unlabelled between when there are few; when fewer than BK_PLOT_MIN_TICKS
 * decades fall in the range, 2 and 5 (then every 1..9) times a decade are labelled
 * too, and within less than a decade's factor of 3 the labels are linear ones. */
static void log_ticks(const bk_plot_axis *a, ticks *t)
{
	int d0 = (int)floor(bk_dlog10(a->lo) + 1e-9), d1 = (int)ceil(bk_dlog10(a->hi) - 1e-9);
	double lo = a->lo * (1 - 1e-9), hi = a->hi * (1 + 1e-9);
	int every = d1 - d0 > 8 ? 2 : 1, minor = d1 - d0 <= 5, decades = 0;
	for (int d = d0; d <= d1; d++)
		decades += bk_dpow(10.0, d) >= lo && bk_dpow(10.0, d) <= hi;
	int label_125 = decades < BK_PLOT_MIN_TICKS, label_all = 0;
	if (label_125) { /* would 1, 2, 5 x 10^d give enough? */
		int n = 0;
		for (int d = d0; d <= d1; d++)
			for (int m = 1; m <= 5; m += m == 1 ? 1 : 3)
				n += m * bk_dpow(10.0, d) >= lo && m * bk_dpow(10.0, d) <= hi;
		label_all = n < BK_PLOT_MIN_TICKS;
	}
	if (label_all && a->hi < 3.0 * a->lo && !a->zero_at_lo) {
		linear_ticks(a->lo, a->hi, 4, t);
		return;
	}
	t->n = 0;
	for (int d = d0; d <= d1 && t->n < MAX_TICKS; d++)
		for (int m = 1; m <= 9 && t->n < MAX_TICKS; m++) {
			double v = m * bk_dpow(10.0, d);
			int at_zero = a->zero_at_lo && d == d0;
			if (v < lo || v > hi || (m > 1 && (at_zero || !(minor || label_125))))
				continue;
			int lab = m == 1 ? (d - d0) % every == 0 || label_125 : label_all || (label_125 && (m == 2 || m == 5));
			t->v[t->n] = v;
			t->major[t->n] = lab;
			if (at_zero && m == 1)
				snprintf(t->text[t->n], BK_PLOT_TICK_LEN, "0");
			else if (!lab)
				t->text[t->n][0] = '\0';
			else if (d >= -3 && d <= 3)
				snprintf(t->text[t->n], BK_PLOT_TICK_LEN, "%g", v);
			else if (m == 1)
				snprintf(t->text[t->n], BK_PLOT_TICK_LEN, "1e%d", d);
			else
				snprintf(t->text[t->n], BK_PLOT_TICK_LEN, "%de%d", m, d);
			t->n++;
		}
}

static void make_ticks(const bk_plot_axis *a, int want, ticks *t)
{
	t->n = 0;
	if (a->ncat > 0) { /* categories: one labelled tick at each cell's centre */
		for (int k = 0; k < a->ncat && k < MAX_TICKS; k++) {
			t->v[t->n] = a->lo + (k + 0.5) * (a->hi - a->lo) / a->ncat;
			t->major[t->n] = 1;
			snprintf(t->text[t->n++], BK_PLOT_TICK_LEN, "%s", a->cat[k] ? a->cat[k] : "");
		}
		return;
	}
	if (!a->log) /* a reversed axis (lo > hi) takes the same ticks */
		linear_ticks(fmin(a->lo, a->hi), fmax(a->lo, a->hi), want, t);
	else
		log_ticks(a, t);
}

int bk_plot_ticks(const bk_plot_axis *a, int want, double *v, char (*text)[BK_PLOT_TICK_LEN], int max)
{
	ticks t;
	make_ticks(a, want, &t);
	int k = 0;
	for (int i = 0; i < t.n && k < max; i++)
		if (t.major[i]) {
			v[k] = t.v[i];
			memcpy(text[k++], t.text[i], BK_PLOT_TICK_LEN);
		}
	return k;
}

int bk_plot_bar_ticks(const bk_plot_heat *h, double *v, char (*text)[BK_PLOT_TICK_LEN], int max)
{
	double a, b;
	bar_range(h, &a, &b);
	bk_plot_axis ax = {NULL, 0, a, b, 0, 0, NULL};
	return bk_plot_ticks(&ax, BAR_TICKS, v, text, max);
}

/* ---- layout ------------------------------------------------------------------------ */

#define FS_TITLE 9.0
#define FS_AXIS 8.0
#define FS_TICK BK_PLOT_TICK_PT
#define FS_LABEL 6.0
#define FS_NOTE 6.0
#define MARK_R 2.4 /* marker radius, pt */
#define NOTE_GAP 2.0 /* between footnote lines, pt */

typedef struct layout {
	double W, H;                 /* page, pt */
	double L, R, T, B;           /* plot area edges, pt (T < B: y grows down) */
	double xtick_h;              /* height of the x tick labels (turned: their widest) */
	int xturn;                   /* x tick labels turned upright: too wide side by side */
	double legend_x, bar_x;      /* legend and colour bar columns (0: none) */
	int legend_top;              /* narrow figures: the legend in rows under the title */
	double legend_y;             /* its first row's baseline */
	int note_lines;              /* footnote lines room was made for (>= 1) */
} layout;

static void set_font(cairo_t *cr, double size, int bold)
{
	pthread_once(&fonts_once, fonts_release_at_exit);
	cairo_select_font_face(cr, BK_PLOT_FONT, CAIRO_FONT_SLANT_NORMAL,
	                       bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
	cairo_set_font_size(cr, size);
	/* unhinted metrics and outlines: the same advance widths on every surface */
	cairo_font_options_t *o = cairo_font_options_create();
	cairo_font_options_set_hint_metrics(o, CAIRO_HINT_METRICS_OFF);
	cairo_font_options_set_hint_style(o, CAIRO_HINT_STYLE_NONE);
	cairo_font_options_set_antialias(o, CAIRO_ANTIALIAS_GRAY);
	cairo_set_font_options(cr, o);
	cairo_font_options_destroy(o);
}

/* Text as cairo may take it: valid UTF-8, '?' for any other byte (cairo refuses
 * a string that is not UTF-8). Writes at most len - 1 bytes. */
static void clean_utf8(const char *s, char *out, size_t len)
{
	size_t o = 0;
	const unsigned char *p = (const unsigned char *)s;
	while (*p && o + 5 < len) {
		int n = *p < 0x80 ? 1 : (*p & 0xe0) == 0xc0 && *p >= 0xc2 ? 2 : (*p & 0xf0) == 0xe0 ? 3
		      : (*p & 0xf8) == 0xf0 && *p <= 0xf4 ? 4 : 0;
		for (int k = 1; k < n; k++)
			if ((p[k] & 0xc0) != 0x80)
				n = 0;
		if (n == 3 && ((p[0] == 0xe0 && p[1] < 0xa0) || (p[0] == 0xed && p[1] >= 0xa0)))
			n = 0; /* overlong, surrogate */
		if (n == 4 && ((p[0] == 0xf0 && p[1] < 0x90) || (p[0] == 0xf4 && p[1] >= 0x90)))
			n = 0;
		if (n == 0 || (n == 1 && *p < 0x20)) {
			out[o++] = '?';
			p++;
			continue;
		}
		memcpy(out + o, p, (size_t)n);
		o += (size_t)n;
		p += n;
	}
	out[o] = '\0';
}

static double text_w(cairo_t *cr, const char *s)
{
	char buf[1024];
	cairo_text_extents_t e;
	clean_utf8(s, buf, sizeof buf);
	cairo_text_extents(cr, buf, &e);
	return e.x_advance;
}

/* A context on a 1x1 image for measuring text before any surface exists. */
static cairo_t *measure_ctx(cairo_surface_t **s)
{
	*s = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, 1, 1);
	return cairo_create(*s);
}

static double legend_width(cairo_t *cr, const bk_plot *p)
{
	double w = 0.0;
	set_font(cr, FS_TICK, 0);
	for (int s = 0; s < p->nseries; s++)
		if (p->series[s].name)
			w = fmax(w, text_w(cr, p->series[s].name) + 16.0);
	return w;
}

enum { LEGEND_MAX = 32 };

/* The legend in rows across the page from x = 6 pt: each named series' x offset and
 * row (at most LEGEND_MAX entries). Returns the number of rows. */
static int legend_rows(cairo_t *cr, const bk_plot *p, double W, double *x, int *row)
{
	int rows = 0;
	double at = 6.0;
	set_font(cr, FS_TICK, 0);
	for (int s = 0; s < p->nseries && s < LEGEND_MAX; s++) {
		if (!p->series[s].name)
			continue;
		double w = text_w(cr, p->series[s].name) + 22.0;
		if (rows == 0 || at + w > W - 6.0)
			rows++, at = 6.0;
		x[s] = at;
		row[s] = rows - 1;
		at += w;
	}
	return rows;
}

static void make_layout(cairo_t *cr, const bk_plot *p, layout *lo, int note_lines)
{
	lo->W = p->width_in * 72.0;
	lo->H = p->height_in * 72.0;
	ticks t;
	make_ticks(&p->y, 5, &t);
	set_font(cr, FS_TICK, 0);
	double tw = 0.0;
	for (int i = 0; i < t.n; i++)
		if (t.major[i])
			tw = fmax(tw, text_w(cr, t.text[i]));
	lo->L = 6.0 + FS_AXIS + 4.0 + tw + 4.0;
	lo->T = p->title ? 6.0 + FS_TITLE + 6.0 : 8.0;
	lo->B = lo->H - (4.0 + FS_TICK + 4.0 + FS_AXIS + 4.0 + FS_NOTE + 6.0);
	lo->note_lines = note_lines > 1 ? note_lines : 1;
	lo->B -= (lo->note_lines - 1) * (FS_NOTE + NOTE_GAP); /* a footnote of several lines */
	double right = 8.0, lw = legend_width(cr, p);
	lo->bar_x = lo->legend_x = 0.0;
	if (p->heat) {
		right += 10.0 + 8.0 + 4.0 + 26.0 + FS_AXIS + 4.0; /* gap, bar, ticks, label */
		lo->bar_x = lo->W - right + 10.0;
	}
	lo->legend_top = lw > 0.25 * lo->W; /* a side column would take too much of a narrow plot */
	if (lo->legend_top) {
		double x[LEGEND_MAX];
		int row[LEGEND_MAX];
		int rows = legend_rows(cr, p, lo->W, x, row);
		lo->legend_y = lo->T + FS_TICK - 2.0;
		lo->T += rows * (FS_TICK + 4.0) + 2.0;
	} else if (lw > 0.0) {
		lo->legend_x = lo->W - right - lw + 6.0;
		right += lw + 6.0;
	}
	lo->R = lo->W - right;
	/* x tick labels wider than their spacing are turned a quarter, the plot shortened */
	ticks tx;
	make_ticks(&p->x, 6, &tx);
	set_font(cr, FS_TICK, 0);
	double xw = 0.0, gap = INFINITY;
	for (int i = 0; i < tx.n; i++) {
		xw = fmax(xw, text_w(cr, tx.text[i]));
		if (i > 0)
			gap = fmin(gap, fabs(tx.v[i] - tx.v[i - 1]) / fabs(p->x.hi - p->x.lo) * (lo->R - lo->L));
	}
	lo->xturn = !p->x.log && tx.n > 1 && xw + 3.0 > gap;
	lo->xtick_h = lo->xturn ? xw : FS_TICK;
	if (lo->xturn)
		lo->B -= xw - FS_TICK;
}

/* Data to page coordinates. */
static double axis_t(const bk_plot_axis *a, double v)
{
	if (a->log) {
		if (v <= 0.0)
			return a->zero_at_lo ? 0.0 : NAN;
		return (bk_dlog10(v) - bk_dlog10(a->lo)) / (bk_dlog10(a->hi) - bk_dlog10(a->lo));
	}
	return (v - a->lo) / (a->hi - a->lo);
}

static double page_x(const layout *lo, const bk_plot *p, double x)
{
	return lo->L + axis_t(&p->x, x) * (lo->R - lo->L);
}

static double page_y(const layout *lo, const bk_plot *p, double y)
{
	return lo->B - axis_t(&p->y, y) * (lo->B - lo->T);
}

static int visible(const layout *lo, const bk_plot *p, double x, double y, double *px, double *py)
{
	*px = page_x(lo, p, x);
	*py = page_y(lo, p, y);
	return isfinite(*px) && isfinite(*py) && *px >= lo->L - 0.01 && *px <= lo->R + 0.01 && *py >= lo->T - 0.01 &&
	       *py <= lo->B + 0.01;
}

static void settled_layout(cairo_t *cr, const bk_plot *p, layout *lo);

void bk_plot_to_page_n(const bk_plot *p, int n, const double *x, const double *y, double *px, double *py)
{
	cairo_surface_t *s;
	cairo_t *cr = measure_ctx(&s);
	layout lo;
	settled_layout(cr, p, &lo); /* the whole layout, labels placed: once for all n */
	cairo_destroy(cr);
	cairo_surface_destroy(s);
	for (int i = 0; i < n; i++) {
		px[i] = page_x(&lo, p, x[i]);
		py[i] = page_y(&lo, p, y[i]);
	}
}

void bk_plot_to_page(const bk_plot *p, double x, double y, double *px, double *py)
{
	bk_plot_to_page_n(p, 1, &x, &y, px, py);
}

void bk_plot_areas(const bk_plot *p, double plot[4], double bar[4])
{
	cairo_surface_t *s;
	cairo_t *cr = measure_ctx(&s);
	layout lo;
	settled_layout(cr, p, &lo);
	cairo_destroy(cr);
	cairo_surface_destroy(s);
	plot[0] = lo.L, plot[1] = lo.T, plot[2] = lo.R, plot[3] = lo.B;
	bar[0] = lo.bar_x, bar[1] = lo.T, bar[2] = lo.bar_x + (p->heat ? 8.0 : 0.0), bar[3] = lo.B;
}

/* ---- labels ------------------------------------------------------------------------ */

typedef struct box {
	double x0, y0, x1, y1;
} box;

static int meets(box a, box b)
{
	return a.x0 < b.x1 && b.x0 < a.x1 && a.y0 < b.y1 && b.y0 < a.y1;
}

static int count_labels(const bk_plot *p)
{
	int n = 0;
	for (int s = 0; s < p->nseries; s++)
		for (int i = 0; p->series[s].label && i < p->series[s].n; i++)
			n += p->series[s].label[i] != NULL;
	return n;
}

/* Whether the segment (ax, ay)-(bx, by) meets box b (Liang-Barsky clipping): a line
 * series' segments keep labels off as markers do. */
static int segment_meets(double ax, double ay, double bx, double by, box b)
{
	double t0 = 0.0, t1 = 1.0, dx = bx - ax, dy = by - ay;
	double pq[4][2] = {{-dx, ax - b.x0}, {dx, b.x1 - ax}, {-dy, ay - b.y0}, {dy, b.y1 - ay}};
	for (int k = 0; k < 4; k++) {
		double P = pq[k][0], Q = pq[k][1];
		if (P == 0.0) {
			if (Q < 0.0)
				return 0;
			continue;
		}
		double r = Q / P;
		if (P < 0.0)
			t0 = fmax(t0, r);
		else
			t1 = fmin(t1, r);
		if (t0 > t1)
			return 0;
	}
	return 1;
}

/* The drawn marks labels must not touch: marker boxes, staircase steps and error bars
 * as boxes (the bars 1.2 pt thick), a line series' segments as segments. */
typedef struct marks {
	box *b;
	int n, cap;
	double (*seg)[4];
	int nseg;
} marks;

static int marks_init(const bk_plot *p, const layout *lo, marks *m, int extra)
{
	int nb = extra, ns = 0;
	for (int s = 0; s < p->nseries; s++)
		if (p->series[s].style == BK_PLOT_LINE)
			ns += p->series[s].n;
		else
			nb += 3 * p->series[s].n;
	m->b = malloc(sizeof *m->b * (size_t)(nb + 1));
	m->seg = malloc(sizeof *m->seg * (size_t)(ns + extra + 1)); /* extra: the labels' leaders too */
	m->n = m->nseg = 0;
	m->cap = nb;
	if (!m->b || !m->seg)
		return -1;
	for (int s = 0; s < p->nseries; s++) {
		const bk_plot_series *S = &p->series[s];
		double px, py, qx = 0.0, qy = 0.0;
		int prev = 0;
		for (int i = 0; i < S->n; i++) {
			if (!visible(lo, p, S->x[i], S->y[i], &px, &py))
				continue;
			if (S->style == BK_PLOT_LINE) {
				if (prev)
					memcpy(m->seg[m->nseg++], (double[4]){qx, qy, px, py}, sizeof m->seg[0]);
			} else if (S->style == BK_PLOT_POINTS && S->marker != BK_PLOT_DOT) /* dots: a background cloud */
				m->b[m->n++] = (box){px - MARK_R, py - MARK_R, px + MARK_R, py + MARK_R};
			else if (S->style == BK_PLOT_STEPS && prev) { /* right along qy, then down to py */
				m->b[m->n++] = (box){fmin(qx, px), qy - 0.6, fmax(qx, px), qy + 0.6};
				m->b[m->n++] = (box){px - 0.6, fmin(qy, py), px + 0.6, fmax(qy, py)};
			}
			if (S->xlo && S->xhi && isfinite(S->xlo[i]) && isfinite(S->xhi[i])) { /* drawn clipped to the plot */
				double a = fmax(lo->L, fmin(page_x(lo, p, S->xlo[i]), lo->R));
				double b = fmax(lo->L, fmin(page_x(lo, p, S->xhi[i]), lo->R));
				m->b[m->n++] = (box){fmin(a, b), py - 0.6, fmax(a, b), py + 0.6};
			}
			prev = 1, qx = px, qy = py;
		}
	}
	return 0;
}

static void marks_free(marks *m)
{
	free(m->b);
	free(m->seg);
}

static int marks_meet(const marks *m, box b)
{
	for (int j = 0; j < m->n; j++)
		if (meets(b, m->b[j]))
			return 1;
	for (int j = 0; j < m->nseg; j++)
		if (segment_meets(m->seg[j][0], m->seg[j][1], m->seg[j][2], m->seg[j][3], b))
			return 1;
	return 0;
}

/* The point of box b nearest to (px, py): where a leader line from the marker ends. */
static void nearest_on(box b, double px, double py, double *qx, double *qy)
{
	*qx = fmax(b.x0, fmin(px, b.x1));
	*qy = fmax(b.y0, fmin(py, b.y1));
}

/* Whether a leader from the marker at (px, py) to box b meets a marker or a label
 * other than the marker's own (the segment starts at the marker's edge). Bars and
 * staircase steps (boxes 1.2 pt thin) it may cross: a thin grey line over a thin
 * coloured one stays readable, and a crowd of bars would leave no leader at all. */
/* The leader from the marker at (px, py) to box b: from the marker's edge
 * (sx, sy) to the box's nearest point (qx, qy); 0 when the box is at the
 * marker (no leader). */
static int leader_ends(double px, double py, box b, double *sx, double *sy, double *qx, double *qy)
{
	nearest_on(b, px, py, qx, qy);
	double dx = *qx - px, dy = *qy - py, d = hypot(dx, dy);
	if (d <= MARK_R + 0.5)
		return 0;
	*sx = px + dx * (MARK_R + 0.5) / d, *sy = py + dy * (MARK_R + 0.5) / d;
	return 1;
}

/* Whether box B stops the leader (sx, sy)-(qx, qy) of the marker at (px, py). */
static int blocks_leader(const box *B, double px, double py, double sx, double sy, double qx, double qy)
{
	return fmin(B->x1 - B->x0, B->y1 - B->y0) > 1.3 && segment_meets(sx, sy, qx, qy, *B) &&
	       !(B->x0 <= px && px <= B->x1 && B->y0 <= py && py <= B->y1);
}

static int leader_meets(const marks *m, double px, double py, box b)
{
	double sx, sy, qx, qy;
	if (!leader_ends(px, py, b, &sx, &sy, &qx, &qy))
		return 0;
	for (int j = 0; j < m->n; j++)
		if (blocks_leader(&m->b[j], px, py, sx, sy, qx, qy))
			return 1;
	return 0;
}

/* The first free place for a w x h box around (px, py) at gap g: right, upper right,
 * above, upper left, left, lower left, below, lower right; then the same twice, three
 * times ... rings times as far out, where a leader line will tie the label to its
 * marker (and must itself cross no mark). Returns 0 (none), or the ring (1..rings)
 * with the box in *out. */
static int free_place(const marks *m, const layout *lo, double px, double py, double w, double h, int rings,
                      box *out)
{
	static const double dir[8][2] = {{1, 0}, {1, -1}, {0, -1}, {-1, -1}, {-1, 0}, {-1, 1}, {0, 1}, {1, 1}};
	for (int ring = 1; ring <= rings; ring++)
		for (int d = 0; d < 8; d++) {
			double g = ring * (MARK_R + 1.0);
			double cx = px + dir[d][0] * (g + w / 2), cy = py + dir[d][1] * (g + h / 2);
			box b = {cx - w / 2, cy - h / 2, cx + w / 2, cy + h / 2};
			if (b.x0 < lo->L || b.x1 > lo->R || b.y0 < lo->T || b.y1 > lo->B || marks_meet(m, b) ||
			    (ring > 1 && leader_meets(m, px, py, b)))
				continue;
			*out = b;
			return ring;
		}
	return 0;
}

/* The free place for a w x h box nearest to (px, py) anywhere in the plot, on a
 * 2-pt grid, its leader crossing no marker (free_place's last resort for a key
 * number, so that no label is ever dropped while the plot has room). 0 (none),
 * or 1 with the box in *out. */
/* A grid place of nearest_free: its distance and its index in row-major
 * scan order (the tie-break: the first of equal distance in that order). */
typedef struct grid_place {
	double d, cx, cy; /* cx, cy: the scan's running sums, the same places to the bit */
	int i;
} grid_place;

static int by_distance(const void *a, const void *b)
{
	const grid_place *p = a, *q = b;
	return p->d != q->d ? (p->d < q->d ? -1 : 1) : (p->i > q->i) - (p->i < q->i);
}

/* The marks bucketed by the CELL-pt cells their bounding boxes touch (a
 * pt of slack each side), so that a box is tested against the marks near it
 * only: marks_meet's answer, at the cost of a few marks instead of all. */
#define CELL 16.0
typedef struct mark_grid {
	double L, T;
	int nx, ny;
	int *start, *item; /* CSR: cell c's items are item[start[c] .. start[c + 1]) */
} mark_grid;

static void cell_span(const mark_grid *g, double x0, double y0, double x1, double y1, int *c)
{
	double v[4] = {(x0 - 1 - g->L) / CELL, (y0 - 1 - g->T) / CELL, (x1 + 1 - g->L) / CELL, (y1 + 1 - g->T) / CELL};
	int hi[4] = {g->nx - 1, g->ny - 1, g->nx - 1, g->ny - 1};
	for (int k = 0; k < 4; k++)
		c[k] = !(v[k] > 0) ? 0 : v[k] >= hi[k] ? hi[k] : (int)v[k]; /* NaN: the first cell */
}

static void mark_bounds(const marks *m, int j, double *x0, double *y0, double *x1, double *y1)
{
	if (j < m->n) {
		*x0 = m->b[j].x0, *y0 = m->b[j].y0, *x1 = m->b[j].x1, *y1 = m->b[j].y1;
	} else {
		const double *q = m->seg[j - m->n];
		*x0 = fmin(q[0], q[2]), *y0 = fmin(q[1], q[3]), *x1 = fmax(q[0], q[2]), *y1 = fmax(q[1], q[3]);
	}
}

static int mark_grid_build(mark_grid *g, const marks *m, const layout *lo)
{
	g->L = lo->L, g->T = lo->T;
	g->nx = (int)((lo->R - lo->L) / CELL) + 1;
	g->ny = (int)((lo->B - lo->T) / CELL) + 1;
	int nc = g->nx * g->ny, nm = m->n + m->nseg;
	g->start = calloc((size_t)nc + 1, sizeof *g->start);
	g->item = NULL;
	if (!g->start)
		return -1;
	for (int pass = 0; pass < 2; pass++) { /* count, then fill */
		for (int j = 0; j < nm; j++) {
			double x0, y0, x1, y1;
			int c[4];
			mark_bounds(m, j, &x0, &y0, &x1, &y1);
			cell_span(g, x0, y0, x1, y1, c);
			for (int y = c[1]; y <= c[3]; y++)
				for (int x = c[0]; x <= c[2]; x++) {
					if (pass == 0)
						g->start[y * g->nx + x + 1]++;
					else
						g->item[g->start[y * g->nx + x]++] = j;
				}
		}
		if (pass == 0) {
			for (int k = 0; k < nc; k++)
				g->start[k + 1] += g->start[k];
			if (!(g->item = malloc((size_t)(g->start[nc] + 1) * sizeof *g->item)))
				return -1;
		} else { /* the fill moved each start to the next cell's: back by one cell */
			for (int k = nc; k > 0; k--)
				g->start[k] = g->start[k - 1];
			g->start[0] = 0;
		}
	}
	return 0;
}

static int grid_meets(const mark_grid *g, const marks *m, box b)
{
	int c[4];
	cell_span(g, b.x0, b.y0, b.x1, b.y1, c);
	for (int y = c[1]; y <= c[3]; y++)
		for (int x = c[0]; x <= c[2]; x++)
			for (int k = g->start[y * g->nx + x]; k < g->start[y * g->nx + x + 1]; k++) {
				int j = g->item[k];
				if (j < m->n ? meets(b, m->b[j])
				             : segment_meets(m->seg[j - m->n][0], m->seg[j - m->n][1], m->seg[j - m->n][2],
				                             m->seg[j - m->n][3], b))
					return 1;
			}
	return 0;
}

/* leader_meets through the grid: the cells the leader crosses in order from
 * the marker outward (Amanatides & Woo's walk), each cell's thick boxes
 * tested as leader_meets tests them: its answer, and a leader out of a crowd
 * is found blocked in the first cells instead of after every box. */
static int grid_leader_meets(const mark_grid *g, const marks *m, double px, double py, box b)
{
	double sx, sy, qx, qy;
	if (!leader_ends(px, py, b, &sx, &sy, &qx, &qy))
		return 0;
	double u[4] = {(sx - g->L) / CELL, (sy - g->T) / CELL, (qx - g->L) / CELL, (qy - g->T) / CELL};
	if (!(u[0] >= 0 && u[0] < g->nx && u[2] >= 0 && u[2] < g->nx && u[1] >= 0 && u[1] < g->ny && u[3] >= 0 &&
	      u[3] < g->ny))
		return leader_meets(m, px, py, b); /* an end off the grid: every box */
	int c[4];
	cell_span(g, sx + 1, sy + 1, sx - 1, sy - 1, c); /* the start's own cell (no slack) */
	int x = c[0], y = c[1], ex, ey;
	cell_span(g, qx + 1, qy + 1, qx - 1, qy - 1, c);
	ex = c[0], ey = c[1];
	int stepx = qx > sx ? 1 : -1, stepy = qy > sy ? 1 : -1;
	double tdx = qx != sx ? CELL / fabs(qx - sx) : HUGE_VAL, tdy = qy != sy ? CELL / fabs(qy - sy) : HUGE_VAL;
	double fx = (sx - g->L) / CELL - x, fy = (sy - g->T) / CELL - y; /* where in its cell the start is */
	double tx = qx != sx ? (stepx > 0 ? 1 - fx : fx) * tdx : HUGE_VAL;
	double ty = qy != sy ? (stepy > 0 ? 1 - fy : fy) * tdy : HUGE_VAL;
	for (int guard = 0; guard < g->nx + g->ny + 2; guard++) {
		for (int k = g->start[y * g->nx + x]; k < g->start[y * g->nx + x + 1]; k++) {
			int j = g->item[k];
			if (j < m->n && blocks_leader(&m->b[j], px, py, sx, sy, qx, qy))
				return 1;
		}
		if (x == ex && y == ey)
			return 0;
		if (tx < ty) {
			tx += tdx;
			x += stepx;
		} else {
			ty += tdy;
			y += stepy;
		}
		if (x < 0 || y < 0 || x >= g->nx || y >= g->ny)
			return leader_meets(m, px, py, b); /* off the grid (a clamped end): every box */
	}
	return leader_meets(m, px, py, b);
}

static int nearest_free(const marks *m, const layout *lo, double px, double py, double w, double h, box *out)
{
	/* every place on a 2-pt grid over the plot, tried nearest first: the
	 * first free one is the nearest; each against the marks near it only
	 * (all of them against every mark made a crowded plot's last labels
	 * cost seconds each) */
	int nx = 0, ny = 0;
	for (double cx = lo->L + w / 2; cx + w / 2 <= lo->R; cx += 2)
		nx++;
	for (double cy = lo->T + h / 2; cy + h / 2 <= lo->B; cy += 2)
		ny++;
	if (nx == 0 || ny == 0)
		return 0;
	grid_place *g = malloc((size_t)nx * (size_t)ny * sizeof *g);
	mark_grid mg = {0};
	if (!g || mark_grid_build(&mg, m, lo)) {
		free(g);
		free(mg.start);
		free(mg.item);
		return 0;
	}
	int n = 0;
	double cy = lo->T + h / 2;
	for (int y = 0; y < ny; y++, cy += 2) {
		double cx = lo->L + w / 2;
		for (int x = 0; x < nx; x++, cx += 2, n++)
			g[n] = (grid_place){hypot(cx - px, cy - py), cx, cy, n};
	}
	/* nearest first: bucketed by whole points of distance (a counting sort),
	 * each bucket sorted (by_distance), instead of one sort of every place */
	int nb = 2;
	for (int k = 0; k < n; k++)
		if (g[k].d + 2 > nb)
			nb = (int)g[k].d + 2;
	int *at = calloc((size_t)nb + 1, sizeof *at);
	grid_place *o = malloc((size_t)n * sizeof *o);
	if (!at || !o) {
		free(at);
		free(o);
		free(g);
		free(mg.start);
		free(mg.item);
		return 0;
	}
	for (int k = 0; k < n; k++)
		at[(int)g[k].d + 1]++;
	for (int k = 0; k < nb; k++)
		at[k + 1] += at[k];
	for (int k = 0; k < n; k++)
		o[at[(int)g[k].d]++] = g[k];
	free(g);
	g = o;
	int found = 0, sorted = 0;
	for (int k = 0; k < n && !found; k++) {
		if (k == sorted) { /* the next bucket, in order before its first is tried */
			int e = k + 1;
			while (e < n && (int)g[e].d == (int)g[k].d)
				e++;
			qsort(g + k, (size_t)(e - k), sizeof *g, by_distance);
			sorted = e;
		}
		box b = {g[k].cx - w / 2, g[k].cy - h / 2, g[k].cx + w / 2, g[k].cy + h / 2};
		if (!grid_meets(&mg, m, b) && !grid_leader_meets(&mg, m, px, py, b))
			found = 1, *out = b;
	}
	free(g);
	free(at);
	free(mg.start);
	free(mg.item);
	return found;
}

/* Places every label (plot.h); out holds count_labels(p) entries. A label with no free
 * place tries its key number ("3", named in the footnote's key) in the same places. */
static int place_labels(cairo_t *cr, const bk_plot *p, const layout *lo, bk_plot_label *out)
{
	int nl = count_labels(p), k = 0, nkey = 0;
	marks m;
	if (marks_init(p, lo, &m, nl)) {
		marks_free(&m);
		return -1;
	}
	set_font(cr, FS_LABEL, 0);
	for (int pass = 0; pass < 2; pass++) /* filled markers' labels first, then hollow ones' */
	for (int s = 0; s < p->nseries; s++) {
		const bk_plot_series *S = &p->series[s];
		if ((S->hollow != 0) != pass)
			continue;
		for (int i = 0; S->label && i < S->n; i++) {
			if (!S->label[i])
				continue;
			bk_plot_label *L = &out[k++];
			*L = (bk_plot_label){s, i, 0, 0, 0, 0, 0, 0};
			double px, py;
			if (!visible(lo, p, S->x[i], S->y[i], &px, &py))
				continue;
			box b;
			char num[16];
			snprintf(num, sizeof num, "%d", nkey + 1);
			int ring = free_place(&m, lo, px, py, text_w(cr, S->label[i]), FS_LABEL, 3, &b);
			if (ring)
				L->placed = 1;
			/* a key number is small: it may go further out on its leader
			 * (a crowd of timing bars once left one no place in 3 rings) */
			else if ((ring = free_place(&m, lo, px, py, text_w(cr, num), FS_LABEL, 12, &b)) ||
			         (nearest_free(&m, lo, px, py, text_w(cr, num), FS_LABEL, &b) && (ring = 13)))
				L->placed = 1, L->key = ++nkey;
			if (L->placed) {
				m.b[m.n++] = b;
				if (ring > 1) { /* its leader keeps later labels off too */
					double qx, qy;
					nearest_on(b, px, py, &qx, &qy);
					memcpy(m.seg[m.nseg++], (double[4]){px, py, qx, qy}, sizeof m.seg[0]);
				}
				L->x0 = b.x0, L->y0 = b.y0, L->x1 = b.x1, L->y1 = b.y1;
			}
		}
	}
	marks_free(&m);
	return k;
}

enum { NOTE_MAX = 8 }; /* footnote lines at most */

/* The footnote in lines of at most W - 12 pt: the caller's note (one line, shrunk to
 * fit when longer), then the key of numbered labels ("key: 1 name, 2 name") and the
 * labels with no place at all, wrapped at entries. Returns the number of lines. */
static int note_text(cairo_t *cr, const bk_plot *p, double W, const bk_plot_label *lab, int nl,
                     char line[NOTE_MAX][1024])
{
	int n = 0, dropped = 0;
	set_font(cr, FS_NOTE, 0);
	line[0][0] = '\0';
	if (p->note)
		snprintf(line[n++], 1024, "%s", p->note);
	for (int k = 0; k < nl; k++)
		dropped += !lab[k].placed;
	for (int pass = 0; pass < 2; pass++) {
		int first = 1;
		for (int k = 0; k < nl; k++) {
			if (pass == 0 ? lab[k].key == 0 : lab[k].placed)
				continue;
			const char *name = p->series[lab[k].series].label[lab[k].point];
			char entry[1100];
			if (pass == 0)
				snprintf(entry, sizeof entry, "%s%d %s", first ? "key: " : "", lab[k].key, name);
			else
				snprintf(entry, sizeof entry, "%s", name);
			char head[64] = "";
			if (first && pass == 1)
				snprintf(head, sizeof head, "%d not labelled (no free place): ", dropped);
			char next[2200];
			int cur = n > 0 ? n - 1 : 0;
			snprintf(next, sizeof next, "%s%s%s%s", line[cur], n == 0 ? "" : first ? "; " : ", ", head, entry);
			size_t len = strlen(next);
			if (n > 0 && len < 1024 && text_w(cr, next) <= W - 12.0)
				memcpy(line[cur], next, len + 1);
			else if (n < NOTE_MAX)
				snprintf(line[n++], 1024, "%.60s%.900s", head, entry);
			else { /* out of lines: say so on the last */
				size_t len = strlen(line[NOTE_MAX - 1]);
				if (len < 1000 && !strstr(line[NOTE_MAX - 1], "\xe2\x80\xa6"))
					snprintf(line[NOTE_MAX - 1] + len, 1024 - len, " \xe2\x80\xa6");
			}
			first = 0;
		}
	}
	return n;
}

/* The layout with room for the footnote's lines and the labels placed in it: placing
 * may key labels whose key needs more lines, which shortens the plot, so it is redone
 * until the lines suffice (three rounds at most; a key only shrinks as room grows less). */
static int settle(cairo_t *cr, const bk_plot *p, layout *lo, bk_plot_label *lab)
{
	char (*line)[1024] = malloc(sizeof(char[NOTE_MAX][1024]));
	int nl = count_labels(p), lines = 1, rc = 0;
	if (!line)
		return -1;
	for (int round = 0; round < 3; round++) {
		make_layout(cr, p, lo, lines);
		if ((rc = place_labels(cr, p, lo, lab)) < 0)
			break;
		int need = note_text(cr, p, lo->W, lab, nl, line);
		if (need <= lines)
			break;
		lines = need;
	}
	free(line);
	return rc;
}

/* The layout alone, as the drawing settles it (out of memory: one footnote line). */
static void settled_layout(cairo_t *cr, const bk_plot *p, layout *lo)
{
	bk_plot_label *lab = malloc(sizeof *lab * (size_t)(count_labels(p) + 1));
	if (!lab || settle(cr, p, lo, lab) < 0)
		make_layout(cr, p, lo, 1);
	free(lab);
}

int bk_plot_labels(const bk_plot *p, bk_plot_label *out, int max)
{
	int n = count_labels(p);
	bk_plot_label *all = malloc(sizeof *all * (size_t)(n + 1));
	cairo_surface_t *s;
	cairo_t *cr = measure_ctx(&s);
	layout lo;
	int k = all ? settle(cr, p, &lo, all) : -1;
	cairo_destroy(cr);
	cairo_surface_destroy(s);
	if (k >= 0)
		memcpy(out, all, sizeof *all * (size_t)(k < max ? k : max));
	free(all);
	return k;
}

int bk_plot_marks(const bk_plot *p, double (*box_out)[4], int max)
{
	cairo_surface_t *s;
	cairo_t *cr = measure_ctx(&s);
	layout lo;
	int n = count_labels(p), k = -1;
	bk_plot_label *lab = malloc(sizeof *lab * (size_t)(n + 1));
	marks m = {0};
	if (lab && settle(cr, p, &lo, lab) >= 0 && !marks_init(p, &lo, &m, 0)) {
		k = m.n;
		for (int j = 0; j < m.n && j < max; j++)
			box_out[j][0] = m.b[j].x0, box_out[j][1] = m.b[j].y0, box_out[j][2] = m.b[j].x1, box_out[j][3] = m.b[j].y1;
	}
	marks_free(&m);
	free(lab);
	cairo_destroy(cr);
	cairo_surface_destroy(s);
	return k;
}

/* ---- drawing ----------------------------------------------------------------------- */

static void rgb(cairo_t *cr, unsigned c)
{
	cairo_set_source_rgb(cr, ((c >> 16) & 255) / 255.0, ((c >> 8) & 255) / 255.0, (c & 255) / 255.0);
}

/* Text at (x, y): ax 0 left, 0.5 centred, 1 right of x; y is the baseline. */
static void text_at(cairo_t *cr, double x, double y, double ax, const char *s)
{
	char buf[1024];
	clean_utf8(s, buf, sizeof buf);
	cairo_text_extents_t e;
	cairo_text_extents(cr, buf, &e);
	cairo_move_to(cr, x - ax * e.x_advance, y);
	cairo_show_text(cr, buf);
}

/* text_at with the font shrunk (never below 4 pt) until s is at most maxw wide:
 * a long title or axis name stays on the page. */
static void text_fit(cairo_t *cr, double x, double y, double ax, const char *s, double size, int bold, double maxw)
{
	set_font(cr, size, bold);
	double w = text_w(cr, s);
	if (w > maxw && maxw > 0)
		set_font(cr, fmax(4.0, size * maxw / w), bold);
	text_at(cr, x, y, ax, s);
}

static void marker(cairo_t *cr, int m, double x, double y, double r)
{
	switch (m) {
	case BK_PLOT_SQUARE: cairo_rectangle(cr, x - r * 0.85, y - r * 0.85, r * 1.7, r * 1.7); break;
	case BK_PLOT_TRIANGLE:
		cairo_move_to(cr, x, y - r * 1.15);
		cairo_line_to(cr, x + r, y + r * 0.75);
		cairo_line_to(cr, x - r, y + r * 0.75);
		cairo_close_path(cr);
		break;
	case BK_PLOT_DOT: cairo_arc(cr, x, y, r * 0.4, 0, 2 * PI); break;
	default: cairo_new_sub_path(cr); cairo_arc(cr, x, y, r, 0, 2 * PI);
	}
}

static void draw_marker(cairo_t *cr, const bk_plot_series *S, double x, double y)
{
	marker(cr, S->marker, x, y, MARK_R);
	if (S->hollow || S->marker == BK_PLOT_DOT) {
		cairo_set_source_rgb(cr, 1, 1, 1);
		if (S->marker == BK_PLOT_DOT)
			rgb(cr, S->rgb);
		cairo_fill_preserve(cr);
	} else {
		rgb(cr, S->rgb);
		cairo_fill_preserve(cr);
	}
	rgb(cr, S->rgb);
	cairo_set_line_width(cr, S->marker == BK_PLOT_DOT ? 0.0 : 0.8);
	cairo_stroke(cr);
}

/* The cells as an nx x ny image painted over their rectangle with nearest-neighbour
 * filtering: exact cell colours in the PNG, one compact image in the SVG and PDF
 * (not a rectangle per cell), and no seams between cells in any viewer. */
static int draw_heat(cairo_t *cr, const bk_plot *p, const layout *lo)
{
	const bk_plot_heat *h = p->heat;
	double m = fmax(fabs(h->vmin), fabs(h->vmax));
	cairo_surface_t *img = cairo_image_surface_create(CAIRO_FORMAT_RGB24, h->nx, h->ny);
	if (cairo_surface_status(img) != CAIRO_STATUS_SUCCESS) {
		cairo_surface_destroy(img);
		return -1;
	}
	cairo_surface_flush(img);
	unsigned char *d = cairo_image_surface_get_data(img);
	int stride = cairo_image_surface_get_stride(img);
	for (int j = 0; j < h->ny; j++) {
		uint32_t *row = (uint32_t *)(d + (size_t)(h->ny - 1 - j) * stride); /* image row 0 is y1 */
		for (int i = 0; i < h->nx; i++) {
			double v = h->value[(size_t)j * h->nx + i];
			unsigned char c[3] = {128, 128, 128};
			if (!isnan(v)) {
				double t = h->map == BK_PLOT_DIVERGING ? (m > 0 ? 0.5 + 0.5 * v / m : 0.5)
				                                       : (h->vmax > h->vmin ? (v - h->vmin) / (h->vmax - h->vmin) : 0.0);
				if (isinf(v))
					t = v > 0 ? 1.0 : 0.0;
				bk_plot_colour(h->map, t, c);
			}
			row[i] = (uint32_t)c[0] << 16 | (uint32_t)c[1] << 8 | c[2];
		}
	}
	cairo_surface_mark_dirty(img);
	double x0 = page_x(lo, p, h->x0), x1 = page_x(lo, p, h->x1), y0 = page_y(lo, p, h->y0), y1 = page_y(lo, p, h->y1);
	cairo_save(cr);
	cairo_rectangle(cr, lo->L, lo->T, lo->R - lo->L, lo->B - lo->T);
	cairo_clip(cr);
	cairo_translate(cr, x0, y1);
	cairo_scale(cr, (x1 - x0) / h->nx, (y0 - y1) / h->ny);
	cairo_set_source_surface(cr, img, 0, 0);
	cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_NEAREST);
	cairo_rectangle(cr, 0, 0, h->nx, h->ny);
	cairo_fill(cr);
	cairo_restore(cr);
	cairo_surface_destroy(img);
	return 0;
}

static void draw_bar(cairo_t *cr, const bk_plot *p, const layout *lo)
{
	const bk_plot_heat *h = p->heat;
	double x = lo->bar_x, w = 8.0, a, b;
	bar_range(h, &a, &b);
	/* a 1 x 128 image, nearest filter: no seams; the end rows take the map's ends exactly */
	cairo_surface_t *img = cairo_image_surface_create(CAIRO_FORMAT_RGB24, 1, 128);
	if (cairo_surface_status(img) == CAIRO_STATUS_SUCCESS) {
		cairo_surface_flush(img);
		unsigned char *d = cairo_image_surface_get_data(img);
		int stride = cairo_image_surface_get_stride(img);
		for (int k = 0; k < 128; k++) {
			unsigned char c[3];
			bk_plot_colour(h->map, (127 - k) / 127.0, c); /* row 0 at the top: the high end */
			*(uint32_t *)(d + (size_t)k * stride) = (uint32_t)c[0] << 16 | (uint32_t)c[1] << 8 | c[2];
		}
		cairo_surface_mark_dirty(img);
		cairo_save(cr);
		cairo_translate(cr, x, lo->T);
		cairo_scale(cr, w, (lo->B - lo->T) / 128.0);
		cairo_set_source_surface(cr, img, 0, 0);
		cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_NEAREST);
		cairo_rectangle(cr, 0, 0, 1, 128);
		cairo_fill(cr);
		cairo_restore(cr);
	}
	cairo_surface_destroy(img);
	cairo_set_source_rgb(cr, 0, 0, 0);
	cairo_set_line_width(cr, 0.5);
	cairo_rectangle(cr, x, lo->T, w, lo->B - lo->T);
	cairo_stroke(cr);
	bk_plot_axis ax = {NULL, 0, a, b, 0, 0, NULL};
	ticks t;
	make_ticks(&ax, BAR_TICKS, &t);
	set_font(cr, FS_TICK, 0);
	for (int i = 0; i < t.n; i++) {
		double y = lo->B - (t.v[i] - a) / (b - a) * (lo->B - lo->T);
		cairo_move_to(cr, x + w, y);
		cairo_line_to(cr, x + w + 2.5, y);
		cairo_stroke(cr);
		text_at(cr, x + w + 4.0, y + FS_TICK * 0.35, 0.0, t.text[i]);
	}
	if (h->label) {
		cairo_save(cr);
		cairo_translate(cr, lo->W - 6.0, (lo->T + lo->B) / 2);
		cairo_rotate(cr, -PI / 2);
		text_fit(cr, 0, 0, 0.5, h->label, FS_AXIS, 0, lo->H - 12.0);
		cairo_restore(cr);
	}
}

static void draw_axes(cairo_t *cr, const bk_plot *p, const layout *lo)
{
	ticks tx, ty;
	make_ticks(&p->x, 6, &tx);
	make_ticks(&p->y, 5, &ty);
	cairo_set_line_width(cr, 0.4);
	cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
	for (int i = 0; !p->heat && i < tx.n; i++) { /* grid under the data, none over a heatmap */
		cairo_move_to(cr, page_x(lo, p, tx.v[i]), lo->T);
		cairo_line_to(cr, page_x(lo, p, tx.v[i]), lo->B);
	}
	for (int i = 0; !p->heat && i < ty.n; i++)
		if (ty.major[i]) {
			cairo_move_to(cr, lo->L, page_y(lo, p, ty.v[i]));
			cairo_line_to(cr, lo->R, page_y(lo, p, ty.v[i]));
		}
	cairo_stroke(cr);
}

static void draw_frame(cairo_t *cr, const bk_plot *p, const layout *lo)
{
	ticks tx, ty;
	make_ticks(&p->x, 6, &tx);
	make_ticks(&p->y, 5, &ty);
	cairo_set_source_rgb(cr, 0.15, 0.15, 0.15);
	cairo_set_line_width(cr, 0.6);
	cairo_rectangle(cr, lo->L, lo->T, lo->R - lo->L, lo->B - lo->T);
	cairo_stroke(cr);
	set_font(cr, FS_TICK, 0);
	for (int i = 0; i < tx.n; i++) {
		double x = page_x(lo, p, tx.v[i]);
		cairo_move_to(cr, x, lo->B);
		cairo_line_to(cr, x, lo->B + (tx.major[i] ? 3.0 : 1.5));
		cairo_stroke(cr);
		if (tx.major[i] && lo->xturn) {
			cairo_save(cr);
			cairo_translate(cr, x + FS_TICK * 0.35, lo->B + 4.0);
			cairo_rotate(cr, -PI / 2);
			text_at(cr, 0, 0, 1.0, tx.text[i]);
			cairo_restore(cr);
		} else if (tx.major[i])
			text_at(cr, x, lo->B + 4.0 + FS_TICK, 0.5, tx.text[i]);
	}
	for (int i = 0; i < ty.n; i++) {
		double y = page_y(lo, p, ty.v[i]);
		cairo_move_to(cr, lo->L, y);
		cairo_line_to(cr, lo->L - (ty.major[i] ? 3.0 : 1.5), y);
		cairo_stroke(cr);
		if (ty.major[i] && ty.text[i][0])
			text_at(cr, lo->L - 4.5, y + FS_TICK * 0.35, 1.0, ty.text[i]);
	}
	if (p->y.log && p->y.zero_at_lo) { /* the axis break between "0" and its first decade */
		double yb = (page_y(lo, p, p->y.lo) + page_y(lo, p, p->y.lo * 10)) / 2;
		cairo_set_source_rgb(cr, 1, 1, 1);
		cairo_rectangle(cr, lo->L - 2, yb - 2, 4, 4);
		cairo_fill(cr);
		cairo_set_source_rgb(cr, 0.15, 0.15, 0.15);
		for (int k = 0; k < 2; k++) {
			cairo_move_to(cr, lo->L - 3, yb - 2 + 2 * k + 1.5);
			cairo_line_to(cr, lo->L + 3, yb - 2 + 2 * k - 1.5);
		}
		cairo_stroke(cr);
	}
	if (p->x.label) { /* centred under the plot, moved left if it would run off the page */
		set_font(cr, FS_AXIS, 0);
		double w = fmin(text_w(cr, p->x.label), lo->W - 12.0), cx = fmin((lo->L + lo->R) / 2, lo->W - 6.0 - w / 2);
		text_fit(cr, fmax(cx, 6.0 + w / 2), lo->B + 4.0 + lo->xtick_h + 4.0 + FS_AXIS, 0.5, p->x.label, FS_AXIS, 0,
		         lo->W - 12.0);
	}
	if (p->y.label) {
		cairo_save(cr);
		cairo_translate(cr, 6.0 + FS_AXIS * 0.8, (lo->T + lo->B) / 2);
		cairo_rotate(cr, -PI / 2);
		text_fit(cr, 0, 0, 0.5, p->y.label, FS_AXIS, 0, lo->B - lo->T + 20.0);
		cairo_restore(cr);
	}
	if (p->title)
		text_fit(cr, lo->W / 2, 6.0 + FS_TITLE, 0.5, p->title, FS_TITLE, 1, lo->W - 12.0);
}

static void draw_series(cairo_t *cr, const bk_plot *p, const layout *lo, const bk_plot_series *S)
{
	double px, py;
	cairo_save(cr);
	cairo_rectangle(cr, lo->L, lo->T, lo->R - lo->L, lo->B - lo->T);
	cairo_clip(cr);
	if (S->style != BK_PLOT_POINTS) { /* in the order given; steps go right, then down */
		int started = 0;
		double last_y = 0.0;
		for (int i = 0; i < S->n; i++) {
			if (!visible(lo, p, S->x[i], S->y[i], &px, &py))
				continue;
			if (!started)
				cairo_move_to(cr, px, py);
			else {
				if (S->style == BK_PLOT_STEPS)
					cairo_line_to(cr, px, last_y);
				cairo_line_to(cr, px, py);
			}
			started = 1;
			last_y = py;
		}
		rgb(cr, S->rgb);
		cairo_set_line_width(cr, 0.8);
		if (S->style == BK_PLOT_STEPS) {
			static const double dash[2] = {3.0, 1.8};
			cairo_set_dash(cr, dash, 2, 0);
		}
		cairo_stroke(cr);
		cairo_set_dash(cr, NULL, 0, 0);
	}
	for (int i = 0; S->xlo && S->xhi && i < S->n; i++)
		if (visible(lo, p, S->x[i], S->y[i], &px, &py) && isfinite(S->xlo[i]) && isfinite(S->xhi[i])) {
			rgb(cr, S->rgb);
			cairo_set_line_width(cr, 0.6);
			cairo_move_to(cr, page_x(lo, p, S->xlo[i]), py);
			cairo_line_to(cr, page_x(lo, p, S->xhi[i]), py);
			cairo_stroke(cr);
		}
	cairo_restore(cr);
	if (S->style != BK_PLOT_POINTS)
		return;
	for (int i = 0; i < S->n; i++)
		if (visible(lo, p, S->x[i], S->y[i], &px, &py))
			draw_marker(cr, S, px, py);
}

static void legend_entry(cairo_t *cr, const bk_plot_series *S, double x, double y)
{
	if (S->style != BK_PLOT_POINTS) {
		rgb(cr, S->rgb);
		cairo_set_line_width(cr, 0.8);
		static const double dash[2] = {3.0, 1.8};
		cairo_set_dash(cr, dash, S->style == BK_PLOT_STEPS ? 2 : 0, 0);
		cairo_move_to(cr, x, y - 2.2);
		cairo_line_to(cr, x + 10, y - 2.2);
		cairo_stroke(cr);
		cairo_set_dash(cr, NULL, 0, 0);
	}
	if (S->style == BK_PLOT_POINTS)
		draw_marker(cr, S, x + 5, y - 2.2);
	cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
	text_at(cr, x + 14, y, 0.0, S->name);
}

static void draw_legend(cairo_t *cr, const bk_plot *p, const layout *lo)
{
	double x[LEGEND_MAX], y = lo->T + 6.0;
	int row[LEGEND_MAX];
	if (lo->legend_top)
		legend_rows(cr, p, lo->W, x, row);
	set_font(cr, FS_TICK, 0);
	for (int s = 0; s < p->nseries; s++) {
		if (!p->series[s].name)
			continue;
		if (lo->legend_top) {
			if (s < LEGEND_MAX)
				legend_entry(cr, &p->series[s], x[s], lo->legend_y + row[s] * (FS_TICK + 4.0));
			continue;
		}
		legend_entry(cr, &p->series[s], lo->legend_x, y);
		y += FS_TICK + 4.0;
	}
}

/* The footnote (note_text): its lines upward from the page's bottom edge. */
static int draw_note(cairo_t *cr, const bk_plot *p, const layout *lo, const bk_plot_label *lab, int nl)
{
	char (*line)[1024] = malloc(sizeof(char[NOTE_MAX][1024]));
	if (!line)
		return -1;
	int n = note_text(cr, p, lo->W, lab, nl, line);
	if (n > lo->note_lines) { /* settle ran out of rounds: the lines it made room for, "..." after */
		n = lo->note_lines;
		size_t len = strlen(line[n - 1]);
		snprintf(line[n - 1] + (len < 1000 ? len : 1000), 24, " \xe2\x80\xa6");
	}
	cairo_set_source_rgb(cr, 0.33, 0.33, 0.33);
	for (int k = 0; k < n; k++)
		text_fit(cr, 6.0, lo->H - 5.0 - (n - 1 - k) * (FS_NOTE + NOTE_GAP), 0.0, line[k], FS_NOTE, 0, lo->W - 12.0);
	free(line);
	return 0;
}

static int draw(cairo_t *cr, const bk_plot *p)
{
	layout lo;
	int nl = count_labels(p);
	bk_plot_label *lab = malloc(sizeof *lab * (size_t)(nl + 1));
	if (!lab || settle(cr, p, &lo, lab) < 0) {
		free(lab);
		return -1;
	}
	cairo_set_source_rgb(cr, 1, 1, 1);
	cairo_paint(cr);
	if (p->heat && draw_heat(cr, p, &lo)) {
		free(lab);
		return -1;
	}
	draw_axes(cr, p, &lo);
	for (int s = 0; s < p->nseries; s++)
		draw_series(cr, p, &lo, &p->series[s]);
	for (int k = 0; k < nl; k++) { /* a label set apart (the second ring) is tied to its marker */
		const bk_plot_series *S = &p->series[lab[k].series];
		double px, py, qx, qy;
		if (!lab[k].placed || !visible(&lo, p, S->x[lab[k].point], S->y[lab[k].point], &px, &py))
			continue;
		nearest_on((box){lab[k].x0, lab[k].y0, lab[k].x1, lab[k].y1}, px, py, &qx, &qy);
		double d = hypot(qx - px, qy - py);
		if (d <= 1.5 * (MARK_R + 1.0)) /* the first ring's: beside its marker, no leader */
			continue;
		cairo_set_source_rgb(cr, 0.45, 0.45, 0.45);
		cairo_set_line_width(cr, 0.4);
		cairo_move_to(cr, px + (qx - px) * (MARK_R + 0.5) / d, py + (qy - py) * (MARK_R + 0.5) / d);
		cairo_line_to(cr, qx, qy);
		cairo_stroke(cr);
	}
	set_font(cr, FS_LABEL, 0);
	for (int k = 0; k < nl; k++)
		if (lab[k].placed) {
			/* white halo first: a label stays legible over a grid line or a step */
			char num[16];
			snprintf(num, sizeof num, "%d", lab[k].key);
			cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
			text_at(cr, lab[k].x0, lab[k].y1 - FS_LABEL * 0.2, 0.0,
			        lab[k].key ? num : p->series[lab[k].series].label[lab[k].point]);
		}
	draw_frame(cr, p, &lo);
	if (p->heat)
		draw_bar(cr, p, &lo);
	draw_legend(cr, p, &lo);
	int rc = draw_note(cr, p, &lo, lab, nl);
	free(lab);
	if (rc)
		return -1;
	return cairo_status(cr) == CAIRO_STATUS_SUCCESS ? 0 : -1;
}

int bk_plot_unexplained(const bk_plot *p)
{
	int hollow_key = 0;
	for (int s = 0; s < p->nseries; s++)
		hollow_key |= p->series[s].name && p->series[s].hollow && p->series[s].n == 0;
	layout lo;
	cairo_surface_t *sf;
	cairo_t *cr = measure_ctx(&sf);
	settled_layout(cr, p, &lo);
	cairo_destroy(cr);
	cairo_surface_destroy(sf);
	for (int s = 0; s < p->nseries; s++) {
		const bk_plot_series *S = &p->series[s];
		int drawn = 0;
		double px, py;
		for (int i = 0; i < S->n && !drawn; i++)
			drawn = visible(&lo, p, S->x[i], S->y[i], &px, &py);
		if (!drawn || S->name)
			continue;
		int ok = 0;
		for (int t = 0; t < p->nseries && !ok; t++) {
			const bk_plot_series *E = &p->series[t];
			if (!E->name || E->style != S->style || E->marker != S->marker || E->rgb != S->rgb)
				continue;
			ok = S->style != BK_PLOT_POINTS || !E->hollow == !S->hollow || (S->hollow && hollow_key);
		}
		if (!ok)
			return s;
	}
	return -1;
}

/* ---- output ------------------------------------------------------------------------ */

static cairo_status_t to_file(void *closure, const unsigned char *data, unsigned int len)
{
	return fwrite(data, 1, len, closure) == len ? CAIRO_STATUS_SUCCESS : CAIRO_STATUS_WRITE_ERROR;
}

/* Cairo's pixels (premultiplied ARGB on white, so opaque) as 8-bit RGB with tEXt
 * title, description and software and the print size (pngio.h: no tIME chunk,
 * fixed zlib level). */
static int write_png(const bk_plot *p, cairo_surface_t *s, FILE *f)
{
	int w = cairo_image_surface_get_width(s), h = cairo_image_surface_get_height(s);
	int stride = cairo_image_surface_get_stride(s);
	const unsigned char *d = cairo_image_surface_get_data(s);
	unsigned char *rgb = malloc((size_t)w * (size_t)h * 3);
	if (!rgb)
		return -1;
	for (int y = 0; y < h; y++) {
		const uint32_t *px = (const uint32_t *)(d + (size_t)y * stride);
		unsigned char *row = rgb + (size_t)y * (size_t)w * 3;
		for (int x = 0; x < w; x++) {
			row[3 * x] = (unsigned char)(px[x] >> 16);
			row[3 * x + 1] = (unsigned char)(px[x] >> 8);
			row[3 * x + 2] = (unsigned char)px[x];
		}
	}
	const bk_png_text text[3] = {
		{"Title", p->title ? p->title : ""},
		{"Description", p->provenance ? p->provenance : ""},
		{"Software", "brdfkit " BK_VERSION " (cairo)"},
	};
	char err[256];
	int rc = bk_png_write(f, w, h, 3, 1, BK_PLOT_DPI, rgb, text, 3, err, sizeof err);
	free(rgb);
	return rc;
}

/* Writes svg[0..len) with cairo's surface and image ids ("surface<N>", "image<N>":
 * numbers from a counter that lives as long as the process) renumbered in order of
 * first appearance, so a figure's bytes do not depend on how many were drawn before
 * it. Only names right after id=" or # are ids (base64 data may spell anything). */
static void put_renumbered(const char *svg, size_t len, FILE *f)
{
	enum { MAXID = 64 };
	static const char *const key[2] = {"surface", "image"};
	long seen[2][MAXID];
	int nseen[2] = {0, 0};
	size_t i = 0;
	for (size_t j = 0; j < len; j++) {
		int after_id = (j >= 4 && !memcmp(svg + j - 4, "id=\"", 4)) || (j >= 1 && svg[j - 1] == '#');
		int kk = -1;
		for (int t = 0; t < 2 && after_id && kk < 0; t++) {
			size_t k = strlen(key[t]);
			if (j + k < len && !memcmp(svg + j, key[t], k) && svg[j + k] >= '0' && svg[j + k] <= '9')
				kk = t;
		}
		if (kk < 0)
			continue;
		size_t at = j + strlen(key[kk]), end = at;
		long n = 0;
		while (end < len && svg[end] >= '0' && svg[end] <= '9' && n < 100000000)
			n = n * 10 + (svg[end++] - '0');
		int id = 0;
		while (id < nseen[kk] && seen[kk][id] != n)
			id++;
		if (id == nseen[kk] && nseen[kk] < MAXID)
			seen[kk][nseen[kk]++] = n;
		fwrite(svg + i, 1, at - i, f);
		fprintf(f, "%d", id + 1);
		i = j = end;
		j--;
	}
	fwrite(svg + i, 1, len - i, f);
}

/* The SVG with the provenance as a comment after cairo's XML declaration (nothing
 * may stand before it); an XML comment may not hold "--". */
static int svg_with_comment(const bk_plot *p, const char *svg, size_t len, FILE *f)
{
	const char *nl = memchr(svg, '\n', len);
	size_t head = nl ? (size_t)(nl - svg) + 1 : 0;
	fwrite(svg, 1, head, f);
	if (p->provenance) {
		fputs("<!-- ", f);
		for (const char *c = p->provenance; *c; c++)
			fputc(*c == '-' && c[1] == '-' ? '=' : *c, f);
		fputs(" -->\n", f);
	}
	put_renumbered(svg + head, len - head, f);
	return ferror(f) ? -1 : 0;
}

int bk_plot_write(const bk_plot *p, bk_plot_format fmt, FILE *f)
{
	double W = p->width_in * 72.0, H = p->height_in * 72.0;
	char *mem = NULL;
	size_t memlen = 0;
	FILE *out = f;
	cairo_surface_t *s;
	if (fmt == BK_PLOT_PNG)
		s = cairo_image_surface_create(CAIRO_FORMAT_RGB24, (int)lround(p->width_in * BK_PLOT_DPI),
		                               (int)lround(p->height_in * BK_PLOT_DPI));
	else if (fmt == BK_PLOT_SVG) {
		if (!(out = open_memstream(&mem, &memlen)))
			return -1;
		s = cairo_svg_surface_create_for_stream(to_file, out, W, H);
		cairo_svg_surface_restrict_to_version(s, CAIRO_SVG_VERSION_1_1);
	} else {
		s = cairo_pdf_surface_create_for_stream(to_file, f, W, H);
		cairo_pdf_surface_set_metadata(s, CAIRO_PDF_METADATA_CREATE_DATE, BK_PLOT_PDF_DATE);
		cairo_pdf_surface_set_metadata(s, CAIRO_PDF_METADATA_CREATOR, "brdfkit " BK_VERSION);
		if (p->title)
			cairo_pdf_surface_set_metadata(s, CAIRO_PDF_METADATA_TITLE, p->title);
		if (p->provenance)
			cairo_pdf_surface_set_metadata(s, CAIRO_PDF_METADATA_SUBJECT, p->provenance);
	}
	cairo_t *cr = cairo_create(s);
	if (fmt == BK_PLOT_PNG)
		cairo_scale(cr, BK_PLOT_DPI / 72.0, BK_PLOT_DPI / 72.0);
	int rc = draw(cr, p);
	cairo_destroy(cr);
	cairo_surface_flush(s);
	if (rc == 0 && fmt == BK_PLOT_PNG)
		rc = write_png(p, s, f);
	cairo_surface_finish(s); /* the SVG and PDF are written here */
	if (cairo_surface_status(s) != CAIRO_STATUS_SUCCESS)
		rc = -1;
	cairo_surface_destroy(s);
	if (fmt == BK_PLOT_SVG) {
		if (fclose(out))
			rc = -1;
		if (rc == 0)
			rc = svg_with_comment(p, mem, memlen, f);
		free(mem);
	}
	return rc || ferror(f) ? -1 : 0;
}

int bk_plot_write_files(const bk_plot *p, const char *dir, const char *stem, char *err, size_t errlen)
{
	static const char *const ext[3] = {"png", "svg", "pdf"};
	for (int k = 0; k < 3; k++) {
		char path[4400];
		snprintf(path, sizeof path, "%.4000s/%.300s.%s", dir, stem, ext[k]);
		FILE *f = bk_out_fopen(path, err, errlen); /* failures name the file and the errno */
		if (!f)
			return -1;
		int rc = bk_plot_write(p, (bk_plot_format)k, f);
		if (bk_out_fclose(f, path, err, errlen))
			return -1;
		if (rc) { /* no write failed: cairo's drawing did */
			snprintf(err, errlen, "%s: drawing the figure failed", path);
			return -1;
		}
	}
	return 0;
}
