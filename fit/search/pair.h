/*
 * pair.h — a split-sum pair (A, B) as the one form the shader computes:
 * f0*(A) + (B) (Karis 2013: specular = SpecularColor·A + B). The one place
 * that text is built: the search's cost, compare's and stability's catalog
 * rows, scene's env forms and the front's refit all call it.
 */
#ifndef FIT_SEARCH_PAIR_H
#define FIT_SEARCH_PAIR_H

#include <stddef.h>

/* Writes "f0*(A) + (B)" into buf. 0, or -1 when it does not fit in len
 * (buf then holds nothing usable). */
int bk_pair_text(const char *a, const char *b, char *buf, size_t len);

/* The same, malloc'd (NULL when out of memory). */
char *bk_pair_dup(const char *a, const char *b);

#endif
