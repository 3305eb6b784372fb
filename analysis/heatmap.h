/*
 * heatmap.h — error maps of a fitted approximation over a 2-D plane, written five
 * ways: a figure as PNG, SVG and PDF for a person or a paper (plot.h: diverging
 * colours, colour bar, axes in the plane's values), a FLOAT OpenEXR for tools, and a
 * tidy CSV for any plotting program. All share one convention, stated in each file:
 *
 *   cells      value[j * nx + i], i = 0..nx-1 along x, j = 0..ny-1 along y
 *   ranges     x0, x1, y0, y1 are the outer cell EDGES of the plane, so cell (i, j)
 *              covers [x0 + i dx, x0 + (i + 1) dx] and its centre is
 *              x = x0 + (i + 0.5) dx, dx = (x1 - x0)/nx (likewise y with dy, j, ny)
 *   origin     y0 at the bottom, as a person reads a plot: in the figure and the EXR the
 *              last (bottom) row holds j = 0, the first (top) row j = ny - 1;
 *              x0 is on the left
 *   value      signed, e.g. error = approximation - target; NaN = no data
 */
#ifndef ANALYSIS_HEATMAP_H
#define ANALYSIS_HEATMAP_H

#include <stddef.h>

typedef struct bk_heatmap {
	int nx, ny;                /* cells, each 1..BK_HEATMAP_MAX_CELLS */
	const double *value;       /* nx * ny values, value[j * nx + i]; NaN = no data */
	double x0, x1, y0, y1;     /* cell edges (see above); finite, x0 != x1, y0 != y1 */
	const char *xname, *yname; /* axis labels, units in brackets: "theta (deg)" */
	const char *title;         /* figure title, EXR/CSV provenance */
	const char *value_name;    /* what value is: CSV column, colour bar label */
	const char *conventions;   /* free text into the EXR header and CSV comments */
} bk_heatmap;

/* Cells per axis; keeps every size computation far from int overflow. */
#define BK_HEATMAP_MAX_CELLS 16384

/*
 * Writes DIR/<stem>.exr, .png, .csv, .svg and .pdf.
 *   EXR  nx x ny, one FLOAT channel "Y" = value (signed, NaN kept), ZIP, with string
 *        attributes brdfkit:title, brdfkit:axes, brdfkit:origin, brdfkit:value,
 *        brdfkit:conventions, brdfkit:version.
 *   PNG, SVG, PDF  one figure (plot.h), 3.5 x 2.9 in (a paper's single column; the
 *        PNG at BK_PLOT_DPI): the cells drawn as nearest-neighbour blocks over their
 *        edges on linear axes in the plane's units (x0 left, y0 bottom; reversed
 *        ranges drawn reversed), ticks with values, xname and yname as axis labels,
 *        title above; colour scale symmetric about zero: ColorBrewer RdBu, blue =
 *        -max|value|, near white = 0, red = +max|value| over the finite values; NaN
 *        grey (128,128,128) and a "grey: no data" footnote, +-inf the extreme colours;
 *        a colour bar labelled value_name (a plane one cell high: a line instead, see
 *        bk_heatmap_figure). Text in DejaVu Sans, long names shrunk to
 *        fit. Title and a description (scale, conventions) in PNG tEXt, the PDF's
 *        metadata and an SVG comment. Same bytes for the same input.
 *   CSV  '#' comment lines (title, axes, conventions), a header naming the columns
 *        after xname, yname and value_name (sanitised to [A-Za-z0-9_]), then one row
 *        per cell, x fastest, cell-centre coordinates, %.9g, NaN as an empty field.
 * NULL names fall back to "x", "y", "value"; NULL title and conventions to "".
 *
 * All or nothing: the five files are first written completely to temporary files
 * (mkstemp, "<final>.tmpXXXXXX" in DIR), then renamed into place one after another.
 * Every write error happens before the first rename, and then existing files are
 * untouched. Should a rename itself fail (say a directory stands at DIR/<stem>.png),
 * the files already renamed and the older files at the remaining names are removed,
 * so the stem is never left with a mix of old and new files. No temporary survives.
 * Returns 0, or -1 with one lowercase line "path: what went wrong" in err (errlen
 * bytes, always NUL-terminated when errlen > 0).
 */
int bk_heatmap_write(const bk_heatmap *h, const char *dir, const char *stem, char *err,
                     size_t errlen);

/* How the figure colours and labels a map (NULL: as bk_heatmap_write says). */
typedef struct bk_heatmap_style {
	int sequential;          /* magnitudes, shares: BK_PLOT_SEQUENTIAL from 0 (dark) to top (light) */
	double top;              /* the scale's top; <= 0: the largest finite value */
	const char *const *xcat; /* NULL, or nx labels: cell i stands for the sample xcat[i] (the axis is
	                            ticked at cell centres with them; the CSV's x column holds them) */
	const char *const *ycat; /* likewise ny labels for y */
} bk_heatmap_style;

int bk_heatmap_write_styled(const bk_heatmap *h, const bk_heatmap_style *st, const char *dir, const char *stem,
                            char *err, size_t errlen);

/* What the figure draws: a map (cells under a colour bar) or, for a plane one cell high
 * without y categories (a 1-input target, f over LoH), the value as a line against x,
 * its y axis labelled value_name (symmetric about zero for signed error), no colour bar;
 * the EXR and CSV stay nx x 1 as above. Labels point into h or the style. Returns 0, or
 * -1 with a message as bk_heatmap_png_layout's. */
enum { BK_HEATMAP_MAP, BK_HEATMAP_LINE };
typedef struct bk_heatmap_figure_info {
	int kind;                   /* BK_HEATMAP_MAP or BK_HEATMAP_LINE */
	const char *xlabel, *ylabel;
	int colour_bar;             /* drawn */
	double ylo, yhi;            /* the y axis range */
} bk_heatmap_figure_info;
int bk_heatmap_figure(const bk_heatmap *h, const bk_heatmap_style *st, bk_heatmap_figure_info *out, char *err,
                      size_t errlen);

/* Where things land in the PNG, in pixels from its top-left corner: the pixels whose
 * centres lie inside the plot rectangle (the cells' edges x0..x1, y0..y1) and inside
 * the colour bar (top row +max|value|, bottom row -max|value|). Cell (i, j) covers
 * plot_x + [i, i + 1) plot_w / nx and, from the bottom, [j, j + 1) plot_h / ny, to
 * within a pixel. A frame surrounds both, on their edges. */
typedef struct bk_heatmap_layout {
	int width, height;
	int plot_x, plot_y, plot_w, plot_h;
	int bar_x, bar_y, bar_w, bar_h;
} bk_heatmap_layout;

/* The layout bk_heatmap_write uses for h. Returns 0, or -1 with a message as above
 * (path replaced by "heatmap") when h is not valid. */
int bk_heatmap_png_layout(const bk_heatmap *h, bk_heatmap_layout *out, char *err,
                          size_t errlen);

#endif
