/*
 * msl.h — Metal Shading Language from the SPIR-V brdfkit already validates:
 * a form's GLSL (bk_form_emit, float or float16_t) in a compute shader,
 * glslang in-process (bk_gpucost_spirv), then SPIRV-Cross's MSL back end
 * (its C API, Debian libspirv-cross-c-shared-dev), as engines make their
 * Metal shaders. The function is cut out of SPIRV-Cross's translation unit
 * and given bk_form_emit's provenance comment and the GLSL's name and
 * signature (by value: SPIRV-Cross writes "thread const half&").
 *
 * WGSL is not emitted: no WGSL validator (naga, tint) is packaged in Debian
 * 12, so nothing here could prove the text compiles.
 */
#ifndef ANALYSIS_MSL_H
#define ANALYSIS_MSL_H

#include "brdf.h"

#include <stddef.h>

/* 1 if name cannot be a Metal function's name beyond what GLSL already
 * refuses (bk_lang_reserved(BK_LANG_GLSL, ...), which msl's names pass
 * too): C++14's keywords, Metal's address spaces and function qualifiers
 * (device, kernel, ...), its scalar, vector and matrix types (half4,
 * float3x3, ...), its namespaces and the <metal_stdlib> functions brdfkit's
 * code or SPIRV-Cross's translation may call (rsqrt, saturate, as_type,
 * ...); SPIRV-Cross keeps such a name as it is, which would not compile. */
int bk_msl_reserved(const char *name);

/* f as one MSL function: half 0 (BK_EMIT_SINGLE) float, otherwise half (MSL
 * has one 16-bit type; the constants on the half grid, bk_form_emit's rule).
 * info as bk_form_emit's (its name must be free in GLSL and Metal:
 * bk_msl_reserved). Returns
 * malloc'd text, or NULL with a message in err. */
char *bk_msl_emit(const bk_form *f, int half, const double *params, const bk_emit_info *info,
                  const bk_emit_style *style, char *err, size_t errlen);

#endif
