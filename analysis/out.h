/*
 * out.h — the one safe-write module: atomic output files and directories,
 * the cleanup of temporaries on a signal, the error text of an errno, and
 * CSV/HTML escaping and slugs: shared by the analysis modules that write
 * results and by the command-line tool. Its files, one concern each:
 * out_base.c (error text, paths, whole writes), out_registry.c (live
 * temporaries, the signal handler, the command line), out_file.c (single
 * files, inputs), out_manifest.c, out_dir.c and out_swap.c (directories),
 * out_text.c (escaping); out_int.h holds what they share.
 */
#ifndef ANALYSIS_OUT_H
#define ANALYSIS_OUT_H

#include <stddef.h>
#include <stdio.h>

/* strerror(e) with its first letter lowercased, so that every message reads
 * "what: detail" ("no space left on device"); a capital before a second
 * capital (an acronym) stays. The one copy for every writer and reader of
 * files; the text lives in a thread-local buffer until the next call. */
const char *bk_out_errtext(int e);
/* "a/b/c" -> dir "a/b", returns "c"; "c" -> ".", "c"; "/c" -> "/", "c". */
const char *bk_out_split(const char *path, char *dir, size_t len);
/* All n bytes to fd, a short write continued and EINTR retried: 0, or -1
 * with errno. */
int bk_out_write_all(int fd, const void *buf, size_t n);

/* Atomic output: text goes to a temporary file beside path, "path.tmpXXXXXX",
 * whose six letters come from its inode number and which its writer keeps
 * locked (flock) until the rename; bk_out_commit flushes it to disk (fsync),
 * renames it into place and fsyncs the directory (a failure of any is an
 * error), bk_out_abort removes it. Nothing is ever left half-written at path,
 * and bk_out_open first removes the temporaries of path that dead runs left
 * (letters of their inode, lock free): a checkpoint's included. A user's file
 * so named (a copy is another inode) stays.
 * This is brdfkit's one temporary scheme (search checkpoints, heatmaps and
 * EXRs write through it too), chosen over naming a finished temporary by a
 * hash of its content: the name needs no text in memory first (writers
 * stream through stdio), a leftover proves itself by fstat without being
 * read, and a crash at any point leaves nothing (before the link) or a
 * temporary that the next write of the same path removes. */
typedef struct bk_out {
	FILE *f;
	char path[4096], tmp[4112];
	int slot;  /* in the registry of live temporaries (bk_out_track) */
	int guard; /* a file the user named: bk_out_file_check again before the rename */
} bk_out;

int bk_out_open(bk_out *o, const char *path, char *err, size_t errlen);
int bk_out_commit(bk_out *o, char *err, size_t errlen);
void bk_out_abort(bk_out *o);
/* bk_out_commit, the file's lock kept: *held is its descriptor, still
 * holding flock(LOCK_EX), for a writer whose file says "a live run holds
 * me" after the rename too (a checkpoint: search_ck.c); -1 on a failure
 * (when only the directory's fsync failed the file is in place and *held
 * is set). The caller closes it. */
int bk_out_commit_held(bk_out *o, int *held, char *err, size_t errlen);
/* Removes the temporaries of path that dead runs left (as bk_out_open does
 * first): returns how many. */
int bk_out_clean(const char *path);

/* A single file the user names (--out FILE): as safe as a directory. What
 * stands at path is replaced only when brdfkit wrote it, as its first lines
 * say (each format's provenance line: out_file.c's table), or when it is empty; a
 * symlink (never followed), anything not a regular file, a file of other
 * content, and any path inside a directory brdfkit writes whole (one holding
 * BK_OUT_MARKER, here or above: that run would delete or refuse it) are
 * refused with one line naming path. check: for a command to refuse before
 * the work; open_file: the check, then bk_out_open; its commit checks again
 * just before the rename. */
int bk_out_file_check(const char *path, char *err, size_t errlen);
int bk_out_open_file(bk_out *o, const char *path, char *err, size_t errlen);

/* An input file opened for reading without blocking on a FIFO or a device
 * (O_NONBLOCK, dropped once it is known to be a regular file): its fd; -1
 * when it cannot be opened (errno kept, why its text), -2 when it is not a
 * regular file (why "is a directory" or "not a regular file (a FIFO)"). For
 * the files brdfkit reads back (CSVs, report's sections, checkpoints); a form
 * and a scene file may come from a pipe, and are read as streams. */
int bk_in_open(const char *path, char *why, size_t len);

/* An output directory, replaced whole: begin makes DIR.tmpXXXXXX (d->tmp) for
 * the caller to fill, commit swaps it in with one rename, abort removes it.
 * Only a directory brdfkit wrote is ever replaced: its marker file
 * BK_OUT_MARKER holds the command line and lists every file and directory the
 * run wrote (the format: out_int.h), and the directory holds nothing else. Only
 * what the list names is deleted. A marker of other content (the format
 * before included), or an entry it does not list (a note, a checkpoint, a
 * symlink), is refused with one line naming it, before the work (check,
 * begin) and again under the lock at the swap (commit). An absent path or an
 * empty directory may be used; the current directory, one of its parents or
 * / never. Symlinks are never followed when deleting. While a run lives it
 * holds flock(LOCK_EX) on its marker; beside DIR a later run removes only the
 * names a run recorded before making them (its build tree's name, kept in the
 * tree), and only when their lock is free: never a user's DIR.old2024 or a
 * copy. A commit that waits more than 2 s for DIR's lock says so on stderr
 * and waits on. Messages name path as given; the commands put "--out " in
 * front. */
#define BK_OUT_MARKER ".brdfkit-output"
typedef struct bk_out_dir {
	char name[4096];  /* the path as given, for messages */
	char path[4096];  /* the same without trailing slashes */
	char tmp[4112];   /* where the new result is built */
	int lock;         /* fd of tmp's marker, held LOCK_EX until the end */
	int slot;         /* in the registry of live temporaries */
} bk_out_dir;

/* The checks of begin alone, creating nothing: for a command to refuse a bad
 * --out before minutes of work. */
int bk_out_dir_check(const char *path, char *err, size_t errlen);
/* command: what the marker records; NULL for the command line bk_out_init saw. */
int bk_out_dir_begin(bk_out_dir *d, const char *path, const char *command, char *err, size_t errlen);
/* Every file and directory under d->tmp fsync'd and listed in its marker,
 * then d->tmp swapped with path by renameat2(RENAME_EXCHANGE) (where the file
 * system has no exchange: the old directory moved aside first), the parent
 * fsync'd (a failure is an error, with the new result in place), the old
 * directory removed as its marker lists it. Two runs committing to one path
 * end with one whole result. */
int bk_out_dir_commit(bk_out_dir *d, char *err, size_t errlen);
void bk_out_dir_abort(bk_out_dir *d);

/* A file of a tree being built (under a bk_out_dir's tmp), opened "w"; closed
 * by bk_out_fclose, which says whether every write reached it. A failure is
 * one line in err naming the file as it will be named once the tree is
 * swapped in (DIR/..., not DIR.tmpXXXXXX/...) and the errno: "sW/front.csv:
 * cannot write: no space left on device". NULL or -1 then. */
FILE *bk_out_fopen(const char *path, char *err, size_t errlen);
int bk_out_fclose(FILE *f, const char *path, char *err, size_t errlen);
/* path as those messages show it (for a writer with its own temporaries). */
const char *bk_out_shown(const char *path, char *buf, size_t len);

/* Once, from main: records the command line for markers and installs the
 * handler that removes the live temporaries on SIGINT, SIGTERM and SIGHUP
 * before dying of the signal (exit status 128 + signal). */
void bk_out_init(int argc, char **argv);
/* That command line, the one every output records: words that are not plain
 * in single quotes, control characters shown as '?' (it lands in comment
 * lines, where a line break would start a line of data or code). */
const char *bk_out_command(void);
/* The registry of live temporaries the handler removes: a file, or a
 * directory with everything under it. Returns a slot for bk_out_untrack, or
 * -1 when the registry is full (the temporary is then only not cleaned on a
 * signal). bk_out_track_child names a child process to kill first (0: none). */
int bk_out_track(const char *path, int is_dir);
void bk_out_untrack(int slot);
void bk_out_track_child(int pid);

/* "LUT 64x64 half" -> "lut_64x64_half": a name as a file name. */
void bk_slug(const char *name, char *buf, size_t len);
/* s escaped for HTML text and attribute values. */
void bk_html_text(FILE *f, const char *s);

/* The one writer of a link (an href or src value) in every section and page:
 * prefix (--link-prefix, checked by bk_link_prefix_check; NULL: none) then
 * path, both file paths relative to the page, percent-encoded as RFC 3986
 * path segments: every byte but unreserved (A-Z a-z 0-9 - . _ ~), the
 * sub-delims ! $ & ' ( ) * + , ; = , '@' and '/' becomes %XX (':' too, so
 * no first segment reads as a scheme). So a folder "a#b" is not a fragment,
 * "c%41d" is not "cAd", "e?f" is not a query, a space or a non-ASCII name
 * is a path; what is left is HTML-escaped ('&'). */
void bk_html_link(FILE *f, const char *prefix, const char *path);
/* The same as a string (malloc'd; NULL when out of memory), for a prefix a
 * writer pastes into many attributes with printf. */
char *bk_html_link_text(const char *prefix, const char *path);
/* --link-prefix, checked where the option is parsed, with report's rule for
 * links (page.h) made stricter: a relative path only. Refused: a scheme (a
 * ':' before the first '/': javascript:, data:, http:), a network path
 * ("//host", "\\host", "/\host", which browsers read as another host), a
 * backslash anywhere (a '/' to a browser), a control character. 0, or -1
 * with err "--link-prefix 'P': why". */
int bk_link_prefix_check(const char *prefix, char *err, size_t errlen);

/* Writes s as one CSV field, quoted when it holds a comma, quote, CR or LF,
 * starts with '#' or starts or ends with a blank. */
void bk_csv_field(FILE *f, const char *s);

/* A growing text buffer (generated sources): bk_sb_put appends printf-style;
 * after an allocation failure oom is set and further puts do nothing, so a
 * caller checks once at the end. s is malloc'd (free it), NUL-terminated. */
typedef struct bk_strbuf {
	char *s;
	size_t len, cap;
	int oom;
} bk_strbuf;
void bk_sb_put(bk_strbuf *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#endif
