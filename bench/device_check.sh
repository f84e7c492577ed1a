#!/usr/bin/env bash
# One OpenCL device, end to end, from a build folder: `dpoints devices`, the
# kernel-vs-reference tests (ctest label kernel_ref: the device's own choices
# and the GPU ones) on that device, a consolidation of the demo scan on it, and
# bench_stages (the OpenCL backend against the scalar reference on the same
# inputs). Everything the run prints goes to OUTDIR/device_check.log as well,
# the benchmark's JSON lines to OUTDIR/bench_stages.json. A GPU is where this
# matters: CI has PoCL and rusticl only, so this is how "any OpenCL device" is
# checked on one.
#
#   bench/device_check.sh BUILD_DIR DEVICE OUTDIR [bench_stages options...]
#
# DEVICE is what --device takes (index or name substring, `dpoints devices`).
# Exit status: the first failing step's (the later steps still run).
set -uo pipefail
usage="usage: device_check.sh BUILD_DIR DEVICE OUTDIR [bench_stages options]"
build=${1:?$usage}
device=${2:?$usage}
out=${3:?$usage}
shift 3
mkdir -p "$out" || exit 1
export DPOINTS_DEVICE=$device
status=0
step() {
	local name=$1
	shift
	echo "== $name: $*"
	local t0=$SECONDS
	"$@"
	local rc=$?
	echo "== $name: exit $rc, $((SECONDS - t0)) s"
	if [ "$rc" -ne 0 ] && [ "$status" -eq 0 ]; then status=$rc; fi
}
bench() {
	"$build/bench_stages" --device "$device" "$@" > "$out/bench_stages.json"
}
# ctest --test-dir needs CMake 3.20; the project asks for 3.18
kernel_tests() {
	(cd "$build" && ctest -L kernel_ref --output-on-failure --no-tests=error)
}
main() {
	step devices "$build/dpoints" devices
	step kernel_ref kernel_tests
	step demo "$build/dpoints" demo -o "$out/demo"
	step bench_stages bench "$@"
	return "$status"
}
main "$@" 2>&1 | tee "$out/device_check.log"
