/*
 * page.c — the page's inputs (page.h): files read with a bound, the link
 * prefix escaped once, and the check a section passes before brdfkit report
 * copies it into the page. The check is an allow-list: a small scanner
 * walks the tags and accepts only what brdfkit's own section writers emit,
 * so a section from elsewhere, or one whose writer forgot an escape, is
 * refused with the line of the first thing that does not belong.
 */
#define _XOPEN_SOURCE 700 /* realpath (XSI) */
#include "page.h"

#include "out.h"

#include <errno.h>
#include <limits.h>
#include <stddef.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---- reading with a bound ------------------------------------------------------ */

static void reason(char *err, size_t errlen, int e)
{
	snprintf(err, errlen, "cannot be read: %s", bk_out_errtext(e));
}

/* Reads fd to its end or to cap + 1 bytes into a buffer of its own. */
static char *read_fd(int fd, size_t cap, size_t hint, size_t *len, char *err, size_t errlen)
{
	size_t size = (hint < cap ? hint : cap) + 2, n = 0; /* room for one byte past the cap, and the NUL */
	char *buf = malloc(size);
	if (!buf) {
		reason(err, errlen, ENOMEM);
		return NULL;
	}
	for (;;) {
		if (n + 1 == size) {
			size_t grown = size - 2 < cap / 2 ? 2 * size : cap + 2;
			char *b = grown > size ? realloc(buf, grown) : NULL;
			if (!b) {
				free(buf);
				if (grown > size)
					reason(err, errlen, ENOMEM);
				else
					snprintf(err, errlen, "is longer than %zu bytes", cap);
				return NULL;
			}
			buf = b;
			size = grown;
		}
		ssize_t k = read(fd, buf + n, size - 1 - n);
		if (k < 0 && errno == EINTR)
			continue;
		if (k < 0) {
			int e = errno;
			free(buf);
			reason(err, errlen, e);
			return NULL;
		}
		if (k == 0)
			break;
		n += (size_t)k;
	}
	if (n > cap) {
		free(buf);
		snprintf(err, errlen, "is longer than %zu bytes", cap);
		return NULL;
	}
	buf[n] = '\0';
	*len = n;
	return buf;
}

/* bk_read_bounded and bk_read_regular: regular, a path other than "-" must
 * name a regular file, opened without blocking on a FIFO (bk_in_open). */
static char *read_path(const char *path, int regular, size_t cap, size_t *len, char *err, size_t errlen)
{
	int stdin_ = !strcmp(path, "-");
	char why[96];
	int fd = stdin_ ? 0 : regular ? bk_in_open(path, why, sizeof why) : open(path, O_RDONLY | O_CLOEXEC);
	struct stat st;
	if (fd == -2) {
		snprintf(err, errlen, "%s", why);
		return NULL;
	}
	if (fd < 0 || fstat(fd, &st)) {
		reason(err, errlen, errno);
		if (fd > 0)
			close(fd);
		return NULL;
	}
	char *text = NULL;
	if (S_ISDIR(st.st_mode))
		snprintf(err, errlen, "is a directory");
	else if (S_ISREG(st.st_mode) && (unsigned long long)st.st_size > cap)
		snprintf(err, errlen, "is %lld bytes, more than %zu", (long long)st.st_size, cap);
	else /* a regular file may still grow while it is read: the bound holds anyway */
		text = read_fd(fd, cap, S_ISREG(st.st_mode) ? (size_t)st.st_size : 4096, len, err, errlen);
	if (!stdin_)
		close(fd);
	return text;
}

char *bk_read_bounded(const char *path, size_t cap, size_t *len, char *err, size_t errlen)
{
	return read_path(path, 0, cap, len, err, errlen);
}

char *bk_read_regular(const char *path, size_t cap, size_t *len, char *err, size_t errlen)
{
	return read_path(path, 1, cap, len, err, errlen);
}

char *bk_html_escaped(const char *s)
{
	char *out = NULL;
	size_t size = 0;
	FILE *f = open_memstream(&out, &size);
	if (!f)
		return NULL;
	bk_html_text(f, s);
	if (fclose(f)) {
		free(out);
		return NULL;
	}
	return out;
}

/* ---- the section check ------------------------------------------------------------ */

/* What brdfkit's sections are made of: the page's tables and text, and the
 * SVG plots report.c draws. Anything not listed is refused. */
static const char *const elements[] = {
	"section", "h2", "h3", "h4", "p", "a", "img", "table", "tr", "th", "td", "code", "b", "i", "em", "strong",
	"br", "span", "sup", "sub", "ul", "ol", "li",
	"svg", "style", "g", "rect", "line", "polyline", "polygon", "path", "circle", "ellipse", "text", "tspan",
	"title", "figure", "figcaption", "details", "summary", NULL};
static const char *const attributes[] = {
	"id", "class", "href", "src", "alt", "width", "height", "colspan", "rowspan",
	"xmlns", "viewBox", "x", "y", "x1", "y1", "x2", "y2", "cx", "cy", "r", "rx", "ry", "d", "points",
	"transform", "fill", "fill-opacity", "stroke", "stroke-width", "stroke-dasharray", "stroke-linejoin",
	"opacity", "font-family", "font-size", "font-weight", "text-anchor", "dominant-baseline", NULL};

typedef struct scan {
	const char *start, *s, *end;
	char *err;
	size_t errlen;
} scan;

static int listed(const char *const *list, const char *name, size_t n)
{
	for (; *list; list++)
		if (strlen(*list) == n && !strncasecmp(*list, name, n))
			return 1;
	return 0;
}

static int refuse(scan *S, const char *at, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static int refuse(scan *S, const char *at, const char *fmt, ...)
{
	int line = 1;
	for (const char *p = S->start; p < at; p++)
		line += *p == '\n';
	int k = snprintf(S->err, S->errlen, "line %d: ", line);
	va_list ap;
	va_start(ap, fmt);
	if (k > 0 && (size_t)k < S->errlen)
		vsnprintf(S->err + k, S->errlen - (size_t)k, fmt, ap);
	va_end(ap);
	return -1;
}

static int is_space(char c)
{
	return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f';
}

static int is_alnum(char c)
{
	return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9');
}

/* A name's length at p: a letter, then letters, digits, '-' (and ':' for
 * attributes, so that xlink:href is seen whole and refused). */
static size_t name_len(const scan *S, const char *p, int attr)
{
	size_t n = 0;
	if (p >= S->end || !((*p >= 'a' && *p <= 'z') || (*p >= 'A' && *p <= 'Z')))
		return 0;
	while (p + n < S->end && (is_alnum(p[n]) || p[n] == '-' || (attr && p[n] == ':')))
		n++;
	return n;
}

/* A link's value once its character references are read: the five named
 * ones brdf's escaping writes stand for themselves; any other could spell
 * "javascript:" where it cannot be seen, so it is refused. */
static int url_check(scan *S, const char *v, size_t n)
{
	static const struct {
		const char *ref;
		char c;
	} refs[] = {{"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&#39;", '\''}};
	char url[16];
	size_t u = 0, pos = 0, lead = 0; /* pos: characters read; lead: the spaces a browser strips first */
	char first = 0;
	for (size_t i = 0; i < n; pos++) {
		char c = v[i];
		size_t step = 1;
		if (c == '&') {
			size_t k = 0;
			while (k < sizeof refs / sizeof refs[0] &&
			       !(strlen(refs[k].ref) <= n - i && !strncmp(v + i, refs[k].ref, strlen(refs[k].ref))))
				k++;
			if (k == sizeof refs / sizeof refs[0])
				return refuse(S, v, "a character reference in a link (brdfkit writes only &amp; &lt; &gt; &quot;)");
			c = refs[k].c;
			step = strlen(refs[k].ref);
		}
		if ((unsigned char)c < 0x20 || c == 0x7f) /* browsers drop tabs and line breaks from a URL */
			return refuse(S, v, "a control character in a link");
		int slash = c == '/' || c == '\\'; /* a backslash is a '/' to a browser */
		if (c == ' ' && pos == lead) { /* stripped by a browser: the link starts after */
			lead++;
			i += step;
			continue;
		}
		if (pos == lead && slash) { /* the next character decides: a path, or "//host" */
			first = c;
			i += step;
			continue;
		}
		if (pos == lead + 1 && first && slash) /* two slashes of either kind: another host */
			return refuse(S, v, "a network-path link ('//host' or '\\\\host': another host, not a relative link)");
		if (first || c == '/' || c == '?' || c == '#') /* the path starts: no scheme */
			return 0;
		if (c == ':') {
			url[u] = '\0';
			if (!strcasecmp(url, "http") || !strcasecmp(url, "https"))
				return 0;
			return refuse(S, v, "a link with the scheme '%s:' (only relative, http: and https: links)", url);
		}
		if (u + 1 < sizeof url)
			url[u++] = c;
		i += step;
	}
	return 0;
}

/* name="value": value quoted with '"', no raw '<' (brdfkit escapes it). */
static int attribute(scan *S)
{
	const char *at = S->s;
	size_t n = name_len(S, at, 1);
	if (!n)
		return refuse(S, at, "'%c' where an attribute's name should be", *at);
	if (!listed(attributes, at, n))
		return refuse(S, at, "%.*s=: not an attribute brdfkit writes", (int)(n < 40 ? n : 40), at);
	S->s += n;
	if (S->s + 1 >= S->end || S->s[0] != '=' || S->s[1] != '"')
		return refuse(S, at, "%.*s: a value not written as =\"...\"", (int)(n < 40 ? n : 40), at);
	const char *v = S->s + 2, *q = memchr(v, '"', (size_t)(S->end - v));
	if (!q)
		return refuse(S, at, "%.*s: an attribute's value never ends", (int)(n < 40 ? n : 40), at);
	if (memchr(v, '<', (size_t)(q - v)))
		return refuse(S, at, "%.*s: a raw '<' in an attribute's value", (int)(n < 40 ? n : 40), at);
	S->s = q + 1;
	if ((n == 4 && !strncasecmp(at, "href", 4)) || (n == 3 && !strncasecmp(at, "src", 3)))
		return url_check(S, v, (size_t)(q - v));
	return 0;
}

/* A <style>'s text: selectors and properties only. Without '(' there is no
 * url() or expression(), without '@' no @import, without '\' no escape that
 * spells either, without '<' no end of the element. */
static int style_text(scan *S)
{
	static const char ok[] = ".#:;,{}%-_ \t\n";
	const char *close = S->s;
	while (close < S->end && !(S->end - close >= 8 && !strncasecmp(close, "</style>", 8))) {
		if (!is_alnum(*close) && !strchr(ok, *close))
			return refuse(S, close, "<style>: '%c' (a section's style is selectors and properties only)", *close);
		close++;
	}
	if (close == S->end)
		return refuse(S, S->s, "<style> never ends");
	S->s = close;
	return 0;
}

/* <name attr="..." ...> or </name>, at S->s == '<'. */
static int tag(scan *S)
{
	const char *at = S->s;
	int end = at + 1 < S->end && at[1] == '/';
	const char *name = at + 1 + end;
	size_t n = name_len(S, name, 0);
	if (!n)
		return refuse(S, at, "a '<' that opens no tag (brdfkit writes text with '<' escaped)");
	if (!listed(elements, name, n))
		return refuse(S, at, "<%s%.*s>: not an element brdfkit writes", end ? "/" : "", (int)(n < 40 ? n : 40),
		              name);
	S->s = name + n;
	for (;;) {
		int spaced = 0;
		while (S->s < S->end && is_space(*S->s))
			S->s++, spaced = 1;
		if (S->s >= S->end)
			return refuse(S, at, "a tag that never ends");
		if (*S->s == '>' || (S->s + 1 < S->end && S->s[0] == '/' && S->s[1] == '>')) {
			S->s += *S->s == '>' ? 1 : 2;
			break;
		}
		if (end || !spaced)
			return refuse(S, S->s, "'%c' inside a tag", *S->s);
		if (attribute(S))
			return -1;
	}
	return !end && n == 5 && !strncasecmp(name, "style", 5) ? style_text(S) : 0;
}

/* The marker: <section id="ID"> first, </section> last. */
static int marker(scan *S, char *id, size_t idlen)
{
	static const char open[] = "<section id=\"";
	const char *p = S->start + sizeof open - 1, *q = p;
	if ((size_t)(S->end - S->start) < sizeof open - 1 || strncmp(S->start, open, sizeof open - 1))
		return refuse(S, S->start, "does not open with <section id=\"...\"> (not a section brdfkit wrote)");
	while (q < S->end && (is_alnum(*q) || *q == '-' || *q == '_'))
		q++;
	if (q == p || q + 1 >= S->end || q[0] != '"' || q[1] != '>')
		return refuse(S, p, "the section's id is not made of letters, digits, '-' and '_'");
	if ((size_t)(q - p) >= idlen)
		return refuse(S, p, "the section's id is longer than %zu characters", idlen - 1);
	memcpy(id, p, (size_t)(q - p));
	id[q - p] = '\0';
	const char *e = S->end;
	while (e > S->start && is_space(e[-1]))
		e--;
	if (e - S->start < 10 || strncmp(e - 10, "</section>", 10))
		return refuse(S, e, "does not end with </section> (not a whole section)");
	return 0;
}

int bk_section_check(const char *text, size_t len, char *id, size_t idlen, char *err, size_t errlen)
{
	scan S = {text, text, text + len, err, errlen};
	if (marker(&S, id, idlen))
		return -1;
	while (S.s < S.end) {
		const char *lt = memchr(S.s, '<', (size_t)(S.end - S.s));
		if (!lt)
			break;
		S.s = lt;
		if (tag(&S))
			return -1;
	}
	return 0;
}

/* ---- folding long tables ------------------------------------------------------------ */

/* Whether the tag at p (a '<') is <name ...> or <name> (open: end 0) or
 * </name> (end 1), the name whole. */
static int is_tag(const char *p, const char *e, const char *name, int end)
{
	size_t n = strlen(name);
	if (e - p < (ptrdiff_t)(n + 2 + (size_t)end) || p[0] != '<' || (end && p[1] != '/'))
		return 0;
	p += 1 + end;
	if (strncasecmp(p, name, n))
		return 0;
	char c = p[n];
	return c == '>' || is_space(c) || c == '/';
}

/* The end of the table opening at p: just after its </table> (nested tables
 * counted), or e. */
static const char *table_end(const char *p, const char *e, int *rows)
{
	int depth = 0;
	*rows = 0;
	for (const char *q = p; q < e; q++) {
		if (*q != '<')
			continue;
		if (is_tag(q, e, "table", 0))
			depth++;
		else if (is_tag(q, e, "tr", 0))
			*rows += depth == 1;
		else if (is_tag(q, e, "table", 1) && --depth == 0) {
			const char *gt = memchr(q, '>', (size_t)(e - q));
			return gt ? gt + 1 : e;
		}
	}
	return e;
}

/* The summary line: "N rows: " and the first row's cells' text, tags left
 * out, runs of space as one, cut after the last whole cell that ends within
 * 160 characters (a cell's text is whole, so no character reference is cut). */
static void fold_summary(FILE *f, const char *p, const char *e, int rows)
{
	const char *tr = p;
	while (tr < e && !is_tag(tr, e, "tr", 0))
		tr++;
	char line[256];
	size_t n = 0, whole = 0; /* whole: the length up to the last finished cell */
	int in_tag = 0, cells = 0, over = 0;
	for (const char *q = tr; q < e && !is_tag(q, e, "tr", 1) && !over; q++) {
		if (*q == '<') {
			if (is_tag(q, e, "th", 0) || is_tag(q, e, "td", 0)) {
				whole = n;
				if (cells++) {
					line[n++] = ',';
					line[n++] = ' ';
				}
			}
			in_tag = 1;
		} else if (*q == '>' && in_tag)
			in_tag = 0;
		else if (!in_tag && !(is_space(*q) && (n == 0 || line[n - 1] == ' '))) {
			line[n++] = is_space(*q) ? ' ' : *q;
		}
		over = n > 160;
	}
	if (over)
		n = whole;
	else
		whole = n;
	while (n && (line[n - 1] == ' ' || line[n - 1] == ','))
		n--;
	fprintf(f, "<details class=\"fold\"><summary>%d rows: %.*s%s</summary>\n", rows, (int)n, line, over ? ", \xe2\x80\xa6" : "");
}

int bk_page_fold(FILE *f, const char *text, size_t len, int min_rows)
{
	const char *p = text, *e = text + len, *done = text;
	int details = 0, folded = 0;
	while ((p = memchr(p, '<', (size_t)(e - p)))) {
		if (is_tag(p, e, "details", 0))
			details++;
		else if (is_tag(p, e, "details", 1))
			details -= details > 0;
		else if (is_tag(p, e, "table", 0) && !details) {
			int rows;
			const char *end = table_end(p, e, &rows);
			if (rows > min_rows) {
				fwrite(done, 1, (size_t)(p - done), f);
				fold_summary(f, p, end, rows);
				fwrite(p, 1, (size_t)(end - p), f);
				fputs("</details>", f);
				done = end;
				folded++;
			}
			p = end;
			continue;
		}
		p++;
	}
	fwrite(done, 1, (size_t)(e - done), f);
	return folded;
}

/* ---- links from the page ------------------------------------------------------------- */

/* The components of an absolute path, in place: '/' turned to NUL. */
static int components(char *path, char **comp, int max)
{
	int n = 0;
	for (char *p = path; *p;) {
		while (*p == '/')
			*p++ = '\0';
		if (*p && n < max)
			comp[n++] = p;
		while (*p && *p != '/')
			p++;
	}
	return n;
}

int bk_page_rel_dir(const char *page_path, const char *dir, char *out, size_t outlen, char *err, size_t errlen)
{
	char page_dir[PATH_MAX], a[PATH_MAX], b[PATH_MAX];
	bk_out_split(page_path, page_dir, sizeof page_dir); /* "/x.html": the root itself */
	const char *bad = !realpath(page_dir, a) ? page_dir : !realpath(dir, b) ? dir : NULL;
	if (bad) {
		snprintf(err, errlen, "%.300s: cannot be resolved: %s", bad, strerror(errno));
		return -1;
	}
	char *ca[PATH_MAX / 2], *cb[PATH_MAX / 2];
	int na = components(a, ca, PATH_MAX / 2), nb = components(b, cb, PATH_MAX / 2), c = 0;
	while (c < na && c < nb && !strcmp(ca[c], cb[c]))
		c++;
	size_t n = 0;
	/* "./" unless the link climbs: a first component such as "javascript:x"
	 * would otherwise be read as a URL scheme (page.h) */
	int k = snprintf(out, outlen, "%s", c == na ? "./" : "");
	n = (size_t)k;
	for (int j = c; j < na && n < outlen; j++)
		n += (size_t)snprintf(out + n, outlen - n, "../");
	for (int j = c; j < nb && n < outlen; j++)
		n += (size_t)snprintf(out + n, outlen - n, "%s/", cb[j]);
	if (n >= outlen) {
		snprintf(err, errlen, "%.300s: path too long", dir);
		return -1;
	}
	return 0;
}
