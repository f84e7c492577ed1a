#!/usr/bin/env bash
# Reading what people have and writing where they want: gzip-compressed
# inputs, standard input with --format, `wlop -o -`, XYZ columns detected or
# named (ambiguous ones refused naming --columns), Leica PTS, and colours and
# intensities carried through: a two-coloured scan keeps each half's colour in
# surface.ply, and wlop's output has the input's colours.
source "$(dirname "$0")/support/cli_check.sh"
opts=(--samples 300 --seed 5 --quiet)

expect_ok scan scan --shape sphere --res 32 --seed 2 -o "$tmp/s.ply" || finish
# the scan as XYZ (colours by side: red where x < 0, blue elsewhere), PTS
# (count line, intensity, colours) and a two-coloured ascii PLY
py "$PLY_PY"'
import sys
names, rows, _ = read_ply(sys.argv[1])
out = sys.argv[2]
def col(r):
    return (230, 20, 10) if r[0] < 0 else (10, 20, 230)
with open(out + "/s.xyz", "w") as f:
    for r in rows:
        f.write("%.9g %.9g %.9g\n" % r[:3])
with open(out + "/rgb.xyz", "w") as f:
    for r in rows:
        f.write("%.9g %.9g %.9g %d %d %d\n" % (r[:3] + col(r)))
with open(out + "/odd.xyz", "w") as f:
    for i, r in enumerate(rows):
        f.write("%.9g %.9g %.9g %d %d %d\n" % (r[:3] + (i % 7 - 3, 2, 9)))
with open(out + "/scan.pts", "w") as f:
    f.write("%d\n" % len(rows))
    for r in rows:
        f.write("%.6f %.6f %.6f %d %d %d %d\n" % (r[:3] + (-900 if r[0] < 0 else 500,) + col(r)))
with open(out + "/two.ply", "w") as f:
    f.write("ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\n"
            "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n" % len(rows))
    for r in rows:
        f.write("%.9g %.9g %.9g %d %d %d\n" % (r[:3] + col(r)))
' "$tmp/s.ply" "$tmp"

# gzip: the same result as the plain file
gzip -c "$tmp/s.ply" >"$tmp/gz.ply.gz"
gzip -c "$tmp/s.xyz" >"$tmp/s.xyz.gz"
cp "$tmp/s.ply" "$tmp/gz.ply"
expect_ok plain consolidate "$tmp/gz.ply" -o "$tmp/plain" "${opts[@]}"
expect_ok gz consolidate "$tmp/gz.ply.gz" -o "$tmp/gz" "${opts[@]}"
cmp -s "$tmp/plain/surface.ply" "$tmp/gz/surface.ply" && ok "consolidate .ply.gz: the same surface as .ply" ||
	fail ".ply.gz gave another surface"
expect_ok xyzgz wlop "$tmp/s.xyz.gz" -o "$tmp/xyzgz.ply" --samples 200 --quiet

# standard input needs --format; -o - writes the PLY to stdout
status=0
"$dpoints" wlop - --samples 200 -o "$tmp/x.ply" <"$tmp/s.xyz" >"$tmp/noformat.out" 2>"$tmp/noformat.err" || status=$?
one_error_line noformat 2 "standard input" "--format"
status=0
"$dpoints" wlop - --format xyz --samples 200 --seed 4 -o "$tmp/stdin.ply" --quiet <"$tmp/s.xyz.gz" \
	>"$tmp/stdin.out" 2>"$tmp/stdin.err" || status=$?
[ "$status" -eq 0 ] && ok "wlop - --format xyz (gzip on stdin)" || fail "stdin: status $status: $(cat "$tmp/stdin.err")"
expect_ok tofile wlop "$tmp/s.ply" --samples 200 --seed 4 -o "$tmp/file.ply" --quiet
abs=$(cd "$(dirname "$dpoints")" && pwd)/$(basename "$dpoints")
(cd "$tmp" && "$abs" wlop s.ply --samples 200 --seed 4 -o - --quiet >"$tmp/stdout.ply" 2>"$tmp/stdout.err") &&
	cmp -s "$tmp/file.ply" "$tmp/stdout.ply" && [ ! -e "$tmp/-" ] &&
	grep -q "^wlop: " "$tmp/stdout.err" && ok "wlop -o -: the PLY on stdout, the summary line on stderr" ||
	fail "wlop -o -: $(head -c 200 "$tmp/stdout.err")"
status=0
"$dpoints" wlop "$tmp/missing.ply" -o - >"$tmp/stdoutbad.out" 2>"$tmp/stdoutbad.err" || status=$?
if [ -s "$tmp/stdoutbad.out" ]; then fail "stdoutbad: wrote to stdout"; else one_error_line stdoutbad 2 "missing.ply"; fi
# the other one-file outputs take - too; never two of one run
(cd "$tmp" && "$abs" wlop s.ply --samples 200 --seed 4 -o rep.ply --report - --quiet >"$tmp/report.out" \
	2>"$tmp/report.err") && [ ! -e "$tmp/-" ] && grep -q '"command": "wlop"' "$tmp/report.out" &&
	grep -q "^wlop: " "$tmp/report.err" && ok "wlop --report -: the JSON on stdout, the summary line on stderr" ||
	fail "wlop --report -: $(head -c 200 "$tmp/report.err")"
run twostdout wlop "$tmp/s.ply" -o - --report -
if [ -s "$tmp/twostdout.out" ]; then fail "twostdout: wrote to stdout"; else one_error_line twostdout 2 "only one output"; fi
expect_ok scanfile scan --shape sphere --res 24 -o "$tmp/scan.ply" --mesh-out "$tmp/mesh.ply"
(cd "$tmp" && "$abs" scan --shape sphere --res 24 -o - >"$tmp/scan_stdout.ply" 2>"$tmp/scan_stdout.err" &&
	"$abs" scan --shape sphere --res 24 -o scan2.ply --mesh-out - >"$tmp/mesh_stdout.ply" 2>/dev/null) &&
	cmp -s "$tmp/scan.ply" "$tmp/scan_stdout.ply" && cmp -s "$tmp/mesh.ply" "$tmp/mesh_stdout.ply" &&
	cmp -s "$tmp/scan.ply" "$tmp/scan2.ply" && [ ! -e "$tmp/-" ] && grep -q "^scan: " "$tmp/scan_stdout.err" &&
	ok "scan -o - and --mesh-out -: the same files on stdout" || fail "scan to stdout: $(head -c 200 "$tmp/scan_stdout.err")"
run scantwo scan --shape sphere -o - --mesh-out -
if [ -s "$tmp/scantwo.out" ]; then fail "scantwo: wrote to stdout"; else one_error_line scantwo 2 "only one output"; fi
expect_ok renderfile render "$tmp/scan.ply" -o "$tmp/pic.png" --size 64
(cd "$tmp" && "$abs" render scan.ply -o - --size 64 >"$tmp/pic_stdout.png" 2>/dev/null) &&
	cmp -s "$tmp/pic.png" "$tmp/pic_stdout.png" && [ ! -e "$tmp/-" ] && ok "render -o -: the PNG on stdout" ||
	fail "render -o - gave another picture"
run renderbad render "$tmp/missing.ply" -o -
run folderstdout consolidate "$tmp/s.ply" -o -
one_error_line folderstdout 2 "folder of files"
[ -e "$tmp/-" ] || [ -e ./- ] && fail "consolidate -o -: made a folder named -"
if [ -s "$tmp/renderbad.out" ]; then fail "renderbad: wrote to stdout"; else one_error_line renderbad 2 "missing.ply"; fi

# XYZ columns
run odd wlop "$tmp/odd.xyz" -o "$tmp/odd.ply" --samples 200
one_error_line odd 2 "odd.xyz" "--columns"
expect_ok oddnamed wlop "$tmp/odd.xyz" -o "$tmp/odd.ply" --samples 200 --quiet --columns x,y,z,_,_,_ &&
	ok "--columns x,y,z,_,_,_ reads it"
run badcols wlop "$tmp/odd.xyz" -o "$tmp/odd.ply" --columns x,y,w
one_error_line badcols 2 "unknown column 'w'"

# colours: XYZ, PTS and PLY inputs; wlop and consolidate outputs
# side_colours FILE: every point off the x = 0 plane by a margin has its side's colour
side_colours() {
	py "$PLY_PY"'
import sys
names, rows, _ = read_ply(sys.argv[1])
if "red" not in names:
    sys.exit("no red property in %s: %s" % (sys.argv[1], names))
x, r, g, b = (names.index(k) for k in ("x", "red", "green", "blue"))
wrong = [row for row in rows if abs(row[x]) > 0.15 and (row[r], row[g], row[b]) != ((230, 20, 10) if row[x] < 0 else (10, 20, 230))]
seen = {(row[r], row[g], row[b]) for row in rows}
if wrong or seen != {(230, 20, 10), (10, 20, 230)}:
    sys.exit("%d of %d points with the other side'"'"'s colour; colours %s" % (len(wrong), len(rows), seen))
' "$1"
}
for input in rgb.xyz scan.pts two.ply; do
	expect_ok "wlop_$input" wlop "$tmp/$input" -o "$tmp/w_$input.ply" --samples 300 --quiet &&
		msg=$(side_colours "$tmp/w_$input.ply" 2>&1) && ok "wlop $input: colours carried" ||
		fail "wlop $input: ${msg:-}"
done
expect_ok two consolidate "$tmp/two.ply" -o "$tmp/two" --samples 400 --quiet --save-stages &&
	msg=$(side_colours "$tmp/two/surface.ply" 2>&1) && ok "two-coloured input: each half keeps its colour in surface.ply" ||
	fail "surface.ply colours: ${msg:-}"
msg=$(side_colours "$tmp/two/wlop.ply" 2>&1) && ok "--save-stages wlop.ply has the colours" || fail "wlop.ply: $msg"
py "$PLY_PY"'
import sys
names, _, _ = read_ply(sys.argv[1])
sys.exit(0 if "red" not in names and "intensity" not in names else "colours without coloured input")
' "$tmp/plain/surface.ply" && ok "no colours in, no colours out" || fail "plain input got colours"

# intensity: PTS -> wlop output and surface.ply, by side
side_intensity() {
	py "$PLY_PY"'
import sys
names, rows, _ = read_ply(sys.argv[1])
if "intensity" not in names:
    sys.exit("no intensity in %s: %s" % (sys.argv[1], names))
x, i = names.index("x"), names.index("intensity")
wrong = [r for r in rows if abs(r[x]) > 0.15 and r[i] != (-900 if r[x] < 0 else 500)]
sys.exit("%d of %d points with the other side'"'"'s intensity" % (len(wrong), len(rows)) if wrong else 0)
' "$1"
}
msg=$(side_intensity "$tmp/w_scan.pts.ply" 2>&1) && ok "wlop scan.pts: intensity carried" || fail "wlop intensity: $msg"
expect_ok pts consolidate "$tmp/scan.pts" -o "$tmp/pts" --samples 400 --quiet &&
	msg=$(side_intensity "$tmp/pts/surface.ply" 2>&1) && ok "PTS: surface.ply has the intensity of each side" ||
	fail "surface.ply intensity: ${msg:-}"
finish
