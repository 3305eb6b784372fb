/*
 * cmd_scene.c — brdfkit scene: from a scene file (analysis/scene.h) to one
 * specialised shader per feature set, each term the cheapest form that meets
 * the error budget on the set's own domain (analysis/scene_fit.h), with the
 * fp16 guards it needs and none it does not, against the generic shader.
 */
#include "brdf.h"
#include "cli.h"
#include "cmd.h"
#include "compare.h"
#include "expr.h"
#include "gpucost.h"
#include "out.h"
#include "scene.h"
#include "scene_fit.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define TIME_REPS 7
#define SCENE_CHIPS 8

/* What the run decided for one feature set. */
typedef struct set_result {
	bk_scene_set set;
	int has[BK_SCENE_TERMS];
	bk_scene_choice ch[BK_SCENE_TERMS], gen[BK_SCENE_TERMS];
	double cost, gen_cost;   /* ALU + fetches, the scene's weights */
	int spirv, gen_spirv;    /* SPIR-V instructions of the forms (fetches not counted) */
	double ns, gen_ns;       /* CPU ns per evaluation of the forms, summed */
	/* --gpu: ACO's net instructions per term and chip (NaN: a LUT, nothing compiled), and
	 * summed over the set's terms (fetches not included) */
	double gpu[BK_SCENE_TERMS][SCENE_CHIPS], gen_gpu[BK_SCENE_TERMS][SCENE_CHIPS];
	double gpu_sum[SCENE_CHIPS], gen_gpu_sum[SCENE_CHIPS];
} set_result;

/* --gpu: the chips, shared by every scene of the run */
static struct {
	const char *chip[SCENE_CHIPS];
	int n;
	char buf[512], driver[256];
} gpu;

static const char *const lang_ext[3] = {"glsl", "hlsl", "c"};
static const bk_lang lang_of[3] = {BK_LANG_GLSL, BK_LANG_HLSL, BK_LANG_C};

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
	return t == BK_SCENE_TERM_VF ? "albedo_max_abs" : t == BK_SCENE_TERM_ENV ? "max_abs" : "guard_max_rel";
}

/* One generated function of text (constants p) into f. Returns 0 or -1. */
static int emit(FILE *f, const char *text, const double *p, bk_lang lang, int half, const bk_emit_info *info, char *err,
                size_t errlen)
{
	bk_form_error fe;
	bk_form *form = bk_form_parse(text, &fe);
	if (!form) {
		snprintf(err, errlen, "%s: %s", info->name, fe.message);
		return -1;
	}
	char *code = bk_form_emit(form, lang, half, p, info);
	bk_form_free(form);
	if (!code) {
		snprintf(err, errlen, "%s: code generation failed", info->name);
		return -1;
	}
	fprintf(f, "%s\n", code);
	free(code);
	return 0;
}

/* How to make and sample a LUT choice, as comment lines. */
static void lut_comment(FILE *f, const bk_scene_choice *c, const char *fname, const char *c0, const char *c1)
{
	const bk_lut_layout *L = &c->lut_layout;
	int remap = L->r_lo > 0 || L->r_hi < 1, folded = !isnan(L->f0);
	char opts[160] = "", v[96] = "r";
	int k = 0;
	if (folded)
		k += snprintf(opts + k, sizeof opts - (size_t)k, " --f0 %.9g", L->f0);
	if (remap)
		k += snprintf(opts + k, sizeof opts - (size_t)k, " --r-range %.9g:%.9g", L->r_lo, L->r_hi);
	if (L->warp != BK_LUT_WARP_NONE)
		snprintf(opts + k, sizeof opts - (size_t)k, " --warp %s", bk_lut_warp_name(L->warp));
	if (remap) /* v = (r - r_lo)/(r_hi - r_lo) as one multiply-add */
		snprintf(v, sizeof v, "r*%.9g + %.9g", 1 / (L->r_hi - L->r_lo), -L->r_lo / (L->r_hi - L->r_lo));
	fprintf(f, "%s %s: the environment BRDF is a texture here (%s):%s\n", c0, fname,
	        c->at_cost ? "the most accurate at the generic's cost and memory" : "cheaper at this ALU:TEX ratio",
	        c1);
	fprintf(f, "%s   %s, made by: brdfkit lut --size %d%s%s --out DIR%s%s\n", c0, c->name, c->lut_size, opts,
	        c->lut_fmt == BK_LUT_HALF ? " --half" : "", c->lut_fmt == BK_LUT_UNORM8 ? ", stored as 8-bit unorm" : "", c1);
	fprintf(f, "%s   sample it with bilinear filtering and clamp to edge at u = %s, v = %s;%s\n", c0,
	        bk_lut_warp_form(L->warp), v, c1);
	if (folded)
		fprintf(f, "%s   env = its one channel (f0 = %g folded in); max abs error %.3g on the domain%s\n\n", c0, L->f0,
		        c->err, c1);
	else
		fprintf(f, "%s   then env = f0*A + B (A, B its two channels); max abs error %.3g on the domain%s\n\n", c0, c->err,
		        c1);
}

/* The functions of one set in one language: the chosen terms, the diffuse,
 * a comment for a LUT. Returns 0 or -1. */
static int write_shader(FILE *f, const bk_scene *sc, const set_result *R, int li, const char *hash, char *err,
                        size_t errlen)
{
	char dom[256];
	domain_text(sc, &R->set, dom, sizeof dom);
	const char *c0 = li == 2 ? "/*" : "//", *c1 = li == 2 ? " */" : "";
	fprintf(f, "%s brdfkit %s: scene '%s' (file hash %s), feature set %s: DO NOT EDIT%s\n", c0, BK_VERSION, sc->name,
	        hash, R->set.name, c1);
	fprintf(f, "%s command: %s%s\n", c0, bk_out_command(), c1);
	fprintf(f, "%s domain: %s; precision %s%s\n", c0, dom, sc->half ? "mediump (binary16)" : "highp", c1);
	fprintf(f, "%s cost: %g (generic shader: %g); conventions: r perceptual roughness, a = r^2, V includes "
	           "1/(4 NoL NoV), BRDF without NoL%s\n\n", c0, R->cost, R->gen_cost, c1);
	for (int t = 0; t < BK_SCENE_TERMS; t++) {
		if (!R->has[t])
			continue;
		const bk_scene_choice *c = &R->ch[t];
		char fname[96], errtext[160];
		snprintf(fname, sizeof fname, "%s_%s", R->set.name, bk_scene_term_name(t));
		if (c->lut) {
			lut_comment(f, c, fname, c0, c1);
			continue;
		}
		snprintf(errtext, sizeof errtext, "%s %.3g in %s on the domain (budget %.3g); fp16 guards: %.60s",
		         err_unit(t), c->err, sc->half ? "half" : "single", c->budget, c->guards);
		bk_emit_info info = {fname, c->source, "r perceptual roughness, a = r^2; V includes 1/(4 NoL NoV)", dom,
		                     errtext, bk_out_command()};
		if (emit(f, c->text, c->p, lang_of[li], sc->half, &info, err, errlen))
			return -1;
	}
	if (R->set.needs.diffuse) {
		char fname[96];
		snprintf(fname, sizeof fname, "%s_diffuse", R->set.name);
		bk_emit_info info = {fname, "Lambert", "times the diffuse colour (1/pi included)", NULL, "exact", bk_out_command()};
		if (emit(f, "Fd_lambert()", NULL, lang_of[li], sc->half, &info, err, errlen))
			return -1;
	}
	return 0;
}

static void params_text(FILE *f, const bk_scene_choice *c)
{
	int np = 0;
	if (c->text) {
		bk_form_error fe;
		bk_form *form = bk_form_parse(c->text, &fe);
		np = form ? bk_form_nparams(form) : 0;
		bk_form_free(form);
	}
	for (int j = 0; j < np; j++)
		fprintf(f, "%sp%d=%.9g", j ? ";" : "", j, c->p[j]);
}

static void scene_csv(FILE *f, const bk_scene *sc, const set_result *R, int nset, const char *hash)
{
	fprintf(f, "# brdfkit %s scene specialisation: scene '%s' (file hash %s)\n", BK_VERSION, sc->name, hash);
	fprintf(f, "# command: %s\n", bk_out_command());
	fprintf(f, "# error: vf = directional-albedo max abs error of D*V*F, env = max abs error of f0*A + B, both at the "
	           "ends of the set's f0 range on its (NoV, r) domain, in %s; D is exact GGX, its error the largest relative error its fp16 guard adds where it acts. cost: simple*%g + "
	           "complex*%g + fetches*%g. conventions: r perceptual roughness, a = r^2, V includes 1/(4 NoL NoV)\n",
	        sc->half ? "half precision (mediump)" : "single precision (highp)", sc->simple_cost, sc->complex_cost,
	        sc->fetch_cost);
	if (gpu.n)
		fprintf(f, "# aco_CHIP_instructions: AMD instructions of the term's form (brdfkit gpucost: Mesa RADV's null "
		           "device, %s, fp32, net of a load/store baseline; empty for a LUT), and of the generic shader's\n",
		        gpu.driver);
	fputs("material,feature_set,term,choice,form,parameters,simple,complex,fetches,cost,error,error_kind,budget,"
	      "meets_budget,fp16_guards,generic_cost,generic_error,at_generic_cost,at_generic_cost_error", f);
	for (int c = 0; c < gpu.n; c++)
		fprintf(f, ",aco_%s_instructions,generic_aco_%s_instructions", gpu.chip[c], gpu.chip[c]);
	fputc('\n', f);
	for (int i = 0; i < nset; i++)
		for (int m = 0; m < R[i].set.nmat; m++)
			for (int t = 0; t < BK_SCENE_TERMS; t++) {
				if (!R[i].has[t])
					continue;
				const bk_scene_choice *c = &R[i].ch[t], *g = &R[i].gen[t];
				bk_csv_field(f, sc->mat[R[i].set.mat[m]].name);
				fprintf(f, ",%s,%s,", R[i].set.name, bk_scene_term_name(t));
				bk_csv_field(f, c->name);
				fputc(',', f);
				bk_csv_field(f, c->text ? c->text : "");
				fputc(',', f);
				params_text(f, c);
				fprintf(f, ",%d,%d,%d,%g,%.6g,%s,", c->ops.simple, c->ops.complex, c->fetches, c->cost, c->err,
				        err_unit(t));
				if (isfinite(c->budget))
					fprintf(f, "%.6g", c->budget);
				fprintf(f, ",%d,", c->meets);
				bk_csv_field(f, c->guards);
				fprintf(f, ",%g,%.6g,", g->cost, g->err);
				bk_csv_field(f, c->eq_name);
				fputc(',', f);
				if (c->eq_name[0])
					fprintf(f, "%.6g", c->eq_err);
				for (int k = 0; k < gpu.n; k++) {
					fputc(',', f);
					if (!isnan(R[i].gpu[t][k]))
						fprintf(f, "%.0f", R[i].gpu[t][k]);
					fputc(',', f);
					if (!isnan(R[i].gen_gpu[t][k]))
						fprintf(f, "%.0f", R[i].gen_gpu[t][k]);
				}
				fputc('\n', f);
			}
}

/* The set's worst error over its vf and env terms, and the generic's: both
 * are directional-albedo errors (scene_fit.h), so the larger is the
 * shader's; NaN when the set has neither (D alone, or diffuse only). */
static void set_errors(const set_result *r, double *err, double *gen_err)
{
	*err = *gen_err = NAN;
	for (int t = BK_SCENE_TERM_VF; t <= BK_SCENE_TERM_ENV; t++)
		if (r->has[t]) {
			*err = isnan(*err) || r->ch[t].err > *err ? r->ch[t].err : *err;
			*gen_err = isnan(*gen_err) || r->gen[t].err > *gen_err ? r->gen[t].err : *gen_err;
		}
}

static void sets_csv(FILE *f, const bk_scene *sc, const set_result *R, int nset)
{
	fprintf(f, "# brdfkit %s scene '%s': each feature set's shader against the generic one (GGX D, "
	           "height-correlated Smith V x Schlick F, %dx%d half DFG LUT, fp16 guards in mediump); spirv: SPIR-V "
	           "instructions of the forms' GLSL after spirv-opt -O (fetches not included)\n",
	        BK_VERSION, sc->name, BK_SCENE_GENERIC_LUT, BK_SCENE_GENERIC_LUT);
	if (gpu.n)
		fprintf(f, "# aco_CHIP_instructions: AMD instructions of the set's forms, summed (brdfkit gpucost: Mesa RADV's "
		           "null device, %s, fp32, net of a load/store baseline per form; fetches not included)\n",
		        gpu.driver);
	fputs("# error, generic_error: the largest of the set's vf and env errors (both directional-albedo errors on "
	      "the set's domain in the scene's precision; scene.csv has each); error_ratio = generic_error / error\n", f);
	fputs("feature_set,materials,r_lo,r_hi,f0_lo,f0_hi,cost,generic_cost,cost_ratio,spirv,generic_spirv,error,"
	      "generic_error,error_ratio", f);
	for (int c = 0; c < gpu.n; c++)
		fprintf(f, ",aco_%s_instructions,generic_aco_%s_instructions", gpu.chip[c], gpu.chip[c]);
	fputc('\n', f);
	for (int i = 0; i < nset; i++) {
		const set_result *r = &R[i];
		fprintf(f, "%s,", r->set.name);
		char names[1024] = "";
		for (int m = 0; m < r->set.nmat; m++)
			snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", m ? ";" : "",
			         sc->mat[r->set.mat[m]].name);
		bk_csv_field(f, names);
		fprintf(f, ",%g,%g,%g,%g,%g,%g,%.3g,%d,%d", r->set.r_lo, r->set.r_hi, r->set.f0_lo, r->set.f0_hi, r->cost,
		        r->gen_cost, r->gen_cost / r->cost, r->spirv, r->gen_spirv);
		double e, ge;
		set_errors(r, &e, &ge);
		if (isnan(e))
			fputs(",,,", f);
		else
			fprintf(f, ",%.6g,%.6g,%.3g", e, ge, ge / e);
		for (int c = 0; c < gpu.n; c++)
			fprintf(f, ",%.0f,%.0f", r->gpu_sum[c], r->gen_gpu_sum[c]);
		fputc('\n', f);
	}
}

/* with_time: the CPU timings too (stdout; report.txt stays reproducible) */
static void report_txt(FILE *f, const bk_scene *sc, const set_result *R, int nset, int with_time)
{
	fprintf(f, "scene '%s': %d material%s, %d feature set%s; punctual lights %s, image-based lighting %s, diffuse %s; "
	           "%s; ",
	        sc->name, sc->nmat, sc->nmat == 1 ? "" : "s", nset, nset == 1 ? "" : "s", sc->punctual ? "yes" : "no",
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
	for (int i = 0; i < nset; i++) {
		const set_result *r = &R[i];
		char dom[256];
		domain_text(sc, &r->set, dom, sizeof dom);
		fprintf(f, "\nfeature set %s (", r->set.name);
		for (int m = 0; m < r->set.nmat; m++)
			fprintf(f, "%s%s", m ? ", " : "", sc->mat[r->set.mat[m]].name);
		fprintf(f, "): %s\n", dom);
		if (!r->set.needs.vf && !r->set.needs.env)
			fputs("  no specular (the materials have none): diffuse only\n", f);
		if (r->set.needs.fixed_f0)
			fprintf(f, "  one f0 (%g): folded into the constants, no f0 input\n", r->set.needs.f0);
		for (int t = 0; t < BK_SCENE_TERMS; t++) {
			if (!r->has[t])
				continue;
			const bk_scene_choice *c = &r->ch[t], *g = &r->gen[t];
			if (t == BK_SCENE_TERM_D) {
				fprintf(f, "  D   exact GGX: cost %g (generic %g)\n      fp16 guards: %s\n", c->cost, g->cost, c->guards);
				continue;
			}
			fprintf(f, "  %-3s %s: cost %g (generic %g), %s %.3g (generic %.3g, budget %.3g%s), %d candidates scored\n",
			        bk_scene_term_name(t), c->name, c->cost, g->cost, err_unit(t), c->err, g->err, c->budget,
			        c->meets ? "" : ": NOT MET, the most accurate kept", c->scored);
			fprintf(f, "      fp16 guards: %s\n", c->guards);
			if (c->eq_name[0] && g->err > 0)
				fprintf(f, "      at the generic's cost: %s, cost %g, %s %.3g (%.2fx the generic's accuracy)\n", c->eq_name,
				        c->eq_cost, err_unit(t), c->eq_err, g->err / c->eq_err);
		}
		double e, ge;
		set_errors(r, &e, &ge);
		if (r->cost > 0) {
			fprintf(f, "  shader cost %g against the generic %g (%.2fx cheaper); SPIR-V %d against %d", r->cost,
			        r->gen_cost, r->gen_cost / r->cost, r->spirv, r->gen_spirv);
			if (e > 0) /* NaN: no vf or env term */
				fprintf(f, "; worst term error %.3g against the generic's %.3g (%.2fx %s)", e, ge,
				        ge >= e ? ge / e : e / ge, ge >= e ? "more accurate" : "less accurate");
		} else {
			fprintf(f, "  shader: the diffuse term alone, as in the generic shader");
		}
		if (with_time && r->cost > 0 && isfinite(r->ns) && isfinite(r->gen_ns))
			fprintf(f, "; CPU %.2f ns against %.2f ns per evaluation", r->ns, r->gen_ns);
		fputc('\n', f);
	}
}

/* One scene's part of the page: a heading, the choices, the savings. */
static void section_body(FILE *f, const bk_scene *sc, const set_result *R, int nset, const char *prefix)
{
	fputs("<h3>", f);
	bk_html_text(f, sc->name);
	fprintf(f, "</h3>\n<p>%d material%s, %s, %s%s%s, ", sc->nmat, sc->nmat == 1 ? "" : "s",
	        sc->half ? "mediump" : "highp", sc->punctual ? "punctual lights" : "no punctual lights",
	        sc->ibl ? ", image-based lighting" : ", no IBL", sc->diffuse ? ", diffuse" : "");
	if (sc->alu_tex)
		fprintf(f, "ALU:TEX %d", sc->alu_tex);
	else
		fprintf(f, "costs simple %g, complex %g, fetch %g", sc->simple_cost, sc->complex_cost, sc->fetch_cost);
	fprintf(f, ". Tables: <a href=\"%sscene.csv\">scene.csv</a>, <a href=\"%ssets.csv\">sets.csv</a>, "
	           "<a href=\"%sreport.txt\">report.txt</a>.</p>\n", prefix, prefix, prefix);
	fputs("<table>\n<tr><th>feature set</th><th>term</th><th>choice</th><th>cost (generic)</th><th>error "
	      "(generic)</th><th>budget</th><th>fp16 guards</th></tr>\n", f);
	for (int i = 0; i < nset; i++)
		for (int t = 0; t < BK_SCENE_TERMS; t++) {
			if (!R[i].has[t])
				continue;
			const bk_scene_choice *c = &R[i].ch[t], *g = &R[i].gen[t];
			fprintf(f, "<tr><td>%s</td><td>%s</td><td>", R[i].set.name, bk_scene_term_name(t));
			bk_html_text(f, c->name);
			fprintf(f, "</td><td>%g (%g)</td><td>%.3g (%.3g)</td><td>", c->cost, g->cost, c->err, g->err);
			if (isfinite(c->budget))
				fprintf(f, "%.3g%s", c->budget, c->meets ? "" : " not met");
			fputs("</td><td>", f);
			bk_html_text(f, c->guards);
			fputs("</td></tr>\n", f);
		}
	fputs("</table>\n<table>\n<tr><th>feature set</th><th>shader cost</th><th>generic</th><th>ratio</th>"
	      "<th>SPIR-V</th><th>generic SPIR-V</th><th>worst term error</th><th>generic</th><th>accuracy gain</th>"
	      "<th>shaders</th></tr>\n", f);
	for (int i = 0; i < nset; i++) {
		const set_result *r = &R[i];
		double e, ge;
		set_errors(r, &e, &ge);
		fprintf(f, "<tr><td>%s</td><td>%g</td><td>%g</td><td>%.2fx</td><td>%d</td><td>%d</td>", r->set.name, r->cost,
		        r->gen_cost, r->gen_cost / r->cost, r->spirv, r->gen_spirv);
		if (isnan(e) || !(e > 0))
			fputs("<td></td><td></td><td></td><td>", f);
		else
			fprintf(f, "<td>%.3g</td><td>%.3g</td><td>%.2fx</td><td>", e, ge, ge / e);
		for (int li = 0; li < 3; li++)
			if (sc->languages & (1u << li))
				fprintf(f, "<a href=\"%s%s/shader.%s\">%s</a> ", prefix, r->set.name, lang_ext[li], lang_ext[li]);
		fputs("</td></tr>\n", f);
	}
	fputs("</table>\n", f);
}

static void section_open(FILE *f, const char *id)
{
	fprintf(f, "<section id=\"%s\">\n<h2>Scenes: shaders specialised to what a scene contains</h2>\n<p>For each scene, "
	           "materials with the same needs share a feature set and one shader; each term it needs is the cheapest "
	           "form that meets the scene's error budget on the set's own roughness, f0 and NoV range (catalog forms, "
	           "published and refitted there, LUTs at the scene's ALU:TEX ratio, a short search for V&middot;F), with "
	           "the fp16 guards it needs at the scene's precision and none it does not. Errors: V&middot;F, the "
	           "directional albedo's max abs error of D&middot;V&middot;F; env, the max abs error of f0&middot;A + B. "
	           "The generic shader: GGX D &middot; height-correlated Smith V &middot; Schlick F and a %d&sup2; half DFG "
	           "LUT, with the fp16 guards in mediump.</p>\n", id, BK_SCENE_GENERIC_LUT);
}

/* SPIR-V count of a choice's form (0 for a LUT: the fetch is counted apart). */
static int spirv_of(const bk_scene_choice *c)
{
	if (c->lut || !c->text)
		return 0;
	bk_form_error fe;
	bk_form *f = bk_form_parse(c->text, &fe);
	char err[256];
	int n = f ? bk_spirv_count(f, c->p, err, sizeof err) : -1;
	bk_form_free(f);
	return n;
}

/* CPU ns per evaluation of every form of every set and of the generic, timed
 * together (interleaved) and summed per set. */
static void time_sets(set_result *R, int nset)
{
	size_t cap = (size_t)(nset > 0 ? nset : 1) * BK_SCENE_TERMS * 2;
	int n = 0;
	bk_compare_row *rows = calloc(cap, sizeof *rows);
	int *owner = calloc(cap, sizeof *owner);
	for (int i = 0; i < nset; i++)
		R[i].ns = R[i].gen_ns = 0;
	for (int i = 0; rows && owner && i < nset; i++)
		for (int t = 0; t < BK_SCENE_TERMS; t++)
			for (int g = 0; g < 2 && R[i].has[t]; g++) {
				const bk_scene_choice *c = g ? &R[i].gen[t] : &R[i].ch[t];
				if (c->lut || !c->text)
					continue;
				bk_compare_row *r = &rows[n];
				snprintf(r->name, sizeof r->name, "%s %s %d", R[i].set.name, bk_scene_term_name(t), g);
				snprintf(r->form, sizeof r->form, "%s", c->text);
				memcpy(r->params, c->p, sizeof r->params);
				bk_form_error fe;
				bk_form *f = bk_form_parse(c->text, &fe);
				r->nparams = f ? bk_form_nparams(f) : 0;
				bk_form_free(f);
				owner[n++] = i * 2 + g;
			}
	char err[256];
	if (!rows || !owner || bk_time_rows(rows, n, TIME_REPS, err, sizeof err)) {
		for (int i = 0; i < nset; i++)
			R[i].ns = R[i].gen_ns = NAN;
	} else {
		for (int k = 0; k < n; k++) {
			set_result *r = &R[owner[k] / 2];
			*(owner[k] % 2 ? &r->gen_ns : &r->ns) += rows[k].ns;
		}
	}
	free(rows);
	free(owner);
}

/* --gpu: every chosen and generic form of every set compiled for each chip
 * (one Vulkan instance per chip for the whole scene). Returns 0 or 1. */
static int gpu_sets(set_result *R, int nset)
{
	int n = 2 * nset * BK_SCENE_TERMS, nc = gpu.n, rc = 0;
	const char **a = calloc((size_t)n, sizeof *a);
	const double **p = calloc((size_t)n, sizeof *p);
	double *insn = calloc((size_t)n * (size_t)nc + 1, sizeof *insn);
	char err[700];
	if (!a || !p || !insn)
		rc = cli_fail("scene", "out of memory");
	for (int i = 0; !rc && i < nset; i++)
		for (int t = 0; t < BK_SCENE_TERMS; t++)
			for (int g = 0; g < 2; g++) {
				const bk_scene_choice *c = g ? &R[i].gen[t] : &R[i].ch[t];
				int k = (i * BK_SCENE_TERMS + t) * 2 + g;
				a[k] = R[i].has[t] && !c->lut ? c->text : NULL;
				p[k] = c->p;
			}
	if (!rc && bk_gpucost_texts(a, NULL, p, n, gpu.chip, nc, insn, NULL, NULL, gpu.driver, sizeof gpu.driver, err,
	                            sizeof err))
		rc = cli_fail("scene", "--gpu: %s", err);
	for (int i = 0; !rc && i < nset; i++)
		for (int c = 0; c < nc; c++) {
			R[i].gpu_sum[c] = R[i].gen_gpu_sum[c] = 0;
			for (int t = 0; t < BK_SCENE_TERMS; t++)
				for (int g = 0; g < 2; g++) {
					double v = insn[((i * BK_SCENE_TERMS + t) * 2 + g) * nc + c];
					*(g ? &R[i].gen_gpu[t][c] : &R[i].gpu[t][c]) = v;
					if (!isnan(v))
						*(g ? &R[i].gen_gpu_sum[c] : &R[i].gpu_sum[c]) += v;
				}
		}
	free(a);
	free(p);
	free(insn);
	return rc;
}

static void timing_csv(FILE *f, const set_result *R, int nset)
{
	fprintf(f, "# CPU ns per evaluation of each feature set's forms (generated C, -O2, median of %d interleaved "
	           "runs, summed over the set's terms; LUT fetches not included): not reproducible\n", TIME_REPS);
	fputs("feature_set,ns_per_eval,generic_ns_per_eval\n", f);
	for (int i = 0; i < nset; i++)
		fprintf(f, "%s,%.3f,%.3f\n", R[i].set.name, R[i].ns, R[i].gen_ns);
}

typedef struct scene_run {
	const char *file;
	char stem[64];  /* the file's name without directory and .json: its folder when several */
	char hash[20];  /* FNV-1a of the file's bytes */
	bk_scene sc;
	bk_scene_set sets[BK_SCENE_MAX_MATERIALS];
	set_result R[BK_SCENE_MAX_MATERIALS];
	int nset;
} scene_run;

/* One scene's files into dir (existing). */
static int write_scene(const char *dir, const scene_run *S, int timed, char *err, size_t errlen)
{
	char path[8800];
	int rc = 0;
	for (int i = 0; i < S->nset && !rc; i++) {
		snprintf(path, sizeof path, "%s/%s", dir, S->R[i].set.name);
		if (mkdir(path, 0777))
			return -1;
		for (int li = 0; li < 3 && !rc; li++) {
			if (!(S->sc.languages & (1u << li)))
				continue;
			snprintf(path, sizeof path, "%s/%s/shader.%s", dir, S->R[i].set.name, lang_ext[li]);
			FILE *f = fopen(path, "w");
			if (!f)
				return -1;
			rc = write_shader(f, &S->sc, &S->R[i], li, S->hash, err, errlen);
			if (ferror(f) | fclose(f))
				rc = -1;
		}
	}
	static const char *const files[] = {"scene.csv", "sets.csv", "report.txt", "timing.csv"};
	for (int k = 0; k < 4 && !rc; k++) {
		if (k == 3 && !timed)
			break;
		snprintf(path, sizeof path, "%s/%s", dir, files[k]);
		FILE *f = fopen(path, "w");
		if (!f)
			return -1;
		switch (k) {
		case 0: scene_csv(f, &S->sc, S->R, S->nset, S->hash); break;
		case 1: sets_csv(f, &S->sc, S->R, S->nset); break;
		case 2: report_txt(f, &S->sc, S->R, S->nset, 0); break;
		default: timing_csv(f, S->R, S->nset); break;
		}
		if (ferror(f) | fclose(f))
			rc = -1;
	}
	return rc;
}

static int write_all(const char *dir, const scene_run *S, int n, const char *prefix, const char *id, int timed,
                     char *err, size_t errlen)
{
	char path[4400 + 64];
	int rc = 0;
	for (int k = 0; k < n && !rc; k++) {
		snprintf(path, sizeof path, "%s/%s", dir, S[k].stem);
		if (n > 1 && mkdir(path, 0777))
			return -1;
		rc = write_scene(n > 1 ? path : dir, &S[k], timed, err, errlen);
	}
	snprintf(path, sizeof path, "%s/section.html", dir);
	FILE *f = rc ? NULL : fopen(path, "w");
	if (!f)
		return -1;
	section_open(f, id);
	for (int k = 0; k < n; k++) {
		char pre[4400];
		snprintf(pre, sizeof pre, "%s%s%s", prefix, n > 1 ? S[k].stem : "", n > 1 ? "/" : "");
		section_body(f, &S[k].sc, S[k].R, S[k].nset, pre);
	}
	fputs("</section>\n", f);
	if (ferror(f) | fclose(f))
		rc = -1;
	return rc;
}

/* Reads and checks one scene file into S. Returns 0 or 1 after an error. */
static int load(scene_run *S, const char *file)
{
	memset(S, 0, sizeof *S);
	S->file = file;
	const char *base = strrchr(file, '/') ? strrchr(file, '/') + 1 : file;
	size_t n = strlen(base);
	if (n > 5 && !strcmp(base + n - 5, ".json"))
		n -= 5;
	snprintf(S->stem, sizeof S->stem, "%.*s", (int)(n < sizeof S->stem ? n : sizeof S->stem - 1), base);
	size_t len;
	char *text = cli_read_file(file, &len);
	if (!text)
		return cli_fail("scene", "%s: cannot be read", file);
	char err[512], why[128];
	if (cli_check_text(text, len, why, sizeof why)) {
		free(text);
		return cli_fail("scene", "%s: not a text file (%s)", file, why);
	}
	if (bk_scene_parse(text, len, &S->sc, err, sizeof err)) {
		free(text);
		return cli_fail("scene", "%s: %s", file, err);
	}
	snprintf(S->hash, sizeof S->hash, "%016llx", (unsigned long long)bk_hash_bytes(14695981039346656037ull, text, len));
	free(text);
	S->nset = bk_scene_plan(&S->sc, S->sets);
	return 0;
}

/* Chooses every term of every set of S. Returns 0 or 1 after an error. */
static int specialise(scene_run *S)
{
	char err[512];
	for (int i = 0; i < S->nset; i++) {
		set_result *r = &S->R[i];
		r->set = S->sets[i];
		r->ns = r->gen_ns = NAN;
		r->has[BK_SCENE_TERM_D] = r->has[BK_SCENE_TERM_VF] = r->set.needs.vf;
		r->has[BK_SCENE_TERM_ENV] = r->set.needs.env;
		for (int t = 0; t < BK_SCENE_TERMS; t++) {
			if (!r->has[t])
				continue;
			fprintf(stderr, "brdfkit scene: %s: %s: choosing %s\n", S->stem, r->set.name, bk_scene_term_name(t));
			if (bk_scene_choose(&S->sc, &r->set, t, &r->ch[t], &r->gen[t], cli_progress, "scene: env reference", err,
			                    sizeof err))
				return cli_fail("scene", "%s: %s: %s", S->file, r->set.name, err);
			r->cost += r->ch[t].cost;
			r->gen_cost += r->gen[t].cost;
			r->spirv += spirv_of(&r->ch[t]);
			r->gen_spirv += spirv_of(&r->gen[t]);
		}
	}
	return 0;
}

int cmd_scene(int argc, char **argv)
{
	const char *out = NULL, *prefix = "", *id = "scenes", *chips = NULL;
	int no_time = 0;
	cli_opt opts[] = {
		{.name = "--out", .kind = CLI_STR, .metavar = "DIR", .help = "write the shaders, scene.csv, sets.csv, report.txt, section.html", .dest = &out, .required = 1},
		{.name = "--no-time", .kind = CLI_FLAG, .help = "skip the CPU timing (timing.csv)", .dest = &no_time},
		{.name = "--link-prefix", .kind = CLI_STR, .metavar = "PATH/", .help = "prefix of links in section.html", .dest = &prefix},
		{.name = "--id", .kind = CLI_STR, .metavar = "ID", .help = "the section's HTML id (default scenes)", .dest = &id},
		{.name = "--gpu", .kind = CLI_STR, .metavar = "CHIPS", .help = "AMD instruction counts of every set's forms and the generic's per chip (brdfkit gpucost), in scene.csv and sets.csv", .dest = &chips},
	};
	cli_cmd cmd = {"scene", "From a scene description (JSON) to one specialised shader per feature set: the terms the\n"
	               "scene needs and no others, each the cheapest form that meets the error budget on the\n"
	               "materials' own roughness, f0 and NoV range (catalog forms, published and refitted there;\n"
	               "for the environment BRDF also LUTs at the scene's ALU:TEX ratio; a short search for V*F),\n"
	               "with the fp16 guards it needs at the scene's precision and none it does not; against the\n"
	               "generic shader. Several files: each into DIR/NAME/ (NAME: the file's name without .json),\n"
	               "one section.html for all.",
	               "SCENE.json ... --out DIR",
	               "The scene file (all but materials optional; unknown keys are errors):\n"
	               "  {\"scene\": NAME, \"materials\": [{\"name\": N, \"roughness\": R, \"f0\": F, \"specular\": true}],\n"
	               "   \"lighting\": {\"punctual\": true, \"ibl\": true, \"diffuse\": true},\n"
	               "   \"geometry\": {\"nov\": {\"min\": 0, \"max\": 1}},\n"
	               "   \"target\": {\"precision\": \"mediump\"|\"highp\", \"alu_tex\": 16|32|48|64 or\n"
	               "              \"costs\": {\"simple\": 1, \"complex\": 4, \"fetch\": 16},\n"
	               "              \"lut\": true, \"languages\": [\"glsl\", \"hlsl\", \"c\"],\n"
	               "              \"error\": E|\"generic\"|\"at-generic-cost\"|{\"vf\": E, \"env\": E}}}\n"
	               "R: a number, a list (its hull), {\"min\": x, \"max\": y} or \"texture\" (= [0, 1]).\n"
	               "F: a number, a list, a range, \"dielectric\" (0.04), \"metal\" ([0.5, 1]) or \"texture\" ([0.02, 1]).\n"
	               "\"lut\": false: no DFG texture for the environment BRDF (no sampler to spare). LUTs are\n"
	               "16^2 to 128^2 in unorm8, half or float, in the engines' layout and laid out for the set\n"
	               "(one f0 folded into one channel, rows over its roughness range, x at sqrt(NoV); the\n"
	               "shader's comment gives the brdfkit lut command that makes it and the coordinates).\n"
	               "Defaults: all lighting on, NoV in [0, 1], highp, alu_tex 32, LUT allowed, all languages,\n"
	               "error \"generic\""
	               " (each term as accurate as the generic shader's on the domain, in the scene's precision).\n"
	               "\"at-generic-cost\": each term the most accurate form at no more than the generic's cost\n"
	               "(a LUT: and no more texture memory) instead of the cheapest at a budget.\n"
	               "Errors: vf, the directional-albedo max abs error of D*V*F; env, the max abs error of\n"
	               "f0*A + B; at both ends of the f0 range. The report also gives, for env, the most\n"
	               "accurate candidate at no more than the generic's cost and LUT memory.",
	               opts, 5, 16, 0, {0}};
	int rc = cli_parse(&cmd, argc, argv);
	if (rc)
		return rc == 1 ? 0 : rc;
	if (cmd.npos < 1)
		return cli_usage(&cmd, "give a scene file");
	if (chips) {
		char gerr[700];
		snprintf(gpu.buf, sizeof gpu.buf, "%s", chips);
		if (bk_gpucost_chips(gpu.buf, gpu.chip, SCENE_CHIPS, &gpu.n, gerr, sizeof gerr))
			return cli_usage(&cmd, "--gpu: %s", gerr);
	}
	int n = cmd.npos;
	scene_run *S = calloc(n, sizeof *S);
	if (!S)
		return cli_fail("scene", "out of memory");
	for (int k = 0; k < n && !rc; k++) { /* every file checked before any work */
		rc = load(&S[k], cmd.pos[k]);
		for (int j = 0; j < k && !rc && n > 1; j++)
			if (!strcmp(S[j].stem, S[k].stem))
				rc = cli_usage(&cmd, "'%s' and '%s' would both write DIR/%s/", S[j].file, S[k].file, S[k].stem);
	}
	char err[512];
	if (!rc && bk_out_dir_check(out, err, sizeof err)) /* before the work, not after */
		rc = cli_fail("scene", "--out %s", err);
	char gerr[700];
	if (!rc && gpu.n && bk_gpucost_check(gpu.chip, gpu.n, gpu.driver, sizeof gpu.driver, gerr, sizeof gerr))
		rc = cli_fail("scene", "--gpu: %s", gerr);
	for (int k = 0; k < n && !rc; k++)
		rc = specialise(&S[k]);
	for (int k = 0; k < n && !rc && !no_time; k++)
		time_sets(S[k].R, S[k].nset);
	for (int k = 0; k < n && !rc && gpu.n; k++)
		rc = gpu_sets(S[k].R, S[k].nset);
	if (!rc) {
		bk_out_dir od;
		if (bk_out_dir_begin(&od, out, NULL, err, sizeof err)) {
			rc = cli_fail("scene", "--out %s", err);
		} else {
			err[0] = 0;
			if (write_all(od.tmp, S, n, prefix, id, !no_time, err, sizeof err)) {
				bk_out_dir_abort(&od);
				rc = cli_fail("scene", "%s: writing the results failed%s%s", out, *err ? ": " : "", err);
			} else if (bk_out_dir_commit(&od, err, sizeof err)) {
				rc = cli_fail("scene", "--out %s", err);
			}
		}
	}
	for (int k = 0; k < n; k++) {
		if (!rc)
			report_txt(stdout, &S[k].sc, S[k].R, S[k].nset, 1);
		for (int i = 0; i < S[k].nset; i++)
			for (int t = 0; t < BK_SCENE_TERMS; t++) {
				bk_scene_choice_free(&S[k].R[i].ch[t]);
				bk_scene_choice_free(&S[k].R[i].gen[t]);
			}
	}
	free(S);
	return rc;
}
