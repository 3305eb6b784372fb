/*
 * pngio.h — brdfkit's one PNG writer (libpng): 8-bit grey or RGB images with
 * their conventions as tEXt chunks. No tIME chunk and a fixed zlib level, so
 * the bytes depend on the pixels and the texts alone (make results
 * reproduces them byte for byte).
 */
#ifndef ANALYSIS_PNGIO_H
#define ANALYSIS_PNGIO_H

#include <stddef.h>
#include <stdio.h>

typedef struct bk_png_text {
	const char *key;  /* 1 to 79 Latin-1 characters (the PNG rule) */
	const char *text;
} bk_png_text;

/* Writes a w x h image to f: channels 1 (grey: linear data, no colour chunk)
 * or 3 (RGB, srgb = 1 adds the sRGB chunk); dpi > 0 adds the pHYs chunk (a
 * figure's print size); px holds rows top first, w * channels bytes each. 0,
 * or -1 with libpng's message in err (f is then partly written: the caller
 * aborts its bk_out). */
int bk_png_write(FILE *f, int w, int h, int channels, int srgb, double dpi, const unsigned char *px,
                 const bk_png_text *t, int nt, char *err, size_t errlen);

#endif
