/*
 * ir.h — internals of the formula IR shared by ir_*.c (not installed).
 */
#ifndef BRDF_IR_H
#define BRDF_IR_H

#include "brdf.h"
#include "brdf_ops.h" /* the op enum and bk_instr, public */

typedef struct bk_opinfo {
	const char *name; /* language spelling, "" if none */
	int arity;
	const char *spell[3]; /* C, GLSL, HLSL templates */
	bk_opclass cls[3];    /* what it executes; BK_K_FREE pads */
} bk_opinfo;

extern const bk_opinfo bk_opinfo_table[BK_OP_COUNT];

struct bk_form {
	char *text;
	bk_instr *code;
	int n, cap;
	int out;           /* the result register; after bk_ir_finish, n - 1 */
	int nparams;
	unsigned inputs;
	unsigned params;   /* bit k: p_k is read (after bk_ir_finish) */
	int *hash, hcap;   /* while building: register + 1 by instruction hash (0: empty) */
};

/* Appends op (or finds an identical instruction: common subexpressions are
 * shared as they are built), folding constants where that is exact in all three
 * precisions. Returns the register, or -1 when out of memory. */
int bk_ir_emit(bk_form *f, bk_op op, int a, int b, int c);
int bk_ir_const(bk_form *f, double k);
int bk_ir_input(bk_form *f, bk_input in);
int bk_ir_param(bk_form *f, int p);

/* After parsing: fuses single-use a*b + c into MAD, drops what the result does
 * not use, and renumbers so that the result is the last instruction. */
int bk_ir_finish(bk_form *f, int out);

/* Samples per block of the evaluators: registers are BLOCK values wide. */
#define BK_IR_BLOCK 128

/* The f64 kernel on one block of n <= BK_IR_BLOCK samples, leaving every
 * register's values in reg (f->n x BK_IR_BLOCK); first loads constants and
 * parameters (they stay for later blocks); ahead samples follow (prefetch). */
void bk_ir_forward64(const bk_form *f, size_t n, size_t ahead, int first, const double *const *in,
                     const double *par, double *reg);

/* Half precision in each order a driver may pick (brdf/ir_eval.c): every
 * mad and mix rounded twice (unfused) and once (fused); either may be NULL.
 * bk_form_eval's BK_F16 keeps the worse of the two per sample; tests/vk
 * checks the driver against both. 0, or -1 as bk_form_eval. */
int bk_ir_eval_half_orders(const bk_form *f, size_t n, const double *const in[BK_IN_COUNT], const double *params,
                           double *unfused, double *fused);

/* pow(x, y) has no value (NaN in every evaluator: brdf/ir_eval.c) at 0^y for
 * y <= 0, where GLSL leaves it undefined; a negative base needs no test (log2
 * of it is NaN). Bitwise & so that the kernels' loops stay branch-free. */
#define BK_POW_AT_ZERO_UNDEFINED(x, y) (((x) == 0) & !((y) > 0))

/* One non-leaf instruction of the f64 kernel over a whole block: r[k] :=
 * op(A[k], B[k], C[k]) for k < BK_IR_BLOCK (the operands a unary or binary op
 * does not read may be any block). r overlaps none of A, B, C. */
void bk_ir_op64(const bk_instr *c, double *restrict r, const double *restrict A, const double *restrict B,
                const double *restrict C);

/* bk_ir_avx2, bk_ir_force_generic: brdf_ops.h (public: make bench's side by side) */

/* CLAMP's bounds are literals or (baked-in) parameters: the only case the
 * code may spell as clamp(), which GLSL and HLSL leave undefined for lo > hi
 * (the IR's min(max(x, lo), hi) is spelled out otherwise, and counted as
 * two ops). */
int bk_ir_clamp_fixed_bounds(const bk_form *f, const bk_instr *in);

/* bk_ir_apply (one operation in double precision): declared in brdf_ops.h */
/* One operation as the half kernel computes it on half operands (each step
 * rounded: mad, mix, and pow, exp, log decomposed as a GPU runs them). */
double bk_ir_apply_half(bk_op op, double a, double b, double c);

/* bk_comment_text: declared in brdf.h (public: analysis/ writes comments by the same rule) */

#endif
