/*
 * out_registry.c — the out module's registry of live temporaries, removed by a
 * signal handler before the process dies of the signal; the command line every
 * output records; the lines a run says on stderr and the paths its messages show
 * (out.h).
 */
#define _GNU_SOURCE /* getdents64: Linux */
#include "out.h"
#include "out_int.h"

#include <errno.h>
#include <fcntl.h>
#include <dirent.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

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
int out_rm_at(int dirfd, const char *name, const char *keep_last, int depth)
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
				if (out_rm_at(fd, s, NULL, depth + 1) == 0)
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
			out_rm_at(AT_FDCWD, live[k].path, BK_OUT_MARKER, 0);
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
 * in the form of cli_fail's errors, "brdfkit CMD: what: detail": the out module sits
 * below the command-line tool and cannot call it. */
void out_notice(const char *fmt, ...)
{
	char line[1024];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(line, sizeof line, fmt, ap);
	va_end(ap);
	fprintf(stderr, "brdfkit%s%s: %s\n", command_word[0] ? " " : "", command_word, line);
}

/* path for a message: under a live build tree DIR.tmpXXXXXX (the registry),
 * shown under DIR, where the file goes; control characters as '?'. */
const char *bk_out_shown(const char *path, char *buf, size_t len)
{
	for (int k = 0; k < LIVE_MAX; k++) {
		size_t n = strlen(live[k].path);
		if (live[k].state == 2 && n > 10 && !strncmp(path, live[k].path, n) && path[n] == '/') {
			char p[8400];
			snprintf(p, sizeof p, "%.*s%s", (int)(n - 10), path, path + n); /* ".tmpXXXXXX" left out */
			return out_printable(p, buf, len);
		}
	}
	return out_printable(path, buf, len);
}
