#include "stages/meet.h"

/* Partners whose lines together fix the depth less firmly than this (the sum
 * of their weights 1 - (n·n')²) leave the point where it settled. */
#define MIN_CONDITIONING 0.05f

float dp_meet_shift(const dp_meet_args *a, const float q[3], const float p[3], const float n[3])
{
	const dp_grid *g = a->inner;
	float r2 = a->radius * a->radius;
	uint32_t beg[9], end[9];
	double num = 0.0, den = 0.0;
	dp_grid_rows(g, q[0], q[1], q[2], beg, end);
	for (int row = 0; row < 9; row++)
		for (uint32_t k = beg[row]; k < end[row]; k++) {
			float dx = q[0] - g->x[k], dy = q[1] - g->y[k], dz = q[2] - g->z[k];
			if (dx * dx + dy * dy + dz * dz >= r2)
				continue;
			float w[3] = {p[0] - a->sx[k], p[1] - a->sy[k], p[2] - a->sz[k]};
			if (w[0] * w[0] + w[1] * w[1] + w[2] * w[2] <= a->far_d2)
				continue;
			float b = n[0] * a->nx[k] + n[1] * a->ny[k] + n[2] * a->nz[k];
			if (b > a->cos_w)
				continue;
			/* Lines p - t n and s - u n': the closest approach is at
			 * t = (b e - d) / (1 - b²) with d = -n·w, e = -n'·w. */
			float d = -(n[0] * w[0] + n[1] * w[1] + n[2] * w[2]);
			float e = -(a->nx[k] * w[0] + a->ny[k] * w[1] + a->nz[k] * w[2]);
			num += (double)b * e - d;
			den += 1.0 - (double)b * b;
		}
	if (!(den > MIN_CONDITIONING))
		return 0.0f;
	float depth = -((q[0] - p[0]) * n[0] + (q[1] - p[1]) * n[1] + (q[2] - p[2]) * n[2]);
	float shift = (float)(num / den) - depth;
	return fminf(fmaxf(shift, -a->max_shift), a->max_shift);
}
