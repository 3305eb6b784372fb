/*
 * out.h — atomic output files, CSV/HTML escaping and slugs: shared by the
 * analysis modules that write results and by the command-line tool.
 */
#ifndef ANALYSIS_OUT_H
#define ANALYSIS_OUT_H

#include <stddef.h>
#include <stdio.h>

/* Atomic output: text goes to a temporary file beside path; bk_out_commit
 * renames it into place, bk_out_abort removes it. Nothing is ever left
 * half-written at path. */
typedef struct bk_out {
	FILE *f;
	char path[4096], tmp[4112];
} bk_out;

int bk_out_open(bk_out *o, const char *path, char *err, size_t errlen);
int bk_out_commit(bk_out *o, char *err, size_t errlen);
void bk_out_abort(bk_out *o);

/* Removes dir with the files and directories under it (what a command wrote:
 * results directories are replaced whole). */
void bk_rm_tree(const char *dir);

/* "LUT 64x64 half" -> "lut_64x64_half": a name as a file name. */
void bk_slug(const char *name, char *buf, size_t len);
/* s escaped for HTML text and attribute values. */
void bk_html_text(FILE *f, const char *s);

/* Writes s as one CSV field, quoted when it holds a comma, quote or newline. */
void bk_csv_field(FILE *f, const char *s);

#endif
