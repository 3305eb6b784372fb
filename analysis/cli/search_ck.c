/*
 * search_ck.c — checkpoint files of brdfkit search (search_ck.h).
 */
#define _GNU_SOURCE /* O_TMPFILE (a check that has a fallback), flock: Linux */
#include "search_ck.h"
#include "cli.h"
#include "islands.h"
#include "out.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

/* A save goes through the one safe-write module (out.h): bk_out_open makes
 * the temporary beside PATH, named by its inode and locked from its
 * creation, after removing the temporaries of saves to PATH that dead runs
 * left; the text is written and synced before any rename; the signal
 * handler removes a live temporary. What a checkpoint adds: the check for a
 * live run's checkpoint at PATH, the previous file kept (islands' .prev),
 * and the lock kept after the rename (held_fd). */

/* Writes text into a temporary beside path and syncs it to disk. 0, or -1
 * with "PATH: cannot write: REASON" in err. */
static int ck_write(bk_out *o, const char *path, const char *text, size_t len, char *err, size_t errlen)
{
	if (bk_out_open(o, path, err, errlen))
		return -1;
	if (bk_out_write_all(fileno(o->f), text, len) != 0 || fsync(fileno(o->f)) != 0) {
		int e = errno;
		snprintf(err, errlen, "%s: cannot write: %s", path, bk_out_errtext(e));
		bk_out_abort(o);
		return -1;
	}
	return 0;
}

/* The checkpoint this process wrote last, kept open with its flock(LOCK_EX)
 * from the rename to the next save or the end of the run: as the marker of
 * an --out directory, it tells a second run given the same --checkpoint that
 * the file is another's (a rename gives the path a new inode each save, so
 * the lock moves with it). */
static int held_fd = -1;
static dev_t held_dev;
static ino_t held_ino;

/* Whether the checkpoint at path is locked by another live run (not ours). */
static int locked_by_another(const char *path)
{
	int fd = open(path, O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
	struct stat st;
	int busy = 0;
	if (fd < 0)
		return 0;
	if (fstat(fd, &st) == 0 && !(held_fd >= 0 && st.st_dev == held_dev && st.st_ino == held_ino))
		busy = flock(fd, LOCK_EX | LOCK_NB) != 0 && errno == EWOULDBLOCK;
	close(fd); /* a probe's lock goes with it */
	return busy;
}

#define LOCKED_TEXT "another brdfkit search is writing it (it is locked); give each run its own --checkpoint"

/* Puts the written temporary at its path (after renaming an existing file at
 * path to keep, unless keep is NULL) and syncs the directory; the new file's
 * lock is held from then on. 0, or -1 (err). */
static int ck_commit(bk_out *o, const char *keep, char *err, size_t errlen)
{
	if (locked_by_another(o->path)) { /* two runs started together: the first to save keeps the path */
		snprintf(err, errlen, "%s: " LOCKED_TEXT, o->path);
		bk_out_abort(o);
		return -1;
	}
	if (keep && rename(o->path, keep) != 0 && errno != ENOENT) {
		snprintf(err, errlen, "%.200s: cannot keep it as %.200s: %s", o->path, keep, bk_out_errtext(errno));
		bk_out_abort(o);
		return -1;
	}
	int fd, rc = bk_out_commit_held(o, &fd, err, errlen);
	struct stat st;
	if (fd >= 0 && fstat(fd, &st) == 0) { /* the new file's lock held, the previous one's dropped */
		if (held_fd >= 0)
			close(held_fd);
		held_fd = fd;
		held_dev = st.st_dev;
		held_ino = st.st_ino;
	} else if (fd >= 0) {
		close(fd);
	}
	return rc;
}

/* ---- checks before the work ------------------------------------------------- */

/* path as it will resolve: the real path of its directory, then its last
 * part (path itself need not exist); with whole, path's own real path when
 * it exists (a directory given by a symlink or with trailing slashes).
 * 0, or -1 (errno). */
static int resolved(const char *path, int whole, char *buf)
{
	char p[4096], dir[4096];
	const char *base;
	snprintf(p, sizeof p, "%s", path);
	for (size_t n = strlen(p); n > 1 && p[n - 1] == '/'; n--)
		p[n - 1] = '\0';
	if (whole && realpath(p, buf))
		return 0;
	base = bk_out_split(p, dir, sizeof dir);
	char real[PATH_MAX];
	if (!realpath(dir, real))
		return -1;
	if (snprintf(buf, PATH_MAX, "%s/%s", strcmp(real, "/") ? real : "", base) >= PATH_MAX) {
		errno = ENAMETOOLONG;
		return -1;
	}
	return 0;
}

/* Whether path lies in the directory out, or is out: it would go when the
 * result is swapped in (out.h). */
static int inside(const char *path, const char *out)
{
	char rp[PATH_MAX], ro[PATH_MAX];
	if (!out || resolved(path, 0, rp) || resolved(out, 1, ro))
		return 0;
	size_t n = strlen(ro);
	return strncmp(rp, ro, n) == 0 && (rp[n] == '\0' || rp[n] == '/');
}

/* A file at path that a checkpoint may replace: a regular file that begins
 * as brdfkit's checkpoints do. 0 (also when nothing is there), or -1 (err). */
static int replaceable(const char *path, char *err, size_t errlen)
{
	struct stat st;
	if (lstat(path, &st) != 0) /* nothing there (or no directory: said next) */
		return errno == ENOENT || errno == ENOTDIR ? 0 : (snprintf(err, errlen, "%s: %s", path, bk_out_errtext(errno)), -1);
	if (!S_ISREG(st.st_mode)) {
		snprintf(err, errlen, "%s: exists and is not a regular file", path);
		return -1;
	}
	char head[9] = "";
	FILE *f = fopen(path, "r");
	size_t n = f ? fread(head, 1, 8, f) : 0;
	if (f)
		fclose(f);
	if (st.st_size > 0 && (n < 8 || memcmp(head, "brdfkit-", 8))) {
		snprintf(err, errlen, "%s: exists and is not a brdfkit checkpoint (not replaced)", path);
		return -1;
	}
	return 0;
}

int ck_check_write(const char *path, const char *out, char *err, size_t errlen)
{
	char dir[4096];
	const char *base;
	base = bk_out_split(path, dir, sizeof dir);
	if (!*base || !strcmp(base, ".") || !strcmp(base, "..")) {
		snprintf(err, errlen, "%s: not a file name", path);
		return -1;
	}
	if (inside(path, out)) {
		snprintf(err, errlen, "%s: inside --out %s, which is replaced whole at the end (the checkpoint would go "
		         "with it): put it elsewhere", path, out);
		return -1;
	}
	if (replaceable(path, err, errlen))
		return -1;
	if (locked_by_another(path)) {
		snprintf(err, errlen, "%s: " LOCKED_TEXT, path);
		return -1;
	}
	struct stat st;
	int found = stat(dir, &st) == 0;
	if (!found || !S_ISDIR(st.st_mode)) {
		snprintf(err, errlen, "%s: cannot create: %s", path, bk_out_errtext(found ? ENOTDIR : errno));
		return -1;
	}
	/* a file made and dropped (unnamed: nothing is left), else the permission alone */
	int fd = open(dir, O_TMPFILE | O_WRONLY | O_CLOEXEC, 0600);
	if (fd >= 0) {
		close(fd);
		return 0;
	}
	if ((errno == EOPNOTSUPP || errno == EISDIR || errno == EINVAL) && access(dir, W_OK | X_OK) == 0)
		return 0;
	snprintf(err, errlen, "%s: cannot create: %s", path, bk_out_errtext(errno));
	return -1;
}

int ck_check_read(const char *path, const char *out, int must_exist, char *err, size_t errlen)
{
	if (inside(path, out)) {
		snprintf(err, errlen, "%s: inside --out %s, which is replaced whole at the end (the checkpoint would go "
		         "with it): move it elsewhere first", path, out);
		return -1;
	}
	if (!must_exist)
		return 0;
	/* a FIFO or a device is refused, not opened blocking; /dev/zero is no
	 * directory, so the reason is bk_in_open's, not an errno's */
	char reason[96];
	int fd = bk_in_open(path, reason, sizeof reason);
	if (fd < 0) {
		snprintf(err, errlen, "%s: cannot be read: %s", path, fd == -1 ? bk_out_errtext(errno) : reason);
		return -1;
	}
	close(fd);
	return 0;
}

/* ---- the checkpoint of a search -------------------------------------------------- */

/* The checkpoint's text: header (an island's line, or NULL), then the
 * search's state (malloc'd into *text). 0, or -1 (out of memory). */
int ck_search_text(const bk_search *S, const char *header, char **text, size_t *len)
{
	*text = NULL;
	FILE *m = open_memstream(text, len);
	if (!m)
		return -1;
	if (header)
		fputs(header, m);
	int bad = bk_search_save(S, m);
	if (fclose(m) || bad) {
		free(*text);
		*text = NULL;
		return -1;
	}
	return 0;
}

/* A checkpoint that cannot be written is an error, intermediate ones too:
 * the run stops (the last one written stays whole, and --resume goes on
 * from it), never a shorter run that looks whole. */
int ck_search_save(const bk_search *S, const char *path, char *err, size_t errlen)
{
	char *text;
	size_t len;
	bk_out c;
	if (ck_search_text(S, NULL, &text, &len)) {
		snprintf(err, errlen, "%s: out of memory", path);
		return -1;
	}
	int rc = ck_write(&c, path, text, len, err, errlen) || ck_commit(&c, NULL, err, errlen) ? -1 : 0;
	free(text);
	return rc;
}

/* ---- the checkpoints of islands (an MPI job: islands.h) ------------------------ */

/* A rank's checkpoint is FILE.RANK, with the previous round kept as
 * FILE.RANK.prev: a job killed while the ranks commit a round leaves each
 * rank the round before it at least, and a resume takes the newest round
 * every rank has (save_islands, load_islands). */
#define ISLAND_MAGIC "brdfkit-island-checkpoint 1"

static void island_path(const char *base, int r, const char *suffix, char *buf, size_t len)
{
	snprintf(buf, len, "%s.%d%s", base, r, suffix);
}

/* Every rank's failure text (empty: none) printed by rank 0, one line each.
 * Collective. Returns 1. */
int ck_islands_fail(const char *what, const char *mine)
{
	int K = isl_size();
	char (*all)[256] = isl_rank() == 0 ? calloc((size_t)K, 256) : NULL;
	isl_gather_text(mine, all);
	for (int r = 0; all && r < K; r++)
		if (all[r][0])
			fprintf(stderr, "search: %s: rank %d: %s\n", what, r, all[r]);
	if (isl_rank() == 0 && !all)
		fprintf(stderr, "search: %s failed on some rank (out of memory for the messages)\n", what);
	free(all);
	return 1;
}

/* The round a checkpoint file holds: -1 absent, -2 not one of this job's. */
static long island_round(const char *path, const ck_islands *J)
{
	FILE *f = fopen(path, "r");
	if (!f)
		return errno == ENOENT ? -1 : -2;
	int r, k;
	long round, m, n;
	int ok = fscanf(f, ISLAND_MAGIC " island %d of %d round %ld migrate %ld migrants %ld", &r, &k, &round, &m, &n) == 5;
	fclose(f);
	return ok && r == isl_rank() && k == isl_size() && m == J->migrate && n == J->migrants ? round : -2;
}

/* Two phases, so that no rank moves to round `round` before all have it on
 * disk: each writes a temporary; only when all succeeded does each keep its
 * last round as .prev and rename the new one into place. Collective. */
int ck_islands_save(const ck_islands *J, const bk_search *S, long round)
{
	char path[4096], prev[4112], err[256] = "", head[256];
	int R = isl_rank();
	island_path(J->checkpoint, R, "", path, sizeof path);
	island_path(J->checkpoint, R, ".prev", prev, sizeof prev);
	snprintf(head, sizeof head, ISLAND_MAGIC " island %d of %d round %ld migrate %ld migrants %ld\n", R, isl_size(),
	         round, J->migrate, J->migrants);
	char *text;
	size_t len;
	bk_out c;
	int ok = ck_search_text(S, head, &text, &len) == 0;
	if (!ok)
		snprintf(err, sizeof err, "%.200s: out of memory", path);
	ok = ok && ck_write(&c, path, text, len, err, sizeof err) == 0;
	free(text);
	if (isl_any(!ok)) {
		if (ok)
			bk_out_abort(&c);
		return ck_islands_fail("--checkpoint", ok ? "" : err);
	}
	ok = ck_commit(&c, prev, err, sizeof err) == 0;
	return isl_any(!ok) ? ck_islands_fail("--checkpoint", ok ? "" : err) : 0;
}

/* The newest round every rank has, loaded. Collective. */
int ck_islands_load(const ck_islands *J, bk_search *S, long *round)
{
	char path[4096], prev[4112], err[512] = "";
	int R = isl_rank();
	island_path(J->resume, R, "", path, sizeof path);
	island_path(J->resume, R, ".prev", prev, sizeof prev);
	long cur = island_round(path, J), old = island_round(prev, J);
	long want = isl_min(cur > old ? cur : old);
	const char *from = cur == want ? path : old == want ? prev : NULL;
	int ok = want >= 0 && from;
	if (!ok)
		snprintf(err, sizeof err, "%.200s: no checkpoint of this job's round %ld (island %d of %d, --migrate %ld, "
		         "--migrants %ld; a resume needs the same ranks and options)", path, want, R, isl_size(),
		         J->migrate, J->migrants);
	if (ok) {
		FILE *f = fopen(from, "r");
		char line[256];
		ok = f && fgets(line, sizeof line, f) && bk_search_load(S, f, err, sizeof err) == 0;
		if (!ok && f) {
			char why[400];
			snprintf(why, sizeof why, "%.390s", err);
			snprintf(err, sizeof err, "%.100s: %.300s", from, why);
		} else if (!f) {
			snprintf(err, sizeof err, "%.200s: cannot be read", from);
		}
		if (f)
			fclose(f);
	}
	if (isl_any(!ok))
		return ck_islands_fail("--resume", ok ? "" : err);
	*round = want;
	if (R == 0)
		fprintf(stderr, "search: resumed %d islands at round %ld (%ld fits)\n", isl_size(), want,
		        isl_sum(bk_search_evals(S)));
	else
		isl_sum(bk_search_evals(S));
	return 0;
}

/* The checkpoint files, checked before any work (else a bad path is found
 * when the first is written, minutes on, or the last, with the whole run
 * lost): each rank its own, FILE.RANK and FILE.RANK.prev on islands. Then
 * the temporaries of killed saves to them that prove themselves ours are
 * removed (search_ck.h). Collective. 0, or 1 after the message. */
int ck_islands_check(const ck_islands *J)
{
	const ck_islands *a = J;
	char err[8800] = "", path[4096], prev[4112]; /* room for two paths in a message */
	int K = isl_size(), bad = 0, own = a->islands; /* FILE.RANK: each island its own */
	/* one search on every rank (--split-fits): FILE, which rank 0 alone
	 * writes and every rank reads */
	int writes = own || isl_rank() == 0;
	for (int pass = 0; pass < 2; pass++) {
		const char *base = pass ? a->resume : a->checkpoint;
		island_path(base ? base : "", isl_rank(), "", path, sizeof path);
		island_path(base ? base : "", isl_rank(), ".prev", prev, sizeof prev);
		if (base && pass == 0 && writes)
			bad = own ? ck_check_write(path, a->out, err, sizeof err) || ck_check_write(prev, a->out, err, sizeof err)
			          : ck_check_write(base, a->out, err, sizeof err);
		else if (base && pass == 1)
			bad = own ? ck_check_read(path, a->out, 0, err, sizeof err) || ck_check_read(prev, a->out, 0, err, sizeof err)
			          : ck_check_read(base, a->out, 1, err, sizeof err);
		const char *what = pass ? "--resume" : "--checkpoint";
		if (K > 1 && isl_any(bad))
			return ck_islands_fail(what, bad ? err : "");
		if (bad)
			return cli_fail("search", "%s %s", what, err);
		if (base && writes) /* the rank's own (bk_out_open cleans its path at each save too) */
			bk_out_clean(own ? path : base);
	}
	return 0;
}
