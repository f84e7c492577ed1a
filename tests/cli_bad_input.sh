#!/usr/bin/env bash
# Bad input files given to every command that reads one: exit status 2, one
# error line naming the file, and nothing written. (tests/cli_io_errors.sh
# goes through the format problems one by one on `wlop`.)
source "$(dirname "$0")/support/cli_check.sh"

bad=$tmp/bad
mkdir "$bad"
: >"$bad/empty.xyz"
printf '0 0 0\n1 0 0\n0 1 0\n0 0 nan\n' >"$bad/nan.xyz"
printf '0 0 0\n1 0 0\n0 1 0\n' >"$bad/points.abc"
declare -A needle=([missing.ply]="No such file" [empty.xyz]="empty" [nan.xyz]="non-finite" [points.abc]="unknown")

# good inputs for the other argument of eval and render
expect_ok scan scan --shape sphere --views 2 --res 16 -o "$tmp/good.ply" --mesh-out "$tmp/mesh.ply" || finish

out=$tmp/out
mkdir "$out"
for name in missing.ply empty.xyz nan.xyz points.abc; do
	f=$bad/$name
	run "wlop_$name" wlop "$f" -o "$out/w.ply" --report "$out/w.json"
	one_error_line "wlop_$name" 2 "$f" "${needle[$name]}"
	run "consolidate_$name" consolidate "$f" -o "$out/c"
	one_error_line "consolidate_$name" 2 "$f" "${needle[$name]}"
	run "batch_$name" consolidate "$f" "$f" -o "$out/b" --quiet
	[ "$status" -eq 2 ] || fail "batch of two $name: exit status $status, expected 2"
	run "eval_points_$name" eval "$tmp/mesh.ply" "$f"
	one_error_line "eval_points_$name" 2 "$f" "${needle[$name]}"
	run "eval_mesh_$name" eval "$f" "$tmp/good.ply"
	one_error_line "eval_mesh_$name" 2 "$f" "${needle[$name]}"
	run "render_$name" render "$tmp/good.ply" "$f:red" -o "$out/r.png"
	one_error_line "render_$name" 2 "$f" "${needle[$name]}"
	run "scan_$name" scan "$f" -o "$out/s.ply" --mesh-out "$out/m.ply"
	one_error_line "scan_$name" 2 "$f" "${needle[$name]}"
done
# a point cloud where a mesh is needed
run eval_no_faces eval "$tmp/good.ply" "$tmp/good.ply"
one_error_line eval_no_faces 2 "$tmp/good.ply" "no faces"
run scan_no_faces scan "$tmp/good.ply" -o "$out/s.ply"
one_error_line scan_no_faces 2 "$tmp/good.ply" "no faces"
# files that read but that eval or scan cannot use: one point, a mesh
# squashed to one spot (the line names the file)
echo "1 2 3" >"$bad/one.xyz"
run eval_one_point eval "$tmp/mesh.ply" "$bad/one.xyz"
one_error_line eval_one_point 2 "$bad/one.xyz" "need at least 2 points"
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n0 0 0\n0 0 0\n3 0 1 2\n' >"$bad/spot.ply"
run eval_spot eval "$bad/spot.ply" "$tmp/good.ply"
one_error_line eval_spot 2 "$bad/spot.ply" "zero extent"
run scan_spot scan "$bad/spot.ply" -o "$out/s.ply" --mesh-out "$out/m.ply"
one_error_line scan_spot 2 "$bad/spot.ply" "zero extent"
# an option out of range is said before any file is read, and names none
run scan_views scan "$bad/spot.ply" -o "$out/s.ply" --views 0
one_error_line scan_views 2 "views 0 outside"
grep -q "spot.ply" "$tmp/scan_views.err" && fail "scan_views: a parameter error names the mesh: $(cat "$tmp/scan_views.err")"
run eval_factor eval "$tmp/no-such-mesh.ply" "$tmp/good.ply" --coverage-factor -1
one_error_line eval_factor 2 "coverage factor -1"
grep -q "\.ply" "$tmp/eval_factor.err" && fail "eval_factor: a parameter error names a file: $(cat "$tmp/eval_factor.err")"
# an input the pipeline cannot work with: one point repeated
for _ in 1 2 3 4 5 6 7 8 9 10 11 12; do echo "1 2 3"; done >"$bad/same.xyz"
run wlop_same wlop "$bad/same.xyz" -o "$out/w.ply"
one_error_line wlop_same 2 "$bad/same.xyz" "wlop"
run consolidate_same consolidate "$bad/same.xyz" -o "$out/c"
one_error_line consolidate_same 2 "$bad/same.xyz" "wlop"
# an output folder that cannot be written
run unwritable wlop "$tmp/good.ply" -o "$tmp/no-such-folder/w.ply"
one_error_line unwritable 2 "$tmp/no-such-folder/w.ply"

left=$(find "$out" -mindepth 1)
if [ -n "$left" ]; then
	fail "failed runs left files behind: $left"
else
	ok "no output left behind"
fi
finish
