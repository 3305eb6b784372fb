/*
 * islands_one.c — islands.h for brdfkit itself: one process, no MPI. The
 * collectives are what they are with one rank: the ring hands a process its
 * own bytes, the gather its own line.
 */
#include "islands.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int isl_init(int *argc, char ***argv)
{
	(void)argc;
	(void)argv;
	return 0;
}

void isl_end(int rc) { (void)rc; }
int isl_rank(void) { return 0; }
int isl_size(void) { return 1; }
const char *isl_name(void) { return "one process"; }

static char *copy(const char *buf, size_t n)
{
	char *c = malloc(n + 1);
	if (c) {
		memcpy(c, buf, n);
		c[n] = '\0';
	}
	return c;
}

int isl_ring(const char *buf, size_t n, char **in, size_t *nin)
{
	*nin = n;
	return (*in = copy(buf, n)) ? 0 : -1;
}

int isl_gather(const char *buf, size_t n, int (*take)(void *ctx, int rank, const char *in, size_t n), void *ctx)
{
	char *c = copy(buf, n);
	int rc = c ? take(ctx, 0, c, n) : -1;
	free(c);
	return rc ? -1 : 0;
}

void isl_gather_text(const char *mine, char (*all)[256]) { snprintf(all[0], 256, "%s", mine); }
int isl_share(void *rec, size_t recsize, size_t n) /* one rank wrote them all */
{
	(void)recsize;
	(void)n;
	return rec ? 0 : -1;
}
long isl_sum(long v) { return v; }
long isl_min(long v) { return v; }
long isl_max(long v) { return v; }
int isl_any(int v) { return v != 0; }
