#include "core/eig3.h"

#include <math.h>

/* Sweeps of cyclic Jacobi; 3x3 converges to double precision in < 10. */
#define JACOBI_SWEEPS 32

void dp_eig3_sym(const double s[6], double w[3], double v[3][3])
{
	double a[3][3] = {{s[0], s[1], s[2]}, {s[1], s[3], s[4]}, {s[2], s[4], s[5]}};
	double e[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}; /* columns: eigenvectors */
	for (int sweep = 0; sweep < JACOBI_SWEEPS; sweep++) {
		double off = fabs(a[0][1]) + fabs(a[0][2]) + fabs(a[1][2]);
		double scale = fabs(a[0][0]) + fabs(a[1][1]) + fabs(a[2][2]);
		if (off <= 1e-300 || off <= 1e-15 * scale)
			break;
		for (int p = 0; p < 2; p++)
			for (int q = p + 1; q < 3; q++) {
				if (a[p][q] == 0.0)
					continue;
				double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
				double t = (theta >= 0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
				double c = 1.0 / sqrt(t * t + 1.0), sn = t * c;
				for (int k = 0; k < 3; k++) {
					double akp = a[k][p], akq = a[k][q];
					a[k][p] = c * akp - sn * akq;
					a[k][q] = sn * akp + c * akq;
				}
				for (int k = 0; k < 3; k++) {
					double apk = a[p][k], aqk = a[q][k];
					a[p][k] = c * apk - sn * aqk;
					a[q][k] = sn * apk + c * aqk;
				}
				for (int k = 0; k < 3; k++) {
					double ekp = e[k][p], ekq = e[k][q];
					e[k][p] = c * ekp - sn * ekq;
					e[k][q] = sn * ekp + c * ekq;
				}
			}
	}
	int order[3] = {0, 1, 2};
	for (int i = 0; i < 2; i++)
		for (int j = i + 1; j < 3; j++)
			if (a[order[j]][order[j]] < a[order[i]][order[i]]) {
				int t = order[i];
				order[i] = order[j];
				order[j] = t;
			}
	for (int m = 0; m < 3; m++) {
		w[m] = a[order[m]][order[m]];
		double len = sqrt(e[0][order[m]] * e[0][order[m]] + e[1][order[m]] * e[1][order[m]] +
				  e[2][order[m]] * e[2][order[m]]);
		for (int k = 0; k < 3; k++)
			v[m][k] = e[k][order[m]] / len;
	}
}

/* The closed form's roots lose digits where two of them meet (the cubic's
 * coefficients, not the matrix, fix them there), and v0 turns by that error
 * over the gap w[1] - w[0]. Below this gap, in units of the matrix's size
 * |q| + p, Jacobi answers instead. A covariance that close to a line, or to
 * a multiple of I, has no normal anyway. */
#define SMALLEST_MIN_GAP 1e-3

static void cross(const double a[3], const double b[3], double c[3])
{
	c[0] = a[1] * b[2] - a[2] * b[1];
	c[1] = a[2] * b[0] - a[0] * b[2];
	c[2] = a[0] * b[1] - a[1] * b[0];
}

static int fallback(const double s[6], double w[3], double v0[3])
{
	double v[3][3];
	dp_eig3_sym(s, w, v);
	for (int k = 0; k < 3; k++)
		v0[k] = v[0][k];
	return 0;
}

int dp_eig3_smallest(const double s[6], double w[3], double v0[3])
{
	/* a = q I + p b with tr b = 0 and tr b² = 6: the eigenvalues are
	 * q + 2p β_k, β_k = cos(φ + 2πk/3), with cos 3φ = det(b) / 2 */
	double q = (s[0] + s[3] + s[5]) / 3.0;
	double b0 = s[0] - q, b3 = s[3] - q, b5 = s[5] - q;
	double p = sqrt((b0 * b0 + b3 * b3 + b5 * b5 + 2.0 * (s[1] * s[1] + s[2] * s[2] + s[4] * s[4])) / 6.0);
	double size = fabs(q) + p;
	if (!(p > 1e-12 * size))
		return fallback(s, w, v0); /* a multiple of I, or not finite */
	b0 /= p, b3 /= p, b5 /= p;
	double b1 = s[1] / p, b2 = s[2] / p, b4 = s[4] / p;
	double half_det = 0.5 * (b0 * (b3 * b5 - b4 * b4) - b1 * (b1 * b5 - b4 * b2) + b2 * (b1 * b4 - b3 * b2));
	half_det = half_det < -1.0 ? -1.0 : half_det > 1.0 ? 1.0 : half_det;
	double phi = acos(half_det) / 3.0;
	double beta0 = cos(phi + 2.0943951023931954923); /* 2π/3 */
	w[2] = q + 2.0 * p * cos(phi);
	w[0] = q + 2.0 * p * beta0;
	w[1] = 3.0 * q - w[0] - w[2];
	if (!(w[1] - w[0] > SMALLEST_MIN_GAP * size))
		return fallback(s, w, v0);
	/* the rows of (a - w[0] I) / p = b - 2 β0 I: of order 1 whatever a's
	 * scale, so their cross products neither overflow nor underflow */
	double r[3][3] = {{b0 - 2.0 * beta0, b1, b2}, {b1, b3 - 2.0 * beta0, b4}, {b2, b4, b5 - 2.0 * beta0}};
	double best[3] = {0.0, 0.0, 0.0}, best2 = 0.0;
	for (int i = 0; i < 2; i++)
		for (int j = i + 1; j < 3; j++) {
			double c[3];
			cross(r[i], r[j], c);
			double c2 = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
			if (c2 > best2) {
				best2 = c2;
				best[0] = c[0], best[1] = c[1], best[2] = c[2];
			}
		}
	if (!(best2 > 0.0) || !isfinite(best2))
		return fallback(s, w, v0);
	double len = sqrt(best2);
	for (int k = 0; k < 3; k++)
		v0[k] = best[k] / len;
	return 1;
}
