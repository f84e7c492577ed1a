#!/usr/bin/env bash
# Issue 9, defect 4: a consolidate output folder holds one complete result set
# or none. A re-run replaces the whole set (files the new run did not write go),
# temporaries of dead runs are removed, a run killed at any moment leaves the
# old set or nothing, and a folder holding anything but a result is refused.
source "$(dirname "$0")/support/cli_check.sh"

expect_ok scan scan --shape torus --views 4 --res 48 --noise 0.003 -o "$tmp/torus.ply" || finish
expect_ok scan_big scan --shape torus --views 4 --res 128 --noise 0.003 -o "$tmp/big.ply" || finish

# consistent DIR: empty output, or every file of one result with matching rows.
CONSISTENT_PY="$PLY_PY"'
import json, os
d = sys.argv[1]
names = sorted(os.listdir(d)) if os.path.isdir(d) else []
if not names:
    print("no result"); sys.exit(0)
want = ["dpoints.ply", "report.json", "skeleton.ply", "surface.ply"]
if [n for n in names if n not in ("wlop.ply", "anchors.ply")] != want:
    sys.exit("files %s, expected %s" % (names, want))
n = json.load(open(d + "/report.json"))["results"]["deep_points"]
rows = {k: len(read_ply(d + "/" + k)[1]) for k in ("surface.ply", "skeleton.ply")}
edges = read_ply(d + "/dpoints.ply")[2].get("edge")
if rows["surface.ply"] != n or rows["skeleton.ply"] != n or edges != n:
    sys.exit("report.json says %d deep points, rows %s, %s edges" % (n, rows, edges))
print("%d deep points in every file" % n)
'
consistent() {
	local msg
	if msg=$(py "$CONSISTENT_PY" "$2" 2>&1); then ok "$1: $msg"; else fail "$1: $msg"; fi
}

# A re-run without --save-stages leaves no wlop.ply / anchors.ply behind; the
# stale staging folder and per-file temporary of a dead run go, those of a live
# run (this shell) stay.
out=$tmp/out
if expect_ok stages consolidate "$tmp/torus.ply" -o "$out" --samples 300 --save-stages --quiet; then
	[ -s "$out/wlop.ply" ] || fail "stages: no wlop.ply"
	mkdir "$out.tmp.99999999" "$out.old.99999998" "$out.tmp.$$"
	touch "$out.tmp.99999999/surface.ply" "$out.old.99999998/report.json" "$out/skeleton.ply.tmp.99999997"
	if expect_ok rerun consolidate "$tmp/torus.ply" -o "$out" --samples 200 --quiet; then
		for f in wlop.ply anchors.ply skeleton.ply.tmp.99999997; do
			[ ! -e "$out/$f" ] || fail "rerun: $f of the earlier run is still there"
		done
		for f in "$out.tmp.99999999" "$out.old.99999998"; do
			[ ! -e "$f" ] || fail "rerun: $f of a dead run is still there"
		done
		[ -d "$out.tmp.$$" ] || fail "rerun: removed the staging folder of a live run"
		consistent rerun "$out"
		grep -q '"deep_points": 200' "$out/report.json" || fail "rerun: report.json is not the new one"
	fi
	rmdir "$out.tmp.$$"
fi

# A batch replaces each input's sub-folder the same way.
mkdir "$tmp/b"
cp "$tmp/torus.ply" "$tmp/b/one.ply"
cp "$tmp/torus.ply" "$tmp/b/two.ply"
if expect_ok batch1 consolidate "$tmp/b/one.ply" "$tmp/b/two.ply" -o "$tmp/bo" --samples 300 --save-stages --quiet &&
	expect_ok batch2 consolidate "$tmp/b/one.ply" "$tmp/b/two.ply" -o "$tmp/bo" --samples 200 --quiet; then
	for d in one two; do
		[ ! -e "$tmp/bo/$d/wlop.ply" ] || fail "batch: $d/wlop.ply of the earlier run is still there"
		consistent "batch $d" "$tmp/bo/$d"
	done
fi

# Killed with SIGKILL at several moments of a run that replaces an older set:
# the folder holds the old set, the new one, or nothing, never a mix.
kill_dir=$tmp/kill
expect_ok timed consolidate "$tmp/big.ply" -o "$tmp/timed" --samples 3000 --quiet || finish
start=$(date +%s.%N)
expect_ok timed2 consolidate "$tmp/big.ply" -o "$tmp/timed" --samples 3000 --quiet || finish
seconds=$(python3 -c "import sys; print(float(sys.argv[2]) - float(sys.argv[1]))" "$start" "$(date +%s.%N)")
for frac in 0.1 0.5 0.8 0.9 0.95 0.98 1.0; do
	delay=$(python3 -c "import sys; print(max(0.05, float(sys.argv[1]) * float(sys.argv[2])))" "$seconds" "$frac")
	expect_ok "old_$frac" consolidate "$tmp/torus.ply" -o "$kill_dir" --samples 300 --save-stages --quiet || continue
	"$dpoints" consolidate "$tmp/big.ply" -o "$kill_dir" --samples 3000 --quiet >/dev/null 2>&1 &
	pid=$!
	sleep "$delay"
	kill -KILL "$pid" 2>/dev/null || true
	wait "$pid" 2>/dev/null || true
	consistent "killed after ${delay}s" "$kill_dir"
done
if expect_ok after_kill consolidate "$tmp/torus.ply" -o "$kill_dir" --samples 300 --quiet; then
	left=$(cd "$tmp" && ls -d kill.* 2>/dev/null || true)
	[ -z "$left" ] && ok "after_kill: no temporaries of the killed runs left" ||
		fail "after_kill: temporaries left: $left"
	consistent after_kill "$kill_dir"
fi

# A folder holding anything but a result is refused, and left as it was; so
# is a file in the folder's place.
mkdir "$tmp/home"
echo notes >"$tmp/home/notes.txt"
run home consolidate "$tmp/torus.ply" -o "$tmp/home" --samples 100 --quiet
one_error_line home 2 "$tmp/home" "notes.txt" "not a dpoints result"
[ "$(cat "$tmp/home/notes.txt" 2>/dev/null)" = notes ] || fail "home: notes.txt changed"
[ "$(ls "$tmp/home")" = notes.txt ] || fail "home: files written: $(ls "$tmp/home")"
touch "$tmp/afile"
run afile consolidate "$tmp/torus.ply" -o "$tmp/afile" --samples 100 --quiet
one_error_line afile 2 "$tmp/afile" "a file of that name exists"
# an empty folder is fine
mkdir "$tmp/empty"
expect_ok empty consolidate "$tmp/torus.ply" -o "$tmp/empty" --samples 200 --quiet && consistent empty "$tmp/empty"

finish
