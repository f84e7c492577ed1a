#!/usr/bin/env bash
# Every kernel compiles with clang's OpenCL C 1.2 front end for an NVIDIA GPU
# (nvptx64-nvidia-nvcl, down to PTX) in every lane form DP_LANES may take, so
# that nothing only PoCL accepts slips in: PoCL is itself clang, but a CPU
# target with extensions a GPU driver may lack. The files are joined in the
# order the build embeds them (grid.cl first). Exit 77 (skipped) without clang.
set -euo pipefail
src=${1:?usage: kernels_gpu.sh SOURCE_DIR}
clang=${CLANG:-clang}
if ! command -v "$clang" >/dev/null 2>&1; then
	echo "kernels_gpu: no $clang: skipped"
	exit 77
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
files=("$src/kernels/grid.cl")
while IFS= read -r f; do files+=("$f"); done < <(find "$src/kernels" -name '*.cl' ! -name grid.cl | LC_ALL=C sort)
cat "${files[@]}" > "$tmp/all.cl"
want=$(grep -c '__kernel void' "$tmp/all.cl")
# the host's options (DP_CL_BUILD_OPTIONS), for the GPU target
opts=(-x cl -cl-std=CL1.2 -cl-unsafe-math-optimizations -target nvptx64-nvidia-nvcl -O2 -Werror)
for lanes in 1 4 8 16; do
	"$clang" "${opts[@]}" -DDP_LANES="$lanes" -S -o "$tmp/all.ptx" "$tmp/all.cl"
	got=$(grep -c '\.entry' "$tmp/all.ptx")
	if [ "$got" -ne "$want" ]; then
		echo "kernels_gpu: DP_LANES=$lanes: $got PTX entries for $want kernels" >&2
		exit 1
	fi
	echo "kernels_gpu: DP_LANES=$lanes: $want kernels compiled for nvptx64"
done
# The check must be able to fail: a kernel calling what OpenCL C 1.2 lacks.
printf '__kernel void bad(__global float *a) { a[0] = not_an_opencl_builtin(a[0]); }\n' > "$tmp/bad.cl"
if "$clang" "${opts[@]}" -fsyntax-only "$tmp/bad.cl" 2>/dev/null; then
	echo "kernels_gpu: a kernel with an undeclared call compiled" >&2
	exit 1
fi
