#!/usr/bin/env bash
# Batches at scale: one collection of five small scans consolidated as one
# batch (--inputs), as three shards run side by side by GNU parallel, over two
# workers (--device 0,0: PoCL has one device here, so two contexts on it), and
# resumed with --skip-done after one result was deleted: every way gives the
# same per-input files. Then `summary` over the folder, --json, failure
# records, and the shard arithmetic from the Slurm variables.
source "$(dirname "$0")/support/cli_check.sh"
unset SLURM_ARRAY_TASK_ID SLURM_ARRAY_TASK_COUNT SLURM_ARRAY_TASK_MIN SLURM_ARRAY_TASK_STEP DPOINTS_DEVICE

mkdir "$tmp/scans"
names=(sphere torus cylinder knot torus2)
for s in sphere torus cylinder knot; do
	expect_ok "scan_$s" scan --shape "$s" --res 32 --seed 3 -o "$tmp/scans/$s.ply" || finish
done
expect_ok scan_torus2 scan --shape torus --views 2 --res 32 --seed 4 -o "$tmp/scans/torus2.ply" || finish
{
	echo "# five scans"
	for n in "${names[@]}"; do echo "$tmp/scans/$n.ply"; done
	echo
} >"$tmp/list.txt"
opts=(--samples 300 --seed 7 --quiet)

# same_results A B: every input's PLY files in folders A and B are identical
same_results() {
	local a=$1 b=$2 what=$3 n f bad=0
	for n in "${names[@]}"; do
		for f in surface.ply skeleton.ply dpoints.ply; do
			if ! cmp -s "$a/$n/$f" "$b/$n/$f"; then
				fail "$what: $n/$f differs from the single batch"
				bad=1
			fi
		done
	done
	[ "$bad" -eq 0 ] && ok "$what: the same ${#names[@]} x 3 files as the single batch"
}

expect_ok single consolidate --inputs "$tmp/list.txt" -o "$tmp/single" "${opts[@]}" || finish
for n in "${names[@]}"; do
	[ -s "$tmp/single/$n/report.json" ] || fail "single: $n/report.json missing"
done
grep -q '^5 inputs: 5 ok, 0 failed' "$tmp/single.out" && ok "single batch: 5 ok" ||
	fail "single batch: no '5 inputs: 5 ok' line: $(cat "$tmp/single.out")"

if command -v parallel >/dev/null; then
	status=0
	parallel --will-cite -j3 --halt now,fail=1 "$dpoints" consolidate --inputs "$tmp/list.txt" -o "$tmp/sharded" \
		"${opts[@]}" --shard {}/3 ::: 0 1 2 >"$tmp/parallel.out" 2>"$tmp/parallel.err" || status=$?
	if [ "$status" -ne 0 ]; then
		fail "three shards under GNU parallel: exit status $status: $(tail -n 3 "$tmp/parallel.err")"
	else
		same_results "$tmp/single" "$tmp/sharded" "three shards under GNU parallel"
	fi
else
	skip "three shards under GNU parallel: 'parallel' is not installed (Debian package parallel)"
fi

expect_ok workers consolidate --inputs "$tmp/list.txt" -o "$tmp/workers" "${opts[@]}" --device 0,0 &&
	same_results "$tmp/single" "$tmp/workers" "two workers (--device 0,0)"
if msg=$(py '
import sys
rows = [l.split() for l in open(sys.argv[1]) if l.split()[-1:] == ["ok"]]
if len(rows) != 5 or any(r[-2] != "0" for r in rows):
    sys.exit("expected 5 ok rows with device 0: %r" % rows)
' "$tmp/workers.out" 2>&1); then ok "two workers: the table names the device of every input"; else fail "two workers: $msg"; fi

# --device all: every device dp_devices lists (here PoCL's one), by index
expect_ok all consolidate "$tmp/scans/sphere.ply" "$tmp/scans/knot.ply" -o "$tmp/all" "${opts[@]}" --device all &&
	cmp -s "$tmp/all/knot/surface.ply" "$tmp/single/knot/surface.ply" &&
	[ "$(grep -c ' 0  *ok$' "$tmp/all.out")" -eq 2 ] && ok "--device all: both inputs on device 0, same files" ||
	fail "--device all: $(cat "$tmp/all.out")"
run baddev consolidate "$tmp/scans/sphere.ply" -o "$tmp/baddev" "${opts[@]}" --device 0,
one_error_line baddev 2 "--device" "empty"

# resume: one result deleted, the rest are done and left alone
cp -a "$tmp/single" "$tmp/resumed"
rm -r "$tmp/resumed/cylinder"
before=$(stat -c %Y:%i "$tmp/resumed/knot/report.json")
expect_ok resumed consolidate --inputs "$tmp/list.txt" -o "$tmp/resumed" "${opts[@]}" --skip-done &&
	same_results "$tmp/single" "$tmp/resumed" "--skip-done after deleting one result"
grep -q '^5 inputs: 1 ok, 0 failed, 4 skipped' "$tmp/resumed.out" && ok "--skip-done ran only the missing input" ||
	fail "--skip-done: expected 1 run and 4 skipped: $(cat "$tmp/resumed.out")"
[ "$(stat -c %Y:%i "$tmp/resumed/knot/report.json")" = "$before" ] || fail "--skip-done rewrote a finished result"
# a folder missing a file its report lists is not done
rm "$tmp/resumed/torus/skeleton.ply"
expect_ok resumed2 consolidate --inputs "$tmp/list.txt" -o "$tmp/resumed" "${opts[@]}" --skip-done &&
	grep -q '1 ok, 0 failed, 4 skipped' "$tmp/resumed2.out" && cmp -s "$tmp/single/torus/skeleton.ply" \
	"$tmp/resumed/torus/skeleton.ply" && ok "--skip-done redoes a folder missing a listed file" ||
	fail "--skip-done with a missing skeleton.ply: $(cat "$tmp/resumed2.out")"

# summary: one table, JSON lines; a failure record beside the results
expect_ok summary summary "$tmp/single"
if msg=$(py '
import sys
lines = open(sys.argv[1]).read().splitlines()
if lines[0].split()[:3] != ["input", "points", "dpoints"] or len(lines) != 7:
    sys.exit("expected a header, 5 rows and a total: %r" % lines)
if not lines[-1].startswith("5 inputs: 5 ok, 0 failed"):
    sys.exit("no totals line: %r" % lines[-1])
' "$tmp/summary.out" 2>&1); then ok "summary: a table of 5 results"; else fail "summary: $msg"; fi
printf '0 0 0\n1 0 0\n0 1 0\n0 0 nan\n' >"$tmp/bad.xyz"
run withbad consolidate "$tmp/scans/sphere.ply" "$tmp/bad.xyz" -o "$tmp/withbad" "${opts[@]}"
[ "$status" -eq 2 ] && [ -s "$tmp/withbad/bad.failed.json" ] && [ ! -e "$tmp/withbad/bad" ] &&
	ok "a failed input leaves bad.failed.json, no folder" || fail "failure record: status $status, $(ls "$tmp/withbad")"
run sumbad summary "$tmp/withbad" --json
if [ "$status" -eq 1 ] && msg=$(py '
import json, sys
rows = [json.loads(l) for l in open(sys.argv[1])]
st = {r["input"].split("/")[-1]: r for r in rows}
if set(st) != {"sphere.ply", "bad.xyz"}:
    sys.exit("rows %r" % list(st))
b, s = st["bad.xyz"], st["sphere.ply"]
if b["status"] != "failed" or "non-finite" not in b["error"]:
    sys.exit("bad row %r" % b)
if s["status"] != "ok" or s["error"] is not None or s["deep_points"] != 300 or s["points"] <= 0:
    sys.exit("ok row %r" % s)
run = json.load(open(sys.argv[2] + "/sphere/report.json"))["results"]["deep_points_run"]
if s["deep_points_run"] != run or run < 300:
    sys.exit("deep_points_run %r, the report has %r" % (s["deep_points_run"], run))
for k in ("wlop", "normals", "sink", "skeleton", "surface", "total"):
    if not s["seconds"][k] >= 0:
        sys.exit("seconds %r" % s["seconds"])
if set(s["stop"]) != {"wlop", "sink", "skeleton", "surface"} or not set(s["stop"].values()) <= {"converged", "stalled", "settled", "cap"}:
    sys.exit("stop %r" % s["stop"])
' "$tmp/sumbad.out" "$tmp/withbad" 2>&1); then ok "summary --json: a failed and an ok row, exit 1"; else fail "summary --json: status $status: ${msg:-}"; fi
# a report written before deep_points_run existed: the count kept was the count run;
# before the sinking's converged: it stopped at its cap when anchors are unsettled
mkdir "$tmp/old" && cp -a "$tmp/single/sphere" "$tmp/old/" && py '
import json, sys
r = json.load(open(sys.argv[1]))
if r["results"]["sink"]["converged"] is not True:
    sys.exit("sink: %r" % r["results"]["sink"])
del r["results"]["deep_points_run"]
del r["results"]["sink"]["converged"]
r["results"]["sink"]["unsettled"] = 3
json.dump(r, open(sys.argv[1], "w"))
' "$tmp/old/sphere/report.json" || fail "report.json of the sphere: no sink.converged"
expect_ok sumold summary "$tmp/old" --json
if msg=$(py '
import json, sys
s = json.loads(open(sys.argv[1]).read())
if s["deep_points_run"] != s["deep_points"] or s["deep_points"] != 300 or s["stop"]["sink"] != "cap":
    sys.exit("%r" % s)
' "$tmp/sumold.out" 2>&1); then ok "summary --json of an older report: run = kept, sink capped by its unsettled anchors"; else fail "summary of an older report: $msg"; fi
# a later success clears the record
expect_ok fixed consolidate "$tmp/scans/sphere.ply" "$tmp/scans/torus.ply" -o "$tmp/withbad" "${opts[@]}" &&
	[ -e "$tmp/withbad/bad.failed.json" ] && ok "a record of another input stays" || fail "record vanished"
run sumnone summary "$tmp/nothing-here"
one_error_line sumnone 2 "nothing-here"

# consolidate --json: stdout is one JSON object
expect_ok json1 consolidate "$tmp/scans/knot.ply" -o "$tmp/json1" "${opts[@]}" --json
if msg=$(py '
import json, sys
d = json.load(open(sys.argv[1]))
if d["status"] != "ok" or d["results"]["deep_points"] != 300 or "seconds" not in d or "stop" not in d:
    sys.exit("%r" % d)
' "$tmp/json1.out" 2>&1); then ok "consolidate --json: one object with the results"; else fail "consolidate --json: $msg"; fi
expect_ok jsonb consolidate --inputs "$tmp/list.txt" -o "$tmp/resumed" "${opts[@]}" --json --skip-done
if msg=$(py '
import json, sys
d = json.load(open(sys.argv[1]))
if [r["status"] for r in d["inputs"]] != ["skipped"] * 5 or d["skipped"] != 5 or d["shard"] != "0/1":
    sys.exit("%r" % d)
if d["inputs"][0]["results"]["deep_points"] != 300:
    sys.exit("skipped rows lack their results")
' "$tmp/jsonb.out" 2>&1); then ok "consolidate --json (batch, all done): one object"; else fail "batch --json: $msg"; fi

# Shard arithmetic: missing inputs fail at once, and the JSON says which ran.
printf '%s\n' a b c d e f g | sed "s|^|$tmp/none/|; s|$|.xyz|" >"$tmp/seven.txt"
# shard_of NAME WANT ENV... : the inputs the shard ran, by name
shard_of() {
	local name=$1 want=$2 got
	shift 2
	status=0
	env "$@" "$dpoints" consolidate --inputs "$tmp/seven.txt" -o "$tmp/shards" --json --quiet \
		>"$tmp/$name.out" 2>"$tmp/$name.err" || status=$?
	got=$(py '
import json, sys
print(" ".join(r["input"].split("/")[-1][0] for r in json.load(open(sys.argv[1]))["inputs"]))
' "$tmp/$name.out" 2>&1) || true
	[ "$got" = "$want" ] && ok "$name: inputs $got" || fail "$name: inputs '$got', expected '$want' (status $status)"
}
shard_of slurm_2of3 "c f" SLURM_ARRAY_TASK_ID=2 SLURM_ARRAY_TASK_COUNT=3
shard_of slurm_0of3 "a d g" SLURM_ARRAY_TASK_ID=0 SLURM_ARRAY_TASK_COUNT=3
shard_of slurm_min1 "b e" SLURM_ARRAY_TASK_ID=2 SLURM_ARRAY_TASK_COUNT=3 SLURM_ARRAY_TASK_MIN=1
shard_of slurm_step "g" SLURM_ARRAY_TASK_ID=12 SLURM_ARRAY_TASK_COUNT=7 SLURM_ARRAY_TASK_MIN=0 SLURM_ARRAY_TASK_STEP=2
sed -i 's/^/#/' "$tmp/seven.txt" # a list of comments only
# --shard wins over the Slurm variables
SLURM_ARRAY_TASK_ID=0 SLURM_ARRAY_TASK_COUNT=3 run shard_flag_over consolidate --inputs "$tmp/list.txt" --shard 0/4 -o "$tmp/shards1" --json --quiet --samples 300
py 'import json, sys; d = json.load(open(sys.argv[1])); sys.exit([r["input"].split("/")[-1] for r in d["inputs"]] != ["sphere.ply", "torus2.ply"])' \
	"$tmp/shard_flag_over.out" && ok "--shard 0/4 of five: sphere, torus2" || fail "--shard 0/4: $(cat "$tmp/shard_flag_over.out")"
run empty_list consolidate --inputs "$tmp/seven.txt" -o "$tmp/x"
one_error_line empty_list 2 "seven.txt" "no input paths"
run bad_shard consolidate --inputs "$tmp/list.txt" --shard 3/3 -o "$tmp/x"
one_error_line bad_shard 2 "--shard" "3/3"
status=0
SLURM_ARRAY_TASK_ID=3 SLURM_ARRAY_TASK_COUNT=3 "$dpoints" consolidate --inputs "$tmp/list.txt" -o "$tmp/x" \
	>"$tmp/bad_slurm.out" 2>"$tmp/bad_slurm.err" || status=$?
one_error_line bad_slurm 2 "SLURM_ARRAY_TASK_ID=3" "--shard"
run no_list consolidate --inputs "$tmp/missing.txt" -o "$tmp/x"
one_error_line no_list 2 "missing.txt" "cannot open"
[ ! -e "$tmp/x" ] || fail "a refused run left its output folder"
# a shard whose inputs all failed keeps their records for `summary`
[ -s "$tmp/shards/c.failed.json" ] && [ -s "$tmp/shards/g.failed.json" ] && ok "failed shards leave their records" ||
	fail "failed shards: $(ls "$tmp/shards" 2>&1)"
run sumshards summary "$tmp/shards"
[ "$status" -eq 1 ] && grep -q "FAILED: .*none/c.xyz" "$tmp/sumshards.out" && ok "summary lists the shards' failures" ||
	fail "summary of failed shards: status $status $(cat "$tmp/sumshards.out")"
finish
