/* Eigen-decomposition of symmetric 3x3 matrices (PCA of neighbourhoods). */
#ifndef DP_CORE_EIG3_H
#define DP_CORE_EIG3_H

/* a = {a00, a01, a02, a11, a12, a22}. On return w[0] <= w[1] <= w[2] are the
 * eigenvalues and v[m] the unit eigenvector of w[m] (so v[0] is the normal of
 * a planar neighbourhood, v[2] its dominant direction). Cyclic Jacobi: exact
 * enough for covariance matrices and never fails. */
void dp_eig3_sym(const double a[6], double w[3], double v[3][3]);

/* The same w[0] <= w[1] <= w[2], but only v0, the unit eigenvector of w[0]
 * (a neighbourhood's normal), for the surface stage, which asks it of every
 * point in every iteration: the eigenvalues in closed form (the roots of the
 * characteristic cubic by the trigonometric formula, to about 1e-8 of the
 * matrix's size where two roots meet) and v0 as the longest cross product of
 * two rows of a - w[0] I, several times faster than the Jacobi sweeps. Where
 * w[0] is within 1e-3 of the matrix's size of w[1] (those rows span a line
 * or less, and v0 is barely defined) it falls back on dp_eig3_sym. Returns 1
 * when the closed form answered, 0 when Jacobi did. */
int dp_eig3_smallest(const double a[6], double w[3], double v0[3]);

/* First and second moments of offsets d (from any fixed origin, chosen near
 * the points so that float positions keep their precision): zero-initialise,
 * add each offset, then dp_moments_cov gives the covariance in dp_eig3_sym's
 * layout. */
typedef struct dp_moments {
	double s[3], ss[6];
	double count;
} dp_moments;

static inline void dp_moments_add(dp_moments *m, const double d[3])
{
	for (int a = 0; a < 3; a++)
		m->s[a] += d[a];
	m->ss[0] += d[0] * d[0];
	m->ss[1] += d[0] * d[1];
	m->ss[2] += d[0] * d[2];
	m->ss[3] += d[1] * d[1];
	m->ss[4] += d[1] * d[2];
	m->ss[5] += d[2] * d[2];
	m->count += 1.0;
}

static inline void dp_moments_cov(const dp_moments *m, double cov[6])
{
	double c = m->count, mean[3] = {m->s[0] / c, m->s[1] / c, m->s[2] / c};
	cov[0] = m->ss[0] / c - mean[0] * mean[0];
	cov[1] = m->ss[1] / c - mean[0] * mean[1];
	cov[2] = m->ss[2] / c - mean[0] * mean[2];
	cov[3] = m->ss[3] / c - mean[1] * mean[1];
	cov[4] = m->ss[4] / c - mean[1] * mean[2];
	cov[5] = m->ss[5] / c - mean[2] * mean[2];
}

#endif
