/*
 * test_tabtarget.c — files read as target samples (analysis/tabtarget.h):
 * MERL's half/difference angles against direction vectors built as MERL's
 * reference code builds them; its solid-angle weights against a physical
 * identity (the mean of NoL NoV over pairs of directions uniform in solid
 * angle over the hemisphere is 1/2 x 1/2), with the uniform weight as the
 * control the identity must catch; a CSV's derived inputs, its weights and
 * the text of its errors; EXR tables written here with lut's attributes,
 * read back on both origins (a flipped read is the control), and damaged.
 */
#include <criterion/criterion.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "exr.h"
#include "tabtarget.h"

/* ω_l = R_y(θh) d(θd, φd), h = R_y(θh) z, ω_v = 2 (ω_l·h) h - ω_l */
static void vectors(double th, double td, double pd, double *nol, double *nov, double *noh, double *loh)
{
	double d[3] = {sin(td) * cos(pd), sin(td) * sin(pd), cos(td)};
	double l[3] = {d[0] * cos(th) + d[2] * sin(th), d[1], -d[0] * sin(th) + d[2] * cos(th)};
	double h[3] = {sin(th), 0, cos(th)};
	*loh = l[0] * h[0] + l[1] * h[1] + l[2] * h[2];
	*nol = l[2];
	*nov = 2 * *loh * h[2] - l[2];
	*noh = h[2];
}

Test(tabtarget, merl_cosines_are_the_reference_geometry)
{
	for (int i = 0; i < 90; i += 7)
		for (int j = 0; j < 90; j += 11)
			for (int k = 0; k < 180; k += 13) {
				double th, td, pd, a[4], b[4];
				bk_merl_angles(i, j, k, &th, &td, &pd);
				bk_merl_cosines(th, td, pd, &a[0], &a[1], &a[2], &a[3]);
				vectors(th, td, pd, &b[1], &b[0], &b[2], &b[3]);
				for (int q = 0; q < 4; q++)
					cr_assert(fabs(a[q] - b[q]) < 1e-14, "bin (%d %d %d) cosine %d: %.17g vs %.17g", i, j, k, q,
					          a[q], b[q]);
			}
	/* MERL's look-up (floor of sqrt(θh/(π/2))·90, θd·180/π, φd·180/π) maps each centre back to its bin */
	double th, td, pd;
	bk_merl_angles(37, 61, 123, &th, &td, &pd);
	cr_expect_eq((int)(sqrt(th / (BK_PI / 2)) * 90), 37);
	cr_expect_eq((int)(td / (BK_PI / 2) * 90), 61);
	cr_expect_eq((int)(pd / BK_PI * 180), 123);
}

static char *write_merl(double value)
{
	static char path[] = "/tmp/bk_test_merl_XXXXXX";
	int fd = mkstemp(path);
	cr_assert(fd >= 0);
	FILE *f = fdopen(fd, "wb");
	int32_t dims[3] = {90, 90, 180};
	fwrite(dims, sizeof dims, 1, f);
	for (size_t q = 0; q < 3 * BK_MERL_N; q++)
		fwrite(&value, sizeof value, 1, f);
	cr_assert(fclose(f) == 0);
	return path;
}

Test(tabtarget, merl_weights_are_solid_angle)
{
	char *path = write_merl(1500.0), err[600];
	bk_samples s;
	int rc = bk_tabtarget_merl(path, BK_MERL_R, &s, err, sizeof err);
	unlink(path);
	cr_assert_eq(rc, 0, "%s", err);
	double mean = 0, uniform = 0, wsum = 0;
	for (size_t i = 0; i < s.n; i++) {
		double c = s.in[BK_IN_NOL][i] * s.in[BK_IN_NOV][i];
		mean += s.w[i] * c;
		uniform += c / (double)s.n;
		wsum += s.w[i];
		cr_assert(s.y[i] == 1.0); /* 1500 x the red scale 1/1500 */
	}
	cr_log_info("mean NoL NoV: solid-angle weights %.6f, uniform %.6f (1/4 exact)", mean, uniform);
	cr_expect(fabs(wsum - 1) < 1e-12);
	/* E[NoL NoV] over independent uniform directions = (1/2)(1/2); the bins
	 * are 90x90x180 centres, so the midpoint rule's error is ~2e-5 here */
	cr_expect(fabs(mean - 0.25) < 1e-4, "solid-angle weighted mean NoL NoV %.6f, not 1/4", mean);
	cr_expect(fabs(uniform - 0.25) > 1e-4, "control: MERL's warped grid, uniformly weighted, gives %.6f", uniform);
	cr_expect(isnan(s.in[BK_IN_R][0]) && isnan(s.in[BK_IN_F0][0]), "no roughness or f0 in a measured BRDF");
	bk_samples_free(&s);
}

static int read_csv_text(const char *text, bk_samples *s, char *err, size_t errlen)
{
	char dir[] = "/tmp/bk_test_table_XXXXXX", path[64];
	cr_assert(mkdtemp(dir) != NULL);
	snprintf(path, sizeof path, "%s/t.csv", dir);
	FILE *f = fopen(path, "w");
	cr_assert(f && fputs(text, f) >= 0 && fclose(f) == 0);
	int rc = bk_tabtarget_table(path, NULL, s, err, errlen);
	unlink(path);
	rmdir(dir);
	return rc;
}

Test(tabtarget, csv_inputs_and_weights)
{
	bk_samples s;
	char err[600];
	int rc = read_csv_text("# a comment\nvalue,r,weight,NoV\n1,0.5,1,0.25\n2,0.25,3,0.5\n", &s, err, sizeof err);
	cr_assert_eq(rc, 0, "%s", err);
	cr_expect_eq(s.n, 2);
	cr_expect(s.in[BK_IN_A][0] == 0.25 && s.in[BK_IN_A][1] == 0.0625, "a = r^2");
	cr_expect(s.w[0] == 0.25 && s.w[1] == 0.75, "weights scaled to sum to 1");
	cr_expect(s.y[1] == 2 && s.in[BK_IN_NOV][1] == 0.5);
	cr_expect_eq(s.provides, 1u << BK_IN_NOV | 1u << BK_IN_R | 1u << BK_IN_A);
	bk_samples_free(&s);
	rc = read_csv_text("a,value\n0.25,1\n", &s, err, sizeof err);
	cr_assert_eq(rc, 0, "%s", err);
	cr_expect(s.in[BK_IN_R][0] == 0.5, "r = sqrt(a)");
	bk_samples_free(&s);
}

Test(tabtarget, csv_errors_say_where)
{
	bk_samples s;
	char err[600];
	cr_expect_eq(read_csv_text("NoV,value\n0.5,1\n0.5,nan\n", &s, err, sizeof err), -1);
	cr_expect(strstr(err, ".csv:3: column 'value' (field 2): 'nan' is not a finite number") != NULL, "%s", err);
	cr_expect_eq(read_csv_text("NoV,value\n-0.5,1\n", &s, err, sizeof err), -1);
	cr_expect(strstr(err, ".csv:2: column 'NoV' (field 1): -0.5 is outside [0, 1]") != NULL, "%s", err);
	cr_expect_eq(read_csv_text("NoV,value,weight\n0.5,1,-1\n", &s, err, sizeof err), -1);
	cr_expect(strstr(err, ".csv:2: column 'weight' (field 3): -1 is outside [0, inf)") != NULL, "%s", err);
	cr_expect_eq(read_csv_text("NoV,value\n", &s, err, sizeof err), -1);
	cr_expect(strstr(err, "no data rows") != NULL, "%s", err);
}

/* ---- EXR tables: written here with the attributes lut writes -------------- */

static const char classic_axes[] =
	"x: NoV = (i + 0.5)/width at texel centres; y: perceptual roughness r = (j + 0.5)/height";

/* A 6x4 table of v = NoV + 10 r, laid out as lut lays it out (origin top:
 * scanline y holds r row y; bottom: row h - 1 - y), or with attrs given. */
static void write_table(const char *path, const char *axes, const char *origin, int top, float poison)
{
	enum { W = 6, H = 4 };
	float v[W * H];
	for (int y = 0; y < H; y++)
		for (int i = 0; i < W; i++) {
			int j = top ? y : H - 1 - y;
			v[y * W + i] = (float)((i + 0.5) / W + 10 * (j + 0.5) / H);
		}
	v[2 * W + 3] += poison;
	const char *names[1] = {"R"};
	const float *data[1] = {v};
	bk_exr_attr attrs[2] = {{"brdfkit:axes", BK_EXR_ATTR_STRING, axes, 0},
	                        {"brdfkit:origin", BK_EXR_ATTR_STRING, origin, 0}};
	char err[300];
	cr_assert_eq(bk_exr_write(path, W, H, 1, names, data, 0, attrs, axes ? 2 : 0, err, sizeof err), 0, "%s", err);
}

Test(tabtarget, exr_axes_and_origin)
{
	char dir[] = "/tmp/bk_test_exr_XXXXXX", path[64], err[600];
	cr_assert(mkdtemp(dir) != NULL);
	snprintf(path, sizeof path, "%s/t.exr", dir);
	for (int top = 0; top < 2; top++) {
		write_table(path, classic_axes, top ? "top: scanline 0 ..." : "bottom: the last scanline ...", top, 0);
		bk_samples s;
		cr_assert_eq(bk_tabtarget_table(path, NULL, &s, err, sizeof err), 0, "%s", err);
		cr_expect_eq(s.n, 24);
		for (size_t q = 0; q < s.n; q++) /* float storage: 1e-6 */
			cr_expect(fabs(s.y[q] - (s.in[BK_IN_NOV][q] + 10 * s.in[BK_IN_R][q])) < 1e-5, "origin %s, sample %zu",
			          top ? "top" : "bottom", q);
		bk_samples_free(&s);
	}
	/* control: a bottom-origin file read as top puts every row at the wrong r */
	write_table(path, classic_axes, "top: scanline 0 ...", 0, 0);
	bk_samples s;
	cr_assert_eq(bk_tabtarget_table(path, NULL, &s, err, sizeof err), 0, "%s", err);
	cr_expect(fabs(s.y[0] - (s.in[BK_IN_NOV][0] + 10 * s.in[BK_IN_R][0])) > 1, "a flipped table is caught");
	bk_samples_free(&s);

	write_table(path, classic_axes, "top: scanline 0 ...", 1, NAN);
	cr_expect_eq(bk_tabtarget_table(path, NULL, &s, err, sizeof err), -1);
	cr_expect(strstr(err, "t.exr: channel R, texel (3, 2): value nan is not finite") != NULL, "%s", err);
	write_table(path, NULL, NULL, 1, 0);
	cr_expect_eq(bk_tabtarget_table(path, NULL, &s, err, sizeof err), -1);
	cr_expect(strstr(err, "t.exr: no string attribute brdfkit:axes") != NULL, "%s", err);
	write_table(path, classic_axes, "left: ...", 1, 0);
	cr_expect_eq(bk_tabtarget_table(path, NULL, &s, err, sizeof err), -1);
	cr_expect(strstr(err, "t.exr: attribute brdfkit:origin is absent or neither") != NULL, "%s", err);
	write_table(path, "x: u = cbrt(NoV) at texel centres u = (i + 0.5)/width; y: v = (r - 0)/1 at texel centres "
	            "v = (j + 0.5)/height, r perceptual roughness", "top: ...", 1, 0);
	cr_expect_eq(bk_tabtarget_table(path, NULL, &s, err, sizeof err), -1);
	cr_expect(strstr(err, "is not a layout brdfkit lut writes") != NULL, "%s", err);
	unlink(path);
	rmdir(dir);
}

/* bk_target_build's copy: all samples, or every k-th (search's screening),
 * the weights rescaled to sum to 1, and --weight none's uniform weights */
Test(tabtarget, build_copies_and_strides)
{
	bk_samples t, s;
	char err[600];
	cr_assert_eq(read_csv_text("NoV,value,weight\n0,0,1\n0.1,1,1\n0.2,2,1\n0.3,3,2\n0.4,4,1\n0.5,5,1\n0.6,6,3\n"
	                           "0.7,7,1\n0.8,8,1\n0.9,9,4\n", &t, err, sizeof err), 0, "%s", err);
	bk_target_options o;
	bk_target_defaults(BK_TARGET_TABLE, &o);
	o.table = &t;
	cr_expect_eq(bk_target_samples(&o), 10);
	cr_assert_eq(bk_target_build(&o, &s, NULL, NULL, err, sizeof err), 0, "%s", err);
	cr_expect_eq(s.n, 10);
	cr_expect(fabs(s.w[9] - 4.0 / 16) < 1e-15);
	bk_samples_free(&s);
	o.nx = 4; /* stride ceil(10/4) = 3: samples 0, 3, 6, 9 of weights 1, 2, 3, 4 */
	cr_expect_eq(bk_target_samples(&o), 4);
	cr_assert_eq(bk_target_build(&o, &s, NULL, NULL, err, sizeof err), 0, "%s", err);
	cr_expect_eq(s.n, 4);
	for (int i = 0; i < 4; i++) {
		cr_expect(s.y[i] == 3 * i, "sample %d is the file's %d-th", i, 3 * i);
		cr_expect(fabs(s.w[i] - (i + 1) / 10.0) < 1e-15, "weight %d: %g", i, s.w[i]);
	}
	cr_expect(strstr(s.description, "; one sample in 3 (4)") != NULL, "%s", s.description);
	bk_samples_free(&s);
	o.nx = 0;
	o.weight = BK_WEIGHT_NONE;
	cr_assert_eq(bk_target_build(&o, &s, NULL, NULL, err, sizeof err), 0, "%s", err);
	cr_expect(s.w[0] == 0.1 && s.w[9] == 0.1);
	bk_samples_free(&s);
	bk_samples_free(&t);
}
