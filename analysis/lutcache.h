/*
 * lutcache.h — reference tables kept on disk between runs (BRDFKIT_TABLE_CACHE).
 *
 * A LUT row's texels are baked by the reference integrator at tol 1e-8
 * (lutscore.c): a 128² table is about two CPU seconds, and every brdfkit
 * compare, search --fetch-cost and scene bakes the tables it scores anew,
 * the same tables run after run; so is every env, ms and sheen target's
 * grid of reference integrals (bk_lutcache_target_build). With BRDFKIT_TABLE_CACHE naming a directory,
 * a table baked once is written there (one file per table, through the one
 * safe writer, analysis/out.h) and a later run reads it instead of baking it:
 * the same bits, so every output is the same bytes with or without it. A
 * file is taken only when its key (what the bake depends on: layout, Smith
 * form, channel, tolerance), its length and its checksum all match, and the
 * caller re-bakes a few texels and compares them bit for bit, so a file left
 * by another build whose integrator differs is baked over, not read.
 * make test points every suite at one fresh directory (Makefile).
 * Unset, or any failure to read or write there: the table is baked, as
 * without the cache; nothing is reported (a cache is never the answer).
 */
#ifndef BK_LUTCACHE_H
#define BK_LUTCACHE_H

#include "target.h"

#include <stddef.h>

/* The directory of BRDFKIT_TABLE_CACHE, NULL when unset or empty. */
const char *bk_lutcache_dir(void);
/* Reads the n doubles stored under key into t: 0, or -1 (absent, damaged,
 * another key). */
int bk_lutcache_read(const char *dir, const char *key, double *t, size_t n);
/* Stores t under key (atomically; a failure leaves no file and is ignored). */
void bk_lutcache_write(const char *dir, const char *key, const double *t, size_t n);
/* The key's lock (an flock on its .lock file beside the table), held while
 * one process makes what it would store, so that others that need the same
 * table at once wait for the file instead of making it too (make test's
 * suites start together, on an empty cache): a descriptor, or -1 where it
 * cannot be had (the caller then makes it without). No caller holds two. */
int bk_lutcache_lock(const char *dir, const char *key);
void bk_lutcache_unlock(int fd);
/* The n doubles kept under key into t, the one way every table is had:
 * cached(ctx, t) reads and checks the file (0: taken); failing that, under
 * the key's lock it looks again, then make(ctx, t) makes them (0, or -1:
 * nothing stored) and they are stored. dir NULL: make alone. 0, or -1 when
 * make failed. */
int bk_lutcache_fetch(const char *dir, const char *key, double *t, size_t n, int (*cached)(void *ctx, double *t),
                      int (*make)(void *ctx, double *t), void *ctx);

/* bk_target_build, the reference integrals of an env, ms or sheen target
 * (target.h, bk_target_reference: 4,096 integrals for a default 64x64 env,
 * about half a CPU second) taken from the cache when it holds them, made and
 * stored there when it does not; any other target, a grid over 256² cells,
 * or no cache: the build itself. The same bits either way, and the same
 * errors; progress only while integrals are made. */
int bk_lutcache_target_build(const bk_target_options *o, bk_samples *s, bk_progress_fn progress, void *ctx,
                             char *err, size_t errlen);
/* The key those integrals are kept under: what they depend on. */
void bk_lutcache_target_key(const bk_target_options *o, char *key, size_t len);

#endif
