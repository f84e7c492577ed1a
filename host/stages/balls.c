/* The inside test of the surface stage: see balls.h. */
#include "stages/balls.h"

#include "core/common.h"
#include "grid/hash.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct candidate {
	float radius;
	uint32_t row;
} candidate;

static int largest_first(const void *pa, const void *pb)
{
	const candidate *a = pa, *b = pb;
	if (a->radius != b->radius)
		return a->radius < b->radius ? 1 : -1;
	return (a->row > b->row) - (a->row < b->row);
}

/* Whether a kept ball (hashed in cells no smaller than the largest radius
 * plus the slack) contains ball `row` of `in`, grown by `slack`. Kept balls
 * are no smaller, so a container's centre lies within one cell, in the 27
 * cells around. */
static int contained(const dp_hash *h, const dp_balls *in, const uint32_t *kept_row, uint32_t row, float slack)
{
	float x = in->x[row], y = in->y[row], z = in->z[row], rad = in->radius[row];
	int64_t ci = dp_hash_cell(h, x), cj = dp_hash_cell(h, y), ck = dp_hash_cell(h, z);
	for (int64_t i = ci - 1; i <= ci + 1; i++)
		for (int64_t j = cj - 1; j <= cj + 1; j++)
			for (int64_t k = ck - 1; k <= ck + 1; k++)
				for (uint32_t p = h->head[dp_hash_bucket(h, i, j, k)]; p != DP_HASH_NONE; p = h->next[p]) {
					uint32_t o = kept_row[p];
					float dx = in->x[o] - x, dy = in->y[o] - y, dz = in->z[o] - z;
					if (sqrtf(dx * dx + dy * dy + dz * dz) + rad <= in->radius[o] + slack)
						return 1;
				}
	return 0;
}

dp_status dp_ball_set_build(dp_ball_set *set, const dp_balls *in, float slack, dp_error *err)
{
	dp_ball_set_free(set);
	size_t m = 0;
	for (size_t i = 0; i < in->n; i++)
		m += in->radius[i] > 0.0f;
	if (m == 0)
		return DP_OK;
	candidate *c = dp_alloc_array(m, sizeof *c);
	uint32_t *kept_row = dp_alloc_array(m, sizeof *kept_row);
	float *kx = dp_alloc_array(m, 3 * sizeof(float));
	dp_hash h = {0};
	dp_status st = DP_OK;
	if (!c || !kept_row || !kx || !(set->radius = dp_alloc_array(m, sizeof(float))) ||
	    !(set->row = dp_alloc_array(m, sizeof(uint32_t)))) {
		st = dp_fail(err, DP_ERR_NOMEM, "surface: out of memory for %zu balls", m);
		goto out;
	}
	m = 0;
	for (size_t i = 0; i < in->n; i++)
		if (in->radius[i] > 0.0f)
			c[m++] = (candidate){in->radius[i], (uint32_t)i};
	qsort(c, m, sizeof *c, largest_first);
	/* A container's centre lies within its radius plus the slack: cells that
	 * large keep it in the 27 around. No smaller than a 2^-40 of the largest
	 * coordinate either, so that cell indices stay integers (tiny radii). */
	float far = 0.0f;
	for (size_t i = 0; i < m; i++) {
		uint32_t row = c[i].row;
		far = fmaxf(far, fmaxf(fabsf(in->x[row]), fmaxf(fabsf(in->y[row]), fabsf(in->z[row]))));
	}
	float cell = fmaxf(c[0].radius + slack, ldexpf(far, -40));
	if ((st = dp_hash_alloc(&h, m, cell, err)) != DP_OK)
		goto out;
	size_t kept = 0;
	for (size_t i = 0; i < m; i++) {
		uint32_t row = c[i].row;
		if (contained(&h, in, kept_row, row, slack))
			continue;
		kept_row[kept] = row;
		dp_hash_insert(&h, (uint32_t)kept, in->x[row], in->y[row], in->z[row]);
		kept++;
	}
	float *ky = kx + m, *kz = kx + 2 * m;
	for (size_t i = 0; i < kept; i++) {
		kx[i] = in->x[kept_row[i]];
		ky[i] = in->y[kept_row[i]];
		kz[i] = in->z[kept_row[i]];
	}
	if ((st = dp_grid_build(&set->grid, kept, kx, ky, kz, c[0].radius, err)) != DP_OK)
		goto out;
	for (size_t i = 0; i < kept; i++) {
		uint32_t o = set->grid.perm[i];
		set->row[i] = kept_row[o];
		set->radius[i] = in->radius[kept_row[o]];
	}
	set->n = kept;
out:
	dp_hash_free(&h);
	free(c);
	free(kept_row);
	free(kx);
	if (st != DP_OK)
		dp_ball_set_free(set);
	return st;
}

void dp_ball_set_free(dp_ball_set *set)
{
	dp_grid_free(&set->grid);
	free(set->radius);
	free(set->row);
	memset(set, 0, sizeof *set);
}

int32_t dp_ball_set_deepest(const dp_ball_set *set, float x, float y, float z, float nx, float ny, float nz,
			    float margin, float *dist)
{
	if (set->n == 0)
		return -1;
	const dp_grid *g = &set->grid;
	uint32_t beg[9], end[9];
	dp_grid_rows(g, x, y, z, beg, end);
	int32_t best = -1;
	float best_depth = margin;
	for (int rr = 0; rr < 9; rr++)
		for (uint32_t k = beg[rr]; k < end[rr]; k++) {
			float dx = g->x[k] - x, dy = g->y[k] - y, dz = g->z[k] - z;
			if (dx * nx + dy * ny + dz * nz <= 0.0f)
				continue; /* the centre is behind: the point faces out of this ball */
			float d = sqrtf(dx * dx + dy * dy + dz * dz);
			if (set->radius[k] - d > best_depth) {
				best_depth = set->radius[k] - d;
				best = (int32_t)k;
				*dist = d;
			}
		}
	return best;
}
