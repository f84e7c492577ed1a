/* Scalar reference of the sinking operators: the specification the kernels in
 * kernels/sink.cl must match. */
#include "ops/operators.h"

#include <math.h>

void dp_ref_sink_front(const dp_sink_front_args *a)
{
	const dp_grid *g = a->inner;
	float r2 = a->radius * a->radius;
	uint32_t beg[9], end[9];
	for (size_t i = 0; i < a->nq; i++) {
		float best = DP_SINK_NO_FRONT;
		dp_grid_rows(g, a->qx[i], a->qy[i], a->qz[i], beg, end);
		for (int r = 0; r < 9; r++)
			for (uint32_t k = beg[r]; k < end[r]; k++) {
				float dx = a->qx[i] - g->x[k], dy = a->qy[i] - g->y[k], dz = a->qz[i] - g->z[k];
				if (dx * dx + dy * dy + dz * dz >= r2)
					continue;
				float ex = a->px[i] - a->sx[k], ey = a->py[i] - a->sy[k], ez = a->pz[i] - a->sz[k];
				float dot = a->qnx[i] * a->nx[k] + a->qny[i] * a->ny[k] + a->qnz[i] * a->nz[k];
				/* -(n'·(p - p')) = n'·(p' - p): how far p lies behind the partner's plane */
				float behind = -(a->nx[k] * ex + a->ny[k] * ey + a->nz[k] * ez);
				if (dp_sink_partner(ex * ex + ey * ey + ez * ez, a->far_d2, dot, behind, a->wall_min) &&
				    dot < best)
					best = dot;
			}
		a->min_dot[i] = best;
	}
}

void dp_ref_sink_step(const dp_sink_step_args *a)
{
	const dp_grid *g = a->surface;
	float r2 = a->radius * a->radius;
	uint32_t beg[9], end[9];
	for (size_t i = 0; i < a->nq; i++) {
		float sum = 0.0f, count = 0.0f;
		dp_grid_rows(g, a->px[i], a->py[i], a->pz[i], beg, end);
		for (int r = 0; r < 9; r++)
			for (uint32_t k = beg[r]; k < end[r]; k++) {
				float dx = a->px[i] - g->x[k], dy = a->py[i] - g->y[k], dz = a->pz[i] - g->z[k];
				if (dx * dx + dy * dy + dz * dz < r2 && a->stop[k] >= a->depth[i] - a->margin) {
					sum += a->move[k];
					count += 1.0f;
				}
			}
		a->mean[i] = count > 0.0f ? sum / count : 0.0f;
	}
}

void dp_ref_sink_smooth(const dp_sink_smooth_args *a)
{
	const dp_grid *g = a->surface;
	float r2 = a->radius * a->radius;
	uint32_t beg[9], end[9];
	for (size_t i = 0; i < a->nq; i++) {
		float sx = 0.0f, sy = 0.0f, sz = 0.0f, sw = 0.0f;
		dp_grid_rows(g, a->px[i], a->py[i], a->pz[i], beg, end);
		for (int r = 0; r < 9; r++)
			for (uint32_t k = beg[r]; k < end[r]; k++) {
				float dx = a->px[i] - g->x[k], dy = a->py[i] - g->y[k], dz = a->pz[i] - g->z[k];
				float d2 = dx * dx + dy * dy + dz * dz;
				if (d2 >= r2)
					continue;
				float dot = a->qnx[i] * a->nx[k] + a->qny[i] * a->ny[k] + a->qnz[i] * a->nz[k];
				float u = (1.0f - dot) * a->phi_scale;
				float w = expf(-d2 * a->inv_r2 - u * u);
				sx += w * (a->ix[k] - a->qx[i]);
				sy += w * (a->iy[k] - a->qy[i]);
				sz += w * (a->iz[k] - a->qz[i]);
				sw += w;
			}
		a->out_x[i] = sx;
		a->out_y[i] = sy;
		a->out_z[i] = sz;
		a->out_w[i] = sw;
	}
}
