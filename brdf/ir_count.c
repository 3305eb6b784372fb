/*
 * ir_count.c — op counts per class from the opcode table's classes, over the
 * instructions the result uses (after folding, sharing, power expansion and
 * multiply-add fusion), and the one-number cost model.
 */
#include "ir.h"

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
		for (int j = 0; j < 3; j++) {
			bk_opclass k = info->cls[j];
			if (k == BK_K_FREE)
				continue;
			ops->n[k]++;
			if (bk_opclass_is_complex(k))
				ops->complex++;
			else
				ops->simple++;
		}
	}
}

double bk_ops_cost(const bk_ops *ops, double simple_cost, double complex_cost)
{
	return ops->simple * simple_cost + ops->complex * complex_cost;
}
