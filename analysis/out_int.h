/*
 * out_int.h — the out module's internals, shared by its files (out_base.c,
 * out_registry.c, out_file.c, out_manifest.c, out_dir.c, out_swap.c) and by
 * nothing else: other modules include out.h. Internal names start "out_",
 * the public ones "bk_out_".
 */
#ifndef ANALYSIS_OUT_INT_H
#define ANALYSIS_OUT_INT_H

#include "out.h"

#include <stddef.h>

/* ---- out_base.c ---- */

/* The names in dfd ("." and ".." left out), malloc'd one after another
 * ("a\0b\0"), *count of them; NULL with errno on failure. */
char *out_dir_names(int dfd, size_t *count);
/* s for a one-line message: control characters shown as '?'. */
const char *out_printable(const char *s, char *buf, size_t len);
/* The six letters and digits after "BASE.KIND" in entry (KIND "tmp" or "old"),
 * or NULL when entry is not so named: the temporaries of files and trees. */
const char *out_temp_letters(const char *entry, const char *base, const char *kind);

/* ---- out_registry.c ---- */

/* Removes name (relative to dirfd), a directory with everything under it,
 * never following a symlink; keep_last removed last. Async-signal-safe (the
 * signal handler's). 0, or -1 with errno; ENOENT counts as done. */
int out_rm_at(int dirfd, const char *name, const char *keep_last, int depth);
/* One line on stderr that does not end the run, "brdfkit CMD: what". */
void out_notice(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* ---- out_manifest.c: an output directory's marker ---- */

/* The marker BK_OUT_MARKER says what brdfkit wrote, one item a line:
 *
 *     brdfkit-output 2        the format
 *     brdfkit lut --out lut   the command
 *     f dfg.csv               each file (f) and directory (d) of the result,
 *     f dfg.exr               its path inside DIR, in byte order (strcmp),
 *     end                     with '\' and newline escaped as \\ and \n
 *
 * A run writes the first two lines when it begins and the list when it
 * commits, so a marker without "end" is a run's that was building. Only a
 * directory whose marker is complete, and lists every entry in it with its
 * type, is replaced, and only what it lists is deleted. The marker of the
 * format before (one line, the command) lists nothing, so it is not enough.
 *
 * TEMPS, beside the marker, holds the name the tree was built under
 * ("DIR.tmpXXXXXX", from mkdtemp), written while no other run can know the
 * name. The swap leaves the previous result at that name (or, without
 * RENAME_EXCHANGE, at "DIR.oldXXXXXX" with the same letters); TEMPS stays in
 * DIR until that is removed. So a later run removes only names brdfkit
 * recorded: a build tree whose TEMPS names itself (its run died before the
 * swap), and the names recorded in DIR (its run died after). The marker and
 * TEMPS are the protocol's, not the result's: never listed, always allowed. */
#define MARKER_MAGIC "brdfkit-output 2"
#define MARKER_NEW BK_OUT_MARKER ".new"
#define TEMPS BK_OUT_MARKER ".tmps"
#define MARKER_MAX (16 << 20) /* a result lists a few hundred names (results/: 170 at most) */
#define TREE_DEPTH 32         /* results are 3 deep; deeper is refused, never followed */

typedef struct entry {
	char *path;
	char type; /* 'f' or 'd' */
} entry;

typedef struct manifest {
	char *text; /* the marker's bytes, lines split and unescaped in place */
	entry *e;   /* pointing into text, in byte order */
	size_t n;
} manifest;

enum { MK_FOREIGN, MK_OLD, MK_BUILDING, MK_COMPLETE };

enum { WALK_CHECK, WALK_REMOVE };
typedef struct walk {
	const manifest *m;
	int mode;          /* WALK_CHECK: only look; WALK_REMOVE: remove what m lists */
	int unlisted;      /* entries m does not list (or lists with another type) */
	char first[4096];  /* the first of them in byte order, for the message */
} walk;

enum { DIR_ABSENT, DIR_EMPTY, DIR_OURS, DIR_FOREIGN, DIR_OLD, DIR_UNLISTED, DIR_RETRY, DIR_ERROR };

typedef struct look {
	int kind;
	int marker;       /* DIR_FOREIGN: it has a .brdfkit-output, not brdfkit's */
	int mfd;          /* DIR_OURS, asked to lock: the marker, locked */
	int err;          /* DIR_ERROR: errno */
	int link;         /* DIR_FOREIGN: a symlink (to anything: never followed) */
	manifest m;       /* DIR_OURS: what its run listed */
	char first[4096]; /* DIR_UNLISTED: the first entry it did not list */
} look;

#define NOT_OURS "exists and was not written by brdfkit"

/* s into b with '\' and newline escaped: one line holds one name. */
void out_put_escaped(bk_strbuf *b, const char *s);
void out_manifest_free(manifest *m);
/* The marker open at fd read whole and parsed into m: an MK_ kind, or -1 with errno. */
int out_marker_read(int fd, manifest *m);
/* The tree under dfd against w->m (WALK_CHECK: count what it does not list;
 * WALK_REMOVE: remove what it lists). 0, or -1 with errno. */
int out_walk_tree(walk *w, int dfd, const char *prefix, int depth);
/* The tree name (open at dfd, in pfd) removed as m lists it when it holds
 * nothing else: 0; 1 with the first unlisted entry in first; -1 with errno. */
int out_remove_listed(int pfd, const char *name, int dfd, const manifest *m, char *first, size_t flen);
/* The new tree (tfd) fsync'd and listed into its marker (fd). 0, or -1 (errno). */
int out_write_list(int fd, int tfd);

/* ---- out_dir.c: what stands at --out ---- */

/* What stands at name in pfd, into k (a DIR_ kind); shown: NULL to look
 * only, else the marker is locked first (k->mfd). */
int out_classify(int pfd, const char *name, const char *shown, look *k);
void out_look_done(look *k);
/* The one line for a directory k says may not be replaced, or for a failure. */
void out_refusal(const look *k, const char *given, const char *doing, char *err, size_t errlen);
/* A stripped path's parent directory, opened, and its last name in *base. */
int out_open_parent(const char *path, const char **base);

#endif
