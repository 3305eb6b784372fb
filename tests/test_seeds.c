/*
 * test_seeds.c — what a search starts from (fit/search/seeds.h) and the one
 * catalog-to-target mapping (fit/search/catalogmap.h). The expected entries
 * are read off fit/catalog.c by hand: its VF, V, env and F rows, their texts
 * and their order.
 */
#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

#include "catalog.h"
#include "search/catalogmap.h"
#include "search/seeds.h"

static const unsigned ALL = (1u << BK_IN_COUNT) - 1;

/* vf2d: the four VF rows of the catalog, in catalog order; no V row (one of
 * them, v_kelemen_talk_r x Schlick, is the target itself). */
Test(seeds, vf2d_gets_the_vf_rows)
{
	bk_seeds sd;
	memset(&sd, 0, sizeof sd);
	cr_assert_eq(bk_seeds_catalog(&sd, BK_TARGET_VF2D, 0, ALL), 0);
	const char *want[] = {"vf_talk_r", "vf_talk_a", "vf_talk_unity_urp", "fv_schuler"};
	cr_assert_eq(sd.n, 4);
	for (int k = 0; k < 4; k++)
		cr_expect_str_eq(sd.name[k], want[k]);
	cr_expect_str_eq(sd.text[0], "f0/(4*LoH*LoH*(r + p0))");
	cr_expect_eq(sd.p[0][0], 0.5); /* vf_talk_r's published p0 */
	cr_expect_null(sd.text_b[0]);
	bk_seeds_free(&sd);
}

/* vf: the V rows too, each times Schlick's F; v_kelemen is 0.25/(LoH*LoH). */
Test(seeds, vf_gets_v_rows_times_schlick)
{
	bk_seeds sd;
	memset(&sd, 0, sizeof sd);
	cr_assert_eq(bk_seeds_catalog(&sd, BK_TARGET_VF, 0, ALL), 0);
	int found = 0;
	for (int k = 0; k < sd.n; k++)
		if (!strcmp(sd.name[k], "v_kelemen")) {
			cr_expect_str_eq(sd.text[k], "(0.25/(LoH*LoH))*F_schlick(f0, 1, LoH)");
			found = 1;
		}
	cr_expect(found, "v_kelemen not seeded on vf");
	/* 4 VF rows and 6 V rows (v_hammon, v_kelemen, _unreal, _hable, _talk_r, _talk_a) */
	cr_expect_eq(sd.n, 10);
	bk_seeds_free(&sd);
}

/* f: the three F rows, then Schlick's baseline at constants 1. */
Test(seeds, f_ends_with_the_schlick_baseline)
{
	bk_seeds sd;
	memset(&sd, 0, sizeof sd);
	cr_assert_eq(bk_seeds_catalog(&sd, BK_TARGET_F, 0, ALL), 0);
	cr_assert_eq(sd.n, 4);
	cr_expect_str_eq(sd.name[0], "f_schlick_sg");
	cr_expect_str_eq(sd.name[3], "F_schlick");
	cr_expect_str_eq(sd.text[3], "F_schlick(f0, 1, LoH)");
	cr_expect_eq(sd.p[3][0], 1.0);
	bk_seeds_free(&sd);
}

/* env as split pairs: env_talk_r stays A = 1, B = (1 - max(r, NoV))^3; as
 * one form it is f0*(1) + ((1 - max(r, NoV))^3), and the env_f0 rows join. */
Test(seeds, env_pairs_split_or_one_form)
{
	bk_seeds a, b;
	memset(&a, 0, sizeof a);
	memset(&b, 0, sizeof b);
	cr_assert_eq(bk_seeds_catalog(&a, BK_TARGET_ENV, 0, ALL), 0);
	cr_assert_eq(bk_seeds_catalog(&b, BK_TARGET_ENV, 1, ALL), 0);
	cr_assert_str_eq(a.name[0], "env_talk_r");
	cr_expect_str_eq(a.text[0], "1");
	cr_expect_str_eq(a.text_b[0], "(1 - max(r, NoV))^3");
	cr_assert_str_eq(b.name[0], "env_talk_r");
	cr_expect_str_eq(b.text[0], "f0*(1) + ((1 - max(r, NoV))^3)");
	cr_expect_null(b.text_b[0]);
	/* split rows: env_talk_r, env_talk_a, env_karis2014_split, env_materialx;
	 * one form adds the 12 env_f0 rows */
	cr_expect_eq(a.n, 4);
	cr_expect_eq(b.n, 16);
	bk_seeds_free(&a);
	bk_seeds_free(&b);
}

/* Negative control of the inputs check: without NoV no env row reads only
 * what the samples provide. */
Test(seeds, rows_reading_a_missing_input_are_left_out)
{
	bk_seeds sd;
	memset(&sd, 0, sizeof sd);
	cr_assert_eq(bk_seeds_catalog(&sd, BK_TARGET_ENV, 0, ALL & ~(1u << BK_IN_NOV)), 0);
	cr_expect_eq(sd.n, 0);
	bk_seeds_free(&sd);
}

Test(seeds, screening_grid_per_target)
{
	bk_target_options o;
	bk_target_defaults(BK_TARGET_VF2D, &o);
	bk_seeds_screening_grid(&o);
	cr_expect(o.nx == 32 && o.nr == 32);
	bk_target_defaults(BK_TARGET_VF, &o);
	bk_seeds_screening_grid(&o);
	cr_expect(o.nx == 8 && o.nr == 8 && o.nu == 8 && o.nphi == 4); /* 2,048 samples */
	bk_target_defaults(BK_TARGET_ENV, &o);
	bk_seeds_screening_grid(&o);
	cr_expect(o.nx == 16 && o.nr == 16);
	bk_target_defaults(BK_TARGET_FORM, &o);
	o.ndomain = 2;
	bk_seeds_screening_grid(&o);
	cr_expect_eq(o.nx, 32); /* 32 x 32 = 1,024 */
}

Test(seeds, add_apply_and_full)
{
	bk_seeds sd;
	memset(&sd, 0, sizeof sd);
	for (int k = 0; k < BK_SEEDS_MAX; k++)
		cr_assert_eq(bk_seeds_add(&sd, "p0*r", NULL, NULL, NULL), 0);
	cr_expect_eq(bk_seeds_add(&sd, "p0*r", NULL, NULL, NULL), -1); /* full */
	bk_search_options o;
	bk_search_defaults(&o);
	bk_seeds_apply(&sd, &o);
	cr_expect_eq(o.nseeds, BK_SEEDS_MAX);
	cr_expect_eq(o.seeds, sd.text);
	cr_expect_eq(o.seed_p[5][2], 1.0);
	bk_seeds_free(&sd);
}

/* ---- the mapping ---------------------------------------------------------- */

Test(catalogmap, tags_and_answers)
{
	cr_expect_str_eq(bk_catmap_tag(BK_TARGET_SPEC), "DVF");
	cr_expect_null(bk_catmap_tag(BK_TARGET_FORM));
	const bk_catalog_entry *v = bk_catalog_find("v_kelemen"), *e = bk_catalog_find("env_karis2014");
	cr_assert(v && e);
	cr_expect(bk_catmap_answers(BK_TARGET_VF, 0, v));
	cr_expect(bk_catmap_answers(BK_TARGET_VF2D, 0, v)); /* compare lists it on vf2d */
	cr_expect(!bk_catmap_answers(BK_TARGET_D, 0, v));
	cr_expect(bk_catmap_answers(BK_TARGET_ENV, 1, e));  /* env_f0 as one form */
	cr_expect(!bk_catmap_answers(BK_TARGET_ENV, 0, e)); /* not among split pairs */
}

/* spec is the rendered lobe (D V F NoL): a DVF row is scored times NoL. */
Test(catalogmap, spec_rows_times_nol)
{
	const bk_catalog_entry *d = bk_catalog_find("dvf_talk_r");
	cr_assert(d);
	char *t = bk_catmap_form(BK_TARGET_SPEC, 0, d);
	cr_assert(t);
	char want[512];
	snprintf(want, sizeof want, "(%s)*NoL", d->form);
	cr_expect_str_eq(t, want);
	free(t);
}
