#include "backend/neighbours.h"

#include "core/common.h"

#include <math.h>
#include <string.h>

/* The record of op, NULL when the table is full (counts then go to the total
 * only). */
static dp_neighbour_op *op_record(dp_neighbour_counts *c, const char *op)
{
	for (size_t i = 0; i < c->nops; i++)
		if (!strcmp(c->ops[i].name, op))
			return &c->ops[i];
	if (c->nops == DP_NEIGHBOUR_MAX_OPS)
		return NULL;
	dp_neighbour_op *r = &c->ops[c->nops++];
	memset(r, 0, sizeof *r);
	snprintf(r->name, sizeof r->name, "%s", op);
	return r;
}

static void record(dp_neighbour_counts *c, const char *op, const dp_grid *g, size_t nq, double pairs,
		   double radius, double t0)
{
	dp_neighbour_op *r = op_record(c, op);
	if (r) {
		r->launches += 1.0;
		r->pairs += pairs;
		r->radius_sum += radius;
		r->nq_sum += (double)nq;
		r->ndata = g->n;
	}
	c->pairs += pairs;
	c->seconds += dp_seconds() - t0;
}

void dp_count_neighbours(dp_context *ctx, const char *op, const dp_grid *g, size_t nq, const float *qx,
			 const float *qy, const float *qz, float radius)
{
	if (!ctx->neighbours)
		return;
	double t0 = dp_seconds(), pairs = 0.0;
	float r2 = radius * radius;
	int reach = dp_grid_reach_cells(g, radius);
	for (size_t i = 0; i < nq; i++) {
		int cx = dp_grid_coord(g, 0, qx[i]), cy = dp_grid_coord(g, 1, qy[i]), cz = dp_grid_coord(g, 2, qz[i]);
		for (int dz = -reach; dz <= reach; dz++)
			for (int dy = -reach; dy <= reach; dy++) {
				uint32_t beg, end;
				dp_grid_row(g, cx, cy + dy, cz + dz, reach, &beg, &end);
				for (uint32_t k = beg; k < end; k++) {
					float dx = qx[i] - g->x[k], ey = qy[i] - g->y[k], ez = qz[i] - g->z[k];
					pairs += dx * dx + ey * ey + ez * ez < r2;
				}
			}
	}
	record(ctx->neighbours, op, g, nq, pairs, radius, t0);
}

void dp_count_neighbours_metric(dp_context *ctx, const char *op, const dp_grid *g, size_t nq, const float *qx,
				const float *qy, const float *qz, const float *metric, const float *reach,
				float cutoff)
{
	if (!ctx->neighbours)
		return;
	double t0 = dp_seconds(), pairs = 0.0, radius = 0.0;
	float c2 = cutoff * cutoff;
	for (size_t i = 0; i < nq; i++) {
		const float *m = metric + 9 * i, *e = reach + 3 * i;
		radius += cbrt((double)e[0] * e[1] * e[2]);
		int cx = dp_grid_coord(g, 0, qx[i]), cy = dp_grid_coord(g, 1, qy[i]), cz = dp_grid_coord(g, 2, qz[i]);
		int rx = dp_grid_reach_cells(g, e[0]), ry = dp_grid_reach_cells(g, e[1]);
		int rz = dp_grid_reach_cells(g, e[2]);
		for (int dz = -rz; dz <= rz; dz++)
			for (int dy = -ry; dy <= ry; dy++) {
				uint32_t beg, end;
				dp_grid_row(g, cx, cy + dy, cz + dz, rx, &beg, &end);
				for (uint32_t k = beg; k < end; k++) {
					float d[3] = {qx[i] - g->x[k], qy[i] - g->y[k], qz[i] - g->z[k]}, u2 = 0.0f;
					for (int a = 0; a < 3; a++) {
						float ua = m[3 * a] * d[0] + m[3 * a + 1] * d[1] + m[3 * a + 2] * d[2];
						u2 += ua * ua;
					}
					pairs += u2 <= c2;
				}
			}
	}
	record(ctx->neighbours, op, g, nq, pairs, nq ? radius / (double)nq : 0.0, t0);
}
