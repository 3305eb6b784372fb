/*
 * tabtarget.c — CSV, EXR and MERL files read as fit target samples
 * (tabtarget.h). Each reader fills a bk_samples whole or leaves nothing.
 */
#include "tabtarget.h"
#include "csvtab.h"
#include "exr.h"
#include "lut.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

const char *const bk_merl_channel_names[BK_MERL_CHANNELS] = {"r", "g", "b", "luminance"};
const double bk_merl_scale[3] = {1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0};

/* All arrays, every input NaN until a reader sets it (fit/ reads s->in[k]
 * for every k and takes NaN as "not provided"). */
static int samples_alloc(bk_samples *s, size_t n, const char *path, char *err, size_t errlen)
{
	memset(s, 0, sizeof *s);
	size_t m = n ? n : 1;
	int ok = 1;
	for (int k = 0; k < BK_IN_COUNT && ok; k++)
		ok = (s->in[k] = malloc(m * sizeof(double))) != NULL;
	ok = ok && (s->y = calloc(m, sizeof *s->y)) && (s->w = calloc(m, sizeof *s->w)) &&
	     (s->measure = calloc(m, sizeof *s->measure)) && (s->cell = calloc(m, sizeof *s->cell));
	if (!ok) {
		bk_samples_free(s);
		snprintf(err, errlen, "%s: out of memory for %zu samples", path, n);
		return -1;
	}
	for (int k = 0; k < BK_IN_COUNT; k++)
		for (size_t i = 0; i < n; i++)
			s->in[k][i] = NAN;
	s->ncomp = 1;
	return 0;
}

/* No plane: the samples are scattered (CSV) or 3-D (MERL); one cell. */
static void no_plane(bk_samples *s)
{
	s->plane_nx = s->plane_ny = 1;
	s->plane_x0 = s->plane_y0 = 0;
	s->plane_x1 = s->plane_y1 = 1;
	s->plane_xname = s->plane_yname = "-";
	s->plane_x_input = s->plane_y_input = -1;
}

static int ends_with(const char *s, const char *tail)
{
	size_t n = strlen(s), m = strlen(tail);
	return n >= m && strcasecmp(s + n - m, tail) == 0;
}

/* ---- CSV ------------------------------------------------------------------ */

enum { COL_VALUE = BK_IN_COUNT, COL_WEIGHT, NCOLS };

static int csv_cell(const bk_csvtab *t, const char *const *cols, int i, int k, double *x, char *err, size_t errlen)
{
	const char *text = bk_csvtab_get(t, i, k);
	if (bk_csvtab_number(text, x))
		return bk_csvtab_err(err, errlen, t->path, t->line[i], "column '%s' (field %d): '%.40s' is not a finite number",
		                     cols[k], t->col[k] + 1, text);
	double lo = 0, hi = 1; /* cosines over the upper hemisphere, r, a and f0 */
	if (k == COL_VALUE)
		return 0;
	if (k == COL_WEIGHT)
		hi = HUGE_VAL;
	if (!(*x >= lo && *x <= hi))
		return bk_csvtab_err(err, errlen, t->path, t->line[i], "column '%s' (field %d): %s is outside [0, %s",
		                     cols[k], t->col[k] + 1, text, k == COL_WEIGHT ? "inf)" : "1]");
	return 0;
}

static int read_csv(const char *path, bk_samples *s, char *err, size_t errlen)
{
	const char *cols[NCOLS + 1];
	for (int k = 0; k < BK_IN_COUNT; k++)
		cols[k] = bk_input_name((bk_input)k);
	cols[COL_VALUE] = "value";
	cols[COL_WEIGHT] = "weight";
	cols[NCOLS] = NULL;
	bk_csvtab_spec spec = {cols, ((1u << BK_IN_COUNT) - 1) | 1u << COL_WEIGHT,
	                       "a table target has a column 'value'", 1 << 22, 1L << 30, NULL, NULL};
	bk_csvtab t;
	int rc = bk_csvtab_read(path, &spec, &t, err, errlen);
	if (rc)
		return rc;
	unsigned given = 0;
	for (int k = 0; k < BK_IN_COUNT; k++)
		given |= (t.col[k] >= 0 ? 1u : 0u) << k;
	rc = -1;
	if (!given)
		bk_csvtab_err(err, errlen, path, t.header_line, "no input column (NoV, NoL, NoH, LoH, r, a or f0)");
	else if ((given >> BK_IN_R & 1) && (given >> BK_IN_A & 1))
		bk_csvtab_err(err, errlen, path, t.header_line, "columns 'r' and 'a' both given: a = r^2, give one");
	else if (t.n == 0)
		bk_csvtab_err(err, errlen, path, t.header_line, "no data rows");
	else if (samples_alloc(s, (size_t)t.n, path, err, errlen) == 0)
		rc = 0;
	double wsum = 0;
	for (int i = 0; rc == 0 && i < t.n; i++) {
		for (int k = 0; rc == 0 && k < NCOLS; k++) {
			double x = 1.0;
			if (k < BK_IN_COUNT ? !(given >> k & 1) : t.col[k] < 0)
				continue;
			if ((rc = csv_cell(&t, cols, i, k, &x, err, errlen)))
				break;
			if (k < BK_IN_COUNT)
				s->in[k][i] = x;
			else if (k == COL_VALUE)
				s->y[i] = x;
			else
				s->w[i] = x;
		}
		if (t.col[COL_WEIGHT] < 0)
			s->w[i] = 1.0;
		if (given >> BK_IN_R & 1)
			s->in[BK_IN_A][i] = s->in[BK_IN_R][i] * s->in[BK_IN_R][i];
		if (given >> BK_IN_A & 1)
			s->in[BK_IN_R][i] = sqrt(s->in[BK_IN_A][i]);
		wsum += s->w[i];
	}
	if (rc == 0 && !(wsum > 0 && isfinite(wsum))) {
		bk_csvtab_err(err, errlen, path, 0, "the weights sum to %g: nothing to fit", wsum);
		rc = -1;
	}
	if (rc) {
		if (s->y)
			bk_samples_free(s);
		bk_csvtab_free(&t);
		return -1;
	}
	for (int i = 0; i < t.n; i++)
		s->w[i] /= wsum;
	s->n = (size_t)t.n;
	s->provides = given | ((given & (1u << BK_IN_R | 1u << BK_IN_A)) ? 1u << BK_IN_R | 1u << BK_IN_A : 0u);
	no_plane(s);
	size_t w = (size_t)snprintf(s->description, sizeof s->description, "table: %.200s, %d samples of column 'value' at ",
	                            path, t.n);
	for (int k = 0, first = 1; k < BK_IN_COUNT && w < sizeof s->description; k++)
		if (given >> k & 1) {
			w += (size_t)snprintf(s->description + w, sizeof s->description - w, "%s%s", first ? "" : ", ",
			                      cols[k]);
			first = 0;
		}
	if (w < sizeof s->description)
		snprintf(s->description + w, sizeof s->description - w, "%s; weight %s, scaled to sum to 1",
		         (given >> BK_IN_R & 1) ? " (a = r^2)" : (given >> BK_IN_A & 1) ? " (r = sqrt(a))" : "",
		         t.col[COL_WEIGHT] >= 0 ? "column 'weight'" : "uniform");
	bk_csvtab_free(&t);
	return 0;
}

/* ---- EXR: a 2-D table as brdfkit lut writes it ----------------------------- */

/* The x and y axes from brdfkit:axes: the layout whose text (lut.c's one
 * wording, bk_lut_axes_text) the attribute is, the plain one or the warped or
 * cut one its numbers say. */
static int exr_layout(const char *path, int w, int h, bk_lut_layout *L, char *err, size_t errlen)
{
	char axes[512], want[512];
	if (bk_exr_read_attr(path, "brdfkit:axes", axes, sizeof axes)) {
		snprintf(err, errlen, "%s: no string attribute brdfkit:axes (a table target is laid out as brdfkit lut "
		         "writes it)", path);
		return -1;
	}
	*L = (bk_lut_layout){w, h, 0, 1, BK_LUT_WARP_NONE, NAN};
	bk_lut_axes_text(L, want, sizeof want);
	if (!strcmp(axes, want))
		return 0;
	const char *y = strstr(axes, "; y: ");
	char warp[64];
	double lo, span;
	if (y && sscanf(axes, "x: u = %63[^ ]", warp) == 1 && sscanf(y, "; y: v = (r - %lf)/%lf", &lo, &span) == 2)
		for (int k = 0; k < BK_LUT_WARPS; k++) {
			/* 9 digits each (lut.c): lo + span may pass 1 by a rounding */
			double hi = lo + span > 1 && lo + span < 1 + 1e-9 ? 1 : lo + span;
			/* f0 0: any folded f0 words the plain layout this way too (lut.c classic()) */
			*L = (bk_lut_layout){w, h, lo, hi, (bk_lut_warp)k, 0};
			bk_lut_axes_text(L, want, sizeof want);
			if (!strcmp(warp, bk_lut_warp_form((bk_lut_warp)k)) && !strcmp(axes, want) && !bk_lut_layout_check(L))
				return 0;
		}
	snprintf(err, errlen, "%s: attribute brdfkit:axes '%.200s' is not a layout brdfkit lut writes", path, axes);
	return -1;
}

static int read_exr(const char *path, const char *channel, bk_samples *s, char *err, size_t errlen)
{
	bk_lut_layout L;
	char origin[512];
	FILE *f = fopen(path, "rb"); /* an absent file is said as such, not as an absent attribute */
	if (!f) {
		snprintf(err, errlen, "%s: cannot open: %s", path, strerror(errno));
		return -2;
	}
	fclose(f);
	bk_exr_image img; /* first: a damaged header is said as such, not as an absent attribute */
	if (bk_exr_read(path, &img, err, errlen))
		return -1;
	if (exr_layout(path, img.width, img.height, &L, err, errlen)) {
		bk_exr_image_free(&img);
		return -1;
	}
	if (bk_exr_read_attr(path, "brdfkit:origin", origin, sizeof origin) ||
	    (strncmp(origin, "top:", 4) && strncmp(origin, "bottom:", 7))) {
		snprintf(err, errlen, "%s: attribute brdfkit:origin is absent or neither 'top: ...' nor 'bottom: ...'", path);
		bk_exr_image_free(&img);
		return -1;
	}
	int top = !strncmp(origin, "top:", 4);
	int c = -1;
	if (channel && (c = bk_exr_channel_index(&img, channel)) < 0)
		snprintf(err, errlen, "%s: no channel '%s' (the file has %d: %s%s%s%s%s)", path, channel, img.nchan,
		         img.names[0], img.nchan > 1 ? ", " : "", img.nchan > 1 ? img.names[1] : "",
		         img.nchan > 2 ? ", " : "", img.nchan > 2 ? img.names[2] : "");
	else if (!channel && img.nchan != 1)
		snprintf(err, errlen, "%s: %d channels (%s, %s%s): choose one with --channel", path, img.nchan,
		         img.names[0], img.names[1], img.nchan > 2 ? ", ..." : "");
	else if (!channel)
		c = 0;
	size_t n = (size_t)img.width * (size_t)img.height;
	if (c < 0 || samples_alloc(s, n, path, err, errlen)) {
		bk_exr_image_free(&img);
		return -1;
	}
	for (int y = 0; y < img.height; y++) {
		int j = top ? y : img.height - 1 - y;
		double r = bk_lut_texel_r(&L, j);
		for (int i = 0; i < img.width; i++) {
			size_t q = (size_t)j * (size_t)img.width + (size_t)i;
			float v = img.data[c][(size_t)y * (size_t)img.width + (size_t)i];
			if (!isfinite(v)) {
				snprintf(err, errlen, "%s: channel %s, texel (%d, %d): value %g is not finite", path, img.names[c],
				         i, y, (double)v);
				bk_samples_free(s);
				bk_exr_image_free(&img);
				return -1;
			}
			s->in[BK_IN_NOV][q] = bk_lut_texel_nov(&L, i);
			s->in[BK_IN_R][q] = r;
			s->in[BK_IN_A][q] = r * r;
			s->y[q] = v;
			s->w[q] = 1.0 / (double)n;
			s->cell[q] = (int)q;
		}
	}
	s->n = n;
	s->provides = 1u << BK_IN_NOV | 1u << BK_IN_R | 1u << BK_IN_A;
	s->plane_nx = img.width, s->plane_ny = img.height;
	s->plane_x0 = 0, s->plane_x1 = 1, s->plane_y0 = L.r_lo, s->plane_y1 = L.r_hi;
	/* the cells are uniform in u: a warped table's heatmap says so (its edges,
	 * u = 0 and 1, are NoV = 0 and 1 all the same) */
	s->plane_xname = L.warp == BK_LUT_WARP_SQRT ? "u = sqrt(NoV)" : "NoV", s->plane_yname = "r";
	s->plane_x_input = BK_IN_NOV, s->plane_y_input = BK_IN_R;
	snprintf(s->description, sizeof s->description,
	         "table: %.200s, channel %s (%s), %dx%d texels: x = NoV%s, y = perceptual roughness r in [%g, %g] at "
	         "texel centres (a = r^2), origin %s; uniform weight",
	         path, img.names[c], img.half[c] ? "half" : "float", img.width, img.height,
	         L.warp == BK_LUT_WARP_SQRT ? " at u = sqrt(NoV)" : "", L.r_lo, L.r_hi, top ? "top" : "bottom");
	bk_exr_image_free(&img);
	return 0;
}

int bk_tabtarget_table(const char *path, const char *channel, bk_samples *s, char *err, size_t errlen)
{
	memset(s, 0, sizeof *s);
	if (ends_with(path, ".csv"))
		return channel ? (snprintf(err, errlen, "%s: --channel chooses a channel of an EXR or MERL file; a CSV "
		                           "has the column 'value'", path), -1)
		               : read_csv(path, s, err, errlen);
	if (ends_with(path, ".exr"))
		return read_exr(path, channel, s, err, errlen);
	snprintf(err, errlen, "%s: a table target is a .csv or an .exr file", path);
	return -1;
}

/* ---- MERL ------------------------------------------------------------------- */

void bk_merl_angles(int i, int j, int k, double *th, double *td, double *pd)
{
	double u = (i + 0.5) / BK_MERL_NTH;
	*th = u * u * (BK_PI / 2);
	*td = (j + 0.5) / BK_MERL_NTD * (BK_PI / 2);
	*pd = (k + 0.5) / BK_MERL_NPD * BK_PI;
}

void bk_merl_cosines(double th, double td, double pd, double *NoV, double *NoL, double *NoH, double *LoH)
{
	double ch = cos(th), sh = sin(th), cd = cos(td), sd = sin(td), cp = cos(pd);
	*NoH = ch;
	*LoH = cd;
	*NoL = ch * cd - sh * sd * cp;
	*NoV = ch * cd + sh * sd * cp;
}

/* Rec. 709 / sRGB luminance of linear RGB. */
static const double luma[3] = {0.2126, 0.7152, 0.0722};

int bk_tabtarget_merl(const char *path, bk_merl_channel ch, bk_samples *s, char *err, size_t errlen)
{
	memset(s, 0, sizeof *s);
	FILE *f = fopen(path, "rb");
	if (!f) {
		snprintf(err, errlen, "%s: cannot open: %s", path, strerror(errno));
		return -2;
	}
	int32_t dims[3]; /* MERL's files are little-endian, as this machine (x86-64, arm64) */
	const size_t N = BK_MERL_N, plane_bytes = N * sizeof(double), want = 12 + 3 * plane_bytes;
	size_t got = fread(dims, 1, sizeof dims, f);
	double *v = NULL;
	int rc = -1;
	if (got < sizeof dims)
		snprintf(err, errlen, "%s: truncated at byte %zu: a MERL file starts with 3 int32 dimensions (12 bytes)",
		         path, got);
	else if (dims[0] != BK_MERL_NTH || dims[1] != BK_MERL_NTD || dims[2] != BK_MERL_NPD)
		snprintf(err, errlen, "%s: byte 0: dimensions %d x %d x %d, not MERL's %d x %d x %d", path, (int)dims[0],
		         (int)dims[1], (int)dims[2], BK_MERL_NTH, BK_MERL_NTD, BK_MERL_NPD);
	else if (!(v = malloc(3 * plane_bytes)))
		snprintf(err, errlen, "%s: out of memory for 3 x %zu values", path, N);
	else if ((got = fread(v, 1, 3 * plane_bytes, f)) < 3 * plane_bytes)
		snprintf(err, errlen, "%s: truncated at byte %zu: expected %zu bytes (12 + 3 planes of %zu doubles), the %s "
		         "plane is short", path, 12 + got, want, N, got < plane_bytes ? "red" : got < 2 * plane_bytes ?
		         "green" : "blue");
	else if (fgetc(f) != EOF)
		snprintf(err, errlen, "%s: byte %zu: data after the 3 planes (a MERL file is %zu bytes)", path, want, want);
	else
		rc = 0;
	fclose(f);
	if (rc) {
		free(v);
		return -1;
	}
	/* counts first: the samples are allocated once, at their size */
	size_t n = 0, unmeasured = 0;
	for (size_t q = 0; q < N; q++) {
		for (int c = 0; c < 3; c++)
			if (!isfinite(v[c * N + q])) {
				size_t i = q / (BK_MERL_NTD * BK_MERL_NPD), j = q / BK_MERL_NPD % BK_MERL_NTD, k = q % BK_MERL_NPD;
				snprintf(err, errlen, "%s: byte %zu (%s plane, θh %zu, θd %zu, φd %zu): value is not finite", path,
				         12 + (c * N + q) * sizeof(double), c == 0 ? "red" : c == 1 ? "green" : "blue", i, j, k);
				free(v);
				return -1;
			}
	}
	double th, td, pd, NoV, NoL, NoH, LoH;
	for (int pass = 0; pass < 2; pass++) {
		size_t m = 0;
		double wsum = 0;
		for (int i = 0; i < BK_MERL_NTH; i++)
			for (int j = 0; j < BK_MERL_NTD; j++)
				for (int k = 0; k < BK_MERL_NPD; k++) {
					size_t q = ((size_t)i * BK_MERL_NTD + (size_t)j) * BK_MERL_NPD + (size_t)k;
					double val = 0;
					int measured = 1;
					for (int c = 0; c < 3; c++)
						if (ch == BK_MERL_LUMINANCE || (int)ch == c) {
							measured &= v[c * N + q] >= 0;
							val += (ch == BK_MERL_LUMINANCE ? luma[c] : 1.0) * v[c * N + q] * bk_merl_scale[c];
						}
					bk_merl_angles(i, j, k, &th, &td, &pd);
					bk_merl_cosines(th, td, pd, &NoV, &NoL, &NoH, &LoH);
					if (!measured || NoL <= 0 || NoV <= 0) {
						unmeasured += pass == 0 && !measured;
						continue;
					}
					if (pass == 1) {
						double u = (i + 0.5) / BK_MERL_NTH;
						/* dθh = π u du, du = 1/90; dθd = π/180; dφd = π/180 (over [0, π), standing for 2π
						 * with its reciprocal half); the constant factors cancel in the scaling below */
						double w = 4 * cos(td) * sin(th) * sin(td) * u;
						s->in[BK_IN_NOV][m] = NoV;
						s->in[BK_IN_NOL][m] = NoL;
						s->in[BK_IN_NOH][m] = NoH;
						s->in[BK_IN_LOH][m] = LoH;
						s->y[m] = val;
						s->w[m] = w;
						wsum += w;
					}
					m++;
				}
		if (pass == 0) {
			n = m;
			if (n == 0) {
				snprintf(err, errlen, "%s: no measured sample above the horizon in channel %s", path,
				         bk_merl_channel_names[ch]);
				free(v);
				return -1;
			}
			if (samples_alloc(s, n, path, err, errlen)) {
				free(v);
				return -1;
			}
		} else {
			for (size_t q = 0; q < n; q++)
				s->w[q] /= wsum;
		}
	}
	free(v);
	s->n = n;
	s->provides = 1u << BK_IN_NOV | 1u << BK_IN_NOL | 1u << BK_IN_NOH | 1u << BK_IN_LOH;
	no_plane(s);
	char chan[96];
	if (ch == BK_MERL_LUMINANCE)
		snprintf(chan, sizeof chan, "luminance 0.2126 R + 0.7152 G + 0.0722 B");
	else
		snprintf(chan, sizeof chan, "%s x %.6g", ch == BK_MERL_R ? "red" : ch == BK_MERL_G ? "green" : "blue",
		         bk_merl_scale[ch]);
	snprintf(s->description, sizeof s->description,
	         "merl: %.80s, %s (BRDF, 1/sr), %zu samples (%zu unmeasured, %zu below the horizon: left out) at "
	         "bin centres th = ((i+0.5)/90)^2 pi/2, td = (j+0.5)/90 pi/2, pd = (k+0.5)/180 pi (Rusinkiewicz), as "
	         "NoH = cos th, LoH = cos td, NoL, NoV; weight the bin's solid angle dw_l dw_v = 4 cos td sin th sin td "
	         "dth dtd dpd dph, sum 1",
	         path, chan, n, unmeasured, BK_MERL_N - n - unmeasured);
	return 0;
}
