#!/usr/bin/env bash
# A machine without OpenCL: the ICD loader is pointed at an empty vendor
# folder, so it finds no platform. `--backend ref` still runs everything;
# the OpenCL backend and `devices` fail with exit status 3 and one line.
source "$(dirname "$0")/support/cli_check.sh"

mkdir "$tmp/no-vendors"
export OCL_ICD_VENDORS=$tmp/no-vendors
unset DPOINTS_DEVICE

expect_ok scan scan --shape torus --views 3 --res 32 --noise 0.003 -o "$tmp/in.ply" || finish
out=$tmp/out
mkdir "$out"

run devices devices
one_error_line devices 3 "no platform or device"
run wlop_cl wlop "$tmp/in.ply" -o "$out/w.ply" --samples 100
one_error_line wlop_cl 3 "OpenCL" "--backend ref"
run consolidate_cl consolidate "$tmp/in.ply" -o "$out/c" --samples 100
one_error_line consolidate_cl 3 "OpenCL"
left=$(find "$out" -mindepth 1)
[ -z "$left" ] || fail "failed OpenCL runs left files behind: $left"

if expect_ok wlop_ref wlop "$tmp/in.ply" -o "$tmp/w.ply" --samples 100 --backend ref && [ -s "$tmp/w.ply" ]; then
	ok "wlop --backend ref: $(cat "$tmp/wlop_ref.out")"
fi
# 200 deep points: with 100 the whole skeleton of this scan lands 14 units
# below a 0.6-unit torus, which consolidate now refuses (issue 9, defect 6)
if expect_ok consolidate_ref consolidate "$tmp/in.ply" -o "$tmp/c" --samples 200 --backend ref --quiet; then
	for f in surface.ply skeleton.ply dpoints.ply report.json; do
		[ -s "$tmp/c/$f" ] || fail "consolidate --backend ref: $f missing"
	done
	grep -q '"backend": "ref"' "$tmp/c/report.json" || fail "consolidate --backend ref: report does not say ref"
	ok "consolidate --backend ref: $(cat "$tmp/consolidate_ref.out")"
fi
finish
