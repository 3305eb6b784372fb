/*
 * params.c — pN=VALUE words, pN names and p0=X;p1=Y lists (params.h).
 */
#include "params.h"

#include "csvtab.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define ITEM_MAX 128 /* a list item: 'p', two digits, '=' and a number of 17 digits fit many times */

int bk_params_word(const char *text, int *k, double *v, char *err, size_t errlen)
{
	const char *eq = strchr(text, '=');
	size_t nd = strspn(text + (text[0] == 'p'), "0123456789");
	if (text[0] != 'p' || nd == 0 || !eq || text + 1 + nd != eq) /* "p1x=2": not a parameter's name */
		return 0;
	int j = bk_param_index(text, nd + 1);
	if (j < 0) {
		snprintf(err, errlen, "unknown parameter '%.*s' (p0..p%d)", (int)(nd < 20 ? nd + 1 : 20), text,
		         BK_MAX_PARAMS - 1);
		return -1;
	}
	if (bk_csvtab_number(eq + 1, v)) {
		snprintf(err, errlen, "p%d: expected a finite number, got '%.100s'", j, eq + 1);
		return -1;
	}
	*k = j;
	return 1;
}

int bk_params_set(const char *text, double *p, int *given, int *k, char *err, size_t errlen)
{
	int j;
	double v;
	int rc = bk_params_word(text, &j, &v, err, errlen);
	if (rc != 1)
		return rc;
	if (k)
		*k = j;
	if (given[j]) { /* a second value would silently replace the first */
		snprintf(err, errlen, "p%d given twice ('%.100s')", j, text);
		return -1;
	}
	p[j] = v;
	given[j] = 1;
	return 1;
}

int bk_params_list(const char *text, double *p, int *given, char *err, size_t errlen)
{
	if (!*text)
		return 0;
	int item = 1;
	for (const char *t = text;; item++) {
		size_t n = strcspn(t, ";,");
		char s[ITEM_MAX], what[300];
		if (n >= sizeof s) { /* cut, it would be another number */
			snprintf(err, errlen, "parameters: an item longer than %d characters in '%.60s...' (item %d)",
			         ITEM_MAX - 1, t, item);
			return -1;
		}
		snprintf(s, sizeof s, "%.*s", (int)n, t);
		const char *w = s + strspn(s, " ");
		int k;
		double v;
		int rc = *w ? bk_params_word(w, &k, &v, what, sizeof what) : 0;
		if (!*w)
			snprintf(err, errlen, "parameters: empty item in the list '%.200s' (item %d)", text, item);
		else if (rc < 0)
			snprintf(err, errlen, "parameters: %s (item %d)", what, item);
		else if (rc == 0)
			snprintf(err, errlen, "parameters: expected pN=VALUE with N in 0..%d, got '%.60s' (item %d)",
			         BK_MAX_PARAMS - 1, w, item);
		else if (given[k])
			snprintf(err, errlen, "parameters: p%d given twice in the list '%.200s' (item %d)", k, text, item);
		if (!*w || rc != 1 || given[k])
			return -1;
		given[k] = 1;
		p[k] = v;
		if (!t[n])
			return 0;
		t += n + 1;
	}
}

int bk_params_domain(const char *text, double min_rel, bk_target_options *to, char *err, size_t errlen)
{
	char buf[1024];
	if (strlen(text) >= sizeof buf) {
		snprintf(err, errlen, "longer than %zu characters", sizeof buf - 1);
		return -1;
	}
	snprintf(buf, sizeof buf, "%s", text);
	to->ndomain = 0;
	for (char *t = buf, *next; t; t = next) {
		if ((next = strchr(t, ',')))
			*next++ = '\0';
		char *eq = strchr(t, '='), *colon = eq ? strchr(eq + 1, ':') : NULL;
		if (!colon) {
			snprintf(err, errlen, "expected NAME=LO:HI, got '%.100s'", t);
			return -1;
		}
		*eq = *colon = '\0';
		int in = -1;
		for (int k = 0; k < BK_IN_COUNT; k++)
			if (!strcmp(t, bk_input_name((bk_input)k)))
				in = k;
		double lo, hi;
		if (in < 0) {
			snprintf(err, errlen, "'%.100s' is not an input (NoV, NoL, NoH, LoH, r, a, f0)", t);
			return -1;
		}
		if (bk_csvtab_number(eq + 1, &lo) || bk_csvtab_number(colon + 1, &hi)) {
			snprintf(err, errlen, "%s: expected LO:HI (two numbers), got '%.100s:%.100s'", t, eq + 1, colon + 1);
			return -1;
		}
		if (!(lo < hi)) {
			snprintf(err, errlen, "%s: expected LO < HI, got '%.100s:%.100s'", t, eq + 1, colon + 1);
			return -1;
		}
		double need = min_rel * fmax(fabs(lo), fabs(hi));
		if (hi - lo < need) {
			snprintf(err, errlen, "%s: '%.70s:%.70s' is too narrow to sample: HI - LO must be at least %g (%g of the "
			         "larger end)", t, eq + 1, colon + 1, need, min_rel);
			return -1;
		}
		if (to->ndomain == BK_IN_COUNT) {
			snprintf(err, errlen, "more than %d inputs", BK_IN_COUNT);
			return -1;
		}
		to->dom_in[to->ndomain] = in;
		to->dom_lo[to->ndomain] = lo;
		to->dom_hi[to->ndomain++] = hi;
	}
	return 0;
}
