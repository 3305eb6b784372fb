/*
 * out_file.c — atomic single files (a temporary beside the path, named by its
 * inode, fsync'd and renamed into place), the leftovers of dead runs removed,
 * a file the user names replaced only when brdfkit wrote it, inputs opened
 * without blocking, and the files of a tree being built (out.h).
 */
#define _GNU_SOURCE /* O_TMPFILE, renameat2, flock: Linux; each has a fallback or is checked */
#include "out.h"
#include "out_int.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---- single files ------------------------------------------------------------- */

/* The six letters that end a temporary's name ("X.tmpXXXXXX"), computed from
 * its inode number (splitmix64's finaliser, in [A-Za-z0-9]): they prove to a
 * later run that brdfkit made the file under that name. A user's copy is
 * another inode, a file the user renamed has another name; either matches by
 * chance once in 62^6 (5.7e10). The writer holds flock(LOCK_EX) on the file
 * until it is renamed into place, so a temporary whose lock can be taken
 * belongs to a dead run. */
static void inode_tag(ino_t ino, char tag[7])
{
	static const char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789";
	uint64_t x = (uint64_t)ino + 0x9e3779b97f4a7c15u;
	x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9u;
	x = (x ^ (x >> 27)) * 0x94d049bb133111ebu;
	x ^= x >> 31;
	for (int k = 0; k < 6; k++, x /= 62)
		tag[k] = digits[x % 62];
	tag[6] = '\0';
}

/* Removes from dir the temporaries of base that dead runs left: a regular
 * file named base.tmpXXXXXX with its inode's letters and a free lock. Anything
 * else so named (a user's file, a live run's temporary) stays. */
static int clean_file_leftovers(const char *dir, const char *base)
{
	int dfd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC), removed = 0;
	if (dfd < 0)
		return 0;
	size_t n = 0;
	char *names = out_dir_names(dfd, &n);
	for (char *s = names; s && n--; s += strlen(s) + 1) {
		const char *x = out_temp_letters(s, base, "tmp");
		int fd = x ? openat(dfd, s, O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC) : -1;
		if (fd < 0)
			continue;
		struct stat st, now;
		char tag[7] = "";
		if (fstat(fd, &st) == 0 && S_ISREG(st.st_mode))
			inode_tag(st.st_ino, tag);
		if (!strcmp(tag, x) && flock(fd, LOCK_EX | LOCK_NB) == 0 &&
		    fstatat(dfd, s, &now, AT_SYMLINK_NOFOLLOW) == 0 && now.st_ino == st.st_ino && now.st_dev == st.st_dev &&
		    unlinkat(dfd, s, 0) == 0)
			removed++;
		close(fd);
	}
	free(names);
	close(dfd);
	return removed;
}

int bk_out_clean(const char *path)
{
	char dir[4096];
	return clean_file_leftovers(dir, bk_out_split(path, dir, sizeof dir));
}

/* The temporary for o->path in dir, locked and named with its inode's letters
 * from the start: made unnamed (O_TMPFILE) and linked in, so that it never
 * exists under another name; where the file system has no O_TMPFILE, made by
 * mkstemp and renamed (a kill between the two leaves a name no run can
 * prove, which then stays). Returns the descriptor, or -1 with errno. */
static int make_temp(bk_out *o, const char *dir)
{
	char tag[7], proc[64], named[sizeof o->tmp];
	struct stat st;
	int fd = open(dir, O_TMPFILE | O_RDWR | O_CLOEXEC, 0666);
	if (fd >= 0) {
		snprintf(proc, sizeof proc, "/proc/self/fd/%d", fd);
		if (flock(fd, LOCK_EX) == 0 && fstat(fd, &st) == 0) {
			inode_tag(st.st_ino, tag);
			snprintf(o->tmp, sizeof o->tmp, "%s.tmp%s", o->path, tag);
			o->slot = bk_out_track(o->tmp, 0);
			if (linkat(AT_FDCWD, proc, AT_FDCWD, o->tmp, AT_SYMLINK_FOLLOW) == 0)
				return fd;
			bk_out_untrack(o->slot);
			o->slot = -1;
		}
		close(fd);
	} else if (errno != EOPNOTSUPP && errno != EISDIR && errno != EINVAL) {
		return -1;
	}
	snprintf(o->tmp, sizeof o->tmp, "%s.tmpXXXXXX", o->path);
	fd = mkostemp(o->tmp, O_CLOEXEC);
	if (fd < 0)
		return -1;
	o->slot = bk_out_track(o->tmp, 0);
	mode_t um = umask(0); /* mkstemp creates 0600; give the file the mode a plain fopen would */
	umask(um);
	fchmod(fd, 0666 & ~um);
	if (flock(fd, LOCK_EX) == 0 && fstat(fd, &st) == 0) {
		inode_tag(st.st_ino, tag);
		snprintf(named, sizeof named, "%s.tmp%s", o->path, tag);
		if (renameat2(AT_FDCWD, o->tmp, AT_FDCWD, named, RENAME_NOREPLACE) == 0) {
			bk_out_untrack(o->slot);
			strcpy(o->tmp, named);
			o->slot = bk_out_track(o->tmp, 0);
		}
	}
	return fd;
}

int bk_out_open(bk_out *o, const char *path, char *err, size_t errlen)
{
	char sp[1024]; /* path in messages: where it goes, not its build tree's name */
	o->f = NULL;
	o->slot = -1;
	o->guard = 0;
	o->tmp[0] = '\0';
	if (strlen(path) >= sizeof o->path) {
		snprintf(err, errlen, "%.64s...: path too long", path);
		return -1;
	}
	strcpy(o->path, path);
	char dir[4096];
	clean_file_leftovers(dir, bk_out_split(path, dir, sizeof dir));
	int fd = make_temp(o, dir);
	if (fd < 0) {
		int e = errno;
		snprintf(err, errlen, "%s: cannot create: %s", bk_out_shown(path, sp, sizeof sp), bk_out_errtext(e));
		return -1;
	}
	o->f = fdopen(fd, "w");
	if (!o->f) {
		int e = errno;
		snprintf(err, errlen, "%s: %s", bk_out_shown(path, sp, sizeof sp), bk_out_errtext(e));
		close(fd);
		unlink(o->tmp);
		bk_out_untrack(o->slot);
		return -1;
	}
	return 0;
}

/* fsync of the directory holding path, so that its last rename survives a
 * crash. A directory that cannot be opened (no read permission) cannot be
 * synced and is passed over; a failed fsync is an error (-1, errno). */
static int sync_parent(const char *path)
{
	char dir[4096];
	bk_out_split(path, dir, sizeof dir);
	int fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
	if (fd < 0)
		return 0;
	int rc = fsync(fd), e = errno;
	close(fd);
	errno = e;
	return rc;
}

/* The commit of bk_out_commit and bk_out_commit_held: with held, the locked
 * descriptor of the file now at path goes to *held (-1 on a failure). */
static int commit(bk_out *o, int *held, char *err, size_t errlen)
{
	/* fsync before rename: otherwise a crash can leave path naming an empty
	 * file. The lock stays (on a duplicate) until the rename: a run that
	 * could take it would count the temporary as a dead run's. */
	char sp[1024];
	int bad = fflush(o->f) != 0 || ferror(o->f) || fsync(fileno(o->f)) != 0;
	int e = errno, keep = fcntl(fileno(o->f), F_DUPFD_CLOEXEC, 0);
	if (held)
		*held = -1;
	if (fclose(o->f) != 0 || bad) {
		e = bad ? e : errno;
		snprintf(err, errlen, "%s: write failed: %s", bk_out_shown(o->path, sp, sizeof sp), bk_out_errtext(e));
		o->f = NULL;
		unlink(o->tmp);
		bk_out_untrack(o->slot);
		if (keep >= 0)
			close(keep);
		return -1;
	}
	o->f = NULL;
	/* a user's file put at path while we wrote is not ours to replace either */
	if (o->guard && bk_out_file_check(o->path, err, errlen)) {
		unlink(o->tmp);
		bk_out_untrack(o->slot);
		if (keep >= 0)
			close(keep);
		return -1;
	}
	int moved = rename(o->tmp, o->path) == 0;
	e = errno;
	if (!moved)
		unlink(o->tmp);
	bk_out_untrack(o->slot);
	if (moved && held)
		*held = keep;
	else if (keep >= 0)
		close(keep);
	if (!moved) {
		snprintf(err, errlen, "%s: cannot rename into place: %s", bk_out_shown(o->path, sp, sizeof sp), bk_out_errtext(e));
		return -1;
	}
	if (sync_parent(o->path)) {
		snprintf(err, errlen, "%s: written, but the fsync of its directory failed: %s (it may not survive a crash)",
		         bk_out_shown(o->path, sp, sizeof sp), bk_out_errtext(errno));
		return -1;
	}
	return 0;
}

int bk_out_commit(bk_out *o, char *err, size_t errlen)
{
	return commit(o, NULL, err, errlen);
}

int bk_out_commit_held(bk_out *o, int *held, char *err, size_t errlen)
{
	return commit(o, held, err, errlen);
}

void bk_out_abort(bk_out *o)
{
	if (o->f)
		fclose(o->f);
	o->f = NULL;
	if (o->tmp[0])
		unlink(o->tmp);
	bk_out_untrack(o->slot);
}

/* ---- files of a tree being built ---------------------------------------------- */

FILE *bk_out_fopen(const char *path, char *err, size_t errlen)
{
	FILE *f = fopen(path, "w");
	if (!f) {
		int e = errno;
		char p[1024];
		snprintf(err, errlen, "%s: cannot create: %s", bk_out_shown(path, p, sizeof p), bk_out_errtext(e));
		return NULL;
	}
	errno = 0; /* so that the errno bk_out_fclose finds beside ferror is a write's */
	return f;
}

int bk_out_fclose(FILE *f, const char *path, char *err, size_t errlen)
{
	/* stdio keeps no errno with its error flag: the failed write(2) set it,
	 * and the formatting since (printf's) leaves it as it is */
	int e = ferror(f) ? (errno ? errno : EIO) : 0;
	errno = 0;
	if (fclose(f) != 0 && !e)
		e = errno ? errno : EIO;
	if (!e)
		return 0;
	char p[1024];
	snprintf(err, errlen, "%s: cannot write: %s", bk_out_shown(path, p, sizeof p), bk_out_errtext(e));
	return -1;
}

/* ---- a single file the user names -------------------------------------------- */

/* How each single-file output says that brdfkit wrote it, at the start of one
 * of its first lines: generated code's comment (codegen: line 2), the '#'
 * header of the CSVs (albedo, gpucost and its --calibrate, time: line 1) and
 * the page's title (report: line 3). A checkpoint ("brdfkit-search ...") is
 * not among them: it is state, not a result to write over. */
static const char *const signed_lines[] = {" * Generated by brdfkit ", "# brdfkit ", "<title>brdfkit ", NULL};
#define SIGNED_LINES 3

static int signed_by_brdfkit(int fd)
{
	char buf[4096];
	ssize_t n = pread(fd, buf, sizeof buf - 1, 0);
	if (n <= 0)
		return 0;
	buf[n] = '\0';
	const char *p = buf;
	for (int line = 0; line < SIGNED_LINES && p; line++) {
		for (const char *const *s = signed_lines; *s; s++)
			if (!strncmp(p, *s, strlen(*s)))
				return 1;
		if ((p = strchr(p, '\n')))
			p++;
	}
	return 0;
}

/* The directory holding path, or one above it, holds BK_OUT_MARKER: the
 * nearest such into at (resolved), 1; 0 when none does (or the directory
 * does not exist, which bk_out_open reports). */
static int inside_output(const char *path, char *at, size_t len)
{
	char dir[4096], real[PATH_MAX], m[PATH_MAX + 32];
	bk_out_split(path, dir, sizeof dir);
	if (!realpath(dir, real))
		return 0;
	for (;;) {
		struct stat st;
		snprintf(m, sizeof m, "%s/" BK_OUT_MARKER, strcmp(real, "/") ? real : "");
		if (lstat(m, &st) == 0) {
			snprintf(at, len, "%s", real);
			return 1;
		}
		char *slash = strrchr(real, '/');
		if (!slash || !strcmp(real, "/"))
			return 0;
		slash[slash == real] = '\0'; /* "/a" -> "/" */
	}
}

int bk_out_file_check(const char *path, char *err, size_t errlen)
{
	char p[512], at[PATH_MAX], q[512];
	struct stat st;
	out_printable(path, p, sizeof p);
	if (!*path || strlen(path) >= 4096 - 16) {
		snprintf(err, errlen, "%.64s: %s", p, *path ? "path too long" : "empty path");
		return -1;
	}
	if (inside_output(path, at, sizeof at)) {
		snprintf(err, errlen, "%s: inside %s, a directory brdfkit writes whole (its next run would refuse or "
		         "delete the file); choose a path outside it", p, out_printable(at, q, sizeof q));
		return -1;
	}
	if (lstat(path, &st) != 0) /* nothing there, or no directory: bk_out_open says so */
		return 0;
	if (S_ISLNK(st.st_mode)) {
		snprintf(err, errlen, "%s: is a symlink (not followed, not replaced); give the file itself or another path", p);
		return -1;
	}
	if (!S_ISREG(st.st_mode)) {
		snprintf(err, errlen, "%s: exists and is %s (not replaced); choose another path", p,
		         S_ISDIR(st.st_mode) ? "a directory" : "not a regular file");
		return -1;
	}
	if (st.st_size == 0) /* nothing to lose: a touched file, a killed shell redirect */
		return 0;
	int fd = open(path, O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
	int ours = fd >= 0 && signed_by_brdfkit(fd);
	int e = errno;
	if (fd >= 0)
		close(fd);
	if (fd < 0)
		snprintf(err, errlen, "%s: exists and cannot be read to tell whether brdfkit wrote it: %s (not replaced)", p,
		         bk_out_errtext(e));
	else if (!ours)
		snprintf(err, errlen, "%s: " NOT_OURS " (not replaced); choose another path or remove it", p);
	return fd >= 0 && ours ? 0 : -1;
}

int bk_out_open_file(bk_out *o, const char *path, char *err, size_t errlen)
{
	o->f = NULL;
	o->slot = -1;
	o->tmp[0] = '\0';
	o->guard = 0;
	if (bk_out_file_check(path, err, errlen) || bk_out_open(o, path, err, errlen))
		return -1;
	o->guard = 1;
	return 0;
}

/* ---- inputs ----------------------------------------------------------------- */

int bk_in_open(const char *path, char *why, size_t len)
{
	/* O_NONBLOCK: a FIFO with no writer would block the open itself */
	int fd = open(path, O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
	struct stat st;
	if (fd < 0 || fstat(fd, &st) != 0) {
		int e = errno;
		snprintf(why, len, "%s", bk_out_errtext(e));
		if (fd >= 0)
			close(fd);
		errno = e;
		return -1;
	}
	if (!S_ISREG(st.st_mode)) {
		snprintf(why, len, "%s", S_ISDIR(st.st_mode) ? "is a directory"
		                         : S_ISFIFO(st.st_mode) ? "not a regular file (a FIFO)"
		                         : S_ISCHR(st.st_mode) ? "not a regular file (a character device)"
		                         : S_ISBLK(st.st_mode) ? "not a regular file (a block device)"
		                                               : "not a regular file");
		close(fd);
		return -2;
	}
	int fl = fcntl(fd, F_GETFL);
	if (fl < 0 || fcntl(fd, F_SETFL, fl & ~O_NONBLOCK) != 0) {
		int e = errno;
		snprintf(why, len, "%s", bk_out_errtext(e));
		close(fd);
		errno = e;
		return -1;
	}
	return fd;
}
