#!/usr/bin/env bash
# Progress lines of consolidate: "iteration k/cap" for every stage and one
# line when a stage ends with its reason (converged, all settled, the cap;
# refined levels run a fixed count), the coarser levels a one-sided scan
# tries as "coarser k"; --quiet silences them.
source "$(dirname "$0")/support/cli_check.sh"

expect_ok scan scan --shape sphere --res 32 --seed 3 -o "$tmp/s.ply" || finish
expect_ok run consolidate "$tmp/s.ply" -o "$tmp/out" --samples 1200 --coarse-samples 500 --wlop-iters 5 || finish
err="$tmp/run.err"
check() {
	if grep -qE -- "$2" "$err"; then ok "$1"; else fail "$1: no line matching '$2' in: $(cat "$err")"; fi
}
check "wlop iteration k/cap" 'wlop +iteration +1/5,'
check "wlop ends at its cap" 'wlop +ended after 5/5 iterations: stopped at the iteration cap'
check "sink iteration k/cap" 'sink +iteration +1/200,'
check "sink ends settled" 'sink +ended after [0-9]+/200 iterations: all settled'
check "skeleton ends converged" 'skeleton +ended after [0-9]+/100 iterations: converged'
check "surface ends" 'surface +ended after [0-9]+/200 iterations: '
check "a refined level" 'level 1 +ended after 15/15 iterations: fixed iteration count'
# a one-sided scan tries coarser coarse levels: WLOP runs of their own name
expect_ok scan1 scan --shape sphere --views 1 --res 64 --seed 3 -o "$tmp/s1.ply" || finish
expect_ok run consolidate "$tmp/s1.ply" -o "$tmp/out1" --samples 1000 --coarse-samples 1000 --coarse-min 250 || finish
check "the first coarser level tried" 'coarser 1 +ended after [0-9]+/200 iterations: '
check "the second coarser level tried" 'coarser 2 +ended after [0-9]+/200 iterations: '
# runs of one name that each end at their first iteration are still two runs
expect_ok run consolidate "$tmp/s1.ply" -o "$tmp/out2" --samples 1000 --coarse-samples 1000 --coarse-min 250 \
	--wlop-iters 1 || finish
check "coarser levels of one iteration each" 'coarser 2 +ended after 1/1 iterations: stopped at the iteration cap'
expect_ok quiet consolidate "$tmp/s.ply" -o "$tmp/q" --samples 300 --quiet
# the cap warning is no progress line and stays under --quiet
grep -qE "iteration +[0-9]+/|ended after" "$tmp/quiet.err" && fail "--quiet printed progress: $(cat "$tmp/quiet.err")" || ok "--quiet: no progress"
finish
