#include "stages/meet.h"

#include "ops/operators.h"

#include <math.h>

/* Partners whose normal is within 45° of the opposite one: their sinking
 * line and the point's are too close to parallel to cross where it matters
 * (the settle test's thin-wall cut). */
#define OPPOSITE_COS DP_SINK_OPPOSITE_COS
/* Nearly parallel lines (a small ω lets such partners through) cross where
 * the normals' noise puts them: they fix no depth. */
#define MIN_LINE_WEIGHT 0.05

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
			float w[3] = {a->sx[k] - p[0], a->sy[k] - p[1], a->sz[k] - p[2]};
			float b = n[0] * a->nx[k] + n[1] * a->ny[k] + n[2] * a->nz[k];
			float behind = a->nx[k] * w[0] + a->ny[k] * w[1] + a->nz[k] * w[2];
			if (!dp_sink_partner(w[0] * w[0] + w[1] * w[1] + w[2] * w[2], a->far_d2, b, behind, a->wall_min))
				continue;
			if (b > a->cos_w)
				continue;
			double t, weight;
			if (b < OPPOSITE_COS) {
				/* Near-opposite normals (a thin wall): the two sinking
				 * lines nearly coincide, so take the ball centred at
				 * p - t n with radius t that touches the partner's
				 * tangent plane, where n'·(s - p) = t (1 - b). */
				t = (a->nx[k] * w[0] + a->ny[k] * w[1] + a->nz[k] * w[2]) / (1.0 - (double)b);
				/* both estimates agree on exact geometry, so the
				 * weight may jump at the switch */
				weight = 1.0;
			} else {
				/* Lines p - t n and s - u n' are closest where
				 * t (1 - b²) = b n'·(s - p) - n·(s - p). */
				double d = n[0] * w[0] + n[1] * w[1] + n[2] * w[2];
				double e = a->nx[k] * w[0] + a->ny[k] * w[1] + a->nz[k] * w[2];
				weight = 1.0 - (double)b * b;
				if (weight < MIN_LINE_WEIGHT)
					continue;
				t = (b * e - d) / weight;
			}
			num += weight * t;
			den += weight;
		}
	if (!(den > 0.0))
		return 0.0f;
	float depth = -((q[0] - p[0]) * n[0] + (q[1] - p[1]) * n[1] + (q[2] - p[2]) * n[2]);
	float shift = (float)(num / den) - depth;
	if (!isfinite(shift))
		return 0.0f;
	/* never above the surface point, at most max_shift either way */
	return fminf(fmaxf(shift, fmaxf(-a->max_shift, -depth)), a->max_shift);
}
