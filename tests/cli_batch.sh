#!/usr/bin/env bash
# `dpoints consolidate` over several inputs: one sub-folder per input (unique
# even when file names repeat), a bad file reported and skipped while the
# others finish, a summary table, a non-zero exit status. Then a batch over
# small real scans of several formats from the shared data, when present.
source "$(dirname "$0")/support/cli_check.sh"

mkdir "$tmp/a" "$tmp/b"
expect_ok scan_a scan --shape torus --views 3 --res 40 --noise 0.003 -o "$tmp/a/scan.ply" || finish
expect_ok scan_b scan --shape cylinder --views 3 --res 40 --noise 0.003 -o "$tmp/b/scan.ply" || finish
printf '0 0 0\n1 0 0\n0 1 0\n0 0 nan\n' >"$tmp/bad.xyz"

run batch consolidate "$tmp/a/scan.ply" "$tmp/bad.xyz" "$tmp/b/scan.ply" -o "$tmp/out" --samples 150
if [ "$status" -eq 2 ]; then
	ok "batch with a bad file exits with status 2"
else
	fail "batch with a bad file: exit status $status, expected 2"
fi
for d in scan scan-3; do
	for f in surface.ply skeleton.ply dpoints.ply report.json; do
		[ -s "$tmp/out/$d/$f" ] || fail "batch: $d/$f missing"
	done
done
[ ! -e "$tmp/out/bad" ] || fail "batch: a folder was made for the bad input"
grep -qF "$tmp/bad.xyz" "$tmp/batch.err" && grep -q 'non-finite' "$tmp/batch.err" ||
	fail "batch: the bad file is not reported on stderr: $(cat "$tmp/batch.err")"
grep -q '1 of 3 inputs failed' "$tmp/batch.err" || fail "batch: no failure count on stderr"
grep -qF "[2/3] $tmp/bad.xyz" "$tmp/batch.err" || fail "batch: no per-input progress on stderr"
# the table: a header, one row per input in order, a totals line
if msg=$(py '
import json, sys
lines = open(sys.argv[1]).read().split("\n")
start = next((i for i, l in enumerate(lines) if l.split()[:4] == ["input", "points", "dpoints", "run"]), None)
if start is None:
    sys.exit("no summary table on stdout")
rows = lines[start + 1:start + 4]
want = [(sys.argv[2], "ok"), (sys.argv[3], "FAILED:"), (sys.argv[4], "ok")]
for row, (name, state) in zip(rows, want):
    t = row.split()
    if t[0] != name or state not in t:
        sys.exit("table row %r, expected %s %s" % (row, name, state))
    if state == "ok" and t[2] != "150":
        sys.exit("table row %r: not 150 deep points" % row)
if [t[3] for t in (rows[0].split(), rows[2].split())] != [
        str(json.load(open(sys.argv[5] + "/" + d + "/report.json"))["results"]["deep_points_run"])
        for d in ("scan", "scan-3")]:
    sys.exit("the run column is not deep_points_run of the reports: %r" % rows)
if not lines[start + 4].startswith("3 inputs: 2 ok, 1 failed"):
    sys.exit("no totals line: %r" % lines[start + 4])
print("\n".join(lines[start:start + 5]))
' "$tmp/batch.out" "$tmp/a/scan.ply" "$tmp/bad.xyz" "$tmp/b/scan.ply" "$tmp/out" 2>&1); then
	ok "summary table:"
	echo "$msg"
else
	fail "summary table: $msg"
fi

# Real scans, one of each format: xyz, ascii PCD, NOFF, binary PLY with doubles.
data=${DP_DATA_DIR:-${DP_SOURCE_DIR:-$(dirname "$0")/..}/../shared/data}
scans=(cgal/fin90_with_PCA_normals.xyz pcn/chair.pcd cloudcontr/fertility_1n.off cgal/hippo2.ply)
paths=()
for s in "${scans[@]}"; do
	[ -f "$data/$s" ] && paths+=("$data/$s")
done
if [ "${#paths[@]}" -ne "${#scans[@]}" ]; then
	skip "the batch over real scans: ${scans[*]} not all found in $data"
else
	if expect_ok real consolidate "${paths[@]}" -o "$tmp/real" --quiet; then
		for s in "${scans[@]}"; do
			name=$(basename "${s%.*}")
			[ -s "$tmp/real/$name/surface.ply" ] || fail "real scans: $name/surface.ply missing"
		done
		ok "batch over ${#scans[@]} real scans:"
		sed -n '/^input /,$p' "$tmp/real.out"
	fi
fi
finish
