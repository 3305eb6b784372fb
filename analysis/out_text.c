/*
 * out_text.c — escaping for CSV and HTML, links, names as file names and a
 * growing text buffer (out.h).
 */
#define _GNU_SOURCE /* open_memstream */
#include "out.h"
#include "out_int.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void bk_csv_field(FILE *f, const char *s)
{
	/* RFC 4180: a CR is a line break too; a field that starts with '#' would
	 * make a row that opens with it read as a comment line, and readers such
	 * as libcsv trim the blanks around a field that is not quoted */
	size_t n = strlen(s);
	int blank_end = n && (s[0] == ' ' || s[0] == '\t' || s[n - 1] == ' ' || s[n - 1] == '\t');
	if (*s != '#' && !blank_end && !strpbrk(s, ",\"\n\r")) {
		fputs(s, f);
		return;
	}
	fputc('"', f);
	for (; *s; s++) {
		if (*s == '"')
			fputc('"', f);
		fputc(*s, f);
	}
	fputc('"', f);
}

void bk_slug(const char *name, char *buf, size_t len)
{
	size_t k = 0;
	for (; *name && k + 1 < len; name++) {
		char c = *name;
		if ((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_')
			buf[k++] = c;
		else if (c >= 'A' && c <= 'Z')
			buf[k++] = (char)(c - 'A' + 'a');
		else if (k && buf[k - 1] != '_')
			buf[k++] = '_';
	}
	while (k && buf[k - 1] == '_')
		k--;
	buf[k] = '\0';
}

void bk_html_text(FILE *f, const char *s)
{
	for (; *s; s++)
		switch (*s) {
		case '&': fputs("&amp;", f); break;
		case '<': fputs("&lt;", f); break;
		case '>': fputs("&gt;", f); break;
		case '"': fputs("&quot;", f); break;
		default: fputc(*s, f);
		}
}

/* A byte a path segment holds as it is (RFC 3986 pchar less ':' and with
 * '/'); any other is percent-encoded (out.h). */
static int link_plain(unsigned char c)
{
	return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
	       (c && strchr("-._~!$&'()*+,;=@/", c));
}

static void link_part(FILE *f, const char *s)
{
	for (; s && *s; s++) {
		unsigned char c = (unsigned char)*s;
		if (c == '&')
			fputs("&amp;", f); /* the one plain byte HTML needs escaped in a quoted attribute */
		else if (link_plain(c))
			fputc(c, f);
		else
			fprintf(f, "%%%02X", c);
	}
}

void bk_html_link(FILE *f, const char *prefix, const char *path)
{
	link_part(f, prefix);
	link_part(f, path);
}

char *bk_html_link_text(const char *prefix, const char *path)
{
	char *out = NULL;
	size_t size = 0;
	FILE *f = open_memstream(&out, &size);
	if (!f)
		return NULL;
	bk_html_link(f, prefix, path);
	if (fclose(f)) {
		free(out);
		return NULL;
	}
	return out;
}

int bk_link_prefix_check(const char *prefix, char *err, size_t errlen)
{
	for (const char *c = prefix; *c; c++)
		if ((unsigned char)*c < 0x20 || *c == 0x7f) { /* not echoed: the line stays one */
			snprintf(err, errlen, "--link-prefix: a control character (byte %d)", (int)(c - prefix) + 1);
			return -1;
		}
	const char *why = NULL;
	size_t seg = strcspn(prefix, "/");
	if ((prefix[0] == '/' || prefix[0] == '\\') && (prefix[1] == '/' || prefix[1] == '\\'))
		why = "a network path (another host to a browser): give a path relative to the page";
	else if (memchr(prefix, ':', seg))
		why = "a URL scheme: give a path relative to the page (no javascript:, data:, http: ...)";
	else if (strchr(prefix, '\\'))
		why = "a backslash (a '/' to a browser): write '/'";
	if (!why)
		return 0;
	snprintf(err, errlen, "--link-prefix '%.80s': %s", prefix, why);
	return -1;
}

void bk_sb_put(bk_strbuf *b, const char *fmt, ...)
{
	for (;;) {
		if (b->oom)
			return;
		va_list ap;
		va_start(ap, fmt);
		int k = vsnprintf(b->s ? b->s + b->len : NULL, b->s ? b->cap - b->len : 0, fmt, ap);
		va_end(ap);
		if (k < 0) {
			b->oom = 1;
			return;
		}
		if (b->s && b->len + (size_t)k < b->cap) {
			b->len += (size_t)k;
			return;
		}
		size_t cap = b->cap ? b->cap : 4096;
		while (cap <= b->len + (size_t)k)
			cap *= 2;
		char *s = realloc(b->s, cap);
		if (!s) {
			b->oom = 1;
			return;
		}
		b->s = s;
		b->cap = cap;
	}
}
