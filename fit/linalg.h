/*
 * linalg.h — small dense linear algebra for the fitter, from Eigen (linalg.cc).
 */
#ifndef FIT_LINALG_H
#define FIT_LINALG_H

#ifdef __cplusplus
extern "C" {
#endif

/* Eigen-decomposition of the symmetric n x n matrix a (row-major): values in
 * ascending order, vectors[i * n + k] = component i of eigenvector k.
 * Returns 0, or -1 on bad n or failure. */
int bk_sym_eigen(int n, const double *a, double *values, double *vectors);

#ifdef __cplusplus
}
#endif

#endif
