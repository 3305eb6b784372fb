/*
 * islands_mpi.c — islands.h over MPI (Open MPI or MPICH from Debian), linked
 * into build/brdfkit-mpi only. Point-to-point for the ring (MPI_Sendrecv: no
 * rank waits on a send nobody receives), rank by rank to rank 0 for the
 * gather (rank 0 holds one rank's bytes at a time), MPI_Allreduce for the
 * decisions every rank must take alike.
 *
 * A failed MPI call aborts the job (MPI's default error handler,
 * MPI_ERRORS_ARE_FATAL, kept on purpose): a rank that died leaves no way to
 * finish a collective, and the checkpoint is the recovery (README, "On a
 * cluster"). Failures of our own (a malloc) are agreed on with an Allreduce
 * before the transfer they would spoil, so no rank is left waiting.
 */
#include "islands.h"

#include <limits.h>
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static int rank_, size_ = 1;
static MPI_Comm end_comm = MPI_COMM_NULL; /* isl_end's own: its barrier never meets a search's collective */
static char name_[MPI_MAX_LIBRARY_VERSION_STRING + 32] = "MPI";

int isl_init(int *argc, char ***argv)
{
	int provided;
	if (MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) {
		fprintf(stderr, "search: MPI_Init_thread failed\n");
		return -1;
	}
	MPI_Comm_dup(MPI_COMM_WORLD, &end_comm);
	MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
	MPI_Comm_size(MPI_COMM_WORLD, &size_);
	char v[MPI_MAX_LIBRARY_VERSION_STRING];
	int len = 0;
	MPI_Get_library_version(v, &len);
	v[strcspn(v, ",\n")] = '\0'; /* the first line up to a comma: the name and version */
	snprintf(name_, sizeof name_, "%s", v);
	/* rank 0 speaks for the job; the others' failures reach it as text */
	if (rank_ > 0 && (!freopen("/dev/null", "w", stdout) || !freopen("/dev/null", "w", stderr)))
		return -1;
	return 0;
}

/* A failure every rank knows of (a checkpoint a rank cannot write: its text
 * gathered, rank 0 has printed it) must not be cut short by another rank's
 * MPI_Abort while rank 0's line is still on its way: under load the job
 * then ended with no "search:" line at all (tests/mpi.sh saw it). So a
 * failing rank first waits, up to END_WAIT_S, for every rank to reach here:
 * if they all do, the failure is the job's, each rank finalizes and returns
 * rc (mpirun exits with it); if not, some rank is still in the search or
 * dead, and MPI_Abort is what ends the job. The barrier is on a copy of
 * the world communicator, so that a rank still in one of the search's
 * collectives can never match it. */
#define END_WAIT_S 30

void isl_end(int rc)
{
	if (rc == 0 || rc == 2 || rc == 130) { /* done, bad usage (decided alike from argv), interrupted */
		MPI_Finalize();
		return;
	}
	fflush(stdout);
	fflush(stderr);
	MPI_Request all;
	int done = 0;
	if (end_comm != MPI_COMM_NULL && MPI_Ibarrier(end_comm, &all) == MPI_SUCCESS) {
		double until = MPI_Wtime() + END_WAIT_S;
		const struct timespec ms = {0, 1000000};
		while (MPI_Test(&all, &done, MPI_STATUS_IGNORE) == MPI_SUCCESS && !done && MPI_Wtime() < until)
			nanosleep(&ms, NULL);
	}
	if (done) {
		MPI_Finalize();
		return;
	}
	MPI_Abort(MPI_COMM_WORLD, rc);
}
int isl_rank(void) { return rank_; }
int isl_size(void) { return size_; }
const char *isl_name(void) { return name_; }

int isl_any(int v)
{
	int in = v != 0, out = 0;
	MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_LOR, MPI_COMM_WORLD);
	return out;
}

static long reduce(long v, MPI_Op op)
{
	long out = 0;
	MPI_Allreduce(&v, &out, 1, MPI_LONG, op, MPI_COMM_WORLD);
	return out;
}

long isl_sum(long v) { return reduce(v, MPI_SUM); }
long isl_min(long v) { return reduce(v, MPI_MIN); }
long isl_max(long v) { return reduce(v, MPI_MAX); }

int isl_ring(const char *buf, size_t n, char **in, size_t *nin)
{
	int to = (rank_ + 1) % size_, from = (rank_ + size_ - 1) % size_;
	long mine = n > INT_MAX - 1 ? -1 : (long)n, theirs = 0;
	MPI_Sendrecv(&mine, 1, MPI_LONG, to, 1, &theirs, 1, MPI_LONG, from, 1, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
	*in = theirs >= 0 ? malloc((size_t)theirs + 1) : NULL;
	if (isl_any(mine < 0 || !*in)) {
		free(*in);
		*in = NULL;
		return -1;
	}
	MPI_Sendrecv(buf, (int)n, MPI_CHAR, to, 2, *in, (int)theirs, MPI_CHAR, from, 2, MPI_COMM_WORLD,
	             MPI_STATUS_IGNORE);
	(*in)[theirs] = '\0';
	*nin = (size_t)theirs;
	return 0;
}

int isl_gather(const char *buf, size_t n, int (*take)(void *ctx, int rank, const char *in, size_t n), void *ctx)
{
	long mine = n > INT_MAX - 1 ? -1 : (long)n;
	if (isl_any(mine < 0))
		return -1;
	if (rank_ > 0) {
		MPI_Send(&mine, 1, MPI_LONG, 0, 3, MPI_COMM_WORLD);
		MPI_Send(buf, (int)n, MPI_CHAR, 0, 4, MPI_COMM_WORLD);
		return isl_any(0) ? -1 : 0;
	}
	int failed = 0;
	for (int r = 0; r < size_; r++) {
		long len = mine;
		if (r > 0)
			MPI_Recv(&len, 1, MPI_LONG, r, 3, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
		char *in = malloc((size_t)len + 1);
		if (!in) { /* the rank's bytes are on their way and cannot be declined */
			fprintf(stderr, "search: out of memory merging the islands (rank %d: %ld bytes)\n", r, len);
			MPI_Abort(MPI_COMM_WORLD, 1);
		}
		if (r > 0)
			MPI_Recv(in, (int)len, MPI_CHAR, r, 4, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
		else
			memcpy(in, buf, (size_t)len);
		in[len] = '\0';
		if (!failed && take(ctx, r, in, (size_t)len))
			failed = 1;
		free(in);
	}
	return isl_any(failed) ? -1 : 0;
}

int isl_share(void *rec, size_t recsize, size_t n)
{
	size_t K = (size_t)size_, R = (size_t)rank_, mine = n / K + (R < n % K);
	int *count = malloc(sizeof(int) * K), *displ = malloc(sizeof(int) * K);
	char *out = malloc(mine * recsize + 1), *in = malloc(n * recsize + 1);
	/* agreed first: a rank's failure, the batch's length alike, the bytes
	 * within MPI's int counts */
	long v[3] = {!rec || !count || !displ || !out || !in || n * recsize > INT_MAX, (long)n, -(long)n}, all[3];
	MPI_Allreduce(v, all, 3, MPI_LONG, MPI_MAX, MPI_COMM_WORLD);
	int rc = all[0] || all[1] != -all[2] ? -1 : 0;
	if (rc == 0) {
		for (size_t j = 0; j < mine; j++)
			memcpy(out + j * recsize, (char *)rec + (R + j * K) * recsize, recsize);
		for (size_t r = 0, at = 0; r < K; r++) {
			count[r] = (int)((n / K + (r < n % K)) * recsize);
			displ[r] = (int)at;
			at += (size_t)count[r];
		}
		MPI_Allgatherv(out, count[R], MPI_BYTE, in, count, displ, MPI_BYTE, MPI_COMM_WORLD);
		for (size_t r = 0; r < K; r++)
			for (size_t j = 0; r != R && r + j * K < n; j++)
				memcpy((char *)rec + (r + j * K) * recsize, in + (size_t)displ[r] + j * recsize, recsize);
	}
	free(count);
	free(displ);
	free(out);
	free(in);
	return rc;
}

void isl_gather_text(const char *mine, char (*all)[256])
{
	char line[256];
	snprintf(line, sizeof line, "%s", mine);
	MPI_Gather(line, 256, MPI_CHAR, rank_ == 0 ? all : NULL, 256, MPI_CHAR, 0, MPI_COMM_WORLD);
}
