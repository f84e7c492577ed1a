#!/usr/bin/env bash
# The small commands as a user runs them: devices, scan, eval, render, help.
source "$(dirname "$0")/support/cli_check.sh"

# devices: PoCL's CPU device is listed as index 0
if expect_ok devices devices; then
	if grep -qE '^0: .+' "$tmp/devices.out"; then
		ok "devices: $(head -n 1 "$tmp/devices.out")"
	else
		fail "devices: no device with index 0: $(cat "$tmp/devices.out")"
	fi
fi

# help: the command list, and each command's options with their defaults
if expect_ok help --help && grep -q consolidate "$tmp/help.out"; then
	ok "dpoints --help lists the commands"
else
	fail "dpoints --help: $(cat "$tmp/help.out")"
fi
for c in demo consolidate wlop scan eval render devices; do
	if ! expect_ok "help_$c" "$c" --help || ! grep -q '^usage: dpoints '"$c" "$tmp/help_$c.out"; then
		fail "dpoints $c --help: $(head -n 2 "$tmp/help_$c.out")"
	fi
done
grep -q -- '--samples N .*\[default: 20000\]' "$tmp/help_eval.out" || fail "eval --help does not show defaults"
run noargs
[ "$status" -eq 2 ] || fail "dpoints without a command: exit status $status, expected 2"
run unknown frobnicate
[ "$status" -eq 2 ] && grep -q "unknown command 'frobnicate'" "$tmp/unknown.err" ||
	fail "unknown command: exit status $status: $(head -n 1 "$tmp/unknown.err")"

# scan: a complete exact scan of the sphere and a one-view scan, with the mesh
# written as ground truth
if expect_ok scan scan --shape sphere --views 6 --layout sphere --res 48 -o "$tmp/full.ply" --mesh-out "$tmp/gt.ply" &&
	expect_ok scan1 scan --shape sphere --views 1 --res 48 -o "$tmp/one.ply"; then
	ok "scan: $(cat "$tmp/scan.out")"
	# eval: exact samples lie on the mesh (accuracy ~0, float rounding only);
	# the complete scan covers the sphere, one view about half of it or less
	# (a perspective view sees less than a hemisphere)
	if expect_ok eval eval "$tmp/gt.ply" "$tmp/full.ply" --json && expect_ok eval1 eval "$tmp/gt.ply" "$tmp/one.ply" --json &&
		msg=$(py '
import json, sys
full, one = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
if full["accuracy_mean"] > 1e-6 or one["accuracy_mean"] > 1e-6:
    sys.exit("exact samples are off the surface: accuracy %g, %g" % (full["accuracy_mean"], one["accuracy_mean"]))
if full["coverage"] < 0.95:
    sys.exit("complete scan covers only %.3f" % full["coverage"])
if not 0.3 < one["coverage"] < 0.55:
    sys.exit("one view covers %.3f, expected about half or less" % one["coverage"])
if not 0.0 < full["scatter_median"] < 0.2:
    sys.exit("exact samples of a sphere scatter %g off it" % full["scatter_median"])
if full["normal_angle_deg"] > 0.01 or full["normal_flipped"] != 0:
    sys.exit("scanner normals: %g deg, %g flipped" % (full["normal_angle_deg"], full["normal_flipped"]))
print("coverage %.3f complete, %.3f one view; accuracy %.1g" % (full["coverage"], one["coverage"], full["accuracy_mean"]))
' "$tmp/eval.out" "$tmp/eval1.out" 2>&1); then
		ok "eval --json: $msg"
	else
		fail "eval: ${msg:-}"
	fi
	if expect_ok eval_text eval "$tmp/gt.ply" "$tmp/full.ply" && grep -q '^coverage  *0\.9' "$tmp/eval_text.out"; then
		ok "eval prints a table"
	else
		fail "eval text output: $(cat "$tmp/eval_text.out")"
	fi
	# render: two layers with colours, 2 views of 96 px side by side
	if expect_ok render render "$tmp/full.ply:red" "$tmp/one.ply:#0000ff" -o "$tmp/two.png" --views 2 --size 96 &&
		png_check "$tmp/two.png" 192 96 drawn; then
		ok "render: $(cat "$tmp/render.out")"
	fi
fi

# render draws a PLY's edges (deep points as segments): 40 vertical sticks
# cover many more pixels than their 80 end points alone
sticks='
import struct, sys
n, edges = 40, sys.argv[2] == "edges"
with open(sys.argv[1], "wb") as f:
    f.write(b"ply\nformat binary_little_endian 1.0\nelement vertex %d\n" % (2 * n))
    f.write(b"property float x\nproperty float y\nproperty float z\n")
    if edges:
        f.write(b"element edge %d\nproperty int vertex1\nproperty int vertex2\n" % n)
    f.write(b"end_header\n")
    for i in range(2 * n):
        f.write(struct.pack("<3f", (i % n) / n, i // n, 0))
    for i in range(n if edges else 0):
        f.write(struct.pack("<2i", i, n + i))
'
py "$sticks" "$tmp/sticks.ply" edges
py "$sticks" "$tmp/ends.ply" none
if expect_ok sticks render "$tmp/sticks.ply" -o "$tmp/sticks.png" --views 1 --size 64 --point-size 1 &&
	png_check "$tmp/sticks.png" 64 64 drawn && with_edges=$png_drawn &&
	expect_ok ends render "$tmp/ends.ply" -o "$tmp/ends.png" --views 1 --size 64 --point-size 1 &&
	png_check "$tmp/ends.png" 64 64 drawn; then
	if [ "$with_edges" -gt $((3 * png_drawn)) ]; then
		ok "render draws edges: $with_edges pixels with them, $png_drawn without"
	else
		fail "render: edges add little: $with_edges pixels with them, $png_drawn without"
	fi
fi

finish
