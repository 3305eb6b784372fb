/*
 * out.c — what every writer of results shares: atomic output files (a
 * temporary beside the path, fsync'd and renamed into place on success),
 * output directories replaced whole and only when brdfkit wrote them, the
 * removal of live temporaries on a signal, CSV and HTML escaping, and names
 * as file names.
 */
#define _GNU_SOURCE /* renameat2, getdents64, flock: Linux; each has a fallback or is checked */
#include "out.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

/* strerror, lowercased so that every message reads "what: detail". */
static const char *errtext(int e)
{
	static char buf[128];
	snprintf(buf, sizeof buf, "%s", strerror(e));
	if (buf[0] >= 'A' && buf[0] <= 'Z')
		buf[0] = (char)(buf[0] - 'A' + 'a');
	return buf;
}

/* ---- the registry of live temporaries and the signal handler ----------------- */

/* Async-signal safety: the handler reads only this static table and calls only
 * functions POSIX lists as async-signal-safe (kill, waitpid, unlink, openat,
 * unlinkat, close, lseek, strcmp, signal, sigprocmask, raise, _exit) plus
 * getdents64, glibc's bare wrapper of the system call. A slot's path is written completely before its state
 * is set (volatile sig_atomic_t, with a fence), and cleared state first, so
 * the handler never reads a half-written path; at worst it removes a path a
 * commit has just renamed away, which names nothing then (or the old result
 * a commit was about to remove anyway). No malloc, no stdio, no locks. */
#define LIVE_MAX 32
static struct {
	volatile sig_atomic_t state; /* 0 free, 1 file, 2 directory */
	char path[4200];
} live[LIVE_MAX];
static volatile sig_atomic_t live_child;
static char command_line[2048];

int bk_out_track(const char *path, int is_dir)
{
	if (strlen(path) >= sizeof live[0].path)
		return -1;
	for (int k = 0; k < LIVE_MAX; k++)
		if (live[k].state == 0) {
			strcpy(live[k].path, path);
			__atomic_thread_fence(__ATOMIC_SEQ_CST);
			live[k].state = is_dir ? 2 : 1;
			return k;
		}
	return -1;
}

void bk_out_untrack(int slot)
{
	if (slot >= 0 && slot < LIVE_MAX)
		live[slot].state = 0;
	__atomic_thread_fence(__ATOMIC_SEQ_CST);
}

void bk_out_track_child(int pid)
{
	live_child = pid;
}

/* Removes name (relative to dirfd) and, when it is a directory, everything
 * under it, by openat/unlinkat: a symlink is removed, never followed (unlinkat
 * on it removes the link; O_NOFOLLOW refuses to descend through one). keep_last
 * names an entry of the top directory removed after every other (the marker:
 * a half-removed leftover still carries it, so the next run still knows it for
 * brdfkit's). Async-signal-safe (see above). Returns 0 or -1 (errno set);
 * ENOENT counts as done, since another run may be removing the same tree. */
static int rm_at(int dirfd, const char *name, const char *keep_last, int depth)
{
	if (unlinkat(dirfd, name, 0) == 0 || errno == ENOENT)
		return 0;
	if ((errno != EISDIR && errno != EPERM) || depth > 32)
		return -1;
	int fd = openat(dirfd, name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
	if (fd < 0)
		return errno == ENOENT ? 0 : -1;
	/* Passes until one removes nothing: entries removed while reading
	 * getdents may shift what a single pass sees. */
	for (int pass = 0, removed = 1; removed && pass < 64; pass++) {
		removed = 0;
		lseek(fd, 0, SEEK_SET);
		char buf[2048];
		ssize_t n;
		while ((n = getdents64(fd, buf, sizeof buf)) > 0)
			for (ssize_t off = 0; off < n;) {
				struct dirent64 *e = (struct dirent64 *)(void *)(buf + off);
				off += e->d_reclen;
				const char *s = e->d_name;
				if ((s[0] == '.' && (!s[1] || (s[1] == '.' && !s[2]))) ||
				    (keep_last && !strcmp(s, keep_last)))
					continue;
				if (rm_at(fd, s, NULL, depth + 1) == 0)
					removed++;
			}
	}
	if (keep_last)
		unlinkat(fd, keep_last, 0);
	close(fd);
	if (unlinkat(dirfd, name, AT_REMOVEDIR) == 0 || errno == ENOENT)
		return 0;
	return -1;
}

static void on_signal(int sig)
{
	int e = errno;
	pid_t c = (pid_t)live_child;
	if (c > 0) { /* a compiler of timing.c still writing into its scratch directory */
		kill(c, SIGKILL);
		waitpid(c, NULL, 0);
	}
	for (int k = 0; k < LIVE_MAX; k++) {
		if (live[k].state == 1)
			unlink(live[k].path);
		else if (live[k].state == 2)
			rm_at(AT_FDCWD, live[k].path, BK_OUT_MARKER, 0);
	}
	/* die of the signal itself, so that a shell sees 128 + sig and stops its
	 * loop; _exit is the fallback should raise return */
	signal(sig, SIG_DFL);
	sigset_t set;
	sigemptyset(&set);
	sigaddset(&set, sig);
	sigprocmask(SIG_UNBLOCK, &set, NULL);
	raise(sig);
	errno = e;
	_exit(128 + sig);
}

void bk_out_init(int argc, char **argv)
{
	size_t k = 0;
	command_line[0] = '\0';
	for (int i = 0; i < argc && k < sizeof command_line; i++)
		k += (size_t)snprintf(command_line + k, sizeof command_line - k, "%s%s", i ? " " : "",
		                      i ? argv[i] : "brdfkit");
	static const int sigs[] = {SIGINT, SIGTERM, SIGHUP};
	for (size_t i = 0; i < sizeof sigs / sizeof sigs[0]; i++) {
		struct sigaction old, sa;
		memset(&sa, 0, sizeof sa);
		sa.sa_handler = on_signal;
		sigfillset(&sa.sa_mask); /* one handler at a time */
		/* a signal ignored by whoever started us (nohup) stays ignored */
		if (sigaction(sigs[i], NULL, &old) == 0 && old.sa_handler != SIG_IGN)
			sigaction(sigs[i], &sa, NULL);
	}
}

const char *bk_out_command(void)
{
	return command_line[0] ? command_line : "brdfkit";
}

/* ---- single files ------------------------------------------------------------- */

int bk_out_open(bk_out *o, const char *path, char *err, size_t errlen)
{
	o->f = NULL;
	o->slot = -1;
	if (strlen(path) >= sizeof o->path) {
		snprintf(err, errlen, "%.64s...: path too long", path);
		return -1;
	}
	strcpy(o->path, path);
	snprintf(o->tmp, sizeof o->tmp, "%s.tmpXXXXXX", path);
	int fd = mkstemp(o->tmp);
	if (fd < 0) {
		snprintf(err, errlen, "%s: cannot create: %s", path, errtext(errno));
		return -1;
	}
	o->slot = bk_out_track(o->tmp, 0);
	/* mkstemp creates 0600; give the file the mode a plain fopen would. */
	mode_t um = umask(0);
	umask(um);
	fchmod(fd, 0666 & ~um);
	o->f = fdopen(fd, "w");
	if (!o->f) {
		snprintf(err, errlen, "%s: %s", path, errtext(errno));
		close(fd);
		unlink(o->tmp);
		bk_out_untrack(o->slot);
		return -1;
	}
	return 0;
}

/* fsync of the directory holding path (its last rename made durable). */
static void sync_parent(const char *path)
{
	char dir[4096];
	const char *slash = strrchr(path, '/');
	if (!slash)
		snprintf(dir, sizeof dir, ".");
	else
		snprintf(dir, sizeof dir, "%.*s", slash == path ? 1 : (int)(slash - path), path);
	int fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
	if (fd >= 0) {
		fsync(fd);
		close(fd);
	}
}

int bk_out_commit(bk_out *o, char *err, size_t errlen)
{
	/* fsync before rename: otherwise a crash can leave path naming an empty file */
	int bad = fflush(o->f) != 0 || ferror(o->f) || fsync(fileno(o->f)) != 0;
	int e = errno;
	if (fclose(o->f) != 0 || bad) {
		snprintf(err, errlen, "%s: write failed: %s", o->path, errtext(bad ? e : errno));
		o->f = NULL;
		unlink(o->tmp);
		bk_out_untrack(o->slot);
		return -1;
	}
	o->f = NULL;
	if (rename(o->tmp, o->path) != 0) {
		snprintf(err, errlen, "%s: cannot rename into place: %s", o->path, errtext(errno));
		unlink(o->tmp);
		bk_out_untrack(o->slot);
		return -1;
	}
	bk_out_untrack(o->slot);
	sync_parent(o->path);
	return 0;
}

void bk_out_abort(bk_out *o)
{
	if (o->f)
		fclose(o->f);
	o->f = NULL;
	unlink(o->tmp);
	bk_out_untrack(o->slot);
}

/* ---- output directories ------------------------------------------------------- */

enum { DIR_ABSENT, DIR_EMPTY, DIR_OURS, DIR_FOREIGN, DIR_RETRY, DIR_ERROR };

static int dir_is_empty(int fd)
{
	char buf[1024];
	ssize_t n;
	lseek(fd, 0, SEEK_SET);
	while ((n = getdents64(fd, buf, sizeof buf)) > 0)
		for (ssize_t off = 0; off < n;) {
			struct dirent64 *e = (struct dirent64 *)(void *)(buf + off);
			off += e->d_reclen;
			const char *s = e->d_name;
			if (!(s[0] == '.' && (!s[1] || (s[1] == '.' && !s[2]))))
				return 0;
		}
	return n == 0;
}

/* What stands at name in pfd: nothing, an empty directory, a directory with
 * brdfkit's marker (with lock: its marker opened into *mfd and locked
 * LOCK_EX, the directory checked to be still at name after the lock was
 * taken), or something else. */
static int classify(int pfd, const char *name, int lock, int *mfd)
{
	*mfd = -1;
	struct stat st, ms;
	if (fstatat(pfd, name, &st, AT_SYMLINK_NOFOLLOW) != 0)
		return errno == ENOENT ? DIR_ABSENT : DIR_ERROR;
	if (!S_ISDIR(st.st_mode))
		return DIR_FOREIGN;
	int dfd = openat(pfd, name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
	if (dfd < 0)
		return errno == ENOENT || errno == ELOOP || errno == ENOTDIR ? DIR_RETRY : DIR_ERROR;
	int m = openat(dfd, BK_OUT_MARKER, O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
	if (m < 0) {
		int r = errno == ENOENT || errno == ELOOP ? (dir_is_empty(dfd) ? DIR_EMPTY : DIR_FOREIGN) : DIR_ERROR;
		close(dfd);
		return r;
	}
	if (fstat(m, &ms) != 0 || !S_ISREG(ms.st_mode)) {
		close(m);
		close(dfd);
		return DIR_FOREIGN;
	}
	if (!lock) {
		close(m);
		close(dfd);
		return DIR_OURS;
	}
	/* Blocks only while another run swaps this directory out (it holds the
	 * lock from before its rename until the old tree is gone). */
	while (flock(m, LOCK_EX) != 0)
		if (errno != EINTR) {
			close(m);
			close(dfd);
			return DIR_ERROR;
		}
	struct stat now;
	int same = fstatat(pfd, name, &now, AT_SYMLINK_NOFOLLOW) == 0 && now.st_ino == st.st_ino &&
	           now.st_dev == st.st_dev && fstat(m, &ms) == 0 && ms.st_nlink > 0;
	close(dfd);
	if (!same) {
		close(m);
		return DIR_RETRY;
	}
	*mfd = m;
	return DIR_OURS;
}

/* "a/b/" -> "a/b"; "/" stays. */
static void strip_slashes(char *p)
{
	size_t n = strlen(p);
	while (n > 1 && p[n - 1] == '/')
		p[--n] = '\0';
}

/* Splits a stripped path into its parent directory (opened) and last name. */
static int open_parent(const char *path, const char **base)
{
	const char *slash = strrchr(path, '/');
	*base = slash ? slash + 1 : path;
	if (!slash)
		return open(".", O_RDONLY | O_DIRECTORY | O_CLOEXEC);
	char dir[4096];
	snprintf(dir, sizeof dir, "%.*s", slash == path ? 1 : (int)(slash - path), path);
	return open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
}

#define NOT_OURS "exists and was not written by brdfkit; choose another path or remove it"

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
	int pfd = open_parent(path, &base);
	if (!strcmp(base, ".") || !strcmp(base, "..")) {
		if (pfd >= 0)
			close(pfd);
		snprintf(err, errlen, "%s: ends in '.' or '..'; name the output directory itself", given);
		return -1;
	}
	if (pfd < 0) {
		snprintf(err, errlen, "%s: cannot create: %s", given, errtext(errno));
		return -1;
	}
	int m, r = classify(pfd, base, 0, &m);
	int e = errno;
	if (r != DIR_FOREIGN && r != DIR_ERROR && faccessat(pfd, ".", W_OK | X_OK, 0) != 0) {
		e = errno;
		r = DIR_ERROR;
	}
	close(pfd);
	if (r == DIR_FOREIGN)
		snprintf(err, errlen, "%s: " NOT_OURS, given);
	else if (r == DIR_ERROR)
		snprintf(err, errlen, "%s: cannot create: %s", given, errtext(e));
	return r == DIR_FOREIGN || r == DIR_ERROR ? -1 : 0;
}

/* DIR.tmpXXXXXX or DIR.oldXXXXXX (mkdtemp's six letters and digits). */
static int is_leftover(const char *entry, const char *base)
{
	size_t n = strlen(base);
	if (strncmp(entry, base, n) != 0 || (strncmp(entry + n, ".tmp", 4) && strncmp(entry + n, ".old", 4)))
		return 0;
	const char *x = entry + n + 4;
	if (strlen(x) != 6)
		return 0;
	for (; *x; x++)
		if (!((*x >= 'a' && *x <= 'z') || (*x >= 'A' && *x <= 'Z') || (*x >= '0' && *x <= '9')))
			return 0;
	return 1;
}

/* Removes what killed runs left beside path: a DIR.tmp* or DIR.old* with the
 * marker whose lock can be taken (its run is dead: the kernel dropped the
 * lock with it), and empty ones (rmdir removes nothing else). A live run's
 * directory is locked or, before its marker is in place, not empty. */
static void clean_leftovers(int pfd, const char *base)
{
	int fd = dup(pfd);
	DIR *d = fd >= 0 ? fdopendir(fd) : NULL;
	if (!d) {
		if (fd >= 0)
			close(fd);
		return;
	}
	char names[64][300];
	int n = 0;
	for (struct dirent *e; n < 64 && (e = readdir(d));)
		if (strlen(e->d_name) < sizeof names[0] && is_leftover(e->d_name, base))
			strcpy(names[n++], e->d_name);
	closedir(d);
	for (int k = 0; k < n; k++) {
		int dfd = openat(pfd, names[k], O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
		if (dfd < 0)
			continue;
		int m = openat(dfd, BK_OUT_MARKER, O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
		struct stat ms;
		if (m >= 0 && fstat(m, &ms) == 0 && S_ISREG(ms.st_mode) && flock(m, LOCK_EX | LOCK_NB) == 0)
			rm_at(pfd, names[k], BK_OUT_MARKER, 0);
		else if (m < 0 && errno == ENOENT)
			unlinkat(pfd, names[k], AT_REMOVEDIR);
		if (m >= 0)
			close(m);
		close(dfd);
	}
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
	int pfd = open_parent(d->path, &base);
	if (pfd < 0) {
		snprintf(err, errlen, "%s: cannot create: %s", given, errtext(errno));
		return -1;
	}
	clean_leftovers(pfd, base);
	close(pfd);
	if (!command)
		command = bk_out_command();
	/* The marker is created under another name, locked, then renamed into
	 * place: a scan never finds an unlocked marker in a live directory. A
	 * scan may rmdir the directory in the moment before (it is empty then):
	 * then start again. */
	for (int tries = 0; tries < 8; tries++) {
		snprintf(d->tmp, sizeof d->tmp, "%s.tmpXXXXXX", d->path);
		if (!mkdtemp(d->tmp)) {
			snprintf(err, errlen, "%s: cannot create: %s", given, errtext(errno));
			return -1;
		}
		d->slot = bk_out_track(d->tmp, 1);
		mode_t um = umask(0); /* mkdtemp makes 0700; give DIR the mode mkdir would */
		umask(um);
		chmod(d->tmp, 0777 & ~um);
		int dfd = open(d->tmp, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
		int m = dfd < 0 ? -1 : openat(dfd, BK_OUT_MARKER ".new", O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC,
		                              0666);
		int e = errno;
		if (m < 0) {
			if (dfd >= 0)
				close(dfd);
			bk_out_untrack(d->slot);
			if (e == ENOENT)
				continue;
			rm_at(AT_FDCWD, d->tmp, NULL, 0);
			snprintf(err, errlen, "%s: cannot create: %s", given, errtext(e));
			return -1;
		}
		size_t len = strlen(command);
		int ok = flock(m, LOCK_EX) == 0 && write(m, command, len) == (ssize_t)len && write(m, "\n", 1) == 1 &&
		         renameat(dfd, BK_OUT_MARKER ".new", dfd, BK_OUT_MARKER) == 0;
		e = errno;
		close(dfd);
		if (!ok) {
			close(m);
			bk_out_untrack(d->slot);
			rm_at(AT_FDCWD, d->tmp, NULL, 0);
			snprintf(err, errlen, "%s: cannot create: %s", given, errtext(e));
			return -1;
		}
		d->lock = m;
		return 0;
	}
	snprintf(err, errlen, "%s: cannot create: its temporary directory kept vanishing", given);
	return -1;
}

/* fsync of every regular file and directory under dirfd, then of dirfd. */
static int sync_tree(int dirfd, int depth)
{
	DIR *d = NULL;
	int fd = dup(dirfd), rc = 0;
	if (fd < 0 || !(d = fdopendir(fd))) {
		if (fd >= 0)
			close(fd);
		return -1;
	}
	for (struct dirent *e; (e = readdir(d));) {
		if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
			continue;
		struct stat st;
		if (fstatat(dirfd, e->d_name, &st, AT_SYMLINK_NOFOLLOW) != 0)
			return closedir(d), -1;
		if (!S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode))
			continue;
		int c = openat(dirfd, e->d_name, O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
		if (c < 0)
			return closedir(d), -1;
		if (S_ISDIR(st.st_mode) && depth < 32)
			rc |= sync_tree(c, depth + 1);
		else
			rc |= fsync(c);
		close(c);
	}
	closedir(d);
	return rc | fsync(dirfd);
}

void bk_out_dir_abort(bk_out_dir *d)
{
	if (d->tmp[0])
		rm_at(AT_FDCWD, d->tmp, BK_OUT_MARKER, 0);
	bk_out_untrack(d->slot);
	if (d->lock >= 0)
		close(d->lock);
	d->lock = -1;
	d->slot = -1;
	d->tmp[0] = '\0';
}

/* Where renameat2 has no RENAME_EXCHANGE (file systems without it): the old
 * directory, locked by the caller, is moved aside to DIR.oldXXXXXX, the new
 * one renamed in, the old removed. A kill between the two renames leaves DIR
 * absent and both whole directories beside it. Returns 0, 1 to try again
 * (DIR changed meanwhile), -1 with errno. */
static int swap_aside(int pfd, const bk_out_dir *d, const char *base, const char *tbase)
{
	char old[4112];
	snprintf(old, sizeof old, "%s.oldXXXXXX", d->path);
	if (!mkdtemp(old))
		return -1;
	int slot = bk_out_track(old, 1);
	const char *obase = strrchr(old, '/') ? strrchr(old, '/') + 1 : old;
	if (renameat(pfd, base, pfd, obase) != 0) { /* a directory onto an empty one: allowed */
		int e = errno;
		unlinkat(pfd, obase, AT_REMOVEDIR);
		bk_out_untrack(slot);
		errno = e;
		return e == ENOENT ? 1 : -1;
	}
	int r = renameat(pfd, tbase, pfd, base) == 0 ? 0 : errno == ENOTEMPTY || errno == EEXIST ? 1 : -1;
	int e = errno;
	rm_at(pfd, obase, BK_OUT_MARKER, 0);
	bk_out_untrack(slot);
	errno = e;
	return r;
}

int bk_out_dir_commit(bk_out_dir *d, char *err, size_t errlen)
{
	const char *base, *tbase = strrchr(d->tmp, '/') ? strrchr(d->tmp, '/') + 1 : d->tmp;
	int pfd = open_parent(d->path, &base);
	int tfd = open(d->tmp, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
	int bad = pfd < 0 || tfd < 0 || sync_tree(tfd, 0) != 0;
	int e = errno;
	if (tfd >= 0)
		close(tfd);
	if (bad) {
		if (pfd >= 0)
			close(pfd);
		bk_out_dir_abort(d);
		snprintf(err, errlen, "%s: writing the results failed: %s", d->name, errtext(e));
		return -1;
	}
	/* Try until one swap went through: another run may commit to the same
	 * path between our look and our rename; its whole result is then what we
	 * replace. */
	int rc = -1, done = 0;
	e = 0;
	for (int tries = 0; !done && tries < 1000; tries++) {
		int m, r = classify(pfd, base, 1, &m);
		e = errno;
		if (r == DIR_RETRY)
			continue;
		if (r == DIR_FOREIGN || r == DIR_ERROR)
			break;
		if (r == DIR_ABSENT) {
			int s = renameat2(pfd, tbase, pfd, base, RENAME_NOREPLACE);
			if (s != 0 && (errno == EINVAL || errno == ENOSYS)) /* no flags here: a plain rename */
				s = renameat(pfd, tbase, pfd, base);
			e = errno;
			if (s == 0)
				rc = 0, done = 1;
			else if (e != EEXIST && e != ENOTEMPTY && e != ENOTDIR)
				break;
			continue;
		}
		/* DIR_EMPTY or DIR_OURS (m locked): exchange, then remove what came out */
		int s = renameat2(pfd, tbase, pfd, base, RENAME_EXCHANGE);
		e = errno;
		if (s != 0 && (e == EINVAL || e == ENOSYS)) {
			s = r == DIR_EMPTY ? renameat(pfd, tbase, pfd, base) : swap_aside(pfd, d, base, tbase);
			e = errno;
			if (m >= 0)
				close(m);
			if (s == 0)
				rc = 0, done = 1;
			else if (!(s == 1 || (r == DIR_EMPTY && (e == ENOTEMPTY || e == EEXIST))))
				break;
			continue;
		}
		if (s != 0) {
			if (m >= 0)
				close(m);
			if (e == ENOENT)
				continue;
			break;
		}
		/* The new result is in place; d->tmp names the old one now. */
		close(d->lock);
		d->lock = -1;
		if (r == DIR_OURS) {
			rm_at(pfd, tbase, BK_OUT_MARKER, 0);
		} else if (unlinkat(pfd, tbase, AT_REMOVEDIR) != 0) {
			/* the empty directory got files meanwhile: give it back untouched */
			renameat2(pfd, tbase, pfd, base, RENAME_EXCHANGE);
			if (m >= 0)
				close(m);
			break;
		}
		if (m >= 0)
			close(m);
		rc = 0, done = 1;
	}
	if (rc == 0) {
		fsync(pfd);
		bk_out_untrack(d->slot);
		d->slot = -1;
		d->tmp[0] = '\0';
		if (d->lock >= 0)
			close(d->lock);
		d->lock = -1;
	} else {
		bk_out_dir_abort(d);
		int m;
		if (classify(pfd, base, 0, &m) == DIR_FOREIGN)
			snprintf(err, errlen, "%s: " NOT_OURS, d->name);
		else
			snprintf(err, errlen, "%s: cannot replace: %s", d->name, errtext(e ? e : EAGAIN));
	}
	close(pfd);
	return rc;
}

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
