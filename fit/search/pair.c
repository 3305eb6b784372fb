/*
 * pair.c — f0*(A) + (B) (pair.h).
 */
#include "search/pair.h"

#include <stdio.h>
#include <stdlib.h>

#define PAIR_FMT "f0*(%s) + (%s)"

int bk_pair_text(const char *a, const char *b, char *buf, size_t len)
{
	int n = snprintf(buf, len, PAIR_FMT, a, b);
	if (n < 0 || (size_t)n >= len) {
		if (len)
			buf[0] = '\0';
		return -1;
	}
	return 0;
}

char *bk_pair_dup(const char *a, const char *b)
{
	int n = snprintf(NULL, 0, PAIR_FMT, a, b);
	char *t = n < 0 ? NULL : malloc((size_t)n + 1);
	if (t)
		snprintf(t, (size_t)n + 1, PAIR_FMT, a, b);
	return t;
}
