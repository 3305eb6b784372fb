// linalg.cc — the symmetric eigen-decomposition the fitter's standard errors
// and identifiability checks need, from Eigen (Debian libeigen3-dev, already
// pulled in by Ceres) rather than a hand-rolled Jacobi loop. C++ because Eigen
// is a header library for C++; the C face is in linalg.h.
#include "linalg.h"

#include <Eigen/Eigenvalues>

extern "C" int bk_sym_eigen(int n, const double *a, double *values, double *vectors)
{
	if (n < 1 || n > 64)
		return -1;
	Eigen::MatrixXd m(n, n);
	for (int i = 0; i < n; i++)
		for (int j = 0; j < n; j++)
			m(i, j) = a[i * n + j];
	Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(m);
	if (es.info() != Eigen::Success)
		return -1;
	for (int k = 0; k < n; k++) {
		values[k] = es.eigenvalues()(k); // ascending
		for (int i = 0; i < n; i++)
			vectors[i * n + k] = es.eigenvectors()(i, k);
	}
	return 0;
}
