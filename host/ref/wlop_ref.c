/* Scalar reference of the WLOP operators: the specification the kernels in
 * kernels/wlop.cl must match. */
#include "ops/operators.h"

#include <math.h>

void dp_ref_density(const dp_density_args *a)
{
	const dp_grid *g = a->data;
	float h2 = a->h * a->h;
	uint32_t beg[9], end[9];
	for (size_t i = 0; i < a->nq; i++) {
		float sum = 1.0f;
		dp_grid_rows(g, a->qx[i], a->qy[i], a->qz[i], beg, end);
		for (int r = 0; r < 9; r++)
			for (uint32_t k = beg[r]; k < end[r]; k++) {
				float dx = a->qx[i] - g->x[k], dy = a->qy[i] - g->y[k], dz = a->qz[i] - g->z[k];
				float d2 = dx * dx + dy * dy + dz * dz;
				if (d2 < h2 && d2 >= a->min_d2)
					sum += expf(-a->theta_k * d2 / h2);
			}
		a->out[i] = a->sqrt_density ? sqrtf(sum) : sum;
	}
}

void dp_ref_attraction(const dp_attraction_args *a)
{
	const dp_grid *g = a->data;
	float h2 = a->h * a->h;
	uint32_t beg[9], end[9];
	for (size_t i = 0; i < a->nq; i++) {
		float sx = 0.0f, sy = 0.0f, sz = 0.0f, sw = 0.0f;
		dp_grid_rows(g, a->qx[i], a->qy[i], a->qz[i], beg, end);
		for (int r = 0; r < 9; r++)
			for (uint32_t k = beg[r]; k < end[r]; k++) {
				float dx = g->x[k] - a->qx[i], dy = g->y[k] - a->qy[i], dz = g->z[k] - a->qz[i];
				float d2 = dx * dx + dy * dy + dz * dz;
				if (d2 >= h2 || d2 < a->min_d2)
					continue;
				float alpha = expf(-a->theta_k * d2 / h2);
				if (!a->gaussian)
					alpha /= sqrtf(d2);
				float wt = alpha * a->inv_v[k];
				sx += wt * dx;
				sy += wt * dy;
				sz += wt * dz;
				sw += wt;
			}
		a->out_x[i] = sx;
		a->out_y[i] = sy;
		a->out_z[i] = sz;
		a->out_w[i] = sw;
	}
}

void dp_ref_repulsion(const dp_repulsion_args *a)
{
	const dp_grid *g = a->data;
	float h2 = a->h * a->h;
	uint32_t beg[9], end[9];
	for (size_t i = 0; i < a->nq; i++) {
		float sx = 0.0f, sy = 0.0f, sz = 0.0f, sw = 0.0f;
		dp_grid_rows(g, a->qx[i], a->qy[i], a->qz[i], beg, end);
		for (int r = 0; r < 9; r++)
			for (uint32_t k = beg[r]; k < end[r]; k++) {
				float dx = a->qx[i] - g->x[k], dy = a->qy[i] - g->y[k], dz = a->qz[i] - g->z[k];
				float d2 = dx * dx + dy * dy + dz * dz;
				if (d2 >= h2 || d2 < a->min_d2)
					continue;
				float wt = expf(-a->theta_k * d2 / h2) / sqrtf(d2) * a->w[k];
				sx += wt * dx;
				sy += wt * dy;
				sz += wt * dz;
				sw += wt;
			}
		a->out_x[i] = sx;
		a->out_y[i] = sy;
		a->out_z[i] = sz;
		a->out_w[i] = sw;
	}
}
