/*
 * scene_fit.h — for one feature set of a scene (scene.h) and one term it
 * needs, the cheapest form that meets the error budget on the set's own
 * domain: the catalog at its published constants and refitted on that
 * domain, LUTs at the scene's ALU:TEX tier for the environment BRDF (the
 * engines' layout, and laid out for the set: f0 folded into one channel,
 * rows over its roughness range, NoV warped; brdf.h, bk_lut_layout), and
 * the generic shader's term for reference; then the fp16 guards the chosen
 * form needs at the scene's precision, and none it does not.
 *
 * The error of each term, in the scene's precision (binary16 for mediump):
 *   vf   the directional albedo's max abs error of D · V·F over the set's
 *        (NoV, r) cells, at each end of its f0 range (Schlick is linear in
 *        f0, so the ends bound every f0 between for the forms that are too);
 *   env  the max abs error of f0 A + B at the ends of the f0 range (a LUT:
 *        its fetched values and f0 A + B in the scene's precision too);
 *   D    exact GGX (brdfkit has no cheaper D): the guards alone are decided,
 *        and its error is the largest relative error they add where they act
 *        (a roughness floor changes D below it: stability.h's guard_error);
 *   ms   the max abs error of E(NoV, r) = A + B (height-correlated Smith,
 *        F = 1: fit/target.c's ms) on the set's (NoV, r) cells; the generic
 *        is Filament's: E from its 128x128 half DFG LUT (A + B);
 *   sheen the max abs error of the Charlie sheen albedo (target sheen) on
 *        the same cells; the generic is MaterialX's published fit
 *        (sheen_materialx), what shaders ship where no cloth LUT is bound;
 *   cloth exact D_charlie(NoH, a) V_neubelt(NoV, NoL): as D, the guards alone
 *        are decided.
 */
#ifndef ANALYSIS_SCENE_FIT_H
#define ANALYSIS_SCENE_FIT_H

#include "brdf.h"
#include "compare.h"
#include "scene.h"
#include "speclut.h"

typedef enum bk_scene_term {
	BK_SCENE_TERM_D, BK_SCENE_TERM_VF, BK_SCENE_TERM_ENV,
	BK_SCENE_TERM_MS, BK_SCENE_TERM_SHEEN, BK_SCENE_TERM_CLOTH, /* only where a scene asks (scene.h) */
	BK_SCENE_TERMS
} bk_scene_term;
const char *bk_scene_term_name(bk_scene_term t); /* "D", "vf", "env", "ms", "sheen", "cloth" */

/* The generic shader's terms: GGX D, height-correlated Smith V x Schlick F,
 * a 128x128 half DFG LUT, with the fp16 guards in mediump. */
#define BK_SCENE_GENERIC_D "D_ggx(NoH, a)"
#define BK_SCENE_GENERIC_VF "V_smith_ggx_correlated(NoV, NoL, a)*F_schlick(f0, 1, LoH)"
#define BK_SCENE_GENERIC_LUT 128
/* ms: Filament's E, the G channel of the same 128x128 half LUT; sheen:
 * MaterialX's fit; cloth: the exact lobe (Filament's D_Charlie, V_Neubelt) */
#define BK_SCENE_GENERIC_SHEEN "sheen_materialx"
#define BK_SCENE_CLOTH "D_charlie(NoH, a)*V_neubelt(NoV, NoL)"

/* The fits of the short search for vf when only the exact form meets the
 * budget (brdfkit search's albedo objective on the set's domain). */
#define BK_SCENE_SEARCH_EVALS 5000

typedef struct bk_scene_choice {
	bk_scene_term term;
	char name[128];       /* catalog name, "NAME (refit)", "LUT 32x32 half", "generic" */
	char source[256];
	int lut;              /* 1: the environment BRDF is a LUT fetch */
	int lut_size;
	bk_lut_layout lut_layout; /* the generic's ({size, size, 0, 1, none, NaN}) or one for the set */
	bk_lut_format lut_fmt;
	double lut_bytes;
	char *text;           /* the form as emitted: f0 folded where the set has one, guards
	                         applied; NULL for a LUT (allocated) */
	bk_form *form;        /* text parsed, once (owned, as text; NULL for a LUT): what the
	                         writers emit, count and time, so none parses text again */
	double p[BK_MAX_PARAMS];
	bk_ops ops;
	int fetches;
	double cost;          /* ALU cost with the scene's weights, plus fetches x fetch cost */
	double err;           /* on the set's domain, in the scene's precision (after guards) */
	double budget;        /* what it had to meet */
	int at_cost;          /* chosen as the most accurate at the generic's cost ("at-generic-cost") */
	int meets;
	int scored;           /* candidates scored for this choice */
	char guards[256];     /* which fp16 guards, and why (or why none) */
	/* the most accurate candidate at no more than the generic term's cost (a
	   LUT: and no more memory than the generic's), as fitted: what the set
	   gains in accuracy instead of cost; eq_name empty when none (D) */
	char eq_name[128];
	double eq_cost, eq_err;
	/* vf: the low tier's specular LUT (speclut.h), one texture for the whole
	   D·V·F·NoL. Considered (spec_considered) where a fetch plus its least
	   ALU costs less than D and the vf choice together, the scene allows
	   textures ("lut"), its vf budget is a number (not "generic": the exact
	   form's rounding, which V = 1/4 never reaches; not "at-generic-cost")
	   and the vf choice meets it;
	   spec_name, spec_cost (whole: fetch + ALU), spec_err: the best of them
	   (the cheapest within the budget, else the most accurate), scored as vf
	   is (the lobe's directional albedo, scene precision, each f0 end).
	   Chosen (speclut 1, lut 1, spec_layout its layout) where it meets the
	   budget and costs less than D + vf: cost is then net of D's (D's row
	   stays, its arithmetic no longer run: the sum is the LUT's whole cost) */
	int spec_considered, speclut, spec_scored;
	char spec_name[96];
	double spec_cost, spec_err, spec_d_cost;
	bk_speclut spec_layout;
} bk_scene_choice;

/* Chooses the term for the set; generic (may be NULL) gets the generic
 * shader's term on the same domain. progress (may be NULL) reports each
 * phase, the env reference integrals, the catalog forms scored and refitted
 * and the LUT rows, as progress(label, done, total); its ctx is then a text
 * (what the lines start with, e.g. "scene: NAME: SET: env"), and each label is
 * that text and the phase's name. Returns 0, or -1 with a message. */
int bk_scene_choose(const bk_scene *sc, const bk_scene_set *set, bk_scene_term term, bk_scene_choice *ch,
                    bk_scene_choice *generic, bk_progress_fn progress, void *ctx, char *err, size_t errlen);
void bk_scene_choice_free(bk_scene_choice *ch);

/* ms where the set has an env term. The generic's E (gen, may be NULL) is
 * then the A + B of its own env LUT, as Filament reads it: one add, no fetch
 * of its own (its error stays; the choice was made against a fetch of its
 * own, which "at-generic-cost" then allowed). Where the set's env term is a
 * DFG LUT of two channels (A, B), the same holds for the choice: E = A + B
 * for one add and no fetch. Scored on ms's
 * domain as every ms candidate; it replaces *ms when it meets ms's budget
 * for less (or, "at-generic-cost" or nothing meeting the budget, when it is
 * more accurate). A LUT with f0 folded into one channel (f0 A + B) or the
 * specular LUT carries no E: *ms stays. Returns 0 (1 in *taken when it
 * replaced *ms), or -1 with a message. */
int bk_scene_ms_from_env(const bk_scene *sc, const bk_scene_set *set, const bk_scene_choice *env, bk_scene_choice *ms,
                         bk_scene_choice *gen, int *taken, char *err, size_t errlen);

/* The env term's reference samples are built once per distinct domain (the
 * same roughness, NoV and f0 ranges) and kept for the sets that follow,
 * whatever their thread: bk_scene_choose and bk_scene_form_error are
 * thread-safe and give the same bits either way. This frees what is kept
 * (call it when no choice is being made). */
void bk_scene_forget(void);

/* The error of form text (constants p, BK_MAX_PARAMS of them) for term on
 * the set's domain in the scene's precision, as bk_scene_choose scores a
 * candidate; with refit, p is first refitted there from its values. Returns
 * 0, or -1 with a message. */
int bk_scene_form_error(const bk_scene *sc, const bk_scene_set *set, bk_scene_term term, const char *text, double *p,
                        int refit, double *err_out, char *err, size_t errlen);

/* text with the input f0 replaced by the literal value (a whole-word
 * replacement: "f0" inside a longer name is left); allocated. */
char *bk_scene_fold_f0(const char *text, double f0);

#endif
