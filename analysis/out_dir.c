/*
 * out_dir.c — output directories replaced whole and only when brdfkit wrote
 * them: what stands at --out, the leftovers of killed runs beside it, and the
 * build tree begun and aborted (out.h; the swap: out_swap.c).
 */
#define _GNU_SOURCE /* flock, realpath */
#include "out.h"
#include "out_int.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

void out_look_done(look *k)
{
	if (k->mfd >= 0)
		close(k->mfd);
	k->mfd = -1;
	out_manifest_free(&k->m);
}

static int dir_is_empty(int fd)
{
	size_t n = 1;
	char *names = out_dir_names(fd, &n);
	free(names);
	return names && n == 0;
}

/* flock(LOCK_EX) on DIR's marker. Another run holds it only while it swaps DIR
 * and removes the previous result (milliseconds); held after 2 s, it is held
 * by something else (a stopped run, a user's flock), and the wait is said on
 * stderr, once. The run then waits on without a bound: giving up would throw
 * away the finished work, the holder may be a run that is only stopped, and
 * SIGINT still ends the wait and removes the temporaries. */
static int lock_marker(int fd, const char *shown)
{
	for (int k = 0; k < 40; k++) {
		if (flock(fd, LOCK_EX | LOCK_NB) == 0)
			return 0;
		if (errno != EWOULDBLOCK && errno != EINTR)
			return -1;
		nanosleep(&(struct timespec){0, 50000000}, NULL);
	}
	char p[512];
	out_notice("--out %s: another brdfkit is writing it (its " BK_OUT_MARKER " is locked); waiting for it to finish",
	       out_printable(shown, p, sizeof p));
	while (flock(fd, LOCK_EX) != 0)
		if (errno != EINTR)
			return -1;
	return 0;
}

static int looked(look *k, int kind)
{
	k->kind = kind;
	if (kind == DIR_ERROR)
		k->err = errno;
	return kind;
}

/* What stands at name in pfd, into k: nothing, an empty directory, brdfkit's
 * directory holding only what its marker lists (k->m), or one that may not be
 * replaced (foreign, the old marker format, an unlisted entry). shown: NULL to
 * look only; else the marker is locked first (k->mfd, the directory checked
 * to be still at name then) and shown names DIR in the line of a long wait. */
int out_classify(int pfd, const char *name, const char *shown, look *k)
{
	memset(k, 0, offsetof(look, first));
	k->mfd = -1;
	k->first[0] = '\0';
	struct stat st, now;
	if (fstatat(pfd, name, &st, AT_SYMLINK_NOFOLLOW) != 0)
		return looked(k, errno == ENOENT ? DIR_ABSENT : DIR_ERROR);
	k->link = S_ISLNK(st.st_mode);
	if (!S_ISDIR(st.st_mode))
		return looked(k, DIR_FOREIGN);
	int dfd = openat(pfd, name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
	if (dfd < 0)
		return looked(k, errno == ENOENT || errno == ELOOP || errno == ENOTDIR ? DIR_RETRY : DIR_ERROR);
	int r, m = openat(dfd, BK_OUT_MARKER, O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
	if (m < 0) {
		int e = errno;
		k->marker = e == ELOOP;
		r = e == ENOENT || e == ELOOP ? (dir_is_empty(dfd) ? DIR_EMPTY : DIR_FOREIGN) : (errno = e, DIR_ERROR);
	} else if (fstat(m, &now) != 0 || !S_ISREG(now.st_mode)) {
		r = DIR_FOREIGN;
		k->marker = 1;
	} else if (shown && lock_marker(m, shown) != 0) {
		r = DIR_ERROR;
	} else if (shown && !(fstatat(pfd, name, &now, AT_SYMLINK_NOFOLLOW) == 0 && now.st_ino == st.st_ino &&
	                      now.st_dev == st.st_dev && fstat(m, &now) == 0 && now.st_nlink > 0)) {
		r = DIR_RETRY; /* swapped or removed while we waited */
	} else {
		int kind = out_marker_read(m, &k->m);
		walk w = {&k->m, WALK_CHECK, 0, ""};
		k->marker = 1;
		if (kind < 0)
			r = DIR_ERROR;
		else if (kind == MK_OLD)
			r = DIR_OLD;
		else if (kind != MK_COMPLETE)
			r = DIR_FOREIGN;
		else if (out_walk_tree(&w, dfd, "", 0))
			r = DIR_ERROR;
		else if (w.unlisted)
			r = DIR_UNLISTED, snprintf(k->first, sizeof k->first, "%s", w.first);
		else
			r = DIR_OURS;
	}
	looked(k, r);
	close(dfd);
	if (m >= 0 && shown && r == DIR_OURS)
		k->mfd = m;
	else if (m >= 0)
		close(m);
	if (r != DIR_OURS)
		out_manifest_free(&k->m);
	return r;
}

/* The one line for a directory k says may not be replaced, or for a failure
 * (doing: "cannot create", "cannot replace"). */
void out_refusal(const look *k, const char *given, const char *doing, char *err, size_t errlen)
{
	char p[512];
	switch (k->kind) {
	case DIR_FOREIGN:
		if (k->link) { /* one to brdfkit's directory too: the swap would replace the link, not DIR */
			snprintf(err, errlen, "%s: is a symlink: give the directory itself (a symlink is never followed)",
			         given);
			break;
		}
		snprintf(err, errlen, "%s: " NOT_OURS "%s; choose another path or remove it", given,
		         k->marker ? " (its " BK_OUT_MARKER " is not one brdfkit wrote)" : "");
		break;
	case DIR_OLD:
		snprintf(err, errlen, "%s: was written by an older brdfkit, whose " BK_OUT_MARKER
		         " lists no files; remove it yourself or choose another path", given);
		break;
	case DIR_UNLISTED:
		snprintf(err, errlen, "%s: holds '%s', which brdfkit did not write; move it or choose another --out", given,
		         out_printable(k->first, p, sizeof p));
		break;
	default:
		snprintf(err, errlen, "%s: %s: %s", given, doing, bk_out_errtext(k->err ? k->err : EAGAIN));
	}
}

/* "a/b/" -> "a/b"; "/" stays. */
static void strip_slashes(char *p)
{
	size_t n = strlen(p);
	while (n > 1 && p[n - 1] == '/')
		p[--n] = '\0';
}

/* Splits a stripped path into its parent directory (opened) and last name. */
int out_open_parent(const char *path, const char **base)
{
	char dir[4096];
	*base = bk_out_split(path, dir, sizeof dir);
	return open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
}

int bk_out_dir_check(const char *given, char *err, size_t errlen)
{
	char path[4096];
	if (!*given || strlen(given) >= sizeof path - 16) {
		snprintf(err, errlen, "%.64s: %s", given, *given ? "path too long" : "empty path");
		return -1;
	}
	strcpy(path, given);
	strip_slashes(path);
	/* the current directory, one of its parents or /: a rename would empty
	 * the ground the user stands on, whatever it holds */
	char real[PATH_MAX], cwd[PATH_MAX];
	if (realpath(path, real) && realpath(".", cwd)) {
		size_t n = strlen(real);
		if (!strcmp(real, "/") || (!strncmp(cwd, real, n) && (cwd[n] == '\0' || cwd[n] == '/'))) {
			snprintf(err, errlen, "%s: is the current directory or one of its parents; choose another path", given);
			return -1;
		}
	}
	const char *base;
	int pfd = out_open_parent(path, &base);
	if (!strcmp(base, ".") || !strcmp(base, "..")) {
		if (pfd >= 0)
			close(pfd);
		snprintf(err, errlen, "%s: ends in '.' or '..'; name the output directory itself", given);
		return -1;
	}
	if (pfd < 0) {
		snprintf(err, errlen, "%s: cannot create: %s", given, bk_out_errtext(errno));
		return -1;
	}
	look k;
	int r = out_classify(pfd, base, NULL, &k);
	if (r != DIR_FOREIGN && r != DIR_OLD && r != DIR_UNLISTED && r != DIR_ERROR &&
	    faccessat(pfd, ".", W_OK | X_OK, 0) != 0)
		r = looked(&k, DIR_ERROR);
	close(pfd);
	int bad = r == DIR_FOREIGN || r == DIR_OLD || r == DIR_UNLISTED || r == DIR_ERROR;
	if (bad)
		out_refusal(&k, given, "cannot create", err, errlen);
	out_look_done(&k);
	return bad ? -1 : 0;
}

/* The tree open at dfd: the name its TEMPS records (see the marker's comment)
 * into name, 0; -1 when it has none of the form base.tmpXXXXXX. */
static int read_temps(int dfd, const char *base, char name[300])
{
	char buf[320];
	struct stat st;
	int fd = openat(dfd, TEMPS, O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
	ssize_t n = fd >= 0 && fstat(fd, &st) == 0 && S_ISREG(st.st_mode) ? read(fd, buf, sizeof buf - 1) : -1;
	if (fd >= 0)
		close(fd);
	if (n <= 0)
		return -1;
	buf[n] = '\0';
	char *nl = strchr(buf, '\n');
	if (!nl || nl[1] || (*nl = '\0', !out_temp_letters(buf, base, "tmp")) || strlen(buf) >= 300)
		return -1;
	strcpy(name, buf);
	return 0;
}

/* Names a run may remove beside DIR, each with whether its TEMPS names itself. */
typedef struct leftovers {
	char name[64][300];
	char own[64];
	int n;
} leftovers;

static void add_leftover(leftovers *c, const char *name, int own)
{
	for (int k = 0; k < c->n; k++)
		if (!strcmp(c->name[k], name)) {
			c->own[k] |= (char)own;
			return;
		}
	if (c->n < 64 && strlen(name) < sizeof c->name[0]) {
		strcpy(c->name[c->n], name);
		c->own[c->n++] = (char)own;
	}
}

/* A recorded build name R and its "old" twin (the fallback swap's aside). */
static void add_record(leftovers *c, const char *rec, const char *base, int own)
{
	char old[300];
	add_leftover(c, rec, own);
	snprintf(old, sizeof old, "%s", rec);
	memcpy(old + strlen(base) + 1, "old", 3);
	add_leftover(c, old, 0);
}

/* Whether the tree open at dfd carries a complete marker. */
static int has_complete_marker(int dfd)
{
	manifest m;
	int fd = openat(dfd, BK_OUT_MARKER, O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
	int kind = fd >= 0 ? out_marker_read(fd, &m) : -1;
	if (fd >= 0) {
		out_manifest_free(&m);
		close(fd);
	}
	return kind == MK_COMPLETE;
}

/* Removes one candidate when its run is dead (the lock on its marker can be
 * taken): a complete tree as its marker lists it, if it holds nothing else; a
 * tree whose run was killed while building (own: its TEMPS names it) whole;
 * an empty directory (a removal cut short). Anything else stays. */
static void remove_leftover(int pfd, const char *name, int own)
{
	int dfd = openat(pfd, name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
	if (dfd < 0)
		return;
	int fd = openat(dfd, BK_OUT_MARKER, O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
	if (fd < 0) {
		if (errno == ENOENT && dir_is_empty(dfd))
			unlinkat(pfd, name, AT_REMOVEDIR);
	} else if (flock(fd, LOCK_EX | LOCK_NB) == 0) {
		manifest m;
		int kind = out_marker_read(fd, &m);
		if (kind == MK_COMPLETE)
			out_remove_listed(pfd, name, dfd, &m, NULL, 0);
		else if (kind == MK_BUILDING && own)
			out_rm_at(pfd, name, BK_OUT_MARKER, 0);
		out_manifest_free(&m);
	}
	if (fd >= 0)
		close(fd);
	close(dfd);
}

/* Removes what killed runs left beside DIR, and only what brdfkit recorded:
 * the previous result DIR's TEMPS names (its run died before removing it),
 * and build trees whose TEMPS names themselves (their runs died before the
 * swap), with their "old" twins. A user's DIR.old2024 or a copy at
 * DIR.tmpABCDEF records no such name and stays. */
static void clean_leftovers(int pfd, const char *base)
{
	leftovers c = {.n = 0};
	char rec[300];
	int dfd = openat(pfd, base, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
	if (dfd >= 0) {
		if (has_complete_marker(dfd) && read_temps(dfd, base, rec) == 0)
			add_record(&c, rec, base, 0);
		close(dfd);
	}
	size_t n = 0;
	char *names = out_dir_names(pfd, &n);
	for (char *s = names; s && n--; s += strlen(s) + 1) {
		if (!out_temp_letters(s, base, "tmp") || (dfd = openat(pfd, s, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC)) < 0)
			continue;
		if (read_temps(dfd, base, rec) == 0 && !strcmp(rec, s))
			add_record(&c, rec, base, 1);
		close(dfd);
	}
	free(names);
	for (int k = 0; k < c.n; k++)
		remove_leftover(pfd, c.name[k], c.own[k]);
}

int bk_out_dir_begin(bk_out_dir *d, const char *given, const char *command, char *err, size_t errlen)
{
	d->lock = -1;
	d->slot = -1;
	d->tmp[0] = '\0';
	if (bk_out_dir_check(given, err, errlen))
		return -1;
	snprintf(d->name, sizeof d->name, "%s", given);
	snprintf(d->path, sizeof d->path, "%s", given);
	strip_slashes(d->path);
	const char *base;
	int pfd = out_open_parent(d->path, &base);
	if (pfd < 0) {
		snprintf(err, errlen, "%s: cannot create: %s", given, bk_out_errtext(errno));
		return -1;
	}
	clean_leftovers(pfd, base);
	close(pfd);
	bk_strbuf head = {0};
	bk_sb_put(&head, MARKER_MAGIC "\n");
	out_put_escaped(&head, command ? command : bk_out_command());
	bk_sb_put(&head, "\n");
	if (head.oom) {
		free(head.s);
		snprintf(err, errlen, "%s: cannot create: %s", given, bk_out_errtext(ENOMEM));
		return -1;
	}
	/* The marker is created under another name, locked, then renamed into
	 * place: a scan never finds an unlocked marker in a live directory.
	 * TEMPS comes after it, so a tree whose TEMPS names itself has its
	 * marker until its removal. Should the directory vanish before (a
	 * cleaner's rmdir of an empty directory whose name was recorded): start
	 * again. */
	int rc = -1, e = EAGAIN;
	for (int tries = 0; rc && tries < 8; tries++) {
		snprintf(d->tmp, sizeof d->tmp, "%s.tmpXXXXXX", d->path);
		if (!mkdtemp(d->tmp)) {
			e = errno;
			break;
		}
		const char *tbase = strrchr(d->tmp, '/') ? strrchr(d->tmp, '/') + 1 : d->tmp;
		d->slot = bk_out_track(d->tmp, 1);
		mode_t um = umask(0); /* mkdtemp makes 0700; give DIR the mode mkdir would */
		umask(um);
		chmod(d->tmp, 0777 & ~um);
		int dfd = open(d->tmp, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
		int m = dfd < 0 ? -1 : openat(dfd, MARKER_NEW, O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
		int t = -1;
		int ok = m >= 0 && flock(m, LOCK_EX) == 0 && bk_out_write_all(m, head.s, head.len) == 0 &&
		         renameat(dfd, MARKER_NEW, dfd, BK_OUT_MARKER) == 0 &&
		         (t = openat(dfd, TEMPS, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666)) >= 0 &&
		         bk_out_write_all(t, tbase, strlen(tbase)) == 0 && bk_out_write_all(t, "\n", 1) == 0;
		e = errno;
		if (t >= 0 && close(t) != 0 && ok)
			ok = 0, e = errno;
		if (dfd >= 0)
			close(dfd);
		if (ok) {
			d->lock = m;
			rc = 0;
			break;
		}
		if (m >= 0)
			close(m);
		bk_out_untrack(d->slot);
		d->slot = -1;
		if (e == ENOENT && m < 0)
			continue;
		out_rm_at(AT_FDCWD, d->tmp, NULL, 0);
		break;
	}
	free(head.s);
	if (rc) {
		d->tmp[0] = '\0';
		snprintf(err, errlen, "%s: cannot create: %s", given,
		         e == ENOENT ? "its temporary directory kept vanishing" : bk_out_errtext(e));
	}
	return rc;
}

void bk_out_dir_abort(bk_out_dir *d)
{
	if (d->tmp[0])
		out_rm_at(AT_FDCWD, d->tmp, BK_OUT_MARKER, 0);
	bk_out_untrack(d->slot);
	if (d->lock >= 0)
		close(d->lock);
	d->lock = -1;
	d->slot = -1;
	d->tmp[0] = '\0';
}
