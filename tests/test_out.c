/*
 * test_out.c — output directories (analysis/out.c): only a directory brdfkit
 * marked is replaced, whole, symlinks in it are removed and never followed,
 * the current directory, its parents and / are refused, a dead run's
 * temporary is cleaned while a live one's is left alone, and concurrent
 * commits end with one whole result.
 */
#define _GNU_SOURCE /* flock */
#include "out.h"

#include <criterion/criterion.h>
#include <dirent.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

static char dir[] = "/tmp/bk_out_XXXXXX";

static void setup(void)
{
	cr_assert_not_null(mkdtemp(dir));
}

static void teardown(void)
{
	char cmd[128];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
	cr_assert_eq(system(cmd), 0);
}

static void put(const char *path, const char *text)
{
	FILE *f = fopen(path, "w");
	cr_assert_not_null(f, "%s", path);
	fputs(text, f);
	cr_assert_eq(fclose(f), 0);
}

static int exists(const char *path)
{
	struct stat st;
	return lstat(path, &st) == 0;
}

/* The names in d, sorted, space-separated. */
static void listing(const char *d, char *buf, size_t len)
{
	struct dirent **v;
	int n = scandir(d, &v, NULL, alphasort);
	cr_assert(n >= 0, "%s", d);
	buf[0] = '\0';
	for (int i = 0; i < n; i++) {
		if (strcmp(v[i]->d_name, ".") && strcmp(v[i]->d_name, ".."))
			snprintf(buf + strlen(buf), len - strlen(buf), "%s%s", buf[0] ? " " : "", v[i]->d_name);
		free(v[i]);
	}
	free(v);
}

/* One run: begin, a file named after the run, commit. */
static int run_once(const char *out, const char *what)
{
	bk_out_dir d;
	char err[512], path[4300];
	if (bk_out_dir_begin(&d, out, "test", err, sizeof err))
		return -1;
	snprintf(path, sizeof path, "%s/result.txt", d.tmp);
	put(path, what);
	snprintf(path, sizeof path, "%s/%s", d.tmp, what);
	put(path, what);
	return bk_out_dir_commit(&d, err, sizeof err);
}

Test(out_dir, refuses_root_and_the_current_directory)
{
	char err[512];
	cr_assert_eq(bk_out_dir_check("/", err, sizeof err), -1);
	cr_assert_str_eq(err, "/: is the current directory or one of its parents; choose another path");
	cr_assert_eq(bk_out_dir_check(".", err, sizeof err), -1);
	cr_assert_str_eq(err, ".: is the current directory or one of its parents; choose another path");
	cr_assert_eq(bk_out_dir_check("..", err, sizeof err), -1);
	cr_assert_eq(bk_out_dir_check("./", err, sizeof err), -1);
}

Test(out_dir, refuses_a_users_directory_untouched, .init = setup, .fini = teardown)
{
	char out[300], path[400], err[512], names[512];
	snprintf(out, sizeof out, "%s/mydocs", dir);
	cr_assert_eq(mkdir(out, 0777), 0);
	snprintf(path, sizeof path, "%s/thesis.tex", out);
	put(path, "x");
	bk_out_dir d;
	cr_assert_eq(bk_out_dir_begin(&d, out, "test", err, sizeof err), -1);
	char want[600];
	snprintf(want, sizeof want, "%s: exists and was not written by brdfkit; choose another path or remove it", out);
	cr_assert_str_eq(err, want);
	listing(dir, names, sizeof names);
	cr_assert_str_eq(names, "mydocs");
	listing(out, names, sizeof names);
	cr_assert_str_eq(names, "thesis.tex");
}

Test(out_dir, replaces_its_own_directory_whole, .init = setup, .fini = teardown)
{
	char out[300], names[512], path[400];
	snprintf(out, sizeof out, "%s/o", dir);
	cr_assert_eq(run_once(out, "first"), 0);
	cr_assert_eq(run_once(out, "second"), 0);
	listing(out, names, sizeof names);
	cr_assert_str_eq(names, ".brdfkit-output result.txt second");
	listing(dir, names, sizeof names);
	cr_assert_str_eq(names, "o");
	snprintf(path, sizeof path, "%s/.brdfkit-output", out);
	FILE *f = fopen(path, "r");
	char line[64] = "";
	cr_assert(fgets(line, sizeof line, f));
	fclose(f);
	cr_assert_str_eq(line, "test\n");
}

/* The old tree held symlinks to a file and to a directory outside: the links
 * go, their targets stay. */
Test(out_dir, never_follows_symlinks_when_deleting, .init = setup, .fini = teardown)
{
	char out[300], p[300], path[400], link[400], names[512];
	snprintf(out, sizeof out, "%s/o", dir);
	snprintf(p, sizeof p, "%s/p", dir);
	cr_assert_eq(run_once(out, "first"), 0);
	cr_assert_eq(mkdir(p, 0777), 0);
	snprintf(path, sizeof path, "%s/keep.txt", p);
	put(path, "keep");
	snprintf(link, sizeof link, "%s/dirlink", out);
	cr_assert_eq(symlink(p, link), 0);
	snprintf(link, sizeof link, "%s/filelink", out);
	cr_assert_eq(symlink(path, link), 0);
	cr_assert_eq(run_once(out, "second"), 0);
	listing(p, names, sizeof names);
	cr_assert_str_eq(names, "keep.txt");
	listing(out, names, sizeof names);
	cr_assert_str_eq(names, ".brdfkit-output result.txt second");
}

Test(out_dir, abort_leaves_nothing, .init = setup, .fini = teardown)
{
	char out[300], err[512], names[512], path[4300];
	snprintf(out, sizeof out, "%s/o", dir);
	bk_out_dir d;
	cr_assert_eq(bk_out_dir_begin(&d, out, "test", err, sizeof err), 0, "%s", err);
	snprintf(path, sizeof path, "%s/sub", d.tmp);
	cr_assert_eq(mkdir(path, 0777), 0);
	bk_out_dir_abort(&d);
	listing(dir, names, sizeof names);
	cr_assert_str_eq(names, "");
}

/* A leftover DIR.tmp* whose marker is locked belongs to a live run and is
 * kept; once the lock is gone (its run died), the next run removes it. */
Test(out_dir, cleans_a_dead_runs_temporary_only, .init = setup, .fini = teardown)
{
	char out[300], left[300], path[400], names[512];
	snprintf(out, sizeof out, "%s/o", dir);
	snprintf(left, sizeof left, "%s/o.tmpAbC123", dir);
	cr_assert_eq(mkdir(left, 0777), 0);
	snprintf(path, sizeof path, "%s/half.csv", left);
	put(path, "x");
	snprintf(path, sizeof path, "%s/.brdfkit-output", left);
	put(path, "test\n");
	int fd = open(path, O_RDONLY);
	cr_assert(fd >= 0 && flock(fd, LOCK_EX) == 0);
	cr_assert_eq(run_once(out, "first"), 0);
	cr_assert(exists(left), "a live run's temporary was removed");
	close(fd);
	cr_assert_eq(run_once(out, "second"), 0);
	listing(dir, names, sizeof names);
	cr_assert_str_eq(names, "o");
}

/* Eight processes commit to one path at once: every one succeeds and the
 * path holds one whole result, nothing beside it. */
Test(out_dir, concurrent_commits_leave_one_whole_result, .init = setup, .fini = teardown)
{
	char out[300], names[512], what[16];
	snprintf(out, sizeof out, "%s/o", dir);
	pid_t pid[8];
	for (int k = 0; k < 8; k++) {
		snprintf(what, sizeof what, "run%d", k);
		if ((pid[k] = fork()) == 0)
			_exit(run_once(out, what) == 0 ? 0 : 1);
		cr_assert(pid[k] > 0);
	}
	for (int k = 0; k < 8; k++) {
		int st;
		cr_assert_eq(waitpid(pid[k], &st, 0), pid[k]);
		cr_assert(WIFEXITED(st) && WEXITSTATUS(st) == 0, "run %d failed", k);
	}
	listing(dir, names, sizeof names);
	cr_assert_str_eq(names, "o");
	listing(out, names, sizeof names);
	int k = -1;
	cr_assert_eq(sscanf(names, ".brdfkit-output result.txt run%d", &k), 1, "%s", names);
	snprintf(what, sizeof what, "run%d", k);
	char path[400], line[32] = "";
	snprintf(path, sizeof path, "%s/result.txt", out);
	FILE *f = fopen(path, "r");
	cr_assert(fgets(line, sizeof line, f));
	fclose(f);
	cr_assert_str_eq(line, what, "result.txt of another run than its directory");
}
