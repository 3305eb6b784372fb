/*
 * ir_terms.h — the registry's terms as formula-language definitions (internal).
 */
#ifndef BRDF_IR_TERMS_H
#define BRDF_IR_TERMS_H

#include <stddef.h>

typedef struct bk_ir_term {
	const char *name;   /* as in the registry */
	const char *params; /* comma-separated argument names, as the C function's */
	const char *body;   /* "local = expr; ...; expr" */
} bk_ir_term;

const bk_ir_term *bk_ir_term_find(const char *name, size_t len);

#endif
