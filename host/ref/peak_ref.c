/* Scalar reference of the peak operator: the specification kernels/peak.cl
 * must match. */
#include "ops/operators.h"

#include <math.h>

void dp_ref_peak(const dp_peak_args *a)
{
	const dp_grid *g = a->data;
	float r2 = a->radius * a->radius;
	for (size_t i = 0; i < a->nq; i++) {
		int cx = dp_grid_coord(g, 0, a->qx[i]), cy = dp_grid_coord(g, 1, a->qy[i]);
		int cz = dp_grid_coord(g, 2, a->qz[i]);
		float count = 0.0f, sum = 0.0f;
		for (int dz = -a->reach; dz <= a->reach; dz++)
			for (int dy = -a->reach; dy <= a->reach; dy++) {
				uint32_t beg, end;
				dp_grid_row(g, cx, cy + dy, cz + dz, a->reach, &beg, &end);
				for (uint32_t k = beg; k < end; k++) {
					float dx = a->qx[i] - g->x[k], ey = a->qy[i] - g->y[k], ez = a->qz[i] - g->z[k];
					float d2 = dx * dx + ey * ey + ez * ez;
					if (d2 < r2) {
						count += 1.0f;
						sum += expf(-d2 / r2);
					}
				}
			}
		a->count[i] = count;
		a->sum[i] = sum;
	}
}
