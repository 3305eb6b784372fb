/*
 * ir_lex.c — tokens of the formula language, with their 1-based columns.
 */
#include "ir_lex.h"

#include <ctype.h>
#include <stdlib.h>
#include <string.h>

static int ident_char(int c) { return isalnum(c) || c == '_'; }

/* number := digits ['.' digits] [('e'|'E') ['+'|'-'] digits] | '.' digits ...
 * Written out rather than strtod alone so that "inf", "nan" and hex floats,
 * which strtod accepts, are not numbers here. */
static size_t number_len(const char *s)
{
	size_t i = 0;
	while (isdigit((unsigned char)s[i]))
		i++;
	if (s[i] == '.') {
		i++;
		while (isdigit((unsigned char)s[i]))
			i++;
	}
	if (i == 0 || (i == 1 && s[0] == '.'))
		return 0;
	if (s[i] == 'e' || s[i] == 'E') {
		size_t j = i + 1;
		if (s[j] == '+' || s[j] == '-')
			j++;
		if (isdigit((unsigned char)s[j])) {
			while (isdigit((unsigned char)s[j]))
				j++;
			i = j;
		}
	}
	return i;
}

void bk_lex_next(bk_lexer *lx)
{
	const char *s = lx->src;
	while (s[lx->pos] == ' ' || s[lx->pos] == '\t' || s[lx->pos] == '\n' || s[lx->pos] == '\r')
		lx->pos++;
	bk_token *t = &lx->tok;
	t->start = lx->pos;
	t->column = (int)lx->pos + 1;
	char c = s[lx->pos];
	if (c == '\0') {
		t->type = TK_EOF;
		t->len = 0;
		return;
	}
	size_t n = number_len(s + lx->pos);
	if (n) {
		t->type = TK_NUMBER;
		t->len = n;
		t->num = strtod(s + lx->pos, NULL);
	} else if (isalpha((unsigned char)c) || c == '_') {
		n = 1;
		while (ident_char((unsigned char)s[lx->pos + n]))
			n++;
		t->type = TK_IDENT;
		t->len = n;
	} else if (strchr("+-*/^(),;=", c)) {
		t->type = (bk_tktype)c;
		t->len = 1;
	} else {
		t->type = TK_BAD;
		t->len = 1;
	}
	lx->pos += t->len;
}

int bk_tok_is(const bk_token *t, const char *src, const char *word)
{
	return t->type == TK_IDENT && strlen(word) == t->len && strncmp(src + t->start, word, t->len) == 0;
}
