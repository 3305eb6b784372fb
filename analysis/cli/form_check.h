/*
 * form_check.h — what every command that takes a form checks before it emits,
 * counts, measures or analyses it (eval, ops, codegen, time, gpucost,
 * stability): each parameter it uses has a value and each value given is
 * used, and the form has a value somewhere. One line on stderr naming the
 * form and exit 2 (bad usage) on a refusal, as fit and compare refuse.
 */
#ifndef ANALYSIS_CLI_FORM_CHECK_H
#define ANALYSIS_CLI_FORM_CHECK_H

#include "brdf.h"

/* np: the highest parameter the form(s) use + 1; have[k]: p_k has a value;
 * given[k]: it was given on the command line (NULL: none was). A value
 * missing would be a silent zero, a value unused a silent no-op. Returns 0,
 * or 2 after "brdfkit CMD: NAME: ..." on stderr. */
int form_check_params(const char *cmd, const char *name, int np, const int *have, const int *given);

/* The form at params can be computed: no operation on constants that is NaN
 * or infinite in single precision (the code would compute it: 1/0,
 * sqrt(0 - 1)), and finite at some sample of its inputs' domain (not NoV/0,
 * 1/(NoV - NoV)). params NULL: the parameters are unknown (ops), only the
 * constants are checked. Returns 0, or 2 after one line on stderr; 1 (out
 * of memory) after one line too. */
int form_check_finite(const char *cmd, const char *name, const bk_form *f, const double *params);

#endif
