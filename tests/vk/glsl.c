/*
 * glsl.c — the batched compute shaders of tests/vk and the negative
 * control's perturbation (see glsl.h); the float16_t rewrite and the shader
 * head are analysis/lvp.c's.
 */
#include "glsl.h"

#include "lvp.h" /* analysis/lvp.h */
#include "out.h"

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

int vk_calls(const char *glsl, const char *fn)
{
	size_t n = strlen(fn);
	for (const char *s = glsl; *s;) {
		size_t k = bk_lvp_comment_len(s);
		if (k)
			s += k;
		else if (!strncmp(s, fn, n) && (s == glsl || !bk_lvp_ident_char(s[-1])) && s[n + strspn(s + n, " ")] == '(')
			return 1;
		else
			s++;
	}
	return 0;
}

/* ---- the shader --------------------------------------------------------------- */

static void put_main(bk_strbuf *b, const vk_fn *const *fns, int n, bk_precision prec)
{
	const char *T = prec == BK_F16 ? "float16_t" : "float";
	bk_sb_put(b, "void main()\n{\n\tuint k = gl_GlobalInvocationID.x;\n\tif (k >= pc.n)\n\t\treturn;\n"
	             "\tuint i = (pc.in_off + k) * 8u;\n");
	for (int c = 0; c < BK_IN_COUNT; c++)
		bk_sb_put(b, "\t%s %s = %s(inb.v[i + %du]);\n", T, bk_input_name((bk_input)c), T, c);
	bk_sb_put(b, "\tfloat bk_res = 0.0;\n\tswitch (pc.fn) {\n");
	for (int j = 0; j < n; j++) {
		bk_sb_put(b, "\tcase %du: bk_res = float(%s(", j, fns[j]->name);
		const char *sep = "";
		for (int c = 0; c < BK_IN_COUNT; c++)
			if (fns[j]->args >> c & 1) {
				bk_sb_put(b, "%s%s", sep, bk_input_name((bk_input)c));
				sep = ", ";
			}
		bk_sb_put(b, ")); break;\n");
	}
	bk_sb_put(b, "\t}\n\toutb.v[pc.out_off + k] = bk_res;\n}\n");
}

char *vk_shader(const vk_fn *const *fns, int n, bk_precision prec)
{
	bk_strbuf b = {0};
	bk_lvp_head(&b, prec);
	for (int j = 0; j < n && !b.oom; j++) {
		char *text = prec == BK_F16 ? bk_lvp_half_text(fns[j]->glsl) : NULL;
		if (prec == BK_F16 && !text)
			b.oom = 1;
		else
			bk_sb_put(&b, "%s\n", text ? text : fns[j]->glsl);
		free(text);
	}
	put_main(&b, fns, n, prec);
	if (b.oom) {
		free(b.s);
		return NULL;
	}
	return b.s;
}

/* ---- the negative control ------------------------------------------------------ */

char *vk_perturb(const char *glsl, const char *name, double factor, int how)
{
	char sig[96];
	snprintf(sig, sizeof sig, " %s(", name);
	const char *at = strstr(glsl, sig), *body = at ? strstr(at, "\n{\n") : NULL;
	const char *end = body ? strstr(body, "\n}\n") : NULL;
	if (!end)
		return NULL;
	const char *hit = NULL, *s = body;
	size_t k = 0;
	if (how == 1) { /* the return value times NaN */
		hit = strstr(body, "\treturn ");
		if (!hit || hit > end)
			return NULL;
		hit += strcspn(hit, ";");
	}
	while (!hit && s < end) {
		if (bk_lvp_ident_char(*s) && !isdigit((unsigned char)*s))
			while (bk_lvp_ident_char(*s))
				s++;
		else if ((k = bk_lvp_literal_len(s)) > 0 && memchr(s, '.', k))
			hit = s;
		else
			s++;
	}
	if (!hit || hit > end)
		return NULL;
	bk_strbuf b = {0};
	bk_sb_put(&b, "%.*s", (int)(hit - glsl), glsl);
	if (how == 1)
		bk_sb_put(&b, " * uintBitsToFloat(0x7fc00000u)%s", hit);
	else {
		char num[40];
		snprintf(num, sizeof num, "%.9g", strtod(hit, NULL) * factor);
		bk_sb_put(&b, "%s%s%s", num, strpbrk(num, ".e") ? "" : ".0", hit + k);
	}
	if (b.oom) {
		free(b.s);
		return NULL;
	}
	return b.s;
}
