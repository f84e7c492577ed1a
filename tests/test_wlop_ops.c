/* Every WLOP kernel equals its scalar reference (kernels/wlop.cl vs host/ref/wlop_ref.c). */
#include "testkit.h"

#include "backend/wlop_ops.h"

#include <stdlib.h>

typedef struct fixture {
	float *x, *y, *z; /* data (input points) */
	size_t n;
	float *sx, *sy, *sz; /* queries (samples) */
	size_t m;
	dp_grid grid;
	float h;
} fixture;

static int setup(void **state)
{
	fixture *f = calloc(1, sizeof *f);
	dp_rng rng;
	dp_rng_seed(&rng, 3);
	f->h = 0.9f;
	f->n = tk_random_points(&rng, 5000, 8.0f, f->h, &f->x, &f->y, &f->z);
	f->m = tk_random_points(&rng, 700, 8.0f, f->h, &f->sx, &f->sy, &f->sz);
	dp_error err = {0};
	if (dp_grid_build(&f->grid, f->n, f->x, f->y, f->z, f->h, &err) != DP_OK)
		return -1;
	*state = f;
	return 0;
}

static int teardown(void **state)
{
	fixture *f = *state;
	free(f->x);
	free(f->y);
	free(f->z);
	free(f->sx);
	free(f->sy);
	free(f->sz);
	dp_grid_free(&f->grid);
	free(f);
	return 0;
}

static void test_density(void **state)
{
	fixture *f = *state;
	float *ref = malloc(f->m * sizeof *ref), *cl = malloc(f->m * sizeof *cl);
	for (int variant = 0; variant < 2; variant++) {
		dp_density_args a = {
			.data = &f->grid, .nq = f->m, .qx = f->sx, .qy = f->sy, .qz = f->sz, .h = f->h,
			.theta_k = variant ? 4.0f : 16.0f, .min_d2 = 1e-10f, .sqrt_density = variant, .out = ref,
		};
		dp_error err = {0};
		assert_int_equal(dp_op_density(tk_ref_context(), &a, &err), DP_OK);
		a.out = cl;
		if (dp_op_density(tk_cl_context(), &a, &err) != DP_OK)
			fail_msg("%s", err.message);
		tk_assert_close(cl, ref, f->m, 1e-4f, 1e-5f, "density");
	}
	free(ref);
	free(cl);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_density),
	};
	int rc = cmocka_run_group_tests(tests, setup, teardown);
	tk_teardown_contexts(NULL);
	return rc;
}
