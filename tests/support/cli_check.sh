# shellcheck shell=bash
# Sourced by tests/cli_*.sh: the dpoints binary from $1, a scratch folder
# removed on exit, failure counting, and checks of the files the CLI writes.
# Checks report every failure and the script exits 1 at `finish`, so one run
# shows all that is wrong.
set -euo pipefail
dpoints=${1:?usage: $0 PATH_TO_DPOINTS}
if ! command -v python3 >/dev/null; then
	echo "FAIL python3 is needed to check PLY, PNG and JSON outputs"
	exit 1
fi
tmp=$(mktemp -d /tmp/dpoints-cli-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
failures=0
skips=0

# skip WHAT: a part that cannot run here (missing data); the script then exits
# 77, which ctest (SKIP_RETURN_CODE) lists as skipped rather than passed.
skip() {
	echo "SKIP $*"
	skips=$((skips + 1))
}

fail() {
	echo "FAIL $*"
	failures=$((failures + 1))
}

ok() {
	echo "ok   $*"
}

finish() {
	if [ "$failures" -ne 0 ]; then
		echo "$failures check(s) failed"
		exit 1
	fi
	if [ "$skips" -ne 0 ]; then
		echo "$skips part(s) skipped"
		exit 77
	fi
}

# run NAME ARGS...: runs dpoints ARGS with stdout in $tmp/NAME.out, stderr in
# $tmp/NAME.err and the exit status in $status.
run() {
	local name=$1
	shift
	status=0
	"$dpoints" "$@" >"$tmp/$name.out" 2>"$tmp/$name.err" || status=$?
}

# expect_ok NAME ARGS...: run, and fail (showing stderr) unless it exits 0.
expect_ok() {
	local name=$1
	run "$@"
	if [ "$status" -ne 0 ]; then
		fail "$name: exit status $status: $(tail -n 3 "$tmp/$name.err")"
		return 1
	fi
	return 0
}

# one_error_line NAME STATUS NEEDLE...: the run NAME exited with STATUS and
# wrote exactly one line on stderr containing every NEEDLE.
one_error_line() {
	local name=$1 want=$2 lines
	shift 2
	lines=$(wc -l <"$tmp/$name.err")
	if [ "$status" -ne "$want" ]; then
		fail "$name: exit status $status, expected $want: $(head -n 3 "$tmp/$name.err")"
		return
	fi
	if [ "$lines" -ne 1 ]; then
		fail "$name: $lines lines on stderr, expected 1:"
		cat "$tmp/$name.err"
		return
	fi
	for needle in "$@"; do
		if ! grep -qF -- "$needle" "$tmp/$name.err"; then
			fail "$name: stderr lacks '$needle': $(cat "$tmp/$name.err")"
			return
		fi
	done
	ok "$name: $(cat "$tmp/$name.err")"
}

# py SCRIPT ARGS...: runs a python3 check; its stdout is the failure message.
py() {
	local script=$1
	shift
	python3 -c "$script" "$@"
}

# The PLY reader of the checks: binary little endian or ascii, float / double
# / int vertex properties; returns (property names, rows, element counts).
PLY_PY='
import struct, sys
def read_ply(path):
    f = open(path, "rb")
    if f.readline().strip() != b"ply":
        raise SystemExit(path + ": not a PLY file")
    fmt, elements, props, cur = None, [], [], None
    while True:
        t = f.readline().decode().split()
        if not t:
            continue
        if t[0] == "end_header":
            break
        if t[0] == "format":
            fmt = t[1]
        elif t[0] == "element":
            elements.append((t[1], int(t[2])))
            cur = t[1]
        elif t[0] == "property" and cur == "vertex":
            props.append((t[-1], t[1]))
    if elements[0][0] != "vertex":
        raise SystemExit(path + ": first element is not vertex")
    n = elements[0][1]
    codes = {"float": "f", "float32": "f", "double": "d", "int": "i", "int32": "i", "uchar": "B", "uint8": "B"}
    if fmt == "ascii":
        rows = [tuple(float(v) for v in f.readline().split()[:len(props)]) for _ in range(n)]
    else:
        rec = "<" + "".join(codes[p[1]] for p in props)
        size = struct.calcsize(rec)
        data = f.read(size * n)
        if len(data) != size * n:
            raise SystemExit(path + ": truncated")
        rows = list(struct.iter_unpack(rec, data))
    return [p[0] for p in props], rows, dict(elements)
'

# png_check PATH [WIDTH HEIGHT [drawn]]: a well-formed 8-bit PNG (signature,
# every chunk CRC, IHDR, IDAT inflating to exactly the image size; 0 = any
# size); with "drawn", also something drawn on it: at least 0.5% of the pixels
# differ from the corner pixel, their number left in $png_drawn (the
# pure-Python decoding takes about a second per megapixel, so only where it
# matters).
png_check() {
	local path=$1 w=${2:-0} h=${3:-0} drawn=${4:-} msg
	if ! msg=$(py '
import struct, sys, zlib
path, want_w, want_h, drawn = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4] == "drawn"
d = open(path, "rb").read()
if d[:8] != b"\x89PNG\r\n\x1a\n":
    sys.exit("no PNG signature")
pos, idat, ihdr, end = 8, b"", None, False
while pos + 12 <= len(d):
    (ln,) = struct.unpack(">I", d[pos:pos + 4])
    typ, body = d[pos + 4:pos + 8], d[pos + 8:pos + 8 + ln]
    (crc,) = struct.unpack(">I", d[pos + 8 + ln:pos + 12 + ln])
    if zlib.crc32(typ + body) & 0xFFFFFFFF != crc:
        sys.exit("bad CRC in chunk %r" % typ)
    if typ == b"IHDR":
        ihdr = struct.unpack(">IIBBBBB", body)
    elif typ == b"IDAT":
        idat += body
    pos += 12 + ln
    if typ == b"IEND":
        end = True
        break
if not ihdr or not end:
    sys.exit("missing IHDR or IEND")
w, h, depth, ctype, _, _, interlace = ihdr
bpp = {0: 1, 2: 3, 4: 2, 6: 4}.get(ctype)
if depth != 8 or bpp is None or interlace:
    sys.exit("unexpected format depth %d colour type %d" % (depth, ctype))
if (want_w and w != want_w) or (want_h and h != want_h):
    sys.exit("size %dx%d, expected %dx%d" % (w, h, want_w, want_h))
raw = zlib.decompress(idat)
stride = w * bpp
if len(raw) != h * (stride + 1):
    sys.exit("image data is %d bytes, expected %d" % (len(raw), h * (stride + 1)))
if not drawn:
    sys.exit(0)
prev, pix = bytearray(stride), bytearray()
for y in range(h):
    ft, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
    for i in range(stride):
        a = line[i - bpp] if i >= bpp else 0
        b, c = prev[i], prev[i - bpp] if i >= bpp else 0
        if ft == 1: line[i] = (line[i] + a) & 255
        elif ft == 2: line[i] = (line[i] + b) & 255
        elif ft == 3: line[i] = (line[i] + (a + b) // 2) & 255
        elif ft == 4:
            p = a + b - c
            pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
            line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        elif ft != 0:
            sys.exit("bad filter type %d" % ft)
    pix += line
    prev = line
bg = pix[:bpp]
count = sum(1 for k in range(0, len(pix), bpp) if pix[k:k + bpp] != bg)
if count < 0.005 * w * h:
    sys.exit("almost blank: %d of %d pixels drawn" % (count, w * h))
print(count)
' "$path" "$w" "$h" "$drawn" 2>&1); then
		fail "$path: $msg"
		return 1
	fi
	png_drawn=$msg
	return 0
}
