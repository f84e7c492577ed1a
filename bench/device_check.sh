#!/usr/bin/env bash
# One OpenCL device, end to end, from a build folder: `dpoints devices`, the
# kernel-vs-reference tests (ctest label kernel_ref: the device's own choices
# and the GPU ones) on that device, a consolidation of the demo scan on it, and
# bench_stages (the OpenCL backend against the scalar reference on the same
# inputs). Everything the run prints goes to OUTDIR as well, the benchmark's
# JSON lines to OUTDIR/bench_stages.json. A GPU is where this matters: CI has
# PoCL and rusticl only, so this is how "any OpenCL device" is checked on one.
#
#   bench/device_check.sh BUILD_DIR DEVICE OUTDIR [bench_stages options...]
#
# DEVICE is what --device takes (index or name substring, `dpoints devices`).
# Exit status: the first failing step's (the later steps still run).
set -uo pipefail
build=${1:?usage: device_check.sh BUILD_DIR DEVICE OUTDIR [bench_stages options]}
device=${2:?usage: device_check.sh BUILD_DIR DEVICE OUTDIR [bench_stages options]}
out=${3:?usage: device_check.sh BUILD_DIR DEVICE OUTDIR [bench_stages options]}
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
exec > >(tee "$out/device_check.log") 2>&1
step devices "$build/dpoints" devices
step kernel_ref ctest --test-dir "$build" -L kernel_ref --output-on-failure
step demo "$build/dpoints" demo -o "$out/demo"
step bench_stages bench "$@"
exit "$status"
