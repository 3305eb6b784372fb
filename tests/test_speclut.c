/*
 * test_speclut.c — the low tier's specular LUT (analysis/speclut.h): the
 * bake against GGX D written out here, the R·L to N·H map in and out of the
 * plane of incidence, the bilinear lookup on planted texels, the 8-bit
 * storage bound, the ALU count by hand, and the files read back with libpng
 * and the EXR reader. Each threshold check has a negative control.
 */
#include "exr.h"
#include "speclut.h"

#include <criterion/criterion.h>
#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* GGX D (Walter 2007), written out independently of brdf/. */
static double ggx(double NoH, double a)
{
	double a2 = a * a, d = NoH * NoH * (a2 - 1) + 1;
	return a2 / (3.14159265358979323846 * d * d);
}

Test(speclut, bake_at_texel_centres_is_ggx_over_4s)
{
	bk_speclut L = {BK_SPECLUT_NOH, 2, 8, 4, 0, 1, 4, BK_SPECLUT_F_NONE, BK_LUT_FLOAT};
	double raw[32], worst = 0, worst_edge = 0;
	cr_assert_eq(bk_speclut_bake(&L, raw, NULL), 0);
	for (int j = 0; j < 4; j++)
		for (int i = 0; i < 8; i++) {
			double r = (j + 0.5) / 4, x = sqrt((i + 0.5) / 8); /* u = x^2 at the centre */
			double want = ggx(x, r * r) / 4 / 4;
			worst = fmax(worst, fabs(raw[j * 8 + i] - want) / want);
			/* negative control: texel edges (i/8) instead of centres */
			double edge = ggx(sqrt(i / 8.0), r * r) / 16;
			worst_edge = fmax(worst_edge, fabs(raw[j * 8 + i] - edge) / edge);
		}
	cr_assert_lt(worst, 1e-12, "relative error %g", worst);
	cr_assert_gt(worst_edge, 1e-3, "the edge-placed bake should not match (%g)", worst_edge);
	/* R·L: NoH = sqrt((1 + x)/2), warp 4, rows over 0.2..0.6 */
	bk_speclut R = {BK_SPECLUT_ROL, 4, 8, 4, 0.2, 0.6, 16, BK_SPECLUT_F_NONE, BK_LUT_FLOAT};
	cr_assert_eq(bk_speclut_bake(&R, raw, NULL), 0);
	for (int j = 0; j < 4; j++)
		for (int i = 0; i < 8; i++) {
			double r = 0.2 + (j + 0.5) / 4 * 0.4, x = pow((i + 0.5) / 8, 0.25);
			double want = ggx(sqrt((1 + x) / 2), r * r) / 4 / 16;
			cr_assert_lt(fabs(raw[j * 8 + i] - want), 1e-12 * want, "texel %d,%d: %g vs %g", i, j, raw[j * 8 + i], want);
		}
}

/* V at angle tv on one side of N (+x), L at tl on the other, L turned out of
 * the plane by phi about N. */
static void config(double tv, double tl, double phi, double *NoV, double *NoL, double *NoH, double *VoH, double *RoL)
{
	double V[3] = {sin(tv), 0, cos(tv)}, Lv[3] = {-sin(tl) * cos(phi), sin(tl) * sin(phi), cos(tl)};
	double H[3] = {V[0] + Lv[0], V[1] + Lv[1], V[2] + Lv[2]}, n = sqrt(H[0] * H[0] + H[1] * H[1] + H[2] * H[2]);
	for (int k = 0; k < 3; k++)
		H[k] /= n;
	double R[3] = {-V[0], -V[1], V[2]}; /* reflect(-V, N) with N = +z */
	*NoV = V[2];
	*NoL = Lv[2];
	*NoH = H[2];
	*VoH = V[0] * H[0] + V[1] * H[1] + V[2] * H[2];
	*RoL = R[0] * Lv[0] + R[1] * Lv[1] + R[2] * Lv[2];
}

Test(speclut, rol_maps_to_noh_in_the_plane_of_incidence_only)
{
	double in_plane = 0, out_plane = 0, identity = 0;
	for (int a = 1; a < 8; a++)
		for (int b = 1; b < 8; b++) {
			double NoV, NoL, NoH, VoH, RoL, tv = a * 0.19, tl = b * 0.19;
			config(tv, tl, 0, &NoV, &NoL, &NoH, &VoH, &RoL);
			in_plane = fmax(in_plane, fabs(bk_speclut_noh(BK_SPECLUT_ROL, RoL) - NoH));
			identity = fmax(identity, fabs(bk_speclut_rol(NoV, NoL, VoH) - RoL));
			config(tv, tl, 1.2, &NoV, &NoL, &NoH, &VoH, &RoL); /* negative control: L out of the plane */
			out_plane = fmax(out_plane, fabs(bk_speclut_noh(BK_SPECLUT_ROL, RoL) - NoH));
			identity = fmax(identity, fabs(bk_speclut_rol(NoV, NoL, VoH) - RoL)); /* R·L from cosines: always */
		}
	cr_assert_lt(in_plane, 1e-12, "%g", in_plane);
	cr_assert_lt(identity, 1e-12, "%g", identity);
	cr_assert_gt(out_plane, 0.05, "out of the plane the map should fail (%g)", out_plane);
}

Test(speclut, bilinear_exact_at_centres_linear_between_clamped_at_edges)
{
	bk_speclut L = {BK_SPECLUT_NOH, 1, 4, 2, 0, 1, 1, BK_SPECLUT_F_NONE, BK_LUT_FLOAT};
	const double tex[8] = {0.1, 0.5, 0.3, 0.9, /* row 0 */ 0.2, 0.2, 0.7, 0.0};
	for (int j = 0; j < 2; j++)
		for (int i = 0; i < 4; i++)
			cr_assert_eq(bk_speclut_fetch(&L, tex, (i + 0.5) / 4, (j + 0.5) / 2), tex[j * 4 + i]);
	/* halfway between texels 1 and 2 of row 0, and a quarter of the way */
	cr_assert_float_eq(bk_speclut_fetch(&L, tex, 2.0 / 4, 0.25), 0.4, 1e-15);
	cr_assert_float_eq(bk_speclut_fetch(&L, tex, 1.75 / 4, 0.25), 0.5 + 0.25 * (0.3 - 0.5), 1e-15);
	/* between the rows at texel 2: 0.3 + w (0.7 - 0.3), w = 0.5 at v = 0.5 */
	cr_assert_float_eq(bk_speclut_fetch(&L, tex, 2.5 / 4, 0.5), 0.5, 1e-15);
	/* clamp to edge: below the first centre and above the last */
	cr_assert_eq(bk_speclut_fetch(&L, tex, 0.0, 0.0), 0.1);
	cr_assert_eq(bk_speclut_fetch(&L, tex, 1.0, 1.0), 0.0);
	/* weights on 8 fractional bits: 1/1000 of a texel rounds away */
	cr_assert_eq(bk_speclut_fetch(&L, tex, (1.5 + 1e-3) / 4, 0.25), 0.5);
}

Test(speclut, unorm8_storage_within_half_an_lsb_times_scale)
{
	bk_speclut L = {BK_SPECLUT_ROL, 4, 16, 16, 0, 1, 16, BK_SPECLUT_F_NONE, BK_LUT_UNORM8};
	double raw[256], st[256];
	cr_assert_eq(bk_speclut_bake(&L, raw, st), 0);
	double bound = 0.5 / 255 * L.scale;
	int checked = 0;
	for (int k = 0; k < 256; k++)
		if (raw[k] <= 1) { /* above it 8 bits cut to s: stated, not an error bound */
			cr_assert_leq(fabs(st[k] * L.scale - raw[k] * L.scale), bound * (1 + 1e-12), "texel %d", k);
			checked++;
		} else {
			cr_assert_eq(st[k], 1.0);
		}
	cr_assert_gt(checked, 200);
	/* negative control: one texel one LSB off breaks the bound */
	st[100] += 1.0 / 255;
	double worst = 0;
	for (int k = 0; k < 256; k++)
		if (raw[k] <= 1)
			worst = fmax(worst, fabs(st[k] - raw[k]) * L.scale);
	cr_assert_gt(worst, bound);
}

Test(speclut, alu_ops_by_hand)
{
	bk_ops o;
	bk_speclut L = BK_SPECLUT_TALK; /* dot3 (3) + saturate + x^4 (2 mul) + t*16*NoL*f0 (3 mul) */
	cr_assert_eq(bk_speclut_ops(&L, &o), 0);
	cr_assert_eq(o.simple, 9);
	cr_assert_eq(o.complex, 0);
	L.axis = BK_SPECLUT_NOH; /* x^4 + 3 mul */
	cr_assert_eq(bk_speclut_ops(&L, &o), 0);
	cr_assert_eq(o.simple, 5);
	L.warp = 1;
	cr_assert_eq(bk_speclut_ops(&L, &o), 0);
	cr_assert_eq(o.simple, 3);
	L.r_lo = 0.5; /* + the rows' remap, one mad */
	cr_assert_eq(bk_speclut_ops(&L, &o), 0);
	cr_assert_eq(o.simple, 4);
	cr_assert_eq(o.n[BK_K_MAD], 1);
}

Test(speclut, bad_layouts_refused)
{
	bk_speclut L = BK_SPECLUT_TALK;
	cr_assert_null(bk_speclut_check(&L));
	L.warp = 0;
	cr_assert_not_null(bk_speclut_check(&L));
	L = (bk_speclut)BK_SPECLUT_TALK;
	L.scale = 0;
	cr_assert_not_null(bk_speclut_check(&L));
	L = (bk_speclut)BK_SPECLUT_TALK;
	L.r_lo = 0.7, L.r_hi = 0.3;
	cr_assert_not_null(bk_speclut_check(&L));
}

/* The tEXt chunk key of a PNG, into buf; 0 if found. */
static int png_chunk(const char *path, const char *key, char *buf, size_t len, unsigned char *pix, int *w, int *h)
{
	FILE *f = fopen(path, "rb");
	if (!f)
		return -1;
	png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
	png_infop info = png_create_info_struct(png);
	int rc = -1;
	if (setjmp(png_jmpbuf(png))) {
		png_destroy_read_struct(&png, &info, NULL);
		fclose(f);
		return -1;
	}
	png_init_io(png, f);
	png_read_info(png, info);
	*w = (int)png_get_image_width(png, info);
	*h = (int)png_get_image_height(png, info);
	cr_assert_eq(png_get_color_type(png, info), PNG_COLOR_TYPE_GRAY);
	cr_assert_eq(png_get_bit_depth(png, info), 8);
	for (int y = 0; y < *h; y++)
		png_read_row(png, pix + (size_t)y * (size_t)*w, NULL);
	png_read_end(png, info);
	png_textp t;
	int nt = 0;
	png_get_text(png, info, &t, &nt);
	for (int k = 0; k < nt; k++)
		if (!strcmp(t[k].key, key)) {
			snprintf(buf, len, "%s", t[k].text);
			rc = 0;
		}
	png_destroy_read_struct(&png, &info, NULL);
	fclose(f);
	return rc;
}

Test(speclut, files_read_back_with_their_layout)
{
	char dir[] = "/tmp/bk_speclut_XXXXXX", path[256], err[300], buf[1024];
	cr_assert_not_null(mkdtemp(dir));
	bk_speclut L = {BK_SPECLUT_ROL, 4, 16, 8, 0, 1, 16, BK_SPECLUT_F_NONE, BK_LUT_UNORM8};
	cr_assert_eq(bk_speclut_write(&L, dir, "brdfkit test", err, sizeof err), 0, "%s", err);
	double raw[128];
	bk_speclut_bake(&L, raw, NULL);
	/* PNG: 8-bit grey codes round(saturate(raw)*255), layout in tEXt */
	unsigned char pix[128];
	int w = 0, h = 0;
	snprintf(path, sizeof path, "%s/" BK_SPECLUT_PNG, dir);
	cr_assert_eq(png_chunk(path, "brdfkit:layout", buf, sizeof buf, pix, &w, &h), 0);
	cr_assert(w == 16 && h == 8);
	cr_assert_not_null(strstr(buf, "axis=rol warp=4 width=16 height=8"), "%s", buf);
	cr_assert_not_null(strstr(buf, "scale=16"), "%s", buf);
	cr_assert_eq(png_chunk(path, "brdfkit:axes", buf, sizeof buf, pix, &w, &h), 0);
	cr_assert_eq(png_chunk(path, "brdfkit:command", buf, sizeof buf, pix, &w, &h), 0);
	cr_assert_str_eq(buf, "brdfkit test");
	cr_assert_neq(png_chunk(path, "brdfkit:nonesuch", buf, sizeof buf, pix, &w, &h), 0); /* the reader can fail */
	for (int k = 0; k < 128; k++)
		cr_assert_eq(pix[k], (unsigned char)lround(fmin(raw[k], 1.0) * 255), "texel %d", k);
	/* EXR: the float texels, row 0 = the smallest roughness, layout attributes */
	snprintf(path, sizeof path, "%s/" BK_SPECLUT_EXR, dir);
	bk_exr_image img;
	cr_assert_eq(bk_exr_read(path, &img, err, sizeof err), 0, "%s", err);
	cr_assert(img.width == 16 && img.height == 8 && img.nchan == 1);
	for (int k = 0; k < 128; k++)
		cr_assert_eq(img.data[0][k], (float)raw[k], "texel %d", k);
	cr_assert_gt(img.data[0][7 * 16], 100 * img.data[0][0]); /* row 7 is the rough one: wide, where row 0 is ~0 */
	bk_exr_image_free(&img);
	cr_assert_eq(bk_exr_read_attr(path, "brdfkit:layout", buf, sizeof buf), 0);
	cr_assert_not_null(strstr(buf, "axis=rol warp=4"));
	cr_assert_eq(bk_exr_read_attr(path, "brdfkit:texel", buf, sizeof buf), 0);
	cr_assert_not_null(strstr(buf, "1/4"));
	snprintf(path, sizeof path, "rm -rf '%s'", dir);
	cr_assert_eq(system(path), 0);
}

/* On planted samples in the plane of incidence whose exact value is the
 * LUT's own model (D/4 NoL f0), a float LUT's error is interpolation alone:
 * under 5 % of the largest value at 128x64 (2.5 % measured: bilinear across
 * a lobe's peak); the same samples against a V twice the implicit one are
 * 50 % off. */
Test(speclut, score_on_planted_samples)
{
	enum { NS = 64 };
	static double in[BK_IN_COUNT][NS], y[NS], w[NS], meas[NS];
	static int cell[NS];
	bk_samples s;
	memset(&s, 0, sizeof s);
	bk_speclut L = {BK_SPECLUT_ROL, 2, 128, 64, 0, 1, 16, BK_SPECLUT_F_NONE, BK_LUT_FLOAT};
	for (int k = 0; k < NS; k++) {
		double NoV, NoL, NoH, VoH, RoL, r = 0.4 + 0.5 * (k % 8) / 8;
		config(0.2 + 0.1 * (k / 8), 0.15 + 0.1 * (k % 8), 0, &NoV, &NoL, &NoH, &VoH, &RoL);
		in[BK_IN_NOV][k] = NoV, in[BK_IN_NOL][k] = NoL, in[BK_IN_NOH][k] = NoH, in[BK_IN_LOH][k] = VoH;
		in[BK_IN_R][k] = r, in[BK_IN_A][k] = r * r, in[BK_IN_F0][k] = 0.04;
		y[k] = ggx(NoH, r * r) / 4 * NoL * 0.04;
		w[k] = 1;
		cell[k] = 0;
	}
	for (int c = 0; c < BK_IN_COUNT; c++)
		s.in[c] = in[c];
	s.n = NS, s.y = y, s.w = w, s.measure = meas, s.cell = cell;
	s.provides = (1u << BK_IN_COUNT) - 1;
	s.plane_nx = s.plane_ny = 1;
	bk_fit_metrics m;
	cr_assert_eq(bk_speclut_score(&L, BK_F64, &s, &m, NULL), 0);
	double scale = 0;
	for (int k = 0; k < NS; k++)
		scale = fmax(scale, y[k]);
	cr_assert_lt(m.max_abs, 0.05 * scale, "max %g of %g", m.max_abs, scale);
	for (int k = 0; k < NS; k++)
		y[k] *= 2; /* negative control */
	cr_assert_eq(bk_speclut_score(&L, BK_F64, &s, &m, NULL), 0);
	cr_assert_gt(m.max_abs, 0.3 * scale);
}

/* H3: a scale at which a texel (intensity/scale as float32) or the shader's
 * constant (the scale) is not a finite normal float is refused, by the check
 * the command runs first and by the writer, which then writes nothing; at the
 * bound the check states, the EXR holds finite texels equal to the CSV's
 * float column (to float's rounding). */
static int csv_float_column(const char *path, double *v, int n)
{
	FILE *f = fopen(path, "r");
	char line[512];
	int col = -1, k = 0;
	while (f && fgets(line, sizeof line, f)) {
		if (line[0] == '#')
			continue;
		if (col < 0) { /* the header: the column named float */
			int c = 0;
			for (char *t = strtok(line, ",\n"); t; t = strtok(NULL, ",\n"), c++)
				if (!strcmp(t, "float"))
					col = c;
			if (col < 0)
				break;
			continue;
		}
		char *t = strtok(line, ",\n");
		for (int c = 0; t && c < col; c++)
			t = strtok(NULL, ",\n");
		if (!t || k >= n)
			break;
		v[k++] = strtod(t, NULL);
	}
	if (f)
		fclose(f);
	return k;
}

Test(speclut, scales_past_float_refused_exr_agrees_with_csv)
{
	bk_speclut L = BK_SPECLUT_TALK;
	char why[300], err[600], dir[] = "/tmp/bk_speclut_XXXXXX", path[256];
	L.scale = 1e-38; /* the audit's: 39 texels past FLT_MAX */
	cr_assert_eq(bk_speclut_float_check(&L, why, sizeof why), 1);
	cr_assert_not_null(strstr(why, "39 of 4096 texels are +inf in float32"), "%s", why);
	L.scale = 1e-300;
	cr_assert_eq(bk_speclut_float_check(&L, why, sizeof why), 1);
	cr_assert_not_null(strstr(why, "4096 of 4096 texels are +inf"), "%s", why);
	L.scale = 1e-45; /* the shader constant 1e-45 is subnormal too */
	cr_assert_eq(bk_speclut_float_check(&L, why, sizeof why), 1);
	/* the range it states: its lower bound passes, 2 % below it does not */
	char *at = strstr(why, "scale in [");
	cr_assert_not_null(at, "%s", why);
	double lo = strtod(at + strlen("scale in ["), NULL);
	cr_assert(lo > 1e-38 && lo < 1e-37, "%g", lo);
	L.scale = lo / 1.02;
	cr_assert_eq(bk_speclut_float_check(&L, why, sizeof why), 1);
	L.scale = 16; /* negative control: the talk's */
	cr_assert_eq(bk_speclut_float_check(&L, why, sizeof why), 0);
	/* the writer refuses too, and leaves nothing */
	cr_assert_not_null(mkdtemp(dir));
	L.scale = 1e-38;
	cr_assert_eq(bk_speclut_write(&L, dir, "t", err, sizeof err), -1);
	cr_assert_not_null(strstr(err, "+inf in float32"), "%s", err);
	snprintf(path, sizeof path, "%s/" BK_SPECLUT_EXR, dir);
	cr_assert_neq(access(path, F_OK), 0, "spec.exr written");
	/* at the bound: every texel finite, the EXR's float the CSV's number */
	L.scale = lo;
	cr_assert_eq(bk_speclut_write(&L, dir, "t", err, sizeof err), 0, "%s", err);
	bk_exr_image img;
	cr_assert_eq(bk_exr_read(path, &img, err, sizeof err), 0, "%s", err);
	static double csv[4096];
	snprintf(path, sizeof path, "%s/" BK_SPECLUT_CSV, dir);
	cr_assert_eq(csv_float_column(path, csv, 4096), 4096);
	float big = 0;
	for (int k = 0; k < 4096; k++) {
		cr_assert(isfinite(img.data[0][k]), "texel %d: %g", k, img.data[0][k]);
		cr_assert_leq(fabs(img.data[0][k] - csv[k]), 1e-7 * fabs(csv[k]), "texel %d: %g, csv %g", k, img.data[0][k],
		              csv[k]);
		big = fmaxf(big, img.data[0][k]);
	}
	cr_assert_gt(big, 1e38f); /* near FLT_MAX: the bound is tight */
	bk_exr_image_free(&img);
	snprintf(path, sizeof path, "rm -rf '%s'", dir);
	cr_assert_eq(system(path), 0);
}

/* M5: the sweep's ranking, the rms over cells of the albedo error over the
 * cell's albedo: a LUT of zeros (error = -albedo in every cell) scores
 * exactly 1 however the albedo spreads over the cells, where the absolute
 * rms is ruled by the largest cells; half the albedo in every cell is 0.5;
 * a cell without albedo (0, NaN) is left out. */
Test(speclut, relative_albedo_score_puts_zeros_at_one)
{
	bk_samples s;
	memset(&s, 0, sizeof s);
	s.plane_nx = 4, s.plane_ny = 2;
	double albedo[8] = {0.858, 0.6, 0.2, 0.04, 0.04, 0.03, 0, NAN}, zero[8], half[8], good[8];
	for (int k = 0; k < 8; k++) {
		zero[k] = -albedo[k];
		half[k] = -0.5 * albedo[k];
		good[k] = k < 2 ? -albedo[k] : 0.1 * albedo[k]; /* the big cells missed, the rest within 10 % */
	}
	cr_assert_float_eq(bk_speclut_plane_rel_rms(&s, zero, albedo), 1.0, 1e-15);
	cr_assert_float_eq(bk_speclut_plane_rel_rms(&s, half, albedo), 0.5, 1e-15);
	double rz = bk_speclut_plane_rel_rms(&s, zero, albedo), rg = bk_speclut_plane_rel_rms(&s, good, albedo);
	cr_assert_lt(rg, 0.6 * rz, "relative: good %g, zeros %g", rg, rz);
	/* negative control: on the absolute rms the same two are within 20 % */
	double az = bk_speclut_plane_rms(&s, zero), ag = bk_speclut_plane_rms(&s, good);
	cr_assert_gt(ag, 0.8 * az, "absolute: good %g, zeros %g", ag, az);
	zero[2] = NAN; /* no value in a cell that has albedo: the worst score, not a cell less */
	cr_assert(isinf(bk_speclut_plane_rel_rms(&s, zero, albedo)));
	zero[2] = -albedo[2];
	double none[8] = {0, 0, 0, 0, 0, 0, 0, 0};
	cr_assert(isnan(bk_speclut_plane_rel_rms(&s, zero, none)));
}
