/* Eigen-decomposition of symmetric 3x3 matrices (PCA of neighbourhoods). */
#ifndef DP_CORE_EIG3_H
#define DP_CORE_EIG3_H

/* a = {a00, a01, a02, a11, a12, a22}. On return w[0] <= w[1] <= w[2] are the
 * eigenvalues and v[m] the unit eigenvector of w[m] (so v[0] is the normal of
 * a planar neighbourhood, v[2] its dominant direction). Cyclic Jacobi: exact
 * enough for covariance matrices and never fails. */
void dp_eig3_sym(const double a[6], double w[3], double v[3][3]);

#endif
