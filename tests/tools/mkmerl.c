/*
 * mkmerl.c — writes a MERL-format BRDF file (Matusik et al. 2003: int32
 * 90 90 180, then red, green, blue planes of 90*90*180 doubles, each stored
 * as the BRDF divided by its channel's scale 1/1500, 1.15/1500, 1.66/1500)
 * from brdfkit's exact GGX D x height-correlated Smith V x Schlick F, for
 * tests/cli_table.sh to fit back.
 *
 * The geometry is written here from MERL's own reference code
 * (half_diff_coords_to_std_coords: rotate the difference vector by θh about
 * y, reflect it about the half vector), with vectors, not from the reader's
 * closed-form cosines, so that the test checks the reader's parametrisation
 * against an independent one. Bins below the horizon are stored as -1
 * (unmeasured), as MERL's files mark them.
 *
 * usage: mkmerl OUT r f0_red f0_green f0_blue
 */
#include "brdf.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <math.h>

int main(int argc, char **argv)
{
	if (argc != 6) {
		fprintf(stderr, "usage: mkmerl OUT r f0_red f0_green f0_blue\n");
		return 2;
	}
	double r = atof(argv[2]), a = r * r, f0[3] = {atof(argv[3]), atof(argv[4]), atof(argv[5])};
	const double scale[3] = {1.0 / 1500, 1.15 / 1500, 1.66 / 1500};
	const int nth = 90, ntd = 90, npd = 180;
	size_t n = (size_t)nth * ntd * npd;
	double *v = malloc(3 * n * sizeof *v);
	if (!v)
		return 1;
	for (int i = 0; i < nth; i++)
		for (int j = 0; j < ntd; j++)
			for (int k = 0; k < npd; k++) {
				double u = (i + 0.5) / nth, th = u * u * BK_PI / 2, td = (j + 0.5) / ntd * BK_PI / 2,
				       pd = (k + 0.5) / npd * BK_PI;
				double d[3] = {sin(td) * cos(pd), sin(td) * sin(pd), cos(td)};
				/* ω_l = R_y(θh) d; h = R_y(θh) z */
				double l[3] = {d[0] * cos(th) + d[2] * sin(th), d[1], -d[0] * sin(th) + d[2] * cos(th)};
				double h[3] = {sin(th), 0, cos(th)};
				double loh = l[0] * h[0] + l[1] * h[1] + l[2] * h[2];
				double vv[3] = {2 * loh * h[0] - l[0], 2 * loh * h[1] - l[1], 2 * loh * h[2] - l[2]};
				size_t q = ((size_t)i * ntd + j) * npd + k;
				for (int c = 0; c < 3; c++) {
					double brdf = -1;
					if (l[2] > 0 && vv[2] > 0)
						brdf = bk_D_ggx(h[2], a) * bk_V_smith_ggx_correlated(vv[2], l[2], a) *
						       bk_F_schlick(f0[c], 1.0, loh) / scale[c];
					v[c * n + q] = brdf;
				}
			}
	FILE *f = fopen(argv[1], "wb");
	int32_t dims[3] = {nth, ntd, npd};
	if (!f || fwrite(dims, sizeof dims, 1, f) != 1 || fwrite(v, sizeof *v, 3 * n, f) != 3 * n || fclose(f)) {
		fprintf(stderr, "mkmerl: %s: write failed\n", argv[1]);
		return 1;
	}
	free(v);
	return 0;
}
