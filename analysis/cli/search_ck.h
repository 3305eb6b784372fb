/*
 * search_ck.h — the files of search checkpoints (cmd_search.c): checked
 * before the work starts, written whole or not at all, and the temporaries
 * of a save that was killed removed by a later run, only where the file
 * proves itself brdfkit's.
 *
 * A save writes the checkpoint's text into an unnamed file in the
 * checkpoint's directory (O_TMPFILE), syncs it, and only then gives it a
 * name, PATH.tmpH with H the 16 hex digits of the FNV-1a hash of its whole
 * text (expr.h, bk_hash_bytes), which is renamed onto PATH at once. A run
 * killed before the link leaves nothing (the kernel frees the unnamed file);
 * one killed in the microseconds between link and rename leaves PATH.tmpH,
 * whole. A later run removes PATH.tmpH only when its content hashes to H:
 * no file of a user's has that name by chance, and a copy of one is the
 * leftover itself. Where the file system has no O_TMPFILE the named
 * temporary is written directly; a save killed in the middle of that write
 * leaves a part that cannot prove itself and is left alone.
 */
#ifndef CLI_SEARCH_CK_H
#define CLI_SEARCH_CK_H

#include "search.h"

#include <stddef.h>

typedef struct ck_file {
	int fd;          /* the temporary, written and synced; -1: none */
	int named;       /* 1 once it has its name tmp (no O_TMPFILE, or linked) */
	char path[4096]; /* where it goes */
	char tmp[4200];  /* PATH.tmpH */
	int slot;        /* in out.h's registry of live temporaries (removed on a signal) */
} ck_file;

/* Writes text[0..len) into a temporary beside path and syncs it to disk.
 * 0, or -1 with "PATH: cannot write: REASON" (errno's text) in err. */
int ck_write(ck_file *c, const char *path, const char *text, size_t len, char *err, size_t errlen);
/* Puts the temporary at its path (after renaming an existing file at path to
 * keep, unless keep is NULL) and syncs the directory. 0, or -1 (err). */
int ck_commit(ck_file *c, const char *keep, char *err, size_t errlen);
void ck_abort(ck_file *c);

/* Whether a checkpoint can be written at path, before any work: its
 * directory exists and takes a new file, path is nothing or a brdfkit
 * checkpoint (a regular file beginning with "brdfkit-") that no live run
 * holds (a run keeps the checkpoint it wrote last locked, flock, until its
 * next save or its end; ck_commit checks the same before its rename), and
 * path lies outside the output directory out (which is replaced whole at the
 * end, and what is inside it with it). 0, or -1 with "PATH: what" in err. */
int ck_check_write(const char *path, const char *out, char *err, size_t errlen);
/* Whether path is a file to resume from (with must_exist; else only where
 * one would be), outside out: 0, or -1 (err). */
int ck_check_read(const char *path, const char *out, int must_exist, char *err, size_t errlen);
/* Removes the leftovers PATH.tmpH of killed saves to path that prove
 * themselves (see above) and no live run holds. Returns how many. */
int ck_clean(const char *path);

/* ---- a search's checkpoints ---------------------------------------------------- */

/* The checkpoint's text: header (an island's line, or NULL), then the
 * search's state (bk_search_save), malloc'd into *text. 0, or -1 (out of
 * memory). */
int ck_search_text(const bk_search *S, const char *header, char **text, size_t *len);
/* One process's checkpoint at path, written whole. 0, or -1 (err). */
int ck_search_save(const bk_search *S, const char *path, char *err, size_t errlen);

/* The checkpoint options of a run: --checkpoint, --resume (NULL: none),
 * --out, and on islands --migrate and --migrants (a resume needs the same). */
typedef struct ck_islands {
	const char *checkpoint, *resume, *out;
	long migrate, migrants;
} ck_islands;

/* Every rank's failure text (empty: none) printed by rank 0, one line each.
 * Collective (islands.h). Returns 1. */
int ck_islands_fail(const char *what, const char *mine);
/* The checkpoint files checked before any work, each rank its own (FILE.RANK
 * and FILE.RANK.prev on islands, FILE on one process), then the leftovers of
 * killed saves removed (ck_clean). Collective. 0, or 1 after the message. */
int ck_islands_check(const ck_islands *J);
/* Round `round` saved by every rank in two phases (.prev kept). Collective.
 * 0, or 1 after the message. */
int ck_islands_save(const ck_islands *J, const bk_search *S, long round);
/* The newest round every rank has, loaded into S (just made). Collective.
 * 0, or 1 after the message. */
int ck_islands_load(const ck_islands *J, bk_search *S, long *round);

#endif
