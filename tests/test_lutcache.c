/*
 * test_lutcache.c — the reference tables kept on disk (analysis/lutcache.c,
 * BRDFKIT_TABLE_CACHE): a table written there is read back bit for bit and
 * equals the reference integrator's texels (bk_dfg at the layout's texel
 * centres, called here); a damaged file, a truncated one, one with a byte
 * more, another key's file under this name, and a table whose probed texel
 * differs by one ulp (another integrator's) are all refused; a LUT scored
 * with the cache set writes the table there and scores the same bits as
 * without it; and so do the env, ms and sheen targets' reference integrals
 * (bk_lutcache_target_build), each sample the integrator's value at its
 * cell's centre, called here.
 */
#include "brdf.h"
#include "compare.h"
#include "fixture_tmpdir.h"
#include "lutcache.h"
#include "target.h"

#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#define NU 6
#define NR 5

/* The table of L by the reference integrator, called texel by texel here. */
static void baked(const bk_lut_layout *L, double *AB)
{
	size_t n = (size_t)L->nu * (size_t)L->nr;
	for (int j = 0; j < L->nr; j++)
		for (int i = 0; i < L->nu; i++) {
			size_t k = (size_t)j * (size_t)L->nu + (size_t)i;
			cr_assert_eq(bk_dfg(bk_lut_texel_nov(L, i), bk_lut_texel_r(L, j), BK_SMITH_CORRELATED, BK_DFG_TOL, &AB[k],
			                    &AB[n + k], NULL),
			             0);
		}
}

/* The file the table of L is stored in (the only file in dir). */
static void only_file(const char *dir, char *path, size_t len)
{
	char cmd[256];
	snprintf(cmd, sizeof cmd, "ls %s | grep '[.]bin$'", dir); /* beside it, its lock (lutcache.h) */
	FILE *p = popen(cmd, "r");
	cr_assert_not_null(p);
	char name[128];
	cr_assert_not_null(fgets(name, sizeof name, p));
	cr_assert_null(fgets((char[128]){0}, 128, p), "one file in %s", dir);
	pclose(p);
	name[strcspn(name, "\n")] = 0;
	snprintf(path, len, "%s/%s", dir, name);
}

static long file_size(const char *path)
{
	FILE *f = fopen(path, "rb");
	cr_assert_not_null(f);
	fseek(f, 0, SEEK_END);
	long n = ftell(f);
	fclose(f);
	return n;
}

/* Byte at from the end of path flipped (from = 1: the last byte). */
static void flip(const char *path, long from)
{
	FILE *f = fopen(path, "r+b");
	cr_assert_not_null(f);
	fseek(f, -from, SEEK_END);
	int c = fgetc(f);
	fseek(f, -from, SEEK_END);
	fputc(c ^ 0x01, f);
	fclose(f);
}

Test(lutcache, read_back_bit_for_bit_and_every_damage_refused)
{
	char dir[64], path[256], key[256];
	fx_tmpdir_make(dir, sizeof dir, "lutcache");
	bk_lut_layout L = {NU, NR, 0.25, 1, BK_LUT_WARP_SQRT, NAN};
	size_t n = NU * NR;
	double ref[2 * NU * NR], got[2 * NU * NR];
	baked(&L, ref);
	cr_assert_eq(bk_lut_table_cached(dir, &L, BK_SMITH_CORRELATED, 0, got), -1, "an empty directory holds nothing");
	bk_lut_table_key(&L, BK_SMITH_CORRELATED, 0, key, sizeof key);
	bk_lutcache_write(dir, key, ref, 2 * n);
	cr_assert_eq(bk_lut_table_cached(dir, &L, BK_SMITH_CORRELATED, 0, got), 0);
	cr_assert_eq(memcmp(got, ref, sizeof ref), 0, "read back bit for bit");
	/* another table's key (the separable Smith, the cloth channel, another
	 * range) does not find it */
	bk_lut_layout L2 = L;
	L2.r_lo = 0.3;
	cr_assert_eq(bk_lut_table_cached(dir, &L, BK_SMITH_SEPARABLE, 0, got), -1);
	cr_assert_eq(bk_lut_table_cached(dir, &L, BK_SMITH_CORRELATED, 1, got), -1);
	cr_assert_eq(bk_lut_table_cached(dir, &L2, BK_SMITH_CORRELATED, 0, got), -1);

	only_file(dir, path, sizeof path);
	long size = file_size(path);
	cr_assert_eq(size, (long)(strlen("brdfkit reference table 1\n") + strlen(key) + 1 + sizeof ref + 8));
	/* a texel's byte flipped (the checksum no longer agrees), and back */
	flip(path, 8 + 3);
	cr_assert_eq(bk_lut_table_cached(dir, &L, BK_SMITH_CORRELATED, 0, got), -1, "damaged data read");
	flip(path, 8 + 3);
	cr_assert_eq(bk_lut_table_cached(dir, &L, BK_SMITH_CORRELATED, 0, got), 0, "the control: the file restored");
	/* the checksum's byte flipped */
	flip(path, 1);
	cr_assert_eq(bk_lut_table_cached(dir, &L, BK_SMITH_CORRELATED, 0, got), -1, "damaged checksum read");
	flip(path, 1);
	/* a byte more, a byte less */
	FILE *f = fopen(path, "ab");
	fputc(0, f);
	fclose(f);
	cr_assert_eq(bk_lut_table_cached(dir, &L, BK_SMITH_CORRELATED, 0, got), -1, "a longer file read");
	cr_assert_eq(truncate(path, size - 1), 0);
	cr_assert_eq(bk_lut_table_cached(dir, &L, BK_SMITH_CORRELATED, 0, got), -1, "a truncated file read");
	/* another key's table under this name: its key line differs */
	char key2[256], path2[300];
	bk_lut_table_key(&L2, BK_SMITH_CORRELATED, 0, key2, sizeof key2);
	bk_lutcache_write(dir, key2, ref, 2 * n);
	cr_assert_eq(remove(path), 0);
	char cmd[700];
	snprintf(cmd, sizeof cmd, "mv %s/table-*.bin %s", dir, path);
	cr_assert_eq(system(cmd), 0);
	snprintf(path2, sizeof path2, "%s", path);
	cr_assert_eq(bk_lut_table_cached(dir, &L, BK_SMITH_CORRELATED, 0, got), -1, "another key's file read");
	cr_assert_eq(remove(path2), 0);

	/* a table another integrator baked: whole, under this key, its checksum
	 * right, the middle texel's A one ulp off, caught by the probe; one ulp
	 * off in a texel no probe bakes again is the limit of the check (read) */
	double other[2 * NU * NR];
	memcpy(other, ref, sizeof ref);
	size_t mid = (size_t)(NR / 2) * NU + NU / 2;
	other[mid] = nextafter(other[mid], 2.0);
	bk_lutcache_write(dir, key, other, 2 * n);
	cr_assert_eq(bk_lut_table_cached(dir, &L, BK_SMITH_CORRELATED, 0, got), -1, "another integrator's table read");
	memcpy(other, ref, sizeof ref);
	other[n + mid] = nextafter(other[n + mid], 2.0); /* B of the same texel */
	bk_lutcache_write(dir, key, other, 2 * n);
	cr_assert_eq(bk_lut_table_cached(dir, &L, BK_SMITH_CORRELATED, 0, got), -1, "another integrator's B read");
	memcpy(other, ref, sizeof ref);
	other[1] = nextafter(other[1], 2.0);
	bk_lutcache_write(dir, key, other, 2 * n);
	cr_assert_eq(bk_lut_table_cached(dir, &L, BK_SMITH_CORRELATED, 0, got), 0, "texel (1, 0) is not probed");
	fx_tmpdir_remove(dir);
}

/* run(ctx) in a process of its own (a fresh per-process table cache), its
 * len bytes of answer read back into out; the child's exit status 0 and
 * the answer whole are asserted. */
static void in_child(int (*run)(void *ctx, void *out), void *ctx, void *out, size_t len)
{
	int fd[2];
	cr_assert_eq(pipe(fd), 0);
	pid_t pid = fork();
	cr_assert_geq(pid, 0);
	if (pid == 0)
		_exit(run(ctx, out) || write(fd[1], out, len) != (ssize_t)len);
	close(fd[1]);
	size_t got = 0;
	for (ssize_t k; got < len && (k = read(fd[0], (char *)out + got, len - got)) > 0;)
		got += (size_t)k;
	close(fd[0]);
	int st;
	cr_assert_eq(waitpid(pid, &st, 0), pid);
	cr_assert(WIFEXITED(st) && WEXITSTATUS(st) == 0 && got == len);
}

typedef struct score_job {
	const bk_lut_layout *L;
	const bk_samples *s;
	const char *dir;
} score_job;

static int score_run(void *ctx, void *out)
{
	const score_job *j = ctx;
	return (j->dir ? setenv("BRDFKIT_TABLE_CACHE", j->dir, 1) : unsetenv("BRDFKIT_TABLE_CACHE")) ||
	       bk_lut_score_layout(j->L, BK_LUT_FLOAT, BK_SMITH_CORRELATED, BK_F64, j->s, out, NULL);
}

/* L's float LUT scored on s in a process of its own, with
 * BRDFKIT_TABLE_CACHE = dir, or unset (dir NULL). */
static bk_fit_metrics score_in_child(const bk_lut_layout *L, const bk_samples *s, const char *dir)
{
	score_job j = {L, s, dir};
	bk_fit_metrics m;
	in_child(score_run, &j, &m, sizeof m);
	return m;
}

/* A score with the cache set writes the table (the reference integrator's
 * texels, bit for bit) and the next one reads it; both score the same bits
 * as a process without the cache; a wrong table planted in a texel no probe
 * bakes again changes the score, which proves the file is what was read. */
Test(lutcache, a_score_writes_the_table_and_the_next_reads_it)
{
	char dir[64], path[256], key[256];
	fx_tmpdir_make(dir, sizeof dir, "lutcache");
	bk_target_options o;
	bk_samples s;
	char err[256];
	bk_target_defaults(BK_TARGET_ENV, &o);
	o.nx = 7, o.nr = 5;
	cr_assert_eq(bk_target_build(&o, &s, NULL, NULL, err, sizeof err), 0, "%s", err);
	bk_lut_layout L = {NU, NR, 0, 1, BK_LUT_WARP_NONE, NAN};
	bk_fit_metrics plain = score_in_child(&L, &s, NULL);
	bk_fit_metrics first = score_in_child(&L, &s, dir);
	only_file(dir, path, sizeof path);
	double ref[2 * NU * NR], got[2 * NU * NR];
	baked(&L, ref);
	cr_assert_eq(bk_lut_table_cached(dir, &L, BK_SMITH_CORRELATED, 0, got), 0);
	cr_assert_eq(memcmp(got, ref, sizeof ref), 0, "the file holds the bake");
	bk_fit_metrics second = score_in_child(&L, &s, dir);
	cr_assert(!memcmp(&first.rmse, &plain.rmse, sizeof plain.rmse) && !memcmp(&first.max_abs, &plain.max_abs, 8));
	cr_assert(!memcmp(&second.rmse, &plain.rmse, sizeof plain.rmse) && !memcmp(&second.max_abs, &plain.max_abs, 8));
	/* A of texel (1, 0) doubled, the checksum right */
	ref[1] *= 2;
	bk_lut_table_key(&L, BK_SMITH_CORRELATED, 0, key, sizeof key);
	bk_lutcache_write(dir, key, ref, 2 * NU * NR);
	bk_fit_metrics planted = score_in_child(&L, &s, dir);
	cr_assert_neq(planted.rmse, plain.rmse, "the planted table was not read");
	bk_samples_free(&s);
	fx_tmpdir_remove(dir);
}

/* A table another process is baking is waited for, not baked again: with its
 * key's lock held here, a score started in a child finds no file, waits, and
 * then reads the table written here (planted: texel (1, 0)'s A doubled, which
 * no probe bakes again), so it scores what a child reading that file scores,
 * not the integrator's table. The control: a score that does not wait (a
 * cache of its own, the same layout) bakes the true table and scores apart
 * from the planted one. */
Test(lutcache, a_table_being_baked_is_waited_for)
{
	char dir[64], other[64], key[256], err[256];
	fx_tmpdir_make(dir, sizeof dir, "lutcache");
	fx_tmpdir_make(other, sizeof other, "lutcache");
	bk_target_options o;
	bk_samples s;
	bk_target_defaults(BK_TARGET_ENV, &o);
	o.nx = 7, o.nr = 5;
	cr_assert_eq(bk_target_build(&o, &s, NULL, NULL, err, sizeof err), 0, "%s", err);
	bk_lut_layout L = {NU, NR, 0, 1, BK_LUT_WARP_NONE, NAN};
	bk_lut_table_key(&L, BK_SMITH_CORRELATED, 0, key, sizeof key);
	int lock = bk_lutcache_lock(dir, key);
	cr_assert_geq(lock, 0);
	int go[2], fd[2];
	cr_assert_eq(pipe(go), 0);
	cr_assert_eq(pipe(fd), 0);
	pid_t pid = fork();
	cr_assert_geq(pid, 0);
	if (pid == 0) {
		bk_fit_metrics m;
		score_job j = {&L, &s, dir};
		close(go[0]);
		bk_lutcache_unlock(lock); /* the parent's lock is on the description fork shared: this copy goes */
		_exit(write(go[1], "s", 1) != 1 || score_run(&j, &m) || write(fd[1], &m, sizeof m) != (ssize_t)sizeof m);
	}
	close(go[1]);
	close(fd[1]);
	char c;
	cr_assert_eq(read(go[0], &c, 1), 1);
	close(go[0]);
	/* the child on its way into the lock: its first look finds no file */
	struct timespec pause = {0, 300000000};
	nanosleep(&pause, NULL);
	double ref[2 * NU * NR];
	baked(&L, ref);
	ref[1] *= 2;
	bk_lutcache_write(dir, key, ref, 2 * NU * NR);
	bk_lutcache_unlock(lock);
	bk_fit_metrics waited;
	size_t got = 0;
	for (ssize_t k; got < sizeof waited && (k = read(fd[0], (char *)&waited + got, sizeof waited - got)) > 0;)
		got += (size_t)k;
	close(fd[0]);
	int st;
	cr_assert_eq(waitpid(pid, &st, 0), pid);
	cr_assert(WIFEXITED(st) && WEXITSTATUS(st) == 0 && got == sizeof waited);
	bk_fit_metrics planted = score_in_child(&L, &s, dir), baked_here = score_in_child(&L, &s, other);
	cr_assert(!memcmp(&waited.rmse, &planted.rmse, sizeof planted.rmse), "the waiting score did not read the file");
	cr_assert_neq(baked_here.rmse, planted.rmse, "control: a score of its own reads the planted table too");
	bk_samples_free(&s);
	fx_tmpdir_remove(dir);
	fx_tmpdir_remove(other);
}

/* Sample i's exact value by the integrators, called here at the sample's own
 * NoV and r: env's A or B (split) or f0 A + B, ms's A + B, sheen's albedo. */
static double exact(const bk_target_options *o, const bk_samples *s, size_t i)
{
	double NoV = s->in[BK_IN_NOV][i], r = s->in[BK_IN_R][i], A, B;
	if (o->kind == BK_TARGET_SHEEN) {
		cr_assert_eq(bk_sheen_albedo(NoV, r, 1e-8, &A, NULL), 0);
		return A;
	}
	cr_assert_eq(bk_dfg(NoV, r, o->smith, 1e-8, &A, &B, NULL), 0);
	if (o->kind == BK_TARGET_MS)
		return A + B;
	if (o->env_f0_form)
		return s->in[BK_IN_F0][i] * A + B;
	return i < s->start[1] ? A : B;
}

static void same_samples(const bk_samples *a, const bk_samples *b, const char *what)
{
	cr_assert_eq(a->n, b->n, "%s", what);
	cr_assert(!memcmp(a->y, b->y, sizeof *a->y * a->n) && !memcmp(a->w, b->w, sizeof *a->w * a->n), "%s", what);
	for (int k = 0; k < BK_IN_COUNT; k++)
		cr_assert(!memcmp(a->in[k], b->in[k], sizeof *a->in[k] * a->n), "%s: input %d", what, k);
	cr_assert_str_eq(a->description, b->description, "%s", what);
}

typedef struct build_job {
	const bk_target_options *o;
	const char *dir;
	size_t n;
} build_job;

static int build_run(void *ctx, void *out)
{
	const build_job *j = ctx;
	bk_samples s;
	char err[256];
	if (setenv("BRDFKIT_TABLE_CACHE", j->dir, 1) || bk_lutcache_target_build(j->o, &s, NULL, NULL, err, sizeof err))
		return 1;
	int bad = s.n != j->n;
	if (!bad)
		memcpy(out, s.y, sizeof *s.y * j->n);
	bk_samples_free(&s);
	return bad;
}

/* The samples of o built in a process of its own with BRDFKIT_TABLE_CACHE =
 * dir (bk_lutcache_target_build reads the variable): their n values y. */
static void build_in_child(const bk_target_options *o, const char *dir, double *y, size_t n)
{
	build_job j = {o, dir, n};
	in_child(build_run, &j, y, sizeof *y * n);
}

/* env (split and in f0), ms and sheen built through the cache: the first
 * build writes the integrals, the second reads them, and both are the bits
 * of a build without it, each sample the integrator's value at its centre.
 * A file whose unprobed cell is doubled changes the samples (so the second
 * build did read the file), and one whose probed middle cell is one ulp off
 * is integrated over, not read. */
Test(lutcache, targets_built_through_the_cache_are_the_same_bits, .timeout = 120)
{
	bk_target_kind kinds[4] = {BK_TARGET_ENV, BK_TARGET_ENV, BK_TARGET_MS, BK_TARGET_SHEEN};
	for (int t = 0; t < 4; t++) {
		char dir[64], path[256], key[320], err[256];
		fx_tmpdir_make(dir, sizeof dir, "lutcache");
		bk_target_options o;
		bk_target_defaults(kinds[t], &o);
		o.nx = 7, o.nr = 5, o.x_lo = 0.05, o.r_lo = 0.2, o.r_hi = 0.9;
		o.env_f0_form = t == 1;
		bk_samples plain, first, second;
		cr_assert_eq(bk_target_build(&o, &plain, NULL, NULL, err, sizeof err), 0, "%s", err);
		for (size_t i = 0; i < plain.n; i++) {
			double e = exact(&o, &plain, i);
			cr_assert(!memcmp(&plain.y[i], &e, sizeof e), "%s sample %zu: %.17g, the integrator %.17g",
			          bk_target_name(o.kind), i, plain.y[i], e);
		}
		cr_assert_eq(setenv("BRDFKIT_TABLE_CACHE", dir, 1), 0);
		cr_assert_eq(bk_lutcache_target_build(&o, &first, NULL, NULL, err, sizeof err), 0, "%s", err);
		only_file(dir, path, sizeof path);
		cr_assert_eq(bk_lutcache_target_build(&o, &second, NULL, NULL, err, sizeof err), 0, "%s", err);
		cr_assert_eq(unsetenv("BRDFKIT_TABLE_CACHE"), 0);
		same_samples(&plain, &first, "the build that wrote the file");
		same_samples(&plain, &second, "the build that read it");

		/* a planted file: cell 1 (not probed) doubled, the checksum right */
		size_t n = bk_target_reference_cells(&o);
		double *AB = malloc(sizeof *AB * 2 * n), *y = malloc(sizeof *y * plain.n);
		cr_assert(AB && y && n == 35);
		cr_assert_eq(bk_target_reference(&o, AB, NULL, NULL, err, sizeof err), 0, "%s", err);
		bk_lutcache_target_key(&o, key, sizeof key);
		AB[1] *= 2;
		bk_lutcache_write(dir, key, AB, 2 * n);
		build_in_child(&o, dir, y, plain.n);
		cr_assert(memcmp(y, plain.y, sizeof *y * plain.n), "%s: the planted file was not read", bk_target_name(o.kind));
		/* the control: the middle cell's A one ulp off is caught by the probe */
		AB[1] /= 2;
		AB[n / 2] = nextafter(AB[n / 2], 2.0);
		bk_lutcache_write(dir, key, AB, 2 * n);
		build_in_child(&o, dir, y, plain.n);
		cr_assert(!memcmp(y, plain.y, sizeof *y * plain.n), "%s: another integrator's file read", bk_target_name(o.kind));
		free(AB);
		free(y);
		bk_samples_free(&plain);
		bk_samples_free(&first);
		bk_samples_free(&second);
		fx_tmpdir_remove(dir);
	}
}

/* Targets without reference integrals (closed forms) leave nothing there. */
Test(lutcache, a_closed_form_target_writes_nothing)
{
	char dir[64], err[256];
	fx_tmpdir_make(dir, sizeof dir, "lutcache");
	bk_target_options o;
	bk_target_defaults(BK_TARGET_VF2D, &o);
	o.nx = o.nr = 8;
	cr_assert_eq(bk_target_reference_cells(&o), 0);
	bk_samples s;
	cr_assert_eq(setenv("BRDFKIT_TABLE_CACHE", dir, 1), 0);
	cr_assert_eq(bk_lutcache_target_build(&o, &s, NULL, NULL, err, sizeof err), 0, "%s", err);
	cr_assert_eq(unsetenv("BRDFKIT_TABLE_CACHE"), 0);
	char cmd[128];
	snprintf(cmd, sizeof cmd, "test -z \"$(ls %s)\"", dir);
	cr_assert_eq(system(cmd), 0, "a file written for vf2d");
	bk_samples_free(&s);
	fx_tmpdir_remove(dir);
}
