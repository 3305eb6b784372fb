/*
 * form_check.c — the checks of a form every command shares (form_check.h).
 */
#include "form_check.h"

#include "cli.h"

#include <stdio.h>

int form_check_params(const char *cmd, const char *name, int np, const int *have, const int *given)
{
	for (int k = 0; k < np; k++)
		if (!have[k]) {
			if (np == 1)
				fprintf(stderr, "brdfkit %s: %s uses p0 but no value was given (p0=VALUE)\n", cmd, name);
			else
				fprintf(stderr, "brdfkit %s: %s uses p0..p%d but no value was given for p%d (p%d=VALUE)\n", cmd,
				        name, np - 1, k, k);
			return 2;
		}
	for (int k = np; given && k < BK_MAX_PARAMS; k++)
		if (given[k]) {
			if (np == 0)
				fprintf(stderr, "brdfkit %s: p%d=VALUE has no effect: %s uses no parameter\n", cmd, k, name);
			else if (np == 1)
				fprintf(stderr, "brdfkit %s: p%d=VALUE has no effect: %s uses p0 only\n", cmd, k, name);
			else
				fprintf(stderr, "brdfkit %s: p%d=VALUE has no effect: %s uses p0..p%d only\n", cmd, k, name,
				        np - 1);
			return 2;
		}
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
