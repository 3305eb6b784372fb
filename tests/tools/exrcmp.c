/*
 * exrcmp — two EXR images of brdfkit render compared pixel by pixel, for
 * tests/render.sh: every channel value of B must be within
 * rel * |A| + abs of A's (both finite), or both non-finite of the same kind.
 *
 *   exrcmp A.exr B.exr REL ABS
 *
 * prints "exrcmp: N values, K outside, max |B - A| / (rel |A| + abs) X, at
 * (x, y) channel C" and exits 0 when K = 0, 1 when K > 0, 2 on an unreadable
 * file or images of other sizes or channels.
 *
 *   exrcmp --pixel A.exr X Y
 *
 * prints pixel (X, Y) (y down) of A, each channel as "NAME VALUE" (%.9g, a
 * float exactly) on one line, for tests/cli_render_scene.sh; exit 2 when the
 * file is unreadable or the pixel outside it.
 */
#include "exr.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int pixel(const char *path, const char *xs, const char *ys)
{
	bk_exr_image a = {0};
	char err[600], *e1, *e2;
	long x = strtol(xs, &e1, 10), y = strtol(ys, &e2, 10);
	if (*e1 || *e2 || !*xs || !*ys) {
		fprintf(stderr, "exrcmp: --pixel: X and Y are integers, got '%s' '%s'\n", xs, ys);
		return 2;
	}
	if (bk_exr_read(path, &a, err, sizeof err)) {
		fprintf(stderr, "exrcmp: %s\n", err);
		return 2;
	}
	int rc = 0;
	if (x < 0 || y < 0 || x >= a.width || y >= a.height) {
		fprintf(stderr, "exrcmp: %s: pixel (%ld, %ld) outside %dx%d\n", path, x, y, a.width, a.height);
		rc = 2;
	}
	for (int c = 0; !rc && c < a.nchan; c++)
		printf("%s%s %.9g", c ? " " : "", a.names[c], a.data[c][(size_t)y * (size_t)a.width + (size_t)x]);
	if (!rc)
		putchar('\n');
	bk_exr_image_free(&a);
	return rc;
}

int main(int argc, char **argv)
{
	if (argc == 5 && !strcmp(argv[1], "--pixel"))
		return pixel(argv[2], argv[3], argv[4]);
	if (argc != 5) {
		fprintf(stderr, "usage: exrcmp A.exr B.exr REL ABS | exrcmp --pixel A.exr X Y\n");
		return 2;
	}
	bk_exr_image a = {0}, b = {0};
	char err[600];
	double rel = strtod(argv[3], NULL), abs_tol = strtod(argv[4], NULL);
	if (bk_exr_read(argv[1], &a, err, sizeof err) || bk_exr_read(argv[2], &b, err, sizeof err)) {
		fprintf(stderr, "exrcmp: %s\n", err);
		bk_exr_image_free(&a);
		return 2;
	}
	int rc = 0;
	if (a.width != b.width || a.height != b.height || a.nchan != b.nchan) {
		fprintf(stderr, "exrcmp: %dx%dx%d against %dx%dx%d\n", a.width, a.height, a.nchan, b.width, b.height, b.nchan);
		rc = 2;
	}
	size_t n = 0, out = 0, np = (size_t)a.width * (size_t)a.height;
	double worst = 0;
	size_t at = 0;
	int atc = 0;
	for (int c = 0; !rc && c < a.nchan; c++) {
		int cb = bk_exr_channel_index(&b, a.names[c]);
		if (cb < 0) {
			fprintf(stderr, "exrcmp: %s has no channel %s\n", argv[2], a.names[c]);
			rc = 2;
			break;
		}
		for (size_t p = 0; p < np; p++, n++) {
			double x = a.data[c][p], y = b.data[cb][p];
			double q;
			if (!isfinite(x) || !isfinite(y))
				q = (isnan(x) && isnan(y)) || x == y ? 0 : INFINITY;
			else
				q = fabs(y - x) / (rel * fabs(x) + abs_tol);
			if (q > 1)
				out++;
			if (q > worst || (isnan(q) && !isnan(worst))) {
				worst = q;
				at = p;
				atc = c;
			}
		}
	}
	if (!rc) {
		printf("exrcmp: %zu values, %zu outside, max |B - A| / (rel |A| + abs) %.3g, at (%zu, %zu) channel %s\n", n,
		       out, worst, at % (size_t)a.width, at / (size_t)a.width, a.names[atc]);
		rc = out ? 1 : 0;
	}
	bk_exr_image_free(&a);
	bk_exr_image_free(&b);
	return rc;
}
