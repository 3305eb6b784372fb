/*
 * test_params.c — the one reader of parameter values (analysis/params.h):
 * pN names, pN=VALUE words, p0=X;p1=Y lists. The expected values are the
 * decimal texts typed here; each refusal beside a control that passes just
 * inside it, and every error text pinned (it is what a user reads).
 */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "params.h"

TestSuite(params, .timeout = 10);

static char err[700];

Test(params, names_have_one_spelling)
{
	cr_assert_eq(bk_param_index("p0", 2), 0);
	cr_assert_eq(bk_param_index("p9", 2), 9);
	cr_assert_eq(bk_param_index("p15", 3), 15);
	cr_assert_eq(bk_param_index("p10=", 3), 10); /* the length bounds the name */
	cr_assert_eq(bk_param_index("p16", 3), -1);  /* control of p15: one past the last */
	cr_assert_eq(bk_param_index("p01", 3), -1);  /* a second name for p1 */
	cr_assert_eq(bk_param_index("p00", 3), -1);
	cr_assert_eq(bk_param_index("p", 1), -1);
	cr_assert_eq(bk_param_index("q1", 2), -1);
	cr_assert_eq(bk_param_index("p-1", 3), -1);
	cr_assert_eq(bk_param_index("p1x", 3), -1);
	cr_assert_eq(bk_param_index("p100", 4), -1);
}

Test(params, a_word_is_read_or_named_wrong)
{
	int k = -1;
	double v = NAN;
	cr_assert_eq(bk_params_word("p3=0.25", &k, &v, err, sizeof err), 1);
	cr_assert_eq(k, 3);
	cr_assert_eq(v, 0.25);
	cr_assert_eq(bk_params_word("p15=-1e-3", &k, &v, err, sizeof err), 1);
	cr_assert_eq(k, 15);
	cr_assert_eq(v, -1e-3);
	/* not of the shape: the caller reads it as something else */
	const char *other[] = {"NoV=0.5", "p=1", "p0", "p1x=2", "0.5", "", "P0=1"};
	for (size_t i = 0; i < sizeof other / sizeof *other; i++)
		cr_assert_eq(bk_params_word(other[i], &k, &v, err, sizeof err), 0, "'%s'", other[i]);
	/* of the shape, refused */
	cr_assert_eq(bk_params_word("p16=1", &k, &v, err, sizeof err), -1);
	cr_assert_str_eq(err, "unknown parameter 'p16' (p0..p15)");
	cr_assert_eq(bk_params_word("p01=1", &k, &v, err, sizeof err), -1);
	cr_assert_str_eq(err, "unknown parameter 'p01' (p0..p15)");
	const char *bad[] = {"inf", "nan", "1e999", "0x1", " 5", "5 ", "", "1,5"};
	for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
		char w[32], want[80];
		snprintf(w, sizeof w, "p2=%s", bad[i]);
		cr_assert_eq(bk_params_word(w, &k, &v, err, sizeof err), -1, "'%s'", w);
		snprintf(want, sizeof want, "p2: expected a finite number, got '%s'", bad[i]);
		cr_assert_str_eq(err, want);
	}
	/* controls of inf and 1e999: the largest finite double and a subnormal are numbers */
	cr_assert_eq(bk_params_word("p2=1.7976931348623157e308", &k, &v, err, sizeof err), 1);
	cr_assert_eq(v, 1.7976931348623157e308);
	cr_assert_eq(bk_params_word("p2=5e-324", &k, &v, err, sizeof err), 1);
	cr_assert_gt(v, 0);
}

Test(params, a_word_given_twice_is_refused)
{
	double p[BK_MAX_PARAMS] = {0};
	int given[BK_MAX_PARAMS] = {0}, k = -1;
	cr_assert_eq(bk_params_set("p1=2", p, given, &k, err, sizeof err), 1);
	cr_assert(k == 1 && p[1] == 2 && given[1] == 1);
	cr_assert_eq(bk_params_set("p0=3", p, given, NULL, err, sizeof err), 1); /* control: another one */
	cr_assert(p[0] == 3 && given[0] == 1);
	k = -1;
	cr_assert_eq(bk_params_set("p1=5", p, given, &k, err, sizeof err), -1);
	cr_assert_str_eq(err, "p1 given twice ('p1=5')");
	cr_assert_eq(k, 1);
	cr_assert_eq(p[1], 2); /* the first value kept */
	cr_assert_eq(bk_params_set("NoV=1", p, given, &k, err, sizeof err), 0);
}

Test(params, a_list_is_read_whole)
{
	double p[BK_MAX_PARAMS] = {0};
	int given[BK_MAX_PARAMS] = {0};
	cr_assert_eq(bk_params_list("p0=0.5;p2=-3,p1=1e2; p3=7", p, given, err, sizeof err), 0, "%s", err);
	cr_assert(p[0] == 0.5 && p[1] == 100 && p[2] == -3 && p[3] == 7);
	cr_assert(given[0] && given[1] && given[2] && given[3] && !given[4]);
	/* all sixteen, the most a list can hold without a name twice */
	char all[600] = "";
	for (int k = 0; k < BK_MAX_PARAMS; k++)
		snprintf(all + strlen(all), sizeof all - strlen(all), "%sp%d=%d.25", k ? ";" : "", k, k);
	int g2[BK_MAX_PARAMS] = {0};
	cr_assert_eq(bk_params_list(all, p, g2, err, sizeof err), 0, "%s", err);
	for (int k = 0; k < BK_MAX_PARAMS; k++)
		cr_assert(g2[k] && p[k] == k + 0.25);
	/* the empty list: nothing given */
	int g3[BK_MAX_PARAMS] = {0};
	cr_assert_eq(bk_params_list("", p, g3, err, sizeof err), 0);
	for (int k = 0; k < BK_MAX_PARAMS; k++)
		cr_assert(!g3[k]);
}

static void refused(const char *list, const char *want)
{
	double p[BK_MAX_PARAMS] = {0};
	int given[BK_MAX_PARAMS] = {0};
	cr_assert_eq(bk_params_list(list, p, given, err, sizeof err), -1, "'%s' accepted", list);
	cr_assert_str_eq(err, want, "'%s'", list);
}

static void taken(const char *list)
{
	double p[BK_MAX_PARAMS] = {0};
	int given[BK_MAX_PARAMS] = {0};
	cr_assert_eq(bk_params_list(list, p, given, err, sizeof err), 0, "'%s': %s", list, err);
}

Test(params, a_bad_list_names_the_item)
{
	refused("p0=1;p0=2", "parameters: p0 given twice in the list 'p0=1;p0=2' (item 2)");
	taken("p0=1;p1=2");
	refused("p0=1;;p1=2", "parameters: empty item in the list 'p0=1;;p1=2' (item 2)");
	refused("p0=1;", "parameters: empty item in the list 'p0=1;' (item 2)");
	refused(";p0=1", "parameters: empty item in the list ';p0=1' (item 1)");
	refused("p0=1; ", "parameters: empty item in the list 'p0=1; ' (item 2)");
	taken("p0=1; p1=1");
	refused("p0=1;p1", "parameters: expected pN=VALUE with N in 0..15, got 'p1' (item 2)"); /* no '=' */
	refused("p0=1;x=2", "parameters: expected pN=VALUE with N in 0..15, got 'x=2' (item 2)");
	refused("p0=1;p16=2", "parameters: unknown parameter 'p16' (p0..p15) (item 2)");
	taken("p0=1;p15=2");
	refused("p0=inf", "parameters: p0: expected a finite number, got 'inf' (item 1)");
	refused("p0=1;p1=nan", "parameters: p1: expected a finite number, got 'nan' (item 2)");
	refused("p0=1e999", "parameters: p0: expected a finite number, got '1e999' (item 1)");
	taken("p0=1e300");
	/* seventeen items: the last is a name twice or past p15 */
	char many[600] = "";
	for (int k = 0; k <= BK_MAX_PARAMS; k++)
		snprintf(many + strlen(many), sizeof many - strlen(many), "%sp%d=1", k ? ";" : "", k);
	refused(many, "parameters: unknown parameter 'p16' (p0..p15) (item 17)");
	/* an item longer than 127 characters: cut, it would be another number */
	char item[200];
	snprintf(item, sizeof item, "p0=0.%0125d", 1);
	cr_assert_eq(strlen(item), 130);
	char want[300];
	snprintf(want, sizeof want, "parameters: an item longer than 127 characters in '%.60s...' (item 1)", item);
	refused(item, want);
	snprintf(item, sizeof item, "p0=0.%0122d", 1); /* control: 127 characters */
	cr_assert_eq(strlen(item), 127);
	taken(item);
}

/* --domain lists: the one reader of fit's and search's --domain and of
 * bench_recovery's planted forms. Each item at fault is named; an interval
 * narrower than min_rel of its larger end (one ulp at 0.5) is refused, and
 * the same interval passes with min_rel 0 (the control). */
Test(params, domain_lists)
{
	bk_target_options to;
	char err[400];
	memset(&to, 0, sizeof to);
	cr_assert_eq(bk_params_domain("NoV=0:1,r=0.3:1", 1e-6, &to, err, sizeof err), 0, "%s", err);
	cr_assert_eq(to.ndomain, 2);
	cr_assert(to.dom_in[0] == BK_IN_NOV && to.dom_lo[0] == 0 && to.dom_hi[0] == 1);
	cr_assert(to.dom_in[1] == BK_IN_R && to.dom_lo[1] == 0.3 && to.dom_hi[1] == 1);
	static const struct {
		const char *text, *err;
	} bad[] = {
		{"NoV", "expected NAME=LO:HI, got 'NoV'"},
		{"x=0:1", "'x' is not an input"},
		{"NoV=0:y", "NoV: expected LO:HI (two numbers), got '0:y'"},
		{"NoV=1:0", "NoV: expected LO < HI, got '1:0'"},
		{"NoV=0:1,LoH=0.5:0.5000000000000001", "LoH: '0.5:0.5000000000000001' is too narrow to sample"},
	};
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
		cr_assert_eq(bk_params_domain(bad[i].text, 1e-6, &to, err, sizeof err), -1, "%s", bad[i].text);
		cr_assert(strstr(err, bad[i].err), "%s: %s", bad[i].text, err);
	}
	cr_assert_eq(bk_params_domain("LoH=0.5:0.5000000000000001", 0, &to, err, sizeof err), 0, "%s", err);
}
