#include "ops/operators.h"

#include <math.h>

/* Relative slack of a reach over the exact half-extent. The metric's rows are
 * orthogonal only to float rounding and the device divides by the cell with
 * unsafe math (about 1e-6 relative together); cell coordinates of queries and
 * points round by an ulp of their distance to the grid's origin. 1e-3 keeps a
 * point within reach on the scanned side of every rounded cell border, and
 * adds a layer of cells for well under 1% of the queries. */
#define SKELETON_REACH_SLACK 1e-3

float dp_skeleton_reach(size_t nq, const float *metric, float cutoff, float *reach)
{
	float longest = 0.0f;
	for (size_t i = 0; i < nq; i++) {
		const float *m = metric + 9 * i;
		double a[3][3];
		for (int r = 0; r < 3; r++)
			for (int c = 0; c < 3; c++)
				a[r][c] = m[3 * r + c];
		/* M^-1 = adj(M) / det(M); row j of M^-1 is column j of the cofactors. */
		double cof[3][3];
		for (int r = 0; r < 3; r++)
			for (int c = 0; c < 3; c++) {
				int r1 = (r + 1) % 3, r2 = (r + 2) % 3, c1 = (c + 1) % 3, c2 = (c + 2) % 3;
				cof[r][c] = a[r1][c1] * a[r2][c2] - a[r1][c2] * a[r2][c1];
			}
		double det = a[0][0] * cof[0][0] + a[0][1] * cof[0][1] + a[0][2] * cof[0][2];
		for (int j = 0; j < 3; j++) {
			double len = sqrt(cof[0][j] * cof[0][j] + cof[1][j] * cof[1][j] + cof[2][j] * cof[2][j]);
			float e = (float)(cutoff * len / fabs(det) * (1.0 + SKELETON_REACH_SLACK));
			reach[3 * i + j] = e;
			longest = fmaxf(longest, e);
		}
	}
	return longest;
}
