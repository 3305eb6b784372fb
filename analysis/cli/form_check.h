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

/* Warnings, not refusals (the code is valid and computes what the IR does
 * in prec; a GPU may run mediump at single precision's range), one line each
 * on stderr ("brdfkit CMD: warning: NAME: ..."), for code emitted in prec
 * (BK_F32 or BK_F16): a constant the precision cannot hold
 * (bk_form_const_range), and a result it cannot hold at any sample of the
 * grid form_check_finite refuses on (bk_form_range_lost: overflow to inf,
 * or a value that is not 0 flushed to 0 or a subnormal). The one rule: NaN
 * or infinite everywhere in double is refused, lost everywhere in the
 * emitted precision is warned about (unless a constant the precision
 * cannot hold was named first: it is then most likely why). */
/* cmd NULL: the command running (cli_name). */
void form_warn_precision(const char *cmd, const char *name, const bk_form *f, const double *params, bk_precision prec);

#endif
