/*
 * plot.h — every figure brdfkit draws, on cairo: axes (linear or log, ticks with
 * values, axis labels with units), series (markers, Pareto staircases, lines, labelled
 * markers that never overprint), an optional heatmap with its colour bar, a legend, and
 * a footnote. One description of a figure is rendered to PNG, SVG and PDF alike.
 *
 * Contract
 *   size     width_in x height_in inches (a paper's single column is 3.5 in wide, its
 *            double column 7 in: BK_PLOT_SINGLE_W, BK_PLOT_DOUBLE_W); drawing units are
 *            points (1/72 in) in every format; the PNG is BK_PLOT_DPI dots per inch.
 *   text     cairo's toy API, family "DejaVu Sans" (Debian fonts-dejavu-core), metrics
 *            unhinted, so text is measured the same in every format and on every machine
 *            with that font; strings are UTF-8 (invalid bytes are shown as '?').
 *   labels   placed greedily, the labels of filled markers' series before those of
 *            hollow ones', each in series order, then point order: the first of 8
 *            positions around the marker (right, upper right, above, upper left, left,
 *            lower left, below, lower right), then the same twice and three times as far
 *            out (tied to the marker by a thin grey leader that crosses no marker and no
 *            label), whose box stays inside the plot area and meets no marker, no staircase
 *            step, no error bar, no segment of a line, no leader and no label placed
 *            before; a label with no such
 *            position is drawn as a number in the first such position for the number,
 *            the footnote's key naming it ("key: 1 name, 2 name"); with no place even
 *            for that it is named in the footnote ("N not labelled (no free place): a,
 *            b"). The footnote wraps onto up to 8 lines (the plot grows shorter), "..."
 *            ending the last when even that is not enough.
 *   colours  sequential data (magnitudes, shares): BK_PLOT_SEQUENTIAL, a map of our own
 *            computation with OKLab lightness rising linearly 0.30 -> 0.92 (dark blue-
 *            violet to pale yellow); signed error: BK_PLOT_DIVERGING, ColorBrewer RdBu
 *            (blue negative, white zero, red positive), symmetric about zero.
 *   bytes    the same figure gives the same bytes: the PDF's creation date is fixed
 *            (BK_PLOT_PDF_DATE), no time goes into the PNG, and cairo numbers the
 *            SVG's and PDF's objects per document.
 */
#ifndef ANALYSIS_PLOT_H
#define ANALYSIS_PLOT_H

#include <stddef.h>
#include <stdio.h>

#define BK_PLOT_SINGLE_W 3.5
#define BK_PLOT_DOUBLE_W 7.0
#define BK_PLOT_DPI 200
#define BK_PLOT_FONT "DejaVu Sans"
#define BK_PLOT_TICK_PT 7.0 /* tick labels' and the legend's font size, pt (a page shows a PNG's
                               at BK_PLOT_TICK_PT * BK_PLOT_DPI / 72 px times its display scale) */
#define BK_PLOT_PDF_DATE "2000-01-01T00:00:00Z"

typedef struct bk_plot_axis {
	const char *label;  /* with its unit: "cost (simple ALU ops)" */
	int log;            /* log10 axis: lo > 0 */
	double lo, hi;      /* the axis range, lo < hi (bk_plot_axis_fit makes one) */
	int zero_at_lo;     /* log only: values <= 0 are drawn at lo, whose tick reads "0" */
	int ncat;           /* > 0: linear, ncat equal cells lo..hi, each ticked at its centre */
	const char *const *cat; /* with the label cat[k] (e.g. the sample value it stands for) */
} bk_plot_axis;

/* series style: markers; a dashed staircase (right, then down: a Pareto front) through
 * the points in the order given; a solid line. Markers and steps keep labels off,
 * except BK_PLOT_DOT markers, a background cloud labels may cover. */
enum { BK_PLOT_POINTS, BK_PLOT_STEPS, BK_PLOT_LINE };
enum { BK_PLOT_CIRCLE, BK_PLOT_SQUARE, BK_PLOT_TRIANGLE, BK_PLOT_DOT }; /* markers */

typedef struct bk_plot_series {
	const char *name;          /* legend entry; NULL: none */
	int style, marker, hollow; /* hollow: white marker, coloured outline */
	unsigned rgb;              /* 0xRRGGBB */
	int n;
	const double *x, *y;       /* n points; non-finite points are skipped */
	const char *const *label;  /* NULL, or n labels (NULL entries: unlabelled) */
	const double *xlo, *xhi;   /* NULL, or n horizontal bars (e.g. min..max time) */
} bk_plot_series;

enum { BK_PLOT_SEQUENTIAL, BK_PLOT_DIVERGING };

typedef struct bk_plot_heat {
	int nx, ny;
	const double *value;       /* value[j * nx + i], j = 0 at y0; NaN = no data (grey) */
	double x0, x1, y0, y1;     /* outer cell edges, in data units of the axes */
	int map;                   /* BK_PLOT_SEQUENTIAL or BK_PLOT_DIVERGING */
	double vmin, vmax;         /* colour range (diverging: -m..m is used, m = max |.|) */
	const char *label;         /* colour bar label, with its unit */
} bk_plot_heat;

typedef struct bk_plot {
	double width_in, height_in;
	const char *title;         /* NULL: none */
	const char *note;          /* a grey footnote line, or NULL */
	const char *provenance;    /* PNG tEXt "Description", PDF subject, SVG comment */
	bk_plot_axis x, y;
	const bk_plot_series *series;
	int nseries;
	const bk_plot_heat *heat;  /* NULL, or drawn under the series */
} bk_plot;

typedef enum { BK_PLOT_PNG, BK_PLOT_SVG, BK_PLOT_PDF } bk_plot_format;

/* A range for values v[0..n-1] (non-finite and, on a log axis, non-positive ones
 * skipped): linear from min(0, min v) to a round number above max v + 2 % of the span; log from the
 * decade below the smallest to the decade above the largest (1e-3..1 when none). */
void bk_plot_axis_fit(bk_plot_axis *a, const double *v, int n);
/* Widens a to the union of its range and v's fitted range (lo = hi = 0: none yet). */
void bk_plot_axis_grow(bk_plot_axis *a, const double *v, int n);

/* The labelled ticks an axis gets for about `want` intervals (the figure asks 6 of x,
 * 5 of y; categories: one per cell): at least BK_PLOT_MIN_TICKS of them inside
 * [lo, hi] on every linear or log range (log: 1-2-5 or every digit within too few
 * decades), each label distinct and reading back within a thousandth of the step of
 * its value. Writes at most max; returns how many there are (at most max). */
#define BK_PLOT_TICK_LEN 24
#define BK_PLOT_MIN_TICKS 3
int bk_plot_ticks(const bk_plot_axis *a, int want, double *v, char (*text)[BK_PLOT_TICK_LEN], int max);
/* The colour bar's labelled ticks for a heatmap (as bk_plot_ticks, over its range). */
int bk_plot_bar_ticks(const bk_plot_heat *h, double *v, char (*text)[BK_PLOT_TICK_LEN], int max);

/* Writes the figure to f in one format. Returns 0, or -1 (cairo or write error). */
int bk_plot_write(const bk_plot *p, bk_plot_format fmt, FILE *f);
/* DIR/STEM.png, .svg and .pdf. Returns 0, or -1 with "path: what" in err. */
int bk_plot_write_files(const bk_plot *p, const char *dir, const char *stem, char *err, size_t errlen);

/* x tick labels wider than their spacing are drawn turned upright (the plot grows
 * shorter to make room). */

/* Where a data point lands, in points from the figure's top-left corner (times
 * BK_PLOT_DPI/72 for PNG pixels). */
void bk_plot_to_page(const bk_plot *p, double x, double y, double *px, double *py);
/* The same for n points (x[i], y[i]) into px[i], py[i]: the figure is laid
 * out once (its labels placed), not once per point. */
void bk_plot_to_page_n(const bk_plot *p, int n, const double *x, const double *y, double *px, double *py);

/* The plot area and the colour bar (zero width without a heatmap) as left, top,
 * right, bottom in points from the top-left corner; the frames are drawn on these
 * edges. The heatmap's image fills its edges x0..x1, y0..y1 (y1 at the top). */
void bk_plot_areas(const bk_plot *p, double plot[4], double bar[4]);

/* The label placement (see the contract): for each label in order, its series and
 * point, whether placed, and its box in points. Returns the number of labels, at most
 * max written; -1 when out of memory. */
typedef struct bk_plot_label {
	int series, point, placed;
	double x0, y0, x1, y1;
	int key;  /* > 0: placed as this number, named in the footnote's key */
} bk_plot_label;
int bk_plot_labels(const bk_plot *p, bk_plot_label *out, int max);

/* The boxes of the marks labels keep off, in points as above: markers (not dots),
 * staircase steps and error bars (1.2 pt thick), in series and point order; a line
 * series' segments are kept off as segments and not listed. Returns how many (at
 * most max written), or -1 when out of memory. */
int bk_plot_marks(const bk_plot *p, double (*box)[4], int max);

/* The first series with a visible marker the legend does not explain, or -1: a
 * marker is explained by a legend entry (named series) of its own, or by one of
 * the same shape and colour, filled or hollow as it is, or, hollow, by one of the
 * same shape and colour filled beside a named hollow series of no points (a key
 * "hollow: what it means"). Lines and steps: by their own name. */
int bk_plot_unexplained(const bk_plot *p);

/* The colour of t in [0, 1] (clamped) on a map, 8-bit sRGB. */
void bk_plot_colour(int map, double t, unsigned char rgb[3]);

#endif
