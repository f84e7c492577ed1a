#!/usr/bin/env bash
# dpoints render as a new user meets it: a misspelt colour says so, --help
# lists the colour names (each of which works), the vertical axis comes from
# the data unless --up says, every view carries a caption (files, point
# counts, view), and a dpoints.ply alone shows both ends and the sticks.
source "$(dirname "$0")/support/cli_check.sh"

# pixels PNG R,G,B|grey [ROWS]: how many pixels have exactly that colour, or
# are grey (neither black nor white), in the bottom ROWS rows when given
pixels() {
	py '
import struct, sys, zlib
d = open(sys.argv[1], "rb").read()
grey = sys.argv[2] == "grey"
want = None if grey else tuple(int(v) for v in sys.argv[2].split(","))
rows = int(sys.argv[3]) if len(sys.argv) > 3 else 0
pos, idat = 8, b""
while pos < len(d):
    (ln,) = struct.unpack(">I", d[pos:pos + 4])
    typ, body = d[pos + 4:pos + 8], d[pos + 8:pos + 8 + ln]
    if typ == b"IHDR":
        w, h = struct.unpack(">II", body[:8])
    elif typ == b"IDAT":
        idat += body
    pos += 12 + ln
raw, stride, prev, count = zlib.decompress(idat), w * 3, bytearray(w * 3), 0
for y in range(h):
    ft, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
    for i in range(stride):
        a = line[i - 3] if i >= 3 else 0
        b, c = prev[i], prev[i - 3] if i >= 3 else 0
        if ft == 1: line[i] = (line[i] + a) & 255
        elif ft == 2: line[i] = (line[i] + b) & 255
        elif ft == 3: line[i] = (line[i] + (a + b) // 2) & 255
        elif ft == 4:
            p = a + b - c
            pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
            line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
    prev = line
    if rows and y < h - rows:
        continue
    px = [tuple(line[3 * x:3 * x + 3]) for x in range(w)]
    if grey:
        count += sum(1 for p in px if p[0] == p[1] == p[2] and 0 < p[0] < 255)
    else:
        count += sum(1 for p in px if p == want)
print(count)
' "$@"
}

expect_ok scan scan --shape sphere --res 24 --seed 1 -o "$tmp/s.ply" || finish

run misspelt render "$tmp/s.ply:purpl" -o "$tmp/m.png"
one_error_line misspelt 2 "'purpl' is not a colour" "purple" "#rrggbb"
[ ! -e "$tmp/m.png" ] || fail "misspelt colour: a PNG was written"

expect_ok help render --help
names=$(grep -o 'a name ([a-z, ]*)' "$tmp/help.out" | sed 's/a name (//; s/)//; s/,//g')
if [ "$(echo "$names" | wc -w)" -ge 10 ]; then
	bad=""
	for c in $names; do
		"$dpoints" render "$tmp/s.ply:$c" -o "$tmp/c.png" --size 48 --views 1 >/dev/null 2>&1 || bad="$bad $c"
	done
	[ -z "$bad" ] && ok "--help lists $(echo "$names" | wc -w) colour names, each accepted" ||
		fail "listed colours refused:$bad"
else
	fail "--help lists no colour names: $(cat "$tmp/help.out")"
fi

# up axis: a post tall in z is drawn upright without --up; --up wins
py '
import sys
with open(sys.argv[1], "w") as f:
    for i in range(400):
        f.write("%g %g %g\n" % (0.1 * ((i * 7) % 10) / 10, 0.1 * ((i * 3) % 10) / 10, 2.0 * i / 400))
' "$tmp/post.xyz"
expect_ok post render "$tmp/post.xyz" -o "$tmp/post.png" --size 64
grep -q "up z (from the data" "$tmp/post.out" && ok "z-tall data: up z from the data" ||
	fail "z-tall data: $(cat "$tmp/post.out")"
expect_ok posty render "$tmp/post.xyz" -o "$tmp/posty.png" --size 64 --up y
grep -q "up y ->" "$tmp/posty.out" && ok "--up y wins" || fail "--up y: $(cat "$tmp/posty.out")"
expect_ok sphere render "$tmp/s.ply" -o "$tmp/s.png" --size 128 --views 2
grep -q "up y (from the data" "$tmp/sphere.out" && ok "round data: up y" || fail "sphere: $(cat "$tmp/sphere.out")"

# captions in the bottom rows of every view, none with --no-caption
ink=$(pixels "$tmp/s.png" 60,60,60 16)
expect_ok nocap render "$tmp/s.ply" -o "$tmp/nocap.png" --size 128 --views 2 --no-caption
none=$(pixels "$tmp/nocap.png" 60,60,60 16)
[ "$ink" -gt 100 ] && [ "$none" -eq 0 ] && ok "caption: $ink caption pixels, none with --no-caption" ||
	fail "caption pixels: $ink with, $none without"
png_check "$tmp/s.png" 256 128 drawn && ok "captioned PNG is well formed"

# a dpoints.ply alone: grey sticks between two coloured ends
expect_ok cons consolidate "$tmp/s.ply" -o "$tmp/c" --samples 200 --quiet || finish
expect_ok dp render "$tmp/c/dpoints.ply" -o "$tmp/dp.png" --size 128 --views 1 --no-caption
sticks=$(pixels "$tmp/dp.png" grey)
[ "$sticks" -gt 50 ] && ok "dpoints.ply alone: $sticks stick pixels" || fail "dpoints.ply alone: $sticks stick pixels"
finish
