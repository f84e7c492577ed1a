#!/usr/bin/env bash
# `dpoints consolidate` on one small input as a user runs it: the output
# files, their contents, progress on stderr (and none with --quiet), and the
# extra files of --save-stages and --render.
source "$(dirname "$0")/support/cli_check.sh"

# A torus (tubes: a real skeleton) scanned from 4 sides with a little noise.
expect_ok scan scan --shape torus --views 4 --res 48 --noise 0.003 -o "$tmp/torus.ply" || finish
m=300

if expect_ok plain consolidate "$tmp/torus.ply" -o "$tmp/plain" --samples $m; then
	for f in surface.ply skeleton.ply dpoints.ply report.json; do
		[ -s "$tmp/plain/$f" ] || fail "consolidate: $f missing"
	done
	for f in wlop.ply anchors.ply input.png; do
		[ ! -e "$tmp/plain/$f" ] || fail "consolidate: $f written without --save-stages / --render"
	done
	if grep -qE '^consolidate: .*torus.ply: [0-9]+ points -> '$m' deep points \(kept from [0-9]+\)' "$tmp/plain.out"; then
		ok "summary: $(cat "$tmp/plain.out")"
	else
		fail "consolidate: no summary line on stdout: $(cat "$tmp/plain.out")"
	fi
	# progress: stage, iteration and elapsed time, for every stage that iterates
	for stage in wlop sink surface; do
		grep -qE "^ *\[ *[0-9.]+ s\] $stage +iteration +[0-9]+" "$tmp/plain.err" ||
			fail "no progress line for stage $stage on stderr: $(cat "$tmp/plain.err")"
	done
	if msg=$(py "$PLY_PY"'
import json, math
d, m = sys.argv[1], int(sys.argv[2])
names, surface, _ = read_ply(d + "/surface.ply")
if names != ["x", "y", "z", "nx", "ny", "nz", "length", "eta"] or len(surface) != m:
    sys.exit("surface.ply: %s, %d points" % (names, len(surface)))
names, skeleton, _ = read_ply(d + "/skeleton.ply")
if names != ["x", "y", "z"] or len(skeleton) != m:
    sys.exit("skeleton.ply: %s, %d points" % (names, len(skeleton)))
names, ends, elements = read_ply(d + "/dpoints.ply")
if len(ends) != 2 * m or elements.get("edge") != m:
    sys.exit("dpoints.ply: %d vertices, %s edges; expected %d and %d" % (len(ends), elements.get("edge"), 2 * m, m))
# the vertices are the surface points, then the skeleton points, in order
if ends[:m] != [s[:3] for s in surface] or ends[m:] != [q[:3] for q in skeleton]:
    sys.exit("dpoints.ply vertices are not the surface then the skeleton points")
# the length property is the deep point length |p - q|
worst = max(abs(math.dist(s[:3], q) - s[6]) for s, q in zip(surface, skeleton))
if worst > 1e-4:
    sys.exit("surface.ply length differs from |p - q| by up to %g" % worst)
r = json.load(open(d + "/report.json"))
for block in ("wlop", "normals", "sink", "skeleton", "surface"):
    if not r["parameters"].get(block):
        sys.exit("report.json: no parameters.%s" % block)
res = r["results"]
if res["deep_points"] != m or not res["r"] > 0:
    sys.exit("report.json: %s deep points, r = %s" % (res["deep_points"], res["r"]))
# fewer than the coarse level: run at the coarse count (at most the input size), an even subset kept
run, coarse = res["deep_points_run"], r["parameters"]["refine"]["coarse_samples"]
if not m < run <= coarse:
    sys.exit("report.json: %d deep points run for %d asked, coarse level %d" % (run, m, coarse))
# the spacing sinking ran at, and whether every anchor settled
if not isinstance(res["sink"]["converged"], bool) or res["sink"]["r"] <= 0:
    sys.exit("report.json: sink %r" % res["sink"])
# a complete torus is no one-sided scan: its surface stage starts on the whole coarse level
if r["parameters"]["refine"]["fill_samples"] != 2000 or res["filled_from"] != 0:
    sys.exit("report.json: fill_samples %s, filled_from %s" % (r["parameters"]["refine"]["fill_samples"],
                                                                res["filled_from"]))
for stage in ("wlop", "sink", "skeleton", "surface"):
    if not res[stage]["iterations"] > 0:
        sys.exit("report.json: %s ran %s iterations" % (stage, res[stage]["iterations"]))
print("%d deep points, %d edges, r = %.4g, report parses" % (m, m, res["r"]))
' "$tmp/plain" $m 2>&1); then ok "outputs: $msg"; else fail "outputs: $msg"; fi
fi

# The same run with every extra output, quietly.
if expect_ok extra consolidate "$tmp/torus.ply" -o "$tmp/extra" --samples $m --save-stages --render --quiet; then
	if [ -s "$tmp/extra.err" ]; then
		fail "--quiet: stderr is not empty: $(head -n 3 "$tmp/extra.err")"
	else
		ok "--quiet: nothing on stderr"
	fi
	# extra outputs do not change the result (same seed, same input)
	cmp -s "$tmp/plain/surface.ply" "$tmp/extra/surface.ply" ||
		fail "--save-stages --render changed surface.ply"
	if msg=$(py "$PLY_PY"'
m = int(sys.argv[2])
for name, extra in (("wlop.ply", []), ("anchors.ply", ["settled"])):
    names, rows, _ = read_ply(sys.argv[1] + "/" + name)
    if names != ["x", "y", "z", "nx", "ny", "nz"] + extra or len(rows) != m:
        sys.exit("%s: %s, %d points" % (name, names, len(rows)))
print("wlop.ply and anchors.ply: %d points with normals, the anchors with how they settled" % m)
' "$tmp/extra" $m 2>&1); then ok "--save-stages: $msg"; else fail "--save-stages: $msg"; fi
	pngs=0
	for f in input skeleton surface; do
		png_check "$tmp/extra/$f.png" && pngs=$((pngs + 1))
	done
	png_check "$tmp/extra/dpoints.png" 0 0 drawn && pngs=$((pngs + 1))
	[ "$pngs" -eq 4 ] && ok "--render: input, skeleton, surface and dpoints PNGs are valid"
fi

# How each anchor settled (anchors.ply's settled, the dp_settle code): the
# codes add up to report.json's counts, which sinking keeps apart from the
# codes. The torus above settles by fronts alone; a chair seen from one side
# settles all five ways, each a different number of times, so a code written
# as another shows (pytest checks the codes row by row against the library's).
if expect_ok chair1 scan --shape chair --views 1 --res 64 --noise 0.003 -o "$tmp/chair1.ply" &&
	expect_ok ways consolidate "$tmp/chair1.ply" -o "$tmp/ways" --samples 300 --save-stages --quiet; then
	if msg=$(py "$PLY_PY"'
import json
d = sys.argv[1]
names, rows, _ = read_ply(d + "/anchors.ply")
sink = json.load(open(d + "/report.json"))["results"]["sink"]
ways = ["unsettled", "settled_front", "settled_medial", "settled_width", "settled_slow", "settled_flat"]
counts = [0] * len(ways)
for row in rows:
    code = row[names.index("settled")]
    if code != int(code) or not 0 <= code < len(ways):
        sys.exit("anchors.ply: settled = %r is no dp_settle code" % code)
    counts[int(code)] += 1
want = [sink[w] for w in ways]
if counts != want:
    sys.exit("anchors.ply: settled counts %s, report.json %s" % (counts, want))
if sum(c > 0 for c in counts) < 3:
    sys.exit("anchors.ply: only %s: the scene no longer tells the ways apart" % counts)
print("anchors.ply: settled as report.json counts them (%s)" % " ".join(map(str, counts)))
' "$tmp/ways" 2>&1); then ok "settled: $msg"; else fail "settled: $msg"; fi
fi

# --samples Fx: F times the input's points; above the input it upsamples
# through the refined levels, and every output keeps one row per deep point.
raw=$(py "$PLY_PY"'
names, rows, _ = read_ply(sys.argv[1])
print(len(rows))
' "$tmp/torus.ply")
up=$((2 * raw))
# Defaults: the coarse level (at most --coarse-samples 4000) holds all the
# input's distinct positions, the levels above it the rest.
if expect_ok upsample consolidate "$tmp/torus.ply" -o "$tmp/up" --samples 2x --quiet; then
	if msg=$(py "$PLY_PY"'
import json
d, n = sys.argv[1], int(sys.argv[2])
for name in ("surface.ply", "skeleton.ply"):
    _, rows, _ = read_ply(d + "/" + name)
    if len(rows) != n:
        sys.exit("%s: %d rows, expected %d" % (name, len(rows), n))
rep = json.load(open(d + "/report.json"))
levels = rep["results"]["surface"]["levels"]
if rep["results"]["deep_points"] != n or len(levels) < 2 or levels[0]["points"] > n // 2 \
        or levels[-1]["points"] != n:
    sys.exit("report: %d deep points, levels %s" % (rep["results"]["deep_points"], levels))
print("%d raw points -> %d deep points in %d levels" % (n // 2, n, len(levels)))
' "$tmp/up" $up $m 2>&1); then ok "--samples 2x: $msg"; else fail "--samples 2x: $msg"; fi
fi
run bad_factor consolidate "$tmp/torus.ply" -o "$tmp/bad" --samples 0x
one_error_line bad_factor 2 "--samples"
run huge_factor consolidate "$tmp/torus.ply" -o "$tmp/bad" --samples 1e30x
one_error_line huge_factor 2 "deep points"
run bad_ratio consolidate "$tmp/torus.ply" -o "$tmp/bad" --ratio -1
one_error_line bad_ratio 2 "ratio"
# --coarse-samples 0 turns coarse to fine off, as its help says: one level.
if expect_ok one_level consolidate "$tmp/torus.ply" -o "$tmp/one" --samples $m --coarse-samples 0 --quiet; then
	if msg=$(py '
import json, sys
levels = json.load(open(sys.argv[1] + "/report.json"))["results"]["surface"]["levels"]
if len(levels) != 1:
    sys.exit("levels %s" % levels)
print("%d points in one level" % levels[0]["points"])
' "$tmp/one" 2>&1); then ok "--coarse-samples 0: $msg"; else fail "--coarse-samples 0: $msg"; fi
fi
run bad_coarse consolidate "$tmp/torus.ply" -o "$tmp/bad" --coarse-samples -1
one_error_line bad_coarse 2 "--coarse-samples"
run bad_level_factor consolidate "$tmp/torus.ply" -o "$tmp/bad" --level-factor 1
one_error_line bad_level_factor 2 "level factor"

# --even-rounds: the rounds run after the last level, show in the progress,
# keep one row per deep point and are counted in report.json.
if expect_ok even consolidate "$tmp/torus.ply" -o "$tmp/even" --samples $m --even-rounds 2; then
	grep -qE "^ *\[ *[0-9.]+ s\] even 2 +ended after 3/3 iterations: fixed iteration count" "$tmp/even.err" ||
		fail "--even-rounds 2: no end line for the second round: $(cat "$tmp/even.err")"
	if msg=$(py "$PLY_PY"'
import json
d, m = sys.argv[1], int(sys.argv[2])
for name in ("surface.ply", "skeleton.ply"):
    _, rows, _ = read_ply(d + "/" + name)
    if len(rows) != m:
        sys.exit("%s: %d rows, expected %d" % (name, len(rows), m))
rep = json.load(open(d + "/report.json"))
refine, surface = rep["parameters"]["refine"], rep["results"]["surface"]
run = rep["results"]["deep_points_run"]  # the rounds move points of the run the rows are kept from
if refine["even_rounds"] != 2 or refine["even_iters"] != 3 or not 0 <= surface["even_moved"] <= 2 * run // 10:
    sys.exit("report: %s, moved %s" % (refine, surface["even_moved"]))
print("%d rows, %d points moved" % (m, surface["even_moved"]))
' "$tmp/even" $m 2>&1); then ok "--even-rounds 2: $msg"; else fail "--even-rounds 2: $msg"; fi
fi
run bad_fill consolidate "$tmp/torus.ply" -o "$tmp/bad" --fill-samples 4
one_error_line bad_fill 2 "fill level 4"
run bad_even consolidate "$tmp/torus.ply" -o "$tmp/bad" --even-rounds -1
one_error_line bad_even 2 "even-spacing rounds"
run bad_even_iters consolidate "$tmp/torus.ply" -o "$tmp/bad" --even-iters 0
one_error_line bad_even_iters 2 "even-spacing rounds"

# The scan's outline: an axis given is used and reported (any length, 1e300
# too), with its edge margin; --no-silhouette reports none (300 samples are
# too few to find one); a negative edge margin is refused.
if expect_ok outline consolidate "$tmp/torus.ply" -o "$tmp/outline" --samples $m --view-axis 0,0,1e300 \
	--silhouette-edge-margin 1.5 &&
	expect_ok no_outline consolidate "$tmp/torus.ply" -o "$tmp/no_outline" --samples $m --no-silhouette; then
	if msg=$(py '
import json, sys
on, off = (json.load(open(d + "/report.json")) for d in sys.argv[1:3])
p, s = on["parameters"]["surface"], on["results"]["surface"]
if not p["silhouette"] or p["silhouette_axis"] != [0, 0, 1e300] or p["silhouette_margin_r"] != 2.5 \
        or p["silhouette_edge_margin_r"] != 1.5:
    sys.exit("parameters %s" % p)
if s["silhouette_axis"] != [0, 0, 1] or s["silhouette_grazing"] != -1 or s["silhouette_held"] < 0:
    sys.exit("results %s" % s)
t = off["results"]["surface"]
if off["parameters"]["surface"]["silhouette"] or t["silhouette_axis"] != [0, 0, 0] or t["silhouette_held"] != 0 \
        or t["silhouette_capped"] != 0:
    sys.exit("--no-silhouette: %s" % t)
print("axis %s, %d held, %d anchors capped" % (s["silhouette_axis"], s["silhouette_held"], s["silhouette_capped"]))
' "$tmp/outline" "$tmp/no_outline" 2>&1); then ok "--view-axis: $msg"; else fail "--view-axis: $msg"; fi
fi
run bad_edge consolidate "$tmp/torus.ply" -o "$tmp/bad" --silhouette-edge-margin -1
one_error_line bad_edge 2 "silhouette edge margin"
# Facing the scanner: a one-view scan whose eye lies along +x (the ring at
# elevation 0), with that axis given, is one-sided towards +x and reported
# so; --no-face-scanner reports no side and no turns.
if expect_ok scan1 scan --shape torus --views 1 --elevation 0 --res 64 --noise 0.003 -o "$tmp/torus1.ply" &&
	expect_ok face consolidate "$tmp/torus1.ply" -o "$tmp/face" --samples $m --view-axis -3,0,0 &&
	expect_ok no_face consolidate "$tmp/torus1.ply" -o "$tmp/no_face" --samples $m --view-axis -3,0,0 \
		--no-face-scanner --face-scanner-cos 0.7; then
	if msg=$(py '
import json, sys
on, off = (json.load(open(d + "/report.json")) for d in sys.argv[1:3])
p, s = on["parameters"]["surface"], on["results"]["surface"]
t = s["scanner"]
if not p["face_scanner"] or p["face_scanner_cos"] != 0.5 or p["scanner_side"] != 0 or len(t) != 3 \
        or abs(t[0] - 1) > 1e-6 or t[1] != 0 or t[2] != 0 or s["samples_turned"] != 0:
    sys.exit("on: %s, %s" % (p, s))
q, u = off["parameters"]["surface"], off["results"]["surface"]
if q["face_scanner"] or q["face_scanner_cos"] != 0.7 or u["scanner"] != [0, 0, 0] or u["samples_turned"] != 0 \
        or u["scanner_turned"] != 0:
    sys.exit("--no-face-scanner: %s, %s" % (q, u))
print("towards %s, %d held normals turned" % (t, s["scanner_turned"]))
' "$tmp/face" "$tmp/no_face" 2>&1); then ok "--no-face-scanner: $msg"; else fail "--no-face-scanner: $msg"; fi
fi
# The fill level: the one-sided scan's surface starts on a subset of its
# coarse level, which the summary line and report.json say.
if [ -s "$tmp/torus1.ply" ] && expect_ok fill consolidate "$tmp/torus1.ply" -o "$tmp/fill" --samples $m \
	--view-axis -3,0,0 --fill-samples 200; then
	if msg=$(py '
import json, re, sys
line = open(sys.argv[2]).read()
r = json.load(open(sys.argv[1] + "/report.json"))["results"]
run, filled, first = r["deep_points_run"], r["filled_from"], r["surface"]["levels"][0]["points"]
if filled != run or first != 200 or "(kept from %d; surface from a subset of 200)" % run not in line:
    sys.exit("filled_from %s, run %s, first level %s: %s" % (filled, run, first, line))
print(line.strip())
' "$tmp/fill" "$tmp/fill.out" 2>&1); then ok "--fill-samples 200: $msg"; else fail "--fill-samples 200: $msg"; fi
fi
run bad_face consolidate "$tmp/torus.ply" -o "$tmp/bad" --face-scanner-cos 1
one_error_line bad_face 2 "face-scanner cosine"
run bad_axis consolidate "$tmp/torus.ply" -o "$tmp/bad" --view-axis 0,1
one_error_line bad_axis 2 "three numbers"
run bad_margin consolidate "$tmp/torus.ply" -o "$tmp/bad" --silhouette-margin -1
one_error_line bad_margin 2 "silhouette margin"
run bad_grazing consolidate "$tmp/torus.ply" -o "$tmp/bad" --silhouette-grazing 2
one_error_line bad_grazing 2 "grazing fraction"

# A stage stopped at its cap says so on stderr, even with --quiet.
if expect_ok capped consolidate "$tmp/torus.ply" -o "$tmp/capped" --samples $m --wlop-iters 2 --quiet; then
	if grep -q "warning: stopped at the iteration cap before converging: wlop" "$tmp/capped.err"; then
		ok "cap warning: $(cat "$tmp/capped.err")"
	else
		fail "no cap warning for --wlop-iters 2: $(cat "$tmp/capped.err")"
	fi
fi

finish
