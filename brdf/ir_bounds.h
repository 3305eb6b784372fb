/*
 * ir_bounds.h — the IR kernels' callers' buffers, checked at the door.
 *
 * The sanitized brdfkit that make test's scripts run (build/san/brdfkit) links
 * the IR's two kernel files (ir_eval.c, ir_diff.c) built without the
 * sanitizers' per-access instrumentation: instrumented, every element a kernel
 * loop reads or writes is a shadow check and an alignment and overflow check,
 * which also keeps the loops from vectorising, and the kernels were four
 * fifths of the sanitized scripts' time (tests/cli_scene.sh: 124 CPU s
 * against 51). What the scripts can get wrong there is a caller's buffer:
 * inputs, parameters, results, Jacobian shorter than the call says, or freed.
 * So in that build (BK_IR_BOUNDS, set by the Makefile) each entry point asks
 * AddressSanitizer whether every byte it will touch of its caller's buffers is
 * addressable, and aborts naming the buffer and the function if not. The
 * kernels' own loops are checked element by element by the sanitized unit
 * runner (build/san/test_brdfkit), which links them instrumented; the plain
 * build compiles these checks to nothing.
 */
#ifndef BK_IR_BOUNDS_H
#define BK_IR_BOUNDS_H

#include "ir.h"

#include <stddef.h>

#ifdef BK_IR_BOUNDS
#include <sanitizer/asan_interface.h>
#include <stdio.h>
#include <stdlib.h>

static inline void bk_ir_bounds(const void *p, size_t bytes, const char *what, const char *fn)
{
	if (!p || !bytes)
		return;
	void *bad = __asan_region_is_poisoned((void *)p, bytes);
	if (bad) {
		fprintf(stderr, "brdfkit: %s: %s (%zu bytes at %p) is not addressable at byte %zu\n", fn, what, bytes, p,
		        (size_t)((const char *)bad - (const char *)p));
		abort();
	}
}
#define BK_IR_BOUNDS_CHECK(p, bytes, what) bk_ir_bounds((p), (bytes), (what), __func__)
#else
#define BK_IR_BOUNDS_CHECK(p, bytes, what) ((void)0)
#endif

/* What every evaluation reads: the n samples of each input f reads, and its
 * parameters. */
#define BK_IR_BOUNDS_FORM(f, n, in, params)                                                   \
	do {                                                                                    \
		for (int bk_i_ = 0; bk_i_ < BK_IN_COUNT; bk_i_++)                               \
			if ((f)->inputs >> bk_i_ & 1)                                           \
				BK_IR_BOUNDS_CHECK((in)[bk_i_], sizeof(double) * (n), "an input"); \
		BK_IR_BOUNDS_CHECK((params), sizeof(double) * (size_t)(f)->nparams, "params");   \
	} while (0)

#endif
