/*
 * exr.h — float images in and out of OpenEXR files, for heatmaps and look-up tables.
 * brdfkit writes its error maps and fitted LUTs as scanline EXR (ZIP compressed,
 * 1 to 4 planar float channels, HALF or FLOAT on disk) and reads them back in tests
 * and tools. This wraps the OpenEXR C API (OpenEXRCore) so the rest of the project
 * never sees chunks, pipelines or library error callbacks: a write is atomic (a
 * temporary file renamed into place), and every failure comes back as one lowercase
 * line "path: what went wrong" instead of being printed by the library.
 */
#ifndef BK_EXR_H
#define BK_EXR_H

#include <stddef.h>

typedef enum bk_exr_attr_type { BK_EXR_ATTR_STRING, BK_EXR_ATTR_INT } bk_exr_attr_type;

/* An extra header attribute (e.g. the formula and its source for a heatmap). */
typedef struct bk_exr_attr {
	const char *name;
	bk_exr_attr_type type;
	const char *s; /* for STRING */
	int i;         /* for INT */
} bk_exr_attr;

/* Writes a scanline EXR, ZIP compressed, with nchan (1..4) channels named names[c]
 * (e.g. "R","G"), each a width*height float array data[c], row-major, row 0 = the
 * first scanline in the file (y = 0, top of the image as displayed; the data window
 * starts at (0,0)). half != 0 stores HALF channels (the library converts the floats,
 * rounding to nearest even), else FLOAT. attrs (may be NULL when nattrs = 0) become
 * extra header attributes. The file is created with mode 0644.
 * Atomic: writes to a temporary file in the same directory (mkstemp on
 * "<path>.tmpXXXXXX") and renames it over path only on full success; on any failure
 * the temporary file is removed and nothing is left at path (an existing file at path
 * is left untouched).
 * Returns 0, or -1 with a one-line lowercase message "path: what went wrong" in err
 * (errlen bytes, always NUL-terminated; err may be NULL when errlen is 0). */
int bk_exr_write(const char *path, int width, int height, int nchan,
                 const char *const *names, const float *const *data, int half,
                 const bk_exr_attr *attrs, int nattrs, char *err, size_t errlen);

/* How many of data's n values are NaN or infinite as stored: as floats, or
 * as HALF (half != 0: |x| >= 65520 rounds to inf). A LUT writer refuses a
 * table with any (a data file, unlike a heatmap, has no non-finite values
 * to show); bk_exr_write itself writes what it is given. */
size_t bk_exr_nonfinite(const float *data, size_t n, int half);

typedef struct bk_exr_image {
	int width, height, nchan;
	char names[4][32];    /* in file order, which EXR sorts by name ("G" before "R") */
	int half[4];          /* 1 if the channel is stored as HALF */
	float *data[4];       /* malloc'd, width*height each, row 0 = first scanline */
	int compression;      /* exr_compression_t value as read */
} bk_exr_image;

/* Reads part 0 of a scanline EXR with up to 4 channels of FLOAT or HALF (no
 * subsampling) into floats. img is overwritten; on failure it holds no memory.
 * Returns 0 or -1 with a message as for bk_exr_write. */
int bk_exr_read(const char *path, bk_exr_image *img, char *err, size_t errlen);

/* Frees the channel arrays and zeroes img; safe on a zeroed or already freed image. */
void bk_exr_image_free(bk_exr_image *img);

/* Index of the channel called name in img, or -1: channels come back sorted by name,
 * not in the order they were written. */
int bk_exr_channel_index(const bk_exr_image *img, const char *name);

/* Reads a string (or int, formatted as decimal) header attribute of part 0 into buf.
 * Returns 0, or -1 if absent, of another type, unreadable or longer than len - 1. */
int bk_exr_read_attr(const char *path, const char *name, char *buf, size_t len);

#endif
