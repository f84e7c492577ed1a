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
