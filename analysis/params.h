/*
 * params.h — the one reader of parameter values (issue 42: it was written
 * in eight places): a word "pN=VALUE" from a command line, a name "pN"
 * (fit --bound, --hold), and a list "p0=X;p1=Y" (front.csv's parameters
 * column, render --params, a render batch's parameters).
 *
 * The rules, everywhere:
 *   name     'p' then N in plain decimal, 0 <= N < BK_MAX_PARAMS; one
 *            spelling per parameter ("p01" would be a second name for p1).
 *   value    the one number syntax of brdfkit (bk_csvtab_number: finite,
 *            decimal, no space).
 *   list     items separated by ';' or ',', spaces before an item skipped;
 *            an empty item ("p0=1;;", "p0=1;") and a parameter given twice
 *            are refused, as the tool's other lists refuse them; "" is the
 *            empty list.
 * Errors are one text without a prefix (the caller adds "WHO: " or
 * "PATH:LINE: "), naming the bad word and, in a list, its item number.
 */
#ifndef ANALYSIS_PARAMS_H
#define ANALYSIS_PARAMS_H

#include "brdf.h"
#include "target.h"

#include <stddef.h>

/* One word "pN=VALUE": 1 with *k and *v; 0 when text is not of that shape
 * ('p', digits, '='), so the caller may read it as something else; -1 with
 * err ("unknown parameter 'p16' (p0..p15)", "p3: expected a finite number,
 * got 'x'"). */
int bk_params_word(const char *text, int *k, double *v, char *err, size_t errlen);

/* bk_params_word, the value stored in p[*k] and given[*k] set; a parameter
 * already given is refused ("p0 given twice ('p0=2')"). *k (may be NULL):
 * the parameter read, also when it was given twice. */
int bk_params_set(const char *text, double *p, int *given, int *k, char *err, size_t errlen);

/* A list into p[] and given[] (given[] as it was: a parameter it marks is
 * a second value); 0, or -1 with err "parameters: ... (item K)". */
int bk_params_list(const char *text, double *p, int *given, char *err, size_t errlen);

/* A --domain list "IN=LO:HI,IN=LO:HI" (inputs by their names in the formula
 * language, numbers as bk_csvtab_number reads them, LO < HI) into
 * to->dom_in, dom_lo, dom_hi and ndomain: the one reader of the syntax, for
 * brdfkit's fit and search and for bench_recovery's planted forms. 0, or -1
 * with err naming the item at fault ("NoV: expected LO < HI, got '1:0'"),
 * an interval narrower than min_rel of its larger end among them (too
 * narrow to sample). */
int bk_params_domain(const char *text, double min_rel, bk_target_options *to, char *err, size_t errlen);

#endif
