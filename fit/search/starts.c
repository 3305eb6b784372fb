/*
 * starts.c — the screening fits' start values (starts.h).
 */
#include "search/starts.h"

#include "expr.h"

static uint64_t mix64(uint64_t z)
{
	z += 0x9e3779b97f4a7c15ull;
	z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
	z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
	return z ^ (z >> 31);
}

/* 10^(q/4) for q = -8 .. 8: BK_START_DECADES decades either side of 1 */
static const double magnitude[] = {0.01, 0.017782794100389229, 0.031622776601683794, 0.056234132519034911,
                                   0.1, 0.17782794100389229, 0.31622776601683794, 0.56234132519034907,
                                   1.0, 1.7782794100389228, 3.1622776601683795, 5.6234132519034912,
                                   10.0, 17.782794100389228, 31.622776601683793, 56.234132519034908,
                                   100.0};

void bk_search_start(uint64_t seed, const char *text, int k, int np, double *p)
{
	if (k < 2) {
		for (int j = 0; j < np; j++)
			p[j] = k == 0 ? 1.0 : 0.1;
		return;
	}
	uint64_t h = mix64(bk_expr_hash_text(text) ^ mix64(seed) ^ mix64((uint64_t)k << 32));
	for (int j = 0; j < np; j++) {
		h = mix64(h);
		/* one of 17 magnitudes a quarter decade apart (a table, not pow: the
		 * same bits on every libm), one bit of sign */
		double mag = magnitude[(h >> 8) % (sizeof magnitude / sizeof *magnitude)];
		p[j] = (h & 1) ? -mag : mag;
	}
}
