/*
 * out_manifest.c — an output directory's marker (its format: out_int.h): written,
 * read, and a tree walked against the list it holds (out.h, bk_out_dir_*).
 */
#include "out.h"
#include "out_int.h"

#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* s into b with '\' and newline escaped: one line holds one name. */
void out_put_escaped(bk_strbuf *b, const char *s)
{
	while (*s) {
		size_t k = strcspn(s, "\\\n");
		bk_sb_put(b, "%.*s", (int)k, s);
		s += k;
		if (*s)
			bk_sb_put(b, "%s", *s++ == '\\' ? "\\\\" : "\\n");
	}
}

/* put_escaped undone, in place; -1 at an escape it never writes. */
static int unescape(char *s)
{
	char *w = s;
	for (; *s; s++) {
		if (*s != '\\') {
			*w++ = *s;
			continue;
		}
		s++;
		if (*s != '\\' && *s != 'n')
			return -1;
		*w++ = *s == 'n' ? '\n' : '\\';
	}
	*w = '\0';
	return 0;
}

/* A relative path without empty, "." or ".." components. */
static int valid_rel(const char *p)
{
	if (*p == '/')
		return 0;
	for (;;) {
		size_t k = strcspn(p, "/");
		if (k == 0 || (k == 1 && p[0] == '.') || (k == 2 && p[0] == '.' && p[1] == '.'))
			return 0;
		p += k;
		if (!*p++)
			return 1;
	}
}

static int by_path(const void *a, const void *b)
{
	return strcmp(((const entry *)a)->path, ((const entry *)b)->path);
}

void out_manifest_free(manifest *m)
{
	free(m->text);
	free(m->e);
	memset(m, 0, sizeof *m);
}

/* The type m lists rel with, or 0. */
static char listed(const manifest *m, const char *rel)
{
	entry key = {(char *)rel, 0};
	const entry *e = m->n ? bsearch(&key, m->e, m->n, sizeof *m->e, by_path) : NULL;
	return e ? e->type : 0;
}

/* What m->text (len bytes) is: a complete marker (m->e then lists its
 * entries), one cut short (a building run's, or a killed one's), the format
 * before, or something brdfkit did not write. */
static int marker_parse(manifest *m, size_t len)
{
	char *p = m->text, *end = p + len;
	size_t ml = strlen(MARKER_MAGIC);
	if (memchr(p, '\0', len))
		return MK_FOREIGN;
	if (len <= ml || memcmp(p, MARKER_MAGIC, ml) || p[ml] != '\n') {
		char *nl = memchr(p, '\n', len);
		return len > 8 && !memcmp(p, "brdfkit ", 8) && nl == end - 1 ? MK_OLD : MK_FOREIGN;
	}
	p += ml + 1;
	char *nl = memchr(p, '\n', (size_t)(end - p));
	if (!nl)
		return MK_BUILDING;
	p = nl + 1;
	size_t lines = 0;
	for (char *q = p; (q = memchr(q, '\n', (size_t)(end - q))); q++)
		lines++;
	if (!(m->e = malloc((lines + 1) * sizeof *m->e)))
		return -1;
	for (; p < end; p = nl + 1) {
		if (!(nl = memchr(p, '\n', (size_t)(end - p))))
			return MK_BUILDING; /* a line cut short: a run killed while writing it */
		*nl = '\0';
		if (!strcmp(p, "end"))
			return nl + 1 == end ? MK_COMPLETE : MK_FOREIGN;
		if ((p[0] != 'f' && p[0] != 'd') || p[1] != ' ' || unescape(p + 2) || !valid_rel(p + 2) ||
		    (m->n && strcmp(m->e[m->n - 1].path, p + 2) >= 0))
			return MK_FOREIGN;
		m->e[m->n++] = (entry){p + 2, p[0]};
	}
	return MK_BUILDING;
}

/* The marker open at fd read whole (from offset 0) into m and parsed:
 * marker_parse's kind, or -1 with errno when it cannot be read. */
int out_marker_read(int fd, manifest *m)
{
	memset(m, 0, sizeof *m);
	struct stat st;
	if (fstat(fd, &st) != 0)
		return -1;
	if (!S_ISREG(st.st_mode) || st.st_size > MARKER_MAX)
		return MK_FOREIGN;
	size_t len = 0, cap = (size_t)st.st_size + 1;
	ssize_t r = 0;
	if (!(m->text = malloc(cap)))
		return -1;
	while (len + 1 < cap && (r = pread(fd, m->text + len, cap - 1 - len, (off_t)len)) > 0)
		len += (size_t)r;
	if (r < 0)
		return -1;
	m->text[len] = '\0';
	return marker_parse(m, len);
}

/* ---- output directories: walking a tree against its list ------------------------ */

/* The marker and TEMPS at the top of a tree: the protocol's, not the result's. */
static int protocol_name(const char *prefix, const char *s)
{
	return !*prefix && (!strcmp(s, BK_OUT_MARKER) || !strcmp(s, TEMPS));
}

static void note_unlisted(walk *w, const char *rel)
{
	if (!w->unlisted++ || strcmp(rel, w->first) < 0)
		snprintf(w->first, sizeof w->first, "%s", rel);
}

/* The tree under dfd (at prefix inside it) against w->m: every entry listed
 * with its own type is passed (WALK_REMOVE: removed, a directory after what
 * is in it), every other one counted in w. Descends only into directories
 * listed as such and opened with O_NOFOLLOW, and removes with unlinkat, so a
 * symlink is never followed. Returns 0, or -1 with errno. */
int out_walk_tree(walk *w, int dfd, const char *prefix, int depth)
{
	size_t n = 0;
	char *names = out_dir_names(dfd, &n), rel[4096];
	int rc = names ? 0 : -1;
	for (char *s = names; !rc && n--; s += strlen(s) + 1) {
		if (protocol_name(prefix, s))
			continue;
		struct stat st;
		if (snprintf(rel, sizeof rel, "%s%s%s", prefix, *prefix ? "/" : "", s) >= (int)sizeof rel) {
			note_unlisted(w, rel);
			continue;
		}
		if (fstatat(dfd, s, &st, AT_SYMLINK_NOFOLLOW) != 0) {
			rc = errno == ENOENT ? 0 : -1; /* gone meanwhile: another run removing it too */
			continue;
		}
		char type = S_ISREG(st.st_mode) ? 'f' : S_ISDIR(st.st_mode) ? 'd' : '?';
		if (listed(w->m, rel) != type || (type == 'd' && depth >= TREE_DEPTH)) {
			note_unlisted(w, rel);
			continue;
		}
		if (type == 'd') {
			int c = openat(dfd, s, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
			if (c < 0) {
				rc = errno == ENOENT ? 0 : -1;
				continue;
			}
			rc = out_walk_tree(w, c, rel, depth + 1);
			int e = errno;
			close(c);
			errno = e;
		}
		if (!rc && w->mode == WALK_REMOVE && unlinkat(dfd, s, type == 'd' ? AT_REMOVEDIR : 0) != 0 &&
		    errno != ENOENT && errno != ENOTEMPTY) /* not empty: something unlisted came, and stays */
			rc = -1;
	}
	int e = errno;
	free(names);
	errno = e;
	return rc;
}

/* Removes the tree name (open at dfd) beside or at DIR as m lists it: when it
 * holds nothing else, every listed entry, then TEMPS, the marker and the
 * directory; otherwise nothing, returning 1 with the first unlisted entry in
 * first. 0 when removed, -1 with errno on a failure. */
int out_remove_listed(int pfd, const char *name, int dfd, const manifest *m, char *first, size_t flen)
{
	walk w = {m, WALK_CHECK, 0, ""};
	if (out_walk_tree(&w, dfd, "", 0))
		return -1;
	if (!w.unlisted) {
		w.mode = WALK_REMOVE;
		if (out_walk_tree(&w, dfd, "", 0))
			return -1;
	}
	if (w.unlisted) { /* found by the look, or added since */
		if (first)
			snprintf(first, flen, "%s", w.first);
		return 1;
	}
	unlinkat(dfd, TEMPS, 0);
	unlinkat(dfd, BK_OUT_MARKER, 0);
	return unlinkat(pfd, name, AT_REMOVEDIR) == 0 || errno == ENOENT ? 0 : -1;
}

/* Lists every regular file and directory under dfd into *l (paths malloc'd)
 * and fsyncs each, dfd last: the new tree made durable and its list known in
 * one pass. Anything else (no command makes one) goes unlisted, so a later
 * run refuses the tree rather than delete it. */
typedef struct listing {
	entry *e;
	size_t n, cap;
} listing;

static int list_add(listing *l, const char *rel, char type)
{
	if (l->n == l->cap) {
		size_t cap = l->cap ? 2 * l->cap : 64;
		entry *e = realloc(l->e, cap * sizeof *e);
		if (!e)
			return -1;
		l->e = e;
		l->cap = cap;
	}
	if (!(l->e[l->n].path = strdup(rel)))
		return -1;
	l->e[l->n++].type = type;
	return 0;
}

static int list_tree(listing *l, int dfd, const char *prefix, int depth)
{
	size_t n = 0;
	char *names = out_dir_names(dfd, &n), rel[4096];
	int rc = names ? 0 : -1;
	for (char *s = names; !rc && n--; s += strlen(s) + 1) {
		struct stat st;
		if (protocol_name(prefix, s))
			continue;
		if (snprintf(rel, sizeof rel, "%s%s%s", prefix, *prefix ? "/" : "", s) >= (int)sizeof rel) {
			errno = ENAMETOOLONG;
			rc = -1;
		} else if (fstatat(dfd, s, &st, AT_SYMLINK_NOFOLLOW) != 0) {
			rc = -1;
		} else if (S_ISREG(st.st_mode) || S_ISDIR(st.st_mode)) {
			int c = openat(dfd, s, O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
			if (c < 0)
				rc = -1;
			else if (S_ISDIR(st.st_mode))
				rc = depth >= TREE_DEPTH ? (errno = ELOOP, -1) : list_tree(l, c, rel, depth + 1);
			else
				rc = fsync(c);
			int e = errno;
			if (c >= 0)
				close(c);
			if (!rc && list_add(l, rel, S_ISDIR(st.st_mode) ? 'd' : 'f'))
				rc = -1, e = ENOMEM;
			errno = e;
		}
	}
	int e = errno;
	free(names);
	errno = e;
	return rc ? rc : fsync(dfd);
}

/* The new tree (tfd) made durable and its list, in byte order, appended to
 * its marker (fd, locked, holding the first two lines) and flushed. */
int out_write_list(int fd, int tfd)
{
	listing l = {0};
	int rc = list_tree(&l, tfd, "", 0), e = errno;
	if (!rc) {
		bk_strbuf b = {0};
		qsort(l.e, l.n, sizeof *l.e, by_path);
		for (size_t k = 0; k < l.n; k++) {
			bk_sb_put(&b, "%c ", l.e[k].type);
			out_put_escaped(&b, l.e[k].path);
			bk_sb_put(&b, "\n");
		}
		bk_sb_put(&b, "end\n");
		if (b.oom)
			rc = -1, e = ENOMEM;
		else if (lseek(fd, 0, SEEK_END) < 0 || bk_out_write_all(fd, b.s, b.len) || fsync(fd))
			rc = -1, e = errno;
		free(b.s);
	}
	for (size_t k = 0; k < l.n; k++)
		free(l.e[k].path);
	free(l.e);
	errno = e;
	return rc;
}
