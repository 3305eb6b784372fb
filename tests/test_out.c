/*
 * test_out.c — output directories and files (analysis/out_*.c): only a
 * directory whose marker lists everything in it is replaced, and only what it
 * lists is deleted; a marker brdfkit did not write, the format before, an
 * unlisted entry (a note, a subdirectory, a symlink) are refused, before the
 * work and again at the swap; the current directory, its parents and / are
 * refused; only leftovers brdfkit recorded are removed (a dead run's, never a
 * user's renamed backup or copy, never a live run's); a long wait for the
 * lock is said; concurrent commits end with one whole result.
 */
#define _GNU_SOURCE /* flock */
#include "out.h"
#include "fixture_tmpdir.h"

#include <criterion/criterion.h>
#include <dirent.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static char dir[64];

static void setup(void)
{
	fx_tmpdir_make(dir, sizeof dir, "out");
}

static void teardown(void) { cr_assert_eq(fx_tmpdir_remove(dir), 0); }

static void put(const char *path, const char *text)
{
	FILE *f = fopen(path, "w");
	cr_assert_not_null(f, "%s", path);
	fputs(text, f);
	cr_assert_eq(fclose(f), 0);
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

/* The whole text of a file ("" when absent). */
static void slurp(const char *path, char *buf, size_t len)
{
	FILE *f = fopen(path, "r");
	size_t n = f ? fread(buf, 1, len - 1, f) : 0;
	buf[n] = '\0';
	if (f)
		fclose(f);
}

/* The message begin gives for out, which must be refused, with nothing
 * changed in out (its listing before and after). */
static void refused(const char *out, const char *want_tail)
{
	char before[1024], after[1024], err[1024], want[1024];
	listing(out, before, sizeof before);
	bk_out_dir d;
	cr_assert_eq(bk_out_dir_begin(&d, out, "test", err, sizeof err), -1, "%s was not refused", out);
	snprintf(want, sizeof want, "%s: %s", out, want_tail);
	cr_assert_str_eq(err, want);
	cr_assert_eq(bk_out_dir_check(out, err, sizeof err), -1);
	cr_assert_str_eq(err, want);
	listing(out, after, sizeof after);
	cr_assert_str_eq(after, before, "the refused directory changed");
	char parent[400], names[1024];
	snprintf(parent, sizeof parent, "%.*s", (int)(strrchr(out, '/') - out), out);
	listing(parent, names, sizeof names);
	cr_assert_null(strstr(names, ".tmp"), "a temporary beside: %s", names);
}

#define NOT_BRDFKITS                                                                                           \
	"exists and was not written by brdfkit (its .brdfkit-output is not one brdfkit wrote); choose another path or " \
	"remove it"
#define UNLISTED(name) "holds '" name "', which brdfkit did not write; move it or choose another --out"

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

/* The marker lists what the run wrote, in the documented format (out_int.h):
 * the format line, the command, one line per file (f) and directory (d) in
 * byte order, "end"; the text below is written from that description. */
Test(out_dir, replaces_its_own_directory_whole, .init = setup, .fini = teardown)
{
	char out[300], names[512], path[400], text[512];
	snprintf(out, sizeof out, "%s/o", dir);
	cr_assert_eq(run_once(out, "first"), 0);
	cr_assert_eq(run_once(out, "second"), 0);
	listing(out, names, sizeof names);
	cr_assert_str_eq(names, ".brdfkit-output result.txt second");
	listing(dir, names, sizeof names);
	cr_assert_str_eq(names, "o");
	snprintf(path, sizeof path, "%s/.brdfkit-output", out);
	slurp(path, text, sizeof text);
	cr_assert_str_eq(text, "brdfkit-output 2\ntest\nf result.txt\nf second\nend\n");
}

/* Subdirectories, names with a newline or a backslash, and a command with
 * both: listed, escaped (\\ and \n) and replaced as a whole. */
Test(out_dir, lists_subdirectories_and_odd_names, .init = setup, .fini = teardown)
{
	char out[300], err[512], path[4400], text[1024], names[512];
	snprintf(out, sizeof out, "%s/o", dir);
	for (int run = 0; run < 2; run++) {
		bk_out_dir d;
		cr_assert_eq(bk_out_dir_begin(&d, out, "brdfkit x 'a\\b\nc'", err, sizeof err), 0, "%s", err);
		snprintf(path, sizeof path, "%s/maps", d.tmp);
		cr_assert_eq(mkdir(path, 0777), 0);
		snprintf(path, sizeof path, "%s/maps/a b.csv", d.tmp);
		put(path, "x");
		snprintf(path, sizeof path, "%s/odd\nna\\me", d.tmp);
		put(path, "x");
		snprintf(path, sizeof path, "%s/maps-2", d.tmp);
		cr_assert_eq(mkdir(path, 0777), 0);
		cr_assert_eq(bk_out_dir_commit(&d, err, sizeof err), 0, "run %d: %s", run, err);
	}
	snprintf(path, sizeof path, "%s/.brdfkit-output", out);
	slurp(path, text, sizeof text);
	cr_assert_str_eq(text, "brdfkit-output 2\nbrdfkit x 'a\\\\b\\nc'\nd maps\nd maps-2\nf maps/a b.csv\n"
	                       "f odd\\nna\\\\me\nend\n");
	listing(dir, names, sizeof names);
	cr_assert_str_eq(names, "o");
}

/* issue 21, M3: any file named .brdfkit-output made a directory deletable
 * (home2/Documents/thesis.tex was removed). Each marker below is refused; the
 * last, the same directory with the marker brdfkit writes, is not (the
 * negative control: the check can pass). */
Test(out_dir, refuses_a_marker_brdfkit_did_not_write, .init = setup, .fini = teardown)
{
	static const char *const markers[] = {
		"hello\n",
		"",
		"brdfkit-output 2\nbrdfkit lut\n",                             /* cut short: never complete */
		"brdfkit-output 2\nbrdfkit lut\nd Documents\nend\n",         /* Documents/thesis.tex unlisted */
		"brdfkit-output 2\nbrdfkit lut\nd Documents\nf Documents/thesis.tex\nend\nmore\n",
		"brdfkit-output 2\nbrdfkit lut\nf Documents\nf Documents/thesis.tex\nend\n", /* a directory as a file */
		"brdfkit-output 2\nbrdfkit lut\nf Documents/thesis.tex\nd Documents\nend\n", /* not in byte order */
		"brdfkit-output 2\nbrdfkit lut\nd Documents\nf Documents/../thesis.tex\nend\n",
		"brdfkit-output 3\nbrdfkit lut\nd Documents\nf Documents/thesis.tex\nend\n",
	};
	static const char *const why[] = {
		NOT_BRDFKITS, NOT_BRDFKITS, NOT_BRDFKITS, UNLISTED("Documents/thesis.tex"), NOT_BRDFKITS,
		UNLISTED("Documents"), NOT_BRDFKITS, NOT_BRDFKITS, NOT_BRDFKITS,
	};
	char out[300], path[400], names[512];
	snprintf(out, sizeof out, "%s/home2", dir);
	cr_assert_eq(mkdir(out, 0777), 0);
	snprintf(path, sizeof path, "%s/Documents", out);
	cr_assert_eq(mkdir(path, 0777), 0);
	snprintf(path, sizeof path, "%s/Documents/thesis.tex", out);
	put(path, "t");
	for (size_t k = 0; k < sizeof markers / sizeof markers[0]; k++) {
		snprintf(path, sizeof path, "%s/.brdfkit-output", out);
		put(path, markers[k]);
		refused(out, why[k]);
		snprintf(path, sizeof path, "%s/Documents/thesis.tex", out);
		slurp(path, names, sizeof names);
		cr_assert_str_eq(names, "t", "marker %zu", k);
	}
	snprintf(path, sizeof path, "%s/.brdfkit-output", out);
	put(path, "brdfkit-output 2\nbrdfkit lut\nd Documents\nf Documents/thesis.tex\nend\n");
	cr_assert_eq(run_once(out, "mine"), 0);
	listing(out, names, sizeof names);
	cr_assert_str_eq(names, ".brdfkit-output mine result.txt");
}

/* The marker of the format before (one line, the command) lists nothing: the
 * directory is refused, with the reason, not replaced. */
Test(out_dir, refuses_the_marker_format_before, .init = setup, .fini = teardown)
{
	char out[300], path[400];
	snprintf(out, sizeof out, "%s/lut", dir);
	cr_assert_eq(mkdir(out, 0777), 0);
	snprintf(path, sizeof path, "%s/.brdfkit-output", out);
	put(path, "brdfkit lut --size 2 --out lut\n");
	snprintf(path, sizeof path, "%s/dfg.csv", out);
	put(path, "x");
	refused(out, "was written by an older brdfkit, whose .brdfkit-output lists no files; remove it yourself or "
	             "choose another path");
}

/* issue 21, L2: a note, a subdirectory, a file inside a listed subdirectory
 * or a checkpoint in a brdfkit directory were deleted with it. Each is
 * refused, naming the first unlisted entry in byte order. */
Test(out_dir, refuses_what_the_run_did_not_list, .init = setup, .fini = teardown)
{
	char out[300], path[4400], err[512];
	snprintf(out, sizeof out, "%s/real", dir);
	bk_out_dir d;
	cr_assert_eq(bk_out_dir_begin(&d, out, "test", err, sizeof err), 0, "%s", err);
	snprintf(path, sizeof path, "%s/maps", d.tmp);
	cr_assert_eq(mkdir(path, 0777), 0);
	snprintf(path, sizeof path, "%s/maps/form.csv", d.tmp);
	put(path, "x");
	cr_assert_eq(bk_out_dir_commit(&d, err, sizeof err), 0, "%s", err);

	snprintf(path, sizeof path, "%s/notes.txt", out);
	put(path, "n");
	snprintf(path, sizeof path, "%s/mysub", out);
	cr_assert_eq(mkdir(path, 0777), 0);
	refused(out, UNLISTED("mysub"));
	cr_assert_eq(rmdir(path), 0);
	refused(out, UNLISTED("notes.txt"));
	snprintf(path, sizeof path, "%s/notes.txt", out);
	cr_assert_eq(unlink(path), 0);
	snprintf(path, sizeof path, "%s/maps/ck", out);
	put(path, "checkpoint");
	refused(out, UNLISTED("maps/ck"));
	cr_assert_eq(unlink(path), 0);
	/* a listed file gone (a user removed it, git ignores it) is no reason to refuse */
	snprintf(path, sizeof path, "%s/maps/form.csv", out);
	cr_assert_eq(unlink(path), 0);
	cr_assert_eq(run_once(out, "again"), 0);
}

/* The check again at the swap: a note written into DIR while the run worked
 * makes the commit fail, with DIR, its note and nothing beside it left. */
Test(out_dir, checks_again_at_the_swap, .init = setup, .fini = teardown)
{
	char out[300], path[4300], err[512], names[512];
	snprintf(out, sizeof out, "%s/o", dir);
	cr_assert_eq(run_once(out, "first"), 0);
	bk_out_dir d;
	cr_assert_eq(bk_out_dir_begin(&d, out, "test", err, sizeof err), 0, "%s", err);
	snprintf(path, sizeof path, "%s/second", d.tmp);
	put(path, "second");
	snprintf(path, sizeof path, "%s/notes.txt", out);
	put(path, "n");
	cr_assert_eq(bk_out_dir_commit(&d, err, sizeof err), -1);
	char want[600];
	snprintf(want, sizeof want, "%s: " UNLISTED("notes.txt"), out);
	cr_assert_str_eq(err, want);
	listing(out, names, sizeof names);
	cr_assert_str_eq(names, ".brdfkit-output first notes.txt result.txt");
	listing(dir, names, sizeof names);
	cr_assert_str_eq(names, "o");
}

/* A symlink the run did not write is refused, and so is a listed directory
 * replaced by a symlink to the user's directory: nothing is followed and what
 * they point to stays. An abort removes a temporary holding a symlink without
 * following it. */
Test(out_dir, never_follows_symlinks_when_deleting, .init = setup, .fini = teardown)
{
	char out[300], p[300], path[4400], link[400], names[512], err[512];
	snprintf(out, sizeof out, "%s/o", dir);
	snprintf(p, sizeof p, "%s/p", dir);
	cr_assert_eq(mkdir(p, 0777), 0);
	snprintf(path, sizeof path, "%s/keep.txt", p);
	put(path, "keep");
	bk_out_dir d;
	cr_assert_eq(bk_out_dir_begin(&d, out, "test", err, sizeof err), 0, "%s", err);
	snprintf(path, sizeof path, "%s/sub", d.tmp);
	cr_assert_eq(mkdir(path, 0777), 0);
	cr_assert_eq(bk_out_dir_commit(&d, err, sizeof err), 0, "%s", err);

	snprintf(link, sizeof link, "%s/filelink", out);
	snprintf(path, sizeof path, "%s/keep.txt", p);
	cr_assert_eq(symlink(path, link), 0);
	refused(out, UNLISTED("filelink"));
	cr_assert_eq(unlink(link), 0);
	snprintf(link, sizeof link, "%s/sub", out);
	cr_assert_eq(rmdir(link), 0);
	cr_assert_eq(symlink(p, link), 0);
	refused(out, UNLISTED("sub"));
	listing(p, names, sizeof names);
	cr_assert_str_eq(names, "keep.txt");

	snprintf(out, sizeof out, "%s/q", dir);
	cr_assert_eq(bk_out_dir_begin(&d, out, "test", err, sizeof err), 0, "%s", err);
	snprintf(path, sizeof path, "%s/dirlink", d.tmp);
	cr_assert_eq(symlink(p, path), 0);
	bk_out_dir_abort(&d);
	listing(p, names, sizeof names);
	cr_assert_str_eq(names, "keep.txt");
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

/* In a forked child: every descriptor closed but the pipe ends it uses, so
 * that it holds no other child's pipe open (that child would never see EOF). */
static void close_others(int keep1, int keep2)
{
	for (int fd = 3; fd < 1024; fd++)
		if (fd != keep1 && fd != keep2)
			close(fd);
}

/* A child that begins a run on out and stops there until its pipe closes
 * (then dies without committing, as a killed run would). */
static pid_t start_child(const char *out, int *wake)
{
	int ready[2], hold[2];
	cr_assert_eq(pipe(ready), 0);
	cr_assert_eq(pipe(hold), 0);
	pid_t pid = fork();
	cr_assert(pid >= 0);
	if (pid == 0) {
		bk_out_dir d;
		char err[512], path[4300], c;
		close_others(ready[1], hold[0]);
		if (bk_out_dir_begin(&d, out, "test", err, sizeof err))
			_exit(1);
		snprintf(path, sizeof path, "%s/half.csv", d.tmp);
		FILE *f = fopen(path, "w");
		if (!f || fputs("half", f) < 0 || fclose(f))
			_exit(1);
		if (write(ready[1], "r", 1) != 1 || read(hold[0], &c, 1) < 0)
			_exit(1);
		_exit(0);
	}
	close(ready[1]);
	close(hold[0]);
	char c;
	cr_assert_eq(read(ready[0], &c, 1), 1, "the child did not begin");
	close(ready[0]);
	*wake = hold[1];
	return pid;
}

/* issue 21, H4: every run deleted siblings DIR.old?????? and DIR.tmp?????? that
 * held a marker whose lock was free: a user's renamed backup with notes, and a
 * copy. They stay; so does a live run's temporary; a dead run's (its name
 * recorded in itself before anything could be written to it) goes. */
Test(out_dir, removes_only_the_leftovers_it_recorded, .init = setup, .fini = teardown, .timeout = 30)
{
	char out[300], path[400], names[512], cmd[1024];
	snprintf(out, sizeof out, "%s/lut", dir);
	cr_assert_eq(run_once(out, "first"), 0);
	snprintf(path, sizeof path, "%s/lut.old202411", dir);
	cr_assert_eq(rename(out, path), 0);
	snprintf(path, sizeof path, "%s/lut.old202411/notes.txt", dir);
	put(path, "notes");
	cr_assert_eq(run_once(out, "second"), 0);
	snprintf(cmd, sizeof cmd, "cp -a '%s' '%s/lut.tmp2024ab'", out, dir);
	cr_assert_eq(system(cmd), 0);
	/* the look-alike of a killed run, as the code before made it: a marker,
	 * no record of its name */
	snprintf(path, sizeof path, "%s/lut.tmpAbC123", dir);
	cr_assert_eq(mkdir(path, 0777), 0);
	snprintf(path, sizeof path, "%s/lut.tmpAbC123/.brdfkit-output", dir);
	put(path, "brdfkit lut --size 2 --out lut\n");
	snprintf(path, sizeof path, "%s/lut.tmpAbC123/mine.txt", dir);
	put(path, "mine");
	int wake;
	pid_t child = start_child(out, &wake);
	cr_assert_eq(run_once(out, "third"), 0);
	listing(dir, names, sizeof names);
	char live[64] = "";
	cr_assert_eq(sscanf(names, "lut lut.old202411 lut.tmp%6s lut.tmp2024ab lut.tmpAbC123", live), 1,
	             "the live run's temporary or a user's copy is gone: %s", names);
	close(wake); /* the child dies without committing */
	int st;
	cr_assert_eq(waitpid(child, &st, 0), child);
	cr_assert(WIFEXITED(st) && WEXITSTATUS(st) == 0);
	cr_assert_eq(run_once(out, "fourth"), 0);
	listing(dir, names, sizeof names);
	cr_assert_str_eq(names, "lut lut.old202411 lut.tmp2024ab lut.tmpAbC123");
	listing(out, names, sizeof names);
	cr_assert_str_eq(names, ".brdfkit-output fourth result.txt");
	snprintf(path, sizeof path, "%s/lut.old202411", dir);
	listing(path, names, sizeof names);
	cr_assert_str_eq(names, ".brdfkit-output first notes.txt result.txt");
	snprintf(path, sizeof path, "%s/lut.tmp2024ab", dir);
	listing(path, names, sizeof names);
	cr_assert_str_eq(names, ".brdfkit-output result.txt second");
	snprintf(path, sizeof path, "%s/lut.tmpAbC123", dir);
	listing(path, names, sizeof names);
	cr_assert_str_eq(names, ".brdfkit-output mine.txt");
}

/* Runs one commit to out while a child holds the lock on out's marker for
 * hold_ms; returns the seconds it took, stderr's text in errs. */
static double commit_while_locked(const char *out, int hold_ms, char *errs, size_t len)
{
	char marker[400], errfile[400];
	snprintf(marker, sizeof marker, "%s/.brdfkit-output", out);
	snprintf(errfile, sizeof errfile, "%s/stderr.txt", dir);
	int ready[2];
	cr_assert_eq(pipe(ready), 0);
	pid_t holder = fork();
	cr_assert(holder >= 0);
	if (holder == 0) {
		int fd = open(marker, O_RDONLY);
		if (fd < 0 || flock(fd, LOCK_EX) || write(ready[1], "r", 1) != 1)
			_exit(1);
		nanosleep(&(struct timespec){hold_ms / 1000, (hold_ms % 1000) * 1000000L}, NULL);
		_exit(0);
	}
	char c;
	cr_assert_eq(read(ready[0], &c, 1), 1);
	close(ready[0]);
	close(ready[1]);
	fflush(stderr);
	int saved = dup(2), ef = open(errfile, O_WRONLY | O_CREAT | O_TRUNC, 0666);
	cr_assert(saved >= 0 && ef >= 0);
	dup2(ef, 2);
	close(ef);
	struct timespec t0, t1;
	clock_gettime(CLOCK_MONOTONIC, &t0);
	int rc = run_once(out, "second");
	clock_gettime(CLOCK_MONOTONIC, &t1);
	fflush(stderr);
	dup2(saved, 2);
	close(saved);
	int st;
	cr_assert_eq(waitpid(holder, &st, 0), holder);
	cr_assert_eq(rc, 0);
	slurp(errfile, errs, len);
	unlink(errfile);
	return (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
}

/* issue 21, L12: a run waited silently, forever, while another process held
 * the marker's lock. It says which directory it waits for (after 2 s: a
 * commit of another run holds it for milliseconds, so a short hold gets no
 * line, the negative control), then goes on when the lock is free. */
Test(out_dir, says_so_when_it_waits_for_the_lock, .init = setup, .fini = teardown, .timeout = 60)
{
	char out[300], errs[1024], want[600], names[512];
	snprintf(out, sizeof out, "%s/lk", dir);
	cr_assert_eq(run_once(out, "first"), 0);
	double t = commit_while_locked(out, 3500, errs, sizeof errs);
	snprintf(want, sizeof want,
	         "brdfkit: --out %s: another brdfkit is writing it (its .brdfkit-output is locked); "
	         "waiting for it to finish\n",
	         out);
	cr_assert_str_eq(errs, want);
	cr_assert(t >= 3.0, "the commit did not wait for the lock: %g s", t);
	listing(out, names, sizeof names);
	cr_assert_str_eq(names, ".brdfkit-output result.txt second");
	t = commit_while_locked(out, 300, errs, sizeof errs);
	cr_assert_str_eq(errs, "");
	cr_assert(t >= 0.25, "%g s", t);
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

/* A child that opens path with bk_out_open, writes, and stops there until its
 * pipe closes; then it dies without committing, as a killed run would. */
static pid_t start_writer(const char *path, int *wake)
{
	int ready[2], hold[2];
	cr_assert_eq(pipe(ready), 0);
	cr_assert_eq(pipe(hold), 0);
	pid_t pid = fork();
	cr_assert(pid >= 0);
	if (pid == 0) {
		bk_out o;
		char err[512], c;
		close_others(ready[1], hold[0]);
		if (bk_out_open(&o, path, err, sizeof err) || fputs("half", o.f) < 0 || fflush(o.f))
			_exit(1);
		if (write(ready[1], "r", 1) != 1 || read(hold[0], &c, 1) < 0)
			_exit(1);
		_exit(0);
	}
	close(ready[1]);
	close(hold[0]);
	char c;
	cr_assert_eq(read(ready[0], &c, 1), 1, "the writer did not open");
	close(ready[0]);
	*wake = hold[1];
	return pid;
}

static void end_child(pid_t pid, int wake)
{
	int st;
	close(wake);
	cr_assert_eq(waitpid(pid, &st, 0), pid);
	cr_assert(WIFEXITED(st) && WEXITSTATUS(st) == 0);
}

static void write_file(const char *path, const char *text)
{
	bk_out o;
	char err[512];
	cr_assert_eq(bk_out_open(&o, path, err, sizeof err), 0, "%s", err);
	fputs(text, o.f);
	cr_assert_eq(bk_out_commit(&o, err, sizeof err), 0, "%s", err);
}

/* issue 21, L1: the temporaries of killed runs (ck.tmpXXXXXX, from
 * bk_out_open: the checkpoints') were never removed. The next write of the
 * same path removes a dead run's; a live run's, and a user's file so named
 * (a backup, a copy of a temporary), stay. */
Test(out_file, removes_a_dead_runs_temporary_only, .init = setup, .fini = teardown, .timeout = 30)
{
	char ck[300], path[400], names[512], a[16], b[16], cmd[1024];
	snprintf(ck, sizeof ck, "%s/ck", dir);
	int wake_dead, wake_live;
	pid_t dead = start_writer(ck, &wake_dead);
	listing(dir, names, sizeof names);
	cr_assert_eq(sscanf(names, "ck.tmp%6s", a), 1, "%s", names);
	pid_t live = start_writer(ck, &wake_live);
	listing(dir, names, sizeof names);
	char *other = strstr(names, "ck.tmp") == names && !strncmp(names + 6, a, 6) ? names + 13 : names;
	cr_assert_eq(sscanf(other, "ck.tmp%6s", b), 1, "%s", names);
	cr_assert_str_neq(a, b);
	snprintf(path, sizeof path, "%s/ck.tmp2024ab", dir);
	put(path, "mine");
	end_child(dead, wake_dead);
	/* a copy of the dead run's temporary is another inode: not brdfkit's */
	snprintf(cmd, sizeof cmd, "cp '%s/ck.tmp%s' '%s/ck.tmp%s.copy' && mv '%s/ck.tmp%s.copy' '%s/ck.tmpCopy01'", dir, a,
	         dir, a, dir, a, dir);
	cr_assert_eq(system(cmd), 0);
	write_file(ck, "first");
	listing(dir, names, sizeof names);
	char want1[128], want2[128];
	snprintf(want1, sizeof want1, "ck ck.tmp2024ab ck.tmpCopy01 ck.tmp%s", b);
	cr_assert_eq(strlen(names), strlen(want1), "the live temporary or a user's file is gone, or more: %s", names);
	snprintf(want1, sizeof want1, "ck.tmp%s", b);
	snprintf(want2, sizeof want2, "ck.tmp%s", a);
	cr_assert(strstr(names, "ck.tmp2024ab") && strstr(names, "ck.tmpCopy01") && strstr(names, want1) &&
	          !strstr(names, want2), "%s (dead %s, live %s)", names, a, b);
	end_child(live, wake_live);
	write_file(ck, "second");
	listing(dir, names, sizeof names);
	cr_assert_str_eq(names, "ck ck.tmp2024ab ck.tmpCopy01");
	slurp(ck, names, sizeof names);
	cr_assert_str_eq(names, "second");
	slurp(path, names, sizeof names);
	cr_assert_str_eq(names, "mine");
}

/* issue 42: a checkpoint is written through bk_out (search_ck.c). A save
 * killed between its write and its rename leaves its temporary; bk_out_clean
 * (the check before a search) removes it once its writer is dead, and not
 * while the writer lives (the negative control). */
Test(out_file, clean_removes_a_killed_saves_temporary, .init = setup, .fini = teardown, .timeout = 30)
{
	char ck[300], names[512];
	snprintf(ck, sizeof ck, "%s/ck", dir);
	int wake;
	pid_t pid = start_writer(ck, &wake);
	listing(dir, names, sizeof names);
	cr_assert_eq(strncmp(names, "ck.tmp", 6), 0, "%s", names);
	cr_assert_eq(bk_out_clean(ck), 0, "a live save's temporary was removed");
	listing(dir, names, sizeof names);
	cr_assert_eq(strncmp(names, "ck.tmp", 6), 0, "%s", names);
	end_child(pid, wake);
	cr_assert_eq(bk_out_clean(ck), 1);
	listing(dir, names, sizeof names);
	cr_assert_str_eq(names, "");
}

/* A checkpoint's commit keeps its lock after the rename (bk_out_commit_held):
 * a second run probing the file finds it locked while the descriptor is
 * held, and free once it is closed (the negative control). */
Test(out_file, a_held_commit_keeps_the_lock, .init = setup, .fini = teardown)
{
	char ck[300], err[512], text[64];
	snprintf(ck, sizeof ck, "%s/ck", dir);
	bk_out o;
	int held = -2;
	cr_assert_eq(bk_out_open(&o, ck, err, sizeof err), 0, "%s", err);
	fputs("brdfkit-search-checkpoint", o.f);
	cr_assert_eq(bk_out_commit_held(&o, &held, err, sizeof err), 0, "%s", err);
	cr_assert(held >= 0);
	slurp(ck, text, sizeof text);
	cr_assert_str_eq(text, "brdfkit-search-checkpoint");
	int probe = open(ck, O_RDONLY);
	cr_assert(probe >= 0);
	cr_assert_eq(flock(probe, LOCK_EX | LOCK_NB), -1, "the committed file is not locked");
	close(held);
	cr_assert_eq(flock(probe, LOCK_EX | LOCK_NB), 0, "still locked after the descriptor was closed");
	close(probe);
	/* and the plain commit keeps nothing: the file is free at once */
	cr_assert_eq(bk_out_open(&o, ck, err, sizeof err), 0, "%s", err);
	fputs("again", o.f);
	cr_assert_eq(bk_out_commit(&o, err, sizeof err), 0, "%s", err);
	probe = open(ck, O_RDONLY);
	cr_assert_eq(flock(probe, LOCK_EX | LOCK_NB), 0);
	close(probe);
}
