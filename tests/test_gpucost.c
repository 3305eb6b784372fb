/*
 * test_gpucost.c — forms compiled to AMD ISA by RADV's null device
 * (analysis/gpucost.c). The expected counts are facts of the hardware's
 * instruction set, not of this code: GCN and RDNA have no divide instruction
 * (a/b is v_rcp_f32 and a multiply), exp2 is one v_exp_f32, a*b + c is one
 * multiply-add; a form that is just an input compiles to the baseline.
 */
#include "catalog.h"
#include "gpucost.h"

#include <criterion/criterion.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char *const all_chips[] = {"polaris10", "vega10", "navi21", "gfx1100"};
#define NCHIPS 4

/* Occurrences of an instruction in a listing: name then its encoding suffix
 * (_e32, _e64) or a blank; "(then repeated N times)" after it adds N. */
static int count_insn(const char *isa, const char *name)
{
	int n = 0, last = 0;
	size_t k = strlen(name);
	for (const char *p = isa; *p;) {
		size_t len = strcspn(p, "\n");
		const char *q = p + strspn(p, " \t");
		int r;
		if (sscanf(q, "(then repeated %d times)", &r) == 1)
			n += last ? r : 0;
		else if (q[0] == 'v' || q[0] == 's')
			n += last = !strncmp(q, name, k) && (q[k] == '_' || q[k] == ' ' || q[k] == '\t');
		p += len + (p[len] == '\n');
	}
	return n;
}

/* n forms (split-sum pairs where text_b[i]) on nchips chips in one run (one
 * Vulkan instance a chip, not one a form and chip): s, isa and ok at
 * [i * nchips + c], form i on chips[c] (ok 0 and isa NULL where the chip
 * cannot run it: fp16 without shaderFloat16); ok may be NULL. */
static void run_on(const char *const *text, const char *const *text_b, const double *const *params, int n,
                   const char *const *chips, int nchips, int fp16, bk_gpucost_stats *s, char **isa, int *ok)
{
	bk_form *fa[8], *fb[8];
	bk_gpucost_job job[8];
	cr_assert(n <= 8);
	for (int i = 0; i < n; i++) {
		fa[i] = bk_form_parse(text[i], NULL);
		fb[i] = text_b && text_b[i] ? bk_form_parse(text_b[i], NULL) : NULL;
		cr_assert(fa[i] && (!text_b || !text_b[i] || fb[i]), "%s does not parse", text[i]);
		job[i] = (bk_gpucost_job){.form = {fa[i], fb[i]}, .params = params ? params[i] : NULL};
	}
	char driver[256], err[600];
	int rc = bk_gpucost_run(job, n, chips, nchips, fp16, driver, sizeof driver, isa, err, sizeof err);
	cr_assert_eq(rc, 0, "%s on %s: %s", text[0], chips[0], err);
	cr_assert(strstr(driver, "radv"), "driver '%s'", driver);
	for (int i = 0; i < n; i++) {
		bk_form_free(fa[i]);
		bk_form_free(fb[i]);
		for (int c = 0; c < nchips; c++) {
			s[i * nchips + c] = job[i].net[c];
			if (ok)
				ok[i * nchips + c] = job[i].ok[c];
			cr_assert(!job[i].ok[c] || isa[i * nchips + c], "%s on %s: no disassembly", text[i], chips[c]);
		}
	}
}

/* run_on every chip the tests know */
static void run_all(const char *const *text, const char *const *text_b, const double *const *params, int n,
                    int fp16, bk_gpucost_stats *s, char **isa)
{
	run_on(text, text_b, params, n, all_chips, NCHIPS, fp16, s, isa, NULL);
}

static void free_all(char **isa, int n)
{
	for (int k = 0; k < n; k++)
		free(isa[k]);
}

static const bk_catalog_entry *entry(const char *name)
{
	const bk_catalog_entry *e = bk_catalog_find(name);
	cr_assert(e, "catalog has no %s", name);
	return e;
}

Test(gpucost, isa_count_expands_repeats_and_skips_integer_mads)
{
	const char *isa = "BB0:\n"
	                  "\tv_mad_u32_u24 v0, s2, 64, v0                    ; d1c30000\n"
	                  "\tv_rcp_f32_e32 v1, v1\n"
	                  "\tv_fmac_f32_e32 v2, v1, v3\n"
	                  "\t(then repeated 2 times)\n"
	                  "\tv_pk_fma_f16 v4, v4, v5, v6\n"
	                  "\tv_cvt_f16_f32_e32 v7, v7\n"
	                  "\ts_nop 0\n"
	                  "\t(then repeated 5 times)\n"
	                  "\tv_exp_f16_e32 v8, v8\n";
	bk_gpucost_stats s = {0};
	bk_gpucost_isa_count(isa, &s);
	cr_expect_eq(s.transcendental, 2); /* v_rcp_f32, v_exp_f16 */
	cr_expect_eq(s.fma, 4);            /* v_fmac three times, v_pk_fma once; not v_mad_u32_u24 */
	cr_expect_eq(s.packed, 1);
	cr_expect_eq(s.convert, 1);
}

Test(gpucost, unknown_chip_is_refused_before_radv_aborts)
{
	const char *gfx;
	cr_expect_eq(bk_gpucost_chip("NAVI21", &gfx), 0);
	cr_expect_str_eq(gfx, "gfx10.3");
	cr_expect_eq(bk_gpucost_chip("navi31", &gfx), -1); /* rejected by Mesa 22.3 */
	bk_form *f = bk_form_parse("NoV", NULL);
	bk_gpucost_job job = {.form = {f, NULL}};
	const char *chip = "gfx9";
	char driver[64], err[256];
	cr_expect_eq(bk_gpucost_run(&job, 1, &chip, 1, 0, driver, sizeof driver, NULL, err, sizeof err), -1);
	cr_expect(strstr(err, "unknown chip 'gfx9'"), "%s", err);
	bk_form_free(f);
}

/* RADV is installed here (the other tests run it): a VK_ICD_FILENAMES that
 * points elsewhere is what to fix, not a package to install. */
Test(gpucost, a_driver_path_elsewhere_is_named_not_the_package)
{
	cr_assert_eq(access("/usr/share/vulkan/icd.d/radeon_icd.x86_64.json", R_OK), 0, "RADV's ICD file");
	setenv("VK_ICD_FILENAMES", "/nonexistent/radeon_icd.json", 1);
	bk_form *f = bk_form_parse("NoV", NULL);
	bk_gpucost_job job = {.form = {f, NULL}};
	const char *chip = "navi21";
	char driver[64], err[512];
	int rc = bk_gpucost_run(&job, 1, &chip, 1, 0, driver, sizeof driver, NULL, err, sizeof err);
	cr_expect_eq(rc, BK_GPUCOST_NO_DRIVER, "%s", err);
	cr_expect(strstr(err, "VK_ICD_FILENAMES=/nonexistent/radeon_icd.json does not name RADV's"), "%s", err);
	cr_expect_null(strstr(err, "apt-get"), "%s", err);
	bk_form_free(f);
}

Test(gpucost, an_input_alone_costs_nothing)
{
	const char *nov[] = {"NoV"};
	for (int fp16 = 0; fp16 < 2; fp16++) {
		bk_gpucost_stats s[NCHIPS];
		char *isa[NCHIPS];
		run_all(nov, NULL, NULL, 1, fp16, s, isa);
		free_all(isa, NCHIPS);
		for (int c = 0; c < NCHIPS; c++)
			cr_expect(!memcmp(&s[c], &(bk_gpucost_stats){0}, sizeof s[c]), "NoV on %s%s: %ld instructions",
			          all_chips[c], fp16 ? " fp16" : "", s[c].instructions);
	}
}

Test(gpucost, one_multiply_add)
{
	const char *mad[] = {"NoV*NoL + f0"};
	bk_gpucost_stats s[NCHIPS];
	char *isa[NCHIPS];
	run_all(mad, NULL, NULL, 1, 0, s, isa);
	for (int c = 0; c < NCHIPS; c++) {
		cr_expect_eq(s[c].fma, 1, "%s: fma %ld", all_chips[c], s[c].fma);
		cr_expect_eq(s[c].transcendental, 0, "%s", all_chips[c]);
		/* GCN (gfx8, gfx9) has no fused 3-address fp32 fma that ACO picks here: v_mad or v_mac */
		cr_expect(s[c].instructions >= 1 && s[c].instructions <= 2, "%s: %ld", all_chips[c], s[c].instructions);
	}
	free_all(isa, NCHIPS);
}

Test(gpucost, division_is_one_reciprocal)
{
	const char *div[] = {"NoV/NoL"};
	bk_gpucost_stats s[NCHIPS];
	char *isa[NCHIPS];
	run_all(div, NULL, NULL, 1, 0, s, isa);
	for (int c = 0; c < NCHIPS; c++) {
		cr_expect_eq(count_insn(isa[c], "v_rcp_f32"), 1, "%s:\n%s", all_chips[c], isa[c]);
		cr_expect_eq(s[c].transcendental, 1, "%s", all_chips[c]);
	}
	free_all(isa, NCHIPS);
}

Test(gpucost, exp2_is_one_v_exp)
{
	const char *e2[] = {"exp2(NoV)"};
	bk_gpucost_stats s[NCHIPS];
	char *isa[NCHIPS];
	run_all(e2, NULL, NULL, 1, 0, s, isa);
	for (int c = 0; c < NCHIPS; c++) {
		cr_expect_eq(count_insn(isa[c], "v_exp_f32"), 1, "%s:\n%s", all_chips[c], isa[c]);
		cr_expect_eq(s[c].transcendental, 1, "%s", all_chips[c]);
		cr_expect_eq(s[c].instructions, 1, "%s: %ld", all_chips[c], s[c].instructions);
	}
	free_all(isa, NCHIPS);
}

/* The talk's claim: its specular term (V·F, and D·V·F) needs one division,
 * so one v_rcp_f32 and no other transcendental op. */
Test(gpucost, talk_specular_has_one_rcp)
{
	const char *names[] = {"vf_talk_r", "vf_talk_a", "dvf_talk_r"}, *forms[3];
	const double *params[3];
	for (int i = 0; i < 3; i++) {
		forms[i] = entry(names[i])->form;
		params[i] = entry(names[i])->defaults;
	}
	bk_gpucost_stats s[3 * NCHIPS];
	char *isa[3 * NCHIPS];
	run_all(forms, NULL, params, 3, 0, s, isa);
	for (int i = 0; i < 3; i++)
		for (int c = 0; c < NCHIPS; c++) {
			int k = i * NCHIPS + c;
			cr_expect_eq(count_insn(isa[k], "v_rcp_f32"), 1, "%s on %s", names[i], all_chips[c]);
			cr_expect_eq(s[k].transcendental, 1, "%s on %s: %ld", names[i], all_chips[c], s[k].transcendental);
		}
	free_all(isa, 3 * NCHIPS);
}

/* The talk's environment BRDF avoids complex ops by design; Karis's
 * EnvBRDFApprox has one exp2. */
Test(gpucost, talk_env_has_no_transcendental_karis_one_exp)
{
	const bk_catalog_entry *t = entry("env_talk_r"), *k = entry("env_karis2014");
	const char *forms[] = {t->form, k->form}, *forms_b[] = {t->form_b, NULL};
	const double *params[] = {t->defaults, k->defaults};
	bk_gpucost_stats s[2 * NCHIPS];
	char *isa[2 * NCHIPS];
	run_all(forms, forms_b, params, 2, 0, s, isa);
	for (int c = 0; c < NCHIPS; c++) {
		cr_expect_eq(s[c].transcendental, 0, "env_talk_r on %s", all_chips[c]);
		cr_expect_eq(count_insn(isa[NCHIPS + c], "v_exp_f32"), 1, "env_karis2014 on %s", all_chips[c]);
		cr_expect_eq(s[NCHIPS + c].transcendental, 1, "env_karis2014 on %s", all_chips[c]);
	}
	free_all(isa, 2 * NCHIPS);
}

/* fp16: the rewritten GLSL compiles, and where the chip has shaderFloat16
 * (gfx9 on) a half multiply-add is a half instruction, not a float one. */
Test(gpucost, fp16_uses_half_instructions)
{
	bk_form *g = bk_form_parse("NoV*NoL + f0*0.5", NULL);
	const bk_form *f[2] = {g, NULL};
	char *glsl = bk_gpucost_glsl(f, NULL, bk_form_inputs(g), 1, 1);
	cr_assert(glsl);
	cr_expect(strstr(glsl, "float16_t") && strstr(glsl, "0.5hf"), "%s", glsl);
	cr_expect(!strstr(glsl, "highp float") && !strstr(glsl, "\tfloat "), "%s", glsl);
	free(glsl);
	bk_form_free(g);
	const char *mad[] = {"NoV*NoL + f0"}, *nov[] = {"NoV"}, *navi[] = {"navi21"}, *polaris[] = {"polaris10"};
	bk_gpucost_stats s;
	char *isa;
	int ok;
	run_on(mad, NULL, NULL, 1, navi, 1, 1, &s, &isa, &ok);
	cr_expect(ok);
	cr_expect(isa && strstr(isa, "_f16"), "%s", isa);
	cr_expect_eq(isa ? count_insn(isa, "v_fma_f32") + count_insn(isa, "v_fmac_f32") : -1, 0, "%s", isa);
	free(isa);
	run_on(nov, NULL, NULL, 1, polaris, 1, 1, &s, &isa, &ok);
	cr_expect(!ok, "gfx8 in RADV 22.3 has no shaderFloat16");
	free(isa);
}

/* Spearman: monotone is 1 whatever the scale, reversed is -1; with ties the
 * average ranks give Pearson's r on ranks, here x ranks (1, 2.5, 2.5, 4) and
 * y ranks (1, 2, 3, 4): r = 4.5 / sqrt(4.5 * 5) = 0.9486833. */
Test(gpucost, spearman_rank_correlation)
{
	double x[] = {1, 2, 3, 4}, y[] = {10, 100, 1000, 1e4}, z[] = {4, 3, 2, 1};
	cr_expect_float_eq(bk_gpucost_spearman(x, y, 4), 1.0, 1e-12);
	cr_expect_float_eq(bk_gpucost_spearman(x, z, 4), -1.0, 1e-12);
	double t[] = {1, 5, 5, 9};
	cr_expect_float_eq(bk_gpucost_spearman(t, x, 4), 4.5 / sqrt(4.5 * 5), 1e-12);
	double k[] = {2, 2, 2, 2};
	cr_expect(isnan(bk_gpucost_spearman(k, x, 4)));
}

/* Least squares recovers exact weights, and refuses collinear columns. */
Test(gpucost, fit2_recovers_weights)
{
	double a[] = {1, 2, 3, 7}, b[] = {0, 1, 1, 2}, y[4], wa, wb;
	for (int i = 0; i < 4; i++)
		y[i] = 1.5 * a[i] + 4 * b[i];
	cr_assert_eq(bk_gpucost_fit2(a, b, y, 4, &wa, &wb), 0);
	cr_expect_float_eq(wa, 1.5, 1e-12);
	cr_expect_float_eq(wb, 4.0, 1e-12);
	double c[] = {2, 4, 6, 14};
	cr_expect_eq(bk_gpucost_fit2(a, c, y, 4, &wa, &wb), -1);
}
