/*
 * test_scene_refits.c — the refits analysis/scene_fit.c keeps (make results'
 * speed, issue 22): a scene run refits the catalog's forms on each set's
 * domain, and scenes of one run share domains, so a refit is kept per
 * (samples, term, form, start). What is kept must be what a fit gives: the
 * same bits from the kept refit as from a fresh one (after bk_scene_forget),
 * and another form, start or domain must not be handed a kept refit.
 */
#include "scene.h"
#include "scene_fit.h"
#include "fixture_scene.h"

#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

static bk_scene sc;

/* Karis' nonmetal env form (fit/catalog.c: env_karis2014_nonmetal) */
static const char *const karis = "min((p0*r + p2)*(p0*r + p2), exp2(p4*NoV))*(p0*r + p2) + (p1*r + p3)";
/* the same with its last term's slope held at 0: another form */
static const char *const karis_flat = "min((p0*r + p2)*(p0*r + p2), exp2(p4*NoV))*(p0*r + p2) + (0*p1*r + p3)";

typedef struct outcome {
	double p[BK_MAX_PARAMS], e;
} outcome;

static outcome refit_error(double r_lo, const char *form)
{
	outcome o;
	double p[BK_MAX_PARAMS] = {-1, -0.0275, 1, 0.0425, -9.28}; /* the published constants */
	bk_scene_set set = fx_scene_set(r_lo, FX_NEEDS_ENV);
	char err[256];
	cr_assert_eq(bk_scene_form_error(&sc, &set, BK_SCENE_TERM_ENV, form, p, 1, &o.e, err, sizeof err), 0, "%s", err);
	memcpy(o.p, p, sizeof o.p);
	return o;
}

static int same_p(const outcome *a, const outcome *b)
{
	return !memcmp(a->p, b->p, sizeof a->p);
}

static int same(const outcome *a, const outcome *b)
{
	return same_p(a, b) && a->e == b->e;
}

Test(scene_refits, kept_refit_is_the_fit, .timeout = 240)
{
	const char *text = "{\"materials\": [{\"name\": \"m\"}]}";
	char err[512];
	cr_assert_eq(bk_scene_parse(text, strlen(text), &sc, err, sizeof err), 0, "%s", err);
	bk_scene_forget();
	outcome fitted = refit_error(0.5, karis);
	outcome kept = refit_error(0.5, karis);
	bk_scene_forget();
	outcome fresh = refit_error(0.5, karis);
	cr_expect(same(&fitted, &kept), "kept: p0 %.17g e %.17g, fitted: p0 %.17g e %.17g", kept.p[0], kept.e,
	          fitted.p[0], fitted.e);
	cr_expect(same(&fitted, &fresh), "refitted after forgetting: p0 %.17g, first: %.17g", fresh.p[0], fitted.p[0]);
	/* the refit moved the constants (else "the same" says nothing) */
	cr_expect(fitted.p[0] != -1 || fitted.p[4] != -9.28, "the refit left the published constants");
	/* another domain, another form: not the kept refit's constants (the start is in the
	 * key too, but two starts may well reach the same rounded constants, so
	 * no start makes a control that must differ) */
	outcome other_r = refit_error(0.6, karis);
	outcome other_form = refit_error(0.5, karis_flat);
	cr_expect(!same_p(&other_r, &fitted), "r from 0.6 got r from 0.5's refit: p0 %.17g", other_r.p[0]);
	cr_expect(!same_p(&other_form, &fitted), "the form without p1 got the full form's refit: p1 %.17g",
	          other_form.p[1]);
	/* and each of those is its own fit: the same after forgetting */
	bk_scene_forget();
	outcome again = refit_error(0.5, karis_flat);
	cr_expect(same(&again, &other_form), "the other form refitted afresh: p3 %.17g, kept %.17g", again.p[3],
	          other_form.p[3]);
	bk_scene_forget();
}
