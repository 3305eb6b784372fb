/*
 * lvp.c — compute dispatches on Mesa's lavapipe, the shader head and the
 * float16_t rewrite (see lvp.h).
 */
#include "lvp.h"

#include "clock.h"
#include "half.h"

#include <vulkan/vulkan.h>

#include <ctype.h>
#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct bk_lvp {
	VkInstance inst;
	VkPhysicalDevice pd;
	VkDevice dev;
	VkQueue queue;
	uint32_t family;
	VkDescriptorSetLayout dsl;
	VkPipelineLayout layout;
	VkCommandPool pool;
	VkDescriptorPool dpool;
};

void bk_lvp_close(bk_lvp *v)
{
	if (!v)
		return;
	if (v->dev) {
		vkDestroyDescriptorPool(v->dev, v->dpool, NULL);
		vkDestroyCommandPool(v->dev, v->pool, NULL);
		vkDestroyPipelineLayout(v->dev, v->layout, NULL);
		vkDestroyDescriptorSetLayout(v->dev, v->dsl, NULL);
		vkDestroyDevice(v->dev, NULL);
	}
	if (v->inst)
		vkDestroyInstance(v->inst, NULL);
	free(v);
}

static int no_driver(char *err, size_t errlen, const char *what)
{
	snprintf(err, errlen, "no lavapipe (%s); install it: apt-get install mesa-vulkan-drivers", what);
	return BK_LVP_NO_DRIVER;
}

/* The llvmpipe physical device, its driver string and what it offers. */
static int pick(bk_lvp *v, char *driver, size_t driverlen, char *err, size_t errlen)
{
	VkPhysicalDevice pd[16];
	uint32_t n = 16;
	VkResult r = vkEnumeratePhysicalDevices(v->inst, &n, pd);
	if ((r != VK_SUCCESS && r != VK_INCOMPLETE) || n == 0)
		return no_driver(err, errlen, "the Vulkan loader found no physical device");
	for (uint32_t i = 0; i < n; i++) {
		VkPhysicalDeviceVulkan12Properties p12 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_PROPERTIES};
		VkPhysicalDeviceProperties2 pp = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, .pNext = &p12};
		vkGetPhysicalDeviceProperties2(pd[i], &pp);
		if (p12.driverID != VK_DRIVER_ID_MESA_LLVMPIPE)
			continue;
		VkPhysicalDeviceVulkan12Features f12 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
		VkPhysicalDeviceFeatures2 f2 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, .pNext = &f12};
		vkGetPhysicalDeviceFeatures2(pd[i], &f2);
		snprintf(driver, driverlen, "%.60s %.120s", p12.driverName, p12.driverInfo);
		if (!f12.shaderFloat16 || !p12.shaderSignedZeroInfNanPreserveFloat16 ||
		    !p12.shaderSignedZeroInfNanPreserveFloat32) {
			snprintf(err, errlen, "%s lacks shaderFloat16 or SignedZeroInfNanPreserve, which the test needs", driver);
			return -1;
		}
		v->pd = pd[i];
		return 0;
	}
	return no_driver(err, errlen, "no physical device is llvmpipe");
}

static int make_device(bk_lvp *v, char *err, size_t errlen)
{
	VkQueueFamilyProperties qf[16];
	uint32_t nq = 16;
	vkGetPhysicalDeviceQueueFamilyProperties(v->pd, &nq, qf);
	v->family = UINT32_MAX;
	for (uint32_t i = 0; i < nq && v->family == UINT32_MAX; i++)
		if (qf[i].queueFlags & VK_QUEUE_COMPUTE_BIT)
			v->family = i;
	if (v->family == UINT32_MAX) {
		snprintf(err, errlen, "lavapipe has no compute queue");
		return -1;
	}
	float prio = 1;
	VkDeviceQueueCreateInfo q = {.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO, .queueFamilyIndex = v->family,
	                             .queueCount = 1, .pQueuePriorities = &prio};
	VkPhysicalDeviceVulkan12Features want = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES,
	                                         .shaderFloat16 = VK_TRUE};
	VkDeviceCreateInfo dci = {.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, .pNext = &want,
	                          .queueCreateInfoCount = 1, .pQueueCreateInfos = &q};
	VkResult r = vkCreateDevice(v->pd, &dci, NULL, &v->dev);
	if (r != VK_SUCCESS) {
		snprintf(err, errlen, "vkCreateDevice on lavapipe failed (VkResult %d)", (int)r);
		return -1;
	}
	vkGetDeviceQueue(v->dev, v->family, 0, &v->queue);
	VkDescriptorSetLayoutBinding bind[2];
	for (int i = 0; i < 2; i++)
		bind[i] = (VkDescriptorSetLayoutBinding){.binding = (uint32_t)i,
		                                         .descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
		                                         .descriptorCount = 1, .stageFlags = VK_SHADER_STAGE_COMPUTE_BIT};
	VkDescriptorSetLayoutCreateInfo dl = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO,
	                                      .bindingCount = 2, .pBindings = bind};
	VkPushConstantRange push = {.stageFlags = VK_SHADER_STAGE_COMPUTE_BIT, .size = 4 * sizeof(uint32_t)};
	VkPipelineLayoutCreateInfo pl = {.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO, .setLayoutCount = 1,
	                                 .pSetLayouts = &v->dsl, .pushConstantRangeCount = 1,
	                                 .pPushConstantRanges = &push};
	VkCommandPoolCreateInfo cp = {.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
	                              .flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT,
	                              .queueFamilyIndex = v->family};
	VkDescriptorPoolSize ps = {.type = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, .descriptorCount = 2};
	VkDescriptorPoolCreateInfo dp = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO,
	                                 .flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT, .maxSets = 1,
	                                 .poolSizeCount = 1, .pPoolSizes = &ps};
	if (vkCreateDescriptorSetLayout(v->dev, &dl, NULL, &v->dsl) != VK_SUCCESS ||
	    vkCreatePipelineLayout(v->dev, &pl, NULL, &v->layout) != VK_SUCCESS ||
	    vkCreateCommandPool(v->dev, &cp, NULL, &v->pool) != VK_SUCCESS ||
	    vkCreateDescriptorPool(v->dev, &dp, NULL, &v->dpool) != VK_SUCCESS) {
		snprintf(err, errlen, "lavapipe: cannot create the layouts or pools");
		return -1;
	}
	return 0;
}

/* As analysis/gpucost.c does for RADV: the loader unloads the driver with the
 * instance, and a block the driver keeps in a global would then read as a
 * leak in a module LeakSanitizer cannot name. Loaded once more and never
 * unloaded, lavapipe stays mapped and a report names it (tests/lsan.supp).
 * Only the default ICD is pinned; a failure is vkCreateInstance's to report. */
static void pin_driver(void)
{
	const char *icd = getenv("VK_ICD_FILENAMES");
	if (!icd || strcmp(icd, BK_LVP_ICD))
		return;
	dlopen("libvulkan_lvp.so", RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
	dlopen("libVkLayer_MESA_device_select.so", RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
}

int bk_lvp_open(bk_lvp **out, char *driver, size_t driverlen, char *err, size_t errlen)
{
	/* lavapipe, not whatever else the loader finds (a GPU, RADV's null device);
	 * a pipeline cache hit would skip the compile the run should time */
	setenv("VK_ICD_FILENAMES", BK_LVP_ICD, 0);
	setenv("MESA_SHADER_CACHE_DISABLE", "true", 1);
	pin_driver();
	bk_lvp *v = calloc(1, sizeof *v);
	if (!v) {
		snprintf(err, errlen, "out of memory");
		return -1;
	}
	VkApplicationInfo app = {.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO, .pApplicationName = "brdfkit",
	                         .apiVersion = VK_API_VERSION_1_2};
	VkInstanceCreateInfo ici = {.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO, .pApplicationInfo = &app};
	VkResult r = vkCreateInstance(&ici, NULL, &v->inst);
	int rc;
	if (r == VK_ERROR_INCOMPATIBLE_DRIVER || r == VK_ERROR_INITIALIZATION_FAILED)
		rc = no_driver(err, errlen, "the Vulkan loader found no driver at " BK_LVP_ICD);
	else if (r != VK_SUCCESS)
		rc = (snprintf(err, errlen, "vkCreateInstance failed (VkResult %d)", (int)r), -1);
	else if ((rc = pick(v, driver, driverlen, err, errlen)) == 0)
		rc = make_device(v, err, errlen);
	if (rc) {
		bk_lvp_close(v);
		return rc;
	}
	*out = v;
	return 0;
}

/* ---- a run -------------------------------------------------------------------- */

typedef struct buffer {
	VkBuffer b;
	VkDeviceMemory m;
	void *map;
} buffer;

static int make_buffer(bk_lvp *v, size_t size, buffer *b)
{
	VkBufferCreateInfo bi = {.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO, .size = size ? size : 4,
	                         .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT};
	if (vkCreateBuffer(v->dev, &bi, NULL, &b->b) != VK_SUCCESS)
		return -1;
	VkMemoryRequirements req;
	vkGetBufferMemoryRequirements(v->dev, b->b, &req);
	VkPhysicalDeviceMemoryProperties mp;
	vkGetPhysicalDeviceMemoryProperties(v->pd, &mp);
	const VkMemoryPropertyFlags want = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
	for (uint32_t i = 0; i < mp.memoryTypeCount; i++) {
		if (!(req.memoryTypeBits >> i & 1) || (mp.memoryTypes[i].propertyFlags & want) != want)
			continue;
		VkMemoryAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO, .allocationSize = req.size,
		                           .memoryTypeIndex = i};
		if (vkAllocateMemory(v->dev, &ai, NULL, &b->m) != VK_SUCCESS)
			return -1;
		if (vkBindBufferMemory(v->dev, b->b, b->m, 0) != VK_SUCCESS ||
		    vkMapMemory(v->dev, b->m, 0, VK_WHOLE_SIZE, 0, &b->map) != VK_SUCCESS)
			return -1;
		return 0;
	}
	return -1;
}

static void free_buffer(bk_lvp *v, buffer *b)
{
	if (b->m)
		vkFreeMemory(v->dev, b->m, NULL);
	if (b->b)
		vkDestroyBuffer(v->dev, b->b, NULL);
}

static int make_pipelines(bk_lvp *v, unsigned *const *spirv, const size_t *nwords, int n, VkPipeline *pipe,
                          char *err, size_t errlen)
{
	for (int i = 0; i < n; i++) {
		VkShaderModuleCreateInfo mi = {.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO,
		                               .codeSize = nwords[i] * sizeof **spirv, .pCode = spirv[i]};
		VkShaderModule mod;
		if (vkCreateShaderModule(v->dev, &mi, NULL, &mod) != VK_SUCCESS) {
			snprintf(err, errlen, "shader %d: vkCreateShaderModule failed", i);
			return -1;
		}
		VkComputePipelineCreateInfo ci = {
			.sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO,
			.stage = {.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
			          .stage = VK_SHADER_STAGE_COMPUTE_BIT, .module = mod, .pName = "main"},
			.layout = v->layout};
		VkResult r = vkCreateComputePipelines(v->dev, VK_NULL_HANDLE, 1, &ci, NULL, &pipe[i]);
		vkDestroyShaderModule(v->dev, mod, NULL);
		if (r != VK_SUCCESS) {
			snprintf(err, errlen, "shader %d: vkCreateComputePipelines failed (VkResult %d)", i, (int)r);
			return -1;
		}
	}
	return 0;
}

/* One command buffer: every dispatch (they write disjoint outputs), one submit. */
static int dispatch_all(bk_lvp *v, VkDescriptorSet set, const VkPipeline *pipe, const bk_lvp_dispatch *d, int nd,
                        char *err, size_t errlen)
{
	VkCommandBufferAllocateInfo ca = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
	                                  .commandPool = v->pool, .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
	                                  .commandBufferCount = 1};
	VkCommandBuffer cb;
	if (vkAllocateCommandBuffers(v->dev, &ca, &cb) != VK_SUCCESS) {
		snprintf(err, errlen, "vkAllocateCommandBuffers failed");
		return -1;
	}
	VkCommandBufferBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
	                               .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
	vkBeginCommandBuffer(cb, &bi);
	vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, v->layout, 0, 1, &set, 0, NULL);
	int bound = -1;
	for (int i = 0; i < nd; i++) {
		if (d[i].pipe != bound)
			vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipe[bound = d[i].pipe]);
		uint32_t pc[4] = {d[i].fn, d[i].in_off, d[i].out_off, d[i].n};
		vkCmdPushConstants(cb, v->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof pc, pc);
		vkCmdDispatch(cb, (d[i].n + 63) / 64, 1, 1);
	}
	VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER, .srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT,
	                      .dstAccessMask = VK_ACCESS_HOST_READ_BIT};
	vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &mb, 0, NULL,
	                     0, NULL);
	int rc = vkEndCommandBuffer(cb) == VK_SUCCESS ? 0 : -1;
	VkFence fence = VK_NULL_HANDLE;
	VkFenceCreateInfo fi = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
	VkSubmitInfo si = {.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO, .commandBufferCount = 1, .pCommandBuffers = &cb};
	if (!rc && (vkCreateFence(v->dev, &fi, NULL, &fence) != VK_SUCCESS ||
	            vkQueueSubmit(v->queue, 1, &si, fence) != VK_SUCCESS ||
	            vkWaitForFences(v->dev, 1, &fence, VK_TRUE, UINT64_MAX) != VK_SUCCESS))
		rc = -1;
	if (rc)
		snprintf(err, errlen, "lavapipe: recording, submitting or waiting failed");
	if (fence)
		vkDestroyFence(v->dev, fence, NULL);
	vkFreeCommandBuffers(v->dev, v->pool, 1, &cb);
	return rc;
}

int bk_lvp_run(bk_lvp *v, unsigned *const *spirv, const size_t *nwords, int npipe, const float *in, size_t nin,
            const bk_lvp_dispatch *d, int nd, float *out, size_t nout, double seconds[2], char *err, size_t errlen)
{
	buffer bin = {0}, bout = {0};
	VkPipeline *pipe = calloc((size_t)npipe + 1, sizeof *pipe);
	VkDescriptorSet set = VK_NULL_HANDLE;
	int rc = pipe ? 0 : -1;
	if (rc)
		snprintf(err, errlen, "out of memory");
	else if (make_buffer(v, nin * sizeof *in, &bin) || make_buffer(v, nout * sizeof *out, &bout)) {
		snprintf(err, errlen, "lavapipe: cannot make buffers of %zu and %zu floats", nin, nout);
		rc = -1;
	}
	VkDescriptorSetAllocateInfo sa = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO,
	                                  .descriptorPool = v->dpool, .descriptorSetCount = 1, .pSetLayouts = &v->dsl};
	if (!rc && vkAllocateDescriptorSets(v->dev, &sa, &set) != VK_SUCCESS) {
		snprintf(err, errlen, "vkAllocateDescriptorSets failed");
		rc = -1;
	}
	if (!rc) {
		memcpy(bin.map, in, nin * sizeof *in);
		memset(bout.map, 0xff, nout * sizeof *out); /* NaN: an output never written shows */
		VkDescriptorBufferInfo info[2] = {{bin.b, 0, VK_WHOLE_SIZE}, {bout.b, 0, VK_WHOLE_SIZE}};
		VkWriteDescriptorSet w[2];
		for (int i = 0; i < 2; i++)
			w[i] = (VkWriteDescriptorSet){.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstSet = set,
			                              .dstBinding = (uint32_t)i, .descriptorCount = 1,
			                              .descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
			                              .pBufferInfo = &info[i]};
		vkUpdateDescriptorSets(v->dev, 2, w, 0, NULL);
		double t0 = bk_clock_now();
		rc = make_pipelines(v, spirv, nwords, npipe, pipe, err, errlen);
		double t1 = bk_clock_now();
		if (!rc)
			rc = dispatch_all(v, set, pipe, d, nd, err, errlen);
		seconds[0] = t1 - t0;
		seconds[1] = bk_clock_now() - t1;
		if (!rc)
			memcpy(out, bout.map, nout * sizeof *out);
	}
	for (int i = 0; pipe && i < npipe; i++)
		if (pipe[i])
			vkDestroyPipeline(v->dev, pipe[i], NULL);
	if (set)
		vkFreeDescriptorSets(v->dev, v->dpool, 1, &set);
	free_buffer(v, &bin);
	free_buffer(v, &bout);
	free(pipe);
	return rc;
}

/* ---- the GLSL side ------------------------------------------------------------ */

int bk_lvp_ident_char(char c)
{
	return isalnum((unsigned char)c) || c == '_';
}

/* The length of a float literal at s (digits, a '.', an exponent), 0 if
 * there is none or it runs into an identifier (0x7f800000u, 8u). */
size_t bk_lvp_literal_len(const char *s)
{
	if (!isdigit((unsigned char)*s) && !(*s == '.' && isdigit((unsigned char)s[1])))
		return 0;
	size_t k = strspn(s, "0123456789.");
	if (s[k] == 'e' || s[k] == 'E') {
		size_t j = k + 1 + (s[k + 1] == '+' || s[k + 1] == '-');
		if (isdigit((unsigned char)s[j]))
			k = j + strspn(s + j, "0123456789");
	}
	return bk_lvp_ident_char(s[k]) ? 0 : k;
}

/* The length of the comment at s, 0 if s is no comment. */
size_t bk_lvp_comment_len(const char *s)
{
	if (s[0] == '/' && s[1] == '*') {
		const char *e = strstr(s + 2, "*/");
		return e ? (size_t)(e + 2 - s) : strlen(s);
	}
	return s[0] == '/' && s[1] == '/' ? strcspn(s, "\n") : 0;
}

/* A comment at s copied whole; its length, or 0 if s is no comment. */
static size_t put_comment(bk_strbuf *b, const char *s)
{
	size_t k = bk_lvp_comment_len(s);
	if (k)
		bk_sb_put(b, "%.*s", (int)k, s);
	return k;
}

/* v as the exact decimal of its half rounding: a half has at most 11
 * significant bits and 24 fraction bits, which 30 digits always spell out. */
static void put_half_literal(bk_strbuf *b, double v)
{
	char num[64];
	double h = bk_half_round_inline((float)v);
	if (isinf(h)) { /* past 65504: no literal spells it (the IR's f16 has it infinite too) */
		bk_sb_put(b, "float16_t(uintBitsToFloat(0x7f800000u))");
		return;
	}
	snprintf(num, sizeof num, "%.30g", h);
	bk_sb_put(b, "%s%shf", num, strpbrk(num, ".e") ? "" : ".0");
}

char *bk_lvp_half_text(const char *s)
{
	bk_strbuf b = {0};
	while (*s) {
		size_t k = put_comment(&b, s);
		if (k) {
			s += k;
			continue;
		}
		if (isalpha((unsigned char)*s) || *s == '_') {
			k = 0;
			while (bk_lvp_ident_char(s[k]))
				k++;
			if (k == 5 && !strncmp(s, "float", 5))
				bk_sb_put(&b, "float16_t");
			else if ((k == 5 && !strncmp(s, "highp", 5)) || (k == 7 && !strncmp(s, "mediump", 7)) ||
			         (k == 4 && !strncmp(s, "lowp", 4)))
				k += strspn(s + k, " "); /* the qualifier and its space */
			else if (k == 15 && !strncmp(s, "uintBitsToFloat", 15) && s[k] == '(') {
				size_t close = strcspn(s, ")"); /* its argument is one literal */
				bk_sb_put(&b, "float16_t(%.*s)", (int)(close + 1), s);
				k = close + (s[close] == ')');
			} else
				bk_sb_put(&b, "%.*s", (int)k, s);
			s += k;
		} else if ((k = bk_lvp_literal_len(s)) > 0) {
			put_half_literal(&b, strtod(s, NULL));
			s += k;
		} else
			bk_sb_put(&b, "%c", *s++);
	}
	if (b.oom) {
		free(b.s);
		return NULL;
	}
	return b.s;
}

/* The header: SignedZeroInfNanPreserve for the arithmetic's width, so that
 * NaN and infinities mean something (without it the driver may assume there
 * are none: "Precision and Operation of SPIR-V Instructions"); glslang keeps
 * one such mode per id, and the conversions of the f16 shader's main are exact. */
void bk_lvp_head(bk_strbuf *b, bk_precision prec)
{
	int w = prec == BK_F16 ? 16 : 32;
	bk_sb_put(b, "#version 450\n%s#extension GL_EXT_spirv_intrinsics : require\n"
	             "spirv_execution_mode(extensions = [\"SPV_KHR_float_controls\"], capabilities = [4466], 4461, %d);\n"
	             "layout(local_size_x = 64) in;\n"
	             "layout(std430, set = 0, binding = 0) readonly buffer Inputs { float v[]; } inb;\n"
	             "layout(std430, set = 0, binding = 1) writeonly buffer Outputs { float v[]; } outb;\n"
	             "layout(push_constant) uniform Pick { uint fn, in_off, out_off, n; } pc;\n\n",
	          prec == BK_F16 ? "#extension GL_EXT_shader_explicit_arithmetic_types_float16 : require\n" : "", w);
}

