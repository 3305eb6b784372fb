/*
 * test_plot.c — analysis/plot.c, the figure module on cairo.
 *
 * Independent sources: the PNG is read back with libpng and the plot frame found
 * from its pixels (the darkest columns and rows), so a planted marker's
 * expected pixel comes from the frame and a hand interpolation, not from the
 * module's layout; lightness is CIE L* computed here from the sRGB definition;
 * label boxes are checked pairwise; the PDF and SVG by their bytes and by xmllint.
 * Each check has a negative control that shows it can fail.
 */
#include "plot.h"
#include "csvtab.h"

#include <criterion/criterion.h>

#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* ---- helpers --------------------------------------------------------------------- */

typedef struct image {
	int w, h;
	unsigned char *rgb;
} image;

/* The figure as PNG through a temporary file, read back with libpng (8-bit RGB). */
static image render_png(const bk_plot *p)
{
	FILE *f = tmpfile();
	cr_assert_not_null(f);
	cr_assert_eq(bk_plot_write(p, BK_PLOT_PNG, f), 0);
	rewind(f);
	png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
	png_infop info = png_create_info_struct(png);
	cr_assert_not_null(info);
	cr_assert_eq(setjmp(png_jmpbuf(png)), 0, "libpng could not read the PNG");
	png_init_io(png, f);
	png_read_info(png, info);
	image im = {(int)png_get_image_width(png, info), (int)png_get_image_height(png, info), NULL};
	cr_assert_eq(png_get_color_type(png, info), PNG_COLOR_TYPE_RGB);
	cr_assert_eq(png_get_bit_depth(png, info), 8);
	im.rgb = malloc((size_t)im.w * im.h * 3);
	for (int y = 0; y < im.h; y++)
		png_read_row(png, im.rgb + (size_t)y * im.w * 3, NULL);
	png_destroy_read_struct(&png, &info, NULL);
	fclose(f);
	return im;
}

static const unsigned char *px(const image *im, int x, int y)
{
	return im->rgb + ((size_t)y * im->w + x) * 3;
}

static int dark(const unsigned char *c)
{
	return c[0] < 70 && c[1] < 70 && c[2] < 70;
}

/* The first two clusters (runs no more than 3 apart) of the lines whose dark
 * pixel count is at least 90 % of the largest: a frame's two edges (a colour
 * bar's frame, right of the plot, would be the third). */
static void two_edges(const int *count, int n, double *first, double *second)
{
	int top = 0;
	for (int i = 0; i < n; i++)
		top = count[i] > top ? count[i] : top;
	double s[2] = {0, 0};
	int m[2] = {0, 0}, c = -1, last = -10;
	for (int i = 0; i < n && c < 2; i++) {
		if (count[i] < 0.9 * top)
			continue;
		if (i - last > 3)
			c++;
		last = i;
		if (c < 2)
			s[c] += i, m[c]++;
	}
	cr_assert(m[0] > 0 && m[1] > 0, "no frame found");
	*first = s[0] / m[0];
	*second = s[1] / m[1];
}

/* The plot frame from the pixels alone. */
static void find_frame(const image *im, double *L, double *R, double *T, double *B)
{
	int *col = calloc((size_t)im->w, sizeof *col), *row = calloc((size_t)im->h, sizeof *row);
	for (int y = 0; y < im->h; y++)
		for (int x = 0; x < im->w; x++)
			if (dark(px(im, x, y)))
				col[x]++, row[y]++;
	two_edges(col, im->w, L, R);
	two_edges(row, im->h, T, B);
	free(col);
	free(row);
}

/* The centroid of the pure-red pixels (the planted marker). */
static void red_centroid(const image *im, double *cx, double *cy)
{
	double sx = 0, sy = 0;
	int n = 0;
	for (int y = 0; y < im->h; y++)
		for (int x = 0; x < im->w; x++) {
			const unsigned char *c = px(im, x, y);
			if (c[0] > 200 && c[1] < 60 && c[2] < 60)
				sx += x, sy += y, n++;
		}
	cr_assert_gt(n, 4, "the red marker is not in the image");
	*cx = sx / n;
	*cy = sy / n;
}

/* CIE L* of an 8-bit sRGB colour (IEC 61966-2-1 decoding, D65 luminance weights). */
static double lightness(const unsigned char c[3])
{
	double lin[3];
	for (int k = 0; k < 3; k++) {
		double v = c[k] / 255.0;
		lin[k] = v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4);
	}
	double Y = 0.2126 * lin[0] + 0.7152 * lin[1] + 0.0722 * lin[2];
	return Y > 216.0 / 24389.0 ? 116.0 * cbrt(Y) - 16.0 : Y * 24389.0 / 27.0;
}

/* ---- a planted point lands on its pixel ------------------------------------------------ */

static double px_x[1] = {3.0}, px_y[1] = {7.0};

static bk_plot planted(double xhi)
{
	static bk_plot_series s;
	s = (bk_plot_series){NULL, BK_PLOT_POINTS, BK_PLOT_SQUARE, 0, 0xff0000, 1, px_x, px_y, NULL, NULL, NULL};
	bk_plot p = {2.0, 1.5, NULL, NULL, NULL, {"x (unit)", 0, 0.0, xhi, 0, 0, NULL}, {"y (unit)", 0, 0.0, 10.0, 0, 0, NULL}, &s, 1, NULL};
	return p;
}

Test(plot, planted_point_on_its_pixel)
{
	bk_plot p = planted(10.0);
	image im = render_png(&p);
	cr_expect_eq(im.w, 2 * BK_PLOT_DPI);
	cr_expect_eq(im.h, (int)(1.5 * BK_PLOT_DPI));
	double L, R, T, B, cx, cy;
	find_frame(&im, &L, &R, &T, &B);
	red_centroid(&im, &cx, &cy);
	/* by hand: x = 3 of 0..10, y = 7 of 0..10 (up from the bottom edge) */
	double ex = L + 0.3 * (R - L), ey = B - 0.7 * (B - T);
	cr_expect_leq(fabs(cx - ex), 1.5, "marker at x %.2f px, expected %.2f", cx, ex);
	cr_expect_leq(fabs(cy - ey), 1.5, "marker at y %.2f px, expected %.2f", cy, ey);
	free(im.rgb);

	/* negative control: drawn on 0..20, the marker misses the 0..10 expectation */
	p = planted(20.0);
	im = render_png(&p);
	find_frame(&im, &L, &R, &T, &B);
	red_centroid(&im, &cx, &cy);
	ex = L + 0.3 * (R - L);
	cr_expect_gt(fabs(cx - ex), 20.0, "the wrong range should move the marker, at %.2f vs %.2f", cx, ex);
	free(im.rgb);
}

Test(plot, log_axis_point_on_its_pixel)
{
	static double x[1] = {5.0}, y[1] = {1e-2};
	bk_plot_series s = {NULL, BK_PLOT_POINTS, BK_PLOT_SQUARE, 0, 0xff0000, 1, x, y, NULL, NULL, NULL};
	bk_plot p = {2.0, 1.5, NULL, NULL, NULL, {"x", 0, 0, 10, 0, 0, NULL}, {"err", 1, 1e-4, 1.0, 0, 0, NULL}, &s, 1, NULL};
	image im = render_png(&p);
	double L, R, T, B, cx, cy;
	find_frame(&im, &L, &R, &T, &B);
	red_centroid(&im, &cx, &cy);
	double ey = B - 0.5 * (B - T); /* 1e-2 halfway between 1e-4 and 1 in log */
	cr_expect_leq(fabs(cy - ey), 1.5, "marker at y %.2f px, expected %.2f", cy, ey);
	cr_expect_gt(fabs(cy - (B - 0.01 * (B - T))), 20.0, "a linear axis would put it at the bottom");
	free(im.rgb);
}

/* ---- colour maps -------------------------------------------------------------------- */

static int lightness_rises(int map, double *lo, double *hi)
{
	unsigned char c[3];
	double prev = -1.0;
	int ok = 1;
	for (int k = 0; k <= 64; k++) {
		bk_plot_colour(map, k / 64.0, c);
		double l = lightness(c);
		if (k == 0)
			*lo = l;
		*hi = l;
		ok &= l > prev;
		prev = l;
	}
	return ok;
}

Test(plot, sequential_map_ends_and_monotone_lightness)
{
	double lo, hi;
	cr_expect(lightness_rises(BK_PLOT_SEQUENTIAL, &lo, &hi), "sequential: lightness must rise throughout");
	cr_expect_lt(lo, 30.0, "dark end L* %.1f", lo);
	cr_expect_gt(hi, 85.0, "light end L* %.1f", hi);
	/* evenly: no step of 1/64 changes L* by more than twice the mean step */
	unsigned char a[3], b[3];
	for (int k = 0; k < 64; k++) {
		bk_plot_colour(BK_PLOT_SEQUENTIAL, k / 64.0, a);
		bk_plot_colour(BK_PLOT_SEQUENTIAL, (k + 1) / 64.0, b);
		cr_expect_lt(lightness(b) - lightness(a), 2.0 * (hi - lo) / 64.0, "step %d", k);
	}
	/* negative control: the diverging map's lightness rises to white and falls again */
	cr_expect_not(lightness_rises(BK_PLOT_DIVERGING, &lo, &hi));
}

Test(plot, diverging_map_blue_white_red)
{
	unsigned char c[3];
	bk_plot_colour(BK_PLOT_DIVERGING, 0.0, c);
	cr_expect(c[2] > c[0] + 50, "negative end is blue (%d,%d,%d)", c[0], c[1], c[2]);
	bk_plot_colour(BK_PLOT_DIVERGING, 1.0, c);
	cr_expect(c[0] > c[2] + 50, "positive end is red (%d,%d,%d)", c[0], c[1], c[2]);
	bk_plot_colour(BK_PLOT_DIVERGING, 0.5, c);
	cr_expect_gt(lightness(c), 95.0, "zero is near white");
}

/* ---- label placement ----------------------------------------------------------------- */

static int boxes_meet(const bk_plot_label *a, const bk_plot_label *b)
{
	return a->x0 < b->x1 && b->x0 < a->x1 && a->y0 < b->y1 && b->y0 < a->y1;
}

/* Pairs of placed labels that overlap. */
static int overlaps(const bk_plot_label *l, int n)
{
	int k = 0;
	for (int i = 0; i < n; i++)
		for (int j = i + 1; j < n; j++)
			k += l[i].placed && l[j].placed && boxes_meet(&l[i], &l[j]);
	return k;
}

enum { NCROWD = 60 };

Test(plot, crowded_labels_never_overlap)
{
	static double x[NCROWD], y[NCROWD];
	static char name[NCROWD][24];
	static const char *lab[NCROWD];
	for (int i = 0; i < NCROWD; i++) { /* a tight cluster: a spiral of points in 2 x 2 data units */
		x[i] = 5.0 + 1.0 * sqrt(i / (double)NCROWD) * cos(2.4 * i);
		y[i] = 5.0 + 1.0 * sqrt(i / (double)NCROWD) * sin(2.4 * i);
		snprintf(name[i], sizeof name[i], "label %d", i);
		lab[i] = name[i];
	}
	bk_plot_series s = {NULL, BK_PLOT_POINTS, BK_PLOT_CIRCLE, 0, 0x1f77b4, NCROWD, x, y, lab, NULL, NULL};
	bk_plot p = {BK_PLOT_SINGLE_W, 2.6, "crowd", NULL, NULL, {"x", 0, 0, 10, 0, 0, NULL}, {"y", 0, 0, 10, 0, 0, NULL}, &s, 1, NULL};
	bk_plot_label l[NCROWD];
	cr_assert_eq(bk_plot_labels(&p, l, NCROWD), NCROWD);
	int placed = 0;
	for (int i = 0; i < NCROWD; i++)
		placed += l[i].placed;
	cr_expect_gt(placed, 5, "some labels find a place");
	cr_expect_lt(placed, NCROWD, "a cluster this tight cannot hold them all: some are dropped");
	cr_expect_eq(overlaps(l, NCROWD), 0, "placed labels overlap");
	/* no label covers a marker (2.4 pt radius); each marker's place on the
	 * page, all found in one layout (bk_plot_to_page_n); the first also one
	 * at a time, which must agree (the single-point call is the n = 1 case) */
	static double mx[NCROWD], my[NCROWD];
	bk_plot_to_page_n(&p, NCROWD, x, y, mx, my);
	double one_x, one_y;
	bk_plot_to_page(&p, x[0], y[0], &one_x, &one_y);
	cr_expect(one_x == mx[0] && one_y == my[0], "one point: (%g, %g), of n: (%g, %g)", one_x, one_y, mx[0], my[0]);
	for (int i = 0; i < NCROWD; i++)
		for (int j = 0; j < NCROWD && l[i].placed; j++) {
			bk_plot_label m = {0, j, 1, mx[j] - 2.4, my[j] - 2.4, mx[j] + 2.4, my[j] + 2.4, 0};
			cr_expect_not(boxes_meet(&l[i], &m), "label %d covers marker %d", i, j);
		}
	/* negative control: the overlap check sees two boxes planted on each other */
	bk_plot_label two[2] = {{0, 0, 1, 0, 0, 10, 5, 0}, {0, 1, 1, 5, 2, 15, 7, 0}};
	cr_expect_eq(overlaps(two, 2), 1);
	/* the picture says how many are left out */
	FILE *f = tmpfile();
	cr_assert_eq(bk_plot_write(&p, BK_PLOT_PDF, f), 0);
	fclose(f);
}

/* ---- bytes: PDF and SVG -------------------------------------------------------------- */

static char *render_bytes(const bk_plot *p, bk_plot_format fmt, size_t *len)
{
	char *buf = NULL;
	FILE *f = open_memstream(&buf, len);
	cr_assert_not_null(f);
	cr_assert_eq(bk_plot_write(p, fmt, f), 0);
	cr_assert_eq(fclose(f), 0);
	return buf;
}

Test(plot, pdf_is_a_pdf_and_byte_stable)
{
	bk_plot p = planted(10.0);
	p.title = "a title";
	p.provenance = "test_plot";
	size_t la, lb, lc;
	char *a = render_bytes(&p, BK_PLOT_PDF, &la), *b = render_bytes(&p, BK_PLOT_PDF, &lb);
	cr_expect_eq(strncmp(a, "%PDF-", 5), 0);
	cr_expect(la == lb && memcmp(a, b, la) == 0, "two PDFs of one figure differ");
	int dated = 0;
	for (size_t i = 0; i + 31 <= la && !dated; i++)
		dated = !memcmp(a + i, "/CreationDate (20000101000000Z)", 31);
	cr_expect(dated, "the fixed creation date");
	/* the font is DejaVu Sans, embedded (a subset "ABCDEF+DejaVuSans"), not a fallback */
	int dejavu = 0, other = 0;
	for (size_t i = 0; i + 11 <= la; i++) {
		dejavu |= !memcmp(a + i, "+DejaVuSans", 11);
		other |= !memcmp(a + i, "+LiberationS", 11); /* control: a font we do not use */
	}
	cr_expect(dejavu, "DejaVu Sans not embedded: is fonts-dejavu-core installed?");
	cr_expect_not(other);
	p.title = "another title"; /* negative control: a different figure, different bytes */
	char *c = render_bytes(&p, BK_PLOT_PDF, &lc);
	cr_expect(la != lc || memcmp(a, c, la) != 0);
	free(a);
	free(b);
	free(c);
}

static int xmllint_ok(const char *text, size_t len)
{
	char path[] = "/tmp/bk_test_plot_XXXXXX";
	int fd = mkstemp(path);
	cr_assert_geq(fd, 0);
	cr_assert_eq(write(fd, text, len), (ssize_t)len);
	close(fd);
	char cmd[128];
	snprintf(cmd, sizeof cmd, "xmllint --noout %s 2>/dev/null", path);
	int rc = system(cmd);
	unlink(path);
	return rc == 0;
}

Test(plot, svg_well_formed_and_byte_stable)
{
	if (system("command -v xmllint >/dev/null 2>&1") != 0)
		cr_skip_test("xmllint not installed (libxml2-utils)");
	static double x[2] = {1, 2}, y[2] = {3, 4};
	static const char *lab[2] = {"a <b> & \"c\"", "-- not a comment end --"};
	bk_plot_series s = {"kind & <more>", BK_PLOT_POINTS, BK_PLOT_CIRCLE, 0, 0x1f77b4, 2, x, y, lab, NULL, NULL};
	bk_plot p = {BK_PLOT_SINGLE_W, 2.6, "t <&>", "note --", "made -- by a test", {"x", 0, 0, 5, 0, 0, NULL},
	             {"y", 0, 0, 5, 0, 0, NULL}, &s, 1, NULL};
	size_t la, lb;
	char *a = render_bytes(&p, BK_PLOT_SVG, &la), *b = render_bytes(&p, BK_PLOT_SVG, &lb);
	cr_expect(la == lb && memcmp(a, b, la) == 0, "two SVGs of one figure differ");
	cr_expect(xmllint_ok(a, la), "xmllint rejected the SVG");
	cr_expect_null(strstr(a, "<b>"));
	cr_expect_not(xmllint_ok(a, la / 2), "negative control: half an SVG is not well-formed");
	free(a);
	free(b);
}

/* ---- heatmap and colour bar ------------------------------------------------------------ */

Test(plot, heatmap_cells_take_their_colours)
{
	static const double v[2] = {0.0, 1.0}; /* left cell low, right cell high */
	bk_plot_heat h = {2, 1, v, 0.0, 1.0, 0.0, 1.0, BK_PLOT_SEQUENTIAL, 0.0, 1.0, "share"};
	bk_plot p = {2.5, 1.5, NULL, NULL, NULL, {"NoV", 0, 0, 1, 0, 0, NULL}, {"r", 0, 0, 1, 0, 0, NULL}, NULL, 0, &h};
	image im = render_png(&p);
	double L, R, T, B;
	find_frame(&im, &L, &R, &T, &B);
	int y = (int)((T + B) / 2);
	double left = lightness(px(&im, (int)(L + 0.25 * (R - L)), y));
	double right = lightness(px(&im, (int)(L + 0.75 * (R - L)), y));
	cr_expect_lt(left, 30.0, "the low cell is dark (L* %.1f)", left);
	cr_expect_gt(right, 85.0, "the high cell is light (L* %.1f)", right);
	free(im.rgb);
}

/* ---- ticks: at least three, distinct, inside the range ------------------------------- */

/* Checks bk_plot_ticks over [lo, hi]: >= 3 labels, all distinct, each inside the range
 * and reading back (strtod) close to its tick. Returns the number of failures. */
static int tick_faults(int log, double lo, double hi, int want)
{
	bk_plot_axis a = {NULL, log, lo, hi, 0, 0, NULL};
	double v[32];
	char text[32][BK_PLOT_TICK_LEN];
	int n = bk_plot_ticks(&a, want, v, text, 32), bad = n < 3;
	double span = fabs(hi - lo);
	for (int i = 0; i < n; i++) {
		bad += v[i] < fmin(lo, hi) - 1e-9 * span || v[i] > fmax(lo, hi) + 1e-9 * span;
		double back = strtod(text[i], NULL);
		bad += !(fabs(back - v[i]) <= 1e-3 * span + 1e-300);
		for (int j = 0; j < i; j++)
			bad += strcmp(text[i], text[j]) == 0;
	}
	if (bad)
		cr_log_info("ticks on %g..%g (log %d): %d, first \"%s\"", lo, hi, log, n, n ? text[0] : "");
	return bad;
}

Test(plot, ticks_three_distinct_labels_in_every_range)
{
	int bad = 0, cases = 0;
	/* the committed defect: a diverging colour bar of +-0.00495586 had the one tick "0" */
	bad += tick_faults(0, -0.00495586, 0.00495586, 4), cases++;
	static const double mant[] = {1.0, 1.03, 1.5, 2.01, 2.5, 3.3, 4.02, 4.99, 5.01, 7.7, 9.99};
	for (int e = -12; e <= 12; e += 3)
		for (size_t k = 0; k < sizeof mant / sizeof mant[0]; k++) {
			double m = mant[k] * pow(10.0, e);
			for (int want = 3; want <= 6; want++) {
				bad += tick_faults(0, -m, m, want), cases++;        /* symmetric about zero */
				bad += tick_faults(0, 0, m, want), cases++;         /* from zero */
				bad += tick_faults(0, -3 * m, -m, want), cases++;   /* all negative */
				if (m >= 1e-6) /* a tiny span far from zero, well above double's resolution */
					bad += tick_faults(0, 1.0, 1.0 + m * 1e-3, want), cases++;
				bad += tick_faults(0, m, 1.0001 * m, want), cases++;
			}
			bad += tick_faults(1, m, 10 * m, 5), cases++;      /* log: about one decade */
			bad += tick_faults(1, m, 1.2 * m, 5), cases++;     /* log: less than a factor 3 */
			bad += tick_faults(1, m, 1e6 * m, 5), cases++;     /* log: many decades */
		}
	cr_log_info("%d tick ranges", cases);
	cr_expect_eq(bad, 0, "%d faults in %d tick ranges", bad, cases);
	/* negative controls: the checker fails a single tick and a repeated label */
	bk_plot_axis none = {NULL, 0, 0, 1, 0, 0, NULL};
	double v[2];
	char text[2][BK_PLOT_TICK_LEN];
	cr_expect_eq(bk_plot_ticks(&none, 5, v, text, 2), 2, "max bounds the count");
	cr_expect_gt(tick_faults(0, 5, 5 + 1e-15, 4), 0, "a range under double's resolution cannot take 3 distinct labels");
}

Test(plot, colour_bar_of_the_committed_heatmap_has_three_ticks)
{
	/* results/search/vf2d/front/search_vf2d_6/heatmap.png: max |error| 0.00495586
	 * (front.csv's max_abs) gave the step 0.005 and "0" alone */
	double m = 0.00495586, val[2] = {-m, 0.9 * m}, v[32];
	char text[32][BK_PLOT_TICK_LEN];
	bk_plot_heat h = {2, 1, val, 0, 1, 0, 1, BK_PLOT_DIVERGING, -m, m, "error"};
	int n = bk_plot_bar_ticks(&h, v, text, 32);
	cr_expect_geq(n, 3);
	for (int i = 0; i < n; i++)
		cr_expect(fabs(v[i]) <= m, "tick %s outside the bar", text[i]);
}

/* ---- labels: every front point labelled or keyed, no label on a drawn mark -------------- */

enum { MAXPTS = 64 };

typedef struct pts {
	int n;
	double x[MAXPTS], y[MAXPTS], lo[MAXPTS], hi[MAXPTS];
	char name[MAXPTS][96];
	const char *lab[MAXPTS];
} pts;

/* Reads x, y (and optional lo, hi) columns of a committed CSV by name; rows whose
 * join column (name) is in `also` take their x, lo, hi from it (timing.csv). */
static void read_pts(pts *P, const char *path, const char *xcol, const char *ycol)
{
	const char *cols[] = {"name", xcol, ycol, NULL};
	bk_csvtab_spec spec = {cols, 0, NULL, 0, 0, NULL, NULL};
	bk_csvtab t;
	char err[512];
	cr_assert_eq(bk_csvtab_read(path, &spec, &t, err, sizeof err), 0, "%s (run from the repository root)", err);
	P->n = 0;
	for (int i = 0; i < t.n && P->n < MAXPTS; i++) {
		double x, y;
		if (bk_csvtab_number(bk_csvtab_get(&t, i, 1), &x) || bk_csvtab_number(bk_csvtab_get(&t, i, 2), &y))
			continue;
		snprintf(P->name[P->n], sizeof P->name[0], "%s", bk_csvtab_get(&t, i, 0));
		P->lab[P->n] = P->name[P->n];
		P->x[P->n] = x, P->y[P->n] = y, P->lo[P->n] = P->hi[P->n] = NAN;
		P->n++;
	}
	bk_csvtab_free(&t);
}

static int box_meets(const double a[4], const bk_plot_label *l)
{
	return a[0] < l->x1 && l->x0 < a[2] && a[1] < l->y1 && l->y0 < a[3];
}

/* Faults of a figure's labels: unplaced ones, ones crossing a drawn mark or another label. */
static int label_faults(const bk_plot *p, int want_labels)
{
	static bk_plot_label l[4 * MAXPTS];
	static double m[16 * MAXPTS][4];
	int nl = bk_plot_labels(p, l, 4 * MAXPTS), nm = bk_plot_marks(p, m, 16 * MAXPTS), bad = 0;
	cr_assert_eq(nl, want_labels);
	cr_assert_geq(nm, 0);
	for (int i = 0; i < nl; i++) {
		if (!l[i].placed) {
			cr_log_info("label %d (series %d point %d) not placed", i, l[i].series, l[i].point);
			bad++;
			continue;
		}
		for (int j = 0; j < nm && j < 16 * MAXPTS; j++)
			if (box_meets(m[j], &l[i])) {
				cr_log_info("label %d meets mark %d", i, j);
				bad++;
			}
	}
	return bad + overlaps(l, nl);
}

/* results/search/vf2d/pareto.png: 8 of 10 front points were unlabelled. */
Test(plot, every_front_point_of_the_committed_search_is_labelled_or_keyed)
{
	static pts F, C;
	read_pts(&F, "results/search/vf2d/front.csv", "cost", "max_abs");
	read_pts(&C, "results/search/vf2d/catalog.csv", "cost", "max_abs");
	/* the premise: a front as crowded as the one that showed the defect
	 * (10 members then; the count moves with the search) */
	cr_assert_geq(F.n, 8, "the committed front has %d members", F.n);
	for (int i = 1; i < F.n; i++) /* in cost order, as bk_swrite_plot's staircase takes it */
		for (int j = i; j > 0 && F.x[j] < F.x[j - 1]; j--) {
			double t = F.x[j]; F.x[j] = F.x[j - 1]; F.x[j - 1] = t;
			t = F.y[j]; F.y[j] = F.y[j - 1]; F.y[j - 1] = t;
			const char *l = F.lab[j]; F.lab[j] = F.lab[j - 1]; F.lab[j - 1] = l;
		}
	bk_plot_series s[3] = {
		{"search front (refitted)", BK_PLOT_STEPS, BK_PLOT_CIRCLE, 0, 0x1f5fbf, F.n, F.x, F.y, NULL, NULL, NULL},
		{"published", BK_PLOT_POINTS, BK_PLOT_TRIANGLE, 0, 0xc0392b, C.n, C.x, C.y, NULL, NULL, NULL},
		{NULL, BK_PLOT_POINTS, BK_PLOT_CIRCLE, 0, 0x1f5fbf, F.n, F.x, F.y, F.lab, NULL, NULL},
	};
	/* as bk_swrite_plot draws it: 7 x 4.2 in, log error against cost, each
	 * axis grown to the points (a front reaching below 1e-3 is drawn whole) */
	bk_plot p = {BK_PLOT_DOUBLE_W, 4.2, "search on vf2d", "a note", NULL, {"cost", 0, 0, 15, 0, 0, NULL},
	             {"error", 1, 1e-3, 1, 0, 0, NULL}, s, 3, NULL};
	for (int k = 0; k < 2; k++) {
		bk_plot_axis_grow(&p.x, s[k].x, s[k].n);
		bk_plot_axis_grow(&p.y, s[k].y, s[k].n);
	}
	cr_expect_eq(label_faults(&p, F.n), 0, "7 x 4.2 in");
	/* and the same front in a single column: still every point
	 * labelled or keyed (numbers fit where names do not) */
	p.width_in = BK_PLOT_SINGLE_W, p.height_in = 2.6;
	static bk_plot_label l[MAXPTS];
	cr_assert_eq(bk_plot_labels(&p, l, MAXPTS), F.n);
	int keyed = 0;
	for (int i = 0; i < F.n; i++)
		keyed += l[i].key > 0;
	cr_expect_gt(keyed, 0, "a small figure keys some labels");
	cr_expect_eq(label_faults(&p, F.n), 0, "3.5 x 2.6 in");
}

/* results/compare/vf2d/pareto_ns.png: labels crossed by the min..max time bars. */
Test(plot, labels_keep_off_the_committed_compare_error_bars)
{
	static pts P, T;
	read_pts(&P, "results/compare/vf2d/compare.csv", "cost", "max_abs");
	read_pts(&T, "results/compare/vf2d/timing.csv", "ns_per_eval", "ns_min");
	static pts H;
	read_pts(&H, "results/compare/vf2d/timing.csv", "ns_per_eval", "ns_max");
	int n = 0;
	static pts Q; /* error against time, with the bars, for each timed row */
	for (int i = 0; i < P.n; i++)
		for (int j = 0; j < T.n; j++)
			if (!strcmp(P.name[i], T.name[j]) && P.y[i] > 0) {
				snprintf(Q.name[n], sizeof Q.name[0], "%s", P.name[i]);
				Q.lab[n] = Q.name[n];
				Q.x[n] = T.x[j], Q.y[n] = P.y[i], Q.lo[n] = T.y[j], Q.hi[n] = H.y[j];
				n++;
			}
	Q.n = n;
	cr_assert_geq(n, 10, "the committed compare has its timed rows");
	/* the axes take the measured times and errors whatever they are (a fixed
	 * 0..4 ns once left a slower row outside the plot) */
	double xhi = 0, ylo = 1;
	for (int i = 0; i < n; i++)
		xhi = fmax(xhi, Q.hi[i]), ylo = fmin(ylo, Q.y[i]);
	bk_plot_series s[1] = {{"rows", BK_PLOT_POINTS, BK_PLOT_CIRCLE, 0, 0x1f77b4, n, Q.x, Q.y, Q.lab, Q.lo, Q.hi}};
	bk_plot p = {BK_PLOT_DOUBLE_W, 4.2, "vf2d", NULL, NULL, {"ns", 0, 0, ceil(xhi * 1.05), 0, 0, NULL},
	             {"error", 1, pow(10, floor(log10(ylo))), 1, 0, 0, NULL}, s, 1, NULL};
	cr_expect_eq(label_faults(&p, n), 0);
	/* the bars are marks: one box per bar beside each marker's */
	static double m[4 * MAXPTS][4];
	cr_expect_eq(bk_plot_marks(&p, m, 4 * MAXPTS), 2 * n);
	/* negative control: a label planted on a bar is caught */
	double bx[4] = {m[1][0], m[1][1], m[1][2], m[1][3]};
	bk_plot_label on = {0, 0, 1, (bx[0] + bx[2]) / 2 - 3, bx[1] - 2, (bx[0] + bx[2]) / 2 + 3, bx[3] + 2, 0};
	cr_expect(box_meets(bx, &on));
}

/* A planted crowd with long bars through it and a line across it. */
Test(plot, planted_crowd_with_bars_and_a_line_labels_keep_off)
{
	static pts P;
	for (int i = 0; i < 24; i++) { /* 4 rows of 6, bars reaching past the neighbours */
		P.x[i] = 2.0 + 0.8 * (i % 6) + 0.3 * (i / 6), P.y[i] = 2.0 + 1.2 * (i / 6);
		P.lo[i] = P.x[i] - 1.5, P.hi[i] = P.x[i] + 1.2;
		snprintf(P.name[i], sizeof P.name[0], "member_%d", i);
		P.lab[i] = P.name[i];
	}
	double lx[2] = {0, 10}, ly[2] = {0, 10};
	bk_plot_series s[2] = {{"diagonal", BK_PLOT_LINE, BK_PLOT_CIRCLE, 0, 0x444444, 2, lx, ly, NULL, NULL, NULL},
	                       {"rows", BK_PLOT_POINTS, BK_PLOT_SQUARE, 0, 0xd62728, 24, P.x, P.y, P.lab, P.lo, P.hi}};
	bk_plot p = {BK_PLOT_DOUBLE_W, 4.2, "crowd", NULL, NULL, {"x", 0, 0, 10, 0, 0, NULL}, {"y", 0, 0, 10, 0, 0, NULL},
	             s, 2, NULL};
	cr_expect_eq(label_faults(&p, 24), 0);
	/* the line: no placed label box holds a point of the diagonal */
	static bk_plot_label l[24];
	cr_assert_eq(bk_plot_labels(&p, l, 24), 24);
	double dx[201], qx[201], qy[201];
	for (int k = 0; k <= 200; k++)
		dx[k] = k / 20.0;
	bk_plot_to_page_n(&p, 201, dx, dx, qx, qy);
	for (int i = 0; i < 24; i++)
		for (int k = 0; k <= 200 && l[i].placed; k++)
			cr_expect_not(qx[k] > l[i].x0 && qx[k] < l[i].x1 && qy[k] > l[i].y0 && qy[k] < l[i].y1,
			              "label %d on the line", i);
}
