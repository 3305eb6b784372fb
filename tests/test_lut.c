/*
 * test_lut.c — the DFG LUT as files: orientation self-checks on what a reader
 * gets back from the EXR, float and half round trips, the CSV beside it (both
 * in one directory), the conventions in the header, and nothing left behind on
 * failure.
 */
#include "brdf.h"
#include "exr.h"
#include "lut.h"
#include "fixture_tmpdir.h"

#include <criterion/criterion.h>
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define N 16
#define CLASSIC {N, N, 0, 1, BK_LUT_WARP_NONE, NAN} /* the engines' usual layout */

static double A[N * N], B[N * N];
static char dir[64];

static void setup(void)
{
	fx_tmpdir_make(dir, sizeof dir, "lut");
	cr_assert_eq(bk_dfg_lut(N, BK_SMITH_CORRELATED, 0, 1e-7, A, B, NULL, NULL), 0);
}

static void teardown(void) { cr_assert_eq(fx_tmpdir_remove(dir), 0); }

static void write_read(int top, int half, bk_exr_image *img, char *path)
{
	char err[256];
	bk_lut_desc d = {.L = CLASSIC, .half = half, .origin_top = top, .smith = BK_SMITH_CORRELATED, .tol = 1e-7, .command = "test"};
	char sub[200];
	sprintf(sub, "%s/lut_%d_%d", dir, top, half);
	cr_assert_eq(mkdir(sub, 0777), 0);
	cr_assert_eq(bk_lut_write(&d, sub, A, B, err, sizeof err), 0, "%s", err);
	sprintf(path, "%s/" BK_LUT_EXR, sub);
	cr_assert_eq(bk_exr_read(path, img, err, sizeof err), 0, "%s", err);
	cr_assert(img->width == N && img->height == N);
}

/* Pixel (x, y) of channel name, y = 0 being the first scanline. */
static float px(const bk_exr_image *img, const char *name, int x, int y)
{
	int c = bk_exr_channel_index(img, name);
	cr_assert(c >= 0, "channel %s missing", name);
	return img->data[c][(size_t)y * img->width + x];
}

/* What the physics says about each corner, read from the file as an engine
 * would: at r -> 0 and NoV = 1 the split sum is F(1) = f0 alone, A + B -> 1 and
 * B -> 0; at grazing NoV, smooth surfaces reflect almost everything through B
 * ((1 - NoV)^5 ≈ 0.97 at NoV = 1/32); in every row the Fresnel part B is
 * largest on the grazing edge x = 0; rough surfaces lose energy at NoV = 1
 * (A + B ≈ 0.31 at r = 1, the single-scattering loss of GGX). */
static void check_corners(const bk_exr_image *img, int y_smooth, int y_rough)
{
	float a = px(img, "R", N - 1, y_smooth), b = px(img, "G", N - 1, y_smooth);
	cr_assert(fabsf(a + b - 1.0f) < 2e-3f && b < 1e-6f, "smooth, NoV≈1: A %g B %g", a, b);
	float ag = px(img, "R", 0, y_smooth), bg = px(img, "G", 0, y_smooth);
	cr_assert(bg > 0.85f && ag < 0.15f, "smooth, grazing: A %g B %g", ag, bg);
	float ar = px(img, "R", N - 1, y_rough);
	cr_assert(ar < 0.5f, "rough: A(NoV=1) %g", ar);
	for (int y = 0; y < N; y++)
		cr_assert(px(img, "G", 0, y) > px(img, "G", N - 1, y), "row %d: B not largest at grazing", y);
}

Test(lut, origin_top_puts_smooth_row_first, .init = setup, .fini = teardown)
{
	bk_exr_image img;
	char path[256];
	write_read(1, 0, &img, path);
	check_corners(&img, 0, N - 1);
	bk_exr_image_free(&img);
}

Test(lut, origin_bottom_is_the_vertical_flip, .init = setup, .fini = teardown)
{
	bk_exr_image top, bot;
	char p1[256], p2[256];
	write_read(1, 0, &top, p1);
	write_read(0, 0, &bot, p2);
	check_corners(&bot, N - 1, 0);
	for (int y = 0; y < N; y++)
		for (int x = 0; x < N; x++)
			cr_assert(px(&top, "R", x, y) == px(&bot, "R", x, N - 1 - y) &&
			          px(&top, "G", x, y) == px(&bot, "G", x, N - 1 - y));
	bk_exr_image_free(&top);
	bk_exr_image_free(&bot);
}

/* Float32 read back bit-equal to the doubles rounded once; half equal to the
 * doubles rounded to binary16 (gcc's _Float16 rounds to nearest even). */
Test(lut, float_and_half_round_trip, .init = setup, .fini = teardown)
{
	bk_exr_image f, h;
	char p1[256], p2[256];
	write_read(1, 0, &f, p1);
	write_read(1, 1, &h, p2);
	cr_assert(!f.half[0] && h.half[0] && h.half[1]);
	for (int j = 0; j < N; j++)
		for (int i = 0; i < N; i++) {
			double a = A[j * N + i], b = B[j * N + i];
			cr_assert(px(&f, "R", i, j) == (float)a && px(&f, "G", i, j) == (float)b);
			__extension__ _Float16 ha = (_Float16)(float)a, hb = (_Float16)(float)b;
			cr_assert(px(&h, "R", i, j) == (float)ha && px(&h, "G", i, j) == (float)hb,
			          "half (%d,%d): %g vs %g", i, j, px(&h, "R", i, j), (float)ha);
		}
	bk_exr_image_free(&f);
	bk_exr_image_free(&h);
}

/* The conventions travel with the file. */
Test(lut, header_states_conventions, .init = setup, .fini = teardown)
{
	bk_exr_image img;
	char path[256], buf[512];
	write_read(1, 0, &img, path);
	bk_exr_image_free(&img);
	const char *want[][2] = {{"brdfkit:axes", "x: NoV"}, {"brdfkit:origin", "top"},
	                         {"brdfkit:roughness", "perceptual"}, {"brdfkit:channels", "never load as sRGB"},
	                         {"brdfkit:smith", "correlated"}, {"brdfkit:method", "deterministic"},
	                         {"brdfkit:samples", "0"}};
	for (size_t k = 0; k < sizeof want / sizeof want[0]; k++) {
		cr_assert_eq(bk_exr_read_attr(path, want[k][0], buf, sizeof buf), 0, "%s missing", want[k][0]);
		cr_assert_not_null(strstr(buf, want[k][1]), "%s = '%s'", want[k][0], buf);
	}
}

/* The CSV holds the same table at full precision, header after comments. */
Test(lut, csv_beside_exr, .init = setup, .fini = teardown)
{
	bk_exr_image img;
	char path[256], csv[260], line[256];
	write_read(1, 0, &img, path);
	bk_exr_image_free(&img);
	snprintf(csv, sizeof csv, "%s/lut_1_0/" BK_LUT_CSV, dir);
	FILE *f = fopen(csv, "r");
	cr_assert_not_null(f);
	while (fgets(line, sizeof line, f) && line[0] == '#')
		;
	cr_assert_str_eq(line, "nov,roughness,A,B\n");
	int rows = 0;
	double nov, r, a, b;
	while (fscanf(f, "%lf,%lf,%lf,%lf", &nov, &r, &a, &b) == 4) {
		int i = rows % N, j = rows / N;
		cr_assert(fabs(nov - (i + 0.5) / N) < 1e-9 && fabs(r - (j + 0.5) / N) < 1e-9);
		cr_assert(fabs(a - A[j * N + i]) < 1e-8 && fabs(b - B[j * N + i]) < 1e-8);
		rows++;
	}
	fclose(f);
	cr_assert_eq(rows, N * N);
}

static int entries(const char *d)
{
	DIR *dp = opendir(d);
	int n = 0;
	for (struct dirent *e; (e = readdir(dp));)
		n += e->d_name[0] != '.';
	closedir(dp);
	return n;
}

/* A failure leaves neither file nor temporary behind. */
Test(lut, failed_write_leaves_nothing, .init = setup, .fini = teardown)
{
	char err[256], path[300];
	bk_lut_desc d = {.L = CLASSIC, .origin_top = 1};
	snprintf(path, sizeof path, "%s/missing_dir", dir);
	cr_assert_eq(bk_lut_write(&d, path, A, B, err, sizeof err), -1);
	cr_assert_not_null(strstr(err, "missing_dir"), "%s", err);
	cr_assert_eq(entries(dir), 0);
}

/* H3: a table with a texel that is NaN or infinite as stored (a float past
 * FLT_MAX, or past half's 65504 in a half file) is refused and nothing is
 * written; the same table with finite texels (negative control) is. */
Test(lut, non_finite_texels_refused, .init = setup, .fini = teardown)
{
	char err[256];
	double A2[N * N], B2[N * N];
	memcpy(A2, A, sizeof A2);
	memcpy(B2, B, sizeof B2);
	bk_lut_desc d = {.L = CLASSIC, .origin_top = 1, .command = "test"};
	A2[5] = INFINITY;
	cr_assert_eq(bk_lut_write(&d, dir, A2, B2, err, sizeof err), -1);
	cr_assert_not_null(strstr(err, "1 texels are NaN or infinite in float32"), "%s", err);
	A2[5] = 1e39; /* finite in double, +inf once a float */
	B2[7] = NAN;
	cr_assert_eq(bk_lut_write(&d, dir, A2, B2, err, sizeof err), -1);
	cr_assert_not_null(strstr(err, "2 texels"), "%s", err);
	A2[5] = 7e4; /* a float, but +inf in half */
	B2[7] = B[7];
	d.half = 1;
	cr_assert_eq(bk_lut_write(&d, dir, A2, B2, err, sizeof err), -1);
	cr_assert_not_null(strstr(err, "in half"), "%s", err);
	cr_assert_eq(entries(dir), 0);
	d.half = 0; /* negative control: the same table is a float file */
	cr_assert_eq(bk_lut_write(&d, dir, A2, B2, err, sizeof err), 0, "%s", err);
	cr_assert_eq(entries(dir), 2);
	char path[300];
	snprintf(path, sizeof path, "%s/" BK_LUT_EXR, dir);
	unlink(path);
	snprintf(path, sizeof path, "%s/" BK_LUT_CSV, dir);
	unlink(path);
}

/* The pair written by bk_lut_write is the only content of its directory:
 * dfg.exr and dfg.csv, no temporaries. */
Test(lut, writes_the_pair_into_its_directory, .init = setup, .fini = teardown)
{
	bk_exr_image img;
	char path[256], sub[260];
	write_read(1, 0, &img, path);
	bk_exr_image_free(&img);
	snprintf(sub, sizeof sub, "%s/lut_1_0", dir);
	cr_assert_eq(entries(sub), 2);
	snprintf(sub, sizeof sub, "%s/lut_1_0/" BK_LUT_CSV, dir);
	cr_assert_eq(access(sub, R_OK), 0);
}

/* ---- layouts laid out for a scene ---------------------------------------------- */

/* The texel centres and the coordinates a shader computes are one map:
 * u(texel NoV of i) = (i + 0.5)/nu, v(texel r of j) = (j + 0.5)/nr, for each
 * warp and a remapped roughness range; the sqrt warp's texels are the squares
 * of the centres; the classic layout bakes exactly what bk_dfg_lut bakes. */
Test(lut, layout_coordinates_invert_the_texel_centres, .init = setup, .fini = teardown)
{
	for (int w = 0; w < BK_LUT_WARPS; w++) {
		bk_lut_layout L = {12, 7, 0.3, 0.9, (bk_lut_warp)w, NAN};
		cr_assert_eq(bk_lut_layout_check(&L), 0);
		for (int i = 0; i < L.nu; i++) {
			double c = (i + 0.5) / L.nu, nov = bk_lut_texel_nov(&L, i);
			cr_assert(fabs(bk_lut_u(&L, nov) - c) < 1e-15, "warp %s texel %d", bk_lut_warp_name(L.warp), i);
			cr_assert(fabs(nov - (w == BK_LUT_WARP_SQRT ? c * c : c)) < 1e-16);
		}
		for (int j = 0; j < L.nr; j++) {
			cr_assert(fabs(bk_lut_v(&L, bk_lut_texel_r(&L, j)) - (j + 0.5) / L.nr) < 1e-15);
			cr_assert(fabs(bk_lut_texel_r(&L, j) - (0.3 + 0.6 * (j + 0.5) / 7)) < 1e-15);
		}
		cr_assert(bk_lut_u(&L, -1) == 0 && bk_lut_u(&L, 2) == 1 && bk_lut_v(&L, 0) == 0 && bk_lut_v(&L, 1) == 1);
	}
	cr_assert_str_eq(bk_lut_warp_form(BK_LUT_WARP_SQRT), "sqrt(NoV)");
	bk_lut_layout bad[] = {{0, 4, 0, 1, 0, NAN}, {4, 4, 0.5, 0.5, 0, NAN}, {4, 4, -0.1, 1, 0, NAN},
	                       {4, 4, 0, 1.1, 0, NAN}, {4, 4, 0, 1, BK_LUT_WARPS, NAN}, {4, 4, 0, 1, 0, 1.5}};
	for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++)
		cr_assert_eq(bk_lut_layout_check(&bad[k]), -1, "layout %zu", k);
	double a[N * N], b[N * N];
	bk_lut_layout L = CLASSIC;
	cr_assert_eq(bk_dfg_lut_layout(&L, BK_SMITH_CORRELATED, 0, 1e-7, a, b, NULL, NULL), 0);
	cr_assert(memcmp(a, A, sizeof a) == 0 && memcmp(b, B, sizeof b) == 0, "classic layout differs from bk_dfg_lut");
}

/* A one-channel, remapped, warped LUT: one channel R = f0 A + B, each texel
 * the reference integral at its own centre (bk_dfg there, computed here
 * independently of the bake's loop), and the header and CSV state the layout. */
Test(lut, folded_remapped_warped_file, .init = setup, .fini = teardown)
{
	enum { NU = 6, NR = 5 };
	bk_lut_layout L = {NU, NR, 0.4, 1, BK_LUT_WARP_SQRT, 0.04};
	double a[NU * NR], b[NU * NR];
	cr_assert_eq(bk_dfg_lut_layout(&L, BK_SMITH_CORRELATED, 0, 1e-7, a, b, NULL, NULL), 0);
	char err[256], sub[200], path[260], buf[512];
	bk_lut_desc d = {.L = L, .origin_top = 1, .smith = BK_SMITH_CORRELATED, .tol = 1e-7, .command = "test"};
	snprintf(sub, sizeof sub, "%s/folded", dir);
	cr_assert_eq(mkdir(sub, 0777), 0);
	cr_assert_eq(bk_lut_write(&d, sub, a, b, err, sizeof err), 0, "%s", err);
	snprintf(path, sizeof path, "%s/" BK_LUT_EXR, sub);
	bk_exr_image img;
	cr_assert_eq(bk_exr_read(path, &img, err, sizeof err), 0, "%s", err);
	cr_assert(img.width == NU && img.height == NR && img.nchan == 1, "%dx%d, %d channels", img.width, img.height,
	          img.nchan);
	for (int j = 0; j < NR; j++)
		for (int i = 0; i < NU; i++) {
			double nov = ((i + 0.5) / NU) * ((i + 0.5) / NU), r = 0.4 + 0.6 * (j + 0.5) / NR, ea, eb;
			cr_assert_eq(bk_dfg(nov, r, BK_SMITH_CORRELATED, 1e-9, &ea, &eb, NULL), 0);
			float got = px(&img, "R", i, j);
			cr_assert(fabs(got - (0.04 * ea + eb)) < 1e-6, "texel (%d,%d): %g, want %g", i, j, got, 0.04 * ea + eb);
		}
	bk_exr_image_free(&img);
	cr_assert_eq(bk_exr_read_attr(path, "brdfkit:axes", buf, sizeof buf), 0);
	cr_assert(strstr(buf, "sqrt(NoV)") && strstr(buf, "(r - 0.4)/0.6"), "axes: %s", buf);
	cr_assert_eq(bk_exr_read_attr(path, "brdfkit:channels", buf, sizeof buf), 0);
	cr_assert(strstr(buf, "R = 0.04*A + B"), "channels: %s", buf);
	snprintf(path, sizeof path, "%s/" BK_LUT_CSV, sub);
	FILE *f = fopen(path, "r");
	char line[512];
	cr_assert_not_null(f);
	while (fgets(line, sizeof line, f) && line[0] == '#')
		;
	cr_assert_str_eq(line, "nov,roughness,env\n");
	double nov, r, v;
	cr_assert_eq(fscanf(f, "%lf,%lf,%lf", &nov, &r, &v), 3);
	cr_assert(fabs(nov - 1.0 / 144) < 1e-10 && fabs(r - 0.46) < 1e-10, "first texel at %g, %g", nov, r);
	fclose(f);
}

/* Bytes of a whole file into buf (at most cap); returns the length, -1 if unreadable. */
static long slurp(const char *path, char *buf, long cap)
{
	FILE *f = fopen(path, "rb");
	if (!f)
		return -1;
	long n = (long)fread(buf, 1, (size_t)cap, f);
	fclose(f);
	return n;
}

/* The multiscatter and cloth channels (issue 41, item 2), each texel against
 * the independent function at that texel's centre integrated 100 times
 * tighter: E = A + B (bk_dfg), cloth (bk_sheen_albedo), E_avg (bk_ms_E_avg),
 * to the DFG channels' figure of 1e-6 (float32 storage adds ~6e-8 relative);
 * the layout named in the header; the same bytes on a second run. Control: the
 * cloth texel against the function at the next texel's NoV fails the check. */
Test(lut, multiscatter_and_cloth_channels, .init = setup, .fini = teardown)
{
	enum { NU = 8, NR = 6 };
	bk_lut_layout L = {NU, NR, 0.1, 1, BK_LUT_WARP_NONE, NAN};
	double a[NU * NR], b[NU * NR], cloth[NU * NR], e_avg[NR];
	cr_assert_eq(bk_dfg_lut_layout(&L, BK_SMITH_CORRELATED, 0, 1e-7, a, b, NULL, NULL), 0);
	for (int chan = BK_LUT_FILAMENT; chan <= BK_LUT_FULL; chan++) {
		bk_lut_desc d = {.L = L, .origin_top = 1, .smith = BK_SMITH_CORRELATED, .tol = 1e-7, .command = "test",
		                 .chan = (bk_lut_chan)chan};
		cr_assert_eq(bk_lut_extra(&d, cloth, e_avg, NULL, NULL), 0);
		d.cloth = cloth;
		d.e_avg = e_avg;
		char err[256], sub[200], path[260], buf[600];
		snprintf(sub, sizeof sub, "%s/%s", dir, bk_lut_chan_name(d.chan));
		cr_assert_eq(mkdir(sub, 0777), 0);
		cr_assert_eq(bk_lut_write(&d, sub, a, b, err, sizeof err), 0, "%s", err);
		snprintf(path, sizeof path, "%s/" BK_LUT_EXR, sub);
		bk_exr_image img;
		cr_assert_eq(bk_exr_read(path, &img, err, sizeof err), 0, "%s", err);
		cr_assert_eq(img.nchan, chan == BK_LUT_FILAMENT ? 3 : 4);
		double worst = 0.0;
		for (int j = 0; j < NR; j++) {
			double r = 0.1 + 0.9 * (j + 0.5) / NR, ea;
			cr_assert_eq(bk_ms_E_avg(r, BK_SMITH_CORRELATED, 1e-9, &ea, NULL), 0);
			for (int i = 0; i < NU; i++) {
				double nov = (i + 0.5) / NU, A, B, S;
				cr_assert_eq(bk_dfg(nov, r, BK_SMITH_CORRELATED, 1e-9, &A, &B, NULL), 0);
				cr_assert_eq(bk_sheen_albedo(nov, r, 1e-9, &S, NULL), 0);
				double want[4], got[4];
				if (chan == BK_LUT_FILAMENT) {
					want[0] = B, want[1] = A + B, want[2] = S;
				} else {
					want[0] = A, want[1] = B, want[2] = S, want[3] = ea;
				}
				const char *names[4] = {"R", "G", "B", "A"};
				for (int c = 0; c < img.nchan; c++) {
					got[c] = px(&img, names[c], i, j);
					double e = fabs(got[c] - want[c]);
					worst = fmax(worst, e);
					cr_assert(e < 1e-6 + 1e-7 * fabs(want[c]), "%s texel (%d,%d) %s: %.9g, want %.9g",
					          bk_lut_chan_name(d.chan), i, j, names[c], got[c], want[c]);
				}
				if (i + 1 < NU && S > 1e-3) { /* control */
					double S2;
					bk_sheen_albedo((i + 1.5) / NU, r, 1e-9, &S2, NULL);
					cr_assert(fabs(got[2] - S2) > 1e-6, "control: texel (%d,%d) matches its neighbour", i, j);
				}
			}
		}
		cr_log_info("lut %s: worst texel error %.3g\n", bk_lut_chan_name(d.chan), worst);
		bk_exr_image_free(&img);
		cr_assert_eq(bk_exr_read_attr(path, "brdfkit:layout", buf, sizeof buf), 0);
		cr_assert(strncmp(buf, bk_lut_chan_name(d.chan), strlen(bk_lut_chan_name(d.chan))) == 0, "layout: %s", buf);
		cr_assert_eq(bk_exr_read_attr(path, "brdfkit:channels", buf, sizeof buf), 0);
		cr_assert(strstr(buf, "cloth"), "channels: %s", buf);
		/* the CSV names its columns */
		snprintf(path, sizeof path, "%s/" BK_LUT_CSV, sub);
		FILE *f = fopen(path, "r");
		char line[1024];
		cr_assert_not_null(f);
		while (fgets(line, sizeof line, f) && line[0] == '#')
			;
		fclose(f);
		cr_assert_str_eq(line, "nov,roughness,A,B,E,cloth,E_avg\n");
		/* determinism: a second write of a second computation, the same bytes */
		double cloth2[NU * NR], e_avg2[NR];
		cr_assert_eq(bk_lut_extra(&d, cloth2, e_avg2, NULL, NULL), 0);
		d.cloth = cloth2;
		d.e_avg = e_avg2;
		char sub2[220];
		snprintf(sub2, sizeof sub2, "%s2", sub);
		cr_assert_eq(mkdir(sub2, 0777), 0);
		cr_assert_eq(bk_lut_write(&d, sub2, a, b, err, sizeof err), 0, "%s", err);
		static char x1[1 << 16], x2[1 << 16];
		for (int k = 0; k < 2; k++) {
			const char *name = k ? BK_LUT_CSV : BK_LUT_EXR;
			char p1[300], p2[300];
			snprintf(p1, sizeof p1, "%s/%s", sub, name);
			snprintf(p2, sizeof p2, "%s/%s", sub2, name);
			long n1 = slurp(p1, x1, sizeof x1), n2 = slurp(p2, x2, sizeof x2);
			cr_assert(n1 > 0 && n1 == n2 && memcmp(x1, x2, (size_t)n1) == 0, "%s differs between runs", name);
		}
	}
}

/* A folded f0 has no room for the extra channels, and they need their values:
 * refused, nothing written. */
Test(lut, extra_channels_refused_when_folded_or_missing, .init = setup, .fini = teardown)
{
	char err[256], sub[200];
	double one[N];
	bk_lut_desc d = {.L = CLASSIC, .origin_top = 1, .chan = BK_LUT_FILAMENT, .command = "test"};
	snprintf(sub, sizeof sub, "%s/refused", dir);
	cr_assert_eq(mkdir(sub, 0777), 0);
	cr_assert_eq(bk_lut_write(&d, sub, A, B, err, sizeof err), -1);
	cr_assert(strstr(err, "without its cloth"), "%s", err);
	d.cloth = A;
	d.e_avg = one;
	d.L.f0 = 0.04;
	cr_assert_eq(bk_lut_write(&d, sub, A, B, err, sizeof err), -1);
	cr_assert(strstr(err, "folded"), "%s", err);
	DIR *dp = opendir(sub);
	int n = 0;
	for (struct dirent *e; (e = readdir(dp));)
		n += e->d_name[0] != '.';
	closedir(dp);
	cr_assert_eq(n, 0);
	cr_assert_str_eq(bk_lut_chan_name(BK_LUT_FULL), "full");
}
