/*
 * msl.c — a form's Metal function through SPIRV-Cross (msl.h).
 */
#include "msl.h"
#include "gpucost.h"
#include "out.h"

#include <spirv_cross/spirv_cross_c.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Words Metal takes that GLSL leaves free (bk_msl_reserved). */
static const char *const msl_words[] = {
	/* C++14 keywords and alternative tokens GLSL does not reserve */
	"alignas", "alignof", "and", "and_eq", "asm", "auto", "bitand", "bitor", "catch", "char16_t", "char32_t",
	"compl", "const_cast", "constexpr", "decltype", "delete", "dynamic_cast", "explicit", "export", "extern",
	"false", "friend", "goto", "mutable", "new", "noexcept", "not", "not_eq", "nullptr", "operator", "or", "or_eq",
	"private", "protected", "public", "register", "reinterpret_cast", "signed", "sizeof", "static_assert",
	"static_cast", "template", "this", "thread_local", "throw", "true", "try", "typedef", "typeid", "typename",
	"union", "unsigned", "using", "virtual", "wchar_t", "xor", "xor_eq", "namespace", "class", "enum", "static",
	"inline", "volatile", "char", "short", "long", "size_t", "ptrdiff_t",
	/* Metal: address spaces, function and argument qualifiers, types */
	"device", "constant", "thread", "threadgroup", "threadgroup_imageblock", "ray_data", "object_data", "kernel",
	"vertex", "fragment", "visible", "stitchable", "intersection", "mesh", "object", "packed", "uchar", "ushort",
	"ulong", "half", "bfloat", "texture1d", "texture2d", "texture3d", "texturecube", "sampler", "array", "atomic",
	"metal", "fast", "precise", "simd", "uniform", "main0", /* SPIRV-Cross's name for the entry point */
	/* <metal_stdlib> functions a translation may call */
	"rsqrt", "saturate", "as_type", "select", "fmin", "fmax", "fmin3", "fmax3", "median3", "fdim", "fmod",
	"copysign", "powr", "rint", "trunc", "exp10", "log10", "divide", "sincos", "cospi", "sinpi", "tanpi",
	"isordered", "isunordered", "signbit", "ctz", "clz", "popcount", "rotate", "madhi", "mulhi", "addsat",
	"subsat", "absdiff", "extract_bits", "insert_bits", "reverse_bits", "min3", "max3",
};

int bk_msl_reserved(const char *name)
{
	for (size_t i = 0; i < sizeof msl_words / sizeof msl_words[0]; i++)
		if (!strcmp(name, msl_words[i]))
			return 1;
	/* the vector and matrix types: bool2, half4, float3x3, ushort2 ... */
	static const char *const scalar[] = {"bool", "char", "uchar", "short", "ushort", "int", "uint", "long", "ulong",
	                                     "half", "float", "bfloat", "packed_half", "packed_float", "packed_int",
	                                     "packed_uint", "packed_short", "packed_ushort", "packed_char",
	                                     "packed_uchar"};
	for (size_t i = 0; i < sizeof scalar / sizeof scalar[0]; i++) {
		size_t k = strlen(scalar[i]);
		const char *t = name + k;
		if (strncmp(name, scalar[i], k) || t[0] < '2' || t[0] > '4')
			continue;
		if (!t[1] || (t[1] == 'x' && t[2] >= '2' && t[2] <= '4' && !t[3]))
			return 1;
	}
	return 0;
}

/* The compute shader that keeps the function alive: each input read from
 * slot (its bk_input) of one buffer, the result stored to slot 15, so
 * nothing folds away and the function keeps its parameters. */
static char *wrapper(const char *fn, const char *name, unsigned inputs, int half)
{
	const char *T = half ? "float16_t" : "float";
	bk_strbuf b = {0};
	bk_sb_put(&b, "#version 450\n%slayout(local_size_x = 1) in;\n"
	          "layout(std430, set = 0, binding = 0) buffer Data { float v[]; } data;\n%s\nvoid main()\n{\n"
	          "\tdata.v[15] = float(%s(",
	          half ? "#extension GL_EXT_shader_explicit_arithmetic_types_float16 : require\n" : "", fn, name);
	const char *sep = "";
	for (int c = 0; c < BK_IN_COUNT; c++)
		if (inputs >> c & 1) {
			bk_sb_put(&b, "%s%s(data.v[%d])", sep, T, c);
			sep = ", ";
		}
	bk_sb_put(&b, "));\n}\n");
	if (b.oom) {
		free(b.s);
		return NULL;
	}
	return b.s;
}

/* SPIR-V to one MSL translation unit (malloc'd), or NULL with err. */
static char *cross(const unsigned *words, size_t n, char *err, size_t errlen)
{
	spvc_context ctx = NULL;
	spvc_parsed_ir ir = NULL;
	spvc_compiler comp = NULL;
	spvc_compiler_options opt = NULL;
	const char *src = NULL;
	char *out = NULL;
	if (spvc_context_create(&ctx) != SPVC_SUCCESS) {
		snprintf(err, errlen, "spirv-cross: cannot create a context");
		return NULL;
	}
	/* MSL 2.1 (iOS 12, macOS 10.14): half arithmetic and everything the
	 * forms use; nothing newer is needed */
	if (spvc_context_parse_spirv(ctx, words, n, &ir) != SPVC_SUCCESS ||
	    spvc_context_create_compiler(ctx, SPVC_BACKEND_MSL, ir, SPVC_CAPTURE_MODE_TAKE_OWNERSHIP, &comp) != SPVC_SUCCESS ||
	    spvc_compiler_create_compiler_options(comp, &opt) != SPVC_SUCCESS ||
	    spvc_compiler_options_set_uint(opt, SPVC_COMPILER_OPTION_MSL_VERSION, SPVC_MAKE_MSL_VERSION(2, 1, 0)) != SPVC_SUCCESS ||
	    spvc_compiler_install_compiler_options(comp, opt) != SPVC_SUCCESS ||
	    spvc_compiler_compile(comp, &src) != SPVC_SUCCESS)
		snprintf(err, errlen, "spirv-cross: %.400s", spvc_context_get_last_error_string(ctx));
	else if (!(out = strdup(src)))
		snprintf(err, errlen, "out of memory");
	spvc_context_destroy(ctx);
	return out;
}

/* The function named name in SPIRV-Cross's unit, written with the
 * signature "T name(T NoV, ...)" and its body as translated. 0, or -1. */
static int cut(bk_strbuf *b, const char *unit, const char *name, const char *T, unsigned inputs)
{
	char head[96];
	snprintf(head, sizeof head, " %s(", name);
	const char *s = strstr(unit, head);
	const char *body = s ? strstr(s, "\n{\n") : NULL;
	const char *end = body ? strstr(body, "\n}\n") : NULL;
	if (!end)
		return -1;
	bk_sb_put(b, "%s %s(", T, name);
	const char *sep = "";
	for (int c = 0; c < BK_IN_COUNT; c++)
		if (inputs >> c & 1) {
			bk_sb_put(b, "%s%s %s", sep, T, bk_input_name((bk_input)c));
			sep = ", ";
		}
	bk_sb_put(b, ")%.*s\n", (int)(end + 3 - body - 1), body);
	return 0;
}

char *bk_msl_emit(const bk_form *f, int half, const double *params, const bk_emit_info *info,
                  const bk_emit_style *style, char *err, size_t errlen)
{
	const char *name = info && info->name ? info->name : "brdfkit_form";
	if (bk_msl_reserved(name)) {
		snprintf(err, errlen, "'%s' is reserved in Metal", name);
		return NULL;
	}
	char *fn = bk_form_emit_styled(f, BK_LANG_GLSL, half ? BK_EMIT_F16 : BK_EMIT_SINGLE, params, info, style);
	if (!fn) {
		snprintf(err, errlen, "code generation failed (out of memory, or '%s' is reserved in GLSL)", name);
		return NULL;
	}
	unsigned inputs = style && style->inputs ? style->inputs : bk_form_inputs(f);
	char *glsl = wrapper(fn, name, inputs, half);
	size_t n = 0;
	unsigned *words = glsl ? bk_gpucost_spirv(glsl, &n, err, errlen) : NULL;
	char *unit = words ? cross(words, n, err, errlen) : NULL;
	bk_strbuf b = {0};
	char *res = NULL;
	if (unit) {
		/* bk_form_emit's comment, its precision line said for Metal */
		const char *end = strstr(fn, " */\n");
		const char *prec = strstr(fn, " * precision: ");
		const char *next = prec ? strstr(prec, "\n * op counts") : NULL;
		if (prec && next && end) {
			bk_sb_put(&b, "%.*s * precision: MSL %s; SPIRV-Cross's translation of the SPIR-V of\n"
			          " *   brdfkit codegen --lang glsl --precision %s. Metal compiles with fast math unless\n"
			          " *   told -fno-fast-math: it may reorder and fuse, as GPU drivers do\n", (int)(prec - fn), fn,
			          half ? "half with binary16 constants (fp16; bk_form_eval BK_F16)" : "float (fp32)",
			          half ? "float16" : "single");
			bk_sb_put(&b, "%.*s", (int)(end + 4 - next - 1), next + 1);
		}
		bk_sb_put(&b, "#include <metal_stdlib>\nusing namespace metal;\n\n");
		if (cut(&b, unit, name, half ? "half" : "float", inputs) < 0)
			snprintf(err, errlen, "spirv-cross: no function '%s' in its output", name);
		else if (b.oom)
			snprintf(err, errlen, "out of memory");
		else
			res = b.s;
	}
	if (!res)
		free(b.s);
	free(unit);
	free(words);
	free(glsl);
	free(fn);
	return res;
}
