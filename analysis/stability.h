/*
 * stability.h — a form under stress: evaluated in half, single and double
 * precision on a grid that includes the extremes, against long double; where
 * it breaks, the smallest safe inputs in half, and guards that fix it, each
 * with the error it adds on its own.
 */
#ifndef ANALYSIS_STABILITY_H
#define ANALYSIS_STABILITY_H

#include "brdf.h"

#include <stddef.h>

/* A result is "wrong" in a precision where the reference is finite and the
 * value is NaN or infinite; where the reference is a normal number and the
 * value is off by more than this, relative (2 % is about 20 half ulps:
 * rounding alone stays far below it); or where the reference is below half's
 * smallest normal 2^-14 and the value is off by more than 2^-14 (a flush to
 * zero passes); and, whatever the value, where the reference is finite but an
 * operation on the way overflowed or made a NaN (a min or max that hides it
 * does not make it right). */
#define BK_STAB_TOL 0.02

typedef struct bk_stab_prec {
	size_t n;          /* samples */
	size_t nan, inf;   /* non-finite values where the reference is finite */
	size_t overflow;   /* samples with an intermediate overflow (past 65504 in half) */
	size_t subnormal;  /* samples with an intermediate below the smallest normal */
	size_t zeroed;     /* value 0 where the reference is a normal nonzero number */
	size_t well;       /* samples where the reference is normal, finite and well conditioned */
	size_t wrong;      /* failures (BK_STAB_TOL's rule) against the reference at the
	                      inputs as this precision rounds them, and samples where an
	                      operation overflowed or made a NaN that a later min, max or
	                      clamp hid (the reference finite): never right but by luck */
	size_t hidden;     /* of those, the ones with a right value: the hidden kind */
	double max_rel;    /* largest relative error over the well-conditioned samples:
	                      +inf where one of them is NaN or infinite */
	size_t ill;        /* off by more than tol where the reference is ill conditioned
	                      (input rounding alone moves it: 1 - NoH^2 near the highlight) */
	double max_rel_ill;
	char region[512];  /* where the failures are */
	char ill_region[256];
	double ill_noh_min;  /* smallest NoH among the ill-conditioned errors (NaN if none or not read) */
} bk_stab_prec;

typedef struct bk_stability {
	char name[96];
	bk_stab_prec p[3];        /* BK_F64, BK_F32, BK_F16 */
	size_t ref_nonfinite;     /* the reference itself is NaN or infinite (the form's own poles);
	                             bk_stability_run refuses a form that is so at every sample */
	char pole[160];           /* the first such sample in words ("" if none) */
	int safe_as_is;           /* half is right everywhere, nothing hidden, no pole: the only
	                             verdict that needs no guard */
	/* Minimum safe inputs in half: with every cosine >= floor[i], half is right
	 * for r >= r_min[i] (NaN: for no r). r_min/cos_min: the smallest floor for
	 * which some r works, and that r. */
	double floor_cos[5], floor_r[5];
	double r_min;
	double cos_min;
	char *guarded;            /* the form with the guards it needs (allocated: forms have no
	                             length limit; bk_stability_free releases it) */
	bk_form *guarded_form;    /* guarded parsed (owned as guarded is): its users take it
	                             from here rather than parse the text again */
	char guards[256];         /* which guards, in words */
	double guard_error[2];    /* error each guard adds alone (max relative, long double, where the
	                             reference is within half's range): r floor, cos floor */
	char advice[256];         /* guards brdfkit cannot apply as a rewrite (|N x H|^2) */
	int guarded_ok;           /* the guarded form passes in half */
	char constants[256];      /* constants a half shader cannot represent */
	/* failure map in half: fraction of wrong samples per (cosine, r) cell */
	int map_nx, map_ny;
	double map[16 * 16];
} bk_stability;

/* The stress grid's values (extremes included). */
extern const double bk_stab_r[];
extern const int bk_stab_nr;
extern const double bk_stab_cos[];
extern const int bk_stab_ncos;

/* Runs the analysis of form f with params (NULL if it has none: then the
 * form must use none). Returns 0 (release st with bk_stability_free), or -1
 * with a message. The caller's form: a member is parsed once, where it
 * enters (its guards are new forms, rewritten from its text). */
int bk_stability_run_form(const char *name, const bk_form *f, const double *params, double tol,
                          bk_stability *st, char *err, size_t errlen);

/* The same of a form's text, parsed here (an edge: a form as typed): a parse
 * error is bk_stability_parse_error's message. */
int bk_stability_run(const char *name, const char *text, const double *params, double tol,
                     bk_stability *st, char *err, size_t errlen);

/* The message of a form name that does not parse: "NAME:1:COLUMN: what". */
void bk_stability_parse_error(const char *name, const bk_form_error *e, char *err, size_t errlen);
void bk_stability_free(bk_stability *st);

#endif
