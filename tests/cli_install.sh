#!/usr/bin/env bash
# `cmake --install` into a scratch prefix, then the README's library example
# built as a user would, three ways, and each build run on a small scan: with
# pkg-config against the static library (dpoints-static) and the shared one
# (dpoints), and with CMake's find_package(dpoints) against both targets. Also
# the installed tool run from elsewhere. ctest runs this in the build folder,
# which is what gets installed.
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
libdir=$(dirname "$lib")
for f in "$prefix/bin/dpoints" "$prefix/include/dpoints.h" "$prefix/include/dpoints_tools.h" \
	"$prefix/include/dpoints_version.h" "$lib" "$pc" "$libdir/pkgconfig/dpoints-static.pc" \
	"$libdir/libdpoints.so" "$libdir/cmake/dpoints/dpointsConfig.cmake" \
	"$libdir/cmake/dpoints/dpointsConfigVersion.cmake"; do
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
# --static lists what the archive needs (libm among them: without it, sqrt
# was an undefined reference)
if ! private=$(pkg-config --libs --static dpoints 2>&1) || [[ $private != *-lm* ]]; then
	fail "pkg-config --libs --static dpoints lacks -lm: $private"
fi

# build NAME FLAGS...: cc example.c FLAGS -o $tmp/NAME
build_example() {
	local name=$1
	shift
	if cc "$tmp/example.c" "$@" -o "$tmp/$name" 2>"$tmp/$name.cc.log"; then
		ok "$name: README example built with: cc example.c $*"
	else
		fail "$name: README example does not build with 'cc example.c $*': $(head -n 5 "$tmp/$name.cc.log")"
	fi
}
for module in dpoints-static dpoints; do
	if ! flags=$(pkg-config --cflags --libs $module 2>&1); then
		fail "pkg-config $module: $flags"
		finish
	fi
	# the flags must point into the prefix it was installed to, not where the
	# build was configured to install
	case $flags in
	*"-I$prefix/"*) ;;
	*) fail "pkg-config --cflags $module does not point into $prefix: $flags" ;;
	esac
	# shellcheck disable=SC2086 # the flags are meant to split
	if [ $module = dpoints ]; then
		build_example pc_shared $flags "-Wl,-rpath,$libdir"
	else
		build_example pc_static $flags
	fi
done

# find_package: the README's CMake block as it stands (its version request
# included), then the same program against the static target
mkdir "$tmp/consumer"
cp "$tmp/example.c" "$tmp/consumer/example.c"
{
	printf 'cmake_minimum_required(VERSION 3.18)\nproject(consumer C)\n'
	awk '/^```cmake$/ { on = 1; next } on && /^```$/ { exit } on { print }' "$source_dir/README.md" |
		sed 's/add_executable(app /add_executable(cmake_shared /; s/target_link_libraries(app /target_link_libraries(cmake_shared /'
	printf 'add_executable(cmake_static example.c)\ntarget_link_libraries(cmake_static PRIVATE dpoints::dpoints_static)\n'
} >"$tmp/consumer/CMakeLists.txt"
grep -q '^find_package(dpoints ' "$tmp/consumer/CMakeLists.txt" && grep -q 'add_executable(cmake_shared ' "$tmp/consumer/CMakeLists.txt" ||
	fail "no CMake consumer (a \`\`\`cmake block with find_package(dpoints ...) and add_executable(app ...)) in $source_dir/README.md"
if cmake -S "$tmp/consumer" -B "$tmp/consumer/build" -DCMAKE_PREFIX_PATH="$prefix" >"$tmp/consumer.log" 2>&1 &&
	cmake --build "$tmp/consumer/build" >>"$tmp/consumer.log" 2>&1; then
	cp "$tmp/consumer/build/cmake_shared" "$tmp/consumer/build/cmake_static" "$tmp/"
	ok "find_package(dpoints): dpoints::dpoints and dpoints::dpoints_static built"
else
	fail "find_package(dpoints) consumer: $(grep -m 5 -i 'error' "$tmp/consumer.log")"
fi
[ "$failures" -eq 0 ] || finish

# The shared builds load the installed libdpoints.so, the static ones none.
for name in pc_shared cmake_shared pc_static cmake_static; do
	deps=$(ldd "$tmp/$name")
	case $name:$deps in
	*_shared:*"$libdir/libdpoints.so"*) ;;
	*_static:*libdpoints*) fail "$name loads libdpoints: $deps" ;;
	*_static:*) ;;
	*) fail "$name does not load $libdir/libdpoints.so: $deps" ;;
	esac
done

# Run them, and the installed tool, from a folder outside the build.
mkdir "$tmp/run"
cd "$tmp/run"
# 64 x 64 rays: the default 10% of 40 x 40 gives 91 deep points, too few for
# this torus (its skeleton lands far outside it and consolidate refuses it)
"$prefix/bin/dpoints" scan --shape torus --views 3 --res 64 --noise 0.003 -o in.ply >/dev/null ||
	fail "installed dpoints scan failed"
for name in pc_static pc_shared cmake_shared cmake_static; do
	mkdir "$tmp/run/$name"
	cd "$tmp/run/$name"
	if "$tmp/$name" ../in.ply >example.out 2>&1; then
		if msg=$(py "$PLY_PY"'
names, rows, _ = read_ply("surface.ply")
if names[:6] != ["x", "y", "z", "nx", "ny", "nz"] or not rows:
    sys.exit("surface.ply has %s and %d points" % (names, len(rows)))
print("surface.ply: %d points with normals" % len(rows))
' 2>&1); then ok "$name runs: $msg"; else fail "$name output: $msg"; fi
	else
		fail "$name failed: $(cat example.out)"
	fi
	status=0
	"$tmp/$name" missing.ply >example.out 2>&1 || status=$?
	[ "$status" -ne 0 ] && grep -q 'missing.ply' example.out ||
		fail "$name on a missing file: status $status, $(cat example.out)"
done
version=$("$prefix/bin/dpoints" --version)
[[ $version == "dpoints "[0-9]*.[0-9]*.[0-9]* ]] || fail "installed dpoints --version: $version"
finish
