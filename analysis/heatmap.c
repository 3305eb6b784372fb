/*
 * heatmap.c — one error map, three files. The PNG is drawn into an RGB canvas in
 * memory (cells, frame, colour bar, text from an embedded 5x9 bitmap font) and
 * encoded with libpng; the EXR goes through bk_exr_write; the CSV is plain stdio.
 * Each file is first written whole to a mkstemp temporary beside its final name and
 * only then are the three renamed into place, so a write error never touches the
 * files already at those names. bk_out (out.h) is not used: its commit renames at
 * once, and here no rename may happen before all three files are complete.
 */
#include "heatmap.h"
#include "brdf.h" /* BK_VERSION */
#include "exr.h"

#include <png.h>

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---- text: a 5x9 bitmap font ---------------------------------------------------- */

/* Drawn for brdfkit, printable ASCII 32..126. Nine rows of five columns, bit 4 the
 * leftmost; rows 0-6 hold capitals and digits, rows 7-8 descenders (g j p q y , ;)
 * and the underscore, which sits below the baseline so "vf_talk_r" stays readable. */
static const unsigned char font[95][9] = {
	{0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00}, /* ' ' */
	{0x04, 0x04, 0x04, 0x04, 0x04, 0x00, 0x04, 0x00, 0x00}, /* '!' */
	{0x0a, 0x0a, 0x0a, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00}, /* '"' */
	{0x0a, 0x0a, 0x1f, 0x0a, 0x1f, 0x0a, 0x0a, 0x00, 0x00}, /* '#' */
	{0x04, 0x0f, 0x14, 0x0e, 0x05, 0x1e, 0x04, 0x00, 0x00}, /* '$' */
	{0x18, 0x19, 0x02, 0x04, 0x08, 0x13, 0x03, 0x00, 0x00}, /* '%' */
	{0x0c, 0x12, 0x14, 0x08, 0x15, 0x12, 0x0d, 0x00, 0x00}, /* '&' */
	{0x04, 0x04, 0x08, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00}, /* '\'' */
	{0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02, 0x00, 0x00}, /* '(' */
	{0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08, 0x00, 0x00}, /* ')' */
	{0x00, 0x04, 0x15, 0x0e, 0x15, 0x04, 0x00, 0x00, 0x00}, /* '*' */
	{0x00, 0x04, 0x04, 0x1f, 0x04, 0x04, 0x00, 0x00, 0x00}, /* '+' */
	{0x00, 0x00, 0x00, 0x00, 0x00, 0x0c, 0x0c, 0x04, 0x08}, /* ',' */
	{0x00, 0x00, 0x00, 0x1f, 0x00, 0x00, 0x00, 0x00, 0x00}, /* '-' */
	{0x00, 0x00, 0x00, 0x00, 0x00, 0x0c, 0x0c, 0x00, 0x00}, /* '.' */
	{0x00, 0x01, 0x02, 0x04, 0x08, 0x10, 0x00, 0x00, 0x00}, /* '/' */
	{0x0e, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0e, 0x00, 0x00}, /* '0' */
	{0x04, 0x0c, 0x04, 0x04, 0x04, 0x04, 0x0e, 0x00, 0x00}, /* '1' */
	{0x0e, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1f, 0x00, 0x00}, /* '2' */
	{0x1f, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0e, 0x00, 0x00}, /* '3' */
	{0x02, 0x06, 0x0a, 0x12, 0x1f, 0x02, 0x02, 0x00, 0x00}, /* '4' */
	{0x1f, 0x10, 0x1e, 0x01, 0x01, 0x11, 0x0e, 0x00, 0x00}, /* '5' */
	{0x06, 0x08, 0x10, 0x1e, 0x11, 0x11, 0x0e, 0x00, 0x00}, /* '6' */
	{0x1f, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08, 0x00, 0x00}, /* '7' */
	{0x0e, 0x11, 0x11, 0x0e, 0x11, 0x11, 0x0e, 0x00, 0x00}, /* '8' */
	{0x0e, 0x11, 0x11, 0x0f, 0x01, 0x02, 0x0c, 0x00, 0x00}, /* '9' */
	{0x00, 0x0c, 0x0c, 0x00, 0x0c, 0x0c, 0x00, 0x00, 0x00}, /* ':' */
	{0x00, 0x0c, 0x0c, 0x00, 0x0c, 0x0c, 0x04, 0x08, 0x00}, /* ';' */
	{0x02, 0x04, 0x08, 0x10, 0x08, 0x04, 0x02, 0x00, 0x00}, /* '<' */
	{0x00, 0x00, 0x1f, 0x00, 0x1f, 0x00, 0x00, 0x00, 0x00}, /* '=' */
	{0x08, 0x04, 0x02, 0x01, 0x02, 0x04, 0x08, 0x00, 0x00}, /* '>' */
	{0x0e, 0x11, 0x01, 0x02, 0x04, 0x00, 0x04, 0x00, 0x00}, /* '?' */
	{0x0e, 0x11, 0x01, 0x0d, 0x15, 0x15, 0x0e, 0x00, 0x00}, /* '@' */
	{0x0e, 0x11, 0x11, 0x1f, 0x11, 0x11, 0x11, 0x00, 0x00}, /* 'A' */
	{0x1e, 0x11, 0x11, 0x1e, 0x11, 0x11, 0x1e, 0x00, 0x00}, /* 'B' */
	{0x0e, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0e, 0x00, 0x00}, /* 'C' */
	{0x1c, 0x12, 0x11, 0x11, 0x11, 0x12, 0x1c, 0x00, 0x00}, /* 'D' */
	{0x1f, 0x10, 0x10, 0x1e, 0x10, 0x10, 0x1f, 0x00, 0x00}, /* 'E' */
	{0x1f, 0x10, 0x10, 0x1e, 0x10, 0x10, 0x10, 0x00, 0x00}, /* 'F' */
	{0x0e, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0f, 0x00, 0x00}, /* 'G' */
	{0x11, 0x11, 0x11, 0x1f, 0x11, 0x11, 0x11, 0x00, 0x00}, /* 'H' */
	{0x0e, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0e, 0x00, 0x00}, /* 'I' */
	{0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0c, 0x00, 0x00}, /* 'J' */
	{0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11, 0x00, 0x00}, /* 'K' */
	{0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1f, 0x00, 0x00}, /* 'L' */
	{0x11, 0x1b, 0x15, 0x15, 0x11, 0x11, 0x11, 0x00, 0x00}, /* 'M' */
	{0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11, 0x00, 0x00}, /* 'N' */
	{0x0e, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0e, 0x00, 0x00}, /* 'O' */
	{0x1e, 0x11, 0x11, 0x1e, 0x10, 0x10, 0x10, 0x00, 0x00}, /* 'P' */
	{0x0e, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0d, 0x00, 0x00}, /* 'Q' */
	{0x1e, 0x11, 0x11, 0x1e, 0x14, 0x12, 0x11, 0x00, 0x00}, /* 'R' */
	{0x0f, 0x10, 0x10, 0x0e, 0x01, 0x01, 0x1e, 0x00, 0x00}, /* 'S' */
	{0x1f, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04, 0x00, 0x00}, /* 'T' */
	{0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0e, 0x00, 0x00}, /* 'U' */
	{0x11, 0x11, 0x11, 0x11, 0x11, 0x0a, 0x04, 0x00, 0x00}, /* 'V' */
	{0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0a, 0x00, 0x00}, /* 'W' */
	{0x11, 0x11, 0x0a, 0x04, 0x0a, 0x11, 0x11, 0x00, 0x00}, /* 'X' */
	{0x11, 0x11, 0x0a, 0x04, 0x04, 0x04, 0x04, 0x00, 0x00}, /* 'Y' */
	{0x1f, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1f, 0x00, 0x00}, /* 'Z' */
	{0x0e, 0x08, 0x08, 0x08, 0x08, 0x08, 0x0e, 0x00, 0x00}, /* '[' */
	{0x00, 0x10, 0x08, 0x04, 0x02, 0x01, 0x00, 0x00, 0x00}, /* '\\' */
	{0x0e, 0x02, 0x02, 0x02, 0x02, 0x02, 0x0e, 0x00, 0x00}, /* ']' */
	{0x04, 0x0a, 0x11, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00}, /* '^' */
	{0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x1f, 0x00}, /* '_' */
	{0x08, 0x04, 0x02, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00}, /* '`' */
	{0x00, 0x00, 0x0e, 0x01, 0x0f, 0x11, 0x0f, 0x00, 0x00}, /* 'a' */
	{0x10, 0x10, 0x16, 0x19, 0x11, 0x11, 0x1e, 0x00, 0x00}, /* 'b' */
	{0x00, 0x00, 0x0e, 0x10, 0x10, 0x11, 0x0e, 0x00, 0x00}, /* 'c' */
	{0x01, 0x01, 0x0d, 0x13, 0x11, 0x11, 0x0f, 0x00, 0x00}, /* 'd' */
	{0x00, 0x00, 0x0e, 0x11, 0x1f, 0x10, 0x0e, 0x00, 0x00}, /* 'e' */
	{0x06, 0x09, 0x08, 0x1c, 0x08, 0x08, 0x08, 0x00, 0x00}, /* 'f' */
	{0x00, 0x00, 0x0f, 0x11, 0x11, 0x11, 0x0f, 0x01, 0x0e}, /* 'g' */
	{0x10, 0x10, 0x16, 0x19, 0x11, 0x11, 0x11, 0x00, 0x00}, /* 'h' */
	{0x04, 0x00, 0x0c, 0x04, 0x04, 0x04, 0x0e, 0x00, 0x00}, /* 'i' */
	{0x02, 0x00, 0x06, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0c}, /* 'j' */
	{0x10, 0x10, 0x12, 0x14, 0x18, 0x14, 0x12, 0x00, 0x00}, /* 'k' */
	{0x0c, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0e, 0x00, 0x00}, /* 'l' */
	{0x00, 0x00, 0x1a, 0x15, 0x15, 0x15, 0x15, 0x00, 0x00}, /* 'm' */
	{0x00, 0x00, 0x16, 0x19, 0x11, 0x11, 0x11, 0x00, 0x00}, /* 'n' */
	{0x00, 0x00, 0x0e, 0x11, 0x11, 0x11, 0x0e, 0x00, 0x00}, /* 'o' */
	{0x00, 0x00, 0x1e, 0x11, 0x11, 0x11, 0x1e, 0x10, 0x10}, /* 'p' */
	{0x00, 0x00, 0x0f, 0x11, 0x11, 0x11, 0x0f, 0x01, 0x01}, /* 'q' */
	{0x00, 0x00, 0x16, 0x19, 0x10, 0x10, 0x10, 0x00, 0x00}, /* 'r' */
	{0x00, 0x00, 0x0f, 0x10, 0x0e, 0x01, 0x1e, 0x00, 0x00}, /* 's' */
	{0x08, 0x08, 0x1c, 0x08, 0x08, 0x09, 0x06, 0x00, 0x00}, /* 't' */
	{0x00, 0x00, 0x11, 0x11, 0x11, 0x13, 0x0d, 0x00, 0x00}, /* 'u' */
	{0x00, 0x00, 0x11, 0x11, 0x11, 0x0a, 0x04, 0x00, 0x00}, /* 'v' */
	{0x00, 0x00, 0x11, 0x11, 0x15, 0x15, 0x0a, 0x00, 0x00}, /* 'w' */
	{0x00, 0x00, 0x11, 0x0a, 0x04, 0x0a, 0x11, 0x00, 0x00}, /* 'x' */
	{0x00, 0x00, 0x11, 0x11, 0x11, 0x11, 0x0f, 0x01, 0x0e}, /* 'y' */
	{0x00, 0x00, 0x1f, 0x02, 0x04, 0x08, 0x1f, 0x00, 0x00}, /* 'z' */
	{0x02, 0x04, 0x04, 0x08, 0x04, 0x04, 0x02, 0x00, 0x00}, /* '{' */
	{0x04, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}, /* '|' */
	{0x08, 0x04, 0x04, 0x02, 0x04, 0x04, 0x08, 0x00, 0x00}, /* '}' */
	{0x00, 0x00, 0x08, 0x15, 0x02, 0x00, 0x00, 0x00, 0x00}, /* '~' */
};

/* Anything else is drawn as a hollow box, once per UTF-8 sequence. */
static const unsigned char no_glyph[9] = {0x1f, 0x11, 0x11, 0x11, 0x11, 0x11, 0x1f, 0x00, 0x00};

/* Every font pixel is drawn as an FS x FS block: at 2, capitals are 14 px tall,
 * comfortably legible on a screen without anti-aliasing. */
enum { FS = 2, ADV = 6 * FS, CAP = 7 * FS, LINE = 9 * FS };

static const unsigned char *next_glyph(const char **s)
{
	unsigned char c = (unsigned char)*(*s)++;
	if (c >= 32 && c < 127)
		return font[c - 32];
	while (((unsigned char)**s & 0xC0) == 0x80) /* UTF-8 continuation bytes */
		(*s)++;
	return no_glyph;
}

/* Width in pixels of s drawn on one line (no trailing gap after the last glyph). */
static int text_width(const char *s)
{
	int n = 0;
	while (*s) {
		next_glyph(&s);
		n++;
	}
	return n ? n * ADV - FS : 0;
}

/* ---- the canvas ---------------------------------------------------------------- */

typedef struct canvas {
	int w, h;
	unsigned char *rgb; /* w * h * 3 bytes, row 0 at the top */
} canvas;

static const unsigned char black[3] = {0, 0, 0}, white[3] = {255, 255, 255};
static const unsigned char grey[3] = {128, 128, 128}; /* NaN: no data */

static void fill(canvas *c, int x, int y, int w, int h, const unsigned char col[3])
{
	int xa = x < 0 ? 0 : x, ya = y < 0 ? 0 : y;
	int xb = x + w > c->w ? c->w : x + w, yb = y + h > c->h ? c->h : y + h;
	for (int r = ya; r < yb; r++)
		for (int q = xa; q < xb; q++)
			memcpy(c->rgb + ((size_t)r * c->w + q) * 3, col, 3);
}

/* Draws s with the top-left corner of its line box at (x, y). With up != 0 the text
 * is turned a quarter turn counter-clockwise and reads bottom to top: (x, y) is then
 * the line box's bottom-left corner and the glyphs' tops face left. */
static void draw_text(canvas *c, int x, int y, const char *s, int up)
{
	for (int pos = 0; *s; pos += ADV) {
		const unsigned char *g = next_glyph(&s);
		for (int r = 0; r < 9; r++)
			for (int k = 0; k < 5; k++) {
				if (!(g[r] >> (4 - k) & 1))
					continue;
				int along = pos + k * FS, across = r * FS;
				if (up)
					fill(c, x + across, y - along - FS, FS, FS, black);
				else
					fill(c, x + along, y + across, FS, FS, black);
			}
	}
}

/* ---- colours ------------------------------------------------------------------- */

/* ColorBrewer "RdBu", 11 classes (Cynthia A. Brewer, colorbrewer2.org, diverging
 * schemes), listed from its blue end to its red end so that index 0 is -1, index 5
 * (#f7f7f7, the scheme's own near-white) is 0 and index 10 is +1. Between anchors
 * each sRGB byte is interpolated linearly and rounded to nearest. */
static const unsigned char rdbu[11][3] = {
	{0x05, 0x30, 0x61}, {0x21, 0x66, 0xac}, {0x43, 0x93, 0xc3}, {0x92, 0xc5, 0xde},
	{0xd1, 0xe5, 0xf0}, {0xf7, 0xf7, 0xf7}, {0xfd, 0xdb, 0xc7}, {0xf4, 0xa5, 0x82},
	{0xd6, 0x60, 0x4d}, {0xb2, 0x18, 0x2b}, {0x67, 0x00, 0x1f},
};

/* t in [-1, 1] (clamped; NaN is no data) to a colour. */
static void colour_at(double t, unsigned char out[3])
{
	if (isnan(t)) {
		memcpy(out, grey, 3);
		return;
	}
	double u = (fmax(-1.0, fmin(1.0, t)) + 1.0) * 5.0; /* 0..10 along the anchors */
	int k = u >= 10.0 ? 9 : (int)u;
	double f = u - k;
	for (int ch = 0; ch < 3; ch++)
		out[ch] = (unsigned char)floor(rdbu[k][ch] + (rdbu[k + 1][ch] - rdbu[k][ch]) * f + 0.5);
}

/* A value on the symmetric scale +-vmax; infinities take the extreme colours. */
static void colour_of(double v, double vmax, unsigned char out[3])
{
	double t = isinf(v) ? copysign(1.0, v) : vmax > 0 ? v / vmax : v * 0.0;
	colour_at(t, out);
}

/* ---- axis ticks ------------------------------------------------------------------ */

enum { MAX_TICKS = 16 };

typedef struct ticks {
	int n;
	double v[MAX_TICKS];
	char label[MAX_TICKS][24];
} ticks;

/* The smallest of 1, 2, 5 x 10^k that is >= raw. */
static double nice_step(double raw)
{
	double mag = pow(10.0, floor(log10(raw)));
	double f = raw / mag;
	return (f <= 1 ? 1 : f <= 2 ? 2 : f <= 5 ? 5 : 10) * mag;
}

/* Fixed decimals, as many as the step needs ("0.05" a step of 0.05 apart); for
 * tiny steps or huge values %g with enough digits to tell neighbours apart. The
 * choice is made once per axis (big = its largest magnitude) so labels match. */
static void tick_label(double v, double step, double big, char *out, size_t len)
{
	if (step >= 1e-4 && big < 1e6) {
		snprintf(out, len, "%.*f", step >= 1 ? 0 : (int)ceil(-log10(step) - 1e-9), v);
		return;
	}
	double digits = ceil(log10(big / step)) + 1;
	snprintf(out, len, "%.*g", (int)fmax(3, fmin(15, digits)), v);
}

/* Multiples of step inside [min(a, b), max(a, b)]; the 1e-9 slack keeps an end that
 * is itself a multiple (0 and 1 for [0, 1]) despite rounding in lo/step. */
static void ticks_at(double a, double b, double step, ticks *t)
{
	double lo = fmin(a, b), hi = fmax(a, b), big = fmax(fabs(a), fabs(b));
	t->n = 0;
	for (double k = ceil(lo / step - 1e-9); t->n < MAX_TICKS; k++) {
		double v = k * step;
		if (v > hi + 1e-9 * step)
			break;
		if (fabs(v) < 1e-9 * step)
			v = 0; /* never "-0.0" */
		t->v[t->n] = v;
		tick_label(v, step, big, t->label[t->n], sizeof t->label[0]);
		t->n++;
	}
}

/* About five intervals, widened until neighbouring labels keep a gap: two glyphs
 * between labels along x, half a line between labels along y. */
static void axis_ticks(double a, double b, int px, int along_x, ticks *t)
{
	double range = fabs(b - a), raw = range / 5;
	for (int tries = 0; tries < 12; tries++) {
		double step = nice_step(raw);
		ticks_at(a, b, step, t);
		int need = LINE + LINE / 2;
		for (int k = 0; along_x && k < t->n; k++) {
			int w = text_width(t->label[k]) + 2 * ADV;
			need = w > need ? w : need;
		}
		if (step / range * px >= need)
			return;
		raw = step * 1.01; /* the next nice step */
	}
}

/* ---- layout ---------------------------------------------------------------------- */

enum {
	MARGIN = 16,   /* blank border around everything */
	TICK = 5,      /* tick mark length */
	PLOT_MIN_W = 512, PLOT_MIN_H = 384, PLOT_MAX = 2048,
	BAR_W = 22,    /* colour bar width */
	SWATCH_W = 22, /* the grey "no data" legend box */
};

static const char no_data_text[] = "no data";

typedef struct plan {
	bk_heatmap_layout L;
	const bk_heatmap *h;
	const char *title, *xname, *yname, *vname;
	double vmax; /* max |value| over finite cells; 0 when there are none */
	int has_nan;
	ticks xt, yt;
	int xtick_px[MAX_TICKS], ytick_px[MAX_TICKS];
	char bar_label[3][32]; /* +vmax, 0, -vmax */
	int bar_tick_px[3];
	int title_x, title_y, xname_x, xname_y, yname_x, yname_y, vname_x, vname_y;
	int ylabel_right, xlabel_y, barlabel_x, swatch_x, swatch_y;
} plan;

static const char *or_default(const char *s, const char *d) { return s ? s : d; }

static int imax(int a, int b) { return a > b ? a : b; }

/* Cells drawn as k x k blocks, k the smallest integer reaching min_px; sides with
 * more cells than PLOT_MAX pixels are sampled (the EXR and CSV keep every cell). */
static int plot_side(int n, int min_px)
{
	long px = (long)n * ((min_px + n - 1) / n);
	return px > PLOT_MAX ? PLOT_MAX : (int)px;
}

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

/* Where a tick for v goes, relative to the plot's first cell pixel: the axis ends
 * land on the frame lines (-1 and n), values between spread evenly. */
static int tick_off(double v, double a, double b, int n)
{
	double f = fmax(0.0, fmin(1.0, (v - a) / (b - a)));
	return (int)lround(f * (n + 1)) - 1;
}

static void place_ticks(plan *p)
{
	const bk_heatmap *h = p->h;
	bk_heatmap_layout *L = &p->L;
	for (int k = 0; k < p->xt.n; k++)
		p->xtick_px[k] = L->plot_x + tick_off(p->xt.v[k], h->x0, h->x1, L->plot_w);
	for (int k = 0; k < p->yt.n; k++) /* y grows upward */
		p->ytick_px[k] = L->plot_y + L->plot_h - 1 - tick_off(p->yt.v[k], h->y0, h->y1, L->plot_h);
	/* The bar's top row is +vmax, its bottom row -vmax, zero half-way. */
	p->bar_tick_px[0] = L->bar_y;
	p->bar_tick_px[1] = L->bar_y + (L->bar_h - 1) / 2;
	p->bar_tick_px[2] = L->bar_y + L->bar_h - 1;
}

/* Left to right: margin, y name (turned), y tick labels, ticks, plot, gap, colour
 * bar, its ticks and labels, the value name (turned), margin. Top to bottom: margin,
 * title, plot, x ticks and labels, x name, margin. Every width comes from the text
 * it holds, so nothing is clipped; the image grows for long titles and names. */
static void layout_x(plan *p)
{
	bk_heatmap_layout *L = &p->L;
	int yw = 0, bw = 0;
	for (int k = 0; k < p->yt.n; k++)
		yw = imax(yw, text_width(p->yt.label[k]));
	L->plot_x = MARGIN + LINE + 8 + yw + 6 + TICK + 1;
	/* x tick labels are centred on their ticks and must not reach the margin */
	int right_ext = 0;
	for (int k = 0; k < p->xt.n; k++) {
		int w = text_width(p->xt.label[k]);
		int off = tick_off(p->xt.v[k], p->h->x0, p->h->x1, L->plot_w);
		L->plot_x = imax(L->plot_x, MARGIN + w / 2 - off);
		right_ext = imax(right_ext, off + (w - w / 2) - L->plot_w);
	}
	L->bar_x = L->plot_x + L->plot_w + 1 + imax(28, right_ext + 16);
	L->bar_w = BAR_W;
	for (int k = 0; k < 3; k++)
		bw = imax(bw, text_width(p->bar_label[k]));
	p->barlabel_x = L->bar_x + BAR_W + 1 + TICK + 4;
	p->vname_x = p->barlabel_x + bw + 12;
	p->swatch_x = L->bar_x;
	int right = p->vname_x + LINE + MARGIN;
	if (p->has_nan)
		right = imax(right, p->swatch_x + SWATCH_W + 6 + text_width(no_data_text) + MARGIN);
	int tw = text_width(p->title), xw = text_width(p->xname);
	L->width = imax(right, imax(tw, xw) + 2 * MARGIN);
	/* a title or x name wider than the drawing: centre the drawing under it */
	int shift = (L->width - right) / 2;
	L->plot_x += shift;
	L->bar_x += shift;
	p->barlabel_x += shift;
	p->vname_x += shift;
	p->swatch_x += shift;
	p->yname_x = MARGIN + shift;
	p->ylabel_right = L->plot_x - 1 - TICK - 6;
	p->title_x = imax(MARGIN, (L->width - tw) / 2);
	p->xname_x = L->plot_x + (L->plot_w - xw) / 2;
	p->xname_x = imax(MARGIN, p->xname_x + xw > L->width - MARGIN ? L->width - MARGIN - xw : p->xname_x);
}

/* Turned text is centred on the plot's middle, kept inside the margins. */
static int turned_bottom(const plan *p, const char *s)
{
	int w = text_width(s), mid = p->L.plot_y + p->L.plot_h / 2;
	int bottom = mid + w / 2;
	if (bottom > p->L.height - MARGIN)
		bottom = p->L.height - MARGIN;
	return bottom - w < MARGIN ? MARGIN + w : bottom;
}

static void layout_y(plan *p)
{
	bk_heatmap_layout *L = &p->L;
	p->title_y = MARGIN;
	L->plot_y = MARGIN + LINE + 16;
	L->bar_y = L->plot_y;
	L->bar_h = L->plot_h;
	p->xlabel_y = L->plot_y + L->plot_h + 1 + TICK + 4;
	p->swatch_y = p->xlabel_y + 2;
	p->xname_y = p->xlabel_y + LINE + 6;
	L->height = p->xname_y + LINE + MARGIN;
	L->height = imax(L->height, text_width(p->yname) + 2 * MARGIN);
	L->height = imax(L->height, text_width(p->vname) + 2 * MARGIN);
	p->yname_y = turned_bottom(p, p->yname);
	p->vname_y = turned_bottom(p, p->vname);
}

static int make_plan(const bk_heatmap *h, plan *p, const char *who, char *err, size_t errlen)
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
	snprintf(p->bar_label[0], sizeof p->bar_label[0], "%.4g", p->vmax);
	snprintf(p->bar_label[1], sizeof p->bar_label[1], "0");
	snprintf(p->bar_label[2], sizeof p->bar_label[2], "%.4g", p->vmax > 0 ? -p->vmax : 0.0);
	p->L.plot_w = plot_side(h->nx, PLOT_MIN_W);
	/* Tall enough for the turned axis and value names to sit beside the plot; square
	 * cells when that height is sensible. */
	int names = imax(text_width(p->yname), text_width(p->vname));
	long square = (long)h->ny * (p->L.plot_w / h->nx);
	p->L.plot_h = p->L.plot_w >= h->nx && square >= imax(PLOT_MIN_H / 2, names) && square <= PLOT_MAX
	                  ? (int)square : plot_side(h->ny, imax(PLOT_MIN_H, names));
	axis_ticks(h->x0, h->x1, p->L.plot_w, 1, &p->xt);
	axis_ticks(h->y0, h->y1, p->L.plot_h, 0, &p->yt);
	layout_x(p);
	layout_y(p);
	place_ticks(p);
	return 0;
}

int bk_heatmap_png_layout(const bk_heatmap *h, bk_heatmap_layout *out, char *err, size_t errlen)
{
	plan p;
	if (err && errlen)
		err[0] = '\0';
	if (make_plan(h, &p, "heatmap", err, errlen))
		return -1;
	*out = p.L;
	return 0;
}

/* ---- drawing ---------------------------------------------------------------------- */

static void draw_cells(canvas *c, const plan *p)
{
	const bk_heatmap *h = p->h;
	const bk_heatmap_layout *L = &p->L;
	unsigned char col[3];
	for (int q = 0; q < L->plot_h; q++) {
		int j = (int)((long)(L->plot_h - 1 - q) * h->ny / L->plot_h); /* y0 at the bottom */
		for (int s = 0; s < L->plot_w; s++) {
			int i = (int)((long)s * h->nx / L->plot_w);
			colour_of(h->value[(size_t)j * h->nx + i], p->vmax, col);
			memcpy(c->rgb + ((size_t)(L->plot_y + q) * c->w + L->plot_x + s) * 3, col, 3);
		}
	}
}

static void frame(canvas *c, int x, int y, int w, int h)
{
	fill(c, x - 1, y - 1, w + 2, 1, black);
	fill(c, x - 1, y + h, w + 2, 1, black);
	fill(c, x - 1, y, 1, h, black);
	fill(c, x + w, y, 1, h, black);
}

static void draw_axes(canvas *c, const plan *p)
{
	const bk_heatmap_layout *L = &p->L;
	frame(c, L->plot_x, L->plot_y, L->plot_w, L->plot_h);
	for (int k = 0; k < p->xt.n; k++) {
		int x = p->xtick_px[k], w = text_width(p->xt.label[k]);
		fill(c, x, L->plot_y + L->plot_h + 1, 1, TICK, black);
		draw_text(c, x - w / 2, p->xlabel_y, p->xt.label[k], 0);
	}
	for (int k = 0; k < p->yt.n; k++) {
		int y = p->ytick_px[k], w = text_width(p->yt.label[k]);
		fill(c, L->plot_x - 1 - TICK, y, TICK, 1, black);
		draw_text(c, p->ylabel_right - w, y - CAP / 2, p->yt.label[k], 0);
	}
	draw_text(c, p->xname_x, p->xname_y, p->xname, 0);
	draw_text(c, p->yname_x, p->yname_y, p->yname, 1);
	draw_text(c, p->title_x, p->title_y, p->title, 0);
}

static void draw_bar(canvas *c, const plan *p)
{
	const bk_heatmap_layout *L = &p->L;
	unsigned char col[3];
	for (int r = 0; r < L->bar_h; r++) {
		colour_at(L->bar_h > 1 ? 1.0 - 2.0 * r / (L->bar_h - 1) : 0.0, col);
		fill(c, L->bar_x, L->bar_y + r, L->bar_w, 1, col);
	}
	frame(c, L->bar_x, L->bar_y, L->bar_w, L->bar_h);
	for (int k = 0; k < 3; k++) {
		fill(c, L->bar_x + L->bar_w + 1, p->bar_tick_px[k], TICK, 1, black);
		draw_text(c, p->barlabel_x, p->bar_tick_px[k] - CAP / 2, p->bar_label[k], 0);
	}
	draw_text(c, p->vname_x, p->vname_y, p->vname, 1);
	if (p->has_nan) {
		fill(c, p->swatch_x, p->swatch_y, SWATCH_W, CAP, grey);
		frame(c, p->swatch_x, p->swatch_y, SWATCH_W, CAP);
		draw_text(c, p->swatch_x + SWATCH_W + 6, p->swatch_y, no_data_text, 0);
	}
}

/* ---- PNG ------------------------------------------------------------------------- */

typedef struct png_sink {
	char msg[200]; /* libpng's report, kept instead of printed */
	int saved_errno; /* errno when it reported: the cause of a failed fwrite */
} png_sink;

static void on_png_error(png_structp png, png_const_charp msg)
{
	png_sink *k = png_get_error_ptr(png);
	k->saved_errno = errno;
	snprintf(k->msg, sizeof k->msg, "%s", msg);
	png_longjmp(png, 1);
}

static void on_png_warning(png_structp png, png_const_charp msg)
{
	(void)png;
	(void)msg;
}

/* 8-bit RGB, sRGB chunk, title and description as tEXt; no tIME chunk and a fixed
 * zlib level, so the bytes depend only on the pixels and the texts. */
static int encode_png(FILE *f, const canvas *c, const char *title, const char *desc, png_sink *k)
{
	png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, k, on_png_error, on_png_warning);
	png_infop info = png ? png_create_info_struct(png) : NULL;
	if (!info) {
		png_destroy_write_struct(&png, NULL);
		snprintf(k->msg, sizeof k->msg, "out of memory");
		return -1;
	}
	if (setjmp(png_jmpbuf(png))) {
		png_destroy_write_struct(&png, &info);
		return -1;
	}
	png_init_io(png, f);
	png_set_compression_level(png, 9);
	png_set_IHDR(png, info, (png_uint_32)c->w, (png_uint_32)c->h, 8, PNG_COLOR_TYPE_RGB,
	             PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
	png_set_sRGB(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
	png_text text[3] = {
		{.compression = PNG_TEXT_COMPRESSION_NONE, .key = "Title", .text = (char *)title},
		{.compression = PNG_TEXT_COMPRESSION_NONE, .key = "Description", .text = (char *)desc},
		{.compression = PNG_TEXT_COMPRESSION_NONE, .key = "Software", .text = "brdfkit " BK_VERSION},
	};
	png_set_text(png, info, text, 3);
	png_write_info(png, info);
	for (int y = 0; y < c->h; y++)
		png_write_row(png, c->rgb + (size_t)y * c->w * 3);
	png_write_end(png, info);
	png_destroy_write_struct(&png, &info);
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

/* ---- the three files --------------------------------------------------------------- */

/* A file written whole under a temporary name before it is renamed to final. */
typedef struct staged {
	char final[4096], tmp[4112];
	int live; /* tmp exists and is ours to remove */
	FILE *f;
} staged;

static const char *errtext(int e, char *buf, size_t len)
{
	snprintf(buf, len, "%s", strerror(e));
	if (buf[0] >= 'A' && buf[0] <= 'Z' && buf[1] >= 'a' && buf[1] <= 'z')
		buf[0] = (char)(buf[0] - 'A' + 'a');
	return buf;
}

static int fail_errno(char *err, size_t errlen, const char *path, const char *what, int e)
{
	char buf[128];
	snprintf(err, errlen, "%s: %s: %s", path, what, errtext(e, buf, sizeof buf));
	return -1;
}

/* Creates the temporary; as_file keeps it open for stdio, otherwise it only reserves
 * a unique name for bk_exr_write to rename its own temporary onto. */
static int stage_open(staged *s, int as_file, char *err, size_t errlen)
{
	snprintf(s->tmp, sizeof s->tmp, "%s.tmpXXXXXX", s->final);
	int fd = mkstemp(s->tmp);
	if (fd < 0)
		return fail_errno(err, errlen, s->final, "cannot create", errno);
	s->live = 1;
	/* mkstemp creates 0600; give the file the mode a plain fopen would. */
	mode_t um = umask(0);
	umask(um);
	fchmod(fd, 0666 & ~um);
	if (!as_file)
		return close(fd) == 0 ? 0 : fail_errno(err, errlen, s->final, "cannot create", errno);
	s->f = fdopen(fd, "wb");
	if (!s->f) {
		int e = errno;
		close(fd);
		return fail_errno(err, errlen, s->final, "cannot create", e);
	}
	return 0;
}

static int stage_close(staged *s, char *err, size_t errlen)
{
	/* fsync before the rename: otherwise a crash can leave a name on an empty file */
	int bad = fflush(s->f) != 0 || ferror(s->f) || fsync(fileno(s->f)) != 0;
	int rc = fclose(s->f);
	s->f = NULL;
	return bad || rc ? fail_errno(err, errlen, s->final, "write failed", errno) : 0;
}

static void discard(staged s[3])
{
	for (int k = 0; k < 3; k++) {
		if (s[k].f)
			fclose(s[k].f);
		s[k].f = NULL;
		if (s[k].live)
			unlink(s[k].tmp);
		s[k].live = 0;
	}
}

/* Messages from bk_exr_write name the temporary; the caller asked for final. */
static void restate(char *err, size_t errlen, const char *tmp, const char *final)
{
	size_t n = strlen(tmp);
	if (!err || errlen == 0 || strncmp(err, tmp, n) != 0)
		return;
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

static int write_png(const plan *p, staged *s, char *err, size_t errlen)
{
	canvas c = {p->L.width, p->L.height, malloc((size_t)p->L.width * p->L.height * 3)};
	char *desc = xprintf("%s: blue < 0 < red, colour scale -%.4g to +%.4g, grey = no data; "
	                     "x = %s, y = %s, y0 at the bottom; %s", p->vname, p->vmax, p->vmax,
	                     p->xname, p->yname, or_default(p->h->conventions, ""));
	int rc = -1;
	if (!c.rgb || !desc) {
		rc = out_of_memory(err, errlen, s->final);
	} else {
		fill(&c, 0, 0, c.w, c.h, white);
		draw_cells(&c, p);
		draw_axes(&c, p);
		draw_bar(&c, p);
		png_sink k = {"", 0};
		if (encode_png(s->f, &c, p->title, desc, &k) == 0)
			rc = stage_close(s, err, errlen);
		else if (ferror(s->f)) /* libpng says only "Write Error" */
			fail_errno(err, errlen, s->final, "write failed", k.saved_errno);
		else
			snprintf(err, errlen, "%s: png: %s", s->final, k.msg);
	}
	free(desc);
	free(c.rgb);
	return rc;
}

static int write_csv(const plan *p, staged *s, char *err, size_t errlen)
{
	const bk_heatmap *h = p->h;
	char col[3][COL_LEN + 8];
	column_names(p, col);
	char *ax = axis_text("x", p->xname, h->nx, h->x0, h->x1);
	char *ay = axis_text("y", p->yname, h->ny, h->y0, h->y1);
	if (!ax || !ay) {
		free(ax);
		free(ay);
		return out_of_memory(err, errlen, s->final);
	}
	FILE *f = s->f;
	char lead[COL_LEN + 40];
	comment(f, "brdfkit " BK_VERSION " heatmap: ", p->title);
	snprintf(lead, sizeof lead, "column %s: ", col[0]);
	comment(f, lead, ax);
	snprintf(lead, sizeof lead, "column %s: ", col[1]);
	comment(f, lead, ay);
	snprintf(lead, sizeof lead, "column %s: %s", col[2], "signed ");
	comment(f, lead, p->vname);
	comment(f, "an empty value is no data (NaN); one row per cell, x varies fastest", "");
	comment(f, "conventions: ", or_default(h->conventions, ""));
	fprintf(f, "%s,%s,%s\n", col[0], col[1], col[2]);
	double dx = (h->x1 - h->x0) / h->nx, dy = (h->y1 - h->y0) / h->ny;
	for (int j = 0; j < h->ny; j++)
		for (int i = 0; i < h->nx; i++) {
			double v = h->value[(size_t)j * h->nx + i];
			fprintf(f, "%.9g,%.9g,", h->x0 + (i + 0.5) * dx, h->y0 + (j + 0.5) * dy);
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
		rc = bk_exr_write(s->tmp, h->nx, h->ny, 1, names, data, 0, attrs,
		                  (int)(sizeof attrs / sizeof attrs[0]), err, errlen);
		if (rc)
			restate(err, errlen, s->tmp, s->final);
	}
	free(rows);
	free(ax);
	free(ay);
	free(axes);
	free(value);
	return rc;
}

/* Renames the three complete temporaries into place. A failure after the first
 * rename removes all three final names (ours and any older ones not yet replaced):
 * a set of the stem is whole or absent, never a mix of two calls. */
static int place_all(staged s[3], char *err, size_t errlen)
{
	int k = 0;
	for (; k < 3; k++) {
		if (rename(s[k].tmp, s[k].final) != 0)
			break;
		s[k].live = 0;
	}
	if (k == 3)
		return 0;
	fail_errno(err, errlen, s[k].final, "cannot rename into place", errno);
	for (int m = 0; k > 0 && m < 3; m++)
		unlink(s[m].final);
	discard(s);
	return -1;
}

int bk_heatmap_write(const bk_heatmap *h, const char *dir, const char *stem, char *err, size_t errlen)
{
	static const char *const ext[3] = {".exr", ".png", ".csv"};
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
	if (make_plan(h, &p, who, err, errlen))
		return -1;
	staged s[3];
	memset(s, 0, sizeof s);
	for (int k = 0; k < 3; k++)
		if (snprintf(s[k].final, sizeof s[k].final, "%s%s", who, ext[k]) < 0)
			return -1; /* cannot happen: who is at most 4089 bytes */
	int rc = stage_open(&s[0], 0, err, errlen) || stage_open(&s[1], 1, err, errlen) ||
	         stage_open(&s[2], 1, err, errlen) || write_png(&p, &s[1], err, errlen) ||
	         write_csv(&p, &s[2], err, errlen) || write_exr(&p, &s[0], err, errlen)
	             ? -1 : place_all(s, err, errlen);
	if (rc)
		discard(s);
	return rc;
}
