#!/usr/bin/env bash
# Issue 9 as a user meets it: a PLY element of empty rows, a far outlier, a
# huge radius and inputs spanning no volume each end with exit 2 and one
# line naming the input, quickly, instead of a hang, a crash or nonsense.
source "$(dirname "$0")/support/cli_check.sh"

py '
import math, sys
d = sys.argv[1]
def sphere(n):
    for i in range(n):
        t, p = math.acos(1 - 2 * (i + 0.5) / n), math.pi * (1 + 5 ** 0.5) * i
        yield (math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t))
def write(name, pts):
    with open(d + "/" + name, "w") as f:
        f.writelines("%.7g %.7g %.7g\n" % p for p in pts)
write("outlier.xyz", list(sphere(20)) + [(1e20, 0, 0)])
write("sphere.xyz", sphere(300))
write("three.xyz", [(-1, -1, -1), (1, 0.5, -0.2), (0.3, 1, 1)])
write("line.xyz", [(t / 50, 2 * t / 50, 3 * t / 50) for t in range(200)])
grid = [(i % 20 + 0.1 * (i % 7), i // 20 + 0.1 * (i % 3)) for i in range(400)]
write("plane.xyz", [(u, v, 0.5 * u - 0.25 * v) for u, v in grid])
# not quite flat (0.3% of its extent thick): passes the volume test; without
# the width bound sinking throws points far out, which the bound on every
# stage catches
write("nearly_flat.xyz", [(u, v, 0.5 * u - 0.25 * v + 0.03 * ((7 * i) % 3)) for i, (u, v) in enumerate(grid)])
' "$tmp"
printf 'ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nelement junk 18446744073709551615\nend_header\n1 2 3\n' >"$tmp/junk.ply"

check() {
	local name=$1 needle=$2
	shift 2
	status=0
	timeout 60 "$dpoints" "$@" >"$tmp/$name.out" 2>"$tmp/$name.err" || status=$?
	one_error_line "$name" 2 "$needle"
}
check junk junk.ply wlop "$tmp/junk.ply" -o "$tmp/o.ply" --quiet
check outlier outlier.xyz wlop "$tmp/outlier.xyz" -o "$tmp/o.ply" --samples 21 --quiet
check radius "too large" wlop "$tmp/sphere.xyz" -o "$tmp/o.ply" --samples 50 --radius 1e30 --quiet
for shape in three line plane; do
	check "$shape" "span no volume" consolidate "$tmp/$shape.xyz" -o "$tmp/$shape" --samples 3 --quiet
	if [ -e "$tmp/$shape" ]; then fail "$shape: left an output folder"; fi
done
check nearly_flat "far outside" consolidate "$tmp/nearly_flat.xyz" -o "$tmp/nearly_flat" --samples 100 \
	--width-factor 0 --quiet
if [ -e "$tmp/nearly_flat" ]; then fail "nearly_flat: left an output folder"; fi
# With the width bound (the default) no point sinks deeper than the plate is
# wide: the run succeeds, and the bound is what stopped the sinking.
status=0
timeout 60 "$dpoints" consolidate "$tmp/nearly_flat.xyz" -o "$tmp/bounded" --samples 100 --quiet \
	>"$tmp/bounded.out" 2>"$tmp/bounded.err" || status=$?
if [ "$status" -ne 0 ]; then
	fail "nearly_flat with the width bound: exit status $status: $(head -c 300 "$tmp/bounded.err")"
elif ! py 'import json, sys; sys.exit(json.load(open(sys.argv[1]))["results"]["sink"]["settled_width"] == 0)' \
	"$tmp/bounded/report.json"; then
	fail "nearly_flat with the width bound: report.json says no point settled by it"
else
	echo "ok   nearly_flat with the width bound: consolidated"
fi
finish
