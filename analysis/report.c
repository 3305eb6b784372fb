/*
 * report.c — the error-against-cost table drawn three ways: the Pareto fronts
 * (error vs cost, error vs ns), the table as CSV (and the timings apart, since
 * they are the only column that changes from run to run), and the plots as
 * PNG, SVG and PDF (plot.h). Everything here is a pure function of the rows: the same rows give
 * the same bytes.
 */
#include "compare.h"
#include "out.h"
#include "plot.h"
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

/* ---- the plots (plot.h) ------------------------------------------------------------ */

typedef struct kind_style {
	const char *kind, *label;
	unsigned rgb;
	int marker;
} kind_style;

/* Colours: the first four of Tableau 10 (matplotlib's default cycle). Red and
 * green are hard to tell apart for some readers, so colour is never the only
 * cue: each kind has its own marker shape too. The last entry catches any kind
 * not listed. */
static const kind_style kinds[] = {
	{"published", "published constants", 0x1f77b4, BK_PLOT_CIRCLE},
	{"refit", "refitted constants", 0xd62728, BK_PLOT_SQUARE},
	{"lut", "look-up texture", 0x2ca02c, BK_PLOT_TRIANGLE},
	{"form", "searched form", 0x9467bd, BK_PLOT_CIRCLE},
	{NULL, "other", 0x7f7f7f, BK_PLOT_CIRCLE},
};
enum { NKINDS = sizeof kinds / sizeof kinds[0] };

static int kind_index(const char *kind)
{
	for (int k = 0; k < NKINDS - 1; k++)
		if (strcmp(kind, kinds[k].kind) == 0)
			return k;
	return NKINDS - 1;
}

/* A plot's x axis (0 cost, 1 ns, 2 + c chip c) as an axis of the fronts. */
static int plot_axis(int xaxis)
{
	return xaxis == 0 ? 0 : xaxis == 1 ? AXIS_NS : AXIS_GPU + xaxis - 2;
}

/* The front on the plotted axis, recomputed here so the plot agrees with
 * itself whatever tier the caller's bk_pareto used, in x order (x, then
 * error falling, then row index): the staircase's vertices. */
static int front_before(const bk_compare_row *rows, int a, int b, int axis)
{
	double xa = axis_x(&rows[a], axis), xb = axis_x(&rows[b], axis);
	if (xa != xb)
		return xa < xb;
	if (rows[a].m.max_abs != rows[b].m.max_abs)
		return rows[a].m.max_abs > rows[b].m.max_abs;
	return a < b;
}

/* Everything a compare plot holds; arrays sized by the row count. */
typedef struct cfig {
	bk_plot p;
	bk_plot_series s[2 * NKINDS + 2]; /* the staircase, dominated and front per kind, the hollow key */
	double *x, *y, *lo, *hi; /* per series slot: n each */
	const char **label;
	char xlabel[400], note[200], title[200];
} cfig;

static void cfig_free(cfig *c)
{
	free(c->x);
	free(c->y);
	free(c->lo);
	free(c->hi);
	free(c->label);
}

static void x_label(cfig *c, int xaxis, const bk_compare_info *info)
{
	if (xaxis == 1)
		snprintf(c->xlabel, sizeof c->xlabel, "CPU time per evaluation (ns, generated C at -O2; bars: min to max)");
	else if (xaxis >= 2)
		snprintf(c->xlabel, sizeof c->xlabel, "AMD %s instructions (Mesa RADV/ACO, net of a load/store baseline)",
		         info->chip[xaxis - 2]);
	else if (!strcmp(info->cost_model, "ir"))
		snprintf(c->xlabel, sizeof c->xlabel, "cost (simple ALU ops + %g \xc3\x97 complex + %d per bilinear fetch)",
		         info->complex, bk_tier_alu_per_tex[0]);
	else
		snprintf(c->xlabel, sizeof c->xlabel, "cost (model %s: %g \xc3\x97 simple + %g \xc3\x97 complex + %d per fetch)",
		         info->cost_model, info->simple, info->complex, bk_tier_alu_per_tex[0]);
}

/* Builds the figure: per kind one series of dominated rows (hollow) and one of
 * front members (filled, drawn over the others and labelled first, plot.h),
 * the front as a dashed staircase, log error against the axis. */
static int cfig_build(cfig *c, const bk_compare_row *rows, int n, int xaxis, const char *title,
                      const bk_compare_info *info)
{
	memset(c, 0, sizeof *c);
	int axis = plot_axis(xaxis), ns = 2 * NKINDS + 1;
	size_t m = (size_t)(n > 0 ? n : 1) * (size_t)ns;
	c->x = malloc(sizeof *c->x * m);
	c->y = malloc(sizeof *c->y * m);
	c->lo = malloc(sizeof *c->lo * m);
	c->hi = malloc(sizeof *c->hi * m);
	c->label = malloc(sizeof *c->label * m);
	char *on = calloc((size_t)(n > 0 ? n : 1), 1);
	if (!c->x || !c->y || !c->lo || !c->hi || !c->label || !on) {
		free(on);
		cfig_free(c);
		return -1;
	}
	for (int i = 0; i < n; i++)
		on[i] = (char)on_front(rows, n, i, axis);
	int hidden = 0, zero = 0;
	for (int t = 0; t < ns - 1; t++) {
		bk_plot_series *S = &c->s[t + 1];
		int k = t % NKINDS, front = t >= NKINDS; /* dominated first: front markers drawn over them */
		size_t base = (size_t)(t + 1) * (size_t)(n > 0 ? n : 1);
		*S = (bk_plot_series){front ? kinds[k].label : NULL, BK_PLOT_POINTS, kinds[k].marker, !front,
		                      kinds[k].rgb, 0, c->x + base, c->y + base, c->label + base, NULL, NULL};
		for (int i = 0; i < n; i++) {
			if (kind_index(rows[i].kind) != k || on[i] != front)
				continue;
			if (!placeable(&rows[i], axis)) {
				hidden++;
				continue;
			}
			int j = S->n++;
			c->x[base + j] = axis_x(&rows[i], axis);
			c->y[base + j] = fabs(rows[i].m.max_abs);
			zero |= rows[i].m.max_abs == 0.0;
			c->label[base + j] = rows[i].name;
			c->lo[base + j] = xaxis == 1 ? rows[i].ns_min : NAN;
			c->hi[base + j] = xaxis == 1 ? rows[i].ns_max : NAN;
		}
		if (xaxis == 1)
			S->xlo = c->lo + base, S->xhi = c->hi + base;
	}
	for (int k = 0; k < NKINDS; k++) /* the legend names each kind drawn once, at its filled series */
		if (c->s[1 + k].n == 0 && c->s[1 + NKINDS + k].n == 0)
			c->s[1 + NKINDS + k].name = NULL;
	int hollow = 0;
	for (int k = 0; k < NKINDS; k++)
		hollow += c->s[1 + k].n;
	/* a legend entry of its own (no points) says what hollow means, whatever the kind */
	c->s[ns] = (bk_plot_series){hollow ? "hollow: off the front" : NULL, BK_PLOT_POINTS, BK_PLOT_CIRCLE, 1, 0x7f7f7f, 0,
	                            c->x, c->y, NULL, NULL, NULL};
	/* the staircase: front members by repeated minimum (fronts are short) */
	bk_plot_series *F = &c->s[0];
	*F = (bk_plot_series){"Pareto front", BK_PLOT_STEPS, BK_PLOT_CIRCLE, 0, 0x333333, 0, c->x, c->y, NULL, NULL, NULL};
	for (int prev = -1;;) {
		int next = -1;
		for (int i = 0; i < n; i++)
			if (on[i] && (prev < 0 || front_before(rows, prev, i, axis)) &&
			    (next < 0 || front_before(rows, i, next, axis)))
				next = i;
		if (next < 0)
			break;
		c->x[F->n] = axis_x(&rows[next], axis);
		c->y[F->n++] = fabs(rows[next].m.max_abs);
		prev = next;
	}
	if (F->n == 0)
		F->name = NULL;
	free(on);
	/* the axes over every plotted point (and the time bars) */
	c->p.x.label = c->xlabel;
	c->p.y.label = "max |error| (log scale)";
	c->p.y.log = 1;
	for (int t = 1; t < ns; t++) {
		bk_plot_axis_grow(&c->p.x, c->s[t].x, c->s[t].n);
		bk_plot_axis_grow(&c->p.y, c->s[t].y, c->s[t].n);
		if (c->s[t].xhi)
			bk_plot_axis_grow(&c->p.x, c->s[t].xhi, c->s[t].n);
	}
	if (!(c->p.x.hi > c->p.x.lo)) {
		double none[1] = {1.0};
		bk_plot_axis_fit(&c->p.x, none, 1);
	}
	if (!(c->p.y.hi > c->p.y.lo))
		bk_plot_axis_fit(&c->p.y, NULL, 0);
	if (zero) { /* exact rows sit one decade under the rest, on a tick labelled 0 */
		c->p.y.lo /= 10.0;
		c->p.y.zero_at_lo = 1;
	}
	x_label(c, xaxis, info);
	int len = 0;
	if (hidden)
		len = snprintf(c->note, sizeof c->note, "%d not shown (%s)", hidden,
		               xaxis == 1 ? "untimed, or no finite error" : xaxis ? "not compiled, or no finite error"
		                                                                : "no finite error");
	if (!xaxis && len >= 0 && (size_t)len < sizeof c->note)
		snprintf(c->note + len, sizeof c->note - (size_t)len, "%sa fetch priced at the talk's lowest ALU:TEX tier, %d:1",
		         len ? "; " : "", bk_tier_alu_per_tex[0]);
	if (xaxis >= 2 && len >= 0 && (size_t)len < sizeof c->note)
		snprintf(c->note + len, sizeof c->note - (size_t)len, "%sclosed forms only: a LUT's fetch is not compiled",
		         len ? "; " : "");
	snprintf(c->title, sizeof c->title, "%s", title ? title : "");
	/* a chip's plot is one of four side by side on the page: a single column */
	c->p.width_in = xaxis >= 2 ? BK_PLOT_SINGLE_W : BK_PLOT_DOUBLE_W;
	c->p.height_in = xaxis >= 2 ? 3.0 : 4.2;
	c->p.title = title ? c->title : NULL;
	c->p.note = c->note[0] ? c->note : NULL;
	c->p.provenance = "brdfkit compare: max |error| over the samples against cost; see compare.csv";
	c->p.series = c->s;
	c->p.nseries = ns + 1;
	return 0;
}

int bk_compare_plot(const bk_compare_row *rows, int n, int xaxis, const char *title, const bk_compare_info *info,
                    const char *dir, const char *stem, char *err, size_t errlen)
{
	cfig c;
	if (!info)
		info = &default_info;
	if (xaxis < 0 || xaxis >= 2 + info->nchips)
		xaxis = 0;
	if (cfig_build(&c, rows, n, xaxis, title, info)) {
		snprintf(err, errlen, "%s: out of memory", stem);
		return -1;
	}
	int rc = bk_plot_write_files(&c.p, dir, stem, err, errlen);
	cfig_free(&c);
	return rc;
}

int bk_compare_plot_unexplained(const bk_compare_row *rows, int n, int xaxis, const bk_compare_info *info)
{
	cfig c;
	if (!info)
		info = &default_info;
	if (xaxis < 0 || xaxis >= 2 + info->nchips)
		xaxis = 0;
	if (cfig_build(&c, rows, n, xaxis, "t", info))
		return -2;
	int k = bk_plot_unexplained(&c.p);
	cfig_free(&c);
	return k;
}

int bk_compare_plot_points(const bk_compare_row *rows, int n, int xaxis, const bk_compare_info *info,
                           int *shown, int *front, int *labels_placed)
{
	cfig c;
	if (!info)
		info = &default_info;
	if (xaxis < 0 || xaxis >= 2 + info->nchips)
		xaxis = 0;
	if (cfig_build(&c, rows, n, xaxis, "t", info))
		return -1;
	*shown = 0;
	for (int t = 1; t < c.p.nseries; t++)
		*shown += c.s[t].n;
	*front = c.s[0].n;
	bk_plot_label lab[256];
	int nl = bk_plot_labels(&c.p, lab, 256);
	*labels_placed = 0;
	for (int k = 0; k < nl && k < 256; k++)
		*labels_placed += lab[k].placed;
	cfig_free(&c);
	return nl < 0 ? -1 : 0;
}
