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

#include <stddef.h>

/* used: the parameters the form(s) read (bk_form_params, or-ed over a
 * pair); have[k]: p_k has a value; given[k]: it was given on the command
 * line (NULL: none was). A value missing would be a silent zero, a value
 * unused a silent no-op; parameters are numbered from p0 without a gap (a
 * form of p15 alone would need p0..p14 fitted, emitted and given, all
 * unused). Returns 0, or 2 after one usage line on stderr naming NAME. */
int form_check_params(const char *cmd, const char *name, unsigned used, const int *have, const int *given);

/* The parameters a mask names, for a message: "p0", "p0..p3", or each
 * one where there is a gap ("p2, p5"). */
void form_params_text(unsigned used, char *buf, size_t len);
/* The highest parameter of a mask with a gap below it (*missing: the first
 * absent one), or -1 when it is p0..pN whole (or empty). */
int form_gap(unsigned used, int *missing);

/* Every command's reader of one parameter value, "pN=VALUE" (the rules:
 * analysis/params.h, bk_params_word). 1 with *k and *v set; 0 when text
 * does not have that shape ("p" digits "="), so the caller can read it as
 * something else or refuse it; 2 after a usage line (an unknown parameter,
 * not a number). */
int form_param(const char *text, int *k, double *v);
/* form_param, the value stored in params[k] and given[k] set (*k: k, may
 * be NULL); a parameter given before is refused, "p0 given twice for NAME
 * ('p0=2')" (name NULL: without "for NAME"). 1, 0 or 2 as form_param. */
int form_param_set(const char *name, const char *text, double *params, int *given, int *k);

/* A list of them, "p0=X;p1=Y" (bk_params_list: ';' or ','; render --params
 * and a batch's parameters; front.csv's column through frontcsv.h), into
 * params[k] and given[k]: an empty item and a parameter given twice are
 * refused, as the other lists of the tool refuse them (cli_words). 0, or 2
 * after a usage line "WHO: parameters: ... (item K)". */
int form_param_list(const char *who, const char *text, double *params, int *given);

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
