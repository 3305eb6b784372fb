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

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define MAGIC "brdfkit reference table 1\n"

const char *bk_lutcache_dir(void)
{
	const char *d = getenv("BRDFKIT_TABLE_CACHE");
	return d && *d ? d : NULL;
}

static int path_of(const char *dir, const char *key, char *path, size_t len)
{
	unsigned long long h = (unsigned long long)bk_hash_bytes(BK_HASH_INIT, key, strlen(key));
	int w = snprintf(path, len, "%s/table-%016llx.bin", dir, h);
	return w > 0 && (size_t)w < len ? 0 : -1;
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
