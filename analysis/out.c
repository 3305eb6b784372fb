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
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
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
static char command_word[64]; /* argv[1]: "lut", "search"; empty before bk_out_init */

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

/* One argument for the recorded command line: as it is when it is plain,
 * otherwise in single quotes (a quote as '\'') so the line can be pasted
 * back into a shell. */
static size_t put_word(char *buf, size_t len, size_t k, const char *a)
{
	static const char plain[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_./=:,+-@%";
	if (*a && strspn(a, plain) == strlen(a))
		return k + (size_t)snprintf(buf + k, len - k, "%s", a);
	k += (size_t)snprintf(buf + k, len - k, "'");
	for (; *a && k < len; a++)
		k += (size_t)(*a == '\'' ? snprintf(buf + k, len - k, "'\\''") : snprintf(buf + k, len - k, "%c", *a));
	return k < len ? k + (size_t)snprintf(buf + k, len - k, "'") : k;
}

void bk_out_init(int argc, char **argv)
{
	size_t k = (size_t)snprintf(command_line, sizeof command_line, "brdfkit");
	for (int i = 1; i < argc && k + 1 < sizeof command_line; i++) {
		k += (size_t)snprintf(command_line + k, sizeof command_line - k, " ");
		if (k < sizeof command_line)
			k = put_word(command_line, sizeof command_line, k, argv[i]);
	}
	/* The command line is written into comment lines (CSV '#' lines, the
	 * marker, shader and EXR headers): a line break or other control
	 * character from an argument would end the comment and start a line of
	 * data or code, so each is shown as '?' here, once for every writer. */
	for (char *c = command_line; *c; c++)
		if ((unsigned char)*c < 0x20 || *c == 0x7f)
			*c = '?';
	snprintf(command_word, sizeof command_word, "%s", argc > 1 ? argv[1] : "");
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

/* ---- lines while a run goes on, and names in messages --------------------------- */

/* One line on stderr that does not end the run (a wait, a result kept aside),
 * in the form of cli_fail's errors, "brdfkit CMD: what: detail": out.c sits
 * below the command-line tool and cannot call it. */
__attribute__((format(printf, 1, 2))) static void notice(const char *fmt, ...)
{
	char line[1024];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(line, sizeof line, fmt, ap);
	va_end(ap);
	fprintf(stderr, "brdfkit%s%s: %s\n", command_word[0] ? " " : "", command_word, line);
}

/* s for a one-line message: control characters shown as '?'. */
static const char *printable(const char *s, char *buf, size_t len)
{
	size_t k = 0;
	for (; *s && k + 1 < len; s++)
		buf[k++] = (unsigned char)*s < 0x20 || *s == 0x7f ? '?' : *s;
	buf[k] = '\0';
	return buf;
}

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

/* The six letters and digits after "BASE.KIND" in entry (KIND "tmp" or "old"),
 * or NULL when entry is not so named. */
static const char *temp_letters(const char *entry, const char *base, const char *kind)
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

/* "a/b/c" -> dir "a/b", returns "c"; "c" -> ".", "c"; "/c" -> "/", "c". */
static const char *split_path(const char *path, char *dir, size_t len)
{
	const char *slash = strrchr(path, '/');
	if (!slash) {
		snprintf(dir, len, ".");
		return path;
	}
	snprintf(dir, len, "%.*s", slash == path ? 1 : (int)(slash - path), path);
	return slash + 1;
}

/* The names in dfd ("." and ".." left out), malloc'd one after another
 * ("a\0b\0"), *count of them; NULL with errno on failure. */
static char *dir_names(int dfd, size_t *count)
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

/* Removes from dir the temporaries of base that dead runs left: a regular
 * file named base.tmpXXXXXX with its inode's letters and a free lock. Anything
 * else so named (a user's file, a live run's temporary) stays. */
static void clean_file_leftovers(const char *dir, const char *base)
{
	int dfd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
	if (dfd < 0)
		return;
	size_t n = 0;
	char *names = dir_names(dfd, &n);
	for (char *s = names; s && n--; s += strlen(s) + 1) {
		const char *x = temp_letters(s, base, "tmp");
		int fd = x ? openat(dfd, s, O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC) : -1;
		if (fd < 0)
			continue;
		struct stat st, now;
		char tag[7] = "";
		if (fstat(fd, &st) == 0 && S_ISREG(st.st_mode))
			inode_tag(st.st_ino, tag);
		if (!strcmp(tag, x) && flock(fd, LOCK_EX | LOCK_NB) == 0 &&
		    fstatat(dfd, s, &now, AT_SYMLINK_NOFOLLOW) == 0 && now.st_ino == st.st_ino && now.st_dev == st.st_dev)
			unlinkat(dfd, s, 0);
		close(fd);
	}
	free(names);
	close(dfd);
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

static const char *shown_path(const char *path, char *buf, size_t len);

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
	clean_file_leftovers(dir, split_path(path, dir, sizeof dir));
	int fd = make_temp(o, dir);
	if (fd < 0) {
		int e = errno;
		snprintf(err, errlen, "%s: cannot create: %s", shown_path(path, sp, sizeof sp), errtext(e));
		return -1;
	}
	o->f = fdopen(fd, "w");
	if (!o->f) {
		int e = errno;
		snprintf(err, errlen, "%s: %s", shown_path(path, sp, sizeof sp), errtext(e));
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
	split_path(path, dir, sizeof dir);
	int fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
	if (fd < 0)
		return 0;
	int rc = fsync(fd), e = errno;
	close(fd);
	errno = e;
	return rc;
}

int bk_out_commit(bk_out *o, char *err, size_t errlen)
{
	/* fsync before rename: otherwise a crash can leave path naming an empty
	 * file. The lock stays (on a duplicate) until the rename: a run that
	 * could take it would count the temporary as a dead run's. */
	char sp[1024];
	int bad = fflush(o->f) != 0 || ferror(o->f) || fsync(fileno(o->f)) != 0;
	int e = errno, keep = fcntl(fileno(o->f), F_DUPFD_CLOEXEC, 0);
	if (fclose(o->f) != 0 || bad) {
		e = bad ? e : errno;
		snprintf(err, errlen, "%s: write failed: %s", shown_path(o->path, sp, sizeof sp), errtext(e));
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
	if (keep >= 0)
		close(keep);
	if (!moved) {
		snprintf(err, errlen, "%s: cannot rename into place: %s", shown_path(o->path, sp, sizeof sp), errtext(e));
		return -1;
	}
	if (sync_parent(o->path)) {
		snprintf(err, errlen, "%s: written, but the fsync of its directory failed: %s (it may not survive a crash)",
		         shown_path(o->path, sp, sizeof sp), errtext(errno));
		return -1;
	}
	return 0;
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

/* ---- output directories: the marker ------------------------------------------- */

/* The marker BK_OUT_MARKER says what brdfkit wrote, one item a line:
 *
 *     brdfkit-output 2        the format
 *     brdfkit lut --out lut   the command
 *     f dfg.csv               each file (f) and directory (d) of the result,
 *     f dfg.exr               its path inside DIR, in byte order (strcmp),
 *     end                     with '\' and newline escaped as \\ and \n
 *
 * A run writes the first two lines when it begins and the list when it
 * commits, so a marker without "end" is a run's that was building. Only a
 * directory whose marker is complete, and lists every entry in it with its
 * type, is replaced, and only what it lists is deleted. The marker of the
 * format before (one line, the command) lists nothing, so it is not enough.
 *
 * TEMPS, beside the marker, holds the name the tree was built under
 * ("DIR.tmpXXXXXX", from mkdtemp), written while no other run can know the
 * name. The swap leaves the previous result at that name (or, without
 * RENAME_EXCHANGE, at "DIR.oldXXXXXX" with the same letters); TEMPS stays in
 * DIR until that is removed. So a later run removes only names brdfkit
 * recorded: a build tree whose TEMPS names itself (its run died before the
 * swap), and the names recorded in DIR (its run died after). The marker and
 * TEMPS are the protocol's, not the result's: never listed, always allowed. */
#define MARKER_MAGIC "brdfkit-output 2"
#define MARKER_NEW BK_OUT_MARKER ".new"
#define TEMPS BK_OUT_MARKER ".tmps"
#define MARKER_MAX (16 << 20) /* a result lists a few hundred names (results/: 170 at most) */
#define TREE_DEPTH 32         /* results are 3 deep; deeper is refused, never followed */

static int write_all(int fd, const char *s, size_t n)
{
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

/* s into b with '\' and newline escaped: one line holds one name. */
static void put_escaped(bk_strbuf *b, const char *s)
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

typedef struct entry {
	char *path;
	char type; /* 'f' or 'd' */
} entry;

static int by_path(const void *a, const void *b)
{
	return strcmp(((const entry *)a)->path, ((const entry *)b)->path);
}

typedef struct manifest {
	char *text; /* the marker's bytes, lines split and unescaped in place */
	entry *e;   /* pointing into text, in byte order */
	size_t n;
} manifest;

static void manifest_free(manifest *m)
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

enum { MK_FOREIGN, MK_OLD, MK_BUILDING, MK_COMPLETE };

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
static int marker_read(int fd, manifest *m)
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

enum { WALK_CHECK, WALK_REMOVE };
typedef struct walk {
	const manifest *m;
	int mode;          /* WALK_CHECK: only look; WALK_REMOVE: remove what m lists */
	int unlisted;      /* entries m does not list (or lists with another type) */
	char first[4096];  /* the first of them in byte order, for the message */
} walk;

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
static int walk_tree(walk *w, int dfd, const char *prefix, int depth)
{
	size_t n = 0;
	char *names = dir_names(dfd, &n), rel[4096];
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
			rc = walk_tree(w, c, rel, depth + 1);
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
static int remove_listed(int pfd, const char *name, int dfd, const manifest *m, char *first, size_t flen)
{
	walk w = {m, WALK_CHECK, 0, ""};
	if (walk_tree(&w, dfd, "", 0))
		return -1;
	if (!w.unlisted) {
		w.mode = WALK_REMOVE;
		if (walk_tree(&w, dfd, "", 0))
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
	char *names = dir_names(dfd, &n), rel[4096];
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
static int write_list(int fd, int tfd)
{
	listing l = {0};
	int rc = list_tree(&l, tfd, "", 0), e = errno;
	if (!rc) {
		bk_strbuf b = {0};
		qsort(l.e, l.n, sizeof *l.e, by_path);
		for (size_t k = 0; k < l.n; k++) {
			bk_sb_put(&b, "%c ", l.e[k].type);
			put_escaped(&b, l.e[k].path);
			bk_sb_put(&b, "\n");
		}
		bk_sb_put(&b, "end\n");
		if (b.oom)
			rc = -1, e = ENOMEM;
		else if (lseek(fd, 0, SEEK_END) < 0 || write_all(fd, b.s, b.len) || fsync(fd))
			rc = -1, e = errno;
		free(b.s);
	}
	for (size_t k = 0; k < l.n; k++)
		free(l.e[k].path);
	free(l.e);
	errno = e;
	return rc;
}

/* ---- output directories: what stands at --out --------------------------------- */

enum { DIR_ABSENT, DIR_EMPTY, DIR_OURS, DIR_FOREIGN, DIR_OLD, DIR_UNLISTED, DIR_RETRY, DIR_ERROR };

typedef struct look {
	int kind;
	int marker;       /* DIR_FOREIGN: it has a .brdfkit-output, not brdfkit's */
	int mfd;          /* DIR_OURS, asked to lock: the marker, locked */
	int err;          /* DIR_ERROR: errno */
	int link;         /* DIR_FOREIGN: a symlink (to anything: never followed) */
	manifest m;       /* DIR_OURS: what its run listed */
	char first[4096]; /* DIR_UNLISTED: the first entry it did not list */
} look;

static void look_done(look *k)
{
	if (k->mfd >= 0)
		close(k->mfd);
	k->mfd = -1;
	manifest_free(&k->m);
}

static int dir_is_empty(int fd)
{
	size_t n = 1;
	char *names = dir_names(fd, &n);
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
	notice("--out %s: another brdfkit is writing it (its " BK_OUT_MARKER " is locked); waiting for it to finish",
	       printable(shown, p, sizeof p));
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
static int classify(int pfd, const char *name, const char *shown, look *k)
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
		int kind = marker_read(m, &k->m);
		walk w = {&k->m, WALK_CHECK, 0, ""};
		k->marker = 1;
		if (kind < 0)
			r = DIR_ERROR;
		else if (kind == MK_OLD)
			r = DIR_OLD;
		else if (kind != MK_COMPLETE)
			r = DIR_FOREIGN;
		else if (walk_tree(&w, dfd, "", 0))
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
		manifest_free(&k->m);
	return r;
}

#define NOT_OURS "exists and was not written by brdfkit"

/* The one line for a directory k says may not be replaced, or for a failure
 * (doing: "cannot create", "cannot replace"). */
static void refusal(const look *k, const char *given, const char *doing, char *err, size_t errlen)
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
		         printable(k->first, p, sizeof p));
		break;
	default:
		snprintf(err, errlen, "%s: %s: %s", given, doing, errtext(k->err ? k->err : EAGAIN));
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
static int open_parent(const char *path, const char **base)
{
	char dir[4096];
	*base = split_path(path, dir, sizeof dir);
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
	look k;
	int r = classify(pfd, base, NULL, &k);
	if (r != DIR_FOREIGN && r != DIR_OLD && r != DIR_UNLISTED && r != DIR_ERROR &&
	    faccessat(pfd, ".", W_OK | X_OK, 0) != 0)
		r = looked(&k, DIR_ERROR);
	close(pfd);
	int bad = r == DIR_FOREIGN || r == DIR_OLD || r == DIR_UNLISTED || r == DIR_ERROR;
	if (bad)
		refusal(&k, given, "cannot create", err, errlen);
	look_done(&k);
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
	if (!nl || nl[1] || (*nl = '\0', !temp_letters(buf, base, "tmp")) || strlen(buf) >= 300)
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
	int kind = fd >= 0 ? marker_read(fd, &m) : -1;
	if (fd >= 0) {
		manifest_free(&m);
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
		int kind = marker_read(fd, &m);
		if (kind == MK_COMPLETE)
			remove_listed(pfd, name, dfd, &m, NULL, 0);
		else if (kind == MK_BUILDING && own)
			rm_at(pfd, name, BK_OUT_MARKER, 0);
		manifest_free(&m);
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
	char *names = dir_names(pfd, &n);
	for (char *s = names; s && n--; s += strlen(s) + 1) {
		if (!temp_letters(s, base, "tmp") || (dfd = openat(pfd, s, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC)) < 0)
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
	int pfd = open_parent(d->path, &base);
	if (pfd < 0) {
		snprintf(err, errlen, "%s: cannot create: %s", given, errtext(errno));
		return -1;
	}
	clean_leftovers(pfd, base);
	close(pfd);
	bk_strbuf head = {0};
	bk_sb_put(&head, MARKER_MAGIC "\n");
	put_escaped(&head, command ? command : bk_out_command());
	bk_sb_put(&head, "\n");
	if (head.oom) {
		free(head.s);
		snprintf(err, errlen, "%s: cannot create: %s", given, errtext(ENOMEM));
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
		int ok = m >= 0 && flock(m, LOCK_EX) == 0 && write_all(m, head.s, head.len) == 0 &&
		         renameat(dfd, MARKER_NEW, dfd, BK_OUT_MARKER) == 0 &&
		         (t = openat(dfd, TEMPS, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666)) >= 0 &&
		         write_all(t, tbase, strlen(tbase)) == 0 && write_all(t, "\n", 1) == 0;
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
		rm_at(AT_FDCWD, d->tmp, NULL, 0);
		break;
	}
	free(head.s);
	if (rc) {
		d->tmp[0] = '\0';
		snprintf(err, errlen, "%s: cannot create: %s", given,
		         e == ENOENT ? "its temporary directory kept vanishing" : errtext(e));
	}
	return rc;
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

/* Where renameat2 has no RENAME_EXCHANGE: the previous result (locked by the
 * caller) is moved aside to DIR.oldXXXXXX, the letters of our tree's (so
 * that TEMPS records it too), and the new tree renamed in. A kill between
 * the two renames leaves DIR absent and both whole trees beside it, both
 * recorded. Returns 0 with prev set, 1 to try again (DIR changed meanwhile),
 * -1 with errno. */
static int swap_aside(int pfd, const char *base, const char *tbase, char *prev, size_t plen)
{
	char obase[4112];
	if (snprintf(obase, sizeof obase, "%s", tbase) >= (int)sizeof obase)
		return errno = ENAMETOOLONG, -1;
	memcpy(obase + strlen(base) + 1, "old", 3);
	if (mkdirat(pfd, obase, 0700) != 0)
		return -1;
	if (renameat(pfd, base, pfd, obase) != 0) { /* a directory onto an empty one: allowed */
		int e = errno;
		unlinkat(pfd, obase, AT_REMOVEDIR);
		errno = e;
		return e == ENOENT ? 1 : -1;
	}
	if (renameat(pfd, tbase, pfd, base) != 0) {
		int e = errno;
		/* DIR taken meanwhile (another run's whole result) or a failure: the
		 * previous result goes back where it can; else prev names it, and
		 * the caller removes it when another run's result took DIR (1) and
		 * leaves it where it is after a failure (-1) */
		if (renameat(pfd, obase, pfd, base) != 0)
			snprintf(prev, plen, "%s", obase);
		errno = e;
		return e == ENOTEMPTY || e == EEXIST ? 1 : -1;
	}
	snprintf(prev, plen, "%s", obase);
	return 0;
}

/* One try at putting the new tree (tbase) at DIR (base) by what k found there
 * (under DIR's lock). Returns 0 with prev naming where the previous result
 * now lies ("" when there was none), 1 to look again (DIR changed meanwhile),
 * -1 with errno. */
static int try_swap(int pfd, bk_out_dir *d, const char *base, const char *tbase, const look *k, char *prev,
                    size_t plen)
{
	prev[0] = '\0';
	if (k->kind == DIR_ABSENT) {
		int s = renameat2(pfd, tbase, pfd, base, RENAME_NOREPLACE);
		if (s != 0 && (errno == EINVAL || errno == ENOSYS)) /* no flags here: a plain rename */
			s = renameat(pfd, tbase, pfd, base);
		return s == 0 ? 0 : errno == EEXIST || errno == ENOTEMPTY || errno == ENOTDIR ? 1 : -1;
	}
	int s = renameat2(pfd, tbase, pfd, base, RENAME_EXCHANGE);
	if (s != 0 && (errno == EINVAL || errno == ENOSYS)) {
		if (k->kind == DIR_OURS)
			return swap_aside(pfd, base, tbase, prev, plen);
		s = renameat(pfd, tbase, pfd, base); /* onto an empty directory: allowed */
		return s == 0 ? 0 : errno == ENOTEMPTY || errno == EEXIST ? 1 : -1;
	}
	if (s != 0)
		return errno == ENOENT ? 1 : -1;
	/* The new result is in place; tbase names the previous one now. Runs
	 * waiting for DIR's lock may go on: they find our marker. */
	close(d->lock);
	d->lock = -1;
	if (k->kind == DIR_OURS) {
		snprintf(prev, plen, "%s", tbase);
		return 0;
	}
	if (unlinkat(pfd, tbase, AT_REMOVEDIR) == 0)
		return 0;
	/* the empty directory got files meanwhile: give it back untouched */
	int e = errno;
	renameat2(pfd, tbase, pfd, base, RENAME_EXCHANGE);
	errno = e;
	return -1;
}

/* name beside DIR as a path for a message: DIR's directory part, then name. */
static const char *sibling(const bk_out_dir *d, const char *name, char *buf, size_t len)
{
	const char *slash = strrchr(d->path, '/');
	char path[4400];
	snprintf(path, sizeof path, "%.*s%s", slash ? (int)(slash + 1 - d->path) : 0, d->path, name);
	return printable(path, buf, len);
}

/* The previous result, left at prev beside DIR by the swap: removed as its
 * marker lists it (checked under its lock before the swap). Should something
 * have been added since, it is kept whole, with a line saying where. */
static void retire(int pfd, const bk_out_dir *d, const char *prev, const look *k)
{
	char first[4096] = "", p[512], q[512];
	int dfd = openat(pfd, prev, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
	int r = dfd < 0 ? (errno == ENOENT ? 0 : -1) : remove_listed(pfd, prev, dfd, &k->m, first, sizeof first);
	int e = errno;
	if (dfd >= 0)
		close(dfd);
	if (r > 0)
		notice("--out %s: the previous result is kept at %s: it holds '%s', which brdfkit did not write",
		       printable(d->name, p, sizeof p), sibling(d, prev, q, sizeof q), printable(first, first, sizeof first));
	else if (r < 0)
		notice("--out %s: the previous result could not be removed from %s: %s", printable(d->name, p, sizeof p),
		       sibling(d, prev, q, sizeof q), errtext(e));
}

int bk_out_dir_commit(bk_out_dir *d, char *err, size_t errlen)
{
	const char *base, *tbase = strrchr(d->tmp, '/') ? strrchr(d->tmp, '/') + 1 : d->tmp;
	char prev[sizeof d->tmp] = "";
	int pfd = open_parent(d->path, &base);
	int tfd = open(d->tmp, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
	int bad = pfd < 0 || tfd < 0 || write_list(d->lock, tfd) != 0;
	int e = errno;
	if (bad) {
		if (pfd >= 0)
			close(pfd);
		if (tfd >= 0)
			close(tfd);
		bk_out_dir_abort(d);
		snprintf(err, errlen, "%s: writing the results failed: %s", d->name, errtext(e));
		return -1;
	}
	/* Try until one swap went through: another run may commit to the same
	 * path between our look and our rename; its whole result is then what we
	 * replace. */
	look k = {.mfd = -1};
	int rc = -1;
	for (int tries = 0; rc && tries < 1000; tries++) {
		look_done(&k);
		int r = classify(pfd, base, d->name, &k);
		if (r == DIR_RETRY)
			continue;
		if (r != DIR_ABSENT && r != DIR_EMPTY && r != DIR_OURS)
			break;
		int s = try_swap(pfd, d, base, tbase, &k, prev, sizeof prev);
		if (s < 0) { /* a previous result that could not go back stays where it is */
			k.kind = DIR_ERROR;
			k.err = errno;
			break;
		}
		if (s == 0)
			rc = 0;
		else if (prev[0]) /* DIR taken meanwhile: the previous result could not go back */
			retire(pfd, d, prev, &k), prev[0] = '\0';
	}
	if (rc) {
		bk_out_dir_abort(d);
		if (k.kind == DIR_RETRY || k.kind == DIR_ABSENT || k.kind == DIR_EMPTY || k.kind == DIR_OURS)
			k.kind = DIR_ERROR, k.err = EAGAIN;
		refusal(&k, d->name, "cannot replace", err, errlen);
	} else {
		bk_out_untrack(d->slot);
		d->slot = -1;
		d->tmp[0] = '\0';
		if (d->lock >= 0)
			close(d->lock);
		d->lock = -1;
		/* the new result made durable before the previous one goes: should
		 * that fail, the previous one stays (TEMPS records it, so the next
		 * run removes it) and the run fails */
		if (fsync(pfd) != 0) {
			char p[512];
			e = errno;
			rc = -1;
			snprintf(err, errlen,
			         "%s: the new result is in place, but the fsync of its parent directory failed: %s%s%s%s", d->name,
			         errtext(e), prev[0] ? "; the previous result stays at " : "",
			         prev[0] ? sibling(d, prev, p, sizeof p) : "", prev[0] ? " until the next run" : "");
		} else {
			if (prev[0])
				retire(pfd, d, prev, &k);
			unlinkat(tfd, TEMPS, 0); /* nothing left to record */
		}
	}
	look_done(&k);
	close(tfd);
	close(pfd);
	return rc;
}

/* ---- files of a tree being built ---------------------------------------------- */

/* path for a message: under a live build tree DIR.tmpXXXXXX (the registry),
 * shown under DIR, where the file goes; control characters as '?'. */
static const char *shown_path(const char *path, char *buf, size_t len)
{
	for (int k = 0; k < LIVE_MAX; k++) {
		size_t n = strlen(live[k].path);
		if (live[k].state == 2 && n > 10 && !strncmp(path, live[k].path, n) && path[n] == '/') {
			char p[8400];
			snprintf(p, sizeof p, "%.*s%s", (int)(n - 10), path, path + n); /* ".tmpXXXXXX" left out */
			return printable(p, buf, len);
		}
	}
	return printable(path, buf, len);
}

const char *bk_out_shown(const char *path, char *buf, size_t len)
{
	return shown_path(path, buf, len);
}

FILE *bk_out_fopen(const char *path, char *err, size_t errlen)
{
	FILE *f = fopen(path, "w");
	if (!f) {
		int e = errno;
		char p[1024];
		snprintf(err, errlen, "%s: cannot create: %s", shown_path(path, p, sizeof p), errtext(e));
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
	snprintf(err, errlen, "%s: cannot write: %s", shown_path(path, p, sizeof p), errtext(e));
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
	split_path(path, dir, sizeof dir);
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
	printable(path, p, sizeof p);
	if (!*path || strlen(path) >= 4096 - 16) {
		snprintf(err, errlen, "%.64s: %s", p, *path ? "path too long" : "empty path");
		return -1;
	}
	if (inside_output(path, at, sizeof at)) {
		snprintf(err, errlen, "%s: inside %s, a directory brdfkit writes whole (its next run would refuse or "
		         "delete the file); choose a path outside it", p, printable(at, q, sizeof q));
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
		         errtext(e));
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
		snprintf(why, len, "%s", errtext(e));
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
		snprintf(why, len, "%s", errtext(e));
		close(fd);
		errno = e;
		return -1;
	}
	return fd;
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
