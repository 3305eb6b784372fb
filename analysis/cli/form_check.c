/*
 * form_check.c — the checks of a form every command shares (form_check.h).
 */
#include "form_check.h"

#include "cli.h"
#include "params.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int form_param(const char *text, int *k, double *v)
{
	char err[300];
	int rc = bk_params_word(text, k, v, err, sizeof err); /* the one reader (params.h) */
	if (rc < 0)
		return cli_bad("%s", err);
	return rc;
}

int form_param_set(const char *name, const char *text, double *params, int *given, int *k)
{
	char err[300];
	int j = -1, rc = bk_params_set(text, params, given, &j, err, sizeof err);
	if (rc < 0 && j >= 0 && given[j] && name) /* given twice: say for which form */
		return cli_bad("p%d given twice for %s ('%.100s')", j, name, text);
	if (rc < 0)
		return cli_bad("%s", err);
	if (rc == 1 && k)
		*k = j;
	return rc;
}

int form_param_list(const char *who, const char *text, double *params, int *given)
{
	char err[600];
	if (bk_params_list(text, params, given, err, sizeof err))
		return cli_bad("%s: %s", who, err);
	return 0;
}

void form_params_text(unsigned used, char *buf, size_t len)
{
	int np = 0, gap = 0;
	while (np < BK_MAX_PARAMS && used >> np)
		gap |= !(used >> np++ & 1u);
	*buf = '\0';
	if (!gap && np > 1)
		snprintf(buf, len, "p0..p%d", np - 1);
	else
		for (int k = 0; k < np; k++)
			if (used >> k & 1u)
				snprintf(buf + strlen(buf), len - strlen(buf), "%sp%d", *buf ? ", " : "", k);
}

int form_gap(unsigned used, int *missing)
{
	int np = 0;
	while (np < BK_MAX_PARAMS && used >> np)
		np++;
	for (int k = 0; k < np; k++)
		if (!(used >> k & 1u)) {
			*missing = k;
			return np - 1;
		}
	return -1;
}

int form_check_params(const char *cmd, const char *name, unsigned used, const int *have, const int *given)
{
	int np = 0, missing, top = form_gap(used, &missing);
	while (np < BK_MAX_PARAMS && used >> np)
		np++;
	if (top >= 0) /* the values would be positional: p0..p14 all needed, all unused */
		return cli_bad("%s uses p%d but not p%d: number the parameters from p0, without a gap", name, top, missing);
	for (int k = 0; k < np; k++)
		if (!have[k]) {
			if (np == 1)
				return cli_bad("%s uses p0 but no value was given (p0=VALUE)", name);
			return cli_bad("%s uses p0..p%d but no value was given for p%d (p%d=VALUE)", name, np - 1, k, k);
		}
	for (int k = np; given && k < BK_MAX_PARAMS; k++)
		if (given[k]) {
			if (np == 0)
				return cli_bad("p%d=VALUE has no effect: %s uses no parameter", k, name);
			if (np == 1)
				return cli_bad("p%d=VALUE has no effect: %s uses p0 only", k, name);
			return cli_bad("p%d=VALUE has no effect: %s uses p0..p%d only", k, name, np - 1);
		}
	(void)cmd;
	return 0;
}

int form_check_finite(const char *cmd, const char *name, const bk_form *f, const double *params)
{
	char what[200];
	int rc = bk_form_nonfinite(f, params, what, sizeof what);
	if (rc > 0) {
		fprintf(stderr, "brdfkit %s: %s: the code would compute a constant that is not finite: %s\n", cmd, name,
		        what);
		return 2;
	}
	if (rc == 0 && (params || bk_form_nparams(f) == 0) &&
	    (rc = bk_form_nowhere_finite(f, params, what, sizeof what)) > 0) {
		fprintf(stderr, "brdfkit %s: %s: the form is NaN or infinite everywhere on its inputs' domain [0, 1] "
		        "(%s): nothing to compute\n", cmd, name, what);
		return 2;
	}
	return rc < 0 ? cli_fail(cmd, "out of memory") : 0;
}

void form_warn_precision(const char *cmd, const char *name, const bk_form *f, const double *params, bk_precision prec)
{
	char what[200];
	if (!cmd)
		cmd = cli_name();
	int n = bk_form_const_range(f, params, prec, what, sizeof what);
	if (n > 0)
		fprintf(stderr, "brdfkit %s: warning: %s: %s%s\n", cmd, name, what,
		        n > 1 ? " (and more constants the precision cannot hold)" : "");
	/* A constant out of range is usually why the result is lost too: one
	 * warning names the cause, not two the same thing. */
	else if ((n = bk_form_range_lost(f, params, prec, what, sizeof what)) > 0)
		fprintf(stderr, "brdfkit %s: warning: %s: the result is out of %s precision's range at every one of the "
		        "%d samples of its inputs' domain where it has a value (%s)\n", cmd, name,
		        prec == BK_F16 ? "half" : "single", n, what);
}
