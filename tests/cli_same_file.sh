#!/usr/bin/env bash
# Issue 9, defect 3: an output that is an input file (by device and inode,
# whatever the spelling of the path) is refused with exit 2 before anything
# runs, and the input stays as it was.
source "$(dirname "$0")/support/cli_check.sh"

mkdir -p "$tmp/d/out/in"
py '
import math, sys
with open(sys.argv[1], "w") as f:
    for i in range(300):
        t, p = math.acos(1 - 2 * (i + 0.5) / 300), math.pi * (1 + 5 ** 0.5) * i
        f.write("%.6f %.6f %.6f\n" % (math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)))
' "$tmp/d/in.xyz"
cp "$tmp/d/in.xyz" "$tmp/d/out/surface.ply"
cp "$tmp/d/in.xyz" "$tmp/d/out/in/report.json"
ln "$tmp/d/in.xyz" "$tmp/d/hard.ply"
ln -s in.xyz "$tmp/d/soft.ply"
sum=$(cksum <"$tmp/d/in.xyz")

# refused NAME NEEDLE ARGS...: exit 2 with one error line naming NEEDLE, and
# neither the input nor its copies changed.
refused() {
	local name=$1 needle=$2
	shift 2
	run "$name" "$@"
	one_error_line "$name" 2 "$needle" "is the input file"
	for f in in.xyz out/surface.ply out/in/report.json; do
		if [ "$(cksum <"$tmp/d/$f")" != "$sum" ]; then
			fail "$name: $f was changed"
		fi
	done
}

cd "$tmp/d"
refused wlop_same in.xyz wlop in.xyz -o in.xyz --samples 30
refused wlop_dot ./in.xyz wlop in.xyz -o ./in.xyz --samples 30
refused wlop_path ../d/in.xyz wlop in.xyz -o "$tmp/d/../d/in.xyz" --samples 30
refused wlop_hard hard.ply wlop in.xyz -o hard.ply --samples 30
refused wlop_soft soft.ply wlop in.xyz -o soft.ply --samples 30
refused wlop_report in.xyz wlop in.xyz -o "$tmp/w.ply" --report in.xyz --samples 30
if [ -e "$tmp/w.ply" ]; then fail "wlop_report: wrote its PLY although the report would replace the input"; fi
refused consolidate_one out/surface.ply consolidate out/surface.ply -o out --samples 30 --quiet
# in a batch, the second input lies in the folder the first one writes
refused consolidate_batch out/in/report.json consolidate in.xyz out/in/report.json -o out --samples 30 --quiet
refused scan_mesh in.xyz scan in.xyz -o in.xyz --views 1 --res 8
refused scan_mesh_out in.xyz scan in.xyz -o "$tmp/s.ply" --mesh-out in.xyz --views 1 --res 8

# an output beside the input, with a similar name, is fine
expect_ok wlop_beside wlop in.xyz -o in.xyz.ply --samples 30 && ok "wlop_beside: written"

# Two outputs of one run that are one file, existing or not, however spelled:
# refused with exit 2 before anything is written.
two_outputs() {
	local name=$1 needle=$2
	shift 2
	run "$name" "$@"
	one_error_line "$name" 2 "$needle" "two outputs would be the one file"
	for f in "$tmp/d/two.ply" "$tmp/d/old.ply"; do
		if [ -e "$f" ] && [ "$(cksum <"$f")" != "$sum" ]; then
			fail "$name: $f was written"
		fi
	done
}
rm -f two.ply
two_outputs scan_two two.ply scan --shape sphere --views 1 --res 8 -o two.ply --mesh-out two.ply
two_outputs scan_two_dot two.ply scan --shape sphere --views 1 --res 8 -o two.ply --mesh-out ./two.ply
if [ -e two.ply ]; then fail "scan_two: wrote two.ply"; fi
cp in.xyz old.ply
two_outputs scan_two_old old.ply scan --shape sphere --views 1 --res 8 -o old.ply --mesh-out "$tmp/d/../d/old.ply"
two_outputs wlop_two old.ply wlop in.xyz -o old.ply --report ./old.ply --samples 30
# a mesh beside its scan is fine, and leaves no temporary file
expect_ok scan_both scan --shape sphere --views 1 --res 8 -o two.ply --mesh-out mesh.ply &&
	[ -s two.ply ] && [ -s mesh.ply ] && ok "scan_both: scan and mesh written"
# a scan that cannot be written (its name is a folder) leaves no mesh behind
mkdir -p folder.ply
run scan_fails scan --shape sphere --views 1 --res 8 -o folder.ply --mesh-out lone.ply
one_error_line scan_fails 2 "folder.ply"
if [ -e lone.ply ]; then fail "scan_fails: wrote the mesh lone.ply although the scan failed"; fi
leftover=$(find . -name '*.tmp.*')
[ -z "$leftover" ] || fail "temporary files left: $leftover"
finish
