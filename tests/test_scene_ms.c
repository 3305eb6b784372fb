/*
 * test_scene_ms.c — the terms a scene asks for by key (issue 41, scene.h):
 * "multiscatter" (ms, E = A + B) and "cloth" (sheen, the Charlie sheen
 * albedo, and cloth, the exact D_charlie V_neubelt lobe): read, planned into
 * sets of their own, absent where not asked; ms read from the set's env LUT
 * (bk_scene_ms_from_env) only where that LUT carries A and B. The emitted
 * functions against the exact integrals: tests/cli_scene_ms.sh.
 */
#include "brdf.h"
#include "scene.h"
#include "scene_fit.h"

#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

static bk_scene sc;
static char err[512];

static int parse(const char *text)
{
	err[0] = 0;
	return bk_scene_parse(text, strlen(text), &sc, err, sizeof err);
}

static void expect_error(const char *text, const char *message)
{
	cr_assert_eq(parse(text), -1, "accepted: %s", text);
	cr_expect_str_eq(err, message);
}

Test(scene_ms, keys_read_and_defaults)
{
	cr_assert_eq(parse("{\"materials\": [{\"name\": \"m\"}]}"), 0, "%s", err);
	cr_expect(!sc.mat[0].multiscatter && !sc.mat[0].cloth && !sc.multiscatter);
	cr_expect_eq(sc.budget_ms, BK_SCENE_BUDGET_GENERIC);
	cr_expect_eq(sc.budget_sheen, BK_SCENE_BUDGET_GENERIC);
	cr_assert_eq(parse("{\"materials\": [{\"name\": \"m\", \"multiscatter\": true, \"cloth\": true}], "
	                   "\"target\": {\"error\": {\"ms\": 0.02, \"sheen\": 0.03}}}"), 0, "%s", err);
	cr_expect(sc.mat[0].multiscatter && sc.mat[0].cloth);
	cr_expect_eq(sc.budget_ms, 0.02);
	cr_expect_eq(sc.budget_sheen, 0.03);
	cr_expect_eq(sc.budget_vf, BK_SCENE_BUDGET_GENERIC); /* the others untouched */
	/* one number and the words are every term's */
	cr_assert_eq(parse("{\"materials\": [{\"name\": \"m\", \"multiscatter\": true}], \"target\": {\"error\": 0.05}}"), 0,
	             "%s", err);
	cr_expect(sc.budget_ms == 0.05 && sc.budget_sheen == 0.05 && sc.budget_env == 0.05);
	cr_assert_eq(parse("{\"materials\": [{\"name\": \"m\"}], \"target\": {\"error\": \"at-generic-cost\"}}"), 0, "%s", err);
	cr_expect(sc.budget_ms == BK_SCENE_BUDGET_AT_COST && sc.budget_sheen == BK_SCENE_BUDGET_AT_COST);
}

Test(scene_ms, bad_keys_name_their_path)
{
	expect_error("{\"materials\": [{\"name\": \"m\", \"multiscatter\": 1}]}",
	             "materials[0].multiscatter: expected true or false, got a number");
	expect_error("{\"materials\": [{\"name\": \"m\"}, {\"name\": \"n\", \"cloth\": \"yes\"}]}",
	             "materials[1].cloth: expected true or false, got a string");
	expect_error("{\"materials\": [{\"name\": \"m\"}], \"lighting\": {\"multiscatter\": []}}",
	             "lighting.multiscatter: expected true or false, got a list");
	expect_error("{\"materials\": [{\"name\": \"m\", \"specular\": false, \"multiscatter\": true}]}",
	             "materials[0].multiscatter: true has no effect: material 'm' is not specular (\"specular\": false)");
	expect_error("{\"materials\": [{\"name\": \"m\"}], \"target\": {\"error\": {\"ms\": 0.01}}}",
	             "target.error.ms: has no effect when no specular material asks for \"multiscatter\"");
	expect_error("{\"materials\": [{\"name\": \"m\", \"multiscatter\": true}], \"target\": {\"error\": {\"sheen\": 0.01}}}",
	             "target.error.sheen: has no effect when no material asks for \"cloth\"");
	expect_error("{\"materials\": [{\"name\": \"m\", \"multiscatter\": true}], \"target\": {\"error\": {\"ms\": 2}}}",
	             "target.error.ms: 2 is outside [1e-06, 1]");
	/* control: a cloth alone is shaded (no "would not be shaded at all") */
	cr_assert_eq(parse("{\"materials\": [{\"name\": \"m\", \"specular\": false, \"cloth\": true}], "
	                   "\"lighting\": {\"diffuse\": false}}"), 0, "%s", err);
}

/* Sets from needs: ms and cloth only where asked, in the name too; the same
 * materials without the keys keep the names they had. */
Test(scene_ms, plan_and_names)
{
	cr_assert_eq(parse("{\"materials\": [{\"name\": \"steel\", \"f0\": \"metal\", \"multiscatter\": true},"
	                   "{\"name\": \"iron\", \"f0\": \"metal\"},"
	                   "{\"name\": \"velvet\", \"specular\": false, \"cloth\": true},"
	                   "{\"name\": \"silk\", \"cloth\": true, \"f0\": 0.04}]}"), 0, "%s", err);
	bk_scene_set sets[BK_SCENE_MAX_MATERIALS];
	cr_assert_eq(bk_scene_plan(&sc, sets), 4);
	cr_expect_str_eq(sets[0].name, "spec_ibl_ms_diffuse_anyf0");
	cr_expect(sets[0].needs.ms && !sets[0].needs.sheen && !sets[0].needs.cloth);
	cr_expect_str_eq(sets[1].name, "spec_ibl_diffuse_anyf0"); /* as before the keys */
	cr_expect(!sets[1].needs.ms);
	cr_expect_str_eq(sets[2].name, "cloth_diffuse");
	cr_expect(sets[2].needs.sheen && sets[2].needs.cloth && !sets[2].needs.vf && !sets[2].needs.env);
	cr_expect_str_eq(sets[3].name, "spec_ibl_cloth_diffuse_f0_040");
	/* lighting.multiscatter: every specular material's; no punctual light: no cloth lobe, the albedo stays */
	cr_assert_eq(parse("{\"materials\": [{\"name\": \"a\"}, {\"name\": \"v\", \"specular\": false, \"cloth\": true}],"
	                   " \"lighting\": {\"multiscatter\": true, \"punctual\": false}}"), 0, "%s", err);
	bk_scene_needs n;
	bk_scene_material_needs(&sc, 0, &n);
	cr_expect(n.ms && n.env && !n.vf);
	bk_scene_material_needs(&sc, 1, &n);
	cr_expect(!n.ms && n.sheen && !n.cloth);
	cr_expect_str_eq(bk_scene_term_name(BK_SCENE_TERM_MS), "ms");
	cr_expect_str_eq(bk_scene_term_name(BK_SCENE_TERM_SHEEN), "sheen");
	cr_expect_str_eq(bk_scene_term_name(BK_SCENE_TERM_CLOTH), "cloth");
}

/* E = A + B from the env LUT: taken from a 128^2 float LUT of A and B, for
 * one add and no fetch, its error on ms's domain that of bilinear filtering
 * alone (below 1e-3); refused from a folded layout, and under a budget
 * below its error (the controls). */
Test(scene_ms, ms_from_the_env_lut, .timeout = 300)
{
	cr_assert_eq(parse("{\"materials\": [{\"name\": \"m\", \"roughness\": {\"min\": 0.5, \"max\": 1}, "
	                   "\"f0\": \"metal\", \"multiscatter\": true}], \"target\": {\"error\": {\"ms\": 0.01}}}"), 0,
	             "%s", err);
	bk_scene_set sets[BK_SCENE_MAX_MATERIALS];
	cr_assert_eq(bk_scene_plan(&sc, sets), 1);
	bk_scene_choice env, ms;
	memset(&env, 0, sizeof env);
	env.lut = 1;
	env.lut_size = 128;
	env.lut_layout = (bk_lut_layout){128, 128, 0, 1, BK_LUT_WARP_NONE, NAN};
	env.lut_fmt = BK_LUT_FLOAT;
	snprintf(env.name, sizeof env.name, "LUT 128x128 float");
	/* an ms choice as a form would be: cost 20, error 0.005 */
	memset(&ms, 0, sizeof ms);
	ms.cost = 20;
	ms.err = 0.005;
	ms.budget = 0.01;
	ms.meets = 1;
	/* the generic's E as a fetch of its own (bk_scene_choose cannot know the set's env) */
	bk_scene_choice gen;
	memset(&gen, 0, sizeof gen);
	gen.cost = 33;
	gen.fetches = 1;
	gen.err = 7e-4;
	int taken;
	cr_assert_eq(bk_scene_ms_from_env(&sc, &sets[0], &env, &ms, &gen, &taken, err, sizeof err), 0, "%s", err);
	cr_assert(taken);
	/* the generic shader's env LUT holds A and B too: its E costs one add and no fetch, its error as it was */
	cr_expect(gen.cost == sc.simple_cost && gen.fetches == 0 && gen.err == 7e-4);
	/* and at that cost (one add) the only candidate is the env LUT's A + B */
	cr_expect(strstr(ms.eq_name, "A + B") && ms.eq_cost == sc.simple_cost && ms.eq_err == ms.err, "%s", ms.eq_name);
	cr_expect_eq(ms.fetches, 0);
	cr_expect_eq(ms.cost, sc.simple_cost);
	cr_expect(ms.err > 0 && ms.err < 1e-3, "E from a 128^2 float LUT: %g", ms.err);
	cr_expect(ms.meets);
	/* control: a folded layout (f0 A + B at one f0) carries no E */
	bk_scene_choice ms2;
	memset(&ms2, 0, sizeof ms2);
	ms2.cost = 20;
	ms2.err = 0.005;
	ms2.budget = 0.01;
	ms2.meets = 1;
	env.lut_layout.f0 = 0.04;
	cr_assert_eq(bk_scene_ms_from_env(&sc, &sets[0], &env, &ms2, NULL, &taken, err, sizeof err), 0, "%s", err);
	cr_expect(!taken && ms2.cost == 20);
	/* control: a budget below what the LUT reaches keeps the form */
	env.lut_layout.f0 = NAN;
	ms2.budget = 1e-6;
	cr_assert_eq(bk_scene_ms_from_env(&sc, &sets[0], &env, &ms2, NULL, &taken, err, sizeof err), 0, "%s", err);
	cr_expect(!taken && ms2.cost == 20);
}
