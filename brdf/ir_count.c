/*
 * ir_count.c — op counts per class from the opcode table's classes, over the
 * instructions the result uses (after folding, sharing, power expansion and
 * multiply-add fusion), and the one-number cost model.
 */
#include "ir.h"

#include <string.h>

static const char *const class_names[BK_K_COUNT] = {
	"free", "add", "mul", "mad", "minmax", "saturate", "rcp", "div", "sqrt", "rsqrt", "exp2", "log2",
};

const char *bk_opclass_name(bk_opclass k) { return class_names[k]; }

/* Complex: what runs on the transcendental unit (one per cycle on the talk's
 * PowerVR; rcp, rsqrt, sqrt, exp2, log2, and a division's reciprocal). */
int bk_opclass_is_complex(bk_opclass k)
{
	return k >= BK_K_RCP && k <= BK_K_LOG2;
}

void bk_form_count(const bk_form *f, bk_ops *ops)
{
	*ops = (bk_ops){{0}, 0, 0};
	for (int i = 0; i < f->n; i++) {
		const bk_opinfo *info = &bk_opinfo_table[f->code[i].op];
		/* a clamp with a bound computed at run time is emitted as min(max()) */
		int twice = f->code[i].op == BK_OP_CLAMP && !bk_ir_clamp_fixed_bounds(f, &f->code[i]);
		for (int j = 0; j < 3; j++) {
			bk_opclass k = info->cls[j];
			if (k == BK_K_FREE)
				continue;
			ops->n[k] += 1 + twice;
			if (bk_opclass_is_complex(k))
				ops->complex += 1 + twice;
			else
				ops->simple += 1 + twice;
		}
	}
}

double bk_ops_cost(const bk_ops *ops, double simple_cost, double complex_cost)
{
	return ops->simple * simple_cost + ops->complex * complex_cost;
}

/*
 * The cost models. The aco- weights are what `brdfkit gpucost --calibrate
 * --chips CHIP` prints given the front.csv of each search in results/search
 * (fp32, the 39 catalog forms and the 124 members of make results' nine
 * double search fronts, ms and sheen included since issue 41, Mesa 22.3.6
 * RADV/ACO, Debian 12), rounded to 4 digits; tests/gpucost.sh reruns the calibration
 * and fails if they fit its counts worse than its own weights by over 0.1 %
 * of the rms residual (a weight 5 % off does; a front's change in the third
 * decimal does not). ACO issues a
 * transcendental as one instruction, hence complex weights of 1.5-2.3, not
 * the IR's 4: that 4 prices throughput on a mobile GPU's one-per-cycle unit,
 * which an instruction count does not see.
 */
static const bk_cost_model cost_models[] = {
	{"ir", BK_COST_SIMPLE, BK_COST_COMPLEX}, /* the talk: many simple ops per cycle, only one complex */
	{"aco-polaris10", 1.064, 1.666},         /* GCN 4, gfx8 */
	{"aco-vega10", 1.064, 1.666},            /* GCN 5, gfx9 */
	{"aco-navi21", 1.004, 1.553},            /* RDNA 2, gfx10.3 */
	{"aco-gfx1100", 1.005, 2.293},           /* RDNA 3, gfx11 */
};

const bk_cost_model *bk_cost_model_find(const char *name)
{
	for (size_t i = 0; i < sizeof cost_models / sizeof cost_models[0]; i++)
		if (!strcmp(cost_models[i].name, name))
			return &cost_models[i];
	return NULL;
}

const bk_cost_model *bk_cost_model_at(size_t i)
{
	return i < sizeof cost_models / sizeof cost_models[0] ? &cost_models[i] : NULL;
}

int bk_form_count_add(const char *text, bk_ops *ops)
{
	bk_form_error fe;
	bk_form *f = bk_form_parse(text, &fe);
	if (!f)
		return -1;
	bk_ops o;
	bk_form_count(f, &o);
	bk_form_free(f);
	for (int c = 0; c < BK_K_COUNT; c++)
		ops->n[c] += o.n[c];
	ops->simple += o.simple;
	ops->complex += o.complex;
	return 0;
}
