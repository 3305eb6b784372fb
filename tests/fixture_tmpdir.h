/*
 * fixture_tmpdir.h — a test's scratch directory under /tmp: made fresh by
 * mkdtemp (the name's XXXXXX filled in, so it holds no quote and the shell
 * line below needs no escaping), removed whole afterwards. One place for the
 * set-up the file-writing tests shared line for line (test_csvtab.c,
 * test_page.c, test_summary.c, test_lut.c, test_out.c).
 */
#ifndef TESTS_FIXTURE_TMPDIR_H
#define TESTS_FIXTURE_TMPDIR_H

#include <criterion/criterion.h>
#include <criterion/logging.h>

#include <stdio.h>
#include <stdlib.h>

/* dir (len bytes) := a new directory /tmp/bk_TAG_XXXXXX. */
static inline void fx_tmpdir_make(char *dir, size_t len, const char *tag)
{
	snprintf(dir, len, "/tmp/bk_%s_XXXXXX", tag);
	cr_assert_not_null(mkdtemp(dir), "mkdtemp %s failed", dir);
}

/* dir and everything in it gone; 0, or -1 (logged) when rm failed. */
static inline int fx_tmpdir_remove(const char *dir)
{
	char cmd[160];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
	if (system(cmd) == 0)
		return 0;
	cr_log_warn("could not remove %s", dir);
	return -1;
}

#endif
