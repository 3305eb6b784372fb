/*
 * test_emit.c — code generation (bk_form_emit), judged by the tools that will
 * consume the code, not by golden text:
 *
 *   - the C is compiled by the system compiler (cc -std=c11 -O2 -Wall -Wextra
 *     -Werror -pedantic), run on a grid of inputs and compared with the IR's
 *     own single-precision evaluation (bk_form_eval BK_F32);
 *   - the GLSL (highp and mediump) and HLSL (float and half) are compiled by
 *     glslangValidator, the Khronos reference front end; without it these tests
 *     FAIL (Debian package glslang-tools), they never skip;
 *   - the text is deterministic and its provenance comment carries every item
 *     brdf.h promises, the op counts taken from bk_form_count.
 */
#include "brdf.h"
#include "out.h"

#include <criterion/criterion.h>

#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* ---- files and commands ---------------------------------------------------- */

typedef struct workdir {
	char path[64];
} workdir;

static workdir workdir_new(void)
{
	workdir w;
	snprintf(w.path, sizeof w.path, "/tmp/bk_emit_XXXXXX");
	cr_assert_not_null(mkdtemp(w.path), "mkdtemp failed");
	return w;
}

static void workdir_free(const workdir *w)
{
	char cmd[128];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", w->path); /* mkdtemp's name: no quotes in it */
	if (system(cmd) != 0)
		cr_log_warn("could not remove %s", w->path);
}

static void spit(const char *path, const char *text)
{
	FILE *fp = fopen(path, "w");
	cr_assert_not_null(fp, "cannot write %s", path);
	fputs(text, fp);
	cr_assert_eq(fclose(fp), 0, "cannot write %s", path);
}

static char *slurp(const char *path)
{
	FILE *fp = fopen(path, "r");
	if (!fp)
		return NULL;
	size_t len = 0, cap = 4096;
	char *s = malloc(cap);
	for (size_t k; s && (k = fread(s + len, 1, cap - 1 - len, fp)) > 0;) {
		len += k;
		if (len + 1 == cap)
			s = realloc(s, cap *= 2);
	}
	fclose(fp);
	if (s)
		s[len] = '\0';
	return s;
}

/* Runs a shell command with its output into log; on failure the test fails
 * with the command, the log and the source it was given. */
static void run_or_fail(const char *log, const char *source, const char *fmt, ...)
{
	char cmd[1024];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(cmd, sizeof cmd, fmt, ap);
	va_end(ap);
	char full[1200];
	snprintf(full, sizeof full, "( %s ) > '%s' 2>&1", cmd, log);
	int rc = system(full);
	if (rc == 0)
		return;
	char *out = slurp(log), *src = source ? slurp(source) : NULL;
	cr_assert_fail("command failed (status %d): %s\n--- output ---\n%s\n--- %s ---\n%s", rc, cmd,
	               out ? out : "", source ? source : "", src ? src : "");
}

/* glslangValidator is how the GLSL and HLSL are proven to compile: its absence
 * is a broken environment, not a reason to skip. */
static void need_glslang(void)
{
	if (system("command -v glslangValidator > /dev/null 2>&1") != 0)
		cr_assert_fail("glslangValidator not found on PATH: install the Debian package "
		               "glslang-tools (make deps does); the GLSL/HLSL tests need it");
}

/* ---- forms ----------------------------------------------------------------- */

typedef struct form_case {
	const char *text;
	double params[BK_MAX_PARAMS];
} form_case;

#define GGX "D_ggx(NoH,a) * V_smith_ggx_correlated(NoV,NoL,a) * F_schlick(f0,1,LoH)"
#define TALK_SPEC "r^4 / (4*3.14159265*sq(NoH*NoH*(r^4 - 1) + 1) * LoH*LoH*(r + 0.5))"
#define KITCHEN                                                                          \
	"min(NoV, NoL) + max(NoH, 0.25) * clamp(LoH, 0.1, p0) + saturate(2*r - 0.5)"     \
	" + mix(f0, 1, pow(1 - LoH, 5.5)) + exp2(-r) * log(1 + a) + rsqrt(NoV + 0.01)"   \
	" + rcp(NoL + p1) + abs(NoH - 0.5) + sqrt(a) + exp(-NoV) + log2(1 + NoL)"

/* What the code generator must get right beyond plain arithmetic: negation
 * next to negative literals ("- -" must not become the "--" token), negative
 * parameters, a result that is a leaf, no inputs at all, every opcode, a
 * constant that is finite in double but infinite in float. */
static const form_case c_cases[] = {
	{GGX, {0}},
	{TALK_SPEC, {0}},
	{"1/(LoH*LoH*(r+p0))", {0.5}},
	{KITCHEN, {0.9, 0.25}},
	{"-(NoV) * 2 - -a", {0}},
	{"-NoV*-0.5", {0}},
	{"NoV - -0.5", {0}},
	{"-(-NoV)", {0}},
	{"-p0 * NoV - p0", {-0.5}},
	{"p0 - NoV", {-0.25}},
	{"NoV", {0}},
	{"0.25", {0}},
	{"p2", {1, 2, 0.1}},
	{"1e40 * NoV", {0}},
	{"(r - 0.5) * 1e-30 * 1e-15", {0}},
};

static bk_form *parse_or_fail(const char *text)
{
	bk_form_error err;
	bk_form *f = bk_form_parse(text, &err);
	cr_assert_not_null(f, "parse '%s': column %d: %s", text, err.column, err.message);
	return f;
}

static int count_inputs(const bk_form *f)
{
	int k = 0;
	for (int i = 0; i < BK_IN_COUNT; i++)
		k += bk_form_inputs(f) >> i & 1;
	return k;
}

/* ---- the input grid ---------------------------------------------------------
 * Cosines and f0 in [0, 1] with the ends, r in [0, 1] (a = r*r), from a fixed
 * linear congruential sequence so that every run sees the same samples. */

enum { NSAMPLES = 2000 };

typedef struct grid {
	double v[BK_IN_COUNT][NSAMPLES];
} grid;

static double uniform01(uint64_t *s)
{
	*s = *s * 6364136223846793005u + 1442695040888963407u;
	return (double)(*s >> 11) * 0x1p-53;
}

static void grid_fill(grid *g)
{
	uint64_t s = 12345;
	static const double ends[] = {0, 1, 1e-3, 0.5};
	for (int k = 0; k < NSAMPLES; k++) {
		for (int i = 0; i < BK_IN_COUNT; i++)
			g->v[i][k] = k < 4 ? ends[k] : uniform01(&s);
		g->v[BK_IN_A][k] = g->v[BK_IN_R][k] * g->v[BK_IN_R][k];
	}
}

/* Distance in units in the last place between two floats; 0 when both are
 * NaN or both are the same infinity, "far" when only one is. */
static int64_t ulps(float x, float y)
{
	if (isnan(x) || isnan(y))
		return isnan(x) && isnan(y) ? 0 : INT64_MAX;
	if (x == y)
		return 0;
	if (isinf(x) || isinf(y))
		return INT64_MAX;
	int32_t ix, iy;
	memcpy(&ix, &x, sizeof ix);
	memcpy(&iy, &y, sizeof iy);
	int64_t ox = ix < 0 ? (int64_t)INT32_MIN - ix : ix; /* monotonic in the value */
	int64_t oy = iy < 0 ? (int64_t)INT32_MIN - iy : iy;
	return ox > oy ? ox - oy : oy - ox;
}

/* ---- C: compile, run, compare ------------------------------------------------ */

/* A main() reading "count" then count lines of the form's inputs (in bk_input
 * order, as the signature has them), printing one result a line in hex. */
static void write_c_harness(const char *path, const char *code, int nin)
{
	char head[] = "#include <stdio.h>\n";
	char call[256] = "";
	for (int i = 0; i < nin; i++) {
		size_t k = strlen(call);
		snprintf(call + k, sizeof call - k, "%s(float)v[%d]", i ? ", " : "", i);
	}
	char tail[1024];
	snprintf(tail, sizeof tail,
	         "int main(void)\n{\n\tint n;\n\tdouble v[8];\n"
	         "\tif (scanf(\"%%d\", &n) != 1)\n\t\treturn 1;\n"
	         "\tfor (int k = 0; k < n; k++) {\n"
	         "\t\tfor (int i = 0; i < %d; i++)\n"
	         "\t\t\tif (scanf(\"%%lf\", &v[i]) != 1)\n\t\t\t\treturn 1;\n"
	         "\t\tprintf(\"%%a\\n\", (double)gen(%s));\n\t}\n\treturn 0;\n}\n",
	         nin, call);
	size_t len = strlen(head) + strlen(code) + strlen(tail) + 1;
	char *src = malloc(len);
	cr_assert_not_null(src);
	snprintf(src, len, "%s%s%s", head, code, tail);
	spit(path, src);
	free(src);
}

/* The generated function and bk_form_eval(BK_F32) do the same float operations
 * in the same order — the same templates, MAD rounded twice (-std=c11 turns
 * FMA contraction off), the same libm float functions (tgmath.h picks powf,
 * expf, ... in the kernel) — so they should agree bit for bit. MAX_ULPS = 2
 * leaves room for a compiler that legitimately rewrites a libm call (gcc turns
 * powf(x, 2) into x*x, exactly) or a libm whose float functions are within an
 * ulp but not bit-identical between an inlined and a called version. */
enum { MAX_ULPS = 2 };

static void check_c_case(const form_case *fc, const grid *g)
{
	workdir w = workdir_new();
	bk_form *f = parse_or_fail(fc->text);
	bk_emit_info info = {.name = "gen", .source = "test_emit.c"};
	char *code = bk_form_emit(f, BK_LANG_C, 0, fc->params, &info);
	cr_assert_not_null(code, "emit '%s'", fc->text);

	char src[128], exe[128], in[128], out[128], log[128];
	snprintf(src, sizeof src, "%s/gen.c", w.path);
	snprintf(exe, sizeof exe, "%s/gen", w.path);
	snprintf(in, sizeof in, "%s/in.txt", w.path);
	snprintf(out, sizeof out, "%s/out.txt", w.path);
	snprintf(log, sizeof log, "%s/log.txt", w.path);
	int nin = count_inputs(f);
	write_c_harness(src, code, nin);
	run_or_fail(log, src, "cc -std=c11 -O2 -Wall -Wextra -Werror -pedantic '%s' -o '%s' -lm", src, exe);

	FILE *fp = fopen(in, "w");
	cr_assert_not_null(fp);
	fprintf(fp, "%d\n", NSAMPLES);
	for (int k = 0; k < NSAMPLES; k++) {
		for (int i = 0; i < BK_IN_COUNT; i++)
			if (bk_form_inputs(f) >> i & 1)
				fprintf(fp, "%a ", g->v[i][k]);
		fprintf(fp, "\n");
	}
	fclose(fp);
	run_or_fail(log, NULL, "'%s' < '%s' > '%s'", exe, in, out);

	const double *cols[BK_IN_COUNT];
	for (int i = 0; i < BK_IN_COUNT; i++)
		cols[i] = g->v[i];
	static double want[NSAMPLES];
	cr_assert_eq(bk_form_eval(f, BK_F32, NSAMPLES, cols, fc->params, want), 0);
	char *got = slurp(out), *p = got;
	cr_assert_not_null(got);
	for (int k = 0; k < NSAMPLES; k++) {
		char *end;
		double y = strtod(p, &end);
		cr_assert(end != p, "'%s': the harness printed %d values, want %d", fc->text, k, NSAMPLES);
		p = end;
		int64_t d = ulps((float)y, (float)want[k]);
		cr_assert(d <= MAX_ULPS,
		          "'%s' sample %d (NoV %g NoL %g NoH %g LoH %g r %g f0 %g): generated C %.9g, "
		          "bk_form_eval f32 %.9g, %lld ulps apart\n%s",
		          fc->text, k, g->v[0][k], g->v[1][k], g->v[2][k], g->v[3][k], g->v[4][k],
		          g->v[6][k], y, want[k], (long long)d, code);
	}
	free(got);
	free(code);
	bk_form_free(f);
	workdir_free(&w);
}

static void check_c_range(size_t from, size_t to)
{
	static grid g;
	grid_fill(&g);
	for (size_t i = from; i < to && i < sizeof c_cases / sizeof c_cases[0]; i++)
		check_c_case(&c_cases[i], &g);
}

/* Split in three so that Criterion's workers compile in parallel. */
Test(emit, c_matches_f32_eval_terms) { check_c_range(0, 4); }
Test(emit, c_matches_f32_eval_negation) { check_c_range(4, 10); }
Test(emit, c_matches_f32_eval_leaves_and_specials) { check_c_range(10, 100); }

/* ---- GLSL and HLSL: compile with the reference front end ---------------------- */

/* The shaders: every case's function (gen0, gen1, ...) in one fragment
 * shader whose main calls each and sums them, so that one glslangValidator
 * proves the lot (a start of it is ~190 ms, most of it its built-in symbol
 * tables: 90 starts a run before, 6 now); a case that does not compile fails
 * the run, its log naming the line. */
typedef struct shader_set {
	const form_case *cases;
	size_t n;
	char **code;   /* each case's function, as bk_form_emit wrote it */
	unsigned *ins; /* the inputs each reads (bk_form_inputs) */
	unsigned all;  /* their union */
} shader_set;

/* the sum of every case's call, each input as `pre NAME post` (GLSL) or its
 * HLSL lane */
static void put_calls(bk_strbuf *b, const shader_set *set, const char *pre, const char *post, int hlsl)
{
	static const char *const lane[BK_IN_COUNT] = {"u.x", "u.y", "u.z", "u.w", "v.x", "v.y", "v.z"};
	for (size_t c = 0; c < set->n; c++) {
		bk_sb_put(b, "%sgen%zu(", c ? " + " : "", c);
		for (int i = 0, k = 0; i < BK_IN_COUNT; i++)
			if (set->ins[c] >> i & 1) {
				if (hlsl)
					bk_sb_put(b, "%s%s", k++ ? ", " : "", lane[i]);
				else
					bk_sb_put(b, "%s%s%s%s", k++ ? ", " : "", pre, bk_input_name(i), post);
			}
		bk_sb_put(b, ")");
	}
}

/* GLSL ES 3.00 (highp, mediump): a uniform per input. The float16_t variant:
 * Vulkan GLSL 4.50 with the extension, each input from an interpolant of its
 * own. HLSL: the inputs from two interpolants. */
static char *set_shader(const shader_set *set, bk_lang lang, int half)
{
	bk_strbuf b = {0};
	if (lang == BK_LANG_GLSL && half == BK_EMIT_F16)
		bk_sb_put(&b, "#version 450\n#extension GL_EXT_shader_explicit_arithmetic_types_float16 : require\n");
	else if (lang == BK_LANG_GLSL)
		bk_sb_put(&b, "#version 300 es\nprecision highp float;\n");
	for (size_t c = 0; c < set->n; c++)
		bk_sb_put(&b, "%s", set->code[c]);
	if (lang == BK_LANG_HLSL) {
		bk_sb_put(&b, "float4 main(float4 u : TEXCOORD0, float4 v : TEXCOORD1) : SV_Target\n{\n\treturn float4(");
		put_calls(&b, set, "", "", 1);
		bk_sb_put(&b, ", 0, 0, 1);\n}\n");
		cr_assert(!b.oom);
		return b.s;
	}
	for (int i = 0; i < BK_IN_COUNT; i++)
		if (set->all >> i & 1) {
			if (half == BK_EMIT_F16)
				bk_sb_put(&b, "layout(location = %d) in float u_%s;\n", i, bk_input_name(i));
			else
				bk_sb_put(&b, "uniform highp float u_%s;\n", bk_input_name(i));
		}
	bk_sb_put(&b, "%sout vec4 o;\nvoid main() { o = vec4(", half == BK_EMIT_F16 ? "layout(location = 0) " : "");
	if (half == BK_EMIT_F16)
		put_calls(&b, set, "float16_t(u_", ")", 0);
	else
		put_calls(&b, set, "u_", "", 0);
	bk_sb_put(&b, "); }\n");
	cr_assert(!b.oom);
	return b.s;
}

static void check_shader_set(const form_case *cases, size_t n, bk_lang lang, int half, const workdir *w)
{
	shader_set set = {cases, n, calloc(n, sizeof(char *)), calloc(n, sizeof(unsigned)), 0};
	cr_assert(set.code && set.ins);
	for (size_t c = 0; c < n; c++) {
		bk_form *f = parse_or_fail(cases[c].text);
		char name[32];
		snprintf(name, sizeof name, "gen%zu", c);
		bk_emit_info info = {.name = name, .source = "test_emit.c */ /* not a comment end"};
		set.code[c] = bk_form_emit(f, lang, half, cases[c].params, &info);
		cr_assert_not_null(set.code[c], "emit '%s'", cases[c].text);
		set.ins[c] = bk_form_inputs(f);
		set.all |= set.ins[c];
		bk_form_free(f);
	}
	char *shader = set_shader(&set, lang, half);
	char src[128], spv[128], log[128];
	snprintf(src, sizeof src, "%s/gen.%s", w->path, lang == BK_LANG_GLSL ? "frag" : "hlsl");
	snprintf(spv, sizeof spv, "%s/gen.spv", w->path);
	snprintf(log, sizeof log, "%s/log.txt", w->path);
	spit(src, shader);
	if (lang == BK_LANG_GLSL && half == BK_EMIT_F16) /* float16_t is Vulkan GLSL's: compiled to SPIR-V */
		run_or_fail(log, src, "glslangValidator -V -o '%s' '%s'", spv, src);
	else if (lang == BK_LANG_GLSL)
		run_or_fail(log, src, "glslangValidator '%s'", src);
	else /* glslang checks HLSL only on the way to SPIR-V */
		run_or_fail(log, src, "glslangValidator -V -D -S frag -e main -o '%s' '%s'", spv, src);
	free(shader);
	for (size_t c = 0; c < n; c++)
		free(set.code[c]);
	free(set.code);
	free(set.ins);
}

static void check_shaders(bk_lang lang)
{
	need_glslang();
	workdir w = workdir_new();
	for (int half = BK_EMIT_SINGLE; half <= BK_EMIT_F16; half++)
		check_shader_set(c_cases, sizeof c_cases / sizeof c_cases[0], lang, half, &w);
	workdir_free(&w);
}

Test(emit, glsl_highp_mediump_and_float16_compile) { check_shaders(BK_LANG_GLSL); }
Test(emit, hlsl_float_min16float_and_half_compile) { check_shaders(BK_LANG_HLSL); }

/* A NaN parameter has no literal in any language; its spelling must compile. */
Test(emit, nan_parameter_compiles)
{
	form_case fc = {"NoV + p0", {NAN}};
	need_glslang();
	workdir w = workdir_new();
	for (int half = BK_EMIT_SINGLE; half <= BK_EMIT_F16; half++) {
		check_shader_set(&fc, 1, BK_LANG_GLSL, half, &w);
		check_shader_set(&fc, 1, BK_LANG_HLSL, half, &w);
	}
	workdir_free(&w);
	static grid g;
	grid_fill(&g);
	check_c_case(&fc, &g);
}

/* ---- the text itself ----------------------------------------------------------- */

static int occurrences(const char *s, const char *what)
{
	int n = 0;
	for (const char *p = s; (p = strstr(p, what)); p += strlen(what))
		n++;
	return n;
}

static void assert_contains(const char *s, const char *what)
{
	cr_assert_not_null(strstr(s, what), "'%s' missing from:\n%s", what, s);
}

Test(emit, deterministic)
{
	for (bk_lang lang = BK_LANG_C; lang <= BK_LANG_HLSL; lang++) {
		bk_form *f = parse_or_fail(KITCHEN), *g = parse_or_fail(KITCHEN);
		double p[] = {0.9, 0.25};
		char *x = bk_form_emit(f, lang, 1, p, NULL), *y = bk_form_emit(f, lang, 1, p, NULL);
		char *z = bk_form_emit(g, lang, 1, p, NULL); /* a second parse of the same text */
		cr_assert_not_null(x);
		cr_assert_str_eq(x, y);
		cr_assert_str_eq(x, z);
		free(x), free(y), free(z);
		bk_form_free(f), bk_form_free(g);
	}
}

Test(emit, provenance_comment)
{
	bk_form *f = parse_or_fail("1/(LoH*LoH*(r+p0))");
	double p[] = {0.123456789012};
	bk_emit_info info = {"spec_vf", "Optimizing PBR for Mobile (2015)", "r perceptual; V F combined",
	                     "LoH in [0.1, 1], r in [0.05, 1]", "max rel 1.5%",
	                     "brdfkit fit --form '1/(LoH*LoH*(r+p0))'"};
	for (bk_lang lang = BK_LANG_C; lang <= BK_LANG_HLSL; lang++) {
		char *s = bk_form_emit(f, lang, 0, p, &info);
		cr_assert_not_null(s);
		cr_assert_eq(strncmp(s, "/*\n", 3), 0, "the comment opens the text");
		assert_contains(s, "Generated by brdfkit " BK_VERSION);
		assert_contains(s, "DO NOT EDIT");
		assert_contains(s, "command: brdfkit fit --form '1/(LoH*LoH*(r+p0))'");
		assert_contains(s, "form: 1/(LoH*LoH*(r+p0))");
		assert_contains(s, "source: Optimizing PBR for Mobile (2015)");
		assert_contains(s, "conventions: r perceptual; V F combined");
		assert_contains(s, "fitted domain: LoH in [0.1, 1], r in [0.05, 1]");
		assert_contains(s, "fitted error: max rel 1.5%");
		assert_contains(s, "p0 = 0.123456789");
		assert_contains(s, "spec_vf(");
		/* The counts are bk_form_count's, every non-zero class and the total. */
		bk_ops ops;
		bk_form_count(f, &ops);
		char line[160];
		for (int k = 1; k < BK_K_COUNT; k++) {
			snprintf(line, sizeof line, " *   %s %d\n", bk_opclass_name(k), ops.n[k]);
			cr_assert_eq(strstr(s, line) != NULL, ops.n[k] != 0, "class %s:\n%s", bk_opclass_name(k), s);
		}
		snprintf(line, sizeof line, "simple %d, complex %d, cost %g (simple = %g, complex = %g)",
		         ops.simple, ops.complex, bk_ops_cost(&ops, BK_COST_SIMPLE, BK_COST_COMPLEX),
		         BK_COST_SIMPLE, BK_COST_COMPLEX);
		assert_contains(s, line);
		/* The talk's counting: add, two multiplies, one division. */
		assert_contains(s, "simple 3, complex 1, cost 7 (simple = 1, complex = 4)");
		free(s);
	}
	bk_form_free(f);
}

Test(emit, unknown_provenance_said_so)
{
	bk_form *f = parse_or_fail("NoV*NoL");
	char *s = bk_form_emit(f, BK_LANG_GLSL, 1, NULL, NULL);
	cr_assert_not_null(s);
	assert_contains(s, "fitted domain: not fitted");
	assert_contains(s, "fitted error: unknown");
	assert_contains(s, "parameters: none");
	assert_contains(s, "mediump float brdfkit_form(mediump float NoV, mediump float NoL)");
	cr_assert_null(strstr(s, "command:"), "no command line was given");
	free(s);
	bk_form_free(f);
}

/* Caller text cannot end the comment early or open a nested one. */
Test(emit, comment_cannot_be_closed_by_caller_text)
{
	bk_form *f = parse_or_fail("NoV");
	bk_emit_info info = {.source = "a */ b /* c */*/", .command = "x\n*/ int evil;", .error = "*/"};
	char *s = bk_form_emit(f, BK_LANG_C, 0, NULL, &info);
	cr_assert_not_null(s);
	cr_assert_eq(occurrences(s, "*/"), 1, "one comment end only:\n%s", s);
	cr_assert_eq(occurrences(s, "/*"), 1, "one comment start only:\n%s", s);
	free(s);
	bk_form_free(f);
}

/* Only the inputs read, in the fixed order NoV NoL NoH LoH r a f0, whatever
 * order the form mentions them in. */
Test(emit, signature_lists_inputs_read_in_fixed_order)
{
	bk_form *f = parse_or_fail("f0*LoH + r*NoV");
	char *c = bk_form_emit(f, BK_LANG_C, 0, NULL, NULL);
	char *h = bk_form_emit(f, BK_LANG_HLSL, BK_EMIT_F16, NULL, NULL);
	char *m = bk_form_emit(f, BK_LANG_HLSL, BK_EMIT_RELAXED, NULL, NULL);
	cr_assert_not_null(c);
	cr_assert_not_null(h);
	cr_assert_not_null(m);
	assert_contains(c, "static inline float brdfkit_form(float NoV, float LoH, float r, float f0)\n");
	assert_contains(h, "half brdfkit_form(half NoV, half LoH, half r, half f0)\n");
	assert_contains(m, "min16float brdfkit_form(min16float NoV, min16float LoH, min16float r, min16float f0)\n");
	free(c), free(h), free(m);
	bk_form_free(f);
}

Test(emit, parameters_required)
{
	bk_form *f = parse_or_fail("NoV*p1");
	cr_assert_null(bk_form_emit(f, BK_LANG_C, 0, NULL, NULL));
	double p[] = {7, 2.5};
	char *s = bk_form_emit(f, BK_LANG_C, 0, p, NULL);
	cr_assert_not_null(s);
	assert_contains(s, "NoV * 2.5f"); /* the value baked in as a float literal */
	free(s);
	bk_form_free(f);
}

/* ---- mix: the code computes what the IR evaluates ------------------------------
 * GLSL's mix and HLSL's lerp are defined as x(1 - t) + y t; the IR evaluates
 * x + (y - x) t (ir_ops.h: why). The two differ in half: found below by a
 * search over half numbers, each formula computed operation by operation with
 * the half module's rounding rule. The IR's f16 must be the second, and the
 * code must spell the second out rather than call mix()/lerp(), whose formula
 * a compiler chooses. */

static double h16(double x) { return bk_half_round(x); }
static double mix_spelled16(double x, double y, double t) { return h16(x + h16(h16(y - x) * t)); }
static double mix_defined16(double x, double y, double t) { return h16(h16(x * h16(1 - t)) + h16(y * t)); }
/* the spelled-out formula's mad fused, as a driver may (one rounding) */
static double mix_fused16(double x, double y, double t) { return h16(h16(y - x) * t + x); }
/* What BK_F16 returns for a form a driver may fuse (brdf/ir_eval.c): of the
 * two orders, NaN over inf over a number, else the farther from the exact. */
static double worse16(double u, double w, double exact)
{
	if (isnan(u) || isnan(w))
		return NAN;
	if (isinf(u) || isinf(w))
		return isinf(u) ? u : w;
	return fabs(w - exact) > fabs(u - exact) ? w : u;
}

static int same_value(double a, double b) { return (isnan(a) && isnan(b)) || a == b; }

static double ir_mix16(const bk_form *f, double x, double y, double t)
{
	double in[BK_IN_COUNT] = {0}, v = 0;
	const double *ptr[BK_IN_COUNT];
	in[BK_IN_NOV] = x, in[BK_IN_NOL] = y, in[BK_IN_LOH] = t;
	for (int i = 0; i < BK_IN_COUNT; i++)
		ptr[i] = &in[i];
	cr_assert_eq(bk_form_eval(f, BK_F16, 1, ptr, NULL, &v), 0);
	return v;
}

Test(emit, mix_in_half_is_the_spelled_out_formula)
{
	static const double xs[] = {-65504, -40000, -1000, -3.5, -1, -0.1, 0, 0.3, 1, 2.5, 1000, 40000, 65504};
	static const double ts[] = {0, 0.1, 0.3, 0.5, 0.7, 0.9, 1, 1.5, -0.5};
	bk_form *f = parse_or_fail("mix(NoV, NoL, LoH)");
	double worst_rel = 0;
	int finite_vs_not = 0, checked = 0, fused_moves = 0;
	for (size_t i = 0; i < sizeof xs / sizeof xs[0]; i++)
		for (size_t j = 0; j < sizeof xs / sizeof xs[0]; j++)
			for (size_t k = 0; k < sizeof ts / sizeof ts[0]; k++) {
				double x = h16(xs[i]), y = h16(xs[j]), t = h16(ts[k]);
				double want = mix_spelled16(x, y, t), other = mix_defined16(x, y, t);
				double kept = worse16(want, mix_fused16(x, y, t), x + (y - x) * t);
				double got = ir_mix16(f, x, y, t);
				cr_assert(same_value(got, kept), "mix(%g, %g, %g) in half: IR %g, x + (y - x) t step by step %g, "
				          "fused %g", x, y, t, got, want, mix_fused16(x, y, t));
				fused_moves += !same_value(kept, want);
				checked++;
				if (isfinite(want) != isfinite(other))
					finite_vs_not++;
				else if (isfinite(want) && other != 0)
					worst_rel = fmax(worst_rel, fabs(want - other) / fabs(other));
			}
	/* The inputs discriminate: where x + (y - x) t overflows (y - x past
	 * 65504) the defined formula is a number, and finite results differ too. */
	cr_assert_gt(finite_vs_not, 0, "no input where one formula is finite and the other not");
	cr_assert_gt(worst_rel, 0.01, "the formulas never differ by 1 %% in half (largest %g)", worst_rel);
	cr_assert_eq(checked, 13 * 13 * 9);
	/* and the fused order is worse at some of them: the IR keeps it there */
	cr_assert_gt(fused_moves, 0, "the fused mad is never the worse order");
	/* e.g. mix(-40000, 40000, 0.5): y - x = 80000 is inf in half, x(1-t) + yt = 0 */
	cr_assert(isinf(mix_spelled16(-40000, 40000, 0.5)) && mix_defined16(-40000, 40000, 0.5) == 0);
	bk_form_free(f);
}

/* bk_form_eval_half_vs: per sample the order of the mad farther from a
 * target y, computed here step by step with the half rounding rule (mad
 * rounded twice: h16(h16(a b) + c); fused: h16(a b + c)). A target placed
 * between the two orders' values near the unfused one picks the fused, where
 * BK_F16 (farther from the form's own f64 value) may pick the other: the
 * control that the choice is the target's. */
static double mad_unfused16(double a, double b, double c) { return h16(h16(a * b) + c); }
static double mad_fused16(double a, double b, double c) { return h16(a * b + c); }

Test(emit, half_vs_target_keeps_the_order_farther_from_the_target)
{
	bk_form *f = parse_or_fail("NoV*NoL + LoH");
	enum { N = 4096 };
	static double x[N], y[N], z[N], target[N], got[N], own[N];
	const double *ptr[BK_IN_COUNT] = {0};
	ptr[BK_IN_NOV] = x, ptr[BK_IN_NOL] = y, ptr[BK_IN_LOH] = z;
	unsigned seed = 12345;
	for (int k = 0; k < N; k++) {
		seed = seed * 1103515245u + 12345u;
		x[k] = h16(1 + (seed >> 8 & 1023) / 1024.0);
		seed = seed * 1103515245u + 12345u;
		y[k] = h16(1 + (seed >> 8 & 1023) / 1024.0);
		z[k] = h16(-x[k] * y[k] + (seed >> 20 & 7) / 4096.0); /* cancels: the orders differ */
		double u = mad_unfused16(x[k], y[k], z[k]), w = mad_fused16(x[k], y[k], z[k]);
		target[k] = k % 2 ? u + (w - u) * 0.25 : w + (u - w) * 0.25; /* nearer one order, in turn */
	}
	cr_assert_eq(bk_form_eval_half_vs(f, N, ptr, NULL, target, got), 0);
	cr_assert_eq(bk_form_eval(f, BK_F16, N, ptr, NULL, own), 0);
	int differ = 0, picks_other = 0;
	for (int k = 0; k < N; k++) {
		double u = mad_unfused16(x[k], y[k], z[k]), w = mad_fused16(x[k], y[k], z[k]);
		double want = fabs(w - target[k]) > fabs(u - target[k]) ? w : u;
		cr_assert_eq(got[k], want, "sample %d: %g*%g + %g: got %g, unfused %g, fused %g, target %g", k, x[k], y[k],
		             z[k], got[k], u, w, target[k]);
		differ += u != w;
		picks_other += own[k] != got[k];
	}
	cr_assert_gt(differ, N / 8, "the two orders rarely differ (%d of %d): the test proves little", differ, N);
	cr_assert_gt(picks_other, 0, "BK_F16 (against the form's own value) always picks as the target does");
	bk_form_free(f);
}

/* The text: no mix()/lerp() call in any language, the IR's formula instead;
 * and the mediump GLSL compiled by the reference front end has no FMix. */
Test(emit, mix_is_spelled_out_in_every_language)
{
	bk_form *f = parse_or_fail("mix(NoV, NoL, LoH)");
	for (bk_lang lang = BK_LANG_C; lang <= BK_LANG_HLSL; lang++)
		for (int half = 0; half <= (lang != BK_LANG_C); half++) {
			char *s = bk_form_emit(f, lang, half, NULL, NULL);
			cr_assert_not_null(s);
			const char *body = strstr(s, "*/");
			cr_assert_not_null(body);
			cr_assert_null(strstr(body, "mix("), "mix() called:\n%s", s);
			cr_assert_null(strstr(body, "lerp("), "lerp() called:\n%s", s);
			assert_contains(body, " = NoV + (NoL - NoV) * LoH;");
			free(s);
		}
	need_glslang();
	workdir w = workdir_new();
	bk_emit_info info = {.name = "gen"};
	char *code = bk_form_emit(f, BK_LANG_GLSL, 1, NULL, &info);
	/* SPIR-V from ES needs 310 and a uniform block */
	size_t len = strlen(code) + 512;
	char *shader = malloc(len);
	cr_assert_not_null(shader);
	snprintf(shader, len,
	         "#version 310 es\nprecision highp float;\n%s"
	         "layout(std140, binding = 0) uniform U { highp float u_NoV, u_NoL, u_LoH; };\n"
	         "layout(location = 0) out vec4 o;\nvoid main() { o = vec4(gen(u_NoV, u_NoL, u_LoH)); }\n",
	         code);
	char src[128], spv[128], log[128], dis[128];
	snprintf(src, sizeof src, "%s/gen.frag", w.path);
	snprintf(spv, sizeof spv, "%s/gen.spv", w.path);
	snprintf(log, sizeof log, "%s/log.txt", w.path);
	snprintf(dis, sizeof dis, "%s/gen.spvasm", w.path);
	spit(src, shader);
	run_or_fail(log, src, "glslangValidator -V -o '%s' '%s' && spirv-dis -o '%s' '%s'", spv, src, dis, spv);
	char *asm_text = slurp(dis);
	cr_assert_not_null(asm_text);
	cr_assert_null(strstr(asm_text, "FMix"), "the SPIR-V calls FMix:\n%s", asm_text);
	assert_contains(asm_text, "OpFSub");
	assert_contains(asm_text, "OpFMul");
	assert_contains(asm_text, "OpFAdd");
	free(asm_text);
	free(shader);
	free(code);
	workdir_free(&w);
	bk_form_free(f);
}

/* ---- names: every one <math.h> gives a meaning is refused in C ------------------
 * Derived from the system compiler, not from the table under test: the macros
 * <math.h> defines and the functions it declares with glibc's widest feature
 * set (_GNU_SOURCE), leading underscores aside (C refuses every _name). */

static int scan_names(const char *cmd, int macros, int *checked)
{
	FILE *p = popen(cmd, "r");
	cr_assert_not_null(p, "%s", cmd);
	char line[4096];
	int refused = 0;
	while (fgets(line, sizeof line, p)) {
		const char *s = line;
		if (macros) { /* "#define NAME ..." or "#define NAME(args) ..." */
			if (strncmp(s, "#define ", 8))
				continue;
			s += 8;
		}
		for (; *s; s++) {
			if (!((*s >= 'A' && *s <= 'Z') || (*s >= 'a' && *s <= 'z') || *s == '_') ||
			    (s > line && (s[-1] == '_' || (s[-1] >= '0' && s[-1] <= '9') || (s[-1] >= 'A' && s[-1] <= 'Z') ||
			                  (s[-1] >= 'a' && s[-1] <= 'z'))))
				continue;
			size_t n = strspn(s, "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_");
			const char *after = s + n;
			while (*after == ' ')
				after++;
			if ((macros || *after == '(') && s[0] != '_' && n < 64) {
				char name[64];
				memcpy(name, s, n);
				name[n] = '\0';
				(*checked)++;
				refused += bk_lang_reserved(BK_LANG_C, name);
				cr_assert_eq(bk_lang_reserved(BK_LANG_C, name), 1, "<math.h> name '%s' accepted", name);
			}
			if (macros)
				break;
			s += n - 1;
		}
	}
	cr_assert_eq(pclose(p), 0, "%s", cmd);
	return refused;
}

Test(emit, every_math_h_name_is_refused_in_c)
{
	int checked = 0;
	scan_names("echo '#include <math.h>' | cc -E -dM -D_GNU_SOURCE -x c -", 1, &checked);
	int macros = checked;
	scan_names("echo '#include <math.h>' | cc -E -P -D_GNU_SOURCE -x c -", 0, &checked);
	/* the header was read: its macros and some 800 declarations (glibc 2.36) */
	cr_assert_gt(macros, 100);
	cr_assert_gt(checked - macros, 500);
	/* negative control: a name no header gives is accepted */
	cr_assert_eq(bk_lang_reserved(BK_LANG_C, "D_ggx_fit"), 0);
}

/* ---- clamp: defined in every language where the IR is ---------------------------
 * GLSL and HLSL leave clamp(x, lo, hi) undefined for lo > hi; the IR (and C's
 * fminf(fmaxf())) give hi. clamp() only with fixed bounds in order. */

static char *emit_text(const char *text, bk_lang lang, const double *params)
{
	bk_form *f = parse_or_fail(text);
	char *s = bk_form_emit(f, lang, 0, params, NULL);
	cr_assert_not_null(s);
	bk_form_free(f);
	return s;
}

Test(emit, clamp_is_called_only_with_fixed_bounds_in_order)
{
	static const double p_ordered[] = {0.2, 0.9}, p_reversed[] = {0.9, 0.2};
	for (bk_lang lang = BK_LANG_GLSL; lang <= BK_LANG_HLSL; lang++) {
		char *s = emit_text("clamp(NoV, 0.1, 1)", lang, NULL);
		assert_contains(s, "= clamp(NoV, 0.1, 1.0);");
		free(s);
		s = emit_text("clamp(NoV, p0, p1)", lang, p_ordered);
		assert_contains(s, "= clamp(NoV, 0.2, 0.9);");
		free(s);
		s = emit_text("clamp(NoV, p0, p1)", lang, p_reversed);
		assert_contains(s, "= min(max(NoV, 0.9), 0.2);");
		free(s);
		s = emit_text("clamp(NoV, NoL, 1)", lang, NULL);
		assert_contains(s, "= min(max(NoV, NoL), 1.0);");
		free(s);
	}
	char *s = emit_text("clamp(NoV, NoL, 1)", BK_LANG_C, NULL);
	assert_contains(s, "= fminf(fmaxf(NoV, NoL), 1.0f);");
	free(s);
	/* counted as what runs: one clamp, or a max and a min */
	bk_ops o;
	bk_form *f = parse_or_fail("clamp(NoV, 0.1, 1)");
	bk_form_count(f, &o);
	cr_assert_eq(o.n[BK_K_MINMAX], 1);
	bk_form_free(f);
	f = parse_or_fail("clamp(NoV, NoL, 1)");
	bk_form_count(f, &o);
	cr_assert_eq(o.n[BK_K_MINMAX], 2);
	/* and said: a fixed pair out of order is hi everywhere */
	char what[96] = "";
	cr_assert_eq(bk_form_clamp_reversed(f, NULL, what, sizeof what), 0);
	bk_form_free(f);
	f = parse_or_fail("clamp(NoV, 1, 0) + clamp(NoL, p0, p1)");
	cr_assert_eq(bk_form_clamp_reversed(f, p_reversed, what, sizeof what), 2);
	cr_assert_str_eq(what, "clamp(x, 1, 0)");
	cr_assert_eq(bk_form_clamp_reversed(f, p_ordered, what, sizeof what), 1);
	bk_form_free(f);
}

/* ---- constants a precision cannot hold -------------------------------------------- */

static void const_range(const char *text, bk_precision prec, int want, const char *msg)
{
	bk_form *f = parse_or_fail(text);
	char what[200] = "";
	cr_assert_eq(bk_form_const_range(f, NULL, prec, what, sizeof what), want, "%s: %s", text, what);
	if (msg)
		cr_assert_str_eq(what, msg, "%s", text);
	bk_form_free(f);
}

Test(emit, constants_out_of_the_precisions_range)
{
	/* 127.99 is 128 in half, and 2^128 is past half's (and float's) range */
	const_range("exp2(127.99)*NoV", BK_F16, 1, "exp2(128) is +inf in half precision");
	const_range("exp2(127.99)*NoV", BK_F32, 0, NULL); /* 3.3e38 < FLT_MAX */
	const_range("1e-46*NoV", BK_F32, 1, "the constant 1e-46 is 0 in single precision");
	const_range("1e-40*NoV", BK_F32, 1, "the constant 1e-40 is subnormal (0 where GPUs flush) in single precision");
	const_range("70000*NoV", BK_F16, 1, "the constant 70000 is +inf in half precision");
	const_range("1e-5*NoV + 1e-6", BK_F16, 2, "the constant 1e-05 is subnormal (0 where GPUs flush) in half precision");
	/* negative controls: normal numbers in range, and 0 itself */
	const_range("0.5*NoV + exp2(15) + 0*NoL", BK_F16, 0, NULL);
	const_range("1e-30*NoV + 1e38", BK_F32, 0, NULL);
}

/* ---- a front member's style: one signature, named constants, the pair's wrapper ----
 * (bk_emit_style; tests/cli_paste.sh compiles and runs what codegen writes) */
Test(emit, member_style_signature_and_named_constants)
{
	bk_form *f = parse_or_fail("p0*a*LoH + p1*f0");
	double p[2] = {1.5, 0.25};
	bk_emit_info info = {.name = "gen"};
	bk_emit_style st = {1u << BK_IN_LOH | 1u << BK_IN_R | 1u << BK_IN_F0 | 1u << BK_IN_NOV, 1};
	char *c = bk_form_emit_styled(f, BK_LANG_C, 0, p, &info, &st);
	cr_assert_not_null(c);
	assert_contains(c, "static inline float gen(float NoV, float LoH, float r, float f0)\n{\n"
	                   "\tfloat a = r * r; /* alpha from the signature's r");
	assert_contains(c, "\t(void)NoV;\n\tconst float gen_p0 = 1.5f;\n\tconst float gen_p1 = 0.25f;\n");
	cr_assert_null(strstr(c, "(void)r;"), "r is read (for a):\n%s", c);
	cr_assert_null(strstr(c, " 1.5f *"), "a parameter written as a literal:\n%s", c);
	free(c);
	/* the plain function: the inputs f reads, literals (the control) */
	c = bk_form_emit(f, BK_LANG_C, 0, p, &info);
	assert_contains(c, "static inline float gen(float LoH, float a, float f0)");
	cr_assert_null(strstr(c, "gen_p0"), "%s", c);
	free(c);
	/* an input neither taken nor computed: refused */
	bk_emit_style narrow = {1u << BK_IN_LOH | 1u << BK_IN_F0, 1};
	cr_assert_null(bk_form_emit_styled(f, BK_LANG_C, 0, p, &info, &narrow));
	bk_form_free(f);
}

Test(emit, member_style_pair_wrapper)
{
	bk_form *fa = parse_or_fail("p0*NoV"), *fb = parse_or_fail("p1*a");
	double p[2] = {0.5, 2};
	bk_emit_info info = {.name = "env"};
	bk_emit_style st = {1u << BK_IN_NOV | 1u << BK_IN_R, 1};
	static const struct { bk_lang lang; int half; const char *sig, *body; } want[] = {
		{BK_LANG_C, 0, "static inline void env(float NoV, float r, float *A, float *B)\n",
		 "\t*A = env_A(NoV, r);\n\t*B = env_B(NoV, r);\n"},
		{BK_LANG_GLSL, 0, "highp vec2 env(highp float NoV, highp float r)\n", "\treturn vec2(env_A(NoV, r), env_B(NoV, r));\n"},
		{BK_LANG_GLSL, 1, "mediump vec2 env(mediump float NoV, mediump float r)\n", "\treturn vec2(env_A(NoV, r), "},
		{BK_LANG_HLSL, 0, "float2 env(float NoV, float r)\n", "\treturn float2(env_A(NoV, r), env_B(NoV, r));\n"},
	};
	for (size_t k = 0; k < sizeof want / sizeof want[0]; k++) {
		char *s = bk_form_emit_pair(fa, fb, want[k].lang, want[k].half, p, &info, &st);
		cr_assert_not_null(s);
		assert_contains(s, want[k].sig);
		assert_contains(s, want[k].body);
		/* each part names only the parameters it reads: B reads p1 */
		cr_assert_null(strstr(s, "env_B_p0"), "%s", s);
		assert_contains(s, "env_B_p1 = 2");
		free(s);
	}
	bk_form_free(fa);
	bk_form_free(fb);
}

/* Under a half precision every constant is the binary16 value the f16
 * evaluator computes with (bk_half_round of its float), written so that it
 * reads back exactly: p0 = 0.3 is 0.300048828125 (= 1229/4096) and 0.1 is
 * 0.0999755859375 (= 1638/16384) in C, GLSL and HLSL alike. Control: the
 * single-precision text keeps 0.3, which binary16 cannot hold. */
Test(emit, half_constants_on_the_binary16_grid)
{
	bk_form *f = parse_or_fail("NoV*p0 + 0.1");
	double p[] = {0.3};
	cr_assert_eq(bk_half_round(0.3), 1229.0 / 4096);
	cr_assert_eq(bk_half_round(0.1), 1638.0 / 16384);
	for (bk_lang lang = BK_LANG_C; lang <= BK_LANG_HLSL; lang++)
		for (int half = BK_EMIT_RELAXED; half <= BK_EMIT_F16; half++) {
			char *s = bk_form_emit(f, lang, half, p, NULL);
			cr_assert_not_null(s);
			const char *body = strstr(s, " */\n");
			cr_assert_not_null(body);
			assert_contains(body, "0.300048828125");
			assert_contains(body, "0.0999755859375");
			cr_assert_null(strstr(body, "0.3f"), "%s", s);
			free(s);
		}
	char *s = bk_form_emit(f, BK_LANG_GLSL, BK_EMIT_SINGLE, p, NULL);
	assert_contains(strstr(s, " */\n"), "NoV * 0.3 + 0.1;");
	cr_assert_neq(bk_half_round(0.3), 0.3);
	free(s);
	s = bk_form_emit(f, BK_LANG_GLSL, 3, p, NULL); /* no such precision */
	cr_assert_null(s);
	bk_form_free(f);
}
