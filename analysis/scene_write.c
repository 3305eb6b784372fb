/*
 * scene_write.c — one scene's files (scene_write.h): the shaders, the
 * tables, the report and its part of the page. Each comment line of a shader
 * and of a CSV is formatted whole and then escaped whole, so no part of it,
 * typed by a user or not, can end the comment.
 */
#include "scene_write.h"
#include "prov.h"
#include "msl.h"

#include "out.h"

#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

static const char *const lang_ext[BK_SCENE_LANGS] = {"glsl", "hlsl", "c", "metal"};
/* MSL: the GLSL's function translated (emit()), so its names are GLSL's */
static const bk_lang lang_of[BK_SCENE_LANGS] = {BK_LANG_GLSL, BK_LANG_HLSL, BK_LANG_C, BK_LANG_GLSL};
enum { LI_MSL = 3 };

const char *bk_scene_lang_ext(int li)
{
	return li >= 0 && li < BK_SCENE_LANGS ? lang_ext[li] : "?";
}

/* ---- comment lines ---------------------------------------------------------- */

/* The text of fmt, malloc'd (NULL when out of memory). */
static char *vformat(const char *fmt, va_list ap)
{
	va_list aq;
	va_copy(aq, ap);
	int n = vsnprintf(NULL, 0, fmt, aq);
	va_end(aq);
	char *s = n < 0 ? NULL : malloc((size_t)n + 1);
	if (s)
		vsnprintf(s, (size_t)n + 1, fmt, ap);
	return s;
}

/* lead + the text of fmt as one comment line (bk_comment_text: no line break,
 * no comment end, no line continuation) + tail + "\n". Returns 0 or -1. */
static int comment_line(FILE *f, const char *lead, const char *tail, const char *fmt, ...)
	__attribute__((format(printf, 4, 5)));
static int comment_line(FILE *f, const char *lead, const char *tail, const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	char *text = vformat(fmt, ap);
	va_end(ap);
	size_t n = text ? bk_comment_text(NULL, 0, text, NULL) : 0;
	char *safe = text ? malloc(n + 1) : NULL;
	if (safe) {
		bk_comment_text(safe, n + 1, text, NULL);
		fprintf(f, "%s%s%s\n", lead, safe, tail);
	}
	free(text);
	free(safe);
	return safe ? 0 : -1;
}

/* ---- shaders ------------------------------------------------------------------ */

static void domain_text(const bk_scene *sc, const bk_scene_set *S, char *buf, size_t len)
{
	int k = snprintf(buf, len, "r in [%g, %g], NoV in [%g, %g], ", S->r_lo, S->r_hi, sc->nov_lo, sc->nov_hi);
	if (S->needs.fixed_f0)
		snprintf(buf + k, len - k, "f0 = %g (folded)", S->needs.f0);
	else
		snprintf(buf + k, len - k, "f0 in [%g, %g]", S->f0_lo, S->f0_hi);
}

static const char *err_unit(bk_scene_term t)
{
	return t == BK_SCENE_TERM_VF ? "albedo_max_abs"
	     : t == BK_SCENE_TERM_ENV || t == BK_SCENE_TERM_MS || t == BK_SCENE_TERM_SHEEN ? "max_abs" : "guard_max_rel";
}

/* The conventions line of a term's function: the terms a scene asks for
 * (ms, sheen, cloth) say how a shader uses them. */
static const char *conventions(bk_scene_term t)
{
	switch (t) {
	case BK_SCENE_TERM_MS:
		return "E(NoV, r) = A + B: GGX single-scattering directional albedo, height-correlated Smith, F = 1; r perceptual "
		       "roughness; energy compensation: specular *= 1 + f0*(1/E - 1) (Turquin 2019, as Filament)";
	case BK_SCENE_TERM_SHEEN:
		return "directional albedo of D_charlie(a = r^2)*V_neubelt, F = 1 (Estevez & Kulla 2017); r perceptual "
		       "roughness; IBL sheen = sheenColor*E*prefiltered radiance, the layer below scaled by 1 - max(sheenColor)*E";
	case BK_SCENE_TERM_CLOTH:
		return "a = r^2; V_neubelt includes 1/(4 NoL NoV); BRDF without NoL, times the sheen colour (no Fresnel)";
	default:
		return "r perceptual roughness, a = r^2; V includes 1/(4 NoL NoV)";
	}
}

/* One generated function of form (constants p) into f in language li.
 * Returns 0 or -1. */
static int emit(FILE *f, const bk_form *form, const double *p, int li, int half, const bk_emit_info *info, char *err,
                size_t errlen)
{
	bk_lang lang = lang_of[li];
	/* the scene's C is float with the fitted constants, as its tests compare
	 * it with the IR's single precision (half: the GLSL's and HLSL's types) */
	char why[600] = "code generation failed";
	char *code = li == LI_MSL ? bk_msl_emit(form, half, p, info, NULL, why, sizeof why)
	                          : bk_form_emit(form, lang, lang == BK_LANG_C ? BK_EMIT_SINGLE : half, p, info);
	if (!code) {
		snprintf(err, errlen, "%s: %s", info->name, why);
		return -1;
	}
	fprintf(f, "%s\n", code);
	free(code);
	return 0;
}

/* The two lines every texture choice shares: the lut command that makes it
 * (channels: its --channels option or ""; the layout's --f0, --r-range and
 * --warp follow) and where to sample it. Returns 0 or -1. */
static int texture_lines(FILE *f, const bk_scene_choice *c, const char *channels, const char *c0, const char *c1)
{
	const bk_lut_layout *L = &c->lut_layout;
	int remap = L->r_lo > 0 || L->r_hi < 1;
	char opts[160] = "", v[96] = "r";
	int k = 0;
	if (!isnan(L->f0))
		k += snprintf(opts + k, sizeof opts - (size_t)k, " --f0 %.9g", L->f0);
	if (remap)
		k += snprintf(opts + k, sizeof opts - (size_t)k, " --r-range %.9g:%.9g", L->r_lo, L->r_hi);
	if (L->warp != BK_LUT_WARP_NONE)
		snprintf(opts + k, sizeof opts - (size_t)k, " --warp %s", bk_lut_warp_name(L->warp));
	if (remap) /* v = (r - r_lo)/(r_hi - r_lo) as one multiply-add */
		snprintf(v, sizeof v, "r*%.9g + %.9g", 1 / (L->r_hi - L->r_lo), -L->r_lo / (L->r_hi - L->r_lo));
	int rc = comment_line(f, c0, c1, "  %s, made by: brdfkit lut --size %d%s%s%s --out DIR%s", c->name, c->lut_size,
	                      channels, opts, c->lut_fmt == BK_LUT_HALF ? " --precision half" : "",
	                      c->lut_fmt == BK_LUT_UNORM8 ? ", stored as 8-bit unorm" : "");
	rc |= comment_line(f, c0, c1, "  sample it with bilinear filtering and clamp to edge at u = %s, v = %s;",
	                   bk_lut_warp_form(L->warp), v);
	return rc;
}

/* Why a texture was chosen, in the first line of its comment. */
static const char *texture_why(const bk_scene_choice *c)
{
	return c->at_cost ? "the most accurate at the generic's cost and memory" : "cheaper at this ALU:TEX ratio";
}

/* How to make and sample a LUT choice, as comment lines (c0 opens, c1
 * closes each). Returns 0 or -1. */
static int lut_comment(FILE *f, const bk_scene_choice *c, const char *fname, const char *c0, const char *c1)
{
	const bk_lut_layout *L = &c->lut_layout;
	int folded = !isnan(L->f0);
	int rc = comment_line(f, c0, c1, "%s: the environment BRDF is a texture here (%s):", fname, texture_why(c));
	rc |= texture_lines(f, c, "", c0, c1);
	if (folded)
		rc |= comment_line(f, c0, c1, "  env = its one channel (f0 = %g folded in); max abs error %.3g on the domain",
		                   L->f0, c->err);
	else
		rc |= comment_line(f, c0, c1, "  then env = f0*A + B (A, B its two channels); max abs error %.3g on the domain",
		                   c->err);
	fputc('\n', f);
	return rc;
}

/* How to make and sample a specular LUT chosen for vf (speclut.h): it
 * replaces D*V*F*NoL whole. Returns 0 or -1. */
static int speclut_comment(FILE *f, const bk_scene_choice *c, const char *fname, const char *c0, const char *c1)
{
	const bk_speclut *L = &c->spec_layout;
	char axes[700], texel[400], shader[200];
	bk_speclut_describe(L, axes, sizeof axes, texel, sizeof texel, shader, sizeof shader);
	int rc = comment_line(f, c0, c1, "%s: the whole punctual specular D*V*F*NoL is a texture here (cheaper at this "
	                      "ALU:TEX ratio; D and V*F are not computed):", fname);
	rc |= comment_line(f, c0, c1, "  %s, made by: %s", c->name, c->source);
	rc |= comment_line(f, c0, c1, "  %s", axes);
	rc |= comment_line(f, c0, c1, "  %s", texel);
	rc |= comment_line(f, c0, c1, "  %s; directional albedo max abs error %.3g on the domain", shader, c->err);
	fputc('\n', f);
	return rc;
}

/* ms read from the set's env texture: how (no fetch of its own). Returns 0 or -1. */
static int ms_lut_comment(FILE *f, const bk_scene_choice *c, const char *fname, const char *env_fname, const char *c0,
                          const char *c1)
{
	int rc = comment_line(f, c0, c1, "%s: E = A + B, the two channels %s already fetches (no fetch of its own):",
	                      fname, env_fname);
	rc |= comment_line(f, c0, c1, "  E = A + B; energy compensation: specular *= 1 + f0*(1/E - 1) (Turquin 2019, as "
	                   "Filament); max abs error %.3g on the domain", c->err);
	fputc('\n', f);
	return rc;
}

/* ms as a texture of E alone (folded at f0 = 1). Returns 0 or -1. */
static int ms_tex_comment(FILE *f, const bk_scene_choice *c, const char *fname, const char *c0, const char *c1)
{
	int rc = comment_line(f, c0, c1, "%s: E(NoV, r) is a texture here (%s):", fname, texture_why(c));
	rc |= texture_lines(f, c, "", c0, c1); /* its layout's f0 is 1: --f0 1 */
	rc |= comment_line(f, c0, c1, "  E = its one channel (A + B); energy compensation: specular *= 1 + f0*(1/E - 1) "
	                   "(Turquin 2019, as Filament); max abs error %.3g on the domain", c->err);
	fputc('\n', f);
	return rc;
}

/* sheen as the cloth channel's texture (brdfkit lut --channels filament's
 * B). Returns 0 or -1. */
static int sheen_tex_comment(FILE *f, const bk_scene_choice *c, const char *fname, const char *c0, const char *c1)
{
	int rc = comment_line(f, c0, c1, "%s: the sheen albedo is a texture here (%s):", fname, texture_why(c));
	rc |= texture_lines(f, c, " --channels filament", c0, c1);
	rc |= comment_line(f, c0, c1, "  sheen albedo = its B channel (cloth: Charlie D, Neubelt V, F = 1); max abs error "
	                   "%.3g on the domain", c->err);
	fputc('\n', f);
	return rc;
}

/* The provenance lines at the top of a shader. Returns 0 or -1. */
static int shader_head(FILE *f, const bk_scene_doc *d, const bk_scene_result *R, const char *dom, const char *c0,
                       const char *c1)
{
	const bk_scene *sc = d->sc;
	int rc = comment_line(f, c0, c1, "brdfkit %s: scene '%s' (file hash %s), feature set %s: DO NOT EDIT", BK_VERSION,
	                      sc->name, d->hash, R->set.name);
	rc |= comment_line(f, c0, c1, "command: %s", d->command);
	rc |= comment_line(f, c0, c1, "domain: %s; precision %s", dom, sc->half ? "mediump (binary16)" : "highp");
	rc |= comment_line(f, c0, c1,
	                   "cost: %g (generic shader: %g); conventions: r perceptual roughness, a = r^2, V includes "
	                   "1/(4 NoL NoV), BRDF without NoL",
	                   R->cost, R->gen_cost);
	fputc('\n', f);
	return rc;
}

int bk_scene_shader(FILE *f, const bk_scene_doc *d, int i, int li, char *err, size_t errlen)
{
	const bk_scene *sc = d->sc;
	const bk_scene_result *R = &d->R[i];
	char dom[256];
	domain_text(sc, &R->set, dom, sizeof dom);
	const char *c0 = li == 2 ? "/* " : "// ", *c1 = li == 2 ? " */" : "";
	if (shader_head(f, d, R, dom, c0, c1)) {
		snprintf(err, errlen, "out of memory");
		return -1;
	}
	for (int t = 0; t < BK_SCENE_TERMS; t++) {
		if (!R->has[t])
			continue;
		const bk_scene_choice *c = &R->ch[t];
		char fname[96], errtext[160];
		snprintf(fname, sizeof fname, "%s_%s", R->set.name, bk_scene_term_name(t));
		if (t == BK_SCENE_TERM_D && R->ch[BK_SCENE_TERM_VF].speclut)
			continue; /* in the specular LUT */
		if (c->lut && t == BK_SCENE_TERM_MS) { /* read from env's fetch (bk_scene_ms_from_env) */
			char env_fname[96];
			snprintf(env_fname, sizeof env_fname, "%s_env", R->set.name);
			if (c->fetches ? ms_tex_comment(f, c, fname, c0, c1) : ms_lut_comment(f, c, fname, env_fname, c0, c1)) {
				snprintf(err, errlen, "out of memory");
				return -1;
			}
			continue;
		}
		if (c->lut) {
			if (c->speclut                    ? speclut_comment(f, c, fname, c0, c1)
			    : t == BK_SCENE_TERM_SHEEN ? sheen_tex_comment(f, c, fname, c0, c1)
			                               : lut_comment(f, c, fname, c0, c1)) {
				snprintf(err, errlen, "out of memory");
				return -1;
			}
			continue;
		}
		snprintf(errtext, sizeof errtext, "%s %.3g in %s on the domain (budget %.3g); fp16 guards: %.60s",
		         err_unit(t), c->err, sc->half ? "half" : "single", c->budget, c->guards);
		bk_emit_info info = {fname, c->source, conventions(t), dom, errtext, d->command};
		if (!c->form) { /* a choice is made with its form (scene_fit.h) */
			snprintf(err, errlen, "%s: no form", info.name);
			return -1;
		}
		if (emit(f, c->form, c->p, li, sc->half, &info, err, errlen))
			return -1;
	}
	if (R->set.needs.diffuse) {
		char fname[96];
		snprintf(fname, sizeof fname, "%s_diffuse", R->set.name);
		bk_emit_info info = {fname, "Lambert", "times the diffuse colour (1/pi included)", NULL, "exact", d->command};
		bk_form_error fe;
		bk_form *lambert = bk_form_parse("Fd_lambert()", &fe); /* a constant: parsed where it enters */
		if (!lambert) {
			snprintf(err, errlen, "%s: %s", info.name, fe.message);
			return -1;
		}
		int rc = emit(f, lambert, NULL, li, sc->half, &info, err, errlen);
		bk_form_free(lambert);
		if (rc)
			return -1;
	}
	return 0;
}

/* ---- tables ------------------------------------------------------------------- */

/* A number field (after its comma): empty when not a number. */
static void num_field(FILE *f, const char *fmt, double v)
{
	fputc(',', f);
	if (isfinite(v))
		fprintf(f, fmt, v);
}

/* num / den, empty when that is no number (0/0: a set without the term). */
static void ratio_field(FILE *f, const char *fmt, double num, double den)
{
	num_field(f, fmt, den != 0 ? num / den : NAN);
}

/* An instruction count; empty when not measured (negative). */
static void count_field(FILE *f, int n)
{
	fputc(',', f);
	if (n >= 0)
		fprintf(f, "%d", n);
}

static void params_text(FILE *f, const bk_scene_choice *c)
{
	int np = c->form ? bk_form_nparams(c->form) : 0;
	for (int j = 0; j < np; j++)
		fprintf(f, "%sp%d=%.9g", j ? ";" : "", j, c->p[j]);
}

static void scene_row(FILE *f, const bk_scene_doc *d, const bk_scene_result *r, int m, int t)
{
	const bk_scene_choice *c = &r->ch[t], *g = &r->gen[t];
	bk_csv_field(f, d->sc->mat[r->set.mat[m]].name);
	fprintf(f, ",%s,%s,", r->set.name, bk_scene_term_name(t));
	bk_csv_field(f, c->name);
	fputc(',', f);
	bk_csv_field(f, c->text ? c->text : "");
	fputc(',', f);
	params_text(f, c);
	fprintf(f, ",%d,%d,%d,%g,%.6g,%s,", c->ops.simple, c->ops.complex, c->fetches, c->cost, c->err, err_unit(t));
	if (isfinite(c->budget))
		fprintf(f, "%.6g", c->budget);
	fprintf(f, ",%d,", c->meets);
	bk_csv_field(f, c->guards);
	fprintf(f, ",%g,%.6g,", g->cost, g->err);
	bk_csv_field(f, c->eq_name);
	fputc(',', f);
	if (c->eq_name[0])
		fprintf(f, "%.6g", c->eq_err);
	for (int k = 0; k < d->nchips; k++) {
		num_field(f, "%.0f", r->gpu[t][k]);
		num_field(f, "%.0f", r->gen_gpu[t][k]);
	}
	fputc('\n', f);
}

void bk_scene_csv(FILE *f, const bk_scene_doc *d)
{
	const bk_scene *sc = d->sc;
	bk_prov_header(f, d->command, NULL, "scene specialisation: scene '%s' (file hash %s)", sc->name, d->hash);
	fprintf(f, "# error: vf = directional-albedo max abs error of D*V*F, env = max abs error of f0*A + B, both at the "
	           "ends of the set's f0 range on its (NoV, r) domain, in %s; D is exact GGX, its error the largest relative error its fp16 guard adds where it acts. cost: simple*%g + "
	           "complex*%g + fetches*%g. conventions: r perceptual roughness, a = r^2, V includes 1/(4 NoL NoV)\n",
	        sc->half ? "half precision (mediump)" : "single precision (highp)", sc->simple_cost, sc->complex_cost,
	        sc->fetch_cost);
	int asked = 0; /* the terms a scene asks for: their line only where there are some */
	for (int i = 0; i < d->nset; i++)
		asked |= d->R[i].has[BK_SCENE_TERM_MS] || d->R[i].has[BK_SCENE_TERM_SHEEN] || d->R[i].has[BK_SCENE_TERM_CLOTH];
	if (asked)
		fprintf(f, "# error: ms = max abs error of E = A + B (GGX, height-correlated Smith, F = 1), sheen = max abs "
		           "error of the Charlie sheen albedo, both on the set's (NoV, r) domain in the same precision; cloth "
		           "is exact D_charlie*V_neubelt, its error the largest relative error its fp16 guard adds\n");
	if (d->nchips)
		comment_line(f, "# ", "",
		             "aco_CHIP_instructions: AMD instructions of the term's form (brdfkit gpucost: Mesa RADV's null "
		             "device, %s, fp32, net of a load/store baseline; empty for a LUT), and of the generic shader's",
		             d->driver);
	fputs("material,feature_set,term,choice,form,parameters,simple,complex,fetches,cost,error,error_kind,budget,"
	      "meets_budget,fp16_guards,generic_cost,generic_error,at_generic_cost,at_generic_cost_error", f);
	for (int c = 0; c < d->nchips; c++)
		fprintf(f, ",aco_%s_instructions,generic_aco_%s_instructions", d->chip[c], d->chip[c]);
	fputc('\n', f);
	for (int i = 0; i < d->nset; i++)
		for (int m = 0; m < d->R[i].set.nmat; m++)
			for (int t = 0; t < BK_SCENE_TERMS; t++)
				if (d->R[i].has[t])
					scene_row(f, d, &d->R[i], m, t);
}

/* The set's worst error over its vf and env terms, and the generic's: both
 * are directional-albedo errors (scene_fit.h), so the larger is the
 * shader's; NaN when the set has neither (D alone, or diffuse only). */
static void set_errors(const bk_scene_result *r, double *err, double *gen_err)
{
	*err = *gen_err = NAN;
	for (int t = BK_SCENE_TERM_VF; t <= BK_SCENE_TERM_ENV; t++)
		if (r->has[t]) {
			*err = isnan(*err) || r->ch[t].err > *err ? r->ch[t].err : *err;
			*gen_err = isnan(*gen_err) || r->gen[t].err > *gen_err ? r->gen[t].err : *gen_err;
		}
}

void bk_scene_sets_csv(FILE *f, const bk_scene_doc *d)
{
	bk_prov_title(f,
	              "scene '%s': each feature set's shader against the generic one (GGX D, "
	              "height-correlated Smith V x Schlick F, %dx%d half DFG LUT, fp16 guards in mediump); spirv: SPIR-V "
	              "instructions of the forms' GLSL after spirv-opt -O (fetches not included)",
	              d->sc->name, BK_SCENE_GENERIC_LUT, BK_SCENE_GENERIC_LUT);
	bk_prov_command(f, d->command);
	if (d->nchips)
		comment_line(f, "# ", "",
		             "aco_CHIP_instructions: AMD instructions of the set's forms, summed (brdfkit gpucost: Mesa RADV's "
		             "null device, %s, fp32, net of a load/store baseline per form; fetches not included)",
		             d->driver);
	fputs("# error, generic_error: the largest of the set's vf and env errors (both directional-albedo errors on "
	      "the set's domain in the scene's precision; scene.csv has each); error_ratio = generic_error / error\n", f);
	fputs("feature_set,materials,r_lo,r_hi,f0_lo,f0_hi,cost,generic_cost,cost_ratio,spirv,generic_spirv,error,"
	      "generic_error,error_ratio", f);
	for (int c = 0; c < d->nchips; c++)
		fprintf(f, ",aco_%s_instructions,generic_aco_%s_instructions", d->chip[c], d->chip[c]);
	fputc('\n', f);
	for (int i = 0; i < d->nset; i++) {
		const bk_scene_result *r = &d->R[i];
		fprintf(f, "%s,", r->set.name);
		char names[BK_SCENE_MAX_MATERIALS * BK_SCENE_NAME_MAX] = "";
		for (int m = 0; m < r->set.nmat; m++)
			snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", m ? ";" : "",
			         d->sc->mat[r->set.mat[m]].name);
		bk_csv_field(f, names);
		fprintf(f, ",%g,%g,%g,%g,%g,%g", r->set.r_lo, r->set.r_hi, r->set.f0_lo, r->set.f0_hi, r->cost, r->gen_cost);
		ratio_field(f, "%.3g", r->gen_cost, r->cost);
		count_field(f, r->spirv);
		count_field(f, r->gen_spirv);
		double e, ge;
		set_errors(r, &e, &ge);
		num_field(f, "%.6g", e);
		num_field(f, "%.6g", ge);
		ratio_field(f, "%.3g", ge, e);
		for (int c = 0; c < d->nchips; c++) {
			num_field(f, "%.0f", r->gpu_sum[c]);
			num_field(f, "%.0f", r->gen_gpu_sum[c]);
		}
		fputc('\n', f);
	}
}

void bk_scene_timing_csv(FILE *f, const bk_scene_doc *d, int reps)
{
	bk_prov_header(f, d->command, NULL, "scene specialisation timing: scene '%s' (file hash %s)", d->sc->name,
	               d->hash);
	fprintf(f, "# CPU ns per evaluation of each feature set's forms (generated C, -O2, median of %d interleaved "
	           "runs, summed over the set's terms; LUT fetches not included; empty: not measured): not "
	           "reproducible\n", reps);
	fputs("feature_set,ns_per_eval,generic_ns_per_eval\n", f);
	for (int i = 0; i < d->nset; i++) {
		fputs(d->R[i].set.name, f);
		num_field(f, "%.3f", d->R[i].ns);
		num_field(f, "%.3f", d->R[i].gen_ns);
		fputc('\n', f);
	}
}

/* ---- the report in words ---------------------------------------------------------- */

/* A name in the report's text: a control character (a line break, an
 * escape sequence a terminal would obey) is a space, as in a comment. */
static void plain(FILE *f, const char *s)
{
	for (; *s; s++)
		fputc((unsigned char)*s < ' ' || *s == 0x7f ? ' ' : *s, f);
}

static void report_head(FILE *f, const bk_scene_doc *d)
{
	const bk_scene *sc = d->sc;
	fputs("scene '", f);
	plain(f, sc->name);
	fprintf(f, "': %d material%s, %d feature set%s; punctual lights %s, image-based lighting %s, diffuse %s; "
	           "%s; ",
	        sc->nmat, sc->nmat == 1 ? "" : "s", d->nset, d->nset == 1 ? "" : "s", sc->punctual ? "yes" : "no",
	        sc->ibl ? "yes" : "no", sc->diffuse ? "yes" : "no", sc->half ? "mediump (fp16)" : "highp");
	if (sc->alu_tex)
		fprintf(f, "ALU:TEX %d\n", sc->alu_tex);
	else
		fprintf(f, "costs simple %g, complex %g, fetch %g\n", sc->simple_cost, sc->complex_cost, sc->fetch_cost);
	if (sc->budget_vf == BK_SCENE_BUDGET_AT_COST || sc->budget_env == BK_SCENE_BUDGET_AT_COST)
		fputs("  error \"at-generic-cost\": each term the most accurate form at no more than the generic's cost "
		      "(a LUT: and memory)\n", f);
	if (!sc->punctual)
		fputs("  no punctual lights: no D*V*F code\n", f);
	if (!sc->ibl)
		fputs("  no image-based lighting: no environment BRDF code\n", f);
}

static void report_term(FILE *f, const bk_scene_result *r, int t)
{
	const bk_scene_choice *c = &r->ch[t], *g = &r->gen[t];
	if (t == BK_SCENE_TERM_CLOTH) {
		fprintf(f, "  cloth exact Charlie D x Neubelt V: cost %g (generic %g)\n      fp16 guards: ", c->cost, g->cost);
		plain(f, c->guards);
		fputc('\n', f);
		return;
	}
	if (t == BK_SCENE_TERM_D) {
		fprintf(f, "  D   exact GGX: cost %g (generic %g)\n      fp16 guards: ", c->cost, g->cost);
		plain(f, c->guards);
		fputc('\n', f);
		return;
	}
	fprintf(f, "  %-3s ", bk_scene_term_name(t));
	plain(f, c->name);
	fprintf(f, ": cost %g (generic %g), %s %.3g (generic %.3g, budget %.3g%s), %d candidates scored\n", c->cost,
	        g->cost, err_unit(t), c->err, g->err, c->budget, c->meets ? "" : ": NOT MET, the most accurate kept",
	        c->scored);
	fputs("      fp16 guards: ", f);
	plain(f, c->guards);
	fputc('\n', f);
	if (c->spec_considered && !c->speclut) { /* why the specular LUT was not chosen */
		fputs("      specular LUT (replaces D*V*F*NoL): best ", f);
		plain(f, c->spec_name);
		fprintf(f, ", cost %g against D + vf %g, albedo_max_abs %.3g: %s\n", c->spec_cost, c->spec_d_cost + c->cost,
		        c->spec_err, c->spec_err > c->budget ? "over the budget" : "not cheaper");
	} else if (c->speclut) {
		fprintf(f, "      specular LUT: replaces D*V*F*NoL; its whole cost %g, shown net of D's %g\n",
		        c->cost + c->spec_d_cost, c->spec_d_cost);
	}
	if (c->eq_name[0] && g->err > 0) {
		fputs("      at the generic's cost: ", f);
		plain(f, c->eq_name);
		fprintf(f, ", cost %g, %s %.3g", c->eq_cost, err_unit(t), c->eq_err);
		if (c->eq_err > 0) /* exact: no ratio */
			fprintf(f, " (%.2fx the generic's accuracy)", g->err / c->eq_err);
		fputc('\n', f);
	}
}

/* The set's last line: its shader against the generic one. */
static void report_saving(FILE *f, const bk_scene_result *r, int with_time)
{
	double e, ge;
	set_errors(r, &e, &ge);
	if (!(r->cost > 0)) {
		fputs("  shader: the diffuse term alone, as in the generic shader\n", f);
		return;
	}
	fprintf(f, "  shader cost %g against the generic %g (%.2fx cheaper); ", r->cost, r->gen_cost, r->gen_cost / r->cost);
	if (r->spirv >= 0 && r->gen_spirv >= 0)
		fprintf(f, "SPIR-V %d against %d", r->spirv, r->gen_spirv);
	else
		fputs("SPIR-V not measured", f);
	if (e > 0 && ge > 0) /* NaN: no vf or env term */
		fprintf(f, "; worst term error %.3g against the generic's %.3g (%.2fx %s)", e, ge, ge >= e ? ge / e : e / ge,
		        ge >= e ? "more accurate" : "less accurate");
	else if (e >= 0) /* one of them exact: no ratio */
		fprintf(f, "; worst term error %.3g against the generic's %.3g", e, ge);
	if (with_time && isfinite(r->ns) && isfinite(r->gen_ns))
		fprintf(f, "; CPU %.2f ns against %.2f ns per evaluation", r->ns, r->gen_ns);
	else if (with_time)
		fputs("; CPU time not measured", f);
	fputc('\n', f);
}

void bk_scene_report(FILE *f, const bk_scene_doc *d, int with_time)
{
	const bk_scene *sc = d->sc;
	report_head(f, d);
	for (int i = 0; i < d->nset; i++) {
		const bk_scene_result *r = &d->R[i];
		char dom[256];
		domain_text(sc, &r->set, dom, sizeof dom);
		fprintf(f, "\nfeature set %s (", r->set.name);
		for (int m = 0; m < r->set.nmat; m++) {
			fputs(m ? ", " : "", f);
			plain(f, sc->mat[r->set.mat[m]].name);
		}
		fprintf(f, "): %s\n", dom);
		if (!r->set.needs.vf && !r->set.needs.env && !r->set.needs.cloth && !r->set.needs.sheen)
			fputs("  no specular (the materials have none): diffuse only\n", f);
		else if (!r->set.needs.vf && !r->set.needs.env)
			fputs("  no GGX specular (the materials have none): the cloth's sheen alone\n", f);
		if (r->set.needs.fixed_f0)
			fprintf(f, "  one f0 (%g): folded into the constants, no f0 input\n", r->set.needs.f0);
		for (int t = 0; t < BK_SCENE_TERMS; t++)
			if (r->has[t])
				report_term(f, r, t);
		report_saving(f, r, with_time);
	}
}

/* ---- the page section ------------------------------------------------------------------ */

void bk_scene_section_open(FILE *f, const char *id)
{
	fputs("<section id=\"", f);
	bk_html_text(f, id);
	fprintf(f, "\">\n<h2>Scenes: shaders specialised to what a scene contains</h2>\n<p>For each scene, "
	           "materials with the same needs share a feature set and one shader; each term it needs is the cheapest "
	           "form that meets the scene's error budget on the set's own roughness, f0 and NoV range (catalog forms, "
	           "published and refitted there, LUTs at the scene's ALU:TEX ratio, a short search for V&middot;F), with "
	           "the fp16 guards it needs at the scene's precision and none it does not. Errors: V&middot;F, the "
	           "directional albedo's max abs error of D&middot;V&middot;F; env, the max abs error of f0&middot;A + B. "
	           "The generic shader: GGX D &middot; height-correlated Smith V &middot; Schlick F and a %d&sup2; half DFG "
	           "LUT, with the fp16 guards in mediump.</p>\n", BK_SCENE_GENERIC_LUT);
}

void bk_scene_section_close(FILE *f)
{
	fputs("</section>\n", f);
}

/* <a href="PREFIX[DIR/]FILE">TEXT</a>: the link through the one writer
 * (out.h), the text escaped. */
static void link(FILE *f, const char *prefix, const char *dir, const char *file, const char *text)
{
	char path[512];
	snprintf(path, sizeof path, "%s%s%s", dir ? dir : "", dir ? "/" : "", file);
	fputs("<a href=\"", f);
	bk_html_link(f, prefix, path);
	fputs("\">", f);
	bk_html_text(f, text);
	fputs("</a>", f);
}

static void section_choices(FILE *f, const bk_scene_doc *d)
{
	fputs("<table>\n<tr><th>feature set</th><th>term</th><th>choice</th><th>cost (generic)</th><th>error "
	      "(generic)</th><th>budget</th><th>fp16 guards</th></tr>\n", f);
	for (int i = 0; i < d->nset; i++)
		for (int t = 0; t < BK_SCENE_TERMS; t++) {
			const bk_scene_result *r = &d->R[i];
			if (!r->has[t])
				continue;
			const bk_scene_choice *c = &r->ch[t], *g = &r->gen[t];
			fputs("<tr><td>", f);
			bk_html_text(f, r->set.name);
			fprintf(f, "</td><td>%s</td><td>", bk_scene_term_name(t));
			bk_html_text(f, c->name);
			fprintf(f, "</td><td>%g (%g)</td><td>%.3g (%.3g)</td><td>", c->cost, g->cost, c->err, g->err);
			if (isfinite(c->budget))
				fprintf(f, "%.3g%s", c->budget, c->meets ? "" : " not met");
			fputs("</td><td>", f);
			bk_html_text(f, c->guards);
			fputs("</td></tr>\n", f);
		}
	fputs("</table>\n", f);
}

/* A table cell of a number, empty when there is none. */
static void num_cell(FILE *f, const char *fmt, double v)
{
	fputs("<td>", f);
	if (isfinite(v))
		fprintf(f, fmt, v);
	fputs("</td>", f);
}

static void section_savings(FILE *f, const bk_scene_doc *d, const char *prefix)
{
	fputs("<table>\n<tr><th>feature set</th><th>shader cost</th><th>generic</th><th>ratio</th>"
	      "<th>SPIR-V</th><th>generic SPIR-V</th><th>worst term error</th><th>generic</th><th>accuracy gain</th>"
	      "<th>shaders</th></tr>\n", f);
	for (int i = 0; i < d->nset; i++) {
		const bk_scene_result *r = &d->R[i];
		double e, ge;
		set_errors(r, &e, &ge);
		fputs("<tr><td>", f);
		bk_html_text(f, r->set.name);
		fprintf(f, "</td><td>%g</td><td>%g</td>", r->cost, r->gen_cost);
		num_cell(f, "%.2fx", r->cost != 0 ? r->gen_cost / r->cost : NAN);
		num_cell(f, "%.0f", r->spirv >= 0 ? r->spirv : NAN);
		num_cell(f, "%.0f", r->gen_spirv >= 0 ? r->gen_spirv : NAN);
		if (isnan(e) || !(e > 0))
			fputs("<td></td><td></td><td></td>", f);
		else
			fprintf(f, "<td>%.3g</td><td>%.3g</td><td>%.2fx</td>", e, ge, ge / e);
		fputs("<td>", f);
		for (int li = 0; li < BK_SCENE_LANGS; li++)
			if (d->sc->languages & (1u << li)) {
				char file[16];
				snprintf(file, sizeof file, "shader.%s", lang_ext[li]);
				link(f, prefix, r->set.name, file, lang_ext[li]);
				fputc(' ', f);
			}
		fputs("</td></tr>\n", f);
	}
	fputs("</table>\n", f);
}

void bk_scene_section_body(FILE *f, const bk_scene_doc *d, const char *prefix)
{
	const bk_scene *sc = d->sc;
	fputs("<h3>", f);
	bk_html_text(f, sc->name);
	fprintf(f, "</h3>\n<p>%d material%s, %s, %s%s%s, ", sc->nmat, sc->nmat == 1 ? "" : "s",
	        sc->half ? "mediump" : "highp", sc->punctual ? "punctual lights" : "no punctual lights",
	        sc->ibl ? ", image-based lighting" : ", no IBL", sc->diffuse ? ", diffuse" : "");
	if (sc->alu_tex)
		fprintf(f, "ALU:TEX %d", sc->alu_tex);
	else
		fprintf(f, "costs simple %g, complex %g, fetch %g", sc->simple_cost, sc->complex_cost, sc->fetch_cost);
	fputs(". Tables: ", f);
	link(f, prefix, NULL, "scene.csv", "scene.csv");
	fputs(", ", f);
	link(f, prefix, NULL, "sets.csv", "sets.csv");
	fputs(", ", f);
	link(f, prefix, NULL, "report.txt", "report.txt");
	fputs(".</p>\n", f);
	section_choices(f, d);
	section_savings(f, d, prefix);
}
