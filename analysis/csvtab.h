/*
 * csvtab.h — a CSV file read whole as a table whose columns are found by
 * NAME, for every reader of brdfkit's CSVs (front.csv, catalog.csv,
 * compare.csv, a render batch). libcsv parses the fields (RFC 4180: quoted
 * fields hold commas, doubled quotes and line breaks); this module adds the
 * conventions brdfkit's files share and one error format.
 *
 * The contract:
 *   comments    '#' lines before the header (blank lines among them) are
 *               skipped, each handed to spec.comment; after the header a
 *               '#' is data, as every reader took it before this module.
 *   header      the first other record; its names must be distinct (a name
 *               twice is an error), and every spec.cols name not marked
 *               optional must be one of them: "no column 'X' (HINT)".
 *   rows        each data row keeps the line it STARTS on (a quoted first
 *               field that spans lines does not move it; a line ends at LF,
 *               so CRLF counts right; blank lines between records are
 *               skipped, as libcsv does). A row too short to hold a column
 *               asked for is an error "N fields, fewer than the header's";
 *               other short or long rows are read, as before.
 *   spaces      are data: a field is read as written, not trimmed (" 5"
 *               is no number, bk_csvtab_number).
 *   BOM         a UTF-8 byte order mark at the file's start is dropped (a
 *               spreadsheet's export), so its first column keeps its name.
 *   limits      at most spec.max_rows data rows, spec.max_bytes bytes and
 *               BK_CSVTAB_MAX_FIELDS fields a record, so a hostile file
 *               cannot exhaust memory; a NUL byte is not text. A quote
 *               left open to the end of the file is an error "unterminated
 *               quoted field" on the line its row starts on (libcsv's
 *               lenient mode would take the rest of the file as the field).
 *   errors      one line, "PATH:LINE: what" or "PATH: what", written once
 *               by bk_csvtab_err (callers use it for their own row errors).
 */
#ifndef ANALYSIS_CSVTAB_H
#define ANALYSIS_CSVTAB_H

#include <stddef.h>

#define BK_CSVTAB_MAX_COLS 10         /* columns one reader asks for (a table target: 7 inputs, value, weight) */
#define BK_CSVTAB_MAX_FIELDS 256      /* compare.csv has about 50: more is no file brdfkit writes */
#define BK_CSVTAB_MAX_ROWS 4096       /* default: more is no front or catalog brdfkit writes */
#define BK_CSVTAB_MAX_BYTES (16L << 20) /* default: a 4096-row front is about 2 MB */

typedef struct bk_csvtab_spec {
	const char *const *cols; /* the names asked for, NULL-terminated, at most BK_CSVTAB_MAX_COLS */
	unsigned optional;       /* bit k: cols[k] may be absent from the header */
	const char *hint;        /* "no column 'X' (HINT)"; NULL: no parenthesis */
	int max_rows;            /* 0: BK_CSVTAB_MAX_ROWS */
	long max_bytes;          /* 0: BK_CSVTAB_MAX_BYTES */
	/* each '#' line before the header, without its line break (the first
	 * 1023 bytes); NULL: not wanted */
	void (*comment)(void *ctx, int line, const char *text);
	void *ctx;
} bk_csvtab_spec;

typedef struct bk_csvtab {
	const char *path;        /* as given: the errors name it */
	int ncols;               /* spec.cols asked for */
	int col[BK_CSVTAB_MAX_COLS]; /* cols[k]'s field in the header; -1: absent (optional) */
	int header_line;
	int n;                   /* data rows */
	int *line;               /* line[i]: the line row i starts on, from 1 */
	char **cell;             /* cell[i * ncols + k]: row i's cols[k]; NULL for an absent column */
} bk_csvtab;

/* Reads path whole. 0; or, with err "PATH:LINE: what" / "PATH: what" and t
 * empty (nothing to free), -1 for a bad file, -2 for one that cannot be
 * opened or read (a runtime failure, not bad input: exit 1, not 2). */
int bk_csvtab_read(const char *path, const bk_csvtab_spec *spec, bk_csvtab *t, char *err, size_t errlen);

/* Row i's cols[k]: "" for an absent column. */
const char *bk_csvtab_get(const bk_csvtab *t, int i, int k);

void bk_csvtab_free(bk_csvtab *t);

/* The one number syntax of brdfkit, for a field of a user's file as for an
 * option (cli_number forwards here): [+-] digits ['.' [digits]] |
 * [+-] '.' digits, then an optional exponent [eE][+-]digits; nothing before
 * or after (no space). Not hex, inf or nan (which strtod alone would take).
 * Subnormal values are accepted; a value that overflows double, or a nonzero
 * text that underflows to 0, is not. Returns 0 with *x set, or -1. */
int bk_csvtab_number(const char *text, double *x);

/* err = "PATH:LINE: what" (line > 0) or "PATH: what"; returns -1. */
int bk_csvtab_err(char *err, size_t errlen, const char *path, int line, const char *fmt, ...)
	__attribute__((format(printf, 5, 6)));

#endif
