/* Degenerate inputs (issue 9, defect 6): on 3 points the skeleton ended 89
 * units outside a 2-unit box, with exit 0. Such inputs are refused before
 * the pipeline runs, and a result that strays far from the input is an error
 * rather than an output. */
#include "stages/input_check.h"

#include "core/common.h"
#include "core/eig3.h"

#include <math.h>

dp_status dp_check_volume(const dp_cloud *in, dp_error *err)
{
	size_t n = in->n;
	/* WLOP names these problems better: no points, no arrays, NaN */
	if (n == 0 || !in->x || !in->y || !in->z)
		return DP_OK;
	for (size_t i = 0; i < n; i++)
		if (!isfinite(in->x[i]) || !isfinite(in->y[i]) || !isfinite(in->z[i]))
			return DP_OK;
	if (n < 4)
		return dp_fail(err, DP_ERR_ARG, "consolidate: %zu input point%s span no volume (at least 4 are needed)", n,
			       n == 1 ? "" : "s");
	/* about the first point, so a far offset keeps its precision */
	double o[3] = {in->x[0], in->y[0], in->z[0]}, cov[6];
	dp_moments mom = {{0, 0, 0}, {0, 0, 0, 0, 0, 0}, 0};
	for (size_t i = 0; i < n; i++) {
		double d[3] = {in->x[i] - o[0], in->y[i] - o[1], in->z[i] - o[2]};
		dp_moments_add(&mom, d);
	}
	dp_moments_cov(&mom, cov);
	double w[3], v[3][3];
	dp_eig3_sym(cov, w, v);
	/* standard deviations along the principal axes, smallest first */
	double sd[3];
	for (int a = 0; a < 3; a++)
		sd[a] = w[a] > 0.0 ? sqrt(w[a]) : 0.0;
	/* WLOP's count of distinct positions says it with the numbers */
	if (!(sd[2] > 0.0))
		return DP_OK;
	if (sd[1] <= DP_FLAT_RATIO * sd[2])
		return dp_fail(err, DP_ERR_ARG, "consolidate: the %zu input points lie on a line: they span no volume",
			       n);
	if (sd[0] <= DP_FLAT_RATIO * sd[2])
		return dp_fail(err, DP_ERR_ARG, "consolidate: the %zu input points lie in a plane: they span no volume",
			       n);
	return DP_OK;
}

static dp_status check_cloud(const dp_cloud *c, const char *stage, const double lo[3], const double hi[3],
			     double margin, dp_error *err)
{
	for (size_t i = 0; i < c->n; i++) {
		double p[3] = {c->x[i], c->y[i], c->z[i]};
		for (int a = 0; a < 3; a++)
			if (!(p[a] >= lo[a] - margin && p[a] <= hi[a] + margin))
				return dp_fail(err, DP_ERR_ARG,
					       "consolidate: %s point %zu at (%g, %g, %g) is far outside the input's box "
					       "[%g, %g] x [%g, %g] x [%g, %g]: no meaningful result (too few deep points for "
					       "this input, or an input too degenerate)",
					       stage, i, p[0], p[1], p[2], lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]);
	}
	return DP_OK;
}

dp_status dp_check_result_bounds(const dp_cloud *in, const dp_result *res, dp_error *err)
{
	if (in->n == 0)
		return DP_OK;
	double lo[3] = {in->x[0], in->y[0], in->z[0]}, hi[3] = {in->x[0], in->y[0], in->z[0]};
	for (size_t i = 1; i < in->n; i++) {
		double p[3] = {in->x[i], in->y[i], in->z[i]};
		for (int a = 0; a < 3; a++) {
			lo[a] = p[a] < lo[a] ? p[a] : lo[a];
			hi[a] = p[a] > hi[a] ? p[a] : hi[a];
		}
	}
	double diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
			   (hi[2] - lo[2]) * (hi[2] - lo[2]));
	const struct {
		const dp_cloud *c;
		const char *stage;
	} sets[] = {{&res->wlop, "wlop"}, {&res->skeleton, "skeleton"}, {&res->surface, "surface"}};
	for (size_t k = 0; k < sizeof sets / sizeof sets[0]; k++) {
		dp_status st = check_cloud(sets[k].c, sets[k].stage, lo, hi, diag, err);
		if (st != DP_OK)
			return st;
	}
	return DP_OK;
}
