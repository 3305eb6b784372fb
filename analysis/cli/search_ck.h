/*
 * search_ck.h — the files of search checkpoints (cmd_search.c): checked
 * before the work starts, written whole or not at all, and the temporaries
 * of a save that was killed removed by a later run, only where the file
 * proves itself brdfkit's.
 *
 * A save writes through the one safe-write module (out.h, bk_out_open): the
 * checkpoint's text goes into a temporary beside it, PATH.tmpXXXXXX, named
 * by its inode number and locked (flock) from its creation to the rename;
 * it is synced before the rename, so PATH is never half-written. A run
 * killed before the rename leaves that temporary; the next save to PATH
 * (and the check before a run, ck_islands_check) removes it, since its name
 * proves it brdfkit's (a user's file or a copy is another inode) and its
 * lock is free. That one scheme serves checkpoints and every other output:
 * it needs no text in memory before the name (a content hash would), and
 * proves a leftover without reading it.
 */
#ifndef CLI_SEARCH_CK_H
#define CLI_SEARCH_CK_H

#include "search.h"

#include <stddef.h>

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
	int islands; /* the ranks are islands (FILE.RANK); 0: one search, FILE (rank 0 writes it) */
} ck_islands;

/* Every rank's failure text (empty: none) printed by rank 0, one line each.
 * Collective (islands.h). Returns 1. */
int ck_islands_fail(const char *what, const char *mine);
/* The checkpoint files checked before any work, each rank its own (FILE.RANK
 * and FILE.RANK.prev on islands, FILE on one process), then the leftovers of
 * killed saves removed (bk_out_clean). Collective. 0, or 1 after the message. */
int ck_islands_check(const ck_islands *J);
/* Round `round` saved by every rank in two phases (.prev kept). Collective.
 * 0, or 1 after the message. */
int ck_islands_save(const ck_islands *J, const bk_search *S, long round);
/* The newest round every rank has, loaded into S (just made). Collective.
 * 0, or 1 after the message. */
int ck_islands_load(const ck_islands *J, bk_search *S, long *round);

#endif
