/*
 * islands.h — the processes a search runs on: one (islands_one.c, linked into
 * brdfkit) or the ranks of an MPI job (mpi/islands_mpi.c, linked into
 * build/brdfkit-mpi only). Two binaries rather than MPI loaded when needed:
 * brdfkit then needs no MPI runtime at all (not even to start), and the MPI
 * one is built with the MPI library's own compiler flags, so which MPI it
 * uses is fixed at link time, not guessed at run time (Open MPI's plugins do
 * not survive dlopen without RTLD_GLOBAL tricks).
 *
 * Every call but isl_rank, isl_size and isl_name is collective: all ranks make
 * the same calls in the same order. Payloads are bytes (the search's migrant
 * text); sizes are exchanged first, so any size up to INT_MAX goes.
 */
#ifndef CLI_ISLANDS_H
#define CLI_ISLANDS_H

#include <stddef.h>

/* Starts the processes (MPI_Init_thread, FUNNELED: only the main thread
 * talks; the fitting threads never do). Ranks above 0 have their stdout and
 * stderr sent to /dev/null: rank 0 speaks for the job, and a rank's own
 * failure reaches it through isl_gather_text. 0, or -1 (message printed). */
int isl_init(int *argc, char ***argv);
/* Ends them: MPI_Finalize when rc is 0, 2 (bad usage: decided from the
 * command line, so alike on every rank) or 130 (interrupted, results
 * written); otherwise, when every rank fails alike (all reach here within
 * 30 s), MPI_Finalize too, after rank 0's message is out, and the caller
 * exits with rc; else MPI_Abort(rc), so that a rank that failed can never
 * leave the others waiting in a collective (rank 0 has said why). */
void isl_end(int rc);
int isl_rank(void);
int isl_size(void);
/* "one process" or the MPI library's version line. */
const char *isl_name(void);

/* Ring: sends buf[0..n) to rank + 1 and returns in *in (malloc'd, *nin bytes,
 * NUL-terminated) what rank - 1 sent. 0, or -1. */
int isl_ring(const char *buf, size_t n, char **in, size_t *nin);
/* Gather to rank 0, one rank at a time: on rank 0, take(ctx, r, bytes, n) is
 * called for r = 0, 1, ... in order with what rank r sent (NUL-terminated),
 * so rank 0 holds one rank's bytes at a time. Returns 0 when every take
 * returned 0 (on rank 0; elsewhere when the sends went), else -1. */
int isl_gather(const char *buf, size_t n, int (*take)(void *ctx, int rank, const char *in, size_t n), void *ctx);
/* The ranks that split one search's fits (fit/search.h, bk_search_split):
 * rec holds n records of recsize bytes, this rank's (index i with
 * i % isl_size() == isl_rank()) written; the others are filled in from the
 * ranks that wrote them (MPI_Allgatherv). rec NULL says this rank failed.
 * 0, or -1 on every rank (a rank's failure, or n not alike). */
int isl_share(void *rec, size_t recsize, size_t n);
/* One line per rank to rank 0: msg[r] (rank 0's array of isl_size() x 256). */
void isl_gather_text(const char *mine, char (*all)[256]);
/* Reductions over all ranks. */
long isl_sum(long v);
long isl_min(long v);
long isl_max(long v);
int isl_any(int v);

#endif
