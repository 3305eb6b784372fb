/*
 * clock.h — what every measurement shares (brdfkit time and the benchmarks in
 * bench/): a monotonic clock and the median of repeated runs (medians, not
 * means: one preempted run must not move the figure).
 */
#ifndef ANALYSIS_CLOCK_H
#define ANALYSIS_CLOCK_H

#include <stdlib.h>
#include <string.h>
#include <time.h>

static inline double bk_clock_now(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* The CPU time of the process, all threads (a benchmark's CPU-seconds). */
static inline double bk_clock_cpu(void)
{
	struct timespec t;
	clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
	return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static inline int bk_clock_cmp(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

/* Median of n <= 64 values (the upper middle one for even n). */
static inline double bk_clock_median(const double *v, int n)
{
	double s[64];
	memcpy(s, v, sizeof(double) * (size_t)n);
	qsort(s, (size_t)n, sizeof s[0], bk_clock_cmp);
	return s[n / 2];
}

#endif
