#!/usr/bin/env bash
# The shared library exports the public API and nothing else: every defined
# dynamic symbol starts with dp_, every function the headers declare DP_API
# is among them, and internal helpers (dp_fail, the kernels' dispatch) are
# not. Also its SONAME carries the ABI version, and the tool, dp_version()
# and the CMake project agree on the version.
set -euo pipefail
lib=${1:?usage: $0 LIBDPOINTS.so DPOINTS_TOOL VERSION}
tool=${2:?}
version=${3:?}
source_dir=${DP_SOURCE_DIR:?}
failures=0
fail() {
	echo "FAIL $*"
	failures=$((failures + 1))
}

exported=$(nm -D --defined-only "$lib" | awk '{ print $3 }' | sort)
[ -n "$exported" ] || fail "nm -D --defined-only $lib lists nothing"
bad=$(grep -v '^dp_' <<<"$exported" || true)
[ -z "$bad" ] || fail "exported symbols outside dp_: $(tr '\n' ' ' <<<"$bad")"
for internal in dp_fail dp_seconds dp_alloc_array dp_cl_open dp_progress; do
	if grep -qx "$internal" <<<"$exported"; then fail "internal function $internal is exported"; fi
done
declared=$(grep -ho 'DP_API [^(]*(' "$source_dir"/host/include/*.h | grep -o 'dp_[a-z0-9_]*($' | tr -d '(' | sort -u)
missing=$(comm -23 <(echo "$declared") <(echo "$exported"))
[ -z "$missing" ] || fail "declared DP_API but not exported: $(tr '\n' ' ' <<<"$missing")"
echo "ok   $(wc -l <<<"$exported") exported symbols, all dp_, $(wc -l <<<"$declared") declared DP_API"

soname=$(objdump -p "$lib" | awk '/SONAME/ { print $2 }')
major=${version%%.*}
minor=${version#*.}
minor=${minor%%.*}
if [ "$major" = 0 ]; then want="libdpoints.so.0.$minor"; else want="libdpoints.so.$major"; fi
[ "$soname" = "$want" ] || fail "SONAME '$soname', expected '$want'"

out=$("$tool" --version)
[ "$out" = "dpoints $version" ] || fail "dpoints --version says '$out', the project version is $version"
header=$(grep -h 'define DP_VERSION_STRING' "$(dirname "$lib")"/generated/include/dpoints_version.h)
[[ $header == *"\"$version\""* ]] || fail "dpoints_version.h: $header"

if [ "$failures" -ne 0 ]; then
	echo "$failures check(s) failed"
	exit 1
fi
echo "ok   SONAME $soname, version $version in the tool and the header"
