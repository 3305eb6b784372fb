/*
 * report.c — the error-against-cost table drawn three ways: the Pareto fronts
 * (error vs cost, error vs ns), the table as CSV (and the timings apart, since
 * they are the only column that changes from run to run), and a self-contained
 * SVG plot. Everything here is a pure function of the rows: the same rows give
 * the same bytes.
 */
#include "compare.h"
#include "out.h"
#include "search/pareto.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/*
 * Seed 001 ("Optimizing PBR for Mobile", SIGGRAPH 2015), slide "Ratio between
 * math (ALU) and fetching texture (TEX)": ALU:TEX ratios per tier: 16, 32, 48,
 * 64 simple ops per bilinear fetch (SGX54x / SGX554 / G6x30 / G6x50, peak,
 * "numbers might be wrong"). Trilinear and cube fetches cost 2-4x that; a LUT
 * here is one bilinear 2D fetch, so the cheapest case is what we price.
 */
const int bk_tier_alu_per_tex[BK_TIERS] = {16, 32, 48, 64};

/* ---- Pareto fronts ----------------------------------------------------------------- */

/* The x of a row on one axis: AXIS_NS, AXIS_GPU + c for ACO's instructions
 * on chip c, or a tier 0..BK_TIERS-1 for ALU cost plus each fetch priced at
 * that tier's ratio in simple ops. */
enum { AXIS_NS = BK_TIERS, AXIS_GPU };

static double axis_x(const bk_compare_row *r, int axis)
{
	if (axis == AXIS_NS)
		return r->ns;
	if (axis >= AXIS_GPU)
		return r->gpu_insn[axis - AXIS_GPU];
	return r->cost + (double)r->tex_fetches * bk_tier_alu_per_tex[axis];
}

/* A row takes part only with a finite error and x: NaN compares false both
 * ways and would let it dominate nothing and be dominated by nothing, i.e.
 * sit on every front; an infinite error means the form blew up somewhere. */
static int placeable(const bk_compare_row *r, int axis)
{
	return isfinite(r->m.max_abs) && isfinite(axis_x(r, axis));
}

/* Row i on the front of one axis: the search layer's one scan
 * (search/pareto.h) over the placeable rows, then every row exactly tied
 * with a member of it (same x, same error: neither beats the other, so both
 * are kept; the scan keeps one of a tie). 0 when out of memory. */
static int on_front(const bk_compare_row *rows, int n, int i, int axis)
{
	if (!placeable(&rows[i], axis))
		return 0;
	bk_pareto_pt *pt = malloc(sizeof *pt * (size_t)(n > 0 ? n : 1));
	if (!pt)
		return 0;
	size_t m = 0;
	for (int j = 0; j < n; j++)
		if (placeable(&rows[j], axis))
			pt[m++] = (bk_pareto_pt){axis_x(&rows[j], axis), rows[j].m.max_abs, rows[j].name, (size_t)j};
	size_t k = bk_pareto_scan(pt, m);
	double xi = axis_x(&rows[i], axis), ei = rows[i].m.max_abs;
	int on = 0;
	for (size_t f = 0; f < k && !on; f++)
		on = pt[f].id == (size_t)i || (pt[f].cost == xi && pt[f].err == ei);
	free(pt);
	return on;
}

void bk_pareto(bk_compare_row *rows, int n, int tier)
{
	if (tier < 0 || tier >= BK_TIERS)
		tier = 0;
	for (int i = 0; i < n; i++) {
		rows[i].pareto_cost = on_front(rows, n, i, tier);
		rows[i].pareto_ns = on_front(rows, n, i, AXIS_NS);
	}
}

/* ---- CSV ------------------------------------------------------------------------------ */

/* %.9g: round-trips every value the table holds to the digits a reader can use;
 * NaN ("not applicable") is an empty field, which every CSV reader takes as missing. */
static void csv_num(FILE *f, double v)
{
	fputc(',', f);
	if (!isnan(v))
		fprintf(f, "%.9g", v);
}

static void csv_text(FILE *f, const char *s)
{
	fputc(',', f);
	bk_csv_field(f, s);
}

static void csv_params(FILE *f, const bk_compare_row *r)
{
	char buf[BK_MAX_PARAMS * 32] = "";
	size_t len = 0;
	for (int j = 0; j < r->nparams && j < BK_MAX_PARAMS; j++)
		len += (size_t)snprintf(buf + len, sizeof buf - len, "%sp%d=%.9g", j ? ";" : "", j,
		                        r->params[j]);
	csv_text(f, buf);
}

static void csv_header(FILE *f, const bk_compare_info *info)
{
	fputs("name,kind,source,form,form_b,parameters,rmse,weighted_rmse,max_abs,max_rel,"
	      "albedo_max_abs",
	      f);
	for (int k = 1; k < BK_K_COUNT; k++) /* BK_K_FREE (0) is not an op */
		fprintf(f, ",%s", bk_opclass_name((bk_opclass)k));
	fputs(",simple,complex,cost,tex_fetches,sampler_slots,spirv", f);
	for (int t = 0; t < BK_TIERS; t++)
		fprintf(f, ",cheaper_than_fetch_%d", bk_tier_alu_per_tex[t]);
	fputs(",pareto_cost", f);
	for (int c = 0; c < info->nchips; c++)
		fprintf(f, ",aco_%s_instructions,aco_%s_transcendental,aco_%s_vgprs", info->chip[c], info->chip[c],
		        info->chip[c]);
	fputc('\n', f);
}

static void csv_row(FILE *f, const bk_compare_row *r, const bk_compare_info *info)
{
	bk_csv_field(f, r->name);
	csv_text(f, r->kind);
	csv_text(f, r->source);
	csv_text(f, r->form);
	csv_text(f, r->form_b);
	csv_params(f, r);
	csv_num(f, r->m.rmse);
	csv_num(f, r->m.weighted_rmse);
	csv_num(f, r->m.max_abs);
	csv_num(f, r->m.max_rel);
	csv_num(f, r->m.albedo_max_abs);
	for (int k = 1; k < BK_K_COUNT; k++)
		fprintf(f, ",%d", r->ops.n[k]);
	fprintf(f, ",%d,%d", r->ops.simple, r->ops.complex);
	csv_num(f, r->cost);
	fprintf(f, ",%d,%d,", r->tex_fetches, r->sampler_slots);
	if (r->spirv >= 0) /* -1: no SPIR-V tools, or no form: missing, like NaN */
		fprintf(f, "%d", r->spirv);
	for (int t = 0; t < BK_TIERS; t++)
		fprintf(f, ",%d", r->cheaper_than_fetch[t]);
	fprintf(f, ",%d", r->pareto_cost);
	for (int c = 0; c < info->nchips; c++) {
		csv_num(f, r->gpu_insn[c]);
		csv_num(f, r->gpu_transc[c]);
		csv_num(f, r->gpu_vgprs[c]);
	}
	fputc('\n', f);
}

static const bk_compare_info default_info = BK_COMPARE_INFO_INIT;

void bk_compare_csv(FILE *f, const bk_compare_row *rows, int n, const bk_compare_info *info)
{
	if (!info)
		info = &default_info;
	csv_header(f, info);
	for (int i = 0; i < n; i++)
		csv_row(f, &rows[i], info);
}

void bk_timing_csv(FILE *f, const bk_compare_row *rows, int n)
{
	fputs("name,ns_per_eval,ns_min,ns_max,pareto_ns\n", f);
	for (int i = 0; i < n; i++) {
		bk_csv_field(f, rows[i].name);
		csv_num(f, rows[i].ns);
		csv_num(f, rows[i].ns_min);
		csv_num(f, rows[i].ns_max);
		fprintf(f, ",%d\n", rows[i].pareto_ns);
	}
}

/* ---- SVG: text ----------------------------------------------------------------------- */

/* Length of the well-formed UTF-8 sequence at s (1..4), or 0 if it is not one.
 * The table is Unicode's "well-formed byte sequences" (chapter 3, table 3-7):
 * the second byte's range rules out overlong forms and surrogates, which an
 * XML parser rejects. A NUL ends a sequence early and so never matches. */
static int utf8_len(const unsigned char *s)
{
	static const struct {
		unsigned char lead_lo, lead_hi, next_lo, next_hi, len;
	} seq[] = {
		{0x00, 0x7f, 0, 0, 1},       {0xc2, 0xdf, 0x80, 0xbf, 2}, {0xe0, 0xe0, 0xa0, 0xbf, 3},
		{0xe1, 0xec, 0x80, 0xbf, 3}, {0xed, 0xed, 0x80, 0x9f, 3}, {0xee, 0xef, 0x80, 0xbf, 3},
		{0xf0, 0xf0, 0x90, 0xbf, 4}, {0xf1, 0xf3, 0x80, 0xbf, 4}, {0xf4, 0xf4, 0x80, 0x8f, 4},
	};
	for (size_t k = 0; k < sizeof seq / sizeof seq[0]; k++) {
		if (s[0] < seq[k].lead_lo || s[0] > seq[k].lead_hi)
			continue;
		if (seq[k].len > 1 && (s[1] < seq[k].next_lo || s[1] > seq[k].next_hi))
			return 0;
		for (int i = 2; i < seq[k].len; i++)
			if ((s[i] & 0xc0) != 0x80)
				return 0;
		return seq[k].len;
	}
	return 0;
}

/* Text as XML character data or attribute value: the five specials escaped,
 * control characters XML 1.0 forbids and bytes that are not UTF-8 become '?',
 * so any name still gives a well-formed file. */
static void xml_text(FILE *f, const char *s)
{
	const unsigned char *p = (const unsigned char *)s;
	while (*p) {
		int len = utf8_len(p);
		if (len == 0 || (*p < 0x20 && *p != '\t' && *p != '\n')) {
			fputc('?', f);
			p += len ? len : 1;
			continue;
		}
		switch (*p) {
		case '&': fputs("&amp;", f); break;
		case '<': fputs("&lt;", f); break;
		case '>': fputs("&gt;", f); break;
		case '"': fputs("&quot;", f); break;
		case '\'': fputs("&apos;", f); break;
		default: fwrite(p, 1, (size_t)len, f);
		}
		p += len;
	}
}

/* Characters (code points) in s: enough to estimate a label's width. */
static int text_chars(const char *s)
{
	int n = 0;
	for (; *s; s++)
		n += ((unsigned char)*s & 0xc0) != 0x80;
	return n;
}

/* ---- SVG: layout and scales -------------------------------------------------------- */

/* Canvas and plot area in px; the legend sits right of the plot. */
#define SVG_W 760
#define SVG_H 520
#define PLOT_L 76.0
#define PLOT_R 588.0
#define PLOT_T 48.0
#define PLOT_B 456.0
#define LEGEND_X 604.0
#define LABEL_PT 9.0   /* point labels, px */
#define CHAR_W 0.56    /* average sans-serif advance in ems: label width estimate */

typedef struct kind_style {
	const char *kind, *label, *colour;
} kind_style;

/* Colours: the first four of Tableau 10 (matplotlib's default cycle). Red and
 * green are hard to tell apart for some readers, so colour is never the only
 * cue: every point is labelled and its tooltip names its kind. The last entry
 * catches any kind not listed. */
static const kind_style kinds[] = {
	{"published", "published constants", "#1f77b4"},
	{"refit", "refitted constants", "#d62728"},
	{"lut", "look-up texture", "#2ca02c"},
	{"form", "searched form", "#9467bd"},
	{NULL, "other", "#7f7f7f"},
};
enum { NKINDS = sizeof kinds / sizeof kinds[0] };

static int kind_index(const char *kind)
{
	for (int k = 0; k < NKINDS - 1; k++)
		if (strcmp(kind, kinds[k].kind) == 0)
			return k;
	return NKINDS - 1;
}

typedef struct scale {
	double x_lo, x_hi, x_step;  /* linear, ticks every x_step */
	int d_lo, d_hi;             /* log10 decades of the y axis */
	int has_zero;               /* zero errors drawn on the bottom decade, labelled 0 */
} scale;

/* A "nice" tick step (1, 2 or 5 times a power of ten) for about 6 intervals. */
static double nice_step(double span)
{
	double raw = span / 6.0, mag = pow(10.0, floor(log10(raw))), norm = raw / mag;
	return (norm <= 1.0 ? 1.0 : norm <= 2.0 ? 2.0 : norm <= 5.0 ? 5.0 : 10.0) * mag;
}

/* A plot's x axis (0 cost, 1 ns, 2 + c chip c) as an axis of the fronts. */
static int plot_axis(int xaxis)
{
	return xaxis == 0 ? 0 : xaxis == 1 ? AXIS_NS : AXIS_GPU + xaxis - 2;
}

static double point_x(const bk_compare_row *r, int xaxis)
{
	return axis_x(r, plot_axis(xaxis));
}

static int plotted(const bk_compare_row *r, int xaxis)
{
	return placeable(r, plot_axis(xaxis));
}

static void x_range(scale *s, const bk_compare_row *rows, int n, int xaxis)
{
	double lo = 0.0, hi = 0.0; /* cost and time start at zero: the axis shows ratios honestly */
	for (int i = 0; i < n; i++)
		if (plotted(&rows[i], xaxis)) {
			double x = point_x(&rows[i], xaxis);
			lo = fmin(lo, x);
			hi = fmax(hi, xaxis == 1 && isfinite(rows[i].ns_max) ? fmax(x, rows[i].ns_max) : x);
		}
	if (hi <= lo)
		hi = lo + 1.0;
	s->x_step = nice_step(hi - lo);
	s->x_lo = floor(lo / s->x_step) * s->x_step;
	s->x_hi = ceil(hi / s->x_step) * s->x_step;
}

/* Decades covering the positive errors. Zero errors cannot sit on a log axis:
 * they go one decade below the lowest decade tick (at most the smallest
 * positive error / 10), on a tick labelled 0 with a break in the axis above it,
 * so they read as "exact" and never as a small number. */
static void y_range(scale *s, const bk_compare_row *rows, int n, int xaxis)
{
	double lo = INFINITY, hi = 0.0;
	s->has_zero = 0;
	for (int i = 0; i < n; i++) {
		if (!plotted(&rows[i], xaxis))
			continue;
		double e = fabs(rows[i].m.max_abs);
		if (e > 0.0) {
			lo = fmin(lo, e);
			hi = fmax(hi, e);
		} else
			s->has_zero = 1;
	}
	if (hi == 0.0) /* nothing positive: show 1e-3 .. 1 */
		lo = 1e-3, hi = 1.0;
	s->d_lo = (int)floor(log10(lo));
	s->d_hi = (int)ceil(log10(hi));
	if (s->d_hi <= s->d_lo)
		s->d_hi = s->d_lo + 1;
	s->d_lo -= s->has_zero;
}

static double px_x(const scale *s, double x)
{
	return PLOT_L + (x - s->x_lo) / (s->x_hi - s->x_lo) * (PLOT_R - PLOT_L);
}

static double px_y(const scale *s, double err)
{
	double d = err > 0.0 ? log10(err) : s->d_lo; /* zero: on the bottom tick, labelled 0 */
	return PLOT_B - (d - s->d_lo) / (s->d_hi - s->d_lo) * (PLOT_B - PLOT_T);
}

static double row_px_y(const scale *s, const bk_compare_row *r)
{
	return px_y(s, fabs(r->m.max_abs));
}

/* ---- SVG: axes -------------------------------------------------------------------------- */

/* "0.01", "1", "1e-05": plain decimals near 1, exponents beyond. */
static void decade_label(char *buf, size_t len, int d)
{
	if (d >= -3 && d <= 3)
		snprintf(buf, len, "%g", pow(10.0, d));
	else
		snprintf(buf, len, "1e%d", d);
}

static void svg_x_axis(FILE *f, const scale *s, int xaxis, const bk_compare_info *info)
{
	int nticks = (int)lround((s->x_hi - s->x_lo) / s->x_step);
	for (int i = 0; i <= nticks; i++) {
		double v = s->x_lo + i * s->x_step, x = px_x(s, v);
		if (fabs(v) < 1e-9 * s->x_step)
			v = 0.0; /* no "-0" or 1e-17 from the sum */
		fprintf(f, "<line class=\"grid\" x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>\n", x,
		        PLOT_T, x, PLOT_B);
		fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">%g</text>\n", x, PLOT_B + 16,
		        v);
	}
	fprintf(f, "<text x=\"%.1f\" y=\"%d\" text-anchor=\"middle\" font-size=\"12\">", (PLOT_L + PLOT_R) / 2,
	        SVG_H - 28);
	if (xaxis == 1)
		fputs("CPU time per evaluation, ns (generated C, -O2; bars: min to max)", f);
	else if (xaxis >= 2) { /* names from option values: escaped like any text */
		fputs("AMD ", f);
		xml_text(f, info->chip[xaxis - 2]);
		fputs(" instructions (Mesa RADV/ACO), net of a load/store baseline", f);
	} else if (!strcmp(info->cost_model, "ir")) {
		fprintf(f, "cost: simple ALU ops + %g \xc3\x97 complex + %d per bilinear fetch", info->complex,
		        bk_tier_alu_per_tex[0]);
	} else {
		fputs("cost (model ", f);
		xml_text(f, info->cost_model);
		fprintf(f, "): %g \xc3\x97 simple + %g \xc3\x97 complex + %d per bilinear fetch", info->simple, info->complex,
		        bk_tier_alu_per_tex[0]);
	}
	fputs("</text>\n", f);
	if (xaxis >= 2)
		fprintf(f, "<text x=\"%.1f\" y=\"%d\" text-anchor=\"middle\" font-size=\"10\" fill=\"#555\">"
		           "(closed forms only: a LUT's fetch is not compiled; AMD only, no mobile compiler runs "
		           "offline)</text>\n",
		        (PLOT_L + PLOT_R) / 2, SVG_H - 13);
	if (!xaxis)
		fprintf(f, "<text x=\"%.1f\" y=\"%d\" text-anchor=\"middle\" font-size=\"10\" fill=\"#555\">"
		           "(a fetch priced at the lowest ALU:TEX tier of the talk, %d:1; higher tiers make "
		           "look-up textures dearer)</text>\n",
		        (PLOT_L + PLOT_R) / 2, SVG_H - 13, bk_tier_alu_per_tex[0]);
}

static void svg_y_axis(FILE *f, const scale *s)
{
	char buf[32];
	for (int d = s->d_lo; d <= s->d_hi; d++) {
		double y = px_y(s, pow(10.0, d));
		fprintf(f, "<line class=\"grid\" x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>\n", PLOT_L, y,
		        PLOT_R, y);
		if (s->has_zero && d == s->d_lo)
			snprintf(buf, sizeof buf, "0");
		else
			decade_label(buf, sizeof buf, d);
		fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\">%s</text>\n", PLOT_L - 6, y + 4, buf);
		if (d == s->d_hi || (s->has_zero && d == s->d_lo))
			continue;
		for (int m = 2; m <= 9; m++) { /* minor ticks: 2..9 times the decade */
			double ym = px_y(s, m * pow(10.0, d));
			fprintf(f, "<line class=\"minor\" x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>\n",
			        PLOT_L, ym, PLOT_L + 4, ym);
		}
	}
	if (s->has_zero) { /* the break: two short slashes between "0" and the first decade */
		double yb = (px_y(s, pow(10.0, s->d_lo)) + px_y(s, pow(10.0, s->d_lo + 1))) / 2;
		fprintf(f, "<path class=\"break\" d=\"M%.1f %.1fl8 -4M%.1f %.1fl8 -4\"/>\n", PLOT_L - 4, yb + 1,
		        PLOT_L - 4, yb + 5);
	}
	fprintf(f, "<text transform=\"translate(18 %.1f) rotate(-90)\" text-anchor=\"middle\" "
	           "font-size=\"12\">max |error| (log scale)</text>\n",
	        (PLOT_T + PLOT_B) / 2);
	fprintf(f, "<rect class=\"frame\" x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\"/>\n", PLOT_L,
	        PLOT_T, PLOT_R - PLOT_L, PLOT_B - PLOT_T);
}

/* ---- SVG: points, front, labels, legend ------------------------------------------------ */

/* The front on the plotted axis, recomputed here so the plot agrees with
 * itself whatever tier the caller's bk_pareto used. Joined as a staircase in
 * x order (right, then down): the best error reachable at each x. The order is
 * total (x, then error, then row index) and found by repeated minimum, which
 * needs no memory: fronts are short and tables a few hundred rows at most. */
static int front_before(const bk_compare_row *rows, int a, int b, int xaxis)
{
	double xa = point_x(&rows[a], xaxis), xb = point_x(&rows[b], xaxis);
	if (xa != xb)
		return xa < xb;
	if (rows[a].m.max_abs != rows[b].m.max_abs)
		return rows[a].m.max_abs > rows[b].m.max_abs;
	return a < b;
}

static int svg_on_front(const bk_compare_row *rows, int n, int i, int xaxis)
{
	return on_front(rows, n, i, plot_axis(xaxis));
}

static void svg_front(FILE *f, const bk_compare_row *rows, int n, int xaxis, const scale *s)
{
	int prev = -1;
	double prev_y = 0.0;
	for (;;) {
		int next = -1;
		for (int i = 0; i < n; i++)
			if ((prev < 0 || front_before(rows, prev, i, xaxis)) &&
			    (next < 0 || front_before(rows, i, next, xaxis)) && svg_on_front(rows, n, i, xaxis))
				next = i;
		if (next < 0)
			break;
		double x = px_x(s, point_x(&rows[next], xaxis)), y = row_px_y(s, &rows[next]);
		if (prev < 0)
			fprintf(f, "<polyline class=\"front\" points=\"%.1f,%.1f", x, y);
		else
			fprintf(f, " %.1f,%.1f %.1f,%.1f", x, prev_y, x, y);
		prev = next;
		prev_y = y;
	}
	if (prev >= 0)
		fputs("\"/>\n", f);
}

static void svg_point(FILE *f, const bk_compare_row *r, int xaxis, const scale *s, int front)
{
	const kind_style *k = &kinds[kind_index(r->kind)];
	double x = px_x(s, point_x(r, xaxis)), y = row_px_y(s, r);
	if (xaxis == 1 && isfinite(r->ns_min) && isfinite(r->ns_max))
		fprintf(f, "<line class=\"range\" x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"%s\"/>\n",
		        px_x(s, r->ns_min), y, px_x(s, r->ns_max), y, k->colour);
	fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"%s\" stroke=\"%s\" fill=\"%s\"%s><title>", x, y,
	        front ? "4.5" : "3.5", k->colour, front ? k->colour : "#fff",
	        r->m.max_abs == 0.0 ? " stroke-dasharray=\"2 1\"" : "");
	xml_text(f, r->name);
	fputs(" (", f);
	xml_text(f, r->kind);
	fprintf(f, "): max |error| %.3g, %s %.4g%s</title></circle>\n", r->m.max_abs,
	        xaxis == 1 ? "ns" : xaxis ? "instructions" : "cost", point_x(r, xaxis), front ? ", on the front" : "");
}

/* A label's box in px, for the overlap nudge. */
typedef struct box {
	double x0, y0, x1, y1;
} box;

static int overlaps(box a, box b)
{
	return a.x0 < b.x1 && b.x0 < a.x1 && a.y0 < b.y1 && b.y0 < a.y1;
}

/* Labels go right of and above the point (left of it near the right edge).
 * A label that would overlap a point or a label already placed moves down a
 * line, then up, alternating, up to four lines each way, else stays where it
 * was first put; the order of rows fixes the result. */
static box place_label(const box *placed, int nplaced, double x, double y, double w, int *anchor_end)
{
	*anchor_end = x + 6 + w > PLOT_R;
	double bx = *anchor_end ? x - 6 - w : x + 6, by = y - 4;
	box b = {bx, by - LABEL_PT, bx + w, by + 2};
	for (int step = 0; step <= 8; step++) {
		double dy = (step + 1) / 2 * (LABEL_PT + 1) * (step % 2 ? 1 : -1);
		box t = {b.x0, b.y0 + dy, b.x1, b.y1 + dy};
		int clash = 0;
		for (int i = 0; i < nplaced && !clash; i++)
			clash = overlaps(t, placed[i]);
		if (!clash)
			return t;
	}
	return b;
}

/* A point's marker as a box, so that labels keep off it. */
static box point_box(const bk_compare_row *r, int xaxis, const scale *s)
{
	double x = px_x(s, point_x(r, xaxis)), y = row_px_y(s, r);
	return (box){x - 5, y - 5, x + 5, y + 5};
}

static void svg_labels(FILE *f, const bk_compare_row *rows, int n, int xaxis, const scale *s)
{
	/* Without memory for the boxes, labels stay at their first place: same bytes, more overlap. */
	box *placed = malloc(sizeof *placed * (size_t)(2 * n + 1));
	int nplaced = 0;
	for (int i = 0; i < n && placed; i++)
		if (plotted(&rows[i], xaxis))
			placed[nplaced++] = point_box(&rows[i], xaxis, s);
	for (int i = 0; i < n; i++) {
		if (!plotted(&rows[i], xaxis))
			continue;
		double x = px_x(s, point_x(&rows[i], xaxis)), y = row_px_y(s, &rows[i]);
		double w = text_chars(rows[i].name) * CHAR_W * LABEL_PT;
		int end;
		box b = place_label(placed, nplaced, x, y, w, &end);
		if (placed)
			placed[nplaced++] = b;
		if (fabs(b.y1 - (y + 2)) > LABEL_PT + 1.5) /* moved off its line: a leader shows whose it is */
			fprintf(f, "<line class=\"leader\" x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>\n",
			        x, y, end ? b.x1 : b.x0, b.y1 - 5);
		fprintf(f, "<text class=\"label\" x=\"%.1f\" y=\"%.1f\"%s>", end ? b.x1 : b.x0, b.y1 - 2,
		        end ? " text-anchor=\"end\"" : "");
		xml_text(f, rows[i].name);
		fputs("</text>\n", f);
	}
	free(placed);
}

static void svg_legend(FILE *f, const bk_compare_row *rows, int n, int xaxis)
{
	double y = PLOT_T + 8;
	fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-weight=\"bold\">kind</text>\n", LEGEND_X, y);
	for (int k = 0; k < NKINDS; k++) {
		int present = 0;
		for (int i = 0; i < n && !present; i++)
			present = plotted(&rows[i], xaxis) && kind_index(rows[i].kind) == k;
		if (!present)
			continue;
		y += 18;
		/* a rounded square, not a <circle>: circles are the data points only */
		fprintf(f, "<rect x=\"%.1f\" y=\"%.1f\" width=\"9\" height=\"9\" rx=\"4.5\" fill=\"%s\"/>\n",
		        LEGEND_X, y - 8, kinds[k].colour);
		fprintf(f, "<text x=\"%.1f\" y=\"%.1f\">%s</text>\n", LEGEND_X + 15, y, kinds[k].label);
	}
	y += 30;
	fprintf(f, "<rect x=\"%.1f\" y=\"%.1f\" width=\"9\" height=\"9\" rx=\"4.5\" fill=\"#555\"/>\n"
	           "<text x=\"%.1f\" y=\"%.1f\">on the Pareto front</text>\n",
	        LEGEND_X, y - 8, LEGEND_X + 15, y);
	y += 18;
	fprintf(f, "<rect x=\"%.1f\" y=\"%.1f\" width=\"9\" height=\"9\" rx=\"4.5\" fill=\"#fff\" "
	           "stroke=\"#555\"/>\n<text x=\"%.1f\" y=\"%.1f\">dominated</text>\n",
	        LEGEND_X, y - 8, LEGEND_X + 15, y);
	int hidden = 0;
	for (int i = 0; i < n; i++)
		hidden += !plotted(&rows[i], xaxis);
	if (hidden)
		fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" fill=\"#555\">%d not shown:</text>\n"
		           "<text x=\"%.1f\" y=\"%.1f\" fill=\"#555\">%s</text>\n",
		        LEGEND_X, y + 30, hidden, LEGEND_X, y + 44,
		        xaxis == 1 ? "untimed, or no finite error" : xaxis ? "not compiled, or no finite error"
		                                                           : "no finite error");
}

void bk_compare_svg(FILE *f, const bk_compare_row *rows, int n, int xaxis, const char *title,
                    const bk_compare_info *info)
{
	scale s = {0};
	if (!info)
		info = &default_info;
	if (xaxis < 0 || xaxis >= 2 + info->nchips)
		xaxis = 0;
	x_range(&s, rows, n, xaxis);
	y_range(&s, rows, n, xaxis);
	fprintf(f, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" viewBox=\"0 0 %d %d\" "
	           "font-family=\"sans-serif\" font-size=\"11\" class=\"bk-plot\">\n",
	        SVG_W, SVG_H, SVG_W, SVG_H);
	/* Inline in an HTML page a <style> applies to the whole document: every
	 * selector is scoped to the plot's class so none reaches the page. */
	fputs("<style>.bk-plot .grid{stroke:#e4e4e4}.bk-plot .minor{stroke:#999}"
	      ".bk-plot .frame{fill:none;stroke:#333}"
	      ".bk-plot .front{fill:none;stroke:#333;stroke-width:1.2;stroke-dasharray:5 3}"
	      ".bk-plot .range{stroke-width:1.5;opacity:.6}.bk-plot .leader{stroke:#aaa;stroke-width:.6}"
	      ".bk-plot .break{stroke:#333;fill:none}"
	      ".bk-plot .label{font-size:9px;fill:#222;paint-order:stroke;stroke:#fff;stroke-width:2.5px;"
	      "stroke-linejoin:round}.bk-plot circle{stroke-width:1.5}</style>\n",
	      f);
	fprintf(f, "<rect width=\"%d\" height=\"%d\" fill=\"#fff\"/>\n", SVG_W, SVG_H);
	fputs("<text x=\"380\" y=\"26\" text-anchor=\"middle\" font-size=\"15\" font-weight=\"bold\">", f);
	xml_text(f, title ? title : "");
	fputs("</text>\n", f);
	svg_x_axis(f, &s, xaxis, info);
	svg_y_axis(f, &s);
	svg_front(f, rows, n, xaxis, &s);
	for (int i = 0; i < n; i++)
		if (plotted(&rows[i], xaxis))
			svg_point(f, &rows[i], xaxis, &s, svg_on_front(rows, n, i, xaxis));
	svg_labels(f, rows, n, xaxis, &s);
	svg_legend(f, rows, n, xaxis);
	fputs("</svg>\n", f);
}
