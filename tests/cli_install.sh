#!/usr/bin/env bash
# `cmake --install` into a scratch prefix, then the README's library example
# built exactly as the README says (pkg-config --static dpoints) and run on a
# small scan, and the installed tool run from elsewhere. ctest runs this in
# the build folder, which is what gets installed.
source "$(dirname "$0")/support/cli_check.sh"

build=$PWD
source_dir=${DP_SOURCE_DIR:-$(dirname "$0")/..}
prefix=$tmp/prefix
if ! cmake --install "$build" --prefix "$prefix" >"$tmp/install.log" 2>&1; then
	fail "cmake --install $build: $(tail -n 5 "$tmp/install.log")"
	finish
fi
pc=$(find "$prefix" -name dpoints.pc)
lib=$(find "$prefix" -name libdpoints.a)
for f in "$prefix/bin/dpoints" "$prefix/include/dpoints.h" "$lib" "$pc"; do
	[ -n "$f" ] && [ -s "$f" ] || fail "not installed: ${f:-libdpoints.a or dpoints.pc}"
done
[ "$failures" -eq 0 ] || finish
ok "installed: $(cd "$prefix" && find . -type f | sort | tr '\n' ' ')"

# The first C block of the README is the library example.
awk '/^```c$/ { on = 1; next } on && /^```$/ { exit } on { print }' "$source_dir/README.md" >"$tmp/example.c"
if ! grep -q dp_consolidate "$tmp/example.c"; then
	fail "no library example (a \`\`\`c block calling dp_consolidate) in $source_dir/README.md"
	finish
fi
PKG_CONFIG_PATH=$(dirname "$pc")
export PKG_CONFIG_PATH
if ! flags=$(pkg-config --cflags --libs --static dpoints 2>&1); then
	fail "pkg-config --static dpoints: $flags"
	finish
fi
# the flags must point into the prefix it was installed to, not where the
# build was configured to install
case $flags in
*"-I$prefix/"*) ;;
*) fail "pkg-config --cflags does not point into $prefix: $flags" ;;
esac
# shellcheck disable=SC2086 # the flags are meant to split
if cc "$tmp/example.c" $flags -o "$tmp/example" 2>"$tmp/cc.log"; then
	ok "README example built with: cc example.c $flags"
else
	fail "README example does not build with 'cc example.c $flags': $(head -n 5 "$tmp/cc.log")"
	finish
fi

# Run it, and the installed tool, from a folder outside the build.
mkdir "$tmp/run"
cd "$tmp/run"
# 64 x 64 rays: the default 10% of 40 x 40 gives 91 deep points, too few for
# this torus (its skeleton lands far outside it and consolidate refuses it)
"$prefix/bin/dpoints" scan --shape torus --views 3 --res 64 --noise 0.003 -o in.ply >/dev/null ||
	fail "installed dpoints scan failed"
if "$tmp/example" in.ply >example.out 2>&1; then
	if msg=$(py "$PLY_PY"'
names, rows, _ = read_ply("surface.ply")
if names[:6] != ["x", "y", "z", "nx", "ny", "nz"] or not rows:
    sys.exit("surface.ply has %s and %d points" % (names, len(rows)))
print("surface.ply: %d points with normals" % len(rows))
' 2>&1); then ok "README example runs: $msg"; else fail "README example output: $msg"; fi
else
	fail "README example failed: $(cat example.out)"
fi
status=0
"$tmp/example" missing.ply >example.out 2>&1 || status=$?
[ "$status" -ne 0 ] && grep -q 'missing.ply' example.out ||
	fail "README example on a missing file: status $status, $(cat example.out)"
finish
