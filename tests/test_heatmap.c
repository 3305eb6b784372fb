/*
 * test_heatmap.c — analysis/heatmap.c writes one error map as EXR, CSV and a figure
 * (PNG, SVG, PDF).
 * A synthetic field, value = (x - 0.5) * y on 40 x 30 cells over x in [0, 1],
 * y in [1, 3], with one exact zero and one NaN, is written and read back: the EXR
 * holds every value with y0 in the bottom scanline; the PNG, read with libpng, shows
 * red where the value is positive, blue where negative, the scheme's near-white at
 * zero, grey for NaN, the extreme colours in the far corners and at the colour bar's
 * ends, and leaves its border blank (nothing drawn off the edge); the CSV has the
 * sanitised header and one row per cell, x fastest. Two writes give the same bytes.
 * Failures leave nothing behind, or for a failure between renames, no mixed set.
 */
#include "exr.h"
#include "heatmap.h"

#include <criterion/criterion.h>
#include <png.h>

#include <dirent.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

enum { NX = 40, NY = 30 };
enum { ZERO_I = 10, ZERO_J = 12, NAN_I = 30, NAN_J = 5 };

static const char title[] = "vf_talk_r fitted: error (approx - exact)";
static const char conventions[] = "GGX D, height-correlated Smith V, Schlick F with f0 = 0.04";

static char dir[64];
static double field[NX * NY];

static double cx(int i) { return (i + 0.5) / NX; }           /* x in [0, 1] */
static double cy(int j) { return 1.0 + 2.0 * (j + 0.5) / NY; } /* y in [1, 3] */

static bk_heatmap make_field(void)
{
	for (int j = 0; j < NY; j++)
		for (int i = 0; i < NX; i++)
			field[j * NX + i] = (cx(i) - 0.5) * cy(j);
	field[ZERO_J * NX + ZERO_I] = 0.0;
	field[NAN_J * NX + NAN_I] = NAN;
	return (bk_heatmap){NX, NY, field, 0.0, 1.0, 1.0, 3.0, "LoH", "r (perceptual roughness)",
	                    title, "error", conventions};
}

static void make_dir(void)
{
	snprintf(dir, sizeof dir, "/tmp/bk_test_heatmap_XXXXXX");
	cr_assert_not_null(mkdtemp(dir), "mkdtemp failed");
}

static void remove_tree(const char *d)
{
	DIR *dp = opendir(d);
	if (!dp)
		return;
	char p[512];
	for (struct dirent *e; (e = readdir(dp));) {
		if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
			continue;
		snprintf(p, sizeof p, "%s/%s", d, e->d_name);
		if (unlink(p) != 0)
			remove_tree(p);
	}
	closedir(dp);
	rmdir(d);
}

static void remove_dir(void) { remove_tree(dir); }

TestSuite(heatmap, .init = make_dir, .fini = remove_dir);

static void in_dir(char *out, size_t len, const char *name)
{
	snprintf(out, len, "%s/%s", dir, name);
}

/* Names in the directory, sorted and joined by spaces. */
static void list_dir(char *out, size_t len)
{
	struct dirent **names;
	int n = scandir(dir, &names, NULL, alphasort);
	cr_assert_geq(n, 0);
	out[0] = '\0';
	for (int k = 0; k < n; k++) {
		if (names[k]->d_name[0] != '.')
			snprintf(out + strlen(out), len - strlen(out), "%s%s", out[0] ? " " : "",
			         names[k]->d_name);
		free(names[k]);
	}
	free(names);
}

static void write_ok(const bk_heatmap *h, const char *d, const char *stem)
{
	char err[512];
	cr_assert_eq(bk_heatmap_write(h, d, stem, err, sizeof err), 0, "%s", err);
	cr_assert_eq(err[0], '\0');
}

static void assert_one_line_about(const char *err, const char *path)
{
	size_t n = strlen(path);
	cr_assert(strncmp(err, path, n) == 0 && err[n] == ':' && err[n + 1] == ' ',
	          "message must start with \"%s: \": %s", path, err);
	cr_assert_null(strchr(err, '\n'), "message must be one line: %s", err);
}

/* ---- EXR ----------------------------------------------------------------------- */

Test(heatmap, exr_holds_every_value_with_y0_in_the_bottom_scanline)
{
	bk_heatmap h = make_field();
	write_ok(&h, dir, "h");
	char path[256], err[512];
	in_dir(path, sizeof path, "h.exr");
	bk_exr_image img;
	cr_assert_eq(bk_exr_read(path, &img, err, sizeof err), 0, "%s", err);
	cr_assert_eq(img.width, NX);
	cr_assert_eq(img.height, NY);
	cr_assert_eq(img.nchan, 1);
	cr_assert_str_eq(img.names[0], "Y");
	cr_assert_eq(img.half[0], 0, "values must be FLOAT, not HALF");
	for (int j = 0; j < NY; j++)
		for (int i = 0; i < NX; i++) {
			float got = img.data[0][(NY - 1 - j) * NX + i];
			double want = field[j * NX + i];
			if (isnan(want))
				cr_assert(isnan(got), "cell (%d, %d) must stay NaN", i, j);
			else
				cr_assert_eq(got, (float)want, "cell (%d, %d): %.9g, want %.9g", i, j, got, want);
		}
	/* The bottom scanline is y0's row: its right end is (x - 0.5) * y at the
	 * smallest y; the top scanline's right end has the largest y. */
	cr_assert_eq(img.data[0][(NY - 1) * NX + NX - 1], (float)((cx(NX - 1) - 0.5) * cy(0)));
	cr_assert_eq(img.data[0][NX - 1], (float)((cx(NX - 1) - 0.5) * cy(NY - 1)));
	bk_exr_image_free(&img);

	char buf[1024];
	cr_assert_eq(bk_exr_read_attr(path, "brdfkit:origin", buf, sizeof buf), 0);
	cr_assert(strncmp(buf, "bottom: ", 8) == 0, "%s", buf);
	cr_assert_eq(bk_exr_read_attr(path, "brdfkit:title", buf, sizeof buf), 0);
	cr_assert_str_eq(buf, title);
	cr_assert_eq(bk_exr_read_attr(path, "brdfkit:conventions", buf, sizeof buf), 0);
	cr_assert_str_eq(buf, conventions);
	cr_assert_eq(bk_exr_read_attr(path, "brdfkit:axes", buf, sizeof buf), 0);
	cr_assert_not_null(strstr(buf, "x = LoH: 40 cells between edges x0 = 0 and x1 = 1, cell i "
	                               "centred at x0 + (i + 0.5)(x1 - x0)/nx"), "%s", buf);
	cr_assert_not_null(strstr(buf, "y = r (perceptual roughness): 30 cells between edges y0 = 1 "
	                               "and y1 = 3"), "%s", buf);
	cr_assert_eq(bk_exr_read_attr(path, "brdfkit:value", buf, sizeof buf), 0);
	cr_assert(strncmp(buf, "Y = error: signed", 17) == 0, "%s", buf);
	cr_assert_not_null(strstr(buf, "NaN = no data"), "%s", buf);
}

/* ---- PNG ----------------------------------------------------------------------- */

typedef struct rgb_image {
	int w, h;
	unsigned char *px;
} rgb_image;

static rgb_image read_png(const char *path)
{
	png_image im;
	memset(&im, 0, sizeof im);
	im.version = PNG_IMAGE_VERSION;
	cr_assert(png_image_begin_read_from_file(&im, path), "%s: %s", path, im.message);
	im.format = PNG_FORMAT_RGB;
	rgb_image out = {(int)im.width, (int)im.height, malloc(PNG_IMAGE_SIZE(im))};
	cr_assert_not_null(out.px);
	cr_assert(png_image_finish_read(&im, NULL, out.px, 0, NULL), "%s: %s", path, im.message);
	return out;
}

static const unsigned char *at(const rgb_image *im, int x, int y)
{
	cr_assert(x >= 0 && y >= 0 && x < im->w && y < im->h, "pixel (%d, %d) outside", x, y);
	return im->px + ((size_t)y * im->w + x) * 3;
}

/* The centre pixel of cell (i, j) of an nx x ny map: y0 is at the bottom. */
static const unsigned char *cell_of(const rgb_image *im, const bk_heatmap_layout *L, int nx,
                                    int ny, int i, int j)
{
	int x = L->plot_x + (2 * i + 1) * L->plot_w / (2 * nx);
	int y = L->plot_y + L->plot_h - 1 - (2 * j + 1) * L->plot_h / (2 * ny);
	return at(im, x, y);
}

static const unsigned char *cell(const rgb_image *im, const bk_heatmap_layout *L, int i, int j)
{
	return cell_of(im, L, NX, NY, i, j);
}

static void assert_rgb(const unsigned char *p, int r, int g, int b, const char *what)
{
	cr_assert(p[0] == r && p[1] == g && p[2] == b, "%s: (%d, %d, %d), want (%d, %d, %d)", what,
	          p[0], p[1], p[2], r, g, b);
}

/* Nothing is drawn within 8 px of the edge: no label runs off the image. */
static void assert_blank_border(const rgb_image *im)
{
	for (int y = 0; y < im->h; y++)
		for (int x = 0; x < im->w; x++) {
			if (x >= 8 && y >= 8 && x < im->w - 8 && y < im->h - 8)
				continue;
			const unsigned char *p = at(im, x, y);
			cr_assert(p[0] == 255 && p[1] == 255 && p[2] == 255,
			          "ink at (%d, %d) of a %d x %d image: something reaches the edge", x, y,
			          im->w, im->h);
		}
}

/* Pixel (x, y) or its neighbour (x + dx, y + dy) is dark (every channel under 90). */
static void assert_dark_edge(const rgb_image *im, int x, int y, int dx, int dy, const char *what)
{
	const unsigned char *a = at(im, x, y), *b = at(im, x + dx, y + dy);
	int da = a[0] < 90 && a[1] < 90 && a[2] < 90, db = b[0] < 90 && b[1] < 90 && b[2] < 90;
	cr_assert(da || db, "%s: (%d, %d, %d) and (%d, %d, %d), want a dark line", what, a[0], a[1], a[2], b[0], b[1], b[2]);
}

static rgb_image write_and_read_png(const bk_heatmap *h, bk_heatmap_layout *L)
{
	char err[512], path[256];
	cr_assert_eq(bk_heatmap_png_layout(h, L, err, sizeof err), 0, "%s", err);
	write_ok(h, dir, "h");
	in_dir(path, sizeof path, "h.png");
	rgb_image im = read_png(path);
	cr_assert_eq(im.w, L->width);
	cr_assert_eq(im.h, L->height);
	/* the layout is the drawing's: a dark frame on the edges of the plot and bar
	 * (anti-aliased: one of the two pixels across each edge is dark) */
	assert_dark_edge(&im, L->plot_x - 1, L->plot_y + L->plot_h / 2, 1, 0, "plot frame, left");
	assert_dark_edge(&im, L->plot_x + L->plot_w - 1, L->plot_y + L->plot_h / 2, 1, 0, "plot frame, right");
	assert_dark_edge(&im, L->plot_x + L->plot_w / 2, L->plot_y - 1, 0, 1, "plot frame, top");
	assert_dark_edge(&im, L->plot_x + L->plot_w / 2, L->plot_y + L->plot_h - 1, 0, 1, "plot frame, bottom");
	if (L->bar_w > 0) /* a plane one cell high is a line, without a bar (bk_heatmap_figure) */
		assert_dark_edge(&im, L->bar_x - 1, L->bar_y + L->bar_h / 3, 1, 0, "bar frame");
	assert_blank_border(&im);
	return im;
}

Test(heatmap, png_colours_follow_the_sign_and_y_grows_upward)
{
	bk_heatmap h = make_field();
	bk_heatmap_layout L;
	rgb_image im = write_and_read_png(&h, &L);
	cr_assert_geq(L.plot_w, 2 * NX, "cells at least 2 px wide");

	const unsigned char *pos = cell(&im, &L, 35, 20), *neg = cell(&im, &L, 4, 20);
	cr_assert(pos[0] > pos[2] + 60, "positive cell must be red: (%d, %d, %d)", pos[0], pos[1], pos[2]);
	cr_assert(neg[2] > neg[0] + 60, "negative cell must be blue: (%d, %d, %d)", neg[0], neg[1], neg[2]);
	assert_rgb(cell(&im, &L, ZERO_I, ZERO_J), 0xf7, 0xf7, 0xf7, "zero: RdBu's centre");
	assert_rgb(cell(&im, &L, NAN_I, NAN_J), 128, 128, 128, "NaN: grey");

	/* +-max|value| sits in the top corners (largest y), so they take the ends of
	 * RdBu; the bottom right (smallest y) is a paler red. */
	assert_rgb(cell(&im, &L, NX - 1, NY - 1), 0x67, 0x00, 0x1f, "top right: RdBu's red end");
	assert_rgb(cell(&im, &L, 0, NY - 1), 0x05, 0x30, 0x61, "top left: RdBu's blue end");
	const unsigned char *low = cell(&im, &L, NX - 1, 0);
	cr_assert(low[0] > low[2] && low[1] > 0x60, "bottom right must be pale red: (%d, %d, %d)",
	          low[0], low[1], low[2]);

	int bx = L.bar_x + L.bar_w / 2;
	assert_rgb(at(&im, bx, L.bar_y + 2), 0x67, 0x00, 0x1f, "colour bar top: +max");
	assert_rgb(at(&im, bx, L.bar_y + L.bar_h - 3), 0x05, 0x30, 0x61, "colour bar bottom: -max");
	const unsigned char *mid = at(&im, bx, L.bar_y + (L.bar_h - 1) / 2);
	cr_assert(mid[0] >= 240 && mid[1] >= 240 && mid[2] >= 240, "colour bar middle must be near "
	          "white: (%d, %d, %d)", mid[0], mid[1], mid[2]);
	free(im.px);
}

/* The scale is +-max|value| over finite cells; infinities take the extreme colours;
 * between RdBu's anchors each byte is interpolated: -0.25 of 0.5 is half-way from
 * #4393c3 to #92c5de, (106.5, 172, 208.5) rounded to nearest. A map with no data
 * at all is grey with a zero scale. */
Test(heatmap, png_scale_infinities_interpolation_and_no_data)
{
	double v[4] = {INFINITY, -INFINITY, 0.5, -0.25};
	bk_heatmap h = {2, 2, v, 0, 1, 0, 1, "x", "y", "infinities", "error", ""};
	bk_heatmap_layout L;
	rgb_image im = write_and_read_png(&h, &L);
	assert_rgb(cell_of(&im, &L, 2, 2, 0, 0), 0x67, 0x00, 0x1f, "+inf");
	assert_rgb(cell_of(&im, &L, 2, 2, 1, 0), 0x05, 0x30, 0x61, "-inf");
	assert_rgb(cell_of(&im, &L, 2, 2, 0, 1), 0x67, 0x00, 0x1f, "+max");
	assert_rgb(cell_of(&im, &L, 2, 2, 1, 1), 107, 172, 209, "-max/2");
	free(im.px);

	double none[6] = {NAN, NAN, NAN, NAN, NAN, NAN};
	bk_heatmap empty = {3, 2, none, 0, 1, 0, 1, "x", "y", "no data", "error", ""};
	im = write_and_read_png(&empty, &L);
	for (int j = 0; j < 2; j++)
		for (int i = 0; i < 3; i++)
			assert_rgb(cell_of(&im, &L, 3, 2, i, j), 128, 128, 128, "NaN");
	free(im.px);
}

/* Long labels are shrunk to fit instead of running off the image; sides with
 * one cell, thousands of cells, reversed and negative ranges still lay out. */
Test(heatmap, png_fits_long_labels_and_odd_shapes)
{
	static double v[3000 * 2];
	for (int k = 0; k < 3000 * 2; k++)
		v[k] = sin(k * 0.01) * 1e-7;
	const char *long_name = "a long axis name that is longer than the plot is tall, in units (deg)";
	bk_heatmap shapes[] = {
		{1, 1, v, 0, 1, 0, 1, "x", "y", "one cell", "e", NULL},
		{3000, 2, v, -5e-3, 2e-3, 10, -10, long_name, long_name, "3000 x 2, reversed y",
		 "relative error", ""},
		{7, 3, v, -1e6, 1e6, 0, 1, NULL, NULL, NULL, NULL, NULL},
		{40, 30, v, 0, 1, 0, 1, "LoH", "r", "a very long title: vf_talk_r fitted, error "
		 "(approx - exact), with every convention spelled out in full", "error", ""},
	};
	for (size_t k = 0; k < sizeof shapes / sizeof shapes[0]; k++) {
		bk_heatmap_layout L;
		rgb_image im = write_and_read_png(&shapes[k], &L);
		cr_assert_geq(L.plot_w, 300, "shape %zu: the plot keeps most of the width", k);
		cr_assert_leq(L.plot_w, L.width, "shape %zu", k);
		free(im.px);
	}
}

/* ---- CSV ----------------------------------------------------------------------- */

static char *slurp(const char *path, size_t *len)
{
	FILE *f = fopen(path, "rb");
	cr_assert_not_null(f, "%s", path);
	fseek(f, 0, SEEK_END);
	long n = ftell(f);
	rewind(f);
	char *s = malloc((size_t)n + 1);
	cr_assert_eq(fread(s, 1, (size_t)n, f), (size_t)n);
	s[n] = '\0';
	fclose(f);
	if (len)
		*len = (size_t)n;
	return s;
}

Test(heatmap, csv_has_a_sanitised_header_and_one_row_per_cell_x_fastest)
{
	bk_heatmap h = make_field();
	write_ok(&h, dir, "h");
	char path[256];
	in_dir(path, sizeof path, "h.csv");
	char *text = slurp(path, NULL);

	char *line = strtok(text, "\n");
	cr_assert_str_eq(line, "# brdfkit 0.1.0 heatmap: vf_talk_r fitted: error (approx - exact)");
	int comments = 0, seen_conventions = 0;
	for (; line && line[0] == '#'; line = strtok(NULL, "\n")) {
		comments++;
		seen_conventions |= strstr(line, conventions) != NULL;
	}
	cr_assert(seen_conventions, "the conventions must be a comment line");
	cr_assert_gt(comments, 2);
	cr_assert_str_eq(line, "LoH,r_perceptual_roughness,error");

	int rows = 0;
	for (line = strtok(NULL, "\n"); line; line = strtok(NULL, "\n"), rows++) {
		int i = rows % NX, j = rows / NX;
		char *end;
		double x = strtod(line, &end);
		cr_assert_eq(*end, ',', "row %d: %s", rows, line);
		double y = strtod(end + 1, &end);
		cr_assert_eq(*end, ',', "row %d: %s", rows, line);
		cr_assert_float_eq(x, cx(i), 1e-9, "row %d: x = %.9g", rows, x);
		cr_assert_float_eq(y, cy(j), 1e-8, "row %d: y = %.9g", rows, y);
		if (i == NAN_I && j == NAN_J) {
			cr_assert_eq(end[1], '\0', "NaN must be an empty field: %s", line);
			continue;
		}
		double v = strtod(end + 1, &end);
		cr_assert_eq(*end, '\0', "row %d: %s", rows, line);
		/* %.9g keeps nine significant digits: relative error at most 5e-9 */
		cr_assert_float_eq(v, field[j * NX + i], 5e-9 * fabs(field[j * NX + i]) + 1e-300,
		                   "row %d: %.17g", rows, v);
	}
	cr_assert_eq(rows, NX * NY);
	free(text);
}

Test(heatmap, csv_column_names_are_sanitised_defaulted_and_distinct)
{
	double v[4] = {1, -1, 0.5, NAN};
	struct {
		const char *x, *y, *value, *header;
	} cases[] = {
		{"theta (deg)", "phi [rad]", "error (approx - exact)", "theta_deg,phi_rad,error_approx_exact"},
		{NULL, NULL, NULL, "x,y,value"},
		{"NoV", "NoV", "NoV", "NoV,NoV_2,NoV_3"},
		{"(", "  ", "x2", "x,y,x2"},
	};
	for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
		bk_heatmap h = {2, 2, v, 0, 1, 0, 1, cases[k].x, cases[k].y, "t", cases[k].value, "c"};
		write_ok(&h, dir, "names");
		char path[256];
		in_dir(path, sizeof path, "names.csv");
		char *text = slurp(path, NULL);
		char *line = strtok(text, "\n");
		while (line && line[0] == '#')
			line = strtok(NULL, "\n");
		cr_assert_str_eq(line, cases[k].header, "case %zu", k);
		free(text);
	}
}

/* ---- bytes, failures ----------------------------------------------------------- */

static void assert_same_file(const char *a, const char *b)
{
	size_t na, nb;
	char *sa = slurp(a, &na), *sb = slurp(b, &nb);
	cr_assert(na == nb && memcmp(sa, sb, na) == 0, "%s and %s differ", a, b);
	free(sa);
	free(sb);
}

Test(heatmap, two_writes_give_the_same_bytes)
{
	bk_heatmap h = make_field();
	char sub[256], a[300], b[300];
	in_dir(sub, sizeof sub, "again");
	cr_assert_eq(mkdir(sub, 0755), 0);
	write_ok(&h, dir, "h");
	write_ok(&h, sub, "h");
	static const char *const ext[] = {"png", "csv", "exr", "svg", "pdf"};
	for (int k = 0; k < 5; k++) {
		snprintf(a, sizeof a, "%s/h.%s", dir, ext[k]);
		snprintf(b, sizeof b, "%s/h.%s", sub, ext[k]);
		assert_same_file(a, b);
	}
}

Test(heatmap, unwritable_directory_fails_naming_the_path_and_leaves_nothing)
{
	bk_heatmap h = make_field();
	char err[512];
	cr_assert_eq(bk_heatmap_write(&h, "/nonexistent_bk_heatmap", "h", err, sizeof err), -1);
	assert_one_line_about(err, "/nonexistent_bk_heatmap/h.exr");
	cr_assert_not_null(strstr(err, "no such file or directory"), "%s", err);

	/* a regular file where the directory should be */
	char file[256], listing[512];
	in_dir(file, sizeof file, "plain");
	FILE *f = fopen(file, "w");
	cr_assert_not_null(f);
	fclose(f);
	cr_assert_eq(bk_heatmap_write(&h, file, "h", err, sizeof err), -1);
	cr_assert(strncmp(err, file, strlen(file)) == 0, "message must name %s: %s", file, err);
	list_dir(listing, sizeof listing);
	cr_assert_str_eq(listing, "plain");
}

/* A write error (the file-size limit stops the PNG) comes before any rename: an
 * older set of the stem is untouched and no temporary is left. */
Test(heatmap, write_error_keeps_the_older_set_and_leaves_no_temporary)
{
	bk_heatmap h = make_field();
	write_ok(&h, dir, "h");
	char png[256], err[512], listing[512];
	in_dir(png, sizeof png, "h.png");
	size_t before;
	free(slurp(png, &before));

	signal(SIGXFSZ, SIG_IGN);
	struct rlimit lim = {4096, 4096};
	cr_assert_eq(setrlimit(RLIMIT_FSIZE, &lim), 0);
	field[0] = 1.0; /* a different image */
	cr_assert_eq(bk_heatmap_write(&h, dir, "h", err, sizeof err), -1);
	assert_one_line_about(err, png);
	cr_assert_not_null(strstr(err, "file too large"), "%s", err);
	list_dir(listing, sizeof listing);
	cr_assert_str_eq(listing, "h.csv h.exr h.pdf h.png h.svg");
	size_t after;
	free(slurp(png, &after));
	cr_assert_eq(after, before, "the older PNG must be untouched");
}

/* A directory standing at h.png makes the second rename fail after h.exr is in
 * place: the new h.exr and the older h.csv go, so no mixed set remains. */
Test(heatmap, rename_failure_midway_leaves_no_mixed_set)
{
	bk_heatmap h = make_field();
	char path[256], err[512], listing[512];
	in_dir(path, sizeof path, "h.csv");
	FILE *f = fopen(path, "w");
	cr_assert_not_null(f);
	fputs("an older csv\n", f);
	fclose(f);
	in_dir(path, sizeof path, "h.png");
	cr_assert_eq(mkdir(path, 0755), 0);
	cr_assert_eq(bk_heatmap_write(&h, dir, "h", err, sizeof err), -1);
	assert_one_line_about(err, path);
	cr_assert_not_null(strstr(err, "cannot rename into place"), "%s", err);
	list_dir(listing, sizeof listing);
	cr_assert_str_eq(listing, "h.png", "only the directory in the way may remain");
}

Test(heatmap, bad_arguments_fail_with_a_message_and_no_files)
{
	bk_heatmap h = make_field();
	char err[512], who[256], listing[512];
	in_dir(who, sizeof who, "h");
	bk_heatmap bad = h;
	bad.nx = 0;
	cr_assert_eq(bk_heatmap_write(&bad, dir, "h", err, sizeof err), -1);
	assert_one_line_about(err, who);
	cr_assert_not_null(strstr(err, "0 x 30 cells"), "%s", err);
	bad = h;
	bad.x1 = bad.x0;
	cr_assert_eq(bk_heatmap_write(&bad, dir, "h", err, sizeof err), -1);
	cr_assert_not_null(strstr(err, "x range 0 to 0"), "%s", err);
	bad = h;
	bad.y1 = INFINITY;
	cr_assert_eq(bk_heatmap_write(&bad, dir, "h", err, sizeof err), -1);
	cr_assert_not_null(strstr(err, "y range"), "%s", err);
	bad = h;
	bad.value = NULL;
	cr_assert_eq(bk_heatmap_write(&bad, dir, "h", err, sizeof err), -1);
	cr_assert_eq(bk_heatmap_write(NULL, dir, "h", err, sizeof err), -1);
	cr_assert_eq(bk_heatmap_write(&h, dir, "a/b", err, sizeof err), -1);
	cr_assert_eq(bk_heatmap_write(&h, dir, "", err, sizeof err), -1);
	bk_heatmap_layout L;
	cr_assert_eq(bk_heatmap_png_layout(&bad, &L, err, sizeof err), -1);
	assert_one_line_about(err, "heatmap");
	list_dir(listing, sizeof listing);
	cr_assert_str_eq(listing, "");
	cr_assert_eq(bk_heatmap_write(&h, dir, "h", NULL, 0), 0, "err may be NULL when errlen is 0");
}

/* ---- a 1-input target is a line ------------------------------------------------------ */

/* results/search/f_gold/front/search_f_6/heatmap.png drew f's error over LoH as a
 * 2-D map with a "-" y axis; a plane one cell high is a line of the value against x. */
Test(heatmap, one_input_target_is_a_line_with_value_on_y)
{
	static double v[64];
	for (int i = 0; i < 64; i++) /* Fresnel-fit-like error: signed, a few 1e-4 */
		v[i] = 3e-4 * sin(0.3 * i) - 1e-4;
	bk_heatmap f = {64, 1, v, 0, 1, 0, 1, "LoH", "-", "search_f_6 fitted on f_gold", "error", ""};
	bk_heatmap_figure_info fi;
	char err[256];
	cr_assert_eq(bk_heatmap_figure(&f, NULL, &fi, err, sizeof err), 0, "%s", err);
	cr_expect_eq(fi.kind, BK_HEATMAP_LINE);
	cr_expect_str_eq(fi.xlabel, "LoH");
	cr_expect_str_eq(fi.ylabel, "error", "the y axis is the value, not the plane's \"-\"");
	cr_expect_not(fi.colour_bar);
	/* every value is on the y axis, which is symmetric about zero for signed error */
	double m = 0;
	for (int i = 0; i < 64; i++)
		m = fmax(m, fabs(v[i]));
	cr_expect(fi.ylo <= -m && fi.yhi >= m && fi.ylo == -fi.yhi, "y %g..%g for max |error| %g", fi.ylo, fi.yhi, m);
	cr_expect(fi.yhi < 4 * m, "y range %g hugs the data (max %g)", fi.yhi, m);
	/* it writes, and the bar area is empty */
	bk_heatmap_layout L;
	rgb_image im = write_and_read_png(&f, &L);
	cr_expect_eq(L.bar_w, 0);
	free(im.px);
	/* negative control: a plane two cells high stays a map with the plane's y name and a bar */
	static double v2[128];
	bk_heatmap g = {64, 2, v2, 0, 1, 0, 1, "LoH", "r", "vf2d", "error", ""};
	cr_assert_eq(bk_heatmap_figure(&g, NULL, &fi, err, sizeof err), 0, "%s", err);
	cr_expect_eq(fi.kind, BK_HEATMAP_MAP);
	cr_expect_str_eq(fi.ylabel, "r");
	cr_expect(fi.colour_bar);
	/* and one row with y categories (stability's one precision) stays a map */
	static const char *const ycat[1] = {"f16"};
	bk_heatmap_style st = {1, 0, NULL, ycat};
	cr_assert_eq(bk_heatmap_figure(&f, &st, &fi, err, sizeof err), 0, "%s", err);
	cr_expect_eq(fi.kind, BK_HEATMAP_MAP);
}
