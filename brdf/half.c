/*
 * half.c — the binary16 rounding rule's public face (the rule is in half.h).
 */
#include "brdf.h"
#include "half.h"

double bk_half_round(double x)
{
	return bk_half_round_inline(x);
}
