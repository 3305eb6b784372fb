/*
 * test_exr.c — round trips and failure modes of analysis/exr.c. Float channels must
 * come back bit for bit; HALF channels must equal the inputs rounded to the nearest
 * half (ties to even), computed here by a rounding written from the format, checked
 * against gcc's _Float16 where it exists, and pinned by a few hand-derived values.
 * Header attributes, channel names and ZIP compression must survive; chunking is
 * exercised at heights around the 16-line ZIP chunk. Failures (unwritable directory,
 * a library-rejected header, running out of file size mid-data, bad arguments,
 * unreadable input) must return one line naming the path, print nothing, and leave
 * neither the target nor a temporary file behind.
 */
#include "exr.h"

#include <criterion/criterion.h>
#include <criterion/redirect.h>
#include <openexr.h>

#include <dirent.h>
#include <math.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

enum { W = 37, H = 29 };

static char dir[64];

static void make_dir(void)
{
	snprintf(dir, sizeof dir, "/tmp/bk_test_exr_XXXXXX");
	cr_assert_not_null(mkdtemp(dir), "mkdtemp failed");
	cr_redirect_stderr(); /* lets tests assert that the library printed nothing */
}

static int count_entries(const char *d)
{
	DIR *dp = opendir(d);
	cr_assert_not_null(dp);
	int n = 0;
	for (struct dirent *e; (e = readdir(dp));)
		n += strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0;
	closedir(dp);
	return n;
}

static void remove_dir(void)
{
	DIR *dp = opendir(dir);
	if (!dp)
		return;
	char p[512];
	for (struct dirent *e; (e = readdir(dp));) {
		if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
			continue;
		snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
		unlink(p);
	}
	closedir(dp);
	rmdir(dir);
}

static void in_dir(char *out, size_t len, const char *name)
{
	snprintf(out, len, "%s/%s", dir, name);
}

static uint32_t bits(float f)
{
	uint32_t u;
	memcpy(&u, &f, sizeof u);
	return u;
}

/* Exact comparison that also tells -0.0 from 0.0 and inf from a finite value. */
static void assert_same_floats(const float *got, const float *want, size_t n, const char *what)
{
	for (size_t i = 0; i < n; i++)
		cr_assert_eq(bits(got[i]), bits(want[i]), "%s[%zu]: got %.9g, want %.9g", what, i,
		             (double)got[i], (double)want[i]);
}

static void assert_quiet(void)
{
	fflush(stderr);
	cr_assert_stderr_eq_str("", "the library printed to stderr");
}

static void fill_pattern(float *r, float *g, int w, int h)
{
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			r[y * w + x] = (float)(x + 1000 * y);
			g[y * w + x] = sinf(0.37f * (float)x) * cosf(0.11f * (float)y) * 1e3f + 1e-3f * (float)x;
		}
}

TestSuite(exr, .init = make_dir, .fini = remove_dir);

Test(exr, float_round_trip_is_exact)
{
	static float r[W * H], g[W * H];
	fill_pattern(r, g, W, H);
	const char *names[] = {"R", "G"};
	const float *data[] = {r, g};
	const bk_exr_attr attrs[] = {
		{"formula", BK_EXR_ATTR_STRING, "1/(LoH*LoH*(r+p0))", 0},
		{"samples", BK_EXR_ATTR_INT, NULL, -12345},
	};
	char path[256], err[512];
	in_dir(path, sizeof path, "lut.exr");
	cr_assert_eq(bk_exr_write(path, W, H, 2, names, data, 0, attrs, 2, err, sizeof err), 0,
	             "%s", err);
	cr_assert_eq(count_entries(dir), 1, "temporary file left beside the result");

	bk_exr_image img;
	cr_assert_eq(bk_exr_read(path, &img, err, sizeof err), 0, "%s", err);
	cr_assert_eq(img.width, W);
	cr_assert_eq(img.height, H);
	cr_assert_eq(img.nchan, 2);
	cr_assert_str_eq(img.names[0], "G", "EXR keeps channels sorted by name");
	cr_assert_str_eq(img.names[1], "R");
	cr_assert_eq(img.half[0], 0);
	cr_assert_eq(img.half[1], 0);
	cr_assert_eq(img.compression, EXR_COMPRESSION_ZIP);
	int ir = bk_exr_channel_index(&img, "R"), ig = bk_exr_channel_index(&img, "G");
	cr_assert_eq(ir, 1);
	cr_assert_eq(ig, 0);
	cr_assert_eq(bk_exr_channel_index(&img, "B"), -1);
	assert_same_floats(img.data[ir], r, W * H, "R");
	assert_same_floats(img.data[ig], g, W * H, "G");
	cr_assert_eq(img.data[ir][28 * W + 36], 28036.0f, "row 0 must be the first scanline");
	bk_exr_image_free(&img);
	cr_assert_null(img.data[0]);

	char buf[64];
	cr_assert_eq(bk_exr_read_attr(path, "formula", buf, sizeof buf), 0);
	cr_assert_str_eq(buf, "1/(LoH*LoH*(r+p0))");
	cr_assert_eq(bk_exr_read_attr(path, "samples", buf, sizeof buf), 0);
	cr_assert_str_eq(buf, "-12345");
	cr_assert_eq(bk_exr_read_attr(path, "absent", buf, sizeof buf), -1);
	cr_assert_eq(bk_exr_read_attr(path, "dataWindow", buf, sizeof buf), -1,
	             "box2i is not string or int");
	cr_assert_eq(bk_exr_read_attr(path, "formula", buf, 5), -1,
	             "truncation must not pass as a value");
	assert_quiet();
}

/* Round to the nearest half (ties to even), written from the format rather than taken
 * from the code under test: half has 11 significant bits, so a value in [2^(e-1), 2^e)
 * sits on a grid of 2^(e-11); below 2^-14 the grid stays at 2^-24 (subnormals).
 * Scaling by a power of two and rint (default mode: nearest even) are exact in double.
 * Anything that rounds past 65504, the largest half, is infinity. */
static float to_half(float f)
{
	if (isnan(f) || isinf(f))
		return f;
	int e;
	frexp(fabs((double)f), &e);
	int q = e - 11 < -24 ? -24 : e - 11;
	double r = ldexp(rint(ldexp(fabs((double)f), -q)), q);
	return copysignf(r > 65504.0 ? INFINITY : (float)r, f);
}

#ifdef __FLT16_MAX__
/* gcc's own conversion, a second independent opinion (x86-64, gcc >= 12) */
__extension__ typedef _Float16 f16;
static float gcc_half(float f)
{
	return (float)(f16)f;
}
#endif

/* Pixels: the edge cases first, then a ramp over many binades (both signs). */
static void fill_half_inputs(float *v, int n)
{
	static const float edge[] = {
		65504.0f, 6.1e-5f, 1.0f / 3.0f, -0.0f, 0.0f, 65519.0f, 65520.0f, 1e6f, -65504.0f,
		5.9604645e-8f, 2.9e-8f, 3.0e-8f, 1e-10f, 2049.0f, 2051.0f, 0.1f, -2.5f,
		INFINITY, -INFINITY, 6.103515625e-05f, 6.0975552e-05f,
	};
	int ne = (int)(sizeof edge / sizeof edge[0]);
	for (int i = 0; i < n; i++)
		v[i] = i < ne ? edge[i]
		              : (float)((i % 7) - 3) * ldexpf(1.0f + 0.0123f * (float)i, (i % 41) - 26);
}

/* Anchors derived by hand, so the test does not rest on either rounding alone:
 * 1/3 -> 0x3555 = 1365/4096; 6.1e-5 is below 2^-14, a subnormal: 6.1e-5 / 2^-24 = 1023.4
 * -> 1023 * 2^-24; 65519 rounds down to the largest half, 65520 is the tie that goes up
 * to inf; 2049 and 2051 are ties at spacing 2 and go to the even mantissa. */
static void assert_half_anchors(const float *got)
{
	cr_assert_eq(got[0], 65504.0f);
	cr_assert_eq(got[1], 1023.0f * ldexpf(1.0f, -24));
	cr_assert_eq(got[2], 1365.0f / 4096.0f);
	cr_assert(signbit(got[3]) && got[3] == 0.0f, "-0.0 keeps its sign");
	cr_assert_eq(got[5], 65504.0f);
	cr_assert(isinf(got[6]) && got[6] > 0);
	cr_assert(isinf(got[7]) && got[7] > 0);
	cr_assert_eq(got[9], ldexpf(1.0f, -24), "smallest subnormal");
	cr_assert_eq(got[10], 0.0f, "below half the smallest subnormal");
	cr_assert_eq(got[11], ldexpf(1.0f, -24), "above half the smallest subnormal");
	cr_assert_eq(got[13], 2048.0f);
	cr_assert_eq(got[14], 2052.0f);
}

Test(exr, half_round_trip_rounds_to_nearest_even)
{
	static float v[W * H], u[W * H], want_v[W * H], want_u[W * H];
	fill_half_inputs(v, W * H);
	for (int i = 0; i < W * H; i++)
		u[i] = -v[W * H - 1 - i];
	for (int i = 0; i < W * H; i++) {
		want_v[i] = to_half(v[i]);
		want_u[i] = to_half(u[i]);
	}
#ifdef __FLT16_MAX__
	for (int i = 0; i < W * H; i++)
		cr_assert_eq(bits(want_v[i]), bits(gcc_half(v[i])), "to_half(%.9g) disagrees with _Float16",
		             (double)v[i]);
#endif
	const char *names[] = {"V", "U"};
	const float *data[] = {v, u};
	char path[256], err[512];
	in_dir(path, sizeof path, "half.exr");
	cr_assert_eq(bk_exr_write(path, W, H, 2, names, data, 1, NULL, 0, err, sizeof err), 0,
	             "%s", err);
	bk_exr_image img;
	cr_assert_eq(bk_exr_read(path, &img, err, sizeof err), 0, "%s", err);
	cr_assert_eq(img.nchan, 2);
	cr_assert_eq(img.half[0], 1);
	cr_assert_eq(img.half[1], 1);
	cr_assert_eq(img.compression, EXR_COMPRESSION_ZIP);
	int iv = bk_exr_channel_index(&img, "V"), iu = bk_exr_channel_index(&img, "U");
	cr_assert(iv >= 0 && iu >= 0);
	assert_same_floats(img.data[iv], want_v, W * H, "V");
	assert_same_floats(img.data[iu], want_u, W * H, "U");
	assert_half_anchors(img.data[iv]);
	bk_exr_image_free(&img);
	assert_quiet();
}

/* Heights around the 16-line ZIP chunk: one short chunk, exactly full chunks, and a
 * shorter last chunk, each with a value unique to its row. */
Test(exr, chunking_at_every_boundary)
{
	static const int heights[] = {1, 2, 15, 16, 17, 31, 32, 33, 48, 49};
	static float a[3 * 49];
	for (size_t t = 0; t < sizeof heights / sizeof heights[0]; t++) {
		int h = heights[t];
		for (int i = 0; i < 3 * h; i++)
			a[i] = (float)i * 0.5f - 7.0f;
		const char *names[] = {"Y"};
		const float *data[] = {a};
		char path[256], err[512];
		in_dir(path, sizeof path, "h.exr");
		cr_assert_eq(bk_exr_write(path, 3, h, 1, names, data, 0, NULL, 0, err, sizeof err), 0,
		             "height %d: %s", h, err);
		bk_exr_image img;
		cr_assert_eq(bk_exr_read(path, &img, err, sizeof err), 0, "height %d: %s", h, err);
		cr_assert_eq(img.height, h);
		assert_same_floats(img.data[0], a, (size_t)(3 * h), "Y");
		bk_exr_image_free(&img);
	}
	cr_assert_eq(count_entries(dir), 1, "only h.exr, overwritten each time");
	assert_quiet();
}

Test(exr, four_channels_and_overwrite)
{
	static float c0[5 * 17], c1[5 * 17], c2[5 * 17], c3[5 * 17];
	for (int i = 0; i < 5 * 17; i++) {
		c0[i] = (float)i;
		c1[i] = -(float)i;
		c2[i] = (float)i * 0.25f;
		c3[i] = 1.0f / (float)(i + 1);
	}
	const char *names[] = {"R", "G", "B", "A"};
	const float *data[] = {c0, c1, c2, c3};
	char path[256], err[512];
	in_dir(path, sizeof path, "rgba.exr");
	for (int pass = 0; pass < 2; pass++) /* the second write replaces the first */
		cr_assert_eq(bk_exr_write(path, 5, 17, 4, names, data, 0, NULL, 0, err, sizeof err), 0,
		             "%s", err);
	bk_exr_image img;
	cr_assert_eq(bk_exr_read(path, &img, err, sizeof err), 0, "%s", err);
	cr_assert_eq(img.nchan, 4);
	static const char *sorted[] = {"A", "B", "G", "R"};
	for (int c = 0; c < 4; c++)
		cr_assert_str_eq(img.names[c], sorted[c]);
	for (int c = 0; c < 4; c++)
		assert_same_floats(img.data[bk_exr_channel_index(&img, names[c])], data[c], 5 * 17,
		                   names[c]);
	bk_exr_image_free(&img);
	cr_assert_eq(count_entries(dir), 1);
	assert_quiet();
}

static void assert_one_line_about(const char *err, const char *path)
{
	size_t n = strlen(path);
	cr_assert(strncmp(err, path, n) == 0 && err[n] == ':' && err[n + 1] == ' ',
	          "message must start with \"path: \": %s", err);
	cr_assert_null(strchr(err, '\n'), "message must be one line: %s", err);
	cr_assert(err[n + 2] < 'A' || err[n + 2] > 'Z', "message must be lowercase: %s", err);
}

Test(exr, unwritable_directory_fails_and_leaves_nothing)
{
	static float r[W * H], g[W * H];
	fill_pattern(r, g, W, H);
	const char *names[] = {"R", "G"};
	const float *data[] = {r, g};
	const char *path = "/nonexistent_dir/x.exr";
	char err[512];
	cr_assert_eq(bk_exr_write(path, W, H, 2, names, data, 0, NULL, 0, err, sizeof err), -1);
	assert_one_line_about(err, path);
	cr_assert_not_null(strstr(err, "no such file or directory"), "%s", err);
	cr_assert_neq(access(path, F_OK), 0, "a file was left at the path");
	assert_quiet();
}

/* The library rejects a second channel of the same name after the temporary file
 * exists: the earlier file at path must survive and no temporary may remain. */
Test(exr, library_rejection_keeps_old_file_and_leaves_no_temporary)
{
	static float r[W * H], g[W * H];
	fill_pattern(r, g, W, H);
	const char *names[] = {"R", "G"};
	const float *data[] = {r, g};
	char path[256], err[512];
	in_dir(path, sizeof path, "keep.exr");
	cr_assert_eq(bk_exr_write(path, W, H, 2, names, data, 0, NULL, 0, err, sizeof err), 0,
	             "%s", err);

	const char *dup[] = {"R", "R"};
	cr_assert_eq(bk_exr_write(path, W, H, 2, dup, data, 0, NULL, 0, err, sizeof err), -1);
	assert_one_line_about(err, path);
	cr_assert_not_null(strstr(err, "channel 'R'"), "%s", err);
	const bk_exr_attr clash[] = {{"compression", BK_EXR_ATTR_STRING, "zip", 0}};
	cr_assert_eq(bk_exr_write(path, W, H, 2, names, data, 0, clash, 1, err, sizeof err), -1);
	assert_one_line_about(err, path);
	cr_assert_eq(count_entries(dir), 1, "a temporary file was left behind");

	bk_exr_image img;
	cr_assert_eq(bk_exr_read(path, &img, err, sizeof err), 0, "%s", err);
	assert_same_floats(img.data[bk_exr_channel_index(&img, "R")], r, W * H, "R");
	bk_exr_image_free(&img);
	assert_quiet();
}

/* Criterion runs each test in its own process, so a file-size limit here stays here:
 * the header fits, the incompressible pixels do not, and pwrite fails with EFBIG. */
Test(exr, write_error_mid_data_leaves_nothing)
{
	enum { N = 256 };
	static float noise[N * N];
	uint32_t s = 12345u;
	for (int i = 0; i < N * N; i++) {
		s = s * 1664525u + 1013904223u;
		noise[i] = (float)(s >> 8) / 16777216.0f;
	}
	signal(SIGXFSZ, SIG_IGN);
	struct rlimit lim = {8192, 8192};
	cr_assert_eq(setrlimit(RLIMIT_FSIZE, &lim), 0);
	const char *names[] = {"Y"};
	const float *data[] = {noise};
	char path[256], err[512];
	in_dir(path, sizeof path, "big.exr");
	cr_assert_eq(bk_exr_write(path, N, N, 1, names, data, 0, NULL, 0, err, sizeof err), -1);
	assert_one_line_about(err, path);
	cr_assert_not_null(strstr(err, "file too large"), "%s", err);
	cr_assert_eq(count_entries(dir), 0, "a temporary or partial file was left behind");
	assert_quiet();
}

Test(exr, bad_arguments_fail_without_files)
{
	static float r[4];
	const char *names[] = {"R", "G", "B", "A", "Z"};
	const float *data[] = {r, r, r, r, r};
	char path[256], err[512];
	in_dir(path, sizeof path, "bad.exr");
	cr_assert_eq(bk_exr_write(path, 2, 2, 0, names, data, 0, NULL, 0, err, sizeof err), -1);
	assert_one_line_about(err, path);
	cr_assert_eq(bk_exr_write(path, 2, 2, 5, names, data, 0, NULL, 0, err, sizeof err), -1);
	cr_assert_eq(bk_exr_write(path, 0, 2, 1, names, data, 0, NULL, 0, err, sizeof err), -1);
	cr_assert_eq(bk_exr_write(path, 2, 2, 1, names, data, 0, NULL, 1, err, sizeof err), -1);
	const char *empty[] = {""};
	cr_assert_eq(bk_exr_write(path, 2, 2, 1, empty, data, 0, NULL, 0, err, sizeof err), -1);
	cr_assert_eq(bk_exr_write(path, 2, 2, 1, names, data, 0, NULL, 0, NULL, 0), 0,
	             "err may be NULL when errlen is 0");
	cr_assert_eq(count_entries(dir), 1);
	char tiny[8];
	cr_assert_eq(bk_exr_write(path, 2, 2, 0, names, data, 0, NULL, 0, tiny, sizeof tiny), -1);
	cr_assert_eq(strlen(tiny), sizeof tiny - 1, "message truncated and NUL-terminated");
	assert_quiet();
}

Test(exr, unreadable_input_fails_with_message)
{
	char path[256], err[512];
	bk_exr_image img;
	in_dir(path, sizeof path, "missing.exr");
	cr_assert_eq(bk_exr_read(path, &img, err, sizeof err), -1);
	assert_one_line_about(err, path);
	cr_assert_null(img.data[0]);
	char buf[16];
	cr_assert_eq(bk_exr_read_attr(path, "formula", buf, sizeof buf), -1);

	in_dir(path, sizeof path, "junk.exr");
	FILE *f = fopen(path, "w");
	cr_assert_not_null(f);
	fputs("this is not an openexr file, just text long enough to parse\n", f);
	fclose(f);
	cr_assert_eq(bk_exr_read(path, &img, err, sizeof err), -1);
	assert_one_line_about(err, path);
	cr_assert_null(img.data[0]);
	cr_assert_eq(bk_exr_read_attr(path, "formula", buf, sizeof buf), -1);
	assert_quiet();
}
