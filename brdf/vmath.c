/*
 * vmath.c — bk_v_exp2f and bk_v_log2f (vmath.h) over arrays, in the x86-64
 * baseline and in an AVX2 copy picked at run time.
 *
 * gcc -O2 vectorises only loops it needs no scalar epilogue for (its "very
 * cheap" cost model), so the arrays go through in chunks of CHUNK elements,
 * a constant trip count, and the last partial chunk through a padded copy.
 */
#include "vmath.h"

#define CHUNK 64

#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
#define HAVE_AVX2 1
#define AVX2 __attribute__((target("avx2")))
#else
#define HAVE_AVX2 0
#define AVX2
#endif

#define ARRAY(NAME, F, ATTR)                                                        \
	ATTR static void NAME##_chunk(float *restrict y, const float *restrict x)      \
	{                                                                               \
		for (size_t i = 0; i < CHUNK; i++)                                          \
			y[i] = F(x[i]);                                                         \
	}                                                                               \
	ATTR static void NAME(float *y, const float *x, size_t n)                       \
	{                                                                               \
		float a[CHUNK], b[CHUNK];                                                   \
		for (size_t i = 0; i < n; i += CHUNK) {                                     \
			size_t m = n - i < CHUNK ? n - i : CHUNK;                               \
			memcpy(a, x + i, m * sizeof *a);                                        \
			for (size_t j = m; j < CHUNK; j++)                                      \
				a[j] = 1.0f;                                                        \
			NAME##_chunk(b, a);                                                     \
			memcpy(y + i, b, m * sizeof *b);                                        \
		}                                                                           \
	}

ARRAY(exp2_gen, bk_v_exp2f, )
ARRAY(log2_gen, bk_v_log2f, )
#if HAVE_AVX2
ARRAY(exp2_avx2, bk_v_exp2f, AVX2)
ARRAY(log2_avx2, bk_v_log2f, AVX2)
#endif

int bk_v_have_avx2(void)
{
#if HAVE_AVX2
	__builtin_cpu_init();
	return __builtin_cpu_supports("avx2") != 0;
#else
	return 0;
#endif
}

void bk_v_exp2f_n(float *y, const float *x, size_t n, int avx2)
{
#if HAVE_AVX2
	if (avx2 && bk_v_have_avx2()) {
		exp2_avx2(y, x, n);
		return;
	}
#endif
	(void)avx2;
	exp2_gen(y, x, n);
}

void bk_v_log2f_n(float *y, const float *x, size_t n, int avx2)
{
#if HAVE_AVX2
	if (avx2 && bk_v_have_avx2()) {
		log2_avx2(y, x, n);
		return;
	}
#endif
	(void)avx2;
	log2_gen(y, x, n);
}
