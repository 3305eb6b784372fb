/*
 * csvget — reads a column of a brdfkit CSV by its name, for the shell tests.
 *
 *   csvget FILE NAME                 every data row's NAME field, one a line
 *   csvget FILE NAME KEY VALUE       NAME of the rows whose KEY field is VALUE
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

typedef struct reader {
	const char *path, *name, *key, *value;
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

static void on_record(int c, void *vr)
{
	(void)c;
	reader *r = vr;
	r->line++;
	if (r->bad) {
		/* keep freeing */
	} else if (r->header_nf < 0) {
		r->header_nf = r->nf;
		r->col = find(r, r->name);
		r->key_col = r->key ? find(r, r->key) : -1;
		if (r->col < 0 || (r->key && r->key_col < 0)) {
			fprintf(stderr, "csvget: %s: no column '%s'\n", r->path, r->col < 0 ? r->name : r->key);
			r->bad = 1;
		}
	} else if (r->nf != r->header_nf) {
		fprintf(stderr, "csvget: %s: record %ld has %d fields, the header %d\n", r->path, r->line, r->nf,
		        r->header_nf);
		r->bad = 1;
	} else {
		r->rows++;
		if (!r->key || !strcmp(r->field[r->key_col], r->value)) {
			r->matched++;
			puts(r->field[r->col]);
		}
	}
	for (int i = 0; i < r->nf && i < MAX_FIELDS; i++)
		free(r->field[i]);
	r->nf = 0;
}

int main(int argc, char **argv)
{
	if (argc != 3 && argc != 5) {
		fprintf(stderr, "usage: csvget FILE NAME [KEY VALUE]\n");
		return 2;
	}
	reader r = {.path = argv[1], .name = argv[2], .key = argc == 5 ? argv[3] : NULL,
	            .value = argc == 5 ? argv[4] : NULL, .header_nf = -1};
	FILE *f = fopen(r.path, "r");
	if (!f) {
		fprintf(stderr, "csvget: %s: cannot be read\n", r.path);
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
		if (!quoted && line[0] == '#')
			continue;
		for (ssize_t i = 0; i < len; i++)
			if (line[i] == '"')
				quoted = !quoted;
		if (csv_parse(&p, line, (size_t)len, on_field, on_record, &r) != (size_t)len) {
			fprintf(stderr, "csvget: %s: %s\n", r.path, csv_strerror(csv_error(&p)));
			r.bad = 1;
			break;
		}
	}
	csv_fini(&p, on_field, on_record, &r);
	csv_free(&p);
	free(line);
	fclose(f);
	if (r.bad)
		return 1;
	if (r.header_nf < 0 || r.rows == 0) {
		fprintf(stderr, "csvget: %s: no data row\n", r.path);
		return 1;
	}
	if (r.key && !r.matched) {
		fprintf(stderr, "csvget: %s: no row with %s = %s\n", r.path, r.key, r.value);
		return 1;
	}
	return 0;
}
