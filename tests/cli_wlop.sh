#!/usr/bin/env bash
# `dpoints wlop` as a user runs it: a scanned noisy sphere in, a PLY with
# oriented normals and a JSON report holding every parameter out, and the
# scalar reference agreeing with the OpenCL backend.
source "$(dirname "$0")/support/cli_check.sh"

# A unit sphere at the origin seen from 6 sides, noise 0.3% of the diagonal.
expect_ok scan scan --shape sphere --views 6 --layout sphere --res 48 --noise 0.003 -o "$tmp/sphere.ply" || finish

# Every parameter away from its default, so the report shows what was used.
params=(--samples 400 --h-factor 4 --mu 0.4 --iters 60 --tol 0.003 --stall-tol 0.02 --window 8 --min-drop 0.2 --theta-k 8 --weight l1 --seed 7
	--normal-k 12 --graph-k 6)
if expect_ok wlop wlop "$tmp/sphere.ply" -o "$tmp/wlop.ply" --report "$tmp/report.json" "${params[@]}"; then
	if grep -qE '^wlop: [0-9]+ points in, 400 out, h = ' "$tmp/wlop.out"; then
		ok "wlop summary: $(cat "$tmp/wlop.out")"
	else
		fail "wlop: no summary line on stdout: $(cat "$tmp/wlop.out")"
	fi
	# Progress on stderr, as consolidate gives it: a big input is not silent.
	# In order: WLOP's end line (with its cap) before the normals; below 4000
	# samples the denser samples that sign them, a WLOP run of their own name.
	if grep -qE '^  \[ *[0-9.]+ s\] wlop +iteration +1/60, mean move ' "$tmp/wlop.err" &&
		[ "$(grep -oE '\] (wlop +ended|normals|denser +ended|write)' "$tmp/wlop.err" | tr -s ' ' | tr '\n' ,)" = \
			"] wlop ended,] normals,] denser ended,] write," ] &&
		grep -qE '\] wlop +ended after [0-9]+/60 iterations: ' "$tmp/wlop.err"; then
		ok "wlop progress: $(wc -l <"$tmp/wlop.err") lines on stderr"
	else
		fail "wlop: no progress on stderr: $(cat "$tmp/wlop.err")"
	fi
	# Normals: unit length and, on a sphere at the origin, pointing away from it.
	if msg=$(py "$PLY_PY"'
import math
names, rows, elements = read_ply(sys.argv[1])
if names != ["x", "y", "z", "nx", "ny", "nz"]:
    sys.exit("properties %s, expected x y z nx ny nz" % names)
if len(rows) != 400:
    sys.exit("%d points, expected 400" % len(rows))
bad_len = sum(1 for r in rows if abs(math.sqrt(r[3] ** 2 + r[4] ** 2 + r[5] ** 2) - 1) > 1e-3)
inward = sum(1 for r in rows if r[0] * r[3] + r[1] * r[4] + r[2] * r[5] <= 0)
if bad_len:
    sys.exit("%d normals are not unit vectors" % bad_len)
# the issue asks for at least 99% outward on the sphere
if inward > 0.01 * len(rows):
    sys.exit("%d of %d normals point inwards" % (inward, len(rows)))
print("400 unit normals, %d inward" % inward)
' "$tmp/wlop.ply" 2>&1); then ok "wlop.ply: $msg"; else fail "wlop.ply: $msg"; fi
	# The report: every parameter with the value given, and the counts.
	if msg=$(py '
import json, sys
r = json.load(open(sys.argv[1]))
inputs = int(sys.argv[2])
want = {"wlop": {"samples": 400, "ratio": 0.1, "h": 0, "h_factor": 4, "mu": 0.4, "max_iters": 60, "tol": 0.003, "stall_tol": 0.02, "window": 8, "min_drop": 0.2,
                 "theta_k": 8, "weight": "l1", "sqrt_density": False, "seed": 7},
        "normals": {"k": 12, "k_graph": 6, "use_viewpoint": False}}
p = r["parameters"]
for block, values in want.items():
    for key, value in values.items():
        if p[block].get(key) != value:
            sys.exit("parameters.%s.%s = %r, expected %r" % (block, key, p[block].get(key), value))
    extra = set(p[block]) - set(values)
    if extra:
        sys.exit("parameters.%s has keys this test does not know: %s (add them)" % (block, sorted(extra)))
res = r["results"]
if res["points_in"] != inputs or res["points_out"] != 400:
    sys.exit("results: %d in, %d out; expected %d, 400" % (res["points_in"], res["points_out"], inputs))
if not (0 < res["iterations"] <= 60 and res["h"] > 0):
    sys.exit("results: %d iterations, h = %g" % (res["iterations"], res["h"]))
if r["backend"] != "cl" or not r["device"]:
    sys.exit("backend %r device %r" % (r["backend"], r["device"]))
print("%d parameters as given; %d in, %d iterations, h = %.4g" %
      (sum(len(v) for v in want.values()), inputs, res["iterations"], res["h"]))
' "$tmp/report.json" "$(sed -n 's/^scan: .* -> \([0-9]*\) points in .*/\1/p' "$tmp/scan.out")" 2>&1); then
		ok "report.json: $msg"
	else
		fail "report.json: $msg"
	fi
fi

# The reference backend on a tiny input: the same samples. The backends differ
# only in the order of float sums, so positions agree to float rounding
# amplified over the iterations (measured: 4e-7 on a unit sphere); 1e-4 of
# the radius leaves room for that and still catches any real difference.
expect_ok tiny scan --shape sphere --views 4 --res 24 --noise 0.003 -o "$tmp/tiny.ply" || finish
tiny_params=(--samples 80 --iters 20)
if expect_ok tiny_cl wlop "$tmp/tiny.ply" -o "$tmp/tiny_cl.ply" "${tiny_params[@]}" &&
	expect_ok tiny_ref wlop "$tmp/tiny.ply" -o "$tmp/tiny_ref.ply" --backend ref --quiet "${tiny_params[@]}"; then
	if [ -s "$tmp/tiny_ref.err" ]; then
		fail "wlop --quiet wrote on stderr: $(cat "$tmp/tiny_ref.err")"
	else
		ok "wlop --quiet: nothing on stderr"
	fi
	msg=""
	if grep -q 'ref on reference' "$tmp/tiny_ref.out" && msg=$(py "$PLY_PY"'
_, a, _ = read_ply(sys.argv[1])
_, b, _ = read_ply(sys.argv[2])
if len(a) != len(b):
    sys.exit("cl wrote %d points, ref %d" % (len(a), len(b)))
worst = max(abs(u - v) for p, q in zip(a, b) for u, v in zip(p[:3], q[:3]))
if worst > 1e-4:
    sys.exit("positions differ by up to %g" % worst)
print("%d points each, positions within %.2g" % (len(a), worst))
' "$tmp/tiny_cl.ply" "$tmp/tiny_ref.ply" 2>&1); then
		ok "--backend ref agrees with cl: $msg"
	else
		fail "--backend ref against cl: ${msg:-the summary does not name the reference: $(cat "$tmp/tiny_ref.out")}"
	fi
fi

finish
