/*
 * doors.h — the hot numeric files' callers' buffers, checked at the door.
 *
 * The sanitized brdfkit that make test's scripts run (build/san/brdfkit)
 * links the few files where the suites' sanitized time went, built without
 * the sanitizers' per-access instrumentation: the IR's kernels (ir_eval.c,
 * ir_diff.c), the adaptive quadrature and the hemisphere integrals (quad.c,
 * integrate.c, and the scalar libm of dmath.c), and the TinySolver bridge
 * (fit/tiny.cc, Eigen). Instrumented, every element a loop reads or writes
 * is a shadow check and an alignment and overflow check, which also keeps
 * the loops from vectorising: the IR's kernels alone were four fifths of the
 * sanitized scripts' time (tests/cli_scene.sh: 124 CPU s, 48 without).
 * What the scripts can get wrong there is a caller's buffer: inputs,
 * parameters, results, a Jacobian, an out value shorter than the call says,
 * or freed. So in that build (BK_DOORS, set by the Makefile) each entry
 * point asks AddressSanitizer whether every byte it will touch of its
 * caller's buffers is addressable, and aborts naming the buffer and the
 * function if not (tiny.cc needs no door of its own: it reads its caller's
 * buffers first through bk_problem_valid, fit/solver.cc, instrumented). The
 * second sanitized unit runner (build/san/test_brdfkit) links them so too.
 * The files' own loops are checked element by element by the sanitized
 * runner of their own tests (build/san/test_kernels), which links them
 * instrumented; the plain build compiles these checks to nothing.
 * tests/doors.sh: each door's negative control.
 */
#ifndef BK_DOORS_H
#define BK_DOORS_H

#include <stddef.h>

#ifdef BK_DOORS
#include <sanitizer/asan_interface.h>
#include <stdio.h>
#include <stdlib.h>

static inline void bk_door(const void *p, size_t bytes, const char *what, const char *fn)
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
#define BK_DOOR(p, bytes, what) bk_door((p), (bytes), (what), __func__)
#else
#define BK_DOOR(p, bytes, what) ((void)0)
#endif

/* What every evaluation of a form reads: the n samples of each input f
 * reads, and its parameters (ir.h's bk_form). */
#define BK_DOOR_FORM(f, n, in, params)                                                 \
	do {                                                                           \
		for (int bk_i_ = 0; bk_i_ < BK_IN_COUNT; bk_i_++)                      \
			if ((f)->inputs >> bk_i_ & 1)                                  \
				BK_DOOR((in)[bk_i_], sizeof(double) * (n), "an input"); \
		BK_DOOR((params), sizeof(double) * (size_t)(f)->nparams, "params");     \
	} while (0)

#endif
