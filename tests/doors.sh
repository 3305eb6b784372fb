#!/bin/sh
# doors.sh — the sanitized brdfkit's hot numeric files check their callers'
# buffers at the door (brdf/doors.h): each entry point given a buffer one
# element short, or freed, aborts naming it; with every buffer whole the same
# calls return the closed forms' values (the control: the doors do not fire
# on a correct call, and the files linked are the ones that compute).
# usage: sh tests/doors.sh path/to/doors_check
set -u
DC=${1:?usage: doors.sh path/to/doors_check}
pass=0 fail=0
T=$(mktemp -d /tmp/bk_doors_XXXXXX)
trap 'rm -rf "$T"' EXIT
if "$DC" whole >"$T/out" 2>&1 && grep -q 'doors whole: returned' "$T/out"; then
	pass=$((pass + 1))
else
	fail=$((fail + 1)); echo "FAIL: whole buffers: $(cat "$T/out")"
fi
# case, then the buffer and the function the abort must name
for c in "out:out eval" "input:an input eval" "params:params eval" "jac:jac bk_form_eval_diff" \
         "cols:a Jacobian column bound_eval" "bind:an input bk_form_bind" "freed:an input eval" \
         "half:y bk_form_eval_half_vs" "quad_pts:pts bk_quad" "quad_out:out bk_quad" "dfg_B:B bk_dfg" \
         "albedo_material:material bk_albedo"; do
	case_=${c%%:*} rest=${c#*:}
	what=${rest% *} fn=${rest##* }
	# the door's own check, not ASan's report from elsewhere: it names the
	# function and the buffer, and the call never returned
	if ASAN_OPTIONS=detect_leaks=0 "$DC" "$case_" >"$T/out" 2>&1; then
		fail=$((fail + 1)); echo "FAIL: $case_: the short buffer was not caught"
	elif grep -q "brdfkit: $fn: $what (" "$T/out" && ! grep -q 'returned' "$T/out"; then
		pass=$((pass + 1))
	else
		fail=$((fail + 1)); echo "FAIL: $case_: expected 'brdfkit: $fn: $what (': $(head -3 "$T/out")"
	fi
done
echo "doors: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
