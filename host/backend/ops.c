#include "backend/ops.h"
#include "backend/neighbours.h"

#include "core/common.h"
#include "core/parallel.h"

#include <string.h>

/* Kernel arguments of the largest row, n excluded (surface_neighbour has 32). */
#define OPS_MAX_ARGS 40

/* One call of an operator, gathered from its row: the kernel's arguments in
 * order, and what the pair count and the reach check need. */
typedef struct op_call {
	const char *op;
	const char *kernel;
	size_t nq;
	const dp_grid *grid;
	const float *pos[3];
	int npos;
	const float *reach;
	int has_cells, cells; /* a CELLS field and its value */
	float radius;
	const float *metric;
	dp_cl_arg args[OPS_MAX_ARGS];
	size_t nargs;
	dp_cl_grid_storage grid_values;
	int attr_before_grid;
} op_call;

/* Kernel arguments of each row, n included: the arrays below hold them. */
#define OP_COUNT(kind, type, name, width) +OP_COUNT_##kind
#define OP_COUNT_POS 1
#define OP_COUNT_QUERY 1
#define OP_COUNT_REACH 1
#define OP_COUNT_GRID DP_CL_GRID_NARGS
#define OP_COUNT_ATTR 1
#define OP_COUNT_CELLS 1
#define OP_COUNT_RADIUS 1
#define OP_COUNT_METRIC 1
#define OP_COUNT_PARAM 1
#define OP_COUNT_OUT 1
#define OP_ASSERT_SIZE(op, kernel, FIELDS) \
	_Static_assert(1 FIELDS(OP_COUNT) <= OPS_MAX_ARGS + 1, #op ": more kernel arguments than OPS_MAX_ARGS");
DP_OPERATORS(OP_ASSERT_SIZE)

/* Each row has one RADIUS (the true-neighbour counts need it). */
#define OP_RADII(kind, type, name, width) +OP_RADII_##kind
#define OP_RADII_POS 0
#define OP_RADII_QUERY 0
#define OP_RADII_REACH 0
#define OP_RADII_GRID 0
#define OP_RADII_ATTR 0
#define OP_RADII_CELLS 0
#define OP_RADII_RADIUS 1
#define OP_RADII_METRIC 0
#define OP_RADII_PARAM 0
#define OP_RADII_OUT 0
#define OP_ASSERT_RADIUS(op, kernel, FIELDS) _Static_assert(0 FIELDS(OP_RADII) == 1, #op ": not one RADIUS");
DP_OPERATORS(OP_ASSERT_RADIUS)

static void add_arg(op_call *c, dp_cl_arg arg)
{
	c->args[c->nargs++] = arg;
}

static void add_pos(op_call *c, const float *p)
{
	if (c->npos < 3)
		c->pos[c->npos] = p;
	c->npos++;
	add_arg(c, DP_CL_IN(p, c->nq * sizeof(float)));
}

static void add_grid(op_call *c, const dp_grid *g)
{
	dp_cl_arg grid_args[DP_CL_GRID_NARGS];
	c->grid = g;
	dp_cl_grid_args(g, &c->grid_values, grid_args);
	for (int k = 0; k < DP_CL_GRID_NARGS; k++)
		add_arg(c, grid_args[k]);
}

/* Per-grid-point arrays follow the grid (the table's rule): their size is
 * the grid's. */
static size_t grid_points(op_call *c)
{
	if (!c->grid) {
		c->attr_before_grid = 1;
		return 0;
	}
	return c->grid->n;
}

#define OP_GATHER(kind, type, name, width) OP_GATHER_##kind(type, name, width)
#define OP_GATHER_POS(type, name, width) add_pos(&c, a->name);
#define OP_GATHER_QUERY(type, name, width) add_arg(&c, DP_CL_IN(a->name, a->nq * (width) * sizeof(type)));
#define OP_GATHER_REACH(type, name, width)                                      \
	c.reach = a->name;                                                      \
	add_arg(&c, DP_CL_IN(a->name, a->nq * (width) * sizeof(type)));
#define OP_GATHER_GRID(type, name, width) add_grid(&c, a->name);
#define OP_GATHER_ATTR(type, name, width) \
	add_arg(&c, DP_CL_IN(a->name, grid_points(&c) * (width) * sizeof(type)));
#define OP_GATHER_CELLS(type, name, width)                                      \
	c.has_cells = 1;                                                        \
	c.cells = a->name;                                                      \
	add_arg(&c, DP_CL_VALUE(a->name));
#define OP_GATHER_PARAM(type, name, width) add_arg(&c, DP_CL_VALUE(a->name));
#define OP_GATHER_RADIUS(type, name, width)                                     \
	c.radius = a->name;                                                     \
	add_arg(&c, DP_CL_VALUE(a->name));
#define OP_GATHER_METRIC(type, name, width)                                     \
	c.metric = a->name;                                                     \
	add_arg(&c, DP_CL_IN(a->name, a->nq * (width) * sizeof(type)));
#define OP_GATHER_OUT(type, name, width) add_arg(&c, DP_CL_OUT(a->name, a->nq * (width) * sizeof(type)));

/* Every query's reach must lie within the grid's margin (operators.h). */
static dp_status check_reach(const op_call *c, dp_error *err)
{
	double limit = (double)c->grid->margin * (double)c->grid->cell;
	for (size_t k = 0; k < 3 * c->nq; k++)
		if (!((double)c->reach[k] <= limit))
			return dp_fail(err, DP_ERR_ARG,
				       "%s: query %zu reaches %g, beyond the grid's margin of %d cells of %g", c->op,
				       k / 3, (double)c->reach[k], c->grid->margin, (double)c->grid->cell);
	return DP_OK;
}

/* Candidate pairs are counted for the reports on the host, per query, as
 * many as the kernel's cells hold: on a GPU that count cost more than some
 * kernels, so it is split across threads; each range's sum is an integer
 * below 2^53, exact in a double, and the ranges are added in order. */
#define CANDIDATES_MIN_ITEMS 4096

typedef struct candidates_job {
	const op_call *c;
	double part_sum[DP_PARALLEL_MAX];
} candidates_job;

static void candidates_range(void *arg, size_t begin, size_t end, int part)
{
	candidates_job *job = arg;
	const op_call *c = job->c;
	size_t m = end - begin;
	const float *x = c->pos[0] + begin, *y = c->pos[1] + begin, *z = c->pos[2] + begin;
	if (c->reach)
		job->part_sum[part] = dp_grid_candidates_reach(c->grid, m, x, y, z, c->reach + 3 * begin);
	else if (c->has_cells)
		job->part_sum[part] = dp_grid_candidates_cells(c->grid, m, x, y, z, c->cells);
	else
		job->part_sum[part] = dp_grid_candidates(c->grid, m, x, y, z);
}

static double candidates(int threads, const op_call *c)
{
	candidates_job job = {.c = c};
	int parts = dp_parallel_for(threads, c->nq, CANDIDATES_MIN_ITEMS, candidates_range, &job);
	double total = 0.0;
	for (int k = 0; k < parts; k++)
		total += job.part_sum[k];
	return total;
}

static dp_status run(dp_context *ctx, op_call *c, void (*ref)(const void *), const void *a, dp_error *err)
{
	if (c->npos != 3 || !c->grid || c->attr_before_grid || (c->metric && !c->reach))
		return dp_fail(err, DP_ERR_INTERNAL,
			       "%s: its row needs 3 POS fields, a grid before any ATTR and a REACH with its METRIC", c->op);
	if (c->reach) {
		dp_status st = check_reach(c, err);
		if (st != DP_OK)
			return st;
	} else if (c->has_cells && (c->cells < 1 || c->cells > c->grid->margin)) {
		return dp_fail(err, DP_ERR_ARG, "%s: reach %d outside 1..the grid's margin of %d cells", c->op, c->cells,
			       c->grid->margin);
	}
	ctx->pair_evaluations += candidates(ctx->threads, c);
	if (c->metric)
		dp_count_neighbours_metric(ctx, c->kernel, c->grid, c->nq, c->pos[0], c->pos[1], c->pos[2], c->metric,
					   c->reach, c->radius);
	else
		dp_count_neighbours(ctx, c->kernel, c->grid, c->nq, c->pos[0], c->pos[1], c->pos[2], c->radius);
	if (ctx->kind == DP_BACKEND_REF) {
		ref(a);
		return DP_OK;
	}
	return dp_cl_launch(&ctx->cl, c->kernel, c->nq, c->args, c->nargs, err);
}

#define OP_DEFINE_RUN(OPNAME, KERNEL, FIELDS)                                                    \
	static void ref_##OPNAME(const void *a)                                                  \
	{                                                                                    \
		dp_ref_##OPNAME(a);                                                              \
	}                                                                                    \
	dp_status dp_op_##OPNAME(dp_context *ctx, const dp_##OPNAME##_args *a, dp_error *err)       \
	{                                                                                    \
		op_call c;                                                                   \
		memset(&c, 0, sizeof c);                                                     \
		c.op = #OPNAME;                                                                  \
		c.kernel = #KERNEL;                                                          \
		c.nq = a->nq;                                                                \
		FIELDS(OP_GATHER)                                                            \
		return run(ctx, &c, ref_##OPNAME, a, err);                                       \
	}
DP_OPERATORS(OP_DEFINE_RUN)

/* ---- The signature check ------------------------------------------------ */

/* The kernel's type name of each table type (OpenCL C spells int32_t int). */
#define OP_CL_TYPE_float "float"
#define OP_CL_TYPE_int "int"
#define OP_CL_TYPE_int32_t "int"

#define OP_EXPECT(kind, type, name, width) OP_EXPECT_##kind(type, name)
#define OP_EXPECT_IN(type, name) \
	want[k++] = (dp_cl_param){#name, OP_CL_TYPE_##type "*", DP_CL_PARAM_GLOBAL_CONST};
#define OP_EXPECT_POS OP_EXPECT_IN
#define OP_EXPECT_QUERY OP_EXPECT_IN
#define OP_EXPECT_REACH OP_EXPECT_IN
#define OP_EXPECT_ATTR OP_EXPECT_IN
#define OP_EXPECT_GRID(type, name)                          \
	memcpy(want + k, grid, sizeof grid);                \
	k += DP_CL_GRID_NARGS;
#define OP_EXPECT_CELLS OP_EXPECT_PARAM
#define OP_EXPECT_RADIUS OP_EXPECT_PARAM
#define OP_EXPECT_METRIC OP_EXPECT_IN
#define OP_EXPECT_PARAM(type, name) want[k++] = (dp_cl_param){#name, OP_CL_TYPE_##type, DP_CL_PARAM_VALUE};
#define OP_EXPECT_OUT(type, name) want[k++] = (dp_cl_param){#name, OP_CL_TYPE_##type "*", DP_CL_PARAM_GLOBAL};

#define OP_CHECK(op, kernel, FIELDS)                                                 \
	{                                                                            \
		size_t k = 0;                                                        \
		want[k++] = (dp_cl_param){"n", "uint", DP_CL_PARAM_VALUE};           \
		FIELDS(OP_EXPECT)                                                    \
		if ((st = dp_cl_check_signature(cl, #kernel, want, k, err)) != DP_OK) \
			return st;                                                   \
	}

dp_status dp_ops_check_kernels(dp_cl *cl, dp_error *err)
{
	dp_cl_param grid[DP_CL_GRID_NARGS];
	dp_cl_grid_params(grid);
	dp_cl_param want[OPS_MAX_ARGS + 1];
	dp_status st = DP_OK;
	DP_OPERATORS(OP_CHECK)
	return st;
}
