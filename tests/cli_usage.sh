#!/usr/bin/env bash
# Usage errors: unknown options, missing and malformed values (exit status 2)
# and devices that do not exist (exit status 3), each as one clear line, with
# nothing written.
source "$(dirname "$0")/support/cli_check.sh"

expect_ok scan scan --shape sphere --views 2 --res 16 -o "$tmp/in.ply" --mesh-out "$tmp/mesh.ply" || finish
in=$tmp/in.ply
out=$tmp/out
mkdir "$out"

# every command, with the arguments it needs to otherwise run
declare -A args=(
	[wlop]="$in -o $out/w.ply"
	[consolidate]="$in -o $out/c"
	[scan]="--shape sphere -o $out/s.ply"
	[eval]="$tmp/mesh.ply $in"
	[render]="$in -o $out/r.png"
	[demo]="-o $out/d"
	[devices]=""
)
for c in "${!args[@]}"; do
	# shellcheck disable=SC2086 # the arguments are meant to split
	run "${c}_unknown" "$c" ${args[$c]} --no-such-option
	one_error_line "${c}_unknown" 2 "unknown option '--no-such-option'"
done
for c in wlop consolidate scan eval render demo; do
	# shellcheck disable=SC2086
	run "${c}_missing_value" "$c" ${args[$c]} --seed
	case $c in
	render) one_error_line "${c}_missing_value" 2 "unknown option '--seed'" ;; # render has no seed
	*) one_error_line "${c}_missing_value" 2 "--seed needs a value" ;;
	esac
done

# a flag given a value is refused, not turned on
run flag_value consolidate "$in" -o "$out/c" --quiet=0
one_error_line flag_value 2 "--quiet" "takes no value" "'0'"
if [ -e "$out/c" ]; then fail "flag_value: wrote $out/c"; fi

# malformed values name the option and the value
run samples_word wlop "$in" -o "$out/w.ply" --samples many
one_error_line samples_word 2 "--samples" "'many' is not a positive integer"
run samples_zero wlop "$in" -o "$out/w.ply" --samples 0
one_error_line samples_zero 2 "--samples" "'0'"
run backend_bad wlop "$in" -o "$out/w.ply" --backend gpu
one_error_line backend_bad 2 "--backend" "one of cl|ref"
run viewpoint_bad consolidate "$in" -o "$out/c" --viewpoint 1,2
one_error_line viewpoint_bad 2 "--viewpoint" "three numbers"
run ratio_bad wlop "$in" -o "$out/w.ply" --ratio 1.5x
one_error_line ratio_bad 2 "--ratio" "'1.5x' is not a number"
run no_output wlop "$in"
one_error_line no_output 2 "needs INPUT and -o"
run no_input consolidate -o "$out/c"
one_error_line no_input 2 "needs INPUT and -o OUTDIR"
run two_inputs wlop "$in" "$in" -o "$out/w.ply"
one_error_line two_inputs 2 "unexpected argument"

# devices that do not exist: exit status 3 and a line saying which
run device_name wlop "$in" -o "$out/w.ply" --device no-such-device
one_error_line device_name 3 "no-such-device" "dpoints devices"
run device_index consolidate "$in" -o "$out/c" --device 99
one_error_line device_index 3 "99" "out of range"
status=0
DPOINTS_DEVICE=no-such-device "$dpoints" wlop "$in" -o "$out/w.ply" >"$tmp/device_env.out" 2>"$tmp/device_env.err" ||
	status=$?
one_error_line device_env 3 "no-such-device"

left=$(find "$out" -mindepth 1)
if [ -n "$left" ]; then
	fail "failed runs left files behind: $left"
else
	ok "no output left behind"
fi
finish
