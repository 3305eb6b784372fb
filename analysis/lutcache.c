/*
 * lutcache.c — reference tables kept on disk between runs (lutcache.h).
 *
 * A file: the line "brdfkit reference table 1", the key on a line of its
 * own, then the n doubles as this machine stores them (x86-64: IEEE binary64,
 * little-endian) and their FNV-1a checksum. Named by the key's hash, so two
 * keys never share a file however they are spelt; the key inside is compared
 * whole, so a hash collision reads as a miss.
 */
#include "lutcache.h"
#include "expr.h"
#include "out.h"

#include <errno.h>
#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <unistd.h>

#define MAGIC "brdfkit reference table 1\n"

const char *bk_lutcache_dir(void)
{
	const char *d = getenv("BRDFKIT_TABLE_CACHE");
	return d && *d ? d : NULL;
}

static int path_ext(const char *dir, const char *key, const char *ext, char *path, size_t len)
{
	unsigned long long h = (unsigned long long)bk_hash_bytes(BK_HASH_INIT, key, strlen(key));
	int w = snprintf(path, len, "%s/table-%016llx.%s", dir, h, ext);
	return w > 0 && (size_t)w < len ? 0 : -1;
}
static int path_of(const char *dir, const char *key, char *path, size_t len)
{
	return path_ext(dir, key, "bin", path, len);
}

int bk_lutcache_lock(const char *dir, const char *key)
{
	char path[4096];
	if (!dir || path_ext(dir, key, "lock", path, sizeof path))
		return -1;
	int fd = open(path, O_RDWR | O_CREAT | O_CLOEXEC, 0644);
	if (fd < 0)
		return -1;
	while (flock(fd, LOCK_EX)) /* EINTR: a signal the tool handles; anything else: no lock */
		if (errno != EINTR) {
			close(fd);
			return -1;
		}
	return fd;
}

void bk_lutcache_unlock(int fd)
{
	if (fd >= 0)
		close(fd); /* closing the one descriptor releases its lock */
}

int bk_lutcache_fetch(const char *dir, const char *key, double *t, size_t n, int (*cached)(void *ctx, double *t),
                      int (*make)(void *ctx, double *t), void *ctx)
{
	if (dir && !cached(ctx, t))
		return 0;
	int lock = bk_lutcache_lock(dir, key); /* another process may be making it: its file, once written */
	if (lock >= 0 && !cached(ctx, t)) {
		bk_lutcache_unlock(lock);
		return 0;
	}
	int rc = make(ctx, t);
	if (!rc)
		bk_lutcache_write(dir, key, t, n);
	bk_lutcache_unlock(lock);
	return rc ? -1 : 0;
}

int bk_lutcache_read(const char *dir, const char *key, double *t, size_t n)
{
	char path[4096], why[256];
	if (!dir || path_of(dir, key, path, sizeof path))
		return -1;
	int fd = bk_in_open(path, why, sizeof why);
	if (fd < 0)
		return -1;
	FILE *f = fdopen(fd, "rb");
	if (!f) {
		close(fd);
		return -1;
	}
	size_t kl = strlen(key), hl = strlen(MAGIC);
	char *head = malloc(hl + kl + 1);
	uint64_t sum = 0;
	int ok = head && fread(head, 1, hl + kl + 1, f) == hl + kl + 1 && !memcmp(head, MAGIC, hl) &&
	         !memcmp(head + hl, key, kl) && head[hl + kl] == '\n' && fread(t, sizeof *t, n, f) == n &&
	         fread(&sum, sizeof sum, 1, f) == 1 && fgetc(f) == EOF && sum == bk_hash_bytes(BK_HASH_INIT, t, sizeof *t * n);
	free(head);
	fclose(f);
	return ok ? 0 : -1;
}

void bk_lutcache_write(const char *dir, const char *key, const double *t, size_t n)
{
	char path[4096], err[512];
	bk_out o;
	if (!dir || path_of(dir, key, path, sizeof path) || bk_out_open(&o, path, err, sizeof err))
		return;
	uint64_t sum = bk_hash_bytes(BK_HASH_INIT, t, sizeof *t * n);
	if (fputs(MAGIC, o.f) < 0 || fputs(key, o.f) < 0 || fputc('\n', o.f) < 0 || fwrite(t, sizeof *t, n, o.f) != n ||
	    fwrite(&sum, sizeof sum, 1, o.f) != 1)
		bk_out_abort(&o);
	else
		(void)bk_out_commit(&o, err, sizeof err); /* a failed commit leaves nothing (out.h) */
}

/* Targets of up to 256² cells are kept (a 1 MB file; the default 64x64 env
 * is 64 KB): a larger grid is a one-off study, and a 4096² one would write
 * 268 MB. */
#define TARGET_MAX_CELLS 65536

/* env and ms share the DFG's integrals; sheen reads no Smith form. */
void bk_lutcache_target_key(const bk_target_options *o, char *key, size_t len)
{
	int sheen = o->kind == BK_TARGET_SHEEN;
	snprintf(key, len, "target %s smith %d nx %d nr %d x %a %a r %a %a tol %a", sheen ? "sheen" : "dfg",
	         sheen ? 0 : (int)o->smith, o->nx, o->nr, o->x_lo > 0 ? o->x_lo : 0.0, o->x_hi, o->r_lo, o->r_hi, 1e-8);
}

/* Three cells of a file's integrals made again here (the first, the middle,
 * the last) must equal it bit for bit, as bk_lut_table_cached's texels: a
 * file another integrator wrote is made over, not read. */
static int target_probe(const bk_target_options *o, const double *AB, size_t n)
{
	const size_t cell[3] = {0, n / 2, n - 1};
	for (int q = 0; q < 3; q++) {
		double A, B;
		if (bk_target_reference_cell(o, cell[q], &A, &B) || memcmp(&A, &AB[cell[q]], sizeof A) ||
		    memcmp(&B, &AB[n + cell[q]], sizeof B))
			return -1;
	}
	return 0;
}

/* bk_lutcache_fetch's two steps for a target's integrals */
typedef struct target_job {
	const bk_target_options *o;
	const char *dir;
	size_t n;
	bk_progress_fn progress;
	void *ctx;
	char *err;
	size_t errlen;
	char key[320];
} target_job;

static int target_cached(void *ctx, double *AB)
{
	const target_job *j = ctx;
	return bk_lutcache_read(j->dir, j->key, AB, 2 * j->n) || target_probe(j->o, AB, j->n) ? -1 : 0;
}

static int target_make(void *ctx, double *AB)
{
	const target_job *j = ctx;
	return bk_target_reference(j->o, AB, j->progress, j->ctx, j->err, j->errlen);
}

int bk_lutcache_target_build(const bk_target_options *o, bk_samples *s, bk_progress_fn progress, void *ctx,
                             char *err, size_t errlen)
{
	const char *dir = bk_lutcache_dir();
	size_t n = bk_target_reference_cells(o);
	double *AB = dir && n && n <= TARGET_MAX_CELLS && !o->reference ? malloc(sizeof *AB * 2 * n) : NULL;
	if (!AB) /* no cache, nothing to keep in it (or too much), or no memory: the build as it is */
		return bk_target_build(o, s, progress, ctx, err, errlen);
	target_job j = {o, dir, n, progress, ctx, err, errlen, {0}};
	bk_lutcache_target_key(o, j.key, sizeof j.key);
	if (bk_lutcache_fetch(dir, j.key, AB, 2 * n, target_cached, target_make, &j)) {
		free(AB); /* the build fails on the same cell with the same message */
		return bk_target_build(o, s, NULL, NULL, err, errlen);
	}
	bk_target_options t = *o;
	t.reference = AB;
	int rc = bk_target_build(&t, s, NULL, NULL, err, errlen); /* progress: the integrals' (above) */
	free(AB);
	return rc;
}
