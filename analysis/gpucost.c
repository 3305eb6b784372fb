/*
 * gpucost.c — forms compiled to AMD ISA by Mesa RADV's null device (see
 * gpucost.h). Three stages: GLSL text (the form's bk_form_emit function in a
 * compute shader whose inputs come from a buffer, so nothing folds away),
 * SPIR-V (glslang in-process: a glslangValidator process costs ~130 ms per
 * shader), and one compute pipeline per shader and chip with its statistics
 * and disassembly captured.
 */
#include "gpucost.h"
#include "out.h"

#include <glslang/Include/glslang_c_interface.h>
#include <glslang/Public/resource_limits_c.h>
#include <vulkan/vulkan.h>

#include <ctype.h>
#include <dlfcn.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <strings.h>

/* ---- chips ------------------------------------------------------------------------ */

/* The names Mesa 22.3's null winsys matches (ac_get_family_name), one row per
 * graphics chip; anything else makes RADV abort the process, so every name is
 * checked here first. Compute-only chips (arcturus, aldebaran) and pre-gfx8
 * chips are left out: no shader stage a BRDF runs in. */
static const struct {
	const char *name, *gfx;
} chips[] = {
	{"tonga", "gfx8"},       {"iceland", "gfx8"},   {"carrizo", "gfx8"},   {"fiji", "gfx8"},
	{"stoney", "gfx8"},      {"polaris10", "gfx8"}, {"polaris11", "gfx8"}, {"polaris12", "gfx8"},
	{"vegam", "gfx8"},       {"vega10", "gfx9"},    {"vega12", "gfx9"},    {"vega20", "gfx9"},
	{"raven", "gfx9"},       {"raven2", "gfx9"},    {"renoir", "gfx9"},    {"navi10", "gfx10"},
	{"navi12", "gfx10"},     {"navi14", "gfx10"},   {"navi21", "gfx10.3"}, {"navi22", "gfx10.3"},
	{"navi23", "gfx10.3"},   {"navi24", "gfx10.3"}, {"vangogh", "gfx10.3"}, {"rembrandt", "gfx10.3"},
	{"gfx1100", "gfx11"},    {"gfx1101", "gfx11"},  {"gfx1102", "gfx11"},
};

int bk_gpucost_chip(const char *chip, const char **gfx)
{
	for (size_t i = 0; i < sizeof chips / sizeof chips[0]; i++)
		if (!strcasecmp(chip, chips[i].name)) {
			*gfx = chips[i].gfx;
			return 0;
		}
	return -1;
}

const char *bk_gpucost_chip_list(void)
{
	static char list[512];
	if (!list[0])
		for (size_t i = 0; i < sizeof chips / sizeof chips[0]; i++)
			snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", i ? "," : "", chips[i].name);
	return list;
}

int bk_gpucost_chips(char *list, const char **chip, int max, int *n, char *err, size_t errlen)
{
	const char *gfx;
	*n = 0;
	for (char *t = list, *next; t; t = next) { /* not strtok: it skips the empty items */
		if ((next = strchr(t, ',')))
			*next++ = '\0';
		if (!*t) { /* "navi21," or "a,,b": a chip left out by mistake, not nothing */
			snprintf(err, errlen, "an empty item in the list (a stray comma)");
			return -1;
		}
		if (bk_gpucost_chip(t, &gfx)) {
			snprintf(err, errlen, "unknown chip '%.60s' (known: %s)", t, bk_gpucost_chip_list());
			return -1;
		}
		for (int k = 0; k < *n; k++)
			if (!strcasecmp(chip[k], t)) { /* the same rows twice */
				snprintf(err, errlen, "'%.60s' named twice", t);
				return -1;
			}
		if (*n == max) {
			snprintf(err, errlen, "at most %d chips", max);
			return -1;
		}
		chip[(*n)++] = t;
	}
	if (*n == 0)
		snprintf(err, errlen, "no chip named");
	return *n ? 0 : -1;
}

/* ---- GLSL ------------------------------------------------------------------------- */

static int ident_char(char c)
{
	return isalnum((unsigned char)c) || c == '_';
}

/* bk_form_emit's highp GLSL as float16_t arithmetic. Its half option writes
 * mediump, which RADV ignores (identical code), so the text is rewritten:
 * float becomes float16_t, precision qualifiers go (they do not apply to
 * float16_t), and every number becomes a half literal (hf), since GLSL never
 * converts float to float16_t implicitly. Comments are copied untouched. */
static void put_half(bk_strbuf *b, const char *s)
{
	while (*s) {
		if (s[0] == '/' && s[1] == '*') {
			const char *e = strstr(s + 2, "*/");
			size_t k = e ? (size_t)(e + 2 - s) : strlen(s);
			bk_sb_put(b, "%.*s", (int)k, s);
			s += k;
		} else if (s[0] == '/' && s[1] == '/') {
			size_t k = strcspn(s, "\n");
			bk_sb_put(b, "%.*s", (int)k, s);
			s += k;
		} else if (isalpha((unsigned char)*s) || *s == '_') {
			size_t k = 0;
			while (ident_char(s[k]))
				k++;
			if (k == 5 && !strncmp(s, "float", 5))
				bk_sb_put(b, "float16_t");
			else if ((k == 5 && !strncmp(s, "highp", 5)) || (k == 7 && !strncmp(s, "mediump", 7)))
				k += strspn(s + k, " "); /* the qualifier and its space */
			else
				bk_sb_put(b, "%.*s", (int)k, s);
			s += k;
		} else if (isdigit((unsigned char)*s) || (*s == '.' && isdigit((unsigned char)s[1]))) {
			size_t k = strspn(s, "0123456789.");
			int real = memchr(s, '.', k) != NULL;
			if (s[k] == 'e' || s[k] == 'E') {
				real = 1;
				k++;
				k += s[k] == '+' || s[k] == '-';
				k += strspn(s + k, "0123456789");
			}
			bk_sb_put(b, "%.*s%shf", (int)k, s, real ? "" : ".0");
			s += k;
		} else
			bk_sb_put(b, "%c", *s++);
	}
}

/* The arguments of a form's function: its inputs in brdf.h order, which is
 * the order bk_form_emit declares them in. */
static void put_args(bk_strbuf *b, unsigned inputs)
{
	const char *sep = "";
	for (int c = 0; c < BK_IN_COUNT; c++)
		if (inputs >> c & 1) {
			bk_sb_put(b, "%s%s", sep, bk_input_name((bk_input)c));
			sep = ", ";
		}
}

/* Layout: 16 floats per invocation; input c is read from slot c and written
 * back to slot c of the output, so that every load is used in the baseline
 * too; part k's result goes to slot 8 + k (the baseline stores the first
 * input there, or 0). Inputs stay 32-bit in memory; under fp16 they are
 * converted on load and the result on store, in the baseline as well, so
 * the conversions the data path needs cancel out. */
char *bk_gpucost_glsl(const bk_form *const form[2], const double *params, unsigned inputs, int nparts, int fp16)
{
	const char *T = fp16 ? "float16_t" : "float";
	bk_strbuf b = {0};
	bk_sb_put(&b, "#version 450\n%slayout(local_size_x = 64) in;\n"
	           "layout(std430, set = 0, binding = 0) readonly buffer Inputs { float v[]; } inb;\n"
	           "layout(std430, set = 0, binding = 1) writeonly buffer Outputs { float v[]; } outb;\n\n",
	       fp16 ? "#extension GL_EXT_shader_explicit_arithmetic_types_float16 : require\n" : "");
	for (int p = 0; form && p < nparts; p++) {
		bk_emit_info info = {.name = p ? "bk_form_b" : "bk_form_a"};
		char *fn = bk_form_emit(form[p], BK_LANG_GLSL, 0, params, &info);
		if (!fn) {
			free(b.s);
			return NULL;
		}
		if (fp16) {
			bk_sb_put(&b, "// float16_t rewrite of bk_form_emit's highp text (its comment says highp)\n");
			put_half(&b, fn);
		}
		else
			bk_sb_put(&b, "%s", fn);
		bk_sb_put(&b, "\n");
		free(fn);
	}
	bk_sb_put(&b, "void main()\n{\n\tuint i = gl_GlobalInvocationID.x * 16u;\n");
	const char *first = NULL;
	for (int c = 0; c < BK_IN_COUNT; c++)
		if (inputs >> c & 1) {
			const char *name = bk_input_name((bk_input)c);
			bk_sb_put(&b, "\t%s %s = %s(inb.v[i + %du]);\n\toutb.v[i + %du] = float(%s);\n", T, name, T, c, c, name);
			first = first ? first : name;
		}
	for (int p = 0; p < nparts; p++) {
		bk_sb_put(&b, "\toutb.v[i + %du] = float(", 8 + p);
		if (form) {
			bk_sb_put(&b, "bk_form_%c(", p ? 'b' : 'a');
			put_args(&b, bk_form_inputs(form[p]));
			bk_sb_put(&b, "));\n");
		} else
			bk_sb_put(&b, "%s);\n", first ? first : "0.0");
	}
	bk_sb_put(&b, "}\n");
	if (b.oom) {
		free(b.s);
		return NULL;
	}
	return b.s;
}

/* ---- SPIR-V ----------------------------------------------------------------------- */

unsigned *bk_gpucost_spirv(const char *glsl, size_t *n, char *err, size_t errlen)
{
	static int initialised;
	if (!initialised)
		initialised = glslang_initialize_process();
	/* Vulkan 1.1 / SPIR-V 1.3: what every chip of the table's RADV takes */
	glslang_input_t in = {
		.language = GLSLANG_SOURCE_GLSL,
		.stage = GLSLANG_STAGE_COMPUTE,
		.client = GLSLANG_CLIENT_VULKAN,
		.client_version = GLSLANG_TARGET_VULKAN_1_1,
		.target_language = GLSLANG_TARGET_SPV,
		.target_language_version = GLSLANG_TARGET_SPV_1_3,
		.code = glsl,
		.default_version = 450,
		.default_profile = GLSLANG_NO_PROFILE,
		.messages = GLSLANG_MSG_SPV_RULES_BIT | GLSLANG_MSG_VULKAN_RULES_BIT,
		.resource = glslang_default_resource(),
	};
	unsigned *words = NULL;
	glslang_shader_t *sh = glslang_shader_create(&in);
	glslang_program_t *prog = NULL;
	if (!sh) {
		snprintf(err, errlen, "glslang: cannot create a shader");
		return NULL;
	}
	if (!glslang_shader_preprocess(sh, &in) || !glslang_shader_parse(sh, &in)) {
		snprintf(err, errlen, "glslang: %.400s", glslang_shader_get_info_log(sh));
		goto done;
	}
	prog = glslang_program_create();
	glslang_program_add_shader(prog, sh);
	if (!glslang_program_link(prog, GLSLANG_MSG_SPV_RULES_BIT | GLSLANG_MSG_VULKAN_RULES_BIT)) {
		snprintf(err, errlen, "glslang: link: %.400s", glslang_program_get_info_log(prog));
		goto done;
	}
	glslang_program_SPIRV_generate(prog, GLSLANG_STAGE_COMPUTE);
	*n = glslang_program_SPIRV_get_size(prog);
	words = malloc(*n * sizeof *words);
	if (!words)
		snprintf(err, errlen, "out of memory");
	else
		glslang_program_SPIRV_get(prog, words);
done:
	if (prog)
		glslang_program_delete(prog);
	glslang_shader_delete(sh);
	return words;
}

/* ---- ISA -------------------------------------------------------------------------- */

static int starts(const char *m, const char *prefix)
{
	return !strncmp(m, prefix, strlen(prefix));
}

/* A float operation: the integer multiply-adds of address arithmetic
 * (v_mad_u32_u24, v_mad_u64_u32) are not a form's. */
static int is_float(const char *m)
{
	return strstr(m, "_f16") || strstr(m, "_f32") || strstr(m, "_f64") || strstr(m, "legacy");
}

static void count_op(const char *m, bk_gpucost_stats *s, long times)
{
	static const char *const transcendental[] = {"v_rcp_", "v_exp_", "v_sqrt_", "v_rsq_", "v_log_"};
	static const char *const fma[] = {"v_fma", "v_mad", "v_mac_", "v_pk_fma_", "v_pk_mad_"};
	for (size_t i = 0; i < sizeof transcendental / sizeof transcendental[0]; i++)
		if (starts(m, transcendental[i]) && is_float(m))
			s->transcendental += times;
	for (size_t i = 0; i < sizeof fma / sizeof fma[0]; i++)
		if (starts(m, fma[i]) && is_float(m))
			s->fma += times;
	s->packed += starts(m, "v_pk_") ? times : 0;
	s->convert += starts(m, "v_cvt_") ? times : 0;
}

/* One line per instruction, mnemonic first after blanks; ACO folds a run of
 * identical lines into "(then repeated N times)", which counts the previous
 * instruction N more times. Labels ("BB0:") and comments are skipped. */
void bk_gpucost_isa_count(const char *isa, bk_gpucost_stats *s)
{
	char last[64] = "";
	while (*isa) {
		size_t len = strcspn(isa, "\n");
		const char *p = isa + strspn(isa, " \t");
		long n;
		if (sscanf(p, "(then repeated %ld times)", &n) == 1) {
			if (last[0])
				count_op(last, s, n);
		} else if (p[0] == 'v' && p[1] == '_') {
			size_t k = strcspn(p, " \t\n");
			snprintf(last, sizeof last, "%.*s", (int)(k < sizeof last ? k : sizeof last - 1), p);
			count_op(last, s, 1);
		} else if (p[0] == 's' && p[1] == '_')
			last[0] = '\0'; /* a scalar op: repeats of it count nothing here */
		isa += len + (isa[len] == '\n');
	}
}

/* ---- Vulkan: one chip ------------------------------------------------------------- */

typedef struct chip_ctx {
	VkInstance inst;
	VkPhysicalDevice pd;
	VkDevice dev;
	VkDescriptorSetLayout dsl;
	VkPipelineLayout layout;
	PFN_vkGetPipelineExecutablePropertiesKHR props;
	PFN_vkGetPipelineExecutableStatisticsKHR stats;
	PFN_vkGetPipelineExecutableInternalRepresentationsKHR irs;
	int f16; /* shaderFloat16 enabled */
} chip_ctx;

static void close_chip(chip_ctx *c)
{
	if (c->dev) {
		vkDestroyPipelineLayout(c->dev, c->layout, NULL);
		vkDestroyDescriptorSetLayout(c->dev, c->dsl, NULL);
		vkDestroyDevice(c->dev, NULL);
	}
	if (c->inst)
		vkDestroyInstance(c->inst, NULL);
	memset(c, 0, sizeof *c);
}

#define RADV_ICD "/usr/share/vulkan/icd.d/radeon_icd.x86_64.json"

/* Why there is no driver, and the one thing to do about it: the install line
 * only where RADV's ICD file is missing; a VK_ICD_FILENAMES of the user's
 * that names another file while RADV's is installed is named instead. */
static int no_driver(char *err, size_t errlen, const char *what)
{
	const char *icd = getenv("VK_ICD_FILENAMES");
	int installed = access(RADV_ICD, R_OK) == 0;
	if (installed && icd && strcmp(icd, RADV_ICD))
		snprintf(err, errlen, "no Vulkan driver for RADV's null device (%.200s): VK_ICD_FILENAMES=%.200s does not "
		         "name RADV's, which is installed: unset it, or set it to %s", what, icd, RADV_ICD);
	else if (installed)
		snprintf(err, errlen, "no Vulkan driver for RADV's null device (%.200s), though %s is there: the Vulkan "
		         "loader could not use it", what, RADV_ICD);
	else
		snprintf(err, errlen, "no Vulkan driver for RADV's null device (%.200s); %s", what, BK_GPUCOST_INSTALL);
	return BK_GPUCOST_NO_DRIVER;
}

/* The instance, the null device RADV makes for RADV_FORCE_FAMILY, and a
 * device with pipeline executable properties (and shaderFloat16 when asked
 * and the chip has it). */
static int open_chip(chip_ctx *c, int fp16, char *driver, size_t driverlen, char *err, size_t errlen)
{
	memset(c, 0, sizeof *c);
	VkApplicationInfo app = {.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO, .pApplicationName = "brdfkit gpucost",
	                         .apiVersion = VK_API_VERSION_1_2};
	VkInstanceCreateInfo ici = {.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO, .pApplicationInfo = &app};
	VkResult r = vkCreateInstance(&ici, NULL, &c->inst);
	if (r == VK_ERROR_INCOMPATIBLE_DRIVER || r == VK_ERROR_INITIALIZATION_FAILED)
		return no_driver(err, errlen, "the Vulkan loader found no driver");
	if (r != VK_SUCCESS) {
		snprintf(err, errlen, "vkCreateInstance failed (VkResult %d)", (int)r);
		return -1;
	}
	uint32_t n = 1;
	r = vkEnumeratePhysicalDevices(c->inst, &n, &c->pd);
	if ((r != VK_SUCCESS && r != VK_INCOMPLETE) || n == 0) {
		close_chip(c);
		return no_driver(err, errlen, "no physical device");
	}
	VkPhysicalDeviceDriverProperties dp = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
	VkPhysicalDeviceProperties2 pp = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, .pNext = &dp};
	vkGetPhysicalDeviceProperties2(c->pd, &pp);
	if (dp.driverID != VK_DRIVER_ID_MESA_RADV) {
		char what[300];
		snprintf(what, sizeof what, "the driver found is '%.200s', not RADV", pp.properties.deviceName);
		close_chip(c);
		return no_driver(err, errlen, what);
	}
	snprintf(driver, driverlen, "%.100s %.150s", dp.driverName, dp.driverInfo);

	VkPhysicalDeviceVulkan12Features f12 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
	VkPhysicalDeviceFeatures2 f2 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, .pNext = &f12};
	vkGetPhysicalDeviceFeatures2(c->pd, &f2);
	c->f16 = fp16 && f12.shaderFloat16;
	VkPhysicalDeviceVulkan12Features want12 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES,
	                                           .shaderFloat16 = (VkBool32)c->f16};
	VkPhysicalDevicePipelineExecutablePropertiesFeaturesKHR pe = {
		.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PIPELINE_EXECUTABLE_PROPERTIES_FEATURES_KHR,
		.pNext = &want12,
		.pipelineExecutableInfo = VK_TRUE};
	/* any queue family: pipelines are only compiled, never run */
	float prio = 1;
	VkDeviceQueueCreateInfo q = {.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO, .queueCount = 1,
	                             .pQueuePriorities = &prio};
	const char *ext = VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME;
	VkDeviceCreateInfo dci = {.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, .pNext = &pe,
	                          .queueCreateInfoCount = 1, .pQueueCreateInfos = &q,
	                          .enabledExtensionCount = 1, .ppEnabledExtensionNames = &ext};
	if ((r = vkCreateDevice(c->pd, &dci, NULL, &c->dev)) != VK_SUCCESS) {
		snprintf(err, errlen, "vkCreateDevice on '%.200s' failed (VkResult %d)", pp.properties.deviceName, (int)r);
		close_chip(c);
		return -1;
	}
	c->props = (PFN_vkGetPipelineExecutablePropertiesKHR)vkGetDeviceProcAddr(c->dev, "vkGetPipelineExecutablePropertiesKHR");
	c->stats = (PFN_vkGetPipelineExecutableStatisticsKHR)vkGetDeviceProcAddr(c->dev, "vkGetPipelineExecutableStatisticsKHR");
	c->irs = (PFN_vkGetPipelineExecutableInternalRepresentationsKHR)vkGetDeviceProcAddr(
		c->dev, "vkGetPipelineExecutableInternalRepresentationsKHR");
	VkDescriptorSetLayoutBinding bind[2];
	for (int i = 0; i < 2; i++)
		bind[i] = (VkDescriptorSetLayoutBinding){.binding = (uint32_t)i, .descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
		                                         .descriptorCount = 1, .stageFlags = VK_SHADER_STAGE_COMPUTE_BIT};
	VkDescriptorSetLayoutCreateInfo dl = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO,
	                                      .bindingCount = 2, .pBindings = bind};
	VkPipelineLayoutCreateInfo pl = {.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO, .setLayoutCount = 1,
	                                 .pSetLayouts = &c->dsl};
	if (!c->props || !c->stats || !c->irs || vkCreateDescriptorSetLayout(c->dev, &dl, NULL, &c->dsl) != VK_SUCCESS ||
	    vkCreatePipelineLayout(c->dev, &pl, NULL, &c->layout) != VK_SUCCESS) {
		snprintf(err, errlen, "'%.200s': pipeline executable properties unavailable", pp.properties.deviceName);
		close_chip(c);
		return -1;
	}
	return 0;
}

static long stat_value(const VkPipelineExecutableStatisticKHR *s)
{
	switch (s->format) {
	case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_BOOL32_KHR: return (long)s->value.b32;
	case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_INT64_KHR: return (long)s->value.i64;
	case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_UINT64_KHR: return (long)s->value.u64;
	default: return (long)s->value.f64;
	}
}

/* Statistics of one executable into s; the names are RADV's (radv_pipeline.c). */
static int read_stats(const chip_ctx *c, const VkPipelineExecutableInfoKHR *ei, bk_gpucost_stats *s)
{
	VkPipelineExecutableStatisticKHR st[64];
	uint32_t n = 64;
	for (uint32_t i = 0; i < n; i++)
		st[i] = (VkPipelineExecutableStatisticKHR){.sType = VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_STATISTIC_KHR};
	VkResult r = c->stats(c->dev, ei, &n, st);
	if (r != VK_SUCCESS && r != VK_INCOMPLETE)
		return -1;
	static const char *const names[] = {"Instructions", "VGPRs", "SGPRs", "Latency", "Inverse Throughput"};
	long *dest[] = {&s->instructions, &s->vgprs, &s->sgprs, &s->latency, &s->throughput};
	int found = 0;
	for (uint32_t i = 0; i < n; i++)
		for (int k = 0; k < 5; k++)
			if (!strcmp(st[i].name, names[k])) {
				*dest[k] += stat_value(&st[i]);
				found |= 1 << k;
			}
	return found == 31 ? 0 : -1;
}

/* The disassembly of one executable (RADV's representation named
 * "Assembly"), malloc'd, or NULL. */
static char *read_isa(const chip_ctx *c, const VkPipelineExecutableInfoKHR *ei)
{
	VkPipelineExecutableInternalRepresentationKHR ir[8];
	uint32_t n = 8;
	for (uint32_t i = 0; i < n; i++)
		ir[i] = (VkPipelineExecutableInternalRepresentationKHR){
			.sType = VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_INTERNAL_REPRESENTATION_KHR};
	VkResult r = c->irs(c->dev, ei, &n, ir); /* sizes only: pData is NULL */
	if (r != VK_SUCCESS && r != VK_INCOMPLETE)
		return NULL;
	for (uint32_t i = 0; i < n; i++) {
		if (!strstr(ir[i].name, "Assembly"))
			continue;
		uint32_t m = i + 1;
		char *text = calloc(ir[i].dataSize + 1, 1);
		if (!text)
			return NULL;
		ir[i].pData = text;
		for (uint32_t j = 0; j < i; j++)
			ir[j].dataSize = 0; /* filled only for the one asked */
		for (uint32_t j = 0; j < i; j++)
			ir[j].pData = NULL;
		r = c->irs(c->dev, ei, &m, ir);
		if (r != VK_SUCCESS && r != VK_INCOMPLETE) {
			free(text);
			return NULL;
		}
		return text;
	}
	return NULL;
}

/* One compute pipeline: its statistics and ISA counts summed over its
 * executables (a compute pipeline has one). */
static int measure(const chip_ctx *c, const unsigned *words, size_t nwords, bk_gpucost_stats *s, char **isa,
                   char *err, size_t errlen)
{
	memset(s, 0, sizeof *s);
	VkShaderModuleCreateInfo mi = {.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO,
	                               .codeSize = nwords * sizeof *words, .pCode = words};
	VkShaderModule mod;
	if (vkCreateShaderModule(c->dev, &mi, NULL, &mod) != VK_SUCCESS) {
		snprintf(err, errlen, "vkCreateShaderModule failed");
		return -1;
	}
	VkComputePipelineCreateInfo ci = {
		.sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO,
		.flags = VK_PIPELINE_CREATE_CAPTURE_STATISTICS_BIT_KHR |
		         VK_PIPELINE_CREATE_CAPTURE_INTERNAL_REPRESENTATIONS_BIT_KHR,
		.stage = {.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, .stage = VK_SHADER_STAGE_COMPUTE_BIT,
		          .module = mod, .pName = "main"},
		.layout = c->layout};
	VkPipeline pipe;
	VkResult r = vkCreateComputePipelines(c->dev, VK_NULL_HANDLE, 1, &ci, NULL, &pipe);
	vkDestroyShaderModule(c->dev, mod, NULL);
	if (r != VK_SUCCESS) {
		snprintf(err, errlen, "vkCreateComputePipelines failed (VkResult %d)", (int)r);
		return -1;
	}
	VkPipelineInfoKHR pi = {.sType = VK_STRUCTURE_TYPE_PIPELINE_INFO_KHR, .pipeline = pipe};
	VkPipelineExecutablePropertiesKHR ep[4];
	uint32_t n = 4;
	for (uint32_t i = 0; i < n; i++)
		ep[i] = (VkPipelineExecutablePropertiesKHR){.sType = VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_PROPERTIES_KHR};
	int rc = c->props(c->dev, &pi, &n, ep) == VK_SUCCESS && n > 0 ? 0 : -1;
	for (uint32_t i = 0; rc == 0 && i < n; i++) {
		VkPipelineExecutableInfoKHR ei = {.sType = VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_INFO_KHR, .pipeline = pipe,
		                                  .executableIndex = i};
		char *text = read_isa(c, &ei);
		if (!text || read_stats(c, &ei, s)) {
			free(text);
			rc = -1;
			break;
		}
		bk_gpucost_isa_count(text, s);
		if (isa && !*isa)
			*isa = text;
		else
			free(text);
	}
	if (rc)
		snprintf(err, errlen, "the driver gave no statistics or disassembly for a pipeline");
	vkDestroyPipeline(c->dev, pipe, NULL);
	return rc;
}

/* ---- the run ---------------------------------------------------------------------- */

typedef struct spirv {
	unsigned *w;
	size_t n;
} spirv;

/* A baseline per input set and part count: index inputs * 2 + parts - 1. */
#define BASE_KEYS (2 << BK_IN_COUNT)

static unsigned job_inputs(const bk_gpucost_job *j)
{
	return bk_form_inputs(j->form[0]) | (j->form[1] ? bk_form_inputs(j->form[1]) : 0);
}

static int job_key(const bk_gpucost_job *j)
{
	return (int)job_inputs(j) * 2 + (j->form[1] != NULL);
}

static int compile_glsl(char *glsl, spirv *out, const char *what, char *err, size_t errlen)
{
	if (!glsl) {
		snprintf(err, errlen, "%s: code generation failed (out of memory or parameters missing)", what);
		return -1;
	}
	char e[512];
	out->w = bk_gpucost_spirv(glsl, &out->n, e, sizeof e);
	free(glsl);
	if (!out->w) {
		snprintf(err, errlen, "%s: %s", what, e);
		return -1;
	}
	return 0;
}

static int compile_all(bk_gpucost_job *jobs, int n, int fp16, spirv *sj, spirv *sb, char *err, size_t errlen)
{
	for (int i = 0; i < n; i++) {
		char what[32];
		snprintf(what, sizeof what, "form %d", i + 1);
		int parts = jobs[i].form[1] ? 2 : 1;
		if (compile_glsl(bk_gpucost_glsl(jobs[i].form, jobs[i].params, job_inputs(&jobs[i]), parts, fp16), &sj[i],
		                 what, err, errlen))
			return -1;
		int k = job_key(&jobs[i]);
		if (!sb[k].w && compile_glsl(bk_gpucost_glsl(NULL, NULL, job_inputs(&jobs[i]), parts, fp16), &sb[k],
		                             "baseline", err, errlen))
			return -1;
	}
	return 0;
}

static void subtract(bk_gpucost_stats *d, const bk_gpucost_stats *a, const bk_gpucost_stats *b)
{
	*d = (bk_gpucost_stats){a->instructions - b->instructions, a->vgprs - b->vgprs, a->sgprs - b->sgprs,
	                        a->latency - b->latency, a->throughput - b->throughput,
	                        a->transcendental - b->transcendental, a->fma - b->fma,
	                        a->packed - b->packed, a->convert - b->convert};
}

static bk_progress_fn progress_fn; /* bk_gpucost_progress */
static void *progress_ctx;

void bk_gpucost_progress(bk_progress_fn fn, void *ctx)
{
	progress_fn = fn;
	progress_ctx = ctx;
}

static int run_chip(bk_gpucost_job *jobs, int n, int c, int nchips, int fp16, const spirv *sj, const spirv *sb,
                    char *driver, size_t driverlen, char **isa, char *err, size_t errlen)
{
	chip_ctx ctx;
	int rc = open_chip(&ctx, fp16, driver, driverlen, err, errlen);
	if (rc)
		return rc;
	static bk_gpucost_stats base[BASE_KEYS];
	static int have[BASE_KEYS];
	memset(have, 0, sizeof have);
	for (int i = 0; rc == 0 && i < n; i++) {
		jobs[i].ok[c] = !fp16 || ctx.f16;
		if (!jobs[i].ok[c])
			continue;
		int k = job_key(&jobs[i]);
		bk_gpucost_stats s;
		if (!have[k] && (rc = measure(&ctx, sb[k].w, sb[k].n, &base[k], NULL, err, errlen)) == 0)
			have[k] = 1;
		if (rc == 0 && (rc = measure(&ctx, sj[i].w, sj[i].n, &s, isa ? &isa[i * nchips + c] : NULL, err, errlen)) == 0)
			subtract(&jobs[i].net[c], &s, &base[k]);
		if (rc == 0 && progress_fn)
			progress_fn(progress_ctx, c * n + i + 1, nchips * n);
	}
	close_chip(&ctx);
	return rc;
}

/* The Vulkan loader unloads the driver (and Mesa's device-select layer) with
 * each instance, one per chip. A block the driver keeps in a global would
 * then read as a leak to LeakSanitizer, in a module it can no longer name
 * (seen in make test, now and then). Loaded once more here and never
 * unloaded, the driver stays mapped: its globals keep what they hold, a
 * report names the module, and the driver's start-up runs once per process.
 * RADV reads RADV_FORCE_FAMILY when an instance enumerates its devices, not
 * when it is loaded (tests/gpucost.sh checks per-chip ISA facts). Only the
 * default ICD is pinned; a failure is left to vkCreateInstance to report. */
static void pin_driver(void)
{
	const char *icd = getenv("VK_ICD_FILENAMES");
	if (!icd || strcmp(icd, RADV_ICD))
		return;
	dlopen("libvulkan_radeon.so", RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
	dlopen("libVkLayer_MESA_device_select.so", RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
}

int bk_gpucost_run(bk_gpucost_job *jobs, int n, const char *const *chip, int nchips, int fp16, char *driver,
                   size_t driverlen, char **isa, char *err, size_t errlen)
{
	for (int k = 0; isa && k < n * nchips; k++)
		isa[k] = NULL;
	if (nchips > BK_GPUCOST_MAX_CHIPS) {
		snprintf(err, errlen, "at most %d chips", BK_GPUCOST_MAX_CHIPS);
		return -1;
	}
	for (int c = 0; c < nchips; c++) {
		const char *gfx;
		if (bk_gpucost_chip(chip[c], &gfx)) { /* RADV would abort the process */
			snprintf(err, errlen, "unknown chip '%.100s'", chip[c]);
			return -1;
		}
	}
	/* the ICD a user points at is respected (and checked to be RADV below) */
	setenv("VK_ICD_FILENAMES", RADV_ICD, 0);
	pin_driver();
	setenv("MESA_SHADER_CACHE_DISABLE", "true", 1); /* a cache hit captures no statistics */
	spirv *sj = calloc((size_t)n + 1, sizeof *sj), *sb = calloc(BASE_KEYS, sizeof *sb);
	int rc = sj && sb ? 0 : (snprintf(err, errlen, "out of memory"), -1);
	if (rc == 0)
		rc = compile_all(jobs, n, fp16, sj, sb, err, errlen);
	for (int c = 0; rc == 0 && c < nchips; c++) {
		setenv("RADV_FORCE_FAMILY", chip[c], 1);
		rc = run_chip(jobs, n, c, nchips, fp16, sj, sb, driver, driverlen, isa, err, errlen);
	}
	for (int i = 0; sj && i < n; i++)
		free(sj[i].w);
	for (int k = 0; sb && k < BASE_KEYS; k++)
		free(sb[k].w);
	free(sj);
	free(sb);
	return rc;
}

/* ---- calibration ------------------------------------------------------------------ */

/* Average ranks (1-based) of x into r: O(n^2), n is a catalog's size. */
static void ranks(const double *x, int n, double *r)
{
	for (int i = 0; i < n; i++) {
		int below = 0, equal = 0;
		for (int j = 0; j < n; j++) {
			below += x[j] < x[i];
			equal += x[j] == x[i];
		}
		r[i] = below + (equal + 1) / 2.0;
	}
}

double bk_gpucost_spearman(const double *x, const double *y, int n)
{
	if (n < 2)
		return NAN;
	double *rx = malloc(2 * (size_t)n * sizeof *rx);
	if (!rx)
		return NAN;
	double *ry = rx + n, mx = 0, my = 0, sxy = 0, sxx = 0, syy = 0;
	ranks(x, n, rx);
	ranks(y, n, ry);
	for (int i = 0; i < n; i++) {
		mx += rx[i] / n;
		my += ry[i] / n;
	}
	for (int i = 0; i < n; i++) {
		sxy += (rx[i] - mx) * (ry[i] - my);
		sxx += (rx[i] - mx) * (rx[i] - mx);
		syy += (ry[i] - my) * (ry[i] - my);
	}
	free(rx);
	return sxx > 0 && syy > 0 ? sxy / sqrt(sxx * syy) : NAN;
}

int bk_gpucost_fit2(const double *a, const double *b, const double *y, int n, double *wa, double *wb)
{
	double aa = 0, ab = 0, bb = 0, ay = 0, by = 0;
	for (int i = 0; i < n; i++) {
		aa += a[i] * a[i];
		ab += a[i] * b[i];
		bb += b[i] * b[i];
		ay += a[i] * y[i];
		by += b[i] * y[i];
	}
	double det = aa * bb - ab * ab;
	/* relative to the scale of the sums: collinear columns leave only rounding */
	if (!(fabs(det) > 1e-12 * (aa * bb)))
		return -1;
	*wa = (ay * bb - by * ab) / det;
	*wb = (aa * by - ab * ay) / det;
	return 0;
}

int bk_gpucost_forms(const bk_form *const *a, const bk_form *const *b, const double *const *params, int n,
                     const char *const *chips, int nchips, double *insn, double *transc, double *vgprs,
                     char *driver, size_t driverlen, char *err, size_t errlen)
{
	bk_gpucost_job *jobs = calloc((size_t)n + 1, sizeof *jobs);
	int *at = calloc((size_t)n + 1, sizeof *at), m = 0, rc = jobs && at ? 0 : -1;
	if (rc)
		snprintf(err, errlen, "out of memory");
	for (int i = 0; !rc && i < n; i++) {
		if (!a[i])
			continue;
		jobs[m].form[0] = a[i];
		jobs[m].form[1] = b ? b[i] : NULL;
		jobs[m].params = params[i];
		at[m++] = i;
	}
	double *const col[3] = {insn, transc, vgprs};
	for (int q = 0; q < 3; q++)
		for (int k = 0; col[q] && k < n * nchips; k++)
			col[q][k] = NAN;
	if (!rc && m > 0)
		rc = bk_gpucost_run(jobs, m, chips, nchips, 0, driver, driverlen, NULL, err, errlen);
	for (int j = 0; !rc && j < m; j++)
		for (int c = 0; c < nchips; c++) {
			const bk_gpucost_stats *s = &jobs[j].net[c];
			const double v[3] = {(double)s->instructions, (double)s->transcendental, (double)s->vgprs};
			for (int q = 0; q < 3; q++)
				if (col[q] && jobs[j].ok[c])
					col[q][at[j] * nchips + c] = v[q];
		}
	free(jobs);
	free(at);
	return rc;
}

int bk_gpucost_texts(const char *const *a, const char *const *b, const double *const *params, int n,
                     const char *const *chips, int nchips, double *insn, double *transc, double *vgprs,
                     char *driver, size_t driverlen, char *err, size_t errlen)
{
	bk_form **f = calloc(2 * (size_t)n + 1, sizeof *f), **fb = f ? f + n : NULL;
	int rc = f ? 0 : -1;
	if (rc)
		snprintf(err, errlen, "out of memory");
	for (int i = 0; !rc && i < n; i++)
		for (int p = 0; !rc && a[i] && p < 1 + (b && b[i] != NULL); p++) {
			bk_form_error fe;
			const char *text = p ? b[i] : a[i];
			if (!((p ? fb : f)[i] = bk_form_parse(text, &fe))) {
				snprintf(err, errlen, "'%.200s':1:%d: %s", text, fe.column, fe.message);
				rc = -1;
			}
		}
	if (!rc)
		rc = bk_gpucost_forms((const bk_form *const *)f, b ? (const bk_form *const *)fb : NULL, params, n, chips,
		                      nchips, insn, transc, vgprs, driver, driverlen, err, errlen);
	for (int i = 0; f && i < 2 * n; i++)
		bk_form_free(f[i]);
	free(f);
	return rc;
}

int bk_gpucost_check(const char *const *chips, int nchips, char *driver, size_t driverlen, char *err,
                     size_t errlen)
{
	const char *probe[1] = {"LoH"};
	const double *none[1] = {NULL};
	return bk_gpucost_texts(probe, NULL, none, 1, chips, nchips, NULL, NULL, NULL, driver, driverlen, err, errlen);
}
