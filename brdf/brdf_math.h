/*
 * brdf_math.h — a compiled form as mathematics rather than code: LaTeX for a
 * paper, a SymPy snippet for a notebook, MathML Core for the results page
 * (brdf/ir_math.c). One printer walks the instruction list for all three, so
 * the three say the same thing, and each says what the IR computes (the
 * meanings are written in the SymPy snippet's header, where they can be
 * checked by evaluation).
 */
#ifndef BRDF_BRDF_MATH_H
#define BRDF_BRDF_MATH_H

#include "brdf.h"

typedef enum bk_math_lang { BK_MATH_LATEX, BK_MATH_SYMPY, BK_MATH_MATHML } bk_math_lang;

/* The expression alone, malloc'd (NULL when out of memory or lang unknown):
 * LaTeX math-mode text; a SymPy expression over symbols named as the inputs
 * and p0, p1, ... (module imported as sp); a <math> element using only
 * MathML Core elements (math mrow mi mn mo mfrac msup msub msqrt), nothing
 * in it taken from user text but numbers and input names. params NULL: the
 * parameters stay symbols (p_0 ...); else their values are written in
 * digits significant digits (0: the fewest that read back as the float the
 * generated shaders hold). Shared subexpressions are written out at every
 * use: a formula, not a program. SymPy always keeps the parameters symbolic
 * (params ignored; bk_form_math_doc binds them). */
char *bk_form_math(const bk_form *f, bk_math_lang lang, const double *params, int digits);

/* A whole document for codegen: LaTeX as an equation environment named by
 * name (NULL: brdfkit_form) with a '%' comment header (which also holds the
 * expression with p_0, p_1, ... for its constants); SymPy as a Python
 * snippet defining the input and parameter symbols, params (their values,
 * exact doubles), expr (symbolic) and fitted (params substituted) under a
 * '#' comment header with the meanings. info's fields go only into
 * comments (bk_comment_text) — the name into LaTeX as \mathrm text with its
 * specials escaped. params may be NULL only for a form without parameters.
 * Malloc'd, NULL when out of memory, lang not LaTeX or SymPy, or params
 * missing. */
char *bk_form_math_doc(const bk_form *f, bk_math_lang lang, const double *params, const bk_emit_info *info);

#endif
