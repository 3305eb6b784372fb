/*
 * brdf_ops.h — the formula IR's opcodes as a public vocabulary (installed):
 * the enum, each op's arity and language name, and a compiled form's
 * instructions read-only. The search builds its trees from these ops
 * (fit/expr.h). The enum is expanded from brdf/ir_ops.h, the one table of
 * the ops (installed beside this header); nothing here repeats it.
 */
#ifndef BRDF_BRDF_OPS_H
#define BRDF_BRDF_OPS_H

#include "brdf.h"

#ifdef __cplusplus
extern "C" { /* C linkage for a C++ program (tests/install.sh links one) */
#endif

typedef enum bk_op {
#define OP(e, name, arity, c, glsl, hlsl, ...) BK_OP_##e,
#include "ir_ops.h"
	BK_OP_COUNT
} bk_op;

/* R[i] := op(R[a], R[b], R[c]); CONST holds k, INPUT and PARAM their slot
 * (ir_ops.h states the format). */
typedef struct bk_instr {
	bk_op op;
	int a, b, c;
	int slot;
	double k;
} bk_instr;

/* Operands op takes (0 for CONST, INPUT, PARAM); -1 for no op. */
int bk_op_arity(int op);
/* Its spelling in the formula language, "" for ops not written by name;
 * NULL for no op. */
const char *bk_op_name(int op);

/* One operation in double precision: the IR's folding and f64 kernel, and
 * the search's folding of constants (fit/expr.c), so both fold alike. */
double bk_ir_apply(bk_op op, double a, double b, double c);

/* A compiled form's instructions (operands always earlier ones), their
 * count in *n and the register of the result in *out (either may be NULL). */
const bk_instr *bk_form_code(const bk_form *f, int *n, int *out);

/* 1 when the kernels (forward, one op, backward) run their AVX2 copies (the
 * CPU has AVX2), 0 for the x86-64 baseline; the two give the same bits.
 * bk_ir_force_generic(1) pins the baseline (tests), 0 asks the CPU again. */
int bk_ir_avx2(void);
void bk_ir_force_generic(int on);
/* bk_ir_force_libm(1): the kernels call libm's exp2, log2, pow, exp and log
 * (exp2f, log2f, ... in f32 and f16) instead of brdf/vmath.h's vectorised
 * ones and dmath.c's (make bench's old side); 0 back. */
void bk_ir_force_libm(int on);

#ifdef __cplusplus
}
#endif

#endif
