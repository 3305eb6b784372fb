/*
 * lvp.h — Mesa's lavapipe (software Vulkan) running batches of compute
 * dispatches: one instance and one device for the whole run, the pipelines of
 * a batch recorded into one command buffer and submitted once; and the GLSL
 * side of that contract: the shader head (bindings, push constants, the
 * float controls that keep NaN and infinities meaningful) and the float16_t
 * rewrite of emitted functions. Used by brdfkit render (analysis/render.c)
 * and by tests/vk (build/vkrun). SPIR-V comes from bk_gpucost_spirv
 * (glslang in-process, analysis/gpucost.h).
 *
 * The layout every shader run here follows: binding 0 a readonly float
 * buffer of inputs, binding 1 a writeonly float buffer of outputs, push
 * constants (fn, in_off, out_off, n): dispatch k runs n invocations (64 per
 * workgroup); what fn selects and how many floats a sample reads or writes
 * is the shader's own (tests/vk: 8 in, 1 out; render: see render.h).
 */
#ifndef ANALYSIS_LVP_H
#define ANALYSIS_LVP_H

#include "brdf.h"
#include "out.h"

#include <stddef.h>
#include <stdint.h>

#define BK_LVP_ICD "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json"
#define BK_LVP_NO_DRIVER 1

typedef struct bk_lvp bk_lvp;

/* One dispatch: pipeline pipe runs function fn (the push constant) on n
 * samples from sample in_off of the inputs into outputs from out_off. */
typedef struct bk_lvp_dispatch {
	int pipe;
	uint32_t fn, in_off, out_off, n;
} bk_lvp_dispatch;

/* Opens lavapipe (VK_ICD_FILENAMES set to BK_LVP_ICD unless already set; the
 * physical device must be VK_DRIVER_ID_MESA_LLVMPIPE) with shaderFloat16 and
 * SignedZeroInfNanPreserve for 16 and 32 bits, which brdfkit needs (fp16 runs and non-finite values). driver
 * gets "llvmpipe Mesa 22.3.6 (LLVM 15.0.6)". 0; BK_LVP_NO_DRIVER with one line
 * in err saying what to install; -1 with a message. */
int bk_lvp_open(bk_lvp **v, char *driver, size_t driverlen, char *err, size_t errlen);

/* Creates the pipelines (SPIR-V words), runs the dispatches over in (8 floats
 * per sample) into out, and destroys the pipelines. seconds gets the time of
 * pipeline creation and of the run. 0, or -1 with a message. */
int bk_lvp_run(bk_lvp *v, unsigned *const *spirv, const size_t *nwords, int npipe, const float *in, size_t nin,
            const bk_lvp_dispatch *d, int nd, float *out, size_t nout, double seconds[2], char *err, size_t errlen);

void bk_lvp_close(bk_lvp *v);

/* The shader head of that layout: #version 450, the float16 extension for
 * BK_F16, SignedZeroInfNanPreserve for the arithmetic's width (without it the
 * driver may assume there are no NaN or infinities: "Precision and Operation
 * of SPIR-V Instructions"; glslang keeps one such mode per id, so the f16
 * shader's f32 conversions are exact ones), local size 64, the two buffers
 * (inb.v[], outb.v[]) and the push constants pc.fn, pc.in_off, pc.out_off, pc.n. */
void bk_lvp_head(bk_strbuf *b, bk_precision prec);

/* A function's text with float16_t arithmetic: "float" becomes float16_t,
 * precision qualifiers go (desktop drivers ignore mediump, so that is the
 * only way to run half), and every literal becomes the exact decimal of its
 * float value rounded to half (nearest, ties to even: what bk_form_eval
 * BK_F16 loads), with the hf suffix. Exact, because glslang 12 converts a
 * half literal toward zero: "0.040618896hf" (the float of a half value 1331
 * * 2^-15) would compile to 1330 * 2^-15. A literal past 65504 becomes +inf.
 * Comments are kept. Malloc'd, or NULL. */
char *bk_lvp_half_text(const char *glsl);

/* The lexing the rewrite uses, for callers that edit emitted text: the
 * length of a float literal at s (0 if none, or if it runs into an
 * identifier: 8u, 0x7f800000u), of a comment at s (0 if none); whether c may
 * be part of an identifier. */
size_t bk_lvp_literal_len(const char *s);
size_t bk_lvp_comment_len(const char *s);
int bk_lvp_ident_char(char c);

#endif
