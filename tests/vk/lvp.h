/*
 * lvp.h — Mesa's lavapipe (software Vulkan) running batches of compute
 * dispatches: one instance and one device for the whole run, the pipelines of
 * a batch recorded into one command buffer and submitted once.
 */
#ifndef TESTS_VK_LVP_H
#define TESTS_VK_LVP_H

#include <stddef.h>
#include <stdint.h>

#define LVP_ICD "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json"
#define LVP_NO_DRIVER 1

typedef struct lvp lvp;

/* One dispatch: pipeline pipe runs function fn (the push constant) on n
 * samples from sample in_off of the inputs into outputs from out_off. */
typedef struct lvp_dispatch {
	int pipe;
	uint32_t fn, in_off, out_off, n;
} lvp_dispatch;

/* Opens lavapipe (VK_ICD_FILENAMES set to LVP_ICD unless already set; the
 * physical device must be VK_DRIVER_ID_MESA_LLVMPIPE) with shaderFloat16 and
 * SignedZeroInfNanPreserve for 16 and 32 bits, which the test needs. driver
 * gets "llvmpipe Mesa 22.3.6 (LLVM 15.0.6)". 0; LVP_NO_DRIVER with one line
 * in err saying what to install; -1 with a message. */
int lvp_open(lvp **v, char *driver, size_t driverlen, char *err, size_t errlen);

/* Creates the pipelines (SPIR-V words), runs the dispatches over in (8 floats
 * per sample) into out, and destroys the pipelines. seconds gets the time of
 * pipeline creation and of the run. 0, or -1 with a message. */
int lvp_run(lvp *v, unsigned *const *spirv, const size_t *nwords, int npipe, const float *in, size_t nin,
            const lvp_dispatch *d, int nd, float *out, size_t nout, double seconds[2], char *err, size_t errlen);

void lvp_close(lvp *v);

#endif
