/*
 * out_swap.c — an output directory's commit: the new tree swapped in with one
 * rename, the previous result removed as its marker lists it (out.h).
 */
#define _GNU_SOURCE /* renameat2: Linux; it has a fallback */
#include "out.h"
#include "out_int.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

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
	return out_printable(path, buf, len);
}

/* The previous result, left at prev beside DIR by the swap: removed as its
 * marker lists it (checked under its lock before the swap). Should something
 * have been added since, it is kept whole, with a line saying where. */
static void retire(int pfd, const bk_out_dir *d, const char *prev, const look *k)
{
	char first[4096] = "", p[512], q[512];
	int dfd = openat(pfd, prev, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
	int r = dfd < 0 ? (errno == ENOENT ? 0 : -1) : out_remove_listed(pfd, prev, dfd, &k->m, first, sizeof first);
	int e = errno;
	if (dfd >= 0)
		close(dfd);
	if (r > 0)
		out_notice("--out %s: the previous result is kept at %s: it holds '%s', which brdfkit did not write",
		       out_printable(d->name, p, sizeof p), sibling(d, prev, q, sizeof q), out_printable(first, first, sizeof first));
	else if (r < 0)
		out_notice("--out %s: the previous result could not be removed from %s: %s", out_printable(d->name, p, sizeof p),
		       sibling(d, prev, q, sizeof q), bk_out_errtext(e));
}

int bk_out_dir_commit(bk_out_dir *d, char *err, size_t errlen)
{
	const char *base, *tbase = strrchr(d->tmp, '/') ? strrchr(d->tmp, '/') + 1 : d->tmp;
	char prev[sizeof d->tmp] = "";
	int pfd = out_open_parent(d->path, &base);
	int tfd = open(d->tmp, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
	int bad = pfd < 0 || tfd < 0 || out_write_list(d->lock, tfd) != 0;
	int e = errno;
	if (bad) {
		if (pfd >= 0)
			close(pfd);
		if (tfd >= 0)
			close(tfd);
		bk_out_dir_abort(d);
		snprintf(err, errlen, "%s: writing the results failed: %s", d->name, bk_out_errtext(e));
		return -1;
	}
	/* Try until one swap went through: another run may commit to the same
	 * path between our look and our rename; its whole result is then what we
	 * replace. */
	look k = {.mfd = -1};
	int rc = -1;
	for (int tries = 0; rc && tries < 1000; tries++) {
		out_look_done(&k);
		int r = out_classify(pfd, base, d->name, &k);
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
		out_refusal(&k, d->name, "cannot replace", err, errlen);
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
			         bk_out_errtext(e), prev[0] ? "; the previous result stays at " : "",
			         prev[0] ? sibling(d, prev, p, sizeof p) : "", prev[0] ? " until the next run" : "");
		} else {
			if (prev[0])
				retire(pfd, d, prev, &k);
			unlinkat(tfd, TEMPS, 0); /* nothing left to record */
		}
	}
	out_look_done(&k);
	close(tfd);
	close(pfd);
	return rc;
}
