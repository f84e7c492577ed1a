/* The operators of host/ops/operators.h as the context runs them: dp_op_<op>
 * counts the candidate pairs, then calls the scalar reference or launches the
 * kernel, by the context's backend. */
#ifndef DP_BACKEND_OPS_H
#define DP_BACKEND_OPS_H

#include "backend/context.h"
#include "ops/operators.h"

#define DP_OP_DECLARE_RUN(op, kernel, FIELDS) \
	dp_status dp_op_##op(dp_context *ctx, const dp_##op##_args *a, dp_error *err);
DP_OPERATORS(DP_OP_DECLARE_RUN)
#undef DP_OP_DECLARE_RUN

/* Checks that every kernel of cl's program takes the arguments its table row
 * lists (names, types, address spaces, const), so that a launch cannot pass
 * an argument in the wrong place. The program must have been built with
 * -cl-kernel-arg-info (DP_CL_BUILD_OPTIONS). DP_ERR_KERNEL_BUILD, naming the
 * kernel and the first argument that differs, when one does not. */
dp_status dp_ops_check_kernels(dp_cl *cl, dp_error *err);

#endif
