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

/* One form (a split-sum pair when text_b) on one chip: net figures and the ISA. */
static bk_gpucost_stats run_one(const char *text, const char *text_b, const double *params, const char *chip,
                                int fp16, char **isa, int *ok)
{
	bk_form *a = bk_form_parse(text, NULL), *b = text_b ? bk_form_parse(text_b, NULL) : NULL;
	bk_gpucost_job job = {.form = {a, b}, .params = params};
	cr_assert(a && (!text_b || b), "%s does not parse", text);
	char driver[256], err[600];
	*isa = NULL;
	int rc = bk_gpucost_run(&job, 1, &chip, 1, fp16, driver, sizeof driver, isa, err, sizeof err);
	cr_assert_eq(rc, 0, "%s on %s: %s", text, chip, err);
	cr_assert(strstr(driver, "radv"), "driver '%s'", driver);
	bk_form_free(a);
	bk_form_free(b);
	if (ok)
		*ok = job.ok[0];
	return job.net[0];
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
	for (int c = 0; c < NCHIPS; c++)
		for (int fp16 = 0; fp16 < 2; fp16++) {
			char *isa;
			int ok;
			bk_gpucost_stats s = run_one("NoV", NULL, NULL, all_chips[c], fp16, &isa, &ok);
			free(isa);
			cr_expect(!memcmp(&s, &(bk_gpucost_stats){0}, sizeof s), "NoV on %s%s: %ld instructions",
			          all_chips[c], fp16 ? " fp16" : "", s.instructions);
		}
}

Test(gpucost, one_multiply_add)
{
	for (int c = 0; c < NCHIPS; c++) {
		char *isa;
		bk_gpucost_stats s = run_one("NoV*NoL + f0", NULL, NULL, all_chips[c], 0, &isa, NULL);
		cr_expect_eq(s.fma, 1, "%s: fma %ld", all_chips[c], s.fma);
		cr_expect_eq(s.transcendental, 0, "%s", all_chips[c]);
		/* GCN (gfx8, gfx9) has no fused 3-address fp32 fma that ACO picks here: v_mad or v_mac */
		cr_expect(s.instructions >= 1 && s.instructions <= 2, "%s: %ld", all_chips[c], s.instructions);
		free(isa);
	}
}

Test(gpucost, division_is_one_reciprocal)
{
	for (int c = 0; c < NCHIPS; c++) {
		char *isa;
		bk_gpucost_stats s = run_one("NoV/NoL", NULL, NULL, all_chips[c], 0, &isa, NULL);
		cr_expect_eq(count_insn(isa, "v_rcp_f32"), 1, "%s:\n%s", all_chips[c], isa);
		cr_expect_eq(s.transcendental, 1, "%s", all_chips[c]);
		free(isa);
	}
}

Test(gpucost, exp2_is_one_v_exp)
{
	for (int c = 0; c < NCHIPS; c++) {
		char *isa;
		bk_gpucost_stats s = run_one("exp2(NoV)", NULL, NULL, all_chips[c], 0, &isa, NULL);
		cr_expect_eq(count_insn(isa, "v_exp_f32"), 1, "%s:\n%s", all_chips[c], isa);
		cr_expect_eq(s.transcendental, 1, "%s", all_chips[c]);
		cr_expect_eq(s.instructions, 1, "%s: %ld", all_chips[c], s.instructions);
		free(isa);
	}
}

/* The talk's claim: its specular term (V·F, and D·V·F) needs one division,
 * so one v_rcp_f32 and no other transcendental op. */
Test(gpucost, talk_specular_has_one_rcp)
{
	const char *names[] = {"vf_talk_r", "vf_talk_a", "dvf_talk_r"};
	for (int i = 0; i < 3; i++)
		for (int c = 0; c < NCHIPS; c++) {
			const bk_catalog_entry *e = entry(names[i]);
			char *isa;
			bk_gpucost_stats s = run_one(e->form, NULL, e->defaults, all_chips[c], 0, &isa, NULL);
			cr_expect_eq(count_insn(isa, "v_rcp_f32"), 1, "%s on %s", names[i], all_chips[c]);
			cr_expect_eq(s.transcendental, 1, "%s on %s: %ld", names[i], all_chips[c], s.transcendental);
			free(isa);
		}
}

/* The talk's environment BRDF avoids complex ops by design; Karis's
 * EnvBRDFApprox has one exp2. */
Test(gpucost, talk_env_has_no_transcendental_karis_one_exp)
{
	for (int c = 0; c < NCHIPS; c++) {
		const bk_catalog_entry *t = entry("env_talk_r"), *k = entry("env_karis2014");
		char *isa;
		bk_gpucost_stats s = run_one(t->form, t->form_b, t->defaults, all_chips[c], 0, &isa, NULL);
		cr_expect_eq(s.transcendental, 0, "env_talk_r on %s", all_chips[c]);
		free(isa);
		s = run_one(k->form, NULL, k->defaults, all_chips[c], 0, &isa, NULL);
		cr_expect_eq(count_insn(isa, "v_exp_f32"), 1, "env_karis2014 on %s", all_chips[c]);
		cr_expect_eq(s.transcendental, 1, "env_karis2014 on %s", all_chips[c]);
		free(isa);
	}
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
	char *isa;
	int ok;
	run_one("NoV*NoL + f0", NULL, NULL, "navi21", 1, &isa, &ok);
	cr_expect(ok);
	cr_expect(strstr(isa, "_f16"), "%s", isa);
	cr_expect_eq(count_insn(isa, "v_fma_f32") + count_insn(isa, "v_fmac_f32"), 0, "%s", isa);
	free(isa);
	run_one("NoV", NULL, NULL, "polaris10", 1, &isa, &ok);
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
