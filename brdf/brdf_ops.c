/*
 * brdf_ops.c — the public reading of the op table and of a form's code
 * (brdf_ops.h).
 */
#include "ir.h"

int bk_op_arity(int op) { return op >= 0 && op < BK_OP_COUNT ? bk_opinfo_table[op].arity : -1; }

const char *bk_op_name(int op) { return op >= 0 && op < BK_OP_COUNT ? bk_opinfo_table[op].name : NULL; }

const bk_instr *bk_form_code(const bk_form *f, int *n, int *out)
{
	if (n)
		*n = f->n;
	if (out)
		*out = f->out;
	return f->code;
}
