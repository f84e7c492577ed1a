#include "testkit.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static dp_context *cl_ctx, *ref_ctx;

dp_context *tk_cl_context(void)
{
	if (!cl_ctx) {
		dp_error err = {0};
		if (dp_context_create(&cl_ctx, DP_BACKEND_CL, NULL, &err) != DP_OK)
			fail_msg("no OpenCL context: %s", err.message);
	}
	return cl_ctx;
}

dp_context *tk_ref_context(void)
{
	if (!ref_ctx) {
		dp_error err = {0};
		if (dp_context_create(&ref_ctx, DP_BACKEND_REF, NULL, &err) != DP_OK)
			fail_msg("no reference context: %s", err.message);
	}
	return ref_ctx;
}

int tk_teardown_contexts(void **state)
{
	(void)state;
	dp_context_free(cl_ctx);
	dp_context_free(ref_ctx);
	cl_ctx = ref_ctx = NULL;
	return 0;
}

size_t tk_random_points(dp_rng *rng, size_t n_uniform, float extent, float cell, float **px, float **py, float **pz)
{
	const size_t n_dup = 8, n_border = 16, n_cluster = 32, n_isolated = 1;
	size_t n = n_uniform + n_dup + n_border + n_cluster + n_isolated;
	float *x = malloc(n * sizeof *x), *y = malloc(n * sizeof *y), *z = malloc(n * sizeof *z);
	assert_non_null(x);
	assert_non_null(y);
	assert_non_null(z);
	size_t i = 0;
	for (; i < n_uniform; i++) {
		x[i] = (float)(dp_rng_uniform(rng) * extent);
		y[i] = (float)(dp_rng_uniform(rng) * extent);
		z[i] = (float)(dp_rng_uniform(rng) * extent);
	}
	for (size_t d = 0; d < n_dup; d++, i++) {
		size_t src = n_uniform ? (size_t)(dp_rng_uniform(rng) * (double)n_uniform) : 0;
		x[i] = n_uniform ? x[src] : 0.5f * extent;
		y[i] = n_uniform ? y[src] : 0.5f * extent;
		z[i] = n_uniform ? z[src] : 0.5f * extent;
	}
	for (size_t b = 0; b < n_border; b++, i++) {
		x[i] = cell * (float)(int)(dp_rng_uniform(rng) * extent / cell);
		y[i] = cell * (float)(int)(dp_rng_uniform(rng) * extent / cell);
		z[i] = (float)(dp_rng_uniform(rng) * extent);
	}
	float cx = 0.3f * extent, cy = 0.6f * extent, cz = 0.4f * extent;
	for (size_t c = 0; c < n_cluster; c++, i++) {
		x[i] = cx + (float)(dp_rng_normal(rng) * 0.05 * cell);
		y[i] = cy + (float)(dp_rng_normal(rng) * 0.05 * cell);
		z[i] = cz + (float)(dp_rng_normal(rng) * 0.05 * cell);
	}
	x[i] = y[i] = z[i] = 3.0f * extent;
	i++;
	*px = x;
	*py = y;
	*pz = z;
	return i;
}

void tk_assert_close(const float *a, const float *b, size_t n, float rtol, float atol, const char *what)
{
	size_t worst = 0, bad = 0;
	double worst_excess = -1.0;
	for (size_t i = 0; i < n; i++) {
		double tol = atol + rtol * fabs((double)b[i]);
		double diff = fabs((double)a[i] - (double)b[i]);
		if (!(diff <= tol) || isnan(a[i]) != isnan(b[i])) {
			bad++;
			if (diff - tol > worst_excess || isnan(diff)) {
				worst_excess = diff - tol;
				worst = i;
			}
		}
	}
	if (bad)
		fail_msg("%s: %zu of %zu values differ; worst at %zu: %.9g vs %.9g", what, bad, n, worst,
			 (double)a[worst], (double)b[worst]);
}

void tk_assert_rows_in_step(const dp_result *res, size_t n)
{
	assert_int_equal(res->surface.n, n);
	assert_int_equal(res->skeleton.n, n);
	for (size_t i = 0; i < n; i++) {
		float m[3] = {res->surface.x[i] - res->skeleton.x[i], res->surface.y[i] - res->skeleton.y[i],
			      res->surface.z[i] - res->skeleton.z[i]};
		float len = sqrtf(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
		assert_true(fabsf(len - res->length[i]) <= 1e-4f * (1.0f + len));
	}
}

static int tk_data_missing;

int tk_exit_status(int failed)
{
	return failed ? failed : tk_data_missing ? TK_EXIT_SKIPPED : 0;
}

const char *tk_data_path(const char *relative)
{
	static char path[8192];
	const char *dir = getenv("DP_DATA_DIR");
	char fallback[4096];
	if (!dir) {
		const char *src = getenv("DP_SOURCE_DIR");
		snprintf(fallback, sizeof fallback, "%s/../shared/data", src ? src : ".");
		dir = fallback;
	}
	snprintf(path, sizeof path, "%s/%s", dir, relative);
	struct stat sb;
	if (stat(path, &sb) != 0) {
		printf("SKIP: test data %s is absent (shared data folder not found)\n", path);
		tk_data_missing = 1;
		return NULL;
	}
	return path;
}

const char *tk_temp_dir(void)
{
	static char dir[64];
	snprintf(dir, sizeof dir, "/tmp/dpoints-test-XXXXXX");
	if (!mkdtemp(dir))
		fail_msg("mkdtemp failed");
	return dir;
}

void tk_scan_shape(const char *name, int views, int res, double noise, uint64_t seed, dp_shape *shape,
		   dp_cloud *mesh, dp_cloud *scan)
{
	dp_error err = {0};
	dp_shape s;
	dp_cloud m = {0};
	dp_scan_params sp;
	dp_scan_params_default(&sp);
	sp.views = views;
	sp.res = res;
	sp.noise = noise;
	sp.normals = 0;
	sp.seed = seed;
	if (dp_shape_default(name, &s, &err) != DP_OK || dp_shape_mesh(&s, &m, &err) != DP_OK ||
	    dp_scan(&m, &sp, scan, NULL, &err) != DP_OK)
		fail_msg("%s", err.message);
	if (shape)
		*shape = s;
	if (mesh)
		*mesh = m;
	else
		dp_cloud_free(&m);
}

void tk_normals_in_cap(size_t n, const double axis[3], double cap_deg, float *nx, float *ny, float *nz)
{
	double a[3] = {axis[0], axis[1], axis[2]}, len = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
	for (int c = 0; c < 3; c++)
		a[c] /= len;
	/* u, v across the axis */
	double e[3] = {fabs(a[0]) < 0.9 ? 1.0 : 0.0, fabs(a[0]) < 0.9 ? 0.0 : 1.0, 0.0};
	double u[3] = {a[1] * e[2] - a[2] * e[1], a[2] * e[0] - a[0] * e[2], a[0] * e[1] - a[1] * e[0]};
	double ul = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
	for (int c = 0; c < 3; c++)
		u[c] /= ul;
	double v[3] = {a[1] * u[2] - a[2] * u[1], a[2] * u[0] - a[0] * u[2], a[0] * u[1] - a[1] * u[0]};
	double zmin = cos(cap_deg * M_PI / 180.0), golden = M_PI * (3.0 - sqrt(5.0));
	for (size_t i = 0; i < n; i++) {
		double z = 1.0 - (1.0 - zmin) * ((double)i + 0.5) / (double)n, s = sqrt(1.0 - z * z), t = golden * (double)i;
		double w[3];
		for (int c = 0; c < 3; c++)
			w[c] = z * a[c] + s * cos(t) * u[c] + s * sin(t) * v[c];
		nx[i] = (float)w[0], ny[i] = (float)w[1], nz[i] = (float)w[2];
	}
}
