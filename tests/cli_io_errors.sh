#!/usr/bin/env bash
# Bad input files through the CLI: exit status 2, one error line on stderr
# naming the file and the problem, and no output file. `dpoints wlop` reads
# its input before it opens a device, so this needs no OpenCL.
set -euo pipefail
dpoints=${1:?usage: cli_io_errors.sh PATH_TO_DPOINTS}
tmp=$(mktemp -d /tmp/dpoints-cli-io-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
failures=0

# expect NAME NEEDLE: runs wlop on $tmp/NAME and checks the outcome.
expect() {
	local input=$tmp/$1 needle=$2 out=$tmp/out.ply status=0
	"$dpoints" wlop "$input" -o "$out" >"$tmp/stdout" 2>"$tmp/stderr" || status=$?
	local lines
	lines=$(wc -l <"$tmp/stderr")
	if [ "$status" -ne 2 ]; then
		echo "FAIL $1: exit status $status, expected 2"; failures=$((failures + 1))
	elif [ "$lines" -ne 1 ]; then
		echo "FAIL $1: $lines lines on stderr, expected 1:"; cat "$tmp/stderr"; failures=$((failures + 1))
	elif ! grep -qF "$input" "$tmp/stderr" || ! grep -qF "$needle" "$tmp/stderr"; then
		echo "FAIL $1: stderr lacks the path or '$needle':"; cat "$tmp/stderr"; failures=$((failures + 1))
	elif compgen -G "$tmp/out.ply*" >/dev/null; then
		echo "FAIL $1: an output file was written"; failures=$((failures + 1))
	else
		echo "ok   $1: $(cat "$tmp/stderr")"
	fi
}

header='ply
format ascii 1.0
element vertex 5
property float x
property float y
property float z
end_header'

: >"$tmp/empty.xyz"
printf '1 2 3\n4 nan 6\n' >"$tmp/nan.xyz"
printf '%s\n1.000000 2.000000 3.000000\n1.000000 2.000000 3.000000\n' "$header" >"$tmp/truncated.ply"
printf '%s\n' "${header/vertex 5/vertex 1000000000000}" >"$tmp/lying.ply"
printf '1 2 3\n' >"$tmp/points.abc"
printf 'FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 1\nDATA binary_compressed\n' >"$tmp/compressed.pcd"

expect missing.ply "No such file"
expect empty.xyz "empty"
expect nan.xyz "non-finite"
expect truncated.ply "truncated"
expect lying.ply "bytes follow"
expect points.abc "unknown"
expect compressed.pcd "unsupported"

if [ "$failures" -ne 0 ]; then
	echo "$failures case(s) failed"
	exit 1
fi
