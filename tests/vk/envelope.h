/*
 * envelope.h — the values a conforming Vulkan driver may return for a form's
 * emitted GLSL at one sample, from the precision the Vulkan specification
 * gives each SPIR-V operation (appendix "Vulkan Environment for SPIR-V",
 * section "Precision and Operation of SPIR-V Instructions", tables "Precision
 * of core SPIR-V Instructions" and "Precision of GLSL.std.450 Instructions",
 * Vulkan 1.3; the emitted statements are the IR's instructions one to one
 * (brdf/ir_emit.c), so the form's instruction list is walked here):
 *
 *   + - *, min max clamp abs neg   correctly rounded (either neighbour: the
 *                                  rounding mode is not specified)
 *   a / b, 1.0 / a                 2.5 ULP for |b| in [2^-126, 2^126]
 *                                  (half: [2^-14, 2^14]); outside: undefined
 *   inversesqrt                    2 ULP
 *   sqrt                           inherited from 1.0 / inversesqrt()
 *   exp, exp2                      3 + 2|x| ULP (half: 1 + 2|x| ULP)
 *   log, log2                      3 ULP outside [0.5, 2]; absolute error
 *                                  < 2^-21 inside (half: < 2^-7)
 *   pow(x, y)                      inherited from exp2(y * log2(x))
 *   mix(x, y, a)                   inherited from x * (1 - a) + y * a, which
 *                                  "may be transformed using associativity,
 *                                  commutativity and distributivity": the
 *                                  result lies within E of the exact value, E
 *                                  the farthest any such formula's envelope
 *                                  reaches; taken over the definition and
 *                                  x + a * (y - x) (Mesa's nir_lower_flrp
 *                                  picks either). Where the emitter spells mix
 *                                  out as x + (y - x) * a, its three ops.
 *   a * b + c (the IR's MAD)       a multiply then an add, each correctly
 *                                  rounded (a fused result lies inside)
 *
 * plus the section's general rules: a result whose allowed range passes the
 * largest finite value may be infinite; any denormal a shader generates (and
 * any denormal operand) may be flushed to zero unless DenormPreserve is
 * declared, and lavapipe does not offer it (shaderDenormPreserveFloat32 = 0),
 * so a result below the smallest normal may be zero; dividing a non-zero by
 * zero gives an infinity, whose sign follows the zero's (not tracked here);
 * an operation outside its mathematical domain (0/0, sqrt(-1), log(-1),
 * pow(0, 0)) is undefined.
 *
 * One allowance is the GLSL compiler's, not the driver's: a statement whose
 * operands are all literals (baked parameters, constants the IR keeps because
 * folding them is inexact in some precision) is a constant expression, and
 * glslang folds it in double from the literals' decimal values before any
 * SPIR-V exists ("2.72721 - 2.71929" becomes 0.00791999977, the float
 * difference is 0.00792002678), then converts to float (to half toward zero).
 * With fold set, such a statement may also have either neighbour of that
 * double value; so may the (y - x) of a spelled-out mix of two literals.
 *
 * A sample's envelope is an interval [lo, hi] of the precision's values (an
 * end may be infinite), or unbounded where a division's precision is not
 * bounded (its divisor may be zero or past the range above) or an IEEE NaN
 * may arise (inf - inf, 0 * inf): there only NaN/Inf kinds are compared; or
 * undefined, where an operation is outside its domain and the specifications
 * give it no value at all (0/0, the log, sqrt or inversesqrt of a negative,
 * pow(x, y) for x < 0 or x = 0 with y <= 0): there anything, NaN or a number,
 * is what a conforming driver may return, and nothing is compared. (mix()
 * where one formula can make a NaN is left unbounded, not undefined, though
 * the "Inherited From" rule would allow anything: the IR must say what the
 * emitted code computes, and that ambiguity is what the emitter removes by
 * spelling mix out.) The envelope is
 * rigorous for the operations as written: interval ends are floats of the
 * precision, rounded outward; + - * are exact in double with an error-free
 * sum; the ulp-bounded operations' ends come from libm in double, nudged
 * outward by 2^-50 (libm's error is below 2^-52) before the outward rounding.
 *
 * The specification also lets a driver rearrange expressions (associativity,
 * distributivity: "Evaluation of Expressions") unless NoContraction is set,
 * with no bound; the emitted code does not set it and this envelope does not
 * grant that: a driver that rearranges beyond the statement-by-statement
 * bounds is reported, as a user of the shader would get its result.
 */
#ifndef TESTS_VK_ENVELOPE_H
#define TESTS_VK_ENVELOPE_H

#include "brdf.h"

#include <stddef.h>

#define VK_UNBOUNDED 1 /* any value, but NaN/Inf kinds must match the IR's */
#define VK_UNDEFINED 2 /* any value at all */

typedef struct vk_env {
	double lo, hi; /* the allowed values, ends included; +-INFINITY for an infinite end */
	int any;       /* 0, VK_UNBOUNDED or VK_UNDEFINED (then lo, hi are unused) */
} vk_env;

/* The rules' switches: flush lets a result below the smallest normal be zero
 * (the specification's default), fold the compiler's folding above; either
 * off, for counting who needs it. */
typedef struct vk_rules {
	bk_precision prec; /* BK_F32 or BK_F16 */
	int flush;
	int fold;          /* a statement of literals may be folded at compile time in double */
	int mix_builtin;   /* the text calls GLSL mix() (else it spells out x + (y - x) * t) */
	double exp_slack;  /* ULPs granted to exp and exp2 past the specification's 3 + 2|x|:
	                    * lavapipe's exp2 was measured 0.6 ULP past it (exp(-0.04886)
	                    * 0.952315927, the bound ends at 0.952315867); an allowance */
} vk_rules;

/* The envelope of f (params baked in) at n samples: in[i] holds input i's
 * values (exactly representable in the precision), NULL where f does not read
 * it. Constants are the precision's rounding to nearest of the float literal
 * the emitter writes (tests/vk/glsl.c writes half literals exactly). 0, or -1
 * when out of memory or an input is missing. */
int vk_envelope(const bk_form *f, const double *params, const vk_rules *rules, size_t n,
                const double *const in[BK_IN_COUNT], vk_env *out);

/* The specification's ulp(x) in the precision: the smallest distance between
 * two different finite values that enclose x. */
double vk_ulp(double x, bk_precision p);

/* 1 if v is one of the values env allows (NaN only where it is unbounded or
 * undefined; the kind rule is the caller's). */
int vk_env_allows(const vk_env *env, double v);

#endif
