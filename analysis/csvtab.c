/*
 * csvtab.c — a CSV file read whole by column name (csvtab.h).
 *
 * Spaces are data: libcsv's default trims spaces and tabs around unquoted
 * fields, so " 5" would read as the number 5 and a name " x" as "x"; its
 * space function here says no byte is one, and a field is read as written.
 * A line of blanks alone is still no record: the blanks that start a line
 * are held until its next byte says which it is.
 *
 * A record's first line: libcsv begins a record at the first byte after the
 * previous one that is not a CR or LF, and ends it only at an
 * unquoted CR or LF. So between records the bytes go to libcsv one at a
 * time until that first byte (its line is the record's), and inside a record
 * in pieces that each end at a CR or LF: after every piece the line count and
 * "inside a record" are exact however many lines a quoted field spans. (The
 * line where the first field ENDS, the rule before, is past the row's start
 * when that field spans lines.)
 */
#include "csvtab.h"
#include "out.h"

#include <csv.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define COMMENT_MAX 1024

typedef struct reader {
	const bk_csvtab_spec *spec;
	bk_csvtab *t;
	char *err;
	size_t errlen;
	int bad, io, max_rows, cap; /* io: the file could not be opened or read */
	int line;      /* the line of the next byte, from 1 */
	int at_start;  /* the next byte starts a line */
	int open;      /* inside a record, which started on rec_line */
	int rec_line, header_done, nfield;
	char pend[64]; /* spaces and tabs that start a line: a record's first bytes, or a blank line */
	size_t npend;
	char *head[BK_CSVTAB_MAX_FIELDS]; /* the header's names while it is read */
	int want[BK_CSVTAB_MAX_FIELDS];   /* field j is cols[want[j]], or -1 */
	char *cur[BK_CSVTAB_MAX_COLS];    /* the record's cells asked for */
	int in_comment, comment_line;
	size_t clen;
	char comment[COMMENT_MAX];
	char buf[1 << 16]; /* the file's bytes, a piece at a time */
} reader;

static int verr(char *err, size_t errlen, const char *path, int line, const char *fmt, va_list ap)
{
	int k = line > 0 ? snprintf(err, errlen, "%.300s:%d: ", path, line) : snprintf(err, errlen, "%.300s: ", path);
	if (k >= 0 && (size_t)k < errlen)
		vsnprintf(err + k, errlen - (size_t)k, fmt, ap);
	return -1;
}

int bk_csvtab_err(char *err, size_t errlen, const char *path, int line, const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	verr(err, errlen, path, line, fmt, ap);
	va_end(ap);
	return -1;
}

static void fail(reader *r, int line, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static void fail(reader *r, int line, const char *fmt, ...)
{
	if (r->bad++) /* the first error is the one that names the cause */
		return;
	va_list ap;
	va_start(ap, fmt);
	verr(r->err, r->errlen, r->t->path, line, fmt, ap);
	va_end(ap);
}

static void on_field(void *s, size_t len, void *data)
{
	reader *r = data;
	if (r->bad)
		return;
	if (r->nfield >= BK_CSVTAB_MAX_FIELDS) {
		fail(r, r->rec_line, "more than %d fields", BK_CSVTAB_MAX_FIELDS);
		return;
	}
	int j = r->nfield++;
	char **to = !r->header_done ? &r->head[j] : r->want[j] >= 0 ? &r->cur[r->want[j]] : NULL;
	if (to && !(*to = strndup(s ? s : "", len)))
		fail(r, 0, "out of memory");
}

static void header(reader *r)
{
	bk_csvtab *t = r->t;
	const bk_csvtab_spec *sp = r->spec;
	t->header_line = r->rec_line;
	for (int j = 0; j < r->nfield; j++)
		for (int i = 0; i < j && r->head[j][0]; i++)
			if (!strcmp(r->head[i], r->head[j])) {
				fail(r, r->rec_line, "column '%.60s' twice in the header", r->head[j]);
				return;
			}
	memset(r->want, -1, sizeof r->want); /* every byte 0xff: each int -1 */
	for (int k = 0; k < t->ncols; k++) {
		t->col[k] = -1;
		for (int j = 0; j < r->nfield && t->col[k] < 0; j++)
			if (!strcmp(r->head[j], sp->cols[k]))
				t->col[k] = j;
		if (t->col[k] >= 0)
			r->want[t->col[k]] = k;
		else if (!(sp->optional >> k & 1u)) {
			fail(r, r->rec_line, "no column '%s'%s%s%s", sp->cols[k], sp->hint ? " (" : "", sp->hint ? sp->hint : "",
			     sp->hint ? ")" : "");
			return;
		}
	}
	r->header_done = 1;
}

static void row(reader *r)
{
	bk_csvtab *t = r->t;
	if (t->n >= r->max_rows) {
		fail(r, r->rec_line, "more than %d rows", r->max_rows);
		return;
	}
	for (int k = 0; k < t->ncols; k++)
		if (t->col[k] >= r->nfield) {
			fail(r, r->rec_line, "%d fields, fewer than the header's", r->nfield);
			return;
		}
	if (t->n == r->cap) { /* doubling, up to max_rows */
		int cap = r->cap ? 2 * r->cap : 64;
		cap = cap < r->max_rows ? cap : r->max_rows;
		int *line = realloc(t->line, (size_t)cap * sizeof *line); /* cell: ncols + 1, never 0 bytes */
		char **cell = line ? realloc(t->cell, (size_t)cap * (size_t)(t->ncols + 1) * sizeof *cell) : NULL;
		t->line = line ? line : t->line;
		if (!cell) {
			fail(r, 0, "out of memory");
			return;
		}
		t->cell = cell;
		r->cap = cap;
	}
	t->line[t->n] = r->rec_line;
	for (int k = 0; k < t->ncols; k++) {
		t->cell[t->n * t->ncols + k] = r->cur[k];
		r->cur[k] = NULL;
	}
	t->n++;
}

/* The record's fields freed: after each record, and at the end. */
static void reset(reader *r)
{
	for (int j = 0; j < r->nfield; j++) {
		free(r->head[j]);
		r->head[j] = NULL;
	}
	for (int k = 0; k < BK_CSVTAB_MAX_COLS; k++) {
		free(r->cur[k]);
		r->cur[k] = NULL;
	}
	r->nfield = 0;
	r->open = 0;
}

static void on_record(int c, void *data)
{
	(void)c;
	reader *r = data;
	if (r->bad) {
	} else if (!r->header_done)
		header(r);
	else
		row(r);
	reset(r);
}

static void feed(reader *r, struct csv_parser *p, const char *s, size_t n)
{
	if (csv_parse(p, s, n, on_field, on_record, r) != n)
		fail(r, r->line, "%s", csv_strerror(csv_error(p)));
}

static void comment_end(reader *r)
{
	size_t n = r->clen < COMMENT_MAX ? r->clen : COMMENT_MAX - 1;
	if (n && r->comment[n - 1] == '\r')
		n--;
	r->comment[n] = '\0';
	if (r->spec->comment)
		r->spec->comment(r->spec->ctx, r->comment_line, r->comment);
	r->in_comment = 0;
}

/* No byte is a space to trim (the header says why). */
static int no_space(unsigned char c)
{
	(void)c;
	return 0;
}

/* Bytes s[0..n) of the file, in order (csvtab.c's header says how). */
static void process(reader *r, struct csv_parser *p, const char *s, size_t n)
{
	for (size_t i = 0; i < n && !r->bad;) {
		unsigned char c = (unsigned char)s[i];
		if (c == '\0') {
			fail(r, r->line, "a NUL byte (not a text file)");
			return;
		}
		if (r->in_comment) {
			size_t k = i;
			while (k < n && s[k] != '\n' && s[k] != '\0')
				k++;
			size_t room = r->clen < COMMENT_MAX ? COMMENT_MAX - r->clen : 0;
			memcpy(r->comment + r->clen, s + i, k - i < room ? k - i : room);
			r->clen += k - i;
			i = k;
			if (k < n && s[k] == '\n') {
				comment_end(r);
				r->line++;
				r->at_start = 1;
				i++;
			}
			continue;
		}
		if (!r->open) {
			if (c == '#' && r->at_start && !r->header_done) {
				r->in_comment = 1;
				r->comment_line = r->line;
				r->clen = 0;
				continue;
			}
			if ((c == ' ' || c == '\t') && r->npend < sizeof r->pend) { /* known at the line's next other byte */
				r->pend[r->npend++] = (char)c;
				r->at_start = 0;
				i++;
				continue;
			}
			if (c == '\r' || c == '\n') { /* libcsv skips these between records */
				r->npend = 0;             /* and a line of blanks with them, as before */
				feed(r, p, s + i, 1);
				r->at_start = c == '\n';
				r->line += c == '\n';
				i++;
				continue;
			}
			r->open = 1;
			r->rec_line = r->line;
			if (r->npend) { /* data: the record's first field starts with them */
				feed(r, p, r->pend, r->npend);
				r->npend = 0;
			}
		}
		size_t k = i; /* the piece: up to and with the next CR or LF */
		while (k < n && s[k] != '\r' && s[k] != '\n' && s[k] != '\0')
			k++;
		if (k < n && s[k] != '\0')
			k++;
		feed(r, p, s + i, k - i);
		r->at_start = s[k - 1] == '\n';
		r->line += r->at_start;
		i = k;
	}
}

int bk_csvtab_read(const char *path, const bk_csvtab_spec *spec, bk_csvtab *t, char *err, size_t errlen)
{
	memset(t, 0, sizeof *t);
	t->path = path;
	while (spec->cols[t->ncols] && t->ncols < BK_CSVTAB_MAX_COLS)
		t->ncols++;
	reader *r = calloc(1, sizeof *r); /* 70 kB: not on a caller's stack */
	if (!r)
		return bk_csvtab_err(err, errlen, path, 0, "out of memory");
	r->spec = spec, r->t = t, r->err = err, r->errlen = errlen, r->line = r->at_start = 1;
	r->max_rows = spec->max_rows > 0 ? spec->max_rows : BK_CSVTAB_MAX_ROWS;
	long max_bytes = spec->max_bytes > 0 ? spec->max_bytes : BK_CSVTAB_MAX_BYTES, total = 0;
	/* opened without blocking on a FIFO (no writer: no end), and only a
	 * regular file read: every CSV handed in is a file brdfkit or a user wrote */
	char why[96];
	int fd = bk_in_open(path, why, sizeof why), e = errno;
	FILE *f = fd >= 0 ? fdopen(fd, "rb") : NULL;
	struct csv_parser p;
	if (fd >= 0 && !f)
		e = errno, close(fd);
	if (fd == -2) {
		r->io = 1;
		fail(r, 0, "%s", why);
	} else if (!f) {
		r->io = 1;
		fail(r, 0, "cannot be read (%s)", strerror(e));
	} else if (csv_init(&p, CSV_APPEND_NULL)) {
		fclose(f);
		f = NULL;
		fail(r, 0, "out of memory");
	} else
		csv_set_space_func(&p, no_space);
	if (f) {
		size_t got;
		for (int first = 1; !r->bad && (got = fread(r->buf, 1, sizeof r->buf, f)) > 0; first = 0) {
			const char *s = r->buf;
			if ((total += (long)got) > max_bytes) {
				fail(r, 0, "more than %ld bytes", max_bytes);
				break;
			}
			if (first && got >= 3 && !memcmp(s, "\xEF\xBB\xBF", 3)) /* a UTF-8 BOM */
				s += 3, got -= 3;
			process(r, &p, s, got);
		}
		if (!r->bad && ferror(f)) {
			r->io = 1;
			fail(r, 0, "read failed");
		}
		if (!r->bad && r->in_comment)
			comment_end(r);
		/* libcsv's lenient mode takes a quote left open to the end of the
		 * file into one field, and csv_fini would end the record as if it
		 * were whole: a misleading error about its content follows. Its
		 * state says so before: a quoted field begun (libcsv's FIELD_BEGUN
		 * is 2, csv.c) and not closed. */
		if (!r->bad && r->open && p.quoted && p.pstate == 2)
			fail(r, r->rec_line, "unterminated quoted field (a quote opened in this row is never closed)");
		if (!r->bad && csv_fini(&p, on_field, on_record, r))
			fail(r, r->rec_line, "%s", csv_strerror(csv_error(&p)));
		if (!r->bad && !r->header_done)
			fail(r, 0, "empty (no header)");
		csv_free(&p);
		fclose(f);
	}
	reset(r); /* a record cut short by an error */
	int bad = r->bad, io = r->io;
	free(r);
	if (bad)
		bk_csvtab_free(t);
	return !bad ? 0 : io ? -2 : -1;
}

const char *bk_csvtab_get(const bk_csvtab *t, int i, int k)
{
	const char *s = t->cell[i * t->ncols + k];
	return s ? s : "";
}

void bk_csvtab_free(bk_csvtab *t)
{
	for (int i = 0; t->cell && i < t->n * t->ncols; i++)
		free(t->cell[i]);
	free(t->cell);
	free(t->line);
	memset(t, 0, sizeof *t);
}

int bk_csvtab_number(const char *text, double *x)
{
	static const char digits[] = "0123456789";
	const char *s = text + (*text == '+' || *text == '-'), *mant = s;
	s += strspn(s, digits);
	if (*s == '.')
		s += 1 + strspn(s + 1, digits);
	size_t nmant = (size_t)(s - mant);
	if (nmant == 0 || (nmant == 1 && *mant == '.'))
		return -1;
	int nonzero = strcspn(mant, "123456789") < nmant;
	if (*s == 'e' || *s == 'E') {
		s += 1 + (s[1] == '+' || s[1] == '-');
		size_t e = strspn(s, digits);
		if (e == 0)
			return -1;
		s += e;
	}
	if (*s)
		return -1;
	double v = strtod(text, NULL);
	/* ERANGE is also how strtod reports a subnormal result, which is a number
	 * like any other; overflow to inf, and a nonzero text that underflows to
	 * zero, are not the value typed. */
	if (!isfinite(v) || (v == 0.0 && nonzero))
		return -1;
	*x = v;
	return 0;
}
