/*
 * bridge.h — what the two C++ files of the Ceres bridge share (solver.cc, the
 * Ceres solve; tiny.cc, the TinySolver fast path). Internal, C++ only.
 */
#ifndef FIT_BRIDGE_H
#define FIT_BRIDGE_H

#include "solver.h"

#include <cstdarg>
#include <cstddef>
#include <cstdio>
#include <cstring>

namespace bk_bridge {

/* A message into buf (NULL or len 0: none). */
inline void say(char *buf, size_t len, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
inline void say(char *buf, size_t len, const char *fmt, ...)
{
	if (buf == nullptr || len == 0)
		return;
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(buf, len, fmt, ap);
	va_end(ap);
}

/* An enum field read as the int C stored there: C lets any int live in an enum
 * object, and loading an out-of-range value as the enum type is undefined in
 * C++ (UBSan's -fsanitize=enum reports it). */
inline int enum_value(const void *field)
{
	static_assert(sizeof(bk_loss) == sizeof(int) && sizeof(bk_trust_region) == sizeof(int),
	              "the C enums are int-sized");
	int v;
	std::memcpy(&v, field, sizeof v);
	return v;
}

/* The message of a solve that stopped at the edge of where the form is
 * finite: its last trial steps were rejected for non-finite residuals and the
 * step shrank below the parameter tolerance (NO_CONVERGENCE; both solvers). */
constexpr const char *kEdgeMessage =
    "stopped at the edge of where the form is finite: the last trial steps gave non-finite residuals and were "
    "rejected";

} // namespace bk_bridge

#endif
