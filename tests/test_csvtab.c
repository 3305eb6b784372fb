/*
 * test_csvtab.c — a CSV read by column name (analysis/csvtab.h) on files
 * planted in a temporary directory, every expected cell and line counted by
 * hand from the planted text; each limit and each error beside a control
 * that passes just inside it.
 */
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "csvtab.h"
#include "fixture_tmpdir.h"

static char dir[64], path[128], err[800];

static void make_dir(void) { fx_tmpdir_make(dir, sizeof dir, "csvtab"); }

static void remove_dir(void) { fx_tmpdir_remove(dir); }

TestSuite(csvtab, .init = make_dir, .fini = remove_dir, .timeout = 30);

/* text[0..len) as dir/f.csv; its path */
static const char *plant_n(const char *text, size_t len)
{
	snprintf(path, sizeof path, "%s/f.csv", dir);
	FILE *f = fopen(path, "wb");
	cr_assert_not_null(f);
	cr_assert_eq(fwrite(text, 1, len, f), len);
	cr_assert_eq(fclose(f), 0);
	return path;
}

static const char *plant(const char *text)
{
	return plant_n(text, strlen(text));
}

static const char *const AB[] = {"a", "b", NULL};

/* reads text with cols; asserts success */
static void read_ok(const char *text, const bk_csvtab_spec *spec, bk_csvtab *t)
{
	cr_assert_eq(bk_csvtab_read(plant(text), spec, t, err, sizeof err), 0, "%s", err);
}

/* reads text with spec; asserts err is exactly "PATH" + tail */
static void read_bad(const char *text, size_t len, const bk_csvtab_spec *spec, const char *tail)
{
	bk_csvtab t;
	char want[300];
	cr_expect_eq(bk_csvtab_read(plant_n(text, len), spec, &t, err, sizeof err), -1, "accepted: want %s", tail);
	snprintf(want, sizeof want, "%s%s", path, tail);
	cr_expect_str_eq(err, want);
	cr_expect_eq(t.n, 0);
	cr_expect_null(t.cell);
}

/* a literal, NUL bytes and all */
#define READ_BAD(text, spec, tail) read_bad(text, sizeof text - 1, spec, tail)

static char seen[4][1100];
static int seen_line[4], nseen;

static void note(void *ctx, int line, const char *text)
{
	(void)ctx;
	if (nseen < 4) {
		seen_line[nseen] = line;
		snprintf(seen[nseen], sizeof seen[nseen], "%s", text);
	}
	nseen++;
}

/* Columns found by name whatever their order, an extra column between them,
 * the '#' lines before the header handed over with their lines. */
Test(csvtab, columns_by_name_in_any_order)
{
	bk_csvtab_spec spec = {.cols = AB, .comment = note};
	bk_csvtab t;
	nseen = 0;
	read_ok("# one\n# two, with a comma\nb,extra,a\n1,x,2\n3,y,4\n", &spec, &t);
	cr_expect_eq(nseen, 2);
	cr_expect_str_eq(seen[0], "# one");
	cr_expect_str_eq(seen[1], "# two, with a comma");
	cr_expect_eq(seen_line[0], 1);
	cr_expect_eq(seen_line[1], 2);
	cr_expect_eq(t.header_line, 3);
	cr_expect_eq(t.col[0], 2);
	cr_expect_eq(t.col[1], 0);
	cr_assert_eq(t.n, 2);
	cr_expect_str_eq(bk_csvtab_get(&t, 0, 0), "2");
	cr_expect_str_eq(bk_csvtab_get(&t, 0, 1), "1");
	cr_expect_str_eq(bk_csvtab_get(&t, 1, 0), "4");
	cr_expect_str_eq(bk_csvtab_get(&t, 1, 1), "3");
	cr_expect_eq(t.line[0], 4);
	cr_expect_eq(t.line[1], 5);
	bk_csvtab_free(&t);
}

/* After the header a '#' is data (every reader took it so); blank and
 * space-only lines between records are no rows and do not shift lines. */
Test(csvtab, hash_after_the_header_is_data_and_blank_lines_skipped)
{
	static const char *const A[] = {"a", NULL};
	bk_csvtab_spec spec = {.cols = A};
	bk_csvtab t;
	read_ok("a\n#x\n\n   \n\t\ny\n", &spec, &t);
	cr_assert_eq(t.n, 2);
	cr_expect_str_eq(bk_csvtab_get(&t, 0, 0), "#x");
	cr_expect_eq(t.line[0], 2);
	cr_expect_str_eq(bk_csvtab_get(&t, 1, 0), "y");
	cr_expect_eq(t.line[1], 6);
	bk_csvtab_free(&t);
}

/* Quoted fields: a comma, doubled quotes, line breaks kept as written; the
 * last row without a final line break. */
Test(csvtab, quoted_fields)
{
	bk_csvtab_spec spec = {.cols = AB};
	bk_csvtab t;
	read_ok("a,b\n\"x, \"\"y\"\"\",1\n\"p\nq\",2\nlast,3", &spec, &t);
	cr_assert_eq(t.n, 3);
	cr_expect_str_eq(bk_csvtab_get(&t, 0, 0), "x, \"y\"");
	cr_expect_str_eq(bk_csvtab_get(&t, 1, 0), "p\nq");
	cr_expect_eq(t.line[1], 3);
	cr_expect_str_eq(bk_csvtab_get(&t, 2, 0), "last");
	cr_expect_str_eq(bk_csvtab_get(&t, 2, 1), "3");
	cr_expect_eq(t.line[2], 5);
	bk_csvtab_free(&t);
}

/* A row whose quoted first field spans lines 3 to 5 starts on line 3. The
 * rule of the readers before (the line where the first field ENDS) gives 5:
 * the second assertion is what that rule fails. */
Test(csvtab, a_row_starts_where_its_first_field_starts)
{
	bk_csvtab_spec spec = {.cols = AB};
	bk_csvtab t;
	read_ok("# c\na,b\n\"first\nsecond\nthird\",7\nplain,8\n", &spec, &t);
	cr_assert_eq(t.n, 2);
	cr_expect_str_eq(bk_csvtab_get(&t, 0, 0), "first\nsecond\nthird");
	cr_expect_eq(t.line[0], 3);
	cr_expect_neq(t.line[0], 5, "the line where the first field ends");
	cr_expect_eq(t.line[1], 6);
	bk_csvtab_free(&t);
}

/* CRLF: the same lines; a CRLF inside quotes is the field's, blank CRLF
 * lines between records are skipped. */
Test(csvtab, crlf_lines)
{
	bk_csvtab_spec spec = {.cols = AB};
	bk_csvtab t;
	read_ok("# c\r\na,b\r\n\"x\r\ny\r\nz\",1\r\n\r\n\r\nw,2\r\n", &spec, &t);
	cr_assert_eq(t.n, 2);
	cr_expect_str_eq(bk_csvtab_get(&t, 0, 0), "x\r\ny\r\nz");
	cr_expect_eq(t.line[0], 3);
	cr_expect_str_eq(bk_csvtab_get(&t, 1, 0), "w");
	cr_expect_str_eq(bk_csvtab_get(&t, 1, 1), "2");
	cr_expect_eq(t.line[1], 8);
	bk_csvtab_free(&t);
}

/* A UTF-8 BOM at the file's start is dropped (the header's first name and a
 * first '#' line stay whole); one elsewhere is the field's (3 bytes more). */
Test(csvtab, byte_order_mark_at_the_start_only)
{
	bk_csvtab_spec spec = {.cols = AB, .comment = note};
	bk_csvtab t;
	nseen = 0;
	read_ok("\xEF\xBB\xBF# c\na,b\n\xEF\xBB\xBFx,1\n", &spec, &t);
	cr_expect_eq(nseen, 1);
	cr_expect_str_eq(seen[0], "# c");
	cr_assert_eq(t.n, 1);
	cr_expect_eq(strlen(bk_csvtab_get(&t, 0, 0)), 4);
	cr_expect_eq(t.line[0], 3);
	bk_csvtab_free(&t);
	read_ok("\xEF\xBB\xBF" "a,b\n1,2\n", &spec, &t);
	cr_expect_eq(t.col[0], 0);
	cr_expect_str_eq(bk_csvtab_get(&t, 0, 0), "1");
	bk_csvtab_free(&t);
}

/* Lines counted across the 64 KiB pieces the file is read in: a quoted
 * field of lines 2-4 padded so that a piece ends at each byte of the rows
 * in turn; by hand, rows start on lines 2, 6 and 7 whatever the padding. */
Test(csvtab, lines_across_read_pieces)
{
	bk_csvtab_spec spec = {.cols = AB};
	size_t head = strlen("a,b\n\"");
	for (size_t pad = 65536 - head - 24; pad <= 65536 - head; pad++) {
		char *s = malloc(pad + 64);
		cr_assert_not_null(s);
		memcpy(s, "a,b\n\"", head);
		memset(s + head, 'x', pad);
		strcpy(s + head + pad, "\n\ny\",1\n\nz,2\n\"c\nd\",3\n");
		bk_csvtab t;
		cr_assert_eq(bk_csvtab_read(plant(s), &spec, &t, err, sizeof err), 0, "%s", err);
		cr_assert_eq(t.n, 3, "pad %zu", pad);
		cr_expect_eq(t.line[0], 2, "pad %zu", pad);
		cr_expect_eq(strlen(bk_csvtab_get(&t, 0, 0)), pad + 3, "pad %zu", pad);
		cr_expect_eq(t.line[1], 6, "pad %zu", pad);
		cr_expect_str_eq(bk_csvtab_get(&t, 1, 0), "z");
		cr_expect_eq(t.line[2], 7, "pad %zu", pad);
		cr_expect_str_eq(bk_csvtab_get(&t, 2, 0), "c\nd");
		bk_csvtab_free(&t);
		free(s);
	}
}

Test(csvtab, empty_file_and_header_only)
{
	bk_csvtab_spec spec = {.cols = AB};
	READ_BAD("", &spec, ": empty (no header)");
	READ_BAD("# only\n# comments\n\n", &spec, ": empty (no header)");
	bk_csvtab t;
	read_ok("# c\na,b\n", &spec, &t); /* the control: a header, no rows */
	cr_expect_eq(t.n, 0);
	cr_expect_eq(t.header_line, 2);
	bk_csvtab_free(&t);
	/* a file that cannot be opened is -2 (runtime), a bad one -1 (read_bad) */
	cr_expect_eq(bk_csvtab_read("/nonexistent/f.csv", &spec, &t, err, sizeof err), -2);
	cr_expect_str_eq(err, "/nonexistent/f.csv: cannot be read (No such file or directory)");
}

/* A required column missing, named with the header's line and the hint; an
 * optional one missing reads as "" (the control). */
Test(csvtab, missing_column)
{
	bk_csvtab_spec spec = {.cols = AB};
	READ_BAD("# c\na,c\n1,2\n", &spec, ":2: no column 'b'");
	spec.hint = "not a front";
	READ_BAD("# c\na,c\n1,2\n", &spec, ":2: no column 'b' (not a front)");
	spec.optional = 1u << 1;
	bk_csvtab t;
	read_ok("# c\na,c\n1,2\n", &spec, &t);
	cr_expect_eq(t.col[1], -1);
	cr_expect_str_eq(bk_csvtab_get(&t, 0, 0), "1");
	cr_expect_str_eq(bk_csvtab_get(&t, 0, 1), "");
	bk_csvtab_free(&t);
}

/* A name twice in the header is an error even where not asked for; the
 * control has the same names once. */
Test(csvtab, duplicate_column)
{
	bk_csvtab_spec spec = {.cols = AB};
	READ_BAD("a,b,c,c\n1,2,3,4\n", &spec, ":1: column 'c' twice in the header");
	bk_csvtab t;
	read_ok("a,b,c,d\n1,2,3,4\n", &spec, &t);
	cr_expect_eq(t.n, 1);
	bk_csvtab_free(&t);
}

/* A row short of a column asked for fails on its first line (the quoted
 * field spans lines 3-4); short of one not asked for, or longer than the
 * header, it is read (as the readers before did). */
Test(csvtab, ragged_rows)
{
	bk_csvtab_spec spec = {.cols = AB};
	READ_BAD("b,c,a\n1,2,3\n\"4\n5\",6\n", &spec, ":3: 2 fields, fewer than the header's");
	bk_csvtab t;
	read_ok("a,b,c\n1,2,3\n4,5\n6,7,8,9\n", &spec, &t);
	cr_assert_eq(t.n, 3);
	cr_expect_str_eq(bk_csvtab_get(&t, 1, 1), "5");
	cr_expect_str_eq(bk_csvtab_get(&t, 2, 0), "6");
	bk_csvtab_free(&t);
}

/* max_rows 130 (past the first 64 rows' storage, grown twice): 130 rows
 * read, a 131st fails on its line (the header is line 1, row i line i + 2). */
Test(csvtab, row_limit)
{
	bk_csvtab_spec spec = {.cols = AB, .max_rows = 130};
	static char s[131 * 12 + 8];
	for (int n = 130; n <= 131; n++) {
		strcpy(s, "a,b\n");
		for (int i = 0; i < n; i++) {
			size_t len = strlen(s);
			snprintf(s + len, sizeof s - len, "%d,%d\n", i, -i);
		}
		bk_csvtab t;
		if (n == 131) {
			read_bad(s, strlen(s), &spec, ":132: more than 130 rows");
			continue;
		}
		read_ok(s, &spec, &t);
		cr_assert_eq(t.n, 130);
		cr_expect_str_eq(bk_csvtab_get(&t, 129, 0), "129");
		cr_expect_str_eq(bk_csvtab_get(&t, 129, 1), "-129");
		cr_expect_eq(t.line[129], 131);
		bk_csvtab_free(&t);
	}
}

/* max_bytes: a file of exactly that many bytes is read, one more fails. */
Test(csvtab, byte_limit)
{
	static const char text[] = "a,b\n1,2\n"; /* 8 bytes */
	bk_csvtab_spec spec = {.cols = AB, .max_bytes = 8};
	bk_csvtab t;
	read_ok(text, &spec, &t);
	cr_expect_eq(t.n, 1);
	bk_csvtab_free(&t);
	spec.max_bytes = 7;
	READ_BAD(text, &spec, ": more than 7 bytes");
}

/* 256 fields a record are read, 257 fail on the record's line. */
Test(csvtab, field_limit)
{
	static const char *const A[] = {"a", NULL};
	bk_csvtab_spec spec = {.cols = A};
	char s[300];
	for (int nf = 256; nf <= 257; nf++) {
		size_t n = 0;
		s[n++] = 'a';
		for (int j = 1; j < nf; j++)
			s[n++] = ',';
		strcpy(s + n, "\n1\n");
		bk_csvtab t;
		if (nf == 256) {
			read_ok(s, &spec, &t);
			cr_expect_eq(t.n, 1);
			bk_csvtab_free(&t);
		} else
			read_bad(s, strlen(s), &spec, ":1: more than 256 fields");
	}
}

/* A '#' line's first 1023 bytes are handed over: 1023 whole, 1024 cut. */
Test(csvtab, long_comment_cut)
{
	static const char *const A[] = {"a", NULL};
	bk_csvtab_spec spec = {.cols = A, .comment = note};
	for (size_t len = 1023; len <= 1024; len++) {
		char *s = malloc(len + 16);
		cr_assert_not_null(s);
		memset(s, '#', len);
		strcpy(s + len, "\na\n1\n");
		bk_csvtab t;
		nseen = 0;
		read_ok(s, &spec, &t);
		cr_expect_eq(nseen, 1);
		cr_expect_eq(strlen(seen[0]), 1023, "a comment of %zu bytes", len);
		cr_expect_eq(t.line[0], 3);
		bk_csvtab_free(&t);
		free(s);
	}
}

/* Not text, or a quote left open (libcsv, lenient, would take the rest of
 * the file into the field): errors on the line of the NUL, and of the row
 * that opened the quote, in the first field or a later one, with or without
 * a line break after it. A quote closed on a later line is a field. */
#define OPEN_QUOTE "unterminated quoted field (a quote opened in this row is never closed)"
Test(csvtab, nul_byte_and_open_quote)
{
	bk_csvtab_spec spec = {.cols = AB};
	READ_BAD("a,b\n1,2\nx\0y,3\n", &spec, ":3: a NUL byte (not a text file)");
	READ_BAD("a,b\n1,2\n\"open,3\nmore\n", &spec, ":3: " OPEN_QUOTE);
	READ_BAD("a,b\n1,2\nx,\"open\n", &spec, ":3: " OPEN_QUOTE);
	READ_BAD("a,b\n1,\"open", &spec, ":2: " OPEN_QUOTE);
	bk_csvtab t;
	read_ok("a,b\n1,\"two\nlines\"\n3,4\n", &spec, &t);
	cr_expect_eq(t.n, 2);
	cr_expect_eq(t.line[1], 4);
	bk_csvtab_free(&t);
}

/* Spaces are data (L8): a field is read as written, so " 5" is no number;
 * a line of blanks alone is still no row. */
Test(csvtab, spaces_are_data)
{
	bk_csvtab_spec spec = {.cols = AB};
	bk_csvtab t;
	read_ok("a,b\n 5,x \n  \t\n\t7,y\n", &spec, &t);
	cr_assert_eq(t.n, 2);
	cr_expect_str_eq(bk_csvtab_get(&t, 0, 0), " 5");
	cr_expect_str_eq(bk_csvtab_get(&t, 0, 1), "x ");
	cr_expect_str_eq(bk_csvtab_get(&t, 1, 0), "\t7");
	cr_expect_eq(t.line[1], 4);
	double x;
	cr_expect_eq(bk_csvtab_number(bk_csvtab_get(&t, 0, 0), &x), -1);
	bk_csvtab_free(&t);
}

/* The one number syntax: decimal, nothing around it. */
Test(csvtab, decimal_numbers_only)
{
	static const char *const good[] = {"5", "+5", "-0.5e-3", ".5", "5.", "1E3", "4.9e-324"};
	static const double want[] = {5, 5, -0.5e-3, 0.5, 5, 1000, 4.9e-324};
	static const char *const bad[] = {" 5", "5 ", "0x10", "0x1p-30", "inf", "nan", "1e999", "1e-400", "", "5abc", ".",
	                                  "e5", "1e", "\t5"};
	double x;
	for (size_t i = 0; i < sizeof good / sizeof good[0]; i++) {
		cr_expect_eq(bk_csvtab_number(good[i], &x), 0, "'%s' refused", good[i]);
		cr_expect_eq(x, want[i], "'%s' read as %g", good[i], x);
	}
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
		cr_expect_eq(bk_csvtab_number(bad[i], &x), -1, "'%s' accepted", bad[i]);
}
