/*
 * ir_lex.h — the lexer of the formula language (internal).
 */
#ifndef BRDF_IR_LEX_H
#define BRDF_IR_LEX_H

#include <stddef.h>

typedef enum bk_tktype {
	TK_EOF = 0, TK_NUMBER = 256, TK_IDENT, TK_BAD,
	/* single characters stand for themselves: + - * / ^ ( ) , ; = */
} bk_tktype;

typedef struct bk_token {
	bk_tktype type;
	size_t start, len; /* byte range in the source */
	int column;        /* 1-based */
	double num;
} bk_token;

typedef struct bk_lexer {
	const char *src;
	size_t pos;
	bk_token tok; /* the current token */
} bk_lexer;

void bk_lex_next(bk_lexer *lx);
int bk_tok_is(const bk_token *t, const char *src, const char *word);

#endif
