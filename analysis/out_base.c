/*
 * out_base.c — what every file of the out module shares: the one error text,
 * a path's directory and name, a whole write, a directory's names and a name
 * made printable (out.h, out_int.h).
 */
#include "out.h"
#include "out_int.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

const char *bk_out_errtext(int e)
{
	/* thread-local: threads that write report their own failures; the
	 * capital is lowered only before a lowercase letter, so that an
	 * acronym ("RPC ...") stays as the C library spells it */
	static _Thread_local char buf[128];
	snprintf(buf, sizeof buf, "%s", strerror(e));
	if (buf[0] >= 'A' && buf[0] <= 'Z' && buf[1] >= 'a' && buf[1] <= 'z')
		buf[0] = (char)(buf[0] - 'A' + 'a');
	return buf;
}

/* "a/b/c" -> dir "a/b", returns "c"; "c" -> ".", "c"; "/c" -> "/", "c". */
const char *bk_out_split(const char *path, char *dir, size_t len)
{
	const char *slash = strrchr(path, '/');
	if (!slash) {
		snprintf(dir, len, ".");
		return path;
	}
	snprintf(dir, len, "%.*s", slash == path ? 1 : (int)(slash - path), path);
	return slash + 1;
}

int bk_out_write_all(int fd, const void *buf, size_t n)
{
	const char *s = buf;
	while (n) {
		ssize_t k = write(fd, s, n);
		if (k < 0 && errno == EINTR)
			continue;
		if (k <= 0)
			return -1;
		s += k;
		n -= (size_t)k;
	}
	return 0;
}

/* The names in dfd ("." and ".." left out), malloc'd one after another
 * ("a\0b\0"), *count of them; NULL with errno on failure. */
char *out_dir_names(int dfd, size_t *count)
{
	int fd = fcntl(dfd, F_DUPFD_CLOEXEC, 0);
	DIR *d = fd >= 0 ? fdopendir(fd) : NULL;
	if (!d) {
		if (fd >= 0)
			close(fd);
		return NULL;
	}
	rewinddir(d); /* the duplicate shares dfd's offset, which an earlier read moved */
	bk_strbuf b = {0};
	size_t n = 0;
	struct dirent *e;
	for (errno = 0; (e = readdir(d)); errno = 0)
		if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) {
			bk_sb_put(&b, "%s%c", e->d_name, '\0');
			n++;
		}
	int err = errno ? errno : b.oom ? ENOMEM : 0;
	closedir(d);
	if (!err && !b.s)
		b.s = calloc(1, 1);
	if (err || !b.s) {
		free(b.s);
		errno = err ? err : ENOMEM;
		return NULL;
	}
	*count = n;
	return b.s;
}

/* s for a one-line message: control characters shown as '?'. */
const char *out_printable(const char *s, char *buf, size_t len)
{
	size_t k = 0;
	for (; *s && k + 1 < len; s++)
		buf[k++] = (unsigned char)*s < 0x20 || *s == 0x7f ? '?' : *s;
	buf[k] = '\0';
	return buf;
}

/* The six letters and digits after "BASE.KIND" in entry (KIND "tmp" or "old"),
 * or NULL when entry is not so named. */
const char *out_temp_letters(const char *entry, const char *base, const char *kind)
{
	size_t n = strlen(base);
	if (!n || strncmp(entry, base, n) || entry[n] != '.' || strncmp(entry + n + 1, kind, 3))
		return NULL;
	const char *x = entry + n + 4;
	if (strlen(x) != 6)
		return NULL;
	for (const char *c = x; *c; c++)
		if (!((*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') || (*c >= '0' && *c <= '9')))
			return NULL;
	return x;
}
