/*
 * csvget — reads a column of a brdfkit CSV by its name, for the shell tests.
 *
 *   csvget FILE NAME                 every data row's NAME field, one a line
 *   csvget FILE NAME KEY VALUE       NAME of the rows whose KEY field is VALUE
 *   csvget --each NAME FILE...       each FILE's rows' NAME fields, then a line
 *                                    "@@" (one process for many files: a
 *                                    unit test reads 300 of them)
 *   csvget --set FILE NAME KEY VALUE NEW   FILE with NAME set to NEW in those rows
 *   csvget --drop FILE KEY VALUE     FILE without the rows whose KEY field is VALUE
 *
 * --set and --drop make the negative controls of the tests (a front whose best
 * rmse is edited upward, a front without the answer): the copy keeps comment
 * lines and quotes a field only where it must, as brdfkit writes its CSVs, and
 * fails as the reading does when the column or the row is not there.
 *
 * Lines that start with '#' before the header or between records are comments
 * (brdfkit writes its conventions there) and are skipped; the first other line
 * is the header. Fields are RFC 4180 (libcsv): a quoted form may hold commas.
 * A missing file, a missing column, a row with another field count or no data
 * row at all is an error (exit 1, one line on stderr): a check that reads
 * nothing must fail, never pass on an empty answer.
 */
#include <csv.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_FIELDS 256

typedef enum { GET, SET, DROP } mode;

typedef struct reader {
	mode mode;
	const char *path, *name, *key, *value, *set_to;
	char *field[MAX_FIELDS];
	int nf, header_nf, col, key_col, rows, matched, bad;
	long line;
} reader;

static void on_field(void *s, size_t len, void *vr)
{
	reader *r = vr;
	if (r->nf < MAX_FIELDS)
		r->field[r->nf] = strndup(s ? s : "", len);
	r->nf++;
}

static int find(const reader *r, const char *name)
{
	for (int i = 0; i < r->nf && i < MAX_FIELDS; i++)
		if (!strcmp(r->field[i], name))
			return i;
	return -1;
}

/* One field as brdfkit writes it: quoted (quotes doubled) only when it holds a
 * comma, a quote or a line break. */
static void put_field(const char *f, int last)
{
	if (strpbrk(f, ",\"\r\n")) {
		putchar('"');
		for (; *f; f++) {
			if (*f == '"')
				putchar('"');
			putchar(*f);
		}
		putchar('"');
	} else {
		fputs(f, stdout);
	}
	putchar(last ? '\n' : ',');
}

static void put_record(const reader *r)
{
	for (int i = 0; i < r->nf && i < MAX_FIELDS; i++)
		put_field(r->field[i], i == r->nf - 1);
}

static void on_record(int c, void *vr)
{
	(void)c;
	reader *r = vr;
	r->line++;
	if (r->bad) {
		/* keep freeing */
	} else if (r->header_nf < 0) {
		r->header_nf = r->nf;
		r->col = r->name ? find(r, r->name) : -1;
		r->key_col = r->key ? find(r, r->key) : -1;
		if ((r->name && r->col < 0) || (r->key && r->key_col < 0)) {
			fprintf(stderr, "csvget: %s: no column '%s'\n", r->path,
			        r->name && r->col < 0 ? r->name : r->key);
			r->bad = 1;
		} else if (r->mode != GET) {
			put_record(r);
		}
	} else if (r->nf != r->header_nf) {
		fprintf(stderr, "csvget: %s: record %ld has %d fields, the header %d\n", r->path, r->line, r->nf,
		        r->header_nf);
		r->bad = 1;
	} else {
		r->rows++;
		int hit = !r->key || !strcmp(r->field[r->key_col], r->value);
		r->matched += hit;
		if (r->mode == GET && hit) {
			puts(r->field[r->col]);
		} else if (r->mode == SET) {
			if (hit) {
				free(r->field[r->col]);
				r->field[r->col] = strdup(r->set_to);
			}
			put_record(r);
		} else if (r->mode == DROP && !hit) {
			put_record(r);
		}
	}
	for (int i = 0; i < r->nf && i < MAX_FIELDS; i++)
		free(r->field[i]);
	r->nf = 0;
}

static int usage(void)
{
	fprintf(stderr, "usage: csvget FILE NAME [KEY VALUE] | --each NAME FILE... | --set FILE NAME KEY VALUE NEW | "
	                "--drop FILE KEY VALUE\n");
	return 2;
}

/* r's file read and written out as its mode says: 0, or 1 with a line on
 * stderr. */
static int run(reader *r)
{
	FILE *f = fopen(r->path, "r");
	if (!f) {
		fprintf(stderr, "csvget: %s: cannot be read\n", r->path);
		return 1;
	}
	struct csv_parser p;
	if (csv_init(&p, CSV_APPEND_NULL)) {
		fclose(f);
		return 1;
	}
	char *line = NULL;
	size_t cap = 0;
	ssize_t len;
	int quoted = 0; /* inside a quoted field that spans lines: not a comment */
	while ((len = getline(&line, &cap, f)) > 0) {
		if (!quoted && line[0] == '#') {
			if (r->mode != GET)
				fputs(line, stdout);
			continue;
		}
		for (ssize_t i = 0; i < len; i++)
			if (line[i] == '"')
				quoted = !quoted;
		if (csv_parse(&p, line, (size_t)len, on_field, on_record, r) != (size_t)len) {
			fprintf(stderr, "csvget: %s: %s\n", r->path, csv_strerror(csv_error(&p)));
			r->bad = 1;
			break;
		}
	}
	csv_fini(&p, on_field, on_record, r);
	csv_free(&p);
	free(line);
	fclose(f);
	if (r->bad)
		return 1;
	if (r->header_nf < 0 || r->rows == 0) {
		fprintf(stderr, "csvget: %s: no data row\n", r->path);
		return 1;
	}
	if (r->key && !r->matched) {
		fprintf(stderr, "csvget: %s: no row with %s = %s\n", r->path, r->key, r->value);
		return 1;
	}
	return 0;
}

int main(int argc, char **argv)
{
	reader r = {.header_nf = -1};
	if (argc >= 4 && !strcmp(argv[1], "--each")) {
		int rc = 0;
		for (int i = 3; i < argc; i++) {
			reader each = {.header_nf = -1, .mode = GET, .path = argv[i], .name = argv[2]};
			rc |= run(&each);
			puts("@@");
		}
		return rc;
	}
	if (argc == 7 && !strcmp(argv[1], "--set")) {
		r.mode = SET, r.path = argv[2], r.name = argv[3], r.key = argv[4], r.value = argv[5], r.set_to = argv[6];
	} else if (argc == 5 && !strcmp(argv[1], "--drop")) {
		r.mode = DROP, r.path = argv[2], r.key = argv[3], r.value = argv[4];
	} else if ((argc == 3 || argc == 5) && argv[1][0] != '-') {
		r.mode = GET, r.path = argv[1], r.name = argv[2];
		r.key = argc == 5 ? argv[3] : NULL, r.value = argc == 5 ? argv[4] : NULL;
	} else {
		return usage();
	}
	return run(&r);
}
