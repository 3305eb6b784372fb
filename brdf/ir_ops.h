/*
 * ir_ops.h — THE opcode table of the formula IR, the single source of the
 * enum, the language spelling, the arity, the op-count classes and the C, GLSL
 * and HLSL spellings. Include it with OP defined; it undefines OP.
 *
 * Instruction format: R[i] := op(R[a], R[b], R[c]), operands always earlier in
 * the list (the list is in SSA form and topologically ordered).
 *
 * Columns: OP(enum, language name, arity, C, GLSL, HLSL, count classes...)
 *   - language name "" for ops the user does not write by name;
 *   - spellings are templates: %0 %1 %2 are the operands (already parenthesised
 *     where needed); C is float code (sqrtf, ...);
 *   - count classes are what a GPU executes for it (BK_K_FREE: a source modifier or
 *     a register read; pow = log2 + mul + exp2, exp = mul + exp2, log = log2 + mul,
 *     mix(x,y,t) = x + t(y - x) = add + mad).
 *
 * pow(x, y) means exp2(y * log2(x)) in every evaluator and language, as GLSL
 * and HLSL define it and GPUs run it, and NaN where they give it no value
 * (x < 0; x = 0 with y <= 0): C's powf, finite for a negative base with an
 * integral power, is not what a shader computes, so the C spelling is the
 * decomposition itself with that domain (brdf/ir_eval.c).
 *
 * mix is written out, never as GLSL mix() or HLSL lerp(): those are defined
 * as x(1 - t) + y t, which differs from x + t(y - x) in rounding, and in
 * overflow where y - x exceeds the format (in half: inf against a number),
 * and compilers pick either formula by context (Mesa's nir_lower_flrp: the
 * defined one for a constant t or y = +-1, x + t(y - x) otherwise; LLVM's
 * DirectX backend: x + s(y - x)). Spelled out, every language computes what
 * the IR evaluates, and no GPU has a float lerp instruction, so the spelled-out
 * add + mad is also what mix() costs once lowered.
 */
/*  enum      name        ar  C                              GLSL                      HLSL                       classes           meaning */
OP(CONST,    "",          0, "%k",                          "%k",                     "%k",                      BK_K_FREE)          /* R := constant k */
OP(INPUT,    "",          0, "%n",                          "%n",                     "%n",                      BK_K_FREE)          /* R := input slot */
OP(PARAM,    "",          0, "%n",                          "%n",                     "%n",                      BK_K_FREE)          /* R := parameter p_k */
OP(ADD,      "",          2, "%0 + %1",                     "%0 + %1",                "%0 + %1",                 BK_K_ADD)           /* R := A + B */
OP(SUB,      "",          2, "%0 - %1",                     "%0 - %1",                "%0 - %1",                 BK_K_ADD)           /* R := A - B */
OP(MUL,      "",          2, "%0 * %1",                     "%0 * %1",                "%0 * %1",                 BK_K_MUL)           /* R := A * B */
OP(DIV,      "",          2, "%0 / %1",                     "%0 / %1",                "%0 / %1",                 BK_K_DIV)           /* R := A / B */
OP(NEG,      "",          1, "-%0",                         "-%0",                    "-%0",                     BK_K_FREE)          /* R := -A (source modifier) */
OP(MAD,      "",          3, "%0 * %1 + %2",                "%0 * %1 + %2",           "mad(%0, %1, %2)",         BK_K_MAD)           /* R := A * B + C, rounded twice */
OP(POW,      "pow",       2, "%0 == 0.0f && !(%1 > 0.0f) ? NAN : exp2f(%1 * log2f(%0))", "pow(%0, %1)",            "pow(%0, %1)",             BK_K_LOG2, BK_K_MUL, BK_K_EXP2) /* R := 2^(B log2 A): NaN for A < 0 */
OP(SQRT,     "sqrt",      1, "sqrtf(%0)",                   "sqrt(%0)",               "sqrt(%0)",                BK_K_SQRT)          /* R := sqrt A */
OP(RSQRT,    "rsqrt",     1, "1.0f / sqrtf(%0)",            "inversesqrt(%0)",        "rsqrt(%0)",               BK_K_RSQRT)         /* R := 1/sqrt A */
OP(RCP,      "rcp",       1, "1.0f / %0",                   "1.0 / %0",               "rcp(%0)",                 BK_K_RCP)           /* R := 1/A */
OP(EXP,      "exp",       1, "expf(%0)",                    "exp(%0)",                "exp(%0)",                 BK_K_MUL, BK_K_EXP2)   /* R := e^A */
OP(EXP2,     "exp2",      1, "exp2f(%0)",                   "exp2(%0)",               "exp2(%0)",                BK_K_EXP2)          /* R := 2^A */
OP(LOG,      "log",       1, "logf(%0)",                    "log(%0)",                "log(%0)",                 BK_K_LOG2, BK_K_MUL)   /* R := ln A */
OP(LOG2,     "log2",      1, "log2f(%0)",                   "log2(%0)",               "log2(%0)",                BK_K_LOG2)          /* R := log2 A */
OP(MIN,      "min",       2, "fminf(%0, %1)",               "min(%0, %1)",            "min(%0, %1)",             BK_K_MINMAX)        /* R := min(A, B) */
OP(MAX,      "max",       2, "fmaxf(%0, %1)",               "max(%0, %1)",            "max(%0, %1)",             BK_K_MINMAX)        /* R := max(A, B) */
OP(CLAMP,    "clamp",     3, "fminf(fmaxf(%0, %1), %2)",    "clamp(%0, %1, %2)",      "clamp(%0, %1, %2)",       BK_K_MINMAX)        /* R := min(max(A, B), C) */
OP(SATURATE, "saturate",  1, "fminf(fmaxf(%0, 0.0f), 1.0f)", "clamp(%0, 0.0, 1.0)",   "saturate(%0)",            BK_K_SATURATE)      /* R := clamp(A, 0, 1) */
OP(MIX,      "mix",       3, "%0 + (%1 - %0) * %2",         "%0 + (%1 - %0) * %2",    "%0 + (%1 - %0) * %2",     BK_K_ADD, BK_K_MAD)    /* R := A + (B - A) C, spelled out */
OP(ABS,      "abs",       1, "fabsf(%0)",                   "abs(%0)",                "abs(%0)",                 BK_K_FREE)          /* R := |A| (source modifier) */
#undef OP
