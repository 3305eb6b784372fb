/*
 * halflit.c — every floating literal of generated code files is a binary16
 * value (tests/cli_msl.sh): the half files of a half front must write each
 * constant exactly as the half code holds it (brdf.h's BK_EMIT_*), the same
 * value in C, GLSL, HLSL and Metal.
 *
 * usage: halflit FILE...   prints "FILE: literal TEXT is not a binary16
 * value" for each that is not and exits 1 then; "N literals" otherwise (exit
 * 2 when there was none: a check of nothing proves nothing). Comments are
 * skipped; integers (the bits of uintBitsToFloat(0x7f800000u)) are no
 * floating literals; a literal's suffix (f, hf, h) is its type, not its value.
 */
#include "half.h"

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static char *slurp(const char *path)
{
	FILE *f = fopen(path, "rb");
	if (!f)
		return NULL;
	size_t cap = 1 << 16, n = 0;
	char *s = malloc(cap);
	size_t k;
	while (s && (k = fread(s + n, 1, cap - n - 1, f)) > 0)
		if ((n += k) + 1 == cap && !(s = realloc(s, cap *= 2)))
			break;
	fclose(f);
	if (s)
		s[n] = '\0';
	return s;
}

/* Checks the literals of s; returns how many are bad, counts all in *n. */
static int check(const char *path, const char *s, long *n)
{
	int bad = 0;
	while (*s) {
		if (s[0] == '/' && s[1] == '*') {
			const char *e = strstr(s + 2, "*/");
			s = e ? e + 2 : s + strlen(s);
		} else if (s[0] == '/' && s[1] == '/') {
			s += strcspn(s, "\n");
		} else if (isalpha((unsigned char)*s) || *s == '_') {
			while (isalnum((unsigned char)*s) || *s == '_')
				s++;
		} else if (isdigit((unsigned char)*s) || (*s == '.' && isdigit((unsigned char)s[1]))) {
			size_t k = strspn(s, "0123456789.");
			int real = memchr(s, '.', k) != NULL;
			if (s[k] == 'e' || s[k] == 'E') {
				real = 1;
				k++;
				k += s[k] == '+' || s[k] == '-';
				k += strspn(s + k, "0123456789");
			}
			if (real) {
				double x = strtod(s, NULL);
				++*n;
				if (bk_half_round_inline(x) != x && ++bad)
					printf("%s: literal %.*s is not a binary16 value\n", path, (int)k, s);
			}
			s += k;
			while (isalnum((unsigned char)*s)) /* suffix, or the rest of 0x7f800000u */
				s++;
		} else {
			s++;
		}
	}
	return bad;
}

int main(int argc, char **argv)
{
	int bad = 0;
	long n = 0;
	for (int i = 1; i < argc; i++) {
		char *s = slurp(argv[i]);
		if (!s) {
			fprintf(stderr, "halflit: %s: cannot read\n", argv[i]);
			return 2;
		}
		bad += check(argv[i], s, &n);
		free(s);
	}
	if (bad)
		return 1;
	printf("%ld literals\n", n);
	return n ? 0 : 2;
}
