/*
 * test_timing.c — run time and SPIR-V size of forms (analysis/timing.c).
 *
 * Timings are checked as properties only (finite, positive, min <= median <=
 * max, NaN where nothing is timed): a machine under load may reorder any two
 * forms, so which form is cheaper is asserted on the SPIR-V counts, which are
 * deterministic, never on nanoseconds.
 */
#include "catalog.h"
#include "compare.h"
#include "gpucost.h"

#include <criterion/criterion.h>

#include <dirent.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define GGX "D_ggx(NoH,a)*V_smith_ggx_correlated(NoV,NoL,a)*F_schlick(f0,1,LoH)"
/* pow, exp and exp2 with parameters: libm calls in C, transcendental ops on a GPU */
#define POWY "pow(1 - LoH, p0) * exp2(p1*NoV) + pow(r, 2.5) * exp(-a)"

static void set_row(bk_compare_row *r, const char *name, const char *form, const char *form_b, int np, ...)
{
	memset(r, 0, sizeof *r);
	snprintf(r->name, sizeof r->name, "%s", name);
	snprintf(r->form, sizeof r->form, "%s", form);
	snprintf(r->form_b, sizeof r->form_b, "%s", form_b ? form_b : "");
	va_list ap;
	va_start(ap, np);
	for (int i = 0; i < np; i++)
		r->params[i] = va_arg(ap, double);
	va_end(ap);
	r->nparams = np;
	r->ns = r->ns_min = r->ns_max = -1; /* must be overwritten */
	bk_compare_row_parse(r, NULL, 0); /* the row's IR, as a command makes it (a bad form: none) */
}

static int spirv(const char *text, const double *params)
{
	bk_form_error fe;
	bk_form *f = bk_form_parse(text, &fe);
	cr_assert_not_null(f, "%s: %s", text, fe.message);
	char err[512] = "";
	int k = bk_spirv_count(f, params, err, sizeof err);
	bk_form_free(f);
	cr_assert_geq(k, 0, "bk_spirv_count(%s): %s (Debian package spirv-tools)", text, err);
	return k;
}

Test(timing, rows_timed_and_lut_skipped)
{
	const bk_catalog_entry *env = bk_catalog_find("env_karis2014_split");
	cr_assert_not_null(env);
	bk_compare_row rows[5];
	set_row(&rows[0], "trivial", "NoV", NULL, 0);
	set_row(&rows[1], "LUT 64x64 half", "", NULL, 0);
	set_row(&rows[2], "ggx", GGX, NULL, 0);
	set_row(&rows[3], "pow", POWY, NULL, 2, 5.0, -3.0);
	set_row(&rows[4], "split", env->form, env->form_b, 0); /* A and B, one evaluation */
	rows[4].nparams = env->nparams;
	memcpy(rows[4].params, env->defaults, sizeof rows[4].params);
	char err[512] = "";
	cr_assert_eq(bk_time_rows(rows, 5, 5, err, sizeof err), 0, "%s", err);
	bk_compare_rows_free(rows, 5);
	for (int i = 0; i < 5; i++) {
		const bk_compare_row *r = &rows[i];
		if (i == 1) {
			cr_expect(isnan(r->ns) && isnan(r->ns_min) && isnan(r->ns_max), "LUT row timed");
			continue;
		}
		cr_expect(isfinite(r->ns) && r->ns > 0, "%s: ns %g", r->name, r->ns);
		cr_expect(r->ns_min > 0 && r->ns_min <= r->ns && r->ns <= r->ns_max && isfinite(r->ns_max),
		          "%s: min %g median %g max %g", r->name, r->ns_min, r->ns, r->ns_max);
		cr_expect_lt(r->ns, 1e4, "%s: %g ns per evaluation", r->name, r->ns);
	}
}

/* Which form is costlier, asserted where it is deterministic. */
Test(timing, spirv_orders_forms)
{
	double p[BK_MAX_PARAMS] = {5.0, -3.0};
	int trivial = spirv("NoV", NULL), ggx = spirv(GGX, NULL), powy = spirv(POWY, p);
	cr_expect(trivial >= 0 && trivial <= 2, "NoV: %d instructions net of the baseline", trivial);
	cr_expect_gt(ggx, trivial + 10, "GGX %d vs NoV %d", ggx, trivial);
	cr_expect_gt(powy, trivial + 3, "pow form %d vs NoV %d", powy, trivial);
	cr_expect_eq(spirv(GGX, NULL), ggx, "not deterministic");
	cr_expect_eq(spirv("1", NULL), 0, "a constant costs nothing");
}

/* The SPIR-V counted is the reference front end's: glslang in-process
 * (bk_gpucost_spirv, which timing.c calls) gives the words glslangValidator
 * writes for the same compute shader and target, byte for byte; a shader one
 * constant apart gives other words (the comparison's negative control). */
static const char *const spv_shader =
	"#version 450\nlayout(local_size_x = 64) in;\n"
	"layout(std430, binding = 0) buffer B { float v[]; };\n"
	"float f(float NoV, float r) { return 1.0 / (NoV * (1.0 - r) + r) + exp2(%s * NoV); }\n"
	"void main() { uint i = gl_GlobalInvocationID.x; v[i] = f(v[i], v[i + 1u]); }\n";

Test(timing, in_process_spirv_is_glslangValidators)
{
	char dir[] = "/tmp/bk_spv_XXXXXX", src[64], spv[64], cmd[256], glsl[512], other[512], err[256] = "";
	cr_assert_not_null(mkdtemp(dir));
	snprintf(src, sizeof src, "%s/s.comp", dir);
	snprintf(spv, sizeof spv, "%s/s.spv", dir);
	snprintf(glsl, sizeof glsl, spv_shader, "-9.28");
	snprintf(other, sizeof other, spv_shader, "-9.0");
	FILE *f = fopen(src, "w");
	cr_assert(f && fputs(glsl, f) >= 0 && fclose(f) == 0);
	snprintf(cmd, sizeof cmd, "glslangValidator -V --target-env vulkan1.1 -o '%s' '%s' >/dev/null 2>&1", spv, src);
	int rc = system(cmd);
	static unsigned char ref[1 << 16];
	size_t len = 0;
	if ((f = fopen(spv, "rb"))) {
		len = fread(ref, 1, sizeof ref, f);
		fclose(f);
	}
	unlink(src);
	unlink(spv);
	rmdir(dir);
	cr_assert_eq(rc, 0, "glslangValidator failed or missing (Debian package glslang-tools)");
	size_t n = 0, m = 0;
	unsigned *w = bk_gpucost_spirv(glsl, &n, err, sizeof err), *x = bk_gpucost_spirv(other, &m, err, sizeof err);
	cr_assert(w && x, "%s", err);
	cr_expect(len > 20 && n * sizeof *w == len && memcmp(w, ref, len) == 0,
	          "in-process %zu bytes, glslangValidator %zu: not the same words", n * sizeof *w, len);
	cr_expect(!(m * sizeof *x == len && memcmp(x, ref, len) == 0), "control: another shader gave the same words");
	free(w);
	free(x);
}

Test(timing, errors_are_one_line_messages)
{
	bk_compare_row rows[2];
	char err[512] = "";
	set_row(&rows[0], "good", "NoV", NULL, 0);
	set_row(&rows[1], "bad", "NoV +* 2", NULL, 0);
	/* the one parse says where; a row left without IR is refused, not parsed again */
	cr_assert_eq(bk_compare_row_parse(&rows[1], err, sizeof err), -1);
	cr_expect(strstr(err, "bad: form:1:6:") != NULL, "message: %s", err);
	cr_expect(strchr(err, '\n') == NULL, "message: %s", err);
	cr_expect(rows[1].f[0] == NULL);
	cr_assert_eq(bk_time_rows(rows, 2, 3, err, sizeof err), -1);
	cr_expect(strstr(err, "bad: its form was not parsed") != NULL, "message: %s", err);
	set_row(&rows[1], "params", "NoV*p1", NULL, 1, 2.0);
	cr_assert_eq(bk_time_rows(rows, 2, 3, err, sizeof err), -1);
	cr_expect(strstr(err, "p0..p1") != NULL, "message: %s", err);
	cr_assert_eq(bk_time_rows(rows, 1, 0, err, sizeof err), -1);
	cr_expect(strstr(err, "reps") != NULL, "message: %s", err);
	bk_compare_rows_free(rows, 2);
}

static int dir_empty(const char *path)
{
	DIR *d = opendir(path);
	cr_assert_not_null(d);
	int n = 0;
	for (struct dirent *e; (e = readdir(d));)
		n += strcmp(e->d_name, ".") && strcmp(e->d_name, "..");
	closedir(d);
	return n == 0;
}

/* Each test runs in its own process (Criterion forks), so TMPDIR and PATH
 * changes stay here. */
Test(timing, temporary_files_removed)
{
	char dir[] = "/tmp/bk_test_timing_XXXXXX";
	cr_assert_not_null(mkdtemp(dir));
	setenv("TMPDIR", dir, 1);
	bk_compare_row row;
	set_row(&row, "one", "NoV*NoL", NULL, 0);
	char err[512] = "";
	int rc = bk_time_rows(&row, 1, 1, err, sizeof err);
	int ok1 = dir_empty(dir);
	bk_compare_rows_free(&row, 1);
	set_row(&row, "bad", "NoV*", NULL, 0);
	bk_time_rows(&row, 1, 1, err, sizeof err);
	int ok2 = dir_empty(dir);
	spirv("NoV*NoL", NULL);
	int ok3 = dir_empty(dir);
	rmdir(dir);
	cr_assert_eq(rc, 0, "%s", err);
	cr_expect(ok1 && ok2 && ok3, "files left in %s: after timing %d, after a failure %d, after spirv %d", dir,
	          !ok1, !ok2, !ok3);
}

Test(timing, missing_tools_named)
{
	setenv("PATH", "/nonexistent", 1);
	bk_compare_row row;
	set_row(&row, "one", "NoV", NULL, 0);
	char err[512] = "";
	cr_assert_eq(bk_time_rows(&row, 1, 1, err, sizeof err), -1);
	cr_expect(strstr(err, "cc not found") != NULL, "message: %s", err);
	bk_compare_rows_free(&row, 1);
	bk_form *f = bk_form_parse("NoV", NULL);
	cr_assert_eq(bk_spirv_count(f, NULL, err, sizeof err), -1);
	/* glslang runs in-process; the optimiser is the first tool spawned */
	cr_expect(strstr(err, "spirv-opt not found") && strstr(err, "spirv-tools"), "message: %s", err);
	bk_form_free(f);
}
