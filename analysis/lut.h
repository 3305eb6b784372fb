/*
 * lut.h — the DFG look-up table on disk: OpenEXR (R = A, G = B) with its
 * conventions as header attributes, and the same table as CSV beside it.
 */
#ifndef ANALYSIS_LUT_H
#define ANALYSIS_LUT_H

#include "brdf.h"

#include <stddef.h>

typedef struct bk_lut_desc {
	int size;          /* texels per side */
	int half;          /* store HALF channels instead of FLOAT */
	int origin_top;    /* 1: first scanline holds r = 0.5/size */
	bk_smith smith;
	long samples;      /* 0: deterministic integrator with tol */
	double tol;
	const char *command; /* the command line, recorded for provenance */
} bk_lut_desc;

/* "x.exr" -> "x.csv" into buf; -1 if path does not end in ".exr". */
int bk_lut_csv_path(const char *exr_path, char *buf, size_t len);

/* Writes exr_path and its CSV from A, B as bk_dfg_lut fills them (row j =
 * roughness (j + 0.5)/size). Both files appear, or neither does. Returns 0, or
 * -1 with a one-line message in err. */
int bk_lut_write(const bk_lut_desc *d, const char *exr_path, const double *A,
                 const double *B, char *err, size_t errlen);

#endif
