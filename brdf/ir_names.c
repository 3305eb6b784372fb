/*
 * ir_names.c — the names a generated function may not have, per language:
 * whatever the language, its standard library or the code around the
 * function already gives a meaning (a function of that name would not
 * compile, or would silently be another), and the names of the body itself.
 *
 *   C     C11 keywords (6.4.1); every name C11's library headers declare or
 *         define (7.2 to 7.30, Annex K), their macro and type families;
 *         every identifier <math.h> declares or defines
 *         with glibc's widest feature set (_GNU_SOURCE): C11 7.12, TS 18661
 *         (fadd, roundeven, f32 ... f128x variants), POSIX/SVID/GNU extras
 *         (j0, y1, gamma, M_PI); main; the predefined macros linux and unix of
 *         gcc's GNU modes; reserved identifiers (7.1.3: any _name at file
 *         scope); at most 63 characters (5.2.4.1: the significant initial
 *         characters of an internal identifier).
 *   GLSL  keywords and reserved words of GLSL ES 3.00 and GLSL 4.50 (3.6,
 *         3.8), Vulkan GLSL's texture and subpass types, the explicit-
 *         arithmetic types (float16_t, f16vec4: gpucost writes them), every
 *         built-in function of ES 3.20 and 4.60 (chapter 8: a user function
 *         of that name redeclares it), main, the gl_ prefix and any "__".
 *   HLSL  keywords and reserved words, numeric vector and matrix types, every
 *         intrinsic (Shader Model 6 included), main (the usual entry point),
 *         "__" anywhere and _Uppercase (DXC is a C++ compiler).
 *
 * Tables are lists of exact names; families are rules (a math function's
 * f/l/f32...f128x forms, GLSL's vecN and sampler types). tests/cli_ir.sh
 * derives <math.h>'s names from the system compiler and compiles the
 * accepted names.
 */
#include "ir.h"

#include <string.h>

/* ---- C ------------------------------------------------------------------------ */

static const char *const c_words[] = {
	/* C11 6.4.1 */
	"auto", "break", "case", "char", "const", "continue", "default", "do", "double", "else", "enum",
	"extern", "float", "for", "goto", "if", "inline", "int", "long", "register", "restrict",
	"return", "short", "signed", "sizeof", "static", "struct", "switch", "typedef", "union",
	"unsigned", "void", "volatile", "while", "_Alignas", "_Alignof", "_Atomic", "_Bool",
	"_Complex", "_Generic", "_Imaginary", "_Noreturn", "_Static_assert", "_Thread_local",
	/* the program's entry point; gcc's GNU-mode predefined macros */
	"main", "linux", "unix",
	/* <math.h>: types, macros, classification (C11 7.12, TS 18661) */
	"float_t", "double_t", "INFINITY", "NAN", "MAXFLOAT", "MATH_ERRNO", "MATH_ERREXCEPT",
	"math_errhandling", "signgam", "fpclassify", "iscanonical", "iseqsig", "isfinite", "isgreater",
	"isgreaterequal", "isinf", "isless", "islessequal", "islessgreater", "isnan", "isnormal",
	"issignaling", "issubnormal", "isunordered", "iszero", "signbit",
	/* what the templates of ir_ops.h call: in the list above or below, named
	 * here too for the table's readers */
	"sqrtf", "powf", "expf", "exp2f", "logf", "log2f", "fminf", "fmaxf", "fabsf",
	/* the rest of C11's library (7.2 to 7.30): every function, macro, type
	 * and object a header declares; a caller that includes the header
	 * would meet a conflicting declaration or a macro expansion (7.1.3).
	 * Families (FLT_..., SIGxxx, int..._t, atomic_...) are rules below. */
	/* <assert.h> */
	"assert", "static_assert", "NDEBUG",
	/* <complex.h> (the functions come with f and l: c_cfamily) */
	"complex", "imaginary", "I", "CMPLX", "CMPLXF", "CMPLXL",
	/* <ctype.h> */
	"isalnum", "isalpha", "isblank", "iscntrl", "isdigit", "isgraph", "islower", "isprint", "ispunct",
	"isspace", "isupper", "isxdigit", "tolower", "toupper",
	/* <errno.h> (E and a digit or an uppercase letter: a rule) */
	"errno",
	/* <fenv.h> (FE_: a rule) */
	"fenv_t", "fexcept_t", "feclearexcept", "fegetexceptflag", "feraiseexcept", "fesetexceptflag",
	"fetestexcept", "fegetround", "fesetround", "fegetenv", "feholdexcept", "fesetenv", "feupdateenv",
	/* <float.h> (FLT_, DBL_, LDBL_: a rule) */
	"DECIMAL_DIG",
	/* <inttypes.h> (PRI, SCN: a rule) */
	"imaxdiv_t", "imaxabs", "imaxdiv", "strtoimax", "strtoumax", "wcstoimax", "wcstoumax",
	/* <iso646.h> */
	"and", "and_eq", "bitand", "bitor", "compl", "not", "not_eq", "or", "or_eq", "xor", "xor_eq",
	/* <limits.h> */
	"CHAR_BIT", "SCHAR_MIN", "SCHAR_MAX", "UCHAR_MAX", "CHAR_MIN", "CHAR_MAX", "MB_LEN_MAX", "SHRT_MIN",
	"SHRT_MAX", "USHRT_MAX", "INT_MIN", "INT_MAX", "UINT_MAX", "LONG_MIN", "LONG_MAX", "ULONG_MAX",
	"LLONG_MIN", "LLONG_MAX", "ULLONG_MAX",
	/* <locale.h> (LC_: a rule; struct lconv is a tag, another name space) */
	"setlocale", "localeconv",
	/* <setjmp.h> */
	"jmp_buf", "setjmp", "longjmp",
	/* <signal.h> (SIG and SIG_ with an uppercase letter: a rule) */
	"sig_atomic_t", "signal", "raise",
	/* <stdalign.h>, <stdbool.h>, <stdnoreturn.h> */
	"alignas", "alignof", "bool", "true", "false", "noreturn",
	/* <stdarg.h> */
	"va_list", "va_arg", "va_copy", "va_end", "va_start",
	/* <stdatomic.h> (atomic_ and a lowercase letter, memory_order, ATOMIC_: rules) */
	"kill_dependency",
	/* <stddef.h>, <stdint.h> (int..._t and INT..._MAX/_MIN/_C: rules) */
	"ptrdiff_t", "size_t", "max_align_t", "wchar_t", "NULL", "offsetof", "PTRDIFF_MIN", "PTRDIFF_MAX",
	"SIG_ATOMIC_MIN", "SIG_ATOMIC_MAX", "SIZE_MAX", "WCHAR_MIN", "WCHAR_MAX", "WINT_MIN", "WINT_MAX",
	/* <stdio.h> */
	"FILE", "fpos_t", "_IOFBF", "_IOLBF", "_IONBF", "BUFSIZ", "EOF", "FOPEN_MAX", "FILENAME_MAX", "L_tmpnam",
	"SEEK_CUR", "SEEK_END", "SEEK_SET", "TMP_MAX", "stderr", "stdin", "stdout", "remove", "rename", "tmpfile",
	"tmpnam", "fclose", "fflush", "fopen", "freopen", "setbuf", "setvbuf", "fprintf", "fscanf", "printf",
	"scanf", "snprintf", "sprintf", "sscanf", "vfprintf", "vfscanf", "vprintf", "vscanf", "vsnprintf",
	"vsprintf", "vsscanf", "fgetc", "fgets", "fputc", "fputs", "getc", "getchar", "gets", "putc", "putchar",
	"puts", "ungetc", "fread", "fwrite", "fgetpos", "fseek", "fsetpos", "ftell", "rewind", "clearerr", "feof",
	"ferror", "perror",
	/* <stdlib.h> */
	"div_t", "ldiv_t", "lldiv_t", "EXIT_FAILURE", "EXIT_SUCCESS", "RAND_MAX", "MB_CUR_MAX", "atof", "atoi",
	"atol", "atoll", "strtod", "strtof", "strtold", "strtol", "strtoll", "strtoul", "strtoull", "rand", "srand",
	"aligned_alloc", "calloc", "free", "malloc", "realloc", "abort", "atexit", "at_quick_exit", "exit",
	"getenv", "quick_exit", "system", "bsearch", "qsort", "abs", "labs", "llabs", "div", "ldiv", "lldiv",
	"mblen", "mbtowc", "wctomb", "mbstowcs", "wcstombs",
	/* <string.h> */
	"memcpy", "memmove", "strcpy", "strncpy", "strcat", "strncat", "memcmp", "strcmp", "strcoll", "strncmp",
	"strxfrm", "memchr", "strchr", "strcspn", "strpbrk", "strrchr", "strspn", "strstr", "strtok", "memset",
	"strerror", "strlen",
	/* <threads.h> (cnd_, mtx_, thrd_, tss_ and a lowercase letter: a rule) */
	"thread_local", "ONCE_FLAG_INIT", "TSS_DTOR_ITERATIONS", "once_flag", "call_once",
	/* <time.h> (struct tm and timespec are tags: another name space) */
	"CLOCKS_PER_SEC", "TIME_UTC", "clock_t", "time_t", "clock", "difftime", "mktime",
	"time", "timespec_get", "asctime", "ctime", "gmtime", "localtime", "strftime",
	/* <uchar.h> */
	"mbstate_t", "char16_t", "char32_t", "mbrtoc16", "c16rtomb", "mbrtoc32", "c32rtomb",
	/* <wchar.h> */
	"wint_t", "WEOF", "fwprintf", "fwscanf", "swprintf", "swscanf", "vfwprintf", "vfwscanf", "vswprintf",
	"vswscanf", "vwprintf", "vwscanf", "wprintf", "wscanf", "fgetwc", "fgetws", "fputwc", "fputws", "fwide",
	"getwc", "getwchar", "putwc", "putwchar", "ungetwc", "wcstod", "wcstof", "wcstold", "wcstol", "wcstoll",
	"wcstoul", "wcstoull", "wcscpy", "wcsncpy", "wmemcpy", "wmemmove", "wcscat", "wcsncat", "wcscmp",
	"wcscoll", "wcsncmp", "wcsxfrm", "wmemcmp", "wcschr", "wcscspn", "wcspbrk", "wcsrchr", "wcsspn", "wcsstr",
	"wcstok", "wmemchr", "wcslen", "wmemset", "wcsftime", "btowc", "wctob", "mbsinit", "mbrlen", "mbrtowc",
	"wcrtomb", "mbsrtowcs", "wcsrtombs",
	/* <wctype.h> */
	"wctrans_t", "wctype_t", "iswalnum", "iswalpha", "iswblank", "iswcntrl", "iswdigit", "iswgraph",
	"iswlower", "iswprint", "iswpunct", "iswspace", "iswupper", "iswxdigit", "iswctype", "wctype", "towlower",
	"towupper", "towctrans", "wctrans",
	/* Annex K's types and macros (its functions are NAME_s: a rule) */
	"errno_t", "rsize_t", "RSIZE_MAX", "L_tmpnam_s", "TMP_MAX_S", "constraint_handler_t",
	"set_constraint_handler_s", "abort_handler_s", "ignore_handler_s",
	NULL,
};

/* <complex.h>'s functions, each with f and l (cabs, cabsf, cabsl). */
static const char *const c_complex[] = {
	"cacos", "casin", "catan", "ccos", "csin", "ctan", "cacosh", "casinh", "catanh", "ccosh", "csinh",
	"ctanh", "cexp", "clog", "cabs", "cpow", "csqrt", "carg", "cimag", "conj", "cproj", "creal",
};

/* <math.h> functions and constants that come with every type suffix
 * (acos, acosf, acosl, acosf32, ... acosf128x). */
static const char *const c_math[] = {
	"acos", "acosh", "acospi", "asin", "asinh", "asinpi", "atan", "atan2", "atan2pi", "atanh", "atanpi",
	"canonicalize", "cbrt", "ceil", "compoundn", "copysign", "cos", "cosh", "cospi", "drem", "erf", "erfc",
	"exp", "exp10", "exp10m1", "exp2", "exp2m1", "expm1", "fabs", "fdim", "finite", "floor", "fma", "fmax",
	"fmaximum", "fmaximum_mag", "fmaximum_mag_num", "fmaximum_num", "fmaxmag", "fmin", "fminimum",
	"fminimum_mag", "fminimum_mag_num", "fminimum_num", "fminmag", "fmod", "frexp", "fromfp", "fromfpx",
	"gamma", "getpayload", "hypot", "ilogb", "isinf", "isnan", "j0", "j1", "jn", "ldexp", "lgamma", "llogb",
	"llrint", "llround", "log", "log10", "log10p1", "log1p", "log2", "log2p1", "logb", "logp1", "lrint",
	"lround", "modf", "nan", "nearbyint", "nextafter", "nextdown", "nexttoward", "nextup", "pow", "pow10",
	"pown", "powr", "remainder", "remquo", "rint", "rootn", "round", "roundeven", "rsqrt", "scalb",
	"scalbln", "scalbn", "setpayload", "setpayloadsig", "significand", "sin", "sincos", "sinh", "sinpi",
	"sqrt", "tan", "tanh", "tanpi", "tgamma", "totalorder", "totalordermag", "trunc", "ufromfp",
	"ufromfpx", "y0", "y1", "yn",
	"M_E", "M_LOG2E", "M_LOG10E", "M_LN2", "M_LN10", "M_PI", "M_PI_2", "M_PI_4", "M_1_PI", "M_2_PI",
	"M_2_SQRTPI", "M_SQRT2", "M_SQRT1_2",
};

static const char *const float_suffix[] = {"", "f", "l", "f16", "f32", "f64", "f128", "f32x", "f64x", "f128x"};
#define NSUFFIX (sizeof float_suffix / sizeof float_suffix[0])

static int is_suffix(const char *s)
{
	for (size_t i = 0; i < NSUFFIX; i++)
		if (!strcmp(s, float_suffix[i]))
			return 1;
	return 0;
}

/* name is stem followed by a type suffix (stem_r: lgammaf_r has the suffix
 * before "_r"). */
static int stem_suffix(const char *name, const char *stem, const char *tail)
{
	size_t n = strlen(stem), t = strlen(tail), m = strlen(name);
	if (strncmp(name, stem, n) || m < n + t || strcmp(name + m - t, tail))
		return 0;
	char mid[16];
	if (m - n - t >= sizeof mid)
		return 0;
	memcpy(mid, name + n, m - n - t);
	mid[m - n - t] = '\0';
	return is_suffix(mid);
}

/* TS 18661's narrowing operations: fadd, daddl, f32mulf64, f32xsqrtf128 ... */
static int c_narrowing(const char *name)
{
	static const char *const result[] = {"f", "d", "f32", "f64", "f128", "f32x", "f64x", "f128x"};
	static const char *const op[] = {"add", "sub", "mul", "div", "fma", "sqrt"};
	for (size_t r = 0; r < sizeof result / sizeof result[0]; r++)
		for (size_t o = 0; o < sizeof op / sizeof op[0]; o++) {
			size_t k = strlen(result[r]);
			if (!strncmp(name, result[r], k) && stem_suffix(name + k, op[o], ""))
				return 1;
		}
	return 0;
}

/* prefix then a character of set: "SIG" and an uppercase letter */
static int prefix_then(const char *name, const char *prefix, const char *set)
{
	size_t n = strlen(prefix);
	return !strncmp(name, prefix, n) && name[n] && strchr(set, name[n]);
}

static int ends(const char *name, const char *tail)
{
	size_t n = strlen(name), t = strlen(tail);
	return n > t && !strcmp(name + n - t, tail);
}

#define UPPER "ABCDEFGHIJKLMNOPQRSTUVWXYZ"
#define LOWER "abcdefghijklmnopqrstuvwxyz"

/* The macro and type families of C11's headers, each as the header states
 * it (7.31, future library directions, where that is no wider than the
 * header's own names): E and a digit or an uppercase letter (errno.h), FE_,
 * FLT_, DBL_, LDBL_, LC_, SIG and SIG_ with an uppercase letter, PRI and SCN
 * with a lowercase letter or X, int/uint..._t, INT/UINT..._MAX/_MIN/_C,
 * atomic_ and cnd_/mtx_/thrd_/tss_ with a lowercase letter, memory_order,
 * ATOMIC_; Annex K's NAME_s of a library function. Left out: 7.31's
 * is/to/str/mem/wcs prefixes with a lowercase letter, which no header
 * declares beyond the names listed (refusing them would refuse "total" and
 * "strength"). */
static int c_library_family(const char *name)
{
	static const char *const upper_prefix[] = {"FE_", "FLT_", "DBL_", "LDBL_", "LC_", "SIG_", "SIG", "ATOMIC_"};
	static const char *const lower_prefix[] = {"atomic_", "cnd_", "mtx_", "thrd_", "tss_"};
	for (size_t i = 0; i < sizeof upper_prefix / sizeof upper_prefix[0]; i++)
		if (prefix_then(name, upper_prefix[i], UPPER))
			return 1;
	for (size_t i = 0; i < sizeof lower_prefix / sizeof lower_prefix[0]; i++)
		if (prefix_then(name, lower_prefix[i], LOWER))
			return 1;
	if (prefix_then(name, "E", "0123456789" UPPER) || prefix_then(name, "PRI", LOWER "X") ||
	    prefix_then(name, "SCN", LOWER "X") || !strncmp(name, "memory_order", 12))
		return 1;
	if ((!strncmp(name, "int", 3) || !strncmp(name, "uint", 4)) && ends(name, "_t"))
		return 1;
	if ((!strncmp(name, "INT", 3) || !strncmp(name, "UINT", 4)) &&
	    (ends(name, "_MAX") || ends(name, "_MIN") || ends(name, "_C")))
		return 1;
	for (size_t i = 0; i < sizeof c_complex / sizeof c_complex[0]; i++) {
		size_t n = strlen(c_complex[i]);
		if (!strncmp(name, c_complex[i], n) && (!name[n] || ((name[n] == 'f' || name[n] == 'l') && !name[n + 1])))
			return 1;
	}
	if (ends(name, "_s")) { /* Annex K: printf_s, strcpy_s, ... */
		char stem[BK_NAME_MAX + 1];
		size_t n = strlen(name) - 2;
		memcpy(stem, name, n);
		stem[n] = '\0';
		for (const char *const *w = c_words; *w; w++)
			if (!strcmp(*w, stem) && (*w)[0] >= 'a' && (*w)[0] <= 'z')
				return 1;
	}
	return 0;
}

static int c_family(const char *name)
{
	for (size_t i = 0; i < sizeof c_math / sizeof c_math[0]; i++)
		if (stem_suffix(name, c_math[i], ""))
			return 1;
	if (c_library_family(name))
		return 1;
	if (stem_suffix(name, "lgamma", "_r") || c_narrowing(name))
		return 1;
	/* macro families: FP_ and an uppercase letter is the implementation's
	 * (C11 7.12), HUGE_VAL and SNAN come with every type */
	return (!strncmp(name, "FP_", 3) && name[3] >= 'A' && name[3] <= 'Z') || !strncmp(name, "HUGE_VAL", 8) ||
	       !strncmp(name, "SNAN", 4) ||
	       name[0] == '_'; /* C11 7.1.3: every _name is reserved at file scope, where the function is */
}

/* ---- GLSL --------------------------------------------------------------------- */

static const char *const glsl_words[] = {
	/* keywords, GLSL ES 3.00 3.6 and GLSL 4.50 3.6 (types by rule below) */
	"attribute", "const", "uniform", "varying", "buffer", "shared", "coherent", "volatile", "restrict",
	"readonly", "writeonly", "atomic_uint", "layout", "centroid", "flat", "smooth", "noperspective",
	"patch", "sample", "break", "continue", "do", "for", "while", "switch", "case", "default", "if",
	"else", "subroutine", "in", "out", "inout", "float", "double", "int", "void", "bool", "true", "false",
	"invariant", "precise", "discard", "return", "uint", "lowp", "mediump", "highp", "precision", "struct",
	"demote", "terminateInvocation",
	/* reserved for future use */
	"common", "partition", "active", "asm", "class", "union", "enum", "typedef", "template", "this",
	"resource", "goto", "inline", "noinline", "public", "static", "extern", "external", "interface",
	"long", "short", "half", "fixed", "unsigned", "superp", "input", "output", "filter", "sizeof", "cast",
	"namespace", "using",
	/* explicit arithmetic scalar types (GL_EXT_shader_explicit_arithmetic_types) */
	"int8_t", "uint8_t", "int16_t", "uint16_t", "int32_t", "uint32_t", "int64_t", "uint64_t",
	"float16_t", "float32_t", "float64_t",
	/* the entry point */
	"main",
	/* built-in functions, GLSL 4.60 and ES 3.20 chapter 8 */
	"radians", "degrees", "sin", "cos", "tan", "asin", "acos", "atan", "sinh", "cosh", "tanh", "asinh",
	"acosh", "atanh", "pow", "exp", "log", "exp2", "log2", "sqrt", "inversesqrt", "abs", "sign", "floor",
	"trunc", "round", "roundEven", "ceil", "fract", "mod", "modf", "min", "max", "clamp", "mix", "step",
	"smoothstep", "isnan", "isinf", "floatBitsToInt", "floatBitsToUint", "intBitsToFloat",
	"uintBitsToFloat", "fma", "frexp", "ldexp", "packUnorm2x16", "packSnorm2x16", "packUnorm4x8",
	"packSnorm4x8", "unpackUnorm2x16", "unpackSnorm2x16", "unpackUnorm4x8", "unpackSnorm4x8",
	"packHalf2x16", "unpackHalf2x16", "packDouble2x32", "unpackDouble2x32", "length", "distance", "dot",
	"cross", "normalize", "ftransform", "faceforward", "reflect", "refract", "matrixCompMult",
	"outerProduct", "transpose", "determinant", "inverse", "lessThan", "lessThanEqual", "greaterThan",
	"greaterThanEqual", "equal", "notEqual", "any", "all", "not", "uaddCarry", "usubBorrow",
	"umulExtended", "imulExtended", "bitfieldExtract", "bitfieldInsert", "bitfieldReverse", "bitCount",
	"findLSB", "findMSB", "textureSize", "textureQueryLod", "textureQueryLevels", "textureSamples",
	"texture", "textureProj", "textureLod", "textureOffset", "texelFetch", "texelFetchOffset",
	"textureProjOffset", "textureLodOffset", "textureProjLod", "textureProjLodOffset", "textureGrad",
	"textureGradOffset", "textureProjGrad", "textureProjGradOffset", "textureGather",
	"textureGatherOffset", "textureGatherOffsets", "texture1D", "texture1DProj", "texture1DLod",
	"texture1DProjLod", "texture2D", "texture2DProj", "texture2DLod", "texture2DProjLod", "texture3D",
	"texture3DProj", "texture3DLod", "texture3DProjLod", "textureCube", "textureCubeLod", "shadow1D",
	"shadow2D", "shadow1DProj", "shadow2DProj", "shadow1DLod", "shadow2DLod", "shadow1DProjLod",
	"shadow2DProjLod", "texture2DLodEXT", "texture2DProjLodEXT", "textureCubeLodEXT",
	"atomicCounterIncrement", "atomicCounterDecrement", "atomicCounter", "atomicCounterAdd",
	"atomicCounterSubtract", "atomicCounterMin", "atomicCounterMax", "atomicCounterAnd",
	"atomicCounterOr", "atomicCounterXor", "atomicCounterExchange", "atomicCounterCompSwap", "atomicAdd",
	"atomicMin", "atomicMax", "atomicAnd", "atomicOr", "atomicXor", "atomicExchange", "atomicCompSwap",
	"imageSize", "imageSamples", "imageLoad", "imageStore", "imageAtomicAdd", "imageAtomicMin",
	"imageAtomicMax", "imageAtomicAnd", "imageAtomicOr", "imageAtomicXor", "imageAtomicExchange",
	"imageAtomicCompSwap", "dFdx", "dFdy", "dFdxFine", "dFdyFine", "dFdxCoarse", "dFdyCoarse", "fwidth",
	"fwidthFine", "fwidthCoarse", "interpolateAtCentroid", "interpolateAtSample", "interpolateAtOffset",
	"noise1", "noise2", "noise3", "noise4", "EmitStreamVertex", "EndStreamPrimitive", "EmitVertex",
	"EndPrimitive", "barrier", "memoryBarrier", "memoryBarrierAtomicCounter", "memoryBarrierBuffer",
	"memoryBarrierShared", "memoryBarrierImage", "groupMemoryBarrier", "subpassLoad", "anyInvocation",
	"allInvocations", "allInvocationsEqual",
	NULL,
};

static int starts(const char *s, const char *prefix, const char **rest)
{
	size_t n = strlen(prefix);
	if (strncmp(s, prefix, n))
		return 0;
	*rest = s + n;
	return 1;
}

/* vec2 ... u64vec4, mat2 ... f64mat4x4 */
static int glsl_vector_type(const char *s)
{
	static const char *const vec[] = {"f16vec", "f32vec", "f64vec", "i8vec", "u8vec", "i16vec", "u16vec",
	                                  "i32vec", "u32vec", "i64vec", "u64vec", "ivec", "uvec", "bvec", "dvec",
	                                  "hvec", "fvec", "vec"};
	static const char *const mat[] = {"f16mat", "f32mat", "f64mat", "dmat", "mat"};
	const char *d;
	for (size_t i = 0; i < sizeof vec / sizeof vec[0]; i++)
		if (starts(s, vec[i], &d) && d[0] >= '2' && d[0] <= '4' && !d[1])
			return 1;
	for (size_t i = 0; i < sizeof mat / sizeof mat[0]; i++)
		if (starts(s, mat[i], &d) && d[0] >= '2' && d[0] <= '4' &&
		    (!d[1] || (d[1] == 'x' && d[2] >= '2' && d[2] <= '4' && !d[3])))
			return 1;
	return 0;
}

/* [iu](sampler|image|texture)(1D|2D|...)[Shadow], sampler, samplerShadow,
 * [iu]subpassInput[MS] (desktop, ES and Vulkan GLSL's opaque types) */
static int glsl_opaque_type(const char *s)
{
	static const char *const kind[] = {"sampler", "image", "texture"};
	static const char *const dim[] = {"1D", "2D", "3D", "Cube", "2DRect", "3DRect", "1DArray", "2DArray",
	                                  "Buffer", "2DMS", "2DMSArray", "CubeArray", ""};
	const char *d, *e;
	if ((*s == 'i' || *s == 'u') && glsl_opaque_type(s + 1)) /* isampler2D; but image2D is no "i" + mage2D */
		return 1;
	if (starts(s, "subpassInput", &d))
		return !*d || !strcmp(d, "MS");
	for (size_t k = 0; k < sizeof kind / sizeof kind[0]; k++) {
		if (!starts(s, kind[k], &d))
			continue;
		for (size_t j = 0; j < sizeof dim / sizeof dim[0]; j++)
			if (starts(d, dim[j], &e) && (!*e || !strcmp(e, "Shadow")))
				return 1;
	}
	return 0;
}

static int glsl_family(const char *name)
{
	return !strncmp(name, "gl_", 3) || strstr(name, "__") != NULL || glsl_vector_type(name) ||
	       glsl_opaque_type(name);
}

/* ---- HLSL --------------------------------------------------------------------- */

static const char *const hlsl_words[] = {
	/* keywords */
	"AppendStructuredBuffer", "asm", "asm_fragment", "BlendState", "bool", "break", "Buffer",
	"ByteAddressBuffer", "case", "cbuffer", "centroid", "class", "column_major", "compile",
	"compile_fragment", "CompileShader", "const", "continue", "ComputeShader", "ConsumeStructuredBuffer",
	"default", "DepthStencilState", "DepthStencilView", "discard", "do", "double", "DomainShader", "dword",
	"else", "export", "extern", "false", "float", "for", "fxgroup", "GeometryShader", "groupshared",
	"half", "Hullshader", "HullShader", "if", "in", "inline", "inout", "InputPatch", "int", "interface",
	"line", "lineadj", "linear", "LineStream", "matrix", "min16float", "min10float", "min16int",
	"min12int", "min16uint", "namespace", "nointerpolation", "noperspective", "NULL", "out",
	"OutputPatch", "packoffset", "pass", "pixelfragment", "PixelShader", "point", "PointStream",
	"precise", "RasterizerState", "RenderTargetView", "return", "register", "row_major", "RWBuffer",
	"RWByteAddressBuffer", "RWStructuredBuffer", "RWTexture1D", "RWTexture1DArray", "RWTexture2D",
	"RWTexture2DArray", "RWTexture3D", "sample", "sampler", "sampler1D", "sampler2D", "sampler3D",
	"samplerCUBE", "SamplerState", "sampler_state", "SamplerComparisonState", "shared", "snorm",
	"stateblock", "stateblock_state", "static", "string", "struct", "switch", "StructuredBuffer",
	"tbuffer", "technique", "technique10", "technique11", "texture", "Texture", "Texture1D",
	"Texture1DArray", "Texture2D", "Texture2DArray", "Texture2DMS", "Texture2DMSArray", "Texture3D",
	"TextureCube", "TextureCubeArray", "true", "typedef", "triangle", "triangleadj", "TriangleStream",
	"uint", "uniform", "unorm", "unsigned", "vector", "vertexfragment", "VertexShader", "void",
	"volatile", "while", "globallycoherent", "ConstantBuffer", "TextureBuffer", "RasterizerOrderedBuffer",
	"RasterizerOrderedByteAddressBuffer", "RasterizerOrderedStructuredBuffer", "RasterizerOrderedTexture1D",
	"RasterizerOrderedTexture2D", "RasterizerOrderedTexture3D", "RaytracingAccelerationStructure",
	"RayDesc", "BuiltInTriangleIntersectionAttributes", "indices", "vertices", "primitives", "payload",
	"SubpassInput", "SubpassInputMS", "FeedbackTexture2D", "FeedbackTexture2DArray", "int16_t", "uint16_t",
	"int32_t", "uint32_t", "int64_t", "uint64_t", "float16_t", "float32_t", "float64_t",
	/* reserved words */
	"auto", "catch", "char", "const_cast", "delete", "dynamic_cast", "enum", "explicit", "friend", "goto",
	"long", "mutable", "new", "operator", "private", "protected", "public", "reinterpret_cast", "short",
	"signed", "sizeof", "static_cast", "template", "this", "throw", "try", "typename", "union", "using",
	"virtual",
	/* the usual entry point (the -E/-e of the compile) */
	"main",
	/* intrinsics (Shader Model 1 to 6.x) */
	"abort", "abs", "acos", "all", "AllMemoryBarrier", "AllMemoryBarrierWithGroupSync", "and", "any",
	"asdouble", "asfloat", "asfloat16", "asin", "asint", "asint16", "asuint", "asuint16", "atan", "atan2",
	"ceil", "CheckAccessFullyMapped", "clamp", "clip", "cos", "cosh", "countbits", "cross",
	"D3DCOLORtoUBYTE4", "ddx", "ddx_coarse", "ddx_fine", "ddy", "ddy_coarse", "ddy_fine", "degrees",
	"determinant", "DeviceMemoryBarrier", "DeviceMemoryBarrierWithGroupSync", "distance", "dot",
	"dot2add", "dot4add_i8packed", "dot4add_u8packed", "dst", "errorf", "EvaluateAttributeAtCentroid",
	"EvaluateAttributeAtSample", "EvaluateAttributeSnapped", "exp", "exp2", "f16tof32", "f32tof16",
	"faceforward", "firstbithigh", "firstbitlow", "floor", "fma", "fmod", "frac", "frexp", "fwidth",
	"GetRenderTargetSampleCount", "GetRenderTargetSamplePosition", "GroupMemoryBarrier",
	"GroupMemoryBarrierWithGroupSync", "InterlockedAdd", "InterlockedAnd", "InterlockedCompareExchange",
	"InterlockedCompareStore", "InterlockedExchange", "InterlockedMax", "InterlockedMin", "InterlockedOr",
	"InterlockedXor", "isfinite", "isinf", "isnan", "ldexp", "length", "lerp", "lit", "log", "log10",
	"log2", "mad", "max", "min", "modf", "msad4", "mul", "noise", "NonUniformResourceIndex", "normalize",
	"or", "pow", "printf", "Process2DQuadTessFactorsAvg", "Process2DQuadTessFactorsMax",
	"Process2DQuadTessFactorsMin", "ProcessIsolineTessFactors", "ProcessQuadTessFactorsAvg",
	"ProcessQuadTessFactorsMax", "ProcessQuadTessFactorsMin", "ProcessTriTessFactorsAvg",
	"ProcessTriTessFactorsMax", "ProcessTriTessFactorsMin", "radians", "rcp", "reflect", "refract",
	"reversebits", "round", "rsqrt", "saturate", "select", "sign", "sin", "sincos", "sinh", "smoothstep",
	"sqrt", "step", "tan", "tanh", "tex1D", "tex1Dbias", "tex1Dgrad", "tex1Dlod", "tex1Dproj", "tex2D",
	"tex2Dbias", "tex2Dgrad", "tex2Dlod", "tex2Dproj", "tex3D", "tex3Dbias", "tex3Dgrad", "tex3Dlod",
	"tex3Dproj", "texCUBE", "texCUBEbias", "texCUBEgrad", "texCUBElod", "texCUBEproj", "transpose",
	"trunc", "WaveIsFirstLane", "WaveGetLaneIndex", "WaveGetLaneCount", "WaveActiveAnyTrue",
	"WaveActiveAllTrue", "WaveActiveBallot", "WaveReadLaneFirst", "WaveReadLaneAt", "WaveActiveAllEqual",
	"WaveActiveCountBits", "WaveActiveSum", "WaveActiveProduct", "WaveActiveBitAnd", "WaveActiveBitOr",
	"WaveActiveBitXor", "WaveActiveMin", "WaveActiveMax", "WavePrefixCountBits", "WavePrefixSum",
	"WavePrefixProduct", "WaveMatch", "WaveMultiPrefixSum", "WaveMultiPrefixProduct",
	"WaveMultiPrefixCountBits", "WaveMultiPrefixBitAnd", "WaveMultiPrefixBitOr", "WaveMultiPrefixBitXor",
	"QuadReadLaneAt", "QuadReadAcrossX", "QuadReadAcrossY", "QuadReadAcrossDiagonal", "QuadAny",
	"QuadAll", "TraceRay", "ReportHit", "CallShader", "IgnoreHit", "AcceptHitAndEndSearch",
	"DispatchMesh", "SetMeshOutputCounts",
	NULL,
};

/* HLSL's numeric vector and matrix types: a scalar type then N or NxM, 1..4. */
static int hlsl_vector_type(const char *s)
{
	static const char *const scalar[] = {"bool", "int", "uint", "dword", "half", "float", "double",
	                                     "min16float", "min10float", "min16int", "min12int", "min16uint",
	                                     "int16_t", "uint16_t", "int32_t", "uint32_t", "int64_t", "uint64_t",
	                                     "float16_t", "float32_t", "float64_t"};
	for (size_t i = 0; i < sizeof scalar / sizeof scalar[0]; i++) {
		size_t n = strlen(scalar[i]);
		if (strncmp(s, scalar[i], n) != 0)
			continue;
		const char *d = s + n;
		if (d[0] >= '1' && d[0] <= '4' && (d[1] == '\0' || (d[1] == 'x' && d[2] >= '1' && d[2] <= '4' && !d[3])))
			return 1;
	}
	return 0;
}

static int hlsl_family(const char *name)
{
	/* DXC is a C++ front end: __ anywhere and _Uppercase are the implementation's */
	return hlsl_vector_type(name) || strstr(name, "__") != NULL ||
	       (name[0] == '_' && name[1] >= 'A' && name[1] <= 'Z');
}

/* ---- all languages ------------------------------------------------------------ */

static const char *const *const lang_words[3] = {c_words, glsl_words, hlsl_words};

const char *bk_lang_word(bk_lang lang, size_t i)
{
	if ((unsigned)lang > BK_LANG_HLSL)
		return NULL;
	for (size_t k = 0; k <= i; k++)
		if (!lang_words[lang][k])
			return NULL;
	return lang_words[lang][i];
}

int bk_identifier(const char *s)
{
	if (!((*s >= 'A' && *s <= 'Z') || (*s >= 'a' && *s <= 'z') || *s == '_'))
		return 0;
	return strspn(s, "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_") == strlen(s);
}

int bk_lang_reserved(bk_lang lang, const char *name)
{
	if ((unsigned)lang > BK_LANG_HLSL || strlen(name) > BK_NAME_MAX || !bk_identifier(name))
		return 1;
	for (const char *const *w = lang_words[lang]; *w; w++)
		if (strcmp(*w, name) == 0)
			return 1;
	/* the body's own names: temporaries tN and the inputs (the parameters) */
	if (name[0] == 't' && name[1] && strspn(name + 1, "0123456789") == strlen(name + 1))
		return 1;
	for (int i = 0; i < BK_IN_COUNT; i++)
		if (strcmp(name, bk_input_name((bk_input)i)) == 0)
			return 1;
	switch (lang) {
	case BK_LANG_C: return c_family(name);
	case BK_LANG_GLSL: return glsl_family(name);
	case BK_LANG_HLSL: return hlsl_family(name);
	}
	return 1;
}
