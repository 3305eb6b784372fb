/*
 * test_out_base.c — the pieces every file of the out module shares
 * (analysis/out_base.c): the one error text, a path's parts, a whole write.
 * The expected texts are the C library's own (strerror, written out here as
 * glibc spells them), so the tests say what the lowering changes and what it
 * leaves alone.
 */
#include "out.h"
#include "fixture_tmpdir.h"

#include <criterion/criterion.h>
#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <string.h>
#include <unistd.h>

/* issue 42: out.c, search_ck.c, heatmap.c and page.c each lowered strerror
 * by a copy of their own; bk_out_errtext is the one left. */
Test(out_base, errtext_lowers_the_first_letter)
{
	/* the negative control: glibc's text starts with a capital, so the
	 * checks below fail for a function that returns strerror unchanged */
	cr_assert_str_eq(strerror(ENOSPC), "No space left on device");
	cr_assert_str_eq(bk_out_errtext(ENOSPC), "no space left on device");
	cr_assert_str_eq(bk_out_errtext(ENOENT), "no such file or directory");
	cr_assert_str_eq(bk_out_errtext(EACCES), "permission denied");
	cr_assert_str_eq(bk_out_errtext(EIO), "input/output error");
}

Test(out_base, errtext_keeps_an_acronym)
{
	/* EDOTDOT is "RFS specific error": a capital before a capital stays */
	cr_assert_str_eq(strerror(EDOTDOT), "RFS specific error");
	cr_assert_str_eq(bk_out_errtext(EDOTDOT), "RFS specific error");
	/* the negative control: one capital is lowered (above), so the guard is what kept this one */
	cr_assert_str_neq(bk_out_errtext(ENOSPC), strerror(ENOSPC));
}

static void *errtext_of(void *arg)
{
	return (void *)bk_out_errtext(*(int *)arg);
}

/* A thread's text is its own: another thread's call does not overwrite it. */
Test(out_base, errtext_is_per_thread)
{
	const char *mine = bk_out_errtext(ENOENT);
	int e = EACCES;
	pthread_t t;
	void *theirs;
	cr_assert_eq(pthread_create(&t, NULL, errtext_of, &e), 0);
	cr_assert_eq(pthread_join(t, &theirs), 0);
	cr_assert_str_eq(mine, "no such file or directory");
	cr_assert_neq(theirs, (void *)mine, "one buffer for two threads");
}

Test(out_base, split_names_directory_and_file)
{
	char dir[64];
	cr_assert_str_eq(bk_out_split("a/b/c", dir, sizeof dir), "c");
	cr_assert_str_eq(dir, "a/b");
	cr_assert_str_eq(bk_out_split("c", dir, sizeof dir), "c");
	cr_assert_str_eq(dir, ".");
	cr_assert_str_eq(bk_out_split("/c", dir, sizeof dir), "c");
	cr_assert_str_eq(dir, "/");
	cr_assert_str_eq(bk_out_split("a/", dir, sizeof dir), "");
	cr_assert_str_eq(dir, "a");
}

Test(out_base, write_all_writes_every_byte)
{
	char d[64], path[128];
	fx_tmpdir_make(d, sizeof d, "outbase");
	snprintf(path, sizeof path, "%s/f", d);
	static char text[300000]; /* more than one pipe or page: short writes are continued */
	for (size_t k = 0; k < sizeof text; k++)
		text[k] = (char)('a' + k % 26);
	int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
	cr_assert(fd >= 0);
	cr_assert_eq(bk_out_write_all(fd, text, sizeof text), 0);
	cr_assert_eq(close(fd), 0);
	static char back[sizeof text + 1];
	fd = open(path, O_RDONLY);
	ssize_t n = 0, r;
	while ((r = read(fd, back + n, sizeof back - (size_t)n)) > 0)
		n += r;
	close(fd);
	cr_assert_eq(n, (ssize_t)sizeof text);
	cr_assert_eq(memcmp(back, text, sizeof text), 0);
	/* the negative control: a write that cannot happen is -1 with its errno */
	errno = 0;
	cr_assert_eq(bk_out_write_all(-1, text, 1), -1);
	cr_assert_eq(errno, EBADF);
	cr_assert_eq(fx_tmpdir_remove(d), 0);
}
