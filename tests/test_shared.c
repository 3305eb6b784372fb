/*
 * test_shared.c — what a process keeps for its threads (make results' speed,
 * issue 22): the LUT reference tables of analysis/lutscore.c, shared by
 * threads and kept, and the env reference samples of analysis/scene_fit.c,
 * built once per domain. The values must not depend on who built them or
 * when: threads at once, then again from what is kept, then rebuilt; and a
 * different domain must not be taken for a kept one.
 */
#include "brdf.h"
#include "compare.h"
#include "scene.h"
#include "scene_fit.h"
#include "fixture_scene.h"
#include "target.h"

#include <criterion/criterion.h>
#include <math.h>
#include <pthread.h>
#include <string.h>

/* ---- LUT tables ----------------------------------------------------------- */

typedef struct lut_arg {
	const bk_lut_layout *L;
	bk_lut_format fmt;
	const bk_samples *s;
	bk_fit_metrics m;
	int rc;
} lut_arg;

static void *score_lut(void *v)
{
	lut_arg *a = v;
	a->rc = bk_lut_score_layout(a->L, a->fmt, BK_SMITH_CORRELATED, BK_F64, a->s, &a->m, NULL);
	return NULL;
}

/* Samples at the texel centres of a 16x16 table over r in [0.37, 0.83] (a
 * layout no other test asks): a float table is then off by its storage's
 * rounding alone (bilinear weights 0 at a centre), below 1e-7, from two
 * threads baking it at once and from the kept table after; unorm8's rounding
 * is well above that (the control). */
Test(shared, lut_table_from_threads_and_kept, .timeout = 120)
{
	bk_target_options o;
	char err[256];
	bk_target_defaults(BK_TARGET_ENV, &o);
	o.nx = o.nr = 16;
	o.x_lo = 0, o.x_hi = 1, o.r_lo = 0.37, o.r_hi = 0.83;
	bk_samples s;
	cr_assert_eq(bk_target_build(&o, &s, NULL, NULL, err, sizeof err), 0, "%s", err);
	bk_lut_layout L = {16, 16, 0.37, 0.83, BK_LUT_WARP_NONE, NAN};
	lut_arg a[3];
	memset(a, 0, sizeof a);
	for (int t = 0; t < 3; t++)
		a[t] = (lut_arg){.L = &L, .fmt = t < 2 ? BK_LUT_FLOAT : BK_LUT_UNORM8, .s = &s, .rc = -1};
	pthread_t th[2];
	for (int t = 0; t < 2; t++)
		cr_assert_eq(pthread_create(&th[t], NULL, score_lut, &a[t]), 0);
	for (int t = 0; t < 2; t++)
		pthread_join(th[t], NULL);
	score_lut(&a[2]);
	for (int t = 0; t < 3; t++)
		cr_assert_eq(a[t].rc, 0, "call %d failed", t);
	cr_expect(a[0].m.max_abs < 1e-7, "float at the centres: %g", a[0].m.max_abs);
	cr_expect_eq(a[0].m.max_abs, a[1].m.max_abs, "two threads: %.17g, %.17g", a[0].m.max_abs, a[1].m.max_abs);
	cr_expect_eq(a[0].m.rmse, a[1].m.rmse);
	cr_expect(a[2].m.max_abs > 1e-4, "unorm8 at the centres: %g (its rounding, up to 1/510)", a[2].m.max_abs);
	lut_arg again = {.L = &L, .fmt = BK_LUT_FLOAT, .s = &s, .rc = -1};
	score_lut(&again); /* from the kept table */
	cr_assert_eq(again.rc, 0);
	cr_expect_eq(again.m.max_abs, a[0].m.max_abs);
	cr_expect_eq(again.m.rmse, a[0].m.rmse);
	bk_samples_free(&s);
}

/* ---- scene env references ------------------------------------------------- */

static bk_scene sc;

/* Karis' nonmetal env form at its published constants */
static const char *const karis = "min((p0*r + p2)*(p0*r + p2), exp2(p4*NoV))*(p0*r + p2) + (p1*r + p3)";

typedef struct env_arg {
	bk_scene_set set;
	double e;
	int rc;
} env_arg;

static void *env_error(void *v)
{
	env_arg *a = v;
	double p[BK_MAX_PARAMS] = {-1, -0.0275, 1, 0.0425, -9.28};
	char err[256];
	a->rc = bk_scene_form_error(&sc, &a->set, BK_SCENE_TERM_ENV, karis, p, 0, &a->e, err, sizeof err);
	return NULL;
}

/* The error of one form on a set's env domain: built, then from the kept
 * samples, then rebuilt after bk_scene_forget, and from two threads at once
 * on a domain not kept yet: the same bits each time; on another roughness
 * range a different error (the kept samples are the domain's own). */
Test(shared, scene_env_reference_kept_per_domain, .timeout = 240)
{
	const char *text = "{\"materials\": [{\"name\": \"m\"}]}";
	char err[512];
	cr_assert_eq(bk_scene_parse(text, strlen(text), &sc, err, sizeof err), 0, "%s", err);
	bk_scene_forget();
	env_arg a = {fx_scene_set(0.5, FX_NEEDS_ENV), 0, -1}, b = a, c = a, other = {fx_scene_set(0.2, FX_NEEDS_ENV), 0, -1};
	env_error(&a); /* built */
	env_error(&b); /* kept */
	bk_scene_forget();
	env_error(&c); /* rebuilt */
	env_error(&other);
	cr_assert(!a.rc && !b.rc && !c.rc && !other.rc);
	cr_expect_eq(a.e, b.e, "built %.17g, kept %.17g", a.e, b.e);
	cr_expect_eq(a.e, c.e, "built %.17g, rebuilt %.17g", a.e, c.e);
	cr_expect_neq(a.e, other.e, "r from 0.5 and from 0.2: %.17g both", a.e);
	env_arg t[2] = {{fx_scene_set(0.7, FX_NEEDS_ENV), 0, -1}, {fx_scene_set(0.7, FX_NEEDS_ENV), 0, -1}};
	pthread_t th[2];
	for (int k = 0; k < 2; k++)
		cr_assert_eq(pthread_create(&th[k], NULL, env_error, &t[k]), 0);
	for (int k = 0; k < 2; k++)
		pthread_join(th[k], NULL);
	cr_assert(!t[0].rc && !t[1].rc);
	cr_expect_eq(t[0].e, t[1].e, "two threads: %.17g, %.17g", t[0].e, t[1].e);
	bk_scene_forget();
	env_arg alone = {fx_scene_set(0.7, FX_NEEDS_ENV), 0, -1};
	env_error(&alone);
	cr_expect_eq(alone.e, t[0].e, "alone after forgetting: %.17g", alone.e);
	bk_scene_forget();
}
